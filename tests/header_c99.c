/* SPDX-License-Identifier: MIT */
/* The public header must compile on its own, as C99 and as C++. */
#include <ray.h>
