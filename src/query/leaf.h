/* SPDX-License-Identifier: MIT */
/*
** leaf.h -- part of the query template (traverse.h): what a leaf holds,
** tested: the triangles of a triangle leaf (the nearest so far and the
** tie rule), the other kinds but instances one by one through the
** kinds' dispatch (scene/kinds.c).
*/
#ifndef RAY_LEAF_H
#define RAY_LEAF_H

#include "query/gate.h"

/*
** The nearest triangle so far (index TRI_NONE: none yet), and the
** interval's end a new candidate is tested against: r->tmax before the
** first triangle hit (the interval is open), the next double above it
** after one, so that a tie is seen and settled by tri_beats; and where
** its corners are read again for the hit record (its leaf's rows and
** their stride: ray__leaf_tri), once per ray rather than copied at every
** candidate that becomes the nearest.
*/
#define TRI_NONE 0xffffffffu
typedef struct tri_best {
    unsigned index;
    double beta, gamma;
    double limit;
    const float *rows;
    unsigned n;
} tri_best;

static inline void tri_best_start(tri_best *b)
{
    b->index = TRI_NONE;
}

/* What a candidate's t must lie below for a ray r whose nearest triangle
** so far is *best (NULL: any hit, no ties to settle). */
static inline double tri_limit(const ray_ray *r, const void *best)
{
    const tri_best *b = best;

    return b != NULL && b->index != TRI_NONE ? b->limit : r->tmax;
}

/*
** Does triangle i, hit at t (below the limit), beat the nearest so far?
** Nearer wins; of two hit at the same t (a ray through a shared edge or
** vertex hits both, often at equal t), the lower (geom_id, prim_id) wins,
** whichever the traversal met first: the answer then depends on the
** geometry alone, not on the order a traversal visits it in, so packets
** (ray_intersect_batch), refit and rebuilt trees and single rays agree.
*/
static inline int tri_beats(const ray_scene *s, unsigned i, double t,
                            const ray_ray *r, const void *best)
{
    const tri_best *b = best;
    const ray__tri_id *x, *y;

    if (t < r->tmax || b == NULL || b->index == TRI_NONE)
        return 1;
    x = &s->tri_ids[i];
    y = &s->tri_ids[b->index];
    return x->geom_id != y->geom_id ? x->geom_id < y->geom_id
                                    : x->prim_id < y->prim_id;
}

/* Record hit t on triangle i (its leaf's rows from "rows", stride n;
** beta, gamma) as the nearest so far. */
static inline void tri_hit(unsigned i, const float *rows, unsigned n,
                           double t, double beta, double gamma, ray_ray *r,
                           void *best)
{
    r->tmax = t;
    if (best != NULL) {
        tri_best *b = best;
        b->index = i;
        b->rows = rows;
        b->n = n;
        b->beta = beta;
        b->gamma = gamma;
        b->limit = ray__next_up(t);     /* nextafter, inline (vec.h) */
    }
}

/*
** ray__triangle_fill (prim/triangle.c) on the corners *c: the record of
** a triangle hit.  The AVX2 copy computes it in the lanes of a register
** (x, y, z and a lane not used) with the same operations in the same
** order, lane for lane -- the cross product's products and difference,
** the division by the largest component and the product by 1 / |n|, the
** point's and its error bound's sums of products: IEEE arithmetic rounds
** each the same in a lane as alone -- so the same bits (tests/check_bvh.c
** compares every record of the AVX2 copy with the plain copy's, which
** calls ray__triangle_fill, byte for byte: hit_same), at about half
** the instructions of the call (callgrind, bench/raycost's camera rays
** that hit, issue 34).  The plain copy calls it.
*/
#if defined(__AVX2__) && !defined(RAY_NO_SIMD)
static inline __m256d corner_lanes(const ray_vec3 *v)
{
    /* x, y, z and 0: not a read past the corner (the last corner of
    ** leaf_tri ends its array). */
    return _mm256_maskload_pd(&v->x, _mm256_set_epi64x(0, -1, -1, -1));
}

static inline void vec_from_lanes(ray_vec3 *v, __m256d x)
{
    /* x and y, then z: straight from the register, not through a copy
    ** of the four lanes on the stack. */
    _mm_storeu_pd(&v->x, _mm256_castpd256_pd128(x));
    _mm_store_sd(&v->z, _mm256_extractf128_pd(x, 1));
}

