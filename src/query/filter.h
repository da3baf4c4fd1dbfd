/* SPDX-License-Identifier: MIT */
/*
** filter.h -- part of the query template (traverse.h): the float filter
** in front of the exact triangle test.  A leaf's triangles (up to eight,
** their float corners in the leaf's rows: scene.h, RAY__LEAF_ROWS) go
** through the watertight test's arithmetic in float, all at once; a
** triangle is skipped only when a proven bound on that float arithmetic's
** error says the exact double test would miss it, and every other one
** goes to the exact test (prim/watertight.h), which still decides every
** hit.  So the answers are bit for bit those of the exact test alone
** (API-NOTES 15); the filter only saves the tests of triangles the ray
** clearly misses, which are most of a leaf's.
**
** The bound.  Let the frame be the exact test's (Woop et al., JCGT 2013:
** axes kx, ky, kz, origin o, shear s = d_k / d_kz rounded to double,
** |s| <= 1 as kz is the largest direction component), and for a vertex v
** of the triangle the exact projection
**     Z = v_kz - o_kz,  X = (v_kx - o_kx) - s_x Z,  Y likewise,
** with E = X_c Y_b - Y_c X_b (and the two other edge functions) the exact
** edge functions.  Write u = 2^-24 (float's unit roundoff), O = max_k
** |o_k|, M >= max_k |v_k - o_k| over the vertices (the scene's box, per
** ray), W = max of |X|, |Y| over the triangle's three vertices, and tau =
** 2^-126 for each rounding that may underflow or be flushed to zero
** (FTZ/DAZ, which games often set: a flushed result is off by < 2^-126).
**
**   inputs:  v_f = fl32(v), off by <= d = u (O + M) (0 for a mesh whose
**            coordinates are floats: the scene's float_exact), o_f =
**            fl32(o) by <= u O, s_f = fl32(s) by <= u |s| <= u;
**   v - o:   a_f = fl32(v_f - o_f), z_f likewise, off from v - o by
**            zeta = rho + u (M + rho) + tau, rho = d + u O + 2 tau;
**   s z:     m_f = fl32(s_f z_f), off from s Z by <= |s| zeta + u (M +
**            zeta) + u (1 + u)(M + zeta) + tau = e_m;
**   X:       x_f = fl32(a_f - m_f), off by xi <= (zeta + e_m)(1 + u) +
**            tau + u |X|  =  xi0 + u W.
**   As W <= W_f + xi, where W_f is the largest of the computed |x_f|,
**   |y_f| (what a lane can see), xi <= (xi0 + u W_f) / (1 - u).
**   xi0 is linear in O and M: expanded in exact rational arithmetic it
**   is 4.0000007 u O + 6.0000008 u M + 8.000001 tau (with d = 0:
**   2.0000004 u O + 4.0000004 u M + the same), which the filter takes as
**   (4 + 2^-20) u O + (6 + 2^-20) u M + 9 tau (2 + 2^-20, 4 + 2^-20):
**   three operations a ray instead of the chain above.
**   E:       e_f = fl32(fl32(x_c y_b) - fl32(y_c x_b)): the inputs' error
**            adds <= 4 W xi + 2 xi^2, the three roundings <= (4u +
**            2u^2)(W + xi)^2 + 3 tau; with P = W_f + 2 xi >= W + xi,
**            |e_f - E| <= D = P (4 xi + 4.0001 u P) + 3 tau.
**
** The exact test's own edge functions, in double from the same frame,
** are off from E by D_d <= 16 u_d W (W + M) + 4 u_d W^2 (u_d = 2^-53;
** prim/watertight.h derives its bound the same way), which is below
** 2^-26 D, and its long double re-evaluation rounds less.  So where e_f <
** -(D + D_d) on one edge and e_f > D + D_d on another, the exact test
** sees one edge function negative and one positive, strictly, in either
** branch: a miss, as Woop et al.'s test decides (the signs differ).  The
** filter computes B >= D + D_d in float: D's few roundings of positive
** quantities lose at most 9u of it, and the factor 1 + 2^-10 covers that
** and D_d; tau terms add 2^-124.  A lane whose float corners are NaN (a
** coordinate beyond RAY__LEAF_FLOAT_MAX) gets NaN edge functions, which
** no comparison rejects; a ray with O + M beyond 2^60, where the float
** arithmetic could overflow, is not filtered at all, nor are the scenes
** that use Cramer's test (ray_scene_set_watertight 0), whose decisions
** this bound does not cover, nor builds where float expressions are
** evaluated in more precision than float (FLT_EVAL_METHOD != 0).
**
** The bound is tested both ways (tests/check_filter.c): rays at the
** vertices and edges of meshes near and far from the origin give the
** same hits with the filter on and off, and with the bound halved
** (ray__scene_set_filter_scale) some do not.
*/
#ifndef RAY_FILTER_H
#define RAY_FILTER_H

