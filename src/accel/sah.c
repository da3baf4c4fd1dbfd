/* SPDX-License-Identifier: MIT */
/*
** sah.c -- splitting a node of a bounding volume hierarchy by the binned
** surface-area heuristic (Wald, "On fast Construction of SAH-based
** Bounding Volume Hierarchies", IEEE Symposium on Interactive Ray Tracing
** 2007): at each node the item centroids are dropped into BINS bins along
** each axis, and the split between two bins that minimises
**     C_trav + (A_left * N_left + A_right * N_right) / A_node
** is taken, unless a leaf (cost N, intersection cost 1) is cheaper.
** C_trav and the size below which a node is a leaf are the caller's
** (ray__bvh_costs: triangles and the costlier curved surfaces differ); a
** node that small still splits where it is sparse (sparse.c).
*/
#include <stdint.h>

#include "accel/builder.h"
#include "core/tasks.h"

#define BINS 16
#define MAX_LEAF 8       /* a node with more items is always split */

/* No split found yet among nb bins: any split's cost is lower. */
static split split_none(int nb)
{
    split none;

    none.axis = -1;
    none.bin = 0;
    none.bins = nb;
    none.cost = HUGE_VALF;
    none.cmin = 0;
    none.scale = 0;
    return none;
}

/* The scale that maps doubled centroids to nb bins along each axis: nb *
** (1 - eps) / extent keeps the largest centroid in range; a flat axis
** gets scale 0 (everything in bin 0, never split). */
static void bin_scales(const box *cb, int nb, float scale[3])
{
    int axis;

    for (axis = 0; axis < 3; axis++) {
        float extent = cb->hi[axis] - cb->lo[axis];
        scale[axis] = extent > 0 ? (float)nb * (1.0f - 1e-6f) / extent : 0;
    }
}

#if RAY__SSE2
#include <emmintrin.h>
#endif

#if RAY__SSE2
typedef struct bins4 bin_set;
#else
typedef struct bin_set bin_set;
#endif
static void bin_node(const builder *bd, size_t begin, size_t end,
                     const box *cb, const float scale[3], int nb,
                     bin_set *out);

#if RAY__SSE2

/* A ref's lo (or hi) in one register, the fourth lane (id, pad) zeroed:
** never arithmetic on it. */
static inline __m128 ref_lanes(const ref *r, size_t at)
{
    const __m128 xyz = _mm_castsi128_ps(_mm_set_epi32(0, -1, -1, -1));

    return _mm_and_ps(_mm_loadu_ps((const float *)(const void *)
                                   ((const char *)r + at)), xyz);
}

/*
** The bins with SSE, as registers: one holds a box's lo (or hi) on all
** three axes.  An item's three bins grow by one min and one max each,
** where the scalar loop (below, without SSE) does three of each; the bin
** indices of the three axes come from one subtraction, one product, one
** clamp and one conversion.  The arithmetic is bin_of's and box_grow's,
** lane for lane (minps / maxps pick as their "a < b ? a : b").
*/
typedef struct bins4 {
    __m128 lo[3][BINS], hi[3][BINS];
    int count[3][BINS];
} bins4;

/*
** The counts are zeroed in a loop of their own, not beside the boxes:
** GCC 12.2 at -O1 (Debian 12) deleted both calls of the one-loop form
** from bin_items, so the bins started from whatever the stack held --
** the tree then changed with the thread count and lost its single-item
** leaves (tests/check_bvh.c's threaded builds and regions test fail
** built with CFLAGS=-O1; -O0, -O2, -O3, -Os, -Og and clang -O1 kept
** the calls).  A standalone reproducer of the same loop shape shows the
** wrong sums at -O1 alone; the split loops give the right ones at every
** level.  make check-o1 (CI) runs the suite at -O1 to keep it so.
*/
static void bins4_empty(bins4 *bn, int nb)
{
    int axis, b;

    for (axis = 0; axis < 3; axis++)
        for (b = 0; b < nb; b++) {
            bn->lo[axis][b] = _mm_set1_ps(FLT_MAX);
            bn->hi[axis][b] = _mm_set1_ps(-FLT_MAX);
        }
    for (axis = 0; axis < 3; axis++)
        for (b = 0; b < nb; b++)
            bn->count[axis][b] = 0;
}

