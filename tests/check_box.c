/* SPDX-License-Identifier: MIT */
/*
** check_box.c -- ray_box and ray_scene_add_box: exact answers for an
** axis-aligned box at 0 and 1e5, edges, corners and rays along faces
** (the slab method's d_k == 0 case), texture coordinates, rotated boxes
** against a long double reference at 0, 1e5 and 1e6 (also grazing and
** from inside), tmin/tmax, the direction's length, the frame, bad input,
** and the scene (the same hit through the BVH, the counter, the messages).
*/
#include <stdio.h>
#include <stdlib.h>

#include "tests.h"

static ray_box_params box_of(ray_vec3 c, ray_vec3 h, ray_vec3 ax,
                             ray_vec3 ay)
{
    ray_box_params b;
    b.center = c;
    b.half_extents = h;
    b.axis_x = ax;
    b.axis_y = ay;
    return b;
}

/* Axis-aligned, half-extents 1, 2, 3 (exact), about (o, o, o). */
static ray_box_params aligned(double o)
{
    return box_of(vec(o, o, o), vec(1, 2, 3), vec(1, 0, 0), vec(0, 1, 0));
}

/*
** Axis-aligned: all of the frame is exact (the normalised axes are 0 and
** 1, every dot product has one non-zero term), so the local coordinates
** are exact differences of doubles and t, p, n, (u, v) are exact for
** these representable inputs, also at 1e5 (the differences of coordinates
** near 1e5 are exact).  One ray per face, from outside along the face's
** inward normal, aimed at the local point (0.5, -1, 1.5) moved onto the
** face: u, v from ray.h's rule.
*/
START_TEST(axis_aligned_faces_should_be_exact)
{
    static const struct {
        double n[3];
        double u, v;
    } face[6] = {
        /* +x: u along +y (q_y = -1 of 2: 0.25), v along z (1.5 of 3) */
        {{1, 0, 0}, 0.25, 0.75},
        /* -x: u along -y: 0.75 */
        {{-1, 0, 0}, 0.75, 0.75},
        /* +y: u along +z (1.5 of 3: 0.75), v along x (0.5 of 1: 0.75) */
        {{0, 1, 0}, 0.75, 0.75},
        {{0, -1, 0}, 0.25, 0.75},
        /* +z: u along +x (0.75), v along y (0.25) */
        {{0, 0, 1}, 0.75, 0.25},
        {{0, 0, -1}, 0.25, 0.25},
    };
    double o = test_offset(_i);
    ray_box_params b = aligned(o);
    int f;

    for (f = 0; f < 6; f++) {
        ray_vec3 n = vec(face[f].n[0], face[f].n[1], face[f].n[2]);
        ray_vec3 q = vec(0.5, -1, 1.5), at, org;
        ray_hit h;
        int k = n.x != 0 ? 0 : (n.y != 0 ? 1 : 2);
        double hk = k == 0 ? 1 : (k == 1 ? 2 : 3), sign = n.x + n.y + n.z;

        if (k == 0)
            q.x = sign * hk;
        else if (k == 1)
            q.y = sign * hk;
        else
            q.z = sign * hk;
        at = vadd(b.center, q);
        org = vadd(at, vscale(n, 8));
        ck_assert_int_eq(ray_box(&(ray_ray){org, vscale(n, -2), 0, HUGE_VAL},
                                 &b, &h),
                         1);
        ck_assert_double_eq(h.t, 4);
        ck_assert_vec_eq(h.p, at);
        ck_assert_vec_eq(h.n, n);
        ck_assert_double_eq(h.u, face[f].u);
        ck_assert_double_eq(h.v, face[f].v);
        ck_assert_uint_eq(h.geom_id, RAY_INVALID_ID);
        ck_assert_uint_eq(h.prim_id, RAY_INVALID_ID);
        /* p_err: gamma(5) (|c| + |q|) per component, a few ulps. */
        ck_assert(h.p_err.x > 0 && h.p_err.x < 8 * U64 * (fabs(o) + 4));
        ck_assert(hit_is_finite(&h));
    }
}
END_TEST

