/* SPDX-License-Identifier: MIT */
/*
** direct.c -- ray_shade_direct: the direct-light loop every material
** would otherwise repeat (sample each light, weigh it by the material's
** BRDF, ask for a shadow ray only when the sample can contribute).
*/
#include <float.h>

#include "trace/trace.h"

/* Any channel strictly positive: a factor that can add light.  NaN
** channels do not count (NaN > 0 is false). */
static int rgb_any_positive(ray_rgb c)
{
    return c.r > 0 || c.g > 0 || c.b > 0;
}

/* -d / |d| where |d|^2 overflows (|d| past ~1.3e154) or underflows
** (below ~1.5e-154), though a ray may have any finite, non-zero
** direction: the overflow-safe v3_normalize, out of line. */
static RAY__NOINLINE ray_vec3 toward_eye_scaled(ray_vec3 d)
{
    ray_vec3 e = d;

    (void)v3_normalize(d, &e);     /* d is finite and non-zero */
    return v3_scale(e, -1.0);
}

/* -d / |d|, the unit direction back toward the eye, computed as the
** built-in Phong did before it used this file (divide, then negate), so
** moving a material onto ray_shade_direct keeps its bits. */
static ray_vec3 toward_eye(ray_vec3 d)
{
    double len2 = v3_dot(d, d), len;
    ray_vec3 e;

    if (!(len2 < HUGE_VAL && len2 >= DBL_MIN))
        return toward_eye_scaled(d);
    len = sqrt(len2);
    e.x = -(d.x / len);
    e.y = -(d.y / len);
    e.z = -(d.z / len);
    return e;
}

/*
** One light sample's factor f from the BRDF, zero behind the shading
** normal, where the BRDF is not called.  Sets b->to_light and
** b->cos_light for the BRDF.
*/
RAY__HOT_INLINE ray_rgb sample_factor(const ray_shade_args *a,
                                      ray_brdf_fn brdf, void *ud,
                                      ray_brdf_args *b)
{
    const ray_light_sample *ls = b->sample;
    ray_rgb f = {0, 0, 0};

    b->to_light = ls->dir;
    b->cos_light = v3_dot(a->shading_normal, ls->dir);
    if (b->cos_light > 0)
        f = brdf(ud, b);
    return f;
}

/* Can factor f of sample_factor's sample b add light? */
RAY__HOT_INLINE int contributes(const ray_brdf_args *b, ray_rgb f)
{
    return b->cos_light > 0 && rgb_any_positive(f);
}

/* Sample ls's light, weighed by f, added to *out. */
RAY__HOT_INLINE void add_light(const ray_light_sample *ls, ray_rgb f,
                               ray_rgb *out)
{
    out->r += f.r * ls->radiance.r;
    out->g += f.g * ls->radiance.g;
    out->b += f.b * ls->radiance.b;
}

/*
** One light sample: its factor, then its shadow ray.  With pruning, a
** sample that cannot add light costs no ray; without, the ray is cast
** anyway (the naive mode that pruning is measured against), and the
** sample still adds nothing.  sp: the hit's shadow-ray origins, made
** once (core/spawn.h).  Inlined: out of line, its call cost the bunny
** scene 10M instructions (examples/mesh).
*/
RAY__HOT_INLINE void add_sample(ray_ctx *ctx, const ray_shade_args *a,
                                ray__spawner *sp, ray_brdf_fn brdf,
                                void *ud, ray_brdf_args *b, ray_rgb *out)
{
    const ray_light_sample *ls = b->sample;
    ray_rgb f = sample_factor(a, brdf, ud, b);
    int adds = contributes(b, f);

    if (!adds && a->prune)
        return;
    if (!ray__light_visible(ctx, sp, ls) || !adds)
        return;
    add_light(ls, f, out);
}

/*
** Samples drawn a batch at a time, then weighed, then their shadow rays
** asked together: a sample is a chain of divisions and square roots
** (light.c) that waited on itself between the shadow queries, where a
** batch's chains overlap (the bunny scene, examples/mesh: 1.12 times as
** fast; issue 35); and a shading point's rays towards one light go the
** same way, so eight of them go through the BVH together where the scene
** allows (ray__occluded_group: the packets, the same answers).  The same
** random numbers in the same order, since nothing between two samples
** draws one (a shadow query none; the BRDF none unless it reaches the
** context through its ud, which ray_shade_direct(3) warns of); the light
** added in the samples' order, so the same sums.
*/
#define SAMPLE_BATCH 16

