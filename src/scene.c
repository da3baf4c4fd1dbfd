/* SPDX-License-Identifier: MIT */
/*
** scene.c -- building a scene: geometry, materials, lights, settings,
** then commit.  Every add either completes or leaves the scene as it was.
*/
#include <stdlib.h>
#include <string.h>

#include "scene.h"

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
    return ray__allocate(&s->alloc, size);
}

void ray__free(const ray_scene *s, void *ptr, size_t size)
{
    ray__release(&s->alloc, ptr, size);
}

void *ray__realloc(const ray_scene *s, void *ptr, size_t osize, size_t nsize)
{
    return ray__reallocate(&s->alloc, ptr, osize, nsize);
}

/*
** The array "items" of *cap elements of "elem" bytes, with room for one
** more than "used": itself, or a copy twice as large (*cap updated).  NULL
** when that allocation fails, with items and *cap unchanged.
*/
void *ray__grow(ray_scene *s, void *items, size_t *cap, size_t used,
                size_t elem)
{
    size_t ncap;
    void *p;

    if (used < *cap)
        return items;
    ncap = *cap ? 2 * *cap : 8;
    if (ncap > (size_t)-1 / elem)
        return NULL;
    p = ray__reallocate(&s->alloc, items, *cap * elem, ncap * elem);
    if (p != NULL)
        *cap = ncap;
    return p;
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
    s->alloc.fn = alloc;
    s->alloc.ud = alloc_ud;
    s->limits.max_depth = RAY_DEFAULT_MAX_DEPTH;
    s->limits.min_weight = RAY_DEFAULT_MIN_WEIGHT;
    s->limits.max_fanout = RAY_DEFAULT_MAX_FANOUT;
    s->prune = 1;
    s->watertight = 1;
    s->build_threads = 1;
    s->dirty = RAY__DIRTY_ALL;
    *out = s;
    return RAY_OK;
}

void ray__mesh_release(const ray_scene *s, ray__mesh *m)
{
    /* The scene's own copies: freed through a cast, as allocated. */
    ray__free(s, m->uv_scale, m->n_tris * sizeof *m->uv_scale);
    m->uv_scale = NULL;
    if (!m->borrowed) {
        ray__free(s, ray__unconst(m->indices),
                  3 * m->n_tris * sizeof *m->indices);
        ray__free(s, ray__unconst(m->normals),
                  m->n_vertices * sizeof *m->normals);
        ray__free(s, ray__unconst(m->texcoords),
                  2 * m->n_vertices * sizeof *m->texcoords);
    }
    m->borrowed = 0;
    m->indices = NULL;
    m->normals = NULL;
    m->texcoords = NULL;
}

void ray_scene_free(ray_scene *s)
{
    size_t i;

    if (s == NULL)
        return;
    for (i = 0; i < s->n_meshes; i++)
        ray__mesh_release(s, &s->meshes[i]);
    ray__free(s, s->meshes, s->cap_meshes * sizeof *s->meshes);
    ray__free(s, s->surfaces, s->cap_surfaces * sizeof *s->surfaces);
    ray__free(s, s->instances, s->cap_instances * sizeof *s->instances);
    ray__free(s, s->tris, s->cap_tris * sizeof *s->tris);
    ray__free(s, s->tri_ids, s->cap_tri_ids * sizeof *s->tri_ids);
    ray__bvh_free(&s->alloc, &s->tri_bvh);
    ray__bvh_free(&s->alloc, &s->prim_bvh);
    ray__free(s, s->planes, s->n_planes * sizeof *s->planes);
    ray__free(s, s->prims, s->cap_prims * sizeof *s->prims);
    ray__free(s, s->verts, s->cap_verts * sizeof *s->verts);
    ray__free(s, s->materials, s->cap_materials * sizeof *s->materials);
    ray__free(s, s->lights, s->cap_lights * sizeof *s->lights);
    ray__free(s, s, sizeof *s);
}

int ray__material_known(ray_scene *s, unsigned material)
{
    if (material < s->n_materials || material == RAY_NO_MATERIAL)
        return RAY_OK;
    return ray__fail(s, RAY_EINVAL, "material %u does not exist (the scene "
                     "has %zu)", material, s->n_materials);
}

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

