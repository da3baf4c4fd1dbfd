/* SPDX-License-Identifier: MIT */
/*
** game.c -- what a game pays for a live scene: a refit after a mesh's
** vertices moved against a full rebuild (the 59k and 940k-triangle
** bunnies), one commit per frame of 1,000 moving instances, the memory
** of an instance, the cost of filters and masks on the query path, and
** of going through an instance; Embree's equivalents in the same run
** when built with it (HAVE_EMBREE), as ratios.
**
**     game DATA_DIR          (bunny-2.obj, bunny-4.obj)
**
** Method: every figure is the median of REPS runs; ratios are taken
** within one run (these machines are shared and noisy).  One thread for
** ours: commit and refit are single-threaded; Embree uses its own thread
** pool on every CPU (noted in the table).  No assertion: tests test.
*/
#include <string.h>
#include <stdio.h>
#include <unistd.h>

#include "bench.h"
#include "obj.h"
#include "common.h"

#include "embree.h"

#define REPS 7

static int reps = REPS;

static obj_mesh load(const char *dir, const char *name)
{
    obj_mesh m;
    char path[512], err[600];

    snprintf(path, sizeof path, "%s/%s", dir, name);
    if (obj_load(path, &m, err, sizeof err) != 0) {
        fprintf(stderr, "game: %s (run scripts/fetch-bunny.sh)\n", err);
        exit(1);
    }
    return m;
}

/* The vertices moved a little (a wave through the mesh): frame f. */
static void wave(const obj_mesh *m, ray_vec3 *out, int f, double size)
{
    size_t i;

    for (i = 0; i < m->vertex_count; i++) {
        ray_vec3 v = m->vertices[i];
        out[i] = vec(v.x, v.y + 0.01 * size * sin(20 * v.x / size + f), v.z);
    }
}

/* ------------------------------------------------------ refit vs rebuild */

/*
** Ours: a commit after ray_scene_update_mesh (a refit), against a commit
** after disabling and enabling the mesh again (the same geometry, the
** triangle BVH rebuilt from scratch).
*/
static void refit_row(const char *name, const obj_mesh *m)
{
    ray_mesh rm = obj_as_ray_mesh(m);
    ray_vec3 *v = malloc(m->vertex_count * sizeof *v), lo, hi, c;
    double refit[REPS], rebuild[REPS], fresh[REPS], eref[REPS], ereb[REPS];
    double refit2[REPS], size, t;
    ray_scene *s, *s2;
    unsigned id, id2;
    int k;

    obj_bounds(m, &lo, &hi, &c, &size);
    rm.normals = NULL;            /* positions only, as a game updates */
    rm.texcoords = NULL;
    rm.vertices = v;
    wave(m, v, 0, size);
    check(ray_scene_new(&s, NULL, NULL), "scene");
    check(ray_scene_add_mesh(s, &rm, RAY_NO_MATERIAL, &id), "mesh");
    check(ray_scene_commit(s), "commit");
    /* The same on two threads (ray_scene_set_build_threads): the refit's
    ** leaves fitted in parallel, as Embree's pool of 2 does. */
    check(ray_scene_new(&s2, NULL, NULL), "scene");
    check(ray_scene_add_mesh(s2, &rm, RAY_NO_MATERIAL, &id2), "mesh");
    check(ray_scene_set_build_threads(s2, 2), "threads");
    check(ray_scene_commit(s2), "commit");
#ifdef HAVE_EMBREE
    RTCDevice dev = rtcNewDevice(NULL);
    RTCScene es = rtcNewScene(dev);
    float *ev;
    RTCGeometry g = embree_triangles(dev, v, m->vertex_count, m->indices,
                                     m->triangle_count, &ev);
    /* Embree uses a geometry's build quality (REFIT here) only in a scene
    ** of build quality LOW, its two-level mode (rtcSetGeometryBuildQuality
    ** (3)). */
    rtcSetGeometryBuildQuality(g, RTC_BUILD_QUALITY_REFIT);
    rtcSetSceneBuildQuality(es, RTC_BUILD_QUALITY_LOW);
    rtcSetSceneFlags(es, RTC_SCENE_FLAG_DYNAMIC);
    rtcCommitGeometry(g);
    rtcAttachGeometry(es, g);
    rtcCommitScene(es);
#endif
    for (k = 0; k < reps; k++) {
        wave(m, v, k + 1, size);
        t = now_seconds();
        check(ray_scene_update_mesh(s, id, &rm), "update");
        check(ray_scene_commit(s), "refit commit");
        refit[k] = now_seconds() - t;
        t = now_seconds();
        check(ray_scene_update_mesh(s2, id2, &rm), "update");
        check(ray_scene_commit(s2), "refit commit");
        refit2[k] = now_seconds() - t;
        t = now_seconds();
        check(ray_scene_set_enabled(s, id, 0), "disable");
        check(ray_scene_set_enabled(s, id, 1), "enable");
        check(ray_scene_commit(s), "rebuild commit");
        rebuild[k] = now_seconds() - t;
        /* What a program without updates does: a new scene. */
        {
            ray_scene *again;
            t = now_seconds();
            check(ray_scene_new(&again, NULL, NULL), "scene");
            check(ray_scene_add_mesh(again, &rm, RAY_NO_MATERIAL, NULL),
                  "mesh");
            check(ray_scene_commit(again), "fresh commit");
            fresh[k] = now_seconds() - t;
            ray_scene_free(again);
        }
#ifdef HAVE_EMBREE
        t = now_seconds();
        embree_positions(ev, v, m->vertex_count);
        rtcUpdateGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0);
        rtcCommitGeometry(g);
        rtcCommitScene(es);
        eref[k] = now_seconds() - t;
#else
        eref[k] = 0;
#endif
    }
