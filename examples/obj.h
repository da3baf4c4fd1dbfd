/* SPDX-License-Identifier: MIT */
/*
** obj.h -- a small Wavefront OBJ reader for the examples, the benchmarks
** and the tests: v, vt, vn and f (polygons fan-triangulated; v, v/t,
** v//n, v/t/n corners; negative indices count back from the last element
** defined).  Other statements (o, g, s, usemtl, mtllib, l, p) are ignored.
** Not part of the library.  Header-only; every function is static.
**
** Malformed input is an error naming the line, never a crash: bad or
** missing numbers, non-finite numbers, index 0, out-of-range indices,
** faces of fewer than 3 corners, and allocation failures.
*/
#ifndef EXAMPLES_OBJ_H
#define EXAMPLES_OBJ_H

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <ray.h>

#include "parse.h"

/* A mesh ready for ray_scene_add_mesh (arrays owned here). */
typedef struct obj_mesh {
    ray_vec3 *vertices;
    size_t vertex_count;
    unsigned *indices;
    size_t triangle_count;
    ray_vec3 *normals;       /* NULL if no face corner names a normal */
    double *texcoords;       /* NULL if no face corner names a (s, t) */
} obj_mesh;

/* A growable array of "elem"-byte elements. */
typedef struct obj_array {
    void *data;
    size_t count, cap, elem;
} obj_array;

static inline int obj_push(obj_array *a, const void *item)
{
    if (a->count == a->cap) {
        size_t ncap = a->cap ? 2 * a->cap : 64;
        void *p;
        if (ncap > (size_t)-1 / a->elem)
            return -1;
        p = realloc(a->data, ncap * a->elem);
        if (p == NULL)
            return -1;
        a->data = p;
        a->cap = ncap;
    }
    memcpy((char *)a->data + a->count * a->elem, item, a->elem);
    a->count++;
    return 0;
}

/* One face corner: 0-based indices into v, vt, vn; (size_t)-1 = none. */
typedef struct obj_corner {
    size_t v, t, n;
} obj_corner;

#define OBJ_NONE ((size_t)-1)

typedef struct obj_parser {
    obj_array v, vt, vn, corners;    /* corners: 3 per triangle */
    size_t line;
    char *err;
    size_t errlen;
} obj_parser;

/* The compiler checks obj_fail's format strings like printf's. */
static inline int obj_fail(obj_parser *p, const char *fmt, ...)
    PARSE_PRINTF_LIKE(2, 3);

static inline int obj_fail(obj_parser *p, const char *fmt, ...)
{
    va_list ap;
    int rc;

    va_start(ap, fmt);
    rc = parse_vfail(p->err, p->errlen, p->line, fmt, ap);
    va_end(ap);
    return rc;
}

/* Parse "count" finite numbers from *s (spaces/tabs between). */
static inline int obj_numbers(obj_parser *p, const char **s, double *out,
                              int count, int optional_from)
{
    int i;

    for (i = 0; i < count; i++) {
        char *end;
        while (**s == ' ' || **s == '\t')
            (*s)++;
        if (**s == '\0' || **s == '\n' || **s == '\r' || **s == '#') {
            if (i >= optional_from) {
                out[i] = 0.0;
                continue;
            }
            return obj_fail(p, "expected %d numbers, found %d", count, i);
        }
        errno = 0;
        out[i] = strtod(*s, &end);
        if (end == *s || (*end != '\0' && *end != ' ' && *end != '\t' &&
                          *end != '\n' && *end != '\r' && *end != '#'))
            return obj_fail(p, "not a number: '%.20s'", *s);
        if (!isfinite(out[i]))
            return obj_fail(p, "number out of range: '%.20s'", *s);
        *s = end;
    }
    return 0;
}

/* An index field of a corner: 1-based, or negative counting back. */
static inline int obj_index(obj_parser *p, const char **s, size_t defined,
                            const char *what, size_t *out)
{
    char *end;
    long long k;

    errno = 0;
    k = strtoll(*s, &end, 10);
    if (end == *s)
        return obj_fail(p, "bad %s index: '%.20s'", what, *s);
    if (errno == ERANGE)
        return obj_fail(p, "%s index out of range", what);
    *s = end;
    if (k == 0)
        return obj_fail(p, "%s index 0 (OBJ indices start at 1)", what);
    if (k > 0 && (unsigned long long)k <= defined)
        *out = (size_t)(k - 1);
    else if (k < 0 && (unsigned long long)(-(k + 1)) < defined)
        *out = defined - (size_t)(-k);
    else
        return obj_fail(p, "%s index %lld out of range (%zu defined so far)",
                        what, k, defined);
    return 0;
}

