/*
** sampling.c -- mapping uniform samples onto shapes.
*/
#include "internal.h"

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
