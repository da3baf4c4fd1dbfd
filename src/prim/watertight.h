/* SPDX-License-Identifier: MIT */
/*
** watertight.h -- the watertight ray/triangle test, split in two: what
** depends on the ray alone (its frame, set up once per ray) and the test
** of one triangle in that frame with the interval (tmin, tmax).  Inline,
** so the BVH traversal pays no call per triangle; ray_triangle_watertight
** (triangle.c) is the two together, so both give the same answers.
*/
#ifndef RAY_WATERTIGHT_H
#define RAY_WATERTIGHT_H

#include "prim/prim.h"

typedef struct ray__watertight {
    ray__frame f;            /* kx, ky swapped for a negative dz */
    double sz;               /* 1 / dz */
} ray__watertight;

/*
** The 2x2 edge function a_x b_y - a_y b_x in long double (64 significant
** bits on x86, 113 on AArch64 Linux, plain double on some platforms).
** Used only to re-evaluate the edge functions when one is exactly 0 in
** double: more often then its true sign shows.  It stays exactly
** antisymmetric, fl(p - q) = -fl(q - p), so two triangles sharing the
** edge still get opposite values.
*/
static inline double ray__edge_extended(double ax, double ay, double bx,
                                       double by)
{
    return (double)((long double)ax * (long double)by -
                    (long double)ay * (long double)bx);
}

/* min and max as single instructions (fmin/fmax are libm calls for
** their NaN rules, not needed here); minpd / maxpd pick the same way. */
static inline double dmin(double a, double b)
{
    return a < b ? a : b;
}

static inline double dmax(double a, double b)
{
    return a > b ? a : b;
}

/*
** Woop, Benthin and Wald, "Watertight Ray/Triangle Intersection", JCGT
** 2(1), 2013, in double.  The vertices are translated to the ray origin,
** the axes permuted so the largest direction component is z (and swapped
** for a negative one, to keep the winding), and sheared so the ray is the
** +z axis; the triangle is then hit iff the origin of the xy plane is
** inside it, decided by the three 2-D edge functions U, V, W.
**
** Why it is watertight: each vertex is transformed on its own, so a
** vertex shared by two triangles gets the same coordinates in both, and an
** edge function depends only on its edge's two vertices: a shared edge
** gives exactly -U in the neighbour (without FMA contraction, which the
** build forbids).  Edge functions are accepted with their sign inclusive,
** so a ray exactly on the edge hits at least one side.  When one is
** exactly 0 all three are re-evaluated in long double (the paper's double
** fallback for float), which picks the true side more often.
**
** t and the barycentrics come from the same quantities: det = U + V + W,
** t = (U Az + V Bz + W Cz) / det, beta = V / det, gamma = W / det.
*/
static inline int ray__watertight_init(ray__watertight *w,
                                       const ray_ray *r)
{
    int neg;
    size_t at[2];
    double o[2], shear[2];

    if (!ray__frame_init(&w->f, r))  /* zero or NaN direction: a miss */
        return 0;
    /* A negative dz swaps x and y, to keep the winding; by indexing, as
    ** the sign is a coin toss. */
    neg = w->f.dz < 0;
    at[0] = w->f.at[0], at[1] = w->f.at[1];
    o[0] = w->f.o[0], o[1] = w->f.o[1];
    shear[0] = w->f.sx, shear[1] = w->f.sy;
    w->f.at[0] = at[neg], w->f.at[1] = at[!neg];
    w->f.o[0] = o[neg], w->f.o[1] = o[!neg];
    w->f.sx = shear[neg], w->f.sy = shear[!neg];
    w->sz = 1.0 / w->f.dz;
    return 1;
}

