/* SPDX-License-Identifier: MIT */
/*
** check_defaults.c -- zero is the default (issue 37): every options
** struct a caller fills, zeroed ({0}) or given by a designated
** initializer, answers real queries and renders exactly as the defaults
** do (NULL options, or the fields set to their documented values); and
** the init functions that remain: the documented values, each struct
** accepted by the call that consumes it, and NULL a no-op.  The structs
** filled so: ray_query, ray_batch, ray_sweep, ray_shape,
** ray_render_options, ray_camera, ray_scheduler, ray_glass_params,
** ray_contains_options, ray_distance_grid_options and
** ray_image_load_options; ray_light and ray_phong_params, zeroed but for
** the colours (a colour's zero is black: ray.h), as their init functions
** give them; and ray_limits, whose zeros are all values (ray.h: depth 0
** traces no bounce), so {0} is not the defaults there but NULL is.
*/
#include <string.h>

#include "tests.h"

/* The pinhole camera that libray 0.1's camera init function made (at the
** origin, looking down -z, up +y, 60 degrees, no lens), written as a
** designated initializer with its defaults left out: a usable camera,
** byte for byte the one with every field written out. */
START_TEST(zeroed_camera_should_give_a_usable_pinhole)
{
    ray_camera c = {.look_at = {0, 0, -1}};
    ray_camera full = {.position = {0, 0, 0}, .look_at = {0, 0, -1},
                       .up = {0, 1, 0}, .vfov = 60, .aperture = 0,
                       .focus_distance = 0};
    ray_scene *s;
    ray_material m = plain();
    ray_render_options o = {.width = 4, .height = 3};
    float img[3 * 4 * 3], want[3 * 4 * 3];

    ck_assert_vec_eq(c.position, vec(0, 0, 0));
    ck_assert_vec_eq(c.look_at, vec(0, 0, -1));
    ck_assert_double_eq(c.aperture, 0);
    ck_assert_double_eq(c.focus_distance, 0);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_render(s, &full, &o, want, NULL), RAY_OK);
    ck_assert_int_eq(ray_render(s, &c, &o, img, NULL), RAY_OK);
    ck_assert_mem_eq(img, want, sizeof want);
    ray_scene_free(s);
}
END_TEST

START_TEST(light_init_should_give_every_kind_a_valid_light)
{
    int kinds[4] = {RAY_LIGHT_POINT, RAY_LIGHT_DIRECTIONAL, RAY_LIGHT_SPHERE,
                    RAY_LIGHT_RECT};
    ray_scene *s;
    int k;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    for (k = 0; k < 4; k++) {
        ray_light l;
        memset(&l, 0x7f, sizeof l);
        ray_light_init(&l, kinds[k]);
        ck_assert_int_eq(l.kind, kinds[k]);
        ck_assert_vec_eq(l.position, vec(0, 0, 0));
        ck_assert_vec_eq(l.direction, vec(0, -1, 0));
        ck_assert_vec_eq(l.edge1, vec(1, 0, 0));
        ck_assert_vec_eq(l.edge2, vec(0, 0, 1));
        ck_assert_double_eq(l.radius, 1);
        ck_assert(l.intensity.r == 1 && l.intensity.g == 1 &&
                  l.intensity.b == 1);
        ck_assert_uint_eq(l.samples, 16);
        ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    }
    ck_assert_uint_eq(ray_scene_light_count(s), 4);
    ray_scene_free(s);
    ray_light_init(NULL, RAY_LIGHT_POINT);
}
END_TEST

START_TEST(limits_mesh_and_material_params_should_init_to_defaults)
{
    ray_limits l;
    ray_mesh mesh;
    ray_phong_params p;
    ray_glass_params g = {0};
    ray_scene *s;
    ray_material m;

    memset(&l, 0x7f, sizeof l);
    ray_limits_init(&l);
    ck_assert_uint_eq(l.max_depth, RAY_DEFAULT_MAX_DEPTH);
    ck_assert_double_eq(l.min_weight, RAY_DEFAULT_MIN_WEIGHT);
    ck_assert_uint_eq(l.max_fanout, RAY_DEFAULT_MAX_FANOUT);
    ck_assert_int_eq(l.no_pruning, 0);       /* pruning on */
    memset(&mesh, 0, sizeof mesh);
    memset(&p, 0x7f, sizeof p);
    ray_phong_params_init(&p);
    ck_assert(p.diffuse.r == 0.8 && p.diffuse.g == 0.8 && p.diffuse.b == 0.8);
    ck_assert(p.specular.r == 0 && p.reflect.r == 0 && p.texture.fn == NULL);
    ck_assert_double_eq(p.shininess, 32);
    ck_assert_int_eq(p.blinn, 0);
    /* Each accepted where it is consumed; the empty mesh is refused. */
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_set_limits(s, &l), RAY_OK);
    m = ray_material_phong(&p);
    ck_assert_uint_eq(m.effects, RAY_EFFECT_SHADOW | RAY_EFFECT_CAUSTICS);
    ck_assert_int_eq(ray_scene_add_material(s, &m, NULL), RAY_OK);
    m = ray_material_glass(&g);
    ck_assert_int_eq(ray_scene_add_material(s, &m, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &mesh, 0, NULL), RAY_EINVAL);
    ray_scene_free(s);
    ray_limits_init(NULL);
    ray_phong_params_init(NULL);
}
END_TEST

