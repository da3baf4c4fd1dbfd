/* SPDX-License-Identifier: MIT */
/*
** check_closest.c -- ray_closest_point: the nearest surface point of a
** committed scene, against brute force over every primitive computed in
** long double by the test's own routines (not the library's), for
** thousands of random query points near and far, with the scene at the
** origin and moved to 1e5; radius pruning, radius +Inf, points on the
** surface, at vertices, on edges, inside closed meshes and far beyond;
** the skipped kinds; empty scenes and misuse.
*/
#include <string.h>
#include <pthread.h>
#include <stdlib.h>

#include "tests.h"
#include "hardcases.h"

#include "ldgeom.h"

/* --------------------------------------------------------------- scene */

/*
** The mixed scene, moved by "o": every kind ray_closest_point searches,
** and one it skips.  Its coordinates lie within 10 of o.
**   0  an icosphere mesh of radius 2 (320 triangles) at o
**   1  a sphere of radius 1 at o + (5, 0, 0)
**   2  a sphere of radius 0.5 at o + (-4, 3, 1)
**   3  the plane through o + (0, -3, 0) with normal (0.1, 1, 0.2)
**   4  an oriented box at o + (0, 4, -3), half-extents (1, 0.5, 0.75),
**      axes (1, 1, 0) and (-1, 1, 1) (made orthogonal by the library)
**   5  a capsule from o + (-3, -1, -2) to o + (-1, 1, -4), radius 0.6
**   6  an L-shaped (concave) hexagon in the plane x - z = 5 + o.x - o.z
**   7  a torus at o + (0, 0, 7): skipped
**   8  the cube mesh [-1, 1]^3 + o + (6, 5, 4) (12 triangles)
**   9  .. 11  three lone triangles (ray_scene_add_triangle): an obtuse
**      one, a thin one (10 degrees at a vertex) and a plain one.  A
**      closed mesh's edge belongs to two triangles, the nearer answer
**      wins, so a triangle's own edge and vertex regions are tested here.
** Every feature (edge, radius) is longer than 0.1.
*/
enum { N_GEOMS = 12 };

static const double lone[3][3][3] = {
    {{2, -2, 3}, {5, -1.5, 3.5}, {3, -1.9, 2.5}},
    {{-6, -1, 4}, {-2, -0.5, 4.2}, {-6, -0.3, 4.1}},
    {{1, 6, 1}, {3, 7, 3}, {0, 8, 2}}};

/* The L's outline in its plane's (u, v), and its four triangles. */
static const double l_uv[6][2] = {{0, 0}, {2, 0}, {2, 1},
                                  {1, 1}, {1, 2}, {0, 2}};
static const int l_tris[4][3] = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}};

typedef struct mixed {
    ray_scene *s;
    ray_vec3 o;
    hc_mesh ball, cube;
    ray_vec3 sc[2];
    double sr[2];
    ray_vec3 plane_p, plane_n;
    ray_box_params box;
    ray_capsule_params cap;
    ray_vec3 poly[6];
    ray_vec3 tri[3][3];
} mixed;

static ray_vec3 at(ray_vec3 o, double x, double y, double z)
{
    return vec(o.x + x, o.y + y, o.z + z);
}

