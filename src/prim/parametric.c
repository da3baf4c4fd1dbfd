/* SPDX-License-Identifier: MIT */
/*
** parametric.c -- ray / parametric surface S(u, v) (the lecture's "ray ∩
** parametric object"): e + t d = S(u, v) solved for (t, u, v) by Newton's
** method, from starting points found by subdividing the (u, v) domain.
**
** The problem was posed for patches by Kajiya ("Ray Tracing Parametric
** Patches", SIGGRAPH 1982, who solved it algebraically); the method here is
** the one that replaced his: boxes of sub-patches cull the domain and give
** each surviving piece a starting point, and Newton's method converges
** from it (Sweeney and Bartels, "Ray Tracing Free-Form B-Spline Surfaces",
** IEEE CG&A 6(2), 1986; Martin, Cohen, Fish and Shirley, "Practical Ray
** Tracing of Trimmed NURBS Surfaces", JGT 5(1), 2000, sections 3-4).
**
** In order: the domain's quad tree is walked depth first, nearest box
** first, dropping rectangles whose box the ray misses or enters beyond
** the best root so far (search, split, ray_meets_box); at each leaf
** Newton starts from the centre (newton, newton_step); a leaf whose start
** did not settle is split further (visit_leaf, REFINE_LEVELS).  Known
** limit: a ray grazing a curved surface so closely that both of its
** crossings fall in one leaf, and Newton picks the far one from every
** start, gets the far one (on random rays at a paraboloid, 1 in 3000, all
** within 3 degrees of tangency).
*/
#include "prim/prim.h"

/* The header's defaults: 4 levels give 16 x 16 starting rectangles, on
** which Newton converges from the centre for the smooth patches of
** modelling (Martin et al. stop refining at a similar flatness); 16
** steps leave room for the handful that quadratic convergence needs plus
** the slow linear convergence toward a double (tangent) root, where |F|
** still falls by 4 per step. */
#define DEFAULT_SUBDIVISIONS 4u
#define DEFAULT_MAX_ITERATIONS 16u

/* The deepest quad tree accepted: at 12 levels a rectangle is 1/4096 of
** the domain in each direction, finer than any starting point needs; the
** bound also sizes the traversal stack. */
#define MAX_SUBDIVISIONS 12u

/*
** A leaf whose start did not give a root is split again, up to
** REFINE_LEVELS more levels, rather than given up (Sweeney and Bartels's
** refinement): the boxes of its quarters either miss the ray, which
** proves the miss, or give starts nearer the root.  It matters for a ray
** missing a curved surface by a hair, where Newton wanders ("stuck"), and
** for a ray crossing a leaf near a tangency, whose two close roots send
** Newton against the leaf's border ("left").  A leaf that gave a root is
** split too, to look for a nearer root in the same leaf (a grazing ray
** can cross one leaf twice, and Newton from the centre may pick the far
** crossing) -- unless the normals sampled on the leaf show that the ray
** crosses it only once (one_crossing): then nothing nearer is there, and
** the 4 boxes and starts of that refinement (~20% of a hit's work) are
** saved for 6 evaluations.  A convex patch's box exceeds it by about its
** curvature times the piece's size squared, so 8 more levels (2^-16 of
** that excess) prove misses by 1e-6 of the patch's size.
** REFINE_BOX_BUDGET caps the boxes the refinement may ask for, so a
** pathological ray (one lying along a ruling of the surface) ends as
** non-convergence instead of taking 4^8 times longer: under 1 ms for a
** Bezier patch.  On random rays at strongly folded random patches the
** most any ray used was ~4000 (at a budget of 1024, 1 ray in 5000 ran
** out; the average is ~40-100).
*/
#define REFINE_LEVELS 8u
#define REFINE_BOX_BUDGET 4096u

/*
** The descent to "subdivisions" levels is bounded too: at most
** DESCENT_BOX_BUDGET boxes per ray (4 per split), after which the ray
** ends as non-convergence (-RAY_ELIMIT) rather than visiting every leaf of
** a 12-level tree, 4^12 = 16.7 million of them, for a ray lying in a flat
** patch (found by fuzz/fuzz_surfaces: 25 s for one ray).  A ray crossing
** a 4096 x 4096 grid of leaves in a straight line meets ~2 x 4096 of them
** and their ancestors, about 4 x 2 x 12 x 4096 / 12 boxes: the budget,
** 2^18, leaves room for 8 times that, and bounds a ray's work to a few
** tens of milliseconds.
*/
#define DESCENT_BOX_BUDGET 262144u
#define MAX_LEVELS (MAX_SUBDIVISIONS + REFINE_LEVELS)

