/* SPDX-License-Identifier: MIT */
/*
** implicit.c -- ray / implicit surface f(p) = 0, as root finding on
** g(t) = f(org + t*dir): march along the ray to bracket the first sign
** change (by sphere tracing when a Lipschitz bound is known, else by a
** fixed step), then refine the bracket.
*/
#include "prim/prim.h"

/* The descriptor with its defaults filled in, and the ray's own scale. */
typedef struct implicit_job {
    const ray_implicit_surface *s;
    const ray_ray *r;
    double dlen;             /* |dir|: t steps of world length dt * dlen */
    double tol_t;            /* the tolerance in units of t */
    double step_t;           /* the fixed sampling step in units of t */
    double lip_t;            /* Lipschitz bound of g: L * |dir|; 0 = none */
    unsigned evals_left;     /* max_iterations, counted down */
    int bad;                 /* f returned NaN or Inf */
} implicit_job;

/* Defaults of the header: the step is 1/128 of the box diagonal (a dozen
** samples cross a feature a tenth of the box wide); the tolerance is
** ray__default_tolerance's.  Sphere tracing
** needs about 3 sqrt(2 R / tol) steps to bring a ray tangent to a surface
** of curvature radius R within the tolerance (the distance along the
** tangent shrinks as x^2 / 2R): 63,000 for a sphere filling its box, so
** 100,000 evaluations let tangent rays end in a touch, not a failure. */
#define DEFAULT_STEPS_PER_DIAGONAL 128.0
#define DEFAULT_MAX_ITERATIONS 100000u

static int descriptor_valid(const ray_implicit_surface *s)
{
    return s->f != NULL && v3_isfinite(s->lo) && v3_isfinite(s->hi) &&
           s->lo.x <= s->hi.x && s->lo.y <= s->hi.y && s->lo.z <= s->hi.z &&
           s->lipschitz >= 0 && s->lipschitz < HUGE_VAL && s->step >= 0 &&
           s->step < HUGE_VAL && s->tolerance >= 0 &&
           s->tolerance < HUGE_VAL;
}

int ray__implicit_valid(const ray_implicit_surface *s)
{
    return s != NULL && descriptor_valid(s);
}

/*
** The part of the ray inside the box, grown by the tolerance (a surface
** may touch the box), in double: [*t0, *t1] within [tmin, tmax].  A zero
** direction component gives an infinite 1/d (IEEE) and a slab that is
** everything or nothing; a NaN from 0 * Inf (origin on a slab plane) is
** ignored by the comparisons, which keeps the slab.
*/
static int clip_to_box(const ray_ray *r, ray_vec3 lo, ray_vec3 hi,
                       double *t0, double *t1)
{
    double a = r->tmin, b = r->tmax;
    int k;

    for (k = 0; k < 3; k++) {
        double inv = 1.0 / v3_axis(r->dir, k), o = v3_axis(r->org, k);
        double tn = (v3_axis(lo, k) - o) * inv, tf = (v3_axis(hi, k) - o) * inv;
        if (tn > tf) {
            double x = tn;
            tn = tf;
            tf = x;
        }
        if (tn > a)
            a = tn;
        if (tf < b)
            b = tf;
    }
    *t0 = a;
    *t1 = b;
    return a <= b;
}

/* g(t), counted; NaN or Inf marks the job bad. */
static double job_eval(implicit_job *j, double t)
{
    double g;

    if (j->evals_left > 0)
        j->evals_left--;
    g = j->s->f(j->s->ud, v3_madd(j->r->org, t, j->r->dir));
    if (!isfinite(g)) {
        j->bad = 1;
        return 0;
    }
    return g;
}

/*
** grad f at p: the callback's, or central differences with step
** h = cbrt(DBL_EPSILON) * scale, which balances the truncation error
** (~h^2 f''') against the rounding error (~eps f / h) of the quotient
** (Press et al., Numerical Recipes, 3rd ed., 5.7).  "scale" is that of
** the box, so h follows the surface's size.
*/
/* cbrt(DBL_EPSILON) = 2^(-52/3), correctly rounded (60-digit decimal
** arithmetic), written out rather than asked of the C runtime's cbrt,
** which differs between C libraries (doc/PLATFORMS.md): the step, and so
** the hit, must be the same bits everywhere. */
#define CBRT_EPSILON 0x1.965fea53d6e3dp-18

