/* SPDX-License-Identifier: MIT */
/*
** closest.c -- ray_closest_point: the nearest surface point of a
** committed scene to a query point q within a radius, over the
** structures the ray queries use (intersect.c): the planes one by one,
** then the BVH over the bounded primitives and the BVH over the
** triangles.  Each BVH is walked nearest box first, and a box is skipped
** when even its nearest point lies farther from q than the search
** radius, which starts as the caller's radius and shrinks to the
** distance of each nearer surface point found.
*/
#include "query/query.h"

/* The larger of a and b by a comparison, not libm's fmax, which is a
** function call where the compiler must keep its NaN rule (the hot
** loops below call it millions of times a second); for operands that
** cannot be NaN. */
static inline double max2(double a, double b)
{
    return a > b ? a : b;
}

/* ------------------------------------------------------------ triangles */

/* t clamped to [0, 1]; a NaN t (0/0) gives 0. */
static inline double unit_clamp(double t)
{
    return t > 0 ? (t < 1 ? t : 1.0) : 0.0;
}

/* The nearest of the three edges' nearest points: the face's fallback
** when its determinants cannot be divided by (below). */
static ray_vec3 nearest_edge_point(ray_vec3 a, ray_vec3 b, ray_vec3 c,
                                   ray_vec3 q)
{
    ray_vec3 e[3];
    double d[3];
    int k, best = 0;

    e[0] = ray__segment_closest(q, a, b);
    e[1] = ray__segment_closest(q, b, c);
    e[2] = ray__segment_closest(q, c, a);
    for (k = 0; k < 3; k++) {
        d[k] = ray__distance(e[k], q);
        if (d[k] < d[best])
            best = k;
    }
    return e[best];
}

/*
** The point of triangle (a, b, c) nearest q: Ericson, "Real-Time
** Collision Detection", Morgan Kaufmann 2005, section 5.1.5
** (ClosestPtPointTriangle).  The Voronoi region of the triangle that q
** lies in -- a vertex, an edge or the face -- is found from the dot
** products d1 .. d6 of the edges ab, ac with q's offsets from the
** vertices and from the barycentric determinants va, vb, vc formed of
** them, each test needing none of the later ones; the point is the
** vertex itself (exactly), a + t ab on an edge, or a + v ab + w ac on
** the face, with (t, v, w) from the same quantities.
**
** ab, ac and q's offsets are scaled by 2^-e (exactly), e the exponent
** of their largest component, so that the dot products and the
** determinants (products of four coordinates) neither overflow nor
** underflow for a triangle of any size and a q at any distance from it;
** the region and (t, v, w) do not depend on the scale, and the point is
** formed from the unscaled vertices.
**
** Rounding: the edge and face points are a + t ab (+ w ac) with t, v, w
** in [0, 1] (clamped: rounding may carry a quotient an ulp past an end),
** so p lies on the triangle within gamma(3) (|a| + |ab| + |ac|) per
** component whatever q.  Where p lies along the triangle is off by the
** rounding of the dot products, gamma(3) |ab| |q - a| and the like,
** divided by the conditioning of the determinants: about 10 u |q - a| /
** sin^2 of the triangle's smallest angle.  That moves p along the
** surface; the distance |p - q| changes by it only to second order when
** q is off the plane, and to first order when q lies in the plane.
** A triangle whose determinants cannot be divided by (their sum is not
** positive: a sliver within rounding of a segment) falls back to the
** nearest of its edges' points, which is then as near as any.
*/
static ray_vec3 tri_closest(ray_vec3 a, ray_vec3 b, ray_vec3 c, ray_vec3 q)
{
    ray_vec3 ab = v3_sub(b, a), ac = v3_sub(c, a), ap = v3_sub(q, a);
    ray_vec3 bp, cp;
    double m, s, d1, d2, d3, d4, d5, d6, va, vb, vc, sum, v, w;

    /* Differences of finite doubles: +-Inf where they overflow, never
    ** NaN, so the comparisons of max2 see every one. */
    m = max2(max2(max2(fabs(ab.x), fabs(ab.y)), max2(fabs(ab.z), fabs(ac.x))),
             max2(max2(fabs(ac.y), fabs(ac.z)),
                  max2(max2(fabs(ap.x), fabs(ap.y)), fabs(ap.z))));
    if (!(m > 0 && m < HUGE_VAL))
        return a;   /* q == a on a point (not a usable triangle), or overflow */
    s = ray__pow2(-ray__exponent_of(m));
    bp = v3_scale(v3_sub(q, b), s);
    cp = v3_scale(v3_sub(q, c), s);
    ab = v3_scale(ab, s);
    ac = v3_scale(ac, s);
    ap = v3_scale(ap, s);

    d1 = v3_dot(ab, ap);
    d2 = v3_dot(ac, ap);
    if (d1 <= 0 && d2 <= 0)
        return a;                                       /* vertex a */
    d3 = v3_dot(ab, bp);
    d4 = v3_dot(ac, bp);
    if (d3 >= 0 && d4 <= d3)
        return b;                                       /* vertex b */
    vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0)                  /* edge ab */
        return v3_madd(a, unit_clamp(d1 / (d1 - d3)), v3_sub(b, a));
    d5 = v3_dot(ab, cp);
    d6 = v3_dot(ac, cp);
    if (d6 >= 0 && d5 <= d6)
        return c;                                       /* vertex c */
    vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0)                  /* edge ac */
        return v3_madd(a, unit_clamp(d2 / (d2 - d6)), v3_sub(c, a));
    va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)        /* edge bc */
        return v3_madd(b, unit_clamp((d4 - d3) / ((d4 - d3) + (d5 - d6))),
                       v3_sub(c, b));
    sum = va + vb + vc;                                 /* the face */
    if (!(sum > 0 && sum < HUGE_VAL))
        return nearest_edge_point(a, b, c, q);
    v = unit_clamp(vb / sum);
    w = unit_clamp(vc / sum);
    return v3_add(a, v3_add(v3_scale(v3_sub(b, a), v),
                            v3_scale(v3_sub(c, a), w)));
}