/* Depth-first traversal: popping a node and pushing its 4 children adds
** at most 3 entries per level below the root. */
#define STACK_SIZE (3u * MAX_LEVELS + 1u)

/* A Newton iterate may stray 1/16 of its rectangle's size beyond it, so
** a root on the border between two rectangles is found from either. */
#define GROWTH_FRACTION (1.0 / 16.0)

/*
** Where S_u x S_v vanishes (a collapsed edge: every point of the top row
** of a Bezier lid is the apex), the normal is taken a little toward the
** domain's centre: first 1e-6 of the domain's size, where the cross
** product is ~1e-6 of its typical length (far above its rounding) and
** the normal turns by ~1e-6 radians (far below what shading shows), then
** 100 times farther, twice, for surfaces degenerate over a wider band.
*/
#define NUDGE_FIRST 1e-6
#define NUDGE_GROWTH 100.0
#define NUDGE_TRIES 3

/*
** The rounding of a point evaluated as a convex combination of points of
** the surface's box by nested sums, as ray_bezier_surface does (18
** roundings, counted in bezier.c); see fill_hit.
*/
#define EVAL_ROUNDINGS 18

typedef struct rect {
    double u0, u1, v0, v1;
} rect;

typedef struct node {
    rect r;
    double tnear;            /* where the ray enters its box */
    unsigned level;          /* 0: the whole domain */
    unsigned quad;           /* its quarter of its parent: bit 0 the
                                upper u half, bit 1 the upper v half */
} node;

/* A halved control net (ray__bezier_split): 7 x 7 points. */
#define GRID_POINTS (RAY__BEZIER_GRID * RAY__BEZIER_GRID)

/* How one Newton start ended. */
enum {
    START_ROOT,              /* accepted: the new nearest hit */
    START_LEFT,              /* no root in reach: see newton() */
    START_TANGENT,           /* no step: the ray is parallel to S there */
    START_OUTSIDE,           /* a root outside (tmin, best so far) */
    START_STUCK,             /* max_iterations steps, still inside */
    START_BAD                /* the callback returned NaN or Inf */
};

/* The descriptor with its defaults filled in, and the search's state. */
typedef struct job {
    const ray_ray *ray;
    const ray_parametric_surface *s;
    rect domain;
    double tol;
    double tol_t;            /* tol / |d|: the tolerance in units of t */
    unsigned levels, max_iter;
    unsigned refine_left;    /* boxes refinement may still ask for */
    unsigned descent_left;   /* boxes the descent may still ask for */
    int exhausted;           /* the descent ran out of its budget */
    ray_vec3 scale;          /* per axis, max |coordinate| of the box */
    int found;
    int undecided;           /* a start stuck, or refinement cut short */
    double t, u, v;          /* the nearest accepted root */
    ray_vec3 p, s_u, s_v;    /* S and its partials there */
    double end_u, end_v;     /* where the last start's root was */
    ray_vec3 end_su, end_sv; /* S_u and S_v there */
    /* The Bezier fast path (see bezier_search); cp NULL: the callbacks. */
    const ray_vec3 *cp;      /* the patch's 16 control points */
    ray_vec3 mag;            /* ray__bezier_magnitude */
    ray_vec3 (*grids)[GRID_POINTS]; /* grids[L - 1]: level L's nets */
} job;

/* ------------------------------------------------------------ validation */

/* The domain, [0, 1]^2 when all four are 0; 0 if it is empty or not
** finite (written so that NaN fails). */
static int domain_of(const ray_parametric_surface *s, rect *d)
{
    if (s->u0 == 0 && s->u1 == 0 && s->v0 == 0 && s->v1 == 0) {
        d->u0 = 0;
        d->u1 = 1;
        d->v0 = 0;
        d->v1 = 1;
        return 1;
    }
    d->u0 = s->u0;
    d->u1 = s->u1;
    d->v0 = s->v0;
    d->v1 = s->v1;
    return d->u0 < d->u1 && d->v0 < d->v1 && isfinite(d->u1 - d->u0) &&
           isfinite(d->v1 - d->v0);
}

