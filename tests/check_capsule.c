/* SPDX-License-Identifier: MIT */
/*
** check_capsule.c -- ray_capsule and ray_scene_add_capsule: exact
** values, a long double reference at offsets 0, 1e5 and 1e6, tangent and
** grazing rays, rays along the axis, rays from inside, tmin / tmax, bad
** input, texture coordinates, the point capsule against ray_sphere, the
** direction's length, and the scene through its BVH.
*/
#include <stdio.h>
#include <stdlib.h>

#include "tests.h"

/* pi, which strict C99 <math.h> does not define. */
#define PI 3.14159265358979323846

static ray_capsule_params capsule(ray_vec3 a, ray_vec3 b, double radius)
{
    ray_capsule_params c;
    c.a = a;
    c.b = b;
    c.radius = radius;
    return c;
}

/* The capsule of the exact cases: ends (o -+ 1, o, o), radius 1/2, so
** that half = 1 and every answer below is a short dyadic number. */
static ray_capsule_params unit_x(double o)
{
    return capsule(vec(o - 1, o, o), vec(o + 1, o, o), 0.5);
}

/*
** v of the exact capsule: the meridian's length is pi R + 2 half =
** pi/2 + 2; the cylinder's middle is at arc pi/4 + 1, the middle of the
** total: v = 1/2.  u: the frame of w = +x (ray__tangent_frame) is
** t1 = -z, t2 = +y, so n = +z = -t1 gives atan2(-1, -0)/2pi + 1/2 = 1/4.
** 4 ulps: a handful of roundings of values below 1.
*/
START_TEST(capsule_should_hit_side_at_exact_t)
{
    double o = test_offset(_i), tol = tol_at(o);
    ray_capsule_params c = unit_x(o);
    ray_ray r = ray_from(vec(o, o, o + 5), vec(0, 0, -1));
    ray_hit h;

    ck_assert_int_eq(ray_capsule(&r, &c, &h), 1);
    ck_assert_double_eq_tol(h.t, 4.5, tol);
    ck_assert_vec_eq_tol(h.p, vec(o, o, o + 0.5), tol);
    ck_assert_vec_eq_tol(h.n, vec(0, 0, 1), 4 * DBL_EPSILON);
    ck_assert_double_eq_tol(h.u, 0.25, 4 * DBL_EPSILON);
    ck_assert_double_eq_tol(h.v, 0.5, 4 * DBL_EPSILON);
    ck_assert_uint_eq(h.geom_id, RAY_INVALID_ID);
    ck_assert_uint_eq(h.prim_id, RAY_INVALID_ID);
    ck_assert(hit_is_finite(&h));
    /* p_err: gamma(32) (|m_i| + 2 (R + half)) = gamma(32) (o + 3). */
    ck_assert(h.p_err.x > 0 && h.p_err.x < 64 * DBL_EPSILON * (o + 3));
}
END_TEST

/*
** Along the axis: a's pole at x = o - 1.5 (t = 3.5, v = 0, n = -x); from
** the midpoint, b's pole (t = 1.5, v = 1).  With the capsule along x the
** direction's components across the axis are exactly 0: the cylinder's
** quadratic degenerates and the caps alone answer.  Off the axis by 0.3,
** a's sphere (centre o - 1) is met at x = -1 - sqrt(0.25 - 0.09) = -1.4:
** t = 3.6, n = (-0.8, 0.6, 0), v = R phi / (pi R + 2) with phi =
** atan2(0.6, 0.8) the angle from a's pole.
*/
START_TEST(capsule_should_hit_caps_along_the_axis)
{
    double o = test_offset(_i), tol = tol_at(o);
    ray_capsule_params c = unit_x(o);
    ray_ray in = ray_from(vec(o - 5, o, o), vec(1, 0, 0));
    ray_ray mid = ray_from(vec(o, o, o), vec(1, 0, 0));
    ray_ray off = ray_from(vec(o - 5, o + 0.3, o), vec(1, 0, 0));
    ray_ray back = ray_from(vec(o + 5, o, o), vec(-1, 0, 0));
    ray_hit h;

    ck_assert_int_eq(ray_capsule(&in, &c, &h), 1);
    ck_assert_double_eq_tol(h.t, 3.5, tol);
    ck_assert_vec_eq_tol(h.p, vec(o - 1.5, o, o), tol);
    ck_assert_vec_eq_tol(h.n, vec(-1, 0, 0), 4 * DBL_EPSILON);
    ck_assert_double_eq_tol(h.v, 0.0, 4 * DBL_EPSILON);
    ck_assert_int_eq(ray_capsule(&mid, &c, &h), 1);
    ck_assert_double_eq_tol(h.t, 1.5, tol);
    ck_assert_vec_eq_tol(h.n, vec(1, 0, 0), 4 * DBL_EPSILON);
    ck_assert_double_eq_tol(h.v, 1.0, 4 * DBL_EPSILON);
    ck_assert_int_eq(ray_capsule(&back, &c, &h), 1);
    ck_assert_double_eq_tol(h.t, 3.5, tol);
    ck_assert_vec_eq_tol(h.n, vec(1, 0, 0), 4 * DBL_EPSILON);
    /* 0.3 and 0.09 are not dyadic: 1e-14 covers their roundings; at
    ** offset 1e5, o + 0.3 rounds by up to an ulp of 1e5, which turns the
    ** normal by that over R (and moves v with it): tol over R = 2 tol. */
    ck_assert_int_eq(ray_capsule(&off, &c, &h), 1);
    ck_assert_double_eq_tol(h.t, 3.6, 1e-14 + tol);
    ck_assert_vec_eq_tol(h.n, vec(-0.8, 0.6, 0), 1e-14 + 2 * tol);
    ck_assert_double_eq_tol(h.v, 0.5 * atan2(0.6, 0.8) / (PI / 2 + 2),
                            1e-14 + 2 * tol);
}
END_TEST

