/* SPDX-License-Identifier: MIT */
/*
** sampling.c -- mapping uniform samples onto shapes.
*/
#include "core/sampling.h"

/*
** Shirley and Chiu's concentric map ("A Low Distortion Map Between Disk
** and Square", JGT 2(3), 1997): (a, b) in [-1,1]^2 to the unit disk,
** keeping strata compact (unlike r = sqrt(u), phi = 2 pi v).
*/
void ray__concentric_disk(double a, double b, double *x, double *y)
{
    double rad, phi;

    if (a == 0 && b == 0) {
        *x = 0;
        *y = 0;
        return;
    }
    if (fabs(a) > fabs(b)) {
        rad = a;
        phi = (RAY__PI / 4) * (b / a);
    } else {
        rad = b;
        phi = RAY__PI / 2 - (RAY__PI / 4) * (a / b);
    }
    *x = rad * cos(phi);
    *y = rad * sin(phi);
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
