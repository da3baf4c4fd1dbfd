/* SPDX-License-Identifier: MIT */
/*
** check_direct.c -- ray_shade_direct against the loop it replaces (the
** same bits, for every kind of light), its pruning and effect rules
** (proved by the shadow-ray counters), its argument checks, and the
** static inline vector and colour helpers of ray.h.
*/
#include <stdlib.h>

#include "tests.h"

#define W 24
#define H 18

/* ---------------------------------------------------------------- scenes */

/*
** Light set "which": 0 point, 1 directional, 2 sphere (9 samples),
** 3 rect (25 samples, more than direct.c's batch of 16; emitting
** downward), 4 all four.  Every light sits above the floor, to one side,
** so the ball casts a shadow on it.
*/
static void add_lights(ray_scene *s, int which)
{
    int k;

    for (k = 0; k < 4; k++) {
        ray_light l;

        if (which != 4 && which != k)
            continue;
        ray_light_init(&l, k == 0   ? RAY_LIGHT_POINT
                           : k == 1 ? RAY_LIGHT_DIRECTIONAL
                           : k == 2 ? RAY_LIGHT_SPHERE
                                    : RAY_LIGHT_RECT);
        l.position = vec(1.5 - k, 4, 0.5 * k);
        l.direction = vec(-0.3, -1, -0.2);
        l.radius = 0.5;
        l.samples = k == 2 ? 9 : 25;
        l.intensity = rgb(6, 5, 4);
        ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    }
}

/* The default tree limits in the naive mode (ray_limits.no_pruning). */
static const ray_limits naive_limits = {.max_depth = RAY_DEFAULT_MAX_DEPTH,
                                        .min_weight = RAY_DEFAULT_MIN_WEIGHT,
                                        .max_fanout = RAY_DEFAULT_MAX_FANOUT,
                                        .no_pruning = 1};

/* An octahedron of "radius" r about c, eight triangles of material mat:
** a blocker whose shadow rays walk a triangle BVH (the packets'). */
static void add_octahedron(ray_scene *s, ray_vec3 c, double r, unsigned mat)
{
    static const unsigned idx[24] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4,
                                     2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
    ray_vec3 v[6];
    ray_mesh m;

    v[0] = vec(c.x + r, c.y, c.z), v[1] = vec(c.x - r, c.y, c.z);
    v[2] = vec(c.x, c.y, c.z + r), v[3] = vec(c.x, c.y, c.z - r);
    v[4] = vec(c.x, c.y + r, c.z), v[5] = vec(c.x, c.y - r, c.z);
    memset(&m, 0, sizeof m);
    m.vertices = v;
    m.vertex_count = 6;
    m.indices = idx;
    m.triangle_count = 8;
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, mat, NULL), RAY_OK);
}

/* A floor and a ball of material "m" (a sphere; with "mesh" 1 an
** octahedron of triangles; with 2 the sphere and four more out of sight,
** too many spheres for the packets) under light set "which", seen from
** above at an angle, rendered at W x H, one sample a pixel, 2 threads. */
static ray_stats render_scene_of(const ray_material *m, int which, int prune,
                                 int mesh, float *img)
{
    int k;
    ray_render_options o;
    ray_camera cam;
    ray_scene *s;
    ray_stats st;
    unsigned mat;

    cam = (ray_camera){.look_at = {0, 0, -1}};
    cam.position = vec(0, 5, 5);
    cam.look_at = vec(0, 0, 0);
    cam.up = vec(0, 1, 0);
    cam.vfov = 50;
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_set_limits(s, prune ? NULL : &naive_limits), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, m, &mat), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 1, 0), mat, NULL), RAY_OK);
    if (mesh == 1)
        add_octahedron(s, vec(0, 1, 0), 0.8, mat);
    else
        ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 1, 0), 0.7, mat, NULL),
                         RAY_OK);
    for (k = 0; mesh == 2 && k < 4; k++)    /* five spheres: no packets */
        ck_assert_int_eq(ray_scene_add_sphere(s, vec(-20 - 2 * k, 1, -20), 0.5,
                                              mat, NULL), RAY_OK);
    add_lights(s, which);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    o = (ray_render_options){.width = W, .height = H};
    o.threads = 2;
    o.seed = 12345;
    ck_assert_int_eq(ray_render(s, &cam, &o, img, &st), RAY_OK);
    ray_scene_free(s);
    return st;
}