/* ------------------------------------------------------------ the kinds */

/*
** The nearest surface point *pt of primitive p to q and the unit normal
** *n there, by kind: 1, or 0 for a kind that has no closest-point
** routine (or a result that is not finite).  The dispatch below is a
** switch generated from the list of kinds (RAY__PRIM_KINDS, prim.h)
** with no default, as in kinds.c: a kind added to the list without its
** closest_NAME does not compile.
*/

/* The sphere's point along q - c: c + r (q - c)/|q - c|, within a few
** ulps of |c| + r of the sphere (the unit vector's 4 roundings, the
** product and the sum).  q at the centre exactly: every point is as
** near, and the +z pole is taken. */
static int closest_SPHERE(const ray_scene *s, const ray__prim *p,
                          ray_vec3 q, ray_vec3 *pt, ray_vec3 *n)
{
    ray_vec3 rel = v3_sub(q, p->a), dir;

    (void)s;
    if (!v3_isfinite(rel))
        return 0;
    if (!v3_normalize(rel, &dir))
        dir = v3(0, 0, 1);
    *pt = v3_madd(p->a, p->radius, dir);
    *n = dir;
    return v3_isfinite(*pt);
}

/* q's foot on the plane, q - ((q - point).n) n with the scene's unit n:
** on the plane within a few ulps of |q| + |q - point|.  The normal as
** the plane was given (normalised), not turned toward q, as ray_plane's. */
static int closest_PLANE(const ray_scene *s, const ray__prim *p,
                         ray_vec3 q, ray_vec3 *pt, ray_vec3 *n)
{
    double h = v3_dot(v3_sub(q, p->a), p->b);

    (void)s;
    *pt = v3_madd(q, -h, p->b);
    *n = p->b;
    return v3_isfinite(*pt);
}

/* Triangles are in the triangle BVH, walked with tri_closest inline, so
** their geometry is never asked here (and after commit tris[first ..]
** are reordered): nothing. */
static int in_triangle_bvh(void)
{
    return 0;
}

static int closest_TRIANGLE(const ray_scene *s, const ray__prim *p,
                            ray_vec3 q, ray_vec3 *pt, ray_vec3 *n)
{
    (void)s, (void)p, (void)q, (void)pt, (void)n;
    return in_triangle_bvh();
}

static int closest_MESH(const ray_scene *s, const ray__prim *p, ray_vec3 q,
                        ray_vec3 *pt, ray_vec3 *n)
{
    (void)s, (void)p, (void)q, (void)pt, (void)n;
    return in_triangle_bvh();
}

static int closest_POLYGON(const ray_scene *s, const ray__prim *p,
                           ray_vec3 q, ray_vec3 *pt, ray_vec3 *n)
{
    return ray__polygon_closest(s->verts + p->first, p->count, q, pt, n);
}

