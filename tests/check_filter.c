/* SPDX-License-Identifier: MIT */
/*
** check_filter.c -- the float filter in front of the exact triangle test
** (src/query/filter.h): it only skips triangles the exact test misses, so
** every answer is bit for bit the exact test's alone (API notes 15), on
** ten million hard rays -- at shared vertices and edges of a closed
** icosphere, needles and caps, grazing rays -- with meshes whose
** vertices are floats and meshes whose are not, at 0, 1e5 and 1e6 from
** the origin; and its bound is tight: half of it loses hits on worst
** cases built for it, for float and for double meshes, so a test fails
** when the bound or its origin term is halved.
*/
#include <stdlib.h>

#include "tests.h"
#include "filter_kit.h"
#include "scene/scene.h"

/* A committed scene of mesh m alone. */
static ray_scene *kit_scene(const hc_mesh *m)
{
    ray_mesh rm = hc_ray_mesh(m);
    ray_scene *s;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &rm, RAY_NO_MATERIAL, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    return s;
}

/* Rays 0 .. n - 1 of fk_ray's kinds at m from "dist" away: how many
** answer otherwise with the filter than without it -- the nearest hit's
** status and record, byte for byte (records cleared first), and, for
** every fourth ray, the any-hit query. */
static size_t differences(ray_scene *s, const hc_mesh *m, double dist,
                          size_t n, unsigned long long seed, size_t *hits)
{
    rng g = {seed};
    size_t i, diff = 0;

    *hits = 0;
    for (i = 0; i < n; i++) {
        ray_ray r = fk_ray(m, dist, &g, (unsigned)i);
        ray_hit hf, he;
        int f, e;
        memset(&hf, 0, sizeof hf);
        memset(&he, 0, sizeof he);
        ray__scene_set_tri_mode(s, RAY__TRI_FILTERED);
        f = ray_intersect(s, &r, &hf, NULL);
        ray__scene_set_tri_mode(s, RAY__TRI_EXACT);
        e = ray_intersect(s, &r, &he, NULL);
        *hits += f > 0;
        diff += f != e || memcmp(&hf, &he, sizeof hf) != 0;
        if (i % 4 == 0) {
            ray__scene_set_tri_mode(s, RAY__TRI_FILTERED);
            f = ray_occluded(s, &r, NULL);
            ray__scene_set_tri_mode(s, RAY__TRI_EXACT);
            diff += f != ray_occluded(s, &r, NULL);
        }
    }
    return diff;
}

/* The test's ray count: ten million under make check-long, a million
** under make check (the sanitizer builds' count too: they are 3 to 15
** times slower), or RAY_FILTER_RAYS. */
static size_t filter_rays(void)
{
    return test_count("RAY_FILTER_RAYS", 10000000, 1000000);
}

/*
** Three meshes (a closed icosphere of 1280 triangles, a spindle of 400
** needles, a strip of 400 caps), each with float and with non-float
** vertices, at 0, 1e5 and 1e6 from the origin: 18 scenes, the rays
** shared out among them.  Not one answer differs.  (The rays were also
** run through the AVX2 copy and the baseline one, which
** check_bvh.c compares; the filter's three versions -- eight lanes, two
** halves of four, plain C -- run in the CI's builds.)
*/
START_TEST(filter_should_change_no_answer_on_ten_million_hard_rays)
{
    static const double offsets[3] = {0, 1e5, 1e6};
    size_t per = filter_rays() / 18 + 1, total = 0, hits = 0;
    int o, kind, floats;

    for (o = 0; o < 3; o++)
        for (kind = 0; kind < 3; kind++)
            for (floats = 0; floats < 2; floats++) {
                ray_vec3 c = v3(offsets[o], -0.5 * offsets[o],
                                0.25 * offsets[o]);
                hc_mesh m = kind == 0   ? hc_icosphere(c, 3)
                            : kind == 1 ? hc_spindle(c, 200, 50)
                                        : fk_caps(c, 400);
                ray_scene *s;
                size_t h, d;
                fk_grid(&m, floats);
                s = kit_scene(&m);
                d = differences(s, &m, kind == 1 ? 80 : 5, per,
                                (unsigned long long)(100 * o + 10 * kind +
                                                     floats),
                                &h);
                ck_assert_msg(d == 0, "%zu of %zu answers differ (mesh %d, "
                              "offset %g, floats %d)", d, per, kind,
                              offsets[o], floats);
                total += per;
                hits += h;
                ray_scene_free(s);
                hc_mesh_free(&m);
            }
    /* Most rays hit: the cases are hard, not missed. */
    ck_assert_msg(hits > total / 2, "%zu hits of %zu rays", hits, total);
}
END_TEST

