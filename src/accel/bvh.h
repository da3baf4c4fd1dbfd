/* SPDX-License-Identifier: MIT */
/*
** bvh.h -- the BVH: its node types and its builder (build.c), generic over
** the items' boxes and allocating through an allocator of its own, so it
** knows nothing of the scene that uses it.
*/
#ifndef RAY_BVH_H
#define RAY_BVH_H

#include "core/alloc.h"

/*
** A node of the binary BVH that the build makes and collapses into wide
** nodes: its box, in float, rounded outward from the double geometry so
** it still contains it; an inner node (count == 0) has its two children
** side by side at nodes[first] and nodes[first + 1], a leaf holds items
** first .. first + count - 1.
*/
typedef struct ray__node {
    float lo[3], hi[3];
    unsigned first, count;
} ray__node;

/*
** The traversal's node: up to RAY__WIDTH children's boxes side by side,
** one float array per bound and axis, so four- or eight-lane arithmetic
** tests them all at once.  Eight children rather than four halve the
** depth a ray descends, and traversal is a chain of dependent node visits
** (each ~70 cycles, mostly latency); the two four-lane halves of a node
** are independent and overlap.  count[k] == 0: child[k] is the index of an
** inner node; else slot k is a leaf, count[k] == RAY__LEAF | n, of the n
** items from child[k].  An unused slot is a leaf of no items with an
** empty box (lo = +Inf, hi = -Inf), so even a ray that "entered" it would
** test nothing.  256 bytes: four cache lines.
*/
#define RAY__WIDTH 8
#define RAY__LEAF 0x80000000u
typedef struct ray__wnode {
    float lo[3][RAY__WIDTH], hi[3][RAY__WIDTH];
    unsigned child[RAY__WIDTH], count[RAY__WIDTH];
} ray__wnode;

typedef struct ray__bvh {
    ray__node *nodes;    /* binary BVH: the build's, during the collapse */
    size_t n_nodes;
    ray__wnode *wide;    /* what traversal uses */
    size_t n_wide, cap_wide;
    unsigned *items;     /* leaf order -> item index */
    size_t n_items;
    unsigned *leaves;    /* refit's: the leaf slots (node * RAY__WIDTH +
                            slot) by their first item; made by the first
                            refit, kept until the BVH is freed */
    size_t n_leaves;
} ray__bvh;

/*
** Build a BVH over n items whose float boxes box(ud, i, lo, hi) writes
** (rounded outward), with the binned surface-area heuristic, collapsed to
** RAY__WIDTH-wide nodes; its lower subtrees are tasks (core/tasks.h) for
** "sched" if it has a run, else for up to "threads" threads (0: one per
** online CPU; the calling thread is one of them, the others are started
** and joined inside).  The tree is the same, bit for bit, at every
** thread count and in every task order.  The allocator is called on
** the calling thread only, and so is box unless costs->box_threads.
** On success *out holds the nodes and the item permutation (through
** allocator a).  RAY_OK or RAY_ENOMEM (nothing kept); a thread that
** cannot be started only means fewer threads.  ray__bvh_free gives them
** back through the same allocator.
*/
typedef void (*ray__box_fn)(const void *ud, size_t i, float lo[3],
                            float hi[3]);
/*
** The build's record of an item: its box and id (the builder permutes
** them; builder.h), 32 bytes.  A costs->boxes callback fills the boxes of
** items begin .. end - 1 into out[0 .. end - begin - 1] at once (lo and
** hi only, rounded outward), in place of box one item at a time (which
** may then be NULL): a mesh's lookups made once a run, not once an
** item.
*/
typedef struct ray__box_rec {
    float lo[3];
    unsigned id;             /* lo and id, hi and pad: one SSE load each */
    float hi[3];
    unsigned pad;
} ray__box_rec;
typedef void (*ray__boxes_fn)(const void *ud, size_t begin, size_t end,
                              ray__box_rec *out);
