/* SPDX-License-Identifier: MIT */
/*
** triangles.c -- the triangle slots at commit: the BVH over the live
** ones (of enabled geometry), the slots put in its leaf order, and the
** leaves' float corners (scene.h, RAY__LEAF_ROWS), which the queries'
** float filter reads in front of the exact double test.  A refit keeps
** the tree and fits its boxes, and the float corners, again.
*/
#include <string.h>

#include "scene/scene.h"

/*
** The triangle BVH's cost settings (accel/sah.c): a split costs 1.5
** triangle tests, and eight triangles or fewer always make a leaf.  The
** float filter (query/filter.h) tests a leaf's triangles eight at a time
** in one pass, so a leaf of eight costs about what a leaf of one does,
** and a wide node tests all its boxes at once, whatever their number:
** bench/mesh measured (issue 27).
*/
static const ray__bvh_costs tri_costs = {1.5f, RAY__LEAF_MAX};

/* The smaller and larger of two, of three finite numbers (no libm call:
** the NaN rules of fmin are not needed here, vertices are finite). */
static double min2(double a, double b)
{
    return a < b ? a : b;
}

static double max2(double a, double b)
{
    return a > b ? a : b;
}

static double min3(double a, double b, double c)
{
    return min2(min2(a, b), c);
}

static double max3(double a, double b, double c)
{
    return max2(max2(a, b), c);
}

/* *lo, *hi grown to hold triangle t. */
static inline void corners_grow(const ray__tri *t, ray_vec3 *lo,
                                ray_vec3 *hi)
{
    lo->x = min2(lo->x, min3(t->a.x, t->b.x, t->c.x));
    lo->y = min2(lo->y, min3(t->a.y, t->b.y, t->c.y));
    lo->z = min2(lo->z, min3(t->a.z, t->b.z, t->c.z));
    hi->x = max2(hi->x, max3(t->a.x, t->b.x, t->c.x));
    hi->y = max2(hi->y, max3(t->a.y, t->b.y, t->c.y));
    hi->z = max2(hi->z, max3(t->a.z, t->b.z, t->c.z));
}

/* The double box lo, hi rounded outward into float (once per box:
** rounding outward is monotonic, so the union of rounded boxes is the
** rounded union, bit for bit). */
static void box_out(ray_vec3 lo, ray_vec3 hi, float flo[3], float fhi[3])
{
    flo[0] = ray__float_down(lo.x);
    flo[1] = ray__float_down(lo.y);
    flo[2] = ray__float_down(lo.z);
    fhi[0] = ray__float_up(hi.x);
    fhi[1] = ray__float_up(hi.y);
    fhi[2] = ray__float_up(hi.z);
}

/* The float box of slot i, rounded outward (the build's box callback). */
static void tri_box(const void *ud, size_t i, float lo[3], float hi[3])
{
    ray__tri t = ray__tri_of(ud, i);
    ray_vec3 a = t.a, b = t.a;

    corners_grow(&t, &a, &b);
    box_out(a, b, lo, hi);
}

/* Does x lie where the leaf rows keep floats (RAY__LEAF_FLOAT_MAX)? */
static inline int row_fits(double x)
{
    return fabs(x) <= RAY__LEAF_FLOAT_MAX;
}

/*
** The nine floats of triangle t, corner by corner (a, b, c), axis by
** axis, at rows[0], rows[stride], ... rows[8 stride], each the nearest
** float.  A triangle with a coordinate beyond RAY__LEAF_FLOAT_MAX (where
** the filter's arithmetic could overflow, and where a conversion to
** float could be out of range) gets NaN in all nine, which the filter
** never rejects: the exact test decides it.
*/
static inline void leaf_rows(const ray__tri *t, float *rows, size_t stride)
{
    /* Written out, not looped over an array of nine: a refit writes every
    ** triangle's rows, and the loops were two fifths of its instructions
    ** (callgrind, bench/game's 59k refit, issue 36). */
    int ok = row_fits(t->a.x) & row_fits(t->a.y) & row_fits(t->a.z) &
             row_fits(t->b.x) & row_fits(t->b.y) & row_fits(t->b.z) &
             row_fits(t->c.x) & row_fits(t->c.y) & row_fits(t->c.z);
    float *r = rows;

    if (ok) {
        r[0] = (float)t->a.x, r += stride;
        r[0] = (float)t->a.y, r += stride;
        r[0] = (float)t->a.z, r += stride;
        r[0] = (float)t->b.x, r += stride;
        r[0] = (float)t->b.y, r += stride;
        r[0] = (float)t->b.z, r += stride;
        r[0] = (float)t->c.x, r += stride;
        r[0] = (float)t->c.y, r += stride;
        r[0] = (float)t->c.z;
    } else {
        int k;
        for (k = 0; k < RAY__LEAF_ROWS; k++)
            rows[(size_t)k * stride] = (float)NAN;
    }
}

