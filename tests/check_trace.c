/* SPDX-License-Identifier: MIT */
/*
** check_trace.c -- the ray tree: its limits, declared effects, built-in
** materials' optics, and shadow rays that do not hit their own surface.
*/
#include "tests.h"

#include "core/sampling.h"   /* ray__concentric_disk */

/* A scene with two facing mirror planes y = 0 and y = 1 (reflectance
** "k") and the given limits; a context traces one vertical ray. */
static ray_stats bounce_between_mirrors(double k, const ray_limits *lim)
{
    ray_rgb refl = rgb(k, k, k), c;
    ray_material m = ray_material_mirror(&refl);
    ray_scene *s;
    ray_ctx *ctx;
    ray_stats st;
    ray_ray r = ray_from(vec(0, 0.5, 0), vec(0.001, 1, 0));
    unsigned mat;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, &mat), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 1, 0), mat, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 1, 0), vec(0, -1, 0), mat, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_set_limits(s, lim), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(s, 1, &ctx), RAY_OK);
    ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1.0, &c), RAY_OK);
    ray_ctx_stats(ctx, &st);
    ray_ctx_free(ctx);
    ray_scene_free(s);
    return st;
}

START_TEST(trace_should_stop_facing_mirrors_at_max_depth)
{
    ray_limits lim = {.max_depth = 5, .min_weight = 0.0,
                      .max_fanout = 2};
    ray_stats st = bounce_between_mirrors(1.0, &lim);

    ck_assert_uint_eq(st.rays[RAY_KIND_PRIMARY], 1);
    ck_assert_uint_eq(st.rays[RAY_KIND_REFLECTION], 5);
    ck_assert_uint_eq(st.cut_depth, 1);
    ck_assert_uint_eq(st.max_depth, 5);
    ck_assert_uint_eq(st.tests, 6 * 2);      /* 6 rays x 2 planes */
}
END_TEST

/* Reflectance 0.5 with min_weight 0.1: path weights 0.5, 0.25, 0.125
** are traced, 0.0625 is cut (Hall and Greenberg's adaptive depth). */
/* The deepest tree allowed really is traced (no stack trouble), and one
** level more is refused when set. */
START_TEST(trace_should_allow_max_depth_and_refuse_more)
{
    ray_limits lim = {.max_depth = RAY_MAX_DEPTH, .min_weight = 0.0,
                      .max_fanout = 2};
    ray_stats st = bounce_between_mirrors(1.0, &lim);
    ray_scene *s;

    ck_assert_uint_eq(st.rays[RAY_KIND_REFLECTION], RAY_MAX_DEPTH);
    ck_assert_uint_eq(st.max_depth, RAY_MAX_DEPTH);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    lim.max_depth = RAY_MAX_DEPTH + 1;
    ck_assert_int_eq(ray_scene_set_limits(s, &lim), RAY_EINVAL);
    lim.max_depth = 0;
    ck_assert_int_eq(ray_scene_set_limits(s, &lim), RAY_OK);
    ray_scene_free(s);
}
END_TEST

START_TEST(trace_should_cut_by_weight)
{
    ray_limits lim = {.max_depth = RAY_MAX_DEPTH, .min_weight = 0.1,
                      .max_fanout = 2};
    ray_stats st = bounce_between_mirrors(0.5, &lim);

    ck_assert_uint_eq(st.rays[RAY_KIND_REFLECTION], 3);
    ck_assert_uint_eq(st.cut_weight, 1);
    ck_assert_uint_eq(st.cut_depth, 0);
}
END_TEST

/* A material that tries three reflections, and records the results. */
typedef struct greedy {
    int results[3];
} greedy;

static void greedy_shade(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                         ray_rgb *out)
{
    greedy *g = ud;
    ray_ray r;
    ray_rgb c;
    int i;

    (void)out;
    if (a->depth > 0)
        return;
    ck_assert_int_eq(ray_spawn(a->hit, vec(0, 0, 1), &r), RAY_OK);
    for (i = 0; i < 3; i++)
        g->results[i] = ray_trace(ctx, &r, RAY_KIND_REFLECTION, 0.5, &c);
}

