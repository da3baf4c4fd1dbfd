/* SPDX-License-Identifier: MIT */
/*
** accuracy.c -- what accuracy costs in time, every knob in one run:
**
**   1. each primitive's variants (float / double, textbook / cancellation-
**      free, Cramer / watertight): nanoseconds per test on the same rays,
**      the error of t and of the hit point against long double (median,
**      99th percentile, maximum, in ulps), and failures on the stability
**      suite's hard-case sets (tests/hardcases.h);
**   2. per image (Whitted, Cornell box, bunny): samples per pixel (uniform
**      and adaptive), maximum depth, minimum weight: render time against
**      the error (RMSE, PSNR) from a converged reference;
**   3. robust ray offsets against a fixed epsilon: acne pixels and time.
**
**     accuracy DATA_DIR PLOT_DIR    (prints Markdown; writes .dat files to PLOT_DIR)
**
** Method: a warm-up, then the median of REPS repetitions; variants compared
** on the same inputs in the same run.  BENCH_QUICK=1: small sizes (< 1 min).
** Asserts nothing (bench/run.sh turns the output into bench/RESULTS.md).
*/
#include "hardcases.h"
#include "bench.h"
#include "scenes.h"
#include "reference.h"
#include "prim/watertight.h"

static int reps = 5;
static int quick, smoke;

/* The q-quantile (0..1) of v[0..n-1], sorting v. */
static double quantile(double *v, size_t n, double q)
{
    size_t k;
    if (n == 0)
        return 0;
    qsort(v, n, sizeof *v, bench_cmp_double);
    k = (size_t)(q * (double)(n - 1) + 0.5);
    return v[k];
}

/* ------------------------------------------------------------ workloads */

/*
** A workload: n rays each with its own primitive, half aimed at a point
** on it (hits) and half at a point beside it (misses), from 1 to 20 units
** away -- the same inputs for every variant of that primitive.
*/
typedef struct work {
    size_t n;
    ray_ray *rays;
    ray_vec3 *a, *b, *c;     /* sphere: a = centre, r[i] radius */
    double *r;
} work;

static void work_alloc(work *w, size_t n)
{
    w->n = n;
    w->rays = malloc(n * sizeof *w->rays);
    w->a = malloc(n * sizeof *w->a);
    w->b = malloc(n * sizeof *w->b);
    w->c = malloc(n * sizeof *w->c);
    w->r = malloc(n * sizeof *w->r);
}

static void work_free(work *w)
{
    free(w->rays);
    free(w->a);
    free(w->b);
    free(w->c);
    free(w->r);
}

static ray_ray aimed(rng *g, ray_vec3 target)
{
    ray_ray r;
    r.org = v3_add(target, v3_scale(rng_dir(g), 1 + 19 * rng_unit(g)));
    r.dir = v3_sub(target, r.org);
    r.tmin = 0;
    r.tmax = HUGE_VAL;
    return r;
}

static ray_vec3 rnd_point(rng *g, double s)
{
    return v3(s * (2 * rng_unit(g) - 1), s * (2 * rng_unit(g) - 1),
              s * (2 * rng_unit(g) - 1));
}

static work sphere_work(size_t n)
{
    rng g = {1};
    work w;
    size_t i;

    work_alloc(&w, n);
    for (i = 0; i < n; i++) {
        ray_vec3 nrm = rng_dir(&g);
        w.a[i] = rnd_point(&g, 100);
        w.r[i] = 0.1 + 5 * rng_unit(&g);
        w.rays[i] = aimed(&g, v3_add(w.a[i],
                                     v3_scale(nrm, w.r[i] * (i & 1 ? 1.2 : 0.8))));
    }
    return w;
}

static work triangle_work(size_t n)
{
    rng g = {2};
    work w;
    size_t i;

    work_alloc(&w, n);
    for (i = 0; i < n; i++) {
        double u = rng_unit(&g), v = rng_unit(&g);
        w.a[i] = rnd_point(&g, 100);
        w.b[i] = v3_add(w.a[i], v3_scale(rng_dir(&g), 0.5 + 3 * rng_unit(&g)));
        w.c[i] = v3_add(w.a[i], v3_scale(rng_dir(&g), 0.5 + 3 * rng_unit(&g)));
        if (u + v > 1) {
            u = 1 - u;
            v = 1 - v;
        }
        if (i & 1)                       /* beside the triangle */
            u = -0.2 - u;
        w.rays[i] = aimed(&g, v3_add(v3_add(v3_scale(w.a[i], 1 - u - v),
                                            v3_scale(w.b[i], u)),
                                     v3_scale(w.c[i], v)));
    }
    return w;
}

static work plane_work(size_t n)
{
    rng g = {3};
    work w;
    size_t i;

    work_alloc(&w, n);
    for (i = 0; i < n; i++) {
        ray_vec3 nrm = rng_dir(&g), t1, t2;
        ray__tangent_frame(nrm, &t1, &t2);
        w.a[i] = rnd_point(&g, 100);
        w.b[i] = nrm;
        w.rays[i] = aimed(&g, v3_add(w.a[i], v3_add(v3_scale(t1, 5 * rng_unit(&g)),
                                                    v3_scale(t2, 5 * rng_unit(&g)))));
        if (i & 1)                       /* pointing away: a miss */
            w.rays[i].dir = v3_scale(w.rays[i].dir, -1);
    }
    return w;
}

/* ------------------------------------------------------------ references */

/* The robust sphere root in long double: the reference for both forms. */
static int sphere_ref(const ray_ray *r, ray_vec3 c, double R, long double *t)
{
    long double f[3] = {(long double)r->org.x - c.x, (long double)r->org.y - c.y,
                        (long double)r->org.z - c.z};
    long double d[3] = {r->dir.x, r->dir.y, r->dir.z}, a = 0, b = 0, l2 = 0,
                f2 = 0, disc, cc, q, t0, t1;
    int k;

    for (k = 0; k < 3; k++) {
        a += d[k] * d[k];
        b -= f[k] * d[k];
        f2 += f[k] * f[k];
    }
    for (k = 0; k < 3; k++) {
        long double l = f[k] + b / a * d[k];
        l2 += l * l;
    }
    disc = ((long double)R - sqrtl(l2)) * ((long double)R + sqrtl(l2));
    if (disc < 0)
        return 0;
    cc = (sqrtl(f2) - R) * (sqrtl(f2) + R);
    q = b + (b < 0 ? -1 : 1) * sqrtl(a * disc);
    t0 = cc / q;
    t1 = q / a;
    if (t0 > t1) {
        long double s = t0;
        t0 = t1;
        t1 = s;
    }
    *t = t0 > 0 ? t0 : t1;
    return *t > 0;
}

