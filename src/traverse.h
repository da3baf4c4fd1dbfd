/* SPDX-License-Identifier: MIT */
/*
** traverse.h -- the scene queries (nearest hit, any hit) over the planes
** and the two BVHs, as static functions: included by intersect.c, built
** for the baseline instruction set, and by intersect_avx2.c, built with
** AVX2 (the Makefile adds -mavx2 on x86), which ray__intersect and
** ray__occluded pick at run time on CPUs that have it.  Both copies do
** the same arithmetic, lane for lane, so they give the same answers.
** The traversal knows triangles alone, tested inline; every other kind
** is reached through the kinds' dispatch, ray__prim_intersect (kinds.c).
*/
#ifndef RAY_TRAVERSE_H
#define RAY_TRAVERSE_H

#include <string.h>

#include "scene.h"
#include "watertight.h"

/*
** The slab test, eight boxes at a time in float, kept conservative: it
** may let a box through that the ray misses, never the reverse.
**
**   * The origin is bracketed, o_lo <= o <= o_hi (float_down / float_up),
**     and each plane distance uses the end that makes the near distance
**     smaller and the far distance larger; the boxes themselves were
**     rounded outward from the double geometry.
**   * (b - o) * (1/d) then carries three float roundings (gamma(3) of
**     float, relative), so the far distance -- clipped to tmax first, so
**     that the same slack covers a near distance rounded past tmax -- is
**     moved away from zero by FAR_SLACK times its magnitude (a factor,
**     as in Ize's 1 + 2 gamma(3), would move a negative far distance the
**     wrong way: tmin may be negative).  Ize proves with that bound that
**     no hit is lost ("Robust BVH Ray Traversal", JCGT 2(2), 2013;
**     pbrt-v4 Bounds3::IntersectP; Embree's robust mode); the popped
**     entries get the same slack against tmax.
**   * The distances are in units of a direction scaled by a power of two
**     (exact) so that its largest component lies in [1, 2): 1/d of that
**     component is then a normal float whatever the ray's length.
**   * A zero direction component makes 1/d = +-Inf (IEEE), so the slab is
**     everything or nothing (Williams et al., "An Efficient and Robust
**     Ray-Box Intersection Algorithm", JGT 10(1), 2005); 0 * Inf = NaN
**     when the origin is on the plane, and the max/min below ignore a NaN
**     operand: the box is kept.  A component too small beside the largest
**     for 1/d to be a normal float (below 2^-126 of it) gets 1/d = NaN:
**     its slab is ignored, which only lets more boxes through.
**
** Everything else stays in double: the triangle tests decide the hits.
*/
typedef struct trav {
    float o_near[3], o_far[3];   /* the origin end used for near / far */
    float inv[3];                /* 1 / scaled direction (NaN: ignored) */
    size_t near_at[3], far_at[3];/* offsets of the near / far bound arrays */
    float tmin;                  /* scaled, widened to a float */
    double t_scale;              /* distance units of the scaled direction */
    int framed;                  /* wt set up: 1; 0 not yet; -1 cannot be */
    ray__watertight wt;          /* the triangle test's frame of the ray */
#if RAY__PAIRS
    ray__watertight2 wt2;        /* the same, for two triangles at once */
#endif
} trav;

/*
** The far distance's slack, relative: 2 gamma(3) as Ize's bound asks
** (the near and the far distance each off by gamma(3)), plus 4u for the
** two roundings of far + |far| * slack itself; u = 2^-24.
*/
#define FLOAT_U 5.9604644775390625e-8f
#define FAR_SLACK (2.0f * (3.0f * FLOAT_U) / (1.0f - 3.0f * FLOAT_U) + \
                   4.0f * FLOAT_U)

/* The interval's end t in the scaled units, rounded up to a float. */
static inline float trav_tmax(const trav *tr, double t)
{
    return ray__float_up(t * tr->t_scale);
}

/* t moved away from zero by the slack. */
static inline float with_slack(float t)
{
    return t + fabsf(t) * FAR_SLACK;
}

/* 2^e for e in [-1022, 1023], built from its bits (exact). */
static inline double pow2(int e)
{
    uint64_t bits = (uint64_t)(e + 1023) << 52;
    double x;

    memcpy(&x, &bits, sizeof x);
    return x;
}

/* The binary exponent of finite x > 0, clamped to [-1022, 1023] (a
** subnormal gets -1022). */
static inline int exponent_of(double x)
{
    uint64_t bits;
    int e;

    memcpy(&bits, &x, sizeof bits);
    e = (int)(bits >> 52 & 0x7ff) - 1023;
    return e < -1022 ? -1022 : e;
}

