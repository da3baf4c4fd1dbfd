/* SPDX-License-Identifier: MIT */
/*
** check_errmsg.c -- ray_scene_errmsg: every validation path of every
** building call leaves its status and a message that names the argument,
** index or value at fault; a success clears it; a committed scene, a NULL
** scene and out-of-memory failures are reported too.
*/
#include <string.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "tests.h"

/* ------------------------------------------------ valid inputs to break */

/* One triangle over three vertices, with normals and texture coordinates,
** copied so that a case can break one field of its own copy. */
typedef struct mesh_data {
    ray_vec3 v[3], n[3];
    double tex[6];
    unsigned idx[6];
    ray_mesh m;
} mesh_data;

static void mesh_init(mesh_data *d)
{
    int i;

    memset(&d->m, 0, sizeof d->m);
    d->v[0] = vec(0, 0, 0);
    d->v[1] = vec(1, 0, 0);
    d->v[2] = vec(0, 1, 0);
    for (i = 0; i < 3; i++)
        d->n[i] = vec(0, 0, 1);
    for (i = 0; i < 6; i++) {
        d->tex[i] = 0.5;
        d->idx[i] = (unsigned)(i % 3);
    }
    d->m.vertices = d->v;
    d->m.vertex_count = 3;
    d->m.indices = d->idx;
    d->m.triangle_count = 2;
    d->m.normals = d->n;
    d->m.texcoords = d->tex;
}

static double ball(void *ud, ray_vec3 p)
{
    (void)ud;
    return p.x * p.x + p.y * p.y + p.z * p.z - 1;
}

static ray_implicit_surface implicit_ok(void)
{
    ray_implicit_surface is;

    memset(&is, 0, sizeof is);
    is.f = ball;
    is.lo = vec(-1, -1, -1);
    is.hi = vec(1, 1, 1);
    return is;
}

static void flat_eval(void *ud, double u, double v, ray_vec3 *p,
                      ray_vec3 *pu, ray_vec3 *pv)
{
    (void)ud;
    *p = vec(u, v, 0);
    *pu = vec(1, 0, 0);
    *pv = vec(0, 1, 0);
}

static void flat_bounds(void *ud, double u0, double u1, double v0,
                        double v1, ray_vec3 *lo, ray_vec3 *hi)
{
    (void)ud;
    *lo = vec(u0, v0, 0);
    *hi = vec(u1, v1, 0);
}

/* A bounds callback that lies: the scene must say so. */
static void nan_bounds(void *ud, double u0, double u1, double v0,
                       double v1, ray_vec3 *lo, ray_vec3 *hi)
{
    (void)ud;
    (void)u1;
    (void)v1;
    *lo = vec(u0, v0, (double)NAN);
    *hi = vec(1, 1, 0);
}

static ray_parametric_surface parametric_ok(void)
{
    ray_parametric_surface ps;

    memset(&ps, 0, sizeof ps);
    ps.eval = flat_eval;
    ps.bounds = flat_bounds;
    return ps;
}

static ray_torus_params torus_ok(void)
{
    ray_torus_params t;

    t.center = vec(0, 0, 0);
    t.axis = vec(0, 0, 1);
    t.major = 2;
    t.minor = 0.5;
    return t;
}

static void bezier_ok(ray_vec3 cp[16])
{
    int i;

    for (i = 0; i < 16; i++)
        cp[i] = vec(i % 4, i / 4, 0);
}

static ray_light light_ok(int kind)
{
    ray_light l;

    memset(&l, 0, sizeof l);
    l.kind = kind;
    l.direction = vec(0, -1, 0);
    l.edge1 = vec(1, 0, 0);
    l.edge2 = vec(0, 0, 1);
    l.radius = 1;
    l.intensity.r = l.intensity.g = l.intensity.b = 1;
    return l;
}

/* ------------------------------------------------------------ the cases */

/* Each case makes one failing call on a scene that has material 0 only. */
typedef int (*failing_call)(ray_scene *s);

static int material_null(ray_scene *s)
{
    return ray_scene_add_material(s, NULL, NULL);
}

static int material_no_shade(ray_scene *s)
{
    ray_material m = plain();
    m.shade = NULL;
    return ray_scene_add_material(s, &m, NULL);
}

static int material_bad_effects(ray_scene *s)
{
    ray_material m = plain();
    m.effects = 0xc1;   /* 0x40 and 0x80 unknown, 1 known */
    return ray_scene_add_material(s, &m, NULL);
}

static int sphere_nan_center(ray_scene *s)
{
    return ray_scene_add_sphere(s, vec(0, (double)NAN, 0), 1, 0, NULL);
}

static int sphere_negative_radius(ray_scene *s)
{
    return ray_scene_add_sphere(s, vec(0, 0, 0), -1, 0, NULL);
}

static int sphere_infinite_radius(ray_scene *s)
{
    return ray_scene_add_sphere(s, vec(0, 0, 0), HUGE_VAL, 0, NULL);
}

static int sphere_unknown_material(ray_scene *s)
{
    return ray_scene_add_sphere(s, vec(0, 0, 0), 1, 5, NULL);
}

static int plane_infinite_point(ray_scene *s)
{
    return ray_scene_add_plane(s, vec(0, HUGE_VAL, 0), vec(0, 1, 0), 0, NULL);
}

static int plane_zero_normal(ray_scene *s)
{
    return ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 0, 0), 0, NULL);
}

static int plane_nan_normal(ray_scene *s)
{
    return ray_scene_add_plane(s, vec(0, 0, 0), vec((double)NAN, 1, 0), 0, NULL);
}

static int plane_unknown_material(ray_scene *s)
{
    return ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 1, 0), 1, NULL);
}

static int triangle_nan_vertex(ray_scene *s)
{
    return ray_scene_add_triangle(s, vec(0, 0, 0), vec(1, (double)NAN, 0),
                                  vec(0, 1, 0), 0, NULL);
}

static int triangle_collinear(ray_scene *s)
{
    return ray_scene_add_triangle(s, vec(0, 0, 0), vec(1, 0, 0),
                                  vec(2, 0, 0), 0, NULL);
}

static int triangle_unknown_material(ray_scene *s)
{
    return ray_scene_add_triangle(s, vec(0, 0, 0), vec(1, 0, 0),
                                  vec(0, 1, 0), 2, NULL);
}

static const ray_vec3 quad[4] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};

static int polygon_null(ray_scene *s)
{
    return ray_scene_add_polygon(s, NULL, 4, 0, NULL);
}

static int polygon_two_vertices(ray_scene *s)
{
    return ray_scene_add_polygon(s, quad, 2, 0, NULL);
}

static int polygon_infinite_vertex(ray_scene *s)
{
    ray_vec3 v[4];
    memcpy(v, quad, sizeof v);
    v[2].z = -HUGE_VAL;
    return ray_scene_add_polygon(s, v, 4, 0, NULL);
}

