/* SPDX-License-Identifier: MIT */
/*
** raycost.c -- what one query costs, in nanoseconds a ray, for libray's
** ray_intersect and ray_occluded, Embree's rtcIntersect1 / rtcOccluded1
** (HAVE_EMBREE) and tinybvh's BVH8_CPU (HAVE_TINYBVH: bench/tinybvh.cpp),
** on the same rays, one thread (issue 34's cost-per-ray table):
**
**   miss box    rays that pass beside the mesh's box: the fixed cost of
**               a query (set-up and the root node alone);
**   enter+miss  camera rays that enter the box and miss the mesh;
**   hit         camera rays that hit it;
**   ground      a game's ground query: rays straight down onto a
**               100 x 100 grid of 20,000 triangles, every one a hit;
**   shadow      any-hit rays from points on the mesh towards a light
**               above it (ray_occluded).
**
**     raycost DATA_DIR          (bunny-2.obj, the 59k bunny)
**
** Method as bench/mesh.c: each repetition times every tool on the whole
** ray set one after the other, so a noisy neighbour hits all; the figure
** is the median over REPS repetitions after a warm-up, and the ratios are
** medians of the repetitions' own ratios.  Directions are unit, so every
** tool reports the same t; the hit counts are printed to show that the
** tools agree.  Prints Markdown; asserts nothing.  BENCH_QUICK=1: fewer
** rays and repetitions; RAYCOST_TOOLS and RAYCOST_ROWS pick columns and
** rows (for A/B runs and profiles), RAYCOST_MESH another mesh of
** DATA_DIR than bunny-2.obj; RAYCOST_CPU_TIME=1 times by thread
** CPU time (a machine busy with others' work).  Built against the
** library's counted build (make bench-counts, -DRAY_BENCH_COUNTS), it
** prints instead the work of libray's queries per ray: nodes, leaves,
** triangles filtered, exact tests (issue 34).
**
** RAYCOST_AB=path/to/libray.so: another build of libray (a change's base,
** built in a worktree) as a fourth column, its scenes built the same way
** and its passes interleaved with the others', with its ratio to this
** build's: a change measured against its base in one run, so that a
** noisy machine slows both alike (POSIX only: dlopen).  A shared
** library runs a little slower than the static one linked here (position-
** independent code: up to a tenth on these rows), so for a fair A/B give
** this build's shared library too, as RAYCOST_AB_OURS: the libray column
** then runs that.
*/
#include <time.h>
#if defined(__unix__) && !defined(RAY_BENCH_COUNTS)
#define HAVE_AB 1
#include <dlfcn.h>
#endif

#include "bench.h"
#include "obj.h"
#include "embree.h"
#ifdef HAVE_TINYBVH
#include "tinybvh.h"
#endif

enum { TOOL_OURS, TOOL_EMBREE, TOOL_TINY, TOOL_AB, TOOLS };

#ifdef HAVE_AB
static void die(const char *what);

/* The other build's entry points (RAYCOST_AB). */
typedef struct ab_lib {
    int (*scene_new)(ray_scene **, ray_alloc_fn, void *);
    int (*add_material)(ray_scene *, const ray_material *, unsigned *);
    int (*add_mesh)(ray_scene *, const ray_mesh *, unsigned, unsigned *);
    int (*commit)(ray_scene *);
    void (*scene_free)(ray_scene *);
    int (*intersect)(const ray_scene *, const ray_ray *, ray_hit *,
                     ray_stats *);
    int (*occluded)(const ray_scene *, const ray_ray *, ray_stats *);
} ab_lib;

static ab_lib ab[2];         /* RAYCOST_AB's, RAYCOST_AB_OURS's */

