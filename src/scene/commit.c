/* SPDX-License-Identifier: MIT */
/*
** commit.c -- committing a scene: what changed is built again (the
** triangle BVH rebuilt or refitted, the BVH over the other bounded kinds
** and the plane list), instances' boxes are taken again, and the
** scene's effects, gate and box summed up.  Read-only until the next
** change.
*/
#include <string.h>

#include "core/platform.h"
#include "scene/scene.h"

/* The smaller and larger of two, of three finite numbers (no libm call:
** the NaN rules of fmin are not needed here, vertices are finite). */
static double min2(double a, double b)
{
    return a < b ? a : b;
}

static double max2(double a, double b)
{
    return a > b ? a : b;
}

static double min3(double a, double b, double c)
{
    return min2(min2(a, b), c);
}

static double max3(double a, double b, double c)
{
    return max2(max2(a, b), c);
}

/*
** The BVHs' cost settings (accel/sah.c).  Triangles: a split costs 1.5 triangle
** tests, and four triangles or fewer always make a leaf, since a wide node
** tests all its boxes at once, whatever their number, and so costs more
** than the binary SAH prices a split: bench/mesh measured the same ray
** throughput on the bunny for traversal costs 1.0 to 2.0 and leaves of 1
** to 4, and 1.5 with 4 builds fastest and takes least memory (103 bytes
** per triangle on the 59k bunny against 126 for 1.0 with 1).  Other
** primitives: a curved surface's test costs up to thousands of box tests,
** so every split the SAH finds is taken, down to single primitives.
*/
static const ray__bvh_costs tri_costs = {1.5f, 4};
static const ray__bvh_costs prim_costs = {1.0f, 1};

/*
** The float box of triangles first .. first + n - 1 (a leaf's), rounded
** outward once from their double bounds: the same box as the union of
** their own rounded boxes (rounding outward is monotonic), at a quarter
** of the roundings for the refit's four-triangle leaves.
*/
static void tris_box(const void *ud, size_t first, size_t n, float lo[3],
                     float hi[3])
{
    const ray__tri *t = &((const ray_scene *)ud)->tris[first];
    ray_vec3 a = t->a, b = t->a;
    size_t i;

    for (i = 0; i < n; i++, t++) {
        a.x = min2(a.x, min3(t->a.x, t->b.x, t->c.x));
        a.y = min2(a.y, min3(t->a.y, t->b.y, t->c.y));
        a.z = min2(a.z, min3(t->a.z, t->b.z, t->c.z));
        b.x = max2(b.x, max3(t->a.x, t->b.x, t->c.x));
        b.y = max2(b.y, max3(t->a.y, t->b.y, t->c.y));
        b.z = max2(b.z, max3(t->a.z, t->b.z, t->c.z));
    }
    lo[0] = ray__float_down(a.x);
    lo[1] = ray__float_down(a.y);
    lo[2] = ray__float_down(a.z);
    hi[0] = ray__float_up(b.x);
    hi[1] = ray__float_up(b.y);
    hi[2] = ray__float_up(b.z);
}

/* The float box of triangle i of the scene, rounded outward (the build's
** box callback, once a triangle): tris_box of one, without its loop (the
** min of a set that holds x is the min of x and the set, bit for bit). */
static void tri_box(const void *ud, size_t i, float lo[3], float hi[3])
{
    const ray__tri *t = &((const ray_scene *)ud)->tris[i];

    lo[0] = ray__float_down(min3(t->a.x, t->b.x, t->c.x));
    lo[1] = ray__float_down(min3(t->a.y, t->b.y, t->c.y));
    lo[2] = ray__float_down(min3(t->a.z, t->b.z, t->c.z));
    hi[0] = ray__float_up(max3(t->a.x, t->b.x, t->c.x));
    hi[1] = ray__float_up(max3(t->a.y, t->b.y, t->c.y));
    hi[2] = ray__float_up(max3(t->a.z, t->b.z, t->c.z));
}

