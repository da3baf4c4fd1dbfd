/* SPDX-License-Identifier: MIT */
/*
** fuzz_live.c -- the shape queries (issue 30) in a live scene (issue 38):
** the input builds a scene as fuzz_shapes does (every kind of geometry,
** an instance of a child scene under an arbitrary transform, a counting
** allocator that may fail one allocation), with visibility masks and
** filters, then runs rounds of staged changes, each ended by a commit:
** instances moved, mesh vertices updated (the child's too, the child
** committed again), geometry disabled, enabled, removed and added, masks
** changed, filters set that reject by a rule the input picks (all, odd
** or even prim_id, none).  After each commit it runs sweeps, overlaps,
** rays, closest points and surface points with a query mask, and checks
** what an oracle can decide:
**
**   * masks (ray.h, section 12): nothing any query reports (sweeps,
**     overlaps, ray_intersect) has a mask without a bit outside the
**     query's ignore_mask (through an instance, the instance's and the
**     child geometry's both), so mask-0 geometry is never reported, with
**     the default options too (issue 38, defect 2); and an overlap with
**     ignore_mask Q finds exactly those of the one with ignore_mask 0
**     that pass Q (masks select, they do not move anything);
**   * filters: ray_intersect and ray_intersect_sweep (RAY_FILTER_
**     INTERSECT) never report a primitive its filter rejects; ray_occluded
**     (RAY_FILTER_OCCLUDED) answers as ray_intersect where every filter
**     is called by both or neither; the overlaps and ray_closest_point
**     call no filter (ray.h), so none is checked of them;
**   * disabled and removed geometry is reported by no query, closest
**     points included (masks and filters do not apply to them, enabling
**     does), and has no surface point (removed: RAY_EINVAL); changes to
**     removed geometry, set_transform on anything but an instance,
**     update_mesh on anything but a mesh and filters on instances are
**     refused with RAY_EINVAL;
**   * staged changes: a successful change makes the scene answer
**     -RAY_ESTATE until the commit, failed ones leave it committed; after
**     the commit every answer equals, bit for bit, that of a scene built
**     afresh in the final state (every geometry added in the same order
**     with its final vertices, transform, mask and filter, the disabled
**     ones disabled and the removed ones, as a stand-in, removed before
**     its one commit): ray_scene_update_mesh(3) promises it for refits,
**     API-NOTES decision 11 for any tree ("answers do not depend on the
**     path taken"), and ray.h's tie rules make the answers unique (the
**     sweeps' once their box search stopped skipping ties: this target's
**     first finding); the overlaps' _all form is in id order, so its list
**     is compared whole; ray_closest_point's point is unspecified among
**     ties, so only its answer and distance are;
**   * what fuzz_shapes checks of a contact (t in [tmin, tmax], finite
**     fields, a unit normal, depth only for an overlap at tmin, known
**     flags) and of an overlap (both forms agree); no leak after
**     ray_scene_free.
*/
#include <string.h>

#include "fuzz.h"

#define MAX_GEOMS 8             /* of the scene, added over all rounds */
#define MAX_CHILD 3             /* of the instanced scene */
#define MAX_ROUNDS 6            /* rounds of changes and a commit */
#define MESH_CORNERS 8          /* a mesh is a hexahedron ... */
#define MESH_TRIANGLES 12       /* ... of two triangles a face */
/* Every primitive of a full scene: 8 instances of 3 meshes of 12. */
#define MAX_FOUND (MAX_GEOMS * MAX_CHILD * MESH_TRIANGLES)

enum kind {
    K_TRIANGLE, K_SPHERE, K_BOX, K_CAPSULE, K_POLYGON, K_PLANE, K_MESH,
    K_TORUS, K_INSTANCE, N_KINDS
};

/* What a filter rejects, by the candidate's prim_id. */
enum rule { RULE_NONE, RULE_REJECT_ALL, RULE_REJECT_ODD, RULE_REJECT_EVEN,
            RULE_KEEP_ALL, N_RULES };

/* One piece of geometry as it stands now: how to add it afresh. */
typedef struct desc {
    enum kind kind;
    ray_vec3 v[MESH_CORNERS];    /* triangle, polygon, mesh corners;
                                    sphere v[0]; plane v[0], normal v[1] */
    unsigned nv;                 /* the polygon's vertices */
    double radius;
    ray_box_params box;
    ray_capsule_params cap;
    ray_torus_params tor;
    ray_transform xf;
    unsigned mask;
    int rule;                    /* enum rule */
    unsigned queries;            /* the filter's RAY_FILTER_* */
    int enabled, removed;
} desc;

