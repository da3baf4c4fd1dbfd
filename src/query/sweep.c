/* SPDX-License-Identifier: MIT */
/*
** sweep.c -- ray_intersect_sweep: the first contact of a sphere or a
** capsule moved along a line through a committed scene.  The structures
** are the ray queries' (intersect.c): the planes one by one, then the
** BVH over the bounded primitives (instances descended into, as
** closest.c does) and the BVH over the triangles, each walked nearest
** box first, a box entered when the shape's path meets it grown by the
** shape (the radius, and the capsule's axis), and skipped once the
** contact found so far comes before it.  Each primitive is brought to
** world space, relative to the sweep's start, and handed to the narrow
** phase (prim/sweep.h: the Minkowski sum's pieces, conservative and
** watertight).
*/
#include "query/query.h"
#include "query/why.h"
#include "prim/overlap.h"

/* The search's state. */
typedef struct sweeper {
    ray__sweep sw;           /* the narrow phase's, relative to o */
    ray_vec3 o;              /* the frame's origin: the sweep's a */
    const ray__gate *gate;   /* masks and filters, or NULL */
    ray_ray path;            /* the sweep's path, for the filters */
    ray__contact best;       /* the contact so far (t = +Inf: none) */
    unsigned geom_id, prim_id, inst_id, flags;
    int stale;
    /* The scene being searched: the top one, or an instance's child. */
    const ray__instance *in; /* NULL at the top */
    unsigned in_id;          /* its id in the top scene */
    /* The shape in that scene's space, for its boxes: the path's start
    ** and direction (the narrow phase's t units), the axis, and a
    ** radius that holds the shape's image (radius |L^-1|_2). */
    ray_vec3 bo, bd, bs;
    double br;
    /* Inside an instance: the narrow phase's skin (below) for any of its
    ** features, in the child's units; unused at the top. */
    double inst_skin;
} sweeper;

/* The larger of a and b (operands that cannot be NaN). */
static double max2(double a, double b)
{
    return a > b ? a : b;
}

/* The largest |component| of v. */
static double max_abs(ray_vec3 v)
{
    return max2(max2(fabs(v.x), fabs(v.y)), fabs(v.z));
}

/* ------------------------------------------------------------ boxes */

/*
** The narrow phase's skin for any feature inside box [lo, hi]: it meets
** each feature grown by ray__sweep_eps of the feature's coordinates
** relative to the sweep's start o (sweep_pieces.c), up to gamma(64) of
** them, so a contact comes that much before the shape itself touches.
** The box must be grown by as much, or a box whose contact ties the
** best one (or comes a skin before it) is skipped, and which of the two
** is reported depends on the tree (a mesh refitted answered another
** triangle of a tie than the same mesh built afresh: fuzz_live).  At
** the top the box is the world's, and |x - o| <= |lo| + |hi| + |o| per
** axis for x in it; inside an instance, its world box bounds every
** feature, and the skin is mapped to the child's units as the radius is
** (visit_instance).
*/
static double box_skin(const sweeper *w, const float lo[3],
                       const float hi[3])
{
    double m = 0;
    int k;

    if (w->in != NULL)
        return w->inst_skin;
    for (k = 0; k < 3; k++) {
        double o = k == 0 ? w->o.x : k == 1 ? w->o.y : w->o.z;
        m = max2(m, fabs((double)lo[k]) + fabs((double)hi[k]) + fabs(o));
    }
    return ray__sweep_eps(&w->sw, m);
}

