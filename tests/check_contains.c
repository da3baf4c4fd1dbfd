/* SPDX-License-Identifier: MIT */
/*
** check_contains.c -- ray_contains and ray_signed_distance against brute
** force over every triangle, in the test's own code: for convex closed
** meshes (a cube, an icosphere) the exact answer from the sign of every
** face's orientation (inside: behind all, on the surface: behind or on
** all and on one), for the others the parity along +x over every
** triangle without the BVH, and the winding number summed in long double.
** Points at vertices, on edges and faces, an ulp inside and outside,
** uniform in the box, at offsets 0, 1e5 and 1e6; meshes with a hole, a
** crack and a flipped triangle; instances and solid primitives; misuse.
*/
#include <stdlib.h>

#include "core/predicates.h"
#include "core/vec.h"
#include "scene/scene.h"
#include "tests.h"
#include "hardcases.h"
#include "winding_ref.h"

/* Winding numbers: the library sums in double and the reference in long
** double; each of up to 1280 solid angles is within a few ulps of 4 pi
** (atan2 and the sums: 1e-15 each), so 1e-9 (the target) holds
** with a margin of 1e3 even near edges, where an angle's condition
** number grows as 1 / distance (points here stay 1e-7 of the size away
** from edges, or on a face an ulp off, where the angle is +-2 pi). */
#define WIND_TOL 1e-9

/* The fast winding number (the default: Barill et al.'s order-2
** far-field expansion through the BVH, beta 2) is approximate: a cluster
** of radius r seen from d > 2 r away contributes an error of order
** (r / d)^2 of its own solid angle (the Taylor series' next term), and
** the clusters at the edge of acceptance add up.  Measured
** (RAY_TEST_WINDING_ERR=1): the largest error of these tests' points is
** 2.8e-2, at a uniform point inside the holed icosphere of level 3 (3.5e-2
** at 2000 such points, of which fast_winding_soup asks 1000), and 2.4e-2
** on the 59k bunny (bench/contains.c); ray.h documents 5e-2, the
** tolerance here, which stays below ray_contains' margin of 0.2 about
** 1/2 within which it sums exactly (so inside is compared exactly). */
#define FAST_TOL 5e-2

static ray_scene *scene_of(const hc_mesh *m, int commit)
{
    ray_scene *s = NULL;
    ray_mesh rm = hc_ray_mesh(m);

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &rm, RAY_NO_MATERIAL, NULL), RAY_OK);
    if (commit)
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    return s;
}

/* Convex mesh, outward faces: 2 inside, 1 on the surface, 0 outside,
** from orient3d's exact sign (positive: q behind the face). */
static int convex_ref(const hc_mesh *m, ray_vec3 q)
{
    int on = 0;
    size_t i;

    for (i = 0; i < m->nt; i++) {
        const unsigned *t = m->idx + 3 * i;
        double d = ray__orient3d(m->v[t[0]], m->v[t[1]], m->v[t[2]], q);
        if (d < 0)
            return 0;
        on |= d == 0;
    }
    return on ? 1 : 2;
}

/* The winding number in long double over every triangle, its
** determinant's sign the exact one (winding_ref.h, which
** fuzz/fuzz_winding.c shares). */
static double winding_ref(const hc_mesh *m, ray_vec3 q)
{
    return winding_ref_sum(m->v, m->idx, m->nt, q);
}

/*
** Whether q lies within 1e-9 of an edge (the mesh's size is 2 or 4
** here) but not at its ends.  The winding number is not defined on an
** edge and its condition number grows as size / distance: at a point an
** ulp off an edge (a rounded midpoint) two triangles' angles come from
** rounding noise in det and in the denominator, in double and in long
** double alike (measured: 6e-3 apart at an icosphere's edge midpoint).
** Such points (the ulp neighbours of vertices too) are checked for
** inside and on_surface only; the centroids and their ulp neighbours
** are 0.1 or more from every edge, where the condition number (about 20)
** times double's rounding stays far below WIND_TOL.
*/
static int near_edge(const hc_mesh *m, ray_vec3 q)
{
    size_t i, k;

    for (i = 0; i < m->nt; i++)
        for (k = 0; k < 3; k++) {
            ray_vec3 a = m->v[m->idx[3 * i + k]];
            ray_vec3 b = m->v[m->idx[3 * i + (k + 1) % 3]];
            ray_vec3 ab = v3_sub(b, a), aq = v3_sub(q, a);
            double t = v3_dot(aq, ab) / v3_dot(ab, ab);
            if (t > 0 && t < 1 &&
                v3_length(v3_sub(aq, v3_scale(ab, t))) < 2e-9)
                return 1;
        }
    return 0;
}

/* The parity along +x over every triangle, perturbed as the library
** documents (q + (0, e, e^2)), but without its BVH: 1 inside, 0 outside;
** *on for a triangle holding q. */
static int sos_side(ray_vec3 a, ray_vec3 b, ray_vec3 q)
{
    double o = ray__orient2d(a.y, a.z, b.y, b.z, q.y, q.z);
    if (o != 0)
        return o > 0 ? 1 : -1;
    if (b.z != a.z)
        return b.z < a.z ? 1 : -1;
    return b.y > a.y ? 1 : b.y < a.y ? -1 : 0;
}

static int parity_ref(const hc_mesh *m, ray_vec3 q)
{
    int parity = 0;
    size_t i;

    for (i = 0; i < m->nt; i++) {
        const unsigned *t = m->idx + 3 * i;
        ray_vec3 a = m->v[t[0]], b = m->v[t[1]], c = m->v[t[2]];
        int s1 = sos_side(a, b, q), s2 = sos_side(b, c, q),
            s3 = sos_side(c, a, q);
        double d;
        if (s1 == 0 || s1 != s2 || s1 != s3)
            continue;
        d = ray__orient3d(a, b, c, q);
        if ((d > 0 && s1 > 0) || (d < 0 && s1 < 0))
            parity ^= 1;
    }
    return parity;
}

/* The hard points of mesh m: every vertex, every edge's midpoint and
** the points an ulp off each vertex toward and away from "centre", each
** face's centroid and its ulp neighbours alike, and n uniform points in its box grown by 10%. */
static size_t hard_points(const hc_mesh *m, ray_vec3 centre, size_t n,
                          ray_vec3 **out)
{
    size_t cap = 3 * m->nv + 6 * m->nt + n, k = 0, i;
    ray_vec3 *p = malloc(cap * sizeof *p), lo = m->v[0], hi = m->v[0];
    rng g = {39};

    for (i = 0; i < m->nv; i++) {
        ray_vec3 v = m->v[i];
        p[k++] = v;
        p[k++] = v3(nextafter(v.x, centre.x), nextafter(v.y, centre.y),
                    nextafter(v.z, centre.z));
        p[k++] = v3(nextafter(v.x, v.x + (v.x - centre.x)),
                    nextafter(v.y, v.y + (v.y - centre.y)),
                    nextafter(v.z, v.z + (v.z - centre.z)));
        lo = v3(fmin(lo.x, v.x), fmin(lo.y, v.y), fmin(lo.z, v.z));
        hi = v3(fmax(hi.x, v.x), fmax(hi.y, v.y), fmax(hi.z, v.z));
    }
    for (i = 0; i < m->nt; i++) {
        const unsigned *t = m->idx + 3 * i;
        ray_vec3 a = m->v[t[0]], b = m->v[t[1]], c = m->v[t[2]];
        p[k++] = v3_scale(v3_add(a, b), 0.5);
        p[k++] = v3_scale(v3_add(b, c), 0.5);
        p[k++] = v3_scale(v3_add(c, a), 0.5);
        ray_vec3 f = v3_scale(v3_add(v3_add(a, b), c), 1.0 / 3);
        p[k++] = f;
        p[k++] = v3(nextafter(f.x, centre.x), nextafter(f.y, centre.y),
                    nextafter(f.z, centre.z));
        p[k++] = v3(nextafter(f.x, f.x + (f.x - centre.x)),
                    nextafter(f.y, f.y + (f.y - centre.y)),
                    nextafter(f.z, f.z + (f.z - centre.z)));
    }
    for (i = 0; i < n; i++) {
        ray_vec3 d = v3_scale(v3_sub(hi, lo), 0.1);
        ray_vec3 l = v3_sub(lo, d), h = v3_add(hi, d);
        p[k++] = v3(rng_range(&g, l.x, h.x), rng_range(&g, l.y, h.y),
                    rng_range(&g, l.z, h.z));
    }
    *out = p;
    return k;
}

