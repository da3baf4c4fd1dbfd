/* SPDX-License-Identifier: MIT */
/*
** closed.c -- whether a mesh is closed, for ray_contains: its triangles'
** edges, taken by their vertex indices and without direction, each used
** an even number of times (a mod-2 cycle: no boundary).  That is the
** condition under which the parity of a ray's crossings is the same for
** every ray from a point (the point's "inside" is well defined), and it
** holds for closed 2-manifolds, for several closed parts in one mesh and
** for triangles flipped against their neighbours (parity ignores
** orientation); a crack, a hole or a dangling triangle breaks it.
** Edges are matched by index, so shared vertices are bit-identical in
** every triangle that uses them: what makes the parity exact.  A mesh
** whose duplicated vertices were never welded (an STL file's) counts as
** open.  A degenerate edge (both ends one index) is no edge.
*/
#include <stdlib.h>

#include "scene/scene.h"

static int key_cmp(const void *pa, const void *pb)
{
    unsigned long long a = *(const unsigned long long *)pa;
    unsigned long long b = *(const unsigned long long *)pb;

    return (a > b) - (a < b);
}

int ray__mesh_closed(const ray_scene *s, const unsigned *indices,
                     size_t n_tris, int *closed)
{
    unsigned long long *keys;
    size_t n = 0, i, run;

    *closed = 0;
    if (n_tris == 0)
        return RAY_OK;
    if (n_tris > ((size_t)-1) / 3 / sizeof *keys)
        return RAY_ENOMEM;
    keys = ray__alloc(s, 3 * n_tris * sizeof *keys);
    if (keys == NULL)
        return RAY_ENOMEM;
    for (i = 0; i < 3 * n_tris; i++) {
        unsigned p = indices[i];
        unsigned q = indices[i % 3 == 2 ? i - 2 : i + 1];
        if (p == q)
            continue;
        keys[n++] = p < q ? ((unsigned long long)p << 32) | q
                          : ((unsigned long long)q << 32) | p;
    }
    qsort(keys, n, sizeof *keys, key_cmp);
    *closed = n > 0;
    for (i = 0; i < n; i += run) {
        for (run = 1; i + run < n && keys[i + run] == keys[i]; run++)
            ;
        if (run % 2 != 0) {
            *closed = 0;
            break;
        }
    }
    ray__free(s, keys, 3 * n_tris * sizeof *keys);
    return RAY_OK;
}
