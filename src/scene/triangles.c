/* SPDX-License-Identifier: MIT */
/*
** triangles.c -- the triangle slots at commit: the BVH over the live
** ones (of enabled geometry), the slots put in its leaf order, and the
** leaves' float corners (scene.h, RAY__LEAF_ROWS), which the queries'
** float filter reads in front of the exact double test.  A refit keeps
** the tree and fits its boxes, and the float corners, again.
*/
#include <string.h>

#include "core/platform.h"
#include "core/tasks.h"
#include "scene/slots.h"

/*
** The triangle BVH's cost settings (accel/sah.c): a split costs 1.5
** triangle tests, and eight triangles or fewer always make a leaf.  The
** float filter (query/filter.h) tests a leaf's triangles eight at a time
** in one pass, so a leaf of eight costs about what a leaf of one does,
** and a wide node tests all its boxes at once, whatever their number:
** bench/mesh measured (issue 27).  A triangle's box (tri_box) reads only
** the scene, so the build may make them on its threads.
*/
static const ray__bvh_costs tri_costs = {1.5f, RAY__LEAF_MAX, 1};

/* The smaller and larger of two, of three finite numbers (no libm call:
** the NaN rules of fmin are not needed here, vertices are finite). */
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

/* *lo, *hi grown to hold triangle t. */
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

/* The corners of live slot "slot" into *t, as ray__tri_of reads them:
** found by ray__slot_corners_at (*m and *m_geom its cache), a mesh's read
** through ray__mesh_tri, which applies the rule for a triangle without
** a normal (the pointers into its positions go unused). */
RAY__HOT_INLINE void refit_corners(const ray_scene *s, size_t slot,
                                    const ray__mesh **m, unsigned *m_geom,
                                    ray__tri *t)
{
    const ray_vec3 *p[3];

    if (ray__slot_corners_at(s, slot, m, m_geom, t, p))
        ray__mesh_tri(*m, s->tri_ids[slot].prim_id, t);
}

/* The float box of slot i, rounded outward (the build's box callback). */
static void tri_box(const void *ud, size_t i, float lo[3], float hi[3])
{
    const ray__mesh *m = NULL;
    unsigned m_geom = (unsigned)-1;
    ray__tri t;
    ray_vec3 a, b;

    refit_corners(ud, i, &m, &m_geom, &t);
    a = b = t.a;

    corners_grow(&t, &a, &b);
    ray__box_out_float(a, b, lo, hi);
}

/* Does x lie where the leaf rows keep floats (RAY__LEAF_FLOAT_MAX)? */
static inline int row_fits(double x)
{
    return fabs(x) <= RAY__LEAF_FLOAT_MAX;
}

/*
** The nine floats of triangle t, corner by corner (a, b, c), axis by
** axis, at rows[0], rows[stride], ... rows[8 stride], each the nearest
** float.  A triangle with a coordinate beyond RAY__LEAF_FLOAT_MAX (where
** the filter's arithmetic could overflow, and where a conversion to
** float could be out of range) gets NaN in all nine, which the filter
** never rejects: the exact test decides it (fits: whether every
** coordinate is within it).
*/
static inline void rows_nan(float *rows, size_t stride)
{
    int k;

    for (k = 0; k < RAY__LEAF_ROWS; k++)
        rows[(size_t)k * stride] = (float)NAN;
}

static inline void leaf_rows_fitting(const ray__tri *t, float *rows,
                                     size_t stride, int fits)
{
    /* Written out, not looped over an array of nine: a refit writes every
    ** triangle's rows, and the loops were two fifths of its instructions
    ** (callgrind, bench/game's 59k refit, issue 36). */
    float *r = rows;

    if (fits) {
        r[0] = (float)t->a.x, r += stride;
        r[0] = (float)t->a.y, r += stride;
        r[0] = (float)t->a.z, r += stride;
        r[0] = (float)t->b.x, r += stride;
        r[0] = (float)t->b.y, r += stride;
        r[0] = (float)t->b.z, r += stride;
        r[0] = (float)t->c.x, r += stride;
        r[0] = (float)t->c.y, r += stride;
        r[0] = (float)t->c.z;
    } else
        rows_nan(rows, stride);
}

