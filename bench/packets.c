/* SPDX-License-Identifier: MIT */
/*
** packets.c -- many rays at once: ray_intersect_batch /
** ray_occluded_batch (eight rays a packet where the CPU has AVX2)
** against our one-ray queries and,
** when built with Embree (HAVE_EMBREE), Embree's rtcIntersect1 /
** rtcOccluded1 and rtcIntersect8 / rtcOccluded8 on the same rays, one
** thread, in the same run.  Prints Markdown; asserts nothing.
**
**     packets DATA_DIR       (bunny-2.obj, bunny-4.obj)
**
** Rays: camera rays of a 1024 x 1024 image ordered in 4 x 2 pixel blocks
** (each packet of eight is one block), camera on +z at 2.5 and 1.0
** bounding-box diagonals; shadow rays from those hits to a point light
** above the camera (neighbouring pixels' shadow rays share a packet);
** incoherent rays, cosine-distributed about the hit normals (packets of
** rays that scatter: the packets' worst case).  Secondary rays start at
** ray_spawn's origin with tmin = 1e-5 diagonals for both engines, as in
** bench/mesh.c (Embree works in float and would re-hit the surface).
**
** Method as bench/mesh.c: each timing is the median of REPS runs after a
** warm-up; the four ways alternate within each repetition, and each ratio
** is the median of the repetitions' own ratios.  "same as one ray": ours
** in packets against ours one ray at a time, hit flag, t, primitive and
** every field of the hit record compared bit for bit (must be 100%).
** BENCH_QUICK=1: 256 x 256 rays, three repetitions, the 940k mesh
** skipped.
*/
#include "bench.h"
#include "obj.h"
#include "common.h"

#include "embree.h"

static int reps = 5;

#define WAYS 4
enum { OURS_ONE, OURS_N, EMBREE_ONE, EMBREE_8 };

typedef struct ray_set {
    const char *name;
    ray_ray *rays;
    size_t n;
    int occlusion;
} ray_set;

/* Camera rays in 4 x 2 blocks: rays[8 b + j] is pixel j % 4, j / 4 of
** block b (blocks in scanline order). */
static ray_set camera_rays(ray_vec3 centre, double diag, double dist,
                           unsigned res, const char *name)
{
    ray_set s;
    unsigned bx, by, j;

    s.name = name;
    s.n = (size_t)res * res;
    s.occlusion = 0;
    s.rays = malloc(s.n * sizeof *s.rays);
    if (s.rays == NULL)
        exit(1);
    for (by = 0; by < res; by += 2)
        for (bx = 0; bx < res; bx += 4)
            for (j = 0; j < 8; j++)
                s.rays[(size_t)by * res + (size_t)bx * 2 + j] =
                    bench_camera_ray(centre, diag, dist, res, bx + j % 4,
                                     by + j / 4);
    return s;
}

/* From each hit of "cam" (in its order), a shadow ray to "light" or a
** cosine-distributed ray (Malley's method) about the normal on the side
** the camera ray came from. */
static ray_set secondary_rays(const ray_scene *scene, const ray_set *cam,
                              int shadow, ray_vec3 light, double diag,
                              const char *name)
{
    ray_set s;
    rng g = {4242};
    size_t i;

    s.name = name;
    s.rays = malloc(cam->n * sizeof *s.rays);
    s.n = 0;
    s.occlusion = 1;
    if (s.rays == NULL)
        exit(1);
    for (i = 0; i < cam->n; i++) {
        ray_hit h;
        ray_ray *out = &s.rays[s.n];
        ray_vec3 n, d;
        double u1, u2;
        if (ray_intersect(scene, &cam->rays[i], &h, NULL) <= 0)
            continue;
        if (shadow) {
            if (ray_spawn_to(&h, light, out) != RAY_OK)
                continue;
            out->tmin = 1e-5 * diag / sqrt(ray_vec3_dot(out->dir, out->dir));
            s.n++;
            continue;
        }
        n = h.n;
        if (ray_vec3_dot(n, cam->rays[i].dir) > 0)
            n = vec(-n.x, -n.y, -n.z);
        u1 = rng_unit(&g);
        u2 = rng_unit(&g);
        d = bench_cosine_dir(n, u1, u2);
        if (ray_spawn(&h, d, out) == RAY_OK) {
            out->tmin = 1e-5 * diag;
            s.n++;
        }
    }
    return s;
}

