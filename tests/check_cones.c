/* SPDX-License-Identifier: MIT */
/*
** check_cones.c -- ray cones and mip-mapped textures (issue 19): the mip
** pyramid's box filter on known inputs, the filtered lookup, images made
** from memory, the cone's width and footprint through the tracer
** (distance, flat and curved mirrors, refraction, instances), camera
** cones in ray_render (any thread count, cones off = the old bytes) and
** misuse.
*/
#include <stdlib.h>

#include "tests.h"
#include "image/image.h"
#include "trace/trace.h"

/*
** A level texel is a sum of at most 16 weighted texels in double (each
** product and sum within a few units of 2^-53 relative of values below
** 2^4 here), rounded to float once: within 2^-24 relative of the exact
** box average, plus the double sum's error, far below another 2^-24.
** So: 2^-23 relative to the larger of |value| and 1.
*/
static double level_tol(double expect)
{
    return ldexp(fmax(fabs(expect), 1.0), -23);
}

/* Level k's texel (x, y), channel c. */
static double texel(const ray_image *img, unsigned k, unsigned x, unsigned y,
                    unsigned c)
{
    unsigned w, h;
    const float *p = ray__image_level(img, k, &w, &h);

    ck_assert_ptr_nonnull(p);
    ck_assert_uint_lt(x, w);
    ck_assert_uint_lt(y, h);
    return (double)p[3 * ((size_t)y * w + x) + c];
}

/* An image whose texel (x, y) is (x + w y, 1, y): distinct, exact. */
static ray_image *ramp_image(unsigned w, unsigned h)
{
    float *rgb = malloc(3 * sizeof(float) * w * h);
    ray_image *img = NULL;
    unsigned x, y;

    ck_assert_ptr_nonnull(rgb);
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            float *p = rgb + 3 * ((size_t)y * w + x);
            p[0] = (float)(x + w * y);
            p[1] = 1.0f;
            p[2] = (float)y;
        }
    ck_assert_int_eq(ray_image_new(w, h, rgb, &img), RAY_OK);
    free(rgb);
    ck_assert_ptr_nonnull(img);
    return img;
}

static void expect_level_size(const ray_image *img, unsigned k, unsigned w,
                              unsigned h)
{
    unsigned gw = 0, gh = 0;

    ck_assert_ptr_nonnull(ray__image_level(img, k, &gw, &gh));
    ck_assert_uint_eq(gw, w);
    ck_assert_uint_eq(gh, h);
}

START_TEST(mip_4x4_should_average_2x2_blocks)
{
    ray_image *img = ramp_image(4, 4);
    unsigned x, y;

    ck_assert_uint_eq(ray__image_levels(img), 3);
    expect_level_size(img, 0, 4, 4);
    expect_level_size(img, 1, 2, 2);
    expect_level_size(img, 2, 1, 1);
    ck_assert_ptr_null(ray__image_level(img, 3, &x, &y));
    /* Level 1 texel (x, y): the mean of level 0's (2x..2x+1, 2y..2y+1):
    ** red (2x + 0.5) + 4 (2y + 0.5), blue 2y + 0.5 -- exact (weights
    ** 1/4, sums of small integers). */
    for (y = 0; y < 2; y++)
        for (x = 0; x < 2; x++) {
            ck_assert_double_eq(texel(img, 1, x, y, 0),
                                (2.0 * x + 0.5) + 4 * (2.0 * y + 0.5));
            ck_assert_double_eq(texel(img, 1, x, y, 1), 1.0);
            ck_assert_double_eq(texel(img, 1, x, y, 2), 2.0 * y + 0.5);
        }
    ck_assert_double_eq(texel(img, 2, 0, 0, 0), 7.5);   /* mean of 0..15 */
    ck_assert_double_eq(texel(img, 2, 0, 0, 1), 1.0);
    ck_assert_double_eq(texel(img, 2, 0, 0, 2), 1.5);
    ray_image_free(img);
}
END_TEST

/* 5 x 3: x by the area weights (0.4 0.4 0.2 | 0.2 0.4 0.4), y 3 -> 1 by
** (1/3 1/3 1/3); then 2 x 1 -> 1 x 1 by (1/2 1/2). */
START_TEST(mip_5x3_should_weigh_texels_by_area)
{
    static const double wx[2][5] = {{0.4, 0.4, 0.2, 0, 0},
                                    {0, 0, 0.2, 0.4, 0.4}};
    ray_image *img = ramp_image(5, 3);
    double mean = 0;
    unsigned i, x, y;

    ck_assert_uint_eq(ray__image_levels(img), 3);
    expect_level_size(img, 1, 2, 1);
    expect_level_size(img, 2, 1, 1);
    for (i = 0; i < 2; i++) {
        double r = 0, b = 0;
        for (y = 0; y < 3; y++)
            for (x = 0; x < 5; x++) {
                r += wx[i][x] / 3 * (x + 5.0 * y);
                b += wx[i][x] / 3 * y;
            }
        ck_assert_double_eq_tol(texel(img, 1, i, 0, 0), r, level_tol(r));
        ck_assert_double_eq_tol(texel(img, 1, i, 0, 1), 1.0, level_tol(1));
        ck_assert_double_eq_tol(texel(img, 1, i, 0, 2), b, level_tol(b));
    }
    /* The exact box keeps the mean: (0 + .. + 14) / 15 = 7 on every
    ** level (each a float rounding of the level below's mean, and the
    ** level below's texels rounded too: two level_tol). */
    for (x = 0; x < 15; x++)
        mean += x / 15.0;
    ck_assert_double_eq_tol(
        (texel(img, 1, 0, 0, 0) + texel(img, 1, 1, 0, 0)) / 2, mean,
        level_tol(mean));
    ck_assert_double_eq_tol(texel(img, 2, 0, 0, 0), mean,
                            2 * level_tol(mean));
    ck_assert_double_eq_tol(texel(img, 2, 0, 0, 2), 1.0, 2 * level_tol(1));
    ray_image_free(img);
}
END_TEST

