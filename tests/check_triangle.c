/* SPDX-License-Identifier: MIT */
/*
** check_triangle.c -- ray_triangle (Cramer's rule).
*/
#include <float.h>

#include "tests.h"

/* The unit right triangle (0,0,0), (1,0,0), (0,1,0) moved by (o,o,o). */
static void unit_triangle(double o, ray_vec3 *a, ray_vec3 *b, ray_vec3 *c)
{
    *a = vec(o, o, o);
    *b = vec(o + 1, o, o);
    *c = vec(o, o + 1, o);
}

/* A ray straight down (-z) onto the point (x, y) of the plane z = o. */
static ray_ray down_onto(double o, double x, double y)
{
    return ray_from(vec(o + x, o + y, o + 1), vec(0, 0, -1));
}

START_TEST(triangle_should_hit_interior_with_barycentrics)
{
    double o = test_offset(_i), tol = tol_at(o);
    ray_vec3 a, b, c;
    ray_ray r = down_onto(o, 0.25, 0.5);
    ray_hit h;

    unit_triangle(o, &a, &b, &c);
    ck_assert_int_eq(ray_triangle(&r, a, b, c, &h), 1);
    ck_assert_double_eq_tol(h.t, 1.0, tol);
    ck_assert_double_eq_tol(h.u, 0.25, tol);
    ck_assert_double_eq_tol(h.v, 0.5, tol);
    ck_assert_vec_eq_tol(h.p, vec(o + 0.25, o + 0.5, o), tol);
    ck_assert_vec_eq(h.n, vec(0, 0, 1));
    ck_assert(hit_is_finite(&h));
    ck_assert_uint_eq(h.prim_id, RAY_INVALID_ID);
}
END_TEST

START_TEST(triangle_should_hit_back_face_with_same_normal)
{
    ray_vec3 a, b, c;
    ray_ray r = ray_from(vec(0.2, 0.2, -3), vec(0, 0, 1));
    ray_hit h;

    unit_triangle(0, &a, &b, &c);
    ck_assert_int_eq(ray_triangle(&r, a, b, c, &h), 1);
    ck_assert_double_eq_tol(h.t, 3.0, 4 * DBL_EPSILON);
    ck_assert_vec_eq(h.n, vec(0, 0, 1));
}
END_TEST

START_TEST(triangle_should_miss_outside_and_behind)
{
    double o = test_offset(_i);
    ray_vec3 a, b, c;
    ray_ray outside = down_onto(o, 0.6, 0.6);
    ray_ray negative = down_onto(o, -0.1, 0.5);
    ray_ray behind = ray_from(vec(o + 0.2, o + 0.2, o + 1), vec(0, 0, 1));
    ray_hit h;

    unit_triangle(o, &a, &b, &c);
    hit_poison(&h);
    ck_assert_int_eq(ray_triangle(&outside, a, b, c, &h), 0);
    ck_assert_int_eq(ray_triangle(&negative, a, b, c, &h), 0);
    ck_assert_int_eq(ray_triangle(&behind, a, b, c, &h), 0);
    ck_assert(hit_is_poisoned(&h));
}
END_TEST

/* Edges and vertices are inclusive: points exactly on them hit, with the
** barycentrics exactly 0 or 1 where the geometry makes them so. */
START_TEST(triangle_should_hit_exactly_on_edges_and_vertices)
{
    double o = test_offset(_i), tol = tol_at(o);
    ray_vec3 a, b, c;
    double pts[6][2] = {{0.5, 0.0}, {0.0, 0.5}, {0.5, 0.5},
                        {0.0, 0.0}, {1.0, 0.0}, {0.0, 1.0}};
    int k;

    unit_triangle(o, &a, &b, &c);
    for (k = 0; k < 6; k++) {
        ray_ray r = down_onto(o, pts[k][0], pts[k][1]);
        ray_hit h;
        ck_assert_msg(ray_triangle(&r, a, b, c, &h) == 1, "point %d", k);
        ck_assert_double_eq_tol(h.u, pts[k][0], tol);
        ck_assert_double_eq_tol(h.v, pts[k][1], tol);
    }
}
END_TEST

