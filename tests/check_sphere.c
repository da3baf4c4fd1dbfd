/* SPDX-License-Identifier: MIT */
/*
** check_sphere.c -- ray_sphere: normal cases, hard cases, bad input and a
** fixed-seed property test.
*/
#include <math.h>
#include <string.h>

#include "tests.h"
#include "scene/scene.h"

START_TEST(sphere_should_hit_front_at_exact_t)
{
    double o = test_offset(_i), tol = tol_at(o);
    ray_vec3 c = vec(o, o, o);
    ray_ray r = ray_from(vec(o, o, o - 5), vec(0, 0, 1));
    ray_hit h;

    ck_assert_int_eq(ray_sphere(&r, c, 1.0, &h), 1);
    ck_assert_double_eq_tol(h.t, 4.0, tol);
    ck_assert_vec_eq_tol(h.p, vec(o, o, o - 1), tol);
    ck_assert_vec_eq_tol(h.n, vec(0, 0, -1), 4 * DBL_EPSILON);
    /* n = (0,0,-1): longitude atan2(0,-1)/2pi + 1/2 = 1, latitude 1/2. */
    ck_assert_double_eq_tol(h.u, 1.0, 4 * DBL_EPSILON);
    ck_assert_double_eq_tol(h.v, 0.5, 4 * DBL_EPSILON);
    ck_assert_uint_eq(h.geom_id, RAY_INVALID_ID);
    ck_assert(hit_is_finite(&h));
}
END_TEST

START_TEST(sphere_should_give_texture_coordinates_at_poles_and_equator)
{
    ray_vec3 c = vec(0, 0, 0);
    ray_ray top = ray_from(vec(0, 5, 0), vec(0, -1, 0));
    ray_ray bottom = ray_from(vec(0, -5, 0), vec(0, 1, 0));
    ray_ray side = ray_from(vec(5, 0, 0), vec(-1, 0, 0));
    ray_hit h;

    ck_assert_int_eq(ray_sphere(&top, c, 2.0, &h), 1);
    ck_assert_double_eq_tol(h.v, 1.0, 4 * DBL_EPSILON);
    ck_assert_int_eq(ray_sphere(&bottom, c, 2.0, &h), 1);
    ck_assert_double_eq_tol(h.v, 0.0, 4 * DBL_EPSILON);
    /* n = +x: atan2(1, 0)/2pi + 1/2 = 3/4. */
    ck_assert_int_eq(ray_sphere(&side, c, 2.0, &h), 1);
    ck_assert_double_eq_tol(h.u, 0.75, 4 * DBL_EPSILON);
    ck_assert_double_eq_tol(h.v, 0.5, 4 * DBL_EPSILON);
}
END_TEST

START_TEST(sphere_should_miss_to_the_side_and_behind)
{
    double o = test_offset(_i);
    ray_vec3 c = vec(o, o, o);
    ray_ray side = ray_from(vec(o, o + 2, o - 5), vec(0, 0, 1));
    ray_ray behind = ray_from(vec(o, o, o + 5), vec(0, 0, 1));
    ray_hit h;

    hit_poison(&h);
    ck_assert_int_eq(ray_sphere(&side, c, 1.0, &h), 0);
    ck_assert_int_eq(ray_sphere(&behind, c, 1.0, &h), 0);
    ck_assert(hit_is_poisoned(&h));
}
END_TEST

START_TEST(sphere_should_hit_far_side_from_inside)
{
    double o = test_offset(_i), tol = tol_at(o);
    ray_vec3 c = vec(o, o, o);
    ray_ray r = ray_from(c, vec(0, 0, 1));
    ray_ray off_centre = ray_from(vec(o + 0.5, o, o), vec(0, 0, 2));
    ray_hit h;

    ck_assert_int_eq(ray_sphere(&r, c, 1.0, &h), 1);
    ck_assert_double_eq_tol(h.t, 1.0, tol);
    ck_assert_vec_eq_tol(h.n, vec(0, 0, 1), 4 * DBL_EPSILON);
    /* |dir| = 2, so t is half the distance sqrt(1 - 0.25). */
    ck_assert_int_eq(ray_sphere(&off_centre, c, 1.0, &h), 1);
    ck_assert_double_eq_tol(h.t, sqrt(0.75) / 2, tol);
}
END_TEST

/* t exactly at tmin or tmax is not a hit (open interval); with tmin on the
** near root the far root is returned. */
START_TEST(sphere_should_respect_open_interval)
{
    ray_vec3 c = vec(0, 0, 0);
    ray_ray r = ray_from(vec(0, 0, -5), vec(0, 0, 1));
    ray_hit h;

    r.tmin = 4.0;
    ck_assert_int_eq(ray_sphere(&r, c, 1.0, &h), 1);
    ck_assert_double_eq(h.t, 6.0);
    r.tmin = 0.0;
    r.tmax = 4.0;
    hit_poison(&h);
    ck_assert_int_eq(ray_sphere(&r, c, 1.0, &h), 0);
    ck_assert(hit_is_poisoned(&h));
    r.tmin = 4.0;
    r.tmax = 6.0;
    ck_assert_int_eq(ray_sphere(&r, c, 1.0, &h), 0);
    r.tmax = nextafter(4.0, 5.0);
    r.tmin = 0.0;
    ck_assert_int_eq(ray_sphere(&r, c, 1.0, &h), 1);
    ck_assert_double_eq(h.t, 4.0);
    r.tmin = 6.0;                    /* tmin > tmax: empty interval */
    r.tmax = 1.0;
    ck_assert_int_eq(ray_sphere(&r, c, 1.0, &h), 0);
}
END_TEST

