/*
** bvh.c -- building a bounding volume hierarchy with the binned
** surface-area heuristic (Wald, "On fast Construction of SAH-based
** Bounding Volume Hierarchies", IEEE Symposium on Interactive Ray Tracing
** 2007): at each node the item centroids are dropped into BINS bins along
** each axis, and the split between two bins that minimises
**     C_trav + (A_left * N_left + A_right * N_right) / A_node
** is taken, unless a leaf (cost N, intersection cost 1) is cheaper.
*/
#include <float.h>
#include <string.h>

#include "internal.h"

#define BINS 16
#define MAX_LEAF 8       /* a node with more items is always split */
#define MAX_DEPTH 60     /* traversal stacks hold 64 entries */
#define TRAVERSAL_COST 1.0f  /* relative to one primitive test (pbrt: 1/8
                                for a SIMD-less triangle; we measured 1 to
                                build faster, shallower trees for double
                                Cramer tests) */

float ray__float_down(double x)
{
    float f = (float)x;
    return (double)f > x ? nextafterf(f, -HUGE_VALF) : f;
}

float ray__float_up(double x)
{
    float f = (float)x;
    return (double)f < x ? nextafterf(f, HUGE_VALF) : f;
}

typedef struct box {
    float lo[3], hi[3];
} box;

static void box_empty(box *b)
{
    int k;
    for (k = 0; k < 3; k++) {
        b->lo[k] = FLT_MAX;
        b->hi[k] = -FLT_MAX;
    }
}

static void box_grow(box *b, const float *lohi)
{
    int k;
    for (k = 0; k < 3; k++) {
        if (lohi[k] < b->lo[k])
            b->lo[k] = lohi[k];
        if (lohi[3 + k] > b->hi[k])
            b->hi[k] = lohi[3 + k];
    }
}

static void box_merge(box *b, const box *o)
{
    box_grow(b, o->lo);     /* lo[3] and hi[3] are contiguous */
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
    const float *boxes;      /* 6 per item */
    float *centroids;        /* 3 per item, box centres */
    unsigned *ids;
    ray__node *nodes;
    size_t n_nodes;
} builder;

typedef struct split {
    int axis, bin;           /* items with bin index <= bin go left */
    float cost;
    float cmin, scale;       /* bin of c = (c - cmin) * scale */
} split;

static int bin_of(float c, float cmin, float scale)
{
    int b = (int)((c - cmin) * scale);
    return b < 0 ? 0 : (b >= BINS ? BINS - 1 : b);
}

/* The best binned split of ids[begin, end) along each axis. */
static split best_split(const builder *bd, size_t begin, size_t end,
                        const box *cb, float node_area)
{
    split best;
    int axis;

    best.axis = -1;
    best.bin = 0;
    best.cost = HUGE_VALF;
    best.cmin = 0;
    best.scale = 0;
    for (axis = 0; axis < 3; axis++) {
        float extent = cb->hi[axis] - cb->lo[axis], scale, right_area[BINS];
        box bins[BINS], acc;
        size_t count[BINS], right_count[BINS], n_left = 0, i;
        int b;

        if (!(extent > 0))
            continue;
        /* BINS * (1 - eps) / extent keeps the largest centroid in range. */
        scale = (float)BINS * (1.0f - 1e-6f) / extent;
        for (b = 0; b < BINS; b++) {
            box_empty(&bins[b]);
            count[b] = 0;
        }
        for (i = begin; i < end; i++) {
            unsigned id = bd->ids[i];
            b = bin_of(bd->centroids[3 * (size_t)id + (size_t)axis], cb->lo[axis], scale);
            box_grow(&bins[b], bd->boxes + 6 * (size_t)id);
            count[b]++;
        }
        box_empty(&acc);
        right_count[BINS - 1] = 0;
        for (b = BINS - 1; b > 0; b--) {
            box_merge(&acc, &bins[b]);
            right_count[b - 1] = (b < BINS - 1 ? right_count[b] : 0) + count[b];
            right_area[b - 1] = box_area(&acc);
        }
        box_empty(&acc);
        for (b = 0; b < BINS - 1; b++) {
            float cost;
            box_merge(&acc, &bins[b]);
            n_left += count[b];
            if (n_left == 0 || right_count[b] == 0)
                continue;
            cost = TRAVERSAL_COST +
                   (box_area(&acc) * (float)n_left +
                    right_area[b] * (float)right_count[b]) / node_area;
            if (cost < best.cost) {
                best.cost = cost;
                best.axis = axis;
                best.bin = b;
                best.cmin = cb->lo[axis];
                best.scale = scale;
            }
        }
    }
    return best;
}

/* Move the items of the split's left side to the front; returns the
** first index of the right side. */
static size_t partition(builder *bd, size_t begin, size_t end, const split *sp)
{
    size_t i = begin, j = end;

    while (i < j) {
        unsigned id = bd->ids[i];
        if (bin_of(bd->centroids[3 * (size_t)id + (size_t)sp->axis], sp->cmin, sp->scale) <=
            sp->bin) {
            i++;
        } else {
            bd->ids[i] = bd->ids[--j];
            bd->ids[j] = id;
        }
    }
    return i;
}

