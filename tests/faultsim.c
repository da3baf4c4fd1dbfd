/* SPDX-License-Identifier: MIT */
/*
** faultsim.c -- every allocation of every public entry point that
** allocates fails in turn, with leak accounting (SQLite's faultsim,
** test/malloc_common.tcl; Lua's ltests.c "failnext").
**
** The program is linked with -Wl,--wrap for malloc, calloc, realloc,
** free, the libpng simplified-API call the PNG writer makes, and
** pthread_create / pthread_mutex_init (the Makefile's FAULT_WRAPS; on
** Windows, whose threads are platform_win32.c's, the platform layer's
** ray__thread_start, and no mutex can fail there: WIN_FAULT_WRAPS): the
** library's calls in libray.a then land in the __wrap_* functions below,
** each a "fault point".  The PNG loader gives libpng its own allocator
** (png_create_read_struct_2 with malloc from libray.a), so libpng's
** allocations while loading are memory fault points like the rest.  The
** writer's libpng allocations happen inside the shared libpng, out of the
** linker's reach, so its libpng call stands for them: an injected failure
** there fails the call as libpng does when its malloc fails
** (png_safe_execute: the image freed, a message, 0).
**
** Each workload (a scene of every kind, contexts, renders of every kind,
** a textured render from a loaded PNG, PNG writing) runs once clean,
** counting its fault points n and taking a digest of its results; then
** for k = 1 .. n twice:
**   once -- only fault point k fails.  The call that failed must return
**           the status for that kind (RAY_ENOMEM for memory and mutexes,
**           RAY_EPNG for libpng) or absorb it (a thread not started: the
**           render goes on with fewer); it is then retried, and the
**           workload must end RAY_OK with the clean run's digest: a
**           failed call left everything as it was.
**   from -- fault point k and every later one fail.  The workload ends
**           at the first error, which must be that status.
** Either way, once the workload has freed what it made, no block it
** allocated may still be live, and with the scene's allocator hook every
** free must name the size that was allocated.  Each workload runs with
** the libc allocator (malloc wrapped) and with an allocator hook.
*/
#include <errno.h>
#include <limits.h>
#include <math.h>
#if !defined(_WIN32)
#include <pthread.h>
#endif
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "ray.h"
#include "prim/prim.h"         /* ray__implicit_torus (internal) */
#include "tempfiles.h"
#include "testkit.h"
#if defined(_WIN32)
#define WIN32_LEAN_AND_MEAN
#include <windows.h>
#include "core/platform.h"
#endif

/* RAY_TEST_PNG 0 (make PNG=0): a library without libpng, whose PNG calls
** return RAY_ENOTSUP; the PNG workloads and libpng's wrap are left out. */
#ifndef RAY_TEST_PNG
#define RAY_TEST_PNG 1
#endif
#if RAY_TEST_PNG
#include <png.h>
#endif

/* ------------------------------------------------------------ the wraps */

void *__real_malloc(size_t size);
void *__real_calloc(size_t n, size_t size);
void *__real_realloc(void *ptr, size_t size);
void __real_free(void *ptr);
#if RAY_TEST_PNG
int __real_png_image_write_to_memory(png_imagep image, void *memory,
                                     png_alloc_size_t *memory_bytes,
                                     int convert_to_8bit, const void *buffer,
                                     png_int_32 row_stride,
                                     const void *colormap);
#endif
#if defined(_WIN32)
int __real_ray__thread_start(ray__thread *t, size_t stack);
#else
int __real_posix_memalign(void **out, size_t align, size_t size);
int __real_pthread_create(pthread_t *thread, const pthread_attr_t *attr,
                          void *(*start)(void *), void *arg);
int __real_pthread_mutex_init(pthread_mutex_t *m,
                              const pthread_mutexattr_t *attr);
#endif

void *__wrap_malloc(size_t size);
#if !defined(_WIN32)
int __wrap_posix_memalign(void **out, size_t align, size_t size);
#endif
void *__wrap_calloc(size_t n, size_t size);
void *__wrap_realloc(void *ptr, size_t size);
void __wrap_free(void *ptr);
#if RAY_TEST_PNG
int __wrap_png_image_write_to_memory(png_imagep image, void *memory,
                                     png_alloc_size_t *memory_bytes,
                                     int convert_to_8bit, const void *buffer,
                                     png_int_32 row_stride,
                                     const void *colormap);
#endif
#if defined(_WIN32)
int __wrap_ray__thread_start(ray__thread *t, size_t stack);
#else
int __wrap_pthread_create(pthread_t *thread, const pthread_attr_t *attr,
                          void *(*start)(void *), void *arg);
int __wrap_pthread_mutex_init(pthread_mutex_t *m,
                              const pthread_mutexattr_t *attr);
#endif

/* Kinds of fault point, and the status a failure of each must give. */
enum { FP_MEMORY, FP_PNG, FP_THREAD, FP_MUTEX, FP_KINDS };
static const char *const kind_name[FP_KINDS] = {"memory", "libpng",
                                                "thread", "mutex"};

/* Live blocks: open addressing on the pointer, tombstones for deletions;
** emptied before each run (a run starts with nothing live). */
#define LIVE_SLOTS 4096u
#define TOMBSTONE ((void *)&live_table)

typedef struct live_block {
    void *ptr;
    size_t size;
} live_block;

static live_block live_table[LIVE_SLOTS];

/* The lock behind the run's state.  Windows: a slim lock, which needs no
** initialisation call and allocates nothing -- winpthreads' mutex
** allocates through calloc, which the link wraps too, into this lock
** again. */
#if defined(_WIN32)
static SRWLOCK fs_lock = SRWLOCK_INIT;
#define FS_LOCK() AcquireSRWLockExclusive(&fs_lock)
#define FS_UNLOCK() ReleaseSRWLockExclusive(&fs_lock)
#else
static pthread_mutex_t fs_lock = PTHREAD_MUTEX_INITIALIZER;
#define FS_LOCK() pthread_mutex_lock(&fs_lock)
#define FS_UNLOCK() pthread_mutex_unlock(&fs_lock)
#endif