/* Give back the spare capacity that doubling left in the triangle arrays
** (a failed shrink keeps the larger block: harmless). */
static void trim_tris(ray_scene *s)
{
    void *p;

    if (s->n_tris == 0)
        return;          /* a zero-size realloc frees: keep the blocks */
    if (s->cap_tris > s->n_tris) {
        p = ray__realloc(s, s->tris, s->cap_tris * sizeof *s->tris,
                         s->n_tris * sizeof *s->tris);
        if (p != NULL) {
            s->tris = p;
            s->cap_tris = s->n_tris;
        }
    }
    if (s->cap_tri_ids > s->n_tris) {
        p = ray__realloc(s, s->tri_ids, s->cap_tri_ids * sizeof *s->tri_ids,
                         s->n_tris * sizeof *s->tri_ids);
        if (p != NULL) {
            s->tri_ids = p;
            s->cap_tri_ids = s->n_tris;
        }
    }
}

/*
** Put tris[i] (and its ids) at position i of leaf order, i.e. apply the
** permutation items (item index of leaf position i) in place, walking its
** cycles; the top bit of items[] marks the positions already placed
** (indices are below 2^31).  The fallback of gather_tris (below).
*/
static void permute_tris(ray_scene *s, unsigned *items, size_t n)
{
    const unsigned done = 0x80000000u;
    size_t start;

    for (start = 0; start < n; start++) {
        ray__tri t;
        ray__tri_id id;
        size_t pos = start;
        if (items[start] & done)
            continue;
        t = s->tris[start];
        id = s->tri_ids[start];
        for (;;) {
            size_t src = items[pos];
            items[pos] |= done;
            if (src == start) {
                s->tris[pos] = t;
                s->tri_ids[pos] = id;
                break;
            }
            s->tris[pos] = s->tris[src];
            s->tri_ids[pos] = s->tri_ids[src];
            pos = src;
        }
    }
}

/* permute_tris for the ids alone. */
static void permute_ids(ray_scene *s, unsigned *items, size_t n)
{
    const unsigned done = 0x80000000u;
    size_t start;

    for (start = 0; start < n; start++) {
        ray__tri_id id;
        size_t pos = start;
        if (items[start] & done)
            continue;
        id = s->tri_ids[start];
        for (;;) {
            size_t src = items[pos];
            items[pos] |= done;
            if (src == start) {
                s->tri_ids[pos] = id;
                break;
            }
            s->tri_ids[pos] = s->tri_ids[src];
            pos = src;
        }
    }
}

/*
** The same permutation, gathered into new arrays (the triangles first,
** their old array freed before the ids' is made, so that at most one
** extra array is held): each read is random but none depends on another,
** where walking the cycles in place chases one random read after the
** other (at 940k triangles the walk took about a sixth of the commit,
** perf on bench/mesh's bunny-4).  Where memory is short for an array,
** that array is permuted in place instead: the same order.
*/
static void gather_tris(ray_scene *s, unsigned *items, size_t n)
{
    size_t i, all = s->n_tris;
    ray__tri *t = ray__alloc(s, all * sizeof *t);
    ray__tri_id *id;

    if (t == NULL) {
        permute_tris(s, items, n);
        return;
    }
    for (i = 0; i < n; i++)
        t[i] = s->tris[items[i]];
    memcpy(t + n, s->tris + n, (all - n) * sizeof *t);   /* waiting ones */
    ray__free(s, s->tris, s->cap_tris * sizeof *s->tris);
    s->tris = t;
    s->cap_tris = all;
    id = ray__alloc(s, all * sizeof *id);
    if (id == NULL) {
        permute_ids(s, items, n);
        return;
    }
    for (i = 0; i < n; i++)
        id[i] = s->tri_ids[items[i]];
    memcpy(id + n, s->tri_ids + n, (all - n) * sizeof *id);
    ray__free(s, s->tri_ids, s->cap_tri_ids * sizeof *s->tri_ids);
    s->tri_ids = id;
    s->cap_tri_ids = all;
}

/* Is triangle slot i of geometry that queries may see? */
static int tri_live(const ray_scene *s, size_t i)
{
    const ray__prim *p = &s->prims[s->tri_ids[i].geom_id];
    return p->enabled && !p->removed;
}