/*
** Are the float corners of every live triangle exact (the scene's
** float_exact, which lets the filter's bound drop the vertices'
** rounding)?  Yes when each live mesh's positions are floats (checked as
** they were copied) and each live single triangle's corners are.
*/
static int corners_are_floats(const ray_scene *s)
{
    size_t i;

    for (i = 0; i < s->n_prims; i++) {
        const ray__prim *p = &s->prims[i];
        if (!p->enabled || p->removed)
            continue;
        if (p->kind == RAY__KIND_MESH && !s->meshes[p->mesh].pos_floats)
            return 0;
        if (p->kind == RAY__KIND_TRIANGLE &&
            !(ray__is_float(p->a.x) && ray__is_float(p->a.y) &&
              ray__is_float(p->a.z) && ray__is_float(p->b.x) &&
              ray__is_float(p->b.y) && ray__is_float(p->b.z) &&
              ray__is_float(p->c.x) && ray__is_float(p->c.y) &&
              ray__is_float(p->c.z)))
            return 0;
    }
    return 1;
}

/*
** The leaves of a BVH over slots, each leaf's (first slot, count), in
** node order: fn(ud, first, n) for each.
*/
typedef void (*leaf_fn)(void *ud, unsigned first, unsigned n);

static void each_leaf(const ray__bvh *bvh, leaf_fn fn, void *ud)
{
    size_t w;
    int k;

    for (w = 0; w < bvh->n_wide; w++)
        for (k = 0; k < RAY__WIDTH; k++) {
            const ray__wnode *q = &bvh->wide[w];
            unsigned n = q->count[k] & ~RAY__LEAF;
            if (q->count[k] != 0 && n > 0)
                fn(ud, q->child[k], n);
        }
}

/* Leaf layout from rows in slot order (before the slots are permuted):
** a leaf's slot j is slot items[first + j] then. */
typedef struct leaf_gather {
    float *out;
    const float *by_slot;        /* RAY__LEAF_ROWS floats per old slot */
    const unsigned *items;
} leaf_gather;

static void gather_leaf(void *ud, unsigned first, unsigned n)
{
    const leaf_gather *g = ud;
    float *rows = g->out + (size_t)RAY__LEAF_ROWS * first;
    unsigned j;
    int r;

    for (j = 0; j < n; j++) {
        const float *src = g->by_slot +
                           (size_t)RAY__LEAF_ROWS * g->items[first + j];
        for (r = 0; r < RAY__LEAF_ROWS; r++)
            rows[(size_t)r * n + j] = src[r];
    }
}

/*
** The float corners of the n live slots in the leaves of the fresh BVH
** (its items: the old slot of each leaf position), into a new leaf_f:
** first in slot order into by_slot (the rebuild's scratch, of
** RAY__LEAF_ROWS n floats at least), reading the geometry as it lies (a
** mesh's indices in order), then gathered into leaf order, one random
** read a slot.  RAY_OK or RAY_ENOMEM (nothing changed).
*/
static int leaves_make(ray_scene *s, const ray__bvh *fresh, size_t n,
                       float *by_slot)
{
    size_t floats = RAY__LEAF_ROWS * n + RAY__LEAF_PAD, i;
    float *out = ray__alloc(s, floats * sizeof *out);
    leaf_gather g;

    if (out == NULL)
        return RAY_ENOMEM;
    for (i = 0; i < n; i++) {
        ray__tri t = ray__tri_of(s, i);
        leaf_rows(&t, by_slot + RAY__LEAF_ROWS * i, 1);
    }
    g.out = out;
    g.by_slot = by_slot;
    g.items = fresh->items;
    each_leaf(fresh, gather_leaf, &g);
    memset(out + RAY__LEAF_ROWS * n, 0, RAY__LEAF_PAD * sizeof *out);
    s->leaf_f = out;
    s->cap_leaf_f = floats;
    s->float_exact = corners_are_floats(s);
    return RAY_OK;
}

