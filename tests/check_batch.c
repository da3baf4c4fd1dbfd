/* SPDX-License-Identifier: MIT */
/*
** check_batch.c -- ray_intersect_batch and ray_occluded_batch (one set
** of options for every ray, ray_batch.query, or each ray its own): the
** same answers as ray_intersect and ray_occluded ray by ray, bit for
** bit (API notes 11: answers do not depend on the path taken), on closed
** meshes at the
** origin and moved to 1e5 -- coherent camera blocks (the packets' fast
** case), scattered rays (packets of rays going everywhere), rays aimed
** exactly at shared vertices and edges (where two triangles tie in t and
** the packet's visiting order differs from the ray's own), short
** intervals, unusable rays mixed in, batch sizes that are not multiples
** of eight; the ray-by-ray path of scenes and queries the packets do not
** take; ties settled by (geom_id, prim_id) whatever the order (two copies
** of one mesh: every hit a tie); misuse.
*/
#include <string.h>
#include <stdlib.h>

#include "tests.h"
#include "hardcases.h"

/* A committed scene of the meshes m[0 .. n - 1]. */
static ray_scene *mesh_scene(const hc_mesh *m, int n)
{
    ray_scene *s;
    int k;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    for (k = 0; k < n; k++) {
        ray_mesh rm = hc_ray_mesh(&m[k]);
        ck_assert_int_eq(ray_scene_add_mesh(s, &rm, RAY_NO_MATERIAL, NULL),
                         RAY_OK);
    }
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    return s;
}

/*
** n rays of four kinds, in runs: blocks of 4 x 2 camera rays from "eye"
** towards "centre" (coherent), rays from random points near the centre
** in random directions (scattered), rays aimed exactly at random vertices
** and edge points of m (ties), and every 97th ray unusable (zero or NaN
** direction) or with an interval shorter than the way to the mesh.
*/
static ray_ray *batch_rays(const hc_mesh *m, ray_vec3 centre, size_t n,
                           unsigned long long seed)
{
    ray_ray *r = malloc(n * sizeof *r);
    rng g = {seed};
    ray_vec3 eye = v3_add(centre, v3(0.3, 0.7, 9));
    size_t i;

    ck_assert_ptr_nonnull(r);
    for (i = 0; i < n; i++) {
        size_t kind = i / 64 % 3, px = i % 8;
        r[i].tmin = 0;
        r[i].tmax = HUGE_VAL;
        if (kind == 0) {                  /* a 4 x 2 block of pixels */
            double bx = (double)(i / 8 % 16) / 8 - 1, by = (double)(i / 128 % 16) / 8 - 1;
            r[i].org = eye;
            r[i].dir = v3_sub(v3_add(centre, v3(3 * bx + 0.02 * (double)(px % 4),
                                                3 * by + 0.02 * (double)(px / 4), 0)),
                              eye);
        } else if (kind == 1) {           /* scattered */
            r[i].org = v3_add(centre, v3_scale(rng_dir(&g), 5 * rng_unit(&g)));
            r[i].dir = rng_dir(&g);
        } else {                          /* at a vertex or an edge */
            size_t t = (size_t)(rng_unit(&g) * (double)m->nt) % m->nt;
            unsigned e = (unsigned)(rng_unit(&g) * 3) % 3;
            ray_vec3 a = m->v[m->idx[3 * t + e]];
            ray_vec3 b = m->v[m->idx[3 * t + (e + 1) % 3]];
            double s = px < 4 ? 0 : rng_unit(&g);
            r[i].org = v3_add(centre, v3_scale(rng_dir(&g), 6));
            r[i].dir = v3_sub(v3_add(v3_scale(a, 1 - s), v3_scale(b, s)),
                              r[i].org);
        }
        if (i % 97 == 5)
            r[i].dir = v3(0, 0, 0);
        else if (i % 97 == 17)
            r[i].dir.y = (double)NAN;
        else if (i % 97 == 29)
            r[i].tmax = 0.5;
        else if (i % 97 == 41)
            r[i].tmin = 4;
    }
    return r;
}

