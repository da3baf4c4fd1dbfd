/* SPDX-License-Identifier: MIT */
/*
** check_render.c -- ray_render: determinism across thread counts and
** region splits, cancellation, options, and the pixels themselves.
*/
#include <pthread.h>
#include <stdlib.h>

#include "tests.h"

#define W 37
#define H 23

/*
** A small asymmetric scene that uses every source of randomness: a red
** sphere on the left, a blue glass sphere on the right, a checker floor,
** a rect area light (jittered samples) and depth of field.
*/
typedef struct test_scene {
    ray_phong_params red, white, grey;
    ray_glass_params glass;
    ray_checker_params checker;
    ray_scene *scene;
    ray_camera cam;
} test_scene;

static void build(test_scene *t)
{
    ray_material m;
    ray_light l;
    unsigned red, glass, floor;

    memset(t, 0, sizeof *t);
    t->red.diffuse = rgb(0.9, 0.05, 0.05);
    t->red.specular = rgb(0.3, 0.3, 0.3);
    t->red.shininess = 20;
    t->white.diffuse = rgb(0.8, 0.8, 0.8);
    t->grey.diffuse = rgb(0.2, 0.2, 0.2);
    t->glass.ior = 1.5;
    t->glass.absorption = rgb(1.0, 0.6, 0.0);
    t->checker.even = ray_material_phong(&t->white);
    t->checker.odd = ray_material_phong(&t->grey);
    t->checker.scale = 2;
    ck_assert_int_eq(ray_scene_new(&t->scene, NULL, NULL), RAY_OK);
    m = ray_material_phong(&t->red);
    ck_assert_int_eq(ray_scene_add_material(t->scene, &m, &red), RAY_OK);
    m = ray_material_glass(&t->glass);
    ck_assert_int_eq(ray_scene_add_material(t->scene, &m, &glass), RAY_OK);
    m = ray_material_checker(&t->checker);
    ck_assert_int_eq(ray_scene_add_material(t->scene, &m, &floor), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(t->scene, vec(-1.2, 1, 0), 1, red, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(t->scene, vec(1.2, 1, 0), 1, glass, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(t->scene, vec(0, 0, 0), vec(0, 1, 0), floor, NULL), RAY_OK);
    memset(&l, 0, sizeof l);
    l.kind = RAY_LIGHT_RECT;
    l.position = vec(-1, 5, -1);
    l.edge1 = vec(2, 0, 0);
    l.edge2 = vec(0, 0, 2);       /* (2,0,0) x (0,0,2) = (0,-4,0): down */
    l.intensity = rgb(30, 30, 30);
    l.samples = 4;
    ck_assert_int_eq(ray_scene_add_light(t->scene, &l, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_set_background(t->scene, rgb(0.1, 0.2, 0.9), NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(t->scene), RAY_OK);
    t->cam.position = vec(0, 1.5, 6);
    t->cam.look_at = vec(0, 1, 0);
    t->cam.up = vec(0, 1, 0);
    t->cam.vfov = 50;
    t->cam.aperture = 0.1;
}

static float *render_with(test_scene *t, unsigned threads, unsigned y0,
                          unsigned y1, ray_stats *st)
{
    ray_render_options opt;
    float *img = malloc(sizeof(float) * 3 * W * H);

    ck_assert_ptr_nonnull(img);
    opt = (ray_render_options){.width = W, .height = H};
    opt.threads = threads;
    opt.samples = 4;
    opt.seed = 2026;
    opt.y0 = y0;
    opt.y1 = y1;
    ck_assert_int_eq(ray_render(t->scene, &t->cam, &opt, img, st), RAY_OK);
    return img;
}

START_TEST(render_should_be_identical_for_any_thread_count)
{
    test_scene t;
    unsigned counts[] = {2, 3, 8, 0};
    ray_stats s1, sn;
    float *ref, *img;
    int k;

    build(&t);
    ref = render_with(&t, 1, 0, 0, &s1);
    ck_assert_uint_eq(s1.rays[RAY_KIND_PRIMARY], W * H * 4);
    for (k = 0; k < 4; k++) {
        img = render_with(&t, counts[k], 0, 0, &sn);
        ck_assert_msg(memcmp(img, ref, sizeof(float) * 3 * W * H) == 0,
                      "%u threads differ", counts[k]);
        ck_assert_uint_eq(sn.rays[RAY_KIND_SHADOW], s1.rays[RAY_KIND_SHADOW]);
        ck_assert_uint_eq(sn.tests, s1.tests);
        free(img);
    }
    free(ref);
    ray_scene_free(t.scene);
}
END_TEST

START_TEST(render_regions_should_stitch_bit_exactly)
{
    test_scene t;
    unsigned cuts[] = {0, 7, 8, 20, H};
    float *ref, *full = malloc(sizeof(float) * 3 * W * H);
    int k;

    build(&t);
    ref = render_with(&t, 2, 0, 0, NULL);
    for (k = 0; k < 4; k++) {
        float *part = render_with(&t, 2, cuts[k], cuts[k + 1], NULL);
        memcpy(full + 3 * W * cuts[k], part,
               sizeof(float) * 3 * W * (cuts[k + 1] - cuts[k]));
        free(part);
    }
    ck_assert(memcmp(full, ref, sizeof(float) * 3 * W * H) == 0);
    free(full);
    free(ref);
    ray_scene_free(t.scene);
}
END_TEST

/*
** Several ray_render calls on one scene at once, each with its own
** buffer and two threads of its own (ray_render(3): a committed scene is
** read-only, so any number of renders may share it).  Each image must be
** the bytes of a render made alone; under make tsan this is also the
** race check of the renderer's shared state.
*/
#define CONCURRENT_RENDERS 3

typedef struct render_call {
    test_scene *t;
    float *img;
    int rc;
} render_call;

static void *render_thread(void *arg)
{
    render_call *c = arg;
    ray_render_options opt;

    opt = (ray_render_options){.width = W, .height = H};
    opt.threads = 2;
    opt.samples = 4;
    opt.seed = 2026;
    c->rc = ray_render(c->t->scene, &c->t->cam, &opt, c->img, NULL);
    return NULL;
}

START_TEST(concurrent_renders_of_one_scene_should_match_a_lone_render)
{
    test_scene t;
    render_call calls[CONCURRENT_RENDERS];
    pthread_t threads[CONCURRENT_RENDERS];
    float *ref;
    int k;

    build(&t);
    ref = render_with(&t, 2, 0, 0, NULL);
    for (k = 0; k < CONCURRENT_RENDERS; k++) {
        calls[k].t = &t;
        calls[k].img = calloc(3 * W * H, sizeof(float));
        calls[k].rc = -1;
        ck_assert_ptr_nonnull(calls[k].img);
        ck_assert_int_eq(pthread_create(&threads[k], NULL, render_thread,
                                        &calls[k]), 0);
    }
    for (k = 0; k < CONCURRENT_RENDERS; k++)
        ck_assert_int_eq(pthread_join(threads[k], NULL), 0);
    for (k = 0; k < CONCURRENT_RENDERS; k++) {
        ck_assert_int_eq(calls[k].rc, RAY_OK);
        ck_assert_msg(memcmp(calls[k].img, ref, sizeof(float) * 3 * W * H) == 0,
                      "concurrent render %d differs", k);
        free(calls[k].img);
    }
    free(ref);
    ray_scene_free(t.scene);
}
END_TEST

/* Cancel after 3 rows: no further callbacks, RAY_ECANCELED. */
static int cancel_after_three(void *ud, unsigned done, unsigned total)
{
    unsigned *calls = ud;

    ck_assert_uint_eq(total, H);
    ck_assert_uint_le(done, H);
    (*calls)++;
    return *calls >= 3;
}

START_TEST(render_should_cancel_from_progress)
{
    test_scene t;
    ray_render_options opt;
    float *img = malloc(sizeof(float) * 3 * W * H);
    unsigned calls = 0;

    build(&t);
    opt = (ray_render_options){.width = W, .height = H};
    opt.threads = 2;
    opt.progress = cancel_after_three;
    opt.progress_ud = &calls;
    ck_assert_int_eq(ray_render(t.scene, &t.cam, &opt, img, NULL), RAY_ECANCELED);
    ck_assert_uint_eq(calls, 3);
    free(img);
    ray_scene_free(t.scene);
}
END_TEST

/* Pixels: the left sphere is red, the sky at the top is the background,
** the glass sphere's absorption (1.0, 0.6, 0.0) takes red out of what it
** shows. */
START_TEST(render_should_put_colours_where_the_scene_is)
{
    test_scene t;
    float *img;
    const float *left, *top, *glass;

    build(&t);
    img = render_with(&t, 2, 0, 0, NULL);
    left = img + 3 * (11 * W + 10);
    top = img + 3 * (0 * W + 18);
    glass = img + 3 * (11 * W + 26);
    ck_assert(left[0] > 3 * left[1] && left[0] > 3 * left[2]);
    ck_assert_double_eq_tol(top[0], 0.1, 1e-6);
    ck_assert_double_eq_tol(top[2], 0.9, 1e-6);
    ck_assert(glass[2] > glass[0]);
    free(img);
    ray_scene_free(t.scene);
}
END_TEST

START_TEST(render_should_reject_bad_options)
{
    test_scene t;
    ray_render_options opt;
    ray_camera cam;
    float img[3 * W * H];
    ray_scene *open_scene;

    build(&t);
    opt = (ray_render_options){.width = W, .height = H};
    ck_assert_int_eq(ray_render(NULL, &t.cam, &opt, img, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_render(t.scene, NULL, &opt, img, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_render(t.scene, &t.cam, NULL, img, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_render(t.scene, &t.cam, &opt, NULL, NULL), RAY_EINVAL);
    opt.y0 = 5;
    opt.y1 = 5;
    ck_assert_int_eq(ray_render(t.scene, &t.cam, &opt, img, NULL), RAY_EINVAL);
    opt.y0 = 0;
    opt.y1 = H + 1;
    ck_assert_int_eq(ray_render(t.scene, &t.cam, &opt, img, NULL), RAY_EINVAL);
    opt = (ray_render_options){.width = 0, .height = H};
    ck_assert_int_eq(ray_render(t.scene, &t.cam, &opt, img, NULL), RAY_EINVAL);
    opt = (ray_render_options){.width = W, .height = H};
    opt.samples = 0;                           /* zero is the default: 1 */
    ck_assert_int_eq(ray_render(t.scene, &t.cam, &opt, img, NULL), RAY_OK);
    opt.samples = RAY_MAX_PIXEL_SAMPLES + 1;   /* also: no endless loop */
    ck_assert_int_eq(ray_render(t.scene, &t.cam, &opt, img, NULL), RAY_EINVAL);
    opt.samples = 0xffffffffu;
    ck_assert_int_eq(ray_render(t.scene, &t.cam, &opt, img, NULL), RAY_EINVAL);
    opt = (ray_render_options){.width = W, .height = H};
    cam = t.cam;
    cam.look_at = cam.position;
    ck_assert_int_eq(ray_render(t.scene, &cam, &opt, img, NULL), RAY_EINVAL);
    cam = t.cam;
    cam.position = vec(0, 1, 6);
    cam.look_at = vec(0, 1, 0);
    cam.up = vec(0, 0, -1);           /* parallel to the view direction */
    ck_assert_int_eq(ray_render(t.scene, &cam, &opt, img, NULL), RAY_EINVAL);
    /* Issue 14, defect 3: parallel, yet the rounded cross product is not
    ** zero (~1e-16 |up|): refused by the angle test; and at any scale of
    ** up.  An up 1e-12 rad off the view axis is a real direction. */
    cam.position = vec(0, 1, 5);
    cam.look_at = vec(0, 0, 0);
    cam.up = vec(0, -1, -5);
    ck_assert_int_eq(ray_render(t.scene, &cam, &opt, img, NULL), RAY_EINVAL);
    cam.up = vec(0, -1e-200, -5e-200);
    ck_assert_int_eq(ray_render(t.scene, &cam, &opt, img, NULL), RAY_EINVAL);
    cam.up = vec(0, 1e200, 5e200);
    ck_assert_int_eq(ray_render(t.scene, &cam, &opt, img, NULL), RAY_EINVAL);
    cam.up = vec(5e-12, -1, -5);
    ck_assert_int_eq(ray_render(t.scene, &cam, &opt, img, NULL), RAY_OK);
    cam = t.cam;
    cam.vfov = 180;
    ck_assert_int_eq(ray_render(t.scene, &cam, &opt, img, NULL), RAY_EINVAL);
    cam.vfov = (double)NAN;
    ck_assert_int_eq(ray_render(t.scene, &cam, &opt, img, NULL), RAY_EINVAL);
    /* Not committed: RAY_ESTATE, as the queries answer (-RAY_ESTATE). */
    ck_assert_int_eq(ray_scene_new(&open_scene, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_render(open_scene, &t.cam, &opt, img, NULL), RAY_ESTATE);
    ray_scene_free(open_scene);
    ray_scene_free(t.scene);
}
END_TEST

/* One refusal: a change to good options or camera, the code ray_render
** returns for it, and a word its reason must name. */
typedef struct refusal {
    const char *what;
    int code;
} refusal;

static const refusal refusals[] = {
    {"width", RAY_EINVAL},            /* 0: width 0 */
    {"height", RAY_EINVAL},           /* 1: height 0 */
    {"y1 24 is beyond", RAY_EINVAL},  /* 2: y1 > height */
    {"y0 5 is not below", RAY_EINVAL},   /* 3: y0 = y1 */
    {"samples 4294967295", RAY_EINVAL},   /* 4 (0 is the default, 1) */
    {"samples 65537", RAY_EINVAL},    /* 5 */
    {"adaptive_threshold -1", RAY_EINVAL},  /* 6 */
    {"adaptive_depth 9", RAY_EINVAL}, /* 7 */
    {"photons", RAY_EINVAL},          /* 8: above the cap */
    {"photon_radius -1", RAY_EINVAL}, /* 9 */
    {"vfov 180", RAY_EINVAL},         /* 10 */
    {"coincide", RAY_EINVAL},         /* 11: eye at look_at */
    {"up (0, 0, -1)", RAY_EINVAL},    /* 12: up along the view */
    {"aperture -1", RAY_EINVAL},      /* 13 */
    {"not committed", RAY_ESTATE},    /* 14: changed since the commit */
    {"camera is NULL", RAY_EINVAL},   /* 15 */
    /* Each other operand of the camera's tests (issue 38). */
    {"position, look_at or up", RAY_EINVAL},  /* 16: position NaN */
    {"position, look_at or up", RAY_EINVAL},  /* 17: look_at infinite */
    {"position, look_at or up", RAY_EINVAL},  /* 18: up NaN */
    {"aperture inf", RAY_EINVAL},     /* 19 */
    {"aperture nan", RAY_EINVAL},     /* 20 */
    {"focus_distance -1", RAY_EINVAL},   /* 21 */
    {"focus_distance inf", RAY_EINVAL},  /* 22 */
    {"focus_distance nan", RAY_EINVAL},  /* 23 */
};
#define N_REFUSALS (sizeof refusals / sizeof refusals[0])

static void break_one(int k, ray_render_options *o, ray_camera *c,
                      ray_scene *s)
{
    switch (k) {
    case 0: o->width = 0; break;
    case 1: o->height = 0; break;
    case 2: o->y1 = H + 1; break;
    case 3: o->y0 = 5; o->y1 = 5; break;
    case 4: o->samples = 0xffffffffu; break;
    case 5: o->samples = RAY_MAX_PIXEL_SAMPLES + 1; break;
    case 6: o->adaptive_threshold = -1; break;
    case 7: o->adaptive_threshold = 0.1; o->adaptive_depth = 9; break;
    case 8: o->photons = RAY_MAX_PHOTONS + 1; break;
    case 9: o->photon_radius = -1; break;
    case 10: c->vfov = 180; break;
    case 11: c->look_at = c->position; break;
    case 12: c->look_at = vec(c->position.x, c->position.y, 0);
             c->up = vec(0, 0, -1); break;
    case 13: c->aperture = -1; break;
    case 14: ck_assert_int_eq(ray_scene_set_limits(s, NULL), RAY_OK); break;
    case 16: c->position.y = (double)NAN; break;
    case 17: c->look_at.z = -HUGE_VAL; break;
    case 18: c->up.x = (double)NAN; break;
    case 19: c->aperture = HUGE_VAL; break;
    case 20: c->aperture = (double)NAN; break;
    case 21: c->focus_distance = -1; break;
    case 22: c->focus_distance = HUGE_VAL; break;
    case 23: c->focus_distance = (double)NAN; break;
    default: break;
    }
}

/*
** Issue 29: a refused render says which argument or field and why, as
** the building calls do, through ray_render_check, which returns the
** very code ray_render returned and names the field with its value; the
** scene's own message (ray_scene_errmsg) is left alone, for ray_render's
** scene is const and shared between threads.  The message is always
** NUL-terminated: cut to size - 1 bytes in a short buffer, nothing
** written with size 0, "" for good arguments.
*/
START_TEST(render_check_should_say_which_option_and_why)
{
    const refusal *f = &refusals[_i];
    test_scene t;
    ray_render_options o;
    ray_camera cam;
    char msg[256], small[16];
    float img[3 * W * H];
    int rc;

    build(&t);
    o = (ray_render_options){.width = W, .height = H};
    cam = t.cam;
    ck_assert_int_eq(ray_render_check(t.scene, &cam, &o, NULL, msg, sizeof msg), RAY_OK);
    ck_assert_str_eq(msg, "");
    break_one(_i, &o, &cam, t.scene);
    rc = ray_render(t.scene, _i == 15 ? NULL : &cam, &o, img, NULL);
    ck_assert_int_eq(rc, f->code);
    memset(msg, 'x', sizeof msg);
    ck_assert_int_eq(ray_render_check(t.scene, _i == 15 ? NULL : &cam, &o, NULL,
                                      msg, sizeof msg), rc);
    ck_assert_msg(strncmp(msg, "ray_render: ", 12) == 0 &&
                  strstr(msg, f->what) != NULL,
                  "refusal %d: \"%s\" does not name \"%s\"", _i, msg,
                  f->what);
    ck_assert_str_eq(ray_scene_errmsg(t.scene), "");
    /* Short buffer: cut, terminated; no buffer: the code alone. */
    ck_assert_int_eq(ray_render_check(t.scene, _i == 15 ? NULL : &cam, &o, NULL,
                                      small, sizeof small), rc);
    ck_assert_uint_eq(strlen(small), sizeof small - 1);
    ck_assert(strncmp(small, msg, sizeof small - 1) == 0);
    small[0] = 'x';
    ck_assert_int_eq(ray_render_check(t.scene, _i == 15 ? NULL : &cam, &o, NULL,
                                      small, 0), rc);
    ck_assert_int_eq(small[0], 'x');
    ck_assert_int_eq(ray_render_check(t.scene, _i == 15 ? NULL : &cam, &o, NULL,
                                      NULL, 64), rc);
    ray_scene_free(t.scene);
}
END_TEST

/*
** The other side of each range: the last value every option and camera
** field accepts is accepted (a "<" slipped to "<=" in a check refuses
** it; the refusals above only catch the first value out).  Checked by
** ray_render_check, which makes ray_render's very checks, without the
** cost of rendering 65536 samples a pixel.
*/
START_TEST(render_check_should_accept_the_last_value_of_each_range)
{
    test_scene t;
    ray_render_options o;
    ray_camera cam;
    char msg[256];
    int k;

    build(&t);
    for (k = 0; k < 9; k++) {
        o = (ray_render_options){.width = W, .height = H};
        cam = t.cam;
        switch (k) {
        case 0: o.samples = RAY_MAX_PIXEL_SAMPLES; break;
        case 1: o.y0 = H - 1; o.y1 = H; break;
        case 2: o.adaptive_threshold = 0.1; o.adaptive_depth = 8; break;
        case 3: o.adaptive_threshold = 0.1; o.adaptive_depth = 1; break;
        case 4: o.adaptive_threshold = HUGE_VAL; break;     /* corners only */
        case 5: o.photons = RAY_MAX_PHOTONS; break;
        case 6: cam.vfov = nextafter(180, 0); break;
        case 7: cam.vfov = nextafter(0, 1); break;
        default: cam.aperture = 0; cam.focus_distance = 0; break;
        }
        ck_assert_msg(ray_render_check(t.scene, &cam, &o, NULL, msg, sizeof msg) ==
                          RAY_OK, "edge %d refused: %s", k, msg);
    }
    ray_scene_free(t.scene);
}
END_TEST

/* ----------------------------------------- counters summed over threads */

/* A keep-all filter; counts its calls when ud is not NULL (one render
** thread only: no two calls overlap). */
static int keep_and_count(void *ud, const ray_ray *r,
                          const ray_hit *candidate, void *query_ud)
{
    (void)r;
    (void)candidate;
    (void)query_ud;
    if (ud != NULL)
        ++*(unsigned long long *)ud;
    return 1;
}

/* A material that asks for one shadow ray per shade without declaring
** RAY_EFFECT_SHADOW (the slip the counter exposes), counting its calls
** when ud is not NULL. */
static void forgetful_shade(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                            ray_rgb *out)
{
    ray_light_sample ls;
    ray_ray mirror;
    ray_rgb seen;

    if (ud != NULL)
        ++*(unsigned long long *)ud;
    *out = rgb(0.5, 0.5, 0.5);
    if (ray_light_sample_at(ctx, a, 0, 0, &ls) == RAY_OK &&
        !ray_light_visible(ctx, a, &ls))
        *out = rgb(0, 0, 0);
    /* And a reflection it did not declare either: refused, and counted
    ** (ray_stats.traces_undeclared), one per shade. */
    mirror.org = a->hit->p;
    mirror.dir = a->hit->n;
    mirror.tmin = 0;
    mirror.tmax = HUGE_VAL;
    if (ray_trace(ctx, &mirror, RAY_KIND_REFLECTION, 0.5, &seen) !=
        RAY_EEFFECT)
        *out = rgb(1, 0, 0);
}

static ray_stats render_counted(unsigned threads, unsigned long long *filters,
                                unsigned long long *shades)
{
    ray_material m;
    ray_light l;
    ray_camera cam;
    ray_render_options o;
    ray_scene *s;
    ray_stats st;
    float img[3 * W * H];
    unsigned mat, ball;

    m.shade = forgetful_shade;
    m.ud = shades;
    m.effects = 0;
    m.scatter = NULL;
    ray_light_init(&l, RAY_LIGHT_POINT);
    l.position = vec(2, 5, 3);
    cam = (ray_camera){.look_at = {0, 0, -1}};
    cam.position = vec(0, 2, 6);
    cam.look_at = vec(0, 0.5, 0);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, &mat), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 1, 0), 1, mat, &ball), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 1, 0), mat, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_set_filter(s, ball, keep_and_count, filters,
                                          RAY_FILTER_INTERSECT), RAY_OK);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    o = (ray_render_options){.width = W, .height = H};
    o.threads = threads;
    o.samples = 4;
    ck_assert_int_eq(ray_render(s, &cam, &o, img, &st), RAY_OK);
    ray_scene_free(s);
    return st;
}

/*
** ray_render's counters are its threads' counters summed, every one of
** them: on one thread they equal what the callbacks counted themselves
** (filter calls; shadow requests dropped for want of RAY_EFFECT_SHADOW
** and reflections refused for want of RAY_EFFECT_REFLECTION, one each
** per shade), exactly, and on three threads they are the same
** numbers (the work does not depend on the split).  A counter the sum
** forgot reads 0 on three threads, or on one.
*/
START_TEST(render_stats_should_sum_every_counter_over_threads)
{
    unsigned long long filters = 0, shades = 0;
    ray_stats one = render_counted(1, &filters, &shades);
    ray_stats three = render_counted(3, NULL, NULL);
    int k;

    ck_assert_uint_gt(filters, 0);
    ck_assert_uint_gt(shades, 0);
    ck_assert_uint_eq(one.filter_calls, filters);
    ck_assert_uint_eq(one.shadows_undeclared, shades);
    ck_assert_uint_eq(one.rays[RAY_KIND_SHADOW], 0);
    ck_assert_uint_eq(three.filter_calls, one.filter_calls);
    ck_assert_uint_eq(three.shadows_undeclared, one.shadows_undeclared);
    ck_assert_uint_eq(one.traces_undeclared, shades);
    ck_assert_uint_eq(three.traces_undeclared, one.traces_undeclared);
    for (k = 0; k < RAY_KIND_COUNT; k++)
        ck_assert_uint_eq(three.rays[k], one.rays[k]);
    ck_assert_uint_eq(three.tests, one.tests);
    for (k = 0; k < RAY_PRIM_KINDS; k++)
        ck_assert_uint_eq(three.tests_by_kind[k], one.tests_by_kind[k]);
    for (k = 0; k < RAY_HIST_BINS; k++)
        ck_assert_uint_eq(three.samples_hist[k], one.samples_hist[k]);
    ck_assert_uint_eq(three.pixels, (unsigned long long)W * H);
    ck_assert_uint_eq(one.pixels, three.pixels);
}
END_TEST

/* Records where each primary ray crosses the image plane of a 1x1 frame
** seen by a 90-degree camera looking down -z (background only). */
typedef struct sample_log {
    unsigned n;
    double sx[64], sy[64];
} sample_log;

static void log_sample(void *ud, const ray_ray *r, ray_rgb *out)
{
    sample_log *log = ud;

    (void)out;
    if (log->n < 64) {
        log->sx[log->n] = (r->dir.x / -r->dir.z + 1) / 2;
        log->sy[log->n] = (1 - r->dir.y / -r->dir.z) / 2;
        log->n++;
    }
}

/*
** Sample positions inside a pixel: for n = 2, 3, 5, 7 (n-rooks) every one
** of the n columns and n rows of an n x n grid holds exactly one sample;
** for n = 4, 9 (k x k) every cell of the k x k grid holds one.  1e-9
** absorbs the rounding of the direction (exact positions are never on a
** cell border except with probability 0).
*/
START_TEST(render_samples_should_cover_every_stratum)
{
    unsigned ns[] = {2, 3, 5, 7, 4, 9};
    int k;

    for (k = 0; k < 6; k++) {
        unsigned n = ns[k], i, cols = 0, rows = 0, cells = n;
        int square = n == 4 || n == 9;
        unsigned side = n == 4 ? 2 : 3;
        sample_log log;
        ray_scene *s;
        ray_camera cam;
        ray_render_options opt;
        float px[3];

        memset(&log, 0, sizeof log);
        memset(&cam, 0, sizeof cam);
        cam.position = vec(0, 0, 0);
        cam.look_at = vec(0, 0, -1);
        cam.up = vec(0, 1, 0);
        cam.vfov = 90;
        ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_set_background(s, rgb(0, 0, 0), log_sample, &log), RAY_OK);
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        opt = (ray_render_options){.width = 1, .height = 1};
        opt.samples = n;
        opt.threads = 1;
        ck_assert_int_eq(ray_render(s, &cam, &opt, px, NULL), RAY_OK);
        ck_assert_uint_eq(log.n, n);
        if (square) {
            unsigned seen = 0;
            for (i = 0; i < n; i++) {
                unsigned cx = (unsigned)(log.sx[i] * side);
                unsigned cy = (unsigned)(log.sy[i] * side);
                ck_assert(cx < side && cy < side);
                seen |= 1u << (cy * side + cx);
            }
            ck_assert_uint_eq(seen, (1u << n) - 1);
        } else {
            for (i = 0; i < n; i++) {
                ck_assert(log.sx[i] > -1e-9 && log.sx[i] < 1 + 1e-9);
                cols |= 1u << (unsigned)(log.sx[i] * cells);
                rows |= 1u << (unsigned)(log.sy[i] * cells);
            }
            ck_assert_uint_eq(cols, (1u << n) - 1);
            ck_assert_uint_eq(rows, (1u << n) - 1);
        }
        ray_scene_free(s);
    }
}
END_TEST

/* A material whose colour is the user's ud: 3 doubles. */
static void constant_shade(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                           ray_rgb *out)
{
    const double *c = ud;
    (void)ctx;
    (void)a;
    out->r = c[0], out->g = c[1], out->b = c[2];
}

/*
** Issue 14, defect 5: accepted input beyond float's range made +Inf
** pixels (a background of 1e300; a material returning 1e40, as a point
** light 1e-20 from a surface gives).  Every pixel is finite: clamped to
** FLT_MAX (and to -FLT_MAX below), a NaN from a user material becomes 0;
** values within float's range are stored as before, (float)x exactly.
** For one sample and adaptive sampling both.
*/
START_TEST(render_pixels_should_always_be_finite)
{
    enum { PW = 8, PH = 6 };
    static const double colours[4][3] = {
        {1e40, -1e40, 0.25}, {(double)NAN, 1.0, 1e300}, {0.5, 0.5, 0.5},
        {HUGE_VAL, -HUGE_VAL, 3.0}};
    static const float want[4][3] = {
        {FLT_MAX, -FLT_MAX, 0.25f}, {0.0f, 1.0f, FLT_MAX},
        {0.5f, 0.5f, 0.5f}, {FLT_MAX, -FLT_MAX, 3.0f}};
    float img[3 * PW * PH];
    int k, adaptive, i;

    for (k = 0; k < 4; k++)
        for (adaptive = 0; adaptive < 2; adaptive++) {
            ray_material m;
            ray_scene *s;
            ray_camera cam;
            ray_render_options o;
            ray_rgb bg = {1e300, 1e300, 1e300};

            m.shade = constant_shade;
            m.ud = ray__test_unconst(colours[k]);
            m.effects = 0;
            m.scatter = NULL;
            ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
            ck_assert_int_eq(ray_scene_add_material(s, &m, NULL), RAY_OK);
            ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1, 0,
                                                  NULL), RAY_OK);
            ck_assert_int_eq(ray_scene_set_background(s, bg, NULL, NULL), RAY_OK);
            ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
            memset(&cam, 0, sizeof cam);
            cam.position = vec(0, 0, 4), cam.look_at = vec(0, 0, 0);
            cam.up = vec(0, 1, 0), cam.vfov = 40;
            o = (ray_render_options){.width = PW, .height = PH};
            if (adaptive)
                o.adaptive_threshold = 0.05;
            ck_assert_int_eq(ray_render(s, &cam, &o, img, NULL), RAY_OK);
            for (i = 0; i < 3 * PW * PH; i++)
                ck_assert(isfinite(img[i]));
            /* The corner sees the background, the centre the sphere. */
            ck_assert(img[0] == FLT_MAX);
            i = 3 * (PH / 2 * PW + PW / 2);
            ck_assert(img[i] == want[k][0] && img[i + 1] == want[k][1] &&
                      img[i + 2] == want[k][2]);
            ray_scene_free(s);
        }
}
END_TEST