/* Axis k of the traversal data: origin component o, direction component
** d, and d scaled by the power of two (ds). */
static inline void trav_axis(trav *tr, int k, double o, double d, double ds)
{
    /* 1/d < 0 exactly when d's sign bit is set (d = -0: -Inf). */
    int neg = signbit(d) != 0;
    double inv = 1.0 / ds;
    float ends[2];
    size_t at[2];

    ends[0] = ray__float_down(o);
    ends[1] = ray__float_up(o);
    at[0] = offsetof(ray__wnode, lo[k]);
    at[1] = offsetof(ray__wnode, hi[k]);
    /* 1/d beyond float: NaN, the slab ignored (chosen by indexing, as
    ** the other choices here). */
    {
        double choice[2];
        choice[0] = inv;
        choice[1] = (double)NAN;
        tr->inv[k] = (float)choice[(d != 0) & !(fabs(ds) >= 0x1p-126)];
    }
    /* inv >= 0: near = (lo_plane - o_hi) * inv, far = (hi - o_lo) * inv;
    ** inv < 0:  near = (hi_plane - o_lo) * inv, far = (lo - o_hi) * inv. */
    tr->near_at[k] = at[neg];
    tr->far_at[k] = at[!neg];
    tr->o_near[k] = ends[!neg];
    tr->o_far[k] = ends[neg];
}

/*
** The traversal data of r, a ray that passed ray__ray_usable.  Free of
** branches on the ray's signs and roundings (each a coin toss for
** incoherent rays): the choices are made by indexing, and the axes are
** written out (a loop's exit is mispredicted once a ray).
*/
static void trav_init(trav *tr, const ray_ray *r)
{
    ray_vec3 ad = v3_abs(r->dir);
    double m = ad.x > ad.y ? ad.x : ad.y, down;
    int e;

    m = m > ad.z ? m : ad.z;
    e = exponent_of(m);
    tr->t_scale = pow2(e);          /* t' = t 2^e for d' = d 2^-e */
    down = pow2(-e);
    trav_axis(tr, 0, r->org.x, r->dir.x, r->dir.x * down);
    trav_axis(tr, 1, r->org.y, r->dir.y, r->dir.y * down);
    trav_axis(tr, 2, r->org.z, r->dir.z, r->dir.z * down);
    tr->tmin = ray__float_down(r->tmin * tr->t_scale);
    tr->framed = 0;
}

/*
** The triangle test's frame of the ray, set up when the ray first reaches
** a leaf of triangles: most primary rays of a scene that does not fill
** the frame reach none, and would pay its three divisions for nothing.
** 0 if the ray has no frame (a zero or NaN direction: never for a ray
** that passed ray__ray_usable).
*/
static inline int trav_frame(trav *tr, const ray_ray *r)
{
    if (tr->framed == 0) {
        tr->framed = ray__watertight_init(&tr->wt, r) ? 1 : -1;
#if RAY__PAIRS
        if (tr->framed > 0)
            ray__watertight2_init(&tr->wt2, &tr->wt);
#endif
    }
    return tr->framed > 0;
}

/* Node q's bound array at byte offset "at" (one of trav's offsets). */
static inline const float *bound_at(const ray__wnode *q, size_t at)
{
    return (const float *)(const void *)((const char *)q + at);
}

/*
** Which of node q's boxes does the ray enter within (tmin, tmax)?
** boxes_hit returns a bit mask; entry[k] is where it enters box k.  The
** ray's quantities are first spread over the lanes ("lanes", once per
** traversal), so a node costs only its loads and the arithmetic.
*/
#if !defined(RAY_NO_SIMD) && (defined(__AVX__) || defined(__SSE2__))
#if RAY__WIDTH != 8
#error "boxes_hit below tests eight lanes, or two halves of four"
#endif
/*
** The ray's quantities in a register each: eight lanes with AVX (the
** AVX2 copy of the queries), four with SSE.
*/
#if defined(__AVX__)
#include <immintrin.h>
typedef __m256 vf;
#define VF_SET1 _mm256_set1_ps
#else
#include <emmintrin.h>
typedef __m128 vf;
#define VF_SET1 _mm_set1_ps
#endif

typedef struct lanes {
    vf o_near[3], o_far[3], inv[3], tmin, slack;
    size_t near_at[3], far_at[3];
} lanes;

static inline void lanes_axis(lanes *l, const trav *tr, int a)
{
    l->o_near[a] = VF_SET1(tr->o_near[a]);
    l->o_far[a] = VF_SET1(tr->o_far[a]);
    l->inv[a] = VF_SET1(tr->inv[a]);
    l->near_at[a] = tr->near_at[a];
    l->far_at[a] = tr->far_at[a];
}

