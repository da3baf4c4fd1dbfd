/* SPDX-License-Identifier: MIT */
/*
** tests.h -- what the Check suites in tests/ share: the suites, tolerances,
** assertions on vectors and hit records; the rest, shared with faultsim.c
** and the benchmarks, is testkit.h's.
*/
#ifndef RAY_TESTS_H
#define RAY_TESTS_H

#include <check.h>
#include "ckpass.h"   /* ck_assert_msg without a message a pass */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "ray.h"
#include "testkit.h"

Suite *version_suite(void);
Suite *sphere_suite(void);
Suite *triangle_suite(void);
Suite *plane_suite(void);
Suite *polygon_suite(void);
Suite *barycentric_suite(void);
Suite *png_suite(void);
Suite *optics_suite(void);
Suite *scene_suite(void);
Suite *trace_suite(void);
Suite *render_suite(void);
Suite *bvh_suite(void);
Suite *obj_suite(void);
Suite *effects_suite(void);
Suite *numerics_suite(void);
Suite *implicit_suite(void);
Suite *parametric_suite(void);
Suite *texture_suite(void);
Suite *bpt_suite(void);
Suite *surfaces_suite(void);
Suite *selfhit_suite(void);
Suite *null_suite(void);
Suite *defaults_suite(void);
Suite *errmsg_suite(void);
Suite *why_suite(void);
Suite *progress_suite(void);
Suite *edges_suite(void);
Suite *box_suite(void);
Suite *direct_suite(void);
Suite *capsule_suite(void);
Suite *games_suite(void);
Suite *instance_suite(void);
Suite *dynamic_suite(void);
Suite *user_suite(void);
Suite *closest_suite(void);
Suite *batch_suite(void);
Suite *lazy_suite(void);
Suite *cones_suite(void);
Suite *caustics_suite(void);
Suite *cones_caustics_hard_suite(void);
Suite *filter_suite(void);
Suite *scheduler_suite(void);
Suite *platform_suite(void);
Suite *exact_suite(void);
Suite *sweep_suite(void);
Suite *contains_suite(void);
Suite *overlap_suite(void);
Suite *slips_suite(void);

/* Double's unit roundoff, 2^-53: tolerances below are multiples of it. */
#define U64 (DBL_EPSILON * 0.5)

/* Hard cases are repeated with the whole scene moved this far from the
** world origin (loop tests take the index _i). */
#define N_OFFSETS 2
static inline double test_offset(int i)
{
    return i == 0 ? 0.0 : 1e5;
}

/*
** Tolerance for positions and t in the small exact scenes: their inputs
** and answers are exactly representable, so only the rounding of a few
** dozen operations on coordinates of magnitude |offset| + 10 is allowed:
** 64 ulps of that magnitude.
*/
static inline double tol_at(double offset)
{
    return 64 * DBL_EPSILON * (fabs(offset) + 10.0);
}

static inline ray_ray make_ray(ray_vec3 org, ray_vec3 dir, double tmin,
                               double tmax)
{
    ray_ray r;
    r.org = org;
    r.dir = dir;
    r.tmin = tmin;
    r.tmax = tmax;
    return r;
}

/* A case, or a part of one, that cannot run on this platform (a POSIX
** device on Windows, say): said on stdout, never dropped silently; the
** Windows run lists these lines (doc/PLATFORMS.md). */
static inline void test_skip(const char *test, const char *why)
{
    printf("SKIP %s: %s\n", test, why);
    fflush(stdout);
}

/*
** The count of a long differential loop (issue 38): `full` under make
** check-long (RAY_CHECK_LONG=1), which CI runs, and `quick` under make
** check, so that a first make check stays short; the environment
** variable `env` (e.g. RAY_FILTER_RAYS), when set, overrides both.
** Both counts run somewhere in CI: no coverage is lost, only moved.
*/
static inline size_t test_count(const char *env, size_t full, size_t quick)
{
    const char *v = env != NULL ? getenv(env) : NULL;
    const char *lng = getenv("RAY_CHECK_LONG");

    if (v != NULL && v[0] != '\0')
        return (size_t)strtod(v, NULL);
    return lng != NULL && strcmp(lng, "1") == 0 ? full : quick;
}

/* A ray on (0, +Inf): the usual primary ray. */
static inline ray_ray ray_from(ray_vec3 org, ray_vec3 dir)
{
    return make_ray(org, dir, 0.0, HUGE_VAL);
}

/* Fill a hit record with a byte pattern, to check that a miss leaves it
** untouched (memcmp with a second copy). */
static inline void hit_poison(ray_hit *h)
{
    memset(h, 0xA5, sizeof *h);
}

static inline int hit_is_poisoned(const ray_hit *h)
{
    ray_hit ref;
    hit_poison(&ref);
    return memcmp(h, &ref, sizeof ref) == 0;
}

/* Every double of a hit record is finite. */
static inline int hit_is_finite(const ray_hit *h)
{
    return isfinite(h->t) && isfinite(h->p.x) && isfinite(h->p.y) &&
           isfinite(h->p.z) && isfinite(h->n.x) && isfinite(h->n.y) &&
           isfinite(h->n.z) && isfinite(h->u) && isfinite(h->v) &&
           isfinite(h->p_err.x) && isfinite(h->p_err.y) &&
           isfinite(h->p_err.z);
}

/* What a material sees of a hit (shade_record, a material that shades
** nothing, keeps it): for tests of shading normals, texture
** coordinates and ids. */
typedef struct shade_seen {
    ray_vec3 shading_normal, normal;
    double u, v;
    unsigned geom_id, prim_id;
} shade_seen;

static inline void shade_record(void *ud, ray_ctx *ctx,
                                const ray_shade_args *a, ray_rgb *out)
{
    shade_seen *s = ud;
    (void)ctx;
    (void)out;
    s->shading_normal = a->shading_normal;
    s->normal = a->normal;
    s->u = a->u;
    s->v = a->v;
    s->geom_id = a->hit->geom_id;
    s->prim_id = a->hit->prim_id;
}

/* Exact equality, component by component. */
#define ck_assert_vec_eq(a, b)                                            \
    do {                                                                  \
        ck_assert_double_eq((a).x, (b).x);                                \
        ck_assert_double_eq((a).y, (b).y);                                \
        ck_assert_double_eq((a).z, (b).z);                                \
    } while (0)

/* |a - b| < tol per component (Check's comparison is strict). */
#define ck_assert_vec_eq_tol(a, b, tol)                                   \
    do {                                                                  \
        ck_assert_double_eq_tol((a).x, (b).x, (tol));                     \
        ck_assert_double_eq_tol((a).y, (b).y, (tol));                     \
        ck_assert_double_eq_tol((a).z, (b).z, (tol));                     \
    } while (0)

/* One to four random edits of buf[0 .. *n): a byte replaced by one of
** "alphabet" (alen characters), a byte deleted, or the rest cut off: the
** file readers' fuzz tests (check_obj.c, check_bpt.c). */
static inline void mutate(rng *g, char *buf, size_t *n, const char *alphabet,
                          size_t alen)
{
    size_t i, edits = 1 + rng_next(g) % 4;

    for (i = 0; i < edits && *n > 0; i++) {
        size_t at = (size_t)(rng_next(g) % *n);
        switch (rng_next(g) % 3) {
        case 0:
            buf[at] = alphabet[rng_next(g) % alen];
            break;
        case 1:
            memmove(buf + at, buf + at + 1, *n - at - 1);
            (*n)--;
            break;
        default:
            *n = at + 1;
            break;
        }
    }
}

#endif
