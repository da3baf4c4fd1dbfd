/* SPDX-License-Identifier: MIT */
/*
** check_sweep.c -- ray_intersect_sweep: spheres and capsules swept
** through the mixed scene (shapekit.h) against a brute force over every
** convex piece of it in long double (the first t at which the shape
** comes within its radius of the piece, found by the tests' own ternary
** search and bisection on the piece's convex distance, not by the
** library's pieces), at the origin and at 1e5; grazing sweeps along a
** wall, sweeps that start in contact, radii from 1e-6 to 1e3 of the
** scene, radius 0 against ray_intersect, the no-tunnelling set (closed
** meshes' vertices and edges at 0, 1e5 and 1e6), instances, masks and
** filters, the kinds answered by their boxes, misuse.
*/
#include <float.h>
#include <stdlib.h>
#include <string.h>

#include "shapekit.h"

/* ---------------------------------------------------------- reference */

/* A sweep in long double: the core [a + t d, b + t d] at t. */
typedef struct lsweep {
    lvec a, b, d;
    ld r, t0, t1;
} lsweep;

static lsweep lsweep_of(const ray_sweep *w)
{
    lsweep l;

    l.a = lv(w->shape.a);
    l.b = lv(w->shape.b);
    l.d = lv(w->dir);
    l.r = (ld)w->shape.radius;
    l.t0 = (ld)w->tmin;
    l.t1 = w->tmax == 0 ? 1 : (ld)w->tmax;   /* zero: the whole motion */
    return l;
}

/* Piece p's clearance at t: its signed distance to the core, less r. */
static ld clearance(const piece *p, const lsweep *l, ld t)
{
    return kit_distance(p, ladd(l->a, lscale(l->d, t)),
                        ladd(l->b, lscale(l->d, t))) - l->r;
}

/* Can piece p come within the radius of the core over the sweep?  (Its
** bounding sphere against the path of a, grown by |b - a|.) */
static int reachable(const piece *p, const lsweep *l)
{
    lvec a0 = ladd(l->a, lscale(l->d, l->t0));
    lvec a1 = ladd(l->a, lscale(l->d, l->t1));

    if (!(p->reach < HUGE_VALL))
        return 1;
    return ldist(ref_segment(p->centre, a0, a1), p->centre) <=
           p->reach + l->r + ldist(l->a, l->b) + 1e-9L;
}

/* The first t in [t0, t1] at which piece p's clearance is <= thr, or
** +Inf: the clearance is convex in t, so its minimum by ternary search,
** then bisection on the part before it. */
static ld first_at(const piece *p, const lsweep *l, ld thr)
{
    ld lo = l->t0, hi = l->t1, tmin, a, b;
    int k;

    if (clearance(p, l, l->t0) <= thr)
        return l->t0;
    for (k = 0; k < 120; k++) {
        ld m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
        if (clearance(p, l, m1) < clearance(p, l, m2))
            hi = m2;
        else
            lo = m1;
    }
    tmin = (lo + hi) / 2;
    if (clearance(p, l, tmin) > thr)
        return HUGE_VALL;
    a = l->t0;
    b = tmin;
    for (k = 0; k < 120; k++) {
        ld m = (a + b) / 2;
        if (clearance(p, l, m) <= thr)
            b = m;
        else
            a = m;
    }
    return b;
}

/* The least clearance of every reachable piece at t (its signed
** distance less r); *which: the piece. */
static ld clearance_all(const kit *k, const lsweep *l, ld t, size_t *which)
{
    ld best = HUGE_VALL;
    size_t i;

    for (i = 0; i < k->n; i++) {
        ld c;
        if (!reachable(&k->p[i], l))
            continue;
        c = clearance(&k->p[i], l, t);
        if (c < best) {
            best = c;
            if (which != NULL)
                *which = i;
        }
    }
    return best;
}

/* The first t at which some piece's clearance is <= thr (+Inf: none). */
static ld first_all(const kit *k, const lsweep *l, ld thr)
{
    ld best = HUGE_VALL;
    size_t i;

    for (i = 0; i < k->n; i++)
        if (reachable(&k->p[i], l)) {
            ld t = first_at(&k->p[i], l, thr);
            if (t < best)
                best = t;
        }
    return best;
}

/* The least distance from x to the pieces named (geom_id, prim_id),
** unsigned (a contact point lies on the surface). */
static ld distance_to_named(const kit *k, unsigned g, unsigned i,
                            unsigned in, lvec x)
{
    ld best = HUGE_VALL;
    size_t j;

    for (j = 0; j < k->n; j++)
        if (k->p[j].geom_id == g && k->p[j].prim_id == i &&
            k->p[j].inst_id == in) {
            ld d = fabsl(kit_distance(&k->p[j], x, x));
            if (d < best)
                best = d;
        }
    return best;
}

/*
** One sweep checked against the reference, with tolerance tol (a
** distance):
**   - overlapping at tmin by more than tol: an overlap reported, at
**     tmin, its depth the deepest piece's within tol;
**   - else no contact reported: no piece is entered by more than tol
**     over the interval (a graze within tol may go either way);
**   - else a contact at t: no piece was entered by more than tol before
**     it (conservative), the shape is within tol of touching some piece
**     at t, the contact point lies on the piece named, at the radius
**     from the core (a sphere's centre), the normal along that offset.
** Returns 1 for a contact, 0 for none.
*/
static int check_sweep(const kit *k, const ray_sweep *w, ld tol,
                       const char *what, int n)
{
    lsweep l = lsweep_of(w);
    ray_contact c;
    ld start = clearance_all(k, &l, l.t0, NULL);
    int rc = ray_intersect_sweep(k->s, w, NULL, &c);

    ck_assert_msg(rc == 0 || rc == 1, "%s %d: rc %d", what, n, rc);
    if (start < -tol) {
        ck_assert_msg(rc == 1 && (c.flags & RAY_CONTACT_OVERLAP) &&
                          c.t == w->tmin,
                      "%s %d: overlap by %Lg not reported (rc %d, flags %u)",
                      what, n, -start, rc, rc == 1 ? c.flags : 0u);
        ck_assert_msg(fabsl((ld)c.depth + start) <= tol, "%s %d: depth %.17g,"
                      " reference %.17Lg", what, n, c.depth, -start);
        return 1;
    }
    if (rc == 0) {
        ld pen = first_all(k, &l, -tol);
        ck_assert_msg(!(pen < HUGE_VALL), "%s %d: no contact, but the shape "
                      "goes %Lg deep at t = %.17Lg", what, n,
                      -clearance_all(k, &l, pen, NULL), pen);
        return 0;
    }
    {
        ld pen = first_all(k, &l, -tol), at = clearance_all(k, &l, (ld)c.t,
                                                             NULL);
        lvec x0 = ladd(l.a, lscale(l.d, (ld)c.t));
        lvec x1 = ladd(l.b, lscale(l.d, (ld)c.t)), core, off;
        ck_assert_msg(c.t >= w->tmin && c.t <= (double)l.t1, "%s %d: t %.17g "
                      "outside the interval", what, n, c.t);
        ck_assert_msg((ld)c.t <= pen, "%s %d: contact at %.17g, but the shape "
                      "is %Lg inside at %.17Lg", what, n, c.t, tol, pen);
        ck_assert_msg(at <= tol, "%s %d: contact at %.17g with the shape %Lg "
                      "from everything", what, n, c.t, at);
        if (c.flags & RAY_CONTACT_OVERLAP)
            return 1;
        ck_assert_msg(distance_to_named(k, c.geom_id, c.prim_id, c.inst_id,
                                        lv(c.p)) <= tol,
                      "%s %d: p %Lg off geometry %u, %u (instance %u)", what,
                      n, distance_to_named(k, c.geom_id, c.prim_id,
                                           c.inst_id, lv(c.p)),
                      c.geom_id, c.prim_id, c.inst_id);
        core = ref_segment(lv(c.p), x0, x1);
        off = lsub(core, lv(c.p));
        ck_assert_msg(fabsl(llen(off) - l.r) <= tol, "%s %d: p at %Lg from "
                      "the core, radius %Lg", what, n, llen(off), l.r);
        if (l.r > 1e3L * tol)
            ck_assert_msg(ldot(lunit(off), lv(c.n)) >= 1 - 1e-9L,
                          "%s %d: normal off the offset", what, n);
        ck_assert_msg(fabsl(llen(lv(c.n)) - 1) <= 1e-12L, "%s %d: n not "
                      "unit", what, n);
    }
    return 1;
}

/* ------------------------------------------------------------- tests */