/*
** Tangent ray x = 1: the discriminant is exactly 0 here (|l| = 1), so this
** is the one-root case: a hit at t = 5, p = (1,0,0), no NaN.  A hair
** outside misses, a hair inside hits twice near t = 5.
*/
START_TEST(sphere_should_classify_tangent_rays)
{
    double o = test_offset(_i), tol = tol_at(o);
    ray_vec3 c = vec(o, o, o);
    ray_ray tangent = ray_from(vec(o + 1, o, o - 5), vec(0, 0, 1));
    ray_ray outside = ray_from(vec(o + 1 + 1e-9, o, o - 5), vec(0, 0, 1));
    ray_ray inside = ray_from(vec(o + 1 - 1e-9, o, o - 5), vec(0, 0, 1));
    ray_hit h;

    ck_assert_int_eq(ray_sphere(&tangent, c, 1.0, &h), 1);
    ck_assert(hit_is_finite(&h));
    ck_assert_double_eq_tol(h.t, 5.0, tol);
    ck_assert_vec_eq_tol(h.p, vec(o + 1, o, o), tol);
    ck_assert_vec_eq_tol(h.n, vec(1, 0, 0), 1e-12);
    ck_assert_int_eq(ray_sphere(&outside, c, 1.0, &h), 0);
    ck_assert_int_eq(ray_sphere(&inside, c, 1.0, &h), 1);
    ck_assert(hit_is_finite(&h));
    /* The chord half-length is sqrt(1 - x^2) ~ 4.5e-5, taken in long
    ** double from the x actually stored (1 - 1e-9 rounded): near the
    ** tangent t depends on x with a factor x/sqrt(1 - x^2) ~ 2e4, so the
    ** reference must use the same input.  That factor multiplies the
    ** error of |l|, the distance of the line from the centre; along this
    ** axis-aligned ray |l| = sqrt(fl(x^2)) is x exactly (in binary
    ** floating point, sqrt(fl(x * x)) = |x|), (1 - |l|) is exact
    ** (Sterbenz) and (1 + |l|) one rounding, so the chord is within 2u of
    ** its value and t = c / q within a few roundings of 5: 8u |t| (the
    ** code gives one ulp).  The margin once was 1e-12, a thousand times
    ** that, which also passed R^2 - l^2 formed by squaring first (its
    ** rounding of l^2 through the factor above: t off by 1.2e-14,
    ** measured with that slip).  The oblique rays below, where |l| is
    ** rounded, have their own bound. */
    if (o == 0.0) {
        long double x = (long double)inside.org.x;
        ck_assert_double_eq_tol(h.t, (double)(5.0L - sqrtl(1.0L - x * x)),
                                8 * U64 * 5);
    }
}
END_TEST

/* Ray r's line against a sphere centred at c, in long double from the
** stored inputs (f = org - c, d = dir): *a = d.d, *b = f.d and *l2, the
** line's squared distance from c, as |f - (f.d / d.d) d|^2: ff - b^2 / a
** would cancel ~|f|^2 away (Hearn and Baker).  The references' shared
** start. */
static void ld_line(const ray_ray *r, ray_vec3 c, long double *a,
                    long double *b, long double *l2)
{
    long double f[3], d[3];
    int k;

    f[0] = (long double)r->org.x - (long double)c.x;
    f[1] = (long double)r->org.y - (long double)c.y;
    f[2] = (long double)r->org.z - (long double)c.z;
    d[0] = (long double)r->dir.x;
    d[1] = (long double)r->dir.y;
    d[2] = (long double)r->dir.z;
    *a = *b = *l2 = 0;
    for (k = 0; k < 3; k++) {
        *a += d[k] * d[k];
        *b += f[k] * d[k];
    }
    for (k = 0; k < 3; k++) {
        long double l = f[k] - *b / *a * d[k];
        *l2 += l * l;
    }
}

/* The near root of ray r against the sphere (c, R) in long double, from
** the stored inputs: the reference of the oblique tangent test. */
static long double sphere_t_ref(const ray_ray *r, ray_vec3 c, double R)
{
    long double a, b, l2;

    ld_line(r, c, &a, &b, &l2);
    return (-b - sqrtl(a * ((long double)R * (long double)R - l2))) / a;
}

