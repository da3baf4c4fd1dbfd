/* SPDX-License-Identifier: MIT */
/*
** triangle.c -- ray / triangle by Cramer's rule (Shirley and Marschner,
** "Fundamentals of Computer Graphics", 3rd ed., section 4.4.2).
*/
#include "prim/prim.h"
#include "prim/watertight.h"

/*
** Fill *hit from the barycentrics.  The point is interpolated from the
** vertices rather than taken as org + t*dir, so its rounding error lies
** along the surface and is bounded by gamma(7) * sum |b_i * v_i| (pbrt-v4
** Triangle::InteractionFromIntersection, "pError").  The normal is the
** normalised (b-a) x (c-a); if it has no length, the triangle is
** degenerate even though the determinant rounded to non-zero: a miss.
*/
int ray__triangle_fill(ray_vec3 va, ray_vec3 vb, ray_vec3 vc, double t,
                       double beta, double gamma, ray_hit *hit)
{
    double alpha = 1.0 - beta - gamma;
    ray_vec3 n, p, err;

    if (!v3_normalize(v3_cross(v3_sub(vb, va), v3_sub(vc, va)), &n))
        return 0;
    p = v3_add(v3_add(v3_scale(va, alpha), v3_scale(vb, beta)),
               v3_scale(vc, gamma));
    /* Plus the three products' underflow, RAY__TINY each (vec.h). */
    err = v3_add(v3_scale(v3_add(v3_add(v3_abs(v3_scale(va, alpha)),
                                        v3_abs(v3_scale(vb, beta))),
                                 v3_abs(v3_scale(vc, gamma))),
                          ray__gamma(7)),
                 v3(4 * RAY__TINY, 4 * RAY__TINY, 4 * RAY__TINY));
    /* err finite implies p finite: rounding is monotone, so each |p_k|,
    ** summed in the same order, is at most err's sum of magnitudes, and
    ** a NaN term makes that sum NaN.  One compare for the three
    ** (v3_off_finite). */
    if (!(v3_off_finite(err) == 0))
        return 0;
    hit->t = t;
    hit->p = p;
    hit->n = n;
    hit->u = beta;
    hit->v = gamma;
    hit->p_err = err;
    hit->geom_id = RAY_INVALID_ID;
    hit->prim_id = RAY_INVALID_ID;
    hit->inst_id = RAY_INVALID_ID;
    return 1;
}

/*
** One component of the normal (A-B) x (A-C), x1 y2 - y1 x2: plain where
** the two products cancel by less than half (|x1 y2| + |y1 x2| <= 2 |n|,
** then within 3u), ray__diff_of_products (within 2u) where they cancel
** more -- always on caps and on needles whose odd edge is not A's, where
** A-B and A-C are nearly parallel.  See ray__triangle_test.
*/
static inline double normal_component(double x1, double y2, double y1, double x2)
{
    double n = x1 * y2 - y1 * x2;

    if (fabs(x1 * y2) + fabs(y1 * x2) <= 2 * fabs(n))
        return n;
    return ray__diff_of_products(x1, y2, y1, x2);
}

/*
** A bound on the rounding error of t = N.(A-e) / N.d below, by the
** running error analysis of Higham ("Accuracy and Stability of Numerical
** Algorithms", 2nd ed., section 3.1), with gamma(n) = n u / (1 - n u):
** each component of N = (A-B) x (A-C), x1 y2 - y1 x2 from differences
** (one rounding each), is within gamma(4) (|x1 y2| + |y1 x2|) (the inputs'
** 2u, then 3u plain or 2u compensated: normal_component); the dot
** products add gamma(4) sum |N_i (A-e)_i| (with A-e's rounding) and
** gamma(3) sum |N_i d_i|.  With t = t_num / m,
** |t - t_exact| <= dt_num / |m| + |t| (dm / |m| + u).  A hit must have
** its whole error interval past tmin: see ray__watertight_t_error.
*/
static double cramer_t_error(double a, double b, double c, double d,
                             double e, double f, const double n[3],
                             const double dir[3], const double ae[3],
                             double m, double t)
{
    double n_err[3], dt_num = 0, dm = 0;
    int k;

    n_err[0] = ray__gamma(4) * (fabs(b * f) + fabs(c * e));
    n_err[1] = ray__gamma(4) * (fabs(c * d) + fabs(a * f));
    n_err[2] = ray__gamma(4) * (fabs(a * e) + fabs(b * d));
    for (k = 0; k < 3; k++) {
        dt_num += n_err[k] * fabs(ae[k]) +
                  ray__gamma(4) * fabs(n[k] * ae[k]);
        dm += n_err[k] * fabs(dir[k]) + ray__gamma(3) * fabs(n[k] * dir[k]);
    }
    /* Underflow: the dozen products of each sum may lose RAY__TINY each. */
    dt_num = dt_num * (1 + ray__gamma(2)) + 16 * RAY__TINY;
    dm = dm * (1 + ray__gamma(2)) + 16 * RAY__TINY;
    return (dt_num + fabs(t) * dm) / fabs(m) + ray__gamma(2) * fabs(t);
}

