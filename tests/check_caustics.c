/* SPDX-License-Identifier: MIT */
/*
** check_caustics.c -- caustics by photon tracing (issue 19): the power a
** mirror sends onto a floor, the focus of a glass sphere, no photon where
** no caustic can be, the same bytes at any thread count, bad settings
** refused, misuse answered.
**
** Statistical tolerances: N photons leave the light; each reaches the
** mirror (or the disk of a density estimate) independently with some
** probability p, so the count is binomial, and the estimate's relative
** standard deviation is sqrt((1 - p) / (N p)) (about 1 / sqrt(count)).
** The tests allow 5 of them (a 5-sigma deviation has probability 6e-7 by
** the central limit theorem), and the seed is fixed, so they are
** deterministic anyway.
*/
#include <stdlib.h>

#include "tests.h"
#include "caustics_kit.h"
#include "scenes.h"

/* pi, which strict C99 <math.h> does not define. */
#define PI 3.14159265358979323846

static ray_light point_light(ray_vec3 p, ray_rgb intensity)
{
    ray_light l;

    ray_light_init(&l, RAY_LIGHT_POINT);
    l.position = p;
    l.intensity = intensity;
    return l;
}

/*
** The mirror scene: a point light of intensity I at (0, 1, 0), under a
** square mirror 2 x 2 at y = 2 (facing down, reflectance R), over the
** probe floor y = 0.  The square subtends the solid angle
** 4 asin(a b / sqrt((a^2 + d^2)(b^2 + d^2))) = 4 asin(1/2) = 2 pi / 3
** from the light (a = b = 1 half-sides, d = 1), so the floor receives
** R I 2 pi / 3 in all (every reflected photon lands on the infinite
** floor), and at (x, z) the irradiance of the mirror image of the light,
** R I cos / dist^2 from (0, 3, 0), where the image's rays pass through
** the square (|x|, |z| < 3).
*/
static const ray_rgb mirror_I = {2.0, 3.0, 5.0};

