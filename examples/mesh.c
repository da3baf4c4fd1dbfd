/* SPDX-License-Identifier: MIT */
/*
** mesh.c -- load a Wavefront OBJ and render it: clay (Blinn-Phong, smooth
** if the file has normals) on a slightly reflective floor, under a
** spherical light, seen from the +z side at a distance that frames it.
**
**     mesh model.obj [out.png [width height [samples [threads]]]]
**
** scripts/fetch-bunny.sh writes data/bunny.obj (and finer versions).
*/
#include "scenes.h"

int main(int argc, char **argv)
{
    ray_camera cam;
    ray_scene *scene;
    size_t triangles;
    int rc;

    if (argc < 2) {
        fprintf(stderr, "usage: mesh model.obj [out.png [width height "
                        "[samples [threads]]]]\n");
        return 2;
    }
    scene = mesh_scene(argv[1], &cam, 1, NULL, &triangles);
    if (scene == NULL)
        return 1;
    printf("mesh: %s: %zu triangles\n", argv[1], triangles);
    rc = render_to_png("mesh", scene, &cam, argc - 1, argv + 1, 480, 360);
    ray_scene_free(scene);
    return rc;
}
