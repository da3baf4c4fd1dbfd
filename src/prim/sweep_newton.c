/* SPDX-License-Identifier: MIT */
/*
** sweep_newton.c -- a moving sphere or capsule against a convex body
** known only by its nearest points: an ellipsoid, or an ellipsoid swept
** along a segment (an instance's sphere or capsule through a transform
** that is not a similarity), whose Minkowski sum with a ball has no
** pieces of closed form.
**
** The distance D(t) between the shape's core (a point, a segment) moving
** on a line and a convex body is a convex function of t (the distance
** to a convex set of a point moving on a line, after the Minkowski
** trick: a segment [x, x + s] against K is the point x against K - [0,
** s], convex too).  Its derivative is d . n, n the unit vector from the
** body's nearest point to the core's.  Newton's method on D(t) = r +
** eps, started left of that crossing, stays left of it (a convex
** function lies above its tangents, so each step lands at or before
** the crossing) and converges to it: quadratically where the path
** crosses the surface, linearly where it grazes it.  So the contact is
** never late, whatever the number of steps: after 64 the last point is
** reported (early, never past the contact).  A core that moves away
** (D' above the rounding of d . n) has passed its nearest approach
** without contact: by convexity there is none later.  The steps aim at
** r + eps and stop within 2 eps of r, eps as for the pieces
** (ray__sweep_eps): the computed distance is within a few ulps of the
** magnitudes, so a step cannot reach past r.
*/
#include "prim/sweep.h"

/* The largest |component| of v. */
static double max_abs(ray_vec3 v)
{
    double x = fabs(v.x), y = fabs(v.y), z = fabs(v.z);
    double m = x > y ? x : y;

    return m > z ? m : z;
}

/* The ellipsoid's point with outward normal n: c + U e^2 U^T n / |e U^T
** n| (its support point in the direction n). */
static ray_vec3 support(const ray__ellipsoid *el, ray_vec3 n)
{
    double g[3], len;
    int k;

    for (k = 0; k < 3; k++)
        g[k] = el->e[k] * (el->u[0][k] * n.x + el->u[1][k] * n.y +
                           el->u[2][k] * n.z);
    len = v3_length(v3(g[0], g[1], g[2]));
    if (!(len > 0))
        return el->c;
    for (k = 0; k < 3; k++)
        g[k] *= el->e[k] / len;
    return v3(el->c.x + el->u[0][0] * g[0] + el->u[0][1] * g[1] +
                  el->u[0][2] * g[2],
              el->c.y + el->u[1][0] * g[0] + el->u[1][1] * g[1] +
                  el->u[1][2] * g[2],
              el->c.z + el->u[2][0] * g[0] + el->u[2][1] * g[1] +
                  el->u[2][2] * g[2]);
}

/*
** The signed distance at t between the core and the body, the body's
** point *p (on the scene: for a capsule sweep against an ellipsoid, the
** ellipsoid's point facing the core, not the Minkowski body's), the
** core's point *q and the body's outward unit normal *n there; +Inf
** when no nearest point is found.
*/
static double distance_at(const ray__sweep *sw, const ray__ellipsoid *el,
                          double t, ray_vec3 *p, ray_vec3 *q, ray_vec3 *n)
{
    ray_vec3 x = v3_scale(sw->d, t), pm;
    int capsule = max_abs(sw->s) > 0, inside = 0, ok;
    double d;

    if (capsule)                 /* E - [0, s]: E at c - s swept by s */
        ok = ray__ellipsoid_sweep_closest(v3_sub(el->c, sw->s), sw->s,
                                          (const double(*)[3])el->u, el->e,
                                          x, &pm, n, &inside);
    else if (max_abs(el->w) > 0)
        ok = ray__ellipsoid_sweep_closest(el->c, el->w,
                                          (const double(*)[3])el->u, el->e,
                                          x, &pm, n, &inside);
    else {
        ok = ray__ellipsoid_closest(el->c, (const double(*)[3])el->u,
                                    el->e, x, &pm, n);
        inside = ok && v3_dot(v3_sub(x, pm), *n) < 0;
    }
    if (!ok)
        return HUGE_VAL;
    d = ray__distance(x, pm);
    *q = x;
    *p = pm;
    if (capsule) {
        *p = support(el, *n);
        *q = v3_add(x, v3_sub(*p, pm));
    }
    return inside ? -d : d;
}

int ray__sweep_ellipsoid(ray__sweep *sw, const ray__ellipsoid *el,
                         ray__contact *best)
{
    ray_vec3 p, q, n, dir;
    double eps, dist, t = sw->t0;
    int k;

    if (max_abs(sw->s) > 0 && max_abs(el->w) > 0)
        return -1;
    eps = ray__sweep_eps(sw, max_abs(el->c) + max_abs(el->w) + el->e[0]);
    dist = distance_at(sw, el, t, &p, &q, &n);
    if (!(dist < HUGE_VAL))
        return 0;
    if (ray__sweep_overlap(sw, dist, q, p, n, eps, best))
        return 1;
    if (!(sw->d_len > 0))
        return 0;                       /* no motion: the overlap alone */
    for (k = 0; k < 64; k++) {
        double g = dist - sw->r, rate;
        if (!v3_normalize(v3_sub(q, p), &dir))
            dir = n;
        if (g <= 2 * eps)
            return ray__contact_offer(best, t, p, dir, 0);
        /* The unit vector q - p is off by the points' errors (within
        ** eps) over their distance: the rate is rounding below that. */
        rate = v3_dot(sw->d, dir);
        if (!(rate < -sw->d_len * (ray__gamma(8) + 2 * eps / dist)))
            return 0;                   /* moving away: none, by convexity */
        t += (g - eps) / -rate;
        if (!(t <= sw->t1))
            return 0;
        dist = distance_at(sw, el, t, &p, &q, &n);
        if (!(dist < HUGE_VAL))
            return 0;
    }
    if (!v3_normalize(v3_sub(q, p), &dir))
        dir = n;
    return ray__contact_offer(best, t, p, dir, 0);
}
