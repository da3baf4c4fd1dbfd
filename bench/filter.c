/* SPDX-License-Identifier: MIT */
/*
** filter.c -- what exactness costs, triangle by triangle (issue 27): the
** same rays through the same tree in three modes -- the exact double test
** alone (libray before the filter), the float filter in front of it (the
** default: the same answers, bit for bit), and the filter's float test
** taken as final (a float tracer: what the exact test buys) -- on the
** Stanford bunny at three sizes and on a closed icosphere, one thread:
** Mrays/s, the answers that differ from the exact test's, bytes per
** triangle, and the leaks of each mode through the icosphere's shared
** vertices and edges (rays from its centre at every vertex and every edge
** midpoint: a closed mesh, so every one must hit).  Prints Markdown;
** asserts nothing.
**
**     filter DATA_DIR          (bunny.obj, bunny-2.obj, bunny-4.obj)
**     filter --profile MESH primary|incoherent|refit|build [THREADS]
**                              (one row's rays alone, 20 times, or 200
**                              refits, or 20 cold builds of a fresh scene,
**                              the commits on THREADS build threads,
**                              default 1: make profile; issue 36's
**                              before-and-after timings)
**
** Method: medians of REPS runs, the three modes in turn within each run
** so that a noisy neighbour slows all three; each ratio is the median of
** the runs' own ratios.  BENCH_QUICK=1: fewer rays and runs, the 940k
** bunny skipped.
*/
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench.h"
#include "common.h"
#include "hardcases.h"
#include "obj.h"
#include "scene/scene.h"

static int reps = 5;

static const char *const mode_name[3] = {"exact alone",
                                         "filter + exact (default)",
                                         "filter alone (float)"};
static const int modes[3] = {RAY__TRI_EXACT, RAY__TRI_FILTERED,
                             RAY__TRI_FLOAT};

/* n rays through s in mode m: seconds, and each ray's answer. */
static double trace(ray_scene *s, int m, const ray_ray *r, size_t n,
                    ray_hit *h, int *res)
{
    double t = now_seconds();
    size_t i;

    ray__scene_set_tri_mode(s, m);
    for (i = 0; i < n; i++)
        res[i] = ray_intersect(s, &r[i], &h[i], NULL);
    return now_seconds() - t;
}

/* Answers of b unlike a's: hit or miss, or the triangle hit ("same
** t" too: t bit for bit, which the float test's t never is). */
static size_t unlike(const int *ra, const ray_hit *ha, const int *rb,
                     const ray_hit *hb, size_t n, int same_t)
{
    size_t i, d = 0;

    for (i = 0; i < n; i++)
        d += ra[i] != rb[i] ||
             (ra[i] > 0 && ((same_t && ha[i].t != hb[i].t) ||
                            ha[i].geom_id != hb[i].geom_id ||
                            ha[i].prim_id != hb[i].prim_id));
    return d;
}

/* One row per ray set: the three modes' Mrays/s and the ratios. */
static void row(const char *mesh, size_t tris, double bytes,
                const char *what, ray_scene *s, const ray_ray *r, size_t n)
{
    ray_hit *h[3];
    int *res[3], k, m;
    double t[3][9], fe[9], ff[9];

    for (m = 0; m < 3; m++) {
        h[m] = calloc(n, sizeof *h[m]);
        res[m] = calloc(n, sizeof *res[m]);
        if (h[m] == NULL || res[m] == NULL) {
            printf("(out of memory)\n");
            exit(1);
        }
        trace(s, modes[m], r, n, h[m], res[m]);          /* warm-up */
    }
    for (k = 0; k < reps; k++) {
        for (m = 0; m < 3; m++)
            t[m][k] = trace(s, modes[m], r, n, h[m], res[m]);
        fe[k] = t[0][k] / t[1][k];
        ff[k] = t[1][k] / t[2][k];
    }
    printf("| %s | %zu | %.1f | %s | %.2f | %.2f | %.2f | %.2f | %.2f | "
           "%zu | %zu |\n", mesh, tris, bytes, what,
           (double)n / median(t[0], reps) / 1e6,
           (double)n / median(t[1], reps) / 1e6,
           (double)n / median(t[2], reps) / 1e6, median(fe, reps),
           median(ff, reps), unlike(res[0], h[0], res[1], h[1], n, 1),
           unlike(res[0], h[0], res[2], h[2], n, 0));
    for (m = 0; m < 3; m++) {
        free(h[m]);
        free(res[m]);
    }
    ray__scene_set_tri_mode(s, RAY__TRI_FILTERED);
}

