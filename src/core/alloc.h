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

static inline void *ray__allocate(const ray__allocator *a, size_t size)
{
    return a->fn(a->ud, NULL, 0, size);
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
    return a->fn(a->ud, ptr, osize, nsize);
}

#endif /* RAY_ALLOC_H */
