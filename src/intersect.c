/*
** intersect.c -- nearest-hit and any-hit queries over a committed scene:
** the planes one by one, then two BVHs, one over the triangles (stored in
** leaf order) and one over the other bounded primitives (spheres,
** polygons and the curved surfaces).  Each hit shrinks tmax,
** so every later box and primitive is tested against the nearest so far.
*/
#include <string.h>

#include "internal.h"

/*
** The slab test, four boxes at a time in float, kept conservative: it may
** let a box through that the ray misses, never the reverse.
**
**   * The origin is bracketed, o_lo <= o <= o_hi (float_down / float_up),
**     and each plane distance uses the end that makes the near distance
**     smaller and the far distance larger; the boxes themselves were
**     rounded outward from the double geometry.
**   * (b - o) * (1/d) then carries three float roundings, so the far
**     distance is grown by 1 + 2 gamma(3) (float's gamma): the bound with
**     which Ize proves no hit is lost ("Robust BVH Ray Traversal", JCGT
**     2(2), 2013; pbrt-v4 Bounds3::IntersectP; Embree's robust mode).
**   * A zero direction component makes 1/d = +-Inf (IEEE), so the slab is
**     everything or nothing (Williams et al., "An Efficient and Robust
**     Ray-Box Intersection Algorithm", JGT 10(1), 2005); 0 * Inf = NaN
**     when the origin is on the plane, and the max/min below ignore a NaN
**     operand: the box is kept.
**
** Everything else stays in double: the triangle tests decide the hits.
*/
typedef struct trav {
    float o_near[3], o_far[3];   /* the origin end used for near / far */
    float inv[3];
    int near_hi[3];              /* 1: the near plane is hi on that axis */
    float tmin, tmax;            /* the interval, widened to floats */
} trav;

/* float's gamma(3) doubled: 1 + 2 * 3u / (1 - 3u), u = 2^-24. */
#define FLOAT_GROW (1.0f + 2.0f * (3.0f * 5.96046448e-8f) / \
                               (1.0f - 3.0f * 5.96046448e-8f))

static void trav_init(trav *tr, const ray_ray *r)
{
    double o[3], d[3];
    int k;

    o[0] = r->org.x;
    o[1] = r->org.y;
    o[2] = r->org.z;
    d[0] = r->dir.x;
    d[1] = r->dir.y;
    d[2] = r->dir.z;
    for (k = 0; k < 3; k++) {
        double inv = 1.0 / d[k];
        int neg = inv < 0 || (inv == 0 && signbit(d[k]));
        float lo = ray__float_down(o[k]), hi = ray__float_up(o[k]);
        tr->inv[k] = (float)inv;
        tr->near_hi[k] = neg;
        /* inv >= 0: near = (lo_plane - o_hi) * inv, far = (hi - o_lo) * inv;
        ** inv < 0:  near = (hi_plane - o_lo) * inv, far = (lo - o_hi) * inv. */
        tr->o_near[k] = neg ? lo : hi;
        tr->o_far[k] = neg ? hi : lo;
    }
    tr->tmin = ray__float_down(r->tmin);
    tr->tmax = ray__float_up(r->tmax);
}

/* Which of node q's four boxes does the ray enter within (tmin, tmax)?
** Returns a bit mask; entry[k] is where it enters box k. */
#if defined(__GNUC__) && !defined(RAY_NO_VECTOR_EXTENSIONS)
/*
** With GCC or Clang, the four lanes are written with their vector
** extensions (one SSE/NEON register per quantity); the arithmetic is the
** same as the plain loop below, lane for lane.  Selections go through
** comparison masks so that a NaN lane keeps the old value exactly as the
** plain "tn > t0 ? tn : t0" does.
*/
typedef float v4f __attribute__((vector_size(16)));
typedef int v4i __attribute__((vector_size(16)));

static inline v4f v4_load(const float *p)
{
    v4f v;
    memcpy(&v, p, sizeof v);     /* no alignment assumed: movups */
    return v;
}

static inline v4f v4_select(v4i mask, v4f a, v4f b)
{
    return (v4f)(((v4i)a & mask) | ((v4i)b & ~mask));
}

