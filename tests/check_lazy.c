/* SPDX-License-Identifier: MIT */
/*
** check_lazy.c -- the scene queries fill the record of the nearest hit
** alone (issue 17): spheres and planes are tested for t during the
** traversal and filled once, at the end.  The answers must be those of
** the bare primitives, bit for bit (API-NOTES 11: a ray gives the same
** hit whatever path it takes), which these tests check against
** ray_sphere and ray_plane called directly on the same rays; and a
** render fills a sphere's texture coordinates only when its material
** reads them.
*/
#include "tests.h"

#define N_SPHERES 24
#define N_PLANES 3

typedef struct lazy_world {
    ray_scene *s;
    ray_vec3 c[N_SPHERES];
    double r[N_SPHERES];
    ray_vec3 pp[N_PLANES], pn[N_PLANES];
    unsigned sphere_id[N_SPHERES], plane_id[N_PLANES];
} lazy_world;

/*
** Spheres of radii 0.05 to 3 in [-10, 10]^3 (overlapping), and planes
** whose unit normals v3_normalize leaves as they are (components 0 or of
** one magnitude, 1/sqrt(2) or 1/sqrt(3) computed as the library computes
** 1/|n|): the scene stores the normal normalised, and ray_plane called
** directly must see the same one.
*/
static void lazy_world_make(lazy_world *w)
{
    rng g = {17};
    double s2 = 1.0 / sqrt(2.0), s3 = 1.0 / sqrt(3.0);
    int i;

    ck_assert_int_eq(ray_scene_new(&w->s, NULL, NULL), RAY_OK);
    w->pp[0] = vec(0, -11, 0);
    w->pn[0] = vec(0, 1, 0);
    w->pp[1] = vec(12, 0.25, -3);
    w->pn[1] = vec(-s2, 0, s2);
    w->pp[2] = vec(-12, 1, 2);
    w->pn[2] = vec(s3, -s3, s3);
    for (i = 0; i < N_PLANES; i++)
        ck_assert_int_eq(ray_scene_add_plane(w->s, w->pp[i], w->pn[i],
                                             RAY_NO_MATERIAL,
                                             &w->plane_id[i]), RAY_OK);
    for (i = 0; i < N_SPHERES; i++) {
        w->c[i] = rng_point(&g, -10, 10);
        w->r[i] = rng_range(&g, 0.05, 3);
        ck_assert_int_eq(ray_scene_add_sphere(w->s, w->c[i], w->r[i],
                                              RAY_NO_MATERIAL,
                                              &w->sphere_id[i]), RAY_OK);
    }
    ck_assert_int_eq(ray_scene_commit(w->s), RAY_OK);
}

/*
** The nearest hit by the bare primitives, each called on the whole ray:
** a primitive returns its nearest root in (tmin, tmax), so the smallest of
** their t is what any order of tests that shrinks tmax finds.  *tie: two
** primitives gave the same t (the scene then keeps whichever it tested
** first; the rays below are checked only where there is none).
*/
static int lazy_expected(const lazy_world *w, const ray_ray *r, ray_hit *best,
                         int *tie)
{
    int found = 0, i;
    ray_hit h;

    *tie = 0;
    for (i = 0; i < N_SPHERES + N_PLANES; i++) {
        int hit = i < N_SPHERES
                      ? ray_sphere(r, w->c[i], w->r[i], &h)
                      : ray_plane(r, w->pp[i - N_SPHERES],
                                  w->pn[i - N_SPHERES], &h);
        if (!hit)
            continue;
        h.geom_id = i < N_SPHERES ? w->sphere_id[i]
                                  : w->plane_id[i - N_SPHERES];
        h.prim_id = 0;
        if (found && h.t == best->t)
            *tie = 1;
        if (!found || h.t < best->t) {
            *best = h;
            found = 1;
        }
    }
    return found;
}

