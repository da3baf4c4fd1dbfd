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

static inline double min2(double a, double b)
{
    return a < b ? a : b;
}

/* ------------------------------------------------------------ the search */

/*
** The search's state.  Box distances are compared squared, in units
** scaled by 2^-k so that no square overflows: a box's float bounds are
** at most FLT_MAX ~ 2^128 in magnitude (or infinite on the far side), so
** an offset from q is below |q| + 2^128, and |q| is brought below 2^510
** (the sum of three squares then below 2^1022).  For |q| < 2^510, k = 0.
**
** Inside an instance the boxes are the child's, in its space, and q is
** the query point taken there, but every candidate is measured in world
** space, from qw: "best" is a world distance, and an object-space box
** at distance d from q holds no point nearer qw than d / |L^-1|_2 (L's
** smallest singular value times d), so the boxes face best |L^-1|_2
** ("widen").  That makes the answer the world's nearest point for any
** invertible affine transform (issue 30), where searching the child in
** its own metric and mapping its answer back is right only for a
** similarity.  The candidates' world points and q are rounded on their
** way between the spaces, so the boxes face that radius grown by the
** rounding margin that instance_margin derives ("margin").
*/
typedef struct query {
    ray_vec3 q;              /* in the space of the scene searched */
    int q_ok;                /* q is qw's image (0: it overflowed) */
    ray_vec3 qw;             /* in world space (q itself at the top) */
    const ray__instance *in; /* the instance searched through, or NULL */
    unsigned inst_id;        /* its geometry id in the top scene */
    double widen;            /* |L^-1|_2 inside an instance, else 1 */
    double margin;           /* the transforms' rounding, in the child's
                                units, inside an instance, else 0 */
    double scale;            /* 2^-k */
    double best;             /* the search radius: radius, then nearest */
    double best2;            /* >= ((best widen + margin) scale)^2, what
                                boxes face (set_best) */
    int found;
    int stale;               /* met an instance whose child changed */
    ray_closest out;
} query;

/*
** best2 from best: an upper bound on ((best (1 + 3u) widen + margin)
** scale)^2.  A candidate kept at computed distance d <= best lies within
** d (1 + 3u) of q (ray__distance's 3 ulps), so 1 + 6u for the square.
** best widen and the sum round once each (relative u; the sum of two
** non-negative terms, exact where margin is 0) and the scaling is exact
** but where it underflows (off by at most 2^-1075), the square rounds
** once more (relative u, or 2^-1075 where it underflows): with this
** product's own rounding, (1 + 6u) (1 + u)^6 <= 1 + gamma(12), so the
** rounded square times 1 + gamma(12) plus two subnormals covers it.
** +Inf stays +Inf: nothing is pruned.
*/
static void set_best(query *qs, double best)
{
    double b = (best * qs->widen + qs->margin) * qs->scale;

    qs->best = best;
    qs->best2 = b * b * (1 + ray__gamma(12)) + 2 * RAY__TINY;
    if (!(qs->best2 >= 0))      /* 0 times an infinite widen: prune nothing */
        qs->best2 = HUGE_VAL;
}

/* Keep surface point p at computed distance d from q if it is nearer than
** the best so far (or, before the first, within the radius, inclusive);
** a non-finite distance (p and q farther apart than DBL_MAX) is no answer. */
static int nearer(const query *qs, double d)
{
    return d < HUGE_VAL && (qs->found ? d < qs->best : d <= qs->best);
}

/* Keep world point p at world distance d (nearer() said so). */
static void record(query *qs, ray_vec3 p, double d, ray_vec3 n,
                   unsigned geom_id, unsigned prim_id)
{
    qs->out.p = p;
    qs->out.distance = d;
    qs->out.n = n;
    qs->out.geom_id = geom_id;
    qs->out.prim_id = prim_id;
    qs->out.inst_id = qs->in != NULL ? qs->inst_id : RAY_INVALID_ID;
    qs->found = 1;
    set_best(qs, d);
}

/* ------------------------------------------------------------ the kinds */

