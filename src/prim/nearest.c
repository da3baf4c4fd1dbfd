/* SPDX-License-Identifier: MIT */
/*
** nearest.c -- nearest points between the simple pieces the scene
** queries are made of (ray_closest_point, the sweeps and overlaps): a
** point and a triangle, two segments, a segment and a triangle.  No
** scene here: plain geometry on doubles.
*/
#include "prim/prim.h"

/* The larger of a and b by a comparison (operands that cannot be NaN). */
static double max2(double a, double b)
{
    return a > b ? a : b;
}

/* t clamped to [0, 1]; a NaN t (0/0) gives 0. */
static double unit_clamp(double t)
{
    return t > 0 ? (t < 1 ? t : 1.0) : 0.0;
}

/* The nearest of the three edges' nearest points: the face's fallback
** when its determinants cannot be divided by (below). */
static ray_vec3 nearest_edge_point(ray_vec3 a, ray_vec3 b, ray_vec3 c,
                                   ray_vec3 q)
{
    ray_vec3 e[3];
    double d[3];
    int k, best = 0;

    e[0] = ray__segment_closest(q, a, b);
    e[1] = ray__segment_closest(q, b, c);
    e[2] = ray__segment_closest(q, c, a);
    for (k = 0; k < 3; k++) {
        d[k] = ray__distance(e[k], q);
        if (d[k] < d[best])
            best = k;
    }
    return e[best];
}

/* (a x b), each component by ray__diff_of_products: relative accuracy
** however much its two products cancel (sweep_pieces.c's
** ray__cross_exact, here for the sliver path below). */
static ray_vec3 cross_acc(ray_vec3 a, ray_vec3 b)
{
    return v3(ray__diff_of_products(a.y, b.z, a.z, b.y),
              ray__diff_of_products(a.z, b.x, a.x, b.z),
              ray__diff_of_products(a.x, b.y, a.y, b.x));
}

static double min3(double a, double b, double c)
{
    double m = a < b ? a : b;
    return m < c ? m : c;
}

static double max3(double a, double b, double c)
{
    return max2(max2(a, b), c);
}

/*
** Whether x lies in the box of a, b and c grown by tol(k) per axis:
** every point of the triangle does.
*/
static int in_corners_box(ray_vec3 a, ray_vec3 b, ray_vec3 c, ray_vec3 x,
                          ray_vec3 tol)
{
    return x.x >= min3(a.x, b.x, c.x) - tol.x &&
           x.x <= max3(a.x, b.x, c.x) + tol.x &&
           x.y >= min3(a.y, b.y, c.y) - tol.y &&
           x.y <= max3(a.y, b.y, c.y) + tol.y &&
           x.z >= min3(a.z, b.z, c.z) - tol.z &&
           x.z <= max3(a.z, b.z, c.z) + tol.z;
}

/*
** The sliver path (issue 38, defect 6): a triangle whose smallest angle
** theta has sin theta < 1/16 (about 3.6 degrees).  Ericson's region
** walk divides determinants that cancel as sin^2 theta, so its point
** could sit far along such a triangle from the nearest one (a distance
** off by 24 on a 4e4-long cap sliver 0.003 wide).  Here q is projected
** on the plane along the unit normal n of the accurate cross product
** ab x ac (each component without cancellation error): the foot
** q - ((q - a).n) n; if it lies inside the triangle (the three edge
** functions ((v - u) x (foot - u)).n, each accurate, not negative) it is
** the nearest point, and otherwise the nearest point lies on the
** boundary: the nearest of the three edges' nearest points, each a
** clamped projection on a segment, well conditioned whatever the angles.
** The foot is within a few ulps of |q| + |q - p| of the exact one, less
** the error of n, which tilts by about u (longest edge) / (width) of
** the triangle (the rounding of its edge vectors, inherent in them):
** see ray_closest_point(3), Accuracy, for the bound this gives.  A
** triangle thinner than its edges' rounding (corners 4e-270 apart with
** the third 0.7 away) has two edges parallel to rounding, and a foot on
** their common line beyond the corner passes both edge tests (each
** rounds to 0): so a foot outside the corners' box, grown by the
** foot's and the corners' rounding, is no inside point whatever the
** tests say (fuzz_live found such a foot 30 away from its triangle,
** reported as the nearest point and met by ray_overlap_shape).  ab, ac,
** ap are the scaled edge vectors and q's offset (see below), s the
** scale.  Returns 0 (use the region walk) when the foot is not finite.
*/
static int sliver_closest(ray_vec3 a, ray_vec3 b, ray_vec3 c, ray_vec3 q,
                          ray_vec3 ab, ray_vec3 ac, ray_vec3 ap, double s,
                          ray_vec3 *p)
{
    ray_vec3 n, bc = v3_sub(ac, ab), foot, pr;
    double h;

    if (!v3_normalize(cross_acc(ab, ac), &n))
        return 0;
    h = v3_dot(ap, n);
    pr = v3_madd(ap, -h, n);
    if (v3_dot(cross_acc(ab, pr), n) >= 0 &&
        v3_dot(cross_acc(bc, v3_sub(pr, ab)), n) >= 0 &&
        v3_dot(cross_acc(v3_scale(ac, -1), v3_sub(pr, ac)), n) >= 0) {
        ray_vec3 tol;
        foot = v3_madd(q, -(h / s), n);
        if (!v3_isfinite(foot))
            return 0;
        /* The foot rounds twice (the product and the difference), within
        ** gamma(2) of |q| + |h / s| per component; the corners are the
        ** stored ones, exact.  gamma(8) of both leaves room. */
        tol.x = ray__gamma(8) * (fabs(q.x) + fabs(h / s) + fabs(foot.x));
        tol.y = ray__gamma(8) * (fabs(q.y) + fabs(h / s) + fabs(foot.y));
        tol.z = ray__gamma(8) * (fabs(q.z) + fabs(h / s) + fabs(foot.z));
        if (in_corners_box(a, b, c, foot, tol)) {
            *p = foot;
            return 1;
        }
    }
    *p = nearest_edge_point(a, b, c, q);
    return 1;
}

