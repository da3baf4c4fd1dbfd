/* SPDX-License-Identifier: MIT */
/*
** contains.c -- ray_contains and ray_signed_distance: whether a point is
** inside the solid a committed scene bounds, and its signed distance.
**
** Closed meshes (closed.c) by the parity of the crossings of the ray
** from q along +x, every crossing decided by exact predicates with the
** ray perturbed symbolically, and most points answered by a grid of
** labels instead: scene/parity.c, which says why both are exact.
**
** Open meshes and single triangles by the generalized winding number
** (Jacobson, Kavan and Sorkine-Hornung, "Robust Inside-Outside
** Segmentation using Generalized Winding Numbers", SIGGRAPH 2013): the
** sum over their triangles of the signed solid angle, by Van Oosterom
** and Strackee's formula ("The Solid Angle of a Plane Triangle", IEEE
** Trans. Biomed. Eng. 30(2), 1983), over 4 pi; its determinant's sign
** is the exact one, so a point an ulp off a face gets the side it is
** on.  Through the BVH with Barill et al.'s far-field expansion ("Fast
** Winding Numbers for Soups and Clouds", 2018: winding.c), or summed
** over every triangle (RAY_CONTAINS_WINDING_EXACT: the caller asks for
** the number itself, within 1e-9; a mask that leaves some of the
** triangles out; or no expansions); a point whose fast
** winding number lies within WINDING_MARGIN of 1/2 is summed again
** exactly, so that the expansion's error never decides its side.
*/
#include <limits.h>
#include <string.h>

#include "core/predicates.h"
#include "query/query.h"
#include "query/why.h"

/* A fast winding number this near 1/2 is summed again over every
** triangle before it decides inside or outside: the expansion's error
** (order 2, beta 2) stayed below 3.5e-2 wherever measured (the soups,
** holes, cracks and instances of tests/check_contains.c, whose FAST_TOL
** says where; 2.4e-2 on the 59k bunny at 2000 uniform points,
** bench/contains.c), and ray.h documents 5e-2: a margin of four times
** that leaves no point whose side the expansion decides wrongly there,
** while points this near 1/2 are few (a hole's rim, the surface itself,
** a soup's folds). */
#define WINDING_MARGIN 0.2

/* The flags ray_contains knows. */
#define KNOWN_FLAGS (RAY_CONTAINS_WINDING | RAY_CONTAINS_WINDING_EXACT)

/* A query's state, for one point and scene (the top one, or an
** instance's child, searched with q in its space). */
typedef struct cquery {
    ray_vec3 q;                  /* in the space of the scene searched */
    ray_vec3 qw;                 /* in world space */
    const ray__instance *in;     /* the instance searched through */
    unsigned ignore;             /* options->ignore_mask: the query's
                                    mask is ~ignore */
    int winding_all;             /* RAY_CONTAINS_WINDING */
    int exact;                   /* RAY_CONTAINS_WINDING_EXACT */
    int fast;                    /* some angles came from expansions */
    int parity_only;             /* open triangles not summed: only the
                                    solids and closed meshes
                                    (ray__solid_holds) */
    unsigned parity;             /* crossings and solids, mod 2 */
    int on;                      /* exactly on a closed mesh */
    int stale;                   /* met an instance changed since */
    double angle;                /* sum of signed solid angles */
} cquery;

/* ------------------------------------------------------------ the scene */

static int counted(const cquery *cq, const ray__prim *p)
{
    return p->enabled && !p->removed && (p->mask & ~cq->ignore) != 0;
}

static void search_in(const ray_scene *s, cquery *cq);

/* The instance of prim p: its child searched with q in its space, the
** child's parity added to ours (parity needs no particular ray: the
** child's +x is as good as any); its open triangles' angles measured in
** world space. */
static void visit_instance(const ray_scene *s, const ray__prim *p,
                           cquery *cq)
{
    const ray__instance *in = &s->instances[p->surface];
    cquery child = *cq;

    (void)s;
    if (!in->child->committed || in->child->generation != in->generation) {
        cq->stale = 1;
        return;
    }
    child.q = ray__instance_point_to_object(in, cq->qw);
    if (!v3_isfinite(child.q))
        return;
    child.in = in;
    child.parity = 0;
    child.angle = 0;
    search_in(in->child, &child);
    cq->stale |= child.stale;
    cq->fast |= child.fast;
    cq->on |= child.on;
    cq->parity ^= child.parity;
    cq->angle += child.angle;
}