/*
** The bound's worst cases, in each regime of its derivation (filter.h:
** xi0 = (4 + 2^-20) u O + (6 + 2^-20) u M, or (2, 4) for float corners):
** 625 triangles, their vertices on the float grid of step q = 1/8 just
** above 2^20 around where the ray crosses z = z0, their edge bc across
** the ray's path, at (W, -W) and (-W, W) steps in the ray's frame (the
** four products of the edge function at their largest), its edge
** function small, and each vertex then moved by "off" (0 for a float
** mesh; else just under half a step, so that each coordinate's float is
** the grid point and its rounding error d = u (O + M) is at its largest,
** in the direction that adds to the origin's); W: the half-width, in
** steps, of the triangles' edge bc across the ray.  Counts the exact
** test's hits and those the filter loses with its bound times "scale";
** asserts that with the whole bound it loses none, and that the corners
** are or are not floats as meant.
*/
static void family_losses(const char *name, const ray_ray *r, double z0,
                          int W, ray_vec3 off, int floats, double scale,
                          int *hits, int *lost)
{
    const double q = 0.125;
    double t = (z0 - r->org.z) / r->dir.z;
    double cx = floor((r->org.x + t * r->dir.x) / q) * q;
    double cy = floor((r->org.y + t * r->dir.y) / q) * q;
    int d1, d2, e1, e2;

    *hits = *lost = 0;
    for (d1 = -2; d1 <= 2; d1++)
        for (d2 = -2; d2 <= 2; d2++)
            for (e1 = -2; e1 <= 2; e1++)
                for (e2 = -2; e2 <= 2; e2++) {
                    ray_vec3 v[3];
                    unsigned idx[3] = {0, 1, 2};
                    ray_mesh m;
                    ray_scene *s;
                    ray_hit h;
                    int exact, full, part;
                    v[0] = v3(cx + (W + 1) * q, cy + (W + 1) * q, z0);
                    v[1] = v3(cx + (W + 1 + d1) * q, cy + (-W + 1 + d2) * q,
                              z0);
                    v[2] = v3(cx + (-W + 1 + e1) * q, cy + (W + 1 + e2) * q,
                              z0);
                    v[0] = v3_add(v[0], off);
                    v[1] = v3_add(v[1], off);
                    v[2] = v3_add(v[2], off);
                    memset(&m, 0, sizeof m);
                    m.vertices = v;
                    m.vertex_count = 3;
                    m.indices = idx;
                    m.triangle_count = 1;
                    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
                    ck_assert_int_eq(ray_scene_add_mesh(s, &m,
                                                        RAY_NO_MATERIAL,
                                                        NULL), RAY_OK);
                    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
                    ck_assert_int_eq(s->float_exact, floats);
                    ray__scene_set_tri_mode(s, RAY__TRI_EXACT);
                    exact = ray_intersect(s, r, &h, NULL);
                    ray__scene_set_tri_mode(s, RAY__TRI_FILTERED);
                    full = ray_intersect(s, r, &h, NULL);
                    ray__scene_set_filter_scale(s, scale);
                    part = ray_intersect(s, r, &h, NULL);
                    ray_scene_free(s);
                    ck_assert_msg(full == exact, "%s: the whole bound "
                                  "answers %d, the exact test %d (%d %d %d "
                                  "%d)", name, full, exact, d1, d2, e1, e2);
                    *hits += exact > 0;
                    *lost += exact > 0 && part == 0;
                }
}

