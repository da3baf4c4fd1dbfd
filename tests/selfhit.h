/* SPDX-License-Identifier: MIT */
/*
** selfhit.h -- counts "acne": secondary rays, spawned from a hit with
** ray_spawn / ray_spawn_to, that hit the surface they leave.  Shared by
** the Check suite (tests/check_selfhit.c asserts zero everywhere) and the
** bench (bench/selfhit.c prints the counts per primitive kind).
**
** For every primitive kind, placed axis-aligned or rotated, at offsets
** 0, 0.5, 1e5 and 1e6 from the origin, camera rays at steep and at
** grazing angles find a hit; from it three rays leave:
**   - a shadow ray toward a point light above the surface (ray_spawn_to),
**   - the mirror reflection (ray_spawn, ray_reflect),
**   - the refraction into the surface (ray_spawn, ray_refract, eta 1/1.5),
** each through the bare primitive function and through a one-primitive
** scene (ray_intersect, and ray_occluded for the shadow ray).
**
** What counts as a self-hit.  A flat primitive (plane, polygon, triangle,
** mesh quad, flat Bezier patch) can never be hit again by a ray leaving
** it: any hit is acne.  A curved one legitimately can (a shadow ray
** through a sphere, a refracted ray reaching the far side, a reflection
** inside a torus's hole), but only at a chord's distance, at least
** 2 rho sin(theta) for curvature radius rho and leaving angle theta; acne
** is found within the rounding error of the hit point, some ulps of its
** coordinates.  So a curved-surface hit counts when closer than
** SH_NEAR: 1e-6 of the object's size plus 2^20 ulps of the largest
** coordinate -- three or more orders above the errors that cause acne
** (and above the default root tolerance of ray_implicit and
** ray_parametric, 1e-9 of the size plus 64 ulps), and below the shortest
** legitimate chord the test's angles produce (the grazing camera rays
** leave at 0.05 degrees or more: 2 * 0.35 * sin(0.05 deg) = 6e-4).
**
** Header-only, deterministic (fixed seeds of testkit.h's generator); not
** part of the library.
*/
#ifndef TESTS_SELFHIT_H
#define TESTS_SELFHIT_H

#include <math.h>
#include <float.h>
#include <stdlib.h>
#include <string.h>

#include "ray.h"
#include "prim/prim.h"         /* ray__implicit_torus */
#include "testkit.h"

typedef enum sh_kind {
    SH_SPHERE,
    SH_PLANE,
    SH_TRIANGLE,             /* ray_triangle: Cramer's rule */
    SH_TRIANGLE_WATERTIGHT,  /* ray_triangle_watertight */
    SH_MESH,                 /* a two-triangle quad, scene watertight */
    SH_MESH_CRAMER,          /* the same with ray_scene_set_watertight 0 */
    SH_POLYGON,
    SH_TORUS,
    SH_IMPLICIT,             /* the torus through ray_implicit */
    SH_BEZIER,               /* a flat bicubic patch, ray_parametric */
    SH_BOX,                  /* ray_box, axes of other lengths, skewed */
    SH_CAPSULE,              /* ray_capsule, along the local x axis */
    SH_USER,                 /* user geometry: ray_sphere in a callback */
    SH_KINDS
} sh_kind;

static const char *const sh_kind_name[SH_KINDS] = {
    "sphere", "plane", "triangle (Cramer)", "triangle (watertight)",
    "mesh quad (watertight)", "mesh quad (Cramer)", "polygon", "torus",
    "implicit torus", "Bezier patch (flat)",
    "box", "capsule", "user sphere"
};

/* Offsets of the placements from the origin (each coordinate). */
static const double sh_offsets[] = {0, 0.5, 1e5, 1e6};
#define SH_OFFSETS 4

typedef struct sh_counts {
    long rays;               /* camera rays that hit */
    long shadow, reflect, refract;   /* of those, secondary self-hits */
} sh_counts;

/* One primitive, placed: world = c + rot * local. */
typedef struct sh_prim {
    sh_kind kind;
    ray_vec3 c, ex, ey, ez;  /* placement: origin and rotated axes */
    double size;             /* half-extent of the object */
    ray_vec3 tri[4];         /* quad corners (world), triangle = tri[0..2] */
    ray_vec3 poly[6];
    ray_vec3 cp[16];
    ray_torus_params torus;
    ray_implicit_surface implicit;
    ray_parametric_surface bezier;
    ray_box_params box;
    ray_capsule_params capsule;
    ray_vec3 user_center;    /* the user sphere's: c, radius 1 */
} sh_prim;

