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

#ifndef RAY_TEST_PNG
#define RAY_TEST_PNG 1
#endif

#include "tests.h"
#include "tempfiles.h"
#include "hardcases.h"
#include "scheduler_kit.h"
#include "prim/prim.h"       /* the primitives' internal entry points */
#include "prim/sweep.h"      /* ray__polygon_plane_mapped */
#include "trace/trace.h"     /* ray__photon_map_counts */
#include "scene/scene.h"     /* ray__scene_set_tri_mode */

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

/*
** ray_contains on a box turned 90 degrees about z (local x along world
** y): inside where every local coordinate is within its half extent
** (2, 1, 0.5), the faces included, and outside past any one of them --
** local x, y and z in turn.  The frame's entries are 0 and +-1 and the
** points small binary fractions: the tests are exact.
*/
START_TEST(a_box_should_contain_within_each_half_extent)
{
    static const ray_vec3 q[] = {
        {0, 0, 0}, {-0.75, 1.5, 0.25}, {1, 2, 0.5},      /* in, on */
        {0, 2.5, 0}, {1.25, 0, 0}, {0, 0, 0.75}};        /* past x, y, z */
    ray_inside in[sizeof q / sizeof *q];
    ray_box_params b;
    ray_scene *s;
    size_t i;

    memset(&b, 0, sizeof b);
    b.half_extents = vec(2, 1, 0.5);
    b.axis_x = vec(0, 1, 0);
    b.axis_y = vec(-1, 0, 0);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_box(s, &b, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_contains(s, q, sizeof q / sizeof *q, NULL, in), 3);
    for (i = 0; i < sizeof q / sizeof *q; i++)
        ck_assert_msg(in[i].inside == (i < 3), "point %u: %d", (unsigned)i,
                      in[i].inside);
    ray_scene_free(s);
}
END_TEST

/*
** A closed mesh with no volume: the two faces (a, b, c) and (c, b, a) of
** a triangle whose corners lie exactly on one line through the origin,
** a, 2a and 1024a with a = (1, 3, x), x = 0.1 with its last two bits
** cleared.  Every edge has its twin, so the mesh is closed; and its
** rounded normal is not zero (c - a rounds in z alone: 1023 x needs 61
** bits), so the triangle keeps its corners rather than being read as a
** point (scene.h).  Exactly, it has no area in any coordinate plane:
** ray_contains's parity walk takes it as its segments.  A point exactly
** on one of them (1.5a, between a and 2a; 4a, between 2a and 1024a: both
** exact, x having the bits to spare) lies on the surface (inside,
** on_surface); points on the line beyond the ends (-a, 0.5a) and one off
** it are outside.  The predicates are exact: no tolerance.
*/
START_TEST(a_closed_mesh_without_volume_should_hold_only_its_segments)
{
    const double x = ldexp(floor(ldexp(0.1, 53) / 4) * 4, -53);
    const ray_vec3 a = {1, 3, x};
    const ray_vec3 v[3] = {{a.x, a.y, a.z}, {2 * a.x, 2 * a.y, 2 * a.z},
                           {1024 * a.x, 1024 * a.y, 1024 * a.z}};
    static const unsigned idx[6] = {0, 1, 2, 2, 1, 0};
    const ray_vec3 q[5] = {{1.5 * a.x, 1.5 * a.y, 1.5 * a.z},
                           {4 * a.x, 4 * a.y, 4 * a.z},
                           {-a.x, -a.y, -a.z},
                           {0.5 * a.x, 0.5 * a.y, 0.5 * a.z},
                           {1.5 * a.x, 1.5 * a.y, 1.5 * a.z + 1}};
    ray_inside in[5];
    ray_mesh m;
    ray_scene *s;
    int i;

    ck_assert(1.5 * x - x == 0.5 * x);          /* 1.5a is exact */
    memset(&m, 0, sizeof m);
    m.vertices = v;
    m.vertex_count = 3;
    m.indices = idx;
    m.triangle_count = 2;
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_contains(s, q, 5, NULL, in), 2);
    for (i = 0; i < 5; i++) {
        ck_assert_msg(in[i].inside == (i < 2), "point %d: inside %d", i,
                      in[i].inside);
        ck_assert_int_eq(in[i].on_surface, i < 2);
    }
    ray_scene_free(s);
}
END_TEST

/* ------------------------------------------------------------- overlap */

/* The overlaps of a capsule shape from a to b, radius r, with s: how many
** (at most 4), the first in *f. */
static size_t capsule_overlaps(const ray_scene *s, ray_vec3 a, ray_vec3 b,
                               double r, ray_overlap *f)
{
    ray_overlap found[4];
    ray_shape sh;
    size_t count = 99;

    memset(&sh, 0, sizeof sh);
    sh.a = a;
    sh.b = b;
    sh.radius = r;
    ck_assert_int_eq(ray_overlap_shape_all(s, &sh, NULL, found, 4, &count),
                     count > 0);
    if (count > 0)
        *f = found[0];
    return count;
}