/* A new scene with materials m[0 .. n - 1] (ids 0 ..) and a point light
** at (0, 5, 0), for a test's geometry. */
static ray_scene *lit_scene(const ray_material *m, unsigned n)
{
    ray_light light;
    ray_scene *s;
    unsigned i;

    ray_light_init(&light, RAY_LIGHT_POINT);
    light.position = vec(0, 5, 0);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    for (i = 0; i < n; i++)
        ck_assert_int_eq(ray_scene_add_material(s, &m[i], NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_light(s, &light, NULL), RAY_OK);
    return s;
}

/* Commit s, render it with cam and o into img, and free it. */
static void render_and_free(ray_scene *s, const ray_camera *cam,
                            const ray_render_options *o, float *img)
{
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_render(s, cam, o, img, NULL), RAY_OK);
    ray_scene_free(s);
}

/* A glass sphere of the given params in front of a lit grey triangle,
** rendered W x H from the origin down -z. */
static void render_glass(const ray_glass_params *g, float *img,
                         unsigned w, unsigned h)
{
    static ray_phong_params grey;
    static const ray_vec3 tri[3] = {{-6, -6, -8}, {6, -6, -8}, {0, 6, -8}};
    static const unsigned idx[3] = {0, 1, 2};
    ray_mesh mesh = {.vertices = tri, .vertex_count = 3, .indices = idx,
                     .triangle_count = 1};
    ray_camera cam = {.look_at = {0, 0, -1}};
    ray_render_options o = {.width = w, .height = h};
    ray_material m[2];
    ray_scene *s;

    ray_phong_params_init(&grey);
    m[0] = ray_material_phong(&grey);
    m[1] = ray_material_glass(g);
    s = lit_scene(m, 2);
    ck_assert_int_eq(ray_scene_add_mesh(s, &mesh, 0, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, -4), 1.5, 1, NULL),
                     RAY_OK);
    render_and_free(s, &cam, &o, img);
}

/*
** A zeroed ray_glass_params is window glass (issue 37: ior 0 is 1.5, so
** the struct needs no init function): the bytes of { .ior = 1.5 } with
** no absorption, and not those of water (1.33), so that the sphere bends
** what is seen through it.
*/
START_TEST(zeroed_glass_params_should_be_window_glass)
{
    enum { W = 12, H = 9 };
    static float want[3 * W * H], got[3 * W * H], water[3 * W * H];
    const ray_glass_params zero = {0}, window = {.ior = 1.5},
                           wet = {.ior = 1.33};

    render_glass(&window, want, W, H);
    render_glass(&zero, got, W, H);
    render_glass(&wet, water, W, H);
    ck_assert_mem_eq(got, want, sizeof want);
    ck_assert(memcmp(water, want, sizeof want) != 0);
}
END_TEST

/* A lit plane under the camera with a checkerboard of scale "scale"
** (red and blue Lambertian squares), rendered W x H. */
static void render_checker(double scale, float *img, unsigned w, unsigned h)
{
    static ray_phong_params red, blue;
    ray_checker_params cp = {.scale = scale};
    ray_camera cam = {.position = {0, 3, 0}, .look_at = {0, 0, -6}};
    ray_render_options o = {.width = w, .height = h};
    ray_material m;
    ray_scene *s;

    red.diffuse = ray_rgb_make(0.8, 0.1, 0.1);
    blue.diffuse = ray_rgb_make(0.1, 0.1, 0.8);
    cp.even = ray_material_phong(&red);
    cp.odd = ray_material_phong(&blue);
    m = ray_material_checker(&cp);
    s = lit_scene(&m, 1);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, -1, 0), vec(0, 1, 0), 0,
                                         NULL), RAY_OK);
    render_and_free(s, &cam, &o, img);
}

/* A zeroed ray_checker_params' scale is 1 (issue 37: 0 gave one square,
** every hit the even material): the bytes of scale 1, not those of 2,
** and both colours on screen. */
START_TEST(zeroed_checker_scale_should_be_one)
{
    enum { W = 16, H = 12 };
    static float want[3 * W * H], got[3 * W * H], fine[3 * W * H];
    int k, reds = 0, blues = 0;

    render_checker(1, want, W, H);
    render_checker(0, got, W, H);
    render_checker(2, fine, W, H);
    ck_assert_mem_eq(got, want, sizeof want);
    ck_assert(memcmp(fine, want, sizeof want) != 0);
    for (k = 0; k < W * H; k++) {
        reds += got[3 * k] > 2 * got[3 * k + 2];
        blues += got[3 * k + 2] > 2 * got[3 * k];
    }
    ck_assert_int_gt(reds, 0);
    ck_assert_int_gt(blues, 0);
}
END_TEST

/* A square's colour as the checker's shade callback paints it: the even
** square writes 1 into red, the odd one 1 into blue. */
static void paint_even(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                       ray_rgb *out)
{
    (void)ud, (void)ctx, (void)a;
    out->r = 1;
}

static void paint_odd(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                      ray_rgb *out)
{
    (void)ud, (void)ctx, (void)a;
    out->b = 1;
}