#include "query/query.h"
#include "prim/watertight.h"

#if defined(__AVX__) && !defined(RAY_NO_SIMD)
#include <immintrin.h>
#elif RAY__SSE2
#include <emmintrin.h>
#endif

#define FILTER_U 0x1p-24                 /* float's unit roundoff */
#define FILTER_TAU 0x1p-126              /* a flushed result's error */
#define FILTER_MAX 0x1p60                /* O + M beyond: no filter */

/*
** A ray's filter: the frame's rows (of the nine: axis kx, ky, kz of
** corner a), its origin and shear in float, and the bound's per-ray
** parts: xi = xa + xc W_f, B = (P (4 xi + k P)) f + t.  on: 0 when the
** ray is not filtered (every triangle goes to the exact test).
*/
typedef struct tri_filter {
    int on;
    unsigned row[3];
    float o[3], sx, sy, sz;
    float xa, xc, k, f, t;
} tri_filter;

/*
** x (positive, finite, below FLT_MAX) as a float no smaller than it: one
** rounding to nearest moves it by at most 2^-24 of itself, which the
** factor 1 + 2^-20 more than covers -- cheaper than stepping the float
** up, and the bound only grows by a millionth.
*/
static inline float filter_up(double x)
{
    return (float)(x * (1 + 0x1p-20));
}

/* The larger of two non-negative doubles, by a comparison. */
static inline double filter_dmax(double a, double b)
{
    return a > b ? a : b;
}

/* The float constants of the bound, rounded up: u / (1 - u) (the next
** float above 2^-24), 4.0001 u (0x1.0008p-22 is 4.0005 u) and 4 tau. */
#define FILTER_XC 0x1.000002p-24f
#define FILTER_K 0x1.0008p-22f
#define FILTER_T 0x1p-124f

/* xi0's coefficients of u O and u M, and its constant (the bound's
** expansion above), rounded up; XI_EXACT_*: for float-exact corners. */
#define FILTER_XI_O (4.0 + 0x1p-20)
#define FILTER_XI_M (6.0 + 0x1p-20)
#define FILTER_XI_O_EXACT (2.0 + 0x1p-20)
#define FILTER_XI_M_EXACT (4.0 + 0x1p-20)
#define FILTER_XI_TAU 9.0

/* The largest |v - o| over the scene's box along one axis: the end
** farther from o (lo <= hi), by a subtraction each. */
static inline double filter_reach(double lo, double hi, double o)
{
    return filter_dmax(o - lo, hi - o);
}

/* The filter of ray r, whose exact frame is wt, in scene s (its box
** bounds the vertices; its float_exact says whether their floats are
** exact; its filter_scale multiplies the bound: 1, or 1/2 in a test). */
static void tri_filter_init(tri_filter *f, const ray__watertight *wt,
                            const ray_ray *r, const ray_scene *s)
{
    const double u = FILTER_U, tau = FILTER_TAU;
    const ray_vec3 o = r->org;
    double o_max, m, xi0;
    int k;

    f->on = 0;
#if FLT_EVAL_METHOD == 0
    if (!s->watertight || s->tri_mode == RAY__TRI_EXACT)
        return;
    o_max = filter_dmax(filter_dmax(fabs(o.x), fabs(o.y)), fabs(o.z));
    m = filter_dmax(filter_dmax(filter_reach(s->lo.x, s->hi.x, o.x),
                                filter_reach(s->lo.y, s->hi.y, o.y)),
                    filter_reach(s->lo.z, s->hi.z, o.z));
    /* m rounds: one more ulp of it, and no filter for a box too far, or
    ** an empty one (lo > hi: m < 0). */
    m *= 1 + 0x1p-50;
    if (!(m >= 0 && o_max + m <= FILTER_MAX))
        return;
    xi0 = s->float_exact
              ? FILTER_XI_O_EXACT * u * o_max + FILTER_XI_M_EXACT * u * m
              : FILTER_XI_O * u * o_max + FILTER_XI_M * u * m;
    xi0 += FILTER_XI_TAU * tau;
    for (k = 0; k < 3; k++) {
        f->row[k] = (unsigned)(wt->f.at[k] / sizeof(double));
        f->o[k] = (float)wt->f.o[k];
    }
    f->sx = (float)wt->f.sx;
    f->sy = (float)wt->f.sy;
    f->sz = (float)wt->sz;
    f->xa = filter_up(xi0 / (1 - u));
    f->xc = FILTER_XC;
    f->k = FILTER_K;
    f->f = filter_up(s->filter_scale * (1 + 0x1p-10));
    f->t = FILTER_T;
    f->on = 1;
#else
    (void)wt;
    (void)r;
    (void)s;
    (void)o, (void)o_max, (void)m, (void)xi0, (void)k, (void)u, (void)tau;
#endif
}