static ray_stats render_scene(const ray_material *m, int which, int prune,
                              float *img)
{
    return render_scene_of(m, which, prune, 0, img);
}

/* Two renders gave the same bits and cast the same rays (and, with
** "tests", made the same intersection tests). */
static void assert_same_rays(const float *a, const float *b,
                             const ray_stats *sa, const ray_stats *sb,
                             int tests)
{
    int k;

    ck_assert(memcmp(a, b, sizeof(float) * 3 * W * H) == 0);
    for (k = 0; k < RAY_KIND_COUNT; k++)
        ck_assert_uint_eq(sa->rays[k], sb->rays[k]);
    if (tests)
        ck_assert_uint_eq(sa->tests, sb->tests);
}

static void assert_same_render(const float *a, const float *b,
                               const ray_stats *sa, const ray_stats *sb)
{
    assert_same_rays(a, b, sa, sb, 1);
}

/* ------------------------------------------- a BRDF and its hand loop */

/* Diffuse plus a Blinn lobe, so both directions of ray_brdf_args count:
** (0.6, 0.5, 0.4) cos + 0.3 max(0, n.h)^8. */
static ray_rgb test_brdf(void *ud, const ray_brdf_args *b)
{
    ray_vec3 h = ray_vec3_add(b->to_light, b->to_eye);
    double nh = ray_vec3_dot(b->shade->shading_normal, h) /
                sqrt(ray_vec3_dot(h, h));
    double spec = nh > 0 ? 0.3 * pow(nh, 8) : 0;

    (void)ud;
    return ray_rgb_add(ray_rgb_scale(rgb(0.6, 0.5, 0.4), b->cos_light),
                       rgb(spec, spec, spec));
}

/* -d / |d| as ray_shade_direct documents it. */
static ray_vec3 to_eye_of(ray_vec3 d)
{
    double len = sqrt(vdot(d, d));
    return vec(-(d.x / len), -(d.y / len), -(d.z / len));
}

/* The loop a material would write by hand (the README's before this
** call existed): no shadow ray for a light behind the surface. */
static void hand_shade(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                       ray_rgb *out)
{
    ray_brdf_args b;
    unsigned li, si;

    (void)ud;
    b.shade = a;
    b.to_eye = to_eye_of(a->ray->dir);
    for (li = 0; li < ray_scene_light_count(a->scene); li++) {
        for (si = 0; si < ray_light_samples(a->scene, li); si++) {
            ray_light_sample ls;
            ray_rgb f;

            if (ray_light_sample_at(ctx, a, li, si, &ls) != RAY_OK)
                continue;
            b.sample = &ls;
            b.light = li;
            b.to_light = ls.dir;
            b.cos_light = vdot(a->shading_normal, ls.dir);
            if (b.cos_light <= 0 || !ray_light_visible(ctx, a, &ls))
                continue;
            f = test_brdf(NULL, &b);
            out->r += f.r * ls.radiance.r;
            out->g += f.g * ls.radiance.g;
            out->b += f.b * ls.radiance.b;
        }
    }
}

static void direct_shade(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                         ray_rgb *out)
{
    ck_assert_int_eq(ray_shade_direct(ctx, a, test_brdf, ud, out), RAY_OK);
}

static ray_material material_of(ray_shade_fn fn, void *ud, unsigned effects)
{
    ray_material m;
    m.shade = fn;
    m.ud = ud;
    m.effects = effects;
    m.scatter = NULL;
    return m;
}

