/* SPDX-License-Identifier: MIT */
/*
** surfaces.c -- adding the curved surfaces to a scene: torus, implicit,
** parametric and Bezier, the shapes, and the caller's own geometry.  Each
** is kept with its box, through which the scene's BVH reaches it
** (kinds.c calls ray_torus, ray_implicit, ray_parametric, the shapes'
** functions and the user's callback).
*/
#include <string.h>

#include "scene/scene.h"

/* Append a surface descriptor and the primitive that names it; nothing
** is added on failure. */
static int add_surface(ray_scene *s, ray__kind kind, unsigned material,
                       const ray__surface *surf, ray_vec3 lo, ray_vec3 hi,
                       unsigned *geom_id)
{
    ray__prim p;
    void *grown;
    int rc = ray__material_known(s, material);

    if (rc != RAY_OK)
        return rc;
    if (s->n_surfaces >= RAY_INVALID_ID)
        return ray__fail(s, RAY_ENOMEM, "too many surfaces (%zu: ids are "
                         "32-bit)", s->n_surfaces);
    grown = ray__grow(s, s->surfaces, &s->cap_surfaces, s->n_surfaces,
                      sizeof *s->surfaces);
    if (grown == NULL)
        return ray__fail(s, RAY_ENOMEM, "out of memory (surface %zu)",
                         s->n_surfaces);
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

/*
** The messages of the descriptors' checks.  Whether a descriptor is valid
** is decided by the primitive's own test (ray__torus_box,
** ray__implicit_valid, ray__parametric_domain), so that a scene accepts
** exactly what the bare function does; these run only once that test has
** refused it, to name the first field that breaks the contract of its man
** page, and fall back to a general message for what they cannot name.
*/
static int torus_fail(ray_scene *s, const ray_torus_params *t)
{
    ray_vec3 unit;

    if (t == NULL)
        return ray__fail(s, RAY_EINVAL, "torus parameters are NULL");
    if (!v3_isfinite(t->center))
        return ray__fail(s, RAY_EINVAL, "center " RAY__V3FMT " is not "
                         "finite", RAY__V3ARGS(t->center));
    if (!v3_isfinite(t->axis) || !v3_normalize(t->axis, &unit))
        return ray__fail(s, RAY_EINVAL, "axis " RAY__V3FMT " is zero or "
                         "not finite", RAY__V3ARGS(t->axis));
    if (!(t->major > 0 && t->major < HUGE_VAL))
        return ray__fail(s, RAY_EINVAL, "major radius %g is not positive "
                         "and finite", t->major);
    if (!(t->minor > 0 && t->minor < t->major))
        return ray__fail(s, RAY_EINVAL, "minor radius %g is not in (0, "
                         "major radius %g): only ring tori", t->minor,
                         t->major);
    return ray__fail(s, RAY_EINVAL, "the torus (major radius %g, center "
                     RAY__V3FMT ") reaches beyond the largest double",
                     t->major, RAY__V3ARGS(t->center));
}

/* A setting that must be finite and >= 0 (0 picks the default). */
static int setting_valid(double x)
{
    return x >= 0 && x < HUGE_VAL;
}

static int implicit_fail(ray_scene *s, const ray_implicit_surface *is)
{
    if (is == NULL)
        return ray__fail(s, RAY_EINVAL, "surface is NULL");
    if (is->f == NULL)
        return ray__fail(s, RAY_EINVAL, "field function f is NULL");
    if (!v3_isfinite(is->lo) || !v3_isfinite(is->hi) ||
        !(is->lo.x <= is->hi.x && is->lo.y <= is->hi.y &&
          is->lo.z <= is->hi.z))
        return ray__fail(s, RAY_EINVAL, "box lo " RAY__V3FMT " hi "
                         RAY__V3FMT " is not finite or has lo > hi",
                         RAY__V3ARGS(is->lo), RAY__V3ARGS(is->hi));
    if (!setting_valid(is->lipschitz))
        return ray__fail(s, RAY_EINVAL, "lipschitz %g is negative or not "
                         "finite", is->lipschitz);
    if (!setting_valid(is->step))
        return ray__fail(s, RAY_EINVAL, "step %g is negative or not finite",
                         is->step);
    if (!setting_valid(is->tolerance))
        return ray__fail(s, RAY_EINVAL, "tolerance %g is negative or not "
                         "finite", is->tolerance);
    return ray__fail(s, RAY_EINVAL, "invalid descriptor");
}

/* The most subdivisions ray_parametric(3) allows. */
#define PARAMETRIC_MAX_SUBDIVISIONS 12u

static int parametric_fail(ray_scene *s, const ray_parametric_surface *ps)
{
    if (ps == NULL)
        return ray__fail(s, RAY_EINVAL, "surface is NULL");
    if (ps->eval == NULL)
        return ray__fail(s, RAY_EINVAL, "eval is NULL");
    if (ps->bounds == NULL)
        return ray__fail(s, RAY_EINVAL, "bounds is NULL");
    if (ps->subdivisions > PARAMETRIC_MAX_SUBDIVISIONS)
        return ray__fail(s, RAY_EINVAL, "subdivisions %u is more than %u",
                         ps->subdivisions, PARAMETRIC_MAX_SUBDIVISIONS);
    if (!setting_valid(ps->tolerance))
        return ray__fail(s, RAY_EINVAL, "tolerance %g is negative or not "
                         "finite", ps->tolerance);
    return ray__fail(s, RAY_EINVAL, "domain [%g, %g] x [%g, %g] is empty or "
                     "not finite", ps->u0, ps->u1, ps->v0, ps->v1);
}

int ray_scene_add_torus(ray_scene *s, const ray_torus_params *t,
                        unsigned material, unsigned *geom_id)
{
    ray__surface surf;
    ray_vec3 lo, hi;
    int rc = ray__begin(s, "ray_scene_add_torus");

    if (rc != RAY_OK)
        return rc;
    if (!ray__torus_box(t, &lo, &hi))
        return torus_fail(s, t);
    memset(&surf, 0, sizeof surf);
    surf.torus = *t;
    return add_surface(s, RAY__KIND_TORUS, material, &surf, lo, hi, geom_id);
}

int ray_scene_add_implicit(ray_scene *s, const ray_implicit_surface *is,
                           unsigned material, unsigned *geom_id)
{
    ray__surface surf;
    ray_vec3 grow;
    double tol;
    int rc = ray__begin(s, "ray_scene_add_implicit");

    if (rc != RAY_OK)
        return rc;
    if (!ray__implicit_valid(is))
        return implicit_fail(s, is);
    memset(&surf, 0, sizeof surf);
    surf.implicit = *is;
    /* A hit lies within the tolerance of the box (ray_implicit clips the
    ** ray to the box grown by it): so does the BVH's box. */
    tol = ray__implicit_tolerance(is);
    grow = v3(tol, tol, tol);
    return add_surface(s, RAY__KIND_IMPLICIT, material, &surf,
                       v3_sub(is->lo, grow), v3_add(is->hi, grow), geom_id);
}

int ray_scene_add_parametric(ray_scene *s, const ray_parametric_surface *ps,
                             unsigned material, unsigned *geom_id)
{
    ray__surface surf;
    ray_vec3 lo, hi, grow;
    double d[4], tol;
    int rc = ray__begin(s, "ray_scene_add_parametric");

    if (rc != RAY_OK)
        return rc;
    if (!ray__parametric_domain(ps, d))
        return parametric_fail(s, ps);
    ps->bounds(ps->ud, d[0], d[1], d[2], d[3], &lo, &hi);
    if (!v3_isfinite(lo) || !v3_isfinite(hi) || lo.x > hi.x ||
        lo.y > hi.y || lo.z > hi.z)
        return ray__fail(s, RAY_EINVAL, "the bounds callback gave lo "
                         RAY__V3FMT " hi " RAY__V3FMT ": not finite, or "
                         "lo > hi", RAY__V3ARGS(lo), RAY__V3ARGS(hi));
    memset(&surf, 0, sizeof surf);
    surf.parametric = *ps;
    /* ray_parametric accepts roots within its tolerance of the box: so
    ** does the BVH's box. */
    tol = ps->tolerance > 0 ? ps->tolerance : ray__default_tolerance(lo, hi);
    grow = v3(tol, tol, tol);
    return add_surface(s, RAY__KIND_PARAMETRIC, material, &surf,
                       v3_sub(lo, grow), v3_add(hi, grow), geom_id);
}

/*
** User geometry keeps its descriptor as a surface record, and the box its
** bounds callback gave now (ray__user_box, user.c).  The box is not grown:
** the callback promises it holds every hit, and the BVH's float boxes are
** rounded outward from it.
*/
int ray_scene_add_user(ray_scene *s, const ray_user_geometry *g,
                       unsigned material, unsigned *geom_id)
{
    ray__surface surf;
    ray_vec3 lo, hi;
    char why[RAY__ERRMSG_SIZE];
    int rc = ray__begin(s, "ray_scene_add_user");

    if (rc != RAY_OK)
        return rc;
    if (g == NULL)
        return ray__fail(s, RAY_EINVAL, "user geometry is NULL");
    if (g->bounds == NULL)
        return ray__fail(s, RAY_EINVAL, "bounds is NULL");
    if (g->intersect == NULL)
        return ray__fail(s, RAY_EINVAL, "intersect is NULL");
    if (!ray__user_box(g, &lo, &hi, why, sizeof why))
        return ray__fail(s, RAY_EINVAL, "%s", why);
    memset(&surf, 0, sizeof surf);
    surf.user = *g;
    return add_surface(s, RAY__KIND_USER, material, &surf, lo, hi, geom_id);
}

/* A Bezier patch keeps its 16 control points in the scene's vertex array
** (no surface record): its descriptor is made from them on each test,
** which costs a few stores, and stays valid however the array grows. */
int ray_scene_add_bezier(ray_scene *s, const ray_vec3 cp[16],
                         unsigned material, unsigned *geom_id)
{
    ray__prim p;
    double tol;
    int rc = ray__begin(s, "ray_scene_add_bezier"), k;

    if (rc != RAY_OK)
        return rc;
    if (cp == NULL)
        return ray__fail(s, RAY_EINVAL, "control points are NULL");
    memset(&p, 0, sizeof p);
    p.kind = RAY__KIND_BEZIER;
    p.material = material;
    p.a = p.b = cp[0];
    for (k = 0; k < 16; k++) {
        if (!v3_isfinite(cp[k]))
            return ray__fail(s, RAY_EINVAL, "control point %d " RAY__V3FMT
                             " is not finite", k, RAY__V3ARGS(cp[k]));
        /* The convex hull property: the patch lies in its points' box. */
        p.a = v3(fmin(p.a.x, cp[k].x), fmin(p.a.y, cp[k].y),
                 fmin(p.a.z, cp[k].z));
        p.b = v3(fmax(p.b.x, cp[k].x), fmax(p.b.y, cp[k].y),
                 fmax(p.b.z, cp[k].z));
    }
    rc = ray__material_known(s, material);
    if (rc != RAY_OK)
        return rc;
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

/*
** ray_scene_add_NAME of every shape (RAY__SHAPES, prim.h): the shape's own
** check decides what is valid (so a scene accepts exactly what ray_NAME
** does), gives the box and names the field at fault.
*/
#define SHAPE_ADDER(X, NAME, name, type, counted_as)                       \
    int ray_scene_add_##name(ray_scene *s, const type *params,              \
                             unsigned material, unsigned *geom_id)          \
    {                                                                       \
        ray__surface surf;                                                  \
        ray_vec3 lo, hi;                                                    \
        char why[RAY__ERRMSG_SIZE];                                         \
        int rc = ray__begin(s, "ray_scene_add_" #name);                     \
                                                                            \
        if (rc != RAY_OK)                                                   \
            return rc;                                                      \
        if (!ray__##name##_check(params, &lo, &hi, why, sizeof why))        \
            return ray__fail(s, RAY_EINVAL, "%s", why);                     \
        memset(&surf, 0, sizeof surf);                                      \
        surf.name = *params;                                                \
        return add_surface(s, RAY__KIND_##NAME, material, &surf, lo, hi,    \
                           geom_id);                                        \
    }
RAY__SHAPES(SHAPE_ADDER, _)