/* Camera rays at 1.0 diagonal, and cosine rays from their hits. */
static ray_ray *rays_of(ray_scene *s, ray_vec3 c, double diag,
                        unsigned res, size_t *n_primary, size_t *n_all)
{
    size_t n = (size_t)res * res, k = 0, i;
    ray_ray *r = malloc(2 * n * sizeof *r);
    rng g = {7};
    unsigned x, y;

    if (r == NULL)
        return NULL;
    for (y = 0; y < res; y++)
        for (x = 0; x < res; x++)
            r[k++] = bench_camera_ray(c, diag, 1.0, res, x, y);
    *n_primary = k;
    for (i = 0; i < *n_primary; i++) {
        ray_hit h;
        if (ray_intersect(s, &r[i], &h, NULL) > 0) {
            ray_vec3 up = h.n;
            if (up.x * r[i].dir.x + up.y * r[i].dir.y + up.z * r[i].dir.z > 0)
                up = ray_vec3_make(-up.x, -up.y, -up.z);
            if (ray_spawn(&h, bench_cosine_dir(up, rng_unit(&g),
                                               rng_unit(&g)), &r[k]) ==
                RAY_OK)
                k++;
        }
    }
    *n_all = k;
    return r;
}

/* The mesh at path in a scene of its own (nop_scene_new, counting its
** bytes into *cnt, which must outlive the scene: its allocator writes
** there until ray_scene_free, and into *bytes per triangle), with the
** centre and the diagonal of its box; 0 where it cannot be read (a row
** says why). */
static int load(const char *path, obj_mesh *obj, ray_scene **s,
                counting *cnt, ray_vec3 *c, double *diag, double *bytes)
{
    ray_mesh mesh;
    ray_vec3 lo, hi;
    char err[1200];
    size_t i;

    if (obj_load(path, obj, err, sizeof err) != 0) {
        printf("| %s | (skipped: %s) |\n", path, err);
        return 0;
    }
    mesh = obj_as_ray_mesh(obj);
    cnt->now = cnt->peak = 0;
    if (nop_scene_new(s, counting_alloc, cnt) != RAY_OK ||
        ray_scene_add_mesh(*s, &mesh, 0, NULL) != RAY_OK ||
        ray_scene_commit(*s) != RAY_OK) {
        printf("| %s | (scene failed) |\n", path);
        exit(1);
    }
    *bytes = (double)cnt->now / (double)obj->triangle_count;
    lo = hi = obj->vertices[0];
    for (i = 1; i < obj->vertex_count; i++) {
        ray_vec3 v = obj->vertices[i];
        lo = ray_vec3_make(v.x < lo.x ? v.x : lo.x, v.y < lo.y ? v.y : lo.y,
                           v.z < lo.z ? v.z : lo.z);
        hi = ray_vec3_make(v.x > hi.x ? v.x : hi.x, v.y > hi.y ? v.y : hi.y,
                           v.z > hi.z ? v.z : hi.z);
    }
    *c = ray_vec3_make((lo.x + hi.x) / 2, (lo.y + hi.y) / 2,
                       (lo.z + hi.z) / 2);
    *diag = sqrt((hi.x - lo.x) * (hi.x - lo.x) +
                 (hi.y - lo.y) * (hi.y - lo.y) +
                 (hi.z - lo.z) * (hi.z - lo.z));
    return 1;
}

static void bench_bunny(const char *path, unsigned res)
{
    obj_mesh obj;
    ray_scene *s;
    counting cnt;
    ray_ray *r;
    ray_vec3 c;
    size_t np, na;
    double diag, bytes;

    if (!load(path, &obj, &s, &cnt, &c, &diag, &bytes))
        return;
    r = rays_of(s, c, diag, res, &np, &na);
    if (r == NULL)
        exit(1);
    row(path, obj.triangle_count, bytes, "primary, 1.0 diagonal", s, r, np);
    row(path, obj.triangle_count, bytes, "incoherent (cosine)", s, r + np,
        na - np);
    free(r);
    ray_scene_free(s);
    obj_free(&obj);
}