/* Cramer's rule in long double: the triangle reference. */
static int triangle_ref(const ray_ray *r, ray_vec3 A, ray_vec3 B, ray_vec3 C,
                        long double *t)
{
    long double a = (long double)A.x - B.x, b = (long double)A.y - B.y,
                c = (long double)A.z - B.z, d = (long double)A.x - C.x,
                e = (long double)A.y - C.y, f = (long double)A.z - C.z,
                g = r->dir.x, h = r->dir.y, i = r->dir.z,
                j = (long double)A.x - r->org.x, k = (long double)A.y - r->org.y,
                l = (long double)A.z - r->org.z;
    long double m = a * (e * i - h * f) + b * (g * f - d * i) + c * (d * h - e * g);

    if (m == 0)
        return 0;
    *t = -(f * (a * k - j * b) + e * (j * c - a * l) + d * (b * l - k * c)) / m;
    return 1;
}

static int plane_ref(const ray_ray *r, ray_vec3 p, ray_vec3 n, long double *t)
{
    long double num = ((long double)p.x - r->org.x) * n.x +
                      ((long double)p.y - r->org.y) * n.y +
                      ((long double)p.z - r->org.z) * n.z;
    long double den = (long double)r->dir.x * n.x + (long double)r->dir.y * n.y +
                      (long double)r->dir.z * n.z;
    if (den == 0)
        return 0;
    *t = num / den;
    return *t > 0;
}

/* Hit-point error: |p - (o + t_ref d)| in ulps of the point's largest
** coordinate. */
static double point_ulps(ray_vec3 p, const ray_ray *r, long double t)
{
    long double q[3] = {r->org.x + t * r->dir.x, r->org.y + t * r->dir.y,
                        r->org.z + t * r->dir.z};
    long double e = fabsl(p.x - q[0]), m = fabsl(q[0]);
    double scale;

    if (fabsl(p.y - q[1]) > e)
        e = fabsl(p.y - q[1]);
    if (fabsl(p.z - q[2]) > e)
        e = fabsl(p.z - q[2]);
    if (fabsl(q[1]) > m)
        m = fabsl(q[1]);
    if (fabsl(q[2]) > m)
        m = fabsl(q[2]);
    scale = nextafter((double)m, HUGE_VAL) - (double)m;
    return (double)(e / (long double)scale);
}

/* ------------------------------------------------------------ variants */

enum {
    V_SPHERE_TEXTBOOK, V_SPHERE_ROBUST,
    V_TRI_FLOAT, V_TRI_CRAMER, V_TRI_WATERTIGHT,
    V_PLANE_RAW, V_PLANE,
    V_COUNT
};

static const char *variant_name[V_COUNT] = {
    "sphere, textbook b^2 - 4ac (double)",
    "sphere, cancellation-free (ray_sphere)",
    "triangle, Cramer in float",
    "triangle, Cramer in double (ray_triangle)",
    "triangle, watertight (ray_triangle_watertight)",
    "plane, hit point e + t d",
    "plane, projected hit point (ray_plane)"
};

/* Run variant v on ray i of w: 1 on a hit, with t and the point. */
static int run_variant(int v, const work *w, size_t i, double *t, ray_vec3 *p)
{
    const ray_ray *r = &w->rays[i];
    ray_hit h;
    int hit;

    switch (v) {
    case V_SPHERE_TEXTBOOK: hit = ray__sphere_naive(r, w->a[i], w->r[i], &h); break;
    case V_SPHERE_ROBUST: hit = ray_sphere(r, w->a[i], w->r[i], &h); break;
    case V_TRI_FLOAT:
        hit = ray__triangle_float(r, w->a[i], w->b[i], w->c[i], &h.t);
        h.p = v3_madd(r->org, h.t, r->dir);
        break;
    case V_TRI_CRAMER: hit = ray_triangle(r, w->a[i], w->b[i], w->c[i], &h); break;
    case V_TRI_WATERTIGHT:
        hit = ray_triangle_watertight(r, w->a[i], w->b[i], w->c[i], &h);
        break;
    case V_PLANE_RAW:
        hit = ray_plane(r, w->a[i], w->b[i], &h);
        h.p = v3_madd(r->org, h.t, r->dir);
        break;
    default: hit = ray_plane(r, w->a[i], w->b[i], &h); break;
    }
    *t = h.t;
    *p = h.p;
    return hit;
}

static int reference(int v, const work *w, size_t i, long double *t)
{
    if (v <= V_SPHERE_ROBUST)
        return sphere_ref(&w->rays[i], w->a[i], w->r[i], t);
    if (v <= V_TRI_WATERTIGHT)
        return triangle_ref(&w->rays[i], w->a[i], w->b[i], w->c[i], t);
    return plane_ref(&w->rays[i], w->a[i], w->b[i], t);
}

/* Nanoseconds per test: the median of reps passes over the workload. */
static double ns_per_test(int v, const work *w)
{
    double times[16], t, sink = 0;
    ray_vec3 p;
    int k;
    size_t i;

    for (k = 0; k <= reps; k++) {
        double t0 = now_seconds();
        for (i = 0; i < w->n; i++)
            if (run_variant(v, w, i, &t, &p))
                sink += t;
        if (k > 0)                       /* pass 0 is the warm-up */
            times[k - 1] = now_seconds() - t0;
    }
    if (sink == 42.0)                    /* keep the loop alive */
        printf(" ");
    return quantile(times, (size_t)reps, 0.5) * 1e9 / (double)w->n;
}

