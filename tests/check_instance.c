/* SPDX-License-Identifier: MIT */
/*
** check_instance.c -- instances (ray_scene_add_instance): the same answers
** as the geometry flattened into world space, bit for bit through an
** identity transform; normals by the inverse transpose; no leaks and no
** self-hits through rotations, scales and offsets of 1e5; the child's
** materials and effects; moving an instance; a child changed under its
** parent; bad input refused with nothing added.
*/
#include <string.h>
#include <stdlib.h>

#include "tests.h"
#include "hardcases.h"

/* Rotation by angle a about the unit axis u, scaled by s, then moved by
** c (Rodrigues' formula). */
static ray_transform xfm_make(ray_vec3 u, double a, double s, ray_vec3 c)
{
    double co = cos(a), si = sin(a), k = 1 - co;
    ray_transform t;

    t.m[0][0] = s * (co + u.x * u.x * k);
    t.m[0][1] = s * (u.x * u.y * k - u.z * si);
    t.m[0][2] = s * (u.x * u.z * k + u.y * si);
    t.m[1][0] = s * (u.y * u.x * k + u.z * si);
    t.m[1][1] = s * (co + u.y * u.y * k);
    t.m[1][2] = s * (u.y * u.z * k - u.x * si);
    t.m[2][0] = s * (u.z * u.x * k - u.y * si);
    t.m[2][1] = s * (u.z * u.y * k + u.x * si);
    t.m[2][2] = s * (co + u.z * u.z * k);
    t.m[0][3] = c.x;
    t.m[1][3] = c.y;
    t.m[2][3] = c.z;
    return t;
}

static ray_vec3 vnorm(ray_vec3 v)
{
    return vscale(v, 1 / vlen(v));
}

static ray_vec3 xfm_point(const ray_transform *t, ray_vec3 p)
{
    return vec(t->m[0][0] * p.x + t->m[0][1] * p.y + t->m[0][2] * p.z +
                   t->m[0][3],
               t->m[1][0] * p.x + t->m[1][1] * p.y + t->m[1][2] * p.z +
                   t->m[1][3],
               t->m[2][0] * p.x + t->m[2][1] * p.y + t->m[2][2] * p.z +
                   t->m[2][3]);
}

