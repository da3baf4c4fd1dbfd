/* SPDX-License-Identifier: MIT */
/*
** check_games.c -- what a game or tool embedding the library needs of the
** scene API: geometry without materials (RAY_NO_MATERIAL), queried from
** the calling thread, rendered black; vertex input as games keep it
** (strided float positions, 16-bit indices) giving the same hits as
** doubles and no leaks.
*/
#include <string.h>
#include <stdint.h>
#include <stdlib.h>

#include "tests.h"
#include "hardcases.h"

/* A scene with no material at all: the cube [-1, 1]^3 (geometry 0) and a
** 320-triangle icosphere of radius 2 around (10, 0, 0) (geometry 1), both
** RAY_NO_MATERIAL, committed; *nt_sphere its triangle count. */
static ray_scene *unshaded_scene(size_t *nt_sphere)
{
    hc_mesh cube = hc_cube(vec(0, 0, 0));
    hc_mesh ball = hc_icosphere(vec(10, 0, 0), 2);
    ray_mesh m;
    ray_scene *s;
    unsigned id;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    m = hc_ray_mesh(&cube);
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, &id), RAY_OK);
    ck_assert_uint_eq(id, 0);
    m = hc_ray_mesh(&ball);
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, &id), RAY_OK);
    ck_assert_uint_eq(id, 1);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    *nt_sphere = ball.nt;
    hc_mesh_free(&cube);
    hc_mesh_free(&ball);
    return s;
}

/*
** Queries of material-less meshes.  The cube's top face (z = 1, face 1 of
** hc_cube: triangles 2 = (4, 5, 7) where x > y and 3 = (4, 7, 6) where
** x < y) seen from z = 10 straight down: t = 9 exactly (exact inputs, one
** subtraction).  The icosphere has a vertex on its z axis, (10, 0, 2),
** so a ray from 10 above its centre hits there: t = 8 within tol_at (a
** few dozen roundings of coordinates near 10).
*/
START_TEST(meshes_without_material_should_be_queried)
{
    size_t nt;
    ray_scene *s = unshaded_scene(&nt);
    ray_ray r = ray_from(vec(0.5, -0.5, 10), vec(0, 0, -1));
    ray_hit h;

    ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), 1);
    ck_assert_uint_eq(h.geom_id, 0);
    ck_assert_uint_eq(h.prim_id, 2);
    ck_assert(h.t == 9.0);
    r.org = vec(-0.5, 0.5, 10);
    ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), 1);
    ck_assert_uint_eq(h.geom_id, 0);
    ck_assert_uint_eq(h.prim_id, 3);
    r.org = vec(10, 0, 10);
    ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), 1);
    ck_assert_uint_eq(h.geom_id, 1);
    ck_assert_uint_lt(h.prim_id, nt);
    ck_assert_msg(fabs(h.t - 8.0) <= tol_at(10.0), "t %.17g", h.t);
    r.org = vec(5, 0, 10);
    ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), 0);
    /* Line of sight: through the cube is blocked, beside it is clear. */
    r = make_ray(vec(-5, 0, 0), vec(1, 0, 0), 0, 4.5);
    ck_assert_int_eq(ray_occluded(s, &r, NULL), 1);
    r.tmax = 3.5;
    ck_assert_int_eq(ray_occluded(s, &r, NULL), 0);
    ck_assert_uint_eq(ray_scene_effects(s), 0u);
    ray_scene_free(s);
}
END_TEST

