/* SPDX-License-Identifier: MIT */
/*
** refit.c -- a BVH's boxes fitted again, bottom up, to geometry that
** moved but kept its items (ray__bvh_refit): the same tree.
*/
#include "accel/builder.h"
#include "core/platform.h"
#include "core/tasks.h"

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

/*
** The nodes that hold the leaves lie in the collapse's order, not the
** list's, so each leaf's node (its child and count read, its box
** written: the whole 256 bytes) was a cache miss, most of the leaf
** pass's own time in a 940k refit (perf annotate, bench/filter --profile
** refit, issue 36).  The list says which node comes next: the node of
** the leaf this many ahead is fetched, line by line (always inlined:
** GCC drops the calls of a function of prefetches alone, scene/slots.h).
*/
#define REFIT_PREFETCH_LEAVES 8

RAY__HOT_INLINE void prefetch_node(const ray__bvh *bvh, size_t leaf)
{
    const char *w = (const char *)&bvh->wide[bvh->leaves[leaf] / RAY__WIDTH];
    size_t at;

    for (at = 0; at < sizeof(ray__wnode); at += 64)
        RAY__PREFETCH(w + at);
}

/* Leaf slots leaves[begin .. end - 1] refitted. */
static void refit_leaf_run(ray__bvh *bvh, ray__range_box_fn range_box,
                           const void *ud, size_t begin, size_t end)
{
    size_t i;

    for (i = begin; i < end; i++) {
        ray__wnode *q = &bvh->wide[bvh->leaves[i] / RAY__WIDTH];
        int slot = (int)(bvh->leaves[i] % RAY__WIDTH);
        box b;
        if (i + REFIT_PREFETCH_LEAVES < end)
            prefetch_node(bvh, i + REFIT_PREFETCH_LEAVES);
        range_box(ud, q->child[slot], q->count[slot] & ~RAY__LEAF, b.lo,
                  b.hi);
        slot_fit(q, slot, &b);
    }
}

/*
** The leaf pass in parallel: the list in "tasks" runs of consecutive
** leaves, so each thread reads its triangles in order too.  Each leaf
** writes only its own slot and what range_box writes for it (a leaf's
** own rows, for the triangles), so the runs share nothing, and the boxes
** are the same floats in any order and at any thread count.
*/
typedef struct refit_job {
    ray__bvh *bvh;
    ray__range_box_fn range_box;
    const void *ud;
} refit_job;

static void refit_task(void *arg, unsigned k, size_t begin, size_t end)
{
    const refit_job *job = arg;

    (void)k;
    refit_leaf_run(job->bvh, job->range_box, job->ud, begin, end);
}

/*
** Below this many leaves (about six triangles each) the leaf pass runs
** on the calling thread: starting a thread costs tens of microseconds,
** about what a thousand leaves take (bench/game's 59k refit: 3 ms for
** its 10,031 leaves on one thread).  Runs: four a thread, so that a
** thread slowed by its neighbours' work leaves less to wait for.
*/
#define REFIT_PARALLEL_LEAVES 2048
#define REFIT_RUNS_PER_THREAD 4

/* The leaf slots refitted in the order of their items. */
static int refit_leaves_in_order(const ray__allocator *a, ray__bvh *bvh,
                                 ray__range_box_fn range_box, const void *ud,
                                 size_t n_items, const ray_scheduler *sched,
                                 unsigned threads)
{
    if (!leaves_in_order(a, bvh, n_items))
        return 0;
    if (threads == 0)
        threads = ray__online_cpus();
    if (threads > RAY__MAX_BUILD_THREADS)
        threads = RAY__MAX_BUILD_THREADS;
    if ((threads > 1 || (sched != NULL && sched->run != NULL)) &&
        bvh->n_leaves >= REFIT_PARALLEL_LEAVES) {
        size_t tasks = (size_t)threads * REFIT_RUNS_PER_THREAD;
        refit_job job;
        job.bvh = bvh;
        job.range_box = range_box;
        job.ud = ud;
        /* tasks runs (or a few fewer where they do not divide the
        ** leaves), at most 256: a task number holds them. */
        (void)ray__tasks_runs(sched, a, threads, 0, bvh->n_leaves,
                              (bvh->n_leaves + tasks - 1) / tasks,
                              refit_task, &job);
    } else {
        refit_leaf_run(bvh, range_box, ud, 0, bvh->n_leaves);
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
                    size_t n_items, const ray_scheduler *sched,
                    unsigned threads)
{
    int leaves_done = refit_leaves_in_order(a, bvh, range_box, ud, n_items,
                                            sched, threads);
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