static ray_vec3 job_gradient(implicit_job *j, ray_vec3 p)
{
    const ray_implicit_surface *s = j->s;
    double h, g[3];
    int k;

    /* Charged to max_iterations like the samples: one call of the
    ** gradient callback, or the six of f below. */
    unsigned cost = s->gradient != NULL ? 1u : 6u;

    j->evals_left -= j->evals_left < cost ? j->evals_left : cost;
    if (s->gradient != NULL)
        return s->gradient(s->ud, p);
    h = CBRT_EPSILON *
        fmax(v3_length(v3_sub(s->hi, s->lo)), DBL_MIN);
    for (k = 0; k < 3; k++) {
        ray_vec3 e = v3(k == 0, k == 1, k == 2);
        ray_vec3 hi = v3_madd(p, h, e), lo = v3_madd(p, -h, e);
        /* Divide by the step actually taken: p +- h rounds, and far from
        ** the origin that rounding is a large part of h (Numerical
        ** Recipes' "temp = x + h; h = temp - x"). */
        g[k] = (s->f(s->ud, hi) - s->f(s->ud, lo)) /
               (v3_axis(hi, k) - v3_axis(lo, k));
    }
    return v3(g[0], g[1], g[2]);
}

static int opposite(double a, double b)
{
    return (a < 0 && b > 0) || (a > 0 && b < 0);
}

/*
** The root in [a, b], where g(a) = ga and g(b) = gb have opposite signs.
** Each step tries Newton (when f has a gradient callback: g' = grad f .
** dir) and otherwise the Illinois variant of regula falsi (Dowell and
** Jarratt, BIT 11, 1971: the stale end's value is halved so the bracket
** keeps shrinking from both sides); a candidate outside the bracket, or a
** bracket that did not halve in a step, falls back to bisection, so the
** bracket shrinks at least as fast as bisection's every other step
** (Brent's safeguard, "Algorithms for Minimization without Derivatives",
** 1973, ch. 4).  Ends when the bracket is narrower than the tolerance or
** holds no double between its ends.  *width receives its final width.
*/
static double refine(implicit_job *j, double a, double b, double ga,
                     double gb, double *width)
{
    double prev_width = HUGE_VAL;
    int stale = 0;           /* the end kept last step: -1 a, +1 b */

    while (b - a > j->tol_t && j->evals_left > 0 && !j->bad) {
        double cand = (a * gb - b * ga) / (gb - ga), gx;
        if (j->s->gradient != NULL) {
            /* Newton from the end nearer the root (smaller |g|). */
            double x0 = fabs(ga) < fabs(gb) ? a : b;
            double g0 = x0 == a ? ga : gb;
            ray_vec3 grad = j->s->gradient(
                j->s->ud, v3_madd(j->r->org, x0, j->r->dir));
            double newton = x0 - g0 / v3_dot(grad, j->r->dir);
            if (newton > a && newton < b)    /* a NaN step fails here */
                cand = newton;
        }
        /* Bisect when the candidate is outside or the last step did not
        ** halve the bracket. */
        if (!(cand > a && cand < b) || b - a > 0.5 * prev_width)
            cand = 0.5 * (a + b);
        if (cand <= a || cand >= b)  /* no double strictly inside */
            break;
        prev_width = b - a;
        gx = job_eval(j, cand);
        if (gx == 0) {
            a = b = cand;
            break;
        }
        if (opposite(gx, ga)) {
            b = cand;
            gb = gx;
            if (stale == -1)
                ga *= 0.5;
            stale = -1;
        } else {
            a = cand;
            ga = gx;
            if (stale == 1)
                gb *= 0.5;
            stale = 1;
        }
    }
    *width = b - a;
    /* The estimate inside the final bracket: where the chord crosses 0. */
    if (a == b)
        return a;
    {
        double x = (a * gb - b * ga) / (gb - ga);
        return x >= a && x <= b ? x : 0.5 * (a + b);
    }
}

