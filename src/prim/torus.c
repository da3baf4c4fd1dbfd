/* SPDX-License-Identifier: MIT */
/*
** torus.c -- ray / torus: the exact quartic, solved without a closed
** formula; and the same torus as an implicit surface (its signed
** distance) for ray_implicit, so the two methods can check each other.
*/
#include "core/exact.h"
#include "prim/prim.h"

/* The torus in its own frame: a unit axis "a" (local z) with the
** tangents t1, t2 (local x, y) of ray__tangent_frame. */
typedef struct torus_frame {
    ray_vec3 c, t1, t2, a;
    double major, minor;
} torus_frame;

static int torus_frame_init(const ray_torus_params *t, torus_frame *f)
{
    if (t == NULL || !v3_isfinite(t->center) || !v3_normalize(t->axis, &f->a))
        return 0;
    /* A ring torus only: a spindle torus (minor >= major) crosses itself,
    ** and its quartic's inner surface is not the tube projected on below. */
    if (!(t->major > 0 && t->major < HUGE_VAL) ||
        !(t->minor > 0 && t->minor < t->major) ||
        !(2 * (t->major + t->minor) < HUGE_VAL))  /* the error bound's */
        return 0;
    ray__tangent_frame(f->a, &f->t1, &f->t2);
    f->c = t->center;
    f->major = t->major;
    f->minor = t->minor;
    return 1;
}

static ray_vec3 to_local(const torus_frame *f, ray_vec3 v)
{
    return v3(v3_dot(v, f->t1), v3_dot(v, f->t2), v3_dot(v, f->a));
}

static ray_vec3 to_world(const torus_frame *f, ray_vec3 v)
{
    return v3_add(v3_add(v3_scale(f->t1, v.x), v3_scale(f->t2, v.y)),
                  v3_scale(f->a, v.z));
}

/*
** The box of the torus: along world axis k the tube's centre circle
** reaches R sqrt(1 - a_k^2) from the centre, and the tube r beyond.  It is
** grown by gamma(8) of the coordinates' magnitude, more than the few
** roundings of this sum and of the frame, so it contains every hit point
** the intersection can compute.
*/
int ray__torus_box(const ray_torus_params *t, ray_vec3 *lo, ray_vec3 *hi)
{
    torus_frame f;
    double ext[3];
    ray_vec3 e, grow;
    int k;

    if (!torus_frame_init(t, &f))
        return 0;
    for (k = 0; k < 3; k++) {
        double ak = v3_axis(f.a, k);
        ext[k] = f.major * sqrt(fmax(0.0, 1.0 - ak * ak)) + f.minor;
    }
    e = v3(ext[0], ext[1], ext[2]);
    grow = v3_scale(v3_add(v3_abs(f.c), e), ray__gamma(8));
    *lo = v3_sub(v3_sub(f.c, e), grow);
    *hi = v3_add(v3_add(f.c, e), grow);
    return v3_isfinite(*lo) && v3_isfinite(*hi);
}

/*
** The quartic of the ray q(s) = o + s*d (local, |d| = 1, o the point of
** the ray nearest the centre) against (|q|^2 + R^2 - r^2)^2 =
** 4R^2 (q.x^2 + q.y^2).  With a = d.d, b = o.d, K = |o|^2 + R^2 - r^2 and
** A(s) = a s^2 + 2b s + K:
**   c4 = a^2, c3 = 4ab, c2 = 4b^2 + 2aK - 4R^2 (dx^2 + dy^2),
**   c1 = 4bK - 8R^2 (ox dx + oy dy), c0 = K^2 - 4R^2 rho^2.
** c0 is the difference of two ~R^4 terms that nearly cancel when the ray
** passes close to the tube, so it is formed as the product
** (K - 2R rho)(K + 2R rho) with K - 2R rho = D^2 - r^2 = (D - r)(D + r),
** D = the distance from o to the tube's centre circle: the same trick as
** ray_sphere's c = (|f| - R)(|f| + R).
*/
static void torus_quartic(ray_vec3 o, ray_vec3 d, double major, double minor,
                          double c[5])
{
    double a = v3_dot(d, d), b = v3_dot(o, d);
    double rho = ray__hypot(o.x, o.y);
    double dist = ray__hypot(rho - major, o.z);
    double k = v3_dot(o, o) + (major - minor) * (major + minor);
    double r2 = 4.0 * major * major;

    c[4] = a * a;
    c[3] = 4.0 * a * b;
    c[2] = 4.0 * b * b + 2.0 * a * k - r2 * (d.x * d.x + d.y * d.y);
    c[1] = 4.0 * b * k - 2.0 * r2 * (o.x * d.x + o.y * d.y);
    c[0] = (dist - minor) * (dist + minor) * (k + 2.0 * major * rho);
}

