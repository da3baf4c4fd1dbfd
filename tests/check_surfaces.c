/* SPDX-License-Identifier: MIT */
/*
** check_surfaces.c -- curved surfaces in scenes: ray_scene_add_torus,
** _implicit, _parametric and _bezier; the BVH finds what the bare
** functions find; failures are counted, not guessed.
*/
#include <stdlib.h>

#include "bench.h"
#include "prim/prim.h"         /* ray__implicit_torus */
#include "tests.h"

/* A scene whose material 0 shades nothing (the tests only intersect). */
static ray_scene *new_scene(void)
{
    ray_scene *s = NULL;   /* -O1 cannot see that ck_assert stops */

    ck_assert_int_eq(nop_scene_new(&s, NULL, NULL), RAY_OK);
    return s;
}

/* A dome-shaped Bezier patch over [x0, x0 + 3] x [y0, y0 + 3]. */
static void dome(ray_vec3 cp[16], double x0, double y0, double z0)
{
    int i, j;

    for (i = 0; i < 4; i++)
        for (j = 0; j < 4; j++)
            cp[4 * i + j] = vec(x0 + j, y0 + i,
                                z0 + ((i == 1 || i == 2) && (j == 1 || j == 2)
                                          ? 1.0
                                          : 0.0));
}

/* A bumpy field for a parametric surface: z = 0.2 sin(u) cos(v) over
** [0, 3]^2, with a box that holds it (|z| <= 0.2). */
static void wave_eval(void *ud, double u, double v, ray_vec3 *p,
                      ray_vec3 *pu, ray_vec3 *pv)
{
    (void)ud;
    *p = vec(u, v, 0.2 * sin(u) * cos(v));
    *pu = vec(1, 0, 0.2 * cos(u) * cos(v));
    *pv = vec(0, 1, -0.2 * sin(u) * sin(v));
}

static void wave_bounds(void *ud, double u0, double u1, double v0, double v1,
                        ray_vec3 *lo, ray_vec3 *hi)
{
    (void)ud;
    *lo = vec(u0, v0, -0.2);
    *hi = vec(u1, v1, 0.2);
}

static ray_parametric_surface wave_surface(void)
{
    ray_parametric_surface ps;
    memset(&ps, 0, sizeof ps);
    ps.eval = wave_eval;
    ps.bounds = wave_bounds;
    ps.u1 = 3;
    ps.v1 = 3;
    return ps;
}