/* leaf_rows_fitting with the test of every coordinate (fits: each is
** within RAY__LEAF_FLOAT_MAX). */
static inline void leaf_rows(const ray__tri *t, float *rows, size_t stride)
{
    leaf_rows_fitting(t, rows, stride,
                      row_fits(t->a.x) & row_fits(t->a.y) &
                      row_fits(t->a.z) & row_fits(t->b.x) &
                      row_fits(t->b.y) & row_fits(t->b.z) &
                      row_fits(t->c.x) & row_fits(t->c.y) &
                      row_fits(t->c.z));
}

/*
** fn(s, begin, end, out) over the n live slots in runs of SLOT_RUN, on
** the scene's build threads or scheduler (ray_scene_set_build_threads):
** the commit's passes that read every triangle once and write what is
** the slot's own (its rows, its copy), so the runs share nothing and the
** bytes are the same at any thread count.  They were two fifths of a
** 940k build's time on the calling thread while the others waited
** (callgrind, one thread each, issue 36).
*/
#define SLOT_RUN 16384

typedef void (*slot_fn)(const ray_scene *s, size_t begin, size_t end,
                        void *out);

typedef struct slot_job {
    const ray_scene *s;
    slot_fn fn;
    void *out;
} slot_job;

static void slot_task(void *ud, unsigned k, size_t begin, size_t end)
{
    const slot_job *job = ud;

    (void)k;
    job->fn(job->s, begin, end, job->out);
}

/* fn over 0 .. n - 1 in runs of "run" (slots_run's threads). */
static void runs_of(ray_scene *s, size_t n, size_t run, slot_fn fn, void *out)
{
    /* 0: one a CPU, as the build's own threads (build.c). */
    unsigned threads = s->build_threads != 0 ? s->build_threads
                                             : ray__online_cpus();
    slot_job job;

    job.s = s;
    job.fn = fn;
    job.out = out;
    if (!ray__tasks_runs(&s->scheduler, &s->alloc, threads, 0, n, run,
                         slot_task, &job))
        fn(s, 0, n, out);
}

static void slots_run(ray_scene *s, size_t n, slot_fn fn, void *out)
{
    runs_of(s, n, SLOT_RUN, fn, out);
}

/* Slots begin .. end - 1's rows, by slot, into out (leaves_make). */
static void rows_by_slot(const ray_scene *s, size_t begin, size_t end,
                         void *out)
{
    float *by_slot = out;
    const ray__mesh *m = NULL;
    unsigned m_geom = (unsigned)-1;
    size_t i;

    for (i = begin; i < end; i++) {
        ray__tri t;
        refit_corners(s, i, &m, &m_geom, &t);
        leaf_rows(&t, by_slot + RAY__LEAF_ROWS * i, 1);
    }
}

/* Slots begin .. end - 1's corners copied into out (leaf_tris_make). */
static void copies_by_slot(const ray_scene *s, size_t begin, size_t end,
                           void *out)
{
    ray__tri *copy = out;
    const ray__mesh *m = NULL;
    unsigned m_geom = (unsigned)-1;
    size_t i;

    for (i = begin; i < end; i++) {
        refit_corners(s, i, &m, &m_geom, &copy[i]);
        if (m != NULL)
            ray__prefetch_slots(s, i, m, m_geom);
    }
}

/*
** Are the float corners of every live triangle exact (the scene's
** float_exact, which lets the filter's bound drop the vertices'
** rounding)?  Yes when each live mesh's positions are floats (checked as
** they were copied) and each live single triangle's corners are.
*/
static int corners_are_floats(const ray_scene *s)
{
    size_t i;

    for (i = 0; i < s->n_prims; i++) {
        const ray__prim *p = &s->prims[i];
        if (!p->enabled || p->removed)
            continue;
        if (p->kind == RAY__KIND_MESH && !s->meshes[p->mesh].pos_floats)
            return 0;
        if (p->kind == RAY__KIND_TRIANGLE &&
            !(ray__is_float(p->a.x) && ray__is_float(p->a.y) &&
              ray__is_float(p->a.z) && ray__is_float(p->b.x) &&
              ray__is_float(p->b.y) && ray__is_float(p->b.z) &&
              ray__is_float(p->c.x) && ray__is_float(p->c.y) &&
              ray__is_float(p->c.z)))
            return 0;
    }
    return 1;
}