/*
** Origin-dominated, float mesh: the origin at 2^20 + 1 (O = 2^20, M
** about 20, xi0 = 2.0000004 u O), a ray along (1, 1, 1) -- its shear 1,
** exact, so the whole float error is the origin's rounding, half an ulp
** (1/16) on each axis, aligned to shift the projected triangle by (1/8,
** 1/8), the most the bound allows (filter.h: the common shift).  The
** origin's rounding moves the float edge function by 4 W / 8 = 2 (W = 4)
** toward negative, against a bound of about 2 (4 xi W, xi = 1/8), so the
** filter keeps every hit with its bound and drops some with half.
** Origin-dominated with a double mesh: the same origin (xi0 = 4.0000007
** u O), and each vertex coordinate 2^-30 short of half a float step off
** the grid, so that its rounding adds d = u O = 1/16 on each axis in the
** direction of the origin's: the projected triangle moves by 1/4 = 4 u
** O, all of the bound's origin and vertex terms, so that with
** FILTER_XI_O halved (make mutants' filter-xi-o) the whole bound loses
** hits, which family_losses refuses.  Vertex-dominated, float and double
** meshes: the origin near 0 (O = 1/16, M = 2^20, xi0 = 4 u M or 6 u M),
** each component 2^-24 short of 1/16, so that v - o rounds by half a
** step (1/16 = u M) on each axis, the direction (1 - e, 1 - e, 1) with e
** just under 2^-24 (its shear's float is 1: off by u, times Z = 2^20 a
** further 1/16), and the double mesh's own rounding as above: shifts of
** 3/16 (of the bound's 4/16) and 5/16 (of 6/16).  In each, half the
** bound loses hits (68 to 206 of some 140 to 570), the whole bound none.
** Without the vertex term for the double meshes (filter.h,
** FILTER_XI_*_EXACT used for every mesh), both double cases lose hits
** too.
*/
START_TEST(filter_bound_halved_should_lose_hits_in_every_regime)
{
    const double F = 1048577.0, h = 0.0625, z = F + 10;
    const double e = 0x1p-24 * (1 - 0x1p-20);
    const double dv = h - 0x1p-30;      /* a vertex's rounding: ~1/16 */
    ray_ray r;
    int hits, lost;

    r.tmin = 0;
    r.tmax = HUGE_VAL;
    /* Origin-dominated, float mesh and double mesh. */
    r.org = v3(F + h - 0x1p-30, F + h - 0x1p-30, F - h + 0x1p-30);
    r.dir = v3(1, 1, 1);
    family_losses("origin, float mesh", &r, z, 32, v3(0, 0, 0), 1, 0.5,
                  &hits, &lost);
    ck_assert_int_eq(hits, 290);        /* the exact test's, fixed */
    ck_assert_msg(lost > 0, "origin, float mesh: half the bound lost none "
                  "of %d hits", hits);
    family_losses("origin, double mesh", &r, z, 32, v3(-dv, -dv, dv), 0, 0.5,
                  &hits, &lost);
    ck_assert_int_eq(hits, 565);        /* the exact test's, fixed */
    ck_assert_msg(lost > 0, "origin, double mesh: half the bound lost none "
                  "of %d hits", hits);
    /* Vertex-dominated, float mesh and double mesh. */
    r.org = v3(h - 0x1p-24, h - 0x1p-24, -h + 0x1p-24);
    r.dir = v3(1 - e, 1 - e, 1);
    family_losses("vertex, float mesh", &r, z, 32, v3(0, 0, 0), 1, 0.5,
                  &hits, &lost);
    ck_assert_int_eq(hits, 142);
    ck_assert_msg(lost > 0, "vertex, float mesh: half the bound lost none "
                  "of %d hits", hits);
    family_losses("vertex, double mesh", &r, z, 32, v3(-dv, -dv, dv), 0, 0.5,
                  &hits, &lost);
    ck_assert_int_eq(hits, 455);
    ck_assert_msg(lost > 0, "vertex, double mesh: half the bound lost none "
                  "of %d hits", hits);
    /* The same with triangles that span much of the box: W = 2^19 and
    ** 2^20 steps (a projected extent W of 2^16 and 2^17 against M of
    ** 2^21), the plane z0 moved so that every coordinate stays in
    ** [2^20, 2^21), where a float's step is 1/8.  (The products'
    ** rounding, 4.0001 u P^2, cannot dominate the bound: xi >= xi0 + u
    ** W and xi0 >= 4 u M >= 2 u W, so it is at most a quarter of it.
    ** Halved, to 2.0001 u P^2, it is still a bound, so no test can fail
    ** on that: of the three roundings it counts, the subtraction's cannot
    ** take e_f below -B when p0 - p1 is not (rounding is monotonic and
    ** -B is a float), and the two products' are at most u W_f^2 each.) */
    family_losses("vertex, float mesh, W 2^19", &r,
                  1048576.0 + 0x1p19 * 0.125 * 1.5, 1 << 19, v3(0, 0, 0), 1,
                  0.5, &hits, &lost);
    ck_assert_int_eq(hits, 122);
    ck_assert_msg(lost > 0, "vertex, float mesh, W 2^19: half the bound "
                  "lost none of %d hits", hits);
    family_losses("vertex, double mesh, W 2^20", &r,
                  1048576.0 + 0x1p20 * 0.125 * 1.5, 1 << 20, v3(-dv, -dv, dv),
                  0, 0.5, &hits, &lost);
    ck_assert_int_eq(hits, 435);
    ck_assert_msg(lost > 0, "vertex, double mesh, W 2^20: half the bound "
                  "lost none of %d hits", hits);
}
END_TEST