/* One corner "v", "v/t", "v//n" or "v/t/n". */
static inline int obj_parse_corner(obj_parser *p, const char **s,
                                   obj_corner *c)
{
    c->t = c->n = OBJ_NONE;
    if (obj_index(p, s, p->v.count, "vertex", &c->v))
        return -1;
    if (**s != '/')
        return 0;
    (*s)++;
    if (**s != '/' && obj_index(p, s, p->vt.count, "texture", &c->t))
        return -1;
    if (**s != '/')
        return 0;
    (*s)++;
    return obj_index(p, s, p->vn.count, "normal", &c->n);
}

/* "f c1 c2 c3 ...": a polygon, fanned into triangles (c1, ci, ci+1). */
static inline int obj_parse_face(obj_parser *p, const char *s)
{
    obj_corner first = {0, 0, 0}, prev = {0, 0, 0}, c;
    int n = 0;

    for (;;) {
        while (*s == ' ' || *s == '\t')
            s++;
        if (*s == '\0' || *s == '\n' || *s == '\r' || *s == '#')
            break;
        if (obj_parse_corner(p, &s, &c))
            return -1;
        if (*s != '\0' && *s != ' ' && *s != '\t' && *s != '\n' &&
            *s != '\r' && *s != '#')
            return obj_fail(p, "bad face corner near '%.20s'", s);
        if (n == 0)
            first = c;
        else if (n >= 2) {
            if (obj_push(&p->corners, &first) || obj_push(&p->corners, &prev) ||
                obj_push(&p->corners, &c))
                return obj_fail(p, "out of memory");
        }
        prev = c;
        n++;
    }
    if (n < 3)
        return obj_fail(p, "a face needs 3 corners, found %d", n);
    return 0;
}

/* "x y z" (of a "v" or "vn" line) appended to array a as a ray_vec3. */
static inline int obj_parse_vec3(obj_parser *p, const char *s, obj_array *a)
{
    double x[3];
    ray_vec3 v;

    if (obj_numbers(p, &s, x, 3, 3))
        return -1;
    v.x = x[0];
    v.y = x[1];
    v.z = x[2];
    return obj_push(a, &v) ? obj_fail(p, "out of memory") : 0;
}

static inline int obj_parse_line(obj_parser *p, const char *s)
{
    double x[3];

    while (*s == ' ' || *s == '\t')
        s++;
    if (s[0] == 'v' && (s[1] == ' ' || s[1] == '\t'))
        return obj_parse_vec3(p, s + 1, &p->v);
    if (s[0] == 'v' && s[1] == 't' && (s[2] == ' ' || s[2] == '\t')) {
        s += 2;
        if (obj_numbers(p, &s, x, 2, 1))        /* t may be omitted */
            return -1;
        return obj_push(&p->vt, x) ? obj_fail(p, "out of memory") : 0;
    }
    if (s[0] == 'v' && s[1] == 'n' && (s[2] == ' ' || s[2] == '\t'))
        return obj_parse_vec3(p, s + 2, &p->vn);
    if (s[0] == 'f' && (s[1] == ' ' || s[1] == '\t'))
        return obj_parse_face(p, s + 1);
    return 0;                               /* comments and the rest */
}

/*
** Turn the corners into a mesh.  Without texture coordinates or normals a
** corner is its position, so the positions are the vertices.  Otherwise
** every corner gets its own vertex (no attempt to share: the examples do
** not need it, and the meshes stay exact).
*/
static inline int obj_build(obj_parser *p, obj_mesh *m)
{
    const obj_corner *c = p->corners.data;
    size_t n = p->corners.count, i;
    int has_t = 0, has_n = 0;

    memset(m, 0, sizeof *m);
    for (i = 0; i < n; i++) {
        has_t |= c[i].t != OBJ_NONE;
        has_n |= c[i].n != OBJ_NONE;
    }
    if (n / 3 > 0xffffffffu || p->v.count > 0xffffffffu)
        return -1;
    m->triangle_count = n / 3;
    m->indices = malloc((n ? n : 1) * sizeof *m->indices);
    if (m->indices == NULL)
        return -1;
    if (!has_t && !has_n) {
        m->vertices = p->v.data;
        m->vertex_count = p->v.count;
        p->v.data = NULL;
        for (i = 0; i < n; i++)
            m->indices[i] = (unsigned)c[i].v;
        return 0;
    }
    m->vertex_count = n;
    m->vertices = malloc((n ? n : 1) * sizeof *m->vertices);
    m->normals = has_n ? malloc((n ? n : 1) * sizeof *m->normals) : NULL;
    m->texcoords = has_t ? malloc((n ? 2 * n : 1) * sizeof *m->texcoords)
                         : NULL;
    if (m->vertices == NULL || (has_n && m->normals == NULL) ||
        (has_t && m->texcoords == NULL))
        return -1;
    for (i = 0; i < n; i++) {
        const ray_vec3 *pv = p->v.data, *pn = p->vn.data;
        const double *pt = p->vt.data;
        m->indices[i] = (unsigned)i;
        m->vertices[i] = pv[c[i].v];
        if (has_n) {
            ray_vec3 zero = {0, 0, 0};
            m->normals[i] = c[i].n != OBJ_NONE ? pn[c[i].n] : zero;
        }
        if (has_t) {
            m->texcoords[2 * i] = c[i].t != OBJ_NONE ? pt[2 * c[i].t] : 0;
            m->texcoords[2 * i + 1] = c[i].t != OBJ_NONE ? pt[2 * c[i].t + 1] : 0;
        }
    }
    return 0;
}