/* A scene's geometry, in id order (a failed add takes no id). */
typedef struct level {
    desc g[MAX_GEOMS];
    unsigned n;
} level;

typedef struct world {
    fuzz_input in;
    level top, child;
    ray_scene *scene, *child_scene;
    fuzz_alloc alloc, child_alloc;
    ray_scene *fresh, *fresh_child;   /* the final state, built afresh */
    fuzz_alloc fresh_alloc, fresh_child_alloc;
    int committed;               /* the live scene answers queries */
    int rules[N_RULES];          /* the filters' ud: rules[k] == k */
} world;

static const unsigned mesh_index[3 * MESH_TRIANGLES] = {
    0, 2, 1, 1, 2, 3,   4, 5, 6, 5, 7, 6,   0, 1, 4, 1, 5, 4,
    2, 6, 3, 3, 6, 7,   0, 4, 2, 2, 4, 6,   1, 3, 5, 3, 7, 5
};

static int rule_filter(void *ud, const ray_ray *r, const ray_hit *candidate,
                       void *query_ud)
{
    const int *rule = (const int *)ud;

    (void)r;
    (void)query_ud;
    switch (*rule) {
    case RULE_REJECT_ALL:
        return 0;
    case RULE_REJECT_ODD:
        return (candidate->prim_id & 1u) == 0;
    case RULE_REJECT_EVEN:
        return (candidate->prim_id & 1u) != 0;
    default:
        return 1;
    }
}

/* A mask, or a query's ignore_mask: few bits, so that layers meet. */
static unsigned fuzz_mask(fuzz_input *in)
{
    unsigned b = fuzz_u8(in);
    return b & 8u ? ~(b & 7u) : b & 7u;
}

/* ------------------------------------------------ describing geometry */

/* Eight corners: a box (centre +- half extents) or any eight points. */
static void read_corners(world *w, ray_vec3 *v)
{
    unsigned k;

    if (fuzz_u8(&w->in) & 1) {
        ray_vec3 c = fuzz_vec3(&w->in), e = fuzz_vec3(&w->in);
        for (k = 0; k < MESH_CORNERS; k++) {
            v[k].x = k & 1 ? c.x + e.x : c.x - e.x;
            v[k].y = k & 2 ? c.y + e.y : c.y - e.y;
            v[k].z = k & 4 ? c.z + e.z : c.z - e.z;
        }
    } else
        for (k = 0; k < MESH_CORNERS; k++)
            v[k] = fuzz_vec3(&w->in);
}

static void read_transform(world *w, ray_transform *xf)
{
    int i, j;

    if (fuzz_u8(&w->in) & 1) {          /* often a plain placement */
        ray_transform_identity(xf);
        xf->m[0][0] = xf->m[1][1] = fuzz_double(&w->in);
        xf->m[0][3] = fuzz_double(&w->in);
        xf->m[1][3] = fuzz_double(&w->in);
        return;
    }
    for (i = 0; i < 3; i++)
        for (j = 0; j < 4; j++)
            xf->m[i][j] = fuzz_double(&w->in);
}

/* A new piece of geometry (a child has no planes and no instances), its
** mask and often a filter (none on instances: refused). */
static void read_desc(world *w, desc *d, int child)
{
    unsigned k;

    memset(d, 0, sizeof *d);
    d->kind = (enum kind)fuzz_below(&w->in, child ? K_INSTANCE : N_KINDS);
    if (child && d->kind == K_PLANE)
        d->kind = K_MESH;
    d->mask = fuzz_u8(&w->in) & 1 ? fuzz_mask(&w->in) : ~0u;
    if (d->kind != K_INSTANCE && (fuzz_u8(&w->in) & 3) == 0) {
        d->rule = 1 + (int)fuzz_below(&w->in, N_RULES - 1);
        d->queries = 1 + fuzz_below(&w->in, 3);
    }
    d->enabled = 1;
    switch (d->kind) {
    case K_TRIANGLE:
    case K_SPHERE:
    case K_PLANE:
        for (k = 0; k < 3; k++)
            d->v[k] = fuzz_vec3(&w->in);
        d->radius = fuzz_double(&w->in);
        break;
    case K_POLYGON:
        d->nv = 3 + fuzz_below(&w->in, 3);
        for (k = 0; k < d->nv; k++)
            d->v[k] = fuzz_vec3(&w->in);
        break;
    case K_MESH:
        read_corners(w, d->v);
        break;
    case K_BOX:
        d->box.center = fuzz_vec3(&w->in);
        d->box.half_extents = fuzz_vec3(&w->in);
        d->box.axis_x = fuzz_vec3(&w->in);
        d->box.axis_y = fuzz_vec3(&w->in);
        break;
    case K_CAPSULE:
        d->cap.a = fuzz_vec3(&w->in);
        d->cap.b = fuzz_vec3(&w->in);
        d->cap.radius = fuzz_double(&w->in);
        break;
    case K_TORUS:
        d->tor.center = fuzz_vec3(&w->in);
        d->tor.axis = fuzz_vec3(&w->in);
        d->tor.major = fuzz_double(&w->in);
        d->tor.minor = fuzz_double(&w->in);
        break;
    case K_INSTANCE:
    case N_KINDS:
        read_transform(w, &d->xf);
        break;
    }
}

