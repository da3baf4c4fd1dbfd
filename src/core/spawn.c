/* SPDX-License-Identifier: MIT */
/*
** spawn.c -- secondary rays that start just off the surface.
*/
#include "core/spawn.h"

/* x moved one ulp further in the direction of "dir" (not at all if 0):
** nextafter(x, +-HUGE_VAL), inline (vec.h says why the bits are the same). */
static inline double step_away(double x, double dir)
{
    if (dir > 0)
        return ray__next_up(x);
    if (dir < 0)
        return ray__next_down(x);
    return x;
}

/* The hit's nine numbers finite (v3_off_finite: one compare). */
static int hit_valid(const ray_hit *hit)
{
    double off = v3_off_finite(hit->p) + v3_off_finite(hit->n);

    return off + v3_off_finite(hit->p_err) == 0;
}

/* The side of the surface that "dir" leaves toward: 0 along the normal
** (or in the surface), 1 against it.  A NaN product counts as 0, as the
** comparison has it. */
static int side_of(const ray_hit *hit, ray_vec3 dir)
{
    return v3_dot(dir, hit->n) < 0;
}

/*
** The origin of a ray leaving "hit" toward "side" (side_of).
**
** The hit point p is only known to lie within p +- p_err of the surface.
** Moving it along the geometric normal by d = dot(|n|, p_err) puts it past
** that box on that side, so the ray cannot start behind the surface
** it leaves (pbrt-v4, section 6.8.6, OffsetRayOrigin).  We move by 2d: the
** intersection routines' own rounding of t near t = 0 is of the same order
** as p_err, and the factor 2 keeps the re-hit root negative rather than
** merely near zero (pbrt instead adds a conservative t > delta-t test to
** every intersector).  Finally each component is stepped one ulp further
** away, since p + offset is itself rounded (also pbrt).
*/
static int offset_origin(const ray_hit *hit, int side, ray_vec3 *org)
{
    ray_vec3 n = hit->n, an = v3_abs(n);
    double d = 2.0 * v3_dot(an, hit->p_err);
    ray_vec3 off, o;

    if (side)
        n = v3_scale(n, -1.0);
    off = v3_scale(n, d);
    o = v3_add(hit->p, off);
    o.x = step_away(o.x, off.x);
    o.y = step_away(o.y, off.y);
    o.z = step_away(o.z, off.z);
    if (v3_off_finite(o) != 0)
        return 0;
    *org = o;
    return 1;
}

/* The ray from org to target, as ray_spawn_to ends. */
static int ray_to(ray_vec3 org, ray_vec3 target, ray_ray *out)
{
    ray_vec3 dir = v3_sub(target, org);

    if (v3_off_finite(dir) != 0)
        return RAY_EINVAL;
    out->org = org;
    out->dir = dir;
    out->tmin = 0.0;
    out->tmax = 1.0;
    return RAY_OK;
}

int ray_spawn(const ray_hit *hit, ray_vec3 dir, ray_ray *out)
{
    ray_vec3 org;

    if (hit == NULL || out == NULL || !hit_valid(hit) ||
        v3_off_finite(dir) != 0 || (dir.x == 0 && dir.y == 0 && dir.z == 0) ||
        !offset_origin(hit, side_of(hit, dir), &org))
        return RAY_EINVAL;
    out->org = org;
    out->dir = dir;
    out->tmin = 0.0;
    out->tmax = HUGE_VAL;
    return RAY_OK;
}

int ray_spawn_to(const ray_hit *hit, ray_vec3 target, ray_ray *out)
{
    ray_vec3 org, dir;

    if (hit == NULL || out == NULL || !hit_valid(hit) ||
        v3_off_finite(target) != 0)
        return RAY_EINVAL;
    dir = v3_sub(target, hit->p);
    if ((dir.x == 0 && dir.y == 0 && dir.z == 0) ||
        !offset_origin(hit, side_of(hit, dir), &org))
        return RAY_EINVAL;
    return ray_to(org, target, out);
}

int ray__spawn_to(ray__spawner *sp, ray_vec3 target, ray_ray *out)
{
    ray_vec3 dir;
    int side;

    if (v3_off_finite(target) != 0)
        return RAY_EINVAL;
    dir = v3_sub(target, sp->hit->p);
    if (dir.x == 0 && dir.y == 0 && dir.z == 0)
        return RAY_EINVAL;
    side = side_of(sp->hit, dir);
    /* The hit checked as ray_spawn_to checks it, once a side: a hit not
    ** finite (p, and so dir, NaN or infinite) ends here whatever side. */
    if (sp->made[side] == 0)
        sp->made[side] = hit_valid(sp->hit) &&
                         offset_origin(sp->hit, side, &sp->org[side]) ? 1 : -1;
    if (sp->made[side] < 0)
        return RAY_EINVAL;
    return ray_to(sp->org[side], target, out);
}
