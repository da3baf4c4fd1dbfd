/* SPDX-License-Identifier: MIT */
/*
** box.c -- ray / oriented box: the slab method (Kay and Kajiya, "Ray
** Tracing Complex Scenes", SIGGRAPH 1986; Williams, Barrus, Morley and
** Shirley, "An Efficient and Robust Ray-Box Intersection Algorithm", JGT
** 10(1), 2005) in the box's own frame, with the ray's origin taken
** relative to the box's centre, so a box far from the world origin keeps
** its digits, and the direction scaled by a power of two, so its length
** does not matter.
*/
#include <stdio.h>

#include "prim/prim.h"

/* A vector in a message, as the scene's BOX_V3FMT (scene.h, a layer
** above this file) writes it. */
#define BOX_V3FMT "(%g, %g, %g)"
#define BOX_V3ARGS(v) (v).x, (v).y, (v).z

/*
** The box's frame: ex = axis_x / |axis_x|; ey = axis_y / |axis_y| made
** orthogonal to ex by Gram-Schmidt, run twice ("twice is enough":
** Giraud, Langou, Rozloznik, "The loss of orthogonality in the
** Gram-Schmidt process", Comput. Math. Appl. 50, 2005), then normalised;
** ez = ex x ey, normalised.  The same operations on every call, so the
** scene (which keeps the parameters) and the bare function see the same
** box bit for bit.
**
** FRAME_DELTA bounds the computed frame's departure from orthonormality,
** |e_j . e_k - [j == k]|: each normalisation leaves a relative error of
** about 5 roundings per component (the division by the largest
** component, the dot product's 3, the square root, the reciprocal and
** the product), so |e_k|^2 - 1 is within about 10; the second projection
** leaves |ex . r2| within about 6 roundings of |r2| whatever r1's size,
** 11 after normalising; the cross product adds 2 per component, 10 after
** normalising.  gamma(16) covers each with room; tests/check_box.c
** measures the frame of random and nearly parallel axes against it.
** The same bound decides "parallel": axis_y / |axis_y| is refused when
** its part orthogonal to ex is within gamma(16) in every component, the
** rounding error of that part (yn's and ex's 5 each, the dot product's
** 3, the product and the difference): then it may be rounding noise and
** carries no direction.
*/
#define FRAME_ROUNDINGS 16

static double frame_delta(void)
{
    return ray__gamma(FRAME_ROUNDINGS);
}

typedef struct box_frame {
    ray_vec3 e[3];           /* the unit axes x, y, z, in world space */
} box_frame;

/* Why a parameter block is refused (BOX_VALID: it is not). */
typedef enum box_fault {
    BOX_VALID,
    BOX_NULL,
    BOX_CENTER,
    BOX_HALF_EXTENTS,
    BOX_AXIS_X,
    BOX_AXIS_Y,
    BOX_PARALLEL,
    BOX_TOO_LARGE,
    BOX_HALF_TOO_LARGE
} box_fault;

/*
** The largest half-extent accepted, 2^1021 (about 2.2e307), so that a ray
** starting inside has a finite exit t (issue 38, defect 10: half-extents
** of 1e308 were accepted and a ray from the centre missed).  local_ray
** scales the direction so its largest component lies in [1/2, 1): its
** length is at least 1/2, so its largest local component |d_k| is at
** least 1/(2 sqrt 3) > 0.288 (the frame orthonormal to delta), and an
** origin inside has |o_k| <= h_k, so that slab's exit (h_k + |o_k|) /
** |d_k| is below 6.93 h_k (with its few roundings) <= 1.74 2^1023 <
** DBL_MAX.  The smallest exit, which ray_box reports, is no larger.
*/
#define BOX_MAX_HALF 0x1p1021

static double max_abs(ray_vec3 a)
{
    return fmax(fabs(a.x), fmax(fabs(a.y), fabs(a.z)));
}

static void to_array(ray_vec3 v, double a[3])
{
    a[0] = v.x;
    a[1] = v.y;
    a[2] = v.z;
}

/* a minus its component along the unit vector "unit". */
static ray_vec3 without_component(ray_vec3 a, ray_vec3 unit)
{
    return v3_madd(a, -v3_dot(a, unit), unit);
}