/* The state of the current run, behind one lock: the render's threads
** may reach a fault point (a material's libc call, say) while others do. */
static struct {
    int armed;                 /* counting and failing: a run is going */
    long events;               /* fault points passed in this run */
    long by_kind[FP_KINDS];    /* the same, by kind */
    long fail_from, fail_to;   /* which fail, counted from 1 */
    long injected;             /* failures injected in this run */
    int first_kind;            /* kind of the first, -1 if none (a
                                  thread's only if no other kind failed) */
    long live, live_peak;      /* blocks allocated in the run, not freed */
    long size_errors;          /* frees through the hook with a wrong size */
    int in_png_write;          /* inside the wrapped libpng write call */
} fs = {0, 0, {0, 0, 0, 0}, 0, 0, 0, -1, 0, 0, 0, 0};

static size_t slot_of(const void *p)
{
    uintptr_t h = (uintptr_t)p;
    h ^= h >> 17;
    h *= (uintptr_t)0x9e3779b97f4a7c15u;
    return (size_t)(h >> 7) % LIVE_SLOTS;
}

/* Called with the lock held. */
static void live_add(void *p, size_t size)
{
    size_t i = slot_of(p), k;

    for (k = 0; k < LIVE_SLOTS; k++, i = (i + 1) % LIVE_SLOTS)
        if (live_table[i].ptr == NULL || live_table[i].ptr == TOMBSTONE) {
            live_table[i].ptr = p;
            live_table[i].size = size;
            if (++fs.live > fs.live_peak)
                fs.live_peak = fs.live;
            return;
        }
    fprintf(stderr, "faultsim: more than %u live blocks\n", LIVE_SLOTS);
    exit(EXIT_FAILURE);
}

/* Forget p if it is live; its size through *size.  0 if it was not (a
** block from before the run, or from libc itself). */
static int live_remove(const void *p, size_t *size)
{
    size_t i = slot_of(p), k;

    for (k = 0; k < LIVE_SLOTS && live_table[i].ptr != NULL;
         k++, i = (i + 1) % LIVE_SLOTS)
        if (live_table[i].ptr == p) {
            live_table[i].ptr = TOMBSTONE;
            fs.live--;
            if (size != NULL)
                *size = live_table[i].size;
            return 1;
        }
    return 0;
}

/* One fault point of the given kind: 1 if it is to fail. */
static int fault_point(int kind)
{
    int fail;

    FS_LOCK();
    fail = 0;
    /* An allocation inside libpng's write call (a static libpng, whose
    ** own malloc calls the link wraps too: the Windows build) fails that
    ** call as its libpng fault point does. */
    if (kind == FP_MEMORY && fs.in_png_write)
        kind = FP_PNG;
    if (fs.armed) {
        fs.events++;
        fs.by_kind[kind]++;
        fail = fs.events >= fs.fail_from && fs.events <= fs.fail_to;
        /* A thread not started is absorbed (fewer threads), so a call
        ** that fails answers for the first failure of another kind. */
        if (fail && (fs.first_kind < 0 ||
                     (fs.first_kind == FP_THREAD && kind != FP_THREAD)))
            fs.first_kind = kind;
        fs.injected += fail;
    }
    FS_UNLOCK();
    return fail;
}

static void track(void *p, size_t size)
{
    if (p == NULL)
        return;
    FS_LOCK();
    if (fs.armed)
        live_add(p, size);
    FS_UNLOCK();
}

static void untrack(const void *p)
{
    if (p == NULL)
        return;
    FS_LOCK();
    live_remove(p, NULL);
    FS_UNLOCK();
}

void *__wrap_malloc(size_t size)
{
    void *p;

    if (fault_point(FP_MEMORY))
        return NULL;
    p = __real_malloc(size);
    track(p, size);
    return p;
}

#if !defined(_WIN32)
/* The default allocator's large blocks (platform_posix.c, huge pages). */
int __wrap_posix_memalign(void **out, size_t align, size_t size)
{
    int rc;

    if (fault_point(FP_MEMORY))
        return ENOMEM;
    rc = __real_posix_memalign(out, align, size);
    if (rc == 0)
        track(*out, size);
    return rc;
}
#endif

void *__wrap_calloc(size_t n, size_t size)
{
    void *p;

    if (fault_point(FP_MEMORY))
        return NULL;
    p = __real_calloc(n, size);
    track(p, n * size);
    return p;
}

void *__wrap_realloc(void *ptr, size_t size)
{
    void *p;

    if (size == 0) {            /* the library frees with free(), not this */
        untrack(ptr);
        return __real_realloc(ptr, size);
    }
    if (fault_point(FP_MEMORY))
        return NULL;            /* ptr stays allocated, as C99 7.20.3.4 says */
    p = __real_realloc(ptr, size);
    if (p != NULL) {
        untrack(ptr);
        track(p, size);
    }
    return p;
}

void __wrap_free(void *ptr)
{
    untrack(ptr);
    __real_free(ptr);
}

#if RAY_TEST_PNG
/* What libpng does when an allocation inside the call fails. */
static int png_fails(png_imagep image)
{
    png_image_free(image);
    image->warning_or_error = PNG_IMAGE_ERROR;
    strcpy(image->message, "out of memory (faultsim)");
    return 0;
}

int __wrap_png_image_write_to_memory(png_imagep image, void *memory,
                                     png_alloc_size_t *memory_bytes,
                                     int convert_to_8bit, const void *buffer,
                                     png_int_32 row_stride,
                                     const void *colormap)
{
    int ok;

    if (fault_point(FP_PNG))
        return png_fails(image);
    FS_LOCK();
    fs.in_png_write = 1;
    FS_UNLOCK();
    ok = __real_png_image_write_to_memory(image, memory, memory_bytes,
                                          convert_to_8bit, buffer,
                                          row_stride, colormap);
    FS_LOCK();
    fs.in_png_write = 0;
    FS_UNLOCK();
    return ok;
}
#endif