/* 1 x 7: only the height halves, 7 -> 3 (weights 2/7 2/7 2/7 1/7 ...) ->
** 1; 9 x 1 likewise along x; 1 x 1 is its own pyramid. */
START_TEST(mip_1xN_should_halve_one_side_and_1x1_stay)
{
    ray_image *tall = ramp_image(1, 7), *wide = ramp_image(9, 1);
    ray_image *one = ramp_image(1, 1);
    ray_rgb c;
    double r;

    ck_assert_uint_eq(ray__image_levels(tall), 3);
    expect_level_size(tall, 1, 1, 3);
    expect_level_size(tall, 2, 1, 1);
    /* Level 1 row 0 covers [0, 7/3): texels 0, 1 whole, 2 a third. */
    r = (0 + 1 + 2 / 3.0) * 3 / 7.0;
    ck_assert_double_eq_tol(texel(tall, 1, 0, 0, 0), r, level_tol(r));
    /* Row 1 covers [7/3, 14/3): 2/3 of texel 2, 3, 2/3 of texel 4. */
    r = (2 * 2 / 3.0 + 3 + 4 * 2 / 3.0) * 3 / 7.0;
    ck_assert_double_eq_tol(texel(tall, 1, 0, 1, 0), r, level_tol(r));
    ck_assert_double_eq_tol(texel(tall, 2, 0, 0, 0), 3.0, 2 * level_tol(3));

    ck_assert_uint_eq(ray__image_levels(wide), 4);   /* 9, 4, 2, 1 */
    expect_level_size(wide, 1, 4, 1);
    expect_level_size(wide, 3, 1, 1);
    ck_assert_double_eq_tol(texel(wide, 3, 0, 0, 0), 4.0, 3 * level_tol(4));

    ck_assert_uint_eq(ray__image_levels(one), 1);
    ck_assert_int_eq(ray_image_sample(one, 0.3, 0.7, 1e9, &c),
                     RAY_OK);
    ck_assert_double_eq(c.r, 0.0);
    ck_assert_double_eq(c.g, 1.0);
    ray_image_free(tall);
    ray_image_free(wide);
    ray_image_free(one);
}
END_TEST

static int rgb_same(ray_rgb a, ray_rgb b)
{
    return memcmp(&a, &b, sizeof a) == 0;
}

START_TEST(footprint_within_a_texel_should_be_the_plain_sample)
{
    ray_image *img = ramp_image(8, 4);
    rng g = {19};
    int i;

    /* The largest side is 8: a footprint of 1/8 or less is one texel. */
    for (i = 0; i < 200; i++) {
        double s = 4 * rng_unit(&g) - 2, t = 4 * rng_unit(&g) - 2;
        double w = (i % 3 == 0) ? 0.0 : rng_unit(&g) / 8;
        ray_rgb a, b;
        ck_assert_int_eq(ray_image_sample(img, s, t, 0, &a), RAY_OK);
        ck_assert_int_eq(ray_image_sample(img, s, t, w, &b),
                         RAY_OK);
        ck_assert(rgb_same(a, b));
    }
    ray_image_free(img);
}
END_TEST

/* The bilinear sample of a 1 x 1-texel-per-level check: level k alone at
** lambda = k, and the blend between. */
START_TEST(footprint_should_pick_and_blend_levels)
{
    ray_image *img = ramp_image(8, 8);
    ray_rgb at1, at2, mid, top;
    double s = 0.3, t = 0.6, want;

    /* lambda = log2(w 8) = 1: level 1 (4 x 4) alone.  Its bilinear
    ** sample at (s, t): x = 0.3 * 4 - 0.5 = 0.7, y = 0.4 * 4 - 0.5 =
    ** 1.1, texel (x, y) of level 1 red = 2x + 0.5 + 8 (2y + 0.5). */
    ck_assert_int_eq(ray_image_sample(img, s, t, 0.25, &at1),
                     RAY_OK);
    want = (2 * 0.7 + 0.5) + 8 * (2 * 1.1 + 0.5);
    /* The bilinear weights carry a few roundings of 2^-53 on values
    ** below 64: 1e-12 is far above them and far below a texel step. */
    ck_assert_double_eq_tol(at1.r, want, 1e-12);
    ck_assert_int_eq(ray_image_sample(img, s, t, 0.5, &at2),
                     RAY_OK);
    ck_assert_int_eq(ray_image_sample(img, s, t, sqrt(0.125),
                                                &mid), RAY_OK);
    /* lambda = 1.5: halfway between levels 1 and 2 (the blend's own
    ** roundings, with log2's, stay within 1e-12 of values below 64). */
    ck_assert_double_eq_tol(mid.r, 0.5 * (at1.r + at2.r), 1e-12);
    ck_assert_double_eq_tol(mid.b, 0.5 * (at1.b + at2.b), 1e-12);
    /* Past the last level (lambda >= 3), +Inf included: the mean. */
    ck_assert_int_eq(ray_image_sample(img, s, t, HUGE_VAL, &top),
                     RAY_OK);
    ck_assert_double_eq(top.r, 31.5);
    ck_assert_double_eq(top.b, 3.5);
    ck_assert_int_eq(ray_image_sample(img, s, t, 1.0, &top),
                     RAY_OK);
    ck_assert_double_eq(top.r, 31.5);
    ray_image_free(img);
}
END_TEST