static ray_mesh mesh_of(const desc *d)
{
    ray_mesh m;

    memset(&m, 0, sizeof m);
    m.vertices = d->v;
    m.vertex_count = MESH_CORNERS;
    m.indices = mesh_index;
    m.triangle_count = MESH_TRIANGLES;
    return m;
}

/* Add d to s as it stands (its shape, not its mask, filter or state). */
static int add_desc(ray_scene *s, const ray_scene *child, const desc *d,
                    unsigned *id)
{
    ray_mesh m;

    switch (d->kind) {
    case K_TRIANGLE:
        return ray_scene_add_triangle(s, d->v[0], d->v[1], d->v[2],
                                      RAY_NO_MATERIAL, id);
    case K_SPHERE:
        return ray_scene_add_sphere(s, d->v[0], d->radius, RAY_NO_MATERIAL,
                                    id);
    case K_PLANE:
        return ray_scene_add_plane(s, d->v[0], d->v[1], RAY_NO_MATERIAL, id);
    case K_POLYGON:
        return ray_scene_add_polygon(s, d->v, d->nv, RAY_NO_MATERIAL, id);
    case K_MESH:
        m = mesh_of(d);
        return ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, id);
    case K_BOX:
        return ray_scene_add_box(s, &d->box, RAY_NO_MATERIAL, id);
    case K_CAPSULE:
        return ray_scene_add_capsule(s, &d->cap, RAY_NO_MATERIAL, id);
    case K_TORUS:
        return ray_scene_add_torus(s, &d->tor, RAY_NO_MATERIAL, id);
    case K_INSTANCE:
    case N_KINDS:
        break;
    }
    return ray_scene_add_instance(s, child, &d->xf, id);
}

/* Mask, filter and state of d, as set on geometry "id" of s. */
static void set_state(world *w, ray_scene *s, unsigned id, const desc *d)
{
    if (d->removed) {
        FUZZ_CHECK(ray_scene_remove(s, id) == RAY_OK,
                   "fresh scene: ray_scene_remove");
        return;
    }
    if (d->mask != ~0u)
        FUZZ_CHECK(ray_scene_set_mask(s, id, d->mask) == RAY_OK,
                   "fresh scene: ray_scene_set_mask");
    if (d->rule != RULE_NONE)
        FUZZ_CHECK(ray_scene_set_filter(s, id, rule_filter, &w->rules[d->rule],
                                        d->queries) == RAY_OK,
                   "fresh scene: ray_scene_set_filter");
    if (!d->enabled)
        FUZZ_CHECK(ray_scene_set_enabled(s, id, 0) == RAY_OK,
                   "fresh scene: ray_scene_set_enabled");
}

/*
** Build a level afresh in its final state, committed.  Every add must
** succeed with the id it had: the live scene accepted this data (by the
** add, or by an update or a move, which check it as the add does).
*/
static ray_scene *build_fresh(world *w, const level *lv, const ray_scene *child,
                              fuzz_alloc *a)
{
    const ray_vec3 origin = {0, 0, 0};
    ray_scene *s;
    unsigned i, id;

    memset(a, 0, sizeof *a);
    if (ray_scene_new(&s, fuzz_alloc_fn, a) != RAY_OK)
        return NULL;
    for (i = 0; i < lv->n; i++) {
        const desc *d = &lv->g[i];
        int rc;
        /* Removed geometry keeps its id and nothing else: a stand-in
        ** (an instance's child may have grown out of its range since). */
        if (d->removed)
            rc = ray_scene_add_sphere(s, origin, 1, RAY_NO_MATERIAL, &id);
        else
            rc = add_desc(s, child, d, &id);
        FUZZ_CHECK(rc == RAY_OK && id == i,
                   "fresh scene: the final state's data is accepted, same id");
        set_state(w, s, id, d);
    }
    FUZZ_CHECK(ray_scene_commit(s) == RAY_OK,
               "fresh scene: commits as the live one did");
    return s;
}