static ray_scene *mirror_scene(void)
{
    ray_scene *s;
    ray_material probe = probe_material();
    ray_material mirror = ray_material_mirror(&mirror_R);
    ray_light l = point_light(vec(0, 1, 0), mirror_I);
    unsigned pm, mm;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &probe, &pm), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &mirror, &mm), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 1, 0), pm,
                                         NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_triangle(s, vec(-1, 2, -1), vec(1, 2, -1),
                                            vec(1, 2, 1), mm, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_triangle(s, vec(-1, 2, -1), vec(1, 2, 1),
                                            vec(-1, 2, 1), mm, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    return s;
}

static ray_photon_map *build(const ray_scene *s, unsigned long long n,
                             double radius, unsigned threads)
{
    ray_render_options o;
    ray_photon_map *map = NULL;

    o = (ray_render_options){.width = 1, .height = 1};
    o.photons = n;
    o.photon_radius = radius;
    o.threads = threads;
    o.seed = 19;
    ck_assert_int_eq(ray_photon_map_build(s, &o, &map), RAY_OK);
    ck_assert_ptr_nonnull(map);
    return map;
}

START_TEST(mirror_should_send_its_reflected_power_to_the_floor)
{
    /* All of it: a radius of 100 holds every photon (the footprint is
    ** the 6 x 6 square under the mirror), so E pi r^2 is the total.
    ** The light sits inside the sphere around the mirror's box (radius
    ** sqrt 2 > 1), so photons go everywhere: p = (2 pi / 3) / (4 pi) =
    ** 1/6 reach the mirror, relative deviation sqrt(5 / N). */
    const unsigned long long N = 200000;
    const double r = 100, omega = 2 * PI / 3;
    const double tol = 5 * sqrt((1 - 1.0 / 6) / ((double)N / 6.0));
    ray_scene *s = mirror_scene();
    ray_photon_map *map = build(s, N, r, 2);
    ray_ctx *ctx;
    ray_rgb e;
    ray_stats st;

    ck_assert_uint_eq(ray_scene_effects(s) & RAY_EFFECT_CAUSTICS,
                      RAY_EFFECT_CAUSTICS);
    ck_assert_int_eq(ray_ctx_new(s, 0, &ctx), RAY_OK);
    e = floor_irradiance(ctx, 0, 0);
    ck_assert(e.r == 0 && e.g == 0 && e.b == 0);   /* no map yet: zero */
    ck_assert_int_eq(ray_ctx_set_photon_map(ctx, map), RAY_OK);
    e = floor_irradiance(ctx, 0, 0);
    ck_assert_double_eq_tol(e.r * PI * r * r,
                            mirror_R.r * mirror_I.r * omega,
                            tol * mirror_R.r * mirror_I.r * omega);
    ck_assert_double_eq_tol(e.g * PI * r * r,
                            mirror_R.g * mirror_I.g * omega,
                            tol * mirror_R.g * mirror_I.g * omega);
    ck_assert_double_eq_tol(e.b * PI * r * r,
                            mirror_R.b * mirror_I.b * omega,
                            tol * mirror_R.b * mirror_I.b * omega);
    ray_ctx_stats(ctx, &st);
    ck_assert_uint_eq(st.photon_lookups, 1);      /* not the one without */
    ray_ctx_free(ctx);
    ray_photon_map_free(map);
    ray_scene_free(s);
}
END_TEST

START_TEST(disk_estimate_should_give_the_mirror_image_irradiance)
{
    /* E at (x, 0, z) is R I cos / d^2 from the image (0, 3, 0).  With
    ** r = 0.25 the disk holds about E pi r^2 / (photon power) photons
    ** (photon power 4 pi I R / N, all channels alike); its relative
    ** deviation is 1 / sqrt(that count).  The kernel's bias: E varies
    ** over the disk by its curvature, (r / d)^2 ~ 0.7% at d = 3, added. */
    const unsigned long long N = 1000000;
    const double r = 0.25;
    static const double pts[3][2] = {{0, 0}, {1, 0.5}, {-1.5, -1.2}};
    ray_scene *s = mirror_scene();
    ray_photon_map *map = build(s, N, r, 2);
    ray_ctx *ctx;
    int k;

    ck_assert_int_eq(ray_ctx_new(s, 0, &ctx), RAY_OK);
    ck_assert_int_eq(ray_ctx_set_photon_map(ctx, map), RAY_OK);
    for (k = 0; k < 3; k++) {
        double x = pts[k][0], z = pts[k][1];
        double d2 = x * x + 9 + z * z, cosv = 3 / sqrt(d2);
        double want = mirror_R.g * mirror_I.g * cosv / d2;
        double per = 4 * PI * mirror_I.g * mirror_R.g / (double)N;
        double count = want * PI * r * r / per;
        double tol = 5 / sqrt(count) + (r * r) / d2;
        ray_rgb e = floor_irradiance(ctx, x, z);
        ck_assert_double_eq_tol(e.g, want, tol * want);
        /* The channels share the photons: r and b scale with R I. */
        ck_assert_double_eq_tol(e.r / (mirror_R.r * mirror_I.r),
                                e.g / (mirror_R.g * mirror_I.g),
                                1e-6 * e.g);     /* float powers: 2^-24 */
    }
    /* Outside the footprint (|x| > 3 + r): nothing. */
    ck_assert(floor_irradiance(ctx, 3.5, 0).g == 0);
    ray_ctx_free(ctx);
    ray_photon_map_free(map);
    ray_scene_free(s);
}
END_TEST

/* The solid angle of the mirror square (|x|, |z| <= 1 at y = 2) from
** the point p below it, whose foot lies inside the square: the sum over
** the four rectangles that meet at the foot of asin(a b / sqrt((a^2 +
** h^2)(b^2 + h^2))), h the height (the formula of the first test). */
static double mirror_solid_angle(ray_vec3 p)
{
    double h = 2 - p.y, sum = 0;
    double ax[2] = {1 - p.x, 1 + p.x}, bz[2] = {1 - p.z, 1 + p.z};
    int i, j;

    for (i = 0; i < 2; i++)
        for (j = 0; j < 2; j++)
            sum += asin(ax[i] * bz[j] /
                        sqrt((ax[i] * ax[i] + h * h) * (bz[j] * bz[j] + h * h)));
    return sum;
}

/*
** Photons from two lights of unequal power (issue 29: no test built
** two).  The mirror scene with a second point light B close under the
** mirror, much brighter in red: A = (2, 3, 5) at (0, 1, 0), B = (30,
** 0.5, 0.5) at (0.3, 1.8, -0.2).  Both sit inside the sphere around the
** mirror, so they emit everywhere; each photon picks light i with
** probability p_i = its power over the total (4 pi I summed over the
** channels: 10 and 31) and carries I_i 4 pi / (N p_i), and reaches the
** mirror with probability q_i = Omega_i / (4 pi).  So:
**   - photons stored (those the mirror sends to the floor) are binomial,
**     N sum p_i q_i: a selection by any other weight (red alone: 2 and
**     30) moves it by 40 standard deviations;
**   - the floor receives R (I_A Omega_A + I_B Omega_B) in each channel,
**     whatever the selection, if each photon's power is divided by the
**     probability its light was actually chosen with; the sum over the
**     photons has variance N (E[X^2] - E[X]^2), X a photon's power on the
**     floor.
** Both within 5 standard deviations (the file's rule).
*/
START_TEST(photons_of_unequal_lights_should_be_shared_by_power)
{
    const unsigned long long N = 200000;
    const double r = 100;
    const ray_rgb IB = {30, 0.5, 0.5};
    const ray_vec3 pa = {0, 1, 0}, pb = {0.3, 1.8, -0.2};
    ray_scene *s = mirror_scene();
    ray_light lb = point_light(pb, IB);
    double omega[2], p[2], q = 0, mean_q;
    const ray_rgb *I[2];
    ray_render_options o;
    ray_photon_map *map;
    ray_camera cam;
    ray_stats st;
    ray_ctx *ctx;
    ray_rgb e;
    float px[3];
    int i, ch;

    ck_assert_int_eq(ray_scene_add_light(s, &lb, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    I[0] = &mirror_I;
    I[1] = &IB;
    omega[0] = mirror_solid_angle(pa);
    omega[1] = mirror_solid_angle(pb);
    ck_assert_double_eq_tol(omega[0], 2 * PI / 3, 1e-12);  /* the formula */
    p[0] = 10.0 / 41;
    p[1] = 31.0 / 41;
    for (i = 0; i < 2; i++)
        q += p[i] * omega[i] / (4 * PI);
    /* Stored photons, counted by a render's pass (the same seed and
    ** count as build(): the same photons). */
    cam = (ray_camera){.look_at = {0, 0, -1}};
    cam.position = vec(0, 0.5, 3);
    o = (ray_render_options){.width = 1, .height = 1};
    o.photons = N;
    o.threads = 2;
    o.seed = 19;
    ck_assert_int_eq(ray_render(s, &cam, &o, px, &st), RAY_OK);
    ck_assert_uint_eq(st.photons_emitted, N);
    mean_q = (double)N * q;
    ck_assert_msg(fabs((double)st.photons_stored - mean_q) <=
                      5 * sqrt(mean_q * (1 - q)),
                  "stored %llu, expected %.0f", st.photons_stored, mean_q);
    /* The power on the floor, per channel. */
    map = build(s, N, r, 2);
    ck_assert_int_eq(ray_ctx_new(s, 0, &ctx), RAY_OK);
    ck_assert_int_eq(ray_ctx_set_photon_map(ctx, map), RAY_OK);
    e = floor_irradiance(ctx, 0, 0);
    for (ch = 0; ch < 3; ch++) {
        double R = (&mirror_R.r)[ch], got = (&e.r)[ch] * PI * r * r;
        double want = 0, ex = 0, ex2 = 0;
        for (i = 0; i < 2; i++) {
            double I_c = (&I[i]->r)[ch];
            double x = R * I_c * 4 * PI / ((double)N * p[i]);
            double prob = p[i] * omega[i] / (4 * PI);
            want += R * I_c * omega[i];
            ex += prob * x;
            ex2 += prob * x * x;
        }
        ck_assert_msg(fabs(got - want) <= 5 * sqrt((double)N * (ex2 - ex * ex)),
                      "channel %d: %g on the floor, expected %g", ch, got,
                      want);
    }
    ray_ctx_free(ctx);
    ray_photon_map_free(map);
    ray_scene_free(s);
}
END_TEST

/*
** The automatic radius at a count other than the reference one (issue
** 29: at 100 000 photons the exponent of N / 100 000 cannot show).  At N
** = 15 625 the rule (ray.h) gives r = D / 100 (N / 100 000)^(-1/6) =
** D / 100 * 1.3627, D the diagonal of the mirror's box (2 sqrt 2).  A
** map with the automatic radius and one with that radius given gather
** the same photons (the pass does not depend on the radius), so their
** estimates agree wherever a photon is near: to 1e-8 relative, the
** rule's D being the box's diagonal grown by 2^-30 (photons.c) and the
** estimate going as 1 / r^2.  That this detects a different radius is
** checked too: a radius 1e-4 larger moves the estimates by 2e-4.  The
** points: a grid over the footprint, most of them with a photon near.
*/
START_TEST(automatic_radius_should_follow_the_rule_at_any_count)
{
    const unsigned long long N = 15625;
    const double D = 2 * sqrt(2.0);
    const double r = D / 100 * pow((double)N / 100000, -1.0 / 6);
    ray_scene *s = mirror_scene();
    ray_photon_map *automatic = build(s, N, 0, 2), *given = build(s, N, r, 2),
                   *wider = build(s, N, r * (1 + 1e-4), 2);
    ray_ctx *ca, *cg, *cw;
    int i, j, seen = 0, moved = 0;

    ck_assert_int_eq(ray_ctx_new(s, 0, &ca), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(s, 0, &cg), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(s, 0, &cw), RAY_OK);
    ck_assert_int_eq(ray_ctx_set_photon_map(ca, automatic), RAY_OK);
    ck_assert_int_eq(ray_ctx_set_photon_map(cg, given), RAY_OK);
    ck_assert_int_eq(ray_ctx_set_photon_map(cw, wider), RAY_OK);
    for (i = 0; i < 40; i++)
        for (j = 0; j < 40; j++) {
            double x = -2.9 + 5.8 * i / 39, z = -2.9 + 5.8 * j / 39;
            ray_rgb a = floor_irradiance(ca, x, z);
            ray_rgb g = floor_irradiance(cg, x, z);
            ray_rgb w = floor_irradiance(cw, x, z);
            ck_assert_msg(fabs(a.g - g.g) <= 1e-8 * g.g,
                          "at (%g, %g): %.17g with the automatic radius, "
                          "%.17g with the rule's", x, z, a.g, g.g);
            seen += g.g > 0;
            moved += fabs(w.g - g.g) > 1e-4 * g.g;
        }
    ck_assert_int_gt(seen, 400);
    ck_assert_int_eq(moved, seen);
    ray_ctx_free(ca);
    ray_ctx_free(cg);
    ray_ctx_free(cw);
    ray_photon_map_free(automatic);
    ray_photon_map_free(given);
    ray_photon_map_free(wider);
    ray_scene_free(s);
}
END_TEST

/*
** A glass sphere of radius 1 under a point light straight above: a ball
** lens of focal length f = n R / (2 (n - 1)) = 1.5 from its centre; for
** the light s = 10 - h above the centre the image lies s' = 1 / (1/f -
** 1/s) below it, which is the floor for h = 1.8376 (solved by fixed
** point: h = s').  The brightest point of the floor must be below the
** centre, and far brighter than the unfocused light I / 10^2 there.
*/
START_TEST(glass_sphere_should_focus_its_caustic_below_its_centre)
{
    const double h = 1.8376, cx = 0.7, cz = -0.4, step = 0.05, r = 0.04;
    static const ray_glass_params glass = {1.5, {0, 0, 0}};
    ray_scene *s;
    ray_material probe = probe_material(), g = ray_material_glass(&glass);
    ray_light l = point_light(vec(cx, 10, cz), rgb(100, 100, 100));
    ray_photon_map *map;
    ray_ctx *ctx;
    unsigned pm, gm;
    double best = -1, bx = 0, bz = 0;
    int i, j;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &probe, &pm), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &g, &gm), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 1, 0), pm,
                                         NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(cx, h, cz), 1, gm, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    map = build(s, 200000, r, 2);
    ck_assert_int_eq(ray_ctx_new(s, 0, &ctx), RAY_OK);
    ck_assert_int_eq(ray_ctx_set_photon_map(ctx, map), RAY_OK);
    for (i = -12; i <= 12; i++)
        for (j = -12; j <= 12; j++) {
            double x = cx + i * step, z = cz + j * step;
            ray_rgb e = floor_irradiance(ctx, x, z);
            if (e.g > best) {
                best = e.g;
                bx = x;
                bz = z;
            }
        }
    /* Within one grid step and the gather radius of the axis. */
    ck_assert_double_eq_tol(bx, cx, step + r);
    ck_assert_double_eq_tol(bz, cz, step + r);
    /* The lens gathers I * (its solid angle, pi / 8.2^2) into a spot a
    ** few radii r across: far more than 10x the unfocused I / 100. */
    ck_assert(best > 10 * 100.0 / 100.0);
    /* Half a radius out, inside the sphere's shadow, only the halo of
    ** its spherical aberration: much less. */
    ck_assert(floor_irradiance(ctx, cx + 0.5, cz).g < best / 10);
    ray_ctx_free(ctx);
    ray_photon_map_free(map);
    ray_scene_free(s);
}
END_TEST

