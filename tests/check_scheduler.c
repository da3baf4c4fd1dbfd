/* SPDX-License-Identifier: MIT */
/*
** check_scheduler.c -- the program's job system (ray_scheduler): renders,
** photon passes and builds handed to it give the bytes the built-in
** threads give, whatever order and threads run the tasks; the render
** options' scheduler, the scene's, and the built-in threads, in that
** order; the setting's rules.  (The builds' trees are compared in
** check_bvh.c.)
*/
#include <string.h>

#include "scenes.h"
#include "scheduler_kit.h"

#define W 40
#define H 30

/* The caustics scene (examples/scenes.h: glass, a ring of mirrors with
** their own scatter callback, a jittered area light) with adaptive
** antialiasing and photons: every part of a render that runs as tasks,
** the photon pass's included. */
static void options(ray_render_options *o, unsigned threads)
{
    *o = (ray_render_options){.width = W, .height = H};
    o->threads = threads;
    o->adaptive_threshold = 0.05;
    o->adaptive_depth = 2;
    o->photons = 20000;      /* 5 chunks of 4096: several tasks have some */
}

/* The built-in threads at every count give the same bytes (check_render.c
** shows it for other scenes); the reference is the one-thread image. */
static void reference(const ray_scene *s, const ray_camera *cam, float *img)
{
    ray_render_options o;

    options(&o, 1);
    ck_assert_int_eq(ray_render(s, cam, &o, img, NULL), RAY_OK);
}

/*
** A render on a scheduler is the built-in threads' image, byte for byte:
** tasks run last first, in a new random order each run, and on a pool
** of 3 threads of the test's own (in a random order, the caller only
** waiting), at 1, 2, 5 and 8 tasks; the scheduler was asked for those
** tasks (the render's, after the photon pass's).
*/
START_TEST(render_on_a_scheduler_should_give_the_built_in_bytes)
{
    static float ref[3 * W * H], img[3 * W * H];
    static const unsigned tasks[] = {1, 2, 5, 8};
    ray_camera cam;
    ray_scene *s = caustics_scene(&cam);
    test_pool *pool = pool_new(3);
    sched_log reverse_log, random_log;
    ray_scheduler sched[3];
    ray_render_options o;
    size_t k, t;

    reference(s, &cam, ref);
    sched[0] = test_scheduler(reverse_run, &reverse_log);
    sched[1] = test_scheduler(random_run, &random_log);
    sched[2] = pool_scheduler(pool);
    for (k = 0; k < 3; k++) {
        sched_log *log = k == 0 ? &reverse_log
                                : k == 1 ? &random_log : &pool->log;
        for (t = 0; t < sizeof tasks / sizeof *tasks; t++) {
            unsigned runs = log->runs;
            options(&o, tasks[t]);
            o.scheduler = &sched[k];
            memset(img, 0, sizeof img);
            ck_assert_int_eq(ray_render(s, &cam, &o, img, NULL), RAY_OK);
            ck_assert_msg(memcmp(img, ref, sizeof img) == 0,
                          "scheduler %zu, %u tasks", k, tasks[t]);
            /* The photon pass's run, then the rows'. */
            ck_assert_uint_eq(log->runs, runs + 2);
            ck_assert_uint_eq(log->last_count, tasks[t]);
        }
    }
    pool_free(pool);
    ray_scene_free(s);
}
END_TEST

/*
** The built-in threads at several counts, and the same counts of tasks on
** the pool, with photons and a progress callback (called once a chunk of
** 4096 photons, then once a row, one call at a time): one image, and the
** same photons stored.
*/
typedef struct reports {
    unsigned chunks, rows;
} reports;

static int count_reports(void *ud, unsigned done, unsigned total)
{
    reports *r = ud;

    (void)done;
    /* One call at a time (ray.h); the photon pass's total is its photons,
    ** 20000, the rows' H. */
    if (total == H)
        r->rows++;
    else
        r->chunks++;
    return 0;
}