static int polygon_zero_area(ray_scene *s)
{
    ray_vec3 line[3] = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}};
    return ray_scene_add_polygon(s, line, 3, 0, NULL);
}

static int polygon_unknown_material(ray_scene *s)
{
    return ray_scene_add_polygon(s, quad, 4, 3, NULL);
}

static int mesh_null(ray_scene *s)
{
    return ray_scene_add_mesh(s, NULL, 0, NULL);
}

static int mesh_null_vertices(ray_scene *s)
{
    mesh_data d;
    mesh_init(&d);
    d.m.vertices = NULL;
    return ray_scene_add_mesh(s, &d.m, 0, NULL);
}

static int mesh_null_indices(ray_scene *s)
{
    mesh_data d;
    mesh_init(&d);
    d.m.indices = NULL;
    return ray_scene_add_mesh(s, &d.m, 0, NULL);
}

/* One triangle as a game keeps it: float positions, each followed by a
** fourth float (stride 16), and 16-bit indices. */
typedef struct game_mesh_data {
    float v[3][4];
    uint16_t idx[3];
    ray_mesh m;
} game_mesh_data;

static void game_mesh_init(game_mesh_data *d)
{
    static const float v[3][4] = {{0, 0, 0, 1}, {1, 0, 0, 1}, {0, 1, 0, 1}};
    int i;

    memcpy(d->v, v, sizeof v);
    for (i = 0; i < 3; i++)
        d->idx[i] = (uint16_t)i;
    memset(&d->m, 0, sizeof d->m);
    d->m.positions = d->v;
    d->m.position_stride = sizeof d->v[0];
    d->m.position_type = RAY_FLOAT32;
    d->m.vertex_count = 3;
    d->m.index_data = d->idx;
    d->m.index_type = RAY_UINT16;
    d->m.triangle_count = 1;
}

static int game_mesh_short_stride(ray_scene *s)
{
    game_mesh_data d;
    game_mesh_init(&d);
    d.m.position_stride = 8;
    return ray_scene_add_mesh(s, &d.m, 0, NULL);
}

static int game_mesh_null_positions(ray_scene *s)
{
    game_mesh_data d;
    game_mesh_init(&d);
    d.m.positions = NULL;
    return ray_scene_add_mesh(s, &d.m, 0, NULL);
}

static int game_mesh_no_position_type(ray_scene *s)
{
    game_mesh_data d;
    game_mesh_init(&d);
    d.m.position_type = 0;
    return ray_scene_add_mesh(s, &d.m, 0, NULL);
}

static int game_mesh_bad_index_type(ray_scene *s)
{
    game_mesh_data d;
    game_mesh_init(&d);
    d.m.index_type = RAY_FLOAT32;
    return ray_scene_add_mesh(s, &d.m, 0, NULL);
}

static int game_mesh_null_index_data(ray_scene *s)
{
    game_mesh_data d;
    game_mesh_init(&d);
    d.m.index_data = NULL;
    return ray_scene_add_mesh(s, &d.m, 0, NULL);
}

static int game_mesh_index_5_of_3(ray_scene *s)
{
    game_mesh_data d;
    game_mesh_init(&d);
    d.idx[2] = 5;
    return ray_scene_add_mesh(s, &d.m, 0, NULL);
}

static int game_mesh_inf_position(ray_scene *s)
{
    game_mesh_data d;
    game_mesh_init(&d);
    d.v[1][1] = (float)INFINITY;
    return ray_scene_add_mesh(s, &d.m, 0, NULL);
}

static int game_mesh_nan_position(ray_scene *s)
{
    game_mesh_data d;
    game_mesh_init(&d);
    d.v[2][0] = NAN;             /* C99 7.12: NAN is a float constant */
    return ray_scene_add_mesh(s, &d.m, 0, NULL);
}

static int game_mesh_position_type_uint16(ray_scene *s)
{
    game_mesh_data d;
    game_mesh_init(&d);
    d.m.position_type = RAY_UINT16;
    return ray_scene_add_mesh(s, &d.m, 0, NULL);
}

static int game_mesh_no_index_type(ray_scene *s)
{
    game_mesh_data d;
    game_mesh_init(&d);
    d.m.index_type = 0;
    return ray_scene_add_mesh(s, &d.m, 0, NULL);
}

/* Doubles need 24 bytes a position: a float-sized stride of 16 is short. */
static int game_mesh_double_short_stride(ray_scene *s)
{
    double v[3][2];
    game_mesh_data d;
    game_mesh_init(&d);
    memset(v, 0, sizeof v);
    d.m.positions = v;
    d.m.position_type = RAY_FLOAT64;
    d.m.position_stride = 16;
    return ray_scene_add_mesh(s, &d.m, 0, NULL);
}

/* 32-bit indices: index 3 of 3 vertices, the first out of range. */
static int game_mesh_uint32_index_3_of_3(ray_scene *s)
{
    static const uint32_t idx[6] = {0, 1, 2, 2, 1, 3};
    game_mesh_data d;
    game_mesh_init(&d);
    d.m.index_data = idx;
    d.m.index_type = RAY_UINT32;
    d.m.triangle_count = 2;
    return ray_scene_add_mesh(s, &d.m, 0, NULL);
}

static int mesh_no_vertices(ray_scene *s)
{
    mesh_data d;
    mesh_init(&d);
    d.m.vertex_count = 0;
    return ray_scene_add_mesh(s, &d.m, 0, NULL);
}

static int mesh_no_triangles(ray_scene *s)
{
    mesh_data d;
    mesh_init(&d);
    d.m.triangle_count = 0;
    return ray_scene_add_mesh(s, &d.m, 0, NULL);
}

/* The example: index 7 in triangle 0 of a 3-vertex mesh. */
static int mesh_index_7_of_3(ray_scene *s)
{
    mesh_data d;
    mesh_init(&d);
    d.idx[1] = 7;
    return ray_scene_add_mesh(s, &d.m, 0, NULL);
}

/* The triangle is counted from the index's position: idx[5] is in 1. */
static int mesh_index_in_second_triangle(ray_scene *s)
{
    mesh_data d;
    mesh_init(&d);
    d.idx[5] = 3;
    return ray_scene_add_mesh(s, &d.m, 0, NULL);
}

static int mesh_nan_vertex(ray_scene *s)
{
    mesh_data d;
    mesh_init(&d);
    d.v[2].x = (double)NAN;
    return ray_scene_add_mesh(s, &d.m, 0, NULL);
}

/* -inf, and a vertex that is not the last: mesh.c's quick test of the
** whole array (the sum of x * 0) must see every sign and position. */
static int mesh_minus_inf_vertex(ray_scene *s)
{
    mesh_data d;
    mesh_init(&d);
    d.v[0].z = -(double)INFINITY;
    return ray_scene_add_mesh(s, &d.m, 0, NULL);
}