/* A diffuse floor and sphere under a light: nothing scatters photons. */
static ray_scene *diffuse_scene(void)
{
    static ray_phong_params p;
    ray_scene *s;
    ray_material m;
    ray_light l = point_light(vec(2, 6, 3), rgb(30, 30, 30));
    unsigned id;

    ray_phong_params_init(&p);
    m = ray_material_phong(&p);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, &id), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 1, 0), id,
                                         NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(0, 1, 0), 1, id, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    return s;
}

#define W 40
#define H 30

static ray_stats render(const ray_scene *s, unsigned long long photons,
                        unsigned threads, float *img)
{
    ray_camera cam;
    ray_render_options o;
    ray_stats st;

    cam = (ray_camera){.look_at = {0, 0, -1}};
    cam.position = vec(0, 4, 7.5);
    cam.look_at = vec(0, 0.5, 0);
    o = (ray_render_options){.width = W, .height = H};
    o.threads = threads;
    o.photons = photons;
    ck_assert_int_eq(ray_render(s, &cam, &o, img, &st), RAY_OK);
    return st;
}

START_TEST(scene_without_specular_should_trace_no_photon)
{
    static float a[3 * W * H], b[3 * W * H];
    ray_scene *s = diffuse_scene();
    ray_stats sa, sb;
    ray_photon_map *map;
    ray_ctx *ctx;

    ck_assert_uint_eq(ray_scene_effects(s),
                      RAY_EFFECT_SHADOW);           /* no caustics */
    sa = render(s, 0, 2, a);
    sb = render(s, 100000, 2, b);
    ck_assert_uint_eq(sb.photons_emitted, 0);
    ck_assert_uint_eq(sb.photons_stored, 0);
    ck_assert_uint_eq(sb.photon_lookups, 0);
    ck_assert_uint_eq(sa.tests, sb.tests);
    ck_assert(memcmp(a, b, sizeof a) == 0);
    /* The explicit map is empty, and reads zero. */
    map = build(s, 1000, 0, 1);
    ck_assert_int_eq(ray_ctx_new(s, 0, &ctx), RAY_OK);
    ck_assert_int_eq(ray_ctx_set_photon_map(ctx, map), RAY_OK);
    ray_ctx_free(ctx);
    ray_photon_map_free(map);
    ray_scene_free(s);
}
END_TEST

