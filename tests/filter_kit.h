/* SPDX-License-Identifier: MIT */
/*
** filter_kit.h -- the hard scenes and rays of the float filter's tests
** (check_filter.c) and bench (bench/filter.c): hardcases.h's closed
** icosphere and spindle of needles, a strip of caps, with vertices that
** are floats or are not, near and far from the origin; rays at shared
** vertices and edges, grazing rays and rays at random points, from the
** generator of testkit.h (deterministic).
*/
#ifndef RAY_FILTER_KIT_H
#define RAY_FILTER_KIT_H

#include "hardcases.h"

/*
** A strip of n caps (each triangle with one angle near 180 degrees: its
** third vertex 1e-6 off the line of the other two) along x around
** "centre", neighbours sharing two vertices; vertices on the line,
** alternately 1e-6 above it.
*/
static inline hc_mesh fk_caps(ray_vec3 centre, size_t n)
{
    hc_mesh m;
    size_t i;

    m.nv = n + 2;
    m.nt = n;
    m.v = malloc(m.nv * sizeof *m.v);
    m.idx = malloc(3 * m.nt * sizeof *m.idx);
    for (i = 0; i < m.nv; i++)
        m.v[i] = v3_add(centre, v3(2 * (double)i / (double)n - 1,
                                   i % 2 ? 1e-6 : 0.0, i % 3 ? 1e-7 : 0.0));
    for (i = 0; i < n; i++) {
        m.idx[3 * i] = (unsigned)i;
        m.idx[3 * i + 1] = (unsigned)(i + 1);
        m.idx[3 * i + 2] = (unsigned)(i + 2);
    }
    return m;
}

/*
** The vertices made floats (each coordinate rounded to float: a mesh as
** games keep it, whose float copy in the leaves is exact), or, with
** floats 0, moved off the float grid (each coordinate times 1 + k 2^-40,
** k a small odd number, so that its float is not exact).
*/
static inline void fk_grid(hc_mesh *m, int floats)
{
    size_t i;

    for (i = 0; i < m->nv; i++) {
        ray_vec3 p = m->v[i];
        if (floats)
            p = v3((double)(float)p.x, (double)(float)p.y,
                   (double)(float)p.z);
        else
            p = v3(p.x * (1 + (double)(2 * (i % 7) + 1) * 0x1p-40),
                   p.y * (1 - (double)(2 * (i % 5) + 1) * 0x1p-40),
                   p.z * (1 + (double)(2 * (i % 3) + 1) * 0x1p-40));
        m->v[i] = p;
    }
}

/*
** Ray k of a set aimed at mesh m, of kind k % 4: 0 at a vertex, 1 at a
** point of an edge, 2 grazing (from a point in a triangle's plane, tilted
** out of it by 1e-9 to 1e-3 radians), 3 at a random point of a triangle;
** from "dist" away (grazing: along the triangle's first edge), the
** interval (0, +Inf).
*/
static inline ray_ray fk_ray(const hc_mesh *m, double dist, rng *g,
                             unsigned kind)
{
    size_t t = (size_t)(rng_unit(g) * (double)m->nt) % m->nt;
    ray_vec3 a = m->v[m->idx[3 * t]], b = m->v[m->idx[3 * t + 1]],
             c = m->v[m->idx[3 * t + 2]], target, d;
    double u = rng_unit(g), v = rng_unit(g);
    ray_ray r;

    r.tmin = 0;
    r.tmax = HUGE_VAL;
    switch (kind % 4) {
    case 0:
        target = a;
        break;
    case 1:
        target = v3_add(a, v3_scale(v3_sub(b, a), u));
        break;
    case 2: {
        ray_vec3 e1 = v3_sub(b, a), n = v3_cross(e1, v3_sub(c, a));
        double len = v3_length(n);
        target = v3_scale(v3_add(v3_add(a, b), c), 1.0 / 3);
        d = v3_add(v3_scale(e1, dist / v3_length(e1)),
                   v3_scale(n, pow(10.0, -9 + 6 * v) * dist /
                                   (len > 0 ? len : 1)));
        r.org = v3_sub(target, d);
        r.dir = d;
        return r;
    }
    default:
        if (u + v > 1)
            u = 1 - u, v = 1 - v;
        target = v3_add(a, v3_add(v3_scale(v3_sub(b, a), u),
                                  v3_scale(v3_sub(c, a), v)));
        break;
    }
    r.org = v3_add(target, v3_scale(rng_dir(g), dist));
    r.dir = v3_sub(target, r.org);
    return r;
}

#endif /* RAY_FILTER_KIT_H */
