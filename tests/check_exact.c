/* SPDX-License-Identifier: MIT */
/*
** check_exact.c -- the arithmetic the geometry needs the same on every
** platform, done in plain doubles rather than by the C runtime: the
** exact error of a product (ray__product_error, core/vec.h: what fma
** gives where fma is right; MinGW's is not) and hypot (ray__hypot,
** core/exact.c).  Checked against integer arithmetic and exact cases,
** not against the C library under test.
*/
#include <stdlib.h>

#include "core/exact.h"
#include "core/vec.h"
#include "tests.h"

#if defined(__SIZEOF_INT128__)
/* GCC's and Clang's 128-bit integers (a test-only extension). */
__extension__ typedef __int128 wide;

/* x / 2^unit as a 128-bit integer, x a multiple of 2^unit below 2^(unit
** + 108) in magnitude; *ok cleared if it is not. */
static wide at_unit(double x, int unit, int *ok)
{
    int ex;
    wide m = (wide)ldexp(frexp(x, &ex), 53);

    ex -= 53;
    while (m != 0 && m % 2 == 0) {    /* the odd mantissa: the largest
                                         power of two x is a multiple of */
        m /= 2;
        ex++;
    }
    if (m == 0)
        return 0;
    if (ex < unit || ex - unit > 108) {
        *ok = 0;
        return 0;
    }
    return m * ((wide)1 << (ex - unit));
}

/*
** Is p + e exactly a*b?  With 53-bit integer mantissas a = ia 2^ka,
** b = ib 2^kb, a*b is ia ib (106 bits) in units of 2^(ka + kb), and p
** and e, if right, are multiples of that unit below 2^108 of it.
*/
static int sum_is_product(double a, double b, double p, double e)
{
    int ka, kb, ok = 1;
    wide ia = (wide)ldexp(frexp(a, &ka), 53);
    wide ib = (wide)ldexp(frexp(b, &kb), 53);
    int unit = ka + kb - 106;
    wide sum = at_unit(p, unit, &ok) + at_unit(e, unit, &ok);

    return ok && sum == ia * ib;
}
#endif

/*
** ray__product_error(a, b, fl(a*b)) is a*b - fl(a*b) exactly, checked in
** 128-bit integers, over a million products of random operands from
** 2^-400 to 2^400 and of operands near the split's overflow (2^1000 by
** 2^-900: handed 2^512 across); and it is symmetric in a and b, also
** where the error rounds (subnormal products).
*/
START_TEST(product_error_should_be_exact)
{
    rng g = {4242};
    long i;

    for (i = 0; i < 1000000; i++) {
        double a = ldexp(rng_range(&g, -1, 1), (int)(rng_next(&g) % 800) - 400);
        double b = ldexp(rng_range(&g, -1, 1), (int)(rng_next(&g) % 800) - 400);
        double p = a * b, e = ray__product_error(a, b, p);
        if (i % 100 == 0) {
            a = ldexp(rng_range(&g, 0.5, 1), 1000);
            b = ldexp(rng_range(&g, -1, -0.5), -900);
            p = a * b;
            e = ray__product_error(a, b, p);
        }
        ck_assert(e == ray__product_error(b, a, p));
#if defined(__SIZEOF_INT128__)
        if (a != 0 && b != 0)
            ck_assert_msg(sum_is_product(a, b, p, e), "%a * %a: %a + %a",
                          a, b, p, e);
        /* The check can fail: an error one ulp off is caught. */
        if (e != 0)
            ck_assert(!sum_is_product(a, b, p, nextafter(e, HUGE_VAL)));
#endif
    }
    for (i = 0; i < 10000; i++) {
        double a = ldexp(rng_range(&g, -1, 1), -540);
        double b = ldexp(rng_range(&g, -1, 1), -540);
        double p = a * b;
        ck_assert(ray__product_error(a, b, p) == ray__product_error(b, a, p));
    }
}
END_TEST

/* The ulps between two positive finite doubles. */
static double ulps_apart(double a, double b)
{
    return fabs(a - b) / (nextafter(fmax(a, b), HUGE_VAL) - fmax(a, b));
}

