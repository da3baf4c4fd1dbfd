/* SPDX-License-Identifier: MIT */
/*
** bvh.c -- building a bounding volume hierarchy with the binned
** surface-area heuristic (Wald, "On fast Construction of SAH-based
** Bounding Volume Hierarchies", IEEE Symposium on Interactive Ray Tracing
** 2007): at each node the item centroids are dropped into BINS bins along
** each axis, and the split between two bins that minimises
**     C_trav + (A_left * N_left + A_right * N_right) / A_node
** is taken, unless a leaf (cost N, intersection cost 1) is cheaper.
** C_trav and the size below which a node is always a leaf are the
** caller's (ray__bvh_costs: triangles and the costlier curved surfaces
** differ).
*/
#include <float.h>
#include <limits.h>
#include <pthread.h>
#include <stddef.h>
#include <string.h>
#include <unistd.h>

#include "accel/bvh.h"
#include "core/platform.h"

#define BINS 16
#define MAX_DEPTH 60     /* traversal stacks hold 64 levels */
#define MAX_LEAF 8       /* a node with more items is always split */

/*
** Builder records: an item's box and id, 32 bytes, permuted in place by
** the partitions so every pass over a node's items reads memory in order.
** The centroid is not stored: lo + hi (twice the centre) serves, since
** binning only needs an affine image of it.
*/
typedef struct ref {
    float lo[3];
    unsigned id;             /* lo and id, hi and pad: one SSE load each */
    float hi[3];
    unsigned pad;
} ref;

typedef struct box {
    float lo[3], hi[3];
} box;

static inline float fmin2(float a, float b)
{
    return a < b ? a : b;
}

static inline float fmax2(float a, float b)
{
    return a > b ? a : b;
}

static void box_empty(box *b)
{
    b->lo[0] = b->lo[1] = b->lo[2] = FLT_MAX;
    b->hi[0] = b->hi[1] = b->hi[2] = -FLT_MAX;
}

static inline void box_grow(box *b, const float *lo, const float *hi)
{
    b->lo[0] = fmin2(b->lo[0], lo[0]);
    b->lo[1] = fmin2(b->lo[1], lo[1]);
    b->lo[2] = fmin2(b->lo[2], lo[2]);
    b->hi[0] = fmax2(b->hi[0], hi[0]);
    b->hi[1] = fmax2(b->hi[1], hi[1]);
    b->hi[2] = fmax2(b->hi[2], hi[2]);
}

/* Half the surface area (the constant factor cancels in the SAH). */
static float box_area(const box *b)
{
    float dx = b->hi[0] - b->lo[0], dy = b->hi[1] - b->lo[1],
          dz = b->hi[2] - b->lo[2];
    if (!(dx >= 0))
        return 0;
    return dx * dy + dy * dz + dz * dx;
}

typedef struct builder {
    const ray__bvh_costs *costs;
    ref *refs;
    ray__node *nodes;
    size_t n_nodes;
} builder;

typedef struct split {
    int axis, bin;           /* items with bin index <= bin go left */
    int bins;                /* how many bins were used */
    float cost;
    float cmin, scale;       /* bin of c = (c - cmin) * scale */
} split;

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

