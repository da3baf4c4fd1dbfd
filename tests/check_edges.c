/* SPDX-License-Identifier: MIT */
/*
** check_edges.c -- hard cases that cut across the areas (issue 38's
** branch coverage): geometry removed or disabled seen by every query
** kind, and the refusals and degenerate inputs of the functions whose
** other suites test their ordinary cases.  Each test asserts the values
** it gets; the tolerances are derived beside them.
*/
#include <stdlib.h>
#include <string.h>

#include "tests.h"
#include "caustics_kit.h"
#include "hardcases.h"
#include "trace/trace.h"     /* ray__photon_map_counts */

/* ------------------------------------- geometry removed or disabled */

/*
** A scene whose only live geometry is the unit sphere at the origin (id
** 0), beside one removed or disabled object of each kind that bounds a
** solid or lives in the triangle BVH: closed meshes, a sphere, a box, a
** capsule, an open triangle and two instances of a closed cube.  Every
** query must answer as if the unit sphere were alone.
*/
typedef struct ghost_scene {
    ray_scene *s, *child;
    hc_mesh cube[3];
} ghost_scene;

enum { GHOST_KEEP, GHOST_REMOVE, GHOST_DISABLE };

static void ghost_add_mesh(ray_scene *s, hc_mesh *m, ray_vec3 c, int how)
{
    ray_mesh rm;
    unsigned id;

    *m = hc_cube(c);
    rm = hc_ray_mesh(m);
    ck_assert_int_eq(ray_scene_add_mesh(s, &rm, RAY_NO_MATERIAL, &id), RAY_OK);
    if (how == GHOST_REMOVE)
        ck_assert_int_eq(ray_scene_remove(s, id), RAY_OK);
    else if (how == GHOST_DISABLE)
        ck_assert_int_eq(ray_scene_set_enabled(s, id, 0), RAY_OK);
}

static void ghost_hide(ray_scene *s, unsigned id, int how)
{
    if (how == GHOST_REMOVE)
        ck_assert_int_eq(ray_scene_remove(s, id), RAY_OK);
    else
        ck_assert_int_eq(ray_scene_set_enabled(s, id, 0), RAY_OK);
}

