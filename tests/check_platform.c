/* SPDX-License-Identifier: MIT */
/*
** check_platform.c -- the platform layer (src/core/platform.h) and the
** built-in task runner (src/core/tasks.h), on whichever branch this
** build has: POSIX, or Win32 (MinGW, run under Wine).  The CPU count and
** AVX2 test, threads and a mutex, every task run once, and the file
** calls: replacing, refusing, UTF-8 names.
*/
#include <string.h>
#include <dirent.h>
#include <fenv.h>
#include <stdint.h>
#include <stdlib.h>

#include "core/platform.h"
#include "core/tasks.h"
#include "scene/scene.h"
#include "scheduler_kit.h"
#include "tempfiles.h"
#include "tests.h"

#if defined(_WIN32)
#include <wchar.h>
#endif

START_TEST(platform_should_count_cpus_and_find_avx2)
{
    int avx2 = ray__cpu_has_avx2();

    ck_assert_uint_ge(ray__online_cpus(), 1);
    ck_assert(avx2 == 0 || avx2 == 1);
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
    /* libgcc's own probe (also cpuid and xgetbv) must agree. */
    ck_assert_int_eq(avx2, __builtin_cpu_supports("avx2") != 0);
#endif
}
END_TEST

/* ---------------------------------------------------- threads, mutex */

enum { ADDS = 20000, THREADS = 4 };

typedef struct shared_count {
    ray__mutex *lock;
    long n;
} shared_count;

static void add_many(void *arg)
{
    shared_count *c = arg;
    int i;

    for (i = 0; i < ADDS; i++) {
        ray__mutex_lock(c->lock);
        c->n++;
        ray__mutex_unlock(c->lock);
    }
}

static void *libc_alloc(void *ud, void *ptr, size_t osize, size_t nsize)
{
    (void)ud;
    (void)osize;
    if (nsize == 0) {
        free(ptr);
        return NULL;
    }
    return realloc(ptr, nsize);
}

/* Threads with a 1 MiB stack, their adds serialised by the mutex: none
** lost; joined, every one has returned. */
START_TEST(threads_should_run_and_share_a_mutex)
{
    ray__allocator a = {libc_alloc, NULL};
    ray__thread t[THREADS];
    shared_count c = {NULL, 0};
    int i;

    ck_assert_int_eq(ray__mutex_new(&a, &c.lock), RAY_OK);
    for (i = 0; i < THREADS; i++) {
        t[i].fn = add_many;
        t[i].arg = &c;
        ck_assert_int_eq(ray__thread_start(&t[i], (size_t)1 << 20), 0);
    }
    for (i = 0; i < THREADS; i++)
        ray__thread_join(&t[i]);
    ck_assert_int_eq(c.n, (long)THREADS * ADDS);
    ray__mutex_free(&a, c.lock);
    ray__mutex_free(&a, NULL);                /* a no-op */
}
END_TEST

/* --------------------------------------------------------------- tasks */

enum { MAX_TASKS = 1000 };

/* Each task writes only its own slot: no two tasks share one, so the
** counts need no lock, and a task run twice or never shows. */
static void count_task(void *ud, unsigned i)
{
    unsigned *runs = ud;

    runs[i]++;
}

static void assert_each_once(const unsigned *runs, unsigned count)
{
    unsigned i;

    for (i = 0; i < count; i++)
        ck_assert_msg(runs[i] == 1, "task %u ran %u times", i, runs[i]);
}

/* An allocator that refuses everything: the runner's thread handles and
** lock cannot be had. */
static void *no_alloc(void *ud, void *ptr, size_t osize, size_t nsize)
{
    (void)ud;
    (void)osize;
    if (nsize == 0)
        free(ptr);
    return NULL;
}

/*
** Every task runs exactly once: fewer threads than tasks, more threads
** than tasks, one thread, 0 threads, no task; and with no memory for the
** threads or the lock (all on the calling thread).
*/
START_TEST(built_in_threads_should_run_every_task_once)
{
    static const unsigned cases[][2] = {{1, 5}, {4, 3}, {3, 100}, {8, 1000},
                                        {0, 7}, {64, 64}, {5, 0}};
    static unsigned runs[MAX_TASKS];
    ray__allocator a = {libc_alloc, NULL}, none = {no_alloc, NULL};
    size_t k;

    for (k = 0; k < sizeof cases / sizeof *cases; k++) {
        memset(runs, 0, sizeof runs);
        ray__tasks_run(NULL, &a, cases[k][0], 0, cases[k][1], count_task,
                       runs);
        assert_each_once(runs, cases[k][1]);
        ck_assert_uint_eq(runs[cases[k][1] % MAX_TASKS],
                          cases[k][1] == MAX_TASKS ? 1u : 0u);
        memset(runs, 0, sizeof runs);
        ray__tasks_run(NULL, &none, cases[k][0], (size_t)1 << 20,
                       cases[k][1], count_task, runs);
        assert_each_once(runs, cases[k][1]);
    }
}
END_TEST