/*
** Drop refs[begin, end) into the first nb bins of each axis: the build's
** inner loop.  Items go in turn to two sets of bins, merged at the end:
** successive items of a mesh tend to fall in the same bin, and one set
** would chain every update of a bin on the one before (a store, a load
** and a min each), where two halve the chains -- for nodes of PAIRS_MIN
** items or more: below, emptying and merging the second set costs more
** than it saves.  The merge may order two
** zeros of opposite sign otherwise than one pass would; the boxes only
** give the bins' areas, whose values (and so the tree) are the same.
*/
#define PAIRS_MIN 64

/* The first nb bins of "more" merged into *out. */
static void bins_merge(bins4 *out, const bins4 *more, int nb)
{
    int axis, b;

    for (axis = 0; axis < 3; axis++)
        for (b = 0; b < nb; b++) {
            out->lo[axis][b] = _mm_min_ps(out->lo[axis][b], more->lo[axis][b]);
            out->hi[axis][b] = _mm_max_ps(out->hi[axis][b], more->hi[axis][b]);
            out->count[axis][b] += more->count[axis][b];
        }
}

/* One item, refs[i], dropped into its three bins of *bn (bin_items). */
static inline void bin_one(bins4 *bn, const ref *r, __m128 cmin, __m128 sc,
                           __m128 top)
{
    __m128 lo = ref_lanes(r, offsetof(ref, lo));
    __m128 hi = ref_lanes(r, offsetof(ref, hi));
    __m128 x = _mm_mul_ps(_mm_sub_ps(_mm_add_ps(lo, hi), cmin), sc);
    __m128i k;
    int k0, k1, k2;

    x = _mm_min_ps(_mm_max_ps(x, _mm_setzero_ps()), top);
    /* The bins, below BINS, from the low halves of the three lanes:
    ** no store and reload of the four indices. */
    k = _mm_cvttps_epi32(x);
    k0 = _mm_cvtsi128_si32(k);
    k1 = _mm_extract_epi16(k, 2);
    k2 = _mm_extract_epi16(k, 4);
    bn->lo[0][k0] = _mm_min_ps(bn->lo[0][k0], lo);
    bn->hi[0][k0] = _mm_max_ps(bn->hi[0][k0], hi);
    bn->count[0][k0]++;
    bn->lo[1][k1] = _mm_min_ps(bn->lo[1][k1], lo);
    bn->hi[1][k1] = _mm_max_ps(bn->hi[1][k1], hi);
    bn->count[1][k1]++;
    bn->lo[2][k2] = _mm_min_ps(bn->lo[2][k2], lo);
    bn->hi[2][k2] = _mm_max_ps(bn->hi[2][k2], hi);
    bn->count[2][k2]++;
}

static void bin_items(const builder *bd, size_t begin, size_t end,
                      const box *cb, const float scale[3], int nb,
                      bins4 *out)
{
    bins4 two;
    size_t i = begin;
    const __m128 cmin = _mm_set_ps(0, cb->lo[2], cb->lo[1], cb->lo[0]);
    const __m128 sc = _mm_set_ps(0, scale[2], scale[1], scale[0]);
    const __m128 top = _mm_set1_ps((float)(nb - 1));

    bins4_empty(out, nb);
    if (end - begin >= PAIRS_MIN) {
        /* Items at even offsets from begin into *out, odd ones into two:
        ** a pair a turn, without choosing the set item by item. */
        bins4_empty(&two, nb);
        for (; i + 1 < end; i += 2) {
            bin_one(out, &bd->refs[i], cmin, sc, top);
            bin_one(&two, &bd->refs[i + 1], cmin, sc, top);
        }
        if (i < end)
            bin_one(out, &bd->refs[i], cmin, sc, top);
        bins_merge(out, &two, nb);
        return;
    }
    for (; i < end; i++)
        bin_one(out, &bd->refs[i], cmin, sc, top);
}

/*
** box_area of four boxes at once, lane k of the result for box k (given
** as registers of lo and hi): the same operations in the same order, so
** the same floats.
*/
static inline __m128 area4(const __m128 *lo, const __m128 *hi)
{
    __m128 dx = _mm_sub_ps(hi[0], lo[0]), dy = _mm_sub_ps(hi[1], lo[1]);
    __m128 dz = _mm_sub_ps(hi[2], lo[2]), dw = _mm_sub_ps(hi[3], lo[3]);
    __m128 a;

    _MM_TRANSPOSE4_PS(dx, dy, dz, dw);
    a = _mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, dy), _mm_mul_ps(dy, dz)),
                   _mm_mul_ps(dz, dx));
    return _mm_and_ps(a, _mm_cmpge_ps(dx, _mm_setzero_ps()));
}

