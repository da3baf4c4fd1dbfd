/* SPDX-License-Identifier: MIT */
/*
** image.c -- images for textures: loaded from PNG through libpng's
** simplified API (libpng 1.6, png.h section 5), kept as linear RGB floats,
** sampled with wrap-around and bilinear filtering.
*/
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <png.h>

#include "vec.h"

struct ray_image {
    unsigned width, height;
    float *rgb;              /* 3 per texel, rows top to bottom */
};

/* Images up to 16384 on a side: 3 GiB of floats at most, and every index
** below fits an unsigned with room to spare. */
#define MAX_IMAGE_SIDE 16384u

/* The sRGB transfer function's inverse, IEC 61966-2-1:1999 section 5.2:
** an 8-bit code to linear light. */
static double srgb_decode(double encoded)
{
    if (encoded <= 0.04045)
        return encoded / 12.92;
    return pow((encoded + 0.055) / 1.055, 2.4);
}

/*
** libpng converts on reading (palettes and grey expanded; alpha composed
** on black, as there is no background).  An 8-bit file is
** read as 8-bit sRGB codes (libpng re-encodes a file that declares
** another gamma) and decoded here with the exact IEC curve: libpng's own
** linear output approximates sRGB by a 2.2 power, up to 1% off in the
** mid-tones.  A 16-bit file is read as 16-bit linear samples
** (PNG_FORMAT_LINEAR_RGB), as ray_write_png's 16-bit files are.
*/
static int read_pixels(png_image *png, ray_image **out)
{
    int sixteen = (png->format & PNG_FORMAT_FLAG_LINEAR) != 0;
    size_t count, i;
    ray_image *img;
    void *buf;
    float lut[256];

    if (png->width > MAX_IMAGE_SIDE || png->height > MAX_IMAGE_SIDE) {
        png_image_free(png);
        return RAY_ERANGE;
    }
    png->format = sixteen ? PNG_FORMAT_LINEAR_RGB : PNG_FORMAT_RGB;
    count = (size_t)png->width * png->height * 3;
    /* Zeroed: without a background colour libpng composes alpha "onto
    ** the buffer" (png.h), so transparent pixels become black rather than
    ** whatever the heap held -- as the 16-bit path does by itself. */
    buf = calloc(count, sixteen ? sizeof(png_uint_16) : 1);
    if (buf == NULL) {
        png_image_free(png);
        return RAY_ENOMEM;
    }
    if (!png_image_finish_read(png, NULL, buf, 0, NULL)) {
        free(buf);
        png_image_free(png);
        return RAY_EPNG;
    }
    /* The floats only once the file decoded: a truncated file that
    ** declares a huge size fails before this allocation. */
    img = malloc(sizeof *img);
    if (img != NULL)
        img->rgb = malloc(count * sizeof *img->rgb);
    if (img == NULL || img->rgb == NULL) {
        free(img);
        free(buf);
        return RAY_ENOMEM;
    }
    for (i = 0; i < 256; i++)
        lut[i] = (float)srgb_decode((double)i / 255.0);
    for (i = 0; i < count; i++)
        img->rgb[i] = sixteen
                          ? (float)(((const png_uint_16 *)buf)[i] / 65535.0)
                          : lut[((const unsigned char *)buf)[i]];
    img->width = png->width;
    img->height = png->height;
    free(buf);
    *out = img;
    return RAY_OK;
}

int ray_image_load_png(const char *path, ray_image **out)
{
    png_image png;
    FILE *fp;
    int status;

    if (path == NULL || out == NULL)
        return RAY_EINVAL;
    fp = fopen(path, "rb");
    if (fp == NULL)
        return RAY_EIO;
    memset(&png, 0, sizeof png);
    png.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_stdio(&png, fp)) {
        /* libpng reports read errors and bad signatures alike; tell an
        ** I/O failure by the stream's error flag. */
        status = ferror(fp) ? RAY_EIO : RAY_EPNG;
        png_image_free(&png);
        fclose(fp);
        return status;
    }
    status = read_pixels(&png, out);
    if (status == RAY_EPNG && ferror(fp))
        status = RAY_EIO;
    fclose(fp);
    return status;
}

void ray_image_free(ray_image *img)
{
    if (img == NULL)
        return;
    free(img->rgb);
    free(img);
}

void ray_image_size(const ray_image *img, unsigned *width, unsigned *height)
{
    if (img == NULL)
        return;
    if (width != NULL)
        *width = img->width;
    if (height != NULL)
        *height = img->height;
}

/* x mod n for any integer-valued double x, as an index in [0, n). */
static unsigned wrap(double x, unsigned n)
{
    double m = fmod(x, (double)n);
    if (m < 0)
        m += n;
    /* fmod is exact; m + n may round up to n for a tiny negative m. */
    return m >= n ? 0 : (unsigned)m;
}

/*
** Bilinear filtering between the four texel centres around (s, t):
** texel (i, j) covers [i, i+1) x [j, j+1) in units of texels, its centre
** at i + 1/2, so x = s * width - 1/2 falls between centres floor(x) and
** floor(x) + 1 with weight x - floor(x) on the second.  s and t are first
** reduced to [0, 1) so that s = 1e9 keeps its fraction's digits.
*/
int ray_image_sample(const ray_image *img, double s, double t, ray_rgb *out)
{
    double x, y, fx, fy, w[4];
    unsigned i0, i1, j0, j1, idx[4], k;
    ray_rgb c = {0, 0, 0};

    if (img == NULL || out == NULL || !isfinite(s) || !isfinite(t))
        return RAY_EINVAL;
    s -= floor(s);
    t -= floor(t);
    x = s * img->width - 0.5;
    y = (1.0 - t) * img->height - 0.5;   /* t = 0 is the bottom row */
    fx = x - floor(x);
    fy = y - floor(y);
    i0 = wrap(floor(x), img->width);
    i1 = wrap(floor(x) + 1, img->width);
    j0 = wrap(floor(y), img->height);
    j1 = wrap(floor(y) + 1, img->height);
    idx[0] = j0 * img->width + i0;
    idx[1] = j0 * img->width + i1;
    idx[2] = j1 * img->width + i0;
    idx[3] = j1 * img->width + i1;
    w[0] = (1 - fx) * (1 - fy);
    w[1] = fx * (1 - fy);
    w[2] = (1 - fx) * fy;
    w[3] = fx * fy;
    for (k = 0; k < 4; k++) {
        const float *p = img->rgb + 3 * (size_t)idx[k];
        c.r += w[k] * (double)p[0];
        c.g += w[k] * (double)p[1];
        c.b += w[k] * (double)p[2];
    }
    *out = c;
    return RAY_OK;
}

static void image_texture(void *ud, const ray_shade_args *args, ray_rgb *out)
{
    /* Non-finite (u, v) leave *out as the caller preset it. */
    ray_image_sample(ud, args->u, args->v, out);
}

ray_texture ray_texture_image(const ray_image *img)
{
    ray_texture t;

    t.fn = img != NULL ? image_texture : NULL;
    t.ud = ray__unconst(img);
    return t;
}
