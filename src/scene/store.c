/* SPDX-License-Identifier: MIT */
/*
** store.c -- the scene's store: creating and freeing a scene, its
** allocation (through the user's allocator, or libc's), its growing
** arrays, and the records every add appends.  Every add either completes
** or leaves the scene as it was.
*/
#include <stdlib.h>
#include <string.h>

#include "core/platform.h"
#include "scene/slots.h"

/* The allocator of a scene made without one: libc's, a large block on
** whole huge pages where the platform can (platform.h). */
static void *libc_alloc(void *ud, void *ptr, size_t osize, size_t nsize)
{
    (void)ud;
#if RAY__WHOLE_HUGE_PAGES
    if (nsize >= RAY__HUGE_BLOCK ||
        (ptr != NULL && osize >= RAY__HUGE_BLOCK))
        return ray__huge_realloc(ptr, osize, nsize);
#else
    (void)osize;
#endif
    if (nsize > 0)
        return realloc(ptr, nsize);
    free(ptr);
    return NULL;
}

void *ray__alloc(const ray_scene *s, size_t size)
{
    return ray__allocate(&s->alloc, size);
}

void ray__free(const ray_scene *s, void *ptr, size_t size)
{
    ray__release(&s->alloc, ptr, size);
}

void *ray__realloc(const ray_scene *s, void *ptr, size_t osize, size_t nsize)
{
    return ray__reallocate(&s->alloc, ptr, osize, nsize);
}

/*
** The array "items" of *cap elements of "elem" bytes, with room for one
** more than "used": itself, or a copy twice as large (*cap updated).  NULL
** when that allocation fails, with items and *cap unchanged.
*/
void *ray__grow(ray_scene *s, void *items, size_t *cap, size_t used,
                size_t elem)
{
    size_t ncap;
    void *p;

    if (used < *cap)
        return items;
    ncap = *cap ? 2 * *cap : 8;
    if (ncap > (size_t)-1 / elem)
        return NULL;
    p = ray__reallocate(&s->alloc, items, *cap * elem, ncap * elem);
    if (p != NULL)
        *cap = ncap;
    return p;
}

int ray_scene_new(ray_scene **out, ray_alloc_fn alloc, void *alloc_ud)
{
    ray_scene *s;

    if (out == NULL)
        return RAY_EINVAL;
    if (alloc == NULL) {
        alloc = libc_alloc;
        alloc_ud = NULL;
    }
    s = alloc(alloc_ud, NULL, 0, sizeof *s);
    if (s == NULL)
        return RAY_ENOMEM;
    memset(s, 0, sizeof *s);
    s->alloc.fn = alloc;
    s->alloc.ud = alloc_ud;
    s->limits.max_depth = RAY_DEFAULT_MAX_DEPTH;
    s->limits.min_weight = RAY_DEFAULT_MIN_WEIGHT;
    s->limits.max_fanout = RAY_DEFAULT_MAX_FANOUT;
    s->prune = 1;
    s->watertight = 1;
    s->build_threads = 1;
    s->tri_mode = RAY__TRI_FILTERED;
    s->filter_scale = 1.0;
    s->dirty = RAY__DIRTY_ALL;
    *out = s;
    return RAY_OK;
}

void ray__mesh_release(const ray_scene *s, ray__mesh *m)
{
    /* The scene's own copies: freed through a cast, as allocated. */
    ray__free(s, m->uv_scale, m->n_tris * sizeof *m->uv_scale);
    m->uv_scale = NULL;
    ray__free(s, m->pos, m->n_vertices * sizeof *m->pos);
    m->pos = NULL;
    if (m->own_indices)
        ray__free(s, ray__unconst(m->indices),
                  3 * m->n_tris * sizeof *m->indices);
    m->own_indices = 0;
    if (!m->borrowed) {
        ray__free(s, ray__unconst(m->normals),
                  m->n_vertices * sizeof *m->normals);
        ray__free(s, ray__unconst(m->texcoords),
                  2 * m->n_vertices * sizeof *m->texcoords);
    }
    m->borrowed = 0;
    m->indices = NULL;
    m->normals = NULL;
    m->texcoords = NULL;
}

