/* SPDX-License-Identifier: MIT */
/*
** check_why.c -- why a query refused (ray.h, ray_query.why): every
** refusal of every query that takes options, provoked one at a time,
** returns its status and leaves in the caller's buffer a reason that
** names the call, the argument (the index, for an array) and the value;
** a query that answers leaves the buffer as it was; a NULL why, a
** buffer of one byte and a short buffer are safe.
*/
#include <limits.h>
#include <stdio.h>
#include <string.h>

#include "tests.h"

/* The scenes the cases query: each refusal needs one of them. */
typedef struct fixture {
    ray_scene *ok;       /* committed: a unit sphere at the origin */
    ray_scene *raw;      /* the same, never committed */
    ray_scene *top;      /* an instance (geom_id 0) of child, which was
                            changed after top's commit: stale */
    ray_scene *child;
    ray_scene *flat;     /* committed: one triangle, nothing closed */
    ray_scene *mem;      /* committed: a closed tetrahedron, its memory
                            cut off before a first ray_contains */
    long left;           /* mem's allocations left */
} fixture;

static ray_scene *sphere_scene(int commit)
{
    ray_scene *s;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1,
                                          RAY_NO_MATERIAL, NULL), RAY_OK);
    if (commit)
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    return s;
}

static void fixture_init(fixture *f)
{
    static const ray_vec3 v[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0},
                                  {0, 0, 1}};
    static const unsigned idx[12] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    ray_mesh m = {0};
    ray_transform t;

    f->ok = sphere_scene(1);
    f->raw = sphere_scene(0);
    f->child = sphere_scene(1);
    ck_assert_int_eq(ray_scene_new(&f->top, NULL, NULL), RAY_OK);
    ray_transform_identity(&t);
    ck_assert_int_eq(ray_scene_add_instance(f->top, f->child, &t, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_commit(f->top), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(f->child, vec(3, 0, 0), 1,
                                          RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_new(&f->flat, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_triangle(f->flat, vec(-1, -1, 0),
                                            vec(1, -1, 0), vec(0, 1, 0),
                                            RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(f->flat), RAY_OK);
    f->left = LONG_MAX;
    ck_assert_int_eq(ray_scene_new(&f->mem, failing_alloc, &f->left),
                     RAY_OK);
    m.vertices = v;
    m.vertex_count = 4;
    m.indices = idx;
    m.triangle_count = 4;
    ck_assert_int_eq(ray_scene_add_mesh(f->mem, &m, RAY_NO_MATERIAL, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_commit(f->mem), RAY_OK);
    f->left = 0;
}

static void fixture_free(fixture *f)
{
    ray_scene_free(f->top);   /* before the scene it instances */
    ray_scene_free(f->child);
    ray_scene_free(f->ok);
    ray_scene_free(f->raw);
    ray_scene_free(f->flat);
    ray_scene_free(f->mem);
}

/* One refusal: its status and what its reason must hold, in words. */
typedef struct refusal {
    int rc;
    const char *must[4];  /* substrings, NULL-terminated */
} refusal;

#define ESTATE_WORDS "the scene is not committed"
#define STALE_WORDS "instance 0's scene was changed"

/* The cases, in the order of run_case's switch. */
static const refusal cases[] = {
    /* ray_intersect */
    {-RAY_EINVAL, {"ray_intersect: ", "scene is NULL"}},
    {-RAY_EINVAL, {"ray_intersect: ", "r is NULL"}},
    {-RAY_EINVAL, {"ray_intersect: ", "hit is NULL"}},
    {-RAY_ESTATE, {"ray_intersect: ", ESTATE_WORDS}},
    {-RAY_ESTATE, {"ray_intersect: ", STALE_WORDS}},
    /* ray_occluded (5) */
    {-RAY_EINVAL, {"ray_occluded: ", "scene is NULL"}},
    {-RAY_EINVAL, {"ray_occluded: ", "r is NULL"}},
    {-RAY_ESTATE, {"ray_occluded: ", ESTATE_WORDS}},
    {-RAY_ESTATE, {"ray_occluded: ", STALE_WORDS}},
    /* ray_intersect_all (9) */
    {-RAY_EINVAL, {"ray_intersect_all: ", "scene is NULL"}},
    {-RAY_EINVAL, {"ray_intersect_all: ", "r is NULL"}},
    {-RAY_EINVAL, {"ray_intersect_all: ", "count is NULL"}},
    {-RAY_EINVAL, {"ray_intersect_all: ", "hits is NULL", "cap = 3"}},
    {-RAY_ESTATE, {"ray_intersect_all: ", ESTATE_WORDS}},
    {-RAY_ESTATE, {"ray_intersect_all: ", STALE_WORDS}},
    /* ray_intersect_batch (15) */
    {RAY_EINVAL, {"ray_intersect_batch: ", "scene is NULL"}},
    {RAY_EINVAL, {"ray_intersect_batch: ", "b->rays is NULL", "b->n = 2"}},
    {RAY_EINVAL, {"ray_intersect_batch: ", "b->results is NULL",
                  "b->n = 2"}},
    {RAY_EINVAL, {"ray_intersect_batch: ", "b->hits is NULL", "b->n = 2"}},
    {RAY_ESTATE, {"ray_intersect_batch: ", ESTATE_WORDS}},
    /* ray_occluded_batch (20) */
    {RAY_EINVAL, {"ray_occluded_batch: ", "scene is NULL"}},
    {RAY_EINVAL, {"ray_occluded_batch: ", "b->rays is NULL", "b->n = 2"}},
    {RAY_EINVAL, {"ray_occluded_batch: ", "b->results is NULL",
                  "b->n = 2"}},
    {RAY_ESTATE, {"ray_occluded_batch: ", ESTATE_WORDS}},
    /* ray_intersect_sweep (24) */
    {-RAY_EINVAL, {"ray_intersect_sweep: ", "scene is NULL"}},
    {-RAY_EINVAL, {"ray_intersect_sweep: ", "sweep is NULL"}},
    {-RAY_EINVAL, {"ray_intersect_sweep: ", "c is NULL"}},
    {-RAY_EINVAL, {"ray_intersect_sweep: ", "sweep->dir", "nan",
                   "not finite"}},
    {-RAY_EINVAL, {"ray_intersect_sweep: ", "sweep->tmin is -inf",
                   "not finite"}},
    {-RAY_EINVAL, {"ray_intersect_sweep: ", "sweep->tmax is 2",
                   "not above tmin 5"}},
    {-RAY_EINVAL, {"ray_intersect_sweep: ", "sweep->tmin * dir overflows",
                   "tmin 1.0000000000000001e+300", "10000000000"}},
    {-RAY_EINVAL, {"ray_intersect_sweep: ", "sweep->shape.kind is 7",
                   "RAY_SHAPE_*"}},
    {-RAY_EINVAL, {"ray_intersect_sweep: ", "sweep->shape.a (nan, 0, 0)",
                   "not finite"}},
    {-RAY_EINVAL, {"ray_intersect_sweep: ", "sweep->shape.b (0, inf, 0)",
                   "not finite"}},
    {-RAY_EINVAL, {"ray_intersect_sweep: ", "sweep->shape.b - "
                   "sweep->shape.a overflows", "1.7976931348623157e+308"}},
    {-RAY_EINVAL, {"ray_intersect_sweep: ", "sweep->shape.radius is -1",
                   "negative or not finite"}},
    {-RAY_EINVAL, {"ray_intersect_sweep: ", "sweep->shape.radius is inf"}},
    {-RAY_EINVAL, {"ray_intersect_sweep: ", "sweep->shape.box: ",
                   "half_extents", "-1"}},
    {-RAY_EKIND, {"ray_intersect_sweep: ", "RAY_SHAPE_BOX",
                  "not swept"}},
    {-RAY_ESTATE, {"ray_intersect_sweep: ", ESTATE_WORDS}},
    {-RAY_ESTATE, {"ray_intersect_sweep: ", STALE_WORDS}},
    {-RAY_ESTATE, {"ray_intersect_sweep: ", STALE_WORDS}},
    /* ray_overlap_shape (42) */
    {-RAY_EINVAL, {"ray_overlap_shape: ", "scene is NULL"}},
    {-RAY_EINVAL, {"ray_overlap_shape: ", "shape is NULL"}},
    {-RAY_EINVAL, {"ray_overlap_shape: ", "fn is NULL"}},
    {-RAY_EINVAL, {"ray_overlap_shape: ", "shape->kind is 7"}},
    {-RAY_EINVAL, {"ray_overlap_shape: ", "shape->radius is -1"}},
    {-RAY_EINVAL, {"ray_overlap_shape: ", "shape->a (nan, 0, 0)"}},
    {-RAY_EINVAL, {"ray_overlap_shape: ", "shape->box: ", "axis_y",
                   "(0, 0, 0)"}},
    {-RAY_ESTATE, {"ray_overlap_shape: ", ESTATE_WORDS}},
    {-RAY_ESTATE, {"ray_overlap_shape: ", STALE_WORDS}},
    /* ray_overlap_shape_all (51) */
    {-RAY_EINVAL, {"ray_overlap_shape_all: ", "scene is NULL"}},
    {-RAY_EINVAL, {"ray_overlap_shape_all: ", "count is NULL"}},
    {-RAY_EINVAL, {"ray_overlap_shape_all: ", "found is NULL",
                   "cap = 2"}},
    {-RAY_EINVAL, {"ray_overlap_shape_all: ", "shape->radius is -1"}},
    {-RAY_ESTATE, {"ray_overlap_shape_all: ", ESTATE_WORDS}},
    {-RAY_ESTATE, {"ray_overlap_shape_all: ", STALE_WORDS}},
    /* ray_contains (57) */
    {-RAY_EINVAL, {"ray_contains: ", "scene is NULL"}},
    {-RAY_EINVAL, {"ray_contains: ", "points is NULL", "n = 2"}},
    {-RAY_EINVAL, {"ray_contains: ", "n is 2147483648",
                   "more than INT_MAX"}},
    {-RAY_EINVAL, {"ray_contains: ", "options->flags 0x101",
                   "unknown bits 0x100"}},
    {-RAY_EINVAL, {"ray_contains: ", "points[1] (0, nan, 0)",
                   "not finite"}},
    {-RAY_ESTATE, {"ray_contains: ", ESTATE_WORDS}},
    {-RAY_ESTATE, {"ray_contains: ", STALE_WORDS}},
    {-RAY_EDEGENERATE, {"ray_contains: ", "ignore_mask 0x0",
                        "RAY_CONTAINS_WINDING"}},
    {-RAY_ENOMEM, {"ray_contains: ", "out of memory"}},
    /* ray_signed_distance (66) */
    {-RAY_EINVAL, {"ray_signed_distance: ", "distance is NULL"}},
    {-RAY_EINVAL, {"ray_signed_distance: ", "scene is NULL"}},
    {-RAY_EINVAL, {"ray_signed_distance: ", "q (inf, 0, 0)",
                   "not finite"}},
    {-RAY_EINVAL, {"ray_signed_distance: ", "radius is nan"}},
    {-RAY_EINVAL, {"ray_signed_distance: ", "radius is -0.5"}},
    {-RAY_ESTATE, {"ray_signed_distance: ", ESTATE_WORDS}},
    {-RAY_ESTATE, {"ray_signed_distance: ", STALE_WORDS}},
    {-RAY_EDEGENERATE, {"ray_signed_distance: ", "RAY_CONTAINS_WINDING"}},
    /* ray_distance_grid (74): its statuses are not negated */
    {RAY_EINVAL, {"ray_distance_grid: ", "scene is NULL"}},
    {RAY_EINVAL, {"ray_distance_grid: ", "out is NULL"}},
    {RAY_EINVAL, {"ray_distance_grid: ", "hi (1, 1, nan)", "not finite"}},
    {RAY_EINVAL, {"ray_distance_grid: ", "a count is 0", "ny 0"}},
    {RAY_EINVAL, {"ray_distance_grid: ", "options->band is -1"}},
    {RAY_EINVAL, {"ray_distance_grid: ", "overflow size_t",
                  "nx 4294967295"}},
    {RAY_EINVAL, {"ray_distance_grid: ", "unknown bits 0x100"}},
    {RAY_ESTATE, {"ray_distance_grid: ", ESTATE_WORDS}},
    {RAY_EDEGENERATE, {"ray_distance_grid: ", "RAY_CONTAINS_WINDING"}},
    /* (83) The other operands of the grid's and the sweep's tests. */
    {RAY_EINVAL, {"ray_distance_grid: ", "a count is 0", "nz 0"}},
    {RAY_EINVAL, {"ray_distance_grid: ", "a count is 0", "nx 0"}},
    {RAY_EINVAL, {"ray_distance_grid: ", "options->band is nan"}},
    {RAY_EINVAL, {"ray_distance_grid: ", "options->band is inf"}},
    {RAY_EINVAL, {"ray_distance_grid: ", "lo (-inf, -1, -1)",
                  "not finite"}},
    {-RAY_EINVAL, {"ray_intersect_sweep: ", "sweep->tmin is inf",
                   "not finite"}},
    {-RAY_EINVAL, {"ray_intersect_sweep: ", "sweep->tmin is nan",
                   "not finite"}},
};
#define N_CASES ((int)(sizeof cases / sizeof *cases))

static int stop_now(void *ud, const ray_overlap *found)
{
    (void)ud;
    (void)found;
    return 1;
}

/* A sweep that every check passes: a unit sphere from z = -5 along +z. */
static ray_sweep good_sweep(void)
{
    ray_sweep sw;

    memset(&sw, 0, sizeof sw);
    sw.shape = sphere_shape(vec(0, 0, -5), 0.5);
    sw.dir = vec(0, 0, 10);
    return sw;
}

static ray_box_params good_box(void)
{
    ray_box_params b;

    b.center = vec(0, 0, 0);
    b.half_extents = vec(1, 1, 1);
    b.axis_x = vec(1, 0, 0);
    b.axis_y = vec(0, 1, 0);
    return b;
}

/* Case i's call, its reason to q->why (or b.why, co.why). */
static int run_case(int i, fixture *f, ray_query *q, ray_batch *b,
                    ray_contains_options *co)
{
    ray_ray r = {{0, 0, -5}, {0, 0, 1}, 0, HUGE_VAL};
    ray_ray rays[2];
    int results[2];
    ray_hit hit, hits[3];
    size_t count;
    ray_sweep sw = good_sweep();
    ray_contact c;
    ray_shape k = sphere_shape(vec(0, 0, 0), 1);
    ray_box_params box = good_box();
    ray_overlap found[2];
    ray_vec3 pts[2] = {{0, 0, 0}, {0, 0, 0}};
    ray_inside in[2];
    double d;
    ray_distance_grid_options go = {.contains = *co};
    ray_vec3 lo = {-1, -1, -1}, hi = {1, 1, 1};
    float grid[8];

    rays[0] = rays[1] = r;
    b->rays = rays;
    b->n = 2;
    b->hits = hits;
    b->results = results;
    switch (i) {
    case 0: return ray_intersect(NULL, &r, &hit, q);
    case 1: return ray_intersect(f->ok, NULL, &hit, q);
    case 2: return ray_intersect(f->ok, &r, NULL, q);
    case 3: return ray_intersect(f->raw, &r, &hit, q);
    case 4: return ray_intersect(f->top, &r, &hit, q);
    case 5: return ray_occluded(NULL, &r, q);
    case 6: return ray_occluded(f->ok, NULL, q);
    case 7: return ray_occluded(f->raw, &r, q);
    case 8: return ray_occluded(f->top, &r, q);
    case 9: return ray_intersect_all(NULL, &r, q, hits, 3, &count);
    case 10: return ray_intersect_all(f->ok, NULL, q, hits, 3, &count);
    case 11: return ray_intersect_all(f->ok, &r, q, hits, 3, NULL);
    case 12: return ray_intersect_all(f->ok, &r, q, NULL, 3, &count);
    case 13: return ray_intersect_all(f->raw, &r, q, hits, 3, &count);
    case 14: return ray_intersect_all(f->top, &r, q, hits, 3, &count);
    case 15: return ray_intersect_batch(NULL, b);
    case 16: b->rays = NULL; return ray_intersect_batch(f->ok, b);
    case 17: b->results = NULL; return ray_intersect_batch(f->ok, b);
    case 18: b->hits = NULL; return ray_intersect_batch(f->ok, b);
    case 19: return ray_intersect_batch(f->raw, b);
    case 20: return ray_occluded_batch(NULL, b);
    case 21: b->rays = NULL; return ray_occluded_batch(f->ok, b);
    case 22: b->results = NULL; return ray_occluded_batch(f->ok, b);
    case 23: return ray_occluded_batch(f->raw, b);
    case 24: return ray_intersect_sweep(NULL, &sw, q, &c);
    case 25: return ray_intersect_sweep(f->ok, NULL, q, &c);
    case 26: return ray_intersect_sweep(f->ok, &sw, q, NULL);
    case 27: sw.dir.y = (double)NAN; break;
    case 28: sw.tmin = -HUGE_VAL; break;
    case 29: sw.tmin = 5; sw.tmax = 2; break;
    case 30: sw.dir = vec(0, 0, 1e10); sw.tmin = 1e300; sw.tmax = 2e300;
             break;
    case 31: sw.shape.kind = 7; break;
    case 32: sw.shape.a = vec((double)NAN, 0, 0); break;
    case 33: sw.shape.b = vec(0, HUGE_VAL, 0); break;
    case 34: sw.shape.a = vec(-DBL_MAX, 0, 0);
             sw.shape.b = vec(DBL_MAX, 0, 0); break;
    case 35: sw.shape.radius = -1; break;
    case 36: sw.shape.radius = HUGE_VAL; break;
    case 37: box.half_extents.y = -1; sw.shape = box_shape(&box); break;
    case 38: sw.shape = box_shape(&box); break;
    case 39: return ray_intersect_sweep(f->raw, &sw, q, &c);
    case 40: return ray_intersect_sweep(f->top, &sw, q, &c);
    case 41: sw.shape.radius = 0;    /* a point moving: the ray's path */
             return ray_intersect_sweep(f->top, &sw, q, &c);
    case 42: return ray_overlap_shape(NULL, &k, q, stop_now, NULL);
    case 43: return ray_overlap_shape(f->ok, NULL, q, stop_now, NULL);
    case 44: return ray_overlap_shape(f->ok, &k, q, NULL, NULL);
    case 45: k.kind = 7; return ray_overlap_shape(f->ok, &k, q, stop_now,
                                                  NULL);
    case 46: k.radius = -1; return ray_overlap_shape(f->ok, &k, q, stop_now,
                                                     NULL);
    case 47: k.a = vec((double)NAN, 0, 0);
             return ray_overlap_shape(f->ok, &k, q, stop_now, NULL);
    case 48: box.axis_y = vec(0, 0, 0); k = box_shape(&box);
             return ray_overlap_shape(f->ok, &k, q, stop_now, NULL);
    case 49: return ray_overlap_shape(f->raw, &k, q, stop_now, NULL);
    case 50: return ray_overlap_shape(f->top, &k, q, stop_now, NULL);
    case 51: return ray_overlap_shape_all(NULL, &k, q, found, 2, &count);
    case 52: return ray_overlap_shape_all(f->ok, &k, q, found, 2, NULL);
    case 53: return ray_overlap_shape_all(f->ok, &k, q, NULL, 2, &count);
    case 54: k.radius = -1;
             return ray_overlap_shape_all(f->ok, &k, q, found, 2, &count);
    case 55: return ray_overlap_shape_all(f->raw, &k, q, found, 2, &count);
    case 56: return ray_overlap_shape_all(f->top, &k, q, found, 2, &count);
    case 57: return ray_contains(NULL, pts, 2, co, in);
    case 58: return ray_contains(f->ok, NULL, 2, co, in);
    case 59: return ray_contains(f->ok, pts, (size_t)INT_MAX + 1, co, NULL);
    case 60: co->flags = 0x101; return ray_contains(f->ok, pts, 2, co, in);
    case 61: pts[1].y = (double)NAN;
             return ray_contains(f->ok, pts, 2, co, in);
    case 62: return ray_contains(f->raw, pts, 2, co, in);
    case 63: co->flags = RAY_CONTAINS_WINDING;
             return ray_contains(f->top, pts, 2, co, in);
    case 64: return ray_contains(f->flat, pts, 2, co, in);
    case 65: return ray_contains(f->mem, pts, 2, co, in);
    case 66: return ray_signed_distance(f->ok, pts[0], 1, co, NULL, NULL);
    case 67: return ray_signed_distance(NULL, pts[0], 1, co, &d, NULL);
    case 68: return ray_signed_distance(f->ok, vec(HUGE_VAL, 0, 0), 1, co,
                                        &d, NULL);
    case 69: return ray_signed_distance(f->ok, pts[0], (double)NAN, co, &d,
                                        NULL);
    case 70: return ray_signed_distance(f->ok, pts[0], -0.5, co, &d, NULL);
    case 71: return ray_signed_distance(f->raw, pts[0], 1, co, &d, NULL);
    case 72: co->flags = RAY_CONTAINS_WINDING;
             return ray_signed_distance(f->top, pts[0], 1, co, &d, NULL);
    case 73: return ray_signed_distance(f->flat, pts[0], 1, co, &d, NULL);
    case 74: return ray_distance_grid(NULL, lo, hi, 2, 2, 2, &go, grid);
    case 75: return ray_distance_grid(f->ok, lo, hi, 2, 2, 2, &go, NULL);
    case 76: hi.z = (double)NAN;
             return ray_distance_grid(f->ok, lo, hi, 2, 2, 2, &go, grid);
    case 77: return ray_distance_grid(f->ok, lo, hi, 2, 0, 2, &go, grid);
    case 78: go.band = -1;
             return ray_distance_grid(f->ok, lo, hi, 2, 2, 2, &go, grid);
    case 79: return ray_distance_grid(f->ok, lo, hi, UINT_MAX, UINT_MAX,
                                      UINT_MAX, &go, grid);
    case 80: go.contains.flags = 0x100;
             return ray_distance_grid(f->ok, lo, hi, 2, 2, 2, &go, grid);
    case 81: return ray_distance_grid(f->raw, lo, hi, 2, 2, 2, &go, grid);
    case 82: return ray_distance_grid(f->flat, lo, hi, 2, 2, 2, &go, grid);
    case 83: return ray_distance_grid(f->ok, lo, hi, 2, 2, 0, &go, grid);
    case 84: return ray_distance_grid(f->ok, lo, hi, 0, 2, 2, &go, grid);
    case 85: go.band = (double)NAN;
             return ray_distance_grid(f->ok, lo, hi, 2, 2, 2, &go, grid);
    case 86: go.band = HUGE_VAL;
             return ray_distance_grid(f->ok, lo, hi, 2, 2, 2, &go, grid);
    case 87: lo.x = -HUGE_VAL;
             return ray_distance_grid(f->ok, lo, hi, 2, 2, 2, &go, grid);
    case 88: sw.tmin = HUGE_VAL; break;
    case 89: sw.tmin = (double)NAN; break;
    default: ck_abort_msg("no case %d", i);
    }
    /* The sweep cases that broke one field of sw. */
    return ray_intersect_sweep(f->ok, &sw, q, &c);
}

/* The buffer a case's call writes its reason into. */
static const char *reason_of(int i, const ray_query *q, const ray_batch *b,
                             const ray_contains_options *co)
{
    if (i >= 15 && i < 24)
        return b->why;
    if (i >= 88)            /* the sweep's, after the grid's */
        return q->why;
    if (i >= 57)
        return co->why;
    return q->why;
}

/*
** Each refusal returns its status and names the call, the argument and
** the value (as the table says); then the same call without a buffer
** (why NULL: the options as before) and with a buffer of 1 byte (the
** reason cut to "") returns the same status.
*/
START_TEST(each_refusal_should_say_what_it_was)
{
    char why[256], small[1];
    ray_query q = {.why = why, .why_size = sizeof why};
    ray_batch b = {.why = why, .why_size = sizeof why};
    ray_contains_options co = {.why = why, .why_size = sizeof why};
    fixture f;
    int k;

    fixture_init(&f);
    memset(why, 'x', sizeof why);
    ck_assert_int_eq(run_case(_i, &f, &q, &b, &co), cases[_i].rc);
    ck_assert_ptr_eq(reason_of(_i, &q, &b, &co), why);
    ck_assert_msg(memchr(why, '\0', sizeof why) != NULL,
                  "case %d: the reason is not terminated", _i);
    for (k = 0; k < 4 && cases[_i].must[k] != NULL; k++)
        ck_assert_msg(strstr(why, cases[_i].must[k]) != NULL,
                      "case %d: \"%s\" does not say \"%s\"", _i, why,
                      cases[_i].must[k]);
    /* The reason begins with its call's name. */
    ck_assert_msg(strncmp(why, cases[_i].must[0], strlen(cases[_i].must[0]))
                  == 0, "case %d: \"%s\"", _i, why);
    /* Without a buffer, and with one byte of it: the same status. */
    q.why = b.why = co.why = NULL;
    co.flags = 0;
    ck_assert_int_eq(run_case(_i, &f, &q, &b, &co), cases[_i].rc);
    q.why = b.why = co.why = small;
    q.why_size = b.why_size = co.why_size = sizeof small;
    small[0] = 'x';
    co.flags = 0;
    ck_assert_int_eq(run_case(_i, &f, &q, &b, &co), cases[_i].rc);
    ck_assert_int_eq(small[0], '\0');
    fixture_free(&f);
}
END_TEST

/*
** A cut reason is the first why_size - 1 bytes of the whole one,
** terminated; why_size 0 writes nothing.
*/
START_TEST(a_short_buffer_should_hold_the_reason_cut)
{
    char whole[256], cut[12];
    ray_query q = {.why = whole, .why_size = sizeof whole};
    ray_ray r = {{0, 0, -5}, {0, 0, 1}, 0, HUGE_VAL};

    ck_assert_int_eq(ray_occluded(NULL, &r, &q), -RAY_EINVAL);
    ck_assert_str_eq(whole, "ray_occluded: scene is NULL");
    q.why = cut;
    q.why_size = sizeof cut;
    ck_assert_int_eq(ray_occluded(NULL, &r, &q), -RAY_EINVAL);
    ck_assert_str_eq(cut, "ray_occlude");
    memset(cut, 'x', sizeof cut);
    q.why_size = 0;
    ck_assert_int_eq(ray_occluded(NULL, &r, &q), -RAY_EINVAL);
    ck_assert_int_eq(cut[0], 'x');
}
END_TEST

/*
** A query that answers -- a hit, a miss, a count -- leaves the buffer as
** it was: the reason is written on the refusal path only.
*/
START_TEST(an_answer_should_leave_the_buffer_untouched)
{
    char why[64];
    ray_query q = {.why = why, .why_size = sizeof why};
    ray_batch b = {.why = why, .why_size = sizeof why};
    ray_contains_options co = {.why = why, .why_size = sizeof why};
    ray_ray r = {{0, 0, -5}, {0, 0, 1}, 0, HUGE_VAL};
    ray_ray miss = {{5, 5, -5}, {0, 0, 1}, 0, HUGE_VAL};
    ray_hit hit, hits[2];
    int results[2];
    size_t count;
    ray_sweep sw = good_sweep();
    ray_contact c;
    ray_overlap found[2];
    ray_vec3 p = {0, 0, 0};
    ray_inside in;
    double d;
    fixture f;
    char poison[64];

    fixture_init(&f);
    memset(poison, 'p', sizeof poison);
    memcpy(why, poison, sizeof why);
    ck_assert_int_eq(ray_intersect(f.ok, &r, &hit, &q), 1);
    ck_assert_int_eq(ray_intersect(f.ok, &miss, &hit, &q), 0);
    ck_assert_int_eq(ray_occluded(f.ok, &r, &q), 1);
    ck_assert_int_eq(ray_intersect_all(f.ok, &r, &q, hits, 2, &count), 2);
    b.rays = (const ray_ray[2]){r, miss};
    b.n = 2;
    b.hits = hits;
    b.results = results;
    ck_assert_int_eq(ray_intersect_batch(f.ok, &b), RAY_OK);
    ck_assert_int_eq(ray_occluded_batch(f.ok, &b), RAY_OK);
    ck_assert_int_eq(ray_intersect_sweep(f.ok, &sw, &q, &c), 1);
    ck_assert_int_eq(ray_overlap_shape(f.ok, TK_SPHERE(p, 1), &q, stop_now,
                                       NULL), 1);
    ck_assert_int_eq(ray_overlap_shape_all(f.ok, TK_SPHERE(p, 1), &q, found,
                                           2, &count), 1);
    ck_assert_int_eq(ray_contains(f.ok, &p, 1, &co, &in), 1);
    ck_assert_int_eq(ray_signed_distance(f.ok, p, HUGE_VAL, &co, &d, NULL),
                     1);
    ck_assert_mem_eq(why, poison, sizeof why);
    fixture_free(&f);
}
END_TEST

Suite *why_suite(void)
{
    Suite *s = suite_create("why");
    TCase *tc = tcase_create("core");

    tcase_add_loop_test(tc, each_refusal_should_say_what_it_was, 0, N_CASES);
    tcase_add_test(tc, a_short_buffer_should_hold_the_reason_cut);
    tcase_add_test(tc, an_answer_should_leave_the_buffer_untouched);
    suite_add_tcase(s, tc);
    return s;
}