#ifdef HAVE_EMBREE
    /* Embree's rebuilds after its refits: switching the build quality
    ** back and forth would make every commit a rebuild. */
    rtcSetGeometryBuildQuality(g, RTC_BUILD_QUALITY_MEDIUM);
    for (k = 0; k < reps; k++) {
        t = now_seconds();
        rtcUpdateGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0);
        rtcCommitGeometry(g);
        rtcCommitScene(es);
        ereb[k] = now_seconds() - t;
    }
#else
    for (k = 0; k < reps; k++)
        ereb[k] = 0;
#endif
    {
        double r = median(refit, reps), b = median(rebuild, reps),
               f = median(fresh, reps);
        printf("| %s | %zu | %.2f | %.1f | %.1fx | %.1f | %.1fx |", name,
               m->triangle_count, 1e3 * r, 1e3 * b, b / r, 1e3 * f, f / r);
#ifdef HAVE_EMBREE
        printf(" %.2f | %.1f | %.2f |", 1e3 * median(eref, reps),
               1e3 * median(ereb, reps), r / median(eref, reps));
        printf(" %.2f | %.2f |\n", 1e3 * median(refit2, reps),
               median(refit2, reps) / median(eref, reps));
#else
        (void)eref;
        (void)ereb;
        printf(" - | - | - | %.2f | - |\n", 1e3 * median(refit2, reps));
#endif
    }
#ifdef HAVE_EMBREE
    rtcReleaseScene(es);
    rtcReleaseGeometry(g);
    rtcReleaseDevice(dev);
#endif
    ray_scene_free(s);
    ray_scene_free(s2);
    free(v);
}

/* ------------------------------------------------------------- instances */

/* Instance i's transform at frame f: a grid of 40 x 25, turning. */
static void instance_xfm(int i, int f, double size, ray_transform *t)
{
    double a = 0.05 * f + i, c = cos(a), s = sin(a);

    ray_transform_identity(t);
    t->m[0][0] = c;
    t->m[0][2] = s;
    t->m[2][0] = -s;
    t->m[2][2] = c;
    t->m[0][3] = 2 * size * (i % 40);
    t->m[1][3] = 0.01 * size * f;
    t->m[2][3] = 2 * size * (i / 40);
}