/*
** Near-tangent rays in oblique directions, where |l| (the line's distance
** from the centre) is rounded, unlike along an axis: inside the
** silhouette by 1e-3, 1e-6 and 1e-9 of R = 1, from 5, 1e3 and 1e5 away,
** around a centre at 0 and at 1e5.  The margin is sphere.c's own error
** analysis: |l| within dl = 17u |f| (gamma(8) (|f| + |b'/a| |d|)), which
** moves the root by dl R / h (h = sqrt(R^2 - l^2), the half chord: dt/dl
** = l / h), plus 8u |t| for the roots' own roundings.  Far from the
** sphere (|f| = 1e5) the lecture's b'^2 - ac loses the chord entirely
** (its rounding, u |f|^2, is a thousand times the chord's square), and
** forming R^2 - l^2 or l without the cancellation-free order exceeds it
** too; the code stays within 3% of it (SPHERE_TEST_FIGURES=1 prints
** each ratio).
*/
START_TEST(sphere_should_find_oblique_near_tangent_roots_to_its_bound)
{
    static const double inside[3] = {1e-3, 1e-6, 1e-9};
    static const double away[3] = {5, 1e3, 1e5};
    static const double centre[2] = {0, 1e5};
    /* An oblique unit direction, and a unit vector across it. */
    ray_vec3 d = vscale(vec(0.3, -0.5, 0.7), 1 / vlen(vec(0.3, -0.5, 0.7)));
    ray_vec3 side = vsub(vec(0.8, 0.6, 0), vscale(d, vdot(vec(0.8, 0.6, 0), d)));
    int i, j, k;

    side = vscale(side, 1 / vlen(side));
    for (k = 0; k < 2; k++)
        for (i = 0; i < 3; i++)
            for (j = 0; j < 3; j++) {
                ray_vec3 c = vec(centre[k], -centre[k], 0.5 * centre[k]);
                double off = 1 - inside[i];
                ray_ray r = ray_from(vadd(vadd(c, vscale(side, off)),
                                          vscale(d, -away[j])), d);
                long double t = sphere_t_ref(&r, c, 1), h, f, bound;
                ray_hit hit;

                f = (long double)vlen(vsub(r.org, c));
                h = sqrtl(1 - (long double)off * (long double)off);
                bound = 17 * (long double)U64 * f / h +
                        8 * (long double)U64 * fabsl(t);
                ck_assert_int_eq(ray_sphere(&r, c, 1, &hit), 1);
                if (getenv("SPHERE_TEST_FIGURES") != NULL)
                    fprintf(stderr, "err/bound %.3Lg\n",
                            fabsl((long double)hit.t - t) / bound);
                ck_assert_msg(fabsl((long double)hit.t - t) <= bound,
                              "centre %g, inside %g, from %g: t %.17g, "
                              "reference %.17Lg, bound %.3Lg", centre[k],
                              inside[i], away[j], hit.t, t, bound);
            }
}
END_TEST

START_TEST(sphere_should_miss_on_bad_input)
{
    ray_vec3 c = vec(0, 0, 0), org = vec(0, 0, -5), dir = vec(0, 0, 1);
    double nan = (double)NAN, inf = HUGE_VAL;
    ray_ray rays[8];
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
        ck_assert_msg(ray_sphere(&rays[i], c, 1.0, &h) == 0, "ray %d", i);
    ck_assert_int_eq(ray_sphere(&rays[0] + 0, c, 1.0, &h), 0);
    {
        ray_ray ok = ray_from(org, dir);
        double radii[] = {0.0, -1.0, nan, inf, -inf, -0.0};
        for (i = 0; i < 6; i++)
            ck_assert_int_eq(ray_sphere(&ok, c, radii[i], &h), 0);
        ck_assert_int_eq(ray_sphere(&ok, vec(nan, 0, 0), 1.0, &h), 0);
        ck_assert_int_eq(ray_sphere(&ok, vec(0, inf, 0), 1.0, &h), 0);
    }
    ck_assert(hit_is_poisoned(&h));
}
END_TEST

/*
** A sphere of radius 1e-3 at distance 1e4 (the lecture's b^2 - ac would
** subtract two ~1e16 numbers to find ~1e-6).  Rays through x = 0.9e-3 and
** 1.1e-3 must hit and miss; the centre ray's t is 1e4 - 1e-3, with an
** error of a few ulps of 1e4 (ulp(1e4) = 1.8e-12): tolerance 1e-10.
*/
START_TEST(sphere_should_hit_tiny_and_far)
{
    double o = test_offset(_i);
    ray_vec3 c = vec(o, o, o - 1e4);
    ray_ray centre = ray_from(vec(o, o, o), vec(0, 0, -1));
    ray_ray in = ray_from(vec(o + 0.9e-3, o, o), vec(0, 0, -1));
    ray_ray out = ray_from(vec(o + 1.1e-3, o, o), vec(0, 0, -1));
    ray_hit h;

    ck_assert_int_eq(ray_sphere(&centre, c, 1e-3, &h), 1);
    ck_assert_double_eq_tol(h.t, 1e4 - 1e-3, 1e-10 + tol_at(o));
    ck_assert_vec_eq_tol(h.n, vec(0, 0, 1), 1e-12);
    ck_assert_int_eq(ray_sphere(&in, c, 1e-3, &h), 1);
    ck_assert_double_eq_tol(h.t, 1e4 - sqrt(1e-6 - 0.81e-6), 1e-9);
    ck_assert_int_eq(ray_sphere(&out, c, 1e-3, &h), 0);
}
END_TEST

