/* SPDX-License-Identifier: MIT */
/*
** geometry.c -- adding the lecture's primitives to a scene: spheres,
** planes, triangles, polygons, and the record of a mesh (mesh.c adds its
** triangles).
*/
#include <string.h>

#include "scene/scene.h"

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
    /* c: the unit normal of the hit records, b normalised once more, as
    ** ray_plane normalises whatever normal it is given (kinds.c
    ** plane_fill): made once here, not once per hit (issue 35).  b is
    ** unit, finite and non-zero, so this cannot fail. */
    (void)v3_normalize(p.b, &p.c);
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
    s->tri_ids[s->n_tris].geom_id = (unsigned)(s->n_prims - 1);
    s->tri_ids[s->n_tris].prim_id = 0;
    s->n_tris++;
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
    /* The plane every ray tests first, made once (kinds.c's hit_POLYGON):
    ** its centroid in a, its Newell normal in b. */
    (void)ray__polygon_plane(v, n, &p.a, &p.b);
    rc = ray__add_prim(s, &p, geom_id);
    if (rc != RAY_OK)
        return rc;
    memcpy(s->verts + s->n_verts, v, n * sizeof *v);
    s->n_verts += n;
    return RAY_OK;
}

/*
** The geometry record of a mesh whose triangles are slots first ..
** first+count-1 (already reserved), with its positions, indices and
** shading data.  Both arrays are grown first, so a failure changes
** nothing.
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
