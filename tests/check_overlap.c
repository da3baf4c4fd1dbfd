/* SPDX-License-Identifier: MIT */
/*
** check_overlap.c -- ray_overlap_shape and its _all form: every
** primitive of the mixed scene (shapekit.h) that meets a sphere, a
** capsule or an oriented box, against brute force over every piece in
** long double (distances for the sphere and the capsule; separating
** axes computed by the test for the box), at the origin and at 1e5; instances through affine
** maps; ellipsoids; the kinds found by their boxes; masks; stopping;
** the array form's order, cap and count; misuse.
*/
#include <string.h>

#include "shapekit.h"

/* ------------------------------------------------------- reference */

/* A convex polytope for separating axes: its vertices, edge directions
** and face normals, in long double. */
typedef struct lpoly {
    lvec v[8], d[3], f[3];
    int nv, nd, nf;
} lpoly;

static lpoly lpoly_box(const ray_box_params *b)
{
    lpoly p;
    lvec e[3];
    ld h[3];
    int k;

    kit_box_frame(b, e, h);
    for (k = 0; k < 8; k++) {
        lvec x = lv(b->center);
        x = ladd(x, lscale(e[0], k & 1 ? h[0] : -h[0]));
        x = ladd(x, lscale(e[1], k & 2 ? h[1] : -h[1]));
        p.v[k] = ladd(x, lscale(e[2], k & 4 ? h[2] : -h[2]));
    }
    for (k = 0; k < 3; k++)
        p.d[k] = p.f[k] = e[k];
    p.nv = 8;
    p.nd = p.nf = 3;
    return p;
}

static lpoly lpoly_para(const lvec corner[8])
{
    lpoly p;
    int k;

    for (k = 0; k < 8; k++)
        p.v[k] = corner[k];
    p.d[0] = lsub(corner[1], corner[0]);
    p.d[1] = lsub(corner[2], corner[0]);
    p.d[2] = lsub(corner[4], corner[0]);
    for (k = 0; k < 3; k++)
        p.f[k] = lcross(p.d[(k + 1) % 3], p.d[(k + 2) % 3]);
    p.nv = 8;
    p.nd = p.nf = 3;
    return p;
}

static lpoly lpoly_tri(lvec a, lvec b, lvec c)
{
    lpoly p;

    p.v[0] = a;
    p.v[1] = b;
    p.v[2] = c;
    p.d[0] = lsub(b, a);
    p.d[1] = lsub(c, b);
    p.d[2] = lsub(a, c);
    p.f[0] = lcross(p.d[0], p.d[1]);
    p.nv = 3;
    p.nd = 3;
    p.nf = 1;
    return p;
}

/* The gap of the two on axis x (normalised): > 0 separated. */
static ld gap_on(const lpoly *a, const lpoly *b, lvec x)
{
    ld alo = HUGE_VALL, ahi = -HUGE_VALL, blo = HUGE_VALL, bhi = -HUGE_VALL;
    ld len = llen(x);
    int i;

    if (!(len > 1e-30L))
        return -HUGE_VALL;
    for (i = 0; i < a->nv; i++) {
        ld t = ldot(a->v[i], x) / len;
        alo = fminl(alo, t);
        ahi = fmaxl(ahi, t);
    }
    for (i = 0; i < b->nv; i++) {
        ld t = ldot(b->v[i], x) / len;
        blo = fminl(blo, t);
        bhi = fmaxl(bhi, t);
    }
    return fmaxl(blo - ahi, alo - bhi);
}

/* The largest gap over every candidate axis: > 0 disjoint, <= 0 they
** meet (a lower bound of how far apart, or minus how deep). */
static ld separation(const lpoly *a, const lpoly *b)
{
    ld best = -HUGE_VALL;
    int i, j;

    for (i = 0; i < a->nf; i++)
        best = fmaxl(best, gap_on(a, b, a->f[i]));
    for (i = 0; i < b->nf; i++)
        best = fmaxl(best, gap_on(a, b, b->f[i]));
    for (i = 0; i < a->nd; i++)
        for (j = 0; j < b->nd; j++)
            best = fmaxl(best, gap_on(a, b, lcross(a->d[i], b->d[j])));
    return best;
}

/* How far piece p is from the query (> 0: apart; <= 0: they meet): a
** distance less the radius for the sphere and the capsule (the piece's
** signed distance to the core, a point or a segment), a separation for
** the box. */
static ld apart(const piece *p, const ray_shape *sh)
{
    const ray_box_params *box = &sh->box;

    if (sh->kind != RAY_SHAPE_BOX)
        return kit_distance(p, lv(sh->a), lv(sh->b)) - (ld)sh->radius;
    {
        lpoly q = lpoly_box(box), t;
        piece qb;
        memset(&qb, 0, sizeof qb);
        qb.kind = PIECE_BOX;
        qb.box = *box;
        switch (p->kind) {
        case PIECE_TRI:
            t = lpoly_tri(p->a, p->b, p->c);
            return separation(&q, &t);
        case PIECE_PARA:
            t = lpoly_para(p->corner);
            return separation(&q, &t);
        case PIECE_BOX:
            t = lpoly_box(&p->box);
            return separation(&q, &t);
        case PIECE_SPHERE:
            return kit_box_signed(box, p->a) - p->R;
        case PIECE_CAPSULE:
            return kit_distance(&qb, p->a, p->b) - p->R;
        default: {
            ld lo = HUGE_VALL, hi = -HUGE_VALL;
            int k;
            for (k = 0; k < 8; k++) {
                ld h = ldot(lsub(q.v[k], p->a), p->b);
                lo = fminl(lo, h);
                hi = fmaxl(hi, h);
            }
            return fmaxl(lo, -hi);
        }
        }
    }
}

/* What a query found, by (inst, geom, prim), sorted as the library
** sorts them. */
typedef struct catch_list {
    ray_overlap o[512];
    size_t n;
} catch_list;

static int catch_one(void *ud, const ray_overlap *o)
{
    catch_list *c = ud;
    ck_assert_uint_lt(c->n, 512);
    c->o[c->n++] = *o;
    return 0;
}

static int found_in(const ray_overlap *o, size_t n, unsigned g, unsigned i,
                    unsigned in)
{
    size_t k;

    for (k = 0; k < n; k++)
        if (o[k].geom_id == g && o[k].prim_id == i && o[k].inst_id == in)
            return 1;
    return 0;
}

