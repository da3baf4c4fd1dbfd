/* SPDX-License-Identifier: MIT */
/*
** platform_win32.c -- platform.h on Windows (Windows 7 and later):
** _beginthreadex, SRWLOCK, GetActiveProcessorCount, and the wide file
** calls (CreateFileW, FlushFileBuffers, MoveFileExW) with UTF-8 paths.
** MSVC and MinGW both build this branch (MinGW would otherwise reach
** winpthreads through pthread.h), so the one tested under Wine is the
** one MSVC users get.  The POSIX branch is platform_posix.c.
*/
#if defined(_WIN32)

/* GetActiveProcessorCount is Windows 7's (0x0601); SRWLOCK, Vista's. */
#if defined(_WIN32_WINNT)
#if _WIN32_WINNT < 0x0601
#undef _WIN32_WINNT
#define _WIN32_WINNT 0x0601
#endif
#else
#define _WIN32_WINNT 0x0601
#endif
#define WIN32_LEAN_AND_MEAN
#include <windows.h>
#include <process.h>

#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include "core/platform.h"

unsigned ray__online_cpus(void)
{
    /* Every processor group's: a thread may run in any of them (Windows
    ** 11 spreads a process's threads over the groups; before that, a
    ** count past the first group's 64 only means idle threads). */
    DWORD n = GetActiveProcessorCount(ALL_PROCESSOR_GROUPS);
    return n > 0 && n <= UINT_MAX ? (unsigned)n : 1u;
}

/* ------------------------------------------------------------ threads */

/* A HANDLE is a pointer: it fits ray__thread.handle.ptr. */
typedef char ray__handle_fits[
    sizeof(HANDLE) <= sizeof(((ray__thread *)0)->handle) ? 1 : -1];

void ray__memory_hint(void *p, size_t size)
{
    (void)p;                      /* large pages need a privilege there */
    (void)size;
}

static unsigned __stdcall thread_main(void *arg)
{
    ray__thread *t = arg;

    t->fn(t->arg);
    return 0;
}

/*
** _beginthreadex, not CreateThread: the C runtime sets up its per-thread
** data (errno, the locale) for threads it starts.  The stack size is a
** reservation (STACK_SIZE_PARAM_IS_A_RESERVATION): address space, not
** committed memory, as on POSIX.
*/
int ray__thread_start(ray__thread *t, size_t stack)
{
    unsigned size = stack <= UINT_MAX ? (unsigned)stack : UINT_MAX;
    uintptr_t h = _beginthreadex(NULL, size, thread_main, t,
                                 stack > 0 ? STACK_SIZE_PARAM_IS_A_RESERVATION
                                           : 0, NULL);

    if (h == 0)
        return -1;
    t->handle.ptr = (void *)h;
    return 0;
}

void ray__thread_join(ray__thread *t)
{
    HANDLE h = (HANDLE)t->handle.ptr;

    WaitForSingleObject(h, INFINITE);
    CloseHandle(h);
}

/* ------------------------------------------------------------ mutexes */

/* A slim reader/writer lock, taken exclusively: it needs no destruction
** and cannot fail to initialise. */
struct ray__mutex {
    SRWLOCK lock;
};

int ray__mutex_new(const ray__allocator *a, ray__mutex **out)
{
    ray__mutex *m = ray__allocate(a, sizeof *m);

    if (m == NULL)
        return RAY_ENOMEM;
    InitializeSRWLock(&m->lock);
    *out = m;
    return RAY_OK;
}

void ray__mutex_free(const ray__allocator *a, ray__mutex *m)
{
    ray__release(a, m, sizeof *m);
}

void ray__mutex_lock(ray__mutex *m)
{
    AcquireSRWLockExclusive(&m->lock);
}

void ray__mutex_unlock(ray__mutex *m)
{
    ReleaseSRWLockExclusive(&m->lock);
}

/* Vista's condition variable, on the SRW lock taken exclusively: it too
** needs no destruction and cannot fail to initialise. */
struct ray__cond {
    CONDITION_VARIABLE c;
};

int ray__cond_new(const ray__allocator *a, ray__cond **out)
{
    ray__cond *c = ray__allocate(a, sizeof *c);

    if (c == NULL)
        return RAY_ENOMEM;
    InitializeConditionVariable(&c->c);
    *out = c;
    return RAY_OK;
}

void ray__cond_free(const ray__allocator *a, ray__cond *c)
{
    ray__release(a, c, sizeof *c);
}

void ray__cond_wait(ray__cond *c, ray__mutex *m)
{
    (void)SleepConditionVariableSRW(&c->c, &m->lock, INFINITE, 0);
}

void ray__cond_broadcast(ray__cond *c)
{
    WakeAllConditionVariable(&c->c);
}

/* -------------------------------------------------------------- files */

