/* SPDX-License-Identifier: MIT */
/*
** traverse.h -- the query template: the scene queries (nearest hit, any
** hit) over the planes and the two BVHs, as static functions, included
** by intersect.c, built for the baseline instruction set, and by
** intersect_avx2.c, built with AVX2 (the Makefile adds -mavx2 on x86),
** which ray__intersect and ray__occluded pick at run time on CPUs that
** have it.  Both copies do the same arithmetic, lane for lane, so they
** give the same answers.  The template's parts, each included here:
**   slab.h       a ray's traversal data and the wide nodes' box test;
**   gate.h       masks, filters and all hits;
**   leaf.h       a leaf's triangles (tested inline) and other kinds
**                (through the kinds' dispatch, scene/kinds.c);
**   traverse.h   an instance met (the query descends into its child),
**                the ordered traversal and the queries themselves;
**   plain.h      the short paths of the plain queries of a scene of
**                triangles alone and of one of instances of such scenes.
*/
#ifndef RAY_TRAVERSE_H
#define RAY_TRAVERSE_H

#include "query/slab.h"
#include "scene/candidate.h"

enum { LEAF_TRIANGLES, LEAF_PRIMS, LEAF_INSTANCES };

/* Add a query's counts to *st (if any): the kinds it counted
** (qc->kinds, and the triangles where it tested any), not all
** RAY_PRIM_KINDS of them, whose loop was 3% of the Whitted render's
** instructions (callgrind, issue 35).  No triangle test adds 0: the
** same sums without that turn of the loop, on every query of a scene
** without triangles. */
static void add_counts(ray_stats *st, const ray__counts *qc)
{
    unsigned kinds = qc->kinds | (qc->tests[RAY_PRIM_TRIANGLE] != 0
                                      ? 1u << RAY_PRIM_TRIANGLE : 0u);

    if (st == NULL)
        return;
    for (; kinds != 0; kinds &= kinds - 1) {
        int k = lowest_bit(kinds);
        st->tests_by_kind[k] += qc->tests[k];
        st->tests += qc->tests[k];
    }
    st->root_failures += qc->failures;
    st->filter_calls += qc->filter_calls;
}

#include "query/leaf.h"

/* A scene of triangles alone (no planes, no bounded kinds, so no
** instances): query_nearest_tris says what its queries skip. */
static inline int tris_only(const ray_scene *s)
{
    return s->n_planes == 0 && s->prim_bvh.n_wide == 0;
}

/* An instance's child inside a parent's query: nearest or any as the
** parent's query is, with its counts and gate (below, with the queries
** it recurses into). */
static int query_child(const ray_scene *child, ray_ray *r, ray_hit *hit,
                       ray__counts *qc);

/* World ray r in instance in's child space into *ro (ray__instance_ray_
** to_object), written in the AVX copy as the two halves the child's
** set-up reads (slab.h's ray_halves), so that its loads are forwarded
** from these stores. */
static inline void child_ray(const ray__instance *in, const ray_ray *r,
                             ray_ray *ro)
{
#if defined(__AVX__) && !defined(RAY_NO_SIMD)
    ray_ray t;

    ray__instance_ray_to_object(in, r, &t);
    ray_halves_store(ro, _mm256_set_pd(t.dir.x, t.org.z, t.org.y, t.org.x),
                     _mm256_set_pd(t.tmax, t.tmin, t.dir.z, t.dir.y));
#else
    ray__instance_ray_to_object(in, r, ro);
#endif
}

/* Instance idx of s met by world ray r: counted, and r in its child's
** space in *ro; NULL (qc->stale set) where the child changed since s was
** committed. */
static const ray__instance *instance_enter(const ray_scene *s, unsigned idx,
                                           const ray_ray *r, ray_ray *ro,
                                           ray__counts *qc)
{
    const ray__instance *in = &s->instances[s->prims[idx].surface];

    ray__count_tests(qc, RAY_PRIM_INSTANCE, 1);
    if (ray__instance_stale(in)) {
        qc->stale = 1;
        return NULL;
    }
    child_ray(in, r, ro);
    return in;
}