static inline int tri_fill(const ray__tri *c, double t, double beta,
                           double gamma, ray_hit *hit)
{
    __m256d a = corner_lanes(&c->a), b = corner_lanes(&c->b);
    __m256d cc = corner_lanes(&c->c);
    __m256d e1 = _mm256_sub_pd(b, a), e2 = _mm256_sub_pd(cc, a);
    /* yzx and zxy: v3_cross's x = e1.y e2.z - e1.z e2.y and the others */
    __m256d cr = _mm256_sub_pd(
        _mm256_mul_pd(_mm256_permute4x64_pd(e1, _MM_SHUFFLE(3, 0, 2, 1)),
                      _mm256_permute4x64_pd(e2, _MM_SHUFFLE(3, 1, 0, 2))),
        _mm256_mul_pd(_mm256_permute4x64_pd(e1, _MM_SHUFFLE(3, 1, 0, 2)),
                      _mm256_permute4x64_pd(e2, _MM_SHUFFLE(3, 0, 2, 1))));
    double alpha = 1.0 - beta - gamma, m, len, q[4];
    ray_vec3 n;
    __m256d pa, pb, pc, err, ok;

    vec_from_lanes(&n, cr);
    if (!v3_normalizable(n))            /* v3_normalize's test */
        return 0;
    m = dmax(dmax(fabs(n.x), fabs(n.y)), fabs(n.z));
    cr = _mm256_div_pd(cr, _mm256_set1_pd(m));
    _mm256_storeu_pd(q, cr);
    len = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
    cr = _mm256_mul_pd(cr, _mm256_set1_pd(1.0 / len));
    pa = _mm256_mul_pd(a, _mm256_set1_pd(alpha));
    pb = _mm256_mul_pd(b, _mm256_set1_pd(beta));
    pc = _mm256_mul_pd(cc, _mm256_set1_pd(gamma));
    {
        __m256d sign = _mm256_set1_pd(-0.0);
        err = _mm256_add_pd(_mm256_add_pd(_mm256_andnot_pd(sign, pa),
                                          _mm256_andnot_pd(sign, pb)),
                            _mm256_andnot_pd(sign, pc));
    }
    err = _mm256_add_pd(_mm256_mul_pd(err, _mm256_set1_pd(ray__gamma(7))),
                        _mm256_set1_pd(4 * RAY__TINY));
    /* err finite in x, y, z (ray__triangle_fill says why that is p's) */
    ok = _mm256_cmp_pd(_mm256_sub_pd(err, err), _mm256_setzero_pd(),
                       _CMP_EQ_OQ);
    if ((_mm256_movemask_pd(ok) & 7) != 7)
        return 0;
    hit->t = t;
    vec_from_lanes(&hit->p, _mm256_add_pd(_mm256_add_pd(pa, pb), pc));
    vec_from_lanes(&hit->n, cr);
    hit->u = beta;
    hit->v = gamma;
    vec_from_lanes(&hit->p_err, err);
    return 1;
}

/*
** ray__instance_to_world (scene/instance.c) in the lanes of a register,
** x, y, z: lane k of each step is row k's sum there, with the same
** operations in the same order (the point, its error's carried, forward
** and return terms, their sum; the normal by the columns of L^-1), so
** the same bits (tests/check_bvh.c compares the AVX2 copy's instance
** hits with the plain copy's, byte for byte).  The matrices' columns are
** the lanes: |m[k][j]| for k = 0, 1, 2 is column j of |L|.  The record
** of an instance's nearest hit took 372 instructions as the scalar call,
** about 220 here: rays onto a crowd of instances 1,803 -> 1,750 a ray
** (callgrind, bench/game DATA instances), 1.82, 1.68, 1.69 -> 1.79,
** 1.67, 1.64 times Embree's time in three interleaved runs (bench/game,
** issue 36).  A return term past DBL_MAX, which the scalar form scales
** differently, is left to it.
*/
static inline __m256d lanes3(double x, double y, double z)
{
    return _mm256_set_pd(0.0, z, y, x);
}

