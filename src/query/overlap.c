/* SPDX-License-Identifier: MIT */
/*
** overlap.c -- ray_overlap_shape: every primitive of a committed scene
** that meets a sphere, a capsule or an oriented box.  The
** structures are the ray queries' (intersect.c): the planes, then both
** BVHs, every node whose box meets the region's box entered (instances
** descended into with the region's image in the child's space), every
** primitive tested in world space by the narrow phase (prim/overlap.h:
** distances for the sphere and the capsule, separating axes for the
** box).
*/
#include <stdio.h>

#include "query/query.h"
#include "query/why.h"
#include "prim/overlap.h"

/* The query region, in world space: a sphere (c, r), a capsule (the
** segment [c, c2], r; is_capsule) or a box. */
typedef struct region {
    int is_box, is_capsule;
    ray_vec3 c, c2;
    double r;
    ray__pped box;
} region;

/* Where what is found goes: the caller's function, or an array that
** keeps the "cap" first in id order and counts them all. */
typedef struct found_list {
    ray_overlap_fn fn;
    void *ud;
    ray_overlap *out;
    size_t cap, count;
    int stop;
} found_list;

typedef struct searcher {
    region q;
    const ray__gate *gate;       /* masks, or NULL */
    found_list *found;
    /* The scene being searched and, inside an instance, the instance;
    ** the box of the region's image in that scene's space. */
    const ray__instance *in;
    unsigned in_id;
    ray_vec3 lo, hi;
} searcher;

/* ------------------------------------------------------------ results */

static int id_before(const ray_overlap *a, const ray_overlap *b)
{
    if (a->inst_id != b->inst_id)
        return a->inst_id < b->inst_id;
    if (a->geom_id != b->geom_id)
        return a->geom_id < b->geom_id;
    return a->prim_id < b->prim_id;
}

static void report(searcher *w, unsigned geom_id, unsigned prim_id,
                   unsigned flags)
{
    found_list *f = w->found;
    ray_overlap o;

    o.geom_id = geom_id;
    o.prim_id = prim_id;
    o.inst_id = w->in != NULL ? w->in_id : RAY_INVALID_ID;
    o.flags = flags;
    f->count++;
    if (f->fn != NULL) {
        if (f->fn(f->ud, &o) != 0)
            f->stop = 1;
        return;
    }
    if (f->count <= f->cap) {
        f->out[f->count - 1] = o;
    } else if (f->cap > 0) {
        size_t i, worst = 0;
        for (i = 1; i < f->cap; i++)
            if (id_before(&f->out[worst], &f->out[i]))
                worst = i;
        if (id_before(&o, &f->out[worst]))
            f->out[worst] = o;
    }
}

/* ------------------------------------------------------------ shapes */

/* Point x of the scene searched in world space. */
static ray_vec3 world(const searcher *w, ray_vec3 x)
{
    return w->in != NULL ? ray__instance_point_to_world(w->in, x) : x;
}

/* A parallelepiped of the scene searched (an oriented box's, an
** axis-aligned box's), in world space through the instance. */
static ray__pped pped_world(const searcher *w, ray__pped p)
{
    const ray__instance *in = w->in;
    ray_vec3 o = v3(0, 0, 0);
    int k;

    if (in == NULL)
        return p;
    o = ray__instance_point_to_world(in, o);
    p.c = ray__instance_point_to_world(in, p.c);
    for (k = 0; k < 3; k++)
        p.e[k] = v3_sub(ray__instance_point_to_world(in, p.e[k]), o);
    return p;
}

/* The region meets world parallelepiped p (a solid). */
static int meets_pped(const searcher *w, const ray__pped *p)
{
    if (w->q.is_box)
        return ray__pped_overlaps_pped(&w->q.box, p);
    if (w->q.is_capsule)
        return ray__pped_segment(p, w->q.c, w->q.c2) <= w->q.r;
    return ray__pped_signed(p, w->q.c, NULL) <= w->q.r;
}

/* The region meets the primitive's box (through the transform): the
** answer for the kinds without a test of their own (BOUNDS). */
static unsigned by_bounds(const searcher *w, const ray_scene *s,
                          const ray__prim *p)
{
    ray_vec3 lo, hi;
    ray__pped b;

    ray__prim_box(s, p, &lo, &hi);
    b.c = v3_scale(v3_add(lo, hi), 0.5);
    b.e[0] = v3(0.5 * (hi.x - lo.x), 0, 0);
    b.e[1] = v3(0, 0.5 * (hi.y - lo.y), 0);
    b.e[2] = v3(0, 0, 0.5 * (hi.z - lo.z));
    b = pped_world(w, b);
    return meets_pped(w, &b) ? 1u | RAY_CONTACT_BOUNDS : 0u;
}

