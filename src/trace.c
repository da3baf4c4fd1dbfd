/* SPDX-License-Identifier: MIT */
/*
** trace.c -- the recursive ray tree: trace a ray, shade its hit with the
** material's callback, which may trace further rays through the same
** context.  The tree's bounds (depth, weight, fan-out) are enforced here.
*/
#include <string.h>

#include "trace.h"

void ray__ctx_start(ray_ctx *ctx, unsigned long long rng)
{
    ctx->rng = rng;
    ctx->in_shade = 0;
    ctx->depth = 0;
    ctx->weight = 1.0;
    ctx->effects = 0;
    ctx->fanout = 0;
}

int ray_ctx_new(const ray_scene *scene, unsigned long long seed,
                ray_ctx **out)
{
    ray_ctx *ctx;

    if (scene == NULL || out == NULL || !scene->committed)
        return RAY_EINVAL;
    ctx = ray__alloc(scene, sizeof *ctx);
    if (ctx == NULL)
        return RAY_ENOMEM;
    memset(ctx, 0, sizeof *ctx);
    ctx->scene = scene;
    ray__ctx_start(ctx, ray__mix64(seed));
    *out = ctx;
    return RAY_OK;
}

void ray_ctx_free(ray_ctx *ctx)
{
    if (ctx != NULL)
        ray__free(ctx->scene, ctx, sizeof *ctx);
}

void ray_ctx_stats(const ray_ctx *ctx, ray_stats *out)
{
    if (ctx != NULL && out != NULL)
        *out = ctx->stats;
}

double ray_ctx_random(ray_ctx *ctx)
{
    unsigned long long z;

    if (ctx == NULL)
        return 0.0;
    z = ray__mix64(ctx->rng += 0x9e3779b97f4a7c15ull);
    return (double)(z >> 11) * (1.0 / 9007199254740992.0);  /* 53 bits */
}

static const unsigned effect_of_kind[RAY_KIND_COUNT] = {
    0, RAY_EFFECT_SHADOW, RAY_EFFECT_REFLECTION, RAY_EFFECT_REFRACTION
};

/*
** May this ray be traced?  Returns RAY_OK and the new depth and weight, or
** the reason it may not, counting cut-offs by kind of limit.
*/
static int admit(ray_ctx *ctx, unsigned kind, double attenuation,
                 unsigned *depth, double *weight)
{
    const ray_limits *lim = &ctx->scene->limits;

    if (!ctx->in_shade) {
        if (kind != RAY_KIND_PRIMARY)
            return RAY_EINVAL;
        *depth = 0;
        *weight = attenuation;
        return RAY_OK;
    }
    if (kind != RAY_KIND_REFLECTION && kind != RAY_KIND_REFRACTION)
        return RAY_EINVAL;
    if ((ctx->effects & effect_of_kind[kind]) == 0)
        return RAY_EEFFECT;
    *depth = ctx->depth + 1;
    *weight = ctx->weight * attenuation;
    if (*depth > lim->max_depth) {
        ctx->stats.cut_depth++;
        return RAY_ELIMIT;
    }
    /* Written so that a NaN weight is cut too.  Without pruning (the
    ** naive mode) only depth and fan-out bound the tree. */
    if (ctx->scene->prune && !(*weight >= lim->min_weight)) {
        ctx->stats.cut_weight++;
        return RAY_ELIMIT;
    }
    if (ctx->fanout >= lim->max_fanout) {
        ctx->stats.cut_fanout++;
        return RAY_ELIMIT;
    }
    return RAY_OK;
}

/* The radiance of a ray that hits nothing. */
static void background(const ray_scene *s, const ray_ray *r, ray_rgb *out)
{
    *out = s->background;
    if (s->background_fn != NULL)
        s->background_fn(s->background_ud, r, out);
}

/*
** A mesh's shading data at a hit: the vertex normals and texture
** coordinates interpolated with the hit's barycentrics (1-u-v, u, v), the
** lecture's "what about texturing?"; the latter only if some material of
** the scene declared RAY_EFFECT_TEXTURE.  The shading normal is turned to the
** side of the facing geometric normal; if the interpolation cancels (or
** the mesh has no normals) it is the geometric one.
*/
static void mesh_shading(const ray_scene *top, const ray_hit *hit,
                         ray_shade_args *args)
{
    const ray__instance *in = ray__hit_instance(top, hit);
    const ray_scene *s = in != NULL ? in->child : top;
    const ray__prim *p = &s->prims[hit->geom_id];
    const ray__mesh *m;
    unsigned t[3];
    size_t k;
    double w0 = 1.0 - hit->u - hit->v, w1 = hit->u, w2 = hit->v;

    if (p->kind != RAY__KIND_MESH)
        return;
    m = &s->meshes[p->mesh];
    if (m->normals == NULL && m->texcoords == NULL)
        return;
    k = 3 * (size_t)hit->prim_id;
    t[0] = ray__mesh_corner(m, k);
    t[1] = ray__mesh_corner(m, k + 1);
    t[2] = ray__mesh_corner(m, k + 2);
    if (m->normals != NULL) {
        ray_vec3 n = v3_add(v3_add(v3_scale(m->normals[t[0]], w0),
                                   v3_scale(m->normals[t[1]], w1)),
                            v3_scale(m->normals[t[2]], w2));
        if (in != NULL)
            n = ray__instance_normal(in, n);
        if (v3_normalize(n, &n))
            args->shading_normal = v3_dot(n, args->normal) < 0
                                       ? v3_scale(n, -1.0) : n;
    }
    if (m->texcoords != NULL && (top->effects & RAY_EFFECT_TEXTURE)) {
        const double *st = m->texcoords;
        args->u = w0 * st[2 * t[0]] + w1 * st[2 * t[1]] + w2 * st[2 * t[2]];
        args->v = w0 * st[2 * t[0] + 1] + w1 * st[2 * t[1] + 1] +
                  w2 * st[2 * t[2] + 1];
    }
}