/* GetLastError's codes as errno's, for the callers of ray_write_png
** (ray.h: RAY_EIO, "see errno"): the codes the calls below give. */
static int errno_of(DWORD error)
{
    switch (error) {
    case ERROR_FILE_NOT_FOUND:
    case ERROR_PATH_NOT_FOUND:
    case ERROR_INVALID_DRIVE:
    case ERROR_BAD_NETPATH:
    case ERROR_BAD_NET_NAME:
    case ERROR_INVALID_NAME:
        return ENOENT;
    case ERROR_ACCESS_DENIED:
    case ERROR_SHARING_VIOLATION:
    case ERROR_LOCK_VIOLATION:
    case ERROR_CURRENT_DIRECTORY:
        return EACCES;
    case ERROR_WRITE_PROTECT:
        return EROFS;
    case ERROR_FILE_EXISTS:
    case ERROR_ALREADY_EXISTS:
        return EEXIST;
    case ERROR_DISK_FULL:
    case ERROR_HANDLE_DISK_FULL:
        return ENOSPC;
    case ERROR_FILENAME_EXCED_RANGE:
        return ENAMETOOLONG;
    case ERROR_NOT_ENOUGH_MEMORY:
    case ERROR_OUTOFMEMORY:
        return ENOMEM;
    case ERROR_BROKEN_PIPE:
    case ERROR_NO_DATA:
        return EPIPE;
    case ERROR_DIRECTORY:
        return ENOTDIR;
    case ERROR_INVALID_PARAMETER:
        return EINVAL;
    default:
        return EIO;
    }
}

/* errno from the last failed Win32 call; the status to return. */
static int failed_with(DWORD error)
{
    errno = errno_of(error);
    return RAY_EIO;
}

/*
** A UTF-8 string as a new UTF-16 one (malloc'd), or NULL with errno:
** EILSEQ if it is not UTF-8 (MB_ERR_INVALID_CHARS), ENOMEM.
*/
static wchar_t *widen(const char *s)
{
    int n = MultiByteToWideChar(CP_UTF8, MB_ERR_INVALID_CHARS, s, -1,
                                NULL, 0);
    wchar_t *w;

    if (n <= 0) {
        errno = GetLastError() == ERROR_NO_UNICODE_TRANSLATION ? EILSEQ
                                                               : EINVAL;
        return NULL;
    }
    w = malloc((size_t)n * sizeof *w);
    if (w == NULL) {
        errno = ENOMEM;
        return NULL;
    }
    MultiByteToWideChar(CP_UTF8, MB_ERR_INVALID_CHARS, s, -1, w, n);
    return w;
}

/* The status of a failed widen(). */
static int widen_failed(void)
{
    return errno == ENOMEM ? RAY_ENOMEM : RAY_EIO;
}

/* "N": not inherited by child processes, as O_CLOEXEC on POSIX. */
FILE *ray__file_open_read(const char *path)
{
    wchar_t *w = widen(path);
    FILE *fp;
    int saved_errno;

    if (w == NULL)
        return NULL;
    fp = _wfopen(w, L"rbN");
    saved_errno = errno;
    free(w);
    errno = saved_errno;
    return fp;
}

/* All of data to h, in pieces WriteFile's DWORD can count. */
static int write_all(HANDLE h, const void *data, size_t size)
{
    const unsigned char *p = data;

    while (size > 0) {
        DWORD piece = size > (1u << 30) ? (1u << 30) : (DWORD)size, n = 0;
        if (!WriteFile(h, p, piece, &n, NULL) || n == 0)
            return 0;
        p += n;
        size -= n;
    }
    return 1;
}

/*
** A device or a pipe (NUL, \\.\pipe\name) is written in place through
** the handle that found it: it cannot be replaced, and on failure nothing
** is removed.  No FlushFileBuffers: on a pipe it would wait for the
** reader to read everything.
*/
static int write_in_place(HANDLE h, const void *data, size_t size)
{
    DWORD error = write_all(h, data, size) ? ERROR_SUCCESS : GetLastError();

    if (!CloseHandle(h) && error == ERROR_SUCCESS)
        error = GetLastError();
    return error == ERROR_SUCCESS ? RAY_OK : failed_with(error);
}

/* Tries at a free temporary name: each collision is another writer of
** the same path in this process, or the leftover of a crashed one. */
#define TEMP_ATTEMPTS 100
/* ".<pid>-<attempt>.tmp": a DWORD's and an int's digits, ".tmp". */
#define TEMP_SUFFIX_SIZE 48