/* hard_points' every third hard point and n uniform ones: the fast
** winding tests' points, few enough that each test stays well under a
** second (every point costs three passes over the triangles: the
** reference, near_edge and the exact sum). */
static size_t some_points(const hc_mesh *m, ray_vec3 centre, size_t n,
                          ray_vec3 **out)
{
    size_t all = hard_points(m, centre, n, out), hard = all - n, i, k = 0;

    for (i = 0; i < all; i++)
        if (i >= hard || i % 3 == 0)
            (*out)[k++] = (*out)[i];
    return k;
}

/* A largest error seen by check_fast, for the comment on FAST_TOL
** (RAY_TEST_WINDING_ERR=1 prints it). */
static void report_err(const char *what, double err)
{
    if (getenv("RAY_TEST_WINDING_ERR") != NULL)
        fprintf(stderr, "%s: fast winding error %.3g\n", what, err);
}

/* The fast winding number (flags without RAY_CONTAINS_WINDING_EXACT)
** at points pts of scene s, whose triangles in world space are ref's:
** inside and on_surface as the exact sum's (RAY_CONTAINS_WINDING_EXACT)
** at every point; off the edges (near_edge: undefined there), the exact
** sum within WIND_TOL and the fast one within FAST_TOL of the long
** double sum.  Returns the largest fast error. */
static double check_fast(const ray_scene *s, const hc_mesh *ref,
                         const ray_vec3 *pts, size_t n, unsigned flags)
{
    ray_inside *f = malloc(n * sizeof *f), *e = malloc(n * sizeof *e);
    ray_contains_options of = {0}, oe = {0};
    double worst = 0;
    size_t i;
    int fast_in, exact_in;

    of.flags = flags;
    oe.flags = flags | RAY_CONTAINS_WINDING_EXACT;
    fast_in = ray_contains(s, pts, n, &of, f);
    exact_in = ray_contains(s, pts, n, &oe, e);
    ck_assert_int_ge(fast_in, 0);
    ck_assert_int_eq(fast_in, exact_in);
    for (i = 0; i < n; i++) {
        double w, err;
        ck_assert_msg(f[i].inside == e[i].inside &&
                          f[i].on_surface == e[i].on_surface,
                      "point %zu (%.17g, %.17g, %.17g): fast %d (%.17g), "
                      "exact %d (%.17g)", i, pts[i].x, pts[i].y, pts[i].z,
                      f[i].inside, f[i].winding, e[i].inside, e[i].winding);
        if (near_edge(ref, pts[i]))
            continue;
        w = winding_ref(ref, pts[i]);
        ck_assert_msg(fabs(e[i].winding - w) <= WIND_TOL,
                      "point %zu: exact winding %.17g, reference %.17g", i,
                      e[i].winding, w);
        err = fabs(f[i].winding - w);
        ck_assert_msg(err <= FAST_TOL,
                      "point %zu (%.17g, %.17g, %.17g): fast winding %.17g, "
                      "reference %.17g", i, pts[i].x, pts[i].y, pts[i].z,
                      f[i].winding, w);
        worst = err > worst ? err : worst;
    }
    free(f);
    free(e);
    return worst;
}

/* A convex closed mesh at its hard points: inside and on_surface as the
** faces' signs say, the parity walk as the brute force's, and the
** winding number (off the surface) as the long double sum. */
static void check_convex(hc_mesh m, ray_vec3 centre, int winding)
{
    ray_scene *s = scene_of(&m, 1);
    ray_vec3 *pts;
    size_t n = hard_points(&m, centre, 400, &pts), i;
    ray_inside *out = malloc(n * sizeof *out);
    ray_contains_options o = {0};
    int count = 0, on = 0, in = 0;

    ck_assert_int_ge(ray_contains(s, pts, n, NULL, out), 0);
    for (i = 0; i < n; i++) {
        int ref = convex_ref(&m, pts[i]);
        ck_assert_msg(out[i].on_surface == (ref == 1) &&
                          out[i].inside == (ref >= 1),
                      "point %zu (%.17g, %.17g, %.17g): inside %d on %d, "
                      "reference %d", i, pts[i].x, pts[i].y, pts[i].z,
                      out[i].inside, out[i].on_surface, ref);
        ck_assert_int_eq(parity_ref(&m, pts[i]) == 1 || ref == 1,
                         out[i].inside);
        count += out[i].inside;
        on += ref == 1;
        in += ref == 2;
    }
    /* Every vertex is on the surface; each ulp step toward the centre
    ** is inside and away from it outside for the convex meshes here. */
    ck_assert_int_ge(on, (int)m.nv);
    ck_assert_int_ge(in, (int)m.nv);
    ck_assert_int_eq(ray_contains(s, pts, n, NULL, NULL), count);
    if (winding) {
        o.flags = RAY_CONTAINS_WINDING | RAY_CONTAINS_WINDING_EXACT;
        ck_assert_int_ge(ray_contains(s, pts, n, &o, out), 0);
        for (i = 0; i < n; i++) {
            double w = winding_ref(&m, pts[i]);
            int ref = convex_ref(&m, pts[i]);
            if (ref == 1 || near_edge(&m, pts[i]))
                continue;           /* on the surface: undefined */
            ck_assert_msg(fabs(out[i].winding - w) <= WIND_TOL,
                          "point %zu: winding %.17g, reference %.17g", i,
                          out[i].winding, w);
            /* Convex and closed: 1 inside, 0 outside. */
            ck_assert_msg(fabs(w - (ref == 2)) <= WIND_TOL, "w %g", w);
        }
        report_err("convex", check_fast(s, &m, pts, n, RAY_CONTAINS_WINDING));
    }
    free(out);
    free(pts);
    ray_scene_free(s);
    hc_mesh_free(&m);
}

START_TEST(cube_at_offsets)
{
    static const double off[3] = {0, 1e5, 1e6};
    int k;

    for (k = 0; k < 3; k++) {
        ray_vec3 c = v3(off[k], -off[k] / 3, off[k] * 0.7);
        check_convex(hc_cube(c), c, 1);
    }
}
END_TEST

