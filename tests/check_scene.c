/* SPDX-License-Identifier: MIT */
/*
** check_scene.c -- building scenes: errors, lifetime, allocator failures,
** and the ray_intersect / ray_occluded queries.
*/
#include <pthread.h>
#include <stdlib.h>

#include "tests.h"
#include "hardcases.h"

START_TEST(scene_should_assign_ids_in_order)
{
    ray_scene *s;
    ray_material m = plain();
    ray_vec3 quad[4] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    ray_light l;
    unsigned id = 99, mat = 99;

    memset(&l, 0, sizeof l);
    l.kind = RAY_LIGHT_POINT;
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, &mat), RAY_OK);
    ck_assert_uint_eq(mat, 0);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1, mat, &id), RAY_OK);
    ck_assert_uint_eq(id, 0);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 2, 0), mat, &id), RAY_OK);
    ck_assert_uint_eq(id, 1);
    ck_assert_int_eq(ray_scene_add_triangle(s, quad[0], quad[1], quad[2], mat, &id), RAY_OK);
    ck_assert_uint_eq(id, 2);
    ck_assert_int_eq(ray_scene_add_polygon(s, quad, 4, mat, &id), RAY_OK);
    ck_assert_uint_eq(id, 3);
    ck_assert_int_eq(ray_scene_add_light(s, &l, &id), RAY_OK);
    ck_assert_uint_eq(id, 0);
    ck_assert_uint_eq(ray_scene_light_count(s), 1);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ray_scene_free(s);
    ray_scene_free(NULL);
}
END_TEST

/* Bad input is refused with nothing half-added: the next good add gets
** the next id as if the bad ones never happened. */
START_TEST(scene_should_reject_bad_geometry_atomically)
{
    ray_scene *s;
    ray_material m = plain(), bad = plain();
    ray_vec3 line[3] = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
    ray_vec3 nanpoly[3] = {{0, 0, 0}, {1, 0, 0}, {0, (double)NAN, 0}};
    ray_light l;
    unsigned id = 99, mat;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, &mat), RAY_OK);
    bad.shade = NULL;
    ck_assert_int_eq(ray_scene_add_material(s, &bad, NULL), RAY_EINVAL);
    bad = plain();
    bad.effects = 64;
    ck_assert_int_eq(ray_scene_add_material(s, &bad, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_material(s, NULL, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec((double)NAN, 0, 0), 1, mat, &id), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 0, mat, &id), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), HUGE_VAL, mat, &id), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1, mat + 1, &id), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 0, 0), mat, &id), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, HUGE_VAL, 0), vec(0, 1, 0), mat, &id), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_triangle(s, line[0], line[1], line[2], mat, &id), RAY_EDEGENERATE);
    ck_assert_int_eq(ray_scene_add_triangle(s, line[0], line[1], vec(0, 0, (double)NAN), mat, &id), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_polygon(s, line, 3, mat, &id), RAY_EDEGENERATE);
    ck_assert_int_eq(ray_scene_add_polygon(s, nanpoly, 3, mat, &id), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_polygon(s, line, 2, mat, &id), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_polygon(s, NULL, 3, mat, &id), RAY_EINVAL);
    memset(&l, 0, sizeof l);
    l.kind = 17;
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_EINVAL);
    /* Zeros are defaults (check_defaults.c); these are not lights. */
    l.kind = RAY_LIGHT_DIRECTIONAL;     /* a direction not finite */
    l.direction = vec(0, (double)NAN, 0);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_EINVAL);
    l.kind = RAY_LIGHT_SPHERE;          /* a negative radius */
    l.radius = -0.5;
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_EINVAL);
    l.kind = RAY_LIGHT_RECT;            /* parallel edges */
    l.edge1 = vec(0, 0, 1);
    l.edge2 = vec(0, 0, -3);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_EINVAL);
    l.kind = RAY_LIGHT_POINT;
    l.intensity.g = -1;
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_EINVAL);
    l.intensity.g = (double)NAN;
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_EINVAL);
    /* Issue 38: each channel negative or infinite in turn, an infinite
    ** radius, a rectangle's edge not finite (either), a position not
    ** finite. */
    {
        static const ray_rgb wrong[6] = {{-1, 1, 1}, {HUGE_VAL, 1, 1},
                                         {1, HUGE_VAL, 1}, {1, 1, -1},
                                         {1, 1, HUGE_VAL}, {1, -1, 1}};
        int k;

        for (k = 0; k < 6; k++) {
            l.intensity = wrong[k];
            ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_EINVAL);
            ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(s), "intensity"));
        }
    }
    l.intensity = rgb(1, 1, 1);
    l.kind = RAY_LIGHT_SPHERE;
    l.radius = HUGE_VAL;
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_EINVAL);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(s), "radius inf"));
    l.kind = RAY_LIGHT_RECT;
    l.edge1 = vec(HUGE_VAL, 0, 0);
    l.edge2 = vec(0, 0, 1);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_EINVAL);
    l.edge1 = vec(1, 0, 0);
    l.edge2 = vec(0, 0, (double)NAN);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_EINVAL);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(s), "edges"));
    l.kind = RAY_LIGHT_DIRECTIONAL;
    l.direction = vec(0, -HUGE_VAL, 0);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_EINVAL);
    l.kind = RAY_LIGHT_POINT;
    l.position = vec(0, 0, HUGE_VAL);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_EINVAL);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(s), "position"));
    ck_assert_uint_eq(ray_scene_light_count(s), 0);
    ck_assert_uint_eq(id, 99);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1, mat, &id), RAY_OK);
    ck_assert_uint_eq(id, 0);
    ck_assert_int_eq(ray_scene_set_ambient(s, rgb(-1, 0, 0)), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_set_background(s, rgb(0, (double)NAN, 0), NULL, NULL), RAY_EINVAL);
    {
        ray_limits lim = {.max_depth = 3, .min_weight = 2.0,
                          .max_fanout = 1};
        ck_assert_int_eq(ray_scene_set_limits(s, &lim), RAY_EINVAL);
        lim.min_weight = (double)NAN;
        ck_assert_int_eq(ray_scene_set_limits(s, &lim), RAY_EINVAL);
    }
    ray_scene_free(s);
}
END_TEST

