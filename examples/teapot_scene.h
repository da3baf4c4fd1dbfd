/* SPDX-License-Identifier: MIT */
/*
** teapot_scene.h -- the Utah teapot's scene (examples/teapot.c), shared
** with examples/mpi_render.c so both render the same bytes.  Header-only.
*/
#ifndef EXAMPLES_TEAPOT_SCENE_H
#define EXAMPLES_TEAPOT_SCENE_H

#include "bpt.h"
#include "common.h"

/*
** Newell's data is z-up; the scene is y-up (the floor is y = const and
** the backdrop's gradient follows y).  (x, y, z) -> (x, z, -y) is the
** rotation by -90 degrees about x: a rotation, not a mirror, so each patch
** keeps its orientation (which side its u x v normal points to).  The spout,
** toward +x, stays on the right of a camera on the +z side.
*/
static inline ray_vec3 newell_to_scene(ray_vec3 p)
{
    return vec(p.x, p.z, -p.y);
}

/* The box of the rotated control points: centre, lowest y, diagonal. */
static inline void scene_bounds(const bpt_patches *model, ray_vec3 *centre,
                         double *floor_y, double *diag)
{
    ray_vec3 lo, hi, a, b;

    bpt_bounds(model, &lo, &hi);
    a = newell_to_scene(lo);
    b = newell_to_scene(hi);
    /* The rotation negates y, so a.z >= b.z: the centre and the diagonal
    ** do not mind. */
    *centre = vec((a.x + b.x) / 2, (a.y + b.y) / 2, (a.z + b.z) / 2);
    *floor_y = a.y;
    *diag = sqrt((b.x - a.x) * (b.x - a.x) + (b.y - a.y) * (b.y - a.y) +
                 (b.z - a.z) * (b.z - a.z));
}

/* Every patch, rotated to y-up, with material "glaze". */
static inline void add_patches(ray_scene *scene, const bpt_patches *model,
                        unsigned glaze)
{
    size_t k;
    int c;

    for (k = 0; k < model->count; k++) {
        ray_vec3 cp[16];
        for (c = 0; c < 16; c++)
            cp[c] = newell_to_scene(model->patches[k][c]);
        check(ray_scene_add_bezier(scene, cp, glaze, NULL),
              "ray_scene_add_bezier");
    }
}

/*
** The floor: light and dark squares an eighth of the model's size, just
** below it.  The teapot's bottom touches z = 0 at its centre and rises
** slowly from there (its first two rows of control points lie on z = 0),
** so a plane at the lowest point would stay within rounding error of the
** bottom around that point, and which of the two a ray hits would be
** noise.  Lowered by a thousandth of the model's size, far under a
** pixel, it is clear of it.
*/
static inline void add_floor(ray_scene *scene, double floor_y, double diag)
{
    /* Parameter blocks are borrowed by the scene: static, to outlive it. */
    static ray_phong_params light, dark;
    static ray_checker_params floor_params;
    ray_material m;
    unsigned id;

    light = phong_params(rgb(0.78, 0.76, 0.72), rgb(0.1, 0.1, 0.1), 20,
                  rgb(0, 0, 0));
    dark = phong_params(rgb(0.3, 0.32, 0.36), rgb(0.1, 0.1, 0.1), 20, rgb(0, 0, 0));
    floor_params.even = ray_material_phong(&light);
    floor_params.odd = ray_material_phong(&dark);
    floor_params.scale = 8.0 / diag;
    m = ray_material_checker(&floor_params);
    check(ray_scene_add_material(scene, &m, &id), "floor material");
    check(ray_scene_add_plane(scene, vec(0, floor_y - 1e-3 * diag, 0),
                              vec(0, 1, 0), id, NULL), "floor");
}

/*
** A soft key light up and to the left, and a dim point fill light near
** the camera (its shadows fall behind the teapot, where they are not
** seen).  Intensities grow with the square of the model's size, so the
** light arriving is the same at any scale.
*/
static inline void add_lights(ray_scene *scene, ray_vec3 centre, double diag)
{
    ray_light key, fill;
    double d2 = diag * diag;

    memset(&key, 0, sizeof key);
    key.kind = RAY_LIGHT_SPHERE;
    key.position = vec(centre.x - 0.8 * diag, centre.y + 1.3 * diag,
                       centre.z + 0.9 * diag);
    key.radius = 0.15 * diag;           /* wide enough for soft shadows */
    key.intensity = rgb(2.6 * d2, 2.5 * d2, 2.3 * d2);     /* warm white */
    key.samples = 9;                    /* 3 x 3 shadow rays */
    check(ray_scene_add_light(scene, &key, NULL), "key light");

    memset(&fill, 0, sizeof fill);
    fill.kind = RAY_LIGHT_POINT;
    fill.position = vec(centre.x + 0.9 * diag, centre.y + 0.6 * diag,
                        centre.z + 1.5 * diag);
    fill.intensity = rgb(0.35 * d2, 0.38 * d2, 0.45 * d2);  /* cool */
    check(ray_scene_add_light(scene, &fill, NULL), "fill light");
}

/* The background: a pale blue-grey, lighter toward the zenith, by the
** escaping ray's direction. */
static inline void backdrop(void *ud, const ray_ray *r, ray_rgb *out)
{
    double len = sqrt(r->dir.x * r->dir.x + r->dir.y * r->dir.y +
                      r->dir.z * r->dir.z);
    double up = len > 0 ? r->dir.y / len : 0;    /* -1 .. 1 */
    double k = 0.5 * (up + 1);                   /*  0 .. 1 */

    (void)ud;
    *out = rgb(0.45 + 0.3 * k, 0.5 + 0.3 * k, 0.6 + 0.3 * k);
}

/* The committed scene, and the camera framing it into *cam. */
static inline ray_scene *teapot_scene(const bpt_patches *model, ray_camera *cam)
{
    static ray_phong_params glaze;   /* borrowed by the scene */
    ray_material m;
    ray_scene *scene;
    ray_vec3 centre;
    unsigned glaze_id;
    double floor_y, diag;

    scene_bounds(model, &centre, &floor_y, &diag);
    check(ray_scene_new(&scene, NULL, NULL), "ray_scene_new");
    /* A glazed red: saturated diffuse, a sharp white highlight, and a
    ** faint reflection of the floor and the backdrop. */
    glaze = phong_params(rgb(0.6, 0.07, 0.05), rgb(0.7, 0.7, 0.7), 90,
                  rgb(0.06, 0.06, 0.06));
    m = ray_material_phong(&glaze);
    check(ray_scene_add_material(scene, &m, &glaze_id), "glaze material");
    add_patches(scene, model, glaze_id);
    add_floor(scene, floor_y, diag);
    add_lights(scene, centre, diag);
    check(ray_scene_set_ambient(scene, rgb(0.12, 0.12, 0.14)), "ambient");
    check(ray_scene_set_background(scene, rgb(0, 0, 0), backdrop, NULL), "background");
    check(ray_scene_commit(scene), "ray_scene_commit");

    /* From the front and a little above (about 25 degrees), 1.4 box
    ** diagonals away: the teapot fills three quarters of the width. */
    memset(cam, 0, sizeof *cam);
    cam->position = vec(centre.x + 0.2 * diag, centre.y + 0.55 * diag,
                        centre.z + 1.25 * diag);
    cam->look_at = centre;
    cam->up = vec(0, 1, 0);
    cam->vfov = 32;
    return scene;
}

#endif