START_TEST(capsule_should_miss_to_the_side_and_behind)
{
    double o = test_offset(_i);
    ray_capsule_params c = unit_x(o);
    ray_ray side = ray_from(vec(o, o + 0.6, o - 5), vec(0, 0, 1));
    ray_ray past = ray_from(vec(o + 1.6, o, o - 5), vec(0, 0, 1));
    ray_ray behind = ray_from(vec(o, o, o + 5), vec(0, 0, 1));
    ray_ray along = ray_from(vec(o - 5, o + 0.6, o), vec(1, 0, 0));
    ray_hit h;

    hit_poison(&h);
    ck_assert_int_eq(ray_capsule(&side, &c, &h), 0);
    ck_assert_int_eq(ray_capsule(&past, &c, &h), 0);
    ck_assert_int_eq(ray_capsule(&behind, &c, &h), 0);
    ck_assert_int_eq(ray_capsule(&along, &c, &h), 0);
    ck_assert(hit_is_poisoned(&h));
}
END_TEST

/* From inside: the midpoint along (1, 1, 0) leaves through the cylinder
** at y = 1/2, x = 1/2 <= half: t = 1/2; along (3, 1, 0) through b's cap
** (x = 1 + R cos, y = R sin on the line y = x/3: t = x/3 with
** (x - 1)^2 + (x/3)^2 = 1/4, the larger root). */
START_TEST(capsule_should_hit_far_side_from_inside)
{
    double o = test_offset(_i), tol = tol_at(o);
    ray_capsule_params c = unit_x(o);
    ray_ray diag = ray_from(vec(o, o, o), vec(1, 1, 0));
    ray_ray cap = ray_from(vec(o, o, o), vec(3, 1, 0));
    ray_hit h;
    /* 10/9 x^2 - 2 x + 3/4 = 0: x = (2 + sqrt(4 - 10/3)) / (20/9). */
    double x = (2 + sqrt(4 - 10.0 / 3)) / (20.0 / 9);

    ck_assert_int_eq(ray_capsule(&diag, &c, &h), 1);
    ck_assert_double_eq_tol(h.t, 0.5, tol);
    ck_assert_vec_eq_tol(h.n, vec(0, 1, 0), 4 * DBL_EPSILON);
    ck_assert_int_eq(ray_capsule(&cap, &c, &h), 1);
    ck_assert_double_eq_tol(h.t, x / 3, 1e-14 + tol);
    ck_assert(h.n.x > 0 && h.n.y > 0);
}
END_TEST

/* The open interval: t exactly at tmin or tmax is not a hit; with tmin
** on the entry the exit is returned. */
START_TEST(capsule_should_respect_open_interval)
{
    ray_capsule_params c = unit_x(0);
    ray_ray r = ray_from(vec(0, 0, -5), vec(0, 0, 1));
    ray_hit h;

    r.tmin = 4.5;
    ck_assert_int_eq(ray_capsule(&r, &c, &h), 1);
    ck_assert_double_eq(h.t, 5.5);
    r.tmin = 0;
    r.tmax = 4.5;
    hit_poison(&h);
    ck_assert_int_eq(ray_capsule(&r, &c, &h), 0);
    ck_assert(hit_is_poisoned(&h));
    r.tmax = nextafter(4.5, 5.0);
    ck_assert_int_eq(ray_capsule(&r, &c, &h), 1);
    ck_assert_double_eq(h.t, 4.5);
    r.tmin = 4.5;
    r.tmax = 5.5;
    ck_assert_int_eq(ray_capsule(&r, &c, &h), 0);
    r.tmin = 6;                         /* tmin > tmax: empty */
    r.tmax = 1;
    ck_assert_int_eq(ray_capsule(&r, &c, &h), 0);
}
END_TEST

/* ------------------------------------------------ the long double model */