static int settings_valid(const ray_parametric_surface *s)
{
    return s->eval != NULL && s->bounds != NULL &&
           s->subdivisions <= MAX_SUBDIVISIONS && s->tolerance >= 0 &&
           s->tolerance < HUGE_VAL;
}

int ray__parametric_domain(const ray_parametric_surface *s, double d[4])
{
    rect r;

    if (s == NULL || !settings_valid(s) || !domain_of(s, &r))
        return 0;
    d[0] = r.u0;
    d[1] = r.u1;
    d[2] = r.v0;
    d[3] = r.v1;
    return 1;
}

/* |a|, scaled by its largest component first so that it neither
** overflows nor underflows (as v3_normalize). */
static double safe_length(ray_vec3 a)
{
    double m = fmax(fabs(a.x), fmax(fabs(a.y), fabs(a.z)));

    if (!(m > 0))
        return m == 0 ? 0 : m;
    return m * v3_length(v3_scale(a, 1.0 / m));
}

/* max |component| of a finite vector, by comparisons (fmax is a library
** call without -ffinite-math-only, and this runs at every Newton step). */
static double max_abs(ray_vec3 a)
{
    double x = fabs(a.x), y = fabs(a.y), z = fabs(a.z);
    double m = x > y ? x : y;

    return m > z ? m : z;
}

static ray_vec3 abs_max(ray_vec3 lo, ray_vec3 hi)
{
    return v3(fmax(fabs(lo.x), fabs(hi.x)), fmax(fabs(lo.y), fabs(hi.y)),
              fmax(fabs(lo.z), fabs(hi.z)));
}

/* ----------------------------------------------------------------- boxes */

/* The box of S over "r" from the callback; 0 if it is not finite or has
** lo > hi on some axis (a broken callback). */
static int box_of(const job *j, const rect *r, ray_vec3 *lo, ray_vec3 *hi)
{
    j->s->bounds(j->s->ud, r->u0, r->u1, r->v0, r->v1, lo, hi);
    return v3_isfinite(*lo) && v3_isfinite(*hi) && lo->x <= hi->x &&
           lo->y <= hi->y && lo->z <= hi->z;
}

/*
** Slab test (Kay and Kajiya, SIGGRAPH 1986) of the ray, on (tmin, best
** root so far), against the box grown by the tolerance, so a surface
** that touches its box, or a root accepted within the tolerance of the
** ray, is not culled.  A zero direction component is handled apart (the
** slab is everything or nothing): no 0 * Inf = NaN can occur, so an
** origin on a slab plane keeps the box.  Each slab t = (x - o)/d carries
** two roundings; widening both ends by 2 gamma(3)|t| covers them and the
** widening's own (pbrt-v4 Bounds3::IntersectP's 1 + 2 gamma(3)).  The
** entry t goes to *tnear; the test is inclusive, so conservative.
*/
static int ray_meets_box(const job *j, ray_vec3 lo, ray_vec3 hi,
                         double *tnear)
{
    const ray_ray *r = j->ray;
    double t0 = r->tmin, t1 = j->t, widen = 2 * ray__gamma(3);
    int k;

    for (k = 0; k < 3; k++) {
        double o = v3_axis(r->org, k), d = v3_axis(r->dir, k);
        double a = v3_axis(lo, k) - j->tol, b = v3_axis(hi, k) + j->tol;
        double ta, tb;

        if (d == 0) {
            if (!(o >= a && o <= b))
                return 0;
            continue;
        }
        ta = (a - o) / d;
        tb = (b - o) / d;
        if (ta > tb) {
            double x = ta;
            ta = tb;
            tb = x;
        }
        ta -= widen * fabs(ta);
        tb += widen * fabs(tb);
        if (ta > t0)
            t0 = ta;
        if (tb < t1)
            t1 = tb;
    }
    *tnear = t0;
    return t0 <= t1 && t0 < j->t;
}

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
static int still_along(const job *j, ray_vec3 s_w, double width)
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
    int hold_u = still_along(j, s_u, dom->u1 - dom->u0);
    int hold_v = still_along(j, s_v, dom->v1 - dom->v0);

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
static int newton(job *j, const node *n)
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
        still_along(j, s_u, j->domain.u1 - j->domain.u0) ||
        still_along(j, s_v, j->domain.v1 - j->domain.v0))
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
static int cosine_range(const job *j, const rect *r, double *lo, double *hi)
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
static int root_settles(const job *j, const rect *r, double lo, double hi)
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