#if defined(_WIN32)
int __wrap_ray__thread_start(ray__thread *t, size_t stack)
{
    if (fault_point(FP_THREAD))
        return -1;              /* _beginthreadex failed: no thread */
    return __real_ray__thread_start(t, stack);
}
#else
int __wrap_pthread_create(pthread_t *thread, const pthread_attr_t *attr,
                          void *(*start)(void *), void *arg)
{
    if (fault_point(FP_THREAD))
        return EAGAIN;          /* POSIX: no resources for a thread */
    return __real_pthread_create(thread, attr, start, arg);
}

int __wrap_pthread_mutex_init(pthread_mutex_t *m,
                              const pthread_mutexattr_t *attr)
{
    if (fault_point(FP_MUTEX))
        return ENOMEM;          /* POSIX: no memory for the mutex */
    return __real_pthread_mutex_init(m, attr);
}
#endif

/* The scene allocator hook: its own fault point, the sizes checked. */
static void *hook_alloc(void *ud, void *ptr, size_t osize, size_t nsize)
{
    void *p;
    size_t had;

    (void)ud;
    if (ptr != NULL && nsize == 0) {
        FS_LOCK();
        if (live_remove(ptr, &had) && had != osize)
            fs.size_errors++;
        FS_UNLOCK();
        __real_free(ptr);
        return NULL;
    }
    if (fault_point(FP_MEMORY))
        return NULL;
    p = __real_realloc(ptr, nsize);
    if (p != NULL) {
        FS_LOCK();
        if (ptr != NULL && live_remove(ptr, &had) && had != osize)
            fs.size_errors++;
        if (fs.armed)
            live_add(p, nsize);
        FS_UNLOCK();
    }
    return p;
}

/* ------------------------------------------------------- workload tools */

/* A workload's environment: the allocator, the retry rule, the digest. */
typedef struct env {
    ray_alloc_fn alloc;       /* NULL (libc, wrapped) or hook_alloc */
    int retry;                /* "once" runs: retry a call that failed */
    int first_status;         /* the first failed call's status, or 0 */
    uint64_t digest;          /* FNV-1a of the results */
    const char *dir;          /* a private temporary directory */
} env;

static long injected_so_far(void)
{
    long n;

    FS_LOCK();
    n = fs.injected;
    FS_UNLOCK();
    return n;
}

/*
** CALL(e, expr): run a library call.  When it fails and a failure was
** injected during it: note its status, and in a "once" run call it again
** (the fault has passed: it must now succeed).  Any failure left jumps to
** "out", where the workload frees what it made.
*/
#define CALL(e, expr)                                                   \
    do {                                                                \
        long before_ = injected_so_far();                               \
        rc = (expr);                                                    \
        if (rc != RAY_OK && injected_so_far() > before_) {              \
            if ((e)->first_status == 0)                                 \
                (e)->first_status = rc;                                 \
            if ((e)->retry)                                             \
                rc = (expr);                                            \
        }                                                               \
        if (rc != RAY_OK)                                               \
            goto out;                                                   \
    } while (0)

static void digest_bytes(env *e, const void *p, size_t n)
{
    const unsigned char *b = p;
    size_t i;

    for (i = 0; i < n; i++) {
        e->digest ^= b[i];
        e->digest *= 0x100000001b3u;    /* FNV-1a 64-bit prime */
    }
}

/* What a workload's scene holds: bits. */
enum {
    HAS_PRIMS = 1,            /* spheres, plane, triangle, polygon */
    HAS_AREA = 2,             /* sphere and rect lights, not a point */
    HAS_CURVED = 4,           /* implicit, torus, parametric, Bezier */
    HAS_MESH = 8,             /* meshes with and without attributes */
    HAS_TEXTURE = 16,         /* a textured sphere; needs scene_parts.image */
    HAS_MANY = 32             /* enough of each to grow every array */
};

/* Everything a scene borrows, kept alive with it. */
typedef struct scene_parts {
    ray_phong_params red, white, textured;
    ray_rgb mirror;
    ray_glass_params glass;
    ray_torus_params torus, implicit_torus;
    ray_implicit_surface implicit;
    ray_parametric_surface wave;
    const ray_image *image;
} scene_parts;

static void wave_eval(void *ud, double u, double v, ray_vec3 *p,
                      ray_vec3 *pu, ray_vec3 *pv)
{
    (void)ud;
    *p = vec(u - 1.5, 0.2 * sin(u) * cos(v) + 0.3, v - 3.0);
    *pu = vec(1, 0.2 * cos(u) * cos(v), 0);
    *pv = vec(0, -0.2 * sin(u) * sin(v), 1);
}

static void wave_bounds(void *ud, double u0, double u1, double v0, double v1,
                        ray_vec3 *lo, ray_vec3 *hi)
{
    (void)ud;
    *lo = vec(u0 - 1.5, 0.1, v0 - 3.0);
    *hi = vec(u1 - 1.5, 0.5, v1 - 3.0);
}

static int add_prims(env *e, ray_scene *s, unsigned red, unsigned glass)
{
    ray_vec3 quad[4] = {{-3, 0, -2}, {-2, 0, -2}, {-2, 1, -2}, {-3, 1, -2}};
    int rc;

    CALL(e, ray_scene_add_sphere(s, vec(-1, 1, 0), 1, red, NULL));
    CALL(e, ray_scene_add_sphere(s, vec(1.2, 0.8, 0.5), 0.8, glass, NULL));
    CALL(e, ray_scene_add_triangle(s, vec(2, 0, -2), vec(3, 0, -2),
                                   vec(2.5, 1.5, -2), red, NULL));
    CALL(e, ray_scene_add_polygon(s, quad, 4, red, NULL));
out:
    return rc;
}

