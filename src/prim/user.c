/* SPDX-License-Identifier: MIT */
/*
** user.c -- the caller's own geometry (ray_scene_add_user): its box and
** its intersection come from callbacks, so the library checks what they
** answer instead of trusting it.  A box that is not finite, or has
** lo > hi, is refused when the geometry is added; a hit that breaks the
** contract of ray_hit (ray.h) is a failure, which the scene takes as a
** miss and counts, as it does a failed root search.
*/
#include <stdio.h>

#include "prim/prim.h"

int ray__user_box(const ray_user_geometry *g, ray_vec3 *lo, ray_vec3 *hi,
                  char *why, size_t why_size)
{
    static const char axis_name[3] = {'x', 'y', 'z'};
    int k;

    /* A callback that writes nothing leaves a box that is not finite:
    ** refused like any other. */
    *lo = v3(HUGE_VAL, HUGE_VAL, HUGE_VAL);
    *hi = v3(-HUGE_VAL, -HUGE_VAL, -HUGE_VAL);
    g->bounds(g->ud, lo, hi);
    for (k = 0; k < 3; k++) {
        double l = v3_axis(*lo, k), h = v3_axis(*hi, k);

        if (!isfinite(l) || !isfinite(h)) {
            snprintf(why, why_size, "the bounds callback gave lo "
                     "(%g, %g, %g) hi (%g, %g, %g): %c is not finite",
                     lo->x, lo->y, lo->z, hi->x, hi->y, hi->z, axis_name[k]);
            return 0;
        }
        if (l > h) {
            snprintf(why, why_size, "the bounds callback gave lo "
                     "(%g, %g, %g) hi (%g, %g, %g): lo.%c %g > hi.%c %g",
                     lo->x, lo->y, lo->z, hi->x, hi->y, hi->z, axis_name[k],
                     l, axis_name[k], h);
            return 0;
        }
    }
    return 1;
}

/*
** How far from 1 the squared length of a normal may be for it to count as
** unit and be kept as the callback gave it: gamma(16).  A normal made
** unit by rounding arithmetic (v3_normalize: a division by the largest
** component, the square root of a sum of three squares, a reciprocal and
** a product, about 6 roundings per component) has each component within
** gamma(6) of the exact unit vector's, so its squared length within
** gamma(12) of 1, and forming n.n adds 3 roundings: gamma(15) < gamma(16).
** Normalising such a normal again would only round it once more, and
** would change the bits of a callback that calls a built-in primitive
** (ray_sphere): a user sphere must answer exactly as the scene's.
*/
#define UNIT_SLACK ray__gamma(16)

int ray__user_hit(const ray_user_geometry *g, const ray_ray *r,
                  ray_hit *hit)
{
    ray_hit h;
    int ok;

    /* What the callback leaves unwritten fails the checks below (t at
    ** tmin, p infinite, n zero), except u, v and p_err, which may be 0. */
    memset(&h, 0, sizeof h);
    h.t = r->tmin;
    h.p = v3(HUGE_VAL, HUGE_VAL, HUGE_VAL);
    ok = g->intersect(g->ud, r, &h);
    if (ok == 0)
        return 0;
    if (ok != 1)        /* a negated status (ray_implicit's), or nonsense */
        return -1;
    /* Written so that a NaN fails each test instead of passing it. */
    if (!(h.t > r->tmin && h.t < r->tmax) || !v3_isfinite(h.p) ||
        !isfinite(h.u) || !isfinite(h.v) || !v3_isfinite(h.p_err) ||
        !(h.p_err.x >= 0 && h.p_err.y >= 0 && h.p_err.z >= 0))
        return -1;
    if (!(fabs(v3_dot(h.n, h.n) - 1) <= UNIT_SLACK) &&
        (!v3_isfinite(h.n) || !v3_normalize(h.n, &h.n)))
        return -1;
    h.geom_id = RAY_INVALID_ID;
    h.prim_id = RAY_INVALID_ID;
    *hit = h;
    return 1;
}
