/* SPDX-License-Identifier: MIT */
/*
** prim.h -- the primitives' layer: the ray's frame, the default
** tolerance, the primitives' internal entry points, and the one list of
** primitive kinds.  A primitive's source file includes this (or vec.h)
** alone: it cannot see the BVH, the scene or the trace context.
*/
#ifndef RAY_PRIM_H
#define RAY_PRIM_H

#include "core/vec.h"

/*
** The default tolerance of ray_implicit and ray_parametric for a surface
** in the box [lo, hi] (ray.h): 1e-9 of the box's diagonal -- far below
** what a picture shows, far above the rounding of a reasonable field or
** S(u, v) of a surface that size -- plus 64 ulps of the box's largest
** |coordinate| (64 DBL_EPSILON m), because far from the origin the
** coordinates themselves, and f computed from them, are that coarse.
** (Relative to the coordinates alone, a unit sphere at 1e9 would get a
** tolerance of 1.)  The diagonal is formed from coordinates divided by
** the largest, so it neither overflows nor underflows.
*/
#define RAY__TOLERANCE_OF_DIAGONAL 1e-9
#define RAY__TOLERANCE_ULPS 64.0
static inline double ray__default_tolerance(ray_vec3 lo, ray_vec3 hi)
{
    double m = fmax(fmax(fabs(lo.x), fabs(hi.x)),
                    fmax(fmax(fabs(lo.y), fabs(hi.y)),
                         fmax(fabs(lo.z), fabs(hi.z))));
    ray_vec3 e;

    if (!(m > 0))
        return 0;
    e = v3(hi.x / m - lo.x / m, hi.y / m - lo.y / m, hi.z / m - lo.z / m);
    return m * (RAY__TOLERANCE_OF_DIAGONAL * v3_length(e) +
                RAY__TOLERANCE_ULPS * DBL_EPSILON);
}

/* ----------------------------------------------------- shared internals */
/*
** The ray's own frame (Woop, Benthin, Wald, "Watertight Ray/Triangle
** Intersection", JCGT 2(1), 2013, section 3): kz is the axis of dir's
** largest component, kx and ky the two others in cyclic order, and the
** shear (sx, sy) maps dir onto the kz axis.  A vertex is projected on its
** own, translated to the ray origin and sheared, so vertices shared by two
** primitives get bit-identical coordinates: what makes both the polygon
** test and the watertight triangle test watertight.
*/
typedef struct ray__frame {
    size_t at[3];            /* byte offsets of components kx, ky, kz */
    double o[3];             /* the origin's components kx, ky, kz */
    double dz;               /* dir's component along kz */
    double sx, sy;
} ray__frame;

/* The frame's axes kx, ky, kz (a permutation of 0, 1, 2) for origin org. */
static inline void ray__frame_axes(ray__frame *f, ray_vec3 org, int kx,
                                   int ky, int kz)
{
    static const size_t at[3] = {offsetof(ray_vec3, x),
                                 offsetof(ray_vec3, y),
                                 offsetof(ray_vec3, z)};
    f->at[0] = at[kx];
    f->at[1] = at[ky];
    f->at[2] = at[kz];
    f->o[0] = v3_at(&org, f->at[0]);
    f->o[1] = v3_at(&org, f->at[1]);
    f->o[2] = v3_at(&org, f->at[2]);
}

/* Set up the frame of r; 0 (frame unset) for a zero or NaN direction.
** Indexing instead of branches: which axis is largest is a coin toss for
** incoherent rays, and a mispredicted branch costs more than the lot. */
static inline int ray__frame_init(ray__frame *f, const ray_ray *r)
{
    static const int next_axis[3] = {1, 2, 0};
    ray_vec3 ad = v3_abs(r->dir);
    double d[3];
    int x_largest = (ad.x > ad.y) & (ad.x > ad.z);
    int y_largest = !(ad.x > ad.y) & (ad.y > ad.z);
    int kz = 2 - 2 * x_largest - y_largest, kx = next_axis[kz];
    int ky = next_axis[kx];

    d[0] = r->dir.x;
    d[1] = r->dir.y;
    d[2] = r->dir.z;
    f->dz = d[kz];
    if (f->dz == 0 || f->dz != f->dz)
        return 0;
    f->sx = d[kx] / f->dz;
    f->sy = d[ky] / f->dz;
    ray__frame_axes(f, r->org, kx, ky, kz);
    return 1;
}

/* Vertex v in the frame: p[0], p[1] sheared so the ray is (0, 0); p[2]
** the unsheared distance along kz (v - org)[kz]. */
static inline void ray__frame_project(const ray__frame *f, const ray_vec3 *v,
                                      double p[3])
{
    p[2] = v3_at(v, f->at[2]) - f->o[2];
    p[0] = (v3_at(v, f->at[0]) - f->o[0]) - f->sx * p[2];
    p[1] = (v3_at(v, f->at[1]) - f->o[1]) - f->sy * p[2];
}

