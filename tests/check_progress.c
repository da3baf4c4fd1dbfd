/* SPDX-License-Identifier: MIT */
/*
** check_progress.c -- a commit's progress and its cancel
** (ray_scene_set_progress): the reports rise and end at done == total; a
** cancel at the first report, at one in the middle and at the last one
** returns RAY_ECANCELED and leaves the scene as before the commit, which
** then commits again and answers every ray bit for bit as a scene never
** cancelled does, on one build thread and on four.
*/
#include <string.h>

#include "tests.h"

/* A terrain of GRID x GRID quads (2 GRID^2 triangles, some thousands of
** reports' worth: 4 reports or more) and a row of spheres over it. */
#define GRID 100
#define SPHERES 40
#define MAX_CALLS 4096

typedef struct recorder {
    unsigned calls;
    unsigned cancel_at;      /* 1-based call that cancels; 0: none */
    unsigned done[MAX_CALLS], total[MAX_CALLS];
} recorder;

static int record(void *ud, unsigned done, unsigned total)
{
    recorder *r = ud;

    ck_assert_uint_lt(r->calls, MAX_CALLS);
    r->done[r->calls] = done;
    r->total[r->calls] = total;
    r->calls++;
    return r->calls == r->cancel_at;
}

/* The scene, built but not committed; "threads" build threads. */
static ray_scene *terrain(unsigned threads)
{
    static ray_vec3 v[(GRID + 1) * (GRID + 1)];
    static unsigned idx[6 * GRID * GRID];
    ray_mesh m = {0};
    ray_scene *s;
    unsigned i, j, k = 0;

    for (j = 0; j <= GRID; j++)
        for (i = 0; i <= GRID; i++)
            /* A bumpy height, so that the SAH has real choices. */
            v[j * (GRID + 1) + i] = vec(i, 0.25 * sin(0.7 * i) *
                                        cos(0.3 * j), j);
    for (j = 0; j < GRID; j++)
        for (i = 0; i < GRID; i++) {
            unsigned a = j * (GRID + 1) + i, b = a + 1,
                     c = a + GRID + 1, d = c + 1;
            idx[k++] = a, idx[k++] = c, idx[k++] = b;
            idx[k++] = b, idx[k++] = c, idx[k++] = d;
        }
    m.vertices = v;
    m.vertex_count = (GRID + 1) * (GRID + 1);
    m.indices = idx;
    m.triangle_count = 2 * GRID * GRID;
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_set_build_threads(s, threads), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, NULL),
                     RAY_OK);
    for (i = 0; i < SPHERES; i++)
        ck_assert_int_eq(ray_scene_add_sphere(s, vec(2.5 * i, 2, 50), 1,
                                              RAY_NO_MATERIAL, NULL),
                         RAY_OK);
    return s;
}

/* Every answer of a ray fan over the scene, a's equal to b's bit for bit
** (the same trees: the same hits, in every field). */
static void same_answers(const ray_scene *a, const ray_scene *b)
{
    int i, j;

    for (j = 0; j < 40; j++)
        for (i = 0; i < 40; i++) {
            ray_ray r = {{50, 10, 50},
                         {(i - 19.5) / 10, -1, (j - 19.5) / 10}, 0,
                         HUGE_VAL};
            ray_hit ha, hb;
            int ra, rb;
            hit_poison(&ha);
            hit_poison(&hb);
            ra = ray_intersect(a, &r, &ha, NULL);
            rb = ray_intersect(b, &r, &hb, NULL);
            ck_assert_int_eq(ra, rb);
            ck_assert_int_ge(ra, 0);
            ck_assert_msg(memcmp(&ha, &hb, sizeof ha) == 0,
                          "ray (%d, %d): the hits differ", i, j);
            ck_assert_int_eq(ray_occluded(a, &r, NULL),
                             ray_occluded(b, &r, NULL));
        }
}

/* Build threads of the loop tests: one (deterministic report order) and
** four (the subtrees report from several threads). */
static const unsigned threads_of[2] = {1, 4};