/*
** A closed mesh whose box is wider than DBL_MAX along x (an octahedron
** with tips at +-1e308: hi - lo overflows to Inf): the containment grid
** would get Inf-sized cells and NaN counts (a NaN converted to an
** unsigned, undefined behaviour that clang's UBSan reports; make fuzz
** found it, fuzz/crashes/fuzz_contains/grid-extent-overflows), so the
** scene gets none and the walk answers alone.  The octahedron |x| / 1e308
** + |y| + |z| <= 1: its centre and a point at a fifth of each tip are
** inside, points past a face outside; the exact answer, no tolerance
** (every point is at least 0.2 of the unit from a face).
*/
START_TEST(contains_box_wider_than_dbl_max)
{
    static const double verts[6][3] = {
        {1e308, 0, 0}, {-1e308, 0, 0}, {0, 1, 0},
        {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    static const unsigned idx[24] = {
        0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4,
        2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
    static const double pts[6][3] = {
        {0, 0, 0}, {2e307, 0.2, 0.2}, {-2e307, -0.2, 0.2},
        {0, 0.7, 0.7}, {5e307, 0.4, 0.4}, {0, 0, -1.5}};
    static const int want[6] = {1, 1, 1, 0, 0, 0};
    ray_vec3 v[6], p[6];
    ray_inside out[6];
    ray_mesh m;
    ray_scene *s;
    int i;

    for (i = 0; i < 6; i++) {
        v[i] = v3(verts[i][0], verts[i][1], verts[i][2]);
        p[i] = v3(pts[i][0], pts[i][1], pts[i][2]);
    }
    memset(&m, 0, sizeof m);
    m.vertices = v;
    m.vertex_count = 6;
    m.indices = idx;
    m.triangle_count = 8;
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_contains(s, p, 6, NULL, out), 3);
    for (i = 0; i < 6; i++) {
        ck_assert_msg(out[i].inside == want[i], "point %d: inside %d", i,
                      out[i].inside);
        ck_assert_int_eq(out[i].on_surface, 0);
    }
    ray_scene_free(s);
}
END_TEST

START_TEST(icosphere_at_offsets)
{
    static const double off[3] = {0, 1e5, 1e6};
    int k;

    for (k = 0; k < 3; k++) {
        ray_vec3 c = v3(off[k] * 0.3, off[k], -off[k]);
        check_convex(hc_icosphere(c, 2), c, k == 0);
    }
}
END_TEST

/* Two cubes in one mesh, one beside the other and a small one inside
** the first (nested: its inside is outside the solid, by parity), at the
** hard points of all: the walk as the brute-force parity over every
** triangle, and on_surface as the convex tests of the parts. */
START_TEST(nested_and_apart)
{
    hc_mesh a = hc_cube(v3(0, 0, 0)), b = hc_cube(v3(3, 0.5, 0.25));
    hc_mesh m;
    ray_scene *s;
    ray_vec3 *pts;
    ray_inside *out;
    size_t n, i, k;

    m.nv = 3 * 8;
    m.nt = 3 * 12;
    m.v = malloc(m.nv * sizeof *m.v);
    m.idx = malloc(3 * m.nt * sizeof *m.idx);
    for (i = 0; i < 8; i++) {
        m.v[i] = a.v[i];
        m.v[8 + i] = b.v[i];
        m.v[16 + i] = v3_scale(a.v[i], 0.5);    /* the nested one */
    }
    for (k = 0; k < 3; k++)
        for (i = 0; i < 36; i++)
            m.idx[36 * k + i] = a.idx[i] + (unsigned)(8 * k);
    s = scene_of(&m, 1);
    n = hard_points(&m, v3(0, 0, 0), 2000, &pts);
    out = malloc(n * sizeof *out);
    ck_assert_int_ge(ray_contains(s, pts, n, NULL, out), 0);
    for (i = 0; i < n; i++) {
        hc_mesh part;
        int on = 0;
        for (k = 0; k < 3; k++) {
            part.v = m.v + 8 * k;
            part.idx = a.idx;
            part.nv = 8;
            part.nt = 12;
            on |= convex_ref(&part, pts[i]) == 1;
        }
        ck_assert_int_eq(out[i].on_surface, on);
        ck_assert_msg(out[i].inside == (on || parity_ref(&m, pts[i])),
                      "point %zu", i);
    }
    /* The nested cube's inside is out of the solid; between the two is
    ** in. */
    ck_assert_int_eq(ray_contains(s, &(ray_vec3){0.1, 0.2, 0.3}, 1, NULL,
                                  NULL), 0);
    ck_assert_int_eq(ray_contains(s, &(ray_vec3){0.75, 0.2, 0.3}, 1, NULL,
                                  NULL), 1);
    free(out);
    free(pts);
    ray_scene_free(s);
    hc_mesh_free(&a);
    hc_mesh_free(&b);
    hc_mesh_free(&m);
}
END_TEST

/* The icosphere of level 2 (320 triangles: the BVH has inner nodes,
** whose expansions are read) around c, damaged by kind: 0 a hole of
** "hole" triangles, 1 a crack (triangle 0's first two corners
** duplicated), 2 a flipped triangle. */
static hc_mesh damaged(ray_vec3 c, int kind, size_t hole)
{
    hc_mesh m = hc_icosphere(c, 2);

    if (kind == 0) {
        m.nt -= hole;
    } else if (kind == 1) {
        unsigned *t = m.idx;
        m.v = realloc(m.v, (m.nv + 2) * sizeof *m.v);
        m.v[m.nv] = m.v[t[0]];
        m.v[m.nv + 1] = m.v[t[1]];
        t[0] = (unsigned)m.nv;
        t[1] = (unsigned)m.nv + 1;
        m.nv += 2;
    } else {
        unsigned x = m.idx[3 * 7];
        m.idx[3 * 7] = m.idx[3 * 7 + 1];
        m.idx[3 * 7 + 1] = x;
    }
    return m;
}

/* An icosphere with a hole (a triangle removed), a crack (one edge's
** vertices duplicated on one side) and a flipped triangle: the first two
** are not closed and answer by the winding number (within WIND_TOL of the
** long double sum, inside where it exceeds 1/2); the flipped one is still
** closed (parity ignores orientation) and answers exactly. */
START_TEST(hole_crack_flip)
{
    ray_vec3 c = v3(0, 0, 0);
    int kind;

    for (kind = 0; kind < 3; kind++) {
        /* The hole one triangle wide. */
        hc_mesh m = damaged(c, kind, 1), orig = hc_icosphere(c, 2);
        ray_scene *s;
        ray_vec3 *pts;
        ray_inside *out;
        ray_contains_options o = {0};
        size_t n, i;

        s = scene_of(&m, 1);
        n = hard_points(&m, c, 300, &pts);
        out = malloc(n * sizeof *out);
        if (kind < 2) {
            /* Nothing closed: the exact answer is refused. */
            ck_assert_int_eq(ray_contains(s, pts, n, NULL, out),
                             -RAY_EDEGENERATE);
            o.flags = RAY_CONTAINS_WINDING | RAY_CONTAINS_WINDING_EXACT;
        }
        ck_assert_int_ge(ray_contains(s, pts, n, &o, out), 0);
        for (i = 0; i < n; i++) {
            int ref = convex_ref(&orig, pts[i]);
            if (kind == 2) {
                ck_assert_int_eq(out[i].inside, ref >= 1);
                ck_assert_int_eq(out[i].on_surface, ref == 1);
                ck_assert(out[i].winding == 0);
            } else {
                double w = winding_ref(&m, pts[i]);
                ck_assert_int_eq(out[i].on_surface, 0);
                if (ref == 1 || near_edge(&m, pts[i]))
                    continue;
                ck_assert_msg(fabs(out[i].winding - w) <= WIND_TOL,
                              "kind %d point %zu: %.17g vs %.17g", kind, i,
                              out[i].winding, w);
                ck_assert_int_eq(out[i].inside, w > 0.5);
            }
        }
        report_err("hole_crack_flip",
                   check_fast(s, &m, pts, n, RAY_CONTAINS_WINDING));
        free(out);
        free(pts);
        ray_scene_free(s);
        hc_mesh_free(&m);
        hc_mesh_free(&orig);
    }
}
END_TEST

/* Mesh m and, beside it, a closed cube (centre c + (6, 0, 0)): ray_contains
** then answers without RAY_CONTAINS_WINDING too, m by the winding number
** (its out.winding m's alone) and the cube by parity, the BVH's nodes
** mixing both classes of triangles (winding.c). */
static ray_scene *scene_with_cube(const hc_mesh *m, ray_vec3 c,
                                  unsigned flags, unsigned *geom,
                                  hc_mesh *cube)
{
    ray_scene *s = NULL;
    ray_mesh rm = hc_ray_mesh(m), rc;

    rm.flags = flags;                    /* RAY_MESH_BORROW or 0 */
    *cube = hc_cube(v3_add(c, v3(6, 0, 0)));
    rc = hc_ray_mesh(cube);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &rm, RAY_NO_MATERIAL, geom), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &rc, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    return s;
}

/* The fast winding number against the long double sum and the exact
** sum's answers (check_fast) on damaged icospheres: the three kinds at
** the origin, the hole at offsets 1e5 and 1e6; every winding number
** (RAY_CONTAINS_WINDING), and the open ones' by default beside a closed
** cube. */
START_TEST(fast_winding_damaged)
{
    static const double off[3] = {0, 1e5, 1e6};
    double worst = 0;
    int k, kind;

    for (k = 0; k < 3; k++)
        for (kind = 0; kind < 3; kind++) {
            ray_vec3 c = v3(off[k], -off[k] * 0.4, off[k] * 0.9);
            hc_mesh m, cube;
            ray_scene *s;
            ray_vec3 *pts;
            size_t n;
            unsigned geom;
            if (k > 0 && kind > 0)
                continue;
            m = damaged(c, kind, 3);
            n = some_points(&m, c, 500, &pts);
            s = scene_of(&m, 1);
            worst = fmax(worst, check_fast(s, &m, pts, n,
                                           RAY_CONTAINS_WINDING));
            ray_scene_free(s);
            if (kind < 2) {
                s = scene_with_cube(&m, c, 0, &geom, &cube);
                worst = fmax(worst, check_fast(s, &m, pts, n, 0));
                ray_scene_free(s);
                hc_mesh_free(&cube);
            }
            free(pts);
            hc_mesh_free(&m);
        }
    report_err("damaged", worst);
}
END_TEST

/* The winding number asked for (RAY_CONTAINS_WINDING_EXACT, ray.h) at
** every hard point of scene s, whose triangles the number sums are
** ref's: within WIND_TOL of the long double sum wherever it is well
** conditioned (vertices, faces and their ulp neighbours, uniform points:
** all but near_edge's), and inside as that sum says (beyond WIND_TOL of
** 1/2; the scenes' cube holds none of these points).  Returns the points
** checked. */
static size_t check_asked(const ray_scene *s, const hc_mesh *ref,
                          const ray_vec3 *pts, size_t n, unsigned flags)
{
    ray_inside *out = malloc(n * sizeof *out);
    ray_contains_options o = {0};
    size_t i, checked = 0;

    o.flags = flags | RAY_CONTAINS_WINDING_EXACT;
    ck_assert_int_ge(ray_contains(s, pts, n, &o, out), 0);
    for (i = 0; i < n; i++) {
        double w;
        if (near_edge(ref, pts[i]))
            continue;
        w = winding_ref(ref, pts[i]);
        ck_assert_msg(fabs(out[i].winding - w) <= WIND_TOL,
                      "point %zu (%.17g, %.17g, %.17g): winding %.17g, "
                      "reference %.17g", i, pts[i].x, pts[i].y, pts[i].z,
                      out[i].winding, w);
        if (fabs(w - 0.5) > WIND_TOL)
            ck_assert_int_eq(out[i].inside, w > 0.5);
        checked++;
    }
    free(out);
    return checked;
}

/* The number asked for on the icosphere with a hole, a crack and a
** flipped triangle (damaged), each at offsets 0, 1e5 and 1e6, at all of
** its hard points: every mesh by the winding number
** (RAY_CONTAINS_WINDING), and, for the two that are not closed, the
** default flags beside a closed cube (the number is then the open
** mesh's alone). */
START_TEST(winding_number_asked)
{
    static const double off[3] = {0, 1e5, 1e6};
    int k, kind;

    for (k = 0; k < 3; k++)
        for (kind = 0; kind < 3; kind++) {
            ray_vec3 c = v3(-off[k] * 0.6, off[k], off[k] * 0.3);
            hc_mesh m = damaged(c, kind, 3), cube;
            ray_scene *s = scene_of(&m, 1);
            ray_vec3 *pts;
            size_t n = hard_points(&m, c, 200, &pts), checked;
            unsigned geom;

            checked = check_asked(s, &m, pts, n, RAY_CONTAINS_WINDING);
            /* Every vertex, face centroid and their ulp neighbours but
            ** those near an edge, and the uniform points. */
            ck_assert_uint_ge(checked, m.nv + 3 * m.nt + 200);
            ray_scene_free(s);
            if (kind < 2) {
                s = scene_with_cube(&m, c, 0, &geom, &cube);
                check_asked(s, &m, pts, n, 0);
                ray_scene_free(s);
                hc_mesh_free(&cube);
            }
            free(pts);
            hc_mesh_free(&m);
        }
}
END_TEST

/* A point at a triangle's rounded centroid lies within rounding of its
** plane, on it: the triangle subtends +-2 pi, the sign the exact
** orientation's (4.6e-18 off the plane here, where a long double
** determinant rounds to zero).  fuzz_winding found the reference taking
** the zero's sign bit instead (winding_ref.h); this is its input, a
** fan of three triangles, and the point moved an ulp across the plane.
** The angle of 2 pi is exact to within atan2's rounding and the
** remaining 1e-17 / |den| of the point's distance to the plane, so one
** triangle's winding number is +-1/2 within 1e-15 (a few ulps of 1/2);
** the fan's is compared with the reference within WIND_TOL. */
START_TEST(winding_number_at_a_rounded_centroid)
{
    /* The first triangle raised by 2 and by 4 along z. */
    static ray_vec3 v[9] = {{0, 0, 0}, {7.8125, -7.8125, -7.875},
                            {-7.5, -7.9375, -7.875}, {0, 0, 2},
                            {7.8125, -7.8125, -5.875},
                            {-7.5, -7.9375, -5.875}, {0, 0, 4},
                            {7.8125, -7.8125, -3.875},
                            {-7.5, -7.9375, -3.875}};
    static unsigned idx[9] = {0, 1, 2, 3, 4, 5, 6, 7, 8};
    hc_mesh one = {v, idx, 3, 1}, fan = {v, idx, 9, 3};
    ray_contains_options o = {0};
    ray_inside out[2];
    ray_vec3 q[2];
    ray_scene *s;
    int i;

    q[0] = v3((0 + 7.8125 - 7.5) / 3, (0 - 7.8125 - 7.9375) / 3,
              (0 - 7.875 - 7.875) / 3);
    q[1] = v3(nextafter(q[0].x, -HUGE_VAL), q[0].y, q[0].z);
    ck_assert(ray__orient3d(v[0], v[1], v[2], q[0]) > 0);
    ck_assert(ray__orient3d(v[0], v[1], v[2], q[1]) < 0);
    o.flags = RAY_CONTAINS_WINDING | RAY_CONTAINS_WINDING_EXACT;
    s = scene_of(&one, 1);
    ck_assert_int_ge(ray_contains(s, q, 2, &o, out), 0);
    ck_assert_double_eq_tol(out[0].winding, 0.5, 1e-15);
    ck_assert_double_eq_tol(out[1].winding, -0.5, 1e-15);
    for (i = 0; i < 2; i++)
        ck_assert_double_eq_tol(winding_ref(&one, q[i]), out[i].winding,
                                WIND_TOL);
    ray_scene_free(s);
    s = scene_of(&fan, 1);
    ck_assert_int_ge(ray_contains(s, q, 2, &o, out), 0);
    for (i = 0; i < 2; i++)
        ck_assert_double_eq_tol(winding_ref(&fan, q[i]), out[i].winding,
                                WIND_TOL);
    ray_scene_free(s);
}
END_TEST

/* The same on a soup of 200 random triangles (offsets 0 and 1e6) beside
** a closed cube, and on the finer icosphere of level 3 with a hole at
** 1000 uniform points, where the largest error was seen (FAST_TOL). */
START_TEST(fast_winding_soup)
{
    static const double off[2] = {0, 1e6};
    double worst = 0;
    int k;

    for (k = 0; k < 2; k++) {
        ray_vec3 c = v3(off[k] * 0.5, off[k], -off[k] * 0.2);
        rng g = {77};
        hc_mesh m, cube;
        unsigned geom;
        ray_scene *s;
        ray_vec3 *pts;
        size_t i, n;
        m.nt = 200;
        m.nv = 3 * m.nt;
        m.v = malloc(m.nv * sizeof *m.v);
        m.idx = malloc(3 * m.nt * sizeof *m.idx);
        for (i = 0; i < m.nt; i++) {
            ray_vec3 a = v3(rng_range(&g, -1, 1), rng_range(&g, -1, 1),
                            rng_range(&g, -1, 1));
            int j;
            for (j = 0; j < 3; j++) {
                m.v[3 * i + (size_t)j] =
                    v3_add(c, v3_add(a, v3(rng_range(&g, -0.3, 0.3),
                                           rng_range(&g, -0.3, 0.3),
                                           rng_range(&g, -0.3, 0.3))));
                m.idx[3 * i + (size_t)j] = (unsigned)(3 * i + (size_t)j);
            }
        }
        s = scene_with_cube(&m, c, 0, &geom, &cube);
        n = some_points(&m, c, 1000, &pts);
        worst = fmax(worst, check_fast(s, &m, pts, n, 0));
        free(pts);
        ray_scene_free(s);
        hc_mesh_free(&m);
        hc_mesh_free(&cube);
    }
    {
        hc_mesh m = hc_icosphere(v3(0, 0, 0), 3), cube;
        ray_vec3 *pts;
        size_t n;
        unsigned geom;
        ray_scene *s;
        m.nt -= 3;
        s = scene_with_cube(&m, v3(0, 0, 0), 0, &geom, &cube);
        n = hard_points(&m, v3(0, 0, 0), 1000, &pts);
        worst = fmax(worst, check_fast(s, &m, pts + (n - 1000), 1000, 0));
        free(pts);
        ray_scene_free(s);
        hc_mesh_free(&m);
        hc_mesh_free(&cube);
    }
    report_err("soup", worst);
}
END_TEST

/* v's image under the 3 x 4 transform t. */
static ray_vec3 xfm_point(const ray_transform *t, ray_vec3 v)
{
    const double (*m)[4] = t->m;

    return v3(m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z + m[0][3],
              m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z + m[1][3],
              m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z + m[2][3]);
}

/* Through instances: a holed icosphere placed three times, by a rotation
** with a uniform scale, by a shear with a non-uniform scale and a mirror
** (det < 0: its faces turn inward), and by a translation alone, far from
** the origin; the reference
** is the long double sum over both images' triangles in world space
** (the expansions are taken to world space, winding.c). */
START_TEST(fast_winding_instances)
{
    hc_mesh m = damaged(v3(0, 0, 0), 0, 3), ref;
    ray_scene *child = scene_of(&m, 1), *s = NULL;
    ray_transform t[3] = {{{{0, -1.5, 0, 1e5}, {1.5, 0, 0, 2}, {0, 0, 1.5, 3}}},
                          {{{2, 0.5, 0, 1e5 + 7}, {0, -0.5, 0.3, 1},
                            {0.2, 0, 1, 3}}},
                          {{{1, 0, 0, 1e5 - 6}, {0, 1, 0, 2}, {0, 0, 1, 4}}}};
    ray_vec3 *pts;
    size_t n, i;
    int k;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ref.nv = 3 * m.nv;
    ref.nt = 3 * m.nt;
    ref.v = malloc(ref.nv * sizeof *ref.v);
    ref.idx = malloc(3 * ref.nt * sizeof *ref.idx);
    for (k = 0; k < 3; k++) {
        ck_assert_int_eq(ray_scene_add_instance(s, child, &t[k], NULL),
                         RAY_OK);
        for (i = 0; i < m.nv; i++)
            ref.v[(size_t)k * m.nv + i] = xfm_point(&t[k], m.v[i]);
        for (i = 0; i < 3 * m.nt; i++)
            ref.idx[(size_t)k * 3 * m.nt + i] =
                m.idx[i] + (unsigned)((size_t)k * m.nv);
    }
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    n = some_points(&ref, v3(1e5 + 3, 2, 3), 1000, &pts);
    report_err("instances", check_fast(s, &ref, pts, n, RAY_CONTAINS_WINDING));
    free(pts);
    ray_scene_free(s);
    ray_scene_free(child);
    hc_mesh_free(&m);
    hc_mesh_free(&ref);
}
END_TEST

/* An update that moves an open mesh's vertices or changes its indices
** makes the next query's expansions anew: the fast
** answers follow the brute force of the mesh as it is now, at points
** that the mesh left and entered. */
START_TEST(fast_winding_follows_updates)
{
    int borrow;

    for (borrow = 0; borrow < 2; borrow++) {
        hc_mesh m = damaged(v3(0, 0, 0), 0, 3), cube;
        ray_mesh rm = hc_ray_mesh(&m);
        ray_scene *s;
        ray_vec3 *pts;
        size_t n, i;
        unsigned geom;
        int step;

        rm.flags = borrow ? RAY_MESH_BORROW : 0;
        s = scene_with_cube(&m, v3(0, 0, 0), rm.flags, &geom, &cube);
        for (step = 0; step < 3; step++) {
            n = some_points(&m, v3(1.5 * step, 0, 0), 300, &pts);
            report_err("updates", check_fast(s, &m, pts, n, 0));
            free(pts);
            if (step == 0) {            /* moved and squashed: a refit */
                for (i = 0; i < m.nv; i++)
                    m.v[i] = v3(m.v[i].x * 0.5 + 3, m.v[i].y, m.v[i].z);
            } else {                    /* new indices: two triangles
                                           turned into copies of a third */
                for (i = 0; i < 6; i++)
                    m.idx[i] = m.idx[3 * (5 + (size_t)step) + i % 3];
            }
            ck_assert_int_eq(ray_scene_update_mesh(s, geom,
                                                   borrow ? NULL : &rm),
                             RAY_OK);
            ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        }
        ray_scene_free(s);
        hc_mesh_free(&m);
        hc_mesh_free(&cube);
    }
}
END_TEST

/* Solids and instances: a sphere, a box and a capsule count as solids;
** an instance counts its child's closed mesh at the point taken into its
** space; masks leave geometry out; disabled geometry is not counted. */
START_TEST(solids_instances_masks)
{
    hc_mesh cube = hc_cube(v3(0, 0, 0));
    ray_scene *child = scene_of(&cube, 1), *s = NULL;
    ray_transform t;
    ray_box_params b = {{10, 0, 0}, {1, 2, 3}, {1, 1, 0}, {-1, 1, 0}};
    ray_capsule_params cap = {{0, 10, 0}, {0, 14, 0}, 0.5};
    ray_contains_options o = {0};
    unsigned sphere, inst;
    ray_inside r;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, v3(-10, 0, 0), 2, RAY_NO_MATERIAL, &sphere),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_add_box(s, &b, RAY_NO_MATERIAL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_capsule(s, &cap, RAY_NO_MATERIAL, NULL), RAY_OK);
    ray_transform_identity(&t);
    t.m[0][0] = 2;                    /* x scaled by 2, moved to z = 20 */
    t.m[2][3] = 20;
    ck_assert_int_eq(ray_scene_add_instance(s, child, &t, &inst), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_contains(s, &(ray_vec3){-10, 1.9, 0}, 1, NULL, &r),
                     1);
    ck_assert_int_eq(r.on_surface, 0);
    ck_assert_int_eq(ray_contains(s, &(ray_vec3){-10, 2.1, 0}, 1, NULL, NULL),
                     0);
    /* The box's axes are x + y and y - x: (10.7, 0.7) is 0.99 along x. */
    ck_assert_int_eq(ray_contains(s, &(ray_vec3){10.7, 0.7, 0}, 1, NULL,
                                  NULL), 1);
    ck_assert_int_eq(ray_contains(s, &(ray_vec3){10.75, 0.75, 0}, 1, NULL,
                                  NULL), 0);
    ck_assert_int_eq(ray_contains(s, &(ray_vec3){0.4, 14.2, 0}, 1, NULL,
                                  NULL), 1);
    ck_assert_int_eq(ray_contains(s, &(ray_vec3){0.4, 14.4, 0}, 1, NULL,
                                  NULL), 0);
    /* The instance: x in [-2, 2], z in [19, 21]; its corner exactly. */
    ck_assert_int_eq(ray_contains(s, &(ray_vec3){1.9, 0, 20.5}, 1, NULL,
                                  NULL), 1);
    ck_assert_int_eq(ray_contains(s, &(ray_vec3){2.1, 0, 20.5}, 1, NULL,
                                  NULL), 0);
    ck_assert_int_eq(ray_contains(s, &(ray_vec3){2, 1, 21}, 1, NULL, &r), 1);
    ck_assert_int_eq(r.on_surface, 1);
    /* Masks: the sphere hidden by ignore_mask, then disabled. */
    ck_assert_int_eq(ray_scene_set_mask(s, sphere, 4u), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    o.ignore_mask = 4u;
    ck_assert_int_eq(ray_contains(s, &(ray_vec3){-10, 0, 0}, 1, &o, NULL), 0);
    ck_assert_int_eq(ray_contains(s, &(ray_vec3){-10, 0, 0}, 1, NULL, NULL),
                     1);
    ck_assert_int_eq(ray_scene_set_enabled(s, sphere, 0), RAY_OK);
    ck_assert_int_eq(ray_contains(s, &(ray_vec3){-10, 0, 0}, 1, NULL, NULL),
                     -RAY_ESTATE);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_contains(s, &(ray_vec3){-10, 0, 0}, 1, NULL, NULL),
                     0);
    /* The child changed and not re-committed in s: stale. */
    ck_assert_int_eq(ray_scene_set_enabled(child, 0, 0), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    ck_assert_int_eq(ray_contains(s, &(ray_vec3){0, 0, 0}, 1, NULL, &r),
                     -RAY_ESTATE);
    ray_scene_free(s);
    ray_scene_free(child);
    hc_mesh_free(&cube);
}
END_TEST

START_TEST(misuse)
{
    hc_mesh cube = hc_cube(v3(0, 0, 0));
    ray_scene *s = scene_of(&cube, 0), *empty = NULL;
    ray_vec3 p[2] = {{0, 0, 0}, {0, 0, 0}};
    ray_inside r = {7, 7, 7.0};
    ray_contains_options o = {0};
    double d = 42;

    ck_assert_int_eq(ray_contains(s, p, 1, NULL, &r), -RAY_ESTATE);
    ck_assert_int_eq(ray_signed_distance(s, p[0], HUGE_VAL, NULL, &d, NULL),
                     -RAY_ESTATE);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_contains(NULL, p, 1, NULL, &r), -RAY_EINVAL);
    ck_assert_int_eq(ray_contains(s, NULL, 1, NULL, &r), -RAY_EINVAL);
    ck_assert_int_eq(ray_contains(s, NULL, 0, NULL, NULL), 0);
    p[1].y = (double)NAN;
    ck_assert_int_eq(ray_contains(s, p, 2, NULL, &r), -RAY_EINVAL);
    p[1].y = HUGE_VAL;
    ck_assert_int_eq(ray_contains(s, p, 2, NULL, &r), -RAY_EINVAL);
    o.flags = 4;
    ck_assert_int_eq(ray_contains(s, p, 1, &o, &r), -RAY_EINVAL);
    ck_assert_int_eq(ray_signed_distance(s, p[1], HUGE_VAL, NULL, &d, NULL),
                     -RAY_EINVAL);
    ck_assert_int_eq(ray_signed_distance(s, p[0], HUGE_VAL, NULL, NULL,
                                         NULL), -RAY_EINVAL);
    ck_assert_int_eq(ray_signed_distance(s, p[0], -1, NULL, &d, NULL),
                     -RAY_EINVAL);
    /* Nothing written on failure. */
    ck_assert_int_eq(r.inside, 7);
    ck_assert(d == 42);
    /* A scene with nothing closed: refused, unless the winding number is
    ** asked for (0 everywhere in an empty scene). */
    ck_assert_int_eq(ray_scene_new(&empty, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(empty), RAY_OK);
    ck_assert_int_eq(ray_contains(empty, p, 1, NULL, &r), -RAY_EDEGENERATE);
    o.flags = RAY_CONTAINS_WINDING;
    ck_assert_int_eq(ray_contains(empty, p, 1, &o, &r), 0);
    ck_assert(r.winding == 0 && r.inside == 0 && r.on_surface == 0);
    ck_assert_int_eq(ray_signed_distance(empty, p[0], 5, &o, &d, NULL), 0);
    ck_assert(d == 5);
    ray_scene_free(empty);
    ray_scene_free(s);
    hc_mesh_free(&cube);
}
END_TEST

/* Signed distance: the closest point's distance, negative inside, 0 on
** the surface, +-radius beyond it.  The cube's distances are exact in
** double here (axis-aligned faces, distances of small integers and
** halves), so they are compared exactly. */
START_TEST(signed_distance)
{
    hc_mesh cube = hc_cube(v3(0, 0, 0));
    ray_scene *s = scene_of(&cube, 1);
    ray_closest c;
    double d;

    ck_assert_int_eq(ray_signed_distance(s, v3(0, 0, 0), HUGE_VAL, NULL, &d,
                                         &c), 1);
    ck_assert(d == -1 && c.distance == 1);
    ck_assert_int_eq(ray_signed_distance(s, v3(0.5, 0, 0), HUGE_VAL, NULL,
                                         &d, NULL), 1);
    ck_assert(d == -0.5);
    ck_assert_int_eq(ray_signed_distance(s, v3(3, 0, 0), HUGE_VAL, NULL, &d,
                                         NULL), 1);
    ck_assert(d == 2);
    ck_assert_int_eq(ray_signed_distance(s, v3(1, 1, -1), HUGE_VAL, NULL, &d,
                                         NULL), 1);
    ck_assert(d == 0 && !signbit(d));
    ck_assert_int_eq(ray_signed_distance(s, v3(0, 0, 0), 0.5, NULL, &d,
                                         NULL), 0);
    ck_assert(d == -0.5);
    ck_assert_int_eq(ray_signed_distance(s, v3(5, 0, 0), 0.5, NULL, &d,
                                         NULL), 0);
    ck_assert(d == 0.5);
    ray_scene_free(s);
    hc_mesh_free(&cube);
}
END_TEST

/* The predicates: exact signs where double rounding would lose them. */
START_TEST(predicates)
{
    double e = 0x1p-52;

    /* Three points on the line y = x, one an ulp off it. */
    ck_assert(ray__orient2d(0.5, 0.5, 12, 12, 24, 24) == 0);
    ck_assert(ray__orient2d(0.5, 0.5 + e, 12, 12, 24, 24) > 0);
    ck_assert(ray__orient2d(0.5, 0.5 - e / 2, 12, 12, 24, 24) < 0);
    ck_assert(ray__orient3d(v3(1, 0, 0), v3(0, 1, 0), v3(0, 0, 1),
                            v3(0, 0, 0)) > 0);
    ck_assert(ray__orient3d(v3(1e6 + 1, 1e6, 1e6), v3(1e6, 1e6 + 1, 1e6),
                            v3(1e6, 1e6, 1e6 + 1),
                            v3(1e6 + 1.0 / 3, 1e6 + 1.0 / 3,
                               1e6 + 1.0 / 3)) != 0);
    ck_assert(ray__orient3d(v3(0.1, 0.2, 0.3), v3(0.4, 0.5, 0.6),
                            v3(0.7, 0.8, 0.9), v3(1.0, 1.1, 1.2)) ==
              -ray__orient3d(v3(0.4, 0.5, 0.6), v3(0.1, 0.2, 0.3),
                             v3(0.7, 0.8, 0.9), v3(1.0, 1.1, 1.2)));
}
END_TEST

/* A scheduler that runs the tasks backwards on the calling thread: task
** order must not change a byte. */
static void run_backwards(void *ud, unsigned count, ray_task_fn task,
                          void *task_ud)
{
    unsigned i;

    (void)ud;
    for (i = count; i-- > 0;)
        task(task_ud, i);
}

/* Sample (i, j, k) of an nx x ny x nz grid over [lo, hi], as
** ray_distance_grid places it (ray.h). */
static ray_vec3 grid_point(ray_vec3 lo, ray_vec3 hi, unsigned nx, unsigned ny,
                           unsigned nz, unsigned i, unsigned j, unsigned k)
{
    return v3(lo.x + (hi.x - lo.x) / (nx - 1) * i,
              lo.y + (hi.y - lo.y) / (ny - 1) * j,
              lo.z + (hi.z - lo.z) / (nz - 1) * k);
}

/* The grid: each sample is ray_signed_distance at its point rounded to
** float (compared exactly: the same computation), the same bytes on 1
** and 3 threads and in reverse task order; a narrow band clamps to
** +-band; misuse writes nothing. */
START_TEST(distance_grid)
{
    hc_mesh m = hc_icosphere(v3(0.25, 0, 0), 2);
    ray_scene *s = scene_of(&m, 1);
    enum { NX = 13, NY = 9, NZ = 7, N = NX * NY * NZ };
    float *a = malloc(N * sizeof *a), *b = malloc(N * sizeof *b);
    ray_distance_grid_options o = {0};
    ray_scheduler sched = {run_backwards, NULL, 0};
    ray_vec3 lo = v3(-3, -2.5, -2.2), hi = v3(3, 2.5, 2.2);
    unsigned i, j, k;

    o.threads = 1;
    ck_assert_int_eq(ray_distance_grid(s, lo, hi, NX, NY, NZ, &o, a), RAY_OK);
    for (k = 0; k < NZ; k++)
        for (j = 0; j < NY; j++)
            for (i = 0; i < NX; i++) {
                ray_vec3 p = grid_point(lo, hi, NX, NY, NZ, i, j, k);
                double d;
                ck_assert_int_eq(ray_signed_distance(s, p, HUGE_VAL, NULL,
                                                     &d, NULL), 1);
                ck_assert(a[(k * NY + j) * NX + i] == (float)d);
            }
    o.threads = 3;
    ck_assert_int_eq(ray_distance_grid(s, lo, hi, NX, NY, NZ, &o, b), RAY_OK);
    ck_assert(memcmp(a, b, N * sizeof *a) == 0);
    o.scheduler = &sched;
    memset(b, 0, N * sizeof *b);
    ck_assert_int_eq(ray_distance_grid(s, lo, hi, NX, NY, NZ, &o, b), RAY_OK);
    ck_assert(memcmp(a, b, N * sizeof *a) == 0);
    /* The narrow band: within it the same values, beyond it +-band. */
    o.band = 0.5;
    ck_assert_int_eq(ray_distance_grid(s, lo, hi, NX, NY, NZ, &o, b), RAY_OK);
    for (i = 0; i < N; i++)
        ck_assert(fabsf(a[i]) <= 0.5f ? b[i] == a[i]
                                      : b[i] == (a[i] < 0 ? -0.5f : 0.5f));
    /* Misuse: nothing written. */
    memset(b, 0, N * sizeof *b);
    o.band = -1;
    ck_assert_int_eq(ray_distance_grid(s, lo, hi, NX, NY, NZ, &o, b),
                     RAY_EINVAL);
    ck_assert_int_eq(ray_distance_grid(s, lo, hi, 0, NY, NZ, NULL, b),
                     RAY_EINVAL);
    ck_assert_int_eq(ray_distance_grid(s, v3((double)NAN, 0, 0), hi, NX, NY, NZ,
                                       NULL, b), RAY_EINVAL);
    ck_assert_int_eq(ray_distance_grid(s, lo, hi, 1u << 30, 1u << 30, 64,
                                       NULL, b), RAY_EINVAL);
    ck_assert_int_eq(ray_distance_grid(NULL, lo, hi, NX, NY, NZ, NULL, b),
                     RAY_EINVAL);
    for (i = 0; i < N; i++)
        ck_assert(b[i] == 0);
    free(a);
    free(b);
    ray_scene_free(s);
    hc_mesh_free(&m);
}
END_TEST

/* Each sample's search starts within the distance to the row's previous
** sample's point (grid.c: warm_radius), which must not change a bit:
** every sample of a finer grid, whose rows cross the surface many times,
** equals its own search from the band (or the whole scene), near the
** origin and 2^17 away (the closest points' roundings there are what
** the radius' margin covers). */
START_TEST(distance_grid_warm_start)
{
    static const double offsets[2] = {0, 0x1p17};
    enum { NX = 41, NY = 17, NZ = 5, N = NX * NY * NZ };
    float *a = malloc(N * sizeof *a);
    int f, b;

    for (f = 0; f < 2; f++) {
        ray_vec3 c = v3(offsets[f], -offsets[f], 0.5 * offsets[f]);
        hc_mesh m = hc_icosphere(c, 3);
        ray_scene *s = scene_of(&m, 1);
        ray_vec3 lo = v3_add(c, v3(-2.6, -2.3, -0.4));
        ray_vec3 hi = v3_add(c, v3(2.6, 2.3, 0.4));
        for (b = 0; b < 2; b++) {
            ray_distance_grid_options o = {0};
            double radius = b ? 0.3 : HUGE_VAL;
            unsigned i, j, k;
            o.threads = 1;
            o.band = b ? radius : 0;
            ck_assert_int_eq(ray_distance_grid(s, lo, hi, NX, NY, NZ, &o, a),
                             RAY_OK);
            for (k = 0; k < NZ; k++)
                for (j = 0; j < NY; j++)
                    for (i = 0; i < NX; i++) {
                        ray_vec3 p = grid_point(lo, hi, NX, NY, NZ, i,
                                                j, k);
                        double d;
                        ck_assert_int_ge(ray_signed_distance(s, p, radius,
                                                             NULL, &d, NULL),
                                         0);
                        ck_assert(a[(k * NY + j) * NX + i] == (float)d);
                    }
        }
        ray_scene_free(s);
        hc_mesh_free(&m);
    }
    free(a);
}
END_TEST

/*
** The grid of labels (scene/parity.c) against brute force, for a mesh m
** in scene s (its only geometry): a cell is marked touched exactly when
** some triangle's closed box meets its closed box (exact comparisons of
** the mesh's doubles with the walls), and an untouched cell's label is
** the brute-force parity at its centre and at each of its eight corners
** (points of the closed cell, none on the surface).  Returns how many
** untouched cells are inside.
*/
static size_t check_grid_labels(const hc_mesh *m, const ray_scene *s)
{
    const ray__cgrid *g = &s->cgrid;
    size_t inside = 0, untouched = 0;
    unsigned i, j, k, t, c;

    /* The first ray_contains builds the grid. */
    ck_assert_int_ge(ray_contains(s, NULL, 0, NULL, NULL), 0);
    ck_assert_uint_gt(g->n[0], 0);
    for (k = 0; k < g->n[2]; k++)
        for (j = 0; j < g->n[1]; j++)
            for (i = 0; i < g->n[0]; i++) {
                double lo[3] = {g->wall[0][i], g->wall[1][j], g->wall[2][k]};
                double hi[3] = {g->wall[0][i + 1], g->wall[1][j + 1],
                                g->wall[2][k + 1]};
                unsigned char label =
                    g->label[((size_t)k * g->n[1] + j) * g->n[0] + i];
                int touched = 0;
                for (t = 0; t < m->nt && !touched; t++) {
                    ray_vec3 a = m->v[m->idx[3 * t]], b = m->v[m->idx[3 * t + 1]];
                    ray_vec3 cc = m->v[m->idx[3 * t + 2]];
                    double tl[3] = {fmin(a.x, fmin(b.x, cc.x)),
                                    fmin(a.y, fmin(b.y, cc.y)),
                                    fmin(a.z, fmin(b.z, cc.z))};
                    double th[3] = {fmax(a.x, fmax(b.x, cc.x)),
                                    fmax(a.y, fmax(b.y, cc.y)),
                                    fmax(a.z, fmax(b.z, cc.z))};
                    touched = tl[0] <= hi[0] && th[0] >= lo[0] &&
                              tl[1] <= hi[1] && th[1] >= lo[1] &&
                              tl[2] <= hi[2] && th[2] >= lo[2];
                }
                ck_assert_msg((label == 0) == touched,
                              "cell (%u, %u, %u): label %u, touched %d", i,
                              j, k, label, touched);
                if (touched)
                    continue;
                untouched++;
                inside += label == 2;
                ck_assert_int_eq(parity_ref(m, v3(0.5 * (lo[0] + hi[0]),
                                                  0.5 * (lo[1] + hi[1]),
                                                  0.5 * (lo[2] + hi[2]))),
                                 label - 1);
                for (c = 0; c < 8; c++)
                    ck_assert_int_eq(parity_ref(m, v3(c & 1 ? hi[0] : lo[0],
                                                      c & 2 ? hi[1] : lo[1],
                                                      c & 4 ? hi[2] : lo[2])),
                                     label - 1);
            }
    ck_assert_uint_gt(untouched, 0);
    return inside;
}

/* The grid's cells' corners and points on its walls (where the cell
** index and the row's walk change), in s holding convex mesh m alone:
** ray_contains as the faces' signs say. */
static void check_grid_walls(const hc_mesh *m, const ray_scene *s)
{
    const ray__cgrid *g = &s->cgrid;
    rng r = {3939};
    unsigned n, i;

    for (n = 0; n < 400; n++) {
        unsigned j = (unsigned)(rng_unit(&r) * (g->n[1] + 1));
        unsigned k = (unsigned)(rng_unit(&r) * (g->n[2] + 1));
        j = j > g->n[1] ? g->n[1] : j;
        k = k > g->n[2] ? g->n[2] : k;
        for (i = 0; i <= g->n[0]; i++) {
            /* A corner, then a point of the wall x = wall[i]. */
            ray_vec3 q[2];
            int p;
            q[0] = v3(g->wall[0][i], g->wall[1][j], g->wall[2][k]);
            q[1] = v3(g->wall[0][i],
                      rng_range(&r, g->wall[1][0], g->wall[1][g->n[1]]),
                      rng_range(&r, g->wall[2][0], g->wall[2][g->n[2]]));
            for (p = 0; p < 2; p++) {
                ray_inside out;
                int ref = convex_ref(m, q[p]);
                ck_assert_int_ge(ray_contains(s, &q[p], 1, NULL, &out), 0);
                ck_assert_msg(out.inside == (ref >= 1) &&
                                  out.on_surface == (ref == 1),
                              "(%.17g, %.17g, %.17g): inside %d on %d, "
                              "reference %d", q[p].x, q[p].y, q[p].z,
                              out.inside, out.on_surface, ref);
            }
        }
    }
}

/* The grid of labels: exact labels and marks for a cube, icospheres at
** offsets and the nested cubes; corners and walls of the cells answered
** exactly. */
START_TEST(grid_labels)
{
    static const double off[3] = {0, 1e5, 1e6};
    hc_mesh a = hc_cube(v3(0, 0, 0)), b = hc_cube(v3(3, 0.5, 0.25)), m;
    ray_scene *s;
    size_t i, k;

    for (k = 0; k < 3; k++) {
        ray_vec3 c = v3(off[k] * 0.3, off[k], -off[k]);
        hc_mesh ico = hc_icosphere(c, 2), cube = hc_cube(c);
        s = scene_of(&ico, 1);
        ck_assert_uint_gt(check_grid_labels(&ico, s), 0);
        check_grid_walls(&ico, s);
        ray_scene_free(s);
        s = scene_of(&cube, 1);
        ck_assert_uint_gt(check_grid_labels(&cube, s), 0);
        check_grid_walls(&cube, s);
        ray_scene_free(s);
        hc_mesh_free(&ico);
        hc_mesh_free(&cube);
    }
    /* The nested cubes: inside, outside (the nested one's inside), apart. */
    m.nv = 3 * 8;
    m.nt = 3 * 12;
    m.v = malloc(m.nv * sizeof *m.v);
    m.idx = malloc(3 * m.nt * sizeof *m.idx);
    for (i = 0; i < 8; i++) {
        m.v[i] = a.v[i];
        m.v[8 + i] = b.v[i];
        m.v[16 + i] = v3_scale(a.v[i], 0.5);
    }
    for (k = 0; k < 3; k++)
        for (i = 0; i < 36; i++)
            m.idx[36 * k + i] = a.idx[i] + (unsigned)(8 * k);
    s = scene_of(&m, 1);
    ck_assert_uint_gt(check_grid_labels(&m, s), 0);
    ray_scene_free(s);
    hc_mesh_free(&a);
    hc_mesh_free(&b);
    hc_mesh_free(&m);
}
END_TEST

/* Two closed meshes in one scene (a cube and an icosphere that overlap:
** by parity their common part is outside), against the brute force over
** both; with one left out by the query's mask (the labels do not apply:
** the whole ray, over the other alone); after the cube moves
** (ray_scene_update_mesh and a commit: a refit, which drops the grid, so
** the whole ray again). */
START_TEST(grid_masks_and_updates)
{
    hc_mesh cube = hc_cube(v3(0, 0, 0)), ico = hc_icosphere(v3(1.2, 0.3, 0.1), 2);
    hc_mesh both;
    ray_mesh rc = hc_ray_mesh(&cube), ri = hc_ray_mesh(&ico);
    ray_contains_options o = {0};
    ray_scene *s = NULL;
    ray_vec3 *pts, *pi;
    ray_inside *out;
    unsigned gc, gi;
    size_t n, ni, i, pass;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &rc, RAY_NO_MATERIAL, &gc), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &ri, RAY_NO_MATERIAL, &gi), RAY_OK);
    ck_assert_int_eq(ray_scene_set_mask(s, gi, 2u), RAY_OK);
    both.nv = cube.nv + ico.nv;
    both.nt = cube.nt + ico.nt;
    both.v = malloc(both.nv * sizeof *both.v);
    both.idx = malloc(3 * both.nt * sizeof *both.idx);
    for (pass = 0; pass < 2; pass++) {
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        /* Built by the first ray_contains after a rebuild, not by the
        ** commit; never after a refit (pass 1). */
        ck_assert_uint_eq(s->cgrid.n[0], 0);
        ck_assert_int_eq(ray_contains(s, NULL, 0, NULL, NULL), 0);
        ck_assert_int_eq(s->cgrid.n[0] > 0, pass == 0);
        memcpy(both.v, cube.v, cube.nv * sizeof *both.v);
        memcpy(both.v + cube.nv, ico.v, ico.nv * sizeof *both.v);
        memcpy(both.idx, cube.idx, 3 * cube.nt * sizeof *both.idx);
        for (i = 0; i < 3 * ico.nt; i++)
            both.idx[3 * cube.nt + i] = ico.idx[i] + (unsigned)cube.nv;
        n = hard_points(&cube, v3(0, 0, 0), 3000, &pts);
        ni = hard_points(&ico, v3(1.2, 0.3, 0.1), 0, &pi);
        pts = realloc(pts, (n + ni) * sizeof *pts);
        memcpy(pts + n, pi, ni * sizeof *pi);
        n += ni;
        out = malloc(n * sizeof *out);
        o.ignore_mask = 0;
        ck_assert_int_ge(ray_contains(s, pts, n, &o, out), 0);
        for (i = 0; i < n; i++) {
            int on = convex_ref(&cube, pts[i]) == 1 ||
                     convex_ref(&ico, pts[i]) == 1;
            ck_assert_int_eq(out[i].on_surface, on);
            ck_assert_msg(out[i].inside == (on || parity_ref(&both, pts[i])),
                          "pass %zu point %zu", pass, i);
        }
        o.ignore_mask = 2u;                 /* the icosphere left out */
        ck_assert_int_ge(ray_contains(s, pts, n, &o, out), 0);
        for (i = 0; i < n; i++) {
            int ref = convex_ref(&cube, pts[i]);
            ck_assert_int_eq(out[i].on_surface, ref == 1);
            ck_assert_int_eq(out[i].inside, ref >= 1);
        }
        free(out);
        free(pts);
        free(pi);
        /* The cube moves by (0.3, -0.2, 0.1). */
        for (i = 0; i < cube.nv; i++)
            cube.v[i] = v3_add(cube.v[i], v3(0.3, -0.2, 0.1));
        ck_assert_int_eq(ray_scene_update_mesh(s, gc, &rc), RAY_OK);
    }
    ray_scene_free(s);
    hc_mesh_free(&cube);
    hc_mesh_free(&ico);
    hc_mesh_free(&both);
}
END_TEST

