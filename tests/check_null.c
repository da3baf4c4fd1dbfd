/* SPDX-License-Identifier: MIT */
/*
** check_null.c -- one rule for NULL, tested on every public function
** (ray(7), "NULL arguments"): a NULL where an object is required is never
** a crash and never a write.  A function returning a status returns
** RAY_EINVAL; an intersection function returns 0 (a miss), or
** -RAY_EINVAL where it can report misuse (the scene queries, the
** iterative surfaces); a void function does nothing; a query of a
** property returns its neutral value (0, or a fixed string).  Optional
** outputs documented as "may be NULL" are skipped.  Each call runs in the
** suite's forked process, so a crash fails the test rather than the run.
*/
#include <stdlib.h>
#include <string.h>

#include "prim/prim.h"         /* ray__implicit_torus */
#include "tests.h"

#ifndef RAY_TEST_PNG
#define RAY_TEST_PNG 1
#endif
#if !RAY_TEST_PNG
#include "image/image.h"
#endif

static ray_ray a_ray(void)
{
    ray_ray r;
    r.org = vec(0, 0, 5);
    r.dir = vec(0, 0, -1);
    r.tmin = 0;
    r.tmax = HUGE_VAL;
    return r;
}

/* A committed scene with one sphere and one point light. */
static ray_scene *a_scene(void)
{
    ray_material m = plain();
    ray_light l;
    ray_scene *s;

    memset(&l, 0, sizeof l);
    l.kind = RAY_LIGHT_POINT;
    l.position = vec(0, 5, 0);
    l.intensity.r = l.intensity.g = l.intensity.b = 1;
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1, 0, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    return s;
}