/*
** Geometry idx of s, an instance, against world ray r: RAY__HIT_FULL
** with *hit filled -- the child's hit brought back to world space, its
** error bound grown by the rounding of both transforms
** (ray__instance_to_world), geom_id and prim_id the child's, inst_id idx;
** for an any-hit query only t, which is all it reads -- or 0 on a miss.
** A child changed since s was committed is a miss with qc->stale set (the
** query then answers -RAY_ESTATE).  Counted as one test of its kind
** (RAY_PRIM_INSTANCE, its column in RAY__PRIM_KINDS), as every bounded
** primitive's test is.  Inside, qc names the instance, so that the gate
** offers the child's candidates in world space.  Here, beside the
** queries it recurses into, as Embree's instance intersector sits in its
** traversal kernels; the scene keeps the instance's record, transforms
** and box (scene/instance.c).
*/
static int instance_hit(const ray_scene *s, unsigned idx, const ray_ray *r,
                        ray_hit *hit, ray__counts *qc)
{
    const ray__instance *outer_inst = qc->inst, *in;
    const ray_ray *outer_ray = qc->world_ray;
    unsigned outer_id = qc->inst_id;
    ray_ray ro;
    ray_hit h;
    int found;

    if ((in = instance_enter(s, idx, r, &ro, qc)) == NULL)
        return 0;
    qc->inst = in;
    qc->inst_id = idx;
    qc->world_ray = r;
    found = query_child(in->child, &ro, &h, qc);
    qc->inst = outer_inst;
    qc->inst_id = outer_id;
    qc->world_ray = outer_ray;
    if (found <= 0)
        return 0;
    if (qc->any) {
        /* Any hit: only that there is one counts; t for the record. */
        memset(hit, 0, sizeof *hit);
        hit->t = ro.tmax;
        return RAY__HIT_FULL;
    }
    ray__instance_to_world(in, &h, hit);
    hit->inst_id = idx;
    return RAY__HIT_FULL;
}

/* The nearest hit of a child of triangles alone, its record not yet
** made (below, after the traversal it runs). */
static int child_tris_nearest(const ray_scene *child, ray_ray *r,
                              tri_best *tb, ray__counts *qc);

/*
** Instance idx of s against world ray r for an ungated nearest-hit query,
** where its child is of triangles alone (the usual instance): as
** instance_hit, but the hit's record is left to prim_fill_best, which
** makes it -- the child's record (tri_record) brought to world space --
** once per ray, for the nearest, where instance_hit made it at every
** instance hit.  A ray through a crowd of instances hits several before
** the nearest: in a game's frame (bench/game.c), two a ray that hits.
** The same functions on the same numbers, so the same record.  1 with
** r->tmax shrunk and *best holding it; 0 on a miss (qc->stale set if
** the child changed since s was committed).
*/
static int instance_nearest(const ray_scene *s, unsigned idx, ray_ray *r,
                            prim_best *best, ray__counts *qc)
{
    const ray__instance *in;
    ray_ray ro;
    tri_best tb;

    if ((in = instance_enter(s, idx, r, &ro, qc)) == NULL ||
        !trav_usable(&ro) || !child_tris_nearest(in->child, &ro, &tb, qc))
        return 0;
    /* The triangle's ids, which its record reads at the end of the
    ** walk, asked of the cache now: they lie apart from its leaf, and
    ** their miss was two thirds of the record's time in a game's frame
    ** (perf annotate, bench/game frame, issue 36). */
    RAY__PREFETCH(&in->child->tri_ids[tb.index]);
    r->tmax = ro.tmax;
    best->h.t = ro.tmax;
    best->deferred = idx;
    best->child = in->child;
    best->tri = tb;
    return 1;
}

/*
** Item "item" of the BVH over the bounded kinds against r, the interval
** shrunk to a hit and the nearest kept in *best (NULL for any hit): an
** instance (its own mask passed on a gated query) by descending into it,
** every other kind through prim_candidate.
*/
static int prim_test(const ray_scene *s, unsigned item, ray_ray *r,
                     void *best, ray__counts *qc)
{
    unsigned idx = s->prim_bvh.items[item];
    const ray__prim *p = &s->prims[idx];
    ray_hit h;
    int k;

    if (p->kind != RAY__KIND_INSTANCE)
        k = prim_candidate(s, idx, r, &h, qc);
    else if (qc->gate != NULL && (p->mask & qc->gate->mask) == 0)
        k = 0;
    else if (best != NULL && qc->gate == NULL &&
             tris_only(s->instances[p->surface].child))
        return instance_nearest(s, idx, r, best, qc);
    else
        k = instance_hit(s, idx, r, &h, qc);
    if (!k)
        return 0;
    r->tmax = h.t;
    if (best != NULL)
        prim_keep(best, idx, k, &h);
    return 1;
}

