/* SPDX-License-Identifier: MIT */
/*
** parity.c -- the closed meshes' part of ray_contains: the parity of the
** crossings of the ray from q along +x with their triangles, exactly,
** and the grid of labels that answers most points without a ray.
**
** The ray.  Every crossing is decided by exact predicates
** (core/predicates.c) with the ray perturbed symbolically: q' = q + (0,
** e, e^2) for an infinitesimal e (Edelsbrunner and Muecke, "Simulation
** of Simplicity", ACM TOG 9(1), 1990).  The perturbed ray meets no
** vertex or edge, so it crosses a closed mesh's surface a number of
** times whose parity is the point's inside, and each crossing is decided
** once: an edge shared by two triangles gives them opposite signs for
** q' (the sign below is antisymmetric in the edge's ends).  The walk is
** the triangle BVH's boxes along the ray, which also holds every box
** that contains q itself, where the exact on-surface test runs.
**
** The grid (built by the first ray_contains after the triangle BVH's
** rebuild, ray__cgrid_ensure; a refit drops it, commit.c says why).  Cells over the box of
** the closed meshes' triangles, with walls at doubles; a cell whose
** closed box no triangle's closed box (exact, in double) touches holds
** no point of the surface, nor does a neighbourhood of it (finitely many
** closed boxes, each disjoint from the cell's: a positive gap), so every
** point of it, and every perturbed q' within e of it, has one answer:
** its label, computed once by the exact parity below.  A query point in
** such a cell is answered by the label alone (it is not on the surface).
** A point in a touched cell casts its ray only as far as the first
** untouched cell E of its row (the cells of its y and z along +x): a
** triangle the perturbed ray crosses has q's y and z in its closed box,
** as E's box has, so its box, disjoint from E's, lies wholly before E's
** lower x wall X0 or wholly after its upper one; the crossings before X0
** are those of the triangles whose largest x is below X0 (a double
** comparison), and the ray's rest, from a point q' + t x within e of E,
** has E's label for parity.  So the parity is exact as before, and the
** walk is that of a segment a cell or two long rather than of a ray
** through the whole mesh.  The labels themselves come from the same
** bounded rays, one for each run of untouched cells of a row, taken from
** the row's end backwards (the last run's ray reaches past every box).
** Where a query asks for a subset of the closed meshes (a mask that
** leaves one out), the labels do not apply: the ray goes all the way.
*/
#include <float.h>
#include <math.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "core/predicates.h"
#include "core/platform.h"
#include "scene/scene.h"

/* Cells in the grid for each closed triangle, a byte each: at 8, 96% of
** the 59k bunny's uniform points (bench/contains.c's, its box grown by
** 10%) land in an untouched cell; 32 took 7% fewer instructions a
** uniform point and 3% fewer a hard one (callgrind, the bench's sets) for
** four times the bytes.  -DCELLS_PER_TRI=n tries others. */
#ifndef CELLS_PER_TRI
#define CELLS_PER_TRI 8
#endif
/* At most this many cells on an axis, and in all (16 MB of labels). */
#define AXIS_MAX 1024u
#define CELLS_MAX (1u << 24)
/* The marking's work: at most this many cells marked per cell of the
** grid (large triangles whose boxes cover much of it), beyond which the
** grid would be mostly touched anyway and is not built. */
#define MARKS_PER_CELL 64

/* ------------------------------------------------- the exact predicates */

static int sgn(double x)
{
    return (x > 0) - (x < 0);
}

static double min3(double a, double b, double c)
{
    double m = a < b ? a : b;

    return m < c ? m : c;
}

static double max3(double a, double b, double c)
{
    double m = a > b ? a : b;

    return m > c ? m : c;
}

