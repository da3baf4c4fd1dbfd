/* SPDX-License-Identifier: MIT */
/*
** whitted.c -- the classic scene of Whitted's 1980 paper: a checkerboard
** floor, a mirror sphere and a glass sphere under a point light.
**
**     whitted [out.png [width height [samples [threads]]]]
**
** Defaults: whitted.png, 640 x 480, 4 samples per pixel, all CPUs.
*/
#include "scenes.h"

int main(int argc, char **argv)
{
    ray_camera cam;
    ray_scene *scene = whitted_scene(&cam, 1, NULL);
    int rc = render_to_png("whitted", scene, &cam, argc, argv, 640, 480);

    ray_scene_free(scene);
    return rc;
}