/*
** The best binned split of refs[begin, end), all three axes binned in one
** pass over the items; cb is the box of the doubled centroids.  A node of
** few items uses as many bins as items (at least 4): the sweep over 3 x 16
** bins would otherwise cost more than the items themselves.  The sweep
** takes the boxes on both sides of each of the nb - 1 candidate planes
** (running unions, one min and one max a step), then their areas and
** costs four planes at a time: the scalar sweep's arithmetic (without
** SSE, below), lane for lane, so the same costs and the same choice.
*/
static split best_split(const builder *bd, size_t begin, size_t end,
                        const box *cb, float node_area)
{
    bins4 bins;
    float scale[3];
    split best;
    size_t count = end - begin;
    int axis, b, nb = count >= BINS ? BINS : (count < 4 ? 4 : (int)count);
    const __m128 trav = _mm_set1_ps(bd->costs->traversal);
    const __m128 area = _mm_set1_ps(node_area);

    best = split_none(nb);
    bin_scales(cb, nb, scale);
    bin_node(bd, begin, end, cb, scale, nb, &bins);
    for (axis = 0; axis < 3; axis++) {
        /* Plane b (0 .. nb - 2) has bins 0 .. b on its left, the rest on
        ** its right; the entries after nb - 2, up to a multiple of four,
        ** are padding (empty). */
        __m128 llo[BINS], lhi[BINS], rlo[BINS], rhi[BINS];
        __m128 alo = _mm_set1_ps(FLT_MAX), ahi = _mm_set1_ps(-FLT_MAX);
        int lcount[BINS], rcount[BINS], n = 0;
        float cost[BINS];

        if (scale[axis] == 0)
            continue;
        for (b = nb - 1; b < ((nb + 2) & ~3); b++) {
            llo[b] = rlo[b] = alo;
            lhi[b] = rhi[b] = ahi;
            lcount[b] = rcount[b] = 0;
        }
        for (b = nb - 1; b > 0; b--) {
            alo = _mm_min_ps(alo, bins.lo[axis][b]);
            ahi = _mm_max_ps(ahi, bins.hi[axis][b]);
            n += bins.count[axis][b];
            rlo[b - 1] = alo;
            rhi[b - 1] = ahi;
            rcount[b - 1] = n;
        }
        alo = _mm_set1_ps(FLT_MAX);
        ahi = _mm_set1_ps(-FLT_MAX);
        n = 0;
        for (b = 0; b < nb - 1; b++) {
            alo = _mm_min_ps(alo, bins.lo[axis][b]);
            ahi = _mm_max_ps(ahi, bins.hi[axis][b]);
            n += bins.count[axis][b];
            llo[b] = alo;
            lhi[b] = ahi;
            lcount[b] = n;
        }
        for (b = 0; b < nb - 1; b += 4) {
            __m128 nl = _mm_cvtepi32_ps(_mm_loadu_si128(
                            (const __m128i *)(const void *)&lcount[b]));
            __m128 nr = _mm_cvtepi32_ps(_mm_loadu_si128(
                            (const __m128i *)(const void *)&rcount[b]));
            __m128 c = _mm_add_ps(trav, _mm_div_ps(
                _mm_add_ps(_mm_mul_ps(area4(&llo[b], &lhi[b]), nl),
                           _mm_mul_ps(area4(&rlo[b], &rhi[b]), nr)), area));
            _mm_storeu_ps(&cost[b], c);
        }
        for (b = 0; b < nb - 1; b++) {
            if (lcount[b] == 0 || rcount[b] == 0)
                continue;
            if (cost[b] < best.cost) {
                best.cost = cost[b];
                best.axis = axis;
                best.bin = b;
                best.cmin = cb->lo[axis];
                best.scale = scale[axis];
            }
        }
    }
    return best;
}
#else
typedef struct bin {
    box b;
    size_t count;
} bin;

