/* SPDX-License-Identifier: MIT */
/*
** teapot.c -- the Utah teapot (Martin Newell, 1975) as its 32 bicubic
** Bezier patches, each intersected as a curved surface
** (ray_scene_add_bezier), not tessellated: a red glaze (Phong, a white
** highlight and a little mirror) on a checkerboard floor, under a soft
** spherical key light and a dim fill light, against a pale backdrop.
**
**     teapot [model.bpt [out.png [width height [samples [threads]]]]]
**
** model.bpt defaults to data/teapot.bpt, which scripts/fetch-teapot.sh
** writes (the data is fetched, not committed: see there).  Any file in
** the same Newell patch format works: the camera and the lights are
** placed from the control points' box.
**
** The teapot is not closed: there is a gap around the lid and the spout
** is open, so some patches are seen from behind.  Materials shade with
** the normal turned toward the ray, so both sides are lit alike.
*/
#include "teapot_scene.h"

static int file_exists(const char *path)
{
    FILE *f = fopen(path, "rb");
    int exists = f != NULL;

    if (exists)
        fclose(f);
    return exists;
}

int main(int argc, char **argv)
{
    static const example_cli cli = {
        .name = "teapot", .input = "model.bpt",
        .input_what = "the Newell patch file",
        .input_default = "data/teapot.bpt", .output_default = "teapot.png",
        .sized = 1, .width = 480, .height = 360, .samples = 4,
        .what = "Renders the Utah teapot as Bezier patches on a checkerboard "
                "floor."};
    example_args args;
    bpt_patches model;
    ray_camera cam;
    ray_scene *scene;
    char err[600];
    const char *path;
    int rc = example_start(&cli, argc, argv, &args);

    if (rc != 0)
        return rc;
    path = args.input;
    if (!file_exists(path)) {
        perror(path);
        fprintf(stderr, "teapot: the teapot is not in the repository; "
                        "scripts/fetch-teapot.sh writes data/teapot.bpt\n");
        return 1;
    }
    if (bpt_load(path, &model, err, sizeof err) != 0) {
        fprintf(stderr, "teapot: %s\n", err);
        return 1;
    }
    printf("teapot: %s: %zu patches, %zu control points\n", path,
           model.count, model.vertex_count);
    scene = teapot_scene(&model, &cam);
    bpt_free(&model);                /* the scene copied the patches */
    rc = render_to_png(&args, scene, &cam);
    ray_scene_free(scene);
    return rc;
}
