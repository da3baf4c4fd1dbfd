/* SPDX-License-Identifier: MIT */
/*
** camera.h -- the camera's precomputed frame (private).
*/
#ifndef RAY_CAMERA_H
#define RAY_CAMERA_H

#include "trace/trace.h"

typedef struct ray__cam {
    ray_vec3 org, u, v, w;   /* right, up, backward */
    double half_w, half_h;   /* image-plane half extents at distance 1 */
    double lens_radius, focus;
    double inv_w, inv_h;
} ray__cam;

/* The frame of a camera that ray_render_check accepted (RAY_EINVAL for
** one whose view axis or roll cannot be normalised). */
int ray__camera_setup(ray__cam *c, const ray_camera *cam, unsigned width,
                      unsigned height);
/* Zero is the default (ray.h): *oo and *co are *o and *c with their zero
** fields given the values they stand for (samples 1, adaptive depth 2;
** up +y, vfov 60), so that the checks and the render read one meaning.
** o and c are not NULL. */
void ray__render_defaults(const ray_render_options *o, const ray_camera *c,
                          ray_render_options *oo, ray_camera *co);
void ray__camera_ray(const ray__cam *c, double x, double y, double lx,
                     double ly, ray_ray *r);

#endif