START_TEST(image_misuse_should_leave_outputs_untouched)
{
    float rgb[3 * 4] = {0, 0, 0, 1, 1, 1, 0.5f, 0.5f, 0.5f, 1, 0, 0};
    ray_image *img = (ray_image *)&rgb, *keep = img, *good = NULL;
    ray_rgb c = {7, 7, 7};

    ck_assert_int_eq(ray_image_new(2, 2, NULL, &img), RAY_EINVAL);
    ck_assert_int_eq(ray_image_new(2, 2, rgb, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_image_new(0, 2, rgb, &img), RAY_EINVAL);
    ck_assert_int_eq(ray_image_new(2, 0, rgb, &img), RAY_EINVAL);
    /* Refused from the size alone: rgb is not read. */
    ck_assert_int_eq(ray_image_new(16385, 1, rgb, &img), RAY_ELIMIT);
    ck_assert_int_eq(ray_image_new(1, 4000000000u, rgb, &img), RAY_ELIMIT);
    rgb[4] = (float)NAN;
    ck_assert_int_eq(ray_image_new(2, 2, rgb, &img), RAY_EINVAL);
    rgb[4] = (float)HUGE_VAL;
    ck_assert_int_eq(ray_image_new(2, 2, rgb, &img), RAY_EINVAL);
    ck_assert_ptr_eq(img, keep);
    rgb[4] = 1;
    ck_assert_int_eq(ray_image_new(2, 2, rgb, &good), RAY_OK);
    ck_assert_int_eq(ray_image_sample(NULL, 0, 0, 0, &c),
                     RAY_EINVAL);
    ck_assert_int_eq(ray_image_sample(good, 0, 0, 0, NULL),
                     RAY_EINVAL);
    ck_assert_int_eq(
        ray_image_sample(good, 0, 0, (double)NAN, &c), RAY_EINVAL);
    ck_assert_int_eq(ray_image_sample(good, 0, 0, -1e-300, &c),
                     RAY_EINVAL);
    ck_assert_int_eq(
        ray_image_sample(good, (double)NAN, 0, 1, &c), RAY_EINVAL);
    ck_assert_int_eq(ray_image_sample(good, 0, HUGE_VAL, 1, &c),
                     RAY_EINVAL);
    ck_assert_double_eq(c.r, 7);
    ck_assert_double_eq(c.g, 7);
    ck_assert_double_eq(c.b, 7);
    ray_image_free(good);
}
END_TEST

/* ray_texture_image filters over args->footprint when it is positive. */
START_TEST(image_texture_should_use_the_footprint)
{
    ray_image *img = ramp_image(8, 8);
    ray_texture tex = ray_texture_image(img);
    ray_shade_args a;
    ray_rgb got, want;

    memset(&a, 0, sizeof a);
    a.u = 0.3;
    a.v = 0.6;
    tex.fn(tex.ud, &a, &got);
    ck_assert_int_eq(ray_image_sample(img, 0.3, 0.6, 0, &want), RAY_OK);
    ck_assert(rgb_same(got, want));
    a.footprint = 0.3;
    tex.fn(tex.ud, &a, &got);
    ck_assert_int_eq(ray_image_sample(img, 0.3, 0.6, 0.3, &want),
                     RAY_OK);
    ck_assert(rgb_same(got, want));
    ray_image_free(img);
}
END_TEST

/* ------------------------------------------------------------ the tracer */

/* What a recording material saw at its last hit. */
typedef struct cone_seen {
    double width, footprint, t, u, v;
    ray_vec3 dir;
    int calls;
} cone_seen;

static void record_cone(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                        ray_rgb *out)
{
    cone_seen *s = ud;

    (void)ctx;
    (void)out;
    s->width = a->cone_width;
    s->footprint = a->footprint;
    s->t = a->hit->t;
    s->u = a->u;
    s->v = a->v;
    s->dir = a->ray->dir;
    s->calls++;
}

static ray_material recorder(cone_seen *seen, unsigned effects)
{
    ray_material m;

    memset(seen, 0, sizeof *seen);
    m.shade = record_cone;
    m.ud = seen;
    m.effects = effects;
    return m;
}

static ray_scene *new_scene(void)
{
    ray_scene *s = NULL;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    return s;
}

/* Trace one primary ray with cone (w0, spread) through a new context. */
static void trace_cone(ray_scene *s, ray_vec3 org, ray_vec3 dir, double w0,
                       double spread)
{
    ray_ctx *ctx = NULL;
    ray_ray r = ray_from(org, dir);
    ray_rgb c;

    ck_assert_int_eq(ray_ctx_new(s, 1, &ctx), RAY_OK);
    ck_assert_int_eq(ray_ctx_set_cone(ctx, w0, spread), RAY_OK);
    ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1.0, &c), RAY_OK);
    ray_ctx_free(ctx);
}

/*
** The width is w0 + spread t |dir|: t from ray_plane within a few ulps
** (ray-numerics(7)), |dir| within 2 ulps, the product and sum one each:
** 16 ulps relative is a generous bound for all of them together.
*/
#define CONE_REL (16 * DBL_EPSILON)

START_TEST(cone_should_grow_linearly_with_distance_on_a_plane)
{
    static const double dist[3] = {1, 2, 4};
    double width[3], foot[3];
    int i;

    for (i = 0; i < 3; i++) {
        cone_seen seen;
        ray_material m = recorder(&seen, RAY_EFFECT_TEXTURE);
        ray_scene *s = new_scene();
        unsigned mid;
        /* The plane z = 0 met from height dist[i] at incidence cos 0.8:
        ** the distance along the ray is dist / 0.8. */
        ck_assert_int_eq(ray_scene_add_material(s, &m, &mid), RAY_OK);
        ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 0, 1),
                                             mid, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        trace_cone(s, vec(0, 0, dist[i]), vec(0.6, 0, -0.8), 0, 0.01);
        ck_assert_int_eq(seen.calls, 1);
        width[i] = seen.width;
        foot[i] = seen.footprint;
        ck_assert_double_eq_tol(width[i], 0.01 * dist[i] / 0.8,
                                CONE_REL * width[i]);
        /* The plane's (u, v) are lengths: the footprint is the width
        ** stretched by 1 / cos(incidence), one more division. */
        ck_assert_double_eq_tol(foot[i], width[i] / 0.8, CONE_REL * foot[i]);
        ray_scene_free(s);
    }
    ck_assert_double_eq_tol(width[1] / width[0], 2.0, 2 * CONE_REL * 2);
    ck_assert_double_eq_tol(width[2] / width[1], 2.0, 2 * CONE_REL * 2);
    ck_assert_double_eq_tol(foot[2] / foot[0], 4.0, 2 * CONE_REL * 4);
}
END_TEST

START_TEST(cone_should_start_at_its_width)
{
    cone_seen seen;
    ray_material m = recorder(&seen, RAY_EFFECT_TEXTURE);
    ray_scene *s = new_scene();
    unsigned mid;

    ck_assert_int_eq(ray_scene_add_material(s, &m, &mid), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 0, 1), mid,
                                         NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    /* A direction of length 2: the distance is t |dir| = 3. */
    trace_cone(s, vec(0, 0, 3), vec(0, 0, -2), 0.5, 0.25);
    ck_assert_double_eq_tol(seen.width, 0.5 + 0.25 * 3, CONE_REL * 2);
    /* A cylinder (spread 0) keeps its width. */
    trace_cone(s, vec(0, 0, 3), vec(0, 0, -1), 0.5, 0);
    ck_assert_double_eq(seen.width, 0.5);
    ray_scene_free(s);
}
END_TEST

