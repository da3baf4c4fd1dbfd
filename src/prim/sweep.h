/* SPDX-License-Identifier: MIT */
/*
** sweep.h -- the narrow phase of the shape queries: a sphere or a
** capsule moved along a line against one primitive (its first contact,
** or its overlap where it starts), and a box or a sphere against one
** primitive (overlap.c).  Plain geometry, no scene: the query layer
** (query/sweep.c, query/overlap.c) brings every primitive here in the
** world's shape, relative to the sweep's start.
*/
#ifndef RAY_SWEEP_H
#define RAY_SWEEP_H

#include "prim/prim.h"

/*
** The swept shape, in a frame whose origin is the capsule's end "a" at t
** = 0 (so a far-away sweep keeps its digits: every feature is taken
** relative to it, one rounding each, the same for a vertex shared by
** two triangles): the capsule around [t d, s + t d] of radius r at t
** (s = 0: a sphere at t d), for t in [t0, t1]; t1 shrinks to the best
** contact found so far.  x0 = t0 d, the core's start.
*/
typedef struct ray__sweep {
    ray_vec3 d;              /* the motion per unit t */
    ray_vec3 s;              /* the capsule's axis b - a (0: a sphere) */
    double r;                /* the radius, >= 0 */
    double t0, t1;           /* the interval searched */
    ray_vec3 x0;             /* t0 d */
    double d_len;            /* |d| */
    double t_unit;           /* t here is t_unit times the caller's t */
} ray__sweep;

/* Set up *sw for the caller's motion d over [t0, t1]: d is scaled by a
** power of two (exact) so that its largest component is in [1, 2), and
** t0, t1 and every t of a contact are in those units (a caller's t is
** sw->t_unit times them). */
void ray__sweep_start(ray__sweep *sw, ray_vec3 d, ray_vec3 s, double r,
                      double t0, double t1);

/*
** A contact: t in [t0, t1]; p, the contact point on the primitive (in the
** sweep's frame); n, the unit normal from the primitive toward the
** shape; depth > 0 when the shape already overlaps the primitive at t0
** (then t = t0 and n is the direction that separates them fastest).
*/
typedef struct ray__contact {
    double t;
    ray_vec3 p, n;
    double depth;
} ray__contact;

/*
** Keep contact (t, p, n, depth) in *best if it is better: earlier, or at
** the same t deeper.  1 if kept.
*/
int ray__contact_offer(ray__contact *best, double t, ray_vec3 p, ray_vec3 n,
                       double depth);

/*
** The slack every piece test is inflated by, for features whose largest
** coordinate magnitude in the sweep's frame is m: eps = gamma(64) (m +
** r + |s|) (sweep.c says why it covers the tests' rounding).
*/
double ray__sweep_eps(const ray__sweep *sw, double m);

/*
** Primitives against the sweep, each in the sweep's frame: 1 with *c
** (better than it was: ray__contact_offer) or 0.  Solids (sphere,
** capsule, parallelepiped) report an overlap when the shape starts
** partly inside them; surfaces (triangle, plane, polygon) when it
** starts within its radius of them.  A sphere sweep (s = 0) is tested
** against the Minkowski sum's pieces (sweep.c); a capsule sweep by
** conservative Newton steps on the convex distance between the moving
** segment and the primitive (sweep_newton.c).
**   triangle:       corners a, b, c;
**   sphere:         centre c, radius R;
**   capsule:        segment [a, b], radius R;
**   plane:          a point and a unit normal (two-sided surface);
**   polygon:        v[0 .. n-1] mapped by xf into the sweep's frame (an
**                   instance's transform with the frame's origin taken
**                   off its translation), even-odd as ray_polygon;
**   parallelepiped: 8 corners, corner k = c + (+-e0) + (+-e1) + (+-e2)
**                   by the bits of k (a box through any affine map).
*/
int ray__sweep_triangle(ray__sweep *sw, ray_vec3 a, ray_vec3 b, ray_vec3 c,
                        ray__contact *best);
int ray__sweep_sphere(ray__sweep *sw, ray_vec3 c, double R,
                      ray__contact *best);
int ray__sweep_capsule(ray__sweep *sw, ray_vec3 a, ray_vec3 b, double R,
                       ray__contact *best);
int ray__sweep_plane(ray__sweep *sw, ray_vec3 point, ray_vec3 n,
                     ray__contact *best);
int ray__sweep_polygon(ray__sweep *sw, const ray_vec3 *v, size_t count,
                       const ray_transform *xf, ray__contact *best);
int ray__sweep_parallelepiped(ray__sweep *sw, const ray_vec3 corner[8],
                              ray__contact *best);

/*
** An ellipsoid {c + U diag(e) v : |v| <= 1} (U's columns its unit axes,
** e its semi-axes, descending), swept along c + [0, 1] w (w = 0: the
** ellipsoid alone): what an instance's sphere or capsule is through a
** transform that is not a similarity, in the sweep's frame.
** ray__sweep_ellipsoid: its first contact with the sweep by
** conservative Newton steps on the convex distance (sweep_newton.c): 1
** with *best improved, 0, or -1 for a capsule sweep against a swept
** ellipsoid (an ellipsoid swept along a parallelogram, which this does
** not answer: the caller takes its bounds).
*/
typedef struct ray__ellipsoid {
    ray_vec3 c, w;
    double u[3][3], e[3];
} ray__ellipsoid;
int ray__sweep_ellipsoid(ray__sweep *sw, const ray__ellipsoid *el,
                         ray__contact *best);

