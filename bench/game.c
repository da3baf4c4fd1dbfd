/* SPDX-License-Identifier: MIT */
/*
** game.c -- what a game pays for a live scene: a refit after a mesh's
** vertices moved against a full rebuild (the 59k and 940k-triangle
** bunnies), one commit per frame of 1,000 moving instances, the memory
** of an instance, the cost of filters and masks on the query path, and
** of going through an instance, and a game's frame (10 skinned meshes
** refitted, 100 props moved, one commit, 100k incoherent rays: issue
** 36); Embree's equivalents in the same run when built with it
** (HAVE_EMBREE), as ratios.
**
**     game DATA_DIR          (bunny-2.obj, bunny-4.obj)
**     game DATA_DIR frame    (the frame's table alone: no data read)
**
** Method: every figure is the median of REPS runs; ratios are taken
** within one run (these machines are shared and noisy).  One thread for
** ours: commit and refit are single-threaded; Embree uses its own thread
** pool on every CPU (noted in the table).  No assertion: tests test.
*/
#include <string.h>
#include <stdio.h>
#include <unistd.h>
#include <pthread.h>

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

#ifdef HAVE_EMBREE
/* An Embree scene set up to refit one mesh: on device "config" (NULL: its
** default pool of all CPUs). */
typedef struct embree_refit {
    RTCDevice dev;
    RTCScene s;
    RTCGeometry g;
    float *v;
} embree_refit;

static void embree_refit_new(embree_refit *e, const char *config,
                             const ray_vec3 *v, const obj_mesh *m)
{
    e->dev = rtcNewDevice(config);
    e->s = rtcNewScene(e->dev);
    e->g = embree_triangles(e->dev, v, m->vertex_count, m->indices,
                            m->triangle_count, &e->v);
    /* Embree uses a geometry's build quality (REFIT here) only in a scene
    ** of build quality LOW, its two-level mode (rtcSetGeometryBuildQuality
    ** (3)). */
    rtcSetGeometryBuildQuality(e->g, RTC_BUILD_QUALITY_REFIT);
    rtcSetSceneBuildQuality(e->s, RTC_BUILD_QUALITY_LOW);
    rtcSetSceneFlags(e->s, RTC_SCENE_FLAG_DYNAMIC);
    rtcCommitGeometry(e->g);
    rtcAttachGeometry(e->s, e->g);
    rtcCommitScene(e->s);
}

/* Seconds for Embree's refit to vertices v: the positions written into
** its shared float buffer (as ours are copied), then the commits. */
static double embree_refit_time(embree_refit *e, const ray_vec3 *v,
                                size_t n)
{
    double t = now_seconds();

    embree_positions(e->v, v, n);
    rtcUpdateGeometryBuffer(e->g, RTC_BUFFER_TYPE_VERTEX, 0);
    rtcCommitGeometry(e->g);
    rtcCommitScene(e->s);
    return now_seconds() - t;
}

static void embree_refit_free(embree_refit *e)
{
    rtcReleaseScene(e->s);
    rtcReleaseGeometry(e->g);
    rtcReleaseDevice(e->dev);
}
#endif

/*
** Ours: a commit after ray_scene_update_mesh (a refit), against a commit
** after disabling and enabling the mesh again (the same geometry, the
** triangle BVH rebuilt from scratch).  The refits first, ours and
** Embree's in turn, then the rebuilds, each side's as Embree's always
** were: a refit timed right after a rebuild of its scene made the
** refit's list of leaves again (accel/refit.c, once a tree) and found
** the caches full of the rebuild's memory, which no game's frame does.
*/
static void refit_row(const char *name, const obj_mesh *m)
{
    ray_mesh rm = obj_as_ray_mesh(m);
    ray_vec3 *v = malloc(m->vertex_count * sizeof *v), lo, hi, c;
    double refit[REPS], rebuild[REPS], fresh[REPS], eref[REPS], ereb[REPS];
    double eref1[REPS];
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
    /* Embree twice: on its default pool (all CPUs) and on one thread. */
    embree_refit ep, e1;
    embree_refit_new(&ep, NULL, v, m);
    embree_refit_new(&e1, "threads=1", v, m);
#endif
    /* The refits in a row, then the rebuilds (the comment above says
    ** why). */
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
#ifdef HAVE_EMBREE
        eref[k] = embree_refit_time(&ep, v, m->vertex_count);
        eref1[k] = embree_refit_time(&e1, v, m->vertex_count);
#else
        eref[k] = eref1[k] = 0;
#endif
    }
    for (k = 0; k < reps; k++) {
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
    }