/* The world sphere's image in a scene's space, or the box's there: the
** parallelepiped L^-1 (q - t), for an instance's round kinds that are
** tested in their own space. */
static ray__pped box_in_object(const ray__instance *in, const ray__pped *q,
                               double scale, ray_vec3 centre)
{
    ray__pped p;
    ray_ray r, o;
    int k;

    r.org = q->c;
    r.dir = v3(0, 0, 0);
    r.tmin = r.tmax = 0;
    ray__instance_ray_to_object(in, &r, &o);
    p.c = v3_scale(v3_sub(o.org, centre), scale);
    for (k = 0; k < 3; k++) {
        r.dir = q->e[k];
        ray__instance_ray_to_object(in, &r, &o);
        p.e[k] = v3_scale(o.dir, scale);
    }
    return p;
}

/*
** Geometry p against the region, by kind: 1 (| RAY_CONTACT_BOUNDS) when
** they meet, else 0.  A switch generated from the list of kinds
** (RAY__PRIM_KINDS, prim.h) with no default, as in kinds.c.
*/
static unsigned meets_SPHERE(const searcher *w, const ray_scene *s,
                             const ray__prim *p)
{
    const ray__instance *in = w->in;
    ray_vec3 c = world(w, p->a), pt, n;
    double e[3];
    int k;

    (void)s;
    if (in == NULL || in->similarity > 0) {
        double R = p->radius * (in != NULL ? in->similarity : 1);
        if (w->q.is_box)
            return ray__pped_signed(&w->q.box, c, NULL) <= R;
        if (w->q.is_capsule)
            return ray__distance(ray__segment_closest(c, w->q.c, w->q.c2),
                                 c) <= R + w->q.r;
        return ray__distance(c, w->q.c) <= R + w->q.r;
    }
    if (!(in->sv[0] > 0))
        return 0;
    if (w->q.is_box) {
        /* In the sphere's own space scaled to the unit ball: the box's
        ** image against the origin. */
        ray__pped b = box_in_object(in, &w->q.box, 1 / p->radius, p->a);
        return ray__pped_signed(&b, v3(0, 0, 0), NULL) <= 1;
    }
    for (k = 0; k < 3; k++)
        e[k] = p->radius * in->sv[k];
    if (w->q.is_capsule) {
        /* The segment [c, c2] meets the ellipsoid E grown by r where the
        ** point c meets E swept by c - c2 grown by r (the Minkowski
        ** trick: |c + s (c2 - c) - x| = |c - (x - s (c2 - c))|). */
        int inside;
        if (!ray__ellipsoid_sweep_closest(c, v3_sub(w->q.c, w->q.c2),
                                          (const double(*)[3])in->axes, e,
                                          w->q.c, &pt, &n, &inside))
            return 0;
        return inside || ray__distance(pt, w->q.c) <= w->q.r;
    }
    if (!ray__ellipsoid_closest(c, (const double(*)[3])in->axes, e, w->q.c,
                                &pt, &n))
        return 0;
    return v3_dot(v3_sub(w->q.c, pt), n) <= 0 ||
           ray__distance(pt, w->q.c) <= w->q.r;
}

static unsigned meets_PLANE(const searcher *w, const ray_scene *s,
                            const ray__prim *p)
{
    (void)s;
    if (w->q.is_box)
        return ray__pped_overlaps_plane(&w->q.box, p->a, p->b) ? 1u : 0u;
    if (w->q.is_capsule) {
        /* A segment whose ends lie on both sides (or on it) crosses it;
        ** else its nearer end is nearest. */
        double ha = v3_dot(v3_sub(w->q.c, p->a), p->b);
        double hb = v3_dot(v3_sub(w->q.c2, p->a), p->b);
        if ((ha <= 0) != (hb <= 0) || ha == 0 || hb == 0)
            return 1;
        return fmin(fabs(ha), fabs(hb)) <= w->q.r;
    }
    return fabs(v3_dot(v3_sub(w->q.c, p->a), p->b)) <= w->q.r;
}

