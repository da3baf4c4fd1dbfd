/* SPDX-License-Identifier: MIT */
/*
** ellipsoid.c -- what a sphere or a capsule becomes through an affine
** map that is not a similarity (an instance's non-uniform scale or
** shear): an ellipsoid, or an ellipsoid swept along a segment, and the
** nearest points of those, so that the queries through instances answer
** in world space (ray_closest_point, the sweeps and overlaps).  Also the
** singular value decomposition of the 3 x 3 linear part that gives the
** ellipsoid's axes.  Plain geometry: no scene.
*/
#include "prim/prim.h"

/*
** L = U diag(s) V^T by one-sided Jacobi (Hestenes 1958; Demmel and
** Veselic, "Jacobi's method is more accurate than QR", SIAM J. Matrix
** Anal. Appl. 13(4), 1992): plane rotations from the right make the
** columns of L V pairwise orthogonal; then s_k = |column k| and U's
** column k is column k / s_k.  A pair (i, j) is rotated while |c_i .
** c_j| exceeds DBL_EPSILON |c_i| |c_j| (orthogonal to working
** precision); the rotation is Rutishauser's (zeta = (|c_j|^2 -
** |c_i|^2) / (2 c_i . c_j), t = sign(zeta) / (|zeta| + sqrt(1 +
** zeta^2))).  Sweeps converge quadratically: 3 x 3 takes 4 to 6; 30 is a
** cap that is never reached by an invertible L the scene accepted.  L
** is scaled by a power of two (exact) to bring its largest entry into
** [1, 2), so the squares of the columns neither overflow nor underflow
** unless L's entries span more than 2^500 (then the small singular
** values lose digits, not the large ones).  The values are sorted
** descending, U's columns with them.  0 for a zero or non-finite L.
*/
int ray__svd3(const double l[3][3], double u[3][3], double s[3])
{
    double c[3][3], big = 0, scale;
    int i, j, k, sweep, order[3] = {0, 1, 2};

    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            big = fmax(big, fabs(l[i][j]));
    if (!(big > 0 && big < HUGE_VAL))
        return 0;
    scale = ray__pow2(-ray__exponent_of(big));
    for (i = 0; i < 3; i++)              /* c[k] = column k of L, scaled */
        for (k = 0; k < 3; k++)
            c[k][i] = l[i][k] * scale;
    for (sweep = 0; sweep < 30; sweep++) {
        int rotated = 0;
        for (i = 0; i < 2; i++)
            for (j = i + 1; j < 3; j++) {
                double a = 0, b = 0, g = 0, zeta, t, cs, sn;
                for (k = 0; k < 3; k++) {
                    a += c[i][k] * c[i][k];
                    b += c[j][k] * c[j][k];
                    g += c[i][k] * c[j][k];
                }
                if (!(fabs(g) > DBL_EPSILON * sqrt(a) * sqrt(b)))
                    continue;
                rotated = 1;
                zeta = (b - a) / (2 * g);
                t = (zeta >= 0 ? 1.0 : -1.0) /
                    (fabs(zeta) + sqrt(1 + zeta * zeta));
                cs = 1 / sqrt(1 + t * t);
                sn = cs * t;
                for (k = 0; k < 3; k++) {
                    double x = c[i][k], y = c[j][k];
                    c[i][k] = cs * x - sn * y;
                    c[j][k] = sn * x + cs * y;
                }
            }
        if (!rotated)
            break;
    }
    for (k = 0; k < 3; k++)
        s[k] = v3_length(v3(c[k][0], c[k][1], c[k][2]));
    /* Descending, by insertion. */
    for (i = 1; i < 3; i++)
        for (j = i; j > 0 && s[order[j]] > s[order[j - 1]]; j--) {
            int x = order[j];
            order[j] = order[j - 1];
            order[j - 1] = x;
        }
    {
        double sv[3];
        for (k = 0; k < 3; k++) {
            int from = order[k];
            if (!(s[from] > 0))
                return 0;
            for (i = 0; i < 3; i++)
                u[i][k] = c[from][i] / s[from];
            sv[k] = s[from] / scale;
        }
        for (k = 0; k < 3; k++)
            s[k] = sv[k];
    }
    return s[2] > 0 && s[0] < HUGE_VAL;
}