/*
** The reference: every crossing of the cylinder and of the two cap
** spheres in long double, from the same double inputs (converted
** exactly), kept if it lies on the capsule's part of that surface (the
** cylinder within the segment's slab, a cap beyond its end), the
** nearest past tmin = 0 returned.  The quadratics are those of the
** textbook, with the near root in the stable form: long double's 11 more
** bits cover the cancellation of b^2 - ac for the small f of these rays.
*/
static int ref_capsule(ray_vec3 org, ray_vec3 dir, ray_capsule_params c,
                       long double *t_best, long double n_best[3])
{
    long double a[3] = {(long double)c.a.x, (long double)c.a.y,
                        (long double)c.a.z};
    long double b[3] = {(long double)c.b.x, (long double)c.b.y,
                        (long double)c.b.z};
    long double O[3] = {(long double)org.x, (long double)org.y,
                        (long double)org.z};
    long double D[3] = {(long double)dir.x, (long double)dir.y,
                        (long double)dir.z};
    long double m[3], w[3], f[3], L = 0, R = (long double)c.radius, fw = 0;
    long double dw = 0;
    long double fp[3], dp[3], best = -1;
    int i, side, found = 0;

    for (i = 0; i < 3; i++) {
        m[i] = (a[i] + b[i]) / 2;
        w[i] = (b[i] - a[i]) / 2;
        L += w[i] * w[i];
        f[i] = O[i] - m[i];
    }
    L = sqrtl(L);
    for (i = 0; i < 3; i++) {
        w[i] = L > 0 ? w[i] / L : (i == 1);
        fw += f[i] * w[i];
        dw += D[i] * w[i];
    }
    for (i = 0; i < 3; i++) {
        fp[i] = f[i] - fw * w[i];
        dp[i] = D[i] - dw * w[i];
    }
    /* side 0: the cylinder; -1, +1: the caps about -+ half. */
    for (side = -1; side <= 1; side++) {
        long double ff[3], dd[3], qa = 0, qb = 0, qc = 0, disc, q, r[2];
        int k;

        for (i = 0; i < 3; i++) {
            ff[i] = side == 0 ? fp[i] : f[i] - side * L * w[i];
            dd[i] = side == 0 ? dp[i] : D[i];
            qa += dd[i] * dd[i];
            qb -= ff[i] * dd[i];
            qc += ff[i] * ff[i];
        }
        qc -= R * R;
        disc = qb * qb - qa * qc;
        if (!(qa > 0) || disc < 0)
            continue;
        q = qb + copysignl(sqrtl(disc), qb);
        r[0] = qc / q;
        r[1] = q / qa;
        for (k = 0; k < 2; k++) {
            long double z = fw + r[k] * dw, t = r[k];
            int on = side == 0 ? fabsl(z) <= L : side * z >= L;

            if (on && t > 0 && (!found || t < best)) {
                found = 1;
                best = t;
                for (i = 0; i < 3; i++) {
                    long double pi = f[i] + t * D[i];
                    long double ax = side == 0 ? fw + t * dw : side * L;
                    n_best[i] = (pi - ax * w[i]) / R;
                }
            }
        }
    }
    *t_best = best;
    return found;
}

/* The offsets of the reference tests. */
static const double ref_offsets[3] = {0, 1e5, 1e6};

/* A random capsule near (o, o, o): ends within 3, radius 0.1 to 2. */
static ray_capsule_params random_capsule(rng *g, double o, int point)
{
    ray_vec3 m = vadd(vec(o, o, o), rng_point(g, -3, 3));
    ray_vec3 a = vadd(m, rng_point(g, -3, 3));
    return capsule(a, point ? a : vadd(m, rng_point(g, -3, 3)),
                   rng_range(g, 0.1, 2));
}

/* A point on the surface and its normal: on the cylinder or a cap. */
static ray_vec3 surface_point(rng *g, ray_capsule_params c, ray_vec3 *n)
{
    ray_vec3 h = vsub(c.b, c.a), w, dir = rng_dir(g);
    double len = vlen(h);

    w = len > 0 ? vscale(h, 1 / len) : vec(0, 1, 0);
    if (len > 0 && rng_unit(g) < 0.5) {
        ray_vec3 perp = vsub(dir, vscale(w, vdot(dir, w)));
        *n = vscale(perp, 1 / vlen(perp));
        return vadd(vadd(c.a, vscale(h, rng_unit(g))),
                    vscale(*n, c.radius));
    }
    *n = dir;
    return vadd(vdot(dir, w) >= 0 ? c.b : c.a, vscale(dir, c.radius));
}

/*
** 6000 random capsules per offset 0, 1e5, 1e6, each with a random
** surface point P aimed at from outside within 78 degrees of the normal
** (cos > 0.2), from 0.5 to 20 away: the hit must be the reference's.
** Tolerance on the distance along the ray: the inputs' coordinates are
** up to M = 1.8 offset + 10, f = org - m is exact to u M and everything
** after it is relative to |f| <= 30: a few dozen roundings; the error
** across the surface reaches t through 1/cos <= 5: 5 * 64 u (M + 30).
** (At offset 0 that is 1.1e-12; at 1e6, 6e-8.)  The normal: 1e-10 --
** the point's error over the radius >= 0.1, at 1e6 (6e-8 / 0.1 would
** be too tight for the worst rays: 64 u M / R = 1.4e-8 is the normal's
** own bound; we allow 1e-6 there and 1e-10 at 0).
*/
START_TEST(capsule_should_match_long_double_reference)
{
    double o = ref_offsets[_i];
    double M = 1.8 * o + 10, tol = 5 * 64 * U64 * (M + 30);
    double ntol = o == 0 ? 1e-10 : 1e-6;
    rng g = {7 + (uint64_t)_i};
    int i;

    for (i = 0; i < 6000; i++) {
        ray_capsule_params c = random_capsule(&g, o, i % 10 == 0);
        ray_vec3 n, P = surface_point(&g, c, &n), w;
        ray_ray r;
        ray_hit h;
        long double t_ref, n_ref[3];
        double dl;

        do
            w = rng_dir(&g);
        while (vdot(w, n) < 0.2);
        r = ray_from(vadd(P, vscale(w, rng_range(&g, 0.5, 20))),
                     vec(0, 0, 0));
        r.dir = vsub(P, r.org);
        dl = vlen(r.dir);
        ck_assert_int_eq(ref_capsule(r.org, r.dir, c, &t_ref, n_ref), 1);
        ck_assert_msg(ray_capsule(&r, &c, &h) == 1, "ray %d missed", i);
        ck_assert_msg(fabs(h.t - (double)t_ref) * dl <= tol,
                      "ray %d: t %.17g, reference %.17Lg", i, h.t, t_ref);
        ck_assert_double_eq_tol(h.n.x, (double)n_ref[0], ntol);
        ck_assert_double_eq_tol(h.n.y, (double)n_ref[1], ntol);
        ck_assert_double_eq_tol(h.n.z, (double)n_ref[2], ntol);
        ck_assert_double_eq_tol(vlen(h.n), 1.0, 4 * DBL_EPSILON);
        ck_assert(hit_is_finite(&h));
        /* p within its own bound (plus the tolerance) of the line's point
        ** at the reference's t, which lies on the exact surface. */
        {
            long double q[3] = {
                (long double)r.org.x + t_ref * (long double)r.dir.x,
                (long double)r.org.y + t_ref * (long double)r.dir.y,
                (long double)r.org.z + t_ref * (long double)r.dir.z};
            ck_assert(fabsl((long double)h.p.x - q[0]) <=
                      (long double)(h.p_err.x + tol));
            ck_assert(fabsl((long double)h.p.y - q[1]) <=
                      (long double)(h.p_err.y + tol));
            ck_assert(fabsl((long double)h.p.z - q[2]) <=
                      (long double)(h.p_err.z + tol));
        }
    }
}
END_TEST