/*
** A committed scene may be changed: each change is staged and the scene
** answers no query (-RAY_ESTATE) until it is committed again; a failed
** call changes nothing and keeps it committed; a commit with nothing
** staged is a no-op that keeps answering.
*/
START_TEST(scene_changes_after_commit_should_wait_for_the_next_commit)
{
    ray_scene *s;
    ray_material m = plain();
    ray_vec3 tri[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    ray_ray down = ray_from(vec(0.25, 0.25, 5), vec(0, 0, -1));
    ray_hit h;
    unsigned mat, id = 99;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, &mat), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_intersect(s, &down, &h, NULL), 0);
    /* A bad call: an error, nothing added, still committed. */
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), -1, mat, &id), RAY_EINVAL);
    ck_assert_uint_eq(id, 99);
    ck_assert_int_eq(ray_intersect(s, &down, &h, NULL), 0);
    /* A good one: staged, invisible to queries until the commit. */
    ck_assert_int_eq(ray_scene_add_triangle(s, tri[0], tri[1], tri[2], mat, &id), RAY_OK);
    ck_assert_uint_eq(id, 0);
    ck_assert_int_eq(ray_intersect(s, &down, &h, NULL), -RAY_ESTATE);
    ck_assert_int_eq(ray_occluded(s, &down, NULL), -RAY_ESTATE);
    ck_assert_uint_eq(ray_scene_effects(s), 0);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_intersect(s, &down, &h, NULL), 1);
    ck_assert_double_eq(h.t, 5.0);                  /* exact: z 5 -> 0 */
    ck_assert_uint_eq(h.geom_id, 0);
    ck_assert_uint_eq(h.inst_id, RAY_INVALID_ID);
    ray_scene_free(s);
    ck_assert_int_eq(ray_scene_new(NULL, NULL, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_material(NULL, &m, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_commit(NULL), RAY_EINVAL);
}
END_TEST

/*
** An allocator that fails the n-th call and tracks the bytes outstanding,
** so every error path can be shown to free what it took (and nothing
** leaks at ray_scene_free), whatever call fails.
*/
typedef struct tracked {
    long calls, fail_at;
    long long outstanding;
} tracked;

static void *tracked_alloc(void *ud, void *ptr, size_t osize, size_t nsize)
{
    tracked *t = ud;
    void *p;

    if (nsize == 0) {
        t->outstanding -= (long long)osize;
        free(ptr);
        return NULL;
    }
    if (++t->calls == t->fail_at)
        return NULL;
    p = realloc(ptr, nsize);
    if (p != NULL)
        t->outstanding += (long long)nsize - (long long)osize;
    return p;
}

/* Build a scene with every kind of object; stop at the first error. */
static int build_everything(ray_scene *s)
{
    ray_material m = plain();
    ray_vec3 quad[4] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    ray_light l;
    unsigned mat;
    int rc, i;

    memset(&l, 0, sizeof l);
    if ((rc = ray_scene_add_material(s, &m, &mat)) != RAY_OK)
        return rc;
    for (i = 0; i < 20; i++) {
        double x = i;
        if ((rc = ray_scene_add_sphere(s, vec(x, 0, 0), 1, mat, NULL)) != RAY_OK ||
            (rc = ray_scene_add_triangle(s, quad[0], quad[1], vec(x, 2, 1), mat, NULL)) != RAY_OK ||
            (rc = ray_scene_add_polygon(s, quad, 4, mat, NULL)) != RAY_OK ||
            (rc = ray_scene_add_light(s, &l, NULL)) != RAY_OK)
            return rc;
    }
    return ray_scene_commit(s);
}

START_TEST(scene_should_survive_every_allocation_failure)
{
    long n;
    int saw_ok = 0;

    for (n = 1; n < 200 && !saw_ok; n++) {
        tracked t = {0, 0, 0};
        ray_scene *s = NULL;
        int rc;

        t.fail_at = n;
        rc = ray_scene_new(&s, tracked_alloc, &t);
        if (rc == RAY_OK) {
            rc = build_everything(s);
            /* Reported in the scene's fixed buffer, which needs no memory. */
            if (rc == RAY_ENOMEM)
                ck_assert_msg(strstr(ray_scene_errmsg(s), ": out of memory") != NULL,
                              "fail_at %ld: \"%s\"", n, ray_scene_errmsg(s));
            ray_scene_free(s);
        }
        ck_assert_msg(rc == RAY_OK || rc == RAY_ENOMEM, "fail_at %ld: %d", n, rc);
        saw_ok = rc == RAY_OK;
        ck_assert_msg(t.outstanding == 0, "fail_at %ld: %lld bytes leaked",
                      n, t.outstanding);
    }
    ck_assert(saw_ok);
}
END_TEST

/*
** A refit whose allocations fail, each in turn (the list of leaves and
** the slots' vertex indices it makes once a tree, accel/refit.c and
** scene/triangles.c): the commit still succeeds, reading through the
** meshes instead, and the scene answers as one built afresh from the
** moved vertices, bit for bit; nothing leaks.  Two refits after each
** failure, so that the second makes what the first could not.
*/
START_TEST(refit_should_survive_every_allocation_failure)
{
    hc_mesh ball = hc_icosphere(vec(0, 0, 0), 3);
    ray_vec3 *v = malloc(ball.nv * sizeof *v);
    long n;
    int done = 0;

    for (n = 1; n < 100 && !done; n++) {
        tracked t = {0, 0, 0};
        ray_mesh m = hc_ray_mesh(&ball);
        ray_scene *s = NULL, *fresh = NULL;
        rng g = {41};
        unsigned id;
        int round, k;

        memcpy(v, ball.v, ball.nv * sizeof *v);
        m.vertices = v;
        ck_assert_int_eq(ray_scene_new(&s, tracked_alloc, &t), RAY_OK);
        ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, &id),
                         RAY_OK);
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        t.fail_at = t.calls + n;
        for (round = 0; round < 2; round++) {
            size_t i;
            for (i = 0; i < ball.nv; i++)
                v[i] = vadd(v[i], vscale(rng_dir(&g), 0.02));
            ck_assert_int_eq(ray_scene_update_mesh(s, id, &m), RAY_OK);
            ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        }
        done = t.calls < t.fail_at;      /* no allocation failed: the end */
        ck_assert_int_eq(ray_scene_new(&fresh, NULL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_mesh(fresh, &m, RAY_NO_MATERIAL, NULL),
                         RAY_OK);
        ck_assert_int_eq(ray_scene_commit(fresh), RAY_OK);
        for (k = 0; k < 300; k++) {
            ray_vec3 to = vscale(rng_dir(&g), 0.5);
            ray_ray r = ray_from(vscale(rng_dir(&g), 5), vec(0, 0, 0));
            ray_hit a, b;
            int ha, hb;
            r.dir = vsub(to, r.org);
            ha = ray_intersect(s, &r, &a, NULL);
            hb = ray_intersect(fresh, &r, &b, NULL);
            ck_assert_int_eq(ha, hb);
            if (ha == 1)
                ck_assert_msg(hit_same(&a, &b), "fail_at %ld, ray %d", n, k);
        }
        ray_scene_free(fresh);
        ray_scene_free(s);
        ck_assert_msg(t.outstanding == 0, "fail_at %ld: %lld bytes leaked",
                      n, t.outstanding);
    }
    ck_assert(done);
    hc_mesh_free(&ball);
    free(v);
}
END_TEST

