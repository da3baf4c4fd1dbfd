/* SPDX-License-Identifier: MIT */
/*
** boxes.c -- a triangle slot's box from its corners as they are now: the
** build's, for runs of slots (ray__tri_boxes), and a refit's leaf, its
** box with its slots' float rows and double corners written again
** (ray__refit_leaf; refit_avx2.c the same leaf with AVX2).  Both read
** the corners as refit_corners does and take the minima and maxima in
** the same order, so a refit's boxes are the build's floats.
*/
#include <string.h>

#include "scene/slots.h"

#if !RAY__SSE2
/* The smaller and larger of two, of three finite numbers (no libm call:
** the NaN rules of fmin are not needed here, vertices are finite); the
** SSE2 code says them as minpd and maxpd, which pick the same way. */
static double min2(double a, double b)
{
    return a < b ? a : b;
}

static double max2(double a, double b)
{
    return a > b ? a : b;
}

static double min3(double a, double b, double c)
{
    return min2(min2(a, b), c);
}

static double max3(double a, double b, double c)
{
    return max2(max2(a, b), c);
}

/* *lo, *hi grown to hold triangle t (tri_boxes with SSE2 says it in its
** registers). */
static inline void corners_grow(const ray__tri *t, ray_vec3 *lo,
                                ray_vec3 *hi)
{
    lo->x = min2(lo->x, min3(t->a.x, t->b.x, t->c.x));
    lo->y = min2(lo->y, min3(t->a.y, t->b.y, t->c.y));
    lo->z = min2(lo->z, min3(t->a.z, t->b.z, t->c.z));
    hi->x = max2(hi->x, max3(t->a.x, t->b.x, t->c.x));
    hi->y = max2(hi->y, max3(t->a.y, t->b.y, t->c.y));
    hi->z = max2(hi->z, max3(t->a.z, t->b.z, t->c.z));
}
#endif

/*
** A refit's leaf: the box of slots first .. first + n - 1, from the
** geometry's vertices as they are now, and their float corners written
** again in the leaf's rows (ud: the scene, whose leaf_f the refit
** rewrites: each leaf its own rows).
**
** The same corners, the same operations in the same order as the build's
** (corners_grow: the box's minima and maxima, signed zeros included;
** leaf_rows: the floats), so the same bits; written for the refit, which
** does it for every triangle of every frame (issue 36).  A mesh's
** triangle is read through ray__mesh_tri, inline, where ray__tri_of was
** a call returning 72 bytes through memory (a store-forwarding stall a
** triangle: perf put a quarter of a 59k refit there).  Whether the nine
** coordinates fit the rows (|x| <= RAY__LEAF_FLOAT_MAX, leaf_rows's
** test) is read from the triangle's own box: |x| <= M for the three
** corners of an axis exactly when their minimum is >= -M and their
** maximum <= M (vertices are finite), six comparisons for nine.
*/
#if RAY__SSE2
#include <emmintrin.h>

/*
** With SSE2 (every x86-64), x and y of a corner in one register and z in
** another: the operations of the scalar loop below, lane by lane, so the
** same bits in any rounding mode.  _mm_min_pd(p, q) is p < q ? p : q in
** each lane (MINPD returns its second operand for equal values, signed
** zeros, and NaN), which is min2's expression; _mm_cvtpd_ps rounds as a
** cast does, in the current mode.  About as many instructions as the
** scalar loop, but shorter chains: a 59k refit a third faster (bench/
** filter --profile refit, issue 36).  Registers travel in a struct by
** address: 32-bit MSVC passes no more than three by value.
*/
typedef struct corners2 {
    __m128d a, az, b, bz, c, cz;     /* x and y, then z, of each corner */
} corners2;

typedef struct refit_box {
    __m128d lo_xy, lo_z, hi_xy, hi_z;
} refit_box;

