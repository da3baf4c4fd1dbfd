/* SPDX-License-Identifier: MIT */
/*
** check_texture.c -- PNG image textures (load, bilinear sampling, wrap),
** textured Phong, and the texture coordinates every primitive hands to a
** material.  In a library built without libpng (RAY_TEST_PNG 0, make
** PNG=0) the loading tests give way to one that the PNG calls return
** RAY_ENOTSUP, and the sampling tests take their image from image.c.
*/
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>
#if defined(_WIN32)
#define WIN32_LEAN_AND_MEAN
#include <windows.h>
#include <psapi.h>
#else
#include <sys/resource.h>
#endif

#include "tempfiles.h"
#include "prim/prim.h"         /* ray__implicit_torus */
#include "tests.h"

#ifndef RAY_TEST_PNG
#define RAY_TEST_PNG 1
#endif
#if RAY_TEST_PNG
#include <png.h>
#else
#include "image/image.h"
#endif

#if RAY_TEST_PNG
static char *temp_path(const char *tag)
{
    static char buf[512];
    char name[80];
    snprintf(name, sizeof name, "libray-check-tex-%s-%ld.png", tag,
             (long)getpid());
    test_tmp_path(buf, sizeof buf, name);
    return buf;
}
#endif

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

#if RAY_TEST_PNG
/* Write the test image as a 16-bit linear PNG and load it back. */
static ray_image *load_test_image(void)
{
    float rgb[4 * 2 * 3];
    ray_image *img = NULL;
    const char *path = temp_path("lin16");

    test_texels(rgb);
    ck_assert_int_eq(ray_write_png(path, rgb, 4, 2, 16), RAY_OK);
    ck_assert_int_eq(ray_image_load_png(path, NULL, &img), RAY_OK);
    unlink(path);
    ck_assert_ptr_nonnull(img);
    return img;
}
#else
/* No PNG: the test image made as the loader would make it. */
static ray_image *load_test_image(void)
{
    float *rgb = malloc(sizeof(float) * 4 * 2 * 3);
    ray_image *img;

    ck_assert_ptr_nonnull(rgb);
    test_texels(rgb);
    img = ray__image_new(4, 2, rgb);
    ck_assert_ptr_nonnull(img);
    return img;
}
#endif

/* 16-bit samples round to 1/65535: half of that is the largest error. */
#define Q16 (0.5 / 65535.0 + 1e-7)

/*
** A 16-bit linear file (gAMA 1.0) loads to the same linear values; the
** texel centres sample to the texels themselves; t = 0 is the bottom row.
*/
#if RAY_TEST_PNG
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
                                              1 - (y + 0.5) / 2, 0, &c),
                             RAY_OK);
            ck_assert_double_eq_tol(c.r, x / 4.0, Q16);
            ck_assert_double_eq_tol(c.g, y / 2.0, Q16);
            ck_assert_double_eq_tol(c.b, 0.5, Q16);
        }
    ray_image_free(img);
}
END_TEST
#endif

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
    ray_image_sample(img, 0.5, 0.75, 0, &a);
    ck_assert_double_eq_tol(a.r, 0.375, Q16);
    ck_assert_double_eq_tol(a.g, 0.0, Q16);
    /* Between the rows (t = 0.5): g = (0 + 0.5) / 2. */
    ray_image_sample(img, 0.125, 0.5, 0, &a);
    ck_assert_double_eq_tol(a.g, 0.25, Q16);
    ck_assert_double_eq_tol(a.r, 0.0, Q16);
    /* Wrap: the same colour one and three periods away. */
    ray_image_sample(img, 0.3, 0.6, 0, &a);
    ray_image_sample(img, 1.3, -0.4, 0, &b);
    ck_assert_double_eq_tol(a.r, b.r, 1e-12);
    ck_assert_double_eq_tol(a.g, b.g, 1e-12);
    ray_image_sample(img, -2.7, 3.6, 0, &b);
    ck_assert_double_eq_tol(a.r, b.r, 1e-12);
    /* s = 0 sits halfway between column 3 (r = 0.75) and column 0 (r = 0). */
    ray_image_sample(img, 0.0, 0.75, 0, &a);
    ck_assert_double_eq_tol(a.r, 0.375, Q16);
    ray_image_free(img);
}
END_TEST

