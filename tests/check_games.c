/* SPDX-License-Identifier: MIT */
/*
** check_games.c -- what a game or tool embedding the library needs of the
** scene API: geometry without materials (RAY_NO_MATERIAL), queried from
** the calling thread, rendered black.
*/
#include <stdlib.h>

#include "tests.h"
#include "hardcases.h"

static ray_mesh mesh_of(const hc_mesh *h)
{
    ray_mesh m;

    ray_mesh_init(&m);
    m.vertices = h->v;
    m.vertex_count = h->nv;
    m.indices = h->idx;
    m.triangle_count = h->nt;
    return m;
}

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
    m = mesh_of(&cube);
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, &id), RAY_OK);
    ck_assert_uint_eq(id, 0);
    m = mesh_of(&ball);
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

    ck_assert_int_eq(ray_intersect(s, &r, &h), 1);
    ck_assert_uint_eq(h.geom_id, 0);
    ck_assert_uint_eq(h.prim_id, 2);
    ck_assert(h.t == 9.0);
    r.org = vec(-0.5, 0.5, 10);
    ck_assert_int_eq(ray_intersect(s, &r, &h), 1);
    ck_assert_uint_eq(h.geom_id, 0);
    ck_assert_uint_eq(h.prim_id, 3);
    r.org = vec(10, 0, 10);
    ck_assert_int_eq(ray_intersect(s, &r, &h), 1);
    ck_assert_uint_eq(h.geom_id, 1);
    ck_assert_uint_lt(h.prim_id, nt);
    ck_assert_msg(fabs(h.t - 8.0) <= tol_at(10.0), "t %.17g", h.t);
    r.org = vec(5, 0, 10);
    ck_assert_int_eq(ray_intersect(s, &r, &h), 0);
    /* Line of sight: through the cube is blocked, beside it is clear. */
    r = make_ray(vec(-5, 0, 0), vec(1, 0, 0), 0, 4.5);
    ck_assert_int_eq(ray_occluded(s, &r), 1);
    r.tmax = 3.5;
    ck_assert_int_eq(ray_occluded(s, &r), 0);
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
        ray_mesh m = mesh_of(&cube);
        ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, NULL),
                         RAY_OK);
        hc_mesh_free(&cube);
    }
    ray_light_init(&light, RAY_LIGHT_POINT);
    light.position = vec(0, 0, 10);
    ck_assert_int_eq(ray_scene_add_light(s, &light, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_set_background(s, sky), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_uint_eq(ray_scene_effects(s), 0u);
    ray_camera_init(&cam);
    cam.position = vec(0, 0, 8);
    cam.look_at = vec(0, 0, 0);
    cam.up = vec(0, 1, 0);
    cam.vfov = 30;
    ray_render_options_init(&o, W, H);
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
    ck_assert_uint_eq(ray_scene_effects(s), mirror.effects);
    ray_scene_free(s);
}
END_TEST

Suite *games_suite(void)
{
    Suite *su = suite_create("games");
    TCase *nomat = tcase_create("no_material");

    tcase_add_test(nomat, meshes_without_material_should_be_queried);
    tcase_add_test(nomat, meshes_without_material_should_render_black);
    tcase_add_test(nomat, no_material_should_be_accepted_everywhere);
    suite_add_tcase(su, nomat);
    return su;
}
