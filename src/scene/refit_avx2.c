/* SPDX-License-Identifier: MIT */
/*
** refit_avx2.c -- the refit's leaf (boxes.c, ray__refit_leaf) once more,
** built with -mavx2 where the compiler targets x86 (the Makefile's and
** CMake's AVX2 flag, as for query/intersect_avx2.c): a corner's x, y and
** z in one register, so that its box, its normal test, its nine floats
** and its copy take one operation where the SSE2 leaf takes two or three.
** triangles.c calls it on a CPU with AVX2 (the scene's avx2, which its
** first commit asked of the CPU).  Built without AVX2 (another build
** system, or with RAY_NO_SIMD or RAY_NO_AVX2), ray__refit_leaf_avx2
** answers NULL and the baseline leaf runs.
**
** The same bits as the SSE2 leaf, lane for lane: the same products,
** differences, minima and maxima in the same order (vminpd and vmaxpd
** pick as minpd and maxpd do, "a < b ? a : b"), and vcvtpd2ps rounds
** as cvtpd2ps does, in the current mode; without FMA (-mavx2 alone, and
** -ffp-contract=off), no product is fused.  The fourth lane is loaded as
** 0 (a masked load, which reads nothing past the corner) and so never
** changes a test: 0 is neither above 0 nor infinite nor out of range.
** tests/check_bvh.c compares the two leaves on hard meshes, bit for bit.
*/
#include "scene/slots.h"
#include "core/floats_avx.h"

#if defined(__AVX2__) && !defined(RAY_NO_SIMD) && !defined(RAY_NO_AVX2)
#include <immintrin.h>

/* A corner: x, y, z and a zero. */
static inline __m256d corner(const ray_vec3 *p)
{
    return _mm256_maskload_pd(&p->x, _mm256_set_epi64x(0, -1, -1, -1));
}

/*
** Does the triangle a, b, c have a normal (ray__corners_usable)?  Its
** cross product e1.yzx e2.zxy - e1.zxy e2.yzx, the products and
** differences of the scalar one: some component non-zero, none infinite
** or NaN.
*/
static inline int usable(__m256d a, __m256d b, __m256d c)
{
    const __m256d sign = _mm256_set1_pd(-0.0), inf = _mm256_set1_pd(HUGE_VAL);
    __m256d e1 = _mm256_sub_pd(b, a), e2 = _mm256_sub_pd(c, a);
    __m256d p = _mm256_mul_pd(_mm256_permute4x64_pd(e1, _MM_SHUFFLE(3, 0, 2, 1)),
                              _mm256_permute4x64_pd(e2, _MM_SHUFFLE(3, 1, 0, 2)));
    __m256d q = _mm256_mul_pd(_mm256_permute4x64_pd(e1, _MM_SHUFFLE(3, 1, 0, 2)),
                              _mm256_permute4x64_pd(e2, _MM_SHUFFLE(3, 0, 2, 1)));
    __m256d n = _mm256_andnot_pd(sign, _mm256_sub_pd(p, q));

    return _mm256_movemask_pd(_mm256_cmp_pd(n, _mm256_setzero_pd(), _CMP_GT_OQ)) != 0 &&
           _mm256_movemask_pd(_mm256_cmp_pd(n, inf, _CMP_LT_OQ)) == 15;
}

/* A corner's three floats at r[0], r[stride], r[2 stride]. */
static inline void corner_rows(float *r, size_t stride, __m256d v)
{
    __m128 f = _mm256_cvtpd_ps(v);

    _mm_store_ss(r, f);
    _mm_store_ss(r + stride, _mm_shuffle_ps(f, f, 1));
    _mm_store_ss(r + 2 * stride, _mm_shuffle_ps(f, f, 2));
}

/* Does every coordinate of the box lo, hi lie within the rows' range
** (RAY__LEAF_FLOAT_MAX)? */
static inline int fits(__m256d lo, __m256d hi)
{
    const __m256d big = _mm256_set1_pd(RAY__LEAF_FLOAT_MAX),
                  nbig = _mm256_set1_pd(-RAY__LEAF_FLOAT_MAX);

    return _mm256_movemask_pd(_mm256_and_pd(_mm256_cmp_pd(lo, nbig, _CMP_GE_OQ),
                                            _mm256_cmp_pd(hi, big, _CMP_LE_OQ))) == 15;
}

/* ray__box_out_float (boxes.c) on the lanes x, y, z of lo and hi at
** once (floats_step: the same bits), where the six scalar roundings were
** a tenth of the leaf's time (perf annotate, a 940k refit, issue 36). */
static void leaf_box_out(__m256d lo, __m256d hi, float flo[3], float fhi[3])
{
    float l[4], h[4];

    _mm_storeu_ps(l, floats_step(lo, 0));
    _mm_storeu_ps(h, floats_step(hi, 1));
    memcpy(flo, l, 3 * sizeof *flo);
    memcpy(fhi, h, 3 * sizeof *fhi);
}

/* The leaf of n slots from "first": its box into lo, hi (rounded out to
** float), every slot's rows and copy written. */
static void refit_leaf_avx2(const void *ud, size_t first, size_t n,
                            float lo[3], float hi[3])
{
    const ray_scene *s = ud;
    float *rows = s->leaf_f + RAY__LEAF_ROWS * first;
    ray__tri *copy = s->leaf_tri != NULL ? s->leaf_tri + first : NULL;
    const ray__mesh *m = NULL;
    unsigned m_geom = (unsigned)-1;
    __m256d box_lo = _mm256_setzero_pd(), box_hi = box_lo;
    size_t j;

    for (j = 0; j < n; j++) {
        const ray_vec3 *p[3];
        ray__tri t;
        int mesh = ray__slot_corners_at(s, first + j, &m, &m_geom, &t, p);
        __m256d a = corner(p[0]), b = corner(p[1]), c = corner(p[2]);
        __m256d tlo, thi;
        float *r = rows + j;

        if (mesh)
            ray__prefetch_slots(s, first + j, m, m_geom);
        if (mesh && !usable(a, b, c))
            b = c = a;
        tlo = _mm256_min_pd(_mm256_min_pd(a, b), c);
        thi = _mm256_max_pd(_mm256_max_pd(a, b), c);
        if (j == 0)
            box_lo = box_hi = a;
        box_lo = _mm256_min_pd(box_lo, tlo);
        box_hi = _mm256_max_pd(box_hi, thi);
        if (fits(tlo, thi)) {
            corner_rows(r, n, a);
            corner_rows(r + 3 * n, n, b);
            corner_rows(r + 6 * n, n, c);
        } else {
            int k;
            for (k = 0; k < RAY__LEAF_ROWS; k++)
                r[(size_t)k * n] = (float)NAN;
        }
        if (copy != NULL) {
            /* In order, each store's zero lane overwritten by the next
            ** corner; the last corner's two halves stop at its z. */
            _mm256_storeu_pd(&copy[j].a.x, a);
            _mm256_storeu_pd(&copy[j].b.x, b);
            _mm_storeu_pd(&copy[j].c.x, _mm256_castpd256_pd128(c));
            _mm_store_sd(&copy[j].c.z, _mm256_extractf128_pd(c, 1));
        }
    }
    leaf_box_out(box_lo, box_hi, lo, hi);
}

ray__range_box_fn ray__refit_leaf_avx2(void)
{
    return refit_leaf_avx2;
}
#else
ray__range_box_fn ray__refit_leaf_avx2(void)
{
    return NULL;
}
#endif
