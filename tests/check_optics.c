/* SPDX-License-Identifier: MIT */
/*
** check_optics.c -- ray_reflect, ray_refract, ray_fresnel, ray_spawn.
*/
#include "tests.h"

#include "core/spawn.h"   /* ray__spawner: one hit, many rays */

/* The Fresnel reference values come from Mitsuba 3's test_fresnel.py
** (robustness.md section 8), given to 6 digits there: tolerance 1e-6. */
START_TEST(fresnel_should_match_reference_values)
{
    double deg = 3.14159265358979323846 / 180;

    ck_assert_double_eq_tol(ray_fresnel(1.0, 1 / 1.5), 0.04, 1e-12);
    ck_assert_double_eq_tol(ray_fresnel(cos(45 * deg), 1 / 1.5), 0.050240, 1e-6);
    ck_assert_double_eq(ray_fresnel(cos(45 * deg), 1.5), 1.0);   /* TIR */
    ck_assert_double_eq_tol(ray_fresnel(cos(10 * deg), 1.5), 0.040083, 1e-6);
    /* Index ratio 1: no interface, no reflection. */
    ck_assert_double_eq_tol(ray_fresnel(0.3, 1.0), 0.0, 1e-15);
    /* Bad input is total reflection, never NaN. */
    ck_assert_double_eq(ray_fresnel((double)NAN, 1.5), 1.0);
    ck_assert_double_eq(ray_fresnel(0.5, -1.0), 1.0);
    ck_assert_double_eq(ray_fresnel(0.5, (double)NAN), 1.0);
}
END_TEST

/* The critical angle glass -> air is asin(1/1.5) = 41.8103 degrees: at
** 41.80 the ray still refracts (nearly grazing), at 41.82 it reflects. */
START_TEST(refract_should_switch_to_tir_at_critical_angle)
{
    double deg = 3.14159265358979323846 / 180;
    ray_vec3 n = vec(0, 0, 1), t;
    ray_vec3 below = vec(sin(41.80 * deg), 0, -cos(41.80 * deg));
    ray_vec3 beyond = vec(sin(41.82 * deg), 0, -cos(41.82 * deg));

    ck_assert_int_eq(ray_refract(below, n, 1.5, &t), 1);
    ck_assert_double_eq_tol(vlen(t), 1.0, 4 * DBL_EPSILON);
    /* cos t = sqrt(1 - (1.5 sin 41.80)^2) = 0.0200: nearly grazing. */
    ck_assert(t.z < 0 && t.z > -0.03);
    ck_assert_double_eq_tol(t.x, 1.5 * sin(41.80 * deg), 1e-12);
    t = vec(7, 7, 7);
    ck_assert_int_eq(ray_refract(beyond, n, 1.5, &t), 0);
    ck_assert_double_eq(t.x, 7);
    ck_assert_double_eq(ray_fresnel(cos(41.82 * deg), 1.5), 1.0);
}
END_TEST

/* Snell: sin(i) = eta sin(t) over many angles; eta = 1 does not bend;
** the normal may face either way; non-unit d is fine. */
START_TEST(refract_should_obey_snell)
{
    ray_vec3 n = vec(0, 1, 0), t;
    int k;

    for (k = 0; k < 20; k++) {
        double a = 1.5 * k / 20.0;
        ray_vec3 d = vec(3 * sin(a), -3 * cos(a), 0);
        ck_assert_int_eq(ray_refract(d, n, 1 / 1.5, &t), 1);
        ck_assert_double_eq_tol(sin(a), 1.5 * t.x, 1e-12);
        ck_assert(t.y < 0);
        ck_assert_int_eq(ray_refract(d, vec(0, -1, 0), 1 / 1.5, &t), 1);
        ck_assert_double_eq_tol(sin(a), 1.5 * t.x, 1e-12);
        ck_assert_int_eq(ray_refract(d, n, 1.0, &t), 1);
        ck_assert_vec_eq_tol(t, vscale(d, 1.0 / 3), 1e-15);
    }
    ck_assert_int_eq(ray_refract(vec(0, 0, 0), n, 1.5, &t), 0);
    ck_assert_int_eq(ray_refract(vec(0, -1, 0), n, 0.0, &t), 0);
    ck_assert_int_eq(ray_refract(vec(0, -1, 0), n, (double)NAN, &t), 0);
    ck_assert_int_eq(ray_refract(vec((double)NAN, -1, 0), n, 1.5, &t), 0);
    ck_assert_int_eq(ray_refract(vec(0, -1, 0), n, 1.5, NULL), 0);
}
END_TEST