/* Closedness by brute force: every undirected edge of a triangle (both
** ends one index: no edge) used an even number of times, counted over
** all corners, O(n^2) (the definition closed.c's buckets compute). */
static int closed_brute(const unsigned *idx, size_t n_tris)
{
    size_t n = 3 * n_tris, i, j, edges = 0;

    for (i = 0; i < n; i++) {
        unsigned p = idx[i], q = idx[i % 3 == 2 ? i - 2 : i + 1];
        size_t uses = 0;
        if (p == q)
            continue;
        edges++;
        for (j = 0; j < n; j++) {
            unsigned a = idx[j], b = idx[j % 3 == 2 ? j - 2 : j + 1];
            uses += (a == p && b == q) || (a == q && b == p);
        }
        if (uses % 2 != 0)
            return 0;
    }
    return edges > 0;
}

/* ray__mesh_closed against the brute force on random index lists over
** few vertices (many repeated edges, degenerate triangles, fans of more
** than 32 edges at one vertex: closed.c's qsort buckets), half of them
** made even by repeating every triangle, some by repeating it flipped. */
START_TEST(closedness_matches_brute_force)
{
    static unsigned idx[2 * 3 * 120];
    rng g = {12345};
    ray_scene *s;
    int trial, closed_seen = 0, open_seen = 0;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    for (trial = 0; trial < 400; trial++) {
        size_t n_tris = 1 + rng_next(&g) % 60, k, nv = 2 + rng_next(&g) % 40;
        int closed = -1;
        for (k = 0; k < 3 * n_tris; k++)
            idx[k] = (unsigned)(rng_next(&g) % nv);
        if (trial % 2 == 0) {          /* every edge twice: closed */
            for (k = 0; k < n_tris; k++) {
                int flip = (int)(rng_next(&g) % 2);
                idx[3 * (n_tris + k)] = idx[3 * k];
                idx[3 * (n_tris + k) + 1] = idx[3 * k + (flip ? 2 : 1)];
                idx[3 * (n_tris + k) + 2] = idx[3 * k + (flip ? 1 : 2)];
            }
            n_tris *= 2;
        }
        ck_assert_int_eq(ray__mesh_closed(s, idx, n_tris, &closed), RAY_OK);
        ck_assert_int_eq(closed, closed_brute(idx, n_tris));
        closed_seen += closed;
        open_seen += !closed;
    }
    /* Both answers met, so neither path went untested. */
    ck_assert_int_gt(closed_seen, 100);
    ck_assert_int_gt(open_seen, 100);
    ray_scene_free(s);
}
END_TEST