/*
** RAY__TRI_FLOAT, the float tracer the benches compare with (filter.h's
** tri_float_hit, no bound, leaks and all), still keeps the contract on
** easy rays: straight down onto a triangle at z = 5 whose vertices are
** floats, well inside its edges, it hits at t = 5 as the exact test does,
** and a ray that starts on the triangle's plane (t = 0 = tmin) misses,
** as tmin < t demands.  (make mutants' filter-hit-sign, a hit refused
** whenever an edge function is not zero, and filter-hit-tmin, t = tmin
** taken as a hit: neither reached the suite before, as no test ran this
** mode.)
*/
START_TEST(float_mode_should_hit_inside_and_miss_at_tmin)
{
    ray_scene *s;
    ray_ray r;
    ray_hit h;
    int i, j;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_triangle(s, v3(0, 0, 5), v3(4, 0, 5),
                                            v3(0, 4, 5), RAY_NO_MATERIAL,
                                            NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ray__scene_set_tri_mode(s, RAY__TRI_FLOAT);
    r.dir = v3(0, 0, 1);
    r.tmin = 0;
    r.tmax = HUGE_VAL;
    for (i = 1; i <= 5; i++)
        for (j = 1; j <= 5 - i; j++) {
            r.org = v3(0.5 * i, 0.5 * j, 0);
            ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), 1);
            /* Every float step exact here (small integers and halves,
            ** z differences of 5, shear 0): t is 5 exactly. */
            ck_assert_double_eq(h.t, 5.0);
            ck_assert_uint_eq(h.geom_id, 0);
        }
    r.org = v3(1, 1, 5);
    ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), 0);
    ck_assert_int_eq(ray_occluded(s, &r, NULL), 0);
    ray_scene_free(s);
}
END_TEST

Suite *filter_suite(void)
{
    Suite *s = suite_create("filter");
    TCase *t = tcase_create("filter");

    tcase_set_timeout(t, 300);
    tcase_add_test(t, filter_should_change_no_answer_on_ten_million_hard_rays);
    tcase_add_test(t, filter_bound_halved_should_lose_hits_in_every_regime);
    tcase_add_test(t, float_mode_should_hit_inside_and_miss_at_tmin);
    suite_add_tcase(s, t);
    return s;
}
