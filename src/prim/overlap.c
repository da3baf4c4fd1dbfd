/* SPDX-License-Identifier: MIT */
/*
** overlap.c -- do two shapes meet?  A box (any parallelepiped: an
** oriented box, or a box through an instance's affine map) against a
** triangle, a polygon, a plane, another parallelepiped, a point and a
** segment: the narrow phase of ray_overlap_shape's boxes, and of its
** spheres' and capsules' tests against boxes (query/overlap.c).  Plain
** geometry, no scene.
**
** Separating axes (Gottschalk, Lin, Manocha, "OBBTree", SIGGRAPH 1996;
** Akenine-Moller, "Fast 3D Triangle-Box Overlap Testing", JGT 6(1),
** 2001; Ericson, "Real-Time Collision Detection", 2005, 4.4 and 5.2):
** two convex polytopes are disjoint exactly when their projections on
** some axis are, and it suffices to try each one's face normals and the
** cross products of an edge of one with an edge of the other.  Every
** projection is taken relative to the parallelepiped's centre, so far
** geometry keeps its digits; a cross product that rounds to zero (two
** parallel edges) is no axis (its pair is covered by the face normals).
** Each projection is a dot product of three terms and the comparison
** adds a few: within gamma(8) of the magnitudes involved, so a pair that
** touches (projections meeting within that) may go either way, and
** nothing else: the test is exact to rounding.
*/
#include <stdio.h>

#include "prim/overlap.h"

int ray__pped_of_box(const ray_box_params *b, ray__pped *p)
{
    ray_vec3 e[3];

    if (!ray__box_frame(b, e))
        return 0;
    p->c = b->center;
    p->e[0] = v3_scale(e[0], b->half_extents.x);
    p->e[1] = v3_scale(e[1], b->half_extents.y);
    p->e[2] = v3_scale(e[2], b->half_extents.z);
    return 1;
}

/* The half-width of p's projection on axis a: sum |e_i . a|. */
static double reach(const ray__pped *p, ray_vec3 a)
{
    return fabs(v3_dot(p->e[0], a)) + fabs(v3_dot(p->e[1], a)) +
           fabs(v3_dot(p->e[2], a));
}

/* Does axis a separate p (its centre at the origin of the offsets) from
** the points v[0 .. n-1] (offsets from p's centre)?  A zero axis
** separates nothing. */
static int separates(const ray__pped *p, ray_vec3 a, const ray_vec3 *v,
                     size_t n)
{
    double lo = HUGE_VAL, hi = -HUGE_VAL, r;
    size_t i;

    if (a.x == 0 && a.y == 0 && a.z == 0)
        return 0;
    for (i = 0; i < n; i++) {
        double x = v3_dot(v[i], a);
        lo = x < lo ? x : lo;
        hi = x > hi ? x : hi;
    }
    r = reach(p, a);
    return lo > r || hi < -r;
}

/* p's face normals (cross products of its edge pairs). */
static void face_axes(const ray__pped *p, ray_vec3 n[3])
{
    n[0] = v3_cross(p->e[1], p->e[2]);
    n[1] = v3_cross(p->e[2], p->e[0]);
    n[2] = v3_cross(p->e[0], p->e[1]);
}

/* SAT between p and the convex polytope with vertices v (offsets from
** p's centre), edges along d[0 .. nd-1] and face normals f[0 .. nf-1]. */
static int sat(const ray__pped *p, const ray_vec3 *v, size_t n,
               const ray_vec3 *d, size_t nd, const ray_vec3 *f, size_t nf)
{
    ray_vec3 pn[3];
    size_t i, j;

    face_axes(p, pn);
    for (i = 0; i < 3; i++)
        if (separates(p, pn[i], v, n))
            return 0;
    for (i = 0; i < nf; i++)
        if (separates(p, f[i], v, n))
            return 0;
    for (i = 0; i < 3; i++)
        for (j = 0; j < nd; j++)
            if (separates(p, v3_cross(p->e[i], d[j]), v, n))
                return 0;
    return 1;
}

int ray__pped_overlaps_triangle(const ray__pped *p, ray_vec3 a, ray_vec3 b,
                                ray_vec3 c)
{
    ray_vec3 v[3], d[3], f;

    v[0] = v3_sub(a, p->c);
    v[1] = v3_sub(b, p->c);
    v[2] = v3_sub(c, p->c);
    d[0] = v3_sub(v[1], v[0]);
    d[1] = v3_sub(v[2], v[1]);
    d[2] = v3_sub(v[0], v[2]);
    f = v3_cross(d[0], d[1]);
    return sat(p, v, 3, d, 3, &f, 1);
}

