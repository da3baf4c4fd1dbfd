/* SPDX-License-Identifier: MIT */
/*
** sweep_pieces.c -- the first contact of a moving sphere or capsule
** with one primitive, by the pieces of a Minkowski sum (Ericson, "Real-Time
** Collision Detection", 2005, sections 5.5.6 and 5.5.7; Akenine-Moller
** et al., "Real-Time Rendering", 4th ed., 25.9).
**
** A sphere of radius r whose centre moves along x(t) = t d touches a
** primitive K at the first t where x(t) lies in K + B(r), the points
** within r of K.  A capsule whose segment is [x(t), x(t) + s] touches K
** where x(t) lies in K - [0, s] + B(r).  For a polytope (a triangle, a
** polygon, a box) that sum is the union of convex PIECES, one per
** feature of K - [0, s]: a vertex gives a ball (its sphere), an edge a
** cylinder of radius r closed by nothing (its ends are the vertices'
** balls), a face a slab of half-width r over the face (its sides are the
** edges' cylinders).  Each piece is convex, so the path enters each at
** most once, and the first contact is the earliest entry of any piece:
** every piece lies inside the sum, and every point of the sum's
** boundary lies on some piece (the nearest point of K - [0, s] to a
** point of the sum is inside a face, inside an edge or a vertex).
** K - [0, s] is K itself for a sphere (s = 0); for a capsule it is the
** prism K swept by -s, whose features are K's and K - s's, a
** parallelogram per edge of K and an edge [v - s, v] per vertex v.
**
** Watertight (issue 30): two triangles that share an edge share its
** cylinder and the balls of its ends, and each is tested with the same
** arithmetic for both (the edge's ends in one order, the smaller first;
** every feature taken relative to the sweep's start, one rounding each,
** so a shared vertex has the same coordinates in both), as the
** watertight ray test shares its edge functions.  And a face's slab
** ends exactly where its edges' cylinders begin (the slab's rim lies on
** them), so a path that a face's inside test rejects by rounding near an
** edge enters that edge's cylinder instead, a depth h^2 / (2 r) later,
** h the rejection's distance from the edge (a few ulps): no path
** reaches the sum's inside between two pieces.
**
** Conservative: every piece is inflated by eps = gamma(64) M (M the
** magnitude of its features' coordinates in the sweep's frame plus r,
** |s| and |x(t0)|: ray__sweep_eps).  Every quantity a piece test forms
** (the start's offset f from the feature, its part across an edge, the
** distance l of the path's line from the feature, disc's factors R +- l,
** a plane distance) is a sum of at most a dozen rounded terms of
** magnitudes below M, so within gamma(16) M of its exact value (Higham,
** "Accuracy and Stability of Numerical Algorithms", 2nd ed., 3.1,
** counting the inputs' own rounding into the frame); an error delta in
** the distances the test compares with the radius R is the exact test
** of a piece of radius R -+ delta, and the root's own rounding (a square
** root, a sum, a division: 4u of t) moves the point by 4u |t d| <= 4u M
** along the path, so the entry computed is the exact entry of a piece of
** radius within R +- gamma(40) M.  With R = r + eps, that radius is above
** r: no exact shape before the contact penetrates K, and at the contact
** the shape is within 2 eps of touching it (ray_intersect_sweep(3)).
**
** Starting inside an inflated piece (touching, within eps, but not
** overlapping: the caller classified that first) the piece is a contact
** at t0 only if the path moves into it, its velocity's part toward the
** feature above the rounding of that part: 2 eps + gamma(8) |f| times
** |d|; a path along a wall at the radius slides on, as it must.  And a
** path that only grazes a ball or a cylinder -- its line never comes
** nearer the feature than r - eps, so it never goes more than eps into
** the exact piece -- is no contact with it: else a shape sliding at its
** radius over a flat mesh would stop at every inner edge and vertex of
** it, whose inflated cylinders and balls stand eps above the face (the
** "ghost" or "internal edge" contacts of character controllers).  So
** the bound is: no shape before the contact is more than 2 eps inside
** any surface (eps from the grazes, eps from the rounding).
*/
#include "prim/sweep.h"