START_TEST(progress_should_rise_to_done)
{
    ray_scene *s = terrain(threads_of[_i]);
    recorder *r = calloc(1, sizeof *r);
    unsigned k, total = 2 * GRID * GRID + SPHERES;

    ck_assert_ptr_nonnull(r);
    ck_assert_int_eq(ray_scene_set_progress(s, record, r), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    /* 20040 primitives, a report per 4096 or more: 2 at least, and far
    ** fewer than one per primitive. */
    ck_assert_uint_ge(r->calls, 2);
    ck_assert_uint_le(r->calls, total / 1000);
    for (k = 0; k < r->calls; k++) {
        ck_assert_uint_eq(r->total[k], total);
        ck_assert_uint_le(r->done[k], total);
        if (k > 0)
            ck_assert_uint_ge(r->done[k], r->done[k - 1]);
    }
    ck_assert_uint_eq(r->done[r->calls - 1], total);
    /* A commit that builds nothing reports nothing. */
    r->calls = 0;
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_uint_eq(r->calls, 0);
    ray_scene_free(s);
    free(r);
}
END_TEST

/*
** Cancel at report 1, at the middle one and at the last (done == total):
** RAY_ECANCELED, never a call after it, the scene not committed (the
** queries -RAY_ESTATE, ray_scene_errmsg says so); committed again
** without the callback, the same answers as a scene never cancelled.
*/
START_TEST(a_cancelled_commit_should_commit_again_the_same)
{
    unsigned threads = threads_of[_i / 3], which = (unsigned)_i % 3;
    ray_scene *ref = terrain(threads), *s = terrain(threads);
    recorder *r = calloc(1, sizeof *r);
    ray_ray down = {{50, 10, 50}, {0, -1, 0}, 0, HUGE_VAL};
    ray_hit h;
    unsigned n_calls;

    ck_assert_ptr_nonnull(r);
    ck_assert_int_eq(ray_scene_set_progress(ref, record, r), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(ref), RAY_OK);
    n_calls = r->calls;
    memset(r, 0, sizeof *r);
    r->cancel_at = which == 0 ? 1 : which == 1 ? (n_calls + 1) / 2
                                               : n_calls;
    ck_assert_int_eq(ray_scene_set_progress(s, record, r), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_ECANCELED);
    ck_assert_uint_eq(r->calls, r->cancel_at);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(s), "cancelled"));
    hit_poison(&h);
    ck_assert_int_eq(ray_intersect(s, &down, &h, NULL), -RAY_ESTATE);
    ck_assert(hit_is_poisoned(&h));
    ck_assert_uint_eq(ray_scene_effects(s), 0);
    ck_assert_int_eq(ray_scene_set_progress(s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_uint_eq(r->calls, r->cancel_at);    /* removed: not called */
    same_answers(ref, s);
    ray_scene_free(ref);
    ray_scene_free(s);
    free(r);
}
END_TEST

/* A small scene is reported too: its one report is done == total. */
START_TEST(a_small_commit_should_report_once)
{
    ray_scene *s;
    recorder *r = calloc(1, sizeof *r);

    ck_assert_ptr_nonnull(r);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1,
                                          RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_set_progress(s, record, r), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_uint_eq(r->calls, 1);
    ck_assert_uint_eq(r->done[0], 1);
    ck_assert_uint_eq(r->total[0], 1);
    ck_assert_int_eq(ray_scene_set_progress(NULL, record, r), RAY_EINVAL);
    ray_scene_free(s);
    free(r);
}
END_TEST

Suite *progress_suite(void)
{
    Suite *s = suite_create("progress");
    TCase *tc = tcase_create("commit");

    tcase_add_loop_test(tc, progress_should_rise_to_done, 0, 2);
    tcase_add_loop_test(tc, a_cancelled_commit_should_commit_again_the_same,
                        0, 6);
    tcase_add_test(tc, a_small_commit_should_report_once);
    suite_add_tcase(s, tc);
    return s;
}