START_TEST(intersect_should_find_nearest_and_any)
{
    ray_scene *s;
    ray_material m = plain();
    unsigned mat, near_id, far_id;
    ray_ray r = ray_from(vec(0, 0, 10), vec(0, 0, -1));
    ray_hit h;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, &mat), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, -5), 1, mat, &far_id), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1, mat, &near_id), RAY_OK);
    hit_poison(&h);
    /* Not committed: a negated status, so that it is not read as a miss. */
    ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), -RAY_ESTATE);
    ck_assert_int_eq(ray_occluded(s, &r, NULL), -RAY_ESTATE);
    ck_assert(hit_is_poisoned(&h));
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), 1);
    ck_assert_uint_eq(h.geom_id, near_id);
    ck_assert_double_eq_tol(h.t, 9.0, 1e-14);
    ck_assert_int_eq(ray_occluded(s, &r, NULL), 1);
    r.tmax = 8.0;
    ck_assert_int_eq(ray_occluded(s, &r, NULL), 0);
    r.org = vec(0, 0, -2);
    r.tmax = HUGE_VAL;
    ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), 1);
    ck_assert_uint_eq(h.geom_id, far_id);
    hit_poison(&h);
    ck_assert_int_eq(ray_intersect(NULL, &r, &h, NULL), -RAY_EINVAL);
    ck_assert_int_eq(ray_intersect(s, NULL, &h, NULL), -RAY_EINVAL);
    ck_assert_int_eq(ray_intersect(s, &r, NULL, NULL), -RAY_EINVAL);
    ck_assert_int_eq(ray_occluded(NULL, &r, NULL), -RAY_EINVAL);
    ck_assert_int_eq(ray_occluded(s, NULL, NULL), -RAY_EINVAL);
    ck_assert(hit_is_poisoned(&h));
    /* An invalid ray is not misuse: it is a miss, as for the primitives. */
    r.dir = vec(0, 0, 0);
    ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), 0);
    ck_assert_int_eq(ray_occluded(s, &r, NULL), 0);
    r.dir = vec((double)NAN, 0, -1);
    ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), 0);
    ck_assert_int_eq(ray_occluded(s, &r, NULL), 0);
    ck_assert(hit_is_poisoned(&h));
    ray_scene_free(s);
}
END_TEST

