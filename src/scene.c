/*
** scene.c -- building a scene: geometry, materials, lights, settings,
** then commit.  Every add either completes or leaves the scene as it was.
*/
#include <stdlib.h>
#include <string.h>

#include "internal.h"

static void *libc_alloc(void *ud, void *ptr, size_t osize, size_t nsize)
{
    (void)ud;
    (void)osize;
    if (nsize == 0) {
        free(ptr);
        return NULL;
    }
    return realloc(ptr, nsize);
}

void *ray__alloc(const ray_scene *s, size_t size)
{
    return s->alloc(s->alloc_ud, NULL, 0, size);
}

void ray__free(const ray_scene *s, void *ptr, size_t size)
{
    if (ptr != NULL)
        s->alloc(s->alloc_ud, ptr, size, 0);
}

/*
** Make room for one more element of "elem" bytes in the array *items of
** *cap elements, doubling.  On failure nothing changes.
*/
static int grow(ray_scene *s, void **items, size_t *cap, size_t used,
                size_t elem)
{
    size_t ncap;
    void *p;

    if (used < *cap)
        return RAY_OK;
    ncap = *cap ? 2 * *cap : 8;
    if (ncap > (size_t)-1 / elem)
        return RAY_ENOMEM;
    p = s->alloc(s->alloc_ud, *items, *cap * elem, ncap * elem);
    if (p == NULL)
        return RAY_ENOMEM;
    *items = p;
    *cap = ncap;
    return RAY_OK;
}

int ray_scene_new(ray_scene **out, ray_alloc_fn alloc, void *alloc_ud)
{
    ray_scene *s;

    if (out == NULL)
        return RAY_EINVAL;
    if (alloc == NULL) {
        alloc = libc_alloc;
        alloc_ud = NULL;
    }
    s = alloc(alloc_ud, NULL, 0, sizeof *s);
    if (s == NULL)
        return RAY_ENOMEM;
    memset(s, 0, sizeof *s);
    s->alloc = alloc;
    s->alloc_ud = alloc_ud;
    s->limits.max_depth = RAY_DEFAULT_MAX_DEPTH;
    s->limits.min_weight = RAY_DEFAULT_MIN_WEIGHT;
    s->limits.max_fanout = RAY_DEFAULT_MAX_FANOUT;
    *out = s;
    return RAY_OK;
}

void ray_scene_free(ray_scene *s)
{
    if (s == NULL)
        return;
    ray__free(s, s->prims, s->cap_prims * sizeof *s->prims);
    ray__free(s, s->verts, s->cap_verts * sizeof *s->verts);
    ray__free(s, s->materials, s->cap_materials * sizeof *s->materials);
    ray__free(s, s->lights, s->cap_lights * sizeof *s->lights);
    ray__free(s, s, sizeof *s);
}

/* RAY_OK if the scene may still be changed. */
static int editable(const ray_scene *s)
{
    if (s == NULL)
        return RAY_EINVAL;
    return s->committed ? RAY_ESTATE : RAY_OK;
}

int ray_scene_add_material(ray_scene *s, const ray_material *m,
                           unsigned *id)
{
    const unsigned known = RAY_EFFECT_REFLECTION | RAY_EFFECT_REFRACTION |
                           RAY_EFFECT_SHADOW;
    int rc = editable(s);

    if (rc != RAY_OK)
        return rc;
    if (m == NULL || m->shade == NULL || (m->effects & ~known) != 0)
        return RAY_EINVAL;
    if (s->n_materials >= RAY_INVALID_ID)
        return RAY_ENOMEM;
    rc = grow(s, (void **)&s->materials, &s->cap_materials, s->n_materials,
              sizeof *s->materials);
    if (rc != RAY_OK)
        return rc;
    s->materials[s->n_materials] = *m;
    if (id != NULL)
        *id = (unsigned)s->n_materials;
    s->n_materials++;
    return RAY_OK;
}

