/* SPDX-License-Identifier: MIT */
/*
** build.c -- ray__bvh_build: the binary tree of a BVH built from its root
** by sah.c's splits, its top a level at a time and its lower subtrees
** depth first, on threads, then
** collapsed into wide nodes (wide.c); and ray__bvh_free.
*/
#include <limits.h>

#include "accel/builder.h"
#include "core/platform.h"
#include "core/tasks.h"

/*
** The threaded build.  The top of the tree is split a level at a time
** (build_top) until every node left has at most top_limit(n) items;
** those nodes become subtree tasks, numbered in the order the top
** phase reaches them, and task j builds into its own run of the node
** array, from region[j] on (2 m - 2 nodes at most below its root for m
** items, so the runs fit in the 2 n - 1 a binary tree needs: the top's
** L leaves take 2 L - 1, their runs 2 n - 2 L).  Each task works on its
** own items (a contiguous range of refs) and its own nodes, so the
** tasks share nothing (the built-in threads only the counter that hands
** them out: core/tasks.c), and what a task writes does not depend on
** which thread ran it or when: the tree, its item order and every float
** are the same at any thread count, in any task order.  The
** runs are then closed up in task order (their links moved with them),
** so the node array shrinks to what the tree uses before the collapse
** allocates the wide nodes, as in the plain build.
** The splits are those of a plain depth-first build (a node's division
** depends on its items alone, not on when it is made), so the wide tree
** is too, but for the order of the top's nodes.
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
    unsigned *items;         /* the item order, written as subtrees end */
    subtree *tasks;
    const size_t *order;     /* tasks by size, largest first */
    ray__progress *prog;     /* NULL: no reports */
} build_job;

/* The items of refs[begin, end) in their final order: each subtree's
** and each leaf of the top's as it is done, on its thread, where one
** pass over them all after the build was a serial twentieth of a 940k
** build's time on two threads (perf, issue 36). */
static void items_write(const ref *refs, unsigned *items, size_t begin,
                        size_t end)
{
    size_t i;

    for (i = begin; i < end; i++)
        items[i] = refs[i].id;
}

int ray__progress_add(ray__progress *p, size_t items)
{
    int cancelled;

    if (p->lock != NULL)
        ray__mutex_lock(p->lock);
    p->done += items;
    p->reported = p->done;
    /* The callback's counts are unsigned: a commit of more than 2^32 - 1
    ** items reports them clamped (one BVH holds at most 2^31 - 1). */
    if (!p->cancelled &&
        p->fn(p->ud, p->done < UINT_MAX ? (unsigned)p->done : UINT_MAX,
              p->total < UINT_MAX ? (unsigned)p->total : UINT_MAX) != 0)
        p->cancelled = 1;
    cancelled = p->cancelled;
    if (p->lock != NULL)
        ray__mutex_unlock(p->lock);
    return cancelled;
}

/*
** Count a leaf's items toward the next report: every RAY__PROGRESS_STEP
** items or more (the callback costs one call per thousands of items,
** not one per item).  Returns whether the build is cancelled.
*/
static int leaf_done(ray__progress *prog, size_t *pending, size_t items)
{
    if (prog == NULL)
        return 0;
    *pending += items;
    if (*pending < RAY__PROGRESS_STEP)
        return 0;
    items = *pending;
    *pending = 0;
    return ray__progress_add(prog, items);
}

/* Build one subtree, depth first, into its region; it stops where the
** progress callback cancels the build (the tree is then thrown away). */
static void build_subtree(const build_job *job, subtree *st)
{
    builder bd;
    task stack[2 * MAX_DEPTH + 4];
    size_t pending = 0;
    int sp = 1;

    bd.costs = job->costs;
    bd.refs = job->refs;
    bd.nodes = job->nodes;
    bd.n_nodes = st->region;
    bd.alloc = NULL;
    bd.sched = NULL;
    bd.threads = 1;
    stack[0] = st->root;
    while (sp > 0) {
        task t = stack[--sp];
        int children = ray__bvh_split(&bd, &t, stack + sp);
        sp += children;
        if (children == 0 &&
            leaf_done(job->prog, &pending, t.end - t.begin))
            return;
    }
    if (pending > 0)
        (void)ray__progress_add(job->prog, pending);
    st->used = bd.n_nodes - st->region;
    items_write(job->refs, job->items, st->root.begin, st->root.end);
}