/*
** A sphere of radius 1e6 used as a ground, the camera 1 above it: the
** near root is the small difference of two ~1e6 terms in the textbook
** formula.  Straight down: t = 1 within a few ulps of 1e6 (ulp = 1.2e-10,
** tolerance 1e-9).  A grazing ray sloping 1e-2 down meets the ground at
** t ~ 100.5 (the horizon is at sqrt(2R) ~ 1414); the reference is the
** cancellation-free root in long double.  Tolerance 1e-9: the inputs'
** quantisation ulp(R) = 1.2e-10 moves the root by about that much.
*/
START_TEST(sphere_should_hit_huge_ground_near_origin)
{
    double R = 1e6;
    ray_vec3 c = vec(0, -R, 0);
    ray_ray down = ray_from(vec(0, 1, 0), vec(0, -1, 0));
    ray_ray graze = ray_from(vec(0, 1, 0), vec(1, -1e-2, 0));
    ray_hit h;
    long double a, b, cc, t_ref;

    ck_assert_int_eq(ray_sphere(&down, c, R, &h), 1);
    ck_assert_double_eq_tol(h.t, 1.0, 1e-9);
    ck_assert_vec_eq_tol(h.p, vec(0, 0, 0), 1e-9);
    ck_assert_int_eq(ray_sphere(&graze, c, R, &h), 1);
    /* Reference: a t^2 + 2 b t + cc = 0 in long double, near root by the
    ** cancellation-free form. */
    a = 1.0L + (long double)(1e-2 * 1e-2);
    b = -(long double)1e-2 * (1.0L + (long double)R);
    cc = (1.0L + (long double)R) * (1.0L + (long double)R) -
         (long double)R * (long double)R;
    t_ref = cc / (-b + sqrtl(b * b - a * cc));
    ck_assert_double_eq_tol(h.t, (double)t_ref, 1e-9);
    ck_assert(hit_is_finite(&h));
}
END_TEST

/*
** Property test: 20000 random spheres (centre in [-10,10]^3, radius in
** [0.1, 5]), a random surface point P, a ray from outside aimed at P within
** 78 degrees of the normal (cos > 0.2, so the error of t along the ray
** projects onto the surface by at most a factor 5).  The hit must be P
** with t = 1.  Bound: coordinates up to ~40, ~30 roundings, factor 5:
** 40 * 5 * 64 u ~ 1.4e-12; we allow 1e-11 and also check that P lies in
** the reported error box p +- p_err grown by the same slack.
*/
START_TEST(sphere_should_reproduce_aimed_points)
{
    rng g = {42};
    int i;

    for (i = 0; i < 20000; i++) {
        ray_vec3 c = rng_point(&g, -10, 10);
        double radius = rng_range(&g, 0.1, 5);
        ray_vec3 n = rng_dir(&g), w;
        ray_vec3 P = vadd(c, vscale(n, radius));
        ray_ray r;
        ray_hit h;

        do
            w = rng_dir(&g);
        while (vdot(w, n) < 0.2);
        r = ray_from(vadd(P, vscale(w, rng_range(&g, 0.5, 20))),
                     vec(0, 0, 0));
        r.dir = vsub(P, r.org);
        ck_assert_int_eq(ray_sphere(&r, c, radius, &h), 1);
        ck_assert_double_eq_tol(h.t, 1.0, 1e-11);
        ck_assert_vec_eq_tol(h.p, P, 1e-11);
        ck_assert_double_eq_tol(vdot(h.n, n), 1.0, 1e-12);
        ck_assert_double_eq_tol(vlen(h.n), 1.0, 4 * DBL_EPSILON);
        /* |p - c| = radius within the error box. */
        ck_assert_double_eq_tol(vdist(h.p, c), radius,
                                vlen(h.p_err) + 4 * DBL_EPSILON * radius);
    }
}
END_TEST

/* The lecture's naive formula is kept (internally) for the comparison. */
int ray__sphere_naive(const ray_ray *r, ray_vec3 center, double radius,
                      ray_hit *hit);