/* Append a primitive already validated. */
static int add_prim(ray_scene *s, const ray__prim *p, unsigned *geom_id)
{
    int rc;

    if (p->material >= s->n_materials)
        return RAY_EINVAL;
    if (s->n_prims >= RAY_INVALID_ID)
        return RAY_ENOMEM;
    rc = grow(s, (void **)&s->prims, &s->cap_prims, s->n_prims,
              sizeof *s->prims);
    if (rc != RAY_OK)
        return rc;
    s->prims[s->n_prims] = *p;
    if (geom_id != NULL)
        *geom_id = (unsigned)s->n_prims;
    s->n_prims++;
    return RAY_OK;
}

static ray__prim prim_of(int kind, unsigned material)
{
    ray__prim p;

    memset(&p, 0, sizeof p);
    p.kind = kind;
    p.material = material;
    return p;
}

int ray_scene_add_sphere(ray_scene *s, ray_vec3 center, double radius,
                         unsigned material, unsigned *geom_id)
{
    ray__prim p = prim_of(PRIM_SPHERE, material);
    int rc = editable(s);

    if (rc != RAY_OK)
        return rc;
    if (!v3_isfinite(center) || !(radius > 0 && radius < HUGE_VAL))
        return RAY_EINVAL;
    p.a = center;
    p.radius = radius;
    return add_prim(s, &p, geom_id);
}

int ray_scene_add_plane(ray_scene *s, ray_vec3 point, ray_vec3 normal,
                        unsigned material, unsigned *geom_id)
{
    ray__prim p = prim_of(PRIM_PLANE, material);
    int rc = editable(s);

    if (rc != RAY_OK)
        return rc;
    if (!v3_isfinite(point) || !v3_isfinite(normal) ||
        !v3_normalize(normal, &p.b))
        return RAY_EINVAL;
    p.a = point;
    return add_prim(s, &p, geom_id);
}

int ray_scene_add_triangle(ray_scene *s, ray_vec3 a, ray_vec3 b, ray_vec3 c,
                           unsigned material, unsigned *geom_id)
{
    ray__prim p = prim_of(PRIM_TRIANGLE, material);
    ray_vec3 n;
    int rc = editable(s);

    if (rc != RAY_OK)
        return rc;
    if (!v3_isfinite(a) || !v3_isfinite(b) || !v3_isfinite(c))
        return RAY_EINVAL;
    if (!v3_normalize(v3_cross(v3_sub(b, a), v3_sub(c, a)), &n))
        return RAY_EDEGENERATE;
    p.a = a;
    p.b = b;
    p.c = c;
    return add_prim(s, &p, geom_id);
}

int ray_scene_add_polygon(ray_scene *s, const ray_vec3 *v, size_t n,
                          unsigned material, unsigned *geom_id)
{
    ray__prim p = prim_of(PRIM_POLYGON, material);
    ray_vec3 area = v3(0, 0, 0), unit;
    size_t i;
    int rc = editable(s);

    if (rc != RAY_OK)
        return rc;
    if (v == NULL || n < 3)
        return RAY_EINVAL;
    for (i = 0; i < n; i++) {
        if (!v3_isfinite(v[i]))
            return RAY_EINVAL;
        area = v3_add(area, v3_cross(v3_sub(v[i], v[0]),
                                     v3_sub(v[(i + 1) % n], v[0])));
    }
    if (!v3_normalize(area, &unit))
        return RAY_EDEGENERATE;
    if (material >= s->n_materials)
        return RAY_EINVAL;
    if (n > (size_t)-1 / 2 - s->n_verts)
        return RAY_ENOMEM;
    while (s->cap_verts < s->n_verts + n) {
        rc = grow(s, (void **)&s->verts, &s->cap_verts, s->cap_verts,
                  sizeof *s->verts);
        if (rc != RAY_OK)
            return rc;
    }
    p.first = s->n_verts;
    p.count = n;
    rc = add_prim(s, &p, geom_id);
    if (rc != RAY_OK)
        return rc;
    memcpy(s->verts + s->n_verts, v, n * sizeof *v);
    s->n_verts += n;
    return RAY_OK;
}

