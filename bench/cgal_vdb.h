/* SPDX-License-Identifier: MIT */
/*
** cgal_vdb.h -- C calls onto CGAL's Side_of_triangle_mesh (the exact
** reference for containment) and OpenVDB's mesh-to-volume bakers, for
** bench/contains.c; bench/cgal_vdb.cpp implements them, built by the
** Makefile with $(CXX) only where Debian's libcgal-dev (HAVE_CGAL) or
** libopenvdb-dev (HAVE_OPENVDB) is installed.  Not part of the library.
*/
#ifndef BENCH_CGAL_VDB_H
#define BENCH_CGAL_VDB_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct cgal_side cgal_side;

/* CGAL 5.5's Side_of_triangle_mesh over a Surface_mesh of the
** Exact_predicates_inexact_constructions_kernel (its AABB tree built
** here, not in the queries): xyz three doubles a vertex, idx three
** vertex numbers a triangle.  NULL on failure. */
cgal_side *cgal_side_new(const double *xyz, size_t nv, const unsigned *idx,
                         size_t nt);
void cgal_side_free(cgal_side *c);
/* For each of n points (three doubles each): 1 inside (CGAL's
** ON_BOUNDED_SIDE), 0 on the boundary, -1 outside. */
void cgal_side_query(const cgal_side *c, const double *pts, size_t n,
                     signed char *out);
/* For each of n points: the distance to the mesh's nearest point, by
** CGAL's AABB_tree::closest_point over the same mesh (a tree of its own,
** built with its distance queries' acceleration by cgal_side_new). */
void cgal_closest_query(const cgal_side *c, const double *pts, size_t n,
                        double *dist);

/* OpenVDB's signed distance over a cubic lattice: n^3 samples at
** lo + step * (i, j, k), the mesh's triangles given in world space.
** band_voxels > 0: meshToLevelSet with that half width (a narrow band,
** the samples beyond it +-band); 0: meshToSignedDistanceField with both
** bands wide enough to cover the whole lattice.  On `threads` TBB threads.
** Returns the bake's seconds (the grid's making, not the copy into out:
** out[(k n + j) n + i] is the grid's value at (i, j, k)), or -1. */
double vdb_bake(const double *xyz, size_t nv, const unsigned *idx,
                size_t nt, const double lo[3], double step, unsigned n,
                double band_voxels, unsigned threads, float *out);

#ifdef __cplusplus
}
#endif

#endif
