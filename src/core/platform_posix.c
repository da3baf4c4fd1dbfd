/* SPDX-License-Identifier: MIT */
/*
** platform_posix.c -- platform.h on POSIX.1-2008: pthreads, sysconf,
** and open/write/fsync/rename for the safe write.  Only calls macOS has
** too (it is POSIX-certified); _SC_NPROCESSORS_ONLN, not in POSIX.1-2008
** but on every POSIX system in use, is asked for where the headers show
** it (macOS hides it under _POSIX_C_SOURCE unless _DARWIN_C_SOURCE).
** The Win32 branch is platform_win32.c; MinGW takes that one.
*/
#if !defined(_WIN32)

#if !defined(_POSIX_C_SOURCE)
#define _POSIX_C_SOURCE 200809L
#endif
#if defined(__APPLE__) && !defined(_DARWIN_C_SOURCE)
#define _DARWIN_C_SOURCE 1        /* _SC_NPROCESSORS_ONLN (see above) */
#endif
#if defined(__linux__) && !defined(_GNU_SOURCE)
#define _GNU_SOURCE 1             /* madvise, MADV_HUGEPAGE, mremap */
#endif

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/platform.h"

unsigned ray__online_cpus(void)
{
#if defined(_SC_NPROCESSORS_ONLN)
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 && n <= (long)UINT_MAX ? (unsigned)n : 1u;
#else
    return 1u;                    /* unknown: the calling thread alone */
#endif
}

/* ------------------------------------------------------------- memory */

/* A transparent huge page: x86-64's, arm64's. */
#define HUGE_PAGE ((size_t)1 << 21)

void ray__memory_hint(void *p, size_t size)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    const uintptr_t huge = HUGE_PAGE;
    uintptr_t lo = ((uintptr_t)p + huge - 1) & ~(huge - 1);
    uintptr_t hi = ((uintptr_t)p + size) & ~(huge - 1);

    if (hi > lo)
        (void)madvise((void *)lo, hi - lo, MADV_HUGEPAGE);  /* a hint */
#else
    (void)p;
    (void)size;
#endif
}

/* Large blocks on whole huge pages (ray__huge_realloc,
** RAY__WHOLE_HUGE_PAGES): Linux's headers declare what it calls. */
#if RAY__WHOLE_HUGE_PAGES && !defined(MADV_HUGEPAGE)
#error "Linux's sys/mman.h without MADV_HUGEPAGE"
#endif

#if RAY__WHOLE_HUGE_PAGES
/* A large block's length: "size" rounded up to whole huge pages; 0 where
** that, or the huge page more that huge_map asks for, overflows. */
static size_t huge_len(size_t size)
{
    return size > (size_t)-1 - 2 * HUGE_PAGE
               ? 0
               : (size + HUGE_PAGE - 1) & ~(HUGE_PAGE - 1);
}

