/* SPDX-License-Identifier: MIT */
/*
** fuzz_winding.c -- ray_contains' winding number (issue 39): the fast
** one through the BVH (Barill et al.'s far-field expansions, winding.c)
** against the sum over every triangle (RAY_CONTAINS_WINDING_EXACT, how a
** caller asks for the number itself) and both against a long double sum
** (tests/winding_ref.h, shared with tests/check_contains.c), on meshes
** the input builds: a mesh of up to 32 triangles over up to 24 vertices
** on a lattice of sixteenths in [-8, 8)^3 (open or closed, cracks,
** flips, repeats and degenerate triangles alike), or a soup of up to 32
** small triangles, each within a cube of side 2 about a lattice point of
** its own; copied on a grid of up to 4 x
** 4 x 4 cells 1 to 16 apart (up to 2048 triangles: inner nodes of the
** BVH, and clusters that points see from afar, where the expansions are
** read); moved by 0, 1e5 or 1e6 and placed directly or through an
** instance that permutes, mirrors, doubles and moves the axes; up to 8
** points at lattice points, vertices, edge midpoints and centroids, or
** an ulp off them.  Every mesh is asked with RAY_CONTAINS_WINDING (every
** triangle by the winding number, closed or not).  Checked:
**
**   * the number asked for (RAY_CONTAINS_WINDING_EXACT) is within
**     WIND_TOL of the long double sum, off the edges (near_edge) and
**     within the predicates' range (in_range);
**   * the fast answer's inside is the exact one's wherever the exact
**     winding number is farther than FAST_ERR (ray.h's documented error
**     of the fast number) from 1/2, and its number within FAST_ERR of
**     the exact one; a fast number within 0.2 of 1/2 (ray_contains sums
**     those again exactly) is the exact one, bit for bit.
**
** The lattice keeps every difference of coordinates exact, at the
** offsets too (1e6 + k / 16 is a double), and the instances' maps take
** lattice points to lattice points exactly: so the library and the
** reference sum the same triangles, and the only differences are the
** rounding of the sums (and the expansions' error on the fast side).
*/
#include <string.h>

#include "fuzz.h"
#include "core/predicates.h"
#include "winding_ref.h"

#define MAX_POOL 24              /* a mesh's vertices */
#define MAX_T 32                 /* a mesh's or a soup's triangles */
#define MAX_COPIES 4             /* copies along each axis */
#define MAX_ALL_T (MAX_T * MAX_COPIES * MAX_COPIES * MAX_COPIES)
#define MAX_V (3 * MAX_ALL_T)
#define MAX_P 8

/* The number asked for: each of up to 2048 solid angles rounded in
** double within a few ulps of its size, at most 2 pi (atan2, sqrt and
** the sums: about 1e-15 each, 2e-12 in all, over 4 pi), and the
** reference's in long double, so 1e-9 (issue 39's target) holds with a
** margin of some 500 wherever every angle is well conditioned; near an
** edge an angle's condition number grows as size / distance
** (NEAR_EDGE). */
#define WIND_TOL 1e-9

/* The fast number's documented error (ray.h, ray_contains: within 5e-2
** of the exact sum, as measured). */
#define FAST_ERR 5e-2

/* The fast number within this of 1/2 is summed again exactly (contains.c,
** WINDING_MARGIN). */
#define RESUM_MARGIN 0.2

/* A point nearer an edge (its ends excluded) than this has an
** ill-conditioned winding number, not checked (its inside still is,
** where far from 1/2).  Farther, a triangle's angle, of size up to 28
** (a pattern's diagonal), is conditioned at most 28 / 1.6e-4 = 2e5:
** 2e-11 of error for each of the triangles along the edge (up to 32:
** a pattern repeating one triangle), 6e-10 in all, within WIND_TOL. */
#define NEAR_EDGE (1e-5 * 16)