static void ghost_build(ghost_scene *g)
{
    ray_box_params b;
    ray_capsule_params c;
    ray_transform x;
    unsigned id;

    ck_assert_int_eq(ray_scene_new(&g->child, NULL, NULL), RAY_OK);
    ghost_add_mesh(g->child, &g->cube[0], vec(0, 0, 0), GHOST_KEEP);
    ck_assert_int_eq(ray_scene_commit(g->child), RAY_OK);

    ck_assert_int_eq(ray_scene_new(&g->s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(g->s, vec(0, 0, 0), 1,
                                          RAY_NO_MATERIAL, &id), RAY_OK);
    ck_assert_uint_eq(id, 0);
    ghost_add_mesh(g->s, &g->cube[1], vec(5, 0, 0), GHOST_REMOVE);
    ghost_add_mesh(g->s, &g->cube[2], vec(25, 0, 0), GHOST_DISABLE);
    ck_assert_int_eq(ray_scene_add_sphere(g->s, vec(10, 0, 0), 1,
                                          RAY_NO_MATERIAL, &id), RAY_OK);
    ghost_hide(g->s, id, GHOST_DISABLE);
    memset(&b, 0, sizeof b);
    b.center = vec(15, 0, 0);
    b.half_extents = vec(1, 1, 1);
    b.axis_x = vec(1, 0, 0);
    b.axis_y = vec(0, 1, 0);
    ck_assert_int_eq(ray_scene_add_box(g->s, &b, RAY_NO_MATERIAL, &id),
                     RAY_OK);
    ghost_hide(g->s, id, GHOST_REMOVE);
    c.a = vec(19, 0, 0);
    c.b = vec(21, 0, 0);
    c.radius = 1;
    ck_assert_int_eq(ray_scene_add_capsule(g->s, &c, RAY_NO_MATERIAL, &id),
                     RAY_OK);
    ghost_hide(g->s, id, GHOST_DISABLE);
    ck_assert_int_eq(ray_scene_add_triangle(g->s, vec(-1, -5, -1),
                                            vec(1, -5, -1), vec(0, -5, 1),
                                            RAY_NO_MATERIAL, &id), RAY_OK);
    ghost_hide(g->s, id, GHOST_REMOVE);
    ray_transform_identity(&x);
    x.m[1][3] = 5;
    ck_assert_int_eq(ray_scene_add_instance(g->s, g->child, &x, &id), RAY_OK);
    ghost_hide(g->s, id, GHOST_REMOVE);
    x.m[1][3] = 10;
    ck_assert_int_eq(ray_scene_add_instance(g->s, g->child, &x, &id), RAY_OK);
    ghost_hide(g->s, id, GHOST_DISABLE);
    ck_assert_int_eq(ray_scene_commit(g->s), RAY_OK);
}

static void ghost_free(ghost_scene *g)
{
    int k;

    ray_scene_free(g->s);
    ray_scene_free(g->child);
    for (k = 0; k < 3; k++)
        hc_mesh_free(&g->cube[k]);
}

/* The centres of the hidden objects, and one point inside the sphere. */
static const ray_vec3 ghost_points[] = {
    {5, 0, 0}, {25, 0, 0}, {10, 0, 0}, {15, 0, 0}, {20, 0, 0},
    {0, -5, 0}, {0, 5, 0}, {0, 10, 0}, {0.25, 0, 0}};
#define N_GHOST (sizeof ghost_points / sizeof *ghost_points)

/*
** ray_contains by parity, by the fast and the exact winding number, and
** ray_signed_distance: one point inside, the last (|q| = 0.25 < 1),
** and the distance is |q| - 1 from the sphere alone.  The sphere's
** distance is computed from a centre and radius that are exact in
** binary, to within a few roundings of |q| (at most 25): 1e-12 is far
** above that and far below the next object's gap (2 or more).
*/
START_TEST(hidden_geometry_should_not_contain_or_attract)
{
    static const unsigned flags[3] = {0, RAY_CONTAINS_WINDING,
                                      RAY_CONTAINS_WINDING |
                                      RAY_CONTAINS_WINDING_EXACT};
    ghost_scene g;
    ray_inside in[N_GHOST];
    ray_contains_options o;
    size_t i;
    int f;

    ghost_build(&g);
    for (f = 0; f < 3; f++) {
        memset(&o, 0, sizeof o);
        o.flags = flags[f];
        memset(in, 0xAB, sizeof in);
        ck_assert_int_eq(ray_contains(g.s, ghost_points, N_GHOST, &o, in),
                         1);
        for (i = 0; i < N_GHOST; i++) {
            ck_assert_msg(in[i].inside == (i == N_GHOST - 1),
                          "flags %u point %u: inside %d", flags[f],
                          (unsigned)i, in[i].inside);
            ck_assert_int_eq(in[i].on_surface, 0);
        }
    }
    for (i = 0; i < N_GHOST; i++) {
        ray_vec3 q = ghost_points[i];
        double d = -7, want = vlen(q) - 1;
        ray_closest c;

        memset(&o, 0, sizeof o);
        ck_assert_int_eq(ray_signed_distance(g.s, q, HUGE_VAL, &o, &d, &c),
                         1);
        ck_assert_msg(fabs(d - want) <= 1e-12, "point %u: %.17g, want %.17g",
                      (unsigned)i, d, want);
        ck_assert_uint_eq(c.geom_id, 0);
        ck_assert_uint_eq(c.inst_id, RAY_INVALID_ID);
        memset(&c, 0, sizeof c);
        ck_assert_int_eq(ray_closest_point(g.s, q, HUGE_VAL, &c), 1);
        ck_assert_msg(fabs(c.distance - fabs(want)) <= 1e-12,
                      "point %u: closest %.17g", (unsigned)i, c.distance);
        ck_assert_uint_eq(c.geom_id, 0);
    }
    ghost_free(&g);
}
END_TEST

/*
** Shapes placed on each hidden object overlap nothing, and sweeps and
** rays aimed through them reach the sphere or nothing.  A sweep of a
** sphere of radius 0.5 from (-30, 0, 0) along +x through every hidden
** object on the x axis first touches the unit sphere at x = -1.5: t =
** 28.5 of a motion of length 1 a unit of t, within 1e-9 (the sweep's
** root is solved to a few ulps of its 30-unit scale, ~1e-14).
*/
START_TEST(hidden_geometry_should_not_be_touched)
{
    ghost_scene g;
    ray_overlap found[4];
    ray_contact hit;
    ray_sweep sw;
    ray_hit h;
    ray_ray r;
    size_t i, count;

    ghost_build(&g);
    for (i = 0; i + 1 < N_GHOST; i++) {
        ray_shape sh;

        memset(&sh, 0, sizeof sh);
        sh.a = sh.b = ghost_points[i];
        sh.radius = 0.5;
        count = 99;
        ck_assert_int_eq(ray_overlap_shape_all(g.s, &sh, NULL, found, 4,
                                               &count), 0);
        ck_assert_uint_eq(count, 0);
    }
    memset(&sw, 0, sizeof sw);
    sw.shape.a = sw.shape.b = vec(30, 0, 0);
    sw.shape.radius = 0.5;
    sw.dir = vec(-1, 0, 0);
    sw.tmax = 100;
    memset(&hit, 0, sizeof hit);
    ck_assert_int_eq(ray_intersect_sweep(g.s, &sw, NULL, &hit), 1);
    ck_assert_msg(fabs(hit.t - 28.5) <= 1e-9, "t %.17g", hit.t);
    ck_assert_uint_eq(hit.geom_id, 0);
    /* Down the y axis through the hidden instances and triangle: the
    ** sphere's top at t = 19 from y = 20 (exact in binary; 1e-12). */
    r.org = vec(0, 20, 0);
    r.dir = vec(0, -1, 0);
    r.tmin = 0;
    r.tmax = HUGE_VAL;
    ck_assert_int_eq(ray_intersect(g.s, &r, &h, NULL), 1);
    ck_assert_msg(fabs(h.t - 19) <= 1e-12, "t %.17g", h.t);
    ck_assert_uint_eq(h.geom_id, 0);
    ghost_free(&g);
}
END_TEST

/* ------------------------------------------------------------ photons */

/*
** The mirror scene of check_caustics.c, smaller: a point light of
** intensity I at (0, 1, 0) under a 2 x 2 mirror at y = 2, over the probe
** floor y = 0; then what the test adds.  Returns the scene uncommitted.
*/
static ray_scene *photon_scene(ray_rgb I, unsigned *pm, unsigned *mm)
{
    static const ray_rgb R = {0.5, 0.5, 0.5};
    ray_scene *s;
    ray_material probe = probe_material();
    ray_material mirror = ray_material_mirror(&R);
    ray_light l;

    ray_light_init(&l, RAY_LIGHT_POINT);
    l.position = vec(0, 1, 0);
    l.intensity = I;
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &probe, pm), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &mirror, mm), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 1, 0), *pm,
                                         NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    return s;
}