/* A solid primitive holding q (closed: its boundary included, to the
** rounding of the tests) flips the parity.  Instances are searched
** separately (search_in), as their open meshes count from afar. */
static void visit_solid(const ray_scene *s, const ray__prim *p, cquery *cq)
{
    ray_vec3 q = cq->q;

    if (p->kind == RAY__KIND_SPHERE) {
        ray_vec3 d = v3_sub(q, p->a);
        if (v3_dot(d, d) <= p->radius * p->radius)
            cq->parity ^= 1u;
    } else if (p->kind == RAY__KIND_BOX) {
        const ray_box_params *b = &s->surfaces[p->surface].box;
        ray_vec3 e[3], d = v3_sub(q, b->center);
        if (ray__box_frame(b, e) &&
            fabs(v3_dot(d, e[0])) <= b->half_extents.x &&
            fabs(v3_dot(d, e[1])) <= b->half_extents.y &&
            fabs(v3_dot(d, e[2])) <= b->half_extents.z)
            cq->parity ^= 1u;
    } else if (p->kind == RAY__KIND_CAPSULE) {
        const ray_capsule_params *c = &s->surfaces[p->surface].capsule;
        if (ray__distance(q, ray__segment_closest(q, c->a, c->b)) <=
            c->radius)
            cq->parity ^= 1u;
    }
}

/* The boxes the ray from q along +x enters (which include every box
** holding q): y and z within, the box not wholly behind.  The float
** boxes contain their geometry (rounded outward at commit), and the
** comparisons are exact in double; an unused slot (lo +Inf, hi -Inf)
** fails them.  (The closed meshes' triangles: scene/parity.c.) */
static int box_on_ray(const ray__wnode *w, int k, ray_vec3 q)
{
    return (double)w->hi[0][k] >= q.x && (double)w->lo[1][k] <= q.y &&
           (double)w->hi[1][k] >= q.y && (double)w->lo[2][k] <= q.z &&
           (double)w->hi[2][k] >= q.z;
}

/* Every solid primitive of the BVH over the bounded kinds on the ray,
** depth first.  At most RAY__WIDTH pushed and one popped a level, 64
** levels at most (accel/build.h). */
static void walk_solids(const ray_scene *s, cquery *cq)
{
    const ray__bvh *bvh = &s->prim_bvh;
    unsigned stack_child[RAY__WIDTH * 64], stack_count[RAY__WIDTH * 64];
    unsigned child = 0, count = 0;
    int sp = 0;

    if (bvh->n_wide == 0)
        return;
    for (;;) {
        if (count == 0) {
            const ray__wnode *w = &bvh->wide[child];
            int k;
            for (k = 0; k < RAY__WIDTH; k++) {
                if (w->count[k] == RAY__LEAF || !box_on_ray(w, k, cq->q))
                    continue;
                stack_child[sp] = w->child[k];
                stack_count[sp] = w->count[k];
                sp++;
            }
        } else {
            unsigned i, end = child + (count & ~RAY__LEAF);
            for (i = child; i < end; i++) {
                const ray__prim *p = &s->prims[bvh->items[i]];
                if (counted(cq, p))
                    visit_solid(s, p, cq);
            }
        }
        if (sp == 0)
            return;
        sp--;
        child = stack_child[sp];
        count = stack_count[sp];
    }
}

/* Whether s has counted triangles answered by the winding number,
** whether some enabled ones of theirs are left out by the mask (hidden:
** then the expansions, which hold them all, do not apply), whether it
** has counted instances, and whether every enabled closed mesh is
** counted (so that the grid's labels apply, scene/parity.c): a scan of
** its geometry records, not its triangles. */
static void kinds_in(const ray_scene *s, const cquery *cq, int *open,
                     int *hidden, int *instances, int *all_closed)
{
    size_t i;

    *open = *hidden = *instances = 0;
    *all_closed = 1;
    for (i = 0; i < s->n_prims; i++) {
        const ray__prim *p = &s->prims[i];
        if (!counted(cq, p)) {
            int closed = p->kind == RAY__KIND_MESH && s->meshes[p->mesh].closed;
            if (!p->enabled || p->removed)
                continue;
            if (closed)
                *all_closed = 0;
            if (p->kind == RAY__KIND_TRIANGLE ||
                (p->kind == RAY__KIND_MESH && (cq->winding_all || !closed)))
                *hidden = 1;
            continue;
        }
        if (p->kind == RAY__KIND_INSTANCE)
            *instances = 1;
        else if (p->kind == RAY__KIND_TRIANGLE ||
                 (p->kind == RAY__KIND_MESH &&
                  (cq->winding_all || !s->meshes[p->mesh].closed)))
            *open = 1;
    }
}