/* The bin of doubled centroid c: clamped in float before the conversion
** (a NaN, from an infinite box, goes to bin 0), as the SSE binning does. */
static inline int bin_of(float c, float cmin, float scale, int bins)
{
    float x = (c - cmin) * scale, top = (float)(bins - 1);

    x = x > 0 ? x : 0;
    x = x < top ? x : top;
    return (int)x;
}

struct bin_set {
    bin b[3][BINS];
};

/* The first nb bins of "more" merged into *out. */
static void bins_merge(bin_set *out, const bin_set *more, int nb)
{
    int axis, b;

    for (axis = 0; axis < 3; axis++)
        for (b = 0; b < nb; b++) {
            box_grow(&out->b[axis][b].b, more->b[axis][b].b.lo,
                     more->b[axis][b].b.hi);
            out->b[axis][b].count += more->b[axis][b].count;
        }
}

/* Drop refs[begin, end) into the first nb bins of each axis (emptied
** first): the build's inner loop. */
static void bin_items(const builder *bd, size_t begin, size_t end,
                      const box *cb, const float scale[3], int nb,
                      bin_set *set)
{
    bin (*bins)[BINS] = set->b;
    size_t i;
    int axis, b;

    for (axis = 0; axis < 3; axis++)
        for (b = 0; b < nb; b++) {
            box_empty(&bins[axis][b].b);
            bins[axis][b].count = 0;
        }
    for (i = begin; i < end; i++) {
        const ref *r = &bd->refs[i];
        for (axis = 0; axis < 3; axis++) {
            bin *bn = &bins[axis][bin_of(centroid2(r, axis), cb->lo[axis],
                                         scale[axis], nb)];
            box_grow(&bn->b, r->lo, r->hi);
            bn->count++;
        }
    }
}

/* best_split without SSE: the SSE one's rules, one plane at a time. */
static split best_split(const builder *bd, size_t begin, size_t end,
                        const box *cb, float node_area)
{
    bin_set set;
    bin (*bins)[BINS] = set.b;
    float scale[3];
    split best;
    size_t count = end - begin;
    int axis, b, nb = count >= BINS ? BINS : (count < 4 ? 4 : (int)count);

    best = split_none(nb);
    bin_scales(cb, nb, scale);
    bin_node(bd, begin, end, cb, scale, nb, &set);
    for (axis = 0; axis < 3; axis++) {
        float right_area[BINS];
        size_t right_count[BINS], n_left = 0;
        box acc;

        if (scale[axis] == 0)
            continue;
        box_empty(&acc);
        right_count[nb - 1] = 0;
        for (b = nb - 1; b > 0; b--) {
            box_grow(&acc, bins[axis][b].b.lo, bins[axis][b].b.hi);
            right_count[b - 1] = right_count[b] + bins[axis][b].count;
            right_area[b - 1] = box_area(&acc);
        }
        box_empty(&acc);
        for (b = 0; b < nb - 1; b++) {
            float cost;
            box_grow(&acc, bins[axis][b].b.lo, bins[axis][b].b.hi);
            n_left += bins[axis][b].count;
            if (n_left == 0 || right_count[b] == 0)
                continue;
            cost = bd->costs->traversal +
                   (box_area(&acc) * (float)n_left +
                    right_area[b] * (float)right_count[b]) / node_area;
            if (cost < best.cost) {
                best.cost = cost;
                best.axis = axis;
                best.bin = b;
                best.cmin = cb->lo[axis];
                best.scale = scale[axis];
            }
        }
    }
    return best;
}
#endif

/*
** The bins of a large node on the build's threads (builder.threads,
** sched): its items in runs of BIN_RUN, each run binned by a task into a
** set of its own, the sets then merged in run order.  A bin's count is
** the same sum, and its box the same floats but perhaps for the sign of a
** zero (the merge's order), which no area sees: the same costs, the same
** split, the same tree at any thread count.  Only the top of the tree
** (build.c: the nodes split before the subtree tasks, every item binned
** once a level) runs on one thread otherwise: two fifths of a 940k
** build's time on two threads (issue 36).  A run binned by a task of its
** own costs a thread's start, tens of microseconds, where binning a run
** takes a few hundred.
*/
#define BIN_RUN 16384

/* The sets' alignment: SSE registers (bins4) are read and written with
** aligned loads and stores, and the scene's allocator promises no more
** than any block of its own (ray_alloc_fn): the block is taken that much
** larger and the sets start at the first multiple of it. */
#define BIN_ALIGN 16