static void lanes_init(lanes *l, const trav *tr)
{
    lanes_axis(l, tr, 0);           /* written out: no loop to exit */
    lanes_axis(l, tr, 1);
    lanes_axis(l, tr, 2);
    l->tmin = VF_SET1(tr->tmin);
    l->slack = VF_SET1(FAR_SLACK);
}
#endif

#if defined(__AVX__) && !defined(RAY_NO_SIMD)
/*
** AVX: all eight lanes in one register, the same arithmetic as the plain
** loop below lane for lane (vmaxps / vminps pick as maxps / minps do).
*/
static inline void slab8(const ray__wnode *q, const lanes *l, int a,
                         __m256 *t0, __m256 *t1)
{
    __m256 np = _mm256_loadu_ps(bound_at(q, l->near_at[a]));
    __m256 fp = _mm256_loadu_ps(bound_at(q, l->far_at[a]));
    __m256 tn = _mm256_mul_ps(_mm256_sub_ps(np, l->o_near[a]), l->inv[a]);
    __m256 tf = _mm256_mul_ps(_mm256_sub_ps(fp, l->o_far[a]), l->inv[a]);

    *t0 = _mm256_max_ps(tn, *t0);                    /* NaN tn: ignored */
    *t1 = _mm256_min_ps(tf, *t1);                    /* NaN tf: ignored */
}

static inline unsigned boxes_hit(const ray__wnode *q, const lanes *l,
                                 float tmax, float entry[RAY__WIDTH])
{
    __m256 t0 = l->tmin, t1 = _mm256_set1_ps(HUGE_VALF);

    slab8(q, l, 0, &t0, &t1);
    slab8(q, l, 1, &t0, &t1);
    slab8(q, l, 2, &t0, &t1);
    t1 = _mm256_min_ps(t1, _mm256_set1_ps(tmax));
    t1 = _mm256_add_ps(t1, _mm256_mul_ps(
                               _mm256_andnot_ps(_mm256_set1_ps(-0.0f), t1),
                               l->slack));
    _mm256_storeu_ps(entry, t0);
    return (unsigned)_mm256_movemask_ps(_mm256_cmp_ps(t0, t1, _CMP_LE_OQ));
}
#elif defined(__SSE2__) && !defined(RAY_NO_SIMD)
/*
** SSE: four lanes a register, the same arithmetic as the plain loop below
** lane for lane; a node's two halves are independent, so their latencies
** overlap.  maxps / minps return their second operand when either is NaN,
** so max(tn, t0) keeps t0 for a NaN tn exactly as the plain
** "tn > t0 ? tn : t0" does.  slab4 narrows [*t0, *t1] to the slab of
** axis a in lanes lane .. lane + 3.
*/
static inline void slab4(const ray__wnode *q, const lanes *l, int a,
                         int lane, __m128 *t0, __m128 *t1)
{
    __m128 np = _mm_loadu_ps(bound_at(q, l->near_at[a]) + lane);
    __m128 fp = _mm_loadu_ps(bound_at(q, l->far_at[a]) + lane);
    __m128 tn = _mm_mul_ps(_mm_sub_ps(np, l->o_near[a]), l->inv[a]);
    __m128 tf = _mm_mul_ps(_mm_sub_ps(fp, l->o_far[a]), l->inv[a]);

    *t0 = _mm_max_ps(tn, *t0);                       /* NaN tn: ignored */
    *t1 = _mm_min_ps(tf, *t1);                       /* NaN tf: ignored */
}

static inline unsigned boxes_hit4(const ray__wnode *q, const lanes *l,
                                  __m128 vmax, int lane, float *entry)
{
    __m128 t0 = l->tmin, t1 = _mm_set1_ps(HUGE_VALF);

    slab4(q, l, 0, lane, &t0, &t1);
    slab4(q, l, 1, lane, &t0, &t1);
    slab4(q, l, 2, lane, &t0, &t1);
    /* Clipped to tmax, then the slack: t1 is never NaN; -Inf (a box
    ** wholly outside a slab of a zero direction component) gives NaN,
    ** a miss. */
    t1 = _mm_min_ps(t1, vmax);
    t1 = _mm_add_ps(t1, _mm_mul_ps(_mm_andnot_ps(_mm_set1_ps(-0.0f), t1),
                                   l->slack));
    _mm_storeu_ps(entry + lane, t0);
    return (unsigned)_mm_movemask_ps(_mm_cmple_ps(t0, t1)) << lane;
}

static inline unsigned boxes_hit(const ray__wnode *q, const lanes *l,
                                 float tmax, float entry[RAY__WIDTH])
{
    __m128 vmax = _mm_set1_ps(tmax);

    /* Written out for the two halves (-O2 does not unroll a loop). */
    return boxes_hit4(q, l, vmax, 0, entry) | boxes_hit4(q, l, vmax, 4, entry);
}
#else
/* Plain C reads the ray's quantities from the traversal data itself. */
typedef struct lanes {
    const trav *tr;
} lanes;

