/* SPDX-License-Identifier: MIT */
/*
** check_dynamic.c -- a scene that changes after commit (refitted mesh
** updates, enable, disable, remove, add), visibility masks, filters
** (cut-outs, ignoring the shooter, transparent shadows, the far side of
** a sphere) and every hit along a ray, each against a brute-force or a
** freshly built answer.
*/
#include <string.h>
#include <stdint.h>
#include <stdlib.h>

#include "tests.h"
#include "hardcases.h"

/* Every vertex of m moved by up to "amount" in each coordinate. */
static void wobble(ray_vec3 *v, size_t n, rng *g, double amount)
{
    size_t i;

    for (i = 0; i < n; i++)
        v[i] = vadd(v[i], vec(rng_range(g, -amount, amount),
                              rng_range(g, -amount, amount),
                              rng_range(g, -amount, amount)));
}

static ray_ray random_ray(rng *g)
{
    ray_vec3 target = vec(rng_range(g, -6, 6), rng_range(g, -3, 3),
                          rng_range(g, -3, 3));
    ray_vec3 from = vadd(target, vscale(rng_dir(g), 25));
    return ray_from(from, vsub(target, from));
}

/*
** A mesh updated in place and refitted answers as a scene built afresh
** from the same vertices: same hits, same t bit for bit, same ids (the
** same triangle tests on the same triangles; only the boxes around them
** differ).  Three rounds of deformation; one triangle starts with zero
** area and gains some in the update, and must then be hit.
*/
START_TEST(refit_should_answer_as_a_rebuild)
{
    hc_mesh ball = hc_icosphere(vec(-3, 0, 0), 3), cube = hc_cube(vec(4, 0, 0));
    ray_vec3 *v = malloc(ball.nv * sizeof *v);
    ray_mesh mb = hc_ray_mesh(&ball), mc = hc_ray_mesh(&cube);
    ray_scene *live;
    rng g = {21};
    unsigned idb, idc;
    int round, i;

    memcpy(v, ball.v, ball.nv * sizeof *v);
    /* Triangle 0 of the cube degenerate: its third corner on its first. */
    cube.v[cube.idx[2]] = cube.v[cube.idx[0]];
    ck_assert_int_eq(ray_scene_new(&live, NULL, NULL), RAY_OK);
    mb.vertices = v;
    ck_assert_int_eq(ray_scene_add_mesh(live, &mb, RAY_NO_MATERIAL, &idb), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(live, &mc, RAY_NO_MATERIAL, &idc), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(live), RAY_OK);
    for (round = 0; round < 3; round++) {
        ray_scene *fresh;
        hc_mesh cube2 = hc_cube(vec(4 + round, 0, 0));
        ray_mesh mc2 = hc_ray_mesh(&cube2);
        int hits = 0;
        if (round == 1) {
            /* A rebuild between refits: the next refit starts afresh
            ** (its list of leaves goes with the old tree). */
            ck_assert_int_eq(ray_scene_set_enabled(live, idc, 0), RAY_OK);
            ck_assert_int_eq(ray_scene_set_enabled(live, idc, 1), RAY_OK);
            ck_assert_int_eq(ray_scene_commit(live), RAY_OK);
        }
        wobble(v, ball.nv, &g, 0.3);
        ck_assert_int_eq(ray_scene_update_mesh(live, idb, &mb), RAY_OK);
        ck_assert_int_eq(ray_scene_update_mesh(live, idc, &mc2), RAY_OK);
        ck_assert_int_eq(ray_intersect(live,
                                       &(ray_ray){{0, 0, 9}, {0, 0, -1}, 0, 1},
                                       &(ray_hit){0}, NULL), -RAY_ESTATE);
        ck_assert_int_eq(ray_scene_commit(live), RAY_OK);
        ck_assert_int_eq(ray_scene_new(&fresh, NULL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_mesh(fresh, &mb, RAY_NO_MATERIAL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_mesh(fresh, &mc2, RAY_NO_MATERIAL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_commit(fresh), RAY_OK);
        for (i = 0; i < 3000; i++) {
            ray_ray r = random_ray(&g);
            ray_hit a, b;
            int ha = ray_intersect(live, &r, &a, NULL),
                hb = ray_intersect(fresh, &r, &b, NULL);
            ck_assert_int_eq(ha, hb);
            ck_assert_int_eq(ray_occluded(live, &r, NULL),
                             ray_occluded(fresh, &r, NULL));
            if (ha == 1) {
                hits++;
                ck_assert(hit_same(&a, &b));
            }
        }
        ck_assert_int_gt(hits, 1000);
        /* The once-degenerate cube triangle 0 is hit now: aim at the
        ** middle of its face (z = -1 side of hc_cube face 0). */
        {
            const unsigned *t = cube2.idx;
            ray_vec3 c = vscale(vadd(vadd(cube2.v[t[0]], cube2.v[t[1]]), cube2.v[t[2]]), 1.0 / 3);
            ray_vec3 n = vcross(vsub(cube2.v[t[1]], cube2.v[t[0]]), vsub(cube2.v[t[2]], cube2.v[t[0]]));
            ray_ray r = ray_from(vadd(c, vscale(n, 3)), vscale(n, -1));
            ray_hit h;
            ck_assert_int_eq(ray_intersect(live, &r, &h, NULL), 1);
            ck_assert_uint_eq(h.geom_id, idc);
            ck_assert_uint_eq(h.prim_id, 0);
        }
        ray_scene_free(fresh);
        hc_mesh_free(&cube2);
    }
    ray_scene_free(live);
    hc_mesh_free(&ball);
    hc_mesh_free(&cube);
    free(v);
}
END_TEST

/* Do s and fresh answer ray r alike, bit for bit?  1 if it hit. */
static int same_answer(const ray_scene *s, const ray_scene *fresh,
                       const ray_ray *r)
{
    ray_hit a, b;
    int ha = ray_intersect(s, r, &a, NULL), hb = ray_intersect(fresh, r, &b, NULL);

    ck_assert_int_eq(ha, hb);
    ck_assert_int_eq(ray_occluded(s, r, NULL), ray_occluded(fresh, r, NULL));
    if (ha == 1)
        ck_assert(hit_same(&a, &b));
    return ha == 1;
}

/* The triangles of "idx" in the opposite order, into "out". */
static void reversed_triangles(const unsigned *idx, size_t nt, unsigned *out)
{
    size_t i;

    for (i = 0; i < nt; i++)
        memcpy(out + 3 * (nt - 1 - i), idx + 3 * i, 3 * sizeof *out);
}

/*
** A refit reads each slot's vertex indices from a copy in the tree's
** order, made by the first refit (triangles.c, slot_vertices), for the
** meshes that keep their own indices: an update that brings other
** indices -- the triangles of a mesh in another order, through an
** unsigned array or 16-bit index_data, copied or borrowed (a borrowed
** unsigned array changed in place is read there, never through the
** copy) -- must drop it, or the refit would fit each slot to the
** triangle it had before and the leaves would hold the wrong corners.
** Each scene, after a refit with its old indices and then one with the
** new, answers as one built afresh from the new: the same prim_id, t and
** record, bit for bit.  The mesh alone (the copy's fast path: every slot
** of one mesh), and beside another mesh and a single triangle (the
** slots' ids read).
*/
START_TEST(refit_should_follow_new_indices)
{
    hc_mesh ball = hc_icosphere(vec(0, 0, 0), 3), cube = hc_cube(vec(4, 0, 0));
    size_t n = 3 * ball.nt, i;
    unsigned *rev = malloc(n * sizeof *rev), *idx = malloc(n * sizeof *idx);
    uint16_t *idx16 = malloc(n * sizeof *idx16);
    ray_vec3 *v = malloc(ball.nv * sizeof *v);
    rng g = {31};
    int variant, k;

    reversed_triangles(ball.idx, ball.nt, rev);
    for (variant = 0; variant < 8; variant++) {
        int others = variant & 1, borrow = variant >> 1 & 1,
            narrow = variant >> 2 & 1;
        ray_mesh m = hc_ray_mesh(&ball), mc = hc_ray_mesh(&cube), f;
        ray_scene *s, *fresh;
        unsigned id;
        int hits = 0;
        memcpy(idx, ball.idx, n * sizeof *idx);
        for (i = 0; i < n; i++)
            idx16[i] = (uint16_t)ball.idx[i];
        memcpy(v, ball.v, ball.nv * sizeof *v);
        m.vertices = v;
        m.indices = narrow ? NULL : idx;
        m.index_data = narrow ? idx16 : NULL;
        m.index_type = RAY_UINT16;
        m.flags = borrow ? RAY_MESH_BORROW : 0;
        ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, &id),
                         RAY_OK);
        if (others) {
            ck_assert_int_eq(ray_scene_add_mesh(s, &mc, RAY_NO_MATERIAL,
                                                NULL), RAY_OK);
            ck_assert_int_eq(ray_scene_add_triangle(s, vec(-4, -1, 0),
                                                    vec(-2, -1, 0),
                                                    vec(-3, 1, 0),
                                                    RAY_NO_MATERIAL, NULL),
                             RAY_OK);
        }
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        /* Refits with the indices as they were: the copy made, kept. */
        for (k = 0; k < 2; k++) {
            wobble(v, ball.nv, &g, 0.05);
            ck_assert_int_eq(ray_scene_update_mesh(s, id, borrow ? NULL : &m),
                             RAY_OK);
            ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        }
        /* The same triangles in the opposite order, moved again: in
        ** place where borrowed, in the update's arrays where copied. */
        wobble(v, ball.nv, &g, 0.05);
        memcpy(idx, rev, n * sizeof *idx);
        for (i = 0; i < n; i++)
            idx16[i] = (uint16_t)rev[i];
        ck_assert_int_eq(ray_scene_update_mesh(s, id, borrow ? NULL : &m),
                         RAY_OK);
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        f = hc_ray_mesh(&ball);
        f.vertices = v;
        f.indices = rev;
        ck_assert_int_eq(ray_scene_new(&fresh, NULL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_mesh(fresh, &f, RAY_NO_MATERIAL, NULL),
                         RAY_OK);
        if (others) {
            ck_assert_int_eq(ray_scene_add_mesh(fresh, &mc, RAY_NO_MATERIAL,
                                                NULL), RAY_OK);
            ck_assert_int_eq(ray_scene_add_triangle(fresh, vec(-4, -1, 0),
                                                    vec(-2, -1, 0),
                                                    vec(-3, 1, 0),
                                                    RAY_NO_MATERIAL, NULL),
                             RAY_OK);
        }
        ck_assert_int_eq(ray_scene_commit(fresh), RAY_OK);
        for (k = 0; k < 2000; k++) {
            ray_ray r = random_ray(&g);
            hits += same_answer(s, fresh, &r);
        }
        ck_assert_int_gt(hits, 300);
        ray_scene_free(fresh);
        ray_scene_free(s);
    }
    hc_mesh_free(&ball);
    hc_mesh_free(&cube);
    free(rev);
    free(idx);
    free(idx16);
    free(v);
}
END_TEST

/* A game's vertex: position and normal as floats, 24 bytes. */
typedef struct game_vertex {
    float pos[3];
    float normal[3];
} game_vertex;

/* A material that reports the shading normal it was given as a colour. */
static void normal_colour(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                          ray_rgb *out)
{
    (void)ud;
    (void)ctx;
    out->r = a->shading_normal.x;
    out->g = a->shading_normal.y;
    out->b = a->shading_normal.z;
}

/*
** A borrowed mesh (RAY_MESH_BORROW): interleaved float positions, 16-bit
** indices, double normals, none of them copied.  The caller moves the
** positions in place; ray_scene_update_mesh(.., NULL) reads them again,
** and after the commit the scene answers as one built afresh from the
** moved positions, bit for bit.  Shading reads the borrowed normals.  A
** copied mesh cannot be updated from NULL; unknown flags are refused.
*/
START_TEST(borrowed_mesh_should_be_read_again_in_place)
{
    hc_mesh ball = hc_icosphere(vec(0, 0, 0), 2);
    game_vertex *gv = malloc(ball.nv * sizeof *gv);
    uint16_t *idx16 = malloc(3 * ball.nt * sizeof *idx16);
    ray_vec3 *nrm = malloc(ball.nv * sizeof *nrm), *moved = malloc(ball.nv * sizeof *moved);
    ray_material mat = {normal_colour, NULL, 0, NULL};
    ray_mesh m, copied;
    ray_scene *s, *fresh;
    ray_ctx *ctx;
    rng g = {24};
    unsigned id, mid, cid;
    size_t i;
    int k, hits = 0;

    for (i = 0; i < ball.nv; i++) {
        gv[i].pos[0] = (float)ball.v[i].x;
        gv[i].pos[1] = (float)ball.v[i].y;
        gv[i].pos[2] = (float)ball.v[i].z;
        nrm[i] = vec(0, 0, 1);                 /* a flat lie: seen in shading */
    }
    for (i = 0; i < 3 * ball.nt; i++)
        idx16[i] = (uint16_t)ball.idx[i];
    memset(&m, 0, sizeof m);
    m.positions = gv;
    m.position_stride = sizeof *gv;
    m.position_type = RAY_FLOAT32;
    m.vertex_count = ball.nv;
    m.index_data = idx16;
    m.index_type = RAY_UINT16;
    m.triangle_count = ball.nt;
    m.normals = nrm;
    m.flags = RAY_MESH_BORROW;
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &mat, &mid), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, mid, &id), RAY_OK);
    copied = m;
    copied.flags = 0;
    ck_assert_int_eq(ray_scene_add_mesh(s, &copied, mid, &cid), RAY_OK);
    ck_assert_int_eq(ray_scene_set_enabled(s, cid, 0), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    /* Moved in place: the scene sees it at the update and commit. */
    for (i = 0; i < ball.nv; i++) {
        gv[i].pos[0] = (float)(gv[i].pos[0] * 1.5f + 0.25f);
        moved[i] = vec((double)gv[i].pos[0], (double)gv[i].pos[1],
                       (double)gv[i].pos[2]);
    }
    ck_assert_int_eq(ray_scene_update_mesh(s, id, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_scene_new(&fresh, NULL, NULL), RAY_OK);
    copied = m;
    copied.flags = 0;
    copied.positions = NULL;
    copied.vertices = moved;
    ck_assert_int_eq(ray_scene_add_mesh(fresh, &copied, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(fresh), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(s, 1, &ctx), RAY_OK);
    for (k = 0; k < 2000; k++) {
        ray_ray r = random_ray(&g);
        ray_hit a, b;
        ray_rgb c;
        int ha = ray_intersect(s, &r, &a, NULL);
        ck_assert_int_eq(ha, ray_intersect(fresh, &r, &b, NULL));
        if (ha != 1)
            continue;
        hits++;
        ck_assert(a.t == b.t && a.prim_id == b.prim_id && a.geom_id == id);
        /* Shading: the borrowed normals (0, 0, 1), turned to the ray. */
        ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1, &c), RAY_OK);
        ck_assert(c.r == 0 && c.g == 0 && fabs(c.b) == 1);
    }
    ck_assert_int_gt(hits, 500);
    ck_assert_int_eq(ray_scene_update_mesh(s, cid, NULL), RAY_EINVAL);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(s), "RAY_MESH_BORROW"));
    copied.flags = 4;
    ck_assert_int_eq(ray_scene_update_mesh(s, cid, &copied), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_mesh(s, &copied, mid, NULL), RAY_EINVAL);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(s), "flags"));
    ray_ctx_free(ctx);
    ray_scene_free(fresh);
    ray_scene_free(s);
    hc_mesh_free(&ball);
    free(gv);
    free(idx16);
    free(nrm);
    free(moved);
}
END_TEST