/*
** Tangent rays.  Along z at height y = R over the cylinder's middle: the
** closest approach is exactly R (disc = 0), one hit at t = 5; 1e-9
** higher, a miss; 1e-9 lower, the entry near 5 - sqrt(R^2 - y^2) =
** 5 - 3.2e-5, checked in long double from the y actually stored.  The
** root moves by y / sqrt(R^2 - y^2) ~ 1.6e4 per unit of the distance
** of the line from the axis, but along this axis-aligned ray that
** distance is y exactly (sqrt(fl(y * y)) = |y| in binary floating
** point) and R - y exact (Sterbenz), so only the roots' own roundings
** remain: 8u |t| (the code gives one ulp; the margin was 1e-11 before,
** wide enough for R^2 - l^2 squared first, which puts t 1.6e-14 off).  Touching b's pole (x = half + R): t = 5.
** Along the top line y = R, parallel to the axis: the ray lies in the
** surface; it is tangent to a's sphere at the seam: t = 4 (x = -1).
*/
START_TEST(capsule_should_classify_tangent_rays)
{
    double o = test_offset(_i), tol = tol_at(o);
    ray_capsule_params c = unit_x(o);
    ray_ray tangent = ray_from(vec(o, o + 0.5, o - 5), vec(0, 0, 1));
    ray_ray above = ray_from(vec(o, o + 0.5 + 1e-9, o - 5), vec(0, 0, 1));
    ray_ray below = ray_from(vec(o, o + 0.5 - 1e-9, o - 5), vec(0, 0, 1));
    ray_ray pole = ray_from(vec(o + 1.5, o, o - 5), vec(0, 0, 1));
    ray_ray line = ray_from(vec(o - 5, o + 0.5, o), vec(1, 0, 0));
    ray_ray line_above = ray_from(vec(o - 5, o + 0.5 + 1e-9, o),
                                  vec(1, 0, 0));
    ray_hit h;

    ck_assert_int_eq(ray_capsule(&tangent, &c, &h), 1);
    ck_assert_double_eq_tol(h.t, 5.0, tol);
    ck_assert_vec_eq_tol(h.n, vec(0, 1, 0), 1e-12);
    ck_assert_int_eq(ray_capsule(&above, &c, &h), 0);
    ck_assert_int_eq(ray_capsule(&below, &c, &h), 1);
    if (o == 0) {
        long double y = (long double)below.org.y;
        ck_assert_double_eq_tol(h.t, (double)(5.0L - sqrtl(0.25L - y * y)),
                                8 * U64 * 5);
    }
    ck_assert_int_eq(ray_capsule(&pole, &c, &h), 1);
    ck_assert_double_eq_tol(h.t, 5.0, tol);
    ck_assert_vec_eq_tol(h.n, vec(1, 0, 0), 1e-12);
    ck_assert_int_eq(ray_capsule(&line, &c, &h), 1);
    ck_assert_double_eq_tol(h.t, 4.0, tol);
    ck_assert_vec_eq_tol(h.n, vec(0, 1, 0), 1e-12);
    ck_assert(hit_is_finite(&h));
    ck_assert_int_eq(ray_capsule(&line_above, &c, &h), 0);
}
END_TEST

