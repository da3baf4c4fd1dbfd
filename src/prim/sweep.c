/* SPDX-License-Identifier: MIT */
/*
** sweep.c -- a moving sphere or capsule against each kind of primitive
** (ray__sweep_triangle .. ray__sweep_parallelepiped, sweep.h): where
** the shape starts, overlapping or not (the signed distance between its
** core and the primitive), then the pieces of the primitive's Minkowski
** sum with the shape (sweep_pieces.c explains them, why they are
** watertight and why the contact they give is conservative).
*/
#include "prim/sweep.h"

/* The largest |component| of v (comparisons: v has no NaN here). */
static double max_abs(ray_vec3 v)
{
    double x = fabs(v.x), y = fabs(v.y), z = fabs(v.z);
    double m = x > y ? x : y;

    return m > z ? m : z;
}

/* Did *best change from *was (a better contact offered)? */
static int changed(const ray__contact *was, const ray__contact *best)
{
    return best->t != was->t || best->depth != was->depth;
}

int ray__sweep_triangle(ray__sweep *sw, ray_vec3 a, ray_vec3 b, ray_vec3 c,
                        ray__contact *best)
{
    ray_vec3 v[3], q, p, n;
    int capsule = max_abs(sw->s) > 0, k;
    ray__contact before = *best;
    double eps;

    v[0] = a;
    v[1] = b;
    v[2] = c;
    eps = ray__sweep_eps_of(sw, v, 3);
    if (capsule)
        ray__segment_triangle_closest(sw->x0, v3_add(sw->x0, sw->s), a, b,
                                      c, &q, &p);
    else {
        q = sw->x0;
        p = ray__triangle_closest(a, b, c, q);
    }
    if (!v3_normalize(ray__cross_exact(v3_sub(b, a), v3_sub(c, a)), &n))
        n = v3(0, 0, 1);
    if (ray__sweep_overlap(sw, ray__distance(q, p), q, p, n, eps, best))
        return 1;
    ray__sweep_faces(sw, v, 3, eps, capsule, best);
    for (k = 0; k < 3; k++) {
        ray_vec3 e[2];
        e[0] = v[k];
        e[1] = v[(k + 1) % 3];
        ray__sweep_edge(sw, e[0], e[1], ray__sweep_eps_of(sw, e, 2), capsule,
                        best);
        ray__sweep_vertex(sw, v[k], ray__sweep_eps_of(sw, &v[k], 1), capsule,
                          best);
    }
    return changed(&before, best);
}

/*
** A sphere (a solid): the ball of radius r + R about c for a sphere
** sweep; for a capsule sweep, the capsule [c - s, c] of that radius (the
** sphere seen from the capsule's end a): one cylinder and two balls.
*/
int ray__sweep_sphere(ray__sweep *sw, ray_vec3 c, double R,
                      ray__contact *best)
{
    double eps = ray__sweep_eps(sw, max_abs(c) + R);
    int capsule = max_abs(sw->s) > 0;
    ray_vec3 q = sw->x0, cs = v3_sub(c, sw->s), n;
    ray__contact before = *best;
    ray__origin o;

    if (capsule)
        q = ray__segment_closest(c, sw->x0, v3_add(sw->x0, sw->s));
    if (!v3_normalize(v3_sub(q, c), &n))
        n = v3(0, 0, 1);
    if (ray__sweep_overlap(sw, ray__distance(q, c) - R, q, v3_madd(c, R, n), n,
                           eps,
                best))
        return 1;
    o.kind = RAY__FROM_PLAIN;
    ray__sweep_ball(sw, c, R, eps, &o, best);
    if (capsule) {
        o.kind = RAY__FROM_FIXED;
        o.at = c;
        ray__sweep_ball(sw, cs, R, eps, &o, best);
        ray__sweep_cylinder(sw, cs, c, R, eps, &o, best);
    }
    return changed(&before, best);
}

