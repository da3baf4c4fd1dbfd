/* SPDX-License-Identifier: MIT */
/*
** check_version.c -- version macros and function, status-code strings.
*/
#include <stdio.h>

#include "tests.h"

START_TEST(version_should_match_header)
{
    char buf[32];

    ck_assert_int_eq(ray_version_number(), RAY_VERSION_NUMBER);
    ck_assert_str_eq(ray_version_string(), RAY_VERSION_STRING);
    ck_assert_int_eq(RAY_VERSION_NUMBER, RAY_VERSION_MAJOR * 10000 +
                     RAY_VERSION_MINOR * 100 + RAY_VERSION_PATCH);
    snprintf(buf, sizeof buf, "%d.%d.%d", RAY_VERSION_MAJOR,
             RAY_VERSION_MINOR, RAY_VERSION_PATCH);
    ck_assert_str_eq(buf, RAY_VERSION_STRING);
}
END_TEST

START_TEST(strerror_should_name_every_code)
{
    int codes[] = {RAY_OK, RAY_EINVAL, RAY_EDEGENERATE, RAY_ERANGE,
                   RAY_ENOMEM, RAY_EIO, RAY_EPNG, RAY_ESTATE, RAY_ECANCELED,
                   RAY_ELIMIT, RAY_EEFFECT, RAY_ENOTSUP, RAY_EKIND};
    size_t n = sizeof codes / sizeof codes[0], i, j;

    for (i = 0; i < n; i++) {
        const char *s = ray_strerror(codes[i]);
        ck_assert_ptr_nonnull(s);
        ck_assert_str_ne(s, "unknown error");
        for (j = 0; j < i; j++)
            ck_assert_str_ne(s, ray_strerror(codes[j]));
    }
    ck_assert_str_eq(ray_strerror(RAY_OK), "success");
}
END_TEST

/* The queries and the iterative intersections return negated statuses:
** each reads as the status itself. */
START_TEST(strerror_should_accept_negated_codes)
{
    int codes[] = {RAY_EINVAL, RAY_EDEGENERATE, RAY_ERANGE, RAY_ENOMEM,
                   RAY_EIO, RAY_EPNG, RAY_ESTATE, RAY_ECANCELED, RAY_ELIMIT,
                   RAY_EEFFECT, RAY_ENOTSUP, RAY_EKIND};
    size_t i;

    for (i = 0; i < sizeof codes / sizeof codes[0]; i++)
        ck_assert_str_eq(ray_strerror(-codes[i]), ray_strerror(codes[i]));
    ck_assert_str_eq(ray_strerror(-RAY_ELIMIT),
                     "a limit was reached (ray tree, iterations, image load)");
    ck_assert_str_eq(ray_strerror(-RAY_ESTATE),
                     "operation not allowed in this state");
}
END_TEST

/* Statuses are ABI: a new one goes at the end, the others keep their
** numbers (README, "Versions and ABI"). */
START_TEST(status_codes_should_keep_their_numbers)
{
    ck_assert_int_eq(RAY_OK, 0);
    ck_assert_int_eq(RAY_EINVAL, 1);
    ck_assert_int_eq(RAY_EPNG, 6);
    ck_assert_int_eq(RAY_EEFFECT, 10);
    ck_assert_int_eq(RAY_ENOTSUP, 11);
    ck_assert_str_eq(ray_strerror(RAY_ENOTSUP), "not supported by this build");
    ck_assert_str_eq(ray_strerror(-RAY_ENOTSUP), "not supported by this build");
    ck_assert_int_eq(RAY_EKIND, 12);
    ck_assert_str_eq(ray_strerror(RAY_EKIND),
                     "not available for this kind of geometry");
    ck_assert_str_eq(ray_strerror(-RAY_EKIND),
                     "not available for this kind of geometry");
}
END_TEST

START_TEST(strerror_should_survive_unknown_codes)
{
    ck_assert_str_eq(ray_strerror(RAY_EKIND + 1), "unknown error");
    ck_assert_str_eq(ray_strerror(-RAY_EKIND - 1), "unknown error");
    ck_assert_str_eq(ray_strerror(12345), "unknown error");
    ck_assert_str_eq(ray_strerror(-12345), "unknown error");
    /* INT_MIN has no negation in int: it must not be negated. */
    ck_assert_str_eq(ray_strerror(-2147483647 - 1), "unknown error");
    ck_assert_str_eq(ray_strerror(2147483647), "unknown error");
}
END_TEST

Suite *version_suite(void)
{
    Suite *s = suite_create("version");
    TCase *tc = tcase_create("core");

    tcase_add_test(tc, version_should_match_header);
    tcase_add_test(tc, strerror_should_name_every_code);
    tcase_add_test(tc, strerror_should_accept_negated_codes);
    tcase_add_test(tc, strerror_should_survive_unknown_codes);
    tcase_add_test(tc, status_codes_should_keep_their_numbers);
    suite_add_tcase(s, tc);
    return s;
}