/* Scene s for one point: its solids and closed meshes along the ray,
** its open triangles' angles (only where it has some: a closed mesh's
** point costs its ray's walk alone), its instances. */
static void search_in(const ray_scene *s, cquery *cq)
{
    size_t i;
    int open, hidden, instances, all_closed;

    kinds_in(s, cq, &open, &hidden, &instances, &all_closed);
    walk_solids(s, cq);
    if (!cq->winding_all) {
        unsigned parity;
        int on;
        /* The grid's labels serve ray_contains (an instance's child: its
        ** grid ensured here; the top scene's once a call, in
        ** ray_contains); ray__solid_holds walks the rays and leaves the
        ** grid unbuilt and unread. */
        int grid = all_closed && !cq->parity_only;
        if (grid && cq->in != NULL)
            ray__cgrid_ensure(s);
        ray__closed_parity(s, cq->q, cq->ignore, grid, &parity, &on);
        cq->on |= on;
        cq->parity ^= parity;
    }
    if (open && !cq->parity_only) {
        double a;
        if (!cq->exact && !hidden &&
            ray__winding_fast(s, cq->qw, cq->in, cq->winding_all, &a)) {
            cq->angle += a;
            cq->fast = 1;
        } else {
            cq->angle += ray__winding_exact(s, cq->qw, cq->in, cq->ignore,
                                            cq->winding_all);
        }
    }
    for (i = 0; instances && i < s->n_prims; i++) {
        const ray__prim *p = &s->prims[i];
        if (p->kind == RAY__KIND_INSTANCE && counted(cq, p))
            visit_instance(s, p, cq);
    }
}

/* Whether s (its instances' children included) holds anything answered
** exactly: a closed mesh or a solid primitive. */
static int has_exact(const ray_scene *s, unsigned ignore)
{
    size_t i;

    for (i = 0; i < s->n_prims; i++) {
        const ray__prim *p = &s->prims[i];
        if (!p->enabled || p->removed || (p->mask & ~ignore) == 0)
            continue;
        if ((p->kind == RAY__KIND_MESH && s->meshes[p->mesh].closed) ||
            p->kind == RAY__KIND_SPHERE || p->kind == RAY__KIND_BOX ||
            p->kind == RAY__KIND_CAPSULE)
            return 1;
        if (p->kind == RAY__KIND_INSTANCE &&
            has_exact(s->instances[p->surface].child, ignore))
            return 1;
    }
    return 0;
}

/* A query's state for point q of the top scene, nothing counted yet. */
static void cquery_start(cquery *cq, ray_vec3 q, unsigned ignore,
                         unsigned flags, int parity_only)
{
    cq->q = cq->qw = q;
    cq->in = NULL;
    cq->ignore = ignore;
    cq->winding_all = (flags & RAY_CONTAINS_WINDING) != 0;
    cq->exact = (flags & RAY_CONTAINS_WINDING_EXACT) != 0;
    cq->fast = 0;
    cq->parity_only = parity_only;
    cq->parity = 0;
    cq->on = 0;
    cq->stale = 0;
    cq->angle = 0;
}

/* One point's answer: 1 inside (on the surface included), 0 outside, or
** -RAY_ESTATE. */
static int contains_one(const ray_scene *s, ray_vec3 q, unsigned ignore,
                        unsigned flags, ray_inside *out)
{
    cquery cq;
    double w;

    cquery_start(&cq, q, ignore, flags, 0);
    search_in(s, &cq);
    if (cq.stale)
        return -RAY_ESTATE;
    w = cq.angle / (4 * RAY__PI);
    if (cq.fast && fabs(w - 0.5) < WINDING_MARGIN) {
        /* Near 1/2: the exact sum decides (WINDING_MARGIN). */
        cquery_start(&cq, q, ignore, flags | RAY_CONTAINS_WINDING_EXACT, 0);
        search_in(s, &cq);
        if (cq.stale)
            return -RAY_ESTATE;
        w = cq.angle / (4 * RAY__PI);
    }
    out->on_surface = cq.on;
    out->winding = w;
    /* Parity and winding combine as crossings do: a point inside an
    ** open surface (w > 1/2) and a closed one is inside neither. */
    out->inside = cq.on || ((cq.parity & 1u) != 0) != (w > 0.5);
    return out->inside;
}

