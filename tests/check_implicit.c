/* SPDX-License-Identifier: MIT */
/*
** check_implicit.c -- ray_implicit (sphere tracing and bracketing),
** ray_torus (the quartic) against the generic method, metaballs, and the
** polynomial root finder behind the torus.
*/
#include <stdlib.h>

#include "prim/prim.h"
#include "tests.h"

/* ----------------------------------------------------------- fields */

/* The unit sphere's signed distance around a centre: 1-Lipschitz. */
typedef struct sphere_field {
    ray_vec3 c;
    double radius;
} sphere_field;

static double sphere_sdf(void *ud, ray_vec3 p)
{
    const sphere_field *s = ud;
    return vdist(p, s->c) - s->radius;
}

static ray_implicit_surface sphere_surface(sphere_field *sf, double lipschitz)
{
    ray_implicit_surface s;
    memset(&s, 0, sizeof s);
    s.f = sphere_sdf;
    s.ud = sf;
    s.lo = vsub(sf->c, vec(sf->radius, sf->radius, sf->radius));
    s.hi = vadd(sf->c, vec(sf->radius, sf->radius, sf->radius));
    s.lipschitz = lipschitz;
    return s;
}

/* The tolerance ray_implicit uses by default for box [lo, hi]: 1e-9 of
** the diagonal plus 64 DBL_EPSILON of the largest |coordinate| (ray.h). */
static double default_tol(const ray_implicit_surface *s)
{
    double big = fmax(fmax(fabs(s->lo.x), fabs(s->hi.x)),
                      fmax(fmax(fabs(s->lo.y), fabs(s->hi.y)),
                           fmax(fabs(s->lo.z), fabs(s->hi.z))));
    return 1e-9 * vdist(s->hi, s->lo) + 64 * DBL_EPSILON * big;
}

/* The exact distance of p from the sphere, in long double (64-bit
** significand), so the reference's own rounding is 2^11 below double's. */
static double sphere_distance(ray_vec3 p, ray_vec3 c, double radius)
{
    long double dx = (long double)p.x - (long double)c.x,
                dy = (long double)p.y - (long double)c.y,
                dz = (long double)p.z - (long double)c.z;
    return (double)fabsl(sqrtl(dx * dx + dy * dy + dz * dz) -
                         (long double)radius);
}

/* -------------------------------------------------- implicit sphere */

/*
** A sphere written as f = |p - c| - R agrees with ray_sphere on random
** rays through its box, in both modes, at the origin and at 1e5: the same
** hit or miss, and the implicit hit within the tolerance of the exact
** surface (plus its own p_err).  Rays that pass within 1e-6 of tangency
** are left out: there the answers may differ legitimately (a ray
** passing within the tolerance may touch), and they are tested apart.
** Normals: the unit gradient of the distance at a point within tol of
** the surface is off by up to ~tol / R radians (tol = 4.5e-9 at the
** origin, 1e-4 at 1e5: the default is relative to the coordinates), so
** 2 tol / R + 1e-9.
*/
START_TEST(implicit_sphere_should_agree_with_ray_sphere)
{
    double offset = test_offset(_i % N_OFFSETS), lip = _i / N_OFFSETS ? 0 : 1;
    sphere_field sf;
    ray_implicit_surface s;
    rng g = {42};
    int n, hits = 0;
    double tol;

    sf.c = vec(offset, -offset, 0.5 * offset);
    sf.radius = 1.0;
    s = sphere_surface(&sf, lip);
    tol = default_tol(&s);
    for (n = 0; n < 20000; n++) {
        ray_vec3 o = vadd(sf.c, vscale(rng_dir(&g), 3.0));
        ray_vec3 aim = vadd(sf.c, vscale(rng_dir(&g), 1.2));
        ray_ray r = ray_from(o, vsub(aim, o));
        ray_hit h1, h2;
        int a = ray_sphere(&r, sf.c, sf.radius, &h1);
        int b = ray_implicit(&r, &s, &h2);
        ray_vec3 u = vscale(r.dir, 1.0 / vlen(r.dir));
        ray_vec3 w = vsub(sf.c, o);
        double miss = vlen(vsub(w, vscale(u, vdot(w, u)))) - sf.radius;

        ck_assert_int_ge(b, 0);
        if (fabs(miss) < 2 * tol)
            continue;
        ck_assert_int_eq(a, b);
        if (!a)
            continue;
        hits++;
        ck_assert(hit_is_finite(&h2));
        ck_assert_double_le(sphere_distance(h2.p, sf.c, sf.radius),
                            tol + vlen(h2.p_err));
        ck_assert_vec_eq_tol(h2.n, h1.n, 2 * tol / sf.radius + 1e-9);
    }
    ck_assert_int_gt(hits, 5000);
}
END_TEST

