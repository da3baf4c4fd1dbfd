/* SPDX-License-Identifier: MIT */
/*
** check.c -- what ray_render refuses, and why in words (ray_render_check):
** the one list of its argument checks, which ray_render runs itself, so
** the two cannot disagree.  The message goes to the caller's buffer, not
** to the scene: ray_render takes a const scene that other threads may be
** rendering at the same time (ray.h, ray_render_check, says why).
** Below them, the warnings: arguments ray_render accepts but that make
** an image black, looked for only when the caller asks (warnings not
** NULL), so that ray_render, which does not ask, pays nothing for them.
*/
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "render/camera.h"

/* Write "ray_render: " and the formatted reason into msg (when there is
** room: msg NULL or size 0 writes nothing), and return code. */
static int refuse(char *msg, size_t size, int code, const char *fmt, ...)
    RAY__PRINTF(4, 5);

static int refuse(char *msg, size_t size, int code, const char *fmt, ...)
{
    va_list ap;
    int head;

    if (msg == NULL || size == 0)
        return code;
    head = snprintf(msg, size, "ray_render: ");
    if (head < 0 || (size_t)head >= size)
        return code;             /* truncated: keep what was written */
    va_start(ap, fmt);
    vsnprintf(msg + head, size - (size_t)head, fmt, ap);
    va_end(ap);
    return code;
}

/*
** Is the up vector usable with view axis w (unit): not parallel to it?
** Decided by the angle, scale-free: the sine of the angle between the
** unit up vector and w is the length of their cross product, computed to
** within a few roundings of 1 (unit factors: each component is within
** gamma(3) of the exact one).  A sine below 16 ulps (3.6e-15 rad) is
** rounding noise, not a direction: eye (0, 1, 5), look-at (0, 0, 0), up
** (0, -1, -5) gives |up x w| ~ 1e-16 |up|, which the previous test (the
** rounded cross product's length > 0) took for a frame.
*/
static int up_usable(ray_vec3 up, ray_vec3 w)
{
    ray_vec3 unit_up, u;

    return v3_normalize(up, &unit_up) &&
           v3_length(v3_cross(unit_up, w)) > 16 * DBL_EPSILON &&
           v3_normalize(v3_cross(up, w), &u);
}

/* The camera's fields, in the order ray_camera declares them. */
static int camera_check(const ray_camera *c, char *msg, size_t size)
{
    ray_vec3 w;

    if (!v3_isfinite(c->position) || !v3_isfinite(c->look_at) ||
        !v3_isfinite(c->up))
        return refuse(msg, size, RAY_EINVAL, "camera position, look_at or "
                      "up has a NaN or infinite component");
    if (!(c->vfov > 0 && c->vfov < 180))
        return refuse(msg, size, RAY_EINVAL, "camera vfov %g: the vertical "
                      "field of view must lie in (0, 180) degrees", c->vfov);
    if (!(c->aperture >= 0 && c->aperture < HUGE_VAL))
        return refuse(msg, size, RAY_EINVAL, "camera aperture %g: must be "
                      "0 (a pinhole) or positive and finite", c->aperture);
    if (!(c->focus_distance >= 0 && c->focus_distance < HUGE_VAL))
        return refuse(msg, size, RAY_EINVAL, "camera focus_distance %g: "
                      "must be 0 (the look-at distance) or positive and "
                      "finite", c->focus_distance);
    if (!v3_normalize(v3_sub(c->position, c->look_at), &w))
        return refuse(msg, size, RAY_EINVAL, "camera position and look_at "
                      "coincide (or are too close to give a direction)");
    if (!up_usable(c->up, w))
        return refuse(msg, size, RAY_EINVAL, "camera up (%g, %g, %g) is "
                      "zero or within 3.6e-15 rad of the view axis: it "
                      "gives no roll", c->up.x, c->up.y, c->up.z);
    return RAY_OK;
}

void ray__render_defaults(const ray_render_options *o, const ray_camera *c,
                          ray_render_options *oo, ray_camera *co)
{
    *oo = *o;
    *co = *c;
    if (oo->samples == 0)
        oo->samples = 1;
    if (oo->adaptive_depth == 0)
        oo->adaptive_depth = 2;
    if (co->up.x == 0 && co->up.y == 0 && co->up.z == 0)
        co->up = v3(0, 1, 0);
    if (co->vfov == 0)
        co->vfov = 60;
}

/* The options' fields, in the order ray_render_options declares them. */
static int options_check(const ray_render_options *o, char *msg,
                         size_t size)
{
    unsigned y1 = o->y1 ? o->y1 : o->height;

    if (o->width == 0 || o->height == 0)
        return refuse(msg, size, RAY_EINVAL, "options width %u, height %u: "
                      "neither may be 0", o->width, o->height);
    if (o->width > (size_t)-1 / 3 / sizeof(float) / o->height)
        return refuse(msg, size, RAY_EINVAL, "options width %u x height "
                      "%u: the image's size overflows size_t", o->width,
                      o->height);
    if (y1 > o->height)
        return refuse(msg, size, RAY_EINVAL, "options y1 %u is beyond the "
                      "frame's height %u", o->y1, o->height);
    if (o->y0 >= y1)
        return refuse(msg, size, RAY_EINVAL, "options y0 %u is not below "
                      "y1 %u (y1 0 means the height): no rows", o->y0, y1);
    if (o->samples > RAY_MAX_PIXEL_SAMPLES)
        return refuse(msg, size, RAY_EINVAL, "options samples %u: must be "
                      "0 (1) .. RAY_MAX_PIXEL_SAMPLES (%u), also with "
                      "adaptive antialiasing", o->samples,
                      RAY_MAX_PIXEL_SAMPLES);
    if (!(o->adaptive_threshold >= 0))
        return refuse(msg, size, RAY_EINVAL, "options adaptive_threshold "
                      "%g: must be 0 (off) or positive",
                      o->adaptive_threshold);
    if (o->adaptive_threshold > 0 && o->adaptive_depth > 8)
        return refuse(msg, size, RAY_EINVAL, "options adaptive_depth %u: "
                      "must be 0 (2) .. 8 when adaptive_threshold is set",
                      o->adaptive_depth);
    if (o->photons > RAY_MAX_PHOTONS)
        return refuse(msg, size, RAY_EINVAL, "options photons %llu: above "
                      "RAY_MAX_PHOTONS (%llu)", o->photons, RAY_MAX_PHOTONS);
    if (!ray__photon_radius_valid(o->photon_radius))
        return refuse(msg, size, RAY_EINVAL, "options photon_radius %g: "
                      "must be 0 (automatic) or positive, with pi r^2 "
                      "neither under- nor overflowing", o->photon_radius);
    return RAY_OK;
}

