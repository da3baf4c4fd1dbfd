/* SPDX-License-Identifier: MIT */
/*
** surfaces.c -- adding the curved surfaces to a scene: torus, implicit,
** parametric and Bezier.  Each is kept with its box, through which the
** scene's BVH reaches it (intersect.c calls ray_torus, ray_implicit and
** ray_parametric).
*/
#include <string.h>

#include "internal.h"

/* Append a surface descriptor and the primitive that names it; nothing
** is added on failure. */
static int add_surface(ray_scene *s, int kind, unsigned material,
                       const ray__surface *surf, ray_vec3 lo, ray_vec3 hi,
                       unsigned *geom_id)
{
    ray__prim p;
    void *grown;
    int rc;

    if (material >= s->n_materials)
        return RAY_EINVAL;
    if (s->n_surfaces >= RAY_INVALID_ID)
        return RAY_ENOMEM;
    grown = ray__grow(s, s->surfaces, &s->cap_surfaces, s->n_surfaces,
                      sizeof *s->surfaces);
    if (grown == NULL)
        return RAY_ENOMEM;
    s->surfaces = grown;
    memset(&p, 0, sizeof p);
    p.kind = kind;
    p.material = material;
    p.a = lo;
    p.b = hi;
    p.surface = (unsigned)s->n_surfaces;
    rc = ray__add_prim(s, &p, geom_id);
    if (rc != RAY_OK)
        return rc;
    s->surfaces[s->n_surfaces++] = *surf;
    return RAY_OK;
}

int ray_scene_add_torus(ray_scene *s, const ray_torus_params *t,
                        unsigned material, unsigned *geom_id)
{
    ray__surface surf;
    ray_vec3 lo, hi;
    int rc = ray__editable(s);

    if (rc != RAY_OK)
        return rc;
    if (!ray__torus_box(t, &lo, &hi))
        return RAY_EINVAL;
    memset(&surf, 0, sizeof surf);
    surf.torus = *t;
    return add_surface(s, PRIM_TORUS, material, &surf, lo, hi, geom_id);
}

int ray_scene_add_implicit(ray_scene *s, const ray_implicit_surface *is,
                           unsigned material, unsigned *geom_id)
{
    ray__surface surf;
    ray_vec3 grow;
    double tol;
    int rc = ray__editable(s);

    if (rc != RAY_OK)
        return rc;
    if (!ray__implicit_valid(is))
        return RAY_EINVAL;
    memset(&surf, 0, sizeof surf);
    surf.implicit = *is;
    /* A hit lies within the tolerance of the box (ray_implicit clips the
    ** ray to the box grown by it): so does the BVH's box. */
    tol = ray__implicit_tolerance(is);
    grow = v3(tol, tol, tol);
    return add_surface(s, PRIM_IMPLICIT, material, &surf,
                       v3_sub(is->lo, grow), v3_add(is->hi, grow), geom_id);
}

int ray_scene_add_parametric(ray_scene *s, const ray_parametric_surface *ps,
                             unsigned material, unsigned *geom_id)
{
    ray__surface surf;
    ray_vec3 lo, hi, grow;
    double d[4], tol;
    int rc = ray__editable(s);

    if (rc != RAY_OK)
        return rc;
    if (!ray__parametric_domain(ps, d))
        return RAY_EINVAL;
    ps->bounds(ps->ud, d[0], d[1], d[2], d[3], &lo, &hi);
    if (!v3_isfinite(lo) || !v3_isfinite(hi) || lo.x > hi.x ||
        lo.y > hi.y || lo.z > hi.z)
        return RAY_EINVAL;
    memset(&surf, 0, sizeof surf);
    surf.parametric = *ps;
    /* ray_parametric accepts roots within its tolerance of the box: so
    ** does the BVH's box. */
    tol = ps->tolerance > 0 ? ps->tolerance : ray__default_tolerance(lo, hi);
    grow = v3(tol, tol, tol);
    return add_surface(s, PRIM_PARAMETRIC, material, &surf,
                       v3_sub(lo, grow), v3_add(hi, grow), geom_id);
}

/* A Bezier patch keeps its 16 control points in the scene's vertex array
** (no surface record): its descriptor is made from them on each test,
** which costs a few stores, and stays valid however the array grows. */
int ray_scene_add_bezier(ray_scene *s, const ray_vec3 cp[16],
                         unsigned material, unsigned *geom_id)
{
    ray__prim p;
    double tol;
    int rc = ray__editable(s), k;

    if (rc != RAY_OK)
        return rc;
    if (cp == NULL)
        return RAY_EINVAL;
    memset(&p, 0, sizeof p);
    p.kind = PRIM_BEZIER;
    p.material = material;
    p.a = p.b = cp[0];
    for (k = 0; k < 16; k++) {
        if (!v3_isfinite(cp[k]))
            return RAY_EINVAL;
        /* The convex hull property: the patch lies in its points' box. */
        p.a = v3(fmin(p.a.x, cp[k].x), fmin(p.a.y, cp[k].y),
                 fmin(p.a.z, cp[k].z));
        p.b = v3(fmax(p.b.x, cp[k].x), fmax(p.b.y, cp[k].y),
                 fmax(p.b.z, cp[k].z));
    }
    if (material >= s->n_materials)
        return RAY_EINVAL;
    /* Roots within the default tolerance of the box are accepted. */
    tol = ray__default_tolerance(p.a, p.b);
    p.a = v3_sub(p.a, v3(tol, tol, tol));
    p.b = v3_add(p.b, v3(tol, tol, tol));
    rc = ray__reserve_verts(s, 16);
    if (rc != RAY_OK)
        return rc;
    p.first = s->n_verts;
    p.count = 16;
    rc = ray__add_prim(s, &p, geom_id);
    if (rc != RAY_OK)
        return rc;
    memcpy(s->verts + s->n_verts, cp, 16 * sizeof *cp);
    s->n_verts += 16;
    return RAY_OK;
}
