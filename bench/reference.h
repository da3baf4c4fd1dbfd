/* SPDX-License-Identifier: MIT */
/*
** reference.h -- minimal references for the bare primitives, for the
** table "bare primitive vs reference" of bench/accuracy.c (issue 17):
** what ray_sphere, ray_plane, ray_triangle and ray_triangle_watertight
** would cost written the shortest way that keeps their accuracy.
** Header-only; not part of the library.
**
** Two references per primitive, on the bench's rays (bench/accuracy.c,
** sphere_work, plane_work, triangle_work):
**
**   ref_NAME_t    "t only": the same decision (hit or miss) and the same
**                 t, bit for bit -- the same cancellation-free formulas
**                 as the library (a different formula, Moeller-Trumbore
**                 for the triangle or b^2 - ac for the sphere, rounds
**                 differently and is less accurate), and nothing else;
**   ref_NAME_hit  "same record": that, plus every field of ray_hit the
**                 primitive fills (t, p, n, u, v, p_err, the ids), by
**                 the library's formulas, written out straight.
**
** What they leave out, and why it does not change an answer on the
** bench's rays (the table counts the rays where it does: "mismatches"):
**
**   - the checks of bad input (NULL, radius <= 0 or not finite, zero or
**     NaN direction, a zero normal, results that overflow): the bench's
**     inputs are finite, within 200 of the origin, with radii in [0.1,
**     5.1] and directions of length 1 to 20;
**   - ray_sphere's scaling of the direction by a power of two: exact, so
**     t comes out the same without it (every quantity below scales by a
**     power of two, and sqrt of x 4^-e is sqrt(x) 2^-e exactly) wherever
**     nothing overflows or underflows, which it cannot on those rays;
**   - the error-interval test against tmin (t minus its rounding-error
**     bound must still be > tmin: no self-intersection).  It rejects only
**     a root within its error bound of tmin = 0, a few ulps of the
**     geometry's size divided by |d|: a ray starting on the surface, or
**     within ~1e-13 of it.  The bench's rays start at random points 1 to
**     20 units from the point they aim at, which do not come that close
**     (the mismatch count is the check).
**
** Everything else is the library's arithmetic, operation for operation
** (the build has -ffp-contract=off, so no FMA is fused in either).  The
** functions are kept out of line (REF_NOINLINE) so that they pay a call
** per test, as the library's functions called from the bench do.
*/
#ifndef BENCH_REFERENCE_H
#define BENCH_REFERENCE_H

#include "core/vec.h"

#if defined(__GNUC__)
#define REF_NOINLINE __attribute__((noinline))
#else
#define REF_NOINLINE
#endif

/* a / |a| as v3_normalize rounds it: divided by the largest |component|
** first, then times 1 / length. */
static inline ray_vec3 ref_normalize(ray_vec3 a)
{
    double ax = fabs(a.x), ay = fabs(a.y), az = fabs(a.z);
    double m = ax > ay ? ax : ay, len;

    m = m > az ? m : az;
    a = v3(a.x / m, a.y / m, a.z / m);
    len = sqrt(a.x * a.x + a.y * a.y + a.z * a.z);
    return v3_scale(a, 1.0 / len);
}

static inline void ref_ids(ray_hit *h)
{
    h->geom_id = RAY_INVALID_ID;
    h->prim_id = RAY_INVALID_ID;
    h->inst_id = RAY_INVALID_ID;
}

/* ---------------------------------------------------------------- sphere */

