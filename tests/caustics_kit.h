/* SPDX-License-Identifier: MIT */
/*
** caustics_kit.h -- what the caustics tests share (check_caustics.c,
** check_cones_caustics_hard.c): a probe material that shades the caustic
** irradiance itself, and the irradiance it reads on the floor y = 0.
*/
#ifndef CAUSTICS_KIT_H
#define CAUSTICS_KIT_H

#include "tests.h"

/* A floor probe: the material of the surface whose caustic irradiance a
** test reads.  It declares RAY_EFFECT_CAUSTICS (photons are stored on
** it) and shades the irradiance itself, so ray_trace returns it. */
static void irradiance_shade(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                             ray_rgb *out)
{
    (void)ud;
    ck_assert_int_eq(ray_caustics_at(ctx, a, out), RAY_OK);
}

static ray_material probe_material(void)
{
    ray_material m;

    m.shade = irradiance_shade;
    m.ud = NULL;
    m.effects = RAY_EFFECT_CAUSTICS;
    m.scatter = NULL;
    return m;
}

/* The caustic irradiance on the floor y = 0 at (x, z): a ray from 0.5
** above, straight down, shaded by the probe. */
static ray_rgb floor_irradiance(ray_ctx *ctx, double x, double z)
{
    ray_ray r = make_ray(vec(x, 0.5, z), vec(0, -1, 0), 0, HUGE_VAL);
    ray_rgb e = {-1, -1, -1};

    ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1.0, &e), RAY_OK);
    return e;
}

/* The mirrors' reflectance in both files' mirror scenes. */
static const ray_rgb mirror_R = {0.8, 0.6, 0.4};

#endif /* CAUSTICS_KIT_H */
