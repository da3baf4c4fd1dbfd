/* SPDX-License-Identifier: MIT */
/*
** check_slips.c -- the gaps issue 38 found: one-line slips in the code
** that passed the whole suite.  Each test here was seen to fail on its
** slip (the closing note lists them):
**   1. batches against the single-ray calls, bit for bit, on scenes that
**      are not triangles alone (every kind, instances, a plane beside a
**      mesh), groups holding unusable rays, per-ray masks with and
**      without gates;
**   2. ray_surface_point round trips for every kind it serves, and its
**      p_err against the documented bound, near the origin and at 1e6;
**   3. ray_closest_point's normal through rotated and sheared instances;
**   4. where ray_spawn_to's segment ends, and a target on a surface;
**   5. sweeps sliding at their radius over a grid's inner vertices and
**      edges, flat and folded (the graze rule);
**   6. proven bounds tested in each regime of their derivation.
*/
#include <string.h>

#include "shapekit.h"

/* ------------------------------------------------- 1. batches vs rays */

/*
** rays[0 .. n - 1] through ray_intersect_batch and ray_occluded_batch,
** with one set of options for every ray (ray_batch.query = q_all, when qs
** is NULL) and with per-ray queries (ray_batch.queries = qs, or NULL:
** the defaults, when q_all is NULL too), must give what ray_intersect and
** ray_occluded give ray by ray, bit for bit (API notes 11).  Returns how
** many rays hit; the per-ray batches' counters (packets, single rays) are
** added to *st.
*/
static size_t batch_vs_single(const ray_scene *s, const ray_ray *rays,
                              size_t n, const ray_query *qs,
                              const ray_query *q_all, ray_stats *st,
                              const char *what)
{
    ray_hit *hs = malloc(n * sizeof *hs), *hb = malloc(n * sizeof *hb);
    int *rs = malloc(n * sizeof *rs), *os = malloc(n * sizeof *os);
    int *rb = malloc(n * sizeof *rb);
    ray_batch b;
    size_t i, hits = 0;
    int pass;

    ck_assert(hs != NULL && hb != NULL && rs != NULL && os != NULL &&
              rb != NULL);
    for (i = 0; i < n; i++) {
        const ray_query *q = qs != NULL ? &qs[i] : q_all;
        hit_poison(&hs[i]);
        rs[i] = ray_intersect(s, &rays[i], &hs[i], q);
        os[i] = ray_occluded(s, &rays[i], q);
        ck_assert_msg(rs[i] == os[i], "%s ray %zu: nearest %d, any %d",
                      what, i, rs[i], os[i]);
        hits += rs[i] == 1;
    }
    for (pass = 0; pass < 4; pass++) {
        for (i = 0; i < n; i++)
            hit_poison(&hb[i]), rb[i] = 7;
        memset(&b, 0, sizeof b);
        b.rays = rays;
        b.n = n;
        b.hits = hb;
        b.results = rb;
        if (pass < 2) {                     /* one set for every ray */
            b.query = q_all;
        } else {                            /* each ray its own */
            b.queries = qs;
            b.stats = st;
        }
        if (pass == 0 && qs == NULL)
            ck_assert_int_eq(ray_intersect_batch(s, &b), RAY_OK);
        else if (pass == 1 && qs == NULL)
            ck_assert_int_eq(ray_occluded_batch(s, &b), RAY_OK);
        else if (pass == 2 && (qs != NULL || q_all == NULL))
            ck_assert_int_eq(ray_intersect_batch(s, &b), RAY_OK);
        else if (pass == 3 && (qs != NULL || q_all == NULL))
            ck_assert_int_eq(ray_occluded_batch(s, &b), RAY_OK);
        else
            continue;
        for (i = 0; i < n; i++) {
            ck_assert_msg(rb[i] == rs[i],
                          "%s, %s, ray %zu: batch %d, single ray %d", what,
                          pass == 0 ? "ray_intersect_batch, one query"
                          : pass == 1 ? "ray_occluded_batch, one query"
                          : pass == 2 ? "ray_intersect_batch"
                                      : "ray_occluded_batch",
                          i, rb[i], rs[i]);
            if (pass % 2 == 0)
                ck_assert_msg(rs[i] == 1 ? hit_same(&hb[i], &hs[i])
                                         : hit_is_poisoned(&hb[i]),
                              "%s, ray %zu: the batch's hit record differs",
                              what, i);
        }
    }
    free(hs), free(hb), free(rs), free(os), free(rb);
    return hits;
}

/*
** n rays in coherent groups of eight (a 4 x 2 block of pixels, well
** within the packets' 8 degrees) from "eye" towards a grid of points
** spanning "span" around "at" in x and y: the groups packets may take.
*/
static ray_ray *camera_rays(ray_vec3 eye, ray_vec3 at, double span, size_t n)
{
    ray_ray *r = malloc(n * sizeof *r);
    size_t i, blocks = n / 8, side = (size_t)ceil(sqrt((double)blocks));

    ck_assert_ptr_nonnull(r);
    for (i = 0; i < n; i++) {
        size_t blk = i / 8, px = i % 8;
        double bx = side > 1 ? (double)(blk % side) / (double)(side - 1) - 0.5 : 0;
        double by = side > 1 ? (double)(blk / side) / (double)(side - 1) - 0.5 : 0;
        ray_vec3 to = vec(at.x + span * bx + 0.01 * (double)(px % 4),
                          at.y + span * by + 0.01 * (double)(px / 4), at.z);
        r[i] = ray_from(eye, vsub(to, eye));
    }
    return r;
}