/* Append a primitive already validated. */
int ray__add_prim(ray_scene *s, const ray__prim *prim, unsigned *geom_id)
{
    void *p;
    int rc = ray__material_known(s, prim->material);

    if (rc != RAY_OK)
        return rc;
    if (s->n_prims >= RAY_INVALID_ID)
        return ray__fail(s, RAY_ENOMEM, "too many geometries (%zu: ids are "
                         "32-bit)", s->n_prims);
    p = ray__grow(s, s->prims, &s->cap_prims, s->n_prims, sizeof *s->prims);
    if (p == NULL)
        return ray__fail(s, RAY_ENOMEM, "out of memory (geometry %zu)",
                         s->n_prims);
    s->prims = p;
    s->prims[s->n_prims] = *prim;
    s->prims[s->n_prims].mask = ~0u;
    s->prims[s->n_prims].enabled = 1;
    if (geom_id != NULL)
        *geom_id = (unsigned)s->n_prims;
    s->n_prims++;
    ray__touch(s, ray__dirty_of(prim));
    return RAY_OK;
}

static ray__prim prim_of(ray__kind kind, unsigned material)
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
    ray__prim p = prim_of(RAY__KIND_SPHERE, material);
    int rc = ray__begin(s, "ray_scene_add_sphere");

    if (rc != RAY_OK)
        return rc;
    if (!v3_isfinite(center))
        return ray__fail(s, RAY_EINVAL, "center " RAY__V3FMT " is not "
                         "finite", RAY__V3ARGS(center));
    if (!(radius > 0 && radius < HUGE_VAL))
        return ray__fail(s, RAY_EINVAL, "radius %g is not positive and "
                         "finite", radius);
    p.a = center;
    p.radius = radius;
    return ray__add_prim(s, &p, geom_id);
}

int ray_scene_add_plane(ray_scene *s, ray_vec3 point, ray_vec3 normal,
                        unsigned material, unsigned *geom_id)
{
    ray__prim p = prim_of(RAY__KIND_PLANE, material);
    int rc = ray__begin(s, "ray_scene_add_plane");

    if (rc != RAY_OK)
        return rc;
    if (!v3_isfinite(point))
        return ray__fail(s, RAY_EINVAL, "point " RAY__V3FMT " is not "
                         "finite", RAY__V3ARGS(point));
    /* A finite normal fails to normalise only when it is zero. */
    if (!v3_isfinite(normal) || !v3_normalize(normal, &p.b))
        return ray__fail(s, RAY_EINVAL, "normal " RAY__V3FMT " is zero or "
                         "not finite", RAY__V3ARGS(normal));
    p.a = point;
    return ray__add_prim(s, &p, geom_id);
}

int ray_scene_add_triangle(ray_scene *s, ray_vec3 a, ray_vec3 b, ray_vec3 c,
                           unsigned material, unsigned *geom_id)
{
    ray__prim p = prim_of(RAY__KIND_TRIANGLE, material);
    ray_vec3 n, v[3];
    int rc = ray__begin(s, "ray_scene_add_triangle"), k;

    if (rc != RAY_OK)
        return rc;
    v[0] = a;
    v[1] = b;
    v[2] = c;
    for (k = 0; k < 3; k++)
        if (!v3_isfinite(v[k]))
            return ray__fail(s, RAY_EINVAL, "vertex %c " RAY__V3FMT " is "
                             "not finite", "abc"[k], RAY__V3ARGS(v[k]));
    if (!v3_normalize(v3_cross(v3_sub(b, a), v3_sub(c, a)), &n))
        return ray__fail(s, RAY_EDEGENERATE, "zero area: vertices "
                         RAY__V3FMT ", " RAY__V3FMT ", " RAY__V3FMT " are "
                         "collinear", RAY__V3ARGS(a), RAY__V3ARGS(b),
                         RAY__V3ARGS(c));
    rc = ray__material_known(s, material);
    if (rc != RAY_OK)
        return rc;
    rc = ray__reserve_tris(s, 1);
    if (rc != RAY_OK)
        return rc;
    p.a = a;
    p.b = b;
    p.c = c;
    p.first = s->n_tris;
    p.count = 1;
    rc = ray__add_prim(s, &p, geom_id);
    if (rc != RAY_OK)
        return rc;
    s->tris[s->n_tris].a = a;
    s->tris[s->n_tris].b = b;
    s->tris[s->n_tris].c = c;
    s->tri_ids[s->n_tris].geom_id = (unsigned)(s->n_prims - 1);
    s->tri_ids[s->n_tris].prim_id = 0;
    s->n_tris++;
    return RAY_OK;
}