/* May the builder's work run on threads (builder.threads, sched)? */
static int builder_parallel(const builder *bd)
{
    return bd->threads > 1 || (bd->sched != NULL && bd->sched->run != NULL);
}

typedef struct bin_job {
    const builder *bd;
    const box *cb;
    const float *scale;
    int nb;
    bin_set *sets;
} bin_job;

static void bin_run_task(void *ud, unsigned k, size_t begin, size_t end)
{
    const bin_job *job = ud;

    bin_items(job->bd, begin, end, job->cb, job->scale, job->nb,
              &job->sets[k]);
}

static void bin_node(const builder *bd, size_t begin, size_t end,
                     const box *cb, const float scale[3], int nb,
                     bin_set *out)
{
    size_t runs = (end - begin + BIN_RUN - 1) / BIN_RUN, k, bytes = 0;
    int parallel = builder_parallel(bd);
    unsigned char *raw = NULL;
    bin_job job;

    job.sets = NULL;
    if (parallel && runs >= 2 && runs <= 0xffffffffu &&
        (raw = ray__allocate(bd->alloc, bytes = runs * sizeof *job.sets +
                                                 BIN_ALIGN - 1)) != NULL)
        job.sets = (bin_set *)(void *)(raw + (BIN_ALIGN - (uintptr_t)raw %
                                                          BIN_ALIGN) %
                                                 BIN_ALIGN);
    if (job.sets == NULL) {                 /* one thread, or no memory */
        bin_items(bd, begin, end, cb, scale, nb, out);
        return;
    }
    job.bd = bd;
    job.cb = cb;
    job.scale = scale;
    job.nb = nb;
    /* runs fits a task number (tested above): every run is binned. */
    (void)ray__tasks_runs(bd->sched, bd->alloc, bd->threads, begin, end,
                          BIN_RUN, bin_run_task, &job);
    *out = job.sets[0];
    for (k = 1; k < runs; k++)
        bins_merge(out, &job.sets[k], nb);
    ray__release(bd->alloc, raw, bytes);
}

#if RAY__SSE2
/* Bounds as four registers (items' lo and hi, centroids' lo and hi);
** bounds4_grow is the plain version's box_grow twice, lane for lane. */
typedef struct bounds4 {
    __m128 lo, hi, clo, chi;
} bounds4;

static void bounds4_empty(bounds4 *b)
{
    b->lo = b->clo = _mm_set1_ps(FLT_MAX);
    b->hi = b->chi = _mm_set1_ps(-FLT_MAX);
}

static inline void bounds4_grow(bounds4 *b, const ref *r)
{
    __m128 lo = ref_lanes(r, offsetof(ref, lo));
    __m128 hi = ref_lanes(r, offsetof(ref, hi));
    __m128 c = _mm_add_ps(lo, hi);

    b->lo = _mm_min_ps(b->lo, lo);
    b->hi = _mm_max_ps(b->hi, hi);
    b->clo = _mm_min_ps(b->clo, c);
    b->chi = _mm_max_ps(b->chi, c);
}

/* b grown by bounds c (both boxes), lane for lane as bounds4_grow. */
static void bounds4_grow_bounds(bounds4 *b, const bounds *c)
{
    float v[4] = {0, 0, 0, 0};

    memcpy(v, c->items.lo, sizeof c->items.lo);
    b->lo = _mm_min_ps(b->lo, _mm_loadu_ps(v));
    memcpy(v, c->items.hi, sizeof c->items.hi);
    b->hi = _mm_max_ps(b->hi, _mm_loadu_ps(v));
    memcpy(v, c->centroids.lo, sizeof c->centroids.lo);
    b->clo = _mm_min_ps(b->clo, _mm_loadu_ps(v));
    memcpy(v, c->centroids.hi, sizeof c->centroids.hi);
    b->chi = _mm_max_ps(b->chi, _mm_loadu_ps(v));
}

static void bounds4_store(const bounds4 *b, bounds *out)
{
    float v[4];

    _mm_storeu_ps(v, b->lo);
    memcpy(out->items.lo, v, sizeof out->items.lo);
    _mm_storeu_ps(v, b->hi);
    memcpy(out->items.hi, v, sizeof out->items.hi);
    _mm_storeu_ps(v, b->clo);
    memcpy(out->centroids.lo, v, sizeof out->centroids.lo);
    _mm_storeu_ps(v, b->chi);
    memcpy(out->centroids.hi, v, sizeof out->centroids.hi);
}
#else
typedef bounds bounds4;

