/* SPDX-License-Identifier: MIT */
/*
** scenes.h -- the showcase scenes, shared by the examples and the
** benchmarks so both render exactly the same thing.  Header-only.
*/
#ifndef EXAMPLES_SCENES_H
#define EXAMPLES_SCENES_H

#include "common.h"
#include "obj.h"

/* The scene's ray tree bounds: "limits" (NULL: the defaults), in the
** naive mode (ray_limits.no_pruning) when prune is 0. */
static inline void set_tree_limits(ray_scene *scene, int prune,
                                   const ray_limits *limits)
{
    ray_limits l;

    if (limits != NULL)
        l = *limits;
    else
        ray_limits_init(&l);
    l.no_pruning = !prune;
    check(ray_scene_set_limits(scene, &l), "limits");
}

/*
** Whitted's 1980 scene: a red and yellow checkerboard floor, a mirror
** sphere and a glass sphere under a point light, a sky gradient.
** Returns a committed scene and fills *cam.  prune = 0 builds it in the
** naive mode (ray_limits.no_pruning), and "limits" (NULL: the defaults)
** bounds its ray tree, for the benchmarks.
*/
static inline ray_scene *whitted_scene(ray_camera *cam, int prune,
                                       const ray_limits *limits)
{
    static const ray_phong_params red = {.diffuse = {0.75, 0.08, 0.06},
                                         .specular = {0.2, 0.2, 0.2},
                                         .shininess = 40, .blinn = 1};
    static const ray_phong_params yellow = {.diffuse = {0.8, 0.7, 0.1},
                                            .specular = {0.2, 0.2, 0.2},
                                            .shininess = 40, .blinn = 1};
    static const ray_rgb chrome = {0.9, 0.9, 0.9};
    static const ray_glass_params glass = {.ior = 1.5,
                                           .absorption = {0.05, 0.02, 0.01}};
    static ray_checker_params floor_params;
    /* The sky: a vertical gradient of the escaping ray's direction. */
    static sky_colors blue_sky = {{0.35, 0.45, 0.75}, {0.25, 0.3, 0.2}};
    ray_light light = {.kind = RAY_LIGHT_POINT, .position = {4, 7, 5},
                       .intensity = {80, 80, 80}};
    ray_camera view = {.position = {0, 1.5, 5.5}, .look_at = {0, 0.9, 0},
                       .up = {0, 1, 0}, .vfov = 45};
    ray_material m;
    ray_scene *scene;
    unsigned floor_mat, mirror_mat, glass_mat;

    floor_params.even = ray_material_phong(&red);
    floor_params.odd = ray_material_phong(&yellow);
    floor_params.scale = 1.0;
    check(ray_scene_new(&scene, NULL, NULL), "ray_scene_new");
    m = ray_material_checker(&floor_params);
    check(ray_scene_add_material(scene, &m, &floor_mat), "floor material");
    m = ray_material_mirror(&chrome);
    check(ray_scene_add_material(scene, &m, &mirror_mat), "mirror material");
    m = ray_material_glass(&glass);
    check(ray_scene_add_material(scene, &m, &glass_mat), "glass material");
    check(ray_scene_add_plane(scene, vec(0, 0, 0), vec(0, 1, 0), floor_mat,
                              NULL), "floor");
    check(ray_scene_add_sphere(scene, vec(-1.1, 1.0, -1.2), 1.0, mirror_mat,
                               NULL), "mirror sphere");
    check(ray_scene_add_sphere(scene, vec(0.9, 0.8, 0.6), 0.8, glass_mat,
                               NULL), "glass sphere");
    check(ray_scene_add_light(scene, &light, NULL), "light");
    check(ray_scene_set_ambient(scene, rgb(0.12, 0.12, 0.14)), "ambient");
    check(ray_scene_set_background(scene, rgb(0, 0, 0), sky_gradient, &blue_sky),
          "background");
    set_tree_limits(scene, prune, limits);
    check(ray_scene_commit(scene), "commit");
    *cam = view;
    return scene;
}

/* Add the quad a b c d as two triangles (a b c, a c d). */
static inline void add_quad_triangles(ray_scene *s, ray_vec3 a, ray_vec3 b,
                               ray_vec3 c, ray_vec3 d, unsigned mat)
{
    check(ray_scene_add_triangle(s, a, b, c, mat, NULL), "triangle");
    check(ray_scene_add_triangle(s, a, c, d, mat, NULL), "triangle");
}

