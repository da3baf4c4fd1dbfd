/* SPDX-License-Identifier: MIT */
/*
** newton.c -- ray_parametric's root finding at a leaf of its search
** (parametric.c): Newton's method on F(t, u, v) = e + t d - S(u, v) from
** the leaf's centre, and the test that a rectangle holds one crossing
** of the surface (the cosine between the ray and the normal keeps its
** sign), which decides when a start that did not settle is refined.
*/
#include "prim/parametric_search.h"

/* ---------------------------------------------------------------- Newton */

/*
** The Newton step for F(t, u, v) = e + t d - S(u, v): the Jacobian is
** J = [d, -S_u, -S_v], and J [dt du dv]^T = -F is solved by Cramer's rule
** (the lecture's), each 3x3 determinant written as a triple product
** det[a, b, c] = a . (b x c).  With N = S_u x S_v and g = -F:
**     D  = det[d, -S_u, -S_v] = d . N
**     dt = det[g, -S_u, -S_v] / D = g . N / D
**     du = det[d, g, -S_v] / D    = g . (d x S_v) / D
**     dv = det[d, -S_u, g] / D    = g . (S_u x d) / D
** D = 0 (or not finite) means the ray is parallel to the tangent plane:
** Newton has no step.  Returns 0 then, and the start ends as a miss
** (START_TANGENT), neither "stuck" nor refined: an exactly singular J
** is no evidence of a root, and it is what a ray lying in the plane of a
** planar patch meets at every start and every refinement -- such a ray
** misses, like ray_triangle's parallel rays.
*/
static int cramer_step(ray_vec3 d, ray_vec3 g, ray_vec3 s_u, ray_vec3 s_v,
                       double step[3])
{
    ray_vec3 n = v3_cross(s_u, s_v);
    double det = v3_dot(d, n);

    if (det == 0 || !isfinite(det))
        return 0;
    step[0] = v3_dot(g, n) / det;
    step[1] = v3_dot(g, v3_cross(d, s_v)) / det;
    step[2] = v3_dot(g, v3_cross(s_u, d)) / det;
    return 1;
}

/*
** The step when S does not move along one parameter here (see
** newton_step): least squares on the two columns left, a = d and
** b = -S_w, by the 2x2 normal equations (Gauss-Newton; Nocedal and
** Wright, "Numerical Optimization", 2nd ed., section 10.3), again by
** Cramer's rule, with det = (a.a)(b.b) - (a.b)^2 formed as |a x b|^2 so
** it cannot come out negative.  Where b is 0 or parallel to d, only t
** moves: to the point of the ray nearest S.  Writes dt and dw.
*/
static int reduced_step(ray_vec3 d, ray_vec3 g, ray_vec3 s_w, double *dt,
                        double *dw)
{
    ray_vec3 b = v3_scale(s_w, -1.0), axb = v3_cross(d, b);
    double aa = v3_dot(d, d), ab = v3_dot(d, b), bb = v3_dot(b, b);
    double ag = v3_dot(d, g), bg = v3_dot(b, g), det = v3_dot(axb, axb);

    if (det > 0 && isfinite(det)) {
        *dt = (ag * bb - ab * bg) / det;
        *dw = (aa * bg - ab * ag) / det;
    } else {
        *dt = ag / aa;
        *dw = 0;
    }
    return isfinite(*dt) && isfinite(*dw);
}

/* S moves by less than the tolerance when its parameter with partial
** s_w crosses the whole domain (of that "width"). */
int ray__param_still_along(const job *j, ray_vec3 s_w, double width)
{
    return max_abs(s_w) * width <= j->tol;
}

/* x stands on the border of [lo, hi] and dx pushes it out. */
static int pushed_out(double x, double dx, double lo, double hi)
{
    return (x == lo && dx < 0) || (x == hi && dx > 0);
}

/*
** One step from (t, u, v) into step[] = (dt, du, dv), for an iterate
** kept in the rectangle "box"; *held says whether u or v was held fixed.
** Returns 0 where Newton has no step (cramer_step).
**
** A parameter is held, and the others solved for by least squares
** (reduced_step), in two cases.  Where S_u (or S_v) is so small that
** moving u (v) across the whole domain would move S by less than the
** tolerance, S does not depend on it there -- the collapsed edge of a
** Bezier lid, where every u gives the apex -- and J is singular for want
** of that column, not because the ray is tangent.  And where the iterate
** stands on the border of its box and the full step would take it out:
** the iterate slides along the border, toward a root on it, or toward
** the point nearest the ray (an active-set method: Nocedal and Wright,
** section 16.5).  Near a collapsed edge the full step in u is huge (S_u
** is tiny there) though the root, the apex, is at hand: sliding reaches
** it instead of leaving.
*/
static int newton_step(const job *j, const rect *box, double u, double v,
                       ray_vec3 f, ray_vec3 s_u, ray_vec3 s_v,
                       double step[3], int *held)
{
    const rect *dom = &j->domain;
    ray_vec3 d = j->ray->dir, g = v3_scale(f, -1.0), zero = v3(0, 0, 0);
    int hold_u = ray__param_still_along(j, s_u, dom->u1 - dom->u0);
    int hold_v = ray__param_still_along(j, s_v, dom->v1 - dom->v0);

    if (!hold_u && !hold_v) {
        if (!cramer_step(d, g, s_u, s_v, step))
            return 0;
        hold_u = pushed_out(u, step[1], box->u0, box->u1);
        hold_v = pushed_out(v, step[2], box->v0, box->v1);
    }
    *held = hold_u || hold_v;
    if (!*held)
        return 1;
    step[1] = step[2] = 0;
    if (hold_u && hold_v)
        return reduced_step(d, g, zero, &step[0], &step[1]);
    if (hold_u)
        return reduced_step(d, g, s_v, &step[0], &step[2]);
    return reduced_step(d, g, s_u, &step[0], &step[1]);
}