static int add_curved(env *e, ray_scene *s, scene_parts *sp, unsigned mat)
{
    ray_vec3 cp[16];
    int rc, i, j;

    sp->torus.center = vec(-1.5, 0.5, 1.5);
    sp->torus.axis = vec(0, 1, 0);
    sp->torus.major = 0.6;
    sp->torus.minor = 0.2;
    CALL(e, ray_scene_add_torus(s, &sp->torus, mat, NULL));
    sp->implicit_torus = sp->torus;
    sp->implicit_torus.center = vec(1.5, 0.5, 1.5);
    CALL(e, ray__implicit_torus(&sp->implicit_torus, &sp->implicit));
    CALL(e, ray_scene_add_implicit(s, &sp->implicit, mat, NULL));
    memset(&sp->wave, 0, sizeof sp->wave);
    sp->wave.eval = wave_eval;
    sp->wave.bounds = wave_bounds;
    sp->wave.u1 = 3;
    sp->wave.v1 = 2;
    CALL(e, ray_scene_add_parametric(s, &sp->wave, mat, NULL));
    for (i = 0; i < 4; i++)        /* a dome over [-0.5, 1] x [1, 2.5] */
        for (j = 0; j < 4; j++)
            cp[4 * i + j] = vec(-0.5 + 0.5 * j,
                                (i == 1 || i == 2) && (j == 1 || j == 2)
                                    ? 1.0 : 0.2,
                                1.0 + 0.5 * i);
    CALL(e, ray_scene_add_bezier(s, cp, mat, NULL));
out:
    return rc;
}

/* A pyramid three times: with normals and texture coordinates, bare,
** and as a game gives it (float positions, 16-bit indices, whose copy
** for shading is one more allocation) with normals. */
static int add_meshes(env *e, ray_scene *s, unsigned mat)
{
    static const uint16_t idx16[12] = {0, 4, 1, 1, 4, 2, 2, 4, 3, 3, 4, 0};
    float fpos[5][3];
    static const ray_vec3 v[5] = {
        {0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}, {0.5, 1, 0.5}};
    static const ray_vec3 n[5] = {
        {-1, 1, -1}, {1, 1, -1}, {1, 1, 1}, {-1, 1, 1}, {0, 1, 0}};
    static const double st[10] = {0, 0, 1, 0, 1, 1, 0, 1, 0.5, 0.5};
    static const unsigned idx[12] = {0, 4, 1, 1, 4, 2, 2, 4, 3, 3, 4, 0};
    ray_vec3 moved[5];
    ray_mesh m;
    int rc, i;

    memset(&m, 0, sizeof m);
    for (i = 0; i < 5; i++)
        moved[i] = vec(v[i].x - 2.5, v[i].y, v[i].z);
    m.vertices = moved;
    m.vertex_count = 5;
    m.indices = idx;
    m.triangle_count = 4;
    m.normals = n;
    m.texcoords = st;
    CALL(e, ray_scene_add_mesh(s, &m, mat, NULL));
    for (i = 0; i < 5; i++)
        moved[i] = vec(v[i].x + 1.5, v[i].y, v[i].z + 1);
    m.normals = NULL;
    m.texcoords = NULL;
    CALL(e, ray_scene_add_mesh(s, &m, mat, NULL));
    for (i = 0; i < 5; i++) {
        fpos[i][0] = (float)v[i].x - 0.5f;
        fpos[i][1] = (float)v[i].y;
        fpos[i][2] = (float)v[i].z - 2.0f;
    }
    m.vertices = NULL;
    m.indices = NULL;
    m.positions = fpos;
    m.position_type = RAY_FLOAT32;
    m.index_data = idx16;
    m.index_type = RAY_UINT16;
    m.normals = n;
    CALL(e, ray_scene_add_mesh(s, &m, mat, NULL));
out:
    return rc;
}

static int add_lights(env *e, ray_scene *s, int area)
{
    ray_light l;
    int rc;

    memset(&l, 0, sizeof l);
    if (area) {
        l.kind = RAY_LIGHT_RECT;
        l.position = vec(-1, 5, -1);
        l.edge1 = vec(2, 0, 0);
        l.edge2 = vec(0, 0, 2);   /* edge1 x edge2 = (0, -4, 0): down */
        l.intensity = rgb(20, 20, 20);
        l.samples = 4;
        CALL(e, ray_scene_add_light(s, &l, NULL));
        l.kind = RAY_LIGHT_SPHERE;
        l.position = vec(3, 4, 3);
        l.radius = 0.5;
        CALL(e, ray_scene_add_light(s, &l, NULL));
    } else {
        l.kind = RAY_LIGHT_POINT;
        l.position = vec(2, 5, 4);
        l.intensity = rgb(30, 30, 30);
        CALL(e, ray_scene_add_light(s, &l, NULL));
        l.kind = RAY_LIGHT_DIRECTIONAL;
        l.direction = vec(-1, -2, -1);
        l.intensity = rgb(0.3, 0.3, 0.3);
        CALL(e, ray_scene_add_light(s, &l, NULL));
    }
out:
    return rc;
}

/* Past the 8 that every array starts with (scene.c, ray__grow), so each
** grows by realloc with its contents to keep -- and trimming follows. */
static int add_many(env *e, ray_scene *s, const ray_material *m)
{
    ray_light l;
    unsigned mat;
    int rc, i;

    memset(&l, 0, sizeof l);
    l.kind = RAY_LIGHT_POINT;
    l.intensity = rgb(2, 2, 2);
    for (i = 0; i < 9; i++) {
        CALL(e, ray_scene_add_material(s, m, &mat));
        CALL(e, ray_scene_add_sphere(s, vec(-4 + i, 3, -3), 0.3, mat, NULL));
        CALL(e, ray_scene_add_triangle(s, vec(-4 + i, 0, -4),
                                       vec(-3.5 + i, 0, -4),
                                       vec(-4 + i, 1, -4), mat, NULL));
        l.position = vec(-4 + i, 6, 2);
        CALL(e, ray_scene_add_light(s, &l, NULL));
    }
out:
    return rc;
}