static void free_fresh(world *w)
{
    ray_scene_free(w->fresh);
    ray_scene_free(w->fresh_child);
    FUZZ_CHECK(w->fresh_alloc.live_blocks == 0 &&
                   w->fresh_child_alloc.live_blocks == 0,
               "ray_scene_free frees everything (fresh scenes)");
    w->fresh = w->fresh_child = NULL;
}

/* ----------------------------------------------------------- the oracle */

/* Live, enabled, and (where masks apply) passing the query's mask. */
static int desc_shown(const desc *d, unsigned ignore_mask, int use_mask)
{
    return d->enabled && !d->removed &&
           (!use_mask || (d->mask & ~ignore_mask) != 0);
}

/* Whether d's filter, for queries of kind "queries", rejects "prim". */
static int desc_rejects(const desc *d, unsigned prim, unsigned queries)
{
    if ((d->queries & queries) == 0)
        return 0;
    switch (d->rule) {
    case RULE_REJECT_ALL:
        return 1;
    case RULE_REJECT_ODD:
        return (prim & 1u) != 0;
    case RULE_REJECT_EVEN:
        return (prim & 1u) == 0;
    default:
        return 0;
    }
}

/*
** Whether a query with this ignore_mask, whose filters are those of
** "queries" (0: it calls none), may report (geom, prim, inst): live,
** enabled and unmasked geometry (through an instance: the instance and
** the child's geometry both) of a prim_id it has, not rejected.
** use_mask 0: masks do not apply (ray_closest_point).
*/
static int may_report(const world *w, unsigned geom, unsigned prim,
                      unsigned inst, unsigned ignore_mask, int use_mask,
                      unsigned queries)
{
    const desc *d;

    if (inst != RAY_INVALID_ID) {
        if (inst >= w->top.n || w->top.g[inst].kind != K_INSTANCE ||
            !desc_shown(&w->top.g[inst], ignore_mask, use_mask) ||
            geom >= w->child.n)
            return 0;
        d = &w->child.g[geom];
    } else {
        if (geom >= w->top.n || w->top.g[geom].kind == K_INSTANCE)
            return 0;
        d = &w->top.g[geom];
    }
    if (!desc_shown(d, ignore_mask, use_mask))
        return 0;
    if (prim >= (d->kind == K_MESH ? MESH_TRIANGLES : 1u))
        return 0;
    return !desc_rejects(d, prim, queries);
}

static int same_bits(double a, double b)
{
    return memcmp(&a, &b, sizeof a) == 0;
}

static int same_vec(ray_vec3 a, ray_vec3 b)
{
    return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z);
}

static int same_hit(const ray_hit *a, const ray_hit *b)
{
    return same_bits(a->t, b->t) && same_vec(a->p, b->p) &&
           same_vec(a->n, b->n) && same_bits(a->u, b->u) &&
           same_bits(a->v, b->v) && same_vec(a->p_err, b->p_err) &&
           a->geom_id == b->geom_id && a->prim_id == b->prim_id &&
           a->inst_id == b->inst_id;
}

static int same_contact(const ray_contact *a, const ray_contact *b)
{
    return same_bits(a->t, b->t) && same_vec(a->p, b->p) &&
           same_vec(a->n, b->n) && same_bits(a->depth, b->depth) &&
           a->flags == b->flags && a->geom_id == b->geom_id &&
           a->prim_id == b->prim_id && a->inst_id == b->inst_id;
}

/* ------------------------------------------------------------ queries */

static double unit_error(ray_vec3 n)
{
    return fabs(n.x * n.x + n.y * n.y + n.z * n.z - 1);
}

static void check_contact(const ray_sweep *s, const ray_contact *c)
{
    const double tmax = s->tmax == 0 ? 1 : s->tmax;

    FUZZ_CHECK(c->t >= s->tmin && c->t <= tmax && isfinite(c->t),
               "sweep: t in [tmin, tmax]");
    FUZZ_CHECK(fuzz_finite3(c->p) && fuzz_finite3(c->n), "sweep: finite");
    FUZZ_CHECK(unit_error(c->n) <= FUZZ_UNIT_TOL, "sweep: unit normal");
    FUZZ_CHECK(c->depth >= 0 && isfinite(c->depth), "sweep: depth >= 0");
    FUZZ_CHECK((c->flags & ~(RAY_CONTACT_OVERLAP | RAY_CONTACT_BOUNDS)) == 0,
               "sweep: known flags");
    FUZZ_CHECK(c->depth == 0 || ((c->flags & RAY_CONTACT_OVERLAP) &&
                                 c->t == s->tmin),
               "sweep: depth of an overlap");
}

