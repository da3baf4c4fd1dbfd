/* SPDX-License-Identifier: MIT */
/*
** check_defaults.c -- the init functions of the public structs that may
** grow: the documented values, each struct accepted by the call that
** consumes it, and NULL a no-op.
*/
#include <string.h>

#include "tests.h"

START_TEST(camera_init_should_give_a_usable_pinhole)
{
    ray_camera c;
    ray_scene *s;
    ray_material m = plain();
    ray_render_options o;
    float img[3 * 4 * 3];

    memset(&c, 0x7f, sizeof c);
    ray_camera_init(&c);
    ck_assert_vec_eq(c.position, vec(0, 0, 0));
    ck_assert_vec_eq(c.look_at, vec(0, 0, -1));
    ck_assert_vec_eq(c.up, vec(0, 1, 0));
    ck_assert_double_eq(c.vfov, 60);
    ck_assert_double_eq(c.aperture, 0);
    ck_assert_double_eq(c.focus_distance, 0);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ray_render_options_init(&o, 4, 3);
    ck_assert_int_eq(ray_render(s, &c, &o, img, NULL), RAY_OK);
    ray_scene_free(s);
    ray_camera_init(NULL);
}
END_TEST

START_TEST(light_init_should_give_every_kind_a_valid_light)
{
    int kinds[4] = {RAY_LIGHT_POINT, RAY_LIGHT_DIRECTIONAL, RAY_LIGHT_SPHERE,
                    RAY_LIGHT_RECT};
    ray_scene *s;
    int k;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    for (k = 0; k < 4; k++) {
        ray_light l;
        memset(&l, 0x7f, sizeof l);
        ray_light_init(&l, kinds[k]);
        ck_assert_int_eq(l.kind, kinds[k]);
        ck_assert_vec_eq(l.position, vec(0, 0, 0));
        ck_assert_vec_eq(l.direction, vec(0, -1, 0));
        ck_assert_vec_eq(l.edge1, vec(1, 0, 0));
        ck_assert_vec_eq(l.edge2, vec(0, 0, 1));
        ck_assert_double_eq(l.radius, 1);
        ck_assert(l.intensity.r == 1 && l.intensity.g == 1 &&
                  l.intensity.b == 1);
        ck_assert_uint_eq(l.samples, 16);
        ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    }
    ck_assert_uint_eq(ray_scene_light_count(s), 4);
    ray_scene_free(s);
    ray_light_init(NULL, RAY_LIGHT_POINT);
}
END_TEST

START_TEST(limits_mesh_and_material_params_should_init_to_defaults)
{
    ray_limits l;
    ray_mesh mesh;
    ray_phong_params p;
    ray_glass_params g;
    ray_scene *s;
    ray_material m;

    memset(&l, 0x7f, sizeof l);
    ray_limits_init(&l);
    ck_assert_uint_eq(l.max_depth, RAY_DEFAULT_MAX_DEPTH);
    ck_assert_double_eq(l.min_weight, RAY_DEFAULT_MIN_WEIGHT);
    ck_assert_uint_eq(l.max_fanout, RAY_DEFAULT_MAX_FANOUT);
    memset(&mesh, 0x7f, sizeof mesh);
    ray_mesh_init(&mesh);
    ck_assert(mesh.vertices == NULL && mesh.indices == NULL &&
              mesh.normals == NULL && mesh.texcoords == NULL);
    ck_assert(mesh.vertex_count == 0 && mesh.triangle_count == 0);
    memset(&p, 0x7f, sizeof p);
    ray_phong_params_init(&p);
    ck_assert(p.diffuse.r == 0.8 && p.diffuse.g == 0.8 && p.diffuse.b == 0.8);
    ck_assert(p.specular.r == 0 && p.reflect.r == 0 && p.texture.fn == NULL);
    ck_assert_double_eq(p.shininess, 32);
    ck_assert_int_eq(p.blinn, 0);
    memset(&g, 0x7f, sizeof g);
    ray_glass_params_init(&g);
    ck_assert_double_eq(g.ior, 1.5);
    ck_assert(g.absorption.r == 0 && g.absorption.g == 0 &&
              g.absorption.b == 0);
    /* Each accepted where it is consumed; the empty mesh is refused. */
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_set_limits(s, &l), RAY_OK);
    m = ray_material_phong(&p);
    ck_assert_uint_eq(m.effects, RAY_EFFECT_SHADOW | RAY_EFFECT_CAUSTICS);
    ck_assert_int_eq(ray_scene_add_material(s, &m, NULL), RAY_OK);
    m = ray_material_glass(&g);
    ck_assert_int_eq(ray_scene_add_material(s, &m, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &mesh, 0, NULL), RAY_EINVAL);
    ray_scene_free(s);
    ray_limits_init(NULL);
    ray_mesh_init(NULL);
    ray_phong_params_init(NULL);
    ray_glass_params_init(NULL);
}
END_TEST

Suite *defaults_suite(void)
{
    Suite *s = suite_create("defaults");
    TCase *tc = tcase_create("init");

    tcase_add_test(tc, camera_init_should_give_a_usable_pinhole);
    tcase_add_test(tc, light_init_should_give_every_kind_a_valid_light);
    tcase_add_test(tc, limits_mesh_and_material_params_should_init_to_defaults);
    suite_add_tcase(s, tc);
    return s;
}
