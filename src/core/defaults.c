/* SPDX-License-Identifier: MIT */
/*
** defaults.c -- the init functions of the public structs with a zero that
** is a value (a black light or surface, no bounce): each sets every
** field, so a field added in a later version gets its default in
** programs that call them (ray(7), "Versions and ABI").  Where a zero is
** a default, init writes the value it stands for: the same light.
** NULL is a no-op, as for every function returning nothing.
*/
#include <string.h>

#include "ray.h"

static ray_rgb grey(double level)
{
    return ray_rgb_make(level, level, level);
}

void ray_light_init(ray_light *l, int kind)
{
    if (l == NULL)
        return;
    memset(l, 0, sizeof *l);
    l->kind = kind;
    l->direction = ray_vec3_make(0, -1, 0);
    l->edge1 = ray_vec3_make(1, 0, 0);
    l->edge2 = ray_vec3_make(0, 0, 1);
    l->radius = 1;
    l->intensity = grey(1);
    l->samples = 16;
}

void ray_limits_init(ray_limits *l)
{
    if (l == NULL)
        return;
    memset(l, 0, sizeof *l);
    l->max_depth = RAY_DEFAULT_MAX_DEPTH;
    l->min_weight = RAY_DEFAULT_MIN_WEIGHT;
    l->max_fanout = RAY_DEFAULT_MAX_FANOUT;
}

void ray_phong_params_init(ray_phong_params *p)
{
    if (p == NULL)
        return;
    memset(p, 0, sizeof *p);
    p->diffuse = grey(0.8);
    p->shininess = RAY_DEFAULT_SHININESS;
}
