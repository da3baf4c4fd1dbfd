/* SPDX-License-Identifier: MIT */
/*
** mesh.c -- BVH benchmark on the Stanford bunny (scripts/fetch-bunny.sh):
** build time, primary-ray and incoherent-ray throughput at 1 thread and
** all threads, bytes per triangle, the BVH against brute force on the
** small bunny, and -- when built with Embree (HAVE_EMBREE) -- the same
** rays through Embree's rtcIntersect1/rtcOccluded1 in the same run, with
** throughput ratios and agreement.  Prints Markdown; asserts nothing.
**
**     mesh DATA_DIR          (bunny.obj, bunny-2.obj, bunny-4.obj)
**
** Method: every timing is the median of REPS runs after one warm-up run;
** ours and Embree's alternate within each repetition, so a noisy
** neighbour hits both, and the ratio is the median of the repetitions'
** own ratios (each of two runs next to each other in time), which a slow
** spell of the shared machine moves less than a ratio of two medians.
** BENCH_QUICK=1: 256 x 256 rays, fewer repetitions, and the 940k mesh
** skipped.
**
** The build is timed twice against Embree's: at one thread (ours by
** default; Embree on a device made with "threads=1", at
** RTC_BUILD_QUALITY_MEDIUM, its default quality) and at all threads
** (ours with ray_scene_set_build_threads(s, 0); Embree's default device,
** its thread pool over every CPU).  Only one Embree device lives at a
** time: Embree's thread pool is shared by its devices and sized for the
** largest count any live one asked for, so a "threads=1" device beside a
** default one builds on every CPU.  The instruction sets each side ran
** are printed first: ours by the rule intersect.c picks its copy of the
** queries with, Embree's from its own verbose output.
*/
#include <pthread.h>
#include <sys/resource.h>
#include <unistd.h>

#include "bench.h"
#include "obj.h"
#include "common.h"

#include "embree.h"
#include "query/query.h"          /* RAY__AVX2_COPY: is there an AVX2 copy? */

static int reps = 5;

/* ------------------------------------------------------------ rays */

typedef struct ray_set {
    ray_ray *rays;
    size_t n;
    int occlusion;           /* any-hit queries (shadow-style) */
} ray_set;

/* Results of one pass: hit flag, t, primitive per ray. */
typedef struct results {
    unsigned char *hit;
    double *t;
    unsigned *prim;
} results;

static void results_alloc(results *r, size_t n)
{
    r->hit = calloc(n, 1);
    r->t = calloc(n, sizeof *r->t);
    r->prim = calloc(n, sizeof *r->prim);
    if (r->hit == NULL || r->t == NULL || r->prim == NULL) {
        fprintf(stderr, "bench: out of memory\n");
        exit(1);
    }
}

static void results_free(results *r)
{
    free(r->hit);
    free(r->t);
    free(r->prim);
}

/* Camera on +z at dist * diag from the centre, 45 degrees, res x res. */
static ray_set primary_rays(ray_vec3 centre, double diag, double dist,
                            unsigned res)
{
    ray_set s;
    unsigned x, y;

    s.n = (size_t)res * res;
    s.occlusion = 0;
    s.rays = malloc(s.n * sizeof *s.rays);
    if (s.rays == NULL)
        exit(1);
    for (y = 0; y < res; y++)
        for (x = 0; x < res; x++)
            s.rays[(size_t)y * res + x] =
                bench_camera_ray(centre, diag, dist, res, x, y);
    return s;
}

/*
** Incoherent rays: from each primary hit, a direction drawn from the
** cosine distribution about the normal on the side the ray came from
** (Malley's method: a uniform disk sample lifted to the hemisphere),
** origin offset by ray_spawn.  Shadow-style (any-hit) if occlusion.
**
** ray_spawn's offset is scaled to our double hit point's error (~1e-15
** here); Embree works in float and has no such offset, so from the same
** origin it re-hits the surface the ray leaves at t ~ 1e-7.  To compare
** like with like, both engines get tmin = 1e-5 diagonals (about 100 float
** ulps of the coordinates): hits closer than that are ignored by both.
*/
static ray_set secondary_rays(const ray_scene *scene, const ray_set *prim,
                              int occlusion, double diag)
{
    ray_set s;
    size_t i;
    rng g = {12345};

    s.rays = malloc(prim->n * sizeof *s.rays);
    s.n = 0;
    s.occlusion = occlusion;
    if (s.rays == NULL)
        exit(1);
    for (i = 0; i < prim->n; i++) {
        ray_hit h;
        ray_vec3 n, d;
        double u1, u2;
        if (!ray_intersect(scene, &prim->rays[i], &h, NULL))
            continue;
        n = h.n;
        if (n.x * prim->rays[i].dir.x + n.y * prim->rays[i].dir.y +
            n.z * prim->rays[i].dir.z > 0)
            n = vec(-n.x, -n.y, -n.z);
        u1 = rng_unit(&g);
        u2 = rng_unit(&g);
        d = bench_cosine_dir(n, u1, u2);
        if (ray_spawn(&h, d, &s.rays[s.n]) == RAY_OK) {
            s.rays[s.n].tmin = 1e-5 * diag;
            s.n++;
        }
    }
    return s;
}