/*
** Rendering them: every pixel is the background, bit for bit, or exact
** black where a mesh is hit (no material: nothing is shaded, nothing
** traced from it), with a light in the scene too (effects stay 0: no
** material asks for shadows).
*/
START_TEST(meshes_without_material_should_render_black)
{
    static const ray_rgb sky = {0.25, 0.5, 0.75};
    enum { W = 24, H = 16 };
    float img[3 * W * H];
    ray_render_options o;
    ray_camera cam;
    ray_light light;
    ray_stats st;
    ray_scene *s;
    long black = 0, background = 0;
    int i;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    {
        hc_mesh cube = hc_cube(vec(0, 0, 0));
        ray_mesh m = hc_ray_mesh(&cube);
        ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, NULL),
                         RAY_OK);
        hc_mesh_free(&cube);
    }
    ray_light_init(&light, RAY_LIGHT_POINT);
    light.position = vec(0, 0, 10);
    ck_assert_int_eq(ray_scene_add_light(s, &light, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_set_background(s, sky, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_uint_eq(ray_scene_effects(s), 0u);
    cam = (ray_camera){.look_at = {0, 0, -1}};
    cam.position = vec(0, 0, 8);
    cam.look_at = vec(0, 0, 0);
    cam.up = vec(0, 1, 0);
    cam.vfov = 30;
    o = (ray_render_options){.width = W, .height = H};
    o.threads = 2;
    ck_assert_int_eq(ray_render(s, &cam, &o, img, &st), RAY_OK);
    for (i = 0; i < W * H; i++) {
        const float *p = img + 3 * i;
        if (p[0] == 0.0f && p[1] == 0.0f && p[2] == 0.0f)
            black++;
        else if (p[0] == 0.25f && p[1] == 0.5f && p[2] == 0.75f)
            background++;
        else
            ck_abort_msg("pixel %d is (%g, %g, %g)", i, (double)p[0],
                         (double)p[1], (double)p[2]);
    }
    /* The centre pixel sees the cube, the corner the sky. */
    ck_assert(img[3 * (W * (H / 2) + W / 2)] == 0.0f);
    ck_assert(img[0] == 0.25f);
    ck_assert_int_gt(black, 0);
    ck_assert_int_gt(background, 0);
    ck_assert_uint_eq(st.rays[RAY_KIND_SHADOW], 0);
    ck_assert_uint_eq(st.rays[RAY_KIND_REFLECTION], 0);
    ray_scene_free(s);
}
END_TEST

/*
** Every geometry call takes RAY_NO_MATERIAL, and a scene mixing it with
** a real material keeps that material's effects only; a material id that
** does not exist is still refused.
*/
START_TEST(no_material_should_be_accepted_everywhere)
{
    static const ray_vec3 quad[4] = {{0, 0, 5}, {1, 0, 5}, {1, 1, 5},
                                     {0, 1, 5}};
    ray_material mirror = ray_material_mirror(NULL);
    ray_scene *s;
    unsigned mat;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1, 0, NULL),
                     RAY_EINVAL);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1,
                                          RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, -2, 0), vec(0, 1, 0),
                                         RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_triangle(s, vec(0, 0, 3), vec(1, 0, 3),
                                            vec(0, 1, 3), RAY_NO_MATERIAL,
                                            NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_polygon(s, quad, 4, RAY_NO_MATERIAL,
                                           NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &mirror, &mat), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(5, 0, 0), 1, mat, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    /* The mirror's reflection; its photon scattering is no effect of a
    ** scene without light or gatherer (ray_scene_effects). */
    ck_assert_uint_eq(ray_scene_effects(s), RAY_EFFECT_REFLECTION);
    ray_scene_free(s);
}
END_TEST

/* ------------------------------------------ vertex input as games keep it */

/* An interleaved game vertex: 32 bytes, the position first. */
typedef struct game_vertex {
    float pos[3], nrm[3], uv[2];
} game_vertex;

/*
** A hardcases.h mesh as a game keeps it: its vertices rounded to float,
** interleaved (game_vertex, stride 32) and packed (stride 0), its indices
** as 16- and 32-bit integers; dbl holds the doubles of those floats, the
** mesh that the float-sourced one must be.
*/
typedef struct game_mesh {
    game_vertex *vb;
    float *packed;
    uint16_t *i16;
    uint32_t *i32;
    ray_vec3 *dbl;
    const unsigned *idx;     /* the hc_mesh's own */
    size_t nv, nt;
    long rounded;            /* coordinates the rounding to float changed */
} game_mesh;

