/* SPDX-License-Identifier: MIT */
/*
** implicit.c -- the lecture's "ray ∩ implicit surface", three ways: a
** gold torus solved exactly (ray_scene_add_torus, the quartic), blue
** metaballs sphere-traced with their Lipschitz bound
** (ray_implicit_blobs), and a rounded cube written here as a user field
** f(x, y, z) = x^4 + y^4 + z^4 - r^4 with no bound, found by bracketing
** sign changes along the ray -- on a checkerboard floor under a soft
** light.
**
**     implicit [out.png [width height [samples [threads]]]]
**
** Defaults: implicit.png, 480 x 300, 4 samples per pixel, all CPUs.
*/
#include "common.h"

/* The "squircle" cube |p - c|_4 = r: smooth, rounder than a cube, and its
** gradient 4 (p - c)^3 grows with the distance, so there is no global
** Lipschitz bound: ray_implicit samples it every "step" instead. */
typedef struct squircle {
    ray_vec3 c;
    double r;
} squircle;

static double squircle_f(void *ud, ray_vec3 p)
{
    const squircle *s = ud;
    double x = p.x - s->c.x, y = p.y - s->c.y, z = p.z - s->c.z;
    double r2 = s->r * s->r;
    return x * x * x * x + y * y * y * y + z * z * z * z - r2 * r2;
}

static ray_vec3 squircle_grad(void *ud, ray_vec3 p)
{
    const squircle *s = ud;
    double x = p.x - s->c.x, y = p.y - s->c.y, z = p.z - s->c.z;
    return vec(4 * x * x * x, 4 * y * y * y, 4 * z * z * z);
}

/* Texture coordinates of the squircle: its front face's x and y. */
static void squircle_uv(void *ud, ray_vec3 p, ray_vec3 n, double *u,
                        double *v)
{
    const squircle *s = ud;
    (void)n;
    *u = (p.x - s->c.x) / s->r;
    *v = (p.y - s->c.y) / s->r;
}


static unsigned add_material(ray_scene *s, ray_material m)
{
    unsigned id;
    check(ray_scene_add_material(s, &m, &id), "ray_scene_add_material");
    return id;
}

int main(int argc, char **argv)
{
    /* The sky: pale grey-blue, brighter overhead. */
    static sky_colors pale_sky = {{0.55, 0.6, 0.7}, {0.2, 0.25, 0.25}};
    /* Everything the scene borrows lives as long as main. */
    static ray_phong_params gold, blue, ivory, light_sq, dark_sq;
    static ray_checker_params floor_params;
    static const ray_blob blobs[] = {
        {.center = {-0.35, 0.55, 0.0}, .radius = 0.75, .strength = 1.0},
        {.center = {0.35, 0.75, 0.1}, .radius = 0.7, .strength = 1.0},
        {.center = {0.0, 1.25, -0.1}, .radius = 0.6, .strength = 1.0},
        {.center = {-0.1, 0.9, 0.45}, .radius = 0.5, .strength = 0.8},
        {.center = {0.25, 1.5, 0.3}, .radius = 0.45, .strength = 0.7}};
    static ray_blobs_params blob_params;
    static squircle cube = {{1.9, 0.55, -0.6}, 0.55};
    ray_torus_params torus = {.center = {-1.9, 0.45, -0.4},
                              .axis = {0.35, 1, 0.25}, .major = 0.62,
                              .minor = 0.22};
    ray_implicit_surface blob_surface, cube_surface;
    ray_light key = {.kind = RAY_LIGHT_SPHERE, .position = {-3, 6, 4},
                     .radius = 0.6, .intensity = {45, 44, 40},
                     .samples = 16};
    ray_camera cam = {.position = {0, 1.7, 4.9}, .look_at = {0, 0.7, -0.3},
                      .up = {0, 1, 0}, .vfov = 40};
    static const example_cli cli = {
        .name = "implicit", .output_default = "implicit.png", .sized = 1,
        .width = 480, .height = 300, .samples = 4,
        .what = "Renders implicit surfaces: an exact torus, metaballs and a "
                "rounded cube."};
    example_args args;
    ray_scene *scene;
    unsigned floor_mat;
    int rc = example_start(&cli, argc, argv, &args);

    if (rc != 0)
        return rc;
    gold = phong_params(rgb(0.8, 0.55, 0.15), rgb(0.6, 0.55, 0.4), 80,
                 rgb(0.25, 0.2, 0.1));
    blue = phong_params(rgb(0.15, 0.3, 0.8), rgb(0.5, 0.5, 0.5), 120,
                 rgb(0.05, 0.05, 0.05));
    ivory = phong_params(rgb(0.85, 0.82, 0.75), rgb(0.3, 0.3, 0.3), 40,
                  rgb(0, 0, 0));
    light_sq = phong_params(rgb(0.75, 0.75, 0.72), rgb(0, 0, 0), 1, rgb(0, 0, 0));
    dark_sq = phong_params(rgb(0.25, 0.27, 0.3), rgb(0, 0, 0), 1, rgb(0, 0, 0));
    floor_params.even = ray_material_phong(&light_sq);
    floor_params.odd = ray_material_phong(&dark_sq);
    floor_params.scale = 1.0;

    blob_params.blobs = blobs;
    blob_params.count = sizeof blobs / sizeof blobs[0];
    blob_params.threshold = 0.35;
    check(ray_implicit_blobs(&blob_params, &blob_surface),
          "ray_implicit_blobs");

    memset(&cube_surface, 0, sizeof cube_surface);
    cube_surface.f = squircle_f;
    cube_surface.gradient = squircle_grad;
    cube_surface.uv = squircle_uv;
    cube_surface.ud = &cube;
    cube_surface.lo = vec(cube.c.x - cube.r, cube.c.y - cube.r,
                          cube.c.z - cube.r);
    cube_surface.hi = vec(cube.c.x + cube.r, cube.c.y + cube.r,
                          cube.c.z + cube.r);
    cube_surface.lipschitz = 0;           /* none: bracketing */
    cube_surface.step = cube.r / 16;      /* no feature is thinner */

    check(ray_scene_new(&scene, NULL, NULL), "ray_scene_new");
    floor_mat = add_material(scene, ray_material_checker(&floor_params));
    check(ray_scene_add_plane(scene, vec(0, 0, 0), vec(0, 1, 0), floor_mat,
                              NULL), "floor");
    check(ray_scene_add_torus(scene, &torus,
                              add_material(scene, ray_material_phong(&gold)),
                              NULL), "ray_scene_add_torus");
    check(ray_scene_add_implicit(scene, &blob_surface,
                                 add_material(scene,
                                              ray_material_phong(&blue)),
                                 NULL), "metaballs");
    check(ray_scene_add_implicit(scene, &cube_surface,
                                 add_material(scene,
                                              ray_material_phong(&ivory)),
                                 NULL), "rounded cube");
    check(ray_scene_add_light(scene, &key, NULL), "light");
    check(ray_scene_set_background(scene, rgb(0, 0, 0), sky_gradient, &pale_sky),
          "background");
    check(ray_scene_set_ambient(scene, rgb(0.12, 0.12, 0.14)), "ambient");
    check(ray_scene_commit(scene), "ray_scene_commit");
    rc = render_to_png(&args, scene, &cam);
    ray_scene_free(scene);
    return rc;
}
