/* SPDX-License-Identifier: MIT */
/*
** capsule.c -- ray / capsule: the points at distance "radius" from the
** segment [a, b], a cylinder around the segment closed by two
** hemispheres.  The capsule is convex, so a ray crosses its surface at
** most twice, entering and leaving; each crossing is found on the
** infinite cylinder first and, where it falls beyond an end of the
** segment, on that end's cap sphere instead.  Every quadratic is solved
** in the cancellation-free arrangement of ray_sphere (sphere.c).
*/
#include <stdio.h>

#include "prim/prim.h"

/*
** The capsule in its own frame: the origin at the segment's midpoint m
** (so a far-away capsule keeps its digits: a ray near it differs from m
** by a small f), z along the unit axis w from a to b, x and y along the
** tangents t1, t2 that ray_plane takes for the normal w
** (ray__tangent_frame).  The segment is z in [-half, half].  A point
** capsule (a == b) takes w = +y, so that its (u, v) are ray_sphere's.
*/
typedef struct capsule_frame {
    ray_vec3 m, t1, t2, w;
    double half, radius;
    double m_max;                /* max |m_i|: for the error bounds */
} capsule_frame;

/* The largest |component| of v. */
static double max_abs(ray_vec3 v)
{
    return fmax(fabs(v.x), fmax(fabs(v.y), fabs(v.z)));
}

/*
** p_err of every hit point, per component: the projected point of
** fill_hit is formed in the capsule's frame from a unit vector (4
** roundings of a normalisation) times the radius, plus +-half, then
** rotated and added to m (5 roundings of terms summing to at most
** |m_i| + 2 radius + half); the computed frame itself is orthonormal
** and on the exact axis to about 10 roundings (h's rounding, the
** normalisation, ray__tangent_frame's 4 operations), which moves a point
** at distance radius + half from m by that much; m rounds once.  Well
** inside gamma(32) (|m_i| + 2 (radius + half)), the bound ray_torus
** uses for a comparable chain.
*/
static ray_vec3 point_error(const capsule_frame *k)
{
    double g = ray__gamma(32), reach = 2 * (k->radius + k->half);

    return v3(g * (fabs(k->m.x) + reach), g * (fabs(k->m.y) + reach),
              g * (fabs(k->m.z) + reach));
}

/*
** The frame of valid params, 1; else 0.  Valid: a, b finite, 0 < radius
** < Inf, and the capsule's box grown by twice the point error finite (so
** are then every hit point and its bound).  m and h = (b - a)/2 are
** formed from the halves, which cannot overflow; |h| through
** v3_normalize's scaling, for the same reason.
*/
static int capsule_setup(const ray_capsule_params *c, capsule_frame *k,
                         ray_vec3 *lo, ray_vec3 *hi)
{
    ray_vec3 h, e, l, u;
    double hm;

    if (c == NULL || !v3_isfinite(c->a) || !v3_isfinite(c->b) ||
        !(c->radius > 0 && c->radius < HUGE_VAL))
        return 0;
    k->m = v3_add(v3_scale(c->a, 0.5), v3_scale(c->b, 0.5));
    h = v3_sub(v3_scale(c->b, 0.5), v3_scale(c->a, 0.5));
    hm = max_abs(h);
    if (v3_normalize(h, &k->w))
        k->half = hm * v3_length(v3(h.x / hm, h.y / hm, h.z / hm));
    else {
        k->w = v3(0, 1, 0);
        k->half = 0;
    }
    ray__tangent_frame(k->w, &k->t1, &k->t2);
    k->radius = c->radius;
    k->m_max = max_abs(k->m);
    /* The box: the segment's box grown by radius and twice the point
    ** error (which also covers the two roundings of forming it). */
    e = v3_scale(point_error(k), 2.0);
    l = v3(fmin(c->a.x, c->b.x), fmin(c->a.y, c->b.y), fmin(c->a.z, c->b.z));
    u = v3(fmax(c->a.x, c->b.x), fmax(c->a.y, c->b.y), fmax(c->a.z, c->b.z));
    l = v3_sub(v3_sub(l, v3(c->radius, c->radius, c->radius)), e);
    u = v3_add(v3_add(u, v3(c->radius, c->radius, c->radius)), e);
    if (!v3_isfinite(l) || !v3_isfinite(u) || !isfinite(k->half))
        return 0;
    if (lo != NULL) {
        *lo = l;
        *hi = u;
    }
    return 1;
}