/*
** A refit, "times" times over: every vertex of the mesh (geometry 0 of s)
** moved up by a thousandth of the diagonal, ray_scene_update_mesh, and
** the commit that refits the tree.  Prints the fastest in ms.
*/
static void profile_refit(ray_scene *s, obj_mesh *obj, double diag,
                          int times, unsigned threads)
{
    ray_mesh mesh = obj_as_ray_mesh(obj);
    double best = HUGE_VAL;
    size_t i;
    int k;

    if (ray_scene_set_build_threads(s, threads) != RAY_OK)
        exit(1);
    for (k = 0; k < times; k++) {
        double t;
        for (i = 0; i < obj->vertex_count; i++)
            obj->vertices[i].y += 1e-3 * diag;
        t = now_seconds();
        if (ray_scene_update_mesh(s, 0, &mesh) != RAY_OK ||
            ray_scene_commit(s) != RAY_OK)
            exit(1);
        t = now_seconds() - t;
        best = t < best ? t : best;
    }
    printf("profile: %zu triangles, %d refits on %u threads: %.2f ms "
           "(fastest)\n", obj->triangle_count, times, threads, best * 1e3);
}

/*
** A cold build, "times" times over: a fresh scene, the mesh added, the
** commit on "threads" build threads, the scene freed.  Prints the
** fastest in ms.
*/
static void profile_build(const obj_mesh *obj, int times, unsigned threads)
{
    ray_mesh mesh = obj_as_ray_mesh(obj);
    double best = HUGE_VAL;
    int k;

    for (k = 0; k < times; k++) {
        ray_scene *s;
        double t = now_seconds();
        if (nop_scene_new(&s, NULL, NULL) != RAY_OK ||
            ray_scene_set_build_threads(s, threads) != RAY_OK ||
            ray_scene_add_mesh(s, &mesh, 0, NULL) != RAY_OK ||
            ray_scene_commit(s) != RAY_OK)
            exit(1);
        ray_scene_free(s);
        t = now_seconds() - t;
        best = t < best ? t : best;
    }
    printf("profile: %zu triangles, %d cold builds on %u threads: %.2f ms "
           "(fastest)\n", obj->triangle_count, times, threads, best * 1e3);
}

/*
** The rays of one row alone, in the default mode, "times" times over (or
** a refit, ten times as many): a process for a profiler to watch (make
** profile), which spends its time on nothing else.  Prints the Mrays/s of
** the fastest pass.
*/
static int profile(const char *path, const char *kind, int times,
                   unsigned threads)
{
    obj_mesh obj;
    ray_scene *s;
    counting cnt;
    ray_ray *r;
    ray_hit *h;
    ray_vec3 c;
    size_t np, na, n, i;
    double diag, bytes, best = HUGE_VAL;
    int incoherent = strcmp(kind, "incoherent") == 0, k;
    int refit = strcmp(kind, "refit") == 0;
    int build = strcmp(kind, "build") == 0;

    if (!incoherent && !refit && !build && strcmp(kind, "primary") != 0)
        return 2;
    if (!load(path, &obj, &s, &cnt, &c, &diag, &bytes))
        return 1;
    if (build) {
        ray_scene_free(s);
        profile_build(&obj, times, threads);
        obj_free(&obj);
        return 0;
    }
    if (refit) {
        profile_refit(s, &obj, diag, 10 * times, threads);
        ray_scene_free(s);
        obj_free(&obj);
        return 0;
    }
    r = rays_of(s, c, diag, 512, &np, &na);
    n = incoherent ? na - np : np;
    h = malloc(n * sizeof *h);
    if (r == NULL || h == NULL)
        exit(1);
    for (k = 0; k < times; k++) {
        const ray_ray *q = incoherent ? r + np : r;
        double t = now_seconds();
        for (i = 0; i < n; i++)
            (void)ray_intersect(s, &q[i], &h[i], NULL);
        t = now_seconds() - t;
        best = t < best ? t : best;
    }
    printf("profile: %s, %zu %s rays, %d passes: %.2f Mrays/s (fastest)\n",
           path, n, kind, times, (double)n / best / 1e6);
    free(h);
    free(r);
    ray_scene_free(s);
    obj_free(&obj);
    return 0;
}