/* ------------------------------------------- ray_render_check's warnings */

/* A grey Lambertian material's parameters: the material points at them,
** so they outlive every scene; const, so tests on several threads share
** them without a race. */
static const ray_phong_params warn_grey = {
    .diffuse = {0.8, 0.8, 0.8}, .shininess = 32
};

/* A scene for the warnings: a grey Phong material (its id in *mat),
** nothing else; the caller adds, commits and frees. */
static ray_scene *warn_scene(unsigned *mat)
{
    ray_material m;
    ray_scene *s = NULL;

    m = ray_material_phong(&warn_grey);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, mat), RAY_OK);
    return s;
}

static void add_light(ray_scene *s, ray_rgb intensity)
{
    ray_light l;

    ray_light_init(&l, RAY_LIGHT_POINT);
    l.position = vec(0, 10, 0);
    l.intensity = intensity;
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
}

/* The warnings ray_render_check gives s (committed here) for a camera at
** eye looking down -z, asserting RAY_OK, that msg is "" exactly when
** there are none and names them otherwise, and that ray_render, which
** does not ask for them, renders the scene. */
static unsigned warnings_at(ray_scene *s, ray_vec3 eye)
{
    ray_camera cam;
    ray_render_options o;
    char msg[512];
    float img[3 * 4 * 3];
    unsigned w = 0xdeadu;

    memset(&cam, 0, sizeof cam);
    cam.position = eye;
    cam.look_at = vec(eye.x, eye.y, eye.z - 1);
    memset(&o, 0, sizeof o);
    o.width = 4;
    o.height = 3;
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_render_check(s, &cam, &o, &w, msg, sizeof msg),
                     RAY_OK);
    ck_assert_uint_eq(w & ~(RAY_RENDER_WARN_UNLIT | RAY_RENDER_WARN_EMPTY |
                            RAY_RENDER_WARN_EYE_INSIDE), 0);
    if (w == 0) {
        ck_assert_str_eq(msg, "");
    } else {
        ck_assert_msg(strncmp(msg, "ray_render: warning: ", 21) == 0,
                      "%s", msg);
        ck_assert((strstr(msg, "no light") != NULL) ==
                  ((w & RAY_RENDER_WARN_UNLIT) != 0));
        ck_assert((strstr(msg, "black background") != NULL) ==
                  ((w & RAY_RENDER_WARN_EMPTY) != 0));
        ck_assert((strstr(msg, "inside a solid") != NULL) ==
                  ((w & RAY_RENDER_WARN_EYE_INSIDE) != 0));
    }
    /* Without "warnings" none is looked for: msg stays "". */
    ck_assert_int_eq(ray_render_check(s, &cam, &o, NULL, msg, sizeof msg),
                     RAY_OK);
    ck_assert_str_eq(msg, "");
    ck_assert_int_eq(ray_render(s, &cam, &o, img, NULL), RAY_OK);
    return w;
}