/* ray_intersect_batch and ray_occluded_batch with one set of options q
** for every ray (ray_batch.query) against the single-ray queries on
** rays[0 .. n - 1]; returns the hits found. */
static size_t check_against_single(const ray_scene *s, const ray_ray *rays,
                                   size_t n, const ray_query *q)
{
    ray_hit *hits = calloc(n ? n : 1, sizeof *hits);
    int *res = malloc((n ? n : 1) * sizeof *res);
    size_t i, found = 0;

    ck_assert_ptr_nonnull(hits);
    ck_assert_ptr_nonnull(res);
    ck_assert_int_eq(ray_intersect_batch(s, &(ray_batch){.rays = rays, .n = n,
                                                         .hits = hits,
                                                         .results = res,
                                                         .query = q}),
                     RAY_OK);
    for (i = 0; i < n; i++) {
        ray_hit one;
        int rc = ray_intersect(s, &rays[i], &one, q);
        ck_assert_msg(res[i] == rc, "ray %zu: batch %d, single %d", i, res[i],
                      rc);
        if (rc > 0) {
            ck_assert_msg(hit_same(&hits[i], &one),
                          "ray %zu: t %.17g prim %u vs t %.17g prim %u", i,
                          hits[i].t, hits[i].prim_id, one.t, one.prim_id);
            found++;
        }
    }
    ck_assert_int_eq(ray_occluded_batch(s, &(ray_batch){.rays = rays, .n = n,
                                                        .results = res,
                                                        .query = q}),
                     RAY_OK);
    for (i = 0; i < n; i++)
        ck_assert_msg(res[i] == ray_occluded(s, &rays[i], q),
                      "ray %zu: occluded batch %d", i, res[i]);
    free(hits);
    free(res);
    return found;
}

/* Icospheres (2,562 and 642 vertices, closed) side by side: thousands of
** rays of every kind, at the origin and at 1e5, and batch sizes 1 to 9
** and not multiples of eight. */
START_TEST(batch_should_match_single_rays_bit_for_bit)
{
    double off = test_offset(_i);
    ray_vec3 c = v3(off, off * 0.5, -off);
    hc_mesh m[2];
    ray_scene *s;
    ray_ray *rays;
    size_t n = 6001, hits, k;

    m[0] = hc_icosphere(c, 4);
    m[1] = hc_icosphere(v3_add(c, v3(3.5, 0.5, -1)), 3);
    s = mesh_scene(m, 2);
    rays = batch_rays(&m[0], c, n, 12345 + (unsigned long long)_i);
    hits = check_against_single(s, rays, n, NULL);
    /* Most rays are aimed at the meshes: a batch that found nothing
    ** would pass the comparison vacuously. */
    ck_assert_uint_gt(hits, n / 2);
    for (k = 1; k <= 9; k++)
        check_against_single(s, rays + 100 * k, k, NULL);
    free(rays);
    ray_scene_free(s);
    hc_mesh_free(&m[0]);
    hc_mesh_free(&m[1]);
}
END_TEST

/* Scenes and queries that go ray by ray -- a sphere and a plane beside
** the mesh, a query mask, a filter -- give the single-ray answers too. */
static int keep_even(void *ud, const ray_ray *r, const ray_hit *h,
                     void *query_ud)
{
    (void)ud;
    (void)r;
    (void)query_ud;
    return h->prim_id % 2 == 0;
}