/*
** A quick answer of is_sliver (below) for the usual triangle, far from
** sliver: 1 when is_sliver surely says 0, else 0 (then ask it).  Every
** triangle a closest-point search meets asks (a narrow-band grid bakes
** millions), and is_sliver's accurate cross product and four square
** roots were a fifth of such a bake.  Here without them: the plain cross
** product, off from the exact one by at most 2 sqrt(3) gamma(2) |ab| |ac|
** (each component's two products and difference), and squared lengths.
** Where |ab x ac|^2 exceeds (1 + 2^-20) / 256 times the product of the
** two longest squared edges -- whose roundings, a few u, and that error,
** below 2^-40 of the product, the margin of 2^-20 more than covers --
** is_sliver's own roundings cannot bring its 16 |ab x ac| below the
** product of the two longest edges.  Products too small to be normal
** (a tiny triangle far from q) are left to is_sliver.
*/
static int surely_not_sliver(ray_vec3 ab, ray_vec3 ac)
{
    ray_vec3 bc = v3_sub(ac, ab), cr = v3_cross(ab, ac);
    double la = v3_dot(ab, ab), lb = v3_dot(ac, ac), lc = v3_dot(bc, bc);
    double p = max2(max2(la * lb, la * lc), lb * lc);

    return p > 0x1p-900 && v3_dot(cr, cr) > p * ((1 + 0x1p-20) / 256);
}

/* sin of the triangle's smallest angle is below 1/16: |ab x ac| over
** the product of its two longest edges (the smallest angle lies between
** them), compared without a division.  On the scaled edges. */
static int is_sliver(ray_vec3 ab, ray_vec3 ac)
{
    ray_vec3 bc = v3_sub(ac, ab);
    double l[3], cr, t;

    if (surely_not_sliver(ab, ac))
        return 0;
    cr = v3_length(cross_acc(ab, ac));

    l[0] = v3_length(ab);
    l[1] = v3_length(ac);
    l[2] = v3_length(bc);
    /* Sort so that l[0] and l[1] are the two longest. */
    if (l[2] > l[0])
        t = l[0], l[0] = l[2], l[2] = t;
    if (l[2] > l[1])
        t = l[1], l[1] = l[2], l[2] = t;
    return 16 * cr < l[0] * l[1];
}