static void lanes_init(lanes *l, const trav *tr)
{
    l->tr = tr;
}

static inline unsigned boxes_hit(const ray__wnode *q, const lanes *l,
                                 float tmax, float entry[RAY__WIDTH])
{
    const trav *tr = l->tr;
    float t0[RAY__WIDTH], t1[RAY__WIDTH];
    unsigned mask = 0;
    int a, k;

    for (k = 0; k < RAY__WIDTH; k++) {
        t0[k] = tr->tmin;
        t1[k] = HUGE_VALF;
    }
    for (a = 0; a < 3; a++) {
        const float *np = bound_at(q, tr->near_at[a]);
        const float *fp = bound_at(q, tr->far_at[a]);
        for (k = 0; k < RAY__WIDTH; k++) {
            float tn = (np[k] - tr->o_near[a]) * tr->inv[a];
            float tf = (fp[k] - tr->o_far[a]) * tr->inv[a];
            t0[k] = tn > t0[k] ? tn : t0[k];        /* NaN tn: ignored */
            t1[k] = tf < t1[k] ? tf : t1[k];        /* NaN tf: ignored */
        }
    }
    for (k = 0; k < RAY__WIDTH; k++) {
        float far = t1[k] < tmax ? t1[k] : tmax;
        far = with_slack(far);                  /* as the SSE lanes */
        entry[k] = t0[k];
        mask |= (unsigned)(t0[k] <= far) << k;
    }
    return mask;
}
#endif

enum { LEAF_TRIANGLES, LEAF_PRIMS };

/* traverse() is inlined into each caller, its "leaf" and "any" constant
** there, so that each of the four copies keeps only its own branches. */
#if defined(__GNUC__)
#define RAY__INLINE inline __attribute__((always_inline))
#else
#define RAY__INLINE inline
#endif

/* Add a query's counts to *st (if any). */
static void add_counts(ray_stats *st, const ray__counts *qc)
{
    int k;

    if (st == NULL)
        return;
    for (k = 0; k < RAY_PRIM_KINDS; k++) {
        st->tests_by_kind[k] += qc->tests[k];
        st->tests += qc->tests[k];
    }
    st->root_failures += qc->failures;
    st->filter_calls += qc->filter_calls;
}

static int tri_leaf(const ray_scene *s, trav *tr, unsigned first,
                    unsigned end, ray_ray *r, void *best, int any,
                    ray__counts *qc);
static int prim_test(const ray_scene *s, unsigned i, ray_ray *r, void *best,
                     ray__counts *qc);

/* A node's slot waiting on the traversal stack: child and count as in
** ray__wnode, and where the ray enters its box. */
typedef struct pending {
    unsigned child, count;
    float t;
} pending;

/* The lowest set bit of a mask of RAY__WIDTH bits (mask != 0). */
static inline int lowest_bit(unsigned mask)
{
#if defined(__GNUC__)
    return __builtin_ctz(mask);
#else
    int k = 0;
    while (!(mask >> k & 1))
        k++;
    return k;
#endif
}

