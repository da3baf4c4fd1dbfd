/* SPDX-License-Identifier: MIT */
/*
** surfaces.c -- what the curved surfaces cost: the generic root finders
** (ray_implicit, ray_parametric) against the exact or flat methods on the
** same rays, with the accuracy of their hit points.  Prints Markdown;
** asserts nothing (tests/check_implicit.c and check_parametric.c do).
*/
#include <stdio.h>
#include <string.h>

#include "bench.h"
#include "core/vec.h"
#include "prim/prim.h"         /* ray__implicit_torus */

typedef int (*method_fn)(const ray_ray *r, const void *obj, ray_hit *hit);

/* The objects, each with its exact distance (long double) where known. */
typedef struct object {
    ray_torus_params torus;
    ray_implicit_surface sphere_st, sphere_br, torus_st, torus_br, blobs;
    ray_parametric_surface flat, dome;
    ray_vec3 flat_cp[16], dome_cp[16];
    ray_blob blob[5];
    ray_blobs_params blob_params;
} object;

static double unit_sphere_sdf(void *ud, ray_vec3 p)
{
    (void)ud;
    return sqrt(p.x * p.x + p.y * p.y + p.z * p.z) - 1.0;
}

static int m_sphere(const ray_ray *r, const void *o, ray_hit *h)
{
    (void)o;
    return ray_sphere(r, v3(0, 0, 0), 1.0, h);
}
static int m_sphere_st(const ray_ray *r, const void *o, ray_hit *h)
{
    return ray_implicit(r, &((const object *)o)->sphere_st, h);
}
static int m_sphere_br(const ray_ray *r, const void *o, ray_hit *h)
{
    return ray_implicit(r, &((const object *)o)->sphere_br, h);
}
static int m_torus(const ray_ray *r, const void *o, ray_hit *h)
{
    return ray_torus(r, &((const object *)o)->torus, h);
}
static int m_torus_st(const ray_ray *r, const void *o, ray_hit *h)
{
    return ray_implicit(r, &((const object *)o)->torus_st, h);
}
static int m_torus_br(const ray_ray *r, const void *o, ray_hit *h)
{
    return ray_implicit(r, &((const object *)o)->torus_br, h);
}
static int m_blobs(const ray_ray *r, const void *o, ray_hit *h)
{
    return ray_implicit(r, &((const object *)o)->blobs, h);
}
/* The flat patch's own quad as two triangles (Cramer). */
static int m_flat_tris(const ray_ray *r, const void *o, ray_hit *h)
{
    const ray_vec3 *cp = ((const object *)o)->flat_cp;
    return ray_triangle(r, cp[0], cp[3], cp[15], h) ||
           ray_triangle(r, cp[0], cp[15], cp[12], h);
}
static int m_flat(const ray_ray *r, const void *o, ray_hit *h)
{
    return ray_parametric(r, &((const object *)o)->flat, h);
}
static int m_dome(const ray_ray *r, const void *o, ray_hit *h)
{
    return ray_parametric(r, &((const object *)o)->dome, h);
}

/* Exact distances from p to each surface, in long double. */
static double d_sphere(ray_vec3 p, const object *o)
{
    long double x = p.x, y = p.y, z = p.z;
    (void)o;
    return (double)fabsl(sqrtl(x * x + y * y + z * z) - 1.0L);
}
static double d_torus(ray_vec3 p, const object *o)
{
    long double x = p.x, y = p.y, z = p.z;
    long double rho = sqrtl(x * x + z * z);
    return (double)fabsl(sqrtl((rho - o->torus.major) * (rho - o->torus.major) +
                               y * y) - o->torus.minor);
}
static double d_flat(ray_vec3 p, const object *o)
{
    (void)o;
    return fabs(p.z);
}

typedef struct row {
    const char *surface, *method;
    method_fn fn;
    double (*dist)(ray_vec3 p, const object *o);
    int baseline;            /* 1: the reference row for the ratio */
    double reach;            /* rays aim within this radius */
} row;

/* Rays from a sphere of radius 4 toward points within "reach" of the
** origin (the Bezier patches sit around it too). */
static void make_rays(ray_ray *rays, int n, double reach)
{
    rng g = {12345};
    int i;

    for (i = 0; i < n; i++) {
        ray_vec3 o = v3_scale(rng_dir(&g), 4.0);
        ray_vec3 aim = v3_scale(rng_dir(&g), reach * cbrt(rng_unit(&g)));
        rays[i].org = o;
        rays[i].dir = v3_sub(aim, o);
        rays[i].tmin = 0;
        rays[i].tmax = HUGE_VAL;
    }
}