/*
** The point of triangle (a, b, c) nearest q: Ericson, "Real-Time
** Collision Detection", Morgan Kaufmann 2005, section 5.1.5
** (ClosestPtPointTriangle).  The Voronoi region of the triangle that q
** lies in -- a vertex, an edge or the face -- is found from the dot
** products d1 .. d6 of the edges ab, ac with q's offsets from the
** vertices and from the barycentric determinants va, vb, vc formed of
** them, each test needing none of the later ones; the point is the
** vertex itself (exactly), a + t ab on an edge, or a + v ab + w ac on
** the face, with (t, v, w) from the same quantities.
**
** ab, ac and q's offsets are scaled by 2^-e (exactly), e the exponent
** of their largest component, so that the dot products and the
** determinants (products of four coordinates) neither overflow nor
** underflow for a triangle of any size and a q at any distance from it;
** the region and (t, v, w) do not depend on the scale, and the point is
** formed from the unscaled vertices.
**
** Rounding: the edge and face points are a + t ab (+ w ac) with t, v, w
** in [0, 1] (clamped: rounding may carry a quotient an ulp past an end),
** so p lies on the triangle within gamma(3) (|a| + |ab| + |ac|) per
** component whatever q.  Where p lies along the triangle is off by the
** rounding of the dot products, gamma(3) |ab| |q - a| and the like,
** divided by the conditioning of the determinants: about 10 u |q - a| /
** sin^2 of the triangle's smallest angle.  That moves p along the
** surface; the distance |p - q| changes by it only to second order when
** q is off the plane, and to first order when q lies in the plane.
** A triangle whose determinants cannot be divided by (their sum is not
** positive: a sliver within rounding of a segment) falls back to the
** nearest of its edges' points, which is then as near as any.
*/
ray_vec3 ray__triangle_closest(ray_vec3 a, ray_vec3 b, ray_vec3 c,
                               ray_vec3 q)
{
    ray_vec3 ab = v3_sub(b, a), ac = v3_sub(c, a), ap = v3_sub(q, a);
    ray_vec3 bp, cp;
    double m, s, d1, d2, d3, d4, d5, d6, va, vb, vc, sum, v, w;

    /* Differences of finite doubles: +-Inf where they overflow, never
    ** NaN, so the comparisons of max2 see every one. */
    m = max2(max2(max2(fabs(ab.x), fabs(ab.y)), max2(fabs(ab.z), fabs(ac.x))),
             max2(max2(fabs(ac.y), fabs(ac.z)),
                  max2(max2(fabs(ap.x), fabs(ap.y)), fabs(ap.z))));
    if (!(m > 0 && m < HUGE_VAL))
        return a;   /* q == a on a point (not a usable triangle), or overflow */
    s = ray__pow2(-ray__exponent_of(m));
    bp = v3_scale(v3_sub(q, b), s);
    cp = v3_scale(v3_sub(q, c), s);
    ab = v3_scale(ab, s);
    ac = v3_scale(ac, s);
    ap = v3_scale(ap, s);
    if (is_sliver(ab, ac)) {
        ray_vec3 p;
        if (sliver_closest(a, b, c, q, ab, ac, ap, s, &p))
            return p;
    }

    d1 = v3_dot(ab, ap);
    d2 = v3_dot(ac, ap);
    if (d1 <= 0 && d2 <= 0)
        return a;                                       /* vertex a */
    d3 = v3_dot(ab, bp);
    d4 = v3_dot(ac, bp);
    if (d3 >= 0 && d4 <= d3)
        return b;                                       /* vertex b */
    vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0)                  /* edge ab */
        return v3_madd(a, unit_clamp(d1 / (d1 - d3)), v3_sub(b, a));
    d5 = v3_dot(ab, cp);
    d6 = v3_dot(ac, cp);
    if (d6 >= 0 && d5 <= d6)
        return c;                                       /* vertex c */
    vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0)                  /* edge ac */
        return v3_madd(a, unit_clamp(d2 / (d2 - d6)), v3_sub(c, a));
    va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)        /* edge bc */
        return v3_madd(b, unit_clamp((d4 - d3) / ((d4 - d3) + (d5 - d6))),
                       v3_sub(c, b));
    sum = va + vb + vc;                                 /* the face */
    if (!(sum > 0 && sum < HUGE_VAL))
        return nearest_edge_point(a, b, c, q);
    v = unit_clamp(vb / sum);
    w = unit_clamp(vc / sum);
    return v3_add(a, v3_add(v3_scale(v3_sub(b, a), v),
                            v3_scale(v3_sub(c, a), w)));
}

/*
** The nearest points *ps of segment [p0, p1] and *qs of segment [q0,
** q1]: Ericson, "Real-Time Collision Detection", 2005, section 5.1.9
** (ClosestPtSegmentSegment).  s and t, the parameters along the two,
** minimise |p(s) - q(t)|^2 over [0, 1]^2: s from the unconstrained
** minimum of the pair of lines (a Cramer quotient, clamped), t from s
** (clamped), then s again from the clamped t, so that the pair is the
** constrained minimum whatever the lines' angle; a segment of zero
** length (its squared length 0 or not finite) is its first end, and two
** parallel segments (the determinant a e - b^2 not above gamma(6) a e:
** the lines are parallel to within the rounding of its terms) start
** from s = 0, from which the same two clamps give a nearest pair.
** The points are formed as ends plus clamped parameters times the
** segments, within gamma(3) of the segments' magnitudes of them; the
** parameters are off by the rounding of the dot products over the
** conditioning of the pair (the sine of their angle), which moves the
** points along the segments where the distance is stationary.
*/
void ray__segments_closest(ray_vec3 p0, ray_vec3 p1, ray_vec3 q0,
                           ray_vec3 q1, ray_vec3 *ps, ray_vec3 *qs)
{
    ray_vec3 d1 = v3_sub(p1, p0), d2 = v3_sub(q1, q0), r = v3_sub(p0, q0);
    double a = v3_dot(d1, d1), e = v3_dot(d2, d2), f = v3_dot(d2, r);
    double s = 0, t = 0;
    int p_point = !(a > 0 && a < HUGE_VAL), q_point = !(e > 0 && e < HUGE_VAL);

    if (p_point && q_point) {
        *ps = p0;
        *qs = q0;
        return;
    }
    if (p_point) {
        t = unit_clamp(f / e);
    } else {
        double c = v3_dot(d1, r);
        if (q_point) {
            s = unit_clamp(-c / a);
        } else {
            double b = v3_dot(d1, d2), den = a * e - b * b;
            if (den > ray__gamma(6) * a * e)
                s = unit_clamp((b * f - c * e) / den);
            t = (b * s + f) / e;
            if (!(t > 0)) {
                t = 0;
                s = unit_clamp(-c / a);
            } else if (t > 1) {
                t = 1;
                s = unit_clamp((b - c) / a);
            }
        }
    }
    *ps = s > 0 ? (s < 1 ? v3_madd(p0, s, d1) : p1) : p0;
    *qs = t > 0 ? (t < 1 ? v3_madd(q0, t, d2) : q1) : q0;
}