START_TEST(reflect_should_mirror_about_the_normal)
{
    ray_vec3 r = ray_reflect(vec(1, -1, 0), vec(0, 1, 0));

    ck_assert_vec_eq(r, vec(1, 1, 0));
    r = ray_reflect(vec(1, -1, 2), vec(0, -1, 0));    /* either side */
    ck_assert_vec_eq(r, vec(1, 1, 2));
}
END_TEST

/*
** A ray spawned from a hit leaves the surface: for 10000 random outgoing
** directions on each side of a sphere and a tilted triangle, at the origin
** and 1e5 away, the spawned ray never re-hits the surface on the side it
** leaves (for the convex sphere's outside, never at all).
*/
START_TEST(spawn_should_not_rehit_the_surface)
{
    double offsets[] = {0.0, 1e3, 1e5};
    rng g = {77};
    int o, k;

    for (o = 0; o < 3; o++) {
        double X = offsets[o];
        ray_vec3 c = vec(X, 0, 0);
        ray_vec3 A = vec(X - 50, 1, X - 50), B = vec(X + 50, 1.37, X - 50),
                 C = vec(X - 50, 0.61, X + 50);
        for (k = 0; k < 10000; k++) {
            ray_vec3 dir = rng_dir(&g), w = rng_dir(&g), P;
            ray_ray prim = ray_from(vadd(c, vscale(dir, 5)), vscale(dir, -1)), s;
            ray_hit h, h2;

            ck_assert_int_eq(ray_sphere(&prim, c, 1.0, &h), 1);
            if (vdot(w, h.n) < 0)
                w = vscale(w, -1);
            ck_assert_int_eq(ray_spawn(&h, w, &s), RAY_OK);
            ck_assert_msg(!ray_sphere(&s, c, 1.0, &h2),
                          "sphere at %g: self-hit at t=%g", X, h2.t);
            /* The triangle, from a random point above it. */
            P = vadd(vadd(vscale(A, 0.3), vscale(B, 0.3)), vscale(C, 0.4));
            prim = ray_from(vadd(P, vadd(vec(0, 3, 0), rng_point(&g, -2, 2))),
                            vec(0, 0, 0));
            prim.dir = vsub(P, prim.org);
            ck_assert_int_eq(ray_triangle(&prim, A, B, C, &h), 1);
            w = rng_dir(&g);
            ck_assert_int_eq(ray_spawn(&h, w, &s), RAY_OK);
            ck_assert_msg(!ray_triangle(&s, A, B, C, &h2),
                          "triangle at %g: self-hit at t=%g", X, h2.t);
        }
    }
}
END_TEST

