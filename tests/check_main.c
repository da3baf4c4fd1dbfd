/* SPDX-License-Identifier: MIT */
/*
** check_main.c -- runs every suite.  Fork mode stays on (Check's default),
** so a crash fails one test instead of the run.
**
** Where Check cannot fork (Windows: doc/PLATFORMS.md) each suite runs in
** a process of its own instead: the program starts itself once per suite
** (RAY_CHECK_SUITE=name) and adds up what they report, so a crash ends
** one suite, not the run; and before each test the child writes the
** test's name to a file (Check's tcase_fn_start, which its runner calls
** as a test starts, wrapped at link time: -Wl,--wrap=tcase_fn_start), so
** a crashed suite's report names the test that was running.
** RAY_CHECK_CRASH=1 runs instead a suite whose test crashes, then the
** version suite, to show that report and that the run goes on (make
** windows-check runs it).
*/
#include <stdlib.h>

#include "tests.h"

#if defined(_WIN32)
#define WIN32_LEAN_AND_MEAN
#include <windows.h>
#include <process.h>
#define CHECK_ISOLATED 1
#else
#define CHECK_ISOLATED 0
#endif

/* Every suite, by name. */
#define SUITES(X)                                                       \
    X(version) X(sphere) X(triangle) X(plane) X(polygon) X(barycentric)  \
    X(png) X(optics) X(scene) X(trace) X(render) X(bvh) X(obj)          \
    X(effects) X(numerics) X(implicit) X(parametric) X(texture) X(bpt)  \
    X(surfaces) X(selfhit) X(null) X(defaults) X(errmsg) X(box)         \
    X(direct) X(capsule) X(games) X(instance) X(dynamic) X(user)        \
    X(closest) X(batch) X(lazy) X(cones) X(caustics)                    \
    X(cones_caustics_hard) X(filter) X(scheduler) X(platform) X(exact)  \
    X(sweep) X(overlap) X(slips)

typedef struct named_suite {
    const char *name;
    Suite *(*make)(void);
} named_suite;

#define SUITE_ENTRY(name) {#name, name##_suite},
static const named_suite suites[] = {SUITES(SUITE_ENTRY)};
#define N_SUITES (sizeof suites / sizeof *suites)

#if CHECK_ISOLATED
/* ------------------------------------------- one process per suite */

/* A test that crashes (RAY_CHECK_CRASH=1), for the report. */
START_TEST(crash_should_name_the_test)
{
    volatile int *nowhere = NULL;
    *nowhere = 1;
}
END_TEST

static Suite *crash_suite(void)
{
    Suite *s = suite_create("crash");
    TCase *tc = tcase_create("crash");

    tcase_add_test(tc, crash_should_name_the_test);
    suite_add_tcase(s, tc);
    return s;
}

/* Where the child writes the running test's name (RAY_CHECK_CURRENT). */
void __real_tcase_fn_start(const char *fname, const char *file, int line);
void __wrap_tcase_fn_start(const char *fname, const char *file, int line);

void __wrap_tcase_fn_start(const char *fname, const char *file, int line)
{
    const char *path = getenv("RAY_CHECK_CURRENT");
    FILE *fp = path != NULL ? fopen(path, "w") : NULL;

    if (fp != NULL) {
        fprintf(fp, "%s (%s:%d)\n", fname, file, line);
        fclose(fp);
    }
    __real_tcase_fn_start(fname, file, line);
}

/* A crash ends the child with the exception's code (0xC0000005 for an
** access violation): no error dialog, no debugger attached (Wine's
** winedbg would otherwise print a backtrace and linger). */
static LONG WINAPI end_quietly(EXCEPTION_POINTERS *e)
{
    fflush(stdout);
    ExitProcess((UINT)e->ExceptionRecord->ExceptionCode);
    return EXCEPTION_EXECUTE_HANDLER;
}

/* The child: one suite, its counts appended to RAY_CHECK_RESULTS. */
static int run_child(const char *name)
{
    const char *results = getenv("RAY_CHECK_RESULTS");
    Suite *s = NULL;
    SRunner *sr;
    FILE *fp;
    size_t i;
    int run, failed;

    SetErrorMode(SEM_FAILCRITICALERRORS | SEM_NOGPFAULTERRORBOX);
    SetUnhandledExceptionFilter(end_quietly);
    for (i = 0; i < N_SUITES; i++)
        if (strcmp(name, suites[i].name) == 0)
            s = suites[i].make();
    if (strcmp(name, "crash") == 0)
        s = crash_suite();
    if (s == NULL) {
        fprintf(stderr, "check_ray: no suite %s\n", name);
        return 3;
    }
    sr = srunner_create(s);
    srunner_set_fork_status(sr, CK_NOFORK);
    srunner_run_all(sr, CK_NORMAL);
    run = srunner_ntests_run(sr);
    failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    fp = results != NULL ? fopen(results, "a") : NULL;
    if (fp != NULL) {
        fprintf(fp, "%s %d %d\n", name, run, failed);
        fclose(fp);
    }
    return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}