/* Ray k of the property test: from a random point, grazing a sphere,
** starting on a sphere (within the rounding of c + R n), starting on a
** plane, or from far away; tmin 0, a small positive one or a negative
** one; tmax unbounded or finite. */
static ray_ray lazy_ray(const lazy_world *w, rng *g, int k)
{
    int i = (int)(rng_unit(g) * N_SPHERES);
    ray_vec3 n = rng_dir(g);
    ray_ray r;

    switch (k % 5) {
    case 0:
        r = ray_from(rng_point(g, -14, 14), rng_dir(g));
        break;
    case 1: {   /* along a tangent line, from either side */
        ray_vec3 t = vcross(n, rng_dir(g));
        double len = vlen(t);
        t = vscale(t, 1.0 / len);
        r = ray_from(vadd(vadd(w->c[i], vscale(n, w->r[i])),
                          vscale(t, -rng_range(g, 0.5, 20))),
                     vscale(t, rng_range(g, 0.1, 10)));
        break;
    }
    case 2:     /* leaving a sphere, outward or inward */
        r = ray_from(vadd(w->c[i], vscale(n, w->r[i])),
                     rng_unit(g) < 0.5 ? rng_dir(g) : vscale(n, -1));
        break;
    case 3: {   /* on a plane */
        int j = (int)(rng_unit(g) * N_PLANES);
        ray_vec3 t1 = vcross(w->pn[j], rng_dir(g));
        r = ray_from(vadd(w->pp[j], vscale(t1, rng_range(g, 0, 8))),
                     rng_dir(g));
        break;
    }
    default:
        r = ray_from(vscale(rng_dir(g), 1e3), rng_dir(g));
        break;
    }
    r.dir = vscale(r.dir, rng_range(g, 0.01, 100));
    r.tmin = k % 7 == 0 ? 1e-6 : (k % 11 == 0 ? -1.0 : 0.0);
    if (k % 3 == 0)
        r.tmax = rng_range(g, 0.1, 30);
    return r;
}

/* Thousands of rays: ray_intersect's hit is the bare primitives', every
** field bit for bit, and ray_occluded says hit exactly when they do. */
START_TEST(scene_hits_should_be_the_bare_primitives_bit_for_bit)
{
    lazy_world w;
    rng g = {18};
    int k, checked = 0, hits = 0;

    lazy_world_make(&w);
    for (k = 0; k < 20000; k++) {
        ray_ray r = lazy_ray(&w, &g, k);
        ray_hit got, want;
        int tie, expect = lazy_expected(&w, &r, &want, &tie);
        int rc = ray_intersect(w.s, &r, &got, NULL);

        ck_assert_int_eq(ray_occluded(w.s, &r, NULL), expect);
        if (tie)
            continue;
        checked++;
        ck_assert_int_eq(rc, expect);
        if (!expect)
            continue;
        hits++;
        ck_assert_msg(hit_same(&got, &want),
                      "ray %d: t %.17g vs %.17g, geom %u vs %u", k, got.t,
                      want.t, got.geom_id, want.geom_id);
    }
    /* The rays must exercise both answers, not pass vacuously. */
    ck_assert_int_gt(checked, 19000);
    ck_assert_int_gt(hits, 5000);
    ck_assert_int_gt(checked - hits, 2000);
    ray_scene_free(w.s);
}
END_TEST