static void add_mirror(ray_scene *s, double y, double half, unsigned mm,
                       unsigned *id)
{
    ray_vec3 v[4];

    v[0] = vec(-half, y, -half);
    v[1] = vec(half, y, -half);
    v[2] = vec(half, y, half);
    v[3] = vec(-half, y, half);
    ck_assert_int_eq(ray_scene_add_polygon(s, v, 4, mm, id), RAY_OK);
}

static int photon_build(const ray_scene *s, unsigned long long n,
                        ray_stats *st, ray_photon_map **keep)
{
    ray_render_options o;
    ray_photon_map *map = NULL;
    int rc;

    o = (ray_render_options){.width = 1, .height = 1};
    o.photons = n;
    o.seed = 7;
    o.threads = 1;
    rc = ray_photon_map_build(s, &o, &map);
    memset(st, 0, sizeof *st);
    if (rc == RAY_OK) {
        ray__photon_map_counts(map, st);
        if (keep != NULL)
            *keep = map;
        else
            ray_photon_map_free(map);
    } else
        ck_assert_ptr_null(map);
    return rc;
}

/*
** What the photon pass aims at: only enabled geometry whose material
** scatters.  A disabled mirror, a mirror without a material and an
** instance whose child scatters nothing are no target; with one live
** mirror among them the pass emits every photon and stores some (the
** live mirror sends light down to the floor), and with the live one
** disabled too nothing scatters: every photon is emitted, none stored.
** Counts, not energies: exact.
*/
START_TEST(photons_should_aim_only_at_live_scattering_geometry)
{
    ray_scene *s, *child;
    ray_transform x;
    ray_stats st;
    unsigned pm, mm, cm, live, dead;
    ray_material plain_m = plain();

    s = photon_scene(rgb(1, 1, 1), &pm, &mm);
    add_mirror(s, 2, 1, mm, &live);
    add_mirror(s, 3, 1, mm, &dead);
    ck_assert_int_eq(ray_scene_set_enabled(s, dead, 0), RAY_OK);
    add_mirror(s, 4, 1, RAY_NO_MATERIAL, NULL);
    ck_assert_int_eq(ray_scene_new(&child, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(child, &plain_m, &cm), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(child, vec(0, 0, 0), 0.5, cm, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    ray_transform_identity(&x);
    x.m[0][3] = 5;
    ck_assert_int_eq(ray_scene_add_instance(s, child, &x, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(photon_build(s, 2000, &st, NULL), RAY_OK);
    ck_assert_uint_eq(st.photons_emitted, 2000);
    ck_assert_uint_gt(st.photons_stored, 0);
    ck_assert_int_eq(ray_scene_set_enabled(s, live, 0), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(photon_build(s, 2000, &st, NULL), RAY_OK);
    ck_assert_uint_eq(st.photons_stored, 0);
    /* The child changed since the commit: the pass refuses, as the
    ** queries do, and writes no map. */
    ck_assert_int_eq(ray_scene_add_sphere(child, vec(0, 2, 0), 0.5, cm, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    ck_assert_int_eq(photon_build(s, 2000, &st, NULL), RAY_ESTATE);
    ray_scene_free(s);
    ray_scene_free(child);
}
END_TEST

/*
** Lights whose total power is 0 (a dark light) or overflows (two lights
** of 1e308 each: their sum is infinite) emit nothing: the map is empty
** and built (RAY_OK), as for a scene without caustics.  A scattering
** plane with nothing bounded (no box to aim at) is aimed at by the whole
** sphere around the scene: photons are emitted.
*/
START_TEST(photons_should_handle_dark_and_overflowing_lights)
{
    ray_scene *s;
    ray_light l;
    ray_stats st;
    unsigned pm, mm;

    s = photon_scene(rgb(0, 0, 0), &pm, &mm);
    add_mirror(s, 2, 1, mm, NULL);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(photon_build(s, 1000, &st, NULL), RAY_OK);
    ck_assert_uint_eq(st.photons_emitted, 0);
    ck_assert_uint_eq(st.photons_stored, 0);
    ray_scene_free(s);

    s = photon_scene(rgb(1e308, 1e308, 1e308), &pm, &mm);
    ray_light_init(&l, RAY_LIGHT_POINT);
    l.position = vec(0, 1.5, 0);
    l.intensity = rgb(1e308, 1e308, 1e308);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    add_mirror(s, 2, 1, mm, NULL);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(photon_build(s, 1000, &st, NULL), RAY_OK);
    ck_assert_uint_eq(st.photons_emitted, 0);
    ck_assert_uint_eq(st.photons_stored, 0);
    ray_scene_free(s);

    /* A mirror plane y = 2 facing down over the floor: every photon sent
    ** up is reflected down and lands on the floor. */
    s = photon_scene(rgb(1, 1, 1), &pm, &mm);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 2, 0), vec(0, -1, 0), mm,
                                         NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(photon_build(s, 1000, &st, NULL), RAY_OK);
    ck_assert_uint_eq(st.photons_emitted, 1000);
    ck_assert_uint_gt(st.photons_stored, 0);
    ray_scene_free(s);
}
END_TEST

/*
** The automatic radius is D / 100 (N / 100 000)^(-1/6), D the diagonal
** of the scattering geometry's box.  A mirror sphere of radius 1e-160 at
** the origin (its box about 2e-160 wide: nothing of the centre's
** rounding to add) at 1000 photons gives a radius near 7e-162, whose
** disk area (1.6e-322, subnormal) has no finite inverse: refused
** (RAY_EINVAL, no map), as an explicit radius of 1e-200 is.  A mirror
** sphere of radius 1e160, whose box's diagonal overflows (|hi - lo|^2 is
** 1.2e321), is aimed at by no finite sphere: the pass falls back to a
** unit scale and still emits every photon, without dividing by the
** infinite size.
*/
START_TEST(photons_should_survive_targets_too_small_or_too_large)
{
    ray_scene *s;
    ray_stats st;
    unsigned pm, mm;

    s = photon_scene(rgb(1, 1, 1), &pm, &mm);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1e-160, mm, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(photon_build(s, 1000, &st, NULL), RAY_EINVAL);
    ray_scene_free(s);

    s = photon_scene(rgb(1, 1, 1), &pm, &mm);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 1e161, 0), 1e160, mm,
                                          NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(photon_build(s, 1000, &st, NULL), RAY_OK);
    ck_assert_uint_eq(st.photons_emitted, 1000);
    ray_scene_free(s);
}
END_TEST

Suite *edges_suite(void)
{
    Suite *s = suite_create("edges");
    TCase *tc = tcase_create("core");

    tcase_add_test(tc, hidden_geometry_should_not_contain_or_attract);
    tcase_add_test(tc, hidden_geometry_should_not_be_touched);
    tcase_add_test(tc, photons_should_aim_only_at_live_scattering_geometry);
    tcase_add_test(tc, photons_should_handle_dark_and_overflowing_lights);
    tcase_add_test(tc, photons_should_survive_targets_too_small_or_too_large);
    suite_add_tcase(s, tc);
    return s;
}
