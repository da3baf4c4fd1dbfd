/* SPDX-License-Identifier: MIT */
/*
** hello.c -- the smallest program that renders something: one red sphere,
** one light, one PNG.
*/
#include "common.h"

int main(void)
{
    static const ray_phong_params red = {{0.8, 0.1, 0.1}, {0, 0, 0}, 1, 0,
                                         {0, 0, 0}, {NULL, NULL}};
    static float image[160 * 120 * 3];
    ray_material m = ray_material_phong(&red);
    ray_light light = {RAY_LIGHT_POINT, {5, 5, 5}, {0, 0, 0}, {0, 0, 0},
                       {0, 0, 0}, 0, {60, 60, 60}, 0};
    ray_camera cam = {{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 40, 0, 0};
    ray_render_options opt;
    ray_scene *scene;
    ray_stats stats;
    unsigned mat;

    check(ray_scene_new(&scene, NULL, NULL), "ray_scene_new");
    check(ray_scene_add_material(scene, &m, &mat), "add_material");
    check(ray_scene_add_sphere(scene, vec(0, 0, 0), 1, mat, NULL), "add_sphere");
    check(ray_scene_add_light(scene, &light, NULL), "add_light");
    check(ray_scene_commit(scene), "commit");
    ray_render_options_init(&opt, 160, 120);
    check(ray_render(scene, &cam, &opt, image, &stats), "render");
    check(ray_write_png("hello.png", image, 160, 120, 8), "hello.png");
    print_stats("hello", &stats, 0);
    ray_scene_free(scene);
    return 0;
}
