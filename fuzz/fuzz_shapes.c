/* SPDX-License-Identifier: MIT */
/*
** fuzz_shapes.c -- the shape queries (issue 30) on a scene the input
** builds: up to 8 pieces of geometry of every kind (a triangle, a
** sphere, an oriented box, a capsule, a polygon, a plane, a small mesh,
** a torus, an instance of a child scene under an arbitrary transform),
** every value arbitrary (NaN, +-Inf, subnormals, 1e300, degenerate
** shapes), made with a counting allocator; then sweeps, overlaps and
** surface points with arbitrary arguments.  Checked:
**
**   * ray_intersect_sweep answers 1, 0, -RAY_EINVAL or -RAY_ESTATE, and
**     -RAY_EINVAL exactly for the misuse ray.h lists (a NaN or infinite
**     a, b or dir, a zero dir, b - a or tmin dir overflowing, a radius
**     negative, NaN or infinite, tmin not finite, tmax not above tmin;
**     tmax 0 is read as 1, the default);
**     *c untouched unless 1; a contact
**     lies in [tmin, tmax], every field finite, n unit, depth >= 0 (> 0
**     only for RAY_CONTACT_OVERLAP at tmin), flags known, ids that name
**     geometry; radius 0 with a == b answers as ray_intersect, with the
**     same t;
**   * the overlaps: the callback and _all forms agree on the count, the
**     ids name geometry, flags are known, nothing is written on misuse;
**   * ray_surface_point answers a documented status, writes nothing
**     unless RAY_OK, then a finite record with a unit normal, from which
**     ray_spawn's ray does not hit the triangle it leaves;
**   * after ray_scene_free the allocator holds nothing.
*/
#include <string.h>

#include "fuzz.h"

#define MAX_GEOMS 8

typedef struct world {
    fuzz_input in;
    ray_scene *scene, *child;
    fuzz_alloc alloc, child_alloc;
    unsigned n_geoms, child_geoms;
    int committed;
} world;

/* A small closed mesh: a tetrahedron with corners from the input. */
static int add_mesh(world *w, ray_scene *s)
{
    static const unsigned idx[12] = {0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2};
    ray_vec3 v[4];
    ray_mesh m;
    int k;

    for (k = 0; k < 4; k++)
        v[k] = fuzz_vec3(&w->in);
    memset(&m, 0, sizeof m);
    m.vertices = v;
    m.vertex_count = 4;
    m.indices = idx;
    m.triangle_count = 4;
    return ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, NULL);
}

/* One piece of geometry of a kind the input picks (no instance in the
** child: two levels only); its status. */
static int add_geometry(world *w, ray_scene *s, int child)
{
    unsigned kind = fuzz_below(&w->in, child ? 8 : 9);
    ray_vec3 a, b, c, v[5];
    ray_box_params box;
    ray_capsule_params cap;
    ray_torus_params tor;
    ray_transform xf;
    int i, j;

    switch (kind) {
    case 0:
        a = fuzz_vec3(&w->in), b = fuzz_vec3(&w->in), c = fuzz_vec3(&w->in);
        return ray_scene_add_triangle(s, a, b, c, RAY_NO_MATERIAL, NULL);
    case 1:
        a = fuzz_vec3(&w->in);
        return ray_scene_add_sphere(s, a, fuzz_double(&w->in), RAY_NO_MATERIAL,
                                    NULL);
    case 2:
        box.center = fuzz_vec3(&w->in);
        box.half_extents = fuzz_vec3(&w->in);
        box.axis_x = fuzz_vec3(&w->in);
        box.axis_y = fuzz_vec3(&w->in);
        return ray_scene_add_box(s, &box, RAY_NO_MATERIAL, NULL);
    case 3:
        cap.a = fuzz_vec3(&w->in);
        cap.b = fuzz_vec3(&w->in);
        cap.radius = fuzz_double(&w->in);
        return ray_scene_add_capsule(s, &cap, RAY_NO_MATERIAL, NULL);
    case 4:
        j = 3 + (int)fuzz_below(&w->in, 3);
        for (i = 0; i < j; i++)
            v[i] = fuzz_vec3(&w->in);
        return ray_scene_add_polygon(s, v, (size_t)j, RAY_NO_MATERIAL, NULL);
    case 5:
        if (child)
            return add_mesh(w, s);
        a = fuzz_vec3(&w->in);
        b = fuzz_vec3(&w->in);
        return ray_scene_add_plane(s, a, b, RAY_NO_MATERIAL, NULL);
    case 6:
        return add_mesh(w, s);
    case 7:
        tor.center = fuzz_vec3(&w->in);
        tor.axis = fuzz_vec3(&w->in);
        tor.major = fuzz_double(&w->in);
        tor.minor = fuzz_double(&w->in);
        return ray_scene_add_torus(s, &tor, RAY_NO_MATERIAL, NULL);
    default:
        for (i = 0; i < 3; i++)
            for (j = 0; j < 4; j++)
                xf.m[i][j] = fuzz_double(&w->in);
        if (fuzz_u8(&w->in) & 1) {       /* often a plain placement */
            ray_transform_identity(&xf);
            xf.m[0][0] = xf.m[1][1] = fuzz_double(&w->in);
            xf.m[0][3] = fuzz_double(&w->in);
        }
        return ray_scene_add_instance(s, w->child, &xf, NULL);
    }
}