/*
** The tolerance of a check, a distance: 2^-40 (9e-13) of the magnitudes
** in the library's bound, 20 (the scene's size) + r + |b - a| + |tmin
** dir|: the library's bound is 2 eps, eps = gamma(64) (M + r + |s| +
** |x0|) (ray_intersect_sweep(3)), 1.4e-14 of those magnitudes; the
** tests leave a factor 32 for the reference's own rounding (long double
** bisections, to 2^-64 relative) and M's reach.
*/
static ld tol_of(const ray_sweep *w)
{
    return 0x1p-40L * (20 + (ld)w->shape.radius + (ld)vdist(w->shape.a, w->shape.b) +
                       (ld)vlen(vscale(w->dir, w->tmin)));
}

/*
** Brute force: 240 sphere sweeps and 120 capsule sweeps from random
** points within 12 of the scene, toward random points of it (so most
** meet something), radii 0.05 to 3, over [0, 1] and [0.3, 1.5], at the
** origin and at 1e5.  Every check of check_sweep holds, and a good part
** of the sweeps have contacts (at least a third).
*/
START_TEST(sweeps_should_match_brute_force)
{
    kit k;
    rng g = {1234 + (uint64_t)_i};
    int i, contacts = 0;
    ray_vec3 o = vec(test_offset(_i), -test_offset(_i), test_offset(_i) / 2);

    kit_build(&k, o, 1);
    for (i = 0; i < 360; i++) {
        ray_sweep w;
        ray_vec3 from = vadd(o, rng_point(&g, -12, 12));
        ray_vec3 to = vadd(o, rng_point(&g, -6, 6));
        memset(&w, 0, sizeof w);
        w.shape.a = w.shape.b = from;
        if (i >= 240)
            w.shape.b = vadd(from, vscale(rng_dir(&g), rng_range(&g, 0.2, 3)));
        w.shape.radius = rng_range(&g, 0.05, 3);
        w.dir = vsub(to, from);
        if (i % 3 == 1) {
            w.tmin = 0.3;
            w.tmax = 1.5;
        }
        contacts += check_sweep(&k, &w, tol_of(&w), "sweep", i);
    }
    ck_assert_int_ge(contacts, 120);
    kit_free(&k);
}
END_TEST

/*
** Radii from 1e-6 to 1e3 of the scene (its size 20: 2e-5 to 2e4), 40
** sweeps each under make check-long, 12 under make check (issue 38),
** sphere and capsule, against the reference.
*/
START_TEST(sweeps_should_take_any_radius)
{
    static const double radius[6] = {2e-5, 2e-3, 0.2, 20, 2e3, 2e4};
    kit k;
    rng g = {99};
    int i, r, n = (int)test_count(NULL, 40, 12);

    kit_build(&k, vec(0, 0, 0), 0);
    for (r = 0; r < 6; r++)
        for (i = 0; i < n; i++) {
            ray_sweep w;
            ray_vec3 from = vscale(rng_dir(&g), 15 + 2 * radius[r]);
            memset(&w, 0, sizeof w);
            w.shape.a = w.shape.b = from;
            if (i % 2)
                w.shape.b = vadd(from, vscale(rng_dir(&g), 0.5));
            w.shape.radius = radius[r];
            w.dir = vsub(rng_point(&g, -4, 4), from);
            check_sweep(&k, &w, tol_of(&w), "radius", r * 100 + i);
        }
    kit_free(&k);
}
END_TEST

/* A flat wall of 10 x 10 quads (200 triangles, inner edges and
** vertices everywhere) in the plane z = 0 over [-5, 5]^2. */
static ray_scene *wall(void)
{
    ray_vec3 v[121];
    unsigned idx[600];
    ray_mesh m;
    ray_scene *s;
    int i, j;

    for (j = 0; j <= 10; j++)
        for (i = 0; i <= 10; i++)
            v[j * 11 + i] = vec(i - 5, j - 5, 0);
    for (j = 0; j < 10; j++)
        for (i = 0; i < 10; i++) {
            unsigned a = (unsigned)(j * 11 + i), *t = idx + 6 * (j * 10 + i);
            t[0] = a, t[1] = a + 1, t[2] = a + 12;
            t[3] = a, t[4] = a + 12, t[5] = a + 11;
        }
    memset(&m, 0, sizeof m);
    m.vertices = v;
    m.vertex_count = 121;
    m.indices = idx;
    m.triangle_count = 200;
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    return s;
}

/*
** Grazing: a sphere (or a lying capsule) sliding along the wall at
** exactly its radius, across the wall's inner edges and vertices, in 50
** directions, touches nothing (no "ghost" contact at an inner edge); a
** hair (1e-9 r) above, nothing; a hair below, an overlap of that depth;
** a path that sinks by 1e-3 over its length touches the face at the t
** where its centre is r above it, within the bound.
*/
START_TEST(sweeps_should_slide_along_a_wall)
{
    ray_scene *s = wall();
    rng g = {5};
    int i;

    for (i = 0; i < 50; i++) {
        double r = rng_range(&g, 0.1, 1), a = rng_range(&g, 0, 6.283185307179586);
        ray_vec3 from = vec(rng_range(&g, -2, 2), rng_range(&g, -2, 2), r);
        ray_sweep w;
        ray_contact c;
        memset(&w, 0, sizeof w);
        w.shape.a = w.shape.b = from;
        if (i % 2)
            w.shape.b = vadd(from, vec(0.3 * sin(a), 0.3 * cos(a), 0));
        w.shape.radius = r;
        w.dir = vec(2 * cos(a), 2 * sin(a), 0);
        ck_assert_msg(ray_intersect_sweep(s, &w, NULL, &c) == 0,
                      "slide %d: a contact at t %.17g, n (%g, %g, %g)", i,
                      c.t, c.n.x, c.n.y, c.n.z);
        w.shape.a.z = w.shape.b.z = r * (1 + 1e-9);
        ck_assert_int_eq(ray_intersect_sweep(s, &w, NULL, &c), 0);
        w.shape.a.z = w.shape.b.z = r * (1 - 1e-9);
        ck_assert_int_eq(ray_intersect_sweep(s, &w, NULL, &c), 1);
        ck_assert(c.flags & RAY_CONTACT_OVERLAP);
        ck_assert_double_eq_tol(c.depth, r * 1e-9, r * 1e-12);
        ck_assert_double_eq_tol(c.n.z, 1, 1e-12);
        /* Sinking: z = r + 1e-3 - 1e-3 t: the face at t = 1. */
        w.shape.a.z = w.shape.b.z = r + 1e-3;
        w.dir.z = -1e-3;
        w.tmax = 2;
        ck_assert_int_eq(ray_intersect_sweep(s, &w, NULL, &c), 1);
        ck_assert_msg(c.t <= 1 && c.t >= 1 - 1e-9, "sink %d: t %.17g", i, c.t);
        ck_assert_double_eq_tol(c.n.z, 1, 1e-12);
        ck_assert_double_eq_tol(c.p.z, 0, 1e-15);
    }
    ray_scene_free(s);
}
END_TEST

/*
** Starting in contact: a sphere at exactly its radius from the wall's
** face, from one of its inner edges and from one of its vertices (off
** the face's side, so that the edge or the vertex is the nearest
** feature: the sphere beyond the wall's border at x = 5), moving into
** it: a contact at tmin, depth 0, not an overlap; moving away or along:
** none.
*/
START_TEST(sweeps_should_start_in_contact)
{
    ray_scene *s = wall();
    ray_sweep w;
    ray_contact c;
    int k;

    for (k = 0; k < 3; k++) {
        /* Face: above (0.3, 0.2); the border edge x = 5 from beside it;
        ** the corner (5, 5, 0) from off its diagonal. */
        ray_vec3 from[3] = {{0.3, 0.2, 0.5}, {5.4, 0.3, 0.3}, {5.3, 5.4, 0}};
        ray_vec3 into[3] = {{0.1, 0, -1}, {-1, 0.2, -0.5}, {-0.3, -0.4, 0.1}};
        double r = k == 0 ? 0.5 : k == 1 ? 0.5 : 0.5;
        memset(&w, 0, sizeof w);
        w.shape.a = w.shape.b = from[k];
        w.shape.radius = r;
        w.dir = into[k];
        ck_assert_int_eq(ray_intersect_sweep(s, &w, NULL, &c), 1);
        ck_assert_msg(c.t == 0, "start %d: t %.17g", k, c.t);
        ck_assert_uint_eq(c.flags & RAY_CONTACT_OVERLAP, 0);
        ck_assert(c.depth == 0);
        w.dir = vscale(into[k], -1);
        ck_assert_int_eq(ray_intersect_sweep(s, &w, NULL, &c), 0);
    }
    ray_scene_free(s);
}
END_TEST