/* Does ray r (down the z axis at x) hit geometry "id" first? */
static int first_is(const ray_scene *s, double x, unsigned id)
{
    ray_ray r = ray_from(vec(x, 0, 10), vec(0, 0, -1));
    ray_hit h;
    return ray_intersect(s, &r, &h, NULL) == 1 && h.geom_id == id;
}

/*
** Enable, disable, remove and add after commit: each staged until the
** commit, then the queries see exactly what is enabled; ids stay (a
** removed id is not reused); bad updates are refused and change nothing.
*/
START_TEST(geometry_should_come_and_go_after_commit)
{
    hc_mesh cube = hc_cube(vec(0, 0, 0));
    ray_mesh m = hc_ray_mesh(&cube);
    ray_scene *s;
    unsigned sph, msh, late;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(5, 0, 0), 1, RAY_NO_MATERIAL, &sph), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, &msh), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert(first_is(s, 5, sph) && first_is(s, 0, msh));
    ck_assert_int_eq(ray_scene_set_enabled(s, sph, 0), RAY_OK);
    ck_assert_int_eq(ray_scene_set_enabled(s, msh, 0), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert(!first_is(s, 5, sph) && !first_is(s, 0, msh));
    ck_assert_int_eq(ray_scene_set_enabled(s, msh, 1), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert(!first_is(s, 5, sph) && first_is(s, 0, msh));
    /* Setting what is already set stages nothing: still committed. */
    ck_assert_int_eq(ray_scene_set_enabled(s, msh, 1), RAY_OK);
    ck_assert(first_is(s, 0, msh));
    ck_assert_int_eq(ray_scene_remove(s, msh), RAY_OK);
    ck_assert_int_eq(ray_scene_remove(s, msh), RAY_EINVAL);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(s), "removed"));
    ck_assert_int_eq(ray_scene_set_enabled(s, msh, 1), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_update_mesh(s, msh, &m), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(-5, 0, 0), 1, RAY_NO_MATERIAL, &late), RAY_OK);
    ck_assert_uint_eq(late, 2);
    ck_assert_int_eq(ray_scene_set_enabled(s, sph, 1), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert(first_is(s, 5, sph) && !first_is(s, 0, msh) && first_is(s, -5, late));
    ray_scene_free(s);
    hc_mesh_free(&cube);
}
END_TEST

