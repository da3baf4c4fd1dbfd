/* SPDX-License-Identifier: MIT */
/*
** bpt.h -- a reader for Bezier patch files in the "Newell" text format of
** the Utah teapot (scripts/fetch-teapot.sh writes data/teapot.bpt):
**
**     32                                   the number of patches
**     1, 2, 3, 4, 5, 6, ..., 16            per patch, 16 1-based vertex
**     ...                                  indices: 4 rows of 4 points
**     290                                  the number of vertices
**     1.4, 0, 2.4                          per vertex, x, y, z
**     ...
**
** Blanks and tabs may surround the commas; blank lines are skipped; CRLF
** line ends are accepted.  Each patch comes out as 16 ray_vec3 in the
** file's order, row by row, which is the layout of ray_bezier_surface and
** ray_scene_add_bezier (cp[4*i + j], j along u).  Not part of the library.
** Header-only; every function is static.
**
** Malformed input is an error naming the line, never a crash: missing,
** non-positive or too large counts, a patch line without exactly 16
** indices, an index 0 or above the vertex count, a vertex line without
** exactly 3 numbers, non-numeric or non-finite numbers, text after a
** field or after the last vertex, a file that ends early, and allocation
** failures.
**
** BPT_REALLOC (default realloc) may be defined before the #include to
** test allocation failures; what it returns is released with free().
*/
#ifndef EXAMPLES_BPT_H
#define EXAMPLES_BPT_H

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <ray.h>

#include "parse.h"

#ifndef BPT_REALLOC
#define BPT_REALLOC realloc
#endif

/* A patch: its 16 control points, row i (along v) at 4*i, column j (along
** u) at + j, as ray_scene_add_bezier takes them. */
typedef ray_vec3 bpt_patch[16];

/* The patches of a file (the array owned here). */
typedef struct bpt_patches {
    bpt_patch *patches;
    size_t count;
    size_t vertex_count;     /* the file's control points, for reports */
} bpt_patches;

/*
** Counts above this are "too many": the teapot has 32 patches and 290
** vertices, finer models a few thousand.  A million patches is 384 MB of
** control points, so the bound keeps a corrupt count from asking for
** absurd memory, and every size computed from a count far from overflow.
*/
#define BPT_MAX_COUNT 1000000L

/* Longest line accepted: 16 indices of 7 digits, or 3 numbers in full
** precision (17 digits, sign, exponent), fit many times over. */
#define BPT_LINE_MAX 4096

/* A patch as read: its indices, and its line for the later range check. */
typedef struct bpt_patch_ref {
    unsigned index[16];      /* 1-based; the upper bound is checked once
                                the vertex count is known */
    size_t line;
} bpt_patch_ref;

typedef struct bpt_parser {
    const char *text;
    size_t len, pos;         /* pos: the start of the next line */
    size_t line;             /* the number of the line in buf */
    char buf[BPT_LINE_MAX];
    bpt_patch_ref *refs;
    ray_vec3 *vertices;
    size_t patch_count, vertex_count;   /* as the file declares them */
    size_t refs_cap, vertices_cap;      /* as allocated */
    char *err;
    size_t errlen;
} bpt_parser;

/* The compiler checks bpt_fail's format strings like printf's. */
static inline int bpt_fail(bpt_parser *p, const char *fmt, ...)
    PARSE_PRINTF_LIKE(2, 3);

/* Write "line N: <message>" into the caller's buffer; returns -1. */
static inline int bpt_fail(bpt_parser *p, const char *fmt, ...)
{
    va_list ap;
    int rc;

    va_start(ap, fmt);
    rc = parse_vfail(p->err, p->errlen, p->line, fmt, ap);
    va_end(ap);
    return rc;
}

static inline int bpt_is_blank(char c)
{
    return c == ' ' || c == '\t' || c == '\r';
}

static inline const char *bpt_skip_blanks(const char *s)
{
    while (bpt_is_blank(*s))
        s++;
    return s;
}

