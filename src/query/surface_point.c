/* SPDX-License-Identifier: MIT */
/*
** surface_point.c -- ray_surface_point: the hit record of a point of the
** scene's own geometry given by its primitive and its own coordinates
** (u, v), for rays that start there (lightmap texels, ambient occlusion
** from interpolated points): the point and its error bound computed
** from the stored geometry by the formulas a ray's hit would use, so
** that ray_spawn offsets a ray leaving it past that bound and the ray
** never meets the surface it starts on.
*/
#include "query/query.h"
#include "prim/sweep.h"

/* A triangle's point at barycentrics (u, v): ray__triangle_fill, the
** hit record's own formulas (pbrt-v4's gamma(7) bound on the
** interpolation), on the corners the queries read (ray__tri_by_id). */
static int triangle_point(const ray_scene *s, unsigned geom_id,
                          unsigned prim_id, double u, double v,
                          ray_hit *h)
{
    ray__tri t;

    if (!(u >= 0 && v >= 0 && u + v <= 1) ||
        prim_id >= s->prims[geom_id].count)
        return RAY_EINVAL;
    t = ray__tri_by_id(s, geom_id, prim_id);
    /* A triangle without area (read as a point) has no point. */
    if (!ray__triangle_fill(t.a, t.b, t.c, 0, u, v, h))
        return RAY_EINVAL;
    return RAY_OK;
}

/*
** A sphere's point at (u, v) as ray_sphere reports them: u = atan2(n.x,
** n.z) / 2pi + 1/2, v = acos(-n.y) / pi, so n = (sin(pi v) sin phi,
** -cos(pi v), sin(pi v) cos phi) with phi = 2 pi (u - 1/2); normalised
** and scaled as ray__sphere_fill does (libm's sin and cos are within an
** ulp or two, which the normalisation's own rounding dwarfs), with its
** bound gamma(7) (|c| + r |n|).
*/
static int sphere_point(const ray__prim *p, double u, double v, ray_hit *h)
{
    double phi = 2 * RAY__PI * (u - 0.5), rho = sin(RAY__PI * v);
    ray_vec3 n;

    if (!(u >= 0 && u <= 1 && v >= 0 && v <= 1) ||
        !v3_normalize(v3(rho * sin(phi), -cos(RAY__PI * v), rho * cos(phi)),
                      &n))
        return RAY_EINVAL;
    h->t = 0;
    h->p = v3_madd(p->a, p->radius, n);
    h->n = n;
    h->u = u;
    h->v = v;
    h->p_err = v3_scale(v3_add(v3_abs(p->a), v3_scale(v3_abs(n), p->radius)),
                        ray__gamma(7));
    return v3_isfinite(h->p) && v3_isfinite(h->p_err) ? RAY_OK : RAY_EINVAL;
}

/*
** A plane's (or a polygon's) point at (u, v) along ray_plane's tangents
** from "origin" (the plane's point; a polygon's first vertex), put back
** onto the plane through "at" with unit normal n as ray__plane_fill puts
** a hit, and its bound: gamma(8) of the largest magnitude of the point
** and "at" (ray__plane_fill's), plus gamma(4) (|u| + |v|) for the
** tangents' rounding (3 roundings each, and the sum).
*/
static int plane_point(ray_vec3 at, ray_vec3 n, ray_vec3 origin, double u,
                       double v, ray_hit *h)
{
    ray_vec3 t1, t2, p, mag;
    double bound;

    ray__tangent_frame(n, &t1, &t2);
    p = v3_add(origin, v3_add(v3_scale(t1, u), v3_scale(t2, v)));
    p = v3_madd(p, -v3_dot(v3_sub(p, at), n), n);
    mag = v3_add(v3_abs(p), v3_abs(at));
    bound = ray__gamma(8) * fmax(mag.x, fmax(mag.y, mag.z)) +
            ray__gamma(4) * (fabs(u) + fabs(v));
    if (!v3_isfinite(p) || !(bound < HUGE_VAL))
        return RAY_EINVAL;
    h->t = 0;
    h->p = p;
    h->n = n;
    h->u = u;
    h->v = v;
    h->p_err = v3(bound, bound, bound);
    return RAY_OK;
}

/* Geometry geom_id of s (not an instance) at (u, v): RAY_OK with *h,
** RAY_EINVAL, or RAY_EKIND for a kind without surface points. */
static int own_point(const ray_scene *s, unsigned geom_id, unsigned prim_id,
                     double u, double v, ray_hit *h)
{
    const ray__prim *p;
    ray_vec3 c, n;

    if (geom_id >= s->n_prims || s->prims[geom_id].removed ||
        !isfinite(u) || !isfinite(v))
        return RAY_EINVAL;
    p = &s->prims[geom_id];
    switch (p->kind) {
    case RAY__KIND_TRIANGLE:
    case RAY__KIND_MESH:
        return triangle_point(s, geom_id, prim_id, u, v, h);
    case RAY__KIND_SPHERE:
        return prim_id == 0 ? sphere_point(p, u, v, h) : RAY_EINVAL;
    case RAY__KIND_PLANE:
        return prim_id == 0 ? plane_point(p->a, p->b, p->a, u, v, h)
                            : RAY_EINVAL;
    case RAY__KIND_POLYGON:
        if (prim_id != 0 ||
            !ray__polygon_plane_mapped(s->verts + p->first, p->count, NULL,
                                       &c, &n) ||
            plane_point(c, n, s->verts[p->first], u, v, h) != RAY_OK ||
            !ray__polygon_contains(s->verts + p->first, p->count, NULL,
                                   h->p))
            return RAY_EINVAL;
        return RAY_OK;
    case RAY__KIND_TORUS:
    case RAY__KIND_IMPLICIT:
    case RAY__KIND_PARAMETRIC:
    case RAY__KIND_BEZIER:
    case RAY__KIND_USER:
    case RAY__KIND_BOX:
    case RAY__KIND_CAPSULE:
        return RAY_EKIND;
    case RAY__KIND_INSTANCE:
        return RAY_EINVAL;
    }
    return RAY_EINVAL;               /* not a ray__kind: cannot happen */
}

int ray_surface_point(const ray_scene *s, unsigned geom_id, unsigned prim_id,
                      unsigned inst_id, double u, double v, ray_hit *hit)
{
    const ray_scene *owner = s;
    const ray__instance *in = NULL;
    ray_hit h, w;
    int rc;

    if (s == NULL || hit == NULL)
        return RAY_EINVAL;
    if (!s->committed)
        return RAY_ESTATE;
    if (inst_id != RAY_INVALID_ID) {
        if (inst_id >= s->n_prims || s->prims[inst_id].removed ||
            s->prims[inst_id].kind != RAY__KIND_INSTANCE)
            return RAY_EINVAL;
        in = &s->instances[s->prims[inst_id].surface];
        if (ray__instance_stale(in))
            return RAY_ESTATE;
        owner = in->child;
    }
    if ((rc = own_point(owner, geom_id, prim_id, u, v, &h)) != RAY_OK)
        return rc;
    h.geom_id = geom_id;
    h.prim_id = prim_id;
    h.inst_id = RAY_INVALID_ID;
    if (in != NULL) {
        ray__instance_to_world(in, &h, &w);
        w.inst_id = inst_id;
        if (!v3_isfinite(w.p) || !v3_isfinite(w.p_err))
            return RAY_EINVAL;
        h = w;
    }
    ray__hit_store(hit, &h);
    return RAY_OK;
}
