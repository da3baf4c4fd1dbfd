/* SPDX-License-Identifier: MIT */
/*
** camera.c -- primary rays from a pinhole or thin-lens camera.
*/
#include "render/camera.h"

int ray__camera_setup(ray__cam *c, const ray_camera *cam, unsigned width,
                      unsigned height)
{
    ray_vec3 w, u, v;
    double half, focus;

    /* ray_render_check (check.c) has refused any camera for which these
    ** normalisations fail: the frame is well defined here. */
    if (!v3_normalize(v3_sub(cam->position, cam->look_at), &w) ||
        !v3_normalize(v3_cross(cam->up, w), &u))
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