/*
** Radius 0 with a == b is ray_intersect: on the mixed scene, 500 random
** rays, the same answer bit for bit (t, p, ids; n the hit's normal
** turned against the ray) and the same misses.
*/
START_TEST(radius_zero_should_be_the_ray)
{
    kit k;
    rng g = {17};
    int i, hits = 0;

    kit_build(&k, vec(0, 0, 0), 1);
    for (i = 0; i < 500; i++) {
        ray_vec3 from = rng_point(&g, -12, 12);
        ray_ray r = ray_from(from, vsub(rng_point(&g, -6, 6), from));
        ray_sweep w;
        ray_contact c;
        ray_hit h;
        int a, b;
        memset(&w, 0, sizeof w);
        w.shape.a = w.shape.b = r.org;
        w.dir = r.dir;
        w.tmin = 0;
        w.tmax = HUGE_VAL;
        a = ray_intersect(k.s, &r, &h, NULL);
        b = ray_intersect_sweep(k.s, &w, NULL, &c);
        ck_assert_int_eq(a, b);
        if (!a)
            continue;
        hits++;
        ck_assert(memcmp(&c.t, &h.t, sizeof h.t) == 0);
        ck_assert(memcmp(&c.p, &h.p, sizeof h.p) == 0);
        ck_assert_uint_eq(c.geom_id, h.geom_id);
        ck_assert_uint_eq(c.prim_id, h.prim_id);
        ck_assert(vdot(c.n, r.dir) <= 0);
        ck_assert_double_eq_tol(fabs(vdot(c.n, h.n)), 1, 1e-15);
    }
    ck_assert_int_gt(hits, 100);
    kit_free(&k);
}
END_TEST

/*
** No tunnelling: spheres and capsules swept into closed meshes (an
** icosphere of 1280 triangles, the cube) aimed exactly at their
** vertices and at points of their edges, from outside toward the
** centre, radii from 1e-9 to 0.5, at 0, 1e5 and 1e6 from the origin:
** every sweep reports a contact no later than the t at which its core
** reaches the point aimed at (a shape there would be inside the mesh).
*/
START_TEST(sweeps_should_not_tunnel_through_closed_meshes)
{
    static const double offset[3] = {0, 1e5, 1e6};
    static const double radius[4] = {1e-9, 1e-5, 0.01, 0.5};
    rng g = {2024};
    int m, oi, misses = 0, total = 0;

    for (oi = 0; oi < 3; oi++)
        for (m = 0; m < 2; m++) {
            ray_vec3 o = vec(offset[oi], offset[oi] * 0.7, -offset[oi] * 0.3);
            hc_mesh h = m == 0 ? hc_icosphere(o, 3) : hc_cube(o);
            ray_mesh mesh = hc_ray_mesh(&h);
            ray_scene *s;
            size_t t;
            ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
            ck_assert_int_eq(ray_scene_add_mesh(s, &mesh, RAY_NO_MATERIAL, NULL), RAY_OK);
            ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
            for (t = 0; t < h.nt; t += m == 0 ? 7 : 1) {
                int e;
                for (e = 0; e < 4; e++) {
                    ray_vec3 p0 = h.v[h.idx[3 * t + (size_t)(e % 3)]];
                    ray_vec3 p1 = h.v[h.idx[3 * t + (size_t)((e + 1) % 3)]];
                    ray_vec3 aim = e == 3 ? p0 : vadd(p0, vscale(vsub(p1, p0), rng_unit(&g)));
                    ray_vec3 out = vsub(aim, o), from;
                    ray_sweep w;
                    ray_contact c;
                    double r = radius[(t + (size_t)e) % 4];
                    int rc;
                    /* From 3 units out, along a direction tilted up to
                    ** 30 degrees off the radial one. */
                    out = vscale(out, 1 / vlen(out));
                    out = vadd(out, vscale(rng_dir(&g), 0.5));
                    from = vadd(aim, vscale(out, 3 / vlen(out)));
                    memset(&w, 0, sizeof w);
                    w.shape.a = w.shape.b = from;
                    if (e % 2)
                        w.shape.b = vadd(from, vscale(out, 0.5 / vlen(out)));
                    w.shape.radius = r;
                    w.dir = vsub(aim, from);
                    w.tmax = 2;
                    rc = ray_intersect_sweep(s, &w, NULL, &c);
                    total++;
                    if (rc != 1 || !(c.t <= 1))
                        misses++;
                }
            }
            ray_scene_free(s);
            hc_mesh_free(&h);
        }
    ck_assert_int_gt(total, 2000);
    ck_assert_int_eq(misses, 0);
}
END_TEST

/* ------------------------------------------------------- instances */

/*
** Instances: 8 placements of a child of a mesh (an icosahedron), a box
** and the L polygon under random affine maps (scales 0.4 to 2.5 per
** axis, shears, reflections), and 4 of a child of a sphere and a capsule
** under similarities (a rotation, a uniform scale, a reflection), swept
** by 200 spheres and capsules against the brute force over every piece
** taken to world space in long double: exact through any transform for
** the polytopes, through similarities for the round kinds.  200 sweeps
** under make check-long, the first 60 of them under make check (issue
** 38: the brute force took 8 of the suite's 13 s); a quarter of them
** at least meet something.
*/
START_TEST(sweeps_should_be_exact_through_instances)
{
    ray_scene *child[2];
    kit k;
    rng g = {808};
    int i, contacts = 0, n = (int)test_count(NULL, 200, 60);

    kit_build_instanced(&k, &g, child);
    for (i = 0; i < n; i++) {
        ray_sweep w;
        ray_vec3 from = rng_point(&g, -18, 18), to = rng_point(&g, -12, 12);
        memset(&w, 0, sizeof w);
        w.shape.a = w.shape.b = from;
        if (i % 2)
            w.shape.b = vadd(from, vscale(rng_dir(&g), rng_range(&g, 0.2, 2)));
        w.shape.radius = rng_range(&g, 0.05, 1.5);
        w.dir = vsub(to, from);
        contacts += check_sweep(&k, &w, tol_of(&w), "instance", i);
    }
    ck_assert_int_ge(contacts, n / 4);
    kit_free(&k);
    ray_scene_free(child[0]);
    ray_scene_free(child[1]);
}
END_TEST