/*
** f = e - c, a = d.d, b' = -f.d, disc = (R - |l|)(R + |l|) with l = f +
** (b'/a) d the centre's offset from the line, c = (|f| - R)(|f| + R),
** q = b' + sign(b') sqrt(a disc), roots c/q and q/a (sphere.c).
*/
static REF_NOINLINE int ref_sphere_t(const ray_ray *r, ray_vec3 c, double R,
                                     double *t_out)
{
    ray_vec3 f = v3_sub(r->org, c), d = r->dir;
    double a = v3_dot(d, d), b = -v3_dot(f, d);
    double l = v3_length(v3_madd(f, b / a, d));
    double disc = (R - l) * (R + l), fl, cc, q, t0, t1;

    if (!(disc >= 0))
        return 0;
    fl = v3_length(f);
    cc = (fl - R) * (fl + R);
    q = b + copysign(sqrt(a * disc), b);
    t0 = cc / q;
    t1 = q / a;
    if (t0 > t1) {
        double s = t0;
        t0 = t1;
        t1 = s;
    }
    if (t0 > r->tmin && t0 < r->tmax)
        *t_out = t0;
    else if (t1 > r->tmin && t1 < r->tmax)
        *t_out = t1;
    else
        return 0;
    return 1;
}

/* The record: the point projected onto the sphere, n = (p - c)/|p - c|,
** p_err gamma(7) (|c| + R |n|), (u, v) the longitude and latitude. */
static REF_NOINLINE int ref_sphere_hit(const ray_ray *r, ray_vec3 c,
                                       double R, ray_hit *h)
{
    double t, ny;
    ray_vec3 n;

    if (!ref_sphere_t(r, c, R, &t))
        return 0;
    n = ref_normalize(v3_sub(v3_madd(r->org, t, r->dir), c));
    ny = n.y < -1.0 ? -1.0 : (n.y > 1.0 ? 1.0 : n.y);
    h->t = t;
    h->p = v3_madd(c, R, n);
    h->n = n;
    h->u = atan2(n.x, n.z) / (2.0 * RAY__PI) + 0.5;
    h->v = acos(-ny) / RAY__PI;
    h->p_err = v3_scale(v3_add(v3_abs(c), v3_scale(v3_abs(n), R)),
                        ray__gamma(7));
    ref_ids(h);
    return 1;
}

/* ----------------------------------------------------------------- plane */

/* t = (point - e).n / (d.n), with the normal as given (plane.c). */
static REF_NOINLINE int ref_plane_t(const ray_ray *r, ray_vec3 point,
                                    ray_vec3 normal, double *t_out)
{
    double den = v3_dot(r->dir, normal), t;

    if (den == 0)
        return 0;
    t = v3_dot(v3_sub(point, r->org), normal) / den;
    if (!(t > r->tmin && t < r->tmax))
        return 0;
    *t_out = t;
    return 1;
}

/* The record: e + t d projected back onto the plane, p_err gamma(8) of
** its largest coordinate, (u, v) in the tangent frame, in halves (as
** ray__plane_fill, whose halving keeps huge coordinates finite). */
static REF_NOINLINE int ref_plane_hit(const ray_ray *r, ray_vec3 point,
                                      ray_vec3 normal, ray_hit *h)
{
    double t, bound;
    ray_vec3 n, p, mag, t1, t2, half;

    if (!ref_plane_t(r, point, normal, &t))
        return 0;
    n = ref_normalize(normal);
    p = v3_madd(r->org, t, r->dir);
    p = v3_madd(p, -v3_dot(v3_sub(p, point), n), n);
    mag = v3_add(v3_abs(p), v3_abs(point));
    bound = ray__gamma(8) * fmax(mag.x, fmax(mag.y, mag.z));
    ray__tangent_frame(n, &t1, &t2);
    half = v3_sub(v3_scale(p, 0.5), v3_scale(point, 0.5));
    h->t = t;
    h->p = p;
    h->n = n;
    h->u = 2 * v3_dot(half, t1);
    h->v = 2 * v3_dot(half, t2);
    h->p_err = v3(bound, bound, bound);
    ref_ids(h);
    return 1;
}

/* -------------------------------------------------------------- triangles */

/* One component x1 y2 - y1 x2 of the normal, compensated where the
** products cancel by more than half (triangle.c, normal_component). */
static inline double ref_minor(double x1, double y2, double y1, double x2)
{
    double n = x1 * y2 - y1 * x2;

    if (fabs(x1 * y2) + fabs(y1 * x2) <= 2 * fabs(n))
        return n;
    return ray__diff_of_products(x1, y2, y1, x2);
}

