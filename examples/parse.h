/*
** parse.h -- what the examples' file readers (obj.h, bpt.h) share: the
** "line N: message" error they write into the caller's buffer.
** Header-only; not part of the library.
*/
#ifndef EXAMPLES_PARSE_H
#define EXAMPLES_PARSE_H

#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>

/* Argument "f" is a printf format whose arguments start at "a" (0: a
** va_list), for the compiler to check; clang's -Wformat-nonliteral wants
** the va_list function marked too. */
#if defined(__GNUC__)
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

#endif