/*
** Where the fill of a sphere's record may fail, the scene fills it on
** the spot, as ray_sphere does, so the answer stays the primitive's: a
** sphere smaller than the rounding of its centre's coordinates (the hit
** point, org + t dir, may round onto the centre: no normal), and spheres
** near the top of double's range (p or p_err may overflow).
*/
START_TEST(scene_should_agree_with_spheres_whose_fill_may_fail)
{
    static const double radii[] = {1e-30, 1e-17, 1e-16, 0x1p999, 0x1p1000};
    static const double centres[] = {1.0, 1.0, 3.0, 0x1p1000, 0x1p1022};
    size_t i;

    for (i = 0; i < sizeof radii / sizeof radii[0]; i++) {
        ray_scene *s;
        ray_vec3 c = vec(centres[i], centres[i], centres[i]);
        ray_ray r = ray_from(vec(0, 0, 0), vec(1, 1, 1));
        ray_hit got, want;
        int expect = ray_sphere(&r, c, radii[i], &want), rc;

        ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
        ck_assert_int_eq(ray_scene_add_sphere(s, c, radii[i],
                                              RAY_NO_MATERIAL, NULL),
                         RAY_OK);
        ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
        rc = ray_intersect(s, &r, &got, NULL);
        ck_assert_int_eq(rc, expect);
        ck_assert_int_eq(ray_occluded(s, &r, NULL), expect);
        if (expect) {
            want.geom_id = 0;
            want.prim_id = 0;
            ck_assert(hit_same(&got, &want));
        }
        ray_scene_free(s);
    }
}
END_TEST

/* A material that keeps the hit record it is given. */
static void keep_hit(void *ud, ray_ctx *ctx, const ray_shade_args *a,
                     ray_rgb *out)
{
    (void)ctx;
    (void)out;
    *(ray_hit *)ud = *a->hit;
}

/*
** Texture coordinates only when read (API-NOTES 14): in a render, a
** sphere whose material declares no RAY_EFFECT_TEXTURE gets its hit
** without (u, v) (0, 0), every other field as ray_intersect gives it,
** even beside a sphere whose material declares it, which gets the whole
** record of ray_intersect.
*/
START_TEST(render_should_fill_sphere_uv_only_when_read)
{
    ray_material mat[2];
    ray_hit seen[2];
    ray_scene *s;
    ray_ctx *ctx;
    unsigned id[2];
    int k;

    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    for (k = 0; k < 2; k++) {
        memset(&seen[k], 0, sizeof seen[k]);
        mat[k].shade = keep_hit;
        mat[k].ud = &seen[k];
        mat[k].effects = k ? RAY_EFFECT_TEXTURE : 0;
        mat[k].scatter = NULL;
        ck_assert_int_eq(ray_scene_add_material(s, &mat[k], &id[k]), RAY_OK);
        ck_assert_int_eq(ray_scene_add_sphere(s, vec(3.0 * k, 0, 0), 1,
                                              id[k], NULL), RAY_OK);
    }
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    ck_assert_int_eq(ray_scene_effects(s) & RAY_EFFECT_TEXTURE,
                     RAY_EFFECT_TEXTURE);
    ck_assert_int_eq(ray_ctx_new(s, 0, &ctx), RAY_OK);
    for (k = 0; k < 2; k++) {
        ray_ray r = ray_from(vec(3.0 * k + 0.3, 0.2, -5), vec(0, 0, 1));
        ray_hit want;
        ray_rgb c;

        ck_assert_int_eq(ray_intersect(s, &r, &want, NULL), 1);
        ck_assert_uint_eq(want.geom_id, (unsigned)k);
        ck_assert_int_eq(ray_trace(ctx, &r, RAY_KIND_PRIMARY, 1.0, &c),
                         RAY_OK);
        /* (0.3, 0.2) off the axis: the longitude and latitude are not 0. */
        ck_assert(want.u != 0 && want.v != 0);
        if (k == 0) {
            want.u = 0;
            want.v = 0;
        }
        ck_assert(hit_same(&seen[k], &want));
    }
    ray_ctx_free(ctx);
    ray_scene_free(s);
}
END_TEST

Suite *lazy_suite(void)
{
    Suite *s = suite_create("lazy");
    TCase *tc = tcase_create("core");

    tcase_add_test(tc, scene_hits_should_be_the_bare_primitives_bit_for_bit);
    tcase_add_test(tc, scene_should_agree_with_spheres_whose_fill_may_fail);
    tcase_add_test(tc, render_should_fill_sphere_uv_only_when_read);
    suite_add_tcase(s, tc);
    return s;
}