static inline unsigned boxes_hit(const ray__node4 *q, const trav *tr,
                                 float tmax, float entry[4])
{
    v4f t0 = {tr->tmin, tr->tmin, tr->tmin, tr->tmin};
    v4f t1 = {HUGE_VALF, HUGE_VALF, HUGE_VALF, HUGE_VALF};
    v4f grow = {FLOAT_GROW, FLOAT_GROW, FLOAT_GROW, FLOAT_GROW};
    v4f vmax = {tmax, tmax, tmax, tmax};
    v4i hit;
    int a;

    for (a = 0; a < 3; a++) {
        v4f np = v4_load(tr->near_hi[a] ? q->hi[a] : q->lo[a]);
        v4f fp = v4_load(tr->near_hi[a] ? q->lo[a] : q->hi[a]);
        v4f on = {tr->o_near[a], tr->o_near[a], tr->o_near[a], tr->o_near[a]};
        v4f of = {tr->o_far[a], tr->o_far[a], tr->o_far[a], tr->o_far[a]};
        v4f inv = {tr->inv[a], tr->inv[a], tr->inv[a], tr->inv[a]};
        v4f tn = (np - on) * inv, tf = (fp - of) * inv;
        t0 = v4_select(tn > t0, tn, t0);            /* NaN tn: ignored */
        t1 = v4_select(tf < t1, tf, t1);            /* NaN tf: ignored */
    }
    t1 = t1 * grow;
    t1 = v4_select(t1 < vmax, t1, vmax);
    hit = t0 <= t1;
    memcpy(entry, &t0, sizeof t0);
    return (unsigned)((hit[0] & 1) | (hit[1] & 2) | (hit[2] & 4) |
                      (hit[3] & 8));
}
#else
static inline unsigned boxes_hit(const ray__node4 *q, const trav *tr,
                                 float tmax, float entry[4])
{
    float t0[4], t1[4];
    unsigned mask = 0;
    int a, k;

    for (k = 0; k < 4; k++) {
        t0[k] = tr->tmin;
        t1[k] = HUGE_VALF;
    }
    for (a = 0; a < 3; a++) {
        const float *np = tr->near_hi[a] ? q->hi[a] : q->lo[a];
        const float *fp = tr->near_hi[a] ? q->lo[a] : q->hi[a];
        for (k = 0; k < 4; k++) {
            float tn = (np[k] - tr->o_near[a]) * tr->inv[a];
            float tf = (fp[k] - tr->o_far[a]) * tr->inv[a];
            t0[k] = tn > t0[k] ? tn : t0[k];        /* NaN tn: ignored */
            t1[k] = tf < t1[k] ? tf : t1[k];        /* NaN tf: ignored */
        }
    }
    for (k = 0; k < 4; k++) {
        float far = t1[k] * FLOAT_GROW;
        far = far < tmax ? far : tmax;
        entry[k] = t0[k];
        mask |= (unsigned)(t0[k] <= far) << k;
    }
    return mask;
}
#endif

enum { LEAF_TRIANGLES, LEAF_PRIMS };

/* The public counter index of an internal primitive kind. */
static int kind_of(int prim_kind)
{
    switch (prim_kind) {
    case PRIM_SPHERE:
        return RAY_PRIM_SPHERE;
    case PRIM_PLANE:
        return RAY_PRIM_PLANE;
    case PRIM_POLYGON:
        return RAY_PRIM_POLYGON;
    case PRIM_TORUS:
        return RAY_PRIM_TORUS;
    case PRIM_IMPLICIT:
        return RAY_PRIM_IMPLICIT;
    case PRIM_PARAMETRIC:
    case PRIM_BEZIER:
        return RAY_PRIM_PARAMETRIC;
    default:
        return RAY_PRIM_TRIANGLE;
    }
}

/* What one query counts: tests by kind, and the curved-surface tests
** that failed (iteration limit) and were taken as misses. */
typedef struct query_counts {
    unsigned long long tests[RAY_PRIM_KINDS];
    unsigned long long failures;
} query_counts;

/* Add a query's counts to *st (if any). */
static void add_counts(ray_stats *st, const query_counts *qc)
{
    int k;

    if (st == NULL)
        return;
    for (k = 0; k < RAY_PRIM_KINDS; k++) {
        st->tests_by_kind[k] += qc->tests[k];
        st->tests += qc->tests[k];
    }
    st->root_failures += qc->failures;
}