#ifdef HAVE_EMBREE
    /* Embree's rebuilds after its refits: switching the build quality
    ** back and forth would make every commit a rebuild. */
    rtcSetGeometryBuildQuality(ep.g, RTC_BUILD_QUALITY_MEDIUM);
    for (k = 0; k < reps; k++) {
        t = now_seconds();
        rtcUpdateGeometryBuffer(ep.g, RTC_BUFFER_TYPE_VERTEX, 0);
        rtcCommitGeometry(ep.g);
        rtcCommitScene(ep.s);
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
        printf(" %.1f | %.2f | %.2f |", 1e3 * median(ereb, reps),
               1e3 * median(eref1, reps), r / median(eref1, reps));
        printf(" %.2f | %.2f | %.2f |\n", 1e3 * median(refit2, reps),
               1e3 * median(eref, reps), median(refit2, reps) /
               median(eref, reps));
#else
        (void)eref;
        (void)eref1;
        (void)ereb;
        printf(" - | - | - | %.2f | - | - |\n", 1e3 * median(refit2, reps));
#endif
    }
#ifdef HAVE_EMBREE
    embree_refit_free(&ep);
    embree_refit_free(&e1);
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
                hits += ray_intersect(top, &rays[q], &h, NULL) == 1;
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
        *hits += ray_intersect(s, &rays[i], &h, q) == 1;
    return now_seconds() - t;
}

/*
** The price of gates on the bunny's camera rays, each against the plain
** scene in the same run: a query mask (ray_intersect's options, one bit), a
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
        printf("| ray_intersect with a ray_query, mask 1 (%zu hits) | "
               "%.2f | %.2f |\n",
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

/* ------------------------------------------------------- a game's frame */

/*
** A game's frame (issue 36): 10 skinned characters and 100 moving props,
** then incoherent rays.  A character is a tube of FRAME_AROUND x
** FRAME_ALONG quads (20,000 triangles, 10,100 float vertices, as a game's
** vertex buffer holds them) that the frame's "skinning" bends and swells
** in its own space; each is in a child scene of its own, placed in the
** top scene by an instance that walks: what a game does (DXR's and
** Vulkan's bottom-level structure per skinned mesh, refitted, and a top
** level rebuilt every frame; Embree's two-level scenes), so a refit
** never has to stretch one tree's boxes over characters walking apart.
** The props are 100 instances of one 96-triangle mesh.
*/
#define FRAME_CHARS 10
#define FRAME_PROPS 100
#define FRAME_AROUND 100u
#define FRAME_ALONG 100u
#define FRAME_WARM 2
#define FRAME_REPS 15            /* frames are short: more of them */

/* Indices of a tube of around x along quads: ring j holds vertices
** j * around .. j * around + around - 1 (along + 1 rings). */
static unsigned *tube_indices(unsigned around, unsigned along)
{
    /* One index more: Embree reads a shared buffer 16 bytes at a time. */
    size_t n = (size_t)6 * around * along;
    unsigned *idx = malloc((n + 1) * sizeof *idx), i, j;

    if (idx == NULL)
        check(RAY_ENOMEM, "tube");
    for (j = 0; j < along; j++)
        for (i = 0; i < around; i++) {
            unsigned a = j * around + i, b = j * around + (i + 1) % around,
                     *t = idx + 6 * ((size_t)j * around + i);
            t[0] = a; t[1] = b; t[2] = b + around;
            t[3] = a; t[4] = b + around; t[5] = a + around;
        }
    idx[n] = 0;
    return idx;
}

/*
** The tube's positions (floats, packed) bent by "bend" radians along its
** length (the axis an arc in the x-y plane, each ring turned with it: a
** chain of bones, skinned) and swelling in a wave of phase "phase".
*/
static void tube_skin(float *out, unsigned around, unsigned along,
                      double radius, double length, double bend, double phase)
{
    double k = bend / length, pi = 3.14159265358979323846;
    unsigned i, j;

    for (j = 0; j <= along; j++) {
        double h = length * j / along, th = k * h;
        double cx = fabs(k) > 1e-12 ? (1 - cos(th)) / k : 0;
        double cy = fabs(k) > 1e-12 ? sin(th) / k : h;
        double r = radius * (1 + 0.15 * sin(2 * pi * h / length + phase));
        for (i = 0; i < around; i++) {
            double a = 2 * pi * i / around, ca = cos(a), sa = sin(a);
            float *p = out + 3 * ((size_t)j * around + i);
            p[0] = (float)(cx + r * ca * cos(th));
            p[1] = (float)(cy - r * ca * sin(th));
            p[2] = (float)(r * sa);
        }
    }
}

