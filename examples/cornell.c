/* SPDX-License-Identifier: MIT */
/*
** cornell.c -- a Cornell-box-like room of polygons and triangles, lit by
** a rectangular area light under the ceiling (soft shadows), with a tall
** block, a mirror sphere and a glass sphere.
**
**     cornell [out.png [width height [samples [threads]]]]
**
** Defaults: cornell.png, 400 x 400, 4 samples per pixel, all CPUs.
*/
#include "scenes.h"

int main(int argc, char **argv)
{
    ray_camera cam;
    ray_scene *scene = cornell_scene(&cam, 1, NULL);
    int rc = render_to_png("cornell", scene, &cam, argc, argv, 400, 400);

    ray_scene_free(scene);
    return rc;
}