/* One row: timing, errors of t and p, and hard-case failures. */
static void primitive_row(int v, const work *w, const char *failures,
                          double *base_ns)
{
    double *et = malloc(w->n * sizeof *et), *ep = malloc(w->n * sizeof *ep);
    size_t i, m = 0, missed = 0;
    double ns = ns_per_test(v, w);

    for (i = 0; i < w->n; i++) {
        long double tr = 0;   /* set where reference() answers 1 */
        double t;
        ray_vec3 p;
        int hit = run_variant(v, w, i, &t, &p), ref = reference(v, w, i, &tr);
        if (ref && !hit && (i & 1) == 0)
            missed++;
        if (!hit || !ref)
            continue;
        et[m] = hc_ulps(t, tr);
        ep[m++] = point_ulps(p, &w->rays[i], tr);
    }
    if (*base_ns == 0)
        *base_ns = ns;
    printf("| %s | %.1f | %.2f | %.3g / %.3g / %.3g | %.3g / %.3g / %.3g | "
           "%zu | %s |\n", variant_name[v], ns, ns / *base_ns,
           quantile(et, m, 0.5), quantile(et, m, 0.99), quantile(et, m, 1.0),
           quantile(ep, m, 0.5), quantile(ep, m, 0.99), quantile(ep, m, 1.0),
           missed, failures);
    free(et);
    free(ep);
}

static void primitives(void)
{
    size_t n = smoke ? 200 : quick ? 20000 : 200000;
    long hard = smoke ? 50 : quick ? 5000 : 50000;
    work sw = sphere_work(n), tw = triangle_work(n), pw = plane_work(n);
    char f[4][160];
    double base;
    hc_mesh ico = hc_icosphere(v3(0, 0, 0), 2);
    hc_sphere_result sn = hc_sphere_far(1e-2, 1e6, 101, 1),
                     sr = hc_sphere_far(1e-2, 1e6, 101, 0);

    printf("### Primitives\n\n%zu rays per primitive, half hits and half "
           "misses, from 1 to 20 units away, primitives within 100 of the "
           "origin; errors against long double (64-bit significand) as "
           "median / 99th percentile / maximum in ulps of t and of the hit "
           "point's largest coordinate.  \"missed\": aimed hits not found.  "
           "Hard cases: the stability suite's sets (tests/hardcases.h).\n\n",
           n);
    printf("| variant | ns per test | time ratio | error of t (ulps) | "
           "error of point (ulps) | missed | hard cases |\n"
           "|---|---|---|---|---|---|---|\n");
    snprintf(f[0], sizeof f[0], "sphere r 1e-2 at 1e6: %ld of %ld rays wrong",
             sn.wrong, sn.rays);
    snprintf(f[1], sizeof f[1], "sphere r 1e-2 at 1e6: %ld of %ld wrong",
             sr.wrong, sr.rays);
    base = 0;
    primitive_row(V_SPHERE_TEXTBOOK, &sw, f[0], &base);
    primitive_row(V_SPHERE_ROBUST, &sw, f[1], &base);
    snprintf(f[0], sizeof f[0], "leaks %ld of %ld edge rays; false hits %ld "
             "of %ld at 1e-9", hc_leaks(&ico, v3(0, 0, 0), hard, 1, HC_CRAMER_FLOAT, 1),
             hard, hc_false_hits(1e-9, hard, HC_CRAMER_FLOAT), hard);
    snprintf(f[1], sizeof f[1], "leaks %ld of %ld edge rays; false hits %ld "
             "of %ld at 1e-9", hc_leaks(&ico, v3(0, 0, 0), hard, 1, HC_CRAMER, 1),
             hard, hc_false_hits(1e-9, hard, HC_CRAMER), hard);
    snprintf(f[2], sizeof f[2], "leaks %ld of %ld edge rays; false hits %ld "
             "of %ld at 1e-9", hc_leaks(&ico, v3(0, 0, 0), hard, 1, HC_WATERTIGHT, 1),
             hard, hc_false_hits(1e-9, hard, HC_WATERTIGHT), hard);
    base = 0;
    primitive_row(V_TRI_CRAMER, &tw, f[1], &base);
    primitive_row(V_TRI_FLOAT, &tw, f[0], &base);
    primitive_row(V_TRI_WATERTIGHT, &tw, f[2], &base);
    base = 0;
    primitive_row(V_PLANE, &pw, "-", &base);
    primitive_row(V_PLANE_RAW, &pw, "-", &base);
    {
        double t0, nb, nn;
        rng g = {4};
        size_t i, m = smoke ? 200 : quick ? 20000 : 200000;
        ray_vec3 *pts = malloc(4 * m * sizeof *pts);
        double abg[3], sink = 0;
        for (i = 0; i < 4 * m; i++)
            pts[i] = rnd_point(&g, 10);
        t0 = now_seconds();
        for (i = 0; i < m; i++)
            if (ray__barycentric_naive(pts[4 * i], pts[4 * i + 1], pts[4 * i + 2],
                                       pts[4 * i + 3], abg) == RAY_OK)
                sink += abg[0];
        nn = (now_seconds() - t0) * 1e9 / (double)m;
        t0 = now_seconds();
        for (i = 0; i < m; i++)
            if (ray_barycentric(pts[4 * i], pts[4 * i + 1], pts[4 * i + 2],
                                pts[4 * i + 3], abg, NULL) == RAY_OK)
                sink += abg[0];
        nb = (now_seconds() - t0) * 1e9 / (double)m;
        printf("| barycentric, divided by N.N (lecture) | %.1f | 1.00 | - | - "
               "| - | max drift of alpha+beta+gamma: %.2g |\n", nn,
               hc_bary_drift(hard, 1));
        printf("| barycentric, divided by the sum (ray_barycentric) | %.1f | "
               "%.2f | - | - | - | max drift: %.2g |\n", nb, nb / nn,
               hc_bary_drift(hard, 0));
        if (sink == 42.0)
            printf(" ");
        free(pts);
    }
    {
        /* Polygons: one variant (the ray-frame crossing test); its cost
        ** per test on quads, and the shared-edge partition. */
        rng g = {6};
        size_t i, m = smoke ? 200 : quick ? 20000 : 200000, both = 0, none = 0;
        double t0, ns;
        ray_vec3 q[4] = {{0.1, 0.2, 0}, {3.7, 0.3, 0}, {2.9, 4.1, 0},
                         {0.2, 3.3, 0}}, left[3], right[3];
        ray_hit h;
        ray_ray *rays = malloc(m * sizeof *rays);
        double sink = 0;
        left[0] = q[0], left[1] = q[1], left[2] = q[2];
        right[0] = q[0], right[1] = q[2], right[2] = q[3];
        for (i = 0; i < m; i++)
            rays[i] = aimed(&g, v3(4 * rng_unit(&g), 4 * rng_unit(&g), 0));
        t0 = now_seconds();
        for (i = 0; i < m; i++)
            if (ray_polygon(&rays[i], q, 4, &h))
                sink += h.t;
        ns = (now_seconds() - t0) * 1e9 / (double)m;
        if (sink == 42.0)
            printf(" ");
        free(rays);
        for (i = 0; i < (size_t)hard; i++) {
            double s = 0.01 + 0.98 * rng_unit(&g);
            ray_ray r = aimed(&g, v3_add(v3_scale(q[0], 1 - s), v3_scale(q[2], s)));
            int k = ray_polygon(&r, left, 3, &h) + ray_polygon(&r, right, 3, &h);
            both += k == 2;
            none += k == 0;
        }
        printf("| polygon, crossings in the ray's frame (ray_polygon, 4 "
               "vertices) | %.1f | - | - | - | - | rays at a shared edge in "
               "both: %zu, in neither: %zu of %ld |\n\n", ns, both, none, hard);
    }
    printf("Float Cramer is the fastest test in isolation, but it leaks "
           "through shared edges, hits points 1e-9 outside an edge about half "
           "the time, and its t is off by ~1e9 ulps of double: libray does "
           "not export float variants (a game keeps float vertices and "
           "converts them when adding a mesh; the scene stores doubles).  "
           "The watertight test costs 1.3 to 1.5 Cramer tests in isolation; "
           "inside a whole traversal the difference is 0 to 10%% (see the "
           "mesh benchmark's \"Triangle test inside the traversal\").\n\n");
    work_free(&sw);
    work_free(&tw);
    work_free(&pw);
    hc_mesh_free(&ico);
}