/* Is x a float value?  Decided without a float: its significand has at
** most 24 bits and its exponent is a float's (normal or zero here). */
static int is_float_value(double x)
{
    int e;
    double m = ldexp(frexp(x, &e), 24);

    return x == 0 || (m == floor(m) && e >= -125 && e <= 128);
}

static game_mesh game_mesh_of(const hc_mesh *h)
{
    game_mesh g;
    size_t i;
    int k;

    g.nv = h->nv;
    g.nt = h->nt;
    g.idx = h->idx;
    g.rounded = 0;
    g.vb = calloc(h->nv, sizeof *g.vb);
    g.packed = malloc(3 * h->nv * sizeof *g.packed);
    g.i16 = malloc(3 * h->nt * sizeof *g.i16);
    g.i32 = malloc(3 * h->nt * sizeof *g.i32);
    g.dbl = malloc(h->nv * sizeof *g.dbl);
    ck_assert(g.vb != NULL && g.packed != NULL && g.i16 != NULL &&
              g.i32 != NULL && g.dbl != NULL);
    ck_assert_uint_lt(h->nv, 65536);
    for (i = 0; i < h->nv; i++) {
        game_vertex *gv = &g.vb[i];
        gv->pos[0] = (float)h->v[i].x;
        gv->pos[1] = (float)h->v[i].y;
        gv->pos[2] = (float)h->v[i].z;
        gv->nrm[0] = -1.0f;      /* not a position: must be skipped */
        gv->uv[1] = 0.5f;
        memcpy(g.packed + 3 * i, gv->pos, sizeof gv->pos);
    }
    /*
    ** The doubles of the floats, read back through a volatile lvalue.
    ** Not (double)(float)x in one go, nor a plain load of the float just
    ** stored: GCC 12.2 at -O2 vectorises two such round trips (SLP) and
    ** then folds (vector double)(vector float)x into x, so the expected
    ** mesh silently became the unrounded one (a volatile load cannot be
    ** forwarded from the store).  is_float_value checks the result
    ** without any float arithmetic.
    */
    for (i = 0; i < h->nv; i++) {
        const volatile float *f = g.vb[i].pos;
        double c[3];
        for (k = 0; k < 3; k++) {
            c[k] = (double)f[k];
            ck_assert_msg(is_float_value(c[k]), "vertex %zu: %.17g", i,
                          c[k]);
        }
        g.dbl[i] = vec(c[0], c[1], c[2]);
        g.rounded += (c[0] != h->v[i].x) + (c[1] != h->v[i].y) +
                     (c[2] != h->v[i].z);
    }
    for (i = 0; i < 3 * h->nt; i++) {
        g.i16[i] = (uint16_t)h->idx[i];
        g.i32[i] = h->idx[i];
    }
    return g;
}

static void game_mesh_free(game_mesh *g)
{
    free(g->vb);
    free(g->packed);
    free(g->i16);
    free(g->i32);
    free(g->dbl);
}

/* The float-sourced ray_mesh of g: interleaved (stride 32) or packed
** (stride 0) positions, 16- or 32-bit indices. */
static ray_mesh game_ray_mesh(const game_mesh *g, int interleaved, int wide)
{
    ray_mesh m;

    memset(&m, 0, sizeof m);
    m.vertex_count = g->nv;
    m.triangle_count = g->nt;
    m.positions = interleaved ? (const void *)g->vb : (const void *)g->packed;
    m.position_stride = interleaved ? sizeof(game_vertex) : 0;
    m.position_type = RAY_FLOAT32;
    m.index_data = wide ? (const void *)g->i32 : (const void *)g->i16;
    m.index_type = wide ? RAY_UINT32 : RAY_UINT16;
    return m;
}

/* The same mesh as doubles: vertices and unsigned indices. */
static ray_mesh double_ray_mesh(const game_mesh *g)
{
    ray_mesh m;

    memset(&m, 0, sizeof m);
    m.vertices = g->dbl;
    m.vertex_count = g->nv;
    m.indices = g->idx;
    m.triangle_count = g->nt;
    return m;
}