START_TEST(spawn_to_should_end_before_the_target)
{
    ray_ray prim = ray_from(vec(0, 5, 0), vec(0, -1, 0)), s;
    ray_hit h;

    ck_assert_int_eq(ray_plane(&prim, vec(0, 0, 0), vec(0, 1, 0), &h), 1);
    ck_assert_int_eq(ray_spawn_to(&h, vec(3, 4, 0), &s), RAY_OK);
    ck_assert_double_eq(s.tmax, 1.0);
    ck_assert_double_eq(s.tmin, 0.0);
    ck_assert(s.org.y >= 0);
    ck_assert_vec_eq_tol(vadd(s.org, s.dir), vec(3, 4, 0), 1e-15);
    /* Bad input: nothing written. */
    s.tmax = 42;
    ck_assert_int_eq(ray_spawn_to(&h, h.p, &s), RAY_EINVAL);
    ck_assert_int_eq(ray_spawn_to(&h, vec((double)NAN, 0, 0), &s), RAY_EINVAL);
    ck_assert_int_eq(ray_spawn(&h, vec(0, 0, 0), &s), RAY_EINVAL);
    ck_assert_int_eq(ray_spawn(&h, vec(0, HUGE_VAL, 0), &s), RAY_EINVAL);
    ck_assert_int_eq(ray_spawn(NULL, vec(0, 1, 0), &s), RAY_EINVAL);
    ck_assert_int_eq(ray_spawn(&h, vec(0, 1, 0), NULL), RAY_EINVAL);
    ck_assert_double_eq(s.tmax, 42);
}
END_TEST

/*
** ray_spawn and ray_spawn_to refuse a hit or a direction (a target) with
** any of its numbers NaN, +Inf or -Inf -- each of the hit's point,
** normal and error bound and the direction, component by component --
** and write nothing; the same input, finite, spawns a ray.
*/
static double *spawn_input(ray_hit *h, ray_vec3 *d, int which)
{
    ray_vec3 *v[4];

    v[0] = &h->p;
    v[1] = &h->n;
    v[2] = &h->p_err;
    v[3] = d;
    return which % 3 == 0   ? &v[which / 3]->x
           : which % 3 == 1 ? &v[which / 3]->y
                            : &v[which / 3]->z;
}

START_TEST(spawn_should_refuse_every_non_finite_number)
{
    static const double bad[] = {(double)NAN, HUGE_VAL, -HUGE_VAL};
    ray_ray prim = ray_from(vec(0, 5, 0), vec(0.1, -1, 0.2)), s;
    ray_hit base;
    unsigned char untouched[sizeof s];
    int which, k;

    ck_assert_int_eq(ray_plane(&prim, vec(0, 0, 0), vec(0, 1, 0), &base), 1);
    memset(untouched, 0x5a, sizeof untouched);
    for (which = 0; which < 12; which++)
        for (k = 0; k < 3; k++) {
            ray_hit h = base;
            ray_vec3 d = vec(0.3, 1, -0.2);
            *spawn_input(&h, &d, which) = bad[k];
            memset(&s, 0x5a, sizeof s);
            ck_assert_int_eq(ray_spawn(&h, d, &s), RAY_EINVAL);
            /* the target is not finite where d is not */
            ck_assert_int_eq(ray_spawn_to(&h, vadd(base.p, d), &s),
                             RAY_EINVAL);
            ck_assert(memcmp(&s, untouched, sizeof s) == 0);
        }
    ck_assert_int_eq(ray_spawn_to(&base, vadd(base.p, vec(0.3, 1, -0.2)), &s),
                     RAY_OK);
    ck_assert_int_eq(ray_spawn(&base, vec(0.3, 1, -0.2), &s), RAY_OK);
}
END_TEST

/*
** The other side of the trade-off: the offset must not skip thin
** geometry.  Two parallel planes 1e-3 apart, 1e3 from the origin: a
** shadow ray from a hit on the lower one toward a light above is blocked
** by the upper one, which it meets 1e-3 above its start.
*/
START_TEST(spawn_should_not_skip_thin_gaps)
{
    double X = 1e3;
    ray_ray prim = ray_from(vec(X + 0.3, 5e-4, X - 0.2), vec(0.1, -1, 0.05));
    ray_ray s;
    ray_hit h, h2;

    ck_assert_int_eq(ray_plane(&prim, vec(X, 0, X), vec(0, 1, 0), &h), 1);
    ck_assert_int_eq(ray_spawn_to(&h, vec(X, 10, X), &s), RAY_OK);
    ck_assert_int_eq(ray_plane(&s, vec(X, 1e-3, X), vec(0, 1, 0), &h2), 1);
    ck_assert_double_eq_tol(h2.p.y, 1e-3, 1e-12);
}
END_TEST