/* Direct: the floor y = 0 from height D.  Through the mirror: up 0.5 D to
** a flat mirror at y = 1.5 D and down 1.5 D: twice the path, twice the
** width and the footprint. */
START_TEST(cone_should_double_through_a_flat_mirror_at_twice_the_distance)
{
    static const ray_rgb one = {1, 1, 1};
    cone_seen seen;
    ray_material m = recorder(&seen, RAY_EFFECT_TEXTURE);
    ray_material mirror = ray_material_mirror(&one);
    ray_scene *s = new_scene();
    unsigned mid, mirror_id;
    double direct, direct_fp, d = 3.0;

    ck_assert_int_eq(ray_scene_add_material(s, &m, &mid), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &mirror, &mirror_id), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 1, 0), mid,
                                         NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 1.5 * d, 0),
                                         vec(0, -1, 0), mirror_id, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    trace_cone(s, vec(0, d, 0), vec(0, -1, 0), 0, 0.02);
    direct = seen.width;
    direct_fp = seen.footprint;
    ck_assert_double_eq_tol(direct, 0.02 * d, CONE_REL * direct);
    seen.calls = 0;
    trace_cone(s, vec(0, d, 0), vec(0, 1, 0), 0, 0.02);
    ck_assert_int_eq(seen.calls, 1);
    /* Two segments, each within CONE_REL. */
    ck_assert_double_eq_tol(seen.width / direct, 2.0, 4 * CONE_REL * 2);
    ck_assert_double_eq_tol(seen.footprint / direct_fp, 2.0,
                            4 * CONE_REL * 2);
    ray_scene_free(s);
}
END_TEST

/*
** A sphere mirror of radius R met head-on at distance D: the width there
** is w = spread D, and the reflection's spread is spread + 2 w / R
** (convex, trace.c's cone_at_hit); the ray comes straight back over D + E
** to the plane z = E behind the eye.  From inside (concave), the spread
** becomes spread - 2 w / R.
*/
START_TEST(cone_should_widen_off_a_convex_and_narrow_off_a_concave_mirror)
{
    static const ray_rgb one = {1, 1, 1};
    cone_seen seen;
    ray_material m = recorder(&seen, RAY_EFFECT_TEXTURE);
    ray_material mirror = ray_material_mirror(&one);
    ray_scene *s = new_scene();
    unsigned mid, mirror_id;
    double R = 2, D = 3, E = 1, g = 0.01, w, want;

    ck_assert_int_eq(ray_scene_add_material(s, &m, &mid), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &mirror, &mirror_id), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, -D - R), R, mirror_id,
                                          NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, E), vec(0, 0, -1), mid,
                                         NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    trace_cone(s, vec(0, 0, 0), vec(0, 0, -1), 0, g);
    ck_assert_int_eq(seen.calls, 1);
    w = g * D;
    want = w + (g + 2 * w / R) * (D + E);
    /* Each of the two segments within CONE_REL, the curvature term too. */
    ck_assert_double_eq_tol(seen.width, want, 4 * CONE_REL * want);
    /* Without the curvature it would be g (2 D + E): visibly less. */
    ck_assert_double_gt(seen.width, 1.5 * g * (2 * D + E));
    ray_scene_free(s);

    /* Concave: from the centre of a mirror sphere of radius R, out R to
    ** the wall (w = g R), back 1.5 R to the plane z = R/2: spread g - 2 g
    ** = -g, width g R - g 1.5 R = -0.5 g R, seen as its size 0.5 g R. */
    memset(&seen, 0, sizeof seen);
    s = new_scene();
    ck_assert_int_eq(ray_scene_add_material(s, &m, &mid), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &mirror, &mirror_id), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), R, mirror_id,
                                          NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, R / 2), vec(0, 0, -1),
                                         mid, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    trace_cone(s, vec(0, 0, 0), vec(0, 0, -1), 0, g);
    ck_assert_int_eq(seen.calls, 1);
    want = 0.5 * g * R;
    /* The difference g R - 1.5 g R cancels to a third of its terms: the
    ** terms' relative error, tripled. */
    ck_assert_double_eq_tol(seen.width, want, 3 * 4 * CONE_REL * want);
    ray_scene_free(s);
}
END_TEST

/*
** Refraction (trace.c's refracted_spread).  Head-on through a pane the
** index cannot be read from the directions (they are parallel): the cone
** goes on as it came, its width the spread times the whole path.
*/
START_TEST(cone_should_pass_head_on_through_a_pane_unchanged)
{
    cone_seen seen;
    ray_material m = recorder(&seen, RAY_EFFECT_TEXTURE);
    ray_glass_params gp = {0};       /* window glass, ior 1.5 */
    ray_material glass;
    ray_scene *s = new_scene();
    unsigned mid, gid;
    ray_vec3 quad[4];

    glass = ray_material_glass(&gp);
    ck_assert_int_eq(ray_scene_add_material(s, &m, &mid), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &glass, &gid), RAY_OK);
    /* A pane z = -1 (polygon) in front of the floor z = -3, met head-on:
    ** no bending. */
    quad[0] = vec(-1, -1, -1);
    quad[1] = vec(1, -1, -1);
    quad[2] = vec(1, 1, -1);
    quad[3] = vec(-1, 1, -1);
    ck_assert_int_eq(ray_scene_add_polygon(s, quad, 4, gid, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, -3), vec(0, 0, 1), mid,
                                         NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    trace_cone(s, vec(0, 0, 0), vec(0, 0, -1), 0, 0.01);
    ck_assert_int_ge(seen.calls, 1);
    ck_assert_double_eq_tol(seen.width, 0.03, 4 * CONE_REL * 0.03);
    ray_scene_free(s);
}
END_TEST

/*
** The cones' closed forms below take a few dozen roundings of 2^-53
** each; 1e-12 of the value leaves a margin of thousands, while the
** errors they guard against (a spread not scaled, or not focused) change
** the width by more than 1%.
*/
#define REFRACT_REL 1e-12

