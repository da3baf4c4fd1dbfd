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
**
** Elsewhere (POSIX) the suites are shared out among RAY_CHECK_JOBS worker
** processes (default: the number of CPUs online), so that make check
** takes the time of its longest suites rather than of all of them (issue
** 38).  Each worker is a fork of this program that runs one suite at a
** time, handed out longest first (the static estimates in slow_suites
** below), its output held in a temporary file and printed whole when the
** suite ends, so that two suites' lines never interleave; its counts come
** back in a second file.  RAY_CHECK_JOBS=1, CK_RUN_SUITE or CK_FORK=no
** run every suite in this process, one after the other, as before.
**
** Either way the run ends with the line "checks: N passed, N failed"
** alone (the line CI's reader looks for), also written to the file named
** by RAY_CHECK_SUMMARY where that is set (make check prints it last).
*/
#include <stdlib.h>

#include "tests.h"

#if defined(_WIN32)
#define WIN32_LEAN_AND_MEAN
#include <windows.h>
#include <errno.h>
#include <process.h>
#define CHECK_ISOLATED 1
#else
#include <errno.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
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
    X(sweep) X(overlap) X(contains) X(slips) X(why) X(progress)      \
    X(edges)

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

/* Did the file at path get made (the child wrote the test it began)? */
static int file_made(const char *path)
{
    FILE *fp = fopen(path, "r");

    if (fp == NULL)
        return 0;
    fclose(fp);
    return 1;
}

/*
** Run suite "name" in a child, its exit status.  A child that was never
** started (_spawnv's -1 with errno set, and no test begun) is started
** again, twice at most, a second apart: Wine under load has failed to
** start one now and then (CI, and a loaded run of make windows-check:
** "suite filter CRASHED (exit code 0xffffffff) in test ?"), which is no
** result of the suite's.  A child that ran is never run again: its
** crash stays a crash.
*/
static intptr_t spawn_suite(const char *self, const char *const *argv,
                            const char *current, const char *name)
{
    intptr_t status = -1;
    int tries;

    for (tries = 0; tries < 3; tries++) {
        if (tries > 0) {
            printf("check_ray: suite %s was not started (%s): again\n",
                   name, strerror(errno));
            fflush(stdout);
            Sleep(1000);
        }
        errno = 0;
        status = _spawnv(_P_WAIT, self, argv);
        if (status != -1 || errno == 0 || file_made(current))
            break;
    }
    return status;
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
        status = spawn_suite(self, argv, current, name);
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
    printf("checks: %d passed, %d failed\n", checks - failed,
           failed + crashed);
    return failed == 0 && crashed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
#endif

/* What a check that passes calls (tests.h): nothing, out of the
** compiler's sight in the suites' files. */
void test_passed(void)
{
}

/* The summary line, on stdout and in RAY_CHECK_SUMMARY's file. */
static void summary(int passed, int failed)
{
    const char *path = getenv("RAY_CHECK_SUMMARY");
    FILE *fp = path != NULL && path[0] != '\0' ? fopen(path, "w") : NULL;

    printf("checks: %d passed, %d failed\n", passed, failed);
    fflush(stdout);
    if (fp != NULL) {
        fprintf(fp, "checks: %d passed, %d failed\n", passed, failed);
        fclose(fp);
    }
}

#if !CHECK_ISOLATED
/* ---------------------------------------- suites over worker processes */

/*
** The suites that take longest (seconds of one core, make check's counts,
** measured with RAY_CHECK_JOBS=1 CK_RUN_SUITE=name; doc/TESTING.md):
** handed out first, so that no long suite starts last and leaves the
** other workers idle (longest processing time first, Graham 1969).  The
** rest follow in SUITES order.  An estimate that is off costs balance,
** never coverage.
*/
static const char *const slow_suites[] = {
    "sweep", "bvh", "closest", "exact", "contains", "overlap", "filter",
    "numerics", "games", "sphere", "barycentric"
};
#define N_SLOW (sizeof slow_suites / sizeof *slow_suites)

/* Is suite i asked for?  RAY_CHECK_SUITES: a list of names (make
** check-long's), or every suite when unset. */
static int wanted(size_t i)
{
    const char *list = getenv("RAY_CHECK_SUITES");
    size_t len = strlen(suites[i].name);
    const char *p;

    if (list == NULL || list[0] == '\0')
        return 1;
    for (p = list; (p = strstr(p, suites[i].name)) != NULL; p += len)
        if ((p == list || p[-1] == ' ' || p[-1] == ',') &&
            (p[len] == '\0' || p[len] == ' ' || p[len] == ','))
            return 1;
    return 0;
}

/* Order: the slow suites first, then every other in SUITES order; only
** those asked for.  Returns how many. */
static size_t hand_out_order(size_t *order)
{
    size_t i, j, n = 0;

    for (j = 0; j < N_SLOW; j++)
        for (i = 0; i < N_SUITES; i++)
            if (strcmp(slow_suites[j], suites[i].name) == 0 && wanted(i))
                order[n++] = i;
    for (i = 0; i < N_SUITES; i++) {
        int slow = 0;
        for (j = 0; j < N_SLOW; j++)
            slow |= strcmp(slow_suites[j], suites[i].name) == 0;
        if (!slow && wanted(i))
            order[n++] = i;
    }
    return n;
}

typedef struct worker {
    pid_t pid;         /* 0: idle */
    size_t suite;
    FILE *out, *counts;
    double start;
} worker;

/* The child: suite i, its output to out, "run failed" to counts. */
static void run_in_child(size_t i, FILE *out, FILE *counts)
{
    SRunner *sr;
    int run, failed;

    fflush(stdout);
    fflush(stderr);
    if (dup2(fileno(out), STDOUT_FILENO) < 0 ||
        dup2(fileno(out), STDERR_FILENO) < 0)
        _exit(3);
    sr = srunner_create(suites[i].make());
    srunner_run_all(sr, CK_NORMAL);
    run = srunner_ntests_run(sr);
    failed = srunner_ntests_failed(sr);
    srunner_free(sr);
    fprintf(counts, "%d %d\n", run, failed);
    fflush(counts);
    fflush(stdout);
    _exit(failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE);
}

/* Copies what a finished suite printed to stdout. */
static void print_output(FILE *out)
{
    char buf[4096];
    size_t n;

    rewind(out);
    while ((n = fread(buf, 1, sizeof buf, out)) > 0)
        fwrite(buf, 1, n, stdout);
    fflush(stdout);
}

/*
** Every suite in at most `jobs` workers at once; the totals.  A suite
** whose process ends other than by exit 0 or 1 (a crash outside Check's
** own forked tests, a worker killed) counts as one failed check more, and
** is named.
*/
static int run_sharded(int jobs)
{
    size_t order[N_SUITES], next = 0, done = 0, i, n;
    worker w[64];
    double t0 = now_seconds(), took[N_SUITES];
    int checks = 0, failed = 0, crashed = 0, k;

    n = hand_out_order(order);
    if (n == 0) {
        fprintf(stderr, "check_ray: no suite named in RAY_CHECK_SUITES\n");
        return EXIT_FAILURE;
    }
    if (jobs > (int)(sizeof w / sizeof *w))
        jobs = (int)(sizeof w / sizeof *w);
    if (jobs > (int)n)
        jobs = (int)n;
    memset(w, 0, sizeof w);
    memset(took, 0, sizeof took);
    printf("check_ray: %u suites over %d processes (RAY_CHECK_JOBS)\n",
           (unsigned)n, jobs);
    fflush(stdout);
    while (done < n) {
        int status, r, f;
        pid_t pid;
        /* Start suites while a worker slot is free. */
        for (k = 0; k < jobs && next < n; k++) {
            if (w[k].pid != 0)
                continue;
            w[k].suite = order[next++];
            w[k].out = tmpfile();
            w[k].counts = tmpfile();
            if (w[k].out == NULL || w[k].counts == NULL) {
                perror("check_ray: tmpfile");
                exit(EXIT_FAILURE);
            }
            w[k].start = now_seconds();
            fflush(stdout);
            pid = fork();
            if (pid < 0) {
                perror("check_ray: fork");
                exit(EXIT_FAILURE);
            }
            if (pid == 0)
                run_in_child(w[k].suite, w[k].out, w[k].counts);
            w[k].pid = pid;
        }
        pid = waitpid(-1, &status, 0);
        if (pid < 0) {
            if (errno == EINTR)
                continue;
            perror("check_ray: waitpid");
            exit(EXIT_FAILURE);
        }
        for (k = 0; k < jobs && w[k].pid != pid; k++)
            ;
        if (k == jobs)
            continue;    /* not a worker of ours */
        i = w[k].suite;
        took[i] = now_seconds() - w[k].start;
        print_output(w[k].out);
        rewind(w[k].counts);
        if (fscanf(w[k].counts, "%d %d", &r, &f) == 2 && WIFEXITED(status) &&
            (WEXITSTATUS(status) == 0 || WEXITSTATUS(status) == 1)) {
            checks += r;
            failed += f;
        } else {
            printf("check_ray: suite %s CRASHED (%s %d)\n", suites[i].name,
                   WIFSIGNALED(status) ? "signal" : "exit status",
                   WIFSIGNALED(status) ? WTERMSIG(status)
                                       : WEXITSTATUS(status));
            crashed++;
        }
        fclose(w[k].out);
        fclose(w[k].counts);
        w[k].pid = 0;
        done++;
    }
    /* The three longest suites, for whoever balances the shards. */
    printf("check_ray: %d checks in %.1f s over %d processes; longest:",
           checks, now_seconds() - t0, jobs);
    for (k = 0; k < 3; k++) {
        size_t top = N_SUITES;
        for (i = 0; i < N_SUITES; i++)
            if (took[i] > 0 && (top == N_SUITES || took[i] > took[top]))
                top = i;
        if (top == N_SUITES)
            break;
        printf(" %s %.1f s", suites[top].name, took[top]);
        took[top] = 0;
    }
    printf("\n");
    summary(checks - failed, failed + crashed);
    return failed == 0 && crashed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}

/* RAY_CHECK_JOBS, or the CPUs online; 1 when Check's fork mode is off or
** one suite was asked for (CK_RUN_SUITE: it runs alone anyway). */
static int check_jobs(void)
{
    const char *env = getenv("RAY_CHECK_JOBS");
    const char *fork_mode = getenv("CK_FORK");
    const char *one = getenv("CK_RUN_SUITE");
    long n = 0;

    if ((fork_mode != NULL && strcmp(fork_mode, "no") == 0) ||
        (one != NULL && one[0] != '\0'))
        return 1;
    if (env != NULL && env[0] != '\0')
        n = strtol(env, NULL, 10);
#ifdef _SC_NPROCESSORS_ONLN
    else
        n = sysconf(_SC_NPROCESSORS_ONLN);
#endif
    return n < 1 ? 1 : n > 64 ? 64 : (int)n;
}
#endif

int main(int argc, char **argv)
{
    SRunner *sr;
    size_t i;
    int failed, run;

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
    {
        int jobs = check_jobs();
        const char *some = getenv("RAY_CHECK_SUITES");
        if (jobs > 1 || (some != NULL && some[0] != '\0'))
            return run_sharded(jobs);
    }
#endif
    sr = srunner_create(suites[0].make());
    for (i = 1; i < N_SUITES; i++)
        srunner_add_suite(sr, suites[i].make());
    srunner_run_all(sr, CK_NORMAL);
    failed = srunner_ntests_failed(sr);
    run = srunner_ntests_run(sr);
    srunner_free(sr);
    summary(run - failed, failed);
    return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
