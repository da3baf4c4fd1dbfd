/* SPDX-License-Identifier: MIT */
/*
** light.c -- light samples and shadow rays for material callbacks.
*/
#include <float.h>

#include "trace/trace.h"

/* Samples per shading point: side * side (ray__light.side, made when
** the light was added: area lights round their count up to a square). */
/* Light "light"'s samples, an index known to be in range. */
static unsigned samples_of(const ray_scene *s, unsigned light)
{
    unsigned k = s->lights[light].side;

    return k * k;
}

unsigned ray_light_samples(const ray_scene *s, unsigned light)
{
    if (s == NULL || light >= s->n_lights)
        return 0;
    return samples_of(s, light);
}

/*
** The disk of sphere light l facing point "from" (its silhouette from
** there): its tangents.  The same for every sample of a shading point, so
** ray_shade_direct makes it once a point and light, not once a sample: a
** normalisation and a tangent frame, about a fifth of a sample's
** instructions (callgrind, examples/mesh; issue 35).  ok 0: "from" is
** the light's centre (every sample is the centre).
*/
void ray__sphere_light_frame(const ray_light *l, ray_vec3 from,
                             ray__light_frame *f)
{
    ray_vec3 w;

    f->ok = v3_normalize(v3_sub(from, l->position), &w);
    if (f->ok)
        ray__tangent_frame(w, &f->t1, &f->t2);
}

/*
** A jittered position in stratum "index" of a k x k grid over [0,1)^2,
** mapped onto the light: the parallelogram for a rect light; for a sphere
** light, the disk of its radius facing the shading point (its silhouette,
** frame f) by Shirley and Chiu's concentric map ("A Low Distortion Map
** Between Disk and Square", JGT 2(3), 1997), which keeps the strata
** compact.
*/
static ray_vec3 area_point(ray_ctx *ctx, const ray_light *l,
                           const ray__light_frame *f, unsigned index,
                           unsigned k)
{
    double su = ((double)(index % k) + ray__ctx_random(ctx)) / (double)k;
    double sv = ((double)(index / k) + ray__ctx_random(ctx)) / (double)k;
    double dx, dy;

    if (l->kind == RAY_LIGHT_RECT)
        return v3_add(l->position, v3_add(v3_scale(l->edge1, su),
                                          v3_scale(l->edge2, sv)));
    ray__concentric_disk(2 * su - 1, 2 * sv - 1, &dx, &dy);
    if (!f->ok)
        return l->position;
    return v3_add(l->position, v3_add(v3_scale(f->t1, l->radius * dx),
                                      v3_scale(f->t2, l->radius * dy)));
}

static ray_rgb rgb_scale(ray_rgb c, double s)
{
    c.r *= s;
    c.g *= s;
    c.b *= s;
    return c;
}

int ray_light_sample_at(ray_ctx *ctx, const ray_shade_args *args,
                        unsigned light, unsigned index,
                        ray_light_sample *out)
{
    ray__light_frame f;

    if (ctx == NULL || args == NULL || args->hit == NULL || out == NULL ||
        light >= ctx->scene->n_lights ||
        index >= samples_of(ctx->scene, light))
        return RAY_EINVAL;
    ray__light_frame_at(ctx->scene, light, args->hit->p, &f);
    return ray__light_sample(ctx, args, light, index, &f, out);
}

int ray__light_sample(ray_ctx *ctx, const ray_shade_args *args,
                      unsigned light, unsigned index,
                      const ray__light_frame *f, ray_light_sample *out)
{
    const ray__light *sl;
    const ray_light *l;
    ray_light_sample ls;
    ray_vec3 p, to;
    double d2, dist, n = 1.0, scale;

    sl = &ctx->scene->lights[light];
    l = &sl->desc;
    p = args->hit->p;
    if (l->kind == RAY_LIGHT_DIRECTIONAL) {
        ls.dir = sl->axis;
        ls.dist = HUGE_VAL;
        ls.radiance = l->intensity;
        ls.point = p;
        *out = ls;
        return RAY_OK;
    }
    if (l->kind == RAY_LIGHT_POINT)
        ls.point = l->position;
    else {
        unsigned k = sl->side;
        ls.point = area_point(ctx, l, f, index, k);
        n = (double)(k * k);
    }
    to = v3_sub(ls.point, p);
    d2 = v3_dot(to, to);
    dist = sqrt(d2);
    if (!(dist > 0 && dist < HUGE_VAL))
        return RAY_EINVAL;
    /* The unit direction from the distance already taken, one division:
    ** v3_normalize's scaling (a division a component, a second square
    ** root and a third division) guards against |to|^2 overflowing or
    ** underflowing, and it cannot overflow here (dist is finite), so
    ** only an underflowed |to|^2, whose root has lost bits, goes that
    ** way.  Within 2 ulp of unit length either way; the scaled way was
    ** 17% of the bunny scene's time with this function's divisions
    ** (perf, examples/mesh; issue 35). */
    if (d2 >= DBL_MIN)
        ls.dir = v3_scale(to, 1.0 / dist);
    else if (!v3_normalize(to, &ls.dir))
        return RAY_EINVAL;
    ls.dist = dist;
    /* Inverse-square falloff, the total split evenly over the samples.
    ** A light closer than ~1e-154 would overflow 1/dist^2: refused. */
    scale = 1.0 / (dist * dist * n);
    if (!(scale < HUGE_VAL))
        return RAY_EINVAL;
    ls.radiance = rgb_scale(l->intensity, scale);
    if (l->kind == RAY_LIGHT_RECT) {
        /* A one-sided Lambertian emitter: its intensity toward the point
        ** falls with the cosine at the light, and is 0 behind it. */
        double cos_l = -v3_dot(sl->axis, ls.dir);
        ls.radiance = rgb_scale(ls.radiance, cos_l > 0 ? cos_l : 0.0);
    }
    if (!(ls.radiance.r < HUGE_VAL && ls.radiance.g < HUGE_VAL &&
          ls.radiance.b < HUGE_VAL))
        return RAY_EINVAL;
    *out = ls;
    return RAY_OK;
}

int ray_light_visible(ray_ctx *ctx, const ray_shade_args *args,
                      const ray_light_sample *sample)
{
    ray__spawner sp;

    if (ctx == NULL || args == NULL || args->hit == NULL || sample == NULL)
        return 0;
    ray__spawner_start(&sp, args->hit);
    return ray__light_visible(ctx, &sp, sample);
}

int ray__light_visible(ray_ctx *ctx, ray__spawner *sp,
                       const ray_light_sample *sample)
{
    ray_ray shadow;

    switch (ray__shadow_ray(ctx, sp, sample, &shadow)) {
    case RAY__SHADOW_NONE:
        return 1;
    case RAY__SHADOW_CAST:
        return ray__shadow_passes(
            ctx, ray__occluded(ctx->scene, &shadow, &ctx->stats));
    default:
        return 0;
    }
}

void ray__light_samples(ray_ctx *ctx, const ray_shade_args *args,
                        unsigned light, unsigned first, unsigned count,
                        const ray__light_frame *f, ray_light_sample *out,
                        int *ok)
{
    unsigned j;

    for (j = 0; j < count; j++)
        ok[j] = ray__light_sample(ctx, args, light, first + j, f, &out[j]) ==
                RAY_OK;
}
