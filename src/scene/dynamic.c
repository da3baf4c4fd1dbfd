/* SPDX-License-Identifier: MIT */
/*
** dynamic.c -- changing geometry after it was added, before or after a
** commit: enable and disable, remove, masks and filters.  Each change is
** staged (ray__touch) for the next commit, which rebuilds only the class
** of BVH it touched; the queries (query/gate.h) honour masks and filters.
*/
#include "scene/scene.h"

int ray_scene_set_enabled(ray_scene *s, unsigned geom_id, int enabled)
{
    int rc = ray__begin(s, "ray_scene_set_enabled");
    ray__prim *p;

    if (rc != RAY_OK)
        return rc;
    if ((p = ray__live_prim(s, geom_id)) == NULL)
        return RAY_EINVAL;
    if (p->enabled == (enabled != 0))
        return RAY_OK;                  /* nothing changes: no commit due */
    p->enabled = enabled != 0;
    ray__touch(s, ray__dirty_of(p));
    return RAY_OK;
}

/*
** Removal marks the geometry; the next commit drops its triangles from
** the store (rebuild_triangles) and its slot from the BVHs.  A mesh's
** shading data is freed now: nothing can shade it any more (the scene
** answers no query until that commit).
*/
int ray_scene_remove(ray_scene *s, unsigned geom_id)
{
    int rc = ray__begin(s, "ray_scene_remove");
    ray__prim *p;

    if (rc != RAY_OK)
        return rc;
    if ((p = ray__live_prim(s, geom_id)) == NULL)
        return RAY_EINVAL;
    if (p->kind == RAY__KIND_MESH)
        ray__mesh_release(s, &s->meshes[p->mesh]);
    if (p->kind == RAY__KIND_INSTANCE)
        s->instances[p->surface].removed = 1;   /* its child may go now */
    p->removed = 1;
    p->enabled = 0;
    ray__touch(s, ray__dirty_of(p));
    return RAY_OK;
}

int ray_scene_set_mask(ray_scene *s, unsigned geom_id, unsigned mask)
{
    int rc = ray__begin(s, "ray_scene_set_mask");
    ray__prim *p;

    if (rc != RAY_OK)
        return rc;
    if ((p = ray__live_prim(s, geom_id)) == NULL)
        return RAY_EINVAL;
    p->mask = mask;
    ray__touch(s, 0);                   /* the commit sees the gate */
    return RAY_OK;
}

int ray_scene_set_filter(ray_scene *s, unsigned geom_id, ray_filter_fn fn,
                         void *ud, unsigned queries)
{
    const unsigned known = RAY_FILTER_INTERSECT | RAY_FILTER_OCCLUDED;
    int rc = ray__begin(s, "ray_scene_set_filter");
    ray__prim *p;

    if (rc != RAY_OK)
        return rc;
    if ((p = ray__live_prim(s, geom_id)) == NULL)
        return RAY_EINVAL;
    if (p->kind == RAY__KIND_INSTANCE)
        return ray__fail(s, RAY_EINVAL, "geometry %u is an instance: set "
                         "filters on its scene's geometry", geom_id);
    if ((queries & ~known) != 0 || (fn != NULL && queries == 0))
        return ray__fail(s, RAY_EINVAL, "queries 0x%x: give "
                         "RAY_FILTER_INTERSECT, RAY_FILTER_OCCLUDED or both",
                         queries);
    p->filter = fn;
    p->filter_ud = fn != NULL ? ud : NULL;
    p->filter_queries = fn != NULL ? queries : 0u;
    ray__touch(s, 0);
    return RAY_OK;
}