/* A task that asks for a pass of its own, on the same scheduler: four
** tasks counted in its own quarter of "inner". */
typedef struct nesting {
    const ray_scheduler *sched;
    const ray__allocator *a;
    unsigned *outer, *inner;
} nesting;

static void nesting_task(void *ud, unsigned i)
{
    const nesting *n = ud;

    n->outer[i]++;
    ray__tasks_run(n->sched, n->a, 2, 0, 4, count_task, n->inner + 4 * i);
}

/*
** A crew (tasks.h) runs every task of every pass once, at every thread
** count: passes one after another on the same threads, an empty pass, a
** pass asked for from inside a task (run on the asking thread), and with
** no memory for its threads or lock (all on the calling thread).  A crew
** that is given no pass starts no thread.
*/
START_TEST(crew_should_run_every_task_of_every_pass_once)
{
    static const unsigned threads[] = {1, 2, 3, 8}, passes[] = {5, 100, 0,
                                                                1000, 7};
    static unsigned runs[MAX_TASKS], outer[16], inner[64];
    ray__allocator a = {libc_alloc, NULL}, none = {no_alloc, NULL};
    size_t k, p, m;

    for (m = 0; m < 2; m++)
        for (k = 0; k < sizeof threads / sizeof *threads; k++) {
            ray__crew crew;
            ray_scheduler sched;
            nesting n;
            ray__crew_begin(&crew, m == 0 ? &a : &none, threads[k], 0);
            sched = ray__crew_scheduler(&crew);
            ck_assert_uint_eq(sched.threads, threads[k]);
            for (p = 0; p < sizeof passes / sizeof *passes; p++) {
                memset(runs, 0, sizeof runs);
                ray__tasks_run(&sched, &a, threads[k], 0, passes[p],
                               count_task, runs);
                assert_each_once(runs, passes[p]);
            }
            memset(outer, 0, sizeof outer);
            memset(inner, 0, sizeof inner);
            n.sched = &sched;
            n.a = &a;
            n.outer = outer;
            n.inner = inner;
            ray__tasks_run(&sched, &a, threads[k], 0, 16, nesting_task, &n);
            assert_each_once(outer, 16);
            assert_each_once(inner, 64);
            ray__crew_end(&crew);
        }
    {
        ray__crew idle;
        ray__crew_begin(&idle, &a, 4, 0);
        ray__crew_end(&idle);
        ck_assert_int_eq(idle.state, 0);
        ck_assert_ptr_null(idle.t);
    }
}
END_TEST

/* A scheduler whose run counts, then runs the tasks itself. */
static void counting_run(void *ud, unsigned count, ray_task_fn task,
                         void *task_ud)
{
    unsigned *calls = ud, i;

    (*calls)++;
    for (i = 0; i < count; i++)
        task(task_ud, i);
}

/* A scheduler is handed the tasks (and the thread count does not
** matter); one without run is the built-in threads; no task, no call.
** The options' scheduler wins over the fallback. */
START_TEST(tasks_should_go_to_the_scheduler)
{
    static unsigned runs[MAX_TASKS];
    ray__allocator a = {libc_alloc, NULL};
    ray_scheduler s, t;
    unsigned calls = 0;

    memset(&s, 0, sizeof s);
    s.run = counting_run;
    s.ud = &calls;
    ray__tasks_run(&s, &a, 1, 0, 10, count_task, runs);
    assert_each_once(runs, 10);
    ck_assert_uint_eq(calls, 1);
    ray__tasks_run(&s, &a, 4, 0, 0, count_task, runs);
    ck_assert_uint_eq(calls, 1);
    memset(&t, 0, sizeof t);
    memset(runs, 0, sizeof runs);
    ray__tasks_run(&t, &a, 3, 0, 10, count_task, runs);
    assert_each_once(runs, 10);
    ck_assert_uint_eq(calls, 1);
    ck_assert(ray__scheduler_pick(&s, &t) == &s);
    ck_assert(ray__scheduler_pick(&t, &s) == &s);
    ck_assert(ray__scheduler_pick(NULL, &t) == NULL);
    ck_assert(ray__scheduler_pick(NULL, NULL) == NULL);
    ck_assert_uint_eq(ray__task_count(5, &s), 5);
    s.threads = 3;
    ck_assert_uint_eq(ray__task_count(0, &s), 3);
    ck_assert_uint_eq(ray__task_count(0, NULL), ray__online_cpus());
}
END_TEST

