/* SPDX-License-Identifier: MIT */
/*
** threads.c -- the Whitted scene's render time at 1 thread and at N
** threads (default 2; "threads N" or BENCH_THREADS=N for more), the
** speed-up as a ratio measured in the same run, and rays per second.
**
** Method: one warm-up render, then REPS rounds, each rendering once with 1
** thread and once with N (interleaved, so a noisy neighbour hits both),
** and the median of each.  No assertion: a benchmark reports, tests test.
*/
#include "bench.h"
#include "scenes.h"

#define REPS 5

static double timed_render(const ray_scene *s, const ray_camera *cam,
                           ray_render_options *opt, float *img,
                           ray_stats *st)
{
    double t = now_seconds();
    check(ray_render(s, cam, opt, img, st), "ray_render");
    return now_seconds() - t;
}

int main(int argc, char **argv)
{
    const char *env = getenv("BENCH_THREADS");
    unsigned n = argc > 1 ? (unsigned)atoi(argv[1])
                          : env != NULL ? (unsigned)atoi(env) : 2;
    int level = bench_level(), reps = level ? 3 : REPS, i;
    unsigned width = level == BENCH_SMOKE ? 16 : 640,
             height = level == BENCH_SMOKE ? 12 : 480;
    double t1[REPS], tn[REPS], m1, mn;
    unsigned long long rays;
    ray_render_options opt;
    ray_camera cam;
    ray_scene *scene = whitted_scene(&cam, 1, NULL);
    ray_stats st;
    float *img;

    if (level == BENCH_SMOKE)
        reps = 1;
    img = malloc(sizeof(float) * 3 * width * height);
    if (img == NULL || n == 0)
        return 1;
    opt = (ray_render_options){.width = width, .height = height};
    opt.samples = 4;
    opt.threads = n;
    timed_render(scene, &cam, &opt, img, &st);            /* warm-up */
    for (i = 0; i < reps; i++) {
        opt.threads = 1;
        t1[i] = timed_render(scene, &cam, &opt, img, &st);
        opt.threads = n;
        tn[i] = timed_render(scene, &cam, &opt, img, &st);
    }
    m1 = median(t1, reps);
    mn = median(tn, reps);
    rays = st.rays[RAY_KIND_PRIMARY] + st.rays[RAY_KIND_SHADOW] +
           st.rays[RAY_KIND_REFLECTION] + st.rays[RAY_KIND_REFRACTION];
    printf("## Whitted scene, %ux%u, 4 samples per pixel (%llu rays), "
           "median of %d\n\n", width, height, rays, reps);
    printf("| threads | time (s) | Mrays/s | speed-up vs 1 thread |\n");
    printf("|---|---|---|---|\n");
    printf("| 1 | %.3f | %.2f | 1.00 |\n", m1, (double)rays / m1 / 1e6);
    printf("| %u | %.3f | %.2f | %.2f |\n\n", n, mn, (double)rays / mn / 1e6,
           m1 / mn);
    free(img);
    ray_scene_free(scene);
    return 0;
}