/* Bad updates: an error with a message, the scene still committed and
** answering as before. */
START_TEST(updates_should_refuse_bad_input)
{
    hc_mesh cube = hc_cube(vec(0, 0, 0)), ball = hc_icosphere(vec(0, 0, 0), 1);
    ray_mesh m = hc_ray_mesh(&cube), other = hc_ray_mesh(&ball), bad;
    ray_vec3 nan_v[8];
    unsigned bad_idx[36];                       /* the cube's 12 triangles */
    ray_scene *s;
    unsigned msh, sph;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, &msh), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(5, 0, 0), 1, RAY_NO_MATERIAL, &sph), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_scene_update_mesh(NULL, msh, &m), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_update_mesh(s, msh, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_update_mesh(s, 99, &m), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_update_mesh(s, sph, &m), RAY_EINVAL);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(s), "not a mesh"));
    ck_assert_int_eq(ray_scene_update_mesh(s, msh, &other), RAY_EINVAL);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(s), "triangle_count"));
    memcpy(nan_v, cube.v, sizeof nan_v);
    nan_v[3].y = (double)NAN;
    bad = m;
    bad.vertices = nan_v;
    ck_assert_int_eq(ray_scene_update_mesh(s, msh, &bad), RAY_EINVAL);
    bad = m;
    bad.vertex_count = 4;                       /* indices out of range */
    ck_assert_int_eq(ray_scene_update_mesh(s, msh, &bad), RAY_EINVAL);
    /* The same vertices, one index past them: indices unlike those kept
    ** are checked (those kept are not, mesh.c's indices_kept). */
    memcpy(bad_idx, cube.idx, sizeof bad_idx);
    bad_idx[35] = 8;
    bad = m;
    bad.indices = bad_idx;
    ck_assert_int_eq(ray_scene_update_mesh(s, msh, &bad), RAY_EINVAL);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(s), "out of range"));
    ck_assert_int_eq(ray_scene_set_enabled(s, 99, 0), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_remove(s, 99), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_remove(NULL, 0), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_set_mask(s, 99, 1), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_set_filter(s, 99, NULL, NULL, 0), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_set_filter(s, msh, NULL, NULL, 4), RAY_EINVAL);
    /* Still committed, the cube where it was. */
    ck_assert(first_is(s, 0, msh) && first_is(s, 5, sph));
    ray_scene_free(s);
    hc_mesh_free(&cube);
    hc_mesh_free(&ball);
}
END_TEST