/*
** 1,000 instances of the 59k-triangle bunny moving every frame: the
** median time of 1,000 ray_scene_set_transform calls and the commit that
** rebuilds the top level; the memory of the bunny scene alone and of the
** scene of its 1,000 instances (the per-instance cost).
*/
static void instances_row(const obj_mesh *m, unsigned quick_res)
{
    ray_mesh rm = obj_as_ray_mesh(m);
    counting child_mem = {0, 0}, top_mem = {0, 0};
    ray_scene *child, *top;
    ray_transform xf;
    ray_vec3 lo, hi, c;
    double frame[REPS], size, efr[REPS], t;
    int i, k, n = 1000;

    obj_bounds(m, &lo, &hi, &c, &size);
    check(ray_scene_new(&child, counting_alloc, &child_mem), "child");
    check(ray_scene_add_mesh(child, &rm, RAY_NO_MATERIAL, NULL), "mesh");
    check(ray_scene_commit(child), "child commit");
    check(ray_scene_new(&top, counting_alloc, &top_mem), "top");
    for (i = 0; i < n; i++) {
        instance_xfm(i, 0, size, &xf);
        check(ray_scene_add_instance(top, child, &xf, NULL), "instance");
    }
    check(ray_scene_commit(top), "top commit");
#ifdef HAVE_EMBREE
    RTCDevice dev = rtcNewDevice(NULL);
    RTCScene ec = rtcNewScene(dev), et = rtcNewScene(dev);
    RTCGeometry g = embree_triangles(dev, m->vertices, m->vertex_count,
                                     m->indices, m->triangle_count, NULL);
    RTCGeometry *inst = malloc((size_t)n * sizeof *inst);
    rtcCommitGeometry(g);
    rtcAttachGeometry(ec, g);
    rtcCommitScene(ec);
    /* Embree's advice for a top level rebuilt every frame. */
    rtcSetSceneFlags(et, RTC_SCENE_FLAG_DYNAMIC);
    rtcSetSceneBuildQuality(et, RTC_BUILD_QUALITY_LOW);
    for (i = 0; i < n; i++) {
        float f[12];
        int r, q;
        instance_xfm(i, 0, size, &xf);
        for (r = 0; r < 3; r++)
            for (q = 0; q < 4; q++)
                f[4 * r + q] = (float)xf.m[r][q];
        inst[i] = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(inst[i], ec);
        rtcSetGeometryTransform(inst[i], 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, f);
        rtcCommitGeometry(inst[i]);
        rtcAttachGeometry(et, inst[i]);
    }
    rtcCommitScene(et);
#endif
    for (k = 0; k < reps; k++) {
        t = now_seconds();
        for (i = 0; i < n; i++) {
            instance_xfm(i, k + 1, size, &xf);
            check(ray_scene_set_transform(top, (unsigned)i, &xf), "move");
        }
        check(ray_scene_commit(top), "frame commit");
        frame[k] = now_seconds() - t;
#ifdef HAVE_EMBREE
        t = now_seconds();
        for (i = 0; i < n; i++) {
            float f[12];
            int r, q;
            instance_xfm(i, k + 1, size, &xf);
            for (r = 0; r < 3; r++)
                for (q = 0; q < 4; q++)
                    f[4 * r + q] = (float)xf.m[r][q];
            rtcSetGeometryTransform(inst[i], 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR,
                                    f);
            rtcCommitGeometry(inst[i]);
        }
        rtcCommitScene(et);
        efr[k] = now_seconds() - t;
#else
        efr[k] = 0;
#endif
    }
    /* Queries over the field of instances: rays straight down onto
    ** them, each at a random point of an instance's box (its centre
    ** moved by the frame's transform), one thread each. */
    {
        size_t nr = (size_t)quick_res * quick_res, hits = 0, q;
        ray_ray *rays = malloc(nr * sizeof *rays);
        double tq[REPS], teq[REPS];
        rng gen = {99};
        ray_hit h;
        for (q = 0; q < nr; q++) {
            ray_vec3 at;
            instance_xfm((int)(q % (size_t)n), reps, size, &xf);
            at = vec(xf.m[0][0] * c.x + xf.m[0][1] * c.y + xf.m[0][2] * c.z +
                         xf.m[0][3],
                     xf.m[1][0] * c.x + xf.m[1][1] * c.y + xf.m[1][2] * c.z +
                         xf.m[1][3],
                     xf.m[2][0] * c.x + xf.m[2][1] * c.y + xf.m[2][2] * c.z +
                         xf.m[2][3]);
            rays[q].org = vec(at.x + rng_range(&gen, -0.3, 0.3) * size,
                              at.y + 10 * size,
                              at.z + rng_range(&gen, -0.3, 0.3) * size);
            rays[q].dir = vec(0.01, -1, 0.02);
            rays[q].tmin = 0;
            rays[q].tmax = HUGE_VAL;
        }
        for (k = 0; k < reps; k++) {
            t = now_seconds();
            for (q = 0, hits = 0; q < nr; q++)
                hits += ray_intersect(top, &rays[q], &h) == 1;
            tq[k] = now_seconds() - t;
#ifdef HAVE_EMBREE
            t = now_seconds();
            for (q = 0; q < nr; q++)
                (void)embree_hit(et, &rays[q], NULL, NULL);
            teq[k] = now_seconds() - t;
#else
            teq[k] = 0;
#endif
        }
        printf("| rays down onto the 1,000 instances (%zu of %zu hit), "
               "one thread | %.2f Mrays/s |", hits, nr,
               (double)nr / median(tq, reps) / 1e6);
#ifdef HAVE_EMBREE
        printf(" %.2f Mrays/s | %.2f (time) |\n",
               (double)nr / median(teq, reps) / 1e6,
               median(tq, reps) / median(teq, reps));
#else
        (void)teq;
        printf(" - | - |\n");
#endif
        free(rays);
    }
    printf("| 1,000 instances of the %zu-triangle bunny moved, then "
           "committed (per frame) | %.3f ms |", m->triangle_count,
           1e3 * median(frame, reps));
#ifdef HAVE_EMBREE
    printf(" %.3f ms | %.2f |\n", 1e3 * median(efr, reps),
           median(frame, reps) / median(efr, reps));
    for (i = 0; i < n; i++)
        rtcReleaseGeometry(inst[i]);
    free(inst);
    rtcReleaseScene(et);
    rtcReleaseScene(ec);
    rtcReleaseGeometry(g);
    rtcReleaseDevice(dev);
#else
    (void)efr;
    printf(" - | - |\n");
#endif
    printf("| Memory: the bunny scene once | %.1f KiB | | |\n",
           (double)child_mem.now / 1024);
    printf("| Memory: the scene of its 1,000 instances | %.1f KiB (%.0f bytes "
           "an instance) | | |\n\n", (double)top_mem.now / 1024,
           (double)top_mem.now / n);
    ray_scene_free(top);
    ray_scene_free(child);
}