static box_fault frame_of(const ray_box_params *b, box_frame *f)
{
    ray_vec3 h, yn, r1;

    if (b == NULL)
        return BOX_NULL;
    if (!v3_isfinite(b->center))
        return BOX_CENTER;
    h = b->half_extents;
    if (!(h.x > 0 && h.x < HUGE_VAL && h.y > 0 && h.y < HUGE_VAL &&
          h.z > 0 && h.z < HUGE_VAL))
        return BOX_HALF_EXTENTS;
    if (h.x > BOX_MAX_HALF || h.y > BOX_MAX_HALF || h.z > BOX_MAX_HALF)
        return BOX_HALF_TOO_LARGE;
    if (!v3_normalize(b->axis_x, &f->e[0]))
        return BOX_AXIS_X;
    if (!v3_normalize(b->axis_y, &yn))
        return BOX_AXIS_Y;
    r1 = without_component(yn, f->e[0]);
    if (!(max_abs(r1) > frame_delta()) ||
        !v3_normalize(without_component(r1, f->e[0]), &f->e[1]) ||
        !v3_normalize(v3_cross(f->e[0], f->e[1]), &f->e[2]))
        return BOX_PARALLEL;
    return BOX_VALID;
}

/*
** The world box of the oriented box, rounded outward: centre +- ext,
** ext_i = sum_k h_k |e_k,i|, grown by gamma(12) (|c_i| + ext_i), which
** covers the rounding of a hit point (gamma(4) of the same magnitudes,
** box_fill), of ext (3 roundings) and of forming lo and hi (3), so every
** hit point ray_box computes lies inside.  0 when it does not fit in a
** double.
*/
static int world_box(const ray_box_params *b, const box_frame *f,
                     ray_vec3 *lo, ray_vec3 *hi)
{
    double c[3], h[3], e[3][3], l[3], u[3];
    int i;

    to_array(b->center, c);
    to_array(b->half_extents, h);
    for (i = 0; i < 3; i++)
        to_array(f->e[i], e[i]);
    for (i = 0; i < 3; i++) {
        double ext = h[0] * fabs(e[0][i]) + h[1] * fabs(e[1][i]) +
                     h[2] * fabs(e[2][i]);
        double grow = ray__gamma(12) * (fabs(c[i]) + ext);

        l[i] = (c[i] - ext) - grow;
        u[i] = (c[i] + ext) + grow;
        if (!(fabs(l[i]) < HUGE_VAL && fabs(u[i]) < HUGE_VAL))
            return 0;
    }
    *lo = v3(l[0], l[1], l[2]);
    *hi = v3(u[0], u[1], u[2]);
    return 1;
}

/* The frame and the world box of b, or why b is refused: the one test
** of validity, shared by ray_box and the scene's check. */
static box_fault box_setup(const ray_box_params *b, box_frame *f,
                           ray_vec3 *lo, ray_vec3 *hi)
{
    box_fault fault = frame_of(b, f);

    if (fault == BOX_VALID && !world_box(b, f, lo, hi))
        fault = BOX_TOO_LARGE;
    return fault;
}

/*
** The ray in the box's frame.  The direction is scaled by 2^-e, e the
** exponent of its largest component, which brings that component into
** [1/2, 1) exactly (ldexp only moves the exponent; components 2^1000
** times smaller than the largest may lose bits as subnormals, noise
** beside it): a direction of any length gives the same local direction,
** and t for the scaled direction is t * 2^e, exactly (ray_sphere's
** scaled_dir does the same).
*/
typedef struct box_ray {
    double h[3];             /* the half-extents */
    double o[3], d[3];       /* origin - centre and scaled dir, local */
    double o_mag[3], d_mag[3];   /* sum_i |rel_i e_k,i|, sum_i |d_i e_k,i| */
    double o_sum, d_sum;     /* sum_k |o_k|, sum_k |d_k| */
} box_ray;