/*
** A double root near t: the march reached |g(t)| <= L |dir| tol_t (the
** surface may be within the tolerance) without a sign change.  One Newton
** step along the gradient, q = p - f grad f / |grad f|^2, moves toward
** the surface; if f changes sign between p and q and |q - p| is within
** the tolerance, the surface touches the ray there: a real hit.
** *slope receives g'(t) = grad f . dir, for the caller's look ahead.
*/
static int touches(implicit_job *j, double t, double g, double *dist,
                   double *slope)
{
    const ray_implicit_surface *s = j->s;
    ray_vec3 p = v3_madd(j->r->org, t, j->r->dir), grad = job_gradient(j, p);
    double gg = v3_dot(grad, grad), fq;
    ray_vec3 q;

    if (!(gg > 0) || !isfinite(gg))
        return 0;
    *slope = v3_dot(grad, j->r->dir);
    if (g * *slope > 0)      /* |g| grows along the ray: moving away */
        return 0;
    q = v3_madd(p, -g / gg, grad);
    *dist = v3_length(v3_sub(q, p));
    if (!(*dist <= j->tol_t * j->dlen))
        return 0;
    if (j->evals_left > 0)
        j->evals_left--;
    fq = s->f(s->ud, q);
    if (!isfinite(fq)) {
        j->bad = 1;
        return 0;
    }
    return fq == 0 || opposite(fq, g);
}

/*
** The ray near the surface at (t, g) may still cross it a little further
** on (a ray at a shallow angle: the march's minimum step gains only
** tol * cos(angle) on the surface per step).  Newton along the ray
** predicts the crossing at t - g / g'; a sample twice as far is tried, and
** a sign change there brackets the crossing for refine(), which is much
** more accurate than taking t itself.  Returns 1 with *tb, *gb on a
** bracket.
*/
static int crossing_ahead(implicit_job *j, double t, double g, double slope,
                          double t1, double *tb, double *gb)
{
    double ahead = -2 * g / slope;

    if (!(ahead > 0) || !(ahead < HUGE_VAL))
        return 0;
    *tb = t + ahead < t1 ? t + ahead : t1;
    *gb = job_eval(j, *tb);
    return !j->bad && opposite(g, *gb);
}

/*
** The next sample after t: sphere tracing's step |g| / (L |dir|) -- no
** root can be nearer -- but never less than the tolerance, so the march
** ends; or the fixed step without a bound.
*/
/* The smallest step: the tolerance, but never below 2 ulps of t, since
** a smaller step would round back to t and sample the same point again
** until the evaluations ran out (a ray from far away, or a tolerance
** below the spacing of the doubles near t). */
static double floor_step(const implicit_job *j, double t)
{
    return fmax(j->tol_t, 2 * DBL_EPSILON * fabs(t));
}

static double next_step(const implicit_job *j, double t, double g)
{
    double floor_t = floor_step(j, t);

    if (j->lip_t > 0)
        return fmax(fabs(g) / j->lip_t, floor_t);
    return fmax(j->step_t, floor_t);
}

/*
** Is a root at t past tmin by more than the tolerance?  The root is known
** only to the tolerance along the ray (the bracket's width, or the touch's
** distance), so one closer to tmin may be the surface the ray starts on
** (a ray leaving it, its origin within the tolerance of it): not a hit.
** The same rule as the analytic primitives' rounding-error bounds
** (ray__watertight_t_error in watertight.h); ray_spawn offsets by twice
** p_err, which covers the tolerance, so secondary rays clear it.
*/
static int past_tmin(const implicit_job *j, double t)
{
    return t - j->tol_t > j->r->tmin;
}

/*
** March from t0 to t1.  Returns 1 with *t and *err (the world distance
** within which the surface lies from the ray point at *t) on a hit, 0 on a
** miss, -1 when the evaluations ran out.
*/
static int march(implicit_job *j, double t0, double t1, double *t,
                 double *err)
{
    double ta = t0, ga = job_eval(j, t0);

    /* A root exactly at the start counts only if it is past tmin. */
    if (ga == 0 && past_tmin(j, t0) && !j->bad) {
        *t = t0;
        *err = 0;
        return 1;
    }
    while (!j->bad) {
        double h = next_step(j, ta, ga), tb, gb, width, slope;
        if (j->evals_left == 0)
            return -1;
        tb = ta + h < t1 ? ta + h : t1;
        gb = job_eval(j, tb);
        if (j->bad)
            break;
        /* An exact zero counts as a root past tmin only as any root does
        ** (past_tmin): a step from a start at tmin can land on tmin
        ** itself when the box starts behind the ray (found by
        ** fuzz/fuzz_surfaces: a hit at t = tmin = 0). */
        if (gb == 0 && past_tmin(j, tb) && tb < j->r->tmax) {
            *t = tb;
            *err = 0;
            return 1;
        }
        if (opposite(ga, gb)) {
            *t = refine(j, ta, tb, ga, gb, &width);
            if (j->bad)
                break;
            if (width > j->tol_t && j->evals_left == 0)
                return -1;   /* ran out before the bracket was narrow */
            *err = width * j->dlen;
            if (past_tmin(j, *t))
                return *t < j->r->tmax;
            /* A root within the tolerance of tmin: the ray leaving the
            ** surface it starts on.  Not a hit; look further along. */
            ta = tb;
            ga = gb;
            continue;
        }
        if (j->lip_t > 0 && h <= floor_step(j, ta) && ga != 0 &&
            ta > j->r->tmin &&
            touches(j, ta, ga, err, &slope)) {
            if (crossing_ahead(j, ta, ga, slope, t1, &tb, &gb)) {
                *t = refine(j, ta, tb, ga, gb, &width);
                if (width > j->tol_t && j->evals_left == 0)
                    return -1;
                *err = width * j->dlen;
            } else {
                *t = ta;
            }
            if (j->bad)
                break;
            return past_tmin(j, *t) && *t < j->r->tmax;
        }
        if (tb >= t1)
            return 0;
        ta = tb;
        ga = gb;
    }
    return -2;
}