/*
** Through a transform that is not a similarity a sphere is an ellipsoid
** and a capsule an ellipsoid swept along a segment: spheres and
** capsules swept toward them (40 each) meet them, the contact point's
** preimage lies on the sphere or capsule (within 1e-12), at the radius
** from the core, and no point of a sample of the surface (40 x 80
** directions of the preimage, mapped) comes within the radius less the
** tolerance of the core at 5 times up to the contact (conservative).
** A capsule swept against such a capsule answers by its box, flagged.
*/
START_TEST(sweeps_should_meet_ellipsoids)
{
    const ld pi = 3.14159265358979323846L;
    ray_scene *child[2], *top[2];
    ray_capsule_params cap;
    ray_transform xf;
    rng g = {4242};
    int kind, i, bounds = 0;

    ray_transform_identity(&xf);
    xf.m[0][0] = 2.5;
    xf.m[0][1] = 0.7;
    xf.m[1][1] = 0.6;
    xf.m[2][2] = 1.3;
    xf.m[2][0] = -0.4;
    xf.m[0][3] = 1;
    cap.a = vec(-0.5, 0, 0);
    cap.b = vec(0.5, 0.5, 0.5);
    cap.radius = 0.5;
    for (kind = 0; kind < 2; kind++) {
        ck_assert_int_eq(ray_scene_new(&child[kind], NULL, NULL), RAY_OK);
        if (kind == 0)
            ck_assert_int_eq(ray_scene_add_sphere(child[kind], vec(0, 0, 0), 1, RAY_NO_MATERIAL, NULL), RAY_OK);
        else
            ck_assert_int_eq(ray_scene_add_capsule(child[kind], &cap, RAY_NO_MATERIAL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_commit(child[kind]), RAY_OK);
        ck_assert_int_eq(ray_scene_new(&top[kind], NULL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_instance(top[kind], child[kind], &xf, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_commit(top[kind]), RAY_OK);
    }
    for (kind = 0; kind < 2; kind++)
        for (i = 0; i < 40; i++) {
            ray_sweep w;
            ray_contact c;
            lvec y, e;
            ld tol, rr;
            int a, b, j, rc;
            memset(&w, 0, sizeof w);
            w.shape.a = w.shape.b = vadd(vec(1, 0, 0), vscale(rng_dir(&g), 6));
            if (i % 2)
                w.shape.b = vadd(w.shape.a, vscale(rng_dir(&g), 0.8));
            w.shape.radius = rng_range(&g, 0.1, 1);
            /* Toward the image of the centre (the segment's midpoint),
            ** within 0.1: inside (|L^-1|_2 < 2 keeps it within 0.2). */
            w.dir = vsub(vadd(kind == 0 ? vec(1, 0, 0) : vec(1.175, 0.15, 0.325),
                              rng_point(&g, -0.1, 0.1)), w.shape.a);
            tol = tol_of(&w);
            rc = ray_intersect_sweep(top[kind], &w, NULL, &c);
            ck_assert_int_eq(rc, 1);
            if (kind == 1 && i % 2) {
                ck_assert_uint_eq(c.flags, RAY_CONTACT_BOUNDS);
                bounds++;
                continue;
            }
            ck_assert_uint_eq(c.flags, 0);
            /* The preimage of p, on the surface. */
            {
                /* L = [[2.5, .7, 0], [0, .6, 0], [-.4, 0, 1.3]]: solved. */
                lvec q = lsub(lv(c.p), lv3(1, 0, 0));
                ld yy = q.y / 0.6L, xx = (q.x - 0.7L * yy) / 2.5L;
                ld zz = (q.z + 0.4L * xx) / 1.3L;
                y = lv3(xx, yy, zz);
            }
            rr = kind == 0 ? llen(y) - 1
                           : ldist(y, ref_segment(y, lv(cap.a), lv(cap.b))) - (ld)cap.radius;
            ck_assert_msg(fabsl(rr) <= 1e-12L, "kind %d sweep %d: preimage off by %Lg", kind, i, rr);
            {
                lvec x0 = ladd(lv(w.shape.a), lscale(lv(w.dir), (ld)c.t));
                lvec x1 = ladd(lv(w.shape.b), lscale(lv(w.dir), (ld)c.t));
                ld d = ldist(ref_segment(lv(c.p), x0, x1), lv(c.p));
                ck_assert_msg(fabsl(d - (ld)w.shape.radius) <= tol, "kind %d sweep %d: p at %Lg", kind, i, d);
            }
            for (j = 0; j <= 4; j++) {
                ld t = (ld)c.t * j / 4;
                lvec x0 = ladd(lv(w.shape.a), lscale(lv(w.dir), t));
                lvec x1 = ladd(lv(w.shape.b), lscale(lv(w.dir), t));
                int k2;
                for (k2 = 0; k2 <= (kind == 0 ? 0 : 4); k2++) {
                    lvec o = kind == 0 ? lv3(0, 0, 0)
                                       : ladd(lv(cap.a), lscale(lsub(lv(cap.b), lv(cap.a)), (ld)k2 / 4));
                    ld R = kind == 0 ? 1 : (ld)cap.radius;
                    for (a = 0; a < 40; a++)
                        for (b = 0; b < 80; b++) {
                            ld th = pi * (a + 0.5L) / 40, ph = 2 * pi * b / 80;
                            lvec wp;
                            e = ladd(o, lscale(lv3(sinl(th) * cosl(ph), sinl(th) * sinl(ph), cosl(th)), R));
                            wp = lv3(2.5L * e.x + 0.7L * e.y + 1, 0.6L * e.y, -0.4L * e.x + 1.3L * e.z);
                            ck_assert_msg(ldist(ref_segment(wp, x0, x1), wp) >= (ld)w.shape.radius - tol,
                                          "kind %d sweep %d: inside at t %Lg", kind, i, t);
                        }
                }
            }
        }
    ck_assert_int_eq(bounds, 20);
    for (kind = 0; kind < 2; kind++) {
        ray_scene_free(top[kind]);
        ray_scene_free(child[kind]);
    }
}
END_TEST

/*
** Masks and filters as for rays: a sweep with a mask that the icosphere
** does not share passes through it to the sphere behind; a filter that
** rejects the icosphere (ignore the shooter, by query_ud) does the same,
** and is handed the path with the candidate inside its interval.
*/
static int reject_named(void *ud, const ray_ray *r, const ray_hit *h, void *q)
{
    int *calls = ud;
    (*calls)++;
    ck_assert(h->t > r->tmin && h->t < r->tmax);
    return q == NULL || h->geom_id != *(const unsigned *)q;
}

START_TEST(sweeps_should_follow_masks_and_filters)
{
    kit k;
    ray_sweep w;
    ray_contact c;
    ray_query q;
    unsigned shooter = 0;
    int calls = 0;

    kit_build(&k, vec(0, 0, 0), 0);
    memset(&w, 0, sizeof w);
    w.shape.a = w.shape.b = vec(-6, 0.2, 0);
    w.shape.radius = 0.3;
    w.dir = vec(20, 0, 0);
    ck_assert_int_eq(ray_intersect_sweep(k.s, &w, NULL, &c), 1);
    ck_assert_uint_eq(c.geom_id, 0);
    ck_assert_int_eq(ray_scene_set_mask(k.s, 0, 2), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(k.s), RAY_OK);
    memset(&q, 0, sizeof q);
    q.ignore_mask = ~1u;
    ck_assert_int_eq(ray_intersect_sweep(k.s, &w, &q, &c), 1);
    ck_assert_uint_eq(c.geom_id, 1);                  /* the sphere behind */
    ck_assert_int_eq(ray_scene_set_mask(k.s, 0, ~0u), RAY_OK);
    ck_assert_int_eq(ray_scene_set_filter(k.s, 0, reject_named, &calls,
                                          RAY_FILTER_INTERSECT), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(k.s), RAY_OK);
    q.ignore_mask = 0;
    q.query_ud = &shooter;
    ck_assert_int_eq(ray_intersect_sweep(k.s, &w, &q, &c), 1);
    ck_assert_uint_eq(c.geom_id, 1);
    ck_assert_int_gt(calls, 0);
    q.query_ud = NULL;
    ck_assert_int_eq(ray_intersect_sweep(k.s, &w, &q, &c), 1);
    ck_assert_uint_eq(c.geom_id, 0);
    kit_free(&k);
}
END_TEST

/*
** Ties are broken by ids whatever the tree (ray.h: "Ties in t: the
** deeper overlap, then the lower (inst_id, geom_id, prim_id)").  A
** hexahedron's corners, several of them on the plane x = 0: a sphere of
** radius 0.5 falling from (0, 1000, 0) along -y first meets corner 5,
** (0, 1, 0), which triangles 2, 3, 5, 10 and 11 share; each one's
** contact there is the corner's own piece, so their t is the same
** double, and triangle 2 is the answer.  The box holding triangle 2 is
** entered a few ulps after that t when it is not grown by the narrow
** phase's skin (gamma(64) of the coordinates relative to the start,
** against the box's gamma(8) of its own): fuzz_live found a mesh
** refitted (ray_scene_update_mesh) answering triangle 2 and the same
** mesh built afresh answering 10 (5 here, without its filter).  The
** start is 1000 away so that the skin, about 7e-12, also exceeds what an
** instance's box already has to spare (2^-40 of the motion, 9e-13).
** Exact comparisons: a tie is bit for bit.
*/
static const unsigned hex_index[36] = {
    0, 2, 1, 1, 2, 3,   4, 5, 6, 5, 7, 6,   0, 1, 4, 1, 5, 4,
    2, 6, 3, 3, 6, 7,   0, 4, 2, 2, 4, 6,   1, 3, 5, 3, 7, 5
};

static ray_scene *hex_scene(const ray_vec3 *v, size_t triangles,
                            const unsigned *index)
{
    ray_scene *s;
    ray_mesh m;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    memset(&m, 0, sizeof m);
    m.vertices = v;
    m.vertex_count = 8;
    m.indices = index;
    m.triangle_count = triangles;
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    return s;
}

START_TEST(sweep_ties_should_go_to_the_lower_ids_whatever_the_tree)
{
    static const ray_vec3 v[8] = {
        {0, 2, 2}, {2, 0, -1}, {0, -1, 0}, {0, 0, 0},
        {0, 0, 0}, {0, 1, 0}, {0, 0, 10}, {0, 0, -1}
    };
    static const ray_vec3 before[8] = {
        {-1, -1, -1}, {1, -1, -1}, {-1, 1, -1}, {1, 1, -1},
        {-1, -1, 1}, {1, -1, 1}, {-1, 1, 1}, {1, 1, 1}
    };
    ray_scene *s = hex_scene(v, 12, hex_index);
    ray_scene *one = hex_scene(v, 1, hex_index + 3 * 2);
    ray_scene *top;
    ray_transform id;
    ray_contact c, alone;
    ray_mesh m;
    ray_sweep w;

    memset(&w, 0, sizeof w);
    w.shape.a = w.shape.b = vec(0, 1000, 0);
    w.shape.radius = 0.5;
    w.dir = vec(0, -1, 0);
    w.tmax = HUGE_VAL;
    ck_assert_int_eq(ray_intersect_sweep(one, &w, NULL, &alone), 1);
    ck_assert_int_eq(ray_intersect_sweep(s, &w, NULL, &c), 1);
    ck_assert_uint_eq(c.prim_id, 2);
    ck_assert(c.t == alone.t);
    /* Through an instance (identity: the child's own answer). */
    ck_assert_int_eq(ray_scene_new(&top, NULL, NULL), RAY_OK);
    ray_transform_identity(&id);
    ck_assert_int_eq(ray_scene_add_instance(top, s, &id, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    ck_assert_int_eq(ray_intersect_sweep(top, &w, NULL, &c), 1);
    ck_assert_uint_eq(c.inst_id, 0);
    ck_assert_uint_eq(c.prim_id, 2);
    ck_assert(c.t == alone.t);
    ray_scene_free(top);
    ray_scene_free(s);
    /* Refitted from other corners: the same answer. */
    s = hex_scene(before, 12, hex_index);
    memset(&m, 0, sizeof m);
    m.vertices = v;
    m.vertex_count = 8;
    m.indices = hex_index;
    m.triangle_count = 12;
    ck_assert_int_eq(ray_scene_update_mesh(s, 0, &m), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_intersect_sweep(s, &w, NULL, &c), 1);
    ck_assert_uint_eq(c.prim_id, 2);
    ck_assert(c.t == alone.t);
    ray_scene_free(s);
    ray_scene_free(one);
}
END_TEST

/*
** A sweep whose dir is near DBL_MAX: a sphere of radius 0.5 from the
** origin along (-DBL_MAX, 17.25, 17.25) reaches z = 16.75, the height
** of a 34.5-wide square's plane less the radius, at t = 16.75 / 17.25,
** with its centre at x = -1.7e308, nowhere near the square.  The face's
** edge functions there overflow to NaN, which compared as inside: the
** sweep reported a contact on the square at x = -1.7e308 whenever the
** square shared a box with a triangle 1e150 wide (fuzz_live found it
** as a refitted scene answering 1 where the same scene built afresh
** answered 0).  The big triangle, at y = 10, is met at x = -9e307,
** beyond its corners too: no contact at all.
*/
START_TEST(sweeps_should_not_touch_faces_beyond_their_corners)
{
    static const ray_vec3 square[4] = {
        {0, 0, 17.25}, {34.5, 0, 17.25}, {0, 34.5, 17.25},
        {34.5, 34.5, 17.25}
    };
    static const unsigned index[6] = {0, 1, 2, 1, 3, 2};
    ray_scene *s;
    ray_mesh m;
    ray_sweep w;
    ray_contact c;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    memset(&m, 0, sizeof m);
    m.vertices = square;
    m.vertex_count = 4;
    m.indices = index;
    m.triangle_count = 2;
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_add_triangle(s, vec(-1e150, 10, -1e150),
                                            vec(1e150, 10, -1e150),
                                            vec(0, 10, 1e150),
                                            RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    memset(&w, 0, sizeof w);
    w.shape.radius = 0.5;
    w.dir = vec(-DBL_MAX, 17.25, 17.25);
    ck_assert_int_eq(ray_intersect_sweep(s, &w, NULL, &c), 0);
    ray_scene_free(s);
}
END_TEST

/*
** The kinds with no sweep of their own answer against their box,
** flagged: a torus of major radius 1, minor 0.3 about z at the origin
** (box [-1.3, 1.3]^2 x [-0.3, 0.3]): a sphere of radius 0.2 falling
** from z = 2 onto its hole touches the box's top at t = (2 - 0.5) / 4,
** RAY_CONTACT_BOUNDS, and never gets through.
*/
START_TEST(other_kinds_should_answer_by_their_boxes)
{
    ray_scene *s;
    ray_torus_params tor;
    ray_sweep w;
    ray_contact c;

    tor.center = vec(0, 0, 0);
    tor.axis = vec(0, 0, 1);
    tor.major = 1;
    tor.minor = 0.3;
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_torus(s, &tor, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    memset(&w, 0, sizeof w);
    w.shape.a = w.shape.b = vec(0, 0, 2);
    w.shape.radius = 0.2;
    w.dir = vec(0, 0, -4);
    ck_assert_int_eq(ray_intersect_sweep(s, &w, NULL, &c), 1);
    ck_assert_uint_eq(c.flags, RAY_CONTACT_BOUNDS);
    /* The box is the torus's, rounded outward: within 1e-9 of 0.3. */
    ck_assert_double_eq_tol(c.t, (2 - 0.5) / 4, 1e-9);
    ck_assert_double_eq_tol(c.n.z, 1, 1e-12);
    ray_scene_free(s);
}
END_TEST

/*
** Misuse is a negated status, *c untouched: NULLs, NaN in any input, a
** negative or infinite radius, an unknown shape kind, an empty or
** reversed interval, an uncommitted scene, a scene changed since its
** commit, an instance whose scene changed; a box shape is not swept
** (-RAY_EKIND, after its params are checked as ray_box checks them).
** No motion is no misuse: the overlap test, here clear of the sphere (0).
*/
START_TEST(sweeps_should_refuse_misuse)
{
    ray_scene *s, *child, *top;
    ray_sweep w, bad;
    ray_contact c, ref;
    ray_transform xf;

    memset(&ref, 0xA5, sizeof ref);
    c = ref;
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1, RAY_NO_MATERIAL, NULL), RAY_OK);
    memset(&w, 0, sizeof w);
    w.shape.a = w.shape.b = vec(0, 0, 5);
    w.shape.radius = 0.5;
    w.dir = vec(0, 0, -5);
    ck_assert_int_eq(ray_intersect_sweep(s, &w, NULL, &c), -RAY_ESTATE);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_intersect_sweep(NULL, &w, NULL, &c), -RAY_EINVAL);
    ck_assert_int_eq(ray_intersect_sweep(s, NULL, NULL, &c), -RAY_EINVAL);
    ck_assert_int_eq(ray_intersect_sweep(s, &w, NULL, NULL), -RAY_EINVAL);
    bad = w, bad.shape.a.x = (double)NAN;
    ck_assert_int_eq(ray_intersect_sweep(s, &bad, NULL, &c), -RAY_EINVAL);
    bad = w, bad.shape.b.y = HUGE_VAL;
    ck_assert_int_eq(ray_intersect_sweep(s, &bad, NULL, &c), -RAY_EINVAL);
    bad = w, bad.dir.z = (double)NAN;
    ck_assert_int_eq(ray_intersect_sweep(s, &bad, NULL, &c), -RAY_EINVAL);
    bad = w, bad.shape.radius = -1;
    ck_assert_int_eq(ray_intersect_sweep(s, &bad, NULL, &c), -RAY_EINVAL);
    bad = w, bad.shape.radius = (double)NAN;
    ck_assert_int_eq(ray_intersect_sweep(s, &bad, NULL, &c), -RAY_EINVAL);
    bad = w, bad.shape.radius = HUGE_VAL;
    ck_assert_int_eq(ray_intersect_sweep(s, &bad, NULL, &c), -RAY_EINVAL);
    bad = w, bad.dir = vec(0, 0, 0);
    ck_assert_int_eq(ray_intersect_sweep(s, &bad, NULL, &c), 0);
    bad = w, bad.shape.kind = 2;
    ck_assert_int_eq(ray_intersect_sweep(s, &bad, NULL, &c), -RAY_EINVAL);
    bad = w, bad.shape.kind = ~0u;
    ck_assert_int_eq(ray_intersect_sweep(s, &bad, NULL, &c), -RAY_EINVAL);
    bad = w, bad.shape.kind = RAY_SHAPE_BOX;     /* box all zero: refused */
    ck_assert_int_eq(ray_intersect_sweep(s, &bad, NULL, &c), -RAY_EINVAL);
    bad.shape.box.half_extents = vec(1, 1, 1);
    bad.shape.box.axis_x = vec(1, 0, 0);
    bad.shape.box.axis_y = vec(0, 1, 0);
    ck_assert_int_eq(ray_intersect_sweep(s, &bad, NULL, &c), -RAY_EKIND);
    bad.dir = vec(0, 0, 0);
    ck_assert_int_eq(ray_intersect_sweep(s, &bad, NULL, &c), -RAY_EKIND);
    bad.shape.box.half_extents.y = (double)NAN;
    ck_assert_int_eq(ray_intersect_sweep(s, &bad, NULL, &c), -RAY_EINVAL);
    bad = w, bad.tmin = 1, bad.tmax = 1;
    ck_assert_int_eq(ray_intersect_sweep(s, &bad, NULL, &c), -RAY_EINVAL);
    bad = w, bad.tmin = 2, bad.tmax = 1;
    ck_assert_int_eq(ray_intersect_sweep(s, &bad, NULL, &c), -RAY_EINVAL);
    bad = w, bad.tmax = (double)NAN;
    ck_assert_int_eq(ray_intersect_sweep(s, &bad, NULL, &c), -RAY_EINVAL);
    bad = w, bad.tmin = -HUGE_VAL;
    ck_assert_int_eq(ray_intersect_sweep(s, &bad, NULL, &c), -RAY_EINVAL);
    ck_assert(memcmp(&c, &ref, sizeof c) == 0);
    /* tmax = +Inf is the usual unbounded sweep. */
    bad = w, bad.tmax = HUGE_VAL;
    ck_assert_int_eq(ray_intersect_sweep(s, &bad, NULL, &c), 1);
    ck_assert_double_eq_tol(c.t, 3.5 / 5, 1e-13);
    /* Changed since the commit. */
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(9, 0, 0), 1, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_intersect_sweep(s, &w, NULL, &c), -RAY_ESTATE);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    /* A stale instance. */
    ck_assert_int_eq(ray_scene_new(&child, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(child, vec(0, 0, 0), 1, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    ck_assert_int_eq(ray_scene_new(&top, NULL, NULL), RAY_OK);
    ray_transform_identity(&xf);
    ck_assert_int_eq(ray_scene_add_instance(top, child, &xf, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    ck_assert_int_eq(ray_intersect_sweep(top, &w, NULL, &c), 1);
    ck_assert_int_eq(ray_scene_add_sphere(child, vec(3, 0, 0), 1, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    ck_assert_int_eq(ray_intersect_sweep(top, &w, NULL, &c), -RAY_ESTATE);
    ray_scene_free(top);
    ray_scene_free(child);
    ray_scene_free(s);
}
END_TEST

/*
** Issue 38, defect 8: a swept capsule whose segment b - a has subnormal
** or tiny components (|b - a|^2 underflows to 0) against a box.  The
** capsule's axis computations divided by that zero, and a sweep that
** never comes near the box (radius 0.5 at z = 0, the box's top at
** z = -2, moving sideways) got a contact with a point at the box's far
** corner.  Such a capsule is within |b - a| (below 1e-153) of the sphere
** at a, so it must answer as that sphere does: no contact sideways, and
** straight down the contact at t = 1.5 on the top face.  Tolerance: the
** sweep's own inflation, gamma(64) of the magnitudes (about 8 ulps of
** 64; within 1e-13 of 1.5 here), and p on the face plane z = -2 within
** the same.
*/
START_TEST(capsules_with_subnormal_segments_should_sweep_as_their_sphere)
{
    static const ray_vec3 tiny[4] = {{1e-310, -1e-310, -1e-300},
                                     {1e-310, 0, 0},
                                     {0, 4e-320, 0},
                                     {-1e-300, 1e-300, 1e-300}};
    ray_box_params b;
    ray_scene *s;
    int i;

    b.center = vec(0, 0, -3);
    b.half_extents = vec(1, 1, 1);
    b.axis_x = vec(1, 0, 0);
    b.axis_y = vec(0, 1, 0);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_box(s, &b, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    for (i = 0; i < 4; i++) {
        ray_sweep sw;
        ray_contact c;
        memset(&sw, 0, sizeof sw);
        sw.shape.a = vec(0, 0, 0);
        sw.shape.b = tiny[i];
        sw.shape.radius = 0.5;
        sw.dir = vec(-1, -1, -1e-310);
        sw.tmax = 1;
        ck_assert_msg(ray_intersect_sweep(s, &sw, NULL, &c) == 0,
                      "segment %d: contact at t %g, p (%g %g %g)", i, c.t,
                      c.p.x, c.p.y, c.p.z);
        sw.dir = vec(0, 0, -1);
        sw.tmax = 10;
        ck_assert_int_eq(ray_intersect_sweep(s, &sw, NULL, &c), 1);
        ck_assert_double_eq_tol(c.t, 1.5, 1e-13);
        ck_assert_double_eq_tol(c.p.z, -2, 1e-13);
        ck_assert(fabs(c.p.x) <= 1e-13 && fabs(c.p.y) <= 1e-13);
        ck_assert_double_eq_tol(c.n.z, 1, 1e-13);
    }
    ray_scene_free(s);
}
END_TEST

/*
** Issue 38, documented answer: the radius-0 sweep against user geometry
** (ray_intersect_sweep(3), Kinds of geometry).  A sphere of radius 0 is
** a ray, so user geometry answers it by its own intersect callback: the
** unit square at z = 0 (inside a box of [-2, 2]^2 x [-1, 1]) is met at
** t = 5 exactly, its own point, no RAY_CONTACT_BOUNDS.  Any shape with
** a radius or a segment is answered against the box: a sphere of radius
** 1e-9 stops at the box's top, t = 4 - 1e-9 (within the sweep's
** inflation, gamma(64) of the magnitudes: 1e-12 here), flagged
** RAY_CONTACT_BOUNDS, and so does a capsule of radius 0.
*/
static void square_bounds(void *ud, ray_vec3 *lo, ray_vec3 *hi)
{
    (void)ud;
    *lo = vec(-2, -2, -1);
    *hi = vec(2, 2, 1);
}

static int square_hit(void *ud, const ray_ray *r, ray_hit *h)
{
    double t;
    ray_vec3 p;

    (void)ud;
    if (r->dir.z == 0)
        return 0;
    t = -r->org.z / r->dir.z;
    p = vec(r->org.x + t * r->dir.x, r->org.y + t * r->dir.y, 0);
    if (!(t > r->tmin && t < r->tmax) || fabs(p.x) > 1 || fabs(p.y) > 1)
        return 0;
    memset(h, 0, sizeof *h);
    h->t = t;
    h->p = p;
    h->n = vec(0, 0, 1);
    return 1;
}

START_TEST(radius_zero_sweeps_should_ask_user_geometry_itself)
{
    ray_user_geometry g;
    ray_scene *s;
    ray_sweep sw;
    ray_contact c;

    g.bounds = square_bounds;
    g.intersect = square_hit;
    g.ud = NULL;
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_user(s, &g, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    memset(&sw, 0, sizeof sw);
    sw.shape.a = sw.shape.b = vec(0.5, 0.25, 5);
    sw.dir = vec(0, 0, -1);
    sw.tmax = 10;
    ck_assert_int_eq(ray_intersect_sweep(s, &sw, NULL, &c), 1);
    ck_assert(c.t == 5);
    ck_assert(c.p.x == 0.5 && c.p.y == 0.25 && c.p.z == 0);
    ck_assert_uint_eq(c.flags, 0);
    /* Outside the square but inside its box: a ray passes. */
    sw.shape.a = sw.shape.b = vec(1.5, 0, 5);
    ck_assert_int_eq(ray_intersect_sweep(s, &sw, NULL, &c), 0);
    /* A radius: the box. */
    sw.shape.radius = 1e-9;
    ck_assert_int_eq(ray_intersect_sweep(s, &sw, NULL, &c), 1);
    ck_assert_double_eq_tol(c.t, 4 - 1e-9, 1e-12);
    ck_assert_uint_eq(c.flags, RAY_CONTACT_BOUNDS);
    /* A capsule of radius 0: the box too. */
    sw.shape.radius = 0;
    sw.shape.b = vec(1.5, 0.5, 5);
    ck_assert_int_eq(ray_intersect_sweep(s, &sw, NULL, &c), 1);
    ck_assert_double_eq_tol(c.t, 4, 1e-12);
    ck_assert_uint_eq(c.flags, RAY_CONTACT_BOUNDS);
    ray_scene_free(s);
}
END_TEST

/*
** No motion (dir 0) is the overlap test at tmin: a sphere or a capsule
** standing in a wall, in a floor mesh, inside a box, in a corner (the
** deeper of two), through a rotated and non-uniformly scaled instance of
** a box and through one of a sphere (an ellipsoid) reports the deepest
** overlap: t = tmin, RAY_CONTACT_OVERLAP, the depth and the normal that
** frees it, the same bits as a moving sweep's overlap at its start (the
** same computation).  Pushed by depth (plus 1e-9, far above the sweep's
** eps of about 1e-13 here and far below every feature) along n, the
** shape overlaps nothing (the corner takes two pushes); touching at
** exactly the radius is no overlap.  Depths and normals: tol_at (64 ulps
** of the coordinates' magnitude: a few dozen roundings on exact inputs),
** the ellipsoid's 1e-9 (its nearest point is iterated to within a few
** ulps of its semi-axes, ray__ellipsoid_closest, with 1e-9 to spare).
*/
typedef struct still_case {
    double a[3], b[3], r;        /* the shape, relative to o */
    double depth, n[3];          /* the expected overlap (depth 0: none) */
    int pushes;                  /* how many pushes free it */
} still_case;

START_TEST(zero_motion_should_report_the_deepest_overlap)
{
    static const still_case cases[] = {
        {{-2.8, 0, 2.5}, {-2.8, 0, 2.5}, 0.5, 0.3, {1, 0, 0}, 1},   /* wall */
        {{0, 0, 0.3}, {0, 0, 1.3}, 0.5, 0.2, {0, 0, 1}, 1},         /* floor */
        {{-1, -1, 0.1}, {1, -1, 0.1}, 0.5, 0.4, {0, 0, 1}, 1},      /* lying */
        {{3, 0.2, 1.7}, {3, 0.2, 1.7}, 0.2, 0.5, {0, 0, 1}, 1},     /* in box */
        {{-2.7, 0, 0.1}, {-2.7, 0, 0.1}, 0.5, 0.4, {0, 0, 1}, 2},   /* corner */
        {{0.2, 11.8, 1}, {0.2, 11.8, 1}, 0.5, 0.7, {0, 1, 0}, 1},   /* instance */
        {{2.3, -10, 3}, {2.3, -10, 3}, 0.5, 0.2, {1, 0, 0}, 1},     /* ellipsoid */
        {{0, 0, 3}, {0, 0, 3}, 0.5, 0, {0, 0, 0}, 0},               /* clear */
        {{0, 0, 0.5}, {1, 0, 0.5}, 0.5, 0, {0, 0, 0}, 0},           /* touching */
    };
    static const double floor_v[4][3] = {{-5, -5, 0}, {5, -5, 0}, {5, 5, 0},
                                         {-5, 5, 0}};
    static const double wall_v[4][3] = {{-3, -5, 0}, {-3, 5, 0}, {-3, 5, 5},
                                        {-3, -5, 5}};
    static const unsigned quad[6] = {0, 1, 2, 0, 2, 3};
    ray_vec3 o = vec(test_offset(_i), test_offset(_i) / 3, -test_offset(_i));
    ray_scene *s, *cbox, *cball;
    ray_vec3 fv[4], wv[4];
    ray_mesh m;
    ray_box_params b;
    ray_transform xf;
    size_t k;
    int j;

    for (j = 0; j < 4; j++) {
        fv[j] = vadd(o, vec(floor_v[j][0], floor_v[j][1], floor_v[j][2]));
        wv[j] = vadd(o, vec(wall_v[j][0], wall_v[j][1], wall_v[j][2]));
    }
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    memset(&m, 0, sizeof m);
    m.vertex_count = 4;
    m.indices = quad;
    m.triangle_count = 2;
    m.vertices = fv;
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, NULL), RAY_OK);
    m.vertices = wv;
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, NULL), RAY_OK);
    b.center = vadd(o, vec(3, 0, 1));
    b.half_extents = vec(1, 1, 1);
    b.axis_x = vec(1, 0, 0);
    b.axis_y = vec(0, 1, 0);
    ck_assert_int_eq(ray_scene_add_box(s, &b, RAY_NO_MATERIAL, NULL), RAY_OK);
    /* A unit box scaled by (2, 1, 1), turned 90 degrees about z (x -> y):
    ** |x| <= 1, |y - 10| <= 2, |z - 1| <= 1 about o. */
    ck_assert_int_eq(ray_scene_new(&cbox, NULL, NULL), RAY_OK);
    b.center = vec(0, 0, 0);
    ck_assert_int_eq(ray_scene_add_box(cbox, &b, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(cbox), RAY_OK);
    ray_transform_identity(&xf);
    xf.m[0][0] = 0, xf.m[0][1] = -1;
    xf.m[1][0] = 2, xf.m[1][1] = 0;
    xf.m[0][3] = o.x, xf.m[1][3] = o.y + 10, xf.m[2][3] = o.z + 1;
    ck_assert_int_eq(ray_scene_add_instance(s, cbox, &xf, NULL), RAY_OK);
    /* A unit sphere scaled by (2, 1, 1): an ellipsoid about (0, -10, 3). */
    ck_assert_int_eq(ray_scene_new(&cball, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(cball, vec(0, 0, 0), 1, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(cball), RAY_OK);
    ray_transform_identity(&xf);
    xf.m[0][0] = 2;
    xf.m[0][3] = o.x, xf.m[1][3] = o.y - 10, xf.m[2][3] = o.z + 3;
    ck_assert_int_eq(ray_scene_add_instance(s, cball, &xf, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);

    for (k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        const still_case *e = &cases[k];
        double tol = k == 6 ? 1e-9 : tol_at(test_offset(_i));
        ray_sweep w, moving;
        ray_contact c, cm, ref;
        int push;

        memset(&w, 0, sizeof w);
        w.shape.a = vadd(o, vec(e->a[0], e->a[1], e->a[2]));
        w.shape.b = vadd(o, vec(e->b[0], e->b[1], e->b[2]));
        w.shape.radius = e->r;
        w.tmin = 0.25;                 /* t = tmin, whatever tmin is */
        memset(&ref, 0xA5, sizeof ref);
        c = ref;
        if (e->depth == 0) {
            ck_assert_int_eq(ray_intersect_sweep(s, &w, NULL, &c), 0);
            ck_assert(memcmp(&c, &ref, sizeof c) == 0);
            continue;
        }
        ck_assert_int_eq(ray_intersect_sweep(s, &w, NULL, &c), 1);
        ck_assert(c.t == 0.25);
        ck_assert_uint_eq(c.flags & RAY_CONTACT_OVERLAP, RAY_CONTACT_OVERLAP);
        ck_assert_msg(fabs(c.depth - e->depth) <= tol,
                      "case %zu: depth %.17g, want %g", k, c.depth, e->depth);
        ck_assert_msg(fabs(c.n.x - e->n[0]) <= tol && fabs(c.n.y - e->n[1]) <= tol &&
                      fabs(c.n.z - e->n[2]) <= tol,
                      "case %zu: n (%g, %g, %g)", k, c.n.x, c.n.y, c.n.z);
        /* The moving sweep's overlap at its start (tmin 0: the shape
        ** where it stands): the same bits. */
        moving = w;
        moving.dir = vec(0.5, -1, 2);
        moving.tmin = 0;
        ck_assert_int_eq(ray_intersect_sweep(s, &moving, NULL, &cm), 1);
        ck_assert(cm.t == 0 && cm.depth == c.depth && cm.flags == c.flags);
        ck_assert(cm.n.x == c.n.x && cm.n.y == c.n.y && cm.n.z == c.n.z);
        ck_assert(cm.geom_id == c.geom_id && cm.prim_id == c.prim_id &&
                  cm.inst_id == c.inst_id);
        /* Pushed out along n by depth (and 1e-9): free. */
        for (push = 0; push < e->pushes; push++) {
            ray_vec3 d;
            ck_assert_int_eq(ray_intersect_sweep(s, &w, NULL, &c), 1);
            d = vscale(c.n, c.depth + 1e-9);
            w.shape.a = vadd(w.shape.a, d);
            w.shape.b = vadd(w.shape.b, d);
        }
        c = ref;
        ck_assert_msg(ray_intersect_sweep(s, &w, NULL, &c) == 0,
                      "case %zu: still overlapping after %d pushes", k,
                      e->pushes);
        ck_assert(memcmp(&c, &ref, sizeof c) == 0);
    }
    /* A point (radius 0) standing still: inside the box, 1 deep. */
    {
        ray_sweep w;
        ray_contact c;
        memset(&w, 0, sizeof w);
        w.shape.a = w.shape.b = vadd(o, vec(3, 0, 1));
        ck_assert_int_eq(ray_intersect_sweep(s, &w, NULL, &c), 1);
        ck_assert_uint_eq(c.flags, RAY_CONTACT_OVERLAP);
        ck_assert_double_eq_tol(c.depth, 1, tol_at(test_offset(_i)));
        /* On the floor's surface, a point overlaps nothing. */
        w.shape.a = w.shape.b = vadd(o, vec(0, 0, 0));
        ck_assert_int_eq(ray_intersect_sweep(s, &w, NULL, &c), 0);
    }
    ray_scene_free(s);
    ray_scene_free(cbox);
    ray_scene_free(cball);
}
END_TEST

/* ------------------------------------------------- the bound's both ends */

/* The distance from p to triangle abc in long double (Ericson, "Real-Time
** Collision Detection", 5.1.5: the closest point by its Voronoi region),
** all relative to the sweep's start, where the coordinates are small. */
static ld bound_dot(const ld *a, const ld *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static ld bound_tri_dist(const ld p[3], const ld a[3], const ld b[3],
                         const ld c[3])
{
    ld ab[3], ac[3], ap[3], bp[3], cp[3], q[3], d1, d2, d3, d4, d5, d6;
    ld va, vb, vc, v, w, sum = 0;
    int k;

    for (k = 0; k < 3; k++) {
        ab[k] = b[k] - a[k];
        ac[k] = c[k] - a[k];
        ap[k] = p[k] - a[k];
        bp[k] = p[k] - b[k];
        cp[k] = p[k] - c[k];
    }
    d1 = bound_dot(ab, ap);
    d2 = bound_dot(ac, ap);
    d3 = bound_dot(ab, bp);
    d4 = bound_dot(ac, bp);
    d5 = bound_dot(ab, cp);
    d6 = bound_dot(ac, cp);
    vc = d1 * d4 - d3 * d2;
    vb = d5 * d2 - d1 * d6;
    va = d3 * d6 - d5 * d4;
    for (k = 0; k < 3; k++) {
        if (d1 <= 0 && d2 <= 0)
            q[k] = a[k];
        else if (d3 >= 0 && d4 <= d3)
            q[k] = b[k];
        else if (vc <= 0 && d1 >= 0 && d3 <= 0)
            q[k] = a[k] + d1 / (d1 - d3) * ab[k];
        else if (d6 >= 0 && d5 <= d6)
            q[k] = c[k];
        else if (vb <= 0 && d2 >= 0 && d6 <= 0)
            q[k] = a[k] + d2 / (d2 - d6) * ac[k];
        else if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)
            q[k] = b[k] + (d4 - d3) / ((d4 - d3) + (d5 - d6)) *
                              (c[k] - b[k]);
        else {
            v = vb / (va + vb + vc);
            w = vc / (va + vb + vc);
            q[k] = a[k] + ab[k] * v + ac[k] * w;
        }
        sum += (p[k] - q[k]) * (p[k] - q[k]);
    }
    return sqrtl(sum);
}

/*
** The sweep's proven bound at both ends (ray_intersect_sweep(3)): moving
** the shape to the contact's t never puts it inside, and there it is
** within 2 eps of touching, eps = gamma(64) (M + radius) for a sphere
** from tmin 0 (M the largest coordinate of the features met, relative
** to a: here the triangle's three vertices, at least the library's M).
** Spheres of radius 0.01 to 10 swept at random triangles of size 0.1 to
** 100, aimed within 1.2 radii of a point in a face (kind 0), on an edge
** (1) or at a vertex (2), at 0, 1e5 and 1e6 from the origin; the shape's
** distance at t in long double, relative to a (where it is exact to
** 2^-64 of the coordinates, below 2^-8 eps).  Without the inflation
** (eps 0) the rounding puts the shape inside, and the test fails at its
** first sweep.  Cut to gamma(8), the inflation still covered the
** rounding of every sweep tried, so no test here fails on that cut
** (issue 38's closing note gives the search).
*/
/* 2000 sweeps for each offset and kind (0.2 s), or RAY_SWEEP_BOUND_SWEEPS:
** ten times as many found nothing more, so make check-long (which would
** run the whole sweep suite again) does not raise it. */
static size_t bound_sweeps(void)
{
    const char *v = getenv("RAY_SWEEP_BOUND_SWEEPS");

    return v != NULL && v[0] != '\0' ? (size_t)strtod(v, NULL) : 2000;
}

START_TEST(sweep_contact_should_be_outside_and_within_two_eps)
{
    static const double offsets[3] = {0, 1e5, 1e6};
    size_t n = bound_sweeps(), i, contacts = 0;
    int o, kind;

    for (o = 0; o < 3; o++)
        for (kind = 0; kind < 3; kind++) {
            rng g = {(uint64_t)(31 + 3 * o + kind)};
            ray_vec3 base = vec(offsets[o], -0.5 * offsets[o],
                                0.25 * offsets[o]);
            for (i = 0; i < n; i++) {
                ray_vec3 v[3], target, dir, side;
                double r = pow(10, rng_range(&g, -2, 1));
                double size = pow(10, rng_range(&g, -1, 2));
                double u = rng_unit(&g), w = rng_unit(&g), dist, m = 0;
                ray_scene *s;
                ray_sweep sw;
                ray_contact c;
                int k;
                for (k = 0; k < 3; k++)
                    v[k] = v3_add(base, v3_scale(rng_dir(&g), size));
                if (u + w > 1)
                    u = 1 - u, w = 1 - w;
                if (kind == 1)
                    w = 0;
                if (kind == 2)
                    u = w = 0;
                target = v3_add(v[0],
                                v3_add(v3_scale(v3_sub(v[1], v[0]), u),
                                       v3_scale(v3_sub(v[2], v[0]), w)));
                dir = rng_dir(&g);
                dist = r * rng_range(&g, 1.5, 20);
                side = v3_cross(dir, rng_dir(&g));
                side = v3_scale(side, 1 / v3_length(side));
                memset(&sw, 0, sizeof sw);    /* a capsule shape */
                sw.shape.a = v3_add(v3_sub(target, v3_scale(dir, dist)),
                              v3_scale(side, r * rng_range(&g, 0, 1.2)));
                sw.shape.b = sw.shape.a;
                sw.shape.radius = r;
                sw.dir = v3_scale(dir, 2 * dist);
                sw.tmin = 0;
                sw.tmax = 1;
                ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
                ck_assert_int_eq(ray_scene_add_triangle(s, v[0], v[1], v[2],
                                                        RAY_NO_MATERIAL,
                                                        NULL), RAY_OK);
                ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
                if (ray_intersect_sweep(s, &sw, NULL, &c) == 1 &&
                    !(c.flags & RAY_CONTACT_OVERLAP)) {
                    ld p[3], A[3], B[3], C[3], d, eps;
                    p[0] = (ld)c.t * (ld)sw.dir.x;
                    p[1] = (ld)c.t * (ld)sw.dir.y;
                    p[2] = (ld)c.t * (ld)sw.dir.z;
                    A[0] = (ld)v[0].x - (ld)sw.shape.a.x;
                    A[1] = (ld)v[0].y - (ld)sw.shape.a.y;
                    A[2] = (ld)v[0].z - (ld)sw.shape.a.z;
                    B[0] = (ld)v[1].x - (ld)sw.shape.a.x;
                    B[1] = (ld)v[1].y - (ld)sw.shape.a.y;
                    B[2] = (ld)v[1].z - (ld)sw.shape.a.z;
                    C[0] = (ld)v[2].x - (ld)sw.shape.a.x;
                    C[1] = (ld)v[2].y - (ld)sw.shape.a.y;
                    C[2] = (ld)v[2].z - (ld)sw.shape.a.z;
                    for (k = 0; k < 3; k++) {
                        ray_vec3 e = v3_sub(v[k], sw.shape.a);
                        m = fmax(m, fmax(fabs(e.x),
                                         fmax(fabs(e.y), fabs(e.z))));
                    }
                    /* gamma(64) = 64 u / (1 - 64 u), u = 2^-53. */
                    eps = 64 * 0x1p-53L / (1 - 64 * 0x1p-53L) *
                          ((ld)m + (ld)r);
                    d = bound_tri_dist(p, A, B, C) - (ld)r;
                    ck_assert_msg(d >= 0 && d <= 2 * eps,
                                  "offset %g, kind %d, sweep %zu: the "
                                  "shape at t is %Lg eps from touching",
                                  offsets[o], kind, i, d / eps);
                    contacts++;
                }
                ray_scene_free(s);
            }
        }
    /* Most sweeps meet the triangle: the test is not vacuous. */
    ck_assert_msg(contacts > 9 * n * 3 / 4, "%zu contacts of %zu", contacts,
                  9 * n);
}
END_TEST

Suite *sweep_suite(void)
{
    Suite *s = suite_create("sweep");
    TCase *tc = tcase_create("core");
    TCase *bound = tcase_create("bound");

    tcase_set_timeout(tc, 300);
    tcase_set_timeout(bound, 120);
    tcase_add_loop_test(tc, sweeps_should_match_brute_force, 0, N_OFFSETS);
    tcase_add_test(tc, sweeps_should_take_any_radius);
    tcase_add_test(tc, sweeps_should_slide_along_a_wall);
    tcase_add_test(tc, sweeps_should_start_in_contact);
    tcase_add_test(tc, radius_zero_should_be_the_ray);
    tcase_add_test(tc, sweeps_should_not_tunnel_through_closed_meshes);
    tcase_add_test(tc, sweeps_should_be_exact_through_instances);
    tcase_add_test(tc, sweeps_should_meet_ellipsoids);
    tcase_add_test(tc, sweeps_should_follow_masks_and_filters);
    tcase_add_test(tc, sweep_ties_should_go_to_the_lower_ids_whatever_the_tree);
    tcase_add_test(tc, sweeps_should_not_touch_faces_beyond_their_corners);
    tcase_add_test(tc, other_kinds_should_answer_by_their_boxes);
    tcase_add_test(tc, sweeps_should_refuse_misuse);
    tcase_add_test(tc, capsules_with_subnormal_segments_should_sweep_as_their_sphere);
    tcase_add_test(tc, radius_zero_sweeps_should_ask_user_geometry_itself);
    tcase_add_loop_test(tc, zero_motion_should_report_the_deepest_overlap, 0,
                        N_OFFSETS);
    tcase_add_test(bound, sweep_contact_should_be_outside_and_within_two_eps);
    suite_add_tcase(s, tc);
    suite_add_tcase(s, bound);
    return s;
}
