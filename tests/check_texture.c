/* SPDX-License-Identifier: MIT */
/*
** check_texture.c -- PNG image textures (load, bilinear sampling, wrap),
** textured Phong, and the texture coordinates every primitive hands to a
** material.
*/
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include <png.h>

#include "tests.h"

static char *temp_path(const char *tag)
{
    static char buf[80];
    snprintf(buf, sizeof buf, "/tmp/libray-check-tex-%s-%ld.png", tag,
             (long)getpid());
    return buf;
}

/* A 4 x 2 image whose texels are all different: texel (x, y) = (x / 4,
** y / 2, 0.5), rows top to bottom. */
static void test_texels(float rgb[4 * 2 * 3])
{
    int x, y;

    for (y = 0; y < 2; y++)
        for (x = 0; x < 4; x++) {
            float *p = rgb + 3 * (y * 4 + x);
            p[0] = (float)x / 4.0f;
            p[1] = (float)y / 2.0f;
            p[2] = 0.5f;
        }
}

/* Write the test image as a 16-bit linear PNG and load it back. */
static ray_image *load_test_image(void)
{
    float rgb[4 * 2 * 3];
    ray_image *img = NULL;
    const char *path = temp_path("lin16");

    test_texels(rgb);
    ck_assert_int_eq(ray_write_png(path, rgb, 4, 2, 16), RAY_OK);
    ck_assert_int_eq(ray_image_load_png(path, &img), RAY_OK);
    unlink(path);
    ck_assert_ptr_nonnull(img);
    return img;
}

/* 16-bit samples round to 1/65535: half of that is the largest error. */
#define Q16 (0.5 / 65535.0 + 1e-7)

/*
** A 16-bit linear file (gAMA 1.0) loads to the same linear values; the
** texel centres sample to the texels themselves; t = 0 is the bottom row.
*/
START_TEST(image_should_load_16_bit_linear_png_exactly)
{
    ray_image *img = load_test_image();
    unsigned w = 0, h = 0;
    ray_rgb c;
    int x, y;

    ray_image_size(img, &w, &h);
    ck_assert_uint_eq(w, 4);
    ck_assert_uint_eq(h, 2);
    for (y = 0; y < 2; y++)
        for (x = 0; x < 4; x++) {
            /* Texel (x, y) from the top has its centre at s = (x + 1/2) / 4
            ** and t = 1 - (y + 1/2) / 2. */
            ck_assert_int_eq(ray_image_sample(img, (x + 0.5) / 4,
                                              1 - (y + 0.5) / 2, &c),
                             RAY_OK);
            ck_assert_double_eq_tol(c.r, x / 4.0, Q16);
            ck_assert_double_eq_tol(c.g, y / 2.0, Q16);
            ck_assert_double_eq_tol(c.b, 0.5, Q16);
        }
    ray_image_free(img);
}
END_TEST

/*
** Bilinear: halfway between two texel centres is their mean; s and t
** wrap (s + 1, s - 3 give the same); between the last and the first
** column the filter wraps too.  Exact inputs: the tolerance is the
** quantisation of the file (Q16) plus a few float roundings.
*/
START_TEST(image_should_filter_bilinearly_and_wrap)
{
    ray_image *img = load_test_image();
    ray_rgb a, b;

    /* Between columns 1 and 2 of the top row: r = (0.25 + 0.5) / 2. */
    ray_image_sample(img, 0.5, 0.75, &a);
    ck_assert_double_eq_tol(a.r, 0.375, Q16);
    ck_assert_double_eq_tol(a.g, 0.0, Q16);
    /* Between the rows (t = 0.5): g = (0 + 0.5) / 2. */
    ray_image_sample(img, 0.125, 0.5, &a);
    ck_assert_double_eq_tol(a.g, 0.25, Q16);
    ck_assert_double_eq_tol(a.r, 0.0, Q16);
    /* Wrap: the same colour one and three periods away. */
    ray_image_sample(img, 0.3, 0.6, &a);
    ray_image_sample(img, 1.3, -0.4, &b);
    ck_assert_double_eq_tol(a.r, b.r, 1e-12);
    ck_assert_double_eq_tol(a.g, b.g, 1e-12);
    ray_image_sample(img, -2.7, 3.6, &b);
    ck_assert_double_eq_tol(a.r, b.r, 1e-12);
    /* s = 0 sits halfway between column 3 (r = 0.75) and column 0 (r = 0). */
    ray_image_sample(img, 0.0, 0.75, &a);
    ck_assert_double_eq_tol(a.r, 0.375, Q16);
    ray_image_free(img);
}
END_TEST