/* A committed scene of the one mesh m, watertight or Cramer's rule. */
static ray_scene *scene_of_mesh(const ray_mesh *m, int watertight)
{
    ray_scene *s;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, m, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_set_watertight(s, watertight), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    return s;
}

static int same_bits(const void *a, const void *b, size_t n)
{
    return memcmp(a, b, n) == 0;
}

/* Two answers are the same bits: hit or miss, and every field of the hit
** (field by field: the padding is not compared). */
static void assert_same_hit(int hit_a, const ray_hit *a, int hit_b,
                            const ray_hit *b, long k)
{
    ck_assert_msg(hit_a == hit_b, "ray %ld: hit %d vs %d", k, hit_a, hit_b);
    if (hit_a != 1)
        return;
    ck_assert_msg(same_bits(&a->t, &b->t, sizeof a->t) &&
                  same_bits(&a->p, &b->p, sizeof a->p) &&
                  same_bits(&a->n, &b->n, sizeof a->n) &&
                  same_bits(&a->u, &b->u, sizeof a->u) &&
                  same_bits(&a->v, &b->v, sizeof a->v) &&
                  same_bits(&a->p_err, &b->p_err, sizeof a->p_err) &&
                  a->prim_id == b->prim_id && a->geom_id == b->geom_id,
                  "ray %ld: t %.17g vs %.17g, prim %u vs %u", k, a->t, b->t,
                  a->prim_id, b->prim_id);
}

/*
** A closed 1280-triangle icosphere of radius 2 around (1000.3, -300.7,
** 700.1), given as floats (interleaved with other attributes, stride 32,
** or packed) with 16- or 32-bit indices, against the same mesh given as
** the doubles of those floats: floats convert exactly, so every answer
** must be the same bits (t, p, n, u, v, p_err, ids; hit or miss, and
** ray_occluded's), no tolerance.  20,000 rays from inside and outside,
** some missing; watertight test (_i even) and Cramer's rule (_i odd).
** The floats must differ from the mesh's doubles (most coordinates), or
** the conversion would not be tested.
*/
START_TEST(float_mesh_should_hit_as_its_doubles)
{
    int watertight = !(_i & 1), interleaved = !(_i & 2), wide = (_i & 4) != 0;
    ray_vec3 c = vec(1000.3, -300.7, 700.1);
    hc_mesh h = hc_icosphere(c, 3);
    game_mesh g = game_mesh_of(&h);
    ray_mesh fm = game_ray_mesh(&g, interleaved, wide),
             dm = double_ray_mesh(&g);
    ray_scene *sf = scene_of_mesh(&fm, watertight),
              *sd = scene_of_mesh(&dm, watertight);
    rng r = {16 + (uint64_t)_i};
    long k, hits = 0;

    ck_assert_int_gt(g.rounded, (long)(2 * h.nv));
    for (k = 0; k < 20000; k++) {
        /* From 1.5 (inside) or 5 (outside) away, toward a point within 2.5
        ** of the centre (so some rays miss). */
        ray_vec3 org = vadd(c, vscale(rng_dir(&r), (k & 1) ? 1.5 : 5.0));
        ray_vec3 to = vadd(c, vscale(rng_dir(&r), 2.5 * rng_unit(&r)));
        ray_ray ray = ray_from(org, vsub(to, org));
        ray_hit a, b;
        int ha = ray_intersect(sf, &ray, &a, NULL),
            hb = ray_intersect(sd, &ray, &b, NULL);
        assert_same_hit(ha, &a, hb, &b, k);
        ck_assert_int_eq(ray_occluded(sf, &ray, NULL),
                         ray_occluded(sd, &ray, NULL));
        hits += ha == 1;
    }
    ck_assert_int_gt(hits, 10000);
    ck_assert_int_lt(hits, 20000);
    ray_scene_free(sf);
    ray_scene_free(sd);
    game_mesh_free(&g);
    hc_mesh_free(&h);
}
END_TEST