/*
** Capsule shapes against round primitives seen through an instance that
** scales x by 2 (not a similarity: the sphere is an ellipsoid of
** semi-axes 2, 1, 1 around (10, 0, 0), the capsule a swept ellipsoid
** from y = 5 to 7).  A segment through the ellipsoid overlaps it (even
** with a radius of 0.01: inside); one along x = 13 lies 1 from it
** (the nearest point (12, 0, 0)), so radius 0.5 misses and 1.5 meets.
** The stretched capsule is answered by its box against a capsule shape
** (ray.h): one in the box's corner, 0.7 from the capsule's end in its
** own space, is reported with RAY_CONTACT_BOUNDS.  A torus is answered by its box too: a small
** sphere in its hole.
*/
START_TEST(overlaps_should_see_stretched_spheres_and_boxes_of_the_rest)
{
    ray_scene *child, *s, *ts;
    ray_capsule_params cap = {{0, 5, 0}, {0, 7, 0}, 0.5};
    ray_torus_params tor = {{0, 0, 0}, {0, 0, 1}, 2, 0.5};
    ray_transform x;
    ray_overlap f;
    unsigned inst, sphere_id, cap_id;

    ck_assert_int_eq(ray_scene_new(&child, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(child, vec(0, 0, 0), 1,
                                          RAY_NO_MATERIAL, &sphere_id),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_add_capsule(child, &cap, RAY_NO_MATERIAL,
                                           &cap_id), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ray_transform_identity(&x);
    x.m[0][0] = 2;
    x.m[0][3] = 10;
    ck_assert_int_eq(ray_scene_add_instance(s, child, &x, &inst), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);

    ck_assert_uint_eq(capsule_overlaps(s, vec(10, -3, 0), vec(10, 3, 0), 0.01,
                                       &f), 1);
    ck_assert_uint_eq(f.geom_id, sphere_id);
    ck_assert_uint_eq(f.inst_id, inst);
    ck_assert_uint_eq(f.flags & RAY_CONTACT_BOUNDS, 0);
    ck_assert_uint_eq(capsule_overlaps(s, vec(13, -3, 0), vec(13, 3, 0), 0.5,
                                       &f), 0);
    ck_assert_uint_eq(capsule_overlaps(s, vec(13, -3, 0), vec(13, 3, 0), 1.5,
                                       &f), 1);
    ck_assert_uint_eq(f.geom_id, sphere_id);
    ck_assert_uint_eq(capsule_overlaps(s, vec(10.9, 7.4, 0.4),
                                       vec(10.9, 7.45, 0.4), 0.02, &f), 1);
    ck_assert_uint_eq(f.geom_id, cap_id);
    ck_assert_uint_eq(f.flags & RAY_CONTACT_BOUNDS, RAY_CONTACT_BOUNDS);
    ck_assert_uint_eq(capsule_overlaps(s, vec(10, 20, 0), vec(10, 21, 0), 0.5,
                                       &f), 0);
    /* Swept down z at x = 10 onto each: the stretched capsule's (and
    ** sphere's) section there has half-height 0.5 (1) in z, so a
    ** sphere of radius 0.25 from z = 5 touches at t = 4.25 (3.75);
    ** 1e-9: the ellipsoid's sweep is solved iteratively to ~1e-12. */
    {
        static const double ys[2] = {6, 0}, want[2] = {4.25, 3.75};
        int k;
        for (k = 0; k < 2; k++) {
            ray_sweep sw;
            ray_contact c;
            memset(&sw, 0, sizeof sw);
            sw.shape.a = sw.shape.b = vec(10, ys[k], 5);
            sw.shape.radius = 0.25;
            sw.dir = vec(0, 0, -1);
            sw.tmax = 10;
            ck_assert_int_eq(ray_intersect_sweep(s, &sw, NULL, &c), 1);
            ck_assert_uint_eq(c.geom_id, k == 0 ? cap_id : sphere_id);
            ck_assert_uint_eq(c.inst_id, inst);
            ck_assert_msg(fabs(c.t - want[k]) <= 1e-9, "%d: t %.17g", k,
                          c.t);
        }
    }

    ck_assert_int_eq(ray_scene_new(&ts, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_torus(ts, &tor, RAY_NO_MATERIAL, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_commit(ts), RAY_OK);
    ck_assert_uint_eq(capsule_overlaps(ts, vec(0, 0, 0), vec(0, 0, 0), 0.1,
                                       &f), 1);
    ck_assert_uint_eq(f.flags & RAY_CONTACT_BOUNDS, RAY_CONTACT_BOUNDS);
    ck_assert_uint_eq(capsule_overlaps(ts, vec(0, 0, 5), vec(0, 0, 6), 0.1,
                                       &f), 0);
    ray_scene_free(ts);
    ray_scene_free(s);
    ray_scene_free(child);
}
END_TEST

/* ray_intersect_all's order: t, then geom_id, prim_id, inst_id. */
static int hit_cmp(const void *pa, const void *pb)
{
    const ray_hit *a = pa, *b = pb;

    if (a->t != b->t)
        return a->t < b->t ? -1 : 1;
    if (a->geom_id != b->geom_id)
        return a->geom_id < b->geom_id ? -1 : 1;
    if (a->prim_id != b->prim_id)
        return a->prim_id < b->prim_id ? -1 : 1;
    return a->inst_id < b->inst_id ? -1 : a->inst_id > b->inst_id;
}

/*
** Six hits at one t (the plane z = 0 at t = 5, exact): two coincident
** triangles (geom 0 and 1), a mesh of two coincident triangles (geom 2,
** prims 0 and 1) and two instances (geom 3 and 4) of a scene holding
** the same triangle (its geom 0).  With room for k < 6 of them,
** ray_intersect_all keeps the k first in its order (ties by geom_id,
** then prim_id, then inst_id), nearest first, and counts all six.
*/
START_TEST(intersect_all_should_break_ties_by_ids_when_full)
{
    static const unsigned idx[6] = {0, 1, 2, 0, 1, 2};
    const ray_vec3 v[3] = {{-1, -1, 0}, {2, -1, 0}, {-1, 2, 0}};
    ray_hit all[8], some[8];
    ray_scene *child, *s;
    ray_transform x;
    ray_mesh m;
    ray_ray r = ray_from(vec(0.25, 0.25, 5), vec(0, 0, -1));
    size_t count, cap, i;

    memset(&m, 0, sizeof m);
    m.vertices = v;
    m.vertex_count = 3;
    m.indices = idx;
    m.triangle_count = 2;
    ck_assert_int_eq(ray_scene_new(&child, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_triangle(child, v[0], v[1], v[2],
                                            RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    for (i = 0; i < 2; i++)
        ck_assert_int_eq(ray_scene_add_triangle(s, v[0], v[1], v[2],
                                                RAY_NO_MATERIAL, NULL),
                         RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, NULL), RAY_OK);
    ray_transform_identity(&x);
    for (i = 0; i < 2; i++)
        ck_assert_int_eq(ray_scene_add_instance(s, child, &x, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_intersect_all(s, &r, NULL, all, 8, &count), 6);
    ck_assert_uint_eq(count, 6);
    qsort(all, 6, sizeof *all, hit_cmp);
    for (i = 0; i < 6; i++)
        ck_assert(all[i].t == 5);
    for (cap = 1; cap < 6; cap++) {
        ck_assert_int_eq(ray_intersect_all(s, &r, NULL, some, cap, &count),
                         6);
        ck_assert_uint_eq(count, 6);
        for (i = 0; i < cap; i++)
            ck_assert_msg(hit_cmp(&some[i], &all[i]) == 0, "cap %u hit %u: "
                          "geom %u prim %u inst %u, want %u %u %u",
                          (unsigned)cap, (unsigned)i, some[i].geom_id,
                          some[i].prim_id, some[i].inst_id, all[i].geom_id,
                          all[i].prim_id, all[i].inst_id);
    }
    ray_scene_free(s);
    ray_scene_free(child);
}
END_TEST

/*
** The benches' float tracer (RAY__TRI_FLOAT: filter.h's tri_float_hit,
** taken as final) on the rays it must still answer: from below (z = 0,
** up) and from above (z = 10, down: the edge functions all of the other
** sign) through the triangle at z = 5 it hits at t = 5 exactly (small
** integers and halves: every float step exact); beside each edge, past
** tmax (4) and along the triangle's plane (no area seen: det 0) it
** misses.
*/
START_TEST(float_mode_should_miss_beside_beyond_and_along)
{
    static const ray_vec3 beside[3] = {{-0.5, 1, 0}, {1, -0.5, 0},
                                       {3, 3, 0}};
    ray_scene *s;
    ray_ray r;
    ray_hit h;
    int k;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_triangle(s, vec(0, 0, 5), vec(4, 0, 5),
                                            vec(0, 4, 5), RAY_NO_MATERIAL,
                                            NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ray__scene_set_tri_mode(s, RAY__TRI_FLOAT);
    r = ray_from(vec(1, 1, 0), vec(0, 0, 1));
    ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), 1);
    ck_assert(h.t == 5);
    r = ray_from(vec(1, 1, 10), vec(0, 0, -1));
    ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), 1);
    ck_assert(h.t == 5);
    for (k = 0; k < 3; k++) {
        r = ray_from(beside[k], vec(0, 0, 1));
        ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), 0);
    }
    r = ray_from(vec(1, 1, 0), vec(0, 0, 1));
    r.tmax = 4;
    ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), 0);
    r = ray_from(vec(-1, 1, 5), vec(1, 0, 0));
    ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), 0);
    ray_scene_free(s);
}
END_TEST

/* ------------------------------------------------------------- sweeps */

/* A filter that keeps every candidate, checking that the ray it is
** handed holds the candidate's t strictly inside (ud: calls). */
static int keep_inside(void *ud, const ray_ray *r, const ray_hit *h,
                       void *query_ud)
{
    (void)query_ud;
    ++*(int *)ud;
    ck_assert_msg(r->tmin < h->t && h->t < r->tmax, "t %.17g not in "
                  "(%.17g, %.17g)", h->t, r->tmin, r->tmax);
    return 1;
}