/* The spacing of doubles at x's binade and the next one up: a bound on
** one rounding of a value near x (and of x plus a tiny offset). */
static double ulp_at(double x)
{
    double a = fabs(x);
    return nextafter(nextafter(a, HUGE_VAL), HUGE_VAL) -
           nextafter(a, HUGE_VAL);
}

/*
** ray_spawn's offset is the documented rule (ray_spawn(3), "The offset
** rule"), by its size and not only by its effect: o = p + 2 d s n, d =
** |n.x| e.x + |n.y| e.y + |n.z| e.z, s the side the new ray points to
** (+1 when w.n >= 0), then each component stepped one ulp away from p.
** A looser or tighter offset also lets the spawned rays of the tests
** above escape; here, for an oblique normal with a negative component
** (so |n| and n differ in d), an error box of unequal sides and p at 1
** and at 1e5, each component of o - p (exact: Sterbenz) must equal 2 d s
** n_k to within gamma(4) of it (d's dot product, the doubling and the
** product with n_k) plus 1.5 ulps of p_k (the sum's rounding, half an
** ulp, and the step, one).  The test asserts that d |n_k| itself is
** above 4 times that margin: an offset of d (half the rule) or 4 d
** fails it.  Then, with an error box far below an ulp of p, the offset
** is the step alone: o_k is exactly the next double after p_k away from
** the surface, and p_k itself where n_k = 0.
*/
START_TEST(spawn_offset_should_follow_the_documented_rule)
{
    static const double scale[2] = {1, 1e5};
    ray_vec3 n = vscale(vec(2, -3, 6), 1 / vlen(vec(2, -3, 6)));
    /* w.n > 0, < 0 and = 0 (s = +1, -1, +1; the last exactly 0, the
    ** products commuting). */
    const double dirs[3][3] = {{0.3, 0.1, 1}, {-0.2, 0.5, -1},
                               {n.y, -n.x, 0}};
    int o, k, w;

    for (o = 0; o < 2; o++)
        for (w = 0; w < 3; w++) {
            ray_hit h;
            ray_ray s;
            ray_vec3 dir = vec(dirs[w][0], dirs[w][1], dirs[w][2]);
            long double d;
            double sgn;

            memset(&h, 0, sizeof h);
            h.p = vscale(vec(1.5, -2.25, 3), scale[o]);
            h.n = n;
            h.p_err = vscale(vec(1e-10, 3e-10, 2e-10), scale[o]);
            if (w == 2)
                ck_assert(vdot(dir, n) == 0);
            d = fabsl((long double)n.x) * (long double)h.p_err.x +
                fabsl((long double)n.y) * (long double)h.p_err.y +
                fabsl((long double)n.z) * (long double)h.p_err.z;
            sgn = vdot(dir, n) >= 0 ? 1 : -1;
            ck_assert_int_eq(ray_spawn(&h, dir, &s), RAY_OK);
            for (k = 0; k < 3; k++) {
                double pk = (&h.p.x)[k], ok = (&s.org.x)[k];
                long double nk = (long double)(&n.x)[k];
                long double want = 2 * d * (long double)sgn * nk;
                long double tol = 4 * (long double)DBL_EPSILON *
                                      fabsl(want) +
                                  1.5L * (long double)ulp_at(pk);
                ck_assert_msg(fabsl((long double)(ok - pk) - want) <= tol,
                              "scale %g dir %d axis %d: offset %.17g, the "
                              "rule %.17Lg (margin %.3Lg)", scale[o], w, k,
                              ok - pk, want, tol);
                ck_assert(d * fabsl(nk) > 4 * tol);   /* d alone fails */
            }
            ck_assert_vec_eq(s.dir, dir);
            ck_assert(s.tmin == 0 && s.tmax == HUGE_VAL);
        }
    /* An error box far below an ulp: the one-ulp step alone. */
    {
        ray_hit h;
        ray_ray s;

        memset(&h, 0, sizeof h);
        h.p = vec(1.5, -2.25, 3);
        h.n = vec(0.6, 0, -0.8);
        h.p_err = vec(1e-30, 1e-30, 1e-30);
        ck_assert_int_eq(ray_spawn(&h, vec(1, 1, 0), &s), RAY_OK);
        ck_assert(s.org.x == nextafter(1.5, HUGE_VAL));
        ck_assert(s.org.y == -2.25);
        ck_assert(s.org.z == nextafter(3.0, -HUGE_VAL));
        /* The other side, through ray_spawn_to: the same origin rule,
        ** then the segment to the target (tmax 1). */
        ck_assert_int_eq(ray_spawn_to(&h, vec(-5, 0, 9), &s), RAY_OK);
        ck_assert(s.org.x == nextafter(1.5, -HUGE_VAL));
        ck_assert(s.org.y == -2.25);
        ck_assert(s.org.z == nextafter(3.0, HUGE_VAL));
        ck_assert(s.tmax == 1);
        ck_assert_vec_eq(s.dir, vsub(vec(-5, 0, 9), s.org));
    }
}
END_TEST