static void one_sweep(world *w, const ray_query *q)
{
    unsigned how = fuzz_u8(&w->in);
    ray_contact c, fc;
    ray_sweep s;
    int rc, frc;

    memset(&s, 0, sizeof s);
    s.shape.a = fuzz_vec3(&w->in);
    s.shape.b = how & 1 ? fuzz_vec3(&w->in) : s.shape.a;
    s.shape.radius = how & 2 ? fuzz_double(&w->in) : 0.5;
    s.dir = how & 4 ? s.dir : fuzz_vec3(&w->in);   /* 0: an overlap test */
    s.tmin = how & 8 ? fuzz_double(&w->in) : 0;
    s.tmax = how & 16 ? fuzz_double(&w->in) : (how & 32 ? HUGE_VAL : 0);
    rc = ray_intersect_sweep(w->scene, &s, q, &c);
    frc = ray_intersect_sweep(w->fresh, &s, q, &fc);
    FUZZ_CHECK(rc == frc, "sweep: as the fresh scene answers");
    FUZZ_CHECK(rc == 1 || rc == 0 || rc == -RAY_EINVAL || rc == -RAY_EKIND,
               "sweep: a documented answer on a committed scene");
    if (rc != 1)
        return;
    check_contact(&s, &c);
    FUZZ_CHECK(may_report(w, c.geom_id, c.prim_id, c.inst_id, q->ignore_mask,
                          1, RAY_FILTER_INTERSECT),
               "sweep: only shown, unmasked, unfiltered geometry");
    FUZZ_CHECK(same_contact(&c, &fc), "sweep: the fresh scene's contact");
}

static int count_overlap(void *ud, const ray_overlap *o)
{
    (void)o;
    ++*(int *)ud;
    return 0;
}

static int same_overlap(const ray_overlap *a, const ray_overlap *b)
{
    return a->geom_id == b->geom_id && a->prim_id == b->prim_id &&
           a->inst_id == b->inst_id && a->flags == b->flags;
}

static void read_shape(world *w, ray_shape *shape)
{
    unsigned how = fuzz_u8(&w->in);

    memset(shape, 0, sizeof *shape);
    if (how & 1) {
        shape->kind = RAY_SHAPE_BOX;
        shape->box.center = fuzz_vec3(&w->in);
        shape->box.half_extents = fuzz_vec3(&w->in);
        shape->box.axis_x = fuzz_vec3(&w->in);
        shape->box.axis_y = fuzz_vec3(&w->in);
        return;
    }
    shape->a = shape->b = fuzz_vec3(&w->in);
    if (how & 2)
        shape->b = fuzz_vec3(&w->in);
    shape->radius = how & 4 ? fuzz_double(&w->in) : 1;
}

static void one_overlap(world *w, const ray_query *q)
{
    ray_overlap found[MAX_FOUND], fresh[MAX_FOUND], all[MAX_FOUND];
    size_t n, fn, na, i, j;
    ray_query unmasked;
    ray_shape shape;
    int rc, k = 0;

    read_shape(w, &shape);
    memset(&unmasked, 0, sizeof unmasked);
    rc = ray_overlap_shape_all(w->scene, &shape, q, found, MAX_FOUND, &n);
    FUZZ_CHECK(rc == ray_overlap_shape(w->scene, &shape, q, count_overlap, &k),
               "overlap: the two forms agree");
    FUZZ_CHECK(rc == ray_overlap_shape_all(w->fresh, &shape, q, fresh,
                                           MAX_FOUND, &fn),
               "overlap: as the fresh scene answers");
    if (rc < 0) {
        FUZZ_CHECK(rc == -RAY_EINVAL, "overlap: a documented status");
        return;
    }
    FUZZ_CHECK(rc == k && (size_t)rc == n && n <= MAX_FOUND,
               "overlap: counts agree");
    FUZZ_CHECK(fn == n, "overlap: the fresh scene's count");
    for (i = 0; i < n; i++) {
        FUZZ_CHECK(same_overlap(&found[i], &fresh[i]),
                   "overlap: the fresh scene's list, in id order");
        FUZZ_CHECK(may_report(w, found[i].geom_id, found[i].prim_id,
                              found[i].inst_id, q->ignore_mask, 1, 0),
                   "overlap: only shown, unmasked geometry");
    }
    /* Masks select: the unmasked list, less what this mask hides. */
    FUZZ_CHECK(ray_overlap_shape_all(w->scene, &shape, &unmasked, all,
                                     MAX_FOUND, &na) >= 0,
               "overlap: ignore_mask 0 answers too");
    for (i = j = 0; i < na; i++)
        if (may_report(w, all[i].geom_id, all[i].prim_id, all[i].inst_id,
                       q->ignore_mask, 1, 0)) {
            FUZZ_CHECK(j < n && same_overlap(&all[i], &found[j]),
                       "overlap: the mask hides what it names, no more");
            j++;
        }
    FUZZ_CHECK(j == n, "overlap: the mask finds nothing ignore_mask 0 hid");
}