/*
** A sphere of radius 1 swept down from (0, 5, 0) between two instances
** of the unit sphere at x = -1.5 and x = +1.5 touches both at once, at
** the same t (the scene is symmetric in x, and the arithmetic of -x is
** that of x): the lower instance id wins, whichever side it is on (the
** contact point's x has its sign), at t = 5 - sqrt(4 - 2.25) within
** 1e-12 (a root of a quadratic of size 25, a few ulps).
*/
START_TEST(sweep_ties_should_go_to_the_lower_instance)
{
    int order;

    for (order = 0; order < 2; order++) {
        ray_scene *child, *s;
        ray_transform x;
        ray_sweep sw;
        ray_contact c;
        double first = order == 0 ? -1.5 : 1.5;

        ck_assert_int_eq(ray_scene_new(&child, NULL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_sphere(child, vec(0, 0, 0), 1,
                                              RAY_NO_MATERIAL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
        ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
        ray_transform_identity(&x);
        x.m[0][3] = first;
        ck_assert_int_eq(ray_scene_add_instance(s, child, &x, NULL), RAY_OK);
        x.m[0][3] = -first;
        ck_assert_int_eq(ray_scene_add_instance(s, child, &x, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        memset(&sw, 0, sizeof sw);
        sw.shape.a = sw.shape.b = vec(0, 5, 0);
        sw.shape.radius = 1;
        sw.dir = vec(0, -1, 0);
        sw.tmax = 10;
        ck_assert_int_eq(ray_intersect_sweep(s, &sw, NULL, &c), 1);
        ck_assert_uint_eq(c.inst_id, 0);
        ck_assert_msg(fabs(c.t - (5 - sqrt(1.75))) <= 1e-12, "t %.17g", c.t);
        ck_assert_msg(c.p.x * first > 0, "order %d: contact x %g", order,
                      c.p.x);
        ray_scene_free(s);
        ray_scene_free(child);
    }
}
END_TEST

/*
** A sweep that starts overlapping a filtered sphere: the contact is at
** tmin (t = 0, depth > 0), and the filter is handed a ray whose open
** interval still holds that t (tmin stepped below it), and keeps it.
*/
START_TEST(sweep_filter_should_see_a_contact_at_tmin)
{
    ray_scene *s;
    ray_sweep sw;
    ray_contact c;
    unsigned id;
    int calls = 0;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1,
                                          RAY_NO_MATERIAL, &id), RAY_OK);
    ck_assert_int_eq(ray_scene_set_filter(s, id, keep_inside, &calls,
                                          RAY_FILTER_INTERSECT), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    memset(&sw, 0, sizeof sw);
    sw.shape.a = vec(0, 1.25, 0);
    sw.shape.b = vec(0, 2, 0);
    sw.shape.radius = 0.5;                 /* 0.25 deep at the start */
    sw.dir = vec(1, 0, 0);
    sw.tmax = 1;
    ck_assert_int_eq(ray_intersect_sweep(s, &sw, NULL, &c), 1);
    ck_assert(c.t == 0);
    ck_assert_uint_eq(c.flags & RAY_CONTACT_OVERLAP, RAY_CONTACT_OVERLAP);
    ck_assert_msg(fabs(c.depth - 0.25) <= 1e-12, "depth %.17g", c.depth);
    ck_assert_int_ge(calls, 1);
    ray_scene_free(s);
}
END_TEST

/* ------------------------------------------------------ dynamic scenes */

/* A unit quad [0, 1]^2 at height z, two triangles. */
static void quad_at(ray_vec3 v[4], double z)
{
    v[0] = vec(0, 0, z);
    v[1] = vec(1, 0, z);
    v[2] = vec(1, 1, z);
    v[3] = vec(0, 1, z);
}

static double down_t(const ray_scene *s)
{
    ray_ray r = ray_from(vec(0.25, 0.5, 5), vec(0, 0, -1));
    ray_hit h;

    ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), 1);
    return h.t;
}

/*
** Updates of a disabled mesh: written over its arrays (the positions
** alone) and copied afresh (normals added), neither touching what a
** disabled mesh has no part in; once enabled and committed, rays meet
** the updated quad (t = 5 - z, exact).
*/
START_TEST(a_disabled_mesh_should_take_updates)
{
    static const unsigned idx[6] = {0, 1, 2, 0, 2, 3};
    ray_vec3 v[4], n[4];
    ray_mesh m;
    ray_scene *s;
    unsigned id;
    int k;

    quad_at(v, 0);
    for (k = 0; k < 4; k++)
        n[k] = vec(0, 0, 1);
    memset(&m, 0, sizeof m);
    m.vertices = v;
    m.vertex_count = 4;
    m.indices = idx;
    m.triangle_count = 2;
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, &id), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert(down_t(s) == 5);
    ck_assert_int_eq(ray_scene_set_enabled(s, id, 0), RAY_OK);
    quad_at(v, 1);                                  /* rewritten */
    ck_assert_int_eq(ray_scene_update_mesh(s, id, &m), RAY_OK);
    ck_assert_int_eq(ray_scene_set_enabled(s, id, 1), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert(down_t(s) == 4);
    ck_assert_int_eq(ray_scene_set_enabled(s, id, 0), RAY_OK);
    quad_at(v, 2);
    m.normals = n;                                  /* copied afresh */
    ck_assert_int_eq(ray_scene_update_mesh(s, id, &m), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    {
        ray_ray r = ray_from(vec(0.25, 0.5, 5), vec(0, 0, -1));
        ray_hit h;
        ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), 0);
    }
    ck_assert_int_eq(ray_scene_set_enabled(s, id, 1), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert(down_t(s) == 3);
    ray_scene_free(s);
}
END_TEST

/* A shade that records the shading normal (ud: where). */
static void record_normal(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                          ray_rgb *out)
{
    (void)ctx;
    *(ray_vec3 *)ud = a->shading_normal;
    *out = rgb(1, 1, 1);
}

/*
** A mesh with vertex normals seen through an instance that turns it 90
** degrees about x (local z to world -y): the interpolated normal is
** turned with it, (0.6, 0, 0.8) to (0.6, -0.8, 0), to within 1e-12 (the
** transform's entries are exact; a normalisation's rounding), and faces
** the ray coming up +y as the geometric normal (0, -1, 0) does.
*/
START_TEST(instanced_vertex_normals_should_turn_with_the_instance)
{
    static const unsigned idx[6] = {0, 1, 2, 0, 2, 3};
    ray_vec3 v[4], n[4], got = {0, 0, 0};
    ray_material mat = {record_normal, &got, 0, NULL};
    ray_scene *child, *s;
    ray_transform x;
    ray_mesh m;
    ray_ctx *ctx;
    ray_ray r;
    ray_rgb c;
    unsigned mid;
    int k;

    quad_at(v, 0);
    for (k = 0; k < 4; k++)
        n[k] = vec(0.6, 0, 0.8);
    memset(&m, 0, sizeof m);
    m.vertices = v;
    m.vertex_count = 4;
    m.indices = idx;
    m.triangle_count = 2;
    m.normals = n;
    ck_assert_int_eq(ray_scene_new(&child, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(child, &mat, &mid), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(child, &m, mid, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    memset(&x, 0, sizeof x);
    x.m[0][0] = 1;
    x.m[1][2] = -1;
    x.m[2][1] = 1;
    ck_assert_int_eq(ray_scene_add_instance(s, child, &x, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(s, 1, &ctx), RAY_OK);
    r = ray_from(vec(0.25, -5, 0.5), vec(0, 1, 0));
    ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1.0, &c), RAY_OK);
    ck_assert(c.r == 1);
    ck_assert_vec_eq_tol(got, vec(0.6, -0.8, 0), 1e-12);
    ray_ctx_free(ctx);
    ray_scene_free(s);
    ray_scene_free(child);
}
END_TEST

/*
** Changes the parent's commit must refuse: a child that gained a plane
** after it was instanced (an instance cannot hold unbounded geometry:
** RAY_EINVAL, its message naming the instance); and a filter asked for
** no query (queries 0 with a function: RAY_EINVAL).
*/
START_TEST(a_parent_commit_should_refuse_a_child_grown_unbounded)
{
    ray_scene *child, *s;
    ray_transform x;
    unsigned id;

    ck_assert_int_eq(ray_scene_new(&child, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(child, vec(0, 0, 0), 1,
                                          RAY_NO_MATERIAL, &id), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    ck_assert_int_eq(ray_scene_set_filter(child, id, keep_inside, NULL, 0),
                     RAY_EINVAL);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ray_transform_identity(&x);
    ck_assert_int_eq(ray_scene_add_instance(s, child, &x, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(child, vec(0, -2, 0), vec(0, 1, 0),
                                         RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(5, 0, 0), 1, RAY_NO_MATERIAL,
                                          NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_EINVAL);
    ck_assert_str_eq(ray_scene_errmsg(s), "ray_scene_commit: instance 0: "
                     "its scene now has planes or instances");
    ray_scene_free(s);
    ray_scene_free(child);
}
END_TEST

/* A progress callback that records its last call and answers *cancel. */
typedef struct progress_log {
    unsigned calls, done, total;
    int cancel;
} progress_log;

static int log_progress(void *ud, unsigned done, unsigned total)
{
    progress_log *p = ud;

    p->calls++;
    p->done = done;
    p->total = total;
    return p->cancel;
}

/*
** A commit that places nothing in a tree (a plane alone: unbounded, in
** no BVH) still tells its callback the end, once: 0 of 0.  A callback
** that cancels then makes the commit fail (RAY_ECANCELED), the scene left
** uncommitted, and the next commit, not cancelled, succeeds.
*/
START_TEST(a_commit_of_nothing_to_place_should_report_0_of_0)
{
    progress_log log = {0, 99, 99, 1};
    ray_scene *s;
    ray_ray r = ray_from(vec(0, 5, 0), vec(0, -1, 0));
    ray_hit h;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 1, 0),
                                         RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_set_progress(s, log_progress, &log), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_ECANCELED);
    ck_assert_uint_eq(log.calls, 1);
    ck_assert_uint_eq(log.done, 0);
    ck_assert_uint_eq(log.total, 0);
    ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), -RAY_ESTATE);
    log.cancel = 0;
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_uint_eq(log.calls, 2);
    ck_assert_uint_eq(log.total, 0);
    ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), 1);
    ck_assert(h.t == 5);
    ray_scene_free(s);
}
END_TEST

/* A shade that asks for lights 0, 1 and 2's samples: each must be
** refused with *out untouched (ud: how many were); light 3 answers. */
static void probe_refused_lights(void *ud, ray_ctx *ctx,
                                 const ray_shade_args *a, ray_rgb *out)
{
    ray_light_sample ls, before;
    int k;

    memset(&ls, 0x5a, sizeof ls);
    before = ls;
    for (k = 0; k < 3; k++)
        if (ray_light_sample_at(ctx, a, (unsigned)k, 0, &ls) == RAY_EINVAL &&
            memcmp(&ls, &before, sizeof ls) == 0)
            ++*(int *)ud;
    ck_assert_int_eq(ray_light_sample_at(ctx, a, 3, 0, &ls), RAY_OK);
    *out = rgb(0, 0, 0);
}

/*
** Lights a shading point cannot take a sample of: a point light exactly
** at the hit (distance 0: no direction), one 1e-3 above it with an
** intensity of 1e303 (its radiance, 1e303 / 1e-6, overflows), and a
** sphere light centred on the hit (no direction to turn its disk to: the
** sample is the centre, distance 0); each refused (RAY_EINVAL, *out
** untouched), while a fourth light answers.
** The hit is (0.5, 0.5, 0) exactly: the plane z = 0 met at t = 5.
*/
START_TEST(light_samples_should_refuse_zero_distance_and_overflow)
{
    int refused = 0;
    ray_material m = {probe_refused_lights, &refused, 0, NULL};
    ray_light l;
    ray_scene *s;
    ray_ctx *ctx;
    ray_ray r = ray_from(vec(0.5, 0.5, 5), vec(0, 0, -1));
    ray_rgb c;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 0, 1), 0,
                                         NULL), RAY_OK);
    ray_light_init(&l, RAY_LIGHT_POINT);
    l.position = vec(0.5, 0.5, 0);
    l.intensity = rgb(1, 1, 1);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    l.position = vec(0.5, 0.5, 1e-3);
    l.intensity = rgb(1e303, 1, 1);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    ray_light_init(&l, RAY_LIGHT_SPHERE);     /* centred on the hit */
    l.position = vec(0.5, 0.5, 0);
    l.radius = 0.25;
    l.intensity = rgb(1, 1, 1);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    ray_light_init(&l, RAY_LIGHT_POINT);
    l.position = vec(0.5, 0.5, 2);
    l.intensity = rgb(1, 1, 1);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(s, 1, &ctx), RAY_OK);
    ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1.0, &c), RAY_OK);
    ck_assert_int_eq(refused, 3);
    ray_ctx_free(ctx);
    ray_scene_free(s);
}
END_TEST

/* ------------------------------------------------------------ photons */

/* The photon tests' floor: a material that declares RAY_EFFECT_CAUSTICS
** (photons are stored on it), as caustics_kit.h's probe. */
static void caustics_shade(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                           ray_rgb *out)
{
    (void)ud;
    ck_assert_int_eq(ray_caustics_at(ctx, a, out), RAY_OK);
}