/* A ray that can hit anything: finite origin and direction, a non-zero
** direction and tmin < tmax (a hit needs tmin < t < tmax); every other
** ray hits nothing, whatever the geometry. */
static inline int ray__ray_usable(const ray_ray *r)
{
    /* x - x is 0 for a finite x and NaN for an infinite or NaN one: one
    ** compare for all six components, and no branch but the last. */
    double finite = ((r->org.x - r->org.x) + (r->org.y - r->org.y)) +
                    ((r->org.z - r->org.z) + (r->dir.x - r->dir.x)) +
                    ((r->dir.y - r->dir.y) + (r->dir.z - r->dir.z));
    int nonzero = (r->dir.x != 0) | (r->dir.y != 0) | (r->dir.z != 0);

    return (finite == 0) & nonzero & (r->tmin < r->tmax);
}

/*
** The textbook sphere test exactly as the lecture writes it (b^2 - ac on
** the raw coefficients, (-b -+ sqrt)/a).  Kept only so tests and the bench
** can show what the cancellation-free ray_sphere buys; not exported.
*/
int ray__sphere_naive(const ray_ray *r, ray_vec3 center, double radius,
                      ray_hit *hit);

/*
** The sphere and the plane split in two, so that a scene query can test
** many and fill the record of the nearest alone: ray__sphere_t and
** ray__plane_t are ray_sphere's and ray_plane's decision and t (1 with *t
** set on a hit), ray__sphere_fill the record of ray_sphere at t (0, *hit
** untouched, when a result is not finite: then ray_sphere misses), with
** its texture coordinates (u, v) when "uv" is 1, else u = v = 0 (a
** render, for a sphere whose material reads no (u, v):
** RAY_EFFECT_TEXTURE).
** ray__sphere_fills and ray__plane_fills (below): 1 when the fill at t
** is sure to succeed (a cheap sufficient test), 0 when it might fail.
*/
int ray__sphere_t(const ray_ray *r, ray_vec3 center, double radius,
                  double *t);
int ray__sphere_fill(const ray_ray *r, ray_vec3 center, double radius,
                     double t, int uv, ray_hit *hit);

/*
** ray__sphere_t in two steps, for a query that tests several spheres with
** one ray: what depends on the ray alone (its direction scaled by a power
** of two, d.d, the scaled tmin), once; then each sphere, reading r's
** origin and its current tmax.  The same arithmetic, so the same bits.
** ray__sphere_ray_init: 0 for a zero or non-finite direction (every
** sphere is then missed).
*/
typedef struct ray__sphere_ray {
    ray_vec3 d;                  /* the direction times 2^-e */
    double a, tmin;              /* d.d, and tmin times 2^e */
    int e;
} ray__sphere_ray;

static inline int ray__sphere_ray_init(const ray_ray *r,
                                       ray__sphere_ray *sr);

#define RAY__SPHERE_MISS_K 0x1p-44

/* ray__sphere_surely_missed's margin (below says why) and the radius's
** part of its bound, R^2 (1 + K), or NaN where the radius is outside the
** test's guards (no comparison with NaN holds: never "missed"); the test
** forms it here, and scene/commit.c keeps it for a scene's few spheres. */
static inline double ray__sphere_miss_rr(double radius)
{
    if (!(radius >= 0x1p-400 && radius <= 0x1p500))
        return (double)NAN;
    return radius * radius * (1 + RAY__SPHERE_MISS_K);
}

/*
** A scene's few spheres (its few_spheres), in prim_bvh's item order, as
** the four lanes of their miss test (ray__sphere_surely_missed, which
** the AVX copy of the queries runs on all of them at once: query/few.h):
** centres, and R^2 (1 + K) as the test forms it (ray__sphere_miss_rr);
** NaN in the lanes past them, so that no lane there is ever missed.  Set
** at commit.
*/
#define RAY__FEW_SPHERES 4
typedef struct ray__few_spheres {
    double cx[RAY__FEW_SPHERES], cy[RAY__FEW_SPHERES],
        cz[RAY__FEW_SPHERES], rr[RAY__FEW_SPHERES];
} ray__few_spheres;

