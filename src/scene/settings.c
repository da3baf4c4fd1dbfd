/* SPDX-License-Identifier: MIT */
/*
** settings.c -- what a scene holds besides its geometry: materials,
** lights, the background and ambient light, the ray tree's limits (the
** naive mode, no_pruning, among them) and the benchmark knobs (the
** watertight test, build threads).
*/

#include "core/sampling.h"
#include "scene/scene.h"

int ray_scene_add_material(ray_scene *s, const ray_material *m,
                           unsigned *id)
{
    const unsigned known = RAY_EFFECT_REFLECTION | RAY_EFFECT_REFRACTION |
                           RAY_EFFECT_SHADOW | RAY_EFFECT_TEXTURE |
                           RAY_EFFECT_CAUSTICS | RAY_EFFECT_SCATTER;
    void *p;
    int rc = ray__begin(s, "ray_scene_add_material");

    if (rc != RAY_OK)
        return rc;
    if (m == NULL)
        return ray__fail(s, RAY_EINVAL, "material is NULL");
    if (m->shade == NULL)
        return ray__fail(s, RAY_EINVAL, "shade function is NULL");
    if ((m->effects & ~known) != 0)
        return ray__fail(s, RAY_EINVAL, "unknown effect bits 0x%x (known: "
                         "RAY_EFFECT_* = 0x%x)", m->effects & ~known, known);
    if ((m->effects & RAY_EFFECT_SCATTER) && m->scatter == NULL)
        return ray__fail(s, RAY_EINVAL, "RAY_EFFECT_SCATTER without a "
                         "scatter function");
    if (s->n_materials >= RAY_INVALID_ID)
        return ray__fail(s, RAY_ENOMEM, "too many materials (%zu: ids are "
                         "32-bit)", s->n_materials);
    p = ray__grow(s, s->materials, &s->cap_materials, s->n_materials,
             sizeof *s->materials);
    if (p == NULL)
        return ray__fail(s, RAY_ENOMEM, "out of memory (material %zu)",
                         s->n_materials);
    s->materials = p;
    s->materials[s->n_materials] = *m;
    /* Read only with the bit (ray.h): code that fills a material field
    ** by field and predates "scatter" leaves garbage there. */
    if (!(m->effects & RAY_EFFECT_SCATTER))
        s->materials[s->n_materials].scatter = NULL;
    if (id != NULL)
        *id = (unsigned)s->n_materials;
    s->n_materials++;
    ray__touch(s, 0);
    return RAY_OK;
}

static int rgb_valid(ray_rgb c)
{
    return c.r >= 0 && c.r < HUGE_VAL && c.g >= 0 && c.g < HUGE_VAL &&
           c.b >= 0 && c.b < HUGE_VAL;
}

/* A light's point (position) must be finite: RAY_OK or the failure. */
static int light_position(ray_scene *s, const ray_light *l)
{
    if (v3_isfinite(l->position))
        return RAY_OK;
    return ray__fail(s, RAY_EINVAL, "position " RAY__V3FMT " is not finite",
                     RAY__V3ARGS(l->position));
}

/* The geometry of each kind of light, and *axis, the unit vector of
** ray__light (zero for the kinds without one). */
static int light_shape(ray_scene *s, const ray_light *l, ray_vec3 *axis)
{
    *axis = v3(0, 0, 0);
    switch (l->kind) {
    case RAY_LIGHT_POINT:
        return light_position(s, l);
    case RAY_LIGHT_DIRECTIONAL:
        if (v3_isfinite(l->direction) &&
            v3_normalize(v3_scale(l->direction, -1.0), axis))
            return RAY_OK;
        return ray__fail(s, RAY_EINVAL, "direction " RAY__V3FMT " is not "
                         "finite, or too short to normalise",
                         RAY__V3ARGS(l->direction));
    case RAY_LIGHT_SPHERE:
        if (!(l->radius > 0 && l->radius < HUGE_VAL))
            return ray__fail(s, RAY_EINVAL, "sphere light radius %g is not "
                             "positive and finite", l->radius);
        return light_position(s, l);
    case RAY_LIGHT_RECT:
        if (!v3_isfinite(l->edge1) || !v3_isfinite(l->edge2) ||
            !v3_normalize(v3_cross(l->edge1, l->edge2), axis))
            return ray__fail(s, RAY_EINVAL, "edges " RAY__V3FMT " and "
                             RAY__V3FMT " are parallel, too short or not "
                             "finite",
                             RAY__V3ARGS(l->edge1), RAY__V3ARGS(l->edge2));
        return light_position(s, l);
    default:
        return ray__fail(s, RAY_EINVAL, "unknown kind %d (not a "
                         "RAY_LIGHT_*)", l->kind);
    }
}