START_TEST(built_in_threads_and_pool_should_agree_at_every_count)
{
    static float ref[3 * W * H], img[3 * W * H];
    ray_camera cam;
    ray_scene *s = caustics_scene(&cam);
    test_pool *pool = pool_new(4);
    ray_scheduler sched = pool_scheduler(pool);
    ray_render_options o;
    ray_stats a, b;
    unsigned threads;
    reports rep;

    reference(s, &cam, ref);
    for (threads = 1; threads <= 4; threads++) {
        options(&o, threads);
        ck_assert_int_eq(ray_render(s, &cam, &o, img, &a), RAY_OK);
        ck_assert(memcmp(img, ref, sizeof img) == 0);
        o.scheduler = &sched;
        rep.chunks = rep.rows = 0;
        o.progress = count_reports;
        o.progress_ud = &rep;
        memset(img, 0, sizeof img);
        ck_assert_int_eq(ray_render(s, &cam, &o, img, &b), RAY_OK);
        ck_assert(memcmp(img, ref, sizeof img) == 0);
        ck_assert_uint_eq(rep.rows, H);
        ck_assert_uint_eq(rep.chunks, 5);    /* 20000 photons: 5 chunks */
        ck_assert_uint_eq(a.photons_stored, b.photons_stored);
        ck_assert_uint_gt(b.photons_stored, 0);
    }
    pool_free(pool);
    ray_scene_free(s);
}
END_TEST