/*
** ray__solid_holds -- whether q lies in a solid of s (ray_render_check's
** eye test): ray_contains's exact parity over the spheres, boxes,
** capsules and closed meshes, through instances, the boundary included,
** every enabled geometry of a non-zero mask counted.  Open meshes and
** triangles are left out rather than answered by the winding number: a
** hole lets the eye see out, so they bound no solid it can be shut in,
** and their O(triangles) sum would cost more than the whole check.  0
** for a scene with an instance changed since its commit (the caller has
** refused those), and when memory runs out finding which meshes are
** closed (a warning the check then leaves out).
*/
int ray__solid_holds(const ray_scene *s, ray_vec3 q)
{
    cquery cq;

    if (ray__closed_ensure(s) != RAY_OK)
        return 0;           /* out of memory: no closed mesh to be in */
    cquery_start(&cq, q, 0, 0u, 1);
    search_in(s, &cq);
    return !cq.stale && (cq.on || (cq.parity & 1u) != 0);
}

/*
** Why ray_contains (or ray_signed_distance: op) refused with rc (ray.h,
** ray_contains_options.why): contains_run's checks again, in their
** order, on the refusal path only.
*/
static int contains_refused(const ray_contains_options *o, const char *op,
                            int rc, const ray_scene *s,
                            const ray_vec3 *points, size_t n)
{
    char *why = o != NULL ? o->why : NULL;
    size_t size = o != NULL ? o->why_size : 0;
    size_t i;

    if (why == NULL)
        return rc;
    if (s == NULL)
        return ray__why(why, size, rc, op, "scene is NULL");
    if (points == NULL && n > 0)
        return ray__why(why, size, rc, op, "points is NULL with n = %zu", n);
    if (n > INT_MAX)
        return ray__why(why, size, rc, op, "n is %zu: more than INT_MAX", n);
    if ((o->flags & ~KNOWN_FLAGS) != 0)
        return ray__why(why, size, rc, op, "options->flags 0x%x has unknown "
                        "bits 0x%x", o->flags, o->flags & ~KNOWN_FLAGS);
    for (i = 0; i < n; i++) {
        if (v3_isfinite(points[i]))
            continue;
        if (strcmp(op, "ray_signed_distance") == 0)     /* its q */
            return ray__why(why, size, rc, op, "q " RAY__WHY_V3 " is not "
                            "finite", RAY__WHY_V3ARGS(points[i]));
        return ray__why(why, size, rc, op, "points[%zu] " RAY__WHY_V3
                        " is not finite", i, RAY__WHY_V3ARGS(points[i]));
    }
    if (rc == -RAY_ENOMEM)
        return ray__why(why, size, rc, op, "out of memory finding which "
                        "meshes are closed or the winding number's "
                        "expansions (a later call tries again)");
    if (rc == -RAY_EDEGENERATE)
        return ray__why(why, size, rc, op, "no closed mesh, sphere, box or "
                        "capsule that options->ignore_mask 0x%x leaves seen "
                        "answers exactly: ask for RAY_CONTAINS_WINDING",
                        o->ignore_mask);
    return ray__why_state(why, size, rc, op, s);
}

