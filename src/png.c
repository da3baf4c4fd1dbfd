/* SPDX-License-Identifier: MIT */
/*
** png.c -- PNG files through libpng's simplified API (libpng 1.6, png.h
** section 5): no setjmp, no callbacks, errors come back as a message in
** the png_image.  Writing (ray_write_png) and loading textures
** (ray_image_load_png, made into images by image.c); the only file that
** includes <png.h>.
*/
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <png.h>

#include "image.h"

/* Clamp to [0, 1]; NaN goes to 0 (the comparison is false for NaN). */
static double unit_clamp(float x)
{
    if (!(x > 0.0f))
        return 0.0;
    return x < 1.0f ? (double)x : 1.0;
}

/* The sRGB transfer function, IEC 61966-2-1:1999 section 5.2. */
static double srgb_encode(double linear)
{
    if (linear <= 0.0031308)
        return 12.92 * linear;
    return 1.055 * pow(linear, 1.0 / 2.4) - 0.055;
}

int ray_image_to_srgb8(const float *rgb, size_t count, unsigned char *out)
{
    size_t i;

    if (rgb == NULL || out == NULL)
        return RAY_EINVAL;
    for (i = 0; i < 3 * count; i++)
        out[i] = (unsigned char)(srgb_encode(unit_clamp(rgb[i])) * 255.0 + 0.5);
    return RAY_OK;
}

static void to_linear16(const float *rgb, size_t count, png_uint_16 *out)
{
    size_t i;

    for (i = 0; i < 3 * count; i++)
        out[i] = (png_uint_16)(unit_clamp(rgb[i]) * 65535.0 + 0.5);
}

/*
** png_image_write_to_stdio, then a checked flush and fclose: a full disk
** often shows only when the buffered data are written out.  A failed file
** is removed so no truncated PNG is left behind.
*/
static int write_file(const char *path, png_image *img, const void *pixels)
{
    FILE *fp = fopen(path, "wb");
    int ok, io_failed, saved_errno;

    if (fp == NULL)
        return RAY_EIO;
    ok = png_image_write_to_stdio(img, fp, 0, pixels, 0, NULL);
    io_failed = fflush(fp) != 0 || ferror(fp);
    io_failed |= fclose(fp) != 0;
    if (ok && !io_failed)
        return RAY_OK;
    saved_errno = errno;        /* remove() must not hide the cause */
    remove(path);
    errno = saved_errno;
    return io_failed ? RAY_EIO : RAY_EPNG;
}

int ray_write_png(const char *path, const float *rgb, unsigned width,
                  unsigned height, int bits)
{
    png_image img;
    size_t count, bytes;
    void *pixels;
    int rc;

    if (path == NULL || rgb == NULL || width == 0 || height == 0 ||
        (bits != 8 && bits != 16))
        return RAY_EINVAL;
    /* libpng limits rows to 2^31-1 bytes; also keep our sizes in size_t. */
    if (width > PNG_UINT_31_MAX / 6 || height > PNG_UINT_31_MAX ||
        (size_t)height > SIZE_MAX / 6 / width)
        return RAY_EINVAL;
    count = (size_t)width * height;
    bytes = count * 3 * (size_t)(bits / 8);
    pixels = malloc(bytes);
    if (pixels == NULL)
        return RAY_ENOMEM;
    if (bits == 8)
        ray_image_to_srgb8(rgb, count, (unsigned char *)pixels);
    else
        to_linear16(rgb, count, (png_uint_16 *)pixels);
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    img.width = width;
    img.height = height;
    img.format = bits == 8 ? PNG_FORMAT_RGB : PNG_FORMAT_LINEAR_RGB;
    rc = write_file(path, &img, pixels);
    png_image_free(&img);
    free(pixels);
    return rc;
}

/* ------------------------------------------------------ loading textures */

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
    float *rgb, lut[256];
    void *buf;

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
    rgb = malloc(count * sizeof *rgb);
    if (rgb == NULL) {
        free(buf);
        return RAY_ENOMEM;
    }
    for (i = 0; i < 256; i++)
        lut[i] = (float)srgb_decode((double)i / 255.0);
    for (i = 0; i < count; i++)
        rgb[i] = sixteen ? (float)(((const png_uint_16 *)buf)[i] / 65535.0)
                         : lut[((const unsigned char *)buf)[i]];
    free(buf);
    img = ray__image_new(png->width, png->height, rgb);
    if (img == NULL) {
        free(rgb);
        return RAY_ENOMEM;
    }
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
