/* SPDX-License-Identifier: MIT */
/*
** check_selfhit.c -- no acne: rays leaving a surface never hit it again
** within its rounding error, for every primitive kind, placement and
** offset (tests/selfhit.h), through the bare functions and the scene; a
** diffuse floor at y = 0 (and walls at x = 0, z = 0) under a point light
** renders every lit pixel at its analytic value; the mesh floor given as
** floats (ray_mesh's positions) has no acne either; ray_sphere's hit does
** not depend on the direction's length.
*/
#include <math.h>
#include <float.h>
#include <stdlib.h>
#include <string.h>

#include "tests.h"
#include "selfhit.h"

/*
** Every kind, both placements, offsets 0, 0.5, 1e5, 1e6, bare and scene:
** zero self-hits (shadow, reflection, refraction).  Before the hit tests
** bounded t's rounding error, the watertight triangle and the mesh quad
** failed here (18 to 1,066 per 4,000 camera hits at offsets 0 and 0.5).
** The curved surfaces' iterative kinds get fewer rays: each costs 20 to
** 60 us.  At least a quarter of the camera rays must hit, so the test
** cannot pass by missing.
*/
START_TEST(selfhit_should_be_zero_for_every_kind)
{
    sh_kind k = (sh_kind)_i;
    int n = (k == SH_IMPLICIT || k == SH_BEZIER) ? 120 : 1500;
    int rot, o, path;

    for (rot = 0; rot < 2; rot++)
        for (o = 0; o < SH_OFFSETS; o++)
            for (path = 0; path < 2; path++) {
                sh_prim p;
                sh_counts c;
                ray_scene *s = NULL;

                sh_place(&p, k, sh_offsets[o], rot);
                if (path == 1) {
                    s = sh_scene(&p);
                    ck_assert_ptr_nonnull(s);
                }
                sh_run(&p, s, n, 99 + (uint64_t)(o + 4 * rot), &c);
                ray_scene_free(s);
                ck_assert_msg(c.rays >= n / 4, "%s: only %ld hits",
                              sh_kind_name[k], c.rays);
                ck_assert_msg(c.shadow == 0 && c.reflect == 0 &&
                                  c.refract == 0,
                              "%s %s offset %g %s: self-hits shadow %ld "
                              "reflect %ld refract %ld of %ld",
                              sh_kind_name[k], rot ? "rotated" : "aligned",
                              sh_offsets[o], path ? "scene" : "bare",
                              c.shadow, c.reflect, c.refract, c.rays);
            }
}
END_TEST

/*
** The floor y = 0 itself, without ray_spawn: a ray starting at the hit
** point (exactly on the floor: every vertex has y = 0, so p.y = 0 exactly
** and p_err.y = 0) hits the floor at exact t = 0.  The tests must not
** report the rounding noise around it as a hit, for any flat kind, in
** either direction (tmin = 0).
*/
START_TEST(floor_rays_from_the_hit_point_should_not_rehit)
{
    int k, i;

    for (k = 0; k < SH_KINDS; k++) {
        sh_prim p;
        ray_scene *s;
        rng g = {5};
        long hits = 0;

        if (!sh_flat((sh_kind)k))
            continue;
        sh_place(&p, (sh_kind)k, 0, 0);
        s = sh_scene(&p);
        ck_assert_ptr_nonnull(s);
        for (i = 0; i < 3000; i++) {
            double x = 180 * rng_unit(&g) - 90, z = 180 * rng_unit(&g) - 90;
            ray_ray r, out;
            ray_hit h, h2;
            r.org = vec(x + 3, 0.01 + 5 * rng_unit(&g), z - 4);
            r.dir = vec(x - r.org.x, -r.org.y, z - r.org.z);
            r.tmin = 0, r.tmax = HUGE_VAL;
            if (!sh_bare(&p, &r, &h))
                continue;
            hits++;
            ck_assert(h.p.y == 0);
            out.org = h.p, out.tmin = 0, out.tmax = HUGE_VAL;
            out.dir = ray_reflect(r.dir, h.n);
            ck_assert_msg(!sh_bare(&p, &out, &h2), "%s: reflected re-hit",
                          sh_kind_name[k]);
            ck_assert_int_eq(ray_intersect(s, &out, &h2, NULL), 0);
            out.dir = r.dir;
            ck_assert_msg(!sh_bare(&p, &out, &h2), "%s: through re-hit",
                          sh_kind_name[k]);
            ck_assert_int_eq(ray_occluded(s, &out, NULL), 0);
        }
        ck_assert_int_gt(hits, 1000);
        ray_scene_free(s);
    }
}
END_TEST