/*
** A capsule [a, b] of radius R (a solid): for a sphere sweep, the
** cylinder and the two balls of radius r + R; for a capsule sweep, the
** parallelogram [a, b] - [0, s] grown by r + R: its face (a slab of
** half-width r + R + eps), four cylinders and four balls.
*/
int ray__sweep_capsule(ray__sweep *sw, ray_vec3 a, ray_vec3 b, double R,
                       ray__contact *best)
{
    ray_vec3 q, p, n, quad[4], nrm;
    ray__contact before = *best;
    double eps;
    int capsule = max_abs(sw->s) > 0;
    ray__origin o;

    eps = ray__sweep_eps(sw, fmax(max_abs(a), max_abs(b)) + R);
    if (capsule)
        ray__segments_closest(sw->x0, v3_add(sw->x0, sw->s), a, b, &q, &p);
    else {
        q = sw->x0;
        p = ray__segment_closest(q, a, b);
    }
    if (!v3_normalize(v3_sub(q, p), &n))
        n = v3(0, 0, 1);
    if (ray__sweep_overlap(sw, ray__distance(q, p) - R, q, v3_madd(p, R, n), n,
                           eps,
                best))
        return 1;
    o.kind = RAY__FROM_PLAIN;
    ray__sweep_cylinder(sw, a, b, R, eps, &o, best);
    ray__sweep_ball(sw, a, R, eps, &o, best);
    ray__sweep_ball(sw, b, R, eps, &o, best);
    if (capsule) {
        ray__face fc;
        o.kind = RAY__FROM_SHIFTED;
        ray__sweep_cylinder(sw, v3_sub(a, sw->s), v3_sub(b, sw->s), R, eps,
                            &o, best);
        ray__sweep_ball(sw, v3_sub(a, sw->s), R, eps, &o, best);
        ray__sweep_ball(sw, v3_sub(b, sw->s), R, eps, &o, best);
        o.kind = RAY__FROM_FIXED;
        o.at = a;
        ray__sweep_cylinder(sw, v3_sub(a, sw->s), a, R, eps, &o, best);
        o.at = b;
        ray__sweep_cylinder(sw, v3_sub(b, sw->s), b, R, eps, &o, best);
        quad[0] = a;
        quad[1] = b;
        quad[2] = v3_sub(b, sw->s);
        quad[3] = v3_sub(a, sw->s);
        if (v3_normalize(ray__cross_exact(v3_sub(b, a), v3_scale(sw->s, -1)),
                         &nrm)) {
            /* The face's slab is r + R + eps thick: grow r by R for it,
            ** the contact point R further toward the shape. */
            ray__sweep wide = *sw;
            ray__contact c = *best;
            wide.r += R;
            fc.v = quad;
            fc.n = 4;
            fc.pv = NULL;
            o.kind = RAY__FROM_PARALLELOGRAM;
            o.at = a;
            o.e = v3_sub(b, a);
            c.t = best->t;
            if (ray__sweep_slab(&wide, &fc, nrm, a, eps, &o, &c))
                ray__contact_offer(best, c.t, v3_madd(c.p, R, c.n), c.n, 0);
        }
    }
    return changed(&before, best);
}

/* A plane (a two-sided surface): its slab, and for a capsule the slab
** of its copy moved by -s. */
int ray__sweep_plane(ray__sweep *sw, ray_vec3 point, ray_vec3 nrm,
                     ray__contact *best)
{
    double eps = ray__sweep_eps(sw, max_abs(point));
    double h0 = v3_dot(v3_sub(sw->x0, point), nrm), h1 = h0;
    ray__contact before = *best;
    int capsule = max_abs(sw->s) > 0;
    ray_vec3 q = sw->x0;
    ray__face fc;
    ray__origin o;

    if (capsule) {
        h1 = v3_dot(v3_sub(v3_add(sw->x0, sw->s), point), nrm);
        if (fabs(h1) < fabs(h0))
            q = v3_add(sw->x0, sw->s);
    }
    if (ray__sweep_overlap(sw, (h0 < 0) != (h1 < 0) ? 0.0
                                                 : fmin(fabs(h0), fabs(h1)),
                           q,
                v3_madd(q, -v3_dot(v3_sub(q, point), nrm), nrm), nrm, eps,
                best))
        return 1;
    fc.v = NULL;
    fc.n = 0;
    fc.pv = NULL;
    o.kind = RAY__FROM_PLAIN;
    ray__sweep_slab(sw, &fc, nrm, point, eps, &o, best);
    if (capsule) {
        o.kind = RAY__FROM_SHIFTED;
        ray__sweep_slab(sw, &fc, nrm, v3_sub(point, sw->s), eps, &o, best);
    }
    return changed(&before, best);
}

/* ------------------------------------------------ polygons and boxes */

