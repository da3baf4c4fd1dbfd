/* SPDX-License-Identifier: MIT */
/*
** hardcases.h -- the hard cases of the stability suite, as measurements
** that tests/check_numerics.c asserts on and bench/numerics.c prints:
** each runs the naive variant and the library's on the same inputs and
** reports errors against a higher-precision reference (long double), or
** counts of leaks, false hits, misclassifications and self-hits.
** Header-only; every function is static.  Uses the library's internal
** naive variants (src/prim/prim.h); its random inputs come from testkit.h's
** generator (rng, rng_unit, rng_dir).
*/
#ifndef RAY_HARDCASES_H
#define RAY_HARDCASES_H

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prim/prim.h"
#include "testkit.h"

/* |a - b| in units of the spacing of doubles at b. */
static inline double hc_ulps(double a, long double b)
{
    double ref = (double)b;
    double ulp = nextafter(fabs(ref), HUGE_VAL) - fabs(ref);
    return (double)(fabsl((long double)a - b) / (long double)ulp);
}

/* ------------------------------------------------------------- spheres */

typedef struct hc_sphere_result {
    long wrong;          /* hit/miss opposite to the exact answer */
    long rays;
    double max_ulps;     /* largest error of t, in ulps of t */
} hc_sphere_result;

/*
** A sphere of radius r at distance D down -z, an orthographic n x n grid
** of rays from z = 0 over [-1.2 r, 1.2 r]^2.  The exact answer, in long
** double: hit iff x^2 + y^2 < r^2 (rays within 1e-6 r^2 of the silhouette
** are skipped: their answer is decided by the rounding of the inputs),
** t = D - sqrt(r^2 - x^2 - y^2).
*/
static inline hc_sphere_result hc_sphere_far(double r, double D, int n,
                                             int naive)
{
    hc_sphere_result res = {0, 0, 0};
    ray_vec3 c = v3(0, 0, -D);
    int i, j;

    for (i = 0; i < n; i++)
        for (j = 0; j < n; j++) {
            double x = r * (-1.2 + 2.4 * (i + 0.5) / n);
            double y = r * (-1.2 + 2.4 * (j + 0.5) / n);
            long double rho2 = (long double)x * (long double)x +
                               (long double)y * (long double)y;
            long double gap = (long double)r * (long double)r - rho2;
            ray_ray ray;
            ray_hit h;
            int expect, got;

            if (fabsl(gap) < 1e-6L * (long double)r * (long double)r)
                continue;
            ray.org = v3(x, y, 0);
            ray.dir = v3(0, 0, -1);
            ray.tmin = 0;
            ray.tmax = HUGE_VAL;
            expect = gap > 0;
            got = naive ? ray__sphere_naive(&ray, c, r, &h)
                        : ray_sphere(&ray, c, r, &h);
            res.rays++;
            if (got != expect)
                res.wrong++;
            else if (got) {
                double e = hc_ulps(h.t, (long double)D - sqrtl(gap));
                if (e > res.max_ulps)
                    res.max_ulps = e;
            }
        }
    return res;
}

/*
** A ground sphere of radius R centred R below the origin, rays from
** height h down at slopes 1 .. 1e-3 below the horizontal (all hit near the
** origin).  Reference t: the near root of the same quadratic in long
** double, by the cancellation-free form.  Returns the largest error of t
** relative to t (the near root of the textbook form cancels).
*/
static inline double hc_ground(double R, double h, int naive)
{
    ray_vec3 c = v3(0, -R, 0);
    double worst = 0;
    int k;

    for (k = 0; k <= 30; k++) {
        double slope = pow(10.0, -3.0 * k / 30.0);
        ray_ray ray;
        ray_hit hit;
        long double a, b, cc, disc, t_ref;

        ray.org = v3(0, h, 0);
        ray.dir = v3(1, -slope, 0);
        ray.tmin = 0;
        ray.tmax = HUGE_VAL;
        /* f = org - c = (0, h + R, 0): a t^2 - 2 b t + cc = 0. */
        a = 1.0L + (long double)slope * (long double)slope;
        b = (long double)slope * ((long double)h + (long double)R);
        cc = (long double)h * ((long double)h + 2.0L * (long double)R);
        disc = b * b - a * cc;
        if (disc < 0)
            continue;
        t_ref = cc / (b + sqrtl(disc));
        if (!(naive ? ray__sphere_naive(&ray, c, R, &hit)
                    : ray_sphere(&ray, c, R, &hit)))
            return HUGE_VAL;                /* a miss is the worst error */
        if (fabsl((long double)hit.t - t_ref) / t_ref > (long double)worst)
            worst = (double)(fabsl((long double)hit.t - t_ref) / t_ref);
    }
    return worst;
}