static void setup(object *o)
{
    int i, j;

    memset(o, 0, sizeof *o);
    o->sphere_st.f = unit_sphere_sdf;
    o->sphere_st.lo = v3(-1, -1, -1);
    o->sphere_st.hi = v3(1, 1, 1);
    o->sphere_st.lipschitz = 1;
    o->sphere_br = o->sphere_st;
    o->sphere_br.lipschitz = 0;
    o->torus.center = v3(0, 0, 0);
    o->torus.axis = v3(0, 1, 0);
    o->torus.major = 1.0;
    o->torus.minor = 0.25;
    ray__implicit_torus(&o->torus, &o->torus_st);
    o->torus_br = o->torus_st;
    o->torus_br.lipschitz = 0;
    for (i = 0; i < 5; i++) {
        o->blob[i].center = v3(0.4 * cos(1.3 * i), 0.3 * sin(2.1 * i),
                               0.35 * cos(0.7 * i + 1));
        o->blob[i].radius = 0.7;
        o->blob[i].strength = 1;
    }
    o->blob_params.blobs = o->blob;
    o->blob_params.count = 5;
    o->blob_params.threshold = 0.4;
    ray_implicit_blobs(&o->blob_params, &o->blobs);
    for (i = 0; i < 4; i++)
        for (j = 0; j < 4; j++) {
            o->flat_cp[4 * i + j] = v3(-1 + 2.0 * j / 3, -1 + 2.0 * i / 3, 0);
            o->dome_cp[4 * i + j] =
                v3(-1 + 2.0 * j / 3, -1 + 2.0 * i / 3,
                   (i == 1 || i == 2) && (j == 1 || j == 2) ? 1.0 : 0.0);
        }
    ray_bezier_surface(o->flat_cp, &o->flat);
    ray_bezier_surface(o->dome_cp, &o->dome);
}

int main(void)
{
    static const row rows[] = {
        {"sphere", "ray_sphere (quadratic)", m_sphere, d_sphere, 1, 1.2},
        {"sphere", "ray_implicit, sphere tracing (L = 1)", m_sphere_st,
         d_sphere, 0, 1.2},
        {"sphere", "ray_implicit, bracketing (no bound)", m_sphere_br,
         d_sphere, 0, 1.2},
        {"torus", "ray_torus (quartic)", m_torus, d_torus, 1, 1.3},
        {"torus", "ray_implicit, sphere tracing (L = 1)", m_torus_st,
         d_torus, 0, 1.3},
        {"torus", "ray_implicit, bracketing (no bound)", m_torus_br, d_torus,
         0, 1.3},
        {"5 metaballs", "ray_implicit_blobs, sphere tracing", m_blobs, NULL,
         1, 1.2},
        {"flat square", "two triangles (ray_triangle)", m_flat_tris, d_flat,
         1, 1.2},
        {"flat square", "bicubic patch, ray_parametric", m_flat, d_flat, 0,
         1.2},
        {"dome", "bicubic patch, ray_parametric", m_dome, NULL, 0, 1.2}};
    int level = bench_level();
    int n = level == BENCH_SMOKE ? 50 : level ? 20000 : 100000,
        rounds = level == BENCH_SMOKE ? 1 : level ? 3 : 5, k, i, rd;
    double base_ns = 0;
    object *o = malloc(sizeof *o);
    ray_ray *rays = malloc((size_t)n * sizeof *rays);

    if (o == NULL || rays == NULL)
        return 1;
    setup(o);
    printf("## Curved surfaces: generic root finding against exact "
           "methods\n\n");
    printf("%d random rays from a sphere of radius 4 toward points within "
           "the object's reach (the same rays for each method of an "
           "object); time per ray is the median of %d rounds, one thread; "
           "ratio against the first method of the object; accuracy is the "
           "largest distance of a hit point from the exact surface (long "
           "double).  The generic methods' default tolerance is 1e-9 of "
           "the box's diagonal plus 64 ulps of its largest coordinate "
           "(~3.5e-9 here).\n\n", n, rounds);
    printf("| surface | method | ns per ray | ratio | hits | failures | "
           "max distance from surface |\n|---|---|---|---|---|---|---|\n");
    for (k = 0; k < (int)(sizeof rows / sizeof rows[0]); k++) {
        const row *rw = &rows[k];
        double t[9], maxd = 0, ns;
        long hits = 0, fails = 0;
        make_rays(rays, n, rw->reach);
        for (rd = 0; rd < rounds; rd++) {
            volatile long sink = 0;
            double t0 = now_seconds();
            for (i = 0; i < n; i++) {
                ray_hit h;
                sink += rw->fn(&rays[i], o, &h);
            }
            t[rd] = now_seconds() - t0;
            (void)sink;
        }
        for (i = 0; i < n; i++) {
            ray_hit h;
            int got = rw->fn(&rays[i], o, &h);
            if (got < 0)
                fails++;
            if (got == 1) {
                hits++;
                if (rw->dist != NULL)
                    maxd = fmax(maxd, rw->dist(h.p, o));
            }
        }
        ns = median(t, rounds) / n * 1e9;
        if (rw->baseline)
            base_ns = ns;
        printf("| %s | %s | %.1f | %.2f | %ld | %ld | ", rw->surface,
               rw->method, ns, ns / base_ns, hits, fails);
        if (rw->dist != NULL)
            printf("%.2g |\n", maxd);
        else
            printf("- |\n");
    }
    printf("\n");
    free(rays);
    free(o);
    return 0;
}
