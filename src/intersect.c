/*
** intersect.c -- nearest-hit and any-hit queries over a scene's geometry.
** For now a linear loop over every primitive: each hit shrinks tmax, so
** later primitives are tested against the nearest hit so far.
*/
#include "internal.h"

/* One primitive against the ray; fills *hit on a hit in (tmin, tmax). */
static int prim_intersect(const ray_scene *s, const ray__prim *p,
                          const ray_ray *r, ray_hit *hit)
{
    switch (p->kind) {
    case PRIM_SPHERE:
        return ray_sphere(r, p->a, p->radius, hit);
    case PRIM_PLANE:
        return ray_plane(r, p->a, p->b, hit);
    case PRIM_TRIANGLE:
        return ray_triangle(r, p->a, p->b, p->c, hit);
    default:
        return ray_polygon(r, s->verts + p->first, p->count, hit);
    }
}

int ray__intersect(const ray_scene *s, const ray_ray *r, ray_hit *hit,
                   unsigned long long *tests)
{
    ray_ray shrinking = *r;
    ray_hit h;
    size_t i, found = (size_t)-1;

    for (i = 0; i < s->n_prims; i++) {
        if (prim_intersect(s, &s->prims[i], &shrinking, &h)) {
            shrinking.tmax = h.t;
            *hit = h;
            found = i;
        }
    }
    if (tests != NULL)
        *tests += s->n_prims;
    if (found == (size_t)-1)
        return 0;
    hit->geom_id = (unsigned)found;
    hit->prim_id = 0;
    return 1;
}

int ray__occluded(const ray_scene *s, const ray_ray *r,
                  unsigned long long *tests)
{
    ray_hit h;
    size_t i;

    for (i = 0; i < s->n_prims; i++) {
        if (prim_intersect(s, &s->prims[i], r, &h)) {
            if (tests != NULL)
                *tests += i + 1;
            return 1;
        }
    }
    if (tests != NULL)
        *tests += s->n_prims;
    return 0;
}

int ray_intersect(const ray_scene *s, const ray_ray *r, ray_hit *hit)
{
    if (s == NULL || r == NULL || hit == NULL || !s->committed)
        return 0;
    return ray__intersect(s, r, hit, NULL);
}

int ray_occluded(const ray_scene *s, const ray_ray *r)
{
    if (s == NULL || r == NULL || !s->committed)
        return 0;
    return ray__occluded(s, r, NULL);
}