/*
** Ordered traversal: of the children a ray enters, the nearest is visited
** next and the others pushed with their entry distances, the farthest
** deepest, so they are popped nearest first and only if still in front
** of the nearest hit found since.  One child entered (the usual case deep
** in the tree) needs no stack at all, two a single compare.  "any": stop
** at the first hit.  "leaf" picks the primitive test.
*/
static RAY__INLINE int traverse(const ray_scene *s, const ray__bvh *bvh,
                                trav *tr, ray_ray *r, int leaf,
                                void *best, int any, ray__counts *qc)
{
    pending stack[RAY__WIDTH * 64];   /* WIDTH - 1 a level, 64 levels */
    unsigned child = 0, count = 0;    /* the root: an inner node */
    float tmax = trav_tmax(tr, r->tmax);  /* earlier hits shrank it */
    float tpop = with_slack(tmax);        /* what popped entries face */
    int sp = 0, found = 0;
    lanes l;

    if (bvh->n_wide == 0)
        return 0;
    lanes_init(&l, tr);
    for (;;) {
        if (count == 0) {                           /* an inner node */
            const ray__wnode *q = &bvh->wide[child];
            float entry[RAY__WIDTH];
            unsigned mask = boxes_hit(q, &l, tmax, entry);
            int k0, k1, base, j;

            if (mask == 0)
                goto pop;
            k0 = lowest_bit(mask);
            mask &= mask - 1;
            if (mask == 0) {
                child = q->child[k0];
                count = q->count[k0];
                continue;
            }
            k1 = lowest_bit(mask);
            mask &= mask - 1;
            if (mask == 0) {
                /* Any hit will do: no order (an occluder found a little
                ** later costs less than ordering every node). */
                int near = !any && entry[k1] < entry[k0] ? k1 : k0;
                int far = near == k0 ? k1 : k0;
                stack[sp].child = q->child[far];
                stack[sp].count = q->count[far];
                stack[sp++].t = entry[far];
                child = q->child[near];
                count = q->count[near];
                continue;
            }
            /* Three or more: push them all, insertion-sorted so the
            ** nearest is on top (unsorted for any hit), and pop it. */
            base = sp;
            for (mask |= 1u << k0 | 1u << k1; mask != 0; mask &= mask - 1) {
                int k = lowest_bit(mask);
                pending p;
                p.child = q->child[k];
                p.count = q->count[k];
                p.t = entry[k];
                for (j = sp; !any && j > base && stack[j - 1].t < p.t; j--)
                    stack[j] = stack[j - 1];
                stack[j] = p;
                sp++;
            }
            sp--;
            child = stack[sp].child;
            count = stack[sp].count;
            continue;
        }
        if (leaf == LEAF_TRIANGLES) {               /* a leaf */
            unsigned n = count & ~RAY__LEAF;
            qc->tests[RAY_PRIM_TRIANGLE] += n;
            if (tri_leaf(s, tr, child, child + n, r, best, any, qc)) {
                found = 1;
                if (any)
                    return found;
                tmax = trav_tmax(tr, r->tmax);
                tpop = with_slack(tmax);
            }
        } else {
            unsigned i, end = child + (count & ~RAY__LEAF);
            for (i = child; i < end; i++) {
                if (prim_test(s, i, r, best, qc)) {
                    found = 1;
                    if (any)
                        return found;
                    tmax = trav_tmax(tr, r->tmax);
                    tpop = with_slack(tmax);
                }
            }
        }
    pop:
        do {
            if (sp == 0)
                return found;
            sp--;
        } while (stack[sp].t > tpop);
        child = stack[sp].child;
        count = stack[sp].count;
    }
}

