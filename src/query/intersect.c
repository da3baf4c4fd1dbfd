/* SPDX-License-Identifier: MIT */
/*
** intersect.c -- nearest-hit and any-hit queries over a committed scene:
** the planes one by one, then two BVHs, one over the triangles (stored in
** leaf order) and one over the other bounded primitives (spheres,
** polygons and the curved surfaces).  Each hit shrinks tmax,
** so every later box and primitive is tested against the nearest so far.
*/
#include "query/traverse.h"
#include "query/why.h"

#ifdef RAY_BENCH_COUNTS
unsigned long long ray__work[RAY__WORK_KINDS];
#endif

/* The queries of traverse.h for the baseline instruction set, and the
** choice of the AVX2 copy (intersect_avx2.c) where the CPU has it: the
** scene's avx2, which its commit asked of the CPU (ray__cpu_has_avx2:
** cpuid, and whether the OS saves the AVX registers), so a query pays a
** load and a test.  A NULL gate is the plain queries' path (traverse.h
** never reaches a gate). */
int ray__intersect_gated_base(const ray_scene *s, const ray_ray *r,
                              const ray__gate *g, int uv, ray_hit *hit,
                              ray_stats *st)
{
    return query_nearest_gated(s, r, g, uv, hit, st);
}

int ray__occluded_gated_base(const ray_scene *s, const ray_ray *r,
                             const ray__gate *g, ray_stats *st)
{
    return query_any_gated(s, r, g, st);
}

void ray__trav_data_base(const ray_ray *r, uint32_t f[13], size_t at[6])
{
    trav_data(r, f, at);
}

int ray__intersect_tris_base(const ray_scene *s, const ray_ray *r,
                             ray_hit *hit)
{
    return query_nearest_tris(s, r, hit);
}

int ray__occluded_tris_base(const ray_scene *s, const ray_ray *r)
{
    return query_any_tris(s, r);
}

int ray__intersect_instances_base(const ray_scene *s, const ray_ray *r,
                                  ray_hit *hit)
{
    return query_nearest_instances(s, r, hit);
}

int ray__occluded_instances_base(const ray_scene *s, const ray_ray *r)
{
    return query_any_instances(s, r);
}

int ray__intersect_few_base(const ray_scene *s, const ray_ray *r, int uv,
                            ray_hit *hit, ray_stats *st)
{
    return query_nearest_few(s, r, uv, hit, st);
}

int ray__occluded_few_base(const ray_scene *s, const ray_ray *r,
                           ray_stats *st)
{
    return query_any_few(s, r, st);
}

/* The AVX2 copy where the CPU has it (see above). */
#define HAS_AVX2(s) ((s)->avx2)

/*
** The gate of a query with options q (NULL: the plain queries' every
** mask bit seen, ignore_mask 0, and no query_ud) for filters of kind "query": NULL (the
** ungated path) when nothing can gate it: no mask or filter in the scene
** and q asks for nothing.  The scene's "gated" covers its instances'
** children too (set at commit).
*/
static const ray__gate *gate_of(const ray_scene *s, const ray_query *q,
                                unsigned query, ray__gate *g)
{
    g->mask = q != NULL ? ~q->ignore_mask : ~0u;
    g->query_ud = q != NULL ? q->query_ud : NULL;
    g->query = query;
    g->all = NULL;
    if (!s->gated && g->mask == ~0u)
        return NULL;
    return g;
}

/* The tracer's queries (ungated, counted).  A scene of planes and a few
** spheres (and triangles) goes straight to its lean path (plain.h,
** query_nearest_few), which the general query hands it to only after its
** own frame and checks: Whitted's render 566.1M -> 556.3M instructions,
** the Cornell box's 2366.3M -> 2361.2M (callgrind; issue 35). */
int ray__intersect(const ray_scene *s, const ray_ray *r, int uv,
                   ray_hit *hit, ray_stats *st)
{
    ray__gate g;

    if (!s->gated && s->few_spheres) {
#if RAY__AVX2_COPY
        if (HAS_AVX2(s))
            return ray__intersect_few_avx2(s, r, uv, hit, st);
#endif
        return ray__intersect_few_base(s, r, uv, hit, st);
    }
    return ray__intersect_gated(s, r, gate_of(s, NULL, RAY_FILTER_INTERSECT,
                                              &g), uv, hit, st);
}

int ray__occluded(const ray_scene *s, const ray_ray *r, ray_stats *st)
{
    ray__gate g;

    if (!s->gated && s->few_spheres) {
#if RAY__AVX2_COPY
        if (HAS_AVX2(s))
            return ray__occluded_few_avx2(s, r, st);
#endif
        return ray__occluded_few_base(s, r, st);
    }
    return ray__occluded_gated(s, r, gate_of(s, NULL, RAY_FILTER_OCCLUDED, &g),
                               st);
}