/*
** The mesh quad floor of selfhit.h as a game gives it: its four corners
** rounded to float in an interleaved vertex buffer (position, normal,
** texture coordinates: stride 32) with 16-bit indices; at offsets 0, 0.5
** and 1e5, axis-aligned (the floor y = offset: the floats are exact) and
** rotated, with the watertight test and with Cramer's rule.  Zero
** self-hits of the shadow, reflection and refraction rays that sh_run
** spawns with ray_spawn_to and ray_spawn.  Rotated, each corner moves
** by at most sqrt(3) 2^-24 of its largest coordinate (0.0103 at 1e5),
** which tilts a triangle (shortest altitude 141) by at most 2 * 0.0103 /
** 141 rad = 0.0084 degrees (measured: 0.0007) and folds the quad by
** twice that: the camera rays, 0.05 degrees or more above the exact
** floor, meet either triangle at over 0.03 degrees and leave it away
** from the other, so any hit is acne, as for every flat kind.
*/
typedef struct floor_vertex {
    float pos[3], nrm[3], uv[2];
} floor_vertex;

START_TEST(float_floor_should_not_rehit)
{
    static const uint16_t quad[6] = {0, 1, 2, 0, 2, 3};
    sh_kind kind = _i & 1 ? SH_MESH_CRAMER : SH_MESH;
    int rot = (_i >> 1) & 1, o = _i >> 2, n = 1500, k;
    floor_vertex vb[4];
    sh_prim p;
    sh_counts c;
    ray_mesh m;
    ray_scene *s;

    sh_place(&p, kind, sh_offsets[o], rot);
    memset(vb, 0, sizeof vb);
    for (k = 0; k < 4; k++) {
        vb[k].pos[0] = (float)p.tri[k].x;
        vb[k].pos[1] = (float)p.tri[k].y;
        vb[k].pos[2] = (float)p.tri[k].z;
        vb[k].nrm[1] = 1.0f;
    }
    memset(&m, 0, sizeof m);
    m.positions = vb;
    m.position_stride = sizeof vb[0];
    m.position_type = RAY_FLOAT32;
    m.vertex_count = 4;
    m.index_data = quad;
    m.index_type = RAY_UINT16;
    m.triangle_count = 2;
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_mesh(s, &m, RAY_NO_MATERIAL, NULL),
                     RAY_OK);
    ck_assert_int_eq(ray_scene_set_watertight(s, kind == SH_MESH), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    sh_run(&p, s, n, 199 + (uint64_t)_i, &c);
    ray_scene_free(s);
    ck_assert_msg(c.rays >= n / 4, "only %ld hits", c.rays);
    ck_assert_msg(c.shadow == 0 && c.reflect == 0 && c.refract == 0,
                  "float %s %s offset %g: self-hits shadow %ld reflect %ld "
                  "refract %ld of %ld", sh_kind_name[kind],
                  rot ? "rotated" : "aligned", sh_offsets[o], c.shadow,
                  c.reflect, c.refract, c.rays);
}
END_TEST