/* ------------------------------------------------ the nearest point */

/* sqrt(sum v_i^2) for n values, without overflow (each divided by the
** largest first): Eberly's RobustLength. */
static double robust_length(const double *v, int n)
{
    double m = 0, sum = 0;
    int i;

    for (i = 0; i < n; i++)
        m = fmax(m, fabs(v[i]));
    if (!(m > 0))
        return m;
    for (i = 0; i < n; i++)
        sum += (v[i] / m) * (v[i] / m);
    return m * sqrt(sum);
}

/*
** The root s of G(s) = sum_i (r_i z_i / (s + r_i))^2 - 1 that Eberly's
** method bisects ("Distance from a Point to an Ellipse, an Ellipsoid, or
** a Hyperellipsoid", Geometric Tools, 2013, GetRoot): G decreases on
** s > -1 (the smallest r_i is 1, the last axis's), from +Inf to -1, so
** its one root lies in [z_last - 1, |r z| - 1] (0 on the right when the
** point is inside, g < 0), and bisection to the midpoint that equals an
** end gives it to the last bit: at most about 1100 halvings (the
** exponent range), usually 60 to 150.
*/
static double ellipse_root(const double *r, const double *z, int n, double g)
{
    double nz[3], s0, s1, s = 0;
    int i, k;

    for (i = 0; i < n; i++)
        nz[i] = r[i] * z[i];
    s0 = z[n - 1] - 1;
    s1 = g < 0 ? 0 : robust_length(nz, n) - 1;
    for (k = 0; k < 2200; k++) {
        double sum = 0;
        s = 0.5 * (s0 + s1);
        if (s == s0 || s == s1)
            break;
        for (i = 0; i < n; i++) {
            double ratio = nz[i] / (s + r[i]);
            sum += ratio * ratio;
        }
        g = sum - 1;
        if (g > 0)
            s0 = s;
        else if (g < 0)
            s1 = s;
        else
            break;
    }
    return s;
}

/*
** The point x of the ellipse or ellipsoid (n = 2, 3) with semi-axes e[0]
** >= e[1] (>= e[2]) > 0 nearest y, every y[i] >= 0 (the first octant:
** the caller reflects), Eberly's DistancePointEllipse and
** DistancePointEllipsoid: where every y[i] > 0, x_i = r_i y_i / (s + r_i)
** with r_i = (e_i / e_last)^2 and s the root above (or x = y on the
** surface); a zero coordinate reduces the problem to the axes' ellipse
** (or to a closed form where the point lies on the plane of the two
** largest axes close enough to the centre that the nearest point leaves
** it: the focal region).
*/
static void ellipse_nearest(const double *e, const double *y, int n,
                            double *x)
{
    double z[3] = {0, 0, 0}, r[3], g = -1;   /* z: gcc -O1 warns, n >= 2 */
    int i, zero = -1;

    for (i = 0; i < n; i++)
        if (!(y[i] > 0))
            zero = i;
    if (zero < 0) {
        for (i = 0; i < n; i++) {
            z[i] = y[i] / e[i];
            g += z[i] * z[i];
        }
        if (g == 0) {
            for (i = 0; i < n; i++)
                x[i] = y[i];
            return;
        }
        for (i = 0; i < n; i++)
            r[i] = (e[i] / e[n - 1]) * (e[i] / e[n - 1]);
        {
            double sbar = ellipse_root(r, z, n, g);
            for (i = 0; i < n; i++)
                x[i] = r[i] * y[i] / (sbar + r[i]);
        }
        return;
    }
    if (zero < n - 1) {
        /* y[zero] == 0 for an axis other than the last: x[zero] = 0 and
        ** the others are the nearest point of the remaining ellipse
        ** (its axes still descending). */
        double ee[2], yy[2], xx[2];
        int m = 0;
        for (i = 0; i < n; i++)
            if (i != zero) {
                ee[m] = e[i];
                yy[m++] = y[i];
            }
        if (n == 3) {
            ellipse_nearest(ee, yy, 2, xx);
            for (i = 0, m = 0; i < n; i++)
                x[i] = i == zero ? 0.0 : xx[m++];
        } else {
            x[zero] = 0;
            x[1 - zero] = e[1 - zero];
        }
        return;
    }
    /* The last coordinate is 0: the focal-region closed form where the
    ** others are near enough the centre, else the larger axes' ellipse. */
    {
        double xde[2], discr = 1;
        int inside = 1;
        for (i = 0; i < n - 1; i++) {
            double numer = e[i] * y[i];
            double denom = e[i] * e[i] - e[n - 1] * e[n - 1];
            if (!(numer < denom)) {
                inside = 0;
                break;
            }
            xde[i] = numer / denom;
            discr -= xde[i] * xde[i];
        }
        if (inside && discr > 0) {
            for (i = 0; i < n - 1; i++)
                x[i] = e[i] * xde[i];
            x[n - 1] = e[n - 1] * sqrt(discr);
            return;
        }
        x[n - 1] = 0;
        if (n == 3)
            ellipse_nearest(e, y, 2, x);
        else
            x[0] = e[0];
    }
}