static int local_ray(const ray_ray *r, const ray_box_params *b,
                     const box_frame *f, box_ray *L, int *e)
{
    double m = max_abs(r->dir);
    ray_vec3 rel = v3_sub(r->org, b->center), d;
    int k;

    frexp(m, e);
    d = v3(ldexp(r->dir.x, -*e), ldexp(r->dir.y, -*e), ldexp(r->dir.z, -*e));
    to_array(b->half_extents, L->h);
    L->o_sum = L->d_sum = 0;
    for (k = 0; k < 3; k++) {
        ray_vec3 ek = f->e[k];
        L->o[k] = v3_dot(rel, ek);
        L->d[k] = v3_dot(d, ek);
        L->o_mag[k] = v3_dot(v3_abs(rel), v3_abs(ek));
        L->d_mag[k] = v3_dot(v3_abs(d), v3_abs(ek));
        L->o_sum += fabs(L->o[k]);
        L->d_sum += fabs(L->d[k]);
    }
    /* An origin farther from the centre than doubles reach: a miss. */
    return L->o_sum < HUGE_VAL;
}

/*
** Rounding-error bounds, in the scaled direction's units (running error
** analysis: Higham, "Accuracy and Stability of Numerical Algorithms", 2nd
** ed., 3.1; gamma(n) = n u / (1 - n u)).  The box is the one spanned by
** the computed frame; its local coordinates are q = (M M^T)^-1 M f for
** the matrix M of rows e_k, where the dot products give M f: with
** |M M^T - I| <= delta per entry (FRAME_DELTA), |q_k - (M f)_k| <= delta
** sum_j |q_j| <= 2 delta sum_j |(M f)_j| (first order, and the second
** order while 3 delta < 1/2).  So the local origin o_k = rel . e_k is off
** by at most
**     e_o = gamma(4) sum_i |rel_i e_k,i| + 2 delta sum_j |o_j|
** (rel = org - centre rounds once, the dot product 3 times), and the
** local direction d_k by e_d = gamma(3) sum_i |d_i e_k,i| + 2 delta
** sum_j |d_j|; each times (1 + gamma(2)) for the bound's own evaluation.
*/
static double origin_error(const box_ray *L, int k)
{
    return (ray__gamma(4) * L->o_mag[k] + 2 * frame_delta() * L->o_sum) *
           (1 + ray__gamma(2));
}

static double direction_error(const box_ray *L, int k)
{
    return (ray__gamma(3) * L->d_mag[k] + 2 * frame_delta() * L->d_sum) *
           (1 + ray__gamma(2));
}

/*
** A lower bound on the exact t = (face - o_k) / d_k, face = +-h_k, by
** interval arithmetic on its terms: the numerator is off by at most e_n =
** e_o + u |face - o_k| (its subtraction), the denominator by e_d, so
** with the signs arranged for d_k > 0 the exact quotient is at least
** (n - e_n) / (d_k + e_d) when n - e_n >= 0 and (n - e_n) / (d_k - e_d)
** otherwise.  (The first-order bound (e_n + |t| e_d) / |d_k| is far too
** pessimistic when e_d is a good part of |d_k|, a ray nearly parallel to
** a slab, whose t is huge but of a known sign.)  Rounded down by
** gamma(3) for the three operations that form it.  -HUGE_VAL when e_d >=
** |d_k|: d_k's sign is unknown, and t anything.
*/
static double slab_t_lower(const box_ray *L, int k, double face)
{
    double n = face - L->o[k], den = L->d[k];
    double e_n = origin_error(L, k) + ray__gamma(1) * fabs(n);
    double e_d = direction_error(L, k), low;

    if (!(e_d < fabs(den)))
        return -HUGE_VAL;
    if (den < 0)
        n = -n, den = -den;
    low = (n - e_n) / (n - e_n >= 0 ? den + e_d : den - e_d);
    return low >= 0 ? low * (1 - ray__gamma(3)) : low * (1 + ray__gamma(3));
}

/* The face of slab k a ray enters (side -1: the face at -h_k) or leaves
** through, by the sign of its local direction. */
static double entry_side(const box_ray *L, int k)
{
    return L->d[k] > 0 ? -1.0 : 1.0;
}