/*
** The same bits as the hand-written loop, for each kind of light and all
** four at once, area lights with 9 and 25 jittered samples: the two draw
** the same random numbers in the same order and add in the same order,
** so the images must agree exactly, and so must the shadow-ray counts
** (no sample behind the surface costs a ray in either).  Runs 5 to 9:
** the ball is an octahedron of triangles, whose shadow rays
** ray_shade_direct asks eight at a time (through the packets, where the
** CPU has them): the same images and rays, the tests counted in the
** packets' order (ray_shade_direct(3)), so not compared.  Runs 10 to 14:
** five spheres, a scene the packets do not take, so each sample's ray
** is asked at once (direct.c), on every CPU.
*/
START_TEST(direct_should_equal_the_hand_written_loop)
{
    ray_material hand = material_of(hand_shade, NULL, RAY_EFFECT_SHADOW);
    ray_material direct = material_of(direct_shade, NULL, RAY_EFFECT_SHADOW);
    static float a[3 * W * H], b[3 * W * H];
    int mesh = _i / 5, which = _i % 5;
    ray_stats sa = render_scene_of(&hand, which, 1, mesh, a);
    ray_stats sb = render_scene_of(&direct, which, 1, mesh, b);
    double sum = 0;
    int k;

    assert_same_rays(a, b, &sa, &sb, mesh != 1);
    ck_assert_uint_gt(sa.rays[RAY_KIND_SHADOW], 0);
    for (k = 0; k < 3 * W * H; k++)
        sum += (double)a[k];
    ck_assert(sum > 0);                       /* something was lit */
}
END_TEST

/*
** One ray from (0, 0, 5) along (0, 0, -2) (not unit) onto the plane
** z = 0 of material m (the hit: the origin, exactly), under lights[0 ..
** n - 1] and, if "blocker" is 1, a ball at (1.5, 0, 2) of radius 0.5
** (if 2, five balls far from the hit and its lights, too many spheres
** for the packets): the ray's colour, and the context's counts in *st.
*/
static ray_rgb trace_down(const ray_material *m, const ray_light *lights,
                          unsigned n, int blocker, ray_stats *st)
{
    ray_ray r = ray_from(vec(0, 0, 5), vec(0, 0, -2));
    ray_scene *s;
    ray_ctx *ctx;
    ray_rgb c = rgb(-1, -1, -1);
    unsigned mat, k;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, m, &mat), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 0, 1), mat, NULL), RAY_OK);
    if (blocker == 1)
        ck_assert_int_eq(ray_scene_add_sphere(s, vec(1.5, 0, 2), 0.5, mat, NULL), RAY_OK);
    for (k = 0; blocker == 2 && k < 5; k++)  /* out of the way; no packets */
        ck_assert_int_eq(ray_scene_add_sphere(s, vec(-20 - 2.0 * k, 0, 20), 0.5,
                                              mat, NULL), RAY_OK);
    for (k = 0; k < n; k++)
        ck_assert_int_eq(ray_scene_add_light(s, &lights[k], NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(s, 1, &ctx), RAY_OK);
    ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1.0, &c), RAY_OK);
    ray_ctx_stats(ctx, st);
    ray_ctx_free(ctx);
    ray_scene_free(s);
    return c;
}

/* trace_down with ray_shade_direct under the first "n" of: a sphere
** light of 9 samples up and aside, then one of 9 samples centred on the
** hit itself (every sample at distance 0, refused). */
static ray_rgb shade_under_lights(unsigned n, int spheres, ray_stats *st)
{
    ray_material direct = material_of(direct_shade, NULL, RAY_EFFECT_SHADOW);
    ray_light l[2];
    unsigned k;

    for (k = 0; k < 2; k++) {
        ray_light_init(&l[k], RAY_LIGHT_SPHERE);
        l[k].position = k == 0 ? vec(1, 0, 3) : vec(0, 0, 0);
        l[k].radius = 0.5;
        l[k].samples = 9;
        l[k].intensity = rgb(5, 5, 5);
    }
    return trace_down(&direct, l, n, spheres ? 2 : 0, st);
}

