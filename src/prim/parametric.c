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
** Newton starts from the centre (newton.c); a leaf whose start did not
** settle is split further (visit_leaf, REFINE_LEVELS).  Known
** limit: a ray grazing a curved surface so closely that both of its
** crossings fall in one leaf, and Newton picks the far one from every
** start, gets the far one (on random rays at a paraboloid, 1 in 3000, all
** within 3 degrees of tangency).
*/
#include "prim/parametric_search.h"
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
    int end = ray__param_newton(j, n);

    if (end == START_BAD)
        return 0;
    if (end == START_OUTSIDE || end == START_TANGENT)
        return 1;
    /* A root the ray crosses nowhere else in the leaf: nothing nearer. */
    if (end == START_ROOT) {
        double lo, hi;
        if (ray__param_cosine_range(j, &n->r, &lo, &hi) &&
            ray__param_root_settles(j, &n->r, lo, hi))
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
    if (ray__param_still_along(j, s_u, j->domain.u1 - j->domain.u0) ||
        ray__param_still_along(j, s_v, j->domain.v1 - j->domain.v0))
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
