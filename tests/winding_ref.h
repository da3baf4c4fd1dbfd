/* SPDX-License-Identifier: MIT */
/*
** winding_ref.h -- the generalized winding number's brute-force
** reference (Jacobson et al. 2013), shared by tests/check_contains.c
** and fuzz/fuzz_winding.c: every triangle's solid angle summed in long
** double, by van Oosterom and Strackee's formula (1983: tan(Omega / 2)
** = det / den), each angle's sign the exact orientation's
** (ray__orient3d, the library's predicate), so that rounding near a
** triangle's plane cannot flip it.  Header-only, the function static.
*/
#ifndef RAY_WINDING_REF_H
#define RAY_WINDING_REF_H

#include <math.h>

#include "core/predicates.h"

/* The winding number at q of the nt triangles idx (three vertex numbers
** each) over the vertices v; a triangle whose plane holds q adds 0. */
static inline double winding_ref_sum(const ray_vec3 *v, const unsigned *idx,
                                     size_t nt, ray_vec3 q)
{
    long double sum = 0;
    size_t i;

    for (i = 0; i < nt; i++) {
        ray_vec3 A = v[idx[3 * i]], B = v[idx[3 * i + 1]], C = v[idx[3 * i + 2]];
        long double a[3] = {(long double)A.x - (long double)q.x, (long double)A.y - (long double)q.y,
                            (long double)A.z - (long double)q.z};
        long double b[3] = {(long double)B.x - (long double)q.x, (long double)B.y - (long double)q.y,
                            (long double)B.z - (long double)q.z};
        long double c[3] = {(long double)C.x - (long double)q.x, (long double)C.y - (long double)q.y,
                            (long double)C.z - (long double)q.z};
        long double det = a[0] * (b[1] * c[2] - b[2] * c[1]) -
                          a[1] * (b[0] * c[2] - b[2] * c[0]) +
                          a[2] * (b[0] * c[1] - b[1] * c[0]);
        long double la = sqrtl(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
        long double lb = sqrtl(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
        long double lc = sqrtl(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        long double den = la * lb * lc +
                          (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) * lc +
                          (b[0] * c[0] + b[1] * c[1] + b[2] * c[2]) * la +
                          (c[0] * a[0] + c[1] * a[1] + c[2] * a[2]) * lb;
        double sign = ray__orient3d(A, B, C, q);
        if (sign == 0)
            continue;
        /* A point within rounding of the plane, on the triangle, can
        ** round det to a zero of either sign, where atan2l would pick
        ** +-pi from that zero's sign bit (a point at a triangle's
        ** rounded centroid: fuzz/corpus/fuzz_winding); the exact
        ** estimate stands in for it then. */
        if (det == 0)
            det = (long double)sign;
        else if ((det > 0) != (sign > 0))
            det = -det;
        sum += 2 * atan2l(det, den);
    }
    return (double)(sum / (4 * 3.141592653589793238462643383279503L));
}

#endif /* RAY_WINDING_REF_H */
