/*
** common.h -- small helpers shared by the examples: vectors, colours, a
** progress bar and the statistics printout.  Not part of the library.
*/
#ifndef EXAMPLES_COMMON_H
#define EXAMPLES_COMMON_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

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

static inline void print_stats(const char *name, const ray_stats *s, double seconds)
{
    unsigned long long total = s->rays[RAY_KIND_PRIMARY] +
                               s->rays[RAY_KIND_SHADOW] +
                               s->rays[RAY_KIND_REFLECTION] +
                               s->rays[RAY_KIND_REFRACTION];

    printf("%s: rays primary %llu, shadow %llu, reflection %llu, "
           "refraction %llu (total %llu)\n", name,
           s->rays[RAY_KIND_PRIMARY], s->rays[RAY_KIND_SHADOW],
           s->rays[RAY_KIND_REFLECTION], s->rays[RAY_KIND_REFRACTION], total);
    printf("%s: intersection tests %llu, deepest level %u, cut by depth "
           "%llu, weight %llu, fan-out %llu\n", name, s->tests, s->max_depth,
           s->cut_depth, s->cut_weight, s->cut_fanout);
    if (seconds > 0)
        printf("%s: %.3f s, %.2f Mrays/s\n", name, seconds,
               (double)total / seconds / 1e6);
}

/* Die with a message naming the failed call. */
static inline void check(int rc, const char *what)
{
    if (rc != RAY_OK) {
        fprintf(stderr, "%s: %s\n", what, ray_strerror(rc));
        exit(1);
    }
}

#endif