/*
** The sign of orient2d(a, b, q') in the (y, z) plane for the perturbed
** q' = (qy + e, qz + e^2), from o = orient2d(a, b, q) in that plane
** (exact sign): o's sign when non-zero, else that of its terms in e,
** -(bz - az) e and (by - ay) e^2, the first that is non-zero.  A
** difference of two doubles has the exact sign (gradual underflow), so
** no arithmetic is needed for them.  Antisymmetric in a and b.  0 only
** for a = b in the plane (a degenerate projected edge).
*/
static int side_sos(ray_vec3 a, ray_vec3 b, double o)
{
    if (o != 0)
        return o > 0 ? 1 : -1;
    if (b.z != a.z)
        return b.z < a.z ? 1 : -1;
    if (b.y != a.y)
        return b.y > a.y ? 1 : -1;
    return 0;
}

/* Whether q lies on segment [a, b] (a point when a = b): collinear in
** all three coordinate planes, and within the segment's box. */
static int on_segment(ray_vec3 a, ray_vec3 b, ray_vec3 q)
{
    if (ray__orient2d(a.x, a.y, b.x, b.y, q.x, q.y) != 0 ||
        ray__orient2d(a.y, a.z, b.y, b.z, q.y, q.z) != 0 ||
        ray__orient2d(a.z, a.x, b.z, b.x, q.z, q.x) != 0)
        return 0;
    return q.x >= fmin(a.x, b.x) && q.x <= fmax(a.x, b.x) &&
           q.y >= fmin(a.y, b.y) && q.y <= fmax(a.y, b.y) &&
           q.z >= fmin(a.z, b.z) && q.z <= fmax(a.z, b.z);
}

/* Whether q, in the plane of triangle a, b, c (orient3d 0), lies on the
** closed triangle: inside (edges included) in a coordinate plane where
** it has area; a triangle with none is its three segments. */
static int on_triangle_in_plane(ray_vec3 a, ray_vec3 b, ray_vec3 c,
                                ray_vec3 q)
{
    static const int axes[3][2] = {{0, 1}, {1, 2}, {2, 0}};
    int k;

    for (k = 0; k < 3; k++) {
        int i = axes[k][0], j = axes[k][1], s, s1, s2, s3;
        double ai = v3_axis(a, i), aj = v3_axis(a, j);
        double bi = v3_axis(b, i), bj = v3_axis(b, j);
        double ci = v3_axis(c, i), cj = v3_axis(c, j);
        double qi = v3_axis(q, i), qj = v3_axis(q, j);

        s = sgn(ray__orient2d(ai, aj, bi, bj, ci, cj));
        if (s == 0)
            continue;
        s1 = sgn(ray__orient2d(ai, aj, bi, bj, qi, qj));
        s2 = sgn(ray__orient2d(bi, bj, ci, cj, qi, qj));
        s3 = sgn(ray__orient2d(ci, cj, ai, aj, qi, qj));
        return s1 != -s && s2 != -s && s3 != -s;
    }
    return on_segment(a, b, q) || on_segment(b, c, q) ||
           on_segment(c, a, q);
}

/* A walk's state: the point, where its ray stops counting (x_end: the
** crossings of triangles whose box ends below it), which triangles
** count, and what it found. */
typedef struct pwalk {
    ray_vec3 q;
    double x_end;
    unsigned ignore;             /* the query's mask is ~ignore */
    int all;                     /* every closed mesh counts: no mask test */
    int every;                   /* every live slot counts: no test at all */
    unsigned parity;
    int on;                      /* q lies on a triangle: the walk stops */
} pwalk;