/*
** The system [A-B, A-C, d] [beta gamma t]^T = A - e, with the book's
** names for its entries:
**
**     | a d g |   | beta  |   | j |      a,b,c = A - B
**     | b e h | * | gamma | = | k |      d,e,f = A - C
**     | c f i |   | t     |   | l |      g,h,i = d (ray direction)
**                                        j,k,l = A - e (e: ray origin)
**
** Cramer's rule with six 2x2 minors for the barycentrics' numerators:
**   beta  = (j(ei-hf) + k(gf-di) + l(dh-eg)) / M
**   gamma = (i(ak-jb) + h(jc-al) + g(bl-kc)) / M
** and the determinant and t's numerator by the triple products' other
** order, through the normal N = (A-B) x (A-C) = (bf-ce, cd-af, ae-bd):
**   M     = det[A-B, A-C, d]   = N . d
**   t     = det[A-B, A-C, A-e] / M = N . (A-e) / M.
** The book takes M = a(ei-hf) + b(gf-di) + c(dh-eg) and t from the
** minors (ak-jb) ... too, but those dot a rounded cross product with a
** vector nearly parallel to one of its factors when A-B and A-C are
** nearly parallel (a cap, or a needle seen from its far vertex): the
** cross product's rounding error, u |A-C| |d| per component in any
** direction, then survives the cancellation, and M and t lose a factor of
** the aspect ratio -- 1.6e7 conditioned ulps of t on the slivers of
** bench/accuracy.c.  N carries the sliver's thinness in its own
** cancellations (x1 y2 - y1 x2 of nearly parallel edges), which
** normal_component computes to 2u relative; the dot products that follow
** lose only what the geometry does (|cos theta| for M, the origin's
** distance for t).  The barycentrics' numerators keep the book's minors:
** their errors, divided by M, are at most about u |A-e| / altitude, a few
** ulps of the barycentric as a distance (the bench's u and v columns).
**
** Only M == 0 exactly is rejected for its size.  The 1997 Moeller-Trumbore
** code rejects |M| < 1e-6, which is scale-dependent and drops every
** triangle with edges shorter than ~1e-3.  A NaN M, or one past DBL_MAX
** (finite inputs whose products overflow: edges near 1e154 and a long
** direction), is a miss too, refused with M == 0: the range tests below
** would not refuse an infinite M, as every finite numerator divided by it
** is a zero, which passes them where tmin < 0 (a hit at t = 0 on vertex A
** wherever the ray went; issue 38, found by make mutants' tri-sign-filter).
*/
int ray__triangle_test(const ray_ray *r, ray_vec3 va, ray_vec3 vb,
                       ray_vec3 vc, double *t_out, double *beta_out,
                       double *gamma_out)
{
    double a = va.x - vb.x, b = va.y - vb.y, c = va.z - vb.z;
    double d = va.x - vc.x, e = va.y - vc.y, f = va.z - vc.z;
    double g = r->dir.x, h = r->dir.y, i = r->dir.z;
    double j = va.x - r->org.x, k = va.y - r->org.y, l = va.z - r->org.z;
    double ei_hf = e * i - h * f, gf_di = g * f - d * i, dh_eg = d * h - e * g;
    double ak_jb = a * k - j * b, jc_al = j * c - a * l, bl_kc = b * l - k * c;
    double nx = normal_component(b, f, c, e), ny = normal_component(c, d, a, f),
           nz = normal_component(a, e, b, d);
    double m = nx * g + ny * h + nz * i;
    double t_num, gamma_num, beta_num, sign, t, beta, gamma;

    /* A parallel ray or a zero-area triangle; M NaN or overflowed. */
    if (m == 0 || !(fabs(m) <= DBL_MAX))
        return 0;
    /*
    ** Sign filters on the numerators first, exact and division-free: for
    ** sign = sign(m), x/m >= 0 exactly when sign * x >= 0 (the quotient of
    ** a signed zero is a zero of the same sign), and a NaN fails both.  So
    ** these reject nothing the tests below would accept, and most misses
    ** never pay for a division.
    */
    sign = m > 0 ? 1.0 : -1.0;
    gamma_num = i * ak_jb + h * jc_al + g * bl_kc;
    beta_num = j * ei_hf + k * gf_di + l * dh_eg;
    if (!(sign * gamma_num >= 0 && sign * beta_num >= 0))
        return 0;
    t_num = nx * j + ny * k + nz * l;
    if (r->tmin >= 0 && !(sign * t_num > 0))      /* t <= 0 <= tmin */
        return 0;
    /* Divisions rather than one reciprocal: each quotient is then
    ** correctly rounded, and an edge hit stays exactly on its edge. */
    t = t_num / m;
    if (!(t > r->tmin && t < r->tmax))
        return 0;
    gamma = gamma_num / m;
    if (!(gamma >= 0 && gamma <= 1))
        return 0;
    beta = beta_num / m;
    if (!(beta >= 0 && beta <= 1 - gamma))
        return 0;
    /* Last, as it costs most: only a hit inside the triangle pays. */
    {
        const double n[3] = {nx, ny, nz}, dir[3] = {g, h, i},
                     ae[3] = {j, k, l};
        if (!(t - cramer_t_error(a, b, c, d, e, f, n, dir, ae, m, t) >
              r->tmin))
            return 0;
    }
    *t_out = t;
    *beta_out = beta;
    *gamma_out = gamma;
    return 1;
}

