/* SPDX-License-Identifier: MIT */
/*
** effects.c -- what simulating only the needed effects saves: for each
** example scene, the rays cast and the render time with the effect
** analysis and pruning on, against the naive mode that spawns every
** declared effect up to the maximum depth (ray_limits.no_pruning),
** with the image difference this costs; and adaptive against uniform
** antialiasing: primary rays, time and error against a converged
** reference.  Prints Markdown; asserts nothing.
**
**     effects [DATA_DIR]      (data/bunny.obj for the mesh scene)
**
** Method: one warm-up render, then the median of REPS; pruned and naive
** alternate within each repetition.  BENCH_QUICK=1: smaller images.
*/
#include "bench.h"
#include "scenes.h"

static int reps = 3;

static unsigned long long total_rays(const ray_stats *s)
{
    return s->rays[RAY_KIND_PRIMARY] + s->rays[RAY_KIND_SHADOW] +
           s->rays[RAY_KIND_REFLECTION] + s->rays[RAY_KIND_REFRACTION];
}

static double render(const ray_scene *s, const ray_camera *cam,
                     const ray_render_options *o, float *img, ray_stats *st)
{
    double t = now_seconds();
    check(ray_render(s, cam, o, img, st), "ray_render");
    return now_seconds() - t;
}

typedef ray_scene *(*scene_fn)(const char *arg, ray_camera *cam, int prune);

static ray_scene *make_whitted(const char *arg, ray_camera *cam, int prune)
{
    (void)arg;
    return whitted_scene(cam, prune, NULL);
}

static ray_scene *make_cornell(const char *arg, ray_camera *cam, int prune)
{
    (void)arg;
    return cornell_scene(cam, prune, NULL);
}

static ray_scene *make_mesh(const char *arg, ray_camera *cam, int prune)
{
    return mesh_scene(arg, cam, prune, NULL, NULL);
}

/* One row of the pruned-versus-naive table. */
static void pruning_row(const char *name, scene_fn make, const char *arg,
                        unsigned w, unsigned h)
{
    ray_camera cam;
    ray_scene *pruned = make(arg, &cam, 1),
              *naive = pruned != NULL ? make(arg, &cam, 0) : NULL;
    ray_render_options o;
    ray_stats sp, sn;
    float *ip = malloc(sizeof(float) * 3 * w * h),
          *in = malloc(sizeof(float) * 3 * w * h);
    double tp[9], tn[9];
    int k;

    if (pruned == NULL || naive == NULL || ip == NULL || in == NULL) {
        printf("| %s | (skipped) | | | | | |\n", name);
        ray_scene_free(pruned);
        ray_scene_free(naive);
        free(ip);
        free(in);
        return;
    }
    o = (ray_render_options){.width = w, .height = h};
    o.samples = 4;
    render(pruned, &cam, &o, ip, &sp);
    for (k = 0; k < reps; k++) {
        tp[k] = render(pruned, &cam, &o, ip, &sp);
        tn[k] = render(naive, &cam, &o, in, &sn);
    }
    printf("| %s | %llu | %llu | %.2f | %.3f | %.3f | %.2f | %.2g |\n", name,
           total_rays(&sp), total_rays(&sn),
           (double)total_rays(&sn) / (double)total_rays(&sp),
           median(tp, reps), median(tn, reps),
           median(tn, reps) / median(tp, reps), rmse(ip, in, (size_t)w * h));
    free(ip);
    free(in);
    ray_scene_free(pruned);
    ray_scene_free(naive);
}

/* Adaptive against uniform antialiasing on one scene. */
static void antialiasing_rows(const char *name, scene_fn make,
                              const char *arg, unsigned w, unsigned h)
{
    static const unsigned uniform[] = {1, 4, 9, 16};
    static const double thresholds[] = {0.1, 0.05, 0.02};
    ray_camera cam;
    ray_scene *s = make(arg, &cam, 1);
    ray_render_options o;
    ray_stats st;
    float *ref = malloc(sizeof(float) * 3 * w * h),
          *img = malloc(sizeof(float) * 3 * w * h);
    int k;

    if (s == NULL || ref == NULL || img == NULL) {
        printf("| %s | (skipped) | | | | |\n", name);
        ray_scene_free(s);
        free(ref);
        free(img);
        return;
    }
    o = (ray_render_options){.width = w, .height = h};
    o.samples = 256;
    render(s, &cam, &o, ref, &st);
    for (k = 0; k < 4; k++) {
        double t, e;
        o = (ray_render_options){.width = w, .height = h};
        o.samples = uniform[k];
        t = render(s, &cam, &o, img, &st);
        e = rmse(img, ref, (size_t)w * h);
        printf("| %s | uniform %u | %.2f | %.3f | %.4f | %.1f |\n", name,
               uniform[k], (double)st.rays[RAY_KIND_PRIMARY] / (w * h), t, e,
               psnr(e));
    }
    for (k = 0; k < 3; k++) {
        double t, e;
        o = (ray_render_options){.width = w, .height = h};
        o.adaptive_threshold = thresholds[k];
        o.adaptive_depth = 2;
        t = render(s, &cam, &o, img, &st);
        e = rmse(img, ref, (size_t)w * h);
        printf("| %s | adaptive %.2g, depth 2 | %.2f | %.3f | %.4f | %.1f |\n",
               name, thresholds[k], (double)st.rays[RAY_KIND_PRIMARY] / (w * h),
               t, e, psnr(e));
    }
    free(ref);
    free(img);
    ray_scene_free(s);
}

int main(int argc, char **argv)
{
    const char *dir = argc > 1 ? argv[1] : "data";
    int level = bench_level(), smoke = level == BENCH_SMOKE;
    unsigned w = smoke ? 16 : level ? 160 : 320, h = smoke ? 12 : level ? 120 : 240;
    unsigned aw = smoke ? 8 : level ? 80 : 160, ah = smoke ? 6 : level ? 60 : 120;
    char bunny[512];

    reps = level ? 1 : 3;
    snprintf(bunny, sizeof bunny, "%s/bunny.obj", dir);
    printf("## Simulating only what the scene needs\n\n");
    printf("Pruned (effect analysis, weight cut-off 1/256, no rays for zero "
           "weights or lights behind a surface) against the naive mode "
           "(every declared effect up to depth 8), %ux%u, 4 samples per "
           "pixel, median of %d; the last column is the RMSE between the "
           "two images (clamped to [0, 1]).\n\n", w, h, reps);
    printf("| scene | rays pruned | rays naive | naive / pruned | time pruned "
           "(s) | time naive (s) | time ratio | image RMSE |\n");
    printf("|---|---|---|---|---|---|---|---|\n");
    pruning_row("Whitted", make_whitted, NULL, w, h);
    pruning_row("Cornell box", make_cornell, NULL, w, h);
    pruning_row("bunny (3,674 triangles)", make_mesh, bunny, w, h);
    printf("\nAntialiasing, %ux%u: primary rays per pixel, render time and "
           "error against a 256-sample reference (RMSE, PSNR in dB).\n\n",
           aw, ah);
    printf("| scene | sampling | primary rays per pixel | time (s) | RMSE | "
           "PSNR |\n");
    printf("|---|---|---|---|---|---|\n");
    antialiasing_rows("Whitted", make_whitted, NULL, aw, ah);
    antialiasing_rows("Cornell box", make_cornell, NULL, aw, ah);
    antialiasing_rows("bunny", make_mesh, bunny, aw, ah);
    printf("\n");
    return 0;
}