static int tri_test(const ray_scene *s, unsigned i, ray_ray *r, void *best);
static int prim_test(const ray_scene *s, unsigned i, ray_ray *r, void *best,
                     query_counts *qc);

/*
** Ordered traversal: the children a ray enters are visited nearest first,
** the others pushed with their entry distances and popped only if still in
** front of the nearest hit found since.  "any": stop at the first hit.
** "leaf" picks the primitive test; the function is inlined into each
** caller, so that choice is made at compile time.
*/
static inline int traverse(const ray_scene *s, const ray__bvh *bvh,
                           ray_ray *r, int leaf, void *best, int any,
                           query_counts *qc)
{
    unsigned stack[4 * 64], ni = 0;
    float stack_t[4 * 64], tmax;
    int sp = 0, found = 0;
    trav tr;

    if (bvh->n_nodes4 == 0)
        return 0;
    trav_init(&tr, r);
    tmax = tr.tmax;
    for (;;) {
        const ray__node4 *q = &bvh->nodes4[ni];
        float entry[4];
        unsigned mask = boxes_hit(q, &tr, tmax, entry), order[4];
        int n = 0, k, j;

        /* The entered children, sorted nearest first (insertion sort). */
        for (k = 0; k < 4; k++) {
            if (!(mask >> k & 1) || q->count[k] == RAY__EMPTY)
                continue;
            for (j = n; j > 0 && entry[order[j - 1]] > entry[k]; j--)
                order[j] = order[j - 1];
            order[j] = (unsigned)k;
            n++;
        }
        /* Leaves now, nearest first; inner nodes go on the stack, the
        ** nearest on top. */
        for (k = 0; k < n; k++) {
            unsigned c = order[k], i;
            if (q->count[c] == 0 || entry[c] > tmax)
                continue;
            for (i = q->child[c]; i < q->child[c] + q->count[c]; i++) {
                if (leaf == LEAF_TRIANGLES)
                    qc->tests[RAY_PRIM_TRIANGLE]++;
                else
                    qc->tests[kind_of(s->prims[bvh->items[i]].kind)]++;
                if (leaf == LEAF_TRIANGLES ? tri_test(s, i, r, best)
                                           : prim_test(s, i, r, best, qc)) {
                    found = 1;
                    if (any)
                        goto done;
                    tmax = ray__float_up(r->tmax);
                }
            }
        }
        for (k = n - 1; k >= 0; k--) {
            unsigned c = order[k];
            if (q->count[c] == 0) {
                stack[sp] = q->child[c];
                stack_t[sp++] = entry[c];
            }
        }
        for (;;) {
            if (sp == 0)
                goto done;
            sp--;
            if (stack_t[sp] <= tmax) {
                ni = stack[sp];
                break;
            }
        }
    }
done:
    return found;
}

/* The nearest triangle so far. */
typedef struct tri_best {
    unsigned index;
    double beta, gamma;
} tri_best;

static inline int tri_test(const ray_scene *s, unsigned i, ray_ray *r,
                           void *best)
{
    const ray__tri *t = &s->tris[i];
    double th, beta, gamma;
    int hit = s->watertight
                  ? ray__triangle_watertight_test(r, t->a, t->b, t->c, &th,
                                                  &beta, &gamma)
                  : ray__triangle_test(r, t->a, t->b, t->c, &th, &beta,
                                       &gamma);

    if (!hit)
        return 0;
    r->tmax = th;
    if (best != NULL) {
        tri_best *b = best;
        b->index = i;
        b->beta = beta;
        b->gamma = gamma;
    }
    return 1;
}

/* A Bezier patch from its control points in the scene. */
static int bezier_intersect(const ray_scene *s, const ray__prim *p,
                            const ray_ray *r, ray_hit *hit)
{
    ray_parametric_surface ps;

    if (ray_bezier_surface(s->verts + p->first, &ps) != RAY_OK)
        return 0;          /* cannot happen: checked when added */
    return ray_parametric(r, &ps, hit);
}

