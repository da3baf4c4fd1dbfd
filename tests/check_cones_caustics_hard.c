/* SPDX-License-Identifier: MIT */
/*
** check_cones_caustics_hard.c -- the hard cases of caustics, ray cones
** and mip maps (issue 19), found by a review: a photon map freed after
** its scene, the allocator's threads, absurd intensities and radii, cones
** wider than any length, mirrored instances, 16384-texel strips, scenes
** far from the origin, the sun over a pool.  Each test once failed (or
** pins down what the review checked).
*/
#include <float.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "tests.h"
#include "caustics_kit.h"

#define PI 3.14159265358979323846

/* ------------------------------------------------------------ helpers */

/* check_caustics.c's mirror scene (light (0,1,0) under a 2 x 2 mirror at
** y = 2, probe floor y = 0), through allocator "alloc", light "I". */
static ray_scene *mirror_scene(ray_alloc_fn alloc, void *ud, ray_rgb I,
                               const ray_material *floor_mat)
{
    ray_scene *s = NULL;   /* -O1 cannot see that ck_assert stops */
    ray_material probe = floor_mat ? *floor_mat : probe_material();
    ray_material mirror = ray_material_mirror(&mirror_R);
    ray_light l;
    unsigned pm, mm;

    ray_light_init(&l, RAY_LIGHT_POINT);
    l.position = vec(0, 1, 0);
    l.intensity = I;
    ck_assert_int_eq(ray_scene_new(&s, alloc, ud), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &probe, &pm), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &mirror, &mm), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 1, 0), pm,
                                         NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_triangle(s, vec(-1, 2, -1), vec(1, 2, -1),
                                            vec(1, 2, 1), mm, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_triangle(s, vec(-1, 2, -1), vec(1, 2, 1),
                                            vec(-1, 2, 1), mm, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    return s;
}

/* ---------------------------------- 1. allocator called off the caller */

typedef struct thread_alloc {
    pthread_t owner;
    pthread_mutex_t lock;        /* the test's own bookkeeping only */
    long off_thread;
} thread_alloc;

static void *owner_alloc(void *ud, void *ptr, size_t osize, size_t nsize)
{
    thread_alloc *t = ud;

    (void)osize;
    if (!pthread_equal(pthread_self(), t->owner)) {
        pthread_mutex_lock(&t->lock);
        t->off_thread++;
        pthread_mutex_unlock(&t->lock);
    }
    if (nsize == 0) {
        free(ptr);
        return NULL;
    }
    return realloc(ptr, nsize);
}

/*
** ray_scene_new: a commit "allocates on its calling thread only", and
** before issue 19 ray_render allocated only on its calling thread (workers
** and adaptive caches are allocated before the threads start).  The photon
** pass grows each chunk's buffer (photons.c store -> ray__realloc) on
** the worker threads, as ray.h (ray_scene_new) now says; with threads = 1
** it runs on the calling thread alone, so a program whose allocator is
** not thread-safe asks for one thread.
*/
START_TEST(hard_photon_pass_allocates_on_caller_thread_only)
{
    thread_alloc t;
    ray_render_options o;
    ray_photon_map *map = NULL;
    ray_scene *s = NULL;   /* -O1 cannot see that ck_assert stops */
    ray_rgb I = {1, 1, 1};

    t.owner = pthread_self();
    pthread_mutex_init(&t.lock, NULL);
    t.off_thread = 0;
    s = mirror_scene(owner_alloc, &t, I, NULL);
    o = (ray_render_options){.width = 1, .height = 1};
    o.photons = 100000;
    o.threads = 1;
    ck_assert_int_eq(ray_photon_map_build(s, &o, &map), RAY_OK);
    ray_photon_map_free(map);
    ray_scene_free(s);
    pthread_mutex_destroy(&t.lock);
    ck_assert_msg(t.off_thread == 0,
                  "%ld allocator calls on the photon threads", t.off_thread);
}
END_TEST

/* ------------------------------------- 2. map freed after its scene */

/* libc, but a block is overwritten before it is freed, so a read of freed
** scene memory finds garbage (a use after free made visible without ASan). */
static void *poison_alloc(void *ud, void *ptr, size_t osize, size_t nsize)
{
    (void)ud;
    if (nsize == 0) {
        if (ptr != NULL)
            memset(ptr, 0x5A, osize);
        free(ptr);
        return NULL;
    }
    return realloc(ptr, nsize);
}

/*
** A photon map may be freed before or after its scene (ray.h): it frees
** through a copy of the scene's allocator.  It once read the freed
** scene's allocator: a use after free, which the poisoning allocator
** below makes visible without ASan.
*/
START_TEST(hard_map_free_after_scene_free)
{
    ray_render_options o;
    ray_photon_map *map = NULL;
    ray_rgb I = {1, 1, 1};
    ray_scene *s = mirror_scene(poison_alloc, NULL, I, NULL);

    o = (ray_render_options){.width = 1, .height = 1};
    o.photons = 10000;
    o.threads = 1;
    ck_assert_int_eq(ray_photon_map_build(s, &o, &map), RAY_OK);
    ray_scene_free(s);
    ray_photon_map_free(map);   /* reads the freed scene: crashes */
}
END_TEST

/* ----------------------------- 3. photon power above FLT_MAX -> Inf/NaN */

/*
** A photon's power is stored as float (photons.c store): converting a
** power above FLT_MAX (3.4e38; intensity * omega / photons) is undefined
** behaviour (C99 6.3.1.5), in practice +Inf, which made the irradiance
** +Inf and a Phong floor with a zero diffuse channel Inf * 0 = NaN; the
** power is now clamped to FLT_MAX and the irradiance to DBL_MAX.
** The light's intensity 1e300 is finite, which ray_scene_add_light
** accepts; the true irradiance, about R I cos / d^2, is finite (~1e299).
*/
START_TEST(hard_huge_intensity_caustic_is_finite)
{
    ray_rgb I = {1e300, 1e300, 1e300};
    ray_render_options o;
    ray_photon_map *map = NULL;
    ray_scene *s = mirror_scene(NULL, NULL, I, NULL);
    ray_ctx *ctx;
    ray_rgb e;

    o = (ray_render_options){.width = 1, .height = 1};
    o.photons = 100000;
    o.photon_radius = 0.25;
    o.threads = 1;
    ck_assert_int_eq(ray_photon_map_build(s, &o, &map), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(s, 0, &ctx), RAY_OK);
    ck_assert_int_eq(ray_ctx_set_photon_map(ctx, map), RAY_OK);
    e = floor_irradiance(ctx, 0, 0);
    ck_assert_msg(isfinite(e.r) && isfinite(e.g) && isfinite(e.b),
                  "irradiance (%g, %g, %g) for a light of intensity 1e300",
                  e.r, e.g, e.b);
    ray_ctx_free(ctx);
    ray_photon_map_free(map);
    ray_scene_free(s);
}
END_TEST

START_TEST(hard_huge_intensity_phong_caustic_no_nan)
{
    static const ray_phong_params red = {{1, 0, 0}, {0, 0, 0}, 1, 0,
                                         {0, 0, 0}, {NULL, NULL}};
    ray_material floor_mat = ray_material_phong(&red);
    ray_rgb I = {1e300, 1e300, 1e300};
    ray_render_options o;
    ray_photon_map *map = NULL;
    ray_scene *s = mirror_scene(NULL, NULL, I, &floor_mat);
    ray_ctx *ctx;
    ray_rgb e;

    o = (ray_render_options){.width = 1, .height = 1};
    o.photons = 100000;
    o.photon_radius = 0.25;
    o.threads = 1;
    ck_assert_int_eq(ray_photon_map_build(s, &o, &map), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(s, 0, &ctx), RAY_OK);
    ck_assert_int_eq(ray_ctx_set_photon_map(ctx, map), RAY_OK);
    e = floor_irradiance(ctx, 0, 0);
    /* green: diffuse 0, so direct 0 and caustic 0, not NaN */
    ck_assert_msg(!isnan(e.g), "Phong floor green = %g (diffuse 0)", e.g);
    ray_ctx_free(ctx);
    ray_photon_map_free(map);
    ray_scene_free(s);
}
END_TEST

/* --------------------------------------- 4. photon_radius contract */

/*
** ray_render(3) / ray.h: RAY_EINVAL for "a photon_radius NaN, negative,
** infinite or whose pi r^2 under- or overflows".  options_valid checks
** the area too (ray__photon_radius_valid), also for a scene without
** caustics, where the photon pass (which checked it before) never runs.
*/
START_TEST(hard_render_radius_area_overflow_einval)
{
    ray_scene *s = NULL;   /* -O1 cannot see that ck_assert stops */
    ray_camera cam;
    ray_render_options o;
    float px[3] = {-1, -1, -1};

    ck_assert_int_eq(nop_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, -5), 1, 0, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    cam = (ray_camera){.look_at = {0, 0, -1}};
    o = (ray_render_options){.width = 1, .height = 1};
    o.photons = 1000;
    o.photon_radius = 1e200;    /* pi r^2 = +Inf */
    ck_assert_int_eq(ray_render(s, &cam, &o, px, NULL), RAY_EINVAL);
    ray_scene_free(s);
}
END_TEST

/* --------------------------------------------- 5. cones: NaN width */

static void cone_probe(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                       ray_rgb *out)
{
    (void)ctx;
    *(double *)ud = a->cone_width;
    out->r = a->footprint;
    out->g = out->b = 0;
}

/*
** ray_ctx_set_cone accepted any finite spread (1e300 rad): at distance 2
** the width overflowed to +Inf, the flat mirror's bend was Inf * 0 = NaN,
** and the next material saw a NaN cone_width.  A spread is now below pi,
** and widths and spreads are clamped to finite values (trace.c).
*/
START_TEST(hard_cone_width_never_nan)
{
    ray_scene *s = NULL;   /* -O1 cannot see that ck_assert stops */
    ray_material probe, mirror;
    static const ray_rgb one = {1, 1, 1};
    double seen = -1;
    ray_ctx *ctx;
    ray_rgb out;
    ray_ray r = make_ray(vec(0, 0, 0), vec(0, 0, -1), 0, HUGE_VAL);
    unsigned pm, mm;

    probe.shade = cone_probe;
    probe.ud = &seen;
    probe.effects = RAY_EFFECT_TEXTURE;
    probe.scatter = NULL;
    mirror = ray_material_mirror(&one);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &probe, &pm), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &mirror, &mm), RAY_OK);
    /* mirror plane z = -2 facing +z; probe plane z = 5 facing -z */
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, -2), vec(0, 0, 1), mm,
                                         NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 5), vec(0, 0, -1), pm,
                                         NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(s, 0, &ctx), RAY_OK);
    /* A spread of pi or more is no cone: refused, the cone unchanged. */
    ck_assert_int_eq(ray_ctx_set_cone(ctx, 0, DBL_MAX), RAY_EINVAL);
    ck_assert_int_eq(ray_ctx_set_cone(ctx, 0, 3.1416), RAY_EINVAL);
    /* The widest cone allowed, off a flat mirror: finite. */
    ck_assert_int_eq(ray_ctx_set_cone(ctx, DBL_MAX, 3.14), RAY_OK);
    ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1.0, &out),
                     RAY_OK);
    ck_assert_msg(isfinite(seen), "cone_width %g after a flat mirror", seen);
    ray_ctx_free(ctx);
    ray_scene_free(s);
    /* A cone 1e306 wide off a sphere mirror of radius 1e-3: its spread
    ** grows by 2 w / R = 2e309, beyond double; it is carried as the
    ** widest finite cone, never Inf (which the next flat surface would
    ** turn into NaN). */
    seen = -1;
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &probe, &pm), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &mirror, &mm), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, -2), 1e-3, mm, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 5), vec(0, 0, -1), pm,
                                         NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(s, 0, &ctx), RAY_OK);
    ck_assert_int_eq(ray_ctx_set_cone(ctx, 1e306, 0), RAY_OK);
    ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1.0, &out),
                     RAY_OK);
    ck_assert_msg(isfinite(seen), "cone_width %g off a tiny sphere", seen);
    ray_ctx_free(ctx);
    ray_scene_free(s);
}
END_TEST