/*
** An array of "size"-byte elements "data" with room for *cap, grown so
** that it holds at least one more, up to "limit" (<= BPT_MAX_COUNT, so no
** product overflows).  Growing by doubling rather than to the declared
** count at once means a count that lies costs memory only as far as lines
** actually come.  The new array, or NULL (then data is untouched).
*/
static inline void *bpt_grow(void *data, size_t *cap, size_t limit,
                             size_t size)
{
    /* The first block: the teapot's 32 patches fit, with room to spare. */
    size_t ncap = *cap ? 2 * *cap : 64;
    void *grown;

    if (ncap > limit)
        ncap = limit;
    grown = BPT_REALLOC(data, ncap * size);
    if (grown != NULL)
        *cap = ncap;
    return grown;
}

/*
** Read the next line that is not blank into p->buf.  Returns 1, or 0 at
** the end of the text (then p->line is the line after the last, where
** the missing text was expected), or -1 for a line too long or with a
** NUL byte.
*/
static inline int bpt_next_line(bpt_parser *p)
{
    while (p->pos < p->len) {
        size_t start = p->pos, end = start;
        while (end < p->len && p->text[end] != '\n')
            end++;
        p->pos = end + 1;
        p->line++;
        if (end - start >= sizeof p->buf)
            return bpt_fail(p, "line longer than %d bytes", BPT_LINE_MAX - 1);
        if (memchr(p->text + start, '\0', end - start) != NULL)
            return bpt_fail(p, "NUL byte in text");
        memcpy(p->buf, p->text + start, end - start);
        p->buf[end - start] = '\0';
        if (*bpt_skip_blanks(p->buf) != '\0')
            return 1;
    }
    p->line++;
    return 0;
}

/* The next line, which must exist: "what" names what it should hold. */
static inline int bpt_expect_line(bpt_parser *p, const char *what)
{
    int rc = bpt_next_line(p);

    if (rc == 0)
        return bpt_fail(p, "file ends where %s was expected", what);
    return rc < 0 ? -1 : 0;
}

/* The same for item k (from 0) of "count" "what"s (patches, vertices). */
static inline int bpt_expect_item(bpt_parser *p, const char *what, size_t k,
                                  size_t count)
{
    int rc = bpt_next_line(p);

    if (rc == 0)
        return bpt_fail(p, "file ends where %s %zu of %zu was expected",
                        what, k + 1, count);
    return rc < 0 ? -1 : 0;
}

/*
** A decimal integer at *s (after blanks) into *out, saturated to
** +-(BPT_MAX_COUNT + 1) so callers can say "too large" without overflow.
** -1 (nothing reported) if *s does not start with one.
*/
static inline int bpt_integer(const char **s, long *out)
{
    const char *c = bpt_skip_blanks(*s);
    int negative = 0;
    long value = 0;

    if (*c == '+' || *c == '-')
        negative = *c++ == '-';
    if (*c < '0' || *c > '9')
        return -1;
    for (; *c >= '0' && *c <= '9'; c++)
        if (value <= BPT_MAX_COUNT)
            value = 10 * value + (*c - '0');
    if (value > BPT_MAX_COUNT)
        value = BPT_MAX_COUNT + 1;
    *out = negative ? -value : value;
    *s = c;
    return 0;
}

/* A line holding just a count of "what" (patches or vertices). */
static inline int bpt_parse_count(bpt_parser *p, const char *what,
                                  size_t *out)
{
    const char *number = bpt_skip_blanks(p->buf), *s = number, *rest;
    long n;

    if (bpt_integer(&s, &n) != 0)
        return bpt_fail(p, "expected the number of %s, found '%.20s'", what,
                        number);
    rest = bpt_skip_blanks(s);
    if (*rest == ',')
        return bpt_fail(p, "expected the number of %s, found a list (the "
                        "count missing, or more lines than a count said?)",
                        what);
    if (*rest != '\0')
        return bpt_fail(p, "text after the number of %s: '%.20s'", what,
                        rest);
    /* The number as written: saturated, n may not be. */
    if (n <= 0)
        return bpt_fail(p, "the number of %s must be positive, not %.*s",
                        what, (int)(s - number), number);
    if (n > BPT_MAX_COUNT)
        return bpt_fail(p, "too many %s (more than %ld)", what,
                        BPT_MAX_COUNT);
    *out = (size_t)n;
    return 0;
}