/* ------------------------------------------- bare primitive vs reference */

/*
** Each bare primitive against its minimal references (bench/reference.h)
** on the same rays: "ours" is the library's function, which fills the
** whole ray_hit; "ref, t only" decides hit or miss and t alone, by the
** same formulas; "ref, same record" fills the same record by the same
** formulas, written straight.  Timing: a warm-up pass, then reps rounds
** in which the three take turns (the order rotating each round), the
** median pass of each.  Mismatches: rays where a reference's answer is
** not the library's bit for bit (hit or miss and t; every field of the
** record for "same record"), the first few printed.
*/
enum { P_SPHERE, P_PLANE, P_TRIANGLE, P_WATERTIGHT, P_COUNT };
enum { R_OURS, R_REF_T, R_REF_HIT, R_COUNT };

static const char *prim_name[P_COUNT] = {
    "ray_sphere", "ray_plane", "ray_triangle (Cramer)",
    "ray_triangle_watertight"
};

/* Test ray i of w with primitive p, variant v: 1 on a hit, *h filled
** (only t for R_REF_T). */
static int prim_run(int p, int v, const work *w, size_t i, ray_hit *h)
{
    const ray_ray *r = &w->rays[i];

    switch (p * R_COUNT + v) {
    case P_SPHERE * R_COUNT + R_OURS: return ray_sphere(r, w->a[i], w->r[i], h);
    case P_SPHERE * R_COUNT + R_REF_T: return ref_sphere_t(r, w->a[i], w->r[i], &h->t);
    case P_SPHERE * R_COUNT + R_REF_HIT: return ref_sphere_hit(r, w->a[i], w->r[i], h);
    case P_PLANE * R_COUNT + R_OURS: return ray_plane(r, w->a[i], w->b[i], h);
    case P_PLANE * R_COUNT + R_REF_T: return ref_plane_t(r, w->a[i], w->b[i], &h->t);
    case P_PLANE * R_COUNT + R_REF_HIT: return ref_plane_hit(r, w->a[i], w->b[i], h);
    case P_TRIANGLE * R_COUNT + R_OURS:
        return ray_triangle(r, w->a[i], w->b[i], w->c[i], h);
    case P_TRIANGLE * R_COUNT + R_REF_T:
        return ref_triangle_t(r, w->a[i], w->b[i], w->c[i], &h->t);
    case P_TRIANGLE * R_COUNT + R_REF_HIT:
        return ref_triangle_hit(r, w->a[i], w->b[i], w->c[i], h);
    case P_WATERTIGHT * R_COUNT + R_OURS:
        return ray_triangle_watertight(r, w->a[i], w->b[i], w->c[i], h);
    case P_WATERTIGHT * R_COUNT + R_REF_T:
        return ref_watertight_t(r, w->a[i], w->b[i], w->c[i], &h->t);
    default:
        return ref_watertight_hit(r, w->a[i], w->b[i], w->c[i], h);
    }
}

/* One timed pass of variant v of primitive p over w, in seconds.  The
** switch is outside the loop: each loop calls its function directly. */
#define PRIM_PASS(call)                                                    \
    for (i = 0; i < w->n; i++)                                             \
        if (call)                                                          \
            sink += h.t;
static double prim_pass(int p, int v, const work *w)
{
    const ray_ray *r = w->rays;
    double t0 = now_seconds(), sink = 0;
    ray_hit h;
    size_t i;

    switch (p * R_COUNT + v) {
    case P_SPHERE * R_COUNT + R_OURS:
        PRIM_PASS(ray_sphere(&r[i], w->a[i], w->r[i], &h)) break;
    case P_SPHERE * R_COUNT + R_REF_T:
        PRIM_PASS(ref_sphere_t(&r[i], w->a[i], w->r[i], &h.t)) break;
    case P_SPHERE * R_COUNT + R_REF_HIT:
        PRIM_PASS(ref_sphere_hit(&r[i], w->a[i], w->r[i], &h)) break;
    case P_PLANE * R_COUNT + R_OURS:
        PRIM_PASS(ray_plane(&r[i], w->a[i], w->b[i], &h)) break;
    case P_PLANE * R_COUNT + R_REF_T:
        PRIM_PASS(ref_plane_t(&r[i], w->a[i], w->b[i], &h.t)) break;
    case P_PLANE * R_COUNT + R_REF_HIT:
        PRIM_PASS(ref_plane_hit(&r[i], w->a[i], w->b[i], &h)) break;
    case P_TRIANGLE * R_COUNT + R_OURS:
        PRIM_PASS(ray_triangle(&r[i], w->a[i], w->b[i], w->c[i], &h)) break;
    case P_TRIANGLE * R_COUNT + R_REF_T:
        PRIM_PASS(ref_triangle_t(&r[i], w->a[i], w->b[i], w->c[i], &h.t))
        break;
    case P_TRIANGLE * R_COUNT + R_REF_HIT:
        PRIM_PASS(ref_triangle_hit(&r[i], w->a[i], w->b[i], w->c[i], &h))
        break;
    case P_WATERTIGHT * R_COUNT + R_OURS:
        PRIM_PASS(ray_triangle_watertight(&r[i], w->a[i], w->b[i], w->c[i],
                                          &h)) break;
    case P_WATERTIGHT * R_COUNT + R_REF_T:
        PRIM_PASS(ref_watertight_t(&r[i], w->a[i], w->b[i], w->c[i], &h.t))
        break;
    default:
        PRIM_PASS(ref_watertight_hit(&r[i], w->a[i], w->b[i], w->c[i], &h))
        break;
    }
    if (sink == 42.0)                    /* keep the loop alive */
        printf(" ");
    return now_seconds() - t0;
}
#undef PRIM_PASS