/* Leaf layout from rows in slot order (before the slots are permuted):
** a leaf's slot j is slot items[first + j] then. */
typedef struct leaf_gather {
    float *out;
    const float *by_slot;        /* RAY__LEAF_ROWS floats per old slot */
    const unsigned *items;
    const ray__bvh *bvh;         /* whose leaves */
} leaf_gather;

static void gather_leaf(const leaf_gather *g, unsigned first, unsigned n)
{
    float *rows = g->out + (size_t)RAY__LEAF_ROWS * first;
    unsigned j;
    int r;

    for (j = 0; j < n; j++) {
        const float *src = g->by_slot +
                           (size_t)RAY__LEAF_ROWS * g->items[first + j];
        for (r = 0; r < RAY__LEAF_ROWS; r++)
            rows[(size_t)r * n + j] = src[r];
    }
}

/*
** The leaves of wide nodes begin .. end - 1 gathered (ud: the
** leaf_gather): each leaf writes only its own rows, so runs of nodes go
** to the build's threads (runs_of) and the bytes are the same at any
** thread count.  The gather's random reads were, on the calling thread
** alone, a ninth of a 940k build's time on two threads (perf, issue 36).
*/
#define WIDE_RUN 1024

static void gather_wide(const ray_scene *s, size_t begin, size_t end,
                        void *ud)
{
    const leaf_gather *g = ud;
    size_t w;
    int k;

    (void)s;
    for (w = begin; w < end; w++)
        for (k = 0; k < RAY__WIDTH; k++) {
            const ray__wnode *q = &g->bvh->wide[w];
            unsigned n = q->count[k] & ~RAY__LEAF;
            if (q->count[k] != 0 && n > 0)
                gather_leaf(g, q->child[k], n);
        }
}

/*
** The float corners of the n live slots in the leaves of the fresh BVH
** (its items: the old slot of each leaf position), into a new leaf_f:
** first in slot order into by_slot (the rebuild's scratch, of
** RAY__LEAF_ROWS n floats at least), reading the geometry as it lies (a
** mesh's indices in order), then gathered into leaf order, one random
** read a slot.  RAY_OK or RAY_ENOMEM (nothing changed).
*/
static int leaves_make(ray_scene *s, const ray__bvh *fresh, size_t n,
                       float *by_slot)
{
    size_t floats = RAY__LEAF_ROWS * n + RAY__LEAF_PAD;
    float *out = ray__alloc(s, floats * sizeof *out);
    leaf_gather g;

    if (out == NULL)
        return RAY_ENOMEM;
    slots_run(s, n, rows_by_slot, by_slot);
    g.out = out;
    g.by_slot = by_slot;
    g.items = fresh->items;
    g.bvh = fresh;
    runs_of(s, fresh->n_wide, WIDE_RUN, gather_wide, &g);
    memset(out + RAY__LEAF_ROWS * n, 0, RAY__LEAF_PAD * sizeof *out);
    s->leaf_f = out;
    s->cap_leaf_f = floats;
    s->float_exact = corners_are_floats(s);
    return RAY_OK;
}

typedef struct ids_gather {
    ray__tri_id *id;
    const unsigned *items;
} ids_gather;

/* Leaf positions begin .. end - 1's ids (a run of gather_ids's). */
static void ids_by_position(const ray_scene *s, size_t begin, size_t end,
                            void *ud)
{
    const ids_gather *g = ud;
    size_t i;

    for (i = begin; i < end; i++)
        g->id[i] = s->tri_ids[g->items[i]];
}

