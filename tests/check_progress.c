/* SPDX-License-Identifier: MIT */
/*
** check_progress.c -- a commit's progress and its cancel
** (ray_scene_set_progress): the reports rise and end at done == total; a
** cancel at the first report, at one in the middle and at the last one
** returns RAY_ECANCELED and leaves the scene as before the commit, which
** then commits again and answers every ray bit for bit as a scene never
** cancelled does, on one build thread and on four.  And the photon pass
** of ray_photon_map_build and ray_render (ray_render_options.progress):
** a report per chunk of 4096 photons, rising to done == total, then the
** render's rows; a cancel in the pass returns RAY_ECANCELED with the map,
** the image and the counters untouched, and the scene renders the same
** bytes afterwards.
*/
#include <string.h>

#include "tests.h"
#include "scenes.h"

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

/* ------------------------------------------------------ the photon pass */

#define W 40
#define H 30
/* 5 chunks of 4096 photons (the pass's unit of work and of report), the
** last one partial: 5 reports, and every one of 3 tasks has a chunk. */
#define PHOTONS 20000u
#define CHUNKS 5u

static ray_render_options photon_options(unsigned threads)
{
    ray_render_options o = {.width = W, .height = H};

    o.threads = threads;
    o.photons = PHOTONS;
    return o;
}

/* Photon pass threads of the loop tests: one (reports in chunk order)
** and three (chunks finish in any order, reports still rise). */
static const unsigned pass_threads[2] = {1, 3};

/*
** ray_photon_map_build's reports: one a chunk, done rising to PHOTONS,
** total PHOTONS in each; ray_render's: the same, then one a row (total
** H, done 1 .. H); the render with reports is the render without, byte
** for byte, with the same photons stored.
*/
START_TEST(photon_pass_should_report_every_chunk_then_the_rows)
{
    static float ref[3 * W * H], img[3 * W * H];
    ray_camera cam;
    ray_scene *s = caustics_scene(&cam);
    ray_render_options o = photon_options(pass_threads[_i]);
    recorder *r = calloc(1, sizeof *r);
    ray_photon_map *map = NULL;
    ray_stats a, b;
    unsigned k;

    ck_assert_ptr_nonnull(r);
    ck_assert_int_eq(ray_render(s, &cam, &o, ref, &a), RAY_OK);
    o.progress = record;
    o.progress_ud = r;
    ck_assert_int_eq(ray_photon_map_build(s, &o, &map), RAY_OK);
    ck_assert_ptr_nonnull(map);
    ck_assert_uint_eq(r->calls, CHUNKS);
    for (k = 0; k < CHUNKS; k++) {
        ck_assert_uint_eq(r->total[k], PHOTONS);
        ck_assert_uint_le(r->done[k], PHOTONS);
        if (k > 0)
            ck_assert_uint_gt(r->done[k], r->done[k - 1]);
    }
    ck_assert_uint_eq(r->done[CHUNKS - 1], PHOTONS);
    ray_photon_map_free(map);
    memset(r, 0, sizeof *r);
    ck_assert_int_eq(ray_render(s, &cam, &o, img, &b), RAY_OK);
    ck_assert_mem_eq(img, ref, sizeof ref);
    ck_assert_uint_eq(b.photons_stored, a.photons_stored);
    ck_assert_uint_gt(b.photons_stored, 0);
    ck_assert_uint_eq(r->calls, CHUNKS + H);
    ck_assert_uint_eq(r->done[CHUNKS - 1], PHOTONS);
    for (k = 0; k < H; k++) {
        ck_assert_uint_eq(r->total[CHUNKS + k], H);
        ck_assert_uint_eq(r->done[CHUNKS + k], k + 1);
    }
    ray_scene_free(s);
    free(r);
}
END_TEST