/* ------------------------------------------------------------ tracing */

typedef struct job {
    const ray_set *set;
    results *out;
    void *engine;            /* ray_scene or RTCScene */
    int embree;
    pthread_mutex_t lock;
    size_t next;
} job;

#define CHUNK 4096

#ifdef HAVE_EMBREE
static void embree_trace(RTCScene scene, const ray_ray *r, int occlusion,
                         results *out, size_t i)
{
    if (occlusion) {
        out->hit[i] = (unsigned char)embree_occluded(scene, r);
    } else {
        float t;
        out->hit[i] = (unsigned char)embree_hit(scene, r, &t,
                                                &out->prim[i]);
        out->t[i] = t;
    }
}
#endif

static void *trace_worker(void *arg)
{
    job *j = arg;
    for (;;) {
        size_t begin, end, i;
        pthread_mutex_lock(&j->lock);
        begin = j->next;
        j->next += CHUNK;
        pthread_mutex_unlock(&j->lock);
        if (begin >= j->set->n)
            return NULL;
        end = begin + CHUNK < j->set->n ? begin + CHUNK : j->set->n;
        for (i = begin; i < end; i++) {
            const ray_ray *r = &j->set->rays[i];
#ifdef HAVE_EMBREE
            if (j->embree) {
                embree_trace((RTCScene)j->engine, r, j->set->occlusion,
                             j->out, i);
                continue;
            }
#endif
            if (j->set->occlusion)
                j->out->hit[i] = (unsigned char)ray_occluded(j->engine, r,
                                                             NULL);
            else {
                ray_hit h;
                j->out->hit[i] = (unsigned char)ray_intersect(j->engine, r,
                                                              &h, NULL);
                if (j->out->hit[i]) {
                    j->out->t[i] = h.t;
                    j->out->prim[i] = h.prim_id;
                }
            }
        }
    }
}

/* Trace the set with "threads" threads; returns seconds. */
static double trace_all(void *engine, int embree, const ray_set *set,
                        results *out, unsigned threads)
{
    pthread_t tid[256];
    job j;
    unsigned k;
    double t;

    j.set = set;
    j.out = out;
    j.engine = engine;
    j.embree = embree;
    j.next = 0;
    pthread_mutex_init(&j.lock, NULL);
    t = now_seconds();
    for (k = 1; k < threads; k++)
        pthread_create(&tid[k], NULL, trace_worker, &j);
    trace_worker(&j);
    for (k = 1; k < threads; k++)
        pthread_join(tid[k], NULL);
    t = now_seconds() - t;
    pthread_mutex_destroy(&j.lock);
    return t;
}

/* Our scene of the mesh, built on "threads" threads (0: all CPUs);
** *build_s: the commit (BVH build) time. */
static ray_scene *our_scene_on(const obj_mesh *obj, counting *cnt,
                               double *build_s, int watertight,
                               unsigned threads)
{
    ray_mesh mesh = obj_as_ray_mesh(obj);
    ray_scene *s;
    double t;

    /* cnt NULL: the library's own allocator, as a program that passes
    ** none gets (the build rows' timed runs). */
    check(nop_scene_new(&s, cnt != NULL ? counting_alloc : NULL, cnt),
          "nop_scene_new");
    check(ray_scene_add_mesh(s, &mesh, 0, NULL), "mesh");
    check(ray_scene_set_watertight(s, watertight), "watertight");
    check(ray_scene_set_build_threads(s, threads), "build threads");
    t = now_seconds();
    check(ray_scene_commit(s), "commit");
    *build_s = now_seconds() - t;
    return s;
}

/* The same, built on one thread (the default). */
static ray_scene *our_scene(const obj_mesh *obj, counting *cnt,
                            double *build_s, int watertight)
{
    return our_scene_on(obj, cnt, build_s, watertight, 1);
}