/* A fresh mapping of "len" bytes (whole huge pages) at a huge page's
** boundary: a huge page more is mapped and the ends beyond the boundary
** given back. */
static void *huge_map(size_t len)
{
    char *raw = mmap(NULL, len + HUGE_PAGE, PROT_READ | PROT_WRITE,
                     MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    uintptr_t at;
    size_t head;

    if (raw == MAP_FAILED)
        return NULL;
    at = ((uintptr_t)raw + HUGE_PAGE - 1) & ~(uintptr_t)(HUGE_PAGE - 1);
    head = (size_t)(at - (uintptr_t)raw);
    if (head > 0)
        (void)munmap(raw, head);
    (void)munmap((char *)at + len, HUGE_PAGE - head);
    (void)madvise((void *)at, len, MADV_HUGEPAGE);          /* a hint */
    return (void *)at;
}

/*
** A large block of "olen" bytes (whole huge pages) made "nlen" long: its
** tail given back, or grown where it lies if the addresses after it are
** free (mremap without MREMAP_MAYMOVE, which fails changing nothing), so
** that what was touched stays touched; else copied to a fresh block.  Not
** moved with MREMAP_FIXED onto a fresh mapping: kernels before 6.12
** unmap the target before they check the move, which can then fail
** (a block grown so is two mappings, and they refuse to move two),
** leaving a hole that another thread's mapping may fill (review, issue
** 36).
*/
static void *huge_resize(void *p, size_t olen, size_t nlen)
{
    void *q;

    if (nlen <= olen) {
        if (nlen < olen)
            (void)munmap((char *)p + nlen, olen - nlen);
        return p;
    }
    if (mremap(p, olen, nlen, 0) != MAP_FAILED) {
        (void)madvise(p, nlen, MADV_HUGEPAGE);               /* a hint */
        return p;
    }
    if ((q = huge_map(nlen)) == NULL)
        return NULL;
    memcpy(q, p, olen);
    (void)munmap(p, olen);
    return q;
}

void *ray__huge_realloc(void *ptr, size_t osize, size_t nsize)
{
    const int was_large = ptr != NULL && osize >= RAY__HUGE_BLOCK;
    const int large = nsize >= RAY__HUGE_BLOCK;
    void *q;

    if (nsize == 0) {
        (void)munmap(ptr, huge_len(osize));
        return NULL;
    }
    if (large && huge_len(nsize) == 0)
        return NULL;                 /* too large for whole huge pages */
    if (was_large && large)
        return huge_resize(ptr, huge_len(osize), huge_len(nsize));
    /* Across RAY__HUGE_BLOCK: a block of the other kind, the contents
    ** copied (under 4 MiB of them). */
    q = large ? huge_map(huge_len(nsize)) : malloc(nsize);
    if (q == NULL || ptr == NULL)
        return q;
    memcpy(q, ptr, osize < nsize ? osize : nsize);
    if (was_large)
        (void)munmap(ptr, huge_len(osize));
    else
        free(ptr);
    return q;
}
#endif

/* ------------------------------------------------------------ threads */

/* A pthread_t is copied in and out of ray__thread.handle as bytes: a
** negative array size stops the build where it would not fit. */
typedef char ray__pthread_fits[
    sizeof(pthread_t) <= sizeof(((ray__thread *)0)->handle) ? 1 : -1];

static void *thread_main(void *arg)
{
    ray__thread *t = arg;

    t->fn(t->arg);
    return NULL;
}

int ray__thread_start(ray__thread *t, size_t stack)
{
    pthread_attr_t attr;
    pthread_t id;
    size_t have = 0;
    int rc;

    if (pthread_attr_init(&attr) != 0)
        return -1;
    /* A larger stack if the default is smaller (musl: 128 KiB); a failure
    ** to set it leaves the default, which only risks what it risked. */
    if (stack > 0 && pthread_attr_getstacksize(&attr, &have) == 0 &&
        have < stack)
        pthread_attr_setstacksize(&attr, stack);
    rc = pthread_create(&id, &attr, thread_main, t);
    pthread_attr_destroy(&attr);
    if (rc == 0)
        memcpy(t->handle.bytes, &id, sizeof id);
    return rc;
}

void ray__thread_join(ray__thread *t)
{
    pthread_t id;

    memcpy(&id, t->handle.bytes, sizeof id);
    pthread_join(id, NULL);
}

/* ------------------------------------------------------------ mutexes */

struct ray__mutex {
    pthread_mutex_t m;
};

int ray__mutex_new(const ray__allocator *a, ray__mutex **out)
{
    ray__mutex *m = ray__allocate(a, sizeof *m);

    if (m == NULL)
        return RAY_ENOMEM;
    if (pthread_mutex_init(&m->m, NULL) != 0) {
        ray__release(a, m, sizeof *m);
        return RAY_ENOMEM;        /* EAGAIN or ENOMEM: out of resources */
    }
    *out = m;
    return RAY_OK;
}

void ray__mutex_free(const ray__allocator *a, ray__mutex *m)
{
    if (m == NULL)
        return;
    pthread_mutex_destroy(&m->m);
    ray__release(a, m, sizeof *m);
}

void ray__mutex_lock(ray__mutex *m)
{
    pthread_mutex_lock(&m->m);
}

void ray__mutex_unlock(ray__mutex *m)
{
    pthread_mutex_unlock(&m->m);
}

struct ray__cond {
    pthread_cond_t c;
};

int ray__cond_new(const ray__allocator *a, ray__cond **out)
{
    ray__cond *c = ray__allocate(a, sizeof *c);

    if (c == NULL)
        return RAY_ENOMEM;
    if (pthread_cond_init(&c->c, NULL) != 0) {
        ray__release(a, c, sizeof *c);
        return RAY_ENOMEM;        /* EAGAIN or ENOMEM: out of resources */
    }
    *out = c;
    return RAY_OK;
}

void ray__cond_free(const ray__allocator *a, ray__cond *c)
{
    if (c == NULL)
        return;
    pthread_cond_destroy(&c->c);
    ray__release(a, c, sizeof *c);
}

void ray__cond_wait(ray__cond *c, ray__mutex *m)
{
    pthread_cond_wait(&c->c, &m->m);
}

void ray__cond_broadcast(ray__cond *c)
{
    pthread_cond_broadcast(&c->c);
}

/* -------------------------------------------------------------- files */

FILE *ray__file_open_read(const char *path)
{
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    FILE *fp;
    int saved_errno;

    if (fd < 0)
        return NULL;
    fp = fdopen(fd, "rb");
    if (fp == NULL) {
        saved_errno = errno;
        close(fd);
        errno = saved_errno;
    }
    return fp;
}

/* All of data to fd, through short writes and interruptions. */
static int write_all(int fd, const void *data, size_t size)
{
    const unsigned char *p = data;

    while (size > 0) {
        ssize_t n = write(fd, p, size);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            return -1;            /* write() sets errno (0 bytes: none) */
        p += n;
        size -= (size_t)n;
    }
    return 0;
}

/* close(), keeping an earlier failure's errno ("failed"), else
** reporting its own: -1 if either failed. */
static int close_keeping(int fd, int failed)
{
    int saved_errno = errno;
    int closed = close(fd) == 0;

    if (failed) {
        errno = saved_errno;
        return -1;
    }
    return closed ? 0 : -1;
}

/*
** A device or a FIFO (/dev/stdout into a pipe, /dev/null) is written in
** place: it cannot be replaced, and on failure nothing is removed.
** (A directory fails here too, at open: EISDIR.)
*/
static int write_in_place(const char *path, const void *data, size_t size)
{
    int fd = open(path, O_WRONLY | O_TRUNC | O_CLOEXEC);

    if (fd < 0)
        return RAY_EIO;
    if (close_keeping(fd, write_all(fd, data, size) != 0) != 0)
        return RAY_EIO;
    return RAY_OK;
}

/* Tries at a free temporary name: each EEXIST is another writer of the
** same path in this process, or the leftover of a crashed one. */
#define TEMP_ATTEMPTS 100
/* ".<pid>-<attempt>.tmp": a long's and an int's digits, signs, ".tmp". */
#define TEMP_SUFFIX_SIZE 48

/*
** A temporary file beside the target, "<path>.<pid>-<n>.tmp", created
** with O_EXCL (so two threads, or a planted file, never share it) and mode
** 0666 less the umask, as open would create the target itself; this
** avoids reading the umask, which only umask() can, by changing it for
** every thread.  Returns the descriptor, or -1 (errno set).
*/
static int create_temp(const char *target, char *temp, size_t size)
{
    int attempt, fd = -1;

    for (attempt = 0; attempt < TEMP_ATTEMPTS; attempt++) {
        snprintf(temp, size, "%s.%ld-%d.tmp", target, (long)getpid(),
                 attempt);
        fd = open(temp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0 || errno != EEXIST)
            break;
    }
    return fd;
}

/*
** A regular file, or none yet: write a temporary file, fsync it (a file
** renamed over another must be on the disk first, or a crash could leave
** an empty file where the old one was), and rename it over the target
** only then, so a failure leaves the old file as it was (rename is
** atomic, POSIX.1-2008 rename()).  An existing file's permission bits are
** kept (owner and group become the caller's).  On any failure only the
** temporary file is removed, with errno kept.
*/
static int write_replacing(const char *path, const struct stat *old,
                           const void *data, size_t size)
{
    size_t temp_size = strlen(path) + TEMP_SUFFIX_SIZE;
    char *temp = malloc(temp_size);
    int fd, failed, saved_errno;

    if (temp == NULL)
        return RAY_ENOMEM;
    fd = create_temp(path, temp, temp_size);
    if (fd < 0) {
        free(temp);
        return RAY_EIO;
    }
    failed = (old != NULL && fchmod(fd, old->st_mode & 0777) != 0) ||
             write_all(fd, data, size) != 0 || fsync(fd) != 0;
    failed = close_keeping(fd, failed) != 0 || rename(temp, path) != 0;
    if (failed) {
        saved_errno = errno;        /* unlink() must not hide the cause */
        unlink(temp);
        errno = saved_errno;
    }
    free(temp);
    return failed ? RAY_EIO : RAY_OK;
}

/*
** stat follows symbolic links: a link to a device is written through, a
** link to a regular file is replaced by the new file (the file it named
** is left as it was).
*/
int ray__file_write(const char *path, const void *data, size_t size)
{
    struct stat st;

    if (stat(path, &st) != 0)
        return write_replacing(path, NULL, data, size);
    if (S_ISREG(st.st_mode))
        return write_replacing(path, &st, data, size);
    return write_in_place(path, data, size);
}

#else
/* ISO C wants a translation unit to declare something. */
typedef int ray__platform_posix_unused;
#endif /* !_WIN32 */