/*
** Do a triangle's corners give it a normal (ray__corners_usable)?  Its
** cross product v3_cross(b - a, c - a), component for component:
** (e1.y e2.z - e1.z e2.y, e1.z e2.x - e1.x e2.z) in one register, the
** same products and differences as the scalar one.
*/
static inline int corners_usable_sse2(const corners2 *k)
{
    const __m128d sign = _mm_set1_pd(-0.0), zero = _mm_setzero_pd(),
                  inf = _mm_set1_pd(HUGE_VAL);
    __m128d e1 = _mm_sub_pd(k->b, k->a), e1z = _mm_sub_sd(k->bz, k->az);
    __m128d e2 = _mm_sub_pd(k->c, k->a), e2z = _mm_sub_sd(k->cz, k->az);
    __m128d p = _mm_mul_pd(_mm_shuffle_pd(e1, e1z, 1),      /* e1.y e1.z */
                           _mm_unpacklo_pd(e2z, e2));       /* e2.z e2.x */
    __m128d q = _mm_mul_pd(_mm_unpacklo_pd(e1z, e1),        /* e1.z e1.x */
                           _mm_shuffle_pd(e2, e2z, 1));     /* e2.y e2.z */
    __m128d nxy = _mm_sub_pd(p, q);
    __m128d r = _mm_mul_pd(e1, _mm_shuffle_pd(e2, e2, 1));  /* x y, y x */
    __m128d nz = _mm_sub_sd(r, _mm_unpackhi_pd(r, r));
    int pos, fin;

    nxy = _mm_andnot_pd(sign, nxy);
    nz = _mm_andnot_pd(sign, nz);
    pos = _mm_movemask_pd(_mm_cmpgt_pd(nxy, zero)) |
          (_mm_movemask_pd(_mm_cmpgt_sd(nz, zero)) & 1);
    fin = _mm_movemask_pd(_mm_cmplt_pd(nxy, inf)) == 3 &&
          (_mm_movemask_pd(_mm_cmplt_sd(nz, inf)) & 1);
    return pos != 0 && fin;
}

/* The corners at pa, pb, pc in registers; with "check", a triangle
** without a normal read as its first corner, as ray__mesh_tri reads a
** mesh's. */
static inline void corners_sse2(const ray_vec3 *pa, const ray_vec3 *pb,
                                const ray_vec3 *pc, int check, corners2 *k)
{
    k->a = _mm_loadu_pd(&pa->x);
    k->az = _mm_load_sd(&pa->z);
    k->b = _mm_loadu_pd(&pb->x);
    k->bz = _mm_load_sd(&pb->z);
    k->c = _mm_loadu_pd(&pc->x);
    k->cz = _mm_load_sd(&pc->z);
    if (check && !corners_usable_sse2(k)) {
        k->b = k->c = k->a;
        k->bz = k->cz = k->az;
    }
}

/* The nine floats of a triangle in its rows (leaf_rows_fitting's). */
static inline void rows_sse2(float *r, size_t stride, const corners2 *k)
{
    __m128 f;

    f = _mm_cvtpd_ps(k->a);
    _mm_store_ss(r, f);
    _mm_store_ss(r + stride, _mm_shuffle_ps(f, f, 1));
    _mm_store_ss(r + 2 * stride, _mm_cvtsd_ss(f, k->az));
    f = _mm_cvtpd_ps(k->b);
    _mm_store_ss(r + 3 * stride, f);
    _mm_store_ss(r + 4 * stride, _mm_shuffle_ps(f, f, 1));
    _mm_store_ss(r + 5 * stride, _mm_cvtsd_ss(f, k->bz));
    f = _mm_cvtpd_ps(k->c);
    _mm_store_ss(r + 6 * stride, f);
    _mm_store_ss(r + 7 * stride, _mm_shuffle_ps(f, f, 1));
    _mm_store_ss(r + 8 * stride, _mm_cvtsd_ss(f, k->cz));
}

/* Triangle t (its corners at pa, pb, pc) refitted: the leaf's box *x
** grown (set by the first, "first"), its rows and its copy written. */
static inline void refit_tri_sse2(const ray_vec3 *pa, const ray_vec3 *pb,
                                  const ray_vec3 *pc, int check, int first,
                                  refit_box *x, float *rows, size_t stride,
                                  ray__tri *copy)
{
    const __m128d big = _mm_set1_pd(RAY__LEAF_FLOAT_MAX),
                  nbig = _mm_set1_pd(-RAY__LEAF_FLOAT_MAX);
    __m128d lo, loz, hi, hiz;
    corners2 k;

    corners_sse2(pa, pb, pc, check, &k);
    lo = _mm_min_pd(_mm_min_pd(k.a, k.b), k.c);
    loz = _mm_min_sd(_mm_min_sd(k.az, k.bz), k.cz);
    hi = _mm_max_pd(_mm_max_pd(k.a, k.b), k.c);
    hiz = _mm_max_sd(_mm_max_sd(k.az, k.bz), k.cz);
    if (first) {
        x->lo_xy = x->hi_xy = k.a;
        x->lo_z = x->hi_z = k.az;
    }
    x->lo_xy = _mm_min_pd(x->lo_xy, lo);
    x->lo_z = _mm_min_sd(x->lo_z, loz);
    x->hi_xy = _mm_max_pd(x->hi_xy, hi);
    x->hi_z = _mm_max_sd(x->hi_z, hiz);
    if (_mm_movemask_pd(_mm_and_pd(_mm_cmpge_pd(lo, nbig),
                                   _mm_cmple_pd(hi, big))) == 3 &&
        (_mm_movemask_pd(_mm_and_pd(_mm_cmpge_sd(loz, nbig),
                                    _mm_cmple_sd(hiz, big))) & 1))
        rows_sse2(rows, stride, &k);
    else
        rows_nan(rows, stride);
    if (copy != NULL) {
        _mm_storeu_pd(&copy->a.x, k.a);
        _mm_store_sd(&copy->a.z, k.az);
        _mm_storeu_pd(&copy->b.x, k.b);
        _mm_store_sd(&copy->b.z, k.bz);
        _mm_storeu_pd(&copy->c.x, k.c);
        _mm_store_sd(&copy->c.z, k.cz);
    }
}

