/* SPDX-License-Identifier: MIT */
/*
** overlap.h -- the narrow phase of the overlap queries (overlap.c): a
** parallelepiped (an oriented box, or any box through an affine map)
** against the pieces of the scene.  The sphere's tests are distances:
** the nearest points of nearest.c, ellipsoid.c and the primitives'.
*/
#ifndef RAY_OVERLAP_H
#define RAY_OVERLAP_H

#include "prim/sweep.h"

/* The points c + u0 e[0] + u1 e[1] + u2 e[2], |u_i| <= 1. */
typedef struct ray__pped {
    ray_vec3 c, e[3];
} ray__pped;

/* An oriented box as a parallelepiped (ray_box's frame): 1, or 0 for
** params ray_box refuses. */
int ray__pped_of_box(const ray_box_params *b, ray__pped *p);

/* Separating axes (overlap.c): 1 when p meets the triangle, the other
** parallelepiped q, the plane (a point and a unit normal), the polygon
** v[0 .. count-1] mapped by xf (NULL: not; even-odd). */
int ray__pped_overlaps_triangle(const ray__pped *p, ray_vec3 a, ray_vec3 b,
                                ray_vec3 c);
int ray__pped_overlaps_pped(const ray__pped *p, const ray__pped *q);
int ray__pped_overlaps_plane(const ray__pped *p, ray_vec3 point, ray_vec3 n);
int ray__pped_overlaps_polygon(const ray__pped *p, const ray_vec3 *v,
                               size_t count, const ray_transform *xf);

/* Is x in the solid p?  The signed distance from x to p's surface
** (negative inside), its nearest surface point in *near (may be NULL);
** the distance between segment [a, b] and the solid p (0 when they
** meet). */
int ray__pped_contains(const ray__pped *p, ray_vec3 x);
double ray__pped_signed(const ray__pped *p, ray_vec3 x, ray_vec3 *near);
double ray__pped_segment(const ray__pped *p, ray_vec3 a, ray_vec3 b);

/*
** Does the shape queries' shape k (ray_intersect_sweep, ray_overlap_shape)
** pass their checks (ray.h)?  A capsule: a, b and b - a finite, radius
** in [0, Inf); a box: params ray_box (and ray_scene_add_box) accept,
** whose parallelepiped is finite; another kind: no.  *p, when p is not
** NULL, receives a box's parallelepiped.
*/
int ray__shape_check(const ray_shape *k, ray__pped *p);

/* Why ray__shape_check refused k, in words, into why[size]: the field
** (its name after "name": "shape->" or "sweep->shape."), and its value.
** For the refusal path only. */
void ray__shape_why(const ray_shape *k, const char *name, char *why,
                    size_t size);

#endif /* RAY_OVERLAP_H */