static ray_material probe_material(void)
{
    ray_material m = {caustics_shade, NULL, RAY_EFFECT_CAUSTICS, NULL};
    return m;
}

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

/* A user scatter: the mirror direction, with the weight *ud (a bad one
** where the test asks). */
static int weighted_mirror(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                           ray_vec3 *dir, ray_rgb *w)
{
    ray_vec3 d = a->ray->dir, n = a->normal;
    double k = 2 * vdot(d, n);

    (void)ctx;
    *dir = vsub(d, vscale(n, k));
    *w = *(const ray_rgb *)ud;
    return 1;
}

static void no_shade(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                     ray_rgb *out)
{
    (void)ud; (void)ctx; (void)a;
    *out = rgb(0, 0, 0);
}

/*
** Weights a scatter callback may not hand the photon pass: a negative,
** a NaN and an infinite channel end the photon (none stored), as does a
** weight of 0 and, with pruning (the default limits: min_weight 0.01 of
** the start), one of 1e-3; weight 1 carries it to the floor (some
** stored), and the same 1e-3 with pruning off (no_pruning) does too.  A
** material-less polygon between the light and the mirror stops every
** photon before any bounce: none stored.  Counts: exact.
*/
START_TEST(photons_should_stop_at_bad_weights_and_bare_geometry)
{
    static const double bad[] = {-0.5, (double)NAN, HUGE_VAL, 0, 1e-3};
    ray_rgb w;
    ray_material m = {no_shade, &w, RAY_EFFECT_SCATTER, weighted_mirror};
    ray_limits lim;
    ray_stats st;
    size_t k;
    int ch;

    for (k = 0; k <= sizeof bad / sizeof *bad; k++)
        for (ch = 0; ch < 3; ch++) {
            ray_scene *s;
            unsigned pm, mm, um;
            double x = k < sizeof bad / sizeof *bad ? bad[k] : 1.0;

            if (k >= 3 && ch > 0)
                continue;        /* 0, 1e-3 and 1: grey, once */
            w = rgb(k >= 3 ? x : 1, k >= 3 ? x : 1, k >= 3 ? x : 1);
            if (ch == 0) w.r = x;
            if (ch == 1) w.g = x;
            if (ch == 2) w.b = x;
            s = photon_scene(rgb(1, 1, 1), &pm, &mm);
            ck_assert_int_eq(ray_scene_add_material(s, &m, &um), RAY_OK);
            add_mirror(s, 2, 1, um, NULL);
            ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
            ck_assert_int_eq(photon_build(s, 500, &st, NULL), RAY_OK);
            ck_assert_uint_eq(st.photons_emitted, 500);
            if (k < sizeof bad / sizeof *bad)
                ck_assert_msg(st.photons_stored == 0, "weight (%g %g %g): "
                              "%llu stored", w.r, w.g, w.b,
                              st.photons_stored);
            else
                ck_assert_uint_gt(st.photons_stored, 0);
            if (k == 4) {        /* 1e-3 without pruning: carried on */
                ray_limits_init(&lim);
                lim.no_pruning = 1;
                ck_assert_int_eq(ray_scene_set_limits(s, &lim), RAY_OK);
                ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
                ck_assert_int_eq(photon_build(s, 500, &st, NULL), RAY_OK);
                ck_assert_uint_gt(st.photons_stored, 0);
            }
            if (k == 5) {        /* a bare polygon shields the mirror */
                add_mirror(s, 1.5, 2, RAY_NO_MATERIAL, NULL);
                ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
                ck_assert_int_eq(photon_build(s, 500, &st, NULL), RAY_OK);
                ck_assert_uint_eq(st.photons_emitted, 500);
                ck_assert_uint_eq(st.photons_stored, 0);
            }
            ray_scene_free(s);
        }
}
END_TEST

/* ---------------------------------------------------------- primitives */

/*
** The textbook sphere formula (ray__sphere_naive, the reference of the
** numerics bench): a ray from inside takes the far root, t = 2 exactly
** for the sphere of radius 2 at the origin from its centre (the roots
** are -+sqrt(4) / 1, exact); both roots behind, or beyond tmax, miss;
** and so do a radius 0, infinite or NaN and a zero direction, with the
** hit untouched.
*/
START_TEST(naive_sphere_should_take_the_far_root_and_refuse_the_rest)
{
    ray_ray r = ray_from(vec(0, 0, 0), vec(1, 0, 0));
    ray_hit h;

    hit_poison(&h);
    ck_assert_int_eq(ray__sphere_naive(&r, vec(0, 0, 0), 2, &h), 1);
    ck_assert(h.t == 2 && h.p.x == 2 && h.p.y == 0 && h.p.z == 0);
    hit_poison(&h);
    r.tmax = 1.5;
    ck_assert_int_eq(ray__sphere_naive(&r, vec(0, 0, 0), 2, &h), 0);
    r = ray_from(vec(5, 0, 0), vec(1, 0, 0));       /* sphere behind */
    ck_assert_int_eq(ray__sphere_naive(&r, vec(0, 0, 0), 2, &h), 0);
    r = ray_from(vec(-5, 0, 0), vec(1, 0, 0));
    ck_assert_int_eq(ray__sphere_naive(&r, vec(0, 0, 0), 0, &h), 0);
    ck_assert_int_eq(ray__sphere_naive(&r, vec(0, 0, 0), HUGE_VAL, &h), 0);
    ck_assert_int_eq(ray__sphere_naive(&r, vec(0, 0, 0), (double)NAN, &h),
                     0);
    r.dir = vec(0, 0, 0);
    ck_assert_int_eq(ray__sphere_naive(&r, vec(0, 0, 0), 2, &h), 0);
    ck_assert(hit_is_poisoned(&h));
}
END_TEST

/*
** The single-precision triangle test (the float filter's reference): a
** hit at t = 1 exactly (every input a small binary fraction: the float
** products and the one division are exact); a miss past tmax, beside
** each edge (gamma > 1, beta < 0, beta + gamma > 1), and for a
** degenerate (collinear) triangle, with *t untouched.
*/
START_TEST(float_triangle_should_classify_each_side)
{
    const ray_vec3 a = {0, 0, 0}, b = {1, 0, 0}, c = {0, 1, 0};
    ray_ray r = ray_from(vec(0.25, 0.25, 1), vec(0, 0, -1));
    double t = -1;

    ck_assert_int_eq(ray__triangle_float(&r, a, b, c, &t), 1);
    ck_assert(t == 1);
    t = -1;
    r.tmax = 0.5;
    ck_assert_int_eq(ray__triangle_float(&r, a, b, c, &t), 0);
    r = ray_from(vec(0.25, 1.5, 1), vec(0, 0, -1));   /* past c: gamma */
    ck_assert_int_eq(ray__triangle_float(&r, a, b, c, &t), 0);
    r = ray_from(vec(-0.25, 0.5, 1), vec(0, 0, -1));  /* beyond ac: beta */
    ck_assert_int_eq(ray__triangle_float(&r, a, b, c, &t), 0);
    r = ray_from(vec(0.75, 0.75, 1), vec(0, 0, -1));  /* beyond bc */
    ck_assert_int_eq(ray__triangle_float(&r, a, b, c, &t), 0);
    r = ray_from(vec(0.25, -0.5, 1), vec(0, 0, -1));  /* below ab */
    ck_assert_int_eq(ray__triangle_float(&r, a, b, c, &t), 0);
    r = ray_from(vec(0.25, 0.25, 1), vec(0, 0, -1));
    ck_assert_int_eq(ray__triangle_float(&r, a, b, vec(2, 0, 0), &t), 0);
    ck_assert(t == -1);
}
END_TEST

/*
** Degenerate descriptors and rays the analytic primitives refuse with a
** miss (0, the hit untouched): a box with an infinite or zero half
** extent on each axis in turn, a plane of zero normal, a torus hit by a
** ray whose |dir| overflows (DBL_MAX on every axis: its length is
** 3.1e308); and blobs with a NULL array but a count, refused
** (RAY_EINVAL, the output untouched).
*/
START_TEST(primitives_should_miss_on_degenerate_descriptors)
{
    static const ray_blob one = {{0, 0, 0}, 1, 1};
    ray_ray r = ray_from(vec(-5, 0.1, 0.2), vec(1, 0, 0));
    ray_box_params b;
    ray_torus_params t = {{0, 0, 0}, {0, 0, 1}, 2, 0.5};
    ray_blobs_params bp = {NULL, 1, 0.5};
    ray_implicit_surface out, before;
    ray_hit h;
    int axis, bad;

    hit_poison(&h);
    for (axis = 0; axis < 3; axis++)
        for (bad = 0; bad < 3; bad++) {
            double x = bad == 0 ? HUGE_VAL : bad == 1 ? 0 : (double)NAN;
            memset(&b, 0, sizeof b);
            b.center = vec(0, 0, 0);
            b.half_extents = vec(1, 1, 1);
            b.axis_x = vec(1, 0, 0);
            b.axis_y = vec(0, 1, 0);
            ck_assert_int_eq(ray_box(&r, &b, &h), 1);   /* the good box */
            hit_poison(&h);
            if (axis == 0) b.half_extents.x = x;
            if (axis == 1) b.half_extents.y = x;
            if (axis == 2) b.half_extents.z = x;
            ck_assert_int_eq(ray_box(&r, &b, &h), 0);
            ck_assert(hit_is_poisoned(&h));
        }
    ck_assert_int_eq(ray_plane(&r, vec(0, 0, 0), vec(0, 0, 0), &h), 0);
    r.dir = vec(DBL_MAX, DBL_MAX, DBL_MAX);
    r.org = vec(-5, -5, 0.1);
    ck_assert_int_eq(ray_torus(&r, &t, &h), 0);
    ck_assert(hit_is_poisoned(&h));
    memset(&out, 0x5a, sizeof out);
    before = out;
    ck_assert_int_eq(ray_implicit_blobs(&bp, &out), RAY_EINVAL);
    ck_assert(memcmp(&out, &before, sizeof out) == 0);
    bp.blobs = &one;
    ck_assert_int_eq(ray_implicit_blobs(&bp, &out), RAY_OK);
}
END_TEST