/*
** Does segment [p0, p1] cross triangle (a, b, c)?  1 with *x the
** crossing, else 0: the segment's two ends on opposite sides of the
** plane (or one on it: side products of the signed volumes), and the
** crossing inside the triangle by the signs of the three edge volumes
** (the Moller-Trumbore barycentrics written as scalar triple products,
** Ericson 5.3.6), all taken relative to a so that far geometry keeps its
** digits.  A crossing within rounding of an edge may go either way: the
** callers then also take the edges' nearest points, which are as near.
*/
static int segment_crosses_triangle(ray_vec3 p0, ray_vec3 p1, ray_vec3 a,
                                    ray_vec3 b, ray_vec3 c, ray_vec3 *x)
{
    ray_vec3 ab = v3_sub(b, a), ac = v3_sub(c, a), n = v3_cross(ab, ac);
    ray_vec3 pa = v3_sub(p0, a), qa = v3_sub(p1, a), d, e;
    double s0 = v3_dot(pa, n), s1 = v3_dot(qa, n), den, t, v, w;

    if ((s0 > 0 && s1 > 0) || (s0 < 0 && s1 < 0) || s0 == s1)
        return 0;
    d = v3_sub(p0, p1);
    den = v3_dot(d, n);                     /* s0 - s1, same sign as s0 */
    e = v3_cross(d, pa);
    v = v3_dot(ac, e);
    w = -v3_dot(ab, e);
    if (den < 0) {
        den = -den;
        v = -v;
        w = -w;
    }
    if (!(v >= 0 && w >= 0 && v + w <= den))
        return 0;
    t = s0 / (s0 - s1);
    if (!(t >= 0 && t <= 1))
        return 0;
    *x = v3_madd(p0, t, v3_sub(p1, p0));
    return v3_isfinite(*x);
}

/*
** The nearest points *ps of segment [p0, p1] and *pt of triangle (a, b,
** c) (Ericson 5.1.10): the crossing when the segment crosses the
** triangle (distance 0), else the nearest of the ends' nearest points
** on the triangle and of the segment's nearest points to the three
** edges: the distance between two convex sets that do not meet is
** reached at a boundary feature of one of them, and the segment's
** boundary is its ends, the triangle's relative boundary its edges (the
** face is reached from an end, the pair of lines from an edge).
*/
void ray__segment_triangle_closest(ray_vec3 p0, ray_vec3 p1, ray_vec3 a,
                                   ray_vec3 b, ray_vec3 c, ray_vec3 *ps,
                                   ray_vec3 *pt)
{
    ray_vec3 x, cs, ct, e[3][2];
    double best, d;
    int k;

    if (segment_crosses_triangle(p0, p1, a, b, c, &x)) {
        *ps = *pt = x;
        return;
    }
    *ps = p0;
    *pt = ray__triangle_closest(a, b, c, p0);
    best = ray__distance(*ps, *pt);
    ct = ray__triangle_closest(a, b, c, p1);
    if ((d = ray__distance(p1, ct)) < best) {
        best = d;
        *ps = p1;
        *pt = ct;
    }
    e[0][0] = a, e[0][1] = b;
    e[1][0] = b, e[1][1] = c;
    e[2][0] = c, e[2][1] = a;
    for (k = 0; k < 3; k++) {
        ray__segments_closest(p0, p1, e[k][0], e[k][1], &cs, &ct);
        if ((d = ray__distance(cs, ct)) < best) {
            best = d;
            *ps = cs;
            *pt = ct;
        }
    }
}