static inline void add_quad_polygon(ray_scene *s, ray_vec3 a, ray_vec3 b,
                             ray_vec3 c, ray_vec3 d, unsigned mat)
{
    ray_vec3 v[4];
    v[0] = a;
    v[1] = b;
    v[2] = c;
    v[3] = d;
    check(ray_scene_add_polygon(s, v, 4, mat, NULL), "polygon");
}

/* A box standing on the floor: centre (cx, cz), half sizes hx, hz,
** height h, rotated by angle a about y; four side polygons and a top. */
static inline void add_block(ray_scene *s, double cx, double cz, double hx,
                      double hz, double h, double a, unsigned mat)
{
    ray_vec3 lo[4], hi[4];
    int i;

    for (i = 0; i < 4; i++) {
        double x = (i == 1 || i == 2) ? hx : -hx;
        double z = (i >= 2) ? hz : -hz;
        double rx = cx + x * cos(a) - z * sin(a);
        double rz = cz + x * sin(a) + z * cos(a);
        lo[i] = vec(rx, 0, rz);
        hi[i] = vec(rx, h, rz);
    }
    for (i = 0; i < 4; i++) {
        int j = (i + 1) % 4;
        add_quad_polygon(s, lo[i], lo[j], hi[j], hi[i], mat);
    }
    add_quad_polygon(s, hi[0], hi[3], hi[2], hi[1], mat);
}

/*
** A Cornell-box-like room of polygons (floor, ceiling, back wall, block)
** and triangles (red and green side walls), a rectangular area light under
** the ceiling, a glass and a mirror sphere.  Committed; fills *cam;
** prune as for whitted_scene.
*/
static inline ray_scene *cornell_scene(ray_camera *cam, int prune,
                                       const ray_limits *limits)
{
    static const ray_phong_params white = {.diffuse = {0.75, 0.75, 0.72},
                                           .shininess = 1};
    static const ray_phong_params red = {.diffuse = {0.65, 0.06, 0.05},
                                         .shininess = 1};
    static const ray_phong_params green = {.diffuse = {0.12, 0.5, 0.09},
                                           .shininess = 1};
    static const ray_rgb chrome = {0.92, 0.92, 0.92};
    static const ray_glass_params glass = {.ior = 1.5};
    /* edge1 x edge2 = (0, -2.25, 0): the lamp shines down. */
    ray_light lamp = {.kind = RAY_LIGHT_RECT,
                      .position = {-0.75, 4.98, -0.75},
                      .edge1 = {1.5, 0, 0}, .edge2 = {0, 0, 1.5},
                      .intensity = {16, 15, 13}, .samples = 16};
    ray_camera view = {.position = {0, 2.5, 9.5}, .look_at = {0, 2.5, 0},
                       .up = {0, 1, 0}, .vfov = 36};
    ray_material m;
    ray_scene *scene;
    unsigned w, r, g, mir, gl;

    check(ray_scene_new(&scene, NULL, NULL), "ray_scene_new");
    m = ray_material_phong(&white);
    check(ray_scene_add_material(scene, &m, &w), "white");
    m = ray_material_phong(&red);
    check(ray_scene_add_material(scene, &m, &r), "red");
    m = ray_material_phong(&green);
    check(ray_scene_add_material(scene, &m, &g), "green");
    m = ray_material_mirror(&chrome);
    check(ray_scene_add_material(scene, &m, &mir), "mirror");
    m = ray_material_glass(&glass);
    check(ray_scene_add_material(scene, &m, &gl), "glass");

    /* The room: x, z in [-2.5, 2.5], y in [0, 5], open toward +z. */
    add_quad_polygon(scene, vec(-2.5, 0, 2.5), vec(2.5, 0, 2.5),
                     vec(2.5, 0, -2.5), vec(-2.5, 0, -2.5), w);       /* floor */
    add_quad_polygon(scene, vec(-2.5, 5, -2.5), vec(2.5, 5, -2.5),
                     vec(2.5, 5, 2.5), vec(-2.5, 5, 2.5), w);         /* ceiling */
    add_quad_polygon(scene, vec(-2.5, 0, -2.5), vec(2.5, 0, -2.5),
                     vec(2.5, 5, -2.5), vec(-2.5, 5, -2.5), w);       /* back */
    add_quad_triangles(scene, vec(-2.5, 0, 2.5), vec(-2.5, 0, -2.5),
                       vec(-2.5, 5, -2.5), vec(-2.5, 5, 2.5), r);     /* left */
    add_quad_triangles(scene, vec(2.5, 0, -2.5), vec(2.5, 0, 2.5),
                       vec(2.5, 5, 2.5), vec(2.5, 5, -2.5), g);       /* right */
    add_block(scene, -0.9, -0.8, 0.7, 0.7, 2.8, 0.35, w);
    check(ray_scene_add_sphere(scene, vec(1.2, 0.8, 0.5), 0.8, gl, NULL),
          "glass sphere");
    check(ray_scene_add_sphere(scene, vec(-0.3, 0.5, 1.3), 0.5, mir, NULL),
          "mirror sphere");
    check(ray_scene_add_light(scene, &lamp, NULL), "lamp");
    check(ray_scene_set_ambient(scene, rgb(0.06, 0.06, 0.06)), "ambient");
    set_tree_limits(scene, prune, limits);
    check(ray_scene_commit(scene), "commit");

    *cam = view;
    return scene;
}