/*
** The hit records' error bounds are the documented ones, by value (the
** sizes ray_spawn scales its offset by: a bound a gamma smaller also
** passes the self-hit tests at most scenes).  Oblique hits 1e5 from the
** origin, each bound recomputed in long double from the hit's own
** fields, and held to 4u relative (the library's sums round; a gamma(n)
** slipped to gamma(n - 1) moves it by 1/n, over 12%):
**   sphere (sphere.c): gamma(7) (|c_k| + R |n_k|);
**   triangle (triangle.c, Cramer and watertight): gamma(7) (|alpha a_k|
**     + |beta b_k| + |gamma c_k|) + 4 * 2^-1074, alpha = 1 - beta - gamma
**     as computed (u = beta, v = gamma);
**   plane (plane.c): gamma(8) max_k (|p_k| + |point_k|), every axis.
*/
static long double gam_n(int n)
{
    long double u = (long double)DBL_EPSILON / 2;
    return n * u / (1 - n * u);
}

static void assert_bound(const char *what, double got, long double want)
{
    ck_assert_msg(fabsl((long double)got - want) <= 4 * gam_n(1) * want,
                  "%s: p_err %.17g, the rule gives %.17Lg", what, got, want);
}

START_TEST(hit_error_bounds_should_be_their_documented_values)
{
    const double X = 1e5;
    ray_vec3 c = vec(X, -0.5 * X, 0.25 * X);
    ray_vec3 a = vec(X - 3, 1 - X, X + 2), b = vec(X + 4, 2 - X, X - 1),
             v2 = vec(X + 1, 5 - X, X + 3);
    ray_vec3 pt = vec(X, 0.5 * X, -X), pn = vscale(vec(1, 2, -2), 1.0 / 3);
    ray_ray r = ray_from(vadd(c, vec(-7, 3, 5)), vec(7.25, -2.5, -5.5));
    ray_hit h;
    double alpha;
    int k, w;

    ck_assert_int_eq(ray_sphere(&r, c, 1.5, &h), 1);
    for (k = 0; k < 3; k++)
        assert_bound("sphere", (&h.p_err.x)[k],
                     gam_n(7) * (fabsl((long double)(&c.x)[k]) +
                                 1.5L * fabsl((long double)(&h.n.x)[k])));
    for (w = 0; w < 2; w++) {
        ray_vec3 P = vadd(vadd(vscale(a, 0.2), vscale(b, 0.3)), vscale(v2, 0.5));
        r = ray_from(vadd(P, vec(1, 6, -2)), vec(-1, -6, 2));
        ck_assert_int_eq(w ? ray_triangle_watertight(&r, a, b, v2, &h)
                           : ray_triangle(&r, a, b, v2, &h), 1);
        alpha = 1.0 - h.u - h.v;
        for (k = 0; k < 3; k++)
            assert_bound(w ? "watertight triangle" : "triangle",
                         (&h.p_err.x)[k],
                         gam_n(7) * (fabsl((long double)alpha *
                                           (long double)(&a.x)[k]) +
                                     fabsl((long double)h.u *
                                           (long double)(&b.x)[k]) +
                                     fabsl((long double)h.v *
                                           (long double)(&v2.x)[k])) +
                             4 * 0x1p-1074L);
    }
    r = ray_from(vadd(pt, vec(3, 9, -1)), vec(-0.5, -1.75, 0.25));
    ck_assert_int_eq(ray_plane(&r, pt, pn, &h), 1);
    {
        long double big = 0;
        for (k = 0; k < 3; k++) {
            long double m = fabsl((long double)(&h.p.x)[k]) +
                            fabsl((long double)(&pt.x)[k]);
            big = m > big ? m : big;
        }
        for (k = 0; k < 3; k++)
            assert_bound("plane", (&h.p_err.x)[k], gam_n(8) * big);
    }
}
END_TEST

