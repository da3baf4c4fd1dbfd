/* SPDX-License-Identifier: MIT */
/*
** parametric_search.h -- the search of ray_parametric, private to its two files:
** parametric.c walks the (u, v) domain's quad tree and fills the hit;
** newton.c runs Newton's method from a leaf and tells whether a
** rectangle holds one crossing.  Their settings, a rectangle of the
** domain, a node of the quad tree, and the search's state (job).
*/
#ifndef RAY_PARAMETRIC_SEARCH_H
#define RAY_PARAMETRIC_SEARCH_H

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

/* |a|, scaled by its largest component first so that it neither
** overflows nor underflows (as v3_normalize). */
static inline double safe_length(ray_vec3 a)
{
    double m = fmax(fabs(a.x), fmax(fabs(a.y), fabs(a.z)));

    if (!(m > 0))
        return m == 0 ? 0 : m;
    return m * v3_length(v3_scale(a, 1.0 / m));
}

/* max |component| of a finite vector, by comparisons (fmax is a library
** call without -ffinite-math-only, and this runs at every Newton step). */
static inline double max_abs(ray_vec3 a)
{
    double x = fabs(a.x), y = fabs(a.y), z = fabs(a.z);
    double m = x > y ? x : y;

    return m > z ? m : z;
}

static inline ray_vec3 abs_max(ray_vec3 lo, ray_vec3 hi)
{
    return v3(fmax(fabs(lo.x), fabs(hi.x)), fmax(fabs(lo.y), fabs(hi.y)),
              fmax(fabs(lo.z), fabs(hi.z)));
}

/*
** newton.c's, for the search:
** ray__param_newton -- Newton's method from the centre of node n's
** rectangle: how the start ended (START_*), the root kept in j when
** accepted.
** ray__param_still_along -- is partial s_w so short beside the ray's
** direction that the surface is collapsed there (an edge shrunk to a
** point)?
** ray__param_cosine_range -- bounds *lo, *hi on the cosine between the
** ray and the surface's normal over rectangle r; 0 where they cannot
** be had.
** ray__param_root_settles -- does rectangle r, whose cosine lies in [lo,
** hi], hold one crossing at most, so that a start there settles?
*/
int ray__param_newton(job *j, const node *n);
int ray__param_still_along(const job *j, ray_vec3 s_w, double width);
int ray__param_cosine_range(const job *j, const rect *r, double *lo,
                            double *hi);
int ray__param_root_settles(const job *j, const rect *r, double lo,
                            double hi);

#endif /* RAY_PARAMETRIC_SEARCH_H */
