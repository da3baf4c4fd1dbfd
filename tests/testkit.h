/* SPDX-License-Identifier: MIT */
/*
** testkit.h -- what the Check suites (tests/check_*.c), the fault sweep
** (tests/faultsim.c) and the benchmarks (bench/) share, without Check:
** vector arithmetic, a fixed-seed random generator, image error, a
** material that shades nothing.  vec(), rgb() and now_seconds() are the examples' own,
** from examples/common.h (which users read, so it stays free of test
** code).  Header-only, every function static; not part of the library.
*/
#ifndef RAY_TESTKIT_H
#define RAY_TESTKIT_H

#include <math.h>
#include <string.h>
#include <stdint.h>
#include <stdlib.h>
#include <stddef.h>

#include "ray.h"
#include "common.h"

/*
** Vector arithmetic, written out here rather than taken from the
** library's src/core/vec.h, so that a test's expected value is not computed by
** the code under test.
*/
static inline ray_vec3 vadd(ray_vec3 a, ray_vec3 b)
{
    return vec(a.x + b.x, a.y + b.y, a.z + b.z);
}

static inline ray_vec3 vsub(ray_vec3 a, ray_vec3 b)
{
    return vec(a.x - b.x, a.y - b.y, a.z - b.z);
}

static inline ray_vec3 vscale(ray_vec3 a, double s)
{
    return vec(a.x * s, a.y * s, a.z * s);
}

static inline double vdot(ray_vec3 a, ray_vec3 b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

static inline double vlen(ray_vec3 a)
{
    return sqrt(vdot(a, a));
}

static inline double vdist(ray_vec3 a, ray_vec3 b)
{
    return vlen(vsub(a, b));
}

static inline ray_vec3 vcross(ray_vec3 a, ray_vec3 b)
{
    return vec(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z,
               a.x * b.y - a.y * b.x);
}

/* splitmix64 (Steele, Lea, Flood, OOPSLA 2014): a fixed-seed generator so
** every property test and benchmark sees the same inputs on every run and
** machine, with no libc state.  Seed it with rng g = {seed}. */
typedef struct rng {
    uint64_t s;
} rng;

static inline uint64_t rng_next(rng *g)
{
    uint64_t z = (g->s += 0x9e3779b97f4a7c15u);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
    return z ^ (z >> 31);
}

/* Uniform in [0, 1), 53 random bits. */
static inline double rng_unit(rng *g)
{
    return (double)(rng_next(g) >> 11) * (1.0 / 9007199254740992.0);
}

static inline double rng_range(rng *g, double lo, double hi)
{
    return lo + (hi - lo) * rng_unit(g);
}

/* Uniform direction on the unit sphere (Marsaglia-style rejection). */
static inline ray_vec3 rng_dir(rng *g)
{
    for (;;) {
        ray_vec3 v = vec(rng_range(g, -1, 1), rng_range(g, -1, 1),
                         rng_range(g, -1, 1));
        double l2 = vdot(v, v);
        if (l2 > 1e-4 && l2 <= 1)
            return vscale(v, 1.0 / sqrt(l2));
    }
}

/* A point in [lo, hi)^3. */
static inline ray_vec3 rng_point(rng *g, double lo, double hi)
{
    return vec(rng_range(g, lo, hi), rng_range(g, lo, hi),
               rng_range(g, lo, hi));
}

/* Two hits the same bit for bit, field by field (ray_hit ends in
** padding after its three ids, which a struct copy need not keep). */
static inline int hit_same(const ray_hit *a, const ray_hit *b)
{
    return memcmp(&a->t, &b->t, sizeof a->t) == 0 &&
           memcmp(&a->p, &b->p, sizeof a->p) == 0 &&
           memcmp(&a->n, &b->n, sizeof a->n) == 0 &&
           memcmp(&a->u, &b->u, sizeof a->u) == 0 &&
           memcmp(&a->v, &b->v, sizeof a->v) == 0 &&
           memcmp(&a->p_err, &b->p_err, sizeof a->p_err) == 0 &&
           a->geom_id == b->geom_id && a->prim_id == b->prim_id &&
           a->inst_id == b->inst_id;
}

/* An allocator (ray_alloc_fn) that fails once *(long *)ud allocations
** have been made: out-of-memory paths, one allocation at a time. */
static inline void *failing_alloc(void *ud, void *ptr, size_t osize,
                                  size_t nsize)
{
    long *left = ud;

    (void)osize;
    if (nsize == 0) {
        free(ptr);
        return NULL;
    }
    if (--*left < 0)
        return NULL;
    return realloc(ptr, nsize);
}

/* Root-mean-square difference of two images of n RGB pixels, values
** clamped to [0, 1] (what a display shows), over all channels. */
static inline double rmse(const float *a, const float *b, size_t n)
{
    double sum = 0;
    size_t i;

    for (i = 0; i < 3 * n; i++) {
        double x = fmin(fmax((double)a[i], 0.0), 1.0),
               y = fmin(fmax((double)b[i], 0.0), 1.0);
        sum += (x - y) * (x - y);
    }
    return sqrt(sum / (double)(3 * n));
}

/* A const pointer as the plain void * of a callback's ud (a material's,
** user geometry's: only read), without a cast that drops the qualifier. */
static inline void *ray__test_unconst(const void *p)
{
    union {
        const void *c;
        void *m;
    } u;
    u.c = p;
    return u.m;
}

/* A material that shades nothing (black), declaring no effects: for
** scenes built only to be validated or queried. */
static inline void black(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                         ray_rgb *out)
{
    (void)ud;
    (void)ctx;
    (void)a;
    (void)out;
}

static inline ray_material plain(void)
{
    ray_material m;
    m.shade = black;
    m.ud = NULL;
    m.effects = 0;
    m.scatter = NULL;
    return m;
}

/* A new scene (through "alloc", NULL for libc) whose material 0 is
** plain().  RAY_OK, or the failing call's status (nothing kept). */
static inline int nop_scene_new(ray_scene **out, ray_alloc_fn alloc,
                                void *alloc_ud)
{
    ray_material m = plain();
    ray_scene *s;
    int rc;

    rc = ray_scene_new(&s, alloc, alloc_ud);
    if (rc != RAY_OK)
        return rc;
    rc = ray_scene_add_material(s, &m, NULL);
    if (rc != RAY_OK) {
        ray_scene_free(s);
        return rc;
    }
    *out = s;
    return RAY_OK;
}

/* Shapes of the shape queries (ray_overlap_shape, ray_intersect_sweep):
** a sphere, a capsule, an oriented box; TK_SPHERE, TK_CAPSULE and TK_BOX make a
** pointer to one for a call's argument (a compound literal: it lives to
** the end of the enclosing block). */
static inline ray_shape capsule_shape(ray_vec3 a, ray_vec3 b, double r)
{
    ray_shape k;

    memset(&k, 0, sizeof k);
    k.kind = RAY_SHAPE_CAPSULE;
    k.a = a;
    k.b = b;
    k.radius = r;
    return k;
}

static inline ray_shape sphere_shape(ray_vec3 c, double r)
{
    return capsule_shape(c, c, r);
}

static inline ray_shape box_shape(const ray_box_params *b)
{
    ray_shape k;

    memset(&k, 0, sizeof k);
    k.kind = RAY_SHAPE_BOX;
    k.box = *b;
    return k;
}

#define TK_SPHERE(c, r) ((const ray_shape[]){sphere_shape((c), (r))})
#define TK_CAPSULE(a, b, r) ((const ray_shape[]){capsule_shape((a), (b), (r))})
#define TK_BOX(b) ((const ray_shape[]){box_shape(b)})

#endif