/*
** The interval of t over which the shape's path meets box [lo, hi] (in
** the space of the scene searched), grown by the shape: the capsule's
** end a lies in lo - r - max(s, 0) .. hi + r + max(-s, 0) per axis
** whenever the capsule meets the box.  The box is grown by the narrow
** phase's skin (box_skin), further by
** gamma(8) of its magnitude (its bounds are floats rounded outward from
** the geometry; the growth's own sums round a few times), and each
** slab's t by 2 gamma(3) of itself (the two roundings of (bound - o) /
** d and the division: Ize's bound, "Robust BVH Ray Traversal", JCGT
** 2(2), 2013), so that no box holding a contact is skipped.  *entry:
** where the path enters it (clamped to t0).  0 when it misses, or
** enters after t1.
*/
static int box_entry(const sweeper *w, const float lo[3], const float hi[3],
                     double *entry)
{
    double o[3], d[3], s[3], t0 = w->sw.t0, t1 = w->best.t;
    double reach = w->br + box_skin(w, lo, hi);
    int k;

    o[0] = w->bo.x, o[1] = w->bo.y, o[2] = w->bo.z;
    d[0] = w->bd.x, d[1] = w->bd.y, d[2] = w->bd.z;
    s[0] = w->bs.x, s[1] = w->bs.y, s[2] = w->bs.z;
    if (t1 > w->sw.t1)
        t1 = w->sw.t1;
    for (k = 0; k < 3; k++) {
        double l = (double)lo[k], h = (double)hi[k], grow, ta, tb;
        if (!(l <= h))
            return 0;                       /* an unused slot */
        grow = reach + ray__gamma(8) * (fabs(l) + fabs(h) + reach +
                                        fabs(s[k]) + fabs(o[k]));
        l -= grow + max2(s[k], 0);
        h += grow + max2(-s[k], 0);
        if (d[k] == 0) {
            if (!(o[k] >= l && o[k] <= h))
                return 0;
            continue;
        }
        ta = (l - o[k]) / d[k];
        tb = (h - o[k]) / d[k];
        if (ta > tb) {
            double x = ta;
            ta = tb;
            tb = x;
        }
        ta -= fabs(ta) * 2 * ray__gamma(3);
        tb += fabs(tb) * 2 * ray__gamma(3);
        if (ta > t0)
            t0 = ta;
        if (tb < t1)
            t1 = tb;
        if (!(t0 <= t1))
            return 0;
    }
    *entry = t0;
    return 1;
}

/* ------------------------------------------------------ candidates */

/* Is candidate c (of geometry p, ids as given) better than the best? */
static int beats(const sweeper *w, const ray__contact *c, unsigned geom_id,
                 unsigned prim_id, unsigned inst_id)
{
    const ray__contact *b = &w->best;

    if (c->t != b->t)
        return c->t < b->t;
    if (c->depth != b->depth)
        return c->depth > b->depth;
    if (inst_id != w->inst_id)
        return inst_id < w->inst_id;
    if (geom_id != w->geom_id)
        return geom_id < w->geom_id;
    return prim_id < w->prim_id;
}

/*
** A candidate contact c of geometry p (geom_id, prim_id, of the scene
** being searched): kept if it beats the best and p's filter, if it has
** one for nearest queries, keeps it (handed the path as a ray whose
** open interval holds the contact, and the candidate as a hit in world
** space).
*/
static void consider(sweeper *w, const ray__prim *p, const ray__contact *c,
                     unsigned geom_id, unsigned prim_id, unsigned flags)
{
    unsigned inst_id = w->in != NULL ? w->in_id : RAY_INVALID_ID;

    if (!(c->t < HUGE_VAL) || !beats(w, c, geom_id, prim_id, inst_id))
        return;
    if (w->gate != NULL && p->filter != NULL &&
        (p->filter_queries & RAY_FILTER_INTERSECT)) {
        ray_ray r = w->path;
        ray_hit h;
        memset(&h, 0, sizeof h);
        h.t = c->t * w->sw.t_unit;
        h.p = v3_add(c->p, w->o);
        h.n = c->n;
        h.geom_id = geom_id;
        h.prim_id = prim_id;
        h.inst_id = inst_id;
        if (!(h.t > r.tmin))
            r.tmin = nextafter(h.t, -HUGE_VAL);
        if (!(h.t < r.tmax))
            r.tmax = nextafter(h.t, HUGE_VAL);
        if (!p->filter(p->filter_ud, &r, &h, w->gate->query_ud))
            return;
    }
    w->best = *c;
    if (c->t < w->sw.t1)
        w->sw.t1 = c->t;           /* later contacts need not be sought */
    w->geom_id = geom_id;
    w->prim_id = prim_id;
    w->inst_id = inst_id;
    w->flags = flags | (c->depth > 0 ? RAY_CONTACT_OVERLAP : 0u);
}

/* A fresh candidate slot: no contact, below any the best could tie. */
static ray__contact blank(const sweeper *w)
{
    ray__contact c;

    c.t = w->best.t;
    c.depth = -1;
    c.p = c.n = v3(0, 0, 0);
    return c;
}

/* Does the gate hide geometry p (its mask shares no bit with the
** query's)? */
static int hidden(const sweeper *w, const ray__prim *p)
{
    return w->gate != NULL && (p->mask & w->gate->mask) == 0;
}

