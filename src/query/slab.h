/* SPDX-License-Identifier: MIT */
/*
** slab.h -- part of the query template (traverse.h): a ray's traversal
** data and the box test of a wide node, eight boxes at once in float.
*/
#ifndef RAY_SLAB_H
#define RAY_SLAB_H

#include <string.h>

#if defined(_MSC_VER)
#include <intrin.h>             /* _BitScanForward, _mm_prefetch */
#endif

#include "query/query.h"
#include "query/filter.h"
#include "core/floats_avx.h"

/*
** The slab test, eight boxes at a time in float, kept conservative: it
** may let a box through that the ray misses, never the reverse.
**
**   * The origin is bracketed, o_lo <= o <= o_hi (float_down / float_up),
**     and each plane distance uses the end that makes the near distance
**     smaller and the far distance larger; the boxes themselves were
**     rounded outward from the double geometry.
**   * (b - o) * (1/d) then carries three float roundings (gamma(3) of
**     float, relative), so the far distance -- clipped to tmax first, so
**     that the same slack covers a near distance rounded past tmax -- is
**     moved away from zero by FAR_SLACK times its magnitude (a factor,
**     as in Ize's 1 + 2 gamma(3), would move a negative far distance the
**     wrong way: tmin may be negative).  Ize proves with that bound that
**     no hit is lost ("Robust BVH Ray Traversal", JCGT 2(2), 2013;
**     pbrt-v4 Bounds3::IntersectP; Embree's robust mode); the popped
**     entries get the same slack against tmax.  Where tmin >= 0 (nearly
**     every query) the slack is carried by the far distances' own
**     reciprocals instead, grown by FAR_GROW, off the node test's
**     critical path (FAR_GROW says why that bound holds too).
**   * The distances are in units of a direction scaled by a power of two
**     (exact) so that its largest component lies in [1, 2): 1/d of that
**     component is then a normal float whatever the ray's length.
**   * A zero direction component makes 1/d = +-Inf (IEEE), so the slab is
**     everything or nothing (Williams et al., "An Efficient and Robust
**     Ray-Box Intersection Algorithm", JGT 10(1), 2005); 0 * Inf = NaN
**     when the origin is on the plane, and the max/min below ignore a NaN
**     operand: the box is kept.  A component too small beside the largest
**     for 1/d to be a normal float (below 2^-126 of it) gets 1/d = NaN:
**     its slab is ignored, which only lets more boxes through.
**
** Everything else stays in double: the triangle tests decide the hits.
*/
typedef struct trav {
    float o_near[4], o_far[4];   /* the origin end used for near / far */
    float inv[4];                /* 1 / scaled direction (NaN: ignored);
                                    [3] of each: room for a vector store */
    float inv_far[4];            /* inv times FAR_GROW: the far
                                    distances' where tmin >= 0 */
    size_t near_at[3], far_at[3];/* offsets of the near / far bound arrays */
    float tmin;                  /* scaled, widened to a float */
    double t_scale;              /* distance units of the scaled direction */
    int framed;                  /* wt set up: 1; 0 not yet; -1 cannot be */
    ray__watertight wt;          /* the triangle test's frame of the ray */
    tri_filter flt;              /* the float filter in that frame */
} trav;

/*
** The far distance's slack, relative: 2 gamma(3) as Ize's bound asks
** (the near and the far distance each off by gamma(3)), plus 4u for the
** two roundings of far + |far| * slack itself; u = 2^-24.
*/
#define FLOAT_U 5.9604644775390625e-8f
#define FAR_SLACK (2.0f * (3.0f * FLOAT_U) / (1.0f - 3.0f * FLOAT_U) + \
                   4.0f * FLOAT_U)