int ray__pped_overlaps_pped(const ray__pped *p, const ray__pped *q)
{
    ray_vec3 v[8], f[3];
    int k;

    for (k = 0; k < 8; k++) {
        ray_vec3 x = v3_sub(q->c, p->c);
        x = v3_madd(x, k & 1 ? 1.0 : -1.0, q->e[0]);
        x = v3_madd(x, k & 2 ? 1.0 : -1.0, q->e[1]);
        v[k] = v3_madd(x, k & 4 ? 1.0 : -1.0, q->e[2]);
    }
    face_axes(q, f);
    return sat(p, v, 8, q->e, 3, f, 3);
}

int ray__pped_overlaps_plane(const ray__pped *p, ray_vec3 point, ray_vec3 n)
{
    return fabs(v3_dot(v3_sub(p->c, point), n)) <= reach(p, n);
}

/* p's coordinates of x: x = c + sum u_i e_i (Cramer's rule on the
** three edges); 0 for a flat p. */
static int coordinates(const ray__pped *p, ray_vec3 x, double u[3])
{
    ray_vec3 rel = v3_sub(x, p->c), n[3];
    double vol;
    int k;

    face_axes(p, n);
    vol = v3_dot(p->e[0], n[0]);
    if (!(vol != 0))
        return 0;
    for (k = 0; k < 3; k++)
        u[k] = v3_dot(rel, n[k]) / vol;
    return 1;
}

int ray__pped_contains(const ray__pped *p, ray_vec3 x)
{
    double u[3];

    return coordinates(p, x, u) && fabs(u[0]) <= 1 && fabs(u[1]) <= 1 &&
           fabs(u[2]) <= 1;
}

/* Corner k of p (bit i: +e_i). */
static ray_vec3 corner(const ray__pped *p, int k)
{
    ray_vec3 x = p->c;

    x = v3_madd(x, k & 1 ? 1.0 : -1.0, p->e[0]);
    x = v3_madd(x, k & 2 ? 1.0 : -1.0, p->e[1]);
    return v3_madd(x, k & 4 ? 1.0 : -1.0, p->e[2]);
}

/* The two triangles of face f (axis f / 2, side f % 2). */
static void face_triangles(const ray__pped *p, int f, ray_vec3 t[2][3])
{
    int axis = f / 2, base = f % 2 ? 1 << axis : 0;
    int j = 1 << ((axis + 1) % 3), l = 1 << ((axis + 2) % 3);

    t[0][0] = t[1][0] = corner(p, base);
    t[0][1] = corner(p, base | j);
    t[0][2] = t[1][1] = corner(p, base | j | l);
    t[1][2] = corner(p, base | l);
}

double ray__pped_signed(const ray__pped *p, ray_vec3 x, ray_vec3 *near)
{
    double best = HUGE_VAL;
    int f, t;

    for (f = 0; f < 6; f++) {
        ray_vec3 tri[2][3];
        face_triangles(p, f, tri);
        for (t = 0; t < 2; t++) {
            ray_vec3 y = ray__triangle_closest(tri[t][0], tri[t][1],
                                               tri[t][2], x);
            double d = ray__distance(x, y);
            if (d < best) {
                best = d;
                if (near != NULL)
                    *near = y;
            }
        }
    }
    return ray__pped_contains(p, x) ? -best : best;
}

/*
** The distance between segment [a, b] and the solid p: 0 when they meet
** (an end inside, or the segment crossing a face), else the least of
** the segment's distances to p's faces (two disjoint convex bodies are
** nearest at their boundaries).
*/
double ray__pped_segment(const ray__pped *p, ray_vec3 a, ray_vec3 b)
{
    double best = HUGE_VAL;
    int f, t;

    if (ray__pped_contains(p, a) || ray__pped_contains(p, b))
        return 0;
    for (f = 0; f < 6; f++) {
        ray_vec3 tri[2][3];
        face_triangles(p, f, tri);
        for (t = 0; t < 2; t++) {
            ray_vec3 ps, pt;
            double d;
            ray__segment_triangle_closest(a, b, tri[t][0], tri[t][1],
                                          tri[t][2], &ps, &pt);
            d = ray__distance(ps, pt);
            best = d < best ? d : best;
        }
    }
    return best;
}