#ifdef HAVE_EMBREE
/* Embree's scene of the same mesh (float vertices: Embree's format). */
static RTCScene embree_scene(RTCDevice dev, const obj_mesh *obj,
                             double *build_s)
{
    RTCScene scene = rtcNewScene(dev);
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *v = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0,
                                       RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                       obj->vertex_count);
    unsigned *idx = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0,
                                            RTC_FORMAT_UINT3,
                                            3 * sizeof(unsigned),
                                            obj->triangle_count);
    size_t i;
    double t;

    for (i = 0; i < obj->vertex_count; i++) {
        v[3 * i] = (float)obj->vertices[i].x;
        v[3 * i + 1] = (float)obj->vertices[i].y;
        v[3 * i + 2] = (float)obj->vertices[i].z;
    }
    memcpy(idx, obj->indices, 3 * obj->triangle_count * sizeof *idx);
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    /* Its default, said explicitly: the quality the one-thread row names. */
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_MEDIUM);
    t = now_seconds();
    rtcCommitScene(scene);
    *build_s = now_seconds() - t;
    return scene;
}
#endif

/* ------------------------------------------------------------ report */

static void bbox(const obj_mesh *obj, ray_vec3 *centre, double *diag)
{
    ray_vec3 lo, hi;

    obj_bounds(obj, &lo, &hi, centre, diag);
}

/* Median seconds to trace "set" on one thread with scene s. */
static double one_thread(ray_scene *s, const ray_set *set, results *r)
{
    double t[9];
    int k;

    trace_all(s, 0, set, r, 1);
    for (k = 0; k < reps; k++)
        t[k] = trace_all(s, 0, set, r, 1);
    return median(t, reps);
}

/* The default watertight triangle test against Cramer's rule (the fast
** path, ray_scene_set_watertight(s, 0)) inside whole traversals. */
static void triangle_test_cost(const obj_mesh *obj, const ray_set *primary,
                               const ray_set *incoherent)
{
    counting c1 = {0, 0}, c2 = {0, 0};
    double b;
    ray_scene *wt = our_scene(obj, &c1, &b, 1), *cr = our_scene(obj, &c2, &b, 0);
    results r;
    double pw, pc, iw, ic;

    results_alloc(&r, primary->n);
    pw = one_thread(wt, primary, &r);
    pc = one_thread(cr, primary, &r);
    iw = one_thread(wt, incoherent, &r);
    ic = one_thread(cr, incoherent, &r);
    printf("Triangle test inside the traversal, one thread: primary rays "
           "(1.0 diagonal) %.2f Mrays/s watertight, %.2f Cramer (ratio "
           "%.2f); incoherent rays %.2f watertight, %.2f Cramer (ratio "
           "%.2f).\n\n", (double)primary->n / pw / 1e6,
           (double)primary->n / pc / 1e6, pw / pc,
           (double)incoherent->n / iw / 1e6, (double)incoherent->n / ic / 1e6,
           iw / ic);
    results_free(&r);
    ray_scene_free(wt);
    ray_scene_free(cr);
}

/* Fraction of rays with the same hit/miss and (closest-hit) primitive;
** the largest relative difference of t among rays both hit. */
static void agreement(const ray_set *set, const results *a, const results *b,
                      double *same, double *t_rel)
{
    size_t i, agree = 0;
    double worst = 0;

    for (i = 0; i < set->n; i++) {
        int ok = a->hit[i] == b->hit[i];
        if (ok && a->hit[i] && !set->occlusion) {
            double d = fabs(a->t[i] - b->t[i]) / fmax(fabs(a->t[i]), 1e-30);
            ok = a->prim[i] == b->prim[i];
            if (d > worst)
                worst = d;
        }
        agree += (size_t)ok;
    }
    *same = (double)agree / (double)set->n;
    *t_rel = worst;
}

static void run_set(const char *name, ray_scene *ours, void *embree,
                    const ray_set *set, unsigned threads)
{
    double t_ours[9], t_emb[9], ratio[9], mo, me = 0, same = 0, t_rel = 0;
    results ro, re;
    int k;

    results_alloc(&ro, set->n);
    results_alloc(&re, set->n);
    trace_all(ours, 0, set, &ro, threads);               /* warm-up */
#ifdef HAVE_EMBREE
    trace_all(embree, 1, set, &re, threads);
#else
    (void)embree;
#endif
    for (k = 0; k < reps; k++) {
        t_ours[k] = trace_all(ours, 0, set, &ro, threads);
#ifdef HAVE_EMBREE
        t_emb[k] = trace_all(embree, 1, set, &re, threads);
#else
        t_emb[k] = 0;
#endif
        ratio[k] = t_emb[k] / t_ours[k];
    }
    mo = median(t_ours, reps);
#ifdef HAVE_EMBREE
    me = median(t_emb, reps);
    agreement(set, &ro, &re, &same, &t_rel);
    printf("| %s | %u | %zu | %.2f | %.2f | %.2f | %.4f%% | %.1e |\n", name,
           threads, set->n, (double)set->n / mo / 1e6,
           (double)set->n / me / 1e6, median(ratio, reps),
           100 * same, t_rel);
#else
    (void)me;
    (void)t_emb;
    (void)ratio;
    (void)same;
    (void)t_rel;
    (void)agreement;
    printf("| %s | %u | %zu | %.2f | - | - | - | - |\n", name, threads,
           set->n, (double)set->n / mo / 1e6);
#endif
    results_free(&ro);
    results_free(&re);
}

