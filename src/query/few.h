/* SPDX-License-Identifier: MIT */
/*
** few.h -- part of the query template (traverse.h): a scene of a few
** spheres (s->few_spheres, set at commit) asked one sphere after another
** rather than through a BVH, each sphere's miss test taken for all of
** them at once.
*/
#ifndef RAY_FEW_H
#define RAY_FEW_H

/*
** Which of the few spheres of s the line of origin o and direction d (a
** = d.d) surely misses (ray__sphere_surely_missed, prim/prim.h): bit i
** for sphere i.  The AVX copy tests the four lanes of s->few at once,
** the same operations in the same order on the same numbers lane by lane
** (f = o - c, f x d, f.f, (f x d).(f x d), a (R^2 (1 + K) + f.f K); an
** ordered compare is false on NaN, as C's is), so the same bits: the
** spheres' miss tests were about 90 of the Whitted render's 285
** instructions a query outside the tests themselves (callgrind); the
** baseline copy asks each sphere's.
*/
static RAY__INLINE unsigned few_spheres_missed(const ray_scene *s,
                                               ray_vec3 o, ray_vec3 d,
                                               double a)
{
#if defined(__AVX__) && !defined(RAY_NO_SIMD)
    const ray__few_spheres *fs = &s->few;
    __m256d fx = _mm256_sub_pd(_mm256_set1_pd(o.x), _mm256_loadu_pd(fs->cx));
    __m256d fy = _mm256_sub_pd(_mm256_set1_pd(o.y), _mm256_loadu_pd(fs->cy));
    __m256d fz = _mm256_sub_pd(_mm256_set1_pd(o.z), _mm256_loadu_pd(fs->cz));
    __m256d dx = _mm256_set1_pd(d.x), dy = _mm256_set1_pd(d.y),
            dz = _mm256_set1_pd(d.z);
    __m256d xx = _mm256_sub_pd(_mm256_mul_pd(fy, dz), _mm256_mul_pd(fz, dy));
    __m256d xy = _mm256_sub_pd(_mm256_mul_pd(fz, dx), _mm256_mul_pd(fx, dz));
    __m256d xz = _mm256_sub_pd(_mm256_mul_pd(fx, dy), _mm256_mul_pd(fy, dx));
    __m256d g = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(fx, fx),
                                            _mm256_mul_pd(fy, fy)),
                              _mm256_mul_pd(fz, fz));
    __m256d c = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(xx, xx),
                                            _mm256_mul_pd(xy, xy)),
                              _mm256_mul_pd(xz, xz));
    __m256d bound = _mm256_mul_pd(
        _mm256_set1_pd(a),
        _mm256_add_pd(_mm256_loadu_pd(fs->rr),
                      _mm256_mul_pd(g, _mm256_set1_pd(RAY__SPHERE_MISS_K))));
    __m256d guard = _mm256_cmp_pd(g, _mm256_set1_pd(0x1p1000), _CMP_LT_OQ);

    return (unsigned)_mm256_movemask_pd(
        _mm256_and_pd(guard, _mm256_cmp_pd(c, bound, _CMP_GT_OQ)));
#else
    unsigned i, missed = 0;

    for (i = 0; i < s->prim_bvh.n_items; i++) {
        const ray__prim *p = &s->prims[s->prim_bvh.items[i]];
        if (ray__sphere_surely_missed(v3_sub(o, p->a), d, a, p->radius))
            missed |= 1u << i;
    }
    return missed;
#endif
}

/*
** The few spheres of s (s->few_spheres, set at commit, where commit.c
** says why and what it means for ties) along r, ungated: the ray's part
** of the test taken once (ray__sphere_ray_init), then each sphere's
** candidate test without the kinds' dispatch -- the same functions on
** the same numbers as the dispatch's, so the same answers, at about half
** the instructions a sphere (callgrind, the Whitted render, issue 35).
** 1 if one is hit: r->tmax shrunk to it and the nearest kept in *best
** (NULL: any hit, the first).  *tested: the spheres tested, counted once
** here rather than one by one (which was 15M instructions of the Whitted
** render): all of them, or at an any hit the i + 1 so far.
*/
static RAY__INLINE int few_spheres_along(const ray_scene *s, ray_ray *r,
                                         void *best, int any, int uv,
                                         unsigned *tested)
{
    ray__sphere_ray sr;
    ray_vec3 d = r->dir;
    double a = v3_dot(d, d);
    unsigned i, missed;
    int found = 0, ready = 0;

    *tested = 0;
    if (s->prim_bvh.n_items == 0)
        return 0;
    /* The ray's part of the test is made only for a sphere that the miss
    ** test cannot rule out: most rays of a scene miss all its few spheres
    ** (9 in 10 of the Whitted render's shadow rays).  The miss test reads
    ** the direction as given where d.d lies in [2^-20, 2^20]: a unit
    ** one's, and a shadow ray's towards a point light (its length the
    ** distance).  Its bound is the same for any length of d: c = |f x d|^2
    ** and a = d.d both scale by |d|^2, and its rounding errors are
    ** relative to them (ray__sphere_surely_missed, prim/prim.h), so only
    ** overflow and underflow could break it.  Within that range, with its
    ** guards (|f|^2 < 2^1000, 2^-400 <= R <= 2^500), c and the right side
    ** stay below 2^1021 and the right side at or above 2^-820 (a c that
    ** underflows is below it: the answer is then "not missed", safe).  Its
    ** answer is a safe early out either way, so the answers do not change.
    ** Shadow rays spawned towards a point (ray__spawn_to: d the whole way,
    ** t in [0, 1]) took the scaling's 72 instructions before, read as
    ** given only in [1/4, 4]: the Whitted render 597.7M -> 587.4M
    ** instructions (callgrind, 512 x 384), the same image (issue 35). */
    if (!(a >= 0x1p-20 && a <= 0x1p20)) {
        if (!ray__sphere_ray_init(r, &sr))
            return 0;              /* cannot happen: r is usable */
        d = sr.d;
        a = sr.a;
        ready = 1;
    }
    missed = few_spheres_missed(s, r->org, d, a);
    for (i = 0; i < s->prim_bvh.n_items; i++) {
        unsigned idx = s->prim_bvh.items[i];
        ray_hit h;
        int k;
        if (missed >> i & 1)
            continue;              /* as the test would, which then skips it */
        if (!ready && !ray__sphere_ray_init(r, &sr))
            return 0;              /* cannot happen: r is usable */
        ready = 1;
        k = ray__sphere_candidate(s, idx, &sr, r, &h, uv);
        if (!k)
            continue;
        r->tmax = h.t;
        if (any) {
            *tested = i + 1;
            return 1;
        }
        prim_keep(best, idx, k, &h);
        found = 1;
    }
    *tested = i;                   /* all of them */
    return found;
}

#endif /* RAY_FEW_H */