int ray_triangle(const ray_ray *r, ray_vec3 va, ray_vec3 vb, ray_vec3 vc,
                 ray_hit *hit)
{
    double t, beta, gamma;

    if (r == NULL || hit == NULL)
        return 0;
    if (!ray__triangle_test(r, va, vb, vc, &t, &beta, &gamma))
        return 0;
    return ray__triangle_fill(va, vb, vc, t, beta, gamma, hit);
}

/* ------------------------------------------------------------ watertight */

/* The test itself is in watertight.h, inlined into the BVH traversal. */
int ray__triangle_watertight_test(const ray_ray *r, ray_vec3 va, ray_vec3 vb,
                                  ray_vec3 vc, double *t_out,
                                  double *beta_out, double *gamma_out)
{
    ray__watertight w;

    if (!ray__watertight_init(&w, r))
        return 0;
    return ray__triangle_watertight_pre(&w, r->tmin, r->tmax, &va, &vb,
                                        &vc, t_out, beta_out, gamma_out);
}

int ray_triangle_watertight(const ray_ray *r, ray_vec3 a, ray_vec3 b,
                            ray_vec3 c, ray_hit *hit)
{
    double t, beta, gamma;

    if (r == NULL || hit == NULL)
        return 0;
    if (!ray__triangle_watertight_test(r, a, b, c, &t, &beta, &gamma))
        return 0;
    return ray__triangle_fill(a, b, c, t, beta, gamma, hit);
}

/* ------------------------------------------------------------------ naive */

/*
** Cramer's rule as above but in float, as a game engine storing float
** vertices would run it: kept (not exported) so the stability tests and
** the accuracy bench can show what double and the watertight test buy.
*/
int ray__triangle_float(const ray_ray *r, ray_vec3 va, ray_vec3 vb,
                        ray_vec3 vc, double *t_out)
{
    float ox = (float)r->org.x, oy = (float)r->org.y, oz = (float)r->org.z;
    float ax = (float)va.x, ay = (float)va.y, az = (float)va.z;
    float a = ax - (float)vb.x, b = ay - (float)vb.y, c = az - (float)vb.z;
    float d = ax - (float)vc.x, e = ay - (float)vc.y, f = az - (float)vc.z;
    float g = (float)r->dir.x, h = (float)r->dir.y, i = (float)r->dir.z;
    float j = ax - ox, k = ay - oy, l = az - oz;
    float ei_hf = e * i - h * f, gf_di = g * f - d * i, dh_eg = d * h - e * g;
    float ak_jb = a * k - j * b, jc_al = j * c - a * l, bl_kc = b * l - k * c;
    float m = a * ei_hf + b * gf_di + c * dh_eg, t, beta, gamma;

    if (m == 0)
        return 0;
    t = -(f * ak_jb + e * jc_al + d * bl_kc) / m;
    if (!((double)t > r->tmin && (double)t < r->tmax))
        return 0;
    gamma = (i * ak_jb + h * jc_al + g * bl_kc) / m;
    if (!(gamma >= 0 && gamma <= 1))
        return 0;
    beta = (j * ei_hf + k * gf_di + l * dh_eg) / m;
    if (!(beta >= 0 && beta <= 1 - gamma))
        return 0;
    *t_out = (double)t;
    return 1;
}