/* A hair outside an edge misses: 1e-9 is far above the rounding here. */
START_TEST(triangle_should_miss_a_hair_outside)
{
    ray_vec3 a, b, c;
    ray_ray r1 = down_onto(0, 0.5, -1e-9);
    ray_ray r2 = down_onto(0, 0.5 + 1e-9, 0.5);
    ray_ray r3 = down_onto(0, -1e-9, 0.5);
    ray_hit h;

    unit_triangle(0, &a, &b, &c);
    ck_assert_int_eq(ray_triangle(&r1, a, b, c, &h), 0);
    ck_assert_int_eq(ray_triangle(&r2, a, b, c, &h), 0);
    ck_assert_int_eq(ray_triangle(&r3, a, b, c, &h), 0);
}
END_TEST

START_TEST(triangle_should_miss_parallel_rays)
{
    ray_vec3 a, b, c;
    ray_ray above = ray_from(vec(-1, 0.2, 1), vec(1, 0, 0));
    ray_ray in_plane = ray_from(vec(-1, 0.2, 0), vec(1, 0, 0));
    ray_hit h;

    unit_triangle(0, &a, &b, &c);
    hit_poison(&h);
    ck_assert_int_eq(ray_triangle(&above, a, b, c, &h), 0);
    ck_assert_int_eq(ray_triangle(&in_plane, a, b, c, &h), 0);
    ck_assert(hit_is_poisoned(&h));
}
END_TEST

START_TEST(triangle_should_miss_degenerate_triangles)
{
    ray_ray r = down_onto(0, 0.25, 0.0);
    ray_hit h;
    /* pbrt-v3 Triangle.BadCases: three collinear vertices. */
    ray_vec3 p0 = vec(-1113.45459, -79.049614, -56.2431908);
    ray_vec3 p1 = vec(-1113.45459, -87.0922699, -56.2431908);
    ray_vec3 p2 = vec(-1113.45459, -79.2090149, -56.2431908);
    ray_ray bad = make_ray(vec(-1081.47925, 99.9999542, 87.7701111),
                           vec(-32.1072998, -183.355865, -144.607635),
                           0.0, 0.9999);

    hit_poison(&h);
    ck_assert_int_eq(ray_triangle(&r, vec(0, 0, 0), vec(1, 0, 0),
                                  vec(0.5, 0, 0), &h), 0);
    ck_assert_int_eq(ray_triangle(&r, vec(0, 0, 0), vec(0, 0, 0),
                                  vec(0, 1, 0), &h), 0);
    ck_assert_int_eq(ray_triangle(&r, vec(0.25, 0, 0), vec(0.25, 0, 0),
                                  vec(0.25, 0, 0), &h), 0);
    ck_assert_int_eq(ray_triangle(&bad, p0, p1, p2, &h), 0);
    ck_assert(hit_is_poisoned(&h));
}
END_TEST

/* Moeller-Trumbore's 1997 |det| < 1e-6 rejects these; exact zero does not. */
START_TEST(triangle_should_hit_tiny_triangles)
{
    double sizes[] = {1e-4, 1e-10, 1e-150};
    int k;

    for (k = 0; k < 3; k++) {
        double s = sizes[k];
        ray_ray r = ray_from(vec(s / 3, s / 3, 1), vec(0, 0, -1));
        ray_hit h;
        ck_assert_msg(ray_triangle(&r, vec(0, 0, 0), vec(s, 0, 0),
                                   vec(0, s, 0), &h) == 1, "size %g", s);
        ck_assert_double_eq_tol(h.t, 1.0, 4 * DBL_EPSILON);
        ck_assert_double_eq_tol(h.u, 1.0 / 3, 8 * DBL_EPSILON);
        ck_assert(hit_is_finite(&h));
    }
}
END_TEST

