/* SPDX-License-Identifier: MIT */
/*
** commit.c -- committing a scene: what changed is built again (the
** triangle BVH rebuilt or refitted, the BVH over the other bounded kinds
** and the plane list), instances' boxes are taken again, and the
** scene's effects, gate and box summed up.  Read-only until the next
** change.
*/
#include <stdio.h>
#include <string.h>

#include "core/platform.h"
#include "core/tasks.h"
#include "scene/scene.h"

/*
** The BVH over the bounded kinds but triangles: a curved surface's test
** costs up to thousands of box tests, so every split the SAH finds is
** taken, down to single primitives (accel/sah.c).  The boxes on the
** calling thread: a user kind's comes from the caller's bounds callback,
** which may not be thread-safe.
*/
static const ray__bvh_costs prim_costs = {1.0f, 1, 0, NULL};

/* The bounded primitives' ids, for the box callback. */
typedef struct prim_list {
    const ray_scene *s;
    const unsigned *ids;
} prim_list;

/* The float box of a bounded non-triangle primitive, rounded outward. */
static void prim_box(const void *ud, size_t item, float *blo, float *bhi)
{
    const prim_list *pl = ud;
    const ray_scene *s = pl->s;
    ray_vec3 lo, hi;

    ray__prim_box(s, &s->prims[pl->ids[item]], &lo, &hi);
    /* lo - r and hi + r round too: one more float step covers that. */
    blo[0] = nextafterf(ray__float_down(lo.x), -HUGE_VALF);
    blo[1] = nextafterf(ray__float_down(lo.y), -HUGE_VALF);
    blo[2] = nextafterf(ray__float_down(lo.z), -HUGE_VALF);
    bhi[0] = nextafterf(ray__float_up(hi.x), HUGE_VALF);
    bhi[1] = nextafterf(ray__float_up(hi.y), HUGE_VALF);
    bhi[2] = nextafterf(ray__float_up(hi.z), HUGE_VALF);
}

/* Is geometry i seen by queries, and of class c? */
static int prim_live(const ray_scene *s, size_t i, ray__class c)
{
    const ray__prim *p = &s->prims[i];
    return p->enabled && !p->removed && ray__kind_class(p->kind) == c;
}

/*
** The BVH over the bounded primitives but triangles: spheres, polygons,
** the curved surfaces, the shapes and the instances (items are prim
** indices), and the list of planes, which have no bounds and are tested
** on every ray; of enabled geometry only.  Built aside and swapped in, so
** a failure keeps the old ones.
*/
static int rebuild_prims(ray_scene *s, ray__progress *prog)
{
    size_t n_bounded = 0, n_planes = 0, nb = 0, np = 0, i, k;
    unsigned *ids = NULL, *planes = NULL;
    ray__bvh fresh;
    prim_list pl;
    int rc = RAY_OK;

    for (i = 0; i < s->n_prims; i++) {
        n_planes += (size_t)prim_live(s, i, RAY__CLASS_UNBOUNDED);
        n_bounded += (size_t)prim_live(s, i, RAY__CLASS_BOUNDED);
    }
    if (n_planes > 0 &&
        (planes = ray__alloc(s, n_planes * sizeof *planes)) == NULL)
        return RAY_ENOMEM;
    if (n_bounded > 0 && (ids = ray__alloc(s, n_bounded * sizeof *ids)) == NULL)
        rc = RAY_ENOMEM;
    if (rc == RAY_OK) {
        for (i = 0; i < s->n_prims; i++) {
            if (prim_live(s, i, RAY__CLASS_UNBOUNDED))
                planes[np++] = (unsigned)i;
            else if (prim_live(s, i, RAY__CLASS_BOUNDED))
                ids[nb++] = (unsigned)i;
        }
        pl.s = s;
        pl.ids = ids;
        rc = ray__bvh_build(&s->alloc, prim_box, &pl, n_bounded, &prim_costs,
                            &s->scheduler, s->build_threads, NULL, prog,
                            &fresh);
    }
    if (rc == RAY_OK) {
        /* Items become prim indices. */
        for (k = 0; k < fresh.n_items; k++)
            fresh.items[k] = ids[fresh.items[k]];
        ray__bvh_free(&s->alloc, &s->prim_bvh);
        s->prim_bvh = fresh;
        ray__free(s, s->planes, s->n_planes * sizeof *s->planes);
        s->planes = planes;
        s->n_planes = n_planes;
    } else
        ray__free(s, planes, n_planes * sizeof *planes);
    ray__free(s, ids, n_bounded * sizeof *ids);
    return rc;
}