/*
** Every task runs in the floating-point environment of the thread that
** asked for the work: here rounding upward, set after the threads of a
** pool (a program's scheduler) were made, and which Windows' threads do
** not inherit from their creator (POSIX threads do).  Each task records
** the rounding mode it ran under; the pool's own is its own again after.
*/
static void record_rounding(void *ud, unsigned i)
{
    int *seen = ud;

    seen[i] = fegetround();
}

/* A pool task outside the library: the worker's own rounding. */
static void pool_rounding(void *ud, unsigned i)
{
    int *seen = ud;

    seen[i] = fegetround();
}

START_TEST(tasks_should_run_in_the_callers_floating_point_environment)
{
    enum { TASKS = 16 };
    ray__allocator a = {libc_alloc, NULL};
    test_pool *pool = pool_new(3);
    ray_scheduler sched = pool_scheduler(pool);
    int seen[TASKS], k, i;

    for (k = 0; k < 2; k++) {
        for (i = 0; i < TASKS; i++)
            seen[i] = -1;
        ck_assert_int_eq(fesetround(FE_UPWARD), 0);
        ray__tasks_run(k == 0 ? NULL : &sched, &a, 4, 0, TASKS,
                       record_rounding, seen);
        ck_assert_int_eq(fesetround(FE_TONEAREST), 0);
        for (i = 0; i < TASKS; i++)
            ck_assert_msg(seen[i] == FE_UPWARD, "%s, task %d: rounding %d",
                          k == 0 ? "built-in threads" : "scheduler", i,
                          seen[i]);
    }
    pool_run(pool, TASKS, pool_rounding, seen);
    for (i = 0; i < TASKS; i++)
        ck_assert_int_eq(seen[i], FE_TONEAREST);
    pool_free(pool);
}
END_TEST

/* --------------------------------------------------------------- files */

/* The file's bytes (at most size - 1), NUL-terminated; -1 if it cannot
** be opened. */
static long read_back(const char *path, char *buf, size_t size)
{
    FILE *fp = ray__file_open_read(path);
    size_t n;

    if (fp == NULL)
        return -1;
    n = fread(buf, 1, size - 1, fp);
    buf[n] = '\0';
    fclose(fp);
    return (long)n;
}

/* How many entries the directory holds, . and .. aside. */
static int entries(const char *dir)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    int n = 0;

    ck_assert_ptr_nonnull(d);
    while ((e = readdir(d)) != NULL)
        n += strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0;
    closedir(d);
    return n;
}

/* Bytes 0 .. n - 1 of p: byte i holds i * 131 + seed (mod 256), so a
** block moved or resized is seen to keep its contents exactly. */
static void fill_bytes(unsigned char *p, size_t n, unsigned seed)
{
    size_t i;

    for (i = 0; i < n; i++)
        p[i] = (unsigned char)(i * 131u + seed);
}

static int bytes_kept(const unsigned char *p, size_t n, unsigned seed)
{
    size_t i;

    for (i = 0; i < n; i++)
        if (p[i] != (unsigned char)(i * 131u + seed))
            return 0;
    return 1;
}