/*
** The slots among "count" (<= 8) of a leaf whose triangle the exact test
** must see: bit j for slot j, from the leaf's rows (row r of slot j at
** base + r stride + j; stride is the leaf's slot count).  Lanes past
** count read floats of the next rows, and are masked off.
*/
#if defined(__AVX__) && !defined(RAY_NO_SIMD)
/* Eight lanes in one register each (the AVX2 copy of the queries). */
static inline __m256 filter_abs8(__m256 x)
{
    return _mm256_andnot_ps(_mm256_set1_ps(-0.0f), x);
}

/* One corner's projection, eight lanes: its rows from v (the rows' row
** offsets "at", already times the stride). */
static inline void filter_corner8(const tri_filter *f, const float *v,
                                  const unsigned at[3], __m256 *x, __m256 *y)
{
    __m256 z = _mm256_sub_ps(_mm256_loadu_ps(v + at[2]),
                             _mm256_set1_ps(f->o[2]));
    __m256 ax = _mm256_sub_ps(_mm256_loadu_ps(v + at[0]),
                              _mm256_set1_ps(f->o[0]));
    __m256 ay = _mm256_sub_ps(_mm256_loadu_ps(v + at[1]),
                              _mm256_set1_ps(f->o[1]));

    *x = _mm256_sub_ps(ax, _mm256_mul_ps(_mm256_set1_ps(f->sx), z));
    *y = _mm256_sub_ps(ay, _mm256_mul_ps(_mm256_set1_ps(f->sy), z));
}

static inline unsigned tri_filter_leaf(const tri_filter *f,
                                       const float *base, unsigned n,
                                       unsigned count)
{
    unsigned at[3];
    __m256 x[3], y[3], e[3], w, xi, p, b, lo, hi;
    int c;

    at[0] = f->row[0] * n;
    at[1] = f->row[1] * n;
    at[2] = f->row[2] * n;
    /* The corners written out: -O2 leaves a loop of three rolled. */
    filter_corner8(f, base, at, &x[0], &y[0]);
    filter_corner8(f, base + 3 * n, at, &x[1], &y[1]);
    filter_corner8(f, base + 6 * n, at, &x[2], &y[2]);
    e[0] = _mm256_sub_ps(_mm256_mul_ps(x[2], y[1]), _mm256_mul_ps(y[2], x[1]));
    e[1] = _mm256_sub_ps(_mm256_mul_ps(x[0], y[2]), _mm256_mul_ps(y[0], x[2]));
    e[2] = _mm256_sub_ps(_mm256_mul_ps(x[1], y[0]), _mm256_mul_ps(y[1], x[0]));
    w = _mm256_max_ps(_mm256_max_ps(filter_abs8(x[0]), filter_abs8(x[1])),
                      _mm256_max_ps(filter_abs8(x[2]), filter_abs8(y[0])));
    w = _mm256_max_ps(w, _mm256_max_ps(filter_abs8(y[1]), filter_abs8(y[2])));
    xi = _mm256_add_ps(_mm256_set1_ps(f->xa),
                       _mm256_mul_ps(_mm256_set1_ps(f->xc), w));
    p = _mm256_add_ps(w, _mm256_add_ps(xi, xi));
    b = _mm256_mul_ps(p, _mm256_add_ps(_mm256_mul_ps(_mm256_set1_ps(4.0f), xi),
                                       _mm256_mul_ps(_mm256_set1_ps(f->k), p)));
    b = _mm256_add_ps(_mm256_mul_ps(b, _mm256_set1_ps(f->f)),
                      _mm256_set1_ps(f->t));
    lo = _mm256_min_ps(_mm256_min_ps(e[0], e[1]), e[2]);
    hi = _mm256_max_ps(_mm256_max_ps(e[0], e[1]), e[2]);
    c = _mm256_movemask_ps(_mm256_and_ps(
        _mm256_cmp_ps(lo, _mm256_sub_ps(_mm256_setzero_ps(), b), _CMP_LT_OQ),
        _mm256_cmp_ps(hi, b, _CMP_GT_OQ)));
    return ~(unsigned)c & ((1u << count) - 1u);
}
#elif RAY__SSE2
/* Four lanes a register, the same arithmetic lane for lane; a leaf of
** more than four takes two passes. */
static inline __m128 filter_abs4(__m128 x)
{
    return _mm_andnot_ps(_mm_set1_ps(-0.0f), x);
}