/*
** The slabs |q_k| <= h_k, closed: [entry_k, leave_k] the ray's interval in
** slab k.  A direction with d_k == 0 exactly (an axis-aligned box and a
** ray along a face) is not divided by: (h - o_k)/0 is Inf, or NaN where
** the origin lies on the face plane (0/0), which a max or min would then
** drop or propagate.  The ray is inside that slab for every t when
** |o_k| <= h_k -- on a face plane included, so a ray along a face, inside
** its extent, hits the box where it enters the face (at an edge) -- and
** outside for every t otherwise: a miss.  live[k] is 0 for such a slab.
*/
static int slab_intervals(const box_ray *L, double entry[3], double leave[3],
                          int live[3])
{
    int k;

    for (k = 0; k < 3; k++) {
        double side = entry_side(L, k);

        live[k] = L->d[k] != 0;
        if (!live[k]) {
            if (!(fabs(L->o[k]) <= L->h[k]))
                return 0;
            entry[k] = -HUGE_VAL;
            leave[k] = HUGE_VAL;
            continue;
        }
        entry[k] = (side * L->h[k] - L->o[k]) / L->d[k];
        leave[k] = (-side * L->h[k] - L->o[k]) / L->d[k];
    }
    return 1;
}

/*
** A lower bound on the exact exit, min_k leave_k: the smallest of the
** slabs' own lower bounds (the computed smallest exit alone would not
** do: another slab's exact exit may lie below it by that slab's error).
** A slab whose direction is within its error of 0 may have either sign:
** its exact exit is then (h_k - |q_k|) / |d_k| or more, |q_k| <= |o_k| +
** e_o, which is positive when the origin is inside it by more than its
** error, and unknown (a miss) when not.
*/
static double exit_lower_bound(const box_ray *L, const int live[3])
{
    double lower = HUGE_VAL;
    int k;

    for (k = 0; k < 3; k++) {
        double side = -entry_side(L, k), b;

        if (!live[k])
            continue;
        b = slab_t_lower(L, k, side * L->h[k]);
        if (!(b > -HUGE_VAL)) {
            double margin = L->h[k] - fabs(L->o[k]) - origin_error(L, k);
            double den = fabs(L->d[k]) + direction_error(L, k);
            b = margin > 0 ? margin / den * (1 - ray__gamma(3)) : -HUGE_VAL;
        }
        lower = fmin(lower, b);
    }
    return lower;
}

/*
** Fill *hit for the hit at t (t_s in the scaled units) on the face of
** slab "axis" at side * h.  The local point has q_axis = side * h exactly
** and the other two o_j + t_s d_j clamped to the face (they may round
** past its edge by an ulp), so p = c + sum_k q_k e_k lies on the face of
** the box spanned by the frame but for its own rounding: the sum of three
** products (gamma(3) sum_k |q_k e_k,i|) and the centre's addition (u
** |p_i|), within gamma(4) (|c_i| + sum_k |q_k e_k,i|); gamma(5) with the
** bound's own rounding.  Nothing of t's error reaches p off the face: it
** only moves p along it.  (u, v): ray.h, ray_box.
*/
static int box_fill(const ray_box_params *b, const box_frame *f,
                    const box_ray *L, int axis, double side, double t_s,
                    double t, ray_hit *hit)
{
    int a = (axis + 1) % 3, c = (axis + 2) % 3, k;
    double q[3];
    ray_vec3 s, p, mag;

    for (k = 0; k < 3; k++) {
        double x = L->o[k] + t_s * L->d[k];
        q[k] = k == axis ? side * L->h[k]
                         : fmin(fmax(x, -L->h[k]), L->h[k]);
    }
    s = v3_add(v3_add(v3_scale(f->e[0], q[0]), v3_scale(f->e[1], q[1])),
               v3_scale(f->e[2], q[2]));
    p = v3_add(b->center, s);
    mag = v3_add(v3_add(v3_scale(v3_abs(f->e[0]), fabs(q[0])),
                        v3_scale(v3_abs(f->e[1]), fabs(q[1]))),
                 v3_scale(v3_abs(f->e[2]), fabs(q[2])));
    mag = v3_scale(v3_add(v3_abs(b->center), mag), ray__gamma(5));
    if (!v3_isfinite(p) || !v3_isfinite(mag))
        return 0;
    hit->t = t;
    hit->p = p;
    hit->n = v3_scale(f->e[axis], side);
    hit->u = 0.5 * (side * q[a] / L->h[a]) + 0.5;
    hit->v = 0.5 * (q[c] / L->h[c]) + 0.5;
    hit->p_err = mag;
    hit->geom_id = RAY_INVALID_ID;
    hit->prim_id = RAY_INVALID_ID;
    hit->inst_id = RAY_INVALID_ID;
    return 1;
}