/*
** The nearest triangle so far (index TRI_NONE: none yet), and the
** interval's end a new candidate is tested against: r->tmax before the
** first triangle hit (the interval is open), the next double above it
** after one, so that a tie is seen and settled by tri_beats.
*/
#define TRI_NONE 0xffffffffu
typedef struct tri_best {
    unsigned index;
    double beta, gamma;
    double limit;
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
** (ray_intersect_n), refit and rebuilt trees and single rays agree.
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

/* Record hit t on triangle i (beta, gamma) as the nearest so far. */
static inline void tri_hit(unsigned i, double t, double beta, double gamma,
                           ray_ray *r, void *best)
{
    r->tmax = t;
    if (best != NULL) {
        tri_best *b = best;
        b->index = i;
        b->beta = beta;
        b->gamma = gamma;
        b->limit = nextafter(t, HUGE_VAL);
    }
}

/*
** Gates (ray__gate: masks, filters, all hits), on the gated path only: a
** query without a gate never reaches them.
**
** gate_wants -- does candidate of geometry p need a hit record: a filter
** that applies to this query, or a collector?
** gate_offer -- offer candidate h of geometry p (in the space of the
** query's current scene: object space inside an instance) to its filter
** and the collector, in world space: 1 accepted, 0 rejected.  Collected
** hits are rejected after being recorded, so the traversal goes on and
** finds them all.
*/
static int gate_wants(const ray__prim *p, const ray__gate *g)
{
    return g->all != NULL ||
           (p->filter != NULL && (p->filter_queries & g->query) != 0);
}

/* Keep the cap nearest hits: a new one takes the place of the farthest
** kept when there is no room (hits order by t, then ids: collect_before). */
static int collect_before(const ray_hit *a, const ray_hit *b)
{
    if (a->t != b->t)
        return a->t < b->t;
    if (a->geom_id != b->geom_id)
        return a->geom_id < b->geom_id;
    if (a->prim_id != b->prim_id)
        return a->prim_id < b->prim_id;
    return a->inst_id < b->inst_id;
}

static void collect(ray__collect *c, const ray_hit *h)
{
    size_t i, worst = 0;

    if (c->count < c->cap) {
        ray__hit_store(&c->hits[c->count], h);
    } else if (c->cap > 0) {
        for (i = 1; i < c->cap; i++)
            if (collect_before(&c->hits[worst], &c->hits[i]))
                worst = i;
        if (collect_before(h, &c->hits[worst]))
            ray__hit_store(&c->hits[worst], h);
    }
    c->count++;
}

static int gate_offer(const ray__prim *p, const ray_ray *r, const ray_hit *h,
                      ray__counts *qc)
{
    const ray__gate *g = qc->gate;
    const ray_ray *wr = qc->inst != NULL ? qc->world_ray : r;
    ray_hit w = *h;

    if (qc->inst != NULL) {
        ray__instance_to_world(qc->inst, h, &w);
        w.inst_id = qc->inst_id;
    }
    if (p->filter != NULL && (p->filter_queries & g->query) != 0) {
        qc->filter_calls++;
        if (!p->filter(p->filter_ud, wr, &w, g->query_ud))
            return 0;
    }
    if (g->all != NULL) {
        collect(g->all, &w);
        return 0;
    }
    return 1;
}

/* Triangle i's candidate hit (t, beta, gamma) through the gate. */
static int tri_gate(const ray_scene *s, unsigned i, double t, double beta,
                    double gamma, const ray_ray *r, ray__counts *qc)
{
    const ray__tri_id *id = &s->tri_ids[i];
    const ray__prim *p = &s->prims[id->geom_id];
    const ray__tri *tri = &s->tris[i];
    ray_hit h;

    if ((p->mask & qc->gate->mask) == 0)
        return 0;
    if (!gate_wants(p, qc->gate))
        return 1;
    /* A usable triangle (checked at commit) always fills. */
    if (!ray__triangle_fill(tri->a, tri->b, tri->c, t, beta, gamma, &h))
        return 0;
    h.geom_id = id->geom_id;
    h.prim_id = id->prim_id;
    h.inst_id = RAY_INVALID_ID;
    return gate_offer(p, r, &h, qc);
}

/* A surface may be asked again past a rejected hit this many times per
** ray (ray.h: both sides of a sphere need 2; a torus 4; 16 leaves room
** for implicit surfaces with several layers, and bounds the work a filter
** that rejects everything can cause). */
#define GATE_RETRIES 16

/*
** Geometry "idx" (not a triangle) against r through the gate: hidden by
** its mask; else its hits, nearest first, offered until one is accepted
** (each next one asked for past the last: tmin = its t).  An instance
** passes its own mask here and gates its child's geometry inside.
*/
static int prim_gated(const ray_scene *s, unsigned idx, const ray_ray *r,
                      ray_hit *h, ray__counts *qc)
{
    const ray__prim *p = &s->prims[idx];
    ray_ray rr = *r;
    int k;

    if ((p->mask & qc->gate->mask) == 0)
        return 0;
    if (p->kind == RAY__KIND_INSTANCE || !gate_wants(p, qc->gate))
        return ray__prim_intersect(s, idx, r, h, qc);
    for (k = 0; k < GATE_RETRIES; k++) {
        if (!ray__prim_intersect(s, idx, &rr, h, qc))
            return 0;
        if (gate_offer(p, r, h, qc))
            return 1;
        rr.tmin = h->t;
    }
    return 0;
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
    if (qc->gate == NULL)
        return ray__prim_candidate(s, idx, r, h, qc);
    return prim_gated(s, idx, r, h, qc);
}

/* The nearest hit of a geometry other than a triangle so far: its record
** h, or (deferred != RAY_INVALID_ID) geometry "deferred"'s hit at h.t,
** whose record prim_fill_best fills. */
typedef struct prim_best {
    ray_hit h;
    unsigned deferred;
} prim_best;

/* Record candidate h of geometry idx (prim_candidate's answer k) as the
** nearest so far. */
static inline void prim_keep(prim_best *b, unsigned idx, int k,
                             const ray_hit *h)
{
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
** sure it fills).  0 if it failed (cannot happen). */
static inline int prim_fill_best(const ray_scene *s, const ray_ray *r,
                                 prim_best *b, const ray__counts *qc)
{
    if (b->deferred == RAY_INVALID_ID)
        return 1;
    return ray__prim_fill(s, b->deferred, r, b->h.t, qc->uv, &b->h);
}

/*
** The triangles first .. end - 1 of a leaf, in order, each hit shrinking
** r->tmax; "any": stop at the first hit.  Where SSE2 is there the
** watertight test takes them in pairs (an odd one pairs with itself, its
** twin lane giving the same answer, which the order below ignores); each
** pair's lanes are ended in order, so the answers are those of testing
** one triangle after another.
*/
static inline int tri_leaf(const ray_scene *s, trav *tr,
                           unsigned first, unsigned end, ray_ray *r,
                           void *best, int any, ray__counts *qc)
{
    int found = 0;
    unsigned i;
    ray_ray rl;    /* r with the limit of tri_limit as its tmax */

    if (s->watertight && !trav_frame(tr, r))
        return 0;
#if RAY__PAIRS
    if (s->watertight) {
        for (i = first; i < end; i += 2) {
            unsigned pair[2];
            const ray__tri *t0 = &s->tris[i], *t1;
            int m, lane;
            pair[0] = i;
            pair[1] = i + (i + 1 < end);   /* i itself if last; no branch */
            t1 = &s->tris[pair[1]];
            m = ray__watertight_pair(&tr->wt2, &t0->a, &t1->a, &t0->b,
                                     &t1->b, &t0->c, &t1->c);
            if (m == 0)
                continue;
            /* The twin lane of an odd last triangle is that triangle
            ** again: never offered twice (a gate would see it twice). */
            for (lane = 0; lane < 1 + (pair[1] != pair[0]); lane++) {
                const ray__tri *t = lane ? t1 : t0;
                double th, beta, gamma;
                /* A lane the pair test keeps is a hit candidate: the
                ** one-triangle test ends it, with the compensated edge
                ** functions it computes for candidates (fma, scalar). */
                int hit = (m < 0 || (m >> lane & 1)) &&
                          ray__triangle_watertight_pre(
                              &tr->wt, r->tmin, tri_limit(r, best), &t->a,
                              &t->b, &t->c, &th, &beta, &gamma) &&
                          tri_beats(s, pair[lane], th, r, best);
                if (hit && (qc->gate == NULL ||
                            tri_gate(s, pair[lane], th, beta, gamma, r,
                                     qc))) {
                    tri_hit(pair[lane], th, beta, gamma, r, best);
                    found = 1;
                    if (any)
                        return 1;
                }
            }
        }
        return found;
    }
#endif
    rl = *r;
    for (i = first; i < end; i++) {
        const ray__tri *t = &s->tris[i];
        double th, beta, gamma;
        int hit;
        rl.tmax = tri_limit(r, best);
        hit = (s->watertight
                   ? ray__triangle_watertight_pre(&tr->wt, rl.tmin, rl.tmax,
                                                  &t->a, &t->b, &t->c, &th,
                                                  &beta, &gamma)
                   : ray__triangle_test(&rl, t->a, t->b, t->c, &th, &beta,
                                        &gamma)) &&
              tri_beats(s, i, th, r, best);
        if (hit && (qc->gate == NULL ||
                    tri_gate(s, i, th, beta, gamma, r, qc))) {
            tri_hit(i, th, beta, gamma, r, best);
            found = 1;
            if (any)
                return 1;
        }
    }
    return found;
}

static int prim_test(const ray_scene *s, unsigned item, ray_ray *r,
                     void *best, ray__counts *qc)
{
    unsigned idx = s->prim_bvh.items[item];
    ray_hit h;
    int k = prim_candidate(s, idx, r, &h, qc);

    if (!k)
        return 0;
    r->tmax = h.t;
    if (best != NULL)
        prim_keep(best, idx, k, &h);
    return 1;
}

/*
** A scene of a few spheres (the Whitted scene has two) is not traversed:
** its spheres are tested one after another, as the planes are, and the
** ray's traversal data (trav_init: three divisions and six roundings to
** float) is then not set up at all unless the scene has triangles.  A
** sphere's test for t alone costs about what the box test of a node
** that would skip it does, and trav_init cost 9% of the Whitted
** render's profile (perf, examples/whitted 1024 x 768, one thread).  The
** answers are the traversal's: the box test only ever skips spheres that
** the ray misses.  Two spheres hit at exactly the same t are settled by
** the order they are tested in, in the BVH's leaf order here and in
** box-entry order there, so such a tie may go the other way
** (ray_intersect(3) leaves ties between kinds other than triangles
** unspecified).
*/
#define FEW_SPHERES 4

static int few_spheres(const ray_scene *s)
{
    size_t i, n = s->prim_bvh.n_items;

    if (n > FEW_SPHERES)
        return 0;
    for (i = 0; i < n; i++)
        if (s->prims[s->prim_bvh.items[i]].kind != RAY__KIND_SPHERE)
            return 0;
    return 1;
}

/* The bounded primitives of s along r, by traversal (the traversal data
** set up first if *ready is 0) or one after another (few_spheres). */
static inline int prims_along(const ray_scene *s, trav *tr, int *ready,
                              ray_ray *r, void *best, int any,
                              ray__counts *qc)
{
    unsigned i;
    int found = 0;

    if (!few_spheres(s)) {
        if (!*ready)
            trav_init(tr, r);
        *ready = 1;
        return traverse(s, &s->prim_bvh, tr, r, LEAF_PRIMS, best, any, qc);
    }
    for (i = 0; i < s->prim_bvh.n_items; i++)
        if (prim_test(s, i, r, best, qc)) {
            found = 1;
            if (any)
                return 1;
        }
    return found;
}

/* The triangles of s along r (the traversal data set up first if *ready
** is 0; not at all for a scene without triangles). */
static inline int tris_along(const ray_scene *s, trav *tr, int *ready,
                             ray_ray *r, void *best, int any,
                             ray__counts *qc)
{
    if (s->tri_bvh.n_wide == 0)
        return 0;
    if (!*ready)
        trav_init(tr, r);
    *ready = 1;
    return traverse(s, &s->tri_bvh, tr, r, LEAF_TRIANGLES, best, any, qc);
}

/* A fresh query's state: no counts, gate g (NULL: ungated). */
static void counts_start(ray__counts *qc, const ray__gate *g, int any)
{
    memset(qc, 0, sizeof *qc);
    qc->gate = g;
    qc->any = any;
    qc->inst_id = RAY_INVALID_ID;
    qc->uv = 1;
}

/*
** The nearest hit of s along rr (usable), rr->tmax shrunk to it, into
** *hit; counted and gated by qc.  Planes first, then the bounded kinds,
** then the triangles, each shrinking the interval for the next.
*/
static int nearest_core(const ray_scene *s, ray_ray *rr, ray_hit *hit,
                        ray__counts *qc)
{
    prim_best best;
    tri_best tb;
    trav tr;
    int found = 0, ready = 0;
    size_t i;

    best.deferred = RAY_INVALID_ID;
    tri_best_start(&tb);
    for (i = 0; i < s->n_planes; i++) {
        ray_hit h;
        int k = prim_candidate(s, s->planes[i], rr, &h, qc);
        if (k) {
            rr->tmax = h.t;
            prim_keep(&best, s->planes[i], k, &h);
            found = 1;
        }
    }
    if (prims_along(s, &tr, &ready, rr, &best, 0, qc))
        found = 1;
    if (tris_along(s, &tr, &ready, rr, &tb, 0, qc)) {
        const ray__tri *t = &s->tris[tb.index];
        /* A usable triangle (checked at commit) always fills. */
        if (ray__triangle_fill(t->a, t->b, t->c, rr->tmax, tb.beta,
                               tb.gamma, &best.h)) {
            best.h.geom_id = s->tri_ids[tb.index].geom_id;
            best.h.prim_id = s->tri_ids[tb.index].prim_id;
            best.h.inst_id = RAY_INVALID_ID;
            best.deferred = RAY_INVALID_ID;
            found = 1;
        }
    }
    /* The record of the nearest, once per ray. */
    if (found && !prim_fill_best(s, rr, &best, qc))
        found = 0;
    if (found)
        *hit = best.h;
    return found;
}

/* Is anything of s along rr (usable)?  Counted and gated by qc. */
static int any_core(const ray_scene *s, ray_ray *rr, ray__counts *qc)
{
    ray_hit h;
    trav tr;
    size_t i;
    int ready = 0;

    for (i = 0; i < s->n_planes; i++)
        if (prim_candidate(s, s->planes[i], rr, &h, qc))
            return 1;
    return prims_along(s, &tr, &ready, rr, NULL, 1, qc) ||
           tris_along(s, &tr, &ready, rr, NULL, 1, qc);
}

static int query_nearest_gated(const ray_scene *s, const ray_ray *r,
                               const ray__gate *g, int uv, ray_hit *hit,
                               ray_stats *st)
{
    ray__counts qc;
    ray_ray rr = *r;
    ray_hit best;
    int found;

    if (!ray__ray_usable(r))
        return 0;
    counts_start(&qc, g, 0);
    qc.uv = uv;
    found = nearest_core(s, &rr, &best, &qc);
    add_counts(st, &qc);
    if (qc.stale)
        return -RAY_ESTATE;
    if (found)
        ray__hit_store(hit, &best);
    return found;
}

static int query_any_gated(const ray_scene *s, const ray_ray *r,
                           const ray__gate *g, ray_stats *st)
{
    ray__counts qc;
    ray_ray rr = *r;
    int hit;

    if (!ray__ray_usable(r))
        return 0;
    counts_start(&qc, g, 1);
    hit = any_core(s, &rr, &qc);
    add_counts(st, &qc);
    return qc.stale ? -RAY_ESTATE : hit;
}

/* An instance's child inside a parent's query: nearest or any as the
** parent's query is, with its counts and gate. */
static int query_child(const ray_scene *child, ray_ray *r, ray_hit *hit,
                       ray__counts *qc)
{
    if (!ray__ray_usable(r))
        return 0;
    if (qc->any)
        return any_core(child, r, qc);
    return nearest_core(child, r, hit, qc);
}

#endif
