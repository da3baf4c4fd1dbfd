/* SPDX-License-Identifier: MIT */
/*
** scheduler_kit.h -- test schedulers (ray.h's ray_scheduler), shared by
** check_scheduler.c and check_bvh.c: a program's job system as the
** library meets it, running the tasks in reverse, in a random order on
** the calling thread, or in a random order on a pool of its own threads
** (an engine's workers: the calling thread only waits).  Each counts the
** runs and tasks it was given, so a test can tell it was used.
*/
#ifndef SCHEDULER_KIT_H
#define SCHEDULER_KIT_H

#include <pthread.h>
#include <stdlib.h>

#include "tests.h"

/* What a test scheduler saw: runs, tasks, and the last run's count. */
typedef struct sched_log {
    unsigned runs, last_count;
    unsigned long long tasks;
    unsigned seed;            /* the random order's generator */
} sched_log;

/* A permutation of 0 .. n - 1 (Fisher-Yates, a 32-bit LCG: Numerical
** Recipes' constants), different on every call through *seed. */
static inline unsigned *shuffled(unsigned n, unsigned *seed)
{
    unsigned *order = malloc((n ? n : 1) * sizeof *order);
    unsigned i;

    ck_assert_ptr_nonnull(order);
    for (i = 0; i < n; i++)
        order[i] = i;
    for (i = n; i > 1; i--) {
        unsigned j, t;
        *seed = *seed * 1664525u + 1013904223u;
        j = (*seed >> 8) % i;
        t = order[i - 1];
        order[i - 1] = order[j];
        order[j] = t;
    }
    return order;
}

static inline void log_run(sched_log *log, unsigned count)
{
    log->runs++;
    log->last_count = count;
    log->tasks += count;
}

/* Last task first, on the calling thread. */
static inline void reverse_run(void *ud, unsigned count, ray_task_fn task,
                        void *task_ud)
{
    unsigned i;

    log_run(ud, count);
    for (i = count; i > 0; i--)
        task(task_ud, i - 1);
}

/* A new random order each run, on the calling thread. */
static inline void random_run(void *ud, unsigned count, ray_task_fn task,
                       void *task_ud)
{
    sched_log *log = ud;
    unsigned *order = shuffled(count, &log->seed);
    unsigned i;

    log_run(log, count);
    for (i = 0; i < count; i++)
        task(task_ud, order[i]);
    free(order);
}

static inline ray_scheduler test_scheduler(void (*run)(void *, unsigned,
                                                ray_task_fn, void *),
                                    sched_log *log)
{
    ray_scheduler s;

    memset(&s, 0, sizeof s);
    memset(log, 0, sizeof *log);
    log->seed = 12345;
    s.run = run;
    s.ud = log;
    return s;
}

/*
** A pool of its own threads, as an engine's workers: run() posts the
** tasks in a random order and waits; the workers take them one by one.
** The log is written under the pool's lock.
*/
#define POOL_MAX 8

typedef struct test_pool {
    pthread_mutex_t lock;
    pthread_cond_t work, done;
    pthread_t thread[POOL_MAX];
    unsigned n_threads;
    ray_task_fn task;         /* the run being served */
    void *task_ud;
    unsigned *order;
    unsigned count, next, finished;
    int quit;
    sched_log log;
} test_pool;

static inline void *pool_main(void *arg)
{
    test_pool *p = arg;

    pthread_mutex_lock(&p->lock);
    for (;;) {
        unsigned i;
        ray_task_fn task;
        void *task_ud;
        while (!p->quit && p->next >= p->count)
            pthread_cond_wait(&p->work, &p->lock);
        if (p->quit)
            break;
        i = p->order[p->next++];
        task = p->task;
        task_ud = p->task_ud;
        pthread_mutex_unlock(&p->lock);
        task(task_ud, i);
        pthread_mutex_lock(&p->lock);
        if (++p->finished == p->count)
            pthread_cond_broadcast(&p->done);
    }
    pthread_mutex_unlock(&p->lock);
    return NULL;
}

static inline void pool_run(void *ud, unsigned count, ray_task_fn task,
                     void *task_ud)
{
    test_pool *p = ud;

    pthread_mutex_lock(&p->lock);
    log_run(&p->log, count);
    p->order = shuffled(count, &p->log.seed);
    p->task = task;
    p->task_ud = task_ud;
    p->next = p->finished = 0;
    p->count = count;
    pthread_cond_broadcast(&p->work);
    while (p->finished < p->count)
        pthread_cond_wait(&p->done, &p->lock);
    free(p->order);
    p->order = NULL;
    p->count = p->next = 0;
    pthread_mutex_unlock(&p->lock);
}

static inline test_pool *pool_new(unsigned n_threads)
{
    test_pool *p = calloc(1, sizeof *p);
    unsigned i;

    ck_assert_ptr_nonnull(p);
    ck_assert_uint_le(n_threads, POOL_MAX);
    ck_assert_int_eq(pthread_mutex_init(&p->lock, NULL), 0);
    ck_assert_int_eq(pthread_cond_init(&p->work, NULL), 0);
    ck_assert_int_eq(pthread_cond_init(&p->done, NULL), 0);
    p->log.seed = 777;
    p->n_threads = n_threads;
    for (i = 0; i < n_threads; i++)
        ck_assert_int_eq(pthread_create(&p->thread[i], NULL, pool_main, p),
                         0);
    return p;
}

static inline ray_scheduler pool_scheduler(test_pool *p)
{
    ray_scheduler s;

    memset(&s, 0, sizeof s);
    s.run = pool_run;
    s.ud = p;
    s.threads = p->n_threads;
    return s;
}

static inline void pool_free(test_pool *p)
{
    unsigned i;

    pthread_mutex_lock(&p->lock);
    p->quit = 1;
    pthread_cond_broadcast(&p->work);
    pthread_mutex_unlock(&p->lock);
    for (i = 0; i < p->n_threads; i++)
        ck_assert_int_eq(pthread_join(p->thread[i], NULL), 0);
    pthread_cond_destroy(&p->work);
    pthread_cond_destroy(&p->done);
    pthread_mutex_destroy(&p->lock);
    free(p);
}

#endif /* SCHEDULER_KIT_H */