/*
** Edges and corners are part of the closed box: a ray that only touches
** an edge (near = far) or a corner hits it; so does a ray lying in a face
** plane (d_k == 0 and o_k == h_k: (h - o)/d would be 0/0 = NaN), at the
** edge where it reaches the box, and one lying in the plane but outside
** the face misses, as does one parallel to a slab outside it.  Exact for
** the axis-aligned box at 0 and 1e5.
*/
START_TEST(edges_corners_and_face_planes_should_hit)
{
    double o = test_offset(_i);
    ray_box_params b = aligned(o);
    ray_vec3 c = b.center;
    ray_hit h;

    /* Touches only the edge x = 1, y = 2 at z = 0.5: t = 1. */
    ck_assert_int_eq(ray_box(&(ray_ray){vadd(c, vec(2, 1, 0.5)),
                                        vec(-1, 1, 0), 0, HUGE_VAL},
                             &b, &h),
                     1);
    ck_assert_double_eq(h.t, 1);
    ck_assert_vec_eq(h.p, vadd(c, vec(1, 2, 0.5)));
    ck_assert_vec_eq(h.n, vec(1, 0, 0));   /* tie: the lower axis */
    /* Just past the edge: a miss. */
    hit_poison(&h);
    ck_assert_int_eq(ray_box(&(ray_ray){vadd(c, vec(2, 1.25, 0.5)),
                                        vec(-1, 1, 0), 0, HUGE_VAL},
                             &b, &h),
                     0);
    ck_assert(hit_is_poisoned(&h));
    /* Through the corner (1, 2, 3) only, from (2, 3, 4). */
    ck_assert_int_eq(ray_box(&(ray_ray){vadd(c, vec(2, 1, 4)),
                                        vec(-1, 1, -1), 0, HUGE_VAL},
                             &b, &h),
                     1);
    ck_assert_double_eq(h.t, 1);
    ck_assert_vec_eq(h.p, vadd(c, vec(1, 2, 3)));
    /* In the plane y = 2 of the top face, along x: enters at the edge
    ** x = -1 (u = 1 on the -x face: q_y = +2, reversed), t = 4. */
    ck_assert_int_eq(ray_box(&(ray_ray){vadd(c, vec(-5, 2, 0)),
                                        vec(1, 0, 0), 0, HUGE_VAL},
                             &b, &h),
                     1);
    ck_assert_double_eq(h.t, 4);
    ck_assert_vec_eq(h.p, vadd(c, vec(-1, 2, 0)));
    ck_assert_vec_eq(h.n, vec(-1, 0, 0));
    ck_assert_double_eq(h.u, 0);
    ck_assert_double_eq(h.v, 0.5);
    /* Starting on the top face, along it: leaves at the edge x = 1. */
    ck_assert_int_eq(ray_box(&(ray_ray){vadd(c, vec(0, 2, 0)),
                                        vec(1, 0, 0), 0, HUGE_VAL},
                             &b, &h),
                     1);
    ck_assert_double_eq(h.t, 1);
    ck_assert_vec_eq(h.n, vec(1, 0, 0));
    /* In the plane y = 2 but beside the face (z = 4 > 3): a miss; parallel
    ** to the y slab above it: a miss; -0 as a direction component. */
    ck_assert_int_eq(ray_box(&(ray_ray){vadd(c, vec(-5, 2, 4)),
                                        vec(1, 0, 0), 0, HUGE_VAL},
                             &b, &h),
                     0);
    ck_assert_int_eq(ray_box(&(ray_ray){vadd(c, vec(-5, 2.5, 0)),
                                        vec(1, -0.0, 0), 0, HUGE_VAL},
                             &b, &h),
                     0);
    /* Along the edge line x = 1, y = 2 itself (two zero components): hits
    ** where it reaches z = -3. */
    ck_assert_int_eq(ray_box(&(ray_ray){vadd(c, vec(1, 2, -7)),
                                        vec(0, 0, 1), 0, HUGE_VAL},
                             &b, &h),
                     1);
    ck_assert_double_eq(h.t, 4);
    ck_assert_vec_eq(h.n, vec(0, 0, -1));
    ck_assert(hit_is_finite(&h));
}
END_TEST

/* ----------------------------------------------- the long double reference */

typedef struct ref_hit {
    long double t, p[3], n[3], u, v;
    int axis;
} ref_hit;

