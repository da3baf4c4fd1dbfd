/*
** cornell.c -- a Cornell-box-like room of polygons and triangles, lit by
** a rectangular area light under the ceiling (soft shadows), with a tall
** block, a mirror sphere and a glass sphere.
**
**     cornell [out.png [width height [samples [threads]]]]
*/
#include "common.h"

/* Add the quad a b c d as two triangles (a b c, a c d). */
static void add_quad_triangles(ray_scene *s, ray_vec3 a, ray_vec3 b,
                               ray_vec3 c, ray_vec3 d, unsigned mat)
{
    check(ray_scene_add_triangle(s, a, b, c, mat, NULL), "triangle");
    check(ray_scene_add_triangle(s, a, c, d, mat, NULL), "triangle");
}

static void add_quad_polygon(ray_scene *s, ray_vec3 a, ray_vec3 b,
                             ray_vec3 c, ray_vec3 d, unsigned mat)
{
    ray_vec3 v[4];
    v[0] = a;
    v[1] = b;
    v[2] = c;
    v[3] = d;
    check(ray_scene_add_polygon(s, v, 4, mat, NULL), "polygon");
}

/* A box standing on the floor: centre (cx, cz), half sizes hx, hz,
** height h, rotated by angle a about y; four side polygons and a top. */
static void add_block(ray_scene *s, double cx, double cz, double hx,
                      double hz, double h, double a, unsigned mat)
{
    ray_vec3 lo[4], hi[4];
    int i;

    for (i = 0; i < 4; i++) {
        double x = (i == 1 || i == 2) ? hx : -hx;
        double z = (i >= 2) ? hz : -hz;
        double rx = cx + x * cos(a) - z * sin(a);
        double rz = cz + x * sin(a) + z * cos(a);
        lo[i] = vec(rx, 0, rz);
        hi[i] = vec(rx, h, rz);
    }
    for (i = 0; i < 4; i++) {
        int j = (i + 1) % 4;
        add_quad_polygon(s, lo[i], lo[j], hi[j], hi[i], mat);
    }
    add_quad_polygon(s, hi[0], hi[3], hi[2], hi[1], mat);
}

int main(int argc, char **argv)
{
    static const ray_phong_params white = {{0.75, 0.75, 0.72}, {0, 0, 0}, 1,
                                           0, {0, 0, 0}};
    static const ray_phong_params red = {{0.65, 0.06, 0.05}, {0, 0, 0}, 1, 0,
                                         {0, 0, 0}};
    static const ray_phong_params green = {{0.12, 0.5, 0.09}, {0, 0, 0}, 1,
                                           0, {0, 0, 0}};
    static const ray_rgb chrome = {0.92, 0.92, 0.92};
    static const ray_glass_params glass = {1.5, {0, 0, 0}};
    const char *path = argc > 1 ? argv[1] : "cornell.png";
    unsigned width = argc > 3 ? (unsigned)atoi(argv[2]) : 400;
    unsigned height = argc > 3 ? (unsigned)atoi(argv[3]) : 400;
    /* edge1 x edge2 = (0, -2.25, 0): the lamp shines down. */
    ray_light lamp = {RAY_LIGHT_RECT, {-0.75, 4.98, -0.75}, {0, 0, 0},
                      {1.5, 0, 0}, {0, 0, 1.5}, 0, {16, 15, 13}, 16};
    ray_camera cam = {{0, 2.5, 9.5}, {0, 2.5, 0}, {0, 1, 0}, 36, 0, 0};
    ray_render_options opt;
    ray_material m;
    ray_scene *scene;
    ray_stats stats;
    unsigned w, r, g, mir, gl;
    float *image;

    check(ray_scene_new(&scene, NULL, NULL), "ray_scene_new");
    m = ray_material_phong(&white);
    check(ray_scene_add_material(scene, &m, &w), "white");
    m = ray_material_phong(&red);
    check(ray_scene_add_material(scene, &m, &r), "red");
    m = ray_material_phong(&green);
    check(ray_scene_add_material(scene, &m, &g), "green");
    m = ray_material_mirror(&chrome);
    check(ray_scene_add_material(scene, &m, &mir), "mirror");
    m = ray_material_glass(&glass);
    check(ray_scene_add_material(scene, &m, &gl), "glass");

    /* The room: x, z in [-2.5, 2.5], y in [0, 5], open toward +z. */
    add_quad_polygon(scene, vec(-2.5, 0, 2.5), vec(2.5, 0, 2.5),
                     vec(2.5, 0, -2.5), vec(-2.5, 0, -2.5), w);       /* floor */
    add_quad_polygon(scene, vec(-2.5, 5, -2.5), vec(2.5, 5, -2.5),
                     vec(2.5, 5, 2.5), vec(-2.5, 5, 2.5), w);         /* ceiling */
    add_quad_polygon(scene, vec(-2.5, 0, -2.5), vec(2.5, 0, -2.5),
                     vec(2.5, 5, -2.5), vec(-2.5, 5, -2.5), w);       /* back */
    add_quad_triangles(scene, vec(-2.5, 0, 2.5), vec(-2.5, 0, -2.5),
                       vec(-2.5, 5, -2.5), vec(-2.5, 5, 2.5), r);     /* left */
    add_quad_triangles(scene, vec(2.5, 0, -2.5), vec(2.5, 0, 2.5),
                       vec(2.5, 5, 2.5), vec(2.5, 5, -2.5), g);       /* right */
    add_block(scene, -0.9, -0.8, 0.7, 0.7, 2.8, 0.35, w);
    check(ray_scene_add_sphere(scene, vec(1.2, 0.8, 0.5), 0.8, gl, NULL),
          "glass sphere");
    check(ray_scene_add_sphere(scene, vec(-0.3, 0.5, 1.3), 0.5, mir, NULL),
          "mirror sphere");
    check(ray_scene_add_light(scene, &lamp, NULL), "lamp");
    check(ray_scene_set_ambient(scene, rgb(0.06, 0.06, 0.06)), "ambient");
    check(ray_scene_commit(scene), "commit");

    ray_render_options_init(&opt, width, height);
    opt.samples = argc > 4 ? (unsigned)atoi(argv[4]) : 4;
    opt.threads = argc > 5 ? (unsigned)atoi(argv[5]) : 0;
    opt.progress = progress_bar;
    if (width == 0 || height == 0 || opt.samples == 0)
        return 2;
    image = malloc(sizeof(float) * 3 * width * height);
    if (image == NULL)
        return 1;
    check(ray_render(scene, &cam, &opt, image, &stats), "render");
    check(ray_write_png(path, image, width, height, 8), path);
    printf("cornell: wrote %s (%ux%u, %u samples per pixel)\n", path, width,
           height, opt.samples);
    print_stats("cornell", &stats, 0);
    free(image);
    ray_scene_free(scene);
    return 0;
}