int ray__capsule_check(const ray_capsule_params *p, ray_vec3 *lo,
                       ray_vec3 *hi, char *why, size_t why_size)
{
    capsule_frame k;

    if (capsule_setup(p, &k, lo, hi))
        return 1;
    if (p == NULL)
        snprintf(why, why_size, "capsule parameters are NULL");
    else if (!v3_isfinite(p->a))
        snprintf(why, why_size, "end a (%g, %g, %g) is not finite", p->a.x,
                 p->a.y, p->a.z);
    else if (!v3_isfinite(p->b))
        snprintf(why, why_size, "end b (%g, %g, %g) is not finite", p->b.x,
                 p->b.y, p->b.z);
    else if (!(p->radius > 0 && p->radius < HUGE_VAL))
        snprintf(why, why_size, "radius %g is not positive and finite",
                 p->radius);
    else
        snprintf(why, why_size, "the capsule (radius %g, ends (%g, %g, %g) "
                 "and (%g, %g, %g)) reaches beyond the largest double",
                 p->radius, p->a.x, p->a.y, p->a.z, p->b.x, p->b.y, p->b.z);
    return 0;
}

/* v in the capsule's frame (x along t1, y along t2, z along w). */
static ray_vec3 to_frame(const capsule_frame *k, ray_vec3 v)
{
    return v3(v3_dot(v, k->t1), v3_dot(v, k->t2), v3_dot(v, k->w));
}

/* Frame vector v in world axes. */
static ray_vec3 from_frame(const capsule_frame *k, ray_vec3 v)
{
    return v3_add(v3_add(v3_scale(k->t1, v.x), v3_scale(k->t2, v.y)),
                  v3_scale(k->w, v.z));
}

/*
** The point of the capsule's surface nearest q (ray_closest_point): the
** point of the segment nearest q, s (q's height along the axis in the
** frame, f_z, clamped to [-half, half]), moved by radius away from the
** segment along q - s.  The same whether q is outside or inside: the
** capsule is the set of points within radius of the segment.  q on the
** segment (q - s = 0 exactly): every point at radius around it is as
** near; t1's direction is taken.  p is formed as fill_hit forms a hit
** point, from a unit vector in the frame, so it lies within point_error
** of the surface; the error of f (4 roundings of |q - m| and the
** frame's) moves it along the surface.  0 if q - m overflows.
*/
int ray__capsule_closest(const ray_capsule_params *c, ray_vec3 q,
                         ray_vec3 *p, ray_vec3 *n)
{
    capsule_frame k;
    ray_vec3 rel, f, nl, pt, nw;
    double zc;

    if (!capsule_setup(c, &k, NULL, NULL))
        return 0;
    rel = v3_sub(q, k.m);
    if (!v3_isfinite(rel))
        return 0;
    f = to_frame(&k, rel);
    zc = fmin(fmax(f.z, -k.half), k.half);
    if (!v3_normalize(v3(f.x, f.y, f.z - zc), &nl))
        nl = v3(1, 0, 0);
    pt = v3_add(k.m, from_frame(&k, v3(k.radius * nl.x, k.radius * nl.y,
                                       zc + k.radius * nl.z)));
    if (!v3_isfinite(pt) || !v3_normalize(from_frame(&k, nl), &nw))
        return 0;
    *p = pt;
    *n = nw;
    return 1;
}

/*
** a t^2 - 2 b t + c = 0 for a circle (n = 2: the cylinder's cross
** section) or a sphere (n = 3: a cap) of radius R about the origin, for
** the line f + t d: a = d.d, b = -f.d, c = (|f| - R)(|f| + R), and
** disc = (b^2 - ac)/a = (R - l)(R + l) with l = |f + (b/a) d| the
** distance from the centre to the line's closest point (ray_sphere's
** arrangement: nothing squares before it subtracts, so a far or a huge
** capsule keeps R's digits).  da .. ddisc bound the errors of the four
** (below).
*/
typedef struct quadratic {
    double a, b, c, disc;
    double da, db, dc, ddisc;
} quadratic;

