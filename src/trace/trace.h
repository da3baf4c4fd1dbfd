/* SPDX-License-Identifier: MIT */
/*
** trace.h -- tracing: the per-thread context (struct ray_ctx) and the
** sampler's helpers.
*/
#ifndef RAY_TRACE_H
#define RAY_TRACE_H

#include "core/sampling.h"
#include "core/spawn.h"
#include "query/query.h"

/*
** The ray cone at the hit being shaded (trace.c's cone_at_hit), from
** which the cones of the rays its material traces are derived.
*/
typedef struct ray__hit_cone {
    int on;                  /* the hit carries a cone */
    double width;            /* the cone's signed width there (a cone
                                focused by a concave mirror or a lens
                                passes through 0 and goes on negative) */
    double spread;           /* the spread it arrived with */
    double bend;             /* the surface's curvature, signed (> 0:
                                convex toward the ray), times |width|:
                                how far the normal turns across the
                                footprint */
    ray_vec3 dir;            /* the incoming ray's unit direction */
    ray_vec3 normal;         /* the unit normal facing it */
} ray__hit_cone;

struct ray_ctx {
    const ray_scene *scene;
    ray_stats stats;
    unsigned long long rng;  /* splitmix64 state of the current sample */
    int in_shade;            /* inside a material callback */
    unsigned depth;          /* depth of the hit being shaded */
    double weight;           /* path weight of the ray being shaded */
    unsigned effects;        /* effects of the material being shaded */
    unsigned fanout;         /* secondary rays spawned by that hit so far */
    int stale;               /* a ray of the current tree met an instance
                                of a scene changed since the commit: the
                                outermost ray_trace answers RAY_ESTATE */
    /* Ray cones (trace.c): the cone of the next primary rays
    ** (ray_ctx_set_cone, ray_render), and that of the hit being shaded,
    ** for the rays its material traces. */
    double cone_width, cone_spread;
    ray__hit_cone hit_cone;
    const ray_photon_map *photons;  /* what ray_caustics_at reads: the
                                       render's map, or the one given to
                                       ray_ctx_set_photon_map; NULL: none */
};

