/*
** intersect.c -- nearest-hit and any-hit queries over a committed scene:
** the planes one by one, then two BVHs, one over the triangles (stored in
** leaf order) and one over spheres and polygons.  Each hit shrinks tmax,
** so every later box and primitive is tested against the nearest so far.
*/
#include "internal.h"

/*
** The slab test is made in double on float boxes that were rounded
** outward, with tfar grown by 1 + 2 gamma(3): the three roundings of
** (b - o) * (1/d) can make the computed [tnear, tfar] miss a box the ray
** enters by a hair, and this bound closes that gap (Ize, "Robust BVH Ray
** Traversal", JCGT 2(2), 2013; pbrt-v4 Bounds3::IntersectP).
**
** A zero direction component makes 1/d = +-Inf (IEEE), so the slab is
** [-Inf, +Inf] when the origin is strictly inside it and empty otherwise
** (Williams et al., "An Efficient and Robust Ray-Box Intersection
** Algorithm", JGT 10(1), 2005).  An origin exactly on that slab's plane
** gives 0 * Inf = NaN; the max/min below are written so a NaN operand is
** ignored, i.e. the ray is kept: conservative.
*/
typedef struct trav {
    double o[3], inv[3];
    int near[3];             /* 0: lo is the near plane on that axis */
    double grow;             /* 1 + 2 gamma(3) */
} trav;

static void trav_init(trav *tr, const ray_ray *r)
{
    double d[3];
    int k;

    d[0] = r->dir.x;
    d[1] = r->dir.y;
    d[2] = r->dir.z;
    tr->o[0] = r->org.x;
    tr->o[1] = r->org.y;
    tr->o[2] = r->org.z;
    for (k = 0; k < 3; k++) {
        tr->inv[k] = 1.0 / d[k];
        tr->near[k] = tr->inv[k] < 0 || (tr->inv[k] == 0 && signbit(d[k]));
    }
    tr->grow = 1 + 2 * ray__gamma(3);
}

/* Does the ray meet node n's box within (tmin, tmax)?  *entry: where. */
static int box_hit(const ray__node *n, const trav *tr, double tmin,
                   double tmax, double *entry)
{
    const float *b = n->lo;                 /* lo[3], hi[3] contiguous */
    double t0 = tmin, t1 = tmax;
    int k;

    for (k = 0; k < 3; k++) {
        double tn = ((double)b[3 * tr->near[k] + k] - tr->o[k]) * tr->inv[k];
        double tf = ((double)b[3 * (1 - tr->near[k]) + k] - tr->o[k]) *
                    tr->inv[k] * tr->grow;
        t0 = tn > t0 ? tn : t0;             /* NaN tn: ignored */
        t1 = tf < t1 ? tf : t1;             /* NaN tf: ignored */
    }
    *entry = t0;
    return t0 <= t1;
}

/* Does the ray hit item "i" of the BVH being traversed (shrinking
** r->tmax on a nearest-hit query)? */
typedef int (*leaf_test)(const ray_scene *s, unsigned i, ray_ray *r,
                         void *best);