/* The icosphere's leaks, by mode: rays from its centre at each vertex and
** each edge midpoint (its edges, each counted from both triangles). */
static void bench_leaks(int level)
{
    hc_mesh m = hc_icosphere(ray_vec3_make(0, 0, 0), level);
    ray_mesh rm = hc_ray_mesh(&m);
    long leaks[3][2] = {{0, 0}, {0, 0}, {0, 0}}, rays[2] = {0, 0};
    ray_scene *s;
    size_t i, e;
    int md;

    if (ray_scene_new(&s, NULL, NULL) != RAY_OK ||
        ray_scene_add_mesh(s, &rm, RAY_NO_MATERIAL, NULL) != RAY_OK ||
        ray_scene_commit(s) != RAY_OK)
        exit(1);
    for (md = 0; md < 3; md++) {
        ray__scene_set_tri_mode(s, modes[md]);
        for (i = 0; i < m.nv; i++) {
            ray_ray r;
            ray_hit h;
            r.org = ray_vec3_make(0, 0, 0);
            r.dir = m.v[i];
            r.tmin = 0;
            r.tmax = HUGE_VAL;
            leaks[md][0] += ray_intersect(s, &r, &h, NULL) <= 0;
            rays[0] += md == 0;
        }
        for (i = 0; i < m.nt; i++)
            for (e = 0; e < 3; e++) {
                ray_vec3 a = m.v[m.idx[3 * i + e]],
                         b = m.v[m.idx[3 * i + (e + 1) % 3]];
                ray_ray r;
                ray_hit h;
                r.org = ray_vec3_make(0, 0, 0);
                r.dir = ray_vec3_make((a.x + b.x) / 2, (a.y + b.y) / 2,
                                      (a.z + b.z) / 2);
                r.tmin = 0;
                r.tmax = HUGE_VAL;
                leaks[md][1] += ray_intersect(s, &r, &h, NULL) <= 0;
                rays[1] += md == 0;
            }
    }
    printf("\nLeaks through a closed icosphere (%zu triangles, %zu vertices, "
           "radius 2 at the origin), rays from its centre: at its %ld "
           "vertices / at the midpoints of its edges, %ld (each edge from "
           "both its triangles):\n\n", m.nt, m.nv, rays[0], rays[1]);
    printf("| mode | leaks at vertices | leaks at edge midpoints |\n");
    printf("|---|---|---|\n");
    for (md = 0; md < 3; md++)
        printf("| %s | %ld | %ld |\n", mode_name[md], leaks[md][0],
               leaks[md][1]);
    ray_scene_free(s);
    hc_mesh_free(&m);
}

int main(int argc, char **argv)
{
    const char *dir = argc > 1 ? argv[1] : "data";
    static const char *const names[3] = {"bunny.obj", "bunny-2.obj",
                                         "bunny-4.obj"};
    int level = bench_level(), quick = level != BENCH_FULL;
    int smoke = level == BENCH_SMOKE;
    size_t k;
    char path[1024];

    if ((argc == 4 || argc == 5) && strcmp(argv[1], "--profile") == 0)
        return profile(argv[2], argv[3], 20,
                       argc == 5 ? (unsigned)strtoul(argv[4], NULL, 10) : 1);
    if (quick)
        reps = smoke ? 1 : 3;
    printf("## What exactness costs: the float filter\n\n");
    printf("One thread, the same rays through the same tree in three modes: "
           "the exact double test alone, the float filter in front of it "
           "(the default), and the filter's float test as the verdict (a "
           "float tracer).  Median of %d runs, the modes in turn; ratios "
           "the median of each run's own.  Bytes per triangle: the scene "
           "after commit.  Answers unlike the exact test's: a hit or a miss "
           "where it has the other, or another triangle (filter + exact: "
           "or another t, bit for bit).\n\n", reps);
    printf("| mesh | triangles | bytes/tri | rays | exact alone Mrays/s | "
           "filter + exact Mrays/s | filter alone Mrays/s | filter + exact "
           "/ exact | filter alone / filter + exact | unlike exact: filter "
           "+ exact | unlike exact: filter alone |\n");
    printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (k = 0; k < (quick ? 2u : 3u); k++) {
        snprintf(path, sizeof path, "%s/%s", dir, names[k]);
        bench_bunny(path, smoke ? 8 : quick ? 256 : 512);
    }
    bench_leaks(smoke ? 1 : quick ? 5 : 6);
    printf("\n");
    return 0;
}
