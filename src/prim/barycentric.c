/* SPDX-License-Identifier: MIT */
/*
** barycentric.c -- barycentric coordinates from signed areas.
*/
#include "prim/prim.h"

/*
** The lecture's method: the sub-triangles opposite each vertex have
** (signed) doubled areas |PB x BC|, |PC x CA|, |PA x AB|, the sign coming
** from the dot product of each area vector with the triangle's normal
** N = (b-a) x (c-a).  Dotting with N directly gives area_i * |N|, and the
** three dot products sum to N.N for any p (the p terms cancel because the
** edges sum to zero), so a point off the plane gets the coordinates of its
** projection.
**
** Each coordinate is its area over the SUM of the three computed areas,
** not over the separately computed N.N: the three quotients then add up
** to 1 within about 2 ulps however the areas were rounded (pbrt-v4
** Triangle::Intersect normalises its edge functions the same way), where
** dividing by N.N leaves the rounding differences of four independent
** sums in alpha + beta + gamma.
**
** Each area vector is formed from the vertex nearest in the sum's order
** (p - b, p - c, p - a), the same differences the lecture uses.
*/
int ray_barycentric(ray_vec3 p, ray_vec3 a, ray_vec3 b, ray_vec3 c,
                    double abg[3], int *inside)
{
    ray_vec3 n;
    double ea, eb, ec, sum, alpha, beta, gamma;

    if (abg == NULL || !v3_isfinite(p) || !v3_isfinite(a) ||
        !v3_isfinite(b) || !v3_isfinite(c))
        return RAY_EINVAL;
    n = v3_cross(v3_sub(b, a), v3_sub(c, a));
    if (!v3_isfinite(n))
        return RAY_ERANGE;
    if (v3_dot(n, n) == 0)
        return RAY_EDEGENERATE;
    ea = v3_dot(v3_cross(v3_sub(c, b), v3_sub(p, b)), n);
    eb = v3_dot(v3_cross(v3_sub(a, c), v3_sub(p, c)), n);
    ec = v3_dot(v3_cross(v3_sub(b, a), v3_sub(p, a)), n);
    sum = ea + eb + ec;
    if (!isfinite(ea) || !isfinite(eb) || !isfinite(ec) || !isfinite(sum))
        return RAY_ERANGE;
    /* N.N > 0 yet the computed areas cancel to 0: a sliver whose area is
    ** below the rounding of its own coordinates. */
    if (sum == 0)
        return RAY_EDEGENERATE;
    alpha = ea / sum;
    beta = eb / sum;
    gamma = ec / sum;
    if (!isfinite(alpha) || !isfinite(beta) || !isfinite(gamma))
        return RAY_ERANGE;
    abg[0] = alpha;
    abg[1] = beta;
    abg[2] = gamma;
    if (inside != NULL)
        *inside = alpha >= 0 && beta >= 0 && gamma >= 0;
    return RAY_OK;
}

/*
** The lecture's normalisation, each signed area divided by N.N computed
** on its own: kept (not exported) for the stability tests and the bench,
** which show its alpha + beta + gamma drift against ray_barycentric's.
*/
int ray__barycentric_naive(ray_vec3 p, ray_vec3 a, ray_vec3 b, ray_vec3 c,
                           double abg[3])
{
    ray_vec3 n = v3_cross(v3_sub(b, a), v3_sub(c, a));
    double nn = v3_dot(n, n);

    if (!(nn > 0 && nn < HUGE_VAL))
        return RAY_EDEGENERATE;
    abg[0] = v3_dot(v3_cross(v3_sub(c, b), v3_sub(p, b)), n) / nn;
    abg[1] = v3_dot(v3_cross(v3_sub(a, c), v3_sub(p, c)), n) / nn;
    abg[2] = v3_dot(v3_cross(v3_sub(b, a), v3_sub(p, a)), n) / nn;
    return RAY_OK;
}