START_TEST(batch_should_match_single_rays_where_it_goes_ray_by_ray)
{
    ray_vec3 c = v3(0, 0, 0);
    hc_mesh m = hc_icosphere(c, 3);
    ray_ray *rays = batch_rays(&m, c, 1500, 777);
    ray_scene *s = mesh_scene(&m, 1);
    ray_query q;
    unsigned id;

    ck_assert_int_eq(ray_scene_set_mask(s, 0, 1), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    memset(&q, 0, sizeof q);
    q.ignore_mask = ~2u;                            /* hides the mesh (mask 1) */
    ck_assert_uint_eq(check_against_single(s, rays, 1500, &q), 0);
    q.ignore_mask = ~3u;                            /* sees it */
    ck_assert_uint_gt(check_against_single(s, rays, 1500, &q), 750);
    ck_assert_int_eq(ray_scene_set_filter(s, 0, keep_even, NULL,
                                          RAY_FILTER_INTERSECT |
                                              RAY_FILTER_OCCLUDED),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_uint_gt(check_against_single(s, rays, 1500, NULL), 300);
    ray_scene_free(s);

    s = mesh_scene(&m, 1);
    ck_assert_int_eq(ray_scene_add_sphere(s, v3(1, 1, 1), 1.5,
                                          RAY_NO_MATERIAL, &id),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, v3(0, -1.5, 0), v3(0, 1, 0),
                                         RAY_NO_MATERIAL, &id),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_uint_gt(check_against_single(s, rays, 1500, NULL), 750);
    ray_scene_free(s);
    free(rays);
    hc_mesh_free(&m);
}
END_TEST

/*
** Two triangles that share an edge, in both orders: a ray straight down
** through the edge hits both at t = 1 exactly (the plane y = 0, a ray
** from y = 1, every quantity exact), and the nearest hit is the lower
** prim_id -- the first triangle of the index array -- whichever the
** geometry, through both queries and both batch paths.
*/
START_TEST(ties_should_go_to_the_lower_prim_id)
{
    static const unsigned ab[6] = {0, 1, 2, 0, 2, 3};
    static const unsigned ba[6] = {0, 2, 3, 0, 1, 2};
    ray_vec3 v[4];
    ray_mesh mesh;
    ray_ray r[8];
    ray_hit h[8];
    int res[8], order, k;

    v[0] = v3(-1, 0, -1);
    v[1] = v3(-1, 0, 1);
    v[2] = v3(1, 0, 1);
    v[3] = v3(1, 0, -1);
    for (k = 0; k < 8; k++) {
        /* Points of the diagonal from (-1, 0, -1) to (1, 0, 1). */
        double s = -0.75 + 0.25 * k;
        r[k] = make_ray(v3(s, 1, s), v3(0, -1, 0), 0, HUGE_VAL);
    }
    for (order = 0; order < 2; order++) {
        ray_scene *s;
        memset(&mesh, 0, sizeof mesh);
        mesh.vertices = v;
        mesh.vertex_count = 4;
        mesh.indices = order ? ba : ab;
        mesh.triangle_count = 2;
        ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_mesh(s, &mesh, RAY_NO_MATERIAL,
                                            NULL),
                         RAY_OK);
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        ck_assert_int_eq(ray_intersect_batch(s, &(ray_batch){.rays = r, .n = 8,
                                                             .hits = h,
                                                             .results = res}),
                         RAY_OK);
        for (k = 0; k < 8; k++) {
            ray_hit one;
            ck_assert_int_eq(res[k], 1);
            ck_assert_int_eq(ray_intersect(s, &r[k], &one, NULL), 1);
            ck_assert(hit_same(&h[k], &one));
            ck_assert(h[k].t == 1.0);
            ck_assert_uint_eq(h[k].prim_id, 0);
        }
        ray_scene_free(s);
    }
}
END_TEST

/*
** The same closed mesh added twice (geom_id 0 and 1): every hit is a tie
** between the two copies, met in whatever order the traversal takes
** through the BVH's mixed leaves, and geom_id 0 must win each, in the
** single-ray and the batch queries, with the watertight test and with
** Cramer's rule; misses and unusable rays leave hits[] as it was.
*/
START_TEST(ties_between_geometries_should_go_to_the_lower_geom_id)
{
    ray_vec3 c = v3(0, 0, 0);
    hc_mesh m[2];
    ray_ray *rays;
    ray_hit *hits, before;
    int *res, watertight;
    size_t n = 2000, i, ties = 0;

    m[0] = hc_icosphere(c, 3);
    m[1] = hc_icosphere(c, 3);
    rays = batch_rays(&m[0], c, n, 99);
    hits = malloc(n * sizeof *hits);
    res = malloc(n * sizeof *res);
    ck_assert_ptr_nonnull(hits);
    ck_assert_ptr_nonnull(res);
    memset(&before, 0x5a, sizeof before);
    for (watertight = 1; watertight >= 0; watertight--) {
        ray_scene *s = mesh_scene(m, 2);
        ck_assert_int_eq(ray_scene_set_watertight(s, watertight), RAY_OK);
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        for (i = 0; i < n; i++)
            hits[i] = before;
        ck_assert_int_eq(ray_intersect_batch(s, &(ray_batch){.rays = rays,
                                                             .n = n,
                                                             .hits = hits,
                                                             .results = res}),
                         RAY_OK);
        for (i = 0; i < n; i++) {
            ray_hit one;
            int rc = ray_intersect(s, &rays[i], &one, NULL);
            ck_assert_int_eq(res[i], rc);
            if (rc <= 0) {
                ck_assert(memcmp(&hits[i], &before, sizeof before) == 0);
                continue;
            }
            ck_assert(hit_same(&hits[i], &one));
            ck_assert_uint_eq(one.geom_id, 0);
            ties++;
        }
        ray_scene_free(s);
    }
    /* Most rays hit: the assertions above were not vacuous. */
    ck_assert_uint_gt(ties, n);
    free(rays);
    free(hits);
    free(res);
    hc_mesh_free(&m[0]);
    hc_mesh_free(&m[1]);
}
END_TEST

/* A filter that keeps a hit only when the query's ud (an agent's number)
** differs from the geometry's (the agent's own body). */
static int not_my_body(void *ud, const ray_ray *r, const ray_hit *h,
                       void *query_ud)
{
    (void)r;
    (void)h;
    return query_ud == NULL || *(const unsigned *)ud !=
                                   *(const unsigned *)query_ud;
}

/*
** Unusable rays inside a coherent group of eight, which goes in a packet
** all the same (coherence reads only the directions, and takes one of
** infinite length along the others' mean): an empty interval (tmin ==
** tmax at the mesh, tmin above tmax around it), a NaN end, an infinite
** or NaN origin, a direction (0, 0, -Inf) from tmin 0 and -1.  A single
** ray misses each of them (ray__ray_usable), so the packet must leave
** those lanes out: traced, the infinite direction's frame scales z by
** 1 / Inf = 0, so the triangles on its axis give t = 0, a hit from tmin
** -1 (make mutants' batch-usable).  Every kind in every lane, in a scene
** of triangles alone where the packets take the group (batch_packets
** says so where the CPU has AVX2), against the single-ray answers, and
** the other seven lanes still hit.
*/
START_TEST(unusable_rays_in_a_packet_should_miss_as_single_rays)
{
    ray_vec3 c = v3(0, 0, 0), eye = v3(0.3, 0.7, 9);
    hc_mesh m = hc_icosphere(c, 3);
    ray_scene *s = mesh_scene(&m, 1);
    ray_ray rays[8];
    ray_hit hits[8];
    int res[8];
    ray_stats st;
    int lane, kind, k, avx2 = 0;

#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__)) && \
    !defined(RAY_NO_SIMD) && !defined(RAY_NO_AVX2)
    avx2 = __builtin_cpu_supports("avx2");
#endif
    for (kind = 0; kind < 8; kind++)
        for (lane = 0; lane < 8; lane++) {
            for (k = 0; k < 8; k++)        /* a 4 x 2 block at the sphere */
                rays[k] = make_ray(eye, v3_sub(v3(0.1 * (k % 4), 0.1 * (k / 4),
                                                  0), eye), 0, HUGE_VAL);
            switch (kind) {
            case 0:                         /* empty at the sphere (t ~ 0.8) */
                rays[lane].tmin = rays[lane].tmax = 0.8;
                break;
            case 1:                         /* tmin above tmax, around it */
                rays[lane].tmin = 2;
                rays[lane].tmax = 0.5;
                break;
            case 2:
                rays[lane].tmin = (double)NAN;
                break;
            case 3:
                rays[lane].tmax = (double)NAN;
                break;
            case 4:
                rays[lane].org.x = HUGE_VAL;
                break;
            case 5:
                rays[lane].org.z = (double)NAN;
                break;
            default:                        /* straight down, infinitely */
                rays[lane].dir = v3(0, 0, -HUGE_VAL);
                rays[lane].tmin = kind == 6 ? 0 : -1;
                break;
            }
            memset(&st, 0, sizeof st);
            ck_assert_int_eq(ray_intersect_batch(s, &(ray_batch){
                                 .rays = rays, .n = 8, .hits = hits,
                                 .results = res, .stats = &st}), RAY_OK);
            ck_assert_uint_eq(st.batch_packets, avx2 ? 8 : 0);
            for (k = 0; k < 8; k++) {
                ray_hit one;
                int rc = ray_intersect(s, &rays[k], &one, NULL);
                ck_assert_int_eq(rc, k != lane);
                ck_assert_msg(res[k] == rc, "kind %d lane %d ray %d: batch "
                              "%d, single %d", kind, lane, k, res[k], rc);
                if (rc > 0)
                    ck_assert(hit_same(&hits[k], &one));
            }
            ck_assert_int_eq(ray_occluded_batch(s, &(ray_batch){
                                 .rays = rays, .n = 8, .results = res}),
                             RAY_OK);
            for (k = 0; k < 8; k++)
                ck_assert_msg(res[k] == (k != lane), "kind %d lane %d ray "
                              "%d: occluded batch %d", kind, lane, k, res[k]);
        }
    ray_scene_free(s);
    hc_mesh_free(&m);
}
END_TEST

/*
** Per-ray options (ray_intersect_batch): AI agents' lines of sight, each
** ray with its own mask (agent k's mask hides the mesh of agent k, a mask
** bit each) or its own query_ud (a filter that drops the agent's own
** body): each ray answers as ray_intersect and ray_occluded with
** its own options, bit for bit, in one batch, its tests counted into the
** batch's stats.
*/
START_TEST(batch_should_take_each_rays_own_options)
{
    ray_vec3 c = v3(0, 0, 0);
    hc_mesh m[4];
    ray_ray *rays;
    ray_query *q;
    ray_hit *hits;
    int *res;
    unsigned ids[4], agent[4] = {0, 1, 2, 3};
    ray_scene *s;
    ray_batch b;
    ray_stats st;
    size_t n = 803, i, hidden = 0;
    int k;

    for (k = 0; k < 4; k++)
        m[k] = hc_icosphere(v3(3.0 * k - 4.5, 0, 0), 2);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    for (k = 0; k < 4; k++) {
        ray_mesh rm = hc_ray_mesh(&m[k]);
        ck_assert_int_eq(ray_scene_add_mesh(s, &rm, RAY_NO_MATERIAL, &ids[k]),
                         RAY_OK);
        ck_assert_int_eq(ray_scene_set_mask(s, ids[k], 1u << k), RAY_OK);
    }
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    rays = batch_rays(&m[1], c, n, 4242);
    q = malloc(n * sizeof *q);
    hits = calloc(n, sizeof *hits);
    res = malloc(n * sizeof *res);
    ck_assert_ptr_nonnull(q);
    ck_assert_ptr_nonnull(hits);
    ck_assert_ptr_nonnull(res);
    for (i = 0; i < n; i++) {
        memset(&q[i], 0, sizeof q[i]);
        q[i].ignore_mask = 1u << (i % 4);     /* agent i % 4 sees the others */
    }
    memset(&st, 0, sizeof st);
    b.rays = rays;
    b.queries = q;
    b.n = n;
    b.hits = hits;
    b.results = res;
    b.stats = &st;
    ck_assert_int_eq(ray_intersect_batch(s, &b), RAY_OK);
    for (i = 0; i < n; i++) {
        ray_hit one;
        int rc = ray_intersect(s, &rays[i], &one, &q[i]);
        ck_assert_int_eq(res[i], rc);
        if (rc > 0) {
            ck_assert(hit_same(&hits[i], &one));
            ck_assert_uint_ne(hits[i].geom_id, ids[i % 4]);
        }
        hidden += rc == 0 && ray_intersect(s, &rays[i], &one, NULL) > 0;
    }
    /* The masks hid something, and every ray went one by one (the scene
    ** is gated: packets take no masks) and was counted. */
    ck_assert_uint_gt(hidden, 0);
    ck_assert_uint_eq(st.batch_single, n);
    ck_assert_uint_eq(st.batch_packets, 0);
    ck_assert_uint_gt(st.tests, n);
    ck_assert_int_eq(ray_occluded_batch(s, &b), RAY_OK);
    for (i = 0; i < n; i++)
        ck_assert_int_eq(res[i], ray_occluded(s, &rays[i], &q[i]));
    /* A filter reading each ray's own query_ud. */
    for (k = 0; k < 4; k++) {
        ck_assert_int_eq(ray_scene_set_mask(s, ids[k], ~0u), RAY_OK);
        ck_assert_int_eq(ray_scene_set_filter(s, ids[k], not_my_body,
                                              &agent[k],
                                              RAY_FILTER_INTERSECT |
                                                  RAY_FILTER_OCCLUDED),
                         RAY_OK);
    }
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    for (i = 0; i < n; i++) {
        memset(&q[i], 0, sizeof q[i]);
        q[i].query_ud = &agent[i % 4];
    }
    b.stats = NULL;
    ck_assert_int_eq(ray_intersect_batch(s, &b), RAY_OK);
    for (i = 0; i < n; i++) {
        ray_hit one;
        int rc = ray_intersect(s, &rays[i], &one, &q[i]);
        ck_assert_int_eq(res[i], rc);
        if (rc > 0) {
            ck_assert(hit_same(&hits[i], &one));
            ck_assert_uint_ne(hits[i].geom_id, ids[i % 4]);
        }
    }
    free(rays);
    free(q);
    free(hits);
    free(res);
    ray_scene_free(s);
    for (k = 0; k < 4; k++)
        hc_mesh_free(&m[k]);
}
END_TEST

/* Camera blocks (each eight within a degree) on a scene of triangles go
** in packets where the CPU has AVX2; rays scattered in every direction
** go one by one (packets of such rays were slower than single rays);
** either way the answers are the single rays'. */
START_TEST(batch_should_say_which_path_it_took)
{
    ray_vec3 c = v3(0, 0, 0), eye = v3(0.3, 0.7, 9);
    hc_mesh m = hc_icosphere(c, 3);
    ray_scene *s = mesh_scene(&m, 1);
    size_t n = 800, i;
    ray_ray *rays = malloc(n * sizeof *rays);
    int *res = malloc(n * sizeof *res);
    ray_hit *hits = calloc(n, sizeof *hits);
    ray_batch b;
    ray_stats st;
    rng g = {99};
    int avx2 = 0;

#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__)) && \
    !defined(RAY_NO_SIMD) && !defined(RAY_NO_AVX2)
    avx2 = __builtin_cpu_supports("avx2");
#endif
    ck_assert_ptr_nonnull(rays);
    ck_assert_ptr_nonnull(res);
    ck_assert_ptr_nonnull(hits);
    for (i = 0; i < n; i++) {                /* 4 x 2 pixel blocks */
        double x = (double)(i % 4 + 4 * (i / 8 % 10)) / 40 - 0.5;
        double y = (double)(i / 4 % 2 + 2 * (i / 80)) / 20 - 0.5;
        rays[i] = make_ray(eye, v3_sub(v3(3 * x, 3 * y, 0), eye), 0,
                           HUGE_VAL);
    }
    memset(&b, 0, sizeof b);
    memset(&st, 0, sizeof st);
    b.rays = rays;
    b.n = n;
    b.hits = hits;
    b.results = res;
    b.stats = &st;
    ck_assert_int_eq(ray_intersect_batch(s, &b), RAY_OK);
    ck_assert_uint_eq(st.batch_packets + st.batch_single, n);
    ck_assert_uint_eq(st.batch_packets, avx2 ? n : 0);
    for (i = 0; i < n; i++) {
        ray_hit one;
        ck_assert_int_eq(res[i], ray_intersect(s, &rays[i], &one, NULL));
        if (res[i] > 0)
            ck_assert(hit_same(&hits[i], &one));
    }
    {
        /* One set of options for every ray (ray_batch.query): zeroed or
        ** naming only query_ud, the packets take the blocks as with none
        ** (nothing in the scene reads them), the same answers; ignoring
        ** every bit hides the mesh, ray by ray; per-ray queries, when
        ** given, win over it. */
        int me = 3, *want = malloc(n * sizeof *want);
        ray_query zero = {0}, named = {.query_ud = &me};
    ray_query hide = {.ignore_mask = ~0u};
        ray_query *per = calloc(n, sizeof *per);
        const ray_query *shared[2] = {&zero, &named};
        int k;

        ck_assert_ptr_nonnull(want);
        ck_assert_ptr_nonnull(per);
        memcpy(want, res, n * sizeof *want);
        for (k = 0; k < 2; k++) {
            b.query = shared[k];
            memset(&st, 0, sizeof st);
            ck_assert_int_eq(ray_intersect_batch(s, &b), RAY_OK);
            ck_assert_uint_eq(st.batch_packets, avx2 ? n : 0);
            ck_assert_mem_eq(res, want, n * sizeof *want);
            memset(&st, 0, sizeof st);
            ck_assert_int_eq(ray_occluded_batch(s, &b), RAY_OK);
            ck_assert_uint_eq(st.batch_packets, avx2 ? n : 0);
            ck_assert_mem_eq(res, want, n * sizeof *want);
        }
        b.query = &hide;
        memset(&st, 0, sizeof st);
        ck_assert_int_eq(ray_intersect_batch(s, &b), RAY_OK);
        ck_assert_uint_eq(st.batch_single, n);
        for (i = 0; i < n; i++)
            ck_assert_int_eq(res[i], 0);
        ck_assert_int_eq(ray_occluded_batch(s, &b), RAY_OK);
        for (i = 0; i < n; i++)
            ck_assert_int_eq(res[i], 0);
        b.queries = per;                     /* zeroed, one a ray */
        ck_assert_int_eq(ray_intersect_batch(s, &b), RAY_OK);
        ck_assert_mem_eq(res, want, n * sizeof *want);
        b.queries = NULL;
        b.query = NULL;
        free(per);
        free(want);
    }
    for (i = 0; i < n; i++)                  /* every direction */
        rays[i] = make_ray(rng_point(&g, -1, 1), rng_dir(&g), 0, HUGE_VAL);
    memset(&st, 0, sizeof st);
    ck_assert_int_eq(ray_occluded_batch(s, &b), RAY_OK);
    ck_assert_uint_eq(st.batch_single, n);
    for (i = 0; i < n; i++)
        ck_assert_int_eq(res[i], ray_occluded(s, &rays[i], NULL));
    free(rays);
    free(res);
    free(hits);
    ray_scene_free(s);
    hc_mesh_free(&m);
}
END_TEST

START_TEST(batch_should_refuse_misuse)
{
    hc_mesh m = hc_icosphere(v3(0, 0, 0), 1);
    ray_scene *s = mesh_scene(&m, 1), *fresh;
    ray_ray r = make_ray(v3(0, 0, 9), v3(0, 0, -1), 0, HUGE_VAL);
    ray_hit h, before;
    int res = 7;

    memset(&before, 0x5a, sizeof before);
    h = before;
    {
        /* Each array's misuse, one at a time (a one-ray batch whose
        ** fields are all good but one). */
        ray_batch good = {.rays = &r, .n = 1, .hits = &h, .results = &res};
        ray_batch no_rays = good, no_hits = good, no_res = good;
        ray_batch none = {.n = 0};   /* n = 0: NULL arrays allowed */

        no_rays.rays = NULL;
        no_hits.hits = NULL;
        no_res.results = NULL;
        ck_assert_int_eq(ray_intersect_batch(NULL, &good), RAY_EINVAL);
        ck_assert_int_eq(ray_intersect_batch(s, &no_rays), RAY_EINVAL);
        ck_assert_int_eq(ray_intersect_batch(s, &no_hits), RAY_EINVAL);
        ck_assert_int_eq(ray_intersect_batch(s, &no_res), RAY_EINVAL);
        ck_assert_int_eq(ray_occluded_batch(NULL, &no_hits), RAY_EINVAL);
        ck_assert_int_eq(ray_occluded_batch(s, &no_rays), RAY_EINVAL);
        ck_assert_int_eq(ray_occluded_batch(s, &no_res), RAY_EINVAL);
        /* n = 0: nothing to read or write, NULL arrays allowed. */
        ck_assert_int_eq(ray_intersect_batch(s, &none), RAY_OK);
        ck_assert_int_eq(ray_occluded_batch(s, &none), RAY_OK);
        ck_assert_int_eq(res, 7);
        ck_assert(memcmp(&h, &before, sizeof h) == 0);
        /* Not committed: RAY_ESTATE, nothing written. */
        ck_assert_int_eq(ray_scene_new(&fresh, NULL, NULL), RAY_OK);
        ck_assert_int_eq(ray_intersect_batch(fresh, &good), RAY_ESTATE);
        ck_assert_int_eq(ray_occluded_batch(fresh, &no_hits), RAY_ESTATE);
        ck_assert_int_eq(res, 7);
        ck_assert(memcmp(&h, &before, sizeof h) == 0);
    }
    /* A NULL batch, and the arrays' misuse through a batch filled field
    ** by field; hits is not read by ray_occluded_batch. */
    {
        ray_batch b;
        memset(&b, 0, sizeof b);
        b.rays = &r;
        b.n = 1;
        b.hits = &h;
        b.results = &res;
        ck_assert_int_eq(ray_intersect_batch(s, NULL), RAY_EINVAL);
        ck_assert_int_eq(ray_occluded_batch(s, NULL), RAY_EINVAL);
        ck_assert_int_eq(ray_intersect_batch(NULL, &b), RAY_EINVAL);
        ck_assert_int_eq(ray_intersect_batch(fresh, &b), RAY_ESTATE);
        b.hits = NULL;
        ck_assert_int_eq(ray_intersect_batch(s, &b), RAY_EINVAL);
        b.rays = NULL;
        ck_assert_int_eq(ray_occluded_batch(s, &b), RAY_EINVAL);
        ck_assert_int_eq(res, 7);
        ck_assert(memcmp(&h, &before, sizeof h) == 0);
        b.rays = &r;
        ck_assert_int_eq(ray_occluded_batch(s, &b), RAY_OK);
        ck_assert_int_eq(res, 1);
        res = 7;
    }
    /* And the one ray, for the record. */
    ck_assert_int_eq(ray_intersect_batch(s, &(ray_batch){.rays = &r, .n = 1,
                                                         .hits = &h,
                                                         .results = &res}),
                     RAY_OK);
    ck_assert_int_eq(res, 1);
    ray_scene_free(fresh);
    ray_scene_free(s);
    hc_mesh_free(&m);
}
END_TEST

Suite *batch_suite(void)
{
    Suite *s = suite_create("batch");
    TCase *tc = tcase_create("core");

    tcase_set_timeout(tc, 120);
    tcase_add_loop_test(tc, batch_should_match_single_rays_bit_for_bit, 0,
                        N_OFFSETS);
    tcase_add_test(tc, batch_should_match_single_rays_where_it_goes_ray_by_ray);
    tcase_add_test(tc, ties_should_go_to_the_lower_prim_id);
    tcase_add_test(tc, ties_between_geometries_should_go_to_the_lower_geom_id);
    tcase_add_test(tc, batch_should_take_each_rays_own_options);
    tcase_add_test(tc, batch_should_say_which_path_it_took);
    tcase_add_test(tc, unusable_rays_in_a_packet_should_miss_as_single_rays);
    tcase_add_test(tc, batch_should_refuse_misuse);
    suite_add_tcase(s, tc);
    return s;
}
