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
#include <string.h>

#include "core/platform.h"
#include "scene/scene.h"

/* Below this many, a vertex's neighbours are sorted by insertion (the
** usual vertex has about six edges); above, by qsort (a fan's centre). */
#define INSERTION_MAX 32

static int index_cmp(const void *pa, const void *pb)
{
    unsigned a = *(const unsigned *)pa, b = *(const unsigned *)pb;

    return (a > b) - (a < b);
}

static void sort_indices(unsigned *v, size_t n)
{
    size_t i, j;

    if (n > INSERTION_MAX) {
        qsort(v, n, sizeof *v, index_cmp);
        return;
    }
    for (i = 1; i < n; i++) {
        unsigned x = v[i];
        for (j = i; j > 0 && v[j - 1] > x; j--)
            v[j] = v[j - 1];
        v[j] = x;
    }
}

/* Corner k's edge: to the next corner of its triangle. */
static unsigned edge_end(const unsigned *indices, size_t k)
{
    return indices[k % 3 == 2 ? k - 2 : k + 1];
}

/* Every run of equal values in v[0 .. n) even? */
static int runs_even(const unsigned *v, size_t n)
{
    size_t i, run;

    for (i = 0; i < n; i += run) {
        for (run = 1; i + run < n && v[i + run] == v[i]; run++)
            ;
        if (run % 2 != 0)
            return 0;
    }
    return 1;
}

/*
** The edges bucketed by their lower vertex (a counting sort: start[v] ..
** start[v + 1] - 1 hold the upper ends of v's edges), then each bucket
** sorted and its runs counted.  Linear but for the buckets' small sorts:
** a qsort of every edge's 64-bit key, as this first did, was 70 million
** instructions of the 59k bunny's ray_scene_add_mesh, most of a cold
** build's copy (callgrind, issue 36); the same answer.
*/
int ray__mesh_closed(const ray_scene *s, const unsigned *indices,
                     size_t n_tris, int *closed)
{
    unsigned *upper;
    size_t *start, n = 3 * n_tris, k, m = 0, v, total;
    int ok = 1;

    *closed = 0;
    if (n_tris == 0)
        return RAY_OK;
    if (n_tris > ((size_t)-1) / 3 / sizeof *upper)
        return RAY_ENOMEM;
    for (k = 0; k < n; k++)
        if (indices[k] >= m)
            m = (size_t)indices[k] + 1;
    if (m > ((size_t)-1) / sizeof *start - 1)
        return RAY_ENOMEM;
    upper = ray__alloc(s, n * sizeof *upper);
    start = ray__alloc(s, (m + 1) * sizeof *start);
    if (upper == NULL || start == NULL) {
        ray__free(s, upper, n * sizeof *upper);
        ray__free(s, start, (m + 1) * sizeof *start);
        return RAY_ENOMEM;
    }
    memset(start, 0, (m + 1) * sizeof *start);
    for (k = 0; k < n; k++) {   /* degree by lower end; none for p == q */
        unsigned p = indices[k], q = edge_end(indices, k);
        if (p != q)
            start[(p < q ? p : q) + 1]++;
    }
    for (v = 0; v < m; v++)
        start[v + 1] += start[v];
    total = start[m];
    for (k = 0; k < n; k++) {   /* start[v]: the next free slot of v's */
        unsigned p = indices[k], q = edge_end(indices, k);
        if (p != q)
            upper[start[p < q ? p : q]++] = p < q ? q : p;
    }
    /* Now start[v] is where v's bucket ends, start[v - 1] where it began. */
    for (v = 0; v < m && ok; v++) {
        size_t b = v == 0 ? 0 : start[v - 1];
        sort_indices(upper + b, start[v] - b);
        ok = runs_even(upper + b, start[v] - b);
    }
    *closed = ok && total > 0;
    ray__free(s, upper, n * sizeof *upper);
    ray__free(s, start, (m + 1) * sizeof *start);
    return RAY_OK;
}

int ray__closed_all(ray_scene *s)
{
    size_t i;

    for (i = 0; i < s->n_prims; i++) {
        const ray__prim *p = &s->prims[i];
        ray__mesh *m;
        if (p->kind != RAY__KIND_MESH || p->removed)
            continue;
        m = &s->meshes[p->mesh];
        if (ray__mesh_closed(s, m->indices, m->n_tris, &m->closed) != RAY_OK)
            return RAY_ENOMEM;
    }
    return RAY_OK;
}

int ray__closed_ensure(const ray_scene *s)
{
    ray_scene *w = ray__unconst(s);
    size_t i;
    int rc = RAY_OK;

    if (w->cgrid_lock == NULL)     /* set at commit, read-only after */
        return w->closed_known ? RAY_OK : RAY_ENOMEM;
    ray__mutex_lock(w->cgrid_lock);
    if (!w->closed_known) {
        rc = ray__closed_all(w);
        w->closed_known = rc == RAY_OK;
    }
    ray__mutex_unlock(w->cgrid_lock);
    for (i = 0; i < s->n_prims && rc == RAY_OK; i++) {
        const ray__prim *p = &s->prims[i];
        if (p->kind == RAY__KIND_INSTANCE && !p->removed)
            rc = ray__closed_ensure(s->instances[p->surface].child);
    }
    return rc;
}