/*
** The polygon helpers of the closest-point and sweep queries refuse a
** NULL array and fewer than 3 vertices (0, outputs untouched); the unit
** square's plane is its centroid and the unit normal of its winding.
*/
START_TEST(polygon_helpers_should_refuse_too_few_vertices)
{
    static const ray_vec3 sq[4] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0},
                                   {0, 1, 0}};
    ray_vec3 c = {7, 7, 7}, n = {7, 7, 7}, p = {7, 7, 7};

    ck_assert_int_eq(ray__polygon_plane_mapped(NULL, 4, NULL, &c, &n), 0);
    ck_assert_int_eq(ray__polygon_plane_mapped(sq, 2, NULL, &c, &n), 0);
    ck_assert_int_eq(ray__polygon_closest_mapped(NULL, 4, NULL, vec(0, 0, 1),
                                                 &p, &n), 0);
    ck_assert_int_eq(ray__polygon_closest_mapped(sq, 2, NULL, vec(0, 0, 1),
                                                 &p, &n), 0);
    ck_assert(p.x == 7 && p.y == 7 && p.z == 7);
    ck_assert_int_eq(ray__polygon_plane_mapped(sq, 4, NULL, &c, &n), 1);
    ck_assert(c.x == 0.5 && c.y == 0.5 && c.z == 0);     /* exact */
    ck_assert(n.x == 0 && n.y == 0 && n.z == 1);
}
END_TEST

/*
** The polynomial root finder's edges: a degree outside 1 .. 4 has no
** roots; a linear root outside [lo, hi] is left out on either side; a
** root at lo itself is found (x^2 - x on [0, 2]: 0 and 1, exactly: every
** value involved is an integer); and (x - 0.7)^2, whose coefficients
** 0.49, -1.4 are rounded so that its minimum at 0.7 is 5.6e-17 above
** zero, within the evaluation's rounding bound, gives its double root
** once, within 1e-9 of 0.7 (the minimum's abscissa, -c1 / 2 c2, is
** found to a few ulps).
*/
START_TEST(poly_roots_should_handle_the_ends_and_touching_minima)
{
    static const double lin[2] = {-3, 1};          /* x - 3 */
    static const double sq[3] = {0, -1, 1};        /* x^2 - x */
    static const double dbl[3] = {0.49, -1.4, 1};  /* (x - 0.7)^2 */
    double roots[RAY__POLY_MAX_DEGREE + 1];
    int n;

    ck_assert_int_eq(ray__poly_roots(lin, 0, 0, 10, roots), 0);
    ck_assert_int_eq(ray__poly_roots(lin, RAY__POLY_MAX_DEGREE + 1, 0, 10,
                                     roots), 0);
    ck_assert_int_eq(ray__poly_roots(lin, 1, 0, 10, roots), 1);
    ck_assert(roots[0] == 3);
    ck_assert_int_eq(ray__poly_roots(lin, 1, 4, 10, roots), 0);
    ck_assert_int_eq(ray__poly_roots(lin, 1, 0, 2, roots), 0);
    n = ray__poly_roots(sq, 2, 0, 2, roots);
    ck_assert_int_eq(n, 2);
    ck_assert(roots[0] == 0 && roots[1] == 1);
    n = ray__poly_roots(dbl, 2, -1, 1, roots);
    ck_assert_int_eq(n, 1);
    ck_assert_msg(fabs(roots[0] - 0.7) <= 1e-9, "root %.17g", roots[0]);
}
END_TEST

/*
** The textbook barycentric normalisation (ray__barycentric_naive, kept
** for the stability bench) refuses a degenerate triangle and one whose
** N.N overflows; ray_barycentric says a point beyond each edge is
** outside, with the coordinates (exact for these small integers and
** halves) summing to 1.
*/
START_TEST(barycentrics_should_refuse_degenerate_and_place_each_side)
{
    static const ray_vec3 a = {0, 0, 0}, b = {1, 0, 0}, c = {0, 1, 0};
    static const ray_vec3 outside[3] = {{1, 1, 0}, {-0.5, 0.5, 0},
                                        {0.5, -0.5, 0}};
    double abg[3] = {7, 7, 7};
    int inside, k;

    ck_assert_int_eq(ray__barycentric_naive(vec(0.25, 0.25, 0), a, b,
                                            vec(2, 0, 0), abg),
                     RAY_EDEGENERATE);
    ck_assert_int_eq(ray__barycentric_naive(vec(0, 0, 0), a,
                                            vec(1e200, 0, 0),
                                            vec(0, 1e200, 0), abg),
                     RAY_EDEGENERATE);
    ck_assert(abg[0] == 7 && abg[1] == 7 && abg[2] == 7);
    for (k = 0; k < 3; k++) {
        inside = -1;
        ck_assert_int_eq(ray_barycentric(outside[k], a, b, c, abg, &inside),
                         RAY_OK);
        ck_assert_int_eq(inside, 0);
        ck_assert(abg[0] + abg[1] + abg[2] == 1);
        ck_assert(abg[k] < 0);
    }
}
END_TEST


/*
** A polygon whose vertices are collinear has no area in any coordinate
** plane (the vector area is exactly 0: small integers): its plane is
** refused (0, the normal set to zero) and rays miss it, the hit left
** untouched; one vertex moved off the line gives it a plane again.
*/
START_TEST(a_collinear_polygon_should_have_no_plane)
{
    ray_vec3 v[4] = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}};
    ray_vec3 c, n = {7, 7, 7};
    ray_ray r = ray_from(vec(1, 1, 5), vec(0, 0, -1));
    ray_hit h;

    ck_assert_int_eq(ray__polygon_plane(v, 4, &c, &n), 0);
    ck_assert(n.x == 0 && n.y == 0 && n.z == 0);
    hit_poison(&h);
    ck_assert_int_eq(ray_polygon(&r, v, 4, &h), 0);
    ck_assert(hit_is_poisoned(&h));
    v[3] = vec(3, 0, 3);
    ck_assert_int_eq(ray__polygon_plane(v, 4, &c, &n), 1);
    ck_assert(n.x != 0 || n.y != 0 || n.z != 0);
}
END_TEST

/*
** Metaballs whose strengths are all negative have no surface (the field
** stays above the threshold): built (RAY_OK) with the box of them all,
** and a ray through them misses.  With a positive blob among them the
** box is the positive blobs' alone (the surface lies in their spheres):
** the negative one's, far off, is left out -- exactly, the box being
** centre -+ radius.
*/
START_TEST(blobs_should_box_only_their_positive_spheres)
{
    ray_blob b[2] = {{{0, 0, 0}, 1, -1}, {{10, 0, 0}, 2, -0.5}};
    ray_blobs_params bp = {b, 2, 0.5};
    ray_implicit_surface is;
    ray_ray r = ray_from(vec(-5, 0, 0), vec(1, 0, 0));
    ray_hit h;

    ck_assert_int_eq(ray_implicit_blobs(&bp, &is), RAY_OK);
    ck_assert(is.lo.x == -1 && is.hi.x == 12);
    hit_poison(&h);
    ck_assert_int_eq(ray_implicit(&r, &is, &h), 0);
    ck_assert(hit_is_poisoned(&h));
    b[0].strength = 1;
    ck_assert_int_eq(ray_implicit_blobs(&bp, &is), RAY_OK);
    ck_assert(is.lo.x == -1 && is.lo.y == -1 && is.lo.z == -1);
    ck_assert(is.hi.x == 1 && is.hi.y == 1 && is.hi.z == 1);
    ck_assert_int_eq(ray_implicit(&r, &is, &h), 1);
    ck_assert(h.t > 4 && h.t < 5);         /* inside the unit sphere */
}
END_TEST

/* ------------------------------------------------ parametric surfaces */

static void flat_eval(void *ud, double u, double v, ray_vec3 *p,
                      ray_vec3 *pu, ray_vec3 *pv)
{
    (void)ud;
    *p = vec(u, v, 0);
    *pu = vec(1, 0, 0);
    *pv = vec(0, 1, 0);
}

static void flat_bounds(void *ud, double u0, double u1, double v0, double v1,
                        ray_vec3 *lo, ray_vec3 *hi)
{
    (void)ud;
    *lo = vec(u0, v0, 0);
    *hi = vec(u1, v1, 0);
}

/* The Bezier patch's own eval, called through another function: the
** same surface, not recognised as ray_bezier_surface's. */
static ray_surface_fn bezier_eval_of_patch;

static void bezier_again(void *ud, double u, double v, ray_vec3 *p,
                         ray_vec3 *pu, ray_vec3 *pv)
{
    bezier_eval_of_patch(ud, u, v, p, pu, pv);
}