/* Whether x lies in the predicates' exact range (ray.h: about 2^-480 ..
** 2^480, here with margin): a zero coordinate moved an ulp is a
** subnormal, whose differences' squares underflow in the solid angle's
** lengths (a point 1e-323 from a vertex at the origin). */
static int in_range(double x)
{
    double a = fabs(x);

    return a == 0 || (a >= 0x1p-100 && a <= 0x1p100);
}

/* Lattice coordinate from one byte: a sixteenth in [-8, 8). */
static double lattice(fuzz_input *in)
{
    return ((double)fuzz_u8(in) - 128) / 16;
}

/* A soup's corner about its triangle's centre: a sixteenth in [-1, 1]. */
static double near_corner(fuzz_input *in)
{
    return ((double)fuzz_below(in, 33) - 16) / 16;
}

/* The instance maps: a permutation of the axes (how % 3), a mirror of x
** (how & 4), a scale of 2 (how & 8), and a move by a lattice vector:
** exact on lattice points at every offset. */
static void instance_map(unsigned how, ray_vec3 move, ray_transform *t)
{
    int p = (int)(how % 3), i;
    double s = (how & 8) ? 2 : 1;

    memset(t, 0, sizeof *t);
    for (i = 0; i < 3; i++)
        t->m[i][(i + p) % 3] = s;
    if (how & 4)
        t->m[0][p] = -s;
    t->m[0][3] = move.x;
    t->m[1][3] = move.y;
    t->m[2][3] = move.z;
}

static ray_vec3 map_point(const ray_transform *t, ray_vec3 v)
{
    const double (*m)[4] = t->m;

    return ray_vec3_make(m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z + m[0][3],
                         m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z + m[1][3],
                         m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z + m[2][3]);
}

/* Whether q lies within NEAR_EDGE of an edge of triangles idx over w,
** its ends excluded (at a vertex every angle that meets it is 0). */
static int near_edge(const ray_vec3 *w, const unsigned *idx, size_t nt,
                     ray_vec3 q)
{
    size_t i;
    int k;

    for (i = 0; i < nt; i++)
        for (k = 0; k < 3; k++) {
            ray_vec3 a = w[idx[3 * i + (size_t)k]];
            ray_vec3 b = w[idx[3 * i + (size_t)(k + 1) % 3]];
            long double ab[3] = {(long double)b.x - (long double)a.x, (long double)b.y - (long double)a.y,
                                 (long double)b.z - (long double)a.z};
            long double aq[3] = {(long double)q.x - (long double)a.x, (long double)q.y - (long double)a.y,
                                 (long double)q.z - (long double)a.z};
            long double ll = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
            long double t, d2 = 0;
            int j;
            if (ll == 0)
                continue;
            t = (aq[0] * ab[0] + aq[1] * ab[1] + aq[2] * ab[2]) / ll;
            if (!(t > 0 && t < 1))
                continue;
            for (j = 0; j < 3; j++) {
                long double e = aq[j] - t * ab[j];
                d2 += e * e;
            }
            if (d2 < (long double)NEAR_EDGE * (long double)NEAR_EDGE)
                return 1;
        }
    return 0;
}

/* One point from the input: a lattice point, a vertex, an edge's
** midpoint or a triangle's centroid (of the mesh as stored, in its own
** space), then left as it is or moved an ulp up or down on every axis. */
static ray_vec3 point_of(fuzz_input *in, const ray_vec3 *v, size_t nv,
                         const unsigned *idx, size_t nt, ray_vec3 off)
{
    unsigned kind = fuzz_below(in, 4), nudge;
    ray_vec3 p;

    if (kind == 0) {
        p.x = off.x + lattice(in);
        p.y = off.y + lattice(in);
        p.z = off.z + lattice(in);
    } else if (kind == 1) {
        p = v[fuzz_below(in, (unsigned)nv)];
    } else {
        const unsigned *t = idx + 3 * fuzz_below(in, (unsigned)nt);
        ray_vec3 a = v[t[0]], b = v[t[1]], c = v[t[2]];
        if (kind == 2)
            p = ray_vec3_make((a.x + b.x) / 2, (a.y + b.y) / 2, (a.z + b.z) / 2);
        else
            p = ray_vec3_make((a.x + b.x + c.x) / 3, (a.y + b.y + c.y) / 3,
                              (a.z + b.z + c.z) / 3);
    }
    nudge = fuzz_below(in, 3);
    if (nudge > 0) {
        double to = nudge == 1 ? HUGE_VAL : -HUGE_VAL;
        p = ray_vec3_make(nextafter(p.x, to), nextafter(p.y, to),
                          nextafter(p.z, to));
    }
    return p;
}

