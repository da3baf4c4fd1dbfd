/* SPDX-License-Identifier: MIT */
/*
** platform.h -- what the library asks of the operating system beyond
** ISO C, in one place (doc/PLATFORMS.md): the CPUs, threads, a mutex,
** and the file calls of ray_write_png and ray_image_load_png.
**
** Two branches implement it: platform_posix.c (POSIX.1-2008, the calls
** macOS has too: pthreads, sysconf, open/fsync/rename) and
** platform_win32.c (Win32: _beginthreadex, SRWLOCK,
** GetActiveProcessorCount, CreateFileW/FlushFileBuffers/MoveFileExW),
** chosen by _WIN32, so that MinGW builds the branch MSVC gets, not
** winpthreads; platform_cpu.c asks the CPU itself (cpuid).  No other
** file of src/ includes a system header beyond ISO C's and the
** compiler's intrinsics (scripts/check-layers.sh checks it).
**
** What the library needs is small on purpose: its threads only start,
** take task numbers from a counter under a mutex, and are joined
** (core/tasks.c), so no condition variable and no once are needed.
** Nothing here keeps global state.
*/
#ifndef RAY_PLATFORM_H
#define RAY_PLATFORM_H

#include <stddef.h>
#include <stdio.h>

#include "core/alloc.h"

/* ------------------------------------------------------------ the CPU */

/* The CPUs online (at least 1): what a thread count of 0 means, for the
** threaded build, the photon pass and the render. */
unsigned ray__online_cpus(void);

/* 1 if the CPU has AVX2 and the operating system saves the AVX registers
** (platform_cpu.c), else 0; 0 on other CPUs.  It runs cpuid: callers
** keep the answer (the scene, at commit) rather than ask per query. */
int ray__cpu_has_avx2(void);

/* ------------------------------------------------------------- memory */

/*
** ray__huge_realloc -- for the allocator of a scene made without one
** (store.c, libc's otherwise), on Linux (RAY__WHOLE_HUGE_PAGES) only: a
** block that is, or becomes, RAY__HUGE_BLOCK bytes or more, as a
** ray_alloc_fn would give it (NULL ptr: a new one; nsize 0: freed).
** Such a block is mapped by itself (mmap) at a 2 MiB boundary, a whole
** number of 2 MiB long, and marked for transparent huge pages, so that
** it takes one page fault per 2 MiB: a block libc maps starts 16 bytes
** past a page and ends anywhere, its first and last partial 2 MiB small
** pages, about 3,000 faults a 940k-triangle build; and libc's aligned
** block (posix_memalign, the earlier way) wrote its headers on two pages
** of their own, two more faults a block.  It is known by its size
** (osize, which ray_alloc_fn promises): grown where it lies (mremap)
** when the addresses after it are free, else copied to a fresh one;
** shrunk by giving back its tail; freed with munmap.  Elsewhere, and under AddressSanitizer, not defined: libc's
** alone.
*/
void *ray__huge_realloc(void *ptr, size_t osize, size_t nsize);

/* Does ray__huge_realloc put large blocks on whole huge pages (Linux,
** not under AddressSanitizer: GCC's macro, Clang's feature test)? */
#if defined(__SANITIZE_ADDRESS__)
#define RAY__ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define RAY__ASAN 1
#endif
#endif
#if defined(__linux__) && !defined(RAY__ASAN)
#define RAY__WHOLE_HUGE_PAGES 1
#else
#define RAY__WHOLE_HUGE_PAGES 0
#endif

/* ------------------------------------------------------------ threads */

/*
** A thread the library started: "fn" runs with "arg" on it.  The struct
** is the caller's and must stay in place from ray__thread_start until
** ray__thread_join returns (the new thread reads fn and arg from it).
** "handle" holds the platform's own (a pthread_t, a HANDLE), copied in
** and out as bytes; each branch checks at compile time that it fits.
*/
typedef struct ray__thread {
    void (*fn)(void *arg);
    void *arg;
    union {
        void *ptr;
        unsigned long long word;
        unsigned char bytes[16];
    } handle;
} ray__thread;

/*
** Start t->fn(t->arg) on a new thread with at least "stack" bytes of
** stack (0: the platform's default).  Returns 0, or non-zero when no
** thread could be started (then nothing runs and nothing is to join).
*/
int ray__thread_start(ray__thread *t, size_t stack);

/* Wait for a started thread to return, and release it. */
void ray__thread_join(ray__thread *t);

/* ------------------------------------------------------------ mutexes */

/*
** A mutex, allocated through the caller's allocator (the scene's): its
** size is the platform's (pthread_mutex_t, SRWLOCK) and known only to
** its branch.  ray__mutex_new returns RAY_OK or RAY_ENOMEM (no memory,
** or the platform refused one); ray__mutex_free takes NULL.
*/
typedef struct ray__mutex ray__mutex;

int ray__mutex_new(const ray__allocator *a, ray__mutex **out);
void ray__mutex_free(const ray__allocator *a, ray__mutex *m);
void ray__mutex_lock(ray__mutex *m);
void ray__mutex_unlock(ray__mutex *m);

/*
** A condition variable, allocated as a mutex is (pthread_cond_t,
** CONDITION_VARIABLE): ray__cond_wait releases m (which the caller
** holds), sleeps until a broadcast (or spuriously: callers wait in a loop
** on their own condition) and takes m again.  ray__cond_new returns
** RAY_OK or RAY_ENOMEM; ray__cond_free takes NULL.
*/
typedef struct ray__cond ray__cond;

int ray__cond_new(const ray__allocator *a, ray__cond **out);
void ray__cond_free(const ray__allocator *a, ray__cond *c);
void ray__cond_wait(ray__cond *c, ray__mutex *m);
void ray__cond_broadcast(ray__cond *c);

/* -------------------------------------------------------------- files */

/*
** Paths are the caller's bytes on POSIX and UTF-8 on Windows (converted
** to UTF-16 for the wide calls, so any name works; a path that is not
** UTF-8 fails there with errno EILSEQ).
**
** ray__file_open_read -- the file opened for reading in binary mode, not
** inherited by child processes where the platform allows; NULL with
** errno set on failure.
**
** ray__file_write -- write "size" bytes as the file at "path", safely:
** a regular file (or none yet) is replaced only once the new one is
** complete and on the disk -- a temporary file beside it, flushed to the
** disk, then renamed over it (the rename replaces an existing file), so
** a failure leaves the old file as it was and no temporary file; on
** POSIX the old file's permission bits are kept.  A device or a pipe
** (/dev/null, a FIFO; NUL, \\.\pipe\name) is written in place.  Returns
** RAY_OK, RAY_ENOMEM, or RAY_EIO with errno saying why (EISDIR,
** ENOENT, EACCES, ENOSPC, EFBIG, EILSEQ...; the Win32 branch maps
** GetLastError's codes to these).
*/
FILE *ray__file_open_read(const char *path);
int ray__file_write(const char *path, const void *data, size_t size);

#endif /* RAY_PLATFORM_H */