/* An 8-bit file is sRGB-encoded: it decodes back to linear within the
** 8-bit quantisation, whose largest linear step (near 1) is ~0.0087:
** half of it, 0.0044, bounds the error. */
#if RAY_TEST_PNG
START_TEST(image_should_decode_8_bit_srgb)
{
    float rgb[4 * 2 * 3];
    ray_image *img = NULL;
    const char *path = temp_path("srgb8");
    ray_rgb c;

    test_texels(rgb);
    ck_assert_int_eq(ray_write_png(path, rgb, 4, 2, 8), RAY_OK);
    ck_assert_int_eq(ray_image_load_png(path, NULL, &img), RAY_OK);
    unlink(path);
    ray_image_sample(img, 3.5 / 4, 0.25, 0, &c);   /* texel (3, 1) */
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
    ck_assert_int_eq(ray_image_load_png(path, NULL, &img), RAY_OK);
    unlink(path);
    ray_image_sample(img, 0.25, 0.5, 0, &c);      /* texel 0's centre */
    ck_assert_double_eq(c.r, 0);
    ck_assert_double_eq(c.g, 0);
    ck_assert_double_eq(c.b, 0);
    ray_image_sample(img, 0.75, 0.5, 0, &c);      /* texel 1's centre */
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

    ck_assert_int_eq(ray_image_load_png(NULL, NULL, &img), RAY_EINVAL);
    ck_assert_int_eq(ray_image_load_png(path, NULL, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_image_load_png("/nonexistent/dir/x.png", NULL, &img),
                     RAY_EIO);
    ck_assert_ptr_null(img);
    /* Not a PNG. */
    fp = fopen(path, "wb");
    ck_assert_ptr_nonnull(fp);
    fputs("P3\n1 1\n255\n0 0 0\n", fp);
    fclose(fp);
    ck_assert_int_eq(ray_image_load_png(path, NULL, &img), RAY_EPNG);
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
    ck_assert_int_eq(ray_image_load_png(path, NULL, &img), RAY_EPNG);
    ck_assert_ptr_null(img);
    unlink(path);
    /* Sampling: NULLs and non-finite coordinates write nothing. */
    img = load_test_image();
    ck_assert_int_eq(ray_image_sample(NULL, 0, 0, 0, &c), RAY_EINVAL);
    ck_assert_int_eq(ray_image_sample(img, 0, 0, 0, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_image_sample(img, (double)NAN, 0, 0, &c), RAY_EINVAL);
    ck_assert_int_eq(ray_image_sample(img, 0, HUGE_VAL, 0, &c), RAY_EINVAL);
    ck_assert_double_eq(c.r, 7);
    /* Huge coordinates keep their fraction's digits: 1e9 + 0.125 is
    ** exact in double. */
    {
        ray_rgb a, b;
        ray_image_sample(img, 0.125, 0.25, 0, &a);
        ray_image_sample(img, 1e9 + 0.125, 0.25, 0, &b);
        ck_assert_double_eq_tol(a.r, b.r, 1e-12);
    }
    ray_image_free(img);
    ray_image_free(NULL);
    ray_image_size(NULL, NULL, NULL);
    /* No image, no texture: a material then keeps its plain colour. */
    ck_assert(ray_texture_image(NULL).fn == NULL);
}
END_TEST

/* -------------------------------------------- files libpng's simplified
** API cannot write: interlace, palettes with tRNS, low depths, gAMA */

typedef struct png_spec {
    unsigned width, height;
    int depth, color_type, interlace;
    const png_color *palette;
    int palette_size;
    const png_byte *trns;        /* palette alpha, or NULL */
    int trns_size;
    double gamma;                /* gAMA; 0: none */
    const unsigned char *rows;   /* height rows as libpng packs them */
} png_spec;

static void write_rows(png_structp png, const png_spec *sp, size_t rowbytes)
{
    int pass, passes = png_set_interlace_handling(png);
    unsigned y;

    for (pass = 0; pass < passes; pass++)
        for (y = 0; y < sp->height; y++)
            png_write_row(png, sp->rows + y * rowbytes);
}

static void write_full_png(const char *path, const png_spec *sp)
{
    FILE *fp = fopen(path, "wb");
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL,
                                              NULL, NULL);
    png_infop info = png_create_info_struct(png);

    ck_assert(fp != NULL && png != NULL && info != NULL);
    if (setjmp(png_jmpbuf(png)))
        ck_abort_msg("libpng failed to write %s", path);
    png_init_io(png, fp);
    png_set_IHDR(png, info, sp->width, sp->height, sp->depth, sp->color_type,
                 sp->interlace, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    if (sp->palette != NULL)
        png_set_PLTE(png, info, sp->palette, sp->palette_size);
    if (sp->trns != NULL)
        png_set_tRNS(png, info, sp->trns, sp->trns_size, NULL);
    if (sp->gamma > 0)
        png_set_gAMA(png, info, sp->gamma);
    png_write_info(png, info);
    write_rows(png, sp, png_get_rowbytes(png, info));
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    ck_assert_int_eq(fclose(fp), 0);
}

static ray_image *load_spec(const png_spec *sp)
{
    const char *path = temp_path("spec");
    ray_image *img = NULL;

    write_full_png(path, sp);
    ck_assert_int_eq(ray_image_load_png(path, NULL, &img), RAY_OK);
    unlink(path);
    return img;
}

/* The texel (x, y), counted from the top, by sampling at its centre.
** s * width - 1/2 lands within a few ulps of x, so the neighbours weigh
** less than 1e-15: 1e-9 is far above that and far below any sample step. */
#define CENTRE_TOL 1e-9

static ray_rgb texel(const ray_image *img, unsigned x, unsigned y)
{
    unsigned w = 0, h = 0;
    ray_rgb c = {-1, -1, -1};

    ray_image_size(img, &w, &h);
    ck_assert_int_eq(ray_image_sample(img, (x + 0.5) / w,
                                      1 - (y + 0.5) / h, 0, &c),
                     RAY_OK);
    return c;
}

/*
** Adam7: a 9 x 5 16-bit linear image, interlaced, loads to the same values
** as the plain one (each pass's pixels are put back in place by the
** loader).  9 x 5 leaves some passes narrow or empty.  The values are
** distinct 16-bit codes v, which load as v / 65535 rounded to float: half
** a float ulp, below FLT_EPSILON for values up to 1, plus CENTRE_TOL.
*/
START_TEST(image_should_load_interlaced_files)
{
    enum { W = 9, H = 5 };
    static unsigned char rows[H * W * 6];
    png_spec sp;
    ray_image *plain, *adam7;
    unsigned x, y, k;

    for (y = 0; y < H; y++)
        for (x = 0; x < W; x++)
            for (k = 0; k < 3; k++) {
                unsigned v = 1000 * (9 * y + x) + 300 * k + 7;
                rows[6 * (W * y + x) + 2 * k] = (unsigned char)(v >> 8);
                rows[6 * (W * y + x) + 2 * k + 1] = (unsigned char)v;
            }
    memset(&sp, 0, sizeof sp);
    sp.width = W;
    sp.height = H;
    sp.depth = 16;
    sp.color_type = PNG_COLOR_TYPE_RGB;
    sp.rows = rows;
    sp.interlace = PNG_INTERLACE_NONE;
    plain = load_spec(&sp);
    sp.interlace = PNG_INTERLACE_ADAM7;
    adam7 = load_spec(&sp);
    for (y = 0; y < H; y++)
        for (x = 0; x < W; x++) {
            ray_rgb a = texel(plain, x, y), b = texel(adam7, x, y);
            double v = (1000.0 * (9 * y + x) + 7) / 65535.0;
            ck_assert_double_eq(a.r, b.r);
            ck_assert_double_eq(a.g, b.g);
            ck_assert_double_eq(a.b, b.b);
            ck_assert_double_eq_tol(a.r, v, CENTRE_TOL + (double)FLT_EPSILON);
            ck_assert_double_eq_tol(a.b, v + 600.0 / 65535.0,
                                    CENTRE_TOL + (double)FLT_EPSILON);
        }
    ray_image_free(plain);
    ray_image_free(adam7);
}
END_TEST

/*
** A 2-bit palette with tRNS: opaque red, a fully transparent entry
** (black), white at alpha 128/255 (composed on black: 128/255, since sRGB
** 255 is linear 1), and black without a tRNS entry (opaque).  A 4-bit
** grey file with gAMA 1.0: codes 5 and 15 of 15 are linear 1/3 and 1.
** Grey with alpha, 8-bit, no gamma: sRGB code 200 times alpha 128/255.
** 16-bit grey with gAMA 0.5 goes through the 16-bit table.
** Tolerances: a float rounding of each factor, 2 FLT_EPSILON.
*/
START_TEST(image_should_expand_palettes_grey_and_alpha)
{
    static const png_color palette[4] = {
        {255, 0, 0}, {0, 128, 255}, {255, 255, 255}, {0, 0, 0}};
    static const png_byte trns[3] = {255, 0, 128};
    static const unsigned char indices[1] = {0x1b};   /* 0, 1, 2, 3 */
    static const unsigned char grey4[1] = {0x5f};     /* 5, 15 */
    static const unsigned char grey_alpha[2] = {200, 128};
    static const unsigned char grey16[2] = {0x80, 0x00};
    const double tol = 2 * (double)FLT_EPSILON;
    double v;
    png_spec sp;
    ray_image *img;
    ray_rgb c;

    memset(&sp, 0, sizeof sp);
    sp.width = 4;
    sp.height = 1;
    sp.depth = 2;
    sp.color_type = PNG_COLOR_TYPE_PALETTE;
    sp.palette = palette;
    sp.palette_size = 4;
    sp.trns = trns;
    sp.trns_size = 3;
    sp.rows = indices;
    img = load_spec(&sp);
    c = texel(img, 0, 0);
    ck_assert_double_eq_tol(c.r, 1, CENTRE_TOL);
    ck_assert_double_eq_tol(c.g + c.b, 0, CENTRE_TOL);
    c = texel(img, 1, 0);
    ck_assert_double_eq_tol(c.r + c.g + c.b, 0, CENTRE_TOL);
    c = texel(img, 2, 0);
    ck_assert_double_eq_tol(c.r, 128.0 / 255.0, tol);
    ck_assert_double_eq_tol(c.b, 128.0 / 255.0, tol);
    c = texel(img, 3, 0);
    ck_assert_double_eq_tol(c.r + c.g + c.b, 0, CENTRE_TOL);
    ray_image_free(img);

    memset(&sp, 0, sizeof sp);
    sp.width = 2;
    sp.height = 1;
    sp.depth = 4;
    sp.color_type = PNG_COLOR_TYPE_GRAY;
    sp.gamma = 1.0;
    sp.rows = grey4;
    img = load_spec(&sp);
    c = texel(img, 0, 0);
    ck_assert_double_eq_tol(c.r, 1.0 / 3.0, tol);
    ck_assert_double_eq_tol(c.b, 1.0 / 3.0, tol);
    ck_assert_double_eq_tol(texel(img, 1, 0).g, 1.0, tol);
    ray_image_free(img);

    sp.width = 1;
    sp.depth = 8;
    sp.color_type = PNG_COLOR_TYPE_GRAY_ALPHA;
    sp.gamma = 0;
    sp.rows = grey_alpha;
    img = load_spec(&sp);
    /* IEC 61966-2-1: ((V + 0.055) / 1.055)^2.4 above 0.04045. */
    v = pow((200.0 / 255.0 + 0.055) / 1.055, 2.4) * (128.0 / 255.0);
    c = texel(img, 0, 0);
    ck_assert_double_eq_tol(c.r, v, tol);
    ck_assert_double_eq_tol(c.g, v, tol);
    ray_image_free(img);

    /* 16-bit grey with gAMA 0.5: code 32768 is (32768 / 65535)^2. */
    sp.depth = 16;
    sp.color_type = PNG_COLOR_TYPE_GRAY;
    sp.gamma = 0.5;
    sp.rows = grey16;
    img = load_spec(&sp);
    v = (32768.0 / 65535.0) * (32768.0 / 65535.0);
    ck_assert_double_eq_tol(texel(img, 0, 0).b, v, tol);
    ray_image_free(img);
}
END_TEST

/* ----------------------------------------------- hostile files, limits */

/* CRC-32 of PNG chunks (ISO 3309, as PNG 1.2 section 3.4 gives it),
** bit by bit: libpng refuses a critical chunk whose CRC is wrong. */
static uint32_t crc32_of(const unsigned char *p, size_t n)
{
    uint32_t c = 0xffffffffu;
    size_t i;
    int k;

    for (i = 0; i < n; i++) {
        c ^= p[i];
        for (k = 0; k < 8; k++)
            c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
    }
    return c ^ 0xffffffffu;
}

static void put_u32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)(v >> 24);
    p[1] = (unsigned char)(v >> 16);
    p[2] = (unsigned char)(v >> 8);
    p[3] = (unsigned char)v;
}