static int closest_BOX(const ray_scene *s, const ray__prim *p, ray_vec3 q,
                       ray_vec3 *pt, ray_vec3 *n)
{
    return ray__box_closest(&s->surfaces[p->surface].box, q, pt, n);
}

static int closest_CAPSULE(const ray_scene *s, const ray__prim *p,
                           ray_vec3 q, ray_vec3 *pt, ray_vec3 *n)
{
    return ray__capsule_closest(&s->surfaces[p->surface].capsule, q, pt, n);
}

/*
** Tori, implicit and parametric surfaces and Bezier patches have no
** closest-point routine: the nearest point of a quartic, of a field's
** zero set or of a patch is an iteration of its own (with failures to
** report), not a formula, so ray_closest_point skips them (documented
** in ray.h and ray_closest_point(3)).
*/
static int no_closest_point(void)
{
    return 0;
}

static int closest_TORUS(const ray_scene *s, const ray__prim *p, ray_vec3 q,
                         ray_vec3 *pt, ray_vec3 *n)
{
    (void)s, (void)p, (void)q, (void)pt, (void)n;
    return no_closest_point();
}

static int closest_IMPLICIT(const ray_scene *s, const ray__prim *p,
                            ray_vec3 q, ray_vec3 *pt, ray_vec3 *n)
{
    (void)s, (void)p, (void)q, (void)pt, (void)n;
    return no_closest_point();
}

static int closest_PARAMETRIC(const ray_scene *s, const ray__prim *p,
                              ray_vec3 q, ray_vec3 *pt, ray_vec3 *n)
{
    (void)s, (void)p, (void)q, (void)pt, (void)n;
    return no_closest_point();
}

static int closest_BEZIER(const ray_scene *s, const ray__prim *p,
                          ray_vec3 q, ray_vec3 *pt, ray_vec3 *n)
{
    (void)s, (void)p, (void)q, (void)pt, (void)n;
    return no_closest_point();
}

/* User geometry has only the callbacks its program gave it, and no
** closest-point one: skipped, as the surfaces above. */
static int closest_USER(const ray_scene *s, const ray__prim *p, ray_vec3 q,
                        ray_vec3 *pt, ray_vec3 *n)
{
    (void)s, (void)p, (void)q, (void)pt, (void)n;
    return no_closest_point();
}

/* Instances are searched by visit_instance below (their child's own
** search, with the ids it finds): never asked here. */
static int closest_INSTANCE(const ray_scene *s, const ray__prim *p,
                            ray_vec3 q, ray_vec3 *pt, ray_vec3 *n)
{
    (void)s, (void)p, (void)q, (void)pt, (void)n;
    return 0;
}

static int prim_closest(const ray_scene *s, unsigned i, ray_vec3 q,
                        ray_vec3 *pt, ray_vec3 *n)
{
    const ray__prim *p = &s->prims[i];

    switch (p->kind) {
#define CLOSEST_OF(name, counted_as, class)                                \
    case RAY__KIND_##name:                                                 \
        return closest_##name(s, p, q, pt, n);
        RAY__PRIM_KINDS(CLOSEST_OF)
#undef CLOSEST_OF
    }
    return 0;                       /* not a ray__kind: cannot happen */
}

/* ------------------------------------------------------------ the search */

/*
** The search's state.  Box distances are compared squared, in units
** scaled by 2^-k so that no square overflows: a box's float bounds are
** at most FLT_MAX ~ 2^128 in magnitude (or infinite on the far side), so
** an offset from q is below |q| + 2^128, and |q| is brought below 2^510
** (the sum of three squares then below 2^1022).  For |q| < 2^510, k = 0.
*/
typedef struct query {
    ray_vec3 q;
    double scale;            /* 2^-k */
    double best;             /* the search radius: radius, then nearest */
    double best2;            /* >= (best scale)^2, what boxes face */
    int found;
    int stale;               /* met an instance whose child changed */
    ray_closest out;
} query;

/*
** best2 from best: an upper bound on (best scale)^2: best scale is
** exact but where it underflows (off by at most 2^-1075), the square
** rounds once (relative u, or 2^-1075 where it underflows), so the
** rounded square times 1 + gamma(3) (its own rounding included) plus two
** subnormals covers it.  +Inf stays +Inf: nothing is pruned.
*/
static void set_best(query *qs, double best)
{
    double b = best * qs->scale;

    qs->best = best;
    qs->best2 = b * b * (1 + ray__gamma(3)) + 2 * RAY__TINY;
}

