/* SPDX-License-Identifier: MIT */
/*
** tri_index.c -- where each triangle of the scene is: its slot in the
** scene's triangle store, by (geom_id, prim_id), for the queries that
** are handed a primitive rather than a ray (ray_surface_point).  The
** slots are in BVH leaf order, which only a rebuild of the triangle BVH
** changes, so the index is made then (ray_scene_commit); what the
** scene stores per triangle may change (issue 27), the index with it.
*/
#include "scene/scene.h"

void ray__tri_index_free(ray_scene *s)
{
    ray__free(s, s->slot_of, s->n_slot_of * sizeof *s->slot_of);
    ray__free(s, s->tri_base, s->n_tri_base * sizeof *s->tri_base);
    s->slot_of = NULL;
    s->tri_base = NULL;
    s->n_slot_of = s->n_tri_base = 0;
}

/*
** The index: tri_base[g], for triangle geometry g that was not removed,
** where its triangles start in slot_of (the sum of the counts of those
** before it; SIZE_MAX for other geometry), and slot_of[tri_base[g] + p]
** the slot of its triangle p.  When an array cannot be had there is no
** index (ray__tri_slot then searches the slots): a slower query, not a
** failed commit.
*/
void ray__tri_index_build(ray_scene *s)
{
    size_t g, i, total = 0;

    ray__tri_index_free(s);
    if (s->n_prims == 0 || s->n_tris == 0)
        return;
    s->tri_base = ray__alloc(s, s->n_prims * sizeof *s->tri_base);
    if (s->tri_base == NULL)
        return;
    s->n_tri_base = s->n_prims;
    for (g = 0; g < s->n_prims; g++) {
        const ray__prim *p = &s->prims[g];
        if (ray__kind_class(p->kind) == RAY__CLASS_TRIANGLES && !p->removed) {
            s->tri_base[g] = total;
            total += p->count;
        } else
            s->tri_base[g] = (size_t)-1;
    }
    s->slot_of = total > 0 ? ray__alloc(s, total * sizeof *s->slot_of) : NULL;
    if (s->slot_of == NULL) {
        ray__tri_index_free(s);
        return;
    }
    s->n_slot_of = total;
    for (i = 0; i < s->n_tris; i++) {
        const ray__tri_id *id = &s->tri_ids[i];
        size_t at = s->tri_base[id->geom_id] + id->prim_id;
        if (s->tri_base[id->geom_id] != (size_t)-1 && at < total)
            s->slot_of[at] = (unsigned)i;
    }
}

int ray__tri_slot(const ray_scene *s, unsigned geom_id, unsigned prim_id,
                  size_t *slot)
{
    size_t i;

    if (geom_id >= s->n_prims)
        return 0;
    if (s->tri_base != NULL) {
        size_t base = s->tri_base[geom_id];
        if (base == (size_t)-1 || prim_id >= s->prims[geom_id].count)
            return 0;
        *slot = s->slot_of[base + prim_id];
        return 1;
    }
    for (i = 0; i < s->n_tris; i++)
        if (s->tri_ids[i].geom_id == geom_id &&
            s->tri_ids[i].prim_id == prim_id) {
            *slot = i;
            return 1;
        }
    return 0;
}