/* A flat n x n grid of unit quads in z = z0 centred on the origin, as a
** mesh (two triangles a quad), committed in a scene of its own unless s
** is given (then added to it, not committed). */
static ray_scene *grid_scene(ray_scene *s, int n, double z0, double fold)
{
    ray_vec3 *v = malloc((size_t)((n + 1) * (n + 1)) * sizeof *v);
    unsigned *idx = malloc((size_t)(6 * n * n) * sizeof *idx);
    ray_mesh m;
    int i, j, own = s == NULL;

    ck_assert(v != NULL && idx != NULL);
    for (j = 0; j <= n; j++)
        for (i = 0; i <= n; i++) {
            double y = j - n / 2;
            /* fold > 0: a ridge along y = 0 (z falls by "fold" a unit on
            ** both sides); fold < 0: a valley. */
            v[j * (n + 1) + i] = vec(i - n / 2, y, z0 - fold * fabs(y));
        }
    for (j = 0; j < n; j++)
        for (i = 0; i < n; i++) {
            unsigned a = (unsigned)(j * (n + 1) + i), *t = idx + 6 * (j * n + i);
            t[0] = a, t[1] = a + 1, t[2] = a + (unsigned)n + 2;
            t[3] = a, t[4] = a + (unsigned)n + 2, t[5] = a + (unsigned)n + 1;
        }
    memset(&m, 0, sizeof m);
    m.vertices = v;
    m.vertex_count = (size_t)((n + 1) * (n + 1));
    m.indices = idx;
    m.triangle_count = (size_t)(2 * n * n);
    if (own)
        ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, NULL), RAY_OK);
    if (own)
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    free(v);
    free(idx);
    return s;
}

/*
** Committed scene s: the 2 x 2 grid mesh of grid_scene and geometry 1 (a
** plane or a sphere) beside it, "at" on it past the mesh.  Camera blocks
** "span" across aimed at "at", every ray of which must hit geometry 1
** both ways (nearest and any hit), then blocks aimed at the mesh, each
** batch against the single rays (batch_vs_single).  Nearest-hit packets
** take triangles alone, so every nearest group here must go ray by ray;
** any-hit packets take planes and a few spheres too, each lane testing
** them before the packet's walk of the triangles: a packet that skipped
** them misses the first blocks' rays.  Frees s.
*/
static void batches_beside_a_mesh(ray_scene *s, ray_vec3 at, double span,
                                  const char *what)
{
    ray_stats st;
    ray_ray *r;
    size_t n = 64, i;

    r = camera_rays(vec(0, 0, 10), at, span, n);
    memset(&st, 0, sizeof st);
    ck_assert_uint_eq(batch_vs_single(s, r, n, NULL, NULL, &st, what), n);
    for (i = 0; i < n; i++) {
        ray_hit h;
        ck_assert_int_eq(ray_intersect(s, &r[i], &h, NULL), 1);
        ck_assert_uint_eq(h.geom_id, 1);
    }
    free(r);
    r = camera_rays(vec(0, 0, 10), vec(0, 0, 0), 1.5, n);
    ck_assert_uint_eq(batch_vs_single(s, r, n, NULL, NULL, &st, what), n);
    /* Four batches of n rays each went through the stats: with packets,
    ** the two nearest ones ray by ray and the two any-hit ones in
    ** packets; without (no AVX2, or a scalar build), all ray by ray. */
    if (st.batch_packets == 0) {
        ck_assert_uint_eq(st.batch_single, 4 * n);
    } else {
        ck_assert_uint_eq(st.batch_single, 2 * n);
        ck_assert_uint_eq(st.batch_packets, 2 * n);
    }
    free(r);
    ray_scene_free(s);
}

/* A sphere beside a mesh: a scene of a few spheres and triangles.
** Blocks 0.3 across about the sphere's centre: every ray within 0.2 of
** it at z = 0, inside its radius. */
START_TEST(batches_should_see_a_sphere_beside_a_mesh)
{
    ray_scene *s;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    grid_scene(s, 2, 0, 0);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(3, 0, 0), 0.75,
                                          RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    batches_beside_a_mesh(s, vec(3, 0, 0), 0.3, "sphere beside a mesh");
}
END_TEST

/* A plane beside a mesh.  From (0, 0, 10) towards z = -4 at x in [3,
** 3.5]: 8 / 14 of the way down, at z = 0, x >= 1.7 is past the mesh's
** |x| <= 1. */
START_TEST(batches_should_see_a_plane_beside_a_mesh)
{
    ray_scene *s;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    grid_scene(s, 2, 0, 0);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, -4), vec(0, 0.1, 1),
                                         RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    batches_beside_a_mesh(s, vec(3.25, 0, -4), 0.5, "plane beside a mesh");
}
END_TEST

/*
** The mixed scenes of every kind (shapekit.h: meshes, a sphere, a box, a
** capsule, a polygon, lone triangles, a plane; and instances of them
** under rotations, scales and shears), at the origin and at 1e5: camera
** blocks across them and scattered rays, batch against single ray.
*/
START_TEST(batches_should_match_rays_in_mixed_scenes)
{
    kit k;
    ray_scene *child[2];
    rng g = {38};
    ray_ray *r;
    size_t n = 256, i, hits;
    ray_stats st;
    int which;

    memset(&st, 0, sizeof st);
    for (which = 0; which < 3; which++) {
        ray_vec3 o = which == 1 ? vec(1e5, -1e5, 1e5) : vec(0, 0, 0);
        if (which < 2)
            kit_build(&k, o, 1);
        else
            kit_build_instanced(&k, &g, child);
        r = camera_rays(vadd(o, vec(0.5, 1, 30)), vadd(o, vec(0, 0, 0)), 24, n);
        for (i = n / 2; i < n; i++)      /* half scattered */
            r[i] = ray_from(vadd(o, rng_point(&g, -8, 8)), rng_dir(&g));
        hits = batch_vs_single(k.s, r, n, NULL, NULL, &st, "mixed scene");
        ck_assert_uint_gt(hits, n / 8);
        free(r);
        kit_free(&k);
        if (which == 2)
            ray_scene_free(child[0]), ray_scene_free(child[1]);
    }
}
END_TEST

