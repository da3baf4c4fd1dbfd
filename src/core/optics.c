/* SPDX-License-Identifier: MIT */
/*
** optics.c -- reflection, refraction and Fresnel reflectance.
*/
#include "core/vec.h"

ray_vec3 ray_reflect(ray_vec3 d, ray_vec3 n)
{
    return v3_madd(d, -2.0 * v3_dot(d, n), n);
}

/*
** Snell's law in vector form (Heckbert's; Shirley and Marschner, FCG 3rd
** ed., 13.1): with unit d, n facing d (d.n < 0), cos_i = -d.n and
** sin^2 t = eta^2 (1 - cos_i^2), t = eta d + (eta cos_i - cos_t) n.
** sin^2 t >= 1 is total internal reflection (pbrt-v4 Refract, which also
** flips n when d comes from its other side).
*/
int ray_refract(ray_vec3 d, ray_vec3 n, double eta, ray_vec3 *out)
{
    ray_vec3 dn, t;
    double cos_i, sin2_t, cos_t;

    if (out == NULL || !(eta > 0 && eta < HUGE_VAL) || !v3_isfinite(n) ||
        !v3_normalize(d, &dn))
        return 0;
    cos_i = -v3_dot(dn, n);
    if (cos_i < 0) {
        n = v3_scale(n, -1.0);
        cos_i = -cos_i;
    }
    if (cos_i > 1)
        cos_i = 1;
    sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if (!(sin2_t < 1))
        return 0;
    cos_t = sqrt(1.0 - sin2_t);
    if (!v3_normalize(v3_madd(v3_scale(dn, eta), eta * cos_i - cos_t, n), &t))
        return 0;
    *out = t;
    return 1;
}

/*
** Exact unpolarised Fresnel reflectance of a dielectric interface (the
** average of r_s^2 and r_p^2; Born and Wolf, Principles of Optics, 1.5.2),
** not Schlick's approximation, whose relative error reaches 23% for
** n = 1.5 (forwardscattering.org, post 65, "Schlick's approximation").
*/
double ray_fresnel(double cos_i, double eta)
{
    double sin2_t, cos_t, rs, rp;

    if (!(eta > 0 && eta < HUGE_VAL) || cos_i != cos_i)
        return 1.0;
    cos_i = fabs(cos_i);
    if (cos_i > 1)
        cos_i = 1;
    sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    /* NaN only from Inf * 0: eta^2 overflowed (eta > ~1e154) at normal
    ** incidence, where sin^2 of the transmitted angle is exactly 0 (found
    ** by fuzz/fuzz_primitives: ray_fresnel(1, 1e300) was NaN). */
    if (sin2_t != sin2_t)
        sin2_t = 0;
    if (sin2_t >= 1)
        return 1.0;
    cos_t = sqrt(1.0 - sin2_t);
    rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5 * (rs * rs + rp * rp);
}