/* Library k's entry points from "path" (k: 0 RAYCOST_AB's, 1
** RAYCOST_AB_OURS's).  RTLD_DEEPBIND: its calls to its own public
** functions stay inside it. */
static void ab_open(int k, const char *path)
{
    ab_lib *l = &ab[k];
    void *h = dlopen(path, RTLD_NOW | RTLD_LOCAL | RTLD_DEEPBIND);

    if (h == NULL) {
        fprintf(stderr, "raycost: %s: %s\n", path, dlerror());
        exit(1);
    }
    *(void **)&l->scene_new = dlsym(h, "ray_scene_new");
    *(void **)&l->add_material = dlsym(h, "ray_scene_add_material");
    *(void **)&l->add_mesh = dlsym(h, "ray_scene_add_mesh");
    *(void **)&l->commit = dlsym(h, "ray_scene_commit");
    *(void **)&l->scene_free = dlsym(h, "ray_scene_free");
    *(void **)&l->intersect = dlsym(h, "ray_intersect");
    *(void **)&l->occluded = dlsym(h, "ray_occluded");
    if (!l->scene_new || !l->add_material || !l->add_mesh || !l->commit ||
        !l->scene_free || !l->intersect || !l->occluded) {
        fprintf(stderr, "raycost: %s: not a libray\n", path);
        exit(1);
    }
}

/* Load the libraries asked for: bit 0 set if RAYCOST_AB's is loaded,
** bit 1 if RAYCOST_AB_OURS's is. */
static int ab_load(void)
{
    static int state = -1;
    const char *path, *ours;

    if (state >= 0)                 /* asked once a ray: no getenv then */
        return state;
    path = getenv("RAYCOST_AB");
    ours = getenv("RAYCOST_AB_OURS");
    state = 0;
    if (path != NULL) {
        ab_open(0, path);
        state |= 1;
    }
    if (ours != NULL) {
        ab_open(1, ours);
        state |= 2;
    }
    return state;
}

/* Library k's scene of mesh m. */
static ray_scene *ab_scene(int k, const ray_mesh *m)
{
    ray_material mat = plain();
    ray_scene *s;

    if (ab[k].scene_new(&s, NULL, NULL) != RAY_OK ||
        ab[k].add_material(s, &mat, NULL) != RAY_OK ||
        ab[k].add_mesh(s, m, 0, NULL) != RAY_OK || ab[k].commit(s) != RAY_OK)
        die("RAYCOST_AB's scene");
    return s;
}
#endif

typedef struct ray_set {
    const char *name;
    ray_ray *rays;
    size_t n;
    int any;                 /* any-hit queries */
} ray_set;

/* One mesh as every tool holds it. */
typedef struct tools {
    ray_scene *ours;
#ifdef HAVE_EMBREE
    RTCDevice dev;
    RTCScene embree;
#endif
#ifdef HAVE_TINYBVH
    tbvh *tiny;
#endif
#ifdef HAVE_AB
    ray_scene *other[2];     /* RAYCOST_AB's and RAYCOST_AB_OURS's */
#endif
} tools;