static inline ray_vec3 sh_world(const sh_prim *p, double x, double y,
                                double z)
{
    return vec(p->c.x + x * p->ex.x + y * p->ey.x + z * p->ez.x,
                 p->c.y + x * p->ex.y + y * p->ey.y + z * p->ez.y,
                 p->c.z + x * p->ex.z + y * p->ey.z + z * p->ez.z);
}

static inline int sh_flat(sh_kind k)
{
    /* The box is flat by pieces, but a ray entering it meets the other
    ** faces at a chord's distance: counted as curved, as the capsule. */
    return k != SH_SPHERE && k != SH_TORUS && k != SH_IMPLICIT &&
           k != SH_BOX && k != SH_CAPSULE && k != SH_USER;
}

/*
** Placement "rotated": the axes turned 0.7 rad about (1, 2, 3)/|.|
** (Rodrigues), so no coordinate of the surface is exactly representable
** and no normal is axis-aligned; "axis-aligned": the identity.
*/
static inline void sh_place(sh_prim *p, sh_kind kind, double offset,
                            int rotated)
{
    double k[3] = {1, 2, 3}, len = sqrt(14.0), th = 0.7, c, s;
    double R[3][3];
    int i, j;

    memset(p, 0, sizeof *p);
    p->kind = kind;
    p->c = vec(offset, offset, offset);
    c = cos(th), s = sin(th);
    for (i = 0; i < 3; i++)
        k[i] /= len;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            R[i][j] = (i == j ? c : 0) + (1 - c) * k[i] * k[j];
    R[0][1] -= s * k[2], R[0][2] += s * k[1];
    R[1][0] += s * k[2], R[1][2] -= s * k[0];
    R[2][0] -= s * k[1], R[2][1] += s * k[0];
    if (!rotated)
        for (i = 0; i < 3; i++)
            for (j = 0; j < 3; j++)
                R[i][j] = i == j;
    p->ex = vec(R[0][0], R[1][0], R[2][0]);
    p->ey = vec(R[0][1], R[1][1], R[2][1]);
    p->ez = vec(R[0][2], R[1][2], R[2][2]);
    p->size = !sh_flat(kind) ? 1.35 : 100;
    /* Flat kinds lie in the local plane y = 0: a floor 200 wide, so
    ** camera rays reach it both near its centre and far out. */
    p->tri[0] = sh_world(p, -100, 0, -100);
    p->tri[1] = sh_world(p, -100, 0, 100);
    p->tri[2] = sh_world(p, 100, 0, 100);
    p->tri[3] = sh_world(p, 100, 0, -100);
    for (i = 0; i < 6; i++)
        p->poly[i] = sh_world(p, 100 * cos(i * 1.0471975511965976), 0,
                              -100 * sin(i * 1.0471975511965976));
    for (i = 0; i < 4; i++)
        for (j = 0; j < 4; j++)
            p->cp[4 * i + j] = sh_world(p, -100 + 200.0 * j / 3, 0,
                                        -100 + 200.0 * i / 3);
    p->torus.center = p->c;
    p->torus.axis = p->ey;
    p->torus.major = 1;
    p->torus.minor = 0.35;
    ray__implicit_torus(&p->torus, &p->implicit);
    ray_bezier_surface(p->cp, &p->bezier);
    /* The box's axes as a user may give them: x of length 2, y skewed
    ** toward x (Gram-Schmidt makes it ey again). */
    p->box.center = p->c;
    p->box.half_extents = vec(1.0, 0.4, 0.8);
    p->box.axis_x = vec(2 * p->ex.x, 2 * p->ex.y, 2 * p->ex.z);
    p->box.axis_y = vec(0.5 * p->ey.x + 0.25 * p->ex.x,
                          0.5 * p->ey.y + 0.25 * p->ex.y,
                          0.5 * p->ey.z + 0.25 * p->ex.z);
    /* The capsule: ends at local x = -+0.6, radius 0.6 (1.2 x 2.4 seen
    ** from above: half the camera rays' targets). */
    p->capsule.a = sh_world(p, -0.6, 0, 0);
    p->capsule.b = sh_world(p, 0.6, 0, 0);
    p->capsule.radius = 0.6;
    p->user_center = p->c;
}