static inline void inst_to_world(const ray__instance *in, const ray_hit *obj,
                                 ray_hit *world)
{
    const double (*m)[4] = in->xfm.m;
    const __m256d sign = _mm256_set1_pd(-0.0);
    __m256d col[4], acol[4], ainv[3], w, back, g5s, bound, p[3], e[3];
    double q[4];
    int j;

    for (j = 0; j < 4; j++) {
        col[j] = lanes3(m[0][j], m[1][j], m[2][j]);
        acol[j] = _mm256_andnot_pd(sign, col[j]);
    }
    for (j = 0; j < 3; j++) {
        ainv[j] = _mm256_andnot_pd(
            sign, lanes3(in->inv[0][j], in->inv[1][j], in->inv[2][j]));
    }
    p[0] = _mm256_set1_pd(obj->p.x);
    p[1] = _mm256_set1_pd(obj->p.y);
    p[2] = _mm256_set1_pd(obj->p.z);
    /* point_to_world: row_dot (three products, left to right) + m[k][3] */
    w = _mm256_add_pd(
        _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(col[0], p[0]),
                                    _mm256_mul_pd(col[1], p[1])),
                      _mm256_mul_pd(col[2], p[2])),
        col[3]);
    /* back[j] = scaled_row_sum(g5, inv[j], |w.x| + |m[0][3]|, ...): the
    ** sums |w_k| + |m[k][3]| are lanes, broadcast one at a time */
    {
        __m256d a = _mm256_add_pd(_mm256_andnot_pd(sign, w), acol[3]);
        _mm256_storeu_pd(q, a);
        back = _mm256_add_pd(
            _mm256_add_pd(_mm256_mul_pd(ainv[0], _mm256_set1_pd(q[0])),
                          _mm256_mul_pd(ainv[1], _mm256_set1_pd(q[1]))),
            _mm256_mul_pd(ainv[2], _mm256_set1_pd(q[2])));
        _mm256_storeu_pd(q, back);
        if (!(q[0] < HUGE_VAL && q[1] < HUGE_VAL && q[2] < HUGE_VAL)) {
            ray__instance_to_world(in, obj, world);
            return;
        }
        g5s = _mm256_mul_pd(_mm256_set1_pd(ray__gamma(5)), back);
        _mm256_storeu_pd(q, g5s);
    }
    e[0] = _mm256_set1_pd(obj->p_err.x);
    e[1] = _mm256_set1_pd(obj->p_err.y);
    e[2] = _mm256_set1_pd(obj->p_err.z);
    {
        __m256d carried = _mm256_add_pd(
            _mm256_add_pd(_mm256_mul_pd(acol[0], e[0]),
                          _mm256_mul_pd(acol[1], e[1])),
            _mm256_mul_pd(acol[2], e[2]));
        __m256d fwd = _mm256_mul_pd(
            _mm256_set1_pd(ray__gamma(4)),
            _mm256_add_pd(
                _mm256_add_pd(
                    _mm256_add_pd(
                        _mm256_mul_pd(acol[0], _mm256_andnot_pd(sign, p[0])),
                        _mm256_mul_pd(acol[1], _mm256_andnot_pd(sign, p[1]))),
                    _mm256_mul_pd(acol[2], _mm256_andnot_pd(sign, p[2]))),
                acol[3]));
        __m256d ret = _mm256_add_pd(
            _mm256_add_pd(_mm256_mul_pd(acol[0], _mm256_set1_pd(q[0])),
                          _mm256_mul_pd(acol[1], _mm256_set1_pd(q[1]))),
            _mm256_mul_pd(acol[2], _mm256_set1_pd(q[2])));
        bound = _mm256_mul_pd(_mm256_add_pd(_mm256_add_pd(carried, fwd), ret),
                              _mm256_set1_pd(1.0 + ray__gamma(2)));
    }
    *world = *obj;
    vec_from_lanes(&world->p, w);
    vec_from_lanes(&world->p_err, bound);
    if (!in->linear_identity) {
        /* normal_to_world: inv[0][k] n.x + inv[1][k] n.y + inv[2][k] n.z,
        ** the rows of L^-1 as lanes, then normalized (the scalar call) */
        ray_vec3 n;
        __m256d r0 = _mm256_maskload_pd(in->inv[0],
                                        _mm256_set_epi64x(0, -1, -1, -1));
        __m256d r1 = _mm256_maskload_pd(in->inv[1],
                                        _mm256_set_epi64x(0, -1, -1, -1));
        __m256d r2 = _mm256_maskload_pd(in->inv[2],
                                        _mm256_set_epi64x(0, -1, -1, -1));
        vec_from_lanes(
            &n, _mm256_add_pd(
                    _mm256_add_pd(
                        _mm256_mul_pd(r0, _mm256_set1_pd(obj->n.x)),
                        _mm256_mul_pd(r1, _mm256_set1_pd(obj->n.y))),
                    _mm256_mul_pd(r2, _mm256_set1_pd(obj->n.z))));
        if (v3_normalize(n, &n))
            world->n = n;
    }
}
#else
static inline int tri_fill(const ray__tri *c, double t, double beta,
                           double gamma, ray_hit *hit)
{
    return ray__triangle_fill(c->a, c->b, c->c, t, beta, gamma, hit);
}

