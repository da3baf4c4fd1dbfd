/* SPDX-License-Identifier: MIT */
/*
** check_user.c -- user geometry, ray_scene_add_user: a sphere whose
** callback calls ray_sphere answers exactly as the scene's own sphere
** (alone, among many, beside a mesh; both queries; a rendered image); an
** implicit torus wrapped in a callback answers as ray_scene_add_implicit
** of the same surface; an answer that breaks the contract of ray_hit is a
** miss counted in root_failures; bad input is refused with a message
** naming what is wrong, and adds nothing.
*/
#include <string.h>
#include <stdlib.h>

#include "prim/prim.h"         /* ray__implicit_torus */
#include "tests.h"

/* ------------------------------------------------------- a user sphere */

/* What the callbacks of a user sphere read: its centre and radius, and
** how many times the bounds were asked. */
typedef struct user_sphere {
    ray_vec3 c;
    double r;
    int bounds_calls;
} user_sphere;

/* The box the scene gives its own spheres (src/scene/kinds.c, box_SPHERE), so
** both scenes build the same BVH and traverse it in the same order. */
static void sphere_bounds(void *ud, ray_vec3 *lo, ray_vec3 *hi)
{
    user_sphere *s = ud;

    s->bounds_calls++;
    *lo = vec(s->c.x - s->r, s->c.y - s->r, s->c.z - s->r);
    *hi = vec(s->c.x + s->r, s->c.y + s->r, s->c.z + s->r);
}

static int sphere_intersect(void *ud, const ray_ray *r, ray_hit *hit)
{
    const user_sphere *s = ud;

    return ray_sphere(r, s->c, s->r, hit);
}

static ray_user_geometry sphere_geometry(user_sphere *s)
{
    ray_user_geometry g;

    g.bounds = sphere_bounds;
    g.intersect = sphere_intersect;
    g.ud = s;
    return g;
}

/* N_SPHERES random spheres about "o": enough for the BVH to have inner
** nodes, and for spheres to hide one another. */
#define N_SPHERES 40
static void random_spheres(rng *g, ray_vec3 o, user_sphere *sp)
{
    int k;

    for (k = 0; k < N_SPHERES; k++) {
        sp[k].c = vadd(o, rng_point(g, -5, 5));
        sp[k].r = rng_range(g, 0.2, 1.2);
        sp[k].bounds_calls = 0;
    }
}

/* A grid of 8 x 8 quads (128 triangles) in the plane z = -2 about o,
** [-6, 6] wide, its middle raised to a ridge: the same copy in both
** scenes. */
typedef struct grid {
    ray_vec3 v[81];
    unsigned idx[6 * 64];
    ray_mesh m;
} grid;

static void grid_init(grid *gr, ray_vec3 o)
{
    int i, j, q = 0;

    for (i = 0; i < 9; i++)
        for (j = 0; j < 9; j++)
            gr->v[9 * i + j] = vadd(o, vec(-6 + 1.5 * j, -6 + 1.5 * i,
                                           -2 + (i == 4 ? 1.0 : 0.0)));
    for (i = 0; i < 8; i++)
        for (j = 0; j < 8; j++) {
            unsigned a = (unsigned)(9 * i + j);
            unsigned t[6] = {a, a + 1, a + 10, a, a + 10, a + 9};
            memcpy(gr->idx + 6 * q++, t, sizeof t);
        }
    memset(&gr->m, 0, sizeof gr->m);
    gr->m.vertices = gr->v;
    gr->m.vertex_count = 81;
    gr->m.indices = gr->idx;
    gr->m.triangle_count = 128;
}

