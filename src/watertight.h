/*
** watertight.h -- the watertight ray/triangle test, split in two: what
** depends on the ray alone (its frame, set up once per ray) and the test
** of one triangle in that frame with the interval (tmin, tmax).  Inline,
** so the BVH traversal pays no call per triangle; ray_triangle_watertight
** (triangle.c) is the two together, so both give the same answers.
*/
#ifndef RAY_WATERTIGHT_H
#define RAY_WATERTIGHT_H

#include "internal.h"

typedef struct ray__watertight {
    ray__frame f;            /* kx, ky swapped for a negative dz */
    double sz;               /* 1 / dz */
} ray__watertight;

/*
** The 2x2 edge function a_x b_y - a_y b_x in long double (64 significant
** bits on x86, 113 on AArch64 Linux, plain double on some platforms).
** Used only to re-evaluate the edge functions when one is exactly 0 in
** double: more often then its true sign shows.  It stays exactly
** antisymmetric, fl(p - q) = -fl(q - p), so two triangles sharing the
** edge still get opposite values.
*/
static inline double ray__edge_extended(double ax, double ay, double bx,
                                       double by)
{
    return (double)((long double)ax * (long double)by -
                    (long double)ay * (long double)bx);
}

/* min and max as single instructions (fmin/fmax are libm calls for
** their NaN rules, not needed here). */
static inline double dmin(double a, double b)
{
    return a < b ? a : b;
}

static inline double dmax(double a, double b)
{
    return a > b ? a : b;
}

/*
** Woop, Benthin and Wald, "Watertight Ray/Triangle Intersection", JCGT
** 2(1), 2013, in double.  The vertices are translated to the ray origin,
** the axes permuted so the largest direction component is z (and swapped
** for a negative one, to keep the winding), and sheared so the ray is the
** +z axis; the triangle is then hit iff the origin of the xy plane is
** inside it, decided by the three 2-D edge functions U, V, W.
**
** Why it is watertight: each vertex is transformed on its own, so a
** vertex shared by two triangles gets the same coordinates in both, and an
** edge function depends only on its edge's two vertices: a shared edge
** gives exactly -U in the neighbour (without FMA contraction, which the
** build forbids).  Edge functions are accepted with their sign inclusive,
** so a ray exactly on the edge hits at least one side.  When one is
** exactly 0 all three are re-evaluated in long double (the paper's double
** fallback for float), which picks the true side more often.
**
** t and the barycentrics come from the same quantities: det = U + V + W,
** t = (U Az + V Bz + W Cz) / det, beta = V / det, gamma = W / det.
*/
static inline int ray__watertight_init(ray__watertight *w,
                                       const ray_ray *r)
{
    int neg;
    size_t at[2];
    double o[2], shear[2];

    if (!ray__frame_init(&w->f, r))  /* zero or NaN direction: a miss */
        return 0;
    /* A negative dz swaps x and y, to keep the winding; by indexing, as
    ** the sign is a coin toss. */
    neg = w->f.dz < 0;
    at[0] = w->f.at[0], at[1] = w->f.at[1];
    o[0] = w->f.o[0], o[1] = w->f.o[1];
    shear[0] = w->f.sx, shear[1] = w->f.sy;
    w->f.at[0] = at[neg], w->f.at[1] = at[!neg];
    w->f.o[0] = o[neg], w->f.o[1] = o[!neg];
    w->f.sx = shear[neg], w->f.sy = shear[!neg];
    w->sz = 1.0 / w->f.dz;
    return 1;
}

static inline int ray__triangle_watertight_pre(
    const ray__watertight *wt, double tmin, double tmax, const ray_vec3 *va,
    const ray_vec3 *vb, const ray_vec3 *vc, double *t_out, double *beta_out,
    double *gamma_out)
{
    double pa[3], pb[3], pc[3];
    double ax, ay, bx, by, cx, cy, u, v, w, det, t_num;

    ray__frame_project(&wt->f, va, pa);
    ray__frame_project(&wt->f, vb, pb);
    ray__frame_project(&wt->f, vc, pc);
    ax = pa[0], ay = pa[1];
    bx = pb[0], by = pb[1];
    cx = pc[0], cy = pc[1];
    u = cx * by - cy * bx;
    v = ax * cy - ay * cx;
    w = bx * ay - by * ax;
    /* One compare each for "any zero" and "signs differ", through the
    ** smallest magnitude and the extremes (a NaN among u, v, w may go
    ** either way here: det below is then NaN, a miss in both cases). */
    if (dmin(dmin(fabs(u), fabs(v)), fabs(w)) == 0) {
        u = ray__edge_extended(cx, cy, bx, by);
        v = ray__edge_extended(ax, ay, cx, cy);
        w = ray__edge_extended(bx, by, ax, ay);
    }
    /* Inclusive on both signs: a miss only when the signs truly differ. */
    if (dmin(dmin(u, v), w) < 0 && dmax(dmax(u, v), w) > 0)
        return 0;
    det = u + v + w;
    if (det == 0 || det != det)     /* edge-on, degenerate or bad input */
        return 0;
    t_num = u * (wt->sz * pa[2]) + v * (wt->sz * pb[2]) +
            w * (wt->sz * pc[2]);
    {
        double t = t_num / det, beta, gamma;
        if (!(t > tmin && t < tmax))
            return 0;
        beta = v / det;
        gamma = w / det;
        /* u, v, w share det's sign, so beta, gamma >= 0 and their sum
        ** <= 1 up to rounding; clamp that rounding for the hit record. */
        if (beta < 0)
            beta = 0;
        if (gamma < 0)
            gamma = 0;
        if (beta + gamma > 1) {
            double s = beta + gamma;
            beta /= s;
            gamma /= s;
        }
        *t_out = t;
        *beta_out = beta;
        *gamma_out = gamma;
    }
    return 1;
}

#endif