/*
** Queries from several threads on one committed scene (ray_intersect,
** ray_occluded, and ray_trace through a context per thread): every
** thread must get the answers a lone thread got, bit for bit.  Under
** make tsan this is the race check of the query path.
*/
#define QUERY_THREADS 4
#define QUERY_RAYS 512

typedef struct query_answers {
    ray_hit hit[QUERY_RAYS];
    int found[QUERY_RAYS], blocked[QUERY_RAYS];
    ray_rgb colour[QUERY_RAYS];
} query_answers;

typedef struct query_job {
    const ray_scene *s;
    const ray_ray *rays;
    query_answers *out;
    int rc;
} query_job;

static void *query_thread(void *arg)
{
    query_job *j = arg;
    ray_ctx *ctx;
    int i;

    j->rc = ray_ctx_new(j->s, 7, &ctx);
    if (j->rc != RAY_OK)
        return NULL;
    memset(j->out, 0, sizeof *j->out);
    for (i = 0; i < QUERY_RAYS && j->rc == RAY_OK; i++) {
        j->out->found[i] = ray_intersect(j->s, &j->rays[i], &j->out->hit[i],
                                         NULL);
        j->out->blocked[i] = ray_occluded(j->s, &j->rays[i], NULL);
        j->rc = ray_trace(ctx, &j->rays[i], RAY_KIND_PRIMARY, 1,
                          &j->out->colour[i]);
    }
    ray_ctx_free(ctx);
    return NULL;
}