/* Whether every filter is called by both kinds of ray query, or none:
** then a ray is occluded exactly where it has a nearest hit. */
static int same_filters_both_ways(const world *w)
{
    const unsigned both = RAY_FILTER_INTERSECT | RAY_FILTER_OCCLUDED;
    unsigned i;

    for (i = 0; i < w->top.n; i++)
        if (w->top.g[i].queries != 0 && w->top.g[i].queries != both)
            return 0;
    for (i = 0; i < w->child.n; i++)
        if (w->child.g[i].queries != 0 && w->child.g[i].queries != both)
            return 0;
    return 1;
}

static void one_ray(world *w, const ray_query *q)
{
    ray_ray r = fuzz_ray(&w->in);
    ray_hit h, fh;
    int rc = ray_intersect(w->scene, &r, &h, q);
    int occluded = ray_occluded(w->scene, &r, q);

    FUZZ_CHECK(rc == ray_intersect(w->fresh, &r, &fh, q),
               "ray_intersect: as the fresh scene answers");
    FUZZ_CHECK(occluded == ray_occluded(w->fresh, &r, q),
               "ray_occluded: as the fresh scene answers");
    if (rc >= 0 && same_filters_both_ways(w))
        FUZZ_CHECK(occluded == rc, "ray_occluded: as ray_intersect, where "
                   "every filter answers both kinds of query alike");
    if (rc != 1)
        return;
    fuzz_check_hit(&r, &h, 1, "ray_intersect in a live scene");
    FUZZ_CHECK(may_report(w, h.geom_id, h.prim_id, h.inst_id, q->ignore_mask,
                          1, RAY_FILTER_INTERSECT),
               "ray_intersect: only shown, unmasked, unfiltered geometry");
    FUZZ_CHECK(same_hit(&h, &fh), "ray_intersect: the fresh scene's hit");
}

static void one_closest(world *w)
{
    ray_vec3 p = fuzz_vec3(&w->in);
    double radius = fuzz_u8(&w->in) & 1 ? fuzz_double(&w->in) : HUGE_VAL;
    ray_closest c, fc;
    int rc = ray_closest_point(w->scene, p, radius, &c);

    FUZZ_CHECK(rc == ray_closest_point(w->fresh, p, radius, &fc),
               "ray_closest_point: as the fresh scene answers");
    if (rc != 1)
        return;
    FUZZ_CHECK(may_report(w, c.geom_id, c.prim_id, c.inst_id, 0, 0, 0),
               "ray_closest_point: only shown geometry");
    FUZZ_CHECK(same_bits(c.distance, fc.distance),
               "ray_closest_point: the fresh scene's distance");
}

static void one_surface_point(world *w)
{
    unsigned g = fuzz_below(&w->in, MAX_GEOMS + 1);
    unsigned p = fuzz_below(&w->in, MESH_TRIANGLES + 1);
    unsigned inst = fuzz_u8(&w->in) & 1 ? fuzz_below(&w->in, MAX_GEOMS + 1)
                                        : RAY_INVALID_ID;
    double u = fuzz_double(&w->in), v = fuzz_double(&w->in);
    const desc *d = inst == RAY_INVALID_ID ? (g < w->top.n ? &w->top.g[g] : NULL)
                    : inst < w->top.n && g < w->child.n ? &w->child.g[g]
                                                        : NULL;
    ray_hit h, fh;
    int rc = ray_surface_point(w->scene, g, p, inst, u, v, &h);

    FUZZ_CHECK(rc == ray_surface_point(w->fresh, g, p, inst, u, v, &fh),
               "ray_surface_point: as the fresh scene answers");
    FUZZ_CHECK(rc == RAY_OK || rc == RAY_EINVAL || rc == RAY_EKIND,
               "ray_surface_point: a documented status");
    if (d != NULL && (d->removed ||
                      (inst != RAY_INVALID_ID && w->top.g[inst].removed)))
        FUZZ_CHECK(rc == RAY_EINVAL, "ray_surface_point: removed geometry");
    if (rc == RAY_OK)
        FUZZ_CHECK(same_hit(&h, &fh), "ray_surface_point: the fresh record");
}