static long double ldot(const long double a[3], const long double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void lnormalize(long double a[3])
{
    long double l = sqrtl(ldot(a, a));
    a[0] /= l, a[1] /= l, a[2] /= l;
}

static void lfrom(ray_vec3 v, long double a[3])
{
    a[0] = (long double)v.x, a[1] = (long double)v.y, a[2] = (long double)v.z;
}

/* The exact frame (to long double's 2^-64) of b's axes. */
static void ref_frame(const ray_box_params *b, long double e[3][3])
{
    long double c;
    int i;

    lfrom(b->axis_x, e[0]);
    lfrom(b->axis_y, e[1]);
    lnormalize(e[0]);
    lnormalize(e[1]);
    c = ldot(e[0], e[1]);
    for (i = 0; i < 3; i++)
        e[1][i] -= c * e[0][i];
    lnormalize(e[1]);
    e[2][0] = e[0][1] * e[1][2] - e[0][2] * e[1][1];
    e[2][1] = e[0][2] * e[1][0] - e[0][0] * e[1][2];
    e[2][2] = e[0][0] * e[1][1] - e[0][1] * e[1][0];
    lnormalize(e[2]);
}

/* The slab method in long double; 1 on a hit in (tmin, tmax). */
static int ref_box(const ray_ray *r, const ray_box_params *b, ref_hit *out)
{
    long double e[3][3], f[3], d[3], c[3], h[3], o[3], dl[3], q[3];
    long double near = -HUGE_VALL, far = HUGE_VALL, t, side;
    int k, na = -1, fa = -1, axis, i;

    ref_frame(b, e);
    lfrom(r->org, f);
    lfrom(b->center, c);
    lfrom(b->half_extents, h);
    lfrom(r->dir, d);
    for (i = 0; i < 3; i++)
        f[i] -= c[i];           /* exact: doubles' difference fits */
    for (k = 0; k < 3; k++) {
        long double lo, hi;
        o[k] = ldot(f, e[k]);
        dl[k] = ldot(d, e[k]);
        if (dl[k] == 0) {
            if (fabsl(o[k]) > h[k])
                return 0;
            continue;
        }
        lo = (-h[k] - o[k]) / dl[k];
        hi = (h[k] - o[k]) / dl[k];
        if (lo > hi) {
            long double s = lo;
            lo = hi, hi = s;
        }
        if (lo > near)
            near = lo, na = k;
        if (hi < far)
            far = hi, fa = k;
    }
    if (!(near <= far))
        return 0;
    if (near > (long double)r->tmin && near < (long double)r->tmax)
        t = near, axis = na, side = dl[na] > 0 ? -1 : 1;
    else if (far > (long double)r->tmin && far < (long double)r->tmax)
        t = far, axis = fa, side = dl[fa] > 0 ? 1 : -1;
    else
        return 0;
    for (k = 0; k < 3; k++)
        q[k] = k == axis ? side * h[k] : o[k] + t * dl[k];
    for (i = 0; i < 3; i++) {
        out->p[i] = c[i] + q[0] * e[0][i] + q[1] * e[1][i] + q[2] * e[2][i];
        out->n[i] = side * e[axis][i];
    }
    out->t = t;
    out->axis = axis;
    out->u = 0.5L * (side * q[(axis + 1) % 3] / h[(axis + 1) % 3]) + 0.5L;
    out->v = 0.5L * (q[(axis + 2) % 3] / h[(axis + 2) % 3]) + 0.5L;
    return 1;
}

/* A box of random size and orientation about (o, o, o) + a little, its
** axes of random lengths and not orthogonal (the library's frame). */
static ray_box_params random_box(rng *g, double o)
{
    ray_vec3 ax = rng_dir(g), ay = rng_dir(g);
    ray_box_params b;

    while (fabs(vdot(ax, ay)) > 0.9)
        ay = rng_dir(g);
    b = box_of(vadd(vec(o, o, o), rng_point(g, -1, 1)),
               vec(rng_range(g, 0.1, 3), rng_range(g, 0.1, 3),
                   rng_range(g, 0.1, 3)),
               vscale(ax, rng_range(g, 0.5, 4)),
               vscale(ay, rng_range(g, 0.5, 4)));
    return b;
}

/* The largest error seen, in units of its tolerance, over the reference
** test (printed by the test on failure only). */
typedef struct worst {
    double t, p, n, uv, off;
} worst;

/*
** One ray against the reference.  Tolerances, with u = 2^-53, F = |org -
** c| + t |dir| (the local coordinates' magnitude along the ray) and
** cos = |dir . n| / |dir| (the incidence):
**   t:   64 u F / |dir . n|.  t = (+-h - o_k) / d_k; o_k and d_k carry
**        the dot products' few roundings plus the frame's departure from
**        the exact one (a few ulps per component: the library's bound is
**        gamma(16) and the measured one 3 ulps, frame test below), each
**        relative to F, and dividing by d_k = dir . n scales that by
**        1 / |dir . n|.  64 leaves 4x room over the 16 of the bound;
**   p:   64 u (|c| + F / cos): p = c + sum q_k e_k rounds within a few
**        ulps of |c| + |q|, and t's error moves p along the face by
**        |dt| |dir| = 64 u F / cos;
**   n:   32 u: the frame's error, per component of a unit vector;
**   u, v: p's tolerance over the face's size 2 h;
**   off the face (the distance of p from the reference face plane):
**        2 (n . p_err) + 64 u sum h: what ray_spawn offsets by, plus the
**        frame's error times the box's size (p_err bounds the distance
**        from the box the computed frame spans, ray.h).
** Grazing rays (cos down to 1e-6 below) have correspondingly large t and
** p tolerances: the conditioning of the problem, not a slack.
*/
static void compare(const ray_ray *r, const ray_box_params *b,
                    const ray_hit *h, const ref_hit *ref, worst *w)
{
    double dl = vlen(r->dir), t = h->t;
    double F = vdist(r->org, b->center) + t * dl;
    double dn = fabs((double)((long double)r->dir.x * ref->n[0] +
                              (long double)r->dir.y * ref->n[1] +
                              (long double)r->dir.z * ref->n[2]));
    double cmax = fmax(fabs(b->center.x),
                       fmax(fabs(b->center.y), fabs(b->center.z)));
    double hsum = b->half_extents.x + b->half_extents.y + b->half_extents.z;
    double tol_t = 64 * U64 * F / dn;
    double tol_p = 64 * U64 * (cmax + F * dl / dn);
    double hmin = fmin(b->half_extents.x,
                       fmin(b->half_extents.y, b->half_extents.z));
    double tol_uv = tol_p / (2 * hmin);
    double off = fabs((double)(((long double)h->p.x - ref->p[0]) * ref->n[0] +
                               ((long double)h->p.y - ref->p[1]) * ref->n[1] +
                               ((long double)h->p.z - ref->p[2]) * ref->n[2]));
    double tol_off = 2 * vdot(vec(fabs(h->n.x), fabs(h->n.y), fabs(h->n.z)),
                              h->p_err) +
                     64 * U64 * hsum;
    double ep = fmax(fabs((double)((long double)h->p.x - ref->p[0])),
                     fmax(fabs((double)((long double)h->p.y - ref->p[1])),
                          fabs((double)((long double)h->p.z - ref->p[2]))));
    double en = fmax(fabs((double)((long double)h->n.x - ref->n[0])),
                     fmax(fabs((double)((long double)h->n.y - ref->n[1])),
                          fabs((double)((long double)h->n.z - ref->n[2]))));
    double euv = fmax(fabs((double)((long double)h->u - ref->u)),
                      fabs((double)((long double)h->v - ref->v)));

    ck_assert(hit_is_finite(h));
    ck_assert(h->u >= 0 && h->u <= 1 && h->v >= 0 && h->v <= 1);
    ck_assert_msg(fabs((double)((long double)t - ref->t)) <= tol_t,
                  "t %.17g ref %.17Lg tol %g", t, ref->t, tol_t);
    ck_assert_msg(ep <= tol_p, "p off by %g, tol %g", ep, tol_p);
    ck_assert_msg(en <= 32 * U64, "n off by %g", en);
    ck_assert_msg(euv <= tol_uv, "uv off by %g, tol %g", euv, tol_uv);
    ck_assert_msg(off <= tol_off, "p %g off the face, tol %g", off, tol_off);
    w->t = fmax(w->t, fabs((double)((long double)t - ref->t)) / tol_t);
    w->p = fmax(w->p, ep / tol_p);
    w->n = fmax(w->n, en / (32 * U64));
    w->uv = fmax(w->uv, euv / tol_uv);
    w->off = fmax(w->off, off / tol_off);
}

/* Rays from outside toward a random point of the box, and from a random
** point inside it; the same hit or miss as the reference except where
** the reference's t lies within rounding of tmin (none here: tmin 0 and
** origins at least 1e-3 off the surface). */
static void against_reference(double o, rng *g, int grazing, worst *w)
{
    int i, hits = 0;

    for (i = 0; i < 2000; i++) {
        ray_box_params b = random_box(g, o);
        long double e[3][3];
        ray_vec3 target, org, dir;
        ray_hit h;
        ref_hit ref;
        int got, want, k;

        memset(&ref, 0, sizeof ref);  /* -O1 cannot see ref_box fill it */
        ref_frame(&b, e);
        /* A point in the box (local coordinates in 0.98 of the extents). */
        target = b.center;
        for (k = 0; k < 3; k++) {
            double hk = k == 0 ? b.half_extents.x
                               : (k == 1 ? b.half_extents.y
                                         : b.half_extents.z);
            double s = rng_range(g, -0.98, 0.98) * hk;
            target = vadd(target, vscale(vec((double)e[k][0], (double)e[k][1],
                                             (double)e[k][2]),
                                         s));
        }
        if (grazing) {
            /* Along a face's plane, tilted toward it by 1e-6 .. 1e-2. */
            ray_vec3 n = vec((double)e[i % 3][0], (double)e[i % 3][1],
                             (double)e[i % 3][2]);
            ray_vec3 t1 = vcross(n, rng_dir(g));
            double tilt = pow(10, rng_range(g, -6, -2));
            t1 = vscale(t1, 1 / vlen(t1));
            dir = vsub(t1, vscale(n, tilt));
            org = vsub(vadd(target, vscale(n, 0.999 *
                                           (i % 3 == 0 ? b.half_extents.x
                                            : i % 3 == 1 ? b.half_extents.y
                                                         : b.half_extents.z))),
                       vscale(dir, 20));
        } else if (i % 4 == 3) {
            org = target;         /* from inside */
            dir = rng_dir(g);
        } else {
            dir = rng_dir(g);
            org = vsub(target, vscale(dir, rng_range(g, 8, 30)));
        }
        dir = vscale(dir, rng_range(g, 0.25, 4));
        {
            ray_ray r = ray_from(org, dir);
            got = ray_box(&r, &b, &h);
            want = ref_box(&r, &b, &ref);
            ck_assert_int_eq(got, want);
            if (got) {
                hits++;
                compare(&r, &b, &h, &ref, w);
            }
        }
    }
    /* Enough hits that the test cannot pass by missing (about half of
    ** the grazing rays pass beside the face). */
    ck_assert_int_gt(hits, 800);
}

START_TEST(rotated_boxes_should_match_the_long_double_reference)
{
    static const double offsets[] = {0, 1e5, 1e6};
    worst w = {0, 0, 0, 0, 0};
    rng g = {15};
    int o, grazing;

    for (o = 0; o < 3; o++)
        for (grazing = 0; grazing < 2; grazing++)
            against_reference(offsets[o], &g, grazing, &w);
    /* Keep the figures honest: the measured worst case, in tolerances,
    ** is printed when BOX_TEST_FIGURES is set. */
    if (getenv("BOX_TEST_FIGURES") != NULL)
        fprintf(stderr, "box worst/tol: t %.3g p %.3g n %.3g uv %.3g "
                "off %.3g\n", w.t, w.p, w.n, w.uv, w.off);
}
END_TEST

/* ----------------------------------------------------------- the rest */

/*
** (u, v) run so that (dp/du, dp/dv, n) is right-handed on every face of a
** rotated box: three hits per face, at local offsets (0, 0), (s, 0),
** (0, s) along the face's next two axes, give du > 0 then dv > 0 along the
** face's own tangents -- checked through the world points: the triple
** product (p1 - p0) x (p2 - p0) . n has the sign of du dv' - dv du'.
*/
START_TEST(texture_coordinates_should_be_right_handed_on_every_face)
{
    rng g = {3};
    ray_box_params b = random_box(&g, 0);
    long double e[3][3];
    int axis, side;

    ref_frame(&b, e);
    for (axis = 0; axis < 3; axis++)
        for (side = -1; side <= 1; side += 2) {
            double hh[3] = {b.half_extents.x, b.half_extents.y,
                            b.half_extents.z};
            ray_vec3 ek[3], n, pts[3];
            double uu[3], vv[3], cross;
            int j;

            for (j = 0; j < 3; j++)
                ek[j] = vec((double)e[j][0], (double)e[j][1], (double)e[j][2]);
            n = vscale(ek[axis], side);
            for (j = 0; j < 3; j++) {
                ray_vec3 at = vadd(b.center, vscale(n, hh[axis]));
                ray_hit h;
                if (j == 1)
                    at = vadd(at, vscale(ek[(axis + 1) % 3],
                                         0.1 * hh[(axis + 1) % 3]));
                if (j == 2)
                    at = vadd(at, vscale(ek[(axis + 2) % 3],
                                         0.1 * hh[(axis + 2) % 3]));
                ck_assert_int_eq(ray_box(&(ray_ray){vadd(at, vscale(n, 5)),
                                                    vscale(n, -1), 0,
                                                    HUGE_VAL},
                                         &b, &h),
                                 1);
                ck_assert_vec_eq_tol(h.n, n, 32 * U64);
                pts[j] = h.p, uu[j] = h.u, vv[j] = h.v;
            }
            /* u moves along e_(k+1) (reversed on the negative face), v
            ** along e_(k+2); the centre of the face is (0.5, 0.5). */
            ck_assert_double_eq_tol(uu[0], 0.5, 1e-12);
            ck_assert_double_eq_tol(vv[0], 0.5, 1e-12);
            ck_assert_double_eq_tol(uu[1], 0.5 + side * 0.05, 1e-12);
            ck_assert_double_eq_tol(vv[2], 0.55, 1e-12);
            cross = vdot(vcross(vsub(pts[1], pts[0]), vsub(pts[2], pts[0])),
                         n) *
                    (uu[1] - uu[0]) * (vv[2] - vv[0]);
            ck_assert(cross > 0);
        }
}
END_TEST

/* From inside: the face left through, with the OUTWARD normal; tmin and
** tmax are open and t is compared after the conservative test. */
START_TEST(inside_and_interval_should_follow_the_contract)
{
    double o = test_offset(_i);
    ray_box_params b = aligned(o);
    ray_vec3 c = b.center;
    ray_hit h;

    ck_assert_int_eq(ray_box(&(ray_ray){c, vec(0, 0, -1), 0, HUGE_VAL}, &b,
                             &h),
                     1);
    ck_assert_double_eq(h.t, 3);
    ck_assert_vec_eq(h.n, vec(0, 0, -1));
    ck_assert_vec_eq(h.p, vadd(c, vec(0, 0, -3)));
    /* From outside with tmin past the entry (t = 4): the exit, t = 8. */
    ck_assert_int_eq(ray_box(&(ray_ray){vadd(c, vec(-5, 0, 0)),
                                        vec(1, 0, 0), 5, HUGE_VAL},
                             &b, &h),
                     1);
    ck_assert_double_eq(h.t, 6);
    ck_assert_vec_eq(h.n, vec(1, 0, 0));
    /* tmax exactly at the entry: open, a miss; just above: a hit. */
    ck_assert_int_eq(ray_box(&(ray_ray){vadd(c, vec(-5, 0, 0)),
                                        vec(1, 0, 0), 0, 4},
                             &b, &h),
                     0);
    ck_assert_int_eq(ray_box(&(ray_ray){vadd(c, vec(-5, 0, 0)),
                                        vec(1, 0, 0), 0,
                                        nextafter(4, 5)},
                             &b, &h),
                     1);
    /* tmin at the exit: nothing left. */
    ck_assert_int_eq(ray_box(&(ray_ray){vadd(c, vec(-5, 0, 0)),
                                        vec(1, 0, 0), 6, HUGE_VAL},
                             &b, &h),
                     0);
    /* Starting exactly on the -x face going in: the entry at t = 0 is not
    ** past tmin = 0 by more than its error; the exit at t = 2. */
    ck_assert_int_eq(ray_box(&(ray_ray){vadd(c, vec(-1, 0, 0)),
                                        vec(1, 0, 0), 0, HUGE_VAL},
                             &b, &h),
                     1);
    ck_assert_double_eq(h.t, 2);
    /* ... and going out: nothing. */
    ck_assert_int_eq(ray_box(&(ray_ray){vadd(c, vec(-1, 0, 0)),
                                        vec(-1, 0.3, 0.2), 0, HUGE_VAL},
                             &b, &h),
                     0);
}
END_TEST

/*
** The direction is scaled by a power of two: 2^+-600 times a direction
** give bit for bit the same hit, t scaled exactly; 1e+-200 times it (each
** component rounded, which turns the ray by up to 2^-53 sqrt 3) the same
** point within 1e-13 of the box's size and distance (a few ulps of
** 20 units, turned by that angle).
*/
START_TEST(direction_length_should_not_matter)
{
    rng g = {21};
    int i, hits = 0;

    for (i = 0; i < 200; i++) {
        ray_box_params b = random_box(&g, test_offset(_i));
        ray_vec3 d = rng_dir(&g);
        ray_vec3 org = vsub(b.center, vscale(d, 10));
        ray_hit h0, h1, h2;
        int k, hit;

        d = vadd(d, vscale(rng_dir(&g), 0.1));
        hit = ray_box(&(ray_ray){org, d, 0, HUGE_VAL}, &b, &h0);
        for (k = -1; k <= 1; k += 2) {
            double s2 = ldexp(1, 600 * k), s10 = k > 0 ? 1e200 : 1e-200;
            ck_assert_int_eq(ray_box(&(ray_ray){org, vscale(d, s2), 0,
                                                HUGE_VAL},
                                     &b, &h1),
                             hit);
            ck_assert_int_eq(ray_box(&(ray_ray){org, vscale(d, s10), 0,
                                                HUGE_VAL},
                                     &b, &h2),
                             hit);
            if (!hit)
                continue;
            ck_assert_double_eq(h1.t, h0.t / s2);
            ck_assert_vec_eq(h1.p, h0.p);
            ck_assert_vec_eq(h1.n, h0.n);
            ck_assert_double_eq(h1.u, h0.u);
            ck_assert_vec_eq_tol(h2.p, h0.p, 1e-13 * (20 + test_offset(_i)));
            ck_assert_double_eq_tol(h2.t * s10, h0.t, 1e-13 * h0.t);
        }
        hits += hit;
    }
    ck_assert_int_gt(hits, 100);
}
END_TEST

/*
** The frame is orthonormal to gamma(16) (box.c's FRAME_DELTA) for axes
** at any angle the check accepts, down to 1e-12 rad: measured through the
** normals of three faces (n = e_k), whose dot products the test rounds
** by at most gamma(3).  Axes exactly parallel are refused; 1e-12 apart
** are not.
*/
START_TEST(frame_should_be_orthonormal_for_any_accepted_axes)
{
    rng g = {8};
    double gamma16 = 16 * U64 / (1 - 16 * U64);
    int i;

    for (i = 0; i < 3000; i++) {
        ray_vec3 ax = rng_dir(&g), perp = vcross(ax, rng_dir(&g)), n[3];
        double angle = pow(10, rng_range(&g, -12, 0.2));
        ray_box_params b;
        int k, j;

        perp = vscale(perp, 1 / vlen(perp));
        b = box_of(rng_point(&g, -3, 3), vec(1, 1, 1),
                   vscale(ax, rng_range(&g, 1e-3, 1e3)),
                   vscale(vadd(vscale(ax, cos(angle)),
                               vscale(perp, sin(angle))),
                          rng_range(&g, 1e-3, 1e3)));
        for (k = 0; k < 3; k++) {
            ray_vec3 dir = vec(0, 0, 0);
            ray_hit h;
            /* From the centre along a rough e_k: leaves through face k
            ** (the other slabs are as wide, and the ray is within 45
            ** degrees of e_k... or through a neighbour, fine too). */
            if (k == 0)
                dir = b.axis_x;
            else if (k == 1)
                dir = perp;
            else
                dir = vcross(ax, perp);
            ck_assert_int_eq(ray_box(&(ray_ray){b.center, dir, 0, HUGE_VAL},
                                     &b, &h),
                             1);
            n[k] = h.n;
        }
        for (k = 0; k < 3; k++)
            for (j = k; j < 3; j++) {
                double dot = vdot(n[k], n[j]) - (j == k);
                ck_assert_msg(fabs(dot) <= gamma16 + 3 * U64 * 1.01,
                              "angle %g: e%d.e%d = %g", angle, k, j, dot);
            }
    }
}
END_TEST

START_TEST(bad_input_should_miss)
{
    ray_box_params good = aligned(0), b;
    ray_ray r = ray_from(vec(-5, 0.5, 0.5), vec(1, 0, 0));
    const double nan = (double)NAN, inf = HUGE_VAL;
    ray_hit h;
    int i;

    ck_assert_int_eq(ray_box(&r, &good, &h), 1);
    hit_poison(&h);
    ck_assert_int_eq(ray_box(NULL, &good, &h), 0);
    ck_assert_int_eq(ray_box(&r, NULL, &h), 0);
    ck_assert_int_eq(ray_box(&r, &good, NULL), 0);
    for (i = 0; i < 16; i++) {
        b = good;
        switch (i) {
        case 0: b.center.x = nan; break;
        case 1: b.center.y = inf; break;
        case 2: b.half_extents.x = 0; break;
        case 3: b.half_extents.y = -1; break;
        case 4: b.half_extents.z = nan; break;
        case 5: b.half_extents.z = inf; break;
        case 6: b.axis_x = vec(0, 0, 0); break;
        case 7: b.axis_x.y = nan; break;
        case 8: b.axis_y = vec(0, -0.0, 0); break;
        case 9: b.axis_y.z = inf; break;
        case 10: b.axis_y = vec(3, 0, 0); break;    /* parallel */
        case 11: b.axis_y = vec(-1e-300, 0, 0); break;
        case 12: b.half_extents.x = DBL_MAX; break;  /* beyond DBL_MAX */
        case 13: b.center.x = DBL_MAX; break;
        case 14: b.axis_x = vec(1, 1, 1), b.axis_y = vec(2, 2, 2); break;
        default: b.axis_x = vec(1e-310, 0, 0); break;   /* denormal: fine */
        }
        ck_assert_int_eq(ray_box(&r, &b, &h), i == 15);
        if (i != 15)
            ck_assert(hit_is_poisoned(&h));
        hit_poison(&h);
    }
    /* Bad rays. */
    r.dir = vec(0, 0, 0);
    ck_assert_int_eq(ray_box(&r, &good, &h), 0);
    r.dir = vec(nan, 1, 0);
    ck_assert_int_eq(ray_box(&r, &good, &h), 0);
    r = ray_from(vec(-5, 0.5, 0.5), vec(1, 0, 0));
    r.tmin = nan;
    ck_assert_int_eq(ray_box(&r, &good, &h), 0);
    r.tmin = 5, r.tmax = 1;
    ck_assert_int_eq(ray_box(&r, &good, &h), 0);
    r = ray_from(vec(-inf, 0.5, 0.5), vec(1, 0, 0));
    ck_assert_int_eq(ray_box(&r, &good, &h), 0);
    ck_assert(hit_is_poisoned(&h));
    /* Nearly parallel but not within rounding: a valid (tilted) box. */
    b = good;
    b.axis_y = vec(1, 1e-12, 0);
    ck_assert_int_eq(ray_box(&(ray_ray){vec(0, 10, 0), vec(0, -1, 0), 0,
                                        HUGE_VAL},
                             &b, &h),
                     1);
}
END_TEST

/* A box among spheres in a scene: the BVH gives the box's hits exactly
** as ray_box does (same t, p, n, u, v, p_err), with geom_id and prim_id
** 0; ray_occluded agrees; every test counts under RAY_PRIM_BOX. */
START_TEST(scene_should_give_the_bare_hit)
{
    ray_material m = plain();
    ray_scene *s;
    unsigned mat, id, i;
    rng g = {31};
    ray_box_params b = random_box(&g, test_offset(_i));
    int hits = 0;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, &mat), RAY_OK);
    for (i = 0; i < 8; i++)
        ck_assert_int_eq(ray_scene_add_sphere(s, vadd(b.center,
                                                      vec(10 + i, -10, 5)),
                                              0.5, mat, NULL),
                         RAY_OK);
    ck_assert_int_eq(ray_scene_add_box(s, &b, mat, &id), RAY_OK);
    ck_assert_uint_eq(id, 8);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    for (i = 0; i < 500; i++) {
        ray_vec3 d = rng_dir(&g);
        /* tmax 24: the ray ends 12 past the box, short of the spheres
        ** (15 or more from its centre). */
        ray_ray r = make_ray(vsub(vadd(b.center, rng_point(&g, -1, 1)),
                                  vscale(d, 12)),
                             d, 0, 24);
        ray_hit bare, sc;
        int hb = ray_box(&r, &b, &bare), hs = ray_intersect(s, &r, &sc, NULL);

        ck_assert_int_eq(hb, hs);
        ck_assert_int_eq(ray_occluded(s, &r, NULL), hb);
        if (!hb)
            continue;
        hits++;
        ck_assert_double_eq(sc.t, bare.t);
        ck_assert_vec_eq(sc.p, bare.p);
        ck_assert_vec_eq(sc.n, bare.n);
        ck_assert_vec_eq(sc.p_err, bare.p_err);
        ck_assert_double_eq(sc.u, bare.u);
        ck_assert_double_eq(sc.v, bare.v);
        ck_assert_uint_eq(sc.geom_id, id);
        ck_assert_uint_eq(sc.prim_id, 0);
    }
    ck_assert_int_gt(hits, 100);
    {
        ray_ctx *ctx;
        ray_stats st;
        ray_rgb out;
        ray_ray r = ray_from(vsub(b.center, vec(0, 0, 20)), vec(0, 0, 1));

        ck_assert_int_eq(ray_ctx_new(s, 1, &ctx), RAY_OK);
        ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1, &out),
                         RAY_OK);
        ray_ctx_stats(ctx, &st);
        ck_assert_uint_eq(st.tests_by_kind[RAY_PRIM_BOX], 1);
        ck_assert_uint_eq(st.tests, st.tests_by_kind[RAY_PRIM_BOX] +
                                        st.tests_by_kind[RAY_PRIM_SPHERE]);
        ray_ctx_free(ctx);
    }
    ray_scene_free(s);
}
END_TEST