/*
** A Wavefront OBJ model in clay (Blinn-Phong; smooth if the file has
** normals) on a slightly reflective floor under a spherical light, the
** camera on the +z side framing the model.  NULL (with a message on
** stderr) if the file cannot be read.  *triangles: the model's count.
*/
static inline ray_scene *mesh_scene(const char *path, ray_camera *cam,
                                    int prune, const ray_limits *limits,
                                    size_t *triangles)
{
    static const ray_phong_params clay = {.diffuse = {0.7, 0.66, 0.6},
                                          .specular = {0.25, 0.25, 0.25},
                                          .shininess = 30, .blinn = 1};
    static const ray_phong_params ground = {.diffuse = {0.35, 0.4, 0.45},
                                            .shininess = 1,
                                            .reflect = {0.2, 0.2, 0.2}};
    ray_vec3 lo, hi, centre;
    obj_mesh obj;
    ray_mesh mesh;
    ray_material m;
    ray_light lamp;
    ray_scene *scene;
    unsigned m_clay, m_ground;
    double diag;
    char err[600];

    if (obj_load(path, &obj, err, sizeof err) != 0) {
        fprintf(stderr, "%s\n", err);
        return NULL;
    }
    obj_bounds(&obj, &lo, &hi, &centre, &diag);
    check(ray_scene_new(&scene, NULL, NULL), "ray_scene_new");
    m = ray_material_phong(&clay);
    check(ray_scene_add_material(scene, &m, &m_clay), "material");
    m = ray_material_phong(&ground);
    check(ray_scene_add_material(scene, &m, &m_ground), "material");
    mesh = obj_as_ray_mesh(&obj);
    check(ray_scene_add_mesh(scene, &mesh, m_clay, NULL), "ray_scene_add_mesh");
    check(ray_scene_add_plane(scene, vec(0, lo.y, 0), vec(0, 1, 0), m_ground,
                              NULL), "floor");
    memset(&lamp, 0, sizeof lamp);
    lamp.kind = RAY_LIGHT_SPHERE;
    lamp.position = vec(centre.x + diag, hi.y + diag, centre.z + diag);
    lamp.radius = 0.15 * diag;
    lamp.intensity = rgb(2.2 * diag * diag, 2.2 * diag * diag, 2.2 * diag * diag);
    lamp.samples = 9;
    check(ray_scene_add_light(scene, &lamp, NULL), "light");
    check(ray_scene_set_ambient(scene, rgb(0.15, 0.15, 0.17)), "ambient");
    check(ray_scene_set_background(scene, rgb(0.55, 0.65, 0.8), NULL, NULL), "background");
    set_tree_limits(scene, prune, limits);
    check(ray_scene_commit(scene), "ray_scene_commit");
    memset(cam, 0, sizeof *cam);
    cam->position = vec(centre.x, centre.y + 0.25 * diag, centre.z + 1.3 * diag);
    cam->look_at = centre;
    cam->up = vec(0, 1, 0);
    cam->vfov = 40;
    if (triangles != NULL)
        *triangles = obj.triangle_count;
    obj_free(&obj);
    return scene;
}