/* Queries on the committed live scene and its fresh twin. */
static void run_queries(world *w)
{
    unsigned k, n = 1 + fuzz_below(&w->in, 4);
    ray_query q;

    memset(&q, 0, sizeof q);
    for (k = 0; k < n && fuzz_more(&w->in); k++) {
        q.ignore_mask = fuzz_u8(&w->in) & 1 ? fuzz_mask(&w->in) : 0;
        switch (fuzz_below(&w->in, 5)) {
        case 0:
            one_sweep(w, &q);
            break;
        case 1:
            one_overlap(w, &q);
            break;
        case 2:
            one_ray(w, &q);
            break;
        case 3:
            one_closest(w);
            break;
        default:
            one_surface_point(w);
            break;
        }
    }
}

/* ------------------------------------------------------ staged changes */

/*
** A scene with a change staged answers no query; one whose changes all
** failed (or staged nothing) stays committed and answers.
*/
static void check_staged(const world *w, int staged)
{
    ray_overlap o;
    ray_shape shape;
    size_t n = 77;
    int rc;

    memset(&shape, 0, sizeof shape);
    rc = ray_overlap_shape_all(w->scene, &shape, NULL, &o, 1, &n);
    if (staged)
        FUZZ_CHECK(rc == -RAY_ESTATE && n == 77,
                   "a changed scene answers -RAY_ESTATE until its commit");
    else
        FUZZ_CHECK(rc >= 0, "a failed change leaves the scene committed");
}

/*
** New geometry of the input's, with its mask and filter, added to lv
** (the live scene s) before or after a commit; 1 if it was.
*/
static int add_new(world *w, level *lv, ray_scene *s, int child)
{
    desc *d = &lv->g[lv->n];
    unsigned id;
    int rc;

    if (lv->n == (child ? MAX_CHILD : MAX_GEOMS))
        return 0;
    read_desc(w, d, child);
    rc = add_desc(s, w->child_scene, d, &id);
    FUZZ_CHECK(fuzz_status_valid(rc), "add: a documented status");
    if (rc != RAY_OK)
        return 0;
    FUZZ_CHECK(id == lv->n, "add: ids counted over the added geometry");
    lv->n++;
    if (d->mask != ~0u)
        FUZZ_CHECK(ray_scene_set_mask(s, id, d->mask) == RAY_OK,
                   "ray_scene_set_mask: on live geometry");
    if (d->rule != RULE_NONE)
        FUZZ_CHECK(ray_scene_set_filter(s, id, rule_filter, &w->rules[d->rule],
                                        d->queries) == RAY_OK,
                   "ray_scene_set_filter: on live geometry");
    return 1;
}

/*
** One change to "lv" (the live scene s), recorded in lv when it
** succeeds; those the oracle knows are refused must be.  Returns 1 when
** it staged something.
*/
static int one_change(world *w, level *lv, ray_scene *s, int child)
{
    unsigned what = fuzz_below(&w->in, 7);
    unsigned id = fuzz_below(&w->in, MAX_GEOMS + 1);
    desc *d = id < lv->n ? &lv->g[id] : NULL;
    int gone = d == NULL || d->removed, rc;
    desc nd;
    ray_mesh m;

    if (d != NULL)
        nd = *d;
    else
        memset(&nd, 0, sizeof nd);
    switch (what) {
    case 0:                                     /* move an instance */
        read_transform(w, &nd.xf);
        rc = ray_scene_set_transform(s, id, &nd.xf);
        if (gone || nd.kind != K_INSTANCE)
            FUZZ_CHECK(rc == RAY_EINVAL,
                       "ray_scene_set_transform: only a live instance");
        break;
    case 1:                                     /* new mesh vertices */
        read_corners(w, nd.v);
        m = mesh_of(&nd);
        rc = ray_scene_update_mesh(s, id, &m);
        if (gone || nd.kind != K_MESH)
            FUZZ_CHECK(rc == RAY_EINVAL,
                       "ray_scene_update_mesh: only a live mesh");
        break;
    case 2:                                     /* hide or show */
        nd.enabled = (int)(fuzz_u8(&w->in) & 1);
        rc = ray_scene_set_enabled(s, id, nd.enabled);
        if (gone)
            FUZZ_CHECK(rc == RAY_EINVAL, "ray_scene_set_enabled: live only");
        if (rc == RAY_OK && d->enabled == nd.enabled)
            return 0;                           /* stages nothing */
        break;
    case 3:
        nd.removed = 1;
        nd.enabled = 0;
        rc = ray_scene_remove(s, id);
        if (gone)
            FUZZ_CHECK(rc == RAY_EINVAL, "ray_scene_remove: live only");
        break;
    case 4:
        nd.mask = fuzz_mask(&w->in);
        rc = ray_scene_set_mask(s, id, nd.mask);
        if (gone)
            FUZZ_CHECK(rc == RAY_EINVAL, "ray_scene_set_mask: live only");
        break;
    case 5:
        nd.rule = (int)fuzz_below(&w->in, N_RULES);
        nd.queries = fuzz_below(&w->in, 4);
        rc = ray_scene_set_filter(s, id,
                                  nd.rule == RULE_NONE ? NULL : rule_filter,
                                  &w->rules[nd.rule], nd.queries);
        if (gone || nd.kind == K_INSTANCE ||
            (nd.rule != RULE_NONE && nd.queries == 0))
            FUZZ_CHECK(rc == RAY_EINVAL, "ray_scene_set_filter: refusals");
        if (nd.rule == RULE_NONE)
            nd.queries = 0;
        break;
    default:                                    /* add geometry, staged */
        return add_new(w, lv, s, child);
    }
    FUZZ_CHECK(fuzz_status_valid(rc), "a change: a documented status");
    if (rc != RAY_OK)
        return 0;
    *d = nd;
    return 1;
}