/* The first line of a file (the crashed test's name), or "?". */
static void first_line(const char *path, char *buf, size_t size)
{
    FILE *fp = fopen(path, "r");

    snprintf(buf, size, "?");
    if (fp != NULL) {
        if (fgets(buf, (int)size, fp) != NULL)
            buf[strcspn(buf, "\n")] = '\0';
        fclose(fp);
    }
}

/* The parent: every suite in a child (or, with RAY_CHECK_CRASH=1, the
** crash suite and the version suite); the totals. */
static int run_isolated(const char *self)
{
    static const char *const crash_run[] = {"crash", "version"};
    char current[MAX_PATH + 32], results[MAX_PATH + 32], env[600];
    char test[512], line[256];
    const char *tmp = getenv("TEMP");
    const char *crash = getenv("RAY_CHECK_CRASH");
    int checks = 0, failed = 0, crashed = 0;
    int crash_test = crash != NULL && strcmp(crash, "1") == 0;
    size_t i, n = crash_test ? 2 : N_SUITES;
    FILE *fp;

    snprintf(current, sizeof current, "%s/check_ray-%d.current",
             tmp != NULL ? tmp : ".", _getpid());
    snprintf(results, sizeof results, "%s/check_ray-%d.results",
             tmp != NULL ? tmp : ".", _getpid());
    remove(results);
    snprintf(env, sizeof env, "RAY_CHECK_CURRENT=%s", current);
    _putenv(env);
    snprintf(env, sizeof env, "RAY_CHECK_RESULTS=%s", results);
    _putenv(env);
    printf("check_ray: %u suites, each in a process of its own (no fork "
           "here)\n", (unsigned)n);
    fflush(stdout);
    for (i = 0; i < n; i++) {
        const char *name = crash_test ? crash_run[i] : suites[i].name;
        const char *argv[2];
        intptr_t status;
        argv[0] = self;
        argv[1] = NULL;
        remove(current);
        snprintf(env, sizeof env, "RAY_CHECK_SUITE=%s", name);
        _putenv(env);
        status = _spawnv(_P_WAIT, self, argv);
        if (status == 0 || status == 1)
            continue;
        /* Neither passed nor failed: the child ended some other way. */
        first_line(current, test, sizeof test);
        printf("check_ray: suite %s CRASHED (exit code 0x%lx) in test %s\n",
               name, (unsigned long)status, test);
        fflush(stdout);
        crashed++;
    }
    _putenv("RAY_CHECK_SUITE=");
    fp = fopen(results, "r");
    while (fp != NULL && fgets(line, sizeof line, fp) != NULL) {
        char name[64];
        int r, f;
        if (sscanf(line, "%63s %d %d", name, &r, &f) == 3) {
            checks += r;
            failed += f;
        }
    }
    if (fp != NULL)
        fclose(fp);
    remove(results);
    remove(current);
    printf("check_ray: %d checks in %u suites: %d failed, %d suites "
           "crashed\n", checks, (unsigned)n, failed, crashed);
    return failed == 0 && crashed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
#endif

int main(int argc, char **argv)
{
    SRunner *sr;
    size_t i;
    int failed;

#if CHECK_ISOLATED
    {
        const char *one = getenv("RAY_CHECK_SUITE");
        (void)argc;
        if (one != NULL && one[0] != '\0')
            return run_child(one);
        (void)argv;
        {
            char self[MAX_PATH];
            DWORD n = GetModuleFileNameA(NULL, self, sizeof self);
            if (n == 0 || n >= sizeof self) {
                fprintf(stderr, "check_ray: cannot find itself\n");
                return EXIT_FAILURE;
            }
            return run_isolated(self);
        }
    }
#else
    (void)argc;
    (void)argv;
#endif
    sr = srunner_create(suites[0].make());
    for (i = 1; i < N_SUITES; i++)
        srunner_add_suite(sr, suites[i].make());
    srunner_run_all(sr, CK_NORMAL);
    failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