/*
** Unusable rays inside groups the packets take (a triangle-only grid,
** coherent blocks): an empty interval (tmax == tmin, tmax < tmin), a NaN
** tmin or tmax, a zero or NaN direction, an infinite origin, at each lane
** in turn.  Each must miss (as ray_intersect says: a ray that is not
** usable hits nothing), and the rest of its group answer as alone.
*/
START_TEST(batches_should_miss_unusable_rays_in_packets)
{
    ray_scene *s = grid_scene(NULL, 8, 0, 0);
    ray_stats st;
    ray_ray *r;
    size_t n = 8 * 8 * 7, i;
    int kind;

    memset(&st, 0, sizeof st);
    r = camera_rays(vec(0.3, 0.2, 10), vec(0, 0, 0), 6, n);
    for (i = 0; i < n; i++) {
        size_t grp = i / 8;
        kind = (int)(grp % 7);
        if (i % 8 != grp / 7 % 8)
            continue;                       /* lane grp/7 of each group */
        switch (kind) {
        case 0: r[i].tmax = r[i].tmin = 0.5; break;
        case 1: r[i].tmin = 2, r[i].tmax = 1; break;
        case 2: r[i].tmin = (double)NAN; break;
        case 3: r[i].tmax = (double)NAN; break;
        case 4: r[i].dir = vec(0, 0, 0); break;
        case 5: r[i].dir.y = (double)NAN; break;
        default: r[i].org.x = HUGE_VAL; break;
        }
    }
    /* Every usable ray hits the grid; the unusable ones must not. */
    ck_assert_uint_eq(batch_vs_single(s, r, n, NULL, NULL, &st,
                                      "unusable rays in groups"),
                      n - n / 8);
    /* The groups with an empty or NaN interval stay coherent: packets
    ** took them (else this test would not test the packets). */
#if defined(__x86_64__) || defined(_M_X64)
    if (st.batch_packets == 0)
        test_skip("batches_should_miss_unusable_rays_in_packets",
                  "no packets on this CPU (no AVX2): the single-ray path only");
#endif
    free(r);
    ray_scene_free(s);
}
END_TEST

/*
** Per-ray masks (ray_intersect_batch's queries) in a scene without any
** mask or filter (the ungated path) and in one with a mask set: mask 0
** sees nothing, all bits see everything, one bit sees what shares it;
** the batch as the single rays, in coherent groups whose masks differ.
*/
START_TEST(batches_should_follow_per_ray_masks)
{
    int gated;

    for (gated = 0; gated < 2; gated++) {
        ray_scene *s = grid_scene(NULL, 8, 0, 0);
        ray_query *qs;
        ray_stats st;
        ray_ray *r;
        size_t n = 8 * 16, i, hits;

        if (gated) {          /* the grid keeps bit 1 alone */
            ck_assert_int_eq(ray_scene_set_mask(s, 0, 1u), RAY_OK);
            ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        }
        r = camera_rays(vec(0.3, 0.2, 10), vec(0, 0, 0), 6, n);
        qs = malloc(n * sizeof *qs);
        ck_assert_ptr_nonnull(qs);
        for (i = 0; i < n; i++) {
            memset(&qs[i], 0, sizeof qs[i]);
            /* Groups that see nothing (every bit ignored), everything
            ** (the zeroed default), or mixed lane by lane. */
            switch (i / 8 % 4) {
            case 0: qs[i].ignore_mask = ~0u; break;
            case 1: break;
            case 2: qs[i].ignore_mask = i % 2 ? ~0u : 0; break;
            default: qs[i].ignore_mask = i % 2 ? ~2u : ~1u; break;
            }
        }
        memset(&st, 0, sizeof st);
        hits = batch_vs_single(s, r, n, qs, NULL, &st, gated ? "gated masks"
                                                             : "ungated masks");
        for (i = 0; i < n; i++) {
            ray_hit h;
            int want = qs[i].ignore_mask == ~0u ? 0
                       : gated && qs[i].ignore_mask == ~2u ? 0 : 1;
            ck_assert_msg(ray_intersect(s, &r[i], &h, &qs[i]) == want,
                          "%s scene, ray %zu ignoring mask %#x: not %d",
                          gated ? "gated" : "ungated", i, qs[i].ignore_mask,
                          want);
        }
        ck_assert_uint_eq(hits, gated ? n / 4 + n / 8 + n / 8
                                      : n / 4 + n / 8 + n / 4);
        /* One query ignoring every bit for all (the _n calls' q). */
        memset(&qs[0], 0, sizeof qs[0]);
        qs[0].ignore_mask = ~0u;
        ck_assert_uint_eq(batch_vs_single(s, r, n, NULL, &qs[0], NULL,
                                          "mask 0 for the batch"), 0);
        free(qs);
        free(r);
        ray_scene_free(s);
    }
}
END_TEST

/* ------------------------------------------ 2. ray_surface_point */

/* Does the box p +- e hold a point where the exact plane through a with
** normal nn (any length) passes?  The plane's signed distance over the
** box spans n.(p - a) +- |n|.e: the box meets it iff that span holds 0
** (long double: the inputs' products are exact to about 2^-64). */
static int box_meets_plane(ray_vec3 p, ray_vec3 e, lvec a, lvec nn)
{
    lvec d = lsub(lv(p), a);
    ld s = ldot(nn, d);
    ld w = fabsl(nn.x) * (ld)e.x + fabsl(nn.y) * (ld)e.y +
           fabsl(nn.z) * (ld)e.z;
    return fabsl(s) <= w;
}

/* Does the box p +- e hold a point of the sphere |x - c| = R?  It does
** iff its nearest and farthest points from c bracket R (the box is
** connected). */
static int box_meets_sphere(ray_vec3 p, ray_vec3 e, lvec c, ld R)
{
    ld pc[3] = {(ld)p.x - c.x, (ld)p.y - c.y, (ld)p.z - c.z};
    ld ec[3] = {(ld)e.x, (ld)e.y, (ld)e.z}, lo = 0, hi = 0;
    int k;

    for (k = 0; k < 3; k++) {
        ld a = fabsl(pc[k]) - ec[k], b = fabsl(pc[k]) + ec[k];
        if (a > 0)
            lo += a * a;
        hi += b * b;
    }
    return lo <= R * R && R * R <= hi;
}

/* The largest |component|. */
static double vmax_abs(ray_vec3 a)
{
    return fmax(fabs(a.x), fmax(fabs(a.y), fabs(a.z)));
}

