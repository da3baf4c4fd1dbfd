/* SPDX-License-Identifier: MIT */
/*
** builder.h -- the insides of the BVH builder, private to accel/: the
** builder's item records and boxes, a node's bounds, the task of a node
** to build, and the steps its files share: sah.c splits a node (sparse.c
** a node of few items), build.c builds the binary tree (on threads),
** wide.c collapses it into wide nodes, refit.c fits the boxes again.
*/
#ifndef RAY_BUILDER_H
#define RAY_BUILDER_H

#include <float.h>
#include <string.h>

#include "accel/bvh.h"

#define MAX_DEPTH 60     /* traversal stacks hold 64 levels */

/*
** Builder records: an item's box and id, 32 bytes, permuted in place by
** the partitions so every pass over a node's items reads memory in order.
** The centroid is not stored: lo + hi (twice the centre) serves, since
** binning only needs an affine image of it.
*/
typedef ray__box_rec ref;

/* RAY__BVH_SCRATCH (bvh.h) counts a record's bytes. */
typedef char ray__ref_size_check[sizeof(ref) == RAY__BVH_SCRATCH(1) ? 1 : -1];

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

static inline void box_empty(box *b)
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
static inline float box_area(const box *b)
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
    /* Where a large node's binning may run in parallel (sah.c's
    ** bin_node): the top of a threaded build; threads 1 and sched NULL
    ** elsewhere (a subtree task is already one thread's work). */
    const ray__allocator *alloc;
    const ray_scheduler *sched;
    unsigned threads;
} builder;

/* A split of a node's items: those whose bin is at most "bin" go left. */
typedef struct split {
    int axis, bin;           /* items with bin index <= bin go left */
    int bins;                /* how many bins were used */
    float cost;
    float cmin, scale;       /* bin of c = (c - cmin) * scale */
} split;

/* Twice the centroid along "axis". */
static inline float centroid2(const ref *r, int axis)
{
    return r->lo[axis] + r->hi[axis];
}

/* Does r go to the left of split sp?  edge: (float)(sp->bin + 1). */
static inline int goes_left(const ref *r, const split *sp, float edge)
{
    float x = (centroid2(r, sp->axis) - sp->cmin) * sp->scale;

    return !(x >= edge);
}

/* The boxes a node needs before it is split: its items' box and the box
** of their doubled centroids. */
typedef struct bounds {
    box items, centroids;
} bounds;

typedef struct task {
    size_t node, begin, end;
    unsigned depth;
    bounds b;
} task;

/* Push the task of a child node over refs[begin, end). */
static inline void child_task(task *t, size_t node, size_t begin, size_t end,
                       unsigned depth, const bounds *b)
{
    t->node = node;
    t->begin = begin;
    t->end = end;
    t->depth = depth;
    t->b = *b;
}

/*
** ray__bvh_refs -- the records of n items, refs[i] with item i's box from
** box_of (rounded outward by the caller), and *root, the bounds of them
** all: the builder's first pass.
** ray__bvh_split -- split node t.node (items refs[t.begin, t.end), bounds
** t.b) by the binned SAH, or leave it a leaf; the children's tasks go to
** stack[0] and stack[1].  Returns how many (0 or 2).  In two steps:
** ray__bvh_divide -- node t.node's box set and its items divided (refs
** t.begin .. *mid - 1 and *mid .. t.end - 1, their bounds *left and
** *right): 2; or it stays a leaf: 0.  It writes only that node and
** those items, so nodes of one level may be divided on threads;
** ray__bvh_link -- the node linked to its two children, numbered next
** (bd->n_nodes), their tasks into stack[0] and stack[1].
** ray__bvh_collapse -- the binary nodes of bvh collapsed into
** RAY__WIDTH-wide nodes (bvh->wide), the binary ones left where they are
** (ray__bvh_build frees them, or keeps their block for its caller):
** RAY_OK, or RAY_ENOMEM with bvh as it was.  leaves: the leaf count below each
** binary node, or NULL (memory was short: the collapse then opens nodes
** by their area alone).
*/
void ray__bvh_refs(builder *bd, ray__box_fn box_of, const void *ud,
                   size_t n, bounds *root);
int ray__bvh_split(builder *bd, const task *t, task *stack);
int ray__bvh_divide(builder *bd, const task *t, size_t *mid, bounds *left,
                    bounds *right);
void ray__bvh_link(builder *bd, const task *t, size_t mid,
                   const bounds *left, const bounds *right, task *stack);
int ray__bvh_collapse(const ray__allocator *a, ray__bvh *bvh,
                      const unsigned *leaves);
/*
** A node of few items that is sparse (sparse.c): ray__bvh_has_gap, do
** the boxes of refs[begin, end) surely leave a gap inside their node's
** box b (if not, they make a leaf); ray__bvh_sides_sparse, are the items
** large beside their node, and split sp's two sides apart, with less
** area together than the node's box?
*/
int ray__bvh_has_gap(const builder *bd, size_t begin, size_t end,
                     const box *b);
int ray__bvh_sides_sparse(const builder *bd, size_t begin, size_t end,
                          const split *sp, const box *node);

#endif /* RAY_BUILDER_H */