/*
** Put the ids of the n live slots in leaf order: gathered into "id" (the
** rebuild's scratch, of "bytes"), each read random but none depending on
** another, where walking the permutation's cycles in place chases one
** random read after the other (at 940k triangles the walk took about a
** sixth of the commit, perf on bench/mesh's bunny-4).  The scratch then
** becomes tri_ids (the waiting slots after n copied behind), so nothing
** is copied back: returns 1; or, when the waiting slots do not fit in
** it, the ids are copied back into tri_ids: returns 0.
*/
static int gather_ids(ray_scene *s, const unsigned *items, size_t n,
                      ray__tri_id *id, size_t bytes)
{
    size_t all = s->n_tris;
    ids_gather g;

    g.id = id;
    g.items = items;
    slots_run(s, n, ids_by_position, &g);
    if (all > bytes / sizeof *id) {
        memcpy(s->tri_ids, id, n * sizeof *id);
        return 0;
    }
    memcpy(id + n, s->tri_ids + n, (all - n) * sizeof *id);  /* waiting */
    ray__free(s, s->tri_ids, s->cap_tri_ids * sizeof *s->tri_ids);
    s->tri_ids = id;
    s->cap_tri_ids = bytes / sizeof *id;
    return 1;
}

/* Give back the spare capacity that doubling left in tri_ids (a failed
** shrink keeps the larger block: harmless). */
static void trim_ids(ray_scene *s)
{
    void *p;

    if (s->n_tris == 0 || s->cap_tri_ids == s->n_tris)
        return;          /* a zero-size realloc frees: keep the block */
    p = ray__realloc(s, s->tri_ids, s->cap_tri_ids * sizeof *s->tri_ids,
                     s->n_tris * sizeof *s->tri_ids);
    if (p != NULL) {
        s->tri_ids = p;
        s->cap_tri_ids = s->n_tris;
    }
}

/* Is triangle slot i of geometry that queries may see? */
static int tri_live(const ray_scene *s, size_t i)
{
    const ray__prim *p = &s->prims[s->tri_ids[i].geom_id];
    return p->enabled && !p->removed;
}

/* Swap triangle slots i and j; nothing to do for i == j, the usual case
** (every triangle kept, in place). */
static void tri_swap(ray_scene *s, size_t i, size_t j)
{
    ray__tri_id id;

    if (i == j)
        return;
    id = s->tri_ids[i];
    s->tri_ids[i] = s->tri_ids[j];
    s->tri_ids[j] = id;
}

/* The triangle BVH and the leaves' corners, gone. */
static void leaves_free(ray_scene *s)
{
    ray__bvh_free(&s->alloc, &s->tri_bvh);
    ray__free(s, s->leaf_f, s->cap_leaf_f * sizeof *s->leaf_f);
    ray__free(s, s->leaf_tri, s->n_live_tris * sizeof *s->leaf_tri);
    s->leaf_f = NULL;
    s->cap_leaf_f = 0;
    s->leaf_tri = NULL;
    s->n_live_tris = 0;
}

/*
** The double corners of the n live slots, in leaf order (the slots are
** in it already), for the exact test (ray__leaf_tri): only where they
** are not all floats, as the leaves' floats are those corners otherwise.
** 72 bytes a triangle; out of memory, none: the queries then read the
** corners through the geometry, the same bits, slower.
*/
static void leaf_tris_make(ray_scene *s, size_t n)
{
    if (s->float_exact)
        return;
    s->leaf_tri = ray__alloc(s, n * sizeof *s->leaf_tri);
    if (s->leaf_tri == NULL)
        return;
    slots_run(s, n, copies_by_slot, s->leaf_tri);
}

/* How many slots the rebuild below puts in the BVH: those tri_live
** keeps, the filter its partition applies. */
size_t ray__triangles_live(const ray_scene *s)
{
    size_t n = 0, i;

    for (i = 0; i < s->n_tris; i++)
        n += (size_t)tri_live(s, i);
    return n;
}