/* A committed child: the level-2 icosphere of radius 2 at the origin
** (geometry 0), a sphere of radius 0.5 at (4, 0, 0) (1) and a box at
** (-4, 0, 0) (2), all RAY_NO_MATERIAL. */
static ray_scene *child_scene(hc_mesh *ball)
{
    ray_box_params b;
    ray_mesh m;
    ray_scene *s;

    *ball = hc_icosphere(vec(0, 0, 0), 2);
    m = hc_ray_mesh(ball);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(4, 0, 0), 0.5, RAY_NO_MATERIAL, NULL), RAY_OK);
    memset(&b, 0, sizeof b);
    b.center = vec(-4, 0, 0);
    b.axis_x = vec(1, 0, 0);
    b.axis_y = vec(0, 1, 0);
    b.half_extents = vec(0.5, 0.7, 0.9);
    ck_assert_int_eq(ray_scene_add_box(s, &b, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    return s;
}

/* A random ray through the child's region from 20 away. */
static ray_ray child_ray(rng *g, ray_vec3 c)
{
    ray_vec3 target = vadd(c, vec(rng_range(g, -5, 5), rng_range(g, -2.5, 2.5),
                                  rng_range(g, -2.5, 2.5)));
    ray_vec3 from = vadd(target, vscale(rng_dir(g), 20));
    return ray_from(from, vsub(target, from));
}

/*
** Through an identity transform every answer is the child's own, bit for
** bit (t, p, n, u, v, ids), but for inst_id and a p_err that only grows
** (ray.h): the ray is moved by exact operations (x - 0, 1 x + 0 y + 0 z).
*/
START_TEST(identity_instance_should_answer_as_the_child)
{
    hc_mesh ball;
    ray_scene *child = child_scene(&ball), *top;
    ray_transform id;
    rng g = {11};
    unsigned inst;
    int i, hits = 0;

    ray_transform_identity(&id);
    ck_assert_int_eq(ray_scene_new(&top, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_instance(top, child, &id, &inst), RAY_OK);
    ck_assert_uint_eq(inst, 0);
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    for (i = 0; i < 4000; i++) {
        ray_ray r = child_ray(&g, vec(0, 0, 0));
        ray_hit a, b;
        int ha = ray_intersect(child, &r, &a, NULL),
            hb = ray_intersect(top, &r, &b, NULL);
        ck_assert_int_eq(ha, hb);
        ck_assert_int_eq(ray_occluded(child, &r, NULL),
                         ray_occluded(top, &r, NULL));
        if (ha != 1)
            continue;
        hits++;
        ck_assert(memcmp(&a.t, &b.t, sizeof a.t) == 0);
        ck_assert(memcmp(&a.p, &b.p, sizeof a.p) == 0);
        ck_assert(memcmp(&a.n, &b.n, sizeof a.n) == 0);
        ck_assert(a.u == b.u && a.v == b.v);
        ck_assert_uint_eq(a.geom_id, b.geom_id);
        ck_assert_uint_eq(a.prim_id, b.prim_id);
        ck_assert_uint_eq(a.inst_id, RAY_INVALID_ID);
        ck_assert_uint_eq(b.inst_id, inst);
        ck_assert(b.p_err.x >= a.p_err.x && b.p_err.y >= a.p_err.y &&
                  b.p_err.z >= a.p_err.z);
    }
    ck_assert_int_gt(hits, 1000);
    ray_scene_free(top);
    ray_scene_free(child);
    hc_mesh_free(&ball);
}
END_TEST

/*
** A child of triangles alone goes straight to its triangles
** (traverse.h's query_child, issue 36), and an ungated nearest query
** makes the record of its nearest instance hit alone, once, at the end
** (instance_nearest); one with other kinds too through the general
** query, which makes every instance hit's record as it meets it.  Two
** such children, the same icosphere (the second
** with a tiny sphere far off that no ray reaches, geometry 1), each
** placed by the same six overlapping turned instances (one of them
** hidden by its mask for the gated query): every query answers the same
** bits in both -- nearest, gated, any, all hits and batches -- and the
** nearest is all-hits' first, wherever the instances met first are not
** the nearest.
*/
START_TEST(child_of_triangles_should_answer_as_the_general_query)
{
    hc_mesh ball = hc_icosphere(vec(0, 0, 0), 2);
    ray_mesh m = hc_ray_mesh(&ball);
    ray_scene *child[2], *top[2];
    ray_query q = {.ignore_mask = 0x2u};
    ray_ray rays[64];
    ray_hit all[2][8], batch[2][64];
    int res[2][64];
    rng g = {36};
    int i, j, k, hits = 0, beaten = 0;

    for (k = 0; k < 2; k++) {
        ck_assert_int_eq(ray_scene_new(&child[k], NULL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_mesh(child[k], &m, RAY_NO_MATERIAL,
                                            NULL), RAY_OK);
        if (k == 1)
            ck_assert_int_eq(ray_scene_add_sphere(child[k], vec(60, 0, 0),
                                                  0.01, RAY_NO_MATERIAL,
                                                  NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_commit(child[k]), RAY_OK);
        ck_assert_int_eq(ray_scene_new(&top[k], NULL, NULL), RAY_OK);
        for (i = 0; i < 6; i++) {
            ray_transform x;
            double a = 0.9 * i + 0.3, c = cos(a), s = sin(a);
            ray_transform_identity(&x);
            x.m[0][0] = c;
            x.m[0][1] = -s;
            x.m[1][0] = s;
            x.m[1][1] = c;
            x.m[0][3] = 0.7 * i - 1.75;
            x.m[1][3] = 0.3 * (i % 3);
            x.m[2][3] = 0.2 * i;
            ck_assert_int_eq(ray_scene_add_instance(top[k], child[k], &x,
                                                    NULL), RAY_OK);
        }
        ck_assert_int_eq(ray_scene_set_mask(top[k], 2, 0x2u), RAY_OK);
        ck_assert_int_eq(ray_scene_commit(top[k]), RAY_OK);
    }
    for (j = 0; j < 3000; j++) {
        ray_ray r = child_ray(&g, vec(0, 0, 0));
        ray_hit h[2], hq[2];
        size_t n[2];
        int hit[2], gated[2], any[2], na[2];
        for (k = 0; k < 2; k++) {
            hit[k] = ray_intersect(top[k], &r, &h[k], NULL);
            gated[k] = ray_intersect(top[k], &r, &hq[k], &q);
            any[k] = ray_occluded(top[k], &r, NULL);
            na[k] = ray_intersect_all(top[k], &r, NULL, all[k], 8, &n[k]);
        }
        ck_assert_int_eq(hit[0], hit[1]);
        ck_assert_int_eq(gated[0], gated[1]);
        ck_assert_int_eq(any[0], any[1]);
        ck_assert_int_eq(any[0], hit[0]);
        ck_assert_int_eq(na[0], na[1]);
        ck_assert_int_eq(na[0] > 0, hit[0]);
        if (hit[0] == 1) {
            hits++;
            ck_assert_msg(hit_same(&h[0], &h[1]), "ray %d", j);
            ck_assert_msg(hit_same(&h[0], &all[0][0]), "ray %d", j);
            ck_assert_msg(hit_same(&all[1][0], &all[0][0]), "ray %d", j);
            ck_assert_uint_eq(h[0].geom_id, 0);
            /* Another instance hit farther along: met first or not. */
            for (i = 1; i < na[0] && i < 8; i++)
                if (all[0][i].inst_id != h[0].inst_id) {
                    beaten++;
                    break;
                }
        }
        if (gated[0] == 1) {
            ck_assert_msg(hit_same(&hq[0], &hq[1]), "ray %d", j);
            ck_assert_uint_ne(hq[0].inst_id, 2);
        }
        rays[j % 64] = r;
        if (j % 64 == 63) {
            for (k = 0; k < 2; k++) {
                ray_batch b = {0};
                b.rays = rays;
                b.n = 64;
                b.hits = batch[k];
                b.results = res[k];
                ck_assert_int_eq(ray_intersect_batch(top[k], &b), RAY_OK);
            }
            for (i = 0; i < 64; i++) {
                ck_assert_int_eq(res[0][i], res[1][i]);
                if (res[0][i] == 1)
                    ck_assert_msg(hit_same(&batch[0][i], &batch[1][i]),
                                  "ray %d", i);
            }
        }
    }
    ck_assert_int_gt(hits, 1000);
    ck_assert_int_gt(beaten, 300);
    for (k = 0; k < 2; k++) {
        ray_scene_free(top[k]);
        ray_scene_free(child[k]);
    }
    hc_mesh_free(&ball);
}
END_TEST

/*
** An instance rotated, scaled by 1.5 and moved (to 0 or 1e5) against the
** same geometry flattened: the icosphere's vertices and the sphere's
** centre put through the transform, radius scaled.  Rays aimed at points
** well inside triangles (barycentrics >= 0.1) and at the sphere's middle
** hit the same primitive in both; t agrees within 2^12 ulps of the
** coordinates' magnitude over the direction's length: the two compute
** from differently rounded inputs (transformed vertices vs a transformed
** ray), each some dozens of roundings, amplified near grazing angles.
*/
START_TEST(instance_should_match_flattened_geometry)
{
    double off = test_offset(_i);
    ray_transform xf = xfm_make(vnorm(vec(1, 2, 3)), 0.7, 1.5,
                                vec(off, off * 0.5, -off));
    hc_mesh ball;
    ray_scene *child = child_scene(&ball), *top, *flat;
    ray_vec3 *wv = malloc(ball.nv * sizeof *wv);
    ray_vec3 centre = xfm_point(&xf, vec(4, 0, 0));
    ray_mesh m = hc_ray_mesh(&ball);
    ray_box_params box;
    rng g = {12};
    size_t k;
    int i;

    for (k = 0; k < ball.nv; k++)
        wv[k] = xfm_point(&xf, ball.v[k]);
    m.vertices = wv;
    ck_assert_int_eq(ray_scene_new(&flat, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(flat, &m, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(flat, centre, 0.75, RAY_NO_MATERIAL, NULL), RAY_OK);
    memset(&box, 0, sizeof box);
    box.center = xfm_point(&xf, vec(-4, 0, 0));
    box.axis_x = vsub(xfm_point(&xf, vec(1, 0, 0)), xfm_point(&xf, vec(0, 0, 0)));
    box.axis_y = vsub(xfm_point(&xf, vec(0, 1, 0)), xfm_point(&xf, vec(0, 0, 0)));
    box.half_extents = vec(0.75, 1.05, 1.35);   /* 1.5 x the child's */
    ck_assert_int_eq(ray_scene_add_box(flat, &box, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(flat), RAY_OK);
    ck_assert_int_eq(ray_scene_new(&top, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_instance(top, child, &xf, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    for (i = 0; i < 3000; i++) {
        double b1 = rng_range(&g, 0.1, 0.8), b2 = rng_range(&g, 0.1, 0.9 - b1);
        size_t tri = (size_t)(rng_unit(&g) * (double)ball.nt);
        const unsigned *t = ball.idx + 3 * tri;
        ray_vec3 target = i % 4 == 0
            ? centre
            : vadd(vadd(vscale(wv[t[0]], 1 - b1 - b2), vscale(wv[t[1]], b1)),
                   vscale(wv[t[2]], b2));
        ray_vec3 from = vadd(target, vscale(rng_dir(&g), 30));
        ray_ray r = ray_from(from, vsub(target, from));
        ray_hit a, b;
        double tol = 4096 * DBL_EPSILON * (fabs(off) + 40) / vlen(r.dir);
        ck_assert_int_eq(ray_intersect(flat, &r, &a, NULL), 1);
        ck_assert_int_eq(ray_intersect(top, &r, &b, NULL), 1);
        /* Child geometry 0 is the mesh, 1 the sphere, 2 the box, as in
        ** flat. */
        ck_assert_uint_eq(a.geom_id, b.geom_id);
        ck_assert_uint_eq(a.prim_id, b.prim_id);
        ck_assert_double_eq_tol(a.t, b.t, tol);
        ck_assert_vec_eq_tol(a.p, b.p, tol * vlen(r.dir) + 1e-300);
        /* Normals: the same plane or sphere, unit, to 1e-12 (a few
        ** roundings of unit vectors, plus the inverse transpose) plus
        ** what rounding the flattened vertices to doubles near "off"
        ** turns the face normal by: 64 ulps of off over the shortest
        ** edge (0.5 at this size). */
        ck_assert_vec_eq_tol(a.n, b.n, 1e-12 + 64 * DBL_EPSILON * fabs(off) / 0.5);
    }
    ray_scene_free(top);
    ray_scene_free(flat);
    ray_scene_free(child);
    hc_mesh_free(&ball);
    free(wv);
}
END_TEST

/*
** Closest points through instances: the icosphere child placed rotated,
** scaled by 1.5 and moved (a similarity: distances scale alike), against
** the same geometry flattened, for random points near, inside and far:
** the same distance within 2^12 ulps of the coordinates' magnitude (the
** two round differently, as in the test above), the same primitive where
** the two nearest are not near-ties, and the instance named.  Through a
** non-uniform scale the answer is a surface point within the radius.
*/
START_TEST(closest_points_should_come_through_instances)
{
    double off = test_offset(_i);
    ray_transform xf = xfm_make(vnorm(vec(1, -1, 2)), 1.1, 1.5,
                                vec(off, 2 * off, -off));
    hc_mesh ball = hc_icosphere(vec(0, 0, 0), 2);
    ray_vec3 *wv = malloc(ball.nv * sizeof *wv);
    ray_mesh m = hc_ray_mesh(&ball);
    ray_scene *child, *top, *flat;
    unsigned inst;
    rng g = {15};
    size_t k;
    int i;

    ck_assert_int_eq(ray_scene_new(&child, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(child, &m, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    for (k = 0; k < ball.nv; k++)
        wv[k] = xfm_point(&xf, ball.v[k]);
    m.vertices = wv;
    ck_assert_int_eq(ray_scene_new(&flat, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(flat, &m, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(flat), RAY_OK);
    ck_assert_int_eq(ray_scene_new(&top, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_instance(top, child, &xf, &inst), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    for (i = 0; i < 2000; i++) {
        double reach = i % 3 == 0 ? 2 : i % 3 == 1 ? 6 : 100;
        ray_vec3 q = xfm_point(&xf, vscale(rng_dir(&g), reach * rng_unit(&g)));
        double tol = 4096 * DBL_EPSILON * (fabs(off) * 3 + reach + 10);
        ray_closest a, b;
        ck_assert_int_eq(ray_closest_point(flat, q, HUGE_VAL, &a), 1);
        ck_assert_int_eq(ray_closest_point(top, q, HUGE_VAL, &b), 1);
        ck_assert_double_eq_tol(a.distance, b.distance, tol);
        ck_assert_uint_eq(b.inst_id, inst);
        ck_assert_uint_eq(a.inst_id, RAY_INVALID_ID);
        ck_assert_double_eq_tol(vdist(b.p, q), b.distance, tol);
        /* A radius just short of the distance finds nothing nearer. */
        if (b.distance > 1e-3)
            ck_assert_int_eq(ray_closest_point(top, q, b.distance * (1 - 1e-9) - tol, &a), 0);
    }
    /* A non-uniform scale: still a point of the surface within radius. */
    xf.m[0][0] *= 3;
    xf.m[1][0] *= 3;
    xf.m[2][0] *= 3;
    ck_assert_int_eq(ray_scene_set_transform(top, inst, &xf), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    for (i = 0; i < 200; i++) {
        ray_vec3 q = xfm_point(&xf, vscale(rng_dir(&g), 6 * rng_unit(&g)));
        ray_closest b;
        ck_assert_int_eq(ray_closest_point(top, q, HUGE_VAL, &b), 1);
        ck_assert(b.distance < HUGE_VAL);
        ck_assert_double_eq_tol(vdist(b.p, q), b.distance, 1e-9);
    }
    ray_scene_free(top);
    ray_scene_free(flat);
    ray_scene_free(child);
    hc_mesh_free(&ball);
    free(wv);
}
END_TEST

/*
** Normals go by the inverse transpose: a unit sphere scaled by (2, 1, 1)
** is the ellipsoid x^2/4 + y^2 + z^2 = 1, whose normal at p is along
** (x/4, y, z).  To 1e-12: unit vectors after a few dozen roundings.
*/
START_TEST(normals_should_follow_the_inverse_transpose)
{
    ray_scene *child, *top;
    ray_transform xf;
    rng g = {13};
    int i;

    ck_assert_int_eq(ray_scene_new(&child, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(child, vec(0, 0, 0), 1, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    ray_transform_identity(&xf);
    xf.m[0][0] = 2;
    ck_assert_int_eq(ray_scene_new(&top, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_instance(top, child, &xf, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    for (i = 0; i < 1000; i++) {
        ray_vec3 from = vscale(rng_dir(&g), 10), want;
        ray_ray r = ray_from(from, vsub(vec(rng_range(&g, -1, 1), rng_range(&g, -0.5, 0.5), 0), from));
        ray_hit h;
        if (ray_intersect(top, &r, &h, NULL) != 1)
            continue;
        want = vnorm(vec(h.p.x / 4, h.p.y, h.p.z));
        ck_assert_vec_eq_tol(h.n, want, 1e-12);
        /* On the ellipsoid, to the error bound's scale. */
        ck_assert_double_eq_tol(h.p.x * h.p.x / 4 + h.p.y * h.p.y + h.p.z * h.p.z, 1.0, 1e-12);
    }
    ray_scene_free(top);
    ray_scene_free(child);
}
END_TEST

/*
** Zero leaks through instances: rays from inside the closed icosphere,
** instanced rotated and scaled at 0 and 1e5, aimed exactly at the world
** images of its vertices and edge midpoints, all hit it (the watertight
** test in the child's space sees one consistent ray).
*/
START_TEST(closed_mesh_should_not_leak_through_an_instance)
{
    double off = test_offset(_i);
    ray_transform xf = xfm_make(vnorm(vec(-2, 1, 0.5)), 2.1, 0.75,
                                vec(off, -off, off * 0.25));
    hc_mesh ball = hc_icosphere(vec(0, 0, 0), 2);
    ray_mesh m = hc_ray_mesh(&ball);
    ray_scene *child, *top;
    ray_vec3 inside = xfm_point(&xf, vec(0.1, -0.2, 0.05));
    size_t k, lost = 0, rays = 0;

    ck_assert_int_eq(ray_scene_new(&child, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(child, &m, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    ck_assert_int_eq(ray_scene_new(&top, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_instance(top, child, &xf, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    for (k = 0; k < 3 * ball.nt; k++) {
        const unsigned *t = ball.idx + 3 * (k / 3);
        ray_vec3 a = ball.v[t[k % 3]], b = ball.v[t[(k + 1) % 3]];
        ray_vec3 targets[2];
        int j;
        targets[0] = xfm_point(&xf, a);
        targets[1] = xfm_point(&xf, vscale(vadd(a, b), 0.5));
        for (j = 0; j < 2; j++) {
            ray_ray r = ray_from(inside, vsub(targets[j], inside));
            ray_hit h;
            rays++;
            lost += ray_intersect(top, &r, &h, NULL) != 1;
            lost += ray_occluded(top, &r, NULL) != 1;
        }
    }
    ck_assert_uint_eq(lost, 0);
    ck_assert_uint_gt(rays, 1000);
    ray_scene_free(top);
    ray_scene_free(child);
    hc_mesh_free(&ball);
}
END_TEST

/*
** No acne through instances: a floor quad (two triangles, y = 0, 200
** wide) in the child, instanced rotated and moved to 0 and 1e5; camera
** rays at 0.05 to 80 degrees hit it, and the shadow and reflection rays
** ray_spawn sends from those world hits never meet it again (a flat
** surface: any hit is a self-hit).  Through the rotation and translation
** the hit point's world error bound must cover both transforms' rounding
** (instance.c), or these rays start inside the floor's rounding.
*/
START_TEST(spawned_rays_should_not_self_hit_through_an_instance)
{
    static const ray_vec3 quad[4] = {{-100, 0, -100}, {100, 0, -100},
                                     {100, 0, 100}, {-100, 0, 100}};
    static const unsigned idx[6] = {0, 2, 1, 0, 3, 2};
    double off = test_offset(_i);
    ray_transform xf = xfm_make(vnorm(vec(0.3, 1, -0.2)), 0.4, 1.0,
                                vec(off, 0.5 * off, off));
    ray_mesh m;
    ray_scene *child, *top;
    ray_vec3 up = vnorm(vsub(xfm_point(&xf, vec(0, 1, 0)), xfm_point(&xf, vec(0, 0, 0))));
    ray_vec3 light = xfm_point(&xf, vec(3, 6, 4));
    rng g = {14};
    int i, hits = 0, self = 0;

    memset(&m, 0, sizeof m);
    m.vertices = quad;
    m.vertex_count = 4;
    m.indices = idx;
    m.triangle_count = 2;
    ck_assert_int_eq(ray_scene_new(&child, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(child, &m, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    ck_assert_int_eq(ray_scene_new(&top, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_instance(top, child, &xf, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    for (i = 0; i < 4000; i++) {
        const double deg = 3.14159265358979323846 / 180;
        double el = (i % 2 ? 20 + 60 * rng_unit(&g) : 0.05 + 2.95 * rng_unit(&g)) * deg;
        double az = 6.283185307179586 * rng_unit(&g);
        double reach = i % 4 < 2 ? 4 : 90;
        ray_vec3 local = vec((2 * rng_unit(&g) - 1) * reach, 0,
                             (2 * rng_unit(&g) - 1) * reach);
        ray_vec3 target = xfm_point(&xf, local);
        ray_vec3 eye = xfm_point(&xf, vadd(local, vec(24 * cos(el) * cos(az), 24 * sin(el),
                                                     24 * cos(el) * sin(az))));
        ray_ray r = ray_from(eye, vsub(target, eye)), s;
        ray_hit h;
        if (ray_intersect(top, &r, &h, NULL) != 1)
            continue;
        hits++;
        ck_assert_double_gt(vdot(h.n, up) * vdot(h.n, up), 1 - 1e-12);
        if (ray_spawn_to(&h, light, &s) == RAY_OK)
            self += ray_occluded(top, &s, NULL) == 1;
        if (ray_spawn(&h, ray_reflect(r.dir, h.n), &s) == RAY_OK)
            self += ray_intersect(top, &s, &h, NULL) == 1;
    }
    ck_assert_int_gt(hits, 3000);
    ck_assert_int_eq(self, 0);
    ray_scene_free(top);
    ray_scene_free(child);
}
END_TEST

/*
** The size of the world error bound, not only its effect (issue 29: a
** looser or tighter bound passes the self-hit test above).  A sphere of
** radius 1 at the child's origin, instanced by L = a cyclic permutation
** with the non-uniform scales 2, 1/4 and 4 (x' = 2y, y' = z/4, z' = 4x;
** not symmetric, so a transposed index shows) and a large translation
** c = (1e5, -3e4, 7e4).  Powers of two make L^-1 exact, so the library's
** object-space ray is the test's bit for bit and the child's own hit
** (ray_intersect on the child) is the instance's: t equal, p = L p' + c.
** The bound must then be instance.c's formula (pbrt-v4's ApplyError,
** ray.h "p_err"), per axis k:
**   B_k = (1 + gamma(2)) * ( |L| e' + gamma(4) (|L| |p'| + |c|)
**                           + |L| gamma(5) |L^-1| (|w| + |c|) )_k,
** computed here in long double from the hits' own fields.  Margin: the
** library sums in double, so B_k within 8 ulps of B_k (8 u relative);
** any slip of a gamma's index moves it by u / 14 u or more of the
** dominant terms (gamma(5) -> gamma(4) in the return term: 2u |c| of
** 14u |c|, some 14%), dropping the carried term moves it by e' / B ~
** 1e-5, and a transposed |L| or |L^-1| by a factor of the scales.  The
** test checks its own margin: each term it could lose is above it.
*/
static long double gam(int n)
{
    long double u = (long double)DBL_EPSILON / 2;
    return n * u / (1 - n * u);
}

START_TEST(world_error_bound_should_be_the_documented_one)
{
    static const double L[3][3] = {{0, 2, 0}, {0, 0, 0.25}, {4, 0, 0}};
    static const double Linv[3][3] = {{0, 0, 0.25}, {0.5, 0, 0}, {0, 4, 0}};
    const double c[3] = {1e5, -3e4, 7e4};
    /* Object-space rays (origin, direction): oblique, from outside. */
    static const double rays[3][6] = {{3, 0.25, -0.5, -1, 0.125, 0.1875},
                                      {-0.75, 2.5, 1.25, 0.25, -1, -0.375},
                                      {0.5, -0.5, 3.5, -0.0625, 0.125, -1}};
    ray_transform xf;
    ray_scene *child, *top;
    int i, j, k;

    for (i = 0; i < 3; i++) {
        for (j = 0; j < 3; j++)
            xf.m[i][j] = L[i][j];
        xf.m[i][3] = c[i];
    }
    ck_assert_int_eq(ray_scene_new(&child, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(child, vec(0, 0, 0), 1,
                                          RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    ck_assert_int_eq(ray_scene_new(&top, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_instance(top, child, &xf, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    for (i = 0; i < 3; i++) {
        double o[3], d[3];
        ray_ray ro, rw;
        ray_hit ho, hw;

        ro = ray_from(vec(rays[i][0], rays[i][1], rays[i][2]),
                      vec(rays[i][3], rays[i][4], rays[i][5]));
        /* World ray: o = L o' + c, d = L d', exact (powers of two, one
        ** non-zero term a row, c's last bits free). */
        for (k = 0; k < 3; k++) {
            o[k] = L[k][0] * ro.org.x + L[k][1] * ro.org.y +
                   L[k][2] * ro.org.z + c[k];
            d[k] = L[k][0] * ro.dir.x + L[k][1] * ro.dir.y +
                   L[k][2] * ro.dir.z;
        }
        rw = ray_from(vec(o[0], o[1], o[2]), vec(d[0], d[1], d[2]));
        ck_assert_int_eq(ray_intersect(child, &ro, &ho, NULL), 1);
        ck_assert_int_eq(ray_intersect(top, &rw, &hw, NULL), 1);
        ck_assert_double_eq(hw.t, ho.t);           /* the same object ray */
        for (k = 0; k < 3; k++) {
            const double *pp = &ho.p.x, *ep = &ho.p_err.x, *wp = &hw.p.x,
                         *got = &hw.p_err.x;
            long double carried = 0, fwd = 0, ret = 0, want;
            int jj;

            for (j = 0; j < 3; j++) {
                long double back = 0;
                carried += fabsl((long double)L[k][j]) * (long double)ep[j];
                fwd += fabsl((long double)L[k][j]) * fabsl((long double)pp[j]);
                for (jj = 0; jj < 3; jj++)
                    back += fabsl((long double)Linv[j][jj]) *
                            (fabsl((long double)wp[jj]) + fabsl((long double)c[jj]));
                ret += fabsl((long double)L[k][j]) * gam(5) * back;
            }
            fwd = gam(4) * (fwd + fabsl((long double)c[k]));
            want = (carried + fwd + ret) * (1 + gam(2));
            /* The margin, and the test's power to see each term. */
            ck_assert_msg(fabsl((long double)got[k] - want) <= 8 * gam(1) * want,
                          "ray %d axis %d: p_err %.17g, the rule gives %.17Lg",
                          i, k, got[k], want);
            ck_assert(carried > 64 * gam(1) * want);
            ck_assert(gam(1) * fabsl((long double)c[k]) > 64 * gam(1) * want);
        }
    }
    ray_scene_free(top);
    ray_scene_free(child);
}
END_TEST

/* A material that shades its ud's colour. */
static void flat_colour(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                        ray_rgb *out)
{
    (void)ctx;
    (void)a;
    *out = *(const ray_rgb *)ud;
}

/*
** Rendering through instances: each hit shades with the child's material
** (two children, two colours); the parent's effects include the
** children's materials' (a reflective child makes the parent's
** REFLECTION bit); a disabled instance is not seen.
*/
START_TEST(instances_should_shade_with_their_child_materials)
{
    static ray_rgb red = {1, 0, 0}, blue = {0, 0, 1};
    ray_material mr = {flat_colour, &red, RAY_EFFECT_REFLECTION, NULL};
    ray_material mb = {flat_colour, &blue, 0, NULL};
    ray_scene *c1, *c2, *top;
    ray_transform a, b;
    ray_ctx *ctx;
    ray_ray r1 = ray_from(vec(-3, 0, 10), vec(0, 0, -1));
    ray_ray r2 = ray_from(vec(3, 0, 10), vec(0, 0, -1));
    ray_rgb c;
    unsigned m, i1, i2;

    ck_assert_int_eq(ray_scene_new(&c1, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(c1, &mr, &m), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(c1, vec(0, 0, 0), 1, m, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(c1), RAY_OK);
    ck_assert_int_eq(ray_scene_new(&c2, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(c2, &mb, &m), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(c2, &mb, &m), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(c2, vec(0, 0, 0), 1, m, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(c2), RAY_OK);
    ray_transform_identity(&a);
    ray_transform_identity(&b);
    a.m[0][3] = -3;
    b.m[0][3] = 3;
    ck_assert_int_eq(ray_scene_new(&top, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_instance(top, c1, &a, &i1), RAY_OK);
    ck_assert_int_eq(ray_scene_add_instance(top, c2, &b, &i2), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    ck_assert_uint_eq(ray_scene_effects(top), RAY_EFFECT_REFLECTION);
    ck_assert_int_eq(ray_ctx_new(top, 1, &ctx), RAY_OK);
    ck_assert_int_eq(ray_trace(ctx, &r1, RAY_KIND_PRIMARY, 1, &c), RAY_OK);
    ck_assert(c.r == 1 && c.g == 0 && c.b == 0);
    ck_assert_int_eq(ray_trace(ctx, &r2, RAY_KIND_PRIMARY, 1, &c), RAY_OK);
    ck_assert(c.r == 0 && c.g == 0 && c.b == 1);
    /* The reflective child hidden: no REFLECTION left, red not seen. */
    ck_assert_int_eq(ray_scene_set_enabled(top, i1, 0), RAY_OK);
    ck_assert_int_eq(ray_trace(ctx, &r1, RAY_KIND_PRIMARY, 1, &c), RAY_ESTATE);
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    ck_assert_uint_eq(ray_scene_effects(top), 0);
    ck_assert_int_eq(ray_trace(ctx, &r1, RAY_KIND_PRIMARY, 1, &c), RAY_OK);
    ck_assert(c.r == 0 && c.g == 0 && c.b == 0);
    ray_ctx_free(ctx);
    ray_scene_free(top);
    ray_scene_free(c1);
    ray_scene_free(c2);
}
END_TEST

/*
** Moving an instance (ray_scene_set_transform) stages it: no query until
** the commit, then it answers at the new place and not at the old.  A
** child changed and committed again under its parent: the parent's
** query that meets it says -RAY_ESTATE until the parent is committed
** again, which takes the child's new box.
*/
START_TEST(instances_should_move_and_follow_their_child)
{
    ray_scene *child, *top;
    ray_transform xf;
    ray_ray at0 = ray_from(vec(0, 0, 10), vec(0, 0, -1));
    ray_ray at5 = ray_from(vec(5, 0, 10), vec(0, 0, -1));
    ray_ray far = ray_from(vec(20, 0, 10), vec(0, 0, -1));
    ray_hit h;
    unsigned inst;

    ck_assert_int_eq(ray_scene_new(&child, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(child, vec(0, 0, 0), 1, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    ray_transform_identity(&xf);
    ck_assert_int_eq(ray_scene_new(&top, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_instance(top, child, &xf, &inst), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    ck_assert_int_eq(ray_intersect(top, &at0, &h, NULL), 1);
    ck_assert_double_eq(h.t, 9.0);     /* exact: 10 - 1 on the axis */
    xf.m[0][3] = 5;
    ck_assert_int_eq(ray_scene_set_transform(top, inst, &xf), RAY_OK);
    ck_assert_int_eq(ray_intersect(top, &at0, &h, NULL), -RAY_ESTATE);
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    ck_assert_int_eq(ray_intersect(top, &at0, &h, NULL), 0);
    ck_assert_int_eq(ray_intersect(top, &at5, &h, NULL), 1);
    ck_assert_double_eq(h.t, 9.0);
    ck_assert_double_eq(h.p.x, 5.0);
    /* The child grows a second sphere at x = 15 (world 20). */
    ck_assert_int_eq(ray_scene_add_sphere(child, vec(15, 0, 0), 1, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_intersect(top, &at5, &h, NULL), -RAY_ESTATE);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    ck_assert_int_eq(ray_intersect(top, &at5, &h, NULL), -RAY_ESTATE);
    /* The calls that check every instance first refuse it whatever the
    ** ray, and write nothing. */
    {
        ray_ray miss = ray_from(vec(100, 100, 100), vec(0, 1, 0));
        ray_hit all[4];
        size_t count = 77;
        ray_camera cam;
        ray_render_options opt;
        float px[3 * 4];
        hit_poison(&all[0]);
        ck_assert_int_eq(ray_intersect_all(top, &miss, NULL, all, 4, &count), -RAY_ESTATE);
        ck_assert_uint_eq(count, 77);
        ck_assert(hit_is_poisoned(&all[0]));
        cam = (ray_camera){.look_at = {0, 0, -1}};
        opt = (ray_render_options){.width = 2, .height = 2};
        ck_assert_int_eq(ray_render(top, &cam, &opt, px, NULL), RAY_ESTATE);
    }
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    ck_assert_int_eq(ray_intersect(top, &at5, &h, NULL), 1);
    ck_assert_int_eq(ray_intersect(top, &far, &h, NULL), 1);
    ck_assert_uint_eq(h.geom_id, 1);
    ck_assert_uint_eq(h.inst_id, inst);
    /* Removed, its child may go: nothing of the parent reads it again. */
    ck_assert_int_eq(ray_scene_remove(top, inst), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    ray_scene_free(child);
    ck_assert_int_eq(ray_intersect(top, &at5, &h, NULL), 0);
    {
        size_t count = 77;
        ck_assert_int_eq(ray_intersect_all(top, &at5, NULL, NULL, 0, &count), 0);
        ck_assert_uint_eq(count, 0);
    }
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    ray_scene_free(top);
}
END_TEST

/*
** A commit that fails on one instance changes no other: child A grew and
** was committed, child B changed and was not; the parent's commit
** refuses B and leaves A's instance stale too, so the parent still
** answers -RAY_ESTATE (not A's new sphere through A's old box); once B is
** committed, the parent's commit takes both.
*/
START_TEST(failed_commit_should_leave_every_instance_stale)
{
    ray_scene *a, *b, *p;
    ray_transform xf;
    ray_ray r = ray_from(vec(-10, 0, 0), vec(1, 0, 0));
    ray_ray high = ray_from(vec(-10, 2.5, 0), vec(1, 0, 0));
    ray_hit h;
    unsigned sa;

    ck_assert_int_eq(ray_scene_new(&a, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_new(&b, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_new(&p, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(a, vec(0, 0, 0), 1, RAY_NO_MATERIAL, &sa), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(a), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(b, vec(0, 0, 0), 1, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(b), RAY_OK);
    ray_transform_identity(&xf);
    ck_assert_int_eq(ray_scene_add_instance(p, a, &xf, NULL), RAY_OK);
    xf.m[0][3] = 10;
    ck_assert_int_eq(ray_scene_add_instance(p, b, &xf, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(p), RAY_OK);
    ck_assert_int_eq(ray_scene_remove(a, sa), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(a, vec(0, 0, 0), 3, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(a), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(b, vec(0, 2, 0), 1, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(p), RAY_ESTATE);
    ck_assert_int_eq(ray_intersect(p, &r, &h, NULL), -RAY_ESTATE);
    ck_assert_int_eq(ray_scene_commit(b), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(p), RAY_OK);
    ck_assert_int_eq(ray_intersect(p, &r, &h, NULL), 1);
    ck_assert_double_eq(h.t, 7.0);          /* exact: -10 to -3 */
    ck_assert_int_eq(ray_intersect(p, &high, &h, NULL), 1);   /* the new box */
    ray_scene_free(p);
    ray_scene_free(a);
    ray_scene_free(b);
}
END_TEST

/*
** A user-driven ray_trace whose primary ray misses a stale instance but
** whose shadow ray meets it: the outermost call answers RAY_ESTATE, its
** colour untouched (the material's light test saw "no light" and went
** on); after the parent's commit the same trace is RAY_OK.
*/
START_TEST(trace_should_report_a_stale_instance_met_by_a_shadow_ray)
{
    ray_phong_params grey;
    ray_material m;
    ray_light l;
    ray_scene *child, *top;
    ray_transform xf;
    ray_ctx *ctx;
    ray_ray r = ray_from(vec(0, 5, 5), vec(0, -5, -5));   /* floor at 0 */
    ray_rgb c = {7, 7, 7};
    unsigned mat;

    ck_assert_int_eq(ray_scene_new(&child, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(child, vec(0, 0, 0), 0.5, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    ray_phong_params_init(&grey);
    m = ray_material_phong(&grey);
    ray_light_init(&l, RAY_LIGHT_POINT);
    l.position = vec(0, 10, 0);
    ray_transform_identity(&xf);
    xf.m[1][3] = 5;                                /* between floor and light */
    ck_assert_int_eq(ray_scene_new(&top, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(top, &m, &mat), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(top, vec(0, 0, 0), vec(0, 1, 0), mat, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_light(top, &l, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_instance(top, child, &xf, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(top, 1, &ctx), RAY_OK);
    ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1, &c), RAY_OK);
    /* The child changes and is committed; the parent is not. */
    ck_assert_int_eq(ray_scene_add_sphere(child, vec(0, 0.2, 0), 0.5, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    c.r = c.g = c.b = 7;
    ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1, &c), RAY_ESTATE);
    ck_assert(c.r == 7 && c.g == 7 && c.b == 7);
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1, &c), RAY_OK);
    ray_ctx_free(ctx);
    ray_scene_free(top);
    ray_scene_free(child);
}
END_TEST

/*
** Transforms of any scale: a uniform scale of 1e-110, 1e-106 or 1e103
** (well conditioned, however small or large) is accepted, and a ray
** down the axis hits the unit sphere scaled by it at 4 s within 8 ulps
** (the inverse is computed on rows scaled by powers of two, so neither
** the determinant nor the row lengths underflow or overflow).
*/
START_TEST(instances_should_take_any_scale)
{
    static const double scale[3] = {1e-110, 1e-106, 1e103};
    ray_scene *child, *top;
    int k;

    ck_assert_int_eq(ray_scene_new(&child, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(child, vec(0, 0, 0), 1, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    for (k = 0; k < 3; k++) {
        double sc = scale[k];
        ray_transform xf;
        ray_ray r = ray_from(vec(0, 0, 5 * sc), vec(0, 0, -1));
        ray_hit h;
        ray_transform_identity(&xf);
        xf.m[0][0] = xf.m[1][1] = xf.m[2][2] = sc;
        ck_assert_int_eq(ray_scene_new(&top, NULL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_instance(top, child, &xf, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
        ck_assert_int_eq(ray_intersect(top, &r, &h, NULL), 1);
        ck_assert_double_eq_tol(h.t, 4 * sc, 8 * DBL_EPSILON * 4 * sc);
        ray_scene_free(top);
    }
    ray_scene_free(child);
}
END_TEST

/*
** Issue 30, defect 1: a finite transform that maps its child near
** DBL_MAX gave hits with p.z = -Inf and p_err NaN (found by fuzzing).
** Such a transform is refused (ray_scene_add_instance(3)), by add, by
** set_transform and by a commit after the child grew out of range;
** transforms just within the limit (2^1016) give finite hits.
*/
START_TEST(instances_should_refuse_transforms_beyond_the_doubles)
{
    ray_scene *child, *top;
    ray_transform xf, far;
    unsigned id;
    ray_ray r = ray_from(vec(0, 0, 0), vec(0, 0, -1));
    ray_hit h, all[4];
    size_t n;

    ck_assert_int_eq(ray_scene_new(&child, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(child, vec(0, 0, 0), 1, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    ck_assert_int_eq(ray_scene_new(&top, NULL, NULL), RAY_OK);
    /* The fuzzer's case: z in [-2.5e308, -0.5e308]. */
    ray_transform_identity(&far);
    far.m[2][2] = 1e308;
    far.m[2][3] = -1.5e308;
    ck_assert_int_eq(ray_scene_add_instance(top, child, &far, &id), RAY_EINVAL);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(top), "2^1016"));
    /* Within range: a scale 2^1012 at 2^1014 below: every field finite. */
    ray_transform_identity(&xf);
    xf.m[0][0] = xf.m[1][1] = xf.m[2][2] = 0x1p1012;
    xf.m[2][3] = -0x1p1014;
    ck_assert_int_eq(ray_scene_add_instance(top, child, &xf, &id), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    ck_assert_int_eq(ray_intersect(top, &r, &h, NULL), 1);
    ck_assert(hit_is_finite(&h));
    ck_assert_double_eq_tol(h.p.z, -0x1p1014 + 0x1p1012, 0x1p1012 * 1e-14);
    ck_assert_int_eq(ray_intersect_all(top, &r, NULL, all, 4, &n), 2);
    ck_assert(hit_is_finite(&all[0]) && hit_is_finite(&all[1]));
    /* Moved out of range: refused, the scene still committed as it was. */
    ck_assert_int_eq(ray_scene_set_transform(top, id, &far), RAY_EINVAL);
    ck_assert_int_eq(ray_intersect(top, &r, &h, NULL), 1);
    /* The child grows (a sphere at 100): 2^1012 * 101 + 2^1014 is beyond
    ** 2^1016, so the parent's next commit refuses. */
    ck_assert_int_eq(ray_scene_add_sphere(child, vec(0, 0, 100), 1, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(top), RAY_EINVAL);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(top), "2^1016"));
    ray_scene_free(top);
    ray_scene_free(child);
}
END_TEST

/*
** Issue 30, the unstated rule: the singularity test is scale-free, but
** an inverse with an entry beyond DBL_MAX cannot be stored.
** diag(1e-310, 1, 1) is refused for that reason, and says so (it used to
** be called "singular"); diag(1e-300, 1, 1) is accepted and hit where
** it is (the unit sphere squashed to x in [-1e-300, 1e-300]).
*/
START_TEST(instances_should_say_why_a_tiny_scale_is_refused)
{
    ray_scene *child, *top;
    ray_transform xf;
    ray_ray r = ray_from(vec(0, 0, 5), vec(0, 0, -1));
    ray_hit h;

    ck_assert_int_eq(ray_scene_new(&child, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(child, vec(0, 0, 0), 1, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    ck_assert_int_eq(ray_scene_new(&top, NULL, NULL), RAY_OK);
    ray_transform_identity(&xf);
    xf.m[0][0] = 1e-310;
    ck_assert_int_eq(ray_scene_add_instance(top, child, &xf, NULL), RAY_EINVAL);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(top), "inverse"));
    ck_assert_ptr_null(strstr(ray_scene_errmsg(top), "singular"));
    xf.m[0][0] = 1e-300;
    ck_assert_int_eq(ray_scene_add_instance(top, child, &xf, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    ck_assert_int_eq(ray_intersect(top, &r, &h, NULL), 1);
    ck_assert_double_eq_tol(h.t, 4, 8 * DBL_EPSILON * 4);
    ray_scene_free(top);
    ray_scene_free(child);
}
END_TEST

/*
** Bad input: an error with a message, nothing added (the id untouched,
** the next instance still gets id 0) and a committed scene stays so.
*/
START_TEST(instances_should_refuse_bad_input)
{
    ray_scene *child, *top, *loose, *nested, *planar;
    ray_transform xf, bad;
    unsigned id = 77;
    ray_ray r = ray_from(vec(0, 0, 10), vec(0, 0, -1));
    ray_hit h;

    ck_assert_int_eq(ray_scene_new(&child, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(child, vec(0, 0, 0), 1, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    ck_assert_int_eq(ray_scene_new(&loose, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_new(&planar, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(planar, vec(0, 0, 0), vec(0, 1, 0), RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(planar), RAY_OK);
    ray_transform_identity(&xf);
    ck_assert_int_eq(ray_scene_new(&nested, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_instance(nested, child, &xf, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(nested), RAY_OK);
    ck_assert_int_eq(ray_scene_new(&top, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);

    ck_assert_int_eq(ray_scene_add_instance(NULL, child, &xf, &id), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_instance(top, NULL, &xf, &id), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_instance(top, child, NULL, &id), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_instance(top, top, &xf, &id), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_instance(top, loose, &xf, &id), RAY_ESTATE);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(top), "not committed"));
    ck_assert_int_eq(ray_scene_add_instance(top, nested, &xf, &id), RAY_EINVAL);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(top), "two levels"));
    ck_assert_int_eq(ray_scene_add_instance(top, planar, &xf, &id), RAY_EINVAL);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(top), "planes"));
    bad = xf;
    bad.m[1][3] = (double)NAN;
    ck_assert_int_eq(ray_scene_add_instance(top, child, &bad, &id), RAY_EINVAL);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(top), "m[1][3]"));
    bad = xf;
    bad.m[2][2] = HUGE_VAL;
    ck_assert_int_eq(ray_scene_add_instance(top, child, &bad, &id), RAY_EINVAL);
    bad = xf;                                   /* rows 0 and 1 equal */
    bad.m[1][0] = 1;
    bad.m[1][1] = 0;
    ck_assert_int_eq(ray_scene_add_instance(top, child, &bad, &id), RAY_EINVAL);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(top), "singular"));
    bad = xf;                                   /* nearly so: 1e-17 */
    bad.m[1][0] = 1;
    bad.m[1][1] = 1e-17;
    ck_assert_int_eq(ray_scene_add_instance(top, child, &bad, &id), RAY_EINVAL);
    bad = xf;                                   /* zero scale */
    bad.m[0][0] = 0;
    ck_assert_int_eq(ray_scene_add_instance(top, child, &bad, &id), RAY_EINVAL);
    ck_assert_uint_eq(id, 77);
    /* still committed */
    ck_assert_int_eq(ray_intersect(top, &r, &h, NULL), 0);
    /* Updates of what is not there, or not an instance. */
    ck_assert_int_eq(ray_scene_set_transform(top, 0, &xf), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_instance(top, child, &xf, &id), RAY_OK);
    ck_assert_uint_eq(id, 0);
    ck_assert_int_eq(ray_scene_add_sphere(top, vec(9, 9, 9), 1, RAY_NO_MATERIAL, &id), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    ck_assert_int_eq(ray_scene_set_transform(top, 1, &xf), RAY_EINVAL);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(top), "not an instance"));
    bad = xf;
    bad.m[0][0] = 0;
    ck_assert_int_eq(ray_scene_set_transform(top, 0, &bad), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_set_filter(top, 0, NULL, NULL, 0), RAY_EINVAL);
    /* still committed */
    ck_assert_int_eq(ray_intersect(top, &r, &h, NULL), 1);
    ck_assert_double_eq(h.t, 9.0);
    ray_scene_free(top);
    ray_scene_free(nested);
    ray_scene_free(planar);
    ray_scene_free(loose);
    ray_scene_free(child);
}
END_TEST

/*
** Issue 38, defect 4: the transform check refuses what maps the child
** beyond +-2^1016, and nothing else.  A shear of 1e8 with a translation
** of 1e300 puts a unit box's image within 1e8 of (1e300, 1e300, 1e300),
** and the bounds the check forms (the reach and the rounding both ways,
** ray__instance_box) stay below 1e301, far inside 2^1016 (about 7e305):
** evaluated in long double here, without overflow, as the reference.
** It was refused, because an intermediate product |L^-1| (|x| + |t|)
** (1e8 times 2e300) overflowed before it was scaled by gamma(6).  Now it
** is accepted and a ray aimed at the box's image hits it there with a
** finite p and p_err; a translation of 1e306, really beyond, stays
** refused.  Shears of 1e5 and 1e10 with 1e303 likewise.
*/
START_TEST(instances_should_refuse_only_what_passes_the_bound)
{
    static const double shear[3] = {1e5, 1e8, 1e10};
    static const double shift[3] = {1e303, 1e300, 1e303};
    ray_box_params b;
    ray_scene *child;
    int i;

    b.center = vec(0, 0, 0);
    b.half_extents = vec(0.5, 0.5, 0.5);
    b.axis_x = vec(1, 0, 0);
    b.axis_y = vec(0, 1, 0);
    ck_assert_int_eq(ray_scene_new(&child, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_box(child, &b, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    for (i = 0; i < 3; i++) {
        const double sh = shear[i], t = shift[i];
        ray_transform x = {{{1, sh, 0, t}, {0, 1, 0, t}, {0, 0, 1, t}}};
        ray_scene *s;
        ray_hit h;
        ray_ray r;
        /* The long-double reference: reach |L| |p'| + |t| per row, and
        ** the bound's back term with |L^-1| = [[1, sh, 0], I rows]. */
        const long double g6 = 6 * 0x1p-53L / (1 - 6 * 0x1p-53L); /* gamma(6) */
        const long double shl = (long double)sh, tl = (long double)t;
        long double big0 = 1.0L + shl + tl, big1 = 1.0L + tl;
        long double back = g6 * (big0 + tl + shl * (big1 + tl)) +
                           shl * g6 * (big1 + tl);
        ck_assert(big0 + back < 0x1p1016L);
        ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
        ck_assert_msg(ray_scene_add_instance(s, child, &x, NULL) == RAY_OK,
                      "shear %g shift %g: %s", sh, t, ray_scene_errmsg(s));
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        /* Down the z axis onto the image of the top face's centre. */
        r = make_ray(vec(t, t, t + 1e300), vec(0, 0, -1), 0, HUGE_VAL);
        ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), 1);
        ck_assert(isfinite(h.p.x) && isfinite(h.p.y) && isfinite(h.p.z));
        ck_assert(isfinite(h.p_err.x) && isfinite(h.p_err.y) &&
                  isfinite(h.p_err.z));
        ray_scene_free(s);
        /* Really beyond: refused. */
        x.m[0][3] = x.m[1][3] = x.m[2][3] = 1e306;
        ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_instance(s, child, &x, NULL), RAY_EINVAL);
        ray_scene_free(s);
    }
    ray_scene_free(child);
}
END_TEST

Suite *instance_suite(void)
{
    Suite *s = suite_create("instance");
    TCase *tc = tcase_create("core");

    tcase_add_test(tc, identity_instance_should_answer_as_the_child);
    tcase_add_loop_test(tc, instance_should_match_flattened_geometry, 0, N_OFFSETS);
    tcase_add_loop_test(tc, closest_points_should_come_through_instances, 0, N_OFFSETS);
    tcase_add_test(tc, normals_should_follow_the_inverse_transpose);
    tcase_add_loop_test(tc, closed_mesh_should_not_leak_through_an_instance, 0, N_OFFSETS);
    tcase_add_loop_test(tc, spawned_rays_should_not_self_hit_through_an_instance, 0, N_OFFSETS);
    tcase_add_test(tc, world_error_bound_should_be_the_documented_one);
    tcase_add_test(tc, instances_should_shade_with_their_child_materials);
    tcase_add_test(tc, instances_should_move_and_follow_their_child);
    tcase_add_test(tc, failed_commit_should_leave_every_instance_stale);
    tcase_add_test(tc, instances_should_take_any_scale);
    tcase_add_test(tc, trace_should_report_a_stale_instance_met_by_a_shadow_ray);
    tcase_add_test(tc, instances_should_refuse_bad_input);
    tcase_add_test(tc, instances_should_refuse_transforms_beyond_the_doubles);
    tcase_add_test(tc, instances_should_say_why_a_tiny_scale_is_refused);
    tcase_add_test(tc, instances_should_refuse_only_what_passes_the_bound);
    tcase_add_test(tc, child_of_triangles_should_answer_as_the_general_query);
    suite_add_tcase(s, tc);
    return s;
}
