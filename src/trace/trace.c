/* SPDX-License-Identifier: MIT */
/*
** trace.c -- the recursive ray tree: trace a ray, shade its hit with the
** material's callback, which may trace further rays through the same
** context.  The tree's bounds (depth, weight, fan-out) are enforced here.
*/
#include <float.h>
#include <string.h>

#include "trace/trace.h"

void ray__ctx_start(ray_ctx *ctx, unsigned long long rng)
{
    ctx->rng = rng;
    ctx->in_shade = 0;
    ctx->depth = 0;
    ctx->weight = 1.0;
    ctx->effects = 0;
    ctx->fanout = 0;
    ctx->hit_cone.on = 0;
}

int ray_ctx_new(const ray_scene *scene, unsigned long long seed,
                ray_ctx **out)
{
    ray_ctx *ctx;

    if (scene == NULL || out == NULL)
        return RAY_EINVAL;
    if (!scene->committed)
        return RAY_ESTATE;     /* as the queries and ray_render answer */
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

int ray_ctx_set_cone(ray_ctx *ctx, double width, double spread)
{
    if (ctx == NULL || !(width >= 0 && width < HUGE_VAL) ||
        !(spread >= 0 && spread < RAY__PI))
        return RAY_EINVAL;     /* a cone's whole angle is below pi */
    ctx->cone_width = width;
    ctx->cone_spread = spread;
    return RAY_OK;
}

double ray_ctx_random(ray_ctx *ctx)
{
    if (ctx == NULL)
        return 0.0;
    return ray__ctx_random(ctx);
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
    if ((ctx->effects & effect_of_kind[kind]) == 0) {
        /* Counted, as light.c counts a shadow ray asked for without
        ** RAY_EFFECT_SHADOW: a status the material may ignore would
        ** otherwise show only as a missing reflection in the image.  The
        ** photon pass refuses its scatter callbacks this way too, but
        ** sums only its tests into the render's counters. */
        ctx->stats.traces_undeclared++;
        return RAY_EEFFECT;
    }
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
    a->scene = s;
    a->ray = r;
    a->hit = hit;
    a->entering = v3_dot(r->dir, hit->n) < 0;
    a->normal = a->entering ? hit->n : v3_scale(hit->n, -1.0);
    a->u = hit->u;
    a->v = hit->v;
    a->depth = depth;
    a->weight = weight;
    a->ambient = s->ambient;
    a->shading_normal = a->normal;
    a->prune = s->prune;
    a->cone_width = 0;
    a->footprint = 0;
    mesh_shading(s, hit, a);
}

/*
** A ray's cone (Amanatides, "Ray Tracing with Cones", SIGGRAPH 1984; as
** Akenine-Moller et al. use it for texture level of detail, "Texture
** Level of Detail Strategies for Real-Time Ray Tracing", Ray Tracing
** Gems, 2019, chapter 20): its width w0 at the origin and its spread
** angle (radians, the whole angle), so its width at distance d is
** w0 + spread d (their equation 20.32, the small-angle form).
*/
typedef struct cone {
    double width, spread;
} cone;

/* x clamped to [-DBL_MAX, DBL_MAX], NaN to DBL_MAX: a cone that grew
** beyond every length (a spread near pi over 1e300) is as wide as can be
** (a texture's coarsest level), never NaN or infinite in the sums that
** carry it on.  ray__fmax and ray__fmin: libm's bits, inline (vec.h). */
static double finite_or_max(double x)
{
    return ray__fmax(ray__fmin(x, DBL_MAX), -DBL_MAX);
}

/*
** The cone at the hit and what the material sees of it.  The width at
** the hit is w = w0 + spread d, d = t |dir| (kept signed for the rays
** that go on: a concave mirror's focus makes it pass through 0; the
** material gets |w|).  The footprint in (u, v) is |w| / |cos incidence|
** (the cone's section on the surface, stretched along the plane of
** incidence; the isotropic estimate takes the stretch whole, as their
** section 20.3.4 does) times the surface's (u, v) per unit length
** (ray__prim_uv_scale, which an instance's scale divides).
**
** A reflection off a surface of curvature k (ray__prim_curvature, > 0
** convex toward the ray) widens the spread by beta = 2 k |w|: across the
** footprint the normal turns by k |w| / cos(theta) in the plane of
** incidence and by k |w| across it, and the reflection turns twice as
** much in the first and 2 cos(theta) times in the second; the
** geometric mean of the two is 2 k |w| whatever theta (the 2019 chapter's
** beta = 2 curvature term, eq. 20.33, with the curvature taken from the
** geometry rather than from screen-space normal derivatives).  Flat:
** beta = 0, so a cone through a flat mirror widens as if the mirror were
** not there.  Refraction: refracted_spread.
*/
static void cone_at_hit(ray_ctx *ctx, const ray_scene *owner,
                        const ray_material *m, const ray_ray *r,
                        const ray_hit *hit, const cone *c,
                        ray_shade_args *args)
{
    const ray__instance *in = ray__hit_instance(ctx->scene, hit);
    const ray__prim *p = &owner->prims[hit->geom_id];
    double len = v3_length(r->dir);
    double w = finite_or_max(c->width + c->spread * (hit->t * len));
    double aw = fabs(w), k;
    /* An instance's object lengths per world length: 1 / s for a
    ** similarity s R; else |L^-1| / sqrt(3), the Frobenius norm's value
    ** for the identity, a mean scale. */
    double obj_per_world =
        in == NULL ? 1.0
                   : in->similarity > 0 ? 1.0 / in->similarity
                                        : in->inv_norm / sqrt(3.0);

    args->cone_width = aw;
    if ((m->effects & RAY_EFFECT_TEXTURE) && aw > 0) {
        double scale = ray__prim_uv_scale(owner, p, hit) * obj_per_world;
        double cosi = fabs(v3_dot(r->dir, hit->n)) / len;
        if (scale > 0)
            args->footprint = cosi > 0 ? aw / cosi * scale : HUGE_VAL;
        if (!(args->footprint >= 0))
            args->footprint = 0;     /* NaN from an Inf scale: unknown */
    }
    ctx->hit_cone.on = 1;
    ctx->hit_cone.width = w;
    ctx->hit_cone.spread = c->spread;
    /* Only a curved surface bends: a flat one adds nothing, even to a
    ** cone as wide as DBL_MAX (whose product with 0 would be NaN). */
    k = ray__prim_curvature(owner, p, hit);
    ctx->hit_cone.bend =
        k != 0 ? finite_or_max((args->entering ? aw : -aw) * k *
                               obj_per_world)
               : 0.0;
    ctx->hit_cone.dir = v3_scale(r->dir, 1.0 / len);
    ctx->hit_cone.normal = args->normal;
}

/*
** Below this sine of the incidence angle (2^-30 rad from the normal) the
** ratio of the sines does not give the refractive index: the sines are
** computed from unit vectors with an absolute error of a few ulps of 1,
** so above it eta carries a relative error under 2^-20, a millionth of a
** mip level; below it, nothing reliable.
*/
#define MIN_SIN_FOR_ETA 0x1p-30

/*
** The spread of a cone refracted at the hit into unit direction t
** (Boksansky, Crassin, Akenine-Moller, "Refraction Ray Cones for Texture
** Level of Detail", Ray Tracing Gems II, 2021, ch. 10, refract the
** cone's two edge rays through the normals at the footprint's edges; this
** is the same to first order, in closed form).  Snell's law
** n1 sin(ti) = n2 sin(tt) differentiated: a change of the incoming
** direction by dtheta turns the refracted one by eta cos(ti) / cos(tt)
** dtheta in the plane of incidence and by eta dtheta across it, eta =
** n1 / n2 (the geometric mean of the two scales the spread); a turn
** delta of the normal turns the refracted ray by (1 - eta cos(ti) /
** cos(tt)) delta in the plane (delta = bend / cos(ti) there: the
** footprint is stretched) and by (1 - eta) delta across it, toward the
** normal's inward side, so a convex surface entered (eta < 1) focuses
** the cone: a glass ball of index n focuses a parallel cone at n R /
** (2 (n - 1)) from its centre, the paraxial focus of a ball lens.  The
** tracer does not know the index: eta = sin(tt) / sin(ti), read from the
** two directions, which fails only within MIN_SIN_FOR_ETA of normal
** incidence; there the cone goes on as it came (eta taken as 1).  A
** flat boundary's scaling is undone on the way out of a slab.
*/
static double refracted_spread(const ray__hit_cone *h, ray_vec3 t)
{
    double cos_i = -v3_dot(h->dir, h->normal), cos_t = -v3_dot(t, h->normal);
    double sin_i = v3_length(v3_cross(h->dir, h->normal));
    double eta, in_plane, across;

    if (!(cos_i > 0 && cos_t > 0 && sin_i >= MIN_SIN_FOR_ETA))
        return h->spread;      /* head-on, or not through the surface */
    eta = v3_length(v3_cross(t, h->normal)) / sin_i;
    in_plane = (1 - eta * cos_i / cos_t) / cos_i;
    across = 1 - eta;
    return h->spread * eta * sqrt(cos_i / cos_t) -
           copysign(sqrt(fabs(in_plane * across)), across) * h->bend;
}

/* The cone of a ray the material of the hit being shaded traces: it
** starts with the width at the hit; a reflection turns twice as much as
** the normal (cone_at_hit), a refraction as refracted_spread says. */
static void secondary_cone(const ray__hit_cone *h, unsigned kind,
                           const ray_ray *r, cone *c)
{
    ray_vec3 t;

    c->width = h->width;
    c->spread = h->spread;
    if (kind == RAY_KIND_REFLECTION)
        c->spread = finite_or_max(c->spread + 2 * h->bend);
    else if (v3_normalize(r->dir, &t))
        c->spread = finite_or_max(refracted_spread(h, t));
}

/*
** Shade "hit" with its material, with the context set up for the hit and
** restored afterwards.  Only a material that declared reflection or
** refraction can call ray_trace back (any other call is refused as
** RAY_EEFFECT), so only then is the recursion state saved and restored:
** a scene without such materials pays no recursion bookkeeping.
*/
static void shade(ray_ctx *ctx, const ray_ray *r, const ray_hit *hit,
                  unsigned depth, double weight, const cone *c,
                  ray_rgb *out)
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
    /* The outer hit's cone, kept only where there is one: without, off
    ** is all there is to restore (a cone's other fields are read only
    ** where it is on), and its 80 bytes go uncopied twice a hit. */
    int had_cone = ctx->hit_cone.on;
    ray__hit_cone saved_cone;
    ray_shade_args args;

    if (had_cone)
        saved_cone = ctx->hit_cone;
    ray__shade_args(s, r, hit, depth, weight, &args);
    ctx->hit_cone.on = 0;
    if (c != NULL)
        cone_at_hit(ctx, owner, m, r, hit, c, &args);
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
    if (had_cone)
        ctx->hit_cone = saved_cone;
    else
        ctx->hit_cone.on = 0;
}

static int trace_ray(ray_ctx *ctx, const ray_ray *r, unsigned kind,
                     double attenuation, ray_rgb *out)
{
    unsigned depth;
    double weight;
    ray_hit hit;
    cone c, *has = NULL;
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
    /* The ray's cone: a primary ray's from ray_ctx_set_cone; a secondary
    ** ray's from the hit that spawned it (cone_at_hit).  Only where a
    ** material reads textures (API-NOTES 14). */
    if (ctx->scene->effects & RAY_EFFECT_TEXTURE) {
        if (!ctx->in_shade) {
            c.width = ctx->cone_width;
            c.spread = ctx->cone_spread;
            if (c.width > 0 || c.spread > 0)
                has = &c;
        } else if (ctx->hit_cone.on) {
            secondary_cone(&ctx->hit_cone, kind, r, &c);
            has = &c;
        }
    }
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
        shade(ctx, r, &hit, depth, weight, has, out);
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