/* --------------------------------------------------------- closed meshes */

typedef struct hc_mesh {
    ray_vec3 *v;
    unsigned *idx;
    size_t nv, nt;
} hc_mesh;

static inline void hc_mesh_free(hc_mesh *m)
{
    free(m->v);
    free(m->idx);
}

/* The mesh as ray_scene_add_mesh takes it (its arrays, borrowed). */
static inline ray_mesh hc_ray_mesh(const hc_mesh *h)
{
    ray_mesh m;

    memset(&m, 0, sizeof m);
    m.vertices = h->v;
    m.vertex_count = h->nv;
    m.indices = h->idx;
    m.triangle_count = h->nt;
    return m;
}

/* The closed cube [-1,1]^3 + centre, 12 triangles, outward winding. */
static inline hc_mesh hc_cube(ray_vec3 centre)
{
    static const unsigned faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6},
                                         {0, 1, 5, 4}, {2, 6, 7, 3},
                                         {0, 4, 6, 2}, {1, 3, 7, 5}};
    hc_mesh m;
    int k;

    m.nv = 8;
    m.nt = 12;
    m.v = malloc(8 * sizeof *m.v);
    m.idx = malloc(36 * sizeof *m.idx);
    for (k = 0; k < 8; k++)
        m.v[k] = v3(centre.x + (k & 1 ? 1 : -1), centre.y + (k & 2 ? 1 : -1),
                    centre.z + (k & 4 ? 1 : -1));
    for (k = 0; k < 6; k++) {
        unsigned *t = m.idx + 6 * k;
        t[0] = faces[k][0]; t[1] = faces[k][1]; t[2] = faces[k][2];
        t[3] = faces[k][0]; t[4] = faces[k][2]; t[5] = faces[k][3];
    }
    return m;
}