/* The slab whose entry is last (near) and whose exit is first (far); -1
** where every live slab's is infinite.  Ties go to the lower axis. */
static void last_entry_first_exit(const double entry[3], const double leave[3],
                                  double *near, int *near_axis, double *far,
                                  int *far_axis)
{
    int k;

    *near = -HUGE_VAL, *far = HUGE_VAL;
    *near_axis = *far_axis = -1;
    for (k = 0; k < 3; k++) {
        if (entry[k] > *near)
            *near = entry[k], *near_axis = k;
        if (leave[k] < *far)
            *far = leave[k], *far_axis = k;
    }
}

/*
** The nearest of the entry and (from inside) the exit that lies in (tmin,
** tmax) with its error interval past tmin (ray-numerics(7), "A hit past
** tmin by more than its error": a ray leaving a face starts on it, or
** within its rounding error, and its t for that face is noise around 0).
** The interval test near <= far is closed, so a ray through an edge or a
** corner hits: there is no crack between faces, whichever face the tie
** gives.
*/
int ray_box(const ray_ray *r, const ray_box_params *b, ray_hit *hit)
{
    box_frame f;
    box_ray L;
    ray_vec3 lo, hi;
    double entry[3], leave[3], tmin, tmax, near, far, t_s, side;
    int live[3], e, near_axis, far_axis, axis;

    if (r == NULL || hit == NULL || !ray__ray_usable(r) ||
        box_setup(b, &f, &lo, &hi) != BOX_VALID ||
        !local_ray(r, b, &f, &L, &e) ||
        !slab_intervals(&L, entry, leave, live))
        return 0;
    last_entry_first_exit(entry, leave, &near, &near_axis, &far, &far_axis);
    if (!(near <= far))
        return 0;
    tmin = ldexp(r->tmin, e);
    tmax = ldexp(r->tmax, e);
    if (near_axis >= 0 && near > tmin && near < tmax &&
        slab_t_lower(&L, near_axis,
                     entry_side(&L, near_axis) * L.h[near_axis]) > tmin) {
        t_s = near, axis = near_axis, side = entry_side(&L, near_axis);
    } else if (far_axis >= 0 && far > tmin && far < tmax &&
               exit_lower_bound(&L, live) > tmin) {
        t_s = far, axis = far_axis, side = -entry_side(&L, far_axis);
    } else
        return 0;
    /* Back to the direction's units: exact, but where t overflows or
    ** underflows, which may put it past tmin or tmax. */
    if (!(ldexp(t_s, -e) > r->tmin && ldexp(t_s, -e) < r->tmax))
        return 0;
    return box_fill(b, &f, &L, axis, side, t_s, ldexp(t_s, -e), hit);
}

/* ------------------------------------------------------- closest point */