/*
** The build, timed as the header says: for each row a warm-up, then reps
** repetitions of ours and Embree's in turn; medians of each side and of
** the repetitions' own ratios.  Then our memory after commit and at its
** peak (the tree, and so its memory, is the same at any thread count),
** counted in the warm-up through an allocator that counts (libc's
** realloc behind it); the timed runs build on the library's own, as a
** program that passes none does and as Embree builds on its own: the
** counting one took 15-20% longer at 940k triangles (its large blocks
** not on whole huge pages, src/scene/store.c).
*/
static void bench_build(const obj_mesh *obj, unsigned cpus)
{
    static const char *const row[2] = {
        "one thread (Embree: device \"threads=1\", "
        "RTC_BUILD_QUALITY_MEDIUM)",
        "all threads (ours: ray_scene_set_build_threads 0; Embree: its "
        "default device)"};
    counting cnt = {0, 0};
    long long kept = 0, peak = 0;
    int mode, k;

    printf("| BVH build | threads | ours ms | Embree ms | ours / Embree |\n");
    printf("|---|---|---|---|---|\n");
    for (mode = 0; mode < 2; mode++) {
        double ours[9], emb[9], ratio[9];
#ifdef HAVE_EMBREE
        RTCDevice dev = rtcNewDevice(mode == 0 ? "threads=1" : NULL);
#endif
        for (k = -1; k < reps; k++) {
            double to, te = 0;
            ray_scene *s;
            /* The warm-up counts the memory, through an allocator that
            ** counts (libc's realloc); the timed runs build on the
            ** library's own, as Embree's on its own. */
            cnt.now = cnt.peak = 0;
            s = our_scene_on(obj, k < 0 ? &cnt : NULL, &to, 1,
                             mode == 0 ? 1 : 0);
            if (k < 0) {
                kept = cnt.now;
                peak = cnt.peak;
            }
            ray_scene_free(s);
#ifdef HAVE_EMBREE
            rtcReleaseScene(embree_scene(dev, obj, &te));
#endif
            if (k < 0)
                continue;              /* the warm-up */
            ours[k] = to;
            emb[k] = te;
            ratio[k] = te > 0 ? to / te : 0;
        }
#ifdef HAVE_EMBREE
        rtcReleaseDevice(dev);
        printf("| %s | %u | %.1f | %.1f | %.2f |\n", row[mode],
               mode == 0 ? 1 : cpus, 1e3 * median(ours, reps),
               1e3 * median(emb, reps), median(ratio, reps));
#else
        (void)emb;
        (void)ratio;
        printf("| %s | %u | %.1f | - | - |\n", row[mode],
               mode == 0 ? 1 : cpus, 1e3 * median(ours, reps));
#endif
    }
    printf("\nMemory after commit %.1f bytes/triangle, peak %.1f during "
           "commit\n", (double)kept / (double)obj->triangle_count,
           (double)peak / (double)obj->triangle_count);
}

/* The minor page faults of this process so far (pages first touched). */
static long minor_faults(void)
{
    struct rusage u;

    return getrusage(RUSAGE_SELF, &u) == 0 ? u.ru_minflt : 0;
}

/*
** The cold build, as a program that loads a level makes it: a fresh
** scene each time, from ray_scene_new and ray_scene_add_mesh (which
** copies the mesh) to ray_scene_commit, three in a row, on one thread
** (Embree: rtcNewScene, a new geometry with its buffers filled, the
** commit, on a "threads=1" device, RTC_BUILD_QUALITY_MEDIUM), each
** scene freed before the next, with the minor page faults each side
** takes (pages touched for the first time: fresh memory from the
** system).  The build row above times the commit alone, after a
** warm-up: the difference between the two is the copy and the fresh
** memory's faults (issue 27).
*/
static void bench_cold(const obj_mesh *obj)
{
    double ours[9], emb[9], ratio[9];
    long f_ours = 0, f_emb = 0;
    int k;
#ifdef HAVE_EMBREE
    RTCDevice dev = rtcNewDevice("threads=1");
#endif

    for (k = 0; k < 3; k++) {
        ray_mesh mesh = obj_as_ray_mesh(obj);
        long f0 = minor_faults();
        double t = now_seconds(), te = 0;
        ray_scene *s;
        check(ray_scene_new(&s, NULL, NULL), "ray_scene_new");
        check(ray_scene_add_mesh(s, &mesh, RAY_NO_MATERIAL, NULL), "mesh");
        check(ray_scene_commit(s), "commit");
        ours[k] = now_seconds() - t;
        f_ours += minor_faults() - f0;
        ray_scene_free(s);
#ifdef HAVE_EMBREE
        f0 = minor_faults();
        t = now_seconds();
        rtcReleaseScene(embree_scene(dev, obj, &te));
        emb[k] = now_seconds() - t;
        f_emb += minor_faults() - f0;
#endif
        (void)te;
        ratio[k] = emb[k] > 0 ? ours[k] / emb[k] : 0;
    }
#ifdef HAVE_EMBREE
    rtcReleaseDevice(dev);
    printf("\nCold build, one thread, three fresh scenes in a row (new "
           "scene, add the mesh, commit; freed after): ours %.1f ms, "
           "Embree %.1f ms (median), ours / Embree %.2f; minor page "
           "faults, the three together: ours %ld, Embree %ld\n",
           1e3 * median(ours, 3), 1e3 * median(emb, 3), median(ratio, 3),
           f_ours, f_emb);
#else
    (void)emb;
    (void)ratio;
    (void)f_emb;
    printf("\nCold build, one thread, three fresh scenes in a row (new "
           "scene, add the mesh, commit; freed after): ours %.1f ms "
           "(median); minor page faults, the three together: ours %ld\n",
           1e3 * median(ours, 3), f_ours);
#endif
}

