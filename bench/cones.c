/* SPDX-License-Identifier: MIT */
/*
** cones.c -- what ray cones buy on a textured floor to the horizon (issue
** 19): error against a converged reference and render time at 1, 4 and
** 16 samples per pixel, with cones (the texture filtered over each ray's
** footprint, mip-mapped) and without (rays are lines, the texture
** sampled at a point).  Prints Markdown; asserts nothing.
**
** The floor is the plane y = 0 under a directional light, textured by a
** 256 x 256 checkerboard image (8 x 8 squares per repeat, the image
** repeating every world unit), seen from 1 unit above it, looking just
** below the horizon: near the bottom of the image a square spans many
** pixels, near the horizon many squares fall in one pixel, where point
** sampling aliases (moire) and a pixel's mean is what the eye should get.
**
** The reference is 256 samples per pixel WITHOUT cones: the mean of the
** texture over the pixel's box, the image every method tries to reach.
** With cones the 256 samples would each be filtered over a 1/16 pixel
** footprint -- a slightly blurred pixel -- and the reference would favour
** cones.
**
** Why each sample's cone is the pixel's divided by sqrt(samples): the
** last column filters every sample over the whole pixel's footprint (a
** texture that scales args->footprint by sqrt(samples)), which blurs the
** pixel twice, by the filter and by the samples' spread.
**
** Method: one warm-up render of each, then the median of REPS renders
** per row, lines and cones alternating within each repetition; the time
** ratio is cones / lines in the same run.  2 threads.  BENCH_QUICK=1: a
** smaller image and one repetition.
*/
#include "bench.h"
#include "common.h"

static double render(const ray_scene *s, const ray_camera *cam,
                     const ray_render_options *o, float *img)
{
    double t = now_seconds();
    check(ray_render(s, cam, o, img, NULL), "ray_render");
    return now_seconds() - t;
}

/* A checkerboard of 8 x 8 squares, side x side texels, 0.1 and 0.9. */
static ray_image *checker_image(unsigned side)
{
    float *rgb = malloc(3 * sizeof(float) * side * side);
    ray_image *img = NULL;
    unsigned x, y, sq = side / 8;

    if (rgb == NULL)
        return NULL;
    for (y = 0; y < side; y++)
        for (x = 0; x < side; x++) {
            float c = ((x / sq + y / sq) & 1) ? 0.9f : 0.1f;
            float *p = rgb + 3 * ((size_t)y * side + x);
            p[0] = c;
            p[1] = c;
            p[2] = c;
        }
    check(ray_image_new(side, side, rgb, &img), "ray_image_new");
    free(rgb);
    return img;
}

/* ray_texture_image with the footprint scaled by "scale": the whole
** pixel's footprint for a cone made per sample. */
typedef struct scaled_texture {
    const ray_image *img;
    double scale;
} scaled_texture;

static void scaled_lookup(void *ud, const ray_shade_args *a, ray_rgb *out)
{
    const scaled_texture *t = ud;

    ray_image_sample(t->img, a->u, a->v, a->footprint * t->scale,
                               out);
}

static ray_scene *floor_scene(ray_phong_params *p, ray_texture tex,
                              ray_camera *cam)
{
    ray_scene *s = NULL;
    ray_material m;
    ray_light l;
    unsigned mid;

    ray_phong_params_init(p);
    p->diffuse = rgb(1, 1, 1);
    p->texture = tex;
    m = ray_material_phong(p);
    check(ray_scene_new(&s, NULL, NULL), "ray_scene_new");
    check(ray_scene_add_material(s, &m, &mid), "material");
    check(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 1, 0), mid, NULL),
          "floor");
    memset(&l, 0, sizeof l);
    l.kind = RAY_LIGHT_DIRECTIONAL;
    l.direction = vec(0.3, -1, -0.4);
    l.intensity = rgb(0.9, 0.9, 0.9);
    check(ray_scene_add_light(s, &l, NULL), "light");
    check(ray_scene_set_background(s, rgb(0.6, 0.7, 0.9), NULL, NULL), "background");
    check(ray_scene_commit(s), "commit");
    *cam = (ray_camera){.look_at = {0, 0, -1}};
    cam->position = vec(0, 1, 0);
    cam->look_at = vec(0, 0.75, -10);
    cam->vfov = 40;
    return s;
}

int main(void)
{
    static const unsigned spp[] = {1, 4, 16};
    int level = bench_level(), smoke = level == BENCH_SMOKE;
    int reps = level ? 1 : 9, k, i;
    unsigned w = smoke ? 16 : level ? 160 : 640, h = smoke ? 9 : level ? 90 : 360;
    size_t n = (size_t)w * h;
    ray_image *img = checker_image(256);
    ray_phong_params p, pw;
    scaled_texture whole;
    ray_texture wt;
    ray_camera cam;
    ray_scene *s, *sw;
    ray_render_options o;
    float *ref = malloc(3 * sizeof(float) * n),
          *a = malloc(3 * sizeof(float) * n),
          *b = malloc(3 * sizeof(float) * n);
    double t_ref;

    if (img == NULL || ref == NULL || a == NULL || b == NULL) {
        fprintf(stderr, "cones: out of memory\n");
        return 1;
    }
    s = floor_scene(&p, ray_texture_image(img), &cam);
    whole.img = img;
    wt.fn = scaled_lookup;
    wt.ud = &whole;
    sw = floor_scene(&pw, wt, &cam);
    o = (ray_render_options){.width = w, .height = h};
    o.threads = 2;
    o.samples = smoke ? 16 : 256;
    o.no_cones = 1;
    t_ref = render(s, &cam, &o, ref);
    printf("## Ray cones: a textured floor to the horizon\n\n");
    printf("A 256 x 256 checkerboard texture (8 x 8 squares per world unit) "
           "on a floor seen from 1 unit above, to the horizon, %ux%u, 2 "
           "threads (bench/cones.c).  RMSE (values clamped to [0, 1]) "
           "against a 256-sample reference without cones (%.1f s); time: "
           "median of %d, lines and cones alternating; ratio: cones / "
           "lines in the same run.  Last column: cones over the whole pixel "
           "for every sample (instead of the pixel's / sqrt(samples)), "
           "which blurs twice.\n\n", w, h, t_ref, reps);
    printf("| samples per pixel | RMSE, lines | RMSE, cones | time lines (s) "
           "| time cones (s) | time ratio | RMSE, cones over the whole "
           "pixel |\n");
    printf("|---|---|---|---|---|---|---|\n");
    for (k = 0; k < 3; k++) {
        double tl[9], tc[9], el, ec, ew;
        o.samples = spp[k];
        o.no_cones = 1;
        render(s, &cam, &o, a);                  /* warm-up */
        o.no_cones = 0;
        render(s, &cam, &o, b);
        for (i = 0; i < reps; i++) {
            o.no_cones = 1;
            tl[i] = render(s, &cam, &o, a);
            o.no_cones = 0;
            tc[i] = render(s, &cam, &o, b);
        }
        el = rmse(a, ref, n);
        ec = rmse(b, ref, n);
        whole.scale = sqrt((double)spp[k]);
        o.no_cones = 0;
        render(sw, &cam, &o, a);
        ew = rmse(a, ref, n);
        printf("| %u | %.4f | %.4f | %.3f | %.3f | %.2f | %.4f |\n", spp[k],
               el, ec, median(tl, reps), median(tc, reps),
               median(tc, reps) / median(tl, reps), ew);
    }
    printf("\n");
    ray_scene_free(s);
    ray_scene_free(sw);
    ray_image_free(img);
    free(ref);
    free(a);
    free(b);
    return 0;
}