/* |f| <= tol, without forming |f| when a component already exceeds tol
** (the usual case far from the root). */
static int within_tolerance(ray_vec3 f, double tol)
{
    if (fabs(f.x) > tol || fabs(f.y) > tol || fabs(f.z) > tol)
        return 0;
    return safe_length(f) <= tol;
}

static double clamp(double x, double lo, double hi)
{
    return x < lo ? lo : (x > hi ? hi : x);
}

/*
** Where the iterates of a start on rectangle r may go: r grown by
** GROWTH_FRACTION (so a root on the border between two rectangles is
** found from either), within the domain (where S is defined).
*/
static rect iterate_box(const job *j, const rect *r)
{
    double gu = (r->u1 - r->u0) * GROWTH_FRACTION;
    double gv = (r->v1 - r->v0) * GROWTH_FRACTION;
    rect b;

    b.u0 = clamp(r->u0 - gu, j->domain.u0, j->domain.u1);
    b.u1 = clamp(r->u1 + gu, j->domain.u0, j->domain.u1);
    b.v0 = clamp(r->v0 - gv, j->domain.v0, j->domain.v1);
    b.v1 = clamp(r->v1 + gv, j->domain.v0, j->domain.v1);
    return b;
}

/*
** The iterate (t, u, v) with S there is a root; keep it if it is in the
** ray's interval and nearer than the best so far -- by more than the
** tolerance (tol / |d| in t) once there is one: roots closer than that are
** the same root, found again from a refined leaf, and must not trigger
** another refinement.
*/
static int accept_root(job *j, double t, double u, double v, ray_vec3 s,
                       ray_vec3 s_u, ray_vec3 s_v)
{
    double before = j->t;

    if (j->found)
        before -= j->tol_t;
    /* Past tmin by more than the tolerance (t is known only to it): a
    ** closer root may be the surface the ray starts on (a ray leaving it),
    ** as ray_implicit's past_tmin explains. */
    if (!(t - j->tol_t > j->ray->tmin && t < before))
        return START_OUTSIDE;
    j->found = 1;
    j->t = t;
    j->u = u;
    j->v = v;
    j->p = s;
    j->s_u = s_u;
    j->s_v = s_v;
    return START_ROOT;
}

/*
** Newton from the centre of n's rectangle at t = n->tnear (where the ray
** enters its box: in [tmin, best) by the slab test).  An iterate is
** accepted when |F| <= tol.  Iterates are kept in iterate_box: a step
** out of it is cut at its border (Newton overshoots a root near the
** border, and S is only defined in the domain), and from there
** newton_step slides along it.  Two held steps in a row that do not
** halve max |F| (a convergent Gauss-Newton step more than halves it)
** mean the iterate is settling at the point nearest the ray with
** |F| > tol: the root, if any, is not in the box, and the start has
** "left".
*/
int ray__param_newton(job *j, const node *n)
{
    const ray_ray *r = j->ray;
    rect box = iterate_box(j, &n->r);
    double u = n->r.u0 + 0.5 * (n->r.u1 - n->r.u0);
    double v = n->r.v0 + 0.5 * (n->r.v1 - n->r.v0);
    /* tnear is -Inf only for tmin = -Inf and a slab t that overflowed;
    ** any finite start will do then. */
    double t = isfinite(n->tnear) ? n->tnear : 0.0;
    double last = HUGE_VAL;      /* max |F| at the last held step */
    unsigned k;

    for (k = 0;; k++) {
        ray_vec3 s, s_u, s_v, f;
        double step[3], size;
        int held;

        j->s->eval(j->s->ud, u, v, &s, &s_u, &s_v);
        if (!v3_isfinite(s) || !v3_isfinite(s_u) || !v3_isfinite(s_v))
            return START_BAD;
        f = v3_sub(v3_madd(r->org, t, r->dir), s);
        if (within_tolerance(f, j->tol)) {
            j->end_u = u;
            j->end_v = v;
            j->end_su = s_u;
            j->end_sv = s_v;
            return accept_root(j, t, u, v, s, s_u, s_v);
        }
        if (k == j->max_iter)
            return START_STUCK;
        if (!newton_step(j, &box, u, v, f, s_u, s_v, step, &held))
            return START_TANGENT;
        size = max_abs(f);
        if (held && !(size < 0.5 * last))
            return START_LEFT;
        last = held ? size : HUGE_VAL;
        t += step[0];
        /* Written so that a NaN iterate leaves. */
        if (!isfinite(t) || !isfinite(step[1]) || !isfinite(step[2]))
            return START_LEFT;
        u = clamp(u + step[1], box.u0, box.u1);
        v = clamp(v + step[2], box.v0, box.v1);
    }
}