/*
** The allocator of a scene made without one (store.c, on the platform's
** ray__huge_realloc): blocks below RAY__HUGE_BLOCK and at or above it
** allocated, written whole, grown and shrunk across that size and on
** each side of it, each time with their contents kept, and freed (the
** sizes are the ones each block was given, as ray_alloc_fn promises).
** On Linux a new or grown large block starts at a 2 MiB boundary (its
** huge pages); elsewhere only the contents are checked.  A size too large to
** round up to whole huge pages fails (NULL).
*/
START_TEST(system_alloc_should_keep_contents_across_sizes)
{
    const size_t small = 1000, big = RAY__HUGE_BLOCK,
                 bigger = 3 * RAY__HUGE_BLOCK + 12345;
    ray_scene *s = NULL;
    ray_alloc_fn fn;
    unsigned char *p;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    fn = s->alloc.fn;
    p = fn(s->alloc.ud, NULL, 0, small);
    ck_assert_ptr_nonnull(p);
    fill_bytes(p, small, 1);
    p = fn(s->alloc.ud, p, small, big);            /* small -> large */
    ck_assert_ptr_nonnull(p);
    ck_assert(bytes_kept(p, small, 1));
    fill_bytes(p, big, 2);
    p = fn(s->alloc.ud, p, big, bigger);           /* large, grown */
    ck_assert_ptr_nonnull(p);
    ck_assert(bytes_kept(p, big, 2));
#if RAY__WHOLE_HUGE_PAGES
    /* Grown in place, or copied to a fresh block on a huge page. */
    ck_assert_uint_eq((uintptr_t)p % ((uintptr_t)1 << 21), 0);
#endif
    fill_bytes(p, bigger, 3);
    ck_assert(bytes_kept(p, bigger, 3));
    p = fn(s->alloc.ud, p, bigger, big + 1);       /* large, shrunk */
    ck_assert_ptr_nonnull(p);
    ck_assert(bytes_kept(p, big + 1, 3));
    p = fn(s->alloc.ud, p, big + 1, small);        /* large -> small */
    ck_assert_ptr_nonnull(p);
    ck_assert(bytes_kept(p, small, 3));
    p = fn(s->alloc.ud, p, small, 2 * small);      /* small, grown */
    ck_assert_ptr_nonnull(p);
    ck_assert(bytes_kept(p, small, 3));
    ck_assert_ptr_null(fn(s->alloc.ud, p, 2 * small, 0));
    p = fn(s->alloc.ud, NULL, 0, bigger);          /* a new large one */
    ck_assert_ptr_nonnull(p);
#if RAY__WHOLE_HUGE_PAGES
    ck_assert_uint_eq((uintptr_t)p % ((uintptr_t)1 << 21), 0);
#endif
    fill_bytes(p, bigger, 4);
    ck_assert(bytes_kept(p, bigger, 4));
    ck_assert_ptr_null(fn(s->alloc.ud, p, bigger, 0));
    /* Too large for whole huge pages: NULL, libc not asked (which
    ** AddressSanitizer and ThreadSanitizer stop at such a size). */
    if (RAY__WHOLE_HUGE_PAGES)
        ck_assert_ptr_null(fn(s->alloc.ud, NULL, 0, (size_t)-1));
    ray_scene_free(s);
}
END_TEST

/*
** A new file, then the same path replaced by a longer and a shorter
** one (binary bytes: a CR LF and a ^Z, which a text-mode write would
** change), each read back exactly; no temporary file stays.
*/
START_TEST(file_write_should_replace_and_leave_no_temporary)
{
    static const char first[] = "first\r\n\x1a\nbytes";
    static const char longer[] = "a longer second version\n\n\r";
    char dir[512], path[600], got[64];

    ck_assert(test_make_dir(dir, sizeof dir, "platform"));
    snprintf(path, sizeof path, "%s/out.bin", dir);
    ck_assert_int_eq(ray__file_write(path, first, sizeof first - 1), RAY_OK);
    ck_assert_int_eq(read_back(path, got, sizeof got), (long)sizeof first - 1);
    ck_assert_mem_eq(got, first, sizeof first - 1);
    ck_assert_int_eq(ray__file_write(path, longer, sizeof longer - 1),
                     RAY_OK);
    ck_assert_int_eq(read_back(path, got, sizeof got),
                     (long)sizeof longer - 1);
    ck_assert_mem_eq(got, longer, sizeof longer - 1);
    ck_assert_int_eq(ray__file_write(path, "x", 1), RAY_OK);
    ck_assert_int_eq(read_back(path, got, sizeof got), 1);
    ck_assert_int_eq(ray__file_write(path, "", 0), RAY_OK);
    ck_assert_int_eq(read_back(path, got, sizeof got), 0);
    ck_assert_int_eq(entries(dir), 1);
    ck_assert_int_eq(remove(path), 0);
    ck_assert_int_eq(rmdir(dir), 0);
}
END_TEST