/* Triangles are tested from the triangle BVH (visit_triangle). */
static unsigned in_triangle_bvh(void)
{
    return 0;
}

static unsigned meets_TRIANGLE(const searcher *w, const ray_scene *s,
                               const ray__prim *p)
{
    (void)w, (void)s, (void)p;
    return in_triangle_bvh();
}

static unsigned meets_MESH(const searcher *w, const ray_scene *s,
                           const ray__prim *p)
{
    (void)w, (void)s, (void)p;
    return in_triangle_bvh();
}

static unsigned meets_POLYGON(const searcher *w, const ray_scene *s,
                              const ray__prim *p)
{
    const ray_transform *xf = w->in != NULL ? &w->in->xfm : NULL;
    const ray_vec3 *v = s->verts + p->first;
    ray_vec3 pt, n;

    if (w->q.is_box)
        return ray__pped_overlaps_polygon(&w->q.box, v, p->count, xf) ? 1u
                                                                      : 0u;
    if (w->q.is_capsule) {
        ray_vec3 q;
        return ray__segment_polygon(w->q.c, w->q.c2, v, p->count, xf, &q,
                                    &pt, &n) <= w->q.r;
    }
    return ray__polygon_closest_mapped(v, p->count, xf, w->q.c, &pt, &n) &&
           ray__distance(pt, w->q.c) <= w->q.r;
}

static unsigned meets_BOX(const searcher *w, const ray_scene *s,
                          const ray__prim *p)
{
    ray__pped b;

    if (!ray__pped_of_box(&s->surfaces[p->surface].box, &b))
        return 0;
    b = pped_world(w, b);
    return meets_pped(w, &b) ? 1u : 0u;
}

static unsigned meets_CAPSULE(const searcher *w, const ray_scene *s,
                              const ray__prim *p)
{
    const ray_capsule_params *k = &s->surfaces[p->surface].capsule;
    const ray__instance *in = w->in;
    ray_vec3 a = world(w, k->a), b = world(w, k->b), pt, n;
    double e[3];
    int i, inside;

    if (in == NULL || in->similarity > 0) {
        double R = k->radius * (in != NULL ? in->similarity : 1);
        if (w->q.is_box)
            return ray__pped_segment(&w->q.box, a, b) <= R;
        if (w->q.is_capsule) {
            ray_vec3 ps, pk;
            ray__segments_closest(w->q.c, w->q.c2, a, b, &ps, &pk);
            return ray__distance(ps, pk) <= R + w->q.r;
        }
        return ray__distance(ray__segment_closest(w->q.c, a, b), w->q.c) <=
               R + w->q.r;
    }
    if (!(in->sv[0] > 0))
        return 0;
    if (w->q.is_capsule)     /* a swept ellipsoid: its box (ray.h) */
        return by_bounds(w, s, p);
    if (w->q.is_box) {
        /* In the capsule's own space, where it is a capsule. */
        ray__pped q = box_in_object(in, &w->q.box, 1, v3(0, 0, 0));
        return ray__pped_segment(&q, k->a, k->b) <= k->radius;
    }
    for (i = 0; i < 3; i++)
        e[i] = k->radius * in->sv[i];
    if (!ray__ellipsoid_sweep_closest(a, v3_sub(b, a),
                                      (const double(*)[3])in->axes, e,
                                      w->q.c, &pt, &n, &inside))
        return 0;
    return inside || ray__distance(pt, w->q.c) <= w->q.r;
}

static unsigned meets_TORUS(const searcher *w, const ray_scene *s,
                            const ray__prim *p)
{
    return by_bounds(w, s, p);
}

static unsigned meets_IMPLICIT(const searcher *w, const ray_scene *s,
                               const ray__prim *p)
{
    return by_bounds(w, s, p);
}

static unsigned meets_PARAMETRIC(const searcher *w, const ray_scene *s,
                                 const ray__prim *p)
{
    return by_bounds(w, s, p);
}

static unsigned meets_BEZIER(const searcher *w, const ray_scene *s,
                             const ray__prim *p)
{
    return by_bounds(w, s, p);
}

static unsigned meets_USER(const searcher *w, const ray_scene *s,
                           const ray__prim *p)
{
    return by_bounds(w, s, p);
}

/* Instances are descended into by visit_prim: never asked here. */
static unsigned meets_INSTANCE(const searcher *w, const ray_scene *s,
                               const ray__prim *p)
{
    (void)w, (void)s, (void)p;
    return 0;
}