static ray_stats run_greedy(unsigned effects, greedy *g)
{
    ray_material m;
    ray_scene *s;
    ray_ctx *ctx;
    ray_stats st;
    ray_ray r = ray_from(vec(0, 0, 5), vec(0, 0, -1));
    ray_rgb c;
    unsigned mat;

    m.shade = greedy_shade;
    m.ud = g;
    m.effects = effects;
    m.scatter = NULL;
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, &mat), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 0, 1), mat, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(s, 1, &ctx), RAY_OK);
    ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1.0, &c), RAY_OK);
    /* Outside a callback only primary rays may be traced. */
    ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_REFLECTION, 1.0, &c), RAY_EINVAL);
    ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_COUNT, 1.0, &c), RAY_EINVAL);
    ray_ctx_stats(ctx, &st);
    ray_ctx_free(ctx);
    ray_scene_free(s);
    return st;
}

START_TEST(trace_should_limit_fanout)
{
    greedy g;
    ray_stats st = run_greedy(RAY_EFFECT_REFLECTION, &g);

    ck_assert_int_eq(g.results[0], RAY_OK);
    ck_assert_int_eq(g.results[1], RAY_OK);
    ck_assert_int_eq(g.results[2], RAY_ELIMIT);
    ck_assert_uint_eq(st.rays[RAY_KIND_REFLECTION], 2);
    ck_assert_uint_eq(st.cut_fanout, 1);
}
END_TEST

START_TEST(trace_should_refuse_undeclared_effects)
{
    greedy g;
    ray_stats st = run_greedy(RAY_EFFECT_REFRACTION, &g);

    ck_assert_int_eq(g.results[0], RAY_EEFFECT);
    ck_assert_uint_eq(st.rays[RAY_KIND_REFLECTION], 0);
    ck_assert_uint_eq(st.tests, 1);
}
END_TEST

/* Trace one ray in a scene of one unit sphere at the origin with material
** m, the given limits and a white background; returns the counters. */
static ray_stats trace_unit_sphere(ray_material m, const ray_limits *lim,
                                   ray_ray r, ray_rgb *c)
{
    ray_scene *s;
    ray_ctx *ctx;
    ray_stats st;
    unsigned mat;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, &mat), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1, mat, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_set_limits(s, lim), RAY_OK);
    ck_assert_int_eq(ray_scene_set_background(s, rgb(1, 1, 1), NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(s, 1, &ctx), RAY_OK);
    ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1.0, c), RAY_OK);
    ray_ctx_stats(ctx, &st);
    ray_ctx_free(ctx);
    ray_scene_free(s);
    return st;
}

/* Glass sphere, a ray inside it at 64 degrees from the normal (beyond the
** critical 41.8): total internal reflection at every bounce, so no
** refraction ray is ever traced and the depth limit ends the tree. */
START_TEST(glass_should_reflect_totally_inside)
{
    ray_glass_params gp = {1.5, {0, 0, 0}};
    ray_limits lim = {.max_depth = 6, .min_weight = 0.0,
                      .max_fanout = 2};
    ray_rgb c;
    ray_stats st = trace_unit_sphere(ray_material_glass(&gp), &lim,
                                     ray_from(vec(0, 0.9, 0), vec(1, 0, 0)),
                                     &c);

    ck_assert_uint_eq(st.rays[RAY_KIND_REFRACTION], 0);
    ck_assert_uint_eq(st.rays[RAY_KIND_REFLECTION], 6);
    ck_assert_uint_eq(st.cut_depth, 1);
    /* Nothing ever escapes to the white background: black. */
    ck_assert_double_eq(c.r, 0.0);
}
END_TEST

/*
** A ray from the centre of a glass sphere (normal incidence on the way
** out, ior 1.5 -> 1): Fresnel 0.04 reflected, 0.96 refracted straight out
** to a background of 1.  With depth limit 1 the reflected ray hits the
** far side but its own children are cut, so it brings back 0: 0.96.  With
** index ratio 1 the glass is invisible: exactly the background.
*/
START_TEST(glass_should_refract_from_inside)
{
    ray_glass_params gp = {1.5, {0, 0, 0}};
    ray_limits lim = {.max_depth = 1, .min_weight = 0.0,
                      .max_fanout = 2};
    ray_rgb c;
    ray_stats st;

    st = trace_unit_sphere(ray_material_glass(&gp), &lim,
                           ray_from(vec(0, 0, 0), vec(0, 0, 1)), &c);
    ck_assert_uint_eq(st.rays[RAY_KIND_REFRACTION], 1);
    ck_assert_double_eq_tol(c.g, 0.96, 1e-12);
    gp.ior = 1.0;
    st = trace_unit_sphere(ray_material_glass(&gp), &lim,
                           ray_from(vec(0, 0, 0), vec(0, 0, 1)), &c);
    ck_assert_uint_eq(st.rays[RAY_KIND_REFRACTION], 1);
    ck_assert_uint_eq(st.rays[RAY_KIND_REFLECTION], 0);   /* F = 0 */
    ck_assert_double_eq_tol(c.g, 1.0, 1e-12);
}
END_TEST