/* Build and commit a scene of the given parts into *out (NULL on error,
** with whatever was made freed). */
static int build_scene(env *e, int parts, scene_parts *sp, ray_scene **out)
{
    ray_scene *s = NULL;
    ray_material m;
    unsigned red, white, glass, tex;
    int rc;

    sp->red.diffuse = rgb(0.9, 0.1, 0.1);
    sp->red.specular = rgb(0.3, 0.3, 0.3);
    sp->red.shininess = 20;
    sp->white.diffuse = rgb(0.8, 0.8, 0.8);
    sp->white.reflect = rgb(0.2, 0.2, 0.2);
    sp->mirror = rgb(0.9, 0.9, 0.9);
    sp->glass.ior = 1.5;
    sp->glass.absorption = rgb(0.5, 0.2, 0.0);
    sp->textured.diffuse = rgb(1, 1, 1);
    sp->textured.texture = ray_texture_image(sp->image);
    CALL(e, ray_scene_new(&s, e->alloc, NULL));
    m = ray_material_phong(&sp->red);
    CALL(e, ray_scene_add_material(s, &m, &red));
    m = ray_material_phong(&sp->white);
    CALL(e, ray_scene_add_material(s, &m, &white));
    m = ray_material_glass(&sp->glass);
    CALL(e, ray_scene_add_material(s, &m, &glass));
    CALL(e, ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 1, 0), white, NULL));
    if (parts & HAS_PRIMS)
        CALL(e, add_prims(e, s, red, glass));
    if (parts & HAS_CURVED)
        CALL(e, add_curved(e, s, sp, red));
    if (parts & HAS_MESH)
        CALL(e, add_meshes(e, s, red));
    if (parts & HAS_TEXTURE) {
        m = ray_material_phong(&sp->textured);
        CALL(e, ray_scene_add_material(s, &m, &tex));
        CALL(e, ray_scene_add_sphere(s, vec(0, 1, 1), 0.9, tex, NULL));
        if (parts & HAS_MESH)
            CALL(e, add_meshes(e, s, tex));
    }
    if (parts & HAS_MANY) {
        m = ray_material_phong(&sp->white);
        CALL(e, add_many(e, s, &m));
    }
    CALL(e, add_lights(e, s, (parts & HAS_AREA) != 0));
    CALL(e, ray_scene_set_background(s, rgb(0.1, 0.2, 0.6), NULL, NULL));
    CALL(e, ray_scene_commit(s));
    *out = s;
    return RAY_OK;
out:
    ray_scene_free(s);
    *out = NULL;
    return rc;
}

/* ------------------------------------------------------------ workloads */

#define IMG_W 12
#define IMG_H 9

typedef struct render_case {
    int parts;
    unsigned y0, y1;
    double adaptive;          /* > 0: adaptive antialiasing */
    unsigned samples;
    unsigned long long photons;  /* > 0: caustics (the scene's glass and
                                    reflecting Phong scatter photons) */
} render_case;

static int render_workload(env *e, const render_case *c, const ray_image *img)
{
    static float rgb[IMG_W * IMG_H * 3];
    scene_parts sp;
    ray_scene *s = NULL;
    ray_camera cam;
    ray_render_options o;
    int rc;

    memset(&sp, 0, sizeof sp);
    sp.image = img;
    CALL(e, build_scene(e, c->parts, &sp, &s));
    memset(&cam, 0, sizeof cam);
    cam.position = vec(0, 2, 7);
    cam.look_at = vec(0, 0.7, 0);
    cam.up = vec(0, 1, 0);
    cam.vfov = 45;
    o = (ray_render_options){.width = IMG_W, .height = IMG_H};
    o.threads = 3;            /* two pthread_create calls to fail */
    o.samples = c->samples;
    o.seed = 7;
    o.y0 = c->y0;
    o.y1 = c->y1;
    o.adaptive_threshold = c->adaptive;
    o.photons = c->photons;
    memset(rgb, 0, sizeof rgb);
    CALL(e, ray_render(s, &cam, &o, rgb, NULL));
    digest_bytes(e, rgb, sizeof rgb);
out:
    ray_scene_free(s);
    return rc;
}

static int w_render_point(env *e)
{
    static const render_case c = {HAS_PRIMS, 0, 0, 0, 1, 0};
    return render_workload(e, &c, NULL);
}

static int w_render_area(env *e)
{
    static const render_case c = {HAS_PRIMS | HAS_AREA, 0, 0, 0, 4, 0};
    return render_workload(e, &c, NULL);
}

static int w_render_adaptive(env *e)
{
    static const render_case c = {HAS_PRIMS, 0, 0, 0.05, 1, 0};
    return render_workload(e, &c, NULL);
}

static int w_render_region(env *e)
{
    static const render_case c = {HAS_PRIMS | HAS_AREA, 3, 7, 0.05, 1, 0};
    return render_workload(e, &c, NULL);
}

static int w_render_curved(env *e)
{
    static const render_case c = {HAS_CURVED, 0, 0, 0, 1, 0};
    return render_workload(e, &c, NULL);
}

static int w_render_mesh(env *e)
{
    static const render_case c = {HAS_MESH | HAS_AREA, 0, 0, 0, 1, 0};
    return render_workload(e, &c, NULL);
}