/* ---------------------------------------------------- the query's gates */

static int keep_all(void *ud, const ray_ray *r, const ray_hit *c, void *q)
{
    (void)ud;
    (void)r;
    (void)c;
    (void)q;
    return 1;
}

/* Camera rays at the bunny from +z, a diagonal away: res x res. */
static ray_ray *camera_rays(ray_vec3 c, double diag, unsigned res)
{
    ray_ray *rays = malloc((size_t)res * res * sizeof *rays);
    double half = tan(45.0 * 3.14159265358979323846 / 360.0);
    unsigned x, y;

    for (y = 0; y < res; y++)
        for (x = 0; x < res; x++) {
            ray_ray *r = &rays[(size_t)y * res + x];
            r->org = vec(c.x, c.y, c.z + diag);
            r->dir = vec((2 * (x + 0.5) / res - 1) * half,
                         (1 - 2 * (y + 0.5) / res) * half, -1);
            r->tmin = 0;
            r->tmax = HUGE_VAL;
        }
    return rays;
}

/* Seconds for every ray through scene s (q NULL: ray_intersect). */
static double pass(const ray_scene *s, const ray_ray *rays, size_t n,
                   const ray_query *q, size_t *hits)
{
    double t = now_seconds();
    size_t i;
    ray_hit h;

    *hits = 0;
    for (i = 0; i < n; i++)
        *hits += (q == NULL ? ray_intersect(s, &rays[i], &h)
                            : ray_intersect_opt(s, &rays[i], q, &h)) == 1;
    return now_seconds() - t;
}

