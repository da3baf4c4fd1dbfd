/* SPDX-License-Identifier: MIT */
/*
** alloc.h -- the allocator every object with a lifetime allocates
** through: ray.h's ray_alloc_fn with its user data, as Lua's lua_Alloc.
** The scene keeps the user's (or libc's); the BVH, the photon map and
** the renderer's buffers are handed it, so they need nothing of the scene.
*/
#ifndef RAY_ALLOC_H
#define RAY_ALLOC_H

#include "core/vec.h"

/*
** An allocator as ray.h's ray_alloc_fn describes it, with its user data:
** what the layers above the
** scene's allocate through.
*/
typedef struct ray__allocator {
    ray_alloc_fn fn;
    void *ud;
} ray__allocator;

/*
** ray__memory_hint -- a large block just allocated (RAY__HUGE_BLOCK bytes
** or more), about to be written whole: on Linux, its 2 MiB-
** aligned interior is marked for transparent huge pages (madvise
** MADV_HUGEPAGE), so that a cold build touching 150 MB of fresh memory
** takes one page fault per 2 MiB instead of one per 4 KiB; elsewhere, and
** where the kernel declines, nothing.  A hint: it cannot fail.  The
** platform layer's (platform_posix.c, platform_win32.c), declared here,
** where the allocator calls it (platform.h includes this file).  On the
** 940k bunny: 3 cold builds' minor faults 130,719 -> 13,155, one
** thread's build 776 -> 372 ms, and its rays 16-19% faster for the TLB
** (bench/mesh, issue 36).
*/
void ray__memory_hint(void *p, size_t size);

#define RAY__HUGE_BLOCK ((size_t)4 << 20)

static inline void *ray__allocate(const ray__allocator *a, size_t size)
{
    void *p = a->fn(a->ud, NULL, 0, size);

    if (p != NULL && size >= RAY__HUGE_BLOCK)
        ray__memory_hint(p, size);
    return p;
}

static inline void ray__release(const ray__allocator *a, void *ptr,
                                size_t size)
{
    if (ptr != NULL)
        a->fn(a->ud, ptr, size, 0);
}

static inline void *ray__reallocate(const ray__allocator *a, void *ptr,
                                    size_t osize, size_t nsize)
{
    void *p = a->fn(a->ud, ptr, osize, nsize);

    if (p != NULL && nsize >= RAY__HUGE_BLOCK)
        ray__memory_hint(p, nsize);
    return p;
}

#endif /* RAY_ALLOC_H */
