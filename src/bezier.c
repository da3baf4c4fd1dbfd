/*
** bezier.c -- the bicubic Bezier patch as a ray_parametric_surface:
** S(u, v) = sum_i sum_j B_i(v) B_j(u) cp[4*i + j] with the cubic
** Bernstein polynomials B_k (Farin, "Curves and Surfaces for CAGD", 5th
** ed., ch. 14), and boxes of its sub-patches from de Casteljau
** subdivision of the control net (the convex hull property).
*/
#include "internal.h"

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
** The box of the sub-patch over [u0, u1] x [v0, v1] (clamped to the
** patch's domain [0, 1]^2): its 16 control points are Mv P Mu^T, with
** M the restriction matrices, and their box contains it (convex hull);
** grown by the rounding bound of BOX_ROUNDINGS.
*/
static void bezier_bounds(void *ud, double u0, double u1, double v0,
                          double v1, ray_vec3 *lo, ray_vec3 *hi)
{
    const ray_vec3 *cp = ud;
    double mu[4][4], mv[4][4];
    ray_vec3 rows[16], mag = v3(0, 0, 0), grow;
    int i, k;

    restriction(clamp01(u0), clamp01(u1), mu);
    restriction(clamp01(v0), clamp01(v1), mv);
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