/*
** Issue 38: the optics functions' refusals and clamps, as ray.h documents
** them.  ray_refract: 0 (*out untouched) for an infinite eta, a normal
** that is not finite, a zero or NaN direction.  A normal a rounding
** longer than 1 (1 + 2^-52) head-on makes cos_i 1 + 2^-52, clamped to 1:
** the ray goes straight through, (0, 0, -1) exactly up to the last
** normalisation's rounding (2 ulps).  ray_fresnel: 1 (total reflection)
** for an infinite eta or a NaN cosine; a cosine past 1 is 1's answer,
** bit for bit.
*/
START_TEST(optics_should_refuse_what_is_not_finite)
{
    ray_vec3 t = vec(7, 7, 7);
    double one_up = 1 + DBL_EPSILON;

    ck_assert_int_eq(ray_refract(vec(0, 0, -1), vec(0, 0, 1), HUGE_VAL, &t), 0);
    ck_assert_int_eq(ray_refract(vec(0, 0, -1), vec(0, (double)NAN, 1), 1.5, &t), 0);
    ck_assert_int_eq(ray_refract(vec(0, 0, 0), vec(0, 0, 1), 1.5, &t), 0);
    ck_assert_int_eq(ray_refract(vec((double)NAN, 0, -1), vec(0, 0, 1), 1.5, &t), 0);
    ck_assert(t.x == 7 && t.y == 7 && t.z == 7);
    ck_assert_int_eq(ray_refract(vec(0, 0, -1), vec(0, 0, one_up), 1.5, &t), 1);
    ck_assert(fabs(t.x) == 0 && fabs(t.y) == 0);
    ck_assert_double_eq_tol(t.z, -1, 2 * DBL_EPSILON);
    ck_assert(ray_fresnel(0.5, HUGE_VAL) == 1.0);
    ck_assert(ray_fresnel((double)NAN, 1.5) == 1.0);
    ck_assert(ray_fresnel(one_up, 1.5) == ray_fresnel(1, 1.5));
    ck_assert(ray_fresnel(-one_up, 1.5) == ray_fresnel(1, 1.5));
}
END_TEST