/* splitmix64 (Steele, Lea, Flood, OOPSLA 2014): a tiny, fast, well-mixed
** generator whose state is a single counter, so a pixel's sequence can be
** started anywhere from a hash of its coordinates. */
static inline unsigned long long ray__mix64(unsigned long long z)
{
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

/* The sampler state of sample "s" of pixel (x, y) in a frame with "seed":
** a hash of all four, independent of which thread renders the pixel.
** In two steps: the frame's part, ray__frame_hash(seed), which a render
** makes once, then the pixel's and the sample's (ray__pixel_seed_from). */
static inline unsigned long long ray__frame_hash(unsigned long long seed)
{
    return ray__mix64(seed + 0x9e3779b97f4a7c15ull);
}

static inline unsigned long long ray__pixel_seed_from(unsigned long long
                                                          frame,
                                                      unsigned x, unsigned y,
                                                      unsigned s)
{
    unsigned long long h = ray__mix64(frame ^
                                      (((unsigned long long)y << 32) | x));
    return ray__mix64(h + s);
}

/* ray_ctx_random's next number of ctx (not NULL), inline for the
** library's own samplers: a light sample draws two. */
static inline double ray__ctx_random(ray_ctx *ctx)
{
    unsigned long long z = ray__mix64(ctx->rng += 0x9e3779b97f4a7c15ull);

    return (double)(z >> 11) * (1.0 / 9007199254740992.0);  /* 53 bits */
}

/* Reset a context's per-sample state. */
void ray__ctx_start(ray_ctx *ctx, unsigned long long rng);

/* The shade args of hit "hit" of ray "r" in scene "s" at "depth" with path
** weight "weight": what a material's shade (and scatter) callback gets. */
void ray__shade_args(const ray_scene *s, const ray_ray *r,
                     const ray_hit *hit, unsigned depth, double weight,
                     ray_shade_args *args);

/*
** Light samples without ray_light_sample_at's checks (light.c): the disk
** a sphere light presents to point "from", made once for all of a
** point's samples (ray__light_frame_at; ok 0 for other kinds), then
** sample "index" (< ray_light_samples) of light "light" (< the scene's
** count) for args (hit not NULL) into *out: ray_light_sample_at's answer,
** bit for bit.
*/
typedef struct ray__light_frame {
    int ok;
    ray_vec3 t1, t2;
} ray__light_frame;
void ray__sphere_light_frame(const ray_light *l, ray_vec3 from,
                             ray__light_frame *f);

/* Inline, so that the other kinds' lights (Whitted's point lights) pay
** one compare a point, not a call. */
static inline void ray__light_frame_at(const ray_scene *s, unsigned light,
                                       ray_vec3 from, ray__light_frame *f)
{
    const ray_light *l = &s->lights[light].desc;

    f->ok = 0;
    if (l->kind == RAY_LIGHT_SPHERE)
        ray__sphere_light_frame(l, from, f);
}
int ray__light_sample(ray_ctx *ctx, const ray_shade_args *args,
                      unsigned light, unsigned index,
                      const ray__light_frame *f, ray_light_sample *out);
/* Samples first .. first + count - 1 of the light into out[], ok[j] 1
** where sample first + j was made (ray__light_sample's RAY_OK), 0 where
** refused: a batch, whose chains of divisions and roots overlap. */
void ray__light_samples(ray_ctx *ctx, const ray_shade_args *args,
                        unsigned light, unsigned first, unsigned count,
                        const ray__light_frame *f, ray_light_sample *out,
                        int *ok);

/* ray_light_visible(ctx, args, sample) for args->hit == sp->hit, its
** shadow ray leaving the hit from the origins sp keeps (core/spawn.h);
** ray_light_visible is this on a spawner of its own, so both give the
** same answer and counts, bit for bit. */
int ray__light_visible(ray_ctx *ctx, ray__spawner *sp,
                       const ray_light_sample *sample);

/* ray__light_visible in two steps, for shadow rays queried together
** (direct.c).  ray__shadow_ray: RAY__SHADOW_CAST with the sample's
** shadow ray in *shadow (counted as cast); RAY__SHADOW_NONE where the
** scene's shadows are undeclared (visible, no ray; counted as such);
** RAY__SHADOW_REFUSED where no ray can be made (not visible).
** ray__shadow_passes: visible or not from the ray's occlusion answer
** (ray__occluded's: negative, a stale scene, marks ctx and is not).
** Inline, one copy for both: each runs once a shadow ray.
*/
enum { RAY__SHADOW_REFUSED, RAY__SHADOW_NONE, RAY__SHADOW_CAST };

RAY__HOT_INLINE int ray__shadow_ray(ray_ctx *ctx, ray__spawner *sp,
                                    const ray_light_sample *sample,
                                    ray_ray *shadow)
{
    int rc;

    /* Shadows undeclared: unshadowed, and no ray cast; counted, so that
    ** a forgotten flag shows (ray_stats.shadows_undeclared). */
    if ((ctx->effects & RAY_EFFECT_SHADOW) == 0) {
        ctx->stats.shadows_undeclared++;
        return RAY__SHADOW_NONE;
    }
    if (sample->dist < HUGE_VAL)
        rc = ray__spawn_to(sp, sample->point, shadow);
    else
        rc = ray_spawn(sp->hit, sample->dir, shadow);
    if (rc != RAY_OK)
        return RAY__SHADOW_REFUSED;
    ctx->stats.rays[RAY_KIND_SHADOW]++;
    return RAY__SHADOW_CAST;
}

RAY__HOT_INLINE int ray__shadow_passes(ray_ctx *ctx, int occluded)
{
    /* A negative answer (an instance's child changed since the commit)
    ** is no light: a stale scene must not pass for unoccluded; the
    ** outermost ray_trace then reports it. */
    if (occluded < 0)
        ctx->stale = 1;
    return occluded == 0;
}

/* Can material m read a ray's cone (materials.c says which can)? */
int ray__material_reads_cone(const ray_material *m);

/*
** The photon pass (photons.c): ray_photon_map_build's work, options
** already checked: o->photons photons, as o->threads tasks (0: the
** scheduler's threads, or one per online CPU) on o->scheduler, else the
** scene's, else the built-in threads; ray__photon_map_counts adds the
** map's counters (photons emitted and stored, the photon rays'
** intersection tests) to *st.
*/
int ray__photon_map_make(const ray_scene *s, const ray_render_options *o,
                         ray_photon_map **out);
void ray__photon_map_counts(const ray_photon_map *m, ray_stats *st);

/* ray_caustics_at's estimate from map m at hit point p, n the shading
** side's normal, into *irradiance (photons.c says how). */
void ray__caustics_gather(const ray_photon_map *m, ray_vec3 p, ray_vec3 n,
                          ray_rgb *irradiance);

/* Is a photon radius acceptable (0: automatic, else finite and > 0)? */
int ray__photon_radius_valid(double r);

#endif /* RAY_TRACE_H */