/* ------------------------------------------------------------ tracing */

typedef struct results {
    int *res;
    ray_hit *hits;
    float *t;
    unsigned *prim;
} results;

static void results_alloc(results *r, size_t n)
{
    r->res = calloc(n, sizeof *r->res);
    r->hits = calloc(n, sizeof *r->hits);
    r->t = calloc(n, sizeof *r->t);
    r->prim = calloc(n, sizeof *r->prim);
    if (r->res == NULL || r->hits == NULL || r->t == NULL || r->prim == NULL)
        exit(1);
}

static void results_free(results *r)
{
    free(r->res);
    free(r->hits);
    free(r->t);
    free(r->prim);
}

static void ours_one(const ray_scene *s, const ray_set *set, results *out)
{
    size_t i;

    for (i = 0; i < set->n; i++)
        out->res[i] = set->occlusion
                          ? ray_occluded(s, &set->rays[i], NULL)
                          : ray_intersect(s, &set->rays[i], &out->hits[i],
                                          NULL);
}

static void ours_n(const ray_scene *s, const ray_set *set, results *out)
{
    ray_batch b = {0};

    b.rays = set->rays;
    b.n = set->n;
    b.hits = out->hits;
    b.results = out->res;
    if (set->occlusion)
        check(ray_occluded_batch(s, &b), "ray_occluded_batch");
    else
        check(ray_intersect_batch(s, &b), "ray_intersect_batch");
}

#ifdef HAVE_EMBREE
static void embree_one(RTCScene scene, const ray_set *set, results *out)
{
    size_t i;

    for (i = 0; i < set->n; i++) {
        const ray_ray *r = &set->rays[i];
        if (set->occlusion)
            out->res[i] = embree_occluded(scene, r);
        else
            out->res[i] = embree_hit(scene, r, &out->t[i], &out->prim[i]);
    }
}

/* Eight rays a call, as ray_intersect_batch groups them. */
static void embree_8(RTCScene scene, const ray_set *set, results *out)
{
    struct RTCIntersectContext ctx;
    RTC_ALIGN(32) struct RTCRayHit8 rh;
    RTC_ALIGN(32) int valid[8];
    size_t i;
    int j;

    rtcInitIntersectContext(&ctx);
    for (i = 0; i < set->n; i += 8) {
        for (j = 0; j < 8; j++) {
            const ray_ray *r = &set->rays[i + (size_t)j < set->n ? i + (size_t)j : i];
            valid[j] = i + (size_t)j < set->n ? -1 : 0;
            rh.ray.org_x[j] = (float)r->org.x;
            rh.ray.org_y[j] = (float)r->org.y;
            rh.ray.org_z[j] = (float)r->org.z;
            rh.ray.dir_x[j] = (float)r->dir.x;
            rh.ray.dir_y[j] = (float)r->dir.y;
            rh.ray.dir_z[j] = (float)r->dir.z;
            rh.ray.tnear[j] = (float)r->tmin;
            rh.ray.tfar[j] = r->tmax < HUGE_VAL ? (float)r->tmax : INFINITY;
            rh.ray.mask[j] = 0xffffffffu;
            rh.ray.flags[j] = 0;
            rh.ray.time[j] = 0;
            rh.hit.geomID[j] = RTC_INVALID_GEOMETRY_ID;
        }
        if (set->occlusion)
            rtcOccluded8(valid, scene, &ctx, &rh.ray);
        else
            rtcIntersect8(valid, scene, &ctx, &rh);
        for (j = 0; j < 8 && i + (size_t)j < set->n; j++) {
            if (set->occlusion)
                out->res[i + (size_t)j] = rh.ray.tfar[j] < 0;
            else {
                out->res[i + (size_t)j] =
                    rh.hit.geomID[j] != RTC_INVALID_GEOMETRY_ID;
                out->t[i + (size_t)j] = rh.ray.tfar[j];
                out->prim[i + (size_t)j] = rh.hit.primID[j];
            }
        }
    }
}
#endif