/* Each condition of a caustic missing in turn: no light, no gatherer,
** no scatterer (a disabled mirror), caustics switched off (photons 0). */
START_TEST(effect_analysis_should_need_light_scatterer_and_gatherer)
{
    static float img[3 * W * H];
    ray_material probe = probe_material(), mirror;
    static const ray_rgb one = {1, 1, 1};
    ray_light l = point_light(vec(0, 1, 0), rgb(1, 1, 1));
    ray_scene *s;
    unsigned pm, mm, tri;
    ray_stats st;

    mirror = ray_material_mirror(&one);
    /* A mirror without a light. */
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &probe, &pm), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &mirror, &mm), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 1, 0), pm,
                                         NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_triangle(s, vec(-1, 2, -1), vec(1, 2, -1),
                                            vec(1, 2, 1), mm, &tri), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_uint_eq(ray_scene_effects(s) & RAY_EFFECT_CAUSTICS, 0);
    /* With the light: caustics. */
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_uint_eq(ray_scene_effects(s) & RAY_EFFECT_CAUSTICS,
                      RAY_EFFECT_CAUSTICS);
    st = render(s, 5000, 1, img);
    ck_assert_uint_eq(st.photons_emitted, 5000);
    ck_assert_uint_gt(st.photons_stored, 0);
    st = render(s, 0, 1, img);                      /* switched off */
    ck_assert_uint_eq(st.photons_emitted, 0);
    /* The mirror disabled: nothing scatters. */
    ck_assert_int_eq(ray_scene_set_enabled(s, tri, 0), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_uint_eq(ray_scene_effects(s) & RAY_EFFECT_CAUSTICS, 0);
    st = render(s, 5000, 1, img);
    ck_assert_uint_eq(st.photons_emitted, 0);
    ray_scene_free(s);
    /* Mirrors alone: nothing gathers. */
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &mirror, &mm), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 1, 0), mm,
                                         NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_uint_eq(ray_scene_effects(s),
                      RAY_EFFECT_REFLECTION);
    ray_scene_free(s);
}
END_TEST