void ray_scene_free(ray_scene *s)
{
    size_t i;

    if (s == NULL)
        return;
    for (i = 0; i < s->n_meshes; i++)
        ray__mesh_release(s, &s->meshes[i]);
    ray__free(s, s->meshes, s->cap_meshes * sizeof *s->meshes);
    ray__free(s, s->surfaces, s->cap_surfaces * sizeof *s->surfaces);
    ray__free(s, s->instances, s->cap_instances * sizeof *s->instances);
    ray__free(s, s->tri_ids, s->cap_tri_ids * sizeof *s->tri_ids);
    ray__free(s, s->leaf_f, s->cap_leaf_f * sizeof *s->leaf_f);
    ray__free(s, s->leaf_tri, s->n_live_tris * sizeof *s->leaf_tri);
    ray__slot_vertices_drop(s);
    ray__bvh_free(&s->alloc, &s->tri_bvh);
    ray__bvh_free(&s->alloc, &s->prim_bvh);
    /* ray_contains' grid (parity.c, which calls this file's allocator:
    ** freed here rather than through it, so that no two files call each
    ** other). */
    ray__free(s, s->cgrid.block, s->cgrid.bytes);
    ray__free(s, s->wexp, s->n_wexp * sizeof *s->wexp);
    ray__mutex_free(&s->alloc, s->cgrid_lock);
    ray__free(s, s->planes, s->n_planes * sizeof *s->planes);
    ray__free(s, s->prims, s->cap_prims * sizeof *s->prims);
    ray__free(s, s->verts, s->cap_verts * sizeof *s->verts);
    ray__free(s, s->materials, s->cap_materials * sizeof *s->materials);
    ray__free(s, s->lights, s->cap_lights * sizeof *s->lights);
    ray__free(s, s, sizeof *s);
}

int ray__material_known(ray_scene *s, unsigned material)
{
    if (material < s->n_materials || material == RAY_NO_MATERIAL)
        return RAY_OK;
    return ray__fail(s, RAY_EINVAL, "material %u does not exist (the scene "
                     "has %zu)", material, s->n_materials);
}

/* Append a primitive already validated. */
int ray__add_prim(ray_scene *s, const ray__prim *prim, unsigned *geom_id)
{
    void *p;
    int rc = ray__material_known(s, prim->material);

    if (rc != RAY_OK)
        return rc;
    if (s->n_prims >= RAY_INVALID_ID)
        return ray__fail(s, RAY_ENOMEM, "too many geometries (%zu: ids are "
                         "32-bit)", s->n_prims);
    p = ray__grow(s, s->prims, &s->cap_prims, s->n_prims, sizeof *s->prims);
    if (p == NULL)
        return ray__fail(s, RAY_ENOMEM, "out of memory (geometry %zu)",
                         s->n_prims);
    s->prims = p;
    s->prims[s->n_prims] = *prim;
    s->prims[s->n_prims].mask = ~0u;
    s->prims[s->n_prims].enabled = 1;
    if (geom_id != NULL)
        *geom_id = (unsigned)s->n_prims;
    s->n_prims++;
    ray__touch(s, ray__dirty_of(prim));
    return RAY_OK;
}

/* Room for "more" triangle slots in tri_ids; a failure changes
** nothing. */
int ray__reserve_tris(ray_scene *s, size_t more)
{
    size_t need;
    void *p;

    if (more > 0x7fffffffu - s->n_tris)     /* ids and BVH items are 32-bit */
        return ray__fail(s, RAY_ENOMEM, "%zu + %zu triangles: more than "
                         "2^31 - 1 in a scene", s->n_tris, more);
    need = s->n_tris + more;
    while (s->cap_tri_ids < need) {
        p = ray__grow(s, s->tri_ids, &s->cap_tri_ids, s->cap_tri_ids,
                 sizeof *s->tri_ids);
        if (p == NULL)
            return ray__fail(s, RAY_ENOMEM, "out of memory (room for %zu "
                             "triangles)", need);
        s->tri_ids = p;
    }
    return RAY_OK;
}

int ray__reserve_verts(ray_scene *s, size_t more)
{
    void *grown;

    if (more > (size_t)-1 / 2 - s->n_verts)
        return ray__fail(s, RAY_ENOMEM, "%zu + %zu vertices overflow "
                         "size_t", s->n_verts, more);
    while (s->cap_verts < s->n_verts + more) {
        grown = ray__grow(s, s->verts, &s->cap_verts, s->cap_verts,
                          sizeof *s->verts);
        if (grown == NULL)
            return ray__fail(s, RAY_ENOMEM, "out of memory (room for %zu "
                             "vertices)", s->n_verts + more);
        s->verts = grown;
    }
    return RAY_OK;
}

ray__prim *ray__live_prim(ray_scene *s, unsigned geom_id)
{
    if (geom_id >= s->n_prims || s->prims[geom_id].removed) {
        ray__fail(s, RAY_EINVAL, "no geometry %u (the scene has %zu%s)",
                  geom_id, s->n_prims,
                  geom_id < s->n_prims ? "; it was removed" : "");
        return NULL;
    }
    return &s->prims[geom_id];
}