/* Bitwise equality of two doubles and of two vectors. */
static int same_bits(double a, double b)
{
    return memcmp(&a, &b, sizeof a) == 0;
}

static int same_vec(ray_vec3 a, ray_vec3 b)
{
    return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z);
}

/* The rays of w where reference v's answer differs from ours, bit for
** bit; the first three printed (as a note under the table). */
static size_t prim_mismatches(int p, int v, const work *w, char *note,
                              size_t note_size)
{
    size_t i, bad = 0, used = strlen(note);

    for (i = 0; i < w->n; i++) {
        ray_hit a, b;
        int ha, hb, same;
        memset(&a, 0, sizeof a);
        memset(&b, 0, sizeof b);
        ha = prim_run(p, R_OURS, w, i, &a);
        hb = prim_run(p, v, w, i, &b);
        same = ha == hb && (!ha || same_bits(a.t, b.t));
        if (same && ha && v == R_REF_HIT)
            same = same_vec(a.p, b.p) && same_vec(a.n, b.n) &&
                   same_bits(a.u, b.u) && same_bits(a.v, b.v) &&
                   same_vec(a.p_err, b.p_err) && a.geom_id == b.geom_id &&
                   a.prim_id == b.prim_id && a.inst_id == b.inst_id;
        if (same)
            continue;
        if (bad++ < 3 && used < note_size)
            used += (size_t)snprintf(note + used, note_size - used,
                                     "%s %s, ray %zu: ours %d t %.17g, "
                                     "reference %d t %.17g.  ",
                                     prim_name[p],
                                     v == R_REF_T ? "t only" : "record", i,
                                     ha, a.t, hb, b.t);
    }
    return bad;
}

static void primitives_vs_reference(void)
{
    size_t n = smoke ? 200 : quick ? 20000 : 200000;
    work sw = sphere_work(n), tw = triangle_work(n), pw = plane_work(n);
    const work *wp[P_COUNT];
    char note[1024] = "";
    int p, preps = smoke ? 1 : quick ? 7 : 15;   /* a pass is 2 to 20 ms */

    wp[P_SPHERE] = &sw;
    wp[P_PLANE] = &pw;
    wp[P_TRIANGLE] = &tw;
    wp[P_WATERTIGHT] = &tw;
    printf("### Bare primitive vs reference\n\n"
           "The library's primitives (filling the whole ray_hit) against "
           "minimal references of the same accuracy on the same %zu rays "
           "as above (bench/reference.h): \"t only\" gives the same hit or "
           "miss and the same t, bit for bit, and nothing else; \"same "
           "record\" also fills t, p, n, u, v and p_err by the same "
           "formulas.  Nanoseconds per call, median of %d interleaved "
           "passes; mismatches: rays whose answer differs from ours in any "
           "bit (t only / same record).\n\n", n, preps);
    printf("| primitive | ours (ns) | ref, t only (ns) | ref, same record "
           "(ns) | ours / t only | ours / same record | mismatches |\n"
           "|---|---|---|---|---|---|---|\n");
    for (p = 0; p < P_COUNT; p++) {
        double times[R_COUNT][16], ns[R_COUNT];
        size_t bad_t, bad_h;
        int k, j;
        for (k = 0; k <= preps; k++)
            for (j = 0; j < R_COUNT; j++) {
                int v = (j + k) % R_COUNT;  /* the order rotates */
                double s = prim_pass(p, v, wp[p]);
                if (k > 0)                  /* round 0 is the warm-up */
                    times[v][k - 1] = s;
            }
        for (j = 0; j < R_COUNT; j++)
            ns[j] = quantile(times[j], (size_t)preps, 0.5) * 1e9 /
                    (double)wp[p]->n;
        bad_t = prim_mismatches(p, R_REF_T, wp[p], note, sizeof note);
        bad_h = prim_mismatches(p, R_REF_HIT, wp[p], note, sizeof note);
        printf("| %s | %.1f | %.1f | %.1f | %.2f | %.2f | %zu / %zu |\n",
               prim_name[p], ns[R_OURS], ns[R_REF_T], ns[R_REF_HIT],
               ns[R_OURS] / ns[R_REF_T], ns[R_OURS] / ns[R_REF_HIT], bad_t,
               bad_h);
    }
    printf("\n%s%s", note, note[0] ? "\n\n" : "");
    work_free(&sw);
    work_free(&tw);
    work_free(&pw);
}

/* ------------------------------------------------ needles and caps */

/*
** The edge functions and the determinants as they were before the
** compensated forms (issue 13, part 2), kept here so one run prints the
** before and the after on the same triangles.  old_watertight is
** ray__triangle_watertight_pre with plain double edge functions (long
** double when one is exactly 0); old_cramer is ray__triangle_test with
** the book's six shared minors.
*/
static int old_watertight(const ray_ray *r, ray_vec3 va, ray_vec3 vb,
                          ray_vec3 vc, double *t_out, double *beta_out,
                          double *gamma_out)
{
    ray__watertight wt;
    double pa[3], pb[3], pc[3], u, v, w;

    if (!ray__watertight_init(&wt, r))
        return 0;
    ray__frame_project(&wt.f, &va, pa);
    ray__frame_project(&wt.f, &vb, pb);
    ray__frame_project(&wt.f, &vc, pc);
    u = pc[0] * pb[1] - pc[1] * pb[0];
    v = pa[0] * pc[1] - pa[1] * pc[0];
    w = pb[0] * pa[1] - pb[1] * pa[0];
    if ((u == 0) | (v == 0) | (w == 0)) {
        u = (double)((long double)pc[0] * pb[1] - (long double)pc[1] * pb[0]);
        v = (double)((long double)pa[0] * pc[1] - (long double)pa[1] * pc[0]);
        w = (double)((long double)pb[0] * pa[1] - (long double)pb[1] * pa[0]);
    }
    if (dmin(dmin(u, v), w) < 0 && dmax(dmax(u, v), w) > 0)
        return 0;
    return ray__watertight_finish(
        &wt, u, v, w, pa[2], pb[2], pc[2],
        dmax(dmax(fabs(pa[0]), fabs(pb[0])), fabs(pc[0])),
        dmax(dmax(fabs(pa[1]), fabs(pb[1])), fabs(pc[1])), r->tmin, r->tmax,
        t_out, beta_out, gamma_out);
}