/*
** Room for "more" triangles in the parallel arrays tris and tri_ids, each
** with its own capacity, so a failure growing the second leaves the first
** merely larger: the scene is unchanged.
*/
int ray__reserve_tris(ray_scene *s, size_t more)
{
    size_t need;
    void *p;

    if (more > 0x7fffffffu - s->n_tris)     /* ids and BVH items are 32-bit */
        return ray__fail(s, RAY_ENOMEM, "%zu + %zu triangles: more than "
                         "2^31 - 1 in a scene", s->n_tris, more);
    need = s->n_tris + more;
    while (s->cap_tris < need) {
        p = ray__grow(s, s->tris, &s->cap_tris, s->cap_tris, sizeof *s->tris);
        if (p == NULL)
            return ray__fail(s, RAY_ENOMEM, "out of memory (room for %zu "
                             "triangles)", need);
        s->tris = p;
    }
    while (s->cap_tri_ids < need) {
        p = ray__grow(s, s->tri_ids, &s->cap_tri_ids, s->cap_tri_ids,
                 sizeof *s->tri_ids);
        if (p == NULL)
            return ray__fail(s, RAY_ENOMEM, "out of memory (room for %zu "
                             "triangles)", need);
        s->tri_ids = p;
    }
    return RAY_OK;
}

int ray__reserve_verts(ray_scene *s, size_t more)
{
    void *grown;

    if (more > (size_t)-1 / 2 - s->n_verts)
        return ray__fail(s, RAY_ENOMEM, "%zu + %zu vertices overflow "
                         "size_t", s->n_verts, more);
    while (s->cap_verts < s->n_verts + more) {
        grown = ray__grow(s, s->verts, &s->cap_verts, s->cap_verts,
                          sizeof *s->verts);
        if (grown == NULL)
            return ray__fail(s, RAY_ENOMEM, "out of memory (room for %zu "
                             "vertices)", s->n_verts + more);
        s->verts = grown;
    }
    return RAY_OK;
}

int ray_scene_add_polygon(ray_scene *s, const ray_vec3 *v, size_t n,
                          unsigned material, unsigned *geom_id)
{
    ray__prim p = prim_of(RAY__KIND_POLYGON, material);
    ray_vec3 area = v3(0, 0, 0), unit;
    size_t i;
    int rc = ray__begin(s, "ray_scene_add_polygon");

    if (rc != RAY_OK)
        return rc;
    if (v == NULL)
        return ray__fail(s, RAY_EINVAL, "vertex array is NULL");
    if (n < 3)
        return ray__fail(s, RAY_EINVAL, "%zu vertices: a polygon needs at "
                         "least 3", n);
    for (i = 0; i < n; i++) {
        if (!v3_isfinite(v[i]))
            return ray__fail(s, RAY_EINVAL, "vertex %zu " RAY__V3FMT " is "
                             "not finite", i, RAY__V3ARGS(v[i]));
        area = v3_add(area, v3_cross(v3_sub(v[i], v[0]),
                                     v3_sub(v[(i + 1) % n], v[0])));
    }
    if (!v3_normalize(area, &unit))
        return ray__fail(s, RAY_EDEGENERATE, "zero area: the %zu vertices "
                         "are collinear or the outline cancels itself", n);
    rc = ray__material_known(s, material);
    if (rc != RAY_OK)
        return rc;
    rc = ray__reserve_verts(s, n);
    if (rc != RAY_OK)
        return rc;
    p.first = s->n_verts;
    p.count = n;
    rc = ray__add_prim(s, &p, geom_id);
    if (rc != RAY_OK)
        return rc;
    memcpy(s->verts + s->n_verts, v, n * sizeof *v);
    s->n_verts += n;
    return RAY_OK;
}