/*
** The scene of the round trips, its geometry at "o": 0 a triangle, 1 an
** icosphere mesh (radius 1), 2 a sphere (radius 1.5), 3 a plane, 4 an
** L-shaped polygon (with "plane" 0, a triangle stands in for the plane,
** which instances refuse); and, for "inst", the same placed in a
** second scene through a rotation by 90 degrees about z (its entries 0
** and +-1: exact, so the long double references below hold through it
** too) and a translation by (3, -2, 1).
*/
static const double sp_tri[3][3] = {{0, 0, 0}, {2, 0, 0.5}, {0, 2, 1}};

static ray_scene *sp_scene(ray_vec3 o, int plane)
{
    hc_mesh ico = hc_icosphere(vadd(o, vec(5, 0, 0)), 1);
    ray_mesh m = hc_ray_mesh(&ico);
    ray_vec3 poly[6];
    ray_scene *s;
    int i;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_triangle(
                         s, vadd(o, vec(sp_tri[0][0], sp_tri[0][1], sp_tri[0][2])),
                         vadd(o, vec(sp_tri[1][0], sp_tri[1][1], sp_tri[1][2])),
                         vadd(o, vec(sp_tri[2][0], sp_tri[2][1], sp_tri[2][2])),
                         RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vadd(o, vec(0, 5, 0)), 1.5,
                                          RAY_NO_MATERIAL, NULL), RAY_OK);
    if (plane)
        ck_assert_int_eq(ray_scene_add_plane(s, vadd(o, vec(0, 0, -5)),
                                             vec(0.2, 0.1, 1), RAY_NO_MATERIAL,
                                             NULL), RAY_OK);
    else                 /* instances take no planes: a stand-in, id 3 */
        ck_assert_int_eq(ray_scene_add_triangle(s, vadd(o, vec(9, 9, 9)),
                                                vadd(o, vec(10, 9, 9)),
                                                vadd(o, vec(9, 10, 9)),
                                                RAY_NO_MATERIAL, NULL), RAY_OK);
    for (i = 0; i < 6; i++)
        poly[i] = vadd(o, vec(-6 + kit_l_uv[i][0], kit_l_uv[i][1],
                              0.5 * kit_l_uv[i][0]));
    ck_assert_int_eq(ray_scene_add_polygon(s, poly, 6, RAY_NO_MATERIAL, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    hc_mesh_free(&ico);
    return s;
}

/* Point x of the child through the instance's transform (exact). */
static lvec sp_map(int inst, lvec x)
{
    return inst ? lv3(-x.y + 3, x.x - 2, x.z + 1) : x;
}

/*
** Does hit h's box hold a point of the exact surface of geometry g at
** offset o (through the instance when "inst")?  The planes of the flat
** kinds; the sphere's own equation.
*/
static int sp_box_on_surface(const ray_scene *s, const ray_hit *h,
                             ray_vec3 o, int inst)
{
    lvec lo = lv(o);
    (void)s;
    switch (h->geom_id) {
    case 0: {
        lvec a = sp_map(inst, ladd(lo, lv3(0, 0, 0)));
        lvec b = sp_map(inst, ladd(lo, lv3(2, 0, 0.5L)));
        lvec c = sp_map(inst, ladd(lo, lv3(0, 2, 1)));
        return box_meets_plane(h->p, h->p_err, a, lcross(lsub(b, a), lsub(c, a)));
    }
    case 1: {
        hc_mesh ico = hc_icosphere(vadd(o, vec(5, 0, 0)), 1);
        const unsigned *t = ico.idx + 3 * h->prim_id;
        lvec a = sp_map(inst, lv(ico.v[t[0]]));
        lvec b = sp_map(inst, lv(ico.v[t[1]]));
        lvec c = sp_map(inst, lv(ico.v[t[2]]));
        int ok = box_meets_plane(h->p, h->p_err, a,
                                 lcross(lsub(b, a), lsub(c, a)));
        hc_mesh_free(&ico);
        return ok;
    }
    case 2:
        return box_meets_sphere(h->p, h->p_err,
                                sp_map(inst, ladd(lo, lv3(0, 5, 0))), 1.5L);
    case 3: {
        lvec nn = lv3(0.2L, 0.1L, 1);    /* the doubles 0.2 and 0.1 */
        nn.x = (ld)0.2, nn.y = (ld)0.1;
        if (inst)
            nn = lv3(-nn.y, nn.x, nn.z);
        return box_meets_plane(h->p, h->p_err,
                               sp_map(inst, ladd(lo, lv3(0, 0, -5))), nn);
    }
    default: {
        lvec a = sp_map(inst, ladd(lo, lv3(-6, 0, 0)));
        lvec b = sp_map(inst, ladd(lo, lv3(-4, 0, 1)));
        lvec c = sp_map(inst, ladd(lo, lv3(-6, 2, 0)));
        return box_meets_plane(h->p, h->p_err, a,
                               lcross(lsub(b, a), lsub(c, a)));
    }
    }
}

/*
** Round trips, at the origin and at 1e6, directly and through an
** instance: for every kind ray_surface_point serves, 40 points (u, v) of
** each; a ray aimed at the point p along -n from 0.25 away must hit the
** same geometry (same ids) at p, with the same n, u and v:
**   p: both records lie within their p_err of the exact surface, and the
**      ray, along the normal, crosses it within |p_err| of the aimed p;
**      the aim itself (org + 1 * (p - org)) rounds within an ulp of the
**      coordinates: so |dp| <= 2 |p_err| + |p_err of the hit| + 2 ulps,
**      taken as 4 (max p_err of both) + 4 ulps of |p| per component;
**   n: the same formula on the same corners for the flat kinds (equal),
**      the sphere's (p - c) / r: a dp of that size moves it by dp / r;
**   u, v: a triangle's barycentrics move by dp over its smallest height
**      (above 0.5 for these), a plane's coordinates by dp, a sphere's
**      longitude by dp / (2 pi r sin(pi v)), latitude by dp / (pi r):
**      all within dp / (r sin(pi v)) for r = 1.5, dp / 0.5 for the rest.
** And every p_err must hold a point of the exact surface (the documented
** bound), while staying within 64 ulps of the coordinates involved (a
** bound of 1e-6 would hold too, but ray_spawn would then skip geometry
** thinner than it).
*/
START_TEST(surface_points_should_round_trip)
{
    rng g = {238};
    int where;

    for (where = 0; where < 4; where++) {
        ray_vec3 o = where % 2 ? vec(1e6, -1e6, 1e6) : vec(0, 0, 0);
        int inst = where >= 2;
        ray_scene *child = sp_scene(o, !inst), *s = child;
        unsigned inst_id = RAY_INVALID_ID, gid;
        int k, done[5] = {0};

        if (inst) {
            ray_transform xf;
            memset(&xf, 0, sizeof xf);
            xf.m[0][1] = -1, xf.m[1][0] = 1, xf.m[2][2] = 1;
            xf.m[0][3] = 3, xf.m[1][3] = -2, xf.m[2][3] = 1;
            ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
            ck_assert_int_eq(ray_scene_add_instance(s, child, &xf, &inst_id),
                             RAY_OK);
            ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        }
        for (gid = 0; gid < 5; gid++)
            for (k = 0; k < 40 && !(inst && gid == 3); k++) {
                double u = rng_range(&g, 0.05, 0.95), v = rng_range(&g, 0.05, 0.95);
                unsigned prim = gid == 1 ? (unsigned)k * 7 % 80 : 0;
                ray_hit hs, h;
                ray_ray r;
                double mag, tol_p, tol_uv, tol_n;
                int rc;
                if (gid == 0 || gid == 1)
                    v *= 1 - u;             /* u + v <= 1 */
                else if (gid == 3)
                    u = 4 * u - 2, v = 4 * v - 2;
                else if (gid == 4)
                    u = 4 * u - 2, v = 4 * v - 2;
                rc = ray_surface_point(s, gid, prim, inst_id, u, v, &hs);
                if (gid == 4 && rc == RAY_EINVAL) {
                    continue;          /* outside the L (its tangents' */
                }                      /* (u, v) are the library's) */
                ck_assert_int_eq(rc, RAY_OK);
                done[gid]++;
                ck_assert_msg(sp_box_on_surface(s, &hs, o, inst),
                              "geom %u at %g, inst %d, (u, v) (%.17g, %.17g):"
                              " p_err (%g, %g, %g) holds no surface point",
                              gid, o.x, inst, u, v, hs.p_err.x, hs.p_err.y,
                              hs.p_err.z);
                mag = vmax_abs(hs.p) + 10;
                ck_assert_msg(vmax_abs(hs.p_err) <= 64 * DBL_EPSILON * mag,
                              "geom %u at %g: p_err %g beyond 64 ulps of %g",
                              gid, o.x, vmax_abs(hs.p_err), mag);
                r.org = vadd(hs.p, vscale(hs.n, 0.25));
                r.dir = vsub(hs.p, r.org);
                r.tmin = 0;
                r.tmax = 2;
                ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), 1);
                ck_assert_uint_eq(h.geom_id, gid);
                ck_assert_uint_eq(h.prim_id, prim);
                ck_assert_uint_eq(h.inst_id, inst_id);
                tol_p = 4 * (vmax_abs(hs.p_err) + vmax_abs(h.p_err)) +
                        4 * DBL_EPSILON * mag;
                tol_n = gid == 2 ? tol_p / 1.5 : 4 * DBL_EPSILON;
                tol_uv = gid == 2 ? tol_p / (1.5 * sin(3.141592653589793 * v))
                                  : tol_p / 0.5;
                ck_assert_vec_eq_tol(h.p, hs.p, tol_p);
                ck_assert_vec_eq_tol(h.n, hs.n, tol_n);
                ck_assert_msg(fabs(h.u - u) <= tol_uv && fabs(h.v - v) <= tol_uv,
                              "geom %u at %g inst %d: asked (%.17g, %.17g), "
                              "the ray found (%.17g, %.17g)", gid, o.x, inst,
                              u, v, h.u, h.v);
                ck_assert(hs.u == u && hs.v == v && hs.t == 0);
            }
        for (gid = 0; gid < 5; gid++)
            ck_assert_int_ge(done[gid], inst && gid == 3 ? 0 : 8);
        if (inst)
            ray_scene_free(s);
        ray_scene_free(child);
    }
}
END_TEST

