/* SPDX-License-Identifier: MIT */
/*
** intersect_avx2.c -- the scene queries of traverse.h once more, built
** with -mavx2 where the compiler targets x86 (see the Makefile): the box
** test then takes a node's eight boxes in one register.  intersect.c
** calls these only on a CPU with AVX2.  Built without -mavx2 (another
** build system), they are the baseline code again: slower, not wrong.
*/
#include "query/query.h"

#if RAY__AVX2_COPY
#include "query/packet.h"

int ray__intersect_gated_avx2(const ray_scene *s, const ray_ray *r,
                              const ray__gate *g, int uv, ray_hit *hit,
                              ray_stats *st)
{
    return query_nearest_gated(s, r, g, uv, hit, st);
}

int ray__occluded_gated_avx2(const ray_scene *s, const ray_ray *r,
                             const ray__gate *g, ray_stats *st)
{
    return query_any_gated(s, r, g, st);
}

void ray__trav_data_avx2(const ray_ray *r, uint32_t f[13], size_t at[6])
{
    trav_data(r, f, at);
}

int ray__intersect_tris_avx2(const ray_scene *s, const ray_ray *r,
                             ray_hit *hit)
{
    return query_nearest_tris(s, r, hit);
}

int ray__occluded_tris_avx2(const ray_scene *s, const ray_ray *r)
{
    return query_any_tris(s, r);
}

int ray__intersect_few_avx2(const ray_scene *s, const ray_ray *r, int uv,
                            ray_hit *hit, ray_stats *st)
{
    return query_nearest_few(s, r, uv, hit, st);
}

int ray__occluded_few_avx2(const ray_scene *s, const ray_ray *r,
                           ray_stats *st)
{
    return query_any_few(s, r, st);
}

int ray__intersect_instances_avx2(const ray_scene *s, const ray_ray *r,
                                  ray_hit *hit)
{
    return query_nearest_instances(s, r, hit);
}

int ray__occluded_instances_avx2(const ray_scene *s, const ray_ray *r)
{
    return query_any_instances(s, r);
}

void ray__packets_avx2(const ray_scene *s, const ray_ray *rays, size_t n,
                       ray_hit *hits, int *results, int any, ray_stats *st)
{
#if RAY__PACKETS
    packet_queries(s, rays, n, hits, results, any, st);
#else
    /* Built without AVX (see the top of this file): ray by ray. */
    size_t i;
    for (i = 0; i < n; i++)
        results[i] = any ? query_any_gated(s, &rays[i], NULL, st)
                         : query_nearest_gated(s, &rays[i], NULL, 1, &hits[i],
                                               st);
#endif
}
#else
typedef int ray__no_avx2_copy;  /* ISO C wants a declaration in a file */
#endif