/* The adder refuses what ray_box refuses, naming the field. */
START_TEST(scene_should_refuse_bad_boxes_by_name)
{
    static const char *const field[] = {"parameters are NULL", "center",
                                        "half_extents", "axis_x", "axis_y",
                                        "parallel", "largest double"};
    ray_material m = plain();
    ray_scene *s;
    int i;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, NULL), RAY_OK);
    for (i = 0; i < 7; i++) {
        ray_box_params b = aligned(0);
        unsigned id = 77;

        switch (i) {
        case 1: b.center.z = (double)NAN; break;
        case 2: b.half_extents.y = 0; break;
        case 3: b.axis_x = vec(0, 0, 0); break;
        case 4: b.axis_y = vec(0, HUGE_VAL, 0); break;
        case 5: b.axis_y = vec(-2, 0, 0); break;
        case 6:   /* DBL_MAX + 1e300 (2e292 is its ulp) overflows */
            b.center.z = DBL_MAX;
            b.half_extents.z = 1e300;
            break;
        default: break;
        }
        ck_assert_int_eq(ray_scene_add_box(s, i == 0 ? NULL : &b, 0, &id),
                         RAY_EINVAL);
        ck_assert_uint_eq(id, 77);
        ck_assert_msg(strstr(ray_scene_errmsg(s), field[i]) != NULL,
                      "message: %s", ray_scene_errmsg(s));
        ck_assert_msg(strstr(ray_scene_errmsg(s), "ray_scene_add_box") !=
                          NULL,
                      "message: %s", ray_scene_errmsg(s));
    }
    {
        ray_box_params b = aligned(0);
        ck_assert_int_eq(ray_scene_add_box(s, &b, 5, NULL), RAY_EINVAL);
        ck_assert_int_eq(ray_scene_add_box(NULL, &b, 0, NULL), RAY_EINVAL);
    }
    ray_scene_free(s);
}
END_TEST