START_TEST(triangle_should_respect_open_interval)
{
    ray_vec3 a, b, c;
    ray_ray r = down_onto(0, 0.25, 0.25);
    ray_hit h;

    unit_triangle(0, &a, &b, &c);
    r.tmin = 1.0;
    ck_assert_int_eq(ray_triangle(&r, a, b, c, &h), 0);
    r.tmin = 0.0;
    r.tmax = 1.0;
    ck_assert_int_eq(ray_triangle(&r, a, b, c, &h), 0);
    r.tmax = nextafter(1.0, 2.0);
    ck_assert_int_eq(ray_triangle(&r, a, b, c, &h), 1);
    ck_assert_int_eq(ray_triangle_watertight(&r, a, b, c, &h), 1);
    /* tmin is conservative: the hit at t = 1 (exact here) counts only
    ** when tmin lies below t's rounding-error interval, a few ulps of
    ** the coordinates (ray_triangle(3)); 1e-9 below is far past it, one
    ** ulp below is inside it. */
    r.tmin = 1.0 - 1e-9;
    ck_assert_int_eq(ray_triangle(&r, a, b, c, &h), 1);
    ck_assert_int_eq(ray_triangle_watertight(&r, a, b, c, &h), 1);
    r.tmin = nextafter(1.0, 0.0);
    ck_assert_int_eq(ray_triangle(&r, a, b, c, &h), 0);
    ck_assert_int_eq(ray_triangle_watertight(&r, a, b, c, &h), 0);
    r.tmin = 2.0;
    r.tmax = 0.5;
    ck_assert_int_eq(ray_triangle(&r, a, b, c, &h), 0);
}
END_TEST

START_TEST(triangle_should_miss_on_bad_input)
{
    double nan = (double)NAN, inf = HUGE_VAL;
    ray_vec3 a, b, c;
    ray_ray good = down_onto(0, 0.25, 0.25), r;
    ray_hit h;
    int k;

    unit_triangle(0, &a, &b, &c);
    hit_poison(&h);
    for (k = 0; k < 9; k++) {
        r = good;
        switch (k) {
        case 0: r.org.x = nan; break;
        case 1: r.dir.z = nan; break;
        case 2: r.org.z = inf; break;
        case 3: r.dir.z = -inf; break;
        case 4: r.dir = vec(0, 0, 0); break;
        case 5: r.tmin = nan; break;
        case 6: r.tmax = nan; break;
        case 7: r.dir = vec(-0.0, 0.0, -0.0); break;
        case 8: r.org.x = -inf; break;
        }
        ck_assert_msg(ray_triangle(&r, a, b, c, &h) == 0, "case %d", k);
    }
    ck_assert_int_eq(ray_triangle(&good, vec(nan, 0, 0), b, c, &h), 0);
    ck_assert_int_eq(ray_triangle(&good, a, vec(inf, 0, 0), c, &h), 0);
    ck_assert_int_eq(ray_triangle(&good, a, b, vec(0, inf, inf), &h), 0);
    ck_assert(hit_is_poisoned(&h));
}
END_TEST

/* Two triangles sharing the diagonal of the unit square: rays through
** interior points of the diagonal hit at least one.  (The diagonal's ends
** are corners of the square, where a ray may rightly miss both.) */
START_TEST(triangle_should_not_leak_through_shared_edge)
{
    double o = test_offset(_i);
    ray_vec3 a = vec(o, o, o), b = vec(o + 1, o, o), c = vec(o + 1, o + 1, o),
             d = vec(o, o + 1, o);
    int k;

    for (k = 1; k < 64; k++) {
        double s = k / 64.0;
        ray_ray r = ray_from(vec(o + s + 0.3, o + s - 0.2, o + 2),
                             vec(-0.15, 0.1, -1));
        ray_hit h;
        int hits = ray_triangle(&r, a, b, c, &h) + ray_triangle(&r, a, c, d, &h);
        /* The ray meets z = o at (s, s), on the shared diagonal. */
        ck_assert_msg(hits >= 1, "leak at s = %g", s);
    }
}
END_TEST

