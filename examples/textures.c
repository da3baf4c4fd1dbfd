/* SPDX-License-Identifier: MIT */
/*
** textures.c -- texture coordinates from every kind of primitive, and
** textures of both kinds: images (a PNG loaded with ray_image_load_png,
** and a checkerboard made in memory with ray_image_new), mip-mapped and
** filtered over each camera ray's cone (unless ray_render_options.no_cones; on by
** default), and procedural functions (ray_texture_fn).
**
**   * a sphere wrapped in the image by its longitude and latitude;
**   * a curved Bezier "canvas" showing the image by its (u, v);
**   * a mesh quad with per-vertex (s, t) showing it too;
**   * a torus striped by its two angles (procedural);
**   * the floor, a plane, tiled in its own axes with a checkerboard image
**     of 8 x 8 squares per unit: without cones (no_cones = 1 in
**     ray_render_options) its far squares alias into moire at a few
**     samples per pixel; with them each ray reads the mip level of its
**     footprint.
**
**     textures [image.png [out.png [width height [samples [threads]]]]]
**
** image.png defaults to doc/cornell.png (run from the repository root).
*/
#include "common.h"

/* Stripes around a torus: light along the tube (v), dark bands around
** the axis (u), from the two angles ray_torus gives. */
static void torus_stripes(void *ud, const ray_shade_args *a, ray_rgb *out)
{
    double band = 0.5 + 0.5 * cos(2 * 3.14159265358979 * 12 * a->u);
    double ring = 0.5 + 0.5 * cos(2 * 3.14159265358979 * 3 * a->v);
    (void)ud;
    *out = rgb(0.3 + 0.7 * band, 0.25 + 0.5 * band * ring, 0.2 + 0.2 * ring);
}

/* The floor's tile: a 64 x 64 image of 8 x 8 squares in two warm tones,
** made in memory (linear RGB, rows top to bottom). */
static ray_image *floor_tile(void)
{
    static float texels[64 * 64 * 3];
    ray_image *img;
    int x, y;

    for (y = 0; y < 64; y++)
        for (x = 0; x < 64; x++) {
            int odd = (x / 8 + y / 8) & 1;
            float *p = texels + 3 * (64 * y + x);
            p[0] = odd ? 0.85f : 0.35f;
            p[1] = odd ? 0.7f : 0.27f;
            p[2] = odd ? 0.5f : 0.2f;
        }
    check(ray_image_new(64, 64, texels, &img), "ray_image_new");
    return img;
}


/* A textured Lambert-plus-highlight block; other fields zero. */
static ray_phong_params textured(ray_texture t, double specular)
{
    ray_phong_params p;
    memset(&p, 0, sizeof p);
    p.diffuse = rgb(0.9, 0.9, 0.9);
    p.specular = rgb(specular, specular, specular);
    p.shininess = 60;
    p.blinn = 1;
    p.texture = t;
    return p;
}

static unsigned add_material(ray_scene *s, const ray_phong_params *p)
{
    ray_material m = ray_material_phong(p);
    unsigned id;
    check(ray_scene_add_material(s, &m, &id), "ray_scene_add_material");
    return id;
}

/* A canvas: a Bezier patch bulging toward +z, 2.4 wide and 1.8 high,
** standing on the floor at x = cx; (u, v) = (0, 0) at its lower left, so
** the image shows upright. */
static void canvas(ray_vec3 cp[16], double cx, double cz)
{
    int i, j;
    for (i = 0; i < 4; i++)
        for (j = 0; j < 4; j++) {
            double bulge = (i == 1 || i == 2) && (j == 1 || j == 2) ? 0.5 : 0;
            cp[4 * i + j] = vec(cx - 1.2 + 0.8 * j, 0.2 + 0.6 * i,
                                cz + bulge + 0.15 * (j - 1.5) * (j - 1.5));
        }
}