/*
** Grazing rays against a rotated capsule: rays at 1e-6 to 1e-3 outside
** and inside the silhouette of the cylinder and of a cap, at offsets 0
** and 1e5: hit and miss as the reference says, and the hits' t within
** the reference's by the tolerance of the aimed test divided by the
** grazing cosine's square root (a near-double root: t moves by
** sqrt(error / curvature)): 1e-6 covers it at both offsets.
*/
START_TEST(capsule_should_classify_grazing_rays)
{
    double o = test_offset(_i);
    ray_vec3 a = vec(o + 0.3, o - 0.7, o + 0.2), b = vec(o - 0.9, o + 1.1,
                                                         o + 0.5);
    ray_capsule_params c = capsule(a, b, 0.4);
    ray_vec3 w = vscale(vsub(b, a), 1 / vdist(a, b));
    ray_vec3 side = vcross(w, vec(0, 0, 1)), across;
    rng g = {11};
    int i, hits = 0;

    side = vscale(side, 1 / vlen(side));
    across = vcross(w, side);
    for (i = 0; i < 400; i++) {
        double gap = (i % 2 ? 1 : -1) * pow(10, -6 + 3 * rng_unit(&g));
        int cap = i % 4 >= 2;
        /* Along "across", passing at distance R + gap from the axis
        ** (cylinder) or from b's centre beyond the axis' end (cap). */
        ray_vec3 centre = cap ? vadd(b, vscale(w, 0.2)) : vscale(vadd(a, b),
                                                                 0.5);
        double dist = 0.4 + gap;
        ray_vec3 through;
        ray_ray r;
        ray_hit h;
        long double t_ref, n_ref[3];
        int ref;

        if (cap) {
            /* Through the sphere about b, height above the centre 0.2. */
            double rho = sqrt(fmax(dist * dist - 0.04, 0));
            centre = b;
            through = vadd(vadd(centre, vscale(w, 0.2)), vscale(side, rho));
        } else
            through = vadd(centre, vscale(side, dist));
        r = ray_from(vsub(through, vscale(across, 5)), across);
        ref = ref_capsule(r.org, r.dir, c, &t_ref, n_ref);
        if (fabs(gap) < 1e-5)
            continue;           /* too close for the reference's inputs */
        ck_assert_int_eq(ray_capsule(&r, &c, &h), ref);
        if (ref) {
            hits++;
            ck_assert_double_eq_tol(h.t, (double)t_ref, 1e-6);
        }
    }
    ck_assert_int_gt(hits, 50);
}
END_TEST

/* ------------------------------------------------------- more hard cases */

START_TEST(capsule_should_miss_on_bad_input)
{
    ray_capsule_params c = unit_x(0), bad;
    ray_vec3 org = vec(0, 0, -5), dir = vec(0, 0, 1);
    double nan = (double)NAN, inf = HUGE_VAL;
    double radii[] = {0.0, -0.0, -1.0, nan, inf, -inf};
    ray_ray rays[8], ok = ray_from(org, dir);
    ray_hit h;
    int i;

    rays[0] = ray_from(vec(nan, 0, -5), dir);
    rays[1] = ray_from(org, vec(0, nan, 1));
    rays[2] = ray_from(vec(0, 0, -inf), dir);
    rays[3] = ray_from(org, vec(0, 0, inf));
    rays[4] = ray_from(org, vec(0, 0, 0));
    rays[5] = make_ray(org, dir, nan, HUGE_VAL);
    rays[6] = make_ray(org, dir, 0, nan);
    rays[7] = ray_from(org, vec(-0.0, -0.0, -0.0));
    hit_poison(&h);
    for (i = 0; i < 8; i++)
        ck_assert_msg(ray_capsule(&rays[i], &c, &h) == 0, "ray %d", i);
    ck_assert_int_eq(ray_capsule(NULL, &c, &h), 0);
    ck_assert_int_eq(ray_capsule(&ok, NULL, &h), 0);
    ck_assert_int_eq(ray_capsule(&ok, &c, NULL), 0);
    for (i = 0; i < 6; i++) {
        bad = c;
        bad.radius = radii[i];
        ck_assert_int_eq(ray_capsule(&ok, &bad, &h), 0);
    }
    bad = c;
    bad.a.x = nan;
    ck_assert_int_eq(ray_capsule(&ok, &bad, &h), 0);
    bad = c;
    bad.b.z = -inf;
    ck_assert_int_eq(ray_capsule(&ok, &bad, &h), 0);
    /* Finite but reaching past the largest double. */
    bad = capsule(vec(-1e308, 0, 0), vec(1e308, 0, 0), 1e308);
    ck_assert_int_eq(ray_capsule(&ok, &bad, &h), 0);
    ck_assert(hit_is_poisoned(&h));
}
END_TEST

/*
** A capsule of radius 1e-3 and half-length 1e-3, 1e4 away (the textbook
** b^2 - ac would subtract ~1e16-sized terms): rays across its cylinder
** at 0.9e-3 and 1.1e-3 from the axis hit and miss; along the axis, the
** pole at 1e4 - 2e-3 within a few ulps of 1e4 (1.8e-12): 1e-10.
*/
START_TEST(capsule_should_hit_tiny_and_far)
{
    double o = test_offset(_i);
    ray_capsule_params c = capsule(vec(o - 1e-3, o, o - 1e4),
                                   vec(o + 1e-3, o, o - 1e4), 1e-3);
    ray_ray in = ray_from(vec(o, o + 0.9e-3, o), vec(0, 0, -1));
    ray_ray out = ray_from(vec(o, o + 1.1e-3, o), vec(0, 0, -1));
    ray_ray axis = ray_from(vec(o + 1e4, o, o - 1e4), vec(-1, 0, 0));
    ray_hit h;

    ck_assert_int_eq(ray_capsule(&in, &c, &h), 1);
    ck_assert_double_eq_tol(h.t, 1e4 - sqrt(1e-6 - 0.81e-6), 1e-9);
    ck_assert_int_eq(ray_capsule(&out, &c, &h), 0);
    ck_assert_int_eq(ray_capsule(&axis, &c, &h), 1);
    ck_assert_double_eq_tol(h.t, 1e4 - 2e-3, 1e-10 + tol_at(o));
}
END_TEST