static unsigned prim_meets(const searcher *w, const ray_scene *s,
                           const ray__prim *p)
{
    switch (p->kind) {
#define MEETS_OF(name, counted_as, class)                                  \
    case RAY__KIND_##name:                                                 \
        return meets_##name(w, s, p);
        RAY__PRIM_KINDS(MEETS_OF)
#undef MEETS_OF
    }
    return 0;                       /* not a ray__kind: cannot happen */
}

/* ---------------------------------------------------------- visiting */

/*
** The region's box in the space of the scene searched: in the world, the
** sphere's or the box's; in an instance's child, the box of the
** region's image (an ellipsoid: centre L^-1 (c - t) +- r |row i of
** L^-1|; a parallelepiped: centre +- sum |L^-1 e_k|), grown by 2^-40 of
** its size for the map's rounding (a few ulps).
*/
static void region_box(searcher *w)
{
    double h[3];
    ray_vec3 c;
    int i, k;

    if (w->q.is_capsule) {
        /* The segment's ends (in that space) +- the ball's reach. */
        ray_vec3 a = w->q.c, b = w->q.c2;
        if (w->in != NULL) {
            a = ray__instance_point_to_object(w->in, a);
            b = ray__instance_point_to_object(w->in, b);
        }
        c = v3_scale(v3_add(a, b), 0.5);
        for (i = 0; i < 3; i++)
            h[i] = 0.5 * fabs(v3_axis(b, i) - v3_axis(a, i)) +
                   (w->in == NULL
                        ? w->q.r
                        : w->q.r * v3_length(v3(w->in->inv[i][0],
                                                w->in->inv[i][1],
                                                w->in->inv[i][2])));
    } else if (w->in == NULL) {
        c = w->q.is_box ? w->q.box.c : w->q.c;
        for (i = 0; i < 3; i++)
            h[i] = w->q.r;
        if (w->q.is_box)
            for (i = 0; i < 3; i++) {
                h[i] = 0;
                for (k = 0; k < 3; k++)
                    h[i] += fabs(v3_axis(w->q.box.e[k], i));
            }
    } else if (w->q.is_box) {
        ray__pped b = box_in_object(w->in, &w->q.box, 1, v3(0, 0, 0));
        c = b.c;
        for (i = 0; i < 3; i++) {
            h[i] = 0;
            for (k = 0; k < 3; k++)
                h[i] += fabs(v3_axis(b.e[k], i));
        }
    } else {
        c = ray__instance_point_to_object(w->in, w->q.c);
        for (i = 0; i < 3; i++)
            h[i] = w->q.r * v3_length(v3(w->in->inv[i][0], w->in->inv[i][1],
                                         w->in->inv[i][2]));
    }
    for (i = 0; i < 3; i++)
        h[i] += 0x1p-40 * (h[i] + fabs(v3_axis(c, i)));
    w->lo = v3(c.x - h[0], c.y - h[1], c.z - h[2]);
    w->hi = v3(c.x + h[0], c.y + h[1], c.z + h[2]);
}

/* Does node slot k's float box meet the region's box? */
static int box_meets(const searcher *w, const ray__wnode *n, int k)
{
    return (double)n->lo[0][k] <= w->hi.x && (double)n->hi[0][k] >= w->lo.x &&
           (double)n->lo[1][k] <= w->hi.y && (double)n->hi[1][k] >= w->lo.y &&
           (double)n->lo[2][k] <= w->hi.z && (double)n->hi[2][k] >= w->lo.z;
}

static void search_in(searcher *w, const ray_scene *s);

static void visit_instance(searcher *w, const ray_scene *s, unsigned i)
{
    const ray__instance *in = &s->instances[s->prims[i].surface];
    ray_vec3 lo = w->lo, hi = w->hi;

    w->in = in;
    w->in_id = i;
    region_box(w);
    if (v3_isfinite(w->lo) && v3_isfinite(w->hi))
        search_in(w, in->child);
    w->in = NULL;
    w->in_id = RAY_INVALID_ID;
    w->lo = lo;
    w->hi = hi;
}

static int hidden(const searcher *w, const ray__prim *p)
{
    return w->gate != NULL && (p->mask & w->gate->mask) == 0;
}