/*
** Does the ray's line surely miss the sphere, by more than the rounding of
** ray__sphere_t_at could hide?  A cheap early out for the common case
** (most rays of a scene miss most of its spheres), without the test's
** division and square root, which cost most of a miss (perf on the
** Whitted render); it answers "missed" only where that test misses too.
**
** With f = org - c and the scaled d as computed (the test's own inputs),
** the line passes at D from the centre, D^2 = |f x d|^2 / (d.d).  The
** test's l is within dl <= gamma(8) (|f| + |b'/a| |d|) <= 17u |f| of D
** (sphere_t_error's bound on l; |b'/a| |d| <= |f| (1 + 7u)), so where
** D > R + 36u |f| it finds l >= R + 19u |f| > R and misses: (R - l)(R + l)
** is then below -38u R^2, still a normal number for R >= 2^-400.  As
** 2 R |f| <= R^2 + |f|^2, D > R + e |f| holds where D^2 > (1 + e) R^2 +
** (e + e^2) |f|^2, e = 36u.  The computed c = |f x d|^2 is within 11u
** |f|^2 (d.d) of the exact one (each component of the cross product off
** by gamma(2) |f| |d| at most, by Cauchy-Schwarz; then three squares and
** two sums), and the right side's four roundings move it by 4u: testing
** c > a (R^2 (1 + K) + |f|^2 K) with K = 2^-44 = 512u (>= 36u + 11u + 5u
** + 3u for |f|^2's own rounding) is therefore conservative.  Only where
** no step can overflow or underflow (2^-400 <= R <= 2^500, |f|^2 <
** 2^1000; a NaN or an infinity fails these tests): elsewhere the test
** decides alone.  Inline: a scene query asks it of each of its few
** spheres before it calls the whole test (query/few.h, which takes four
** at once, the same operations lane by lane).
*/
static inline int ray__sphere_surely_missed(ray_vec3 f, ray_vec3 d,
                                            double a, double radius)
{
    ray_vec3 x = v3_cross(f, d);
    double g = v3_dot(f, f), c = v3_dot(x, x);

    if (!(g < 0x1p1000))
        return 0;
    return c > a * (ray__sphere_miss_rr(radius) + g * RAY__SPHERE_MISS_K);
}

int ray__sphere_t_at(const ray__sphere_ray *sr, const ray_ray *r,
                     ray_vec3 center, double radius, double *t);
/* ray__sphere_t_at without its early out, for a caller that asked
** ray__sphere_surely_missed of the same f, d, a and radius already (a
** scene's few spheres, query/traverse.h): the same answer, the early
** out's cross product and dot products not made twice. */
int ray__sphere_t_near(const ray__sphere_ray *sr, const ray_ray *r,
                       ray_vec3 center, double radius, double *t);
int ray__plane_t(const ray_ray *r, ray_vec3 point, ray_vec3 normal,
                 double *t);
/* ray__plane_t for a non-NULL ray and a normal known to normalise (a
** scene's plane, checked when it was added): the same t, one test less. */
static inline int ray__plane_t_valid(const ray_ray *r, ray_vec3 point,
                                     ray_vec3 normal, double *t);

/*
** ray__sphere_fill fails only when p - c (formed as the fill forms it) is
** zero or not finite, or when p or p_err overflow; with |c_i| and radius
** at most 2^999, p_i = c_i + radius n_i (|n_i| <= 1 + 2u) and p_err stay
** below 2^1001.  Inline: it runs on every candidate of a scene query.
*/
static inline int ray__sphere_fills(const ray_ray *r, ray_vec3 c,
                                    double radius, double t)
{
    ray_vec3 v = v3_sub(v3_madd(r->org, t, r->dir), c);

    return v3_normalizable(v) &&
           fabs(c.x) + fabs(c.y) + fabs(c.z) + radius <= 0x1p999;
}

/*
** ray__plane_fill(r, point, n, point, t) with n unit: with the origin,
** t dir and the point within 2^1000 of 0 on every axis (their sums of
** |components| bound each), the point p stays below 2^1002, its
** correction, p_err and (u, v) (|t1_i|, |t2_i| <= 1) below 2^1008: all
** finite and (u, v) within DBL_MAX / 2, so the fill succeeds.
*/
static inline int ray__plane_fills(const ray_ray *r, ray_vec3 point,
                                   double t)
{
    double o = fabs(r->org.x) + fabs(r->org.y) + fabs(r->org.z);
    double q = fabs(point.x) + fabs(point.y) + fabs(point.z);
    double d = fabs(r->dir.x) + fabs(r->dir.y) + fabs(r->dir.z);

    return o + q <= 0x1p1000 && fabs(t) * d <= 0x1p1000;
}

/*
** Fill *hit for a hit at parameter t on the plane through "point" with
** UNIT normal n: the point is projected back onto the plane and given the
** tangent-frame (u, v) of ray_plane, measured from "origin".  Returns 0,
** leaving *hit untouched, if a result is not finite.
*/
double ray__plane_t_error(ray_vec3 po, ray_vec3 n, ray_vec3 dir,
                          double denom, double t);
int ray__plane_fill(const ray_ray *r, ray_vec3 point, ray_vec3 n,
                    ray_vec3 origin, double t, ray_hit *hit);

