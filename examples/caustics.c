/* SPDX-License-Identifier: MIT */
/*
** caustics.c -- light focused by a glass sphere and by a ring of brass
** mirrors onto a diffuse floor (caustics, light paths L S+ D E), which
** tracing from the eye alone cannot find: ray_render emits photons from
** the light first (render option "photons"), traces them through the
** materials that scatter them -- the built-in glass, and the ring's USER
** material, a tinted mirror with its own scatter callback
** (tinted_mirror_scatter in scenes.h) -- and the floor's Phong material
** gathers them (ray_caustics_at).  The scene is caustics_scene in
** examples/scenes.h, shared with bench/caustics.c.
**
**     caustics [out.png [width height [samples [threads]]]]
**
** RAY_PHOTONS (default 1000000) sets the number of photons.
*/
#include "scenes.h"

int main(int argc, char **argv)
{
    static const example_cli cli = {
        .name = "caustics", .output_default = "caustics.png", .sized = 1,
        .width = 640, .height = 480, .samples = 4,
        .what = "Renders the caustics of a glass sphere and a ring of brass "
                "mirrors on a floor\nunder a small light (RAY_PHOTONS "
                "photons, default 1000000)."};
    example_args args;
    ray_camera cam;
    ray_scene *scene;
    const char *env = getenv("RAY_PHOTONS");
    int rc = example_start(&cli, argc, argv, &args);

    if (rc != 0)
        return rc;
    args.photons = 1000000;
    if (env != NULL && env[0] != '\0') {
        char *end;
        unsigned long long n = strtoull(env, &end, 10);
        if (*end != '\0' || n > RAY_MAX_PHOTONS)
            return example_bad(&cli, "RAY_PHOTONS '%s': not a number of "
                               "photons (0 .. %llu)", env,
                               (unsigned long long)RAY_MAX_PHOTONS);
        args.photons = n;
    }
    scene = caustics_scene(&cam);
    rc = render_to_png(&args, scene, &cam);
    ray_scene_free(scene);
    return rc;
}