/* --------------------------------- 6. cones through a mirrored instance */

static double reflected_cone_width(const ray_transform *xfm)
{
    ray_scene *s, *child = NULL;
    ray_material probe, mirror;
    static const ray_rgb one = {1, 1, 1};
    double seen = -1;
    ray_ctx *ctx;
    ray_rgb out;
    /* straight at the sphere's pole (0, 0, 1), back through the eye */
    ray_ray r = make_ray(vec(0.1, 0.05, 5), vec(0, 0, -1), 0, HUGE_VAL);
    unsigned pm, mm;

    probe.shade = cone_probe;
    probe.ud = &seen;
    probe.effects = RAY_EFFECT_TEXTURE;
    probe.scatter = NULL;
    mirror = ray_material_mirror(&one);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &probe, &pm), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 10), vec(0, 0, -1), pm,
                                         NULL), RAY_OK);
    if (xfm == NULL) {
        ck_assert_int_eq(ray_scene_add_material(s, &mirror, &mm), RAY_OK);
        ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1, mm, NULL),
                         RAY_OK);
    } else {
        ck_assert_int_eq(ray_scene_new(&child, NULL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_material(child, &mirror, &mm),
                         RAY_OK);
        ck_assert_int_eq(ray_scene_add_sphere(child, vec(0, 0, 0), 1, mm,
                                              NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
        ck_assert_int_eq(ray_scene_add_instance(s, child, xfm, NULL),
                         RAY_OK);
    }
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(s, 0, &ctx), RAY_OK);
    ck_assert_int_eq(ray_ctx_set_cone(ctx, 0, 0.01), RAY_OK);
    ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1.0, &out),
                     RAY_OK);
    ray_ctx_free(ctx);
    ray_scene_free(s);
    ray_scene_free(child);
    return seen;
}