START_TEST(scene_should_reject_bad_surfaces_and_add_nothing)
{
    ray_scene *s = new_scene();
    ray_torus_params t = {{0, 0, 0}, {0, 0, 1}, 1, 0.25};
    ray_implicit_surface is;
    ray_parametric_surface ps = wave_surface();
    ray_vec3 cp[16];
    unsigned id = 77;

    dome(cp, 0, 0, 0);
    ck_assert_int_eq(ray__implicit_torus(&t, &is), RAY_OK);
    ck_assert_int_eq(ray_scene_add_torus(NULL, &t, 0, &id), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_torus(s, NULL, 0, &id), RAY_EINVAL);
    t.minor = -1;
    ck_assert_int_eq(ray_scene_add_torus(s, &t, 0, &id), RAY_EINVAL);
    t.minor = 0.25;
    ck_assert_int_eq(ray_scene_add_torus(s, &t, 1, &id), RAY_EINVAL);
    is.f = NULL;
    ck_assert_int_eq(ray_scene_add_implicit(s, &is, 0, &id), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_implicit(s, NULL, 0, &id), RAY_EINVAL);
    ps.bounds = NULL;
    ck_assert_int_eq(ray_scene_add_parametric(s, &ps, 0, &id), RAY_EINVAL);
    ps = wave_surface();
    ps.u1 = -1;                                     /* empty domain */
    ck_assert_int_eq(ray_scene_add_parametric(s, &ps, 0, &id), RAY_EINVAL);
    ps = wave_surface();
    ps.subdivisions = 1000;                 /* beyond what ray_parametric takes */
    ck_assert_int_eq(ray_scene_add_parametric(s, &ps, 0, &id), RAY_EINVAL);
    cp[5].y = (double)NAN;
    ck_assert_int_eq(ray_scene_add_bezier(s, cp, 0, &id), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_bezier(s, NULL, 0, &id), RAY_EINVAL);
    ck_assert_uint_eq(id, 77);                      /* nothing added */
    /* Valid ones get ids 0, 1, 2, 3 in order. */
    dome(cp, 0, 0, 0);
    ps = wave_surface();
    ck_assert_int_eq(ray__implicit_torus(&t, &is), RAY_OK);
    ck_assert_int_eq(ray_scene_add_torus(s, &t, 0, &id), RAY_OK);
    ck_assert_uint_eq(id, 0);
    ck_assert_int_eq(ray_scene_add_implicit(s, &is, 0, &id), RAY_OK);
    ck_assert_uint_eq(id, 1);
    ck_assert_int_eq(ray_scene_add_parametric(s, &ps, 0, &id), RAY_OK);
    ck_assert_uint_eq(id, 2);
    ck_assert_int_eq(ray_scene_add_bezier(s, cp, 0, &id), RAY_OK);
    ck_assert_uint_eq(id, 3);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    /* After commit they are staged for the next one, numbered on. */
    ck_assert_int_eq(ray_scene_add_torus(s, &t, 0, &id), RAY_OK);
    ck_assert_uint_eq(id, 4);
    ck_assert_int_eq(ray_scene_add_bezier(s, cp, 0, &id), RAY_OK);
    ck_assert_uint_eq(id, 5);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ray_scene_free(s);
}
END_TEST

/* A bounds callback that breaks its contract, as ud says: 0 a NaN
** corner, 1 lo.y > hi.y, 2 lo.z > hi.z. */
static void bad_bounds(void *ud, double u0, double u1, double v0, double v1,
                       ray_vec3 *lo, ray_vec3 *hi)
{
    int how = *(const int *)ud;

    wave_bounds(NULL, u0, u1, v0, v1, lo, hi);
    if (how == 0)
        lo->x = (double)NAN;
    else if (how == 1)
        lo->y = hi->y + 1;
    else
        lo->z = hi->z + 1;
}

/* The scene's message after a refusal holds "what". */
#define REFUSED_WITH(s, call, what)                                        \
    do {                                                                   \
        ck_assert_int_eq(call, RAY_EINVAL);                                \
        ck_assert_msg(strstr(ray_scene_errmsg(s), what) != NULL, "%s",     \
                      ray_scene_errmsg(s));                                \
    } while (0)