/* Point x of the scene searched, in the sweep's frame (world, minus o). */
static ray_vec3 local(const sweeper *w, ray_vec3 x)
{
    if (w->in != NULL)
        x = ray__instance_point_to_world(w->in, x);
    return v3_sub(x, w->o);
}

/* ------------------------------------------------------------ kinds */

/*
** Geometry p against the sweep, by kind, into *c: 1 and the flags of
** the answer, or 0.  The dispatch is a switch generated from the list of
** kinds (RAY__PRIM_KINDS, prim.h) with no default: a kind added without
** its sweep_NAME does not compile.
*/

/* The corners of box [lo, hi] (bit k of a corner's index: hi on axis
** k), in the sweep's frame. */
static void aabb_corners(const sweeper *w, ray_vec3 lo, ray_vec3 hi,
                         ray_vec3 corner[8])
{
    int k;

    for (k = 0; k < 8; k++)
        corner[k] = local(w, v3(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y,
                                k & 4 ? hi.z : lo.z));
}

/* The answer against p's box (through the instance: a parallelepiped):
** conservative, for the kinds whose surfaces have no sweep of their own
** (ray.h: RAY_CONTACT_BOUNDS). */
static unsigned against_bounds(sweeper *w, const ray_scene *s,
                               const ray__prim *p, ray__contact *c)
{
    ray_vec3 lo, hi, corner[8];

    ray__prim_box(s, p, &lo, &hi);
    aabb_corners(w, lo, hi, corner);
    return ray__sweep_parallelepiped(&w->sw, corner, c) ? RAY_CONTACT_BOUNDS
                                                        : 0u;
}

/* An ellipsoid (swept along w) from a sphere (or capsule) of radius R
** through the instance's transform: its axes and semi-axes. */
static int ellipsoid_of(const ray__instance *in, ray_vec3 c, ray_vec3 axis,
                        double R, ray__ellipsoid *el)
{
    int i, j;

    if (!(in->sv[0] > 0))
        return 0;
    el->c = c;
    el->w = axis;
    for (i = 0; i < 3; i++) {
        el->e[i] = R * in->sv[i];
        for (j = 0; j < 3; j++)
            el->u[i][j] = in->axes[i][j];
    }
    return 1;
}

static unsigned sweep_SPHERE(sweeper *w, const ray_scene *s,
                             const ray__prim *p, ray__contact *c)
{
    ray__ellipsoid el;

    (void)s;
    if (w->in == NULL || w->in->similarity > 0)
        return ray__sweep_sphere(&w->sw, local(w, p->a),
                                 p->radius * (w->in ? w->in->similarity : 1),
                                 c) ? 1u : 0u;
    if (!ellipsoid_of(w->in, local(w, p->a), v3(0, 0, 0), p->radius, &el))
        return 0;
    return ray__sweep_ellipsoid(&w->sw, &el, c) > 0 ? 1u : 0u;
}

/* A plane (never inside an instance: a child has no planes). */
static unsigned sweep_PLANE(sweeper *w, const ray_scene *s,
                            const ray__prim *p, ray__contact *c)
{
    (void)s;
    return ray__sweep_plane(&w->sw, v3_sub(p->a, w->o), p->b, c) ? 1u : 0u;
}

/* Triangles are swept from the triangle BVH (sweep_triangle below). */
static unsigned in_triangle_bvh(void)
{
    return 0;
}

static unsigned sweep_TRIANGLE(sweeper *w, const ray_scene *s,
                               const ray__prim *p, ray__contact *c)
{
    (void)w, (void)s, (void)p, (void)c;
    return in_triangle_bvh();
}

static unsigned sweep_MESH(sweeper *w, const ray_scene *s,
                           const ray__prim *p, ray__contact *c)
{
    (void)w, (void)s, (void)p, (void)c;
    return in_triangle_bvh();
}

/* A polygon: its vertices mapped into the frame on the fly (the
** instance's transform, its translation less o). */
static unsigned sweep_POLYGON(sweeper *w, const ray_scene *s,
                              const ray__prim *p, ray__contact *c)
{
    ray_transform xf;

    if (w->in != NULL)
        xf = w->in->xfm;
    else
        ray_transform_identity(&xf);
    xf.m[0][3] -= w->o.x;
    xf.m[1][3] -= w->o.y;
    xf.m[2][3] -= w->o.z;
    return ray__sweep_polygon(&w->sw, s->verts + p->first, p->count, &xf, c)
               ? 1u : 0u;
}