/* The largest |component| of v (comparisons: v has no NaN here). */
static double max_abs(ray_vec3 v)
{
    double x = fabs(v.x), y = fabs(v.y), z = fabs(v.z);
    double m = x > y ? x : y;

    return m > z ? m : z;
}

/*
** The direction scaled by a power of two (exact) so that its largest
** component lies in [1, 2): t is then measured in those units (t0, t1
** scaled by the inverse), so that neither a tiny nor a huge
** displacement over- or underflows the quadratics' coefficients.  No
** motion (d = 0: ray_intersect_sweep's overlap test) keeps t in the
** caller's units (k = 1) and the shape at its start (x0 = 0): every
** piece then sees no velocity toward it (b = 0 for a ball or a
** cylinder, d . n = 0 for a slab) and offers nothing, and
** ray__sweep_ellipsoid stops after its overlap test, so only the
** overlap at t0 is ever offered.
*/
void ray__sweep_start(ray__sweep *sw, ray_vec3 d, ray_vec3 s, double r,
                      double t0, double t1)
{
    double m = max_abs(d);
    double k = m > 0 ? ray__pow2(-ray__exponent_of(m)) : 1.0;

    sw->d = v3_scale(d, k);
    sw->t_unit = k;
    sw->s = s;
    sw->r = r;
    /*
    ** A capsule whose axis is too short for its own arithmetic: |s|^2
    ** below DBL_MIN (subnormal or 0, every |s_i| < 2^-511), where the
    ** cylinder's and the parallelepiped's quotients by |s|^2 lose all
    ** their digits or divide by 0 (issue 38, defect 8: such a capsule
    ** met a box it never came near).  It lies within the ball about a of
    ** radius r + |s|, and |s| <= |s_x| + |s_y| + |s_z| < 2^-509: swept as
    ** that sphere, its contacts are conservative.  The sum r + that
    ** bound rounds to nearest, below it by at most half an ulp of r,
    ** which the sweep's inflation (gamma(64) of r and more,
    ** ray__sweep_eps) covers many times over.
    */
    if (max_abs(s) > 0 && !(v3_dot(s, s) >= DBL_MIN)) {
        sw->r = r + (fabs(s.x) + fabs(s.y) + fabs(s.z));
        sw->s = v3(0, 0, 0);
    }
    sw->t0 = t0 / k;
    sw->t1 = t1 / k;
    sw->x0 = v3_scale(sw->d, sw->t0);
    sw->d_len = v3_length(sw->d);
}

double ray__sweep_eps(const ray__sweep *sw, double m)
{
    return ray__gamma(64) *
           (m + sw->r + max_abs(sw->s) + max_abs(sw->x0));
}

int ray__contact_offer(ray__contact *best, double t, ray_vec3 p, ray_vec3 n,
                       double depth)
{
    if (!(t < best->t || (t == best->t && depth > best->depth)))
        return 0;
    if (!v3_isfinite(p) || !v3_isfinite(n))
        return 0;
    best->t = t;
    best->p = p;
    best->n = n;
    best->depth = depth;
    return 1;
}

ray_vec3 ray__segment_point(ray_vec3 p, ray_vec3 a, ray_vec3 b)
{
    return ray__segment_closest(p, a, b);
}

/* (a x b), each component by ray__diff_of_products: relative accuracy
** however much its two products cancel, so a sliver's or a thin
** parallelogram's normal is that of its (rounded) corners, not noise. */
ray_vec3 ray__cross_exact(ray_vec3 a, ray_vec3 b)
{
    return v3(ray__diff_of_products(a.y, b.z, a.z, b.y),
              ray__diff_of_products(a.z, b.x, a.x, b.z),
              ray__diff_of_products(a.x, b.y, a.y, b.x));
}

