/*
** internal.h -- private declarations shared by the library's sources.
** Nothing here is part of the API; names are lower_snake_case and static
** inline, or carry the ray__ prefix when they must be linked.
*/
#ifndef RAY_INTERNAL_H
#define RAY_INTERNAL_H

#include <float.h>
#include <math.h>

#include "ray.h"

/* pi, which strict C99 <math.h> does not define. */
#define RAY__PI 3.14159265358979323846

/* ------------------------------------------------------- vector helpers */

static inline ray_vec3 v3(double x, double y, double z)
{
    ray_vec3 r;
    r.x = x;
    r.y = y;
    r.z = z;
    return r;
}

static inline ray_vec3 v3_add(ray_vec3 a, ray_vec3 b)
{
    return v3(a.x + b.x, a.y + b.y, a.z + b.z);
}

static inline ray_vec3 v3_sub(ray_vec3 a, ray_vec3 b)
{
    return v3(a.x - b.x, a.y - b.y, a.z - b.z);
}

static inline ray_vec3 v3_scale(ray_vec3 a, double s)
{
    return v3(a.x * s, a.y * s, a.z * s);
}

/* a + s*b, in two roundings per component (no FMA: see the Makefile). */
static inline ray_vec3 v3_madd(ray_vec3 a, double s, ray_vec3 b)
{
    return v3(a.x + s * b.x, a.y + s * b.y, a.z + s * b.z);
}

static inline double v3_dot(ray_vec3 a, ray_vec3 b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

static inline ray_vec3 v3_cross(ray_vec3 a, ray_vec3 b)
{
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z,
              a.x * b.y - a.y * b.x);
}

static inline ray_vec3 v3_abs(ray_vec3 a)
{
    return v3(fabs(a.x), fabs(a.y), fabs(a.z));
}

static inline double v3_length(ray_vec3 a)
{
    return sqrt(v3_dot(a, a));
}

/*
** a / |a| into *out, safe from overflow and underflow of |a|^2: a is first
** divided by its largest |component|, which brings that component to 1
** and |a| into [1, sqrt 3], so the normal of a 1e-150-sized triangle
** (|n|^2 ~ 1e-600) or of a 1e200-sized one still comes out unit.
** Returns 0, leaving *out untouched, for a zero or non-finite vector.
*/
static inline int v3_normalize(ray_vec3 a, ray_vec3 *out)
{
    double m = fmax(fabs(a.x), fmax(fabs(a.y), fabs(a.z)));
    double len;

    if (!(m > 0 && m < HUGE_VAL))
        return 0;
    a = v3_scale(a, 1.0 / m);
    len = v3_length(a);
    *out = v3_scale(a, 1.0 / len);
    return 1;
}

/* 1 when every component is finite (neither NaN nor +-Inf). */
static inline int v3_isfinite(ray_vec3 a)
{
    return isfinite(a.x) && isfinite(a.y) && isfinite(a.z);
}

/* ------------------------------------------------------ rounding bounds */

/*
** gamma(n) = n*u / (1 - n*u), u = DBL_EPSILON/2: the relative error bound
** of n chained IEEE-754 roundings (Higham, "Accuracy and Stability of
** Numerical Algorithms", 2nd ed., Lemma 3.1; pbrt-v4 util/float.h uses the
** same name).  Used to build the hit records' p_err bounds.
*/
static inline double ray__gamma(int n)
{
    double nu = (double)n * (DBL_EPSILON * 0.5);
    return nu / (1.0 - nu);
}

/* ----------------------------------------------------- shared internals */

/*
** The orthonormal tangents (t1, t2) of unit normal n, so that (t1, t2, n)
** is right-handed.  Duff, Burgess, Christensen, Hery, Kensler, Liani,
** Villemin, "Building an Orthonormal Basis, Revisited", JCGT 6(1), 2017,
** listing 3: branch-free and continuous except across n.z = 0's sign.
*/
void ray__tangent_frame(ray_vec3 n, ray_vec3 *t1, ray_vec3 *t2);

/*
** The textbook sphere test exactly as the lecture writes it (b^2 - ac on
** the raw coefficients, (-b -+ sqrt)/a).  Kept only so tests and the bench
** can show what the cancellation-free ray_sphere buys; not exported.
*/
int ray__sphere_naive(const ray_ray *r, ray_vec3 center, double radius,
                      ray_hit *hit);

/*
** Fill *hit for a hit at parameter t on the plane through "point" with
** UNIT normal n: the point is projected back onto the plane and given the
** tangent-frame (u, v) of ray_plane, measured from "origin".  Returns 0,
** leaving *hit untouched, if a result is not finite.
*/
int ray__plane_fill(const ray_ray *r, ray_vec3 point, ray_vec3 n,
                    ray_vec3 origin, double t, ray_hit *hit);

#endif /* RAY_INTERNAL_H */