/* A box: its corners (through any transform: a parallelepiped). */
static unsigned sweep_BOX(sweeper *w, const ray_scene *s, const ray__prim *p,
                          ray__contact *c)
{
    const ray_box_params *b = &s->surfaces[p->surface].box;
    ray_vec3 e[3], corner[8];
    int k;

    if (!ray__box_frame(b, e))
        return 0;
    for (k = 0; k < 8; k++) {
        ray_vec3 x = b->center;
        x = v3_madd(x, k & 1 ? b->half_extents.x : -b->half_extents.x, e[0]);
        x = v3_madd(x, k & 2 ? b->half_extents.y : -b->half_extents.y, e[1]);
        x = v3_madd(x, k & 4 ? b->half_extents.z : -b->half_extents.z, e[2]);
        corner[k] = local(w, x);
    }
    return ray__sweep_parallelepiped(&w->sw, corner, c) ? 1u : 0u;
}

static unsigned sweep_CAPSULE(sweeper *w, const ray_scene *s,
                              const ray__prim *p, ray__contact *c)
{
    const ray_capsule_params *k = &s->surfaces[p->surface].capsule;
    ray_vec3 a = local(w, k->a), b = local(w, k->b);
    ray__ellipsoid el;
    int rc;

    if (w->in == NULL || w->in->similarity > 0)
        return ray__sweep_capsule(&w->sw, a, b,
                                  k->radius * (w->in ? w->in->similarity : 1),
                                  c) ? 1u : 0u;
    if (!ellipsoid_of(w->in, a, v3_sub(b, a), k->radius, &el))
        return 0;
    rc = ray__sweep_ellipsoid(&w->sw, &el, c);
    if (rc < 0)
        return against_bounds(w, s, p, c);
    return rc > 0 ? 1u : 0u;
}

static unsigned sweep_TORUS(sweeper *w, const ray_scene *s,
                            const ray__prim *p, ray__contact *c)
{
    return against_bounds(w, s, p, c);
}

static unsigned sweep_IMPLICIT(sweeper *w, const ray_scene *s,
                               const ray__prim *p, ray__contact *c)
{
    return against_bounds(w, s, p, c);
}

static unsigned sweep_PARAMETRIC(sweeper *w, const ray_scene *s,
                                 const ray__prim *p, ray__contact *c)
{
    return against_bounds(w, s, p, c);
}

static unsigned sweep_BEZIER(sweeper *w, const ray_scene *s,
                             const ray__prim *p, ray__contact *c)
{
    return against_bounds(w, s, p, c);
}

static unsigned sweep_USER(sweeper *w, const ray_scene *s,
                           const ray__prim *p, ray__contact *c)
{
    return against_bounds(w, s, p, c);
}

/* Instances are descended into by visit_prim: never asked here. */
static unsigned sweep_INSTANCE(sweeper *w, const ray_scene *s,
                               const ray__prim *p, ray__contact *c)
{
    (void)w, (void)s, (void)p, (void)c;
    return 0;
}

static unsigned prim_sweep(sweeper *w, const ray_scene *s,
                           const ray__prim *p, ray__contact *c)
{
    switch (p->kind) {
#define SWEEP_OF(name, counted_as, class)                                  \
    case RAY__KIND_##name:                                                 \
        return sweep_##name(w, s, p, c);
        RAY__PRIM_KINDS(SWEEP_OF)
#undef SWEEP_OF
    }
    return 0;                       /* not a ray__kind: cannot happen */
}

/* ---------------------------------------------------------- visiting */

static void search_in(sweeper *w, const ray_scene *s);

