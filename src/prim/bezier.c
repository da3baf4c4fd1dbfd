/* SPDX-License-Identifier: MIT */
/*
** bezier.c -- the bicubic Bezier patch as a ray_parametric_surface:
** S(u, v) = sum_i sum_j B_i(v) B_j(u) cp[4*i + j] with the cubic
** Bernstein polynomials B_k (Farin, "Curves and Surfaces for CAGD", 5th
** ed., ch. 14), and boxes of its sub-patches from de Casteljau
** subdivision of the control net (the convex hull property).
*/
#include "prim/prim.h"

/*
** Rounding of the box corners.  Each sub-control point is
** sum_i sum_k mv_i mu_k cp_ik with blossom weights in [0, 1] (for
** parameters in [0, 1]) that sum to 1.  A weight is at most 6 roundings
** from its exact value (1 - t, two products, two sums of non-negative
** terms), a row sum adds 1 + 3, the column sum 6 + 1 + 3 more: 20, so the
** point lies within gamma(20) * max |cp| of the exact one per axis
** (Higham, Lemma 3.1 and section 4.2, with the exact weights' sum 1).
** Growing the box by gamma(22) * max |cp| also covers the rounding of
** the growth itself (a product and a difference), so the grown box
** contains the exact sub-patch.
*/
#define BOX_ROUNDINGS 22

/*
** The cubic Bernstein basis at t and its derivative.  Each b[k] is at most
** 5 roundings from the exact value (s = 1 - t and up to 3 products), so S
** below, two nested 4-term sums of products, is within gamma(18) *
** max |cp| of the exact surface per axis (18 = 5 + 1 + 3 for a row, then
** 5 + 1 + 3 more): the bound ray_parametric's p_err assumes.
*/
static void bernstein3(double t, double b[4], double db[4])
{
    double s = 1.0 - t;

    b[0] = s * s * s;
    b[1] = 3.0 * t * s * s;
    b[2] = 3.0 * t * t * s;
    b[3] = t * t * t;
    db[0] = -3.0 * s * s;
    db[1] = 3.0 * s * (s - 2.0 * t);
    db[2] = 3.0 * t * (2.0 * s - t);
    db[3] = 3.0 * t * t;
}

/* sum_k w[k] p[stride * k], k = 0..3. */
static ray_vec3 combine4(const double w[4], const ray_vec3 *p, int stride)
{
    ray_vec3 r = v3_scale(p[0], w[0]);
    int k;

    for (k = 1; k < 4; k++)
        r = v3_madd(r, w[k], p[stride * k]);
    return r;
}

/* S, S_u and S_v: the rows (along u) first, then the column of rows. */
static void bezier_eval(void *ud, double u, double v, ray_vec3 *s,
                        ray_vec3 *s_u, ray_vec3 *s_v)
{
    const ray_vec3 *cp = ud;
    double bu[4], dbu[4], bv[4], dbv[4];
    ray_vec3 row[4], drow[4];
    int i;

    bernstein3(u, bu, dbu);
    bernstein3(v, bv, dbv);
    for (i = 0; i < 4; i++) {
        row[i] = combine4(bu, cp + 4 * i, 1);
        drow[i] = combine4(dbu, cp + 4 * i, 1);
    }
    *s = combine4(bv, row, 1);
    *s_u = combine4(bv, drow, 1);
    *s_v = combine4(dbv, row, 1);
}

/*
** The weights of the blossom P(t1, t2, t3) of a cubic on its four
** control points (Ramshaw, "Blossoming: A Connect-the-Dots Approach to
** Splines", DEC SRC report 19, 1987): the symmetric, multi-affine
** polynomials that reduce to the Bernstein basis when t1 = t2 = t3.
*/
static void blossom_weights(double t1, double t2, double t3, double w[4])
{
    double s1 = 1.0 - t1, s2 = 1.0 - t2, s3 = 1.0 - t3;

    w[0] = s1 * s2 * s3;
    w[1] = t1 * s2 * s3 + s1 * t2 * s3 + s1 * s2 * t3;
    w[2] = t1 * t2 * s3 + t1 * s2 * t3 + s1 * t2 * t3;
    w[3] = t1 * t2 * t3;
}

