/* SPDX-License-Identifier: MIT */
/*
** check_png.c -- ray_image_to_srgb8 and ray_write_png, checked by reading
** the file back with libpng and comparing bytes (stb's image_write_test
** idea: a tiny asymmetric image, different colours on R and B so a channel
** swap or a flip shows).
*/
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include <png.h>

#include "tests.h"

#define W 5
#define H 3

/* An 'L' of red on blue, plus one grey pixel and out-of-range values. */
static void test_image(float *rgb)
{
    int x, y;

    for (y = 0; y < H; y++)
        for (x = 0; x < W; x++) {
            float *p = rgb + 3 * (y * W + x);
            int on = x == 0 || y == H - 1;
            p[0] = on ? 1.0f : 0.0f;
            p[1] = 0.0f;
            p[2] = on ? 0.0f : 1.0f;
        }
    rgb[3 * 7 + 0] = 0.5f;    /* (2,1): mid grey, NaN, over-range */
    rgb[3 * 7 + 1] = NAN;
    rgb[3 * 7 + 2] = 7.0f;
}

static char *temp_path(const char *tag)
{
    static char buf[64];
    snprintf(buf, sizeof buf, "/tmp/libray-check-%s-%ld.png", tag,
             (long)getpid());
    return buf;
}

START_TEST(srgb8_should_follow_the_srgb_curve)
{
    float in[12] = {0.0f, 1.0f, 0.5f, 0.0031308f, 0.18f, -1.0f,
                    2.0f, NAN, INFINITY, -INFINITY, 0.001f, 0.9f};
    unsigned char out[12];

    ck_assert_int_eq(ray_image_to_srgb8(in, 4, out), RAY_OK);
    /* Reference values: 255 * srgb(x) rounded, computed by hand from
    ** IEC 61966-2-1 (0.5 -> 0.73536 -> 187.5 -> 188; 0.18 -> 0.46135 ->
    ** 117.6 -> 118; 0.0031308 -> 0.04045 -> 10.3 -> 10; 0.001 ->
    ** 0.01292 -> 3.29 -> 3; 0.9 -> 0.95477 -> 243.5 -> 243 or 244). */
    ck_assert_uint_eq(out[0], 0);
    ck_assert_uint_eq(out[1], 255);
    ck_assert_uint_eq(out[2], 188);
    ck_assert_uint_eq(out[3], 10);
    ck_assert_uint_eq(out[4], 118);
    ck_assert_uint_eq(out[5], 0);
    ck_assert_uint_eq(out[6], 255);
    ck_assert_uint_eq(out[7], 0);
    ck_assert_uint_eq(out[8], 255);
    ck_assert_uint_eq(out[9], 0);
    ck_assert_uint_eq(out[10], 3);
    ck_assert(out[11] == 243 || out[11] == 244);
    ck_assert_int_eq(ray_image_to_srgb8(NULL, 1, out), RAY_EINVAL);
    ck_assert_int_eq(ray_image_to_srgb8(in, 1, NULL), RAY_EINVAL);
}
END_TEST

START_TEST(png8_should_read_back_identical_bytes)
{
    float rgb[3 * W * H];
    unsigned char expect[3 * W * H], got[3 * W * H];
    png_image img;
    char *path = temp_path("8");

    test_image(rgb);
    ray_image_to_srgb8(rgb, W * H, expect);
    ck_assert_int_eq(ray_write_png(path, rgb, W, H, 8), RAY_OK);
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    ck_assert(png_image_begin_read_from_file(&img, path));
    ck_assert_uint_eq(img.width, W);
    ck_assert_uint_eq(img.height, H);
    img.format = PNG_FORMAT_RGB;
    ck_assert(png_image_finish_read(&img, NULL, got, 0, NULL));
    ck_assert_mem_eq(got, expect, sizeof got);
    /* Spot checks: top-left red, top-right blue, bottom row red. */
    ck_assert_uint_eq(got[0], 255);
    ck_assert_uint_eq(got[2], 0);
    ck_assert_uint_eq(got[3 * 4 + 0], 0);
    ck_assert_uint_eq(got[3 * 4 + 2], 255);
    ck_assert_uint_eq(got[3 * (2 * W + 3) + 0], 255);
    remove(path);
}
END_TEST

START_TEST(png16_should_keep_linear_values)
{
    float rgb[3 * W * H];
    png_uint_16 got[3 * W * H];
    png_image img;
    char *path = temp_path("16");

    test_image(rgb);
    ck_assert_int_eq(ray_write_png(path, rgb, W, H, 16), RAY_OK);
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    ck_assert(png_image_begin_read_from_file(&img, path));
    img.format = PNG_FORMAT_LINEAR_RGB;
    ck_assert(png_image_finish_read(&img, NULL, got, 0, NULL));
    ck_assert_uint_eq(got[0], 65535);
    ck_assert_uint_eq(got[2], 0);
    /* 0.5 -> 32768 (0.5 * 65535 + 0.5 rounds down to 32768). */
    ck_assert_uint_eq(got[3 * 7 + 0], 32768);
    ck_assert_uint_eq(got[3 * 7 + 1], 0);
    ck_assert_uint_eq(got[3 * 7 + 2], 65535);
    remove(path);
}
END_TEST

START_TEST(png_should_report_bad_arguments_and_io_errors)
{
    float rgb[3 * W * H];
    const char *bad = "/nonexistent-dir-libray/x.png";

    test_image(rgb);
    ck_assert_int_eq(ray_write_png(NULL, rgb, W, H, 8), RAY_EINVAL);
    ck_assert_int_eq(ray_write_png("/tmp/x.png", NULL, W, H, 8), RAY_EINVAL);
    ck_assert_int_eq(ray_write_png("/tmp/x.png", rgb, 0, H, 8), RAY_EINVAL);
    ck_assert_int_eq(ray_write_png("/tmp/x.png", rgb, W, 0, 8), RAY_EINVAL);
    ck_assert_int_eq(ray_write_png("/tmp/x.png", rgb, W, H, 12), RAY_EINVAL);
    ck_assert_int_eq(ray_write_png("/tmp/x.png", rgb, 0x7fffffffu, 0x7fffffffu, 8),
                     RAY_EINVAL);
    errno = 0;
    ck_assert_int_eq(ray_write_png(bad, rgb, W, H, 8), RAY_EIO);
    ck_assert_int_ne(errno, 0);
    /* A full device: the write fails at flush time and no file remains
    ** (only where /dev/full exists, as on Linux). */
    if (access("/dev/full", W_OK) == 0)
        ck_assert_int_eq(ray_write_png("/dev/full", rgb, W, H, 8), RAY_EIO);
}
END_TEST

Suite *png_suite(void)
{
    Suite *s = suite_create("png");
    TCase *tc = tcase_create("io");

    tcase_add_test(tc, srgb8_should_follow_the_srgb_curve);
    tcase_add_test(tc, png8_should_read_back_identical_bytes);
    tcase_add_test(tc, png16_should_keep_linear_values);
    tcase_add_test(tc, png_should_report_bad_arguments_and_io_errors);
    suite_add_tcase(s, tc);
    return s;
}
