/* SPDX-License-Identifier: MIT */
/*
** sphere.c -- ray / sphere: the lecture's quadratic, arranged so that
** neither the discriminant nor the near root cancels catastrophically.
*/
#include "internal.h"

/*
** Fill *hit for the root t.  The hit point is projected back onto the
** sphere (pbrt-v4 Sphere::Intersect does the same), which removes the
** error that org + t*dir accumulates along the ray; what remains is the
** rounding of n = (p - c)/|p - c| (4 roundings), of radius*n and of the
** sum with c, bounded by gamma(7)*(|c| + radius*|n|) per component.
** Returns 0, leaving *hit untouched, if anything overflowed.
*/
static int sphere_fill(const ray_ray *r, ray_vec3 c, double radius, double t,
                       ray_hit *hit)
{
    ray_vec3 n, p, err;
    double ny;

    if (!v3_normalize(v3_sub(v3_madd(r->org, t, r->dir), c), &n))
        return 0;
    p = v3_madd(c, radius, n);
    err = v3_scale(v3_add(v3_abs(c), v3_scale(v3_abs(n), radius)),
                   ray__gamma(7));
    if (!v3_isfinite(p) || !v3_isfinite(err))
        return 0;
    ny = n.y < -1.0 ? -1.0 : (n.y > 1.0 ? 1.0 : n.y);
    hit->t = t;
    hit->p = p;
    hit->n = n;
    hit->u = atan2(n.x, n.z) / (2.0 * RAY__PI) + 0.5;
    hit->v = acos(-ny) / RAY__PI;
    hit->p_err = err;
    hit->geom_id = RAY_INVALID_ID;
    hit->prim_id = RAY_INVALID_ID;
    return 1;
}

/* The nearer of the roots t0, t1 inside (tmin, tmax); 0 if neither is. */
static int nearest_root(const ray_ray *r, double t0, double t1, double *t)
{
    if (t0 > t1) {
        double s = t0;
        t0 = t1;
        t1 = s;
    }
    /* Written so that a NaN root fails the test instead of passing it. */
    if (t0 > r->tmin && t0 < r->tmax)
        *t = t0;
    else if (t1 > r->tmin && t1 < r->tmax)
        *t = t1;
    else
        return 0;
    return 1;
}

/*
** With f = e - c, the lecture's quadratic is a t^2 - 2b' t + c = 0 with
** a = d.d, b' = -f.d, c = f.f - R^2 (b' is the usual b over -2).
**
** Discriminant: b'^2 - a*c = a*(R^2 - |l|^2) where l = f + (b'/a) d is the
** vector from the centre to the closest point of the ray's line (Hearn and
** Baker eq. 10-72; Haines, Guenther, Akenine-Moeller, Ray Tracing Gems
** ch. 7, eq. 7-9).  Forming |l| before subtracting keeps R's digits when
** the sphere is small and far: b'^2 - ac subtracts two numbers ~|f|^4 and
** loses R entirely once |f| > 2^26 R in double.  R^2 - |l|^2 is further
** written (R - |l|)(R + |l|) so that it does not square before subtracting
** (pbrt-v4 Sphere::BasicIntersect), and c likewise as (|f| - R)(|f| + R):
** near a huge sphere c is the small difference of two ~R^2 terms.
**
** Roots: q = b' + sign(b') sqrt(a*disc), t0 = c/q, t1 = q/a (Press et al.,
** Numerical Recipes, 5.6): both roots come from an addition of like signs,
** so the near root of a huge sphere does not cancel.
*/
int ray_sphere(const ray_ray *r, ray_vec3 center, double radius,
               ray_hit *hit)
{
    ray_vec3 f = v3_sub(r->org, center);
    double a = v3_dot(r->dir, r->dir);
    double b, l_len, disc, f_len, c, q, t;

    /* Exact tests, no epsilon: a radius that is not a positive finite
    ** number, or a direction whose squared length is 0 (or NaN), misses. */
    if (!(radius > 0 && radius < HUGE_VAL) || !(a > 0))
        return 0;
    b = -v3_dot(f, r->dir);
    l_len = v3_length(v3_madd(f, b / a, r->dir));
    disc = (radius - l_len) * (radius + l_len);
    if (!(disc >= 0))           /* < 0: the line misses; NaN: bad input */
        return 0;
    f_len = v3_length(f);
    c = (f_len - radius) * (f_len + radius);
    q = b + copysign(sqrt(a * disc), b);
    if (!nearest_root(r, c / q, q / a, &t))
        return 0;
    return sphere_fill(r, center, radius, t, hit);
}

/*
** The lecture's formula verbatim:
**   t = (-d.(e-c) -+ sqrt((d.(e-c))^2 - (d.d)((e-c).(e-c) - R^2))) / d.d
*/
int ray__sphere_naive(const ray_ray *r, ray_vec3 center, double radius,
                      ray_hit *hit)
{
    ray_vec3 ec = v3_sub(r->org, center);
    double dd = v3_dot(r->dir, r->dir);
    double dec = v3_dot(r->dir, ec);
    double disc = dec * dec - dd * (v3_dot(ec, ec) - radius * radius);
    double root, t;

    if (!(radius > 0 && radius < HUGE_VAL) || !(dd > 0) || !(disc >= 0))
        return 0;
    root = sqrt(disc);
    if (!nearest_root(r, (-dec - root) / dd, (-dec + root) / dd, &t))
        return 0;
    return sphere_fill(r, center, radius, t, hit);
}
