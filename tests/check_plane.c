/* SPDX-License-Identifier: MIT */
/*
** check_plane.c -- ray_plane.
*/
#include "tests.h"

START_TEST(plane_should_hit_with_tangent_coordinates)
{
    double o = test_offset(_i), tol = tol_at(o);
    ray_vec3 point = vec(o, o, o);
    ray_ray r = ray_from(vec(o + 1, o + 2, o + 3), vec(0, -1, 0));
    ray_hit h;

    ck_assert_int_eq(ray_plane(&r, point, vec(0, 1, 0), &h), 1);
    ck_assert_double_eq_tol(h.t, 2.0, tol);
    ck_assert_vec_eq_tol(h.p, vec(o + 1, o, o + 3), tol);
    ck_assert_vec_eq(h.n, vec(0, 1, 0));
    /* Documented frame for n = +y: t1 = +x, t2 = -z. */
    ck_assert_double_eq_tol(h.u, 1.0, tol);
    ck_assert_double_eq_tol(h.v, -3.0, tol);
    ck_assert(hit_is_finite(&h));
}
END_TEST

/* The normal need not be unit length; the reported one is, and keeps its
** orientation even when the ray comes from behind. */
START_TEST(plane_should_normalise_but_not_flip_the_normal)
{
    ray_ray below = ray_from(vec(0, -2, 0), vec(0, 4, 0));
    ray_hit h;

    ck_assert_int_eq(ray_plane(&below, vec(0, 0, 0), vec(0, 5, 0), &h), 1);
    ck_assert_double_eq_tol(h.t, 0.5, 4 * DBL_EPSILON);
    ck_assert_vec_eq(h.n, vec(0, 1, 0));
}
END_TEST

START_TEST(plane_should_miss_parallel_rays_without_nan)
{
    double o = test_offset(_i);
    ray_vec3 point = vec(o, o, o), n = vec(0, 1, 0);
    ray_ray above = ray_from(vec(o, o + 1, o), vec(1, 0, 0));
    ray_ray inside = ray_from(vec(o, o, o), vec(1, 0, 0));
    ray_ray away = ray_from(vec(o, o + 1, o), vec(0, 1, 0));
    ray_hit h;

    hit_poison(&h);
    ck_assert_int_eq(ray_plane(&above, point, n, &h), 0);
    ck_assert_int_eq(ray_plane(&inside, point, n, &h), 0);
    ck_assert_int_eq(ray_plane(&away, point, n, &h), 0);
    ck_assert(hit_is_poisoned(&h));
}
END_TEST

/*
** Nearly parallel: d.n = -1e-12 from height 1 gives t = 1e12.  The raw
** e + t d has an error of ~ulp(1e12) = 1.2e-4 along the ray, mostly along
** x; the reported point must still be on the plane to within its own
** error bound p_err.
*/
START_TEST(plane_should_keep_grazing_hits_on_the_plane)
{
    ray_ray r = ray_from(vec(0, 1, 0), vec(1, -1e-12, 0));
    ray_hit h;

    ck_assert_int_eq(ray_plane(&r, vec(0, 0, 0), vec(0, 1, 0), &h), 1);
    ck_assert(hit_is_finite(&h));
    ck_assert_double_eq_tol(h.t, 1e12, 1e12 * 4 * DBL_EPSILON);
    ck_assert(fabs(h.p.y) <= h.p_err.y);
    ck_assert(h.p_err.y < 1e-3);
}
END_TEST

START_TEST(plane_should_respect_open_interval)
{
    ray_ray r = ray_from(vec(0, 2, 0), vec(0, -1, 0));
    ray_hit h;

    r.tmax = 2.0;
    ck_assert_int_eq(ray_plane(&r, vec(0, 0, 0), vec(0, 1, 0), &h), 0);
    r.tmax = HUGE_VAL;
    r.tmin = 2.0;
    ck_assert_int_eq(ray_plane(&r, vec(0, 0, 0), vec(0, 1, 0), &h), 0);
    /* tmin is conservative: the hit at t = 2 (exact here) counts only
    ** when tmin lies below t's rounding-error interval (ray_plane(3));
    ** 1e-9 below is far past it, one ulp below is inside it. */
    r.tmin = 2.0 - 1e-9;
    ck_assert_int_eq(ray_plane(&r, vec(0, 0, 0), vec(0, 1, 0), &h), 1);
    ck_assert_double_eq(h.t, 2.0);
    r.tmin = nextafter(2.0, 0.0);
    ck_assert_int_eq(ray_plane(&r, vec(0, 0, 0), vec(0, 1, 0), &h), 0);
}
END_TEST

START_TEST(plane_should_miss_on_bad_input)
{
    double nan = (double)NAN, inf = HUGE_VAL;
    ray_ray good = ray_from(vec(0, 2, 0), vec(0, -1, 0)), r;
    ray_vec3 pt = vec(0, 0, 0), n = vec(0, 1, 0);
    ray_hit h;
    int k;

    hit_poison(&h);
    for (k = 0; k < 7; k++) {
        r = good;
        switch (k) {
        case 0: r.org.y = nan; break;
        case 1: r.dir.x = nan; break;
        case 2: r.org.x = inf; break;
        case 3: r.dir.y = -inf; break;
        case 4: r.dir = vec(0, 0, 0); break;
        case 5: r.tmin = nan; break;
        case 6: r.tmax = -inf; break;
        }
        ck_assert_msg(ray_plane(&r, pt, n, &h) == 0, "case %d", k);
    }
    ck_assert_int_eq(ray_plane(&good, pt, vec(0, 0, 0), &h), 0);
    ck_assert_int_eq(ray_plane(&good, pt, vec(0, nan, 0), &h), 0);
    ck_assert_int_eq(ray_plane(&good, pt, vec(0, inf, 0), &h), 0);
    ck_assert_int_eq(ray_plane(&good, vec(nan, 0, 0), n, &h), 0);
    ck_assert_int_eq(ray_plane(&good, vec(0, inf, 0), n, &h), 0);
    ck_assert(hit_is_poisoned(&h));
}
END_TEST