/*
** Rays along a rotated axis (b - a as the direction: across-axis
** components are rounding residues, not 0, so the cylinder's quadratic
** is barely non-degenerate) and exactly along an axis-aligned one (they
** are 0, and for 1e-170 their squares are): all reach a's pole; the rotated one within 1e-12 of the
** distance |b - a| / 2 + R ahead of the midpoint (the residues tilt the
** ray by ~1e-16 rad).
*/
START_TEST(capsule_should_hit_caps_of_rays_along_the_axis)
{
    double o = test_offset(_i), tol = tol_at(o);
    ray_vec3 a = vec(o + 0.3, o - 0.7, o + 0.2), b = vec(o - 0.9, o + 1.1,
                                                         o + 0.5);
    ray_capsule_params c = capsule(a, b, 0.4);
    ray_vec3 d = vsub(b, a);
    double half = vlen(d) / 2;
    ray_ray r = ray_from(vsub(a, vscale(d, 2)), d);
    ray_ray y = ray_from(vec(o, o - 7, o), vec(0, 3, 0));
    ray_capsule_params cy = capsule(vec(o, o - 1, o), vec(o, o + 2, o), 0.25);
    ray_hit h;

    ck_assert_int_eq(ray_capsule(&r, &c, &h), 1);
    /* From a - 2d: the midpoint is 2.5 |d| away, the pole half + R less. */
    ck_assert_double_eq_tol(h.t * vlen(d), 2.5 * vlen(d) - half - 0.4,
                            1e-12 + tol);
    ck_assert_double_eq_tol(vdot(h.n, d) / vlen(d), -1.0, 1e-12);
    ck_assert_double_eq_tol(h.v, 0.0, 1e-7);
    ck_assert_int_eq(ray_capsule(&y, &cy, &h), 1);
    ck_assert_double_eq_tol(h.t, (7 - 1.25) / 3, tol);
    ck_assert_vec_eq_tol(h.n, vec(0, -1, 0), 4 * DBL_EPSILON);
    /* Across the axis by 1e-170: its square underflows (the cylinder's
    ** leading coefficient is 0), and the ray is taken as parallel: a's
    ** pole at t = 5.25 / 3 all the same (it drifts by 1e-170). */
    y.dir = vec(1e-170, 3, 0);
    ck_assert_int_eq(ray_capsule(&y, &cy, &h), 1);
    ck_assert_double_eq_tol(h.t, (7 - 1.25) / 3, tol);
}
END_TEST

/*
** v is continuous across the seams and increases along a meridian: the
** rays down -z at x from -1.6 to 1.6 over the capsule unit_x(0) meet
** the meridian y = 0, z > 0; between neighbours v grows by the arc
** between their hit points over the meridian's length (pi R + 2 =
** 3.5708), at most the chord's length times pi/2 (arc / chord <= pi/2
** on a circle, 1 on the line).  u stays 1/4 (n.t1 = -n.z < 0, n.t2 = 0)
** except at the poles (x = -+1.5), where the angle around the axis is
** not defined (n.t1 = n.t2 = 0).
*/
START_TEST(capsule_should_give_continuous_texture_coordinates)
{
    ray_capsule_params c = unit_x(0);
    double prev_v = -1, total = PI * 0.5 + 2;
    ray_vec3 prev_p = vec(0, 0, 0);
    int i, hits = 0;

    for (i = 0; i <= 640; i++) {
        double x = -1.6 + 3.2 * i / 640;
        ray_ray r = ray_from(vec(x, 0, 5), vec(0, 0, -1));
        ray_hit h;

        if (ray_capsule(&r, &c, &h) != 1)
            continue;
        if (fabs(h.n.z) > 1e-6)
            ck_assert_double_eq_tol(h.u, 0.25, 4 * DBL_EPSILON);
        ck_assert(h.v >= 0 && h.v <= 1);
        if (prev_v >= 0) {
            ck_assert(h.v >= prev_v);
            ck_assert(h.v - prev_v <=
                      vdist(h.p, prev_p) * (PI / 2) / total + 1e-15);
        }
        prev_v = h.v;
        prev_p = h.p;
        hits++;
    }
    ck_assert_int_gt(hits, 550);
    ck_assert_double_eq_tol(prev_v, 1.0, 1e-2);
}
END_TEST

/*
** A capsule with a == b is the sphere: random rays hit and miss as
** ray_sphere does (away from its silhouette: 1e-9 of the radius), with
** the same t (1e-12: both a few ulps of their coordinates below 30),
** normal and v (1e-12), and u away from its seam (u is within 1e-12 of
** ray_sphere's, mod 1).
*/
START_TEST(point_capsule_should_be_ray_sphere)
{
    rng g = {21};
    int i, hits = 0;

    for (i = 0; i < 5000; i++) {
        ray_vec3 ctr = rng_point(&g, -10, 10);
        double R = rng_range(&g, 0.1, 5);
        ray_capsule_params c = capsule(ctr, ctr, R);
        ray_ray r = ray_from(vadd(ctr, rng_point(&g, -15, 15)),
                             rng_point(&g, -1, 1));
        ray_hit hs, hc;
        int s, k;

        r.dir = vsub(vadd(ctr, rng_point(&g, -R * 1.2, R * 1.2)), r.org);
        {
            /* The distance from the centre to the line, against R. */
            ray_vec3 f = vsub(r.org, ctr);
            double tc = -vdot(f, r.dir) / vdot(r.dir, r.dir);
            if (fabs(vlen(vadd(f, vscale(r.dir, tc))) - R) < 1e-9 * R)
                continue;
        }
        s = ray_sphere(&r, ctr, R, &hs);
        k = ray_capsule(&r, &c, &hc);
        ck_assert_int_eq(k, s);
        if (!s)
            continue;
        hits++;
        ck_assert_double_eq_tol(hc.t, hs.t, 1e-12);
        ck_assert_vec_eq_tol(hc.n, hs.n, 1e-12);
        ck_assert_double_eq_tol(hc.v, hs.v, 1e-12);
        ck_assert(fabs(hc.u - hs.u) < 1e-12 ||
                  fabs(fabs(hc.u - hs.u) - 1) < 1e-12);
    }
    ck_assert_int_gt(hits, 1000);
}
END_TEST