/*
** Tangent rays: a ray touching the unit sphere (a double root of g) is a
** hit with the bound (sphere tracing, Lipschitz 1): the march slows to
** the tolerance near the touching point and the gradient probe finds the
** surface within it.  Raised by 1e-6 (1000x the tolerance) it misses in
** both modes; lowered by 1e-6 it crosses and hits in both.
*/
START_TEST(implicit_should_classify_tangent_rays)
{
    sphere_field sf;
    ray_implicit_surface s;
    ray_hit h;
    ray_ray touch, above, below;

    sf.c = vec(0, 0, 0);
    sf.radius = 1.0;
    s = sphere_surface(&sf, 1);
    touch = ray_from(vec(-2, 1, 0), vec(1, 0, 0));
    above = ray_from(vec(-2, 1 + 1e-6, 0), vec(1, 0, 0));
    below = ray_from(vec(-2, 1 - 1e-6, 0), vec(1, 0, 0));
    ck_assert_int_eq(ray_implicit(&touch, &s, &h), 1);
    /* Where a double root lies is decided only to ~sqrt(tol) along the
    ** ray (the sphere departs from the tangent as x^2 / 2R):
    ** sqrt(2 * 4.5e-9) ~ 1e-4. */
    ck_assert_double_eq_tol(h.t, 2.0, 2e-4);
    ck_assert_double_eq_tol(h.n.y, 1.0, 1e-6);
    hit_poison(&h);
    ck_assert_int_eq(ray_implicit(&above, &s, &h), 0);
    ck_assert(hit_is_poisoned(&h));
    ck_assert_int_eq(ray_implicit(&below, &s, &h), 1);
    s.lipschitz = 0;
    hit_poison(&h);
    ck_assert_int_eq(ray_implicit(&above, &s, &h), 0);
    ck_assert(hit_is_poisoned(&h));
    ck_assert_int_eq(ray_implicit(&below, &s, &h), 1);
}
END_TEST

/* A slab |y| < 5e-5, far thinner than the default step (diagonal / 128 =
** 0.027 in a box of side 2): sphere tracing cannot step over it, whatever
** the ray; bracketing with the default step can (documented). */
static double thin_slab(void *ud, ray_vec3 p)
{
    (void)ud;
    return fabs(p.y) - 5e-5;
}

START_TEST(implicit_should_not_skip_thin_features_with_a_bound)
{
    ray_implicit_surface s;
    rng g = {7};
    int n, skipped_without_bound = 0;

    memset(&s, 0, sizeof s);
    s.f = thin_slab;
    s.lo = vec(-1, -1, -1);
    s.hi = vec(1, 1, 1);
    for (n = 0; n < 2000; n++) {
        ray_vec3 o = vec(rng_range(&g, -0.5, 0.5), 1.0, rng_range(&g, -0.5, 0.5));
        ray_vec3 d = vec(rng_range(&g, -0.4, 0.4), -1, rng_range(&g, -0.4, 0.4));
        ray_ray r = ray_from(o, d);
        ray_hit h;
        s.lipschitz = 1;
        ck_assert_int_eq(ray_implicit(&r, &s, &h), 1);
        /* The top face y = 5e-5, to the tolerance (4.5e-9 by default). */
        ck_assert_double_eq_tol(h.p.y, 5e-5, 1e-8);
        s.lipschitz = 0;
        skipped_without_bound += ray_implicit(&r, &s, &h) == 0;
    }
    /* Not an assertion of a virtue: it shows why the bound matters. */
    ck_assert_int_gt(skipped_without_bound, 0);
}
END_TEST

/* Failure is reported, never a guess: too few evaluations for a grazing
** ray give -RAY_ELIMIT, a field returning NaN gives -RAY_EINVAL, and
** *hit is untouched either way. */
static double nan_field(void *ud, ray_vec3 p)
{
    (void)ud;
    return p.x > 0 ? (double)NAN : 1.0;
}

START_TEST(implicit_should_report_failures)
{
    sphere_field sf;
    ray_implicit_surface s;
    ray_ray r = ray_from(vec(-2, 1 - 1e-3, 0), vec(1, 0, 0));
    ray_hit h;

    sf.c = vec(0, 0, 0);
    sf.radius = 1.0;
    s = sphere_surface(&sf, 1);
    s.max_iterations = 3;
    hit_poison(&h);
    ck_assert_int_eq(ray_implicit(&r, &s, &h), -RAY_ELIMIT);
    ck_assert(hit_is_poisoned(&h));
    s.max_iterations = 0;
    s.f = nan_field;
    r = ray_from(vec(-2, 0, 0), vec(1, 0, 0));
    ck_assert_int_eq(ray_implicit(&r, &s, &h), -RAY_EINVAL);
    ck_assert(hit_is_poisoned(&h));
}
END_TEST