/*
** An icosphere of radius 2 around "centre": the icosahedron with every
** triangle split in four "level" times, the midpoints pushed out to the
** sphere (shared through an edge table, so the mesh is closed; vertices
** are computed around the origin then translated, as a mesh file holds
** them).
*/
static inline hc_mesh hc_icosphere(ray_vec3 centre, int level)
{
    static const double t0 = 1.6180339887498949;
    static const unsigned f20[20][3] = {
        {0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11},
        {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
        {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9},
        {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    double base[12][3] = {{-1, t0, 0}, {1, t0, 0}, {-1, -t0, 0}, {1, -t0, 0},
                          {0, -1, t0}, {0, 1, t0}, {0, -1, -t0}, {0, 1, -t0},
                          {t0, 0, -1}, {t0, 0, 1}, {-t0, 0, -1}, {-t0, 0, 1}};
    size_t nt = 20, cap_v = 12, nv = 12, i;
    hc_mesh m;
    int lv;

    for (lv = 0; lv < level; lv++)
        cap_v += 30 * ((size_t)1 << (2 * lv));   /* edges at that level */
    m.v = malloc(cap_v * sizeof *m.v);
    m.idx = malloc(3 * 20 * ((size_t)1 << (2 * level)) * sizeof *m.idx);
    for (i = 0; i < 12; i++) {
        ray_vec3 p = v3(base[i][0], base[i][1], base[i][2]);
        m.v[i] = v3_scale(p, 2.0 / v3_length(p));
    }
    for (i = 0; i < 20; i++)
        memcpy(m.idx + 3 * i, f20[i], sizeof f20[i]);
    for (lv = 0; lv < level; lv++) {
        size_t size = 8 * nt + 1, k;
        unsigned *key = malloc(2 * size * sizeof *key), *mid = malloc(size * sizeof *mid);
        unsigned *out = malloc(12 * nt * sizeof *out);
        for (k = 0; k < size; k++)
            mid[k] = 0xffffffffu;
        for (i = 0; i < nt; i++) {
            unsigned c3[3], e;
            for (e = 0; e < 3; e++) {
                unsigned a = m.idx[3 * i + e], b = m.idx[3 * i + (e + 1) % 3];
                unsigned lo = a < b ? a : b, hi = a < b ? b : a;
                size_t h = ((size_t)lo * 2654435761u + hi) % size;
                while (mid[h] != 0xffffffffu &&
                       (key[2 * h] != lo || key[2 * h + 1] != hi))
                    h = (h + 1) % size;
                if (mid[h] == 0xffffffffu) {
                    ray_vec3 p = v3_scale(v3_add(m.v[lo], m.v[hi]), 0.5);
                    key[2 * h] = lo;
                    key[2 * h + 1] = hi;
                    m.v[nv] = v3_scale(p, 2.0 / v3_length(p));
                    mid[h] = (unsigned)nv++;
                }
                c3[e] = mid[h];
            }
            {
                unsigned a = m.idx[3 * i], b = m.idx[3 * i + 1],
                         c = m.idx[3 * i + 2], *t = out + 12 * i;
                t[0] = a;     t[1] = c3[0]; t[2] = c3[2];
                t[3] = c3[0]; t[4] = b;     t[5] = c3[1];
                t[6] = c3[2]; t[7] = c3[1]; t[8] = c;
                t[9] = c3[0]; t[10] = c3[1]; t[11] = c3[2];
            }
        }
        memcpy(m.idx, out, 12 * nt * sizeof *out);
        nt *= 4;
        free(key);
        free(mid);
        free(out);
    }
    for (i = 0; i < nv; i++)
        m.v[i] = v3_add(m.v[i], centre);
    m.nv = nv;
    m.nt = nt;
    return m;
}

/*
** A closed spindle of needle triangles: a ring of n vertices of radius 1
** around an axis through "centre" (direction (1, 2, 3), to keep off the
** coordinate axes) and two apexes at +-H along it; 2n triangles, wound
** outwards, with ring edges of 2 pi / n and long edges of about H, so an
** aspect ratio of about H n / (2 pi).  Everything within 0.9 of the
** centre is inside, as hc_leaks wants.
*/
static inline hc_mesh hc_spindle(ray_vec3 centre, size_t n, double H)
{
    hc_mesh m;
    ray_vec3 axis = v3_scale(v3(1, 2, 3), 1 / sqrt(14.0)), t1, t2;
    size_t i;

    ray__tangent_frame(axis, &t1, &t2);
    m.nv = n + 2;
    m.nt = 2 * n;
    m.v = malloc(m.nv * sizeof *m.v);
    m.idx = malloc(3 * m.nt * sizeof *m.idx);
    for (i = 0; i < n; i++) {
        double a = 2 * RAY__PI * (double)i / (double)n;
        m.v[i] = v3_add(centre, v3_add(v3_scale(t1, cos(a)),
                                       v3_scale(t2, sin(a))));
    }
    m.v[n] = v3_add(centre, v3_scale(axis, H));
    m.v[n + 1] = v3_add(centre, v3_scale(axis, -H));
    for (i = 0; i < n; i++) {
        unsigned a = (unsigned)i, b = (unsigned)((i + 1) % n);
        unsigned *t = m.idx + 6 * i;
        t[0] = a, t[1] = b, t[2] = (unsigned)n;            /* top */
        t[3] = b, t[4] = a, t[5] = (unsigned)(n + 1);      /* bottom */
    }
    return m;
}

enum { HC_CRAMER_FLOAT, HC_CRAMER, HC_WATERTIGHT };

/* Does the ray hit any triangle of the mesh, by the given algorithm? */
static inline int hc_mesh_hit(const hc_mesh *m, const ray_ray *r, int algo)
{
    size_t i;

    for (i = 0; i < m->nt; i++) {
        const unsigned *t = m->idx + 3 * i;
        double th, b, g;
        int hit = algo == HC_CRAMER_FLOAT
                      ? ray__triangle_float(r, m->v[t[0]], m->v[t[1]],
                                            m->v[t[2]], &th)
                  : algo == HC_CRAMER
                      ? ray__triangle_test(r, m->v[t[0]], m->v[t[1]],
                                           m->v[t[2]], &th, &b, &g)
                      : ray__triangle_watertight_test(r, m->v[t[0]], m->v[t[1]],
                                                      m->v[t[2]], &th, &b, &g);
        if (hit)
            return 1;
    }
    return 0;
}

/*
** Rays from random points inside the closed mesh (within 0.9 of its
** centre), aimed exactly at a random vertex (on_edge = 0) or at a random
** point of a random edge (on_edge = 1): each must hit the mesh.  Returns
** the leaks: rays that hit nothing.
*/
static inline long hc_leaks(const hc_mesh *m, ray_vec3 centre, long rays,
                            int on_edge, int algo, unsigned long long seed)
{
    rng g = {seed};
    long leaks = 0, k;

    for (k = 0; k < rays; k++) {
        size_t ti = (size_t)(rng_unit(&g) * (double)m->nt) % m->nt;
        unsigned e = (unsigned)(rng_unit(&g) * 3) % 3;
        ray_vec3 a = m->v[m->idx[3 * ti + e]],
                 b = m->v[m->idx[3 * ti + (e + 1) % 3]], target;
        ray_vec3 org = v3_add(centre, v3_scale(rng_dir(&g), 0.9 * rng_unit(&g)));
        ray_ray r;
        if (on_edge) {
            double s = rng_unit(&g);
            target = v3_add(v3_scale(a, 1 - s), v3_scale(b, s));
        } else
            target = a;
        r.org = org;
        r.dir = v3_sub(target, org);
        r.tmin = 0;
        r.tmax = HUGE_VAL;
        leaks += !hc_mesh_hit(m, &r, algo);
    }
    return leaks;
}

/*
** Rays aimed at points a relative distance "gap" outside an edge of a
** triangle (away from the opposite vertex), from above: any hit is false.
*/
static inline long hc_false_hits(double gap, long rays, int algo)
{
    rng g = {99};
    long hits = 0, k;

    for (k = 0; k < rays; k++) {
        ray_vec3 a = v3(10 * rng_unit(&g), 10 * rng_unit(&g), 0);
        ray_vec3 b = v3_add(a, v3(1 + rng_unit(&g), 0.3 * rng_unit(&g), 0));
        ray_vec3 c = v3_add(a, v3(0.3 * rng_unit(&g), 1 + rng_unit(&g), 0));
        double s = rng_unit(&g);
        ray_vec3 on = v3_add(v3_scale(a, 1 - s), v3_scale(b, s));
        ray_vec3 out = v3_sub(on, v3_scale(v3_sub(c, on), gap));
        ray_vec3 org = v3_add(out, v3(rng_unit(&g) - 0.5, rng_unit(&g) - 0.5, 2));
        hc_mesh one;
        unsigned idx[3] = {0, 1, 2};
        ray_vec3 vv[3];
        ray_ray r;
        vv[0] = a;
        vv[1] = b;
        vv[2] = c;
        one.v = vv;
        one.idx = idx;
        one.nt = 1;
        one.nv = 3;
        r.org = org;
        r.dir = v3_sub(out, org);
        r.tmin = 0;
        r.tmax = HUGE_VAL;
        hits += hc_mesh_hit(&one, &r, algo);
    }
    return hits;
}

/* ------------------------------------------------------- self-intersection */

enum { HC_NO_OFFSET, HC_FIXED_EPSILON, HC_SPAWN };

/* The ray leaving hit h toward dir, or toward "to" (if non-NULL) as a
** shadow segment, by one of the three methods: no offset at all; the
** fixed epsilon of many tracers, origin p + 1e-4 n; ray_spawn(_to). */
static inline int hc_leave(const ray_hit *h, ray_vec3 dir, const ray_vec3 *to,
                           int method, ray_ray *out)
{
    ray_vec3 n = v3_dot(dir, h->n) < 0 ? v3_scale(h->n, -1.0) : h->n;

    if (method == HC_SPAWN)
        return (to ? ray_spawn_to(h, *to, out) : ray_spawn(h, dir, out)) ==
               RAY_OK;
    out->org = method == HC_FIXED_EPSILON ? v3_madd(h->p, 1e-4, n) : h->p;
    out->dir = to ? v3_sub(*to, out->org) : dir;
    out->tmin = 0;
    out->tmax = to ? 1.0 : HUGE_VAL;
    return 1;
}

/*
** From "n" primary hits on a unit sphere centred at (X, 0, 0), an outgoing
** ray in a random direction of the normal's hemisphere each: a self-hit
** is any hit of the same (convex) sphere.
*/
static inline long hc_sphere_acne(double X, long n, int method)
{
    rng g = {7};
    ray_vec3 c = v3(X, 0, 0);
    long self = 0, k;

    for (k = 0; k < n; k++) {
        ray_vec3 d = rng_dir(&g), w = rng_dir(&g);
        ray_ray prim, out;
        ray_hit h, h2;
        prim.org = v3_add(c, v3_scale(d, 5));
        prim.dir = v3_scale(d, -1);
        prim.tmin = 0;
        prim.tmax = HUGE_VAL;
        if (!ray_sphere(&prim, c, 1.0, &h))
            continue;
        if (v3_dot(w, h.n) < 0)
            w = v3_scale(w, -1);
        if (!hc_leave(&h, w, NULL, method, &out))
            continue;
        self += ray_sphere(&out, c, 1.0, &h2);
    }
    return self;
}

/*
** A thin sheet: two parallel planes "gap" apart near (X, 0, X).  From n hits
** on the lower one, shadow rays toward a light high above: each must be
** blocked by the upper plane.  Returns the rays that leak through.
*/
static inline long hc_thin_sheet_leaks(double X, double gap, long n,
                                       int method)
{
    rng g = {11};
    long leaks = 0, k;

    for (k = 0; k < n; k++) {
        ray_vec3 light, at = v3(X + 10 * rng_unit(&g), gap / 2, X + 10 * rng_unit(&g));
        ray_ray prim, out;
        ray_hit h, h2;
        prim.org = at;
        prim.dir = v3(0.3 * rng_unit(&g) - 0.15, -1, 0.3 * rng_unit(&g) - 0.15);
        prim.tmin = 0;
        prim.tmax = HUGE_VAL;
        if (!ray_plane(&prim, v3(X, 0, X), v3(0, 1, 0), &h))
            continue;
        light = v3(X, 100, X);
        if (!hc_leave(&h, v3_sub(light, h.p), &light, method, &out))
            continue;
        leaks += !ray_plane(&out, v3(X, gap, X), v3(0, 1, 0), &h2);
    }
    return leaks;
}

/* ------------------------------------------------------------ barycentric */

/* The largest |alpha + beta + gamma - 1| over n random triangles in
** [-10, 10]^3 and random points inside them. */
static inline double hc_bary_drift(long n, int naive)
{
    rng g = {5};
    double worst = 0;
    long k;

    for (k = 0; k < n; k++) {
        ray_vec3 a = v3(20 * rng_unit(&g) - 10, 20 * rng_unit(&g) - 10, 20 * rng_unit(&g) - 10);
        ray_vec3 b = v3(20 * rng_unit(&g) - 10, 20 * rng_unit(&g) - 10, 20 * rng_unit(&g) - 10);
        ray_vec3 c = v3(20 * rng_unit(&g) - 10, 20 * rng_unit(&g) - 10, 20 * rng_unit(&g) - 10);
        double u = rng_unit(&g), v = rng_unit(&g), abg[3], e;
        ray_vec3 p;
        if (u + v > 1) {
            u = 1 - u;
            v = 1 - v;
        }
        p = v3_add(v3_add(v3_scale(a, 1 - u - v), v3_scale(b, u)),
                   v3_scale(c, v));
        int rc = naive ? ray__barycentric_naive(p, a, b, c, abg)
                       : ray_barycentric(p, a, b, c, abg, NULL);
        if (rc != RAY_OK)
            continue;
        e = fabs(abg[0] + abg[1] + abg[2] - 1);
        if (e > worst)
            worst = e;
    }
    return worst;
}

/* ------------------------------------------------- needles and caps */

/*
** The reference arithmetic for slivers: __float128 (113-bit significand)
** where the compiler has it (gcc and clang on x86-64 and AArch64; only
** + - * / are used, which libgcc/compiler-rt provide, so no libquadmath),
** long double otherwise (64 bits on x86, often just double elsewhere:
** HC_QUAD says which, and callers print it).  __extension__ keeps
** -pedantic quiet about the type.
*/
#if defined(__SIZEOF_FLOAT128__) && !defined(HC_NO_FLOAT128)
#define HC_QUAD 1
__extension__ typedef __float128 hc_quad;
#else
#define HC_QUAD 0
typedef long double hc_quad;
#endif

enum { HC_NEEDLE, HC_CAP };

/*
** A sliver and a ray aimed at it, at offset X from the origin.  Needle:
** a short edge of length L / aspect and two long ones (L in [0.5, 5]);
** cap: two vertices L apart and the third near the segment between them,
** L / aspect off it (one angle near 180 degrees).  Aspect 10^U[2, 7], a
** random orientation, the vertices rotated so the odd edge is in any of
** the three positions, then translated by X along a random direction (the
** vertices round to doubles there).  The ray: from 1 to 20 units away
** (half of them, for X >= 20; the others from 0.5 X to 1.5 X away), in a
** random direction, aimed at a random interior point.
*/
static inline void hc_sliver(rng *g, int kind, double X, ray_vec3 v[3],
                             ray_ray *r, double *aspect)
{
    ray_vec3 e1 = rng_dir(g), e2, n = rng_dir(g), c, p[3], target;
    double L = 0.5 + 4.5 * rng_unit(g), h, a, b;
    int k = (int)(3 * rng_unit(g)) % 3, i;

    *aspect = pow(10, 2 + 5 * rng_unit(g));
    h = L / *aspect;
    e2 = v3_cross(n, e1);                /* unit: redraw if nearly parallel */
    while (v3_dot(e2, e2) < 1e-2) {
        n = rng_dir(g);
        e2 = v3_cross(n, e1);
    }
    e2 = v3_scale(e2, 1 / sqrt(v3_dot(e2, e2)));
    c = v3_add(rng_point(g, -1, 1), v3_scale(rng_dir(g), X));
    p[0] = c;
    if (kind == HC_NEEDLE) {
        p[1] = v3_add(c, v3_scale(e2, h));
        p[2] = v3_add(c, v3_add(v3_scale(e1, L), v3_scale(e2, h * rng_unit(g))));
    } else {
        p[1] = v3_add(c, v3_scale(e1, L));
        p[2] = v3_add(c, v3_add(v3_scale(e1, L * (0.2 + 0.6 * rng_unit(g))),
                                v3_scale(e2, h)));
    }
    for (i = 0; i < 3; i++)
        v[i] = p[(i + k) % 3];
    a = rng_unit(g);
    b = rng_unit(g);
    if (a + b > 1) {
        a = 1 - a;
        b = 1 - b;
    }
    target = v3_add(v3_add(v3_scale(v[0], 1 - a - b), v3_scale(v[1], a)),
                    v3_scale(v[2], b));
    /* Half from 1 to 20 units away, half from as far as the offset (a
    ** camera near the origin looking at a far triangle). */
    r->org = v3_add(target, v3_scale(rng_dir(g), rng_unit(g) < 0.5 || X < 20
                                                    ? 1 + 19 * rng_unit(g)
                                                    : X * (0.5 + rng_unit(g))));
    r->dir = v3_sub(target, r->org);
    r->tmin = 0;
    r->tmax = HUGE_VAL;
}

/* The errors of one sliver hit, in conditioned ulps (see hc_sliver_ref). */
typedef struct hc_sliver_err {
    double t, u, v;
} hc_sliver_err;

/*
** The exact t*, beta*, gamma* of the double inputs, by Moeller-Trumbore's
** triple products in hc_quad (the differences of doubles within 2^60 of
** each other are exact in 113 bits; the products then round at 2^-113,
** far below what is measured), and the errors of (t, beta, gamma) in
** conditioned ulps:
**
**   t:     |t - t*| |dir| |cos theta| / ulp(M)
**   beta:  |beta - beta*| alt_B |cos theta| / ulp(M)
**   gamma: |gamma - gamma*| alt_C |cos theta| / ulp(M)
**
** M is the largest |component| of the origin and the three vertices,
** theta the angle between the ray and the normal, alt_B the altitude of
** the triangle from B (to the line CA), alt_C from C.  Why these: moving
** the inputs by an ulp of M moves the hit point along the ray by about
** ulp(M) / |cos theta|, and moves the lines of the edges by about ulp(M),
** which changes a barycentric by ulp(M) / altitude -- so an algorithm
** exact on inputs perturbed by a few ulps scores a few, whatever the
** shape.  (Scaling the barycentrics' errors by the triangle's extent
** instead would charge a needle its aspect ratio for a one-ulp move of a
** vertex across the needle: no double algorithm could meet that.)
** Returns 0 when the reference misses (target outside after rounding).
*/
static inline int hc_sliver_ref(const ray_ray *r, ray_vec3 A, ray_vec3 B,
                                ray_vec3 C, double t, double beta,
                                double gamma, hc_sliver_err *err)
{
    hc_quad e1[3] = {(hc_quad)B.x - (hc_quad)A.x, (hc_quad)B.y - (hc_quad)A.y,
                     (hc_quad)B.z - (hc_quad)A.z};
    hc_quad e2[3] = {(hc_quad)C.x - (hc_quad)A.x, (hc_quad)C.y - (hc_quad)A.y,
                     (hc_quad)C.z - (hc_quad)A.z};
    hc_quad s[3] = {(hc_quad)r->org.x - (hc_quad)A.x, (hc_quad)r->org.y - (hc_quad)A.y,
                    (hc_quad)r->org.z - (hc_quad)A.z};
    hc_quad d[3] = {(hc_quad)r->dir.x, (hc_quad)r->dir.y, (hc_quad)r->dir.z},
            pv[3], qv[3], nq[3], det, ts, bs, gs;
    double nl, cosine, M, ulp, dl;
    const ray_vec3 *all[4] = {&r->org, &A, &B, &C};
    int i;

    pv[0] = d[1] * e2[2] - d[2] * e2[1];          /* d x e2 */
    pv[1] = d[2] * e2[0] - d[0] * e2[2];
    pv[2] = d[0] * e2[1] - d[1] * e2[0];
    qv[0] = s[1] * e1[2] - s[2] * e1[1];          /* s x e1 */
    qv[1] = s[2] * e1[0] - s[0] * e1[2];
    qv[2] = s[0] * e1[1] - s[1] * e1[0];
    nq[0] = e1[1] * e2[2] - e1[2] * e2[1];        /* e1 x e2 */
    nq[1] = e1[2] * e2[0] - e1[0] * e2[2];
    nq[2] = e1[0] * e2[1] - e1[1] * e2[0];
    det = e1[0] * pv[0] + e1[1] * pv[1] + e1[2] * pv[2];
    if (det == 0)
        return 0;
    bs = (s[0] * pv[0] + s[1] * pv[1] + s[2] * pv[2]) / det;
    gs = (d[0] * qv[0] + d[1] * qv[1] + d[2] * qv[2]) / det;
    ts = (e2[0] * qv[0] + e2[1] * qv[1] + e2[2] * qv[2]) / det;
    if (!(bs >= 0 && gs >= 0 && bs + gs <= 1 && ts > 0))
        return 0;
    nl = sqrt((double)(nq[0] * nq[0] + nq[1] * nq[1] + nq[2] * nq[2]));
    dl = sqrt(v3_dot(r->dir, r->dir));
    cosine = fabs((double)(det / (hc_quad)nl)) / dl;   /* det = -(e1 x e2) . d */
    M = 0;
    for (i = 0; i < 4; i++)
        M = fmax(M, fmax(fabs(all[i]->x), fmax(fabs(all[i]->y),
                                               fabs(all[i]->z))));
    ulp = nextafter(M, HUGE_VAL) - M;
    err->t = fabs((double)((hc_quad)t - ts)) * dl * cosine / ulp;
    err->u = fabs((double)((hc_quad)beta - bs)) * (nl / v3_length(v3_sub(C, A))) *
             cosine / ulp;
    err->v = fabs((double)((hc_quad)gamma - gs)) * (nl / v3_length(v3_sub(B, A))) *
             cosine / ulp;
    return 1;
}

#endif