/* Masked queries down the z axis at x: the geometry hit first, or -1. */
static int first_masked(const ray_scene *s, double x, unsigned mask)
{
    ray_ray r = ray_from(vec(x, 0, 10), vec(0, 0, -1));
    ray_query q;
    ray_hit h;
    int hit;

    memset(&q, 0, sizeof q);
    q.ignore_mask = ~mask;
    hit = ray_intersect(s, &r, &h, &q);
    ck_assert_int_eq(ray_occluded(s, &r, &q), hit);
    return hit == 1 ? (int)h.geom_id : -1;
}

/*
** Masks: a sphere, a triangle mesh and an instance of a sphere stacked
** along z under each ray, with masks 1, 2 and 4, the instance's child
** sphere with mask 8: a ray reaches the child only with a bit of each
** (12), not with 4 or 8 alone.  Every mask picks exactly the nearest
** geometry it shares a bit with.
*/
START_TEST(masks_should_pick_geometry_by_shared_bits)
{
    static const ray_vec3 tri[3] = {{-2, -2, 0}, {2, -2, 0}, {0, 2, 0}};
    static const unsigned idx[3] = {0, 1, 2};
    ray_scene *s, *child;
    ray_transform xf;
    ray_mesh m;
    unsigned sph, msh, inst, csph;

    ck_assert_int_eq(ray_scene_new(&child, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(child, vec(0, 0, 0), 1, RAY_NO_MATERIAL, &csph), RAY_OK);
    ck_assert_int_eq(ray_scene_set_mask(child, csph, 8), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    memset(&m, 0, sizeof m);
    m.vertices = tri;
    m.vertex_count = 3;
    m.indices = idx;
    m.triangle_count = 1;
    ray_transform_identity(&xf);
    xf.m[2][3] = -6;                            /* the instance at z = -6 */
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 4), 1, RAY_NO_MATERIAL, &sph), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, &msh), RAY_OK);
    ck_assert_int_eq(ray_scene_add_instance(s, child, &xf, &inst), RAY_OK);
    ck_assert_int_eq(ray_scene_set_mask(s, sph, 1), RAY_OK);
    ck_assert_int_eq(ray_scene_set_mask(s, msh, 2), RAY_OK);
    ck_assert_int_eq(ray_scene_set_mask(s, inst, 4), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(first_masked(s, 0, ~0u), (int)sph);
    ck_assert_int_eq(first_masked(s, 0, 1), (int)sph);
    ck_assert_int_eq(first_masked(s, 0, 2), (int)msh);
    ck_assert_int_eq(first_masked(s, 0, 3), (int)sph);
    ck_assert_int_eq(first_masked(s, 0, 4), -1);     /* child needs 8 */
    ck_assert_int_eq(first_masked(s, 0, 8), -1);     /* instance needs 4 */
    ck_assert_int_eq(first_masked(s, 0, 12), (int)csph);
    ck_assert_int_eq(first_masked(s, 0, 16), -1);
    ck_assert_int_eq(first_masked(s, 0, 0), -1);
    /* The plain queries see everything. */
    {
        ray_ray r = ray_from(vec(0, 0, 10), vec(0, 0, -1));
        ray_hit h;
        ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), 1);
        ck_assert_uint_eq(h.geom_id, sph);
    }
    ray_scene_free(s);
    ray_scene_free(child);
}
END_TEST