START_TEST(implicit_should_reject_bad_input)
{
    sphere_field sf;
    ray_implicit_surface s, bad;
    ray_ray r = ray_from(vec(-3, 0, 0), vec(1, 0, 0));
    ray_hit h;

    sf.c = vec(0, 0, 0);
    sf.radius = 1.0;
    s = sphere_surface(&sf, 1);
    hit_poison(&h);
    ck_assert_int_eq(ray_implicit(NULL, &s, &h), -RAY_EINVAL);
    ck_assert_int_eq(ray_implicit(&r, NULL, &h), -RAY_EINVAL);
    ck_assert_int_eq(ray_implicit(&r, &s, NULL), -RAY_EINVAL);
    bad = s;
    bad.f = NULL;
    ck_assert_int_eq(ray_implicit(&r, &bad, &h), -RAY_EINVAL);
    bad = s;
    bad.lo.x = 2;                                   /* lo > hi */
    ck_assert_int_eq(ray_implicit(&r, &bad, &h), -RAY_EINVAL);
    bad = s;
    bad.hi.y = HUGE_VAL;
    ck_assert_int_eq(ray_implicit(&r, &bad, &h), -RAY_EINVAL);
    bad = s;
    bad.lipschitz = -1;
    ck_assert_int_eq(ray_implicit(&r, &bad, &h), -RAY_EINVAL);
    bad = s;
    bad.tolerance = (double)NAN;
    ck_assert_int_eq(ray_implicit(&r, &bad, &h), -RAY_EINVAL);
    /* Invalid rays are misses. */
    r.dir = vec(0, 0, 0);
    ck_assert_int_eq(ray_implicit(&r, &s, &h), 0);
    r.dir = vec((double)NAN, 1, 0);
    ck_assert_int_eq(ray_implicit(&r, &s, &h), 0);
    r = ray_from(vec(-3, 0, 0), vec(1, 0, 0));
    r.tmin = 5;
    r.tmax = 1;
    ck_assert_int_eq(ray_implicit(&r, &s, &h), 0);
    ck_assert(hit_is_poisoned(&h));
}
END_TEST

/*
** From a hit, ray_spawn's ray outward does not find the same surface
** again (its origin is offset by the hit's p_err, which covers the
** tolerance), and the ray inward finds the far side at distance 2R.
*/
START_TEST(implicit_should_not_self_intersect_from_its_hits)
{
    sphere_field sf;
    ray_implicit_surface s;
    rng g = {99};
    int n;

    sf.c = vec(test_offset(_i), 0, 0);
    sf.radius = 1.0;
    s = sphere_surface(&sf, 1);
    for (n = 0; n < 500; n++) {
        ray_vec3 dir = rng_dir(&g);
        ray_ray r = ray_from(vsub(sf.c, vscale(dir, 3)), dir), out, in;
        ray_hit h, h2;
        ck_assert_int_eq(ray_implicit(&r, &s, &h), 1);
        ck_assert_int_eq(ray_spawn(&h, ray_reflect(dir, h.n), &out), RAY_OK);
        ck_assert_int_eq(ray_implicit(&out, &s, &h2), 0);
        ck_assert_int_eq(ray_spawn(&h, dir, &in), RAY_OK);
        ck_assert_int_eq(ray_implicit(&in, &s, &h2), 1);
        /* The chord through the centre: 2R, to twice the tolerance. */
        ck_assert_double_eq_tol(vdist(h2.p, h.p), 2.0, 2 * default_tol(&s) + 1e-9);
    }
}
END_TEST

/* Without a gradient callback the normal comes from central differences:
** for the distance function their truncation error vanishes to first
** order, and the rounding error is ~eps^(2/3) ~ 4e-11: 1e-8 allows for
** the hit point's own offset (tol / R). */
START_TEST(implicit_should_estimate_normals_by_central_differences)
{
    sphere_field sf;
    ray_implicit_surface s;
    ray_ray r = ray_from(vec(0.3, 0.2, 5), vec(0, 0, -1));
    ray_hit h;
    ray_vec3 exact;

    sf.c = vec(0, 0, 0);
    sf.radius = 1.0;
    s = sphere_surface(&sf, 1);
    ck_assert_int_eq(ray_implicit(&r, &s, &h), 1);
    exact = vscale(h.p, 1.0 / vlen(h.p));
    ck_assert_vec_eq_tol(h.n, exact, 1e-8);
}
END_TEST

/* ----------------------------------------------------------- torus */

static ray_torus_params unit_torus(double offset)
{
    ray_torus_params t;
    t.center = vec(offset, 0.5 * offset, -offset);
    t.axis = vec(0.3, 1, -0.2);
    t.major = 1.0;
    t.minor = 0.25;
    return t;
}