/* The scene: the mesh itself, or a scene holding it through instance t. */
static ray_scene *scene_of(const ray_vec3 *v, size_t nv, const unsigned *idx,
                           size_t nt, const ray_transform *t,
                           ray_scene **child)
{
    ray_scene *s = NULL, *top = NULL;
    ray_mesh m;

    *child = NULL;
    memset(&m, 0, sizeof m);
    m.vertices = v;
    m.vertex_count = nv;
    m.indices = idx;
    m.triangle_count = nt;
    if (ray_scene_new(&s, NULL, NULL) != RAY_OK)
        return NULL;
    if (ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, NULL) != RAY_OK ||
        ray_scene_commit(s) != RAY_OK) {
        ray_scene_free(s);
        return NULL;
    }
    if (t == NULL)
        return s;
    if (ray_scene_new(&top, NULL, NULL) != RAY_OK ||
        ray_scene_add_instance(top, s, t, NULL) != RAY_OK ||
        ray_scene_commit(top) != RAY_OK) {
        ray_scene_free(top);
        ray_scene_free(s);
        return NULL;
    }
    *child = s;
    return top;
}

/* The pattern the input spells (a mesh over a pool of lattice vertices,
** or a soup of small triangles), copied on a grid of up to 4 x 4 x 4
** cells of a lattice spacing (up to 2048 triangles: inner nodes of the
** BVH, and clusters that points see from afar). */
typedef struct pattern {
    ray_vec3 v[MAX_V];
    unsigned idx[3 * MAX_ALL_T];
    size_t nv, nt;
} pattern;

