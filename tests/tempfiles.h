/* SPDX-License-Identifier: MIT */
/*
** tempfiles.h -- where the tests put their files, on POSIX and on
** Windows (doc/PLATFORMS.md): the temporary directory (/tmp; %TEMP% on
** Windows, which has no /tmp) and a fresh private directory in it
** (mkdtemp; _mkdir on a name of the process id and a counter where
** there is no mkdtemp).  Test code, not the library's: it may include
** the platform's headers.
*/
#ifndef RAY_TEMPFILES_H
#define RAY_TEMPFILES_H

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>

#if defined(_WIN32)
#include <direct.h>
#include <process.h>
#else
#include <unistd.h>
#endif

/* The directory temporary files go in, without a trailing separator. */
static inline const char *test_tmpdir(void)
{
#if defined(_WIN32)
    const char *t = getenv("TEMP");
    if (t == NULL || t[0] == '\0')
        t = getenv("TMP");
    return t != NULL && t[0] != '\0' ? t : ".";
#else
    return "/tmp";
#endif
}

/* "<tmpdir>/<name>" into buf. */
static inline void test_tmp_path(char *buf, size_t size, const char *name)
{
    snprintf(buf, size, "%s/%s", test_tmpdir(), name);
}

/* A fresh directory "<tmpdir>/libray-<tag>-..." of this test's own, its
** name into dir; 1, or 0 if none could be made. */
static inline int test_make_dir(char *dir, size_t size, const char *tag)
{
#if defined(_WIN32)
    int k;

    for (k = 0; k < 1000; k++) {
        snprintf(dir, size, "%s/libray-%s-%d-%d", test_tmpdir(), tag,
                 _getpid(), k);
        if (_mkdir(dir) == 0)
            return 1;
        if (errno != EEXIST)
            return 0;
    }
    return 0;
#else
    snprintf(dir, size, "%s/libray-%s-XXXXXX", test_tmpdir(), tag);
    return mkdtemp(dir) != NULL;
#endif
}

#endif /* RAY_TEMPFILES_H */