static void bounds4_empty(bounds4 *b)
{
    box_empty(&b->items);
    box_empty(&b->centroids);
}

static inline void bounds4_grow(bounds4 *b, const ref *r)
{
    float c[3];

    c[0] = centroid2(r, 0);
    c[1] = centroid2(r, 1);
    c[2] = centroid2(r, 2);
    box_grow(&b->items, r->lo, r->hi);
    box_grow(&b->centroids, c, c);
}

static void bounds4_grow_bounds(bounds4 *b, const bounds *c)
{
    box_grow(&b->items, c->items.lo, c->items.hi);
    box_grow(&b->centroids, c->centroids.lo, c->centroids.hi);
}

static void bounds4_store(const bounds4 *b, bounds *out)
{
    *out = *b;
}
#endif


/* Bounds by a pass over the items (halved runs; a run of records). */
static void bounds_of(const builder *bd, size_t begin, size_t end,
                      bounds *out)
{
    size_t i;
    bounds4 b;

    bounds4_empty(&b);
    for (i = begin; i < end; i++)
        bounds4_grow(&b, &bd->refs[i]);
    bounds4_store(&b, out);
}

/*
** The records of items begin .. end - 1: their boxes (box_of) and ids.
** On the build's threads when box_of allows (costs->box_threads: a
** triangle's box reads only the scene), in runs of BIN_RUN items, each
** run's records its own: a tenth of a 940k build, and a quarter of what
** the calling thread did alone on two threads (callgrind, issue 36).
*/
typedef struct refs_job {
    builder *bd;
    ray__box_fn box_of;
    const void *ud;
    bounds *runs;            /* each run's bounds, in item order */
} refs_job;

static void refs_fill(builder *bd, ray__box_fn box_of, const void *ud,
                      size_t begin, size_t end)
{
    size_t i;

    if (bd->costs->boxes != NULL)
        bd->costs->boxes(ud, begin, end, bd->refs + begin);
    for (i = begin; i < end; i++) {
        if (bd->costs->boxes == NULL)
            box_of(ud, i, bd->refs[i].lo, bd->refs[i].hi);
        bd->refs[i].id = (unsigned)i;
        bd->refs[i].pad = 0;
    }
}

static void refs_task(void *ud, unsigned k, size_t begin, size_t end)
{
    const refs_job *job = ud;

    refs_fill(job->bd, job->box_of, job->ud, begin, end);
    bounds_of(job->bd, begin, end, &job->runs[k]);
}

/* Records made a run at a time on one thread: 32 KB of them, in L1. */
#define REFS_RUN 1024

void ray__bvh_refs(builder *bd, ray__box_fn box_of, const void *ud,
                   size_t n, bounds *root)
{
    int parallel = bd->costs->box_threads && builder_parallel(bd);
    size_t runs = (n + BIN_RUN - 1) / BIN_RUN, i;
    refs_job job;
    bounds4 b;

    bounds4_empty(&b);
    job.bd = bd;
    job.box_of = box_of;
    job.ud = ud;
    job.runs = NULL;
    if (parallel && n > BIN_RUN &&
        (job.runs = ray__allocate(bd->alloc, runs * sizeof *job.runs)) !=
            NULL &&
        ray__tasks_runs(bd->sched, bd->alloc, bd->threads, 0, n, BIN_RUN,
                        refs_task, &job)) {
        /* The root's bounds from the runs' own, in run order: the same
        ** floats as one pass in item order (below), as min and max keep
        ** the later of two equal operands (ties: zeros of both signs),
        ** so a run's result, and then the later run's, is the item that
        ** pass keeps.  A pass of its own over the records after the
        ** runs was a twentieth of a 940k build on two threads, on the
        ** calling thread alone (issue 36). */
        for (i = 0; i < runs; i++)
            bounds4_grow_bounds(&b, &job.runs[i]);
    } else {
        /* The root's bounds as the records are made, a run at a time
        ** while the run's records are in the cache (bounds_of's
        ** operations in its order, without a pass of its own). */
        for (i = 0; i < n; i += REFS_RUN) {
            size_t j, end = n - i < REFS_RUN ? n : i + REFS_RUN;
            refs_fill(bd, box_of, ud, i, end);
            for (j = i; j < end; j++)
                bounds4_grow(&b, &bd->refs[j]);
        }
    }
    ray__release(bd->alloc, job.runs, runs * sizeof *job.runs);
    bounds4_store(&b, root);
}