/*
** One query checked: the callback form and the _all form find the same
** primitives, each once; every piece the brute force puts more than tol
** inside the query is found, none more than tol outside is (pieces of
** one primitive -- the L polygon's triangles -- count as one: the
** nearest decides).
*/
static void check_query(const kit *k, const ray_shape *sh, ld tol, int n)
{
    catch_list got;
    ray_overlap all[512];
    size_t count, i, j;
    int rc;

    got.n = 0;
    rc = ray_overlap_shape(k->s, sh, NULL, catch_one, &got);
    ck_assert_int_eq(rc, (int)got.n);
    rc = ray_overlap_shape_all(k->s, sh, NULL, all, 512, &count);
    ck_assert_int_eq(rc, (int)count);
    ck_assert_uint_eq(count, got.n);
    for (i = 0; i < count; i++) {
        ck_assert(found_in(got.o, got.n, all[i].geom_id, all[i].prim_id,
                           all[i].inst_id));
        for (j = 0; j < i; j++)
            ck_assert_msg(!(all[j].geom_id == all[i].geom_id &&
                            all[j].prim_id == all[i].prim_id &&
                            all[j].inst_id == all[i].inst_id),
                          "query %d: found twice", n);
        if (i > 0)
            ck_assert(all[i - 1].inst_id < all[i].inst_id ||
                      (all[i - 1].inst_id == all[i].inst_id &&
                       (all[i - 1].geom_id < all[i].geom_id ||
                        (all[i - 1].geom_id == all[i].geom_id &&
                         all[i - 1].prim_id < all[i].prim_id))));
    }
    for (i = 0; i < k->n; i++) {
        const piece *p = &k->p[i];
        ld d = HUGE_VALL;
        for (j = 0; j < k->n; j++)
            if (k->p[j].geom_id == p->geom_id &&
                k->p[j].prim_id == p->prim_id &&
                k->p[j].inst_id == p->inst_id)
                d = fminl(d, apart(&k->p[j], sh));
        if (d < -tol)
            ck_assert_msg(found_in(all, count, p->geom_id, p->prim_id,
                                   p->inst_id),
                          "query %d: geometry %u, %u (instance %u) %Lg "
                          "inside, not found", n, p->geom_id, p->prim_id,
                          p->inst_id, -d);
        if (d > tol)
            ck_assert_msg(!found_in(all, count, p->geom_id, p->prim_id,
                                    p->inst_id),
                          "query %d: geometry %u, %u (instance %u) %Lg "
                          "apart, found", n, p->geom_id, p->prim_id,
                          p->inst_id, d);
    }
}

/* A random oriented box within "spread" of o, half-extents up to "h". */
static ray_box_params random_box(rng *g, ray_vec3 o, double spread, double h)
{
    ray_box_params b;

    b.center = vadd(o, rng_point(g, -spread, spread));
    b.half_extents = vec(rng_range(g, 0.05, h), rng_range(g, 0.05, h),
                         rng_range(g, 0.05, h));
    b.axis_x = rng_dir(g);
    b.axis_y = rng_dir(g);
    return b;
}

/*
** Brute force: 300 spheres (radius 0.05 to 4), 300 boxes (half
** extents up to 3, random orientations) and 300 capsules (segments up
** to 4 along each axis, radius 0.05 to 3: their reference is the long
** double distance of each piece to the segment, shapekit.h's
** kit_distance) among the mixed scene, at the origin and at 1e5;
** tolerance 2^-40 of 40 (the separations and
** distances are computed to a few ulps of coordinates below 20 relative
** to o, and o itself at 1e5 adds its ulp, 1.5e-11).
*/
START_TEST(overlaps_should_match_brute_force)
{
    kit k;
    rng g = {31 + (uint64_t)_i};
    ray_vec3 o = vec(test_offset(_i), test_offset(_i) / 3, -test_offset(_i));
    ld tol = 0x1p-40L * 40 + (ld)test_offset(_i) * 1e-15L;
    int i;

    kit_build(&k, o, 1);
    for (i = 0; i < 300; i++) {
        ray_vec3 c = vadd(o, rng_point(&g, -10, 10));
        check_query(&k, TK_SPHERE(c, rng_range(&g, 0.05, 4)), tol, i);
    }
    for (i = 0; i < 300; i++) {
        ray_box_params b = random_box(&g, o, 10, 3);
        check_query(&k, TK_BOX(&b), tol, 1000 + i);
    }
    for (i = 0; i < 300; i++) {
        ray_vec3 a = vadd(o, rng_point(&g, -10, 10));
        ray_vec3 b = vadd(a, rng_point(&g, -4, 4));
        check_query(&k, TK_CAPSULE(a, b, rng_range(&g, 0.05, 3)), tol,
                    2000 + i);
    }
    kit_free(&k);
}
END_TEST

/*
** Through instances: the child of a mesh, a box and the L polygon under 8
** random affine maps, the sphere-and-capsule child under 4 similarities
** (shapekit.h's kit_build_instanced, the world the sweeps' instance test
** uses too), 200 spheres, 200 boxes and 200 capsules.
*/
START_TEST(overlaps_should_be_exact_through_instances)
{
    ray_scene *child[2];
    kit k;
    rng g = {909};
    int i;

    kit_build_instanced(&k, &g, child);
    for (i = 0; i < 200; i++)
        check_query(&k, TK_SPHERE(rng_point(&g, -14, 14), rng_range(&g, 0.1, 3)),
                    0x1p-40L * 60, i);
    for (i = 0; i < 200; i++) {
        ray_box_params b = random_box(&g, vec(0, 0, 0), 14, 3);
        check_query(&k, TK_BOX(&b), 0x1p-40L * 60, 1000 + i);
    }
    for (i = 0; i < 200; i++) {
        ray_vec3 a = rng_point(&g, -14, 14);
        ray_vec3 b = vadd(a, rng_point(&g, -4, 4));
        check_query(&k, TK_CAPSULE(a, b, rng_range(&g, 0.1, 3)),
                    0x1p-40L * 60, 2000 + i);
    }
    kit_free(&k);
    ray_scene_free(child[0]);
    ray_scene_free(child[1]);
}
END_TEST