START_TEST(hard_cone_mirrored_instance_same_as_plain)
{
    ray_transform x;
    double plain_w = reflected_cone_width(NULL), mirrored_w, id_w;

    ray_transform_identity(&x);
    id_w = reflected_cone_width(&x);
    x.m[0][0] = -1;             /* mirrored in x: the same sphere */
    mirrored_w = reflected_cone_width(&x);
    ck_assert_msg(plain_w > 0.5, "plain %g", plain_w);
    ck_assert_double_eq_tol(id_w, plain_w, 1e-9 * plain_w);
    ck_assert_double_eq_tol(mirrored_w, plain_w, 1e-9 * plain_w);
}
END_TEST

/* ---------------------------------------------- 7. image strips */

/* 1 x N and N x 1 at the 16384 limit: pyramid levels keep the mean. */
START_TEST(hard_image_strip_mean)
{
    const unsigned n = 16384;
    float *px = malloc(3 * sizeof(float) * n);
    ray_image *a = NULL, *b = NULL;
    ray_rgb ca, cb;
    unsigned i;

    ck_assert_ptr_nonnull(px);
    for (i = 0; i < n; i++)
        px[3 * i] = px[3 * i + 1] = px[3 * i + 2] = (float)(i % 2);
    ck_assert_int_eq(ray_image_new(1, n, px, &a), RAY_OK);
    ck_assert_int_eq(ray_image_new(n, 1, px, &b), RAY_OK);
    ck_assert_int_eq(ray_image_sample(a, 0.3, 0.7, HUGE_VAL, &ca),
                     RAY_OK);
    ck_assert_int_eq(ray_image_sample(b, 0.3, 0.7, HUGE_VAL, &cb),
                     RAY_OK);
    ck_assert_double_eq_tol(ca.r, 0.5, 1e-6);
    ck_assert_double_eq_tol(cb.r, 0.5, 1e-6);
    ck_assert_int_eq(ray_image_sample(b, 0.3, 0.7, 1.0 / 3000, &cb),
                     RAY_OK);
    ck_assert_double_eq_tol(cb.r, 0.5, 1e-6);
    ray_image_free(a);
    ray_image_free(b);
    free(px);
}
END_TEST