/*
** What the scene can ever need: the effects of the materials its enabled
** geometry uses (a material no geometry uses is never shaded;
** RAY_NO_MATERIAL is none), its instances' children's included, and
** shadow rays only if there is a light to cast them toward.  Also whether
** any geometry (a child's included) has a mask or a filter: else queries
** take the ungated path.
*/
static void scene_summary(ray_scene *s)
{
    unsigned e = 0;
    int gated = 0, instances = 0;
    size_t i;

    for (i = 0; i < s->n_prims; i++) {
        const ray__prim *p = &s->prims[i];
        if (!p->enabled || p->removed)
            continue;
        if (p->kind == RAY__KIND_INSTANCE) {
            const ray_scene *c = s->instances[p->surface].child;
            e |= c->material_effects;
            gated |= c->gated;
            instances = 1;
        } else if (p->material != RAY_NO_MATERIAL)
            e |= s->materials[p->material].effects;
        gated |= p->mask != ~0u || p->filter != NULL;
    }
    s->material_effects = e;
    /* A caustic needs a light, a surface that scatters photons and one
    ** that gathers them (L S+ D): else no photon is ever traced, and
    ** neither bit is an effect the scene can need. */
    if (s->n_lights == 0 || !(e & RAY_EFFECT_SCATTER) ||
        !(e & RAY_EFFECT_CAUSTICS))
        e &= ~(RAY_EFFECT_CAUSTICS | RAY_EFFECT_SCATTER);
    s->effects = s->n_lights == 0 ? e & ~RAY_EFFECT_SHADOW : e;
    s->gated = gated;
    s->has_instances = instances;
}

/*
** A scene of a few spheres (the Whitted scene has two) is not traversed:
** its spheres are tested one after another, as the planes are, and the
** ray's traversal data (trav_init: three divisions and six roundings to
** float) is then not set up at all unless the scene has triangles.  A
** sphere's test for t alone costs about what the box test of a node
** that would skip it does, and trav_init cost 9% of the Whitted
** render's profile (perf, examples/whitted 1024 x 768, one thread).  The
** answers are the traversal's: the box test only ever skips spheres that
** the ray misses.  Two spheres hit at exactly the same t are settled by
** the order they are tested in, in the BVH's leaf order here and in
** box-entry order there, so such a tie may go the other way
** (ray_intersect(3) leaves ties between kinds other than triangles
** unspecified).  Decided here, once, not by every query.
*/
static int few_spheres(const ray_scene *s)
{
    size_t i, n = s->prim_bvh.n_items;

    if (n > RAY__FEW_SPHERES)
        return 0;
    for (i = 0; i < n; i++)
        if (s->prims[s->prim_bvh.items[i]].kind != RAY__KIND_SPHERE)
            return 0;
    return 1;
}

/* The few spheres' lanes (ray__few_spheres), or every lane NaN where the
** scene has none such. */
static void few_spheres_lanes(ray_scene *s)
{
    size_t i, n = s->few_spheres ? s->prim_bvh.n_items : 0;

    for (i = 0; i < RAY__FEW_SPHERES; i++) {
        const ray__prim *p =
            i < n ? &s->prims[s->prim_bvh.items[i]] : NULL;
        s->few.cx[i] = p != NULL ? p->a.x : (double)NAN;
        s->few.cy[i] = p != NULL ? p->a.y : (double)NAN;
        s->few.cz[i] = p != NULL ? p->a.z : (double)NAN;
        s->few.rr[i] = p != NULL ? ray__sphere_miss_rr(p->radius)
                                 : (double)NAN;
    }
}

