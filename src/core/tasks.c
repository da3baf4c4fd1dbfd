/* SPDX-License-Identifier: MIT */
/*
** tasks.c -- ray__tasks_run (tasks.h): the program's scheduler, or the
** built-in threads of platform.h sharing a counter of task numbers.
**
** Every task runs in the floating-point environment of the thread that
** asked for the work (C99 <fenv.h>: rounding mode, flush-to-zero, the
** x87's precision): a thread starts with its platform's default, not its
** creator's, on Windows (POSIX threads inherit it), and a program's
** workers carry whatever the program set there (a game engine's
** flush-to-zero).  MinGW's pow and exp compute on the x87, whose
** precision its C runtime sets to 64 bits on the main thread and Windows
** to 53 on every other: 30% of pow's results and 17% of exp's differ
** between the two (scripts/libm-probe.c --threads, under Wine), and a
** row rendered on a started thread came out unlike the same row on the
** caller's.  So each task sets the
** caller's environment, and gives the worker its own back after.
*/
#include <fenv.h>
#include <string.h>

#include "core/platform.h"
#include "core/tasks.h"

const ray_scheduler *ray__scheduler_pick(const ray_scheduler *chosen,
                                         const ray_scheduler *fallback)
{
    if (chosen != NULL && chosen->run != NULL)
        return chosen;
    if (fallback != NULL && fallback->run != NULL)
        return fallback;
    return NULL;
}

unsigned ray__task_count(unsigned threads, const ray_scheduler *scheduler)
{
    if (threads > 0)
        return threads;
    if (scheduler != NULL && scheduler->threads > 0)
        return scheduler->threads;
    return ray__online_cpus();
}

/* A task run in the caller's floating-point environment (see above). */
typedef struct env_task {
    fenv_t env;               /* the caller's */
    ray_task_fn task;
    void *ud;
} env_task;

static void task_in_env(void *arg, unsigned i)
{
    const env_task *t = arg;
    fenv_t own;

    fegetenv(&own);
    fesetenv(&t->env);
    t->task(t->ud, i);
    fesetenv(&own);
}

/* What the built-in threads share: the next task number, under "lock". */
typedef struct tasks_job {
    ray__mutex *lock;
    unsigned next, count;
    ray_task_fn task;
    void *ud;
} tasks_job;

/* Take task numbers until none is left. */
static void take_tasks(void *arg)
{
    tasks_job *job = arg;

    for (;;) {
        unsigned i;
        ray__mutex_lock(job->lock);
        i = job->next;
        if (i < job->count)
            job->next++;
        ray__mutex_unlock(job->lock);
        if (i >= job->count)
            return;
        job->task(job->ud, i);
    }
}

/* The built-in threads: n - 1 started (n >= 2), the caller the n-th. */
static void run_threads(const ray__allocator *a, unsigned n, size_t stack,
                        tasks_job *job)
{
    ray__thread *t = NULL;
    int *started = NULL;
    unsigned i;

    if ((size_t)n - 1 <= (size_t)-1 / sizeof *t) {
        t = ray__allocate(a, ((size_t)n - 1) * sizeof *t);
        started = ray__allocate(a, ((size_t)n - 1) * sizeof *started);
    }
    if (t == NULL || started == NULL ||
        ray__mutex_new(a, &job->lock) != RAY_OK) {
        ray__release(a, t, ((size_t)n - 1) * sizeof *t);
        ray__release(a, started, ((size_t)n - 1) * sizeof *started);
        for (i = 0; i < job->count; i++)   /* all on the calling thread */
            job->task(job->ud, i);
        return;
    }
    for (i = 0; i + 1 < n; i++) {
        t[i].fn = take_tasks;
        t[i].arg = job;
        started[i] = ray__thread_start(&t[i], stack) == 0;
    }
    take_tasks(job);
    for (i = 0; i + 1 < n; i++)
        if (started[i])
            ray__thread_join(&t[i]);
    ray__mutex_free(a, job->lock);
    ray__release(a, t, ((size_t)n - 1) * sizeof *t);
    ray__release(a, started, ((size_t)n - 1) * sizeof *started);
}

void ray__tasks_run(const ray_scheduler *scheduler, const ray__allocator *a,
                    unsigned threads, size_t stack, unsigned count,
                    ray_task_fn task, void *ud)
{
    tasks_job job;
    env_task in_env;
    unsigned i;

    if (count == 0)
        return;
    if (threads > count)
        threads = count;
    if ((scheduler == NULL || scheduler->run == NULL) && threads <= 1) {
        for (i = 0; i < count; i++)      /* all on the calling thread */
            task(ud, i);
        return;
    }
    fegetenv(&in_env.env);
    in_env.task = task;
    in_env.ud = ud;
    if (scheduler != NULL && scheduler->run != NULL) {
        scheduler->run(scheduler->ud, count, task_in_env, &in_env);
        return;
    }
    job.lock = NULL;
    job.next = 0;
    job.count = count;
    job.task = task_in_env;
    job.ud = &in_env;
    run_threads(a, threads, stack, &job);
}

/* ray__tasks_runs's work: the range, its runs' size and the callback. */
typedef struct runs_job {
    size_t begin, end, run;
    ray__run_fn fn;
    void *ud;
} runs_job;