/*
** Where the textbook formula breaks in double: a sphere of radius 1 at
** distance 1e9.  b^2 - ac cancels 1e18-sized terms whose rounding (ulp
** 128) swamps the ~1 difference, so the naive test misclassifies rays a
** little inside the silhouette; the cancellation-free form does not.
*/
/*
** Rays passing just inside and just outside tangency, a relative 2^-20 of
** the radius, for radii from 1e-100 to 1e100, origins from 1 to 1e6 radii
** away and sphere centres up to 1e3 radii from the world origin: inside
** must hit and outside must miss.  2^-20 is far above every rounding in
** play (the test's l is within 17u |f| of the true distance, 2e-9 R at
** |f| = 1e6 R; building the ray adds a few ulps of 1e6 R), and far below
** what a wrong early out would need to be caught: ray_sphere's cheap
** "surely missed" test (sphere.c) answers for these outside rays at
** |f| <= 1e6 R (its margin is 512u |f| <= 6e-8 R), the full test for
** the inside ones.
*/
START_TEST(sphere_should_decide_near_tangent_rays_at_every_scale)
{
    rng g = {2024};
    int k, wrong = 0;

    for (k = 0; k < 20000; k++) {
        double R = pow(10, -100 + 200 * rng_unit(&g));
        double away = pow(10, 6 * rng_unit(&g)) * R;
        ray_vec3 c = vscale(rng_dir(&g), 1e3 * R * rng_unit(&g));
        ray_vec3 d = rng_dir(&g), side;
        double inside = (k & 1) ? 1 + 0x1p-20 : 1 - 0x1p-20;
        ray_ray r;
        ray_hit h;
        side = fabs(d.x) > 0.5 ? vec(d.y, -d.x, 0) : vec(0, d.z, -d.y);
        side = vscale(side, 1 / sqrt(vdot(side, side)));
        r = make_ray(vadd(vadd(c, vscale(side, R * inside)),
                            vscale(d, -away)),
                     d, 0, HUGE_VAL);
        wrong += ray_sphere(&r, c, R, &h) != !(k & 1);
    }
    ck_assert_int_eq(wrong, 0);
}
END_TEST

START_TEST(sphere_should_beat_naive_formula_when_far)
{
    ray_vec3 c = vec(0, 0, -1e9);
    int naive_wrong = 0, robust_wrong = 0, k;

    for (k = 0; k < 200; k++) {
        double x = -1.2 + 2.4 * (k + 0.5) / 200.0;
        int expect = fabs(x) < 1.0;
        ray_ray r = ray_from(vec(x, 0, 0), vec(0, 0, -1));
        ray_hit h;

        if (fabs(fabs(x) - 1.0) < 1e-3)
            continue;
        naive_wrong += ray__sphere_naive(&r, c, 1.0, &h) != expect;
        robust_wrong += ray_sphere(&r, c, 1.0, &h) != expect;
    }
    ck_assert_int_eq(robust_wrong, 0);
    ck_assert_int_gt(naive_wrong, 0);
}
END_TEST


/*
** The few-spheres path (scene/commit.c, FEW_SPHERES: a scene of at most
** four spheres, and planes, tests its spheres one after another instead
** of traversing a BVH, with the ray's part of the test taken once:
** query/traverse.h, prims_along).  Its answers must be ray_sphere's and
** ray_plane's on each primitive, the nearest taken by hand, bit for bit:
** every field of the record compared with == (or memcmp for the ids), on
** rays at 0, 1e5 and 1e6 from the origin -- aimed, grazing, from points
** on the surfaces, with tmin or tmax between the two roots, random -- in
** scenes of tiny and huge spheres, with four spheres (the fast path) and
** with the same four and a fifth no ray meets (the BVH's path), so that
** the two paths are compared with each other too.  ray_sphere shares the
** quadratic with the fast path, so a slip there would be copied on both
** sides: the well-conditioned rays are also checked against the roots
** in long double.
*/
enum { FS_MAX = 5 };

typedef struct fs_scene {
    ray_scene *s;
    unsigned n_sph, n_pl;
    ray_vec3 c[FS_MAX];
    double r[FS_MAX];
    unsigned sph_id[FS_MAX];
    ray_vec3 pp[2], pn[2];
    unsigned pl_id[2];
} fs_scene;

/* n_sph spheres of sc (their first n_sph) and n_pl planes, committed. */
static void fs_build(fs_scene *out, const fs_scene *sc, unsigned n_sph,
                     unsigned n_pl)
{
    unsigned i;

    *out = *sc;
    out->n_sph = n_sph;
    out->n_pl = n_pl;
    ck_assert_int_eq(ray_scene_new(&out->s, NULL, NULL), RAY_OK);
    /* The planes first, so that the spheres' ids are the same with four
    ** and with five spheres. */
    for (i = 0; i < n_pl; i++)
        ck_assert_int_eq(ray_scene_add_plane(out->s, sc->pp[i], sc->pn[i],
                                             RAY_NO_MATERIAL,
                                             &out->pl_id[i]), RAY_OK);
    for (i = 0; i < n_sph; i++)
        ck_assert_int_eq(ray_scene_add_sphere(out->s, sc->c[i], sc->r[i],
                                              RAY_NO_MATERIAL,
                                              &out->sph_id[i]), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(out->s), RAY_OK);
    /* The scene keeps a plane's normal normalised (ray_scene_add_plane),
    ** and tests the plane as ray_plane with that normal: the reference
    ** is given it too (the unit normal's t may differ in the last bit
    ** from the raw one's). */
    for (i = 0; i < n_pl; i++)
        out->pn[i] = out->s->prims[out->pl_id[i]].b;
    /* The path under test: the fast one for four spheres or fewer. */
    ck_assert_int_eq(out->s->few_spheres, n_sph <= 4);
}

