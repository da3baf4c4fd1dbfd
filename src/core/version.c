/* SPDX-License-Identifier: MIT */
/*
** version.c -- the version of the library that was linked.
*/
#include "ray.h"

int ray_version_number(void)
{
    return RAY_VERSION_NUMBER;
}

const char *ray_version_string(void)
{
    return RAY_VERSION_STRING;
}