/*
** Beer-Lambert: index 1 (no bending, no reflection), absorption (1, 0.5,
** 0) per unit length, a ray through the centre of a unit sphere crosses 2
** units of glass: the white background comes back as (e^-2, e^-1, 1).
*/
START_TEST(glass_should_absorb_along_the_path)
{
    ray_glass_params gp = {1.0, {1.0, 0.5, 0.0}};
    ray_limits lim = {.max_depth = RAY_DEFAULT_MAX_DEPTH, .min_weight = RAY_DEFAULT_MIN_WEIGHT,
                      .max_fanout = 2};
    ray_rgb c;

    trace_unit_sphere(ray_material_glass(&gp), &lim,
                      ray_from(vec(0, 0, 5), vec(0, 0, -2)), &c);
    ck_assert_double_eq_tol(c.r, exp(-2.0), 1e-12);
    ck_assert_double_eq_tol(c.g, exp(-1.0), 1e-12);
    ck_assert_double_eq_tol(c.b, 1.0, 1e-12);
}
END_TEST

/*
** A ray may have any finite, non-zero direction, and the built-in
** materials must shade it as they shade the unit one: a direction of
** 1e160 or 1e-160 has |d|^2 past DBL_MAX or below DBL_MIN, which made
** glass's distance t |d| and Phong's view direction Inf or NaN (a fuzzer
** found the NaN colour).  Glass absorbs along the path through a unit
** sphere (exp(-2), exp(-1), 1 as above); Phong, lit by a point light
** beside the eye, must give the unit ray's colour.  Tolerance 1e-12
** relative: the hit point is t d, rounded differently for each scale,
** and every colour term is a smooth function of it.
*/
static ray_rgb phong_lit_sphere(ray_ray r)
{
    ray_phong_params pp = {{0.6, 0.5, 0.4}, {0.3, 0.3, 0.3}, 20, 0,
                           {0.1, 0.1, 0.1}, {NULL, NULL}};
    ray_material m = ray_material_phong(&pp);
    ray_light l = {0};
    ray_scene *s;
    ray_ctx *ctx;
    ray_rgb c;
    unsigned mat;

    l.position = vec(0.5, 0.5, 5);
    l.intensity = rgb(20, 20, 20);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, &mat), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1, mat, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(s, 1, &ctx), RAY_OK);
    ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1.0, &c), RAY_OK);
    ray_ctx_free(ctx);
    ray_scene_free(s);
    return c;
}

START_TEST(materials_should_shade_any_finite_direction)
{
    static const double scales[] = {1e-300, 1e-170, 1e-160, 1e160, 1e170,
                                    1e300};
    ray_glass_params gp = {1.0, {1.0, 0.5, 0.0}};
    ray_limits lim = {.max_depth = RAY_DEFAULT_MAX_DEPTH, .min_weight = RAY_DEFAULT_MIN_WEIGHT,
                      .max_fanout = 2};
    ray_vec3 d = vec(0.02, 0.04, -1);  /* hits at about (0.08, 0.16, 0.98) */
    ray_rgb unit_c = phong_lit_sphere(ray_from(vec(0, 0, 5), d)), c;
    size_t i;

    /* Hit and lit (the background and ambient are black): 0.73 diffuse,
    ** 0.16 highlight, which a NaN or zero view direction loses. */
    ck_assert(unit_c.r > 0.5);
    for (i = 0; i < sizeof scales / sizeof scales[0]; i++) {
        double k = scales[i];
        ray_vec3 dk = vec(d.x * k, d.y * k, d.z * k);

        trace_unit_sphere(ray_material_glass(&gp), &lim,
                          ray_from(vec(0, 0, 5), vec(0, 0, -k)), &c);
        ck_assert_double_eq_tol(c.r, exp(-2.0), 1e-12);
        ck_assert_double_eq_tol(c.g, exp(-1.0), 1e-12);
        ck_assert_double_eq_tol(c.b, 1.0, 1e-12);
        c = phong_lit_sphere(ray_from(vec(0, 0, 5), dk));
        ck_assert_double_eq_tol(c.r, unit_c.r, 1e-12 * unit_c.r);
        ck_assert_double_eq_tol(c.g, unit_c.g, 1e-12 * unit_c.g);
        ck_assert_double_eq_tol(c.b, unit_c.b, 1e-12 * unit_c.b);
    }
}
END_TEST