/*
** Instance i: its child searched with the shape's path in the child's
** space for the boxes (the path mapped; the radius times |L^-1|_2, which
** holds the image of the shape's ball), every primitive still swept in
** world space.
*/
static void visit_instance(sweeper *w, const ray_scene *s, unsigned i)
{
    const ray__instance *in = &s->instances[s->prims[i].surface];
    const ray__instance *outer = w->in;
    ray_vec3 bo = w->bo, bd = w->bd, bs = w->bs;
    double br = w->br, skin = w->inst_skin, m;
    unsigned outer_id = w->in_id;
    ray_ray world, object;

    if (ray__instance_stale(in)) {
        w->stale = 1;
        return;
    }
    world.org = w->o;
    world.dir = w->sw.d;
    world.tmin = world.tmax = 0;
    ray__instance_ray_to_object(in, &world, &object);
    w->bo = object.org;
    w->bd = object.dir;
    world.dir = w->sw.s;
    ray__instance_ray_to_object(in, &world, &object);
    w->bs = object.dir;
    /* The mapped differences round: 2^-40 relative more, far above it. */
    w->br = w->sw.r * in->inv_spec * (1 + 0x1p-40) +
            0x1p-40 * (max_abs(w->bd) + max_abs(w->bs));
    /* The skin of its features (box_skin), from its world box. */
    m = max2(max_abs(v3_sub(in->lo, w->o)), max_abs(v3_sub(in->hi, w->o)));
    w->inst_skin = ray__sweep_eps(&w->sw, m * (1 + 0x1p-40)) * in->inv_spec *
                   (1 + 0x1p-40);
    w->in = in;
    w->in_id = i;
    if (v3_isfinite(w->bo) && v3_isfinite(w->bd) && v3_isfinite(w->bs))
        search_in(w, in->child);
    w->in = outer;
    w->in_id = outer_id;
    w->bo = bo;
    w->bd = bd;
    w->bs = bs;
    w->br = br;
    w->inst_skin = skin;
}

/* Geometry i of s (a plane or a bounded primitive but a triangle). */
static void visit_prim(sweeper *w, const ray_scene *s, unsigned i)
{
    const ray__prim *p = &s->prims[i];
    ray__contact c = blank(w);
    unsigned flags;

    if (hidden(w, p))
        return;
    if (p->kind == RAY__KIND_INSTANCE) {
        visit_instance(w, s, i);
        return;
    }
    if ((flags = prim_sweep(w, s, p, &c)) != 0)
        consider(w, p, &c, i, 0, flags & RAY_CONTACT_BOUNDS);
}

/* Triangle slot i of s, in world space relative to o. */
static void visit_triangle(sweeper *w, const ray_scene *s, unsigned i)
{
    const ray__tri_id *id = &s->tri_ids[i];
    const ray__prim *p = &s->prims[id->geom_id];
    ray__contact c = blank(w);
    ray_vec3 a, b, cc;

    if (hidden(w, p))
        return;
    ray__tri_corners(s, i, &a, &b, &cc);
    /* A triangle without a normal (zero area, read as the point at its
    ** first corner: scene.h) is no surface, as for the rays (issue 38,
    ** defect 5). */
    if (!ray__corners_usable(a, b, cc))
        return;
    if (ray__sweep_triangle(&w->sw, local(w, a), local(w, b), local(w, cc),
                            &c))
        consider(w, p, &c, id->geom_id, id->prim_id, 0);
}

enum { LEAF_TRIANGLES, LEAF_PRIMS };

typedef struct pending {
    unsigned child, count;
    double t;
} pending;

/* Nearest box first, as closest.c walks: of a node's children the path
** enters before the best contact, all pushed (sorted, the nearest on
** top) and popped while still before it. */
static void walk(sweeper *w, const ray_scene *s, const ray__bvh *bvh,
                 int leaf)
{
    pending stack[RAY__WIDTH * 64];
    unsigned child = 0, count = 0;
    int sp = 0;

    if (bvh->n_wide == 0)
        return;
    for (;;) {
        if (count == 0) {
            const ray__wnode *n = &bvh->wide[child];
            int k, j, base = sp;
            for (k = 0; k < RAY__WIDTH; k++) {
                float lo[3], hi[3];
                pending e;
                int a;
                if (n->count[k] == RAY__LEAF)
                    continue;
                for (a = 0; a < 3; a++) {
                    lo[a] = n->lo[a][k];
                    hi[a] = n->hi[a][k];
                }
                if (!box_entry(w, lo, hi, &e.t))
                    continue;
                e.child = n->child[k];
                e.count = n->count[k];
                for (j = sp; j > base && stack[j - 1].t < e.t; j--)
                    stack[j] = stack[j - 1];
                stack[j] = e;
                sp++;
            }
        } else {
            unsigned i, end = child + (count & ~RAY__LEAF);
            for (i = child; i < end; i++) {
                if (leaf == LEAF_TRIANGLES)
                    visit_triangle(w, s, i);
                else
                    visit_prim(w, s, bvh->items[i]);
            }
        }
        do {
            if (sp == 0)
                return;
            sp--;
        } while (!(stack[sp].t <= w->best.t));
        child = stack[sp].child;
        count = stack[sp].count;
    }
}