/* The nearest of ray_sphere's and ray_plane's answers on each primitive,
** the scene's ids set as the scene sets them; *tie: another primitive hit
** at the same t (the scene may then report either: ray_intersect(3)). */
static int fs_reference(const fs_scene *sc, const ray_ray *r, ray_hit *best,
                        int *tie)
{
    unsigned i;
    int found = 0;

    *tie = 0;
    for (i = 0; i < sc->n_sph + sc->n_pl; i++) {
        ray_hit h;
        int k;
        memset(&h, 0, sizeof h);
        if (i < sc->n_sph)
            k = ray_sphere(r, sc->c[i], sc->r[i], &h);
        else
            k = ray_plane(r, sc->pp[i - sc->n_sph], sc->pn[i - sc->n_sph],
                          &h);
        if (!k)
            continue;
        h.geom_id = i < sc->n_sph ? sc->sph_id[i] : sc->pl_id[i - sc->n_sph];
        h.prim_id = 0;
        h.inst_id = RAY_INVALID_ID;
        if (found && h.t == best->t)
            *tie = 1;
        if (!found || h.t < best->t) {
            if (found && h.t < best->t)
                *tie = 0;
            *best = h;
            found = 1;
        }
    }
    return found;
}

/* Two records the same, field by field (== on the doubles: -0 and +0
** would pass, which the library never tells apart either). */
static int fs_same(const ray_hit *a, const ray_hit *b)
{
    return a->t == b->t && a->p.x == b->p.x && a->p.y == b->p.y &&
           a->p.z == b->p.z && a->n.x == b->n.x && a->n.y == b->n.y &&
           a->n.z == b->n.z && a->u == b->u && a->v == b->v &&
           a->p_err.x == b->p_err.x && a->p_err.y == b->p_err.y &&
           a->p_err.z == b->p_err.z && a->geom_id == b->geom_id &&
           a->prim_id == b->prim_id && a->inst_id == b->inst_id;
}

/*
** The roots of sphere (c, R) along r in long double (64-bit significand
** on x86; where long double is double this is the double formula, still
** an independent one), for rays whose line passes within R / 2 of the
** centre: the roots then differ by at least sqrt(3) R / |d| and each is
** within a few units of roundoff of |f| / |d| (f = org - c) of the exact
** one, as the discriminant is at least 3/4 of a R^2, far from 0.  1 and
** *t: the nearest root in (tmin, tmax); 0: none; -1: not such a ray, or
** a root within tol of tmin or tmax (a ray from the surface).
*/
static int fs_ld_root(const ray_ray *r, ray_vec3 c, double R,
                      long double tol, long double *t)
{
    long double a, b, l2, s, t0, t1;
    long double lo = (long double)r->tmin, hi = (long double)r->tmax;

    ld_line(r, c, &a, &b, &l2);
    if (!(l2 <= 0.25L * (long double)R * (long double)R))
        return -1;
    s = sqrtl(((long double)R * (long double)R - l2) / a);
    t0 = -b / a - s;
    t1 = -b / a + s;
    /* A root within the tolerance of tmin or tmax: either answer. */
    if (fabsl(t0 - lo) <= tol || fabsl(t1 - lo) <= tol ||
        fabsl(t0 - hi) <= tol || fabsl(t1 - hi) <= tol)
        return -1;
    if (t0 > lo && t0 < hi)
        *t = t0;
    else if (t1 > lo && t1 < hi)
        *t = t1;
    else
        return 0;
    return 1;
}

/* A point on sphere i of sc, at random. */
static ray_vec3 fs_surface(const fs_scene *sc, unsigned i, rng *g)
{
    return v3_add(sc->c[i], v3_scale(rng_dir(g), sc->r[i]));
}

