/* SPDX-License-Identifier: MIT */
/*
** material.c -- a complete user material: a "glazed" surface, a diffuse
** colour under a glossy coat that reflects a fixed fraction.  It shows
** everything a material callback does: weigh the direct light by a BRDF
** (ray_shade_direct loops over the lights and asks for a shadow ray only
** where the light would contribute), spawn and trace a reflection,
** declare the effects it uses.
**
**     material [out.png]
*/
#include "common.h"

typedef struct glazed {
    ray_rgb color;     /* diffuse reflectance under the coat */
    double coat;       /* fraction reflected by the coat, 0..1 */
} glazed;

/* Lambert under the coat: what multiplies each light sample's radiance
** (the BRDF times the cosine, which ray_shade_direct computes). */
static ray_rgb glazed_brdf(void *ud, const ray_brdf_args *b)
{
    const glazed *g = ud;
    return ray_rgb_scale(g->color, (1 - g->coat) * b->cos_light);
}

/* Ambient and direct light on the diffuse base, plus the coat: a mirror
** reflection weighted by g->coat.  The ray starts just off the surface
** (ray_spawn); the tracer may refuse it when the tree is too deep or the
** path too faint, and then it adds nothing. */
static void glazed_shade(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                         ray_rgb *out)
{
    const glazed *g = ud;
    ray_ray refl;
    ray_rgb c;

    *out = ray_rgb_scale(ray_rgb_mul(a->ambient, g->color), 1 - g->coat);
    ray_shade_direct(ctx, a, glazed_brdf, ud, out);
    if (ray_spawn(a->hit, ray_reflect(a->ray->dir, a->normal), &refl) == RAY_OK &&
        ray_trace(ctx, &refl, RAY_KIND_REFLECTION, g->coat, &c) == RAY_OK)
        *out = ray_rgb_add(*out, ray_rgb_scale(c, g->coat));
}

int main(int argc, char **argv)
{
    static const example_cli cli = {
        .name = "material", .output_default = "material.png", .width = 320,
        .height = 240, .what = "Renders a user material, a glazed sphere, "
                               "on a floor under a soft light."};
    static glazed teal = {{0.1, 0.6, 0.6}, 0.25};
    static const ray_phong_params grey = {.diffuse = {0.7, 0.7, 0.7},
                                          .shininess = 1};
    static float image[320 * 240 * 3];
    ray_material glaze = {.shade = glazed_shade, .ud = &teal,
                          .effects = RAY_EFFECT_SHADOW |
                                     RAY_EFFECT_REFLECTION};
    ray_material floor_mat = ray_material_phong(&grey);
    ray_light lamp = {.kind = RAY_LIGHT_SPHERE, .position = {3, 6, 4},
                      .radius = 0.8, .intensity = {60, 60, 60},
                      .samples = 16};
    ray_camera cam = {.position = {0, 1.5, 5}, .look_at = {0, 0.8, 0},
                      .up = {0, 1, 0}, .vfov = 45};
    ray_render_options opt;
    ray_scene *scene;
    ray_stats stats;
    example_args args;
    unsigned m_glaze, m_floor;
    int rc = example_start(&cli, argc, argv, &args);

    if (rc != 0)
        return rc;

    check(ray_scene_new(&scene, NULL, NULL), "ray_scene_new");
    check(ray_scene_add_material(scene, &glaze, &m_glaze), "glaze");
    check(ray_scene_add_material(scene, &floor_mat, &m_floor), "floor");
    check(ray_scene_add_sphere(scene, vec(0, 1, 0), 1, m_glaze, NULL), "sphere");
    check(ray_scene_add_plane(scene, vec(0, 0, 0), vec(0, 1, 0), m_floor,
                              NULL), "floor");
    check(ray_scene_add_light(scene, &lamp, NULL), "lamp");
    check(ray_scene_set_ambient(scene, rgb(0.1, 0.1, 0.1)), "ambient");
    check(ray_scene_commit(scene), "commit");
    opt = (ray_render_options){.width = 320, .height = 240};
    opt.samples = 4;
    check(ray_render(scene, &cam, &opt, image, &stats), "ray_render");
    rc = example_write_png(&args, image);
    if (rc == 0)
        print_stats("material", scene, &stats, 0);
    ray_scene_free(scene);
    return rc;
}
