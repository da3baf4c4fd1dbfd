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
    static const example_cli cli = {
        .name = "mesh", .input = "model.obj",
        .input_what = "the Wavefront OBJ model", .output_default = "mesh.png",
        .sized = 1, .width = 480, .height = 360, .samples = 4,
        .what = "Renders a Wavefront OBJ model in clay on a floor under a "
                "soft light."};
    example_args args;
    ray_camera cam;
    ray_scene *scene;
    size_t triangles;
    int rc = example_start(&cli, argc, argv, &args);

    if (rc != 0)
        return rc;
    scene = mesh_scene(args.input, &cam, 1, NULL, &triangles);
    if (scene == NULL)
        return 1;
    printf("mesh: %s: %zu triangles\n", args.input, triangles);
    rc = render_to_png(&args, scene, &cam);
    ray_scene_free(scene);
    return rc;
}