/* The exact distance from p to the torus (long double). */
static double torus_distance(ray_vec3 p, const ray_torus_params *t)
{
    long double ax = (long double)t->axis.x, ay = (long double)t->axis.y,
                az = (long double)t->axis.z;
    long double al = sqrtl(ax * ax + ay * ay + az * az);
    long double qx = (long double)p.x - (long double)t->center.x,
                qy = (long double)p.y - (long double)t->center.y,
                qz = (long double)p.z - (long double)t->center.z;
    long double major = (long double)t->major, minor = (long double)t->minor;
    long double z = (qx * ax + qy * ay + qz * az) / al;
    long double rho = sqrtl(fmaxl(qx * qx + qy * qy + qz * qz - z * z, 0));
    return (double)fabsl(sqrtl((rho - major) * (rho - major) + z * z) - minor);
}

/*
** The quartic (ray_torus) and the generic method on the torus's distance
** function (ray__implicit_torus) agree on random rays through the torus's
** box: the same hit or miss, except that the generic method may report a
** ray passing within its tolerance as touching (a hit whose point is
** then within tol of the exact torus; fewer than 1% of the rays); the
** generic hit
** within its tolerance tol of the quartic's along the normal (|dir| = 1;
** tol = 5e-9 at the origin, 1e-4 at 1e5: it is relative to the
** coordinates), so t within tol / |cos| where the ray meets the surface at
** cosine cos, and normals and (u, v) within 2 tol / r (r = 0.25, the
** smaller curvature radius) + 1e-9, away from the seams u, v = 0 = 1.
*/
START_TEST(torus_quartic_should_agree_with_generic_method)
{
    ray_torus_params t = unit_torus(test_offset(_i));
    ray_implicit_surface s;
    rng g = {2024};
    int n, hits = 0, touches = 0;
    double tol;

    ck_assert_int_eq(ray__implicit_torus(&t, &s), RAY_OK);
    tol = default_tol(&s);
    for (n = 0; n < 20000; n++) {
        ray_vec3 o = vadd(t.center, vscale(rng_dir(&g), 3.0));
        ray_vec3 aim = vadd(t.center, vscale(rng_dir(&g), 1.25));
        ray_ray r = ray_from(o, vscale(vsub(aim, o), 1.0 / vdist(aim, o)));
        ray_hit h1, h2;
        int a = ray_torus(&r, &t, &h1), b = ray_implicit(&r, &s, &h2);
        if (a == 0 && b == 1) {
            ck_assert_double_le(torus_distance(h2.p, &t),
                                tol + vlen(h2.p_err));
            touches++;
            continue;
        }
        ck_assert_int_eq(a, b);
        if (!a)
            continue;
        hits++;
        ck_assert_double_le(fabs(h1.t - h2.t) * fabs(vdot(h1.n, r.dir)),
                            tol + vlen(h1.p_err));
        ck_assert_vec_eq_tol(h1.n, h2.n, 2 * tol / t.minor + 1e-9);
        if (fabs(h1.u - 0.5) < 0.49 && fabs(h1.v - 0.5) < 0.49) {
            ck_assert_double_eq_tol(h1.u, h2.u, 2 * tol / t.minor + 1e-9);
            ck_assert_double_eq_tol(h1.v, h2.v, 2 * tol / t.minor + 1e-9);
        }
    }
    ck_assert_int_gt(hits, 3000);
    ck_assert_int_lt(touches, 200);
}
END_TEST

/*
** Hard cases of the quartic: tiny and far (R = 1e-3 at 1e4), huge
** (R = 1e6, seen from 10 above its tube), and a fat torus whose hole is
** almost closed (r = 0.9 R).
** Every hit lies on the exact torus within its own p_err (whose size is
** checked too: a few ulps of the coordinates, not a blanket epsilon).
*/
START_TEST(torus_should_stay_accurate_when_tiny_far_or_huge)
{
    ray_torus_params cases[3];
    int k;

    cases[0].center = vec(1e4, -2e4, 5e3);
    cases[0].axis = vec(0, 0, 1);
    cases[0].major = 1e-3;
    cases[0].minor = 2.5e-4;
    cases[1].center = vec(0, 0, 0);
    cases[1].axis = vec(0, 1, 0);
    cases[1].major = 1e6;
    cases[1].minor = 1e3;
    cases[2].center = vec(3, 1, 2);
    cases[2].axis = vec(1, 1, 1);
    cases[2].major = 0.5;
    cases[2].minor = 0.45;
    for (k = 0; k < 3; k++) {
        const ray_torus_params *t = &cases[k];
        double reach = t->major + t->minor;
        rng g = {(uint64_t)k + 5};
        int n, hits = 0;
        for (n = 0; n < 4000; n++) {
            ray_vec3 o = k == 1 ? vec(rng_range(&g, -2e3, 2e3), 1e3 + 10,
                                      1e6 + rng_range(&g, -2e3, 2e3))
                                : vadd(t->center, vscale(rng_dir(&g), 4 * reach));
            ray_vec3 aim = k == 1 ? vec(o.x + rng_range(&g, -5, 5), 0, o.z)
                                  : vadd(t->center,
                                         vscale(rng_dir(&g), reach));
            ray_ray r = ray_from(o, vsub(aim, o));
            ray_hit h;
            double mag;
            if (!ray_torus(&r, t, &h))
                continue;
            hits++;
            ck_assert(hit_is_finite(&h));
            ck_assert_double_le(torus_distance(h.p, t), vlen(h.p_err));
            mag = vlen(t->center) + 2 * reach;
            ck_assert_double_le(vlen(h.p_err), 1e-13 * mag);
        }
        ck_assert_int_gt(hits, 100);
    }
}
END_TEST