/*
** Item "item" of the BVH of a scene of instances alone, each of a child
** of triangles alone, ungated (s->instances_of_tris, commit.c): what
** prim_test does for such an item, without asking its kind and gate.
*/
static inline int instance_test(const ray_scene *s, unsigned item,
                                ray_ray *r, void *best, ray__counts *qc)
{
    unsigned idx = s->prim_bvh.items[item];
    ray_hit h;

    if (best != NULL)
        return instance_nearest(s, idx, r, best, qc);
    if (!instance_hit(s, idx, r, &h, qc))
        return 0;
    r->tmax = h.t;
    return 1;
}

/* A slot pushed on the traversal stack: what it will read first (an
** inner node's boxes, a triangle leaf's float rows) asked of the cache
** now, as it is popped after the nearer slot's work. */
static inline void prefetch_slot(const ray_scene *s, const ray__bvh *bvh,
                                 unsigned child, unsigned count, int leaf)
{
    if (count == 0)
        prefetch_bytes(&bvh->wide[child], sizeof(ray__wnode));
    else if (leaf == LEAF_TRIANGLES)
        prefetch_bytes(s->leaf_f + RAY__LEAF_ROWS * (size_t)child,
                       RAY__LEAF_ROWS * sizeof(float) *
                           (count & ~RAY__LEAF));
}

/* A node's slot waiting on the traversal stack: child and count as in
** ray__wnode, and where the ray enters its box. */
typedef struct pending {
    unsigned child, count;
    float t;
} pending;


/* walk's "grown" when the caller does not fix it (traverse): read from
** the ray's lanes.  The walks of triangles alone fix it (walk_tris): at
** 1 (tmin >= 0, nearly every ray) the node test's two choices on it fold
** away: camera rays that enter the box and miss 1.05-1.07 times
** as fast, the other rows the same (bench/raycost, RAYCOST_AB both ways
** round, issue 34). */
#define GROWN_ASK (-1)

/*
** Ordered traversal: of the children a ray enters, the nearest is visited
** next and the others pushed with their entry distances, the farthest
** deepest, so they are popped nearest first and only if still in front
** of the nearest hit found since.  One child entered (the usual case deep
** in the tree) needs no stack at all, two a single compare.  "any": stop
** at the first hit.  "leaf" picks the primitive test.
*/
static RAY__INLINE int walk(const ray_scene *s, const ray__bvh *bvh,
                            trav *tr, ray_ray *r, int leaf, void *best,
                            int any, int grown, ray__counts *qc)
{
    pending stack[RAY__WIDTH * 64];   /* WIDTH - 1 a level, 64 levels */
    unsigned child = 0, count = 0;    /* the root: an inner node */
    float tmax = trav_tmax(tr, r->tmax);  /* earlier hits shrank it */
    float tpop = with_slack(tmax);        /* what popped entries face */
    int sp = 0, found = 0;
    lanes l;

    if (bvh->n_wide == 0)
        return 0;
    lanes_init(&l, tr);
    if (grown == GROWN_ASK)
        grown = l.grown;
    for (;;) {
        if (count == 0) {                           /* an inner node */
            const ray__wnode *q = &bvh->wide[child];
            float entry[RAY__WIDTH];
            unsigned mask = boxes_hit(q, &l, tmax, tpop, grown, entry);
            int k0, k1, base, j;

            RAY__WORK(RAY__WORK_NODES, 1);
            if (mask == 0)
                goto pop;
            k0 = lowest_bit(mask);
            mask &= mask - 1;
            if (mask == 0) {
                child = q->child[k0];
                count = q->count[k0];
                continue;
            }
            k1 = lowest_bit(mask);
            mask &= mask - 1;
            if (mask == 0) {
                /* Any hit will do: no order (an occluder found a little
                ** later costs less than ordering every node). */
                int near = !any && entry[k1] < entry[k0] ? k1 : k0;
                int far = near == k0 ? k1 : k0;
                stack[sp].child = q->child[far];
                stack[sp].count = q->count[far];
                prefetch_slot(s, bvh, q->child[far], q->count[far], leaf);
                stack[sp++].t = entry[far];
                child = q->child[near];
                count = q->count[near];
                continue;
            }
            /* Three or more: push them all, insertion-sorted so the
            ** nearest is on top (unsorted for any hit), and pop it. */
            base = sp;
            for (mask |= 1u << k0 | 1u << k1; mask != 0; mask &= mask - 1) {
                int k = lowest_bit(mask);
                pending p;
                p.child = q->child[k];
                p.count = q->count[k];
                p.t = entry[k];
                prefetch_slot(s, bvh, p.child, p.count, leaf);
                for (j = sp; !any && j > base && stack[j - 1].t < p.t; j--)
                    stack[j] = stack[j - 1];
                stack[j] = p;
                sp++;
            }
            sp--;
            child = stack[sp].child;
            count = stack[sp].count;
            continue;
        }
        if (leaf == LEAF_TRIANGLES) {               /* a leaf */
            unsigned n = count & ~RAY__LEAF;
            qc->tests[RAY_PRIM_TRIANGLE] += n;
            RAY__WORK(RAY__WORK_LEAVES, 1);
            if (tri_leaf(s, tr, child, child + n, r, best, any, qc)) {
                found = 1;
                if (any)
                    return found;
                tmax = trav_tmax(tr, r->tmax);
                tpop = with_slack(tmax);
            }
        } else if (leaf == LEAF_INSTANCES) {
            unsigned i, end = child + (count & ~RAY__LEAF);
            for (i = child; i < end; i++) {
                if (instance_test(s, i, r, best, qc)) {
                    found = 1;
                    if (any)
                        return found;
                    tmax = trav_tmax(tr, r->tmax);
                    tpop = with_slack(tmax);
                }
            }
        } else {
            unsigned i, end = child + (count & ~RAY__LEAF);
            for (i = child; i < end; i++) {
                if (prim_test(s, i, r, best, qc)) {
                    found = 1;
                    if (any)
                        return found;
                    tmax = trav_tmax(tr, r->tmax);
                    tpop = with_slack(tmax);
                }
            }
        }
    pop:
        /* An entry beyond the interval's end, which a hit shrank, is
        ** dropped.  An any-hit walk returns at its first hit, so its
        ** interval never shrinks and nothing it pushed (each within the
        ** interval then) lies beyond: it never looks. */
        do {
            if (sp == 0)
                return found;
            sp--;
        } while (!any && stack[sp].t > tpop);
        child = stack[sp].child;
        count = stack[sp].count;
    }
}