/*
** Issue 38: the rest of the curved surfaces' checks, each refusal with
** RAY_EINVAL, the message that names the field at fault (ray_scene_errmsg),
** and nothing added: a torus with a NaN centre, a NaN axis or an
** infinite major radius; an implicit surface's box with a NaN corner
** (either) or lo > hi in y or z, or a negative tolerance; a parametric
** surface whose bounds callback answers a NaN corner or lo > hi in y or
** z (ray_scene_add_parametric asks it for the whole domain).
*/
START_TEST(scene_should_name_what_is_wrong_with_a_surface)
{
    ray_scene *s = new_scene();
    ray_torus_params t0 = {{0, 0, 0}, {0, 0, 1}, 1, 0.25}, t;
    ray_implicit_surface i0, is;
    ray_parametric_surface ps = wave_surface();
    unsigned id = 77;
    int how;

    ck_assert_int_eq(ray__implicit_torus(&t0, &i0), RAY_OK);
    t = t0, t.center.z = (double)NAN;
    REFUSED_WITH(s, ray_scene_add_torus(s, &t, 0, &id), "center");
    t = t0, t.axis.y = (double)NAN;
    REFUSED_WITH(s, ray_scene_add_torus(s, &t, 0, &id), "axis");
    t = t0, t.major = HUGE_VAL;
    REFUSED_WITH(s, ray_scene_add_torus(s, &t, 0, &id), "major radius inf");
    is = i0, is.lo.y = (double)NAN;
    REFUSED_WITH(s, ray_scene_add_implicit(s, &is, 0, &id), "box lo");
    is = i0, is.hi.z = HUGE_VAL;
    REFUSED_WITH(s, ray_scene_add_implicit(s, &is, 0, &id), "box lo");
    is = i0, is.lo.y = is.hi.y + 1;
    REFUSED_WITH(s, ray_scene_add_implicit(s, &is, 0, &id), "lo > hi");
    is = i0, is.lo.z = is.hi.z + 1;
    REFUSED_WITH(s, ray_scene_add_implicit(s, &is, 0, &id), "lo > hi");
    is = i0, is.tolerance = -1;
    REFUSED_WITH(s, ray_scene_add_implicit(s, &is, 0, &id), "tolerance -1");
    ps.bounds = bad_bounds;
    ps.ud = &how;
    for (how = 0; how < 3; how++)
        REFUSED_WITH(s, ray_scene_add_parametric(s, &ps, 0, &id),
                     "the bounds callback gave");
    ck_assert_uint_eq(id, 77);
    /* Nothing was added: the first good one is geometry 0. */
    ck_assert_int_eq(ray_scene_add_torus(s, &t0, 0, &id), RAY_OK);
    ck_assert_uint_eq(id, 0);
    ray_scene_free(s);
}
END_TEST

/* The wave's bounds, broken (as bad_bounds breaks them, by ud) on every
** rectangle smaller than the whole domain [0, 3]^2. */
static void bad_sub_bounds(void *ud, double u0, double u1, double v0,
                           double v1, ray_vec3 *lo, ray_vec3 *hi)
{
    if (u1 - u0 < 3 || v1 - v0 < 3)
        bad_bounds(ud, u0, u1, v0, v1, lo, hi);
    else
        wave_bounds(NULL, u0, u1, v0, v1, lo, hi);
}