/* ------------------------------------------------------------- traversal */

/*
** The control net of a Bezier node: the patch's own at the root, else
** its quarter of the 7 x 7 grid its parent was halved into.  The grid
** of level L is still there when a node of level L is popped: the stack
** holds levels in non-decreasing order from the bottom (a popped node
** is the deepest, and its children go on top one level deeper), so no
** node of a deeper level is left to have overwritten it.
*/
static const ray_vec3 *net_of(const job *j, const node *n, int *stride)
{
    if (n->level == 0) {
        *stride = 4;
        return j->cp;
    }
    *stride = RAY__BEZIER_GRID;
    return j->grids[n->level - 1] + ray__bezier_quarter(n->quad);
}

/*
** The boxes of n's 4 quarters (numbered as node.quad): by the callback,
** or for a Bezier patch from its net halved by de Casteljau into the
** grid of the children's level -- one halving (~400 flops) instead of 4
** nets rebuilt from the whole patch.  Returns 0 if a box is not finite
** (box_of also checks the callback's for lo > hi; a net's box, a
** min and max, cannot have it).
*/
static int quarter_boxes(const job *j, const node *n, const rect kid[4],
                         ray_vec3 lo[4], ray_vec3 hi[4])
{
    const ray_vec3 *net;
    int stride;
    unsigned q;

    if (j->cp == NULL) {
        for (q = 0; q < 4; q++)
            if (!box_of(j, &kid[q], &lo[q], &hi[q]))
                return 0;
        return 1;
    }
    net = net_of(j, n, &stride);
    ray__bezier_split(net, stride, j->mag, n->level + 1,
                      j->grids[n->level], lo, hi);
    for (q = 0; q < 4; q++)
        if (!v3_isfinite(lo[q]) || !v3_isfinite(hi[q]))
            return 0;
    return 1;
}

/*
** Push the quarters of n whose boxes the ray meets (before the best root
** so far), the farthest first so that the nearest is popped next.
** Returns 0 if a box was not finite.
*/
static int split(job *j, const node *n, node *stack, unsigned *top)
{
    double um = n->r.u0 + 0.5 * (n->r.u1 - n->r.u0);
    double vm = n->r.v0 + 0.5 * (n->r.v1 - n->r.v0);
    node kids[4];
    rect kid[4];
    ray_vec3 lo[4], hi[4];
    unsigned count = 0, q, a;

    for (q = 0; q < 4; q++) {
        kid[q].u0 = (q & 1u) ? um : n->r.u0;
        kid[q].u1 = (q & 1u) ? n->r.u1 : um;
        kid[q].v0 = (q & 2u) ? vm : n->r.v0;
        kid[q].v1 = (q & 2u) ? n->r.v1 : vm;
    }
    if (!quarter_boxes(j, n, kid, lo, hi))
        return 0;
    for (q = 0; q < 4; q++) {
        node c;

        c.r = kid[q];
        c.level = n->level + 1;
        c.quad = q;
        if (ray_meets_box(j, lo[q], hi[q], &c.tnear))
            kids[count++] = c;
    }
    /* Insertion sort of at most 4, by decreasing tnear. */
    for (q = 1; q < count; q++) {
        node c = kids[q];
        for (a = q; a > 0 && kids[a - 1].tnear < c.tnear; a--)
            kids[a] = kids[a - 1];
        kids[a] = c;
    }
    for (q = 0; q < count; q++)
        stack[(*top)++] = kids[q];
    return 1;
}