/* Changes to the instanced scene, then its commit (never fails: its
** allocator does not). */
static void change_child(world *w)
{
    unsigned k, n = 1 + fuzz_below(&w->in, 2);

    for (k = 0; k < n; k++)
        one_change(w, &w->child, w->child_scene, 1);
    FUZZ_CHECK(ray_scene_commit(w->child_scene) == RAY_OK,
               "ray_scene_commit: the instanced scene");
}

/* A round: changes, the commit, and queries against a fresh build. */
static void one_round(world *w)
{
    unsigned k, n = 1 + fuzz_below(&w->in, 4);
    int staged = 0, child_changed = 0, rc;

    for (k = 0; k < n; k++) {
        if (fuzz_below(&w->in, 6) == 0) {
            change_child(w);
            child_changed = 1;
        } else
            staged |= one_change(w, &w->top, w->scene, 0);
    }
    /* After the child's commit the instances are stale (-RAY_ESTATE
    ** where a query meets them) until the scene's own. */
    if (staged || (w->committed && !child_changed))
        check_staged(w, staged);
    rc = ray_scene_commit(w->scene);
    FUZZ_CHECK(rc == RAY_OK || rc == RAY_EINVAL || rc == RAY_ENOMEM,
               "ray_scene_commit: a documented status");
    w->committed = rc == RAY_OK;
    if (rc != RAY_OK)
        return;
    w->fresh_child = build_fresh(w, &w->child, NULL, &w->fresh_child_alloc);
    if (w->fresh_child != NULL)
        w->fresh = build_fresh(w, &w->top, w->fresh_child, &w->fresh_alloc);
    if (w->fresh != NULL)
        run_queries(w);
    free_fresh(w);
}

/* The first state: geometry, masks and filters, before any commit. */
static void build_level(world *w, level *lv, ray_scene *s, unsigned n,
                        int child)
{
    unsigned i;

    for (i = 0; i < n; i++)
        add_new(w, lv, s, child);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    world w;
    unsigned k;

    memset(&w, 0, sizeof w);
    for (k = 0; k < N_RULES; k++)
        w.rules[k] = (int)k;
    w.in = fuzz_input_of(data, size);
    w.alloc.fail_at = fuzz_u8(&w.in) == 0xCD ? 1 + fuzz_u8(&w.in) : 0;
    if (ray_scene_new(&w.child_scene, fuzz_alloc_fn, &w.child_alloc) !=
        RAY_OK)
        return 0;
    build_level(&w, &w.child, w.child_scene, fuzz_below(&w.in, MAX_CHILD + 1),
                1);
    FUZZ_CHECK(ray_scene_commit(w.child_scene) == RAY_OK,
               "ray_scene_commit: the instanced scene");
    if (ray_scene_new(&w.scene, fuzz_alloc_fn, &w.alloc) == RAY_OK) {
        build_level(&w, &w.top, w.scene, 1 + fuzz_below(&w.in, MAX_GEOMS), 0);
        for (k = 0; k < MAX_ROUNDS && fuzz_more(&w.in); k++)
            one_round(&w);
        ray_scene_free(w.scene);
    }
    ray_scene_free(w.child_scene);
    FUZZ_CHECK(w.alloc.live_blocks == 0 && w.child_alloc.live_blocks == 0,
               "ray_scene_free frees everything");
    return 0;
}