static int v3_is_zero(ray_vec3 v)
{
    return v.x == 0 && v.y == 0 && v.z == 0;
}

/* *in with its zeros read as their defaults (ray.h): those of
** ray_light_init, the one place they are written, for a zero direction,
** radius or edge, which were no light at all; the intensity is left. */
static ray_light light_defaults(const ray_light *in)
{
    ray_light l = *in, d;

    ray_light_init(&d, in->kind);
    if (v3_is_zero(l.direction))
        l.direction = d.direction;
    if (l.radius == 0)
        l.radius = d.radius;
    if (v3_is_zero(l.edge1))
        l.edge1 = d.edge1;
    if (v3_is_zero(l.edge2))
        l.edge2 = d.edge2;
    return l;
}

int ray_scene_add_light(ray_scene *s, const ray_light *light_in,
                        unsigned *id)
{
    void *p;
    ray_vec3 axis;
    ray_light lit;
    const ray_light *light = &lit;
    int rc = ray__begin(s, "ray_scene_add_light");

    if (rc != RAY_OK)
        return rc;
    if (light_in == NULL)
        return ray__fail(s, RAY_EINVAL, "light is NULL");
    lit = light_defaults(light_in);
    if (!rgb_valid(light->intensity))
        return ray__fail(s, RAY_EINVAL, "intensity (%g, %g, %g) is negative "
                         "or not finite", light->intensity.r,
                         light->intensity.g, light->intensity.b);
    rc = light_shape(s, light, &axis);
    if (rc != RAY_OK)
        return rc;
    if (light->samples > RAY_MAX_LIGHT_SAMPLES)
        return ray__fail(s, RAY_EINVAL, "samples %u is more than "
                         "RAY_MAX_LIGHT_SAMPLES (%u)", light->samples,
                         RAY_MAX_LIGHT_SAMPLES);
    if (s->n_lights >= RAY_INVALID_ID)
        return ray__fail(s, RAY_ENOMEM, "too many lights (%zu: ids are "
                         "32-bit)", s->n_lights);
    p = ray__grow(s, s->lights, &s->cap_lights, s->n_lights, sizeof *s->lights);
    if (p == NULL)
        return ray__fail(s, RAY_ENOMEM, "out of memory (light %zu)",
                         s->n_lights);
    s->lights = p;
    s->lights[s->n_lights].desc = *light;
    s->lights[s->n_lights].axis = axis;
    /* Area lights round their count up to a square k*k (16 when 0), so
    ** the samples can be stratified on a k x k grid (trace/light.c). */
    s->lights[s->n_lights].side =
        light->kind == RAY_LIGHT_POINT || light->kind == RAY_LIGHT_DIRECTIONAL
            ? 1
            : ray__strata_side(light->samples ? light->samples : 16);
    if (id != NULL)
        *id = (unsigned)s->n_lights;
    s->n_lights++;
    ray__touch(s, 0);
    return RAY_OK;
}

/* A colour setting: finite and not negative. */
static int rgb_check(ray_scene *s, const char *what, ray_rgb c)
{
    if (rgb_valid(c))
        return RAY_OK;
    return ray__fail(s, RAY_EINVAL, "%s (%g, %g, %g) is negative or not "
                     "finite", what, c.r, c.g, c.b);
}

int ray_scene_set_background(ray_scene *s, ray_rgb color,
                             ray_background_fn fn, void *ud)
{
    int rc = ray__begin(s, "ray_scene_set_background");

    if (rc != RAY_OK)
        return rc;
    rc = rgb_check(s, "colour", color);
    if (rc != RAY_OK)
        return rc;
    s->background = color;
    s->background_fn = fn;
    s->background_ud = ud;
    ray__touch(s, 0);
    return RAY_OK;
}