/*
** The user sphere: the sphere of SH_SPHERE as user geometry, its
** callback calling ray_sphere, which fills p_err (what ray_spawn offsets
** by): so the scene's checks of the callback's answer, and its BVH, are
** shown to keep the sphere free of acne.  ud: the centre (radius 1).
*/
static inline void sh_user_bounds(void *ud, ray_vec3 *lo, ray_vec3 *hi)
{
    const ray_vec3 *c = (const ray_vec3 *)ud;

    *lo = vec(c->x - 1, c->y - 1, c->z - 1);
    *hi = vec(c->x + 1, c->y + 1, c->z + 1);
}

static inline int sh_user_intersect(void *ud, const ray_ray *r, ray_hit *h)
{
    return ray_sphere(r, *(const ray_vec3 *)ud, 1.0, h);
}

/* The closest hit of the bare primitive function(s); 1 on a hit. */
static inline int sh_bare(const sh_prim *p, const ray_ray *r, ray_hit *h)
{
    ray_hit h2;
    int a, b;

    switch (p->kind) {
    case SH_SPHERE:
        return ray_sphere(r, p->c, 1.0, h) == 1;
    case SH_PLANE:
        return ray_plane(r, p->c, p->ey, h) == 1;
    case SH_TRIANGLE:
        return ray_triangle(r, p->tri[0], p->tri[1], p->tri[2], h) == 1;
    case SH_TRIANGLE_WATERTIGHT:
        return ray_triangle_watertight(r, p->tri[0], p->tri[1], p->tri[2],
                                       h) == 1;
    case SH_MESH:
    case SH_MESH_CRAMER:
        if (p->kind == SH_MESH) {
            a = ray_triangle_watertight(r, p->tri[0], p->tri[1], p->tri[2], h);
            b = ray_triangle_watertight(r, p->tri[0], p->tri[2], p->tri[3],
                                        &h2);
        } else {
            a = ray_triangle(r, p->tri[0], p->tri[1], p->tri[2], h);
            b = ray_triangle(r, p->tri[0], p->tri[2], p->tri[3], &h2);
        }
        if (b == 1 && (a != 1 || h2.t < h->t))
            *h = h2;
        return a == 1 || b == 1;
    case SH_POLYGON:
        return ray_polygon(r, p->poly, 6, h) == 1;
    case SH_TORUS:
        return ray_torus(r, &p->torus, h) == 1;
    case SH_IMPLICIT:
        return ray_implicit(r, &p->implicit, h) == 1;
    case SH_BEZIER:
        return ray_parametric(r, &p->bezier, h) == 1;
    case SH_BOX:
        return ray_box(r, &p->box, h) == 1;
    case SH_CAPSULE:
        return ray_capsule(r, &p->capsule, h) == 1;
    case SH_USER:
        return sh_user_intersect(ray__test_unconst(&p->user_center), r,
                                 h) == 1;
    case SH_KINDS:
        break;
    }
    return 0;
}

/* A committed scene holding only p; NULL if a call failed. */
static inline ray_scene *sh_scene(const sh_prim *p)
{
    static const unsigned quad[6] = {0, 1, 2, 0, 2, 3};
    ray_material m = plain();
    ray_mesh mesh;
    ray_user_geometry user;
    ray_scene *s;
    int rc = RAY_OK;

    if (ray_scene_new(&s, NULL, NULL) != RAY_OK)
        return NULL;
    rc = ray_scene_add_material(s, &m, NULL);
    memset(&mesh, 0, sizeof mesh);
    mesh.vertices = p->tri, mesh.vertex_count = 4;
    mesh.indices = quad, mesh.triangle_count = 2;
    switch (p->kind) {
    case SH_SPHERE: rc |= ray_scene_add_sphere(s, p->c, 1.0, 0, NULL); break;
    case SH_PLANE: rc |= ray_scene_add_plane(s, p->c, p->ey, 0, NULL); break;
    case SH_TRIANGLE:
    case SH_TRIANGLE_WATERTIGHT:
        rc |= ray_scene_add_triangle(s, p->tri[0], p->tri[1], p->tri[2], 0,
                                     NULL);
        break;
    case SH_MESH:
    case SH_MESH_CRAMER: rc |= ray_scene_add_mesh(s, &mesh, 0, NULL); break;
    case SH_POLYGON: rc |= ray_scene_add_polygon(s, p->poly, 6, 0, NULL); break;
    case SH_TORUS: rc |= ray_scene_add_torus(s, &p->torus, 0, NULL); break;
    case SH_IMPLICIT:
        rc |= ray_scene_add_implicit(s, &p->implicit, 0, NULL);
        break;
    case SH_BEZIER: rc |= ray_scene_add_bezier(s, p->cp, 0, NULL); break;
    case SH_BOX: rc |= ray_scene_add_box(s, &p->box, 0, NULL); break;
    case SH_CAPSULE:
        rc |= ray_scene_add_capsule(s, &p->capsule, 0, NULL);
        break;
    case SH_USER:
        user.bounds = sh_user_bounds;
        user.intersect = sh_user_intersect;
        user.ud = ray__test_unconst(&p->user_center);
        rc |= ray_scene_add_user(s, &user, 0, NULL);
        break;
    case SH_KINDS: rc = RAY_EINVAL; break;
    }
    rc |= ray_scene_set_watertight(s, p->kind != SH_TRIANGLE &&
                                          p->kind != SH_MESH_CRAMER);
    rc |= ray_scene_commit(s);
    if (rc != RAY_OK) {
        ray_scene_free(s);
        return NULL;
    }
    return s;
}