/* walk with the ray's grown (trav_grown) read at run time. */
static RAY__INLINE int traverse(const ray_scene *s, const ray__bvh *bvh,
                                trav *tr, ray_ray *r, int leaf,
                                void *best, int any, ray__counts *qc)
{
    return walk(s, bvh, tr, r, leaf, best, any, GROWN_ASK, qc);
}

/* The triangle BVH of s walked with grown fixed (GROWN_ASK says why):
** two copies of the walk, each without the node test's choices on it. */
static RAY__INLINE int walk_tris(const ray_scene *s, trav *tr, ray_ray *r,
                                 void *best, int any, ray__counts *qc)
{
    return trav_grown(tr)
               ? walk(s, &s->tri_bvh, tr, r, LEAF_TRIANGLES, best, any, 1, qc)
               : walk(s, &s->tri_bvh, tr, r, LEAF_TRIANGLES, best, any, 0,
                      qc);
}

/* The BVH of a scene of instances alone (s->instances_of_tris) walked
** with grown fixed, as walk_tris walks the triangles. */
static RAY__INLINE int walk_instances(const ray_scene *s, trav *tr,
                                      ray_ray *r, void *best, int any,
                                      ray__counts *qc)
{
    return trav_grown(tr)
               ? walk(s, &s->prim_bvh, tr, r, LEAF_INSTANCES, best, any, 1,
                      qc)
               : walk(s, &s->prim_bvh, tr, r, LEAF_INSTANCES, best, any, 0,
                      qc);
}

/*
** The nearest hit of child "child", a scene of triangles alone, along its
** ray r (usable), r->tmax shrunk to it and its triangle in *tb (no
** record yet): as query_nearest_tris walks it (walk_tris): rays onto 1,000 instances 1,750 -> 1,727
** instructions a ray (callgrind, bench/game DATA instances), ours /
** Embree in time 1.68, 1.78, 1.84 -> 1.63, 1.70, 1.64 (bench/game, three
** interleaved runs; issue 36).
*/
static int child_tris_nearest(const ray_scene *child, ray_ray *r,
                              tri_best *tb, ray__counts *qc)
{
    trav tr;

    tri_best_start(tb);
    if (child->tri_bvh.n_wide == 0 ||
        !trav_setup(&tr, r, &child->lo, &child->hi))
        return 0;
    return walk_tris(child, &tr, r, tb, 0, qc);
}