/*
** Property: 20000 random triangles in [-10,10]^3 (area not tiny), random
** barycentrics, a ray from a random origin aimed at that point (no more
** than ~84 degrees off the normal).  Expect t = 1 and (u, v) = (beta,
** gamma).  Cramer's errors scale with the coordinates (~20) times
** 1/|cos| (<= 10) and the triangle's conditioning; 1e-9 on t and the
** point, 1e-8 on the barycentrics, is far above the observed ~1e-13 and
** far below anything a wrong formula would give.
*/
START_TEST(triangle_should_reproduce_aimed_points)
{
    rng g = {7};
    int i, done = 0;

    for (i = 0; done < 20000; i++) {
        ray_vec3 a = rng_point(&g, -10, 10), b = rng_point(&g, -10, 10),
                 c = rng_point(&g, -10, 10);
        ray_vec3 n = vcross(vsub(b, a), vsub(c, a));
        double beta = rng_unit(&g), gamma = rng_unit(&g);
        ray_vec3 P, org;
        ray_ray r;
        ray_hit h;

        if (vlen(n) < 1.0)
            continue;
        if (beta + gamma > 1) {
            beta = 1 - beta;
            gamma = 1 - gamma;
        }
        P = vadd(vadd(vscale(a, 1 - beta - gamma), vscale(b, beta)),
                 vscale(c, gamma));
        org = rng_point(&g, -30, 30);
        r = ray_from(org, vsub(P, org));
        if (fabs(vdot(r.dir, n)) < 0.1 * vlen(r.dir) * vlen(n))
            continue;
        done++;
        ck_assert_int_eq(ray_triangle(&r, a, b, c, &h), 1);
        ck_assert_double_eq_tol(h.t, 1.0, 1e-9);
        ck_assert_double_eq_tol(h.u, beta, 1e-8);
        ck_assert_double_eq_tol(h.v, gamma, 1e-8);
        ck_assert_vec_eq_tol(h.p, P, 1e-9);
        ck_assert_double_eq_tol(vlen(h.n), 1.0, 4 * DBL_EPSILON);
        ck_assert(hit_is_finite(&h));
    }
}
END_TEST

/*
** The barycentrics of every hit keep the contract, u, v >= 0 and u + v
** <= 1 as computed in double, exactly: on rays aimed at points of the
** edge bc (where u + v is 1 but for rounding) of random triangles, from
** random origins, for both tests.  The watertight test's u = V / det and
** v = W / det, each rounded, can sum to one ulp above 1: it divides
** both by their sum then (watertight.h's clamp; make mutants'
** wt-clamp), and Cramer's rule keeps v <= 1 - u.  Zero tolerance: the
** bound is the contract's, and the code meets it exactly.
*/
START_TEST(triangle_barycentrics_should_sum_to_at_most_one)
{
    rng g = {2024};
    int i, kind, hits = 0, n = 20000;

    for (i = 0; i < n; i++) {
        ray_vec3 a = rng_point(&g, -10, 10), b = rng_point(&g, -10, 10),
                 c = rng_point(&g, -10, 10);
        double s = rng_unit(&g);
        ray_vec3 P = vadd(vscale(b, 1 - s), vscale(c, s));
        ray_ray r = ray_from(rng_point(&g, -30, 30), vec(0, 0, 0));
        r.dir = vsub(P, r.org);
        for (kind = 0; kind < 2; kind++) {
            ray_hit h;
            int rc = kind ? ray_triangle_watertight(&r, a, b, c, &h)
                          : ray_triangle(&r, a, b, c, &h);
            if (rc != 1)
                continue;
            hits++;
            ck_assert_msg(h.u >= 0 && h.v >= 0 && h.u + h.v <= 1,
                          "%s, ray %d: u %.17g v %.17g, u + v - 1 = %.3g",
                          kind ? "watertight" : "Cramer", i, h.u, h.v,
                          h.u + h.v - 1);
        }
    }
    /* P is within rounding of the edge: about half the rays hit. */
    ck_assert_int_gt(hits, n / 2);
}
END_TEST