/* Cramer (triangle.c): M = N.d, t = N.(A - e) / M with N = (A-B) x (A-C)
** from ref_minor, beta and gamma from the book's minors. */
static inline int ref_cramer(const ray_ray *r, ray_vec3 A, ray_vec3 B,
                             ray_vec3 C, double *t_out, double *beta_out,
                             double *gamma_out)
{
    double a = A.x - B.x, b = A.y - B.y, c = A.z - B.z;
    double d = A.x - C.x, e = A.y - C.y, f = A.z - C.z;
    double g = r->dir.x, h = r->dir.y, i = r->dir.z;
    double j = A.x - r->org.x, k = A.y - r->org.y, l = A.z - r->org.z;
    double nx = ref_minor(b, f, c, e), ny = ref_minor(c, d, a, f),
           nz = ref_minor(a, e, b, d);
    double m = nx * g + ny * h + nz * i, t, beta, gamma;

    if (m == 0)
        return 0;
    t = (nx * j + ny * k + nz * l) / m;
    if (!(t > r->tmin && t < r->tmax))
        return 0;
    gamma = (i * (a * k - j * b) + h * (j * c - a * l) +
             g * (b * l - k * c)) / m;
    if (!(gamma >= 0 && gamma <= 1))
        return 0;
    beta = (j * (e * i - h * f) + k * (g * f - d * i) +
            l * (d * h - e * g)) / m;
    if (!(beta >= 0 && beta <= 1 - gamma))
        return 0;
    *t_out = t;
    *beta_out = beta;
    *gamma_out = gamma;
    return 1;
}

/* The record of a triangle hit (triangle.c, ray__triangle_fill): the
** point interpolated from the vertices, n the unit (B-A) x (C-A). */
static inline void ref_triangle_fill(ray_vec3 A, ray_vec3 B, ray_vec3 C,
                                     double t, double beta, double gamma,
                                     ray_hit *h)
{
    double alpha = 1.0 - beta - gamma;
    ray_vec3 pa = v3_scale(A, alpha), pb = v3_scale(B, beta),
             pc = v3_scale(C, gamma);

    h->t = t;
    h->p = v3_add(v3_add(pa, pb), pc);
    h->n = ref_normalize(v3_cross(v3_sub(B, A), v3_sub(C, A)));
    h->u = beta;
    h->v = gamma;
    h->p_err = v3_add(v3_scale(v3_add(v3_add(v3_abs(pa), v3_abs(pb)),
                                      v3_abs(pc)),
                               ray__gamma(7)),
                      v3(4 * RAY__TINY, 4 * RAY__TINY, 4 * RAY__TINY));
    ref_ids(h);
}

static REF_NOINLINE int ref_triangle_t(const ray_ray *r, ray_vec3 A,
                                       ray_vec3 B, ray_vec3 C, double *t)
{
    double beta, gamma;

    return ref_cramer(r, A, B, C, t, &beta, &gamma);
}

static REF_NOINLINE int ref_triangle_hit(const ray_ray *r, ray_vec3 A,
                                         ray_vec3 B, ray_vec3 C, ray_hit *h)
{
    double t, beta, gamma;

    if (!ref_cramer(r, A, B, C, &t, &beta, &gamma))
        return 0;
    ref_triangle_fill(A, B, C, t, beta, gamma, h);
    return 1;
}

/*
** Watertight (watertight.h; Woop, Benthin, Wald, JCGT 2013): the axes
** permuted so dir's largest component is z (x, y swapped for a negative
** one), vertices translated to the origin and sheared, edge functions
** U, V, W; any exactly 0: all three again in long double; the sign test;
** compensated edge functions for a candidate; t = sum E_i z_i / det.
*/
static inline double ref_edge(double qx, double py, double qy, double px)
{
    double e = qx * py - qy * px;

    if (fabs(qx * py) + fabs(qy * px) <= 2 * fabs(e))
        return e;
    return ray__diff_of_products(qx, py, qy, px);
}

