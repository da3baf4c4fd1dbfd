/* SPDX-License-Identifier: MIT */
/*
** shapes.h -- the interface between bench/shapes.c (C) and
** bench/bullet.cpp (C++, built where Debian's libbullet-dev is
** installed): Bullet's convexSweepTest with a btSphereShape and its
** rayTest over a btBvhTriangleMeshShape of the same triangles, on the
** same paths.  Not part of the library.
*/
#ifndef BENCH_SHAPES_H
#define BENCH_SHAPES_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* One path: from (x0, y0, z0) to (x1, y1, z1); Bullet's answer: hit 1
** and the fraction of the path at the contact, or 0. */
typedef struct bullet_path {
    double from[3], to[3];
    int hit;
    double fraction;
} bullet_path;

/*
** The triangles (vertices v[3 i .. 3 i + 2] of indices idx[3 k .. 3 k +
** 2]) as one btBvhTriangleMeshShape in a btCollisionWorld; then every
** path swept by a btSphereShape of "radius" (radius 0: a rayTest),
** answers into paths[i], and the seconds that took (the world's set-up
** not counted).  Negative when Bullet could not be set up.
*/
double bullet_sweeps(const double *v, size_t nv, const unsigned *idx,
                     size_t nt, double radius, bullet_path *paths,
                     size_t n);

#ifdef __cplusplus
}
#endif

#endif