START_TEST(primitives_should_miss_on_null)
{
    ray_ray r = a_ray();
    ray_hit h;
    ray_vec3 poly[3], a = vec(-1, -1, 0), b = vec(1, -1, 0), c = vec(0, 1, 0);
    ray_torus_params tp;
    ray_implicit_surface is;
    ray_parametric_surface ps;
    ray_vec3 cp[16];
    double abg[3];
    int i;

    poly[0] = a, poly[1] = b, poly[2] = c;
    tp.center = vec(0, 0, 0), tp.axis = vec(0, 0, 1);
    tp.major = 1, tp.minor = 0.25;
    for (i = 0; i < 16; i++)
        cp[i] = vec(i % 4, i / 4, 0);
    ck_assert_int_eq(ray__implicit_torus(&tp, &is), RAY_OK);
    ck_assert_int_eq(ray_bezier_surface(cp, &ps), RAY_OK);

    ck_assert_int_eq(ray_sphere(NULL, vec(0, 0, 0), 1, &h), 0);
    ck_assert_int_eq(ray_sphere(&r, vec(0, 0, 0), 1, NULL), 0);
    ck_assert_int_eq(ray_triangle(NULL, a, b, c, &h), 0);
    ck_assert_int_eq(ray_triangle(&r, a, b, c, NULL), 0);
    ck_assert_int_eq(ray_triangle_watertight(NULL, a, b, c, &h), 0);
    ck_assert_int_eq(ray_triangle_watertight(&r, a, b, c, NULL), 0);
    ck_assert_int_eq(ray_plane(NULL, vec(0, 0, 0), vec(0, 0, 1), &h), 0);
    ck_assert_int_eq(ray_plane(&r, vec(0, 0, 0), vec(0, 0, 1), NULL), 0);
    ck_assert_int_eq(ray_polygon(NULL, poly, 3, &h), 0);
    ck_assert_int_eq(ray_polygon(&r, NULL, 3, &h), 0);
    ck_assert_int_eq(ray_polygon(&r, poly, 3, NULL), 0);
    ck_assert_int_eq(ray_torus(NULL, &tp, &h), 0);
    ck_assert_int_eq(ray_torus(&r, NULL, &h), 0);
    ck_assert_int_eq(ray_torus(&r, &tp, NULL), 0);
    ck_assert_int_eq(ray_implicit(NULL, &is, &h), -RAY_EINVAL);
    ck_assert_int_eq(ray_implicit(&r, NULL, &h), -RAY_EINVAL);
    ck_assert_int_eq(ray_implicit(&r, &is, NULL), -RAY_EINVAL);
    ck_assert_int_eq(ray_parametric(NULL, &ps, &h), -RAY_EINVAL);
    ck_assert_int_eq(ray_parametric(&r, NULL, &h), -RAY_EINVAL);
    ck_assert_int_eq(ray_parametric(&r, &ps, NULL), -RAY_EINVAL);
    ck_assert_int_eq(ray_barycentric(a, a, b, c, NULL, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_barycentric(a, a, b, c, abg, NULL), RAY_OK);
    ck_assert_int_eq(ray__implicit_torus(NULL, &is), RAY_EINVAL);
    ck_assert_int_eq(ray__implicit_torus(&tp, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_implicit_blobs(NULL, &is), RAY_EINVAL);
    ck_assert_int_eq(ray_bezier_surface(NULL, &ps), RAY_EINVAL);
    ck_assert_int_eq(ray_bezier_surface(cp, NULL), RAY_EINVAL);
}
END_TEST

/*
** Issue 38: the primitive functions miss (0; ray_implicit and
** ray_parametric -RAY_EINVAL, "invalid params" in ray.h), *hit untouched,
** on parameters their pages call invalid, each field in turn, where the
** same ray hits the valid shape: a torus with an infinite major radius,
** a minor radius not below the major, or radii whose error bound
** 2 (R + r) overflows, and a ray with tmin >= tmax or a direction whose
** length overflows; an implicit surface's box with lo > hi in y or z or
** a corner not finite, a lipschitz bound, step or tolerance infinite or
** negative; a box's half extent in y or z zero or infinite, or beyond
** 2^1021, or its y axis parallel to x; a sphere of infinite radius or a
** zero direction; a parametric surface with a negative tolerance or an
** empty domain.
*/
START_TEST(primitives_should_miss_on_invalid_parameters)
{
    ray_ray r = a_ray(), rt = a_ray();
    ray_hit h, keep;
    ray_torus_params tp, t;
    ray_implicit_surface i0, is;
    ray_box_params b0, b;
    ray_parametric_surface p0, ps;
    ray_vec3 cp[16];
    int k;

    memset(&keep, 0x5a, sizeof keep);
    h = keep;
    rt.org = vec(1, 0, 5);               /* over the tube, not the hole */
    tp.center = vec(0, 0, 0), tp.axis = vec(0, 0, 1);
    tp.major = 1, tp.minor = 0.25;
    ck_assert_int_eq(ray__implicit_torus(&tp, &i0), RAY_OK);
    b0.center = vec(0, 0, 0), b0.half_extents = vec(1, 1, 1);
    b0.axis_x = vec(1, 0, 0), b0.axis_y = vec(0, 1, 0);
    for (k = 0; k < 16; k++)
        cp[k] = vec(k % 4 - 1.5, k / 4 - 1.5, 0);
    ck_assert_int_eq(ray_bezier_surface(cp, &p0), RAY_OK);
    /* The valid ones hit. */
    ck_assert_int_eq(ray_torus(&rt, &tp, &h), 1);
    ck_assert_int_eq(ray_implicit(&rt, &i0, &h), 1);
    ck_assert_int_eq(ray_box(&r, &b0, &h), 1);
    ck_assert_int_eq(ray_sphere(&r, vec(0, 0, 0), 1, &h), 1);
    ck_assert_int_eq(ray_parametric(&r, &p0, &h), 1);
    h = keep;
#define MISSES(call, rc)                                 \
    do {                                                 \
        ck_assert_int_eq(call, rc);                      \
        ck_assert(memcmp(&h, &keep, sizeof h) == 0);     \
    } while (0)
    t = tp, t.major = HUGE_VAL;
    MISSES(ray_torus(&rt, &t, &h), 0);
    t = tp, t.minor = 1;
    MISSES(ray_torus(&rt, &t, &h), 0);
    t = tp, t.major = 1e308, t.minor = 0.9e308;
    MISSES(ray_torus(&rt, &t, &h), 0);
    r.tmin = 1, r.tmax = 1;
    MISSES(ray_torus(&r, &tp, &h), 0);
    r = a_ray(), r.org = vec(1, 0, 5), r.dir = vec(0, DBL_MAX, -DBL_MAX);
    MISSES(ray_torus(&r, &tp, &h), 0);
    r = a_ray();
    is = i0, is.lo.y = is.hi.y + 1;
    MISSES(ray_implicit(&rt, &is, &h), -RAY_EINVAL);
    is = i0, is.lo.z = is.hi.z + 1;
    MISSES(ray_implicit(&rt, &is, &h), -RAY_EINVAL);
    is = i0, is.hi.x = (double)NAN;
    MISSES(ray_implicit(&rt, &is, &h), -RAY_EINVAL);
    is = i0, is.lipschitz = HUGE_VAL;
    MISSES(ray_implicit(&rt, &is, &h), -RAY_EINVAL);
    is = i0, is.step = -1;
    MISSES(ray_implicit(&rt, &is, &h), -RAY_EINVAL);
    is = i0, is.step = HUGE_VAL;
    MISSES(ray_implicit(&rt, &is, &h), -RAY_EINVAL);
    is = i0, is.tolerance = HUGE_VAL;
    MISSES(ray_implicit(&rt, &is, &h), -RAY_EINVAL);
    b = b0, b.half_extents.y = 0;
    MISSES(ray_box(&r, &b, &h), 0);
    b = b0, b.half_extents.y = HUGE_VAL;
    MISSES(ray_box(&r, &b, &h), 0);
    b = b0, b.half_extents.z = 0;
    MISSES(ray_box(&r, &b, &h), 0);
    b = b0, b.half_extents.z = HUGE_VAL;
    MISSES(ray_box(&r, &b, &h), 0);
    b = b0, b.half_extents.z = 0x1p1022;
    MISSES(ray_box(&r, &b, &h), 0);
    b = b0, b.half_extents.y = 0x1p1022;
    MISSES(ray_box(&r, &b, &h), 0);
    b = b0, b.axis_y = vec(-2, 0, 0);
    MISSES(ray_box(&r, &b, &h), 0);
    MISSES(ray_sphere(&r, vec(0, 0, 0), HUGE_VAL, &h), 0);
    r.dir = vec(0, 0, 0);
    MISSES(ray_sphere(&r, vec(0, 0, 0), 1, &h), 0);
    r = a_ray();
    ps = p0, ps.tolerance = -1;
    MISSES(ray_parametric(&r, &ps, &h), -RAY_EINVAL);
    ps = p0, ps.u0 = 1, ps.u1 = 1, ps.v0 = 0, ps.v1 = 1;
    MISSES(ray_parametric(&r, &ps, &h), -RAY_EINVAL);
    ps = p0, ps.u0 = 0, ps.u1 = 1, ps.v0 = 0, ps.v1 = -1;
    MISSES(ray_parametric(&r, &ps, &h), -RAY_EINVAL);
#undef MISSES
}
END_TEST

START_TEST(spawn_and_optics_should_refuse_null)
{
    ray_ray r = a_ray(), out;
    ray_hit h;
    ray_vec3 t;

    ck_assert_int_eq(ray_sphere(&r, vec(0, 0, 0), 1, &h), 1);
    ck_assert_int_eq(ray_spawn(NULL, vec(0, 0, 1), &out), RAY_EINVAL);
    ck_assert_int_eq(ray_spawn(&h, vec(0, 0, 1), NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_spawn_to(NULL, vec(0, 0, 9), &out), RAY_EINVAL);
    ck_assert_int_eq(ray_spawn_to(&h, vec(0, 0, 9), NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_refract(vec(0, 0, -1), vec(0, 0, 1), 1.5, NULL), 0);
    ck_assert_int_eq(ray_refract(vec(0, 0, -1), vec(0, 0, 1), 1.5, &t), 1);
}
END_TEST

/* A background function that leaves the preset colour. */
static void null_sky(void *ud, const ray_ray *r, ray_rgb *out)
{
    (void)ud;
    (void)r;
    (void)out;
}

/* The default tree limits in the naive mode (ray_limits.no_pruning). */
static const ray_limits naive_limits = {.max_depth = RAY_DEFAULT_MAX_DEPTH,
                                        .min_weight = RAY_DEFAULT_MIN_WEIGHT,
                                        .max_fanout = RAY_DEFAULT_MAX_FANOUT,
                                        .no_pruning = 1};

START_TEST(scene_calls_should_refuse_null)
{
    ray_scene *s = NULL;
    ray_material m = plain();
    ray_light l;
    ray_mesh mesh;
    ray_torus_params tp;
    ray_implicit_surface is;
    ray_parametric_surface ps;
    ray_vec3 cp[16];
    ray_ray r = a_ray();
    ray_hit h;
    ray_rgb black_rgb = {0, 0, 0};
    int i;

    memset(&l, 0, sizeof l);
    memset(&mesh, 0, sizeof mesh);
    tp.center = vec(0, 0, 0), tp.axis = vec(0, 0, 1);
    tp.major = 1, tp.minor = 0.25;
    for (i = 0; i < 16; i++)
        cp[i] = vec(i % 4, i / 4, 0);
    ck_assert_int_eq(ray__implicit_torus(&tp, &is), RAY_OK);
    ck_assert_int_eq(ray_bezier_surface(cp, &ps), RAY_OK);
    ck_assert_int_eq(ray_scene_new(NULL, NULL, NULL), RAY_EINVAL);
    ray_scene_free(NULL);
    ck_assert_int_eq(ray_scene_add_material(NULL, &m, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_sphere(NULL, vec(0, 0, 0), 1, 0, NULL),
                     RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_plane(NULL, vec(0, 0, 0), vec(0, 0, 1), 0,
                                         NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_triangle(NULL, vec(0, 0, 0), vec(1, 0, 0),
                                            vec(0, 1, 0), 0, NULL),
                     RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_polygon(NULL, cp, 3, 0, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_mesh(NULL, &mesh, 0, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_implicit(NULL, &is, 0, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_torus(NULL, &tp, 0, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_parametric(NULL, &ps, 0, NULL),
                     RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_bezier(NULL, cp, 0, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_light(NULL, &l, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_set_background(NULL, black_rgb, NULL, NULL),
                     RAY_EINVAL);
    ck_assert_int_eq(ray_scene_set_background(NULL, black_rgb, null_sky, NULL),
                     RAY_EINVAL);
    ck_assert_int_eq(ray_scene_set_ambient(NULL, black_rgb), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_set_limits(NULL, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_set_limits(NULL, &naive_limits), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_set_watertight(NULL, 1), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_set_build_threads(NULL, 2), RAY_EINVAL);
    ck_assert_uint_eq(ray_scene_effects(NULL), 0);
    ck_assert_uint_eq(ray_scene_light_count(NULL), 0);
    ck_assert_uint_eq(ray_light_samples(NULL, 0), 0);
    ck_assert_int_eq(ray_scene_commit(NULL), RAY_EINVAL);
    ck_assert_str_eq(ray_scene_errmsg(NULL), "no scene (NULL)");
    ck_assert_int_eq(ray_intersect(NULL, &r, &h, NULL), -RAY_EINVAL);
    ck_assert_int_eq(ray_occluded(NULL, &r, NULL), -RAY_EINVAL);
    {
        ray_closest c;
        memset(&c, 0xA5, sizeof c);
        ck_assert_int_eq(ray_closest_point(NULL, r.org, 1, &c), -RAY_EINVAL);
        ck_assert_uint_eq(c.geom_id, 0xA5A5A5A5u);
    }

    /* NULL inner arguments on a real scene. */
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, NULL, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_polygon(s, NULL, 3, 0, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_mesh(s, NULL, 0, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_implicit(s, NULL, 0, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_torus(s, NULL, 0, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_parametric(s, NULL, 0, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_bezier(s, NULL, 0, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_light(s, NULL, NULL), RAY_EINVAL);
    ray_scene_free(s);
    s = a_scene();
    ck_assert_int_eq(ray_intersect(s, NULL, &h, NULL), -RAY_EINVAL);
    ck_assert_int_eq(ray_intersect(s, &r, NULL, NULL), -RAY_EINVAL);
    ck_assert_int_eq(ray_occluded(s, NULL, NULL), -RAY_EINVAL);
    ck_assert_int_eq(ray_closest_point(s, r.org, HUGE_VAL, NULL), -RAY_EINVAL);
    ray_scene_free(s);
}
END_TEST

/*
** The games-and-tools calls: instances, updates, masks, filters, user
** geometry, queries with options (a NULL ray_query is documented as the
** defaults, so it is a valid call, not refused).
*/
START_TEST(live_scene_calls_should_refuse_null)
{
    ray_scene *s = a_scene(), *top;
    ray_transform xf;
    ray_ray r = a_ray();
    ray_hit h;
    size_t count = 77;
    unsigned id = 77;

    ray_transform_identity(NULL);                  /* a no-op */
    ray_transform_identity(&xf);
    ck_assert_int_eq(ray_scene_new(&top, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_instance(NULL, s, &xf, &id), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_instance(top, NULL, &xf, &id), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_instance(top, s, NULL, &id), RAY_EINVAL);
    ck_assert_uint_eq(id, 77);
    ck_assert_int_eq(ray_scene_add_instance(top, s, &xf, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_set_transform(NULL, 0, &xf), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_set_transform(top, 0, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_update_mesh(NULL, 0, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_set_enabled(NULL, 0, 1), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_remove(NULL, 0), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_set_mask(NULL, 0, 1), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_set_filter(NULL, 0, NULL, NULL, 0), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_user(NULL, NULL, 0, &id), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_user(top, NULL, 0, &id), RAY_EINVAL);
    ck_assert_uint_eq(id, 77);
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    ck_assert_int_eq(ray_intersect(NULL, &r, &h, NULL), -RAY_EINVAL);
    ck_assert_int_eq(ray_intersect(top, NULL, &h, NULL), -RAY_EINVAL);
    ck_assert_int_eq(ray_intersect(top, &r, NULL, NULL), -RAY_EINVAL);
    ck_assert_int_eq(ray_occluded(NULL, &r, NULL), -RAY_EINVAL);
    ck_assert_int_eq(ray_occluded(top, NULL, NULL), -RAY_EINVAL);
    ck_assert_int_eq(ray_intersect_all(NULL, &r, NULL, &h, 1, &count), -RAY_EINVAL);
    ck_assert_int_eq(ray_intersect_all(top, NULL, NULL, &h, 1, &count), -RAY_EINVAL);
    ck_assert_int_eq(ray_intersect_all(top, &r, NULL, &h, 1, NULL), -RAY_EINVAL);
    ck_assert_int_eq(ray_intersect_all(top, &r, NULL, NULL, 1, &count), -RAY_EINVAL);
    ck_assert_uint_eq(count, 77);
    /* NULL options: the defaults, the plain query's answer. */
    ck_assert_int_eq(ray_intersect(top, &r, &h, NULL), 1);
    ck_assert_int_eq(ray_occluded(top, &r, NULL), 1);
    ck_assert_int_eq(ray_intersect_all(top, &r, NULL, &h, 1, &count), 2);
    ray_scene_free(top);
    ray_scene_free(s);
}
END_TEST

/* A material that calls the in-callback functions with NULLs and records
** whether each refused as documented. */
typedef struct null_probe {
    int calls, ok;
} null_probe;

static void probe_shade(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                        ray_rgb *out)
{
    null_probe *p = ud;
    ray_light_sample ls;
    ray_ray r = a_ray();
    ray_rgb c;
    int ok = 1;

    ok &= ray_light_sample_at(NULL, a, 0, 0, &ls) == RAY_EINVAL;
    ok &= ray_light_sample_at(ctx, NULL, 0, 0, &ls) == RAY_EINVAL;
    ok &= ray_light_sample_at(ctx, a, 0, 0, NULL) == RAY_EINVAL;
    if (ray_light_sample_at(ctx, a, 0, 0, &ls) == RAY_OK) {
        ok &= ray_light_visible(NULL, a, &ls) == 0;
        ok &= ray_light_visible(ctx, NULL, &ls) == 0;
    }
    ok &= ray_light_visible(ctx, a, NULL) == 0;
    ok &= ray_trace(NULL, &r, RAY_KIND_REFLECTION, 1, &c) == RAY_EINVAL;
    ok &= ray_trace(ctx, NULL, RAY_KIND_REFLECTION, 1, &c) == RAY_EINVAL;
    ok &= ray_trace(ctx, &r, RAY_KIND_REFLECTION, 1, NULL) == RAY_EINVAL;
    p->calls++;
    p->ok += ok;
    out->r = out->g = out->b = 0;
}

START_TEST(context_and_render_calls_should_refuse_null)
{
    ray_scene *s;
    ray_ctx *ctx = NULL;
    ray_stats st;
    ray_camera cam;
    ray_render_options o;
    ray_ray r = a_ray();
    ray_rgb c;
    float img[3 * 4 * 4];
    unsigned char bytes[3];
    null_probe probe = {0, 0};
    ray_material m;
    ray_light l;

    m.shade = probe_shade, m.ud = &probe, m.effects = RAY_EFFECT_SHADOW;
    m.scatter = NULL;
    memset(&l, 0, sizeof l);
    l.kind = RAY_LIGHT_POINT;
    l.position = vec(0, 5, 5);
    l.intensity.r = l.intensity.g = l.intensity.b = 1;
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1, 0, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);

    ck_assert_int_eq(ray_ctx_new(NULL, 1, &ctx), RAY_EINVAL);
    ck_assert_int_eq(ray_ctx_new(s, 1, NULL), RAY_EINVAL);
    ray_ctx_free(NULL);
    memset(&st, 0x5a, sizeof st);
    ray_ctx_stats(NULL, &st);
    ck_assert_uint_eq(((unsigned char *)&st)[0], 0x5a);   /* untouched */
    ck_assert_int_eq(ray_ctx_new(s, 1, &ctx), RAY_OK);
    ray_ctx_stats(ctx, NULL);
    ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1, &c), RAY_OK);
    ck_assert_int_gt(probe.calls, 0);
    ck_assert_int_eq(probe.ok, probe.calls);
    ck_assert(ray_ctx_random(NULL) == 0);
    ray_ctx_free(ctx);

    memset(&cam, 0, sizeof cam);
    cam.position = vec(0, 0, 5), cam.look_at = vec(0, 0, 0);
    cam.up = vec(0, 1, 0), cam.vfov = 40;
    o = (ray_render_options){.width = 4, .height = 4};
    /* One thread: the probe material counts into one struct, and render
    ** threads would update it concurrently (a data race TSan reports). */
    o.threads = 1;
    ck_assert_int_eq(ray_render(NULL, &cam, &o, img, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_render(s, NULL, &o, img, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_render(s, &cam, NULL, img, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_render(s, &cam, &o, NULL, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_render(s, &cam, &o, img, NULL), RAY_OK);
    {
        char why[64];
        ck_assert_int_eq(ray_render_check(NULL, &cam, &o, NULL, why, sizeof why),
                         RAY_EINVAL);
        ck_assert_str_eq(why, "ray_render: scene is NULL");
        ck_assert_int_eq(ray_render_check(s, &cam, NULL, NULL, why, sizeof why),
                         RAY_EINVAL);
        ck_assert_str_eq(why, "ray_render: options is NULL");
        ck_assert_int_eq(ray_render_check(NULL, NULL, NULL, NULL, NULL, 0),
                         RAY_EINVAL);
        ck_assert_int_eq(ray_render_check(s, &cam, &o, NULL, NULL, 0), RAY_OK);
    }
    ray_scene_free(s);

    ck_assert_int_eq(ray_image_to_srgb8(NULL, 1, bytes), RAY_EINVAL);
    ck_assert_int_eq(ray_image_to_srgb8(img, 1, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_write_png(NULL, img, 4, 4, 8), RAY_EINVAL);
    ck_assert_int_eq(ray_write_png("build/null.png", NULL, 4, 4, 8),
                     RAY_EINVAL);
    ck_assert_ptr_nonnull(ray_strerror(RAY_EINVAL));
    ck_assert_ptr_nonnull(ray_version_string());
}
END_TEST

START_TEST(image_calls_should_refuse_null)
{
    ray_image *img = NULL;
    unsigned w = 7, h = 7;
    ray_rgb c;
    ray_texture t;

    ck_assert_int_eq(ray_image_load_png(NULL, NULL, &img), RAY_EINVAL);
    ck_assert_int_eq(ray_image_load_png("doc/cornell.png", NULL, NULL), RAY_EINVAL);
    ray_image_free(NULL);
    ray_image_size(NULL, &w, &h);
    ck_assert_uint_eq(w, 7);          /* no image: nothing written */
    ck_assert_uint_eq(h, 7);
    ck_assert_int_eq(ray_image_sample(NULL, 0.5, 0.5, 0, &c), RAY_EINVAL);
#if RAY_TEST_PNG
    ck_assert_int_eq(ray_image_load_png("doc/cornell.png", NULL, &img), RAY_OK);
#else
    /* No libpng (make PNG=0): an image made as the loader makes them. */
    ck_assert_int_eq(ray_image_load_png("doc/cornell.png", NULL, &img), RAY_ENOTSUP);
    img = ray__image_new(1, 1, calloc(3, sizeof(float)));
    ck_assert_ptr_nonnull(img);
#endif
    ray_image_size(img, NULL, NULL);
    ck_assert_int_eq(ray_image_sample(img, 0.5, 0.5, 0, NULL), RAY_EINVAL);
    ray_image_free(img);
    t = ray_texture_image(NULL);
    ck_assert(t.fn == NULL);
}
END_TEST

Suite *null_suite(void)
{
    Suite *s = suite_create("null");
    TCase *tc = tcase_create("every function");

    tcase_add_test(tc, primitives_should_miss_on_null);
    tcase_add_test(tc, primitives_should_miss_on_invalid_parameters);
    tcase_add_test(tc, spawn_and_optics_should_refuse_null);
    tcase_add_test(tc, scene_calls_should_refuse_null);
    tcase_add_test(tc, live_scene_calls_should_refuse_null);
    tcase_add_test(tc, context_and_render_calls_should_refuse_null);
    tcase_add_test(tc, image_calls_should_refuse_null);
    suite_add_tcase(s, tc);
    return s;
}