/*
** Ordered traversal: of two children hit, the nearer is visited first and
** the farther pushed with its entry distance, and popped only if still in
** front of the nearest hit found since.  "any": stop at the first hit.
*/
static int traverse(const ray_scene *s, const ray__bvh *bvh, ray_ray *r,
                    leaf_test test, void *best, int any,
                    unsigned long long *tests)
{
    unsigned stack[64], ni = 0;
    double stack_t[64], entry;
    unsigned long long n_tests = 0;
    int sp = 0, found = 0;
    trav tr;

    if (bvh->n_nodes == 0)
        return 0;
    trav_init(&tr, r);
    if (!box_hit(&bvh->nodes[0], &tr, r->tmin, r->tmax, &entry))
        return 0;
    for (;;) {
        const ray__node *n = &bvh->nodes[ni];
        if (n->count > 0) {
            unsigned i;
            for (i = n->first; i < n->first + n->count; i++) {
                n_tests++;
                if (test(s, i, r, best)) {
                    found = 1;
                    if (any)
                        goto done;
                }
            }
        } else {
            double e0, e1;
            int h0 = box_hit(&bvh->nodes[n->first], &tr, r->tmin, r->tmax, &e0);
            int h1 = box_hit(&bvh->nodes[n->first + 1], &tr, r->tmin, r->tmax,
                             &e1);
            if (h0 && h1) {
                int first_far = e1 < e0;
                stack[sp] = n->first + (unsigned)!first_far;
                stack_t[sp++] = first_far ? e0 : e1;
                ni = n->first + (unsigned)first_far;
                continue;
            }
            if (h0 || h1) {
                ni = n->first + (unsigned)h1;
                continue;
            }
        }
        for (;;) {
            if (sp == 0)
                goto done;
            sp--;
            if (stack_t[sp] <= r->tmax) {
                ni = stack[sp];
                break;
            }
        }
    }
done:
    if (tests != NULL)
        *tests += n_tests;
    return found;
}

/* The nearest triangle so far. */
typedef struct tri_best {
    unsigned index;
    double beta, gamma;
} tri_best;

static int tri_test(const ray_scene *s, unsigned i, ray_ray *r, void *best)
{
    const ray__tri *t = &s->tris[i];
    double th, beta, gamma;

    if (!ray__triangle_test(r, t->a, t->b, t->c, &th, &beta, &gamma))
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

/* One sphere, plane or polygon against the ray; fills *hit on a hit. */
static int prim_intersect(const ray_scene *s, unsigned i, const ray_ray *r,
                          ray_hit *hit)
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
    default:
        ok = ray_polygon(r, s->verts + p->first, p->count, hit);
        break;
    }
    if (ok) {
        hit->geom_id = i;
        hit->prim_id = 0;
    }
    return ok;
}

static int prim_test(const ray_scene *s, unsigned item, ray_ray *r,
                     void *best)
{
    ray_hit h;

    if (!prim_intersect(s, s->prim_bvh.items[item], r, &h))
        return 0;
    r->tmax = h.t;
    if (best != NULL)
        *(ray_hit *)best = h;
    return 1;
}

int ray__intersect(const ray_scene *s, const ray_ray *r, ray_hit *hit,
                   unsigned long long *tests)
{
    ray_ray rr = *r;
    ray_hit best;
    tri_best tb;
    int found = 0;
    size_t i;

    for (i = 0; i < s->n_planes; i++)
        if (prim_intersect(s, s->planes[i], &rr, &best)) {
            rr.tmax = best.t;
            found = 1;
        }
    if (tests != NULL)
        *tests += s->n_planes;
    if (traverse(s, &s->prim_bvh, &rr, prim_test, &best, 0, tests))
        found = 1;
    if (traverse(s, &s->tri_bvh, &rr, tri_test, &tb, 0, tests)) {
        const ray__tri *t = &s->tris[tb.index];
        /* A usable triangle (checked at commit) always fills. */
        if (ray__triangle_fill(t->a, t->b, t->c, rr.tmax, tb.beta, tb.gamma,
                               &best)) {
            best.geom_id = s->tri_ids[tb.index].geom_id;
            best.prim_id = s->tri_ids[tb.index].prim_id;
            found = 1;
        }
    }
    if (found)
        *hit = best;
    return found;
}

int ray__occluded(const ray_scene *s, const ray_ray *r,
                  unsigned long long *tests)
{
    ray_ray rr = *r;
    ray_hit h;
    size_t i;

    for (i = 0; i < s->n_planes; i++) {
        if (tests != NULL)
            (*tests)++;
        if (prim_intersect(s, s->planes[i], &rr, &h))
            return 1;
    }
    return traverse(s, &s->prim_bvh, &rr, prim_test, NULL, 1, tests) ||
           traverse(s, &s->tri_bvh, &rr, tri_test, NULL, 1, tests);
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
