/* SPDX-License-Identifier: MIT */
/*
** sampling.c -- mapping uniform samples onto shapes.
*/
#include "core/sampling.h"

/*
** sin x and cos x for |x| <= pi/4, inline: the concentric map's angle
** always lies there, and glibc's sincos (a call, its range reduction and
** its general cases) was 114 instructions a light sample and 8% of the
** bunny scene's render time (perf, examples/mesh; issue 35).  Taylor
** series in x^2 by Estrin's scheme (pairs of terms, then pairs of pairs:
** a shorter chain of dependent operations than Horner's, the sample's
** critical path): on |x| <= pi/4 the first term left out,
** x^19/19! for sin and x^18/18! for cos, is below 2^-58 (8e-20 and
** 2e-18), far under the half ulp of results that are at least x/1.2 and
** 0.7.  cos adds its two largest terms last with the rounding error of
** 1 - x^2/2 carried over (fdlibm's k_cos.c does the same), so that
** error is not the result's: within 1 ulp of the true values (0.85 and
** 0.77 ulp the worst of 20M angles against long double; tests/
** check_trace.c holds the map within 5 ulp of libm's long double).
*/
static inline void quarter_sincos(double x, double *s, double *c)
{
    double z = x * x, z2 = z * z, z4 = z2 * z2, hz = 0.5 * z, w = 1.0 - hz;
    double ps = (-1.0 / 6 + z * (1.0 / 120)) +
                z2 * (-1.0 / 5040 + z * (1.0 / 362880)) +
                z4 * ((-1.0 / 39916800 + z * (1.0 / 6227020800.0)) +
                      z2 * (-1.0 / 1307674368000.0 +
                            z * (1.0 / 355687428096000.0)));
    double pc = (1.0 / 24 + z * (-1.0 / 720)) +
                z2 * (1.0 / 40320 + z * (-1.0 / 3628800)) +
                z4 * ((1.0 / 479001600 + z * (-1.0 / 87178291200.0)) +
                      z2 * (1.0 / 20922789888000.0));

    *s = x + x * z * ps;
    *c = w + (((1.0 - w) - hz) + z2 * pc);
}

/*
** Shirley and Chiu's concentric map ("A Low Distortion Map Between Disk
** and Square", JGT 2(3), 1997): (a, b) in [-1,1]^2 to the unit disk,
** keeping strata compact (unlike r = sqrt(u), phi = 2 pi v).  Its angle
** is theta = (pi/4) (b/a) in the wedges about the x axis and
** pi/2 - (pi/4) (a/b) about the y axis, whose cosine and sine are the
** sine and cosine of (pi/4) (a/b): so |angle| <= pi/4 always.
*/
void ray__concentric_disk(double a, double b, double *x, double *y)
{
    double s, c;

    if (a == 0 && b == 0) {
        *x = 0;
        *y = 0;
        return;
    }
    if (fabs(a) > fabs(b)) {
        quarter_sincos((RAY__PI / 4) * (b / a), &s, &c);
        *x = a * c;
        *y = a * s;
    } else {
        quarter_sincos((RAY__PI / 4) * (a / b), &s, &c);
        *x = b * s;
        *y = b * c;
    }
}

/*
** The side k of the smallest square grid k x k that holds n samples (the
** least k with k^2 >= n), for stratifying light and pixel samples.  Both
** callers bound n by 65536, so k <= 256 and k * k cannot overflow.
*/
unsigned ray__strata_side(unsigned n)
{
    unsigned k = 1;

    while (k * k < n)
        k++;
    return k;
}