/* The largest |coordinate| of v. */
static inline double sh_maxabs(ray_vec3 v)
{
    return fmax(fabs(v.x), fmax(fabs(v.y), fabs(v.z)));
}

/* The self-hit distance bound of the header comment. */
static inline double sh_near(const sh_prim *p)
{
    return 1e-6 * p->size +
           1048576.0 * DBL_EPSILON * (sh_maxabs(p->c) + p->size);
}

/* Is the secondary ray s's hit (through scene or bare function) acne? */
static inline int sh_self(const sh_prim *p, const ray_scene *scene,
                          const ray_ray *s, int shadow)
{
    ray_hit h;
    int hit;

    if (scene != NULL) {
        if (shadow && sh_flat(p->kind) && ray_occluded(scene, s, NULL) == 1)
            return 1;
        hit = ray_intersect(scene, s, &h, NULL) == 1;
    } else
        hit = sh_bare(p, s, &h);
    if (!hit)
        return 0;
    if (sh_flat(p->kind))
        return 1;
    return h.t * sqrt(s->dir.x * s->dir.x + s->dir.y * s->dir.y +
                      s->dir.z * s->dir.z) < sh_near(p);
}

/*
** n camera rays (half steep: 20 to 80 degrees above the local floor, half
** grazing: 0.05 to 3 degrees) toward random points of the object (for the
** flat ones, half within 4 of its centre and half out to 90), from 8
** units away for the curved ones and 24 for the flat; through "scene"
** when not NULL, else the bare function.
*/
static inline void sh_run(const sh_prim *p, const ray_scene *scene, int n,
                          uint64_t seed, sh_counts *out)
{
    const double deg = 3.14159265358979323846 / 180;
    ray_vec3 light = sh_world(p, 3, 6, 4);
    rng g = {seed};
    int i;

    memset(out, 0, sizeof *out);
    for (i = 0; i < n; i++) {
        double el = i % 2 ? (20 + 60 * rng_unit(&g)) * deg
                          : (0.05 + 2.95 * rng_unit(&g)) * deg;
        double az = 6.283185307179586 * rng_unit(&g);
        double reach = sh_flat(p->kind) ? (i % 4 < 2 ? 4 : 90) : 1.2;
        double tx = (2 * rng_unit(&g) - 1) * reach;
        double tz = (2 * rng_unit(&g) - 1) * reach;
        double ty = sh_flat(p->kind) ? 0 : (2 * rng_unit(&g) - 1) * 0.4;
        double dist = sh_flat(p->kind) ? 24 : 8;
        ray_vec3 target = sh_world(p, tx, ty, tz), eye, d, t;
        ray_ray r, s;
        ray_hit h;
        int hit;

        eye = sh_world(p, tx + dist * cos(el) * cos(az), ty + dist * sin(el),
                       tz + dist * cos(el) * sin(az));
        d = vec(target.x - eye.x, target.y - eye.y, target.z - eye.z);
        r.org = eye, r.dir = d, r.tmin = 0, r.tmax = HUGE_VAL;
        hit = scene != NULL ? ray_intersect(scene, &r, &h, NULL) == 1
                            : sh_bare(p, &r, &h);
        if (!hit)
            continue;
        out->rays++;
        if (ray_spawn_to(&h, light, &s) == RAY_OK &&
            sh_self(p, scene, &s, 1))
            out->shadow++;
        if (ray_spawn(&h, ray_reflect(d, h.n), &s) == RAY_OK &&
            sh_self(p, scene, &s, 0))
            out->reflect++;
        if (!ray_refract(d, h.n, 1 / 1.5, &t))
            t = d;
        if (ray_spawn(&h, t, &s) == RAY_OK && sh_self(p, scene, &s, 0))
            out->refract++;
    }
}

#endif