/*
** Which scheduler runs a render: the options' if set, else the scene's
** (ray_scene_set_scheduler), else the built-in threads; threads 0 takes
** the scheduler's "threads" as the task count.  The photon map of
** ray_photon_map_build on a scheduler is the built-in one: the same
** caustics through ray_caustics_at.
*/
START_TEST(options_scheduler_should_win_over_the_scene_s)
{
    static float ref[3 * W * H], img[3 * W * H];
    ray_camera cam;
    ray_scene *s = caustics_scene(&cam);
    sched_log scene_log, options_log;
    ray_scheduler on_scene = test_scheduler(random_run, &scene_log);
    ray_scheduler on_options = test_scheduler(reverse_run, &options_log);
    ray_render_options o;

    reference(s, &cam, ref);
    on_scene.threads = 3;
    ck_assert_int_eq(ray_scene_set_scheduler(s, &on_scene), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    options(&o, 0);
    ck_assert_int_eq(ray_render(s, &cam, &o, img, NULL), RAY_OK);
    ck_assert(memcmp(img, ref, sizeof img) == 0);
    ck_assert_uint_eq(scene_log.runs, 2);
    ck_assert_uint_eq(scene_log.last_count, 3);   /* its "threads" */
    o.scheduler = &on_options;
    o.threads = 2;
    ck_assert_int_eq(ray_render(s, &cam, &o, img, NULL), RAY_OK);
    ck_assert(memcmp(img, ref, sizeof img) == 0);
    ck_assert_uint_eq(scene_log.runs, 2);
    ck_assert_uint_eq(options_log.runs, 2);
    ck_assert_uint_eq(options_log.last_count, 2);
    /* A scheduler without run is no scheduler: the scene's again. */
    on_options.run = NULL;
    ck_assert_int_eq(ray_render(s, &cam, &o, img, NULL), RAY_OK);
    ck_assert_uint_eq(scene_log.runs, 4);
    ck_assert_uint_eq(options_log.runs, 2);
    /* NULL on the scene: the built-in threads. */
    ck_assert_int_eq(ray_scene_set_scheduler(s, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_render(s, &cam, &o, img, NULL), RAY_OK);
    ck_assert(memcmp(img, ref, sizeof img) == 0);
    ck_assert_uint_eq(scene_log.runs, 4);
    ray_scene_free(s);
}
END_TEST

START_TEST(photon_map_on_a_scheduler_should_be_the_built_in_one)
{
    ray_camera cam;
    ray_scene *s = caustics_scene(&cam);
    sched_log log;
    ray_scheduler sched = test_scheduler(random_run, &log);
    ray_photon_map *built_in, *scheduled;
    ray_render_options o;
    ray_ctx *a, *b;
    int i;

    options(&o, 3);
    ck_assert_int_eq(ray_photon_map_build(s, &o, &built_in), RAY_OK);
    o.scheduler = &sched;
    ck_assert_int_eq(ray_photon_map_build(s, &o, &scheduled), RAY_OK);
    ck_assert_uint_eq(log.runs, 1);
    ck_assert_uint_eq(log.last_count, 3);
    ck_assert_int_eq(ray_ctx_new(s, 7, &a), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(s, 7, &b), RAY_OK);
    ck_assert_int_eq(ray_ctx_set_photon_map(a, built_in), RAY_OK);
    ck_assert_int_eq(ray_ctx_set_photon_map(b, scheduled), RAY_OK);
    /* Through the camera's pixels: the same radiance, bit for bit. */
    for (i = 0; i < 64; i++) {
        ray_vec3 p = vec(-1.5 + 0.05 * i, 0.5, -1.0 + 0.03 * i);
        ray_ray r = make_ray(cam.position, ray_vec3_sub(p, cam.position),
                             0, HUGE_VAL);
        ray_rgb ca = {-1, -1, -1}, cb = {-2, -2, -2};
        ck_assert_int_eq(ray_trace(a, &r, RAY_KIND_PRIMARY, 1.0, &ca),
                         RAY_OK);
        ck_assert_int_eq(ray_trace(b, &r, RAY_KIND_PRIMARY, 1.0, &cb),
                         RAY_OK);
        ck_assert(memcmp(&ca, &cb, sizeof ca) == 0);
    }
    ray_ctx_free(a);
    ray_ctx_free(b);
    ray_photon_map_free(built_in);
    ray_photon_map_free(scheduled);
    ray_scene_free(s);
}
END_TEST

/*
** The setting: a zeroed scheduler is the built-in threads; NULL scene
** refused; like
** every setting it stages a change (no query until the next commit);
** a scheduler given is copied (changing the caller's struct afterwards
** changes nothing).
*/
START_TEST(scheduler_setting_should_follow_the_setting_rules)
{
    static float img[3 * W * H];
    ray_scheduler sched;
    sched_log log;
    ray_camera cam;
    ray_scene *s = caustics_scene(&cam);
    ray_render_options o;
    ray_ray r = make_ray(vec(0, 5, 0), vec(0, -1, 0), 0, HUGE_VAL);
    ray_hit h;

    memset(&sched, 0, sizeof sched);
    ck_assert_int_eq(ray_scene_set_scheduler(NULL, &sched), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_set_scheduler(NULL, NULL), RAY_EINVAL);

    sched = test_scheduler(reverse_run, &log);
    ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), 1);
    ck_assert_int_eq(ray_scene_set_scheduler(s, &sched), RAY_OK);
    ck_assert_str_eq(ray_scene_errmsg(s), "");
    ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), -RAY_ESTATE);
    options(&o, 2);
    ck_assert_int_eq(ray_render(s, &cam, &o, img, NULL), RAY_ESTATE);  /* uncommitted since the setting */
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), 1);
    sched.run = NULL;                         /* the scene kept a copy */
    ck_assert_int_eq(ray_render(s, &cam, &o, img, NULL), RAY_OK);
    ck_assert_uint_eq(log.runs, 2);
    ray_scene_free(s);
}
END_TEST

Suite *scheduler_suite(void)
{
    Suite *s = suite_create("scheduler");
    TCase *tc = tcase_create("core");

    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, render_on_a_scheduler_should_give_the_built_in_bytes);
    tcase_add_test(tc, built_in_threads_and_pool_should_agree_at_every_count);
    tcase_add_test(tc, options_scheduler_should_win_over_the_scene_s);
    tcase_add_test(tc, photon_map_on_a_scheduler_should_be_the_built_in_one);
    tcase_add_test(tc, scheduler_setting_should_follow_the_setting_rules);
    suite_add_tcase(s, tc);
    return s;
}