/*
** Issue 38: ray_parametric answers -RAY_EINVAL, *hit untouched, for "a
** box with lo > hi from the callbacks" or one not finite (its page), also
** when only the boxes of the subdivision are broken, past the whole
** domain's (a NaN corner, lo > hi in y, in z), where the wave itself is
** hit (t = 5 - 0.2 sin(1.5) cos(1.5) from z = 5, within 1e-9), and for a
** domain whose width overflows (-DBL_MAX to DBL_MAX, in u or v).
** ray_implicit_blobs refuses (RAY_EINVAL, *out untouched) an infinite
** threshold, a blob of infinite radius or of NaN strength, blobs whose box
** overflows (centre and radius 1e308) and a Lipschitz bound that does
** (strength 1e308 over radius 1e-300).
*/
START_TEST(broken_callbacks_and_blobs_should_be_refused)
{
    ray_parametric_surface ps = wave_surface();
    ray_blob blob = {{0, 0, 0}, 1, 1};
    ray_blobs_params bp;
    ray_implicit_surface out, keep;
    ray_ray r;
    ray_hit h, hkeep;
    int how;

    r.org = vec(1.5, 1.5, 5);
    r.dir = vec(0, 0, -1);
    r.tmin = 0;
    r.tmax = HUGE_VAL;
    ck_assert_int_eq(ray_parametric(&r, &ps, &h), 1);
    ck_assert_double_eq_tol(h.t, 5 - 0.2 * sin(1.5) * cos(1.5), 1e-9);
    memset(&hkeep, 0x5a, sizeof hkeep);
    ps.bounds = bad_sub_bounds;
    ps.ud = &how;
    for (how = 0; how < 3; how++) {
        h = hkeep;
        ck_assert_int_eq(ray_parametric(&r, &ps, &h), -RAY_EINVAL);
        ck_assert(memcmp(&h, &hkeep, sizeof h) == 0);
    }
    /* A domain whose width overflows, in u, then in v: not finite. */
    ps = wave_surface();
    ps.u0 = -DBL_MAX, ps.u1 = DBL_MAX;
    ck_assert_int_eq(ray_parametric(&r, &ps, &h), -RAY_EINVAL);
    ps = wave_surface();
    ps.v0 = -DBL_MAX, ps.v1 = DBL_MAX;
    ck_assert_int_eq(ray_parametric(&r, &ps, &h), -RAY_EINVAL);
    ck_assert(memcmp(&h, &hkeep, sizeof h) == 0);
    bp.blobs = &blob;
    bp.count = 1;
    bp.threshold = 0.5;
    ck_assert_int_eq(ray_implicit_blobs(&bp, &out), RAY_OK);
    memset(&keep, 0x5a, sizeof keep);
    out = keep;
    bp.threshold = HUGE_VAL;
    ck_assert_int_eq(ray_implicit_blobs(&bp, &out), RAY_EINVAL);
    bp.threshold = 0.5;
    blob.radius = HUGE_VAL;
    ck_assert_int_eq(ray_implicit_blobs(&bp, &out), RAY_EINVAL);
    blob.radius = 1, blob.strength = (double)NAN;
    ck_assert_int_eq(ray_implicit_blobs(&bp, &out), RAY_EINVAL);
    blob.strength = 1, blob.center = vec(1e308, 0, 0), blob.radius = 1e308;
    ck_assert_int_eq(ray_implicit_blobs(&bp, &out), RAY_EINVAL);
    blob.center = vec(0, 0, 0), blob.radius = 1e-300, blob.strength = 1e308;
    ck_assert_int_eq(ray_implicit_blobs(&bp, &out), RAY_EINVAL);
    ck_assert(memcmp(&out, &keep, sizeof out) == 0);
}
END_TEST

