/* SPDX-License-Identifier: MIT */
/*
** triangles.c -- the triangle slots at commit: the BVH over the live
** ones (of enabled geometry), the slots put in its leaf order, and the
** leaves' float corners (scene.h, RAY__LEAF_ROWS), which the queries'
** float filter reads in front of the exact double test.  A refit keeps
** the tree and fits its boxes, and the float corners, again.
*/
#include <string.h>

#include "core/platform.h"
#include "core/tasks.h"
#include "scene/slots.h"

/*
** The triangle BVH's cost settings (accel/sah.c): a split costs 1.5
** triangle tests, and eight triangles or fewer make a leaf (unless they
** fall into groups apart: accel/sparse.c).  The float filter
** (query/filter.h) tests a leaf's triangles eight at a time in one pass,
** so a leaf of eight costs about what a leaf of one does, and a wide node
** tests all its boxes at once, whatever their number: bench/mesh
** measured (issue 27).  A triangle's box (ray__tri_boxes, boxes.c) reads
** only the scene, so the build may make them on its threads.
*/
static const ray__bvh_costs tri_costs = {1.5f, RAY__LEAF_MAX, 1,
                                         ray__tri_boxes};

/*
** fn(s, begin, end, out) over the n live slots in runs of SLOT_RUN, on
** the scene's build threads or scheduler (ray_scene_set_build_threads):
** the commit's passes that read every triangle once and write what is
** the slot's own (its rows, its copy), so the runs share nothing and the
** bytes are the same at any thread count.  They were two fifths of a
** 940k build's time on the calling thread while the others waited
** (callgrind, one thread each, issue 36).
*/
#define SLOT_RUN 16384

typedef void (*slot_fn)(const ray_scene *s, size_t begin, size_t end,
                        void *out);

typedef struct slot_job {
    const ray_scene *s;
    slot_fn fn;
    void *out;
} slot_job;

static void slot_task(void *ud, unsigned k, size_t begin, size_t end)
{
    const slot_job *job = ud;

    (void)k;
    job->fn(job->s, begin, end, job->out);
}

/* fn over 0 .. n - 1 in runs of "run" (slots_run's threads). */
static void runs_of(ray_scene *s, size_t n, size_t run, slot_fn fn, void *out)
{
    /* 0: one a CPU, as the build's own threads (build.c). */
    unsigned threads = s->build_threads != 0 ? s->build_threads
                                             : ray__online_cpus();
    slot_job job;

    job.s = s;
    job.fn = fn;
    job.out = out;
    if (!ray__tasks_runs(&s->scheduler, &s->alloc, threads, 0, n, run,
                         slot_task, &job))
        fn(s, 0, n, out);
}

static void slots_run(ray_scene *s, size_t n, slot_fn fn, void *out)
{
    runs_of(s, n, SLOT_RUN, fn, out);
}

/* Slots begin .. end - 1's rows, by slot, into out (leaves_make). */
static void rows_by_slot(const ray_scene *s, size_t begin, size_t end,
                         void *out)
{
    float *by_slot = out;
    const ray__mesh *m = NULL;
    unsigned m_geom = (unsigned)-1;
    size_t i;

    for (i = begin; i < end; i++) {
        ray__tri t;
        refit_corners(s, i, &m, &m_geom, &t);
        leaf_rows(&t, by_slot + RAY__LEAF_ROWS * i, 1);
    }
}