static int mesh_infinite_normal(ray_scene *s)
{
    mesh_data d;
    mesh_init(&d);
    d.n[1].y = HUGE_VAL;
    return ray_scene_add_mesh(s, &d.m, 0, NULL);
}

static int mesh_nan_texcoord(ray_scene *s)
{
    mesh_data d;
    mesh_init(&d);
    d.tex[1] = (double)NAN;
    return ray_scene_add_mesh(s, &d.m, 0, NULL);
}

static int mesh_unknown_material(ray_scene *s)
{
    mesh_data d;
    mesh_init(&d);
    return ray_scene_add_mesh(s, &d.m, 4, NULL);
}

/* 3 * triangle_count indices would not fit in a size_t. */
static int mesh_too_many_triangles(ray_scene *s)
{
    mesh_data d;
    mesh_init(&d);
    d.m.triangle_count = SIZE_MAX / 2;
    return ray_scene_add_mesh(s, &d.m, 0, NULL);
}

static int torus_null(ray_scene *s)
{
    return ray_scene_add_torus(s, NULL, 0, NULL);
}

static int torus_nan_center(ray_scene *s)
{
    ray_torus_params t = torus_ok();
    t.center.z = (double)NAN;
    return ray_scene_add_torus(s, &t, 0, NULL);
}

static int torus_zero_axis(ray_scene *s)
{
    ray_torus_params t = torus_ok();
    t.axis = vec(0, 0, 0);
    return ray_scene_add_torus(s, &t, 0, NULL);
}

static int torus_negative_major(ray_scene *s)
{
    ray_torus_params t = torus_ok();
    t.major = -2;
    return ray_scene_add_torus(s, &t, 0, NULL);
}

static int torus_spindle(ray_scene *s)
{
    ray_torus_params t = torus_ok();
    t.minor = 3;
    return ray_scene_add_torus(s, &t, 0, NULL);
}

/* Finite radii whose sum overflows: no other field is at fault. */
static int torus_too_large(ray_scene *s)
{
    ray_torus_params t = torus_ok();
    t.major = 1e308;
    t.minor = 9e307;
    return ray_scene_add_torus(s, &t, 0, NULL);
}

static int torus_unknown_material(ray_scene *s)
{
    ray_torus_params t = torus_ok();
    return ray_scene_add_torus(s, &t, 9, NULL);
}

static int implicit_null(ray_scene *s)
{
    return ray_scene_add_implicit(s, NULL, 0, NULL);
}

static int implicit_no_field(ray_scene *s)
{
    ray_implicit_surface is = implicit_ok();
    is.f = NULL;
    return ray_scene_add_implicit(s, &is, 0, NULL);
}

static int implicit_inverted_box(ray_scene *s)
{
    ray_implicit_surface is = implicit_ok();
    is.lo.y = 2;
    return ray_scene_add_implicit(s, &is, 0, NULL);
}

static int implicit_negative_lipschitz(ray_scene *s)
{
    ray_implicit_surface is = implicit_ok();
    is.lipschitz = -1;
    return ray_scene_add_implicit(s, &is, 0, NULL);
}

static int implicit_nan_step(ray_scene *s)
{
    ray_implicit_surface is = implicit_ok();
    is.step = (double)NAN;
    return ray_scene_add_implicit(s, &is, 0, NULL);
}

static int implicit_infinite_tolerance(ray_scene *s)
{
    ray_implicit_surface is = implicit_ok();
    is.tolerance = HUGE_VAL;
    return ray_scene_add_implicit(s, &is, 0, NULL);
}

static int implicit_unknown_material(ray_scene *s)
{
    ray_implicit_surface is = implicit_ok();
    return ray_scene_add_implicit(s, &is, 1, NULL);
}

static int parametric_null(ray_scene *s)
{
    return ray_scene_add_parametric(s, NULL, 0, NULL);
}

static int parametric_no_eval(ray_scene *s)
{
    ray_parametric_surface ps = parametric_ok();
    ps.eval = NULL;
    return ray_scene_add_parametric(s, &ps, 0, NULL);
}

static int parametric_no_bounds(ray_scene *s)
{
    ray_parametric_surface ps = parametric_ok();
    ps.bounds = NULL;
    return ray_scene_add_parametric(s, &ps, 0, NULL);
}

static int parametric_too_many_subdivisions(ray_scene *s)
{
    ray_parametric_surface ps = parametric_ok();
    ps.subdivisions = 13;
    return ray_scene_add_parametric(s, &ps, 0, NULL);
}

static int parametric_negative_tolerance(ray_scene *s)
{
    ray_parametric_surface ps = parametric_ok();
    ps.tolerance = -0.5;
    return ray_scene_add_parametric(s, &ps, 0, NULL);
}

static int parametric_empty_domain(ray_scene *s)
{
    ray_parametric_surface ps = parametric_ok();
    ps.u0 = 1;
    ps.u1 = 0;
    ps.v1 = 1;
    return ray_scene_add_parametric(s, &ps, 0, NULL);
}

static int parametric_lying_bounds(ray_scene *s)
{
    ray_parametric_surface ps = parametric_ok();
    ps.bounds = nan_bounds;
    return ray_scene_add_parametric(s, &ps, 0, NULL);
}

static int parametric_unknown_material(ray_scene *s)
{
    ray_parametric_surface ps = parametric_ok();
    return ray_scene_add_parametric(s, &ps, 6, NULL);
}

static int bezier_null(ray_scene *s)
{
    return ray_scene_add_bezier(s, NULL, 0, NULL);
}

static int bezier_nan_point(ray_scene *s)
{
    ray_vec3 cp[16];
    bezier_ok(cp);
    cp[5].z = (double)NAN;
    return ray_scene_add_bezier(s, cp, 0, NULL);
}

static int bezier_unknown_material(ray_scene *s)
{
    ray_vec3 cp[16];
    bezier_ok(cp);
    return ray_scene_add_bezier(s, cp, 7, NULL);
}

static int light_null(ray_scene *s)
{
    return ray_scene_add_light(s, NULL, NULL);
}

static int light_negative_intensity(ray_scene *s)
{
    ray_light l = light_ok(RAY_LIGHT_POINT);
    l.intensity.g = -1;
    return ray_scene_add_light(s, &l, NULL);
}

static int light_unknown_kind(ray_scene *s)
{
    ray_light l = light_ok(17);
    return ray_scene_add_light(s, &l, NULL);
}

static int light_point_nan_position(ray_scene *s)
{
    ray_light l = light_ok(RAY_LIGHT_POINT);
    l.position.x = (double)NAN;
    return ray_scene_add_light(s, &l, NULL);
}

/* A zero direction and a zero radius are the defaults (ray.h, 1.0): what
** is refused is a direction not finite and a radius below zero. */
static int light_directional_nan(ray_scene *s)
{
    ray_light l = light_ok(RAY_LIGHT_DIRECTIONAL);
    l.direction = vec((double)NAN, 0, 0);
    return ray_scene_add_light(s, &l, NULL);
}

