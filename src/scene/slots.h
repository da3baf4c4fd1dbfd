/* SPDX-License-Identifier: MIT */
/*
** slots.h -- reading the triangle slots' corners in slot order, for the
** passes that visit every slot once (triangles.c: the leaf rows, the
** corner copies; boxes.c: the build's boxes and the refit's leaf;
** refit_avx2.c: the refit's AVX2 leaf), fetching ahead where the slots
** are in the tree's order, a triangle's float rows, and rounding a
** leaf's box out to float.
*/
#ifndef RAY_SCENE_SLOTS_H
#define RAY_SCENE_SLOTS_H

#include "scene/scene.h"

/*
** s->slot_vertices: 3 a live slot, a mesh slot's vertex indices in slot
** order (other slots' 0), made by the first refit after a build
** (triangles.c) and kept while the meshes' indices are, read only for
** meshes that keep their own indices; s->slot_geom, beside it: the mesh
** every live slot is of, where it keeps its own, else RAY_INVALID_ID.
** Dropped where the slots or such a mesh's indices change; the next
** refit makes them again.
*/
static inline void ray__slot_vertices_drop(ray_scene *s)
{
    ray__free(s, s->slot_vertices,
              3 * s->n_live_tris * sizeof *s->slot_vertices);
    s->slot_vertices = NULL;
}

/*
** Where the corners of live slot "slot" lie, as ray__tri_of reads them

** a mesh's triangle through its indices, p[0..2] into its positions (1:
** whether it has a normal is the caller's to test, ray__corners_usable),
** a single triangle's copied into *t (0: usable, as its add refused any
** other).  *m caches the mesh of geometry *m_geom, so that a run of one
** mesh's triangles (the usual case) looks its mesh up once.  A mesh
** triangle's vertex indices come from s->slot_vertices where a refit
** made them (in slot order, so read as they lie) where the mesh keeps
** its own indices, else from its mesh's indices (in the mesh's order: a
** cache miss a slot in a large mesh; a borrowed array of the caller's
** may change at every update, so it is always read there).
*/
RAY__HOT_INLINE int ray__slot_corners_at(const ray_scene *s, size_t slot,
                                         const ray__mesh **m,
                                         unsigned *m_geom, ray__tri *t,
                                         const ray_vec3 *p[3])
{
    const ray__tri_id *id;
    const unsigned *k;

    if (s->slot_vertices != NULL && s->slot_geom != RAY_INVALID_ID) {
        if (*m_geom != s->slot_geom) {
            *m = &s->meshes[s->prims[s->slot_geom].mesh];
            *m_geom = s->slot_geom;
        }
        k = s->slot_vertices + 3 * slot;
    } else {
        id = &s->tri_ids[slot];
        if (id->geom_id != *m_geom) {
            const ray__prim *prim = &s->prims[id->geom_id];
            if (prim->kind != RAY__KIND_MESH) {
                *t = ray__tri_by_id(s, id->geom_id, id->prim_id);
                p[0] = &t->a;
                p[1] = &t->b;
                p[2] = &t->c;
                return 0;
            }
            *m = &s->meshes[prim->mesh];
            *m_geom = id->geom_id;
        }
        k = s->slot_vertices != NULL && (*m)->own_indices
                ? s->slot_vertices + 3 * slot
                : (*m)->indices + 3 * (size_t)id->prim_id;
    }
    p[0] = &(*m)->pos[k[0]];
    p[1] = &(*m)->pos[k[1]];
    p[2] = &(*m)->pos[k[2]];
    return 1;
}