/* Keep surface point p at computed distance d from q if it is nearer than
** the best so far (or, before the first, within the radius, inclusive);
** a non-finite distance (p and q farther apart than DBL_MAX) is no answer. */
static int nearer(const query *qs, double d)
{
    return d < HUGE_VAL && (qs->found ? d < qs->best : d <= qs->best);
}

static void record(query *qs, ray_vec3 p, double d, ray_vec3 n,
                   unsigned geom_id, unsigned prim_id)
{
    qs->out.p = p;
    qs->out.distance = d;
    qs->out.n = n;
    qs->out.geom_id = geom_id;
    qs->out.prim_id = prim_id;
    qs->out.inst_id = RAY_INVALID_ID;
    qs->found = 1;
    set_best(qs, d);
}

static int search(const ray_scene *s, ray_vec3 q, double radius,
                  query *qs);

/*
** Instance i: the child searched with q in its space, within the radius
** that the world's search radius becomes there (divided by the scale of
** a similarity, else times |L^-1|, which holds every object point whose
** image is within it), its answer brought back to world space and kept
** if nearer there.  Exact for rotations with a uniform scale (distances
** all scale alike); for other transforms the child's nearest point in
** its own metric, which need not be the world's nearest (ray.h).
*/
static void visit_instance(const ray_scene *s, unsigned i, query *qs)
{
    const ray__instance *in = &s->instances[s->prims[i].surface];
    ray_vec3 qo = ray__instance_point_to_object(in, qs->q);
    double r = in->similarity > 0 ? qs->best / in->similarity
                                  : qs->best * in->inv_norm;
    ray_vec3 p, n;
    query child;
    double d;

    if (!in->child->committed || in->child->generation != in->generation) {
        qs->stale = 1;
        return;
    }
    /* Rounding: the radius grown by 2^-40 relative, far above the few
    ** ulps of the map, so no point within the world radius is cut. */
    r += r * 0x1p-40;
    if (!v3_isfinite(qo) || !search(in->child, qo, r, &child))
        return;
    p = ray__instance_point_to_world(in, child.out.p);
    n = ray__instance_normal(in, child.out.n);
    d = ray__distance(p, qs->q);
    if (nearer(qs, d)) {
        record(qs, p, d, n, child.out.geom_id, child.out.prim_id);
        qs->out.inst_id = i;
    }
}

/* Primitive i (a plane or a bounded primitive but a triangle). */
static void visit_prim(const ray_scene *s, unsigned i, query *qs)
{
    ray_vec3 p, n;
    double d;

    if (s->prims[i].kind == RAY__KIND_INSTANCE) {
        visit_instance(s, i, qs);
        return;
    }
    if (!prim_closest(s, i, qs->q, &p, &n))
        return;
    d = ray__distance(p, qs->q);
    if (nearer(qs, d))
        record(qs, p, d, n, i, 0);
}

/* Triangle i of the scene (leaf order); its normal as ray_triangle's,
** (b - a) x (c - a) normalised, computed only for a nearer point. */
static void visit_triangle(const ray_scene *s, unsigned i, query *qs)
{
    ray_vec3 a, b, c, p, n;
    double d;

    ray__tri_corners(s, i, &a, &b, &c);
    p = tri_closest(a, b, c, qs->q);
    d = ray__distance(p, qs->q);
    if (nearer(qs, d) &&
        v3_normalize(v3_cross(v3_sub(b, a), v3_sub(c, a)), &n))
        record(qs, p, d, n, s->tri_ids[i].geom_id, s->tri_ids[i].prim_id);
}

/*
** A lower bound on the squared distance (in the scaled units) from q to
** each of node w's eight float boxes, computed in double from the float
** bounds, which already contain the geometry (rounded outward from it at
** commit).  Per axis the offset max(lo - q, q - hi, 0) rounds once (the
** scaling is exact but in underflow), the squares and their sum round
** three times more: the computed sum is at most the exact one times
** (1 + u)^2 (1 + gamma(3)) <= 1 + gamma(5), so times 1 - gamma(8) (its
** own rounding included) it is no more than the exact one; underflow,
** at most half a subnormal per product and per scaled offset, is covered
** by 4 subnormals.  So no box holding a point within the search radius
** is ever skipped.  An unused slot (lo = +Inf, hi = -Inf) is Inf away.
*/
static void boxes_d2(const ray__wnode *w, const query *qs,
                     double d2[RAY__WIDTH])
{
    const double shrink = 1 - ray__gamma(8);
    int k;

    /* q is finite and a bound is finite or infinite, so no offset is
    ** NaN: max2 will do. */
    for (k = 0; k < RAY__WIDTH; k++) {
        double dx = max2(max2((double)w->lo[0][k] - qs->q.x,
                              qs->q.x - (double)w->hi[0][k]), 0.0);
        double dy = max2(max2((double)w->lo[1][k] - qs->q.y,
                              qs->q.y - (double)w->hi[1][k]), 0.0);
        double dz = max2(max2((double)w->lo[2][k] - qs->q.z,
                              qs->q.z - (double)w->hi[2][k]), 0.0);
        dx *= qs->scale;
        dy *= qs->scale;
        dz *= qs->scale;
        d2[k] = (dx * dx + dy * dy + dz * dz) * shrink - 4 * RAY__TINY;
    }
}