/* Filters' user data: what they were called with and what they reject. */
typedef struct filter_log {
    unsigned calls;
    unsigned reject_geom;
} filter_log;

/* Cut-out: reject hits with p.x < 0. */
static int cut_left(void *ud, const ray_ray *r, const ray_hit *c, void *q)
{
    (void)r;
    (void)q;
    ((filter_log *)ud)->calls++;
    return c->p.x >= 0;
}

/* Ignore the shooter: query_ud names the geometry to skip. */
static int not_shooter(void *ud, const ray_ray *r, const ray_hit *c, void *q)
{
    (void)r;
    ((filter_log *)ud)->calls++;
    return q == NULL || c->geom_id != *(const unsigned *)q;
}

/* Reject hits on the side facing +z (a sphere's front from above). */
static int no_front(void *ud, const ray_ray *r, const ray_hit *c, void *q)
{
    (void)r;
    (void)q;
    ((filter_log *)ud)->calls++;
    return c->n.z <= 0;
}

/*
** Issue 30, defect 2: of two triangles hit at the same t through their
** shared edge, the one with the lower id wins the tie (ray_intersect(3));
** when the other was met first, the winner was offered to its filter
** with the ray's tmax already lowered to its own t, so the candidate
** lay outside the open interval it came with.  The filter must always
** see tmin < t < tmax.  Two triangles share the edge y = 0 and a
** filler of 40 triangles (raised toward one side) varies the BVH's
** leaves, so that either triangle is met first over the 300 scenes;
** every ray goes through the edge.  Before the fix 149 candidates came
** with a ray that did not hold them.
*/
typedef struct interval_log {
    int calls, outside;
} interval_log;

static int filter_checks_interval(void *ud, const ray_ray *r,
                                  const ray_hit *c, void *q)
{
    interval_log *log = ud;
    (void)q;
    log->calls++;
    log->outside += !(c->t > r->tmin && c->t < r->tmax);
    return 1;
}