/*
** Where the interval starts at or past zero (tmin >= 0: nearly every
** query), the slack is put in the far distances themselves: each axis's
** is computed with 1/d grown in magnitude by FAR_GROW and clipped to
** tmax with its slack (with_slack), so the node test's critical path
** (load, distances, min, compare, mask, next child) loses the min, |t|,
** product and sum after it.  Why that is still Ize's bound: a box
** the ray truly enters has exact far distances tf* >= tmin >= 0, and a
** computed near distance is at most tn* (1 + gamma(3)) (negative when
** tn* is); a grown far distance is at least tf* (1 + k)(1 - gamma(4))
** (four roundings: the subtraction, the float inverse, the product by
** FAR_GROW, the product), which is >= tn* (1 + gamma(3)) when k >=
** gamma(3) + gamma(4) + O(u^2), about 7u; 12u leaves room for the double
** division under the inverse.  A negative far distance only gets more
** negative, so a negative tmin (where a box behind the origin counts)
** keeps the slack after the min.  1 + 12u is a float (1 + 6 2^-23).
** Without the growth, tests/check_bvh.c's rays at a flat grid's vertices
** lose hits (bvh_should_not_lose_hits_on_flat_boxes; the mutants
** slab-far-grow and slab-far-grown-tf).  Measured against the slack
** after the min (bench/raycost, RAYCOST_AB, thread CPU time, medians of
** six interleaved runs; before / after in time): camera rays that enter
** the box and miss 1.09, camera hits 1.05, shadow rays 1.08, the ground
** query 1.02, rays that miss the box 1.00; on the 940k bunny
** (RAYCOST_MESH=bunny-4.obj, three runs) 1.04-1.11, 1.07-1.09,
** 1.10-1.11 and 0.96-1.05 (issue 34).
*/
#define FAR_GROW (1.0f + 12.0f * FLOAT_U)

/* The interval's end t in the scaled units, rounded up to a float. */
static inline float trav_tmax(const trav *tr, double t)
{
    return ray__float_up(t * tr->t_scale);
}

/* Do the far distances carry the slack themselves (FAR_GROW)?  Where the
** interval starts at or past zero; the one place the rule is written. */
static inline int trav_grown(const trav *tr)
{
    return !(tr->tmin < 0);
}

/* t moved away from zero by the slack. */
static inline float with_slack(float t)
{
    return t + fabsf(t) * FAR_SLACK;
}

/* The offsets of the near and far bound arrays in a node for the ray's
** octant: bit k of "signs" is direction component k's sign bit (1/d < 0
** exactly when it is set, d = -0 included: -Inf), which swaps lo[k] and
** hi[k], hi[k] lying a fixed span after lo[k].  A table of the eight
** octants, constant: two copies a ray instead of the arithmetic of six
** offsets (a twentieth of a query that misses the scene's box). */
#define OCT_LO(k) (offsetof(ray__wnode, lo[0]) + \
                   (size_t)(k) * sizeof(float) * RAY__WIDTH)
#define OCT_SPAN (offsetof(ray__wnode, hi[0]) - offsetof(ray__wnode, lo[0]))
#define OCT_NEAR(s, k) (OCT_LO(k) + (size_t)((s) >> (k) & 1) * OCT_SPAN)
#define OCT_FAR(s, k) (OCT_LO(k) + (size_t)(1 - ((s) >> (k) & 1)) * OCT_SPAN)
#define OCT_ROW(s) {OCT_NEAR(s, 0), OCT_NEAR(s, 1), OCT_NEAR(s, 2)}, \
                   {OCT_FAR(s, 0), OCT_FAR(s, 1), OCT_FAR(s, 2)}

static inline void trav_octant(trav *tr, int signs)
{
    static const size_t at[8][2][3] = {
        {OCT_ROW(0)}, {OCT_ROW(1)}, {OCT_ROW(2)}, {OCT_ROW(3)},
        {OCT_ROW(4)}, {OCT_ROW(5)}, {OCT_ROW(6)}, {OCT_ROW(7)}};

    memcpy(tr->near_at, at[signs & 7][0], sizeof tr->near_at);
    memcpy(tr->far_at, at[signs & 7][1], sizeof tr->far_at);
}