/* Caustics: the photon pass from a point and a directional light (two
** chunks, on the three render threads:
** their pthread_create calls and every chunk's buffer fail in turn). */
static int w_render_caustics(env *e)
{
    static const render_case c = {HAS_PRIMS, 0, 0, 0, 1, 5000};
    return render_workload(e, &c, NULL);
}

/* A photon map built apart and read from a context. */
static int w_photon_map(env *e)
{
    scene_parts sp;
    ray_scene *s = NULL;
    ray_ctx *ctx = NULL;
    ray_photon_map *map = NULL;
    ray_render_options o;
    int rc, i;

    memset(&sp, 0, sizeof sp);
    CALL(e, build_scene(e, HAS_PRIMS | HAS_AREA, &sp, &s));
    o = (ray_render_options){.width = 1, .height = 1};
    o.photons = 5000;
    o.threads = 2;
    CALL(e, ray_photon_map_build(s, &o, &map));
    CALL(e, ray_ctx_new(s, 3, &ctx));
    CALL(e, ray_ctx_set_photon_map(ctx, map));
    for (i = 0; i < 8; i++) {
        ray_ray r;
        ray_rgb c;
        r.org = vec(-1.5 + 0.4 * i, 3, 2);
        r.dir = vec(0.1, -1, -0.3);
        r.tmin = 0;
        r.tmax = HUGE_VAL;
        CALL(e, ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1.0, &c));
        digest_bytes(e, &c, sizeof c);
    }
out:
    ray_ctx_free(ctx);
    ray_photon_map_free(map);
    ray_scene_free(s);
    return rc;
}

/*
** The shape queries on the same scene (issue 30), which allocate
** nothing: a sphere and a capsule swept along r, the primitives a sphere
** about its origin meets, and a surface point of geometry i, 0 at (0.2,
** 0.3); after a failed allocation and its retry they answer the same.
*/
static void digest_shapes(env *e, const ray_scene *s, const ray_ray *r,
                          unsigned i)
{
    ray_sweep w;
    ray_contact c;
    ray_overlap o[8];
    ray_hit h;
    size_t n = 0;
    int rc;

    memset(&w, 0, sizeof w);
    w.shape.a = w.shape.b = r->org;
    w.shape.radius = 0.3;
    w.dir = r->dir;
    w.tmax = 20;
    memset(&c, 0, sizeof c);
    rc = ray_intersect_sweep(s, &w, NULL, &c);
    digest_bytes(e, &rc, sizeof rc);
    digest_bytes(e, &c, sizeof c);
    w.shape.b = vec(r->org.x + 0.5, r->org.y, r->org.z);
    memset(&c, 0, sizeof c);
    rc = ray_intersect_sweep(s, &w, NULL, &c);
    digest_bytes(e, &rc, sizeof rc);
    digest_bytes(e, &c, sizeof c);
    memset(o, 0, sizeof o);
    rc = ray_overlap_shape_all(s, TK_SPHERE(vec(r->org.x, 0, r->org.z), 1.5), NULL, o,
                                8, &n);
    digest_bytes(e, &rc, sizeof rc);
    digest_bytes(e, o, sizeof o);
    memset(&h, 0, sizeof h);
    rc = ray_surface_point(s, i, 0, RAY_INVALID_ID, 0.2, 0.3, &h);
    digest_bytes(e, &rc, sizeof rc);
    digest_bytes(e, &h, sizeof h);
}

/* A scene of everything, queried; two contexts tracing. */
static int w_scene_and_ctx(env *e)
{
    scene_parts sp;
    ray_scene *s = NULL;
    ray_ctx *a = NULL, *b = NULL;
    int rc, i;

    memset(&sp, 0, sizeof sp);
    CALL(e, build_scene(e, HAS_PRIMS | HAS_CURVED | HAS_MESH | HAS_AREA |
                               HAS_MANY, &sp, &s));
    CALL(e, ray_ctx_new(s, 1, &a));
    CALL(e, ray_ctx_new(s, 2, &b));
    for (i = 0; i < 16; i++) {
        ray_ray r;
        ray_hit h;
        ray_rgb c;

        r.org = vec(-3 + 0.4 * i, 3, 6);
        r.dir = vec(0, -0.4, -1);
        r.tmin = 0;
        r.tmax = HUGE_VAL;
        memset(&h, 0, sizeof h);
        digest_bytes(e, &(int){ray_intersect(s, &r, &h, NULL)}, sizeof(int));
        digest_bytes(e, &h, sizeof h);
        digest_bytes(e, &(int){ray_occluded(s, &r, NULL)}, sizeof(int));
        CALL(e, ray_trace(i % 2 ? a : b, &r, RAY_KIND_PRIMARY, 1, &c));
        digest_bytes(e, &c, sizeof c);
        digest_shapes(e, s, &r, (unsigned)i);
    }
out:
    ray_ctx_free(a);
    ray_ctx_free(b);
    ray_scene_free(s);
    return rc;
}

/*
** A threaded commit (ray_scene_set_build_threads): a wavy grid of 2 x 68 x
** 68 = 9248 triangles, more than the 2 x 4096 that bvh.c builds as one
** task, so the commit starts threads (two pthread_create and a mutex: fault
** points; a thread not started, or the mutex not made, means fewer
** threads and the same tree); then rays down onto it, digested.
*/
#define GRID 68

