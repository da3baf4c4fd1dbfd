/* SPDX-License-Identifier: MIT */
/*
** camera.c -- primary rays from a pinhole or thin-lens camera.
*/
#include "render/camera.h"

/*
** Is the up vector usable with view axis w (unit): not parallel to it?
** Decided by the angle, scale-free: the sine of the angle between the
** unit up vector and w is the length of their cross product, computed to
** within a few roundings of 1 (unit factors: each component is within
** gamma(3) of the exact one).  A sine below 16 ulps (3.6e-15 rad) is
** rounding noise, not a direction: eye (0, 1, 5), look-at (0, 0, 0), up
** (0, -1, -5) gives |up x w| ~ 1e-16 |up|, which the previous test (the
** rounded cross product's length > 0) took for a frame.
*/
static int up_usable(ray_vec3 up, ray_vec3 w)
{
    ray_vec3 unit_up;

    return v3_normalize(up, &unit_up) &&
           v3_length(v3_cross(unit_up, w)) > 16 * DBL_EPSILON;
}

int ray__camera_setup(ray__cam *c, const ray_camera *cam, unsigned width,
                      unsigned height)
{
    ray_vec3 w, u, v;
    double half, focus;

    if (!v3_isfinite(cam->position) || !v3_isfinite(cam->look_at) ||
        !v3_isfinite(cam->up) || !(cam->vfov > 0 && cam->vfov < 180) ||
        !(cam->aperture >= 0 && cam->aperture < HUGE_VAL) ||
        !(cam->focus_distance >= 0 && cam->focus_distance < HUGE_VAL) ||
        !v3_normalize(v3_sub(cam->position, cam->look_at), &w) ||
        !up_usable(cam->up, w) || !v3_normalize(v3_cross(cam->up, w), &u))
        return RAY_EINVAL;
    v = v3_cross(w, u);
    half = tan(cam->vfov * RAY__PI / 360.0);
    focus = cam->focus_distance > 0
                ? cam->focus_distance
                : v3_length(v3_sub(cam->look_at, cam->position));
    c->org = cam->position;
    c->u = u;
    c->v = v;
    c->w = w;
    c->half_h = half;
    c->half_w = half * (double)width / (double)height;
    c->lens_radius = cam->aperture / 2;
    c->focus = focus;
    c->inv_w = 1.0 / (double)width;
    c->inv_h = 1.0 / (double)height;
    return RAY_OK;
}

/*
** The primary ray through image position (x + sx, y + sy), sx, sy in
** [0, 1), y counted from the top.  With a lens, the ray starts at a point
** (lx, ly) in [-1,1]^2 mapped onto the lens disk (concentric map) and
** passes through the point the pinhole ray meets on the focus plane.
*/
void ray__camera_ray(const ray__cam *c, double x, double y, double lx,
                     double ly, ray_ray *r)
{
    double px = (2.0 * x * c->inv_w - 1.0) * c->half_w;
    double py = (1.0 - 2.0 * y * c->inv_h) * c->half_h;
    ray_vec3 dir = v3_sub(v3_add(v3_scale(c->u, px), v3_scale(c->v, py)),
                          c->w);

    r->org = c->org;
    r->tmin = 0.0;
    r->tmax = HUGE_VAL;
    if (c->lens_radius > 0) {
        ray_vec3 focus_point = v3_madd(c->org, c->focus, dir);
        double dx, dy;
        ray__concentric_disk(lx, ly, &dx, &dy);
        r->org = v3_add(c->org, v3_add(v3_scale(c->u, c->lens_radius * dx),
                                       v3_scale(c->v, c->lens_radius * dy)));
        dir = v3_sub(focus_point, r->org);
    }
    r->dir = dir;
}