#include "query/few.h"

/* The bounded primitives of s along r, by traversal (the traversal data
** set up first if *ready is 0) or one after another (few_spheres_along,
** ungated). */
static RAY__INLINE int prims_along(const ray_scene *s, trav *tr, int *ready,
                              ray_ray *r, void *best, int any,
                              ray__counts *qc)
{
    unsigned i, tested;
    int found = 0;

    if (!s->few_spheres) {
        if (!*ready)
            trav_init(tr, r);
        *ready = 1;
        return traverse(s, &s->prim_bvh, tr, r, LEAF_PRIMS, best, any, qc);
    }
    if (qc->gate != NULL) {
        for (i = 0; i < s->prim_bvh.n_items; i++)
            if (prim_test(s, i, r, best, qc)) {
                found = 1;
                if (any)
                    return 1;
            }
        return found;
    }
    found = few_spheres_along(s, r, best, any, qc->uv, &tested);
    if (tested > 0)
        ray__count_tests(qc, RAY_PRIM_SPHERE, tested);
    return found;
}

/* Plane i of s against r, gated or not: prim_candidate's answer, the
** ungated one without the kinds' dispatch (ray__plane_candidate). */
static inline int plane_candidate(const ray_scene *s, unsigned i,
                                  const ray_ray *r, ray_hit *h,
                                  ray__counts *qc)
{
    if (qc->gate != NULL)
        return prim_candidate(s, i, r, h, qc);
    ray__count_tests(qc, RAY_PRIM_PLANE, 1);
    return ray__plane_candidate(s, i, r, h);
}

/* The triangles of s along r (the traversal data set up first if *ready
** is 0; not at all for a scene without triangles). */
static inline int tris_along(const ray_scene *s, trav *tr, int *ready,
                             ray_ray *r, void *best, int any,
                             ray__counts *qc)
{
    if (s->tri_bvh.n_wide == 0)
        return 0;
    if (!*ready)
        trav_init(tr, r);
    *ready = 1;
    return traverse(s, &s->tri_bvh, tr, r, LEAF_TRIANGLES, best, any, qc);
}

/* A fresh query's state, as far as a query of triangles alone without
** counts reads it (query_nearest_tris): no triangle tests, ungated.
** Such a query meets no other kind, so it never reads qc->kinds (which
** counts_start zeroes: one store less on a ray that misses the mesh). */
static void counts_light(ray__counts *qc, int any)
{
    qc->tests[RAY_PRIM_TRIANGLE] = 0;   /* the others by ray__count_tests */
    qc->gate = NULL;
    qc->any = any;
    qc->stale = 0;
    qc->inst_id = RAY_INVALID_ID;
    qc->inst = NULL;
    qc->world_ray = NULL;
    qc->uv = 1;
}

/* A fresh query's state: no counts, gate g (NULL: ungated). */
static void counts_start(ray__counts *qc, const ray__gate *g, int any)
{
    counts_light(qc, any);
    qc->kinds = 0;
    qc->gate = g;
    qc->failures = 0;
    qc->filter_calls = 0;
}

/*
** The nearest hit of s along rr (usable), rr->tmax shrunk to it, into
** *hit; counted and gated by qc.  Planes first, then the bounded kinds,
** then the triangles, each shrinking the interval for the next.
*/
static int nearest_core(const ray_scene *s, ray_ray *rr, ray_hit *hit,
                        ray__counts *qc)
{
    prim_best best;
    tri_best tb;
    trav tr;
    int found = 0, ready = 0;
    size_t i;

    best.deferred = RAY_INVALID_ID;
    tri_best_start(&tb);
    for (i = 0; i < s->n_planes; i++) {
        ray_hit h;
        int k = plane_candidate(s, s->planes[i], rr, &h, qc);
        if (k) {
            rr->tmax = h.t;
            prim_keep(&best, s->planes[i], k, &h);
            found = 1;
        }
    }
    if (prims_along(s, &tr, &ready, rr, &best, 0, qc))
        found = 1;
    if (tris_along(s, &tr, &ready, rr, &tb, 0, qc) &&
        tri_record(s, &tb, rr->tmax, &best.h)) {
        best.deferred = RAY_INVALID_ID;
        found = 1;
    }
    /* The record of the nearest, once per ray. */
    if (found && !prim_fill_best(s, rr, &best, qc))
        found = 0;
    if (found)
        *hit = best.h;
    return found;
}