/* ray__box_out_float's rounding of x, y (xy) and z (z's low lane) in the
** lanes of one register: down (up = 0) or up, the float next to the
** nearest on the far side where the nearest lies on the wrong one, on
** its bits (core/floats_avx.h's floats_step, with SSE2 alone); into
** out[0..2]. */
static inline void box_out_sse2(__m128d xy, __m128d z, int up, float out[3])
{
    __m128 f = _mm_movelh_ps(_mm_cvtpd_ps(xy), _mm_cvtpd_ps(z));
    __m128d bxy = _mm_cvtps_pd(f), bz = _mm_cvtps_pd(_mm_movehl_ps(f, f));
    __m128d nxy = up ? _mm_cmplt_pd(bxy, xy) : _mm_cmpgt_pd(bxy, xy);
    __m128d nz = up ? _mm_cmplt_sd(bz, z) : _mm_cmpgt_sd(bz, z);
    /* the low halves of the 64-bit masks: x, y, z's */
    __m128i need = _mm_castps_si128(_mm_shuffle_ps(
        _mm_castpd_ps(nxy), _mm_castpd_ps(nz), _MM_SHUFFLE(2, 0, 2, 0)));
    __m128i u = _mm_castps_si128(f), sign = _mm_srai_epi32(u, 31);
    /* up: +1 where f >= +0, -1 where f < 0; down: the opposite. */
    __m128i step = _mm_add_epi32(_mm_add_epi32(sign, sign),
                                 _mm_set1_epi32(1));
    float v[4];

    if (!up)
        step = _mm_sub_epi32(_mm_setzero_si128(), step);
    _mm_storeu_ps(v, _mm_castsi128_ps(_mm_add_epi32(u, _mm_and_si128(need,
                                                                     step))));
    memcpy(out, v, 3 * sizeof *out);
}

void ray__refit_leaf(const void *ud, size_t first, size_t n, float lo[3],
                     float hi[3])
{
    const ray_scene *s = ud;
    float *rows = s->leaf_f + RAY__LEAF_ROWS * first;
    ray__tri *copy = s->leaf_tri != NULL ? s->leaf_tri + first : NULL;
    const ray__mesh *m = NULL;
    unsigned m_geom = (unsigned)-1;
    refit_box x;
    size_t j;

    x.lo_xy = x.hi_xy = x.lo_z = x.hi_z = _mm_setzero_pd();
    for (j = 0; j < n; j++) {
        const ray_vec3 *p[3];
        ray__tri t;
        int mesh = ray__slot_corners_at(s, first + j, &m, &m_geom, &t, p);
        if (mesh)
            ray__prefetch_slots(s, first + j, m, m_geom);
        refit_tri_sse2(p[0], p[1], p[2], mesh, j == 0, &x, rows + j, n,
                       copy != NULL ? copy + j : NULL);
    }
    /* rounded out in the registers, as the AVX2 leaf does (refit_avx2.c
    ** says what the scalar rounding cost there) */
    box_out_sse2(x.lo_xy, x.lo_z, 0, lo);
    box_out_sse2(x.hi_xy, x.hi_z, 1, hi);
}