/*
** The triangle's part in q's parity: whether the perturbed ray from q'
** along +x crosses it (q' inside its (y, z) projection, all three sides
** alike, and the plane ahead of q: orient3d's sign times the sides'),
** before x_end; and whether q is on it.  The three orient2d of q
** against the edges in (y, z) serve both: q on the closed triangle has
** them all of one sign or 0 (inside a projection with area, or all 0 on
** a projection without: a segment's line), so two of opposite signs
** rule it out without orient3d, which is the costly one when q lies on
** or next to the plane (its exact stage).
*/
static void cross_triangle(ray_vec3 a, ray_vec3 b, ray_vec3 c, pwalk *w)
{
    const ray_vec3 q = w->q;
    double o1, o2, o3;
    int s1, s2, s3, d = 2;             /* 2: orient3d not taken yet */

    /* Nothing ahead of q, or q' beside the projection (the perturbation
    ** moves q' by less than any gap, so q outside the closed box is q'
    ** outside the triangle): the box's tests, each side apart so that
    ** most triangles leave after one or two comparisons. */
    if ((q.y < a.y && q.y < b.y && q.y < c.y) ||
        (q.y > a.y && q.y > b.y && q.y > c.y) ||
        (q.z < a.z && q.z < b.z && q.z < c.z) ||
        (q.z > a.z && q.z > b.z && q.z > c.z) ||
        (q.x > a.x && q.x > b.x && q.x > c.x))
        return;
    o1 = ray__orient2d(a.y, a.z, b.y, b.z, q.y, q.z);
    o2 = ray__orient2d(b.y, b.z, c.y, c.z, q.y, q.z);
    o3 = ray__orient2d(c.y, c.z, a.y, a.z, q.y, q.z);
    /* Only a triangle whose box holds q can hold q: a vertex of it
    ** (the hard points' commonest case) without a predicate. */
    if (!(q.x < a.x && q.x < b.x && q.x < c.x) &&
        !((o1 > 0 || o2 > 0 || o3 > 0) &&
                        (o1 < 0 || o2 < 0 || o3 < 0))) {
        if ((q.x == a.x && q.y == a.y && q.z == a.z) ||
            (q.x == b.x && q.y == b.y && q.z == b.z) ||
            (q.x == c.x && q.y == c.y && q.z == c.z)) {
            w->on = 1;
            return;
        }
        d = sgn(ray__orient3d(a, b, c, q));
        if (d == 0 && on_triangle_in_plane(a, b, c, q)) {
            w->on = 1;
            return;
        }
    }
    if (max3(a.x, b.x, c.x) >= w->x_end)
        return;                      /* its crossing, if any, is beyond */
    s1 = side_sos(a, b, o1);
    s2 = side_sos(b, c, o2);
    s3 = side_sos(c, a, o3);
    if (s1 == 0 || s1 != s2 || s1 != s3)
        return;
    if (d == 2)
        d = sgn(ray__orient3d(a, b, c, q));
    if (d == 0)
        w->on = 1;            /* q in the plane, inside the triangle */
    else if (d == s1)
        w->parity ^= 1u;      /* the plane lies ahead along +x */
}

/* Whether triangle slot i is a closed mesh's, and counted by the walk
** (enabled and live: slots below n_live_tris are). */
static int slot_counts(const ray_scene *s, const pwalk *w, unsigned i)
{
    const ray__prim *p = &s->prims[s->tri_ids[i].geom_id];

    return p->kind == RAY__KIND_MESH && s->meshes[p->mesh].closed &&
           p->enabled && !p->removed &&
           (w->all || (p->mask & ~w->ignore) != 0);
}

/* x rounded up (down) to a float: the float comparisons below are then
** the exact ones of the float bounds against x (f >= x exactly when f >=
** up(x), f < x when f < up(x), f <= x when f <= down(x)). */
static float up_f(double x)
{
    float f = (float)x;

    return (double)f < x ? nextafterf(f, HUGE_VALF) : f;
}

static float down_f(double x)
{
    float f = (float)x;

    return (double)f > x ? nextafterf(f, -HUGE_VALF) : f;
}

/* The bounds of the ray's boxes as floats: x from q.x, below x_end, y
** and z at q's. */
typedef struct fray {
    float x, x_end, y_lo, y_hi, z_lo, z_hi;
} fray;