/* Twice the centroid along "axis". */
static inline float centroid2(const ref *r, int axis)
{
    return r->lo[axis] + r->hi[axis];
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

#if defined(__SSE2__) && !defined(RAY_NO_SIMD)
#include <emmintrin.h>

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

static void bins4_empty(bins4 *bn, int nb)
{
    int axis, b;

    for (axis = 0; axis < 3; axis++)
        for (b = 0; b < nb; b++) {
            bn->lo[axis][b] = _mm_set1_ps(FLT_MAX);
            bn->hi[axis][b] = _mm_set1_ps(-FLT_MAX);
            bn->count[axis][b] = 0;
        }
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

static void bin_items(const builder *bd, size_t begin, size_t end,
                      const box *cb, const float scale[3], int nb,
                      bins4 *out)
{
    bins4 two;
    size_t i;
    const __m128 cmin = _mm_set_ps(0, cb->lo[2], cb->lo[1], cb->lo[0]);
    const __m128 sc = _mm_set_ps(0, scale[2], scale[1], scale[0]);
    const __m128 top = _mm_set1_ps((float)(nb - 1)), zero = _mm_setzero_ps();
    int axis, b, pairs = end - begin >= PAIRS_MIN;

    bins4_empty(out, nb);
    if (pairs)
        bins4_empty(&two, nb);
    for (i = begin; i < end; i++) {
        bins4 *bn = pairs && ((i - begin) & 1) ? &two : out;
        __m128 lo = ref_lanes(&bd->refs[i], offsetof(ref, lo));
        __m128 hi = ref_lanes(&bd->refs[i], offsetof(ref, hi));
        __m128 x = _mm_mul_ps(_mm_sub_ps(_mm_add_ps(lo, hi), cmin), sc);
        int k[4];
        x = _mm_min_ps(_mm_max_ps(x, zero), top);
        _mm_storeu_si128((__m128i *)(void *)k, _mm_cvttps_epi32(x));
        bn->lo[0][k[0]] = _mm_min_ps(bn->lo[0][k[0]], lo);
        bn->hi[0][k[0]] = _mm_max_ps(bn->hi[0][k[0]], hi);
        bn->count[0][k[0]]++;
        bn->lo[1][k[1]] = _mm_min_ps(bn->lo[1][k[1]], lo);
        bn->hi[1][k[1]] = _mm_max_ps(bn->hi[1][k[1]], hi);
        bn->count[1][k[1]]++;
        bn->lo[2][k[2]] = _mm_min_ps(bn->lo[2][k[2]], lo);
        bn->hi[2][k[2]] = _mm_max_ps(bn->hi[2][k[2]], hi);
        bn->count[2][k[2]]++;
    }
    for (axis = 0; axis < 3 && pairs; axis++)
        for (b = 0; b < nb; b++) {
            out->lo[axis][b] = _mm_min_ps(out->lo[axis][b], two.lo[axis][b]);
            out->hi[axis][b] = _mm_max_ps(out->hi[axis][b], two.hi[axis][b]);
            out->count[axis][b] += two.count[axis][b];
        }
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
    bin_items(bd, begin, end, cb, scale, nb, &bins);
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

/* Drop refs[begin, end) into the first nb bins of each axis (emptied
** first): the build's inner loop. */
static void bin_items(const builder *bd, size_t begin, size_t end,
                      const box *cb, const float scale[3], int nb,
                      bin bins[3][BINS])
{
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
    bin bins[3][BINS];
    float scale[3];
    split best;
    size_t count = end - begin;
    int axis, b, nb = count >= BINS ? BINS : (count < 4 ? 4 : (int)count);

    best = split_none(nb);
    bin_scales(cb, nb, scale);
    bin_items(bd, begin, end, cb, scale, nb, bins);
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

/* The boxes a node needs before it is split: its items' box and the box
** of their doubled centroids. */
typedef struct bounds {
    box items, centroids;
} bounds;

#if defined(__SSE2__) && !defined(RAY_NO_SIMD)
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

static void bounds4_store(const bounds4 *b, bounds *out)
{
    *out = *b;
}
#endif

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
        float x = (centroid2(&bd->refs[i], sp->axis) - sp->cmin) * sp->scale;
        if (!(x >= edge)) {
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

/* Bounds by a pass over the items (halved runs). */
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

static void node_set_box(ray__node *n, const box *b)
{
    memcpy(n->lo, b->lo, sizeof n->lo);
    memcpy(n->hi, b->hi, sizeof n->hi);
}

typedef struct task {
    size_t node, begin, end;
    unsigned depth;
    bounds b;
} task;

/* Push the task of a child node over refs[begin, end). */
static void child_task(task *t, size_t node, size_t begin, size_t end,
                       unsigned depth, const bounds *b)
{
    t->node = node;
    t->begin = begin;
    t->end = end;
    t->depth = depth;
    t->b = *b;
}

/*
** Split node "t.node" (items refs[begin, end), bounds t.b) or make it a
** leaf; children are pushed on the task stack.  Returns how many.
*/
static int build_node(builder *bd, const task *t, task *stack)
{
    ray__node *n = &bd->nodes[t->node];
    size_t count = t->end - t->begin, mid;
    bounds left, right;
    split sp;

    node_set_box(n, &t->b.items);
    n->first = (unsigned)t->begin;
    n->count = (unsigned)count;
    if (count <= bd->costs->leaf_items || t->depth >= MAX_DEPTH)
        return 0;
    sp = best_split(bd, t->begin, t->end, &t->b.centroids,
                    box_area(&t->b.items));
    if (sp.axis < 0) {
        /* All centroids coincide: no binned split separates them.  Halve
        ** the run if it is too long for a leaf, else keep the leaf. */
        if (count <= MAX_LEAF)
            return 0;
        mid = t->begin + count / 2;
        bounds_of(bd, t->begin, mid, &left);
        bounds_of(bd, mid, t->end, &right);
    } else {
        if (count <= MAX_LEAF && sp.cost >= (float)count)
            return 0;
        mid = partition(bd, t->begin, t->end, &sp, &left, &right);
    }
    n->first = (unsigned)bd->n_nodes;
    n->count = 0;
    child_task(&stack[0], bd->n_nodes, t->begin, mid, t->depth + 1, &left);
    child_task(&stack[1], bd->n_nodes + 1, mid, t->end, t->depth + 1, &right);
    bd->n_nodes += 2;
    return 2;
}

void ray__bvh_free(const ray__allocator *a, ray__bvh *bvh)
{
    ray__release(a, bvh->nodes, bvh->cap_nodes * sizeof *bvh->nodes);
    ray__release(a, bvh->wide, bvh->cap_wide * sizeof *bvh->wide);
    ray__release(a, bvh->items, bvh->n_items * sizeof *bvh->items);
    ray__release(a, bvh->leaves, bvh->n_leaves * sizeof *bvh->leaves);
    memset(bvh, 0, sizeof *bvh);
}

/* ------------------------------------------------------- wide collapse */

static float node_area(const ray__node *n)
{
    box b;
    memcpy(b.lo, n->lo, sizeof b.lo);
    memcpy(b.hi, n->hi, sizeof b.hi);
    return box_area(&b);
}

/* Is binary node n an inner node, opened by the collapse? */
static int opens(const ray__node *n)
{
    return n->count == 0;
}

/*
** The up to RAY__WIDTH binary nodes that become the children of the wide
** node for binary node "n": start from its two children and open the
** inner one of largest surface area until there are RAY__WIDTH or only
** leaves remain (the usual greedy collapse: the largest boxes are the
** likeliest to be hit, so they gain most from being tested together).
** Returns how many.
*/
static int gather_children(const ray__node *nodes, unsigned n,
                           unsigned out[RAY__WIDTH])
{
    float area[RAY__WIDTH];      /* out[i]'s, taken once */
    int k = 2;

    out[0] = nodes[n].first;
    out[1] = nodes[n].first + 1;
    area[0] = node_area(&nodes[out[0]]);
    area[1] = node_area(&nodes[out[1]]);
    while (k < RAY__WIDTH) {
        int best = -1, i;
        float best_area = -1;
        for (i = 0; i < k; i++)
            if (opens(&nodes[out[i]]) && area[i] > best_area) {
                best_area = area[i];
                best = i;
            }
        if (best < 0)
            break;
        out[k] = nodes[out[best]].first + 1;
        out[best] = nodes[out[best]].first;
        area[k] = node_area(&nodes[out[k]]);
        area[best] = node_area(&nodes[out[best]]);
        k++;
    }
    return k;
}

static void slot_set(ray__wnode *q, int k, const ray__node *c)
{
    int a;
    for (a = 0; a < 3; a++) {
        q->lo[a][k] = c->lo[a];
        q->hi[a][k] = c->hi[a];
    }
}

static void slot_empty(ray__wnode *q, int k)
{
    int a;
    for (a = 0; a < 3; a++) {
        q->lo[a][k] = HUGE_VALF;
        q->hi[a][k] = -HUGE_VALF;
    }
    q->child[k] = 0;
    q->count[k] = RAY__LEAF;            /* a leaf of no items */
}

/*
** Room in the wide nodes for one more node's children (RAY__WIDTH), the
** array grown by half when full.  RAY_OK or RAY_ENOMEM (*w kept).
*/
static int wide_room(const ray__allocator *a, ray__wnode **w, size_t *cap,
                     size_t used)
{
    size_t more = *cap + *cap / 2 + RAY__WIDTH;
    ray__wnode *grown;

    if (*cap - used >= RAY__WIDTH)
        return RAY_OK;
    grown = ray__reallocate(a, *w, *cap * sizeof **w, more * sizeof **w);
    if (grown == NULL)
        return RAY_ENOMEM;
    *w = grown;
    *cap = more;
    return RAY_OK;
}

/*
** Collapse the binary BVH into wide nodes.  The children of a wide node
** are numbered consecutively, depth first.  The array starts at a sixth
** of the binary nodes (the bunnies need a seventh to an eighth), grows by
** half when full and is trimmed to its size at the end: one walk of the
** tree, where counting first took two.
*/
static int collapse(const ray__allocator *a, ray__bvh *bvh)
{
    size_t cap = bvh->n_nodes / 6 + RAY__WIDTH, used = 1;
    /* (binary node, wide node): RAY__WIDTH - 1 per level, 64 levels */
    unsigned stack[RAY__WIDTH * 64][2];
    ray__wnode *w = ray__allocate(a, cap * sizeof *w), *trimmed;
    int sp = 0;

    if (w == NULL)
        return RAY_ENOMEM;
    if (!opens(&bvh->nodes[0])) {         /* the root is a leaf */
        int k;
        for (k = 1; k < RAY__WIDTH; k++)
            slot_empty(&w[0], k);
        slot_set(&w[0], 0, &bvh->nodes[0]);
        w[0].child[0] = bvh->nodes[0].first;
        w[0].count[0] = RAY__LEAF | bvh->nodes[0].count;
    } else {
        stack[0][0] = 0;
        stack[0][1] = 0;
        sp = 1;
    }
    while (sp > 0) {
        unsigned n = stack[--sp][0], qi = stack[sp][1], kids[RAY__WIDTH];
        int k, m = gather_children(bvh->nodes, n, kids);
        ray__wnode *q;
        if (wide_room(a, &w, &cap, used) != RAY_OK) {
            ray__release(a, w, cap * sizeof *w);
            return RAY_ENOMEM;
        }
        q = &w[qi];
        for (k = 0; k < RAY__WIDTH; k++) {
            const ray__node *c;
            if (k >= m) {
                slot_empty(q, k);
                continue;
            }
            c = &bvh->nodes[kids[k]];
            slot_set(q, k, c);
            if (!opens(c)) {
                q->child[k] = c->first;
                q->count[k] = RAY__LEAF | c->count;
            } else {
                q->child[k] = (unsigned)used;
                q->count[k] = 0;
                stack[sp][0] = kids[k];
                stack[sp++][1] = (unsigned)used++;
            }
        }
    }
    trimmed = ray__reallocate(a, w, cap * sizeof *w, used * sizeof *w);
    if (trimmed != NULL) {               /* else keep the larger block */
        w = trimmed;
        cap = used;
    }
    bvh->wide = w;
    bvh->n_wide = used;
    bvh->cap_wide = cap;
    ray__release(a, bvh->nodes, bvh->cap_nodes * sizeof *bvh->nodes);
    bvh->nodes = NULL;
    bvh->n_nodes = bvh->cap_nodes = 0;
    return RAY_OK;
}

/* ------------------------------------------------------ threaded build */

/*
** The threaded build.  The top of the tree is split on the calling thread,
** depth first as ever, until every node left has at most top_limit(n)
** items; those nodes become subtree tasks, numbered in the order the top
** phase reaches them, and task j builds into its own run of the node
** array, from region[j] on (2 m - 2 nodes at most below its root for m
** items, so the runs fit in the 2 n - 1 a binary tree needs: the top's
** L leaves take 2 L - 1, their runs 2 n - 2 L).  Each task works on its
** own items (a contiguous range of refs) and its own nodes, so the
** threads share nothing but the counter that hands out tasks, and what a
** task writes does not depend on which thread ran it or when: the tree,
** its item order and every float are the same at any thread count.  The
** runs are then closed up in task order (their links moved with them),
** so the node array shrinks to what the tree uses before the collapse
** allocates the wide nodes, as in the plain build.
** The splits are those of the plain depth-first build (the same code on
** the same items), so the wide tree is too.
*/

/* Subtrees of at most n / TOP_SHARE items (and at least TOP_MIN): enough
** tasks for dynamic scheduling to even out, whatever the thread count
** (the rule must not depend on it), and few enough that the top stays
** a small part of the work. */
#define TOP_SHARE 64
#define TOP_MIN 4096

static size_t top_limit(size_t n)
{
    return n / TOP_SHARE > TOP_MIN ? n / TOP_SHARE : TOP_MIN;
}

typedef struct subtree {
    task root;               /* its root node (in the top) and its items */
    size_t region;           /* where its other nodes go */
    size_t used;             /* how many it made there */
} subtree;

typedef struct build_job {
    const ray__bvh_costs *costs;
    ref *refs;
    ray__node *nodes;
    subtree *tasks;
    const size_t *order;     /* tasks by size, largest first */
    size_t n_tasks;
    pthread_mutex_t lock;    /* guards next (threaded runs only) */
    size_t next;
} build_job;

/* Build one subtree, depth first, into its region. */
static void build_subtree(const build_job *job, subtree *st)
{
    builder bd;
    task stack[2 * MAX_DEPTH + 4];
    int sp = 1;

    bd.costs = job->costs;
    bd.refs = job->refs;
    bd.nodes = job->nodes;
    bd.n_nodes = st->region;
    stack[0] = st->root;
    while (sp > 0) {
        task t = stack[--sp];
        sp += build_node(&bd, &t, stack + sp);
    }
    st->used = bd.n_nodes - st->region;
}

static void *build_worker(void *arg)
{
    build_job *job = arg;

    for (;;) {
        size_t k;
        pthread_mutex_lock(&job->lock);
        k = job->next++;
        pthread_mutex_unlock(&job->lock);
        if (k >= job->n_tasks)
            return NULL;
        build_subtree(job, &job->tasks[job->order[k]]);
    }
}

/* Larger subtrees first: the last task to start is then a small one, and
** the threads finish close together. */
static void order_by_size(const subtree *tasks, size_t n, size_t *order)
{
    size_t i, j;

    for (i = 0; i < n; i++) {
        size_t m = tasks[i].root.end - tasks[i].root.begin;
        for (j = i; j > 0; j--) {
            const task *o = &tasks[order[j - 1]].root;
            if (o->end - o->begin >= m)
                break;
            order[j] = order[j - 1];
        }
        order[j] = i;
    }
}

/*
** Run the subtree tasks on "threads" threads (the caller's included):
** fewer if a thread cannot be started or the job's mutex cannot be made
** (then the caller builds them all), the same tree either way.  Thread
** handles live in a small array on the stack, in batches, so that no
** allocation is needed here.
*/
#define THREAD_BATCH 64

static void run_subtrees(build_job *job, unsigned threads)
{
    pthread_t tid[THREAD_BATCH];
    int started[THREAD_BATCH];
    unsigned i, n = 0;

    job->next = 0;
    if (threads > THREAD_BATCH)
        threads = THREAD_BATCH;
    if (threads > job->n_tasks)
        threads = (unsigned)job->n_tasks;
    if (threads > 1 && pthread_mutex_init(&job->lock, NULL) == 0) {
        n = threads - 1;
        for (i = 0; i < n; i++)
            started[i] = pthread_create(&tid[i], NULL, build_worker,
                                        job) == 0;
        build_worker(job);
        for (i = 0; i < n; i++)
            if (started[i])
                pthread_join(tid[i], NULL);
        pthread_mutex_destroy(&job->lock);
        return;
    }
    for (i = 0; i < job->n_tasks; i++)
        build_subtree(job, &job->tasks[job->order[i]]);
}

/*
** Close up the subtrees' runs, in task order, from node "at" on: a run
** moves down by the gaps before it, and so do the links into it (its
** inner nodes' and its root's).  Returns the node count.
*/
static size_t close_up(ray__node *nodes, const subtree *tasks,
                       size_t n_tasks, size_t at)
{
    size_t j, k;

    for (j = 0; j < n_tasks; j++) {
        const subtree *st = &tasks[j];
        unsigned shift = (unsigned)(st->region - at);
        ray__node *root = &nodes[st->root.node];
        if (shift != 0 && st->used > 0) {
            memmove(&nodes[at], &nodes[st->region],
                    st->used * sizeof *nodes);
            for (k = at; k < at + st->used; k++)
                if (nodes[k].count == 0)
                    nodes[k].first -= shift;
            if (root->count == 0)
                root->first -= shift;
        }
        at += st->used;
    }
    return at;
}

int ray__bvh_build(const ray__allocator *a, ray__box_fn box_of,
                   const void *ud, size_t n, const ray__bvh_costs *costs,
                   unsigned threads, ray__bvh *out)
{
    builder bd;
    task stack[2 * MAX_DEPTH + 4];
    size_t cap, i, limit, region, n_tasks = 0, cap_tasks = 0;
    subtree *tasks = NULL;
    size_t *order = NULL;
    unsigned *items;
    int sp = 0, rc = RAY_OK;

    memset(out, 0, sizeof *out);
    if (n == 0)
        return RAY_OK;
    if (n > 0x7fffffffu)
        return RAY_ENOMEM;
    cap = 2 * n - 1;                         /* a binary tree's bound */
    bd.costs = costs;
    bd.refs = ray__allocate(a, n * sizeof *bd.refs);
    bd.nodes = ray__allocate(a, cap * sizeof *bd.nodes);
    items = ray__allocate(a, n * sizeof *items);
    if (bd.refs == NULL || bd.nodes == NULL || items == NULL) {
        rc = RAY_ENOMEM;
        goto done;
    }
    {
        /* The root's bounds as the records are made (bounds_of's
        ** operations in its order, without a pass of its own). */
        bounds root;
        bounds4 b;
        bounds4_empty(&b);
        for (i = 0; i < n; i++) {
            box_of(ud, i, bd.refs[i].lo, bd.refs[i].hi);
            bd.refs[i].id = (unsigned)i;
            bd.refs[i].pad = 0;
            bounds4_grow(&b, &bd.refs[i]);
        }
        bounds4_store(&b, &root);
        bd.n_nodes = 1;
        child_task(&stack[0], 0, 0, n, 0, &root);
    }
    sp = 1;
    /* The top, depth first: the stack never holds more than two tasks per
    ** level.  A node small enough becomes a subtree task. */
    limit = top_limit(n);
    while (sp > 0) {
        task t = stack[--sp];
        if (t.end - t.begin > limit) {
            sp += build_node(&bd, &t, stack + sp);
            continue;
        }
        if (n_tasks == cap_tasks) {
            size_t more = cap_tasks ? 2 * cap_tasks : 2 * TOP_SHARE;
            subtree *grown = ray__reallocate(a, tasks,
                                             cap_tasks * sizeof *tasks,
                                             more * sizeof *tasks);
            if (grown == NULL) {
                rc = RAY_ENOMEM;
                goto done;
            }
            tasks = grown;
            cap_tasks = more;
        }
        tasks[n_tasks++].root = t;
    }
    if (n_tasks > 0) {
        order = ray__allocate(a, n_tasks * sizeof *order);
        if (order == NULL) {
            rc = RAY_ENOMEM;
            goto done;
        }
        region = bd.n_nodes;
        for (i = 0; i < n_tasks; i++) {
            tasks[i].region = region;
            region += 2 * (tasks[i].root.end - tasks[i].root.begin) - 2;
        }
        order_by_size(tasks, n_tasks, order);
        {
            build_job job;
            job.costs = costs;
            job.refs = bd.refs;
            job.nodes = bd.nodes;
            job.tasks = tasks;
            job.order = order;
            job.n_tasks = n_tasks;
            run_subtrees(&job, threads ? threads : ray__online_cpus());
        }
    }
    for (i = 0; i < n; i++)
        items[i] = bd.refs[i].id;
    bd.n_nodes = close_up(bd.nodes, tasks, n_tasks, bd.n_nodes);
    /* Before the collapse allocates: the peak stays where it was. */
    ray__release(a, order, n_tasks * sizeof *order);
    ray__release(a, tasks, cap_tasks * sizeof *tasks);
    ray__release(a, bd.refs, n * sizeof *bd.refs);
    order = NULL;
    tasks = NULL;
    bd.refs = NULL;
    out->nodes = ray__reallocate(a, bd.nodes, cap * sizeof *bd.nodes,
                                 bd.n_nodes * sizeof *bd.nodes);
    out->cap_nodes = bd.n_nodes;
    if (out->nodes == NULL) {            /* shrinking failed: keep it all */
        out->nodes = bd.nodes;
        out->cap_nodes = cap;
    }
    out->n_nodes = bd.n_nodes;
    out->items = items;
    out->n_items = n;
    bd.nodes = NULL;
    items = NULL;
    if (collapse(a, out) != RAY_OK) {
        ray__bvh_free(a, out);
        rc = RAY_ENOMEM;
    }
done:
    ray__release(a, order, n_tasks * sizeof *order);
    ray__release(a, tasks, cap_tasks * sizeof *tasks);
    ray__release(a, bd.refs, n * sizeof *bd.refs);
    ray__release(a, bd.nodes, cap * sizeof *bd.nodes);
    ray__release(a, items, n * sizeof *items);
    return rc;
}

/* Slot k of node q fitted to box b. */
static void slot_fit(ray__wnode *q, int k, const box *b)
{
    int a;

    for (a = 0; a < 3; a++) {
        q->lo[a][k] = b->lo[a];
        q->hi[a][k] = b->hi[a];
    }
}

/*
** The leaf slots listed by their first item (node * RAY__WIDTH + slot),
** kept in bvh->leaves: the leaves of a wide node sit wherever the
** collapse numbered them, so visiting them node by node reads the items
** (the triangles, 72 bytes each) in a scattered order that misses the
** cache at every leaf, where this list reads them as they lie.  Made
** once, through a temporary array of n_items (the slot starting at each
** item); 0 if memory is short (the caller then goes node by node).
*/
static int leaves_in_order(const ray__allocator *a, ray__bvh *bvh,
                           size_t n_items)
{
    unsigned *at, *list;
    size_t w, i, n = 0;
    int k;

    if (bvh->leaves != NULL)
        return 1;
    if (n_items == 0 || bvh->n_wide > 0xffffffffu / RAY__WIDTH)
        return 0;
    at = ray__allocate(a, n_items * sizeof *at);
    if (at == NULL)
        return 0;
    for (i = 0; i < n_items; i++)
        at[i] = 0xffffffffu;
    for (w = 0; w < bvh->n_wide; w++)
        for (k = 0; k < RAY__WIDTH; k++) {
            const ray__wnode *q = &bvh->wide[w];
            if (q->count[k] != 0 && (q->count[k] & ~RAY__LEAF) != 0 &&
                q->child[k] < n_items) {
                at[q->child[k]] = (unsigned)(w * RAY__WIDTH + (size_t)k);
                n++;
            }
        }
    list = ray__allocate(a, n * sizeof *list);
    if (list != NULL) {
        size_t j = 0;
        for (i = 0; i < n_items; i++)
            if (at[i] != 0xffffffffu)
                list[j++] = at[i];
        bvh->leaves = list;
        bvh->n_leaves = n;
    }
    ray__release(a, at, n_items * sizeof *at);
    return list != NULL;
}

/* The leaf slots refitted in the order of their items. */
static int refit_leaves_in_order(const ray__allocator *a, ray__bvh *bvh,
                                 ray__range_box_fn range_box, const void *ud,
                                 size_t n_items)
{
    size_t i;

    if (!leaves_in_order(a, bvh, n_items))
        return 0;
    for (i = 0; i < bvh->n_leaves; i++) {
        ray__wnode *q = &bvh->wide[bvh->leaves[i] / RAY__WIDTH];
        int slot = (int)(bvh->leaves[i] % RAY__WIDTH);
        box b;
        range_box(ud, q->child[slot], q->count[slot] & ~RAY__LEAF, b.lo,
                  b.hi);
        slot_fit(q, slot, &b);
    }
    return 1;
}

/*
** Wide nodes are numbered so that every child comes after its parent
** (collapse numbers them as it goes), so one pass from the last node to
** the first sees every child refitted before its parent.
*/
void ray__bvh_refit(const ray__allocator *a, ray__bvh *bvh,
                    ray__range_box_fn range_box, const void *ud,
                    size_t n_items)
{
    int leaves_done = refit_leaves_in_order(a, bvh, range_box, ud, n_items);
    size_t w = bvh->n_wide;

    while (w-- > 0) {
        ray__wnode *q = &bvh->wide[w];
        int k, j, ax;
        for (k = 0; k < RAY__WIDTH; k++) {
            box b;
            if (q->count[k] == 0) {               /* an inner node */
                const ray__wnode *c = &bvh->wide[q->child[k]];
                box_empty(&b);
                for (j = 0; j < RAY__WIDTH; j++) {
                    float lo[3], hi[3];
                    for (ax = 0; ax < 3; ax++) {
                        lo[ax] = c->lo[ax][j];
                        hi[ax] = c->hi[ax][j];
                    }
                    box_grow(&b, lo, hi);
                }
                slot_fit(q, k, &b);
            } else if (!leaves_done && (q->count[k] & ~RAY__LEAF) != 0) {
                range_box(ud, q->child[k], q->count[k] & ~RAY__LEAF, b.lo,
                          b.hi);
                slot_fit(q, k, &b);
            }
        }
    }
}
