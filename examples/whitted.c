/* SPDX-License-Identifier: MIT */
/*
** whitted.c -- the classic scene of Whitted's 1980 paper: a checkerboard
** floor, a mirror sphere and a glass sphere under a point light.
**
**     whitted [out.png [width height [samples [threads]]]]
**
** Defaults: whitted.png, 640 x 480, 4 samples per pixel, all CPUs.
** --help prints the usage and exits 0, bad arguments print it and exit 2
** (common.h).
*/
#include "scenes.h"

int main(int argc, char **argv)
{
    static const example_cli cli = {
        .name = "whitted", .output_default = "whitted.png", .sized = 1,
        .width = 640, .height = 480, .samples = 4,
        .what = "Renders Whitted's 1980 scene: a checkerboard floor, a mirror "
                "sphere and a glass\nsphere under a point light."};
    example_args args;
    ray_camera cam;
    ray_scene *scene;
    int rc = example_start(&cli, argc, argv, &args);

    if (rc != 0)
        return rc;
    scene = whitted_scene(&cam, 1, NULL);
    rc = render_to_png(&args, scene, &cam);

    ray_scene_free(scene);
    return rc;
}
