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
#include "image.h"

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
    ck_assert_int_eq(ray_image_sample_footprint(one, 0.3, 0.7, 1e9, &c),
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
        ck_assert_int_eq(ray_image_sample(img, s, t, &a), RAY_OK);
        ck_assert_int_eq(ray_image_sample_footprint(img, s, t, w, &b),
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
    ck_assert_int_eq(ray_image_sample_footprint(img, s, t, 0.25, &at1),
                     RAY_OK);
    want = (2 * 0.7 + 0.5) + 8 * (2 * 1.1 + 0.5);
    /* The bilinear weights carry a few roundings of 2^-53 on values
    ** below 64: 1e-12 is far above them and far below a texel step. */
    ck_assert_double_eq_tol(at1.r, want, 1e-12);
    ck_assert_int_eq(ray_image_sample_footprint(img, s, t, 0.5, &at2),
                     RAY_OK);
    ck_assert_int_eq(ray_image_sample_footprint(img, s, t, sqrt(0.125),
                                                &mid), RAY_OK);
    /* lambda = 1.5: halfway between levels 1 and 2 (the blend's own
    ** roundings, with log2's, stay within 1e-12 of values below 64). */
    ck_assert_double_eq_tol(mid.r, 0.5 * (at1.r + at2.r), 1e-12);
    ck_assert_double_eq_tol(mid.b, 0.5 * (at1.b + at2.b), 1e-12);
    /* Past the last level (lambda >= 3), +Inf included: the mean. */
    ck_assert_int_eq(ray_image_sample_footprint(img, s, t, HUGE_VAL, &top),
                     RAY_OK);
    ck_assert_double_eq(top.r, 31.5);
    ck_assert_double_eq(top.b, 3.5);
    ck_assert_int_eq(ray_image_sample_footprint(img, s, t, 1.0, &top),
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
    ck_assert_int_eq(ray_image_sample_footprint(NULL, 0, 0, 0, &c),
                     RAY_EINVAL);
    ck_assert_int_eq(ray_image_sample_footprint(good, 0, 0, 0, NULL),
                     RAY_EINVAL);
    ck_assert_int_eq(ray_image_sample_footprint(good, 0, 0, NAN, &c),
                     RAY_EINVAL);
    ck_assert_int_eq(ray_image_sample_footprint(good, 0, 0, -1e-300, &c),
                     RAY_EINVAL);
    ck_assert_int_eq(ray_image_sample_footprint(good, NAN, 0, 1, &c),
                     RAY_EINVAL);
    ck_assert_int_eq(ray_image_sample_footprint(good, 0, HUGE_VAL, 1, &c),
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
    ck_assert_int_eq(ray_image_sample(img, 0.3, 0.6, &want), RAY_OK);
    ck_assert(rgb_same(got, want));
    a.footprint = 0.3;
    tex.fn(tex.ud, &a, &got);
    ck_assert_int_eq(ray_image_sample_footprint(img, 0.3, 0.6, 0.3, &want),
                     RAY_OK);
    ck_assert(rgb_same(got, want));
    ray_image_free(img);
}
END_TEST

Suite *cones_suite(void)
{
    Suite *s = suite_create("cones");
    TCase *mip = tcase_create("mip");

    tcase_add_test(mip, mip_4x4_should_average_2x2_blocks);
    tcase_add_test(mip, mip_5x3_should_weigh_texels_by_area);
    tcase_add_test(mip, mip_1xN_should_halve_one_side_and_1x1_stay);
    tcase_add_test(mip, footprint_within_a_texel_should_be_the_plain_sample);
    tcase_add_test(mip, footprint_should_pick_and_blend_levels);
    tcase_add_test(mip, image_misuse_should_leave_outputs_untouched);
    tcase_add_test(mip, image_texture_should_use_the_footprint);
    suite_add_tcase(s, mip);
    return s;
}
