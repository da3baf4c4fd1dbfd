/*
** whitted.c -- the classic scene of Whitted's 1980 paper: a checkerboard
** floor, a mirror sphere and a glass sphere under a point light.
**
**     whitted [out.png [width height [samples [threads]]]]
**
** Defaults: whitted.png, 640 x 480, 4 samples per pixel, all CPUs.
*/
#include <time.h>

#include "common.h"

/* Sky: a vertical gradient of the escaping ray's direction. */
static void sky(void *ud, const ray_ray *r, ray_rgb *out)
{
    double len = r->dir.x * r->dir.x + r->dir.y * r->dir.y +
                 r->dir.z * r->dir.z;
    double up = len > 0 ? r->dir.y / sqrt(len) : 0;
    double k = 0.5 * (up + 1);

    (void)ud;
    *out = rgb(0.35 + 0.25 * k, 0.45 + 0.3 * k, 0.75 + 0.2 * k);
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

int main(int argc, char **argv)
{
    static const ray_phong_params red = {{0.75, 0.08, 0.06}, {0.2, 0.2, 0.2},
                                         40, 1, {0, 0, 0}};
    static const ray_phong_params yellow = {{0.8, 0.7, 0.1}, {0.2, 0.2, 0.2},
                                            40, 1, {0, 0, 0}};
    static const ray_rgb chrome = {0.9, 0.9, 0.9};
    static const ray_glass_params glass = {1.5, {0.05, 0.02, 0.01}};
    ray_checker_params floor_params;
    const char *path = argc > 1 ? argv[1] : "whitted.png";
    unsigned width = argc > 3 ? (unsigned)atoi(argv[2]) : 640;
    unsigned height = argc > 3 ? (unsigned)atoi(argv[3]) : 480;
    ray_light light = {RAY_LIGHT_POINT, {4, 7, 5}, {0, 0, 0}, {0, 0, 0},
                       {0, 0, 0}, 0, {80, 80, 80}, 0};
    ray_camera cam = {{0, 1.5, 5.5}, {0, 0.9, 0}, {0, 1, 0}, 45, 0, 0};
    ray_render_options opt;
    ray_material m;
    ray_scene *scene;
    ray_stats stats;
    unsigned floor_mat, mirror_mat, glass_mat;
    float *image;
    double t0;

    floor_params.even = ray_material_phong(&red);
    floor_params.odd = ray_material_phong(&yellow);
    floor_params.scale = 1.0;
    check(ray_scene_new(&scene, NULL, NULL), "ray_scene_new");
    m = ray_material_checker(&floor_params);
    check(ray_scene_add_material(scene, &m, &floor_mat), "floor material");
    m = ray_material_mirror(&chrome);
    check(ray_scene_add_material(scene, &m, &mirror_mat), "mirror material");
    m = ray_material_glass(&glass);
    check(ray_scene_add_material(scene, &m, &glass_mat), "glass material");
    check(ray_scene_add_plane(scene, vec(0, 0, 0), vec(0, 1, 0), floor_mat,
                              NULL), "floor");
    check(ray_scene_add_sphere(scene, vec(-1.1, 1.0, -1.2), 1.0, mirror_mat,
                               NULL), "mirror sphere");
    check(ray_scene_add_sphere(scene, vec(0.9, 0.8, 0.6), 0.8, glass_mat,
                               NULL), "glass sphere");
    check(ray_scene_add_light(scene, &light, NULL), "light");
    check(ray_scene_set_ambient(scene, rgb(0.12, 0.12, 0.14)), "ambient");
    check(ray_scene_set_background_fn(scene, sky, NULL), "background");
    check(ray_scene_commit(scene), "commit");

    ray_render_options_init(&opt, width, height);
    opt.samples = argc > 4 ? (unsigned)atoi(argv[4]) : 4;
    opt.threads = argc > 5 ? (unsigned)atoi(argv[5]) : 0;
    opt.progress = progress_bar;
    if (width == 0 || height == 0 || opt.samples == 0) {
        fprintf(stderr, "usage: whitted [out.png [width height [samples "
                        "[threads]]]]\n");
        return 2;
    }
    image = malloc(sizeof(float) * 3 * width * height);
    if (image == NULL)
        return 1;
    t0 = now();
    check(ray_render(scene, &cam, &opt, image, &stats), "render");
    t0 = now() - t0;
    check(ray_write_png(path, image, width, height, 8), path);
    printf("whitted: wrote %s (%ux%u, %u samples per pixel)\n", path, width,
           height, opt.samples);
    print_stats("whitted", &stats, t0);
    free(image);
    ray_scene_free(scene);
    return 0;
}