START_TEST(queries_from_several_threads_should_agree_with_one)
{
    static const ray_phong_params grey = {{0.6, 0.6, 0.6}, {0.3, 0.3, 0.3},
                                          10, 0, {0.2, 0.2, 0.2}, {NULL, NULL}};
    static query_answers ref, got[QUERY_THREADS];
    static ray_ray rays[QUERY_RAYS];
    ray_material m = ray_material_phong(&grey);
    query_job jobs[QUERY_THREADS + 1];
    pthread_t threads[QUERY_THREADS];
    ray_torus_params torus = {{10, 1, 0}, {0, 1, 0}, 2, 0.5};
    ray_light l;
    ray_scene *s;
    rng g = {99};
    unsigned mat;
    int i, k, hits = 0;

    memset(&l, 0, sizeof l);
    l.kind = RAY_LIGHT_SPHERE;
    l.position = vec(10, 8, 5);
    l.radius = 1;
    l.intensity = rgb(50, 50, 50);
    l.samples = 4;
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, &mat), RAY_OK);
    for (i = 0; i < 20; i++) {
        ck_assert_int_eq(ray_scene_add_sphere(s, vec(i, 0, 0), 0.6, mat, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_triangle(s, vec(i, 1, 0), vec(i + 1, 1, 0),
                                                vec(i, 2, 1), mat, NULL), RAY_OK);
    }
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, -1, 0), vec(0, 1, 0), mat, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_torus(s, &torus, mat, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    for (i = 0; i < QUERY_RAYS; i++)
        rays[i] = ray_from(rng_point(&g, -2, 22), rng_dir(&g));
    jobs[QUERY_THREADS].s = s;
    jobs[QUERY_THREADS].rays = rays;
    jobs[QUERY_THREADS].out = &ref;
    query_thread(&jobs[QUERY_THREADS]);
    ck_assert_int_eq(jobs[QUERY_THREADS].rc, RAY_OK);
    for (k = 0; k < QUERY_THREADS; k++) {
        jobs[k] = jobs[QUERY_THREADS];
        jobs[k].out = &got[k];
        jobs[k].rc = -1;
        ck_assert_int_eq(pthread_create(&threads[k], NULL, query_thread, &jobs[k]), 0);
    }
    for (k = 0; k < QUERY_THREADS; k++)
        ck_assert_int_eq(pthread_join(threads[k], NULL), 0);
    for (k = 0; k < QUERY_THREADS; k++) {
        ck_assert_int_eq(jobs[k].rc, RAY_OK);
        for (i = 0; i < QUERY_RAYS; i++)
            ck_assert_msg(hit_same(&got[k].hit[i], &ref.hit[i]) &&
                          got[k].found[i] == ref.found[i] &&
                          got[k].blocked[i] == ref.blocked[i] &&
                          memcmp(&got[k].colour[i], &ref.colour[i],
                                 sizeof ref.colour[i]) == 0,
                          "thread %d answered ray %d differently", k, (int)i);
    }
    /* The rays must test something: most start among the objects. */
    for (i = 0; i < QUERY_RAYS; i++)
        hits += ref.found[i] == 1;
    ck_assert_int_gt(hits, QUERY_RAYS / 4);
    ray_scene_free(s);
}
END_TEST

Suite *scene_suite(void)
{
    Suite *s = suite_create("scene");
    TCase *tc = tcase_create("build");
    TCase *q = tcase_create("query");

    tcase_add_test(tc, scene_should_assign_ids_in_order);
    tcase_add_test(tc, scene_should_reject_bad_geometry_atomically);
    tcase_add_test(tc, scene_changes_after_commit_should_wait_for_the_next_commit);
    tcase_add_test(tc, scene_should_survive_every_allocation_failure);
    tcase_add_test(tc, refit_should_survive_every_allocation_failure);
    tcase_add_test(q, intersect_should_find_nearest_and_any);
    tcase_add_test(q, queries_from_several_threads_should_agree_with_one);
    suite_add_tcase(s, tc);
    suite_add_tcase(s, q);
    return s;
}