double ray__segment_polygon(ray_vec3 a, ray_vec3 b, const ray_vec3 *v,
                            size_t count, const ray_transform *xf,
                            ray_vec3 *q, ray_vec3 *p, ray_vec3 *nrm)
{
    ray_vec3 c, s = v3_sub(b, a), x, y, cs, ct;
    double best, d, ha, hb;
    size_t i;

    if (!ray__polygon_plane_mapped(v, count, xf, &c, nrm) ||
        !ray__polygon_closest_mapped(v, count, xf, a, p, &x))
        return HUGE_VAL;
    *q = a;
    best = ray__distance(a, *p);
    if (!(max_abs(s) > 0))
        return best;
    ha = v3_dot(v3_sub(a, c), *nrm);
    hb = v3_dot(v3_sub(b, c), *nrm);
    if ((ha <= 0) != (hb <= 0) && ha != hb) {
        x = v3_madd(a, ha / (ha - hb), s);
        if (ray__polygon_contains(v, count, xf, x)) {
            *q = *p = x;
            return 0;
        }
    }
    if (ray__polygon_closest_mapped(v, count, xf, b, &x, &y) &&
        (d = ray__distance(b, x)) < best) {
        best = d;
        *q = b;
        *p = x;
    }
    for (i = 0; i < count; i++) {
        ray__segments_closest(a, b, ray__polygon_vertex(v, i, xf),
                              ray__polygon_vertex(v, (i + 1) % count, xf),
                              &cs, &ct);
        if ((d = ray__distance(cs, ct)) < best) {
            best = d;
            *q = cs;
            *p = ct;
        }
    }
    return best;
}

/* The distance between the core [x0, x0 + s] (s = 0: the point x0) and
** a scene polygon: ray__segment_polygon. */
static double core_polygon(const ray__sweep *sw, const ray_vec3 *v,
                           size_t count, const ray_transform *xf,
                           ray_vec3 *q, ray_vec3 *p, ray_vec3 *nrm)
{
    return ray__segment_polygon(sw->x0, v3_add(sw->x0, sw->s), v, count, xf,
                                q, p, nrm);
}

int ray__sweep_polygon(ray__sweep *sw, const ray_vec3 *v, size_t count,
                       const ray_transform *xf, ray__contact *best)
{
    ray_vec3 q, p, nrm, c, w[2];
    ray__contact before = *best;
    int capsule = max_abs(sw->s) > 0;
    double eps, m = 0, dist;
    size_t i;
    ray__face fc;
    ray__origin o;

    if (count < 3)
        return 0;
    for (i = 0; i < count; i++) {
        double x = max_abs(ray__polygon_vertex(v, i, xf));
        m = m > x ? m : x;
    }
    eps = ray__sweep_eps(sw, m);
    dist = core_polygon(sw, v, count, xf, &q, &p, &nrm);
    if (!(dist < HUGE_VAL))
        return 0;
    if (ray__sweep_overlap(sw, dist, q, p, nrm, eps, best))
        return 1;
    if (!ray__polygon_plane_mapped(v, count, xf, &c, &nrm))
        return 0;
    fc.v = NULL;
    fc.n = 0;
    fc.pv = v;
    fc.pn = count;
    fc.pxf = xf;
    fc.lift = v3(0, 0, 0);
    o.kind = RAY__FROM_PLAIN;
    ray__sweep_slab(sw, &fc, nrm, c, eps, &o, best);
    if (capsule) {
        fc.lift = sw->s;
        o.kind = RAY__FROM_SHIFTED;
        ray__sweep_slab(sw, &fc, nrm, v3_sub(c, sw->s), eps, &o, best);
    }
    for (i = 0; i < count; i++) {
        w[0] = ray__polygon_vertex(v, i, xf);
        w[1] = ray__polygon_vertex(v, (i + 1) % count, xf);
        ray__sweep_edge(sw, w[0], w[1], ray__sweep_eps_of(sw, w, 2), capsule,
                        best);
        ray__sweep_vertex(sw, w[0], ray__sweep_eps_of(sw, w, 1), capsule, best);
    }
    return changed(&before, best);
}

