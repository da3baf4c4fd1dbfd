/* SPDX-License-Identifier: MIT */
/*
** predicates.c -- exact orientation predicates: a floating-point filter
** and, where it cannot decide, the exact value as a floating-point
** expansion (J. R. Shewchuk, "Adaptive Precision Floating-Point
** Arithmetic and Fast Robust Geometric Predicates", Discrete &
** Computational Geometry 18(3), 1997: TWO-SUM, TWO-PRODUCT with
** Veltkamp's split, GROW-EXPANSION and SCALE-EXPANSION with zero
** elimination).  The build forbids FMA contraction (-ffp-contract=off),
** which the error-free transformations below rely on.
*/
#include "core/predicates.h"

/* Shewchuk's error bounds (his epsilon is u = 2^-53): the filtered
** value is within (3 + 16u) u times the permanent for orient2d and
** (7 + 56u) u for orient3d (his ccwerrboundA and o3derrboundA), so a
** value beyond that has the exact sign. */
#define U_HALF (DBL_EPSILON / 2)
#define ERR2 ((3.0 + 16.0 * U_HALF) * U_HALF)
#define ERR3 ((7.0 + 56.0 * U_HALF) * U_HALF)

/* Room for the largest expansion below: orient3d's three products of
** three 2-term differences (2 x 2 x 2 x 2 terms each, doubled by the
** sums) stay within 3 * 64 terms. */
#define MAXTERMS 256

static void two_sum(double a, double b, double *x, double *y)
{
    double s = a + b, bv = s - a, av = s - bv;

    *x = s;
    *y = (a - av) + (b - bv);
}

/* Veltkamp's split: 2^27 + 1 cuts a double into two 26-bit halves. */
static void split(double a, double *hi, double *lo)
{
    double c = 134217729.0 * a, big = c - a;

    *hi = c - big;
    *lo = a - *hi;
}

static void two_product(double a, double b, double *x, double *y)
{
    double p = a * b, ahi, alo, bhi, blo, err1, err2, err3;

    split(a, &ahi, &alo);
    split(b, &bhi, &blo);
    err1 = p - ahi * bhi;
    err2 = err1 - alo * bhi;
    err3 = err2 - ahi * blo;
    *x = p;
    *y = alo * blo - err3;
}

/* h = e + f, both expansions (increasing magnitude, non-overlapping),
** by growing e with each term of f; zeros dropped.  Returns h's length. */
static int expansion_sum(int elen, const double *e, int flen,
                         const double *f, double *h)
{
    double tmp[MAXTERMS];
    int i, j, n = elen;

    for (i = 0; i < elen; i++)
        tmp[i] = e[i];
    for (j = 0; j < flen; j++) {
        double q = f[j], x, y;
        int k = 0;
        for (i = 0; i < n; i++) {
            two_sum(q, tmp[i], &x, &y);
            q = x;
            if (y != 0)
                tmp[k++] = y;
        }
        if (q != 0)
            tmp[k++] = q;
        n = k;
    }
    for (i = 0; i < n; i++)
        h[i] = tmp[i];
    return n;
}

/* h = e * b (SCALE-EXPANSION, zeros dropped).  Returns h's length. */
static int scale_expansion(int elen, const double *e, double b, double *h)
{
    double q, x, y, p, t;
    int i, k = 0;

    two_product(e[0], b, &q, &y);
    if (y != 0)
        h[k++] = y;
    for (i = 1; i < elen; i++) {
        two_product(e[i], b, &p, &t);
        two_sum(q, t, &x, &y);
        if (y != 0)
            h[k++] = y;
        two_sum(p, x, &q, &y);
        if (y != 0)
            h[k++] = y;
    }
    if (q != 0)
        h[k++] = q;
    return k;
}

/* h = e * f, expansions: the sum of e scaled by each term of f, f the
** shorter of the two (the product commutes; a one-term factor, which
** zero elimination makes common, is then one SCALE-EXPANSION rather
** than a sum of as many as the other has terms). */
static int expansion_product(int elen, const double *e, int flen,
                             const double *f, double *h)
{
    double part[MAXTERMS], acc[MAXTERMS];
    int j, n = 0, m;

    if (elen == 0 || flen == 0)
        return 0;
    if (flen > elen) {
        const double *t = e;
        e = f;
        f = t;
        j = elen;
        elen = flen;
        flen = j;
    }
    if (flen == 1)
        return scale_expansion(elen, e, f[0], h);
    for (j = 0; j < flen; j++) {
        m = scale_expansion(elen, e, f[j], part);
        n = expansion_sum(n, acc, m, part, acc);
    }
    for (j = 0; j < n; j++)
        h[j] = acc[j];
    return n;
}