/* Does the checker put (u, v) on an odd square? */
static int checker_says_odd(const ray_material *m, double u, double v)
{
    ray_shade_args a;
    ray_rgb out = {0, 0, 0};

    memset(&a, 0, sizeof a);
    a.u = u;
    a.v = v;
    m->shade(m->ud, NULL, &a, &out);
    ck_assert(out.r + out.b == 1);       /* exactly one square painted */
    return out.b == 1;
}

/* The checker's square: odd where floor(u) + floor(v) is (issue 35 reads
** the parity from an integer below 2^52 instead of libm's fmod), fmod's
** answer at the edges: around 2^52 and 2^53 (where the sum rounds),
** negative cells, -0, an infinity and a NaN (fmod's NaN: even). */
START_TEST(checker_should_pick_the_square_of_the_floors_sum)
{
    static const struct {
        double u, v;
        int odd;
    } cases[] = {
        {0.5, 0.5, 0}, {1.5, 0.5, 1}, {1.5, 1.5, 0}, {-0.5, 0.25, 1},
        {-1.5, -0.5, 1}, {-0.0, 0.0, 0}, {-2.5, 0.0, 1},
        {0x1p52 - 0.5, 0, 1}, {0x1p52 - 1.5, 0, 0}, {0x1p52, 0, 0},
        {0x1p52 + 1, 0, 1}, {-0x1p52 - 1, 0, 1}, {0x1p53, 1, 0},
        {0x1p52, 0x1p52 - 0.5, 1}, {1e300, 0.5, 0}, {HUGE_VAL, 0, 0},
        {-HUGE_VAL, 0, 0}, {(double)NAN, 0.5, 0}};
    static ray_checker_params cp;
    ray_material m;
    size_t i;

    cp.even.shade = paint_even;
    cp.odd.shade = paint_odd;
    cp.scale = 1;
    m = ray_material_checker(&cp);
    for (i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        double cell = floor(cases[i].u) + floor(cases[i].v);
        /* The listed answer is fmod's, the formula the pick replaced. */
        ck_assert_int_eq(fabs(fmod(cell, 2.0)) == 1.0, cases[i].odd);
        ck_assert_int_eq(checker_says_odd(&m, cases[i].u, cases[i].v),
                         cases[i].odd);
    }
}
END_TEST

/* ----------------------------------------------- zero is the default */