/*
** A temporary file beside the target, "<path>.<pid>-<n>.tmp", created
** with CREATE_NEW (so two threads, or a planted file, never share it),
** not shared while it is written.  Returns its handle and its wide name
** (*wtemp, malloc'd), or INVALID_HANDLE_VALUE with *status set.
*/
static HANDLE create_temp(const char *target, wchar_t **wtemp, int *status)
{
    size_t size = strlen(target) + TEMP_SUFFIX_SIZE;
    char *temp = malloc(size);
    HANDLE h = INVALID_HANDLE_VALUE;
    int attempt;

    *wtemp = NULL;
    *status = RAY_ENOMEM;
    if (temp == NULL)
        return h;
    for (attempt = 0; attempt < TEMP_ATTEMPTS; attempt++) {
        DWORD error;
        snprintf(temp, size, "%s.%lu-%d.tmp", target,
                 (unsigned long)GetCurrentProcessId(), attempt);
        *wtemp = widen(temp);
        if (*wtemp == NULL) {
            *status = widen_failed();
            break;
        }
        h = CreateFileW(*wtemp, GENERIC_WRITE, 0, NULL, CREATE_NEW,
                        FILE_ATTRIBUTE_NORMAL, NULL);
        if (h != INVALID_HANDLE_VALUE)
            break;
        error = GetLastError();
        free(*wtemp);
        *wtemp = NULL;
        *status = failed_with(error);
        if (error != ERROR_FILE_EXISTS && error != ERROR_ALREADY_EXISTS)
            break;
    }
    free(temp);
    return h;
}

/*
** A regular file, or none yet: write a temporary file, flush it to the
** disk (FlushFileBuffers: a file moved over another must be on the disk
** first), and move it over the target only then, replacing it
** (MOVEFILE_REPLACE_EXISTING; WRITE_THROUGH: MoveFileExW returns once
** the move is on the disk), so a failure leaves the old file as it was.
** The new file has the directory's default security, as a new file has.
** On any failure only the temporary file is removed, with errno kept.
*/
static int write_replacing(const char *path, const wchar_t *wpath,
                           const void *data, size_t size)
{
    wchar_t *wtemp;
    int rc;
    HANDLE h = create_temp(path, &wtemp, &rc);
    DWORD error = ERROR_SUCCESS;

    if (h == INVALID_HANDLE_VALUE)
        return rc;
    if (!write_all(h, data, size) || !FlushFileBuffers(h))
        error = GetLastError();
    if (!CloseHandle(h) && error == ERROR_SUCCESS)
        error = GetLastError();
    if (error == ERROR_SUCCESS &&
        !MoveFileExW(wtemp, wpath,
                     MOVEFILE_REPLACE_EXISTING | MOVEFILE_WRITE_THROUGH))
        error = GetLastError();
    rc = RAY_OK;
    if (error != ERROR_SUCCESS) {
        DeleteFileW(wtemp);
        rc = failed_with(error);
    }
    free(wtemp);
    return rc;
}

/*
** What is at the path decides, as stat does on POSIX: the path is opened
** as it stands (OPEN_EXISTING) and GetFileType says whether it is a file
** on a disk (replaced) or a device or pipe (written in place, through
** that handle).  No file: a new one.  A directory refuses to open, and
** is named so (EISDIR).  A file that cannot be opened for writing (in
** use, read-only) is left to the replacement, which fails the same way
** or, where the directory allows it, replaces it.
*/
static int write_wide(const char *path, const wchar_t *w, const void *data,
                      size_t size)
{
    HANDLE h = CreateFileW(w, GENERIC_WRITE,
                           FILE_SHARE_READ | FILE_SHARE_WRITE |
                               FILE_SHARE_DELETE,
                           NULL, OPEN_EXISTING, FILE_ATTRIBUTE_NORMAL, NULL);
    DWORD error, attributes;

    if (h != INVALID_HANDLE_VALUE) {
        if (GetFileType(h) != FILE_TYPE_DISK)
            return write_in_place(h, data, size);
        CloseHandle(h);
        return write_replacing(path, w, data, size);
    }
    error = GetLastError();
    if (error == ERROR_FILE_NOT_FOUND)
        return write_replacing(path, w, data, size);
    attributes = GetFileAttributesW(w);
    if (attributes != INVALID_FILE_ATTRIBUTES &&
        (attributes & FILE_ATTRIBUTE_DIRECTORY)) {
        errno = EISDIR;
        return RAY_EIO;
    }
    if (error == ERROR_ACCESS_DENIED || error == ERROR_SHARING_VIOLATION)
        return write_replacing(path, w, data, size);
    return failed_with(error);
}

int ray__file_write(const char *path, const void *data, size_t size)
{
    wchar_t *w = widen(path);
    int rc, saved_errno;

    if (w == NULL)
        return widen_failed();
    rc = write_wide(path, w, data, size);
    saved_errno = errno;
    free(w);
    errno = saved_errno;
    return rc;
}

#else
/* ISO C wants a translation unit to declare something. */
typedef int ray__platform_win32_unused;
#endif /* _WIN32 */