/*
** Set up *k; ef and ed bound the errors of each component of f and d
** (how well the frame's coordinates know the exact ray: see
** ray_capsule).  The running error analysis of ray_sphere's
** sphere_t_error (Higham, "Accuracy and Stability of Numerical
** Algorithms", 2nd ed., 3.1), with the inputs' errors added to first
** order (and their products, for safety):
**   a = sum d_i^2:    da = gamma(3) a + 2 sum |d_i| ed + n ed^2;
**   b = -sum f_i d_i: db = gamma(3) sum |f_i d_i| + sum (|f_i| ed +
**                          |d_i| ef) + n ef ed;
**   |f| within dlen = gamma(4) |f| + 2 ef (sqrt(n) ef, n <= 3), so
**                     dc = dlen (|f| + R + ||f| - R|) + dlen^2 + gamma(3) |c|;
**   l within dl = gamma(8) (|f| + |b/a| |d|) (ray_sphere's) + 2 ef (f
**                 moved) + 4 |f| ed / |d| (the line turned by ed / |d|
**                 about f moves its closest point by at most
**                 2 |f| that angle, in each of 2 ways), so
**                 ddisc = dl (R + l + |R - l|) + dl^2 + gamma(3) |disc|.
** 1 when set up; 0 when the line misses (disc < 0) or a result is not a
** number; -1 when a = 0: the line's direction is 0 (for the cylinder: it
** runs along the axis), and the quadratic degenerates.
*/
static int quadratic_setup(quadratic *k, const double *f, const double *d,
                           int n, double R, double ef, double ed)
{
    double fd = 0, fa = 0, da = 0, f2 = 0, flen, dlen, l2 = 0, l, dl, ddf;
    int i;

    k->a = k->b = 0;
    for (i = 0; i < n; i++) {
        k->a += d[i] * d[i];
        k->b -= f[i] * d[i];
        f2 += f[i] * f[i];
        fd += fabs(f[i] * d[i]);
        fa += fabs(f[i]);
        da += fabs(d[i]);
    }
    if (k->a == 0)
        return -1;
    if (!(k->a > 0))
        return 0;
    for (i = 0; i < n; i++) {
        double li = f[i] + (k->b / k->a) * d[i];
        l2 += li * li;
    }
    l = sqrt(l2);
    k->disc = (R - l) * (R + l);
    if (!(k->disc >= 0))        /* < 0: the line misses; NaN: bad input */
        return 0;
    flen = sqrt(f2);
    dlen = sqrt(k->a);
    k->c = (flen - R) * (flen + R);
    k->da = ray__gamma(3) * k->a + 2 * da * ed + n * ed * ed;
    k->db = ray__gamma(3) * fd + fa * ed + da * ef + n * ef * ed;
    ddf = ray__gamma(4) * flen + 2 * ef;
    k->dc = ddf * (flen + R + fabs(flen - R)) + ddf * ddf +
            ray__gamma(3) * fabs(k->c);
    dl = ray__gamma(8) * (flen + fabs(k->b / k->a) * dlen) + 2 * ef +
         4 * flen * ed / dlen;
    k->ddisc = dl * (R + l + fabs(R - l)) + dl * dl +
               ray__gamma(3) * fabs(k->disc);
    return 1;
}

/* Its roots, t0 <= t1 (Press et al., Numerical Recipes, 5.6: q = b +
** sign(b) sqrt(a disc), t = c/q and q/a, each from an addition of like
** signs).  A NaN root (0/0, the tangent at t = 0) fails every test. */
static void quadratic_roots(const quadratic *k, double *t0, double *t1)
{
    double q = k->b + copysign(sqrt(k->a * k->disc), k->b);
    double r0 = k->c / q, r1 = q / k->a;

    *t0 = r0 < r1 ? r0 : r1;
    *t1 = r0 < r1 ? r1 : r0;
}

/*
** A bound on the error of the root t, as ray_sphere's sphere_t_error:
** the coefficients' errors move g(t) = a t^2 - 2 b t + c by at most
** dg = dc + 2 |t| db + t^2 da, and so a simple root by dg / |g'(t)| =
** dg / (2 s), s = sqrt(a disc) (to first order; times 2 for the second),
** and a double root by at most 2 sqrt(dg / a): the smaller holds.  The
** root's own evaluation (q = b +- s, then c/q or q/a) adds |t| ds / s +
** gamma(4) |t|, ds bounding s's error from da and ddisc.
*/
static double quadratic_t_error(const quadratic *k, double t)
{
    double at = fabs(t);
    double dg = k->dc + 2 * at * k->db + at * at * k->da;
    double s = sqrt(k->a * k->disc), s_low, ds, simple, twofold;

    s_low = sqrt(fmax(k->a - k->da, 0.0) * fmax(k->disc - k->ddisc, 0.0)) *
            (1 - ray__gamma(4));
    ds = s - s_low;
    twofold = k->a > k->da ? 2 * sqrt(dg / (k->a - k->da)) : HUGE_VAL;
    simple = s_low > 0 ? dg / s_low : HUGE_VAL;
    return fmin(simple, twofold) * (1 + ray__gamma(4)) +
           (s > 0 ? at * ds / s : 0) + ray__gamma(4) * at;
}

/* The ray in the capsule's frame: origin F (relative to m), direction D
** (scaled), each component within ef, ed of the exact ray's. */
typedef struct capsule_ray {
    double F[3], D[3];
    double ef, ed, eh;           /* eh: the error of half */
} capsule_ray;