/*
** A ray along x at the height of the tube's top (y = r) touches the torus
** (axis y, R = 1, r = 0.25) at x = -1 and x = 1: double roots, which the
** root finder reports when the quartic's extremum is zero within its
** rounding bound.  1e-6 higher it misses; 1e-6 lower it hits, in both the
** quartic and the generic method.
*/
START_TEST(torus_should_classify_tangent_rays)
{
    ray_torus_params t;
    ray_implicit_surface s;
    ray_ray touch = ray_from(vec(-3, 0.25, 0), vec(1, 0, 0));
    ray_ray above = ray_from(vec(-3, 0.25 + 1e-6, 0), vec(1, 0, 0));
    ray_ray below = ray_from(vec(-3, 0.25 - 1e-6, 0), vec(1, 0, 0));
    ray_hit h;

    t.center = vec(0, 0, 0);
    t.axis = vec(0, 1, 0);
    t.major = 1.0;
    t.minor = 0.25;
    ck_assert_int_eq(ray__implicit_torus(&t, &s), RAY_OK);
    ck_assert_int_eq(ray_torus(&touch, &t, &h), 1);
    /* A double root is located to ~sqrt(eps) relative: 1e-6 is ample. */
    ck_assert_double_eq_tol(h.t, 2.0, 1e-6);
    ck_assert_double_eq_tol(h.n.y, 1.0, 1e-9);
    ck_assert_int_eq(ray_implicit(&touch, &s, &h), 1);
    ck_assert_double_eq_tol(h.t, 2.0, 2e-4);   /* sqrt of the tolerance */
    hit_poison(&h);
    ck_assert_int_eq(ray_torus(&above, &t, &h), 0);
    ck_assert_int_eq(ray_implicit(&above, &s, &h), 0);
    ck_assert(hit_is_poisoned(&h));
    ck_assert_int_eq(ray_torus(&below, &t, &h), 1);
    ck_assert_int_eq(ray_implicit(&below, &s, &h), 1);
}
END_TEST

START_TEST(torus_should_hit_through_the_hole_and_from_inside)
{
    ray_torus_params t;
    ray_hit h;
    ray_ray hole = ray_from(vec(0, 5, 0), vec(0, -1, 0));
    ray_ray across = ray_from(vec(-5, 0, 0), vec(1, 0, 0));
    ray_ray inside = ray_from(vec(1, 0, 0), vec(1, 0, 0));

    t.center = vec(0, 0, 0);
    t.axis = vec(0, 1, 0);
    t.major = 1.0;
    t.minor = 0.25;
    hit_poison(&h);
    ck_assert_int_eq(ray_torus(&hole, &t, &h), 0);   /* the hole */
    ck_assert(hit_is_poisoned(&h));
    ck_assert_int_eq(ray_torus(&across, &t, &h), 1);
    /* Exact inputs: x = -1.25 is hit at t = 3.75, within a few ulps. */
    ck_assert_double_eq_tol(h.t, 3.75, 1e-14);
    ck_assert_double_eq_tol(h.n.x, -1.0, 1e-14);
    ck_assert_int_eq(ray_torus(&inside, &t, &h), 1);
    ck_assert_double_eq_tol(h.t, 0.25, 1e-14);
    ck_assert_double_eq_tol(h.n.x, 1.0, 1e-14);
    /* u = angle around the axis / 2pi + 1/2, in [0, 1]. */
    ck_assert(h.u >= 0 && h.u <= 1 && h.v >= 0 && h.v <= 1);
}
END_TEST

