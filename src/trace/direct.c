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
** One light sample: its factor f from the BRDF (zero behind the shading
** normal, where the BRDF is not called), then its shadow ray.  With
** pruning, a sample that cannot add light costs no ray; without, the ray
** is cast anyway (the naive mode that pruning is measured against), and
** the sample still adds nothing.  sp: the hit's shadow-ray origins, made
** once (core/spawn.h).  Inlined in both its loops: out of line, its call
** cost the bunny scene 10M instructions (examples/mesh).
*/
RAY__HOT_INLINE void add_sample(ray_ctx *ctx, const ray_shade_args *a,
                                ray__spawner *sp, ray_brdf_fn brdf,
                                void *ud, ray_brdf_args *b, ray_rgb *out)
{
    const ray_light_sample *ls = b->sample;
    ray_rgb f = {0, 0, 0};
    int contributes;

    b->to_light = ls->dir;
    b->cos_light = v3_dot(a->shading_normal, ls->dir);
    if (b->cos_light > 0)
        f = brdf(ud, b);
    contributes = b->cos_light > 0 && rgb_any_positive(f);
    if (!contributes && a->prune)
        return;
    if (!ray__light_visible(ctx, sp, ls) || !contributes)
        return;
    out->r += f.r * ls->radiance.r;
    out->g += f.g * ls->radiance.g;
    out->b += f.b * ls->radiance.b;
}

/*
** Samples drawn a batch at a time, then weighed and tested: a sample is
** a chain of divisions and square roots (light.c) that waited on itself
** between the shadow queries, where a batch's chains overlap (the bunny
** scene, examples/mesh: 1.12 times as fast; issue 35).  The same
** random numbers in the same order, since nothing between two samples
** draws one (a shadow query none; the BRDF none unless it reaches the
** context through its ud, which ray_shade_direct(3) warns of).
*/
#define SAMPLE_BATCH 16

/* The samples of an area light (ns > 1), a batch at a time; not inlined,
** so that a point light's one sample keeps the short loop (Whitted's
** scene paid 1.5% more time for the batch's bookkeeping). */
static RAY__NOINLINE void add_batches(ray_ctx *ctx, const ray_shade_args *args,
                                      ray__spawner *sp, unsigned ns,
                                      const ray__light_frame *f,
                                      ray_brdf_fn brdf, void *ud,
                                      ray_brdf_args *b, ray_rgb *out)
{
    unsigned s0, j;

    for (s0 = 0; s0 < ns; s0 += SAMPLE_BATCH) {
        ray_light_sample ls[SAMPLE_BATCH];
        int ok[SAMPLE_BATCH];
        unsigned m = ns - s0 < SAMPLE_BATCH ? ns - s0 : SAMPLE_BATCH;

        ray__light_samples(ctx, args, b->light, s0, m, f, ls, ok);
        for (j = 0; j < m; j++) {
            if (!ok[j])
                continue;
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