/* Run way w on the set; seconds. */
static double run_way(int w, const ray_scene *s, void *embree,
                      const ray_set *set, results *out)
{
    double t = now_seconds();

    switch (w) {
    case OURS_ONE:
        ours_one(s, set, out);
        break;
    case OURS_N:
        ours_n(s, set, out);
        break;
#ifdef HAVE_EMBREE
    case EMBREE_ONE:
        embree_one((RTCScene)embree, set, out);
        break;
    case EMBREE_8:
        embree_8((RTCScene)embree, set, out);
        break;
#endif
    default:
        (void)embree;
        return 0;
    }
    return now_seconds() - t;
}

/* Hit records the same bit for bit (as tests/testkit.h hit_same). */
static size_t same_count(const ray_set *set, const results *a,
                         const results *b)
{
    size_t i, same = 0;

    for (i = 0; i < set->n; i++)
        same += a->res[i] == b->res[i] &&
                (set->occlusion || a->res[i] <= 0 ||
                 hit_same(&a->hits[i], &b->hits[i]));
    return same;
}

static void bench_set(const ray_scene *s, void *embree, const ray_set *set)
{
    results out[WAYS];
    double t[WAYS][9], ratio_n[9], ratio_e8[9], ratio_e1[9], ratio_8v1[9];
    int w, k, ways = embree != NULL ? WAYS : 2;
    size_t same, agree = 0, i;

    for (w = 0; w < WAYS; w++)
        results_alloc(&out[w], set->n);
    for (w = 0; w < ways; w++)
        run_way(w, s, embree, set, &out[w]);          /* warm-up */
    for (k = 0; k < reps; k++) {
        for (w = 0; w < ways; w++)
            t[w][k] = run_way(w, s, embree, set, &out[w]);
        ratio_n[k] = t[OURS_ONE][k] / t[OURS_N][k];
        if (embree != NULL) {
            ratio_e8[k] = t[EMBREE_8][k] / t[OURS_N][k];
            ratio_e1[k] = t[EMBREE_ONE][k] / t[OURS_N][k];
            ratio_8v1[k] = t[EMBREE_ONE][k] / t[EMBREE_8][k];
        }
    }
    same = same_count(set, &out[OURS_ONE], &out[OURS_N]);
    if (embree != NULL)
        for (i = 0; i < set->n; i++)
            agree += (out[OURS_N].res[i] > 0) == (out[EMBREE_8].res[i] > 0) &&
                     (set->occlusion || out[OURS_N].res[i] <= 0 ||
                      out[OURS_N].hits[i].prim_id == out[EMBREE_8].prim[i]);
    double n = (double)set->n;

    printf("| %s | %zu | %.2f | %.2f | %.2f |", set->name, set->n,
           n / median(t[OURS_ONE], reps) / 1e6,
           n / median(t[OURS_N], reps) / 1e6, median(ratio_n, reps));
    if (embree != NULL)
        printf(" %.2f | %.2f | %.2f | %.2f | %.2f |",
               n / median(t[EMBREE_ONE], reps) / 1e6,
               n / median(t[EMBREE_8], reps) / 1e6,
               median(ratio_8v1, reps), median(ratio_e1, reps),
               median(ratio_e8, reps));
    printf(" %.4f%% |", 100.0 * (double)same / n);
    if (embree != NULL)
        printf(" %.4f%% |", 100.0 * (double)agree / n);
    printf("\n");
    for (w = 0; w < WAYS; w++)
        results_free(&out[w]);
}

