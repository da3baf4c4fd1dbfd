/* SPDX-License-Identifier: MIT */
/*
** cornell.c -- a Cornell-box-like room of polygons and triangles, lit by
** a rectangular area light under the ceiling (soft shadows), with a tall
** block, a mirror sphere and a glass sphere.
**
**     cornell [out.png [width height [samples [threads]]]]
**
** Defaults: cornell.png, 400 x 400, 4 samples per pixel, all CPUs.
** --help prints the usage and exits 0, bad arguments print it and exit 2
** (common.h).
*/
#include "scenes.h"

int main(int argc, char **argv)
{
    static const example_cli cli = {
        .name = "cornell", .output_default = "cornell.png", .sized = 1,
        .width = 400, .height = 400, .samples = 4,
        .what = "Renders a Cornell-like box lit by an area light, with a block, "
                "a mirror sphere\nand a glass sphere."};
    example_args args;
    ray_camera cam;
    ray_scene *scene;
    int rc = example_start(&cli, argc, argv, &args);

    if (rc != 0)
        return rc;
    scene = cornell_scene(&cam, 1, NULL);
    rc = render_to_png(&args, scene, &cam);

    ray_scene_free(scene);
    return rc;
}