/*
** The point *p of the ellipsoid {c + U diag(e) w : |w| = 1} (U's columns
** its unit axes, e its semi-axes, descending) nearest q, and the outward
** unit normal *n there (U diag(1/e^2) x, normalised): q's coordinates y
** along the axes, reflected into the first octant, Eberly's nearest
** point, reflected back.  The semi-axes are scaled by the power of two
** that brings the largest into [1, 2) (exact), so that (e_i / e_last)^2
** overflows only for axes more than 2^500 apart.  Inside or outside
** alike.  Rounding: Eberly's root is exact to the last bit of s; x_i =
** r_i y_i / (s + r_i) then rounds a few times, which moves x along the
** surface and off it by a few ulps of |x|; the frame's and the
** reflections' roundings add a few ulps of |c| + |q - c|.  0 for a
** result that is not finite.
*/
int ray__ellipsoid_closest(ray_vec3 c, const double u[3][3],
                           const double e[3], ray_vec3 q, ray_vec3 *p,
                           ray_vec3 *n)
{
    ray_vec3 rel = v3_sub(q, c), pt, nn;
    double y[3], ee[3], x[3], sign[3], scale;
    int i;

    if (!v3_isfinite(rel) || !(e[2] > 0))
        return 0;
    scale = ray__pow2(-ray__exponent_of(e[0]));
    for (i = 0; i < 3; i++) {
        double yi = (u[0][i] * rel.x + u[1][i] * rel.y + u[2][i] * rel.z) *
                    scale;
        sign[i] = yi < 0 ? -1.0 : 1.0;
        y[i] = fabs(yi);
        ee[i] = e[i] * scale;
    }
    ellipse_nearest(ee, y, 3, x);
    for (i = 0; i < 3; i++)
        x[i] = sign[i] * x[i] / scale;
    pt = v3(c.x + u[0][0] * x[0] + u[0][1] * x[1] + u[0][2] * x[2],
            c.y + u[1][0] * x[0] + u[1][1] * x[1] + u[1][2] * x[2],
            c.z + u[2][0] * x[0] + u[2][1] * x[1] + u[2][2] * x[2]);
    for (i = 0; i < 3; i++)
        y[i] = (x[i] * scale) / ((ee[i]) * (ee[i]));
    nn = v3(u[0][0] * y[0] + u[0][1] * y[1] + u[0][2] * y[2],
            u[1][0] * y[0] + u[1][1] * y[1] + u[1][2] * y[2],
            u[2][0] * y[0] + u[2][1] * y[1] + u[2][2] * y[2]);
    if (!v3_isfinite(pt) || !v3_normalize(nn, &nn))
        return 0;
    *p = pt;
    *n = nn;
    return 1;
}