/* A mirror placed through an instance: the analysis sees its child's
** scattering material, and photons find it where the instance puts it
** (the mirror scene's square, moved up by 1: the light at (0, 2, 0) sits
** under it as before, so the floor gets R I 2 pi / 3 as in the first
** test, within the same 5-sigma bound). */
/* A scatter function no photon may reach: the test fails if it runs. */
static int never_scatter(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                         ray_vec3 *dir, ray_rgb *weight)
{
    (void)ud;
    (void)ctx;
    (void)a;
    (void)dir;
    (void)weight;
    ck_abort_msg("scatter called without RAY_EFFECT_SCATTER");
    return 0;
}

/*
** "scatter" is read only with RAY_EFFECT_SCATTER (ray.h): code that fills
** a material field by field and predates the field leaves whatever the
** stack held there.  A mirror-like material whose scatter points to
** never_scatter, without the bit, over the probe floor under a light:
** no caustics, no photon, the function never called.  The bit with a
** NULL function is refused, with the scene's message.
*/
START_TEST(scatter_should_be_read_only_with_its_effect_bit)
{
    static float img[3 * W * H];
    ray_material probe = probe_material(), m;
    ray_light l = point_light(vec(0, 1, 0), rgb(1, 1, 1));
    ray_scene *s;
    unsigned pm, mm, n;
    ray_stats st;

    m = ray_material_mirror(&mirror_R);
    m.effects = RAY_EFFECT_REFLECTION;        /* the bit left out */
    m.scatter = never_scatter;                /* "garbage" */
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &probe, &pm), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, &mm), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), vec(0, 1, 0), pm,
                                         NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_triangle(s, vec(-1, 2, -1), vec(1, 2, -1),
                                            vec(1, 2, 1), mm, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_uint_eq(ray_scene_effects(s) &
                      (RAY_EFFECT_CAUSTICS | RAY_EFFECT_SCATTER), 0);
    st = render(s, 20000, 2, img);
    ck_assert_uint_eq(st.photons_emitted, 0);
    /* The bit without a function: refused, nothing added. */
    m.effects = RAY_EFFECT_REFLECTION | RAY_EFFECT_SCATTER;
    m.scatter = NULL;
    n = 77;
    ck_assert_int_eq(ray_scene_add_material(s, &m, &n), RAY_EINVAL);
    ck_assert_uint_eq(n, 77);
    ck_assert_str_eq(ray_scene_errmsg(s), "ray_scene_add_material: "
                     "RAY_EFFECT_SCATTER without a scatter function");
    /* The built-in mirror declares the bit with its function. */
    m = ray_material_mirror(&mirror_R);
    ck_assert_uint_eq(m.effects, RAY_EFFECT_REFLECTION | RAY_EFFECT_SCATTER);
    ray_scene_free(s);
}
END_TEST