/*
** The geometry record of a mesh whose triangles are tris[first ..
** first+count-1] (already reserved), with its shading data.  Both arrays
** are grown first, so a failure changes nothing.
*/
int ray__add_mesh_prim(ray_scene *s, unsigned material, size_t first,
                       size_t count, const ray__mesh *shading, unsigned *id)
{
    ray__prim p = prim_of(RAY__KIND_MESH, material);
    void *grown;
    int rc;

    grown = ray__grow(s, s->meshes, &s->cap_meshes, s->n_meshes,
                 sizeof *s->meshes);
    if (grown == NULL)
        return ray__fail(s, RAY_ENOMEM, "out of memory (mesh %zu)",
                         s->n_meshes);
    s->meshes = grown;
    p.first = first;
    p.count = count;
    p.mesh = (unsigned)s->n_meshes;
    rc = ray__add_prim(s, &p, id);
    if (rc != RAY_OK)
        return rc;
    s->meshes[s->n_meshes++] = *shading;
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
        return ray__fail(s, RAY_EINVAL, "direction " RAY__V3FMT " is zero "
                         "or not finite", RAY__V3ARGS(l->direction));
    case RAY_LIGHT_SPHERE:
        if (!(l->radius > 0 && l->radius < HUGE_VAL))
            return ray__fail(s, RAY_EINVAL, "sphere light radius %g is not "
                             "positive and finite", l->radius);
        return light_position(s, l);
    case RAY_LIGHT_RECT:
        if (!v3_isfinite(l->edge1) || !v3_isfinite(l->edge2) ||
            !v3_normalize(v3_cross(l->edge1, l->edge2), axis))
            return ray__fail(s, RAY_EINVAL, "edges " RAY__V3FMT " and "
                             RAY__V3FMT " are parallel, zero or not finite",
                             RAY__V3ARGS(l->edge1), RAY__V3ARGS(l->edge2));
        return light_position(s, l);
    default:
        return ray__fail(s, RAY_EINVAL, "unknown kind %d (not a "
                         "RAY_LIGHT_*)", l->kind);
    }
}