/* A chunk at p: length, type, the n bytes of data, CRC; its size. */
static size_t put_chunk(unsigned char *p, const char *type,
                        const unsigned char *data, size_t n)
{
    put_u32(p, (uint32_t)n);
    memcpy(p + 4, type, 4);
    if (n > 0)
        memcpy(p + 8, data, n);
    put_u32(p + 8 + n, crc32_of(p + 4, 4 + n));
    return 12 + n;
}

/* The signature and an IHDR chunk (filter 0, compression 0): 33 bytes. */
static size_t put_header(unsigned char *p, uint32_t width, uint32_t height,
                         int depth, int color_type, int interlace)
{
    static const unsigned char sig[8] = {137, 80, 78, 71, 13, 10, 26, 10};
    unsigned char ihdr[13] = {0};

    memcpy(p, sig, 8);
    put_u32(ihdr, width);
    put_u32(ihdr + 4, height);
    ihdr[8] = (unsigned char)depth;
    ihdr[9] = (unsigned char)color_type;
    ihdr[12] = (unsigned char)interlace;
    return 8 + put_chunk(p + 8, "IHDR", ihdr, 13);
}

static void write_bytes(const char *path, const unsigned char *p, size_t n)
{
    FILE *fp = fopen(path, "wb");
    ck_assert_ptr_nonnull(fp);
    ck_assert_uint_eq(fwrite(p, 1, n, fp), n);
    ck_assert_int_eq(fclose(fp), 0);
}