/*
** t does not depend on the normal's length, so it is computed with the
** normal as given and only a hit pays for normalising it.  d.n == 0 (a
** parallel ray, or one lying in the plane: 0/0) is tested exactly; a
** nearly parallel ray gets a large but finite t, and an overflow to Inf
** or a NaN from bad input fails the NaN-safe range test.  A normal that
** cannot be normalised (zero, infinite, NaN) misses.  Inline: a scene's
** planes are tested against every ray, and the call (register saves
** around two dot products, on rays most of which miss before the
** division) cost 27M instructions of the Whitted render (issue 35).
*/
static inline int ray__plane_t_valid(const ray_ray *r, ray_vec3 point,
                                     ray_vec3 normal, double *t_out)
{
    double denom, num, t;
    ray_vec3 po;

    denom = v3_dot(r->dir, normal);
    if (denom == 0)
        return 0;
    po = v3_sub(point, r->org);
    num = v3_dot(po, normal);
    /* Behind the origin (num and denom of opposite signs: t < 0, or -0
    ** where the quotient underflows) with tmin >= 0: a miss, found
    ** without the division's latency, on about half of a scene's rays
    ** (those leaving a floor upward).  A NaN fails the test and goes on. */
    if (num * denom < 0 && r->tmin >= 0)
        return 0;
    t = num / denom;
    if (!(t > r->tmin && t < r->tmax) ||
        !(t - ray__plane_t_error(po, normal, r->dir, denom, t) > r->tmin))
        return 0;
    *t_out = t;
    return 1;
}

/*
** The real roots of the polynomial c[0] + c[1] x + ... + c[degree] x^degree
** in [lo, hi], ascending, into roots[] (room for degree + 1 needed):
** src/prim/roots.c, after Yuksel (HPG 2022).  c[degree] must not be 0.
*/
#define RAY__POLY_MAX_DEGREE 4
int ray__poly_roots(const double *c, int degree, double lo, double hi,
                    double *roots);

/* 1 if ray_implicit accepts descriptor s (what it answers -RAY_EINVAL to
** whatever the ray); for the scene, which checks when a surface is added. */
int ray__implicit_valid(const ray_implicit_surface *s);

/* 1 if ray_parametric accepts descriptor s, with its domain (defaults
** applied) in d = {u0, u1, v0, v1}; 0 (d untouched) otherwise. */
int ray__parametric_domain(const ray_parametric_surface *s, double d[4]);

/* The tolerance ray_implicit uses for a valid descriptor (its own or
** the default); hits lie within it of the surface's box. */
double ray__implicit_tolerance(const ray_implicit_surface *s);

/*
** User geometry (user.c), the scene's checks of the caller's callbacks.
** ray__user_box: the box of g from its bounds callback, 1 if it is
** usable (finite, lo <= hi on every axis), else 0 with a message naming
** the axis at fault in why (*lo, *hi written either way).  The scene
** calls it when the geometry is added, and keeps the box.
** ray__user_hit: g's intersect callback on r, its answer checked: 1 with
** *hit filled (n unit, geom_id and prim_id RAY_INVALID_ID, for the
** scene to set) for a hit that keeps the contract of ray_hit; 0 for a
** miss; -1 (*hit untouched) for an answer that breaks it, a failure the
** scene counts in root_failures.
*/
int ray__user_box(const ray_user_geometry *g, ray_vec3 *lo, ray_vec3 *hi,
                  char *why, size_t why_size);
int ray__user_hit(const ray_user_geometry *g, const ray_ray *r,
                  ray_hit *hit);

/* The box of a torus, rounded outward (0 for invalid params). */
int ray__torus_box(const ray_torus_params *t, ray_vec3 *lo, ray_vec3 *hi);

/*
** The same torus as a ray_implicit_surface for the generic method
** (ray_implicit): its exact signed distance (Lipschitz constant 1), its
** gradient and ray_torus's (u, v), so that the tests can check the two
** methods against each other.  The params are BORROWED (they are the
** surface's ud).  RAY_OK, or RAY_EINVAL (invalid params as ray_torus
** refuses them, a spindle torus, out NULL: nothing written).  Internal
** since issue 37: a test harness, not a user feature (a program's own
** distance function goes to ray_implicit / ray_scene_add_implicit).
*/
int ray__implicit_torus(const ray_torus_params *t,
                        ray_implicit_surface *out);

/* The triangle test alone (t, beta, gamma) and the hit record of a hit,
** split so a BVH can test many triangles and fill only the nearest. */
int ray__triangle_test(const ray_ray *r, ray_vec3 a, ray_vec3 b, ray_vec3 c,
                       double *t, double *beta, double *gamma);
int ray__triangle_fill(ray_vec3 a, ray_vec3 b, ray_vec3 c, double t,
                       double beta, double gamma, ray_hit *hit);
int ray__triangle_watertight_test(const ray_ray *r, ray_vec3 a, ray_vec3 b,
                                  ray_vec3 c, double *t, double *beta,
                                  double *gamma);

