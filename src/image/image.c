/* SPDX-License-Identifier: MIT */
/*
** image.c -- images for textures, kept as linear RGB floats (loaded from
** PNG files by png.c, or copied from memory by ray_image_new) with their
** mip pyramid, sampled with wrap-around and bilinear filtering, or
** trilinearly between two levels of the pyramid for a footprint (the
** sRGB encoding of float pixels is srgb8.c's).
*/
#include <stdlib.h>
#include <string.h>

#include "image/image.h"

/* One level of the pyramid: level 0 is the image itself. */
typedef struct mip_level {
    unsigned width, height;
    const float *rgb;        /* 3 per texel, rows top to bottom */
} mip_level;

struct ray_image {
    unsigned width, height;
    float *rgb;              /* 3 per texel, rows top to bottom */
    float *mips;             /* levels 1 .. n_levels - 1, one block */
    unsigned n_levels;
    mip_level level[RAY__MIP_MAX_LEVELS];
};

/* The next level's side: half, rounded down, at least 1. */
static unsigned half_side(unsigned n)
{
    return n > 1 ? n / 2 : 1;
}

/*
** The weights of the exact area-weighted box from n texels to m (m =
** half_side(n)): output texel i covers [i n/m, (i+1) n/m) of the input,
** and takes each input texel j by the length of their overlap, divided
** by the length n/m it covers.  Measured in units of 1/m the ends are
** the integers i n and j m, so the overlaps are exact; a weight is
** overlap / n, rounded once.  An even n gives (1/2, 1/2); an odd n > 1
** gives three taps, e.g. n = 5: (0.4, 0.4, 0.2) then (0.2, 0.4, 0.4);
** n = 1 stays (1).  Unlike a 3-tap [1/4 1/2 1/4] filter on odd sizes,
** every input texel gives the same total weight, so each level keeps the
** mean of the one below (the image's average colour at every distance),
** and the filter is the box the footprint models.  n/m < 4, so an output
** texel meets at most 4 input texels: first[i] and w[4 i .. 4 i + 3].
*/
static void box_weights(unsigned n, unsigned m, unsigned *first, double *w)
{
    unsigned i, k;

    for (i = 0; i < m; i++) {
        unsigned long long lo = (unsigned long long)i * n;
        unsigned long long hi = lo + n;
        unsigned j = (unsigned)(lo / m);

        first[i] = j;
        for (k = 0; k < 4; k++, j++) {
            unsigned long long a = (unsigned long long)j * m, b = a + m;
            unsigned long long from = a > lo ? a : lo, to = b < hi ? b : hi;
            w[4 * (size_t)i + k] =
                j < n && to > from ? (double)(to - from) / (double)n : 0.0;
        }
    }
}

/* Level "dst" (w2 x h2) from level "src" (w x h) by the box of box_weights,
** separably: the weights' products, summed in double, rounded to float
** once.  wx, wy, fx, fy: room for 4 w2, 4 h2, w2, h2 entries. */
static void reduce(const mip_level *src, unsigned w2, unsigned h2,
                   float *dst, unsigned *fx, double *wx, unsigned *fy,
                   double *wy)
{
    unsigned i, k, a, b, c;

    box_weights(src->width, w2, fx, wx);
    box_weights(src->height, h2, fy, wy);
    for (k = 0; k < h2; k++)
        for (i = 0; i < w2; i++) {
            double sum[3] = {0, 0, 0};
            for (b = 0; b < 4; b++) {
                double wb = wy[4 * (size_t)k + b];
                if (wb == 0)
                    continue;
                for (a = 0; a < 4; a++) {
                    double wab = wb * wx[4 * (size_t)i + a];
                    const float *p;
                    if (wab == 0)
                        continue;
                    p = src->rgb + 3 * ((size_t)(fy[k] + b) * src->width +
                                        fx[i] + a);
                    for (c = 0; c < 3; c++)
                        sum[c] += wab * (double)p[c];
                }
            }
            for (c = 0; c < 3; c++)
                dst[3 * ((size_t)k * w2 + i) + c] = (float)sum[c];
        }
}

