/* SPDX-License-Identifier: MIT */
/*
** sphere.c -- ray / sphere: the lecture's quadratic, arranged so that
** neither the discriminant nor the near root cancels catastrophically.
*/
#include "prim/prim.h"

/*
** Fill *hit for the root t.  The hit point is projected back onto the
** sphere (pbrt-v4 Sphere::Intersect does the same), which removes the
** error that org + t*dir accumulates along the ray; what remains is the
** rounding of n = (p - c)/|p - c| (4 roundings), of radius*n and of the
** sum with c, bounded by gamma(7)*(|c| + radius*|n|) per component.
** Returns 0, leaving *hit untouched, if anything overflowed.
*/
int ray__sphere_fill(const ray_ray *r, ray_vec3 c, double radius, double t,
                     int uv, ray_hit *hit)
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
    /* The texture coordinates, an atan2 and an acos: only when wanted
    ** (ray__sphere_fill in prim.h). */
    hit->u = uv ? atan2(n.x, n.z) / (2.0 * RAY__PI) + 0.5 : 0.0;
    hit->v = uv ? acos(-ny) / RAY__PI : 0.0;
    hit->p_err = err;
    hit->geom_id = RAY_INVALID_ID;
    hit->prim_id = RAY_INVALID_ID;
    hit->inst_id = RAY_INVALID_ID;
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
** A bound on the rounding error of a root t of a t^2 - 2 b' t + c (the
** quadratic below, in the scaled direction), by running error analysis
** (Higham, "Accuracy and Stability of Numerical Algorithms", 2nd ed.,
** 3.1; gamma(n) = n u / (1 - n u)) of the quantities as ray_sphere forms
** them, with f = org - center rounded once:
**   a = d.d:              da = gamma(3) a;
**   b' = -f.d:            db = gamma(4) sum |f_i d_i|;
**   c = (|f| - R)(|f| + R), |f| within gamma(4) |f|:
**                         dc = gamma(4) |f| (|f| + R + ||f| - R|) + gamma(3) |c|;
**   disc = (R - l)(R + l), l = |f + (b'/a) d| within
**                         dl = gamma(8) (|f| + |b'/a| |d|) (the b'/a error
**                         included, as |b'| <= |f| |d|), so
**                         ddisc = dl (R + l + |R - l|) + gamma(3) |disc|.
** The coefficients' errors move g(t) by at most dg = dc + 2|t| db + t^2 da,
** and so a simple root by dg / |g'(t)| = dg / (2 s), s = sqrt(a disc) (to
** first order; times 2 for the second), and a double root by at most
** 2 sqrt(dg / a): the smaller bound holds.  The root's own evaluation
** through s (q = b' +- s, then c/q or q/a) adds |t| ds / s + gamma(4) |t|,
** ds bounding s's error from ddisc.  Used to require a hit's whole error
** interval past tmin: a ray leaving the sphere starts on it or within its
** rounding error, and its near root is then rounding noise around 0
** (ray__watertight_t_error in watertight.h says more).
*/
typedef struct sphere_quadratic {
    double a, b, c, disc, l, f_len, radius, s, b_over_a;
    ray_vec3 f, d;
} sphere_quadratic;

/* dg above, for root t (|t| = at). */
static double sphere_dg(const sphere_quadratic *k, double at)
{
    double R = k->radius;
    double fd_mag = fabs(k->f.x * k->d.x) + fabs(k->f.y * k->d.y) +
                    fabs(k->f.z * k->d.z);
    double da = ray__gamma(3) * k->a, db = ray__gamma(4) * fd_mag;
    double dc = ray__gamma(4) * k->f_len *
                    (k->f_len + R + fabs(k->f_len - R)) +
                ray__gamma(3) * fabs(k->c);

    return dc + 2 * at * db + at * at * da;
}

/* ddisc above, for |d| at most d_len. */
static double sphere_ddisc(const sphere_quadratic *k, double d_len)
{
    double R = k->radius;
    double dl = ray__gamma(8) * (k->f_len + fabs(k->b_over_a) * d_len);

    return dl * (R + k->l + fabs(R - k->l)) + ray__gamma(3) * fabs(k->disc);
}

static double sphere_t_error(const sphere_quadratic *k, double t)
{
    double at = fabs(t);
    double ddisc = sphere_ddisc(k, v3_length(k->d));
    double dg = sphere_dg(k, at);
    double s = k->s, s_low, ds, simple, twofold;

    s_low = sqrt(k->a * ray__fmax(k->disc - ddisc, 0.0)) * (1 - ray__gamma(4));
    ds = s - s_low;
    twofold = 2 * sqrt(dg / k->a);
    simple = s_low > 0 ? dg / s_low : HUGE_VAL;
    return ray__fmin(simple, twofold) * (1 + ray__gamma(4)) +
           (s > 0 ? at * ds / s : 0) + ray__gamma(4) * at;
}

/*
** Is t - sphere_t_error(k, t) > tmin, decided without the bound's three
** square roots and four divisions where a cheaper, larger bound E already
** says yes (fl(t - E) > tmin and E >= the bound as computed give fl(t -
** bound) > tmin, rounding being monotonic); the bound itself otherwise.
** So the answer is the bound's, bit for bit.  E holds where disc's error
** is small, ddisc <= 2^-20 disc (ddisc formed with |d| < 2 for the scaled
** direction, whose largest component is below 1: no larger than the
** bound's):
**   - s_low >= s sqrt(1 - 2^-20) (1 - gamma(4)) (1 - 6u) > s / 1.01 (6u
**     for the roundings of disc - ddisc, the products and the roots), so
**     the bound's first term is at most 1.01 (1 + gamma(4)) (1 + 3u)
**     dg / s < 2 dg / s;
**   - ds = s - s_low (exact: Sterbenz), so ds / s <= 1 - s_low / s <=
**     2^-20 + gamma(4) + 6u, and the last two terms together are at most
**     |t| (2^-20 + 2 gamma(4) + 8u) < 2^-18 |t|;
**   - the sums' roundings (1 + 2u) fit in the factors' slack, and so do
**     E's own roundings (E = 2 dg / s + 2^-18 |t|, rounded down by at
**     most 3u); |t| >= 2^-1000 keeps 2^-18 |t| a normal number, beside
**     which an underflow's absolute error (2^-1075) in either bound is
**     lost in the slack.
** A NaN or Inf anywhere fails the cheap test: the bound decides.  On
** ordinary hits (disc far from 0, t far from tmin) the cheap test
** decides; the bound is computed only for roots within ~2^-18 |t| + 2
** dg / s of tmin (rays leaving the surface) and for grazing rays.
*/
static int sphere_past_tmin(const sphere_quadratic *k, double tmin,
                            double t)
{
    double at = fabs(t);

    if (at >= 0x1p-1000 && sphere_ddisc(k, 2.0) <= 0x1p-20 * k->disc &&
        t - (2 * sphere_dg(k, at) / k->s + 0x1p-18 * at) > tmin)
        return 1;
    return t - sphere_t_error(k, t) > tmin;
}

/* The nearer of the roots t0, t1 whose error interval lies in (tmin,
** tmax) for the scaled tmin and tmax; 0 if neither does. */
static int nearest_root_bounded(const sphere_quadratic *k, double tmin,
                                double tmax, double t0, double t1, double *t)
{
    if (t0 > t1) {
        double s = t0;
        t0 = t1;
        t1 = s;
    }
    /* Written so that a NaN root fails the test instead of passing it. */
    if (t0 > tmin && t0 < tmax && sphere_past_tmin(k, tmin, t0))
        *t = t0;
    else if (t1 > tmin && t1 < tmax && sphere_past_tmin(k, tmin, t1))
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
**
** The direction is first scaled by a power of two (ray__scaled_dir), and
** t, tmin and tmax with it: once per ray (ray__sphere_ray_init), so that a
** scene query testing several spheres scales it once (ray__sphere_t_at).
*/
int ray__sphere_t_near(const ray__sphere_ray *sr, const ray_ray *r,
                       ray_vec3 center, double radius, double *t_out)
{
    ray_vec3 f, d = sr->d;
    sphere_quadratic k;
    double q, t;

    /* Exact tests, no epsilon: a radius that is not a positive finite
    ** number misses. */
    if (!(radius > 0 && radius < HUGE_VAL))
        return 0;
    f = v3_sub(r->org, center);
    k.a = sr->a;
    k.b = -v3_dot(f, d);
    k.f_len = v3_length(f);
    k.c = (k.f_len - radius) * (k.f_len + radius);
    /* Both roots behind the origin, as computed: with b' < 0, q below
    ** has b''s sign, so t1 = q/a < 0, and with c > 0 so is t0 = c/q;
    ** neither passes tmin >= 0 below.  Found here without the division,
    ** the three square roots and the error bounds: a ray leaving a
    ** sphere outward (its reflection) or passing one behind it, a third
    ** of the spheres the Whitted render tests in full (issue 35). */
    if (k.b < 0 && k.c > 0 && sr->tmin >= 0)
        return 0;
    k.b_over_a = k.b / k.a;
    k.l = v3_length(v3_madd(f, k.b_over_a, d));
    k.disc = (radius - k.l) * (radius + k.l);
    if (!(k.disc >= 0))         /* < 0: the line misses; NaN: bad input */
        return 0;
    k.radius = radius;
    k.f = f;
    k.d = d;
    k.s = sqrt(k.a * k.disc);
    q = k.b + copysign(k.s, k.b);
    /* tmin, tmax in the scaled direction's units (ray__scaled_dir). */
    if (!nearest_root_bounded(&k, sr->tmin, ray__scale_t(r->tmax, sr->e),
                              k.c / q, q / k.a, &t))
        return 0;
    t = ray__unscale_t(t, sr->e);
    if (!(t > r->tmin && t < r->tmax))  /* the product rounded past one */
        return 0;
    *t_out = t;
    return 1;
}

/* The early out first, then the whole test: the early out answers
** "missed" only where the test misses too (prim.h), and reads nothing
** that the test could have changed, so the answer is the test's alone. */
int ray__sphere_t_at(const ray__sphere_ray *sr, const ray_ray *r,
                     ray_vec3 center, double radius, double *t_out)
{
    if (ray__sphere_surely_missed(v3_sub(r->org, center), sr->d, sr->a,
                                  radius))
        return 0;
    return ray__sphere_t_near(sr, r, center, radius, t_out);
}

int ray__sphere_t(const ray_ray *r, ray_vec3 center, double radius,
                  double *t_out)
{
    ray__sphere_ray sr;

    return ray__sphere_ray_init(r, &sr) &&
           ray__sphere_t_at(&sr, r, center, radius, t_out);
}

int ray_sphere(const ray_ray *r, ray_vec3 center, double radius,
               ray_hit *hit)
{
    double t;

    if (hit == NULL || !ray__sphere_t(r, center, radius, &t))
        return 0;
    return ray__sphere_fill(r, center, radius, t, 1, hit);
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
    return ray__sphere_fill(r, center, radius, t, 1, hit);
}