enum { LEAF_TRIANGLES, LEAF_PRIMS };

/* A node's slot waiting on the stack: child and count as in ray__wnode,
** and the lower bound on its box's squared distance. */
typedef struct pending {
    unsigned child, count;
    double d2;
} pending;

/*
** Nearest box first: of a node's children within the search radius,
** all are pushed, insertion-sorted so that the nearest is on top, and
** popped while still within the radius, which every nearer point found
** shrinks.  At most RAY__WIDTH pushed and one popped a level, and the
** BVH is at most 64 levels deep (accel/build.h), so the stack holds them all.
*/
static void walk(const ray_scene *s, const ray__bvh *bvh, int leaf,
                 query *qs)
{
    pending stack[RAY__WIDTH * 64];
    unsigned child = 0, count = 0;    /* the root: an inner node */
    int sp = 0;

    if (bvh->n_wide == 0)
        return;
    for (;;) {
        if (count == 0) {
            const ray__wnode *w = &bvh->wide[child];
            double d2[RAY__WIDTH];
            int k, j, base = sp;

            boxes_d2(w, qs, d2);
            for (k = 0; k < RAY__WIDTH; k++) {
                pending e;
                if (!(d2[k] <= qs->best2) || w->count[k] == RAY__LEAF)
                    continue;           /* too far, or an unused slot */
                e.child = w->child[k];
                e.count = w->count[k];
                e.d2 = d2[k];
                for (j = sp; j > base && stack[j - 1].d2 < e.d2; j--)
                    stack[j] = stack[j - 1];
                stack[j] = e;
                sp++;
            }
        } else {
            unsigned i, end = child + (count & ~RAY__LEAF);
            for (i = child; i < end; i++) {
                if (leaf == LEAF_TRIANGLES)
                    visit_triangle(s, i, qs);
                else
                    visit_prim(s, bvh->items[i], qs);
            }
        }
        do {
            if (sp == 0)
                return;
            sp--;
        } while (!(stack[sp].d2 <= qs->best2));
        child = stack[sp].child;
        count = stack[sp].count;
    }
}

/* The search of scene s for the nearest point to q within radius: 1 and
** qs->out, or 0; qs->stale when an instance's child changed. */
static int search(const ray_scene *s, ray_vec3 q, double radius, query *qs)
{
    double m;
    size_t i;

    qs->q = q;
    m = fmax(fabs(q.x), fmax(fabs(q.y), fabs(q.z)));
    qs->scale = m < 0x1p510 ? 1.0 : ray__pow2(509 - ray__exponent_of(m));
    qs->found = 0;
    qs->stale = 0;
    set_best(qs, radius);
    for (i = 0; i < s->n_planes; i++)
        visit_prim(s, s->planes[i], qs);
    walk(s, &s->prim_bvh, LEAF_PRIMS, qs);
    walk(s, &s->tri_bvh, LEAF_TRIANGLES, qs);
    return qs->found;
}

int ray_closest_point(const ray_scene *s, ray_vec3 q, double radius,
                      ray_closest *out)
{
    query qs;

    if (s == NULL || out == NULL || !v3_isfinite(q) || !(radius >= 0))
        return -RAY_EINVAL;
    if (!s->committed)
        return -RAY_ESTATE;
    if (!search(s, q, radius, &qs))
        return qs.stale ? -RAY_ESTATE : 0;
    if (qs.stale)
        return -RAY_ESTATE;
    /* Field by field: no indeterminate padding for the caller's bytes. */
    out->p = qs.out.p;
    out->distance = qs.out.distance;
    out->n = qs.out.n;
    out->geom_id = qs.out.geom_id;
    out->prim_id = qs.out.prim_id;
    out->inst_id = qs.out.inst_id;
    return 1;
}