START_TEST(filters_should_see_their_candidate_inside_the_ray)
{
    interval_log log = {0, 0};
    rng g = {30};
    int it, k, ties = 0;

    for (it = 0; it < 300; it++) {
        ray_scene *s;
        unsigned g0, g1;
        ray_ray r;
        ray_hit h;
        ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_triangle(s, vec(-1, 0, 0), vec(0, -1, 0), vec(1, 0, 0), RAY_NO_MATERIAL, &g0), RAY_OK);
        ck_assert_int_eq(ray_scene_add_triangle(s, vec(-1, 0, 0), vec(1, 0, 0), vec(0, 1, 0), RAY_NO_MATERIAL, &g1), RAY_OK);
        for (k = 0; k < 40; k++) {
            double x = rng_range(&g, -3, 3), y = rng_range(&g, 0.5, 2.5) - (k & 1 ? 0 : 4);
            double z = rng_range(&g, -2, 0);
            ck_assert_int_eq(ray_scene_add_triangle(s, vec(x, y, z), vec(x + 0.3, y, z), vec(x, y + 0.3, z + it % 3), RAY_NO_MATERIAL, NULL), RAY_OK);
        }
        ck_assert_int_eq(ray_scene_set_filter(s, g0, filter_checks_interval, &log, RAY_FILTER_INTERSECT), RAY_OK);
        ck_assert_int_eq(ray_scene_set_filter(s, g1, filter_checks_interval, &log, RAY_FILTER_INTERSECT), RAY_OK);
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        r = ray_from(vec(rng_range(&g, -0.9, 0.9), 0, 5), vec(0, 0, -1));
        k = log.calls;
        ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), 1);
        /* t = 5 within the watertight test's rounding: a few ulps. */
        ck_assert_double_eq_tol(h.t, 5.0, 8 * DBL_EPSILON * 5);
        ties += log.calls - k == 2;
        ray_scene_free(s);
    }
    ck_assert_int_gt(ties, 50);         /* both orders were met */
    ck_assert_int_eq(log.outside, 0);
}
END_TEST

/*
** Filters, exact counts: a cut-out quad (two triangles, filter rejects
** x < 0) under a 20 x 20 grid of rays: exactly the 200 with x > 0 hit,
** and every ray over the quad is offered once (one triangle each: the
** grid avoids the diagonal); ignore-the-shooter through query_ud;
** a filter on occluded only (transparent shadows) leaves intersect
** alone; a sphere whose front is rejected is hit at its back (t = 11).
*/
START_TEST(filters_should_reject_candidates_exactly)
{
    static const ray_vec3 quad[4] = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    static const unsigned idx[6] = {0, 1, 2, 0, 2, 3};
    filter_log cut = {0, 0}, shoot = {0, 0}, front = {0, 0};
    ray_scene *s;
    ray_mesh m;
    ray_query q;
    unsigned msh, ball, other;
    int i, j, hits = 0;

    memset(&m, 0, sizeof m);
    m.vertices = quad;
    m.vertex_count = 4;
    m.indices = idx;
    m.triangle_count = 2;
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, &msh), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(10, 0, 0), 1, RAY_NO_MATERIAL, &ball), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(20, 0, 0), 1, RAY_NO_MATERIAL, &other), RAY_OK);
    ck_assert_int_eq(ray_scene_set_filter(s, msh, cut_left, &cut, RAY_FILTER_INTERSECT | RAY_FILTER_OCCLUDED), RAY_OK);
    ck_assert_int_eq(ray_scene_set_filter(s, ball, no_front, &front, RAY_FILTER_INTERSECT), RAY_OK);
    ck_assert_int_eq(ray_scene_set_filter(s, other, not_shooter, &shoot, RAY_FILTER_OCCLUDED), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    for (i = 0; i < 20; i++)
        for (j = 0; j < 20; j++) {
            /* Cell centres, -0.95 .. 0.95, off the diagonal x = y. */
            double x = -0.95 + 0.1 * i, y = -0.95 + 0.1 * j + 0.01;
            ray_ray r = ray_from(vec(x, y, 5), vec(0, 0, -1));
            ray_hit h;
            int hit = ray_intersect(s, &r, &h, NULL);
            ck_assert_int_eq(hit, x > 0);
            ck_assert_int_eq(ray_occluded(s, &r, NULL), x > 0);
            hits += hit;
        }
    ck_assert_int_eq(hits, 200);
    ck_assert_uint_eq(cut.calls, 800);          /* 400 rays, 2 queries */
    /* The sphere's front (t = 9) rejected, its back (t = 11) kept. */
    {
        ray_ray r = ray_from(vec(10, 0, 10), vec(0, 0, -1));
        ray_hit h;
        ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), 1);
        ck_assert_double_eq_tol(h.t, 11.0, tol_at(10));
        ck_assert_uint_eq(front.calls, 2);
        /* Occluded does not call an intersect-only filter. */
        ck_assert_int_eq(ray_occluded(s, &r, NULL), 1);
        ck_assert_uint_eq(front.calls, 2);
    }
    /* The shooter's own sphere ignored by its shadow rays only. */
    {
        ray_ray r = ray_from(vec(20, 0, 10), vec(0, 0, -1));
        ray_hit h;
        memset(&q, 0, sizeof q);
        q.query_ud = &other;
        ck_assert_int_eq(ray_occluded(s, &r, &q), 0);
        ck_assert_int_eq(ray_occluded(s, &r, NULL), 1);
        ck_assert_int_eq(ray_intersect(s, &r, &h, &q), 1);
        /* The shooter's query offers the front, then the back (both
        ** rejected); the plain one the front (kept); intersect none. */
        ck_assert_uint_eq(shoot.calls, 3);
        /* Removing the filter: a commit, then no more calls. */
        ck_assert_int_eq(ray_scene_set_filter(s, other, NULL, NULL, 0), RAY_OK);
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        ck_assert_int_eq(ray_occluded(s, &r, &q), 1);
        ck_assert_uint_eq(shoot.calls, 3);
    }
    ray_scene_free(s);
}
END_TEST