/* An update that changes a mesh's indices changes whether it is closed:
** a cube whose triangle 0 is replaced by a copy of triangle 1 has edges
** used an odd number of times, so nothing in the scene answers exactly
** (-RAY_EDEGENERATE without RAY_CONTAINS_WINDING), and restoring the
** indices closes it again.  Mesh copied and borrowed alike; geometry
** unchanged, so only the closedness can change the answer. */
START_TEST(update_changes_closedness)
{
    int borrow;

    for (borrow = 0; borrow < 2; borrow++) {
        hc_mesh cube = hc_cube(v3(0, 0, 0));
        ray_mesh rm = hc_ray_mesh(&cube);
        ray_vec3 centre = v3(0.1, 0.2, 0.3);
        unsigned saved[3], geom;
        ray_scene *s = NULL;
        ray_inside in;
        int k;

        rm.flags = borrow ? RAY_MESH_BORROW : 0;
        ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_mesh(s, &rm, RAY_NO_MATERIAL, &geom),
                         RAY_OK);
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        ck_assert_int_eq(ray_contains(s, &centre, 1, NULL, &in), 1);
        for (k = 0; k < 3; k++) {
            saved[k] = cube.idx[k];
            cube.idx[k] = cube.idx[3 + k];
        }
        ck_assert_int_eq(ray_scene_update_mesh(s, geom, borrow ? NULL : &rm),
                         RAY_OK);
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        ck_assert_int_eq(ray_contains(s, &centre, 1, NULL, &in),
                         -RAY_EDEGENERATE);
        for (k = 0; k < 3; k++)
            cube.idx[k] = saved[k];
        ck_assert_int_eq(ray_scene_update_mesh(s, geom, borrow ? NULL : &rm),
                         RAY_OK);
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        ck_assert_int_eq(ray_contains(s, &centre, 1, NULL, &in), 1);
        ray_scene_free(s);
        hc_mesh_free(&cube);
    }
}
END_TEST