static void bench_mesh(const char *path, unsigned res, unsigned cpus)
{
    obj_mesh obj;
    char err[600];
    counting cnt = {0, 0};
    double b, diag;
    ray_scene *ours = NULL;
    void *emb = NULL;
    ray_vec3 centre;
    ray_set far, near, diffuse, shadow;
#ifdef HAVE_EMBREE
    RTCDevice device;
#endif

    if (obj_load(path, &obj, err, sizeof err) != 0) {
        printf("(skipped: %s)\n\n", err);
        return;
    }
    printf("### %s: %zu triangles\n\n", path, obj.triangle_count);
    bench_build(&obj, cpus);
    bench_cold(&obj);
    ours = our_scene(&obj, &cnt, &b, 1);
#ifdef HAVE_EMBREE
    device = rtcNewDevice(NULL);
    emb = embree_scene(device, &obj, &b);
#endif
    printf("\n| rays | threads | count | ours Mrays/s | Embree Mrays/s | "
           "ours / Embree | same hit and primitive | max rel. t diff |\n");
    printf("|---|---|---|---|---|---|---|---|\n");
    bbox(&obj, &centre, &diag);
    far = primary_rays(centre, diag, 2.5, res);
    near = primary_rays(centre, diag, 1.0, res);
    diffuse = secondary_rays(ours, &near, 0, diag);
    shadow = secondary_rays(ours, &near, 1, diag);
    run_set("primary, 2.5 diagonals", ours, emb, &far, 1);
    run_set("primary, 2.5 diagonals", ours, emb, &far, cpus);
    run_set("primary, 1.0 diagonal", ours, emb, &near, 1);
    run_set("primary, 1.0 diagonal", ours, emb, &near, cpus);
    run_set("incoherent (cosine), closest", ours, emb, &diffuse, 1);
    run_set("incoherent (cosine), closest", ours, emb, &diffuse, cpus);
    run_set("incoherent (cosine), any-hit", ours, emb, &shadow, 1);
    run_set("incoherent (cosine), any-hit", ours, emb, &shadow, cpus);
    printf("\n");
    triangle_test_cost(&obj, &near, &diffuse);
    free(far.rays);
    free(near.rays);
    free(diffuse.rays);
    free(shadow.rays);
    ray_scene_free(ours);
#ifdef HAVE_EMBREE
    rtcReleaseScene((RTCScene)emb);
    rtcReleaseDevice(device);
#endif
    obj_free(&obj);
}

/* The BVH against testing every triangle, on the small bunny. */
static void bench_brute(const char *path)
{
    obj_mesh obj;
    char err[600];
    counting cnt = {0, 0};
    double b, diag, t_bvh[9], t_brute[9];
    ray_scene *ours;
    ray_vec3 centre;
    ray_set set;
    size_t i, j;
    int k;

    if (obj_load(path, &obj, err, sizeof err) != 0) {
        printf("(skipped: %s)\n\n", err);
        return;
    }
    ours = our_scene(&obj, &cnt, &b, 1);
    bbox(&obj, &centre, &diag);
    set = primary_rays(centre, diag, 1.0, 64);
    for (k = 0; k < reps; k++) {
        double t = now_seconds();
        for (i = 0; i < set.n; i++) {
            ray_hit h;
            ray_intersect(ours, &set.rays[i], &h, NULL);
        }
        t_bvh[k] = now_seconds() - t;
        t = now_seconds();
        for (i = 0; i < set.n; i++) {
            ray_ray r = set.rays[i];
            ray_hit h;
            for (j = 0; j < obj.triangle_count; j++) {
                const unsigned *f = obj.indices + 3 * j;
                if (ray_triangle(&r, obj.vertices[f[0]], obj.vertices[f[1]],
                                 obj.vertices[f[2]], &h))
                    r.tmax = h.t;
            }
        }
        t_brute[k] = now_seconds() - t;
    }
    printf("BVH vs brute force (%s, %zu triangles, %zu primary rays at 1.0 "
           "diagonal): %.3g vs %.3g us per ray, BVH %.0fx faster\n\n", path,
           obj.triangle_count, set.n,
           1e6 * median(t_bvh, reps) / (double)set.n,
           1e6 * median(t_brute, reps) / (double)set.n,
           median(t_brute, reps) / median(t_bvh, reps));
    free(set.rays);
    ray_scene_free(ours);
    obj_free(&obj);
}