/*
** The pyramid of img (level 0 set): every level half the one below,
** rounded down, down to 1 x 1, in one block; 0 when out of memory (or
** when the block's size would overflow a size_t), nothing changed.
*/
static int build_pyramid(ray_image *img)
{
    unsigned w = img->width, h = img->height, n = 1, k;
    size_t total = 0, most = (size_t)-1 / (3 * sizeof(float));
    size_t side = (img->width > img->height ? img->width : img->height);
    unsigned *fx, *fy;
    double *wx, *wy;
    float *block;

    while (w > 1 || h > 1) {
        w = half_side(w);
        h = half_side(h);
        if ((size_t)w * h > most - total)
            return 0;
        total += (size_t)w * h;
        n++;
    }
    img->n_levels = n;
    img->mips = NULL;
    if (n == 1)
        return 1;
    block = malloc(3 * sizeof(float) * total);
    /* Scratch for the weights: 4 per output texel of the widest level. */
    fx = malloc(2 * side * sizeof *fx);
    wx = malloc(8 * side * sizeof *wx);
    if (block == NULL || fx == NULL || wx == NULL) {
        free(block);
        free(fx);
        free(wx);
        return 0;
    }
    fy = fx + side;
    wy = wx + 4 * side;
    img->mips = block;
    for (k = 1; k < n; k++) {
        mip_level *l = &img->level[k];
        l->width = half_side(img->level[k - 1].width);
        l->height = half_side(img->level[k - 1].height);
        l->rgb = block;
        reduce(&img->level[k - 1], l->width, l->height, block, fx, wx, fy,
               wy);
        block += 3 * (size_t)l->width * l->height;
    }
    free(fx);
    free(wx);
    return 1;
}

ray_image *ray__image_new(unsigned width, unsigned height, float *rgb)
{
    ray_image *img = malloc(sizeof *img);

    if (img == NULL)
        return NULL;
    img->width = width;
    img->height = height;
    img->rgb = rgb;
    img->level[0].width = width;
    img->level[0].height = height;
    img->level[0].rgb = rgb;
    if (!build_pyramid(img)) {
        free(img);
        return NULL;
    }
    return img;
}

/* The largest side ray_image_new takes: ray_image_load_png's default
** limit (ray_image_load_options), so both constructors accept the same
** images. */
#define NEW_MAX_SIDE 16384u

int ray_image_new(unsigned width, unsigned height, const float *rgb,
                  ray_image **out)
{
    size_t i, n;
    float *copy;
    ray_image *img;

    if (rgb == NULL || out == NULL || width == 0 || height == 0)
        return RAY_EINVAL;
    if (width > NEW_MAX_SIDE || height > NEW_MAX_SIDE)
        return RAY_ELIMIT;
    n = 3 * (size_t)width * height;   /* < 2^30: no overflow */
    for (i = 0; i < n; i++)
        if (!isfinite(rgb[i]))
            return RAY_EINVAL;
    copy = malloc(n * sizeof *copy);
    if (copy == NULL)
        return RAY_ENOMEM;
    memcpy(copy, rgb, n * sizeof *copy);
    img = ray__image_new(width, height, copy);
    if (img == NULL) {
        free(copy);
        return RAY_ENOMEM;
    }
    *out = img;
    return RAY_OK;
}

unsigned ray__image_levels(const ray_image *img)
{
    return img->n_levels;
}

const float *ray__image_level(const ray_image *img, unsigned k,
                              unsigned *width, unsigned *height)
{
    if (k >= img->n_levels)
        return NULL;
    *width = img->level[k].width;
    *height = img->level[k].height;
    return img->level[k].rgb;
}

