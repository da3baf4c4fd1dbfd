/* SPDX-License-Identifier: MIT */
/*
** candidate.h -- a scene's plane and polygon tested inline as a query's
** candidate (ray__plane_candidate, ray__polygon_candidate:
** ray__prim_candidate's answer for them, uncounted and without the
** kinds' dispatch), with the plane's record and the full record's ids
** that kinds.c fills the same way.
*/
#ifndef RAY_SCENE_CANDIDATE_H
#define RAY_SCENE_CANDIDATE_H

#include "scene/scene.h"

/* The plane's record, as ray_plane fills it (its normal made unit: p->c,
** v3_normalize(p->b) made when the plane was added, geometry.c). */
static inline int ray__plane_fill_prim(const ray__prim *p, const ray_ray *r,
                                       double t, ray_hit *hit)
{
    return ray__plane_fill(r, p->a, p->c, p->a, t, hit);
}

/* A full record of geometry i: its ids (geom_id i, no prim_id, no
** instance), for every record the kinds fill (kinds.c). */
static inline int ray__full_record(unsigned i, ray_hit *hit)
{
    hit->geom_id = i;
    hit->prim_id = 0;
    hit->inst_id = RAY_INVALID_ID;
    return RAY__HIT_FULL;
}

/* Inline, always: a scene's planes are tested against every ray, nearest
** and any hit, and its call cost 11M instructions of the Whitted render
** (callgrind, issue 35); left to gcc, it stayed a call (its .isra copy):
** 7.5M more (556.3M -> 548.8M). */
RAY__HOT_INLINE int ray__plane_candidate(const ray_scene *s, unsigned i,
                                         const ray_ray *r, ray_hit *hit)
{
    const ray__prim *p = &s->prims[i];
    double t;

    /* The stored normal p->b normalised when the plane was added. */
    if (!ray__plane_t_valid(r, p->a, p->b, &t))
        return 0;
    if (!ray__plane_fills(r, p->a, t)) {
        if (!ray__plane_fill_prim(p, r, t, hit))
            return 0;
        return ray__full_record(i, hit);
    }
    hit->t = t;
    return RAY__HIT_T;
}

/* Polygon i against r, ungated and uncounted: ray__prim_candidate's
** answer for a polygon (a full record or a miss), without the kinds'
** dispatch and its frame, about 35 instructions a test: the Cornell
** box's shadow rays test its polygons four times each (callgrind,
** issue 35). */
static inline int ray__polygon_candidate(const ray_scene *s, unsigned i,
                                         const ray_ray *r, ray_hit *hit)
{
    const ray__prim *p = &s->prims[i];

    /* ray_polygon against the plane made when it was added (p->a the
    ** centroid, p->b the Newell normal), as kinds.c's hit_POLYGON. */
    return ray__polygon_at(r, s->verts + p->first, p->count, p->a, p->b,
                           hit)
               ? ray__full_record(i, hit)
               : 0;
}

#endif