/* Batch ls[0 .. m - 1] (ok[j]: sample j was made) weighed and its
** shadow rays asked together, its light added to *out in order.  Not
** inlined: its arrays would weigh on add_batches' frame in scenes
** without packets (the Cornell box), which never call it. */
static RAY__NOINLINE void add_batch(ray_ctx *ctx,
                                    const ray_shade_args *args,
                                    ray__spawner *sp,
                                    const ray_light_sample *ls,
                                    const int *ok, unsigned m,
                                    ray_brdf_fn brdf, void *ud,
                                    ray_brdf_args *b, ray_rgb *out)
{
    ray_rgb f[SAMPLE_BATCH];
    ray_ray rays[SAMPLE_BATCH];
    int lit[SAMPLE_BATCH], answer[SAMPLE_BATCH];
    unsigned j, ray_of[SAMPLE_BATCH], n = 0;

    for (j = 0; j < m; j++) {
        int adds;
        lit[j] = 0;
        if (!ok[j])
            continue;
        b->sample = &ls[j];
        f[j] = sample_factor(args, brdf, ud, b);
        adds = contributes(b, f[j]);
        if (!adds && args->prune)
            continue;
        switch (ray__shadow_ray(ctx, sp, &ls[j], &rays[n])) {
        case RAY__SHADOW_NONE:
            lit[j] = adds;
            break;
        case RAY__SHADOW_CAST:
            ray_of[j] = n++;
            lit[j] = adds ? 2 : -1;           /* 2: lit if unoccluded */
            break;
        default:
            break;
        }
    }
    if (n > 0)
        ray__occluded_group(ctx->scene, rays, n, answer, &ctx->stats);
    for (j = 0; j < m; j++) {
        if (lit[j] > 1 || lit[j] < 0) {
            int passes = ray__shadow_passes(ctx, answer[ray_of[j]]);
            lit[j] = lit[j] > 1 && passes;
        }
        if (lit[j])
            add_light(&ls[j], f[j], out);
    }
}

/* The samples of an area light (ns > 1), a batch at a time; not inlined,
** so that a point light's one sample keeps the short loop (Whitted's
** scene paid 1.5% more time for the batch's bookkeeping).  In a scene
** the packets do not take, each sample's ray is asked at once, without
** the grouping's bookkeeping (the Cornell box's polygons). */
static RAY__NOINLINE void add_batches(ray_ctx *ctx, const ray_shade_args *args,
                                      ray__spawner *sp, unsigned ns,
                                      const ray__light_frame *f,
                                      ray_brdf_fn brdf, void *ud,
                                      ray_brdf_args *b, ray_rgb *out)
{
    int packs = ray__occluded_packs(ctx->scene);
    unsigned s0, j;

    for (s0 = 0; s0 < ns; s0 += SAMPLE_BATCH) {
        ray_light_sample ls[SAMPLE_BATCH];
        int ok[SAMPLE_BATCH];
        unsigned m = ns - s0 < SAMPLE_BATCH ? ns - s0 : SAMPLE_BATCH;

        ray__light_samples(ctx, args, b->light, s0, m, f, ls, ok);
        if (packs) {
            add_batch(ctx, args, sp, ls, ok, m, brdf, ud, b, out);
            continue;
        }
        for (j = 0; j < m; j++)
            if (ok[j]) {
                b->sample = &ls[j];
                add_sample(ctx, args, sp, brdf, ud, b, out);
            }
    }
}

int ray_shade_direct(ray_ctx *ctx, const ray_shade_args *args,
                     ray_brdf_fn brdf, void *ud, ray_rgb *out)
{
    ray_brdf_args b;
    ray__spawner sp;
    unsigned li;

    if (ctx == NULL || args == NULL || args->ray == NULL ||
        args->hit == NULL || brdf == NULL || out == NULL)
        return RAY_EINVAL;
    b.shade = args;
    b.to_eye = toward_eye(args->ray->dir);
    ray__spawner_start(&sp, args->hit);
    /* The scene's lights and their strata read here, as
    ** ray_scene_light_count and ray_light_samples read them: the same
    ** counts, without two calls a hit (exported functions, which the
    ** compiler does not inline); the samples as ray_light_sample_at
    ** makes them, a sphere light's disk once for the point. */
    for (li = 0; li < ctx->scene->n_lights; li++) {
        unsigned side = ctx->scene->lights[li].side, ns = side * side;
        ray__light_frame f;
        ray_light_sample ls;

        ray__light_frame_at(ctx->scene, li, args->hit->p, &f);
        b.light = li;
        if (ns > 1)
            add_batches(ctx, args, &sp, ns, &f, brdf, ud, &b, out);
        else if (ns == 1 &&
                 ray__light_sample(ctx, args, li, 0, &f, &ls) == RAY_OK) {
            b.sample = &ls;
            add_sample(ctx, args, &sp, brdf, ud, &b, out);
        }
    }
    return RAY_OK;
}