/* An 8-bit file is sRGB-encoded: it decodes back to linear within the
** 8-bit quantisation, whose largest linear step (near 1) is ~0.0087:
** half of it, 0.0044, bounds the error. */
START_TEST(image_should_decode_8_bit_srgb)
{
    float rgb[4 * 2 * 3];
    ray_image *img = NULL;
    const char *path = temp_path("srgb8");
    ray_rgb c;

    test_texels(rgb);
    ck_assert_int_eq(ray_write_png(path, rgb, 4, 2, 8), RAY_OK);
    ck_assert_int_eq(ray_image_load_png(path, &img), RAY_OK);
    unlink(path);
    ray_image_sample(img, 3.5 / 4, 0.25, &c);   /* texel (3, 1) */
    ck_assert_double_eq_tol(c.r, 0.75, 0.0044);
    ck_assert_double_eq_tol(c.g, 0.5, 0.0044);
    ck_assert_double_eq_tol(c.b, 0.5, 0.0044);
    ray_image_free(img);
}
END_TEST

/*
** Alpha is composed on black, deterministically: libpng composes onto
** the output buffer when given no background, which the loader zeroes
** (it once held whatever the heap did: under ASan, 0xbe grey).  A fully
** transparent red texel is black; a half-transparent green one keeps no
** red or blue.  The file is written as 8-bit RGBA through libpng.
*/
START_TEST(image_should_compose_alpha_on_black)
{
    static const unsigned char rgba[8] = {255, 0, 0, 0, 0, 255, 0, 128};
    const char *path = temp_path("rgba");
    png_image png;
    ray_image *img = NULL;
    ray_rgb c;

    memset(&png, 0, sizeof png);
    png.version = PNG_IMAGE_VERSION;
    png.width = 2;
    png.height = 1;
    png.format = PNG_FORMAT_RGBA;
    ck_assert(png_image_write_to_file(&png, path, 0, rgba, 0, NULL));
    ck_assert_int_eq(ray_image_load_png(path, &img), RAY_OK);
    unlink(path);
    ray_image_sample(img, 0.25, 0.5, &c);      /* texel 0's centre */
    ck_assert_double_eq(c.r, 0);
    ck_assert_double_eq(c.g, 0);
    ck_assert_double_eq(c.b, 0);
    ray_image_sample(img, 0.75, 0.5, &c);      /* texel 1's centre */
    ck_assert_double_eq(c.r, 0);
    ck_assert_double_gt(c.g, 0.1);
    ck_assert_double_eq(c.b, 0);
    ray_image_free(img);
}
END_TEST