/* Is anything of s along rr (usable)?  Counted and gated by qc. */
static int any_core(const ray_scene *s, ray_ray *rr, ray__counts *qc)
{
    ray_hit h;
    trav tr;
    size_t i;
    int ready = 0;

    for (i = 0; i < s->n_planes; i++)
        if (plane_candidate(s, s->planes[i], rr, &h, qc))
            return 1;
    return prims_along(s, &tr, &ready, rr, NULL, 1, qc) ||
           tris_along(s, &tr, &ready, rr, NULL, 1, qc);
}

#include "query/plain.h"

static int query_nearest_gated(const ray_scene *s, const ray_ray *r,
                               const ray__gate *g, int uv, ray_hit *hit,
                               ray_stats *st)
{
    ray__counts qc;
    ray_ray rr;
    ray_hit best;
    int found;

    if (g == NULL && st == NULL && tris_only(s))
        return query_nearest_tris(s, r, hit);
    if (g == NULL && st == NULL && s->instances_of_tris)
        return query_nearest_instances(s, r, hit);
    if (g == NULL && few_prims_only(s))
        return query_nearest_few(s, r, uv, hit, st);
    if (!trav_usable(r))
        return 0;
    ray_copy(&rr, r);
    counts_start(&qc, g, 0);
    qc.uv = uv;
    found = nearest_core(s, &rr, &best, &qc);
    add_counts(st, &qc);
    if (qc.stale)
        return -RAY_ESTATE;
    if (found)
        ray__hit_store(hit, &best);
    return found;
}

static int query_any_gated(const ray_scene *s, const ray_ray *r,
                           const ray__gate *g, ray_stats *st)
{
    ray__counts qc;
    ray_ray rr;
    int hit;

    if (g == NULL && st == NULL && tris_only(s))
        return query_any_tris(s, r);
    if (g == NULL && st == NULL && s->instances_of_tris)
        return query_any_instances(s, r);
    if (g == NULL && few_prims_only(s))
        return query_any_few(s, r, st);
    if (!trav_usable(r))
        return 0;
    ray_copy(&rr, r);
    counts_start(&qc, g, 1);
    hit = any_core(s, &rr, &qc);
    add_counts(st, &qc);
    return qc.stale ? -RAY_ESTATE : hit;
}

/* The traversal data of r as this copy computes it (query.h's
** ray__trav_data_*, for the tests). */
static void trav_data(const ray_ray *r, uint32_t f[13], size_t at[6])
{
    trav tr;
    int k;

    trav_init(&tr, r);
    for (k = 0; k < 3; k++) {
        memcpy(&f[k], &tr.o_near[k], sizeof f[k]);
        memcpy(&f[3 + k], &tr.o_far[k], sizeof f[k]);
        memcpy(&f[6 + k], &tr.inv[k], sizeof f[k]);
        memcpy(&f[10 + k], &tr.inv_far[k], sizeof f[k]);
        at[k] = tr.near_at[k];
        at[3 + k] = tr.far_at[k];
    }
    memcpy(&f[9], &tr.tmin, sizeof f[9]);
}

/*
** An instance's child inside a parent's query: nearest or any as the
** parent's query is, with its counts and gate.  A child of triangles
** alone (the usual one: a mesh placed many times) goes straight to its
** triangles, as query_nearest_tris and query_any_tris do, without the
** planes' loop, the bounded kinds' walk and the deferred record of
** nearest_core and any_core, which find nothing in it: the same
** functions on the same numbers, so the same answers.
*/
static int query_child(const ray_scene *child, ray_ray *r, ray_hit *hit,
                       ray__counts *qc)
{
    tri_best tb;
    trav tr;

    if (!trav_usable(r))
        return 0;
    if (!tris_only(child)) {
        if (qc->any)
            return any_core(child, r, qc);
        return nearest_core(child, r, hit, qc);
    }
    if (!qc->any)
        return child_tris_nearest(child, r, &tb, qc) &&
               tri_record(child, &tb, r->tmax, hit);
    return child->tri_bvh.n_wide != 0 &&
           trav_setup(&tr, r, &child->lo, &child->hi) &&
           traverse(child, &child->tri_bvh, &tr, r, LEAF_TRIANGLES, NULL, 1,
                    qc);
}

#endif