/* The process's peak resident size, in KiB (Linux: ru_maxrss). */
/* The process's peak memory in KiB: its resident set (ru_maxrss) on
** POSIX; on Windows its peak commit (PeakPagefileUsage: every page
** allocated and touched or not, so it sees at least what ru_maxrss does). */
static long peak_kib(void)
{
#if defined(_WIN32)
    PROCESS_MEMORY_COUNTERS pmc;
    memset(&pmc, 0, sizeof pmc);
    pmc.cb = sizeof pmc;
    ck_assert(GetProcessMemoryInfo(GetCurrentProcess(), &pmc, sizeof pmc));
    return (long)(pmc.PeakPagefileUsage / 1024);
#else
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return ru.ru_maxrss;
#endif
}

/* A hostile file may cost this much at most: the defaults' 64 MiB chunk
** limit, which the loads below do not come near (about 0.5 MiB each,
** 2 MiB under ASan), where they cost 1.9 GB and 206 MB (ASan) before. */
#define HOSTILE_KIB (64L << 10)

static int load_file(const char *path, const ray_image_load_options *opt,
                     ray_image **img)
{
    *img = NULL;
    return ray_image_load_png(path, opt, img);
}

/*
** The fuzzer's 193-byte file: a 1 x 1 RGB header, then an sPLT chunk that
** declares 0x73737373 bytes, cut short.  libpng allocated the declared
** length (1.9 GB) before finding the end of the file; now the chunk is
** refused from its header, RAY_ELIMIT.  With the chunk limit raised past
** it, the chunk is skipped unread instead (the loader reads no sPLT) and
** the load ends at the end of the file, RAY_EPNG, as cheaply.
** (ru_maxrss is a peak: in Check's no-fork mode an earlier test's peak
** could hide growth, never fake it.)
*/
START_TEST(image_should_refuse_a_huge_chunk_before_allocating)
{
    unsigned char file[193];
    const char *path = temp_path("splt");
    ray_image_load_options opt;
    ray_image *img;
    size_t n = put_header(file, 1, 1, 8, PNG_COLOR_TYPE_RGB, 0);
    long before;

    put_u32(file + n, 0x73737373u);
    memcpy(file + n + 4, "sPLT", 4);
    memset(file + n + 8, 's', sizeof file - n - 8);
    write_bytes(path, file, sizeof file);
    before = peak_kib();
    ck_assert_int_eq(load_file(path, NULL, &img), RAY_ELIMIT);
    ck_assert_ptr_null(img);
    memset(&opt, 0, sizeof opt);
    opt.max_chunk_bytes = SIZE_MAX;
    ck_assert_int_eq(load_file(path, &opt, &img), RAY_EPNG);
    ck_assert_ptr_null(img);
    ck_assert_int_lt(peak_kib() - before, HOSTILE_KIB);
    unlink(path);
}
END_TEST