/* Is the start's velocity toward the feature above rounding?  f: the
** feature's nearest point to the start, to the start (|f| ~ R). */
static int moving_in(const ray__sweep *sw, ray_vec3 f, double eps)
{
    return v3_dot(sw->d, f) <
           -sw->d_len * (2 * eps + ray__gamma(8) * v3_length(f));
}

/* ------------------------------------------------------------- pieces */

static ray_vec3 scene_point(const ray__sweep *sw, const ray__origin *o,
                            ray_vec3 y)
{
    switch (o->kind) {
    case RAY__FROM_SHIFTED:
        return v3_add(y, sw->s);
    case RAY__FROM_FIXED:
        return o->at;
    case RAY__FROM_PARALLELOGRAM: {
        /* y = at + mu e - nu s: mu from the 2 x 2 normal equations. */
        ray_vec3 w = v3_sub(y, o->at);
        double ee = v3_dot(o->e, o->e), es = v3_dot(o->e, sw->s);
        double ss = v3_dot(sw->s, sw->s);
        double we = v3_dot(w, o->e), ws = v3_dot(w, sw->s);
        double det = ee * ss - es * es;
        double mu = det > 0 ? (we * ss - ws * es) / det : 0.0;
        mu = mu > 0 ? (mu < 1 ? mu : 1.0) : 0.0;
        return v3_madd(o->at, mu, o->e);
    }
    default:
        return y;
    }
}

/* Offer a piece's contact at t: y its point on K - [0, s], n the unit
** normal toward the shape, rp the primitive's own radius (a sphere's, a
** capsule's: the contact point is rp further along n). */
static int offer(const ray__sweep *sw, const ray__origin *o, double t,
                 ray_vec3 y,
                 ray_vec3 n, double rp, ray__contact *best)
{
    return ray__contact_offer(best, t, v3_madd(scene_point(sw, o, y), rp, n),
                              n, 0);
}

/*
** The ball of radius r + rp + eps about v.  The quadratic |f + t d|^2 =
** R^2 (f = x0 - v) in ray_sphere's arrangement: b = -f.d, the line's
** closest approach l = |f + (b / a) d|, disc = (R - l)(R + l) (nothing
** squared before it is subtracted), and the entry c / (b + sqrt(a
** disc)) with c = (|f| - R)(|f| + R), free of cancellation for a path
** that approaches (b > 0).
*/
int ray__sweep_ball(const ray__sweep *sw, ray_vec3 v, double rp, double eps,
                const ray__origin *o, ray__contact *best)
{
    double R = sw->r + rp + eps, a, b, c, l, disc, s, flen;
    ray_vec3 f = v3_sub(sw->x0, v), n;

    flen = v3_length(f);
    b = -v3_dot(f, sw->d);
    if (!(b > 0))
        return 0;                         /* moving away (or along) */
    a = v3_dot(sw->d, sw->d);
    l = v3_length(v3_madd(f, b / a, sw->d));
    if (!(l < R - 2 * eps))
        return 0;                         /* grazes the skin (see top) */
    if (flen <= R) {
        if (!moving_in(sw, f, eps) || !v3_normalize(f, &n))
            return 0;
        return offer(sw, o, sw->t0, v, n, rp, best);
    }
    disc = (R - l) * (R + l);
    if (!(disc >= 0))
        return 0;
    c = (flen - R) * (flen + R);
    s = c / (b + sqrt(a * disc));
    if (!(sw->t0 + s <= sw->t1) ||
        !v3_normalize(v3_madd(f, s, sw->d), &n))
        return 0;
    return offer(sw, o, sw->t0 + s, v, n, rp, best);
}

/* p before q: lexicographic, so an edge is taken in the same order by
** both triangles that share it. */
static int before(ray_vec3 p, ray_vec3 q)
{
    if (p.x != q.x)
        return p.x < q.x;
    if (p.y != q.y)
        return p.y < q.y;
    return p.z < q.z;
}