void ray_image_free(ray_image *img)
{
    if (img == NULL)
        return;
    free(img->rgb);
    free(img->mips);
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
** Bilinear filtering between the four texel centres around (s, t) on
** level l: texel (i, j) covers [i, i+1) x [j, j+1) in units of texels,
** its centre at i + 1/2, so x = s * width - 1/2 falls between centres
** floor(x) and floor(x) + 1 with weight x - floor(x) on the second.  s
** and t are first reduced to [0, 1) so that s = 1e9 keeps its fraction's
** digits.
*/
static ray_rgb bilinear(const mip_level *l, double s, double t)
{
    double x, y, fx, fy, w[4];
    unsigned i0, i1, j0, j1, k;
    size_t idx[4];               /* width * height may pass UINT_MAX */
    ray_rgb c = {0, 0, 0};

    s -= floor(s);
    t -= floor(t);
    x = s * l->width - 0.5;
    y = (1.0 - t) * l->height - 0.5;   /* t = 0 is the bottom row */
    fx = x - floor(x);
    fy = y - floor(y);
    i0 = wrap(floor(x), l->width);
    i1 = wrap(floor(x) + 1, l->width);
    j0 = wrap(floor(y), l->height);
    j1 = wrap(floor(y) + 1, l->height);
    idx[0] = (size_t)j0 * l->width + i0;
    idx[1] = (size_t)j0 * l->width + i1;
    idx[2] = (size_t)j1 * l->width + i0;
    idx[3] = (size_t)j1 * l->width + i1;
    w[0] = (1 - fx) * (1 - fy);
    w[1] = fx * (1 - fy);
    w[2] = (1 - fx) * fy;
    w[3] = fx * fy;
    for (k = 0; k < 4; k++) {
        const float *p = l->rgb + 3 * idx[k];
        c.r += w[k] * (double)p[0];
        c.g += w[k] * (double)p[1];
        c.b += w[k] * (double)p[2];
    }
    return c;
}

/*
** Trilinear mip-mapping (Williams, "Pyramidal Parametrics", SIGGRAPH
** 1983): a footprint "width" (texture units) covers width * side texels
** of level 0 (side: the larger of width and height, so that neither axis
** aliases), and level k has texels 2^k times larger, so the level whose
** texels match the footprint is lambda = log2(width * side).  The two
** levels around lambda are sampled bilinearly and blended by its
** fraction.  lambda <= 0 (a footprint within one texel, width 0
** included) is level 0 alone, the plain bilinear lookup; beyond the last
** level (1 x 1), the last level.
*/
int ray_image_sample(const ray_image *img, double s, double t, double width,
                     ray_rgb *out)
{
    double side, lambda, f;
    unsigned k;
    ray_rgb a, b;

    if (img == NULL || out == NULL || !isfinite(s) || !isfinite(t) ||
        !(width >= 0))
        return RAY_EINVAL;
    side = img->width > img->height ? img->width : img->height;
    if (!(width * side > 1.0)) {
        *out = bilinear(&img->level[0], s, t);
        return RAY_OK;
    }
    lambda = log2(width * side);        /* > 0; +Inf for width = +Inf */
    if (!(lambda < (double)(img->n_levels - 1))) {
        *out = bilinear(&img->level[img->n_levels - 1], s, t);
        return RAY_OK;
    }
    k = (unsigned)lambda;
    f = lambda - (double)k;
    a = bilinear(&img->level[k], s, t);
    b = bilinear(&img->level[k + 1], s, t);
    out->r = a.r + f * (b.r - a.r);
    out->g = a.g + f * (b.g - a.g);
    out->b = a.b + f * (b.b - a.b);
    return RAY_OK;
}

/* With the hit's footprint (ray_shade_args.footprint, set when the ray
** carries a cone) the filtered lookup; without, the plain one. */
static void image_texture(void *ud, const ray_shade_args *args, ray_rgb *out)
{
    /* Non-finite (u, v) leave *out as the caller preset it. */
    ray_image_sample(ud, args->u, args->v,
                     args->footprint > 0 ? args->footprint : 0, out);
}

ray_texture ray_texture_image(const ray_image *img)
{
    ray_texture t;

    t.fn = img != NULL ? image_texture : NULL;
    t.ud = ray__unconst(img);
    return t;
}
