/* SPDX-License-Identifier: MIT */
/*
** intersect.c -- nearest-hit and any-hit queries over a committed scene:
** the planes one by one, then two BVHs, one over the triangles (stored in
** leaf order) and one over the other bounded primitives (spheres,
** polygons and the curved surfaces).  Each hit shrinks tmax,
** so every later box and primitive is tested against the nearest so far.
*/
#include "traverse.h"

/* The queries of traverse.h for the baseline instruction set, and the
** choice of the AVX2 copy (intersect_avx2.c) where the CPU has it:
** __builtin_cpu_supports reads what libgcc found at start-up (a load and
** a test), and also checks that the OS saves the AVX registers. */
int ray__intersect_base(const ray_scene *s, const ray_ray *r, ray_hit *hit,
                        ray_stats *st)
{
    return query_nearest(s, r, hit, st);
}

int ray__occluded_base(const ray_scene *s, const ray_ray *r, ray_stats *st)
{
    return query_any(s, r, st);
}

int ray__intersect(const ray_scene *s, const ray_ray *r, ray_hit *hit,
                   ray_stats *st)
{
#if RAY__AVX2_COPY
    if (__builtin_cpu_supports("avx2"))
        return ray__intersect_avx2(s, r, hit, st);
#endif
    return query_nearest(s, r, hit, st);
}

int ray__occluded(const ray_scene *s, const ray_ray *r, ray_stats *st)
{
#if RAY__AVX2_COPY
    if (__builtin_cpu_supports("avx2"))
        return ray__occluded_avx2(s, r, st);
#endif
    return query_any(s, r, st);
}

/* Misuse is a negated status, not 0, so that it cannot pass for a miss
** (as ray_implicit does); checked once per call, before any traversal. */
static int query_misuse(const ray_scene *s, const ray_ray *r)
{
    if (s == NULL || r == NULL)
        return -RAY_EINVAL;
    return s->committed ? RAY_OK : -RAY_ESTATE;
}

int ray_intersect(const ray_scene *s, const ray_ray *r, ray_hit *hit)
{
    int rc = query_misuse(s, r);

    if (rc != RAY_OK)
        return rc;
    if (hit == NULL)
        return -RAY_EINVAL;
    return ray__intersect(s, r, hit, NULL);
}

int ray_occluded(const ray_scene *s, const ray_ray *r)
{
    int rc = query_misuse(s, r);

    if (rc != RAY_OK)
        return rc;
    return ray__occluded(s, r, NULL);
}
