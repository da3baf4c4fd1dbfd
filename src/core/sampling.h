/* SPDX-License-Identifier: MIT */
/*
** sampling.h -- mapping uniform samples onto shapes (sampling.c): for the
** camera's lens, the lights and the photons.
*/
#ifndef RAY_SAMPLING_H
#define RAY_SAMPLING_H

#include "core/vec.h"

/* The least k with k * k >= n (n <= 65536): a square grid of strata. */
unsigned ray__strata_side(unsigned n);

/* (a, b) in [-1,1]^2 onto the unit disk, by the concentric map. */
void ray__concentric_disk(double a, double b, double *x, double *y);

#endif /* RAY_SAMPLING_H */