/* The children of node n whose boxes the ray from q along +x enters
** before x_end (which include every box holding q), as bits: y and z
** within, the box neither wholly behind nor wholly at or past x_end.
** The float boxes contain their geometry (rounded outward at commit);
** an unused slot (lo +Inf, hi -Inf) fails.  Branch-free over the
** node's width. */
static unsigned boxes_on_ray(const ray__wnode *n, const fray *r)
{
    unsigned bits = 0;
    int k;

#if defined(__SSE2__) && RAY__WIDTH % 4 == 0
    /* Four slots a comparison (x86-64 always has SSE2): the same tests. */
    const __m128 x = _mm_set1_ps(r->x), xe = _mm_set1_ps(r->x_end);
    const __m128 ylo = _mm_set1_ps(r->y_lo), yhi = _mm_set1_ps(r->y_hi);
    const __m128 zlo = _mm_set1_ps(r->z_lo), zhi = _mm_set1_ps(r->z_hi);
    for (k = 0; k < RAY__WIDTH; k += 4) {
        __m128 m = _mm_and_ps(
            _mm_and_ps(_mm_cmpge_ps(_mm_loadu_ps(&n->hi[0][k]), x),
                       _mm_cmplt_ps(_mm_loadu_ps(&n->lo[0][k]), xe)),
            _mm_and_ps(
                _mm_and_ps(_mm_cmple_ps(_mm_loadu_ps(&n->lo[1][k]), ylo),
                           _mm_cmpge_ps(_mm_loadu_ps(&n->hi[1][k]), yhi)),
                _mm_and_ps(_mm_cmple_ps(_mm_loadu_ps(&n->lo[2][k]), zlo),
                           _mm_cmpge_ps(_mm_loadu_ps(&n->hi[2][k]), zhi))));
        bits |= (unsigned)_mm_movemask_ps(m) << k;
    }
#else
    for (k = 0; k < RAY__WIDTH; k++)
        bits |= (unsigned)((n->hi[0][k] >= r->x) & (n->lo[0][k] < r->x_end) &
                           (n->lo[1][k] <= r->y_lo) & (n->hi[1][k] >= r->y_hi) &
                           (n->lo[2][k] <= r->z_lo) & (n->hi[2][k] >= r->z_hi))
                << k;
#endif
    return bits;
}

/* Every leaf of the triangle BVH on the ray, depth first, until q is
** found on a triangle.  At most RAY__WIDTH pushed and one popped a
** level, 64 levels at most (accel/build.h). */
static void walk(const ray_scene *s, pwalk *w)
{
    const ray__bvh *bvh = &s->tri_bvh;
    unsigned stack_child[RAY__WIDTH * 64], stack_count[RAY__WIDTH * 64];
    unsigned child = 0, count = 0;
    int sp = 0;
    fray r;

    if (bvh->n_wide == 0)
        return;
    r.x = up_f(w->q.x);
    r.x_end = up_f(w->x_end);
    r.y_lo = down_f(w->q.y);
    r.y_hi = up_f(w->q.y);
    r.z_lo = down_f(w->q.z);
    r.z_hi = up_f(w->q.z);
    for (;;) {
        if (count == 0) {
            const ray__wnode *n = &bvh->wide[child];
            unsigned bits = boxes_on_ray(n, &r);
            int k;
            for (k = 0; bits != 0; k++, bits >>= 1) {
                if (!(bits & 1u) || n->count[k] == RAY__LEAF)
                    continue;
                stack_child[sp] = n->child[k];
                stack_count[sp] = n->count[k];
                sp++;
            }
        } else {
            unsigned i, m = count & ~RAY__LEAF;
            const float *rows = s->leaf_f + RAY__LEAF_ROWS * (size_t)child;
            for (i = 0; i < m; i++) {
                ray__tri t;
                if (!w->every && !slot_counts(s, w, child + i))
                    continue;
                t = ray__leaf_tri(s, child + i, rows + i, m);
                cross_triangle(t.a, t.b, t.c, w);
                if (w->on)
                    return;
            }
        }
        if (sp == 0)
            return;
        sp--;
        child = stack_child[sp];
        count = stack_count[sp];
    }
}

/* ------------------------------------------------------------- the grid */