/*
** Issue 37's scene: no light, a black ambient, the camera at the origin
** inside a sphere placed there.  Each cause alone, and the cures: a
** light of zero intensity is no light; a non-black ambient without a
** light, or a light, ends UNLIT.
*/
START_TEST(render_check_should_warn_of_a_scene_without_light)
{
    unsigned mat;
    ray_scene *s = warn_scene(&mat);

    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1, mat, NULL),
                     RAY_OK);
    ck_assert_uint_eq(warnings_at(s, vec(0, 0, 0)),
                      RAY_RENDER_WARN_UNLIT | RAY_RENDER_WARN_EYE_INSIDE);
    ck_assert_uint_eq(warnings_at(s, vec(0, 0, 5)), RAY_RENDER_WARN_UNLIT);
    add_light(s, rgb(0, 0, 0));
    ck_assert_uint_eq(warnings_at(s, vec(0, 0, 5)), RAY_RENDER_WARN_UNLIT);
    ck_assert_int_eq(ray_scene_set_ambient(s, rgb(0, 0, 0.01)), RAY_OK);
    ck_assert_uint_eq(warnings_at(s, vec(0, 0, 5)), 0);
    ck_assert_int_eq(ray_scene_set_ambient(s, rgb(0, 0, 0)), RAY_OK);
    add_light(s, rgb(0, 1e-300, 0));
    ck_assert_uint_eq(warnings_at(s, vec(0, 0, 5)), 0);
    ray_scene_free(s);
}
END_TEST