static inline double ref_edge_ld(double ax, double ay, double bx, double by)
{
    return (double)((long double)ax * (long double)by -
                    (long double)ay * (long double)bx);
}

static inline int ref_watertight(const ray_ray *r, ray_vec3 A, ray_vec3 B,
                                 ray_vec3 C, double *t_out,
                                 double *beta_out, double *gamma_out)
{
    const double o[3] = {r->org.x, r->org.y, r->org.z};
    const double d[3] = {r->dir.x, r->dir.y, r->dir.z};
    const double *v[3];
    double ad0 = fabs(d[0]), ad1 = fabs(d[1]), ad2 = fabs(d[2]);
    int kz = ad0 > ad1 && ad0 > ad2 ? 0 : (ad1 > ad2 ? 1 : 2);
    int kx = kz == 2 ? 0 : kz + 1, ky = kx == 2 ? 0 : kx + 1, q;
    double sx, sy, sz, x[3], y[3], z[3], u, vv, w, det, t, beta, gamma;

    if (d[kz] < 0) {
        int s = kx;
        kx = ky;
        ky = s;
    }
    sx = d[kx] / d[kz];
    sy = d[ky] / d[kz];
    sz = 1.0 / d[kz];
    v[0] = &A.x;
    v[1] = &B.x;
    v[2] = &C.x;
    for (q = 0; q < 3; q++) {
        z[q] = v[q][kz] - o[kz];
        x[q] = (v[q][kx] - o[kx]) - sx * z[q];
        y[q] = (v[q][ky] - o[ky]) - sy * z[q];
    }
    u = x[2] * y[1] - y[2] * x[1];
    vv = x[0] * y[2] - y[0] * x[2];
    w = x[1] * y[0] - y[1] * x[0];
    if (u == 0 || vv == 0 || w == 0) {
        u = ref_edge_ld(x[2], y[2], x[1], y[1]);
        vv = ref_edge_ld(x[0], y[0], x[2], y[2]);
        w = ref_edge_ld(x[1], y[1], x[0], y[0]);
        if ((u < 0 || vv < 0 || w < 0) && (u > 0 || vv > 0 || w > 0))
            return 0;
    } else {
        if ((u < 0 || vv < 0 || w < 0) && (u > 0 || vv > 0 || w > 0))
            return 0;
        u = ref_edge(x[2], y[1], y[2], x[1]);
        vv = ref_edge(x[0], y[2], y[0], x[2]);
        w = ref_edge(x[1], y[0], y[1], x[0]);
    }
    det = u + vv + w;
    if (det == 0)
        return 0;
    t = (u * (sz * z[0]) + vv * (sz * z[1]) + w * (sz * z[2])) / det;
    if (!(t > r->tmin && t < r->tmax))
        return 0;
    beta = vv / det;
    gamma = w / det;
    if (beta < 0)
        beta = 0;
    if (gamma < 0)
        gamma = 0;
    if (beta + gamma > 1) {
        double sum = beta + gamma;
        beta /= sum;
        gamma /= sum;
    }
    *t_out = t;
    *beta_out = beta;
    *gamma_out = gamma;
    return 1;
}

static REF_NOINLINE int ref_watertight_t(const ray_ray *r, ray_vec3 A,
                                         ray_vec3 B, ray_vec3 C, double *t)
{
    double beta, gamma;

    return ref_watertight(r, A, B, C, t, &beta, &gamma);
}

static REF_NOINLINE int ref_watertight_hit(const ray_ray *r, ray_vec3 A,
                                           ray_vec3 B, ray_vec3 C,
                                           ray_hit *h)
{
    double t, beta, gamma;

    if (!ref_watertight(r, A, B, C, &t, &beta, &gamma))
        return 0;
    ref_triangle_fill(A, B, C, t, beta, gamma, h);
    return 1;
}

#endif