static int old_cramer(const ray_ray *r, ray_vec3 va, ray_vec3 vb, ray_vec3 vc,
                      double *t_out, double *beta_out, double *gamma_out)
{
    double a = va.x - vb.x, b = va.y - vb.y, c = va.z - vb.z;
    double d = va.x - vc.x, e = va.y - vc.y, f = va.z - vc.z;
    double g = r->dir.x, h = r->dir.y, i = r->dir.z;
    double j = va.x - r->org.x, k = va.y - r->org.y, l = va.z - r->org.z;
    double ei_hf = e * i - h * f, gf_di = g * f - d * i, dh_eg = d * h - e * g;
    double ak_jb = a * k - j * b, jc_al = j * c - a * l, bl_kc = b * l - k * c;
    double m = a * ei_hf + b * gf_di + c * dh_eg;
    double t, beta, gamma;

    if (m == 0)
        return 0;
    t = -(f * ak_jb + e * jc_al + d * bl_kc) / m;
    if (!(t > r->tmin && t < r->tmax))
        return 0;
    gamma = (i * ak_jb + h * jc_al + g * bl_kc) / m;
    if (!(gamma >= 0 && gamma <= 1))
        return 0;
    beta = (j * ei_hf + k * gf_di + l * dh_eg) / m;
    if (!(beta >= 0 && beta <= 1 - gamma))
        return 0;
    *t_out = t;
    *beta_out = beta;
    *gamma_out = gamma;
    return 1;
}

typedef int (*tri_test_fn)(const ray_ray *, ray_vec3, ray_vec3, ray_vec3,
                           double *, double *, double *);

/*
** One row per mode, version and offset: the conditioned errors of t, u
** (beta) and v (gamma) against hc_sliver_ref (tests/hardcases.h), median
** and maximum over n needles and n caps, the aimed rays the test missed,
** and ns per test on those rays.
*/
static void sliver_row(const char *name, tri_test_fn fn, double X, size_t n)
{
    ray_vec3 *v = malloc(6 * n * sizeof *v);
    ray_ray *rays = malloc(2 * n * sizeof *rays);
    double *e[3], times[16], sink = 0, asp, ns;
    size_t i, m = 0, missed = 0, valid = 0;
    rng g = {77};
    /* Called through a volatile pointer: no variant is inlined into the
    ** timing loop, as the library's are not. */
    tri_test_fn volatile call = fn;
    int k;

    for (k = 0; k < 3; k++)
        e[k] = malloc(2 * n * sizeof *e[k]);
    for (i = 0; i < 2 * n; i++)
        hc_sliver(&g, i < n ? HC_NEEDLE : HC_CAP, X, &v[3 * i], &rays[i], &asp);
    for (k = 0; k <= reps; k++) {
        double t0 = now_seconds(), t, b, c;
        for (i = 0; i < 2 * n; i++)
            if (call(&rays[i], v[3 * i], v[3 * i + 1], v[3 * i + 2], &t, &b, &c))
                sink += t;
        if (k > 0)
            times[k - 1] = now_seconds() - t0;
    }
    ns = quantile(times, (size_t)reps, 0.5) * 1e9 / (double)(2 * n);
    for (i = 0; i < 2 * n; i++) {
        double t = 0, b = 0, c = 0;
        hc_sliver_err er;
        int hit = fn(&rays[i], v[3 * i], v[3 * i + 1], v[3 * i + 2], &t, &b, &c);
        if (!hc_sliver_ref(&rays[i], v[3 * i], v[3 * i + 1], v[3 * i + 2], t,
                           b, c, &er))
            continue;
        valid++;
        if (!hit) {
            missed++;
            continue;
        }
        e[0][m] = er.t;
        e[1][m] = er.u;
        e[2][m++] = er.v;
    }
    printf("| %s | %g | %.1f |", name, X, ns);
    for (k = 0; k < 3; k++)
        printf(" %.2g / %.3g |", quantile(e[k], m, 0.5), quantile(e[k], m, 1.0));
    printf(" %zu of %zu |\n", missed, valid);
    if (sink == 42.0)
        printf(" ");
    for (k = 0; k < 3; k++)
        free(e[k]);
    free(v);
    free(rays);
}

static void slivers(void)
{
    static const double X[] = {0, 1e5, 1e6};
    size_t n = smoke ? 200 : quick ? 20000 : 100000;
    int k;

    printf("### Needle and cap triangles\n\n"
           "%zu needles and %zu caps (aspect ratio 10^U[2,7], longest edge "
           "0.5 to 5) at offset X from the origin, random orientations, rays "
           "from 1 to 20 units away (for X > 0 half of them from 0.5 X to "
           "1.5 X away) aimed at random interior points.  Errors "
           "in conditioned ulps against %s, median / maximum: t as |t - t*| "
           "|dir| |cos theta| / ulp(M), u and v as |u - u*| times the "
           "altitude from that vertex times |cos theta| / ulp(M), M the "
           "largest coordinate of the origin and the vertices "
           "(tests/hardcases.h, hc_sliver_ref).  \"before\": the plain "
           "double edge functions and the book's minors, kept in the bench; "
           "\"missed\": aimed rays the reference hits and the test does "
           "not.\n\n", n, n,
           HC_QUAD ? "__float128" : "long double (no __float128 here)");
    printf("| test | X | ns per test | t | u | v | missed |\n"
           "|---|---|---|---|---|---|---|\n");
    for (k = 0; k < 3; k++) {
        sliver_row("Cramer, before", old_cramer, X[k], n);
        sliver_row("Cramer (ray_triangle)", ray__triangle_test, X[k], n);
        sliver_row("watertight, before", old_watertight, X[k], n);
        sliver_row("watertight (ray_triangle_watertight)",
                   ray__triangle_watertight_test, X[k], n);
    }
    printf("\n");
}