/*
** The nearest point of triangle (a, b, c) to q, Ericson's
** ClosestPtPointTriangle ("Real-Time Collision Detection", 5.1.5) as
** the book writes it: brute force's routine, for the baseline below.
*/
static ray_vec3 plain_closest(ray_vec3 q, ray_vec3 a, ray_vec3 b, ray_vec3 c)
{
    ray_vec3 ab = ray_vec3_sub(b, a), ac = ray_vec3_sub(c, a);
    ray_vec3 ap = ray_vec3_sub(q, a), bp = ray_vec3_sub(q, b);
    ray_vec3 cp = ray_vec3_sub(q, c);
    double d1 = ray_vec3_dot(ab, ap), d2 = ray_vec3_dot(ac, ap);
    double d3, d4, d5, d6, va, vb, vc, den;

    if (d1 <= 0 && d2 <= 0)
        return a;
    d3 = ray_vec3_dot(ab, bp);
    d4 = ray_vec3_dot(ac, bp);
    if (d3 >= 0 && d4 <= d3)
        return b;
    vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0)
        return ray_vec3_add(a, ray_vec3_scale(ab, d1 / (d1 - d3)));
    d5 = ray_vec3_dot(ab, cp);
    d6 = ray_vec3_dot(ac, cp);
    if (d6 >= 0 && d5 <= d6)
        return c;
    vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0)
        return ray_vec3_add(a, ray_vec3_scale(ac, d2 / (d2 - d6)));
    va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)
        return ray_vec3_add(b, ray_vec3_scale(ray_vec3_sub(c, b),
                                              (d4 - d3) /
                                                  ((d4 - d3) + (d5 - d6))));
    den = 1 / (va + vb + vc);
    return ray_vec3_add(a, ray_vec3_add(ray_vec3_scale(ab, vb * den),
                                        ray_vec3_scale(ac, vc * den)));
}

/*
** Closest-point queries (ray_closest_point, radius +Inf, one thread) at
** points uniform in the mesh's bounding box grown by a quarter of its
** diagonal on every side (inside the bunny, near it and around it),
** against brute force over every triangle on the first BRUTE of them,
** and the largest relative difference of the two distances there.
*/
static void bench_closest(const char *path)
{
    enum { N = 20000, BRUTE = 100 };
    obj_mesh obj;
    char err[600];
    counting cnt = {0, 0};
    double b, diag, t_bvh[9], t_brute[9], brute[BRUTE], worst = 0, sink = 0;
    ray_vec3 lo, hi, centre, *q;
    ray_scene *ours;
    size_t i, j;
    rng g = {2024};
    int k;

    if (obj_load(path, &obj, err, sizeof err) != 0) {
        printf("(skipped: %s)\n\n", err);
        return;
    }
    ours = our_scene(&obj, &cnt, &b, 1);
    obj_bounds(&obj, &lo, &hi, &centre, &diag);
    q = malloc(N * sizeof *q);
    if (q == NULL)
        exit(1);
    for (i = 0; i < N; i++)
        q[i] = ray_vec3_make(rng_range(&g, lo.x - diag / 4, hi.x + diag / 4),
                             rng_range(&g, lo.y - diag / 4, hi.y + diag / 4),
                             rng_range(&g, lo.z - diag / 4, hi.z + diag / 4));
    for (k = 0; k < reps; k++) {
        double t = now_seconds();
        for (i = 0; i < N; i++) {
            ray_closest c;
            if (ray_closest_point(ours, q[i], HUGE_VAL, &c) > 0)
                sink += c.distance;
        }
        t_bvh[k] = now_seconds() - t;
        t = now_seconds();
        for (i = 0; i < BRUTE; i++) {
            double best = HUGE_VAL;
            for (j = 0; j < obj.triangle_count; j++) {
                const unsigned *f = obj.indices + 3 * j;
                ray_vec3 p = plain_closest(q[i], obj.vertices[f[0]],
                                           obj.vertices[f[1]],
                                           obj.vertices[f[2]]);
                double d = sqrt(ray_vec3_dot(ray_vec3_sub(p, q[i]),
                                             ray_vec3_sub(p, q[i])));
                best = d < best ? d : best;
            }
            brute[i] = best;
        }
        t_brute[k] = now_seconds() - t;
    }
    for (i = 0; i < BRUTE; i++) {
        ray_closest c;
        if (ray_closest_point(ours, q[i], HUGE_VAL, &c) > 0 &&
            fabs(c.distance - brute[i]) / brute[i] > worst)
            worst = fabs(c.distance - brute[i]) / brute[i];
    }
    printf("Closest points (ray_closest_point, %s, %zu triangles, one "
           "thread, %d points in the box grown by a quarter diagonal): "
           "%.3g us per query (%.0f thousand a second); brute force over "
           "every triangle %.3g us, BVH %.0fx faster; largest relative "
           "difference of the distances %.1e%s\n\n", path,
           obj.triangle_count, N, 1e6 * median(t_bvh, reps) / N,
           N / median(t_bvh, reps) / 1e3,
           1e6 * median(t_brute, reps) / BRUTE,
           (median(t_brute, reps) / BRUTE) / (median(t_bvh, reps) / N),
           worst, sink > 0 ? "" : " (no answers)");
    free(q);
    ray_scene_free(ours);
    obj_free(&obj);
}