/*
** The hit at local point q (in units scaled by 1/scale): q is projected
** onto the torus (onto the tube around its nearest centre-circle point),
** which removes the error accumulated along the ray, as ray_sphere does.
** What is left is the rounding of that projection and of the frame
** change back to world space: a few tens of roundings of numbers no
** larger than |c| + 2(R + r), bounded by gamma(32) of that.
*/
static int torus_fill(const torus_frame *f, ray_vec3 q, double scale,
                      double t, ray_hit *hit)
{
    double rho = ray__hypot(q.x, q.y), big = f->major * scale;
    ray_vec3 ring, w, nl, p, n, err;

    /* On the axis (never on a ring torus's surface, but rounding may put
    ** a far-off hit there) every direction is the nearest: take t1's. */
    ring = rho > 0 ? v3(big * q.x / rho, big * q.y / rho, 0) : v3(big, 0, 0);
    w = v3_sub(q, ring);
    if (!v3_normalize(w, &nl))
        return 0;
    p = v3_add(f->c, v3_scale(to_world(f, v3_madd(ring, f->minor * scale,
                                                  nl)),
                              1.0 / scale));
    n = to_world(f, nl);
    err = v3_scale(v3_add(v3_abs(f->c),
                          v3_scale(v3(1, 1, 1), 2.0 * (f->major + f->minor))),
                   ray__gamma(32));
    if (!v3_isfinite(p) || !v3_isfinite(n) || !v3_isfinite(err))
        return 0;
    hit->t = t;
    hit->p = p;
    hit->n = n;
    hit->u = atan2(q.y, q.x) / (2.0 * RAY__PI) + 0.5;
    hit->v = atan2(w.z, rho - big) / (2.0 * RAY__PI) + 0.5;
    hit->p_err = err;
    hit->geom_id = RAY_INVALID_ID;
    hit->prim_id = RAY_INVALID_ID;
    hit->inst_id = RAY_INVALID_ID;
    return 1;
}