/* The naive variants the stability suite and the bench compare with
** (not exported): float Cramer, and barycentrics divided by N.N. */
int ray__triangle_float(const ray_ray *r, ray_vec3 a, ray_vec3 b, ray_vec3 c,
                        double *t);
int ray__barycentric_naive(ray_vec3 p, ray_vec3 a, ray_vec3 b, ray_vec3 c,
                           double abg[3]);

/*
** The bicubic Bezier fast path of ray_parametric (bezier.c), declared
** here for parametric.c: instead of one bounds call per rectangle, which
** rebuilds the sub-patch's control net from the whole patch, the
** traversal carries each quad-tree node's 4 x 4 net and halves it by de
** Casteljau.  ray__bezier_points: the 16 control points of a surface
** made by ray_bezier_surface, NULL for any other.  ray__bezier_magnitude:
** the "mag" the boxes are grown with.  ray__bezier_split: the net (row
** i, column j at net[stride*i + j]) split at u = v = 1/2 into the 7 x 7
** grid whose 4 x 4 corner blocks, at grid + ray__bezier_quarter(q), are
** the quarters' nets (q: bit 0 the upper u half, bit 1 the upper v
** half), and their boxes, grown to contain the exact sub-patches at
** "level" halvings below the patch.
*/
#define RAY__BEZIER_GRID 7
const ray_vec3 *ray__bezier_points(const ray_parametric_surface *s);
ray_vec3 ray__bezier_magnitude(const ray_vec3 cp[16]);
void ray__bezier_split(const ray_vec3 *net, int stride, ray_vec3 mag,
                       unsigned level,
                       ray_vec3 grid[RAY__BEZIER_GRID * RAY__BEZIER_GRID],
                       ray_vec3 lo[4], ray_vec3 hi[4]);
static inline int ray__bezier_quarter(unsigned q)
{
    return RAY__BEZIER_GRID * ((q & 2u) ? 3 : 0) + ((q & 1u) ? 3 : 0);
}

/*
** The direction scaled by a power of two, 2^-e, so that its largest
** component lies in [0.5, 1): exact, componentwise by ldexp (barring
** components ~2^-1000 times smaller than the largest, noise beside it),
** so a direction of length 1e-200, 1e200 or a subnormal one gives the
** same hit as the unit one and d.d can neither overflow nor underflow.
** The parameter along the scaled direction is t 2^e: ray__unscale_t
** converts back, ray__scale_t there (saturating, never 0 * Inf).  0 for a
** zero, infinite or NaN direction.  ray_sphere and ray_capsule use it.
*/
/* ldexp(t, e), by one multiplication where 2^e is a double. */
static inline double ray__scale_t(double t, int e)
{
    return e >= -1074 && e <= 1023 ? t * ray__pow2(e) : ldexp(t, e);
}

static inline double ray__unscale_t(double t, int e)
{
    return ray__scale_t(t, -e);
}

static inline int ray__scaled_dir(ray_vec3 dir, ray_vec3 *d, int *e)
{
    double ax = fabs(dir.x), ay = fabs(dir.y), az = fabs(dir.z);
    /* Comparisons, not fmax (a libm call): a NaN component may be dropped
    ** or taken here, and is refused just below either way. */
    double m = ax > ay ? ax : ay;
    uint64_t bits;

    m = m > az ? m : az;
    if (!(m > 0 && m < HUGE_VAL) || dir.x != dir.x || dir.y != dir.y ||
        dir.z != dir.z)
        return 0;
    /* frexp's exponent, read from the bits of a normal m (m = f 2^e with
    ** f in [0.5, 1)); frexp itself for a subnormal one. */
    if (m >= DBL_MIN) {
        /* e in [-1021, 1024], where ray__scale_t(x, -e) is x 2^-e, one
        ** multiplication: 2^-e made once for the three components, the
        ** same bits at a fifth of the instructions (96 a ray, callgrind,
        ** the Whitted render, issue 35). */
        double down;
        memcpy(&bits, &m, sizeof bits);
        *e = (int)(bits >> 52 & 0x7ff) - 1022;
        down = ray__pow2(-*e);
        *d = v3(dir.x * down, dir.y * down, dir.z * down);
        return 1;
    }
    frexp(m, e);
    *d = v3(ray__scale_t(dir.x, -*e), ray__scale_t(dir.y, -*e),
            ray__scale_t(dir.z, -*e));
    return 1;
}

/* The ray's part of the sphere test (above): its direction scaled by a
** power of two (ray__scaled_dir), d.d and tmin in those units.  Inline:
** a scene query of a few spheres makes it once a ray, and its call (the
** register saves around a few multiplications) cost 24M instructions of
** the Whitted render (callgrind, issue 35). */
static inline int ray__sphere_ray_init(const ray_ray *r,
                                       ray__sphere_ray *sr)
{
    /* A zero (or NaN) direction misses; so does a NULL ray. */
    if (r == NULL || !ray__scaled_dir(r->dir, &sr->d, &sr->e))
        return 0;
    sr->a = v3_dot(sr->d, sr->d);
    sr->tmin = ray__scale_t(r->tmin, sr->e);
    return 1;
}