static int light_sphere_negative_radius(ray_scene *s)
{
    ray_light l = light_ok(RAY_LIGHT_SPHERE);
    l.radius = -1;
    return ray_scene_add_light(s, &l, NULL);
}

static int light_sphere_infinite_position(ray_scene *s)
{
    ray_light l = light_ok(RAY_LIGHT_SPHERE);
    l.position.y = HUGE_VAL;
    return ray_scene_add_light(s, &l, NULL);
}

static int light_rect_parallel_edges(ray_scene *s)
{
    ray_light l = light_ok(RAY_LIGHT_RECT);
    l.edge2 = vec(2, 0, 0);
    return ray_scene_add_light(s, &l, NULL);
}

static int light_rect_nan_position(ray_scene *s)
{
    ray_light l = light_ok(RAY_LIGHT_RECT);
    l.position.z = (double)NAN;
    return ray_scene_add_light(s, &l, NULL);
}

static int light_too_many_samples(ray_scene *s)
{
    ray_light l = light_ok(RAY_LIGHT_SPHERE);
    l.samples = RAY_MAX_LIGHT_SAMPLES + 1;
    return ray_scene_add_light(s, &l, NULL);
}

static int background_negative(ray_scene *s)
{
    return ray_scene_set_background(s, rgb(0.5, -0.25, 0), NULL, NULL);
}

static int ambient_nan(ray_scene *s)
{
    return ray_scene_set_ambient(s, rgb((double)NAN, 0, 0));
}

static int limits_weight_above_one(ray_scene *s)
{
    ray_limits lim = {.max_depth = 3, .min_weight = 2.0,
                      .max_fanout = 1};
    return ray_scene_set_limits(s, &lim);
}

static int limits_too_deep(ray_scene *s)
{
    ray_limits lim = {.max_depth = RAY_MAX_DEPTH + 1, .min_weight = 0.5,
                      .max_fanout = 1};
    return ray_scene_set_limits(s, &lim);
}

/*
** The other operands of each validation's "||" and "&&" (issue 38's
** branch coverage): the refusals above take one operand of most tests
** (a NaN centre, an inverted y); a check that dropped or swapped another
** operand (the axis's finiteness, hi as well as lo, the z extent, an
** infinite where a negative was tried) would let these through.
*/
static int torus_nan_axis(ray_scene *s)
{
    ray_torus_params t = torus_ok();
    t.axis = vec(0, (double)NAN, 1);
    return ray_scene_add_torus(s, &t, 0, NULL);
}

static int torus_infinite_major(ray_scene *s)
{
    ray_torus_params t = torus_ok();
    t.major = HUGE_VAL;
    return ray_scene_add_torus(s, &t, 0, NULL);
}

static int torus_zero_minor(ray_scene *s)
{
    ray_torus_params t = torus_ok();
    t.minor = 0;
    return ray_scene_add_torus(s, &t, 0, NULL);
}

static int implicit_nan_lo(ray_scene *s)
{
    ray_implicit_surface is = implicit_ok();
    is.lo.x = (double)NAN;
    return ray_scene_add_implicit(s, &is, 0, NULL);
}

static int implicit_infinite_hi(ray_scene *s)
{
    ray_implicit_surface is = implicit_ok();
    is.hi.z = HUGE_VAL;
    return ray_scene_add_implicit(s, &is, 0, NULL);
}

static int implicit_inverted_x(ray_scene *s)
{
    ray_implicit_surface is = implicit_ok();
    is.lo.x = 3;
    return ray_scene_add_implicit(s, &is, 0, NULL);
}

static int implicit_inverted_z(ray_scene *s)
{
    ray_implicit_surface is = implicit_ok();
    is.hi.z = -2;
    return ray_scene_add_implicit(s, &is, 0, NULL);
}

static int implicit_infinite_lipschitz(ray_scene *s)
{
    ray_implicit_surface is = implicit_ok();
    is.lipschitz = HUGE_VAL;
    return ray_scene_add_implicit(s, &is, 0, NULL);
}

static int implicit_negative_step(ray_scene *s)
{
    ray_implicit_surface is = implicit_ok();
    is.step = -0.25;
    return ray_scene_add_implicit(s, &is, 0, NULL);
}

static int implicit_negative_tolerance(ray_scene *s)
{
    ray_implicit_surface is = implicit_ok();
    is.tolerance = -1e-3;
    return ray_scene_add_implicit(s, &is, 0, NULL);
}

/* Bounds callbacks that lie in each other way: an infinite hi, and lo >
** hi on x, y and z in turn (ud: the axis, 0 .. 2; 3: the infinite hi). */
static void lying_bounds(void *ud, double u0, double u1, double v0,
                         double v1, ray_vec3 *lo, ray_vec3 *hi)
{
    int how = *(const int *)ud;

    *lo = vec(u0, v0, 0);
    *hi = vec(u1, v1, 0);
    if (how == 0)
        lo->x = u1 + 1;
    else if (how == 1)
        lo->y = v1 + 1;
    else if (how == 2)
        lo->z = 1;
    else
        hi->y = HUGE_VAL;
}

static int parametric_lying(ray_scene *s, int how)
{
    ray_parametric_surface ps = parametric_ok();
    ps.bounds = lying_bounds;
    ps.ud = &how;
    return ray_scene_add_parametric(s, &ps, 0, NULL);
}

static int parametric_bounds_x_inverted(ray_scene *s)
{
    return parametric_lying(s, 0);
}

static int parametric_bounds_y_inverted(ray_scene *s)
{
    return parametric_lying(s, 1);
}

static int parametric_bounds_z_inverted(ray_scene *s)
{
    return parametric_lying(s, 2);
}

static int parametric_bounds_infinite_hi(ray_scene *s)
{
    return parametric_lying(s, 3);
}

static int parametric_infinite_tolerance(ray_scene *s)
{
    ray_parametric_surface ps = parametric_ok();
    ps.tolerance = HUGE_VAL;
    return ray_scene_add_parametric(s, &ps, 0, NULL);
}

static int parametric_nan_domain(ray_scene *s)
{
    ray_parametric_surface ps = parametric_ok();
    ps.u1 = 1;
    ps.v1 = (double)NAN;
    return ray_scene_add_parametric(s, &ps, 0, NULL);
}

static int light_directional_infinite(ray_scene *s)
{
    ray_light l = light_ok(RAY_LIGHT_DIRECTIONAL);
    l.direction = vec(0, -HUGE_VAL, 0);
    return ray_scene_add_light(s, &l, NULL);
}

static int light_sphere_infinite_radius(ray_scene *s)
{
    ray_light l = light_ok(RAY_LIGHT_SPHERE);
    l.radius = HUGE_VAL;
    return ray_scene_add_light(s, &l, NULL);
}

static int light_sphere_nan_radius(ray_scene *s)
{
    ray_light l = light_ok(RAY_LIGHT_SPHERE);
    l.radius = (double)NAN;
    return ray_scene_add_light(s, &l, NULL);
}