/*
** Domains: all four bounds 0 is the unit square (the default), but a
** domain with only u0 = u1 = 0 set is empty (refused, -RAY_EINVAL).  The
** flat Bezier patch of control points (i mod 4, i div 4, 0) is the
** square [0, 3]^2 with x = 3u, y = 3v; restricted to a part of its
** domain (each bound moved in turn) it is searched as a general surface
** and hit only over that part; with its eval wrapped it is not taken for
** a Bezier patch, and still hit.  Every hit straight down from z = 5 at
** t = 5 within 1e-9 (the surface's default tolerance on a box 3 wide:
** about 3e-9 / 3, and the plane is exact), every miss beside the part.
*/
START_TEST(parametric_domains_should_bound_the_search)
{
    static const double dom[4][4] = {{0.5, 1, 0, 1}, {0, 0.5, 0, 1},
                                     {0, 1, 0.5, 1}, {0, 1, 0, 0.5}};
    ray_parametric_surface ps, bz, wrapped;
    ray_vec3 cp[16];
    ray_hit h;
    ray_ray r;
    int i, k;

    memset(&ps, 0, sizeof ps);
    ps.eval = flat_eval;
    ps.bounds = flat_bounds;
    r = ray_from(vec(0.5, 0.5, 5), vec(0, 0, -1));
    ck_assert_int_eq(ray_parametric(&r, &ps, &h), 1);
    ps.v1 = 1;                              /* u0 = u1 = v0 = 0: empty */
    ck_assert_int_eq(ray_parametric(&r, &ps, &h), -RAY_EINVAL);
    ps.v0 = 0.25;
    ck_assert_int_eq(ray_parametric(&r, &ps, &h), -RAY_EINVAL);

    for (i = 0; i < 16; i++)
        cp[i] = vec(i % 4, i / 4, 0);
    ck_assert_int_eq(ray_bezier_surface(cp, &bz), RAY_OK);
    for (k = 0; k < 4; k++) {
        double u_in = 0.5 * (dom[k][0] + dom[k][1]);
        double v_in = 0.5 * (dom[k][2] + dom[k][3]);
        double u_out = dom[k][0] > 0 ? 0.25 : dom[k][1] < 1 ? 0.75 : u_in;
        double v_out = dom[k][2] > 0 ? 0.25 : dom[k][3] < 1 ? 0.75 : v_in;
        ps = bz;
        ps.u0 = dom[k][0];
        ps.u1 = dom[k][1];
        ps.v0 = dom[k][2];
        ps.v1 = dom[k][3];
        r = ray_from(vec(3 * u_in, 3 * v_in, 5), vec(0, 0, -1));
        hit_poison(&h);
        ck_assert_int_eq(ray_parametric(&r, &ps, &h), 1);
        ck_assert_msg(fabs(h.t - 5) <= 1e-9, "domain %d: t %.17g", k, h.t);
        r = ray_from(vec(3 * u_out, 3 * v_out, 5), vec(0, 0, -1));
        ck_assert_int_eq(ray_parametric(&r, &ps, &h), 0);
    }
    bezier_eval_of_patch = bz.eval;
    wrapped = bz;
    wrapped.eval = bezier_again;
    r = ray_from(vec(1.5, 1.5, 5), vec(0, 0, -1));
    hit_poison(&h);
    ck_assert_int_eq(ray_parametric(&r, &wrapped, &h), 1);
    ck_assert_msg(fabs(h.t - 5) <= 1e-9, "wrapped: t %.17g", h.t);
    ck_assert_msg(fabs(h.p.x - 1.5) <= 1e-9 && fabs(h.p.y - 1.5) <= 1e-9,
                  "wrapped: p (%g, %g)", h.p.x, h.p.y);
}
END_TEST

/* ------------------------------------------------------------ materials */

/* Shading arguments at the origin of the plane z = 0, hit by a ray coming
** down at 45 degrees in x (direction (1, 0, -1)), texture coordinates
** (u, v). */
typedef struct flat_args {
    ray_ray r;
    ray_hit h;
    ray_shade_args a;
} flat_args;

static void flat_args_at(flat_args *f, double u, double v)
{
    memset(f, 0, sizeof *f);
    f->r = ray_from(vec(-1, 0, 1), vec(1, 0, -1));
    f->h.t = 1;
    f->h.p = vec(0, 0, 0);
    f->h.n = vec(0, 0, 1);
    f->h.u = u;
    f->h.v = v;
    f->a.ray = &f->r;
    f->a.hit = &f->h;
    f->a.normal = vec(0, 0, 1);
    f->a.shading_normal = f->a.normal;
    f->a.entering = 1;
    f->a.u = u;
    f->a.v = v;
    f->a.weight = 1;
    f->a.prune = 1;
}

/* A shade that writes a colour, to tell whether a checker called it. */
static void paint(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                  ray_rgb *out)
{
    (void)ctx; (void)a;
    *out = *(const ray_rgb *)ud;
}

/*
** The built-in materials' scatter callbacks, called as the photon pass
** calls them.  A mirror of reflectance k sends the photon on along the
** mirror direction (1, 0, 1) with weight k exactly; a black mirror and
** any of them with NULL parameters (mirror, Phong, glass, checker: the
** material made from NULL) end it (0).  A checker scatters as the
** square's material does: the odd square (floor(u) + floor(v) odd) a
** mirror, the even one a Phong without reflection (no scatter), a
** material that declares RAY_EFFECT_SCATTER without a function, and one
** whose scatter refuses; and shades as the square does, or leaves *out
** alone for a square without a shade function.
*/
START_TEST(material_scatter_should_follow_its_parameters)
{
    static const ray_rgb k = {0.25, 0.5, 0.75}, black = {0, 0, 0};
    ray_phong_params pp;
    ray_glass_params gp = {1.5, {0, 0, 0}};
    ray_checker_params cp;
    ray_material mirror = ray_material_mirror(&k), dark, phong, glass,
                 checker, with_reflect;
    ray_rgb w = {-1, -1, -1}, out;
    ray_vec3 dir = {0, 0, 0};
    flat_args f;

    flat_args_at(&f, 0.5, 0.5);
    ck_assert_int_eq(mirror.scatter(mirror.ud, NULL, &f.a, &dir, &w), 1);
    ck_assert(dir.x == 1 && dir.y == 0 && dir.z == 1); /* exact: +-1, 0 */
    ck_assert(w.r == k.r && w.g == k.g && w.b == k.b);
    dark = ray_material_mirror(&black);
    ck_assert_int_eq(dark.scatter(dark.ud, NULL, &f.a, &dir, &w), 0);
    ck_assert_int_eq(mirror.scatter(NULL, NULL, &f.a, &dir, &w), 0);
    ray_phong_params_init(&pp);
    pp.reflect = k;
    with_reflect = ray_material_phong(&pp);
    ck_assert(with_reflect.scatter != NULL);
    ck_assert_int_eq(with_reflect.scatter(NULL, NULL, &f.a, &dir, &w), 0);
    glass = ray_material_glass(&gp);
    ck_assert_int_eq(glass.scatter(NULL, NULL, &f.a, &dir, &w), 0);

    ray_phong_params_init(&pp);
    phong = ray_material_phong(&pp);               /* no reflection */
    ck_assert(phong.scatter == NULL);
    memset(&cp, 0, sizeof cp);
    cp.odd = mirror;
    cp.even = phong;
    checker = ray_material_checker(&cp);
    ck_assert(checker.scatter != NULL);
    ck_assert_int_eq(checker.scatter(NULL, NULL, &f.a, &dir, &w), 0);
    flat_args_at(&f, 1.5, 0.5);                    /* odd: the mirror */
    w = rgb(-1, -1, -1);
    ck_assert_int_eq(checker.scatter(checker.ud, NULL, &f.a, &dir, &w), 1);
    ck_assert(w.r == k.r && w.g == k.g && w.b == k.b);
    flat_args_at(&f, 0.5, 0.5);                    /* even: Phong */
    ck_assert_int_eq(checker.scatter(checker.ud, NULL, &f.a, &dir, &w), 0);
    cp.even.effects |= RAY_EFFECT_SCATTER;         /* declared, no function */
    ck_assert_int_eq(checker.scatter(checker.ud, NULL, &f.a, &dir, &w), 0);
    cp.even = dark;                                /* a scatter that says 0 */
    ck_assert_int_eq(checker.scatter(checker.ud, NULL, &f.a, &dir, &w), 0);

    /* Shading: the even square paints, the odd one has no shade. */
    cp.even.shade = paint;
    cp.even.ud = ray__test_unconst(&k);
    cp.odd.shade = NULL;
    out = rgb(9, 9, 9);
    checker.shade(checker.ud, NULL, &f.a, &out);
    ck_assert(out.r == k.r && out.g == k.g && out.b == k.b);
    flat_args_at(&f, 1.5, 0.5);
    out = rgb(9, 9, 9);
    checker.shade(checker.ud, NULL, &f.a, &out);
    ck_assert(out.r == 9 && out.g == 9 && out.b == 9);
    checker.shade(NULL, NULL, &f.a, &out);
    ck_assert(out.r == 9 && out.g == 9 && out.b == 9);
}
END_TEST

/* ------------------------------------------------------------- render */