/*
** A scene of instances alone, each of a child of triangles alone, and
** ungated (a game's crowd of placed meshes, bench/game): its plain
** queries walk the BVH of the instances straight into each child's
** triangle walk (query/plain.h, query_nearest_instances), past the
** general query's set-up, the planes' loop and each item's kind and
** gate, which are nothing for it.  A child committed again since (its
** instances stale) may hold other kinds by then: the walk asks whether
** it is stale before it walks it, and answers -RAY_ESTATE as the general
** query does.  Any change to this scene uncommits it, so the answer holds
** until the next commit.  Decided here, once, as few_spheres is.
*/
static int instances_of_tris(const ray_scene *s)
{
    size_t i, n = s->prim_bvh.n_items;

    if (n == 0 || s->n_planes != 0 || s->tri_bvh.n_wide != 0 || s->gated)
        return 0;
    for (i = 0; i < n; i++) {
        const ray__prim *p = &s->prims[s->prim_bvh.items[i]];
        const ray_scene *c;
        if (p->kind != RAY__KIND_INSTANCE)
            return 0;
        c = s->instances[p->surface].child;
        if (c->n_planes != 0 || c->prim_bvh.n_wide != 0)
            return 0;
    }
    return 1;
}

/* The box of everything queries may hit but planes: the union of the
** roots of both BVHs (float, rounded outward from the geometry). */
static void scene_box(ray_scene *s)
{
    const ray__bvh *b[2];
    int i, k;

    b[0] = &s->tri_bvh;
    b[1] = &s->prim_bvh;
    s->lo = v3(HUGE_VAL, HUGE_VAL, HUGE_VAL);
    s->hi = v3(-HUGE_VAL, -HUGE_VAL, -HUGE_VAL);
    for (i = 0; i < 2; i++) {
        const ray__wnode *q;
        if (b[i]->n_wide == 0)
            continue;
        q = &b[i]->wide[0];
        for (k = 0; k < RAY__WIDTH; k++) {
            s->lo = v3(fmin(s->lo.x, (double)q->lo[0][k]),
                       fmin(s->lo.y, (double)q->lo[1][k]),
                       fmin(s->lo.z, (double)q->lo[2][k]));
            s->hi = v3(fmax(s->hi.x, (double)q->hi[0][k]),
                       fmax(s->hi.y, (double)q->hi[1][k]),
                       fmax(s->hi.z, (double)q->hi[2][k]));
        }
    }
}

/* Instance geometry i, live, whose child was committed again since
** (or is uncommitted now): its box must be taken again. */
static ray__instance *instance_behind(ray_scene *s, size_t i)
{
    const ray__prim *p = &s->prims[i];
    ray__instance *in;

    if (p->kind != RAY__KIND_INSTANCE || p->removed)
        return NULL;
    in = &s->instances[p->surface];
    return ray__instance_stale(in) ? in : NULL;
}

/*
** Instances whose child was committed again since: their box is taken
** again and the top level rebuilt.  Every such instance is checked
** first (a child uncommitted now, or grown planes or instances, is an
** error that changes nothing); then the scene is marked changed
** (ray__touch), so that if the rebuild fails the scene answers
** -RAY_ESTATE until a commit succeeds, rather than through old boxes.
*/
static int refresh_instances(ray_scene *s)
{
    ray__instance *in, next;
    size_t i;

    for (i = 0; i < s->n_prims; i++) {
        if ((in = instance_behind(s, i)) == NULL)
            continue;
        if (!in->child->committed)
            return ray__fail(s, RAY_ESTATE, "instance %zu: its scene was "
                             "changed and not committed again", i);
        if (in->child->n_planes > 0 || in->child->has_instances)
            return ray__fail(s, RAY_EINVAL, "instance %zu: its scene now "
                             "has planes or instances", i);
        next = *in;
        if (!ray__instance_box(&next))
            return ray__fail(s, RAY_EINVAL, "instance %zu: its transform "
                             "now maps its scene beyond +-2^1016", i);
    }
    for (i = 0; i < s->n_prims; i++) {
        if ((in = instance_behind(s, i)) == NULL)
            continue;
        (void)ray__instance_box(in);    /* in range: checked above */
        in->generation = in->child->generation;
        ray__touch(s, RAY__DIRTY_PRIMS);
    }
    return RAY_OK;
}