static int sweep_misuse(const ray_sweep *s)
{
    int finite = fuzz_finite3(s->shape.a) && fuzz_finite3(s->shape.b) &&
                 fuzz_finite3(s->dir);
    ray_vec3 x0, axis;
    double tmax = s->tmax == 0 ? 1 : s->tmax;   /* zero is the default */

    if (!finite || s->shape.kind != RAY_SHAPE_CAPSULE)
        return 1;                /* the box's kind: -RAY_EINVAL for a zero box */
    x0.x = s->dir.x * s->tmin;
    x0.y = s->dir.y * s->tmin;
    x0.z = s->dir.z * s->tmin;
    axis.x = s->shape.b.x - s->shape.a.x;
    axis.y = s->shape.b.y - s->shape.a.y;
    axis.z = s->shape.b.z - s->shape.a.z;
    return !(s->shape.radius >= 0 && s->shape.radius < HUGE_VAL) || !fuzz_finite3(axis) ||
           !isfinite(s->tmin) || !(tmax > s->tmin) || !fuzz_finite3(x0);
}

/* Geometry ids of a contact or an overlap name something added. */
static void check_ids(const world *w, unsigned geom_id, unsigned inst_id,
                      const char *what)
{
    if (inst_id == RAY_INVALID_ID)
        FUZZ_CHECK(geom_id < w->n_geoms, what);
    else {
        FUZZ_CHECK(inst_id < w->n_geoms, what);
        FUZZ_CHECK(geom_id < w->child_geoms, what);
    }
}