/*
** Adaptive sampling through a lens (aperture > 0): the corners' samples
** go through the lens too.  A sphere shaded a constant colour c in front
** of a background b: every pixel is a mean of samples that are each c or
** b, so each channel lies between them (exactly: a mean of copies of one
** float is that float, and of two values it lies between them; 1e-6
** covers the float rounding of a mixed mean); the corner pixel sees
** only the background and the centre only the sphere, exactly.
*/
START_TEST(adaptive_render_through_a_lens_should_mix_only_what_it_sees)
{
    enum { RW = 9, RH = 9 };
    static const ray_rgb c = {0.25, 0.5, 0.75}, b = {1, 0.125, 0};
    ray_material m = {paint, NULL, 0, NULL};
    float img[3 * RW * RH];
    ray_render_options o;
    ray_camera cam;
    ray_scene *s;
    int i;

    m.ud = ray__test_unconst(&c);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1, 0, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_set_background(s, b, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    memset(&cam, 0, sizeof cam);
    cam.position = vec(0, 0, 4);
    cam.up = vec(0, 1, 0);
    cam.vfov = 40;
    cam.aperture = 0.05;
    o = (ray_render_options){.width = RW, .height = RH};
    o.adaptive_threshold = 0.05;
    o.adaptive_depth = 2;
    o.threads = 1;
    ck_assert_int_eq(ray_render(s, &cam, &o, img, NULL), RAY_OK);
    for (i = 0; i < RW * RH; i++) {
        const double lo[3] = {c.r < b.r ? c.r : b.r, c.g < b.g ? c.g : b.g,
                              c.b < b.b ? c.b : b.b};
        const double hi[3] = {c.r > b.r ? c.r : b.r, c.g > b.g ? c.g : b.g,
                              c.b > b.b ? c.b : b.b};
        int k;
        for (k = 0; k < 3; k++)
            ck_assert_msg((double)img[3 * i + k] >= lo[k] - 1e-6 &&
                          (double)img[3 * i + k] <= hi[k] + 1e-6,
                          "pixel %d channel %d: %g", i, k,
                          (double)img[3 * i + k]);
    }
    ck_assert(img[0] == (float)b.r && img[1] == (float)b.g &&
              img[2] == (float)b.b);
    i = 3 * (RH / 2 * RW + RW / 2);
    ck_assert(img[i] == (float)c.r && img[i + 1] == (float)c.g &&
              img[i + 2] == (float)c.b);
    ray_scene_free(s);
}
END_TEST

/*
** A scheduler that does not say how many tasks it runs at once (threads
** 0), with the options' threads 0 too: the render is cut into tasks for
** the CPUs online, handed to the scheduler (its log counts the run), and
** the image is the same bytes as the one-thread render's (ray_render:
** the same at any thread count and task order).
*/
START_TEST(a_scheduler_of_unsaid_width_should_render_the_same_bytes)
{
    enum { RW = 8, RH = 6 };
    static const ray_rgb c = {0.25, 0.5, 0.75}, b = {1, 0.125, 0};
    ray_material m = {paint, NULL, 0, NULL};
    float one[3 * RW * RH], many[3 * RW * RH];
    ray_render_options o;
    ray_scheduler sched;
    sched_log log;
    ray_camera cam;
    ray_scene *s;

    m.ud = ray__test_unconst(&c);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1, 0, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_set_background(s, b, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    memset(&cam, 0, sizeof cam);
    cam.position = vec(0, 0, 4);
    cam.up = vec(0, 1, 0);
    cam.vfov = 40;
    o = (ray_render_options){.width = RW, .height = RH};
    o.samples = 4;
    o.threads = 1;
    ck_assert_int_eq(ray_render(s, &cam, &o, one, NULL), RAY_OK);
    sched = test_scheduler(reverse_run, &log);
    ck_assert_uint_eq(sched.threads, 0);
    o.threads = 0;
    o.scheduler = &sched;
    ck_assert_int_eq(ray_render(s, &cam, &o, many, NULL), RAY_OK);
    ck_assert_uint_ge(log.runs, 1);
    ck_assert(memcmp(one, many, sizeof one) == 0);
    ray_scene_free(s);
}
END_TEST

/* ----------------------------------------------------- implicit surfaces */

/* The sphere of radius 1 at the origin as a signed distance (1-Lipschitz);
** ud, when set, counts the calls. */
static double unit_sdf(void *ud, ray_vec3 p)
{
    if (ud != NULL)
        ++*(int *)ud;
    return sqrt(p.x * p.x + p.y * p.y + p.z * p.z) - 1;
}

/* The same, NaN wherever x < -0.9: the ray from -x meets NaN first. */
static double nan_outside(void *ud, ray_vec3 p)
{
    (void)ud;
    return p.x < -0.9 ? (double)NAN : unit_sdf(NULL, p);
}

static ray_vec3 unit_grad(void *ud, ray_vec3 p)
{
    double l = sqrt(p.x * p.x + p.y * p.y + p.z * p.z);

    (void)ud;
    return vec(p.x / l, p.y / l, p.z / l);
}

static void nan_u(void *ud, ray_vec3 p, ray_vec3 n, double *u, double *v)
{
    (void)ud; (void)p; (void)n;
    *u = (double)NAN;
    *v = 0.5;
}

static void nan_v(void *ud, ray_vec3 p, ray_vec3 n, double *u, double *v)
{
    (void)ud; (void)p; (void)n;
    *u = 0.5;
    *v = -HUGE_VAL;
}

static ray_implicit_surface unit_implicit(void)
{
    ray_implicit_surface s;

    memset(&s, 0, sizeof s);
    s.f = unit_sdf;
    s.lo = vec(-1, -1, -1);
    s.hi = vec(1, 1, 1);
    s.lipschitz = 1;
    return s;
}

/*
** Rays and surfaces that ray_implicit must turn away without a hit: an
** origin that is not finite (a miss, 0), a point box at the origin with
** the default tolerance (0 there: nothing to find, 0), texture
** coordinates that are not finite and a field that is NaN where the ray
** enters (misuse, -RAY_EINVAL); the hit is left untouched every time.
*/
START_TEST(implicit_should_refuse_what_it_cannot_answer)
{
    ray_implicit_surface s = unit_implicit();
    ray_ray r = ray_from(vec(-3, 0, 0), vec(1, 0, 0));
    ray_hit h;

    hit_poison(&h);
    r.org.y = (double)NAN;
    ck_assert_int_eq(ray_implicit(&r, &s, &h), 0);
    r.org.y = HUGE_VAL;
    ck_assert_int_eq(ray_implicit(&r, &s, &h), 0);
    r = ray_from(vec(-3, 0, 0), vec(1, 0, 0));
    s.lo = s.hi = vec(0, 0, 0);
    ck_assert_int_eq(ray_implicit(&r, &s, &h), 0);
    s = unit_implicit();
    s.uv = nan_u;
    ck_assert_int_eq(ray_implicit(&r, &s, &h), -RAY_EINVAL);
    s.uv = nan_v;
    ck_assert_int_eq(ray_implicit(&r, &s, &h), -RAY_EINVAL);
    s = unit_implicit();
    s.f = nan_outside;
    ck_assert_int_eq(ray_implicit(&r, &s, &h), -RAY_EINVAL);
    s.lipschitz = 0;                     /* the fixed-step march too */
    ck_assert_int_eq(ray_implicit(&r, &s, &h), -RAY_EINVAL);
    ck_assert(hit_is_poisoned(&h));
}
END_TEST

/*
** Every budget of evaluations from 1 to 40, both marches (sphere
** tracing with the bound, fixed steps without), on a ray that meets the
** unit sphere at t = 2 and on one that grazes it (y = 1 - 1e-6): each
** answer is either -RAY_ELIMIT with the hit untouched, or a hit whose t
** lies within the tolerance (the default, 1e-9 of the box's diagonal
** plus rounding: 1e-8 is above it) of the exact entry, and f called
** no more often than the budget (the gradient is given, so no central
** differences add calls); the default budget finds it.
*/
START_TEST(implicit_should_keep_to_any_budget)
{
    static const double ys[2] = {0, 1 - 1e-6};
    int yi, lip, n;

    for (yi = 0; yi < 2; yi++)
        for (lip = 0; lip < 2; lip++) {
            double y = ys[yi], want = 3 - sqrt(1 - y * y);
            for (n = 1; n <= 41; n++) {     /* 41: the default budget */
                ray_implicit_surface s = unit_implicit();
                ray_ray r = ray_from(vec(-3, y, 0), vec(1, 0, 0));
                int calls = 0, rc;
                ray_hit h;

                s.ud = &calls;
                s.lipschitz = lip;
                s.step = lip ? 0 : 0.125;
                s.max_iterations = n <= 40 ? (unsigned)n : 0;
                s.gradient = unit_grad;  /* f's calls: the budget's only */
                hit_poison(&h);
                rc = ray_implicit(&r, &s, &h);
                ck_assert(n > 40 || calls <= n);
                if (rc == -RAY_ELIMIT && n <= 40) {
                    ck_assert(hit_is_poisoned(&h));
                    continue;
                }
                ck_assert_msg(rc == 1, "y %g lip %d budget %d: %d", y, lip,
                              n, rc);
                ck_assert_msg(fabs(h.t - want) <= 1e-8,
                              "y %g lip %d budget %d: t %.17g want %.17g",
                              y, lip, n, h.t, want);
            }
        }
}
END_TEST

/*
** A tolerance far below the spacing of the doubles near the root (1e-300
** at t = 2, where an ulp is 4.4e-16): the bracket is halved until no
** double lies strictly inside it, and the hit is at one of its ends,
** within an ulp or two of the exact t = 2 (1e-15).
*/
START_TEST(implicit_should_stop_refining_at_adjacent_doubles)
{
    ray_implicit_surface s = unit_implicit();
    ray_ray r = ray_from(vec(-3, 0, 0), vec(1, 0, 0));
    ray_hit h;
    int lip;

    for (lip = 0; lip < 2; lip++) {
        s.tolerance = 1e-300;
        s.lipschitz = lip;
        s.step = 0.1;
        s.max_iterations = 100000;
        hit_poison(&h);
        ck_assert_int_eq(ray_implicit(&r, &s, &h), 1);
        ck_assert_msg(fabs(h.t - 2) <= 1e-15, "lip %d: t %.17g", lip, h.t);
        ck_assert_msg(fabs(h.n.x + 1) <= 1e-12, "n.x %.17g", h.n.x);
    }
}
END_TEST

static ray_vec3 zero_grad(void *ud, ray_vec3 p)
{
    (void)ud; (void)p;
    return vec(0, 0, 0);
}

/* The unit sphere's distance, NaN off the plane y = 1 - 1e-6 where the
** grazing ray of the test below runs (its points have that y exactly). */
static double nan_off_the_ray(void *ud, ray_vec3 p)
{
    (void)ud;
    return p.y == 1 - 1e-6 ? unit_sdf(NULL, p) : (double)NAN;
}

/* The plane y = 1 as a field, and its gradient. */
static double plane_y1(void *ud, ray_vec3 p)
{
    (void)ud;
    return p.y - 1;
}

static ray_vec3 plane_y1_grad(void *ud, ray_vec3 p)
{
    (void)ud; (void)p;
    return vec(0, 1, 0);
}

/*
** The tangency test of the bounded march (a ray grazing the surface:
** where the step falls to the tolerance, the gradient step toward the
** surface is probed).  A gradient callback that answers 0 gives no
** probe and no normal at the hit: -RAY_EINVAL (ray.h: a zero gradient at
** the hit).  A field that is NaN at the probed point (off the ray) is
** misuse too: -RAY_EINVAL.  Both leave the hit untouched.  A ray parallel
** to the plane y = 1, 1e-9 below it, inside a tolerance of 1e-6: the
** probe lands on the plane (f = 0 there, exactly: 1 - 1e-9 + 1e-9 rounds
** to 1), no crossing lies ahead (the slope along the ray is 0), and the
** touch is the hit: t within the box's span, the point within the
** tolerance of the plane.
*/
START_TEST(implicit_tangency_probe_should_refuse_bad_callbacks)
{
    ray_implicit_surface s = unit_implicit();
    ray_ray r = ray_from(vec(-3, 1 - 1e-6, 0), vec(1, 0, 0));
    ray_hit h;

    s.gradient = zero_grad;
    hit_poison(&h);
    ck_assert_int_eq(ray_implicit(&r, &s, &h), -RAY_EINVAL);
    s = unit_implicit();
    s.f = nan_off_the_ray;
    s.gradient = unit_grad;
    ck_assert_int_eq(ray_implicit(&r, &s, &h), -RAY_EINVAL);
    ck_assert(hit_is_poisoned(&h));

    memset(&s, 0, sizeof s);
    s.f = plane_y1;
    s.gradient = plane_y1_grad;
    s.lo = vec(-1, 0, -1);
    s.hi = vec(1, 2, 1);
    s.lipschitz = 1;
    s.tolerance = 1e-6;
    r = ray_from(vec(-3, 1 - 1e-9, 0), vec(1, 0, 0));
    ck_assert_int_eq(ray_implicit(&r, &s, &h), 1);
    ck_assert_msg(h.t >= 2 - 1e-6 && h.t <= 4 + 1e-6, "t %.17g", h.t);
    ck_assert_msg(fabs(h.p.y - 1) <= 1e-6, "p.y %.17g", h.p.y);
    ck_assert(h.n.x == 0 && h.n.y == 1 && h.n.z == 0);   /* exact */
}
END_TEST

/* ----------------------------------------------------------------- files */

#if RAY_TEST_PNG && !defined(_WIN32)
/*
** ray_write_png writes a temporary file beside the target and renames it
** over: "<path>.<pid>-<attempt>.tmp", created exclusively.  One left
** where the first attempt would go (another writer's, or a crash's) is
** not touched: the next name is taken, the PNG written (read back: 2 x 2
** pixels of 0.25, 0.5, 1 within 8-bit sRGB's quantisation, 1/255 at most
** after the curve, so 0.01) and the stale file keeps its bytes.
*/
START_TEST(png_write_should_step_past_a_stale_temporary_file)
{
    static const float px[12] = {0.25f, 0.5f, 1, 0.25f, 0.5f, 1,
                                 0.25f, 0.5f, 1, 0.25f, 0.5f, 1};
    char dir[256], path[300], stale[340], got[8] = {0};
    ray_image *img = NULL;
    ray_rgb c;
    unsigned w, h;
    FILE *f;

    ck_assert(test_make_dir(dir, sizeof dir, "edges"));
    snprintf(path, sizeof path, "%s/out.png", dir);
    snprintf(stale, sizeof stale, "%s.%ld-0.tmp", path, (long)getpid());
    f = fopen(stale, "wb");
    ck_assert_ptr_nonnull(f);
    fputs("keep", f);
    fclose(f);
    ck_assert_int_eq(ray_write_png(path, px, 2, 2, 8), RAY_OK);
    f = fopen(stale, "rb");
    ck_assert_ptr_nonnull(f);
    ck_assert_uint_eq(fread(got, 1, sizeof got, f), 4);
    fclose(f);
    ck_assert_str_eq(got, "keep");
    ck_assert_int_eq(ray_image_load_png(path, NULL, &img), RAY_OK);
    ray_image_size(img, &w, &h);
    ck_assert_uint_eq(w, 2);
    ck_assert_uint_eq(h, 2);
    ck_assert_int_eq(ray_image_sample(img, 0.5, 0.5, 0, &c), RAY_OK);
    ck_assert_msg(fabs(c.r - 0.25) <= 0.01 && fabs(c.g - 0.5) <= 0.01 &&
                  fabs(c.b - 1) <= 0.01, "(%g, %g, %g)", c.r, c.g, c.b);
    ray_image_free(img);
    ck_assert_int_eq(remove(stale), 0);
    ck_assert_int_eq(remove(path), 0);
    ck_assert_int_eq(rmdir(dir), 0);
}
END_TEST
#endif

Suite *edges_suite(void)
{
    Suite *s = suite_create("edges");
    TCase *tc = tcase_create("core");

    tcase_add_test(tc, hidden_geometry_should_not_contain_or_attract);
    tcase_add_test(tc, hidden_geometry_should_not_be_touched);
    tcase_add_test(tc, a_box_should_contain_within_each_half_extent);
    tcase_add_test(tc, a_closed_mesh_without_volume_should_hold_only_its_segments);
    tcase_add_test(tc, overlaps_should_see_stretched_spheres_and_boxes_of_the_rest);
    tcase_add_test(tc, intersect_all_should_break_ties_by_ids_when_full);
    tcase_add_test(tc, float_mode_should_miss_beside_beyond_and_along);
    tcase_add_test(tc, sweep_ties_should_go_to_the_lower_instance);
    tcase_add_test(tc, sweep_filter_should_see_a_contact_at_tmin);
    tcase_add_test(tc, a_disabled_mesh_should_take_updates);
    tcase_add_test(tc, instanced_vertex_normals_should_turn_with_the_instance);
    tcase_add_test(tc, a_parent_commit_should_refuse_a_child_grown_unbounded);
    tcase_add_test(tc, a_commit_of_nothing_to_place_should_report_0_of_0);
    tcase_add_test(tc, light_samples_should_refuse_zero_distance_and_overflow);
    tcase_add_test(tc, photons_should_aim_only_at_live_scattering_geometry);
    tcase_add_test(tc, photons_should_handle_dark_and_overflowing_lights);
    tcase_add_test(tc, photons_should_survive_targets_too_small_or_too_large);
    tcase_add_test(tc, photons_should_stop_at_bad_weights_and_bare_geometry);
    tcase_add_test(tc, naive_sphere_should_take_the_far_root_and_refuse_the_rest);
    tcase_add_test(tc, float_triangle_should_classify_each_side);
    tcase_add_test(tc, primitives_should_miss_on_degenerate_descriptors);
    tcase_add_test(tc, polygon_helpers_should_refuse_too_few_vertices);
    tcase_add_test(tc, poly_roots_should_handle_the_ends_and_touching_minima);
    tcase_add_test(tc, barycentrics_should_refuse_degenerate_and_place_each_side);
    tcase_add_test(tc, implicit_tangency_probe_should_refuse_bad_callbacks);
    tcase_add_test(tc, a_collinear_polygon_should_have_no_plane);
    tcase_add_test(tc, blobs_should_box_only_their_positive_spheres);
    tcase_add_test(tc, parametric_domains_should_bound_the_search);
    tcase_add_test(tc, material_scatter_should_follow_its_parameters);
    tcase_add_test(tc, adaptive_render_through_a_lens_should_mix_only_what_it_sees);
    tcase_add_test(tc, a_scheduler_of_unsaid_width_should_render_the_same_bytes);
    tcase_add_test(tc, implicit_should_refuse_what_it_cannot_answer);
    tcase_add_test(tc, implicit_should_keep_to_any_budget);
    tcase_add_test(tc, implicit_should_stop_refining_at_adjacent_doubles);
#if RAY_TEST_PNG && !defined(_WIN32)
    tcase_add_test(tc, png_write_should_step_past_a_stale_temporary_file);
#endif
    suite_add_tcase(s, tc);
    return s;
}
