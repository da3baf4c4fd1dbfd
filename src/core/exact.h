/* SPDX-License-Identifier: MIT */
/*
** exact.h -- what the geometry needs the same to the last bit on every
** platform, computed here in plain double arithmetic rather than by the
** C runtime: MinGW's and glibc's libm disagree in the last bit on a
** part of every function's results (doc/PLATFORMS.md measures it), and
** a query's answer must not depend on the C library it was linked with.
*/
#ifndef RAY_EXACT_H
#define RAY_EXACT_H

/* sqrt(x^2 + y^2) without overflow or underflow, within 0.5 ulp +
** O(u^2) for normal results (exact.c). */
double ray__hypot(double x, double y);

#endif /* RAY_EXACT_H */