START_TEST(torus_should_miss_on_bad_input)
{
    ray_torus_params t;
    ray_implicit_surface s;
    ray_ray r = ray_from(vec(-5, 0, 0), vec(1, 0, 0));
    ray_hit h;

    t.center = vec(0, 0, 0);
    t.axis = vec(0, 1, 0);
    t.major = 1.0;
    t.minor = 0.25;
    hit_poison(&h);
    ck_assert_int_eq(ray_torus(NULL, &t, &h), 0);
    ck_assert_int_eq(ray_torus(&r, NULL, &h), 0);
    t.axis = vec(0, 0, 0);
    ck_assert_int_eq(ray_torus(&r, &t, &h), 0);
    ck_assert_int_eq(ray__implicit_torus(&t, &s), RAY_EINVAL);
    t.axis = vec(0, 1, 0);
    t.minor = 0;
    ck_assert_int_eq(ray_torus(&r, &t, &h), 0);
    t.minor = 1.0;                      /* spindle: refused */
    ck_assert_int_eq(ray_torus(&r, &t, &h), 0);
    ck_assert_int_eq(ray__implicit_torus(&t, &s), RAY_EINVAL);
    t.minor = 0.25;
    t.major = (double)NAN;
    ck_assert_int_eq(ray_torus(&r, &t, &h), 0);
    t.major = 1;
    r.dir = vec(0, 0, 0);
    ck_assert_int_eq(ray_torus(&r, &t, &h), 0);
    r.dir = vec(1, 0, 0);
    r.org.y = HUGE_VAL;
    ck_assert_int_eq(ray_torus(&r, &t, &h), 0);
    ck_assert(hit_is_poisoned(&h));
    ck_assert_int_eq(ray__implicit_torus(&t, NULL), RAY_EINVAL);
}
END_TEST

/*
** Regressions found in review.  A ray entering a torus near its outer
** equator from far away (where the torus touches its bounding sphere)
** got the exit: the root interval assumed the shifted origin exactly
** nearest the centre.  Reference t from __float128 root finding: the ray
** point there is on the torus to 1e-32.  Here 1e3 away, t to 1e-12
** relative (a few ulps of the 1e3 distance).
*/
START_TEST(torus_should_find_the_entry_near_the_outer_equator)
{
    ray_torus_params t = {{0, 0, 0}, {0, 0, 1}, 1.5, 0.5};
    ray_ray r = ray_from(vec(383.77318736018316, 919.93633513208283,
                             96.040341684605792),
                         vec(-0.3819163765650766, -0.9191931974118891,
                             -0.096040341227581871));
    ray_hit h;

    ck_assert_int_eq(ray_torus(&r, &t, &h), 1);
    ck_assert_double_eq_tol(h.t, 999.99999999999989, 1e-9);
}
END_TEST

/*
** Sphere tracing from far away: at t ~ 1e9 the default tolerance
** (~3.5e-9 for a unit sphere) is below the spacing of doubles near t, and
** a step that small rounded back to t, sampling one point until the
** evaluations ran out.  The step is now at least 2 ulps of t: the ray
** hits, within the coarseness of points 1e9 away (ulp(1e9) = 1.2e-7).
** Likewise a tolerance of 1e-300.
*/
START_TEST(implicit_should_march_from_far_away_and_at_tiny_tolerance)
{
    sphere_field sf;
    ray_implicit_surface s;
    ray_ray far = ray_from(vec(-1e9, 0.3, 0.2), vec(1, 0, 0));
    ray_ray near = ray_from(vec(-5, 0.9, 0.01), vec(1, 0, 0));
    ray_hit h;

    sf.c = vec(0, 0, 0);
    sf.radius = 1.0;
    s = sphere_surface(&sf, 1);
    ck_assert_int_eq(ray_implicit(&far, &s, &h), 1);
    ck_assert_double_le(sphere_distance(h.p, sf.c, sf.radius), 1e-6);
    s.tolerance = 1e-300;
    ck_assert_int_eq(ray_implicit(&near, &s, &h), 1);
    /* As accurate as double allows: a few ulps of the coordinates. */
    ck_assert_double_le(sphere_distance(h.p, sf.c, sf.radius), 1e-15);
}
END_TEST

/* ----------------------------------------------------------- blobs */