/*
** The float boxes of slots begin .. end - 1, rounded outward (the
** build's boxes callback, bvh.h): each slot's corners as the refit reads
** them (refit_corners: a mesh's triangle without a normal is its first
** corner), their minima and maxima grown from corner a (corners_grow's,
** so the refit's leaf boxes are the same floats), the mesh looked up
** once a run (ray__slot_corners_at's cache) and its corners read where
** they lie, not copied; with SSE2 x and y in one register and z beside
** them, and the rounding out on the floats' bits.  One slot at a time,
** through a copy of its corners and the scalar rounding, it was 195
** instructions a triangle, a tenth of a one-thread build (callgrind and
** perf, issue 36).
*/
void ray__tri_boxes(const void *ud, size_t begin, size_t end,
                    ray__box_rec *out)
{
    const ray_scene *s = ud;
    const ray__mesh *m = NULL;
    unsigned m_geom = (unsigned)-1;
    size_t i;

    for (i = begin; i < end; i++) {
        const ray_vec3 *p[3];
        ray__tri t;
        int mesh = ray__slot_corners_at(s, i, &m, &m_geom, &t, p);
        __m128d lo, loz, hi, hiz;
        corners2 k;
        /* a single triangle always has a normal: checked for a mesh's */
        corners_sse2(p[0], p[1], p[2], mesh, &k);
        /* corners_grow's from a box of corner a: min2(a, min3(a, b, c)) */
        lo = _mm_min_pd(k.a, _mm_min_pd(_mm_min_pd(k.a, k.b), k.c));
        loz = _mm_min_sd(k.az, _mm_min_sd(_mm_min_sd(k.az, k.bz), k.cz));
        hi = _mm_max_pd(k.a, _mm_max_pd(_mm_max_pd(k.a, k.b), k.c));
        hiz = _mm_max_sd(k.az, _mm_max_sd(_mm_max_sd(k.az, k.bz), k.cz));
        box_out_sse2(lo, loz, 0, out[i - begin].lo);
        box_out_sse2(hi, hiz, 1, out[i - begin].hi);
    }
}
#else
/* The double box lo, hi rounded outward into float (once per box:
** rounding outward is monotonic, so the union of rounded boxes is the
** rounded union, bit for bit), a coordinate at a time: what the SSE2
** and AVX2 code do in the lanes of a register (box_out_sse2,
** core/floats_avx.h). */
static void ray__box_out_float(ray_vec3 lo, ray_vec3 hi, float flo[3],
                               float fhi[3])
{
    flo[0] = ray__float_down(lo.x);
    flo[1] = ray__float_down(lo.y);
    flo[2] = ray__float_down(lo.z);
    fhi[0] = ray__float_up(hi.x);
    fhi[1] = ray__float_up(hi.y);
    fhi[2] = ray__float_up(hi.z);
}

/* tri_boxes without SSE2: the same floats, a coordinate at a time. */
void ray__tri_boxes(const void *ud, size_t begin, size_t end,
                    ray__box_rec *out)
{
    const ray_scene *s = ud;
    const ray__mesh *m = NULL;
    unsigned m_geom = (unsigned)-1;
    size_t i;

    for (i = begin; i < end; i++) {
        ray__tri t;
        ray_vec3 lo, hi;
        refit_corners(s, i, &m, &m_geom, &t);
        lo = hi = t.a;
        corners_grow(&t, &lo, &hi);
        ray__box_out_float(lo, hi, out[i - begin].lo, out[i - begin].hi);
    }
}


void ray__refit_leaf(const void *ud, size_t first, size_t n, float lo[3],
                     float hi[3])
{
    const ray_scene *s = ud;
    float *rows = s->leaf_f + RAY__LEAF_ROWS * first;
    ray__tri *copy = s->leaf_tri != NULL ? s->leaf_tri + first : NULL;
    const ray__mesh *m = NULL;
    unsigned m_geom = (unsigned)-1;
    const double big = RAY__LEAF_FLOAT_MAX;
    ray_vec3 a = {0, 0, 0}, b = a;
    size_t j;

    for (j = 0; j < n; j++) {
        ray__tri t;
        ray_vec3 tlo, thi;
        refit_corners(s, first + j, &m, &m_geom, &t);
        tlo.x = min3(t.a.x, t.b.x, t.c.x);
        tlo.y = min3(t.a.y, t.b.y, t.c.y);
        tlo.z = min3(t.a.z, t.b.z, t.c.z);
        thi.x = max3(t.a.x, t.b.x, t.c.x);
        thi.y = max3(t.a.y, t.b.y, t.c.y);
        thi.z = max3(t.a.z, t.b.z, t.c.z);
        if (j == 0)
            a = b = t.a;
        a.x = min2(a.x, tlo.x);
        a.y = min2(a.y, tlo.y);
        a.z = min2(a.z, tlo.z);
        b.x = max2(b.x, thi.x);
        b.y = max2(b.y, thi.y);
        b.z = max2(b.z, thi.z);
        leaf_rows_fitting(&t, rows + j, n,
                          (tlo.x >= -big) & (tlo.y >= -big) &
                          (tlo.z >= -big) & (thi.x <= big) &
                          (thi.y <= big) & (thi.z <= big));
        if (copy != NULL)
            copy[j] = t;
    }
    ray__box_out_float(a, b, lo, hi);
}

#endif