/*
** A leaf: Newton from its centre.  Unless the start ended on a root
** outside the ray's interval (nothing nearer to find there) or at a
** singular system (see cramer_step), the leaf is refined (see
** REFINE_LEVELS).  At the deepest level a start that left is
** a miss and a stuck one is non-convergence; once the box budget is
** spent, any start without a root leaves the answer undecided
** (non-convergence too: reported, not taken for a miss).  Returns 0 on
** bad callback values.
*/
static int visit_leaf(job *j, const node *n, node *stack, unsigned *top)
{
    int end = newton(j, n);

    if (end == START_BAD)
        return 0;
    if (end == START_OUTSIDE || end == START_TANGENT)
        return 1;
    /* A root the ray crosses nowhere else in the leaf: nothing nearer. */
    if (end == START_ROOT) {
        double lo, hi;
        if (cosine_range(j, &n->r, &lo, &hi) && root_settles(j, &n->r, lo, hi))
            return 1;
    }
    if (n->level >= j->levels + REFINE_LEVELS) {
        if (end == START_STUCK)
            j->undecided = 1;
        return 1;
    }
    if (j->refine_left < 4) {
        if (end != START_ROOT)
            j->undecided = 1;
        return 1;
    }
    j->refine_left -= 4;
    return split(j, n, stack, top);
}

/* Depth-first over the quad tree from "root"; 0 on bad callback values. */
static int search(job *j, const node *root)
{
    node stack[STACK_SIZE];
    unsigned top = 0;

    stack[top++] = *root;
    while (top > 0) {
        node n = stack[--top];

        if (!(n.tnear < j->t))       /* a nearer root was found since */
            continue;
        if (n.level < j->levels) {
            if (j->descent_left < 4) {
                j->exhausted = 1;     /* a root found so far may not be */
                return 1;             /* the nearest: -RAY_ELIMIT */
            }
            j->descent_left -= 4;
            if (!split(j, &n, stack, &top))
                return 0;
        } else if (!visit_leaf(j, &n, stack, &top)) {
            return 0;
        }
    }
    return 1;
}

/*
** The Bezier fast path: bounds from control nets carried down the quad
** tree (quarter_boxes), for a surface made by ray_bezier_surface over
** its own domain [0, 1]^2 (a user-set domain takes the callbacks, which
** clamp to it).  The nets' boxes contain the exact sub-patches, as the
** callback's do (rounding bounds in bezier.c), so the same rectangles
** survive up to boxes differing by rounding (at most ~1e-14 of max
** |cp|, the size of the 64-ulp term of the default tolerance the slab
** test grows them by).  The grids take MAX_LEVELS * 49 * 24 bytes
** (~23 KiB) of stack, here only, not on the generic path.  0 on bad
** callback values.
*/
static int bezier_search(job *j, const node *root)
{
    ray_vec3 grids[MAX_LEVELS][GRID_POINTS];

    j->mag = ray__bezier_magnitude(j->cp);
    j->grids = grids;
    return search(j, root);
}

/* ------------------------------------------------------------ hit record */

/* The point (u, v) moved "frac" of the domain's size toward its centre. */
static void toward_centre(const rect *d, double frac, double *u, double *v)
{
    double uc = d->u0 + 0.5 * (d->u1 - d->u0);
    double vc = d->v0 + 0.5 * (d->v1 - d->v0);

    *u += (*u <= uc ? frac : -frac) * (d->u1 - d->u0);
    *v += (*v <= vc ? frac : -frac) * (d->v1 - d->v0);
}

/* The unit S_u x S_v; 0 where a partial is "still" (its cross product is
** then rounding noise) or the product has no length. */
static int normal_from(const job *j, ray_vec3 s_u, ray_vec3 s_v,
                       ray_vec3 *n)
{
    if (still_along(j, s_u, j->domain.u1 - j->domain.u0) ||
        still_along(j, s_v, j->domain.v1 - j->domain.v0))
        return 0;
    return v3_normalize(v3_cross(s_u, s_v), n);
}

/*
** The unit normal S_u x S_v at the root, else a little toward the centre
** (NUDGE_*: collapsed edges).  Where it stays degenerate the surface has
** no tangent plane near the hit (it is collapsed to a curve or a point),
** so no side is its front: -d/|d|, facing the ray, at least lets shading
** light it and ray_spawn offset toward the side the ray came from.
** Returns 0 if the callback returned NaN or Inf.
*/
static int root_normal(const job *j, ray_vec3 *n)
{
    double frac = NUDGE_FIRST;
    int k;

    if (normal_from(j, j->s_u, j->s_v, n))
        return 1;
    for (k = 0; k < NUDGE_TRIES; k++, frac *= NUDGE_GROWTH) {
        double u = j->u, v = j->v;
        ray_vec3 s, s_u, s_v;

        toward_centre(&j->domain, frac, &u, &v);
        j->s->eval(j->s->ud, u, v, &s, &s_u, &s_v);
        if (!v3_isfinite(s) || !v3_isfinite(s_u) || !v3_isfinite(s_v))
            return 0;
        if (normal_from(j, s_u, s_v, n))
            return 1;
    }
    return v3_normalize(v3_scale(j->ray->dir, -1.0), n);
}