/*
** Fill *hit at t: p = org + t*dir, whose rounding is at most gamma(2) of
** |org| + |t dir| per component, and the surface within "err" of it.
*/
static int implicit_fill(implicit_job *j, double t, double err,
                         ray_hit *hit)
{
    const ray_implicit_surface *s = j->s;
    const ray_ray *r = j->r;
    ray_vec3 p = v3_madd(r->org, t, r->dir), n, perr;
    double u = 0, v = 0;

    if (!v3_normalize(job_gradient(j, p), &n))
        return -RAY_EINVAL;
    if (s->uv != NULL) {
        s->uv(s->ud, p, n, &u, &v);
        if (!isfinite(u) || !isfinite(v))
            return -RAY_EINVAL;
    }
    perr = v3_add(v3_scale(v3_add(v3_abs(r->org),
                                  v3_scale(v3_abs(r->dir), fabs(t))),
                           ray__gamma(2)),
                  v3(err, err, err));
    if (!v3_isfinite(p) || !v3_isfinite(perr))
        return -RAY_EINVAL;
    hit->t = t;
    hit->p = p;
    hit->n = n;
    hit->u = u;
    hit->v = v;
    hit->p_err = perr;
    hit->geom_id = RAY_INVALID_ID;
    hit->prim_id = RAY_INVALID_ID;
    hit->inst_id = RAY_INVALID_ID;
    return 1;
}

double ray__implicit_tolerance(const ray_implicit_surface *s)
{
    return s->tolerance > 0 ? s->tolerance
                            : ray__default_tolerance(s->lo, s->hi);
}

int ray_implicit(const ray_ray *r, const ray_implicit_surface *s,
                 ray_hit *hit)
{
    implicit_job j;
    double tol, diag, t0, t1, t, err;
    int found;

    if (s == NULL || hit == NULL || r == NULL || !descriptor_valid(s))
        return -RAY_EINVAL;
    j.dlen = v3_length(r->dir);
    if (!v3_isfinite(r->org) || !(j.dlen > 0 && j.dlen < HUGE_VAL) ||
        !(r->tmin < r->tmax))
        return 0;
    tol = ray__implicit_tolerance(s);
    if (!(tol > 0))          /* a point box at the origin: nothing to find */
        return 0;
    if (!clip_to_box(r, v3_sub(s->lo, v3(tol, tol, tol)),
                     v3_add(s->hi, v3(tol, tol, tol)), &t0, &t1))
        return 0;
    diag = v3_length(v3_sub(s->hi, s->lo));
    j.s = s;
    j.r = r;
    j.tol_t = tol / j.dlen;
    j.step_t = fmax(s->step > 0 ? s->step : diag / DEFAULT_STEPS_PER_DIAGONAL,
                    tol) / j.dlen;
    j.lip_t = s->lipschitz * j.dlen;
    j.evals_left = s->max_iterations > 0 ? s->max_iterations
                                         : DEFAULT_MAX_ITERATIONS;
    j.bad = 0;
    found = march(&j, t0, t1, &t, &err);
    if (found == -1)
        return -RAY_ELIMIT;
    if (found < 0 || j.bad)
        return -RAY_EINVAL;
    return found ? implicit_fill(&j, t, err, hit) : 0;
}