/*
** The cylinder of radius r + rp + eps about edge [p, q], between the
** planes through its ends across it: the ball's quadratic for the parts
** of f and d across the edge, and the entry kept where its foot on the
** edge lies within it (beyond an end, the end's ball holds the path).
*/
int ray__sweep_cylinder(const ray__sweep *sw, ray_vec3 p, ray_vec3 q, double rp,
                    double eps, const ray__origin *o, ray__contact *best)
{
    double R = sw->r + rp + eps, ee, lam, a, b, c, l, disc, s, flen;
    ray_vec3 e, f, fp, dp, x, n;
    ray__origin oo = *o;

    if (before(q, p)) {
        ray_vec3 w = p;
        p = q;
        q = w;
        if (oo.kind == RAY__FROM_PARALLELOGRAM)
            oo.at = v3_add(oo.at, oo.e), oo.e = v3_scale(oo.e, -1);
    }
    e = v3_sub(q, p);
    ee = v3_dot(e, e);
    if (!(ee > 0 && ee < HUGE_VAL))
        return 0;
    f = v3_sub(sw->x0, p);
    lam = v3_dot(f, e) / ee;
    fp = v3_madd(f, -lam, e);
    dp = v3_madd(sw->d, -(v3_dot(sw->d, e) / ee), e);
    flen = v3_length(fp);
    b = -v3_dot(fp, dp);
    if (!(b > 0))
        return 0;                         /* moving away (or along) */
    a = v3_dot(dp, dp);
    l = v3_length(v3_madd(fp, b / a, dp));
    if (!(l < R - 2 * eps))
        return 0;                         /* grazes the skin (see top) */
    if (flen <= R) {
        if (!(lam >= 0 && lam <= 1) || !moving_in(sw, fp, eps) ||
            !v3_normalize(fp, &n))
            return 0;
        return offer(sw, &oo, sw->t0, v3_madd(p, lam, e), n, rp, best);
    }
    disc = (R - l) * (R + l);
    if (!(disc >= 0))
        return 0;
    c = (flen - R) * (flen + R);
    s = c / (b + sqrt(a * disc));
    x = v3_madd(f, s, sw->d);
    lam = v3_dot(x, e) / ee;
    if (!(lam >= 0 && lam <= 1) || !(sw->t0 + s <= sw->t1) ||
        !v3_normalize(v3_madd(x, -lam, e), &n))
        return 0;
    return offer(sw, &oo, sw->t0 + s, v3_madd(p, lam, e), n, rp, best);
}

/*
** Is x within the box of the convex face's corners, grown by gamma(8) of
** the magnitudes (x is a foot computed on the face's plane, a few
** roundings off)?  Every point of the face is.  The edge functions below
** overflow for an x near DBL_MAX (a sweep whose dir is near it: x is the
** shape's centre at the contact), and a NaN edge function compares as
** inside: fuzz_live found a sweep touching a 34-wide square at x =
** -1.7e308.  Outside the box, x is on no face, whatever they say.
*/
static int face_box_holds(const ray__face *fc, ray_vec3 x)
{
    double lo[3], hi[3], xs[3], tol;
    size_t i;
    int k;

    xs[0] = x.x, xs[1] = x.y, xs[2] = x.z;
    lo[0] = hi[0] = fc->v[0].x;
    lo[1] = hi[1] = fc->v[0].y;
    lo[2] = hi[2] = fc->v[0].z;
    for (i = 1; i < fc->n; i++) {
        double vs[3];
        vs[0] = fc->v[i].x, vs[1] = fc->v[i].y, vs[2] = fc->v[i].z;
        for (k = 0; k < 3; k++) {
            lo[k] = vs[k] < lo[k] ? vs[k] : lo[k];
            hi[k] = vs[k] > hi[k] ? vs[k] : hi[k];
        }
    }
    for (k = 0; k < 3; k++) {
        tol = ray__gamma(8) * (fabs(lo[k]) + fabs(hi[k]) + fabs(xs[k]));
        if (!(xs[k] >= lo[k] - tol && xs[k] <= hi[k] + tol))
            return 0;
    }
    return 1;
}