/* Nothing a camera ray can hit and a black background: EMPTY, also when
** the only geometry is disabled or of mask 0; not with a background
** colour or function, nor once geometry is enabled. */
static void blue_sky(void *ud, const ray_ray *r, ray_rgb *out)
{
    (void)ud, (void)r;
    *out = rgb(0, 0, 1);
}

START_TEST(render_check_should_warn_of_nothing_to_see)
{
    unsigned mat, ball;
    ray_scene *s = warn_scene(&mat);

    add_light(s, rgb(1, 1, 1));
    ck_assert_uint_eq(warnings_at(s, vec(0, 0, 5)), RAY_RENDER_WARN_EMPTY);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1, mat, &ball),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_set_enabled(s, ball, 0), RAY_OK);
    ck_assert_uint_eq(warnings_at(s, vec(0, 0, 5)), RAY_RENDER_WARN_EMPTY);
    ck_assert_int_eq(ray_scene_set_enabled(s, ball, 1), RAY_OK);
    ck_assert_int_eq(ray_scene_set_mask(s, ball, 0), RAY_OK);
    ck_assert_uint_eq(warnings_at(s, vec(0, 0, 5)), RAY_RENDER_WARN_EMPTY);
    ck_assert_int_eq(ray_scene_set_mask(s, ball, 1), RAY_OK);
    ck_assert_uint_eq(warnings_at(s, vec(0, 0, 5)), 0);
    ck_assert_int_eq(ray_scene_set_enabled(s, ball, 0), RAY_OK);
    ck_assert_int_eq(ray_scene_set_background(s, rgb(0.1, 0, 0), NULL, NULL), RAY_OK);
    ck_assert_uint_eq(warnings_at(s, vec(0, 0, 5)), 0);
    ck_assert_int_eq(ray_scene_set_background(s, rgb(0, 0, 0), NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_set_background(s, rgb(0, 0, 0), blue_sky, NULL), RAY_OK);
    ck_assert_uint_eq(warnings_at(s, vec(0, 0, 5)), 0);
    ray_scene_free(s);
}
END_TEST

