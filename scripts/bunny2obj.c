/* SPDX-License-Identifier: MIT */
/*
** bunny2obj.c -- turn the npm package "bunny" (index.js: exports.positions
** = [[x,y,z],...]; exports.cells = [[i,j,k],...], 0-based) into a
** Wavefront OBJ, with every triangle split into four L times (midpoints
** of edges shared between neighbours, so the mesh stays closed).
**
**     bunny2obj index.js L > bunny.obj      (L = 0: 3,674 triangles,
**                                            2: 58,784, 4: 940,544)
** A build tool for scripts/fetch-bunny.sh; not part of the library.
*/
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct vec {
    double x, y, z;
} vec;

static vec *verts;
static size_t n_verts, cap_verts;
static unsigned *tris;
static size_t n_tris;

static void die(const char *msg)
{
    fprintf(stderr, "bunny2obj: %s\n", msg);
    exit(1);
}

static unsigned add_vert(vec v)
{
    if (n_verts == cap_verts) {
        cap_verts = cap_verts ? 2 * cap_verts : 4096;
        verts = realloc(verts, cap_verts * sizeof *verts);
        if (verts == NULL)
            die("out of memory");
    }
    verts[n_verts] = v;
    return (unsigned)n_verts++;
}

/* Read the numbers of the array that follows "key" in text. */
static double *numbers_after(const char *text, const char *key, size_t *n)
{
    const char *p = strstr(text, key);
    size_t cap = 1 << 16;
    double *out = malloc(cap * sizeof *out);
    int depth = 0;

    if (p == NULL || out == NULL)
        die("array not found");
    p = strchr(p, '[');
    *n = 0;
    for (; p != NULL && *p; p++) {
        if (*p == '[')
            depth++;
        else if (*p == ']') {
            if (--depth == 0)
                break;
        } else if ((*p >= '0' && *p <= '9') || *p == '-' || *p == '.') {
            char *end;
            double v = strtod(p, &end);
            if (*n == cap) {
                cap *= 2;
                out = realloc(out, cap * sizeof *out);
                if (out == NULL)
                    die("out of memory");
            }
            out[(*n)++] = v;
            p = end - 1;
        }
    }
    return out;
}

/* Edge midpoint cache: open addressing on (min, max) vertex pairs. */
typedef struct edge {
    unsigned a, b, mid;
} edge;

static unsigned midpoint(edge *table, size_t size, unsigned a, unsigned b)
{
    unsigned lo = a < b ? a : b, hi = a < b ? b : a;
    size_t h = ((size_t)lo * 2654435761u ^ (size_t)hi * 40503u) % size;
    vec m;

    while (table[h].mid != 0xffffffffu) {
        if (table[h].a == lo && table[h].b == hi)
            return table[h].mid;
        h = (h + 1) % size;
    }
    m.x = 0.5 * (verts[lo].x + verts[hi].x);
    m.y = 0.5 * (verts[lo].y + verts[hi].y);
    m.z = 0.5 * (verts[lo].z + verts[hi].z);
    table[h].a = lo;
    table[h].b = hi;
    table[h].mid = add_vert(m);
    return table[h].mid;
}

static void subdivide(void)
{
    size_t size = 4 * 3 * n_tris + 1, i;
    edge *table = malloc(size * sizeof *table);
    unsigned *out = malloc(4 * 3 * n_tris * sizeof *out);

    if (table == NULL || out == NULL)
        die("out of memory");
    for (i = 0; i < size; i++)
        table[i].mid = 0xffffffffu;
    for (i = 0; i < n_tris; i++) {
        unsigned a = tris[3 * i], b = tris[3 * i + 1], c = tris[3 * i + 2];
        unsigned ab = midpoint(table, size, a, b);
        unsigned bc = midpoint(table, size, b, c);
        unsigned ca = midpoint(table, size, c, a);
        unsigned *t = out + 12 * i;
        t[0] = a;  t[1] = ab; t[2] = ca;
        t[3] = ab; t[4] = b;  t[5] = bc;
        t[6] = ca; t[7] = bc; t[8] = c;
        t[9] = ab; t[10] = bc; t[11] = ca;
    }
    free(table);
    free(tris);
    tris = out;
    n_tris *= 4;
}

int main(int argc, char **argv)
{
    FILE *f;
    char *text;
    long len;
    double *pos, *cells;
    size_t np, nc, i;
    int level;

    if (argc != 3)
        die("usage: bunny2obj index.js LEVEL");
    level = atoi(argv[2]);
    f = fopen(argv[1], "rb");
    if (f == NULL || fseek(f, 0, SEEK_END) != 0 || (len = ftell(f)) < 0)
        die("cannot read input");
    rewind(f);
    text = malloc((size_t)len + 1);
    if (text == NULL || fread(text, 1, (size_t)len, f) != (size_t)len)
        die("cannot read input");
    text[len] = '\0';
    fclose(f);
    pos = numbers_after(text, "positions", &np);
    cells = numbers_after(text, "cells", &nc);
    for (i = 0; i + 2 < np; i += 3) {
        vec v = {pos[i], pos[i + 1], pos[i + 2]};
        add_vert(v);
    }
    n_tris = nc / 3;
    tris = malloc(nc * sizeof *tris);
    if (tris == NULL)
        die("out of memory");
    for (i = 0; i < nc; i++) {
        if (cells[i] < 0 || cells[i] >= (double)n_verts)
            die("index out of range");
        tris[i] = (unsigned)cells[i];
    }
    while (level-- > 0)
        subdivide();
    printf("# Stanford bunny (npm package bunny), %zu triangles\n", n_tris);
    for (i = 0; i < n_verts; i++)
        printf("v %.9g %.9g %.9g\n", verts[i].x, verts[i].y, verts[i].z);
    for (i = 0; i < n_tris; i++)
        printf("f %u %u %u\n", tris[3 * i] + 1, tris[3 * i + 1] + 1,
               tris[3 * i + 2] + 1);
    return 0;
}
