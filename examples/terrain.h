/* SPDX-License-Identifier: MIT */
/*
** terrain.h -- the game examples' level: gentle hills over [-24, 24]^2 as
** one mesh of TERRAIN_GRID x TERRAIN_GRID cells, two triangles each
** (4,608 triangles).  examples/game.c, examples/controller.c and
** bench/shapes.c stand on the same ground.  Not part of the library.
*/
#ifndef EXAMPLES_TERRAIN_H
#define EXAMPLES_TERRAIN_H

#include <math.h>

#include <ray.h>

#define TERRAIN_GRID 48

/* The terrain's height at (x, z): y in [-1, 1]. */
static inline double terrain_height(double x, double z)
{
    return sin(0.3 * x) * cos(0.25 * z);
}

/* The terrain as a ray_mesh over arrays of this file's own (static: the
** same every call), for ray_scene_add_mesh, which copies them. */
static inline void terrain_mesh(ray_mesh *m)
{
    enum { G = TERRAIN_GRID };
    static ray_vec3 v[(G + 1) * (G + 1)];
    static unsigned idx[6 * G * G];
    unsigned i, j;

    for (j = 0; j <= G; j++)
        for (i = 0; i <= G; i++) {
            double x = (double)i - G / 2, z = (double)j - G / 2;
            v[j * (G + 1) + i] = ray_vec3_make(x, terrain_height(x, z), z);
        }
    for (j = 0; j < G; j++)
        for (i = 0; i < G; i++) {
            unsigned a = j * (G + 1) + i, *t = idx + 6 * (j * G + i);
            t[0] = a; t[1] = a + G + 1; t[2] = a + 1;
            t[3] = a + 1; t[4] = a + G + 1; t[5] = a + G + 2;
        }
    memset(m, 0, sizeof *m);
    m->vertices = v;
    m->vertex_count = (G + 1) * (G + 1);
    m->indices = idx;
    m->triangle_count = 2 * G * G;
}

#endif