/* Bytes per triangle on the million-triangle grid of the memory test
** (tests/check_bvh.c), which ray.h quotes: deterministic, timed not. */
static void bench_grid_memory(void)
{
    const unsigned N = bench_level() == BENCH_SMOKE ? 8 : 724;
    counting cnt = {0, 0};
    ray_vec3 *v;
    unsigned *idx;
    ray_mesh mesh;
    ray_scene *s = NULL;   /* -O1 cannot see that check() exits */
    long long base;

    if (grid_mesh(N, &mesh, &v, &idx) != 0) {
        printf("(grid memory skipped: out of memory)\n\n");
        return;
    }
    check(nop_scene_new(&s, counting_alloc, &cnt), "nop_scene_new");
    base = cnt.now;
    check(ray_scene_add_mesh(s, &mesh, 0, NULL), "mesh");
    cnt.peak = cnt.now;
    check(ray_scene_commit(s), "commit");
    printf("Memory on a %u x %u grid (%zu triangles, the test's mesh): after "
           "commit %.1f bytes/triangle, peak %.1f during commit\n\n", N, N,
           mesh.triangle_count,
           (double)(cnt.now - base) / (double)mesh.triangle_count,
           (double)(cnt.peak - base) / (double)mesh.triangle_count);
    ray_scene_free(s);
    free(v);
    free(idx);
}

#ifdef HAVE_EMBREE
/* The text of "line" after "key" up to "stop" (or the line's end, less
** its newline) into out; 0 if key is not in the line. */
static int field_after(const char *line, const char *key, const char *stop,
                       char *out, size_t size)
{
    const char *p = strstr(line, key), *end;
    size_t n;

    if (p == NULL)
        return 0;
    p += strlen(key);
    while (*p == ' ')
        p++;
    end = stop != NULL ? strstr(p, stop) : NULL;
    if (end == NULL)
        end = p + strcspn(p, "\n");
    while (end > p && end[-1] == ' ')
        end--;
    n = (size_t)(end - p) < size - 1 ? (size_t)(end - p) : size - 1;
    memcpy(out, p, n);
    out[n] = '\0';
    return 1;
}