#if !defined(__AVX__) || defined(RAY_NO_SIMD)
/* Axis k of the traversal data but its offsets (trav_octant): origin
** component o, direction component d, and d scaled by the power of two
** (ds). */
static inline void trav_axis(trav *tr, int k, double o, double d, double ds)
{
    /* 1/d < 0 exactly when d's sign bit is set (d = -0: -Inf). */
    int neg = signbit(d) != 0;
    double inv = 1.0 / ds;
    float ends[2];

    ends[0] = ray__float_down(o);
    ends[1] = ray__float_up(o);
    /* 1/d beyond float: NaN, the slab ignored (chosen by indexing, as
    ** the other choices here). */
    {
        double choice[2];
        choice[0] = inv;
        choice[1] = (double)NAN;
        tr->inv[k] = (float)choice[(d != 0) & !(fabs(ds) >= 0x1p-126)];
    }
    tr->inv_far[k] = tr->inv[k] * FAR_GROW;
    /* inv >= 0: near = (lo_plane - o_hi) * inv, far = (hi - o_lo) * inv;
    ** inv < 0:  near = (hi_plane - o_lo) * inv, far = (lo - o_hi) * inv. */
    tr->o_near[k] = ends[!neg];
    tr->o_far[k] = ends[neg];
}
#endif

#if defined(__AVX__) && !defined(RAY_NO_SIMD)
/*
** A ray in two registers, its two halves: org.x .. dir.x and dir.y ..
** tmax, each read by one 32-byte load -- and the direction and tmin
** (x y z tmin) from them.  Halves that do not overlap, so that a ray
** written just before as two such stores (an instance's ray in its
** child's space, ray_halves_store) is forwarded from them: a load is
** forwarded from a store only when one store holds it all, else it waits
** until the stores reach the cache, which was the largest stall of an
** instance's child query in a game's frame (perf annotate, bench/game
** frame, issue 36).
*/
typedef struct ray_halves {
    __m256d a;                          /* org.x org.y org.z dir.x */
    __m256d b;                          /* dir.y dir.z tmin tmax */
} ray_halves;

static inline ray_halves ray_halves_load(const ray_ray *r)
{
    ray_halves h;

    h.a = _mm256_loadu_pd(&r->org.x);
    h.b = _mm256_loadu_pd(&r->dir.y);
    return h;
}

/* The direction and tmin: (a3, b0) and (b1, b2) of (a2 a3 b0 b1), b. */
static inline __m256d ray_halves_dir(const ray_halves *h)
{
    return _mm256_shuffle_pd(_mm256_permute2f128_pd(h->a, h->b, 0x21), h->b,
                             5);
}

/* Ray r written as its two halves. */
static inline void ray_halves_store(ray_ray *r, __m256d a, __m256d b)
{
    _mm256_storeu_pd(&r->org.x, a);
    _mm256_storeu_pd(&r->dir.y, b);
}
#endif

/* *dst = *src, a query's own copy of its ray, which its set-up then reads:
** in the AVX copy as the two halves (ray_halves), where the compiler's
** copy wrote sixteen bytes at a time and the set-up's loads waited for
** them: a ray that misses the mesh's box took 1.7 times as long
** (bench/raycost, RAYCOST_AB, issue 34). */
static inline void ray_copy(ray_ray *dst, const ray_ray *src)
{
#if defined(__AVX__) && !defined(RAY_NO_SIMD)
    ray_halves h = ray_halves_load(src);

    ray_halves_store(dst, h.a, h.b);
#else
    *dst = *src;
#endif
}

/*
** ray__ray_usable (prim/prim.h) for this copy's queries: in the AVX copy
** in two registers (ray_halves) -- the origin and the direction's x,
** then the rest of the direction, tmin and tmax -- where the plain
** form's six subtractions, sums and three compares were a tenth of a
** query that misses the scene's box (callgrind, issue 34).  The same
** answer: x - x == 0 exactly when x is finite (the plain form sums the
** six differences, 0 only if each is 0); a non-zero direction component;
** tmin < tmax (NaN: not).
*/
static inline int trav_usable(const ray_ray *r)
{
#if defined(__AVX__) && !defined(RAY_NO_SIMD)
    ray_halves h = ray_halves_load(r);
    __m256d zero = _mm256_setzero_pd();
    /* a: the origin's x, y, z and the direction's x finite (bits 0-3);
    ** b: the direction's y and z (bits 0-1) */
    int finite_a = _mm256_movemask_pd(_mm256_cmp_pd(_mm256_sub_pd(h.a, h.a),
                                                    zero, _CMP_EQ_OQ));
    int finite_b = _mm256_movemask_pd(_mm256_cmp_pd(_mm256_sub_pd(h.b, h.b),
                                                    zero, _CMP_EQ_OQ));
    int nonzero = (_mm256_movemask_pd(_mm256_cmp_pd(h.a, zero, _CMP_NEQ_UQ)) &
                   8) |
                  (_mm256_movemask_pd(_mm256_cmp_pd(h.b, zero, _CMP_NEQ_UQ)) &
                   3);

    return (finite_a == 15) & ((finite_b & 3) == 3) & (nonzero != 0) &
           (r->tmin < r->tmax);
#else
    return ray__ray_usable(r);
#endif
}