static int w_threaded_commit(env *e)
{
    static ray_vec3 v[(GRID + 1) * (GRID + 1)];
    static unsigned idx[6 * GRID * GRID];
    ray_scene *s = NULL;
    ray_material m;
    ray_phong_params red;
    ray_mesh mesh;
    unsigned mat, x, y, k = 0;
    int rc, i;

    for (y = 0; y <= GRID; y++)
        for (x = 0; x <= GRID; x++)
            v[y * (GRID + 1) + x] = vec(x, 0.3 * sin(0.7 * x) * cos(0.5 * y),
                                        y);
    for (y = 0; y < GRID; y++)
        for (x = 0; x < GRID; x++) {
            unsigned c = y * (GRID + 1) + x;
            idx[k++] = c;
            idx[k++] = c + 1;
            idx[k++] = c + GRID + 1;
            idx[k++] = c + 1;
            idx[k++] = c + GRID + 2;
            idx[k++] = c + GRID + 1;
        }
    memset(&mesh, 0, sizeof mesh);
    mesh.vertices = v;
    mesh.vertex_count = (GRID + 1) * (GRID + 1);
    mesh.indices = idx;
    mesh.triangle_count = 2 * GRID * GRID;
    memset(&red, 0, sizeof red);
    red.diffuse = rgb(0.9, 0.1, 0.1);
    m = ray_material_phong(&red);
    CALL(e, ray_scene_new(&s, e->alloc, NULL));
    CALL(e, ray_scene_add_material(s, &m, &mat));
    CALL(e, ray_scene_add_mesh(s, &mesh, mat, NULL));
    CALL(e, ray_scene_set_build_threads(s, 3));
    CALL(e, ray_scene_commit(s));
    for (i = 0; i < 64; i++) {
        ray_ray r;
        ray_hit h;

        r.org = vec(0.5 + 1.05 * i, 5, 0.5 + 0.97 * i);
        r.dir = vec(0.01, -1, 0.02);
        r.tmin = 0;
        r.tmax = HUGE_VAL;
        memset(&h, 0, sizeof h);
        digest_bytes(e, &(int){ray_intersect(s, &r, &h, NULL)}, sizeof(int));
        digest_bytes(e, &h, sizeof h);
    }
out:
    ray_scene_free(s);
    return rc;
}

static char texture_path[4096], output_path[4096];

#if RAY_TEST_PNG
/* Load the texture written at setup, sample it, render with it. */
static int w_texture(env *e)
{
    static const render_case c = {HAS_TEXTURE | HAS_MESH, 0, 0, 0, 1, 0};
    ray_image *img = NULL;
    unsigned w, h;
    ray_rgb texel;
    int rc;

    CALL(e, ray_image_load_png(texture_path, NULL, &img));
    ray_image_size(img, &w, &h);
    digest_bytes(e, &w, sizeof w);
    digest_bytes(e, &h, sizeof h);
    CALL(e, ray_image_sample(img, 0.3, 0.6, 0, &texel));
    digest_bytes(e, &texel, sizeof texel);
    CALL(e, render_workload(e, &c, img));
out:
    ray_image_free(img);
    return rc;
}

/* The file's bytes into the digest; 0 if it cannot be read. */
static int digest_file(env *e, const char *path)
{
    unsigned char buf[4096];
    size_t n;
    FILE *fp = fopen(path, "rb");

    if (fp == NULL)
        return 0;
    while ((n = fread(buf, 1, sizeof buf, fp)) > 0)
        digest_bytes(e, buf, n);
    fclose(fp);
    return 1;
}
#endif

/* A test card: a gradient with a bright corner, some values out of
** [0, 1] and a NaN, so the clamping paths run too. */
static void test_card(float *rgb, unsigned w, unsigned h)
{
    unsigned x, y;

    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            float *p = rgb + 3 * ((size_t)y * w + x);
            p[0] = (float)x / (float)w;
            p[1] = (float)y / (float)h;
            p[2] = (float)(x + y) / (float)(w + h) * 1.5f;
        }
    rgb[0] = -1.0f;
    rgb[1] = (float)NAN;
}

#if RAY_TEST_PNG
/* ray_write_png at both depths; a failed write leaves no file. */
static int w_write_png(env *e)
{
    static float rgb[7 * 5 * 3];
    int rc, bits;

    test_card(rgb, 7, 5);
    for (bits = 8; bits <= 16; bits += 8) {
        long before = injected_so_far();

        remove(output_path);
        rc = ray_write_png(output_path, rgb, 7, 5, bits);
        if (rc != RAY_OK && access(output_path, F_OK) == 0) {
            fprintf(stderr, "faultsim: a failed ray_write_png left %s\n",
                    output_path);
            return -1;
        }
        /* Retried by hand: the file must be gone before the retry too. */
        if (rc != RAY_OK && injected_so_far() > before) {
            if (e->first_status == 0)
                e->first_status = rc;
            if (e->retry)
                rc = ray_write_png(output_path, rgb, 7, 5, bits);
        }
        if (rc != RAY_OK)
            return rc;
        if (!digest_file(e, output_path))
            return RAY_EIO;
    }
    return RAY_OK;
}
#endif

/* --------------------------------------------------------------- runner */

typedef struct workload {
    const char *name;
    int (*run)(env *e);
    int uses_scene;           /* run with the allocator hook as well */
    int uses_png;             /* must reach libpng's wrapped calls */
} workload;

static const workload workloads[] = {
    {"scene+ctx", w_scene_and_ctx, 1, 0},
    {"threaded commit", w_threaded_commit, 1, 0},
    {"render point lights", w_render_point, 1, 0},
    {"render area lights", w_render_area, 1, 0},
    {"render adaptive", w_render_adaptive, 1, 0},
    {"render region", w_render_region, 1, 0},
    {"render curved", w_render_curved, 1, 0},
    {"render mesh", w_render_mesh, 1, 0},
    {"render caustics", w_render_caustics, 1, 0},
    {"photon map", w_photon_map, 1, 0},
#if RAY_TEST_PNG
    {"texture load+render", w_texture, 1, 0},
    {"write png", w_write_png, 0, 1},
#endif
};

/* The outcome of one run. */
typedef struct outcome {
    int rc;
    uint64_t digest;
    int first_status, first_kind;
    long events, injected, leaked, size_errors, peak;
    long by_kind[FP_KINDS];
} outcome;