/*
** Issue 38: ray_spawn and ray_spawn_to refuse (RAY_EINVAL, *out
** untouched) a hit whose p, n or p_err is not finite, a direction that
** is zero or not finite (each of its components the first nonzero one
** in turn), a target at the hit's own point or not finite, and an
** origin that the offset pushes past DBL_MAX; ray_spawn_to also a
** target whose direction from the offset origin overflows.  A good
** spawn from the same hit still works (origin finite, tmax HUGE_VAL).
*/
START_TEST(spawn_should_refuse_what_is_not_finite)
{
    ray_hit h, bad;
    ray_ray r, keep;

    memset(&h, 0, sizeof h);
    h.p = vec(1, 2, 3);
    h.n = vec(0, 0, 1);
    h.p_err = vec(1e-15, 1e-15, 1e-15);
    memset(&keep, 0x5a, sizeof keep);
    r = keep;
    bad = h, bad.p.y = (double)NAN;
    ck_assert_int_eq(ray_spawn(&bad, vec(0, 0, 1), &r), RAY_EINVAL);
    ck_assert_int_eq(ray_spawn_to(&bad, vec(0, 0, 9), &r), RAY_EINVAL);
    bad = h, bad.n.x = HUGE_VAL;
    ck_assert_int_eq(ray_spawn(&bad, vec(0, 0, 1), &r), RAY_EINVAL);
    bad = h, bad.p_err.z = (double)NAN;
    ck_assert_int_eq(ray_spawn(&bad, vec(0, 0, 1), &r), RAY_EINVAL);
    ck_assert_int_eq(ray_spawn_to(&bad, vec(0, 0, 9), &r), RAY_EINVAL);
    ck_assert_int_eq(ray_spawn(&h, vec(0, 0, 0), &r), RAY_EINVAL);
    ck_assert_int_eq(ray_spawn(&h, vec(0, (double)NAN, 1), &r), RAY_EINVAL);
    ck_assert_int_eq(ray_spawn_to(&h, vec(1, 2, 3), &r), RAY_EINVAL);
    ck_assert_int_eq(ray_spawn_to(&h, vec(1, HUGE_VAL, 3), &r), RAY_EINVAL);
    ck_assert(memcmp(&r, &keep, sizeof r) == 0);
    /* Directions whose first nonzero component is y, then z; targets
    ** likewise (the zero test looks at each in turn). */
    ck_assert_int_eq(ray_spawn(&h, vec(0, 1, 0), &r), RAY_OK);
    ck_assert_int_eq(ray_spawn(&h, vec(0, 0, -1), &r), RAY_OK);
    ck_assert(r.tmax == HUGE_VAL && r.org.z < 3);
    ck_assert_int_eq(ray_spawn_to(&h, vec(1, 5, 3), &r), RAY_OK);
    ck_assert_int_eq(ray_spawn_to(&h, vec(1, 2, 5), &r), RAY_OK);
    ck_assert(r.tmax == 1 && r.org.z > 3);
    /* An offset past DBL_MAX: p at DBL_MAX with an error bound of its
    ** size, leaving along +z. */
    r = keep;
    bad = h, bad.p = vec(0, 0, DBL_MAX), bad.p_err = vec(0, 0, DBL_MAX);
    ck_assert_int_eq(ray_spawn(&bad, vec(0, 0, 1), &r), RAY_EINVAL);
    ck_assert_int_eq(ray_spawn_to(&bad, vec(0, 0, -1), &r), RAY_EINVAL);
    /* A target whose direction from the origin overflows. */
    bad = h, bad.p = vec(-DBL_MAX, 0, 0), bad.n = vec(-1, 0, 0);
    ck_assert_int_eq(ray_spawn_to(&bad, vec(DBL_MAX, 0, 0), &r), RAY_EINVAL);
    ck_assert(memcmp(&r, &keep, sizeof r) == 0);
}
END_TEST

/* One spawner's answer for "target" against ray_spawn_to's, bit for bit
** (the ray, or the refusal with *out untouched). */
static void spawner_should_agree(ray__spawner *sp, ray_vec3 target)
{
    ray_ray a, b;
    int ra, rb;

    memset(&a, 0x5a, sizeof a);
    memset(&b, 0x5a, sizeof b);
    ra = ray_spawn_to(sp->hit, target, &a);
    rb = ray__spawn_to(sp, target, &b);
    ck_assert_int_eq(ra, rb);
    ck_assert(memcmp(&a, &b, sizeof a) == 0);
}