/* ------------------------------- 3. closest-point normals, instances */

/* Column j of the instance's linear part L, in long double. */
static lvec xf_col(const ray_transform *t, int j)
{
    return lv3((ld)t->m[0][j], (ld)t->m[1][j], (ld)t->m[2][j]);
}

/* L v (no translation). */
static lvec xf_lin(const ray_transform *t, lvec v)
{
    return ladd(ladd(lscale(xf_col(t, 0), v.x), lscale(xf_col(t, 1), v.y)),
                lscale(xf_col(t, 2), v.z));
}

/* a unit long double vector as doubles */
static ray_vec3 lv_dbl(lvec a)
{
    return vec((double)a.x, (double)a.y, (double)a.z);
}

/*
** The world normal a surface with object normal m has through L: the
** inverse transpose, L^-T m = (m_x c1 x c2 + m_y c2 x c0 + m_z c0 x c1)
** / det L with c_j the columns of L (the adjugate), normalised.
*/
static ray_vec3 xf_normal(const ray_transform *t, lvec m)
{
    lvec c0 = xf_col(t, 0), c1 = xf_col(t, 1), c2 = xf_col(t, 2);
    ld det = ldot(c0, lcross(c1, c2));
    lvec w = ladd(ladd(lscale(lcross(c1, c2), m.x), lscale(lcross(c2, c0), m.y)),
                  lscale(lcross(c0, c1), m.z));
    return lv_dbl(lunit(lscale(w, det < 0 ? -1 : 1)));
}

/* L^-1 y (the adjugate's rows over det L). */
static lvec xf_inv_lin(const ray_transform *t, lvec y)
{
    lvec c0 = xf_col(t, 0), c1 = xf_col(t, 1), c2 = xf_col(t, 2);
    ld det = ldot(c0, lcross(c1, c2));
    return lscale(lv3(ldot(lcross(c1, c2), y), ldot(lcross(c2, c0), y),
                      ldot(lcross(c0, c1), y)), 1 / det);
}