START_TEST(image_should_reject_bad_files_and_arguments)
{
    ray_image *img = NULL;
    ray_rgb c = {7, 7, 7};
    const char *path = temp_path("bad");
    FILE *fp;
    float rgb[4 * 2 * 3];
    long size;
    char *bytes;

    ck_assert_int_eq(ray_image_load_png(NULL, &img), RAY_EINVAL);
    ck_assert_int_eq(ray_image_load_png(path, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_image_load_png("/nonexistent/dir/x.png", &img),
                     RAY_EIO);
    ck_assert_ptr_null(img);
    /* Not a PNG. */
    fp = fopen(path, "wb");
    ck_assert_ptr_nonnull(fp);
    fputs("P3\n1 1\n255\n0 0 0\n", fp);
    fclose(fp);
    ck_assert_int_eq(ray_image_load_png(path, &img), RAY_EPNG);
    ck_assert_ptr_null(img);
    /* A real PNG cut in half. */
    test_texels(rgb);
    ck_assert_int_eq(ray_write_png(path, rgb, 4, 2, 16), RAY_OK);
    fp = fopen(path, "rb");
    fseek(fp, 0, SEEK_END);
    size = ftell(fp);
    rewind(fp);
    bytes = malloc((size_t)size);
    ck_assert_uint_eq(fread(bytes, 1, (size_t)size, fp), (size_t)size);
    fclose(fp);
    fp = fopen(path, "wb");
    fwrite(bytes, 1, (size_t)size / 2, fp);
    fclose(fp);
    free(bytes);
    ck_assert_int_eq(ray_image_load_png(path, &img), RAY_EPNG);
    ck_assert_ptr_null(img);
    unlink(path);
    /* Sampling: NULLs and non-finite coordinates write nothing. */
    img = load_test_image();
    ck_assert_int_eq(ray_image_sample(NULL, 0, 0, &c), RAY_EINVAL);
    ck_assert_int_eq(ray_image_sample(img, 0, 0, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_image_sample(img, NAN, 0, &c), RAY_EINVAL);
    ck_assert_int_eq(ray_image_sample(img, 0, HUGE_VAL, &c), RAY_EINVAL);
    ck_assert_double_eq(c.r, 7);
    /* Huge coordinates keep their fraction's digits: 1e9 + 0.125 is
    ** exact in double. */
    {
        ray_rgb a, b;
        ray_image_sample(img, 0.125, 0.25, &a);
        ray_image_sample(img, 1e9 + 0.125, 0.25, &b);
        ck_assert_double_eq_tol(a.r, b.r, 1e-12);
    }
    ray_image_free(img);
    ray_image_free(NULL);
    ray_image_size(NULL, NULL, NULL);
    /* No image, no texture: a material then keeps its plain colour. */
    ck_assert(ray_texture_image(NULL).fn == NULL);
}
END_TEST

/* ------------------------------------- texture coordinates in scenes */

/* A texture that records the (u, v) it is asked for and returns white. */
typedef struct uv_probe {
    double u, v;
    int calls;
} uv_probe;

static void probe_texture(void *ud, const ray_shade_args *a, ray_rgb *out)
{
    uv_probe *p = ud;
    p->u = a->u;
    p->v = a->v;
    p->calls++;
    *out = rgb_of(1, 1, 1);
}

/* Trace one primary ray through a committed scene; the colour. */
static ray_rgb trace_one(const ray_scene *s, ray_ray r)
{
    ray_ctx *ctx;
    ray_rgb c = {-1, -1, -1};

    ck_assert_int_eq(ray_ctx_new(s, 1, &ctx), RAY_OK);
    ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1.0, &c), RAY_OK);
    ray_ctx_free(ctx);
    return c;
}