/*
** Before field k (from 0) of a line of "total" comma-separated "what"s:
** a comma (k > 0), then something that is not the end of the line.
*/
static inline int bpt_field_start(bpt_parser *p, const char **s, int k,
                                  int total, const char *what)
{
    *s = bpt_skip_blanks(*s);
    if (k > 0) {
        if (**s == '\0')
            return bpt_fail(p, "expected %d %s, found %d", total, what, k);
        if (**s != ',')
            return bpt_fail(p, "expected ',' after field %d, found '%.20s'",
                            k, *s);
        *s = bpt_skip_blanks(*s + 1);
    }
    if (**s == '\0')
        return bpt_fail(p, "expected %d %s, found %d", total, what, k);
    return 0;
}

/* After the last of "total" fields: nothing but blanks. */
static inline int bpt_line_end(bpt_parser *p, const char *s, int total,
                               const char *what)
{
    s = bpt_skip_blanks(s);
    if (*s == ',')
        return bpt_fail(p, "more than %d %s", total, what);
    if (*s != '\0')
        return bpt_fail(p, "text after the %s: '%.20s'", what, s);
    return 0;
}

/* A patch line: 16 indices of at least 1 (the upper bound is checked
** once the vertex count is known). */
static inline int bpt_parse_patch(bpt_parser *p, unsigned *indices)
{
    const char *s = p->buf;
    int k;

    for (k = 0; k < 16; k++) {
        const char *field;
        long index;
        if (bpt_field_start(p, &s, k, 16, "vertex indices"))
            return -1;
        field = s;
        if (bpt_integer(&s, &index) != 0 || *s == '.' || *s == 'e' ||
            *s == 'E')
            return bpt_fail(p, "field %d: not an integer: '%.20s'", k + 1,
                            field);
        if (index < 1)
            return bpt_fail(p, "vertex index %.*s (indices start at 1)",
                            (int)(s - field), field);
        if (index > BPT_MAX_COUNT)
            return bpt_fail(p, "vertex index out of range (more than %ld)",
                            BPT_MAX_COUNT);
        indices[k] = (unsigned)index;
    }
    return bpt_line_end(p, s, 16, "vertex indices");
}

/* A vertex line: 3 finite numbers. */
static inline int bpt_parse_vertex(bpt_parser *p, ray_vec3 *v)
{
    const char *s = p->buf;
    double x[3];
    int k;

    for (k = 0; k < 3; k++) {
        char *end;
        if (bpt_field_start(p, &s, k, 3, "coordinates"))
            return -1;
        x[k] = strtod(s, &end);
        if (end == s)
            return bpt_fail(p, "field %d: not a number: '%.20s'", k + 1, s);
        if (!isfinite(x[k]))
            return bpt_fail(p, "field %d: not finite: '%.20s'", k + 1, s);
        s = end;
    }
    v->x = x[0];
    v->y = x[1];
    v->z = x[2];
    return bpt_line_end(p, s, 3, "coordinates");
}

static inline int bpt_parse_patches(bpt_parser *p)
{
    size_t k;

    if (bpt_expect_line(p, "the number of patches") ||
        bpt_parse_count(p, "patches", &p->patch_count))
        return -1;
    for (k = 0; k < p->patch_count; k++) {
        if (bpt_expect_item(p, "patch", k, p->patch_count))
            return -1;
        if (k == p->refs_cap) {
            void *grown = bpt_grow(p->refs, &p->refs_cap, p->patch_count,
                                   sizeof *p->refs);
            if (grown == NULL)
                return bpt_fail(p, "out of memory");
            p->refs = grown;
        }
        if (bpt_parse_patch(p, p->refs[k].index))
            return -1;
        p->refs[k].line = p->line;
    }
    return 0;
}