/* A commit's failure to build, in words: out of memory, or cancelled by
** the progress callback; either way nothing is committed. */
static int build_failed(ray_scene *s, int rc, const ray__progress *prog,
                        const char *what)
{
    if (rc == RAY_ECANCELED)
        return ray__fail(s, rc, "cancelled by the progress callback at %zu "
                         "of %zu primitives, building the BVH over %s (not "
                         "committed: the changes stay staged)", prog->done,
                         prog->total, what);
    return ray__fail(s, rc, "out of memory building the BVH over %s (not "
                     "committed: retry)", what);
}

/*
** The BVHs that changed, rebuilt (the triangles' refitted when only
** their vertices moved), reporting to prog (NULL: no callback).
*/
static int build_changed(ray_scene *s, ray__progress *prog)
{
    char what[64];
    int rc;

    if ((s->dirty & RAY__DIRTY_PRIMS) &&
        (rc = rebuild_prims(s, prog)) != RAY_OK)
        return build_failed(s, rc, prog, "the spheres, polygons, surfaces "
                            "and instances");
    s->dirty &= ~RAY__DIRTY_PRIMS;
    if (s->dirty & RAY__DIRTY_TRIS) {
        if ((rc = ray__triangles_rebuild(s, prog)) != RAY_OK) {
            snprintf(what, sizeof what, "%zu triangles", s->n_tris);
            return build_failed(s, rc, prog, what);
        }
    } else if (s->dirty & RAY__DIRTY_REFIT)
        ray__triangles_refit(s);
    return RAY_OK;
}

/*
** build_changed on a crew (core/tasks.h) where the scene builds on the
** built-in threads: the commit's passes (the build's levels and
** subtrees, its leaves and ids, its refits) share threads started once,
** where each started and joined its own.  The scene's scheduler is the
** crew's for the while: the passes hand it their tasks as they would a
** program's.  At most RAY__MAX_BUILD_THREADS threads, as the build
** takes.  Only for a commit that builds the triangles again: one that
** refits them, or builds the other kinds' BVH alone, makes a pass or two
** at most, where the crew's last wake-up and join cost more than it
** saves (a game's frame, ten characters refitted on two threads each:
** 3.18-3.37 ms before the crew, 3.38-3.67 with it; bench/game DATA
** frame, three interleaved runs; issue 36); their passes start their own
** threads, as before.
*/
static int build_on_crew(ray_scene *s, ray__progress *prog)
{
    ray_scheduler own = s->scheduler;
    unsigned threads = s->build_threads != 0 ? s->build_threads
                                             : ray__online_cpus();
    ray__crew crew;
    int rc;

    if (own.run != NULL || threads <= 1 || !(s->dirty & RAY__DIRTY_TRIS))
        return build_changed(s, prog);
    if (threads > RAY__MAX_BUILD_THREADS)
        threads = RAY__MAX_BUILD_THREADS;
    ray__crew_begin(&crew, &s->alloc, threads, 0);
    s->scheduler = ray__crew_scheduler(&crew);
    rc = build_changed(s, prog);
    s->scheduler = own;
    ray__crew_end(&crew);
    return rc;
}

/*
** The commit's progress record, when the scene has a callback and the
** commit rebuilds a BVH: the total is every primitive the rebuilds place
** (ray_scene_set_progress).  Returns RAY_OK with *out NULL (nothing to
** report) or ready, or RAY_ENOMEM (no lock for the build's threads).
*/
static int progress_start(ray_scene *s, ray__progress *p,
                          ray__progress **out)
{
    size_t i;

    *out = NULL;
    if (s->progress == NULL ||
        !(s->dirty & (RAY__DIRTY_PRIMS | RAY__DIRTY_TRIS)))
        return RAY_OK;
    p->fn = s->progress;
    p->ud = s->progress_ud;
    p->done = p->total = p->reported = 0;
    p->cancelled = 0;
    if (s->dirty & RAY__DIRTY_PRIMS)
        for (i = 0; i < s->n_prims; i++)
            p->total += (size_t)prim_live(s, i, RAY__CLASS_BOUNDED);
    if (s->dirty & RAY__DIRTY_TRIS)
        p->total += ray__triangles_live(s);
    if (ray__mutex_new(&s->alloc, &p->lock) != RAY_OK)
        return ray__fail(s, RAY_ENOMEM, "out of memory making the progress "
                         "callback's lock (not committed: retry)");
    *out = p;
    return RAY_OK;
}

