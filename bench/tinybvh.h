/* SPDX-License-Identifier: MIT */
/*
** tinybvh.h -- C calls onto tinybvh's BVH8_CPU (bench/tinybvh.cpp), the
** fastest float BVH the benches set beside libray and Embree.  Only with
** HAVE_TINYBVH (the Makefile defines it where ../shared/ext/tiny_bvh.h
** exists).  Not part of the library.
*/
#ifndef BENCH_TINYBVH_H
#define BENCH_TINYBVH_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct tbvh tbvh;

/* A BVH8_CPU over ntri triangles: idx holds three vertex numbers a
** triangle, xyz three doubles a vertex (rounded to float for tinybvh). */
tbvh *tbvh_build(const double *xyz, const unsigned *idx, size_t ntri);
void tbvh_free(tbvh *h);

/* Nearest hit within (0, tmax) of a ray with a unit direction d: 1 and
** *t, *prim, or 0. */
int tbvh_intersect(const tbvh *h, const float o[3], const float d[3],
                   float tmax, float *t, unsigned *prim);
/* Any hit within (0, tmax): 1 if occluded. */
int tbvh_occluded(const tbvh *h, const float o[3], const float d[3],
                  float tmax);

#ifdef __cplusplus
}
#endif

#endif