static void visit_prim(searcher *w, const ray_scene *s, unsigned i)
{
    const ray__prim *p = &s->prims[i];
    unsigned m;

    if (hidden(w, p))
        return;
    if (p->kind == RAY__KIND_INSTANCE) {
        visit_instance(w, s, i);
        return;
    }
    if ((m = prim_meets(w, s, p)) != 0)
        report(w, i, 0, m & RAY_CONTACT_BOUNDS);
}

static void visit_triangle(searcher *w, const ray_scene *s, unsigned i)
{
    const ray__tri_id *id = &s->tri_ids[i];
    ray_vec3 a, b, c;
    int meets;

    if (hidden(w, &s->prims[id->geom_id]))
        return;
    ray__tri_corners(s, i, &a, &b, &c);
    /* A triangle without a normal (zero area, read as the point at its
    ** first corner: scene.h) is no surface, as for the rays and
    ** ray_closest_point (issue 38, defect 5). */
    if (!ray__corners_usable(a, b, c))
        return;
    a = world(w, a);
    b = world(w, b);
    c = world(w, c);
    if (w->q.is_box)
        meets = ray__pped_overlaps_triangle(&w->q.box, a, b, c);
    else if (w->q.is_capsule) {
        ray_vec3 ps, pt;
        ray__segment_triangle_closest(w->q.c, w->q.c2, a, b, c, &ps, &pt);
        meets = ray__distance(ps, pt) <= w->q.r;
    } else
        meets = ray__distance(ray__triangle_closest(a, b, c, w->q.c),
                              w->q.c) <= w->q.r;
    if (meets)
        report(w, id->geom_id, id->prim_id, 0);
}

enum { LEAF_TRIANGLES, LEAF_PRIMS };

/* Every node whose box meets the region's (a stack of them: at most
** RAY__WIDTH pushed and one popped a level, 64 levels). */
static void walk(searcher *w, const ray_scene *s, const ray__bvh *bvh,
                 int leaf)
{
    unsigned stack[RAY__WIDTH * 64][2];
    int sp = 0, k;

    if (bvh->n_wide == 0)
        return;
    stack[sp][0] = 0;
    stack[sp++][1] = 0;
    while (sp > 0 && !w->found->stop) {
        unsigned child = stack[--sp][0], count = stack[sp][1];
        if (count == 0) {
            const ray__wnode *n = &bvh->wide[child];
            for (k = 0; k < RAY__WIDTH; k++)
                if (n->count[k] != RAY__LEAF && box_meets(w, n, k)) {
                    stack[sp][0] = n->child[k];
                    stack[sp++][1] = n->count[k];
                }
        } else {
            unsigned i, end = child + (count & ~RAY__LEAF);
            for (i = child; i < end && !w->found->stop; i++) {
                if (leaf == LEAF_TRIANGLES)
                    visit_triangle(w, s, i);
                else
                    visit_prim(w, s, bvh->items[i]);
            }
        }
    }
}

static void search_in(searcher *w, const ray_scene *s)
{
    size_t i;

    for (i = 0; i < s->n_planes && !w->found->stop; i++)
        visit_prim(w, s, s->planes[i]);
    walk(w, s, &s->prim_bvh, LEAF_PRIMS);
    walk(w, s, &s->tri_bvh, LEAF_TRIANGLES);
}

/* -------------------------------------------------------------- API */

/* Insertion sort by ids (the kept ones are few). */
static void sort_found(ray_overlap *o, size_t n)
{
    size_t i, j;

    for (i = 1; i < n; i++) {
        ray_overlap x = o[i];
        for (j = i; j > 0 && id_before(&x, &o[j - 1]); j--)
            o[j] = o[j - 1];
        o[j] = x;
    }
}

/* The search itself, its arguments checked but the scene's state. */
static int overlap_run(const ray_scene *s, const region *q,
                       const ray_query *opt, found_list *f)
{
    ray__gate g;
    searcher w;

    if (!s->committed)
        return -RAY_ESTATE;
    if (ray__scene_stale(s))
        return -RAY_ESTATE;
    g.mask = opt != NULL ? ~opt->ignore_mask : ~0u;
    g.query_ud = opt != NULL ? opt->query_ud : NULL;
    g.query = 0;
    g.all = NULL;
    w.q = *q;
    /* As the ray queries' gate_of (intersect.c): no gate only where the
    ** scene has no mask to read (s->gated, which covers the instances'
    ** children); with the default all-bits mask a geometry of mask 0 is
    ** still hidden (issue 38, defect 2). */
    w.gate = !s->gated && g.mask == ~0u ? NULL : &g;
    w.found = f;
    w.in = NULL;
    w.in_id = RAY_INVALID_ID;
    region_box(&w);
    search_in(&w, s);
    return f->count > (size_t)0x7fffffff ? 0x7fffffff : (int)f->count;
}