Suite *contains_suite(void)
{
    Suite *s = suite_create("contains");
    TCase *tc = tcase_create("core");

    tcase_add_test(tc, predicates);
    tcase_add_test(tc, cube_at_offsets);
    tcase_add_test(tc, icosphere_at_offsets);
    tcase_add_test(tc, contains_box_wider_than_dbl_max);
    tcase_add_test(tc, nested_and_apart);
    tcase_add_test(tc, hole_crack_flip);
    tcase_add_test(tc, fast_winding_damaged);
    tcase_add_test(tc, fast_winding_soup);
    tcase_add_test(tc, winding_number_asked);
    tcase_add_test(tc, winding_number_at_a_rounded_centroid);
    tcase_add_test(tc, fast_winding_instances);
    tcase_add_test(tc, fast_winding_follows_updates);
    tcase_add_test(tc, solids_instances_masks);
    tcase_add_test(tc, misuse);
    tcase_add_test(tc, signed_distance);
    tcase_add_test(tc, distance_grid);
    tcase_add_test(tc, distance_grid_warm_start);
    tcase_add_test(tc, grid_labels);
    tcase_add_test(tc, grid_masks_and_updates);
    tcase_add_test(tc, closedness_matches_brute_force);
    tcase_add_test(tc, update_changes_closedness);
    suite_add_tcase(s, tc);
    return s;
}