/* A material that traces nothing and shades white. */
static void white(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                  ray_rgb *out)
{
    (void)ud;
    (void)ctx;
    (void)a;
    out->r = out->g = out->b = 1;
}

/*
** Filters run for the renderer's rays too and count in
** ray_stats.filter_calls; a scene without filters makes no call (the
** ungated path), so its counter stays 0.
*/
START_TEST(filter_calls_should_be_counted_and_absent_without_filters)
{
    ray_material w = {white, NULL, 0, NULL};
    filter_log cut = {0, 0};
    ray_scene *s;
    ray_ctx *ctx;
    ray_stats st;
    ray_rgb c;
    unsigned mat, sph;
    int pass;

    for (pass = 0; pass < 2; pass++) {
        ray_ray r1 = ray_from(vec(-0.5, 0, 10), vec(0, 0, -1));
        ray_ray r2 = ray_from(vec(0.5, 0, 10), vec(0, 0, -1));
        ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_material(s, &w, &mat), RAY_OK);
        ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1, mat, &sph), RAY_OK);
        if (pass == 1)
            ck_assert_int_eq(ray_scene_set_filter(s, sph, cut_left, &cut, RAY_FILTER_INTERSECT), RAY_OK);
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        ck_assert_int_eq(ray_ctx_new(s, 1, &ctx), RAY_OK);
        ck_assert_int_eq(ray_trace(ctx, &r1, RAY_KIND_PRIMARY, 1, &c), RAY_OK);
        ck_assert_double_eq(c.r, pass == 0 ? 1.0 : 0.0);  /* cut away */
        ck_assert_int_eq(ray_trace(ctx, &r2, RAY_KIND_PRIMARY, 1, &c), RAY_OK);
        ck_assert_double_eq(c.r, 1.0);
        ray_ctx_stats(ctx, &st);
        /* Pass 1: r1 offers front and back (both x < 0), r2 its front. */
        ck_assert_uint_eq(st.filter_calls, pass == 0 ? 0 : 3);
        ck_assert_uint_eq(cut.calls, pass == 0 ? 0 : 3);
        ray_ctx_free(ctx);
        ray_scene_free(s);
    }
}
END_TEST

/* Every hit along r by brute force: each sphere's roots in turn (asked
** again past each hit, as the scene does) and each triangle once. */
static size_t brute_all(const ray_vec3 *c, size_t nc, const hc_mesh *mesh,
                        const ray_ray *r, double *t)
{
    size_t n = 0, i;

    for (i = 0; i < nc; i++) {
        ray_ray rr = *r;
        ray_hit h;
        while (ray_sphere(&rr, c[i], 0.7, &h) == 1) {
            t[n++] = h.t;
            rr.tmin = h.t;
        }
    }
    for (i = 0; i < mesh->nt; i++) {
        const unsigned *x = mesh->idx + 3 * i;
        ray_hit h;
        if (ray_triangle_watertight(r, mesh->v[x[0]], mesh->v[x[1]], mesh->v[x[2]], &h) == 1)
            t[n++] = h.t;
    }
    return n;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/*
** ray_intersect_all against brute force: 30 spheres and a closed
** icosphere; random rays; the same number of hits and the same t's, bit
** for bit, in order (the same tests on the same primitives).  With less
** room than hits, the nearest ones come back and the count is the total.
*/
START_TEST(all_hits_should_match_brute_force)
{
    hc_mesh ball = hc_icosphere(vec(0, 0, 0), 2);
    ray_mesh m = hc_ray_mesh(&ball);
    ray_vec3 centres[30];
    ray_scene *s;
    rng g = {23};
    size_t i, total = 0;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, NULL), RAY_OK);
    for (i = 0; i < 30; i++) {
        centres[i] = vec(rng_range(&g, -6, 6), rng_range(&g, -3, 3), rng_range(&g, -3, 3));
        ck_assert_int_eq(ray_scene_add_sphere(s, centres[i], 0.7, RAY_NO_MATERIAL, NULL), RAY_OK);
    }
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    for (i = 0; i < 2000; i++) {
        ray_ray r = random_ray(&g);
        ray_hit hits[128], few[3];
        double want[128];
        size_t n = brute_all(centres, 30, &ball, &r, want), got = 999, k;
        ck_assert_int_eq(ray_intersect_all(s, &r, NULL, hits, 128, &got), (int)n);
        ck_assert_uint_eq(got, n);
        qsort(want, n, sizeof *want, cmp_double);
        for (k = 0; k < n; k++)
            ck_assert(hits[k].t == want[k]);
        ck_assert_int_eq(ray_intersect_all(s, &r, NULL, few, 3, &got), (int)n);
        for (k = 0; k < 3 && k < n; k++)
            ck_assert(hit_same(&few[k], &hits[k]));
        total += n;
    }
    ck_assert_uint_gt(total, 2000);
    {
        ray_ray r = random_ray(&g);
        size_t got;
        ck_assert_int_eq(ray_intersect_all(s, &r, NULL, NULL, 1, &got), -RAY_EINVAL);
        ck_assert_int_eq(ray_intersect_all(s, &r, NULL, NULL, 0, NULL), -RAY_EINVAL);
        ck_assert_int_ge(ray_intersect_all(s, &r, NULL, NULL, 0, &got), 0);
        ck_assert_int_eq(ray_intersect_all(NULL, &r, NULL, NULL, 0, &got), -RAY_EINVAL);
    }
    ray_scene_free(s);
    hc_mesh_free(&ball);
}
END_TEST