/*
** ray_sphere scales the direction by a power of two: 2^-600 and 2^600
** times a direction give bit for bit the hit of the direction, with t
** scaled exactly; 1e-200 and 1e200 times it (not powers of two: each
** component rounds by up to half an ulp, which turns the ray by up to
** 2^-53 sqrt(3) and moves the hit along the surface by that times
** dist / |cos| at distance dist and incidence cosine cos) give the same
** hit or miss and the same point within twice the hit's own error bound
** p_err plus that movement (4 ulps of dist / |cos|, to be safe) plus the
** rounding of the ray point org + t dir that ray_sphere projects onto the
** sphere (an ulp or two of its coordinates, here up to 5e4, which turns
** the normal and so slides p along the surface: 4 ulps of the largest).
*/
START_TEST(sphere_should_not_depend_on_direction_length)
{
    rng g = {3};
    int i, hits = 0;

    for (i = 0; i < 4000; i++) {
        ray_vec3 c = vec(1e5 * (rng_unit(&g) - 0.5), 2, 3);
        ray_ray r, rs;
        ray_hit h, hs;
        double len[4] = {0x1p-600, 0x1p600, 1e-200, 1e200};
        int k, hit;

        r.org = vec(c.x + 4, c.y + 5 * rng_unit(&g), c.z - 6);
        r.dir = vec(c.x + 2 * rng_unit(&g) - 1 - r.org.x,
                    c.y + 2 * rng_unit(&g) - 1 - r.org.y, c.z - r.org.z);
        r.tmin = 0, r.tmax = HUGE_VAL;
        hit = ray_sphere(&r, c, 1.0, &h);
        hits += hit;
        for (k = 0; k < 4; k++) {
            rs = r;
            rs.dir = vec(r.dir.x * len[k], r.dir.y * len[k], r.dir.z * len[k]);
            ck_assert_int_eq(ray_sphere(&rs, c, 1.0, &hs), hit);
            if (!hit)
                continue;
            if (k < 2) {
                ck_assert(hs.t == h.t / len[k]);
                ck_assert(hs.p.x == h.p.x && hs.p.y == h.p.y &&
                          hs.p.z == h.p.z);
            } else {
                double dl = sqrt(r.dir.x * r.dir.x + r.dir.y * r.dir.y +
                                 r.dir.z * r.dir.z);
                double cosine = fabs(h.n.x * r.dir.x + h.n.y * r.dir.y +
                                     h.n.z * r.dir.z) / dl;
                double turn = 4 * DBL_EPSILON * h.t * dl / cosine +
                              4 * DBL_EPSILON * (sh_maxabs(r.org) +
                                                 sh_maxabs(c));
                ck_assert(fabs(hs.p.x - h.p.x) <= 2 * h.p_err.x + turn);
                ck_assert(fabs(hs.p.y - h.p.y) <= 2 * h.p_err.y + turn);
                ck_assert(fabs(hs.p.z - h.p.z) <= 2 * h.p_err.z + turn);
            }
        }
    }
    ck_assert_int_gt(hits, 1000);
    /* A subnormal direction (2^-1060): its scale 2^1060 overflows a
    ** double, so the scaling is by exponent (ldexp), not by a factor;
    ** the hit is the unit direction's, t times 2^1060 exactly (tiny
    ** geometry keeps that t finite). */
    {
        ray_ray u, s;
        ray_hit hu, hs;
        u.org = vec(0, 0, 5e-20), u.dir = vec(0, 0, -1);
        u.tmin = 0, u.tmax = HUGE_VAL;
        s = u;
        s.dir = vec(0, 0, -0x1p-1060);
        ck_assert_int_eq(ray_sphere(&u, vec(0, 0, 0), 1e-20, &hu), 1);
        ck_assert_int_eq(ray_sphere(&s, vec(0, 0, 0), 1e-20, &hs), 1);
        ck_assert(hs.t == ldexp(hu.t, 1060));
        ck_assert(hs.p.z == hu.p.z);
    }
}
END_TEST

/* ------------------------------------------- the floor, rendered */

/* Coordinates with the wall's normal axis first moved to y: axis 1 is
** the floor y = 0, axis 0 the wall x = 0, axis 2 the wall z = 0. */
static ray_vec3 on_axis(int axis, double a, double up, double b)
{
    return axis == 1 ? vec(a, up, b) : axis == 0 ? vec(up, a, b)
                                                 : vec(a, b, up);
}

static double axis_of(ray_vec3 v, int axis)
{
    return axis == 0 ? v.x : axis == 1 ? v.y : v.z;
}

static ray_vec3 cross3(ray_vec3 a, ray_vec3 b)
{
    return vec(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z,
               a.x * b.y - a.y * b.x);
}