/*
** A bound on the error of a root s of the quartic (in the scaled local
** frame, |d| = 1 up to rounding), by first-order perturbation (Higham,
** "Accuracy and Stability of Numerical Algorithms", 2nd ed., 3.1 and
** 5.1; gamma(n) = n u / (1 - n u)).  The quartic is g(s) = F(o + s d) with
** F(q) = (|q|^2 + R^2 - r^2)^2 - 4R^2 (q_x^2 + q_y^2), so an error e in the
** ray's point (the origin's rounding into the frame and by the shift, at
** most gamma(6) (|o before the shift| + |s0|), and the direction's, gamma(6)
** |s|) moves g by |grad F| e; the coefficients' own rounding, bounded by
** gamma(12) times the magnitudes of the terms they sum (in this frame
** every quantity is at most ~2, so c0's cancelling hypot is covered by
** the same gamma(12) times its terms' size), and Horner's, gamma(8) sum
** |c_i| |s|^i, add to it.  Then a simple root moves by dg / |g'(s)|,
** g' = grad F . d, and any root by at most 2 (dg / c4)^(1/4) (the bound
** for a quadruple root); the smaller holds.
*/
static double torus_root_error(const double c[5], ray_vec3 o, ray_vec3 d,
                               double major, double minor, double o_err,
                               double s)
{
    ray_vec3 q = v3_madd(o, s, d), grad;
    double as = fabs(s), k = v3_dot(q, q) + (major - minor) * (major + minor);
    double r2 = 4.0 * major * major, mag = 0, slope, dg, terms;
    int i;

    grad = v3_sub(v3_scale(q, 4.0 * k), v3(2 * r2 * q.x, 2 * r2 * q.y, 0));
    for (i = 4; i >= 0; i--)
        mag = mag * as + fabs(c[i]);
    terms = (fabs(v3_dot(o, o)) + major * major + minor * minor) *
            (fabs(v3_dot(o, o)) + major * major + minor * minor + 4.0);
    dg = v3_length(grad) * (o_err + ray__gamma(6) * as) +
         ray__gamma(12) * terms * (1 + as) * (1 + as) * (1 + as) * (1 + as) +
         ray__gamma(8) * mag;
    slope = fabs(v3_dot(grad, d));
    return fmin(slope > 0 ? dg / slope : HUGE_VAL,
                2 * sqrt(sqrt(dg / c[4]))) *
           (1 + ray__gamma(4));
}

/*
** The ray is moved into the torus's frame and scaled by a power of two
** near 1/(R + r), exactly, so the torus has size ~1 whatever its units
** (R^4 would underflow for R = 1e-100 and overflow for R = 1e100); its
** origin is moved to the point nearest the centre, so a far-away ray
** keeps its digits.  The roots are searched in the torus's bounding
** sphere only, |q| <= R + r.
*/
int ray_torus(const ray_ray *r, const ray_torus_params *t, ray_hit *hit)
{
    torus_frame f;
    ray_vec3 o, d;
    double dlen, scale, s0, o_err, reach, half, b, c[5];
    double roots[RAY__POLY_MAX_DEGREE + 1];
    int exponent, n, i;

    if (r == NULL || hit == NULL || !torus_frame_init(t, &f) ||
        !v3_isfinite(r->org) || !v3_isfinite(r->dir) ||
        !(r->tmin < r->tmax))
        return 0;
    /* The unit direction and |dir| without overflow or underflow of
    ** |dir|^2 (v3_normalize divides by the largest component first). */
    if (!v3_normalize(r->dir, &d))
        return 0;
    dlen = v3_dot(r->dir, d);
    if (!(dlen > 0 && dlen < HUGE_VAL))
        return 0;
    frexp(f.major + f.minor, &exponent);
    scale = ldexp(1.0, -exponent);
    d = to_local(&f, d);
    o = v3_scale(to_local(&f, v3_sub(r->org, f.c)), scale);
    s0 = -v3_dot(o, d);
    o_err = ray__gamma(6) * (v3_length(o) + fabs(s0));
    o = v3_madd(o, s0, d);
    reach = (f.major + f.minor) * scale;
    /* The roots lie where the ray is inside the bounding sphere,
    ** |o + s d| <= reach: s in -b -+ sqrt(b^2 - (|o|^2 - reach^2)).  b =
    ** o.d is not quite 0 after the shift (a few ulps of the original
    ** |o|, which far away is large against the torus), so it is kept:
    ** dropping it once lost the near crossing of rays entering close to
    ** the outer equator, where the torus touches that sphere.  A few ulps
    ** of slack keep roots on the sphere itself inside. */
    b = v3_dot(o, d);
    half = b * b - (v3_length(o) - reach) * (v3_length(o) + reach);
    if (!(half >= -4 * DBL_EPSILON * reach * reach))
        return 0;
    half = sqrt(fmax(half, 0.0)) * (1 + 4 * DBL_EPSILON) +
           4 * DBL_EPSILON * reach;
    torus_quartic(o, d, f.major * scale, f.minor * scale, c);
    for (i = 0; i < 5; i++)
        if (!isfinite(c[i]))
            return 0;
    n = ray__poly_roots(c, 4, -b - half, -b + half, roots);
    /* A root counts when its whole error interval lies past tmin: a ray
    ** leaving the torus starts on it or within its rounding error, and
    ** its root there is rounding noise around 0 (ray__watertight_t_error
    ** in watertight.h says more).  s0 + root rounds once more. */
    for (i = 0; i < n; i++) {
        double th = (s0 + roots[i]) / scale / dlen, err;
        if (!(th > r->tmin && th < r->tmax))
            continue;
        err = (torus_root_error(c, o, d, f.major * scale, f.minor * scale,
                                o_err, roots[i]) +
               ray__gamma(1) * (fabs(s0) + fabs(roots[i]))) /
                  scale / dlen +
              ray__gamma(3) * fabs(th);
        if (th - err > r->tmin)
            return torus_fill(&f, v3_madd(o, roots[i], d), scale, th, hit);
    }
    return 0;
}