static void search_in(sweeper *w, const ray_scene *s)
{
    size_t i;

    for (i = 0; i < s->n_planes; i++)
        visit_prim(w, s, s->planes[i]);
    walk(w, s, &s->prim_bvh, LEAF_PRIMS);
    walk(w, s, &s->tri_bvh, LEAF_TRIANGLES);
}

/* -------------------------------------------------------------- API */

/* The gate of a sweep with options q, as intersect.c's gate_of: NULL
** when nothing can gate it. */
static const ray__gate *sweep_gate(const ray_scene *s, const ray_query *q,
                                   ray__gate *g)
{
    g->mask = q != NULL ? ~q->ignore_mask : ~0u;
    g->query_ud = q != NULL ? q->query_ud : NULL;
    g->query = RAY_FILTER_INTERSECT;
    g->all = NULL;
    if (!s->gated && g->mask == ~0u)
        return NULL;
    return g;
}

/* Misuse (ray.h): RAY_OK, or the status to negate.  A box shape is
** checked as ray_box checks its params (RAY_EINVAL), then refused as
** not swept (RAY_EKIND: the shape's kind has no sweep, in every build). */
static int sweep_misuse(const ray_scene *s, const ray_sweep *sw,
                        const ray_contact *c)
{
    const ray_shape *k = sw != NULL ? &sw->shape : NULL;

    if (s == NULL || sw == NULL || c == NULL || !v3_isfinite(sw->dir) ||
        !(sw->tmin > -HUGE_VAL && sw->tmin < HUGE_VAL) ||
        !(sw->tmax > sw->tmin) ||
        !v3_isfinite(v3_scale(sw->dir, sw->tmin)))
        return RAY_EINVAL;
    if (k->kind == RAY_SHAPE_BOX)
        return ray__shape_check(k, NULL) ? RAY_EKIND : RAY_EINVAL;
    if (!ray__shape_check(k, NULL))
        return RAY_EINVAL;
    return s->committed ? RAY_OK : RAY_ESTATE;
}

/*
** Why a sweep refused with rc (ray.h, ray_query.why): sweep_misuse's
** checks again, in their order, on the refusal path only.
*/
static int sweep_refused(const ray_query *q, int rc, const ray_scene *s,
                         const ray_sweep *sw, const ray_contact *c)
{
    static const char op[] = "ray_intersect_sweep";
    char *why = q != NULL ? q->why : NULL;
    size_t size = q != NULL ? q->why_size : 0;
    char shape_why[256];

    if (why == NULL)
        return rc;
    if (s == NULL || sw == NULL || c == NULL)
        return ray__why(why, size, rc, op, "%s is NULL", s == NULL ? "scene"
                        : sw == NULL ? "sweep" : "c");
    if (!v3_isfinite(sw->dir))
        return ray__why(why, size, rc, op, "sweep->dir " RAY__WHY_V3
                        " is not finite", RAY__WHY_V3ARGS(sw->dir));
    if (!(sw->tmin > -HUGE_VAL && sw->tmin < HUGE_VAL))
        return ray__why(why, size, rc, op, "sweep->tmin is %.17g: not "
                        "finite", sw->tmin);
    if (!(sw->tmax > sw->tmin))
        return ray__why(why, size, rc, op, "sweep->tmax is %.17g: not above "
                        "tmin %.17g (a tmax of 0 is 1)", sw->tmax, sw->tmin);
    if (!v3_isfinite(v3_scale(sw->dir, sw->tmin)))
        return ray__why(why, size, rc, op, "sweep->tmin * dir overflows "
                        "(tmin %.17g, dir " RAY__WHY_V3 ")", sw->tmin,
                        RAY__WHY_V3ARGS(sw->dir));
    if (rc == -RAY_EKIND)
        return ray__why(why, size, rc, op, "sweep->shape.kind is "
                        "RAY_SHAPE_BOX: a box is not swept");
    if (rc == -RAY_ESTATE)
        return ray__why_state(why, size, rc, op, s);
    ray__shape_why(&sw->shape, "sweep->shape.", shape_why, sizeof shape_why);
    return ray__why(why, size, rc, op, "%s", shape_why);
}