static inline unsigned filter_half(const tri_filter *f, const float *base,
                                   unsigned n, unsigned lane)
{
    const float *v[3];
    __m128 x[3], y[3], e[3], w, xi, p, b, lo, hi;
    int c;

    v[0] = base + lane;
    v[1] = base + 3 * n + lane;
    v[2] = base + 6 * n + lane;
    for (c = 0; c < 3; c++) {
        __m128 z = _mm_sub_ps(_mm_loadu_ps(v[c] + f->row[2] * n),
                              _mm_set1_ps(f->o[2]));
        __m128 ax = _mm_sub_ps(_mm_loadu_ps(v[c] + f->row[0] * n),
                               _mm_set1_ps(f->o[0]));
        __m128 ay = _mm_sub_ps(_mm_loadu_ps(v[c] + f->row[1] * n),
                               _mm_set1_ps(f->o[1]));
        x[c] = _mm_sub_ps(ax, _mm_mul_ps(_mm_set1_ps(f->sx), z));
        y[c] = _mm_sub_ps(ay, _mm_mul_ps(_mm_set1_ps(f->sy), z));
    }
    e[0] = _mm_sub_ps(_mm_mul_ps(x[2], y[1]), _mm_mul_ps(y[2], x[1]));
    e[1] = _mm_sub_ps(_mm_mul_ps(x[0], y[2]), _mm_mul_ps(y[0], x[2]));
    e[2] = _mm_sub_ps(_mm_mul_ps(x[1], y[0]), _mm_mul_ps(y[1], x[0]));
    w = _mm_max_ps(_mm_max_ps(filter_abs4(x[0]), filter_abs4(x[1])),
                   _mm_max_ps(filter_abs4(x[2]), filter_abs4(y[0])));
    w = _mm_max_ps(w, _mm_max_ps(filter_abs4(y[1]), filter_abs4(y[2])));
    xi = _mm_add_ps(_mm_set1_ps(f->xa), _mm_mul_ps(_mm_set1_ps(f->xc), w));
    p = _mm_add_ps(w, _mm_add_ps(xi, xi));
    b = _mm_mul_ps(p, _mm_add_ps(_mm_mul_ps(_mm_set1_ps(4.0f), xi),
                                 _mm_mul_ps(_mm_set1_ps(f->k), p)));
    b = _mm_add_ps(_mm_mul_ps(b, _mm_set1_ps(f->f)), _mm_set1_ps(f->t));
    lo = _mm_min_ps(_mm_min_ps(e[0], e[1]), e[2]);
    hi = _mm_max_ps(_mm_max_ps(e[0], e[1]), e[2]);
    c = _mm_movemask_ps(_mm_and_ps(_mm_cmplt_ps(lo, _mm_sub_ps(
                                                        _mm_setzero_ps(), b)),
                                   _mm_cmpgt_ps(hi, b)));
    return (~(unsigned)c & 15u) << lane;
}