/*
** The furnace-like scene of robustness.md section 8: the camera inside a
** diffuse sphere (Kd = 0.5) with a point light of intensity 1 at its
** centre.  Every point sees the light at distance 1 along its normal, so
** every pixel is 0.5 * 1 * 1/1^2 = 0.5, and every shadow ray starts on the
** inside of the sphere: one blocked by its own surface (acne) would make a
** pixel black.  At the origin and 1e5 and 1e6 away.  Tolerance 1e-9: the
** sample point lies on the sphere within ~ulp(1e6) = 1.2e-10 relative.
*/
START_TEST(shadow_rays_should_not_hit_their_own_surface)
{
    static const ray_phong_params kd = {{0.5, 0.5, 0.5}, {0, 0, 0}, 1, 0,
                                        {0, 0, 0}, {NULL, NULL}};
    double offsets[] = {0.0, 1e5, 1e6};
    int k;

    for (k = 0; k < 3; k++) {
        double o = offsets[k];
        ray_material m = ray_material_phong(&kd);
        ray_light l;
        ray_camera cam;
        ray_render_options opt;
        ray_scene *s;
        ray_stats st;
        float img[3 * 31 * 31];
        unsigned mat, i;

        memset(&l, 0, sizeof l);
        l.kind = RAY_LIGHT_POINT;
        l.position = vec(o, o, o);
        l.intensity = rgb(1, 1, 1);
        memset(&cam, 0, sizeof cam);
        cam.position = vec(o + 0.3, o - 0.2, o + 0.1);
        cam.look_at = vec(o + 1, o, o);
        cam.up = vec(0, 1, 0);
        cam.vfov = 150;
        ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_material(s, &m, &mat), RAY_OK);
        ck_assert_int_eq(ray_scene_add_sphere(s, vec(o, o, o), 1, mat, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        opt = (ray_render_options){.width = 31, .height = 31};
        opt.threads = 1;
        ck_assert_int_eq(ray_render(s, &cam, &opt, img, &st), RAY_OK);
        ck_assert_uint_eq(st.rays[RAY_KIND_SHADOW], 31 * 31);
        for (i = 0; i < 3 * 31 * 31; i++)
            ck_assert_msg(fabs((double)img[i] - 0.5) < 1e-6, "offset %g: pixel %u = %g",
                          o, i / 3, (double)img[i]);
        ray_scene_free(s);
    }
}
END_TEST

/* ray_light_visible without RAY_EFFECT_SHADOW: no ray, always visible. */
static void count_visible(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                          ray_rgb *out)
{
    int *visible = ud;
    ray_light_sample ls;

    (void)out;
    ck_assert_int_eq(ray_light_sample_at(ctx, a, 0, 0, &ls), RAY_OK);
    ck_assert_int_eq(ray_light_sample_at(ctx, a, 1, 0, &ls), RAY_EINVAL);
    ck_assert_int_eq(ray_light_sample_at(ctx, a, 0, 1, &ls), RAY_EINVAL);
    *visible = ray_light_visible(ctx, a, &ls);
}

START_TEST(undeclared_shadows_should_cast_no_rays)
{
    int declared;

    for (declared = 0; declared < 2; declared++) {
        ray_material m;
        ray_light l;
        ray_scene *s;
        ray_ctx *ctx;
        ray_stats st;
        ray_ray r = ray_from(vec(0, 0, 5), vec(0, 0, -1));
        ray_rgb c;
        unsigned mat;
        int visible = -1;

        m.shade = count_visible;
        m.ud = &visible;
        m.effects = declared ? RAY_EFFECT_SHADOW : 0;
        m.scatter = NULL;
        memset(&l, 0, sizeof l);
        l.kind = RAY_LIGHT_POINT;
        l.position = vec(0, 0, 10);     /* blocked by the sphere above */
        ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_material(s, &m, &mat), RAY_OK);
        ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 0, 1), mat, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 8), 1, mat, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        ck_assert_int_eq(ray_ctx_new(s, 1, &ctx), RAY_OK);
        r.org = vec(0, 0, 5);
        ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1.0, &c), RAY_OK);
        ray_ctx_stats(ctx, &st);
        ck_assert_int_eq(visible, declared ? 0 : 1);
        ck_assert_uint_eq(st.rays[RAY_KIND_SHADOW], declared ? 1 : 0);
        ray_ctx_free(ctx);
        ray_scene_free(s);
    }
}
END_TEST