static int light_rect_nan_edge1(ray_scene *s)
{
    ray_light l = light_ok(RAY_LIGHT_RECT);
    l.edge1 = vec((double)NAN, 0, 0);
    return ray_scene_add_light(s, &l, NULL);
}

static int light_rect_infinite_edge2(ray_scene *s)
{
    ray_light l = light_ok(RAY_LIGHT_RECT);
    l.edge2 = vec(0, 0, HUGE_VAL);
    return ray_scene_add_light(s, &l, NULL);
}

typedef struct errcase {
    failing_call call;
    int status;
    const char *msg;         /* ray_scene_errmsg, exactly */
} errcase;

static const errcase cases[] = {
    {material_null, RAY_EINVAL, "ray_scene_add_material: material is NULL"},
    {material_no_shade, RAY_EINVAL,
     "ray_scene_add_material: shade function is NULL"},
    {material_bad_effects, RAY_EINVAL, "ray_scene_add_material: unknown "
     "effect bits 0xc0 (known: RAY_EFFECT_* = 0x3f)"},
    {sphere_nan_center, RAY_EINVAL,
     "ray_scene_add_sphere: center (0, nan, 0) is not finite"},
    {sphere_negative_radius, RAY_EINVAL,
     "ray_scene_add_sphere: radius -1 is not positive and finite"},
    {sphere_infinite_radius, RAY_EINVAL,
     "ray_scene_add_sphere: radius inf is not positive and finite"},
    {sphere_unknown_material, RAY_EINVAL,
     "ray_scene_add_sphere: material 5 does not exist (the scene has 1)"},
    {plane_infinite_point, RAY_EINVAL,
     "ray_scene_add_plane: point (0, inf, 0) is not finite"},
    {plane_zero_normal, RAY_EINVAL,
     "ray_scene_add_plane: normal (0, 0, 0) is zero or not finite"},
    {plane_nan_normal, RAY_EINVAL,
     "ray_scene_add_plane: normal (nan, 1, 0) is zero or not finite"},
    {plane_unknown_material, RAY_EINVAL,
     "ray_scene_add_plane: material 1 does not exist (the scene has 1)"},
    {triangle_nan_vertex, RAY_EINVAL,
     "ray_scene_add_triangle: vertex b (1, nan, 0) is not finite"},
    {triangle_collinear, RAY_EDEGENERATE, "ray_scene_add_triangle: zero "
     "area: vertices (0, 0, 0), (1, 0, 0), (2, 0, 0) are collinear"},
    {triangle_unknown_material, RAY_EINVAL,
     "ray_scene_add_triangle: material 2 does not exist (the scene has 1)"},
    {polygon_null, RAY_EINVAL, "ray_scene_add_polygon: vertex array is NULL"},
    {polygon_two_vertices, RAY_EINVAL,
     "ray_scene_add_polygon: 2 vertices: a polygon needs at least 3"},
    {polygon_infinite_vertex, RAY_EINVAL,
     "ray_scene_add_polygon: vertex 2 (1, 1, -inf) is not finite"},
    {polygon_zero_area, RAY_EDEGENERATE, "ray_scene_add_polygon: zero area: "
     "the 3 vertices are collinear or the outline cancels itself"},
    {polygon_unknown_material, RAY_EINVAL,
     "ray_scene_add_polygon: material 3 does not exist (the scene has 1)"},
    {mesh_null, RAY_EINVAL, "ray_scene_add_mesh: mesh is NULL"},
    {mesh_null_vertices, RAY_EINVAL,
     "ray_scene_add_mesh: vertices and positions are both NULL"},
    {mesh_null_indices, RAY_EINVAL,
     "ray_scene_add_mesh: indices and index_data are both NULL"},
    {game_mesh_short_stride, RAY_EINVAL, "ray_scene_add_mesh: "
     "position_stride 8 is smaller than a position (12 bytes)"},
    {game_mesh_double_short_stride, RAY_EINVAL, "ray_scene_add_mesh: "
     "position_stride 16 is smaller than a position (24 bytes)"},
    {game_mesh_null_positions, RAY_EINVAL,
     "ray_scene_add_mesh: vertices and positions are both NULL"},
    {game_mesh_no_position_type, RAY_EINVAL, "ray_scene_add_mesh: "
     "position_type 0 is not RAY_FLOAT32 or RAY_FLOAT64"},
    {game_mesh_position_type_uint16, RAY_EINVAL, "ray_scene_add_mesh: "
     "position_type 3 is not RAY_FLOAT32 or RAY_FLOAT64"},
    {game_mesh_bad_index_type, RAY_EINVAL, "ray_scene_add_mesh: "
     "index_type 1 is not RAY_UINT16 or RAY_UINT32"},
    {game_mesh_no_index_type, RAY_EINVAL, "ray_scene_add_mesh: "
     "index_type 0 is not RAY_UINT16 or RAY_UINT32"},
    {game_mesh_null_index_data, RAY_EINVAL,
     "ray_scene_add_mesh: indices and index_data are both NULL"},
    {game_mesh_index_5_of_3, RAY_EINVAL, "ray_scene_add_mesh: "
     "index_data: triangle 0 index 5 out of range (3 vertices)"},
    {game_mesh_uint32_index_3_of_3, RAY_EINVAL, "ray_scene_add_mesh: "
     "index_data: triangle 1 index 3 out of range (3 vertices)"},
    {game_mesh_inf_position, RAY_EINVAL,
     "ray_scene_add_mesh: position 1 (1, inf, 0) is not finite"},
    {game_mesh_nan_position, RAY_EINVAL,
     "ray_scene_add_mesh: position 2 (nan, 1, 0) is not finite"},
    {mesh_no_vertices, RAY_EINVAL,
     "ray_scene_add_mesh: no vertices (vertex_count 0)"},
    {mesh_no_triangles, RAY_EINVAL,
     "ray_scene_add_mesh: no triangles (triangle_count 0)"},
    {mesh_index_7_of_3, RAY_EINVAL,
     "ray_scene_add_mesh: triangle 0 index 7 out of range (3 vertices)"},
    {mesh_index_in_second_triangle, RAY_EINVAL,
     "ray_scene_add_mesh: triangle 1 index 3 out of range (3 vertices)"},
    {mesh_nan_vertex, RAY_EINVAL,
     "ray_scene_add_mesh: vertex 2 (nan, 1, 0) is not finite"},
    {mesh_minus_inf_vertex, RAY_EINVAL,
     "ray_scene_add_mesh: vertex 0 (0, 0, -inf) is not finite"},
    {mesh_infinite_normal, RAY_EINVAL,
     "ray_scene_add_mesh: normal 1 (0, inf, 1) is not finite"},
    {mesh_nan_texcoord, RAY_EINVAL,
     "ray_scene_add_mesh: texture coordinates 0 (0.5, nan) are not finite"},
    {mesh_unknown_material, RAY_EINVAL,
     "ray_scene_add_mesh: material 4 does not exist (the scene has 1)"},
    {mesh_too_many_triangles, RAY_ENOMEM, "the index count overflows size_t"},
    {torus_null, RAY_EINVAL, "ray_scene_add_torus: torus parameters are NULL"},
    {torus_nan_center, RAY_EINVAL,
     "ray_scene_add_torus: center (0, 0, nan) is not finite"},
    {torus_zero_axis, RAY_EINVAL,
     "ray_scene_add_torus: axis (0, 0, 0) is zero or not finite"},
    {torus_negative_major, RAY_EINVAL,
     "ray_scene_add_torus: major radius -2 is not positive and finite"},
    {torus_spindle, RAY_EINVAL, "ray_scene_add_torus: minor radius 3 is not "
     "in (0, major radius 2): only ring tori"},
    {torus_too_large, RAY_EINVAL, "ray_scene_add_torus: the torus (major "
     "radius 1e+308, center (0, 0, 0)) reaches beyond the largest double"},
    {torus_unknown_material, RAY_EINVAL,
     "ray_scene_add_torus: material 9 does not exist (the scene has 1)"},
    {implicit_null, RAY_EINVAL, "ray_scene_add_implicit: surface is NULL"},
    {implicit_no_field, RAY_EINVAL,
     "ray_scene_add_implicit: field function f is NULL"},
    {implicit_inverted_box, RAY_EINVAL, "ray_scene_add_implicit: box lo "
     "(-1, 2, -1) hi (1, 1, 1) is not finite or has lo > hi"},
    {implicit_negative_lipschitz, RAY_EINVAL,
     "ray_scene_add_implicit: lipschitz -1 is negative or not finite"},
    {implicit_nan_step, RAY_EINVAL,
     "ray_scene_add_implicit: step nan is negative or not finite"},
    {implicit_infinite_tolerance, RAY_EINVAL,
     "ray_scene_add_implicit: tolerance inf is negative or not finite"},
    {implicit_unknown_material, RAY_EINVAL,
     "ray_scene_add_implicit: material 1 does not exist (the scene has 1)"},
    {parametric_null, RAY_EINVAL, "ray_scene_add_parametric: surface is NULL"},
    {parametric_no_eval, RAY_EINVAL, "ray_scene_add_parametric: eval is NULL"},
    {parametric_no_bounds, RAY_EINVAL,
     "ray_scene_add_parametric: bounds is NULL"},
    {parametric_too_many_subdivisions, RAY_EINVAL,
     "ray_scene_add_parametric: subdivisions 13 is more than 12"},
    {parametric_negative_tolerance, RAY_EINVAL,
     "ray_scene_add_parametric: tolerance -0.5 is negative or not finite"},
    {parametric_empty_domain, RAY_EINVAL, "ray_scene_add_parametric: domain "
     "[1, 0] x [0, 1] is empty or not finite"},
    {parametric_lying_bounds, RAY_EINVAL, "ray_scene_add_parametric: the "
     "bounds callback gave lo (0, 0, nan) hi (1, 1, 0): not finite, or "
     "lo > hi"},
    {parametric_unknown_material, RAY_EINVAL,
     "ray_scene_add_parametric: material 6 does not exist (the scene has 1)"},
    {bezier_null, RAY_EINVAL, "ray_scene_add_bezier: control points are NULL"},
    {bezier_nan_point, RAY_EINVAL,
     "ray_scene_add_bezier: control point 5 (1, 1, nan) is not finite"},
    {bezier_unknown_material, RAY_EINVAL,
     "ray_scene_add_bezier: material 7 does not exist (the scene has 1)"},
    {light_null, RAY_EINVAL, "ray_scene_add_light: light is NULL"},
    {light_negative_intensity, RAY_EINVAL, "ray_scene_add_light: intensity "
     "(1, -1, 1) is negative or not finite"},
    {light_unknown_kind, RAY_EINVAL,
     "ray_scene_add_light: unknown kind 17 (not a RAY_LIGHT_*)"},
    {light_point_nan_position, RAY_EINVAL,
     "ray_scene_add_light: position (nan, 0, 0) is not finite"},
    {light_directional_nan, RAY_EINVAL,
     "ray_scene_add_light: direction (nan, 0, 0) is not finite, or too "
     "short to normalise"},
    {light_sphere_negative_radius, RAY_EINVAL,
     "ray_scene_add_light: sphere light radius -1 is not positive and "
     "finite"},
    {light_sphere_infinite_position, RAY_EINVAL,
     "ray_scene_add_light: position (0, inf, 0) is not finite"},
    {light_rect_parallel_edges, RAY_EINVAL, "ray_scene_add_light: edges "
     "(1, 0, 0) and (2, 0, 0) are parallel, too short or not finite"},
    {light_rect_nan_position, RAY_EINVAL,
     "ray_scene_add_light: position (0, 0, nan) is not finite"},
    {light_too_many_samples, RAY_EINVAL, "ray_scene_add_light: samples 65537 "
     "is more than RAY_MAX_LIGHT_SAMPLES (65536)"},
    {background_negative, RAY_EINVAL, "ray_scene_set_background: colour "
     "(0.5, -0.25, 0) is negative or not finite"},
    {ambient_nan, RAY_EINVAL, "ray_scene_set_ambient: ambient light "
     "(nan, 0, 0) is negative or not finite"},
    {limits_weight_above_one, RAY_EINVAL,
     "ray_scene_set_limits: min_weight 2 is not in [0, 1]"},
    {limits_too_deep, RAY_EINVAL,
     "ray_scene_set_limits: max_depth 65 is more than RAY_MAX_DEPTH (64)"},
    {torus_nan_axis, RAY_EINVAL,
     "ray_scene_add_torus: axis (0, nan, 1) is zero or not finite"},
    {torus_infinite_major, RAY_EINVAL,
     "ray_scene_add_torus: major radius inf is not positive and finite"},
    {torus_zero_minor, RAY_EINVAL, "ray_scene_add_torus: minor radius 0 is "
     "not in (0, major radius 2): only ring tori"},
    {implicit_nan_lo, RAY_EINVAL, "ray_scene_add_implicit: box lo "
     "(nan, -1, -1) hi (1, 1, 1) is not finite or has lo > hi"},
    {implicit_infinite_hi, RAY_EINVAL, "ray_scene_add_implicit: box lo "
     "(-1, -1, -1) hi (1, 1, inf) is not finite or has lo > hi"},
    {implicit_inverted_x, RAY_EINVAL, "ray_scene_add_implicit: box lo "
     "(3, -1, -1) hi (1, 1, 1) is not finite or has lo > hi"},
    {implicit_inverted_z, RAY_EINVAL, "ray_scene_add_implicit: box lo "
     "(-1, -1, -1) hi (1, 1, -2) is not finite or has lo > hi"},
    {implicit_infinite_lipschitz, RAY_EINVAL,
     "ray_scene_add_implicit: lipschitz inf is negative or not finite"},
    {implicit_negative_step, RAY_EINVAL,
     "ray_scene_add_implicit: step -0.25 is negative or not finite"},
    {implicit_negative_tolerance, RAY_EINVAL,
     "ray_scene_add_implicit: tolerance -0.001 is negative or not finite"},
    {parametric_bounds_x_inverted, RAY_EINVAL, "ray_scene_add_parametric: "
     "the bounds callback gave lo (2, 0, 0) hi (1, 1, 0): not finite, or "
     "lo > hi"},
    {parametric_bounds_y_inverted, RAY_EINVAL, "ray_scene_add_parametric: "
     "the bounds callback gave lo (0, 2, 0) hi (1, 1, 0): not finite, or "
     "lo > hi"},
    {parametric_bounds_z_inverted, RAY_EINVAL, "ray_scene_add_parametric: "
     "the bounds callback gave lo (0, 0, 1) hi (1, 1, 0): not finite, or "
     "lo > hi"},
    {parametric_bounds_infinite_hi, RAY_EINVAL, "ray_scene_add_parametric: "
     "the bounds callback gave lo (0, 0, 0) hi (1, inf, 0): not finite, or "
     "lo > hi"},
    {parametric_infinite_tolerance, RAY_EINVAL,
     "ray_scene_add_parametric: tolerance inf is negative or not finite"},
    {parametric_nan_domain, RAY_EINVAL, "ray_scene_add_parametric: domain "
     "[0, 1] x [0, nan] is empty or not finite"},
    {light_directional_infinite, RAY_EINVAL,
     "ray_scene_add_light: direction (0, -inf, 0) is not finite, or too "
     "short to normalise"},
    {light_sphere_infinite_radius, RAY_EINVAL,
     "ray_scene_add_light: sphere light radius inf is not positive and "
     "finite"},
    {light_sphere_nan_radius, RAY_EINVAL,
     "ray_scene_add_light: sphere light radius nan is not positive and "
     "finite"},
    {light_rect_nan_edge1, RAY_EINVAL, "ray_scene_add_light: edges "
     "(nan, 0, 0) and (0, 0, 1) are parallel, too short or not finite"},
    {light_rect_infinite_edge2, RAY_EINVAL, "ray_scene_add_light: edges "
     "(1, 0, 0) and (0, 0, inf) are parallel, too short or not finite"},
};