/*
** Cancel the pass at its first report, a middle one and its last (done
** == total): RAY_ECANCELED and no call after it, from
** ray_photon_map_build (*out untouched) and from ray_render (the image
** and the counters untouched: no row was started); then the render
** without the callback gives the reference bytes.
*/
START_TEST(cancelled_photon_pass_should_keep_nothing)
{
    static float ref[3 * W * H], img[3 * W * H], poison[3 * W * H];
    static const unsigned cancel_at[3] = {1, (CHUNKS + 1) / 2, CHUNKS};
    ray_camera cam;
    ray_scene *s = caustics_scene(&cam);
    ray_render_options o = photon_options(pass_threads[_i / 3]);
    recorder *r = calloc(1, sizeof *r);
    ray_photon_map *map = (ray_photon_map *)&o;      /* a sentinel */
    ray_stats st, st_poison;

    ck_assert_ptr_nonnull(r);
    ck_assert_int_eq(ray_render(s, &cam, &o, ref, NULL), RAY_OK);
    o.progress = record;
    o.progress_ud = r;
    r->cancel_at = cancel_at[_i % 3];
    ck_assert_int_eq(ray_photon_map_build(s, &o, &map), RAY_ECANCELED);
    ck_assert_ptr_eq(map, (ray_photon_map *)&o);
    ck_assert_uint_eq(r->calls, r->cancel_at);
    memset(r->done, 0, sizeof r->done);
    r->calls = 0;
    memset(poison, 0x5a, sizeof poison);
    memcpy(img, poison, sizeof img);
    memset(&st_poison, 0x5a, sizeof st_poison);
    st = st_poison;
    ck_assert_int_eq(ray_render(s, &cam, &o, img, &st), RAY_ECANCELED);
    ck_assert_uint_eq(r->calls, r->cancel_at);   /* no row reported */
    ck_assert_mem_eq(img, poison, sizeof img);
    ck_assert_mem_eq(&st, &st_poison, sizeof st);
    o.progress = NULL;
    ck_assert_int_eq(ray_render(s, &cam, &o, img, NULL), RAY_OK);
    ck_assert_mem_eq(img, ref, sizeof ref);
    ray_scene_free(s);
    free(r);
}
END_TEST

/* A pass that traces nothing (a scene without caustics) reports
** nothing: the render's reports are its rows alone. */
START_TEST(photon_pass_without_caustics_should_not_report)
{
    static float img[3 * W * H];
    ray_camera cam = {.position = {0, 0, 5}, .look_at = {0, 0, 0}};
    ray_scene *s;
    ray_material m = plain();
    ray_light l;
    ray_render_options o = photon_options(2);
    recorder *r = calloc(1, sizeof *r);
    ray_photon_map *map = NULL;

    ck_assert_ptr_nonnull(r);
    ray_light_init(&l, RAY_LIGHT_POINT);
    l.position = vec(0, 5, 5);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1, 0, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_uint_eq(ray_scene_effects(s) & RAY_EFFECT_CAUSTICS, 0);
    o.progress = record;
    o.progress_ud = r;
    ck_assert_int_eq(ray_photon_map_build(s, &o, &map), RAY_OK);
    ck_assert_uint_eq(r->calls, 0);
    ray_photon_map_free(map);
    ck_assert_int_eq(ray_render(s, &cam, &o, img, NULL), RAY_OK);
    ck_assert_uint_eq(r->calls, H);
    ck_assert_uint_eq(r->total[0], H);
    ray_scene_free(s);
    free(r);
}
END_TEST

Suite *progress_suite(void)
{
    Suite *s = suite_create("progress");
    TCase *tc = tcase_create("commit");
    TCase *pass = tcase_create("photons");

    tcase_add_loop_test(tc, progress_should_rise_to_done, 0, 2);
    tcase_add_loop_test(tc, a_cancelled_commit_should_commit_again_the_same,
                        0, 6);
    tcase_add_test(tc, a_small_commit_should_report_once);
    suite_add_tcase(s, tc);
    tcase_add_loop_test(pass, photon_pass_should_report_every_chunk_then_the_rows,
                        0, 2);
    tcase_add_loop_test(pass, cancelled_photon_pass_should_keep_nothing, 0, 6);
    tcase_add_test(pass, photon_pass_without_caustics_should_not_report);
    suite_add_tcase(s, pass);
    return s;
}