/* The signed distance from q to the ellipsoid at c + s w (negative
** inside), its nearest point and normal; +Inf when none is found. */
static double signed_at(ray_vec3 c, ray_vec3 w, const double u[3][3],
                        const double e[3], ray_vec3 q, double s,
                        ray_vec3 *p, ray_vec3 *n)
{
    double d;

    if (!ray__ellipsoid_closest(v3_madd(c, s, w), u, e, q, p, n))
        return HUGE_VAL;
    d = ray__distance(*p, q);
    return v3_dot(v3_sub(q, *p), *n) < 0 ? -d : d;
}

/*
** An ellipsoid swept along a segment: {c + s w + U diag(e) v : s in [0,
** 1], |v| <= 1}, what a capsule of radius R around [a, b] becomes
** through an affine map L (c = L a + t, w = L (b - a), e = R times L's
** singular values): the point *p of its surface nearest q, for q
** outside it, and the outward normal *n there.  The signed distance from
** q to the ellipsoid at c + s w is a convex function of s (the signed
** distance to a convex set is convex, and q - s w moves on a line), and
** outside the body, which is the union of those ellipsoids, the
** distance to it is their smallest: found by golden-section search
** (Kiefer 1953) to s within 2^-40 of its place in [0, 1], about 60
** steps, then the nearest of that s's point and of the two ends' (which
** golden section never evaluates exactly).  Near its minimum the
** distance is flat to second order in s, so a 2^-40 error in s costs
** a relative 2^-80 of it: below rounding.  For q inside the body the
** answer is the nearest point of the ellipsoid q lies deepest in, which
** is not always the nearest point of the body's boundary (a flat
** ellipsoid swept across its flat side makes a slab thicker than any of
** its ellipsoids): *inside is then set and the caller decides.  0 when
** no ellipsoid point is found (a result that is not finite).
*/
int ray__ellipsoid_sweep_closest(ray_vec3 c, ray_vec3 w, const double u[3][3],
                                 const double e[3], ray_vec3 q, ray_vec3 *p,
                                 ray_vec3 *n, int *inside)
{
    const double phi = 0.6180339887498949;      /* (sqrt 5 - 1) / 2 */
    double lo = 0, hi = 1, s1, s2, f1, f2, best = HUGE_VAL, d;
    double cand[3];
    ray_vec3 pt, nt;
    int k;

    s1 = hi - phi * (hi - lo);
    s2 = lo + phi * (hi - lo);
    f1 = signed_at(c, w, u, e, q, s1, &pt, &nt);
    f2 = signed_at(c, w, u, e, q, s2, &pt, &nt);
    while (hi - lo > 0x1p-40) {
        if (f1 <= f2) {
            hi = s2;
            s2 = s1;
            f2 = f1;
            s1 = hi - phi * (hi - lo);
            f1 = signed_at(c, w, u, e, q, s1, &pt, &nt);
        } else {
            lo = s1;
            s1 = s2;
            f1 = f2;
            s2 = lo + phi * (hi - lo);
            f2 = signed_at(c, w, u, e, q, s2, &pt, &nt);
        }
    }
    cand[0] = 0.5 * (lo + hi);
    cand[1] = 0;
    cand[2] = 1;
    for (k = 0; k < 3; k++) {
        d = signed_at(c, w, u, e, q, cand[k], &pt, &nt);
        if (d < best) {
            best = d;
            *p = pt;
            *n = nt;
        }
    }
    if (!(best < HUGE_VAL))
        return 0;
    *inside = best < 0;
    return 1;
}