/*
** The nearest world-space surface point *pt of primitive p to qs->qw
** and the unit normal *n there, by kind: 1, or 0 for a kind that has no
** closest-point routine (or a result that is not finite).  At the top
** (qs->in NULL) world space is p's own; inside an instance each kind
** takes the shape its primitive has in the world: a sphere, box or
** capsule through a similarity is a sphere, box or capsule again (its
** params mapped, distances scaled alike), through any other transform
** an ellipsoid, a parallelepiped (its 12 world triangles) or an
** ellipsoid swept along a segment (ellipsoid.c); a polygon has its
** vertices mapped.  Normals are the child's normals as the world sees
** them (ray__instance_normal, as a ray's hit through the instance has
** them).  The dispatch below is a switch generated from the list of
** kinds (RAY__PRIM_KINDS, prim.h) with no default, as in kinds.c: a kind
** added to the list without its closest_NAME does not compile.
*/

/* The sphere's point along q - c: c + r (q - c)/|q - c|, within a few
** ulps of |c| + r of the sphere (the unit vector's 4 roundings, the
** product and the sum).  q at the centre exactly: every point is as
** near, and the +z pole is taken. */
static int sphere_point(ray_vec3 c, double r, ray_vec3 q, ray_vec3 *pt,
                        ray_vec3 *n)
{
    ray_vec3 rel = v3_sub(q, c), dir;

    if (!v3_isfinite(rel))
        return 0;
    if (!v3_normalize(rel, &dir))
        dir = v3(0, 0, 1);
    *pt = v3_madd(c, r, dir);
    *n = dir;
    return v3_isfinite(*pt);
}

static int closest_SPHERE(const ray_scene *s, const ray__prim *p,
                          const query *qs, ray_vec3 *pt, ray_vec3 *n)
{
    const ray__instance *in = qs->in;
    double e[3];

    (void)s;
    if (in == NULL)
        return sphere_point(p->a, p->radius, qs->qw, pt, n);
    if (in->similarity > 0)
        return sphere_point(ray__instance_point_to_world(in, p->a),
                            p->radius * in->similarity, qs->qw, pt, n);
    if (!(in->sv[0] > 0))
        return 0;
    e[0] = p->radius * in->sv[0];
    e[1] = p->radius * in->sv[1];
    e[2] = p->radius * in->sv[2];
    return ray__ellipsoid_closest(ray__instance_point_to_world(in, p->a),
                                  (const double(*)[3])in->axes, e, qs->qw,
                                  pt, n);
}

/* q's foot on the plane, q - ((q - point).n) n with the scene's unit n:
** on the plane within a few ulps of |q| + |q - point|.  The normal as
** the plane was given (normalised), not turned toward q, as ray_plane's.
** (An instance's child has no planes.) */
static int closest_PLANE(const ray_scene *s, const ray__prim *p,
                         const query *qs, ray_vec3 *pt, ray_vec3 *n)
{
    double h = v3_dot(v3_sub(qs->q, p->a), p->b);

    (void)s;
    *pt = v3_madd(qs->q, -h, p->b);
    *n = p->b;
    return qs->in == NULL && v3_isfinite(*pt);
}

/* Triangles are in the triangle BVH, walked with visit_triangle, so
** their geometry is never asked here (and after commit tris[first ..]
** are reordered): nothing. */
static int in_triangle_bvh(void)
{
    return 0;
}

static int closest_TRIANGLE(const ray_scene *s, const ray__prim *p,
                            const query *qs, ray_vec3 *pt, ray_vec3 *n)
{
    (void)s, (void)p, (void)qs, (void)pt, (void)n;
    return in_triangle_bvh();
}

static int closest_MESH(const ray_scene *s, const ray__prim *p,
                        const query *qs, ray_vec3 *pt, ray_vec3 *n)
{
    (void)s, (void)p, (void)qs, (void)pt, (void)n;
    return in_triangle_bvh();
}

/* The sign of det L: a reflection turns the Newell normal of mapped
** vertices against the normal the instance's hits report. */
static double det_sign(const ray__instance *in)
{
    const double (*m)[4] = in->xfm.m;
    double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                 m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                 m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);

    return det < 0 ? -1.0 : 1.0;
}