/* The cell of coordinate x on an axis of n cells with walls wall[0..n]:
** wall[i] <= x < wall[i + 1], or the last cell for x = wall[n]; x within
** [wall[0], wall[n]].  From the guess g, corrected by the walls
** themselves, so that rounding in the guess costs a step, never a
** wrong cell. */
static unsigned locate(const double *wall, unsigned n, double x, double g)
{
    unsigned i = g >= (double)n ? n - 1 : g > 0 ? (unsigned)g : 0;

    while (i > 0 && x < wall[i])
        i--;
    while (i + 1 < n && x >= wall[i + 1])
        i++;
    return i;
}

static unsigned locate_axis(const ray__cgrid *g, int a, double x)
{
    return locate(g->wall[a], g->n[a], x, (x - g->wall[a][0]) * g->scale[a]);
}

/* The parity of q's crossings (w->q in row "row" of the grid, at or left
** of cell "from") up to the first untouched cell of its row from "from"
** on, with that cell's label; the whole ray where the row has none. */
static void row_parity(const ray_scene *s, size_t row, unsigned from,
                       pwalk *w)
{
    const ray__cgrid *g = &s->cgrid;
    const unsigned char *label = g->label + row;
    unsigned e = from;

    while (e < g->n[0] && label[e] == 0)
        e++;
    w->x_end = e < g->n[0] ? g->wall[0][e] : HUGE_VAL;
    walk(s, w);
    if (!w->on && e < g->n[0])
        w->parity ^= (unsigned)(label[e] - 1);
}

void ray__closed_parity(const ray_scene *s, ray_vec3 q, unsigned ignore,
                        int all, unsigned *parity, int *on)
{
    const ray__cgrid *g = &s->cgrid;
    pwalk w;

    w.q = q;
    w.x_end = HUGE_VAL;
    w.ignore = ignore;
    w.all = all;
    w.every = all && g->every;
    w.parity = 0;
    w.on = 0;
    if (!all || g->n[0] == 0) {
        walk(s, &w);
    } else if (q.y >= g->wall[1][0] && q.y <= g->wall[1][g->n[1]] &&
               q.z >= g->wall[2][0] && q.z <= g->wall[2][g->n[2]] &&
               q.x <= g->wall[0][g->n[0]]) {
        /* Elsewhere the ray meets no box of a closed triangle. */
        unsigned j = locate_axis(g, 1, q.y), k = locate_axis(g, 2, q.z);
        size_t row = ((size_t)k * g->n[1] + j) * g->n[0];
        if (q.x < g->wall[0][0]) {
            row_parity(s, row, 0, &w);
        } else {
            unsigned i = locate_axis(g, 0, q.x);
            if (g->label[row + i] != 0)
                w.parity = (unsigned)(g->label[row + i] - 1);
            else
                row_parity(s, row, i, &w);
        }
    }
    *parity = w.parity;
    *on = w.on;
}

void ray__cgrid_ensure(const ray_scene *s)
{
    ray_scene *m = ray__unconst(s);

    if (m->cgrid_lock == NULL)      /* set at commit, read-only after */
        return;
    ray__mutex_lock(m->cgrid_lock);
    if (!m->cgrid_tried) {
        m->cgrid_tried = 1;
        /* Out of memory: no grid, the whole rays (as exact). */
        (void)ray__cgrid_build(m);
    }
    ray__mutex_unlock(m->cgrid_lock);
}

void ray__cgrid_free(ray_scene *s)
{
    ray__free(s, s->cgrid.block, s->cgrid.bytes);
    memset(&s->cgrid, 0, sizeof s->cgrid);
}

/* The closed meshes' live triangles, their box; 0 if none. */
static size_t closed_box(const ray_scene *s, double lo[3], double hi[3])
{
    size_t i, n = 0;
    pwalk w;

    w.all = 1;
    w.every = 0;
    w.ignore = 0;
    for (i = 0; i < s->n_live_tris; i++) {
        ray__tri t;
        if (!slot_counts(s, &w, (unsigned)i))
            continue;
        t = ray__tri_of(s, i);
        if (n++ == 0) {
            lo[0] = hi[0] = t.a.x;
            lo[1] = hi[1] = t.a.y;
            lo[2] = hi[2] = t.a.z;
        }
        lo[0] = fmin(lo[0], min3(t.a.x, t.b.x, t.c.x));
        lo[1] = fmin(lo[1], min3(t.a.y, t.b.y, t.c.y));
        lo[2] = fmin(lo[2], min3(t.a.z, t.b.z, t.c.z));
        hi[0] = fmax(hi[0], max3(t.a.x, t.b.x, t.c.x));
        hi[1] = fmax(hi[1], max3(t.a.y, t.b.y, t.c.y));
        hi[2] = fmax(hi[2], max3(t.a.z, t.b.z, t.c.z));
    }
    return n;
}

