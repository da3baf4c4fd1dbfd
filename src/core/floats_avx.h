/* SPDX-License-Identifier: MIT */
/*
** floats_avx.h -- four doubles rounded outward to floats at once: the
** AVX form of vec.h's ray__float_down and ray__float_up, for the files
** built with AVX (the queries' set-up, query/slab.h; the refit's leaf,
** scene/refit_avx2.c).  The same operations lane for lane -- the
** conversion to float (vcvtpd2ps rounds to nearest as cvtsd2ss does),
** the comparison of its double with x, and the step to the neighbouring
** float on the integer bits -- so the same bits.
*/
#ifndef RAY_FLOATS_AVX_H
#define RAY_FLOATS_AVX_H

#if defined(__AVX__) && !defined(RAY_NO_SIMD)
#include <immintrin.h>

/* The four 64-bit lanes of a comparison's mask (all ones or zero) as
** four 32-bit lanes: the low half of each. */
static inline __m128i mask_narrow(__m256d m)
{
    __m256 f = _mm256_castpd_ps(m);

    return _mm_castps_si128(_mm_shuffle_ps(_mm256_castps256_ps128(f),
                                           _mm256_extractf128_ps(f, 1),
                                           _MM_SHUFFLE(2, 0, 2, 0)));
}

/* x's four lanes as floats rounded down (up 0) or up (up 1). */
static inline __m128 floats_step(__m256d x, int up)
{
    __m128 f = _mm256_cvtpd_ps(x);
    __m256d back = _mm256_cvtps_pd(f);
    /* need: the float lies on the wrong side of x (all ones, or 0) */
    __m128i need = mask_narrow(up ? _mm256_cmp_pd(back, x, _CMP_LT_OQ)
                                  : _mm256_cmp_pd(back, x, _CMP_GT_OQ));
    __m128i u = _mm_castps_si128(f);
    __m128i neg = _mm_srai_epi32(u, 31);       /* -1 where f's sign is set */
    /* up: f >= +0: +1; f < 0: -1.  down: f > 0: -1; f < 0 or -0: +1.
    ** As a step s = +-1 (2 neg + 1 for up, -(2 neg + 1) for down), added
    ** where needed: u + (need & s). */
    __m128i step = _mm_add_epi32(_mm_add_epi32(neg, neg), _mm_set1_epi32(1));
    if (!up)
        step = _mm_sub_epi32(_mm_setzero_si128(), step);
    return _mm_castsi128_ps(_mm_add_epi32(u, _mm_and_si128(need, step)));
}
#endif

#endif /* RAY_FLOATS_AVX_H */