/* The inputs of a material's callbacks at a hit: one function, so the
** camera's rays (shade) and the photons (photons.c) see the same args. */
void ray__shade_args(const ray_scene *s, const ray_ray *r,
                     const ray_hit *hit, unsigned depth, double weight,
                     ray_shade_args *a)
{
    ray_shade_args args;

    args.scene = s;
    args.ray = r;
    args.hit = hit;
    args.entering = v3_dot(r->dir, hit->n) < 0;
    args.normal = args.entering ? hit->n : v3_scale(hit->n, -1.0);
    args.u = hit->u;
    args.v = hit->v;
    args.depth = depth;
    args.weight = weight;
    args.ambient = s->ambient;
    args.shading_normal = args.normal;
    args.prune = s->prune;
    mesh_shading(s, hit, &args);
    *a = args;
}

/*
** Shade "hit" with its material, with the context set up for the hit and
** restored afterwards.  Only a material that declared reflection or
** refraction can call ray_trace back (any other call is refused as
** RAY_EEFFECT), so only then is the recursion state saved and restored:
** a scene without such materials pays no recursion bookkeeping.
*/
static void shade(ray_ctx *ctx, const ray_ray *r, const ray_hit *hit,
                  unsigned depth, double weight, ray_rgb *out)
{
    const ray_scene *s = ctx->scene, *owner = ray__hit_owner(s, hit);
    const ray_material *m =
        &owner->materials[owner->prims[hit->geom_id].material];
    int recursive = (m->effects &
                     (RAY_EFFECT_REFLECTION | RAY_EFFECT_REFRACTION)) != 0;
    int in_shade = ctx->in_shade;
    unsigned saved_depth = ctx->depth, effects = ctx->effects;
    unsigned fanout = ctx->fanout;
    double saved_weight = ctx->weight;
    ray_shade_args args;

    ray__shade_args(s, r, hit, depth, weight, &args);
    ctx->in_shade = 1;
    ctx->effects = m->effects;
    if (recursive) {
        ctx->depth = depth;
        ctx->weight = weight;
        ctx->fanout = 0;
    }
    out->r = out->g = out->b = 0.0;
    m->shade(m->ud, ctx, &args, out);
    ctx->in_shade = in_shade;
    ctx->effects = effects;
    if (recursive) {
        ctx->depth = saved_depth;
        ctx->weight = saved_weight;
        ctx->fanout = fanout;
    }
}

static int trace_ray(ray_ctx *ctx, const ray_ray *r, unsigned kind,
                     double attenuation, ray_rgb *out)
{
    unsigned depth;
    double weight;
    ray_hit hit;
    int rc;

    if (ctx == NULL || r == NULL || out == NULL || kind >= RAY_KIND_COUNT)
        return RAY_EINVAL;
    if (!ctx->scene->committed)
        return RAY_ESTATE;     /* changed since ray_ctx_new: commit it */
    rc = admit(ctx, kind, attenuation, &depth, &weight);
    if (rc != RAY_OK)
        return rc;
    if (ctx->in_shade)
        ctx->fanout++;
    ctx->stats.rays[kind]++;
    if (depth > ctx->stats.max_depth)
        ctx->stats.max_depth = depth;
    /* A sphere's (u, v) only where its material reads them (uv 0). */
    rc = ray__intersect(ctx->scene, r, 0, &hit, &ctx->stats);
    if (rc < 0) {
        ctx->stale = 1;        /* an instance's child changed: recommit */
        return RAY_ESTATE;
    }
    if (rc == 0)
        background(ctx->scene, r, out);
    else if (ray__hit_owner(ctx->scene, &hit)->prims[hit.geom_id].material ==
             RAY_NO_MATERIAL)
        out->r = out->g = out->b = 0.0;   /* no material: black (ray.h) */
    else
        shade(ctx, r, &hit, depth, weight, out);
    return RAY_OK;
}

/*
** The outermost call (outside any material callback) answers RAY_ESTATE,
** *out untouched, when any ray of its tree met an instance of a scene
** changed since the commit, even one a material's shadow or reflection
** ray met and the material went on without.
*/
int ray_trace(ray_ctx *ctx, const ray_ray *r, unsigned kind,
              double attenuation, ray_rgb *out)
{
    ray_rgb got;
    int rc;

    if (ctx == NULL || ctx->in_shade)
        return trace_ray(ctx, r, kind, attenuation, out);
    if (out == NULL)
        return RAY_EINVAL;
    ctx->stale = 0;
    rc = trace_ray(ctx, r, kind, attenuation, &got);
    if (rc == RAY_OK && ctx->stale)
        rc = RAY_ESTATE;
    ctx->stale = 0;
    if (rc == RAY_OK)
        *out = got;
    return rc;
}