/*
** A sample that ray_light_sample_at refuses adds nothing and casts no
** ray, in direct.c's batches too: a second light whose every sample is
** refused (at distance 0 from the hit) leaves the first light's colour
** and shadow rays as they were, bit for bit.  Run 1: five spheres out of
** the way, a scene the packets do not take (direct.c's other loop).
*/
START_TEST(direct_should_skip_refused_samples)
{
    ray_stats one, both;
    ray_rgb a = shade_under_lights(1, _i, &one);
    ray_rgb b = shade_under_lights(2, _i, &both);

    ck_assert(a.r > 0);
    ck_assert(a.r == b.r && a.g == b.g && a.b == b.b);
    ck_assert_uint_eq(one.rays[RAY_KIND_SHADOW], 9);
    ck_assert_uint_eq(both.rays[RAY_KIND_SHADOW], 9);
}
END_TEST

/* ------------------------------------- Phong as it was before, by hand */

/* The built-in Phong's loop before it moved onto ray_shade_direct (its
** lobe and its pruning rules), kept here as the reference it must still
** match bit for bit, in both pruning modes. */
static double old_specular(const ray_phong_params *p, ray_vec3 n,
                           ray_vec3 l, ray_vec3 v)
{
    double c;

    if (p->blinn) {
        ray_vec3 h = vec(l.x + v.x, l.y + v.y, l.z + v.z);
        double len2 = vdot(h, h);
        if (!(len2 > 0))
            return 0;
        c = vdot(n, h) / sqrt(len2);
    } else {
        c = -vdot(ray_reflect(l, n), v);
    }
    return c > 0 ? pow(c, p->shininess) : 0;
}

static double max3(ray_rgb c)
{
    return fmax(c.r, fmax(c.g, c.b));
}

static void old_phong_shade(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                            ray_rgb *out)
{
    const ray_phong_params *p = ud;
    ray_vec3 n = a->shading_normal, v = to_eye_of(a->ray->dir);
    unsigned li, si;

    out->r += a->ambient.r * p->diffuse.r;
    out->g += a->ambient.g * p->diffuse.g;
    out->b += a->ambient.b * p->diffuse.b;
    for (li = 0; li < ray_scene_light_count(a->scene); li++) {
        unsigned ns = ray_light_samples(a->scene, li);
        for (si = 0; si < ns; si++) {
            ray_light_sample ls;
            double ndotl, spec;
            ray_rgb f;

            if (ray_light_sample_at(ctx, a, li, si, &ls) != RAY_OK)
                continue;
            ndotl = vdot(n, ls.dir);
            if (ndotl <= 0 && a->prune)
                continue;
            spec = ndotl > 0 ? old_specular(p, n, ls.dir, v) : 0;
            if (ndotl < 0)
                ndotl = 0;
            f = rgb(p->diffuse.r * ndotl + p->specular.r * spec,
                       p->diffuse.g * ndotl + p->specular.g * spec,
                       p->diffuse.b * ndotl + p->specular.b * spec);
            if ((max3(f) <= 0 && a->prune) || !ray_light_visible(ctx, a, &ls))
                continue;
            out->r += f.r * ls.radiance.r;
            out->g += f.g * ls.radiance.g;
            out->b += f.b * ls.radiance.b;
        }
    }
}

/*
** ray_material_phong, now written on ray_shade_direct, renders the bits
** of its former hand-written loop and casts the same rays: Phong and
** Blinn lobes, pruning on and off (off: every sample, behind the surface
** or not, costs its shadow ray in both), all four kinds of light.
*/
START_TEST(phong_should_render_the_bits_of_its_former_loop)
{
    ray_phong_params p;
    static float a[3 * W * H], b[3 * W * H];
    int blinn = _i / 2, prune = _i % 2;
    ray_material builtin, old;
    ray_stats sa, sb;

    ray_phong_params_init(&p);
    p.diffuse = rgb(0.7, 0.5, 0.3);
    p.specular = rgb(0.4, 0.4, 0.4);
    p.shininess = 20;
    p.blinn = blinn;
    builtin = ray_material_phong(&p);
    /* Phong also gathers caustics now; without photons that adds
    ** nothing, so the bits stay its former loop's. */
    old = material_of(old_phong_shade, &p,
                      RAY_EFFECT_SHADOW | RAY_EFFECT_CAUSTICS);
    ck_assert_uint_eq(builtin.effects, old.effects);
    sa = render_scene(&builtin, 4, prune, a);
    sb = render_scene(&old, 4, prune, b);
    assert_same_render(a, b, &sa, &sb);
}
END_TEST