/* The ray's t down onto the quad of the test below, or -1 for a miss. */
static double quad_t(const ray_scene *s, double x, double y)
{
    ray_ray r;
    ray_hit h;

    r.org = vec(x, y, 5);
    r.dir = vec(0, 0, -1);
    r.tmin = 0;
    r.tmax = HUGE_VAL;
    return ray_intersect(s, &r, &h, NULL) == 1 ? h.t : -1;
}

/*
** Issue 38: a mesh with normals and texture coordinates.  Refused
** (RAY_EINVAL, the message naming the vertex) with a normal or either
** texture coordinate not finite, for add and update alike.  Updated with
** the same layout (positions, normals and texture coordinates, copied:
** written over the arrays it keeps) and then with another (one vertex
** more, unused; then without texture coordinates: copied afresh), each
** after its commit answers at its new height: the quad z = h, hit from
** z = 5 at t = 5 - h exactly (h and 5 - h are exact in doubles).
*/
START_TEST(mesh_updates_should_carry_normals_and_texcoords)
{
    static const unsigned idx[6] = {0, 1, 2, 0, 2, 3};
    ray_vec3 v[5], n[5], bad_n[5];
    double uv[10], bad_uv[10];
    ray_scene *s;
    ray_mesh m, bad;
    unsigned id;
    int k;

    for (k = 0; k < 5; k++) {
        v[k] = vec(k == 1 || k == 2 ? 1 : -1, k >= 2 ? 1 : -1, 0);
        n[k] = vec(0, 0, 1);
        uv[2 * k] = v[k].x, uv[2 * k + 1] = v[k].y;
    }
    memcpy(bad_n, n, sizeof n);
    memcpy(bad_uv, uv, sizeof uv);
    memset(&m, 0, sizeof m);
    m.vertices = v;
    m.vertex_count = 4;
    m.indices = idx;
    m.triangle_count = 2;
    m.normals = n;
    m.texcoords = uv;
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    bad = m, bad.normals = bad_n, bad_n[1].y = (double)NAN;
    ck_assert_int_eq(ray_scene_add_mesh(s, &bad, RAY_NO_MATERIAL, &id), RAY_EINVAL);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(s), "normal 1"));
    bad = m, bad.texcoords = bad_uv, bad_uv[4] = HUGE_VAL;
    ck_assert_int_eq(ray_scene_add_mesh(s, &bad, RAY_NO_MATERIAL, &id), RAY_EINVAL);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(s), "texture coordinates 2"));
    bad_uv[4] = uv[4], bad_uv[7] = (double)NAN;
    ck_assert_int_eq(ray_scene_add_mesh(s, &bad, RAY_NO_MATERIAL, &id), RAY_EINVAL);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(s), "texture coordinates 3"));
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, &id), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert(quad_t(s, 0.25, 0.5) == 5);
    /* The same layout: written over. */
    for (k = 0; k < 5; k++)
        v[k].z = 1, n[k] = vec(0, 0.6, 0.8);
    ck_assert_int_eq(ray_scene_update_mesh(s, id, &bad), RAY_EINVAL);
    ck_assert_int_eq(ray_scene_update_mesh(s, id, &m), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert(quad_t(s, 0.25, 0.5) == 4);
    /* One vertex more: copied afresh. */
    for (k = 0; k < 5; k++)
        v[k].z = 2;
    m.vertex_count = 5;
    ck_assert_int_eq(ray_scene_update_mesh(s, id, &m), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert(quad_t(s, 0.25, 0.5) == 3);
    /* Without texture coordinates: copied afresh again. */
    for (k = 0; k < 5; k++)
        v[k].z = 3;
    m.texcoords = NULL;
    ck_assert_int_eq(ray_scene_update_mesh(s, id, &m), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert(quad_t(s, 0.25, 0.5) == 2);
    ck_assert(quad_t(s, 1.5, 0.5) == -1);
    ray_scene_free(s);
}
END_TEST

Suite *dynamic_suite(void)
{
    Suite *s = suite_create("dynamic");
    TCase *tc = tcase_create("core");

    tcase_add_test(tc, refit_should_answer_as_a_rebuild);
    tcase_add_test(tc, refit_should_follow_new_indices);
    tcase_add_test(tc, borrowed_mesh_should_be_read_again_in_place);
    tcase_add_test(tc, geometry_should_come_and_go_after_commit);
    tcase_add_test(tc, updates_should_refuse_bad_input);
    tcase_add_test(tc, masks_should_pick_geometry_by_shared_bits);
    tcase_add_test(tc, filters_should_reject_candidates_exactly);
    tcase_add_test(tc, filters_should_see_their_candidate_inside_the_ray);
    tcase_add_test(tc, filter_calls_should_be_counted_and_absent_without_filters);
    tcase_add_test(tc, all_hits_should_match_brute_force);
    tcase_add_test(tc, mesh_updates_should_carry_normals_and_texcoords);
    suite_add_tcase(s, tc);
    return s;
}