/* Radius 0 and a == b: a ray, answered by the ray query itself. */
static int sweep_ray(const ray_scene *s, const ray_sweep *sw,
                     const ray__gate *g, ray_contact *c)
{
    ray_ray r;
    ray_hit h;
    int rc;

    r.org = sw->shape.a;
    r.dir = sw->dir;
    r.tmin = sw->tmin;
    r.tmax = sw->tmax;
    rc = ray__intersect_gated(s, &r, g, 1, &h, NULL);
    if (rc <= 0)
        return rc;
    c->t = h.t;
    c->p = h.p;
    c->n = v3_dot(h.n, sw->dir) > 0 ? v3_scale(h.n, -1) : h.n;
    c->depth = 0;
    c->flags = 0;
    c->geom_id = h.geom_id;
    c->prim_id = h.prim_id;
    c->inst_id = h.inst_id;
    return 1;
}

int ray_intersect_sweep(const ray_scene *s, const ray_sweep *sw,
                        const ray_query *q, ray_contact *c)
{
    ray_sweep whole;
    ray__gate g;
    sweeper w;
    int rc;

    /* Zero is the default (ray.h): tmax 0 sweeps the whole motion, t up
    ** to 1, so that a sweep naming only its shape and dir moves it. */
    if (sw != NULL && sw->tmax == 0) {
        whole = *sw;
        whole.tmax = 1;
        sw = &whole;
    }
    rc = sweep_misuse(s, sw, c);
    if (rc != RAY_OK)
        return sweep_refused(q, -rc, s, sw, c);
    w.gate = sweep_gate(s, q, &g);
    /* A point moving is a ray; a point standing still (dir 0) is the
    ** overlap test below, as every shape standing still. */
    if (sw->shape.radius == 0 && sw->shape.a.x == sw->shape.b.x &&
        sw->shape.a.y == sw->shape.b.y && sw->shape.a.z == sw->shape.b.z &&
        max_abs(sw->dir) > 0) {
        rc = sweep_ray(s, sw, w.gate, c);
        return rc >= 0 ? rc : sweep_refused(q, rc, s, sw, c);
    }
    memset(&w.best, 0, sizeof w.best);
    w.best.t = HUGE_VAL;
    w.o = sw->shape.a;
    /* dir 0: the narrow phase's overlap at t0 alone (ray__sweep_start
    ** gives it no motion, so no piece enters: sweep.h). */
    ray__sweep_start(&w.sw, sw->dir, v3_sub(sw->shape.b, sw->shape.a),
                     sw->shape.radius, sw->tmin, sw->tmax);
    w.path.org = sw->shape.a;
    w.path.dir = sw->dir;
    w.path.tmin = sw->tmin;
    w.path.tmax = sw->tmax;
    w.geom_id = w.prim_id = w.inst_id = RAY_INVALID_ID;
    w.flags = 0;
    w.stale = 0;
    w.in = NULL;
    w.in_id = RAY_INVALID_ID;
    w.bo = w.o;
    w.bd = w.sw.d;
    w.bs = w.sw.s;
    w.br = w.sw.r;
    w.inst_skin = 0;
    search_in(&w, s);
    if (w.stale)
        return sweep_refused(q, -RAY_ESTATE, s, sw, c);
    /* In the caller's units t may leave the doubles (a tiny motion, a
    ** contact far along it), or the contact point may (geometry within
    ** rounding of DBL_MAX): then it is no contact, as a ray's hit whose
    ** record would not be finite is none (no Inf in a record). */
    if (!(w.best.t * w.sw.t_unit < HUGE_VAL) ||
        !v3_isfinite(v3_add(w.best.p, w.o)))
        return 0;
    c->t = w.best.t * w.sw.t_unit;
    /* A contact at the start is at tmin exactly; and tmin / t_unit may
    ** have underflowed (a huge motion from a tiny tmin): a contact is
    ** then within a subnormal of tmin. */
    if (w.best.t <= w.sw.t0 || c->t < sw->tmin)
        c->t = sw->tmin;
    c->p = v3_add(w.best.p, w.o);
    c->n = w.best.n;
    c->depth = w.best.depth > 0 ? w.best.depth : 0;
    c->flags = w.flags;
    c->geom_id = w.geom_id;
    c->prim_id = w.prim_id;
    c->inst_id = w.inst_id;
    return 1;
}