/*
** A scene of a torus, metaballs, a wave and many Bezier domes (enough
** for the BVH to have inner nodes) answers every random ray exactly as
** the nearest of the bare functions' hits: same geom_id, bit-identical t
** (the same function on the same ray, with tmax only shrunk past hits
** that are farther).  Any-hit agrees with it.
*/
START_TEST(scene_should_find_what_the_bare_functions_find)
{
    ray_scene *s = new_scene();
    ray_torus_params t = {{0, 0, 2}, {0.2, 0, 1}, 1.5, 0.4};
    ray_blob blobs[3] = {{{4, 4, 1}, 1.2, 1}, {{5, 4, 1}, 1.0, 1},
                         {{4.5, 5, 1.5}, 0.9, 1}};
    ray_blobs_params bp;
    ray_implicit_surface is;
    ray_parametric_surface ps = wave_surface(), bez[16];
    ray_vec3 cp[16][16];
    rng g = {123};
    int n, k, hits = 0;

    bp.blobs = blobs;
    bp.count = 3;
    bp.threshold = 0.3;
    ck_assert_int_eq(ray_implicit_blobs(&bp, &is), RAY_OK);
    ck_assert_int_eq(ray_scene_add_torus(s, &t, 0, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_implicit(s, &is, 0, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_parametric(s, &ps, 0, NULL), RAY_OK);
    for (k = 0; k < 16; k++) {
        dome(cp[k], -6 + 3 * (k % 4), -6 + 3 * (k / 4), -1 - 0.1 * k);
        ck_assert_int_eq(ray_scene_add_bezier(s, cp[k], 0, NULL), RAY_OK);
        ck_assert_int_eq(ray_bezier_surface(cp[k], &bez[k]), RAY_OK);
    }
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    for (n = 0; n < 3000; n++) {
        ray_vec3 o = vec(rng_range(&g, -7, 7), rng_range(&g, -7, 7), 8);
        ray_vec3 aim = vec(rng_range(&g, -7, 7), rng_range(&g, -7, 7), -2);
        ray_ray r = ray_from(o, vsub(aim, o));
        ray_hit h, best;
        unsigned best_id = RAY_INVALID_ID;
        int got;
        best.t = HUGE_VAL;
        if (ray_torus(&r, &t, &h) == 1 && h.t < best.t) {
            best = h;
            best_id = 0;
        }
        if (ray_implicit(&r, &is, &h) == 1 && h.t < best.t) {
            best = h;
            best_id = 1;
        }
        if (ray_parametric(&r, &ps, &h) == 1 && h.t < best.t) {
            best = h;
            best_id = 2;
        }
        for (k = 0; k < 16; k++)
            if (ray_parametric(&r, &bez[k], &h) == 1 && h.t < best.t) {
                best = h;
                best_id = 3 + (unsigned)k;
            }
        got = ray_intersect(s, &r, &h, NULL);
        ck_assert_int_eq(got, best_id != RAY_INVALID_ID);
        ck_assert_int_eq(ray_occluded(s, &r, NULL), got);
        if (!got)
            continue;
        hits++;
        ck_assert_uint_eq(h.geom_id, best_id);
        /* The scene's call shrinks tmax past farther hits first, which
        ** may change where a march or a Newton start begins: the root is
        ** the same to the surfaces' tolerances (~1e-8 here). */
        ck_assert_double_eq_tol(h.t, best.t, 1e-7);
    }
    ck_assert_int_gt(hits, 1000);
    ray_scene_free(s);
}
END_TEST

/*
** An implicit surface given too few evaluations fails on every ray that
** reaches its tube (a ray through the hole can leave the box within two
** evaluations, a true miss): the scene takes each failure as a miss (the background)
** and counts it in root_failures, with one RAY_PRIM_IMPLICIT test per
** ray that enters its box.
*/
START_TEST(scene_should_count_root_failures_as_misses)
{
    ray_scene *s = new_scene();
    ray_torus_params t = {{0, 0, 0}, {0, 0, 1}, 1.0, 0.3};
    ray_implicit_surface is;
    ray_ctx *ctx;
    ray_stats st;
    ray_rgb c;
    int n;

    ck_assert_int_eq(ray__implicit_torus(&t, &is), RAY_OK);
    is.max_iterations = 2;
    ck_assert_int_eq(ray_scene_add_implicit(s, &is, 0, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_set_background(s, rgb(0.25, 0, 0), NULL, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(s, 1, &ctx), RAY_OK);
    for (n = 0; n < 10; n++) {
        /* Over the tube (|x| in [0.8, 1.16]), not through the hole. */
        double x = (n % 2 ? 1 : -1) * (0.8 + 0.04 * n);
        ray_ray r = ray_from(vec(x, 0.1, 5), vec(0, 0, -1));
        ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1.0, &c),
                         RAY_OK);
        ck_assert_double_eq(c.r, 0.25);
    }
    ray_ctx_stats(ctx, &st);
    ck_assert_uint_eq(st.tests_by_kind[RAY_PRIM_IMPLICIT], 10);
    ck_assert_uint_eq(st.root_failures, 10);
    ray_ctx_free(ctx);
    ray_scene_free(s);
}
END_TEST

Suite *surfaces_suite(void)
{
    Suite *s = suite_create("surfaces");
    TCase *core = tcase_create("core");

    tcase_set_timeout(core, 60);
    tcase_add_test(core, scene_should_reject_bad_surfaces_and_add_nothing);
    tcase_add_test(core, scene_should_name_what_is_wrong_with_a_surface);
    tcase_add_test(core, broken_callbacks_and_blobs_should_be_refused);
    tcase_add_test(core, scene_should_find_what_the_bare_functions_find);
    tcase_add_test(core, scene_should_count_root_failures_as_misses);
    suite_add_tcase(s, core);
    return s;
}
