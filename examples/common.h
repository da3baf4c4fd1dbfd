/* SPDX-License-Identifier: MIT */
/*
** common.h -- small helpers shared by the examples: vectors, colours, a
** progress bar and the statistics printout.  Not part of the library.
*/
#ifndef EXAMPLES_COMMON_H
#define EXAMPLES_COMMON_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <ray.h>

static inline ray_vec3 vec(double x, double y, double z)
{
    ray_vec3 v;
    v.x = x;
    v.y = y;
    v.z = z;
    return v;
}

static inline ray_rgb rgb(double r, double g, double b)
{
    ray_rgb c;
    c.r = r;
    c.g = g;
    c.b = b;
    return c;
}

/* A progress bar on stderr, redrawn when the percentage changes; never
** cancels.  The renderer calls it one call at a time. */
static inline int progress_bar(void *ud, unsigned done, unsigned total)
{
    unsigned width = 40, filled = done * width / total, i;
    unsigned percent = (unsigned)((unsigned long long)done * 100 / total);

    (void)ud;
    if (done != total && percent ==
                         (unsigned)((unsigned long long)(done - 1) * 100 / total))
        return 0;
    fputs("\r[", stderr);
    for (i = 0; i < width; i++)
        fputc(i < filled ? '#' : ' ', stderr);
    fprintf(stderr, "] %3u%%", percent);
    if (done == total)
        fputc('\n', stderr);
    return 0;
}

static inline void print_stats(const char *name, const ray_stats *s,
                               double seconds)
{
    unsigned long long total = s->rays[RAY_KIND_PRIMARY] +
                               s->rays[RAY_KIND_SHADOW] +
                               s->rays[RAY_KIND_REFLECTION] +
                               s->rays[RAY_KIND_REFRACTION];
    unsigned long long sum = 0;
    int k, lo = -1, hi = -1;

    printf("%s: rays primary %llu, shadow %llu, reflection %llu, "
           "refraction %llu (total %llu)\n", name,
           s->rays[RAY_KIND_PRIMARY], s->rays[RAY_KIND_SHADOW],
           s->rays[RAY_KIND_REFLECTION], s->rays[RAY_KIND_REFRACTION], total);
    printf("%s: intersection tests %llu (spheres %llu, planes %llu, "
           "triangles %llu, polygons %llu, tori %llu, implicit %llu, "
           "parametric %llu)\n", name, s->tests,
           s->tests_by_kind[RAY_PRIM_SPHERE], s->tests_by_kind[RAY_PRIM_PLANE],
           s->tests_by_kind[RAY_PRIM_TRIANGLE],
           s->tests_by_kind[RAY_PRIM_POLYGON], s->tests_by_kind[RAY_PRIM_TORUS],
           s->tests_by_kind[RAY_PRIM_IMPLICIT],
           s->tests_by_kind[RAY_PRIM_PARAMETRIC]);
    if (s->root_failures > 0)
        printf("%s: %llu implicit or parametric tests ran out of iterations "
               "(taken as misses)\n", name, s->root_failures);
    printf("%s: deepest level %u, rays cut by depth %llu, weight %llu, "
           "fan-out %llu\n", name, s->max_depth, s->cut_depth, s->cut_weight,
           s->cut_fanout);
    for (k = 0; k < RAY_HIST_BINS; k++) {
        if (s->samples_hist[k] == 0)
            continue;
        if (lo < 0)
            lo = k;
        hi = k;
        sum += s->samples_hist[k] * (unsigned long long)k;
    }
    if (s->pixels > 0)
        printf("%s: samples per pixel: min %d, mean %.2f, max %d%s\n", name,
               lo, (double)sum / (double)s->pixels, hi,
               hi == RAY_HIST_BINS - 1 ? " or more" : "");
    if (seconds > 0)
        printf("%s: %.3f s, %.2f Mrays/s\n", name, seconds,
               (double)total / seconds / 1e6);
}

/* A Blinn-Phong parameter block; the fields not named (the texture) are
** zero.  Built field by field, so fields added to the struct later stay
** zero. */
static inline ray_phong_params phong_params(ray_rgb diffuse, ray_rgb specular,
                                            double shininess, ray_rgb reflect)
{
    ray_phong_params p;

    memset(&p, 0, sizeof p);
    p.diffuse = diffuse;
    p.specular = specular;
    p.shininess = shininess;
    p.blinn = 1;
    p.reflect = reflect;
    return p;
}

/* A sky for ray_scene_set_background_fn: base + delta * k, k going from 0
** for rays straight down to 1 straight up; ud is a sky_colors. */
typedef struct sky_colors {
    ray_rgb base, delta;
} sky_colors;

static inline void sky_gradient(void *ud, const ray_ray *r, ray_rgb *out)
{
    const sky_colors *c = ud;
    double len = r->dir.x * r->dir.x + r->dir.y * r->dir.y +
                 r->dir.z * r->dir.z;
    double up = len > 0 ? r->dir.y / sqrt(len) : 0;
    double k = 0.5 * (up + 1);

    *out = rgb(c->base.r + c->delta.r * k, c->base.g + c->delta.g * k,
               c->base.b + c->delta.b * k);
}

/* Die with a message naming the failed call. */
static inline void check(int rc, const char *what)
{
    if (rc != RAY_OK) {
        fprintf(stderr, "%s: %s\n", what, ray_strerror(rc));
        exit(1);
    }
}

static inline double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/*
** The examples' command line, NAME [out.png [width height [samples
** [threads]]]]: render "scene" with a progress bar, write the PNG, print
** the statistics.  Returns the process exit status.
*/
static inline int render_to_png(const char *name, const ray_scene *scene,
                                const ray_camera *cam, int argc, char **argv,
                                unsigned width, unsigned height)
{
    char path[256];
    ray_render_options opt;
    ray_stats stats;
    float *image;
    double t;

    snprintf(path, sizeof path, "%s.png", name);
    if (argc > 1)
        snprintf(path, sizeof path, "%s", argv[1]);
    if (argc > 3) {
        width = (unsigned)atoi(argv[2]);
        height = (unsigned)atoi(argv[3]);
    }
    ray_render_options_init(&opt, width, height);
    opt.samples = argc > 4 ? (unsigned)atoi(argv[4]) : 4;
    opt.threads = argc > 5 ? (unsigned)atoi(argv[5]) : 0;
    opt.progress = progress_bar;
    /* RAY_ADAPTIVE=threshold[,depth] turns adaptive antialiasing on. */
    if (getenv("RAY_ADAPTIVE") != NULL) {
        char *end;
        opt.adaptive_threshold = strtod(getenv("RAY_ADAPTIVE"), &end);
        if (*end == ',')
            opt.adaptive_depth = (unsigned)atoi(end + 1);
    }
    if (width == 0 || height == 0 || opt.samples == 0) {
        fprintf(stderr, "usage: %s [out.png [width height [samples "
                        "[threads]]]]\n", name);
        return 2;
    }
    image = malloc(sizeof(float) * 3 * width * height);
    if (image == NULL) {
        fprintf(stderr, "%s: out of memory\n", name);
        return 1;
    }
    t = now_seconds();
    check(ray_render(scene, cam, &opt, image, &stats), "ray_render");
    t = now_seconds() - t;
    check(ray_write_png(path, image, width, height, 8), path);
    printf("%s: wrote %s (%ux%u, %u samples per pixel)\n", name, path,
           width, height, opt.samples);
    print_stats(name, &stats, t);
    free(image);
    return 0;
}

#endif