#if defined(__AVX__) && !defined(RAY_NO_SIMD)
/*
** May a ray enter the box lo .. hi (the scene's: the union of the root
** node's boxes, floats) within its interval?  0: surely not, so the
** query ends before the rest of its set-up (the lanes, the walk's state,
** the root node): a ray that passes beside a mesh's box cost 351
** instructions, 273 with this test; a ray that goes on, about 60 more
** (bench/raycost under callgrind), off its critical path: in time, 1.29
** to 1.36 times as fast on the first and no measurable change on the
** others, the instances' rays 1.02 (issue 34).  The root node's test
** (boxes_hit) on that one box, from the ray's data as trav_setup makes
** it (o_near, o_far, inv, inv_far, tmin, t_scale; in registers, before
** it is stored): the same float
** operations on a box that holds each of the root's, and each is
** monotonic (a face farther out gives a near distance no larger and a
** far one no smaller, a NaN distance leaves its slab out in both), so a
** ray the root node lets through any box is let through here, and the
** answers are the walk's.  tests/check_bvh.c compares this copy with
** the plain one, which has no such test, on rays along and beside the
** box's faces, edges and corners.
*/
static inline int box_may_enter(const ray_vec3 *box_lo,
                                const ray_vec3 *box_hi, __m128 sign,
                                __m128 o_near, __m128 o_far, __m128 inv,
                                __m128 inv_far, float tmin, double t_scale,
                                double tmax)
{
    const __m256i xyz = _mm256_set_epi64x(0, -1, -1, -1);
    __m128 lo = _mm256_cvtpd_ps(_mm256_maskload_pd(&box_lo->x, xyz));
    __m128 hi = _mm256_cvtpd_ps(_mm256_maskload_pd(&box_hi->x, xyz));
    /* inv >= 0 (sign clear): near face lo, far face hi */
    int grown = !(tmin < 0);
    __m128 tn = _mm_mul_ps(_mm_sub_ps(_mm_blendv_ps(lo, hi, sign), o_near),
                           inv);
    /* the far distances by inv_far only where they carry the slack (as
    ** lanes_axis: a negative one would grow the wrong way) */
    __m128 tf = _mm_mul_ps(_mm_sub_ps(_mm_blendv_ps(hi, lo, sign), o_far),
                           grown ? inv_far : inv);
    float t_max = ray__float_up(tmax * t_scale);
    /* lane by lane as boxes_hit (a NaN distance gives the interval's
    ** end), then the largest near and the smallest far of x, y, z */
    __m128 t0 = _mm_max_ps(tn, _mm_set1_ps(tmin));
    __m128 t1 = _mm_min_ps(tf, _mm_set1_ps(grown ? with_slack(t_max)
                                                 : t_max));
    float near, far;

    t0 = _mm_max_ss(t0, _mm_max_ss(_mm_shuffle_ps(t0, t0, 1),
                                   _mm_shuffle_ps(t0, t0, 2)));
    t1 = _mm_min_ss(t1, _mm_min_ss(_mm_shuffle_ps(t1, t1, 1),
                                   _mm_shuffle_ps(t1, t1, 2)));
    near = _mm_cvtss_f32(t0);
    far = _mm_cvtss_f32(t1);
    return near <= (grown ? far : with_slack(far));
}
#endif

