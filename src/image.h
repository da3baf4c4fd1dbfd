/* SPDX-License-Identifier: MIT */
/*
** image.h -- images (image.c) as png.c's loader makes them.  Beside the
** layers: images need no scene, only vectors.
*/
#ifndef RAY_IMAGE_H
#define RAY_IMAGE_H

#include "vec.h"

/* A new image of width x height texels that takes over rgb (3 floats per
** texel, rows top to bottom), for png.c's loader; NULL when out of memory,
** rgb then still the caller's. */
ray_image *ray__image_new(unsigned width, unsigned height, float *rgb);

#endif /* RAY_IMAGE_H */
