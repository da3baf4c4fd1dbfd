/* SPDX-License-Identifier: MIT */
/*
** why.c -- the words of a refused query (why.h): the caller's buffer, not
** the scene's, since a committed scene is const and queried by any number
** of threads at once (ray.h says why).
*/
#include <stdarg.h>
#include <stdio.h>

#include "query/why.h"

int ray__why(char *why, size_t size, int rc, const char *op,
             const char *fmt, ...)
{
    va_list ap;
    int head;

    if (why == NULL || size == 0)
        return rc;
    head = snprintf(why, size, "%s: ", op);
    /* An error from snprintf, or a head that fills the buffer, leaves no
    ** room for the rest: keep what was written. */
    if (head < 0 || (size_t)head >= size)
        return rc;
    va_start(ap, fmt);
    vsnprintf(why + head, size - (size_t)head, fmt, ap);
    va_end(ap);
    return rc;
}

/* The geom_id of s's first instance whose scene changed since s's
** commit, RAY_INVALID_ID if none (instanced scenes hold no instances, so
** one level is all there is). */
static unsigned stale_instance(const ray_scene *s)
{
    size_t i;

    for (i = 0; i < s->n_prims; i++) {
        const ray__prim *p = &s->prims[i];
        if (p->kind == RAY__KIND_INSTANCE && !p->removed &&
            ray__instance_stale(&s->instances[p->surface]))
            return (unsigned)i;
    }
    return RAY_INVALID_ID;
}

int ray__why_state(char *why, size_t size, int rc, const char *op,
                   const ray_scene *s)
{
    unsigned id;

    if (!s->committed)
        return ray__why(why, size, rc, op, "the scene is not committed "
                        "(never, or changed since its last commit)");
    id = stale_instance(s);
    if (id == RAY_INVALID_ID)
        return ray__why(why, size, rc, op, "an instance's scene was "
                        "changed since this scene's commit");
    return ray__why(why, size, rc, op, "instance %u's scene was changed "
                    "since this scene's commit (commit it, then this "
                    "scene)", id);
}
