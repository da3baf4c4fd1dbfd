/* SPDX-License-Identifier: MIT */
/*
** contains.c -- ray_contains against CGAL 5.5's Side_of_triangle_mesh
** (the exact reference: AABB tree, exact-predicates kernel) and
** ray_distance_grid against OpenVDB's meshToSignedDistanceField and
** meshToLevelSet, on the 59k bunny, one thread for containment and two
** for the grids (issue 39's tables):
**
**   uniform     points uniform in the bunny's box grown by 10% on each
**               side (10^6);
**   hard        every vertex and every edge's midpoint (rounded), where
**               a float ray leaks; CGAL calls the vertices and the
**               midpoints that round onto the surface ON_BOUNDARY, as
**               libray's on_surface (its documented answer: inside and
**               on the surface).
**
**     contains DATA_DIR          (bunny-2.obj: scripts/fetch-bunny.sh)
**
** Points per second, the median of REPS repetitions after a warm-up,
** each repetition timing every tool on the whole set one after the other
** (bench/raycost.c's method, so a noisy neighbour hits all); ratios are
** medians of the repetitions' own ratios.  "differ" counts the points
** whose answers (inside / on the boundary / outside) differ from CGAL's.
** The grids: a 128^3 lattice over the bunny's box grown by 10% (made a
** cube, OpenVDB's voxels being cubes), two threads on both sides; sign
** errors against CGAL's answer at each sample (ray_contains' where CGAL
** is not built), on the closed bunny and on one with holes (8 triangles
** removed: nothing closed, so libray answers by the winding number,
** RAY_CONTAINS_WINDING: only a subsample of the lattice is asked there).
** Closest points: ray_closest_point against CGAL's AABB_tree on the
** uniform points (its closest_point, over the same mesh).
** The winding number's own table: the closed and the holed bunny's
** winding number through the BVH against the sum over every triangle
** (RAY_CONTAINS_WINDING_EXACT), their speeds and the largest difference.  HAVE_CGAL, HAVE_OPENVDB: the Makefile
** defines them where Debian's libcgal-dev / libopenvdb-dev is installed
** (bench/cgal_vdb.cpp); without them the libray columns alone.  Prints
** Markdown; asserts nothing.  BENCH_QUICK=1: fewer points, a 32^3
** lattice, fewer repetitions.  CONTAINS_TOOLS=0: libray alone and no
** grids (two builds of libray compared in turn, callgrind).
** CONTAINS_BAND=1: the narrow-band grid's row alone (both tools, signs
** against the same reference), without the minutes of the full fields
** and the winding numbers: a measurement for a short quiet window.
*/
#include <time.h>

#include "bench.h"
#include "obj.h"
#include "scene/scene.h"            /* the grid's bytes (s->cgrid) */
#if defined(HAVE_CGAL) || defined(HAVE_OPENVDB)
#include "cgal_vdb.h"
#endif