/* A turn by angle a about +y, then a move by (x, y, z). */
static void xfm_turn(ray_transform *t, double a, double x, double y, double z)
{
    ray_transform_identity(t);
    t->m[0][0] = cos(a);
    t->m[0][2] = sin(a);
    t->m[2][0] = -sin(a);
    t->m[2][2] = cos(a);
    t->m[0][3] = x;
    t->m[1][3] = y;
    t->m[2][3] = z;
}

/* Character c's place at frame f: a 5 x 2 grid, 4 apart, walking round. */
static void char_xfm(int c, int f, ray_transform *t)
{
    xfm_turn(t, 0.05 * f + c, 4.0 * (c % 5) + 0.3 * sin(0.05 * f + c), 0,
             4.0 * (c / 5) + 0.3 * cos(0.05 * f + c));
}

/* Prop i's place at frame f: a 10 x 10 field, each circling. */
static void prop_xfm(int i, int f, ray_transform *t)
{
    xfm_turn(t, 0.2 * f + i, -1 + 2.0 * (i % 10) + 0.5 * sin(0.1 * f + i),
             0.5 + 3.5 * ((i * 37) % 100) / 100.0 +
                 0.3 * sin(0.13 * f + 2 * i),
             -1 + 0.7 * (i / 10) + 0.5 * cos(0.1 * f + i));
}

/* Character c's skinning at frame f, into its vertex buffer v. */
static void char_skin(float *v, int c, int f)
{
    tube_skin(v, FRAME_AROUND, FRAME_ALONG, 0.5, 4.0,
              sin(0.1 * f + c), 0.3 * f + c);
}

/* The scene's box, which the rays start in: x -2..18, y 0..5, z -2..6. */
static const double frame_lo[3] = {-2, 0, -2}, frame_hi[3] = {18, 5, 6};

/* Ours: the child scenes, the top scene and their ids. */
typedef struct frame_ours {
    ray_scene *top, *prop, *chars[FRAME_CHARS];
    unsigned mesh[FRAME_CHARS], inst[FRAME_CHARS + FRAME_PROPS];
} frame_ours;

static ray_mesh frame_mesh(const float *v, size_t nv, const unsigned *idx,
                           size_t nt)
{
    ray_mesh m;

    memset(&m, 0, sizeof m);
    m.positions = v;
    m.position_type = RAY_FLOAT32;
    m.vertex_count = nv;
    m.indices = idx;
    m.triangle_count = nt;
    return m;
}

static void frame_ours_new(frame_ours *w, unsigned threads, float **cv,
                           const unsigned *cidx, const float *pv,
                           const unsigned *pidx)
{
    size_t nv = (size_t)FRAME_AROUND * (FRAME_ALONG + 1);
    ray_mesh pm = frame_mesh(pv, 12 * 5, pidx, 96);
    ray_transform xf;
    int c, i;

    check(ray_scene_new(&w->prop, NULL, NULL), "prop");
    check(ray_scene_add_mesh(w->prop, &pm, RAY_NO_MATERIAL, NULL), "prop");
    check(ray_scene_commit(w->prop), "prop commit");
    check(ray_scene_new(&w->top, NULL, NULL), "top");
    check(ray_scene_set_build_threads(w->top, threads), "threads");
    for (c = 0; c < FRAME_CHARS; c++) {
        ray_mesh m = frame_mesh(cv[c], nv, cidx,
                                2 * (size_t)FRAME_AROUND * FRAME_ALONG);
        check(ray_scene_new(&w->chars[c], NULL, NULL), "character");
        check(ray_scene_set_build_threads(w->chars[c], threads), "threads");
        check(ray_scene_add_mesh(w->chars[c], &m, RAY_NO_MATERIAL,
                                 &w->mesh[c]), "character");
        check(ray_scene_commit(w->chars[c]), "character commit");
        char_xfm(c, 0, &xf);
        check(ray_scene_add_instance(w->top, w->chars[c], &xf, &w->inst[c]),
              "instance");
    }
    for (i = 0; i < FRAME_PROPS; i++) {
        prop_xfm(i, 0, &xf);
        check(ray_scene_add_instance(w->top, w->prop, &xf,
                                     &w->inst[FRAME_CHARS + i]), "instance");
    }
    check(ray_scene_commit(w->top), "top commit");
}

/* Ours: characters c0 .. c1 - 1 given the frame's skinned positions
** (cv: the buffers), each updated and its scene committed (a refit). */
static void frame_ours_refit(frame_ours *w, float **cv, const unsigned *cidx,
                            int c0, int c1)
{
    size_t nv = (size_t)FRAME_AROUND * (FRAME_ALONG + 1);
    int c;

    for (c = c0; c < c1; c++) {
        ray_mesh m = frame_mesh(cv[c], nv, cidx,
                                2 * (size_t)FRAME_AROUND * FRAME_ALONG);
        check(ray_scene_update_mesh(w->chars[c], w->mesh[c], &m), "skin");
        check(ray_scene_commit(w->chars[c]), "character commit");
    }
}