/* Light validation: every kind needs a finite, non-negative intensity. */
static int light_valid(const ray_light *l)
{
    ray_vec3 e;

    if (!(l->intensity.r >= 0 && l->intensity.r < HUGE_VAL &&
          l->intensity.g >= 0 && l->intensity.g < HUGE_VAL &&
          l->intensity.b >= 0 && l->intensity.b < HUGE_VAL))
        return 0;
    switch (l->kind) {
    case RAY_LIGHT_POINT:
        return v3_isfinite(l->position);
    case RAY_LIGHT_DIRECTIONAL:
        return v3_isfinite(l->direction) && v3_normalize(l->direction, &e);
    case RAY_LIGHT_SPHERE:
        return v3_isfinite(l->position) &&
               l->radius > 0 && l->radius < HUGE_VAL;
    case RAY_LIGHT_RECT:
        return v3_isfinite(l->position) && v3_isfinite(l->edge1) &&
               v3_isfinite(l->edge2) &&
               v3_normalize(v3_cross(l->edge1, l->edge2), &e);
    default:
        return 0;
    }
}

int ray_scene_add_light(ray_scene *s, const ray_light *light, unsigned *id)
{
    int rc = editable(s);

    if (rc != RAY_OK)
        return rc;
    if (light == NULL || !light_valid(light) ||
        light->samples > RAY_MAX_LIGHT_SAMPLES)
        return RAY_EINVAL;
    if (s->n_lights >= RAY_INVALID_ID)
        return RAY_ENOMEM;
    rc = grow(s, (void **)&s->lights, &s->cap_lights, s->n_lights,
              sizeof *s->lights);
    if (rc != RAY_OK)
        return rc;
    s->lights[s->n_lights] = *light;
    if (id != NULL)
        *id = (unsigned)s->n_lights;
    s->n_lights++;
    return RAY_OK;
}

static int rgb_valid(ray_rgb c)
{
    return c.r >= 0 && c.r < HUGE_VAL && c.g >= 0 && c.g < HUGE_VAL &&
           c.b >= 0 && c.b < HUGE_VAL;
}

int ray_scene_set_background(ray_scene *s, ray_rgb color)
{
    int rc = editable(s);

    if (rc != RAY_OK)
        return rc;
    if (!rgb_valid(color))
        return RAY_EINVAL;
    s->background = color;
    return RAY_OK;
}

int ray_scene_set_background_fn(ray_scene *s, ray_background_fn fn,
                                void *ud)
{
    int rc = editable(s);

    if (rc != RAY_OK)
        return rc;
    s->background_fn = fn;
    s->background_ud = ud;
    return RAY_OK;
}

int ray_scene_set_ambient(ray_scene *s, ray_rgb ambient)
{
    int rc = editable(s);

    if (rc != RAY_OK)
        return rc;
    if (!rgb_valid(ambient))
        return RAY_EINVAL;
    s->ambient = ambient;
    return RAY_OK;
}

int ray_scene_set_limits(ray_scene *s, const ray_limits *limits)
{
    int rc = editable(s);

    if (rc != RAY_OK)
        return rc;
    if (limits == NULL) {
        s->limits.max_depth = RAY_DEFAULT_MAX_DEPTH;
        s->limits.min_weight = RAY_DEFAULT_MIN_WEIGHT;
        s->limits.max_fanout = RAY_DEFAULT_MAX_FANOUT;
        return RAY_OK;
    }
    if (!(limits->min_weight >= 0 && limits->min_weight <= 1) ||
        limits->max_depth > RAY_MAX_DEPTH)
        return RAY_EINVAL;
    s->limits = *limits;
    return RAY_OK;
}

int ray_scene_commit(ray_scene *s)
{
    int rc = editable(s);

    if (rc != RAY_OK)
        return rc;
    s->committed = 1;
    return RAY_OK;
}

unsigned ray_scene_light_count(const ray_scene *s)
{
    return s == NULL ? 0 : (unsigned)s->n_lights;
}