static void one_sweep(world *w)
{
    ray_sweep s;
    ray_contact c;
    unsigned how = fuzz_u8(&w->in);
    int rc;

    memset(&s, 0, sizeof s);
    s.shape.a = fuzz_vec3(&w->in);
    s.shape.b = how & 1 ? fuzz_vec3(&w->in) : s.shape.a;
    s.shape.radius = how & 2 ? fuzz_double(&w->in) : 0.5;
    s.dir = fuzz_vec3(&w->in);
    s.tmin = how & 4 ? fuzz_double(&w->in) : 0;
    s.tmax = how & 8 ? fuzz_double(&w->in) : (how & 16 ? HUGE_VAL : 1);
    if (how & 32)
        memset(&s.dir, 0, sizeof s.dir);  /* no motion: the overlap test */
    if (how & 64)
        s.shape.kind = 1u + (how >> 7);  /* a zero box, or an unknown kind */
    fuzz_sentinel(&c, sizeof c);
    rc = ray_intersect_sweep(w->scene, &s, NULL, &c);
    if (s.tmax == 0)
        s.tmax = 1;              /* what the call read: zero is the default */
    if (sweep_misuse(&s)) {
        FUZZ_CHECK(rc == -RAY_EINVAL, "ray_intersect_sweep: misuse refused");
        FUZZ_CHECK(fuzz_untouched(&c, sizeof c), "sweep: *c untouched");
        return;
    }
    FUZZ_CHECK(rc == 1 || rc == 0 || rc == -RAY_ESTATE,
               "ray_intersect_sweep: a documented answer");
    FUZZ_CHECK(w->committed || rc == -RAY_ESTATE, "sweep: ESTATE uncommitted");
    if (rc != 1) {
        FUZZ_CHECK(fuzz_untouched(&c, sizeof c), "sweep: *c untouched");
        return;
    }
    FUZZ_CHECK(c.t >= s.tmin && c.t <= s.tmax && isfinite(c.t),
               "sweep: t in [tmin, tmax]");
    FUZZ_CHECK(fuzz_finite3(c.p) && fuzz_finite3(c.n), "sweep: finite");
    FUZZ_CHECK(fabs(c.n.x * c.n.x + c.n.y * c.n.y + c.n.z * c.n.z - 1) <=
                   FUZZ_UNIT_TOL, "sweep: unit normal");
    FUZZ_CHECK(c.depth >= 0 && isfinite(c.depth), "sweep: depth >= 0");
    FUZZ_CHECK((c.flags & ~(RAY_CONTACT_OVERLAP | RAY_CONTACT_BOUNDS)) == 0,
               "sweep: known flags");
    FUZZ_CHECK(c.depth == 0 || ((c.flags & RAY_CONTACT_OVERLAP) &&
                                c.t == s.tmin), "sweep: depth of an overlap");
    FUZZ_CHECK(!(s.dir.x == 0 && s.dir.y == 0 && s.dir.z == 0) ||
                   ((c.flags & RAY_CONTACT_OVERLAP) && c.depth > 0 &&
                    c.t == s.tmin),
               "sweep: no motion reports an overlap alone");
    check_ids(w, c.geom_id, c.inst_id, "sweep: ids name geometry");
    if (s.shape.radius == 0 &&
        memcmp(&s.shape.a, &s.shape.b, sizeof s.shape.a) == 0 &&
        !(s.dir.x == 0 && s.dir.y == 0 && s.dir.z == 0)) {
        ray_ray r;
        ray_hit h;
        r.org = s.shape.a;
        r.dir = s.dir;
        r.tmin = s.tmin;
        r.tmax = s.tmax;
        FUZZ_CHECK(ray_intersect(w->scene, &r, &h, NULL) == 1 && h.t == c.t,
                   "sweep: radius 0 is ray_intersect");
    }
}

/* The callback of the overlaps: counts, checks ids. */
typedef struct counter {
    const world *w;
    int n;
} counter;

static int count_one(void *ud, const ray_overlap *o)
{
    counter *k = ud;
    check_ids(k->w, o->geom_id, o->inst_id, "overlap: ids name geometry");
    FUZZ_CHECK((o->flags & ~RAY_CONTACT_BOUNDS) == 0, "overlap: known flags");
    k->n++;
    return 0;
}

static void one_overlap(world *w)
{
    unsigned how = fuzz_u8(&w->in);
    ray_overlap found[4];
    ray_box_params b;
    ray_shape q;
    ray_vec3 c = fuzz_vec3(&w->in);
    double r = fuzz_double(&w->in);
    counter k;
    size_t n = 77;
    int rc, rc_all;

    k.w = w;
    k.n = 0;
    b.center = c;
    b.half_extents = fuzz_vec3(&w->in);
    b.axis_x = fuzz_vec3(&w->in);
    b.axis_y = fuzz_vec3(&w->in);
    fuzz_sentinel(found, sizeof found);
    memset(&q, 0, sizeof q);
    if (how & 1) {
        q.kind = RAY_SHAPE_BOX;
        q.box = b;
    } else {
        /* A sphere, or (bit 1) a capsule to a second point. */
        q.a = q.b = c;
        if (how & 2)
            q.b = fuzz_vec3(&w->in);
        q.radius = r;
    }
    if (how & 4)
        q.kind = how >> 3;          /* any kind, the unknown ones refused */
    rc = ray_overlap_shape(w->scene, &q, NULL, count_one, &k);
    rc_all = ray_overlap_shape_all(w->scene, &q, NULL, found, 4, &n);
    FUZZ_CHECK(rc == rc_all, "overlap: the two forms agree");
    if (rc < 0) {
        FUZZ_CHECK(rc == -RAY_EINVAL || rc == -RAY_ESTATE,
                   "overlap: a documented status");
        FUZZ_CHECK(n == 77 && fuzz_untouched(found, sizeof found),
                   "overlap: nothing written on failure");
        return;
    }
    FUZZ_CHECK(w->committed, "overlap: ESTATE uncommitted");
    FUZZ_CHECK(rc == k.n && (size_t)rc == n, "overlap: counts agree");
}