int ray_scene_add_light(ray_scene *s, const ray_light *light, unsigned *id)
{
    void *p;
    ray_vec3 axis;
    int rc = ray__begin(s, "ray_scene_add_light");

    if (rc != RAY_OK)
        return rc;
    if (light == NULL)
        return ray__fail(s, RAY_EINVAL, "light is NULL");
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

int ray_scene_set_background(ray_scene *s, ray_rgb color)
{
    int rc = ray__begin(s, "ray_scene_set_background");

    if (rc != RAY_OK)
        return rc;
    rc = rgb_check(s, "colour", color);
    if (rc != RAY_OK)
        return rc;
    s->background = color;
    ray__touch(s, 0);
    return RAY_OK;
}

int ray_scene_set_background_fn(ray_scene *s, ray_background_fn fn,
                                void *ud)
{
    int rc = ray__begin(s, "ray_scene_set_background_fn");

    if (rc != RAY_OK)
        return rc;
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
    ray__touch(s, 0);
    return RAY_OK;
}

/* The smaller and larger of two, of three finite numbers (no libm call:
** the NaN rules of fmin are not needed here, vertices are finite). */
static double min2(double a, double b)
{
    return a < b ? a : b;
}

static double max2(double a, double b)
{
    return a > b ? a : b;
}

static double min3(double a, double b, double c)
{
    return min2(min2(a, b), c);
}

static double max3(double a, double b, double c)
{
    return max2(max2(a, b), c);
}

/*
** The BVHs' cost settings (bvh.c).  Triangles: a split costs 1.5 triangle
** tests, and four triangles or fewer always make a leaf, since a wide node
** tests all its boxes at once, whatever their number, and so costs more
** than the binary SAH prices a split: bench/mesh measured the same ray
** throughput on the bunny for traversal costs 1.0 to 2.0 and leaves of 1
** to 4, and 1.5 with 4 builds fastest and takes least memory (103 bytes
** per triangle on the 59k bunny against 126 for 1.0 with 1).  Other
** primitives: a curved surface's test costs up to thousands of box tests,
** so every split the SAH finds is taken, down to single primitives.
*/
static const ray__bvh_costs tri_costs = {1.5f, 4};
static const ray__bvh_costs prim_costs = {1.0f, 1};

/*
** The float box of triangles first .. first + n - 1 (a leaf's), rounded
** outward once from their double bounds: the same box as the union of
** their own rounded boxes (rounding outward is monotonic), at a quarter
** of the roundings for the refit's four-triangle leaves.
*/
static void tris_box(const void *ud, size_t first, size_t n, float lo[3],
                     float hi[3])
{
    const ray__tri *t = &((const ray_scene *)ud)->tris[first];
    ray_vec3 a = t->a, b = t->a;
    size_t i;

    for (i = 0; i < n; i++, t++) {
        a.x = min2(a.x, min3(t->a.x, t->b.x, t->c.x));
        a.y = min2(a.y, min3(t->a.y, t->b.y, t->c.y));
        a.z = min2(a.z, min3(t->a.z, t->b.z, t->c.z));
        b.x = max2(b.x, max3(t->a.x, t->b.x, t->c.x));
        b.y = max2(b.y, max3(t->a.y, t->b.y, t->c.y));
        b.z = max2(b.z, max3(t->a.z, t->b.z, t->c.z));
    }
    lo[0] = ray__float_down(a.x);
    lo[1] = ray__float_down(a.y);
    lo[2] = ray__float_down(a.z);
    hi[0] = ray__float_up(b.x);
    hi[1] = ray__float_up(b.y);
    hi[2] = ray__float_up(b.z);
}

/* The float box of triangle i of the scene, rounded outward (the build's
** box callback, once a triangle): tris_box of one, without its loop (the
** min of a set that holds x is the min of x and the set, bit for bit). */
static void tri_box(const void *ud, size_t i, float lo[3], float hi[3])
{
    const ray__tri *t = &((const ray_scene *)ud)->tris[i];

    lo[0] = ray__float_down(min3(t->a.x, t->b.x, t->c.x));
    lo[1] = ray__float_down(min3(t->a.y, t->b.y, t->c.y));
    lo[2] = ray__float_down(min3(t->a.z, t->b.z, t->c.z));
    hi[0] = ray__float_up(max3(t->a.x, t->b.x, t->c.x));
    hi[1] = ray__float_up(max3(t->a.y, t->b.y, t->c.y));
    hi[2] = ray__float_up(max3(t->a.z, t->b.z, t->c.z));
}

/* Give back the spare capacity that doubling left in the triangle arrays
** (a failed shrink keeps the larger block: harmless). */
static void trim_tris(ray_scene *s)
{
    void *p;

    if (s->n_tris == 0)
        return;          /* a zero-size realloc frees: keep the blocks */
    if (s->cap_tris > s->n_tris) {
        p = ray__realloc(s, s->tris, s->cap_tris * sizeof *s->tris,
                         s->n_tris * sizeof *s->tris);
        if (p != NULL) {
            s->tris = p;
            s->cap_tris = s->n_tris;
        }
    }
    if (s->cap_tri_ids > s->n_tris) {
        p = ray__realloc(s, s->tri_ids, s->cap_tri_ids * sizeof *s->tri_ids,
                         s->n_tris * sizeof *s->tri_ids);
        if (p != NULL) {
            s->tri_ids = p;
            s->cap_tri_ids = s->n_tris;
        }
    }
}

/*
** Put tris[i] (and its ids) at position i of leaf order, i.e. apply the
** permutation items (item index of leaf position i) in place, walking its
** cycles; the top bit of items[] marks the positions already placed
** (indices are below 2^31).  The fallback of gather_tris (below).
*/
static void permute_tris(ray_scene *s, unsigned *items, size_t n)
{
    const unsigned done = 0x80000000u;
    size_t start;

    for (start = 0; start < n; start++) {
        ray__tri t;
        ray__tri_id id;
        size_t pos = start;
        if (items[start] & done)
            continue;
        t = s->tris[start];
        id = s->tri_ids[start];
        for (;;) {
            size_t src = items[pos];
            items[pos] |= done;
            if (src == start) {
                s->tris[pos] = t;
                s->tri_ids[pos] = id;
                break;
            }
            s->tris[pos] = s->tris[src];
            s->tri_ids[pos] = s->tri_ids[src];
            pos = src;
        }
    }
}

/* permute_tris for the ids alone. */
static void permute_ids(ray_scene *s, unsigned *items, size_t n)
{
    const unsigned done = 0x80000000u;
    size_t start;

    for (start = 0; start < n; start++) {
        ray__tri_id id;
        size_t pos = start;
        if (items[start] & done)
            continue;
        id = s->tri_ids[start];
        for (;;) {
            size_t src = items[pos];
            items[pos] |= done;
            if (src == start) {
                s->tri_ids[pos] = id;
                break;
            }
            s->tri_ids[pos] = s->tri_ids[src];
            pos = src;
        }
    }
}

/*
** The same permutation, gathered into new arrays (the triangles first,
** their old array freed before the ids' is made, so that at most one
** extra array is held): each read is random but none depends on another,
** where walking the cycles in place chases one random read after the
** other (at 940k triangles the walk took about a sixth of the commit,
** perf on bench/mesh's bunny-4).  Where memory is short for an array,
** that array is permuted in place instead: the same order.
*/
static void gather_tris(ray_scene *s, unsigned *items, size_t n)
{
    size_t i, all = s->n_tris;
    ray__tri *t = ray__alloc(s, all * sizeof *t);
    ray__tri_id *id;

    if (t == NULL) {
        permute_tris(s, items, n);
        return;
    }
    for (i = 0; i < n; i++)
        t[i] = s->tris[items[i]];
    memcpy(t + n, s->tris + n, (all - n) * sizeof *t);   /* waiting ones */
    ray__free(s, s->tris, s->cap_tris * sizeof *s->tris);
    s->tris = t;
    s->cap_tris = all;
    id = ray__alloc(s, all * sizeof *id);
    if (id == NULL) {
        permute_ids(s, items, n);
        return;
    }
    for (i = 0; i < n; i++)
        id[i] = s->tri_ids[items[i]];
    memcpy(id + n, s->tri_ids + n, (all - n) * sizeof *id);
    ray__free(s, s->tri_ids, s->cap_tri_ids * sizeof *s->tri_ids);
    s->tri_ids = id;
    s->cap_tri_ids = all;
}

/* Is triangle slot i of geometry that queries may see? */
static int tri_live(const ray_scene *s, size_t i)
{
    const ray__prim *p = &s->prims[s->tri_ids[i].geom_id];
    return p->enabled && !p->removed;
}

/* Swap triangle slots i and j (and their ids); nothing to do for i == j,
** the usual case (every triangle kept, in place). */
static void tri_swap(ray_scene *s, size_t i, size_t j)
{
    ray__tri t;
    ray__tri_id id;

    if (i == j)
        return;
    t = s->tris[i];
    id = s->tri_ids[i];

    s->tris[i] = s->tris[j];
    s->tri_ids[i] = s->tri_ids[j];
    s->tris[j] = t;
    s->tri_ids[j] = id;
}

/*
** The triangle BVH, rebuilt: the triangles of enabled geometry are moved
** to the front (the others wait behind, outside the BVH, until enabled
** again), then rewritten in leaf order, so every leaf is a contiguous
** run of tris and traversal needs no index indirection.  On failure the
** old BVH is kept (the slots are only reordered: the same triangles).
*/
static int rebuild_triangles(ray_scene *s)
{
    size_t n = 0, i;
    ray__bvh fresh;
    int rc;

    /* Removed geometry's triangles go for good, then the live ones (of
    ** enabled geometry) to the front. */
    for (i = 0; i < s->n_tris; i++)
        if (!s->prims[s->tri_ids[i].geom_id].removed)
            tri_swap(s, n++, i);
    s->n_tris = n;
    n = 0;
    for (i = 0; i < s->n_tris; i++)
        if (tri_live(s, i)) {
            tri_swap(s, n, i);
            ray__tri_collapse_unusable(&s->tris[n++]);   /* while at hand */
        }
    rc = ray__bvh_build(&s->alloc, tri_box, s, n, &tri_costs,
                        s->build_threads, &fresh);
    if (rc != RAY_OK)
        return rc;
    if (n > 0) {
        gather_tris(s, fresh.items, n);
        /* Leaves now index tris directly: the permutation is not kept. */
        ray__free(s, fresh.items, fresh.n_items * sizeof(unsigned));
        fresh.items = NULL;
        fresh.n_items = 0;
    }
    ray__bvh_free(&s->alloc, &s->tri_bvh);
    s->tri_bvh = fresh;
    s->n_live_tris = n;
    trim_tris(s);
    return RAY_OK;
}

static void refit_triangles(ray_scene *s)
{
    /* ray_scene_update_mesh collapsed the unusable ones it wrote. */
    ray__bvh_refit(&s->alloc, &s->tri_bvh, tris_box, s, s->n_live_tris);
}

/* The bounded primitives' ids, for the box callback. */
typedef struct prim_list {
    const ray_scene *s;
    const unsigned *ids;
} prim_list;

/* The float box of a bounded non-triangle primitive, rounded outward. */
static void prim_box(const void *ud, size_t item, float *blo, float *bhi)
{
    const prim_list *pl = ud;
    const ray_scene *s = pl->s;
    ray_vec3 lo, hi;

    ray__prim_box(s, &s->prims[pl->ids[item]], &lo, &hi);
    /* lo - r and hi + r round too: one more float step covers that. */
    blo[0] = nextafterf(ray__float_down(lo.x), -HUGE_VALF);
    blo[1] = nextafterf(ray__float_down(lo.y), -HUGE_VALF);
    blo[2] = nextafterf(ray__float_down(lo.z), -HUGE_VALF);
    bhi[0] = nextafterf(ray__float_up(hi.x), HUGE_VALF);
    bhi[1] = nextafterf(ray__float_up(hi.y), HUGE_VALF);
    bhi[2] = nextafterf(ray__float_up(hi.z), HUGE_VALF);
}

/* Is geometry i seen by queries, and of class c? */
static int prim_live(const ray_scene *s, size_t i, ray__class c)
{
    const ray__prim *p = &s->prims[i];
    return p->enabled && !p->removed && ray__kind_class(p->kind) == c;
}

/*
** The BVH over the bounded primitives but triangles: spheres, polygons,
** the curved surfaces, the shapes and the instances (items are prim
** indices), and the list of planes, which have no bounds and are tested
** on every ray; of enabled geometry only.  Built aside and swapped in, so
** a failure keeps the old ones.
*/
static int rebuild_prims(ray_scene *s)
{
    size_t n_bounded = 0, n_planes = 0, nb = 0, np = 0, i, k;
    unsigned *ids = NULL, *planes = NULL;
    ray__bvh fresh;
    prim_list pl;
    int rc = RAY_OK;

    for (i = 0; i < s->n_prims; i++) {
        n_planes += (size_t)prim_live(s, i, RAY__CLASS_UNBOUNDED);
        n_bounded += (size_t)prim_live(s, i, RAY__CLASS_BOUNDED);
    }
    if (n_planes > 0 &&
        (planes = ray__alloc(s, n_planes * sizeof *planes)) == NULL)
        return RAY_ENOMEM;
    if (n_bounded > 0 && (ids = ray__alloc(s, n_bounded * sizeof *ids)) == NULL)
        rc = RAY_ENOMEM;
    if (rc == RAY_OK) {
        for (i = 0; i < s->n_prims; i++) {
            if (prim_live(s, i, RAY__CLASS_UNBOUNDED))
                planes[np++] = (unsigned)i;
            else if (prim_live(s, i, RAY__CLASS_BOUNDED))
                ids[nb++] = (unsigned)i;
        }
        pl.s = s;
        pl.ids = ids;
        rc = ray__bvh_build(&s->alloc, prim_box, &pl, n_bounded, &prim_costs,
                            s->build_threads, &fresh);
    }
    if (rc == RAY_OK) {
        /* Items become prim indices. */
        for (k = 0; k < fresh.n_items; k++)
            fresh.items[k] = ids[fresh.items[k]];
        ray__bvh_free(&s->alloc, &s->prim_bvh);
        s->prim_bvh = fresh;
        ray__free(s, s->planes, s->n_planes * sizeof *s->planes);
        s->planes = planes;
        s->n_planes = n_planes;
    } else
        ray__free(s, planes, n_planes * sizeof *planes);
    ray__free(s, ids, n_bounded * sizeof *ids);
    return rc;
}

int ray_scene_set_pruning(ray_scene *s, int enabled)
{
    int rc = ray__begin(s, "ray_scene_set_pruning");

    if (rc != RAY_OK)
        return rc;
    s->prune = enabled != 0;
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

unsigned ray_scene_effects(const ray_scene *s)
{
    return s != NULL && s->committed ? s->effects : 0u;
}

/*
** What the scene can ever need: the effects of the materials its enabled
** geometry uses (a material no geometry uses is never shaded;
** RAY_NO_MATERIAL is none), its instances' children's included, and
** shadow rays only if there is a light to cast them toward.  Also whether
** any geometry (a child's included) has a mask or a filter: else queries
** take the ungated path.
*/
static void scene_summary(ray_scene *s)
{
    unsigned e = 0;
    int gated = 0, instances = 0;
    size_t i;

    for (i = 0; i < s->n_prims; i++) {
        const ray__prim *p = &s->prims[i];
        if (!p->enabled || p->removed)
            continue;
        if (p->kind == RAY__KIND_INSTANCE) {
            const ray_scene *c = s->instances[p->surface].child;
            e |= c->material_effects;
            gated |= c->gated;
            instances = 1;
        } else if (p->material != RAY_NO_MATERIAL)
            e |= s->materials[p->material].effects;
        gated |= p->mask != ~0u || p->filter != NULL;
    }
    s->material_effects = e;
    /* A caustic needs a light, a surface that scatters photons and one
    ** that gathers them (L S+ D): else no photon is ever traced, and
    ** neither bit is an effect the scene can need. */
    if (s->n_lights == 0 || !(e & RAY_EFFECT_SCATTER) ||
        !(e & RAY_EFFECT_CAUSTICS))
        e &= ~(RAY_EFFECT_CAUSTICS | RAY_EFFECT_SCATTER);
    s->effects = s->n_lights == 0 ? e & ~RAY_EFFECT_SHADOW : e;
    s->gated = gated;
    s->has_instances = instances;
}

/* The box of everything queries may hit but planes: the union of the
** roots of both BVHs (float, rounded outward from the geometry). */
static void scene_box(ray_scene *s)
{
    const ray__bvh *b[2];
    int i, k;

    b[0] = &s->tri_bvh;
    b[1] = &s->prim_bvh;
    s->lo = v3(HUGE_VAL, HUGE_VAL, HUGE_VAL);
    s->hi = v3(-HUGE_VAL, -HUGE_VAL, -HUGE_VAL);
    for (i = 0; i < 2; i++) {
        const ray__wnode *q;
        if (b[i]->n_wide == 0)
            continue;
        q = &b[i]->wide[0];
        for (k = 0; k < RAY__WIDTH; k++) {
            s->lo = v3(fmin(s->lo.x, (double)q->lo[0][k]),
                       fmin(s->lo.y, (double)q->lo[1][k]),
                       fmin(s->lo.z, (double)q->lo[2][k]));
            s->hi = v3(fmax(s->hi.x, (double)q->hi[0][k]),
                       fmax(s->hi.y, (double)q->hi[1][k]),
                       fmax(s->hi.z, (double)q->hi[2][k]));
        }
    }
}

/* Instance geometry i, live, whose child was committed again since
** (or is uncommitted now): its box must be taken again. */
static ray__instance *instance_behind(ray_scene *s, size_t i)
{
    const ray__prim *p = &s->prims[i];
    ray__instance *in;

    if (p->kind != RAY__KIND_INSTANCE || p->removed)
        return NULL;
    in = &s->instances[p->surface];
    if (in->generation == in->child->generation && in->child->committed)
        return NULL;
    return in;
}

/*
** Instances whose child was committed again since: their box is taken
** again and the top level rebuilt.  Every such instance is checked
** first (a child uncommitted now, or grown planes or instances, is an
** error that changes nothing); then the scene is marked changed
** (ray__touch), so that if the rebuild fails the scene answers
** -RAY_ESTATE until a commit succeeds, rather than through old boxes.
*/
static int refresh_instances(ray_scene *s)
{
    ray__instance *in;
    size_t i;

    for (i = 0; i < s->n_prims; i++) {
        if ((in = instance_behind(s, i)) == NULL)
            continue;
        if (!in->child->committed)
            return ray__fail(s, RAY_ESTATE, "instance %zu: its scene was "
                             "changed and not committed again", i);
        if (in->child->n_planes > 0 || in->child->has_instances)
            return ray__fail(s, RAY_EINVAL, "instance %zu: its scene now "
                             "has planes or instances", i);
    }
    for (i = 0; i < s->n_prims; i++) {
        if ((in = instance_behind(s, i)) == NULL)
            continue;
        ray__instance_box(in);
        in->generation = in->child->generation;
        ray__touch(s, RAY__DIRTY_PRIMS);
    }
    return RAY_OK;
}

void ray__touch(ray_scene *s, unsigned dirty)
{
    s->dirty |= dirty;
    s->committed = 0;
}

/*
** Build what changed (all of it the first time); the scene is then
** read-only until the next change.  A failure (out of memory) leaves the
** scene uncommitted with its changes still staged, so commit can be
** retried.  A commit with nothing to do is a no-op.
*/
int ray_scene_commit(ray_scene *s)
{
    int rc = ray__begin(s, "ray_scene_commit");

    if (rc != RAY_OK)
        return rc;
    if ((rc = refresh_instances(s)) != RAY_OK)
        return rc;
    if (s->committed && s->dirty == 0)
        return RAY_OK;
    if ((s->dirty & RAY__DIRTY_PRIMS) && (rc = rebuild_prims(s)) != RAY_OK)
        return ray__fail(s, rc, "out of memory building the BVH over the "
                         "spheres, polygons, surfaces and instances (not "
                         "committed: retry)");
    s->dirty &= ~RAY__DIRTY_PRIMS;
    if (s->dirty & RAY__DIRTY_TRIS) {
        if ((rc = rebuild_triangles(s)) != RAY_OK)
            return ray__fail(s, rc, "out of memory building the BVH over "
                             "%zu triangles (not committed: retry)",
                             s->n_tris);
    } else if (s->dirty & RAY__DIRTY_REFIT)
        refit_triangles(s);
    s->dirty = 0;
    scene_summary(s);
    scene_box(s);
    s->generation++;
    s->committed = 1;
    return RAY_OK;
}

unsigned ray_scene_light_count(const ray_scene *s)
{
    return s == NULL ? 0 : (unsigned)s->n_lights;
}