/*
** ray__hypot: exact on Pythagorean triples at every scale (2^-1000 to
** 2^1000: no overflow, no underflow of the squares); C99's special cases
** (F.9.4.3: an infinity wins over a NaN); symmetric in its arguments and
** their signs; within one ulp of the C library's on random pairs (each
** is within an ulp of the truth: a looser check, not the reference).
*/
START_TEST(hypot_should_be_exact_at_every_scale)
{
    static const double triples[][3] = {{3, 4, 5}, {5, 12, 13},
                                        {20, 21, 29}, {119, 120, 169},
                                        {696, 697, 985}};
    rng g = {77};
    int k, i;

    for (k = -1000; k <= 1000; k += 25)
        for (i = 0; i < 5; i++) {
            double x = ldexp(triples[i][0], k), y = ldexp(triples[i][1], k);
            double z = ldexp(triples[i][2], k);
            ck_assert_msg(ray__hypot(x, y) == z, "%a %a", x, y);
            ck_assert(ray__hypot(-y, x) == z);
        }
    ck_assert(ray__hypot(HUGE_VAL, (double)NAN) == HUGE_VAL);
    ck_assert(ray__hypot((double)NAN, -HUGE_VAL) == HUGE_VAL);
    ck_assert(isnan(ray__hypot((double)NAN, 1.0)));
    ck_assert(ray__hypot(0.0, 0.0) == 0.0);
    ck_assert(ray__hypot(-2.5, 0.0) == 2.5);
    ck_assert(ray__hypot(DBL_MAX, 0.0) == DBL_MAX);
    ck_assert(ray__hypot(DBL_MAX, DBL_MAX) == HUGE_VAL);
    ck_assert(ray__hypot(0x1p-1074, 0x1p-1074) == 0x1p-1074);
    for (i = 0; i < 100000; i++) {
        double x = ldexp(rng_range(&g, -1, 1), (int)(rng_next(&g) % 200) - 100);
        double y = x * ldexp(rng_range(&g, -1, 1), (int)(rng_next(&g) % 60) - 30);
        double h = ray__hypot(x, y);
        ck_assert(h == ray__hypot(y, x) && h == ray__hypot(-x, -y));
        ck_assert_msg(ulps_apart(h, hypot(x, y)) <= 1.0, "%a %a", x, y);
    }
}
END_TEST

/* The bits of x (a NaN's payload included). */
static uint64_t bits_of(double x)
{
    uint64_t b;
    memcpy(&b, &x, sizeof b);
    return b;
}

/* Do x and y have the same bits, or are both NaN (C99 leaves a NaN's
** payload open)? */
static int same_bits(double x, double y)
{
    return (x != x && y != y) || bits_of(x) == bits_of(y);
}

/*
** The inline nextafter, fmax and fmin of core/vec.h (issue 35) against
** libm's, which they replace in the tracer's hot paths, so the images
** keep their bits: nextafter is defined exactly (C99 F.9.8.3), so its
** bits are compared everywhere; fmax and fmin by value on opposite
** zeros, whose sign C99 leaves open (glibc's x86-64 answers the second,
** as ray__fmax does), by bits otherwise.  Edge cases (zeros, the
** smallest subnormals, DBL_MIN's neighbours, DBL_MAX, infinities, NaN),
** then random bit patterns.
*/
START_TEST(inline_libm_should_give_libm_bits)
{
    static const double edge[] = {0.0, -0.0, 0x1p-1074, -0x1p-1074,
                                  0x1p-1073, DBL_MIN, -DBL_MIN,
                                  0x1.fffffffffffffp-1023, 1.0, -1.0,
                                  0x1.fffffffffffffp-1, DBL_MAX, -DBL_MAX,
                                  HUGE_VAL, -HUGE_VAL, (double)NAN};
    size_t n = sizeof edge / sizeof edge[0], i, j;
    rng g = {0x35};

    for (i = 0; i < n; i++) {
        double x = edge[i];
        ck_assert_msg(same_bits(ray__next_up(x), nextafter(x, HUGE_VAL)),
                      "%a", x);
        ck_assert_msg(same_bits(ray__next_down(x), nextafter(x, -HUGE_VAL)),
                      "%a", x);
        for (j = 0; j < n; j++) {
            double y = edge[j];
            if (x == 0 && y == 0) {
                ck_assert(ray__fmax(x, y) == fmax(x, y));
                ck_assert(ray__fmin(x, y) == fmin(x, y));
                continue;
            }
            ck_assert_msg(same_bits(ray__fmax(x, y), fmax(x, y)), "%a %a",
                          x, y);
            ck_assert_msg(same_bits(ray__fmin(x, y), fmin(x, y)), "%a %a",
                          x, y);
        }
    }
    /* Random patterns, a quarter of them pairs a few ulps apart; a NaN is
    ** made quiet (arithmetic makes no other: a signalling one is fmax's
    ** x + y, a case the library never meets). */
    for (i = 0; i < 200000; i++) {
        uint64_t a = rng_next(&g);
        uint64_t b = i % 4 == 0 ? a ^ (rng_next(&g) & 0xff) : rng_next(&g);
        double x, y;
        if ((a >> 52 & 0x7ff) == 0x7ff)
            a |= (uint64_t)1 << 51;
        if ((b >> 52 & 0x7ff) == 0x7ff)
            b |= (uint64_t)1 << 51;
        memcpy(&x, &a, sizeof x);
        memcpy(&y, &b, sizeof y);
        ck_assert_msg(same_bits(ray__next_up(x), nextafter(x, HUGE_VAL)),
                      "%a", x);
        ck_assert_msg(same_bits(ray__next_down(x), nextafter(x, -HUGE_VAL)),
                      "%a", x);
        ck_assert_msg(same_bits(ray__fmax(x, y), fmax(x, y)), "%a %a", x, y);
        ck_assert_msg(same_bits(ray__fmin(x, y), fmin(x, y)), "%a %a", x, y);
    }
}
END_TEST

Suite *exact_suite(void)
{
    Suite *s = suite_create("exact");
    TCase *tc = tcase_create("core");

    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, product_error_should_be_exact);
    tcase_add_test(tc, hypot_should_be_exact_at_every_scale);
    tcase_add_test(tc, inline_libm_should_give_libm_bits);
    suite_add_tcase(s, tc);
    return s;
}