/* A directory is not replaced (EISDIR); a path through a missing
** directory is not made (ENOENT); nothing is left behind; a file that is
** not there cannot be read (ENOENT). */
START_TEST(file_write_should_refuse_directories_and_missing_paths)
{
    char dir[512], path[600], got[8];

    ck_assert(test_make_dir(dir, sizeof dir, "platform"));
    errno = 0;
    ck_assert_int_eq(ray__file_write(dir, "x", 1), RAY_EIO);
    ck_assert_int_eq(errno, EISDIR);
    snprintf(path, sizeof path, "%s/missing/x.bin", dir);
    errno = 0;
    ck_assert_int_eq(ray__file_write(path, "x", 1), RAY_EIO);
    ck_assert_int_eq(errno, ENOENT);
    errno = 0;
    ck_assert_int_eq(read_back(path, got, sizeof got), -1);
    ck_assert_int_eq(errno, ENOENT);
    ck_assert_int_eq(entries(dir), 0);
    ck_assert_int_eq(rmdir(dir), 0);
}
END_TEST

/*
** A UTF-8 name (e acute, a sun, a CJK character: two-, three- and
** three-byte sequences) is the name on the disk: read back through the
** same call, and found under that name by the platform's own call (on
** Windows the wide one, with the UTF-16 name: the UTF-8 bytes were not
** taken as the ANSI code page's).  Windows also refuses a name that is
** not UTF-8 (EILSEQ), where POSIX takes any bytes.
*/
START_TEST(file_calls_should_take_utf8_names)
{
    static const char name[] = "h\xc3\xa9llo-\xe2\x98\x80-\xe6\x97\xa5.bin";
    char dir[512], path[600], got[16];
    FILE *fp;
#if defined(_WIN32)
    wchar_t wpath[600];
    size_t n;
#endif

    ck_assert(test_make_dir(dir, sizeof dir, "platform"));
    snprintf(path, sizeof path, "%s/%s", dir, name);
    ck_assert_int_eq(ray__file_write(path, "utf-8", 5), RAY_OK);
    ck_assert_int_eq(read_back(path, got, sizeof got), 5);
    ck_assert_str_eq(got, "utf-8");
#if defined(_WIN32)
    /* The directory is ASCII (%TEMP%), the name the UTF-16 one. */
    n = mbstowcs(wpath, dir, 500);
    ck_assert(n < 500);
    wcscpy(wpath + n, L"/h\u00e9llo-\u2600-\u65e5.bin");
    fp = _wfopen(wpath, L"rb");
#else
    fp = fopen(path, "rb");
#endif
    ck_assert_ptr_nonnull(fp);
    ck_assert_int_eq(fgetc(fp), 'u');
    fclose(fp);
    ck_assert_int_eq(entries(dir), 1);
#if defined(_WIN32)
    snprintf(path, sizeof path, "%s/bad-\xc3(.bin", dir);
    errno = 0;
    ck_assert_int_eq(ray__file_write(path, "x", 1), RAY_EIO);
    ck_assert_int_eq(errno, EILSEQ);
    errno = 0;
    ck_assert_ptr_null(ray__file_open_read(path));
    ck_assert_int_eq(errno, EILSEQ);
    ck_assert_int_eq(entries(dir), 1);
    ck_assert_int_eq(_wremove(wpath), 0);
#else
    ck_assert_int_eq(remove(path), 0);
#endif
    ck_assert_int_eq(rmdir(dir), 0);
}
END_TEST

Suite *platform_suite(void)
{
    Suite *s = suite_create("platform");
    TCase *tc = tcase_create("core");

    tcase_add_test(tc, platform_should_count_cpus_and_find_avx2);
    tcase_add_test(tc, threads_should_run_and_share_a_mutex);
    tcase_add_test(tc, built_in_threads_should_run_every_task_once);
    tcase_add_test(tc, tasks_should_go_to_the_scheduler);
    tcase_add_test(tc, crew_should_run_every_task_of_every_pass_once);
    tcase_add_test(tc, tasks_should_run_in_the_callers_floating_point_environment);
    tcase_add_test(tc, system_alloc_should_keep_contents_across_sizes);
    tcase_add_test(tc, file_write_should_replace_and_leave_no_temporary);
    tcase_add_test(tc, file_write_should_refuse_directories_and_missing_paths);
    tcase_add_test(tc, file_calls_should_take_utf8_names);
    suite_add_tcase(s, tc);
    return s;
}
