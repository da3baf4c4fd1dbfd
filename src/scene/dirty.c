/* SPDX-License-Identifier: MIT */
/*
** dirty.c -- what has changed since a scene's commit, in one place: what
** the next commit must redo (the dirty bits every building call sets),
** and whether an instance's child was changed since its parent's commit
** (the stale check every query, render and commit makes).  A commit
** counts itself in the scene's generation; an instance remembers the
** generation of its child that its box was taken at.
*/
#include "scene/scene.h"

void ray__touch(ray_scene *s, unsigned dirty)
{
    s->dirty |= dirty;
    s->committed = 0;
}

unsigned ray__dirty_of(const ray__prim *p)
{
    return ray__kind_class(p->kind) == RAY__CLASS_TRIANGLES
               ? RAY__DIRTY_TRIS : RAY__DIRTY_PRIMS;
}

int ray__scene_stale(const ray_scene *s)
{
    size_t i;

    for (i = 0; i < s->n_instances; i++)
        if (!s->instances[i].removed &&
            ray__instance_stale(&s->instances[i]))
            return 1;
    return 0;
}
