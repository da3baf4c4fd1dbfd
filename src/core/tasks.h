/* SPDX-License-Identifier: MIT */
/*
** tasks.h -- the library's parallel work, as tasks (ray.h's ray_task_fn)
** run by the program's scheduler (ray_scheduler) or by the built-in
** threads (tasks.c): what the render, the threaded BVH build and the
** photon pass hand their work to.
*/
#ifndef RAY_TASKS_H
#define RAY_TASKS_H

#include "core/alloc.h"

/*
** Run task(ud, i) for every i in 0 .. count - 1 and return when all have
** returned.  With a scheduler whose run is set, run does it (on the
** program's threads).  Otherwise the built-in threads: the calling
** thread and up to threads - 1 started ones (no more than count), with
** at least "stack" bytes of stack (0: the platform's default), take the
** task numbers in order from a shared counter, so larger tasks numbered
** first start first.  A thread that cannot be started, or a counter
** lock that cannot be made, only means fewer threads: every task still
** runs once.  "a" (the scene's allocator) serves the thread handles and
** the lock, from the calling thread.  Every task runs in the calling
** thread's floating-point environment (tasks.c says why).
*/
void ray__tasks_run(const ray_scheduler *scheduler, const ray__allocator *a,
                    unsigned threads, size_t stack, unsigned count,
                    ray_task_fn task, void *ud);

/*
** A range of items in runs, a task each: fn(ud, k, b, e) for run k, the
** items b .. e - 1 of begin .. end - 1 cut into runs of "run" items (the
** last one shorter), on ray__tasks_run's threads.  For the passes whose
** runs write only their own items' outputs (or run k's own result), so
** that the bytes are the same at any thread count.  Returns 0 and runs
** nothing where the runs are more than a task number holds: the caller
** then does the range itself.
*/
typedef void (*ray__run_fn)(void *ud, unsigned k, size_t begin, size_t end);

int ray__tasks_runs(const ray_scheduler *scheduler, const ray__allocator *a,
                    unsigned threads, size_t begin, size_t end, size_t run,
                    ray__run_fn fn, void *ud);

/* The most threads a commit's work starts (ray_scene_set_build_threads,
** 0: one per online CPU): its builds (accel/build.c), refits
** (accel/refit.c) and crew (scene/commit.c). */
#define RAY__MAX_BUILD_THREADS 64

/*
** A crew: the built-in threads kept waiting between the parallel passes
** of one piece of work (a commit's build levels, subtrees, leaves and
** ids: scene/commit.c says which commits), where each ray__tasks_run
** would start and join threads of its own, eleven times in a
** 59k-triangle build on two threads: two
** threads' build of it, ours / Embree, 1.29, 1.08 -> 0.90, 1.05
** (build/bench/mesh DATA build, two interleaved runs; issue 36).
** ray__crew_begin starts nothing; ray__crew_scheduler gives the
** ray_scheduler that hands a pass's tasks to the crew, whose threads
** (threads - 1 of them: the caller is one) start at its first pass, so
** work that runs no pass starts none.  A pass asked for from inside a
** pass (a task's own parallel work) runs on the thread that asks.  Where
** the threads or their lock cannot be made, the caller runs every task:
** the same answers, as always.  Its threads have the stack given to
** ray__crew_begin (a pass's own "stack" is not asked: the commit's passes
** ask for none).  ray__crew_end stops and joins them and
** frees what they used.  The allocator is called on the calling thread
** only.
*/
typedef struct ray__crew {
    const ray__allocator *a;
    unsigned threads;
    size_t stack;
    int state;                   /* 0 not started, 1 running, -1 caller only */
    struct ray__thread *t;       /* threads - 1 */
    int *up;                     /* which of them started */
    struct ray__mutex *lock;
    struct ray__cond *wake, *idle;
    /* The pass, under lock: */
    unsigned pass, next, count, busy;
    int active, quit;
    ray_task_fn task;
    void *ud;
} ray__crew;

void ray__crew_begin(ray__crew *c, const ray__allocator *a,
                     unsigned threads, size_t stack);
ray_scheduler ray__crew_scheduler(ray__crew *c);
void ray__crew_end(ray__crew *c);

/* How many tasks a render or photon pass makes: "threads" (its options')
** if not 0, else the scheduler's threads if it says, else one per online
** CPU. */
unsigned ray__task_count(unsigned threads, const ray_scheduler *scheduler);

/* The scheduler to use: "chosen" (a render's options) if it has a run,
** else "fallback" (the scene's) if that has one, else NULL: the built-in
** threads. */
const ray_scheduler *ray__scheduler_pick(const ray_scheduler *chosen,
                                         const ray_scheduler *fallback);

#endif /* RAY_TASKS_H */