/* The last report, done == total, once every BVH is built. */
static int progress_end(ray_scene *s, ray__progress *p, int rc)
{
    if (p == NULL)
        return rc;
    /* The builds' last report may have been done == total already: the
    ** callback hears it once (a scene of nothing to place hears 0 of 0). */
    if (rc == RAY_OK && (p->reported < p->total || p->total == 0)) {
        p->done = p->total;
        if (ray__progress_add(p, 0))
            rc = build_failed(s, RAY_ECANCELED, p, "the scene");
    }
    ray__mutex_free(&s->alloc, p->lock);
    return rc;
}

/*
** Build what changed (all of it the first time); the scene is then
** read-only until the next change.  A failure (out of memory, or a
** cancel from the progress callback) leaves the scene uncommitted with
** its changes still staged, so commit can be retried, and builds the
** same trees then.  A commit with nothing to do is a no-op.
*/
int ray_scene_commit(ray_scene *s)
{
    int rc = ray__begin(s, "ray_scene_commit");
    ray__progress record, *prog;

    if (rc != RAY_OK)
        return rc;
    if ((rc = refresh_instances(s)) != RAY_OK)
        return rc;
    if (s->committed && s->dirty == 0)
        return RAY_OK;
    if ((rc = progress_start(s, &record, &prog)) != RAY_OK)
        return rc;
    rc = progress_end(s, prog, build_on_crew(s, prog));
    if (rc != RAY_OK)
        return rc;
    /* ray_contains' labels follow the triangles (parity.c), but are built
    ** by the first ray_contains after a rebuild, not here: a commit of a
    ** scene that is never asked what contains a point does not pay for
    ** them (15-25% of the bunnies' cold commits).  A refit drops them
    ** for good until the next rebuild: its few milliseconds a frame
    ** (ray_scene_update_mesh) a grid would multiply by five (the 59k
    ** bunny: 2 ms, 11 ms with it), so a moving mesh's ray_contains walks
    ** its whole ray, exact as before the grid.  The lock that lets a
    ** query build them is made once; without it, no grid. */
    if (s->dirty & (RAY__DIRTY_TRIS | RAY__DIRTY_REFIT)) {
        ray__cgrid_free(s);
        s->cgrid_tried = !(s->dirty & RAY__DIRTY_TRIS);
    }
    if (s->cgrid_lock == NULL &&
        ray__mutex_new(&s->alloc, &s->cgrid_lock) != RAY_OK)
        s->cgrid_lock = NULL;
    /* Which meshes are closed: found by the first query that asks
    ** (ray__closed_ensure), or here when no lock lets a query write it
    ** (out of memory here: the queries answer RAY_ENOMEM). */
    if (s->dirty & (RAY__DIRTY_TRIS | RAY__DIRTY_REFIT))
        s->closed_known = s->cgrid_lock == NULL && ray__closed_all(s) == RAY_OK;
    /* The winding number's expansions (query/winding.c) follow the
    ** triangles and their closedness: dropped here, made again by the
    ** first query that needs them (none without the lock: every
    ** triangle is summed then). */
    if (s->dirty & (RAY__DIRTY_TRIS | RAY__DIRTY_REFIT)) {
        ray__free(s, s->wexp, s->n_wexp * sizeof *s->wexp);
        s->wexp = NULL;
        s->n_wexp = 0;
        s->wexp_known = 0;
    }
    s->dirty = 0;
    scene_summary(s);
    scene_box(s);
    s->few_spheres = few_spheres(s);
    few_spheres_lanes(s);
    s->instances_of_tris = instances_of_tris(s);
    s->generation++;
    s->avx2 = ray__cpu_has_avx2();
    s->committed = 1;
    return RAY_OK;
}