/*
** One primitive other than a triangle against the ray; fills *hit on a
** hit.  A curved surface whose iteration failed (a negative answer) is a
** miss, counted in *failures.
*/
static int prim_intersect(const ray_scene *s, unsigned i, const ray_ray *r,
                          ray_hit *hit, unsigned long long *failures)
{
    const ray__prim *p = &s->prims[i];
    int ok;

    switch (p->kind) {
    case PRIM_SPHERE:
        ok = ray_sphere(r, p->a, p->radius, hit);
        break;
    case PRIM_PLANE:
        ok = ray_plane(r, p->a, p->b, hit);
        break;
    case PRIM_TORUS:
        ok = ray_torus(r, &s->surfaces[p->surface].torus, hit);
        break;
    case PRIM_IMPLICIT:
        ok = ray_implicit(r, &s->surfaces[p->surface].implicit, hit);
        break;
    case PRIM_PARAMETRIC:
        ok = ray_parametric(r, &s->surfaces[p->surface].parametric, hit);
        break;
    case PRIM_BEZIER:
        ok = bezier_intersect(s, p, r, hit);
        break;
    default:
        ok = ray_polygon(r, s->verts + p->first, p->count, hit);
        break;
    }
    if (ok < 0) {
        (*failures)++;
        return 0;
    }
    if (ok) {
        hit->geom_id = i;
        hit->prim_id = 0;
    }
    return ok;
}

static int prim_test(const ray_scene *s, unsigned item, ray_ray *r,
                     void *best, query_counts *qc)
{
    ray_hit h;

    if (!prim_intersect(s, s->prim_bvh.items[item], r, &h, &qc->failures))
        return 0;
    r->tmax = h.t;
    if (best != NULL)
        *(ray_hit *)best = h;
    return 1;
}

int ray__intersect(const ray_scene *s, const ray_ray *r, ray_hit *hit,
                   ray_stats *st)
{
    query_counts qc;
    ray_ray rr = *r;
    ray_hit best;
    tri_best tb;
    int found = 0;
    size_t i;

    memset(&qc, 0, sizeof qc);
    for (i = 0; i < s->n_planes; i++)
        if (prim_intersect(s, s->planes[i], &rr, &best, &qc.failures)) {
            rr.tmax = best.t;
            found = 1;
        }
    qc.tests[RAY_PRIM_PLANE] += s->n_planes;
    if (traverse(s, &s->prim_bvh, &rr, LEAF_PRIMS, &best, 0, &qc))
        found = 1;
    if (traverse(s, &s->tri_bvh, &rr, LEAF_TRIANGLES, &tb, 0, &qc)) {
        const ray__tri *t = &s->tris[tb.index];
        /* A usable triangle (checked at commit) always fills. */
        if (ray__triangle_fill(t->a, t->b, t->c, rr.tmax, tb.beta, tb.gamma,
                               &best)) {
            best.geom_id = s->tri_ids[tb.index].geom_id;
            best.prim_id = s->tri_ids[tb.index].prim_id;
            found = 1;
        }
    }
    add_counts(st, &qc);
    if (found)
        *hit = best;
    return found;
}

int ray__occluded(const ray_scene *s, const ray_ray *r, ray_stats *st)
{
    query_counts qc;
    ray_ray rr = *r;
    ray_hit h;
    size_t i;
    int hit = 0;

    memset(&qc, 0, sizeof qc);
    for (i = 0; i < s->n_planes && !hit; i++) {
        qc.tests[RAY_PRIM_PLANE]++;
        hit = prim_intersect(s, s->planes[i], &rr, &h, &qc.failures);
    }
    if (!hit)
        hit = traverse(s, &s->prim_bvh, &rr, LEAF_PRIMS, NULL, 1, &qc) ||
              traverse(s, &s->tri_bvh, &rr, LEAF_TRIANGLES, NULL, 1, &qc);
    add_counts(st, &qc);
    return hit;
}

int ray_intersect(const ray_scene *s, const ray_ray *r, ray_hit *hit)
{
    if (s == NULL || r == NULL || hit == NULL || !s->committed)
        return 0;
    return ray__intersect(s, r, hit, NULL);
}

int ray_occluded(const ray_scene *s, const ray_ray *r)
{
    if (s == NULL || r == NULL || !s->committed)
        return 0;
    return ray__occluded(s, r, NULL);
}