/* The background callback sees the escaping ray; without it, the colour. */
static void gradient(void *ud, const ray_ray *r, ray_rgb *out)
{
    int *calls = ud;
    (*calls)++;
    out->r = r->dir.x;
    out->g = r->dir.y;
    out->b = 0.25;
}

START_TEST(background_should_come_from_colour_or_callback)
{
    ray_scene *s;
    ray_ctx *ctx;
    ray_ray r = ray_from(vec(0, 0, 0), vec(0.5, 0.75, 0));
    ray_rgb c;
    int calls = 0;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_set_background(s, rgb(0.1, 0.2, 0.3), gradient,
                                              &calls), RAY_OK);
    /* A NULL function: the colour alone. */
    ck_assert_int_eq(ray_scene_set_background(s, rgb(0.1, 0.2, 0.3), NULL,
                                              NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(s, 0, &ctx), RAY_OK);
    ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1.0, &c), RAY_OK);
    ck_assert_double_eq(c.g, 0.2);
    ray_ctx_free(ctx);
    ray_scene_free(s);

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_set_background(s, rgb(0, 0, 0), gradient, &calls), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(s, 0, &ctx), RAY_OK);
    ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1.0, &c), RAY_OK);
    ck_assert_int_eq(calls, 1);
    ck_assert_double_eq(c.r, 0.5);
    ck_assert_double_eq(c.g, 0.75);
    ck_assert_int_eq(ray_ctx_new(NULL, 0, &ctx), RAY_EINVAL);
    ray_ctx_free(ctx);
    ray_ctx_free(NULL);
    ray_scene_free(s);
}
END_TEST

/* ray_ctx_random: uniform in [0, 1), the same sequence for the same seed,
** a different one for another seed; mean of 1e5 draws 1/2 within 5 sigma
** (sigma = sqrt(1/12/1e5) = 9.1e-4). */
START_TEST(ctx_random_should_be_uniform_and_reproducible)
{
    ray_scene *s;
    ray_ctx *a, *b, *c;
    double sum = 0;
    int i, same = 1, differ = 0;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(s, 7, &a), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(s, 7, &b), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(s, 8, &c), RAY_OK);
    for (i = 0; i < 100000; i++) {
        double x = ray_ctx_random(a), y = ray_ctx_random(b), z = ray_ctx_random(c);
        ck_assert(x >= 0 && x < 1);
        same &= x == y;
        differ |= x != z;
        sum += x;
    }
    ck_assert(same);
    ck_assert(differ);
    ck_assert_double_eq_tol(sum / 100000, 0.5, 5 * 9.1e-4);
    ck_assert_double_eq(ray_ctx_random(NULL), 0.0);
    ray_ctx_free(a);
    ray_ctx_free(b);
    ray_ctx_free(c);
    ray_scene_free(s);
}
END_TEST

/* Sample counts round up to squares; samples of a sphere light lie on
** its disk facing the point; a directional light is at infinity. */
typedef struct light_probe {
    int checked;
} light_probe;

/* Commit scene s (a probe's material on the plane z = 0, its lights
** added), trace one ray straight down onto it, and free it: the probe
** must have run. */
static void trace_light_probe(ray_scene *s, const light_probe *probe)
{
    ray_ray r = ray_from(vec(0, 0, 5), vec(0, 0, -1));
    ray_ctx *ctx;
    ray_rgb c;

    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(s, 3, &ctx), RAY_OK);
    ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1.0, &c), RAY_OK);
    ck_assert_int_eq(probe->checked, 1);
    ray_ctx_free(ctx);
    ray_scene_free(s);
}

/* dir within 4 DBL_EPSILON a component of to / |to|, taken in long
** double (callers say why 4). */
static int unit_toward(ray_vec3 dir, ray_vec3 to)
{
    long double x = (long double)to.x, y = (long double)to.y,
                z = (long double)to.z, len = sqrtl(x * x + y * y + z * z);
    long double tol = 4 * (long double)DBL_EPSILON;

    return fabsl((long double)dir.x - x / len) <= tol &&
           fabsl((long double)dir.y - y / len) <= tol &&
           fabsl((long double)dir.z - z / len) <= tol;
}