static inline unsigned tri_filter_leaf(const tri_filter *f,
                                       const float *base, unsigned n,
                                       unsigned count)
{
    unsigned keep = filter_half(f, base, n, 0);

    if (count > 4)
        keep |= filter_half(f, base, n, 4);
    return keep & ((1u << count) - 1u);
}
#else
/* Plain C: lane by lane, the same arithmetic (each expression a float
** operation: FLT_EVAL_METHOD is 0 where the filter is on). */
static inline float filter_max(float a, float b)
{
    return a > b ? a : b;
}

static inline float filter_min(float a, float b)
{
    return a < b ? a : b;
}

static inline unsigned tri_filter_leaf(const tri_filter *f,
                                       const float *base, unsigned n,
                                       unsigned count)
{
    unsigned j, keep = 0;

    for (j = 0; j < count; j++) {
        float x[3], y[3], e[3], w, xi, p, b, lo, hi;
        int c;
        for (c = 0; c < 3; c++) {
            const float *v = base + 3 * (unsigned)c * n + j;
            float z = v[f->row[2] * n] - f->o[2];
            float ax = v[f->row[0] * n] - f->o[0];
            float ay = v[f->row[1] * n] - f->o[1];
            float mx = f->sx * z, my = f->sy * z;
            x[c] = ax - mx;
            y[c] = ay - my;
        }
        {
            float p0 = x[2] * y[1], p1 = y[2] * x[1];
            float p2 = x[0] * y[2], p3 = y[0] * x[2];
            float p4 = x[1] * y[0], p5 = y[1] * x[0];
            e[0] = p0 - p1;
            e[1] = p2 - p3;
            e[2] = p4 - p5;
        }
        w = filter_max(filter_max(fabsf(x[0]), fabsf(x[1])),
                       filter_max(fabsf(x[2]), fabsf(y[0])));
        w = filter_max(w, filter_max(fabsf(y[1]), fabsf(y[2])));
        {
            float cw = f->xc * w, x4, kp, sum;
            xi = f->xa + cw;
            p = w + (xi + xi);
            x4 = 4.0f * xi;
            kp = f->k * p;
            sum = x4 + kp;
            b = p * sum;
            b = b * f->f;
            b = b + f->t;
        }
        lo = filter_min(filter_min(e[0], e[1]), e[2]);
        hi = filter_max(filter_max(e[0], e[1]), e[2]);
        keep |= (unsigned)!(lo < -b && hi > b) << j;
    }
    return keep;
}
#endif

/*
** The filter's verdict taken as final, for the bench alone (scene mode
** RAY__TRI_FLOAT: what a float tracer does, leaks and all): slot j of
** the leaf's rows tested by the watertight test in float, its edge
** functions' signs and its t, with no bound.  1 with *t, *beta, *gamma
** on a hit in (tmin, tmax).
*/
static inline int tri_float_hit(const tri_filter *f, const float *base,
                                unsigned n, double tmin, double tmax,
                                double *t, double *beta, double *gamma)
{
    float x[3], y[3], z[3], e[3], det, tf;
    int c;

    for (c = 0; c < 3; c++) {
        const float *v = base + 3 * (unsigned)c * n;
        float ax = v[f->row[0] * n] - f->o[0];
        float ay = v[f->row[1] * n] - f->o[1];
        float mx, my;
        z[c] = v[f->row[2] * n] - f->o[2];
        mx = f->sx * z[c];
        my = f->sy * z[c];
        x[c] = ax - mx;
        y[c] = ay - my;
    }
    e[0] = x[2] * y[1] - y[2] * x[1];
    e[1] = x[0] * y[2] - y[0] * x[2];
    e[2] = x[1] * y[0] - y[1] * x[0];
    if ((e[0] < 0 || e[1] < 0 || e[2] < 0) &&
        (e[0] > 0 || e[1] > 0 || e[2] > 0))
        return 0;
    det = e[0] + e[1] + e[2];
    if (det == 0)
        return 0;
    tf = (e[0] * (f->sz * z[0]) + e[1] * (f->sz * z[1]) +
          e[2] * (f->sz * z[2])) / det;
    if (!((double)tf > tmin && (double)tf < tmax))
        return 0;
    *t = (double)tf;
    *beta = (double)(e[1] / det);
    *gamma = (double)(e[2] / det);
    return 1;
}

#endif /* RAY_FILTER_H */