static inline void inst_to_world(const ray__instance *in, const ray_hit *obj,
                                 ray_hit *world)
{
    ray__instance_to_world(in, obj, world);
}
#endif

/*
** The hit record of b (a triangle found: index != TRI_NONE) at t, in the
** space of scene s, into *h: 1, or 0 if it did not fill -- which cannot
** happen, as a triangle that was hit has a normal (ray__tri_of).  Every
** triangle query ends here: single rays, the general query's triangles
** and the packets' lanes.
*/
static inline int tri_record(const ray_scene *s, const tri_best *b,
                             double t, ray_hit *h)
{
    ray__tri copy;
    const ray__tri *c = ray__leaf_tri_at(s, b->index, b->rows, b->n, &copy);

    if (!tri_fill(c, t, b->beta, b->gamma, h))
        return 0;
    h->geom_id = s->tri_ids[b->index].geom_id;
    h->prim_id = s->tri_ids[b->index].prim_id;
    h->inst_id = RAY_INVALID_ID;
    return 1;
}

/*
** Geometry "idx" (not a triangle) against r, gated or not: 0 on a miss,
** RAY__HIT_FULL with *h filled, or (ungated only) RAY__HIT_T with h->t
** alone, its record left for prim_fill_best to fill if it stays the
** nearest -- a sphere's or a plane's record (a normalisation, a point
** projected, for a sphere an atan2 and an acos) is then filled once per
** ray, not once per candidate, and never for an any-hit query.  A gated
** query fills every candidate: its filters and collector take records.
*/
static inline int prim_candidate(const ray_scene *s, unsigned idx,
                                 const ray_ray *r, ray_hit *h,
                                 ray__counts *qc)
{
    if (qc->gate != NULL)
        return prim_gated(s, idx, r, h, qc);
    if (s->prims[idx].kind == RAY__KIND_POLYGON) {
        ray__count_tests(qc, RAY_PRIM_POLYGON, 1);
        return ray__polygon_candidate(s, idx, r, h);
    }
    return ray__prim_candidate(s, idx, r, h, qc);
}

/* The nearest hit of a geometry other than a triangle so far: its record
** h, or (deferred != RAY_INVALID_ID) geometry "deferred"'s hit at h.t,
** whose record prim_fill_best fills: a kind's own (ray__prim_fill), or,
** where "child" is set, instance "deferred"'s, from triangle "tri" of
** its child of triangles alone (instance_nearest, traverse.h). */
typedef struct prim_best {
    ray_hit h;
    unsigned deferred;
    const ray_scene *child;
    tri_best tri;
} prim_best;

/* Record candidate h of geometry idx (prim_candidate's answer k) as the
** nearest so far. */
static inline void prim_keep(prim_best *b, unsigned idx, int k,
                             const ray_hit *h)
{
    b->child = NULL;
    if (k == RAY__HIT_T) {
        b->h.t = h->t;
        b->deferred = idx;
    } else {
        b->h = *h;
        b->deferred = RAY_INVALID_ID;
    }
}

/* Fill the deferred record of *b, if any: the same formulas on the same t
** as the candidate test would have filled it with (prim_candidate made
** sure it fills; an instance's child triangle was hit, so it has a
** normal), in s's space.  0 if it failed (cannot happen). */
static inline int prim_fill_best(const ray_scene *s, const ray_ray *r,
                                 prim_best *b, const ray__counts *qc)
{
    const ray__instance *in;
    ray_hit h;

    if (b->deferred == RAY_INVALID_ID)
        return 1;
    if (b->child == NULL)
        return ray__prim_fill(s, b->deferred, r, b->h.t, qc->uv, &b->h);
    in = &s->instances[s->prims[b->deferred].surface];
    if (!tri_record(b->child, &b->tri, b->h.t, &h))
        return 0;
    inst_to_world(in, &h, &b->h);
    b->h.inst_id = b->deferred;
    return 1;
}

