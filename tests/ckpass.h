/* SPDX-License-Identifier: MIT */
/*
** ckpass.h -- Check's ck_assert_msg, which every ck_assert_* is built on,
** without the message a passing check sends; included by tests.h after
** <check.h>.
**
** Check's macro tells the parent process of each check that passes
** (_mark_point: a message on its pipe, microseconds), so that a test that
** crashes can name the last check it passed.  The suites' differential
** loops make millions of checks (ray__product_error's million products,
** three checks each, took 9 of the exact suite's 9.5 s), and those
** messages were a third of the whole suite's CPU time: 93 s of one core,
** 60 s without them (issue 38).  Here a check that passes calls
** test_passed() (check_main.c), which does nothing, in another file so
** that the compiler cannot see into it, as it could not into _mark_point;
** a check that fails fails as Check's own does, with the same message.
** A test that crashes is still named (its case, and the line it started
** at); build the suite with -DTEST_MARK_POINTS (in CFLAGS) for Check's
** marks, and the last check passed before the crash.
**
** A system header, as <check.h> is (-isystem, the Makefile): warnings
** at a check's expansion were, and stay, about Check's macros (a hit
** record that the compiler cannot see is set whenever it is read), not
** about the tests.
*/
#ifndef RAY_CKPASS_H
#define RAY_CKPASS_H

#pragma GCC system_header

#include <check.h>

#ifndef TEST_MARK_POINTS
void test_passed(void);
#undef ck_assert_msg
#define ck_assert_msg(expr, ...)                                        \
    ((expr) ? test_passed()                                             \
            : _ck_assert_failed(__FILE__, __LINE__,                     \
                                "Assertion '" #expr "' failed" , ## __VA_ARGS__))
#endif

#endif