/*
** The point of the box's surface nearest q (ray_closest_point), in the
** box's frame: q's local coordinates o_k = (q - c).e_k; the axis of the
** largest excess |o_k| - h_k (ties to the lower axis) is the face of
** the normal.  Outside (that excess > 0) the nearest point is o clamped
** to the box, componentwise (the box is the product of three
** intervals), which puts it on that face; inside or on the surface
** (every excess <= 0, the clamp changes nothing) it is o moved onto
** that face, the nearest one.  The local point l has l_axis = +-h
** exactly and the others within [-h_k, h_k], so p = c + sum_k l_k e_k
** lies on the box spanned by the frame within gamma(5) (|c_i| + sum_k
** |l_k e_k,i|), as box_fill's hit point; the o_k themselves are off by
** origin_error's gamma(4) |q - c| and the frame's delta, which moves p
** along the surface, not off it.
*/
int ray__box_closest(const ray_box_params *b, ray_vec3 q, ray_vec3 *p,
                     ray_vec3 *n)
{
    box_frame f;
    ray_vec3 lo, hi, rel, s, pt;
    double o[3], h[3], l[3], excess = -HUGE_VAL, side;
    int k, axis = 0;

    if (box_setup(b, &f, &lo, &hi) != BOX_VALID)
        return 0;
    rel = v3_sub(q, b->center);
    if (!v3_isfinite(rel))
        return 0;
    to_array(b->half_extents, h);
    for (k = 0; k < 3; k++) {
        o[k] = v3_dot(rel, f.e[k]);
        if (fabs(o[k]) - h[k] > excess) {
            excess = fabs(o[k]) - h[k];
            axis = k;
        }
    }
    side = o[axis] < 0 ? -1.0 : 1.0;
    for (k = 0; k < 3; k++)
        l[k] = fmin(fmax(o[k], -h[k]), h[k]);
    l[axis] = side * h[axis];
    s = v3_add(v3_add(v3_scale(f.e[0], l[0]), v3_scale(f.e[1], l[1])),
               v3_scale(f.e[2], l[2]));
    pt = v3_add(b->center, s);
    if (!v3_isfinite(pt))
        return 0;
    *p = pt;
    *n = v3_scale(f.e[axis], side);
    return 1;
}

/* The box's unit axes as ray_box computes them (frame_of), for the
** queries that read its corners: 1, or 0 for params ray_box refuses. */
int ray__box_frame(const ray_box_params *b, ray_vec3 e[3])
{
    box_frame f;

    if (frame_of(b, &f) != BOX_VALID)
        return 0;
    e[0] = f.e[0];
    e[1] = f.e[1];
    e[2] = f.e[2];
    return 1;
}

/* ------------------------------------------------------ the scene's check */

int ray__box_check(const ray_box_params *p, ray_vec3 *lo, ray_vec3 *hi,
                   char *why, size_t why_size)
{
    box_frame f;
    ray_vec3 l, h;
    box_fault fault = box_setup(p, &f, &l, &h);

    switch (fault) {
    case BOX_VALID:
        *lo = l;
        *hi = h;
        return 1;
    case BOX_NULL:
        snprintf(why, why_size, "box parameters are NULL");
        break;
    case BOX_CENTER:
        snprintf(why, why_size, "center " BOX_V3FMT " is not finite",
                 BOX_V3ARGS(p->center));
        break;
    case BOX_HALF_EXTENTS:
        snprintf(why, why_size, "half_extents " BOX_V3FMT " are not all "
                 "positive and finite", BOX_V3ARGS(p->half_extents));
        break;
    case BOX_AXIS_X:
        snprintf(why, why_size, "axis_x " BOX_V3FMT " is zero or not "
                 "finite", BOX_V3ARGS(p->axis_x));
        break;
    case BOX_AXIS_Y:
        snprintf(why, why_size, "axis_y " BOX_V3FMT " is zero or not "
                 "finite", BOX_V3ARGS(p->axis_y));
        break;
    case BOX_PARALLEL:
        snprintf(why, why_size, "axis_y " BOX_V3FMT " is parallel to "
                 "axis_x " BOX_V3FMT, BOX_V3ARGS(p->axis_y),
                 BOX_V3ARGS(p->axis_x));
        break;
    case BOX_HALF_TOO_LARGE:
        snprintf(why, why_size, "half_extents " BOX_V3FMT " exceed 2^1021 "
                 "(about 2.2e307), past which a ray's t across the box "
                 "could overflow", BOX_V3ARGS(p->half_extents));
        break;
    case BOX_TOO_LARGE:
        snprintf(why, why_size, "the box (center " BOX_V3FMT ", "
                 "half_extents " BOX_V3FMT ") reaches beyond the largest "
                 "double", BOX_V3ARGS(p->center),
                 BOX_V3ARGS(p->half_extents));
        break;
    }
    return 0;
}