static inline int bpt_parse_vertices(bpt_parser *p)
{
    size_t k;
    int rc;

    if (bpt_expect_line(p, "the number of vertices") ||
        bpt_parse_count(p, "vertices", &p->vertex_count))
        return -1;
    for (k = 0; k < p->vertex_count; k++) {
        if (bpt_expect_item(p, "vertex", k, p->vertex_count))
            return -1;
        if (k == p->vertices_cap) {
            void *grown = bpt_grow(p->vertices, &p->vertices_cap,
                                   p->vertex_count, sizeof *p->vertices);
            if (grown == NULL)
                return bpt_fail(p, "out of memory");
            p->vertices = grown;
        }
        if (bpt_parse_vertex(p, &p->vertices[k]))
            return -1;
    }
    rc = bpt_next_line(p);
    if (rc > 0)
        return bpt_fail(p, "text after the last vertex (more vertices than "
                           "the count said?)");
    return rc;
}

/* Every index names a vertex; an error names the patch's line. */
static inline int bpt_check_indices(bpt_parser *p)
{
    size_t k;
    int c;

    for (k = 0; k < p->patch_count; k++)
        for (c = 0; c < 16; c++)
            if (p->refs[k].index[c] > p->vertex_count) {
                p->line = p->refs[k].line;
                return bpt_fail(p, "vertex index %u out of range (%zu "
                                "vertices)", p->refs[k].index[c],
                                p->vertex_count);
            }
    return 0;
}

/* The patches' control points, looked up from the indices. */
static inline int bpt_build(bpt_parser *p, bpt_patches *out)
{
    size_t k;
    int c;

    /* patch_count <= BPT_MAX_COUNT: the size cannot overflow. */
    out->patches = BPT_REALLOC(NULL, p->patch_count * sizeof *out->patches);
    if (out->patches == NULL) {
        p->line = 0;
        return bpt_fail(p, "out of memory");
    }
    for (k = 0; k < p->patch_count; k++)
        for (c = 0; c < 16; c++)
            out->patches[k][c] = p->vertices[p->refs[k].index[c] - 1];
    out->count = p->patch_count;
    out->vertex_count = p->vertex_count;
    return 0;
}

static inline void bpt_free(bpt_patches *b)
{
    free(b->patches);
    memset(b, 0, sizeof *b);
}

/*
** Parse "len" bytes of patch-file text.  Returns 0 and fills *out, or -1
** with a message "line N: ..." in err (*out then empty; bpt_free on it is
** harmless).
*/
static inline int bpt_parse(const char *text, size_t len, bpt_patches *out,
                            char *err, size_t errlen)
{
    bpt_parser p;
    int rc;

    memset(&p, 0, sizeof p);
    p.text = text;
    p.len = len;
    p.err = err;
    p.errlen = errlen;
    if (errlen > 0)
        err[0] = '\0';
    memset(out, 0, sizeof *out);
    rc = bpt_parse_patches(&p);
    if (rc == 0)
        rc = bpt_parse_vertices(&p);
    if (rc == 0)
        rc = bpt_check_indices(&p);
    if (rc == 0)
        rc = bpt_build(&p, out);
    free(p.refs);
    free(p.vertices);
    return rc;
}

/* Read and parse a file; on error err says "PATH: line N: ..." (or
** "PATH: <strerror>" if it cannot be read). */
static inline int bpt_load(const char *path, bpt_patches *out, char *err,
                           size_t errlen)
{
    char *text, msg[512];
    size_t len;
    int rc;

    memset(out, 0, sizeof *out);
    if (parse_read_file(path, BPT_REALLOC, &text, &len, err, errlen) != 0)
        return -1;
    rc = bpt_parse(text, len, out, msg, sizeof msg);
    free(text);
    if (rc != 0)
        parse_error_at(err, errlen, path, msg);
    return rc;
}

/* The box lo .. hi of every control point of b (b->count > 0): by the
** convex hull property it holds the surface. */
static inline void bpt_bounds(const bpt_patches *b, ray_vec3 *lo,
                              ray_vec3 *hi)
{
    ray_vec3 low = b->patches[0][0], high = low;
    size_t k;
    int c;

    for (k = 0; k < b->count; k++)
        for (c = 0; c < 16; c++) {
            ray_vec3 v = b->patches[k][c];
            low.x = fmin(low.x, v.x);
            low.y = fmin(low.y, v.y);
            low.z = fmin(low.z, v.z);
            high.x = fmax(high.x, v.x);
            high.y = fmax(high.y, v.y);
            high.z = fmax(high.z, v.z);
        }
    *lo = low;
    *hi = high;
}

#endif