/*
** Ray k of the set for sc (its spheres 0 .. n - 1), of kind k % 6: 0
** aimed at a point of a sphere from up to 60 of its radii or 40 units
** away; 1 grazing (its line at R (1 + e) from the centre, |e| from 2^-52
** to 2^-20, either sign); 2 from a point on the surface (outward, inward
** or along it); 3 through the centre with tmin or tmax between the two
** roots, or just past one; 4 random; 5 aimed at the centre from far
** (1e3 to 1e7 radii).  Its direction's length from 2^-20 to 2^20, so the
** power-of-two scaling (ray__scaled_dir) varies too.
*/
static ray_ray fs_ray(const fs_scene *sc, unsigned n, rng *g, unsigned k,
                      ray_vec3 centre)
{
    unsigned i = (unsigned)(rng_unit(g) * n) % n;
    ray_vec3 c = sc->c[i], o, target;
    double R = sc->r[i], scale = ldexp(1.0, (int)(rng_unit(g) * 41) - 20);
    ray_ray r;

    r.tmin = 0;
    r.tmax = HUGE_VAL;
    switch (k % 6) {
    case 0:
        target = fs_surface(sc, i, g);
        o = v3_add(target, v3_scale(rng_dir(g), rng_unit(g) < 0.5
                                                    ? 60 * R * rng_unit(g)
                                                    : 40 * rng_unit(g)));
        r.dir = v3_sub(target, o);
        break;
    case 1: {
        ray_vec3 u = rng_dir(g), w = v3_cross(u, rng_dir(g));
        double e = ldexp(1.0, -20 - (int)(rng_unit(g) * 33));
        double len = v3_length(w);
        w = v3_scale(w, 1 / len);
        if (rng_unit(g) < 0.5)
            e = -e;
        /* The closest point of the line, at R (1 + e) from c along w. */
        target = v3_add(c, v3_scale(w, R * (1 + e)));
        o = v3_sub(target, v3_scale(u, R * rng_range(g, 1.5, 50)));
        r.dir = u;
        break;
    }
    case 2: {
        ray_vec3 nrm;
        o = fs_surface(sc, i, g);
        nrm = v3_sub(o, c);
        r.dir = rng_dir(g);
        if (rng_unit(g) < 0.3)      /* along the surface, nearly */
            r.dir = v3_sub(r.dir, v3_scale(nrm, v3_dot(r.dir, nrm) /
                                                    v3_dot(nrm, nrm)));
        break;
    }
    case 3: {
        double dist = R * rng_range(g, 1.5, 100), t0, t1, cut;
        r.dir = rng_dir(g);
        o = v3_sub(c, v3_scale(r.dir, dist));
        /* Unit direction: the roots near dist -+ R. */
        t0 = dist - R;
        t1 = dist + R;
        switch ((unsigned)(rng_unit(g) * 4)) {
        case 0: r.tmin = 0.5 * (t0 + t1); break;
        case 1: r.tmax = 0.5 * (t0 + t1); break;
        case 2: cut = t0 * (1 + 0x1p-40); r.tmin = cut; break;
        default: cut = t1 * (1 - 0x1p-40); r.tmax = cut; break;
        }
        r.dir = v3_scale(r.dir, scale);
        r.tmin /= scale;
        if (r.tmax < HUGE_VAL)
            r.tmax /= scale;
        r.org = o;
        return r;
    }
    case 4:
        o = v3_add(centre, rng_point(g, -30, 30));
        r.dir = rng_dir(g);
        break;
    default:
        target = c;
        o = v3_add(c, v3_scale(rng_dir(g),
                               R * pow(10.0, rng_range(g, 3, 7))));
        r.dir = v3_sub(target, o);
        break;
    }
    r.org = o;
    r.dir = v3_scale(r.dir, scale / v3_length(r.dir));
    return r;
}

/* The spheres and planes of scene "which" around centre: 0 four spheres
** of radii 0.01 to 10 near each other; 1 a tiny sphere (1e-6), a huge one
** (1e5, its top near the centre) and two of unit size, one inside the
** other; both with a fifth sphere of radius 1e-3 at 1e9 from the centre
** (for the five-sphere scene: no ray meets it), and two planes. */
static void fs_make(fs_scene *sc, int which, ray_vec3 centre, rng *g)
{
    unsigned i;

    memset(sc, 0, sizeof *sc);
    for (i = 0; i < 4; i++) {
        sc->c[i] = v3_add(centre, rng_point(g, -10, 10));
        sc->r[i] = pow(10.0, rng_range(g, -2, 1));
    }
    if (which == 1) {
        sc->r[0] = 1e-6;
        sc->c[1] = v3_add(centre, vec(0, -1e5 - 1, 0));
        sc->r[1] = 1e5;
        sc->r[2] = 1;
        sc->c[3] = v3_add(sc->c[2], vec(0.25, 0, 0));
        sc->r[3] = 0.5;
    }
    sc->c[4] = v3_add(centre, vec(0, 0, 1e9));
    sc->r[4] = 1e-3;
    sc->pp[0] = v3_add(centre, vec(0, -20, 0));
    sc->pn[0] = vec(0, 1, 0);
    sc->pp[1] = v3_add(centre, rng_point(g, -5, 5));
    sc->pn[1] = rng_dir(g);
}

/* The count of rays a scene: 50000 under make check-long, 8000 under
** make check, or RAY_FEW_SPHERES_RAYS. */
static size_t fs_rays(void)
{
    return test_count("RAY_FEW_SPHERES_RAYS", 50000, 8000);
}