/*
** Embree's instruction sets, as Embree itself reports them: a device made
** with "verbose=3" prints on stdout, when it builds a scene, the builder
** it selected and its intersectors, each named after the ISA its code was
** compiled for ("avx::BVH8BuilderSAH", "avx512::BVH8Triangle4Intersector1
** Moeller"), and its compiled targets.  stdout goes to a temporary file
** meanwhile (fd 1 redirected, both sides of it flushed), then back.
*/
static void embree_isa(void)
{
    static const ray_vec3 v[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    static const unsigned idx[3] = {0, 1, 2};
    char path[] = "/tmp/bench-mesh-embree-XXXXXX", line[1024];
    char build[128] = "not reported", query[128] = "not reported";
    char targets[256] = "not reported";
    int fd = mkstemp(path), saved;
    FILE *f;

    if (fd < 0) {
        printf("Embree ISA: unknown (no temporary file for its report)\n\n");
        return;
    }
    fflush(stdout);
    saved = dup(1);
    if (saved >= 0 && dup2(fd, 1) >= 0) {
        RTCDevice d = rtcNewDevice("verbose=3");
        RTCScene sc = rtcNewScene(d);
        RTCGeometry g = embree_triangles(d, v, 3, idx, 1, NULL);
        rtcCommitGeometry(g);
        rtcAttachGeometry(sc, g);
        rtcReleaseGeometry(g);
        rtcCommitScene(sc);
        rtcReleaseScene(sc);
        rtcReleaseDevice(d);
        fflush(stdout);
        dup2(saved, 1);
    }
    if (saved >= 0)
        close(saved);
    f = fdopen(fd, "r");
    if (f != NULL) {
        rewind(f);
        while (fgets(line, sizeof line, f) != NULL) {
            if (strstr(line, "building ") != NULL)
                field_after(line, " using ", " ...", build, sizeof build);
            if (strstr(line, "intersector1 ") != NULL)
                field_after(line, "=", NULL, query, sizeof query);
            if (strstr(line, "(compile time enabled)") != NULL)
                field_after(line, "", "(compile", targets, sizeof targets);
        }
        fclose(f);
    } else
        close(fd);
    unlink(path);
    printf("Embree ISA (from its verbose report): rtcIntersect1 %s; build %s; "
           "compiled for %s\n\n", query, build, targets);
}
#endif

/*
** The instruction sets each side ran.  Ours: intersect.c runs the AVX2
** copy of the queries when there is one and the CPU has AVX2 (this is
** its rule: RAY__AVX2_COPY and __builtin_cpu_supports), else the
** baseline; the build bins with SSE2 unless built with RAY_NO_SIMD; no
** code of ours uses AVX-512, which the CPU's line says whether it has.
*/
static void print_isa(void)
{
    int avx2 = 0, avx512 = 0;

#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
    avx2 = __builtin_cpu_supports("avx2") != 0;
    avx512 = __builtin_cpu_supports("avx512f") != 0;
#endif
    printf("ISA: the CPU has AVX2 %s, AVX-512F %s; libray's queries ran "
           "%s, its build binned with %s (libray has no AVX-512 code)\n\n",
           avx2 ? "yes" : "no", avx512 ? "yes" : "no",
           RAY__AVX2_COPY && avx2 ? "the AVX2 copy (intersect_avx2.c)"
                                  : "the baseline copy",
#if defined(__SSE2__) && !defined(RAY_NO_SIMD)
           "SSE2"
#else
           "portable C"
#endif
    );
#ifdef HAVE_EMBREE
    embree_isa();
#endif
}

int main(int argc, char **argv)
{
    const char *dir = argc > 1 ? argv[1] : "data";
    int level = bench_level(), quick = level != BENCH_FULL;
    unsigned res = level == BENCH_SMOKE ? 8 : quick ? 256 : 1024;
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    unsigned cpus = n > 0 ? (n > 256 ? 256 : (unsigned)n) : 1;
    char path[512];

    reps = level == BENCH_SMOKE ? 1 : quick ? 3 : 5;
    /* mesh DATA_DIR build: the build and cold-build rows alone, of both
    ** bunnies (A/B runs of a build change). */
    if (argc > 2 && strcmp(argv[2], "build") == 0) {
        static const char *const name[2] = {"bunny-2.obj", "bunny-4.obj"};
        int i;
        for (i = 0; i < 2; i++) {
            obj_mesh obj;
            char err[600];
            snprintf(path, sizeof path, "%s/%s", dir, name[i]);
            if (obj_load(path, &obj, err, sizeof err) != 0) {
                printf("(skipped: %s)\n\n", err);
                continue;
            }
            printf("### %s: %zu triangles\n\n", path, obj.triangle_count);
            bench_build(&obj, cpus);
            bench_cold(&obj);
            printf("\n");
            obj_free(&obj);
        }
        return 0;
    }
    printf("## Meshes: the Stanford bunny, BVH vs %s\n\n",
#ifdef HAVE_EMBREE
           "Embree " RTC_VERSION_STRING " (rtcIntersect1 / rtcOccluded1, "
           "default scene flags, float)"
#else
           "brute force (Embree absent: install libembree-dev and rerun)"
#endif
    );
    printf("Rays: %ux%u, 1 per pixel, camera on +z at the given distance in "
           "bounding-box diagonals from the centre, 45 degree field of view; "
           "incoherent rays: cosine-distributed from the 1.0-diagonal hits. "
           "Median of %d runs (ours / Embree: median of the runs' own "
           "ratios, ours and Embree's alternating); %u CPUs.\n\n", res, res,
           reps, cpus);
    bench_grid_memory();
    print_isa();
    snprintf(path, sizeof path, "%s/bunny.obj", dir);
    bench_brute(path);
    snprintf(path, sizeof path, "%s/bunny-2.obj", dir);
    bench_closest(path);
    bench_mesh(path, res, cpus);
    if (!quick) {
        snprintf(path, sizeof path, "%s/bunny-4.obj", dir);
        bench_mesh(path, res, cpus);
    }
    return 0;
}
