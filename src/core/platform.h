/* SPDX-License-Identifier: MIT */
/*
** platform.h -- what the library asks of the operating system beyond
** ISO C, in one place: the number of CPUs online.
*/
#ifndef RAY_PLATFORM_H
#define RAY_PLATFORM_H

/* The CPUs online (at least 1): what a thread count of 0 means, for the
** threaded build, the photon pass and the render. */
unsigned ray__online_cpus(void);

#endif /* RAY_PLATFORM_H */