/*
** Row k of m gives control point k of a cubic restricted to [a, b] from
** its control points: the blossom values P(a,a,a), P(a,a,b), P(a,b,b),
** P(b,b,b) -- what de Casteljau subdivision at a and b computes (Farin,
** CAGD, section 5.5), in one weighted sum per point.
*/
static void restriction(double a, double b, double m[4][4])
{
    blossom_weights(a, a, a, m[0]);
    blossom_weights(a, a, b, m[1]);
    blossom_weights(a, b, b, m[2]);
    blossom_weights(b, b, b, m[3]);
}

/* Grow the box [lo, hi] to hold p.  Comparisons rather than fmin/fmax,
** which are library calls without -ffinite-math-only; the points are
** finite (the control points are checked, the weights are in [0, 1]). */
static void include(ray_vec3 *lo, ray_vec3 *hi, ray_vec3 p)
{
    lo->x = p.x < lo->x ? p.x : lo->x;
    lo->y = p.y < lo->y ? p.y : lo->y;
    lo->z = p.z < lo->z ? p.z : lo->z;
    hi->x = p.x > hi->x ? p.x : hi->x;
    hi->y = p.y > hi->y ? p.y : hi->y;
    hi->z = p.z > hi->z ? p.z : hi->z;
}

static double clamp01(double x)
{
    return x < 0 ? 0 : (x > 1 ? 1 : x);
}

/*
** The box of the control points Mv P Mu^T of the sub-patch over [u0, u1]
** x [v0, v1], with M the restriction matrices.  For the whole patch,
** the first box ray_parametric asks for, the restriction matrices are
** the identity, exactly (blossom weights of 0s and 1s, and sums with
** products by 0), so its points are cp: taken as they are, with the
** same result and none of the work.
*/
static void sub_net_box(const ray_vec3 *cp, double u0, double u1, double v0,
                        double v1, ray_vec3 *lo, ray_vec3 *hi)
{
    double mu[4][4], mv[4][4];
    ray_vec3 rows[16];
    int i, k;

    if (u0 == 0 && u1 == 1 && v0 == 0 && v1 == 1) {
        *lo = *hi = cp[0];
        for (i = 1; i < 16; i++)
            include(lo, hi, cp[i]);
        return;
    }
    restriction(u0, u1, mu);
    restriction(v0, v1, mv);
    for (i = 0; i < 4; i++)
        for (k = 0; k < 4; k++)
            rows[4 * i + k] = combine4(mu[k], cp + 4 * i, 1);
    for (k = 0; k < 4; k++) {
        for (i = 0; i < 4; i++) {
            ray_vec3 p = combine4(mv[k], rows + i, 4);
            if (k == 0 && i == 0)
                *lo = *hi = p;
            include(lo, hi, p);
        }
    }
}

/*
** The box of the sub-patch over [u0, u1] x [v0, v1] (clamped to the
** patch's domain [0, 1]^2): its 16 control points (sub_net_box) contain
** it (convex hull); grown by the rounding bound of BOX_ROUNDINGS.
*/
static void bezier_bounds(void *ud, double u0, double u1, double v0,
                          double v1, ray_vec3 *lo, ray_vec3 *hi)
{
    const ray_vec3 *cp = ud;
    ray_vec3 mag = v3(0, 0, 0), grow;
    int i;

    sub_net_box(cp, clamp01(u0), clamp01(u1), clamp01(v0), clamp01(v1), lo,
                hi);
    for (i = 0; i < 16; i++) {
        ray_vec3 a = v3_abs(cp[i]);
        mag.x = a.x > mag.x ? a.x : mag.x;
        mag.y = a.y > mag.y ? a.y : mag.y;
        mag.z = a.z > mag.z ? a.z : mag.z;
    }
    grow = v3_scale(mag, ray__gamma(BOX_ROUNDINGS));
    *lo = v3_sub(*lo, grow);
    *hi = v3_add(*hi, grow);
}