static void pattern_of(fuzz_input *in, ray_vec3 off, pattern *m)
{
    int soup = fuzz_below(in, 2) == 1;
    size_t nv = 3 + fuzz_below(in, MAX_POOL - 2);
    size_t nt = 1 + fuzz_below(in, MAX_T), i, k;
    unsigned copies[3], cx, cy, cz;
    double spacing;

    for (k = 0; k < 3; k++)
        copies[k] = 1 + fuzz_below(in, MAX_COPIES);
    spacing = 1 + fuzz_below(in, 16);
    if (soup) {
        nv = 3 * nt;
        for (i = 0; i < nt; i++) {
            ray_vec3 c;
            c.x = off.x + lattice(in);
            c.y = off.y + lattice(in);
            c.z = off.z + lattice(in);
            for (k = 3 * i; k < 3 * i + 3; k++) {
                m->v[k].x = c.x + near_corner(in);
                m->v[k].y = c.y + near_corner(in);
                m->v[k].z = c.z + near_corner(in);
                m->idx[k] = (unsigned)k;
            }
        }
    } else {
        for (i = 0; i < nv; i++) {
            m->v[i].x = off.x + lattice(in);
            m->v[i].y = off.y + lattice(in);
            m->v[i].z = off.z + lattice(in);
        }
        for (i = 0; i < 3 * nt; i++)
            m->idx[i] = fuzz_below(in, (unsigned)nv);
    }
    m->nv = nv;
    m->nt = nt;
    for (cz = 0; cz < copies[2]; cz++)
        for (cy = 0; cy < copies[1]; cy++)
            for (cx = 0; cx < copies[0]; cx++) {
                size_t v0 = m->nv, t0 = m->nt;
                if (cx + cy + cz == 0)
                    continue;
                for (i = 0; i < nv; i++) {
                    m->v[v0 + i].x = m->v[i].x + cx * spacing;
                    m->v[v0 + i].y = m->v[i].y + cy * spacing;
                    m->v[v0 + i].z = m->v[i].z + cz * spacing;
                }
                for (i = 0; i < 3 * nt; i++)
                    m->idx[3 * t0 + i] = m->idx[i] + (unsigned)v0;
                m->nv += nv;
                m->nt += nt;
            }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const double offsets[3] = {0, 1e5, 1e6};
    static pattern m;
    static ray_vec3 w[MAX_V];
    fuzz_input in = fuzz_input_of(data, size);
    ray_vec3 p[MAX_P], pw[MAX_P], off, move;
    ray_inside fast[MAX_P], exact[MAX_P];
    ray_contains_options of = {0}, oe = {0};
    ray_transform t;
    ray_scene *s, *child;
    double o = offsets[fuzz_below(&in, 3)];
    unsigned how = fuzz_below(&in, 32);
    size_t np, i;
    int rf, re;

    off = ray_vec3_make(o, -0.4 * o, 0.9 * o);
    pattern_of(&in, off, &m);
    /* The instance (how >= 16) moves the mesh back by its offset and
    ** forward by a lattice vector, so world space is at the offset too. */
    move = ray_vec3_make(lattice(&in), lattice(&in), lattice(&in));
    if (how >= 16) {
        ray_transform back;
        ray_vec3 b;
        instance_map(how, ray_vec3_make(0, 0, 0), &back);
        b = map_point(&back, off);
        move = ray_vec3_make(off.x - b.x + move.x, off.y - b.y + move.y,
                             off.z - b.z + move.z);
        instance_map(how, move, &t);
    }
    for (i = 0; i < m.nv; i++)
        w[i] = how >= 16 ? map_point(&t, m.v[i]) : m.v[i];
    np = 1 + fuzz_below(&in, MAX_P);
    for (i = 0; i < np; i++) {
        p[i] = point_of(&in, m.v, m.nv, m.idx, m.nt, off);
        pw[i] = how >= 16 ? map_point(&t, p[i]) : p[i];
    }
    s = scene_of(m.v, m.nv, m.idx, m.nt, how >= 16 ? &t : NULL, &child);
    if (s == NULL)
        return 0;
    of.flags = RAY_CONTAINS_WINDING;
    oe.flags = RAY_CONTAINS_WINDING | RAY_CONTAINS_WINDING_EXACT;
    rf = ray_contains(s, pw, np, &of, fast);
    re = ray_contains(s, pw, np, &oe, exact);
    FUZZ_CHECK(rf >= 0 && re >= 0, "ray_contains: the winding number answers");
    for (i = 0; i < np; i++) {
        double we = exact[i].winding, wf = fast[i].winding;
        FUZZ_CHECK(exact[i].inside == (we > 0.5) && fast[i].inside == (wf > 0.5),
                   "ray_contains: inside where the winding number exceeds 1/2");
        if (in_range(pw[i].x) && in_range(pw[i].y) && in_range(pw[i].z) &&
            !near_edge(w, m.idx, m.nt, pw[i]))
            FUZZ_CHECK(fabs(we - winding_ref_sum(w, m.idx, m.nt, pw[i])) <= WIND_TOL,
                       "ray_contains: the number asked for, within 1e-9 of "
                       "the long double sum");
        if (fabs(we - 0.5) > FAST_ERR)
            FUZZ_CHECK(fast[i].inside == exact[i].inside,
                       "ray_contains: the fast answer is the exact one away "
                       "from 1/2");
        FUZZ_CHECK(fabs(wf - we) <= FAST_ERR,
                   "ray_contains: the fast number within its documented error");
        if (fabs(wf - 0.5) < RESUM_MARGIN)
            FUZZ_CHECK(memcmp(&wf, &we, sizeof wf) == 0,
                       "ray_contains: near 1/2, the exact sum");
    }
    ray_scene_free(s);
    ray_scene_free(child);
    return 0;
}