static int closest_POLYGON(const ray_scene *s, const ray__prim *p,
                           const query *qs, ray_vec3 *pt, ray_vec3 *n)
{
    if (!ray__polygon_closest_mapped(s->verts + p->first, p->count,
                                     qs->in != NULL ? &qs->in->xfm : NULL,
                                     qs->qw, pt, n))
        return 0;
    if (qs->in != NULL)
        *n = v3_scale(*n, det_sign(qs->in));
    return 1;
}

/*
** The nearest point of the parallelepiped that box b is through the
** instance: the nearest of its 12 world triangles' (inside or out: the
** nearest boundary point of a convex body from inside lies on its
** nearest face plane, within that face), with the face's normal.
**
** At an edge or a corner several faces hold that point p: the normal is
** that of the face, among those whose plane holds p, over whose plane q
** lies highest (ray_closest_point(3): at an edge or a corner "the face
** whose plane q lies farthest outside of"; issue 38, defect 3: the first
** face in loop order could have q behind its plane, and a push along
** its normal went into the box).  A face's plane holds p when p's
** height over it, n.(p - x0) (x0 a corner of the face, n its unit world
** normal, by the inverse transpose: outward through reflections too),
** is within 64 DBL_EPSILON (M + d), M the largest coordinate magnitude of
** q and the corners: p is off its own face's plane by at most gamma(3)
** of such magnitudes (ray_closest_point(3), Accuracy), the normal and
** the dot product add a few roundings more, and a face not through p
** (at an edge of a thin face, say) stands off by far more.  Heights, not
** the faces' computed distances, decide: on a sliver face (a strongly
** stretched box) those distances err by more than their differences.
*/
static int parallelepiped_closest(const ray_box_params *b,
                                  const ray__instance *in, ray_vec3 q,
                                  ray_vec3 *pt, ray_vec3 *n)
{
    ray_vec3 e[3], corner[8], best = q, face_o[6], face_n[6];
    double h[3], best_d = HUGE_VAL, face_d[6], m, tie, height;
    int k, axis, f, best_f = -1;

    if (!ray__box_frame(b, e))
        return 0;
    h[0] = b->half_extents.x;
    h[1] = b->half_extents.y;
    h[2] = b->half_extents.z;
    m = fmax(fabs(q.x), fmax(fabs(q.y), fabs(q.z)));
    for (k = 0; k < 8; k++) {
        ray_vec3 c = b->center;
        c = v3_madd(c, k & 1 ? h[0] : -h[0], e[0]);
        c = v3_madd(c, k & 2 ? h[1] : -h[1], e[1]);
        c = v3_madd(c, k & 4 ? h[2] : -h[2], e[2]);
        corner[k] = ray__instance_point_to_world(in, c);
        m = fmax(m, fmax(fabs(corner[k].x),
                         fmax(fabs(corner[k].y), fabs(corner[k].z))));
    }
    for (axis = 0; axis < 3; axis++) {
        int side, j = 1 << ((axis + 1) % 3), l = 1 << ((axis + 2) % 3);
        for (side = 0; side < 2; side++) {
            int base = side ? 1 << axis : 0, t;
            ray_vec3 quad[4];
            f = 2 * axis + side;
            quad[0] = corner[base];
            quad[1] = corner[base | j];
            quad[2] = corner[base | j | l];
            quad[3] = corner[base | l];
            face_d[f] = HUGE_VAL;
            face_o[f] = quad[0];
            for (t = 0; t < 2; t++) {
                ray_vec3 x = ray__triangle_closest(quad[0], quad[1 + t],
                                                   quad[2 + t], q);
                double d = ray__distance(x, q);
                if (d < face_d[f]) {
                    face_d[f] = d;
                    if (d < best_d) {
                        best_d = d;
                        best = x;
                        best_f = f;
                    }
                }
            }
            face_n[f] = ray__instance_normal(
                in, v3_scale(e[axis], side ? 1.0 : -1.0));
        }
    }
    if (!(best_d < HUGE_VAL))
        return 0;
    tie = 64 * DBL_EPSILON * (m + best_d);
    height = v3_dot(face_n[best_f], v3_sub(q, best));
    for (f = 0; f < 6; f++) {
        double above;
        if (!(fabs(v3_dot(face_n[f], v3_sub(best, face_o[f]))) <= tie))
            continue;
        above = v3_dot(face_n[f], v3_sub(q, best));
        if (above > height) {
            height = above;
            best_f = f;
        }
    }
    *pt = best;
    *n = face_n[best_f];
    return 1;
}