/* ------------------------------------------------------ closest points */

/*
** |a - b| without overflow or underflow of the squares: the difference
** is divided by its largest |component| when that lies outside [2^-500,
** 2^500] (where the sum of three squares could leave the doubles), as
** v3_normalize does.  Within sqrt(3)/2 + 3/2 ulps of the length of the
** rounded difference (the sum's three roundings, halved by the root,
** and the root's own), plus one more for the scaling.  +Inf when the
** difference overflows; NaN for a NaN input.
*/
static inline double ray__distance(ray_vec3 a, ray_vec3 b)
{
    ray_vec3 d = v3_sub(a, b);
    double ax = fabs(d.x), ay = fabs(d.y), az = fabs(d.z);
    /* Comparisons, not fmax (a libm call in a hot loop): a NaN component
    ** may be dropped here, but then reaches the sum below. */
    double m = ax > ay ? ax : ay;

    m = m > az ? m : az;
    if (m > 0x1p-500 && m < 0x1p500)
        return v3_length(d);
    if (d.x != d.x || d.y != d.y || d.z != d.z)
        return (double)NAN;
    if (!(m > 0) || !(m < HUGE_VAL))
        return m;
    return m * v3_length(v3(d.x / m, d.y / m, d.z / m));
}

/*
** The point of segment [a, b] nearest q: a + t (b - a), t = (q - a).(b -
** a) / |b - a|^2 clamped to [0, 1] (Ericson, "Real-Time Collision
** Detection", 2005, 5.1.2), so an end is returned exactly.  A segment
** whose |b - a|^2 is 0 or not finite gives t = 0: a.
*/
static inline ray_vec3 ray__segment_closest(ray_vec3 q, ray_vec3 a,
                                            ray_vec3 b)
{
    ray_vec3 ab = v3_sub(b, a);
    double den = v3_dot(ab, ab);
    double t = den > 0 && den < HUGE_VAL ? v3_dot(v3_sub(q, a), ab) / den
                                         : 0.0;

    /* A NaN t (q - a overflowed) fails both tests: a. */
    if (!(t > 0))
        return a;
    if (!(t < 1))
        return b;
    return v3_madd(a, t, ab);
}

/*
** Nearest points between pieces (nearest.c):
** ray__triangle_closest -- the point of triangle (a, b, c) nearest q
** (Ericson's region walk; its accuracy where it is defined);
** ray__segments_closest -- the nearest points *ps on [p0, p1] and *qs on
** [q0, q1] (parallel and zero-length segments included);
** ray__segment_triangle_closest -- the nearest points *ps on [p0, p1]
** and *pt on triangle (a, b, c) (a crossing: the same point, distance 0).
*/
ray_vec3 ray__triangle_closest(ray_vec3 a, ray_vec3 b, ray_vec3 c,
                               ray_vec3 q);
void ray__segments_closest(ray_vec3 p0, ray_vec3 p1, ray_vec3 q0,
                           ray_vec3 q1, ray_vec3 *ps, ray_vec3 *qs);
void ray__segment_triangle_closest(ray_vec3 p0, ray_vec3 p1, ray_vec3 a,
                                   ray_vec3 b, ray_vec3 c, ray_vec3 *ps,
                                   ray_vec3 *pt);

/*
** Affine images of spheres and capsules (ellipsoid.c).
** ray__svd3 -- L = U diag(s) V^T, s descending (U's columns the left
** singular vectors): 1, or 0 for a zero or non-finite L.
** ray__ellipsoid_closest -- the point *p of the ellipsoid {c + U diag(e)
** w : |w| = 1} (e descending, > 0) nearest q, inside or out, and the
** outward unit normal *n there; 1, or 0 (nothing written) for a result
** that is not finite.
** ray__ellipsoid_sweep_closest -- the same for that ellipsoid swept along
** c + s w, s in [0, 1], for q outside it; *inside set when q is inside
** (the nearest point of the ellipsoid q is deepest in, then).
*/
int ray__svd3(const double l[3][3], double u[3][3], double s[3]);
int ray__ellipsoid_closest(ray_vec3 c, const double u[3][3],
                           const double e[3], ray_vec3 q, ray_vec3 *p,
                           ray_vec3 *n);
int ray__ellipsoid_sweep_closest(ray_vec3 c, ray_vec3 w, const double u[3][3],
                                 const double e[3], ray_vec3 q, ray_vec3 *p,
                                 ray_vec3 *n, int *inside);