/* Two glass panes z = -1 (normal +z, entered) and z = -2 (normal -z,
** left), the floor z = -3; a ray at 30 degrees to the normal. */
static ray_scene *slab_scene(cone_seen *seen)
{
    ray_material m = recorder(seen, RAY_EFFECT_TEXTURE);
    static ray_glass_params gp;
    ray_material glass;
    ray_scene *s = new_scene();
    unsigned mid, gid;
    ray_vec3 top[4], bottom[4];
    int i;

    glass = ray_material_glass(&gp);
    ck_assert_int_eq(ray_scene_add_material(s, &m, &mid), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &glass, &gid), RAY_OK);
    for (i = 0; i < 4; i++) {
        double x = (i == 1 || i == 2) ? 10 : -10, y = i < 2 ? -10 : 10;
        top[i] = vec(x, y, -1);
        bottom[3 - i] = vec(x, y, -2);   /* reversed: normal -z */
    }
    ck_assert_int_eq(ray_scene_add_polygon(s, top, 4, gid, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_polygon(s, bottom, 4, gid, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, -3), vec(0, 0, 1), mid,
                                         NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    return s;
}

/*
** Through a slab at 30 degrees: inside, the spread is scaled by eta
** sqrt(cos ti / cos tt), eta = 1 / 1.5 (Snell differentiated: eta cos
** ti / cos tt in the plane of incidence, eta across it, their geometric
** mean); leaving, by the inverse, so the cone goes on with its spread.
*/
START_TEST(cone_should_narrow_inside_a_slab_and_recover_behind_it)
{
    cone_seen seen;
    ray_scene *s = slab_scene(&seen);
    double g = 0.01, ci = sqrt(3.0) / 2, st = 0.5 / 1.5;
    double ct = sqrt(1 - st * st);
    double inside = g / 1.5 * sqrt(ci / ct);
    double want = g / ci + inside / ct + g / ci;

    trace_cone(s, vec(0, 0, 0), vec(0.5, 0, -ci), 0, g);
    ck_assert_int_ge(seen.calls, 1);
    ck_assert_double_eq_tol(seen.width, want, REFRACT_REL * want);
    /* Unscaled inside it would be g (2 / ci + 1 / ct): 5% more. */
    ck_assert_double_lt(seen.width, 0.97 * g * (2 / ci + 1 / ct));
    ray_scene_free(s);
}
END_TEST

/*
** A glass ball of radius R and index n is a lens: a parallel beam near
** its axis focuses at n R / (2 (n - 1)) = 1.5 R from its centre (n =
** 1.5; the paraxial ball lens, e.g. Hecht, Optics, section 6.2).  A cone
** of width w and spread 0 entering 0.001 R off the axis must narrow to
** w / 3 at the far side (the front surface's power over 2R), reach a
** sixth of w a quarter R behind the ball, and about 0 at the focus.  The
** ray is off the axis by 0.001 R so that the index can be read from its
** directions; that aberrates the focus by about (0.001)^2 of R, and the
** model's cosines differ from 1 by as much: the bound 1e-4 w keeps a
** margin of 100 while a cone that ignored the lens would keep its
** width w.
*/
START_TEST(cone_should_focus_behind_a_glass_ball)
{
    static const double behind[2] = {0.25, 0.5}, want[2] = {1.0 / 6, 0};
    double R = 1, D = 5, h = 1e-3 * R, w = 0.01;
    int i;

    for (i = 0; i < 2; i++) {
        cone_seen seen;
        ray_material m = recorder(&seen, RAY_EFFECT_TEXTURE);
        ray_glass_params gp = {0};       /* window glass, ior 1.5 */
        ray_material glass;
        ray_scene *s = new_scene();
        unsigned mid, gid;

            glass = ray_material_glass(&gp);
        ck_assert_int_eq(ray_scene_add_material(s, &m, &mid), RAY_OK);
        ck_assert_int_eq(ray_scene_add_material(s, &glass, &gid), RAY_OK);
        ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, -D), R, gid,
                                              NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, -D - R - behind[i]),
                                             vec(0, 0, 1), mid, NULL),
                         RAY_OK);
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        trace_cone(s, vec(h, 0, 0), vec(0, 0, -1), w, 0);
        ck_assert_int_eq(seen.calls, 1);
        ck_assert_double_eq_tol(seen.width, want[i] * w, 1e-4 * w);
        ray_scene_free(s);
    }
}
END_TEST

