/* SPDX-License-Identifier: MIT */
/*
** intersect.c -- nearest-hit and any-hit queries over a committed scene:
** the planes one by one, then two BVHs, one over the triangles (stored in
** leaf order) and one over the other bounded primitives (spheres,
** polygons and the curved surfaces).  Each hit shrinks tmax,
** so every later box and primitive is tested against the nearest so far.
*/
#include "query/traverse.h"

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

/* The AVX2 copy where the CPU has it (see above). */
#define HAS_AVX2(s) ((s)->avx2)

/*
** The gate of a query with options q (NULL: the plain queries' every
** mask bit and no query_ud) for filters of kind "query": NULL (the
** ungated path) when nothing can gate it: no mask or filter in the scene
** and q asks for nothing.  The scene's "gated" covers its instances'
** children too (set at commit).
*/
static const ray__gate *gate_of(const ray_scene *s, const ray_query *q,
                                unsigned query, ray__gate *g)
{
    g->mask = q != NULL ? q->mask : ~0u;
    g->query_ud = q != NULL ? q->query_ud : NULL;
    g->query = query;
    g->all = NULL;
    if (!s->gated && g->mask == ~0u)
        return NULL;
    return g;
}

int ray__intersect(const ray_scene *s, const ray_ray *r, int uv,
                   ray_hit *hit, ray_stats *st)
{
    ray__gate g;

    return ray__intersect_gated(s, r, gate_of(s, NULL, RAY_FILTER_INTERSECT,
                                              &g), uv, hit, st);
}

int ray__occluded(const ray_scene *s, const ray_ray *r, ray_stats *st)
{
    ray__gate g;

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

void ray_query_init(ray_query *q)
{
    if (q == NULL)
        return;
    q->mask = ~0u;
    q->query_ud = NULL;
}

int ray_intersect_opt(const ray_scene *s, const ray_ray *r,
                      const ray_query *q, ray_hit *hit)
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

int ray_occluded_opt(const ray_scene *s, const ray_ray *r,
                     const ray_query *q)
{
    int rc = query_misuse(s, r);
    ray__gate g;

    if (rc != RAY_OK)
        return rc;
    return ray__occluded_gated(s, r, gate_of(s, q, RAY_FILTER_OCCLUDED, &g),
                               NULL);
}

int ray_intersect(const ray_scene *s, const ray_ray *r, ray_hit *hit)
{
    return ray_intersect_opt(s, r, NULL, hit);
}

int ray_occluded(const ray_scene *s, const ray_ray *r)
{
    return ray_occluded_opt(s, r, NULL);
}

/* Can ray__packets_avx2 take this scene and gate?  Triangles alone (the
** packets settle ties between triangles only: packet.h) and no gate. */
static int packable(const ray_scene *s, const ray__gate *g)
{
    return g == NULL && s->n_planes == 0 && s->prim_bvh.n_wide == 0;
}

/* ray_intersect_n and ray_occluded_n ("any"), their arguments checked. */
static void queries_n(const ray_scene *s, const ray_ray *rays, size_t n,
                      const ray_query *q, ray_hit *hits, int *results,
                      int any)
{
    ray__gate gs;
    const ray__gate *g = gate_of(s, q, any ? RAY_FILTER_OCCLUDED
                                           : RAY_FILTER_INTERSECT, &gs);
    size_t i;

#if RAY__AVX2_COPY
    if (packable(s, g) && HAS_AVX2(s)) {
        ray__packets_avx2(s, rays, n, hits, results, any);
        return;
    }
#else
    (void)packable;
#endif
    for (i = 0; i < n; i++)
        results[i] = any ? ray__occluded_gated(s, &rays[i], g, NULL)
                         : ray__intersect_gated(s, &rays[i], g, 1,
                                                &hits[i], NULL);
}

int ray_intersect_n(const ray_scene *s, const ray_ray *rays, size_t n,
                    const ray_query *q, ray_hit *hits, int *results)
{
    if (s == NULL ||
        (n > 0 && (rays == NULL || hits == NULL || results == NULL)))
        return RAY_EINVAL;
    if (!s->committed)
        return RAY_ESTATE;
    queries_n(s, rays, n, q, hits, results, 0);
    return RAY_OK;
}

int ray_occluded_n(const ray_scene *s, const ray_ray *rays, size_t n,
                   const ray_query *q, int *results)
{
    if (s == NULL || (n > 0 && (rays == NULL || results == NULL)))
        return RAY_EINVAL;
    if (!s->committed)
        return RAY_ESTATE;
    queries_n(s, rays, n, q, NULL, results, 1);
    return RAY_OK;
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
        return rc;
    if (count == NULL || (hits == NULL && cap > 0))
        return -RAY_EINVAL;
    /* Checked before the traversal, so that a stale instance cannot
    ** leave hits[] half written. */
    if (ray__scene_stale(s))
        return -RAY_ESTATE;
    c.hits = hits;
    c.cap = cap;
    c.count = 0;
    gate_of(s, q, RAY_FILTER_INTERSECT | RAY_FILTER_OCCLUDED, &g);
    g.all = &c;
    rc = ray__occluded_gated(s, r, &g, NULL);
    if (rc < 0)
        return rc;
    kept = c.count < cap ? c.count : cap;
    sort_hits(hits, kept);
    *count = c.count;
    return c.count > (size_t)0x7fffffff ? 0x7fffffff : (int)c.count;
}
