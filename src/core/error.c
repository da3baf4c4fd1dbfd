/* SPDX-License-Identifier: MIT */
/*
** error.c -- status codes to text (ray_strerror).  The message a scene
** keeps of its last failed building call is the scene's (scene/errmsg.c).
*/
#include "ray.h"

/* Negated statuses (ray_intersect, ray_implicit...) name the same error.
** Only known codes are negated back: -INT_MIN would overflow. */
const char *ray_strerror(int code)
{
    if (code < 0 && code >= -RAY_EKIND)
        code = -code;
    switch (code) {
    case RAY_OK:          return "success";
    case RAY_EINVAL:      return "invalid argument";
    case RAY_EDEGENERATE: return "degenerate geometry";
    case RAY_ERANGE:      return "result out of range";
    case RAY_ENOMEM:      return "out of memory";
    case RAY_EIO:         return "input/output error";
    case RAY_EPNG:        return "PNG encoding error";
    case RAY_ESTATE:      return "operation not allowed in this state";
    case RAY_ECANCELED:   return "cancelled by the caller";
    case RAY_ELIMIT:
        return "a limit was reached (ray tree, iterations, image load)";
    case RAY_EEFFECT:     return "effect not declared by the material";
    case RAY_ENOTSUP:     return "not supported by this build";
    case RAY_EKIND:
        return "not available for this kind of geometry";
    default:              return "unknown error";
    }
}