static void mixed_build(mixed *m, ray_vec3 o)
{
    ray_torus_params tor;
    ray_mesh mesh;
    unsigned id;
    int i;

    m->o = o;
    m->ball = hc_icosphere(o, 2);
    m->cube = hc_cube(at(o, 6, 5, 4));
    m->sc[0] = at(o, 5, 0, 0);
    m->sr[0] = 1;
    m->sc[1] = at(o, -4, 3, 1);
    m->sr[1] = 0.5;
    m->plane_p = at(o, 0, -3, 0);
    m->plane_n = vec(0.1, 1, 0.2);
    m->box.center = at(o, 0, 4, -3);
    m->box.half_extents = vec(1, 0.5, 0.75);
    m->box.axis_x = vec(1, 1, 0);
    m->box.axis_y = vec(-1, 1, 1);
    m->cap.a = at(o, -3, -1, -2);
    m->cap.b = at(o, -1, 1, -4);
    m->cap.radius = 0.6;
    for (i = 0; i < 6; i++)
        m->poly[i] = at(o, 3 + l_uv[i][0], 2 + l_uv[i][1], -2 + l_uv[i][0]);
    for (i = 0; i < 9; i++)
        m->tri[i / 3][i % 3] = at(o, lone[i / 3][i % 3][0],
                                  lone[i / 3][i % 3][1],
                                  lone[i / 3][i % 3][2]);
    tor.center = at(o, 0, 0, 7);
    tor.axis = vec(0, 0, 1);
    tor.major = 1;
    tor.minor = 0.3;

    ck_assert_int_eq(ray_scene_new(&m->s, NULL, NULL), RAY_OK);
    mesh = hc_ray_mesh(&m->ball);
    ck_assert_int_eq(ray_scene_add_mesh(m->s, &mesh, RAY_NO_MATERIAL, &id),
                     RAY_OK);
    ck_assert_uint_eq(id, 0);
    for (i = 0; i < 2; i++)
        ck_assert_int_eq(ray_scene_add_sphere(m->s, m->sc[i], m->sr[i],
                                              RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(m->s, m->plane_p, m->plane_n,
                                         RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_box(m->s, &m->box, RAY_NO_MATERIAL, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_add_capsule(m->s, &m->cap, RAY_NO_MATERIAL,
                                           NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_polygon(m->s, m->poly, 6, RAY_NO_MATERIAL,
                                           NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_torus(m->s, &tor, RAY_NO_MATERIAL, NULL),
                     RAY_OK);
    mesh = hc_ray_mesh(&m->cube);
    ck_assert_int_eq(ray_scene_add_mesh(m->s, &mesh, RAY_NO_MATERIAL, &id),
                     RAY_OK);
    ck_assert_uint_eq(id, 8);
    for (i = 0; i < 3; i++) {
        ck_assert_int_eq(ray_scene_add_triangle(m->s, m->tri[i][0],
                                                m->tri[i][1], m->tri[i][2],
                                                RAY_NO_MATERIAL, &id), RAY_OK);
        ck_assert_uint_eq(id, 9 + (unsigned)i);
    }
    ck_assert_int_eq(ray_scene_commit(m->s), RAY_OK);
}

static void mixed_free(mixed *m)
{
    ray_scene_free(m->s);
    hc_mesh_free(&m->ball);
    hc_mesh_free(&m->cube);
}

/* Geometry g's (triangle i's, for a mesh) nearest point to q; *n its
** unit normal there (a box: its face's, as the library chooses it). */
static lvec ref_prim(const mixed *m, unsigned g, unsigned i, lvec q, lvec *n)
{
    lvec p, e[3];
    int k;

    switch (g) {
    case 0:
    case 8: {
        const hc_mesh *h = g == 0 ? &m->ball : &m->cube;
        lvec a = lv(h->v[h->idx[3 * i]]), b = lv(h->v[h->idx[3 * i + 1]]),
             c = lv(h->v[h->idx[3 * i + 2]]);
        *n = lunit(lcross(lsub(b, a), lsub(c, a)));
        return ref_triangle(q, a, b, c);
    }
    case 1:
    case 2: {
        lvec c = lv(m->sc[g - 1]);
        *n = lunit(lsub(q, c));
        return ladd(c, lscale(*n, (ld)m->sr[g - 1]));
    }
    case 3:
        *n = lunit(lv(m->plane_n));
        return lsub(q, lscale(*n, ldot(lsub(q, lv(m->plane_p)), *n)));
    case 4:
        ref_box_frame(&m->box, e);
        p = ref_box(&m->box, q, &k);
        *n = ldot(lsub(q, lv(m->box.center)), e[k]) < 0 ? lscale(e[k], -1)
                                                         : e[k];
        return p;
    case 5:
        p = ref_capsule(&m->cap, q);
        *n = lunit(lsub(p, ref_segment(p, lv(m->cap.a), lv(m->cap.b))));
        return p;
    case 6: {
        lvec best = lv(m->poly[0]);
        /* (u, v) -> (u, v, u): e_u x e_v = (-1, 0, 1), counter-clockwise. */
        *n = lunit(lv3(-1, 0, 1));
        for (k = 0; k < 4; k++) {
            lvec t = ref_triangle(q, lv(m->poly[l_tris[k][0]]),
                                  lv(m->poly[l_tris[k][1]]),
                                  lv(m->poly[l_tris[k][2]]));
            if (k == 0 || ldist(t, q) < ldist(best, q))
                best = t;
        }
        return best;
    }
    case 9:
    case 10:
    case 11: {
        lvec a = lv(m->tri[g - 9][0]), b = lv(m->tri[g - 9][1]),
             c = lv(m->tri[g - 9][2]);
        *n = lunit(lcross(lsub(b, a), lsub(c, a)));
        return ref_triangle(q, a, b, c);
    }
    default:
        ck_abort_msg("no geometry %u", g);
    }
    return q;
}

/* How many primitives geometry g has (the torus, 7, none: skipped). */
static size_t prims_of(const mixed *m, unsigned g)
{
    return g == 0 ? m->ball.nt : g == 8 ? m->cube.nt : g == 7 ? 0 : 1;
}

/* The brute-force answer: the nearest of every primitive's nearest
** points; *tie set when another primitive's point lies within "margin"
** of as near but farther than "margin" from it (two answers). */
typedef struct answer {
    lvec p;
    ld d;
    unsigned g, i;
    int tie;
} answer;

static answer brute_force(const mixed *m, lvec q, ld margin)
{
    answer a;
    unsigned g;
    size_t i;
    lvec n;

    a.d = HUGE_VALL;
    a.tie = 0;
    a.g = a.i = 0;
    a.p = q;
    for (g = 0; g < N_GEOMS; g++)
        for (i = 0; i < prims_of(m, g); i++) {
            lvec p = ref_prim(m, g, (unsigned)i, q, &n);
            ld d = ldist(p, q);
            if (d < a.d) {
                a.d = d;
                a.p = p;
                a.g = g;
                a.i = (unsigned)i;
            }
        }
    for (g = 0; g < N_GEOMS; g++)
        for (i = 0; i < prims_of(m, g); i++) {
            lvec p = ref_prim(m, g, (unsigned)i, q, &n);
            if (ldist(p, q) <= a.d + margin && ldist(p, a.p) > margin)
                a.tie = 1;
        }
    return a;
}

/*
** The tolerance of a distance or a position, for a query q whose answer
** is at distance d, with the scene's coordinates within 10 of o:
** 64 DBL_EPSILON (M + d), M = max(|q|, |o| + 10) the largest coordinate
** involved.  From the library's bounds (ray_closest_point(3),
** "Accuracy"): p lies on its primitive within a few ulps of M (the plane's
** foot: of |q| and |q - point| <= 2 M), its place along the surface is
** off by about 10 u |q - a| / sin^2 of the angle at the triangle's first
** vertex a, which conditions Ericson's determinants (36 degrees or more
** in this scene: a factor 3), and |p - q| rounds within 3 ulps of d:
** some 40 ulps of M + d at worst, under the 128 allowed.
** CLOSEST_TEST_FIGURES=1 prints the largest error measured (under 2
** ulps).
*/
static ld tolerance(const mixed *m, ray_vec3 q, ld d)
{
    ld big = fmaxl(fmaxl(fabsl((ld)q.x), fabsl((ld)q.y)), fabsl((ld)q.z));
    ld mo = fmaxl(fmaxl(fabsl((ld)m->o.x), fabsl((ld)m->o.y)),
                  fabsl((ld)m->o.z)) + 10;

    return 64 * (ld)DBL_EPSILON * (fmaxl(big, mo) + d);
}

/* The normals: from coordinates of magnitude M over features of at least
** L = 0.1 (an edge, a radius), the library's and the reference's unit
** normals differ by a few ulps of M / L: 64 DBL_EPSILON M / L allowed,
** plus the direction's own 1/d sensitivity for a sphere's or a capsule's
** normal (the error of p over the distance from the centre). */
static ld normal_tolerance(const mixed *m, ray_vec3 q, ld d)
{
    return tolerance(m, q, d) / (ld)0.1;
}

/*
** One query checked against brute force: found (radius +Inf); the same
** distance within the tolerance; p on the primitive the ids name, and at
** the distance reported from q; the normal that primitive has there;
** and, unless two primitives tie, the brute-force point itself.
** Returns the error of the distance in units of M + d, for the report.
*/
static double check_query(const mixed *m, ray_vec3 q)
{
    ray_closest c;
    lvec lq = lv(q), rp, rn;
    answer a;
    ld tol;

    ck_assert_int_eq(ray_closest_point(m->s, q, HUGE_VAL, &c), 1);
    a = brute_force(m, lq, 0);
    tol = tolerance(m, q, a.d);
    a = brute_force(m, lq, 4 * tol);
    ck_assert_msg(fabsl((ld)c.distance - a.d) <= tol,
                  "q (%.17g, %.17g, %.17g): distance %.17g, brute force "
                  "%.17Lg (geometry %u, %u; got %u, %u)", q.x, q.y, q.z,
                  c.distance, a.d, a.g, a.i, c.geom_id, c.prim_id);
    ck_assert_uint_lt(c.geom_id, N_GEOMS);
    ck_assert_uint_lt(c.prim_id, prims_of(m, c.geom_id));
    rp = ref_prim(m, c.geom_id, c.prim_id, lv(c.p), &rn);
    ck_assert_msg(ldist(rp, lv(c.p)) <= tol, "p off geometry %u by %Lg",
                  c.geom_id, ldist(rp, lv(c.p)));
    ck_assert(fabsl(ldist(lv(c.p), lq) - (ld)c.distance) <= tol);
    /* The normal at p: the reference's at q's answer on that primitive
    ** (for a sphere and a capsule, along p from the centre or axis). */
    ref_prim(m, c.geom_id, c.prim_id, lq, &rn);
    if (c.geom_id == 1 || c.geom_id == 2)
        rn = lunit(lsub(lv(c.p), lv(m->sc[c.geom_id - 1])));
    if (c.geom_id == 5)
        rn = lunit(lsub(lv(c.p), ref_segment(lv(c.p), lv(m->cap.a),
                                            lv(m->cap.b))));
    ck_assert_msg(ldist(lv(c.n), rn) <= normal_tolerance(m, q, a.d),
                  "geometry %u: normal (%g, %g, %g)", c.geom_id, c.n.x,
                  c.n.y, c.n.z);
    if (!a.tie)
        ck_assert_msg(ldist(lv(c.p), a.p) <= tol,
                      "q (%.17g, %.17g, %.17g): p %Lg from brute force's",
                      q.x, q.y, q.z, ldist(lv(c.p), a.p));
    return (double)(fabsl((ld)c.distance - a.d) /
                    (tol / 64));
}

/*
** Brute force, at the origin and at 1e5: 3000 random points in the
** scene's box grown by 2 (inside and outside every solid, above and
** below the plane), 200 at distance 1e3 and 100 at 1e6 in random
** directions.
*/
START_TEST(should_match_brute_force)
{
    mixed m;
    rng g = {0xc105e57u + (uint64_t)_i};
    double o = test_offset(_i), worst = 0;
    int k;

    mixed_build(&m, vec(o, o, o));
    for (k = 0; k < 3300; k++) {
        ray_vec3 q;
        if (k < 3000)
            q = vadd(m.o, rng_point(&g, -12, 12));
        else
            q = vadd(m.o, vscale(rng_dir(&g), k < 3200 ? 1e3 : 1e6));
        worst = fmax(worst, check_query(&m, q));
    }
    if (getenv("CLOSEST_TEST_FIGURES") != NULL)
        fprintf(stderr, "closest, offset %g: largest distance error %.3g "
                "DBL_EPSILON of M + d\n", o, worst);
    mixed_free(&m);
}
END_TEST

/*
** The radius: a query whose nearest point lies at brute-force distance
** d answers 1 for radius d (1 + 4 tol / d) -- just beyond its rounding
** -- and 0, with out untouched, for d (1 - 4 tol / d): the BVH's pruning
** keeps a box within the radius and drops one beyond it.  Exact cases:
** the unit sphere seen from (3, 0, 0), p = (1, 0, 0) and distance 2
** exactly (exact inputs: (q - c)/|q - c| = (1, 0, 0)); radius 2 is
** inclusive, the next double below is not.
*/
START_TEST(radius_should_bound_the_search)
{
    mixed m;
    rng g = {77};
    ray_scene *s;
    ray_closest c, keep;
    int k;

    mixed_build(&m, vec(0, 0, 0));
    for (k = 0; k < 500; k++) {
        ray_vec3 q = rng_point(&g, -12, 12);
        answer a = brute_force(&m, lv(q), 0);
        ld tol = tolerance(&m, q, a.d);
        double above = (double)(a.d + 4 * tol), below = (double)(a.d - 4 * tol);
        ck_assert_int_eq(ray_closest_point(m.s, q, above, &c), 1);
        ck_assert(fabsl((ld)c.distance - a.d) <= tol);
        if (below >= 0) {
            memset(&c, 0xA5, sizeof c);
            keep = c;
            ck_assert_int_eq(ray_closest_point(m.s, q, below, &c), 0);
            ck_assert(memcmp(&c, &keep, sizeof c) == 0);
        }
    }
    mixed_free(&m);

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1,
                                          RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_closest_point(s, vec(3, 0, 0), 2.0, &c), 1);
    ck_assert(c.distance == 2.0);
    ck_assert_vec_eq(c.p, vec(1, 0, 0));
    ck_assert_vec_eq(c.n, vec(1, 0, 0));
    ck_assert_uint_eq(c.geom_id, 0);
    ck_assert_uint_eq(c.prim_id, 0);
    memset(&c, 0xA5, sizeof c);
    keep = c;
    ck_assert_int_eq(ray_closest_point(s, vec(3, 0, 0), nextafter(2.0, 0),
                                       &c), 0);
    ck_assert(memcmp(&c, &keep, sizeof c) == 0);
    ck_assert_int_eq(ray_closest_point(s, vec(3, 0, 0), HUGE_VAL, &c), 1);
    ck_assert(c.distance == 2.0);
    /* Radius 0 finds a point exactly on the surface, and only that. */
    ck_assert_int_eq(ray_closest_point(s, vec(0, 0, -1), 0.0, &c), 1);
    ck_assert(c.distance == 0.0);
    ck_assert_vec_eq(c.p, vec(0, 0, -1));
    ck_assert_int_eq(ray_closest_point(s, vec(0, 0, -1.5), 0.0, &c), 0);
    /* Inside the sphere: the nearest point of its surface, not 0. */
    ck_assert_int_eq(ray_closest_point(s, vec(0, 0.25, 0), HUGE_VAL, &c), 1);
    ck_assert(c.distance == 0.75);
    ck_assert_vec_eq(c.p, vec(0, 1, 0));
    ray_scene_free(s);
}
END_TEST

/*
** The radius is inclusive, and no box holding a point within it is
** skipped: a query repeated with the distance it found as its radius
** finds the same point again, at the same distance.  Around the cube
** mesh [-1, 1]^3 (its float box is its own, exactly), alone and through
** an instance moved by (8, -4, 2) (exact: every offset is), from the
** 7^3 lattice points of components -3, -1.5, -0.5, 0, 0.5, 1.5, 3
** (inside, on the surface, beyond faces, edges and vertices).  Where
** the nearest point faces q along an axis or at a vertex, the box's
** distance is the point's exactly, so a box distance rounded up by a
** few ulps instead of down (boxes_d2's shrink), or a radius squared
** and rounded down (set_best), skips the point.  Exact comparisons:
** both calls compute the same distance from the same point.
*/
START_TEST(radius_found_should_find_the_point_again)
{
    static const double at[7] = {-3, -1.5, -0.5, 0, 0.5, 1.5, 3};
    const ray_vec3 move = vec(8, -4, 2);
    hc_mesh cube = hc_cube(v3(0, 0, 0));
    ray_mesh rm = hc_ray_mesh(&cube);
    ray_scene *child, *top;
    ray_transform xf;
    int x, y, z, inst;

    ck_assert_int_eq(ray_scene_new(&child, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(child, &rm, RAY_NO_MATERIAL, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    ray_transform_identity(&xf);
    xf.m[0][3] = move.x;
    xf.m[1][3] = move.y;
    xf.m[2][3] = move.z;
    ck_assert_int_eq(ray_scene_new(&top, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_instance(top, child, &xf, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    for (inst = 0; inst < 2; inst++)
        for (x = 0; x < 7; x++)
            for (y = 0; y < 7; y++)
                for (z = 0; z < 7; z++) {
                    ray_scene *s = inst ? top : child;
                    ray_vec3 q = vec(at[x], at[y], at[z]);
                    ray_closest first, again;
                    if (inst)
                        q = vadd(q, move);
                    ck_assert_int_eq(ray_closest_point(s, q, HUGE_VAL,
                                                       &first), 1);
                    ck_assert_msg(ray_closest_point(s, q, first.distance,
                                                    &again) == 1,
                                  "q (%g, %g, %g)%s: nothing within the "
                                  "distance found, %.17g", q.x, q.y, q.z,
                                  inst ? " (instance)" : "",
                                  first.distance);
                    ck_assert(again.distance == first.distance);
                    ck_assert_vec_eq(again.p, first.p);
                }
    ray_scene_free(top);
    ray_scene_free(child);
    hc_mesh_free(&cube);
}
END_TEST

/*
** Points on the surface, exactly: on the plane z = 0 (its foot is q
** itself, distance 0), on a face of an axis-aligned box (local
** coordinates exact: p = q), on a sphere's pole; and every vertex of the
** icosphere (Ericson's vertex regions return the vertex itself: p the
** vertex bit for bit, distance 0).  On every edge's midpoint (a+b)/2 as
** rounded, within an ulp of |o| + 2 per component of the exact edge,
** and found within a few ulps more: distance within tol_at(2 o), 64
** ulps of 2 |o| + 10, the other suites' bound for a few dozen roundings.
*/
START_TEST(should_find_points_on_the_surface)
{
    ray_scene *s;
    ray_box_params b;
    ray_closest c;
    double o = test_offset(_i);
    hc_mesh ball = hc_icosphere(vec(o, o, o), 2);
    ray_mesh mesh = hc_ray_mesh(&ball);
    size_t i;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(o, o, o - 20), vec(0, 0, 1),
                                         RAY_NO_MATERIAL, NULL), RAY_OK);
    b.center = vec(o + 10, o, o);
    b.half_extents = vec(1, 1, 1);
    b.axis_x = vec(1, 0, 0);
    b.axis_y = vec(0, 1, 0);
    ck_assert_int_eq(ray_scene_add_box(s, &b, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(o - 10, o, o), 1,
                                          RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &mesh, RAY_NO_MATERIAL, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);

    ck_assert_int_eq(ray_closest_point(s, vec(o + 0.3, o + 0.7, o - 20),
                                       HUGE_VAL, &c), 1);
    ck_assert_uint_eq(c.geom_id, 0);
    ck_assert(c.distance == 0.0);
    ck_assert_vec_eq(c.p, vec(o + 0.3, o + 0.7, o - 20));
    ck_assert_vec_eq(c.n, vec(0, 0, 1));
    ck_assert_int_eq(ray_closest_point(s, vec(o + 11, o + 0.25, o - 0.5),
                                       HUGE_VAL, &c), 1);
    ck_assert_uint_eq(c.geom_id, 1);
    ck_assert(c.distance == 0.0);
    ck_assert_vec_eq(c.p, vec(o + 11, o + 0.25, o - 0.5));
    ck_assert_vec_eq(c.n, vec(1, 0, 0));
    ck_assert_int_eq(ray_closest_point(s, vec(o - 10, o, o + 1), HUGE_VAL,
                                       &c), 1);
    ck_assert_uint_eq(c.geom_id, 2);
    ck_assert(c.distance == 0.0);
    ck_assert_vec_eq(c.n, vec(0, 0, 1));
    for (i = 0; i < ball.nv; i++) {
        ck_assert_int_eq(ray_closest_point(s, ball.v[i], HUGE_VAL, &c), 1);
        ck_assert_uint_eq(c.geom_id, 3);
        ck_assert(c.distance == 0.0);
        ck_assert_vec_eq(c.p, ball.v[i]);
        ck_assert_uint_lt(c.prim_id, ball.nt);
        ck_assert(ball.idx[3 * c.prim_id] == i ||
                  ball.idx[3 * c.prim_id + 1] == i ||
                  ball.idx[3 * c.prim_id + 2] == i);
    }
    for (i = 0; i < 3 * ball.nt; i++) {
        ray_vec3 a = ball.v[ball.idx[i]];
        ray_vec3 e = ball.v[ball.idx[i % 3 == 2 ? i - 2 : i + 1]];
        ray_vec3 mid = vscale(vadd(a, e), 0.5);
        ck_assert_int_eq(ray_closest_point(s, mid, HUGE_VAL, &c), 1);
        ck_assert_uint_eq(c.geom_id, 3);
        ck_assert_msg(c.distance <= tol_at(2 * o), "edge %zu: %g", i,
                      c.distance);
    }
    ray_scene_free(s);
    hc_mesh_free(&ball);
}
END_TEST

/*
** Inside a closed mesh: from the icosphere's centre every face is at its
** inradius, about 1.9 (the brute force says which); a point off centre
** gets the nearest face, not 0.  Far beyond, 1e200 to 1.7e308 from the
** scene, where the box distances are scaled to keep their squares
** finite: the answer is still brute force's, to 1e-15 relative (the
** distance, about |q|, is the difference of coordinates 1e200 and 1
** apart: only its last rounding shows).  Which primitive is nearest is
** below the doubles' resolution there (and long double's), so only the
** distance is checked.  The mixed scene's plane is nearest from almost
** every far direction, so a second scene without one (the icosphere and
** a sphere) has the scaled box distances order the BVHs' boxes.
*/
START_TEST(should_answer_inside_and_far_beyond)
{
    mixed m;
    ray_closest c;
    ray_vec3 far[4];
    int k;

    mixed_build(&m, vec(0, 0, 0));
    check_query(&m, vec(0, 0, 0));
    check_query(&m, vec(0.3, -0.2, 0.1));
    ck_assert_int_eq(ray_closest_point(m.s, vec(0, 0, 0), HUGE_VAL, &c), 1);
    ck_assert_uint_eq(c.geom_id, 0);
    ck_assert(c.distance > 1.8 && c.distance < 2.0);
    far[0] = vec(1e200, 3, -2);
    far[1] = vec(-1.7e308, 0, 0);
    far[2] = vec(0, -1e300, 1e300);
    far[3] = vec(5e153, 5e153, 5e153);
    for (k = 0; k < 4; k++) {
        answer a = brute_force(&m, lv(far[k]), 0);
        ck_assert_int_eq(ray_closest_point(m.s, far[k], HUGE_VAL, &c), 1);
        ck_assert_msg(fabsl((ld)c.distance - a.d) <= 1e-15L * a.d,
                      "far %d: %.17g against %.17Lg", k, c.distance, a.d);
        ck_assert(isfinite(c.p.x) && isfinite(c.p.y) && isfinite(c.p.z));
    }
    {
        hc_mesh ball = hc_icosphere(vec(0, 0, 0), 2);
        ray_mesh mesh = hc_ray_mesh(&ball);
        ray_scene *s;
        size_t i;

        ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_mesh(s, &mesh, RAY_NO_MATERIAL, NULL),
                         RAY_OK);
        ck_assert_int_eq(ray_scene_add_sphere(s, vec(5, 0, 0), 1,
                                              RAY_NO_MATERIAL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        for (k = 0; k < 4; k++) {
            lvec q = lv(far[k]);
            ld best = ldist(q, lv3(5, 0, 0)) - 1;
            for (i = 0; i < ball.nt; i++)
                best = fminl(best, ldist(q, ref_triangle(
                                                q, lv(ball.v[ball.idx[3 * i]]),
                                                lv(ball.v[ball.idx[3 * i + 1]]),
                                                lv(ball.v[ball.idx[3 * i + 2]]))));
            ck_assert_int_eq(ray_closest_point(s, far[k], HUGE_VAL, &c), 1);
            ck_assert_uint_lt(c.geom_id, 2);
            ck_assert_msg(fabsl((ld)c.distance - best) <= 1e-15L * best,
                          "far %d: %.17g against %.17Lg", k, c.distance,
                          best);
        }
        ray_scene_free(s);
        hc_mesh_free(&ball);
    }
    mixed_free(&m);
}
END_TEST

/* Nothing to find: an empty scene, and one whose only geometry is of a
** kind without a closest-point routine (a torus), answer 0, out
** untouched, whatever the radius. */
START_TEST(empty_scenes_should_find_nothing)
{
    ray_scene *s;
    ray_torus_params t;
    ray_closest c, keep;
    int k;

    memset(&c, 0xA5, sizeof c);
    keep = c;
    t.center = vec(0, 0, 0);
    t.axis = vec(0, 1, 0);
    t.major = 2;
    t.minor = 0.5;
    for (k = 0; k < 2; k++) {
        ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
        if (k == 1)
            ck_assert_int_eq(ray_scene_add_torus(s, &t, RAY_NO_MATERIAL,
                                                 NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        ck_assert_int_eq(ray_closest_point(s, vec(0, 0, 0), HUGE_VAL, &c), 0);
        ck_assert_int_eq(ray_closest_point(s, vec(2, 0, 0), 1.0, &c), 0);
        ck_assert(memcmp(&c, &keep, sizeof c) == 0);
        ray_scene_free(s);
    }
}
END_TEST

/* Misuse is a negated status with out untouched: NULL scene or out, a q
** not finite, a negative or NaN radius (-RAY_EINVAL); a scene not yet
** committed (-RAY_ESTATE). */
START_TEST(misuse_should_be_refused)
{
    ray_scene *s;
    ray_closest c, keep;
    ray_vec3 q = vec(3, 0, 0);

    memset(&c, 0xA5, sizeof c);
    keep = c;
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1,
                                          RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_closest_point(s, q, 10, &c), -RAY_ESTATE);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_closest_point(NULL, q, 10, &c), -RAY_EINVAL);
    ck_assert_int_eq(ray_closest_point(s, q, 10, NULL), -RAY_EINVAL);
    ck_assert_int_eq(ray_closest_point(s, vec((double)NAN, 0, 0), 10, &c),
                     -RAY_EINVAL);
    ck_assert_int_eq(ray_closest_point(s, vec(0, HUGE_VAL, 0), 10, &c),
                     -RAY_EINVAL);
    ck_assert_int_eq(ray_closest_point(s, vec(0, 0, -HUGE_VAL), 10, &c),
                     -RAY_EINVAL);
    ck_assert_int_eq(ray_closest_point(s, q, -1, &c), -RAY_EINVAL);
    ck_assert_int_eq(ray_closest_point(s, q, -HUGE_VAL, &c), -RAY_EINVAL);
    ck_assert_int_eq(ray_closest_point(s, q, (double)NAN, &c), -RAY_EINVAL);
    ck_assert(memcmp(&c, &keep, sizeof c) == 0);
    ck_assert_int_eq(ray_closest_point(s, q, 10, &c), 1);
    ray_scene_free(s);
}
END_TEST

/* ------------------------------------------- through any affine transform */

/* A random linear part: a rotation about a random axis, a scale of 0.3
** to 3 per axis (one of them negated every third time: a reflection),
** another rotation and a shear of up to 0.5: every kind of invertible
** affine map but the singular ones. */
static void random_affine(rng *g, int k, ray_transform *t, ray_vec3 at)
{
    double a[3][3], b[3][3], s[3], m[3][3];
    int i, j, l, r;

    for (r = 0; r < 2; r++) {
        ray_vec3 ax = rng_dir(g);
        double th = rng_range(g, 0, 6.283185307179586), c = cos(th),
               sn = sin(th), v = 1 - c;
        double (*q)[3] = r == 0 ? a : b;
        q[0][0] = c + ax.x * ax.x * v;
        q[0][1] = ax.x * ax.y * v - ax.z * sn;
        q[0][2] = ax.x * ax.z * v + ax.y * sn;
        q[1][0] = ax.y * ax.x * v + ax.z * sn;
        q[1][1] = c + ax.y * ax.y * v;
        q[1][2] = ax.y * ax.z * v - ax.x * sn;
        q[2][0] = ax.z * ax.x * v - ax.y * sn;
        q[2][1] = ax.z * ax.y * v + ax.x * sn;
        q[2][2] = c + ax.z * ax.z * v;
    }
    for (i = 0; i < 3; i++)
        s[i] = rng_range(g, 0.3, 3);
    if (k % 3 == 0)
        s[k % 2] = -s[k % 2];
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) {
            m[i][j] = 0;
            for (l = 0; l < 3; l++)
                m[i][j] += a[i][l] * s[l] * b[l][j];
        }
    m[0][1] += rng_range(g, -0.5, 0.5);
    m[1][2] += rng_range(g, -0.5, 0.5);
    ray_transform_identity(t);
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            t->m[i][j] = m[i][j];
    t->m[0][3] = at.x;
    t->m[1][3] = at.y;
    t->m[2][3] = at.z;
}

/* Point v through t, in long double. */
static lvec lxfm(const ray_transform *t, ray_vec3 v)
{
    lvec r;
    lvec l = lv(v);
    r.x = (ld)t->m[0][0] * l.x + (ld)t->m[0][1] * l.y + (ld)t->m[0][2] * l.z + (ld)t->m[0][3];
    r.y = (ld)t->m[1][0] * l.x + (ld)t->m[1][1] * l.y + (ld)t->m[1][2] * l.z + (ld)t->m[1][3];
    r.z = (ld)t->m[2][0] * l.x + (ld)t->m[2][1] * l.y + (ld)t->m[2][2] * l.z + (ld)t->m[2][3];
    return r;
}

/* The child: an icosphere (geometry 0, 80 triangles), a cube mesh
** (geometry 1), an oriented box (2) and the L-shaped hexagon (3): the
** kinds a world-space brute force can take as triangles. */
typedef struct child_ref {
    hc_mesh ball, cube;
    ray_box_params box;
    ray_vec3 poly[6];
} child_ref;

/* Triangle k of geometry g of the child (box: 12, polygon: 4), corners
** in the child's space; 0 when g has no triangle k. */
static int child_triangle(const child_ref *c, unsigned g, size_t k,
                          ray_vec3 v[3])
{
    if (g <= 1) {
        const hc_mesh *h = g == 0 ? &c->ball : &c->cube;
        if (k >= h->nt)
            return 0;
        v[0] = h->v[h->idx[3 * k]];
        v[1] = h->v[h->idx[3 * k + 1]];
        v[2] = h->v[h->idx[3 * k + 2]];
        return 1;
    }
    if (g == 2) {
        lvec e[3], ctr = lv(c->box.center);
        ld h[3];
        int axis = (int)k / 4, side = (int)(k / 2) % 2, t = (int)k % 2, i;
        int sgn[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
        if (k >= 12)
            return 0;
        ref_box_frame(&c->box, e);
        h[0] = (ld)c->box.half_extents.x;
        h[1] = (ld)c->box.half_extents.y;
        h[2] = (ld)c->box.half_extents.z;
        for (i = 0; i < 3; i++) {
            int corner = i == 0 ? 0 : i + t;
            lvec p = ladd(ctr, lscale(e[axis], side ? h[axis] : -h[axis]));
            int j = (axis + 1) % 3, l = (axis + 2) % 3;
            p = ladd(p, lscale(e[j], sgn[corner][0] * h[j]));
            p = ladd(p, lscale(e[l], sgn[corner][1] * h[l]));
            v[i] = vec((double)p.x, (double)p.y, (double)p.z);
        }
        return 1;
    }
    if (g == 3 && k < 4) {
        v[0] = c->poly[l_tris[k][0]];
        v[1] = c->poly[l_tris[k][1]];
        v[2] = c->poly[l_tris[k][2]];
        return 1;
    }
    return 0;
}

/*
** An instance far from the origin: a child of a unit cube mesh
** ([-0.5, 0.5]^3 moved by (0.1, 0.2, 0.3), so that no coordinate lies
** on the doubles' grid near 2^40 and every world corner rounds) and an
** icosphere of radius 1 (the BVH gets several leaves), placed at
** (2^40, 2^40, 2^40), translated alone and rotated too.  Near 2^40 a
** double's ulp is 2^-12, so the library's world triangles stand up to
** half an ulp per component off the exact ones; a boxes' pruning that
** measures the child's exact boxes against the rounded world distances
** skipped the nearest triangle, and a query whose radius was the
** distance it had just found found nothing in about half the cases (the
** review of issue 38).  Against brute force over every world triangle
** in long double, for 2,000 query points within 1.5 of the instance:
** the distance within 4 ulps of 2^40 (a world corner's half ulp plus
** the nearest point's gamma(3) (|a| + |b - a| + |c - a|), about 1.5
** ulps, per component: 2 sqrt(3) < 4 ulps); the found distance as the
** radius finds the same point again (the radius is compared with the
** computed distance, inclusive: ray_closest_point(3)); and the brute
** force's distance plus that tolerance as the radius finds a point.
*/
START_TEST(closest_points_should_keep_their_radius_through_far_instances)
{
    const double far = 0x1p40, tol = 4 * 0x1p-12;
    hc_mesh cube = hc_cube(vec(0.2, 0.4, 0.6)), ball = hc_icosphere(vec(0, 0, 0), 2);
    const hc_mesh *meshes[2];
    ray_scene *child, *top;
    ray_transform xf;
    rng g = {4040};
    size_t i;
    int rot, k, m;

    for (i = 0; i < cube.nv; i++)
        cube.v[i] = vscale(cube.v[i], 0.5);
    for (i = 0; i < ball.nv; i++)
        ball.v[i] = vscale(ball.v[i], 0.5);
    meshes[0] = &cube;
    meshes[1] = &ball;
    ck_assert_int_eq(ray_scene_new(&child, NULL, NULL), RAY_OK);
    for (m = 0; m < 2; m++) {
        ray_mesh rm = hc_ray_mesh(meshes[m]);
        ck_assert_int_eq(ray_scene_add_mesh(child, &rm, RAY_NO_MATERIAL, NULL), RAY_OK);
    }
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    for (rot = 0; rot < 2; rot++) {
        ray_transform_identity(&xf);
        if (rot) {
            xf.m[0][0] = xf.m[1][1] = cos(0.6);
            xf.m[0][1] = -sin(0.6);
            xf.m[1][0] = sin(0.6);
        }
        xf.m[0][3] = xf.m[1][3] = xf.m[2][3] = far;
        ck_assert_int_eq(ray_scene_new(&top, NULL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_instance(top, child, &xf, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
        for (k = 0; k < 2000; k++) {
            ray_vec3 q = vec(far + rng_range(&g, -1.5, 1.5), far + rng_range(&g, -1.5, 1.5),
                             far + rng_range(&g, -1.5, 1.5));
            ld best = HUGE_VALL;
            ray_closest r, again;
            for (m = 0; m < 2; m++)
                for (i = 0; i < meshes[m]->nt; i++) {
                    const ray_vec3 *v = meshes[m]->v;
                    const unsigned *t = meshes[m]->idx + 3 * i;
                    lvec x = ref_triangle(lv(q), lxfm(&xf, v[t[0]]), lxfm(&xf, v[t[1]]),
                                          lxfm(&xf, v[t[2]]));
                    if (ldist(x, lv(q)) < best)
                        best = ldist(x, lv(q));
                }
            ck_assert_int_eq(ray_closest_point(top, q, HUGE_VAL, &r), 1);
            ck_assert_msg(fabsl((ld)r.distance - best) <= (ld)tol,
                          "rotated %d, query %d: distance %.17g, brute force %.17Lg",
                          rot, k, r.distance, best);
            ck_assert_msg(ray_closest_point(top, q, r.distance, &again) == 1,
                          "rotated %d, query %d: nothing within the distance found, %.17g",
                          rot, k, r.distance);
            ck_assert(again.distance == r.distance);
            ck_assert_vec_eq(again.p, r.p);
            ck_assert_int_eq(ray_closest_point(top, q, (double)best + tol, &again), 1);
        }
        ray_scene_free(top);
    }
    ray_scene_free(child);
    hc_mesh_free(&cube);
    hc_mesh_free(&ball);
}
END_TEST

/*
** A sphere and a capsule through a non-uniform scale with a shear are an
** ellipsoid and an ellipsoid swept along a segment, whose nearest points
** have no formula: the library finds them by Eberly's bisection and a
** golden-section search (src/prim/ellipsoid.c).  Checked for 100 points
** a kind under make check-long, 30 under make check (issue 38: the
** dense samples took 5 of the suite's 10 s), near and far, without a reference of the same kind: the answer
** lies on the surface (its preimage is at the radius from the centre or
** the segment, within 1e-12 relative: a few dozen roundings), it is a
** stationary point of the distance (q - p along the normal reported, to
** 1e-9 in angle: the bisection's last bit and the map's rounding,
** divided by the distance), and no point of a dense sample of the
** surface (180 x 360 directions of the preimage, mapped) is nearer by
** more than rounding (90 x 180 directions of the preimage sphere, 9
** spheres along the capsule's axis: points of the body, none nearer an
** outside q than its nearest point).  A point inside the swept
** ellipsoid gets the nearest point of the ellipsoid it lies deepest in
** (ray_closest_point(3)), which is only checked to be stationary.
*/
/* The preimage of world point p under xf, in long double. */
static lvec lxfm_inverse(const ray_transform *xf, ray_vec3 p)
{
    ld m[3][4], inv[3][3], det;
    int i, j;
    lvec d;

    for (i = 0; i < 3; i++)
        for (j = 0; j < 4; j++)
            m[i][j] = (ld)xf->m[i][j];
    d = lv3((ld)p.x - m[0][3], (ld)p.y - m[1][3], (ld)p.z - m[2][3]);

    inv[0][0] = m[1][1] * m[2][2] - m[1][2] * m[2][1];
    inv[0][1] = m[0][2] * m[2][1] - m[0][1] * m[2][2];
    inv[0][2] = m[0][1] * m[1][2] - m[0][2] * m[1][1];
    inv[1][0] = m[1][2] * m[2][0] - m[1][0] * m[2][2];
    inv[1][1] = m[0][0] * m[2][2] - m[0][2] * m[2][0];
    inv[1][2] = m[0][2] * m[1][0] - m[0][0] * m[1][2];
    inv[2][0] = m[1][0] * m[2][1] - m[1][1] * m[2][0];
    inv[2][1] = m[0][1] * m[2][0] - m[0][0] * m[2][1];
    inv[2][2] = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    det = m[0][0] * inv[0][0] + m[0][1] * inv[1][0] + m[0][2] * inv[2][0];
    return lv3((inv[0][0] * d.x + inv[0][1] * d.y + inv[0][2] * d.z) / det,
               (inv[1][0] * d.x + inv[1][1] * d.y + inv[1][2] * d.z) / det,
               (inv[2][0] * d.x + inv[2][1] * d.y + inv[2][2] * d.z) / det);
}

START_TEST(closest_points_should_find_ellipsoids)
{
    const ld pi = 3.14159265358979323846L;
    ray_transform xf;
    ray_scene *child[2], *top[2];
    ray_capsule_params cap;
    rng g = {77};
    int kind, i, n = (int)test_count(NULL, 100, 30);

    ray_transform_identity(&xf);
    xf.m[0][0] = 3;
    xf.m[0][1] = 0.8;
    xf.m[1][1] = 0.5;
    xf.m[1][2] = -0.3;
    xf.m[2][0] = 0.4;
    xf.m[2][2] = 1.5;
    xf.m[0][3] = 1;
    xf.m[1][3] = -2;
    xf.m[2][3] = 0.5;
    cap.a = vec(-1, 0.5, 0);
    cap.b = vec(1, -0.5, 1);
    cap.radius = 0.7;
    for (kind = 0; kind < 2; kind++) {
        unsigned id;
        ck_assert_int_eq(ray_scene_new(&child[kind], NULL, NULL), RAY_OK);
        if (kind == 0)
            ck_assert_int_eq(ray_scene_add_sphere(child[kind], vec(0.5, 0, 0), 1, RAY_NO_MATERIAL, NULL), RAY_OK);
        else
            ck_assert_int_eq(ray_scene_add_capsule(child[kind], &cap, RAY_NO_MATERIAL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_commit(child[kind]), RAY_OK);
        ck_assert_int_eq(ray_scene_new(&top[kind], NULL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_instance(top[kind], child[kind], &xf, &id), RAY_OK);
        ck_assert_int_eq(ray_scene_commit(top[kind]), RAY_OK);
    }
    for (kind = 0; kind < 2; kind++)
        for (i = 0; i < n; i++) {
            ray_vec3 q = rng_point(&g, -8, 8);
            ray_closest r;
            lvec y, seg;
            ld sample = HUGE_VALL, radius;
            int a, b, k, inside;
            if (kind == 1 && i % 2 == 0)
                q = vscale(q, 0.3);
            ck_assert_int_eq(ray_closest_point(top[kind], q, HUGE_VAL, &r), 1);
            y = lxfm_inverse(&xf, q);
            radius = kind == 0 ? 1 : (ld)cap.radius;
            inside = kind == 1 &&
                     ldist(y, ref_segment(y, lv(cap.a), lv(cap.b))) < radius;
            /* Inside a swept ellipsoid: the deepest ellipsoid's point,
            ** on its own surface (the sphere at the segment's point). */
            y = lxfm_inverse(&xf, r.p);
            seg = kind == 0 ? lv(vec(0.5, 0, 0))
                            : ref_segment(y, lv(cap.a), lv(cap.b));
            if (r.distance > 1e-3) {
                lvec c = lcross(lunit(lsub(lv(q), lv(r.p))), lv(r.n));
                ck_assert_msg(llen(c) <= 1e-9L, "kind %d query %d: q - p "
                              "off the normal by %Lg", kind, i, llen(c));
            }
            if (inside)
                continue;
            ck_assert_msg(fabsl(ldist(y, seg) - radius) <= 1e-12L,
                          "kind %d query %d: preimage at %Lg from the axis",
                          kind, i, ldist(y, seg));
            /* Sample the surface (for the capsule, 11 spheres along its
            ** axis: points of the body, none nearer an outside q than
            ** the body's nearest point). */
            for (k = 0; k <= (kind == 0 ? 0 : 8); k++) {
                lvec o = kind == 0 ? seg
                                   : ladd(lv(cap.a), lscale(lsub(lv(cap.b), lv(cap.a)), (ld)k / 8));
                for (a = 0; a < 90; a++)
                    for (b = 0; b < 180; b++) {
                        ld th = pi * (a + 0.5L) / 90, ph = 2 * pi * b / 180;
                        lvec w = lv3(sinl(th) * cosl(ph), sinl(th) * sinl(ph), cosl(th));
                        lvec e = ladd(o, lscale(w, radius));
                        lvec wp = lxfm(&xf, vec((double)e.x, (double)e.y, (double)e.z));
                        if (ldist(wp, lv(q)) < sample)
                            sample = ldist(wp, lv(q));
                    }
            }
            ck_assert_msg((ld)r.distance <= sample + 1e-12L,
                          "kind %d query %d: distance %.17g, a sample "
                          "%.17Lg", kind, i, r.distance, sample);
        }
    for (kind = 0; kind < 2; kind++) {
        ray_scene_free(top[kind]);
        ray_scene_free(child[kind]);
    }
}
END_TEST

/*
** The defect of issue 30, found from outside: through a non-uniform
** scale, a shear or a reflection, ray_closest_point answered the
** child's nearest point in its own space (47 of 1,500 distances off,
** 72 wrong triangles in the reporter's test).  Now: 60 instances of a
** child of meshes, a box and a polygon under random affine maps
** (random_affine), 1,500 query points among them under make check-long,
** the first 500 under make check (issue 38), against brute force
** over every world-space triangle in long double (the box and the
** polygon as their triangles, the box's corners from ref_box_frame in
** long double: they round a little differently from the library's, by
** a few ulps of the box's size).  The distance must agree within
** 2^12 ulps of the coordinates' magnitude (40: the library's world
** corners round once more per product of the map, a few dozen ulps),
** and the primitive named must be the brute force's unless another
** primitive (of another instance, geometry or triangle: the box's and
** the polygon's triangles are one primitive) is as near within twice
** that (a tie: a shared edge or vertex, or two surfaces alike).  A radius 1e-9 short of the answer finds nothing.
*/
START_TEST(closest_points_should_be_exact_through_any_transform)
{
    child_ref c;
    ray_scene *child, *top;
    ray_transform xf[60];
    unsigned ids[60];
    ray_mesh m;
    rng g = {3017};
    const double tol = 4096 * DBL_EPSILON * 40;
    int k, i, wrong = 0, n = (int)test_count(NULL, 1500, 500);

    c.ball = hc_icosphere(vec(0, 0, 0), 1);
    c.cube = hc_cube(vec(2.5, 0, 0));
    c.box.center = vec(0, 2.5, 0);
    c.box.half_extents = vec(0.5, 0.3, 0.8);
    c.box.axis_x = vec(1, 1, 0);
    c.box.axis_y = vec(-1, 1, 1);
    for (i = 0; i < 6; i++)
        c.poly[i] = vec(-3 + l_uv[i][0], l_uv[i][1], 0.5 * l_uv[i][0]);
    ck_assert_int_eq(ray_scene_new(&child, NULL, NULL), RAY_OK);
    m = hc_ray_mesh(&c.ball);
    ck_assert_int_eq(ray_scene_add_mesh(child, &m, RAY_NO_MATERIAL, NULL), RAY_OK);
    m = hc_ray_mesh(&c.cube);
    ck_assert_int_eq(ray_scene_add_mesh(child, &m, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_box(child, &c.box, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_polygon(child, c.poly, 6, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    ck_assert_int_eq(ray_scene_new(&top, NULL, NULL), RAY_OK);
    for (k = 0; k < 60; k++) {
        random_affine(&g, k, &xf[k], rng_point(&g, -15, 15));
        ck_assert_int_eq(ray_scene_add_instance(top, child, &xf[k], &ids[k]), RAY_OK);
    }
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    for (i = 0; i < n; i++) {
        ray_vec3 q = rng_point(&g, -18, 18);
        ld best = HUGE_VALL, second = HUGE_VALL;
        unsigned bi = 0, bg = 0, bk = 0, gg;
        ray_closest r;
        for (k = 0; k < 60; k++)
            for (gg = 0; gg < 4; gg++) {
                size_t t;
                ray_vec3 v[3];
                for (t = 0; child_triangle(&c, gg, t, v); t++) {
                    lvec x = ref_triangle(lv(q), lxfm(&xf[k], v[0]),
                                          lxfm(&xf[k], v[1]),
                                          lxfm(&xf[k], v[2]));
                    ld d = ldist(x, lv(q));
                    unsigned pk = (unsigned)(gg >= 2 ? 0 : t);
                    if (d < best) {
                        if (bi != (unsigned)k || bg != gg || bk != pk)
                            second = best;
                        best = d;
                        bi = (unsigned)k;
                        bg = gg;
                        bk = pk;
                    } else if (d < second &&
                               (bi != (unsigned)k || bg != gg || bk != pk))
                        second = d;
                }
            }
        ck_assert_int_eq(ray_closest_point(top, q, HUGE_VAL, &r), 1);
        ck_assert_msg(fabsl((ld)r.distance - best) <= (ld)tol,
                      "query %d: distance %.17g, brute force %.17Lg", i,
                      r.distance, best);
        ck_assert_double_eq_tol(vdist(r.p, q), r.distance, tol);
        if (second - best > 2 * (ld)tol &&
            (r.inst_id != ids[bi] || r.geom_id != bg || r.prim_id != bk))
            wrong++;
        if (r.distance > 1e-6)
            ck_assert_int_eq(ray_closest_point(top, q, r.distance * (1 - 1e-9), &r), 0);
    }
    ck_assert_int_eq(wrong, 0);
    ray_scene_free(top);
    ray_scene_free(child);
    hc_mesh_free(&c.ball);
    hc_mesh_free(&c.cube);
}
END_TEST

/*
** Threads and memory: one committed scene queried from four threads at
** once, each getting the answers a lone thread got, bit for bit (under
** make tsan, the race check of the query path); and the scene's
** allocator is not called by any query (the calls allocate nothing).
*/
#define CLOSEST_THREADS 4
#define CLOSEST_POINTS 400

typedef struct closest_job {
    const ray_scene *s;
    const ray_vec3 *q;
    ray_closest out[CLOSEST_POINTS];
    int rc[CLOSEST_POINTS];
} closest_job;

static void *closest_thread(void *arg)
{
    closest_job *j = arg;
    int i;

    memset(j->out, 0, sizeof j->out);
    for (i = 0; i < CLOSEST_POINTS; i++)
        j->rc[i] = ray_closest_point(j->s, j->q[i], i % 2 ? HUGE_VAL : 1.0,
                                     &j->out[i]);
    return NULL;
}

/* libc's allocator, counting its calls. */
static void *counted(void *ud, void *ptr, size_t osize, size_t nsize)
{
    (void)osize;
    ++*(long *)ud;
    if (nsize == 0) {
        free(ptr);
        return NULL;
    }
    return realloc(ptr, nsize);
}

/*
** Issue 38, defect 5: a zero-area mesh triangle (collinear vertices: the
** segment (0,0,0)-(2,0,0)) has no normal, and the scene reads it as no
** surface at all (scene.h, ray__tri_by_id: every ray misses it, no record
** is filled from it; ray_scene_add_mesh(3)).  Every query must agree: the
** overlaps reported it (as the point at its first corner) while
** ray_closest_point never found it; now none of ray_intersect,
** ray_closest_point, ray_overlap_shape (a sphere, a box) and a sphere
** sweep through its corners finds it.  A second, proper triangle of the
** same mesh is found by all, so the queries do reach the mesh.
*/
START_TEST(zero_area_triangles_should_be_skipped_by_every_query)
{
    static const ray_vec3 v[6] = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0},
                                  {10, 0, 0}, {11, 0, 0}, {10, 1, 0}};
    static const unsigned idx[6] = {0, 1, 2, 3, 4, 5};
    ray_scene *s;
    ray_mesh m;
    ray_overlap o[2];
    ray_box_params b;
    ray_closest c;
    ray_sweep sw;
    ray_contact k;
    ray_hit h;
    ray_ray r;
    size_t n = 77;

    memset(&m, 0, sizeof m);
    m.vertices = v;
    m.vertex_count = 6;
    m.indices = idx;
    m.triangle_count = 2;
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    /* Near the degenerate one (its first corner included), far from the
    ** other (9 away): nothing. */
    r = make_ray(vec(0, 0, 5), vec(0, 0, -1), 0, HUGE_VAL);
    ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), 0);
    ck_assert_int_eq(ray_closest_point(s, vec(1, 1, 0), 2, &c), 0);
    ck_assert_int_eq(ray_overlap_shape_all(s, TK_SPHERE(vec(0, 0, 0), 2), NULL, o, 2, &n), 0);
    ck_assert_uint_eq(n, 0);
    b.center = vec(0, 0, 0);
    b.half_extents = vec(2, 2, 2);
    b.axis_x = vec(1, 0, 0);
    b.axis_y = vec(0, 1, 0);
    n = 77;
    ck_assert_int_eq(ray_overlap_shape_all(s, TK_BOX(&b), NULL, o, 2, &n), 0);
    ck_assert_uint_eq(n, 0);
    memset(&sw, 0, sizeof sw);
    sw.shape.a = sw.shape.b = vec(0, 0, 5);
    sw.shape.radius = 0.5;
    sw.dir = vec(0, 0, -10);
    ck_assert_int_eq(ray_intersect_sweep(s, &sw, NULL, &k), 0);
    /* The proper triangle: found by each. */
    ck_assert_int_eq(ray_closest_point(s, vec(10.25, 0.25, 1), 2, &c), 1);
    ck_assert_uint_eq(c.prim_id, 1);
    ck_assert_int_eq(ray_overlap_shape_all(s, TK_SPHERE(vec(10.25, 0.25, 1), 2), NULL, o, 2, &n), 1);
    ck_assert_uint_eq(o[0].prim_id, 1);
    ray_scene_free(s);
}
END_TEST

/*
** Issue 38, defect 7: an accepted transform with a row of about 2e-307
** (diag(1, 1, 2e-307): the child flattened onto z = 0) maps a query point
** 1e10 above it to an object-space z of 5e316, past DBL_MAX, and
** ray_closest_point with an infinite radius found nothing.  The world
** answer is plain: the triangle (-1,-1)-(1,-1)-(0,1) flattened stays
** where it is in x and y, so the nearest point to (0.2, 0.1, 1e10) is
** (0.2, 0.1, 0) (exactly: its z is 0 in the child), 1e10 away.  The same
** through a uniform scale of 2e-307 (a similarity) of a unit box: its
** image is the box of half-extent 2e-307, 1e10 from (0, 0, 1e10).  Tolerance: a few roundings of the mapped
** corners and of the distance, 8 ulps of the magnitudes (1e10, and 1).
*/
START_TEST(closest_points_should_be_found_where_q_maps_beyond_the_doubles)
{
    ray_scene *child, *boxes, *s;
    ray_transform flat = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 2e-307, 0}}};
    ray_transform tiny = {{{2e-307, 0, 0, 0}, {0, 2e-307, 0, 0},
                           {0, 0, 2e-307, 0}}};
    ray_box_params b;
    ray_closest c;

    ck_assert_int_eq(ray_scene_new(&child, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_triangle(child, vec(-1, -1, 0), vec(1, -1, 0), vec(0, 1, 0), RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_instance(s, child, &flat, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_closest_point(s, vec(0.2, 0.1, 1e10), HUGE_VAL, &c), 1);
    ck_assert_double_eq_tol(c.distance, 1e10, 8 * DBL_EPSILON * 1e10);
    ck_assert_double_eq_tol(c.p.x, 0.2, 8 * DBL_EPSILON);
    ck_assert_double_eq_tol(c.p.y, 0.1, 8 * DBL_EPSILON);
    ck_assert_double_eq_tol(c.p.z, 0, 8 * DBL_EPSILON);
    ck_assert_uint_eq(c.inst_id, 0);
    /* A finite radius that reaches it, and one that does not. */
    ck_assert_int_eq(ray_closest_point(s, vec(0.2, 0.1, 1e10), 2e10, &c), 1);
    ck_assert_int_eq(ray_closest_point(s, vec(0.2, 0.1, 1e10), 1e9, &c), 0);
    ray_scene_free(s);
    b.center = vec(0, 0, 0);
    b.half_extents = vec(1, 1, 1);
    b.axis_x = vec(1, 0, 0);
    b.axis_y = vec(0, 1, 0);
    ck_assert_int_eq(ray_scene_new(&boxes, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_box(boxes, &b, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(boxes), RAY_OK);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_instance(s, boxes, &tiny, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_closest_point(s, vec(0, 0, 1e10), HUGE_VAL, &c), 1);
    ck_assert_double_eq_tol(c.distance, 1e10, 8 * DBL_EPSILON * 1e10);
    /* The top and bottom faces are 4e-307 apart, 1e10 away: their
    ** distances round alike, so either may be reported (a tie). */
    ck_assert_double_eq_tol(fabs(c.p.z), 2e-307, 8 * DBL_EPSILON * 2e-307);
    ck_assert(fabs(c.p.x) <= 2e-307 && fabs(c.p.y) <= 2e-307);
    ray_scene_free(s);
    ray_scene_free(boxes);
    ray_scene_free(child);
}
END_TEST

/*
** Issue 38, defect 3: through a transform that is not a similarity the
** closest point's normal at a box corner must be that of a face whose
** plane the query point lies outside of (ray_closest_point(3): "the face
** whose plane q lies farthest outside of"), so that a push along n
** leaves the box.  A unit box through a shear with unequal scales (its
** faces meet at obtuse and acute angles); for each of the 8 corners C,
** query points q = C + sum_f l_f N_f with the three world normals N_f
** of its faces and weights l_f in {0.2, 1, 2.5}: q - C lies in the
** corner's normal cone, so C is q's nearest point and
** |q - C|^2 = sum_f l_f N_f.(q - C) > 0: some face has q outside it.
** Asserted: p is C (to 64 ulps of the coordinates, a few roundings of
** the mapped corner and of the triangle's nearest point) and
** n.(q - p) > 0.
*/
START_TEST(closest_normals_at_corners_should_face_the_query_point)
{
    static const double L[3][3] = {{1, 0.9, 0}, {0, 1, 0.7}, {0.3, 0, 2}};
    static const double w[3] = {0.2, 1, 2.5};
    ray_transform x = {{{1, 0.9, 0, 3}, {0, 1, 0.7, -2}, {0.3, 0, 2, 1}}};
    ray_box_params b;
    ray_scene *child, *s;
    double inv[3][3], det;
    int corner, i, j, k, l, bad = 0;

    /* L^-1 by cofactors: its columns are the world face normals
    ** (L^-T e_k). */
    det = L[0][0] * (L[1][1] * L[2][2] - L[1][2] * L[2][1]) -
          L[0][1] * (L[1][0] * L[2][2] - L[1][2] * L[2][0]) +
          L[0][2] * (L[1][0] * L[2][1] - L[1][1] * L[2][0]);
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            inv[j][i] = (L[(i + 1) % 3][(j + 1) % 3] * L[(i + 2) % 3][(j + 2) % 3] -
                         L[(i + 1) % 3][(j + 2) % 3] * L[(i + 2) % 3][(j + 1) % 3]) / det;
    b.center = vec(0, 0, 0);
    b.half_extents = vec(1, 1, 1);
    b.axis_x = vec(1, 0, 0);
    b.axis_y = vec(0, 1, 0);
    ck_assert_int_eq(ray_scene_new(&child, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_box(child, &b, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_instance(s, child, &x, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    for (corner = 0; corner < 8; corner++) {
        double c[3] = {corner & 1 ? 1 : -1, corner & 2 ? 1 : -1,
                       corner & 4 ? 1 : -1};
        double C[3], N[3][3];
        for (i = 0; i < 3; i++) {
            double len = 0;
            C[i] = x.m[i][3];
            for (j = 0; j < 3; j++)
                C[i] += L[i][j] * c[j];
            /* Face i's outward normal: sign c_i times column i of L^-1
            ** (row i of L^-T), normalised. */
            for (j = 0; j < 3; j++)
                N[i][j] = c[i] * inv[i][j];
            for (j = 0; j < 3; j++)
                len += N[i][j] * N[i][j];
            for (j = 0; j < 3; j++)
                N[i][j] /= sqrt(len);
        }
        for (k = 0; k < 27; k++) {
            double q[3], along = 0;
            ray_closest r;
            for (j = 0; j < 3; j++) {
                q[j] = C[j];
                for (l = 0; l < 3; l++)
                    q[j] += w[(k / (l == 0 ? 1 : l == 1 ? 3 : 9)) % 3] * N[l][j];
            }
            ck_assert_int_eq(ray_closest_point(s, vec(q[0], q[1], q[2]), HUGE_VAL, &r), 1);
            ck_assert_double_eq_tol(r.p.x, C[0], 64 * DBL_EPSILON * 8);
            ck_assert_double_eq_tol(r.p.y, C[1], 64 * DBL_EPSILON * 8);
            ck_assert_double_eq_tol(r.p.z, C[2], 64 * DBL_EPSILON * 8);
            along = r.n.x * (q[0] - r.p.x) + r.n.y * (q[1] - r.p.y) +
                    r.n.z * (q[2] - r.p.z);
            if (!(along > 0))
                bad++;
        }
    }
    ck_assert_msg(bad == 0, "%d of 216 normals face away from q", bad);
    ray_scene_free(s);
    ray_scene_free(child);
}
END_TEST

/* The largest error of ray_closest_point's distance to triangle abc, in
** units of DBL_EPSILON (M + d) (M the largest coordinate magnitude),
** over "points" query points within 3 of it (drawn from g), against the
** long-double brute force (ldgeom.h's ref_triangle on the same doubles). */
static double triangle_worst_error(ray_vec3 a, ray_vec3 b, ray_vec3 c,
                                   rng *g, int points)
{
    ray_scene *s;
    double worst = 0;
    int k;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_triangle(s, a, b, c, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    for (k = 0; k < points; k++) {
        double t = rng_unit(g), M, err;
        ray_vec3 q = vec(a.x + t * (b.x - a.x) + 3 * rng_range(g, -1, 1),
                         a.y + t * (b.y - a.y) + 3 * rng_range(g, -1, 1),
                         a.z + 3 * rng_range(g, -1, 1));
        ray_closest cl;
        lvec r = ref_triangle(lv(q), lv(a), lv(b), lv(c));
        ld d = ldist(lv(q), r);
        ck_assert_int_eq(ray_closest_point(s, q, HUGE_VAL, &cl), 1);
        M = fmax(fmax(fabs(q.x), fabs(q.y)), fmax(fabs(b.x), fabs(b.y)));
        M = fmax(M, fmax(fabs(c.x), fabs(c.y)));
        err = (double)fabsl((long double)cl.distance - d) / (DBL_EPSILON * (M + (double)d));
        worst = fmax(worst, err);
    }
    ray_scene_free(s);
    return worst;
}

/*
** A sliver thinner than its edges' rounding: corners (0, 0, 4e-270),
** the origin and (0, 0.5, 0.5), in the plane x = 0.  The foot of q =
** (22, 22, 22) on that plane, (0, 22, 22), lies on the line of the two
** long edges, beyond the corner (0, 0.5, 0.5), and passed both their
** edge tests (each rounds to 0): it was reported as the nearest point,
** 22 from q, though 30 from the triangle, and a sphere of radius 30
** about q met it (fuzz_live's finding, through a mesh refitted beside
** the same mesh built afresh).  The nearest point is that corner,
** |q - c| = sqrt(22^2 + 2 21.5^2); within 1e-12 relative: the distance
** of a point to a corner is a few roundings of a square root.
*/
START_TEST(closest_points_should_stay_on_slivers_thinner_than_rounding)
{
    const ray_vec3 a = {0, 0, 4.2589879266133596e-270}, b = {0, 0, 0};
    const ray_vec3 c = {0, 0.5, 0.5}, q = {22, 22, 22};
    const double want = sqrt(22.0 * 22.0 + 2 * 21.5 * 21.5);
    ray_overlap found[1];
    ray_closest got;
    ray_shape ball;
    ray_scene *s;
    size_t n;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_triangle(s, a, b, c, RAY_NO_MATERIAL,
                                            NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_closest_point(s, q, HUGE_VAL, &got), 1);
    ck_assert_double_eq_tol(got.distance, want, 1e-12 * want);
    ck_assert_double_eq_tol(got.p.y, 0.5, 1e-12);
    memset(&ball, 0, sizeof ball);
    ball.a = ball.b = q;
    ball.radius = 30;
    ck_assert_int_eq(ray_overlap_shape_all(s, &ball, NULL, found, 1, &n), 0);
    ray_scene_free(s);
}
END_TEST

/*
** Issue 38, defect 6: ray_closest_point on slivers.  Ericson's region
** walk divides determinants that cancel as sin^2 of the smallest angle:
** on a cap sliver 4e4 long and 0.003 wide its distance was off by 24.
** Needle slivers (c near b) and cap slivers (c near the middle of ab),
** 10 to 1e5 long and 1e-3 to 1e2 wide, 20,000 query points within 3 of
** them, against the long-double brute force (ldgeom.h's ref_triangle on
** the same doubles): the distance within 32 DBL_EPSILON (M + d), M the
** largest coordinate magnitude, the bound ray_closest_point(3) states
** for every triangle (the largest error measured is below 1).
*/
START_TEST(closest_points_on_slivers_should_keep_the_documented_bound)
{
    rng g = {0x51173u};
    double worst = 0;
    int it;

    for (it = 0; it < 400; it++) {
        double L = pow(10, 1 + 4 * rng_unit(&g)), w = pow(10, -3 + 5 * rng_unit(&g));
        ray_vec3 a = vec(rng_range(&g, -1, 1), rng_range(&g, -1, 1), rng_range(&g, -1, 1)), b, c;

        if (w > L / 16)
            w = L / 100;       /* keep it a sliver */
        b = vec(a.x + L * 0.8, a.y + L * 0.6, a.z + rng_range(&g, -1, 1));
        if (it % 2)             /* a cap: c beside the middle of ab */
            c = vec(a.x + L * 0.4 - w * 0.6, a.y + L * 0.3 + w * 0.8,
                    a.z + 0.5 * rng_range(&g, -1, 1));
        else                    /* a needle: c beside b */
            c = vec(b.x - w * 0.6, b.y + w * 0.8, b.z);
        worst = fmax(worst, triangle_worst_error(a, b, c, &g, 50));
    }
    ck_assert_msg(worst <= 32, "worst %g DBL_EPSILON (M + d)", worst);
}
END_TEST

/*
** The sliver test's quick answer (nearest.c: surely_not_sliver) at its
** edge: triangles whose smallest angle has sine 1/16 (1 + delta), delta
** within +-2^-18, where the quick test answers for some and leaves the
** others to the accurate one, and the accurate one takes either path;
** 200 triangles, 10 to 1e4 long, turned at random, 20 query points each
** within 3 of them, against the long-double brute force with the bound
** of the slivers' test above (the documented one).
*/
START_TEST(closest_points_at_the_sliver_threshold_should_keep_the_bound)
{
    rng g = {0x5117e2u};
    double worst = 0;
    int it;

    for (it = 0; it < 200; it++) {
        double L = pow(10, 1 + 3 * rng_unit(&g));
        double sn = (1 + 0x1p-18 * rng_range(&g, -1, 1)) / 16;
        double cs = sqrt(1 - sn * sn), phi = 6.283185307179586 * rng_unit(&g);
        ray_vec3 a = vec(rng_range(&g, -1, 1), rng_range(&g, -1, 1), rng_range(&g, -1, 1));
        ray_vec3 u = vec(cos(phi), sin(phi), 0), v = vec(-sin(phi), cos(phi), 0);
        ray_vec3 b = vec(a.x + L * u.x, a.y + L * u.y, a.z + 0.25);
        ray_vec3 c = vec(a.x + L * (cs * u.x + sn * v.x),
                         a.y + L * (cs * u.y + sn * v.y), a.z - 0.25);

        worst = fmax(worst, triangle_worst_error(a, b, c, &g, 20));
    }
    ck_assert_msg(worst <= 32, "worst %g DBL_EPSILON (M + d)", worst);
}
END_TEST

/*
** Issue 38, documented answers of ray_surface_point (its page): a mesh
** triangle of zero area has no surface point (RAY_EINVAL: no ray hits
** it, and no query finds it), and a plane's point whose p or error bound
** would not be finite (u = v = DBL_MAX along its tangents) is refused
** with RAY_EINVAL too; *hit is left untouched by both.  A plane point
** at (3, 4) from the plane's point lies on the plane (z = 0 within its
** p_err) 5 from it.
*/
START_TEST(surface_points_should_refuse_what_has_no_point)
{
    static const ray_vec3 v[6] = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0},
                                  {10, 0, 0}, {11, 0, 0}, {10, 1, 0}};
    static const unsigned idx[6] = {0, 1, 2, 3, 4, 5};
    ray_scene *s;
    ray_mesh m;
    ray_hit h, keep;
    unsigned mesh, plane;

    memset(&m, 0, sizeof m);
    m.vertices = v;
    m.vertex_count = 6;
    m.indices = idx;
    m.triangle_count = 2;
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, &mesh), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 0, 1), RAY_NO_MATERIAL, &plane), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    memset(&keep, 0x5a, sizeof keep);
    h = keep;
    ck_assert_int_eq(ray_surface_point(s, mesh, 0, RAY_INVALID_ID, 0.25, 0.25, &h), RAY_EINVAL);
    ck_assert(memcmp(&h, &keep, sizeof h) == 0);
    ck_assert_int_eq(ray_surface_point(s, plane, 0, RAY_INVALID_ID, DBL_MAX, DBL_MAX, &h), RAY_EINVAL);
    ck_assert(memcmp(&h, &keep, sizeof h) == 0);
    /* The proper ones. */
    ck_assert_int_eq(ray_surface_point(s, mesh, 1, RAY_INVALID_ID, 0.25, 0.25, &h), RAY_OK);
    ck_assert_int_eq(ray_surface_point(s, plane, 0, RAY_INVALID_ID, 3, 4, &h), RAY_OK);
    ck_assert(fabs(h.p.z) <= h.p_err.z);
    /* 5 from the plane's point: the tangents are unit within a few ulps
    ** (8 DBL_EPSILON of 5). */
    ck_assert_double_eq_tol(sqrt(h.p.x * h.p.x + h.p.y * h.p.y), 5, 8 * DBL_EPSILON * 5);
    ray_scene_free(s);
}
END_TEST

/*
** Issue 38, the rest of ray_surface_point's refusals (its page: RAY_EINVAL
** for ids that name nothing, removed geometry, an instance where geometry
** was asked for, (u, v) not finite or outside the primitive; RAY_ESTATE
** for an instance whose scene changed since the commit), each with *hit
** untouched: a triangle's barycentrics below 0 or a prim_id past its
** mesh; a sphere's (u, v) outside [0, 1] or a prim_id other than 0; a
** polygon's prim_id other than 0 or a point outside it; a plane point
** whose position overflows (u = DBL_MAX along a tangent from a point at
** 1e308); v NaN with u finite; the instance itself as geom_id; a removed
** instance; an instance whose child was committed again.  Then the good
** calls: a sphere's pole (v = 1: (0, 1, 0) from ray_sphere's v = acos(-n.y)
** / pi), y within its p_err, x and z within 1e-15 (sin(pi) in doubles),
** and the same point through an instance moved by (10, 0, 0).
*/
START_TEST(surface_points_should_refuse_bad_ids_and_coordinates)
{
    static const ray_vec3 tri[3] = {{0, 0, 5}, {1, 0, 5}, {0, 1, 5}};
    static const ray_vec3 sq[4] = {{0, 0, 7}, {1, 0, 7}, {1, 1, 7}, {0, 1, 7}};
    static const unsigned idx[3] = {0, 1, 2};
    ray_scene *s, *top;
    ray_transform t;
    ray_mesh m;
    ray_hit h, keep;
    unsigned mesh, ball, poly, plane, inst, gone;

    memset(&m, 0, sizeof m);
    m.vertices = tri;
    m.vertex_count = 3;
    m.indices = idx;
    m.triangle_count = 1;
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, &mesh), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1, RAY_NO_MATERIAL, &ball), RAY_OK);
    ck_assert_int_eq(ray_scene_add_polygon(s, sq, 4, RAY_NO_MATERIAL, &poly), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    memset(&keep, 0x5a, sizeof keep);
    h = keep;
#define REFUSED(call, rc)                                   \
    do {                                                    \
        ck_assert_int_eq(call, rc);                         \
        ck_assert(memcmp(&h, &keep, sizeof h) == 0);        \
    } while (0)
    REFUSED(ray_surface_point(s, mesh, 0, RAY_INVALID_ID, -0.25, 0.25, &h), RAY_EINVAL);
    REFUSED(ray_surface_point(s, mesh, 0, RAY_INVALID_ID, 0.25, -0.25, &h), RAY_EINVAL);
    REFUSED(ray_surface_point(s, mesh, 1, RAY_INVALID_ID, 0.25, 0.25, &h), RAY_EINVAL);
    REFUSED(ray_surface_point(s, mesh, 0, RAY_INVALID_ID, 0.25, (double)NAN, &h), RAY_EINVAL);
    REFUSED(ray_surface_point(s, ball, 0, RAY_INVALID_ID, -0.5, 0.5, &h), RAY_EINVAL);
    REFUSED(ray_surface_point(s, ball, 0, RAY_INVALID_ID, 1.5, 0.5, &h), RAY_EINVAL);
    REFUSED(ray_surface_point(s, ball, 0, RAY_INVALID_ID, 0.5, -0.5, &h), RAY_EINVAL);
    REFUSED(ray_surface_point(s, ball, 0, RAY_INVALID_ID, 0.5, 1.5, &h), RAY_EINVAL);
    REFUSED(ray_surface_point(s, ball, 1, RAY_INVALID_ID, 0.5, 0.5, &h), RAY_EINVAL);
    REFUSED(ray_surface_point(s, poly, 1, RAY_INVALID_ID, 0.5, 0.5, &h), RAY_EINVAL);
    REFUSED(ray_surface_point(s, poly, 0, RAY_INVALID_ID, 5, 5, &h), RAY_EINVAL);
    /* The proper ones: the sphere's pole, the polygon's inside. */
    ck_assert_int_eq(ray_surface_point(s, ball, 0, RAY_INVALID_ID, 0.5, 1, &h), RAY_OK);
    ck_assert(fabs(h.p.y - 1) <= h.p_err.y);
    /* sin(pi) rounds to 1.2e-16, not 0: the point found is that far from
    ** the pole (a point of the sphere, within p_err of an exact one). */
    ck_assert(fabs(h.p.x) <= 1e-15 && fabs(h.p.z) <= 1e-15);
    ck_assert_int_eq(ray_surface_point(s, poly, 0, RAY_INVALID_ID, 0.5, 0.5, &h), RAY_OK);
    ck_assert(fabs(h.p.z - 7) <= h.p_err.z);

    /* Instances: of a scene without planes (an instance takes none). */
    ck_assert_int_eq(ray_scene_new(&top, NULL, NULL), RAY_OK);
    ray_transform_identity(&t);
    t.m[0][3] = 10;
    ck_assert_int_eq(ray_scene_add_instance(top, s, &t, &inst), RAY_OK);
    ck_assert_int_eq(ray_scene_add_instance(top, s, &t, &gone), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    ck_assert_int_eq(ray_scene_remove(top, gone), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    memset(&keep, 0x5a, sizeof keep);
    h = keep;
    REFUSED(ray_surface_point(top, inst, 0, RAY_INVALID_ID, 0.5, 0.5, &h), RAY_EINVAL);
    REFUSED(ray_surface_point(top, ball, 0, gone, 0.5, 0.5, &h), RAY_EINVAL);
    ck_assert_int_eq(ray_surface_point(top, ball, 0, inst, 0.5, 1, &h), RAY_OK);
    ck_assert_uint_eq(h.inst_id, inst);
    ck_assert_uint_eq(h.geom_id, ball);
    ck_assert(fabs(h.p.y - 1) <= h.p_err.y);
    ck_assert(fabs(h.p.x - 10) <= 1e-14 && fabs(h.p.z) <= 1e-15);
    /* The child committed again: the instance is stale until top's
    ** next commit. */
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, -5), 1, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    h = keep;
    REFUSED(ray_surface_point(top, ball, 0, inst, 0.5, 0.5, &h), RAY_ESTATE);
    ray_scene_free(top);

    /* A plane point past DBL_MAX: from a point at 1e308 on the x axis,
    ** DBL_MAX along the tangent that ray_plane's frame gives for normal
    ** +z (u along x) overflows; -DBL_MAX comes back to -8e307, a finite
    ** point on the plane. */
    ck_assert_int_eq(ray_scene_add_plane(s, vec(1e308, 0, 0), vec(0, 0, 1), RAY_NO_MATERIAL, &plane), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    h = keep;
    REFUSED(ray_surface_point(s, plane, 0, RAY_INVALID_ID, DBL_MAX, 0, &h), RAY_EINVAL);
    ck_assert_int_eq(ray_surface_point(s, plane, 0, RAY_INVALID_ID, -DBL_MAX, 0, &h), RAY_OK);
    ck_assert(isfinite(h.p.x) && isfinite(h.p_err.x) && fabs(h.p.z) <= h.p_err.z);
#undef REFUSED
    ray_scene_free(s);
}
END_TEST

START_TEST(queries_should_share_the_scene_and_allocate_nothing)
{
    static closest_job ref, got[CLOSEST_THREADS];
    static ray_vec3 q[CLOSEST_POINTS];
    hc_mesh ball = hc_icosphere(vec(0, 0, 0), 2);
    ray_mesh mesh = hc_ray_mesh(&ball);
    pthread_t threads[CLOSEST_THREADS];
    ray_capsule_params cap = {{3, -1, 0}, {3, 1, 0}, 0.5};
    ray_scene *s;
    rng g = {4242};
    long calls = 0, after_commit;
    int i, k, found = 0;

    ck_assert_int_eq(ray_scene_new(&s, counted, &calls), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &mesh, RAY_NO_MATERIAL, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(-4, 0, 0), 1,
                                          RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_capsule(s, &cap, RAY_NO_MATERIAL, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    after_commit = calls;
    for (i = 0; i < CLOSEST_POINTS; i++)
        q[i] = rng_point(&g, -6, 6);
    ref.s = s;
    ref.q = q;
    closest_thread(&ref);
    for (k = 0; k < CLOSEST_THREADS; k++) {
        got[k].s = s;
        got[k].q = q;
        ck_assert_int_eq(pthread_create(&threads[k], NULL, closest_thread,
                                        &got[k]), 0);
    }
    for (k = 0; k < CLOSEST_THREADS; k++)
        ck_assert_int_eq(pthread_join(threads[k], NULL), 0);
    for (k = 0; k < CLOSEST_THREADS; k++) {
        ck_assert(memcmp(got[k].rc, ref.rc, sizeof ref.rc) == 0);
        ck_assert(memcmp(got[k].out, ref.out, sizeof ref.out) == 0);
    }
    for (i = 0; i < CLOSEST_POINTS; i++)
        found += ref.rc[i] == 1;
    /* Radius +Inf on every other point finds something; radius 1 on the
    ** others only near the geometry: both answers occur. */
    ck_assert_int_gt(found, CLOSEST_POINTS / 2);
    ck_assert_int_lt(found, CLOSEST_POINTS);
    ck_assert_int_eq(calls, after_commit);
    ray_scene_free(s);
    hc_mesh_free(&ball);
}
END_TEST

/*
** The nearest points of two segments whose lines come nearest beyond an
** end of one (src/prim/nearest.c, ray__segments_closest, under capsule
** closest points, overlaps and sweeps): P along x from 0 to 10, Q from
** (3, -2, 1) to (4, -0.5, 1).  The lines come nearest at Q's parameter
** 4/3, past q1; clamped to q1 = (4, -0.5, 1), P's point must be found
** again for q1, x = 4, not kept at the lines' x = 13/3.  Every value is a
** small binary fraction or its exact quotient's rounding, so within a few
** ulps of 4 (4 * DBL_EPSILON of slack, for the quotients' rounding).
** (make mutants' near-seg-clamp, t > 2 for t > 1: P's point was left at
** the lines' solution.)  The same from the other end, Q reversed.
*/
START_TEST(segments_nearest_beyond_an_end_should_clamp_both)
{
    const double tol = 4 * 4 * DBL_EPSILON;
    ray_vec3 ps, qs;

    ray__segments_closest(v3(0, 0, 0), v3(10, 0, 0), v3(3, -2, 1),
                          v3(4, -0.5, 1), &ps, &qs);
    ck_assert_double_eq_tol(qs.x, 4, tol);
    ck_assert_double_eq_tol(qs.y, -0.5, tol);
    ck_assert_double_eq_tol(ps.x, 4, tol);
    ck_assert_double_eq_tol(ps.y, 0, tol);
    ck_assert_double_eq_tol(ps.z, 0, tol);
    ray__segments_closest(v3(0, 0, 0), v3(10, 0, 0), v3(4, -0.5, 1),
                          v3(3, -2, 1), &ps, &qs);
    ck_assert_double_eq_tol(qs.x, 4, tol);
    ck_assert_double_eq_tol(ps.x, 4, tol);
}
END_TEST

Suite *closest_suite(void)
{
    Suite *s = suite_create("closest");
    TCase *tc = tcase_create("core");

    tcase_set_timeout(tc, 120);
    tcase_add_loop_test(tc, should_match_brute_force, 0, N_OFFSETS);
    tcase_add_test(tc, radius_should_bound_the_search);
    tcase_add_test(tc, radius_found_should_find_the_point_again);
    tcase_add_loop_test(tc, should_find_points_on_the_surface, 0, N_OFFSETS);
    tcase_add_test(tc, should_answer_inside_and_far_beyond);
    tcase_add_test(tc, empty_scenes_should_find_nothing);
    tcase_add_test(tc, misuse_should_be_refused);
    tcase_add_test(tc, closest_points_should_be_exact_through_any_transform);
    tcase_add_test(tc, closest_points_should_keep_their_radius_through_far_instances);
    tcase_add_test(tc, closest_points_should_find_ellipsoids);
    tcase_add_test(tc, queries_should_share_the_scene_and_allocate_nothing);
    tcase_add_test(tc, zero_area_triangles_should_be_skipped_by_every_query);
    tcase_add_test(tc, closest_points_should_be_found_where_q_maps_beyond_the_doubles);
    tcase_add_test(tc, closest_normals_at_corners_should_face_the_query_point);
    tcase_add_test(tc, closest_points_on_slivers_should_keep_the_documented_bound);
    tcase_add_test(tc, closest_points_at_the_sliver_threshold_should_keep_the_bound);
    tcase_add_test(tc, closest_points_should_stay_on_slivers_thinner_than_rounding);
    tcase_add_test(tc, surface_points_should_refuse_what_has_no_point);
    tcase_add_test(tc, surface_points_should_refuse_bad_ids_and_coordinates);
    tcase_add_test(tc, segments_nearest_beyond_an_end_should_clamp_both);
    suite_add_tcase(s, tc);
    return s;
}