/*
** ray_shade_direct's shadow rays leave one hit from origins made once
** (spawn.c's spawner, one a side of the surface): the same rays as
** ray_spawn_to's, in any order of sides -- random hits (tilted, with
** error bounds of their size) and targets on both sides in turn; a
** target at the hit or not finite; a hit not finite (every target
** refused); an offset past DBL_MAX on one side only (that side refused,
** the other not, in either order).
*/
START_TEST(spawner_should_make_spawn_to_rays)
{
    rng g = {38};
    ray__spawner sp;
    ray_hit h, bad;
    int i, j;

    memset(&h, 0, sizeof h);
    for (i = 0; i < 2000; i++) {
        h.p = vec(rng_range(&g, -1e3, 1e3), rng_range(&g, -1, 1), rng_range(&g, -1e-3, 1e-3));
        h.n = rng_dir(&g);
        h.p_err = vscale(vec(rng_unit(&g), rng_unit(&g), rng_unit(&g)), 1e-13);
        ray__spawner_start(&sp, &h);
        for (j = 0; j < 6; j++) {
            ray_vec3 d = rng_dir(&g);
            double side = (j % 3 == 0) == (i % 2 == 0) ? 1 : -1;
            if (vdot(d, h.n) * side < 0)
                d = vscale(d, -1);
            spawner_should_agree(&sp, vadd(h.p, vscale(d, rng_range(&g, 1e-6, 1e6))));
        }
        spawner_should_agree(&sp, h.p);
        spawner_should_agree(&sp, vec(1, (double)NAN, 0));
        spawner_should_agree(&sp, vec(HUGE_VAL, 0, 0));
    }
    bad = h, bad.p_err.y = (double)NAN;
    ray__spawner_start(&sp, &bad);
    spawner_should_agree(&sp, vadd(h.p, h.n));
    spawner_should_agree(&sp, vsub(h.p, h.n));
    /* p at DBL_MAX, an offset of 2e300 along z: below, an origin;
    ** above, past DBL_MAX (refused), whichever side comes first. */
    bad = h, bad.p = vec(0, 0, DBL_MAX), bad.n = vec(0, 0, 1),
    bad.p_err = vec(0, 0, 1e300);
    for (i = 0; i < 2; i++) {
        ray_vec3 below = vec(0, 0, 1), above = vec(0, 1, DBL_MAX);
        ray_ray r;

        ray__spawner_start(&sp, &bad);
        ck_assert_int_eq(ray__spawn_to(&sp, i ? above : below, &r),
                         i ? RAY_EINVAL : RAY_OK);
        ck_assert_int_eq(ray__spawn_to(&sp, i ? below : above, &r),
                         i ? RAY_OK : RAY_EINVAL);
        spawner_should_agree(&sp, below);
        spawner_should_agree(&sp, above);
        spawner_should_agree(&sp, vec(1, 0, 1));
    }
}
END_TEST

Suite *optics_suite(void)
{
    Suite *s = suite_create("optics");
    TCase *tc = tcase_create("optics");
    TCase *sp = tcase_create("spawn");

    tcase_add_test(tc, fresnel_should_match_reference_values);
    tcase_add_test(tc, refract_should_switch_to_tir_at_critical_angle);
    tcase_add_test(tc, refract_should_obey_snell);
    tcase_add_test(tc, reflect_should_mirror_about_the_normal);
    tcase_add_test(tc, optics_should_refuse_what_is_not_finite);
    tcase_add_test(sp, spawn_should_not_rehit_the_surface);
    tcase_add_test(sp, spawn_to_should_end_before_the_target);
    tcase_add_test(sp, spawn_should_refuse_every_non_finite_number);
    tcase_add_test(sp, spawn_offset_should_follow_the_documented_rule);
    tcase_add_test(sp, hit_error_bounds_should_be_their_documented_values);
    tcase_add_test(sp, spawn_should_not_skip_thin_gaps);
    tcase_add_test(sp, spawn_should_refuse_what_is_not_finite);
    tcase_add_test(sp, spawner_should_make_spawn_to_rays);
    suite_add_tcase(s, tc);
    suite_add_tcase(s, sp);
    return s;
}