static double render_timed(const ray_scene *s, const ray_camera *cam,
                           ray_render_options *o, float *img, ray_stats *st)
{
    double t = now_seconds();
    check(ray_render(s, cam, o, img, st), "ray_render");
    return now_seconds() - t;
}

static FILE *plot_file(const char *dir, const char *scene, const char *what)
{
    char path[600];
    snprintf(path, sizeof path, "%s/%s-%s.dat", dir, scene, what);
    return fopen(path, "w");
}

/* The curves of one scene. */
static void image_curves(const char *name, const char *tag, ray_scene *s,
                         const ray_camera *cam, unsigned w, unsigned h,
                         const char *plot_dir,
                         ray_scene *(*rebuild)(const ray_limits *, ray_camera *,
                                               const void *),
                         const void *arg)
{
    static const unsigned spp[] = {1, 4, 16, 64};
    static const double thr[] = {0.1, 0.03, 0.01};
    static const double weights[] = {0.0, 1.0 / 4096, 1.0 / 256, 1.0 / 64,
                                     1.0 / 16};
    size_t n = (size_t)w * h;
    float *ref = malloc(3 * n * sizeof *ref), *img = malloc(3 * n * sizeof *img);
    ray_render_options o;
    ray_stats st;
    FILE *fu = plot_file(plot_dir, tag, "uniform"),
         *fa = plot_file(plot_dir, tag, "adaptive");
    unsigned k, d;

    o = (ray_render_options){.width = w, .height = h};
    o.samples = smoke ? 4 : quick ? 64 : 256;
    o.seed = 0x5eed;         /* independent of the measured renders' noise */
    render_timed(s, cam, &o, ref, &st);
    printf("#### %s (%ux%u, reference %u samples per pixel)\n\n", name, w, h,
           o.samples);
    printf("| knob | setting | time (s) | rays | RMSE | PSNR (dB) |\n"
           "|---|---|---|---|---|---|\n");
    for (k = 0; k < 4; k++) {
        double t, e;
        o = (ray_render_options){.width = w, .height = h};
        o.samples = spp[k];
        t = render_timed(s, cam, &o, img, &st);
        e = rmse(img, ref, n);
        printf("| samples (uniform) | %u | %.3f | %llu | %.4f | %.1f |\n",
               spp[k], t, st.rays[0] + st.rays[1] + st.rays[2] + st.rays[3],
               e, psnr(e));
        if (fu != NULL)
            fprintf(fu, "%g %g\n", t, e);
    }
    for (k = 0; k < 3; k++) {
        double t, e;
        o = (ray_render_options){.width = w, .height = h};
        o.adaptive_threshold = thr[k];
        o.adaptive_depth = 2;
        t = render_timed(s, cam, &o, img, &st);
        e = rmse(img, ref, n);
        printf("| samples (adaptive, depth 2) | threshold %g, %.1f per pixel | "
               "%.3f | %llu | %.4f | %.1f |\n", thr[k],
               (double)st.rays[0] / (double)n, t,
               st.rays[0] + st.rays[1] + st.rays[2] + st.rays[3], e, psnr(e));
        if (fa != NULL)
            fprintf(fa, "%g %g\n", t, e);
    }
    for (d = 1; d <= 8; d += (d < 4 ? 1 : 4)) {
        ray_limits lim = {.max_depth = d, .min_weight = RAY_DEFAULT_MIN_WEIGHT,
                          .max_fanout = RAY_DEFAULT_MAX_FANOUT};
        ray_camera c2;
        ray_scene *s2 = rebuild(&lim, &c2, arg);
        double t, e;
        o = (ray_render_options){.width = w, .height = h};
        o.samples = smoke ? 1 : quick ? 4 : 16;
        t = render_timed(s2, &c2, &o, img, &st);
        e = rmse(img, ref, n);
        printf("| maximum depth (%u spp) | %u | %.3f | %llu | %.4f | %.1f |\n",
               o.samples, d, t,
               st.rays[0] + st.rays[1] + st.rays[2] + st.rays[3], e, psnr(e));
        ray_scene_free(s2);
    }
    for (k = 0; k < 5; k++) {
        ray_limits lim = {.max_depth = RAY_DEFAULT_MAX_DEPTH, .min_weight = weights[k],
                          .max_fanout = RAY_DEFAULT_MAX_FANOUT};
        ray_camera c2;
        ray_scene *s2 = rebuild(&lim, &c2, arg);
        double t, e;
        o = (ray_render_options){.width = w, .height = h};
        o.samples = smoke ? 1 : quick ? 4 : 16;
        t = render_timed(s2, &c2, &o, img, &st);
        e = rmse(img, ref, n);
        printf("| minimum weight (%u spp) | %g | %.3f | %llu | %.4f | %.1f |\n",
               o.samples, weights[k], t,
               st.rays[0] + st.rays[1] + st.rays[2] + st.rays[3], e, psnr(e));
        ray_scene_free(s2);
    }
    printf("\n");
    if (fu != NULL)
        fclose(fu);
    if (fa != NULL)
        fclose(fa);
    free(ref);
    free(img);
}

/* Rebuilders with other ray-tree limits, for the depth and weight sweeps. */
static ray_scene *rebuild_whitted(const ray_limits *lim, ray_camera *cam,
                                  const void *arg)
{
    (void)arg;
    return whitted_scene(cam, 1, lim);
}

static ray_scene *rebuild_cornell(const ray_limits *lim, ray_camera *cam,
                                  const void *arg)
{
    (void)arg;
    return cornell_scene(cam, 1, lim);
}

static ray_scene *rebuild_mesh(const ray_limits *lim, ray_camera *cam,
                               const void *arg)
{
    return mesh_scene(arg, cam, 1, lim, NULL);
}

/* --------------------------------------------------- offsets vs epsilon */

/*
** A diffuse shader that casts its own shadow ray, leaving the surface by
** one of the three methods of tests/hardcases.h, and counts acne: a
** shadow ray blocked although nothing but the surface itself lies between
** it and the light (the scene is one sphere).  Rendered on one thread, so
** the counter needs no lock.
*/
typedef struct acne_shader {
    int method;
    long lit, acne;
} acne_shader;