/*
** The leak test of check_numerics.c on float-sourced meshes: a cube and a
** 1280-triangle icosphere, rounded to float (centres off the float grid,
** so their coordinates do round), interleaved (stride 32), 16-bit
** indices, at three places up to Embree's (148376, 1234, -223423); from
** inside (within 0.9 of the centre, inside both shapes however the
** rounding moved their vertices: it moves them by 2^-24 of their
** coordinates, under 0.01), 40,000 rays each aimed exactly at the
** vertices of the mesh (the doubles of its floats: the mesh that is
** traced) and at points of its shared edges.  The watertight test must
** let none through: the float-sourced mesh is closed as its doubles are.
** Cramer's rule, which promises no such thing, must let some through on
** the same rays (7,680 of the 240,000), or they would not be hard ones.
*/
START_TEST(float_meshes_should_never_leak)
{
    ray_vec3 centres[3];
    long cramer = 0;
    int ci, mi;

    centres[0] = vec(0.3, -0.7, 0.1);
    centres[1] = vec(1e5 + 0.3, -3e4 - 0.7, 7e4 + 0.1);
    centres[2] = vec(148376.3, 1234.7, -223423.1);
    for (ci = 0; ci < 3; ci++)
        for (mi = 0; mi < 2; mi++) {
            ray_vec3 c = centres[ci];
            hc_mesh h = mi ? hc_icosphere(c, 3) : hc_cube(c);
            game_mesh g = game_mesh_of(&h);
            ray_mesh fm = game_ray_mesh(&g, 1, 0);
            ray_scene *s = scene_of_mesh(&fm, 1),
                      *sc = scene_of_mesh(&fm, 0);
            rng r = {(uint64_t)(40 + 2 * ci + mi)};
            long k, leaks = 0;

            ck_assert_int_gt(g.rounded, 0);
            for (k = 0; k < 40000; k++) {
                size_t ti = (size_t)(rng_unit(&r) * (double)g.nt) % g.nt;
                unsigned e = (unsigned)(rng_unit(&r) * 3) % 3;
                ray_vec3 a = g.dbl[g.idx[3 * ti + e]],
                         b = g.dbl[g.idx[3 * ti + (e + 1) % 3]];
                double f = (k & 1) ? rng_unit(&r) : 0.0;
                ray_vec3 target = vadd(vscale(a, 1 - f), vscale(b, f));
                ray_vec3 org = vadd(c, vscale(rng_dir(&r),
                                              0.9 * rng_unit(&r)));
                ray_ray ray = ray_from(org, vsub(target, org));
                ray_hit hit;
                leaks += ray_intersect(s, &ray, &hit, NULL) != 1;
                cramer += ray_intersect(sc, &ray, &hit, NULL) != 1;
            }
            ck_assert_msg(leaks == 0, "%s at centre %d: %ld leaks",
                          mi ? "icosphere" : "cube", ci, leaks);
            ray_scene_free(s);
            ray_scene_free(sc);
            game_mesh_free(&g);
            hc_mesh_free(&h);
        }
    /* The rays are hard ones: Cramer's rule lets some through. */
    ck_assert_int_gt(cramer, 0);
}
END_TEST