/*
** Property: 20000 random planes (point in [-1e3,1e3]^3, any normal),
** a random point P on each, a ray aimed at it from up to 1e3 away, at
** least ~6 degrees off grazing.  t = 1 within 1e-9 (coordinates ~1e3,
** error magnified by <= 10 for the angle: 1e3 * 10 * 32 u ~ 4e-11), and the
** reported point's distance to the plane is within its error box.
*/
/*
** Issue 14, defect 1 (found by fuzzing): origin (-8, 1 + 2^-52, DBL_MAX),
** direction (-8, 0, 0), normal (1, 1, 1) hit the plane at a point with
** coordinates near -DBL_MAX and +DBL_MAX, and (u, v) = ((p - point).t1,
** ...) overflowed to u = -Inf.  No Inf may reach a hit: such a hit is a
** miss (its texture coordinates are beyond double's range), for the
** plane and for a polygon through the plane's point, whatever the point;
** and every finite hit near the range's end has finite (u, v), n, p,
** p_err.
*/
START_TEST(plane_should_never_give_infinite_hit_fields)
{
    ray_ray r = ray_from(vec(-8, 1 + 0x1p-52, DBL_MAX), vec(-8, 0, 0));
    ray_vec3 points[3] = {{0, 0, 0}, {1, 2, 3}, {-8, 1, 1e307}};
    ray_vec3 poly[3] = {{0, 0, 0}, {1, -1, 0}, {0, 1, -1}};
    ray_hit h;
    int k, hit;

    for (k = 0; k < 3; k++) {
        hit = ray_plane(&r, points[k], vec(1, 1, 1), &h);
        if (hit)
            ck_assert(hit_is_finite(&h));
    }
    if (ray_polygon(&r, poly, 3, &h))
        ck_assert(hit_is_finite(&h));
    /* Far from the origin but within range: hits with finite fields. */
    for (k = 0; k < 200; k++) {
        double big = ldexp(1.0, 900 + k / 2);
        ray_ray q = ray_from(vec(big, big, 1), vec(-1e-3 * k - 1, 0.5, -1));
        hit = ray_plane(&q, vec(-big, 0, 0), vec(0.3, 0.5, 1), &h);
        if (hit)
            ck_assert(hit_is_finite(&h));
    }
}
END_TEST

START_TEST(plane_should_reproduce_aimed_points)
{
    rng g = {3};
    int done = 0;

    while (done < 20000) {
        ray_vec3 pt = rng_point(&g, -1e3, 1e3), n = rng_dir(&g), t1, P, org;
        ray_ray r;
        ray_hit h;

        t1 = vcross(n, fabs(n.x) < 0.5 ? vec(1, 0, 0) : vec(0, 1, 0));
        P = vadd(pt, vscale(t1, rng_range(&g, -100, 100)));
        org = vadd(P, vscale(rng_dir(&g), rng_range(&g, 1, 1e3)));
        r = ray_from(org, vsub(P, org));
        if (fabs(vdot(r.dir, n)) < 0.1 * vlen(r.dir))
            continue;
        done++;
        ck_assert_int_eq(ray_plane(&r, pt, vscale(n, rng_range(&g, 0.1, 10)),
                                   &h), 1);
        ck_assert_double_eq_tol(h.t, 1.0, 1e-9);
        ck_assert_vec_eq_tol(h.p, P, 1e-9);
        ck_assert(fabs(vdot(vsub(h.p, pt), h.n)) <=
                  vdot(vec(fabs(h.n.x), fabs(h.n.y), fabs(h.n.z)), h.p_err));
    }
}
END_TEST

Suite *plane_suite(void)
{
    Suite *s = suite_create("plane");
    TCase *core = tcase_create("hits");
    TCase *hard = tcase_create("hard");
    TCase *prop = tcase_create("property");

    tcase_add_loop_test(core, plane_should_hit_with_tangent_coordinates, 0, N_OFFSETS);
    tcase_add_test(core, plane_should_normalise_but_not_flip_the_normal);
    tcase_add_test(core, plane_should_respect_open_interval);
    tcase_add_loop_test(hard, plane_should_miss_parallel_rays_without_nan, 0, N_OFFSETS);
    tcase_add_test(hard, plane_should_keep_grazing_hits_on_the_plane);
    tcase_add_test(hard, plane_should_miss_on_bad_input);
    tcase_add_test(hard, plane_should_never_give_infinite_hit_fields);
    tcase_add_test(prop, plane_should_reproduce_aimed_points);
    suite_add_tcase(s, core);
    suite_add_tcase(s, hard);
    suite_add_tcase(s, prop);
    return s;
}
