/* SPDX-License-Identifier: MIT */
/*
** error.c -- status codes to text, and the message a scene keeps of its
** last failed building call (ray_scene_errmsg), as SQLite's
** sqlite3_errmsg: the status says what kind of error, the message which
** argument, which index and which value.
*/
#include <stdarg.h>
#include <stdio.h>

#include "scene.h"

/* Negated statuses (ray_intersect, ray_implicit...) name the same error.
** Only known codes are negated back: -INT_MIN would overflow. */
const char *ray_strerror(int code)
{
    if (code < 0 && code >= -RAY_ENOTSUP)
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
    default:              return "unknown error";
    }
}

const char *ray_scene_errmsg(const ray_scene *s)
{
    /* No scene has no buffer: a fixed text, as sqlite3_errmsg(NULL). */
    if (s == NULL)
        return "no scene (NULL)";
    return s->errmsg;
}

int ray__begin(ray_scene *s, const char *op)
{
    if (s == NULL)
        return RAY_EINVAL;
    s->op = op;
    s->errmsg[0] = '\0';
    return RAY_OK;
}

int ray__fail(ray_scene *s, int code, const char *fmt, ...)
{
    va_list ap;
    int head = snprintf(s->errmsg, sizeof s->errmsg, "%s: ", s->op);

    /* An error from snprintf, or a head that fills the buffer, leaves
    ** no room for the rest: keep what was written. */
    if (head < 0 || (size_t)head >= sizeof s->errmsg)
        return code;
    va_start(ap, fmt);
    vsnprintf(s->errmsg + head, sizeof s->errmsg - (size_t)head, fmt, ap);
    va_end(ap);
    return code;
}