static double now(void)
{
    struct timespec ts;

    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void die(const char *what)
{
    fprintf(stderr, "contains: %s\n", what);
    exit(1);
}

static void *xmalloc(size_t n)
{
    void *p = malloc(n > 0 ? n : 1);

    if (p == NULL)
        die("out of memory");
    return p;
}

/* CONTAINS_TOOLS=0: libray's containment alone, no CGAL, no grids. */
static int others(void)
{
    const char *pick = getenv("CONTAINS_TOOLS");

    return pick == NULL || strcmp(pick, "0") != 0;
}

/* libray's answer as CGAL's Bounded_side: 1 inside, 0 on the surface,
** -1 outside. */
static signed char side_of(const ray_inside *r)
{
    return r->on_surface ? 0 : r->inside ? 1 : -1;
}

static int key_cmp(const void *pa, const void *pb)
{
    unsigned long long a = *(const unsigned long long *)pa;
    unsigned long long b = *(const unsigned long long *)pb;

    return (a > b) - (a < b);
}

/* One tool's pass over a row's n points, its answers into out. */
typedef void (*row_pass)(const void *tool, const ray_vec3 *pts, size_t n,
                         void *out);

/*
** A row's timing: after a warm-up pass, reps passes of libray's pass and
** (where "theirs" is not NULL) the other tool's, interleaved so that a
** noisy neighbour hits both: points a second in ours[k] and theirs[k],
** and ratio[k] = ours[k] / theirs[k] (0 without the other tool).
*/
static void time_row(row_pass our_pass, const void *us, void *our_out,
                     row_pass their_pass, const void *them, void *their_out,
                     const ray_vec3 *pts, size_t n, int reps, double *ours,
                     double *theirs, double *ratio)
{
    int k;

    for (k = -1; k < reps; k++) {             /* k = -1: warm-up */
        double t0 = now();
        our_pass(us, pts, n, our_out);
        if (k >= 0)
            ours[k] = (double)n / (now() - t0);
        if (their_pass == NULL || them == NULL) {
            if (k >= 0)
                theirs[k] = ratio[k] = 0;
            continue;
        }
        t0 = now();
        their_pass(them, pts, n, their_out);
        if (k >= 0) {
            theirs[k] = (double)n / (now() - t0);
            ratio[k] = ours[k] / theirs[k];
        }
    }
}

/* libray's nearest-point distances, radius +Inf, into out (doubles). */
static void closest_pass(const void *s, const ray_vec3 *pts, size_t n,
                         void *out)
{
    double *d = out;
    size_t i;

    for (i = 0; i < n; i++) {
        ray_closest cl;
        if (ray_closest_point(s, pts[i], HUGE_VAL, &cl) != 1)
            die("ray_closest_point found nothing");
        d[i] = cl.distance;
    }
}

#ifdef HAVE_CGAL
static void cgal_closest_pass(const void *c, const ray_vec3 *pts, size_t n,
                              void *out)
{
    cgal_closest_query(c, &pts[0].x, n, out);
}
#else
#define cgal_closest_pass NULL
#endif

/* ray_closest_point (radius +Inf) against CGAL's AABB_tree::closest_point
** on the same points, one thread, reps interleaved passes: thousands of
** points a second, and the largest difference of the distances over the
** mesh's diagonal. */
static void closest_row(const char *name, const ray_scene *s,
                        const void *cgal, const ray_vec3 *pts, size_t n,
                        int reps, double diag)
{
    double ours[16], theirs[16], ratio[16], worst = 0;
    double *d = xmalloc(n * sizeof *d), *c = xmalloc(n * sizeof *c);

    time_row(closest_pass, s, d, cgal_closest_pass, cgal, c, pts, n, reps,
             ours, theirs, ratio);
    printf("| %s | %zu | %.1f | ", name, n, median(ours, reps) / 1e3);
#ifdef HAVE_CGAL
    if (cgal != NULL) {
        size_t i;
        for (i = 0; i < n; i++)
            worst = fmax(worst, fabs(d[i] - c[i]));
        printf("%.1f | %.2f | %.1e |\n", median(theirs, reps) / 1e3,
               median(ratio, reps), worst / diag);
    } else
#endif
        printf("- | - | - |\n");
    (void)worst, (void)diag;
    free(d);
    free(c);
}

/* Every vertex and every edge's midpoint (each edge once). */
static size_t hard_points(const ray_mesh *m, ray_vec3 **out)
{
    size_t nt = m->triangle_count, n = 0, i, k = 0;
    unsigned long long *keys = xmalloc(3 * nt * sizeof *keys);
    ray_vec3 *p;

    for (i = 0; i < 3 * nt; i++) {
        unsigned a = m->indices[i];
        unsigned b = m->indices[i % 3 == 2 ? i - 2 : i + 1];
        keys[n++] = a < b ? ((unsigned long long)a << 32) | b
                          : ((unsigned long long)b << 32) | a;
    }
    qsort(keys, n, sizeof *keys, key_cmp);
    p = xmalloc((m->vertex_count + n) * sizeof *p);
    for (i = 0; i < m->vertex_count; i++)
        p[k++] = m->vertices[i];
    for (i = 0; i < n; i++) {
        ray_vec3 a, b;
        if (i > 0 && keys[i] == keys[i - 1])
            continue;
        a = m->vertices[keys[i] >> 32];
        b = m->vertices[keys[i] & 0xffffffffu];
        p[k++] = ray_vec3_make(0.5 * (a.x + b.x), 0.5 * (a.y + b.y),
                               0.5 * (a.z + b.z));
    }
    free(keys);
    *out = p;
    return k;
}

#ifdef HAVE_CGAL
static cgal_side *cgal_of(const ray_mesh *m)
{
    cgal_side *c = cgal_side_new(&m->vertices[0].x, m->vertex_count,
                                 m->indices, m->triangle_count);

    if (c == NULL)
        die("CGAL's mesh (not a manifold?)");
    return c;
}
#endif

/* libray's answers for the row (the batch call), into out (ray_inside). */
static void contains_pass(const void *s, const ray_vec3 *pts, size_t n,
                          void *out)
{
    if (ray_contains(s, pts, n, NULL, out) < 0)
        die("ray_contains failed");
}

#ifdef HAVE_CGAL
static void cgal_side_pass(const void *c, const ray_vec3 *pts, size_t n,
                           void *out)
{
    cgal_side_query(c, &pts[0].x, n, out);
}
#else
#define cgal_side_pass NULL
#endif

/* One row: points a second for libray (the batch call) and CGAL,
** medians of reps interleaved passes, and the points where they
** differ. */
static void contains_row(const char *name, const ray_scene *s,
                         const void *cgal, const ray_vec3 *pts, size_t n,
                         int reps)
{
    double ours[16], theirs[16], ratio[16];
    ray_inside *r = xmalloc(n * sizeof *r);
    signed char *c = xmalloc(n);
    size_t i, differ = 0, on_ours = 0, on_theirs = 0, in_ours = 0;

    time_row(contains_pass, s, r, cgal_side_pass, cgal, c, pts, n, reps,
             ours, theirs, ratio);
    for (i = 0; i < n; i++) {
        signed char o = side_of(&r[i]);
        on_ours += o == 0;
        in_ours += o == 1;
#ifdef HAVE_CGAL
        if (cgal == NULL)
            continue;
        on_theirs += c[i] == 0;
        differ += o != c[i];
#endif
    }
    printf("| %s | %zu | %.2f | ", name, n, median(ours, reps) / 1e6);
#ifdef HAVE_CGAL
    if (cgal != NULL)
        printf("%.2f | %.2f | %zu | %zu / %zu |", median(theirs, reps) / 1e6,
               median(ratio, reps), differ, on_ours, on_theirs);
    else
        printf("- | - | - | %zu / - |", on_ours);
#else
    (void)differ;
    (void)on_theirs;
    printf("- | - | - | %zu / - |", on_ours);
#endif
    printf(" %zu |\n", in_ours);
    free(r);
    free(c);
}

/*
** One row of the winding number's table: points a second of the winding
** number summed over every triangle (RAY_CONTAINS_WINDING_EXACT) and
** through the BVH's far-field expansions (the default), medians of reps
** interleaved passes over the same points, with "flags" (the closed
** bunny: RAY_CONTAINS_WINDING, every mesh by the winding number); the
** largest |fast - exact| seen, the points whose inside differs, and the
** points within 0.2 of 1/2 (which the fast path sums again exactly:
** ray.h's ray_contains).
*/
static void winding_row(const char *name, const ray_scene *s, unsigned flags,
                        const ray_vec3 *pts, size_t n, int reps)
{
    double exact[16], fast[16], ratio[16], err = 0;
    ray_inside *re = xmalloc(n * sizeof *re), *rf = xmalloc(n * sizeof *rf);
    ray_contains_options oe = {0}, of = {0};
    size_t i, differ = 0, near = 0;
    int k;

    oe.flags = flags | RAY_CONTAINS_WINDING_EXACT;
    of.flags = flags;
    for (k = -1; k < reps; k++) {             /* k = -1: warm-up */
        double t0 = now();
        if (ray_contains(s, pts, k < 0 ? 1 : n, &oe, re) < 0)
            die("ray_contains (exact winding) failed");
        if (k >= 0)
            exact[k] = (double)n / (now() - t0);
        t0 = now();
        if (ray_contains(s, pts, n, &of, rf) < 0)
            die("ray_contains (fast winding) failed");
        if (k >= 0) {
            fast[k] = (double)n / (now() - t0);
            ratio[k] = fast[k] / exact[k];
        }
    }
    for (i = 0; i < n; i++) {
        double e = fabs(rf[i].winding - re[i].winding);
        err = e > err ? e : err;
        differ += rf[i].inside != re[i].inside;
        near += fabs(re[i].winding - 0.5) < 0.2;
    }
    printf("| %s | %zu | %.2f | %.1f | %.0f | %.1e | %zu | %zu |\n", name, n,
           median(exact, reps) / 1e3, median(fast, reps) / 1e3,
           median(ratio, reps), err, differ, near);
    free(re);
    free(rf);
}

/* The lattice's sample (i, j, k), as ray_distance_grid computes it. */
static ray_vec3 sample(ray_vec3 lo, ray_vec3 hi, unsigned n, unsigned i,
                       unsigned j, unsigned k)
{
    double sx = (hi.x - lo.x) / (double)(n - 1);
    double sy = (hi.y - lo.y) / (double)(n - 1);
    double sz = (hi.z - lo.z) / (double)(n - 1);

    return ray_vec3_make(lo.x + sx * (double)i, lo.y + sy * (double)j,
                         lo.z + sz * (double)k);
}

/* Sign errors of a baked field f against ref (1 inside, 0 on, -1 out):
** a sample that is inside with f >= 0 or outside with f < 0 (on the
** surface: either sign).  exact: also f == 0 on the surface exactly
** (libray's documented answer). */
static size_t sign_errors(const float *f, const signed char *ref, size_t n,
                          int exact)
{
    size_t i, e = 0;

    for (i = 0; i < n; i++) {
        if (ref[i] == 0)
            e += exact && f[i] != 0;
        else
            e += (ref[i] > 0) != (f[i] < 0);
    }
    return e;
}

int main(int argc, char **argv)
{
    const int level = bench_level(), quick = level != BENCH_FULL;
    const int smoke = level == BENCH_SMOKE;
    const int reps = smoke ? 1 : quick ? 3 : 7;
    /* The full field's bakes take tens of seconds at 128^3: one. */
    const int grid_reps[2] = {1, quick ? 1 : 3};
    const size_t n_uniform = smoke ? 100 : quick ? 100000 : 1000000;
    const unsigned gn = smoke ? 8 : quick ? 32 : 128,
                   sub = smoke ? 4 : quick ? 8 : 16;
    const unsigned holes = 8;
    /* The exact winding number costs a pass over 59k triangles a point
    ** (milliseconds): a few thousand points. */
    const size_t n_wind = smoke ? 10 : quick ? 200 : 2000;
    /* Closest points over the whole scene: tens of microseconds each. */
    const size_t n_close = smoke ? 10 : quick ? 2000 : 20000;
    const int wreps = quick ? 1 : 3;
    const char *band_env = getenv("CONTAINS_BAND");
    const int band_only = band_env != NULL && strcmp(band_env, "1") == 0;
    char path[1024], err[2048];
    obj_mesh om;
    ray_mesh m, hm;
    ray_vec3 lo, hi, centre, *uni, *hard, glo, ghi;
    ray_scene *s = NULL, *hs = NULL;
    counting mem = {0, 0};
    size_t i, n_hard, gsz;
    double diag, side, step;
    rng g = {39};
    void *cgal = NULL;
    float *ours, *vdb;
    signed char *ref, *hsub_ref = NULL;
    unsigned *hidx = NULL;
    ray_distance_grid_options go;
    size_t nsub;

    if (argc != 2) {
        fprintf(stderr, "usage: contains DATA_DIR\n");
        return 2;
    }
    snprintf(path, sizeof path, "%s/bunny-2.obj", argv[1]);
    if (obj_load(path, &om, err, sizeof err) != 0) {
        printf("contains: no %s (scripts/fetch-bunny.sh): skipped\n", path);
        return 0;
    }
    m = obj_as_ray_mesh(&om);
    obj_bounds(&om, &lo, &hi, &centre, &diag);
    if (ray_scene_new(&s, counting_alloc, &mem) != RAY_OK ||
        ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, NULL) != RAY_OK ||
        ray_scene_commit(s) != RAY_OK)
        die("libray's scene");
#ifdef HAVE_CGAL
    if (others())
        cgal = cgal_of(&m);
#endif

    uni = xmalloc(n_uniform * sizeof *uni);
    for (i = 0; i < n_uniform; i++) {
        ray_vec3 d = ray_vec3_make(0.1 * (hi.x - lo.x), 0.1 * (hi.y - lo.y),
                                   0.1 * (hi.z - lo.z));
        uni[i] = ray_vec3_make(rng_range(&g, lo.x - d.x, hi.x + d.x),
                               rng_range(&g, lo.y - d.y, hi.y + d.y),
                               rng_range(&g, lo.z - d.z, hi.z + d.z));
    }
    n_hard = hard_points(&m, &hard);

    /* The grid of labels is built by the first ray_contains: count it. */
    if (ray_contains(s, NULL, 0, NULL, NULL) < 0)
        die("ray_contains");
    if (band_only)
        goto grids;
    printf("## Inside or outside: ray_contains against CGAL\n\n");
    printf("The 59k bunny (%zu triangles), one thread, millions of points "
           "a second, median of %d interleaved passes; libray's scene: "
           "%.1f MB (%.0f bytes a triangle), of which ray_contains' grid of "
           "labels %.0f kB (%.1f bytes a triangle, %u x %u x %u cells).  "
           "\"differ\": points whose answer (inside, "
           "on the surface, outside) is not CGAL's; \"on\": points on the "
           "surface (libray / CGAL's ON_BOUNDARY).\n\n",
           m.triangle_count, reps, (double)mem.now / 1e6,
           (double)mem.now / (double)m.triangle_count,
           (double)s->cgrid.bytes / 1e3,
           (double)s->cgrid.bytes / (double)m.triangle_count, s->cgrid.n[0],
           s->cgrid.n[1], s->cgrid.n[2]);
    printf("| points | n | libray (M/s) | CGAL (M/s) | libray / CGAL "
           "| differ | on | inside (libray) |\n"
           "|---|---|---|---|---|---|---|---|\n");
    contains_row("uniform in the box + 10%", s, cgal, uni, n_uniform, reps);
    contains_row("vertices and edge midpoints", s, cgal, hard, n_hard, reps);
    printf("\n");

    printf("### Closest points: ray_closest_point against CGAL's AABB "
           "tree\n\n");
    printf("The nearest point of the 59k bunny's surface (radius +Inf), "
           "one thread, thousands of points a second, median of %d "
           "interleaved passes over the first %zu of the uniform points; "
           "CGAL: AABB_tree::closest_point with its distance queries' "
           "acceleration, over the same mesh.  \"largest difference\": "
           "of the distances, over the bunny's diagonal.\n\n", wreps,
           n_close);
    printf("| points | n | libray (k/s) | CGAL (k/s) | libray / CGAL "
           "| largest difference |\n|---|---|---|---|---|---|\n");
    closest_row("uniform in the box + 10%", s, cgal, uni, n_close, wreps,
                diag);
    printf("\n");

    /* The holed bunny: 8 triangles from the middle of the list left out. */
    hidx = xmalloc(3 * m.triangle_count * sizeof *hidx);
    {
        size_t t, h = 0, first = m.triangle_count / 2;
        for (t = 0; t < m.triangle_count; t++)
            if (t < first || t >= first + holes) {
                memcpy(hidx + 3 * h, m.indices + 3 * t, 3 * sizeof *hidx);
                h++;
            }
        hm = m;
        hm.indices = hidx;
        hm.triangle_count = h;
    }
    if (ray_scene_new(&hs, NULL, NULL) != RAY_OK ||
        ray_scene_add_mesh(hs, &hm, RAY_NO_MATERIAL, NULL) != RAY_OK ||
        ray_scene_commit(hs) != RAY_OK)
        die("libray's holed scene");

    printf("### The winding number: through the BVH against every "
           "triangle\n\n");
    printf("The generalized winding number on the 59k bunny, one thread, "
           "thousands of points a second, median of %d interleaved passes "
           "over the first %zu of the uniform points: \"exact\" sums every "
           "triangle's solid angle (RAY_CONTAINS_WINDING_EXACT), \"fast\" "
           "takes a cluster farther than twice its radius by its order-2 "
           "expansion (Barill et al. 2018; the default).  The closed "
           "bunny and the holed one (%u triangles removed: nothing "
           "closed) are asked with RAY_CONTAINS_WINDING (every mesh by the "
           "winding number).  \"max error\": the largest |fast - exact| winding "
           "number; \"differ\": points inside by one and not the other; "
           "\"near 1/2\": points whose winding number is within 0.2 of "
           "1/2, which the fast path sums again exactly.\n\n",
           wreps, n_wind, holes);
    printf("| mesh | n | exact (k/s) | fast (k/s) | fast / exact "
           "| max error | differ | near 1/2 |\n"
           "|---|---|---|---|---|---|---|---|\n");
    winding_row("closed bunny, RAY_CONTAINS_WINDING", s,
                RAY_CONTAINS_WINDING, uni, n_wind, wreps);
    winding_row("holed bunny, RAY_CONTAINS_WINDING", hs,
                RAY_CONTAINS_WINDING, uni, n_wind, wreps);
    printf("\nThe expansions of the closed bunny: %.0f kB (%zu nodes, %.1f "
           "bytes a triangle), made by its first fast query.\n\n",
           (double)(s->n_wexp * sizeof *s->wexp) / 1e3, s->n_wexp,
           (double)(s->n_wexp * sizeof *s->wexp) /
               (double)m.triangle_count);
    if (!others()) {
        ray_scene_free(s);
        ray_scene_free(hs);
        free(hidx);
        free(uni);
        free(hard);
        obj_free(&om);
        return 0;
    }

grids:
    /* The grids: a cube round the box grown by 10%. */
    side = 1.2 * fmax(hi.x - lo.x, fmax(hi.y - lo.y, hi.z - lo.z));
    glo = ray_vec3_make(centre.x - side / 2, centre.y - side / 2,
                        centre.z - side / 2);
    ghi = ray_vec3_make(glo.x + side, glo.y + side, glo.z + side);
    step = side / (double)(gn - 1);
    gsz = (size_t)gn * gn * gn;
    ours = xmalloc(gsz * sizeof *ours);
    vdb = xmalloc(gsz * sizeof *vdb);
    ref = xmalloc(gsz);
    {
        ray_vec3 *p = xmalloc(gsz * sizeof *p);
        ray_inside *r = xmalloc(gsz * sizeof *r);
        unsigned a, b, c;
        for (c = 0; c < gn; c++)
            for (b = 0; b < gn; b++)
                for (a = 0; a < gn; a++)
                    p[((size_t)c * gn + b) * gn + a] =
                        sample(glo, ghi, gn, a, b, c);
#ifdef HAVE_CGAL
        cgal_side_query(cgal, &p[0].x, gsz, ref);
#else
        if (ray_contains(s, p, gsz, NULL, r) < 0)
            die("ray_contains failed");
        for (i = 0; i < gsz; i++)
            ref[i] = side_of(&r[i]);
#endif
        free(p);
        free(r);
    }

    printf("### Distance-field grids: ray_distance_grid against OpenVDB\n\n");
    printf("A %u^3 lattice over the bunny's box grown by 10%% (a cube), "
           "two threads on both sides, seconds, median of %d interleaved "
           "bakes (%d for the full field); sign errors: samples whose sign is not CGAL's inside or "
           "outside%s (on the surface: libray's 0 exactly, OpenVDB's "
           "either sign).  The holed bunny has %u triangles removed; "
           "libray answers it by the winding number (through the BVH), "
           "asked at every %u-th sample on each axis "
           "(%u^3 points), its time in microseconds a point.\n\n",
           gn, grid_reps[1], grid_reps[0],
#ifdef HAVE_CGAL
           "",
#else
           " (libray's ray_contains here: CGAL not built)",
#endif
           holes, sub, (gn + sub - 1) / sub);
    printf("| field | libray (s) | OpenVDB (s) | OpenVDB / libray "
           "| sign errors libray | sign errors OpenVDB |\n"
           "|---|---|---|---|---|---|\n");
    memset(&go, 0, sizeof go);
    go.threads = 2;
    {
        /* Full field, then a narrow band of 3 voxels. */
        static const double bands[2] = {0, 3};
        int b;
        for (b = band_only; b < 2; b++) {
            double to[8], tv[8], rt[8];
            int k;
            go.band = bands[b] * step;
            for (k = 0; k < grid_reps[b]; k++) {
                double t0 = now();
                if (ray_distance_grid(s, glo, ghi, gn, gn, gn, &go, ours) !=
                    RAY_OK)
                    die("ray_distance_grid failed");
                to[k] = now() - t0;
#ifdef HAVE_OPENVDB
                {
                    double l[3] = {glo.x, glo.y, glo.z};
                    tv[k] = vdb_bake(&m.vertices[0].x, m.vertex_count,
                                     m.indices, m.triangle_count, l, step,
                                     gn, bands[b], 2, vdb);
                    if (tv[k] < 0)
                        die("OpenVDB failed");
                }
                rt[k] = tv[k] / to[k];
#else
                tv[k] = rt[k] = 0;
#endif
            }
            printf("| closed bunny, %s | %.3f | ", b ? "band 3 voxels"
                                                        : "full",
                   median(to, grid_reps[b]));
#ifdef HAVE_OPENVDB
            printf("%.3f | %.2f | %zu | %zu |\n", median(tv, grid_reps[b]),
                   median(rt, grid_reps[b]), sign_errors(ours, ref, gsz, 1),
                   sign_errors(vdb, ref, gsz, 0));
#else
            (void)tv;
            printf("- | - | %zu | - |\n", sign_errors(ours, ref, gsz, 1));
#endif
        }
    }
    /* The holed bunny: OpenVDB's whole field; libray's sign at the
    ** subsample (the winding number through the BVH). */
    if (!band_only) {
        unsigned a, b, c;
        ray_vec3 *p;
        ray_inside *r;
        ray_contains_options co = {.flags = RAY_CONTAINS_WINDING};
        size_t k = 0, e_ours = 0, e_vdb = 0;
        double t0, t_ours, t_vdb = 0;
        nsub = (size_t)((gn + sub - 1) / sub);
        nsub = nsub * nsub * nsub;
        p = xmalloc(nsub * sizeof *p);
        r = xmalloc(nsub * sizeof *r);
        hsub_ref = xmalloc(nsub);
        for (c = 0; c < gn; c += sub)
            for (b = 0; b < gn; b += sub)
                for (a = 0; a < gn; a += sub) {
                    p[k] = sample(glo, ghi, gn, a, b, c);
                    hsub_ref[k++] = ref[((size_t)c * gn + b) * gn + a];
                }
        t0 = now();
        if (ray_contains(hs, p, nsub, &co, r) < 0)
            die("ray_contains (winding) failed");
        t_ours = now() - t0;
        for (k = 0; k < nsub; k++)
            if (hsub_ref[k] != 0)
                e_ours += (hsub_ref[k] > 0) != (r[k].inside != 0);
#ifdef HAVE_OPENVDB
        {
            double l[3] = {glo.x, glo.y, glo.z};
            t_vdb = vdb_bake(&hm.vertices[0].x, hm.vertex_count, hm.indices,
                             hm.triangle_count, l, step, gn, 0, 2, vdb);
            if (t_vdb < 0)
                die("OpenVDB failed");
            e_vdb = sign_errors(vdb, ref, gsz, 0);
        }
#endif
        printf("| holed bunny, full | %.1f us a point (%zu points) | ",
               1e6 * t_ours / (double)nsub, nsub);
#ifdef HAVE_OPENVDB
        printf("%.3f | - | %zu of %zu | %zu of %zu |\n", t_vdb, e_ours, nsub,
               e_vdb, gsz);
#else
        (void)t_vdb;
        (void)e_vdb;
        printf("- | - | %zu of %zu | - |\n", e_ours, nsub);
#endif
        free(p);
        free(r);
    }
    printf("\n");

#ifdef HAVE_CGAL
    cgal_side_free(cgal);
#endif
    ray_scene_free(s);
    ray_scene_free(hs);
    free(uni);
    free(hard);
    free(ours);
    free(vdb);
    free(ref);
    free(hsub_ref);
    free(hidx);
    obj_free(&om);
    return 0;
}
