/* SPDX-License-Identifier: MIT */
/*
** caustics.c -- what caustics cost (issue 19): the caustics scene
** (examples/scenes.h) rendered with 10k to 1M photons, the error of its
** caustics against a reference of 4M photons, and the time of the
** photon pass, of the gather and of the whole render.
**
** The caustic image: a render with N photons minus the same render with
** none (same pixel seed, so the direct light's noise cancels and only the
** photons' part is left); the reference is the same difference at 4M
** photons with another seed (an independent photon set: the N-photon
** sets are not its prefixes).  RMSE over all pixels, and relative to the
** reference caustic's RMS.  Times: the photon pass alone
** (ray_photon_map_build, the same pass ray_render runs), the render with
** photons and the render without (each the median of REPS interleaved
** rounds after a warm-up; 2 threads); the gather is the render with
** photons minus the pass and the render without.  Writes caustics.dat
** (time, RMSE) into the directory argv[1] for bench/run.sh's plot.
** BENCH_QUICK=1: 1M photons for the reference, counts to 300k, 1 round.
*/
#include "bench.h"
#include "scenes.h"

#define REPS 3
#define WIDTH 320
#define HEIGHT 240
#define THREADS 2

static double timed_render(const ray_scene *s, const ray_camera *cam,
                           const ray_render_options *o, float *img,
                           ray_stats *st)
{
    double t = now_seconds();
    check(ray_render(s, cam, o, img, st), "ray_render");
    return now_seconds() - t;
}

static double timed_pass(const ray_scene *s, const ray_render_options *o)
{
    ray_photon_map *map;
    double t = now_seconds();
    check(ray_photon_map_build(s, o, &map), "ray_photon_map_build");
    t = now_seconds() - t;
    ray_photon_map_free(map);
    return t;
}

/* out = a - b, pixel by pixel: the caustic part of a render. */
static void difference(const float *a, const float *b, float *out, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++)
        out[i] = a[i] - b[i];
}

/* The RMSE of two caustic images over their n floats, unclamped (testkit's
** rmse clamps to [0, 1], the displayable range; a caustic's peak is
** brighter). */
static double caustic_rmse(const float *a, const float *b, size_t n)
{
    double sum = 0;
    size_t i;
    for (i = 0; i < n; i++) {
        double d = (double)a[i] - (double)b[i];
        sum += d * d;
    }
    return sqrt(sum / (double)n);
}

int main(int argc, char **argv)
{
    static const unsigned long long counts[] = {10000, 30000, 100000,
                                                300000, 1000000};
    const char *plots = argc > 1 ? argv[1] : ".";
    int level = bench_level(), smoke = level == BENCH_SMOKE;
    int reps = level ? 1 : REPS, n_counts = smoke ? 2 : level ? 4 : 5, i, k;
    unsigned long long ref_n = smoke ? 20000 : level ? 1000000 : 4000000;
    unsigned width = smoke ? 16 : WIDTH, height = smoke ? 12 : HEIGHT;
    size_t n = 3 * (size_t)width * height;
    float *ref = malloc(n * sizeof *ref), *img = malloc(n * sizeof *img);
    float *base = malloc(n * sizeof *base), *c = malloc(n * sizeof *c);
    double ref_rms, t_ref;
    char path[4096];
    FILE *dat;
    ray_render_options o;
    ray_camera cam;
    ray_scene *scene = caustics_scene(&cam);
    ray_stats st;

    if (ref == NULL || img == NULL || base == NULL || c == NULL) {
        fprintf(stderr, "caustics: out of memory\n");
        return 1;
    }
    snprintf(path, sizeof path, "%s/caustics.dat", plots);
    dat = fopen(path, "w");
    if (dat == NULL) {
        perror(path);
        return 1;
    }
    o = (ray_render_options){.width = width, .height = height};
    o.threads = THREADS;
    /* The reference: its own seed, its render without photons subtracted. */
    o.seed = 4242;
    o.photons = ref_n;
    t_ref = timed_render(scene, &cam, &o, img, &st);
    o.photons = 0;
    timed_render(scene, &cam, &o, base, NULL);
    difference(img, base, ref, n);
    {
        double sum = 0;
        size_t j;
        for (j = 0; j < n; j++)
            sum += (double)ref[j] * (double)ref[j];
        ref_rms = sqrt(sum / (double)n);
    }
    printf("## Caustics: error against photon count\n\n");
    printf("The caustics scene (`examples/caustics.c`: a glass sphere and a "
           "ring of brass mirrors\non a diffuse floor under a small rect "
           "light), %ux%u, 1 sample per pixel, %u threads,\nautomatic "
           "radius. Error: RMSE of the caustic part (the render minus the "
           "same\nrender without photons) against a reference of %llu "
           "photons (%.2f s, %llu stored),\nand relative to the reference "
           "caustic's RMS (%.4g). Times: medians of %d interleaved\n"
           "rounds; pass = `ray_photon_map_build`, gather = the render "
           "with photons minus the\npass and the render without.\n\n",
           width, height, THREADS, ref_n, t_ref, st.photons_stored, ref_rms,
           reps);
    printf("| photons | stored | pass (s) | gather (s) | render (s) | "
           "without (s) | RMSE | relative |\n");
    printf("|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    o.seed = 1;
    for (k = 0; k < n_counts; k++) {
        double tp[REPS], tw[REPS], t0[REPS], mp, mw, m0, err;
        o.photons = counts[k];
        timed_render(scene, &cam, &o, img, NULL);     /* warm-up */
        for (i = 0; i < reps; i++) {
            tp[i] = timed_pass(scene, &o);
            tw[i] = timed_render(scene, &cam, &o, img, &st);
            o.photons = 0;
            t0[i] = timed_render(scene, &cam, &o, base, NULL);
            o.photons = counts[k];
        }
        mp = median(tp, reps);
        mw = median(tw, reps);
        m0 = median(t0, reps);
        difference(img, base, c, n);
        err = caustic_rmse(c, ref, n);
        printf("| %llu | %llu | %.3f | %.3f | %.3f | %.3f | %.4g | %.3f |\n",
               counts[k], st.photons_stored, mp, fmax(0.0, mw - mp - m0), mw,
               m0, err, err / ref_rms);
        fprintf(dat, "%g %g %llu\n", mw - m0, err, counts[k]);
    }
    printf("\n");
    fclose(dat);
    ray_scene_free(scene);
    free(ref);
    free(img);
    free(base);
    free(c);
    return 0;
}
