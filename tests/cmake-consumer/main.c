/* SPDX-License-Identifier: MIT */
/*
** main.c -- a program built against an installed libray, as a user's
** would be (scripts/check-install.sh: through pkg-config and through
** CMake's find_package, from a moved install tree).  It renders a 4 x 4
** image of a lit sphere, checks that the library linked is the one the
** header describes, and that PNG output is there exactly when the
** library was built with it (EXPECT_PNG, the build's PNG setting).
** Exit status 0 when all holds.
*/
#include <stdio.h>

#include <ray.h>

#ifndef EXPECT_PNG
#define EXPECT_PNG 1
#endif

static int fail(const char *what, int rc)
{
    fprintf(stderr, "consumer: %s: %s\n", what, ray_strerror(rc));
    return 1;
}

int main(int argc, char **argv)
{
    static const ray_phong_params white = {.diffuse = {0.8, 0.8, 0.8}};
    ray_material m = ray_material_phong(&white);
    ray_light light = {.kind = RAY_LIGHT_POINT, .position = {5, 5, 5},
                       .intensity = {60, 60, 60}};
    ray_camera cam = {.position = {0, 0, 5}, .look_at = {0, 0, 0},
                      .up = {0, 1, 0}, .vfov = 30};
    const ray_vec3 centre = {0, 0, 0};
    ray_render_options opt;
    ray_scene *scene;
    float rgb[4 * 4 * 3];
    int rc, want_png = EXPECT_PNG ? RAY_OK : RAY_ENOTSUP;

    if (ray_version_number() != RAY_VERSION_NUMBER) {
        fprintf(stderr, "consumer: header %s, library %s\n",
                RAY_VERSION_STRING, ray_version_string());
        return 1;
    }
    if ((rc = ray_scene_new(&scene, NULL, NULL)) != RAY_OK)
        return fail("ray_scene_new", rc);
    if ((rc = ray_scene_add_material(scene, &m, NULL)) != RAY_OK ||
        (rc = ray_scene_add_sphere(scene, centre, 1, 0, NULL)) != RAY_OK ||
        (rc = ray_scene_add_light(scene, &light, NULL)) != RAY_OK ||
        (rc = ray_scene_commit(scene)) != RAY_OK)
        return fail("building the scene", rc);
    opt = (ray_render_options){.width = 4, .height = 4};
    opt.threads = 1;
    rc = ray_render(scene, &cam, &opt, rgb, NULL);
    ray_scene_free(scene);
    if (rc != RAY_OK)
        return fail("ray_render", rc);
    /* The sphere fills the middle (30 degrees at distance 5 span 2.7
    ** units, the sphere 2), lit from the viewer's side: not black. */
    if (!(rgb[3 * (1 * 4 + 1)] > 0.0f)) {
        fprintf(stderr, "consumer: the sphere is not lit\n");
        return 1;
    }
    if (argc > 1 && (rc = ray_write_png(argv[1], rgb, 4, 4, 8)) != want_png)
        return fail("ray_write_png gave", rc);
    printf("consumer: libray %s, 4x4 rendered, PNG %s\n",
           ray_version_string(), EXPECT_PNG ? "written" : "RAY_ENOTSUP");
    return 0;
}