/*
** Move the items of the split's left side to the front, gathering both
** sides' bounds on the way (so the children need no pass of their own);
** returns the first index of the right side.  An item goes left when its
** bin is at most sp->bin, i.e. when its unclamped bin coordinate is not
** >= sp->bin + 1 (the same test, without bin_of's clamp and conversion:
** a NaN goes to bin 0 there and left here).
*/
static size_t partition(builder *bd, size_t begin, size_t end,
                        const split *sp, bounds *left, bounds *right)
{
    size_t i = begin, j = end;
    float edge = (float)(sp->bin + 1);
    bounds4 l, r;

    bounds4_empty(&l);
    bounds4_empty(&r);
    while (i < j) {
        if (goes_left(&bd->refs[i], sp, edge)) {
            bounds4_grow(&l, &bd->refs[i]);
            i++;
        } else {
            ref t = bd->refs[i];
            bounds4_grow(&r, &t);
            bd->refs[i] = bd->refs[--j];
            bd->refs[j] = t;
        }
    }
    bounds4_store(&l, left);
    bounds4_store(&r, right);
    return i;
}

static void node_set_box(ray__node *n, const box *b)
{
    memcpy(n->lo, b->lo, sizeof n->lo);
    memcpy(n->hi, b->hi, sizeof n->hi);
}

/* Does a node of few items (a leaf by its count: costs->leaf_items)
** still split, and where (*sp)?  Where it is sparse (sparse.c). */
static int sparse_split(const builder *bd, const task *t, split *sp)
{
    float area = box_area(&t->b.items);

    if (!ray__bvh_has_gap(bd, t->begin, t->end, &t->b.items))
        return 0;
    *sp = best_split(bd, t->begin, t->end, &t->b.centroids, area);
    return sp->axis >= 0 &&
           ray__bvh_sides_sparse(bd, t->begin, t->end, sp, &t->b.items);
}

int ray__bvh_divide(builder *bd, const task *t, size_t *mid, bounds *left,
                    bounds *right)
{
    ray__node *n = &bd->nodes[t->node];
    size_t count = t->end - t->begin;
    split sp;

    node_set_box(n, &t->b.items);
    n->first = (unsigned)t->begin;
    n->count = (unsigned)count;
    if (t->depth >= MAX_DEPTH || count < 2)
        return 0;
    if (count <= bd->costs->leaf_items) {
        if (!sparse_split(bd, t, &sp))
            return 0;
    } else {
        sp = best_split(bd, t->begin, t->end, &t->b.centroids,
                        box_area(&t->b.items));
        if (sp.axis < 0) {
            /* All centroids coincide: no binned split separates them.
            ** Halve the run if it is too long for a leaf, else keep the
            ** leaf. */
            if (count <= MAX_LEAF)
                return 0;
            *mid = t->begin + count / 2;
            bounds_of(bd, t->begin, *mid, left);
            bounds_of(bd, *mid, t->end, right);
            return 2;
        }
        if (count <= MAX_LEAF && sp.cost >= (float)count)
            return 0;
    }
    *mid = partition(bd, t->begin, t->end, &sp, left, right);
    return 2;
}

void ray__bvh_link(builder *bd, const task *t, size_t mid,
                   const bounds *left, const bounds *right, task *stack)
{
    ray__node *n = &bd->nodes[t->node];

    n->first = (unsigned)bd->n_nodes;
    n->count = 0;
    child_task(&stack[0], bd->n_nodes, t->begin, mid, t->depth + 1, left);
    child_task(&stack[1], bd->n_nodes + 1, mid, t->end, t->depth + 1, right);
    bd->n_nodes += 2;
}

int ray__bvh_split(builder *bd, const task *t, task *stack)
{
    size_t mid;
    bounds left, right;

    if (!ray__bvh_divide(bd, t, &mid, &left, &right))
        return 0;
    ray__bvh_link(bd, t, mid, &left, &right, stack);
    return 2;
}