static void probe_lights(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                         ray_rgb *out)
{
    light_probe *p = ud;
    ray_light_sample ls;
    ray_vec3 point[9];
    double far = 0;
    unsigned i;

    (void)out;
    ck_assert_uint_eq(ray_light_samples(a->scene, 0), 1);     /* point */
    ck_assert_uint_eq(ray_light_samples(a->scene, 1), 1);     /* directional */
    ck_assert_uint_eq(ray_light_samples(a->scene, 2), 9);     /* 5 -> 3x3 */
    ck_assert_uint_eq(ray_light_samples(a->scene, 3), 16);    /* 0 -> 16 */
    ck_assert_uint_eq(ray_light_samples(a->scene, 4), 0);     /* no light */
    /* Light 0 sits 1e-160 above the hit: 1/dist^2 overflows, refused
    ** with *out untouched. */
    memset(&ls, 0xAB, sizeof ls);
    {
        ray_light_sample before = ls;
        ck_assert_int_eq(ray_light_sample_at(ctx, a, 0, 0, &ls), RAY_EINVAL);
        ck_assert(memcmp(&ls, &before, sizeof ls) == 0);
    }
    ck_assert_int_eq(ray_light_sample_at(ctx, a, 1, 0, &ls), RAY_OK);
    ck_assert(ls.dist == HUGE_VAL);
    ck_assert_vec_eq_tol(ls.dir, vec(0, 0, 1), 1e-15);
    ck_assert_double_eq(ls.radiance.r, 2.0);
    for (i = 0; i < 9; i++) {
        double from_centre;
        unsigned j;
        ck_assert_int_eq(ray_light_sample_at(ctx, a, 2, i, &ls), RAY_OK);
        /* On the disk of radius 1 around (0,0,10), facing the hit point
        ** (the origin): z = 10, |(x, y)| <= 1; radiance 1/dist^2 split
        ** over the 9 samples. */
        ck_assert_double_eq_tol(ls.point.z, 10.0, 1e-12);
        from_centre = sqrt(ls.point.x * ls.point.x + ls.point.y * ls.point.y);
        ck_assert(from_centre <= 1.0 + 1e-12);
        ck_assert_double_eq_tol(ls.radiance.g, 1.0 / (9 * ls.dist * ls.dist), 1e-15);
        ck_assert_double_eq_tol(ls.dist, vdist(ls.point, a->hit->p), 1e-12);
        /* The unit direction toward the sample, against to / |to| in
        ** long double: within 4 DBL_EPSILON a component (light.c's
        ** to * (1 / dist) rounds the root, the quotient and the product:
        ** 1.6 DBL_EPSILON the worst of 20M random vectors), and of unit
        ** length as closely. */
        ck_assert(unit_toward(ls.dir, vsub(ls.point, a->hit->p)));
        ck_assert(fabs(vdot(ls.dir, ls.dir) - 1) <= 4 * DBL_EPSILON);
        /* Spread over the disk by the strata (light.c's frame, made once
        ** a point): no two samples alike, the outer ones reaching out. */
        for (j = 0; j < i; j++)
            ck_assert(point[j].x != ls.point.x || point[j].y != ls.point.y);
        point[i] = ls.point;
        far = fmax(far, from_centre);
    }
    ck_assert(far > 0.5);
    p->checked = 1;
}

/* Lights as near as |to|^2 underflows: a point light 1e-154 away on the
** diagonal (|to|^2 2e-308, just under DBL_MIN) and 2e-154 (8e-308, just
** over), and a sphere light of 65536 samples 3e-157 away (1.8e-313,
** where a subnormal keeps 35 bits: 1/|to| taken from its root would be
** 1e-11 off).  Each sample's direction is the unit vector toward its
** point within 4 DBL_EPSILON a component (as probe_lights says; light.c:
** one division, or the scaled way below DBL_MIN), and its radiance the
** inverse square split over the samples. */
static void probe_near_lights(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                              ray_rgb *out)
{
    light_probe *p = ud;
    unsigned i;

    (void)out;
    ck_assert(a->hit->p.x == 0 && a->hit->p.y == 0 && a->hit->p.z == 0);
    for (i = 0; i < 3; i++) {
        ray_light_sample ls;
        long double x, y, z, len;

        ck_assert_int_eq(ray_light_sample_at(ctx, a, i, 0, &ls), RAY_OK);
        ck_assert(unit_toward(ls.dir, ls.point));   /* the hit is 0 */
        x = (long double)ls.point.x;
        y = (long double)ls.point.y;
        z = (long double)ls.point.z;
        len = sqrtl(x * x + y * y + z * z);
        /* dist is the root of |to|^2 as it is (for the sphere light a
        ** subnormal's 35 bits: 3e-11), and the radiance its inverse
        ** square. */
        ck_assert_double_eq_tol(ls.dist / (double)len, 1, 1e-10);
        ck_assert_double_eq_tol((double)((long double)ls.radiance.r * len * len *
                                         (i < 2 ? 1 : 65536)), 1, 1e-9);
    }
    p->checked = 1;
}