/* A crossing of the surface: its t (scaled), the error bound of t, and
** the part it lies on: -1 a's cap, 0 the cylinder, +1 b's cap. */
typedef struct crossing {
    double t, err;
    int part;
} crossing;

/*
** Crossing "which" (0 entering, 1 leaving) of the ray with the cap of
** side "part" (-1: a, +1: b), the sphere about z = part * half: 0 if
** the ray misses that sphere.
*/
static int cap_crossing(const capsule_frame *k, const capsule_ray *cr,
                        int part, int which, crossing *out)
{
    quadratic q;
    double f[3], t0, t1;

    f[0] = cr->F[0];
    f[1] = cr->F[1];
    f[2] = cr->F[2] - part * k->half;
    /* f[2] rounds once more, and the centre is known to eh. */
    if (quadratic_setup(&q, f, cr->D, 3, k->radius,
                         cr->ef + cr->eh + ray__gamma(1) * fabs(f[2]),
                         cr->ed) != 1)
        return 0;
    quadratic_roots(&q, &t0, &t1);
    out->t = which == 0 ? t0 : t1;
    out->err = quadratic_t_error(&q, out->t);
    out->part = part;
    return 1;
}

/*
** The two crossings of the ray with the capsule, entering and leaving;
** returns how many of them exist (0: a miss, 2: both).
**
** The cylinder x^2 + y^2 = R^2 first.  Its crossing at height z = F_z +
** t D_z is the capsule's if |z| <= half.  Past an end, it is the
** crossing of that end's cap sphere: the capsule lies inside the
** cylinder, so a ray entering the cylinder above b's end stays outside
** the capsule until it enters b's sphere, which it meets (through the
** disc z = half, inside the sphere) before it could reach the slab of
** the cylinder or a's sphere; and leaving likewise.  Choosing by the
** cylinder's z leaves no crack at a seam: there the two roots agree.
** A ray outside the cylinder misses the capsule.
**
** The ray parallel to the axis (a = D_x^2 + D_y^2 = 0 exactly: the
** quadratic degenerates to a constant) is inside the cylinder for all t
** or never: it enters it at z = -Inf D_z and leaves it at +Inf D_z,
** i.e. enters by a's cap and leaves by b's when D_z > 0.  No epsilon:
** a direction merely close to the axis has a > 0 and the far roots that
** the cylinder really has.  (a is also 0 when D_x, D_y are below 2^-538
** or so, |D| being about 1, and their squares underflow: such a ray
** drifts off the axis' direction by less than 1e-162 per unit of t, and
** is taken as parallel.)
*/
static int capsule_crossings(const capsule_frame *k, const capsule_ray *cr,
                             crossing out[2])
{
    quadratic q;
    double t[2], z[2];
    int i, n = 0, have_q;

    have_q = quadratic_setup(&q, cr->F, cr->D, 2, k->radius, cr->ef,
                             cr->ed);
    if (have_q == 0)
        return 0;               /* outside the cylinder, or not a number */
    if (have_q == 1) {
        quadratic_roots(&q, &t[0], &t[1]);
        z[0] = cr->F[2] + t[0] * cr->D[2];
        z[1] = cr->F[2] + t[1] * cr->D[2];
    } else {
        double fl = sqrt(cr->F[0] * cr->F[0] + cr->F[1] * cr->F[1]);

        if (!(fl <= k->radius))
            return 0;           /* outside the cylinder, or not a number */
        z[0] = cr->D[2] > 0 ? -HUGE_VAL : HUGE_VAL;
        z[1] = -z[0];
        t[0] = t[1] = 0;        /* unused: both crossings are on caps */
    }
    for (i = 0; i < 2; i++) {
        /* A NaN z stays on the cylinder, whose NaN t then fails. */
        int part = z[i] < -k->half ? -1 : (z[i] > k->half ? 1 : 0);

        if (part != 0) {
            if (cap_crossing(k, cr, part, i, &out[n]))
                n++;
        } else if (have_q == 1) {
            out[n].t = t[i];
            out[n].err = quadratic_t_error(&q, t[i]);
            out[n].part = 0;
            n++;
        }
    }
    return n;
}