/*
** Every layout gives the same mesh: the cube around (0.3, -0.7, 0.1) as
** the doubles of its floats (vertices, indices) is the reference; then
** floats packed, floats in game_vertex (stride 32), floats at an odd
** stride (13: unaligned), doubles packed, doubles beside a tag (stride
** 40), doubles at an odd stride (25), each with 16- or 32-bit indices
** (also unaligned: one byte into the buffer).  Rays aimed at the
** centroid of each triangle from outside, and 300 random rays through
** the cube, must give the reference's answers bit for bit, and every
** triangle must be hit.
*/
START_TEST(every_layout_should_give_the_same_mesh)
{
    static const size_t strides[6] = {0, 32, 13, 0, 40, 25};
    ray_vec3 c = vec(0.3, -0.7, 0.1);
    hc_mesh h = hc_cube(c);
    game_mesh g = game_mesh_of(&h);
    ray_mesh ref = double_ray_mesh(&g);
    ray_scene *sr = scene_of_mesh(&ref, 1);
    unsigned char vbuf[8 * 40 + 8], ibuf[36 * 4 + 1];
    int layout, wide;
    size_t i;

    for (layout = 0; layout < 6; layout++)
        for (wide = 0; wide < 2; wide++) {
            int dbl = layout >= 3;
            size_t stride = strides[layout];
            size_t step = stride ? stride : (dbl ? 24u : 12u);
            ray_mesh m;
            ray_scene *s;
            rng r = {7};
            long k;
            int hit_tri[12] = {0};

            memset(vbuf, 0xA5, sizeof vbuf);     /* the bytes between */
            for (i = 0; i < 8; i++) {
                if (dbl) {
                    double p[3];
                    p[0] = g.dbl[i].x, p[1] = g.dbl[i].y, p[2] = g.dbl[i].z;
                    memcpy(vbuf + i * step, p, sizeof p);
                } else
                    memcpy(vbuf + i * step, g.vb[i].pos, sizeof g.vb[i].pos);
            }
            for (i = 0; i < 36; i++) {
                if (wide)
                    memcpy(ibuf + 1 + 4 * i, &g.i32[i], 4);
                else
                    memcpy(ibuf + 1 + 2 * i, &g.i16[i], 2);
            }
            memset(&m, 0, sizeof m);
            m.positions = vbuf;
            m.position_stride = stride;
            m.position_type = dbl ? RAY_FLOAT64 : RAY_FLOAT32;
            m.vertex_count = 8;
            m.index_data = ibuf + 1;
            m.index_type = wide ? RAY_UINT32 : RAY_UINT16;
            m.triangle_count = 12;
            s = scene_of_mesh(&m, 1);
            for (k = 0; k < 12 + 300; k++) {
                ray_vec3 org, to;
                ray_ray ray;
                ray_hit a, b;
                int ha, hb;
                if (k < 12) {
                    const unsigned *t = g.idx + 3 * k;
                    ray_vec3 n;
                    to = vscale(vadd(vadd(g.dbl[t[0]], g.dbl[t[1]]),
                                     g.dbl[t[2]]), 1.0 / 3);
                    n = vcross(vsub(g.dbl[t[1]], g.dbl[t[0]]),
                               vsub(g.dbl[t[2]], g.dbl[t[0]]));
                    org = vadd(to, vscale(n, 2.0 / vlen(n)));
                } else {
                    org = vadd(c, vscale(rng_dir(&r), 4));
                    to = vadd(c, vscale(rng_dir(&r), rng_unit(&r)));
                }
                ray = ray_from(org, vsub(to, org));
                ha = ray_intersect(s, &ray, &a, NULL);
                hb = ray_intersect(sr, &ray, &b, NULL);
                ck_assert_int_eq(ha, 1);
                assert_same_hit(ha, &a, hb, &b, k);
                if (k < 12)
                    ck_assert_uint_eq(a.prim_id, (unsigned)k);
                hit_tri[a.prim_id] = 1;
            }
            for (i = 0; i < 12; i++)
                ck_assert_msg(hit_tri[i], "layout %d wide %d: triangle %zu",
                              layout, wide, i);
            ray_scene_free(s);
        }
    ray_scene_free(sr);
    game_mesh_free(&g);
    hc_mesh_free(&h);
}
END_TEST