/* A sphere, a triangle in front of it and a box, a light: every query
** below has something to find, and the render something to shade. */
static ray_scene *zero_scene(void)
{
    static ray_phong_params grey;
    static const ray_vec3 tri[3] = {{-1, -1, -3}, {1, -1, -3}, {0, 1, -3}};
    static const unsigned idx[3] = {0, 1, 2};
    ray_mesh mesh = {.vertices = tri, .vertex_count = 3, .indices = idx,
                     .triangle_count = 1};
    ray_box_params box = {.center = {3, 0, -5}, .half_extents = {1, 1, 1},
                          .axis_x = {1, 0, 0}, .axis_y = {0, 1, 0}};
    ray_light light;
    ray_material m;
    ray_scene *s;

    ray_phong_params_init(&grey);
    m = ray_material_phong(&grey);
    ray_light_init(&light, RAY_LIGHT_POINT);
    light.position = vec(0, 5, 0);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_light(s, &light, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, -6), 1, 0, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &mesh, 0, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_box(s, &box, 0, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_set_ambient(s, ray_rgb_make(0.1, 0.1, 0.1)),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    return s;
}

static int counting(void *ud, const ray_overlap *found)
{
    (void)found;
    ++*(int *)ud;
    return 0;
}

/*
** ray_query {0} and { .query_ud = me } (0.1's trap: a zero mask that saw
** nothing) answer every ray, batch, sweep and overlap query as NULL
** options and the plain queries do, bit for bit; ignoring a bit the
** geometry has alone still hides it (the mask is not ignored).
*/
START_TEST(zeroed_query_and_batch_should_see_everything)
{
    ray_scene *s = zero_scene();
    int me = 7, k;
    ray_query zero = {0}, named = {.query_ud = &me};
    ray_query hide = {.ignore_mask = ~0u};
    const ray_query *qs[3] = {NULL, &zero, &named};
    ray_ray rays[4];
    ray_hit want[4], got[4];
    int res_want[4], res_got[4];
    size_t total_want, total;
    ray_hit all[8];

    rays[0] = ray_from(vec(0, 0, 0), vec(0, 0, -1));      /* triangle */
    rays[1] = ray_from(vec(0, 1.5, 0), vec(0, -0.25, -1)); /* sphere */
    rays[2] = ray_from(vec(3, 0, 0), vec(0, 0, -1));      /* box */
    rays[3] = ray_from(vec(0, 0, 0), vec(0, 0, 1));       /* nothing */
    for (k = 0; k < 4; k++) {
        hit_poison(&want[k]);
        res_want[k] = ray_intersect(s, &rays[k], &want[k], NULL);
    }
    ck_assert_int_eq(res_want[0] + res_want[1] + res_want[2] + res_want[3],
                     3);
    ck_assert_int_eq(ray_intersect_all(s, &rays[0], NULL, all, 8,
                                       &total_want), 3);
    for (k = 0; k < 3; k++) {
        int i, n = 0;
        ray_batch b = {.rays = rays, .n = 4, .hits = got,
                       .results = res_got};
        ray_contact c0, c1;
        ray_sweep sw = {.shape = {.radius = 0.5},
                        .dir = {0, 0, -4}};       /* tmax 0: the whole move */
        ray_sweep full = sw;

        for (i = 0; i < 4; i++) {
            ray_hit h;
            hit_poison(&h);
            ck_assert_int_eq(ray_intersect(s, &rays[i], &h, qs[k]),
                             res_want[i]);
            ck_assert_int_eq(ray_occluded(s, &rays[i], qs[k]),
                             res_want[i]);
            if (res_want[i] == 1)
                ck_assert(hit_same(&h, &want[i]));
        }
        ck_assert_int_eq(ray_intersect_all(s, &rays[0], qs[k], all, 8,
                                           &total), 3);
        ck_assert_uint_eq(total, total_want);
        /* One query for all (ray_batch.query), and each ray its own
        ** (ray_batch.queries, NULL here: the defaults). */
        ck_assert_int_eq(ray_intersect_batch(s, &(ray_batch){.rays = rays,
                                                             .n = 4,
                                                             .hits = got,
                                                             .results = res_got,
                                                             .query = qs[k]}),
                         RAY_OK);
        ck_assert_mem_eq(res_got, res_want, sizeof res_want);
        ck_assert_int_eq(ray_intersect_batch(s, &b), RAY_OK);
        ck_assert_mem_eq(res_got, res_want, sizeof res_want);
        for (i = 0; i < 4; i++)
            if (res_want[i] == 1)
                ck_assert(hit_same(&got[i], &want[i]));
        /* Sweeps: tmax 0 is the whole motion, tmin 0..tmax 1. */
        full.tmax = 1;
        ck_assert_int_eq(ray_intersect_sweep(s, &sw, qs[k], &c0), 1);
        ck_assert_int_eq(ray_intersect_sweep(s, &full, NULL, &c1), 1);
        ck_assert_mem_eq(&c0, &c1, sizeof c0);
        ck_assert_double_eq_tol(c0.t, (3 - 0.5) / 4, 1e-12);
        /* Overlaps: everything within 10 of the origin. */
        ck_assert_int_eq(ray_overlap_shape(s, TK_SPHERE(vec(0, 0, -4), 10), qs[k],
                                            counting, &n), 3);
        ck_assert_int_eq(n, 3);
        /* A shape by designated initializer (kind 0: a sphere when a ==
        ** b) is the sphere written out; {0} the point at the origin. */
        {
            ray_shape ball = {.a = {0, 0, -4}, .b = {0, 0, -4}, .radius = 10};
            ray_shape zero_shape = {0};
            ray_overlap f0[4], f1[4];
            size_t n0, n1;
            ck_assert_int_eq(ray_overlap_shape_all(s, &ball, qs[k], f0, 4, &n0), 3);
            ck_assert_int_eq(ray_overlap_shape_all(s, TK_SPHERE(vec(0, 0, -4), 10), NULL, f1, 4, &n1), 3);
            ck_assert_mem_eq(f0, f1, 3 * sizeof f0[0]);
            ck_assert_int_eq(ray_overlap_shape_all(s, &zero_shape, qs[k], f0, 4, &n0),
                             ray_overlap_shape_all(s, TK_SPHERE(vec(0, 0, 0), 0), NULL, f1, 4, &n1));
            ck_assert_uint_eq(n0, n1);
            ck_assert_mem_eq(f0, f1, n0 * sizeof f0[0]);
        }
    }
    {
        /* Each ray its own zeroed query, in a batch. */
        ray_query per[4] = {{0}, {.query_ud = &me}, {0}, {0}};
        ray_batch b = {.rays = rays, .queries = per, .n = 4, .hits = got,
                       .results = res_got};
        ck_assert_int_eq(ray_intersect_batch(s, &b), RAY_OK);
        ck_assert_mem_eq(res_got, res_want, sizeof res_want);
        ck_assert_int_eq(ray_occluded_batch(s, &b), RAY_OK);
        ck_assert_mem_eq(res_got, res_want, sizeof res_want);
    }
    /* Ignoring every bit hides everything: the mask is still read. */
    for (k = 0; k < 4; k++)
        ck_assert_int_eq(ray_occluded(s, &rays[k], &hide), 0);
    ray_scene_free(s);
}
END_TEST

/*
** The options reach ray_intersect and ray_occluded on a scene of
** triangles alone without masks or filters, which a NULL q sends straight
** to the triangle walk (issue 34's fast path): a zeroed or named query
** answers as NULL, bit for bit, and a query ignoring every bit hides the
** mesh (a miss, *hit untouched), so the fast path never swallows options.
*/
START_TEST(query_options_should_reach_the_triangles_fast_path)
{
    static const unsigned idx[6] = {0, 1, 2, 0, 2, 3};
    ray_vec3 v[4] = {{-1, -1, -2}, {1, -1, -2}, {1, 1, -2}, {-1, 1, -2}};
    ray_mesh m = {0};
    ray_scene *s;
    int me = 7, k;
    ray_query zero = {0}, named = {.query_ud = &me};
    ray_query hide = {.ignore_mask = ~0u};
    const ray_query *qs[3] = {NULL, &zero, &named};
    ray_ray r = ray_from(vec(0.25, 0.125, 0), vec(0, 0, -1));
    ray_hit want, h;

    m.vertices = v;
    m.vertex_count = 4;
    m.indices = idx;
    m.triangle_count = 2;
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    hit_poison(&want);
    ck_assert_int_eq(ray_intersect(s, &r, &want, NULL), 1);
    ck_assert_double_eq_tol(want.t, 2, 1e-15);   /* the plane z = -2 */
    for (k = 0; k < 3; k++) {
        hit_poison(&h);
        ck_assert_int_eq(ray_intersect(s, &r, &h, qs[k]), 1);
        ck_assert(hit_same(&h, &want));
        ck_assert_int_eq(ray_occluded(s, &r, qs[k]), 1);
    }
    hit_poison(&h);
    ck_assert_int_eq(ray_intersect(s, &r, &h, &hide), 0);
    ck_assert(hit_is_poisoned(&h));
    ck_assert_int_eq(ray_occluded(s, &r, &hide), 0);
    /* Misuse is the same with options as without. */
    ck_assert_int_eq(ray_intersect(s, NULL, &h, &zero), -RAY_EINVAL);
    ck_assert_int_eq(ray_intersect(s, &r, NULL, &zero), -RAY_EINVAL);
    ck_assert_int_eq(ray_occluded(NULL, &r, &zero), -RAY_EINVAL);
    ray_scene_free(s);
}
END_TEST

/*
** ray_render_options { .width, .height } and a camera { .position,
** .look_at } render the bytes of the documented defaults written out
** (samples 1, adaptive depth 2, cones on; up +y, vfov 60), and so do
** structs zeroed by memset and filled field by field (what the init
** functions that left the API in issue 37 did); a zeroed scheduler is the
** built-in threads.
*/
START_TEST(zeroed_render_options_and_camera_should_render_the_defaults)
{
    enum { W = 12, H = 9 };
    static float want[3 * W * H], got[3 * W * H];
    ray_scene *s = zero_scene();
    ray_camera explicit_cam = {.position = {0, 0, 2}, .look_at = {0, 0, -1},
                               .up = {0, 1, 0}, .vfov = 60};
    ray_camera cam = {.position = {0, 0, 2}, .look_at = {0, 0, -1}};
    ray_camera init_cam;
    ray_render_options explicit_o = {.width = W, .height = H, .samples = 1,
                                     .adaptive_depth = 2, .no_cones = 0};
    ray_render_options o = {.width = W, .height = H}, init_o;
    ray_scheduler zero_sched = {0};
    char msg[160];

    ck_assert_int_eq(ray_render(s, &explicit_cam, &explicit_o, want, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_render_check(s, &cam, &o, NULL, msg, sizeof msg), RAY_OK);
    ck_assert_str_eq(msg, "");
    ck_assert_int_eq(ray_render(s, &cam, &o, got, NULL), RAY_OK);
    ck_assert_mem_eq(got, want, sizeof want);
    memset(&init_cam, 0, sizeof init_cam);
    init_cam.position = cam.position;
    init_cam.look_at = cam.look_at;
    memset(&init_o, 0, sizeof init_o);
    init_o.width = W;
    init_o.height = H;
    ck_assert_int_eq(ray_render(s, &init_cam, &init_o, got, NULL), RAY_OK);
    ck_assert_mem_eq(got, want, sizeof want);
    /* Not a blank image: the defaults render something. */
    ck_assert(want[3 * (H / 2 * W + W / 2)] > 0.05f);
    /* Adaptive antialiasing: depth 0 is depth 2. */
    explicit_o.adaptive_threshold = o.adaptive_threshold = 0.05;
    ck_assert_int_eq(ray_render(s, &explicit_cam, &explicit_o, want, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_render(s, &cam, &o, got, NULL), RAY_OK);
    ck_assert_mem_eq(got, want, sizeof want);
    /* A zeroed scheduler in the options and in the scene. */
    o.scheduler = &zero_sched;
    ck_assert_int_eq(ray_render(s, &cam, &o, got, NULL), RAY_OK);
    ck_assert_mem_eq(got, want, sizeof want);
    ck_assert_int_eq(ray_scene_set_scheduler(s, &zero_sched), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_render(s, &cam, &o, got, NULL), RAY_OK);
    ck_assert_mem_eq(got, want, sizeof want);
    /* Hard cases: the limits stay checked after the defaults. */
    o.adaptive_depth = 9;
    ck_assert_int_eq(ray_render(s, &cam, &o, got, NULL), RAY_EINVAL);
    o.adaptive_depth = 0;
    o.samples = RAY_MAX_PIXEL_SAMPLES + 1;
    ck_assert_int_eq(ray_render(s, &cam, &o, got, NULL), RAY_EINVAL);
    o.samples = 0;
    cam.look_at = cam.position;          /* no default for these two */
    ck_assert_int_eq(ray_render(s, &cam, &o, got, NULL), RAY_EINVAL);
    ray_scene_free(s);
}
END_TEST

/* ray_contains_options and ray_distance_grid_options zeroed, by {0} and
** by designated initializers: NULL's answers, to the bit. */
START_TEST(zeroed_contains_and_grid_options_should_be_null)
{
    ray_scene *s = zero_scene();
    ray_vec3 pts[3] = {{0, 0, -6}, {3, 0.5, -5}, {0, 0, 0}};
    ray_inside a[3], b[3];
    ray_contains_options zero = {0}, named = {.flags = 0};
    ray_distance_grid_options gzero = {0}, gnamed = {.threads = 0};
    float ga[4 * 3 * 2], gb[4 * 3 * 2];

    ck_assert_int_eq(ray_contains(s, pts, 3, NULL, a), 2);
    ck_assert_int_eq(ray_contains(s, pts, 3, &zero, b), 2);
    ck_assert_mem_eq(a, b, sizeof a);
    ck_assert_int_eq(ray_contains(s, pts, 3, &named, b), 2);
    ck_assert_mem_eq(a, b, sizeof a);
    ck_assert_int_eq(ray_distance_grid(s, vec(-2, -2, -8), vec(4, 2, -2), 4,
                                       3, 2, NULL, ga), RAY_OK);
    ck_assert_int_eq(ray_distance_grid(s, vec(-2, -2, -8), vec(4, 2, -2), 4,
                                       3, 2, &gzero, gb), RAY_OK);
    ck_assert_mem_eq(ga, gb, sizeof ga);
    ck_assert_int_eq(ray_distance_grid(s, vec(-2, -2, -8), vec(4, 2, -2), 4,
                                       3, 2, &gnamed, gb), RAY_OK);
    ck_assert_mem_eq(ga, gb, sizeof ga);
    ray_scene_free(s);
}
END_TEST

/*
** ray_sweep {0} and a zero-motion sweep by designated initializer answer
** as the same sweeps written out (tmin 0, tmax 1): {0} is a point at the
** origin, where zero_scene has nothing, tested for overlap; a ball of
** radius 0.5 half a unit above the centre of zero_scene's unit sphere
** overlaps it, and is freed by moving it 1 = 1 - 0.5 + 0.5 along +y.
*/
START_TEST(zeroed_sweep_should_be_the_overlap_test_written_out)
{
    ray_scene *s = zero_scene();
    ray_sweep zero = {0};
    ray_sweep zero_full = {.shape = {.a = {0, 0, 0}, .b = {0, 0, 0},
                                     .radius = 0},
                           .dir = {0, 0, 0}, .tmin = 0, .tmax = 1};
    ray_sweep in = {.shape = {.a = {0, 0.5, -6}, .b = {0, 0.5, -6},
                              .radius = 0.5}};
    ray_sweep in_full = in;
    ray_contact c0, c1;

    in_full.tmax = 1;
    memset(&c0, 0x5a, sizeof c0);
    ck_assert_int_eq(ray_intersect_sweep(s, &zero, NULL, &c0), 0);
    ck_assert_int_eq(ray_intersect_sweep(s, &zero_full, NULL, &c0), 0);
    memset(&c0, 0, sizeof c0);
    memset(&c1, 0, sizeof c1);
    ck_assert_int_eq(ray_intersect_sweep(s, &in, NULL, &c0), 1);
    ck_assert_int_eq(ray_intersect_sweep(s, &in_full, NULL, &c1), 1);
    ck_assert_mem_eq(&c0, &c1, sizeof c0);
    ck_assert_uint_eq(c0.geom_id, 0);                  /* the sphere */
    ck_assert(c0.flags & RAY_CONTACT_OVERLAP);
    ck_assert_double_eq(c0.t, 0);
    /* Sphere against sphere in closed form: a few ulps of the inputs. */
    ck_assert_double_eq_tol(c0.depth, 1, 1e-12);
    ck_assert_double_eq_tol(c0.n.y, 1, 1e-12);
    ray_scene_free(s);
}
END_TEST

/*
** ray_batch {0} asks for no rays: RAY_OK from both batch calls, nothing
** read or written (its NULL arrays are allowed with n 0); a ray_render_options
** {0} has no size, which has no default: refused, as is a camera {0},
** whose look_at is its position.
*/
START_TEST(zeroed_batch_and_render_options_should_ask_for_nothing)
{
    ray_scene *s = zero_scene();
    ray_batch none = {0};
    ray_render_options o = {0}, sized = {.width = 2, .height = 2};
    ray_camera cam = {.look_at = {0, 0, -1}}, zero_cam = {0};
    float img[3 * 2 * 2];

    ck_assert_int_eq(ray_intersect_batch(s, &none), RAY_OK);
    ck_assert_int_eq(ray_occluded_batch(s, &none), RAY_OK);
    ck_assert_int_eq(ray_render(s, &cam, &o, img, NULL), RAY_EINVAL);
    ck_assert_int_eq(ray_render(s, &zero_cam, &sized, img, NULL),
                     RAY_EINVAL);
    ck_assert_int_eq(ray_render(s, &cam, &sized, img, NULL), RAY_OK);
    ray_scene_free(s);
}
END_TEST

/*
** ray_image_load_options {0} and by designated initializer with its
** zeros (each 0: the documented default limit) load doc/cornell.png as
** NULL options do, to the pixel; a limit set below the picture's width
** is read (RAY_ELIMIT).  Without libpng every load is RAY_ENOTSUP alike.
*/
START_TEST(zeroed_load_options_should_be_the_default_limits)
{
    const char *path = "doc/cornell.png";
    ray_image_load_options zero = {0}, named = {.max_width = 0,
                                                .max_chunk_bytes = 0};
    ray_image_load_options tiny = {.max_width = 1};
    const ray_image_load_options *opts[2] = {&zero, &named};
    ray_image *want = NULL, *got = NULL;
    unsigned w = 0, h = 0, w2 = 0, h2 = 0;
    int k, i;

#if RAY_TEST_PNG
    ck_assert_int_eq(ray_image_load_png(path, NULL, &want), RAY_OK);
    ray_image_size(want, &w, &h);
    ck_assert_uint_gt(w, 1);
    ck_assert_uint_gt(h, 0);
    for (k = 0; k < 2; k++) {
        ck_assert_int_eq(ray_image_load_png(path, opts[k], &got), RAY_OK);
        ray_image_size(got, &w2, &h2);
        ck_assert_uint_eq(w2, w);
        ck_assert_uint_eq(h2, h);
        for (i = 0; i < 5; i++) {
            /* Texel centres along the diagonal: the stored pixels, bit
            ** for bit, as both images hold the same file. */
            double st = (i + 0.5) / 5;
            ray_rgb a, b;
            ck_assert_int_eq(ray_image_sample(want, st, st, 0, &a), RAY_OK);
            ck_assert_int_eq(ray_image_sample(got, st, st, 0, &b), RAY_OK);
            ck_assert(a.r == b.r && a.g == b.g && a.b == b.b);
        }
        ray_image_free(got);
        got = NULL;
    }
    ck_assert_int_eq(ray_image_load_png(path, &tiny, &got), RAY_ELIMIT);
    ck_assert_ptr_null(got);
    ray_image_free(want);
#else
    (void)w; (void)h; (void)w2; (void)h2; (void)i; (void)want;
    ck_assert_int_eq(ray_image_load_png(path, NULL, &got), RAY_ENOTSUP);
    for (k = 0; k < 2; k++)
        ck_assert_int_eq(ray_image_load_png(path, opts[k], &got),
                         RAY_ENOTSUP);
    ck_assert_int_eq(ray_image_load_png(path, &tiny, &got), RAY_ENOTSUP);
    ck_assert_ptr_null(got);
#endif
}
END_TEST

/* ------------------------------------ lights, surfaces, limits */

enum { LW = 12, LH = 9 };

/*
** A sphere (material "sphere") over a floor (grey), lit by *light alone,
** with *limits (NULL: the defaults), seen LW x LH from above the floor;
** the counters in *st.
*/
static void render_lit(const ray_light *light,
                       const ray_phong_params *sphere,
                       const ray_limits *limits, float *img, ray_stats *st)
{
    static ray_phong_params grey;
    static const ray_vec3 floor_v[3] = {{-20, -1, 5}, {20, -1, 5},
                                        {0, -1, -40}};
    static const unsigned idx[3] = {0, 1, 2};
    ray_mesh mesh = {.vertices = floor_v, .vertex_count = 3, .indices = idx,
                     .triangle_count = 1};
    ray_camera cam = {.position = {0, 0.5, 2}, .look_at = {0, -0.5, -5}};
    ray_render_options o = {.width = LW, .height = LH};
    ray_material m[2];
    ray_scene *s;

    ray_phong_params_init(&grey);
    m[0] = ray_material_phong(&grey);
    m[1] = ray_material_phong(sphere);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m[0], NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m[1], NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_light(s, light, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &mesh, 0, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 0, -5), 1, 1, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_set_limits(s, limits), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_render(s, &cam, &o, img, st), RAY_OK);
    ray_scene_free(s);
}

/* The largest channel of the image.  The tests ask for more than 0.05
** where a light must reach the floor: the grey floor (0.8) under
** intensity 20 from about 5 away is lit near 0.8 * 20 / 25 = 0.6, so
** 0.05 tells lit from black (0) with a margin of ten either way. */
static float brightest(const float *img, size_t n)
{
    float most = 0;
    size_t i;

    for (i = 0; i < n; i++)
        if (img[i] > most)
            most = img[i];
    return most;
}

static ray_phong_params grey_sphere(void)
{
    ray_phong_params p;

    ray_phong_params_init(&p);
    return p;
}

/*
** Every kind of light with only its kind, position and intensity given
** (a zero direction, radius and edges: their defaults, 1.0) renders the
** bytes of ray_light_init's light with the same three fields, and lights
** the scene; a rect light with one edge given takes the other's default.
*/
START_TEST(zeroed_lights_should_be_the_init_lights)
{
    static const int kinds[4] = {RAY_LIGHT_POINT, RAY_LIGHT_DIRECTIONAL,
                                 RAY_LIGHT_SPHERE, RAY_LIGHT_RECT};
    static float want[3 * LW * LH], got[3 * LW * LH];
    const ray_phong_params sphere = grey_sphere();
    ray_light init, zero;
    int k;

    for (k = 0; k < 4; k++) {
        ray_light_init(&init, kinds[k]);
        init.position = vec(0.5, 4, -3);
        init.intensity = rgb(20, 20, 20);
        zero = (ray_light){.kind = kinds[k], .position = {0.5, 4, -3},
                           .intensity = {20, 20, 20}};
        render_lit(&init, &sphere, NULL, want, NULL);
        render_lit(&zero, &sphere, NULL, got, NULL);
        ck_assert_mem_eq(got, want, sizeof want);
        ck_assert_msg(brightest(want, 3 * LW * LH) > 0.05f,
                      "light kind %d lights nothing", kinds[k]);
    }
    /* Hard case: one edge given, the other zero; and -0 is zero. */
    init.edge1 = zero.edge1 = vec(2, 0, 0);
    zero.edge2 = vec(-0.0, 0, -0.0);
    render_lit(&init, &sphere, NULL, want, NULL);
    render_lit(&zero, &sphere, NULL, got, NULL);
    ck_assert_mem_eq(got, want, sizeof want);
}
END_TEST

/*
** A Phong surface with a specular colour and no shininess is lit with
** RAY_DEFAULT_SHININESS's lobe, as ray_phong_params_init's exponent; a
** highlight that an exponent of 1 draws differently (so the lobe is
** there to see).
*/
START_TEST(zeroed_shininess_should_be_the_default_lobe)
{
    static float want[3 * LW * LH], got[3 * LW * LH], wide[3 * LW * LH];
    const ray_phong_params zero = {.diffuse = {0.4, 0.4, 0.4},
                                   .specular = {0.6, 0.6, 0.6}};
    ray_phong_params named = zero, dull = zero, init = grey_sphere();
    ray_light light;

    ck_assert_double_eq(init.shininess, RAY_DEFAULT_SHININESS);
    named.shininess = RAY_DEFAULT_SHININESS;
    dull.shininess = 1;
    ray_light_init(&light, RAY_LIGHT_POINT);
    light.position = vec(0.5, 4, -3);
    light.intensity = rgb(20, 20, 20);
    render_lit(&light, &named, NULL, want, NULL);
    render_lit(&light, &zero, NULL, got, NULL);
    render_lit(&light, &dull, NULL, wide, NULL);
    ck_assert_mem_eq(got, want, sizeof want);
    ck_assert(memcmp(wide, want, sizeof want) != 0);
}
END_TEST

/*
** ray_limits keeps its zeros as values (ray.h): {0} traces no bounce (a
** mirror shows nothing, every reflection cut by depth), NULL and
** ray_limits_init the defaults (the mirror reflects), the same bytes.
*/
START_TEST(zeroed_limits_should_be_values_and_null_the_defaults)
{
    static float want[3 * LW * LH], got[3 * LW * LH], flat[3 * LW * LH];
    ray_phong_params mirror = grey_sphere();
    const ray_limits zero = {0};
    ray_limits init;
    ray_light light;
    ray_stats a, b, c;

    mirror.reflect = rgb(0.8, 0.8, 0.8);
    ray_limits_init(&init);
    ray_light_init(&light, RAY_LIGHT_POINT);
    light.position = vec(0.5, 4, -3);
    light.intensity = rgb(20, 20, 20);
    render_lit(&light, &mirror, NULL, want, &a);
    render_lit(&light, &mirror, &init, got, &b);
    render_lit(&light, &mirror, &zero, flat, &c);
    ck_assert_mem_eq(got, want, sizeof want);
    ck_assert_uint_gt(a.rays[RAY_KIND_REFLECTION], 0);
    ck_assert_uint_eq(c.rays[RAY_KIND_REFLECTION], 0);
    ck_assert_uint_gt(c.cut_depth, 0);
    ck_assert(memcmp(flat, want, sizeof want) != 0);
}
END_TEST

Suite *defaults_suite(void)
{
    Suite *s = suite_create("defaults");
    TCase *tc = tcase_create("init");

    tcase_add_test(tc, zeroed_camera_should_give_a_usable_pinhole);
    tcase_add_test(tc, light_init_should_give_every_kind_a_valid_light);
    tcase_add_test(tc, limits_mesh_and_material_params_should_init_to_defaults);
    tcase_add_test(tc, zeroed_glass_params_should_be_window_glass);
    tcase_add_test(tc, zeroed_checker_scale_should_be_one);
    tcase_add_test(tc, checker_should_pick_the_square_of_the_floors_sum);
    suite_add_tcase(s, tc);
    tc = tcase_create("zero");
    tcase_add_test(tc, zeroed_query_and_batch_should_see_everything);
    tcase_add_test(tc, query_options_should_reach_the_triangles_fast_path);
    tcase_add_test(tc, zeroed_render_options_and_camera_should_render_the_defaults);
    tcase_add_test(tc, zeroed_contains_and_grid_options_should_be_null);
    tcase_add_test(tc, zeroed_sweep_should_be_the_overlap_test_written_out);
    tcase_add_test(tc, zeroed_batch_and_render_options_should_ask_for_nothing);
    tcase_add_test(tc, zeroed_load_options_should_be_the_default_limits);
    tcase_add_test(tc, zeroed_lights_should_be_the_init_lights);
    tcase_add_test(tc, zeroed_shininess_should_be_the_default_lobe);
    tcase_add_test(tc, zeroed_limits_should_be_values_and_null_the_defaults);
    suite_add_tcase(s, tc);
    return s;
}