/* Is x (on the face's plane, within rounding) on the face?  Convex: in
** the corners' box and on the inner side of every edge (edge functions
** against the normal); a face without corners is a whole plane. */
static int face_holds(const ray__face *fc, ray_vec3 nrm, ray_vec3 x)
{
    size_t i;

    if (fc->pv != NULL)
        return ray__polygon_contains(fc->pv, fc->pn, fc->pxf,
                                     v3_add(x, fc->lift));
    if (fc->n > 0 && !face_box_holds(fc, x))
        return 0;                   /* (no corners: a plane, unbounded) */
    for (i = 0; i < fc->n; i++) {
        ray_vec3 a = fc->v[i], b = fc->v[(i + 1) % fc->n];
        if (v3_dot(ray__cross_exact(v3_sub(b, a), v3_sub(x, a)), nrm) < 0)
            return 0;
    }
    return 1;
}

int ray__sweep_slab(const ray__sweep *sw, const ray__face *fc, ray_vec3 nrm,
                    ray_vec3 at, double eps, const ray__origin *o,
                    ray__contact *best)
{
    double R = sw->r + eps, s0, dn, sigma, s;
    ray_vec3 x, foot;

    s0 = v3_dot(v3_sub(sw->x0, at), nrm);
    sigma = s0 < 0 ? -1.0 : 1.0;
    dn = v3_dot(sw->d, nrm);
    if (fabs(s0) <= R) {
        foot = v3_madd(sw->x0, -s0, nrm);
        if (!face_holds(fc, nrm, foot) ||
            !(sigma * dn < -sw->d_len * (2 * eps + ray__gamma(8) * fabs(s0))))
            return 0;
        return offer(sw, o, sw->t0, foot, v3_scale(nrm, sigma), 0, best);
    }
    if (!(sigma * dn < 0))
        return 0;
    s = (sigma * R - s0) / dn;
    if (!(sw->t0 + s <= sw->t1))
        return 0;
    x = v3_madd(sw->x0, s, sw->d);
    foot = v3_madd(x, -v3_dot(v3_sub(x, at), nrm), nrm);
    if (!face_holds(fc, nrm, foot))
        return 0;
    return offer(sw, o, sw->t0 + s, foot, v3_scale(nrm, sigma), 0, best);
}

/* The convex face v[0 .. n-1] (n <= 4) and, for a capsule, its copy
** moved by -s. */
void ray__sweep_faces(const ray__sweep *sw, const ray_vec3 *v, size_t n,
                  double eps, int capsule, ray__contact *best)
{
    ray_vec3 nrm, moved[4];
    ray__origin o;
    ray__face fc;
    size_t i;

    if (!v3_normalize(ray__cross_exact(v3_sub(v[1], v[0]), v3_sub(v[2], v[0])),
                      &nrm))
        return;
    fc.v = v;
    fc.n = n;
    fc.pv = NULL;
    o.kind = RAY__FROM_PLAIN;
    ray__sweep_slab(sw, &fc, nrm, v[0], eps, &o, best);
    if (!capsule)
        return;
    for (i = 0; i < n; i++)
        moved[i] = v3_sub(v[i], sw->s);
    fc.v = moved;
    o.kind = RAY__FROM_SHIFTED;
    ray__sweep_slab(sw, &fc, nrm, moved[0], eps, &o, best);
}

