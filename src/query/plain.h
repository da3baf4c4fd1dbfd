/* SPDX-License-Identifier: MIT */
/*
** plain.h -- part of the query template (traverse.h): the plain queries
** (no options, nothing gated, no counts) of the two kinds of scene that
** skip the general query's set-up: a scene of triangles alone, and a
** scene of instances alone, each of a child of triangles alone.  Each is
** its set-up and the scene's box test, then a walk apart (not inlined).
** ray_intersect and ray_occluded take them first (intersect.c), and the
** general query hands such scenes to them (traverse.h).
*/
#ifndef RAY_PLAIN_H
#define RAY_PLAIN_H

/*
** The common case whole: a scene of triangles alone (no planes, no
** bounded kinds, so no instances) asked without a gate or counts.  What
** nearest_core and any_core do for such a scene, step for step -- the
** traversal data, the ordered walk of the triangle BVH, the record of
** the nearest -- without what only other scenes need (the planes' loop,
** the bounded kinds' walk, the deferred record, a query's counts zeroed
** and added up): that set-up was a fifth of the instructions of a ray
** that misses the mesh's box (bench/raycost under callgrind, issue 34).
** Only the triangle count the leaves add to is read (never: no counts are
** asked), so it alone is set.  The same answers, bit for bit: the same
** functions in the same order (tests/check_bvh.c compares every scene
** kind both ways).
*/
/* The walk and record of query_nearest_tris, for a ray whose traversal
** data *tr is set up: a function of its own, not inlined, so that a ray
** that misses the scene's box never pays for its frame (the traversal
** stack, six registers saved, the stack aligned for the lanes). */
static RAY__NOINLINE int nearest_tris_walk(const ray_scene *s, trav *tr,
                                           const ray_ray *r, ray_hit *hit)
{
    ray__counts qc;
    tri_best tb;
    ray_ray rr;

    counts_light(&qc, 0);
    ray_copy(&rr, r);
    tri_best_start(&tb);
    /* The record straight into *hit: tri_record writes nothing unless it
    ** fills it (tri_fill checks first), so a miss leaves it untouched. */
    return walk_tris(s, tr, &rr, &tb, 0, &qc) &&
           tri_record(s, &tb, rr.tmax, hit);
}

/* Only the set-up and the test of the scene's box come before the call
** (trav_setup is inlined here), so a ray that misses the box costs no
** more than they do: 278 instructions, 202 now, and 1.3 times as fast
** (bench/raycost's first row under callgrind, and RAYCOST_AB both ways
** round, issue 34); the other rows the same. */
static int query_nearest_tris(const ray_scene *s, const ray_ray *r,
                              ray_hit *hit)
{
    trav tr;

    if (!trav_usable(r) || s->tri_bvh.n_wide == 0 ||
        !trav_setup(&tr, r, &s->lo, &s->hi))
        return 0;
    return nearest_tris_walk(s, &tr, r, hit);
}

/* query_any_tris's walk, apart as nearest_tris_walk is. */
static RAY__NOINLINE int any_tris_walk(const ray_scene *s, trav *tr,
                                       const ray_ray *r)
{
    ray__counts qc;
    ray_ray rr;

    counts_light(&qc, 1);
    ray_copy(&rr, r);
    return walk_tris(s, tr, &rr, NULL, 1, &qc);
}

static int query_any_tris(const ray_scene *s, const ray_ray *r)
{
    trav tr;

    if (!trav_usable(r) || s->tri_bvh.n_wide == 0 ||
        !trav_setup(&tr, r, &s->lo, &s->hi))
        return 0;
    return any_tris_walk(s, &tr, r);
}

/*
** A plain query of a scene of instances alone, each of a child of
** triangles alone (s->instances_of_tris, commit.c): what nearest_core and
** any_core do for such a scene, step for step -- the traversal data, the
** ordered walk of the instances' BVH into each child's triangle walk,
** the record of the nearest made once -- without what only other scenes
** need: the general query's set-up (its counts zeroed and added up), the
** planes' loop, and each item's kind and gate (prim_test).  The scene's
** box is tested first, as query_nearest_tris tests its own, so that a ray
** that misses it stores nothing.  The same functions on the same
** numbers, so the same answers, -RAY_ESTATE included where an instance
** met is stale (tests/check_bvh.c compares both ways, in both
** copies).  Apart from the set-up, not inlined, as nearest_tris_walk is.
*/
static RAY__NOINLINE int nearest_instances_walk(const ray_scene *s, trav *tr,
                                                const ray_ray *r,
                                                ray_hit *hit)
{
    ray__counts qc;
    prim_best best;
    ray_ray rr;
    int found;

    counts_start(&qc, NULL, 0);
    ray_copy(&rr, r);
    best.deferred = RAY_INVALID_ID;
    found = walk_instances(s, tr, &rr, &best, 0, &qc);
    if (qc.stale)
        return -RAY_ESTATE;
    if (!found || !prim_fill_best(s, &rr, &best, &qc))
        return 0;
    ray__hit_store(hit, &best.h);
    return 1;
}

static int query_nearest_instances(const ray_scene *s, const ray_ray *r,
                                   ray_hit *hit)
{
    trav tr;

    if (!trav_usable(r) || !trav_setup(&tr, r, &s->lo, &s->hi))
        return 0;
    return nearest_instances_walk(s, &tr, r, hit);
}

/* query_any_instances's walk, apart as nearest_instances_walk is. */
static RAY__NOINLINE int any_instances_walk(const ray_scene *s, trav *tr,
                                            const ray_ray *r)
{
    ray__counts qc;
    ray_ray rr;
    int hit;

    counts_start(&qc, NULL, 1);
    ray_copy(&rr, r);
    hit = walk_instances(s, tr, &rr, NULL, 1, &qc);
    return qc.stale ? -RAY_ESTATE : hit;
}

static int query_any_instances(const ray_scene *s, const ray_ray *r)
{
    trav tr;

    if (!trav_usable(r) || !trav_setup(&tr, r, &s->lo, &s->hi))
        return 0;
    return any_instances_walk(s, &tr, r);
}

#endif /* RAY_PLAIN_H */
