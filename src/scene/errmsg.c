/* SPDX-License-Identifier: MIT */
/*
** errmsg.c -- the message a scene keeps of its last failed building call
** (ray_scene_errmsg), as SQLite's sqlite3_errmsg: the status says what
** kind of error, the message which argument, which index and which value.
*/
#include <stdarg.h>
#include <stdio.h>

#include "scene/scene.h"

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
