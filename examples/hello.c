/* SPDX-License-Identifier: MIT */
/*
** hello.c -- the smallest program that renders something: one red sphere,
** one light, one PNG.
**
**     hello [out.png]
*/
#include "common.h"

int main(int argc, char **argv)
{
    static const example_cli cli = {
        .name = "hello", .output_default = "hello.png", .width = 160,
        .height = 120, .what = "Renders one red sphere under one light."};
    /* Designated initializers: the fields not named are 0, their default,
    ** also those a later version adds (ray(7), "Versions and ABI"). */
    static const ray_phong_params red = {.diffuse = {0.8, 0.1, 0.1},
                                         .shininess = 1};
    static float image[160 * 120 * 3];
    ray_material m = ray_material_phong(&red);
    ray_light light = {.kind = RAY_LIGHT_POINT, .position = {5, 5, 5},
                       .intensity = {60, 60, 60}};
    ray_camera cam = {.position = {0, 0, 5}, .look_at = {0, 0, 0},
                      .up = {0, 1, 0}, .vfov = 40};
    ray_render_options opt = {.width = 160, .height = 120};
    ray_scene *scene;
    ray_stats stats;
    example_args args;
    unsigned mat;
    int rc = example_start(&cli, argc, argv, &args);

    if (rc != 0)
        return rc;

    check(ray_scene_new(&scene, NULL, NULL), "ray_scene_new");
    check(ray_scene_add_material(scene, &m, &mat), "add_material");
    check(ray_scene_add_sphere(scene, vec(0, 0, 0), 1, mat, NULL), "add_sphere");
    check(ray_scene_add_light(scene, &light, NULL), "add_light");
    check(ray_scene_commit(scene), "commit");
    check(ray_render(scene, &cam, &opt, image, &stats), "render");
    rc = example_write_png(&args, image);      /* args.output, 160 x 120 */
    if (rc == 0)
        print_stats("hello", scene, &stats, 0);
    ray_scene_free(scene);
    return rc;
}