static ray_vec3 unit3(ray_vec3 a)
{
    double l = sqrt(a.x * a.x + a.y * a.y + a.z * a.z);
    return vec(a.x / l, a.y / l, a.z / l);
}

/*
** A 64 x 48 render, one sample per pixel (the pixel centre: ray_render(3))
** of a diffuse quad (kd = 0.8, two mesh triangles or a plane) lit by a
** point light of intensity 30 (inverse-square falloff), no ambient.  The
** analytic value of a pixel: its camera ray (built as ray_render(3)
** documents the pinhole camera) meets the wall at p; the value is
** kd I cos / d^2 with cos = n.(L - p)/d.  Acne shows as black (shadowed)
** pixels where this is positive.  Tolerance 1e-5 relative: the image is
** float (2^-24 = 6e-8) and the test's camera ray and the renderer's
** differ by a few double roundings (1e-15); acne is off by 100%.
*/
static void render_wall(int axis, int as_plane)
{
    enum { W = 64, H = 48 };
    static const unsigned quad[6] = {0, 1, 2, 0, 2, 3};
    ray_phong_params pp;
    ray_material m;
    ray_scene *s;
    ray_light l;
    ray_camera cam;
    ray_render_options o;
    ray_vec3 v[4], w, u, vv, normal = on_axis(axis, 0, 1, 0);
    ray_mesh mesh;
    float *img = malloc(3 * W * H * sizeof *img);
    double half, half_w;
    unsigned mat;
    int x, y, lit = 0;

    ck_assert_ptr_nonnull(img);
    memset(&pp, 0, sizeof pp);
    pp.diffuse.r = pp.diffuse.g = pp.diffuse.b = 0.8;
    m = ray_material_phong(&pp);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_material(s, &m, &mat), RAY_OK);
    v[0] = on_axis(axis, -4, 0, -4), v[1] = on_axis(axis, -4, 0, 4);
    v[2] = on_axis(axis, 4, 0, 4), v[3] = on_axis(axis, 4, 0, -4);
    memset(&mesh, 0, sizeof mesh);
    mesh.vertices = v, mesh.vertex_count = 4;
    mesh.indices = quad, mesh.triangle_count = 2;
    if (as_plane)
        ck_assert_int_eq(ray_scene_add_plane(s, vec(0, 0, 0), normal, mat,
                                             NULL), RAY_OK);
    else
        ck_assert_int_eq(ray_scene_add_mesh(s, &mesh, mat, NULL), RAY_OK);
    memset(&l, 0, sizeof l);
    l.kind = RAY_LIGHT_POINT;
    l.position = on_axis(axis, 3, 6, 4);
    l.intensity.r = l.intensity.g = l.intensity.b = 30;
    ck_assert_int_eq(ray_scene_add_light(s, &l, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    memset(&cam, 0, sizeof cam);
    cam.position = on_axis(axis, 0.5, 3, 5);
    cam.look_at = on_axis(axis, 0, 0, 0);
    cam.up = on_axis(axis, 0, 1, 0);
    cam.vfov = 60;
    o = (ray_render_options){.width = W, .height = H};
    ck_assert_int_eq(ray_render(s, &cam, &o, img, NULL), RAY_OK);

    w = unit3(vec(cam.position.x - cam.look_at.x, cam.position.y -
                  cam.look_at.y, cam.position.z - cam.look_at.z));
    u = unit3(cross3(cam.up, w));
    vv = cross3(w, u);
    half = tan(cam.vfov * 3.14159265358979323846 / 360.0);
    half_w = half * W / H;
    for (y = 0; y < H; y++)
        for (x = 0; x < W; x++) {
            double px = (2.0 * (x + 0.5) / W - 1.0) * half_w;
            double py = (1.0 - 2.0 * (y + 0.5) / H) * half;
            ray_vec3 d = vec(u.x * px + vv.x * py - w.x,
                             u.y * px + vv.y * py - w.y,
                             u.z * px + vv.z * py - w.z), p, to;
            double t = -axis_of(cam.position, axis) / axis_of(d, axis);
            double want = 0, dist, got = (double)img[3 * (y * W + x)];

            p = vec(cam.position.x + t * d.x, cam.position.y + t * d.y,
                    cam.position.z + t * d.z);
            if (t > 0 && (as_plane || (fabs(p.x) < 3.99 && fabs(p.y) < 3.99 &&
                                       fabs(p.z) < 3.99))) {
                to = vec(l.position.x - p.x, l.position.y - p.y,
                         l.position.z - p.z);
                dist = sqrt(to.x * to.x + to.y * to.y + to.z * to.z);
                want = 0.8 * 30 * axis_of(to, axis) / dist / (dist * dist);
                lit++;
            } else if (!as_plane && t > 0 && fabs(p.x) < 4.01 &&
                       fabs(p.y) < 4.01 && fabs(p.z) < 4.01)
                continue;       /* the quad's rim: the test's p is inexact */
            ck_assert_msg(fabs(got - want) <= 1e-5 * want + 1e-7,
                          "axis %d %s pixel (%d, %d): %.9g, analytic %.9g",
                          axis, as_plane ? "plane" : "mesh", x, y, got, want);
        }
    ck_assert_int_gt(lit, W * H / 4);
    ray_scene_free(s);
    free(img);
}

START_TEST(floor_and_walls_should_render_their_analytic_light)
{
    int axis;

    for (axis = 0; axis < 3; axis++) {
        render_wall(axis, 0);
        render_wall(axis, 1);
    }
}
END_TEST

/*
** ray_surface_point on a kind without surface points (a torus, an
** implicit surface, a Bezier patch, a box, a capsule, user geometry)
** answers RAY_EKIND, its own status ("not available for this kind of
** geometry"), not RAY_ENOTSUP ("not supported by this build": no build
** has them), in the scene itself and through an instance, with *hit
** untouched; every other kind never answers RAY_EKIND.  Coordinates
** (0.25, 0.25) are finite, so the kind decides (check_overlap.c holds
** the order of the statuses).
*/
START_TEST(surface_point_should_say_which_kinds_have_no_points)
{
    sh_kind k = (sh_kind)_i;
    int none = k == SH_TORUS || k == SH_IMPLICIT || k == SH_BEZIER ||
               k == SH_BOX || k == SH_CAPSULE || k == SH_USER;
    ray_transform t;
    ray_scene *s, *top;
    ray_hit h;
    sh_prim p;
    unsigned inst = RAY_INVALID_ID;
    int rc;

    sh_place(&p, k, 0, 0);
    s = sh_scene(&p);
    ck_assert_ptr_nonnull(s);
    ck_assert_int_eq(ray_scene_new(&top, NULL, NULL), RAY_OK);
    ray_transform_identity(&t);
    t.m[0][3] = 10;                  /* a translation: world space moves */
    /* A plane has no bounds: no instance takes it (ray.h). */
    if (k != SH_PLANE)
        ck_assert_int_eq(ray_scene_add_instance(top, s, &t, &inst), RAY_OK);
    ck_assert_int_eq(ray_scene_commit(top), RAY_OK);
    hit_poison(&h);
    rc = ray_surface_point(s, 0, 0, RAY_INVALID_ID, 0.25, 0.25, &h);
    if (none) {
        ck_assert_msg(rc == RAY_EKIND, "%s: %d", sh_kind_name[k], rc);
        ck_assert(hit_is_poisoned(&h));
        ck_assert_int_eq(ray_surface_point(top, 0, 0, inst, 0.25, 0.25, &h),
                         RAY_EKIND);
        ck_assert(hit_is_poisoned(&h));
    } else {
        ck_assert_msg(rc != RAY_EKIND, "%s: %d", sh_kind_name[k], rc);
        if (k != SH_PLANE)
            ck_assert_int_ne(ray_surface_point(top, 0, 0, inst, 0.25, 0.25,
                                               &h), RAY_EKIND);
    }
    ray_scene_free(top);
    ray_scene_free(s);
}
END_TEST

/*
** Issue 38: a query with options that can hide geometry (a nonzero
** ignore_mask) takes the gated path, which asks each kind of primitive
** through the scene's dispatch (ray__prim_intersect, filling the whole
** record at once) instead of the ungated path's candidates and deferred
** fills; it must find what the ungated query finds, for every kind (the
** Bezier patch also as the ray_parametric_surface it makes, added with
** ray_scene_add_parametric: a kind of its own in the scene).  A mask of
** 1 hides nothing here (every primitive keeps the default mask, all
** bits).  Nine rays down the placement's local -y, fanned 0.3 apart
** (through the curved kinds, and near the centre of the flat ones), and
** three beside every bounded kind: the same answer, the same ids, the
** same t within 1e-12 relative (the sphere's t comes from two formulas
** of the same root; the others from one), and ray_occluded agrees.
*/
static void masked_should_match(ray_scene *s, const sh_prim *p,
                                const char *name)
{
    ray_query q;
    int i, j;

    memset(&q, 0, sizeof q);
    q.ignore_mask = 1;
    for (i = -1; i <= 2; i++)
        for (j = -1; j <= 1; j++) {
            /* i == 2: a ray well beside every bounded kind (x = 250). */
            double x = i == 2 ? 250 : 0.3 * i, z = 0.3 * j;
            ray_ray r;
            ray_hit a, b;
            int ra, rb;

            r.org = sh_world(p, x, 5, z);
            r.dir = vec(-p->ey.x, -p->ey.y, -p->ey.z);
            r.tmin = 0;
            r.tmax = HUGE_VAL;
            hit_poison(&a);
            hit_poison(&b);
            ra = ray_intersect(s, &r, &a, NULL);
            rb = ray_intersect(s, &r, &b, &q);
            ck_assert_msg(ra == rb, "%s (%d, %d): %d vs %d", name, i, j, ra,
                          rb);
            ck_assert_int_eq(ray_occluded(s, &r, &q), ra);
            if (ra != 1) {
                ck_assert(hit_is_poisoned(&b));
                continue;
            }
            ck_assert_uint_eq(a.geom_id, b.geom_id);
            ck_assert_uint_eq(a.prim_id, b.prim_id);
            ck_assert_uint_eq(b.inst_id, RAY_INVALID_ID);
            ck_assert_msg(fabs(a.t - b.t) <= 1e-12 * a.t,
                          "%s: t %.17g vs %.17g", name, a.t, b.t);
        }
}

START_TEST(masked_queries_should_find_what_plain_ones_find)
{
    sh_kind k = (sh_kind)_i;
    ray_scene *s;
    sh_prim p;

    sh_place(&p, k, 0.5, 1);
    s = sh_scene(&p);
    ck_assert_ptr_nonnull(s);
    masked_should_match(s, &p, sh_kind_name[k]);
    ray_scene_free(s);
    if (k == SH_BEZIER) {
        ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_parametric(s, &p.bezier,
                                                  RAY_NO_MATERIAL, NULL),
                         RAY_OK);
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        masked_should_match(s, &p, "parametric (the Bezier patch's)");
        ray_scene_free(s);
    }
}
END_TEST

Suite *selfhit_suite(void)
{
    Suite *s = suite_create("selfhit");
    TCase *tc = tcase_create("acne");

    tcase_set_timeout(tc, 600);
    tcase_add_loop_test(tc, selfhit_should_be_zero_for_every_kind, 0,
                        SH_KINDS);
    tcase_add_test(tc, floor_rays_from_the_hit_point_should_not_rehit);
    tcase_add_loop_test(tc, masked_queries_should_find_what_plain_ones_find,
                        0, SH_KINDS);
    /* offsets 0, 0.5, 1e5 (sh_offsets[0..2]) x placements x tests */
    tcase_add_loop_test(tc, float_floor_should_not_rehit, 0, 12);
    tcase_add_test(tc, sphere_should_not_depend_on_direction_length);
    tcase_add_test(tc, floor_and_walls_should_render_their_analytic_light);
    tcase_add_loop_test(tc,
                        surface_point_should_say_which_kinds_have_no_points,
                        0, SH_KINDS);
    suite_add_tcase(s, tc);
    return s;
}