/* The cells on an axis whose closed extent [wall[i], wall[i + 1]] meets
** [a, b] (within the walls): *first .. *last. */
static void cell_span(const ray__cgrid *g, int axis, double a, double b,
                      unsigned *first, unsigned *last)
{
    const double *wall = g->wall[axis];
    unsigned i = locate_axis(g, axis, a), k = locate_axis(g, axis, b);

    while (i > 0 && wall[i] >= a)     /* the cell below shares that wall */
        i--;
    while (i < k && wall[i + 1] < a)
        i++;
    while (k + 1 < g->n[axis] && wall[k + 1] <= b)
        k++;
    *first = i;
    *last = k;
}

/* The cells a closed triangle slot's box touches: *first .. *last on
** each axis.  0 for a slot that is not a closed mesh's. */
static int slot_cells(const ray_scene *s, const ray__cgrid *g, size_t i,
                      unsigned f[3], unsigned l[3])
{
    pwalk w;
    ray__tri t;

    w.all = 1;
    w.every = 0;
    w.ignore = 0;
    if (!slot_counts(s, &w, (unsigned)i))
        return 0;
    t = ray__tri_of(s, i);
    cell_span(g, 0, min3(t.a.x, t.b.x, t.c.x), max3(t.a.x, t.b.x, t.c.x),
              &f[0], &l[0]);
    cell_span(g, 1, min3(t.a.y, t.b.y, t.c.y), max3(t.a.y, t.b.y, t.c.y),
              &f[1], &l[1]);
    cell_span(g, 2, min3(t.a.z, t.b.z, t.c.z), max3(t.a.z, t.b.z, t.c.z),
              &f[2], &l[2]);
    return 1;
}

/* Mark every cell a closed triangle's box touches (label 0); 0 when that
** is more work than MARKS_PER_CELL a cell, where the grid would be
** mostly touched anyway. */
static int mark_touched(const ray_scene *s, ray__cgrid *g, size_t cells)
{
    size_t i, marks = 0;

    for (i = 0; i < s->n_live_tris; i++) {
        unsigned f[3], l[3], x, y, z;
        if (!slot_cells(s, g, i, f, l))
            continue;
        marks += (size_t)(l[0] - f[0] + 1) * (l[1] - f[1] + 1) *
                 (l[2] - f[2] + 1);
        if (marks > MARKS_PER_CELL * cells)
            return 0;
        for (z = f[2]; z <= l[2]; z++)
            for (y = f[1]; y <= l[1]; y++)
                for (x = f[0]; x <= l[0]; x++)
                    g->label[((size_t)z * g->n[1] + y) * g->n[0] + x] = 0;
    }
    return 1;
}

/* Each untouched cell's label, row by row from the row's end: a run of
** untouched cells shares one, the parity at its last cell's centre up to
** the next run (whose label is known by then) or along the whole row. */
static void label_cells(const ray_scene *s, ray__cgrid *g)
{
    unsigned j, k;

    for (k = 0; k < g->n[2]; k++)
        for (j = 0; j < g->n[1]; j++) {
            size_t row = ((size_t)k * g->n[1] + j) * g->n[0];
            unsigned char *label = g->label + row;
            unsigned char next = 1;
            int in_run = 0;
            unsigned i;
            for (i = g->n[0]; i-- > 0;) {
                if (label[i] == 0) {
                    in_run = 0;
                    continue;
                }
                if (!in_run) {
                    pwalk w;
                    w.q = v3(0.5 * (g->wall[0][i] + g->wall[0][i + 1]),
                             0.5 * (g->wall[1][j] + g->wall[1][j + 1]),
                             0.5 * (g->wall[2][k] + g->wall[2][k + 1]));
                    w.all = 1;
                    w.every = g->every;
                    w.ignore = 0;
                    w.parity = 0;
                    w.on = 0;
                    if (i + 1 < g->n[0])
                        row_parity(s, row, i + 1, &w);
                    next = (unsigned char)(1 + w.parity);
                    in_run = 1;
                }
                label[i] = next;
            }
        }
}