/*
** Slot i against r: the exact test (the watertight test, or Cramer's
** where the scene asks for it), or in the bench's RAY__TRI_FLOAT mode
** the float test's verdict; then the tie rule and the gate.  1 if it is
** the nearest so far (or any hit's), r->tmax shrunk to it.
*/
static inline int tri_slot(const ray_scene *s, trav *tr, unsigned i,
                           const float *rows, unsigned n, ray_ray *r,
                           void *best, ray__counts *qc)
{
    double th, beta, gamma, limit = tri_limit(r, best);
    ray__tri copy;
    const ray__tri *t;
    int hit;

    if (s->tri_mode == RAY__TRI_FLOAT && tr->flt.on) {
        hit = tri_float_hit(&tr->flt, rows, n, r->tmin, limit, &th, &beta,
                            &gamma);
        if (!hit)
            return 0;
        t = ray__leaf_tri_at(s, i, rows, n, &copy);
    } else {
        t = ray__leaf_tri_at(s, i, rows, n, &copy);
        RAY__WORK(RAY__WORK_EXACT, 1);
        if (s->watertight) {
            hit = ray__triangle_watertight_pre(&tr->wt, r->tmin, limit,
                                               &t->a, &t->b, &t->c, &th,
                                               &beta, &gamma);
        } else {
            ray_ray rl = *r;
            rl.tmax = limit;
            hit = ray__triangle_test(&rl, t->a, t->b, t->c, &th, &beta,
                                     &gamma);
        }
    }
    if (!hit || !tri_beats(s, i, th, r, best))
        return 0;
    if (qc->gate != NULL && !tri_gate(s, i, t, th, beta, gamma, r, qc))
        return 0;
    tri_hit(i, rows, n, th, beta, gamma, r, best);
    return 1;
}

/*
** Scenes with at least this many triangles have an any-hit query
** prefetch a leaf's double corners too: 16 MiB of them (72 bytes a
** triangle), past what a core's share of the last-level cache holds.
** Shadow rays on the 59k bunny (4.2 MB of corners, cached) lost 4% to
** the prefetches' instructions; incoherent any-hit rays on the 940k
** bunny (68 MB) gained 15% (bench/raycost, bench/mesh, issue 34).
*/
#define PREFETCH_ANY_TRIS (((size_t)16 << 20) / sizeof(ray__tri))

/*
** The triangles first .. end - 1 of a leaf, in order, each hit shrinking
** r->tmax; "any": stop at the first hit.  The float filter (filter.h)
** takes up to eight at a time and keeps those the exact test must see,
** which it then tests one after another in slot order: the answers are
** those of testing every triangle with the exact test, as the filter
** only drops misses (and misses offer nothing to a gate).
*/
static inline int tri_leaf(const ray_scene *s, trav *tr,
                           unsigned first, unsigned end, ray_ray *r,
                           void *best, int any, ray__counts *qc)
{
    const float *rows = s->leaf_f + RAY__LEAF_ROWS * (size_t)first;
    unsigned n = end - first, j0;
    int found = 0;

    /* The double corners the exact test reads for the filter's
    ** survivors, asked for before the filter runs on the rows.  An
    ** any-hit query usually ends at its first hit, so most corners it
    ** asks for are never read: it asks only where they would miss the
    ** cache anyway (PREFETCH_ANY_TRIS). */
    if (s->leaf_tri != NULL && (!any || s->n_live_tris >= PREFETCH_ANY_TRIS))
        prefetch_bytes(s->leaf_tri + first, n * sizeof *s->leaf_tri);
    if (s->watertight && !trav_frame(tr, r, s))
        return 0;
    for (j0 = 0; j0 < n; j0 += RAY__LEAF_MAX) {
        unsigned count = n - j0 < RAY__LEAF_MAX ? n - j0 : RAY__LEAF_MAX;
        unsigned keep = s->watertight && tr->flt.on
                            ? tri_filter_leaf(&tr->flt, rows + j0, n, count)
                            : (1u << count) - 1u;
        RAY__WORK(RAY__WORK_FILTERED,
                  s->watertight && tr->flt.on ? count : 0);
        for (; keep != 0; keep &= keep - 1) {
            unsigned j = j0 + (unsigned)lowest_bit(keep);
            if (tri_slot(s, tr, first + j, rows + j, n, r, best, qc)) {
                found = 1;
                if (any)
                    return 1;
            }
        }
    }
    return found;
}

#endif /* RAY_LEAF_H */