static void bench_mesh(const char *path, unsigned res, void *device)
{
    obj_mesh obj;
    char err[256];
    ray_scene *s;
    ray_mesh mesh;
    ray_vec3 lo, hi, centre, light;
    double diag;
    ray_set sets[5];
    void *embree = NULL;
    int k;

    if (obj_load(path, &obj, err, sizeof err) != 0) {
        printf("(%s: %s; skipped)\n\n", path, err);
        return;
    }
    obj_bounds(&obj, &lo, &hi, &centre, &diag);
    mesh = obj_as_ray_mesh(&obj);
    check(ray_scene_new(&s, NULL, NULL), "ray_scene_new");
    check(ray_scene_add_mesh(s, &mesh, RAY_NO_MATERIAL, NULL), "mesh");
    check(ray_scene_commit(s), "commit");
#ifdef HAVE_EMBREE
    if (device != NULL) {
        RTCScene es = rtcNewScene((RTCDevice)device);
        RTCGeometry g = embree_triangles((RTCDevice)device, obj.vertices,
                                         obj.vertex_count, obj.indices,
                                         obj.triangle_count, NULL);
        rtcCommitGeometry(g);
        rtcAttachGeometry(es, g);
        rtcReleaseGeometry(g);
        rtcCommitScene(es);
        embree = es;
    }
#else
    (void)device;
#endif
    light = vec(centre.x + diag, centre.y + 2 * diag, centre.z + 2 * diag);
    sets[0] = camera_rays(centre, diag, 2.5, res, "primary, 2.5 diagonals");
    sets[1] = camera_rays(centre, diag, 1.0, res, "primary, 1.0 diagonal");
    sets[2] = secondary_rays(s, &sets[1], 1, light, diag,
                             "shadow (to one light), any-hit");
    sets[3] = secondary_rays(s, &sets[1], 0, light, diag,
                             "incoherent (cosine), any-hit");
    sets[4] = sets[3];
    sets[4].occlusion = 0;
    sets[4].name = "incoherent (cosine), closest";
    printf("### %s: %zu triangles\n\n", path, obj.triangle_count);
    printf("| rays | count | ours one ray Mrays/s | ours packets Mrays/s | "
           "packets / one ray |%s same as one ray |%s\n",
           embree != NULL ? " Embree 1 Mrays/s | Embree 8 Mrays/s | "
                            "Embree 8 / 1 | ours packets / Embree 1 | "
                            "ours packets / Embree 8 |" : "",
           embree != NULL ? " same hit as Embree 8 |" : "");
    printf("|---|---|---|---|---|%s---|%s\n",
           embree != NULL ? "---|---|---|---|---|" : "",
           embree != NULL ? "---|" : "");
    for (k = 0; k < 5; k++)
        bench_set(s, embree, &sets[k]);
    printf("\n");
    for (k = 0; k < 4; k++)
        free(sets[k].rays);
#ifdef HAVE_EMBREE
    if (embree != NULL)
        rtcReleaseScene((RTCScene)embree);
#endif
    ray_scene_free(s);
    obj_free(&obj);
}

int main(int argc, char **argv)
{
    const char *dir = argc > 1 ? argv[1] : "data";
    int level = bench_level(), quick = level != BENCH_FULL;
    unsigned res = level == BENCH_SMOKE ? 8 : quick ? 256 : 1024;
    char path[512];
    void *device = NULL;

    reps = level == BENCH_SMOKE ? 1 : quick ? 3 : 5;
    printf("## Packets: ray_intersect_batch / ray_occluded_batch against "
           "one ray at a time%s\n\n",
#ifdef HAVE_EMBREE
           ", and Embree " RTC_VERSION_STRING "'s rtcIntersect1/8 and "
           "rtcOccluded1/8"
#else
           " (Embree absent: install libembree-dev and rerun)"
#endif
    );
    printf("One thread, %ux%u camera rays in 4x2 pixel blocks (a packet "
           "of eight is one block), camera on +z; shadow and cosine rays "
           "from the 1.0-diagonal hits, in the same order.  Median of %d "
           "runs, ratios the median of the runs' own ratios (the four "
           "ways alternating).  Our packets run where the CPU has AVX2 "
           "(%s here).\n\n", res, res, reps,
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
           __builtin_cpu_supports("avx2") ? "it has" : "it has not"
#else
           "not x86: ray by ray"
#endif
    );
#ifdef HAVE_EMBREE
    device = rtcNewDevice("threads=1");
#endif
    snprintf(path, sizeof path, "%s/bunny-2.obj", dir);
    bench_mesh(path, res, device);
    if (!quick) {
        snprintf(path, sizeof path, "%s/bunny-4.obj", dir);
        bench_mesh(path, res, device);
    }
#ifdef HAVE_EMBREE
    rtcReleaseDevice((RTCDevice)device);
#endif
    return 0;
}