int ray__intersect_gated(const ray_scene *s, const ray_ray *r,
                         const ray__gate *g, int uv, ray_hit *hit,
                         ray_stats *st)
{
#if RAY__AVX2_COPY
    if (HAS_AVX2(s))
        return ray__intersect_gated_avx2(s, r, g, uv, hit, st);
#endif
    return query_nearest_gated(s, r, g, uv, hit, st);
}

int ray__occluded_gated(const ray_scene *s, const ray_ray *r,
                        const ray__gate *g, ray_stats *st)
{
#if RAY__AVX2_COPY
    if (HAS_AVX2(s))
        return ray__occluded_gated_avx2(s, r, g, st);
#endif
    return query_any_gated(s, r, g, st);
}

/* Misuse is a negated status, not 0, so that it cannot pass for a miss
** (as ray_implicit does); checked once per call, before any traversal. */
static int query_misuse(const ray_scene *s, const ray_ray *r)
{
    if (s == NULL || r == NULL)
        return -RAY_EINVAL;
    return s->committed ? RAY_OK : -RAY_ESTATE;
}

/* ray_intersect with options (q not NULL, or a scene the fast path below
** does not take). */
static int intersect_opt(const ray_scene *s, const ray_ray *r, ray_hit *hit,
                         const ray_query *q)
{
    int rc = query_misuse(s, r);
    ray__gate g;

    if (rc != RAY_OK)
        return rc;
    if (hit == NULL)
        return -RAY_EINVAL;
    return ray__intersect_gated(s, r, gate_of(s, q, RAY_FILTER_INTERSECT, &g),
                                1, hit, NULL);
}

static int occluded_opt(const ray_scene *s, const ray_ray *r,
                        const ray_query *q)
{
    int rc = query_misuse(s, r);
    ray__gate g;

    if (rc != RAY_OK)
        return rc;
    return ray__occluded_gated(s, r, gate_of(s, q, RAY_FILTER_OCCLUDED, &g),
                               NULL);
}

/*
** A plain query of a committed scene of triangles alone, with no masks or
** filters (nothing can gate it): straight to the copy's triangle walk
** (traverse.h's query_nearest_tris), past the options, the gate and the
** general query's set-up, which are nothing for it: a game's or a tool's
** most common query, at the fixed cost it needs (issue 34).  A scene of
** instances alone, each of a child of triangles alone (a crowd of placed
** meshes), goes as straight to the instances' walk
** (query_nearest_instances; issue 36).  Taken when q is NULL: a query's
** options may hide geometry whatever the scene's masks (an ignore_mask
** of every bit hides all of it).
*/
static int plain(const ray_scene *s, const ray_ray *r)
{
    return s != NULL && r != NULL && s->committed && !s->gated &&
           (tris_only(s) || s->instances_of_tris);
}

static int plain_nearest(const ray_scene *s, const ray_ray *r, ray_hit *hit)
{
    if (tris_only(s)) {
#if RAY__AVX2_COPY
        if (HAS_AVX2(s))
            return ray__intersect_tris_avx2(s, r, hit);
#endif
        return query_nearest_tris(s, r, hit);
    }
#if RAY__AVX2_COPY
    if (HAS_AVX2(s))
        return ray__intersect_instances_avx2(s, r, hit);
#endif
    return query_nearest_instances(s, r, hit);
}

static int plain_any(const ray_scene *s, const ray_ray *r)
{
    if (tris_only(s)) {
#if RAY__AVX2_COPY
        if (HAS_AVX2(s))
            return ray__occluded_tris_avx2(s, r);
#endif
        return query_any_tris(s, r);
    }
#if RAY__AVX2_COPY
    if (HAS_AVX2(s))
        return ray__occluded_instances_avx2(s, r);
#endif
    return query_any_instances(s, r);
}

/*
** Why a ray query (op) refused with rc (ray.h, ray_query.why): its
** checks again, in their order (query_misuse, then the output's, then the
** scene's state or a stale instance met), on the refusal path only.
** "out" names the output argument that was NULL, when that was the
** reason left.
*/
static int ray_refused(const ray_query *q, const char *op, int rc,
                       const ray_scene *s, const ray_ray *r, const char *out)
{
    char *why = q != NULL ? q->why : NULL;
    size_t size = q != NULL ? q->why_size : 0;

    if (why == NULL)
        return rc;
    if (s == NULL)
        return ray__why(why, size, rc, op, "scene is NULL");
    if (r == NULL)
        return ray__why(why, size, rc, op, "r is NULL");
    if (rc == -RAY_ESTATE)
        return ray__why_state(why, size, rc, op, s);
    return ray__why(why, size, rc, op, "%s", out);
}

