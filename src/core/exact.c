/* SPDX-License-Identifier: MIT */
/*
** exact.c -- exact.h: hypot in plain double arithmetic, the same bits
** wherever IEEE 754 doubles are (with -ffp-contract=off, as the Makefile
** builds; ray__product_error is the exact product error of core/vec.h).
*/
#include "core/exact.h"
#include "core/vec.h"

/*
** hypot: x^2 + y^2 as a double-double (each square as its rounded value
** and its exact error, the sum by Knuth's TwoSum), its square root r,
** then one Newton correction r + (s - r^2) / 2r with r^2 - s formed
** from r^2's exact error (Newton's step for sqrt, Markstein's form): r
** is then within 0.5 ulp + O(u^2) of the true value, so correctly
** rounded but where that falls within O(u^2) of a halfway point.
** Arguments are first scaled by a power of two (exact) so that the
** squares neither overflow nor lose bits to underflow; a result in the
** subnormal range is rounded twice (at the scaled precision, then by
** the scaling back).  Not correctly rounded in every case, as no C
** library's hypot is required to be: what matters is that it is the same
** result everywhere, plain IEEE arithmetic in a fixed order.
*/
double ray__hypot(double x, double y)
{
    double ax = fabs(x), ay = fabs(y), scale = 1.0;
    double h1, l1, h2, l2, sh, sl, t, r, rh, rl;

    if (ax == HUGE_VAL || ay == HUGE_VAL)
        return HUGE_VAL;              /* C99 F.9.4.3: even with a NaN */
    if (ax != ax || ay != ay)
        return ax + ay;               /* NaN */
    if (ax < ay) {
        t = ax;
        ax = ay;
        ay = t;
    }
    if (ay == 0.0)
        return ax;
    if (ax > 0x1p500) {
        ax *= 0x1p-600;
        ay *= 0x1p-600;
        scale = 0x1p600;
    } else if (ax < 0x1p-500) {
        ax *= 0x1p600;
        ay *= 0x1p600;
        scale = 0x1p-600;
    }
    h1 = ax * ax;
    l1 = ray__product_error(ax, ax, h1);
    h2 = ay * ay;
    l2 = ray__product_error(ay, ay, h2);
    sh = h1 + h2;                      /* TwoSum: sh + err = h1 + h2 */
    t = sh - h1;
    sl = (h1 - (sh - t)) + (h2 - t);
    sl += l1 + l2;
    r = sqrt(sh + sl);
    rh = r * r;
    rl = ray__product_error(r, r, rh);
    r += (((sh - rh) - rl) + sl) / (2.0 * r);
    return r * scale;
}
