/* SPDX-License-Identifier: MIT */
/*
** ldgeom.h -- a long double geometry kit for the suites that check the
** scene's geometric queries against brute force (check_closest.c,
** check_sweep.c, check_overlap.c): vectors and the nearest points of
** segments and triangles, computed by the tests' own routines, not the
** library's.  Header-only, every function static.
*/
#ifndef RAY_LDGEOM_H
#define RAY_LDGEOM_H

#include <math.h>

#include "ray.h"


typedef long double ld;
typedef struct lvec {
    ld x, y, z;
} lvec;

static inline lvec lv(ray_vec3 a)
{
    lvec r;
    r.x = (ld)a.x;
    r.y = (ld)a.y;
    r.z = (ld)a.z;
    return r;
}

static inline lvec lv3(ld x, ld y, ld z)
{
    lvec r;
    r.x = x;
    r.y = y;
    r.z = z;
    return r;
}

static inline lvec lsub(lvec a, lvec b)
{
    return lv3(a.x - b.x, a.y - b.y, a.z - b.z);
}

static inline lvec ladd(lvec a, lvec b)
{
    return lv3(a.x + b.x, a.y + b.y, a.z + b.z);
}

static inline lvec lscale(lvec a, ld s)
{
    return lv3(a.x * s, a.y * s, a.z * s);
}

static inline ld ldot(lvec a, lvec b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

static inline lvec lcross(lvec a, lvec b)
{
    return lv3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z,
               a.x * b.y - a.y * b.x);
}

static inline ld llen(lvec a)
{
    return sqrtl(ldot(a, a));
}

static inline lvec lunit(lvec a)
{
    return lscale(a, 1 / llen(a));
}

static inline ld ldist(lvec a, lvec b)
{
    return llen(lsub(a, b));
}

/* The nearest point of segment [a, b] to q. */
static inline lvec ref_segment(lvec q, lvec a, lvec b)
{
    lvec ab = lsub(b, a);
    ld t;

    if (ldot(ab, ab) == 0)
        return a;
    t = ldot(lsub(q, a), ab) / ldot(ab, ab);

    t = t < 0 ? 0 : (t > 1 ? 1 : t);
    return ladd(a, lscale(ab, t));
}

/* The nearest point of triangle (a, b, c) to q: q's foot on the plane
** if the three edge tests put it inside, else the nearest edge point
** (not Ericson's region walk, which the library uses). */
static inline lvec ref_triangle(lvec q, lvec a, lvec b, lvec c)
{
    lvec n = lcross(lsub(b, a), lsub(c, a));
    lvec f = lsub(q, lscale(n, ldot(lsub(q, a), n) / ldot(n, n)));
    lvec e[3];
    int k, best = 0;

    if (ldot(lcross(lsub(b, a), lsub(f, a)), n) >= 0 &&
        ldot(lcross(lsub(c, b), lsub(f, b)), n) >= 0 &&
        ldot(lcross(lsub(a, c), lsub(f, c)), n) >= 0)
        return f;
    e[0] = ref_segment(q, a, b);
    e[1] = ref_segment(q, b, c);
    e[2] = ref_segment(q, c, a);
    for (k = 1; k < 3; k++)
        if (ldist(e[k], q) < ldist(e[best], q))
            best = k;
    return e[best];
}

/* The box's frame as ray_box(3) defines it, in long double. */
static inline void ref_box_frame(const ray_box_params *b, lvec e[3])
{
    lvec x = lunit(lv(b->axis_x)), y = lv(b->axis_y);

    e[0] = x;
    e[1] = lunit(lsub(y, lscale(x, ldot(y, x))));
    e[2] = lcross(e[0], e[1]);
}

/* The nearest point of the box's surface: outside, q clamped to it;
** inside, q moved onto the nearest face.  *face: the face's axis. */
static inline lvec ref_box(const ray_box_params *b, lvec q, int *face)
{
    lvec e[3], rel = lsub(q, lv(b->center)), p = lv(b->center);
    ld o[3], h[3], l[3], excess = -HUGE_VALL;
    int k, axis = 0;

    ref_box_frame(b, e);
    h[0] = (ld)b->half_extents.x;
    h[1] = (ld)b->half_extents.y;
    h[2] = (ld)b->half_extents.z;
    for (k = 0; k < 3; k++) {
        o[k] = ldot(rel, e[k]);
        if (fabsl(o[k]) - h[k] > excess) {
            excess = fabsl(o[k]) - h[k];
            axis = k;
        }
    }
    for (k = 0; k < 3; k++)
        l[k] = excess > 0 ? fminl(fmaxl(o[k], -h[k]), h[k]) : o[k];
    l[axis] = o[axis] < 0 ? -h[axis] : h[axis];
    for (k = 0; k < 3; k++)
        p = ladd(p, lscale(e[k], l[k]));
    if (face != NULL)
        *face = axis;
    return p;
}