/*
** Put the ids of the n live slots in leaf order: gathered into "id" (the
** rebuild's scratch, of "bytes"), each read random but none depending on
** another, where walking the permutation's cycles in place chases one
** random read after the other (at 940k triangles the walk took about a
** sixth of the commit, perf on bench/mesh's bunny-4).  The scratch then
** becomes tri_ids (the waiting slots after n copied behind), so nothing
** is copied back: returns 1; or, when the waiting slots do not fit in
** it, the ids are copied back into tri_ids: returns 0.
*/
static int gather_ids(ray_scene *s, const unsigned *items, size_t n,
                      ray__tri_id *id, size_t bytes)
{
    size_t i, all = s->n_tris;

    for (i = 0; i < n; i++)
        id[i] = s->tri_ids[items[i]];
    if (all > bytes / sizeof *id) {
        memcpy(s->tri_ids, id, n * sizeof *id);
        return 0;
    }
    memcpy(id + n, s->tri_ids + n, (all - n) * sizeof *id);  /* waiting */
    ray__free(s, s->tri_ids, s->cap_tri_ids * sizeof *s->tri_ids);
    s->tri_ids = id;
    s->cap_tri_ids = bytes / sizeof *id;
    return 1;
}

/* Give back the spare capacity that doubling left in tri_ids (a failed
** shrink keeps the larger block: harmless). */
static void trim_ids(ray_scene *s)
{
    void *p;

    if (s->n_tris == 0 || s->cap_tri_ids == s->n_tris)
        return;          /* a zero-size realloc frees: keep the block */
    p = ray__realloc(s, s->tri_ids, s->cap_tri_ids * sizeof *s->tri_ids,
                     s->n_tris * sizeof *s->tri_ids);
    if (p != NULL) {
        s->tri_ids = p;
        s->cap_tri_ids = s->n_tris;
    }
}

/* Is triangle slot i of geometry that queries may see? */
static int tri_live(const ray_scene *s, size_t i)
{
    const ray__prim *p = &s->prims[s->tri_ids[i].geom_id];
    return p->enabled && !p->removed;
}

/* Swap triangle slots i and j; nothing to do for i == j, the usual case
** (every triangle kept, in place). */
static void tri_swap(ray_scene *s, size_t i, size_t j)
{
    ray__tri_id id;

    if (i == j)
        return;
    id = s->tri_ids[i];
    s->tri_ids[i] = s->tri_ids[j];
    s->tri_ids[j] = id;
}

/* The triangle BVH and the leaves' corners, gone. */
static void leaves_free(ray_scene *s)
{
    ray__bvh_free(&s->alloc, &s->tri_bvh);
    ray__free(s, s->leaf_f, s->cap_leaf_f * sizeof *s->leaf_f);
    ray__free(s, s->leaf_tri, s->n_live_tris * sizeof *s->leaf_tri);
    s->leaf_f = NULL;
    s->cap_leaf_f = 0;
    s->leaf_tri = NULL;
    s->n_live_tris = 0;
}

/*
** The double corners of the n live slots, in leaf order (the slots are
** in it already), for the exact test (ray__leaf_tri): only where they
** are not all floats, as the leaves' floats are those corners otherwise.
** 72 bytes a triangle; out of memory, none: the queries then read the
** corners through the geometry, the same bits, slower.
*/
static void leaf_tris_make(ray_scene *s, size_t n)
{
    size_t i;

    if (s->float_exact)
        return;
    s->leaf_tri = ray__alloc(s, n * sizeof *s->leaf_tri);
    if (s->leaf_tri == NULL)
        return;
    for (i = 0; i < n; i++)
        s->leaf_tri[i] = ray__tri_of(s, i);
}

/*
** The triangle BVH, rebuilt: removed geometry's slots go for good, the
** slots of enabled geometry are moved to the front (the others wait
** behind, outside the BVH, until enabled again), the BVH is built over
** them and they are put in its leaf order, so a leaf is a contiguous run
** of slots, and its float corners made.  The old tree and corners are
** freed first, which keeps the peak of a rebuild where a first build's
** is; a failure (out of memory) leaves the scene without a triangle BVH,
** uncommitted, its changes staged for the next commit.
*/
size_t ray__triangles_live(const ray_scene *s)
{
    size_t n = 0, i;

    for (i = 0; i < s->n_tris; i++)
        n += (size_t)(!s->prims[s->tri_ids[i].geom_id].removed &&
                      tri_live(s, i));
    return n;
}

