/* SPDX-License-Identifier: MIT */
/*
** primitives.c -- the primitives alone, without a scene: a sphere and a triangle, seen by a
** pinhole camera, shaded by the angle to a light, written as a PNG.
**
**     primitives [out.png]
*/
#include "common.h"         /* vec(), and the command line */

#include "common.h"

#define WIDTH 320
#define HEIGHT 240

/* Diffuse shade of a hit for a light in direction (1, 1, 1)/sqrt 3,
** the normal turned toward the viewer first. */
static double shade(const ray_ray *r, const ray_hit *h)
{
    double k = 1.0 / sqrt(3.0);
    ray_vec3 n = h->n;
    double cosine;

    if (n.x * r->dir.x + n.y * r->dir.y + n.z * r->dir.z > 0)
        n = vec(-n.x, -n.y, -n.z);
    cosine = k * (n.x + n.y + n.z);
    return 0.1 + 0.9 * (cosine > 0 ? cosine : 0);
}

int main(int argc, char **argv)
{
    static const example_cli cli = {
        .name = "primitives", .output_default = "primitives.png",
        .width = WIDTH, .height = HEIGHT,
        .what = "Renders a sphere and a triangle with the primitive "
                "intersection calls alone."};
    example_args args;
    float *rgb;
    int x, y, rc = example_start(&cli, argc, argv, &args);

    if (rc != 0)
        return rc;
    rgb = malloc(sizeof(float) * 3 * WIDTH * HEIGHT);
    if (rgb == NULL) {
        fprintf(stderr, "primitives: out of memory\n");
        return 1;
    }
    for (y = 0; y < HEIGHT; y++) {
        for (x = 0; x < WIDTH; x++) {
            /* Camera at (0, 0, 4) looking down -z, 60 degree vertical fov. */
            double s = tan(3.14159265358979323846 / 6);
            ray_ray r;
            ray_hit h;
            float *px = rgb + 3 * (y * WIDTH + x);

            r.org = vec(0, 0, 4);
            r.dir = vec((2 * (x + 0.5) / WIDTH - 1) * s * WIDTH / HEIGHT,
                        (1 - 2 * (y + 0.5) / HEIGHT) * s, -1);
            r.tmin = 0;
            r.tmax = HUGE_VAL;
            px[0] = 0.05f;
            px[1] = 0.07f;
            px[2] = 0.12f;
            /* Each hit shrinks tmax, so the nearer surface wins. */
            if (ray_triangle(&r, vec(-2.5, -1.5, -1), vec(2.5, -1.5, -1),
                             vec(0, 2, -2), &h)) {
                double c = shade(&r, &h);
                r.tmax = h.t;
                px[0] = (float)(c * 0.2);
                px[1] = (float)(c * 0.6);
                px[2] = (float)(c * 0.3);
            }
            if (ray_sphere(&r, vec(0.3, -0.2, 0), 1.0, &h)) {
                double c = shade(&r, &h);
                px[0] = (float)(c * 0.9);
                px[1] = (float)(c * 0.3);
                px[2] = (float)(c * 0.2);
            }
        }
    }
    rc = example_write_png(&args, rgb);
    free(rgb);
    if (rc != 0)
        return rc;
    printf("primitives: wrote %s (%dx%d)\n", args.output, WIDTH, HEIGHT);
    return 0;
}