/* Wall time, or with RAYCOST_CPU_TIME=1 the thread's own CPU time: on a
** machine shared with others' builds, a thread's CPU time counts what
** its queries cost, not the time others' processes held the core. */
static double now(void)
{
    static int cpu = -1;
    struct timespec ts;

    if (cpu < 0)
        cpu = getenv("RAYCOST_CPU_TIME") != NULL;
    clock_gettime(cpu ? CLOCK_THREAD_CPUTIME_ID : CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void die(const char *what)
{
    fprintf(stderr, "raycost: %s\n", what);
    exit(1);
}

static ray_vec3 unit(ray_vec3 v)
{
    double l = sqrt(v.x * v.x + v.y * v.y + v.z * v.z);

    return ray_vec3_make(v.x / l, v.y / l, v.z / l);
}

static void tools_build(tools *t, const ray_mesh *m)
{
    double *xyz;
    size_t i;

    if (nop_scene_new(&t->ours, NULL, NULL) != RAY_OK ||
        ray_scene_add_mesh(t->ours, m, 0, NULL) != RAY_OK ||
        ray_scene_commit(t->ours) != RAY_OK)
        die("libray's scene");
    xyz = malloc(3 * m->vertex_count * sizeof *xyz);
    if (xyz == NULL)
        die("out of memory");
    for (i = 0; i < m->vertex_count; i++) {
        xyz[3 * i] = m->vertices[i].x;
        xyz[3 * i + 1] = m->vertices[i].y;
        xyz[3 * i + 2] = m->vertices[i].z;
    }
#ifdef HAVE_EMBREE
    t->dev = rtcNewDevice("threads=1");
    t->embree = rtcNewScene(t->dev);
    {
        RTCGeometry g = embree_triangles(t->dev, m->vertices, m->vertex_count,
                                         m->indices, m->triangle_count, NULL);
        rtcCommitGeometry(g);
        rtcAttachGeometry(t->embree, g);
        rtcReleaseGeometry(g);
    }
    rtcCommitScene(t->embree);
#endif
#ifdef HAVE_TINYBVH
    t->tiny = tbvh_build(xyz, m->indices, m->triangle_count);
#endif
#ifdef HAVE_AB
    {
        int k;
        for (k = 0; k < 2; k++)
            if (ab_load() >> k & 1)
                t->other[k] = ab_scene(k, m);
    }
#endif
    free(xyz);
}

static void tools_free(tools *t)
{
    ray_scene_free(t->ours);
#ifdef HAVE_EMBREE
    rtcReleaseScene(t->embree);
    rtcReleaseDevice(t->dev);
#endif
#ifdef HAVE_TINYBVH
    tbvh_free(t->tiny);
#endif
#ifdef HAVE_AB
    {
        int k;
        for (k = 0; k < 2; k++)
            if (ab_load() >> k & 1)
                ab[k].scene_free(t->other[k]);
    }
#endif
}

/* Is the tool built in and asked for?  RAYCOST_TOOLS=0 (ours alone),
** =01, ... picks tools by their column (for A/B runs of two builds of
** libray and for profiles); all by default. */
static int have(int tool)
{
    const char *pick = getenv("RAYCOST_TOOLS");

    if (pick != NULL && strchr(pick, '0' + tool) == NULL)
        return 0;
#ifndef HAVE_EMBREE
    if (tool == TOOL_EMBREE)
        return 0;
#endif
#ifndef HAVE_TINYBVH
    if (tool == TOOL_TINY)
        return 0;
#endif
#ifdef HAVE_AB
    if (tool == TOOL_AB)
        return ab_load() & 1;
#else
    if (tool == TOOL_AB)
        return 0;
#endif
    (void)tool;
    return 1;
}

/* One pass of a tool over a set: the number of hits. */
static size_t pass(const tools *t, int tool, const ray_set *rs)
{
    size_t i, hits = 0;

#ifdef HAVE_AB
    /* Which loaded library runs this pass (-1: none), settled before the
    ** timed loop rather than asked once a ray. */
    int k = tool == TOOL_AB ? 0 : tool == TOOL_OURS && ab_load() & 2 ? 1 : -1;
#endif

    for (i = 0; i < rs->n; i++) {
        const ray_ray *r = &rs->rays[i];
#ifdef HAVE_AB
        if (k >= 0) {
            ray_hit h;
            hits += (size_t)(rs->any
                                 ? ab[k].occluded(t->other[k], r, NULL)
                                 : ab[k].intersect(t->other[k], r, &h, NULL));
        } else
#endif
        if (tool == TOOL_OURS) {
            ray_hit h;
            hits += (size_t)(rs->any ? ray_occluded(t->ours, r, NULL)
                                     : ray_intersect(t->ours, r, &h, NULL));
        }
#ifdef HAVE_EMBREE
        else if (tool == TOOL_EMBREE)
            hits += (size_t)(rs->any ? embree_occluded(t->embree, r)
                                     : embree_hit(t->embree, r, NULL, NULL));
#endif
#ifdef HAVE_TINYBVH
        else {
            float o[3], d[3], tt;
            unsigned prim;
            o[0] = (float)r->org.x; o[1] = (float)r->org.y; o[2] = (float)r->org.z;
            d[0] = (float)r->dir.x; d[1] = (float)r->dir.y; d[2] = (float)r->dir.z;
            hits += (size_t)(rs->any ? tbvh_occluded(t->tiny, o, d, 1e30f)
                                     : tbvh_intersect(t->tiny, o, d, 1e30f,
                                                      &tt, &prim));
        }
#endif
    }
    return hits;
}

/* One row: ns a ray for each tool, medians of reps interleaved passes. */
/* Is row k (0: the first printed) asked for?  RAYCOST_ROWS=2 (the hit
** row alone), =024, ...: for profiles of one kind of ray; all by
** default. */
static int row_wanted(int k)
{
    const char *pick = getenv("RAYCOST_ROWS");

    return pick == NULL || strchr(pick, '0' + k) != NULL;
}

#ifdef RAY_BENCH_COUNTS
/* The counted build (make bench-counts): what one pass of libray's
** queries over the rays did, per ray, from the library's work counters
** (query/query.h), instead of times. */
extern unsigned long long ray__work[4];

static void count_row(const tools *t, const ray_set *rs)
{
    double n = (double)rs->n;
    size_t hits;

    memset(ray__work, 0, sizeof ray__work);
    hits = pass(t, TOOL_OURS, rs);
    printf("| %s | %zu | %zu | %.2f | %.2f | %.2f | %.2f |\n", rs->name,
           rs->n, hits, (double)ray__work[0] / n, (double)ray__work[1] / n,
           (double)ray__work[2] / n, (double)ray__work[3] / n);
}
#endif

static void row(const tools *t, const ray_set *rs, int reps)
{
    static int index;
    double ns[TOOLS][16], ratio[TOOLS][16], med[TOOLS];
    size_t hits[TOOLS] = {0, 0, 0, 0};
    int k, tool;

    if (!row_wanted(index++))
        return;
#ifdef RAY_BENCH_COUNTS
    (void)reps, (void)ns, (void)ratio, (void)med, (void)hits, (void)k,
        (void)tool;
    count_row(t, rs);
    return;
#endif
    for (k = -1; k < reps; k++)                       /* k = -1: warm-up */
        for (tool = 0; tool < TOOLS; tool++) {
            double t0;
            if (!have(tool))
                continue;
            t0 = now();
            hits[tool] = pass(t, tool, rs);
            if (k >= 0)
                ns[tool][k] = 1e9 * (now() - t0) / (double)rs->n;
        }
    for (tool = 0; tool < TOOLS; tool++) {
        if (!have(tool))
            continue;
        for (k = 0; k < reps; k++)
            ratio[tool][k] = have(TOOL_OURS) ? ns[tool][k] / ns[TOOL_OURS][k]
                                          : 0;
        med[tool] = median(ns[tool], reps);
    }
    printf("| %s | %zu |", rs->name, rs->n);
    for (tool = 0; tool < TOOL_AB; tool++)
        if (have(tool))
            printf(" %.1f (%zu hits) |", med[tool], hits[tool]);
        else
            printf(" - |");
    if (have(TOOL_AB))
        printf(" %.1f (%zu hits) |", med[TOOL_AB], hits[TOOL_AB]);
    for (tool = 1; tool < TOOLS; tool++)
        if (tool == TOOL_AB && !have(TOOL_AB))
            continue;
        else if (have(tool) && have(TOOL_OURS))
            printf(" %.2f |", median(ratio[tool], reps));
        else
            printf(" - |");
    printf("\n");
}

static ray_ray ray_from(ray_vec3 o, ray_vec3 d)
{
    ray_ray r;

    r.org = o;
    r.dir = unit(d);
    r.tmin = 0;
    r.tmax = HUGE_VAL;
    return r;
}

/* Does r enter the box [lo, hi] (a plain slab test in double)? */
static int enters_box(const ray_ray *r, ray_vec3 lo, ray_vec3 hi)
{
    double o[3], d[3], a[3], b[3], t0 = 0, t1 = HUGE_VAL;
    int k;

    o[0] = r->org.x; o[1] = r->org.y; o[2] = r->org.z;
    d[0] = r->dir.x; d[1] = r->dir.y; d[2] = r->dir.z;
    a[0] = lo.x; a[1] = lo.y; a[2] = lo.z;
    b[0] = hi.x; b[1] = hi.y; b[2] = hi.z;
    for (k = 0; k < 3; k++) {
        double n = (a[k] - o[k]) / d[k], f = (b[k] - o[k]) / d[k];
        if (n > f) {
            double x = n;
            n = f;
            f = x;
        }
        t0 = n > t0 ? n : t0;
        t1 = f < t1 ? f : t1;
    }
    return t0 <= t1;
}

/* Camera rays at 1.0 diagonals, sorted by what libray answers into those
** that hit and those that enter the box and miss. */
static void camera_sets(const tools *t, ray_vec3 lo, ray_vec3 hi,
                        unsigned res, ray_set *hit, ray_set *miss)
{
    ray_vec3 c = ray_vec3_make(0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y),
                               0.5 * (lo.z + hi.z));
    double diag = sqrt((hi.x - lo.x) * (hi.x - lo.x) +
                       (hi.y - lo.y) * (hi.y - lo.y) +
                       (hi.z - lo.z) * (hi.z - lo.z));
    unsigned x, y;

    hit->rays = malloc((size_t)res * res * sizeof *hit->rays);
    miss->rays = malloc((size_t)res * res * sizeof *miss->rays);
    if (hit->rays == NULL || miss->rays == NULL)
        die("out of memory");
    hit->n = miss->n = 0;
    for (y = 0; y < res; y++)
        for (x = 0; x < res; x++) {
            ray_ray r = bench_camera_ray(c, diag, 1.0, res, x, y);
            ray_hit h;
            r = ray_from(r.org, r.dir);
            if (ray_intersect(t->ours, &r, &h, NULL) == 1) {
                hit->rays[hit->n++] = r;
            } else if (enters_box(&r, lo, hi)) {
                miss->rays[miss->n++] = r;
            }
        }
}

int main(int argc, char **argv)
{
    const int level = bench_level(), smoke = level == BENCH_SMOKE;
    const int reps = smoke ? 1 : level ? 3 : 7;
    const size_t n = smoke ? 100 : level ? 100000 : 1000000;
    const unsigned res = smoke ? 8 : level ? 400 : 1024;
    char path[1024], err[2048];
    obj_mesh om;
    ray_mesh m, gm;
    ray_vec3 lo, hi, centre, *gv;
    unsigned *gi;
    tools bunny, ground;
    ray_set miss_box, enter_miss, hit, down, shadow;
    rng g = {34};
    size_t i;
    double diag;

    if (argc != 2) {
        fprintf(stderr, "usage: raycost DATA_DIR\n");
        return 2;
    }
    /* RAYCOST_MESH=bunny-4.obj: another mesh of DATA_DIR (for A/B runs
    ** on a mesh past the caches); the 59k bunny by default. */
    snprintf(path, sizeof path, "%s/%s", argv[1],
             getenv("RAYCOST_MESH") != NULL ? getenv("RAYCOST_MESH")
                                            : "bunny-2.obj");
    if (obj_load(path, &om, err, sizeof err) != 0) {
        printf("raycost: no %s (scripts/fetch-bunny.sh): skipped\n", path);
        return 0;
    }
    m = obj_as_ray_mesh(&om);
    obj_bounds(&om, &lo, &hi, &centre, &diag);
    tools_build(&bunny, &m);

    /* Rays from a sphere of 2 diagonals round the box, pointing away
    ** from it: they miss its box. */
    miss_box.name = "miss the box";
    miss_box.any = 0;
    miss_box.n = n;
    miss_box.rays = malloc(n * sizeof *miss_box.rays);
    if (miss_box.rays == NULL)
        die("out of memory");
    for (i = 0; i < n; i++) {
        ray_vec3 d = unit(ray_vec3_make(rng_range(&g, -1, 1),
                                        rng_range(&g, -1, 1),
                                        rng_range(&g, -1, 1)));
        ray_vec3 o = ray_vec3_make(0.5 * (lo.x + hi.x) + 2 * diag * d.x,
                                   0.5 * (lo.y + hi.y) + 2 * diag * d.y,
                                   0.5 * (lo.z + hi.z) + 2 * diag * d.z);
        miss_box.rays[i] = ray_from(o, d);
    }
    camera_sets(&bunny, lo, hi, res, &hit, &enter_miss);
    hit.name = "camera, hit";
    hit.any = 0;
    enter_miss.name = "camera, enter the box and miss";
    enter_miss.any = 0;

    /* Shadow rays: from just off each hit towards a light above. */
    shadow.name = "shadow (any hit)";
    shadow.any = 1;
    shadow.n = hit.n;
    shadow.rays = malloc(hit.n * sizeof *shadow.rays);
    if (shadow.rays == NULL)
        die("out of memory");
    for (i = 0; i < hit.n; i++) {
        ray_hit h;
        ray_vec3 light = ray_vec3_make(hi.x + diag, hi.y + diag, hi.z + diag);
        if (ray_intersect(bunny.ours, &hit.rays[i], &h, NULL) != 1)
            die("a hit ray missed");
        ray_vec3 d = unit(ray_vec3_make(light.x - h.p.x, light.y - h.p.y,
                                        light.z - h.p.z));
        /* Started 1e-6 diagonals off the surface, past its rounding
        ** error, rather than at tmin > 0, which tinybvh has not. */
        shadow.rays[i] = ray_from(
            ray_vec3_make(h.p.x + 1e-6 * diag * d.x, h.p.y + 1e-6 * diag * d.y,
                          h.p.z + 1e-6 * diag * d.z), d);
    }

    if (grid_mesh(100, &gm, &gv, &gi) != 0)
        die("out of memory");
    tools_build(&ground, &gm);
    down.name = "ground query (down onto a 100 x 100 grid)";
    down.any = 0;
    down.n = n;
    down.rays = malloc(n * sizeof *down.rays);
    if (down.rays == NULL)
        die("out of memory");
    for (i = 0; i < n; i++)
        down.rays[i] = ray_from(
            ray_vec3_make(0.5 + 99 * rng_unit(&g),
                          0.5 + 99 * rng_unit(&g), 10),
            ray_vec3_make(0, 0, -1));

#ifdef RAY_BENCH_COUNTS
    printf("### The work of a query\n\n");
    printf("libray's queries on the rays above, per ray, counted by the "
           "library's counted build (make bench-counts: -DRAY_BENCH_COUNTS,"
           " never the library proper): inner nodes tested (8 boxes "
           "each), triangle leaves reached, triangles through the float "
           "filter (up to 8 a pass), exact tests (the filter's "
           "survivors).\n\n");
    printf("| rays | n | hits | nodes | leaves | filtered triangles "
           "| exact tests |\n|---|---|---|---|---|---|---|\n");
#else
    printf("## What a query costs\n\n");
    {
        /* The mesh the rows ran on: the default's name as before. */
        char mesh_name[1100];
        if (getenv("RAYCOST_MESH") == NULL)
            snprintf(mesh_name, sizeof mesh_name, "59k bunny");
        else
            snprintf(mesh_name, sizeof mesh_name, "%s (%zu triangles)",
                     getenv("RAYCOST_MESH"), m.triangle_count);
        printf("ns a ray, one thread, median of %d interleaved passes; %s "
               "and a 20k-triangle grid; ratios are theirs / ours in time "
               "(above 1: ours is faster).\n\n", reps, mesh_name);
    }
    if (have(TOOL_AB))
        printf("| rays | n | libray | Embree | tinybvh | RAYCOST_AB "
               "| Embree / libray | tinybvh / libray | RAYCOST_AB / libray "
               "|\n|---|---|---|---|---|---|---|---|---|\n");
    else
        printf("| rays | n | libray | Embree | tinybvh | Embree / libray "
               "| tinybvh / libray |\n|---|---|---|---|---|---|---|\n");
#endif
    row(&bunny, &miss_box, reps);
    row(&bunny, &enter_miss, reps);
    row(&bunny, &hit, reps);
    row(&bunny, &shadow, reps);
    row(&ground, &down, reps);
    printf("\n");

    tools_free(&bunny);
    tools_free(&ground);
    free(miss_box.rays);
    free(enter_miss.rays);
    free(hit.rays);
    free(shadow.rays);
    free(down.rays);
    free(gv);
    free(gi);
    obj_free(&om);
    return 0;
}