/*
** The (u, v) scale by kind, met head-on at distance 1 with spread 0.01
** (width 0.01): a triangle's barycentrics, sqrt(1 / area); a mesh's (s,
** t), sqrt(st area / area); a sphere at its equator, 1 / (pi R sqrt 2).
*/
START_TEST(footprint_should_scale_by_each_kinds_uv_per_length)
{
    static const ray_vec3 quad_v[4] = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0},
                                       {-1, 1, 0}};
    static const unsigned quad_i[6] = {0, 1, 2, 0, 2, 3};
    static const double quad_st[8] = {0, 0, 1, 0, 1, 1, 0, 1};
    cone_seen seen;
    ray_material m = recorder(&seen, RAY_EFFECT_TEXTURE);
    ray_scene *s = new_scene();
    ray_mesh mesh;
    unsigned mid;
    double w = 0.01;

    /* A right triangle with legs 1 and 2: area 1, over which the
    ** barycentrics span 1/2: scale sqrt(1/2). */
    ck_assert_int_eq(ray_scene_add_material(s, &m, &mid), RAY_OK);
    ck_assert_int_eq(ray_scene_add_triangle(s, vec(-1, -1, 0), vec(0, -1, 0),
                                            vec(-1, 1, 0), mid, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    trace_cone(s, vec(-0.8, -0.5, 1), vec(0, 0, -1), 0, 0.01);
    ck_assert_double_eq_tol(seen.footprint, w * sqrt(0.5),
                            4 * CONE_REL * w);
    ray_scene_free(s);

    /* A 2 x 2 quad with (s, t) over [0, 1]^2: scale 1/2, borrowed or
    ** copied alike. */
    memset(&mesh, 0, sizeof mesh);
    mesh.vertices = quad_v;
    mesh.vertex_count = 4;
    mesh.indices = quad_i;
    mesh.triangle_count = 2;
    mesh.texcoords = quad_st;
    s = new_scene();
    ck_assert_int_eq(ray_scene_add_material(s, &m, &mid), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &mesh, mid, NULL), RAY_OK);
    mesh.flags = RAY_MESH_BORROW;
    ck_assert_int_eq(ray_scene_add_mesh(s, &mesh, mid, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    trace_cone(s, vec(0.5, -0.25, 1), vec(0, 0, -1), 0, 0.01);
    ck_assert_double_eq_tol(seen.footprint, w * 0.5, 4 * CONE_REL * w);
    trace_cone(s, vec(-0.5, 0.25, 1), vec(0, 0, -1), 0, 0.01);
    ck_assert_double_eq_tol(seen.footprint, w * 0.5, 4 * CONE_REL * w);
    ray_scene_free(s);

    /* A sphere of radius 2 met at its equator (v = 1/2; sin(pi/2) = 1
    ** within an ulp). */
    s = new_scene();
    ck_assert_int_eq(ray_scene_add_material(s, &m, &mid), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 2, mid, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    trace_cone(s, vec(0, 0, 3), vec(0, 0, -1), 0, 0.01);
    ck_assert_double_eq_tol(seen.v, 0.5, 4 * DBL_EPSILON);
    ck_assert_double_eq_tol(seen.footprint,
                            w / (3.14159265358979323846 * 2 * sqrt(2.0)),
                            8 * CONE_REL * w);
    ray_scene_free(s);
}
END_TEST

/* Through an instance scaled by 2 (a similarity), a unit sphere's (u, v)
** per world length halves: the footprint of a sphere of radius 2. */
START_TEST(footprint_should_shrink_through_a_scaling_instance)
{
    cone_seen seen;
    ray_material m = recorder(&seen, RAY_EFFECT_TEXTURE);
    ray_scene *child = new_scene(), *s = new_scene();
    ray_transform x;
    unsigned mid;
    double w = 0.03;

    ck_assert_int_eq(ray_scene_add_material(child, &m, &mid), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(child, vec(0, 0, 0), 1, mid, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    ray_transform_identity(&x);
    x.m[0][0] = x.m[1][1] = x.m[2][2] = 2;
    ck_assert_int_eq(ray_scene_add_instance(s, child, &x, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    trace_cone(s, vec(0, 0, 5), vec(0, 0, -1), 0, 0.01);
    ck_assert_int_eq(seen.calls, 1);
    ck_assert_double_eq_tol(seen.width, w, CONE_REL * w);
    /* The instance's hit point and t carry the transform's rounding too:
    ** the same 8 CONE_REL as the plain sphere's. */
    ck_assert_double_eq_tol(seen.footprint,
                            w / (3.14159265358979323846 * 2 * sqrt(2.0)),
                            8 * CONE_REL * w);
    ray_scene_free(s);
    ray_scene_free(child);
}
END_TEST

/* Effects decide work: without RAY_EFFECT_TEXTURE in the scene, no cone;
** a context without ray_ctx_set_cone, none either. */
START_TEST(cone_should_be_zero_without_texture_effect_or_cone)
{
    cone_seen seen;
    ray_material m = recorder(&seen, RAY_EFFECT_SHADOW);
    ray_scene *s = new_scene();
    ray_ctx *ctx = NULL;
    ray_ray r = ray_from(vec(0, 0, 1), vec(0, 0, -1));
    ray_rgb c;
    unsigned mid;

    ck_assert_int_eq(ray_scene_add_material(s, &m, &mid), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 0, 1), mid,
                                         NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    trace_cone(s, vec(0, 0, 1), vec(0, 0, -1), 1, 1);
    ck_assert_int_eq(seen.calls, 1);
    ck_assert_double_eq(seen.width, 0);
    ck_assert_double_eq(seen.footprint, 0);
    ray_scene_free(s);

    m = recorder(&seen, RAY_EFFECT_TEXTURE);
    s = new_scene();
    ck_assert_int_eq(ray_scene_add_material(s, &m, &mid), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 0, 1), mid,
                                         NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(s, 1, &ctx), RAY_OK);
    ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1.0, &c), RAY_OK);
    ck_assert_int_eq(seen.calls, 1);
    ck_assert_double_eq(seen.width, 0);
    ck_assert_double_eq(seen.footprint, 0);
    /* Misuse leaves the cone as it was: still none. */
    ck_assert_int_eq(ray_ctx_set_cone(NULL, 0, 0.1), RAY_EINVAL);
    ck_assert_int_eq(ray_ctx_set_cone(ctx, -1e-300, 0.1), RAY_EINVAL);
    ck_assert_int_eq(ray_ctx_set_cone(ctx, 0, -0.1), RAY_EINVAL);
    ck_assert_int_eq(ray_ctx_set_cone(ctx, (double)NAN, 0.1), RAY_EINVAL);
    ck_assert_int_eq(ray_ctx_set_cone(ctx, 0, (double)NAN), RAY_EINVAL);
    ck_assert_int_eq(ray_ctx_set_cone(ctx, HUGE_VAL, 0.1), RAY_EINVAL);
    ck_assert_int_eq(ray_ctx_set_cone(ctx, 0, HUGE_VAL), RAY_EINVAL);
    ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1.0, &c), RAY_OK);
    ck_assert_double_eq(seen.width, 0);
    /* And a valid cone is then used, and 0, 0 turns it off again. */
    ck_assert_int_eq(ray_ctx_set_cone(ctx, 0, 0.5), RAY_OK);
    ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1.0, &c), RAY_OK);
    ck_assert_double_eq_tol(seen.width, 0.5, CONE_REL);
    ck_assert_int_eq(ray_ctx_set_cone(ctx, 0, 0), RAY_OK);
    ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1.0, &c), RAY_OK);
    ck_assert_double_eq(seen.width, 0);
    ray_ctx_free(ctx);
    ray_scene_free(s);
}
END_TEST

/* ----------------------------------------------------------- ray_render */

static ray_camera floor_camera(void)
{
    ray_camera cam;

    cam = (ray_camera){.look_at = {0, 0, -1}};
    cam.position = vec(0, 1, 0);
    cam.look_at = vec(0, 0.8, -10);
    cam.vfov = 40;
    return cam;
}

/* A camera ray's cone: one pixel's angle, / sqrt(samples). */
START_TEST(render_should_give_camera_rays_the_pixel_cone)
{
    cone_seen seen;
    ray_material m = recorder(&seen, RAY_EFFECT_TEXTURE);
    ray_scene *s = new_scene();
    ray_render_options o;
    ray_camera cam;
    unsigned mid, h = 50;
    float rgb[3 * 4];
    double pixel;

    ck_assert_int_eq(ray_scene_add_material(s, &m, &mid), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, -5), vec(0, 0, 1), mid,
                                         NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    cam = (ray_camera){.look_at = {0, 0, -1}};
    cam.vfov = 30;
    /* One pixel of an h-tall frame, rendered alone (rows 25 .. 26 of a
    ** 1-wide frame: the centre row), one thread: the recorder is not
    ** shared. */
    o = (ray_render_options){.width = 1, .height = h};
    ck_assert_int_eq(o.no_cones, 0);             /* cones on: the default */
    o.threads = 1;
    o.y0 = h / 2;
    o.y1 = h / 2 + 1;
    pixel = atan(2 * tan(15 * 3.14159265358979323846 / 180) / h);
    ck_assert_int_eq(ray_render(s, &cam, &o, rgb, NULL), RAY_OK);
    ck_assert_int_eq(seen.calls, 1);
    ck_assert_double_eq_tol(seen.width,
                            pixel * seen.t * sqrt(vdot(seen.dir, seen.dir)),
                            4 * CONE_REL * seen.width);
    o.samples = 4;
    ck_assert_int_eq(ray_render(s, &cam, &o, rgb, NULL), RAY_OK);
    ck_assert_double_eq_tol(seen.width,
                            pixel / 2 * seen.t *
                                sqrt(vdot(seen.dir, seen.dir)),
                            4 * CONE_REL * seen.width);
    o.no_cones = 1;
    ck_assert_int_eq(ray_render(s, &cam, &o, rgb, NULL), RAY_OK);
    ck_assert_double_eq(seen.width, 0);
    ray_scene_free(s);
}
END_TEST