static void node_set_box(ray__node *n, const box *b)
{
    memcpy(n->lo, b->lo, sizeof n->lo);
    memcpy(n->hi, b->hi, sizeof n->hi);
}

typedef struct task {
    size_t node, begin, end;
    unsigned depth;
} task;

/*
** Split node "t.node" (items ids[begin, end)) or make it a leaf; children
** are pushed on the task stack.  Returns the number of tasks pushed.
*/
static int build_node(builder *bd, task t, task *stack)
{
    ray__node *n = &bd->nodes[t.node];
    size_t count = t.end - t.begin, i, mid;
    box nb, cb;
    split sp;

    box_empty(&nb);
    box_empty(&cb);
    for (i = t.begin; i < t.end; i++) {
        unsigned id = bd->ids[i];
        const float *c = bd->centroids + 3 * (size_t)id;
        float cc[6];
        box_grow(&nb, bd->boxes + 6 * (size_t)id);
        cc[0] = cc[3] = c[0];
        cc[1] = cc[4] = c[1];
        cc[2] = cc[5] = c[2];
        box_grow(&cb, cc);
    }
    node_set_box(n, &nb);
    n->first = (unsigned)t.begin;
    n->count = (unsigned)count;
    if (count <= 1 || t.depth >= MAX_DEPTH)
        return 0;
    sp = best_split(bd, t.begin, t.end, &cb, box_area(&nb));
    if (sp.axis < 0) {
        /* All centroids coincide: no binned split separates them.  Halve
        ** the run if it is too long for a leaf, else keep the leaf. */
        if (count <= MAX_LEAF)
            return 0;
        mid = t.begin + count / 2;
    } else {
        if (count <= MAX_LEAF && sp.cost >= (float)count)
            return 0;
        mid = partition(bd, t.begin, t.end, &sp);
    }
    n->first = (unsigned)bd->n_nodes;
    n->count = 0;
    stack[0].node = bd->n_nodes;
    stack[0].begin = t.begin;
    stack[0].end = mid;
    stack[0].depth = t.depth + 1;
    stack[1].node = bd->n_nodes + 1;
    stack[1].begin = mid;
    stack[1].end = t.end;
    stack[1].depth = t.depth + 1;
    bd->n_nodes += 2;
    return 2;
}

void ray__bvh_free(const ray_scene *s, ray__bvh *bvh)
{
    ray__free(s, bvh->nodes, bvh->cap_nodes * sizeof *bvh->nodes);
    ray__free(s, bvh->items, bvh->n_items * sizeof *bvh->items);
    memset(bvh, 0, sizeof *bvh);
}

int ray__bvh_build(const ray_scene *s, const float *boxes, size_t n,
                   ray__bvh *out)
{
    builder bd;
    task stack[2 * MAX_DEPTH + 4];
    size_t cap, i;
    int sp = 0;

    memset(out, 0, sizeof *out);
    if (n == 0)
        return RAY_OK;
    if (n > 0x7fffffffu)
        return RAY_ENOMEM;
    cap = 2 * n - 1;                         /* a binary tree's bound */
    bd.boxes = boxes;
    bd.centroids = ray__alloc(s, 3 * n * sizeof *bd.centroids);
    bd.ids = ray__alloc(s, n * sizeof *bd.ids);
    bd.nodes = ray__alloc(s, cap * sizeof *bd.nodes);
    if (bd.centroids == NULL || bd.ids == NULL || bd.nodes == NULL) {
        ray__free(s, bd.centroids, 3 * n * sizeof *bd.centroids);
        ray__free(s, bd.ids, n * sizeof *bd.ids);
        ray__free(s, bd.nodes, cap * sizeof *bd.nodes);
        return RAY_ENOMEM;
    }
    for (i = 0; i < n; i++) {
        const float *b = boxes + 6 * i;
        bd.ids[i] = (unsigned)i;
        bd.centroids[3 * i] = 0.5f * b[0] + 0.5f * b[3];
        bd.centroids[3 * i + 1] = 0.5f * b[1] + 0.5f * b[4];
        bd.centroids[3 * i + 2] = 0.5f * b[2] + 0.5f * b[5];
    }
    bd.n_nodes = 1;
    stack[0].node = 0;
    stack[0].begin = 0;
    stack[0].end = n;
    stack[0].depth = 0;
    sp = 1;
    /* Depth-first: the stack never holds more than two tasks per level. */
    while (sp > 0) {
        task t = stack[--sp];
        sp += build_node(&bd, t, stack + sp);
    }
    ray__free(s, bd.centroids, 3 * n * sizeof *bd.centroids);
    out->nodes = ray__realloc(s, bd.nodes, cap * sizeof *bd.nodes,
                              bd.n_nodes * sizeof *bd.nodes);
    out->cap_nodes = bd.n_nodes;
    if (out->nodes == NULL) {            /* shrinking failed: keep it all */
        out->nodes = bd.nodes;
        out->cap_nodes = cap;
    }
    out->n_nodes = bd.n_nodes;
    out->items = bd.ids;
    out->n_items = n;
    return RAY_OK;
}