/*
** The direction is scaled by a power of two: 2^-600 and 2^600 times a
** direction give bit for bit its hit, t scaled exactly; 1e-200 and 1e200
** (each component rounded: the ray turns by ~2^-53) the same hit or
** miss, with p within 2 p_err plus 8 ulps of the hit's distance and
** coordinates (rays closer than 1e-6 of the radius to the silhouette
** are left out: there the turn can flip hit and miss).
*/
START_TEST(capsule_should_not_depend_on_direction_length)
{
    rng g = {5};
    double len[4] = {0x1p-600, 0x1p600, 1e-200, 1e200};
    int i, k, hits = 0;

    for (i = 0; i < 3000; i++) {
        ray_capsule_params c = random_capsule(&g, test_offset(_i), 0);
        ray_vec3 m = vscale(vadd(c.a, c.b), 0.5);
        ray_ray r = ray_from(vadd(m, rng_point(&g, -8, 8)), vec(0, 0, 0)),
                rs;
        ray_hit h, hs;
        int hit;

        r.dir = vsub(vadd(m, rng_point(&g, -3, 3)), r.org);
        hit = ray_capsule(&r, &c, &h);
        hits += hit;
        for (k = 0; k < 4; k++) {
            rs = r;
            rs.dir = vscale(r.dir, len[k]);
            if (k < 2) {
                ck_assert_int_eq(ray_capsule(&rs, &c, &hs), hit);
                if (hit) {
                    ck_assert(hs.t == h.t / len[k]);
                    ck_assert(hs.p.x == h.p.x && hs.p.y == h.p.y &&
                              hs.p.z == h.p.z);
                }
            } else if (hit && ray_capsule(&rs, &c, &hs) == 1) {
                double slack = 8 * DBL_EPSILON *
                               (h.t * vlen(r.dir) * 10 + 2 * fabs(m.x) + 20);
                ck_assert(fabs(hs.p.x - h.p.x) <= 2 * h.p_err.x + slack);
                ck_assert(fabs(hs.p.y - h.p.y) <= 2 * h.p_err.y + slack);
                ck_assert(fabs(hs.p.z - h.p.z) <= 2 * h.p_err.z + slack);
            }
        }
    }
    ck_assert_int_gt(hits, 500);
}
END_TEST

/* ------------------------------------------------------------ the scene */

/*
** A capsule among a sphere, a plane and a triangle, through the BVH:
** ray_intersect answers what ray_capsule answers wherever the capsule is
** nearest (the same t, p, n, u, v bit for bit: the scene calls
** ray_capsule on its copy), with the capsule's geom_id; ray_occluded
** agrees with ray_intersect.
*/
START_TEST(scene_capsule_should_match_bare_function)
{
    double o = test_offset(_i);
    ray_capsule_params c = capsule(vec(o - 1, o + 0.2, o), vec(o + 1.2, o + 0.9,
                                                              o - 0.4), 0.45);
    ray_material m = plain();
    ray_scene *s;
    unsigned mat, id, other;
    rng g = {3};
    int i, capsule_hits = 0;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, &mat), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(o + 3, o, o), 1, mat,
                                          &other), RAY_OK);
    ck_assert_int_eq(ray_scene_add_capsule(s, &c, mat, &id), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(o, o - 2, o), vec(0, 1, 0),
                                         mat, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_triangle(s, vec(o - 3, o, o - 3),
                                            vec(o - 2, o, o - 3),
                                            vec(o - 3, o + 1, o - 3), mat,
                                            NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    for (i = 0; i < 2000; i++) {
        ray_ray r = ray_from(vadd(vec(o, o, o), rng_point(&g, -6, 6)),
                             vec(0, 0, 0));
        ray_hit hs, hb;
        int bare, scene;

        r.dir = vsub(vadd(vec(o, o, o), rng_point(&g, -1.5, 1.5)), r.org);
        bare = ray_capsule(&r, &c, &hb);
        scene = ray_intersect(s, &r, &hs, NULL);
        ck_assert_int_ge(scene, 0);
        ck_assert_int_eq(ray_occluded(s, &r, NULL), scene);
        if (scene == 1 && hs.geom_id == id) {
            capsule_hits++;
            ck_assert_int_eq(bare, 1);
            ck_assert(hs.t == hb.t && hs.u == hb.u && hs.v == hb.v);
            ck_assert_vec_eq(hs.p, hb.p);
            ck_assert_vec_eq(hs.n, hb.n);
            ck_assert_vec_eq(hs.p_err, hb.p_err);
            ck_assert_uint_eq(hs.prim_id, 0);
        } else if (bare) {
            /* Something else is nearer. */
            ck_assert_int_eq(scene, 1);
            ck_assert(hs.t <= hb.t);
        }
    }
    ck_assert_int_gt(capsule_hits, 300);
    ray_scene_free(s);
}
END_TEST

/* RAY_EINVAL, nothing added, and a message naming the field. */
START_TEST(scene_capsule_should_refuse_bad_params)
{
    ray_material m = plain();
    ray_capsule_params c = unit_x(0), bad;
    ray_scene *s;
    unsigned mat, id = 77;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, &mat), RAY_OK);
    ck_assert_int_eq(ray_scene_add_capsule(s, NULL, mat, &id), RAY_EINVAL);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(s), "NULL"));
    bad = c;
    bad.radius = -1;
    ck_assert_int_eq(ray_scene_add_capsule(s, &bad, mat, &id), RAY_EINVAL);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(s),
                                 "ray_scene_add_capsule: radius -1"));
    bad.radius = HUGE_VAL;
    ck_assert_int_eq(ray_scene_add_capsule(s, &bad, mat, &id), RAY_EINVAL);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(s),
                                 "ray_scene_add_capsule: radius inf"));
    bad = c;
    bad.a.y = (double)NAN;
    ck_assert_int_eq(ray_scene_add_capsule(s, &bad, mat, &id), RAY_EINVAL);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(s), "end a"));
    bad = c;
    bad.b.x = HUGE_VAL;
    ck_assert_int_eq(ray_scene_add_capsule(s, &bad, mat, &id), RAY_EINVAL);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(s), "end b"));
    bad = capsule(vec(-1e308, 0, 0), vec(1e308, 0, 0), 1e308);
    ck_assert_int_eq(ray_scene_add_capsule(s, &bad, mat, &id), RAY_EINVAL);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(s), "largest double"));
    ck_assert_int_eq(ray_scene_add_capsule(s, &c, mat + 1, &id), RAY_EINVAL);
    ck_assert_uint_eq(id, 77);
    /* A point capsule is valid. */
    bad = capsule(vec(1, 2, 3), vec(1, 2, 3), 0.5);
    ck_assert_int_eq(ray_scene_add_capsule(s, &bad, mat, &id), RAY_OK);
    ck_assert_uint_eq(id, 0);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    /* Refused after commit too, and the scene stays committed. */
    ck_assert_int_eq(ray_scene_add_capsule(s, &bad, mat + 1, &id), RAY_EINVAL);
    ck_assert_uint_eq(id, 0);
    ck_assert_int_ge(ray_occluded(s, &(ray_ray){{0, 0, 0}, {0, 1, 0}, 0, 1},
                                  NULL), 0);
    ray_scene_free(s);
}
END_TEST