/* Append "; " (after an earlier warning) and the formatted warning to
** msg, which holds a NUL-terminated prefix: truncated at size as refuse()
** truncates, msg NULL or size 0 written nothing. */
static void warn(char *msg, size_t size, const char *fmt, ...)
    RAY__PRINTF(3, 4);

static void warn(char *msg, size_t size, const char *fmt, ...)
{
    va_list ap;
    size_t used;

    if (msg == NULL || size == 0)
        return;
    used = strlen(msg);
    if (used + 1 >= size)
        return;                  /* full: keep what was written */
    if (used == 0) {
        snprintf(msg, size, "ray_render: warning: ");
    } else {
        snprintf(msg + used, size - used, "; ");
    }
    used = strlen(msg);
    if (used + 1 >= size)
        return;
    va_start(ap, fmt);
    vsnprintf(msg + used, size - used, fmt, ap);
    va_end(ap);
}

static int rgb_black(ray_rgb c)
{
    return c.r == 0 && c.g == 0 && c.b == 0;
}

/* Whether any light of s gives light: a light of intensity 0 (every
** channel) adds nothing to any material, so it counts as none.  The
** colours are checked finite and >= 0 where they are set. */
static int lit(const ray_scene *s)
{
    size_t i;

    for (i = 0; i < s->n_lights; i++)
        if (!rgb_black(s->lights[i].desc.intensity))
            return 1;
    return 0;
}

/* Whether s has geometry a camera ray can hit: enabled, not removed, a
** mask other than 0 (which hides it from every query).  An instance
** counts as geometry without a look into its child: cheap, and a
** warning must never be wrong the other way (an empty child only
** costs a warning not given). */
static int has_geometry(const ray_scene *s)
{
    size_t i;

    for (i = 0; i < s->n_prims; i++) {
        const ray__prim *p = &s->prims[i];
        if (p->enabled && !p->removed && p->mask != 0)
            return 1;
    }
    return 0;
}

/* The warnings of an accepted scene and camera (c with its defaults
** given), as RAY_RENDER_WARN_* bits, each also named in msg. */
static unsigned warnings_of(const ray_scene *s, const ray_camera *c,
                            char *msg, size_t size)
{
    unsigned w = 0;

    if (!lit(s) && rgb_black(s->ambient)) {
        w |= RAY_RENDER_WARN_UNLIT;
        warn(msg, size, "no light of non-zero intensity and a black "
             "ambient: every surface the lights shade renders black "
             "(ray_scene_add_light, ray_scene_set_ambient)");
    }
    if (s->background_fn == NULL && rgb_black(s->background) &&
        !has_geometry(s)) {
        w |= RAY_RENDER_WARN_EMPTY;
        warn(msg, size, "no geometry a camera ray can hit and a black "
             "background: every pixel is the background");
    }
    if (ray__solid_holds(s, c->position)) {
        w |= RAY_RENDER_WARN_EYE_INSIDE;
        warn(msg, size, "the camera position (%g, %g, %g) is inside a "
             "solid (a sphere, box, capsule or closed mesh) or on its "
             "surface: every camera ray starts inside it",
             c->position.x, c->position.y, c->position.z);
    }
    return w;
}

int ray_render_check(const ray_scene *scene, const ray_camera *camera,
                     const ray_render_options *options, unsigned *warnings,
                     char *msg, size_t size)
{
    ray_render_options o;
    ray_camera c;
    int rc;

    if (msg != NULL && size > 0)
        msg[0] = '\0';
    if (scene == NULL || camera == NULL || options == NULL)
        return refuse(msg, size, RAY_EINVAL, "%s is NULL",
                      scene == NULL    ? "scene"
                      : camera == NULL ? "camera"
                                       : "options");
    if (!scene->committed)
        return refuse(msg, size, RAY_ESTATE, "the scene is not committed "
                      "(never, or changed since): call ray_scene_commit");
    if (ray__scene_stale(scene))
        return refuse(msg, size, RAY_ESTATE, "a scene it instances changed "
                      "since its commit: commit this scene after it");
    ray__render_defaults(options, camera, &o, &c);
    rc = options_check(&o, msg, size);
    if (rc == RAY_OK)
        rc = camera_check(&c, msg, size);
    /* Written on RAY_OK only, as every output (ray.h, errors); without
    ** "warnings" none is looked for and msg stays "". */
    if (rc == RAY_OK && warnings != NULL)
        *warnings = warnings_of(scene, &c, msg, size);
    return rc;
}