/*
** The traversal data of r, a ray that passed ray__ray_usable.  Free of
** branches on the ray's signs and roundings (each a coin toss for
** incoherent rays): the choices are made by indexing, and the axes are
** written out (a loop's exit is mispredicted once a ray).  box_lo and
** box_hi: NULL, or a box that holds every triangle of the BVH about to
** be walked: 0 when the ray surely misses it (box_may_enter), *tr then
** untouched; else 1.  Only the AVX copy tests the box, and before it
** writes *tr: a ray that misses stores nothing (1.14 times as fast on
** such rays, bench/raycost, RAYCOST_AB, issue 34).
**
** AVX: the three axes of trav_axis at once, x, y, z in the lanes of one
** register (the fourth, tmin's, is computed and not used): the same
** operations lane for lane -- the product by the power of two, the
** division (vdivpd rounds as divsd does), the conversions to float
** (vcvtpd2ps rounds to nearest as cvtsd2ss does) and ray__float_down /
** up's step to the neighbouring float on the integer bits -- so the same
** bits; one division instruction instead of three, and no choice by
** indexing.  The near / far ends of the origin are picked by the sign
** bit of d (blendv reads the sign bit: -0 has it, as signbit says).
** What a query's set-up costs was a fifth of a ray that misses (bench/
** raycost's "miss the box" under callgrind, issue 34).  The rounding
** outward: floats_step, core/floats_avx.h.
*/
static RAY__INLINE int trav_setup(trav *tr, const ray_ray *r,
                                  const ray_vec3 *box_lo,
                                  const ray_vec3 *box_hi)
{
    ray_vec3 ad = v3_abs(r->dir);
    double m = ad.x > ad.y ? ad.x : ad.y, down, t_scale;
    float tmin;
    int e;

    m = m > ad.z ? m : ad.z;
    e = ray__exponent_of(m);
    t_scale = ray__pow2(e);              /* t' = t 2^e for d' = d 2^-e */
    down = ray__pow2(-e);
    tmin = ray__float_down(r->tmin * t_scale);
#if defined(__AVX__) && !defined(RAY_NO_SIMD)
    {
        ray_halves h = ray_halves_load(r);
        __m256d d = ray_halves_dir(&h);                  /* x y z tmin */
        __m256d o = h.a;                                 /* x y z dir.x */
        __m256d ds = _mm256_mul_pd(d, _mm256_set1_pd(down));
        __m256d inv = _mm256_div_pd(_mm256_set1_pd(1.0), ds);
        __m256d abs_ds = _mm256_andnot_pd(_mm256_set1_pd(-0.0), ds);
        __m256d ignored = _mm256_and_pd(
            _mm256_cmp_pd(d, _mm256_setzero_pd(), _CMP_NEQ_OQ),
            _mm256_cmp_pd(abs_ds, _mm256_set1_pd(0x1p-126), _CMP_NGE_UQ));
        __m128 lo = floats_step(o, 0), hi = floats_step(o, 1);
        __m128 sign = _mm256_cvtpd_ps(d);  /* d's sign bit, -0 and all */
        __m128 inv4, inv_far4, o_near4, o_far4;

        inv = _mm256_blendv_pd(inv, _mm256_set1_pd((double)NAN), ignored);
        inv4 = _mm256_cvtpd_ps(inv);
        inv_far4 = _mm_mul_ps(inv4, _mm_set1_ps(FAR_GROW));
        /* inv >= 0 (sign clear): near from o_hi, far from o_lo. */
        o_near4 = _mm_blendv_ps(hi, lo, sign);
        o_far4 = _mm_blendv_ps(lo, hi, sign);
        if (box_lo != NULL &&
            !box_may_enter(box_lo, box_hi, sign, o_near4, o_far4, inv4,
                           inv_far4, tmin, t_scale, r->tmax))
            return 0;
        tr->t_scale = t_scale;
        tr->tmin = tmin;
        tr->framed = 0;
        _mm_storeu_ps(tr->inv, inv4);
        _mm_storeu_ps(tr->inv_far, inv_far4);
        _mm_storeu_ps(tr->o_near, o_near4);
        _mm_storeu_ps(tr->o_far, o_far4);
        trav_octant(tr, _mm256_movemask_pd(d));
        return 1;
    }
#else
    tr->t_scale = t_scale;
    tr->tmin = tmin;
    tr->framed = 0;
    trav_axis(tr, 0, r->org.x, r->dir.x, r->dir.x * down);
    trav_axis(tr, 1, r->org.y, r->dir.y, r->dir.y * down);
    trav_axis(tr, 2, r->org.z, r->dir.z, r->dir.z * down);
    trav_octant(tr, (signbit(r->dir.x) != 0) | (signbit(r->dir.y) != 0) << 1 |
                        (signbit(r->dir.z) != 0) << 2);
    (void)box_lo;
    (void)box_hi;
    return 1;
#endif
}