/* The corners of face f (0 .. 5: axis f / 2, side f % 2) of a
** parallelepiped, in order around it (corner k has bit j for +e_j). */
static void box_face(const ray_vec3 corner[8], int f, ray_vec3 quad[4])
{
    int axis = f / 2, base = f % 2 ? 1 << axis : 0;
    int j = 1 << ((axis + 1) % 3), l = 1 << ((axis + 2) % 3);

    quad[0] = corner[base];
    quad[1] = corner[base | j];
    quad[2] = corner[base | j | l];
    quad[3] = corner[base | l];
}

/* Are the half-edges e mutually orthogonal to within their rounding
** (gamma(16) of the products of their lengths, as box.c's frame)? */
static int orthogonal(const ray_vec3 e[3])
{
    int i;

    for (i = 0; i < 3; i++) {
        const ray_vec3 *a = &e[i], *b = &e[(i + 1) % 3];
        if (fabs(v3_dot(*a, *b)) > ray__gamma(16) * v3_length(*a) *
                                        v3_length(*b))
            return 0;
    }
    return 1;
}

/* The signed distance from x to the parallelepiped (negative inside),
** its nearest surface point *p and that face's outward normal *n.  x's
** coordinates u_k along the half-edges e_k come first (Cramer's rule:
** u_k = (x - c) . (e_i x e_j) / vol): inside (every |u_k| <= 1), the
** nearest boundary point is the foot on the nearest face plane, at
** (1 - |u_k|) |e_k . n_k| from face +-k (n_k its unit normal), and lies
** on that face (the body is convex); outside, the nearest point of its
** six faces (as triangles). */
static double box_signed(const ray_vec3 corner[8], ray_vec3 x, ray_vec3 *p,
                         ray_vec3 *n)
{
    ray_vec3 c = v3_scale(v3_add(corner[0], corner[7]), 0.5), e[3], quad[4];
    ray_vec3 f[3], nn = v3(0, 0, 1);
    double best = HUGE_VAL, vol, u[3];
    int t, k, inside = 1;

    e[0] = v3_scale(v3_sub(corner[1], corner[0]), 0.5);
    e[1] = v3_scale(v3_sub(corner[2], corner[0]), 0.5);
    e[2] = v3_scale(v3_sub(corner[4], corner[0]), 0.5);
    for (k = 0; k < 3; k++)
        f[k] = v3_cross(e[(k + 1) % 3], e[(k + 2) % 3]);
    vol = v3_dot(e[0], f[0]);
    for (k = 0; k < 3; k++) {
        u[k] = v3_dot(v3_sub(x, c), f[k]) / vol;
        inside &= fabs(u[k]) <= 1;
    }
    if (!inside && orthogonal(e)) {
        /* A box with square corners (any similarity of an oriented box):
        ** clamping x's coordinates along its unit axes gives the nearest
        ** point (Ericson 5.1.4), excess by excess. */
        ray_vec3 y = c;
        double sum = 0, m = 0;
        for (k = 0; k < 3; k++) {
            double h = v3_length(e[k]), o = v3_dot(v3_sub(x, c), e[k]) / h;
            double cl = o > h ? h : (o < -h ? -h : o);
            y = v3_madd(y, cl / h, e[k]);
            if (fabs(o) - h > m) {
                m = fabs(o) - h;
                nn = v3_scale(e[k], o < 0 ? -1 / h : 1 / h);
            }
            sum += (o - cl) * (o - cl);
        }
        *p = y;
        *n = nn;
        return sqrt(sum);
    }
    if (inside) {
        for (k = 0; k < 3; k++) {
            ray_vec3 unit;
            double d;
            if (!v3_normalize(f[k], &unit))
                continue;
            if (v3_dot(unit, e[k]) < 0)
                unit = v3_scale(unit, -1);
            d = (1 - fabs(u[k])) * fabs(v3_dot(e[k], unit));
            if (d < best) {
                best = d;
                nn = u[k] < 0 ? v3_scale(unit, -1) : unit;
            }
        }
        *n = nn;
        *p = v3_madd(x, best, nn);
        return -best;
    }
    for (k = 0; k < 6; k++) {
        box_face(corner, k, quad);
        for (t = 0; t < 2; t++) {
            ray_vec3 y = ray__triangle_closest(quad[0], quad[1 + t],
                                               quad[2 + t], x);
            double d = ray__distance(y, x);
            if (d < best) {
                best = d;
                *p = y;
                if (v3_normalize(ray__cross_exact(v3_sub(quad[1], quad[0]),
                                                  v3_sub(quad[3], quad[0])),
                                 &nn) &&
                    v3_dot(nn, v3_sub(quad[0], c)) < 0)
                    nn = v3_scale(nn, -1);
                *n = nn;
            }
        }
    }
    return best;
}