#define N_CASES ((int)(sizeof cases / sizeof cases[0]))

/* Every validation path: its status, its message (glibc prints NaN and
** infinity as "nan" and "inf", which C99 7.19.6.1 allows; "-nan" is
** avoided by building NaNs from the NAN macro), nothing added, and the
** next good call clears the message. */
START_TEST(errmsg_should_name_what_each_validation_refused)
{
    const errcase *c = &cases[_i];
    ray_material m = plain();
    ray_scene *s;
    unsigned id = 99;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, NULL), RAY_OK);
    ck_assert_str_eq(ray_scene_errmsg(s), "");
    ck_assert_int_eq(c->call(s), c->status);
    if (c->status == RAY_ENOMEM)     /* the count is platform-dependent */
        ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(s), c->msg));
    else
        ck_assert_str_eq(ray_scene_errmsg(s), c->msg);
    /* Nothing was half-added: the next geometry gets id 0. */
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1, 0, &id), RAY_OK);
    ck_assert_uint_eq(id, 0);
    ck_assert_str_eq(ray_scene_errmsg(s), "");
    ray_scene_free(s);
}
END_TEST

/* The NAN macro's sign is unspecified; printf shows a negative NaN as
** "-nan".  Check that the platform's NAN prints as the cases expect, so a
** failure above is not mistaken for the library's. */
START_TEST(errmsg_cases_should_print_nan_and_inf_as_expected)
{
    char buf[32];

    snprintf(buf, sizeof buf, "%g %g %g", (double)NAN, HUGE_VAL, -HUGE_VAL);
    ck_assert_str_eq(buf, "nan inf -inf");
}
END_TEST

