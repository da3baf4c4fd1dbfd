/* SPDX-License-Identifier: MIT */
/*
** bench.h -- what the benchmarks share: medians, PSNR, a counting
** allocator, a large grid mesh; and, from tests/testkit.h, a generator,
** image error (rmse) and a scene whose material shades nothing.
** Header-only; not part of the library.
*/
#ifndef BENCH_BENCH_H
#define BENCH_BENCH_H

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ray.h"
#include "testkit.h"

static int bench_cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The median of v[0..n-1] (sorts v). */
static inline double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, bench_cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* PSNR in dB for a peak of 1 (99 for identical images). */
static inline double psnr(double e)
{
    return e > 0 ? -20.0 * log10(e) : 99.0;
}

/* An allocator for ray_scene_new that counts the bytes in use and their
** peak (bytes per triangle, leak checks). */
typedef struct counting {
    long long now, peak;
} counting;

static inline void *counting_alloc(void *ud, void *ptr, size_t osize,
                                   size_t nsize)
{
    counting *c = ud;
    void *p;

    if (nsize == 0) {
        c->now -= (long long)osize;
        free(ptr);
        return NULL;
    }
    p = realloc(ptr, nsize);
    if (p != NULL) {
        c->now += (long long)nsize - (long long)osize;
        if (c->now > c->peak)
            c->peak = c->now;
    }
    return p;
}

/*
** A gently waving n x n grid of unit squares near the z = 0 plane, two
** triangles each: (n+1)^2 vertices, 2 n^2 triangles (n = 724 gives
** 1,048,352, the million-triangle memory figure).  Fills *mesh, whose
** arrays *v and *idx the caller frees; -1 when out of memory.
*/
static inline int grid_mesh(unsigned n, ray_mesh *mesh, ray_vec3 **v,
                            unsigned **idx)
{
    size_t i, j, side = (size_t)n + 1;

    *v = malloc(side * side * sizeof **v);
    *idx = malloc((size_t)6 * n * n * sizeof **idx);
    if (*v == NULL || *idx == NULL) {
        free(*v);
        free(*idx);
        return -1;
    }
    for (j = 0; j < side; j++)
        for (i = 0; i < side; i++) {
            ray_vec3 *p = *v + j * side + i;
            p->x = (double)i;
            p->y = (double)j;
            p->z = 0.01 * sin(0.1 * (double)(i + j));
        }
    for (j = 0; j < n; j++)
        for (i = 0; i < n; i++) {
            unsigned a = (unsigned)(j * side + i), *t = *idx + 6 * (j * n + i);
            t[0] = a; t[1] = a + 1; t[2] = a + n + 2;
            t[3] = a; t[4] = a + n + 2; t[5] = a + n + 1;
        }
    memset(mesh, 0, sizeof *mesh);
    mesh->vertices = *v;
    mesh->vertex_count = side * side;
    mesh->indices = *idx;
    mesh->triangle_count = 2 * (size_t)n * n;
    return 0;
}

#endif