/*
** A bound on the rounding error of the t that ray__watertight_finish
** computes, following pbrt-v4's derivation for this test (Pharr, Jakob,
** Humphreys, "Physically Based Rendering", 4th ed., section 6.8.4,
** "Robust Triangle Intersections"), with gamma(n) = n u / (1 - n u) the
** bound on n successive roundings (Higham) and u = DBL_EPSILON / 2:
**
**   x, y: (v - o) - s z rounds three times on top of the direction's own
**         rounding into s: dx = gamma(5) (max|x| + |s_x| max|z|), dy
**         likewise (pbrt writes max|z|, as |s| <= 1 there too: kz is the
**         largest component; the factor |s| keeps the bound tight for a
**         ray nearly along kz);
**   z:    (v - o)[kz] * (1 / dz): dz_s = gamma(3) max|z s_z|;
**   e:    a x b y - a y b x: de = 2 (gamma(2) max|x| max|y|
**         + dy max|x| + dx max|y|) (also bounds the long double re-
**         evaluation, which rounds less);
**   t_num = sum e_i z_i s_z: 3 (gamma(3) max|e| max|z s_z| + de max|z s_z|
**         + dz_s max|e|);
**   det = e_a + e_b + e_c, whose terms share a sign: gamma(2) |det| + 3 de,
** so |t - t_exact| <= (dt_num + 3 de |t|) / |det| + gamma(4) |t| (the
** division and det's relative error).  pbrt keeps only the first term,
** as it tests t > bound against 0; the others make the bound hold for
** any tmin.
**
** Why it matters: a ray leaving a surface starts on it, or within its
** rounding error, so the exact t of that surface is 0 or negative; the
** computed t is rounding noise around it (about 1e-17 for a triangle in
** the plane y = 0, where ray_spawn has no error to offset by).  Only a t
** whose whole error interval lies past tmin is a hit.
*/
static inline double ray__watertight_t_error(const ray__watertight *wt,
                                             double u, double v, double w,
                                             double za, double zb,
                                             double zc, double max_x,
                                             double max_y, double det,
                                             double t)
{
    double max_zs = dmax(dmax(fabs(za), fabs(zb)), fabs(zc));
    double max_z = max_zs, max_e = dmax(dmax(fabs(u), fabs(v)), fabs(w));
    double dx, dy, dzs, de, dt_num, at = fabs(t);

    max_zs *= fabs(wt->sz) * (1 + ray__gamma(1));
    /* The shear s = d_k / d_z may underflow (a direction component 1e-150
    ** beside 5e216): it is then off by up to RAY__TINY absolutely, and
    ** s z by that times |z| (found by fuzz/fuzz_primitives). */
    dx = ray__gamma(5) * (max_x + fabs(wt->f.sx) * max_z) +
         2 * RAY__TINY * max_z;
    dy = ray__gamma(5) * (max_y + fabs(wt->f.sy) * max_z) +
         2 * RAY__TINY * max_z;
    dzs = ray__gamma(3) * max_zs;
    de = 2 * (ray__gamma(2) * max_x * max_y + dy * max_x + dx * max_y);
    /* Underflow: each product of x, y, z and e, at most a dozen per
    ** term, may lose RAY__TINY (vec.h). */
    de += 8 * RAY__TINY;
    dt_num = 3 * (ray__gamma(3) * max_e * max_zs + de * max_zs +
                  dzs * max_e) + 16 * RAY__TINY;
    return (dt_num + 3 * de * at) / fabs(det) + ray__gamma(4) * at;
}