/*
** vertices and indices, when given, are what is read: positions and
** index_data are then ignored whatever they hold (here a type of 0, a
** stride of 1 and NaN bytes), and the mesh is the one of vertices.
*/
START_TEST(vertices_and_indices_should_win_over_positions)
{
    static const ray_vec3 v[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    static const unsigned idx[3] = {0, 1, 2};
    unsigned char junk[64];
    ray_mesh m;
    ray_scene *s;
    ray_hit hit;
    ray_ray r = ray_from(vec(0.25, 0.25, 1), vec(0, 0, -1));
    double nan = (double)NAN;
    size_t i;

    for (i = 0; i + sizeof nan <= sizeof junk; i += sizeof nan)
        memcpy(junk + i, &nan, sizeof nan);
    memset(&m, 0, sizeof m);
    m.vertices = v;
    m.vertex_count = 3;
    m.indices = idx;
    m.triangle_count = 1;
    m.positions = junk;
    m.position_stride = 1;
    m.index_data = junk;
    s = scene_of_mesh(&m, 1);
    ck_assert_int_eq(ray_intersect(s, &r, &hit, NULL), 1);
    ck_assert(hit.t == 1.0);
    ck_assert_uint_eq(hit.prim_id, 0);
    ray_scene_free(s);
}
END_TEST

/*
** Size and range limits of the game layout, where ray_scene_errmsg's
** numbers depend on the platform's size_t (check_errmsg.c has the rest):
** positions whose last byte lies beyond size_t, refused before any is
** read (the pointer is to one float: reading would fault), with nothing
** added; the largest 16-bit index, 65535, accepted with 65536 vertices.
*/
START_TEST(game_layout_limits_should_hold)
{
    static const float one[3] = {0, 0, 0};
    static const uint16_t top[3] = {0, 65535, 1};
    ray_mesh m;
    ray_scene *s;
    float *big;
    unsigned id;
    size_t i;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    memset(&m, 0, sizeof m);
    m.positions = one;
    m.position_type = RAY_FLOAT32;
    m.position_stride = 32;
    m.vertex_count = (size_t)-1 / 16;
    m.index_data = top;
    m.index_type = RAY_UINT16;
    m.triangle_count = 1;
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, NULL),
                     RAY_EINVAL);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(s),
                                 "positions overflow size_t"));
    m.position_stride = 0;       /* packed: 12 bytes a position */
    m.vertex_count = (size_t)-1 / 8;
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, NULL),
                     RAY_EINVAL);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(s),
                                 "positions overflow size_t"));
    big = calloc(3 * 65536, sizeof *big);
    ck_assert_ptr_nonnull(big);
    for (i = 0; i < 65536; i++)
        big[3 * i] = (float)i;   /* exact: integers below 2^24 */
    big[3 * 65535 + 1] = 1;
    m.positions = big;
    m.vertex_count = 65536;
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, &id),
                     RAY_OK);
    ck_assert_uint_eq(id, 0);    /* the failures added nothing */
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    {
        /* The triangle (0,0,0), (65535,1,0), (1,0,0): its point of
        ** barycentrics u = 1/4, v = 1/2 is (16384.25, 0.25, 0), met at
        ** t = 2 exactly (every vertex has z = 0, the ray runs down z). */
        ray_ray r = ray_from(vec(16384.25, 0.25, 2), vec(0, 0, -1));
        ray_hit hit;
        ck_assert_int_eq(ray_intersect(s, &r, &hit, NULL), 1);
        ck_assert(hit.t == 2.0);
    }
    ray_scene_free(s);
    free(big);
}
END_TEST

/* Trace r in a scene of the one mesh m, shaded by shade_record: what it saw. */
static shade_seen shade_mesh(const ray_mesh *m, const ray_ray *r)
{
    shade_seen got;
    ray_material mat;
    ray_scene *s;
    ray_ctx *ctx;
    ray_rgb c;
    unsigned id;

    memset(&got, 0, sizeof got);
    mat.shade = shade_record;
    mat.ud = &got;
    mat.effects = RAY_EFFECT_TEXTURE;   /* else (s, t) is not interpolated */
    mat.scatter = NULL;
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &mat, &id), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, m, id, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(s, 0, &ctx), RAY_OK);
    ck_assert_int_eq(ray_trace(ctx, r, RAY_KIND_PRIMARY, 1.0, &c), RAY_OK);
    ray_ctx_free(ctx);
    ray_scene_free(s);
    return got;
}

