/* SPDX-License-Identifier: MIT */
/*
** png_none.c -- PNG files in a library built without libpng (make PNG=0,
** which compiles this file instead of png.c): the three PNG calls check
** their arguments as png.c does, so the NULL rule and the size rule of
** ray.h still hold, and then return RAY_ENOTSUP, touching no file and no
** output.  Everything else (scenes, tracing, rendering to float buffers,
** ray_image_to_srgb8) is the same library.
*/
#include <stdint.h>
#include <stdlib.h>

#include "image/image.h"

/* png.h's PNG_UINT_31_MAX (2^31 - 1, PNG 1.2 section 2.1), the limit
** png.c's ray_write_png puts on a row's bytes and on the height. */
#define PNG_NONE_UINT_31_MAX 0x7fffffffu

int ray_write_png(const char *path, const float *rgb, unsigned width,
                  unsigned height, int bits)
{
    if (path == NULL || rgb == NULL || width == 0 || height == 0 ||
        (bits != 8 && bits != 16))
        return RAY_EINVAL;
    if (width > PNG_NONE_UINT_31_MAX / 6 || height > PNG_NONE_UINT_31_MAX ||
        (size_t)height > SIZE_MAX / 6 / width)
        return RAY_EINVAL;
    return RAY_ENOTSUP;
}

int ray_image_load_png(const char *path, const ray_image_load_options *opt,
                       ray_image **out)
{
    (void)opt;
    if (path == NULL || out == NULL)
        return RAY_EINVAL;
    return RAY_ENOTSUP;
}