/*
** Fill *hit for crossing x at world t: the point of the ray in the
** capsule's frame, P = F + t D, is projected onto the part it lies on
** (as ray_sphere does: what is left of t's error lies along the
** surface): on the cylinder, radially, z kept and clamped to the
** segment; on a cap, from its centre, kept on the cap's side of the seam.
** (u, v) as ray.h states; p_err from point_error.  0, *hit untouched, if
** anything is not finite.
*/
static int fill_hit(const capsule_frame *k, const capsule_ray *cr,
                    const crossing *x, double t_world, ray_hit *hit)
{
    double R = k->radius, L = k->half, zc = x->part * L;
    double P[3], s, r, l, total, arc, rho, u;
    ray_vec3 nl, n, p, err;
    int i;

    for (i = 0; i < 3; i++)
        P[i] = cr->F[i] + x->t * cr->D[i];
    if (x->part == 0) {
        if (!v3_normalize(v3(P[0], P[1], 0), &nl))
            return 0;
        nl.z = 0;
        zc = fmin(fmax(P[2], -L), L);
    } else {
        if (!v3_normalize(v3(P[0], P[1], P[2] - zc), &nl))
            return 0;
        /* Rounding may put the normal a hair past the seam, where the
        ** cap's point would lie inside the cylinder: onto the seam. */
        nl.z = x->part < 0 ? fmin(nl.z, 0.0) : fmax(nl.z, 0.0);
        if (!v3_normalize(nl, &nl))
            return 0;
    }
    p = v3_add(k->m, from_frame(k, v3(R * nl.x, R * nl.y, zc + R * nl.z)));
    if (!v3_normalize(from_frame(k, nl), &n))
        return 0;
    err = point_error(k);
    /* v: arc length along the meridian from a's pole over the meridian's
    ** whole length pi R + 2 half, both divided by s = max(R, half) so
    ** neither overflows. */
    s = fmax(R, L);
    r = R / s;
    l = L / s;
    total = RAY__PI * r + 2 * l;
    rho = sqrt(nl.x * nl.x + nl.y * nl.y);
    if (x->part < 0)
        arc = r * atan2(rho, -nl.z);
    else if (x->part > 0)
        arc = total - r * atan2(rho, nl.z);
    else
        arc = r * (RAY__PI / 2) + (zc + L) / s;
    u = atan2(nl.x, -nl.y) / (2.0 * RAY__PI) + 0.5;
    if (!v3_isfinite(p) || !v3_isfinite(err) || !isfinite(arc / total) ||
        !isfinite(u))
        return 0;
    hit->t = t_world;
    hit->p = p;
    hit->n = n;
    hit->u = u;
    hit->v = fmin(fmax(arc / total, 0.0), 1.0);
    hit->p_err = err;
    hit->geom_id = RAY_INVALID_ID;
    hit->prim_id = RAY_INVALID_ID;
    hit->inst_id = RAY_INVALID_ID;
    return 1;
}

/*
** The ray's errors in the frame, per component: f = org - m carries m's
** rounding (u |m_i|) and its own (u |f_i|); rotating f and d into the
** frame adds 3 roundings of the dot products and the frame's own error,
** about 10 roundings off an exact orthonormal frame on the exact axis
** (point_error): within gamma(16) (|f| + |m|) and gamma(16) |d|.  half
** rounds in about 8 operations: gamma(8) half.
*/
int ray_capsule(const ray_ray *r, const ray_capsule_params *c,
                ray_hit *hit)
{
    capsule_frame k;
    capsule_ray cr;
    crossing x[2];
    ray_vec3 f, d, F, D;
    double tmin, tmax, t;
    int i, n, e;

    if (r == NULL || hit == NULL || !capsule_setup(c, &k, NULL, NULL) ||
        !ray__scaled_dir(r->dir, &d, &e))
        return 0;
    f = v3_sub(r->org, k.m);
    F = to_frame(&k, f);
    D = to_frame(&k, d);
    cr.F[0] = F.x, cr.F[1] = F.y, cr.F[2] = F.z;
    cr.D[0] = D.x, cr.D[1] = D.y, cr.D[2] = D.z;
    cr.ef = ray__gamma(16) * (v3_length(f) + 2 * k.m_max);
    cr.ed = ray__gamma(16) * v3_length(d);
    cr.eh = ray__gamma(8) * k.half;
    n = capsule_crossings(&k, &cr, x);
    /* tmin, tmax in the scaled direction's units (ray__scaled_dir).
    ** The nearer crossing whose whole error interval lies past tmin. */
    tmin = ray__scale_t(r->tmin, e);
    tmax = ray__scale_t(r->tmax, e);
    for (i = 0; i < n; i++) {
        if (!(x[i].t > tmin && x[i].t < tmax && x[i].t - x[i].err > tmin))
            continue;
        t = ray__unscale_t(x[i].t, e);
        if (!(t > r->tmin && t < r->tmax))  /* the product rounded past */
            return 0;
        return fill_hit(&k, &cr, &x[i], t, hit);
    }
    return 0;
}