/* A texture function that records the cone it was shaded with. */
static void record_texture(void *ud, const ray_shade_args *a, ray_rgb *out)
{
    cone_seen *s = ud;

    s->width = a->cone_width;
    s->footprint = a->footprint;
    s->t = a->hit->t;
    s->dir = a->ray->dir;
    s->calls++;
    *out = ray_rgb_make(1, 1, 1);
}

/*
** Which materials can read a ray's cone (ray__material_reads_cone, which
** ray_render asks before it gives camera rays one, issue 35): the
** built-in mirror, glass and plain Phong never; a Phong with a texture
** function (a user's, which gets the args), a checker as its squares, a
** user's callback always; a checker that holds itself, past the nesting
** bound, "may read".
*/
START_TEST(materials_should_say_whether_they_can_read_the_cone)
{
    static const ray_rgb chrome = {0.9, 0.9, 0.9};
    static const ray_glass_params glass = {.ior = 1.5};
    static ray_phong_params plain = {.diffuse = {0.5, 0.5, 0.5}};
    static ray_phong_params textured = {.diffuse = {0.5, 0.5, 0.5}};
    static ray_checker_params both_plain, one_textured, itself;
    static cone_seen seen;
    ray_material m, user = recorder(&seen, 0);

    textured.texture.fn = record_texture;
    textured.texture.ud = &seen;
    both_plain.even = ray_material_phong(&plain);
    both_plain.odd = ray_material_mirror(&chrome);
    one_textured.even = ray_material_glass(&glass);
    one_textured.odd = ray_material_phong(&textured);
    m = ray_material_mirror(&chrome);
    ck_assert_int_eq(ray__material_reads_cone(&m), 0);
    m = ray_material_glass(&glass);
    ck_assert_int_eq(ray__material_reads_cone(&m), 0);
    m = ray_material_phong(&plain);
    ck_assert_int_eq(ray__material_reads_cone(&m), 0);
    m = ray_material_phong(&textured);
    ck_assert_int_eq(ray__material_reads_cone(&m), 1);
    m = ray_material_checker(&both_plain);
    ck_assert_int_eq(ray__material_reads_cone(&m), 0);
    m = ray_material_checker(&one_textured);
    ck_assert_int_eq(ray__material_reads_cone(&m), 1);
    ck_assert_int_eq(ray__material_reads_cone(&user), 1);
    /* A checker whose squares are itself: bounded, and "may read". */
    itself.even = ray_material_checker(&itself);
    itself.odd = itself.even;
    ck_assert_int_eq(ray__material_reads_cone(&itself.even), 1);
    ck_assert_int_eq(ray__material_reads_cone(NULL), 0);
}
END_TEST

/* Render one pixel at the centre of an h-tall frame, one thread. */
static void render_centre(const ray_scene *s, unsigned h)
{
    ray_render_options o = {.width = 1, .height = 0};
    ray_camera cam = {.look_at = {0, 0, -1}};
    float rgb[3];

    cam.vfov = 30;
    o.height = h;
    o.threads = 1;
    o.y0 = h / 2;
    o.y1 = h / 2 + 1;
    ck_assert_int_eq(ray_render(s, &cam, &o, rgb, NULL), RAY_OK);
}