/*
** Ellipsoids: a unit sphere through diag(3, 1, 0.5) (rotated by 90
** degrees about z, moved to (10, 0, 0)) is the ellipsoid whose tips lie
** at (10, +-3, 0), (10 +- 1, 0, 0), (10, 0, +-0.5): a sphere of radius 1
** whose centre is 1 +- 1e-9 beyond a tip meets it or not; a box whose
** face is 1e-9 short of a tip or beyond it likewise; a capsule
** (a == b: the same sphere) through the same map, found as its swept
** ellipsoid.
*/
START_TEST(overlaps_should_meet_ellipsoids)
{
    static const double tip[3][3] = {{10, 3, 0}, {11, 0, 0}, {10, 0, 0.5}};
    static const double out[3][3] = {{0, 1, 0}, {1, 0, 0}, {0, 0, 1}};
    ray_scene *child[2], *top[2];
    ray_capsule_params cap;
    ray_transform xf;
    int kind, k;

    ray_transform_identity(&xf);
    xf.m[0][0] = 0;
    xf.m[0][1] = -1;
    xf.m[1][0] = 3;
    xf.m[1][1] = 0;
    xf.m[2][2] = 0.5;
    xf.m[0][3] = 10;
    cap.a = cap.b = vec(0, 0, 0);
    cap.radius = 1;
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
        for (k = 0; k < 3; k++) {
            ray_vec3 t = vec(tip[k][0], tip[k][1], tip[k][2]);
            ray_vec3 o = vec(out[k][0], out[k][1], out[k][2]);
            ray_box_params b;
            size_t n;
            ck_assert_int_eq(ray_overlap_shape_all(top[kind], TK_SPHERE(vadd(t, vscale(o, 1 - 1e-9)), 1), NULL, NULL, 0, &n), 1);
            ck_assert_int_eq(ray_overlap_shape_all(top[kind], TK_SPHERE(vadd(t, vscale(o, 1 + 1e-9)), 1), NULL, NULL, 0, &n), 0);
            b.axis_x = vec(1, 0, 0);
            b.axis_y = vec(0, 1, 0);
            b.half_extents = vec(1, 1, 1);
            b.center = vadd(t, vscale(o, 1 - 1e-9));
            ck_assert_int_eq(ray_overlap_shape_all(top[kind], TK_BOX(&b), NULL, NULL, 0, &n), 1);
            b.center = vadd(t, vscale(o, 1 + 1e-9));
            ck_assert_int_eq(ray_overlap_shape_all(top[kind], TK_BOX(&b), NULL, NULL, 0, &n), 0);
        }
    }
    for (kind = 0; kind < 2; kind++) {
        ray_scene_free(top[kind]);
        ray_scene_free(child[kind]);
    }
}
END_TEST

/*
** The rest: a torus found by its box (flagged); masks; a callback that
** stops the search after the first; the array form's cap (the first in
** id order) and count; misuse (negated statuses, nothing written).
*/
static int stop_now(void *ud, const ray_overlap *o)
{
    (void)o;
    (*(int *)ud)++;
    return 1;
}