/* ------------------------------------- 8. a scene far from the origin */

/* The mirror scene moved by (1e8, 0, 1e8): the same irradiance under the
** mirror as at the origin, within 5 sigma of the count (N = 1e6, r =
** 0.25: about 2800 photons in the disk, 5 / sqrt(2800) = 9.4%). */
static double offset_irradiance(double off)
{
    ray_scene *s = NULL;   /* -O1 cannot see that ck_assert stops */
    ray_material probe = probe_material();
    ray_material mirror = ray_material_mirror(&mirror_R);
    ray_light l;
    ray_render_options o;
    ray_photon_map *map = NULL;
    ray_ctx *ctx;
    ray_rgb e;
    unsigned pm, mm;

    ray_light_init(&l, RAY_LIGHT_POINT);
    l.position = vec(off, 1, off);
    l.intensity = rgb(1, 1, 1);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &probe, &pm), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &mirror, &mm), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(off, 0, off), vec(0, 1, 0),
                                         pm, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_triangle(s, vec(off - 1, 2, off - 1),
                                            vec(off + 1, 2, off - 1),
                                            vec(off + 1, 2, off + 1), mm,
                                            NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_triangle(s, vec(off - 1, 2, off - 1),
                                            vec(off + 1, 2, off + 1),
                                            vec(off - 1, 2, off + 1), mm,
                                            NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    o = (ray_render_options){.width = 1, .height = 1};
    o.photons = 1000000;
    o.photon_radius = 0.25;
    o.threads = 2;
    ck_assert_int_eq(ray_photon_map_build(s, &o, &map), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(s, 0, &ctx), RAY_OK);
    ck_assert_int_eq(ray_ctx_set_photon_map(ctx, map), RAY_OK);
    e = floor_irradiance(ctx, off + 0.5, off + 0.25);
    ray_ctx_free(ctx);
    ray_photon_map_free(map);
    ray_scene_free(s);
    return e.g;
}

START_TEST(hard_caustic_far_from_origin)
{
    double near0 = offset_irradiance(0), far = offset_irradiance(1e8);
    /* want: R I cos / d^2 from the image (0, 3, 0) */
    double d2 = 0.25 + 9 + 0.0625, want = mirror_R.g * 3 / sqrt(d2) / d2;

    ck_assert_double_eq_tol(near0, want, 0.1 * want);
    ck_assert_double_eq_tol(far, want, 0.1 * want);
}
END_TEST


/* ------------------------- 9. directional light over a scattering pool */

/*
** The pool: a water surface (a glass polygon 12 x 12 at y = 1, ior 1.33)
** over a probe floor y = 0, the sun straight down (directional, I = 1),
** and one small diffuse ball (radius 0.25 at (0, 3, 0)).  Every point of
** the floor under the water receives the transmitted sunlight, (1 - F) I
** (F = ((n-1)/(n+1))^2 = 0.020 at normal incidence), at (1.5, 0) as at
** (5, 5): a directional light's photons cover the disk of the sphere
** around the scattering geometry (ray_caustics_at(3); an unbounded
** plane of water would get photons only around the bounded geometry,
** which is why the pool is a polygon).  Tolerance: the photons in the
** gather disk are about N (r / R)^2 (1 - F), R the target sphere's
** radius (the polygon's half-diagonal, sqrt 72); 5 standard deviations
** of that count.
*/
START_TEST(hard_directional_light_over_scattering_pool)
{
    static const ray_glass_params water = {1.33, {0, 0, 0}};
    ray_material probe = probe_material(), glass = ray_material_glass(&water);
    ray_material dull = plain();
    ray_render_options o;
    ray_photon_map *map = NULL;
    ray_scene *s = NULL;   /* -O1 cannot see that ck_assert stops */
    ray_ctx *ctx;
    ray_light l;
    ray_rgb at1, at5;
    ray_vec3 pool[4];
    unsigned pm, gm, dm;
    double F = (0.33 / 2.33) * (0.33 / 2.33), want = 1 - F;
    double r = 0.25, R = sqrt(72.0), N = 1e6;
    double count = N * (r / R) * (r / R) * want, tol = 5 / sqrt(count);

    ray_light_init(&l, RAY_LIGHT_DIRECTIONAL);
    l.direction = vec(0, -1, 0);
    l.intensity = rgb(1, 1, 1);
    pool[0] = vec(-6, 1, -6);
    pool[1] = vec(-6, 1, 6);
    pool[2] = vec(6, 1, 6);
    pool[3] = vec(6, 1, -6);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &probe, &pm), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &glass, &gm), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &dull, &dm), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 1, 0), pm,
                                         NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_polygon(s, pool, 4, gm, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 3, 0), 0.25, dm, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    o = (ray_render_options){.width = 1, .height = 1};
    o.photons = (unsigned long long)N;
    o.photon_radius = r;
    o.threads = 2;
    ck_assert_int_eq(ray_photon_map_build(s, &o, &map), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(s, 0, &ctx), RAY_OK);
    ck_assert_int_eq(ray_ctx_set_photon_map(ctx, map), RAY_OK);
    at1 = floor_irradiance(ctx, 1.5, 0);
    at5 = floor_irradiance(ctx, 5, 5);
    ck_assert_double_eq_tol(at1.g, want, tol * want);
    ck_assert_double_eq_tol(at5.g, want, tol * want);
    ray_ctx_free(ctx);
    ray_photon_map_free(map);
    ray_scene_free(s);
}
END_TEST

Suite *cones_caustics_hard_suite(void)
{
    Suite *s = suite_create("cones_caustics_hard");
    TCase *tc = tcase_create("core");

    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, hard_photon_pass_allocates_on_caller_thread_only);
    tcase_add_test(tc, hard_map_free_after_scene_free);
    tcase_add_test(tc, hard_huge_intensity_caustic_is_finite);
    tcase_add_test(tc, hard_huge_intensity_phong_caustic_no_nan);
    tcase_add_test(tc, hard_render_radius_area_overflow_einval);
    tcase_add_test(tc, hard_cone_width_never_nan);
    tcase_add_test(tc, hard_cone_mirrored_instance_same_as_plain);
    tcase_add_test(tc, hard_image_strip_mean);
    tcase_add_test(tc, hard_caustic_far_from_origin);
    tcase_add_test(tc, hard_directional_light_over_scattering_pool);
    suite_add_tcase(s, tc);
    return s;
}