/*
** Every primitive hands the material the (s, t) of its own hit: the
** texture sees args->u, v equal to the bare function's hit.u, v, for a
** sphere, a plane, a torus, a Bezier patch and an implicit surface with a
** uv callback.  The same doubles flow through, so the comparison is exact.
*/
START_TEST(texture_should_see_every_primitives_coordinates)
{
    static ray_phong_params params;
    static uv_probe probe;
    ray_torus_params torus = {{0, 0, 0}, {0, 0, 1}, 1.0, 0.25};
    ray_vec3 cp[16];
    ray_implicit_surface is;
    int kind, i, j;

    for (i = 0; i < 4; i++)
        for (j = 0; j < 4; j++)
            cp[4 * i + j] = vec(j - 1.5, i - 1.5, 0.1 * (i % 2));
    ck_assert_int_eq(ray_implicit_torus(&torus, &is), RAY_OK);
    memset(&params, 0, sizeof params);
    params.diffuse = rgb_of(1, 1, 1);
    params.texture.fn = probe_texture;
    params.texture.ud = &probe;
    for (kind = 0; kind < 5; kind++) {
        ray_scene *s;
        ray_material m = ray_material_phong(&params);
        ray_ray r = ray_from(vec(0.3, 1.05, 5), vec(0, 0, -1));
        ray_hit h;
        int hit = 0;
        ck_assert(m.effects & RAY_EFFECT_TEXTURE);
        ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_material(s, &m, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_set_ambient(s, rgb_of(1, 1, 1)), RAY_OK);
        switch (kind) {
        case 0:
            ray_scene_add_sphere(s, vec(0, 0, 0), 1.5, 0, NULL);
            hit = ray_sphere(&r, vec(0, 0, 0), 1.5, &h);
            break;
        case 1:
            ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 0, 1), 0, NULL);
            hit = ray_plane(&r, vec(0, 0, 0), vec(0, 0, 1), &h);
            break;
        case 2:
            ray_scene_add_torus(s, &torus, 0, NULL);
            hit = ray_torus(&r, &torus, &h);
            break;
        case 3: {
            ray_parametric_surface ps;
            ray_scene_add_bezier(s, cp, 0, NULL);
            ck_assert_int_eq(ray_bezier_surface(cp, &ps), RAY_OK);
            hit = ray_parametric(&r, &ps, &h);
            break;
        }
        default:
            ray_scene_add_implicit(s, &is, 0, NULL);
            hit = ray_implicit(&r, &is, &h);
            break;
        }
        ck_assert_int_eq(hit, 1);
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        ck_assert(ray_scene_effects(s) & RAY_EFFECT_TEXTURE);
        probe.calls = 0;
        trace_one(s, r);
        ck_assert_int_eq(probe.calls, 1);
        ck_assert_double_eq(probe.u, h.u);
        ck_assert_double_eq(probe.v, h.v);
        ray_scene_free(s);
    }
}
END_TEST

/*
** A plane textured with an image: lit by ambient light 1 only, a ray
** straight down at (x, 1, z) meets y = 0 at (u, v) = (x, -z) (ray_plane's
** frame for +y: t1 = +x, t2 = -z), so the colour is diffuse times the
** image sampled there.  The same arithmetic: 1e-12.
*/
START_TEST(textured_phong_should_multiply_diffuse_by_the_image)
{
    static ray_phong_params params;
    ray_image *img = load_test_image();
    ray_scene *s;
    ray_material m;
    int n;

    memset(&params, 0, sizeof params);
    params.diffuse = rgb_of(0.5, 1, 2);
    params.texture = ray_texture_image(img);
    ck_assert(params.texture.fn != NULL);
    m = ray_material_phong(&params);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 1, 0), 0,
                                         NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_set_ambient(s, rgb_of(1, 1, 1)), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    for (n = 0; n < 20; n++) {
        double x = 0.37 * n - 3, z = 0.21 * n - 1;
        ray_rgb c = trace_one(s, ray_from(vec(x, 1, z), vec(0, -1, 0))), t;
        ck_assert_int_eq(ray_image_sample(img, x, -z, &t), RAY_OK);
        ck_assert_double_eq_tol(c.r, 0.5 * t.r, 1e-12);
        ck_assert_double_eq_tol(c.g, 1.0 * t.g, 1e-12);
        ck_assert_double_eq_tol(c.b, 2.0 * t.b, 1e-12);
    }
    ray_scene_free(s);
    ray_image_free(img);
}
END_TEST

Suite *texture_suite(void)
{
    Suite *s = suite_create("texture");
    TCase *core = tcase_create("core");

    tcase_add_test(core, image_should_load_16_bit_linear_png_exactly);
    tcase_add_test(core, image_should_filter_bilinearly_and_wrap);
    tcase_add_test(core, image_should_decode_8_bit_srgb);
    tcase_add_test(core, image_should_reject_bad_files_and_arguments);
    tcase_add_test(core, image_should_compose_alpha_on_black);
    tcase_add_test(core, texture_should_see_every_primitives_coordinates);
    tcase_add_test(core, textured_phong_should_multiply_diffuse_by_the_image);
    suite_add_tcase(s, core);
    return s;
}