/*
** Normals and texture coordinates stay double arrays, indexed as the
** vertices: with float positions and 16- or 32-bit indices (kept for
** shading as unsigned), the material sees bit for bit what it sees with
** the same mesh as vertices and indices, on both triangles of a quad.
*/
START_TEST(game_mesh_should_shade_as_vertices)
{
    static const game_vertex vb[4] = {
        {{0, 0, 0}, {0}, {0}}, {{2, 0, 0}, {0}, {0}},
        {{2, 2, 0}, {0}, {0}}, {{0, 2, 0}, {0}, {0}}};
    static const ray_vec3 v[4] = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0},
                                  {0, 2, 0}};
    static const ray_vec3 n[4] = {{-1, -1, 1}, {1, -1, 1}, {1, 1, 1},
                                  {-1, 1, 1}};
    static const double st[8] = {0, 0, 1, 0, 1, 1, 0, 1};
    static const unsigned idx[6] = {0, 1, 2, 0, 2, 3};
    static const uint16_t i16[6] = {0, 1, 2, 0, 2, 3};
    static const uint32_t i32[6] = {0, 1, 2, 0, 2, 3};
    ray_mesh ref, gm;
    int wide, k;

    memset(&ref, 0, sizeof ref);
    ref.vertices = v;
    ref.vertex_count = 4;
    ref.indices = idx;
    ref.triangle_count = 2;
    ref.normals = n;
    ref.texcoords = st;
    for (wide = 0; wide < 2; wide++) {
        gm = ref;
        gm.vertices = NULL;
        gm.indices = NULL;
        gm.positions = vb;
        gm.position_stride = sizeof vb[0];
        gm.position_type = RAY_FLOAT32;
        gm.index_data = wide ? (const void *)i32 : (const void *)i16;
        gm.index_type = wide ? RAY_UINT32 : RAY_UINT16;
        for (k = 0; k < 2; k++) {
            ray_ray r = ray_from(k ? vec(0.5, 1.5, 3) : vec(1.5, 0.5, 3),
                                 vec(0, 0, -1));
            shade_seen a = shade_mesh(&gm, &r), b = shade_mesh(&ref, &r);
            ck_assert_uint_eq(a.prim_id, (unsigned)k);
            ck_assert_uint_eq(b.prim_id, (unsigned)k);
            ck_assert(same_bits(&a.shading_normal, &b.shading_normal,
                                sizeof a.shading_normal));
            ck_assert(same_bits(&a.normal, &b.normal, sizeof a.normal));
            ck_assert(same_bits(&a.u, &b.u, sizeof a.u));
            ck_assert(same_bits(&a.v, &b.v, sizeof a.v));
            /* And it is the interpolation, not the default: at (1.5,
            ** 0.5) (s, t) = (0.75, 0.25), at (0.5, 1.5) (0.25, 0.75). */
            ck_assert_double_eq_tol(a.u, k ? 0.25 : 0.75, 1e-12);
            ck_assert_double_eq_tol(a.v, k ? 0.75 : 0.25, 1e-12);
        }
    }
}
END_TEST

Suite *games_suite(void)
{
    Suite *su = suite_create("games");
    TCase *nomat = tcase_create("no_material");
    TCase *input = tcase_create("vertex_input");

    tcase_add_test(nomat, meshes_without_material_should_be_queried);
    tcase_add_test(nomat, meshes_without_material_should_render_black);
    tcase_add_test(nomat, no_material_should_be_accepted_everywhere);
    suite_add_tcase(su, nomat);
    tcase_add_loop_test(input, float_mesh_should_hit_as_its_doubles, 0, 8);
    tcase_add_test(input, float_meshes_should_never_leak);
    tcase_add_test(input, every_layout_should_give_the_same_mesh);
    tcase_add_test(input, vertices_and_indices_should_win_over_positions);
    tcase_add_test(input, game_layout_limits_should_hold);
    tcase_add_test(input, game_mesh_should_shade_as_vertices);
    suite_add_tcase(su, input);
    return su;
}