/* ---------------------------------------------- pruning and effects */

/* A plane facing up (the camera above it), one point light: above the
** plane (in front) or below it (behind), and a BRDF giving "k" times
** white: k = 0 is a zero contribution.  Rendered looking straight down,
** so every pixel sees the plane. */
typedef struct prune_case {
    double light_y;      /* +5: in front of the surface; -5: behind */
    double k;            /* the BRDF's factor */
    unsigned effects;
    unsigned samples;    /* 1: a point light; more: a sphere light's */
} prune_case;

static ray_rgb grey_brdf(void *ud, const ray_brdf_args *b)
{
    const prune_case *c = ud;
    return ray_rgb_scale(rgb(c->k, c->k, c->k), b->cos_light);
}

static void grey_shade(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                       ray_rgb *out)
{
    ck_assert_int_eq(ray_shade_direct(ctx, a, grey_brdf, ud, out), RAY_OK);
}

static ray_stats render_plane(const prune_case *c, int prune, float *img)
{
    ray_material m = material_of(grey_shade, ray__test_unconst(c),
                                 c->effects);
    ray_render_options o;
    ray_camera cam;
    ray_light l;
    ray_scene *s;
    ray_stats st;
    unsigned mat;

    cam = (ray_camera){.look_at = {0, 0, -1}};
    cam.position = vec(0, 10, 0);
    cam.look_at = vec(0, 0, 0);
    cam.up = vec(0, 0, -1);
    cam.vfov = 40;
    ray_light_init(&l, c->samples > 1 ? RAY_LIGHT_SPHERE : RAY_LIGHT_POINT);
    l.position = vec(0.5, c->light_y, 0.25);
    l.radius = 0.5;
    l.samples = c->samples;
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_set_limits(s, prune ? NULL : &naive_limits), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, &mat), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 1, 0), mat, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    o = (ray_render_options){.width = W, .height = H};
    o.threads = 2;
    ck_assert_int_eq(ray_render(s, &cam, &o, img, &st), RAY_OK);
    ray_scene_free(s);
    return st;
}

/*
** Shadow rays, counted: a light in front with a positive BRDF costs one
** per pixel; a light behind the surface, or a BRDF of zero, costs none
** with pruning and one per pixel in the naive mode; without
** RAY_EFFECT_SHADOW none is ever cast, and each request that was
** dropped is counted in shadows_undeclared instead (one per pixel where
** ray_shade_direct asks: a contributing sample, or any in the naive
** mode), exactly, summed over the render's 2 threads; declared, that
** counter stays 0.  Pruning never changes the image.
*/
START_TEST(direct_should_cast_shadow_rays_only_where_they_count)
{
    static const prune_case cases[] = {
        /* light_y, k, effects, samples:  pruned, naive rays per pixel */
        {5, 1, RAY_EFFECT_SHADOW, 1},    /* 1, 1 */
        {-5, 1, RAY_EFFECT_SHADOW, 1},   /* 0, 1: behind the surface */
        {5, 0, RAY_EFFECT_SHADOW, 1},    /* 0, 1: zero contribution */
        {5, 1, 0, 1},                    /* 0, 0: shadows not declared */
        {-5, 1, 0, 1},                   /* 0, 0: not declared, behind */
        /* A sphere light's 9 samples, asked together (direct.c): a
        ** negative factor has no positive channel, so it adds nothing
        ** though the naive mode casts its rays. */
        {5, -1, RAY_EFFECT_SHADOW, 9},   /* 0, 9 */
        {5, 1, RAY_EFFECT_SHADOW, 9},    /* 9, 9 */
    };
    static const unsigned pruned[] = {1, 0, 0, 0, 0, 0, 9},
                          naive[] = {1, 1, 1, 0, 0, 9, 9};
    /* Requests dropped for want of RAY_EFFECT_SHADOW, per pixel. */
    static const unsigned dropped_pruned[] = {0, 0, 0, 1, 0, 0, 0},
                          dropped_naive[] = {0, 0, 0, 1, 1, 0, 0};
    static float a[3 * W * H], b[3 * W * H];
    const prune_case *c = &cases[_i];
    ray_stats sa = render_plane(c, 1, a), sb = render_plane(c, 0, b);

    ck_assert_uint_eq(sa.rays[RAY_KIND_SHADOW], pruned[_i] * W * H);
    ck_assert_uint_eq(sb.rays[RAY_KIND_SHADOW], naive[_i] * W * H);
    ck_assert_uint_eq(sa.shadows_undeclared, dropped_pruned[_i] * W * H);
    ck_assert_uint_eq(sb.shadows_undeclared, dropped_naive[_i] * W * H);
    ck_assert(memcmp(a, b, sizeof a) == 0);
}
END_TEST