/* -------------------------------------------- the torus as a field */

/* p's distance along the unit axis a (z) and from it (rho), and the unit
** radial direction e (ray__tangent_frame's t1 on the axis itself).  Only
** the axis is needed, not the whole frame: the field and its gradient
** are evaluated at every step of a march. */
static void torus_cylindrical(const ray_torus_params *t, ray_vec3 a,
                              ray_vec3 p, double *z, double *rho,
                              ray_vec3 *e)
{
    ray_vec3 q = v3_sub(p, t->center), radial, t2;

    *z = v3_dot(q, a);
    radial = v3_madd(q, -*z, a);
    *rho = v3_length(radial);
    if (!v3_normalize(radial, e))
        ray__tangent_frame(a, e, &t2);
}

/* The unit axis of params checked by ray__implicit_torus. */
static ray_vec3 torus_axis(const ray_torus_params *t)
{
    ray_vec3 a = v3(0, 0, 1);

    v3_normalize(t->axis, &a);
    return a;
}

/* The signed distance to the torus: |p - nearest point of the centre
** circle| - r.  1-Lipschitz, as every distance function is. */
static double torus_field(void *ud, ray_vec3 p)
{
    const ray_torus_params *t = ud;
    double z, rho;
    ray_vec3 e;

    torus_cylindrical(t, torus_axis(t), p, &z, &rho, &e);
    return ray__hypot(rho - t->major, z) - t->minor;
}

static ray_vec3 torus_gradient(void *ud, ray_vec3 p)
{
    const ray_torus_params *t = ud;
    double z, rho;
    ray_vec3 e, g;

    torus_cylindrical(t, torus_axis(t), p, &z, &rho, &e);
    g = v3_sub(p, v3_madd(t->center, t->major, e));
    return v3_normalize(g, &g) ? g : e;
}

/* ray_torus's (u, v): the angle around the axis, then around the tube. */
static void torus_uv(void *ud, ray_vec3 p, ray_vec3 n, double *u, double *v)
{
    const ray_torus_params *t = ud;
    torus_frame f;
    ray_vec3 q;
    double z, rho;
    ray_vec3 e;

    (void)n;
    torus_frame_init(t, &f);
    q = to_local(&f, v3_sub(p, f.c));
    torus_cylindrical(t, f.a, p, &z, &rho, &e);
    *u = atan2(q.y, q.x) / (2.0 * RAY__PI) + 0.5;
    *v = atan2(z, rho - t->major) / (2.0 * RAY__PI) + 0.5;
}

int ray__implicit_torus(const ray_torus_params *t, ray_implicit_surface *out)
{
    ray_implicit_surface s;

    if (out == NULL || !ray__torus_box(t, &s.lo, &s.hi))
        return RAY_EINVAL;
    s.f = torus_field;
    s.gradient = torus_gradient;
    s.uv = torus_uv;
    s.ud = ray__unconst(t);
    s.lipschitz = 1.0;
    s.step = 0;
    s.tolerance = 0;
    s.max_iterations = 0;
    *out = s;
    return RAY_OK;
}