/* ------------------------------------------------ halving (fast path) */

/*
** Rounding of a net carried down the quad tree by halving
** (ray__bezier_split).  A midpoint (a + b) * 0.5 rounds once, in the
** sum: the halving is exact, except where the result is subnormal
** (below).  Halving a cubic at 1/2 nests 3 midpoints (de Casteljau
** subdivision: Farin, CAGD, section 5.5), the tensor-product net 3 along
** u then 3 along v: each child point is sum_k w_k p_k (1 + theta_k) with
** exact de Casteljau weights w_k >= 0 summing to 1 and |theta_k| <=
** gamma(6) (Higham, Lemma 3.1), so it is within gamma(6) max |p_k| of
** the exact point, per axis.  Over levels: with M = max |cp| per axis
** (every exact sub-net lies in the patch net's convex hull, so within M)
** and e_L the error of the nets at level L, e_0 = 0 (the patch's own
** points) and
**     e_L <= e_{L-1} + gamma(6) (M + e_{L-1})
** (the exact halving of an error is a convex combination of it, no
** larger), so 1 + e_L / M <= (1 + gamma(6))^L <= 1 + gamma(6 L)
** (Higham, Lemma 3.3): a level-L net is within gamma(6 L) M of the exact
** sub-patch's net, and growing its box by that contains the sub-patch.
** 2 more roundings cover the growth itself (a product and a difference,
** as BOX_ROUNDINGS).  Where a midpoint is subnormal its halving may
** round, by at most half the smallest subnormal eta = 2^-1074 (a sum
** that underflows is exact: Hauser, "Handling Floating-Point Exceptions
** in Numeric Programs", ACM TOPLAS 18(2), 1996), at most 3 L eta over L
** levels; M is
** taken as max |cp| + UNDERFLOW_MARGIN, which adds gamma(n) 2^-1021 >=
** n 2^-53 2^-1021 = n eta to the growth for n roundings, more than
** enough -- without subnormal constants, whose arithmetic is slow on
** x86, in the loop.  (Martin et al., JGT 2000, likewise bound
** sub-patches by the boxes of refined control nets.)
*/
#define HALVING_ROUNDINGS 6
#define GROWTH_ROUNDINGS 2
#define UNDERFLOW_MARGIN (2.0 * DBL_MIN)

static ray_vec3 midpoint(ray_vec3 a, ray_vec3 b)
{
    return v3_scale(v3_add(a, b), 0.5);
}

/*
** The cubic p[0], p[ps], p[2 ps], p[3 ps] halved at 1/2 by de Casteljau
** (Farin, CAGD, section 5.5): out[0..3 os] is the control polygon of its
** first half and out[3 os..6 os] of its second, sharing out[3 os].
*/
static void halve_cubic(const ray_vec3 *p, int ps, ray_vec3 *out, int os)
{
    ray_vec3 a = midpoint(p[0], p[ps]), b = midpoint(p[ps], p[2 * ps]);
    ray_vec3 c = midpoint(p[2 * ps], p[3 * ps]);
    ray_vec3 d = midpoint(a, b), e = midpoint(b, c);

    out[0] = p[0];
    out[os] = a;
    out[2 * os] = d;
    out[3 * os] = midpoint(d, e);
    out[4 * os] = e;
    out[5 * os] = c;
    out[6 * os] = p[3 * ps];
}

/* The smaller and the larger of a and b, for finite values (comparisons,
** which compile to single min/max instructions, as in include). */
static double lesser(double a, double b)
{
    return a < b ? a : b;
}

static double greater(double a, double b)
{
    return a > b ? a : b;
}