/*
** One blob alone is a sphere: threshold = s (1 - x)^2 at x = d^2 / R^2
** gives d = R sqrt(1 - sqrt(threshold / s)).  Rays through it agree with
** ray_sphere within the tolerance (as for the implicit sphere above).
*/
START_TEST(blob_alone_should_be_a_sphere)
{
    ray_blob b;
    ray_blobs_params p;
    ray_implicit_surface s;
    rng g = {3};
    double radius;
    int n, hits = 0;

    b.center = vec(0.5, -1, 2);
    b.radius = 2.0;
    b.strength = 1.0;
    p.blobs = &b;
    p.count = 1;
    p.threshold = 0.25;
    radius = 2.0 * sqrt(1 - sqrt(0.25));
    ck_assert_int_eq(ray_implicit_blobs(&p, &s), RAY_OK);
    for (n = 0; n < 5000; n++) {
        ray_vec3 o = vadd(b.center, vscale(rng_dir(&g), 4.0));
        ray_vec3 aim = vadd(b.center, vscale(rng_dir(&g), 0.9 * radius));
        ray_ray r = ray_from(o, vsub(aim, o));
        ray_hit h1, h2;
        ck_assert_int_eq(ray_sphere(&r, b.center, radius, &h1), 1);
        ck_assert_int_eq(ray_implicit(&r, &s, &h2), 1);
        hits++;
        ck_assert_double_le(sphere_distance(h2.p, b.center, radius),
                            1e-9 * (vdist(s.hi, s.lo) + 4.0) +
                                vlen(h2.p_err));
        /* The field's gradient is exact: the normal is off only by the
        ** hit point's distance to the surface over the radius. */
        ck_assert_vec_eq_tol(h2.n, h1.n, 1e-7);
    }
    ck_assert_int_eq(hits, 5000);
}
END_TEST

/* The Lipschitz bound of ray_implicit_blobs holds: |f(p) - f(q)| <=
** L |p - q| on random pairs of nearby points among overlapping blobs,
** some negative.  The comparison allows 1e-12 relative for f's rounding. */
START_TEST(blobs_lipschitz_bound_should_hold)
{
    ray_blob b[4];
    ray_blobs_params p;
    ray_implicit_surface s;
    rng g = {11};
    int n, k;

    for (k = 0; k < 4; k++) {
        b[k].center = vec(0.4 * k, 0.3 * (k % 2), 0);
        b[k].radius = 0.6 + 0.1 * k;
        b[k].strength = k == 3 ? -0.5 : 1.0;
    }
    p.blobs = b;
    p.count = 4;
    p.threshold = 0.3;
    ck_assert_int_eq(ray_implicit_blobs(&p, &s), RAY_OK);
    for (n = 0; n < 20000; n++) {
        ray_vec3 a = vec(rng_range(&g, s.lo.x, s.hi.x),
                         rng_range(&g, s.lo.y, s.hi.y),
                         rng_range(&g, s.lo.z, s.hi.z));
        ray_vec3 c = vadd(a, vscale(rng_dir(&g), rng_range(&g, 0, 0.05)));
        double df = fabs(s.f(s.ud, a) - s.f(s.ud, c));
        ck_assert_double_le(df, s.lipschitz * vdist(a, c) * (1 + 1e-12) +
                                    1e-15);
    }
    /* Two overlapping blobs merge: the ray between their centres along
    ** the line through them starts inside and hits the far end. */
    {
        ray_ray r = ray_from(vec(-3, 0, 0), vec(1, 0, 0));
        ray_hit h;
        ck_assert_int_eq(ray_implicit(&r, &s, &h), 1);
        ck_assert(hit_is_finite(&h));
        ck_assert_double_lt(h.p.x, 0);
    }
}
END_TEST

/* A blob of radius 1e200 (r^2 overflows) or 1e-200 (underflows) still
** works: the distances are divided by the radius before squaring. */
START_TEST(blobs_should_work_at_extreme_radii)
{
    double radii[2] = {1e200, 1e-200};
    int k;

    for (k = 0; k < 2; k++) {
        ray_blob b;
        ray_blobs_params p;
        ray_implicit_surface s;
        ray_ray r;
        ray_hit h;
        b.center = vec(0, 0, 0);
        b.radius = radii[k];
        b.strength = 1;
        p.blobs = &b;
        p.count = 1;
        p.threshold = 0.25;
        ck_assert_int_eq(ray_implicit_blobs(&p, &s), RAY_OK);
        r = ray_from(vec(-3 * radii[k], 0, 0), vec(1, 0, 0));
        ck_assert_int_eq(ray_implicit(&r, &s, &h), 1);
        /* The sphere of radius R sqrt(1 - sqrt(1/4)): hit at x = -R/sqrt 2,
        ** to the default tolerance (1e-9 of the box's diagonal). */
        ck_assert_double_eq_tol(h.p.x / radii[k], -sqrt(0.5), 1e-8);
    }
}
END_TEST

START_TEST(blobs_should_reject_bad_input)
{
    ray_blob b;
    ray_blobs_params p;
    ray_implicit_surface s;

    b.center = vec(0, 0, 0);
    b.radius = 1;
    b.strength = 1;
    p.blobs = &b;
    p.count = 1;
    p.threshold = 0.5;
    ck_assert_int_eq(ray_implicit_blobs(NULL, &s), RAY_EINVAL);
    ck_assert_int_eq(ray_implicit_blobs(&p, NULL), RAY_EINVAL);
    p.count = 0;
    ck_assert_int_eq(ray_implicit_blobs(&p, &s), RAY_EINVAL);
    p.count = 1;
    p.threshold = 0;
    ck_assert_int_eq(ray_implicit_blobs(&p, &s), RAY_EINVAL);
    p.threshold = 0.5;
    b.radius = -1;
    ck_assert_int_eq(ray_implicit_blobs(&p, &s), RAY_EINVAL);
    b.radius = 1;
    b.center.x = (double)NAN;
    ck_assert_int_eq(ray_implicit_blobs(&p, &s), RAY_EINVAL);
}
END_TEST