/*
** A user material that scatters photons: a tinted mirror (polished brass
** or gold), reflection weighted by its colour.  Its shade callback
** traces the camera's reflection ray; its scatter callback
** (ray_scatter_fn) sends a photon on in the same direction with the same
** weight, so the light it focuses (a caustic on the floor) matches what
** the eye sees in it.
*/
static inline void tinted_mirror_shade(void *ud, ray_ctx *ctx,
                                       const ray_shade_args *a, ray_rgb *out)
{
    const ray_rgb *tint = ud;
    ray_ray r;
    ray_rgb c;
    double w = fmax(tint->r, fmax(tint->g, tint->b));

    if (ray_spawn(a->hit, ray_reflect(a->ray->dir, a->normal), &r) ==
            RAY_OK &&
        ray_trace(ctx, &r, RAY_KIND_REFLECTION, w, &c) == RAY_OK)
        *out = ray_rgb_mul(*tint, c);
}

static inline int tinted_mirror_scatter(void *ud, ray_ctx *ctx,
                                        const ray_shade_args *a,
                                        ray_vec3 *dir, ray_rgb *weight)
{
    (void)ctx;
    *dir = ray_reflect(a->ray->dir, a->normal);
    *weight = *(const ray_rgb *)ud;
    return 1;
}

/*
** The caustics scene (examples/caustics.c, bench/caustics.c): a glass
** sphere of radius 1 whose focus (a ball lens: f = n R / (2 (n - 1)) =
** 1.5 from its centre, 1.94 for a light 6.6 away) lies on the floor,
** and a ring of tinted-mirror triangles (half a cylinder of radius 2.4
** and height 1.3, 48 quads)
** standing on a diffuse floor under a small rect light.  Committed;
** fills *cam.
*/
static inline ray_scene *caustics_scene(ray_camera *cam)
{
    static const ray_phong_params floor_p = {.diffuse = {0.75, 0.73, 0.7}};
    static const ray_glass_params glass = {.ior = 1.5};
    static ray_rgb brass = {0.95, 0.75, 0.35};   /* ud: read only */
    ray_light light = {.kind = RAY_LIGHT_RECT, .position = {-2.3, 8, 0.7},
                       .edge1 = {0.6, 0, 0}, .edge2 = {0, 0, 0.6},
                       .intensity = {40, 40, 40}, .samples = 4};
    ray_camera view = {.position = {0, 5.5, 7}, .look_at = {0, 0.4, -0.4},
                       .up = {0, 1, 0}, .vfov = 42};
    ray_material m = {.shade = tinted_mirror_shade, .ud = &brass,
                      .effects = RAY_EFFECT_REFLECTION |
                                 RAY_EFFECT_SCATTER,
                      .scatter = tinted_mirror_scatter};
    ray_scene *scene;
    unsigned floor_mat, glass_mat, ring_mat;
    const double R = 2.4, h = 1.3, pi = 3.14159265358979323846;
    int i;

    check(ray_scene_new(&scene, NULL, NULL), "ray_scene_new");
    check(ray_scene_add_material(scene, &m, &ring_mat), "ring material");
    m = ray_material_phong(&floor_p);
    check(ray_scene_add_material(scene, &m, &floor_mat), "floor material");
    m = ray_material_glass(&glass);
    check(ray_scene_add_material(scene, &m, &glass_mat), "glass material");
    check(ray_scene_add_plane(scene, vec(0, 0, 0), vec(0, 1, 0), floor_mat,
                              NULL), "floor");
    check(ray_scene_add_sphere(scene, vec(0, 1.8, 0), 1.0, glass_mat, NULL),
          "glass sphere");
    /* The ring: from angle 0 (+x) over the back (-z) to pi (-x). */
    for (i = 0; i < 48; i++) {
        double a0 = pi * i / 48, a1 = pi * (i + 1) / 48;
        ray_vec3 p0 = vec(0.4 + R * cos(a0), 0, -0.6 - R * sin(a0));
        ray_vec3 p1 = vec(0.4 + R * cos(a1), 0, -0.6 - R * sin(a1));
        add_quad_triangles(scene, p0, p1, vec(p1.x, h, p1.z),
                           vec(p0.x, h, p0.z), ring_mat);
    }
    check(ray_scene_add_light(scene, &light, NULL), "light");
    check(ray_scene_set_ambient(scene, rgb(0.04, 0.04, 0.05)), "ambient");
    check(ray_scene_commit(scene), "commit");
    *cam = view;
    return scene;
}

#endif
