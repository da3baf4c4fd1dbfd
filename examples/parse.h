/* SPDX-License-Identifier: MIT */
/*
** parse.h -- what the examples' file readers (obj.h, bpt.h) share: the
** "line N: message" error they write into the caller's buffer.
** Header-only; not part of the library.
*/
#ifndef EXAMPLES_PARSE_H
#define EXAMPLES_PARSE_H

#include <stdarg.h>
#include <stddef.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* MinGW's isfinite, isnan, isinf and signbit choose a branch by the
** argument's type, and the float branch converts a double argument to
** float: -Wfloat-conversion at every use, for a branch never taken.
** GCC's builtins are the same tests (the library does the same in its
** src/core/vec.h).  Every example reaches this header (through common.h,
** obj.h or bpt.h) after <math.h>. */
#if defined(__MINGW32__) && defined(__GNUC__)
#undef isfinite
#define isfinite(x) __builtin_isfinite(x)
#undef isnan
#define isnan(x) __builtin_isnan(x)
#undef isinf
#define isinf(x) __builtin_isinf(x)
#undef signbit
#define signbit(x) __builtin_signbit(x)
#endif

/* Argument "f" is a printf format whose arguments start at "a" (0: a
** va_list), for the compiler to check; clang's -Wformat-nonliteral wants
** the va_list function marked too.  MinGW: by the rules of the printf its
** stdio.h chose (C99's with __USE_MINGW_ANSI_STDIO, else msvcrt's). */
#if defined(__MINGW32__) && defined(__GNUC__)
#define PARSE_PRINTF_LIKE(f, a) \
    __attribute__((format(__MINGW_PRINTF_FORMAT, f, a)))
#elif defined(__GNUC__)
#define PARSE_PRINTF_LIKE(f, a) __attribute__((format(printf, f, a)))
#else
#define PARSE_PRINTF_LIKE(f, a)
#endif

static inline int parse_vfail(char *err, size_t errlen, size_t line,
                              const char *fmt, va_list ap)
    PARSE_PRINTF_LIKE(4, 0);

/* Write "line N: <message>" into err[0 .. errlen-1] (cut to fit, always
** terminated when errlen > 0); returns -1, the readers' failure. */
static inline int parse_vfail(char *err, size_t errlen, size_t line,
                              const char *fmt, va_list ap)
{
    int n = snprintf(err, errlen, "line %zu: ", line);

    if (n >= 0 && (size_t)n < errlen)
        vsnprintf(err + n, errlen - (size_t)n, fmt, ap);
    return -1;
}

/*
** The whole file "path" in a buffer from realloc_fn (grown by doubling
** from 64 KiB: the usual model in one read; the caller frees it) into
** *text and *len.  0, or -1 with "path: reason" in err and nothing kept.
*/
static inline int parse_read_file(const char *path,
                                  void *(*realloc_fn)(void *, size_t),
                                  char **text_out, size_t *len_out,
                                  char *err, size_t errlen)
{
    const size_t first_chunk = 65536;
    FILE *f = fopen(path, "rb");
    char *text = NULL;
    size_t len = 0, cap = 0;
    int failed;

    if (f == NULL) {
        snprintf(err, errlen, "%s: %s", path, strerror(errno));
        return -1;
    }
    for (;;) {
        size_t got;
        if (len == cap) {
            size_t ncap = cap ? 2 * cap : first_chunk;
            char *t = cap > (size_t)-1 / 2 ? NULL : realloc_fn(text, ncap);
            if (t == NULL) {
                free(text);
                fclose(f);
                snprintf(err, errlen, "%s: out of memory", path);
                return -1;
            }
            text = t;
            cap = ncap;
        }
        got = fread(text + len, 1, cap - len, f);
        len += got;
        if (got == 0)
            break;
    }
    failed = ferror(f);
    fclose(f);
    if (failed) {
        free(text);
        snprintf(err, errlen, "%s: read error", path);
        return -1;
    }
    *text_out = text;
    *len_out = len;
    return 0;
}

/* "path: msg" into err; a long path may truncate it (snprintf still ends
** the string; on an encoding error the message is emptied). */
static inline void parse_error_at(char *err, size_t errlen, const char *path,
                                  const char *msg)
{
    if (snprintf(err, errlen, "%s: %s", path, msg) < 0 && errlen > 0)
        err[0] = '\0';
}

#endif
