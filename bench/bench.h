/* SPDX-License-Identifier: MIT */
/*
** bench.h -- what the benchmarks share: camera and cosine rays, medians,
** PSNR, a counting allocator, a large grid mesh; and, from tests/testkit.h, a generator,
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

/* The sizes a benchmark runs at, from BENCH_QUICK: unset or empty, the
** full run of make bench (BENCH_FULL); "smoke", make check's smoke test
** (BENCH_SMOKE: bench/run.sh runs every program and every mode once, at
** the smallest sizes, a few rays or pixels, one repetition, so that none
** breaks unseen; its figures mean nothing); any other value, the quick
** run of make bench-smoke (BENCH_QUICK_RUN, under a minute). */
enum { BENCH_FULL, BENCH_QUICK_RUN, BENCH_SMOKE };
static inline int bench_level(void)
{
    const char *q = getenv("BENCH_QUICK");

    if (q == NULL || *q == '\0')
        return BENCH_FULL;
    return strcmp(q, "smoke") == 0 ? BENCH_SMOKE : BENCH_QUICK_RUN;
}

/* The ray through pixel (x, y) of a res x res image from a camera on +z
** at dist diagonals from "centre", looking down -z, 45 degrees: the mesh
** benchmarks' primary rays. */
static inline ray_ray bench_camera_ray(ray_vec3 centre, double diag,
                                       double dist, unsigned res, unsigned x,
                                       unsigned y)
{
    double half = tan(45.0 * 3.14159265358979323846 / 360.0);
    ray_ray r;

    r.org = ray_vec3_make(centre.x, centre.y, centre.z + dist * diag);
    r.dir = ray_vec3_make((2 * (x + 0.5) / res - 1) * half,
                          (1 - 2 * (y + 0.5) / res) * half, -1);
    r.tmin = 0;
    r.tmax = HUGE_VAL;
    return r;
}

/* A direction from the cosine distribution about the unit normal n, for
** uniform u1, u2 in [0, 1) (Malley's method: a uniform disk sample lifted
** to the hemisphere). */
static inline ray_vec3 bench_cosine_dir(ray_vec3 n, double u1, double u2)
{
    ray_vec3 t1, t2;
    double r, phi;

    t1 = fabs(n.x) > 0.5 ? ray_vec3_make(n.y, -n.x, 0)
                         : ray_vec3_make(0, n.z, -n.y);
    r = sqrt(t1.x * t1.x + t1.y * t1.y + t1.z * t1.z);
    t1 = ray_vec3_make(t1.x / r, t1.y / r, t1.z / r);
    t2 = ray_vec3_make(n.y * t1.z - n.z * t1.y, n.z * t1.x - n.x * t1.z,
                       n.x * t1.y - n.y * t1.x);
    r = sqrt(u1);
    phi = 2 * 3.14159265358979323846 * u2;
    return ray_vec3_make(
        t1.x * r * cos(phi) + t2.x * r * sin(phi) + n.x * sqrt(1 - u1),
        t1.y * r * cos(phi) + t2.y * r * sin(phi) + n.y * sqrt(1 - u1),
        t1.z * r * cos(phi) + t2.z * r * sin(phi) + n.z * sqrt(1 - u1));
}

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