int ray_intersect(const ray_scene *s, const ray_ray *r, ray_hit *hit,
                  const ray_query *q)
{
    int rc;

    if (q == NULL && hit != NULL && plain(s, r))
        return plain_nearest(s, r, hit);
    rc = intersect_opt(s, r, hit, q);
    return rc >= 0 ? rc
                   : ray_refused(q, "ray_intersect", rc, s, r, "hit is NULL");
}

int ray_occluded(const ray_scene *s, const ray_ray *r, const ray_query *q)
{
    int rc;

    if (q == NULL && plain(s, r))
        return plain_any(s, r);
    rc = occluded_opt(s, r, q);
    return rc >= 0 ? rc : ray_refused(q, "ray_occluded", rc, s, r, "");
}

/*
** Do eight rays go the same way, so that tracing them together pays?
** Each direction lies within acos(0.99) of the first one's (about 8
** degrees; a 4 x 2 block of camera pixels spans well under one, shadow
** rays from neighbouring points to one light a few).  Rays that scatter
** (diffuse bounces, random picks) visit different nodes: together, each
** node a lane visits would be fetched for the eight and tested eight
** times where one lane needs it, which made such packets 7 to 9 % slower
** than one ray at a time (bench/packets, issue 27); they go one by one.
** The test is squared, cos^2 |d0|^2 |dk|^2 <= (d0 . dk)^2 with d0 . dk >
** 0, so that it takes no square root and no division, and an incoherent
** group is usually told by its second ray: a test that normalised all
** eight first cost incoherent batches 2 to 5 % against one ray at a time.
** It only chooses the path: a packet's answers are the single rays'
** (lanes whose rays are not usable are left out there: packet.h), so an
** overflow here (directions near 1e154) costs speed, not correctness.
*/
#define PACKET_COS2 (0.99 * 0.99)

static int coherent(const ray_ray *r)
{
    ray_vec3 d0 = r[0].dir;
    double n0 = v3_dot(d0, d0);
    int k;

    for (k = 1; k < 8; k++) {
        double c = v3_dot(d0, r[k].dir);
        if (!(c > 0 && c * c >= PACKET_COS2 * n0 * v3_dot(r[k].dir, r[k].dir)))
            return 0;
    }
    return 1;
}

/* Can rays[i .. i + 7], each with its own gate, go in a packet? */
static int packet_ok(const ray_scene *s, const ray_ray *rays, size_t i,
                     const ray_query *queries, unsigned kind)
{
    ray__gate g;
    size_t k;

    for (k = i; k < i + 8; k++)
        if (!ray__packable(s, gate_of(s, &queries[k], kind, &g),
                           kind == RAY_FILTER_OCCLUDED))
            return 0;
    return coherent(rays + i);
}

/*
** Rays in groups of eight, ray i with options queries[i] (or the one set
** q_all, NULL for none, when queries is NULL), each group through the BVH
** together where it is packable and coherent, else ray by ray; answers
** into results (and hits), counts into *st (may be NULL), and the
** batch's own counts (batch_packets, batch_single) only where batch is
** set: the batch calls and ray__occluded_group share this one loop.
** Under one set of options the gate and the rule are the same for every
** group, so they are asked once.
*/
static void groups_run(const ray_scene *s, const ray_ray *rays, size_t n,
                       const ray_query *queries, const ray_query *q_all,
                       ray_hit *hits, int *results, int any, int batch,
                       ray_stats *st)
{
    unsigned kind = any ? RAY_FILTER_OCCLUDED : RAY_FILTER_INTERSECT;
    ray__gate g_all;
    /* q_all is not read where each ray has its own (queries): it need not
    ** be set then (ray_batch). */
    const ray__gate *gp_all = queries == NULL
        ? gate_of(s, q_all, kind, &g_all) : NULL;
    int packs = HAS_AVX2(s) && (queries != NULL ||
                                ray__packable(s, gp_all, any));
    size_t i, end;

    for (i = 0; i < n; i = end) {
        end = n - i < 8 ? n : i + 8;
#if RAY__AVX2_COPY
        if (packs && end - i == 8 &&
            (queries != NULL ? packet_ok(s, rays, i, queries, kind)
                             : coherent(rays + i))) {
            ray__packets_avx2(s, rays + i, 8, any ? NULL : hits + i,
                              results + i, any, st);
            if (batch && st != NULL)
                st->batch_packets += 8;
            continue;
        }
#endif
        for (; i < end; i++) {
            ray__gate g;
            const ray__gate *gp = queries != NULL
                ? gate_of(s, &queries[i], kind, &g) : gp_all;
            results[i] = any ? ray__occluded_gated(s, &rays[i], gp, st)
                             : ray__intersect_gated(s, &rays[i], gp, 1,
                                                    &hits[i], st);
            if (batch && st != NULL)
                st->batch_single++;
        }
    }
#if !RAY__AVX2_COPY
    (void)packet_ok;
    (void)packs;
#endif
}