START_TEST(instanced_mirror_should_make_caustics)
{
    const unsigned long long N = 200000;
    const double r = 100, omega = 2 * PI / 3;
    const double tol = 5 * sqrt((1 - 1.0 / 6) / ((double)N / 6.0));
    ray_material probe = probe_material();
    ray_material mirror = ray_material_mirror(&mirror_R);
    ray_light l = point_light(vec(0, 2, 0), mirror_I);
    ray_scene *child, *top;
    ray_transform x;
    ray_photon_map *map;
    ray_ctx *ctx;
    ray_rgb e;
    unsigned pm, mm;

    ck_assert_int_eq(ray_scene_new(&child, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(child, &mirror, &mm), RAY_OK);
    ck_assert_int_eq(ray_scene_add_triangle(child, vec(-1, 2, -1),
                                            vec(1, 2, -1), vec(1, 2, 1), mm,
                                            NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_triangle(child, vec(-1, 2, -1),
                                            vec(1, 2, 1), vec(-1, 2, 1), mm,
                                            NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(child), RAY_OK);
    ck_assert_int_eq(ray_scene_new(&top, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(top, &probe, &pm), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(top, vec(0, 0, 0), vec(0, 1, 0), pm,
                                         NULL), RAY_OK);
    ray_transform_identity(&x);
    x.m[1][3] = 1;               /* up by 1: the mirror at y = 3 */
    ck_assert_int_eq(ray_scene_add_instance(top, child, &x, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_light(top, &l, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    ck_assert_uint_eq(ray_scene_effects(top) & RAY_EFFECT_CAUSTICS,
                      RAY_EFFECT_CAUSTICS);
    map = build(top, N, r, 2);
    ck_assert_int_eq(ray_ctx_new(top, 0, &ctx), RAY_OK);
    ck_assert_int_eq(ray_ctx_set_photon_map(ctx, map), RAY_OK);
    e = floor_irradiance(ctx, 0, 0);
    ck_assert_double_eq_tol(e.g * PI * r * r,
                            mirror_R.g * mirror_I.g * omega,
                            tol * mirror_R.g * mirror_I.g * omega);
    ray_ctx_free(ctx);
    ray_photon_map_free(map);
    ray_scene_free(top);
    ray_scene_free(child);
}
END_TEST

START_TEST(caustics_should_be_the_same_bytes_at_any_thread_count)
{
    static float img[3][3 * W * H];
    ray_camera cam;
    ray_scene *s = caustics_scene(&cam);
    ray_render_options o;
    ray_stats st[3];
    unsigned t;

    o = (ray_render_options){.width = W, .height = H};
    o.photons = 20000;       /* 5 chunks of 4096: every thread has some */
    for (t = 0; t < 3; t++) {
        o.threads = t + 1;
        ck_assert_int_eq(ray_render(s, &cam, &o, img[t], &st[t]), RAY_OK);
        ck_assert_uint_eq(st[t].photons_emitted, 20000);
        ck_assert_uint_eq(st[t].photons_stored, st[0].photons_stored);
        ck_assert_uint_eq(st[t].photon_lookups, st[0].photon_lookups);
        ck_assert(memcmp(img[t], img[0], sizeof img[0]) == 0);
    }
    ck_assert_uint_gt(st[0].photons_stored, 0);
    ck_assert_uint_gt(st[0].photon_lookups, 0);
    /* A region (rows 7 .. 18) traces the same photons: the frame's rows. */
    o.y0 = 7;
    o.y1 = 19;
    ck_assert_int_eq(ray_render(s, &cam, &o, img[1], NULL), RAY_OK);
    ck_assert(memcmp(img[1], img[0] + 3 * W * 7,
                     sizeof(float) * 3 * W * 12) == 0);
    o.y0 = o.y1 = 0;
    /* The caustics change the picture (the photons are not lost). */
    o.photons = 0;
    ck_assert_int_eq(ray_render(s, &cam, &o, img[1], NULL), RAY_OK);
    ck_assert(memcmp(img[1], img[0], sizeof img[0]) != 0);
    ray_scene_free(s);
}
END_TEST

START_TEST(bad_photon_settings_should_be_refused)
{
    static float img[3 * W * H];
    static const double bad_radius[] = {-1, -1e-300, HUGE_VAL,
                                        1e-200, 1e200};
    ray_camera cam;
    ray_scene *s = caustics_scene(&cam);
    ray_render_options o;
    ray_photon_map *map = (ray_photon_map *)&o;    /* a sentinel */
    size_t k;

    o = (ray_render_options){.width = W, .height = H};
    ck_assert_uint_eq(o.photons, 0);                /* the default: off */
    ck_assert(o.photon_radius == 0);                /* automatic */
    memset(img, 0x5a, sizeof img);
    /* 0 photons: a render without caustics, but no map to build. */
    ck_assert_int_eq(ray_photon_map_build(s, &o, &map), RAY_EINVAL);
    ck_assert_ptr_eq(map, (ray_photon_map *)&o);
    o.photons = RAY_MAX_PHOTONS + 1;
    ck_assert_int_eq(ray_photon_map_build(s, &o, &map), RAY_EINVAL);
    ck_assert_int_eq(ray_render(s, &cam, &o, img, NULL), RAY_EINVAL);
    o.photons = 1000;
    o.photon_radius = (double)NAN;
    ck_assert_int_eq(ray_photon_map_build(s, &o, &map), RAY_EINVAL);
    ck_assert_int_eq(ray_render(s, &cam, &o, img, NULL), RAY_EINVAL);
    /* Negative, infinite, and radii whose disk area pi r^2 underflows
    ** to 0 or overflows: refused. */
    for (k = 0; k < sizeof bad_radius / sizeof bad_radius[0]; k++) {
        o.photon_radius = bad_radius[k];
        ck_assert_int_eq(ray_photon_map_build(s, &o, &map), RAY_EINVAL);
        ck_assert_int_eq(ray_render(s, &cam, &o, img, NULL), RAY_EINVAL);
    }
    ck_assert_ptr_eq(map, (ray_photon_map *)&o);
    {
        unsigned char want[sizeof img];
        memset(want, 0x5a, sizeof want);
        ck_assert(memcmp(img, want, sizeof img) == 0);  /* untouched */
    }
    ray_scene_free(s);
}
END_TEST

static int scatter_calls;

/* A user scatter that breaks the contract: tries to trace (refused),
** and answers a NaN weight (the photon stops). */
static int rogue_scatter(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                         ray_vec3 *dir, ray_rgb *weight)
{
    ray_rgb c;
    (void)ud;
    scatter_calls++;
    ck_assert_int_eq(ray_trace(ctx, a->ray, RAY_KIND_REFLECTION, 1.0, &c),
                     RAY_EEFFECT);
    *dir = ray_reflect(a->ray->dir, a->normal);
    *weight = rgb((double)NAN, 1, 1);
    return 1;
}

START_TEST(misuse_should_be_answered)
{
    ray_scene *s = mirror_scene(), *other = mirror_scene(), *rogue;
    ray_photon_map *map = build(s, 1000, 0, 1), *got = NULL;
    ray_render_options o;
    ray_ctx *ctx, *octx;
    ray_shade_args args;
    ray_hit hit;
    ray_rgb e = {7, 7, 7};
    ray_material probe = probe_material(), m = probe_material();
    ray_light l = point_light(vec(0, 1, 0), rgb(1, 1, 1));
    unsigned pm, mm;

    o = (ray_render_options){.width = 1, .height = 1};
    o.photons = 10;
    ck_assert_int_eq(ray_photon_map_build(NULL, &o, &got), RAY_EINVAL);
    ck_assert_int_eq(ray_photon_map_build(s, NULL, &got), RAY_EINVAL);
    ck_assert_int_eq(ray_photon_map_build(s, &o, NULL), RAY_EINVAL);
    ck_assert_ptr_null(got);
    ck_assert_int_eq(ray_ctx_new(s, 0, &ctx), RAY_OK);
    ck_assert_int_eq(ray_ctx_new(other, 0, &octx), RAY_OK);
    ck_assert_int_eq(ray_ctx_set_photon_map(NULL, map), RAY_EINVAL);
    ck_assert_int_eq(ray_ctx_set_photon_map(octx, map), RAY_EINVAL);
    ck_assert_int_eq(ray_ctx_set_photon_map(ctx, map), RAY_OK);
    ck_assert_int_eq(ray_ctx_set_photon_map(ctx, NULL), RAY_OK);
    memset(&args, 0, sizeof args);
    memset(&hit, 0, sizeof hit);
    args.hit = &hit;
    ck_assert_int_eq(ray_caustics_at(NULL, &args, &e), RAY_EINVAL);
    ck_assert_int_eq(ray_caustics_at(ctx, NULL, &e), RAY_EINVAL);
    ck_assert_int_eq(ray_caustics_at(ctx, &args, NULL), RAY_EINVAL);
    args.hit = NULL;
    ck_assert_int_eq(ray_caustics_at(ctx, &args, &e), RAY_EINVAL);
    ck_assert(e.r == 7 && e.g == 7 && e.b == 7);      /* untouched */
    /* Outside a callback (no RAY_EFFECT_CAUSTICS declared): zero. */
    args.hit = &hit;
    ck_assert_int_eq(ray_ctx_set_photon_map(ctx, map), RAY_OK);
    ck_assert_int_eq(ray_caustics_at(ctx, &args, &e), RAY_OK);
    ck_assert(e.r == 0 && e.g == 0 && e.b == 0);
    ray_photon_map_free(NULL);
    ray_ctx_free(ctx);
    ray_ctx_free(octx);
    ray_photon_map_free(map);
    /* Not committed (changed since): refused with RAY_ESTATE, as the
    ** queries and ray_render answer. */
    ck_assert_int_eq(ray_scene_set_ambient(s, rgb(0, 0, 0)), RAY_OK);
    ck_assert_int_eq(ray_photon_map_build(s, &o, &got), RAY_ESTATE);
    ck_assert_ptr_null(got);
    ray_scene_free(s);
    ray_scene_free(other);
    /* A scatter callback that traces and answers NaN: refused, stopped. */
    m.shade = black;
    m.effects = RAY_EFFECT_SCATTER;
    m.scatter = rogue_scatter;
    ck_assert_int_eq(ray_scene_new(&rogue, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(rogue, &probe, &pm), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(rogue, &m, &mm), RAY_OK);
    ck_assert_int_eq(ray_scene_add_plane(rogue, vec(0, 0, 0), vec(0, 1, 0),
                                         pm, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(rogue, vec(0, 2, 0), 0.5, mm,
                                          NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_light(rogue, &l, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(rogue), RAY_OK);
    scatter_calls = 0;
    map = build(rogue, 2000, 0, 1);
    ck_assert_int_gt(scatter_calls, 0);
    ck_assert_int_eq(ray_ctx_new(rogue, 0, &ctx), RAY_OK);
    ck_assert_int_eq(ray_ctx_set_photon_map(ctx, map), RAY_OK);
    e = floor_irradiance(ctx, 0, 0);
    ck_assert(e.r == 0 && e.g == 0 && e.b == 0);       /* none stored */
    ray_ctx_free(ctx);
    ray_photon_map_free(map);
    ray_scene_free(rogue);
}
END_TEST

Suite *caustics_suite(void)
{
    Suite *s = suite_create("caustics");
    TCase *tc = tcase_create("core");

    tcase_set_timeout(tc, 60);
    tcase_add_test(tc, mirror_should_send_its_reflected_power_to_the_floor);
    tcase_add_test(tc, disk_estimate_should_give_the_mirror_image_irradiance);
    tcase_add_test(tc, photons_of_unequal_lights_should_be_shared_by_power);
    tcase_add_test(tc, automatic_radius_should_follow_the_rule_at_any_count);
    tcase_add_test(tc, glass_sphere_should_focus_its_caustic_below_its_centre);
    tcase_add_test(tc, scene_without_specular_should_trace_no_photon);
    tcase_add_test(tc, effect_analysis_should_need_light_scatterer_and_gatherer);
    tcase_add_test(tc, scatter_should_be_read_only_with_its_effect_bit);
    tcase_add_test(tc, instanced_mirror_should_make_caustics);
    tcase_add_test(tc, caustics_should_be_the_same_bytes_at_any_thread_count);
    tcase_add_test(tc, bad_photon_settings_should_be_refused);
    tcase_add_test(tc, misuse_should_be_answered);
    suite_add_tcase(s, tc);
    return s;
}