static void acne_shade(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                       ray_rgb *out)
{
    acne_shader *sh = ud;
    ray_light_sample ls;
    ray_ray shadow;
    double cosine;

    if (ray_light_sample_at(ctx, a, 0, 0, &ls) != RAY_OK)
        return;
    cosine = v3_dot(a->normal, ls.dir);
    if (cosine <= 0.05)
        return;
    sh->lit++;
    if (!hc_leave(a->hit, ls.dir, &ls.point, sh->method, &shadow))
        return;
    if (ray_occluded(a->scene, &shadow, NULL)) {
        sh->acne++;
        return;
    }
    out->r = out->g = out->b = cosine;
}

/* The acne scene: a unit sphere at (X, 0, 0), or (floor) the floor
** y = 0 as a two-triangle mesh quad 8 wide centred at (X, 0, X), the
** scene new users build first; a point light above, material "mat". */
static ray_scene *acne_scene(double X, int floor, const ray_material *mat,
                             ray_camera *cam)
{
    static const unsigned quad[6] = {0, 1, 2, 0, 2, 3};
    ray_vec3 v[4];
    ray_mesh mesh;
    ray_light l;
    ray_scene *s;
    unsigned id;

    memset(&l, 0, sizeof l);
    l.kind = RAY_LIGHT_POINT;
    l.position = floor ? v3(X + 3, 6, X + 4) : v3(X + 3, 4, 5);
    l.intensity = rgb(1, 1, 1);
    check(ray_scene_new(&s, NULL, NULL), "scene");
    check(ray_scene_add_material(s, mat, &id), "material");
    if (floor) {
        v[0] = v3(X - 4, 0, X - 4), v[1] = v3(X - 4, 0, X + 4);
        v[2] = v3(X + 4, 0, X + 4), v[3] = v3(X + 4, 0, X - 4);
        memset(&mesh, 0, sizeof mesh);
        mesh.vertices = v, mesh.vertex_count = 4;
        mesh.indices = quad, mesh.triangle_count = 2;
        check(ray_scene_add_mesh(s, &mesh, id, NULL), "floor");
    } else
        check(ray_scene_add_sphere(s, v3(X, 0, 0), 1, id, NULL), "sphere");
    check(ray_scene_add_light(s, &l, NULL), "light");
    check(ray_scene_commit(s), "commit");
    memset(cam, 0, sizeof *cam);
    cam->position = floor ? v3(X, 3, X + 5) : v3(X + 1, 1, 4);
    cam->look_at = floor ? v3(X, 0, X) : v3(X, 0, 0);
    cam->up = v3(0, 1, 0);
    cam->vfov = floor ? 60 : 40;
    return s;
}

static void offsets(void)
{
    static const double dist[] = {0, 1e5, 1e6};
    static const char *names[] = {"no offset", "fixed 1e-4", "ray_spawn"};
    unsigned w = smoke ? 8 : quick ? 96 : 256, h = w;
    float *img = malloc(3 * (size_t)w * h * sizeof *img);
    int k, m, floor;

    printf("### Ray offsets against a fixed epsilon\n\n"
           "A unit sphere at distance X from the origin, and the floor y = 0 "
           "(a two-triangle mesh quad, watertight test) centred at (X, 0, X), "
           "each lit by a point light, %ux%u pixels, one thread: acne pixels "
           "(lit, yet the shadow ray is blocked by the surface itself) and "
           "render time.  \"no offset\" starts the shadow ray at the hit "
           "point: only the intersection tests' own error bounds (a hit's t "
           "must lie past tmin by more than its rounding error) keep it "
           "clean.\n\n"
           "| scene | X | method | lit pixels | acne pixels | time (s) |\n"
           "|---|---|---|---|---|---|\n", w, h);
    for (floor = 0; floor < 2; floor++)
        for (k = 0; k < 3; k++)
            for (m = 0; m < 3; m++) {
                double X = dist[k], t;
                acne_shader sh = {0, 0, 0};
                ray_material mat = {acne_shade, NULL, 0, NULL};
                ray_camera cam;
                ray_render_options o;
                ray_scene *s;
                sh.method = m == 0 ? HC_NO_OFFSET
                                   : (m == 1 ? HC_FIXED_EPSILON : HC_SPAWN);
                mat.ud = &sh;
                s = acne_scene(X, floor, &mat, &cam);
                o = (ray_render_options){.width = w, .height = h};
                o.threads = 1;
                t = now_seconds();
                check(ray_render(s, &cam, &o, img, NULL), "render");
                t = now_seconds() - t;
                printf("| %s | %g | %s | %ld | %ld | %.3f |\n",
                       floor ? "floor y = 0" : "sphere", X, names[m], sh.lit,
                       sh.acne, t);
                ray_scene_free(s);
            }
    printf("\n");
    free(img);
}

int main(int argc, char **argv)
{
    const char *dir = argc > 1 ? argv[1] : "data";
    const char *plots = argc > 2 ? argv[2] : ".";
    char bunny[512];
    unsigned w, h;
    ray_camera cam;
    ray_scene *s;

    quick = bench_level() != BENCH_FULL;
    smoke = bench_level() == BENCH_SMOKE;
    reps = smoke ? 1 : quick ? 3 : 5;
    w = smoke ? 16 : quick ? 64 : 160;
    h = smoke ? 12 : quick ? 48 : 120;
    snprintf(bunny, sizeof bunny, "%s/bunny.obj", dir);
    printf("## What accuracy costs\n\n");
    if (getenv("BENCH_SLIVERS_ONLY") != NULL) {   /* the table alone */
        slivers();
        return 0;
    }
    if (getenv("BENCH_PRIMS_ONLY") != NULL) {     /* the table alone */
        primitives_vs_reference();
        return 0;
    }
    primitives();
    primitives_vs_reference();
    slivers();
    printf("### Images: time against error\n\n");
    s = whitted_scene(&cam, 1, NULL);
    image_curves("Whitted scene", "whitted", s, &cam, w, h, plots,
                 rebuild_whitted, NULL);
    ray_scene_free(s);
    s = cornell_scene(&cam, 1, NULL);
    image_curves("Cornell box", "cornell", s, &cam, w, h, plots,
                 rebuild_cornell, NULL);
    ray_scene_free(s);
    s = mesh_scene(bunny, &cam, 1, NULL, NULL);
    if (s != NULL) {
        image_curves("Stanford bunny (3,674 triangles)", "bunny", s, &cam, w,
                     h, plots, rebuild_mesh, bunny);
        ray_scene_free(s);
    }
    offsets();
    return 0;
}