/* The corners of live slot "slot" into *t, as ray__tri_of reads them:
** found by ray__slot_corners_at (*m and *m_geom its cache), a mesh's read
** through ray__mesh_tri, which applies the rule for a triangle without
** a normal (the pointers into its positions go unused). */
RAY__HOT_INLINE void refit_corners(const ray_scene *s, size_t slot,
                                    const ray__mesh **m, unsigned *m_geom,
                                    ray__tri *t)
{
    const ray_vec3 *p[3];

    if (ray__slot_corners_at(s, slot, m, m_geom, t, p))
        ray__mesh_tri(*m, s->tri_ids[slot].prim_id, t);
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
** never rejects: the exact test decides it (fits: whether every
** coordinate is within it).
*/
static inline void rows_nan(float *rows, size_t stride)
{
    int k;

    for (k = 0; k < RAY__LEAF_ROWS; k++)
        rows[(size_t)k * stride] = (float)NAN;
}

static inline void leaf_rows_fitting(const ray__tri *t, float *rows,
                                     size_t stride, int fits)
{
    /* Written out, not looped over an array of nine: a refit writes every
    ** triangle's rows, and the loops were two fifths of its instructions
    ** (callgrind, bench/game's 59k refit, issue 36). */
    float *r = rows;

    if (fits) {
        r[0] = (float)t->a.x, r += stride;
        r[0] = (float)t->a.y, r += stride;
        r[0] = (float)t->a.z, r += stride;
        r[0] = (float)t->b.x, r += stride;
        r[0] = (float)t->b.y, r += stride;
        r[0] = (float)t->b.z, r += stride;
        r[0] = (float)t->c.x, r += stride;
        r[0] = (float)t->c.y, r += stride;
        r[0] = (float)t->c.z;
    } else
        rows_nan(rows, stride);
}

/* leaf_rows_fitting with the test of every coordinate (fits: each is
** within RAY__LEAF_FLOAT_MAX). */
static inline void leaf_rows(const ray__tri *t, float *rows, size_t stride)
{
    leaf_rows_fitting(t, rows, stride,
                      row_fits(t->a.x) & row_fits(t->a.y) &
                      row_fits(t->a.z) & row_fits(t->b.x) &
                      row_fits(t->b.y) & row_fits(t->b.z) &
                      row_fits(t->c.x) & row_fits(t->c.y) &
                      row_fits(t->c.z));
}

/*
** The slots lie in the tree's leaf order and their corners wherever
** their mesh's indices point, so in a large mesh each slot's index triple
** and then its corners are two dependent cache misses: most of a 940k
** refit's time sat on those two loads (perf annotate, bench/filter
** --profile refit, issue 36).  A pass that visits the slots in order
** knows the slots ahead (the refit's leaves and the corner copies, which
** run after the slots took the tree's order; the rows, made before, read
** the geometry as it lies and need none): slot + PREFETCH_INDICES's index
** triple is fetched, and slot + PREFETCH_CORNERS's corners, whose triple came
** PREFETCH_INDICES - PREFETCH_CORNERS slots earlier.  Only slots of the
** mesh at hand, *m of geometry m_geom (the usual case): another's would
** cost a lookup.  The distances were measured (bench/filter --profile
** refit on the 940k bunny: 8 and 4 gained little, 32 and 16 most).
** Where the slots' vertex indices lie in slot order (slot_vertices, a
** refit's), only the corners are fetched, their indices read as they
** lie.  Always inlined: GCC found a function of prefetches alone free of
** effects and dropped its calls.
*/
#define PREFETCH_INDICES 32
#define PREFETCH_CORNERS 16
/* With the indices in slot order (no index miss to wait for first), the
** corners this many slots ahead: 8 left most of the gain, 24 to 48 were
** alike (a 940k refit, issue 36). */
#define PREFETCH_AHEAD 32

/* The corners of the triangle whose index triple is at k. */
RAY__HOT_INLINE void prefetch_corners(const ray__mesh *m, const unsigned *k)
{
    RAY__PREFETCH(&m->pos[k[0]]);
    RAY__PREFETCH(&m->pos[k[1]]);
    RAY__PREFETCH(&m->pos[k[2]]);
}

RAY__HOT_INLINE void ray__prefetch_slots(const ray_scene *s, size_t slot,
                                         const ray__mesh *m, unsigned m_geom)
{
    const ray__tri_id *id;

    if (s->slot_vertices != NULL && m->own_indices) {
        if (slot + PREFETCH_AHEAD < s->n_live_tris &&
            (s->slot_geom == m_geom ||
             s->tri_ids[slot + PREFETCH_AHEAD].geom_id == m_geom))
            prefetch_corners(m,
                             s->slot_vertices + 3 * (slot + PREFETCH_AHEAD));
        return;
    }
    if (slot + PREFETCH_INDICES < s->n_live_tris) {
        id = &s->tri_ids[slot + PREFETCH_INDICES];
        if (id->geom_id == m_geom)
            RAY__PREFETCH(m->indices + 3 * (size_t)id->prim_id);
    }
    if (slot + PREFETCH_CORNERS < s->n_live_tris) {
        id = &s->tri_ids[slot + PREFETCH_CORNERS];
        if (id->geom_id == m_geom)
            prefetch_corners(m, m->indices + 3 * (size_t)id->prim_id);
    }
}

/* The build's boxes of slots begin .. end - 1 (boxes.c; the triangle
** BVH's costs->boxes, accel/bvh.h), and the refit's leaf (boxes.c:
** ray__bvh_refit's range_box, ud the scene). */
void ray__tri_boxes(const void *ud, size_t begin, size_t end,
                    ray__box_rec *out);
void ray__refit_leaf(const void *ud, size_t first, size_t n, float lo[3],
                     float hi[3]);

/* The refit's leaf built for AVX2 (refit_avx2.c), which triangles.c
** runs on a CPU with AVX2; NULL where that file was built without it. */
ray__range_box_fn ray__refit_leaf_avx2(void);

#endif /* RAY_SCENE_SLOTS_H */