/* The shape's region: 0 for a shape the queries refuse (ray.h,
** ray__shape_check).  A capsule with a == b is the sphere. */
static int shape_region(const ray_shape *k, region *q)
{
    if (!ray__shape_check(k, &q->box))
        return 0;
    q->is_box = k->kind == RAY_SHAPE_BOX;
    q->is_capsule = !q->is_box && (k->a.x != k->b.x || k->a.y != k->b.y ||
                                   k->a.z != k->b.z);
    q->c = q->is_box ? k->box.center : k->a;
    q->c2 = q->is_box ? q->c : k->b;
    q->r = q->is_box ? 0 : k->radius;
    return 1;
}

static int run_fn(const ray_scene *s, const region *q, const ray_query *opt,
                  ray_overlap_fn fn, void *ud)
{
    found_list f;

    f.fn = fn;
    f.ud = ud;
    f.out = NULL;
    f.cap = f.count = 0;
    f.stop = 0;
    return overlap_run(s, q, opt, &f);
}

static int run_all(const ray_scene *s, const region *q, const ray_query *opt,
                   ray_overlap *out, size_t cap, size_t *count)
{
    found_list f;
    int rc;

    f.fn = NULL;
    f.ud = NULL;
    f.out = out;
    f.cap = cap;
    f.count = 0;
    f.stop = 0;
    rc = overlap_run(s, q, opt, &f);
    if (rc < 0)
        return rc;
    sort_found(out, f.count < cap ? f.count : cap);
    *count = f.count;
    return rc;
}

/*
** Why an overlap (op) refused with rc (ray.h, ray_query.why): the checks
** below again, in their order, on the refusal path only; "out" is the
** output argument's reason when the scene and shape passed.
*/
static int overlap_refused(const ray_query *q, const char *op, int rc,
                           const ray_scene *s, const ray_shape *shape,
                           const char *out)
{
    char shape_why[256];

    if (q == NULL || q->why == NULL)
        return rc;
    if (s == NULL)
        return ray__why(q->why, q->why_size, rc, op, "scene is NULL");
    if (rc == -RAY_ESTATE)
        return ray__why_state(q->why, q->why_size, rc, op, s);
    if (out != NULL)
        return ray__why(q->why, q->why_size, rc, op, "%s", out);
    ray__shape_why(shape, "shape->", shape_why, sizeof shape_why);
    return ray__why(q->why, q->why_size, rc, op, "%s", shape_why);
}

int ray_overlap_shape(const ray_scene *s, const ray_shape *shape,
                      const ray_query *q, ray_overlap_fn fn, void *ud)
{
    region r;
    int rc;

    if (s == NULL || fn == NULL || !shape_region(shape, &r))
        return overlap_refused(q, "ray_overlap_shape", -RAY_EINVAL, s, shape,
                               s != NULL && fn == NULL ? "fn is NULL"
                                                       : NULL);
    rc = run_fn(s, &r, q, fn, ud);
    return rc >= 0 ? rc : overlap_refused(q, "ray_overlap_shape", rc, s,
                                          shape, NULL);
}

int ray_overlap_shape_all(const ray_scene *s, const ray_shape *shape,
                          const ray_query *q, ray_overlap *found, size_t cap,
                          size_t *count)
{
    region r;
    char out[64];
    int rc;

    if (s == NULL || count == NULL || (found == NULL && cap > 0) ||
        !shape_region(shape, &r)) {
        if (count == NULL)
            snprintf(out, sizeof out, "count is NULL");
        else if (found == NULL && cap > 0)
            snprintf(out, sizeof out, "found is NULL with cap = %zu", cap);
        return overlap_refused(q, "ray_overlap_shape_all", -RAY_EINVAL, s,
                               shape, count == NULL ||
                               (found == NULL && cap > 0) ? out : NULL);
    }
    rc = run_all(s, &r, q, found, cap, count);
    return rc >= 0 ? rc : overlap_refused(q, "ray_overlap_shape_all", rc, s,
                                          shape, NULL);
}