/* The traversal data of r, whole (no box test). */
static void trav_init(trav *tr, const ray_ray *r)
{
    (void)trav_setup(tr, r, NULL, NULL);
}

/*
** The triangle test's frame of the ray, and its float filter in scene s,
** set up when the ray first reaches a leaf of triangles: most primary
** rays of a scene that does not fill the frame reach none, and would pay
** its three divisions for nothing.  0 if the ray has no frame (a zero or
** NaN direction: never for a ray that passed ray__ray_usable).
*/
static inline int trav_frame(trav *tr, const ray_ray *r, const ray_scene *s)
{
    if (tr->framed == 0) {
        tr->framed = ray__watertight_init(&tr->wt, r) ? 1 : -1;
        if (tr->framed > 0)
            tri_filter_init(&tr->flt, &tr->wt, r, s);
    }
    return tr->framed > 0;
}

/* The lowest set bit of a mask of RAY__WIDTH bits (mask != 0). */
static inline int lowest_bit(unsigned mask)
{
#if defined(__GNUC__)
    return __builtin_ctz(mask);
#elif defined(_MSC_VER)
    unsigned long k;
    _BitScanForward(&k, mask);
    return (int)k;
#else
    int k = 0;
    while (!(mask >> k & 1))
        k++;
    return k;
#endif
}

/*
** Ask the cache for the lines of [p, p + bytes) now, so that their misses
** overlap the work done before they are read, as a traversal's work
** between deciding to visit a slot and reading it is otherwise stalled
** behind each miss in turn.  On the 940k bunny a camera ray that hits
** visits leaves whose float rows and double corners (leaf_tri, 72 bytes
** a triangle) lie far apart, and a random ray's are cold.  Embree /
** ours in time, 5703337 against these prefetches on a quiet machine:
** the ground query 0.38 -> 0.45 (bench/raycost), the 940k bunny's
** camera rays 0.55 -> 0.65 and incoherent rays 0.43 -> 0.49 (bench/
** mesh, issue 34).  A hint only (RAY__PREFETCH, core/vec.h): no fault,
** no effect on any answer.
*/
#define RAY__CACHE_LINE 64

static inline void prefetch_bytes(const void *p, size_t bytes)
{
    const char *at = (const char *)p, *stop = at + bytes;

    for (; at < stop; at += RAY__CACHE_LINE)
        RAY__PREFETCH(at);
}

/* Node q's bound array at byte offset "at" (one of trav's offsets). */
static inline const float *bound_at(const ray__wnode *q, size_t at)
{
    return (const float *)(const void *)((const char *)q + at);
}

/*
** Which of node q's boxes does the ray enter within (tmin, tmax)?
** boxes_hit returns a bit mask; entry[k] is where it enters box k.  The
** ray's quantities are first spread over the lanes ("lanes", once per
** traversal), so a node costs only its loads and the arithmetic.
*/
#if !defined(RAY_NO_SIMD) && (defined(__AVX__) || RAY__SSE2)
#if RAY__WIDTH != 8
#error "boxes_hit below tests eight lanes, or two halves of four"
#endif
/*
** The ray's quantities in a register each: eight lanes with AVX (the
** AVX2 copy of the queries), four with SSE.
*/
#if defined(__AVX__)
#include <immintrin.h>
typedef __m256 vf;
#define VF_SET1 _mm256_set1_ps
#else
#include <emmintrin.h>
typedef __m128 vf;
#define VF_SET1 _mm_set1_ps
#endif

