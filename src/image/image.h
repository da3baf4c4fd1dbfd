/* SPDX-License-Identifier: MIT */
/*
** image.h -- images (image.c) as png.c's loader makes them, and the
** clamp both pixel encodings share.  Beside the
** layers: images need no scene, only vectors.
*/
#ifndef RAY_IMAGE_H
#define RAY_IMAGE_H

#include "core/vec.h"

/* A new image of width x height texels that takes over rgb (3 floats per
** texel, rows top to bottom), its mip pyramid built, for png.c's loader
** and ray_image_new; NULL when out of memory, rgb then still the
** caller's. */
ray_image *ray__image_new(unsigned width, unsigned height, float *rgb);

/* Levels a pyramid can have: 1 + floor(log2(side)) for a side below
** 2^32. */
#define RAY__MIP_MAX_LEVELS 33

/* The number of levels of img's pyramid (1 for a 1 x 1 image), and level
** k's size and texels (3 floats each, rows top to bottom), NULL for k out
** of range: for the tests, which check the box filter on known inputs. */
unsigned ray__image_levels(const ray_image *img);
const float *ray__image_level(const ray_image *img, unsigned k,
                              unsigned *width, unsigned *height);

#endif /* RAY_IMAGE_H */