/* Two committed scenes of the same spheres, the scene's own in *builtin
** and user geometry in *user, in the same order (so the same geom_ids),
** with the grid after them in both when "gr" is not NULL. */
static void twin_scenes(user_sphere *sp, const grid *gr,
                        ray_scene **builtin, ray_scene **user)
{
    unsigned id;
    int k;

    *builtin = *user = NULL;   /* -O1 cannot see that ck_assert stops */
    ck_assert_int_eq(nop_scene_new(builtin, NULL, NULL), RAY_OK);
    ck_assert_int_eq(nop_scene_new(user, NULL, NULL), RAY_OK);
    for (k = 0; k < N_SPHERES; k++) {
        ray_user_geometry g = sphere_geometry(&sp[k]);

        ck_assert_int_eq(ray_scene_add_sphere(*builtin, sp[k].c, sp[k].r, 0,
                                              NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_user(*user, &g, 0, &id), RAY_OK);
        ck_assert_uint_eq(id, (unsigned)k);
        /* Asked once, when added. */
        ck_assert_int_eq(sp[k].bounds_calls, 1);
    }
    if (gr != NULL) {
        ck_assert_int_eq(ray_scene_add_mesh(*builtin, &gr->m, 0, NULL),
                         RAY_OK);
        ck_assert_int_eq(ray_scene_add_mesh(*user, &gr->m, 0, NULL), RAY_OK);
    }
    ck_assert_int_eq(ray_scene_commit(*builtin), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(*user), RAY_OK);
}

/*
** Random rays (origins among and around the spheres, intervals from
** (0, +Inf) to short segments starting past 0) through 40 spheres, alone
** (_i = 0, 1) and beside a 128-triangle mesh (_i = 2, 3), at offsets 0
** and 1e5: ray_intersect answers the user scene exactly as the built-in
** one, the whole hit record bit for bit (t, p, n, u, v, p_err and both
** ids: the callback calls ray_sphere on the same ray, whose tmax the
** scene shrinks past the same hits), and a miss leaves the record
** untouched in both; ray_occluded agrees.
*/
START_TEST(user_spheres_should_answer_as_the_scene_spheres)
{
    ray_vec3 o = vec(test_offset(_i % 2), test_offset(_i % 2),
                     test_offset(_i % 2));
    user_sphere sp[N_SPHERES];
    grid gr;
    ray_scene *builtin, *user;
    rng g = {17 + (uint64_t)_i};
    int n, sphere_hits = 0, mesh_hits = 0;

    random_spheres(&g, o, sp);
    grid_init(&gr, o);
    twin_scenes(sp, _i >= 2 ? &gr : NULL, &builtin, &user);
    for (n = 0; n < 4000; n++) {
        ray_vec3 from = vadd(o, rng_point(&g, -8, 8));
        ray_ray r = ray_from(from, vsub(vadd(o, rng_point(&g, -5, 5)), from));
        ray_hit hb, hu;
        int b, u;

        if (n % 4 == 1)             /* a segment, as a shadow ray */
            r.tmax = rng_range(&g, 0.2, 1.0);
        if (n % 4 == 2)             /* starting past its origin */
            r.tmin = rng_range(&g, 0, 0.5);
        hit_poison(&hb);
        hit_poison(&hu);
        b = ray_intersect(builtin, &r, &hb, NULL);
        u = ray_intersect(user, &r, &hu, NULL);
        ck_assert_int_eq(u, b);
        ck_assert_msg(u != 1 ? memcmp(&hu, &hb, sizeof hu) == 0
                               : hit_same(&hu, &hb),
                      "ray %d: user hit t %.17g geom %u, scene's t %.17g "
                      "geom %u", n, hu.t, hu.geom_id, hb.t, hb.geom_id);
        ck_assert_int_eq(ray_occluded(user, &r, NULL), b);
        ck_assert_int_eq(ray_occluded(builtin, &r, NULL), b);
        if (b == 1 && hb.geom_id < N_SPHERES)
            sphere_hits++;
        else if (b == 1)
            mesh_hits++;
    }
    ck_assert_int_gt(sphere_hits, 1000);
    if (_i >= 2)
        ck_assert_int_gt(mesh_hits, 100);
    ray_scene_free(builtin);
    ray_scene_free(user);
}
END_TEST

/* A material with a diffuse and a specular lobe under a point light
** (shadow rays leave the spheres through ray_spawn_to and the p_err the
** callback gave) and a half-mirror floor (reflected rays, from another
** kind of surface, reach the spheres): rendered on 4 threads, so the
** callbacks run concurrently, the user scene's image is the built-in
** one's byte for byte, and the tests count under RAY_PRIM_USER as many as
** the scene's spheres count under RAY_PRIM_SPHERE. */
START_TEST(user_spheres_should_render_as_the_scene_spheres)
{
    enum { W = 48, H = 32 };
    ray_phong_params pp;
    ray_material phong, floor_m;
    ray_light l;
    user_sphere sp[N_SPHERES];
    ray_scene *sc[2];
    ray_camera cam;
    ray_render_options opt;
    ray_stats st[2];
    float *img[2];
    rng g = {5};
    int k, lit = 0;
    size_t i;

    random_spheres(&g, vec(0, 0, 0), sp);
    memset(&pp, 0, sizeof pp);
    pp.diffuse = rgb(0.7, 0.5, 0.3);
    pp.specular = rgb(0.3, 0.3, 0.3);
    pp.shininess = 20;
    phong = ray_material_phong(&pp);
    pp.diffuse = rgb(0.4, 0.4, 0.4);
    pp.reflect = rgb(0.5, 0.5, 0.5);
    floor_m = ray_material_phong(&pp);
    ray_light_init(&l, RAY_LIGHT_POINT);
    l.position = vec(2, 9, 12);
    l.intensity = rgb(150, 150, 150);
    for (k = 0; k < 2; k++) {
        ck_assert_int_eq(ray_scene_new(&sc[k], NULL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_material(sc[k], &phong, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_material(sc[k], &floor_m, NULL),
                         RAY_OK);
        ck_assert_int_eq(ray_scene_add_light(sc[k], &l, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_set_ambient(sc[k], rgb(0.1, 0.1, 0.1)),
                         RAY_OK);
        ck_assert_int_eq(ray_scene_add_plane(sc[k], vec(0, -6, 0),
                                             vec(0, 1, 0), 1, NULL), RAY_OK);
    }
    for (k = 0; k < N_SPHERES; k++) {
        ray_user_geometry gm = sphere_geometry(&sp[k]);

        ck_assert_int_eq(ray_scene_add_sphere(sc[0], sp[k].c, sp[k].r, 0,
                                              NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_user(sc[1], &gm, 0, NULL), RAY_OK);
    }
    cam = (ray_camera){.look_at = {0, 0, -1}};
    cam.position = vec(0, 3, 14);
    cam.look_at = vec(0, -1, 0);
    opt = (ray_render_options){.width = W, .height = H};
    opt.threads = 4;
    for (k = 0; k < 2; k++) {
        ck_assert_int_eq(ray_scene_commit(sc[k]), RAY_OK);
        img[k] = malloc(3 * W * H * sizeof *img[k]);
        ck_assert_ptr_nonnull(img[k]);
        ck_assert_int_eq(ray_render(sc[k], &cam, &opt, img[k], &st[k]),
                         RAY_OK);
    }
    ck_assert(memcmp(img[0], img[1], 3 * W * H * sizeof *img[0]) == 0);
    for (i = 0; i < (size_t)W * H; i++)
        lit += img[1][3 * i] > 0;
    ck_assert_int_gt(lit, W * H / 4);
    ck_assert_uint_gt(st[0].tests_by_kind[RAY_PRIM_SPHERE], 0);
    ck_assert_uint_eq(st[1].tests_by_kind[RAY_PRIM_USER],
                      st[0].tests_by_kind[RAY_PRIM_SPHERE]);
    ck_assert_uint_eq(st[1].tests_by_kind[RAY_PRIM_SPHERE], 0);
    ck_assert_uint_eq(st[0].tests_by_kind[RAY_PRIM_USER], 0);
    ck_assert_uint_eq(st[1].tests, st[0].tests);
    ck_assert_uint_eq(st[1].rays[RAY_KIND_SHADOW],
                      st[0].rays[RAY_KIND_SHADOW]);
    ck_assert_uint_gt(st[1].rays[RAY_KIND_SHADOW], 0);
    ck_assert_uint_eq(st[1].root_failures, 0);
    for (k = 0; k < 2; k++) {
        free(img[k]);
        ray_scene_free(sc[k]);
    }
}
END_TEST

/* -------------------------------------------- callbacks that misbehave */

/* What a callback does to the unit sphere's hit before answering. */
typedef enum answer {
    /* valid: a hit */
    GOOD,
    GOOD_NORMAL_TIMES_2,       /* n not unit: normalised */
    GOOD_NORMAL_TINY,          /* n 1e-300 long: n.n underflows */
    GOOD_NORMAL_HUGE,          /* n 1e300 long: n.n overflows */
    GOOD_IDS_WRITTEN,          /* geom_id, prim_id scribbled on */
    GOOD_NO_UV_NO_PERR,        /* u, v and p_err left unwritten: 0 */
    /* invalid: a miss, counted */
    BAD_T_AT_TMIN,             /* the interval is open */
    BAD_T_NEGATIVE,            /* t < tmin */
    BAD_T_PAST_TMAX,
    BAD_T_NAN,
    BAD_T_INF,
    BAD_P_NAN,
    BAD_P_INF,
    BAD_NORMAL_ZERO,
    BAD_NORMAL_NAN,
    BAD_NORMAL_INF,
    BAD_U_NAN,
    BAD_V_INF,
    BAD_PERR_NEGATIVE,
    BAD_PERR_NAN,
    BAD_ANSWER_2,              /* neither 0 nor 1 */
    BAD_ANSWER_ELIMIT,         /* ray_implicit's -RAY_ELIMIT passed on */
    BAD_NOTHING_WRITTEN,       /* 1, with *hit as the library gave it */
    N_ANSWERS
} answer;
#define N_GOOD ((int)BAD_T_AT_TMIN)    /* the answers that are valid */

/* The unit sphere at the origin, then the damage of answer *ud. */
static int answering_intersect(void *ud, const ray_ray *r, ray_hit *hit)
{
    const answer *a = ud;
    ray_hit h;

    if (*a == BAD_NOTHING_WRITTEN)
        return 1;
    if (ray_sphere(r, vec(0, 0, 0), 1, &h) != 1)
        return 0;
    switch (*a) {
    case GOOD: break;
    case GOOD_NORMAL_TIMES_2: h.n = vscale(h.n, 2); break;
    case GOOD_NORMAL_TINY: h.n = vscale(h.n, 1e-300); break;
    case GOOD_NORMAL_HUGE: h.n = vscale(h.n, 1e300); break;
    case GOOD_IDS_WRITTEN: h.geom_id = 123, h.prim_id = 456; break;
    case GOOD_NO_UV_NO_PERR:
        hit->t = h.t, hit->p = h.p, hit->n = h.n;
        return 1;
    case BAD_T_AT_TMIN: h.t = r->tmin; break;
    case BAD_T_NEGATIVE: h.t = -h.t; break;
    case BAD_T_PAST_TMAX: h.t = r->tmax * 2; break;
    case BAD_T_NAN: h.t = (double)NAN; break;
    case BAD_T_INF: h.t = HUGE_VAL; break;
    case BAD_P_NAN: h.p.y = (double)NAN; break;
    case BAD_P_INF: h.p.z = -HUGE_VAL; break;
    case BAD_NORMAL_ZERO: h.n = vec(0, 0, 0); break;
    case BAD_NORMAL_NAN: h.n.x = (double)NAN; break;
    case BAD_NORMAL_INF: h.n.y = HUGE_VAL; break;
    case BAD_U_NAN: h.u = (double)NAN; break;
    case BAD_V_INF: h.v = HUGE_VAL; break;
    case BAD_PERR_NEGATIVE: h.p_err.x = -1e-15; break;
    case BAD_PERR_NAN: h.p_err.z = (double)NAN; break;
    case BAD_ANSWER_2: *hit = h; return 2;
    case BAD_ANSWER_ELIMIT: return -RAY_ELIMIT;
    case BAD_NOTHING_WRITTEN: case N_ANSWERS: break;
    }
    *hit = h;
    return 1;
}

/* The unit sphere's box, whatever the answer. */
static void unit_bounds(void *ud, ray_vec3 *lo, ray_vec3 *hi)
{
    (void)ud;
    *lo = vec(-1, -1, -1);
    *hi = vec(1, 1, 1);
}

/*
** Each answer (_i) on rays aimed at the unit sphere (tmax 100, so "past
** tmax" is finite): the valid ones are hits with the sphere's t, p, u, v
** and a unit normal (ray_sphere's own kept bit for bit; a scaled one
** normalised again, within 4 DBL_EPSILON of it: each normalisation, the
** library's and ray_sphere's, rounds a component about 6 times, 3
** DBL_EPSILON, and squaring doubles that for n.n), with the library's ids; the
** invalid ones are misses, *hit untouched, which ray_trace shades as the
** background and counts, one test under RAY_PRIM_USER and one
** root_failure per ray.
*/
START_TEST(user_answers_should_be_checked)
{
    answer a = (answer)_i;
    ray_user_geometry gm;
    ray_scene *s = NULL;   /* -O1 cannot see that ck_assert stops */
    ray_ctx *ctx;
    ray_stats st;
    unsigned id;
    int n, good = _i < N_GOOD;
    const int rays = 12;

    gm.bounds = unit_bounds;
    gm.intersect = answering_intersect;
    gm.ud = &a;
    ck_assert_int_eq(nop_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(10, 10, 10), 1, 0, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_add_user(s, &gm, 0, &id), RAY_OK);
    ck_assert_uint_eq(id, 1);
    ck_assert_int_eq(ray_scene_set_background(s, rgb(0.25, 0, 0), NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(s, 1, &ctx), RAY_OK);
    for (n = 0; n < rays; n++) {
        ray_ray r = make_ray(vec(0.07 * n - 0.4, 0.3 - 0.05 * n, 5),
                             vec(0.01 * n, 0.02, -1), 0, 100);
        ray_hit h, ref;
        ray_rgb c;

        ck_assert_int_eq(ray_sphere(&r, vec(0, 0, 0), 1, &ref), 1);
        hit_poison(&h);
        ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), good);
        ck_assert_int_eq(ray_occluded(s, &r, NULL), good);
        ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1, &c), RAY_OK);
        /* plain() shades black: a hit is black, a miss the background. */
        ck_assert_double_eq(c.r, good ? 0 : 0.25);
        if (!good) {
            ck_assert(hit_is_poisoned(&h));
            continue;
        }
        ck_assert_double_eq(h.t, ref.t);
        ck_assert_vec_eq(h.p, ref.p);
        ck_assert_uint_eq(h.geom_id, 1);
        ck_assert_uint_eq(h.prim_id, 0);
        if (a == GOOD)
            ck_assert_vec_eq(h.n, ref.n);
        else
            ck_assert_vec_eq_tol(h.n, ref.n, 4 * DBL_EPSILON);
        ck_assert_double_eq_tol(vdot(h.n, h.n), 1, 4 * DBL_EPSILON);
        if (a == GOOD_NO_UV_NO_PERR) {
            ck_assert(h.u == 0 && h.v == 0);
            ck_assert_vec_eq(h.p_err, vec(0, 0, 0));
        } else {
            ck_assert(h.u == ref.u && h.v == ref.v);
            ck_assert_vec_eq(h.p_err, ref.p_err);
        }
    }
    ray_ctx_stats(ctx, &st);
    ck_assert_uint_eq(st.tests_by_kind[RAY_PRIM_USER], rays);
    ck_assert_uint_eq(st.root_failures, good ? 0 : rays);
    ray_ctx_free(ctx);
    ray_scene_free(s);
}
END_TEST

/* --------------------------------------- an implicit surface on top */

/* A ray_implicit_surface as user geometry: its box grown by 1e-3, which
** holds every hit (ray_implicit finds roots within its tolerance, here
** ~1e-8, of the surface's box), and ray_implicit's answer passed on, a
** negated status included. */
static void implicit_bounds(void *ud, ray_vec3 *lo, ray_vec3 *hi)
{
    const ray_implicit_surface *is = ud;

    *lo = vsub(is->lo, vec(1e-3, 1e-3, 1e-3));
    *hi = vadd(is->hi, vec(1e-3, 1e-3, 1e-3));
}

static int implicit_intersect(void *ud, const ray_ray *r, ray_hit *hit)
{
    return ray_implicit(r, ud, hit);
}

/*
** The implicit surfaces can stand on user geometry: a torus given as
** ray__implicit_torus's signed distance, once through
** ray_scene_add_implicit and once wrapped in a callback, gives the same
** answers bit for bit on random rays (the same function on the same
** ray), and with too few evaluations (max_iterations 2, _i = 1) the same
** misses and the same root_failures.
*/
START_TEST(implicit_torus_should_stand_on_user_geometry)
{
    ray_torus_params t = {{0.3, -0.2, 0.1}, {0.2, 1, 0.3}, 1.5, 0.4};
    ray_implicit_surface is;
    ray_user_geometry gm;
    ray_scene *sc[2];
    ray_ctx *ctx[2];
    ray_stats st[2];
    rng g = {71};
    int n, k, hits = 0;

    ck_assert_int_eq(ray__implicit_torus(&t, &is), RAY_OK);
    if (_i == 1)
        is.max_iterations = 2;
    gm.bounds = implicit_bounds;
    gm.intersect = implicit_intersect;
    gm.ud = &is;
    for (k = 0; k < 2; k++)
        ck_assert_int_eq(nop_scene_new(&sc[k], NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_implicit(sc[0], &is, 0, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_user(sc[1], &gm, 0, NULL), RAY_OK);
    for (k = 0; k < 2; k++) {
        ck_assert_int_eq(ray_scene_commit(sc[k]), RAY_OK);
        ck_assert_int_eq(ray_ctx_new(sc[k], 1, &ctx[k]), RAY_OK);
    }
    for (n = 0; n < 600; n++) {
        ray_vec3 from = vadd(rng_point(&g, -1, 1), vscale(rng_dir(&g), 5));
        ray_ray r = ray_from(from, vsub(rng_point(&g, -2, 2), from));
        ray_hit h[2];
        ray_rgb c;
        int got[2];

        for (k = 0; k < 2; k++) {
            hit_poison(&h[k]);
            got[k] = ray_intersect(sc[k], &r, &h[k], NULL);
            ck_assert_int_eq(ray_occluded(sc[k], &r, NULL), got[k]);
            ck_assert_int_eq(ray_trace(ctx[k], &r, RAY_KIND_PRIMARY, 1, &c),
                             RAY_OK);
        }
        ck_assert_int_eq(got[1], got[0]);
        ck_assert(got[0] != 1 ? memcmp(&h[0], &h[1], sizeof h[0]) == 0
                              : hit_same(&h[0], &h[1]));
        hits += got[0] == 1;
    }
    for (k = 0; k < 2; k++)
        ray_ctx_stats(ctx[k], &st[k]);
    /* The user box is the larger (grown by 1e-3, not the tolerance), so
    ** it is entered by every ray that enters the other, and a few more. */
    ck_assert_uint_gt(st[0].tests_by_kind[RAY_PRIM_IMPLICIT], 300);
    ck_assert_uint_ge(st[1].tests_by_kind[RAY_PRIM_USER],
                      st[0].tests_by_kind[RAY_PRIM_IMPLICIT]);
    ck_assert_uint_eq(st[1].root_failures, st[0].root_failures);
    if (_i == 0) {
        ck_assert_int_gt(hits, 200);
        ck_assert_uint_eq(st[0].root_failures, 0);
    } else {
        ck_assert_int_eq(hits, 0);
        ck_assert_uint_gt(st[0].root_failures, 200);
    }
    for (k = 0; k < 2; k++) {
        ray_ctx_free(ctx[k]);
        ray_scene_free(sc[k]);
    }
}
END_TEST

/* ------------------------------------------------------- a flat one */

/* The square |x|, |z| <= 1 of the plane y = 0, facing +y: a box with no
** thickness, which the BVH must still reach. */
static void square_bounds(void *ud, ray_vec3 *lo, ray_vec3 *hi)
{
    (void)ud;
    *lo = vec(-1, 0, -1);
    *hi = vec(1, 0, 1);
}

static int square_intersect(void *ud, const ray_ray *r, ray_hit *hit)
{
    ray_hit h;

    (void)ud;
    if (ray_plane(r, vec(0, 0, 0), vec(0, 1, 0), &h) != 1 ||
        !(fabs(h.p.x) <= 1 && fabs(h.p.z) <= 1))
        return 0;
    *hit = h;
    return 1;
}

/* Rays down onto the square (and beside it) among 20 spheres that fill
** the BVH: hit exactly where ray_plane says inside it, missed outside. */
START_TEST(flat_user_geometry_should_be_found)
{
    ray_user_geometry gm;
    ray_scene *s = NULL;   /* -O1 cannot see that ck_assert stops */
    unsigned id;
    rng g = {9};
    int n, k, hits = 0;

    gm.bounds = square_bounds;
    gm.intersect = square_intersect;
    gm.ud = NULL;
    ck_assert_int_eq(nop_scene_new(&s, NULL, NULL), RAY_OK);
    for (k = 0; k < 20; k++)
        ck_assert_int_eq(ray_scene_add_sphere(s, vec(3 + k, 0, 0), 0.4, 0,
                                              NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_user(s, &gm, 0, &id), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    for (n = 0; n < 1000; n++) {
        ray_vec3 at = vec(rng_range(&g, -1.5, 1.5), 0,
                          rng_range(&g, -1.5, 1.5));
        ray_vec3 from = vadd(at, vec(rng_range(&g, -1, 1), 3, 0));
        ray_ray r = ray_from(from, vsub(at, from));
        ray_hit h, ref;
        int inside = fabs(at.x) <= 1 && fabs(at.z) <= 1;
        int got = ray_intersect(s, &r, &h, NULL);

        /* Within 1e-12 of an edge the rounded p may fall either side. */
        if (fabs(fabs(at.x) - 1) < 1e-12 || fabs(fabs(at.z) - 1) < 1e-12)
            continue;
        ck_assert_int_eq(got, inside);
        if (!got)
            continue;
        hits++;
        ck_assert_int_eq(ray_plane(&r, vec(0, 0, 0), vec(0, 1, 0), &ref), 1);
        ck_assert_uint_eq(h.geom_id, id);
        ck_assert_double_eq(h.t, ref.t);
        ck_assert_vec_eq(h.n, vec(0, 1, 0));
    }
    ck_assert_int_gt(hits, 300);
    ray_scene_free(s);
}
END_TEST

/* ------------------------------------------------------------ bad input */

/* A box as the test sets it, through bounds, counting the calls. */
typedef struct box_answer {
    ray_vec3 lo, hi;
    int write, calls;
} box_answer;

static void given_bounds(void *ud, ray_vec3 *lo, ray_vec3 *hi)
{
    box_answer *b = ud;

    b->calls++;
    if (!b->write)
        return;
    *lo = b->lo;
    *hi = b->hi;
}

static int never_intersect(void *ud, const ray_ray *r, ray_hit *hit)
{
    (void)ud, (void)r, (void)hit;
    return 0;
}

/* Status and the exact message of a refused call. */
#define ck_refused(s, call, status, msg)                                   \
    do {                                                                   \
        ck_assert_int_eq((call), (status));                                \
        ck_assert_str_eq(ray_scene_errmsg(s), (msg));                      \
    } while (0)

START_TEST(bad_user_geometry_should_be_refused_by_name)
{
    box_answer b = {{-1, -2, -3}, {1, 2, 3}, 1, 0};
    ray_user_geometry gm, bad;
    ray_scene *s = NULL;   /* -O1 cannot see that ck_assert stops */
    unsigned id = 77;

    gm.bounds = given_bounds;
    gm.intersect = never_intersect;
    gm.ud = &b;
    ck_assert_int_eq(nop_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_user(NULL, &gm, 0, &id), RAY_EINVAL);
    ck_refused(s, ray_scene_add_user(s, NULL, 0, &id), RAY_EINVAL,
               "ray_scene_add_user: user geometry is NULL");
    bad = gm;
    bad.bounds = NULL;
    ck_refused(s, ray_scene_add_user(s, &bad, 0, &id), RAY_EINVAL,
               "ray_scene_add_user: bounds is NULL");
    bad = gm;
    bad.intersect = NULL;
    ck_refused(s, ray_scene_add_user(s, &bad, 0, &id), RAY_EINVAL,
               "ray_scene_add_user: intersect is NULL");
    ck_assert_int_eq(b.calls, 0);
    b.lo.y = (double)NAN;
    ck_refused(s, ray_scene_add_user(s, &gm, 0, &id), RAY_EINVAL,
               "ray_scene_add_user: the bounds callback gave lo (-1, nan, -3) "
               "hi (1, 2, 3): y is not finite");
    b.lo.y = -2;
    b.hi.x = HUGE_VAL;
    ck_refused(s, ray_scene_add_user(s, &gm, 0, &id), RAY_EINVAL,
               "ray_scene_add_user: the bounds callback gave lo (-1, -2, -3) "
               "hi (inf, 2, 3): x is not finite");
    b.hi.x = 1;
    b.lo.z = 4;
    ck_refused(s, ray_scene_add_user(s, &gm, 0, &id), RAY_EINVAL,
               "ray_scene_add_user: the bounds callback gave lo (-1, -2, 4) "
               "hi (1, 2, 3): lo.z 4 > hi.z 3");
    b.lo.z = -3;
    b.write = 0;
    ck_refused(s, ray_scene_add_user(s, &gm, 0, &id), RAY_EINVAL,
               "ray_scene_add_user: the bounds callback gave lo (inf, inf, "
               "inf) hi (-inf, -inf, -inf): x is not finite");
    b.write = 1;
    ck_refused(s, ray_scene_add_user(s, &gm, 5, &id), RAY_EINVAL,
               "ray_scene_add_user: material 5 does not exist (the scene "
               "has 1)");
    ck_assert_uint_eq(id, 77);
    /* Nothing was added: the next geometry is 0; a box of no extent on
    ** an axis (flat geometry), or on all (a point), is valid. */
    ck_assert_int_eq(ray_scene_add_user(s, &gm, 0, &id), RAY_OK);
    ck_assert_uint_eq(id, 0);
    ck_assert_str_eq(ray_scene_errmsg(s), "");
    b.lo = b.hi = vec(5, 6, 7);
    ck_assert_int_eq(ray_scene_add_user(s, &gm, RAY_NO_MATERIAL, &id),
                     RAY_OK);
    ck_assert_uint_eq(id, 1);
    ck_assert_int_eq(b.calls, 7);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    /* After commit: refused the same way, the scene still committed;
    ** a good one is staged for the next commit. */
    ck_assert_int_eq(ray_scene_add_user(s, NULL, 0, &id), RAY_EINVAL);
    ck_assert_uint_eq(id, 1);
    ck_assert_int_ge(ray_occluded(s, &(ray_ray){{0, 0, 0}, {0, 1, 0}, 0, 1},
                                  NULL), 0);
    ck_assert_int_eq(ray_scene_add_user(s, &gm, 0, &id), RAY_OK);
    ck_assert_uint_eq(id, 2);
    ray_scene_free(s);
}
END_TEST

/* Out of memory for the descriptor's record (left 0) or for the geometry
** record after it (left 1): RAY_ENOMEM, nothing added, and the call
** succeeds once memory is back. */
START_TEST(user_geometry_should_survive_out_of_memory)
{
    box_answer b = {{-1, -1, -1}, {1, 1, 1}, 1, 0};
    ray_user_geometry gm;
    ray_material m = plain();
    ray_scene *s = NULL;   /* -O1 cannot see that ck_assert stops */
    unsigned id = 77;
    long left = 1000;

    gm.bounds = given_bounds;
    gm.intersect = never_intersect;
    gm.ud = &b;
    ck_assert_int_eq(ray_scene_new(&s, failing_alloc, &left), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, NULL), RAY_OK);
    left = 0;
    ck_assert_int_eq(ray_scene_add_user(s, &gm, 0, &id), RAY_ENOMEM);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(s), "out of memory"));
    left = 1;
    ck_assert_int_eq(ray_scene_add_user(s, &gm, 0, &id), RAY_ENOMEM);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(s), "out of memory"));
    ck_assert_uint_eq(id, 77);
    left = 1000;
    ck_assert_int_eq(ray_scene_add_user(s, &gm, 0, &id), RAY_OK);
    ck_assert_uint_eq(id, 0);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ray_scene_free(s);
}
END_TEST

Suite *user_suite(void)
{
    Suite *s = suite_create("user");
    TCase *tc = tcase_create("core");

    tcase_set_timeout(tc, 60);
    tcase_add_loop_test(tc, user_spheres_should_answer_as_the_scene_spheres,
                        0, 4);
    tcase_add_test(tc, user_spheres_should_render_as_the_scene_spheres);
    tcase_add_loop_test(tc, user_answers_should_be_checked, 0, N_ANSWERS);
    tcase_add_loop_test(tc, implicit_torus_should_stand_on_user_geometry, 0,
                        2);
    tcase_add_test(tc, flat_user_geometry_should_be_found);
    tcase_add_test(tc, bad_user_geometry_should_be_refused_by_name);
    tcase_add_test(tc, user_geometry_should_survive_out_of_memory);
    suite_add_tcase(s, tc);
    return s;
}