/* ------------------------------------------------ state, NULL, memory */

/* A background function: the preset colour, made grey. */
static void grey_sky(void *ud, const ray_ray *r, ray_rgb *out)
{
    (void)ud;
    (void)r;
    out->r = out->g = out->b = 0.5;
}

/* Each building call, with valid arguments, on a committed scene. */
static int after_commit(ray_scene *s, int k)
{
    ray_material m = plain();
    ray_light l = light_ok(RAY_LIGHT_POINT);
    ray_torus_params t = torus_ok();
    ray_implicit_surface is = implicit_ok();
    ray_parametric_surface ps = parametric_ok();
    ray_vec3 cp[16];
    ray_limits naive;
    mesh_data d;

    bezier_ok(cp);
    mesh_init(&d);
    ray_limits_init(&naive);
    naive.no_pruning = 1;                /* the naive mode (case 15) */
    switch (k) {
    case 0: return ray_scene_add_material(s, &m, NULL);
    case 1: return ray_scene_add_sphere(s, vec(0, 0, 0), 1, 0, NULL);
    case 2: return ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 1, 0), 0, NULL);
    case 3: return ray_scene_add_triangle(s, quad[0], quad[1], quad[2], 0, NULL);
    case 4: return ray_scene_add_polygon(s, quad, 4, 0, NULL);
    case 5: return ray_scene_add_mesh(s, &d.m, 0, NULL);
    case 6: return ray_scene_add_torus(s, &t, 0, NULL);
    case 7: return ray_scene_add_implicit(s, &is, 0, NULL);
    case 8: return ray_scene_add_parametric(s, &ps, 0, NULL);
    case 9: return ray_scene_add_bezier(s, cp, 0, NULL);
    case 10: return ray_scene_add_light(s, &l, NULL);
    case 11: return ray_scene_set_background(s, rgb(0, 0, 0), NULL, NULL);
    case 12: return ray_scene_set_background(s, rgb(0, 0, 0), grey_sky, NULL);
    case 13: return ray_scene_set_ambient(s, rgb(0, 0, 0));
    case 14: return ray_scene_set_limits(s, NULL);
    case 15: return ray_scene_set_limits(s, &naive);
    case 16: return ray_scene_set_watertight(s, 0);
    case 17: return ray_scene_set_build_threads(s, 2);
    default: return ray_scene_commit(s);
    }
}

static const char *const building_calls[] = {
    "ray_scene_add_material", "ray_scene_add_sphere", "ray_scene_add_plane",
    "ray_scene_add_triangle", "ray_scene_add_polygon", "ray_scene_add_mesh",
    "ray_scene_add_torus", "ray_scene_add_implicit",
    "ray_scene_add_parametric", "ray_scene_add_bezier", "ray_scene_add_light",
    "ray_scene_set_background", "ray_scene_set_background (fn)",
    "ray_scene_set_ambient", "ray_scene_set_limits",
    "ray_scene_set_limits (no_pruning)",
    "ray_scene_set_watertight", "ray_scene_set_build_threads",
    "ray_scene_commit"};