/*
** The hit record.  p = S(u, v) is a point of the surface up to the
** callback's rounding; the ray passes within the tolerance of it.  p_err
** = tol + gamma(18) * scale per axis, scale = max |coordinate| of the
** surface's box: gamma(18) * scale bounds the rounding of a point
** evaluated as a convex combination of points of the box (Higham, Lemma
** 3.1), which is how ray_bezier_surface evaluates (bezier.c); the
** tolerance term covers callbacks that round more, as long as they round
** less than the tolerance -- the premise of accepting |F| <= tol at all.
** Returns 0 (nothing written) on bad callback values.
*/
static int fill_hit(const job *j, ray_hit *hit)
{
    ray_vec3 n;

    if (!root_normal(j, &n))
        return 0;
    hit->t = j->t;
    hit->p = j->p;
    hit->n = n;
    hit->u = j->u;
    hit->v = j->v;
    hit->p_err = v3(j->tol + ray__gamma(EVAL_ROUNDINGS) * j->scale.x,
                    j->tol + ray__gamma(EVAL_ROUNDINGS) * j->scale.y,
                    j->tol + ray__gamma(EVAL_ROUNDINGS) * j->scale.z);
    hit->geom_id = RAY_INVALID_ID;
    hit->prim_id = RAY_INVALID_ID;
    hit->inst_id = RAY_INVALID_ID;
    return 1;
}

/* ------------------------------------------------------------------- API */

/*
** The defaults and the whole surface's box; 0 if the box is bad or the
** surface too large for its tolerance to be finite.
*/
static int job_init(job *j, const ray_ray *r, const ray_parametric_surface *s,
                    ray_vec3 *lo, ray_vec3 *hi)
{
    j->ray = r;
    j->s = s;
    j->levels = s->subdivisions ? s->subdivisions : DEFAULT_SUBDIVISIONS;
    j->max_iter = s->max_iterations ? s->max_iterations
                                    : DEFAULT_MAX_ITERATIONS;
    j->refine_left = REFINE_BOX_BUDGET;
    j->descent_left = DESCENT_BOX_BUDGET;
    j->exhausted = 0;
    j->found = 0;
    j->undecided = 0;
    j->t = r->tmax;
    j->u = j->v = 0;
    if (!box_of(j, &j->domain, lo, hi))
        return 0;
    j->scale = abs_max(*lo, *hi);
    j->tol = s->tolerance;
    if (j->tol == 0)
        j->tol = ray__default_tolerance(*lo, *hi);
    j->tol_t = j->tol / safe_length(r->dir);
    return isfinite(j->tol);
}

/*
** NULL pointers and invalid descriptors are -RAY_EINVAL, as in
** ray_implicit; an invalid ray is a miss, decided before any callback
** runs.
*/
int ray_parametric(const ray_ray *r, const ray_parametric_surface *s,
                   ray_hit *hit)
{
    job j;
    node root;
    ray_vec3 lo, hi;

    if (r == NULL || s == NULL || hit == NULL || !settings_valid(s) ||
        !domain_of(s, &j.domain))
        return -RAY_EINVAL;
    if (!ray__ray_usable(r))
        return 0;
    if (!job_init(&j, r, s, &lo, &hi))
        return -RAY_EINVAL;
    if (!ray_meets_box(&j, lo, hi, &root.tnear))
        return 0;
    root.r = j.domain;
    root.level = 0;
    root.quad = 0;
    j.cp = ray__bezier_points(s);
    if (j.cp != NULL && !(j.domain.u0 == 0 && j.domain.u1 == 1 &&
                          j.domain.v0 == 0 && j.domain.v1 == 1))
        j.cp = NULL;
    if (!(j.cp != NULL ? bezier_search(&j, &root) : search(&j, &root)))
        return -RAY_EINVAL;
    if (j.exhausted)
        return -RAY_ELIMIT;
    if (j.found)
        return fill_hit(&j, hit) ? 1 : -RAY_EINVAL;
    return j.undecided ? -RAY_ELIMIT : 0;
}