/* The unit cube's 8 corners and 12 outward triangles; the first 10 (the
** +z face's two left out) make it open. */
static const ray_vec3 cube_v[8] = {
    {-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
    {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}
};
static const unsigned cube_i[36] = {
    0, 2, 1, 0, 3, 2,   /* -z */
    0, 1, 5, 0, 5, 4,   /* -y */
    1, 2, 6, 1, 6, 5,   /* +x */
    2, 3, 7, 2, 7, 6,   /* +y */
    3, 0, 4, 3, 4, 7,   /* -x */
    4, 5, 6, 4, 6, 7    /* +z */
};

static void add_cube(ray_scene *s, unsigned mat, size_t triangles)
{
    ray_mesh m;

    memset(&m, 0, sizeof m);
    m.vertices = cube_v;
    m.vertex_count = 8;
    m.indices = cube_i;
    m.triangle_count = triangles;
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, mat, NULL), RAY_OK);
}

/*
** The eye inside a solid: a sphere (inside, exactly on its surface, the
** next double outside), a closed mesh (inside, on a face), the same mesh
** open (no solid: not looked at), a box, a capsule, and a sphere seen
** through an instance that moves it onto the eye.  A light in each, so
** that EYE_INSIDE is the only warning.
*/
START_TEST(render_check_should_warn_of_an_eye_inside_a_solid)
{
    unsigned mat;
    ray_scene *s = warn_scene(&mat), *child;
    ray_box_params b;
    ray_capsule_params c;
    ray_transform t;

    add_light(s, rgb(1, 1, 1));
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1, mat, NULL),
                     RAY_OK);
    ck_assert_uint_eq(warnings_at(s, vec(0.5, 0.25, 0)),
                      RAY_RENDER_WARN_EYE_INSIDE);
    /* On the surface: inside, as ray_contains's closed solids (1 * 1 is
    ** exact, so there is no rounding to argue about). */
    ck_assert_uint_eq(warnings_at(s, vec(0, 0, 1)),
                      RAY_RENDER_WARN_EYE_INSIDE);
    ck_assert_uint_eq(warnings_at(s, vec(0, 0, nextafter(1, 2))), 0);
    ray_scene_free(s);

    s = warn_scene(&mat);
    add_light(s, rgb(1, 1, 1));
    add_cube(s, mat, 12);
    ck_assert_uint_eq(warnings_at(s, vec(0.25, 0.5, 0.125)),
                      RAY_RENDER_WARN_EYE_INSIDE);
    ck_assert_uint_eq(warnings_at(s, vec(0.25, 0.5, 1)),
                      RAY_RENDER_WARN_EYE_INSIDE);
    ck_assert_uint_eq(warnings_at(s, vec(0.25, 0.5, 3)), 0);
    ray_scene_free(s);

    /* Open: the eye sees out of the hole, so no solid shuts it in,
    ** although the winding number there is well above 1/2. */
    s = warn_scene(&mat);
    add_light(s, rgb(1, 1, 1));
    add_cube(s, mat, 10);
    ck_assert_uint_eq(warnings_at(s, vec(0.25, 0.5, 0.125)), 0);
    ray_scene_free(s);

    s = warn_scene(&mat);
    add_light(s, rgb(1, 1, 1));
    memset(&b, 0, sizeof b);
    b.center = vec(10, 0, 0);
    b.half_extents = vec(1, 2, 3);
    b.axis_x = vec(1, 1, 0);
    b.axis_y = vec(-1, 1, 0);
    ck_assert_int_eq(ray_scene_add_box(s, &b, mat, NULL), RAY_OK);
    c.a = vec(-10, 0, 0);
    c.b = vec(-10, 4, 0);
    c.radius = 0.5;
    ck_assert_int_eq(ray_scene_add_capsule(s, &c, mat, NULL), RAY_OK);
    ck_assert_uint_eq(warnings_at(s, vec(10.5, 0.5, 2.5)),
                      RAY_RENDER_WARN_EYE_INSIDE);
    ck_assert_uint_eq(warnings_at(s, vec(-10, 4.25, 0)),
                      RAY_RENDER_WARN_EYE_INSIDE);
    ck_assert_uint_eq(warnings_at(s, vec(0, 0, 0)), 0);
    ray_scene_free(s);

    /* Through an instance: the child's unit sphere moved to x = 20. */
    child = warn_scene(&mat);
    ck_assert_int_eq(ray_scene_add_sphere(child, vec(0, 0, 0), 1, mat, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    s = warn_scene(&mat);
    add_light(s, rgb(1, 1, 1));
    ray_transform_identity(&t);
    t.m[0][3] = 20;
    ck_assert_int_eq(ray_scene_add_instance(s, child, &t, NULL), RAY_OK);
    ck_assert_uint_eq(warnings_at(s, vec(20.5, 0, 0)),
                      RAY_RENDER_WARN_EYE_INSIDE);
    ck_assert_uint_eq(warnings_at(s, vec(0.5, 0, 0)), 0);
    ray_scene_free(s);
    ray_scene_free(child);
}
END_TEST

/* A refusal leaves *warnings as it was (outputs only on RAY_OK); a
** buffer too small for the warnings holds their truncated start. */
START_TEST(render_check_warnings_should_follow_the_output_rules)
{
    unsigned mat, w = 0xdeadu;
    ray_scene *s = warn_scene(&mat);
    ray_camera cam;
    ray_render_options o;
    char msg[512], small[24];

    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1, mat, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    cam = (ray_camera){.look_at = {0, 0, -1}};
    memset(&o, 0, sizeof o);
    ck_assert_int_eq(ray_render_check(s, &cam, &o, &w, msg, sizeof msg),
                     RAY_EINVAL);
    ck_assert_uint_eq(w, 0xdeadu);
    ck_assert(strstr(msg, "width") != NULL);
    o.width = o.height = 2;
    ck_assert_int_eq(ray_render_check(s, &cam, &o, &w, msg, sizeof msg),
                     RAY_OK);
    ck_assert_uint_eq(w, RAY_RENDER_WARN_UNLIT | RAY_RENDER_WARN_EYE_INSIDE);
    ck_assert_msg(strstr(msg, "; the camera position (0, 0, 0) is inside")
                  != NULL, "%s", msg);
    memset(small, 'x', sizeof small);
    ck_assert_int_eq(ray_render_check(s, &cam, &o, &w, small, sizeof small),
                     RAY_OK);
    ck_assert_uint_eq(strlen(small), sizeof small - 1);
    ck_assert(strncmp(small, msg, sizeof small - 1) == 0);
    ck_assert_int_eq(ray_render_check(s, &cam, &o, &w, NULL, 0), RAY_OK);
    ck_assert_uint_eq(w, RAY_RENDER_WARN_UNLIT | RAY_RENDER_WARN_EYE_INSIDE);
    ray_scene_free(s);
}
END_TEST

Suite *render_suite(void)
{
    Suite *s = suite_create("render");
    TCase *tc = tcase_create("render");

    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, render_should_be_identical_for_any_thread_count);
    tcase_add_test(tc, render_regions_should_stitch_bit_exactly);
    tcase_add_test(tc, concurrent_renders_of_one_scene_should_match_a_lone_render);
    tcase_add_test(tc, render_should_cancel_from_progress);
    tcase_add_test(tc, render_should_put_colours_where_the_scene_is);
    tcase_add_test(tc, render_should_reject_bad_options);
    tcase_add_loop_test(tc, render_check_should_say_which_option_and_why, 0,
                        (int)N_REFUSALS);
    tcase_add_test(tc, render_check_should_accept_the_last_value_of_each_range);
    tcase_add_test(tc, render_check_should_warn_of_a_scene_without_light);
    tcase_add_test(tc, render_check_should_warn_of_nothing_to_see);
    tcase_add_test(tc, render_check_should_warn_of_an_eye_inside_a_solid);
    tcase_add_test(tc, render_check_warnings_should_follow_the_output_rules);
    tcase_add_test(tc, render_stats_should_sum_every_counter_over_threads);
    tcase_add_test(tc, render_samples_should_cover_every_stratum);
    tcase_add_test(tc, render_pixels_should_always_be_finite);
    suite_add_tcase(s, tc);
    return s;
}