#define N_BUILDING ((int)(sizeof building_calls / sizeof building_calls[0]))

/*
** After a commit every building call is allowed again (ray.h, "Changing
** a committed scene"): with valid arguments it succeeds and leaves no
** message, and the scene answers no query until it is committed again
** (a commit with nothing staged keeps it committed).
*/
START_TEST(building_after_commit_should_stage_a_change)
{
    ray_material m = plain();
    ray_scene *s;
    ray_ray r = ray_from(vec(0, 5, 0), vec(0, -1, 0));
    ray_hit h;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), 0);
    ck_assert_msg(after_commit(s, _i) == RAY_OK, "%s refused after commit",
                  building_calls[_i]);
    ck_assert_str_eq(ray_scene_errmsg(s), "");
    if (_i == N_BUILDING - 1) {                /* the commit itself */
        ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), 0);
    } else {
        ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), -RAY_ESTATE);
        ck_assert_int_eq(ray_occluded(s, &r, NULL), -RAY_ESTATE);
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        ck_assert_int_ge(ray_intersect(s, &r, &h, NULL), 0);
    }
    ray_scene_free(s);
}
END_TEST

/* A NULL scene has nowhere to keep a message: the call says RAY_EINVAL
** and ray_scene_errmsg(NULL) a fixed text. */
START_TEST(errmsg_should_answer_for_a_null_scene)
{
    ck_assert_int_eq(after_commit(NULL, _i), RAY_EINVAL);
    ck_assert_str_eq(ray_scene_errmsg(NULL), "no scene (NULL)");
}
END_TEST

/* The message of the most recent call only: a failure replaces the last
** one, and any success (a setter included) clears it. */
START_TEST(errmsg_should_follow_the_most_recent_call)
{
    ray_material m = plain();
    ray_scene *s;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_str_eq(ray_scene_errmsg(s), "");
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1, 0, NULL),
                     RAY_EINVAL);
    ck_assert_str_eq(ray_scene_errmsg(s), "ray_scene_add_sphere: material 0 "
                     "does not exist (the scene has 0)");
    ck_assert_int_eq(ray_scene_set_ambient(s, rgb(-1, 0, 0)), RAY_EINVAL);
    ck_assert_ptr_nonnull(strstr(ray_scene_errmsg(s), "ray_scene_set_ambient"));
    ck_assert_int_eq(ray_scene_set_limits(s, NULL), RAY_OK);
    ck_assert_str_eq(ray_scene_errmsg(s), "");
    ck_assert_int_eq(ray_scene_add_material(s, &m, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_str_eq(ray_scene_errmsg(s), "");
    ray_scene_free(s);
}
END_TEST

/* Out of memory in each building call that allocates: RAY_ENOMEM and a
** message saying so, from the fixed buffer (no allocation needed). */
START_TEST(errmsg_should_report_out_of_memory)
{
    ray_material m = plain();
    ray_light l = light_ok(RAY_LIGHT_POINT);
    ray_torus_params t = torus_ok();
    ray_implicit_surface is = implicit_ok();
    ray_parametric_surface ps = parametric_ok();
    ray_vec3 cp[16];
    mesh_data d;
    ray_scene *s;
    long left = 1000;
    int k, rc;

    bezier_ok(cp);
    mesh_init(&d);
    ck_assert_int_eq(ray_scene_new(&s, failing_alloc, &left), RAY_OK);
    /* Fill the material array's first block (8), so that the next
    ** material needs memory too; then allow no more allocations. */
    for (k = 0; k < 8; k++)
        ck_assert_int_eq(ray_scene_add_material(s, &m, NULL), RAY_OK);
    left = 0;
    for (k = 0; k < 11; k++) {
        switch (k) {
        case 0: rc = ray_scene_add_sphere(s, vec(0, 0, 0), 1, 0, NULL); break;
        case 1: rc = ray_scene_add_triangle(s, quad[0], quad[1], quad[2], 0, NULL); break;
        case 2: rc = ray_scene_add_polygon(s, quad, 4, 0, NULL); break;
        case 3: rc = ray_scene_add_mesh(s, &d.m, 0, NULL); break;
        case 4: rc = ray_scene_add_torus(s, &t, 0, NULL); break;
        case 5: rc = ray_scene_add_implicit(s, &is, 0, NULL); break;
        case 6: rc = ray_scene_add_parametric(s, &ps, 0, NULL); break;
        case 7: rc = ray_scene_add_bezier(s, cp, 0, NULL); break;
        case 8: rc = ray_scene_add_light(s, &l, NULL); break;
        case 9: rc = ray_scene_add_material(s, &m, NULL); break;
        default: rc = ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 1, 0), 0, NULL);
        }
        ck_assert_msg(rc == RAY_ENOMEM, "call %d: %d", k, rc);
        ck_assert_msg(strstr(ray_scene_errmsg(s), ": out of memory (") != NULL,
                      "call %d: \"%s\"", k, ray_scene_errmsg(s));
    }
    ray_scene_free(s);
}
END_TEST

/* ray_scene_commit out of memory: each BVH named, and a retry with memory
** succeeds. */
START_TEST(errmsg_should_report_commit_out_of_memory)
{
    ray_material m = plain();
    ray_scene *s;
    long left = 1000;

    ck_assert_int_eq(ray_scene_new(&s, failing_alloc, &left), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1, 0, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_triangle(s, quad[0], quad[1], quad[2], 0,
                                            NULL), RAY_OK);
    left = 0;
    ck_assert_int_eq(ray_scene_commit(s), RAY_ENOMEM);
    ck_assert_str_eq(ray_scene_errmsg(s), "ray_scene_commit: out of memory "
                     "building the BVH over the spheres, polygons, "
                     "surfaces and instances (not committed: retry)");
    left = 1000;
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_str_eq(ray_scene_errmsg(s), "");
    ray_scene_free(s);
}
END_TEST

Suite *errmsg_suite(void)
{
    Suite *s = suite_create("errmsg");
    TCase *tc = tcase_create("core");

    tcase_add_test(tc, errmsg_cases_should_print_nan_and_inf_as_expected);
    tcase_add_loop_test(tc, errmsg_should_name_what_each_validation_refused,
                        0, N_CASES);
    tcase_add_loop_test(tc, building_after_commit_should_stage_a_change, 0,
                        N_BUILDING);
    tcase_add_loop_test(tc, errmsg_should_answer_for_a_null_scene, 0,
                        N_BUILDING);
    tcase_add_test(tc, errmsg_should_follow_the_most_recent_call);
    tcase_add_test(tc, errmsg_should_report_out_of_memory);
    tcase_add_test(tc, errmsg_should_report_commit_out_of_memory);
    suite_add_tcase(s, tc);
    return s;
}
