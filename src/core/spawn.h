/* SPDX-License-Identifier: MIT */
/*
** spawn.h -- many rays leaving one hit (spawn.c): ray_spawn_to's checks
** of the hit and its offset origins, made once for all of them, not once
** a ray.  The origin depends on the ray only through the side of the
** surface it leaves toward, so there are two, each made when a ray first
** needs it.  ray_shade_direct's shadow rays (every sample of every light
** leaves one hit) paid both once a sample: about 120 of a shadow ray's
** instructions (callgrind, examples/mesh; issue 35).
*/
#ifndef RAY_SPAWN_H
#define RAY_SPAWN_H

#include "core/vec.h"

typedef struct ray__spawner {
    const ray_hit *hit;
    /* Side 0: along n; 1: against it.  made[side] 0: not made yet; 1:
    ** org[side] made; -1: refused (the hit not finite, or the offset
    ** past DBL_MAX). */
    int made[2];
    ray_vec3 org[2];
} ray__spawner;

/* Rays from "hit" (not NULL, and not changed while sp is in use).
** Inline: a few stores, cheaper than a call. */
static inline void ray__spawner_start(ray__spawner *sp, const ray_hit *hit)
{
    sp->hit = hit;
    sp->made[0] = sp->made[1] = 0;
}

/* ray_spawn_to(sp->hit, target, out): the same answer, bit for bit. */
int ray__spawn_to(ray__spawner *sp, ray_vec3 target, ray_ray *out);

#endif /* RAY_SPAWN_H */