int ray__triangles_rebuild(ray_scene *s, ray__progress *prog)
{
    size_t n = 0, i, scratch_bytes;
    void *scratch = NULL;
    ray__bvh fresh;
    int rc;

    for (i = 0; i < s->n_tris; i++)
        if (!s->prims[s->tri_ids[i].geom_id].removed)
            tri_swap(s, n++, i);
    s->n_tris = n;
    n = 0;
    for (i = 0; i < s->n_tris; i++)
        if (tri_live(s, i))
            tri_swap(s, n++, i);
    leaves_free(s);
    /* One scratch block for the build's records, then the corners in
    ** slot order, then the ids in leaf order, which it becomes (trimmed
    ** below): its pages are touched once, where three blocks of their
    ** own were each mapped afresh (at 940k triangles, 30, 34 and 8 MB:
    ** issue 36). */
    scratch_bytes = RAY__BVH_SCRATCH(n);
    if (scratch_bytes < RAY__LEAF_ROWS * n * sizeof(float))
        scratch_bytes = RAY__LEAF_ROWS * n * sizeof(float);
    /* Whole ids, so that as tri_ids it is given back at its size. */
    scratch_bytes += (sizeof(ray__tri_id) - scratch_bytes %
                      sizeof(ray__tri_id)) % sizeof(ray__tri_id);
    if (n > 0 && (n > (size_t)-1 / 64 ||
                  (scratch = ray__alloc(s, scratch_bytes)) == NULL))
        return RAY_ENOMEM;
    rc = ray__bvh_build(&s->alloc, tri_box, s, n, &tri_costs,
                        &s->scheduler, s->build_threads, scratch, prog,
                        &fresh);
    if (rc != RAY_OK) {
        ray__free(s, scratch, scratch_bytes);
        return rc;
    }
    if (n > 0) {
        if (leaves_make(s, &fresh, n, scratch) != RAY_OK) {
            ray__free(s, scratch, scratch_bytes);
            ray__bvh_free(&s->alloc, &fresh);
            return RAY_ENOMEM;
        }
        if (!gather_ids(s, fresh.items, n, scratch, scratch_bytes))
            ray__free(s, scratch, scratch_bytes);
        /* Leaves now index slots directly: the permutation is not kept. */
        ray__free(s, fresh.items, fresh.n_items * sizeof(unsigned));
        fresh.items = NULL;
        fresh.n_items = 0;
    }
    s->tri_bvh = fresh;
    s->n_live_tris = n;
    trim_ids(s);
    /* Last, once the build's scratch is given back: the peak stays the
    ** build's where it can. */
    if (n > 0)
        leaf_tris_make(s, n);
    return RAY_OK;
}

/*
** A refit's leaf: the box of slots first .. first + n - 1, from the
** geometry's vertices as they are now, and their float corners written
** again in the leaf's rows (ud: the scene, whose leaf_f the refit
** rewrites: each leaf its own rows).
*/
static void refit_leaf(const void *ud, size_t first, size_t n, float lo[3],
                       float hi[3])
{
    ray_scene *s = ray__unconst(ud);
    float *rows = s->leaf_f + RAY__LEAF_ROWS * first;
    ray_vec3 a = {0, 0, 0}, b = a;
    size_t j;

    /*
    ** A mesh's triangle is read here through ray__mesh_tri, inline, where
    ** ray__tri_of was a call returning 72 bytes through memory, read
    ** back in 16-byte loads over its 8-byte stores (a store-forwarding
    ** stall a triangle: perf put a quarter of a 59k refit there); the
    ** same corners, the same operations in the same order (corners_grow,
    ** leaf_rows), so the same floats.
    */
    for (j = 0; j < n; j++) {
        const ray__tri_id *id = &s->tri_ids[first + j];
        const ray__prim *p = &s->prims[id->geom_id];
        ray__tri t;
        if (p->kind == RAY__KIND_MESH)
            ray__mesh_tri(&s->meshes[p->mesh], id->prim_id, &t);
        else
            t = ray__tri_by_id(s, id->geom_id, id->prim_id);
        if (j == 0)
            a = b = t.a;
        corners_grow(&t, &a, &b);
        leaf_rows(&t, rows + j, n);
        if (s->leaf_tri != NULL)
            s->leaf_tri[first + j] = t;
    }
    box_out(a, b, lo, hi);
}

void ray__triangles_refit(ray_scene *s)
{
    ray__bvh_refit(&s->alloc, &s->tri_bvh, refit_leaf, s, s->n_live_tris,
                   &s->scheduler, s->build_threads);
    s->float_exact = corners_are_floats(s);
}
