/* SPDX-License-Identifier: MIT */
/*
** platform.c -- the operating system's answers (platform.h), POSIX.
*/
#include <limits.h>
#include <unistd.h>

#include "core/platform.h"

unsigned ray__online_cpus(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 && n <= (long)UINT_MAX ? (unsigned)n : 1u;
}
