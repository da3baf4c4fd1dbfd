/* SPDX-License-Identifier: MIT */
/*
** roots.c -- the real roots of a polynomial inside an interval, without a
** closed formula (used by the torus's quartic).
**
** Yuksel, "High-Performance Polynomial Root Finding for Graphics", Proc.
** ACM Comput. Graph. Interact. Tech. 5(3), HPG 2022: the roots of p' split
** [lo, hi] into pieces on which p is monotone; a piece whose ends have
** opposite signs holds exactly one root, found by Newton's method kept
** inside the shrinking bracket (bisection when a step leaves it).  p' is
** solved the same way, down to degree 1.  Unlike Ferrari's or Cardano's
** formulas nothing cancels catastrophically: each root is as accurate as
** the evaluation of p near it allows.
*/
#include "prim/prim.h"

/* p(x) by Horner's rule; c[0] is the constant term. */
static double poly_eval(const double *c, int degree, double x)
{
    double y = c[degree];
    int i;

    for (i = degree - 1; i >= 0; i--)
        y = y * x + c[i];
    return y;
}

/*
** A bound on the rounding error of poly_eval at x: Horner's rule of degree
** n is backward stable with |error| <= gamma(2n) * sum |c_i| |x|^i
** (Higham, "Accuracy and Stability of Numerical Algorithms", 2nd ed.,
** eq. 5.3).  A value of p smaller than this is zero as far as double can
** tell.
*/
static double poly_error(const double *c, int degree, double x)
{
    double y = fabs(c[degree]), ax = fabs(x);
    int i;

    for (i = degree - 1; i >= 0; i--)
        y = y * ax + fabs(c[i]);
    return ray__gamma(2 * degree) * y;
}

/*
** The root of p in [a, b] where p(a) = pa and p(b) have opposite signs
** and p is monotone.  Newton from the bracket's midpoint, the bracket
** shrinking to the side of each iterate that keeps the sign change; a
** step that leaves the bracket bisects instead (so the iteration cannot
** diverge), and a step smaller than a few ulps of x ends it: Newton's
** quadratic convergence has then reached double's precision.  At most
** ~2100 steps in theory (bisection through every double), some 5 to 10 in
** practice.
*/
#define NEWTON_DONE (4 * DBL_EPSILON)
static double poly_bracket_root(const double *c, const double *dc, int degree,
                                double a, double b, double pa)
{
    double x = 0.5 * (a + b);
    int i;

    for (i = 0; i < 2200; i++) {
        double px = poly_eval(c, degree, x);
        double step, next;

        if (px == 0)
            return x;
        if ((px < 0) == (pa < 0)) {
            a = x;
            pa = px;
        } else {
            b = x;
        }
        step = px / poly_eval(dc, degree - 1, x);
        next = x - step;
        /* A NaN or infinite step fails the test and bisects. */
        if (!(next > a && next < b)) {
            next = 0.5 * (a + b);
            if (next <= a || next >= b)      /* no double left between */
                return x;
        } else if (fabs(step) <= NEWTON_DONE * fabs(x)) {
            return next;
        }
        x = next;
    }
    return x;
}

/*
** The real roots of c[0] + c[1] x + ... + c[degree] x^degree (degree 1 to
** RAY__POLY_MAX_DEGREE, c[degree] != 0) in [lo, hi], ascending, into
** roots[] (room for degree + 1: a root exactly at lo may come on top of
** one per monotone piece); returns how many.  A double root (where p touches zero
** without crossing, e.g. a ray tangent to a torus) is reported once, at
** the extremum of p, when |p| there is below the evaluation's rounding
** bound.
*/
int ray__poly_roots(const double *c, int degree, double lo, double hi,
                    double *roots)
{
    double dc[RAY__POLY_MAX_DEGREE], ends[RAY__POLY_MAX_DEGREE + 2];
    double pa, pb;
    int n_ends, n = 0, i;

    if (degree < 1 || degree > RAY__POLY_MAX_DEGREE)
        return 0;
    if (degree == 1) {
        double x = -c[0] / c[1];
        if (x >= lo && x <= hi)
            roots[n++] = x;
        return n;
    }
    for (i = 1; i <= degree; i++)
        dc[i - 1] = c[i] * (double)i;
    /* The extrema of p: the pieces' ends are lo, they, hi. */
    n_ends = ray__poly_roots(dc, degree - 1, lo, hi, ends + 1);
    ends[0] = lo;
    ends[n_ends + 1] = hi;
    pa = poly_eval(c, degree, lo);
    for (i = 0; i <= n_ends; i++) {
        double a = ends[i], b = ends[i + 1];
        pb = poly_eval(c, degree, b);
        if (i == 0 && pa == 0)
            roots[n++] = a;
        if ((pa < 0 && pb > 0) || (pa > 0 && pb < 0)) {
            roots[n++] = poly_bracket_root(c, dc, degree, a, b, pa);
        } else if (pb != 0 && i < n_ends &&
                   fabs(pb) <= poly_error(c, degree, b)) {
            /* An extremum that touches zero within rounding: a double
            ** root.  Only interior extrema: at hi there is no touching. */
            roots[n++] = b;
            pb = 0;
        }
        if (pb == 0 && (n == 0 || roots[n - 1] != b))
            roots[n++] = b;
        pa = pb;
    }
    return n;
}