/*
** The test's end, from the edge functions u, v, w (their signs checked),
** the projected distances za, zb, zc of the vertices along kz and the
** largest |x| and |y| of the projected vertices: det, t in (tmin, tmax)
** with its whole error interval past tmin, the barycentrics.
*/
static inline int ray__watertight_finish(const ray__watertight *wt,
                                         double u, double v, double w,
                                         double za, double zb, double zc,
                                         double max_x, double max_y,
                                         double tmin, double tmax,
                                         double *t_out, double *beta_out,
                                         double *gamma_out)
{
    double det = u + v + w, t_num, t, beta, gamma;

    if (det == 0 || det != det)     /* edge-on, degenerate or bad input */
        return 0;
    t_num = u * (wt->sz * za) + v * (wt->sz * zb) + w * (wt->sz * zc);
    t = t_num / det;
    if (!(t > tmin && t < tmax))
        return 0;
    if (!(t - ray__watertight_t_error(wt, u, v, w, za, zb, zc, max_x, max_y,
                                      det, t) > tmin))
        return 0;
    beta = v / det;
    gamma = w / det;
    /* u, v, w share det's sign, so beta, gamma >= 0 and their sum <= 1 up
    ** to rounding; clamp that rounding for the hit record. */
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

/*
** Edge function q_x p_y - q_y p_x (edge p -> q; -E of edge q -> p) again,
** for a triangle the sign test kept: ray__diff_of_products, relative
** error <= 2u, where the plain value has absolute error up to u (|q_x p_y|
** + |q_y p_x|) and so, on a short edge far from the ray, wrong digits
** from the first: its error divided by the edge's length -- what it does
** to the barycentric opposite -- grows as (distance / edge length)^2, up
** to 1e5-1e7 ulps on needles and caps (bench/accuracy.c, "Needle and cap
** triangles").  Filter: where the products cancel by less than half,
** |q_x p_y| + |q_y p_x| <= 2 |plain|, the plain value is already within
** 3u (u for its subtraction, at most 2u |plain| for the products) and the
** fma calls (libm calls where the compiler targets no FMA unit) are
** skipped.  Only hit candidates pay: the sign test (watertightness) uses
** the plain values, as before.
*/
static inline double ray__edge_refine(double plain, double qx, double py,
                                      double qy, double px)
{
    if (fabs(qx * py) + fabs(qy * px) <= 2 * fabs(plain))
        return plain;
    return ray__diff_of_products(qx, py, qy, px);
}

static inline int ray__triangle_watertight_pre(
    const ray__watertight *wt, double tmin, double tmax, const ray_vec3 *va,
    const ray_vec3 *vb, const ray_vec3 *vc, double *t_out, double *beta_out,
    double *gamma_out)
{
    double pa[3], pb[3], pc[3];
    double ax, ay, bx, by, cx, cy, u, v, w;

    ray__frame_project(&wt->f, va, pa);
    ray__frame_project(&wt->f, vb, pb);
    ray__frame_project(&wt->f, vc, pc);
    ax = pa[0], ay = pa[1];
    bx = pb[0], by = pb[1];
    cx = pc[0], cy = pc[1];
    u = cx * by - cy * bx;
    v = ax * cy - ay * cx;
    w = bx * ay - by * ax;
    /* "Any zero" by bitwise or, one branch; not through the smallest
    ** magnitude, which a NaN in another edge function (Inf - Inf in
    ** double, finite in long double) would hide. */
    if ((u == 0) | (v == 0) | (w == 0)) {
        u = ray__edge_extended(cx, cy, bx, by);
        v = ray__edge_extended(ax, ay, cx, cy);
        w = ray__edge_extended(bx, by, ax, ay);
        /* Inclusive on both signs: a miss only when the signs truly
        ** differ (one compare each through the extremes; a NaN may go
        ** either way here, as det is then NaN: a miss in both cases). */
        if (dmin(dmin(u, v), w) < 0 && dmax(dmax(u, v), w) > 0)
            return 0;
    } else {
        if (dmin(dmin(u, v), w) < 0 && dmax(dmax(u, v), w) > 0)
            return 0;
        /* A candidate: t and the barycentrics from accurate edge
        ** functions.  Each keeps its sign or becomes 0 (the compensated
        ** value's sign is the exact one's or 0), so the hit/miss answer
        ** above stands; the long double values of the branch above,
        ** already past double's digits and kept for their range (tiny
        ** triangles whose products underflow in double), are kept. */
        u = ray__edge_refine(u, cx, by, cy, bx);
        v = ray__edge_refine(v, ax, cy, ay, cx);
        w = ray__edge_refine(w, bx, ay, by, ax);
    }
    return ray__watertight_finish(
        wt, u, v, w, pa[2], pb[2], pc[2],
        dmax(dmax(fabs(ax), fabs(bx)), fabs(cx)),
        dmax(dmax(fabs(ay), fabs(by)), fabs(cy)), tmin, tmax, t_out,
        beta_out, gamma_out);
}

/*
** Pairs need SSE2 and doubles evaluated as doubles (FLT_EVAL_METHOD 0):
** on i386 the scalar test may run on the x87 unit, in extended precision,
** and the lanes would then round differently from it.
*/
#if RAY__SSE2 && FLT_EVAL_METHOD == 0
#define RAY__PAIRS 1
#else
#define RAY__PAIRS 0
#endif

#if RAY__PAIRS
#include <emmintrin.h>
/*
** Two triangles at once, one per lane of SSE2's double registers: the
** projection, the edge functions and the sign test above, operation for
** operation (packed IEEE double arithmetic rounds as scalar does, minpd /
** maxpd pick as the scalar "a < b ? a : b" does), so each lane's answer
** is the one-triangle test's.  What the leaves of a BVH spend most of
** their tests on -- rejecting -- is then done in half the instructions
** and with one branch per pair.  ray__watertight2 holds the ray's
** quantities broadcast to both lanes.
*/
typedef struct ray__watertight2 {
    __m128d o[3], sx, sy;
    size_t at[3];
} ray__watertight2;

static inline void ray__watertight2_init(ray__watertight2 *w2,
                                         const ray__watertight *wt)
{
    int k;

    for (k = 0; k < 3; k++) {
        w2->o[k] = _mm_set1_pd(wt->f.o[k]);
        w2->at[k] = wt->f.at[k];
    }
    w2->sx = _mm_set1_pd(wt->f.sx);
    w2->sy = _mm_set1_pd(wt->f.sy);
}

/* Component "at" of v0 and of v1, in lanes 0 and 1. */
static inline __m128d ray__load2(const ray_vec3 *v0, const ray_vec3 *v1,
                                 size_t at)
{
    return _mm_loadh_pd(_mm_load_sd(v3_ptr(v0, at)), v3_ptr(v1, at));
}

/* Vertex v0 (lane 0) and v1 (lane 1) in the frame: ray__frame_project. */
static inline void ray__project2(const ray__watertight2 *w,
                                 const ray_vec3 *v0, const ray_vec3 *v1,
                                 __m128d p[3])
{
    p[2] = _mm_sub_pd(ray__load2(v0, v1, w->at[2]), w->o[2]);
    p[0] = _mm_sub_pd(_mm_sub_pd(ray__load2(v0, v1, w->at[0]), w->o[0]),
                      _mm_mul_pd(w->sx, p[2]));
    p[1] = _mm_sub_pd(_mm_sub_pd(ray__load2(v0, v1, w->at[1]), w->o[1]),
                      _mm_mul_pd(w->sy, p[2]));
}

/*
** Triangles (a0, b0, c0) and (a1, b1, c1) against the ray: a bit mask of
** the lanes whose plain edge functions pass the sign test -- the hit
** candidates, which the caller ends with ray__triangle_watertight_pre
** (the compensated edge functions need fma, which SSE2 lacks; candidates
** are few, a handful per ray); -1 when an edge function is exactly 0 in a
** lane: the caller then tests both with ray__triangle_watertight_pre (the
** long double re-evaluation is scalar; it is rare).  Lane for lane the
** scalar test's plain edge functions and sign test, so the lanes it
** rejects are those the scalar test rejects.
*/
static inline int ray__watertight_pair(const ray__watertight2 *w2,
                                       const ray_vec3 *a0, const ray_vec3 *a1,
                                       const ray_vec3 *b0, const ray_vec3 *b1,
                                       const ray_vec3 *c0, const ray_vec3 *c1)
{
    const __m128d zero = _mm_setzero_pd();
    __m128d pa[3], pb[3], pc[3], eu, ev, ew, lo, hi;
    int miss;

    ray__project2(w2, a0, a1, pa);
    ray__project2(w2, b0, b1, pb);
    ray__project2(w2, c0, c1, pc);
    eu = _mm_sub_pd(_mm_mul_pd(pc[0], pb[1]), _mm_mul_pd(pc[1], pb[0]));
    ev = _mm_sub_pd(_mm_mul_pd(pa[0], pc[1]), _mm_mul_pd(pa[1], pc[0]));
    ew = _mm_sub_pd(_mm_mul_pd(pb[0], pa[1]), _mm_mul_pd(pb[1], pa[0]));
    if (_mm_movemask_pd(_mm_or_pd(_mm_or_pd(_mm_cmpeq_pd(eu, zero),
                                            _mm_cmpeq_pd(ev, zero)),
                                  _mm_cmpeq_pd(ew, zero))))
        return -1;
    lo = _mm_min_pd(_mm_min_pd(eu, ev), ew);
    hi = _mm_max_pd(_mm_max_pd(eu, ev), ew);
    miss = _mm_movemask_pd(_mm_and_pd(_mm_cmplt_pd(lo, zero),
                                      _mm_cmpgt_pd(hi, zero)));
    return ~miss & 3;
}
#endif

#endif