/* ------------------------------------------------ one hit, exact values */

/* What the BRDF saw, and the result, for the single-ray tests. */
typedef struct probe {
    unsigned calls;
    ray_brdf_args seen;
    ray_light_sample sample;
    const ray_shade_args *args;
    int rc;
} probe;

static ray_rgb probe_brdf(void *ud, const ray_brdf_args *b)
{
    probe *p = ud;
    p->calls++;
    p->seen = *b;
    p->sample = *b->sample;
    return ray_rgb_scale(rgb(0.5, 0.25, 1), b->cos_light);
}

static void probe_shade(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                        ray_rgb *out)
{
    probe *p = ud;
    p->args = a;
    p->rc = ray_shade_direct(ctx, a, probe_brdf, ud, out);
}

/* Trace one ray from (0, 0, 5) along (0, 0, -2) (not unit) at the plane
** z = 0, under a point light at "light" (intensity 25) and, if
** "blocker", a ball on the segment between. */
static ray_rgb trace_one(probe *p, ray_vec3 light, int blocker,
                         unsigned effects, ray_stats *st)
{
    ray_material m = material_of(probe_shade, p, effects);
    ray_light l;

    ray_light_init(&l, RAY_LIGHT_POINT);
    l.position = light;
    l.intensity = rgb(25, 25, 25);
    return trace_down(&m, &l, 1, blocker, st);
}

/*
** The arguments the BRDF gets, and the sum, in exact numbers: hit at the
** origin, light at (3, 0, 4), so to_light = (0.6, 0, 0.8), cos_light =
** 0.8, distance 5, radiance 25/25 = 1; to_eye = (0, 0, 1) although the
** ray's direction has length 2.  The result is (0.5, 0.25, 1) * 0.8.
** Tolerance: a handful of roundings of numbers below 2 (normalising,
** one dot product, two products): 8 units of roundoff.
*/
START_TEST(brdf_should_get_unit_directions_and_the_cosine)
{
    const double tol = 8 * U64;
    probe p;
    ray_stats st;
    ray_rgb c;

    memset(&p, 0, sizeof p);
    c = trace_one(&p, vec(3, 0, 4), 0, RAY_EFFECT_SHADOW, &st);
    ck_assert_int_eq(p.rc, RAY_OK);
    ck_assert_uint_eq(p.calls, 1);
    ck_assert_uint_eq(p.seen.light, 0);
    ck_assert_vec_eq_tol(p.seen.to_light, vec(0.6, 0, 0.8), tol);
    ck_assert_vec_eq(p.seen.to_light, p.sample.dir);
    ck_assert_vec_eq(p.seen.to_eye, vec(0, 0, 1));
    ck_assert_double_eq_tol(p.seen.cos_light, 0.8, tol);
    ck_assert_double_eq_tol(p.sample.dist, 5, tol);
    ck_assert_double_eq_tol(c.r, 0.4, tol);
    ck_assert_double_eq_tol(c.g, 0.2, tol);
    ck_assert_double_eq_tol(c.b, 0.8, tol);
    ck_assert_uint_eq(st.rays[RAY_KIND_SHADOW], 1);
}
END_TEST