/* ------------------------------------------------ polynomial roots */

/* Roots of a product of known factors, ascending, to a few ulps: the
** finder refines each in its own monotone bracket; 1e-12 relative allows
** for the roundings of the expanded coefficients. */
START_TEST(poly_roots_should_find_simple_double_and_clustered_roots)
{
    /* (x-1)(x-2)(x-3)(x-4) = x^4 - 10x^3 + 35x^2 - 50x + 24 */
    double c1[5] = {24, -50, 35, -10, 1};
    /* (x-1)^2 (x-3)(x+2) = x^4 - 3x^3 - 3x^2 + 11x - 6 */
    double c2[5] = {-6, 11, -3, -3, 1};
    /* (x - 1)(x - 1.001)(x^2 + 1): two close roots, two complex */
    double c3[5];
    double roots[5];
    int n;

    n = ray__poly_roots(c1, 4, -10, 10, roots);
    ck_assert_int_eq(n, 4);
    ck_assert_double_eq_tol(roots[0], 1, 1e-12);
    ck_assert_double_eq_tol(roots[1], 2, 1e-12);
    ck_assert_double_eq_tol(roots[2], 3, 1e-12);
    ck_assert_double_eq_tol(roots[3], 4, 1e-12);
    /* Only the interval's roots. */
    n = ray__poly_roots(c1, 4, 1.5, 3.5, roots);
    ck_assert_int_eq(n, 2);
    n = ray__poly_roots(c2, 4, -10, 10, roots);
    ck_assert_int_eq(n, 3);
    ck_assert_double_eq_tol(roots[0], -2, 1e-12);
    /* A double root is found to sqrt(eps) ~ 1e-8. */
    ck_assert_double_eq_tol(roots[1], 1, 1e-7);
    ck_assert_double_eq_tol(roots[2], 3, 1e-12);
    /* (x^2 - 2.001x + 1.001)(x^2 + 1) */
    c3[4] = 1;
    c3[3] = -2.001;
    c3[2] = 1.001 + 1;
    c3[1] = -2.001;
    c3[0] = 1.001;
    n = ray__poly_roots(c3, 4, -10, 10, roots);
    ck_assert_int_eq(n, 2);
    ck_assert_double_eq_tol(roots[0], 1, 1e-9);
    ck_assert_double_eq_tol(roots[1], 1.001, 1e-9);
}
END_TEST

Suite *implicit_suite(void)
{
    Suite *s = suite_create("implicit");
    TCase *core = tcase_create("core");
    TCase *hard = tcase_create("hard cases");

    tcase_set_timeout(core, 60);
    tcase_set_timeout(hard, 60);
    tcase_add_loop_test(core, implicit_sphere_should_agree_with_ray_sphere, 0,
                        2 * N_OFFSETS);
    tcase_add_test(core, implicit_should_estimate_normals_by_central_differences);
    tcase_add_loop_test(core, torus_quartic_should_agree_with_generic_method,
                        0, N_OFFSETS);
    tcase_add_test(core, torus_should_hit_through_the_hole_and_from_inside);
    tcase_add_test(core, blob_alone_should_be_a_sphere);
    tcase_add_test(core, blobs_lipschitz_bound_should_hold);
    tcase_add_test(core, poly_roots_should_find_simple_double_and_clustered_roots);
    tcase_add_test(hard, implicit_should_classify_tangent_rays);
    tcase_add_test(hard, implicit_should_not_skip_thin_features_with_a_bound);
    tcase_add_test(hard, implicit_should_report_failures);
    tcase_add_test(hard, implicit_should_reject_bad_input);
    tcase_add_loop_test(hard, implicit_should_not_self_intersect_from_its_hits,
                        0, N_OFFSETS);
    tcase_add_test(hard, torus_should_stay_accurate_when_tiny_far_or_huge);
    tcase_add_test(hard, torus_should_classify_tangent_rays);
    tcase_add_test(hard, torus_should_miss_on_bad_input);
    tcase_add_test(hard, blobs_should_reject_bad_input);
    tcase_add_test(hard, blobs_should_work_at_extreme_radii);
    tcase_add_test(hard, torus_should_find_the_entry_near_the_outer_equator);
    tcase_add_test(hard, implicit_should_march_from_far_away_and_at_tiny_tolerance);
    suite_add_tcase(s, core);
    suite_add_tcase(s, hard);
    return s;
}