/*
** ray_render gives camera rays a cone only where some material can read
** it, and then it reaches them wherever they are: a texture function of
** a Phong square of a checker, a user's material in an instance's child.
** The width is the pixel's angle times the distance, as
** render_should_give_camera_rays_the_pixel_cone checks (same tolerance).
*/
START_TEST(render_should_carry_the_cone_to_whatever_can_read_it)
{
    static ray_phong_params textured = {.diffuse = {0.5, 0.5, 0.5}};
    static ray_checker_params squares;
    static cone_seen seen;
    static const ray_rgb chrome = {0.9, 0.9, 0.9};
    ray_scene *s = new_scene(), *child = new_scene(), *top = new_scene();
    ray_scene *mirrors = new_scene();
    ray_material m;
    cone_seen in_child;
    ray_transform id = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}}};
    unsigned mid, h = 50;
    double pixel = atan(2 * tan(15 * 3.14159265358979323846 / 180) / h);

    memset(&seen, 0, sizeof seen);
    textured.texture.fn = record_texture;
    textured.texture.ud = &seen;
    squares.even = ray_material_phong(&textured);
    squares.odd = squares.even;
    m = ray_material_checker(&squares);
    ck_assert_int_eq(ray_scene_add_material(s, &m, &mid), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, -5), vec(0, 0, 1), mid,
                                         NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    render_centre(s, h);
    ck_assert_int_eq(seen.calls, 1);
    ck_assert_double_gt(seen.width, 0);
    ck_assert_double_eq_tol(seen.width,
                            pixel * seen.t * sqrt(vdot(seen.dir, seen.dir)),
                            4 * CONE_REL * seen.width);
    /* The user's material one level down, behind an instance, after
    ** two instances of a child that cannot read the cone (a mirror off
    ** to the side), which must not end the search. */
    m = ray_material_mirror(&chrome);
    ck_assert_int_eq(ray_scene_add_material(mirrors, &m, &mid), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(mirrors, vec(50, 0, -5), 1, mid,
                                          NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(mirrors), RAY_OK);
    ck_assert_int_eq(ray_scene_add_instance(top, mirrors, &id, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_instance(top, mirrors, &id, NULL), RAY_OK);
    m = recorder(&in_child, RAY_EFFECT_TEXTURE);
    ck_assert_int_eq(ray_scene_add_material(child, &m, &mid), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(child, vec(0, 0, -5), 1, mid, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    ck_assert_int_eq(ray_scene_add_instance(top, child, &id, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    render_centre(top, h);
    ck_assert_int_eq(in_child.calls, 1);
    ck_assert_double_eq_tol(in_child.width,
                            pixel * in_child.t *
                                sqrt(vdot(in_child.dir, in_child.dir)),
                            4 * CONE_REL * in_child.width);
    ray_scene_free(top);
    ray_scene_free(mirrors);
    ray_scene_free(child);
    ray_scene_free(s);
}
END_TEST

/* A checkerboard image, 64 x 64 texels of 8 x 8 squares. */
static ray_image *checker_image(void)
{
    float rgb[64 * 64 * 3];
    ray_image *img = NULL;
    int x, y;

    for (y = 0; y < 64; y++)
        for (x = 0; x < 64; x++) {
            float c = ((x / 8 + y / 8) & 1) ? 0.9f : 0.1f;
            rgb[3 * (64 * y + x)] = c;
            rgb[3 * (64 * y + x) + 1] = c;
            rgb[3 * (64 * y + x) + 2] = c;
        }
    ck_assert_int_eq(ray_image_new(64, 64, rgb, &img), RAY_OK);
    return img;
}

/* The unfiltered texture: ray_image_sample whatever the footprint. */
static void plain_texture(void *ud, const ray_shade_args *a, ray_rgb *out)
{
    ray_image_sample(ud, a->u, a->v, 0, out);
}

/* A Phong floor textured by "tex" under a point light, to the horizon. */
static ray_scene *floor_scene(ray_phong_params *p, ray_texture tex)
{
    ray_scene *s = new_scene();
    ray_material m;
    ray_light l;
    unsigned mid;

    ray_phong_params_init(p);
    p->texture = tex;
    m = ray_material_phong(p);
    ck_assert_int_eq(ray_scene_add_material(s, &m, &mid), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 1, 0), mid,
                                         NULL), RAY_OK);
    memset(&l, 0, sizeof l);
    l.kind = RAY_LIGHT_DIRECTIONAL;
    l.direction = vec(0.3, -1, -0.2);
    l.intensity = ray_rgb_make(1, 1, 1);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    return s;
}

#define FW 48
#define FH 32

static void render_floor(ray_scene *s, unsigned threads, unsigned samples,
                         int cones, float *rgb)
{
    ray_camera cam = floor_camera();
    ray_render_options o;

    o = (ray_render_options){.width = FW, .height = FH};
    o.threads = threads;
    o.samples = samples;
    o.no_cones = !cones;
    ck_assert_int_eq(ray_render(s, &cam, &o, rgb, NULL), RAY_OK);
}

START_TEST(render_with_cones_should_be_the_same_at_any_thread_count)
{
    static float a[3 * FW * FH], b[3 * FW * FH];
    ray_image *img = checker_image();
    ray_phong_params p;
    ray_scene *s = floor_scene(&p, ray_texture_image(img));
    unsigned threads, samples;

    for (samples = 1; samples <= 4; samples += 3) {
        render_floor(s, 1, samples, 1, a);
        for (threads = 2; threads <= 3; threads++) {
            render_floor(s, threads, samples, 1, b);
            ck_assert_int_eq(memcmp(a, b, sizeof a), 0);
        }
    }
    ray_scene_free(s);
    ray_image_free(img);
}
END_TEST

/* cones = 0 is the image the unfiltered texture gives with cones on: the
** bytes of a library without cones; and cones = 1 filters (differs). */
START_TEST(render_without_cones_should_give_the_unfiltered_bytes)
{
    static float off[3 * FW * FH], plain[3 * FW * FH], on[3 * FW * FH];
    ray_image *img = checker_image();
    ray_phong_params p, q;
    ray_scene *s = floor_scene(&p, ray_texture_image(img));
    ray_texture t;
    ray_scene *u;

    t.fn = plain_texture;
    t.ud = img;
    u = floor_scene(&q, t);
    render_floor(s, 2, 4, 0, off);
    render_floor(u, 2, 4, 1, plain);
    render_floor(s, 2, 4, 1, on);
    ck_assert_int_eq(memcmp(off, plain, sizeof off), 0);
    ck_assert_int_ne(memcmp(off, on, sizeof off), 0);
    ray_scene_free(s);
    ray_scene_free(u);
    ray_image_free(img);
}
END_TEST

Suite *cones_suite(void)
{
    Suite *s = suite_create("cones");
    TCase *mip = tcase_create("mip");
    TCase *trace = tcase_create("trace");

    tcase_add_test(mip, mip_4x4_should_average_2x2_blocks);
    tcase_add_test(mip, mip_5x3_should_weigh_texels_by_area);
    tcase_add_test(mip, mip_1xN_should_halve_one_side_and_1x1_stay);
    tcase_add_test(mip, footprint_within_a_texel_should_be_the_plain_sample);
    tcase_add_test(mip, footprint_should_pick_and_blend_levels);
    tcase_add_test(mip, image_misuse_should_leave_outputs_untouched);
    tcase_add_test(mip, image_texture_should_use_the_footprint);
    suite_add_tcase(s, mip);
    tcase_add_test(trace, cone_should_grow_linearly_with_distance_on_a_plane);
    tcase_add_test(trace, cone_should_start_at_its_width);
    tcase_add_test(trace,
        cone_should_double_through_a_flat_mirror_at_twice_the_distance);
    tcase_add_test(trace,
        cone_should_widen_off_a_convex_and_narrow_off_a_concave_mirror);
    tcase_add_test(trace, cone_should_pass_head_on_through_a_pane_unchanged);
    tcase_add_test(trace, cone_should_narrow_inside_a_slab_and_recover_behind_it);
    tcase_add_test(trace, cone_should_focus_behind_a_glass_ball);
    tcase_add_test(trace, footprint_should_scale_by_each_kinds_uv_per_length);
    tcase_add_test(trace, footprint_should_shrink_through_a_scaling_instance);
    tcase_add_test(trace, cone_should_be_zero_without_texture_effect_or_cone);
    tcase_add_test(trace, render_should_give_camera_rays_the_pixel_cone);
    tcase_add_test(trace, materials_should_say_whether_they_can_read_the_cone);
    tcase_add_test(trace, render_should_carry_the_cone_to_whatever_can_read_it);
    tcase_add_test(trace,
        render_with_cones_should_be_the_same_at_any_thread_count);
    tcase_add_test(trace,
        render_without_cones_should_give_the_unfiltered_bytes);
    suite_add_tcase(s, trace);
    return s;
}