/* a - b as an exact expansion (TWO-DIFF): one term where the difference
** is exact (Sterbenz's lemma makes it so for nearby coordinates, the
** usual case where the filter fails: a point on or next to a face),
** else two.  The zero tail is dropped (Shewchuk's zero elimination), so
** the products below have a quarter of the terms or fewer; never an
** empty expansion (a - b = 0 is the one term 0), which
** scale_expansion's first term needs. */
static int diff(double a, double b, double *h)
{
    double x, y;

    two_sum(a, -b, &x, &y);
    if (y == 0) {
        h[0] = x;
        return 1;
    }
    h[0] = y;
    h[1] = x;
    return 2;
}

/* The expansion's value to double precision, its sign exact: the
** largest term carries the sign, as the terms do not overlap. */
static double estimate(int n, const double *e)
{
    double s = 0;
    int i;

    for (i = 0; i < n; i++)
        s += e[i];
    if (n > 0 && (s > 0) != (e[n - 1] > 0))
        return e[n - 1];
    return s;
}

/* p q - r s, expansions each. */
static int cross2(int pl, const double *p, int ql, const double *q, int rl,
                  const double *r, int sl, const double *s, double *h)
{
    double a[MAXTERMS], b[MAXTERMS];
    int i, na = expansion_product(pl, p, ql, q, a);
    int nb = expansion_product(rl, r, sl, s, b);

    for (i = 0; i < nb; i++)
        b[i] = -b[i];
    return expansion_sum(na, a, nb, b, h);
}

double ray__orient2d(double ax, double ay, double bx, double by, double cx,
                     double cy)
{
    double left = (bx - ax) * (cy - ay), right = (by - ay) * (cx - ax);
    double det = left - right, bound = ERR2 * (fabs(left) + fabs(right));
    double e1[2], e2[2], e3[2], e4[2], h[MAXTERMS];
    int n, n1, n2, n3, n4;

    if (det > bound || -det > bound)
        return det;
    n1 = diff(bx, ax, e1);
    n2 = diff(cy, ay, e2);
    n3 = diff(by, ay, e3);
    n4 = diff(cx, ax, e4);
    n = cross2(n1, e1, n2, e2, n3, e3, n4, e4, h);
    return estimate(n, h);
}

double ray__orient3d(ray_vec3 a, ray_vec3 b, ray_vec3 c, ray_vec3 d)
{
    double adx = a.x - d.x, ady = a.y - d.y, adz = a.z - d.z;
    double bdx = b.x - d.x, bdy = b.y - d.y, bdz = b.z - d.z;
    double cdx = c.x - d.x, cdy = c.y - d.y, cdz = c.z - d.z;
    double bc = bdy * cdz - bdz * cdy, ca = cdy * adz - cdz * ady;
    double ab = ady * bdz - adz * bdy;
    double det = adx * bc + bdx * ca + cdx * ab;
    double perm = fabs(adx) * (fabs(bdy * cdz) + fabs(bdz * cdy)) +
                  fabs(bdx) * (fabs(cdy * adz) + fabs(cdz * ady)) +
                  fabs(cdx) * (fabs(ady * bdz) + fabs(adz * bdy));
    double ex[2], ey[2], ez[2], fx[2], fy[2], fz[2], gx[2], gy[2], gz[2];
    double m[MAXTERMS], t1[MAXTERMS], t2[MAXTERMS], t3[MAXTERMS];
    double s12[MAXTERMS], h[MAXTERMS];
    int n, n1, n2, n3, n12;
    int lex, ley, lez, lfx, lfy, lfz, lgx, lgy, lgz;

    if (det > ERR3 * perm || -det > ERR3 * perm)
        return det;
    lex = diff(a.x, d.x, ex), ley = diff(a.y, d.y, ey), lez = diff(a.z, d.z, ez);
    lfx = diff(b.x, d.x, fx), lfy = diff(b.y, d.y, fy), lfz = diff(b.z, d.z, fz);
    lgx = diff(c.x, d.x, gx), lgy = diff(c.y, d.y, gy), lgz = diff(c.z, d.z, gz);
    n = cross2(lfy, fy, lgz, gz, lfz, fz, lgy, gy, m);
    n1 = expansion_product(lex, ex, n, m, t1);
    n = cross2(lgy, gy, lez, ez, lgz, gz, ley, ey, m);
    n2 = expansion_product(lfx, fx, n, m, t2);
    n = cross2(ley, ey, lfz, fz, lez, ez, lfy, fy, m);
    n3 = expansion_product(lgx, gx, n, m, t3);
    n12 = expansion_sum(n1, t1, n2, t2, s12);
    n = expansion_sum(n12, s12, n3, t3, h);
    return estimate(n, h);
}