/* The point of segment [a, b] nearest p (an end, or a + t (b - a)). */
ray_vec3 ray__segment_point(ray_vec3 p, ray_vec3 a, ray_vec3 b);

/*
** The distance between segment [a, b] (a == b: the point a) and the
** polygon v[0 .. count-1] mapped by xf (NULL: not; the region inside its
** outline, even-odd), with the points *q on the segment and *p on the
** polygon that realise it and the polygon's unit Newell normal *nrm
** (sweep.c): 0 where the segment crosses the polygon's inside, else the
** nearest of the ends' nearest points and of the segment's to each edge
** (a segment that does not cross the region is nearest it at an end or
** at the outline); +Inf for a polygon of no area.
*/
double ray__segment_polygon(ray_vec3 a, ray_vec3 b, const ray_vec3 *v,
                            size_t count, const ray_transform *xf,
                            ray_vec3 *q, ray_vec3 *p, ray_vec3 *nrm);

/*
** Polygon helpers (polygon.c), for vertices v mapped by xf (NULL: not):
** ray__polygon_contains -- does the foot of point x on the polygon's
** plane lie inside it (even-odd, Haines' crossings test in the plane's
** tangent frame)?  ray__polygon_plane_mapped -- its centroid and unit
** Newell normal; 0 for no area.
*/
int ray__polygon_contains(const ray_vec3 *v, size_t count,
                          const ray_transform *xf, ray_vec3 x);
int ray__polygon_plane_mapped(const ray_vec3 *v, size_t count,
                              const ray_transform *xf, ray_vec3 *c,
                              ray_vec3 *n);
ray_vec3 ray__polygon_vertex(const ray_vec3 *v, size_t i,
                             const ray_transform *xf);

/*
** The pieces (sweep_pieces.c), for the primitives of sweep.c.
*/
/*
** Where a piece's point y (on K - [0, s]) came from on K itself: the
** scene's contact point.  PLAIN: y; SHIFTED: y + s (a feature of K - s);
** FIXED: the point "at" (an edge [v - s, v]: the capsule's side touches
** v); PARALLELOGRAM: y with its part along -s taken off (an edge [at, at
** + e] of K swept by -s).
*/
enum {
    RAY__FROM_PLAIN,
    RAY__FROM_SHIFTED,
    RAY__FROM_FIXED,
    RAY__FROM_PARALLELOGRAM
};

typedef struct ray__origin {
    int kind;
    ray_vec3 at, e;
} ray__origin;

/*
** A face: a convex polygon v[0 .. n-1] (a triangle, a parallelogram),
** or (poly != NULL) a polygon of the scene, even-odd, whose points are
** the face's points plus "lift" (a face of K - s is K's face moved by
** -s).  Its slab of half-width R = r + eps: the path enters through the
** offset plane on the start's side, where the foot of the entry point
** must lie on the face.
*/
typedef struct ray__face {
    const ray_vec3 *v;
    size_t n;
    const ray_vec3 *pv;          /* a scene polygon instead, or NULL */
    size_t pn;
    const ray_transform *pxf;
    ray_vec3 lift;               /* added before the polygon's test */
} ray__face;

/* a x b, each component by ray__diff_of_products (relative accuracy). */
ray_vec3 ray__cross_exact(ray_vec3 a, ray_vec3 b);
/* The slack of the pieces of features with coordinates v[0 .. n-1]. */
double ray__sweep_eps_of(const ray__sweep *sw, const ray_vec3 *v, size_t n);
/* The ball of radius r + rp + eps about v; the cylinder of that radius
** about [p, q]; the slab of half-width r + eps over face fc (unit
** normal nrm, through "at"): each offers its entry to *best, o saying
** where its point came from on the primitive. */
int ray__sweep_ball(const ray__sweep *sw, ray_vec3 v, double rp, double eps,
                    const ray__origin *o, ray__contact *best);
int ray__sweep_cylinder(const ray__sweep *sw, ray_vec3 p, ray_vec3 q,
                        double rp, double eps, const ray__origin *o,
                        ray__contact *best);
int ray__sweep_slab(const ray__sweep *sw, const ray__face *fc, ray_vec3 nrm,
                    ray_vec3 at, double eps, const ray__origin *o,
                    ray__contact *best);
/* A convex face v[0 .. n-1] (and for a capsule its copy moved by -s);
** an edge (and its copy and parallelogram); a vertex (and its copy and
** the cylinder between them). */
void ray__sweep_faces(const ray__sweep *sw, const ray_vec3 *v, size_t n,
                      double eps, int capsule, ray__contact *best);
void ray__sweep_edge(const ray__sweep *sw, ray_vec3 p, ray_vec3 q,
                     double eps, int capsule, ray__contact *best);
void ray__sweep_vertex(const ray__sweep *sw, ray_vec3 v, double eps,
                       int capsule, ray__contact *best);
/* Overlapping at the start (signed core distance dist < r - eps)?  1
** with the overlap offered to *best. */
int ray__sweep_overlap(const ray__sweep *sw, double dist, ray_vec3 q,
                       ray_vec3 p, ray_vec3 k_normal, double eps,
                       ray__contact *best);

#endif /* RAY_SWEEP_H */