/*
** Issue 38, defect 10: every box ray_scene_add_box accepts is one a ray
** starting inside hits (ray.h: "A ray starting inside hits the face it
** leaves through").  Half-extents of 1e308 were accepted, but the exit
** t in ray_box's scaled units (2e308) overflowed and the ray missed.
** For half-extents from 2^1019 to 1e308, axis-aligned and rotated, and
** directions along an axis and diagonal: accepted implies a hit from
** the centre by ray_box and through the scene by ray_intersect, with a
** finite t.  Half-extents up to 2^1021 (about 2.2e307, ray_box(3)) must
** be accepted; 1e308, whose t across the box may pass DBL_MAX, refused
** with RAY_EINVAL and a message naming half_extents.
*/
START_TEST(accepted_huge_boxes_should_be_hit_from_inside)
{
    static const double h[4] = {0x1p1019, 0x1p1020, 0x1p1021, 1e308};
    static const ray_vec3 dir[3] = {{0, 0, 1}, {1, 1, 1}, {-1, 0.5, 0.25}};
    int i, f, d, accepted = 0;

    for (i = 0; i < 4; i++)
        for (f = 0; f < 2; f++) {
            ray_box_params b = box_of(vec(0, 0, 0), vec(h[i], h[i], h[i]),
                                      f ? vec(1, 1, 0) : vec(1, 0, 0),
                                      f ? vec(-1, 1, 1) : vec(0, 1, 0));
            ray_scene *s;
            int rc;

            ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
            rc = ray_scene_add_box(s, &b, RAY_NO_MATERIAL, NULL);
            if (i <= 2)
                ck_assert_int_eq(rc, RAY_OK);
            if (rc == RAY_OK) {
                accepted++;
                ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
                for (d = 0; d < 3; d++) {
                    ray_ray r = make_ray(vec(0, 0, 0), dir[d], 0, HUGE_VAL);
                    ray_hit hb, hs;
                    ck_assert_msg(ray_box(&r, &b, &hb) == 1,
                                  "h %g frame %d dir %d", h[i], f, d);
                    ck_assert(isfinite(hb.t) && hb.t > 0);
                    ck_assert_int_eq(ray_intersect(s, &r, &hs, NULL), 1);
                    ck_assert(hs.t == hb.t);
                }
            } else {
                ck_assert_int_eq(rc, RAY_EINVAL);
                ck_assert_msg(strstr(ray_scene_errmsg(s), "half_extents") != NULL,
                              "message: %s", ray_scene_errmsg(s));
            }
            ray_scene_free(s);
        }
    ck_assert_int_eq(accepted, 6);
}
END_TEST