/*
** The signed distance between the core and the parallelepiped: for a
** point, box_signed; for a segment, the least signed distance of its
** points, a convex function along it (the signed distance to a convex
** body is convex): golden section, as ray__ellipsoid_sweep_closest, to
** 2^-40 of its length, with the ends; at the minimum the function is
** flat to first order, so that stop costs a relative 2^-80 of the
** distance, below rounding.  A core whose distance from the body's
** centre exceeds its corners' reach by more than 2 r cannot overlap it:
** that lower bound is answered at once.
*/
static double core_box(const ray__sweep *sw, const ray_vec3 corner[8],
                       ray_vec3 *q, ray_vec3 *p, ray_vec3 *n)
{
    const double phi = 0.6180339887498949;
    ray_vec3 a = sw->x0, b = v3_add(sw->x0, sw->s), x, y, m;
    ray_vec3 c = v3_scale(v3_add(corner[0], corner[7]), 0.5);
    double lo = 0, hi = 1, s1, s2, f1, f2, best, d, reach;

    /* Far from the body (its centre farther from the core than the
    ** corners' reach plus the radius): a lower bound will do, for
    ** overlap() only asks whether it is below r. */
    reach = fmax(fmax(ray__distance(corner[0], c),
                      ray__distance(corner[1], c)),
                 fmax(ray__distance(corner[2], c),
                      ray__distance(corner[3], c)));
    d = ray__distance(ray__segment_closest(c, a, b), c) - reach;
    if (d > 2 * sw->r) {
        *q = a;
        *p = corner[0];
        *n = v3(0, 0, 1);
        return d;
    }
    *q = a;
    best = box_signed(corner, a, p, n);
    if (!(max_abs(sw->s) > 0))
        return best;
    if ((d = box_signed(corner, b, &x, &m)) < best) {
        best = d;
        *q = b;
        *p = x;
        *n = m;
    }
    s1 = hi - phi * (hi - lo);
    s2 = lo + phi * (hi - lo);
    f1 = box_signed(corner, v3_madd(a, s1, sw->s), &x, &m);
    f2 = box_signed(corner, v3_madd(a, s2, sw->s), &x, &m);
    while (hi - lo > 0x1p-40) {
        if (f1 <= f2) {
            hi = s2, s2 = s1, f2 = f1, s1 = hi - phi * (hi - lo);
            f1 = box_signed(corner, v3_madd(a, s1, sw->s), &x, &m);
        } else {
            lo = s1, s1 = s2, f1 = f2, s2 = lo + phi * (hi - lo);
            f2 = box_signed(corner, v3_madd(a, s2, sw->s), &x, &m);
        }
    }
    y = v3_madd(a, 0.5 * (lo + hi), sw->s);
    if ((d = box_signed(corner, y, &x, &m)) < best) {
        best = d;
        *q = y;
        *p = x;
        *n = m;
    }
    return best;
}

/* A parallelepiped (a solid): its 6 faces, 12 edges and 8 corners. */
int ray__sweep_parallelepiped(ray__sweep *sw, const ray_vec3 corner[8],
                              ray__contact *best)
{
    ray__contact before = *best;
    int capsule = max_abs(sw->s) > 0, f, k, j;
    double eps = ray__sweep_eps_of(sw, corner, 8), dist;
    ray_vec3 q, p, n, quad[4];

    dist = core_box(sw, corner, &q, &p, &n);
    if (!(dist < HUGE_VAL))
        return 0;
    if (ray__sweep_overlap(sw, dist, q, p, n, eps, best))
        return 1;
    for (f = 0; f < 6; f++) {
        box_face(corner, f, quad);
        ray__sweep_faces(sw, quad, 4, eps, capsule, best);
    }
    for (k = 0; k < 8; k++) {
        for (j = 0; j < 3; j++)
            if (!(k & 1 << j))
                ray__sweep_edge(sw, corner[k], corner[k | 1 << j], eps,
                                capsule, best);
        ray__sweep_vertex(sw, corner[k], eps, capsule, best);
    }
    return changed(&before, best);
}