/* The nearest point of the capsule's surface: radius away from the
** segment's nearest point (q on the segment: any such point). */
static inline lvec ref_capsule(const ray_capsule_params *c, lvec q)
{
    lvec s = ref_segment(q, lv(c->a), lv(c->b)), d = lsub(q, s);

    if (llen(d) == 0)
        d = lcross(lsub(lv(c->b), lv(c->a)), lv3(1, 0, 0));
    return ladd(s, lscale(lunit(d), (ld)c->radius));
}

/* t clamped to [0, 1]. */
static inline ld lclamp01(ld t)
{
    return t < 0 ? 0 : (t > 1 ? 1 : t);
}

/* The distance between segments [p0, p1] and [q0, q1]: the
** unconstrained nearest pair of their lines (Cramer), clamped, then each
** parameter again from the other's clamp, and the four ends' distances
** to the other segment as a check, all in long double. */
static inline ld ref_segments(lvec p0, lvec p1, lvec q0, lvec q1)
{
    lvec d1 = lsub(p1, p0), d2 = lsub(q1, q0), r = lsub(p0, q0);
    ld a = ldot(d1, d1), e = ldot(d2, d2), b = ldot(d1, d2);
    ld c = ldot(d1, r), f = ldot(d2, r), den = a * e - b * b, s = 0, t = 0;
    ld best, d;

    if (a > 0 && e > 0) {
        if (den > 0)
            s = lclamp01((b * f - c * e) / den);
        t = (b * s + f) / e;
        if (t < 0) {
            t = 0;
            s = lclamp01(-c / a);
        } else if (t > 1) {
            t = 1;
            s = lclamp01((b - c) / a);
        }
    }
    best = ldist(ladd(p0, lscale(d1, s)), ladd(q0, lscale(d2, t)));
    if ((d = ldist(ref_segment(p0, q0, q1), p0)) < best)
        best = d;
    if ((d = ldist(ref_segment(p1, q0, q1), p1)) < best)
        best = d;
    if ((d = ldist(ref_segment(q0, p0, p1), q0)) < best)
        best = d;
    if ((d = ldist(ref_segment(q1, p0, p1), q1)) < best)
        best = d;
    return best;
}

/* The distance between segment [p0, p1] and triangle (a, b, c): 0 where
** the segment crosses it (its plane crossing inside the triangle), else
** the least of the ends' distances and the segment's to the edges. */
static inline ld ref_segment_triangle(lvec p0, lvec p1, lvec a, lvec b,
                                      lvec c)
{
    lvec n = lcross(lsub(b, a), lsub(c, a));
    ld h0 = ldot(lsub(p0, a), n), h1 = ldot(lsub(p1, a), n), best, d;

    if ((h0 <= 0 && h1 >= 0) || (h0 >= 0 && h1 <= 0)) {
        if (h0 != h1) {
            lvec x = ladd(p0, lscale(lsub(p1, p0), h0 / (h0 - h1)));
            if (ldist(ref_triangle(x, a, b, c), x) == 0 ||
                (ldot(lcross(lsub(b, a), lsub(x, a)), n) >= 0 &&
                 ldot(lcross(lsub(c, b), lsub(x, b)), n) >= 0 &&
                 ldot(lcross(lsub(a, c), lsub(x, c)), n) >= 0))
                return 0;
        }
    }
    best = ldist(ref_triangle(p0, a, b, c), p0);
    if ((d = ldist(ref_triangle(p1, a, b, c), p1)) < best)
        best = d;
    if ((d = ref_segments(p0, p1, a, b)) < best)
        best = d;
    if ((d = ref_segments(p0, p1, b, c)) < best)
        best = d;
    if ((d = ref_segments(p0, p1, c, a)) < best)
        best = d;
    return best;
}

#endif