START_TEST(overlaps_should_keep_their_rules)
{
    kit k;
    ray_torus_params tor;
    ray_overlap o[4], ref[4], big[256];
    ray_box_params b;
    ray_query q;
    size_t n = 77, m;
    ray_scene *loose;
    int calls = 0;
    unsigned id;

    kit_build(&k, vec(0, 0, 0), 0);
    tor.center = vec(0, 0, 20);
    tor.axis = vec(0, 0, 1);
    tor.major = 1;
    tor.minor = 0.3;
    ck_assert_int_eq(ray_scene_add_torus(k.s, &tor, RAY_NO_MATERIAL, &id), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(k.s), RAY_OK);
    /* The hole of the torus is inside its box. */
    ck_assert_int_eq(ray_overlap_shape_all(k.s, TK_SPHERE(vec(0, 0, 20), 0.1), NULL, o, 4, &n), 1);
    ck_assert_uint_eq(o[0].geom_id, id);
    ck_assert_uint_eq(o[0].flags, RAY_CONTACT_BOUNDS);
    /* A sphere about the box (2) that reaches the icosphere (0): the
    ** box found, then hidden by a mask. */
    ck_assert_int_ge(ray_overlap_shape_all(k.s, TK_SPHERE(vec(0, 4, -3), 3.2), NULL, big, 256, &n), 2);
    ck_assert(found_in(big, n, 2, 0, RAY_INVALID_ID));
    ck_assert(big[0].geom_id == 0);
    ck_assert_int_eq(ray_scene_set_mask(k.s, 2, 4), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(k.s), RAY_OK);
    memset(&q, 0, sizeof q);
    q.ignore_mask = ~3u;
    ck_assert_int_ge(ray_overlap_shape_all(k.s, TK_SPHERE(vec(0, 4, -3), 3.2), &q, big, 256, &n), 1);
    ck_assert(!found_in(big, n, 2, 0, RAY_INVALID_ID));
    /* Stop after the first. */
    ck_assert_int_eq(ray_overlap_shape(k.s, TK_SPHERE(vec(0, 0, 0), 30), NULL, stop_now, &calls), 1);
    ck_assert_int_eq(calls, 1);
    /* The cap keeps the first in id order. */
    ck_assert_int_gt(ray_overlap_shape_all(k.s, TK_SPHERE(vec(0, 0, 0), 30), NULL, ref, 0, &n), 4);
    m = n;
    ck_assert_int_eq(ray_overlap_shape_all(k.s, TK_SPHERE(vec(0, 0, 0), 30), NULL, o, 4, &n), (int)m);
    ck_assert_uint_eq(o[0].geom_id, 0);
    ck_assert_uint_eq(o[0].prim_id, 0);
    ck_assert_uint_eq(o[3].prim_id, 3);
    /* Misuse. */
    n = 77;
    b.center = vec(0, 0, 0);
    b.half_extents = vec(1, 1, 1);
    b.axis_x = vec(1, 0, 0);
    b.axis_y = vec(1, 0, 0);                  /* parallel: refused */
    ck_assert_int_eq(ray_overlap_shape(NULL, TK_SPHERE(vec(0, 0, 0), 1), NULL, stop_now, &calls), -RAY_EINVAL);
    ck_assert_int_eq(ray_overlap_shape(k.s, TK_SPHERE(vec(0, 0, 0), 1), NULL, NULL, NULL), -RAY_EINVAL);
    ck_assert_int_eq(ray_overlap_shape(k.s, TK_SPHERE(vec((double)NAN, 0, 0), 1), NULL, stop_now, &calls), -RAY_EINVAL);
    ck_assert_int_eq(ray_overlap_shape(k.s, TK_SPHERE(vec(0, 0, 0), -1), NULL, stop_now, &calls), -RAY_EINVAL);
    ck_assert_int_eq(ray_overlap_shape(k.s, TK_SPHERE(vec(0, 0, 0), HUGE_VAL), NULL, stop_now, &calls), -RAY_EINVAL);
    ck_assert_int_eq(ray_overlap_shape(k.s, TK_BOX(&b), NULL, stop_now, &calls), -RAY_EINVAL);
    ck_assert_int_eq(ray_overlap_shape(k.s, NULL, NULL, stop_now, &calls), -RAY_EINVAL);
    ck_assert_int_eq(ray_overlap_shape_all(k.s, TK_BOX(&b), NULL, o, 4, &n), -RAY_EINVAL);
    b.axis_y = vec(0, 1, 0);
    ck_assert_int_eq(ray_overlap_shape_all(k.s, TK_BOX(&b), NULL, NULL, 4, &n), -RAY_EINVAL);
    ck_assert_int_eq(ray_overlap_shape_all(k.s, TK_BOX(&b), NULL, o, 4, NULL), -RAY_EINVAL);
    ck_assert_int_eq(ray_overlap_shape_all(k.s, TK_SPHERE(vec(0, 0, 0), 1), NULL, NULL, 4, &n), -RAY_EINVAL);
    ck_assert_uint_eq(n, 77);
    ck_assert_int_eq(calls, 1);
    ck_assert_int_eq(ray_scene_new(&loose, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_overlap_shape_all(loose, TK_SPHERE(vec(0, 0, 0), 1), NULL, o, 4, &n), -RAY_ESTATE);
    ck_assert_int_eq(ray_scene_commit(loose), RAY_OK);
    ck_assert_int_eq(ray_overlap_shape_all(loose, TK_BOX(&b), NULL, o, 4, &n), 0);
    ck_assert_uint_eq(n, 0);
    ray_scene_free(loose);
    ck_assert_int_eq(ray_scene_add_sphere(k.s, vec(0, 0, 0), 1, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_overlap_shape(k.s, TK_BOX(&b), NULL, stop_now, &calls), -RAY_ESTATE);
    kit_free(&k);
}
END_TEST

/*
** Issue 38, defect 2: geometry and instances whose mask is 0 are hidden
** from every query (ray.h, "Masks and filters"), the default options'
** all-bits mask included: ray_intersect and the sweeps hide them, and so
** must the overlaps.  A sphere, a triangle and an instance (of a visible
** sphere) all at the origin, each with mask 0; with NULL options and with
** a zeroed ray_query (ignore_mask 0), nothing is found.  The same scene with the masks back
** to all bits finds all three (so the queries do reach them).
*/
START_TEST(overlaps_should_hide_mask_zero_by_default)
{
    ray_scene *s, *child;
    ray_transform id;
    ray_overlap o[4];
    ray_box_params b;
    ray_query q;
    ray_hit h;
    ray_ray r;
    size_t n = 77;
    unsigned sph, tri, inst;

    ck_assert_int_eq(ray_scene_new(&child, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(child, vec(0, 0, 0), 1, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1, RAY_NO_MATERIAL, &sph), RAY_OK);
    ck_assert_int_eq(ray_scene_add_triangle(s, vec(-1, -1, 0.5), vec(1, -1, 0.5), vec(0, 1, 0.5), RAY_NO_MATERIAL, &tri), RAY_OK);
    ray_transform_identity(&id);
    ck_assert_int_eq(ray_scene_add_instance(s, child, &id, &inst), RAY_OK);
    ck_assert_int_eq(ray_scene_set_mask(s, sph, 0), RAY_OK);
    ck_assert_int_eq(ray_scene_set_mask(s, tri, 0), RAY_OK);
    ck_assert_int_eq(ray_scene_set_mask(s, inst, 0), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    b.center = vec(0, 0, 0);
    b.half_extents = vec(2, 2, 2);
    b.axis_x = vec(1, 0, 0);
    b.axis_y = vec(0, 1, 0);
    memset(&q, 0, sizeof q);
    /* The ray queries hide them all. */
    r = make_ray(vec(0, 0, 10), vec(0, 0, -1), 0, HUGE_VAL);
    ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), 0);
    ck_assert_int_eq(ray_overlap_shape_all(s, TK_SPHERE(vec(0, 0, 0), 2), NULL, o, 4, &n), 0);
    ck_assert_uint_eq(n, 0);
    n = 77;
    ck_assert_int_eq(ray_overlap_shape_all(s, TK_SPHERE(vec(0, 0, 0), 2), &q, o, 4, &n), 0);
    ck_assert_uint_eq(n, 0);
    n = 77;
    ck_assert_int_eq(ray_overlap_shape_all(s, TK_BOX(&b), NULL, o, 4, &n), 0);
    ck_assert_uint_eq(n, 0);
    n = 77;
    ck_assert_int_eq(ray_overlap_shape_all(s, TK_BOX(&b), &q, o, 4, &n), 0);
    ck_assert_uint_eq(n, 0);
    n = 77;
    ck_assert_int_eq(ray_overlap_shape_all(s, TK_CAPSULE(vec(-1, 0, 0), vec(1, 0, 0), 1), NULL, o, 4, &n), 0);
    ck_assert_uint_eq(n, 0);
    n = 77;
    ck_assert_int_eq(ray_overlap_shape_all(s, TK_CAPSULE(vec(-1, 0, 0), vec(1, 0, 0), 1), &q, o, 4, &n), 0);
    ck_assert_uint_eq(n, 0);
    /* Masks back: all three found. */
    ck_assert_int_eq(ray_scene_set_mask(s, sph, ~0u), RAY_OK);
    ck_assert_int_eq(ray_scene_set_mask(s, tri, ~0u), RAY_OK);
    ck_assert_int_eq(ray_scene_set_mask(s, inst, ~0u), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_overlap_shape_all(s, TK_SPHERE(vec(0, 0, 0), 2), NULL, o, 4, &n), 3);
    ck_assert_int_eq(ray_overlap_shape_all(s, TK_BOX(&b), NULL, o, 4, &n), 3);
    ck_assert_int_eq(ray_overlap_shape_all(s, TK_CAPSULE(vec(-1, 0, 0), vec(1, 0, 0), 1), NULL, o, 4, &n), 3);
    ray_scene_free(s);
    ray_scene_free(child);
}
END_TEST

/*
** Issue 38, defect 1: a box region is refused where ray_box and
** ray_scene_add_box refuse the same params: here a centre of 1.7e308 and a
** half extent of 2^1021 (2.2e307, the largest ray_box takes) along x,
** whose far side (1.9e308) is past DBL_MAX.
** Both overlap calls return -RAY_EINVAL and leave *count and the
** callback alone.  The same box moved to the origin (2^1021 each side,
** inside DBL_MAX with the scene's rounding margin) is accepted by all.
*/
START_TEST(overlap_boxes_should_be_refused_as_ray_box_refuses_them)
{
    ray_scene *s;
    ray_overlap o[4];
    ray_box_params b;
    size_t n = 77;
    int calls = 0;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, 0), 1, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    b.center = vec(1.7e308, 0, 0);
    b.half_extents = vec(0x1p1021, 1, 1);
    b.axis_x = vec(1, 0, 0);
    b.axis_y = vec(0, 1, 0);
    ck_assert_int_eq(ray_scene_add_box(s, &b, RAY_NO_MATERIAL, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_overlap_shape(s, TK_BOX(&b), NULL, stop_now, &calls), -RAY_EINVAL);
    ck_assert_int_eq(ray_overlap_shape_all(s, TK_BOX(&b), NULL, o, 4, &n), -RAY_EINVAL);
    ck_assert_uint_eq(n, 77);
    ck_assert_int_eq(calls, 0);
    /* At the origin: accepted, and it holds the sphere. */
    b.center = vec(0, 0, 0);
    ck_assert_int_eq(ray_overlap_shape_all(s, TK_BOX(&b), NULL, o, 4, &n), 1);
    ck_assert_uint_eq(n, 1);
    ray_scene_free(s);
}
END_TEST

/* A new scene, not committed, holding the axis-aligned box of half
** extents 1 at the origin: its params in *b, its geometry id in *id. */
static ray_scene *unit_box_scene(ray_box_params *b, unsigned *id)
{
    ray_scene *s;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    b->center = vec(0, 0, 0);
    b->half_extents = vec(1, 1, 1);
    b->axis_x = vec(1, 0, 0);
    b->axis_y = vec(0, 1, 0);
    ck_assert_int_eq(ray_scene_add_box(s, b, RAY_NO_MATERIAL, id), RAY_OK);
    return s;
}

/*
** Issue 38, documented answer: which status wins when two apply (ray.h,
** "Shape queries" and each page's ERRORS).  The arguments are checked
** before the scene's state: a call with bad arguments on a scene that
** is not committed gets -RAY_EINVAL (RAY_EINVAL for ray_surface_point),
** and a call with good arguments -RAY_ESTATE.  ray_surface_point checks
** its pointers, then the state, then the ids and coordinates: an
** uncommitted scene answers RAY_ESTATE whatever the ids, and a kind
** without surface points answers RAY_EKIND (issue 37: its own status,
** not "not supported by this build") only for finite (u, v).
*/
START_TEST(statuses_should_follow_the_documented_order)
{
    ray_scene *s;
    ray_box_params b;
    ray_sweep sw;
    ray_contact c;
    ray_closest cl;
    ray_overlap o[1];
    ray_hit h;
    size_t n = 77;
    unsigned box;

    s = unit_box_scene(&b, &box);
    /* Not committed: bad arguments win. */
    ck_assert_int_eq(ray_overlap_shape_all(s, TK_SPHERE(vec((double)NAN, 0, 0), 1), NULL, o, 1, &n), -RAY_EINVAL);
    ck_assert_int_eq(ray_overlap_shape_all(s, TK_SPHERE(vec(0, 0, 0), 1), NULL, o, 1, &n), -RAY_ESTATE);
    ck_assert_int_eq(ray_closest_point(s, vec(0, 0, 0), -1, &cl), -RAY_EINVAL);
    ck_assert_int_eq(ray_closest_point(s, vec(0, 0, 0), 1, &cl), -RAY_ESTATE);
    memset(&sw, 0, sizeof sw);
    sw.shape.radius = -1;                     /* a bad radius */
    ck_assert_int_eq(ray_intersect_sweep(s, &sw, NULL, &c), -RAY_EINVAL);
    sw.shape.radius = 0;
    sw.dir = vec(0, 0, 0);   /* no motion: an overlap test, a good sweep */
    ck_assert_int_eq(ray_intersect_sweep(s, &sw, NULL, &c), -RAY_ESTATE);
    sw.dir = vec(0, 0, 1);
    ck_assert_int_eq(ray_intersect_sweep(s, &sw, NULL, &c), -RAY_ESTATE);
    /* A box shape is an argument the sweep does not take: its status
    ** before the state's. */
    sw.shape = box_shape(&b);
    ck_assert_int_eq(ray_intersect_sweep(s, &sw, NULL, &c), -RAY_EKIND);
    memset(&sw, 0, sizeof sw);
    ck_assert_int_eq(ray_surface_point(s, box, 0, RAY_INVALID_ID, 0, 0, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_surface_point(s, 99, 0, RAY_INVALID_ID, 0, 0, &h), RAY_ESTATE);
    ck_assert_uint_eq(n, 77);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    /* Committed: the ids before the kind, finite coordinates before
    ** the kind. */
    ck_assert_int_eq(ray_surface_point(s, 99, 0, RAY_INVALID_ID, 0, 0, &h), RAY_EINVAL);
    ck_assert_int_eq(ray_surface_point(s, box, 0, RAY_INVALID_ID, (double)NAN, 0, &h), RAY_EINVAL);
    hit_poison(&h);
    ck_assert_int_eq(ray_surface_point(s, box, 0, RAY_INVALID_ID, 0.5, 0.5, &h), RAY_EKIND);
    ck_assert(hit_is_poisoned(&h));
    ck_assert_str_eq(ray_strerror(RAY_EKIND),
                     "not available for this kind of geometry");
    ck_assert_int_ne(RAY_EKIND, RAY_ENOTSUP);
    ray_scene_free(s);
}
END_TEST

/*
** The capsule at its radius, exactly: one primitive of each kind alone
** in a scene moved to o (0 and 1e5 from the origin), and a capsule whose
** segment is r + delta from it (its nearest point an end, inside the
** segment, or against an edge), delta = -+ (1e-9 + 1e-14 |o|): found when
** nearer than its radius, not when farther.  delta is far above the
** tests' rounding (the distances are formed from coordinates below |o| +
** 8 with a few dozen roundings: 64 ulps of that, 1e-12 at 1e5, test_tol's
** bound) and far below any other feature, so either answer the other way
** is a wrong one.
*/
typedef struct near_case {
    int kind;                    /* 0 tri, 1 plane, 2 polygon, 3 box,
                                    4 sphere, 5 capsule, 6 mesh */
    double a[3], b[3];           /* the segment at delta 0, relative to o */
    double n[3];                 /* the direction delta moves it */
} near_case;

static void add_near_geometry(ray_scene *s, int kind, ray_vec3 o)
{
    static const double sq[4][3] = {{0, 0, 0}, {4, 0, 0}, {4, 4, 0},
                                    {0, 4, 0}};
    ray_vec3 v[4];
    ray_box_params b;
    ray_capsule_params c;
    ray_mesh m;
    unsigned idx[6] = {0, 1, 2, 0, 2, 3};
    int k;

    for (k = 0; k < 4; k++)
        v[k] = vadd(o, vec(sq[k][0], sq[k][1], sq[k][2]));
    switch (kind) {
    case 0:
        ck_assert_int_eq(ray_scene_add_triangle(s, v[0], v[1], v[2], RAY_NO_MATERIAL, NULL), RAY_OK);
        break;
    case 1:
        ck_assert_int_eq(ray_scene_add_plane(s, o, vec(0, 0, 1), RAY_NO_MATERIAL, NULL), RAY_OK);
        break;
    case 2:
        ck_assert_int_eq(ray_scene_add_polygon(s, v, 4, RAY_NO_MATERIAL, NULL), RAY_OK);
        break;
    case 3:
        b.center = vadd(o, vec(2, 2, -1));
        b.half_extents = vec(2, 2, 1);
        b.axis_x = vec(1, 0, 0);
        b.axis_y = vec(0, 1, 0);
        ck_assert_int_eq(ray_scene_add_box(s, &b, RAY_NO_MATERIAL, NULL), RAY_OK);
        break;
    case 4:
        ck_assert_int_eq(ray_scene_add_sphere(s, vadd(o, vec(2, 2, -1)), 1, RAY_NO_MATERIAL, NULL), RAY_OK);
        break;
    case 5:
        c.a = vadd(o, vec(0, 2, -0.5));
        c.b = vadd(o, vec(4, 2, -0.5));
        c.radius = 0.5;
        ck_assert_int_eq(ray_scene_add_capsule(s, &c, RAY_NO_MATERIAL, NULL), RAY_OK);
        break;
    default:
        memset(&m, 0, sizeof m);
        m.vertices = v;
        m.vertex_count = 4;
        m.indices = idx;
        m.triangle_count = 2;
        ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, NULL), RAY_OK);
        break;
    }
}

START_TEST(capsules_should_meet_at_their_radius_exactly)
{
    /* Every solid's top and every surface lies at z = 0 (relative to
    ** o) over [0, 4]^2; the sphere's top is (2, 2, 0), the capsule's
    ** axis runs along x at y = 2. */
    static const near_case cases[] = {
        {0, {1, 0.5, 0.5}, {2, 0.5, 0.5}, {0, 0, 1}},    /* over the face */
        {0, {1, 0.5, 0.5}, {1, 0.5, 3}, {0, 0, 1}},      /* its end */
        {0, {-0.5, -1, 0}, {-0.5, 5, 0}, {-1, 0, 0}},    /* past edge x=0 */
        {1, {-9, 3, 0.5}, {9, -3, 0.5}, {0, 0, 1}},
        {2, {1, 1, 0.5}, {3, 3, 0.5}, {0, 0, 1}},
        {2, {2, 4.5, -3}, {2, 4.5, 3}, {0, 1, 0}},       /* beside edge y=4 */
        {2, {5, -1, 0}, {4.5, 2, 0}, {1, 0, 0}},         /* its end, sideways */
        {3, {0.5, 1, 0.5}, {3.5, 3, 0.5}, {0, 0, 1}},
        {3, {4.5, -3, -1}, {4.5, 7, -1}, {1, 0, 0}},     /* beside face x=4 */
        {4, {-3, 2, 0.5}, {7, 2, 0.5}, {0, 0, 1}},       /* inside the segment */
        {4, {2, 2, 0.5}, {2, 2, 6}, {0, 0, 1}},          /* its end */
        {5, {2, -3, 0.5}, {2, 7, 0.5}, {0, 0, 1}},       /* crossing above */
        {5, {5, 2, -0.5}, {9, 2, -0.5}, {1, 0, 0}},      /* end to end */
        {6, {1, 1, 0.5}, {3, 1.5, 0.5}, {0, 0, 1}},
        {6, {-0.5, -1, 0}, {-0.5, 5, 0}, {-1, 0, 0}},
    };
    const double r = 0.5;
    ray_vec3 o = vec(test_offset(_i), test_offset(_i) / 3, -test_offset(_i));
    double delta = 1e-9 + 1e-14 * test_offset(_i);
    size_t c;

    for (c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        const near_case *k = &cases[c];
        ray_vec3 n = vec(k->n[0], k->n[1], k->n[2]);
        ray_vec3 a = vadd(o, vec(k->a[0], k->a[1], k->a[2]));
        ray_vec3 b = vadd(o, vec(k->b[0], k->b[1], k->b[2]));
        ray_scene *s;
        ray_overlap f[2];
        size_t cnt;
        int side;

        ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
        add_near_geometry(s, k->kind, o);
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        for (side = -1; side <= 1; side += 2) {
            ray_vec3 d = vscale(n, side * delta);
            int want = side < 0;
            /* (The mesh's segment over both its triangles finds two.) */
            ck_assert_msg((ray_overlap_shape_all(s, TK_CAPSULE(vadd(a, d), vadd(b, d), r), NULL, f, 2, &cnt) > 0) == want,
                          "case %zu, offset %g: %s its radius, %zu found", c,
                          test_offset(_i), want ? "within" : "beyond", cnt);
            if (want)
                ck_assert_uint_eq(f[0].flags, 0);
        }
        /* Reversed, the same segment: the same answers. */
        ck_assert_int_gt(ray_overlap_shape_all(s, TK_CAPSULE(vadd(b, vscale(n, -delta)), vadd(a, vscale(n, -delta)), r), NULL, NULL, 0, &cnt), 0);
        ck_assert_int_eq(ray_overlap_shape_all(s, TK_CAPSULE(vadd(b, vscale(n, delta)), vadd(a, vscale(n, delta)), r), NULL, NULL, 0, &cnt), 0);
        ray_scene_free(s);
    }
}
END_TEST

/*
** The shape's zero default and its refusals: ray_shape {0} is a point
** at the origin (a sphere of radius 0: found inside a solid and on a
** surface through the origin, not by a sphere beside it); a capsule
** through a non-similarity's capsule is found by its box, flagged; NaN
** ends, a negative or infinite radius, b - a past DBL_MAX, an unknown
** kind, a box ray_box refuses: -RAY_EINVAL, nothing written.
*/
START_TEST(shapes_should_default_and_refuse)
{
    ray_scene *s, *child, *top;
    ray_shape zero = {0}, bad;
    ray_capsule_params cap;
    ray_transform xf;
    ray_box_params b;
    ray_overlap f[4];
    size_t n = 77;
    unsigned g_box, g_tri;

    s = unit_box_scene(&b, &g_box);
    ck_assert_int_eq(ray_scene_add_triangle(s, vec(-5, -5, 0), vec(5, -5, 0), vec(0, 5, 0), RAY_NO_MATERIAL, &g_tri), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(3, 0, 0), 1, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_overlap_shape_all(s, &zero, NULL, f, 4, &n), 2);
    ck_assert_uint_eq(n, 2);
    ck_assert_uint_eq(f[0].geom_id, g_box);
    ck_assert_uint_eq(f[1].geom_id, g_tri);
    ck_assert_int_eq(ray_overlap_shape_all(s, TK_SPHERE(vec(0, 0, 0), 0), NULL, NULL, 0, &n), 2);
    /* Refused. */
    memset(f, 0xA5, sizeof f);
    n = 77;
    bad = zero, bad.a.x = (double)NAN;
    ck_assert_int_eq(ray_overlap_shape_all(s, &bad, NULL, f, 4, &n), -RAY_EINVAL);
    bad = zero, bad.b.z = (double)NAN;
    ck_assert_int_eq(ray_overlap_shape_all(s, &bad, NULL, f, 4, &n), -RAY_EINVAL);
    bad = zero, bad.b.y = HUGE_VAL;
    ck_assert_int_eq(ray_overlap_shape_all(s, &bad, NULL, f, 4, &n), -RAY_EINVAL);
    bad = zero, bad.a.x = -1e308, bad.b.x = 1e308;        /* b - a: Inf */
    ck_assert_int_eq(ray_overlap_shape_all(s, &bad, NULL, f, 4, &n), -RAY_EINVAL);
    bad = zero, bad.radius = -1;
    ck_assert_int_eq(ray_overlap_shape_all(s, &bad, NULL, f, 4, &n), -RAY_EINVAL);
    bad = zero, bad.radius = HUGE_VAL;
    ck_assert_int_eq(ray_overlap_shape(s, &bad, NULL, stop_now, NULL), -RAY_EINVAL);
    bad = zero, bad.radius = (double)NAN;
    ck_assert_int_eq(ray_overlap_shape_all(s, &bad, NULL, f, 4, &n), -RAY_EINVAL);
    bad = zero, bad.kind = 2;
    ck_assert_int_eq(ray_overlap_shape_all(s, &bad, NULL, f, 4, &n), -RAY_EINVAL);
    bad = zero, bad.kind = ~0u;
    ck_assert_int_eq(ray_overlap_shape(s, &bad, NULL, stop_now, NULL), -RAY_EINVAL);
    bad = zero, bad.kind = RAY_SHAPE_BOX;          /* a zero box */
    ck_assert_int_eq(ray_overlap_shape_all(s, &bad, NULL, f, 4, &n), -RAY_EINVAL);
    bad.box = b, bad.box.half_extents.z = 0;
    ck_assert_int_eq(ray_overlap_shape_all(s, &bad, NULL, f, 4, &n), -RAY_EINVAL);
    bad.box = b, bad.box.axis_y = vec(2, 0, 0);      /* parallel to x */
    ck_assert_int_eq(ray_overlap_shape_all(s, &bad, NULL, f, 4, &n), -RAY_EINVAL);
    ck_assert_uint_eq(n, 77);
    ck_assert_uint_eq(f[0].geom_id, 0xA5A5A5A5u);
    bad.box = b;                                     /* accepted again */
    ck_assert_int_eq(ray_overlap_shape_all(s, &bad, NULL, f, 4, &n), 2);
    ray_scene_free(s);

    /* A capsule through diag(3, 1, 0.5): a swept ellipsoid, which a
    ** capsule shape meets by its box (the image of [-1, 1]^3 about the
    ** segment [(0,0,0), (1,0,0)] scaled: x in [-3, 6], |y| <= 1,
    ** |z| <= 0.5), flagged; a sphere shape by its nearest point. */
    ck_assert_int_eq(ray_scene_new(&child, NULL, NULL), RAY_OK);
    cap.a = vec(0, 0, 0);
    cap.b = vec(1, 0, 0);
    cap.radius = 1;
    ck_assert_int_eq(ray_scene_add_capsule(child, &cap, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    ck_assert_int_eq(ray_scene_new(&top, NULL, NULL), RAY_OK);
    ray_transform_identity(&xf);
    xf.m[0][0] = 3;
    xf.m[2][2] = 0.5;
    ck_assert_int_eq(ray_scene_add_instance(top, child, &xf, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    ck_assert_int_eq(ray_overlap_shape_all(top, TK_CAPSULE(vec(0, -3, 0.9), vec(0, 3, 0.9), 0.5), NULL, f, 4, &n), 1);
    ck_assert_uint_eq(f[0].flags, RAY_CONTACT_BOUNDS);
    ck_assert_int_eq(ray_overlap_shape_all(top, TK_CAPSULE(vec(0, -3, 1.1), vec(0, 3, 1.1), 0.5), NULL, f, 4, &n), 0);
    ck_assert_int_eq(ray_overlap_shape_all(top, TK_SPHERE(vec(0, 0, 0.9), 0.5), NULL, f, 4, &n), 1);
    ck_assert_uint_eq(f[0].flags, 0);
    ray_scene_free(top);
    ray_scene_free(child);
}
END_TEST

/* User geometry for the test below: the unit sphere around *ud. */
static void unit_bounds(void *ud, ray_vec3 *lo, ray_vec3 *hi)
{
    const ray_vec3 *c = (const ray_vec3 *)ud;

    *lo = vec(c->x - 1, c->y - 1, c->z - 1);
    *hi = vec(c->x + 1, c->y + 1, c->z + 1);
}

static int unit_hit(void *ud, const ray_ray *r, ray_hit *h)
{
    return ray_sphere(r, *(const ray_vec3 *)ud, 1.0, h);
}

/*
** Issue 38, the kinds without routines of their own (ray.h, "Shape
** queries" and ray_closest_point): a torus, an implicit surface (the same
** torus), a parametric surface, a Bezier patch (both the flat square
** [-1, 1]^2, z = 0) and user geometry (a unit sphere), each 10 apart
** along x, and a unit sphere at x = 50.  ray_closest_point skips the
** five: from (0, 0, 5) the sphere is nearest, at sqrt(50^2 + 5^2) - 1
** (within 4 ulps).  A sphere of radius 0.5 at each one's centre overlaps
** it by its box alone (RAY_CONTACT_BOUNDS) and nothing else; the real
** sphere by its surface (flags 0).  A sphere of radius 0.25 swept down
** from z = 5 meets each of the five at its box's top, flagged the same
** (the parametric and Bezier patches' boxes are grown a little for
** rounding: t within 1e-6 of 5 - 0.25 - the top of the box).
*/
START_TEST(box_found_kinds_should_say_so)
{
    static const double top[5] = {0.25, 0.25, 0, 0, 1};
    ray_torus_params tp = {{0, 0, 0}, {0, 0, 1}, 1, 0.25}, ti;
    ray_implicit_surface is;
    ray_parametric_surface ps;
    ray_user_geometry user;
    ray_vec3 cp[2][16], uc = vec(40, 0, 0);
    ray_closest cl;
    ray_scene *s;
    unsigned k;

    ti = tp, ti.center = vec(10, 0, 0);
    ck_assert_int_eq(ray__implicit_torus(&ti, &is), RAY_OK);
    for (k = 0; k < 16; k++) {
        cp[0][k] = vec(20 + (double)(k % 4) * 2 / 3 - 1, (double)(k / 4) * 2 / 3 - 1, 0);
        cp[1][k] = vec(cp[0][k].x + 10, cp[0][k].y, 0);
    }
    ck_assert_int_eq(ray_bezier_surface(cp[0], &ps), RAY_OK);
    memset(&user, 0, sizeof user);
    user.bounds = unit_bounds;
    user.intersect = unit_hit;
    user.ud = &uc;
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_torus(s, &tp, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_implicit(s, &is, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_parametric(s, &ps, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_bezier(s, cp[1], RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_user(s, &user, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(50, 0, 0), 1, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);

    ck_assert_int_eq(ray_closest_point(s, vec(0, 0, 5), HUGE_VAL, &cl), 1);
    ck_assert_uint_eq(cl.geom_id, 5);
    ck_assert_double_eq_tol(cl.distance, sqrt(2525.0) - 1, 4 * DBL_EPSILON * 50);
    for (k = 0; k < 6; k++) {
        ray_overlap o[2];
        size_t n = 0;

        ck_assert_int_eq(ray_overlap_shape_all(s, TK_SPHERE(vec(10.0 * k, 0, 0), 0.5), NULL, o, 2, &n), 1);
        ck_assert_msg(n == 1, "geometry %u: %zu found", k, n);
        ck_assert_uint_eq(o[0].geom_id, k);
        ck_assert_uint_eq(o[0].flags, k < 5 ? RAY_CONTACT_BOUNDS : 0u);
    }
    for (k = 0; k < 5; k++) {
        ray_sweep sw;
        ray_contact c;

        memset(&sw, 0, sizeof sw);
        sw.shape = sphere_shape(vec(10.0 * k, 0, 5), 0.25);
        sw.dir = vec(0, 0, -1);
        sw.tmax = 10;
        ck_assert_int_eq(ray_intersect_sweep(s, &sw, NULL, &c), 1);
        ck_assert_uint_eq(c.geom_id, k);
        ck_assert(c.flags & RAY_CONTACT_BOUNDS);
        ck_assert_msg(fabs(c.t - (4.75 - top[k])) <= 1e-6, "geometry %u: t %.17g",
                      k, c.t);
    }
    ray_scene_free(s);
}
END_TEST

Suite *overlap_suite(void)
{
    Suite *s = suite_create("overlap");
    TCase *tc = tcase_create("core");

    tcase_set_timeout(tc, 300);
    tcase_add_loop_test(tc, overlaps_should_match_brute_force, 0, N_OFFSETS);
    tcase_add_test(tc, overlaps_should_be_exact_through_instances);
    tcase_add_test(tc, overlaps_should_meet_ellipsoids);
    tcase_add_test(tc, overlaps_should_keep_their_rules);
    tcase_add_test(tc, overlaps_should_hide_mask_zero_by_default);
    tcase_add_test(tc, overlap_boxes_should_be_refused_as_ray_box_refuses_them);
    tcase_add_test(tc, statuses_should_follow_the_documented_order);
    tcase_add_loop_test(tc, capsules_should_meet_at_their_radius_exactly, 0,
                        N_OFFSETS);
    tcase_add_test(tc, shapes_should_default_and_refuse);
    tcase_add_test(tc, box_found_kinds_should_say_so);
    suite_add_tcase(s, tc);
    return s;
}