int ray__cgrid_build(ray_scene *s)
{
    ray__cgrid g;
    double lo[3], hi[3], ext[3], emax, h, vol, target;
    size_t n_tris, cells, bytes, i;
    int a;

    ray__cgrid_free(s);
    n_tris = closed_box(s, lo, hi);
    if (n_tris == 0)
        return RAY_OK;
    memset(&g, 0, sizeof g);
    for (a = 0; a < 3; a++)
        ext[a] = hi[a] - lo[a];
    emax = fmax(ext[0], fmax(ext[1], ext[2]));
    /* A box wider than DBL_MAX on some axis (hi - lo overflowed: corners
    ** near +-DBL_MAX) gets no grid: its cells' size would be Inf and
    ** their counts NaN (Inf / Inf), and the walls lo + Inf * 0.  The
    ** queries then take the walk without it, as for a scene with no
    ** closed mesh.  Found by make fuzz (fuzz_contains,
    ** fuzz/crashes/fuzz_contains/grid-extent-overflows). */
    if (!(emax <= DBL_MAX))
        return RAY_OK;
    /* Cubic cells, CELLS_PER_TRI a triangle (CELLS_MAX at most), a flat
    ** axis counted as a 64th of the longest so that the others keep
    ** their cells. */
    vol = 1;
    for (a = 0; a < 3; a++)
        vol *= fmax(ext[a], emax / 64);
    target = fmin((double)CELLS_PER_TRI * (double)n_tris, (double)CELLS_MAX);
    h = cbrt(vol / target);
    cells = 1;
    for (a = 0; a < 3; a++) {
        double c = h > 0 ? ceil(ext[a] / h) : 1;
        /* !(c >= 1): a NaN count too is one cell, never a conversion. */
        g.n[a] = !(c >= 1) ? 1u : c > AXIS_MAX ? AXIS_MAX : (unsigned)c;
        cells *= g.n[a];
    }
    /* Walls, then labels: one block. */
    bytes = (g.n[0] + g.n[1] + g.n[2] + 3) * sizeof(double) + cells;
    g.block = ray__alloc(s, bytes);
    if (g.block == NULL)
        return RAY_ENOMEM;
    g.bytes = bytes;
    g.wall[0] = g.block;
    g.wall[1] = g.wall[0] + g.n[0] + 1;
    g.wall[2] = g.wall[1] + g.n[1] + 1;
    g.label = (unsigned char *)(g.wall[2] + g.n[2] + 1);
    /* Walls at lo + ext i / n, non-decreasing (each step rounds a
    ** non-decreasing value), the last exactly hi. */
    for (a = 0; a < 3; a++) {
        for (i = 0; i < g.n[a]; i++)
            g.wall[a][i] = fmin(lo[a] + ext[a] * ((double)i / (double)g.n[a]),
                                hi[a]);
        g.wall[a][g.n[a]] = hi[a];
        g.scale[a] = ext[a] > 0 ? (double)g.n[a] / ext[a] : 0;
    }
    /* Every live slot a closed mesh's (the commonest scene for
    ** ray_contains): the walks need not look at the slots' geometry. */
    g.every = n_tris == s->n_live_tris;
    memset(g.label, 1, cells);
    if (!mark_touched(s, &g, cells)) {
        ray__free(s, g.block, bytes);
        return RAY_OK;
    }
    s->cgrid = g;
    /* The labels' rays walk the BVH and read the labels found so far. */
    label_cells(s, &s->cgrid);
    return RAY_OK;
}