/*
** A hit's exact t lies past tmin, also where t is least certain: rays
** grazing random triangles (their direction 1e-6 radians off the
** plane, so that M = n . d cancels to a millionth of |n| |d| and its
** rounding moves t by a millionth of t's own precision), aimed at a
** point well inside, with tmin just past the exact t (long double from
** the stored inputs: its error, a few LDBL_EPSILON / 1e-6 relative, is
** within the margin of 16 LDBL_EPSILON / 1e-6).  Every one must miss:
** only a t whose whole error interval lies past tmin is a hit, and the
** interval must count M's error (cramer_t_error's |t| dm; without it
** about 1 in 4000 of these hit).  With tmin 0 each of them hits: the
** rays are aimed inside.
*/
START_TEST(triangle_should_refuse_grazing_hits_at_tmin)
{
    const long double margin = 16 * LDBL_EPSILON / 1e-6L;
    rng g = {31};
    int i, n = 100000, tested = 0;

    for (i = 0; i < n; i++) {
        ray_vec3 a = rng_point(&g, -2, 2), b = rng_point(&g, -2, 2),
                 c = rng_point(&g, -2, 2);
        long double e1[3], e2[3], nv[3], nl, el, tn, tm, t;
        double beta = 0.2 + 0.3 * rng_unit(&g);
        double gamma = 0.2 + 0.3 * rng_unit(&g), len = 1 + 3 * rng_unit(&g);
        ray_vec3 P;
        ray_ray r;
        ray_hit h;
        int k;

        e1[0] = (long double)b.x - (long double)a.x;
        e1[1] = (long double)b.y - (long double)a.y;
        e1[2] = (long double)b.z - (long double)a.z;
        e2[0] = (long double)c.x - (long double)a.x;
        e2[1] = (long double)c.y - (long double)a.y;
        e2[2] = (long double)c.z - (long double)a.z;
        for (k = 0; k < 3; k++)
            nv[k] = e1[(k + 1) % 3] * e2[(k + 2) % 3] -
                    e1[(k + 2) % 3] * e2[(k + 1) % 3];
        nl = sqrtl(nv[0] * nv[0] + nv[1] * nv[1] + nv[2] * nv[2]);
        el = sqrtl(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
        if (nl < 0.5L)                  /* not a sliver: M's size is n's */
            continue;
        P = vadd(a, vadd(vscale(vsub(b, a), beta), vscale(vsub(c, a), gamma)));
        /* Along edge ab, tilted 1e-6 toward the normal. */
        r.dir = vec((double)(e1[0] / el + 1e-6L * nv[0] / nl),
                    (double)(e1[1] / el + 1e-6L * nv[1] / nl),
                    (double)(e1[2] / el + 1e-6L * nv[2] / nl));
        r.org = vsub(P, vscale(r.dir, len));
        tn = ((long double)a.x - (long double)r.org.x) * nv[0] +
             ((long double)a.y - (long double)r.org.y) * nv[1] +
             ((long double)a.z - (long double)r.org.z) * nv[2];
        tm = (long double)r.dir.x * nv[0] + (long double)r.dir.y * nv[1] +
             (long double)r.dir.z * nv[2];
        t = tn / tm;
        r.tmax = HUGE_VAL;
        r.tmin = (double)(t * (1 + margin));
        ck_assert_msg(ray_triangle(&r, a, b, c, &h) == 0,
                      "ray %d: exact t %.17Lg, tmin %.17g, hit at %.17g", i,
                      t, r.tmin, h.t);
        r.tmin = 0;
        ck_assert_int_eq(ray_triangle(&r, a, b, c, &h), 1);
        tested++;
    }
    ck_assert_int_gt(tested, n / 2);
}
END_TEST

/*
** M = n . d past DBL_MAX from finite inputs (edges of 0.95e154, whose
** normal (L^2, L^2, 0) is finite, and the direction (1, 1, 0)): a miss,
** as documented, from tmin -1 as from 0, inside the triangle's shadow or
** not.  Every finite numerator divided by an infinite M is a zero, which
** the range tests take for t = 0 and barycentrics 0 where tmin < 0: a
** hit on vertex a wherever the ray went (true t here is 0.5), which
** ray_triangle reported before it refused an infinite M (issue 38).
*/
START_TEST(triangle_should_miss_where_m_overflows)
{
    const double L = 0.95e154;
    const double ox[3] = {-0.5, -0.5 - 1e-3, -0.5 + 1e-3};
    ray_vec3 a = vec(0, 0, 0), b = vec(0, 0, L), c = vec(L, -L, 0);
    int k;

    for (k = 0; k < 6; k++) {
        ray_ray r = ray_from(vec(ox[k % 3], -0.5, 1e150), vec(1, 1, 0));
        ray_hit h;
        r.tmin = k < 3 ? -1 : 0;
        ck_assert_int_eq(ray_triangle(&r, a, b, c, &h), 0);
        ck_assert_int_eq(ray_triangle_watertight(&r, a, b, c, &h), 0);
    }
}
END_TEST

/*
** A hair outside an edge misses also where the barycentric underflows:
** the triangle (0, 0, 0), (0, 0, L), (L, -L, 0) of L = 1e150 and 1e100,
** rays along (1, 1, 0) from (-d, 0, 1) meet its plane at (-d/2, d/2, 1),
** outside the edge from a by d / 2L, which is below the smallest
** subnormal for d = 1e-230 and 1e-290: its numerator divided by M
** underflows to -0, which "v >= 0" takes, so only the sign test on the
** numerators (exact, before the divisions) refuses it.  tmin -1: t =
** d/2 is within its own error bound of 0.  From (+d, 0, 1), inside by
** as much, they hit (make mutants' tri-sign-filter, that test's && made
** ||, hit both).
*/
START_TEST(triangle_should_miss_a_hair_outside_where_v_underflows)
{
    const double sizes[2] = {1e150, 1e100}, hair[2] = {1e-230, 1e-290};
    int i, k, side;

    for (i = 0; i < 2; i++)
        for (k = 0; k < 2; k++)
            for (side = -1; side <= 1; side += 2) {
                double L = sizes[i];
                ray_ray r = ray_from(vec(side * hair[k], 0, 1),
                                     vec(1, 1, 0));
                ray_hit h;
                r.tmin = -1;
                ck_assert_int_eq(ray_triangle(&r, vec(0, 0, 0), vec(0, 0, L),
                                              vec(L, -L, 0), &h),
                                 side > 0);
            }
}
END_TEST

Suite *triangle_suite(void)
{
    Suite *s = suite_create("triangle");
    TCase *core = tcase_create("hits");
    TCase *hard = tcase_create("hard");
    TCase *prop = tcase_create("property");

    tcase_add_loop_test(core, triangle_should_hit_interior_with_barycentrics, 0, N_OFFSETS);
    tcase_add_test(core, triangle_should_hit_back_face_with_same_normal);
    tcase_add_loop_test(core, triangle_should_miss_outside_and_behind, 0, N_OFFSETS);
    tcase_add_test(core, triangle_should_respect_open_interval);
    tcase_add_loop_test(hard, triangle_should_hit_exactly_on_edges_and_vertices, 0, N_OFFSETS);
    tcase_add_test(hard, triangle_should_miss_a_hair_outside);
    tcase_add_test(hard, triangle_should_miss_parallel_rays);
    tcase_add_test(hard, triangle_should_miss_degenerate_triangles);
    tcase_add_test(hard, triangle_should_hit_tiny_triangles);
    tcase_add_test(hard, triangle_should_miss_on_bad_input);
    tcase_add_test(hard, triangle_should_miss_where_m_overflows);
    tcase_add_test(hard,
                   triangle_should_miss_a_hair_outside_where_v_underflows);
    tcase_add_loop_test(hard, triangle_should_not_leak_through_shared_edge, 0, N_OFFSETS);
    tcase_add_test(prop, triangle_should_reproduce_aimed_points);
    tcase_add_test(prop, triangle_barycentrics_should_sum_to_at_most_one);
    tcase_add_test(prop, triangle_should_refuse_grazing_hits_at_tmin);
    suite_add_tcase(s, core);
    suite_add_tcase(s, hard);
    suite_add_tcase(s, prop);
    return s;
}