typedef struct lanes {
    vf o_near[3], o_far[3], inv[3], inv_far[3], tmin, slack;
    size_t near_at[3], far_at[3];
    int grown;                  /* far distances by inv_far (FAR_GROW) */
} lanes;

static inline void lanes_axis(lanes *l, const trav *tr, int a)
{
    l->o_near[a] = VF_SET1(tr->o_near[a]);
    l->o_far[a] = VF_SET1(tr->o_far[a]);
    l->inv[a] = VF_SET1(tr->inv[a]);
    l->inv_far[a] = VF_SET1(l->grown ? tr->inv_far[a] : tr->inv[a]);
    l->near_at[a] = tr->near_at[a];
    l->far_at[a] = tr->far_at[a];
}

static RAY__INLINE void lanes_init(lanes *l, const trav *tr)
{
    l->grown = trav_grown(tr);
    lanes_axis(l, tr, 0);           /* written out: no loop to exit */
    lanes_axis(l, tr, 1);
    lanes_axis(l, tr, 2);
    l->tmin = VF_SET1(tr->tmin);
    l->slack = VF_SET1(FAR_SLACK);
}
#endif

#if defined(__AVX__) && !defined(RAY_NO_SIMD)
/*
** AVX: all eight lanes in one register, the same arithmetic as the plain
** loop below lane for lane (vmaxps / vminps pick as maxps / minps do).
*/
static inline void slab8(const ray__wnode *q, const lanes *l, int a,
                         __m256 *t0, __m256 *t1)
{
    __m256 np = _mm256_loadu_ps(bound_at(q, l->near_at[a]));
    __m256 fp = _mm256_loadu_ps(bound_at(q, l->far_at[a]));
    __m256 tn = _mm256_mul_ps(_mm256_sub_ps(np, l->o_near[a]), l->inv[a]);
    __m256 tf = _mm256_mul_ps(_mm256_sub_ps(fp, l->o_far[a]), l->inv_far[a]);

    *t0 = _mm256_max_ps(tn, *t0);                    /* NaN tn: ignored */
    *t1 = _mm256_min_ps(tf, *t1);                    /* NaN tf: ignored */
}

/* boxes_hit in registers: the entries in *entry, and in *in the boxes
** entered, all ones in their lanes (packet.h reads both as vectors). */
static inline unsigned boxes_hit_v(const ray__wnode *q, const lanes *l,
                                   float tmax, float tpop, int grown,
                                   __m256 *entry, __m256 *in)
{
    __m256 t0 = l->tmin;
    __m256 t1 = _mm256_set1_ps(grown ? tpop : tmax);

    slab8(q, l, 0, &t0, &t1);
    slab8(q, l, 1, &t0, &t1);
    slab8(q, l, 2, &t0, &t1);
    if (!grown)                     /* the slack after the min: FAR_GROW */
        t1 = _mm256_add_ps(t1, _mm256_mul_ps(
                                   _mm256_andnot_ps(_mm256_set1_ps(-0.0f), t1),
                                   l->slack));
    *entry = t0;
    *in = _mm256_cmp_ps(t0, t1, _CMP_LE_OQ);
    return (unsigned)_mm256_movemask_ps(*in);
}

/* tmax: the interval's end (trav_tmax); tpop: with its slack; grown:
** l->grown, or that value fixed by the caller (traverse.h, GROWN_ASK). */
static inline unsigned boxes_hit(const ray__wnode *q, const lanes *l,
                                 float tmax, float tpop, int grown,
                                 float entry[RAY__WIDTH])
{
    __m256 t0, in;
    unsigned mask = boxes_hit_v(q, l, tmax, tpop, grown, &t0, &in);

    _mm256_storeu_ps(entry, t0);
    return mask;
}
#elif RAY__SSE2
/*
** SSE: four lanes a register, the same arithmetic as the plain loop below
** lane for lane; a node's two halves are independent, so their latencies
** overlap.  maxps / minps return their second operand when either is NaN,
** so max(tn, t0) keeps t0 for a NaN tn exactly as the plain
** "tn > t0 ? tn : t0" does.  slab4 narrows [*t0, *t1] to the slab of
** axis a in lanes lane .. lane + 3.
*/
static inline void slab4(const ray__wnode *q, const lanes *l, int a,
                         int lane, __m128 *t0, __m128 *t1)
{
    __m128 np = _mm_loadu_ps(bound_at(q, l->near_at[a]) + lane);
    __m128 fp = _mm_loadu_ps(bound_at(q, l->far_at[a]) + lane);
    __m128 tn = _mm_mul_ps(_mm_sub_ps(np, l->o_near[a]), l->inv[a]);
    __m128 tf = _mm_mul_ps(_mm_sub_ps(fp, l->o_far[a]), l->inv_far[a]);

    *t0 = _mm_max_ps(tn, *t0);                       /* NaN tn: ignored */
    *t1 = _mm_min_ps(tf, *t1);                       /* NaN tf: ignored */
}