/* The game's second thread: the second half of the characters. */
typedef struct frame_half {
    frame_ours *w;
    float **cv;
    const unsigned *cidx;
} frame_half;

static void *frame_half_run(void *arg)
{
    frame_half *h = arg;

    frame_ours_refit(h->w, h->cv, h->cidx, FRAME_CHARS / 2, FRAME_CHARS);
    return NULL;
}

/* Ours: frame f's moves, updates and commits; split: the characters'
** updates and commits shared with a second thread of the game's (a
** scene is built by one thread at a time, but different scenes may be
** built at once), each commit on one. */
static void frame_ours_step(frame_ours *w, int f, float **cv,
                            const unsigned *cidx, int split)
{
    ray_transform xf;
    int c, i;

    for (i = 0; i < FRAME_PROPS; i++) {
        prop_xfm(i, f, &xf);
        check(ray_scene_set_transform(w->top, w->inst[FRAME_CHARS + i], &xf),
              "move");
    }
    if (split) {
        frame_half h;
        pthread_t th;
        int started;
        h.w = w;
        h.cv = cv;
        h.cidx = cidx;
        started = pthread_create(&th, NULL, frame_half_run, &h) == 0;
        frame_ours_refit(w, cv, cidx, 0, FRAME_CHARS / 2);
        if (started)
            pthread_join(th, NULL);
        else
            frame_half_run(&h);         /* no thread: the same work here */
    } else {
        frame_ours_refit(w, cv, cidx, 0, FRAME_CHARS);
    }
    for (c = 0; c < FRAME_CHARS; c++) {
        char_xfm(c, f, &xf);
        check(ray_scene_set_transform(w->top, w->inst[c], &xf), "walk");
    }
    check(ray_scene_commit(w->top), "top commit");
}

static void frame_ours_free(frame_ours *w)
{
    int c;

    ray_scene_free(w->top);
    for (c = 0; c < FRAME_CHARS; c++)
        ray_scene_free(w->chars[c]);
    ray_scene_free(w->prop);
}

/* One frame's rays through ours, one at a time: seconds; t[i] the hit's
** (HUGE_VAL: a miss), inst[i] its instance; *hits how many hit. */
static double frame_ours_rays(const ray_scene *s, const ray_ray *rays,
                              size_t n, double *t, unsigned *inst,
                              size_t *hits)
{
    double t0 = now_seconds();
    size_t i;
    ray_hit h;

    *hits = 0;
    for (i = 0; i < n; i++)
        if (ray_intersect(s, &rays[i], &h, NULL) == 1) {
            t[i] = h.t;
            inst[i] = h.inst_id;
            ++*hits;
        } else {
            t[i] = HUGE_VAL;
        }
    return now_seconds() - t0;
}

/* The same rays through ray_intersect_batch: seconds. */
static double frame_ours_batch(const ray_scene *s, const ray_ray *rays,
                               size_t n, ray_hit *h, int *res)
{
    double t0 = now_seconds();
    ray_batch b = {0};

    b.rays = rays;
    b.n = n;
    b.hits = h;
    b.results = res;
    check(ray_intersect_batch(s, &b), "batch");
    return now_seconds() - t0;
}

#ifdef HAVE_EMBREE
/* Embree: the same scenes (instances attached in ours' order, so that
** their ids are ours), the characters' vertices in a buffer shared with
** the game's skinning (rtcSetSharedGeometryBuffer: nothing copied). */
typedef struct frame_embree {
    RTCDevice dev;
    RTCScene top, prop, chars[FRAME_CHARS];
    RTCGeometry mesh[FRAME_CHARS], inst[FRAME_CHARS + FRAME_PROPS];
} frame_embree;

static void frame_embree_xfm(RTCGeometry g, const ray_transform *xf)
{
    float m[12];
    int r, q;

    for (r = 0; r < 3; r++)
        for (q = 0; q < 4; q++)
            m[4 * r + q] = (float)xf->m[r][q];
    rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, m);
    rtcCommitGeometry(g);
}

static RTCGeometry frame_embree_mesh(RTCDevice dev, const float *v,
                                     size_t nv, const unsigned *idx,
                                     size_t nt)
{
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);

    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                               v, 0, 3 * sizeof(float), nv);
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                               idx, 0, 3 * sizeof(unsigned), nt);
    return g;
}