/*
** The nearest point *p of a primitive's SURFACE to q, for
** ray_closest_point (closest.c), and the unit normal *n there: a box's
** outward face normal (at an edge or a corner, the face whose plane q
** lies farthest outside of; inside, the nearest face's); a capsule's
** outward normal; a polygon's unit Newell normal.  For parameters the
** scene checked; 0, with nothing written, for parameters ray_box,
** ray_capsule or ray_polygon refuse or a result that is not finite.
** Each states its accuracy where it is defined.
*/
int ray__box_closest(const ray_box_params *b, ray_vec3 q, ray_vec3 *p,
                     ray_vec3 *n);
/* The unit axes e[0..2] of box b as ray_box builds them (Gram-Schmidt
** twice): 1, or 0 for params ray_box refuses. */
int ray__box_frame(const ray_box_params *b, ray_vec3 e[3]);
/* ray__polygon_closest for the polygon whose vertices are v[i] mapped by
** the affine map xf (NULL: not mapped), read one at a time: the nearest
** point in the mapped space, where the mapped polygon is the region
** inside the mapped outline; *n is the mapped polygon's unit Newell
** normal. */
int ray__polygon_closest_mapped(const ray_vec3 *v, size_t count,
                                const ray_transform *xf, ray_vec3 q,
                                ray_vec3 *p, ray_vec3 *n);
int ray__capsule_closest(const ray_capsule_params *c, ray_vec3 q,
                         ray_vec3 *p, ray_vec3 *n);
/*
** ray_polygon in two steps, for a scene that keeps its polygons' planes
** (their vertices never change after they are added):
** ray__polygon_plane -- the plane ray_polygon tests against: the vertex
** centroid c and the Newell normal (twice the vector area); 0, with the
** normal set to zero, for no area (ray__polygon_at then misses, as
** ray_polygon does).
** ray__polygon_at -- ray_polygon against that plane: the same answer and
** record, bit for bit, without the plane's two passes over the vertices
** (11% of the Cornell render, perf, issue 35).
*/
int ray__polygon_plane(const ray_vec3 *v, size_t count, ray_vec3 *c,
                       ray_vec3 *normal);
int ray__polygon_at(const ray_ray *r, const ray_vec3 *v, size_t count,
                    ray_vec3 c, ray_vec3 normal, ray_hit *hit);

int ray__polygon_closest(const ray_vec3 *v, size_t count, ray_vec3 q,
                         ray_vec3 *p, ray_vec3 *n);

/* ------------------------------------------------------ the kinds */

/*
** *dst = *src field by field: a struct assignment may copy the padding
** after ray_hit's three ids from a local whose padding is indeterminate,
** and a caller that compares or hashes its hit records as bytes (after
** clearing them) should see only what the library wrote.
*/
static inline void ray__hit_store(ray_hit *dst, const ray_hit *src)
{
    dst->t = src->t;
    dst->p = src->p;
    dst->n = src->n;
    dst->u = src->u;
    dst->v = src->v;
    dst->p_err = src->p_err;
    dst->geom_id = src->geom_id;
    dst->prim_id = src->prim_id;
    dst->inst_id = src->inst_id;
}

/*
** The shapes: bounded kinds whose scene record is their parameter block
** alone (an oriented box, a capsule).  One line each,
**     S(X, NAME, name, parameter type, counted as)
** gives everything of a shape above its own source file: its line in the
** kind list below, its member of the scene's ray__surface union
** (scene.h), its box and its intersection in src/scene/kinds.c (the box
** the check gave, ray_name on the stored parameters), its
** ray_scene_add_name in src/scene/surfaces.c, and the declaration of its
** check:
**     int ray__name_check(const type *p, ray_vec3 *lo, ray_vec3 *hi,
**                         char *why, size_t why_size);
** which answers 1 with a box containing every hit point ray_name can
** compute (rounded outward) when ray_name accepts p, else 0 with a
** message naming the field at fault in why (p may be NULL).  X is the
** macro the line is expanded for; S the adapter that maps it.
**
** Adding a shape NAME:
**   1. include/ray.h: its parameter struct, ray_name(r, params, hit),
**      ray_scene_add_name(scene, params, material, geom_id), and
**      RAY_PRIM_NAME just before RAY_PRIM_KINDS (<= RAY_PRIM_KINDS_MAX);
**   2. src/prim/name.c, including prim/prim.h alone: ray_name and
**      ray__name_check;
**   3. its line below, and closest_NAME in src/query/closest.c (its
**      nearest point, for ray_closest_point), sweep_NAME in
**      src/query/sweep.c, meets_NAME in src/query/overlap.c (exact, or
**      by its box, flagged RAY_CONTACT_BOUNDS) and its case in
**      src/query/surface_point.c, which the compiler asks for;
**   4. tests/check_name.c (registered in tests/check_main.c and
**      tests/tests.h), man/man3/ray_name.3 naming ray_scene_add_name in
**      its NAME section too (the Makefile links every name it lists), and
**      doc/API.md (its table of functions).
*/
#define RAY__SHAPES(S, X)                                          \
    S(X, BOX, box, ray_box_params, RAY_PRIM_BOX)                     \
    S(X, CAPSULE, capsule, ray_capsule_params, RAY_PRIM_CAPSULE)

