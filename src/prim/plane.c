/* SPDX-License-Identifier: MIT */
/*
** plane.c -- ray / plane: t = (p1 - e).n / (d.n), from substituting the
** ray into the plane equation (p - p1).n = 0.
*/
#include "prim/prim.h"

/*
** The hit point is e + t d, then projected back onto the plane by one
** correction step p -= ((p - point).n) n: e + t d alone carries t's error
** along the ray, which for a grazing ray (t ~ 1/(d.n)) is far off the
** plane.  What remains is the rounding of the correction itself, a few
** ulps of the largest coordinate involved; gamma(8) * max|p_i| + |point_i|
** covers the dot product (5 roundings), the scaling and the subtraction,
** and is applied to every component because the dot product mixes them.
*/
int ray__plane_fill(const ray_ray *r, ray_vec3 point, ray_vec3 n,
                    ray_vec3 origin, double t, ray_hit *hit)
{
    ray_vec3 p = v3_madd(r->org, t, r->dir);
    ray_vec3 t1, t2, half_rel, mag;
    double bound, u, v;

    p = v3_madd(p, -v3_dot(v3_sub(p, point), n), n);
    mag = v3_add(v3_abs(p), v3_abs(point));
    bound = ray__gamma(8) * ray__fmax(mag.x, ray__fmax(mag.y, mag.z));
    if (!v3_isfinite(p) || !(bound < HUGE_VAL))
        return 0;
    /* (u, v) = ((p - origin).t1, (p - origin).t2), in halves: p - origin
    ** overflows for coordinates near +-DBL_MAX of opposite signs, and so
    ** may the dot product's partial sums where the result itself does
    ** not.  Halving and doubling are exact (barring subnormals), so the
    ** bits are those of the plain formula wherever it did not overflow.
    ** A (u, v) beyond double's range is a miss: no Inf reaches a hit. */
    ray__tangent_frame(n, &t1, &t2);
    half_rel = v3_sub(v3_scale(p, 0.5), v3_scale(origin, 0.5));
    u = v3_dot(half_rel, t1);
    v = v3_dot(half_rel, t2);
    if (!(fabs(u) <= DBL_MAX / 2 && fabs(v) <= DBL_MAX / 2))
        return 0;
    hit->t = t;
    hit->p = p;
    hit->n = n;
    hit->u = 2 * u;
    hit->v = 2 * v;
    hit->p_err = v3(bound, bound, bound);
    hit->geom_id = RAY_INVALID_ID;
    hit->prim_id = RAY_INVALID_ID;
    hit->inst_id = RAY_INVALID_ID;
    return 1;
}

/*
** A bound on the rounding error of t = ((point - org).n) / (dir.n), for
** the difference po = point - org as computed (running error analysis,
** Higham, "Accuracy and Stability of Numerical Algorithms", 2nd ed.,
** section 3.1; gamma(n) = n u / (1 - n u)): the numerator's difference,
** product and two additions give gamma(4) sum |po_i n_i| (po's computed
** magnitudes, hence the extra gamma(1)), the denominator's gamma(3) sum
** |d_i n_i|, and |t - t_exact| <= (d_num + |t| d_den) / |den| + u |t|.
** A hit must lie past tmin by more than this: a ray leaving the plane
** starts on it, or within its rounding error, and its computed t for
** that plane is rounding noise around 0 or a negative number
** (ray__watertight_t_error in watertight.h says more).
*/
double ray__plane_t_error(ray_vec3 po, ray_vec3 n, ray_vec3 dir,
                          double denom, double t)
{
    double num_mag = fabs(po.x * n.x) + fabs(po.y * n.y) + fabs(po.z * n.z);
    double den_mag = fabs(dir.x * n.x) + fabs(dir.y * n.y) +
                     fabs(dir.z * n.z);
    double at = fabs(t);

    return (ray__gamma(4) * (1 + ray__gamma(2)) * num_mag +
            at * ray__gamma(3) * (1 + ray__gamma(1)) * den_mag) /
               fabs(denom) +
           ray__gamma(1) * at;
}

int ray__plane_t(const ray_ray *r, ray_vec3 point, ray_vec3 normal,
                 double *t_out)
{
    double t;

    if (r == NULL || !ray__plane_t_valid(r, point, normal, &t) ||
        !v3_normalizable(normal))
        return 0;
    *t_out = t;
    return 1;
}

int ray_plane(const ray_ray *r, ray_vec3 point, ray_vec3 normal,
              ray_hit *hit)
{
    double t;
    ray_vec3 n;

    if (hit == NULL || !ray__plane_t(r, point, normal, &t) ||
        !v3_normalize(normal, &n))
        return 0;
    return ray__plane_fill(r, point, n, point, t, hit);
}