/* Swap triangle slots i and j (and their ids); nothing to do for i == j,
** the usual case (every triangle kept, in place). */
static void tri_swap(ray_scene *s, size_t i, size_t j)
{
    ray__tri t;
    ray__tri_id id;

    if (i == j)
        return;
    t = s->tris[i];
    id = s->tri_ids[i];

    s->tris[i] = s->tris[j];
    s->tri_ids[i] = s->tri_ids[j];
    s->tris[j] = t;
    s->tri_ids[j] = id;
}

/*
** The triangle BVH, rebuilt: the triangles of enabled geometry are moved
** to the front (the others wait behind, outside the BVH, until enabled
** again), then rewritten in leaf order, so every leaf is a contiguous
** run of tris and traversal needs no index indirection.  On failure the
** old BVH is kept (the slots are only reordered: the same triangles).
*/
static int rebuild_triangles(ray_scene *s)
{
    size_t n = 0, i;
    ray__bvh fresh;
    int rc;

    /* Removed geometry's triangles go for good, then the live ones (of
    ** enabled geometry) to the front. */
    for (i = 0; i < s->n_tris; i++)
        if (!s->prims[s->tri_ids[i].geom_id].removed)
            tri_swap(s, n++, i);
    s->n_tris = n;
    n = 0;
    for (i = 0; i < s->n_tris; i++)
        if (tri_live(s, i)) {
            tri_swap(s, n, i);
            ray__tri_collapse_unusable(&s->tris[n++]);   /* while at hand */
        }
    rc = ray__bvh_build(&s->alloc, tri_box, s, n, &tri_costs,
                        &s->scheduler, s->build_threads, &fresh);
    if (rc != RAY_OK)
        return rc;
    if (n > 0) {
        gather_tris(s, fresh.items, n);
        /* Leaves now index tris directly: the permutation is not kept. */
        ray__free(s, fresh.items, fresh.n_items * sizeof(unsigned));
        fresh.items = NULL;
        fresh.n_items = 0;
    }
    ray__bvh_free(&s->alloc, &s->tri_bvh);
    s->tri_bvh = fresh;
    s->n_live_tris = n;
    trim_tris(s);
    return RAY_OK;
}

static void refit_triangles(ray_scene *s)
{
    /* ray_scene_update_mesh collapsed the unusable ones it wrote. */
    ray__bvh_refit(&s->alloc, &s->tri_bvh, tris_box, s, s->n_live_tris);
}

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
static int rebuild_prims(ray_scene *s)
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
                            &s->scheduler, s->build_threads, &fresh);
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
    ray__instance *in;
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
    }
    for (i = 0; i < s->n_prims; i++) {
        if ((in = instance_behind(s, i)) == NULL)
            continue;
        ray__instance_box(in);
        in->generation = in->child->generation;
        ray__touch(s, RAY__DIRTY_PRIMS);
    }
    return RAY_OK;
}

/*
** Build what changed (all of it the first time); the scene is then
** read-only until the next change.  A failure (out of memory) leaves the
** scene uncommitted with its changes still staged, so commit can be
** retried.  A commit with nothing to do is a no-op.
*/
int ray_scene_commit(ray_scene *s)
{
    int rc = ray__begin(s, "ray_scene_commit");

    if (rc != RAY_OK)
        return rc;
    if ((rc = refresh_instances(s)) != RAY_OK)
        return rc;
    if (s->committed && s->dirty == 0)
        return RAY_OK;
    if ((s->dirty & RAY__DIRTY_PRIMS) && (rc = rebuild_prims(s)) != RAY_OK)
        return ray__fail(s, rc, "out of memory building the BVH over the "
                         "spheres, polygons, surfaces and instances (not "
                         "committed: retry)");
    s->dirty &= ~RAY__DIRTY_PRIMS;
    if (s->dirty & RAY__DIRTY_TRIS) {
        if ((rc = rebuild_triangles(s)) != RAY_OK)
            return ray__fail(s, rc, "out of memory building the BVH over "
                             "%zu triangles (not committed: retry)",
                             s->n_tris);
    } else if (s->dirty & RAY__DIRTY_REFIT)
        refit_triangles(s);
    s->dirty = 0;
    scene_summary(s);
    scene_box(s);
    s->generation++;
    s->avx2 = ray__cpu_has_avx2();
    s->committed = 1;
    return RAY_OK;
}
