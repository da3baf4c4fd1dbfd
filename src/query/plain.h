/* SPDX-License-Identifier: MIT */
/*
** plain.h -- part of the query template (traverse.h): the short paths
** that skip the general query's set-up.  The plain queries (no options,
** nothing gated, no counts) of a scene of triangles alone and of a scene
** of instances alone, each of a child of triangles alone: each is its
** set-up and the scene's box test, then a walk apart (not inlined).  And
** the ungated queries, counted or not, of a scene of planes, a few
** spheres and triangles alone.  ray_intersect and ray_occluded take the
** plain ones first (intersect.c), and the general query hands such
** scenes to them (traverse.h).
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

/*
** A scene of planes, a few spheres and triangles alone (no other kind,
** so no instances: Whitted's, a mesh on a ground plane), asked without a
** gate, counts or not: what nearest_core and any_core do for such a
** scene, step for step -- the planes one after another, then the spheres
** (few_spheres_along), then the triangles (few_tris_along), the record
** of the nearest made once -- without what only other scenes need: a
** query's counts zeroed, gathered and added up kind by kind
** (add_counts), the bounded kinds' walk, the gate's checks, and the
** record copied twice on its way out.  The tests are counted straight
** into *st, the same sums.  The same functions on the same numbers, so
** the same answers and counts (tests/check_bvh.c compares them with the
** general query's).
*/
static int few_prims_only(const ray_scene *s)
{
    return s->few_spheres;
}

static void few_counts(ray_stats *st, unsigned long long planes,
                       unsigned long long spheres)
{
    if (st == NULL)
        return;
    st->tests_by_kind[RAY_PRIM_PLANE] += planes;
    st->tests_by_kind[RAY_PRIM_SPHERE] += spheres;
    st->tests += planes + spheres;
}

/*
** The triangles of such a scene (a mesh on a ground plane: examples/mesh)
** along rr, after its planes and spheres: query_nearest_tris's set-up,
** the scene's box test first, and its walk; tb: where the nearest goes
** (NULL: any hit).  The triangle tests the walk counted go to *st (if
** not NULL), as the general query's leaves count them (none where the
** box is missed, where its root node would have let nothing through).
** Against the general query's tris_along: no box test before the walk,
** whose set-up the rays that pass beside the mesh paid (most of a
** ground's shadow rays), and no counts zeroed and gathered for kinds the
** scene lacks.  Called only where the scene has triangles
** (s->tri_bvh.n_wide), and not inlined: the walk's frame would cost the
** queries of a scene without them (Whitted's render: 21M instructions).
*/
static RAY__NOINLINE int few_tris_along(const ray_scene *s, ray_ray *rr,
                                        tri_best *tb, ray_stats *st)
{
    ray__counts qc;
    trav tr;
    int found;

    if (!trav_setup(&tr, rr, &s->lo, &s->hi))
        return 0;
    if (tb != NULL)
        tri_best_start(tb);
    counts_light(&qc, tb == NULL);
    /* Two copies of the walk, each with "any" fixed (its choices off the
    ** node loop), as query_nearest_tris and query_any_tris have. */
    found = tb == NULL ? walk_tris(s, &tr, rr, NULL, 1, &qc)
                       : walk_tris(s, &tr, rr, tb, 0, &qc);
    if (st != NULL) {
        st->tests_by_kind[RAY_PRIM_TRIANGLE] += qc.tests[RAY_PRIM_TRIANGLE];
        st->tests += qc.tests[RAY_PRIM_TRIANGLE];
    }
    return found;
}

static int query_nearest_few(const ray_scene *s, const ray_ray *r, int uv,
                             ray_hit *hit, ray_stats *st)
{
    prim_best best;
    tri_best tb;
    ray_ray rr;
    unsigned tested;
    size_t i;
    int found = 0;

    if (!trav_usable(r))           /* nothing tested, nothing counted */
        return 0;
    ray_copy(&rr, r);
    best.deferred = RAY_INVALID_ID;
    for (i = 0; i < s->n_planes; i++) {
        ray_hit h;
        int k = ray__plane_candidate(s, s->planes[i], &rr, &h);
        if (k) {
            rr.tmax = h.t;
            prim_keep(&best, s->planes[i], k, &h);
            found = 1;
        }
    }
    if (few_spheres_along(s, &rr, &best, 0, uv, &tested))
        found = 1;
    if (s->tri_bvh.n_wide != 0 && few_tris_along(s, &rr, &tb, st) &&
        tri_record(s, &tb, rr.tmax, &best.h)) {
        best.deferred = RAY_INVALID_ID;
        found = 1;
    }
    few_counts(st, s->n_planes, tested);
    /* prim_fill_best's fill: no instance here, so no child. */
    if (found && best.deferred != RAY_INVALID_ID &&
        !ray__prim_fill(s, best.deferred, &rr, best.h.t, uv, &best.h))
        found = 0;
    if (found)
        ray__hit_store(hit, &best.h);
    return found;
}

/* The planes and spheres of such a scene along rr (usable), any hit:
** 1 if one is hit; counted into *st (if not NULL), the planes up to the
** one hit, else all of them and the spheres tested.  What query_any_few
** asks before the triangles, and a packet's lanes too (packet.h). */
static RAY__INLINE int few_any_prims(const ray_scene *s, ray_ray *rr,
                                     ray_stats *st)
{
    unsigned tested;
    size_t i;
    int hit;

    for (i = 0; i < s->n_planes; i++) {
        ray_hit h;
        if (ray__plane_candidate(s, s->planes[i], rr, &h)) {
            few_counts(st, i + 1, 0);
            return 1;
        }
    }
    hit = few_spheres_along(s, rr, NULL, 1, 1, &tested);
    few_counts(st, s->n_planes, tested);
    return hit;
}

static int query_any_few(const ray_scene *s, const ray_ray *r,
                         ray_stats *st)
{
    ray_ray rr;

    if (!trav_usable(r))
        return 0;
    ray_copy(&rr, r);
    return few_any_prims(s, &rr, st) ||
           (s->tri_bvh.n_wide != 0 && few_tris_along(s, &rr, NULL, st));
}

#endif /* RAY_PLAIN_H */