START_TEST(near_lights_should_give_unit_directions)
{
    light_probe probe = {0};
    ray_material m = {probe_near_lights, &probe, 0, NULL};
    ray_light l;
    ray_scene *s;
    unsigned mat;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, &mat), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 0, 1), mat, NULL), RAY_OK);
    ray_light_init(&l, RAY_LIGHT_POINT);
    l.intensity = rgb(1, 1, 1);
    l.position = vec(1e-154, 0, 1e-154);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    l.position = vec(2e-154, 0, 2e-154);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    ray_light_init(&l, RAY_LIGHT_SPHERE);
    l.intensity = rgb(1, 1, 1);
    l.position = vec(3e-157, 0, 3e-157);
    l.radius = 1e-180;
    l.samples = RAY_MAX_LIGHT_SAMPLES;
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    trace_light_probe(s, &probe);
}
END_TEST

/* How far x is from the reference ref, in units of ref's last place
** (0 when both are 0). */
static double ulps_off(double x, long double ref)
{
    double r = (double)ref, ulp = nextafter(fabs(r), HUGE_VAL) - fabs(r);

    return (double)(fabsl((long double)x - ref) / (long double)ulp);
}

/*
** The concentric map (sampling.c) against its definition: radius
** max(|a|, |b|), angle (pi/4) (b/a) about the x axis and
** pi/2 - (pi/4) (a/b) about the y axis, with libm's long double sine and
** cosine of that angle (about the y axis, the sine and cosine of
** (pi/4) (a/b): no cancellation near pi/2 in the reference).  Within
** 5 ulp a coordinate: the inline sine and cosine are within 1 ulp (0.85
** and 0.77 the worst of 20M angles), the angle's quotient and product
** round twice in double (up to about 2.3 ulp of the result once through
** sin), and the product with the radius once more: 3.34 ulp the worst
** of 20M random points.  A wrong coefficient, sign or wedge is off by
** thousands of ulp or more.
*/
static void disk_point_should_follow_its_definition(double a, double b)
{
    const long double quarter = 0.78539816339744830961566084581987572L;
    long double rad, phi;
    double x, y;
    int ok;

    ray__concentric_disk(a, b, &x, &y);
    if (a == 0 && b == 0) {
        ck_assert(x == 0 && y == 0);
        return;
    }
    if (fabs(a) > fabs(b)) {
        rad = (long double)a;
        phi = quarter * ((long double)b / (long double)a);
        ok = ulps_off(x, rad * cosl(phi)) <= 5 && ulps_off(y, rad * sinl(phi)) <= 5;
    } else {                      /* cos and sin of pi/2 - phi */
        rad = (long double)b;
        phi = quarter * ((long double)a / (long double)b);
        ok = ulps_off(x, rad * sinl(phi)) <= 5 && ulps_off(y, rad * cosl(phi)) <= 5;
    }
    ck_assert_msg(ok, "(%a, %a) -> (%.17g, %.17g)", a, b, x, y);
}

START_TEST(concentric_disk_should_follow_its_definition)
{
    int i, j;

    for (i = -400; i <= 400; i++)
        for (j = -400; j <= 400; j++)
            disk_point_should_follow_its_definition(i / 400.0, j / 400.0);
    /* The corners' neighbours, and tiny and denormal radii. */
    disk_point_should_follow_its_definition(1, nextafter(1, 0));
    disk_point_should_follow_its_definition(nextafter(-1, 0), -1);
    disk_point_should_follow_its_definition(0x1p-1060, -0x1p-1070);
    disk_point_should_follow_its_definition(0x1p-1074, 0x1p-1074);
    disk_point_should_follow_its_definition(1e-300, 0.7e-300);
}
END_TEST

START_TEST(lights_should_sample_as_documented)
{
    light_probe probe = {0};
    ray_material m;
    ray_light l;
    ray_scene *s;
    unsigned mat;

    m.shade = probe_lights;
    m.ud = &probe;
    m.effects = 0;
    m.scatter = NULL;
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, &mat), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 0, 1), mat, NULL), RAY_OK);
    memset(&l, 0, sizeof l);
    l.kind = RAY_LIGHT_POINT;
    l.position = vec(0, 0, 1e-160);
    l.intensity = rgb(1, 0, 0);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    l.kind = RAY_LIGHT_DIRECTIONAL;
    l.direction = vec(0, 0, -4);
    l.intensity = rgb(2, 2, 2);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    l.kind = RAY_LIGHT_SPHERE;
    l.position = vec(0, 0, 10);
    l.radius = 1;
    l.intensity = rgb(1, 1, 1);
    l.samples = 5;
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    l.samples = 0;
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    l.samples = RAY_MAX_LIGHT_SAMPLES + 1;
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_EINVAL);
    trace_light_probe(s, &probe);
}
END_TEST