static inline unsigned boxes_hit4(const ray__wnode *q, const lanes *l,
                                  __m128 vmax, int grown, int lane,
                                  float *entry)
{
    __m128 t0 = l->tmin, t1 = vmax;

    slab4(q, l, 0, lane, &t0, &t1);
    slab4(q, l, 1, lane, &t0, &t1);
    slab4(q, l, 2, lane, &t0, &t1);
    /* Clipped to tmax, then the slack (where the far distances do not
    ** carry it: FAR_GROW): t1 is never NaN; -Inf (a box wholly outside a
    ** slab of a zero direction component) gives NaN, a miss. */
    if (!grown)
        t1 = _mm_add_ps(t1, _mm_mul_ps(_mm_andnot_ps(_mm_set1_ps(-0.0f), t1),
                                       l->slack));
    _mm_storeu_ps(entry + lane, t0);
    return (unsigned)_mm_movemask_ps(_mm_cmple_ps(t0, t1)) << lane;
}

/* tmax: the interval's end (trav_tmax); tpop: with its slack; grown:
** l->grown, or that value fixed by the caller (traverse.h, GROWN_ASK). */
static inline unsigned boxes_hit(const ray__wnode *q, const lanes *l,
                                 float tmax, float tpop, int grown,
                                 float entry[RAY__WIDTH])
{
    __m128 vmax = _mm_set1_ps(grown ? tpop : tmax);

    /* Written out for the two halves (-O2 does not unroll a loop). */
    return boxes_hit4(q, l, vmax, grown, 0, entry) |
           boxes_hit4(q, l, vmax, grown, 4, entry);
}
#else
/* Plain C reads the ray's quantities from the traversal data itself. */
typedef struct lanes {
    const trav *tr;
    int grown;                  /* as trav_grown(tr) */
} lanes;

static RAY__INLINE void lanes_init(lanes *l, const trav *tr)
{
    l->tr = tr;
    l->grown = trav_grown(tr);
}

static inline unsigned boxes_hit(const ray__wnode *q, const lanes *l,
                                 float tmax, float tpop, int grown,
                                 float entry[RAY__WIDTH])
{
    const trav *tr = l->tr;
    float t0[RAY__WIDTH], t1[RAY__WIDTH];
    unsigned mask = 0;
    int a, k;

    for (k = 0; k < RAY__WIDTH; k++) {
        t0[k] = tr->tmin;
        t1[k] = grown ? tpop : tmax;
    }
    for (a = 0; a < 3; a++) {
        const float *np = bound_at(q, tr->near_at[a]);
        const float *fp = bound_at(q, tr->far_at[a]);
        float inv_far = grown ? tr->inv_far[a] : tr->inv[a];
        for (k = 0; k < RAY__WIDTH; k++) {
            float tn = (np[k] - tr->o_near[a]) * tr->inv[a];
            float tf = (fp[k] - tr->o_far[a]) * inv_far;
            t0[k] = tn > t0[k] ? tn : t0[k];        /* NaN tn: ignored */
            t1[k] = tf < t1[k] ? tf : t1[k];        /* NaN tf: ignored */
        }
    }
    for (k = 0; k < RAY__WIDTH; k++) {
        float far = grown ? t1[k] : with_slack(t1[k]);  /* as the SSE lanes */
        entry[k] = t0[k];
        mask |= (unsigned)(t0[k] <= far) << k;
    }
    return mask;
}
#endif

#endif /* RAY_SLAB_H */