/*
** The effect analysis decides: a ball between the hit and the light
** shadows it (one shadow ray, nothing added) when the material declared
** RAY_EFFECT_SHADOW; without it no ray is cast and the light arrives in
** full, 0.4 in the red channel as above.
*/
START_TEST(undeclared_shadows_should_leave_the_light_unblocked)
{
    const double tol = 8 * U64;
    probe p;
    ray_stats st;
    ray_rgb c;

    memset(&p, 0, sizeof p);
    c = trace_one(&p, vec(3, 0, 4), 1, RAY_EFFECT_SHADOW, &st);
    ck_assert_uint_eq(st.rays[RAY_KIND_SHADOW], 1);
    ck_assert_uint_eq(st.shadows_undeclared, 0);
    ck_assert_double_eq(c.r, 0);
    memset(&p, 0, sizeof p);
    c = trace_one(&p, vec(3, 0, 4), 1, 0, &st);
    ck_assert_uint_eq(st.rays[RAY_KIND_SHADOW], 0);
    ck_assert_uint_eq(st.shadows_undeclared, 1);   /* the sign it left */
    ck_assert_double_eq_tol(c.r, 0.4, tol);
}
END_TEST

/* A light behind the surface never reaches the BRDF; the sum is 0. */
START_TEST(brdf_should_not_see_a_light_behind_the_surface)
{
    probe p;
    ray_stats st;
    ray_rgb c;

    memset(&p, 0, sizeof p);
    c = trace_one(&p, vec(3, 0, -4), 0, RAY_EFFECT_SHADOW, &st);
    ck_assert_int_eq(p.rc, RAY_OK);
    ck_assert_uint_eq(p.calls, 0);
    ck_assert_uint_eq(st.rays[RAY_KIND_SHADOW], 0);
    ck_assert_double_eq(c.r, 0);
}
END_TEST

/* NULLs: RAY_EINVAL and *out untouched, from inside a callback. */
static void null_shade(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                       ray_rgb *out)
{
    int *ok = ud;
    ray_shade_args no_ray = *a, no_hit = *a;
    ray_rgb before = rgb(0.125, 0.25, 0.5), c = before;

    no_ray.ray = NULL;
    no_hit.hit = NULL;
    *ok = ray_shade_direct(NULL, a, test_brdf, NULL, &c) == RAY_EINVAL &&
          ray_shade_direct(ctx, NULL, test_brdf, NULL, &c) == RAY_EINVAL &&
          ray_shade_direct(ctx, &no_ray, test_brdf, NULL, &c) == RAY_EINVAL &&
          ray_shade_direct(ctx, &no_hit, test_brdf, NULL, &c) == RAY_EINVAL &&
          ray_shade_direct(ctx, a, NULL, NULL, &c) == RAY_EINVAL &&
          ray_shade_direct(ctx, a, test_brdf, NULL, NULL) == RAY_EINVAL &&
          memcmp(&c, &before, sizeof c) == 0 &&
          ray_shade_direct(ctx, a, test_brdf, NULL, &c) == RAY_OK &&
          c.r > before.r;               /* the light did add something */
    (void)out;
}

START_TEST(direct_should_refuse_null_arguments)
{
    ray_material m;
    ray_ray r = ray_from(vec(0, 0, 5), vec(0, 0, -1));
    ray_light l;
    ray_scene *s;
    ray_ctx *ctx;
    ray_rgb c;
    int ok = 0;

    m = material_of(null_shade, &ok, RAY_EFFECT_SHADOW);
    ray_light_init(&l, RAY_LIGHT_POINT);
    l.position = vec(0, 0, 4);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 0, 1), 0, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(s, 1, &ctx), RAY_OK);
    ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1.0, &c), RAY_OK);
    ck_assert_int_eq(ok, 1);
    ray_ctx_free(ctx);
    ray_scene_free(s);
}
END_TEST