/* Slots begin .. end - 1's corners copied into out (leaf_tris_make). */
static void copies_by_slot(const ray_scene *s, size_t begin, size_t end,
                           void *out)
{
    ray__tri *copy = out;
    const ray__mesh *m = NULL;
    unsigned m_geom = (unsigned)-1;
    size_t i;

    for (i = begin; i < end; i++) {
        refit_corners(s, i, &m, &m_geom, &copy[i]);
        if (m != NULL)
            ray__prefetch_slots(s, i, m, m_geom);
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

/* Leaf layout from rows in slot order (before the slots are permuted):
** a leaf's slot j is slot items[first + j] then. */
typedef struct leaf_gather {
    float *out;
    const float *by_slot;        /* RAY__LEAF_ROWS floats per old slot */
    const unsigned *items;
    const ray__bvh *bvh;         /* whose leaves */
} leaf_gather;

static void gather_leaf(const leaf_gather *g, unsigned first, unsigned n)
{
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
** The leaves of wide nodes begin .. end - 1 gathered (ud: the
** leaf_gather): each leaf writes only its own rows, so runs of nodes go
** to the build's threads (runs_of) and the bytes are the same at any
** thread count.  The gather's random reads were, on the calling thread
** alone, a ninth of a 940k build's time on two threads (perf, issue 36).
*/
#define WIDE_RUN 1024

static void gather_wide(const ray_scene *s, size_t begin, size_t end,
                        void *ud)
{
    const leaf_gather *g = ud;
    size_t w;
    int k;

    (void)s;
    for (w = begin; w < end; w++)
        for (k = 0; k < RAY__WIDTH; k++) {
            const ray__wnode *q = &g->bvh->wide[w];
            unsigned n = q->count[k] & ~RAY__LEAF;
            if (q->count[k] != 0 && n > 0)
                gather_leaf(g, q->child[k], n);
        }
}

/*
** The float corners of the n live slots in the leaves of the fresh BVH
** (its items: the old slot of each leaf position), into leaf_f, the
** block "out" of "bytes" (the rebuild's scratch): first in slot order
** into by_slot (RAY__LEAF_ROWS n floats, in the build's node block),
** reading the geometry as it lies (a mesh's indices in order), then
** gathered into leaf order, one random read a slot.  (The rebuild sets
** float_exact, which it asks before the build.)
*/
static void leaves_make(ray_scene *s, const ray__bvh *fresh, size_t n,
                        float *by_slot, float *out, size_t bytes)
{
    leaf_gather g;

    slots_run(s, n, rows_by_slot, by_slot);
    g.out = out;
    g.by_slot = by_slot;
    g.items = fresh->items;
    g.bvh = fresh;
    runs_of(s, fresh->n_wide, WIDE_RUN, gather_wide, &g);
    memset(out + RAY__LEAF_ROWS * n, 0, RAY__LEAF_PAD * sizeof *out);
    s->leaf_f = out;
    s->cap_leaf_f = bytes / sizeof *out;
}

typedef struct ids_gather {
    ray__tri_id *id;
    const unsigned *items;
} ids_gather;

/* Leaf positions begin .. end - 1's ids (a run of gather_ids's). */
static void ids_by_position(const ray_scene *s, size_t begin, size_t end,
                            void *ud)
{
    const ids_gather *g = ud;
    size_t i;

    for (i = begin; i < end; i++)
        g->id[i] = s->tri_ids[g->items[i]];
}

/*
** Put the ids of the n live slots in leaf order: gathered into "id" (in
** the build's node block), each read random but none depending on
** another, where walking the permutation's cycles in place chases one
** random read after the other (at 940k triangles the walk took about a
** sixth of the commit, perf on bench/mesh's bunny-4), then copied back
** (the waiting slots after n stay where they are).
*/
static void gather_ids(ray_scene *s, const unsigned *items, size_t n,
                       ray__tri_id *id)
{
    ids_gather g;

    g.id = id;
    g.items = items;
    slots_run(s, n, ids_by_position, &g);
    memcpy(s->tri_ids, id, n * sizeof *id);
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

/* Is every geometry of s enabled and none removed (the usual scene)?
** Then the rebuild's two passes over the slots (removed ones dropped,
** disabled ones moved behind) would keep every slot in place: they are
** skipped, a serial read of every slot's geometry, 940k of them for the
** big bunny, while the build's threads wait (issue 36). */
static int every_geometry_live(const ray_scene *s)
{
    size_t i;

    for (i = 0; i < s->n_prims; i++)
        if (!s->prims[i].enabled || s->prims[i].removed)
            return 0;
    return 1;
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
    ray__slot_vertices_drop(s);
    s->leaf_f = NULL;
    s->cap_leaf_f = 0;
    s->leaf_tri = NULL;
    s->n_live_tris = 0;
}

/*
** The double corners of the n live slots, in leaf order (the slots are
** in it already), for the exact test (ray__leaf_tri): only where they
** are not all floats, as the leaves' floats are those corners otherwise.
** 72 bytes a triangle, in the build's node block ("spare", "bytes"
** long: its pages touched already), resized; out of memory, none: the
** queries then read the corners through the geometry, the same bits,
** slower.  The spare block is the scene's or freed.
*/
static void leaf_tris_make(ray_scene *s, size_t n, void *spare, size_t bytes)
{
    size_t need = n * sizeof *s->leaf_tri;
    ray__tri *copy = spare;

    if (!s->float_exact && bytes != need)
        copy = ray__realloc(s, spare, bytes, need);
    if (s->float_exact || copy == NULL) {
        ray__free(s, spare, bytes);
        return;
    }
    s->leaf_tri = copy;
    slots_run(s, n, copies_by_slot, s->leaf_tri);
}

/* How many slots the rebuild below puts in the BVH: those tri_live
** keeps, the filter its partition applies. */
size_t ray__triangles_live(const ray_scene *s)
{
    size_t n = 0, i;

    for (i = 0; i < s->n_tris; i++)
        n += (size_t)tri_live(s, i);
    return n;
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
int ray__triangles_rebuild(ray_scene *s, ray__progress *prog)
{
    size_t n = 0, i, scratch_bytes, spare_at;
    int floats;
    void *scratch = NULL;
    ray__bvh_share share;
    ray__bvh fresh;
    int rc;

    if (every_geometry_live(s))
        n = s->n_tris;                 /* every slot stays where it is */
    else {
        for (i = 0; i < s->n_tris; i++)
            if (!s->prims[s->tri_ids[i].geom_id].removed)
                tri_swap(s, n++, i);
        s->n_tris = n;
        n = 0;
        for (i = 0; i < s->n_tris; i++)
            if (tri_live(s, i))
                tri_swap(s, n++, i);
    }
    leaves_free(s);
    /*
    ** Two blocks for the build and what follows it, so that their pages
    ** are touched once (issue 36: each block that large is mapped afresh,
    ** and every first touch of a page is a page fault):
    ** - the scratch: the build's records, then leaf_f (RAY__LEAF_ROWS
    **   floats a slot and the padding), whose size it is;
    ** - the build's binary nodes, kept (ray__bvh_share): the leaves'
    **   corners in slot order and the ids in leaf order, then the double
    **   copy (leaf_tris_make), or freed.
    ** Three cold builds of the 940k bunny in a row: 375 -> 219 minor
    ** faults with the system allocator's blocks (platform.h), Embree's 132
    ** (build/bench/mesh DATA build).
    */
    scratch_bytes = (RAY__LEAF_ROWS * n + RAY__LEAF_PAD) * sizeof(float);
    if (scratch_bytes < RAY__BVH_SCRATCH(n))
        scratch_bytes = RAY__BVH_SCRATCH(n);
    spare_at = RAY__LEAF_ROWS * n * sizeof(float);
    if (n > 0 && (n > (size_t)-1 / 128 ||
                  (scratch = ray__alloc(s, scratch_bytes)) == NULL))
        return RAY_ENOMEM;
    share.records = scratch;
    share.keep = spare_at + n * sizeof(ray__tri_id);
    floats = corners_are_floats(s);
    if (!floats)
        share.keep = n * sizeof *s->leaf_tri;     /* more: the copy's */
    rc = ray__bvh_build(&s->alloc, NULL, s, n, &tri_costs,
                        &s->scheduler, s->build_threads, &share, prog,
                        &fresh);
    if (rc != RAY_OK) {
        ray__free(s, scratch, scratch_bytes);
        return rc;
    }
    if (n > 0) {
        char *spare = share.kept;
        leaves_make(s, &fresh, n, (float *)(void *)spare, scratch,
                    scratch_bytes);
        s->float_exact = floats;
        gather_ids(s, fresh.items, n,
                   (ray__tri_id *)(void *)(spare + spare_at));
        /* Leaves now index slots directly: the permutation is not kept. */
        ray__free(s, fresh.items, fresh.n_items * sizeof(unsigned));
        fresh.items = NULL;
        fresh.n_items = 0;
    }
    s->tri_bvh = fresh;
    s->n_live_tris = n;
    trim_ids(s);
    /* Last, once the permutation is given back: the peak stays the
    ** build's where it can. */
    if (n > 0)
        leaf_tris_make(s, n, share.kept, share.kept_bytes);
    return RAY_OK;
}

/*
** The vertex indices of the n live slots in slot order (slot_vertices),
** for the refits: the slots lie in the tree's order and their indices in
** the mesh's, so a refit that reads each slot's triple through its mesh
** waits on a cache miss per slot before it can even ask for the corners;
** the same triples in slot order are read as they lie, and where every
** live slot is of one mesh (slot_geom: a skinned character) the slots'
** ids are not read at all.  The 940k bunny's refit, ours / Embree in
** time on one thread: 0.96, 1.00, 0.94 -> 0.80, 0.80, 0.80; on two
** threads 0.64 -> 0.53 (bench/game, three interleaved runs against the
** commit before; issue 36).  Made once, by the
** first refit after a build (a scene never refitted keeps no copy), 12
** bytes a triangle; dropped by the next build and by a mesh update that
** brings other indices (mesh.c).  Out of memory, none: the refit then
** reads the triples through the meshes, the same corners.
*/
static void slot_vertices_make(ray_scene *s)
{
    size_t i, n = s->n_live_tris;
    const ray__mesh *m = NULL;
    unsigned m_geom = (unsigned)-1, *v, single = RAY_INVALID_ID;

    if (s->slot_vertices != NULL || n == 0 ||
        n > (size_t)-1 / (3 * sizeof *v) ||
        (v = ray__alloc(s, 3 * n * sizeof *v)) == NULL)
        return;
    for (i = 0; i < n; i++) {
        const ray__tri_id *id = &s->tri_ids[i];
        if (id->geom_id != m_geom) {
            const ray__prim *p = &s->prims[id->geom_id];
            single = i == 0 && p->kind == RAY__KIND_MESH &&
                             s->meshes[p->mesh].own_indices
                         ? id->geom_id
                         : RAY_INVALID_ID;
            if (p->kind != RAY__KIND_MESH) {
                v[3 * i] = v[3 * i + 1] = v[3 * i + 2] = 0;   /* unread */
                continue;
            }
            m = &s->meshes[p->mesh];
            m_geom = id->geom_id;
        }
        memcpy(v + 3 * i, m->indices + 3 * (size_t)id->prim_id,
               3 * sizeof *v);
    }
    s->slot_vertices = v;
    s->slot_geom = single;
}

/* The refit runs on a committed scene, so s->avx2 holds the CPU's
** answer; the AVX2 leaf gives the SSE2 leaf's bits (refit_avx2.c). */
void ray__triangles_refit(ray_scene *s)
{
    ray__range_box_fn leaf = s->avx2 ? ray__refit_leaf_avx2() : NULL;

    slot_vertices_make(s);
    ray__bvh_refit(&s->alloc, &s->tri_bvh, leaf != NULL ? leaf : ray__refit_leaf,
                   s, s->n_live_tris, &s->scheduler, s->build_threads);
    s->float_exact = corners_are_floats(s);
}