/*
** The triangle BVH, rebuilt: removed geometry's slots go for good, the
** slots of enabled geometry are moved to the front (the others wait
** behind, outside the BVH, until enabled again), the BVH is built over
** them and they are put in its leaf order, so a leaf is a contiguous run
** of slots, and its float corners made.  The old tree and corners are
** freed first, which keeps the peak of a rebuild where a first build's
** is; a failure (out of memory) leaves the scene without a triangle BVH,
** uncommitted, its changes staged for the next commit.
*/
int ray__triangles_rebuild(ray_scene *s, ray__progress *prog)
{
    size_t n = 0, i, scratch_bytes;
    void *scratch = NULL;
    ray__bvh fresh;
    int rc;

    for (i = 0; i < s->n_tris; i++)
        if (!s->prims[s->tri_ids[i].geom_id].removed)
            tri_swap(s, n++, i);
    s->n_tris = n;
    n = 0;
    for (i = 0; i < s->n_tris; i++)
        if (tri_live(s, i))
            tri_swap(s, n++, i);
    leaves_free(s);
    /* One scratch block for the build's records, then the corners in
    ** slot order, then the ids in leaf order, which it becomes (trimmed
    ** below): its pages are touched once, where three blocks of their
    ** own were each mapped afresh (at 940k triangles, 30, 34 and 8 MB:
    ** issue 36). */
    scratch_bytes = RAY__BVH_SCRATCH(n);
    if (scratch_bytes < RAY__LEAF_ROWS * n * sizeof(float))
        scratch_bytes = RAY__LEAF_ROWS * n * sizeof(float);
    /* Whole ids, so that as tri_ids it is given back at its size. */
    scratch_bytes += (sizeof(ray__tri_id) - scratch_bytes %
                      sizeof(ray__tri_id)) % sizeof(ray__tri_id);
    if (n > 0 && (n > (size_t)-1 / 64 ||
                  (scratch = ray__alloc(s, scratch_bytes)) == NULL))
        return RAY_ENOMEM;
    rc = ray__bvh_build(&s->alloc, tri_box, s, n, &tri_costs,
                        &s->scheduler, s->build_threads, scratch, prog,
                        &fresh);
    if (rc != RAY_OK) {
        ray__free(s, scratch, scratch_bytes);
        return rc;
    }
    if (n > 0) {
        if (leaves_make(s, &fresh, n, scratch) != RAY_OK) {
            ray__free(s, scratch, scratch_bytes);
            ray__bvh_free(&s->alloc, &fresh);
            return RAY_ENOMEM;
        }
        if (!gather_ids(s, fresh.items, n, scratch, scratch_bytes))
            ray__free(s, scratch, scratch_bytes);
        /* Leaves now index slots directly: the permutation is not kept. */
        ray__free(s, fresh.items, fresh.n_items * sizeof(unsigned));
        fresh.items = NULL;
        fresh.n_items = 0;
    }
    s->tri_bvh = fresh;
    s->n_live_tris = n;
    trim_ids(s);
    /* Last, once the build's scratch is given back: the peak stays the
    ** build's where it can. */
    if (n > 0)
        leaf_tris_make(s, n);
    return RAY_OK;
}

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

    k.a = _mm_loadu_pd(&pa->x);
    k.az = _mm_load_sd(&pa->z);
    k.b = _mm_loadu_pd(&pb->x);
    k.bz = _mm_load_sd(&pb->z);
    k.c = _mm_loadu_pd(&pc->x);
    k.cz = _mm_load_sd(&pc->z);
    if (check && !corners_usable_sse2(&k)) {
        k.b = k.c = k.a;
        k.bz = k.cz = k.az;
    }
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

/* The point whose x and y are in xy's lanes and z in z's low lane. */
static inline ray_vec3 vec3_sse2(__m128d xy, __m128d z)
{
    double out[2];
    ray_vec3 v;

    _mm_storeu_pd(out, xy);
    v.x = out[0];
    v.y = out[1];
    _mm_store_sd(&v.z, z);
    return v;
}

static void refit_leaf(const void *ud, size_t first, size_t n, float lo[3],
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
    ray__box_out_float(vec3_sse2(x.lo_xy, x.lo_z), vec3_sse2(x.hi_xy, x.hi_z), lo, hi);
}
#else
static void refit_leaf(const void *ud, size_t first, size_t n, float lo[3],
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

/* The refit runs on a committed scene, so s->avx2 holds the CPU's
** answer; the AVX2 leaf gives the SSE2 leaf's bits (refit_avx2.c). */
void ray__triangles_refit(ray_scene *s)
{
    ray__range_box_fn leaf = s->avx2 ? ray__refit_leaf_avx2() : NULL;

    ray__bvh_refit(&s->alloc, &s->tri_bvh, leaf != NULL ? leaf : refit_leaf,
                   s, s->n_live_tris, &s->scheduler, s->build_threads);
    s->float_exact = corners_are_floats(s);
}