static void run_task(void *arg, unsigned k)
{
    const runs_job *job = arg;
    size_t begin = job->begin + (size_t)k * job->run;

    job->fn(job->ud, k, begin,
            job->end - begin > job->run ? begin + job->run : job->end);
}

int ray__tasks_runs(const ray_scheduler *scheduler, const ray__allocator *a,
                    unsigned threads, size_t begin, size_t end, size_t run,
                    ray__run_fn fn, void *ud)
{
    size_t runs = (end - begin) / run + ((end - begin) % run != 0);
    runs_job job;

    if (runs > 0xffffffffu)                 /* beyond the task count */
        return 0;
    job.begin = begin;
    job.end = end;
    job.run = run;
    job.fn = fn;
    job.ud = ud;
    ray__tasks_run(scheduler, a, threads, 0, (unsigned)runs, run_task, &job);
    return 1;
}

/* ---------------------------------------------------------------- crew */

/* Take the pass's tasks until none is left; c->lock held on entry and
** on return, released while a task runs.  The last to finish wakes the
** pass's caller. */
static void crew_take(ray__crew *c)
{
    while (c->next < c->count) {
        unsigned i = c->next++;
        c->busy++;
        ray__mutex_unlock(c->lock);
        c->task(c->ud, i);
        ray__mutex_lock(c->lock);
        if (--c->busy == 0 && c->next >= c->count)
            ray__cond_broadcast(c->idle);
    }
}

/* A crew thread: each new pass's tasks, until told to stop. */
static void crew_main(void *arg)
{
    ray__crew *c = arg;
    unsigned seen = 0;

    ray__mutex_lock(c->lock);
    for (;;) {
        while (!c->quit && c->pass == seen)
            ray__cond_wait(c->wake, c->lock);
        if (c->quit)
            break;
        seen = c->pass;
        crew_take(c);
    }
    ray__mutex_unlock(c->lock);
}

/* The threads started (at the first pass): 1 if any runs, else 0 with
** what was made freed (the caller then runs every pass itself). */
static int crew_start(ray__crew *c)
{
    size_t n = (size_t)c->threads - 1;
    unsigned i, any = 0;

    if (c->state != 0)
        return c->state > 0;
    c->state = -1;
    if (n == 0 || n > (size_t)-1 / sizeof *c->t)
        return 0;
    c->t = ray__allocate(c->a, n * sizeof *c->t);
    c->up = ray__allocate(c->a, n * sizeof *c->up);
    if (c->t == NULL || c->up == NULL ||
        ray__mutex_new(c->a, &c->lock) != RAY_OK ||
        ray__cond_new(c->a, &c->wake) != RAY_OK ||
        ray__cond_new(c->a, &c->idle) != RAY_OK) {
        ray__crew_end(c);
        return 0;
    }
    for (i = 0; i < n; i++) {
        c->t[i].fn = crew_main;
        c->t[i].arg = c;
        c->up[i] = ray__thread_start(&c->t[i], c->stack) == 0;
        any |= (unsigned)c->up[i];
    }
    if (!any) {
        ray__crew_end(c);
        return 0;
    }
    c->state = 1;
    return 1;
}

/* The crew's ray_scheduler run: the pass's tasks on its threads and the
** caller, returning when all have returned. */
static void crew_run(void *ud, unsigned count, ray_task_fn task,
                     void *task_ud)
{
    ray__crew *c = ud;
    unsigned i;

    if (crew_start(c)) {
        ray__mutex_lock(c->lock);
        if (!c->active) {
            c->active = 1;
            c->task = task;
            c->ud = task_ud;
            c->next = 0;
            c->count = count;
            c->pass++;
            ray__cond_broadcast(c->wake);
            crew_take(c);
            while (c->busy > 0)
                ray__cond_wait(c->idle, c->lock);
            c->active = 0;
            ray__mutex_unlock(c->lock);
            return;
        }
        ray__mutex_unlock(c->lock);  /* a pass inside a pass: here */
    }
    for (i = 0; i < count; i++)
        task(task_ud, i);
}

void ray__crew_begin(ray__crew *c, const ray__allocator *a,
                     unsigned threads, size_t stack)
{
    memset(c, 0, sizeof *c);
    c->a = a;
    c->threads = threads == 0 ? ray__online_cpus() : threads;
    c->stack = stack;
}

ray_scheduler ray__crew_scheduler(ray__crew *c)
{
    ray_scheduler sched;

    sched.run = crew_run;
    sched.ud = c;
    sched.threads = c->threads;
    return sched;
}

void ray__crew_end(ray__crew *c)
{
    size_t n = (size_t)c->threads - 1, i;

    if (c->state > 0) {
        ray__mutex_lock(c->lock);
        c->quit = 1;
        ray__cond_broadcast(c->wake);
        ray__mutex_unlock(c->lock);
        for (i = 0; i < n; i++)
            if (c->up[i])
                ray__thread_join(&c->t[i]);
    }
    ray__cond_free(c->a, c->idle);
    ray__cond_free(c->a, c->wake);
    ray__mutex_free(c->a, c->lock);
    if (c->t != NULL)
        ray__release(c->a, c->t, n * sizeof *c->t);
    if (c->up != NULL)
        ray__release(c->a, c->up, n * sizeof *c->up);
    c->t = NULL;
    c->up = NULL;
    c->lock = NULL;
    c->wake = c->idle = NULL;
    c->state = c->state > 0 ? 0 : c->state;
}