/* A render of a capsule alone counts its tests under RAY_PRIM_CAPSULE
** and under no other kind. */
START_TEST(scene_capsule_should_count_under_its_kind)
{
    enum { W = 24, H = 16 };
    ray_capsule_params c = unit_x(0);
    ray_material m = plain();
    ray_camera cam;
    ray_render_options o;
    ray_stats st;
    ray_scene *s;
    float img[3 * W * H];
    int k;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_capsule(s, &c, 0, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    cam = (ray_camera){.look_at = {0, 0, -1}};
    cam.position = vec(0, 0, 4);
    o = (ray_render_options){.width = W, .height = H};
    ck_assert_int_eq(ray_render(s, &cam, &o, img, &st), RAY_OK);
    ck_assert_uint_gt(st.tests_by_kind[RAY_PRIM_CAPSULE], 0);
    for (k = 0; k < RAY_PRIM_KINDS_MAX; k++)
        ck_assert_uint_eq(st.tests_by_kind[k],
                          k == RAY_PRIM_CAPSULE ? st.tests : 0);
    ray_scene_free(s);
}
END_TEST

Suite *capsule_suite(void)
{
    Suite *s = suite_create("capsule");
    TCase *core = tcase_create("hits");
    TCase *hard = tcase_create("hard");
    TCase *prop = tcase_create("property");
    TCase *scene = tcase_create("scene");

    tcase_add_loop_test(core, capsule_should_hit_side_at_exact_t, 0, N_OFFSETS);
    tcase_add_loop_test(core, capsule_should_hit_caps_along_the_axis, 0,
                        N_OFFSETS);
    tcase_add_loop_test(core, capsule_should_miss_to_the_side_and_behind, 0,
                        N_OFFSETS);
    tcase_add_loop_test(core, capsule_should_hit_far_side_from_inside, 0,
                        N_OFFSETS);
    tcase_add_test(core, capsule_should_respect_open_interval);
    tcase_add_test(core, capsule_should_give_continuous_texture_coordinates);
    tcase_add_loop_test(hard, capsule_should_classify_tangent_rays, 0,
                        N_OFFSETS);
    tcase_add_loop_test(hard, capsule_should_classify_grazing_rays, 0,
                        N_OFFSETS);
    tcase_add_test(hard, capsule_should_miss_on_bad_input);
    tcase_add_loop_test(hard, capsule_should_hit_tiny_and_far, 0, N_OFFSETS);
    tcase_add_loop_test(hard, capsule_should_hit_caps_of_rays_along_the_axis,
                        0, N_OFFSETS);
    tcase_add_loop_test(prop, capsule_should_match_long_double_reference, 0,
                        3);
    tcase_add_test(prop, point_capsule_should_be_ray_sphere);
    tcase_add_loop_test(prop, capsule_should_not_depend_on_direction_length,
                        0, N_OFFSETS);
    tcase_add_loop_test(scene, scene_capsule_should_match_bare_function, 0,
                        N_OFFSETS);
    tcase_add_test(scene, scene_capsule_should_refuse_bad_params);
    tcase_add_test(scene, scene_capsule_should_count_under_its_kind);
    suite_add_tcase(s, core);
    suite_add_tcase(s, hard);
    suite_add_tcase(s, prop);
    suite_add_tcase(s, scene);
    return s;
}