/*
** The fuzzer's 60-byte file: 16384 x 16384 16-bit RGBA (within the
** default limits) and 15 bytes of IDAT.  The image grows with the rows
** decoded, so the failure (RAY_EPNG) costs a row, not the 1.5 GiB buffer
** the simplified API wanted first.  Lower limits refuse it from the
** header; one pixel over the default side is refused by default.
*/
START_TEST(image_should_bound_memory_by_the_rows_decoded)
{
    /* zlib header, then a stored block of 8 zero bytes that never ends */
    static const unsigned char idat[15] = {0x78, 0x01, 0x00, 8, 0, 0xf7,
                                           0xff};
    unsigned char file[60];
    const char *path = temp_path("huge");
    ray_image_load_options opt;
    ray_image *img;
    size_t n;
    long before;
    int interlace;

    for (interlace = 0; interlace <= 1; interlace++) {
        n = put_header(file, 16384, 16384, 16, PNG_COLOR_TYPE_RGB_ALPHA,
                       interlace);
        n += put_chunk(file + n, "IDAT", idat, sizeof idat);
        ck_assert_uint_eq(n, sizeof file);
        write_bytes(path, file, n);
        before = peak_kib();
        ck_assert_int_eq(load_file(path, NULL, &img), RAY_EPNG);
        ck_assert_ptr_null(img);
        ck_assert_int_lt(peak_kib() - before, HOSTILE_KIB);
        memset(&opt, 0, sizeof opt);
        opt.max_pixels = (size_t)4096 * 4096;
        ck_assert_int_eq(load_file(path, &opt, &img), RAY_ELIMIT);
        memset(&opt, 0, sizeof opt);
        opt.max_width = 16383;
        ck_assert_int_eq(load_file(path, &opt, &img), RAY_ELIMIT);
        opt.max_width = 0;
        opt.max_height = 100;
        ck_assert_int_eq(load_file(path, &opt, &img), RAY_ELIMIT);
        ck_assert_ptr_null(img);
    }
    n = put_header(file, 16385, 1, 8, PNG_COLOR_TYPE_RGB, 0);
    write_bytes(path, file, n);
    ck_assert_int_eq(load_file(path, NULL, &img), RAY_ELIMIT);
    unlink(path);
}
END_TEST