/* The render options as the documentation writes them, width and height
** alone (the init function that zeroed the rest left the API, issue 37):
** every other field zero, the defaults (check_defaults.c renders them
** against the defaults written out). */
START_TEST(render_options_should_default_sensibly)
{
    ray_render_options o;

    memset(&o, 0xff, sizeof o);
    o = (ray_render_options){.width = 64, .height = 32};
    ck_assert_uint_eq(o.width, 64);
    ck_assert_uint_eq(o.height, 32);
    ck_assert_uint_eq(o.y0, 0);
    ck_assert_uint_eq(o.y1, 0);
    ck_assert_uint_eq(o.threads, 0);
    ck_assert_uint_eq(o.samples, 0);           /* zero: the default, 1 */
    ck_assert(o.seed == 0);
    ck_assert(o.progress == NULL);
}
END_TEST

/*
** Issue 38: a built-in material made from a NULL parameter block (its
** constructor borrows the pointer as ud, NULL too) is inert: a ray that
** hits a sphere of it comes back black, exactly, though the background
** it would reflect or refract is grey (0.5) and a material with
** parameters would show it.  Phong without parameters declares no
** mirror term, so no scatter callback (and the checker none without
** materials to pick from).
*/
START_TEST(materials_without_parameters_should_do_nothing)
{
    ray_material m[4];
    int i;

    m[0] = ray_material_phong(NULL);
    m[1] = ray_material_mirror(NULL);
    m[2] = ray_material_glass(NULL);
    m[3] = ray_material_checker(NULL);
    ck_assert(m[0].scatter == NULL);
    ck_assert(m[3].scatter == NULL);
    for (i = 0; i < 4; i++) {
        ray_ray r = ray_from(vec(0.1, 0.2, -5), vec(0, 0, 1));
        ray_rgb c = rgb(7, 7, 7);
        ray_scene *s;
        ray_ctx *ctx;
        unsigned mat;

        ck_assert_ptr_null(m[i].ud);
        ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_material(s, &m[i], &mat), RAY_OK);
        ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1, mat, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_set_background(s, rgb(0.5, 0.5, 0.5), NULL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        ck_assert_int_eq(ray_ctx_new(s, 1, &ctx), RAY_OK);
        ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1.0, &c), RAY_OK);
        ck_assert_msg(c.r == 0 && c.g == 0 && c.b == 0, "material %d: %g %g %g",
                      i, c.r, c.g, c.b);
        ray_ctx_free(ctx);
        ray_scene_free(s);
    }
}
END_TEST

Suite *trace_suite(void)
{
    Suite *s = suite_create("trace");
    TCase *lim = tcase_create("limits");
    TCase *opt = tcase_create("materials");

    tcase_add_test(lim, trace_should_stop_facing_mirrors_at_max_depth);
    tcase_add_test(lim, trace_should_cut_by_weight);
    tcase_add_test(lim, trace_should_allow_max_depth_and_refuse_more);
    tcase_add_test(lim, trace_should_limit_fanout);
    tcase_add_test(lim, trace_should_refuse_undeclared_effects);
    tcase_add_test(opt, glass_should_reflect_totally_inside);
    tcase_add_test(opt, glass_should_refract_from_inside);
    tcase_add_test(opt, glass_should_absorb_along_the_path);
    tcase_add_test(opt, materials_should_shade_any_finite_direction);
    tcase_add_test(opt, shadow_rays_should_not_hit_their_own_surface);
    tcase_add_test(opt, undeclared_shadows_should_cast_no_rays);
    tcase_add_test(opt, background_should_come_from_colour_or_callback);
    tcase_add_test(opt, ctx_random_should_be_uniform_and_reproducible);
    tcase_add_test(opt, lights_should_sample_as_documented);
    tcase_add_test(opt, concentric_disk_should_follow_its_definition);
    tcase_add_test(opt, near_lights_should_give_unit_directions);
    tcase_add_test(opt, render_options_should_default_sensibly);
    tcase_add_test(opt, materials_without_parameters_should_do_nothing);
    suite_add_tcase(s, lim);
    suite_add_tcase(s, opt);
    return s;
}