static void frame_embree_new(frame_embree *w, float **cv,
                             const unsigned *cidx, const float *pv,
                             const unsigned *pidx)
{
    size_t nv = (size_t)FRAME_AROUND * (FRAME_ALONG + 1);
    RTCGeometry g;
    ray_transform xf;
    int c, i;

    w->dev = rtcNewDevice(NULL);
    w->prop = rtcNewScene(w->dev);
    g = frame_embree_mesh(w->dev, pv, 12 * 5, pidx, 96);
    rtcCommitGeometry(g);
    rtcAttachGeometry(w->prop, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(w->prop);
    /* Embree's advice for a top level rebuilt every frame, and for
    ** refitted meshes (a geometry's REFIT quality is used only in a scene
    ** of quality LOW: rtcSetGeometryBuildQuality(3)). */
    w->top = rtcNewScene(w->dev);
    rtcSetSceneFlags(w->top, RTC_SCENE_FLAG_DYNAMIC);
    rtcSetSceneBuildQuality(w->top, RTC_BUILD_QUALITY_LOW);
    for (c = 0; c < FRAME_CHARS; c++) {
        w->chars[c] = rtcNewScene(w->dev);
        rtcSetSceneFlags(w->chars[c], RTC_SCENE_FLAG_DYNAMIC);
        rtcSetSceneBuildQuality(w->chars[c], RTC_BUILD_QUALITY_LOW);
        w->mesh[c] = frame_embree_mesh(w->dev, cv[c], nv, cidx,
                                       2 * (size_t)FRAME_AROUND * FRAME_ALONG);
        rtcSetGeometryBuildQuality(w->mesh[c], RTC_BUILD_QUALITY_REFIT);
        rtcCommitGeometry(w->mesh[c]);
        rtcAttachGeometry(w->chars[c], w->mesh[c]);
        rtcCommitScene(w->chars[c]);
        w->inst[c] = rtcNewGeometry(w->dev, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(w->inst[c], w->chars[c]);
        char_xfm(c, 0, &xf);
        frame_embree_xfm(w->inst[c], &xf);
        rtcAttachGeometry(w->top, w->inst[c]);
    }
    for (i = 0; i < FRAME_PROPS; i++) {
        RTCGeometry p = rtcNewGeometry(w->dev, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(p, w->prop);
        prop_xfm(i, 0, &xf);
        frame_embree_xfm(p, &xf);
        rtcAttachGeometry(w->top, p);
        w->inst[FRAME_CHARS + i] = p;
    }
    rtcCommitScene(w->top);
}

static void frame_embree_step(frame_embree *w, int f)
{
    ray_transform xf;
    int c, i;

    for (i = 0; i < FRAME_PROPS; i++) {
        prop_xfm(i, f, &xf);
        frame_embree_xfm(w->inst[FRAME_CHARS + i], &xf);
    }
    for (c = 0; c < FRAME_CHARS; c++) {
        rtcUpdateGeometryBuffer(w->mesh[c], RTC_BUFFER_TYPE_VERTEX, 0);
        rtcCommitGeometry(w->mesh[c]);
        rtcCommitScene(w->chars[c]);
        char_xfm(c, f, &xf);
        frame_embree_xfm(w->inst[c], &xf);
    }
    rtcCommitScene(w->top);
}

static void frame_embree_free(frame_embree *w)
{
    int c, i;

    for (i = 0; i < FRAME_CHARS + FRAME_PROPS; i++)
        rtcReleaseGeometry(w->inst[i]);
    rtcReleaseScene(w->top);
    for (c = 0; c < FRAME_CHARS; c++) {
        rtcReleaseGeometry(w->mesh[c]);
        rtcReleaseScene(w->chars[c]);
    }
    rtcReleaseScene(w->prop);
    rtcReleaseDevice(w->dev);
}

static void frame_embree_ray(struct RTCRayHit *rh, const ray_ray *r)
{
    rh->ray.org_x = (float)r->org.x;
    rh->ray.org_y = (float)r->org.y;
    rh->ray.org_z = (float)r->org.z;
    rh->ray.dir_x = (float)r->dir.x;
    rh->ray.dir_y = (float)r->dir.y;
    rh->ray.dir_z = (float)r->dir.z;
    rh->ray.tnear = (float)r->tmin;
    rh->ray.tfar = INFINITY;
    rh->ray.mask = 0xffffffffu;
    rh->ray.flags = 0;
    rh->ray.time = 0;
    rh->hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh->hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

/* One frame's rays through Embree, rtcIntersect1 each: as ours'. */
static double frame_embree_rays(RTCScene s, const ray_ray *rays, size_t n,
                                double *t, unsigned *inst, size_t *hits)
{
    double t0 = now_seconds();
    struct RTCIntersectContext ctx;
    struct RTCRayHit rh;
    size_t i;

    *hits = 0;
    for (i = 0; i < n; i++) {
        rtcInitIntersectContext(&ctx);
        frame_embree_ray(&rh, &rays[i]);
        rtcIntersect1(s, &ctx, &rh);
        if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
            t[i] = rh.ray.tfar;
            inst[i] = rh.hit.instID[0];
            ++*hits;
        } else {
            t[i] = HUGE_VAL;
        }
    }
    return now_seconds() - t0;
}

/* The same rays as one stream, rtcIntersect1M (incoherent). */
static double frame_embree_batch(RTCScene s, const ray_ray *rays, size_t n,
                                 struct RTCRayHit *rh)
{
    double t0 = now_seconds();
    struct RTCIntersectContext ctx;
    size_t i;

    for (i = 0; i < n; i++)
        frame_embree_ray(&rh[i], &rays[i]);
    rtcInitIntersectContext(&ctx);
    rtcIntersect1M(s, &ctx, rh, (unsigned)n, sizeof *rh);
    return now_seconds() - t0;
}
#endif

/*
** Rays that two answers disagree on: a hit against a miss, another
** instance, or hits apart by more than 1e-4 (the scene is 20 across);
** *most: the largest difference in t of the rays they agree on.  Embree
** works in float: an instance's transform, its inverse and the ray in
** the instance's space are off by about 1e-6 at 18 units, which moves a
** hit along the ray by that over the cosine of the angle of incidence
** (the largest difference measured, 7.8e-5, was a prop hit at a cosine
** of 0.013).  Hits of random directions have a cosine below c with
** probability c^2, so 1e-4 lets through all but about one hit in 10^4.
*/
static size_t frame_differ(const double *ta, const unsigned *ia,
                           const double *tb, const unsigned *ib, size_t n,
                           double *most)
{
    size_t i, d = 0;

    *most = 0;
    for (i = 0; i < n; i++) {
        int ha = ta[i] < HUGE_VAL, hb = tb[i] < HUGE_VAL;
        if (ha != hb || (ha && (ia[i] != ib[i] || fabs(ta[i] - tb[i]) > 1e-4)))
            d++;
        else if (ha && fabs(ta[i] - tb[i]) > *most)
            *most = fabs(ta[i] - tb[i]);
    }
    return d;
}

/* Ours three ways (the build threads, the game's threads), then Embree. */
#define FRAME_OURS 3
#define FRAME_WORLDS (FRAME_OURS + 1)

static void frame_row(int quick)
{
    static const unsigned build_threads[FRAME_OURS] = {1, 2, 1};
    static const char *const name[FRAME_WORLDS] = {
        "ours, commits on one thread",
        "ours, commits on 2 threads (ray_scene_set_build_threads)",
        "ours, the characters' commits shared by 2 of the game's threads",
        "Embree (commits on its pool)"};
    size_t nv = (size_t)FRAME_AROUND * (FRAME_ALONG + 1),
           nt = 2 * (size_t)FRAME_AROUND * FRAME_ALONG,
           nr = bench_level() == BENCH_SMOKE ? 100 : quick ? 10000 : 100000, i, hits[FRAME_WORLDS], same = 0, d;
    unsigned *cidx = tube_indices(FRAME_AROUND, FRAME_ALONG),
             *pidx = tube_indices(12, 4), *inst[FRAME_WORLDS];
    float *cv[FRAME_CHARS], pv[3 * 12 * 5 + 1];
    ray_ray *rays = malloc(nr * sizeof *rays);
    ray_hit *bh = malloc(nr * sizeof *bh);
    int *res = malloc(nr * sizeof *res), n = quick ? reps : FRAME_REPS,
        frames = n + FRAME_WARM, f, c, w;
    double *t[FRAME_WORLDS], up[FRAME_WORLDS][FRAME_REPS],
           tr[FRAME_WORLDS][FRAME_REPS], tb[FRAME_WORLDS][FRAME_REPS],
           tot[FRAME_WORLDS][FRAME_REPS], t0, most;
    frame_ours ours[FRAME_OURS];
    rng gen = {36};
#ifdef HAVE_EMBREE
    struct RTCRayHit *erh = malloc(nr * sizeof *erh);
    frame_embree emb;
    const int worlds = FRAME_WORLDS;
#else
    const int worlds = FRAME_OURS;
#endif

    for (w = 0; w < FRAME_WORLDS; w++) {
        t[w] = malloc(nr * sizeof *t[w]);
        inst[w] = malloc(nr * sizeof *inst[w]);
        hits[w] = 0;
    }
    /* Embree reads a shared vertex buffer 4 bytes past its last vertex
    ** (rtcSetSharedGeometryBuffer(3)): one float more. */
    for (c = 0; c < FRAME_CHARS; c++) {
        cv[c] = malloc((3 * nv + 1) * sizeof *cv[c]);
        cv[c][3 * nv] = 0;
        char_skin(cv[c], c, 0);
    }
    tube_skin(pv, 12, 4, 0.25, 0.5, 0, 0);
    pv[3 * 12 * 5] = 0;
    /* One draw a statement: the order in which a call's arguments are
    ** evaluated is unspecified (gcc and clang differ), and the rays must
    ** be the same whoever compiled the bench.  Directions uniform on the
    ** sphere: z uniform in [-1, 1], the angle about z uniform. */
    for (i = 0; i < nr; i++) {
        double x = rng_range(&gen, frame_lo[0], frame_hi[0]);
        double y = rng_range(&gen, frame_lo[1], frame_hi[1]);
        double z = rng_range(&gen, frame_lo[2], frame_hi[2]);
        double dz = rng_range(&gen, -1, 1), s = sqrt(1 - dz * dz);
        double phi = rng_range(&gen, 0, 2 * 3.14159265358979323846);
        rays[i].org = vec(x, y, z);
        rays[i].dir = vec(s * cos(phi), s * sin(phi), dz);
        rays[i].tmin = 0;
        rays[i].tmax = HUGE_VAL;
    }
    for (w = 0; w < FRAME_OURS; w++)
        frame_ours_new(&ours[w], build_threads[w], cv, cidx, pv, pidx);
#ifdef HAVE_EMBREE
    frame_embree_new(&emb, cv, cidx, pv, pidx);
#endif
    /* Frame by frame, each in turn (who goes first rotating): the
    ** skinning (the game's, not timed) writes the buffers all read. */
    for (f = 1; f <= frames; f++) {
        int k = f - 1 - FRAME_WARM, j;
        double u[FRAME_WORLDS], r[FRAME_WORLDS], b[FRAME_WORLDS];
        for (c = 0; c < FRAME_CHARS; c++)
            char_skin(cv[c], c, f);
        for (j = 0; j < worlds; j++) {
            w = (j + f) % worlds;
            if (w < FRAME_OURS) {
                t0 = now_seconds();
                frame_ours_step(&ours[w], f, cv, cidx, w == 2);
                u[w] = now_seconds() - t0;
                r[w] = frame_ours_rays(ours[w].top, rays, nr, t[w], inst[w],
                                       &hits[w]);
                b[w] = frame_ours_batch(ours[w].top, rays, nr, bh, res);
            }
#ifdef HAVE_EMBREE
            else {
                t0 = now_seconds();
                frame_embree_step(&emb, f);
                u[w] = now_seconds() - t0;
                r[w] = frame_embree_rays(emb.top, rays, nr, t[w], inst[w],
                                         &hits[w]);
                b[w] = frame_embree_batch(emb.top, rays, nr, erh);
            }
#endif
        }
        if (k >= 0)
            for (w = 0; w < worlds; w++) {
                up[w][k] = u[w];
                tr[w][k] = r[w];
                tb[w][k] = b[w];
                tot[w][k] = u[w] + r[w];
            }
    }
    for (w = 1; w < FRAME_OURS; w++)
        same += frame_differ(t[0], inst[0], t[w], inst[w], nr, &most);
    printf("### A game's frame\n\n");
    printf("%d skinned characters (tubes of %zu triangles, %zu float "
           "vertices, bent and swelling every frame by the game's skinning), "
           "each in a child scene of its own placed by an instance that "
           "walks, and %d instances of a 96-triangle prop, all moving every "
           "frame.  Update + commit: the %d instances' transforms set, the "
           "%d meshes' positions updated (ours: ray_scene_update_mesh from "
           "the float buffers; Embree: the same buffers shared, "
           "rtcUpdateGeometryBuffer), the %d child scenes and the top scene "
           "committed (Embree: refit, top level LOW).  Rays: %zu incoherent "
           "rays (origins uniform in the scene's box, directions uniform, "
           "fixed seed), nearest hit, one thread: one at a time "
           "(ray_intersect; rtcIntersect1) or as a batch (ray_intersect_batch; "
           "rtcIntersect1M).  Median of %d frames after %d warm-up frames, "
           "each way in turn frame by frame; total: the median of the "
           "frames' update + commit + rays one at a time.\n\n",
           FRAME_CHARS, nt, nv, FRAME_PROPS, FRAME_PROPS + FRAME_CHARS,
           FRAME_CHARS, FRAME_CHARS, nr, n, FRAME_WARM);
    printf("| per frame | update + commit ms | rays ms, one at a time | "
           "total ms | rays ms, batch | rays that hit |\n"
           "|---|---|---|---|---|---|\n");
    for (w = 0; w < worlds; w++) {
        up[w][0] = median(up[w], n);
        tr[w][0] = median(tr[w], n);
        tb[w][0] = median(tb[w], n);
        tot[w][0] = median(tot[w], n);
        printf("| %s | %.2f | %.1f | %.1f | %.1f | %zu |\n", name[w],
               1e3 * up[w][0], 1e3 * tr[w][0], 1e3 * tot[w][0],
               1e3 * tb[w][0], hits[w]);
    }
#ifdef HAVE_EMBREE
    static const char *const ratio[FRAME_OURS] = {
        "ours (one thread) / Embree", "ours (2 build threads) / Embree",
        "ours (2 game threads) / Embree"};

    for (w = 0; w < FRAME_OURS; w++)
        printf("| %s | %.2f | %.2f | %.2f | %.2f | |\n", ratio[w],
               up[w][0] / up[FRAME_OURS][0], tr[w][0] / tr[FRAME_OURS][0],
               tot[w][0] / tot[FRAME_OURS][0], tb[w][0] / tb[FRAME_OURS][0]);
    d = frame_differ(t[0], inst[0], t[FRAME_OURS], inst[FRAME_OURS], nr,
                     &most);
    printf("\nThe same geometry: of the last frame's %zu rays, %zu differ "
           "between ours and Embree (a hit against a miss, another "
           "instance, or hits more than 1e-4 apart in a scene 20 across: "
           "Embree's float transforms, about 1e-6 off at 18 units, move a "
           "hit by that over the cosine of its angle, so only hits within "
           "about half a degree of grazing could differ; the largest "
           "difference in t of the others: %.1e), %zu between ours' three "
           "ways (the same trees).\n\n", nr, d, most, same);
    frame_embree_free(&emb);
    free(erh);
#else
    (void)d;
    printf("\nOurs' three ways differ on %zu of the last frame's %zu rays "
           "(the same trees).\n\n", same, nr);
#endif
    for (w = 0; w < FRAME_OURS; w++)
        frame_ours_free(&ours[w]);
    for (w = 0; w < FRAME_WORLDS; w++) {
        free(t[w]);
        free(inst[w]);
    }
    for (c = 0; c < FRAME_CHARS; c++)
        free(cv[c]);
    free(cidx);
    free(pidx);
    free(rays);
    free(bh);
    free(res);
}

int main(int argc, char **argv)
{
    const char *dir = argc > 1 ? argv[1] : "data";
    int level = bench_level(), quick = level != BENCH_FULL;
    unsigned res = level == BENCH_SMOKE ? 8u : quick ? 256u : 512u;
    obj_mesh mid;

    reps = level == BENCH_SMOKE ? 1 : quick ? 3 : REPS;
    /* game DATA_DIR frame: the frame's table alone (perf record);
    ** game DATA_DIR instances: the instances' row alone (callgrind). */
    if (argc > 2 && strcmp(argv[2], "frame") == 0) {
        frame_row(quick);
        return 0;
    }
    mid = load(dir, "bunny-2.obj");
    if (argc > 2 && strcmp(argv[2], "instances") == 0) {
        instances_row(&mid, res);
        obj_free(&mid);
        return 0;
    }
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
           "ray_scene_commit, the refits in a row as a game's frames make "
           "them (ours and Embree's in turn), the rebuilds after.  BVH "
           "rebuild: the same mesh's triangle BVH built "
           "again (disabled and enabled, then committed).  New scene: what a "
           "program without updates does, ray_scene_new, ray_scene_add_mesh "
           "and ray_scene_commit.\n\n");
    printf("| mesh | triangles | refit ms | BVH rebuild ms | rebuild / refit | "
           "new scene ms | new scene / refit | "
           "Embree rebuild ms | Embree refit ms, one thread | "
           "ours / Embree (refit, one thread) | "
           "refit ms, ours on 2 threads | Embree refit ms, its pool | "
           "ours on 2 / Embree on its pool (refit) |\n"
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    refit_row("bunny-2", &mid);
    if (!quick) {
        obj_mesh big = load(dir, "bunny-4.obj");
        refit_row("bunny-4", &big);
        obj_free(&big);
    }
    printf("\n### Instances\n\n| what | ours | Embree | ours / Embree |\n"
           "|---|---|---|---|\n");
    instances_row(&mid, res);
    printf("### Gates on the query path (bunny-2, %ux%u camera rays)\n\n",
           res, res);
    gates_rows(&mid, res);
    obj_free(&mid);
    frame_row(quick);
    return 0;
}