typedef struct ray__bvh_costs {
    float traversal;         /* a split's cost, in item tests */
    unsigned leaf_items;     /* a node of this many items or fewer: a leaf
                                (unless sparse: sparse.c) */
    int box_threads;         /* box may run on the build's threads at once
                                (reads only what no thread writes); 0:
                                on the calling thread only */
    ray__boxes_fn boxes;     /* NULL, or box for runs of items */
} ray__bvh_costs;
/*
** The blocks a build shares with its caller (NULL: none), so that a
** caller with temporaries of its own after the build, and blocks to fill,
** touches fewer pages for the first time (a block that large is mapped
** afresh at each allocation, and every first touch of a page is a page
** fault: issue 36):
** - records: NULL, or a block of at least RAY__BVH_SCRATCH(n) bytes that
**   the build uses for its item records instead of allocating them (and
**   leaves to the caller, its contents undefined);
** - keep: 0, or a size in bytes: the block of the binary nodes, which the
**   build reserves for the worst case of each subtree and so touches
**   across most of its length, is not freed after the collapse but left
**   in *kept, kept_bytes long (at least keep), its contents undefined,
**   for the caller to use and to free or resize through the allocator
**   (NULL when the build fails).
*/
typedef struct ray__bvh_share {
    void *records;
    size_t keep;
    void *kept;
    size_t kept_bytes;
} ray__bvh_share;
#define RAY__BVH_SCRATCH(n) ((n) * (size_t)32)

/*
** A build's progress (ray_scene_set_progress): items placed in leaves so
** far of the total the commit builds over, reported to fn every
** RAY__PROGRESS_STEP items or more, one call at a time (under "lock"
** when the build runs on several threads), and never again once fn has
** asked to cancel: "cancelled" is then set and the builds stop at their
** next report, returning RAY_ECANCELED.  "done" and "cancelled" are read
** and written under the lock alone while a build's tasks run.
*/
#define RAY__PROGRESS_STEP 4096
typedef struct ray__progress {
    ray_progress_fn fn;
    void *ud;
    struct ray__mutex *lock;
    size_t done, total;
    size_t reported;         /* done at the last call (0: none yet) */
    int cancelled;
} ray__progress;

/* Add "items" to p->done and call fn; returns whether the work is
** cancelled (fn asked now or before). */
int ray__progress_add(ray__progress *p, size_t items);

/* prog: NULL, or where the build reports (and learns it is cancelled:
** RAY_ECANCELED, nothing built, as for RAY_ENOMEM). */
int ray__bvh_build(const ray__allocator *a, ray__box_fn box,
                   const void *ud, size_t n, const ray__bvh_costs *costs,
                   const ray_scheduler *sched, unsigned threads,
                   ray__bvh_share *share, ray__progress *prog,
                   ray__bvh *out);
void ray__bvh_free(const ray__allocator *a, ray__bvh *bvh);

/*
** Refit: the same tree, every box fitted again bottom up, a leaf's to its
** items as range_box(ud, first, n, ...) now bounds items first .. first
** + n - 1 (leaf positions: indices into items[] when the BVH keeps them,
** else what the leaves index), rounded outward once for the run.  For
** geometry that moved but kept its items (n_items of them): O(items +
** nodes), with a temporary array of n_items through "a" (without it,
** when that allocation fails, the same boxes, slower); the tree may fit
** worse than a rebuild would.  The leaves are fitted on "threads" threads
** (0: one per online CPU) or on sched's, as a build's are (range_box is
** then called from several threads at once, each leaf once): the same
** boxes at any thread count.
*/
typedef void (*ray__range_box_fn)(const void *ud, size_t first, size_t n,
                                  float lo[3], float hi[3]);
void ray__bvh_refit(const ray__allocator *a, ray__bvh *bvh,
                    ray__range_box_fn range_box, const void *ud,
                    size_t n_items, const ray_scheduler *sched,
                    unsigned threads);

#endif /* RAY_BVH_H */