/* ------------------------------------------------------- one crossing */

/*
** The cosine between the ray and the normal N = S_u x S_v: 0 (no
** cosine) where N is not defined well -- a partial "still" (a collapsed
** edge), N of no length, or values that are not finite (a sample point
** the search itself would not have asked for must not fail the call).
*/
static int cosine_of(const job *j, ray_vec3 n, ray_vec3 s_u, ray_vec3 s_v,
                     double *c)
{
    double ln, ld;

    if (!v3_isfinite(n) || !v3_isfinite(s_u) || !v3_isfinite(s_v) ||
        ray__param_still_along(j, s_u, j->domain.u1 - j->domain.u0) ||
        ray__param_still_along(j, s_v, j->domain.v1 - j->domain.v0))
        return 0;
    ln = safe_length(n);
    ld = safe_length(j->ray->dir);
    if (!(ln > 0) || !isfinite(ln))
        return 0;
    *c = v3_dot(v3_scale(n, 1.0 / ln), v3_scale(j->ray->dir, 1.0 / ld));
    return isfinite(*c);
}

static int cosine_at(const job *j, double u, double v, double *c)
{
    ray_vec3 s, s_u, s_v;

    j->s->eval(j->s->ud, u, v, &s, &s_u, &s_v);
    return v3_isfinite(s) && cosine_of(j, v3_cross(s_u, s_v), s_u, s_v, c);
}

/* The range [lo, hi] of the cosines so far grown to hold c. */
static void widen_range(double c, double *lo, double *hi)
{
    *lo = c < *lo ? c : *lo;
    *hi = c > *hi ? c : *hi;
}

/*
** The range [*lo, *hi] of the cosine c = d.N/(|d||N|) over the corners
** and the centre of r; 0 where a sample has none (see cosine_of).
*/
int ray__param_cosine_range(const job *j, const rect *r, double *lo,
                            double *hi)
{
    double us[3], vs[3], c;
    int k;

    us[0] = r->u0;
    us[1] = r->u0 + 0.5 * (r->u1 - r->u0);
    us[2] = r->u1;
    vs[0] = r->v0;
    vs[1] = r->v0 + 0.5 * (r->v1 - r->v0);
    vs[2] = r->v1;
    *lo = HUGE_VAL;
    *hi = -HUGE_VAL;
    /* The corners, (0, 0) to (2, 2) by twos, and the centre (1, 1). */
    for (k = 0; k < 5; k++) {
        int a = k < 4 ? 2 * (k & 1) : 1, b = k < 4 ? (k & 2) : 1;
        if (!cosine_at(j, us[a], vs[b], &c))
            return 0;
        widen_range(c, lo, hi);
    }
    return 1;
}

/*
** Whether the ray crosses a piece of S at most once, judged from the
** range [lo, hi] of the cosine c = d.N/(|d||N|) sampled on it (its
** corners and centre, and a root on it).  Two crossings S(p1) = e + t1 d,
** S(p2) = e + t2 d make the projection of S along d take the same value
** at p1 and p2; by the mean value theorem on the segment p1 p2 (in the
** convex rectangle) the projection's 2x2 Jacobian, whose determinant is
** d.N, must then be singular or far from constant between them, so d.N
** vanishes on the piece or N turns widely over it (the argument behind
** the uniqueness of a root where the Jacobian stays near a fixed
** invertible matrix: Ortega and Rheinboldt, "Iterative Solution of
** Nonlinear Equations", 5.3).  A sampled test, not a proof: every
** sample's c has the same sign, and the smallest |c| exceeds the spread
** max c - min c: for c to vanish between the samples it would have to
** leave their range by more than the range itself, and on a leaf (1/16
** of a bicubic patch's domain each way, by default), where the normal is
** close to linear, it moves less.
*/
static int one_crossing(double lo, double hi)
{
    if (lo > 0)
        return lo > hi - lo;
    if (hi < 0)
        return -hi > hi - lo;
    return 0;
}

/*
** The last start's root lies in r (not only in its grown iterate box,
** which the samples do not cover), and with the cosine there added to
** the range [lo, hi] sampled on r the ray crosses r's piece only there.
*/
int ray__param_root_settles(const job *j, const rect *r, double lo,
                            double hi)
{
    double c;

    if (!(j->end_u >= r->u0 && j->end_u <= r->u1 && j->end_v >= r->v0 &&
          j->end_v <= r->v1) ||
        !cosine_of(j, v3_cross(j->end_su, j->end_sv), j->end_su, j->end_sv,
                   &c))
        return 0;
    widen_range(c, &lo, &hi);
    return one_crossing(lo, hi);
}