/*
** The box of the 16 points of a net (row i, column k at net[stride*i +
** k]), grown by "grow".  Accumulated in locals, not through lo and hi,
** which the compiler must assume may alias the net.
*/
static void net_box(const ray_vec3 *net, int stride, ray_vec3 grow,
                    ray_vec3 *lo, ray_vec3 *hi)
{
    double x0 = net[0].x, y0 = net[0].y, z0 = net[0].z;
    double x1 = x0, y1 = y0, z1 = z0;
    int i, k;

    for (i = 0; i < 4; i++)
        for (k = 0; k < 4; k++) {
            ray_vec3 p = net[stride * i + k];
            x0 = lesser(p.x, x0);
            y0 = lesser(p.y, y0);
            z0 = lesser(p.z, z0);
            x1 = greater(p.x, x1);
            y1 = greater(p.y, y1);
            z1 = greater(p.z, z1);
        }
    *lo = v3(x0 - grow.x, y0 - grow.y, z0 - grow.z);
    *hi = v3(x1 + grow.x, y1 + grow.y, z1 + grow.z);
}

/* M of the bound above: max |cp| per axis, plus UNDERFLOW_MARGIN. */
ray_vec3 ray__bezier_magnitude(const ray_vec3 cp[16])
{
    ray_vec3 m = v3(0, 0, 0);
    int k;

    for (k = 0; k < 16; k++) {
        ray_vec3 a = v3_abs(cp[k]);
        m = v3(greater(a.x, m.x), greater(a.y, m.y), greater(a.z, m.z));
    }
    return v3(m.x + UNDERFLOW_MARGIN, m.y + UNDERFLOW_MARGIN,
              m.z + UNDERFLOW_MARGIN);
}

/*
** The net halved at u = v = 1/2: the rows along u (into 4 x 7 points),
** then the 7 columns along v, into grid; then the quarters' boxes, grown
** by the bound above for "level" halvings below the patch's net.
*/
void ray__bezier_split(const ray_vec3 *net, int stride, ray_vec3 mag,
                       unsigned level,
                       ray_vec3 grid[RAY__BEZIER_GRID * RAY__BEZIER_GRID],
                       ray_vec3 lo[4], ray_vec3 hi[4])
{
    ray_vec3 rows[4 * RAY__BEZIER_GRID], grow;
    unsigned q;
    int i;

    for (i = 0; i < 4; i++)
        halve_cubic(net + stride * i, 1, rows + RAY__BEZIER_GRID * i, 1);
    for (i = 0; i < RAY__BEZIER_GRID; i++)
        halve_cubic(rows + i, RAY__BEZIER_GRID, grid + i, RAY__BEZIER_GRID);
    grow = v3_scale(mag, ray__gamma(HALVING_ROUNDINGS * (int)level +
                                    GROWTH_ROUNDINGS));
    for (q = 0; q < 4; q++)
        net_box(grid + ray__bezier_quarter(q), RAY__BEZIER_GRID, grow,
                &lo[q], &hi[q]);
}

/* bezier_bounds identifies the surfaces ray_bezier_surface made (eval is
** checked too, so a user pairing it with another eval is not taken). */
const ray_vec3 *ray__bezier_points(const ray_parametric_surface *s)
{
    if (s->bounds == bezier_bounds && s->eval == bezier_eval)
        return s->ud;
    return NULL;
}

int ray_bezier_surface(const ray_vec3 cp[16], ray_parametric_surface *out)
{
    int i;

    if (cp == NULL || out == NULL)
        return RAY_EINVAL;
    for (i = 0; i < 16; i++)
        if (!v3_isfinite(cp[i]))
            return RAY_EINVAL;
    out->eval = bezier_eval;
    out->bounds = bezier_bounds;
    out->ud = ray__unconst(cp);
    out->u0 = 0;
    out->u1 = 1;
    out->v0 = 0;
    out->v1 = 1;
    out->subdivisions = 0;
    out->tolerance = 0;
    out->max_iterations = 0;
    return RAY_OK;
}