Suite *box_suite(void)
{
    Suite *s = suite_create("box");
    TCase *tc = tcase_create("box");

    tcase_set_timeout(tc, 120);
    tcase_add_loop_test(tc, axis_aligned_faces_should_be_exact, 0,
                        N_OFFSETS);
    tcase_add_loop_test(tc, edges_corners_and_face_planes_should_hit, 0,
                        N_OFFSETS);
    tcase_add_test(tc, rotated_boxes_should_match_the_long_double_reference);
    tcase_add_test(tc,
                   texture_coordinates_should_be_right_handed_on_every_face);
    tcase_add_loop_test(tc, inside_and_interval_should_follow_the_contract,
                        0, N_OFFSETS);
    tcase_add_loop_test(tc, direction_length_should_not_matter, 0,
                        N_OFFSETS);
    tcase_add_test(tc, frame_should_be_orthonormal_for_any_accepted_axes);
    tcase_add_test(tc, bad_input_should_miss);
    tcase_add_loop_test(tc, scene_should_give_the_bare_hit, 0, N_OFFSETS);
    tcase_add_test(tc, scene_should_refuse_bad_boxes_by_name);
    tcase_add_test(tc, accepted_huge_boxes_should_be_hit_from_inside);
    suite_add_tcase(s, tc);
    return s;
}