void ray__occluded_group(const ray_scene *s, const ray_ray *rays, size_t n,
                         int *out, ray_stats *st)
{
    groups_run(s, rays, n, NULL, NULL, NULL, out, 1, 0, st);
}

/* A batch's arguments: RAY_OK, RAY_EINVAL or RAY_ESTATE. */
static int batch_check(const ray_scene *s, const ray_ray *rays, size_t n,
                       const ray_hit *hits, const int *results, int any)
{
    if (s == NULL ||
        (n > 0 && (rays == NULL || results == NULL || (!any && hits == NULL))))
        return RAY_EINVAL;
    return s->committed ? RAY_OK : RAY_ESTATE;
}

/* Why a batch (op) was refused with rc, batch_check's checks again in
** their order, into b->why: the refusal path only. */
static int batch_refused(const ray_batch *b, const char *op, int rc,
                         const ray_scene *s)
{
    if (s == NULL)
        return ray__why(b->why, b->why_size, rc, op, "scene is NULL");
    if (rc == RAY_ESTATE)
        return ray__why_state(b->why, b->why_size, rc, op, s);
    return ray__why(b->why, b->why_size, rc, op, "b->%s is NULL with b->n "
                    "= %zu", b->rays == NULL ? "rays"
                    : b->results == NULL ? "results" : "hits",
                    b->n);
}

/* ray_intersect_batch and ray_occluded_batch ("any"): each ray its own
** options (queries), or one set for all (query), through the same
** groups_run and so the same packets. */
static int batch_of(const ray_scene *s, const ray_batch *b, int any,
                    const char *op)
{
    int rc;

    if (b == NULL)
        return RAY_EINVAL;       /* no batch: no buffer for a reason */
    rc = batch_check(s, b->rays, b->n, b->hits, b->results, any);
    if (rc != RAY_OK)
        return batch_refused(b, op, rc, s);
    groups_run(s, b->rays, b->n, b->queries, b->query, any ? NULL : b->hits,
               b->results, any, 1, b->stats);
    return rc;
}

int ray_intersect_batch(const ray_scene *s, const ray_batch *b)
{
    return batch_of(s, b, 0, "ray_intersect_batch");
}

int ray_occluded_batch(const ray_scene *s, const ray_batch *b)
{
    return batch_of(s, b, 1, "ray_occluded_batch");
}

/* Sort the collected hits nearest first (insertion sort: a ray crosses
** few surfaces, and it is stable). */
static void sort_hits(ray_hit *h, size_t n)
{
    size_t i, j;

    for (i = 1; i < n; i++) {
        ray_hit x;
        ray__hit_store(&x, &h[i]);
        for (j = i; j > 0 && collect_before(&x, &h[j - 1]); j--)
            ray__hit_store(&h[j], &h[j - 1]);
        ray__hit_store(&h[j], &x);
    }
}

/* ray_intersect_all's hits NULL with room asked for, in words. */
static int all_refused(const ray_query *q, size_t cap)
{
    if (q == NULL)
        return -RAY_EINVAL;
    return ray__why(q->why, q->why_size, -RAY_EINVAL, "ray_intersect_all",
                    "hits is NULL with cap = %zu", cap);
}

/*
** Every hit: an any-hit traversal whose gate records each candidate that
** passes masks and filters and then rejects it, so nothing stops the
** traversal and no interval shrinks.  Both kinds of filter apply.
*/
int ray_intersect_all(const ray_scene *s, const ray_ray *r,
                      const ray_query *q, ray_hit *hits, size_t cap,
                      size_t *count)
{
    int rc = query_misuse(s, r);
    ray__collect c;
    ray__gate g;
    size_t kept;

    if (rc != RAY_OK)
        return ray_refused(q, "ray_intersect_all", rc, s, r, "");
    if (count == NULL)
        return ray_refused(q, "ray_intersect_all", -RAY_EINVAL, s, r,
                           "count is NULL");
    if (hits == NULL && cap > 0)
        return all_refused(q, cap);
    /* Checked before the traversal, so that a stale instance cannot
    ** leave hits[] half written. */
    if (ray__scene_stale(s))
        return ray_refused(q, "ray_intersect_all", -RAY_ESTATE, s, r, "");
    c.hits = hits;
    c.cap = cap;
    c.count = 0;
    gate_of(s, q, RAY_FILTER_INTERSECT | RAY_FILTER_OCCLUDED, &g);
    g.all = &c;
    rc = ray__occluded_gated(s, r, &g, NULL);
    if (rc < 0)
        return ray_refused(q, "ray_intersect_all", rc, s, r, "");
    kept = c.count < cap ? c.count : cap;
    sort_hits(hits, kept);
    *count = c.count;
    return c.count > (size_t)0x7fffffff ? 0x7fffffff : (int)c.count;
}