static inline void obj_free(obj_mesh *m)
{
    free(m->vertices);
    free(m->indices);
    free(m->normals);
    free(m->texcoords);
    memset(m, 0, sizeof *m);
}

/*
** Parse "len" bytes of OBJ text.  Returns 0 and fills *m, or -1 with a
** message "line N: ..." in err.  A file without faces is an error.
*/
static inline int obj_parse(const char *text, size_t len, obj_mesh *m,
                            char *err, size_t errlen)
{
    obj_parser p;
    size_t start = 0;
    int rc = 0;

    memset(&p, 0, sizeof p);
    p.v.elem = sizeof(ray_vec3);
    p.vt.elem = 2 * sizeof(double);
    p.vn.elem = sizeof(ray_vec3);
    p.corners.elem = sizeof(obj_corner);
    p.err = err;
    p.errlen = errlen;
    memset(m, 0, sizeof *m);
    while (rc == 0 && start < len) {
        size_t end = start;
        char line[4096];
        while (end < len && text[end] != '\n')
            end++;
        p.line++;
        if (end - start >= sizeof line)
            rc = obj_fail(&p, "line longer than %zu bytes", sizeof line - 1);
        else if (memchr(text + start, '\0', end - start) != NULL)
            rc = obj_fail(&p, "NUL byte in text");
        else {
            memcpy(line, text + start, end - start);
            line[end - start] = '\0';
            rc = obj_parse_line(&p, line);
        }
        start = end + 1;
    }
    if (rc == 0 && p.corners.count == 0) {
        p.line = 0;
        rc = obj_fail(&p, "no faces");
    }
    if (rc == 0 && obj_build(&p, m) != 0) {
        obj_free(m);
        rc = obj_fail(&p, "out of memory");
    }
    free(p.v.data);
    free(p.vt.data);
    free(p.vn.data);
    free(p.corners.data);
    return rc;
}

/* Read and parse a file; on error err says "PATH: line N: ...". */
static inline int obj_load(const char *path, obj_mesh *m, char *err,
                           size_t errlen)
{
    char *text, msg[512];
    size_t len;
    int rc;

    if (parse_read_file(path, realloc, &text, &len, err, errlen) != 0)
        return -1;
    rc = obj_parse(text, len, m, msg, sizeof msg);
    free(text);
    if (rc != 0)
        parse_error_at(err, errlen, path, msg);
    return rc;
}

/*
** The mesh's bounding box lo .. hi, its centre and the length of its
** diagonal (for framing a camera).  m must have a vertex.
*/
static inline void obj_bounds(const obj_mesh *m, ray_vec3 *lo, ray_vec3 *hi,
                              ray_vec3 *centre, double *diag)
{
    ray_vec3 a = m->vertices[0], b = a;
    size_t i;

    for (i = 1; i < m->vertex_count; i++) {
        ray_vec3 v = m->vertices[i];
        a.x = fmin(a.x, v.x);
        a.y = fmin(a.y, v.y);
        a.z = fmin(a.z, v.z);
        b.x = fmax(b.x, v.x);
        b.y = fmax(b.y, v.y);
        b.z = fmax(b.z, v.z);
    }
    *lo = a;
    *hi = b;
    centre->x = (a.x + b.x) / 2;
    centre->y = (a.y + b.y) / 2;
    centre->z = (a.z + b.z) / 2;
    *diag = sqrt((b.x - a.x) * (b.x - a.x) + (b.y - a.y) * (b.y - a.y) +
                 (b.z - a.z) * (b.z - a.z));
}

/* The mesh as ray_scene_add_mesh takes it. */
static inline ray_mesh obj_as_ray_mesh(const obj_mesh *m)
{
    ray_mesh r;

    memset(&r, 0, sizeof r);    /* zero is every field's default, those
                                   added later included */
    r.vertices = m->vertices;
    r.vertex_count = m->vertex_count;
    r.indices = m->indices;
    r.triangle_count = m->triangle_count;
    r.normals = m->normals;
    r.texcoords = m->texcoords;
    return r;
}

#endif