/*
** The price of gates on the bunny's camera rays, each against the plain
** scene in the same run: a query mask (ray_intersect_opt, one bit), a
** filter that keeps everything (called once per candidate), and the same
** bunny through an identity instance.
*/
static void gates_rows(const obj_mesh *m, unsigned res)
{
    ray_mesh rm = obj_as_ray_mesh(m);
    ray_scene *plain, *filtered, *top;
    ray_transform id;
    ray_query q;
    ray_ray *rays;
    ray_vec3 lo, hi, c;
    double diag, tp[REPS], tm[REPS], tf[REPS], ti[REPS];
    size_t n = (size_t)res * res, hits[4] = {0, 0, 0, 0};
    unsigned g;
    int k;

    obj_bounds(m, &lo, &hi, &c, &diag);
    rays = camera_rays(c, diag, res);
    check(ray_scene_new(&plain, NULL, NULL), "scene");
    check(ray_scene_add_mesh(plain, &rm, RAY_NO_MATERIAL, NULL), "mesh");
    check(ray_scene_commit(plain), "commit");
    check(ray_scene_new(&filtered, NULL, NULL), "scene");
    check(ray_scene_add_mesh(filtered, &rm, RAY_NO_MATERIAL, &g), "mesh");
    check(ray_scene_set_filter(filtered, g, keep_all, NULL,
                               RAY_FILTER_INTERSECT), "filter");
    check(ray_scene_commit(filtered), "commit");
    ray_transform_identity(&id);
    check(ray_scene_new(&top, NULL, NULL), "scene");
    check(ray_scene_add_instance(top, plain, &id, NULL), "instance");
    check(ray_scene_commit(top), "commit");
    memset(&q, 0, sizeof q);
    q.ignore_mask = ~1u;
    for (k = 0; k < reps; k++) {
        tp[k] = pass(plain, rays, n, NULL, &hits[0]);
        tm[k] = pass(plain, rays, n, &q, &hits[1]);
        tf[k] = pass(filtered, rays, n, NULL, &hits[2]);
        ti[k] = pass(top, rays, n, NULL, &hits[3]);
    }
    {
        double p = median(tp, reps);
        printf("| Query | Mrays/s | time / plain |\n|---|---|---|\n");
        printf("| ray_intersect, plain scene (%zu hits) | %.2f | 1.00 |\n",
               hits[0], (double)n / p / 1e6);
        printf("| ray_intersect_opt, mask 1 (%zu hits) | %.2f | %.2f |\n",
               hits[1], (double)n / median(tm, reps) / 1e6,
               median(tm, reps) / p);
        printf("| ray_intersect, a keep-all filter on the mesh (%zu hits) | "
               "%.2f | %.2f |\n", hits[2], (double)n / median(tf, reps) / 1e6,
               median(tf, reps) / p);
        printf("| ray_intersect through an identity instance (%zu hits) | "
               "%.2f | %.2f |\n\n", hits[3],
               (double)n / median(ti, reps) / 1e6, median(ti, reps) / p);
    }
    ray_scene_free(top);
    ray_scene_free(filtered);
    ray_scene_free(plain);
    free(rays);
}

int main(int argc, char **argv)
{
    const char *dir = argc > 1 ? argv[1] : "data";
    int quick = getenv("BENCH_QUICK") != NULL;
    obj_mesh mid = load(dir, "bunny-2.obj");

    reps = quick ? 3 : REPS;
    printf("## Games and tools: live scenes\n\n");
#ifdef HAVE_EMBREE
    printf("Median of %d runs; ours on one thread (but the column that "
           "says two); Embree %s on its own "
           "thread pool (all %ld CPUs), float vertices.\n\n", reps,
           RTC_VERSION_STRING, sysconf(_SC_NPROCESSORS_ONLN));
#else
    printf("Median of %d runs; ours on one thread (but the column that "
           "says two); Embree absent (install "
           "libembree-dev and rerun for its columns).\n\n", reps);
#endif
    printf("### Refit against rebuild (a commit after "
           "ray_scene_update_mesh against one that rebuilds the triangle "
           "BVH)\n\n");
    printf("Refit: ray_scene_update_mesh with the moved vertices, then "
           "ray_scene_commit.  BVH rebuild: the same mesh's triangle BVH built "
           "again (disabled and enabled, then committed).  New scene: what a "
           "program without updates does, ray_scene_new, ray_scene_add_mesh "
           "and ray_scene_commit.\n\n");
    printf("| mesh | triangles | refit ms | BVH rebuild ms | rebuild / refit | "
           "new scene ms | new scene / refit | "
           "Embree refit ms | Embree rebuild ms | ours / Embree (refit) | "
           "refit ms, ours on 2 threads | ours on 2 / Embree (refit) |\n"
           "|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    refit_row("bunny-2", &mid);
    if (!quick) {
        obj_mesh big = load(dir, "bunny-4.obj");
        refit_row("bunny-4", &big);
        obj_free(&big);
    }
    printf("\n### Instances\n\n| what | ours | Embree | ours / Embree |\n"
           "|---|---|---|---|\n");
    instances_row(&mid, quick ? 256u : 512u);
    printf("### Gates on the query path (bunny-2, %ux%u camera rays)\n\n",
           quick ? 256u : 512u, quick ? 256u : 512u);
    gates_rows(&mid, quick ? 256u : 512u);
    obj_free(&mid);
    return 0;
}
