/* SPDX-License-Identifier: MIT */
/*
** predicates.h -- exact orientation predicates on double coordinates
** (predicates.c), for what must be decided without rounding: which side
** of a triangle's plane a point lies on, and on which side of a segment
** its projection falls (ray_contains: the parity of crossings).
*/
#ifndef RAY_PREDICATES_H
#define RAY_PREDICATES_H

#include "core/vec.h"

/*
** (bx - ax)(cy - ay) - (by - ay)(cx - ax): positive when a, b, c turn
** counter-clockwise.  The value returned is an approximation whose SIGN
** is exact (0 only when the exact value is 0), for coordinates whose
** differences' products neither overflow nor underflow (magnitudes
** within about 2^-480 .. 2^480 apart: Shewchuk's conditions).
*/
double ray__orient2d(double ax, double ay, double bx, double by, double cx,
                     double cy);

/*
** det [a - d; b - d; c - d] (rows), Shewchuk's orient3d: positive when d
** lies below the plane of a, b, c seen counter-clockwise from above.
** Sign exact as ray__orient2d's, same conditions.
*/
double ray__orient3d(ray_vec3 a, ray_vec3 b, ray_vec3 c, ray_vec3 d);

#endif /* RAY_PREDICATES_H */