static int closest_BOX(const ray_scene *s, const ray__prim *p,
                       const query *qs, ray_vec3 *pt, ray_vec3 *n)
{
    const ray_box_params *b = &s->surfaces[p->surface].box;
    const ray__instance *in = qs->in;

    if (in == NULL)
        return ray__box_closest(b, qs->qw, pt, n);
    if (in->similarity > 0 && qs->q_ok) {
        /* Distances scale alike: the child's nearest point, mapped. */
        ray_vec3 po, no;
        if (!ray__box_closest(b, qs->q, &po, &no))
            return 0;
        *pt = ray__instance_point_to_world(in, po);
        *n = ray__instance_normal(in, no);
        return v3_isfinite(*pt);
    }
    return parallelepiped_closest(b, in, qs->qw, pt, n);
}

static int closest_CAPSULE(const ray_scene *s, const ray__prim *p,
                           const query *qs, ray_vec3 *pt, ray_vec3 *n)
{
    const ray_capsule_params *c = &s->surfaces[p->surface].capsule;
    const ray__instance *in = qs->in;
    ray_capsule_params w;
    double e[3];
    int inside;

    if (in == NULL)
        return ray__capsule_closest(c, qs->qw, pt, n);
    w.a = ray__instance_point_to_world(in, c->a);
    w.b = ray__instance_point_to_world(in, c->b);
    if (in->similarity > 0) {
        w.radius = c->radius * in->similarity;
        return ray__capsule_closest(&w, qs->qw, pt, n);
    }
    if (!(in->sv[0] > 0))
        return 0;
    e[0] = c->radius * in->sv[0];
    e[1] = c->radius * in->sv[1];
    e[2] = c->radius * in->sv[2];
    return ray__ellipsoid_sweep_closest(w.a, v3_sub(w.b, w.a),
                                        (const double(*)[3])in->axes, e,
                                        qs->qw, pt, n, &inside);
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

static int closest_TORUS(const ray_scene *s, const ray__prim *p,
                         const query *qs, ray_vec3 *pt, ray_vec3 *n)
{
    (void)s, (void)p, (void)qs, (void)pt, (void)n;
    return no_closest_point();
}

static int closest_IMPLICIT(const ray_scene *s, const ray__prim *p,
                            const query *qs, ray_vec3 *pt, ray_vec3 *n)
{
    (void)s, (void)p, (void)qs, (void)pt, (void)n;
    return no_closest_point();
}

static int closest_PARAMETRIC(const ray_scene *s, const ray__prim *p,
                              const query *qs, ray_vec3 *pt, ray_vec3 *n)
{
    (void)s, (void)p, (void)qs, (void)pt, (void)n;
    return no_closest_point();
}

static int closest_BEZIER(const ray_scene *s, const ray__prim *p,
                          const query *qs, ray_vec3 *pt, ray_vec3 *n)
{
    (void)s, (void)p, (void)qs, (void)pt, (void)n;
    return no_closest_point();
}

/* User geometry has only the callbacks its program gave it, and no
** closest-point one: skipped, as the surfaces above. */
static int closest_USER(const ray_scene *s, const ray__prim *p,
                        const query *qs, ray_vec3 *pt, ray_vec3 *n)
{
    (void)s, (void)p, (void)qs, (void)pt, (void)n;
    return no_closest_point();
}

/* Instances are searched by visit_instance below (their child's own
** search, with the ids it finds): never asked here. */
static int closest_INSTANCE(const ray_scene *s, const ray__prim *p,
                            const query *qs, ray_vec3 *pt, ray_vec3 *n)
{
    (void)s, (void)p, (void)qs, (void)pt, (void)n;
    return 0;
}

static int prim_closest(const ray_scene *s, unsigned i, const query *qs,
                        ray_vec3 *pt, ray_vec3 *n)
{
    const ray__prim *p = &s->prims[i];

    switch (p->kind) {
#define CLOSEST_OF(name, counted_as, class)                                \
    case RAY__KIND_##name:                                                 \
        return closest_##name(s, p, qs, pt, n);
        RAY__PRIM_KINDS(CLOSEST_OF)
#undef CLOSEST_OF
    }
    return 0;                       /* not a ray__kind: cannot happen */
}

/* ------------------------------------------------------------ visiting */

static void search_in(const ray_scene *s, query *qs);

/* The largest |coordinate| along axis k of the child's box (its
** geometry's, rounded outward at commit); 0 for an empty child. */
static double child_extent(const ray_scene *c, int k)
{
    double lo = k == 0 ? c->lo.x : k == 1 ? c->lo.y : c->lo.z;
    double hi = k == 0 ? c->hi.x : k == 1 ? c->hi.y : c->hi.z;

    return lo <= hi ? fmax(fabs(lo), fabs(hi)) : 0.0;
}

/*
** How far, in the child's units, an object point t of a candidate whose
** world distance was computed as d from qw can lie from q (the child's
** image of qw, as computed) beyond widen d: the boxes hold t, so a box
** farther from q than (best widen + margin) holds no candidate nearer
** than best (issue 38's review: through an instance at 2^40 the rounded
** world triangles stood half an ulp of 2^40 nearer than the child's
** exact boxes said, and a radius equal to a found distance found
** nothing).  Three roundings, with M = inv as rounded and the child's
** points within E_j = child_extent(j) per axis:
**   world: the candidate's world point p, computed from the corners
**     L a + c rounded (gamma(4) (|L| |a| + |c|) per component, as in
**     ray__instance_to_world) and then its nearest point (on its
**     triangle to gamma(3) (|a| + |b - a| + |c - a|), nearest.c; the
**     other kinds to a few ulps of the same magnitudes), lies within
**     (gamma(4) + 5 gamma(3)) (1 + gamma(4)) R per component of an exact
**     point L t + c, R = max_k sum_j |L_kj| E_j + |c_k|: under 20 u R,
**     and under 35 u R in the 2-norm (sqrt(3) 20 < 35), which gamma(64)
**     R bounds with room for the other kinds' few ulps.  |p - qw|
**     itself is within 3 ulps of d (ray__distance), which set_best
**     covers;
**   into the child: M (L t + c - c) = t + (M L - I) t, off t by at most
**     inv_residual |t|, |t| <= E_0 + E_1 + E_2;
**   q: M (qw - c) is computed with gamma(4) sum_j |M_kj| (|qw_j| + |c_j|)
**     per component (the difference rounds once, the row's dot product
**     three times; ray__instance_box forms the same terms), under their
**     sum over k in the 2-norm.
** With |M|_2 <= widen, |t - q| <= widen (d + world) + residual + q's:
** the margin is the last three, rounded up by gamma(4) for their own
** sums and products.  An overflowing term makes it +Inf: nothing is
** pruned (or NaN, which set_best takes the same way).
*/
static double instance_margin(const ray__instance *in, ray_vec3 qw,
                              double widen)
{
    const double (*m)[4] = in->xfm.m;
    const double q[3] = {qw.x, qw.y, qw.z};
    double e[3], reach = 0, t = 0, q_err = 0, world;
    int j, k;

    for (j = 0; j < 3; j++) {
        e[j] = child_extent(in->child, j);
        t += e[j];
    }
    for (k = 0; k < 3; k++) {
        double row = fabs(m[k][3]), back = 0;
        for (j = 0; j < 3; j++) {
            row += fabs(m[k][j]) * e[j];
            back += fabs(in->inv[k][j]) * (fabs(q[j]) + fabs(m[j][3]));
        }
        reach = fmax(reach, row);
        q_err += ray__gamma(4) * back;
    }
    world = ray__gamma(64) * reach;
    return (widen * world + in->inv_residual * t + q_err) *
           (1 + ray__gamma(4));
}

/*
** Instance i: its child searched with q taken into its space and the
** world's search radius widened by |L^-1|_2 for its boxes, every
** candidate measured in world space (see query), so that the answer is
** exact for any invertible affine transform.  The child's search starts
** from the world search's state (its best so far) and hands back what
** it found nearer.
*/
static void visit_instance(const ray_scene *s, unsigned i, query *qs)
{
    const ray__instance *in = &s->instances[s->prims[i].surface];
    query child = *qs;

    if (!in->child->committed || in->child->generation != in->generation) {
        qs->stale = 1;
        return;
    }
    child.q = ray__instance_point_to_object(in, qs->qw);
    child.q_ok = v3_isfinite(child.q);
    child.in = in;
    child.inst_id = i;
    child.widen = in->inv_spec;
    child.margin = instance_margin(in, qs->qw, in->inv_spec);
    if (!child.q_ok) {
        /* q's image is past DBL_MAX (a transform with a row near 1e-307
        ** flattens the child, and q lies far off it: issue 38, defect 7),
        ** but the child's world points may well be near q.  Candidates
        ** are measured in world space from qw anyway; only the boxes'
        ** pruning reads q, so it is turned off (an infinite widen: every
        ** box is within reach) and the child searched whole, and the
        ** box's similarity path, which reads q, takes the
        ** parallelepiped's. */
        child.q = v3(0, 0, 0);
        child.widen = HUGE_VAL;
        child.margin = 0;
    }
    search_in(in->child, &child);
    qs->stale |= child.stale;
    if (child.found && (!qs->found || child.out.distance < qs->best)) {
        qs->out = child.out;
        qs->found = 1;
        set_best(qs, child.out.distance);
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
    if (!prim_closest(s, i, qs, &p, &n))
        return;
    d = ray__distance(p, qs->qw);
    if (nearer(qs, d))
        record(qs, p, d, n, i, 0);
}

/* box_d2 of triangle abc's own box (below, with the nodes' boxes). */
static double tri_box_d2(ray_vec3 a, ray_vec3 b, ray_vec3 c,
                         const query *qs);

/* Triangle i of the scene (leaf order), through the instance's transform
** when searched inside one (the world triangle's nearest point); its
** normal as ray_triangle's, (b - a) x (c - a) normalised (through an
** instance, as its hits have it), computed only for a nearer point.  Its
** corners as the ray queries read them (ray__leaf_tri: from its leaf's
** rows, at stride n_rows, or the leaf-order copy), next to the leaf's
** other triangles, rather than through the mesh's indices. */
static void visit_triangle(const ray_scene *s, unsigned i,
                           const float *rows, unsigned n_rows, query *qs)
{
    ray__tri t = ray__leaf_tri(s, i, rows, n_rows);
    ray_vec3 a = t.a, b = t.b, c = t.c, p, n;
    double d;

    if (!(tri_box_d2(a, b, c, qs) <= qs->best2))
        return;
    if (qs->in == NULL)
        p = ray__triangle_closest(a, b, c, qs->qw);
    else
        p = ray__triangle_closest(ray__instance_point_to_world(qs->in, a),
                                  ray__instance_point_to_world(qs->in, b),
                                  ray__instance_point_to_world(qs->in, c),
                                  qs->qw);
    d = ray__distance(p, qs->qw);
    if (nearer(qs, d) &&
        v3_normalize(v3_cross(v3_sub(b, a), v3_sub(c, a)), &n)) {
        if (qs->in != NULL)
            n = ray__instance_normal(qs->in, n);
        record(qs, p, d, n, s->tri_ids[i].geom_id, s->tri_ids[i].prim_id);
    }
}

/*
** A lower bound on the squared distance (in the scaled units) from q to
** the box [lo, hi], computed in double from bounds that contain the
** geometry (a node's float boxes, rounded outward from it at commit, or a
** triangle's own corners' extremes).  Per axis the offset max(lo - q,
** q - hi, 0) rounds once (the scaling is exact but in underflow), the
** squares and their sum round three times more: the computed sum is at
** most the exact one times (1 + u)^2 (1 + gamma(3)) <= 1 + gamma(5), so
** times 1 - gamma(8) (its own rounding included) it is no more than the
** exact one; underflow, at most half a subnormal per product and per
** scaled offset, is covered by 4 subnormals.  So no box holding a point
** within the search radius is ever skipped.  An unused slot (lo = +Inf,
** hi = -Inf) is Inf away.
*/
static inline double box_d2(double lo_x, double lo_y, double lo_z,
                            double hi_x, double hi_y, double hi_z,
                            const query *qs)
{
    const double shrink = 1 - ray__gamma(8);
    /* q is finite and a bound is finite or infinite, so no offset is
    ** NaN: max2 will do. */
    double dx = max2(max2(lo_x - qs->q.x, qs->q.x - hi_x), 0.0);
    double dy = max2(max2(lo_y - qs->q.y, qs->q.y - hi_y), 0.0);
    double dz = max2(max2(lo_z - qs->q.z, qs->q.z - hi_z), 0.0);

    dx *= qs->scale;
    dy *= qs->scale;
    dz *= qs->scale;
    return (dx * dx + dy * dy + dz * dz) * shrink - 4 * RAY__TINY;
}

/* box_d2 of each of node w's eight boxes. */
static void boxes_d2(const ray__wnode *w, const query *qs,
                     double d2[RAY__WIDTH])
{
    int k;

    for (k = 0; k < RAY__WIDTH; k++)
        d2[k] = box_d2((double)w->lo[0][k], (double)w->lo[1][k],
                       (double)w->lo[2][k], (double)w->hi[0][k],
                       (double)w->hi[1][k], (double)w->hi[2][k], qs);
}

/*
** box_d2 of triangle abc's own box, the extremes of its corners (exact),
** in the space searched: a triangle of a leaf whose box is within reach
** lies mostly beyond it once a near point is found, and this bound (a
** dozen operations) spares it the closest-point routine (a hundred and
** more).  The same test as a node's box, so no triangle a node's box
** would keep is skipped: a leaf of one triangle has that box exactly.
*/
static double tri_box_d2(ray_vec3 a, ray_vec3 b, ray_vec3 c,
                         const query *qs)
{
    return box_d2(min2(min2(a.x, b.x), c.x), min2(min2(a.y, b.y), c.y),
                  min2(min2(a.z, b.z), c.z), max2(max2(a.x, b.x), c.x),
                  max2(max2(a.y, b.y), c.y), max2(max2(a.z, b.z), c.z), qs);
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
            unsigned i, n = count & ~RAY__LEAF, end = child + n;
            for (i = child; i < end; i++) {
                if (leaf == LEAF_TRIANGLES)
                    visit_triangle(s, i, s->leaf_f + RAY__LEAF_ROWS *
                                       (size_t)child + (i - child), n, qs);
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

/* The search of scene s (the top scene, or an instance's child) from
** qs's state: its planes, then its two BVHs. */
static void search_in(const ray_scene *s, query *qs)
{
    double m = fmax(fabs(qs->q.x), fmax(fabs(qs->q.y), fabs(qs->q.z)));
    size_t i;

    qs->scale = m < 0x1p510 ? 1.0 : ray__pow2(509 - ray__exponent_of(m));
    set_best(qs, qs->best);
    for (i = 0; i < s->n_planes; i++)
        visit_prim(s, s->planes[i], qs);
    walk(s, &s->prim_bvh, LEAF_PRIMS, qs);
    walk(s, &s->tri_bvh, LEAF_TRIANGLES, qs);
}

int ray_closest_point(const ray_scene *s, ray_vec3 q, double radius,
                      ray_closest *out)
{
    query qs;

    if (s == NULL || out == NULL || !v3_isfinite(q) || !(radius >= 0))
        return -RAY_EINVAL;
    if (!s->committed)
        return -RAY_ESTATE;
    qs.q = qs.qw = q;
    qs.q_ok = 1;
    qs.in = NULL;
    qs.inst_id = RAY_INVALID_ID;
    qs.widen = 1;
    qs.margin = 0;
    qs.best = radius;
    qs.found = 0;
    qs.stale = 0;
    search_in(s, &qs);
    if (qs.stale)
        return -RAY_ESTATE;
    if (!qs.found)
        return 0;
    /* Field by field: no indeterminate padding for the caller's bytes. */
    out->p = qs.out.p;
    out->distance = qs.out.distance;
    out->n = qs.out.n;
    out->geom_id = qs.out.geom_id;
    out->prim_id = qs.out.prim_id;
    out->inst_id = qs.out.inst_id;
    return 1;
}