/*
** A polygon (even-odd, vertices v mapped by xf) against p: they meet
** exactly when a vertex of the polygon lies in p, or an edge of the
** polygon meets p, or an edge of p crosses the polygon's region (its
** plane crossing inside the outline): the polygon's region and p's
** slice of its plane are two plane regions, and two plane regions meet
** where one's boundary crosses the other or one holds the other (then
** a vertex of the inner one, or an edge of p through the outer).
*/
int ray__pped_overlaps_polygon(const ray__pped *p, const ray_vec3 *v,
                               size_t count, const ray_transform *xf)
{
    ray_vec3 c, n;
    size_t i;
    int k, j;

    if (!ray__polygon_plane_mapped(v, count, xf, &c, &n) ||
        !ray__pped_overlaps_plane(p, c, n))
        return 0;
    for (i = 0; i < count; i++) {
        ray_vec3 a = ray__polygon_vertex(v, i, xf);
        ray_vec3 b = ray__polygon_vertex(v, (i + 1) % count, xf);
        if (ray__pped_segment(p, a, b) == 0)
            return 1;
    }
    for (k = 0; k < 8; k++)
        for (j = 0; j < 3; j++) {
            ray_vec3 a, b;
            double ha, hb;
            if (k & 1 << j)
                continue;
            a = corner(p, k);
            b = corner(p, k | 1 << j);
            ha = v3_dot(v3_sub(a, c), n);
            hb = v3_dot(v3_sub(b, c), n);
            if ((ha <= 0) != (hb <= 0) || ha == 0 || hb == 0) {
                ray_vec3 x = ha == hb ? a : v3_madd(a, ha / (ha - hb),
                                                    v3_sub(b, a));
                if (ray__polygon_contains(v, count, xf, x))
                    return 1;
            }
        }
    return 0;
}

/* A box is refused as ray_box and ray_scene_add_box refuse the same
** params (ray__box_check: also a box whose world bounds, with their
** rounding margin, pass DBL_MAX; issue 38, defect 1), so that no query
** answers for a box no other call accepts. */
int ray__shape_check(const ray_shape *k, ray__pped *p)
{
    ray__pped b;
    ray_vec3 lo, hi;
    char why[8];

    if (k == NULL)
        return 0;
    if (k->kind == RAY_SHAPE_CAPSULE)
        return v3_isfinite(k->a) && v3_isfinite(k->b) &&
               v3_isfinite(v3_sub(k->b, k->a)) &&
               k->radius >= 0 && k->radius < HUGE_VAL;
    if (k->kind != RAY_SHAPE_BOX ||
        !ray__box_check(&k->box, &lo, &hi, why, sizeof why) ||
        !ray__pped_of_box(&k->box, &b) || !v3_isfinite(b.e[0]) ||
        !v3_isfinite(b.e[1]) || !v3_isfinite(b.e[2]))
        return 0;
    if (p != NULL)
        *p = b;
    return 1;
}

void ray__shape_why(const ray_shape *k, const char *name, char *why,
                    size_t size)
{
    ray__pped b;
    ray_vec3 lo, hi;
    char box_why[160];

    if (k == NULL)
        snprintf(why, size, "shape is NULL");   /* ray_overlap_shape's */
    else if (k->kind == RAY_SHAPE_CAPSULE && !v3_isfinite(k->a))
        snprintf(why, size, "%sa (%.17g, %.17g, %.17g) is not finite", name,
                 k->a.x, k->a.y, k->a.z);
    else if (k->kind == RAY_SHAPE_CAPSULE && !v3_isfinite(k->b))
        snprintf(why, size, "%sb (%.17g, %.17g, %.17g) is not finite", name,
                 k->b.x, k->b.y, k->b.z);
    else if (k->kind == RAY_SHAPE_CAPSULE &&
             !v3_isfinite(v3_sub(k->b, k->a)))
        snprintf(why, size, "%sb - %sa overflows (a (%.17g, %.17g, %.17g), "
                 "b (%.17g, %.17g, %.17g))", name, name, k->a.x, k->a.y,
                 k->a.z, k->b.x, k->b.y, k->b.z);
    else if (k->kind == RAY_SHAPE_CAPSULE)
        snprintf(why, size, "%sradius is %.17g: negative or not finite",
                 name, k->radius);
    else if (k->kind != RAY_SHAPE_BOX)
        snprintf(why, size, "%skind is %u: not a RAY_SHAPE_*", name,
                 k->kind);
    else if (!ray__box_check(&k->box, &lo, &hi, box_why, sizeof box_why))
        snprintf(why, size, "%sbox: %s", name, box_why);
    else
        snprintf(why, size, "%sbox's corners overflow (its %s)", name,
                 ray__pped_of_box(&k->box, &b) ? "edges" : "axes");
}