/* A quad as a two-triangle mesh with per-vertex (s, t). */
static void add_quad(ray_scene *s, unsigned material)
{
    static const ray_vec3 v[4] = {{-3.1, 0.15, 0.4}, {-1.9, 0.15, 1.0},
                                  {-1.9, 1.05, 1.0}, {-3.1, 1.05, 0.4}};
    static const double st[8] = {0, 0, 1, 0, 1, 1, 0, 1};
    static const unsigned idx[6] = {0, 1, 2, 0, 2, 3};
    ray_mesh m;

    memset(&m, 0, sizeof m);
    m.vertices = v;
    m.vertex_count = 4;
    m.indices = idx;
    m.triangle_count = 2;
    m.texcoords = st;
    check(ray_scene_add_mesh(s, &m, material, NULL), "ray_scene_add_mesh");
}

int main(int argc, char **argv)
{
    /* The sky: pale grey-blue, brighter overhead. */
    static sky_colors pale_sky = {{0.5, 0.55, 0.65}, {0.2, 0.25, 0.3}};
    static ray_phong_params image_mat, torus_mat, floor_mat;
    static const example_cli cli = {
        .name = "textures", .input = "image.png",
        .input_what = "the image texture", .input_default = "doc/cornell.png",
        .output_default = "textures.png", .sized = 1, .width = 480,
        .height = 300, .samples = 4,
        .what = "Renders texture coordinates of every kind of primitive, with "
                "an image texture\nand procedural ones."};
    example_args args;
    ray_torus_params torus = {.center = {2.3, 0.5, 0.6},
                              .axis = {0.2, 1, 0.5}, .major = 0.6,
                              .minor = 0.25};
    ray_light key = {.kind = RAY_LIGHT_SPHERE, .position = {2, 6, 5},
                     .radius = 0.5, .intensity = {50, 50, 48}, .samples = 16};
    ray_camera cam = {.position = {0, 2.0, 6.5}, .look_at = {0, 0.8, 0},
                      .up = {0, 1, 0}, .vfov = 42};
    ray_texture stripes = {.fn = torus_stripes};
    ray_image *image, *tile;
    ray_scene *scene;
    ray_vec3 cp[16];
    unsigned w, h;
    int rc = example_start(&cli, argc, argv, &args);

    if (rc != 0)
        return rc;
    rc = ray_image_load_png(args.input, NULL, &image);
    if (rc != RAY_OK) {
        fprintf(stderr, "textures: %s: %s\n", args.input,
                rc == RAY_EIO ? strerror(errno) : ray_strerror(rc));
        return 1;
    }
    ray_image_size(image, &w, &h);
    printf("textures: %s: %u x %u texels\n", args.input, w, h);
    image_mat = textured(ray_texture_image(image), 0.3);
    torus_mat = textured(stripes, 0.5);
    tile = floor_tile();
    floor_mat = textured(ray_texture_image(tile), 0);

    check(ray_scene_new(&scene, NULL, NULL), "ray_scene_new");
    check(ray_scene_add_plane(scene, vec(0, 0, 0), vec(0, 1, 0),
                              add_material(scene, &floor_mat), NULL),
          "floor");
    check(ray_scene_add_sphere(scene, vec(-0.9, 0.75, 1.4), 0.75,
                               add_material(scene, &image_mat), NULL),
          "sphere");
    canvas(cp, 0.2, -1.2);
    check(ray_scene_add_bezier(scene, cp, add_material(scene, &image_mat),
                               NULL), "canvas");
    add_quad(scene, add_material(scene, &image_mat));
    check(ray_scene_add_torus(scene, &torus,
                              add_material(scene, &torus_mat), NULL),
          "torus");
    check(ray_scene_add_light(scene, &key, NULL), "light");
    check(ray_scene_set_background(scene, rgb(0, 0, 0), sky_gradient, &pale_sky),
          "background");
    check(ray_scene_set_ambient(scene, rgb(0.15, 0.15, 0.17)), "ambient");
    check(ray_scene_commit(scene), "ray_scene_commit");
    rc = render_to_png(&args, scene, &cam);
    ray_scene_free(scene);
    ray_image_free(image);
    ray_image_free(tile);
    return rc;
}