/*
** ray_closest_point's normal through instances: a child of a closed cube
** mesh, a box and a sphere, placed by rotations about random axes, with
** uniform scales (similarities: the box and sphere answer in the child's
** space, their normals mapped), per-axis scales and shears (not
** similarities: the parallelepiped's and the ellipsoid's own world
** normals) and reflections; 60 points q around each (around the cube
** and the sphere, and outside the middle of the box's faces).  The reference is
** the object normal through the inverse transpose of L (what the hits
** report, ray_scene_add_instance(3)) in long double: a triangle's
** (b - a) x (c - a), a box face's axis, the sphere's gradient at the
** point p reported, mapped back into the child.  Tolerance 1e-12: the
** library maps with L's rounded inverse and renormalises (a few ulps
** times L's condition number, at most about 40 here), and the ellipsoid's
** p from Newton steps is within 1e-14 of its surface, which moves the
** gradient's direction by as much over a curvature radius >= 0.2; a
** normal left in the child's space is off by the rotation, 1e-2 or more.
*/
START_TEST(closest_normals_should_turn_with_instances)
{
    hc_mesh cube = hc_cube(vec(0, 0, 0));
    ray_mesh m = hc_ray_mesh(&cube);
    ray_box_params box;
    ray_scene *child;
    rng g = {338};
    int k, checked[3] = {0};

    box.center = vec(8, 0, 0);
    box.half_extents = vec(0.5, 0.7, 0.9);
    box.axis_x = vec(1, 0, 0);
    box.axis_y = vec(0, 1, 0);
    ck_assert_int_eq(ray_scene_new(&child, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(child, &m, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_box(child, &box, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(child, vec(0, 8, 0), 0.8,
                                          RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    for (k = 0; k < 12; k++) {
        ray_transform xf;
        ray_scene *s;
        unsigned id;
        int i;
        /* 0-3 rotations, 4-7 rotations with a uniform scale, 8-11 per-axis
        ** scales and shears; kit_affine reflects when k % 3 == 0. */
        double us = rng_range(&g, 0.5, 2);
        ray_vec3 sc = k < 4 ? vec(1, 1, 1) : k < 8 ? vec(us, us, us)
                                        : rng_point(&g, 0.5, 2);
        kit_affine(&g, k, k < 8 ? 0 : 0.4, sc, rng_point(&g, -5, 5), &xf);
        ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_instance(s, child, &xf, &id), RAY_OK);
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        for (i = 0; i < 60; i++) {
            /* 8 apart, so that the piece q is put near is its nearest. */
            lvec at = i % 3 == 0 ? lv3(0, 0, 0) : lv3(0, 8, 0), qo;
            int face = (int)(rng_next(&g) % 6);
            qo = ladd(at, lscale(lv(rng_dir(&g)), (ld)rng_range(&g, 1.5, 3)));
            if (i % 3 == 1) {
                /* A point of a face of the box, in its middle half: that face's
                ** normal (an edge's or a corner's is the defect 3,
                ** tested with its fix). */
                ld h[3] = {0.5L, 0.7L, 0.9L}, x[3];
                int ax;
                for (ax = 0; ax < 3; ax++)
                    x[ax] = h[ax] * (ld)rng_range(&g, -0.5, 0.5);
                x[face / 2] = (face % 2 ? 1 : -1) * h[face / 2];
                qo = lv3(8 + x[0], x[1], x[2]);
            }
            ray_vec3 q = lv_dbl(kit_map_point(&xf, qo)), want;
            ray_closest c;
            if (i % 3 == 1) {
                /* ... off the face along its world normal, so that the
                ** face's point is the nearest even through a shear. */
                lvec f = lv3(face / 2 == 0 ? (face % 2 ? 1 : -1) : 0,
                             face / 2 == 1 ? (face % 2 ? 1 : -1) : 0,
                             face / 2 == 2 ? (face % 2 ? 1 : -1) : 0);
                q = vadd(q, vscale(xf_normal(&xf, f), rng_range(&g, 0.01, 0.1)));
            }
            ck_assert_int_eq(ray_closest_point(s, q, HUGE_VAL, &c), 1);
            ck_assert_uint_eq(c.inst_id, id);
            if (c.geom_id != (unsigned)(i % 3))
                continue;            /* a shear brought another one nearer */
            checked[c.geom_id]++;
            if (c.geom_id == 0) {
                const unsigned *t = cube.idx + 3 * c.prim_id;
                lvec a = lv(cube.v[t[0]]), b = lv(cube.v[t[1]]),
                     d = lv(cube.v[t[2]]);
                want = xf_normal(&xf, lcross(lsub(b, a), lsub(d, a)));
            } else if (c.geom_id == 1) {
                lvec f = lv3(0, 0, 0);
                if (face / 2 == 0) f.x = face % 2 ? 1 : -1;
                if (face / 2 == 1) f.y = face % 2 ? 1 : -1;
                if (face / 2 == 2) f.z = face % 2 ? 1 : -1;
                want = xf_normal(&xf, f);
            } else {
                lvec po = lsub(xf_inv_lin(&xf, lsub(lv(c.p), lv3((ld)xf.m[0][3],
                                          (ld)xf.m[1][3], (ld)xf.m[2][3]))),
                               lv3(0, 8, 0));
                want = xf_normal(&xf, po);
            }
            ck_assert_msg(fabs(c.n.x - want.x) < 1e-12 &&
                              fabs(c.n.y - want.y) < 1e-12 &&
                              fabs(c.n.z - want.z) < 1e-12,
                          "transform %d, q %d, geom %u: n (%.17g, %.17g, "
                          "%.17g), through L^-T (%.17g, %.17g, %.17g)", k, i,
                          c.geom_id, c.n.x, c.n.y, c.n.z, want.x, want.y,
                          want.z);
        }
        ray_scene_free(s);
    }
    for (k = 0; k < 3; k++)
        ck_assert_int_ge(checked[k], 150);   /* of 240 each */
    (void)xf_lin;
    ray_scene_free(child);
    hc_mesh_free(&cube);
}
END_TEST

/* --------------------------------------------- 4. ray_spawn_to's end */

/*
** The segment ends at its target: org + tmax dir is the target to the
** rounding of dir = target - org and of the sum (half an ulp of each
** magnitude: an ulp of the larger per component), from hand-made hits
** whose offset (2 d = 2e-3 and 2e-9 along n) is far larger than that,
** and from real hits on a sphere at 0 and 1e3; tmin is 0.
*/
START_TEST(spawn_to_should_end_at_its_target)
{
    rng g = {438};
    int i;

    for (i = 0; i < 400; i++) {
        ray_hit h;
        ray_ray r;
        ray_vec3 target = rng_point(&g, -50, 50), end;
        double tol;
        memset(&h, 0, sizeof h);
        if (i % 2 == 0) {
            h.p = rng_point(&g, -10, 10);
            h.n = rng_dir(&g);
            h.p_err = i % 4 == 0 ? vec(1e-3, 1e-3, 1e-3) : vec(1e-9, 2e-9, 3e-9);
        } else {
            ray_vec3 c = i % 4 == 1 ? vec(0, 0, 0) : vec(1e3, -1e3, 1e3);
            ray_vec3 d = rng_dir(&g);
            ray_ray in = ray_from(vadd(c, vscale(d, 5)), vscale(d, -1));
            ck_assert_int_eq(ray_sphere(&in, c, 2, &h), 1);
            target = vadd(c, rng_point(&g, -50, 50));
        }
        ck_assert_int_eq(ray_spawn_to(&h, target, &r), RAY_OK);
        end = vadd(r.org, vscale(r.dir, r.tmax));
        tol = DBL_EPSILON * fmax(vmax_abs(target), vmax_abs(r.org));
        ck_assert_msg(fabs(end.x - target.x) <= tol &&
                          fabs(end.y - target.y) <= tol &&
                          fabs(end.z - target.z) <= tol,
                      "spawn %d: the segment ends at (%.17g, %.17g, %.17g), "
                      "not at its target (%.17g, %.17g, %.17g)", i, end.x,
                      end.y, end.z, target.x, target.y, target.z);
        ck_assert(r.tmin == 0 && r.tmax == 1);
        /* ... and starts off the surface, on the target's side. */
        ck_assert(vdot(vsub(r.org, h.p), h.n) * vdot(vsub(target, h.p), h.n) > 0);
    }
}
END_TEST

/*
** A target on a surface (a point of a light's triangle, from
** ray_surface_point, or any hit) is itself within its p_err of that
** surface, on either side: a segment ending at it exactly crosses the
** surface about half the time (ray_spawn(3): "A target on a surface").
** The rule: end the segment at the target's own spawn origin toward the
** shading point, ray_spawn(&target_hit, p - target, ...).org -- moved off
** its surface by its error bound exactly as the segment's origin is
** moved off the shading point's.  20,000 shadow segments from points of
** a floor to points of a tilted triangle at 1e2 (all coordinates
** rounded): none blocked by the triangle they end on, nor by the floor;
** with the target given bare, many are (counted, not asserted: that is
** the gap); and a real occluder 1e-9 in front of the target (a
** triangle parallel to the light, ten thousand times the offset)
** blocks every one of them.
*/
START_TEST(spawn_to_a_target_on_a_surface_should_not_be_blocked_by_it)
{
    ray_vec3 o = vec(100.25, 37.5, -120.125);
    ray_vec3 f[3] = {vadd(o, vec(-7.3, 0.01, -6.1)), vadd(o, vec(8.9, -0.02, -5.7)),
                     vadd(o, vec(0.3, 0.03, 9.7))};
    ray_vec3 l[3] = {vadd(o, vec(-1.1, 4.1, -0.7)), vadd(o, vec(1.3, 4.3, 0.9)),
                     vadd(o, vec(0.2, 4.05, 1.7))};
    ray_vec3 ln = vcross(vsub(l[1], l[0]), vsub(l[2], l[0])), shift;
    ray_scene *s, *blocker;
    rng g = {4438};
    int i, bare = 0, ruled = 0, blocked = 0;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_triangle(s, f[0], f[1], f[2], RAY_NO_MATERIAL,
                                            NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_triangle(s, l[0], l[1], l[2], RAY_NO_MATERIAL,
                                            NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    /* The light, and a copy of it 1e-9 towards the floor (below it:
    ** the floor is at y - 37.5 ~ 0, the light's plane, tilted by less
    ** than 0.3, at about 4.2 over it), grown so that every segment
    ** crosses it. */
    ln = vscale(ln, 1 / vlen(ln));
    shift = vscale(ln, ln.y > 0 ? -1e-9 : 1e-9);
    ck_assert_int_eq(ray_scene_new(&blocker, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_triangle(blocker, f[0], f[1], f[2],
                                            RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_triangle(blocker, l[0], l[1], l[2],
                                            RAY_NO_MATERIAL, NULL), RAY_OK);
    {
        ray_vec3 c = vscale(vadd(vadd(l[0], l[1]), l[2]), 1.0 / 3), b[3];
        int k;
        for (k = 0; k < 3; k++)
            b[k] = vadd(vadd(c, vscale(vsub(l[k], c), 2)), shift);
        ck_assert_int_eq(ray_scene_add_triangle(blocker, b[0], b[1], b[2],
                                                RAY_NO_MATERIAL, NULL), RAY_OK);
    }
    ck_assert_int_eq(ray_scene_commit(blocker), RAY_OK);
    for (i = 0; i < 20000; i++) {
        double u = rng_unit(&g), v = rng_unit(&g) * (1 - u);
        double a = rng_unit(&g), b = rng_unit(&g) * (1 - a);
        ray_hit from, to;
        ray_ray seg, back;
        ck_assert_int_eq(ray_surface_point(s, 0, 0, RAY_INVALID_ID, u, v, &from),
                         RAY_OK);
        ck_assert_int_eq(ray_surface_point(s, 1, 0, RAY_INVALID_ID, a, b, &to),
                         RAY_OK);
        ck_assert_int_eq(ray_spawn_to(&from, to.p, &seg), RAY_OK);
        bare += ray_occluded(s, &seg, NULL) == 1;
        /* The rule. */
        ck_assert_int_eq(ray_spawn(&to, vsub(from.p, to.p), &back), RAY_OK);
        ck_assert_int_eq(ray_spawn_to(&from, back.org, &seg), RAY_OK);
        ruled += ray_occluded(s, &seg, NULL) == 1;
        blocked += ray_occluded(blocker, &seg, NULL) == 1;
    }
    printf("spawn_to: %d of 20000 segments ending at a bare target on a "
           "triangle blocked by it; with the target's spawn origin: %d\n",
           bare, ruled);
    ck_assert_int_eq(ruled, 0);
    ck_assert_int_eq(blocked, 20000);
    ray_scene_free(s);
    ray_scene_free(blocker);
}
END_TEST

/* ---------------------------------- 5. sliding over inner vertices */

/*
** Spheres and capsules (lying along the motion, and across it where the
** floor is flat across it) sliding at exactly their radius over a 10 x 10
** grid mesh of unit quads (grid_scene), along the paths that pass over
** its inner vertices and edges: along a row of vertices, along a column,
** along the quads' diagonal edges; on a folded grid (ridge, 0.25 a unit
** each side) along the ridge edge itself and along a vertex row of a
** sloped side; on a valley's sloped side.  Every such slide touches
** nothing: the inner edges' and vertices' inflated cylinders and balls
** stand eps above the faces, and the graze rule (sweep_pieces.c) is what
** keeps them from stopping the shape there.  The same slide 1e-6 r
** nearer the floor overlaps it from the start (the test would see a
** contact: it is not blind).
*/
START_TEST(sweeps_should_slide_over_inner_vertices)
{
    static const double folds[3] = {0, 0.25, -0.25};
    int f, path, shape, ri, stops = 0, slides = 0;

    for (f = 0; f < 3; f++) {
        ray_scene *s = grid_scene(NULL, 10, 0, folds[f]);
        double fo = folds[f], nl = sqrt(1 + fo * fo);
        ray_vec3 fn = vec(0, fo / nl, 1 / nl);   /* the y > 0 side's normal */
        for (path = 0; path < 4; path++)
            for (shape = 0; shape < 3; shape++)
                for (ri = 0; ri < 2; ri++) {
                    double r = ri ? 0.7 : 0.3;
                    ray_vec3 from, dir, foot, up, across;
                    ray_sweep w;
                    ray_contact c;
                    if (f > 0 && path >= 2)
                        continue;            /* folded: two paths */
                    if (f == 0) {
                        up = vec(0, 0, 1);
                        if (path == 0)       /* along the row y = 1 */
                            foot = vec(-4.5, 1, 0), dir = vec(9, 0, 0);
                        else if (path == 1)  /* along the column x = 2 */
                            foot = vec(2, -4.5, 0), dir = vec(0, 9, 0);
                        else if (path == 2)  /* along the diagonal edges */
                            foot = vec(-4.25, -4.25, 0), dir = vec(8.5, 8.5, 0);
                        else                 /* the other diagonal: across them */
                            foot = vec(4.25, -4.25, 0), dir = vec(-8.5, 8.5, 0);
                    } else if (path == 0 && f == 1) {
                        up = vec(0, 0, 1);   /* on the ridge edge */
                        foot = vec(-4.5, 0, 0), dir = vec(9, 0, 0);
                    } else {                 /* the row y = 2 of a side */
                        up = fn;
                        foot = vec(-4.5, 2, -fo * 2), dir = vec(9, 0, 0);
                    }
                    if (f > 0 && path == 0 && f == 2)
                        continue;            /* a valley's bottom: no graze */
                    across = vcross(up, vscale(dir, 1 / vlen(dir)));
                    if (shape == 2 && f == 1 && path == 0)
                        continue;            /* across the ridge: not flat */
                    from = vadd(foot, vscale(up, r));
                    memset(&w, 0, sizeof w);
                    w.shape.a = w.shape.b = from;
                    if (shape == 1)
                        w.shape.b = vadd(from, vscale(dir, 0.3 / vlen(dir)));
                    else if (shape == 2)
                        w.shape.b = vadd(from, vscale(across, 0.3));
                    w.shape.radius = r;
                    w.dir = dir;
                    slides++;
                    if (ray_intersect_sweep(s, &w, NULL, &c) != 0) {
                        stops++;
                        ck_assert_msg(0, "fold %g, path %d, shape %d, r %g: "
                                      "stopped at t %.17g, p (%.17g, %.17g, "
                                      "%.17g), prim %u", fo, path, shape, r,
                                      c.t, c.p.x, c.p.y, c.p.z, c.prim_id);
                    }
                    /* 1e-6 r nearer: an overlap from the start. */
                    w.shape.a = vsub(w.shape.a, vscale(up, 1e-6 * r));
                    w.shape.b = vsub(w.shape.b, vscale(up, 1e-6 * r));
                    ck_assert_int_eq(ray_intersect_sweep(s, &w, NULL, &c), 1);
                    ck_assert(c.flags & RAY_CONTACT_OVERLAP);
                    ck_assert(c.t == 0);
                }
        ray_scene_free(s);
    }
    ck_assert_int_eq(stops, 0);
    ck_assert_int_ge(slides, 30);
}
END_TEST

/* -------------------------------------------------------------- suite */

Suite *slips_suite(void)
{
    Suite *s = suite_create("slips");
    TCase *tc = tcase_create("core");

    tcase_set_timeout(tc, 120);
    tcase_add_test(tc, batches_should_see_a_plane_beside_a_mesh);
    tcase_add_test(tc, batches_should_see_a_sphere_beside_a_mesh);
    tcase_add_test(tc, batches_should_match_rays_in_mixed_scenes);
    tcase_add_test(tc, batches_should_miss_unusable_rays_in_packets);
    tcase_add_test(tc, batches_should_follow_per_ray_masks);
    tcase_add_test(tc, surface_points_should_round_trip);
    tcase_add_test(tc, closest_normals_should_turn_with_instances);
    tcase_add_test(tc, spawn_to_should_end_at_its_target);
    tcase_add_test(tc, spawn_to_a_target_on_a_surface_should_not_be_blocked_by_it);
    tcase_add_test(tc, sweeps_should_slide_over_inner_vertices);
    suite_add_tcase(s, tc);
    return s;
}