int ray__contains_run(const ray_scene *s, const ray_vec3 *points,
                        size_t n, const ray_contains_options *o,
                        ray_inside *out, const char *op)
{
    unsigned flags = o != NULL ? o->flags : 0;
    unsigned ignore = o != NULL ? o->ignore_mask : 0;
    size_t i;
    int inside = 0;

    if (s == NULL || (points == NULL && n > 0) || n > INT_MAX ||
        (flags & ~KNOWN_FLAGS) != 0)
        return contains_refused(o, op, -RAY_EINVAL, s, points, n);
    for (i = 0; i < n; i++)
        if (!v3_isfinite(points[i]))
            return contains_refused(o, op, -RAY_EINVAL, s, points, n);
    if (!s->committed)
        return contains_refused(o, op, -RAY_ESTATE, s, points, n);
    if (ray__closed_ensure(s) != RAY_OK)
        return contains_refused(o, op, -RAY_ENOMEM, s, points, n);
    if ((flags & RAY_CONTAINS_WINDING) == 0 && !has_exact(s, ignore))
        return contains_refused(o, op, -RAY_EDEGENERATE, s, points, n);

    /* Instances first, as ray_intersect_all: a stale one fails the call
    ** before anything is written. */
    for (i = 0; i < s->n_prims; i++) {
        const ray__prim *p = &s->prims[i];
        const ray__instance *in;
        if (p->kind != RAY__KIND_INSTANCE || !p->enabled || p->removed)
            continue;
        in = &s->instances[p->surface];
        if (!in->child->committed || in->child->generation != in->generation)
            return contains_refused(o, op, -RAY_ESTATE, s, points, n);
    }
    /* The expansions of the winding number: made once (winding.c), once
    ** no instance is stale (its child's triangles are then as committed). */
    if ((flags & RAY_CONTAINS_WINDING_EXACT) == 0 &&
        ray__wexp_ensure(s, (flags & RAY_CONTAINS_WINDING) != 0) != RAY_OK)
        return contains_refused(o, op, -RAY_ENOMEM, s, points, n);
    if ((flags & RAY_CONTAINS_WINDING) == 0)
        ray__cgrid_ensure(s);
    for (i = 0; i < n; i++) {
        ray_inside r;
        int rc = contains_one(s, points[i], ignore, flags, &r);
        if (rc < 0)
            return contains_refused(o, op, rc, s, points, n);
        inside += rc;
        if (out != NULL) {
            out[i].inside = r.inside;
            out[i].on_surface = r.on_surface;
            out[i].winding = r.winding;
        }
    }
    return inside;
}

int ray_contains(const ray_scene *s, const ray_vec3 *points, size_t n,
                 const ray_contains_options *o, ray_inside *out)
{
    return ray__contains_run(s, points, n, o, out, "ray_contains");
}

/* *distance (and *closest, when not NULL) from q's containment *in and
** its closest-point search's answer within radius: found (1 with *c, or
** 0): ray_signed_distance's rule. */
static void signed_answer(const ray_inside *in, int found,
                          const ray_closest *c, double radius,
                          double *distance, ray_closest *closest)
{
    if (found) {
        *distance = in->on_surface ? 0.0 : in->inside ? -c->distance
                                                      : c->distance;
        if (closest != NULL)
            *closest = *c;
    } else {
        /* On the surface is distance 0 even where no closest point is
        ** found: a closed mesh's triangle of no area holds q, and
        ** ray_closest_point skips such triangles. */
        *distance = in->on_surface ? 0.0 : in->inside ? -radius : radius;
    }
}

int ray_signed_distance(const ray_scene *s, ray_vec3 q, double radius,
                        const ray_contains_options *o, double *distance,
                        ray_closest *closest)
{
    static const char op[] = "ray_signed_distance";
    ray_closest c;
    ray_inside in;
    int rc, found;

    if (distance == NULL)
        return o == NULL ? -RAY_EINVAL
                         : ray__why(o->why, o->why_size, -RAY_EINVAL, op,
                                    "distance is NULL");
    rc = ray__contains_run(s, &q, 1, o, &in, op);
    if (rc < 0)
        return rc;
    found = ray_closest_point(s, q, radius, &c);
    if (found < 0)          /* q and the scene passed: the radius */
        return o == NULL ? found
                         : ray__why(o->why, o->why_size, found, op,
                                    "radius is %.17g: NaN or negative",
                                    radius);
    signed_answer(&in, found, &c, radius, distance, closest);
    return found;
}

int ray__signed_distance_at(const ray_scene *s, ray_vec3 q, double radius,
                            const ray_contains_options *o, double *distance,
                            ray_closest *closest)
{
    ray_closest c;
    ray_inside in;
    int rc, found;

    rc = contains_one(s, q, o != NULL ? o->ignore_mask : 0,
                      o != NULL ? o->flags : 0, &in);
    if (rc < 0)
        return rc;
    found = ray_closest_point(s, q, radius, &c);
    if (found < 0)
        return found;
    signed_answer(&in, found, &c, radius, distance, closest);
    return found;
}
