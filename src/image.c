/* SPDX-License-Identifier: MIT */
/*
** image.c -- images for textures, kept as linear RGB floats (loaded from
** PNG files by png.c), sampled with wrap-around and bilinear filtering;
** and the sRGB encoding of float pixels, which needs no libpng (a build
** with PNG=0 keeps it).
*/
#include <stdlib.h>

#include "image.h"

struct ray_image {
    unsigned width, height;
    float *rgb;              /* 3 per texel, rows top to bottom */
};

ray_image *ray__image_new(unsigned width, unsigned height, float *rgb)
{
    ray_image *img = malloc(sizeof *img);

    if (img == NULL)
        return NULL;
    img->width = width;
    img->height = height;
    img->rgb = rgb;
    return img;
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
        out[i] = (unsigned char)(srgb_encode(ray__unit_clamp(rgb[i])) *
                                 255.0 + 0.5);
    return RAY_OK;
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
    unsigned i0, i1, j0, j1, k;
    size_t idx[4];               /* width * height may pass UINT_MAX */
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
    idx[0] = (size_t)j0 * img->width + i0;
    idx[1] = (size_t)j0 * img->width + i1;
    idx[2] = (size_t)j1 * img->width + i0;
    idx[3] = (size_t)j1 * img->width + i1;
    w[0] = (1 - fx) * (1 - fy);
    w[1] = fx * (1 - fy);
    w[2] = (1 - fx) * fy;
    w[3] = fx * fy;
    for (k = 0; k < 4; k++) {
        const float *p = img->rgb + 3 * idx[k];
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