/* ------------------------------------------------- the inline helpers */

/*
** Exact values: small integers and dyadic fractions are representable
** and their sums and products here are exact, so no tolerance.  The dot
** product sums left to right: (1e16 + 1) rounds to 1e16 (the spacing of
** doubles there is 2), so (1e16, 1, -1e16) . (1, 1, 1) is 0, not 1.
*/
START_TEST(inline_helpers_should_compute_exact_values)
{
    ray_vec3 a = ray_vec3_make(1, 2, 3), b = ray_vec3_make(4, 5, 6);
    ray_rgb c = ray_rgb_make(0.5, 0.25, 2), d = ray_rgb_make(2, 4, 8);

    ck_assert_vec_eq(a, vec(1, 2, 3));
    ck_assert_vec_eq(ray_vec3_add(a, b), vec(5, 7, 9));
    ck_assert_vec_eq(ray_vec3_sub(a, b), vec(-3, -3, -3));
    ck_assert_vec_eq(ray_vec3_scale(a, -0.5), vec(-0.5, -1, -1.5));
    ck_assert_double_eq(ray_vec3_dot(a, b), 32);
    ck_assert_double_eq(ray_vec3_dot(ray_vec3_make(1e16, 1, -1e16),
                                     ray_vec3_make(1, 1, 1)), 0);
    ck_assert_vec_eq(ray_vec3_cross(ray_vec3_make(1, 0, 0),
                                    ray_vec3_make(0, 1, 0)), vec(0, 0, 1));
    ck_assert_vec_eq(ray_vec3_cross(a, b), vec(-3, 6, -3));
    ck_assert_double_eq(c.r, 0.5);
    ck_assert_double_eq(c.g, 0.25);
    ck_assert_double_eq(c.b, 2);
    c = ray_rgb_add(c, d);
    ck_assert(c.r == 2.5 && c.g == 4.25 && c.b == 10);
    c = ray_rgb_mul(ray_rgb_make(0.5, 0.25, 2), d);
    ck_assert(c.r == 1 && c.g == 1 && c.b == 16);
    c = ray_rgb_scale(d, 0.25);
    ck_assert(c.r == 0.5 && c.g == 1 && c.b == 2);
    c = ray_rgb_madd(ray_rgb_make(1, 1, 1), ray_rgb_make(0.5, 0.25, 2), d);
    ck_assert(c.r == 2 && c.g == 2 && c.b == 17);
    /* NaN passes through: nothing is clamped. */
    c = ray_rgb_scale(d, (double)NAN);
    ck_assert(isnan(c.r) && isnan(c.g) && isnan(c.b));
}
END_TEST

Suite *direct_suite(void)
{
    Suite *s = suite_create("direct");
    TCase *tc = tcase_create("loop");

    tcase_add_loop_test(tc, direct_should_equal_the_hand_written_loop, 0, 15);
    tcase_add_loop_test(tc, phong_should_render_the_bits_of_its_former_loop,
                        0, 4);
    tcase_add_loop_test(tc, direct_should_cast_shadow_rays_only_where_they_count,
                        0, 7);
    suite_add_tcase(s, tc);
    tc = tcase_create("hit");
    tcase_add_loop_test(tc, direct_should_skip_refused_samples, 0, 2);
    tcase_add_test(tc, brdf_should_get_unit_directions_and_the_cosine);
    tcase_add_test(tc, undeclared_shadows_should_leave_the_light_unblocked);
    tcase_add_test(tc, brdf_should_not_see_a_light_behind_the_surface);
    tcase_add_test(tc, direct_should_refuse_null_arguments);
    suite_add_tcase(s, tc);
    tc = tcase_create("helpers");
    tcase_add_test(tc, inline_helpers_should_compute_exact_values);
    suite_add_tcase(s, tc);
    return s;
}