/*
** The kinds of primitive, one line each: X(NAME, counted as, class).
** Everything that depends on the kind is generated from this list: the
** enum ray__kind below, and in src/scene/kinds.c the box, the class, the
** intersection and the statistics kind of a piece of geometry.
** The shapes (above) come last, each as X(NAME, counted as, BOUNDED).
**   NAME        the constant RAY__KIND_NAME, and the suffix of the kind's
**               functions in src/scene/kinds.c, box_NAME and hit_NAME;
**   counted as  the RAY_PRIM_* of ray.h its tests count under in
**               ray_stats.tests_by_kind;
**   class       where a committed scene keeps it (scene.h, ray__class):
**               TRIANGLES, in the triangle BVH, whose triangles the
**               queries test inline (query/leaf.h); BOUNDED, in the
**               BVH over the other bounded primitives, tested through
**               hit_NAME (an instance by the queries themselves, which
**               descend into it: query/traverse.h); UNBOUNDED, tested
**               on every ray (the plane), through hit_NAME.
** No switch over ray__kind has a default, and the library is built with
** -Wswitch-enum: a kind left out of a switch, or a line here without its
** box_NAME and hit_NAME, is a compile error rather than a wrong picture.
**
** Adding a kind that is not a shape (its scene record needs more than a
** parameter block: vertices, a mesh):
**   1. include/ray.h: ray_NAME (and its parameter struct), its
**      ray_scene_add_NAME, and RAY_PRIM_NAME, just before RAY_PRIM_KINDS
**      (which must stay <= RAY_PRIM_KINDS_MAX);
**   2. src/prim/NAME.c, including prim/prim.h alone: ray_NAME, and what
**      the scene needs of it (a validity test and a box, as
**      ray__torus_box), declared here below the list;
**   3. the line X(NAME, RAY_PRIM_NAME, BOUNDED) below, and a member of
**      ray__surface (scene.h) if the scene keeps its parameters;
**   4. src/scene/kinds.c: box_NAME and hit_NAME, and in src/query/
**      closest_NAME (closest.c), sweep_NAME (sweep.c), meets_NAME
**      (overlap.c) and a case in surface_point.c, a few lines each, which
**      the compiler asks for;
**   5. src/scene/surfaces.c: ray_scene_add_NAME, through add_surface;
**   6. tests/check_NAME.c (registered in tests/check_main.c and
**      tests/tests.h), man/man3/ray_NAME.3 (a Makefile MLINKS entry for
**      each other function it documents), and doc/API.md.
*/
#define RAY__PRIM_KINDS(X)                                 \
    X(SPHERE,     RAY_PRIM_SPHERE,     BOUNDED)            \
    X(PLANE,      RAY_PRIM_PLANE,      UNBOUNDED)          \
    X(TRIANGLE,   RAY_PRIM_TRIANGLE,   TRIANGLES)          \
    X(POLYGON,    RAY_PRIM_POLYGON,    BOUNDED)            \
    X(MESH,       RAY_PRIM_TRIANGLE,   TRIANGLES)          \
    X(TORUS,      RAY_PRIM_TORUS,      BOUNDED)            \
    X(IMPLICIT,   RAY_PRIM_IMPLICIT,   BOUNDED)            \
    X(PARAMETRIC, RAY_PRIM_PARAMETRIC, BOUNDED)            \
    X(BEZIER,     RAY_PRIM_PARAMETRIC, BOUNDED)            \
    X(INSTANCE,   RAY_PRIM_INSTANCE,   BOUNDED)            \
    X(USER,       RAY_PRIM_USER,       BOUNDED)            \
    RAY__SHAPES(RAY__SHAPE_KIND, X)

#define RAY__SHAPE_KIND(X, NAME, name, type, counted_as)   \
    X(NAME, counted_as, BOUNDED)
#define RAY__SHAPE_CHECK(X, NAME, name, type, counted_as)  \
    int ray__##name##_check(const type *p, ray_vec3 *lo, ray_vec3 *hi, \
                            char *why, size_t why_size);
RAY__SHAPES(RAY__SHAPE_CHECK, _)

#define RAY__KIND_ENUM(name, counted_as, class) RAY__KIND_##name,
typedef enum ray__kind { RAY__PRIM_KINDS(RAY__KIND_ENUM) } ray__kind;
#undef RAY__KIND_ENUM

#endif /* RAY_PRIM_H */