START_TEST(few_spheres_should_answer_as_each_primitive_bit_for_bit)
{
    static const double offsets[3] = {0, 1e5, 1e6};
    size_t n = fs_rays(), i, hits = 0, checked_ld = 0, total = 0;
    int o, which, planes;

    for (o = 0; o < 3; o++)
        for (which = 0; which < 2; which++)
            for (planes = 0; planes <= 2; planes += 2) {
                ray_vec3 centre = vec(offsets[o], -0.5 * offsets[o],
                                      0.25 * offsets[o]);
                rng g = {(uint64_t)(1000 + 10 * o + which + 100 * planes)};
                fs_scene sc, four, five;
                fs_make(&sc, which, centre, &g);
                fs_build(&four, &sc, 4, (unsigned)planes);
                fs_build(&five, &sc, 5, (unsigned)planes);
                for (i = 0; i < n; i++) {
                    ray_ray r = fs_ray(&sc, 4, &g, (unsigned)i, centre);
                    ray_hit want, want4, h4, h5;
                    int tie, tie4, k, k4, k5, j;
                    memset(&want, 0, sizeof want);
                    memset(&want4, 0, sizeof want4);
                    memset(&h4, 0, sizeof h4);
                    memset(&h5, 0, sizeof h5);
                    k = fs_reference(&five, &r, &want, &tie);
                    /* The fifth sphere is never met: the same nearest. */
                    ck_assert_int_eq(fs_reference(&four, &r, &want4, &tie4),
                                     k);
                    ck_assert(!k || fs_same(&want4, &want));
                    k4 = ray_intersect(four.s, &r, &h4, NULL);
                    k5 = ray_intersect(five.s, &r, &h5, NULL);
                    ck_assert_msg(k4 == k && k5 == k,
                                  "ray %zu: %d, %d, want %d (offset %g, "
                                  "scene %d)", i, k4, k5, k, offsets[o],
                                  which);
                    ck_assert_int_eq(ray_occluded(four.s, &r, NULL), k);
                    ck_assert_int_eq(ray_occluded(five.s, &r, NULL), k);
                    /* The long double roots, where well conditioned:
                    ** tol = 2^-40 (|f| + R) / |d| is 2^12 times a
                    ** double's rounding of t (ray_sphere's t is within
                    ** a few ulps of it: ray-numerics(7)), and below
                    ** 2^-16 of the roots' distance 2 R / |d| as long
                    ** as |f| <= 1e7 R (the farthest rays here): a wrong
                    ** root or a lost hit fails. */
                    for (j = 0; j < 4; j++) {
                        long double t, tol = 0x1p-40L * (long double)(
                            (v3_length(v3_sub(r.org, sc.c[j])) + sc.r[j]) /
                            v3_length(r.dir));
                        int kl = fs_ld_root(&r, sc.c[j], sc.r[j], tol, &t);
                        ray_hit hj;
                        int kj;
                        if (kl < 0)
                            continue;
                        kj = ray_sphere(&r, sc.c[j], sc.r[j], &hj);
                        checked_ld++;
                        ck_assert_msg(kj == kl, "ray %zu, sphere %d: %d, "
                                      "long double %d", i, j, kj, kl);
                        if (kj)
                            ck_assert_msg(fabsl((long double)hj.t - t) <=
                                              tol,
                                          "ray %zu, sphere %d: t %a, long "
                                          "double %La (org %a %a %a, dir "
                                          "%a %a %a)", i, j, hj.t, t,
                                          r.org.x, r.org.y, r.org.z,
                                          r.dir.x, r.dir.y, r.dir.z);
                    }
                    total++;
                    if (!k)
                        continue;
                    hits++;
                    if (tie) {       /* either primitive: the same t */
                        ck_assert(h4.t == want.t && h5.t == want.t);
                        continue;
                    }
                    ck_assert_msg(fs_same(&h4, &want) && fs_same(&h5, &want),
                                  "ray %zu: t %a, %a, want %a (geom %u, "
                                  "%u, want %u; offset %g, scene %d)", i,
                                  h4.t, h5.t, want.t, h4.geom_id,
                                  h5.geom_id, want.geom_id, offsets[o],
                                  which);
                }
                ray_scene_free(four.s);
                ray_scene_free(five.s);
            }
    /* Most rays hit something, and many went through the long double
    ** check: the test is not vacuous. */
    ck_assert_msg(hits > total / 2, "%zu hits of %zu", hits, total);
    ck_assert_msg(checked_ld > total / 10, "%zu long double checks of %zu",
                  checked_ld, total);
}
END_TEST

Suite *sphere_suite(void)
{
    Suite *s = suite_create("sphere");
    TCase *core = tcase_create("hits");
    TCase *hard = tcase_create("hard");
    TCase *prop = tcase_create("property");
    TCase *scene = tcase_create("scene");

    tcase_add_loop_test(core, sphere_should_hit_front_at_exact_t, 0, N_OFFSETS);
    tcase_add_test(core, sphere_should_give_texture_coordinates_at_poles_and_equator);
    tcase_add_loop_test(core, sphere_should_miss_to_the_side_and_behind, 0, N_OFFSETS);
    tcase_add_loop_test(core, sphere_should_hit_far_side_from_inside, 0, N_OFFSETS);
    tcase_add_test(core, sphere_should_respect_open_interval);
    tcase_add_loop_test(hard, sphere_should_classify_tangent_rays, 0, N_OFFSETS);
    tcase_add_test(hard, sphere_should_miss_on_bad_input);
    tcase_add_loop_test(hard, sphere_should_hit_tiny_and_far, 0, N_OFFSETS);
    tcase_add_test(hard, sphere_should_hit_huge_ground_near_origin);
    tcase_add_test(hard, sphere_should_beat_naive_formula_when_far);
    tcase_add_test(hard, sphere_should_decide_near_tangent_rays_at_every_scale);
    tcase_add_test(hard, sphere_should_find_oblique_near_tangent_roots_to_its_bound);
    tcase_add_test(prop, sphere_should_reproduce_aimed_points);
    suite_add_tcase(s, core);
    suite_add_tcase(s, hard);
    tcase_add_test(scene, few_spheres_should_answer_as_each_primitive_bit_for_bit);
    tcase_set_timeout(scene, 60);
    suite_add_tcase(s, prop);
    suite_add_tcase(s, scene);
    return s;
}