/*
** The limits at their edges, on the 4 x 2 test image: each refuses one
** over and accepts exactly at it.  A 100-byte tEXt chunk put after IHDR
** passes a 100-byte chunk limit and is refused by a 99-byte one.
*/
START_TEST(image_limits_should_hold_at_their_edges)
{
    const char *path = temp_path("edges");
    ray_image_load_options opt;
    ray_image *img;
    float rgb[4 * 2 * 3];
    unsigned char text[100], *bytes, *file;
    long size;
    size_t n;
    FILE *fp;

    test_texels(rgb);
    ck_assert_int_eq(ray_write_png(path, rgb, 4, 2, 16), RAY_OK);
    memset(&opt, 0, sizeof opt);
    opt.max_width = 3;
    ck_assert_int_eq(load_file(path, &opt, &img), RAY_ELIMIT);
    opt.max_width = 4;
    opt.max_height = 1;
    ck_assert_int_eq(load_file(path, &opt, &img), RAY_ELIMIT);
    opt.max_height = 2;
    opt.max_pixels = 7;
    ck_assert_int_eq(load_file(path, &opt, &img), RAY_ELIMIT);
    ck_assert_ptr_null(img);
    opt.max_pixels = 8;
    ck_assert_int_eq(load_file(path, &opt, &img), RAY_OK);
    ray_image_free(img);

    fp = fopen(path, "rb");
    ck_assert_ptr_nonnull(fp);
    fseek(fp, 0, SEEK_END);
    size = ftell(fp);
    rewind(fp);
    bytes = malloc((size_t)size);
    file = malloc((size_t)size + 12 + sizeof text);
    ck_assert_uint_eq(fread(bytes, 1, (size_t)size, fp), (size_t)size);
    fclose(fp);
    memcpy(file, bytes, 33);                    /* signature and IHDR */
    memset(text, 'x', sizeof text);
    memcpy(text, "Comment", 8);                 /* keyword, NUL, text */
    n = 33 + put_chunk(file + 33, "tEXt", text, sizeof text);
    memcpy(file + n, bytes + 33, (size_t)size - 33);
    write_bytes(path, file, n + (size_t)size - 33);
    free(bytes);
    free(file);
    memset(&opt, 0, sizeof opt);
    opt.max_chunk_bytes = 99;
    ck_assert_int_eq(load_file(path, &opt, &img), RAY_ELIMIT);
    opt.max_chunk_bytes = 100;
    ck_assert_int_eq(load_file(path, &opt, &img), RAY_OK);
    ray_image_free(img);
    ck_assert_int_eq(load_file(path, NULL, &img), RAY_OK);
    ray_image_free(img);
    ck_assert_int_eq(ray_image_load_png(NULL, &opt, &img), RAY_EINVAL);
    ck_assert_int_eq(ray_image_load_png(path, &opt, NULL), RAY_EINVAL);
    unlink(path);
}
END_TEST
#else
/*
** A library built without libpng (make PNG=0): the PNG calls check their
** arguments (RAY_EINVAL as ray.h says), then return RAY_ENOTSUP, leave
** *out untouched and create no file.
*/
START_TEST(png_calls_should_be_unsupported_without_libpng)
{
    char path[512];
    float rgb[4 * 2 * 3];
    ray_image *img = (ray_image *)&img;    /* any non-NULL marker */
    ray_image_load_options opt;

    test_tmp_path(path, sizeof path, "libray-check-nopng.png");
    memset(&opt, 0, sizeof opt);
    test_texels(rgb);
    remove(path);
    ck_assert_int_eq(ray_write_png(path, rgb, 4, 2, 8), RAY_ENOTSUP);
    ck_assert_int_eq(ray_write_png(path, rgb, 4, 2, 16), RAY_ENOTSUP);
    ck_assert_int_eq(access(path, F_OK), -1);
    ck_assert_int_eq(ray_write_png(NULL, rgb, 4, 2, 8), RAY_EINVAL);
    ck_assert_int_eq(ray_write_png(path, NULL, 4, 2, 8), RAY_EINVAL);
    ck_assert_int_eq(ray_write_png(path, rgb, 0, 2, 8), RAY_EINVAL);
    ck_assert_int_eq(ray_write_png(path, rgb, 4, 2, 12), RAY_EINVAL);
    ck_assert_int_eq(ray_image_load_png("doc/cornell.png", NULL, &img), RAY_ENOTSUP);
    ck_assert_int_eq(ray_image_load_png("doc/cornell.png", &opt, &img),
                     RAY_ENOTSUP);
    ck_assert_int_eq(ray_image_load_png("doc/cornell.png", NULL, &img),
                     RAY_ENOTSUP);
    ck_assert(img == (ray_image *)&img);
    ck_assert_int_eq(ray_image_load_png(NULL, NULL, &img), RAY_EINVAL);
    ck_assert_int_eq(ray_image_load_png("doc/cornell.png", NULL, NULL),
                     RAY_EINVAL);
    ck_assert_str_eq(ray_strerror(RAY_ENOTSUP), "not supported by this build");
}
END_TEST
#endif

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
    *out = rgb(1, 1, 1);
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
    ck_assert_int_eq(ray__implicit_torus(&torus, &is), RAY_OK);
    memset(&params, 0, sizeof params);
    params.diffuse = rgb(1, 1, 1);
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
        ck_assert_int_eq(ray_scene_set_ambient(s, rgb(1, 1, 1)), RAY_OK);
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
    params.diffuse = rgb(0.5, 1, 2);
    params.texture = ray_texture_image(img);
    ck_assert(params.texture.fn != NULL);
    m = ray_material_phong(&params);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 1, 0), 0,
                                         NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_set_ambient(s, rgb(1, 1, 1)), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    for (n = 0; n < 20; n++) {
        double x = 0.37 * n - 3, z = 0.21 * n - 1;
        ray_rgb c = trace_one(s, ray_from(vec(x, 1, z), vec(0, -1, 0))), t;
        ck_assert_int_eq(ray_image_sample(img, x, -z, 0, &t), RAY_OK);
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

#if RAY_TEST_PNG
    tcase_add_test(core, image_should_load_16_bit_linear_png_exactly);
#endif
    tcase_add_test(core, image_should_filter_bilinearly_and_wrap);
#if RAY_TEST_PNG
    tcase_add_test(core, image_should_decode_8_bit_srgb);
    tcase_add_test(core, image_should_reject_bad_files_and_arguments);
    tcase_add_test(core, image_should_compose_alpha_on_black);
    tcase_add_test(core, image_should_load_interlaced_files);
    tcase_add_test(core, image_should_expand_palettes_grey_and_alpha);
    tcase_add_test(core, image_should_refuse_a_huge_chunk_before_allocating);
    tcase_add_test(core, image_should_bound_memory_by_the_rows_decoded);
    tcase_add_test(core, image_limits_should_hold_at_their_edges);
#else
    fprintf(stderr, "texture: built with PNG=0: the 9 PNG loading tests "
                    "skipped, RAY_ENOTSUP checked instead\n");
    tcase_add_test(core, png_calls_should_be_unsupported_without_libpng);
#endif
    tcase_add_test(core, texture_should_see_every_primitives_coordinates);
    tcase_add_test(core, textured_phong_should_multiply_diffuse_by_the_image);
    suite_add_tcase(s, core);
    return s;
}