int ray_scene_set_ambient(ray_scene *s, ray_rgb ambient)
{
    int rc = ray__begin(s, "ray_scene_set_ambient");

    if (rc != RAY_OK)
        return rc;
    rc = rgb_check(s, "ambient light", ambient);
    if (rc != RAY_OK)
        return rc;
    s->ambient = ambient;
    ray__touch(s, 0);
    return RAY_OK;
}

int ray_scene_set_limits(ray_scene *s, const ray_limits *limits)
{
    int rc = ray__begin(s, "ray_scene_set_limits");

    if (rc != RAY_OK)
        return rc;
    if (limits == NULL) {
        s->limits.max_depth = RAY_DEFAULT_MAX_DEPTH;
        s->limits.min_weight = RAY_DEFAULT_MIN_WEIGHT;
        s->limits.max_fanout = RAY_DEFAULT_MAX_FANOUT;
        s->limits.no_pruning = 0;
        s->prune = 1;
        ray__touch(s, 0);
        return RAY_OK;
    }
    if (!(limits->min_weight >= 0 && limits->min_weight <= 1))
        return ray__fail(s, RAY_EINVAL, "min_weight %g is not in [0, 1]",
                         limits->min_weight);
    if (limits->max_depth > RAY_MAX_DEPTH)
        return ray__fail(s, RAY_EINVAL, "max_depth %u is more than "
                         "RAY_MAX_DEPTH (%u)", limits->max_depth,
                         RAY_MAX_DEPTH);
    s->limits = *limits;
    s->prune = limits->no_pruning == 0;
    ray__touch(s, 0);
    return RAY_OK;
}

int ray_scene_set_watertight(ray_scene *s, int enabled)
{
    int rc = ray__begin(s, "ray_scene_set_watertight");

    if (rc != RAY_OK)
        return rc;
    s->watertight = enabled != 0;
    ray__touch(s, 0);
    return RAY_OK;
}

/* A setting like the others: after a commit it is staged (ray__touch),
** though the commit that follows rebuilds nothing for it -- the tree is
** the same at every thread count; the next build uses it. */
int ray_scene_set_build_threads(ray_scene *s, unsigned threads)
{
    int rc = ray__begin(s, "ray_scene_set_build_threads");

    if (rc != RAY_OK)
        return rc;
    s->build_threads = threads;
    ray__touch(s, 0);
    return RAY_OK;
}

/* The program's scheduler, copied (NULL: the built-in threads); staged
** like the build threads: the next build and render use it. */
int ray_scene_set_scheduler(ray_scene *s, const ray_scheduler *scheduler)
{
    int rc = ray__begin(s, "ray_scene_set_scheduler");

    if (rc != RAY_OK)
        return rc;
    if (scheduler != NULL)
        s->scheduler = *scheduler;
    else
        memset(&s->scheduler, 0, sizeof s->scheduler);  /* built-in */
    ray__touch(s, 0);
    return RAY_OK;
}

/* The commit's progress callback (NULL: none); staged like the build
** threads, which it reports on. */
int ray_scene_set_progress(ray_scene *s, ray_progress_fn fn, void *ud)
{
    int rc = ray__begin(s, "ray_scene_set_progress");

    if (rc != RAY_OK)
        return rc;
    s->progress = fn;
    s->progress_ud = fn != NULL ? ud : NULL;
    ray__touch(s, 0);
    return RAY_OK;
}

unsigned ray_scene_effects(const ray_scene *s)
{
    return s != NULL && s->committed ? s->effects : 0u;
}

unsigned ray_scene_light_count(const ray_scene *s)
{
    return s == NULL ? 0 : (unsigned)s->n_lights;
}

void ray__scene_set_tri_mode(ray_scene *s, int mode)
{
    s->tri_mode = mode;
}

void ray__scene_set_filter_scale(ray_scene *s, double scale)
{
    s->filter_scale = scale;
}