static outcome run_once(const workload *w, ray_alloc_fn alloc, int retry,
                        long fail_from, long fail_to)
{
    outcome o;
    env e;

    memset(&e, 0, sizeof e);
    e.alloc = alloc;
    e.retry = retry;
    e.digest = 0xcbf29ce484222325u;    /* FNV-1a 64-bit offset basis */
    FS_LOCK();
    memset(live_table, 0, sizeof live_table);
    fs.events = fs.injected = fs.live = fs.live_peak = fs.size_errors = 0;
    memset(fs.by_kind, 0, sizeof fs.by_kind);
    fs.fail_from = fail_from;
    fs.fail_to = fail_to;
    fs.first_kind = -1;
    fs.armed = 1;
    FS_UNLOCK();

    o.rc = w->run(&e);

    FS_LOCK();
    fs.armed = 0;
    o.events = fs.events;
    memcpy(o.by_kind, fs.by_kind, sizeof o.by_kind);
    o.injected = fs.injected;
    o.leaked = fs.live;
    o.peak = fs.live_peak;
    o.size_errors = fs.size_errors;
    o.first_kind = fs.first_kind;
    FS_UNLOCK();
    o.digest = e.digest;
    o.first_status = e.first_status;
    return o;
}

static int expected_status(int kind)
{
    switch (kind) {
    case FP_PNG:
        return RAY_EPNG;
    case FP_THREAD:
        return RAY_OK;        /* the render or the build goes on with
                                 fewer threads */
    default:
        return RAY_ENOMEM;
    }
}

static long failures;

static void fail(const char *what, const workload *w, ray_alloc_fn alloc,
                 const char *mode, long k, const outcome *o)
{
    failures++;
    fprintf(stderr,
            "faultsim: %s: %s (%s allocator), %s k=%ld: rc %d, first failure "
            "%s -> %d, %ld leaked, %ld size errors\n",
            w->name, what, alloc ? "hook" : "libc", mode, k, o->rc,
            o->first_kind >= 0 ? kind_name[o->first_kind] : "none",
            o->first_status, o->leaked, o->size_errors);
}

/* One run's checks against the clean run "ref". */
static void judge(const workload *w, ray_alloc_fn alloc, int retry, long k,
                  const outcome *o, const outcome *ref)
{
    const char *mode = retry ? "once" : "from";
    int want = o->first_kind >= 0 ? expected_status(o->first_kind) : RAY_OK;

    if (o->leaked != 0)
        fail("leak", w, alloc, mode, k, o);
    if (o->size_errors != 0)
        fail("freed with the wrong size", w, alloc, mode, k, o);
    if (o->first_status != 0 && o->first_status != want)
        fail("wrong status for the injected failure", w, alloc, mode, k, o);
    if (retry ? o->rc != RAY_OK
              : o->rc != RAY_OK && o->rc != want)
        fail(retry ? "did not recover once the fault passed"
                   : "wrong status", w, alloc, mode, k, o);
    if (o->rc == RAY_OK && o->digest != ref->digest)
        fail("succeeded with different results", w, alloc, mode, k, o);
}

static long sweep(const workload *w, ray_alloc_fn alloc)
{
    outcome ref = run_once(w, alloc, 0, 0, 0), o;
    long k, injected = 0;
    int retry;

    if (ref.rc != RAY_OK || ref.leaked != 0 || ref.size_errors != 0) {
        fail("the clean run failed", w, alloc, "clean", 0, &ref);
        return 0;
    }
    /* src/image/image.c or src/image/png.c calling libpng through other functions
    ** than FAULT_WRAPS names would silently leave them out. */
    if (w->uses_png && ref.by_kind[FP_PNG] == 0)
        fail("no wrapped libpng call reached: add the library's libpng "
             "calls to FAULT_WRAPS (Makefile) and tests/faultsim.c",
             w, alloc, "clean", 0, &ref);
    for (k = 1; k <= ref.events; k++)
        for (retry = 0; retry <= 1; retry++) {
            o = run_once(w, alloc, retry, k, retry ? k : LONG_MAX);
            injected += o.injected;
            judge(w, alloc, retry, k, &o, &ref);
        }
    printf("faultsim: %-19s %s: %2ld fault points (%2ld memory, %ld libpng, "
           "%ld thread, %ld mutex), %3ld failures injected\n",
           w->name, alloc ? "hook" : "libc", ref.events,
           ref.by_kind[FP_MEMORY], ref.by_kind[FP_PNG],
           ref.by_kind[FP_THREAD], ref.by_kind[FP_MUTEX], injected);
    return injected;
}

/* The 16-bit texture the texture workload loads, and where PNGs go. */
static int setup(char *dir)
{
    float rgb[5 * 4 * 3];

    test_card(rgb, 5, 4);
    if (!test_make_dir(dir, 512, "faultsim"))
        return 0;
    snprintf(texture_path, sizeof texture_path, "%s/texture.png", dir);
    snprintf(output_path, sizeof output_path, "%s/out.png", dir);
#if RAY_TEST_PNG
    return ray_write_png(texture_path, rgb, 5, 4, 16) == RAY_OK;
#else
    printf("faultsim: built with PNG=0: the PNG workloads are left out\n");
    return ray_write_png(texture_path, rgb, 5, 4, 16) == RAY_ENOTSUP;
#endif
}

int main(void)
{
    char dir[512];
    long total = 0;
    size_t i;

    if (!setup(dir)) {
        fprintf(stderr, "faultsim: cannot make the test files in %s\n",
                test_tmpdir());
        return EXIT_FAILURE;
    }
    for (i = 0; i < sizeof workloads / sizeof *workloads; i++) {
        total += sweep(&workloads[i], NULL);
        if (workloads[i].uses_scene)
            total += sweep(&workloads[i], hook_alloc);
    }
    remove(texture_path);
    remove(output_path);
    rmdir(dir);
    printf("faultsim: %ld failures injected, %ld problems\n", total,
           failures);
    return failures == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