static void one_surface_point(world *w)
{
    unsigned g = fuzz_below(&w->in, MAX_GEOMS + 1);
    unsigned p = fuzz_below(&w->in, 5), inst = RAY_INVALID_ID;
    double u = fuzz_double(&w->in), v = fuzz_double(&w->in);
    ray_hit h, hit;
    ray_ray r;
    int rc;

    if (fuzz_u8(&w->in) & 1)
        inst = fuzz_below(&w->in, MAX_GEOMS + 1);
    fuzz_sentinel(&h, sizeof h);
    rc = ray_surface_point(w->scene, g, p, inst, u, v, &h);
    FUZZ_CHECK(rc == RAY_OK || rc == RAY_EINVAL || rc == RAY_EKIND ||
               rc == RAY_ESTATE, "ray_surface_point: a documented status");
    if (rc != RAY_OK) {
        FUZZ_CHECK(fuzz_untouched(&h, sizeof h), "surface point untouched");
        return;
    }
    FUZZ_CHECK(fuzz_finite3(h.p) && fuzz_finite3(h.p_err) &&
                   fuzz_finite3(h.n), "surface point: finite");
    FUZZ_CHECK(fabs(h.n.x * h.n.x + h.n.y * h.n.y + h.n.z * h.n.z - 1) <=
                   FUZZ_UNIT_TOL, "surface point: unit normal");
    if (ray_spawn(&h, h.n, &r) == RAY_OK &&
        ray_intersect(w->scene, &r, &hit, NULL) == 1)
        FUZZ_CHECK(!(hit.geom_id == h.geom_id && hit.prim_id == h.prim_id &&
                     hit.inst_id == h.inst_id),
                   "surface point: a spawned ray leaves its surface");
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    world w;
    unsigned n, i;

    memset(&w, 0, sizeof w);
    w.in = fuzz_input_of(data, size);
    w.alloc.fail_at = fuzz_u8(&w.in) == 0xCD ? 1 + fuzz_u8(&w.in) : 0;
    if (ray_scene_new(&w.child, fuzz_alloc_fn, &w.child_alloc) != RAY_OK)
        return 0;
    n = fuzz_below(&w.in, 3);
    for (i = 0; i < n; i++)
        if (add_geometry(&w, w.child, 1) == RAY_OK)
            w.child_geoms++;
    if (ray_scene_commit(w.child) != RAY_OK) {
        ray_scene_free(w.child);
        return 0;
    }
    if (ray_scene_new(&w.scene, fuzz_alloc_fn, &w.alloc) != RAY_OK) {
        ray_scene_free(w.child);
        return 0;
    }
    n = 1 + fuzz_below(&w.in, MAX_GEOMS);
    for (i = 0; i < n; i++) {
        int rc = add_geometry(&w, w.scene, 0);
        FUZZ_CHECK(fuzz_status_valid(rc), "add: a documented status");
        if (rc == RAY_OK)
            w.n_geoms++;
    }
    w.committed = fuzz_u8(&w.in) != 1 && ray_scene_commit(w.scene) == RAY_OK;
    while (fuzz_more(&w.in)) {
        switch (fuzz_below(&w.in, 3)) {
        case 0:
            one_sweep(&w);
            break;
        case 1:
            one_overlap(&w);
            break;
        default:
            one_surface_point(&w);
            break;
        }
    }
    ray_scene_free(w.scene);
    ray_scene_free(w.child);
    FUZZ_CHECK(w.alloc.live_blocks == 0 && w.child_alloc.live_blocks == 0,
               "ray_scene_free frees everything");
    return 0;
}