/* Task k: the k-th largest subtree (the built-in threads take tasks in
** number order, so the largest start first). */
static void build_task(void *ud, unsigned k)
{
    const build_job *job = ud;

    build_subtree(job, &job->tasks[job->order[k]]);
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


/* leaves[k], the leaves below binary node k of the n (a node's children
** come after it, so one pass from the end sees them first). */
static void count_leaves(const ray__node *nodes, size_t n, unsigned *leaves)
{
    while (n-- > 0) {
        const ray__node *q = &nodes[n];
        leaves[n] = q->count == 0 ? leaves[q->first] + leaves[q->first + 1]
                                  : 1;
    }
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

/*
** The top of the tree, a level at a time: each node of the level with
** more than "limit" items is divided (ray__bvh_divide), the others become
** subtree tasks, in the level's order; then the divided nodes are linked
** to their children, numbered in that order, which make the next level.
** A level's nodes share nothing (each its own items and node), so where
** a level has at least as many to divide as there are threads, each is
** divided on a thread of its own; fewer (the root, the first levels on
** many threads), one after another, each binned on all threads
** (sah.c's bin_node).  Either way the same divisions, numbered in the
** same order: the same tree at any thread count.  Depth first, the top
** was divided on the calling thread alone, its binning alone shared:
** a fifth of a 940k build's time on two threads, the other thread
** waiting (perf, issue 36).
*/
typedef struct cut {
    task t;
    size_t mid;
    bounds left, right;
    int children;
} cut;

typedef struct top_job {
    const builder *bd;
    cut *cuts;
} top_job;

/* Divide level node k on this thread alone (bd's nodes and items). */
static void top_task(void *ud, unsigned k)
{
    const top_job *job = ud;
    builder bd = *job->bd;
    cut *c = &job->cuts[k];

    bd.alloc = NULL;
    bd.sched = NULL;
    bd.threads = 1;
    c->children = ray__bvh_divide(&bd, &c->t, &c->mid, &c->left, &c->right);
}

/* Add subtree task t (grown as needed): RAY_OK or RAY_ENOMEM. */
static int add_subtree(const ray__allocator *a, const task *t,
                       subtree **tasks, size_t *n_tasks, size_t *cap_tasks)
{
    if (*n_tasks == *cap_tasks) {
        size_t more = *cap_tasks ? 2 * *cap_tasks : 2 * TOP_SHARE;
        subtree *grown = ray__reallocate(a, *tasks,
                                         *cap_tasks * sizeof **tasks,
                                         more * sizeof **tasks);
        if (grown == NULL)
            return RAY_ENOMEM;
        *tasks = grown;
        *cap_tasks = more;
    }
    (*tasks)[(*n_tasks)++].root = *t;
    return RAY_OK;
}

static int build_top(builder *bd, const task *root, size_t limit,
                     unsigned *items, ray__progress *prog, size_t *pending,
                     subtree **tasks, size_t *n_tasks, size_t *cap_tasks)
{
    /* A level's nodes to divide each hold more than limit of the n items:
    ** fewer than n / limit of them, their children twice that. */
    size_t n = root->end - root->begin, most = n / limit + 1, count = 1, i;
    size_t bytes = most * sizeof(cut) + 2 * most * sizeof(task);
    unsigned char *raw = ray__allocate(bd->alloc, bytes);
    cut *cuts;
    task *level;
    top_job job;
    int rc = RAY_OK;

    if (raw == NULL)             /* before any arithmetic on it (UBSan) */
        return RAY_ENOMEM;
    cuts = (cut *)(void *)raw;
    level = (task *)(void *)(raw + most * sizeof(cut));
    level[0] = *root;
    job.bd = bd;
    job.cuts = cuts;
    while (count > 0 && rc == RAY_OK) {
        size_t big = 0, next = 0;
        for (i = 0; i < count && rc == RAY_OK; i++) {
            if (level[i].end - level[i].begin > limit)
                cuts[big++].t = level[i];
            else
                rc = add_subtree(bd->alloc, &level[i], tasks, n_tasks,
                                 cap_tasks);
        }
        if (rc != RAY_OK)
            break;
        if (big >= bd->threads && big > 1)
            ray__tasks_run(bd->sched, bd->alloc, bd->threads, 0,
                           (unsigned)big, top_task, &job);
        else
            for (i = 0; i < big; i++)
                cuts[i].children = ray__bvh_divide(
                    bd, &cuts[i].t, &cuts[i].mid, &cuts[i].left,
                    &cuts[i].right);
        for (i = 0; i < big; i++) {
            const cut *c = &cuts[i];
            if (c->children == 0) {
                /* A node the SAH leaves whole (items that cannot be
                ** told apart) is a leaf of the top. */
                items_write(bd->refs, items, c->t.begin, c->t.end);
                if (leaf_done(prog, pending, c->t.end - c->t.begin))
                    rc = RAY_ECANCELED;
                continue;
            }
            ray__bvh_link(bd, &c->t, c->mid, &c->left, &c->right,
                          level + next);
            next += 2;
        }
        count = next;
    }
    ray__release(bd->alloc, raw, bytes);
    return rc;
}

int ray__bvh_build(const ray__allocator *a, ray__box_fn box_of,
                   const void *ud, size_t n, const ray__bvh_costs *costs,
                   const ray_scheduler *sched, unsigned threads,
                   ray__bvh_share *share, ray__progress *prog,
                   ray__bvh *out)
{
    void *scratch = share != NULL ? share->records : NULL;
    size_t keep = share != NULL ? share->keep : 0, node_bytes, shrunk;
    builder bd;
    task root;
    size_t cap, i, region, n_tasks = 0, cap_tasks = 0, pending = 0;
    subtree *tasks = NULL;
    size_t *order = NULL;
    unsigned *items, *leaves;
    int rc = RAY_OK;

    memset(out, 0, sizeof *out);
    if (share != NULL) {
        share->kept = NULL;
        share->kept_bytes = 0;
    }
    if (n == 0)
        return RAY_OK;
    /* Node numbers fit an unsigned, and the nodes' and records' bytes a
    ** size_t (where it is 32 bits, more than 2^26 items would wrap). */
    if (n > 0x7fffffffu || n > (size_t)-1 / 2 / sizeof(ray__box_rec))
        return RAY_ENOMEM;
    cap = 2 * n - 1;                         /* a binary tree's bound */
    node_bytes = cap * sizeof *bd.nodes;
    if (keep > node_bytes)
        node_bytes = keep;
    if (threads == 0)
        threads = ray__online_cpus();
    if (threads > RAY__MAX_BUILD_THREADS)
        threads = RAY__MAX_BUILD_THREADS;
    bd.costs = costs;
    bd.alloc = a;
    bd.sched = sched;
    bd.threads = threads;
    bd.refs = scratch;
    if (scratch == NULL)
        bd.refs = ray__allocate(a, n * sizeof *bd.refs);
    bd.nodes = ray__allocate(a, node_bytes);
    items = ray__allocate(a, n * sizeof *items);
    if (bd.refs == NULL || bd.nodes == NULL || items == NULL) {
        rc = RAY_ENOMEM;
        goto done;
    }
    {
        bounds b;
        ray__bvh_refs(&bd, box_of, ud, n, &b);
        bd.n_nodes = 1;
        child_task(&root, 0, 0, n, 0, &b);
    }
    rc = build_top(&bd, &root, top_limit(n), items, prog, &pending, &tasks,
                   &n_tasks, &cap_tasks);
    if (rc != RAY_OK)
        goto done;
    if (pending > 0 && ray__progress_add(prog, pending)) {
        rc = RAY_ECANCELED;
        goto done;
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
            job.items = items;
            job.tasks = tasks;
            job.order = order;
            job.prog = prog;
            /* On the scheduler, or the calling thread and threads - 1
            ** started ones: fewer if a thread cannot be started, or if the
            ** runner's lock cannot be made (the caller builds them all),
            ** the same tree either way.  n_tasks <= n < 2^31 (checked
            ** above) fits an unsigned. */
            ray__tasks_run(sched, a, threads, 0, (unsigned)n_tasks,
                           build_task, &job);
        }
        /* Read once every task has returned (ray__tasks_run joins them):
        ** a cancelled build left subtrees unfinished. */
        if (prog != NULL && prog->cancelled) {
            rc = RAY_ECANCELED;
            goto done;
        }
    }
    bd.n_nodes = close_up(bd.nodes, tasks, n_tasks, bd.n_nodes);
    /* Before the collapse allocates: the peak stays where it was. */
    ray__release(a, order, n_tasks * sizeof *order);
    ray__release(a, tasks, cap_tasks * sizeof *tasks);
    if (scratch == NULL)
        ray__release(a, bd.refs, n * sizeof *bd.refs);
    order = NULL;
    tasks = NULL;
    bd.refs = NULL;
    /* Shrunk to the nodes, or to what the caller keeps if more: the
    ** tail's pages, which subtrees reserved and did not use, go back now,
    ** before the collapse allocates (a failed shrink keeps it all). */
    shrunk = bd.n_nodes * sizeof *bd.nodes;
    if (keep > shrunk)
        shrunk = keep;
    if (shrunk < node_bytes) {
        ray__node *fit = ray__reallocate(a, bd.nodes, node_bytes, shrunk);
        if (fit != NULL) {
            bd.nodes = fit;
            node_bytes = shrunk;
        }
    }
    out->nodes = bd.nodes;
    out->n_nodes = bd.n_nodes;
    out->items = items;
    out->n_items = n;
    items = NULL;
    /* The collapse's leaf counts in the caller's scratch, if any: the
    ** item records are done with, and its pages were touched.  A block
    ** of their own (under RAY__HUGE_BLOCK: 4 KiB pages) was, where libc
    ** mapped it afresh, a page fault a page: 20 cold builds of the 940k
    ** bunny took 175,768 minor faults, 165,544 with this (perf stat -e
    ** minor-faults build/bench/filter --profile data/bunny-4.obj build
    ** 1), the faults of a serial step of the build (issue 36).  At 4
    ** bytes a node, 2 n - 1 nodes at most, they fit its 32 bytes an item
    ** (RAY__BVH_SCRATCH).  NULL, memory short: the collapse by area
    ** alone. */
    leaves = scratch != NULL ? scratch
                             : ray__allocate(a, bd.n_nodes * sizeof *leaves);
    if (leaves != NULL)
        count_leaves(out->nodes, bd.n_nodes, leaves);
    rc = ray__bvh_collapse(a, out, leaves);
    out->nodes = NULL;                        /* bd.nodes: freed below */
    if (rc != RAY_OK)
        ray__bvh_free(a, out);
    else if (keep > 0) {
        share->kept = bd.nodes;                /* the caller's now */
        share->kept_bytes = node_bytes;
        bd.nodes = NULL;
    }
    if (scratch == NULL)
        ray__release(a, leaves, bd.n_nodes * sizeof *leaves);
done:
    ray__release(a, order, n_tasks * sizeof *order);
    ray__release(a, tasks, cap_tasks * sizeof *tasks);
    if (scratch == NULL)
        ray__release(a, bd.refs, n * sizeof *bd.refs);
    ray__release(a, bd.nodes, node_bytes);
    ray__release(a, items, n * sizeof *items);
    return rc;
}


void ray__bvh_free(const ray__allocator *a, ray__bvh *bvh)
{
    ray__release(a, bvh->wide, bvh->cap_wide * sizeof *bvh->wide);
    ray__release(a, bvh->items, bvh->n_items * sizeof *bvh->items);
    ray__release(a, bvh->leaves, bvh->n_leaves * sizeof *bvh->leaves);
    memset(bvh, 0, sizeof *bvh);
}