/*
** Edge [p, q] of K: its cylinder and, for a capsule, its copy moved by
** -s and the parallelogram between them (the face the edge sweeps).
*/
void ray__sweep_edge(const ray__sweep *sw, ray_vec3 p, ray_vec3 q, double eps,
                 int capsule, ray__contact *best)
{
    ray_vec3 quad[4], nrm;
    ray__origin o;
    ray__face fc;

    o.kind = RAY__FROM_PLAIN;
    ray__sweep_cylinder(sw, p, q, 0, eps, &o, best);
    if (!capsule)
        return;
    o.kind = RAY__FROM_SHIFTED;
    ray__sweep_cylinder(sw, v3_sub(p, sw->s), v3_sub(q, sw->s), 0, eps, &o,
                        best);
    /* The parallelogram, its corners in the edge's canonical order so
    ** that two triangles sharing the edge test the same one. */
    if (before(q, p)) {
        ray_vec3 w = p;
        p = q;
        q = w;
    }
    quad[0] = p;
    quad[1] = q;
    quad[2] = v3_sub(q, sw->s);
    quad[3] = v3_sub(p, sw->s);
    if (!v3_normalize(ray__cross_exact(v3_sub(q, p), v3_scale(sw->s, -1)),
                      &nrm))
        return;                 /* the edge along s: no parallelogram */
    fc.v = quad;
    fc.n = 4;
    fc.pv = NULL;
    o.kind = RAY__FROM_PARALLELOGRAM;
    o.at = p;
    o.e = v3_sub(q, p);
    ray__sweep_slab(sw, &fc, nrm, p, eps, &o, best);
}

/* Vertex v of K: its ball and, for a capsule, the ball of v - s and the
** cylinder [v - s, v] between them (the capsule's side against v). */
void ray__sweep_vertex(const ray__sweep *sw, ray_vec3 v, double eps,
                       int capsule,
                   ray__contact *best)
{
    ray__origin o;

    o.kind = RAY__FROM_PLAIN;
    ray__sweep_ball(sw, v, 0, eps, &o, best);
    if (!capsule)
        return;
    o.kind = RAY__FROM_SHIFTED;
    ray__sweep_ball(sw, v3_sub(v, sw->s), 0, eps, &o, best);
    o.kind = RAY__FROM_FIXED;
    o.at = v;
    ray__sweep_cylinder(sw, v3_sub(v, sw->s), v, 0, eps, &o, best);
}

/* The slack of the pieces of features whose coordinates are v[0 ..
** n-1] (the same for every primitive that shares them). */
double ray__sweep_eps_of(const ray__sweep *sw, const ray_vec3 *v, size_t n)
{
    double m = 0;
    size_t i;

    for (i = 0; i < n; i++) {
        double x = max_abs(v[i]);
        m = m > x ? m : x;
    }
    return ray__sweep_eps(sw, m);
}

/* ----------------------------------------------------- the overlap */

/*
** The shape's start against K: the signed distance "dist" between its
** core (x0, or the segment [x0, x0 + s]) and K (negative inside a
** solid), from the core's point q to K's point p, and K's own normal at
** p (for a core that touches K exactly).  Overlapping when dist < r -
** eps: a contact at t0 with depth r - dist and the normal that separates
** them (q - p, or outward for a core inside a solid, or K's normal
** turned against the motion for a core on K's surface).  1 when it
** overlaps (*best offered it): the pieces are then not asked.
*/
int ray__sweep_overlap(const ray__sweep *sw, double dist, ray_vec3 q,
                       ray_vec3 p,
                   ray_vec3 k_normal, double eps, ray__contact *best)
{
    ray_vec3 n;

    if (!(dist < sw->r - eps))
        return 0;
    if (dist < 0 || !v3_normalize(v3_sub(q, p), &n)) {
        n = k_normal;
        if (dist >= 0 && v3_dot(n, sw->d) > 0)
            n = v3_scale(n, -1);
    } else if (dist < 0)
        n = k_normal;
    ray__contact_offer(best, sw->t0, p, n, sw->r - dist);
    return 1;
}
