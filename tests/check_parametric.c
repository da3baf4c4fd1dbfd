/* SPDX-License-Identifier: MIT */
/*
** check_parametric.c -- ray_parametric and ray_bezier_surface: patches
** with known answers (a planar patch against two triangles, a paraboloid
** against its quadratic, a cylinder over a custom domain), rays that miss
** by a hair, non-convergence, a collapsed edge, self-hits, bad input, and
** the boxes of sub-patches.
**
** Most tolerances are multiples of the default tolerance "tol" of
** ray_parametric: a root is accepted where |e + t d - S(u, v)| <= tol, and
** a point within tol of the surface along a unit ray crossing it at
** cosine c (|d . n|) is within tol / c of the crossing in t, exactly for
** a plane and up to a term quadratic in tol for a curved surface.
*/
#include "tests.h"

/* ------------------------------------------------------------- patches */

/* The cubic Bernstein coefficients of a2 u^2 + a1 u + a0 (degree
** elevation of its power form: Farin, CAGD, section 5.1). */
static void quadratic_coeffs(double a2, double a1, double a0, double c[4])
{
    c[0] = a0;
    c[1] = a0 + a1 / 3;
    c[2] = a0 + 2 * a1 / 3 + a2 / 3;
    c[3] = a0 + a1 + a2;
}

/* S(u, v) = (u, v, k ((u - a)^2 + (v - b)^2)) + off: a paraboloid piece,
** exact as a bicubic (x = u and y = v are linear, z quadratic). */
static void paraboloid_patch(ray_vec3 cp[16], double k, double a, double b,
                             ray_vec3 off)
{
    double cu[4], cv[4];
    int i, j;

    quadratic_coeffs(k, -2 * k * a, k * a * a, cu);
    quadratic_coeffs(k, -2 * k * b, k * b * b, cv);
    for (i = 0; i < 4; i++)
        for (j = 0; j < 4; j++)
            cp[4 * i + j] = vadd(off, vec(j / 3.0, i / 3.0, cu[j] + cv[i]));
}

/* The bilinear patch through four corners (exact as a bicubic: each
** control point is the bilinear interpolation at (j/3, i/3)); planar when
** the corners are. */
static void bilinear_patch(ray_vec3 cp[16], ray_vec3 c00, ray_vec3 c10,
                           ray_vec3 c01, ray_vec3 c11)
{
    int i, j;

    for (i = 0; i < 4; i++)
        for (j = 0; j < 4; j++) {
            double u = j / 3.0, v = i / 3.0;
            cp[4 * i + j] =
                vadd(vadd(vscale(c00, (1 - u) * (1 - v)),
                          vscale(c10, u * (1 - v))),
                     vadd(vscale(c01, (1 - u) * v), vscale(c11, u * v)));
        }
}

/* A quarter dome whose v = 0 row is collapsed to the apex (0, 0, 1), like
** the Utah teapot's lid: rows of radius 0, 0.55, 1, 1 at heights 1, 1,
** 0.55, 0, each a quarter circle by the usual 0.5523 handles. */
static void collapsed_dome(ray_vec3 cp[16])
{
    static const double radius[4] = {0, 0.55, 1, 1};
    static const double height[4] = {1, 1, 0.55, 0};
    const double k = 0.5523;
    int i;

    for (i = 0; i < 4; i++) {
        double r = radius[i], z = height[i];
        cp[4 * i + 0] = vec(r, 0, z);
        cp[4 * i + 1] = vec(r, k * r, z);
        cp[4 * i + 2] = vec(k * r, r, z);
        cp[4 * i + 3] = vec(0, r, z);
    }
}

/* The default tolerance ray_parametric derives for a Bezier patch:
** 1e-9 * diagonal + 64 DBL_EPSILON * largest |coordinate| of its control
** points' box
** (the library grows that box by ~1e-15 relative, which changes this by
** far less than the factors of 2 the assertions allow). */
static double patch_tol(const ray_vec3 cp[16])
{
    ray_vec3 lo = cp[0], hi = cp[0];
    double big;
    int i;

    for (i = 1; i < 16; i++) {
        lo = vec(fmin(lo.x, cp[i].x), fmin(lo.y, cp[i].y),
                 fmin(lo.z, cp[i].z));
        hi = vec(fmax(hi.x, cp[i].x), fmax(hi.y, cp[i].y),
                 fmax(hi.z, cp[i].z));
    }
    big = fmax(fmax(fmax(fabs(lo.x), fabs(hi.x)),
                    fmax(fabs(lo.y), fabs(hi.y))),
               fmax(fabs(lo.z), fabs(hi.z)));
    return 1e-9 * vdist(hi, lo) + 64 * DBL_EPSILON * big;
}

static ray_vec3 unit(ray_vec3 a)
{
    return vscale(a, 1.0 / vlen(a));
}

static int is_unit(ray_vec3 n)
{
    /* A normalised double vector is unit to a few ulps. */
    return fabs(vlen(n) - 1) < 8 * DBL_EPSILON;
}

/* Nearest hit of the two triangles (c00, c10, c11), (c00, c11, c01). */
static int two_triangles(const ray_ray *r, const ray_vec3 c[4], ray_hit *h)
{
    ray_hit a, b;
    int ha = ray_triangle(r, c[0], c[1], c[3], &a);
    int hb = ray_triangle(r, c[0], c[3], c[2], &b);

    if (ha && (!hb || a.t <= b.t))
        *h = a;
    else if (hb)
        *h = b;
    return ha || hb;
}

/* Distance from p to the segment [a, b]. */
static double segment_distance(ray_vec3 p, ray_vec3 a, ray_vec3 b)
{
    ray_vec3 ab = vsub(b, a);
    double s = vdot(vsub(p, a), ab) / vdot(ab, ab);

    s = s < 0 ? 0 : (s > 1 ? 1 : s);
    return vdist(p, vadd(a, vscale(ab, s)));
}

/* -------------------------------------------- (1, 8) planar vs triangles */

/*
** A planar convex quad in a tilted plane as a bilinear bicubic patch
** covers exactly the two triangles of its corners, so on random rays the
** two must agree: same hit or miss except where the ray crosses the plane
** within a few tolerances of the quad's border (a root is accepted within
** tol of the ray), the same t and p.  Repeated 1e5 from the origin, where
** the tolerance scales with the coordinates.
*/
START_TEST(parametric_planar_patch_should_agree_with_two_triangles)
{
    double o = test_offset(_i);
    ray_vec3 origin = vec(o, o, o), e1 = vec(1, 0.3, 0.2),
             e2 = vec(-0.2, 1, 0.5);
    ray_vec3 nrm = unit(vcross(e1, e2)), corner[4], cp[16];
    static const double ab[4][2] = {{0, 0}, {2, 0.1}, {0.2, 1.5},
                                    {1.8, 1.7}};
    ray_parametric_surface s;
    rng g = {42};
    double tol, tri_tol = tol_at(o);
    int k, hits = 0, misses = 0, n = 0;

    for (k = 0; k < 4; k++)
        corner[k] = vadd(origin, vadd(vscale(e1, ab[k][0]),
                                      vscale(e2, ab[k][1])));
    bilinear_patch(cp, corner[0], corner[1], corner[2], corner[3]);
    ck_assert_int_eq(ray_bezier_surface(cp, &s), RAY_OK);
    tol = patch_tol(cp);
    while (n < 1500) {
        double a = rng_range(&g, -0.4, 2.4), b = rng_range(&g, -0.4, 2.1);
        double side = rng_unit(&g) < 0.5 ? -1 : 1;
        ray_vec3 aim = vadd(origin, vadd(vscale(e1, a), vscale(e2, b)));
        ray_vec3 base = vadd(vscale(e1, rng_range(&g, -1, 3)),
                             vscale(e2, rng_range(&g, -1, 3)));
        ray_vec3 from = vadd(vadd(origin, base),
                             vscale(nrm, side * rng_range(&g, 0.5, 4)));
        ray_ray r = ray_from(from, unit(vsub(aim, from)));
        double c = fabs(vdot(r.dir, nrm)), border = HUGE_VAL, band, bound;
        ray_hit hp, ht;
        int rp, rt;

        if (c < 0.01)            /* grazing rays: see the hair tests */
            continue;
        n++;
        for (k = 0; k < 4; k++) {
            static const int edge[4][2] = {{0, 1}, {1, 3}, {3, 2}, {2, 0}};
            border = fmin(border, segment_distance(aim, corner[edge[k][0]],
                                                   corner[edge[k][1]]));
        }
        /* t is within (tol + the triangle's rounding) / c of the crossing
        ** for each: a factor 2 for both, 4 for points (p is within tol of
        ** the ray point).  Within a few such bounds of the border the two
        ** may disagree: the patch accepts a ray passing within tol. */
        bound = 2 * (tol + tri_tol) / c;
        band = 4 * bound;
        rp = ray_parametric(&r, &s, &hp);
        rt = two_triangles(&r, corner, &ht);
        ck_assert_int_ge(rp, 0);
        if (border < band)
            continue;
        ck_assert_int_eq(rp, rt);
        if (!rp) {
            misses++;
            continue;
        }
        hits++;
        ck_assert(hit_is_finite(&hp));
        ck_assert_double_eq_tol(hp.t, ht.t, bound);
        ck_assert_vec_eq_tol(hp.p, ht.p, 2 * bound);
        /* Both normals are the plane's, from differences of points at
        ** |o| + 3: rounding ~1e-16 (|o| + 3), 1e-9 leaves 1e4 of room at
        ** o = 1e5.  Su x Sv and (b - a) x (c - a) both point along e1 x e2. */
        ck_assert_vec_eq_tol(hp.n, nrm, 1e-9);
        ck_assert_vec_eq_tol(ht.n, nrm, 1e-9);
        /* The box p +- p_err reaches the plane (tri_tol: the rounding of
        ** this distance itself at |o|). */
        ck_assert(fabs(vdot(vsub(hp.p, corner[0]), nrm)) <=
                  vdot(vec(fabs(nrm.x), fabs(nrm.y), fabs(nrm.z)), hp.p_err) +
                      tri_tol);
        ck_assert(hp.u >= 0 && hp.u <= 1 && hp.v >= 0 && hp.v <= 1);
        ck_assert_uint_eq(hp.geom_id, RAY_INVALID_ID);
        ck_assert_uint_eq(hp.prim_id, RAY_INVALID_ID);
    }
    /* Not a vacuous comparison: about half the aims are on the quad. */
    ck_assert_int_gt(hits, n / 4);
    ck_assert_int_gt(misses, n / 10);
}
END_TEST

/* ------------------------------------------- (2) paraboloid vs quadratic */

/*
** The rays' roots on z = x^2 + y^2 (the patch's surface extended beyond
** the domain): from the quadratic (dx^2 + dy^2) t^2 + (2(ox dx + oy dy)
** - dz) t + ox^2 + oy^2 - oz = 0, solved without cancellation (Press et
** al., 5.6).  Returns the count (0 or 2) with their cosines |d . n|.
*/
static int paraboloid_roots(const ray_ray *r, double t[2], double cosine[2])
{
    ray_vec3 o = r->org, d = r->dir;
    double qa = d.x * d.x + d.y * d.y;
    double qb = 2 * (o.x * d.x + o.y * d.y) - d.z;
    double qc = o.x * o.x + o.y * o.y - o.z, disc = qb * qb - 4 * qa * qc, q;
    int i, n = 0;

    if (disc < 0 || qa == 0)
        return 0;
    q = -0.5 * (qb + copysign(sqrt(disc), qb));
    t[n++] = q / qa;
    t[n++] = qc / q;
    for (i = 0; i < n; i++) {
        ray_vec3 p = vadd(o, vscale(d, t[i]));
        cosine[i] = fabs(vdot(d, unit(vec(-2 * p.x, -2 * p.y, 1))));
    }
    return n;
}

START_TEST(parametric_paraboloid_patch_should_match_its_quadratic)
{
    ray_vec3 cp[16];
    ray_parametric_surface s;
    rng g = {7};
    double tol;
    int n = 0, hits = 0, compared = 0;

    paraboloid_patch(cp, 1, 0, 0, vec(0, 0, 0));
    ck_assert_int_eq(ray_bezier_surface(cp, &s), RAY_OK);
    tol = patch_tol(cp);
    for (n = 0; n < 1500; n++) {
        double a = rng_range(&g, -0.2, 1.2), b = rng_range(&g, -0.2, 1.2);
        ray_vec3 from = vec(rng_range(&g, -2, 3), rng_range(&g, -2, 3),
                            rng_range(&g, -2, 4));
        ray_ray r = ray_from(from, unit(vsub(vec(a, b, a * a + b * b), from)));
        double t[2], cosine[2], best = HUGE_VAL, best_cos = 1;
        int i, k, skip = 0, want = 0;
        ray_hit h;
        int rc = ray_parametric(&r, &s, &h);

        ck_assert_int_ge(rc, 0);
        k = paraboloid_roots(&r, t, cosine);
        for (i = 0; i < k; i++) {
            ray_vec3 p = vadd(r.org, vscale(r.dir, t[i]));
            double edge = fmin(fmin(fabs(p.x), fabs(1 - p.x)),
                               fmin(fabs(p.y), fabs(1 - p.y)));
            if (!(t[i] > 0))
                continue;
            /* Roots near the border or at grazing incidence are for the
            ** hair tests; within 1e-6 of the border, or below cosine
            ** 0.05, the reference's own choice is not sharp. */
            if (edge < 1e-6 || cosine[i] < 0.05)
                skip = 1;
            if (p.x >= 0 && p.x <= 1 && p.y >= 0 && p.y <= 1 &&
                t[i] < best) {
                best = t[i];
                best_cos = cosine[i];
                want = 1;
            }
        }
        if (skip)
            continue;
        compared++;
        ck_assert_int_eq(rc, want);
        if (!rc)
            continue;
        hits++;
        ck_assert(hit_is_finite(&h));
        /* t within tol / cosine of the crossing (factor 2: the curvature
        ** term and rounding); the point within tol of the ray point; u, v
        ** are x, y of p. */
        ck_assert_double_eq_tol(h.t, best, 2 * tol / best_cos);
        ck_assert(vdist(vadd(r.org, vscale(r.dir, h.t)), h.p) <= tol);
        ck_assert_double_eq_tol(h.u, h.p.x, 4 * DBL_EPSILON);
        ck_assert_double_eq_tol(h.v, h.p.y, 4 * DBL_EPSILON);
        /* n = (-2u, -2v, 1)/|.|, which turns by at most 2 per unit of
        ** (u, v): an error of 4 tol / cosine in u, v gives < 1e-6. */
        ck_assert(is_unit(h.n));
        ck_assert_vec_eq_tol(h.n, unit(vec(-2 * h.u, -2 * h.v, 1)), 1e-6);
    }
    ck_assert_int_gt(compared, 1000);
    ck_assert_int_gt(hits, compared / 4);
}
END_TEST

/* A horizontal ray crossing a cup z = (x - .5)^2 + (y - .5)^2 twice, at
** x = 0.5 -+ sqrt(0.1): the open interval picks the crossing. */
START_TEST(parametric_should_respect_open_interval)
{
    ray_vec3 cp[16];
    ray_parametric_surface s;
    ray_ray r = ray_from(vec(-1, 0.5, 0.1), vec(1, 0, 0));
    double t1 = 1.5 - sqrt(0.1), t2 = 1.5 + sqrt(0.1);
    /* Crossing cosine 2 sqrt(0.1) / sqrt(1 + 0.4) = 0.53: t within
    ** 2 tol / 0.53 < 4 tol. */
    double tol;
    ray_hit h;

    paraboloid_patch(cp, 1, 0.5, 0.5, vec(0, 0, 0));
    ck_assert_int_eq(ray_bezier_surface(cp, &s), RAY_OK);
    tol = 4 * patch_tol(cp);
    ck_assert_int_eq(ray_parametric(&r, &s, &h), 1);
    ck_assert_double_eq_tol(h.t, t1, tol);
    r.tmax = 1.5;
    ck_assert_int_eq(ray_parametric(&r, &s, &h), 1);
    ck_assert_double_eq_tol(h.t, t1, tol);
    r.tmin = 1.5;
    r.tmax = HUGE_VAL;
    ck_assert_int_eq(ray_parametric(&r, &s, &h), 1);
    ck_assert_double_eq_tol(h.t, t2, tol);
    r.tmin = t1 + 0.01;
    r.tmax = t2 - 0.01;
    hit_poison(&h);
    ck_assert_int_eq(ray_parametric(&r, &s, &h), 0);
    ck_assert(hit_is_poisoned(&h));
}
END_TEST

/* The hit does not depend on how finely the domain is cut for starts:
** the cup of the open-interval test, crossed at known t by a ray along x
** and one along the diagonal (both at distance sqrt(0.1) from the axis,
** cosine 0.53, so t within 2 tol / 0.53 < 4 tol). */
START_TEST(parametric_hit_should_not_depend_on_subdivisions)
{
    static const unsigned levels[] = {1, 2, 4, 8, 12};
    ray_vec3 cp[16], diag = unit(vec(1, 1, 0));
    ray_parametric_surface s;
    ray_ray along_x = ray_from(vec(-1, 0.5, 0.1), vec(1, 0, 0));
    ray_ray along_diag = ray_from(vsub(vec(0.5, 0.5, 0.1), diag), diag);
    double tol;
    size_t i;
    ray_hit h;

    paraboloid_patch(cp, 1, 0.5, 0.5, vec(0, 0, 0));
    ck_assert_int_eq(ray_bezier_surface(cp, &s), RAY_OK);
    tol = 4 * patch_tol(cp);
    for (i = 0; i < sizeof levels / sizeof levels[0]; i++) {
        s.subdivisions = levels[i];
        ck_assert_int_eq(ray_parametric(&along_x, &s, &h), 1);
        ck_assert_double_eq_tol(h.t, 1.5 - sqrt(0.1), tol);
        ck_assert_int_eq(ray_parametric(&along_diag, &s, &h), 1);
        ck_assert_double_eq_tol(h.t, 1 - sqrt(0.1), tol);
    }
}
END_TEST

/* ------------------------------------------------ (3) grazing and hairs */

/* Rays 1e-6 outside the border of a flat and of a curved patch miss
** (Newton's iterate stops at the border and is pushed out again: a miss,
** not non-convergence); 1e-6 inside they hit. */
START_TEST(parametric_should_miss_just_outside_the_border)
{
    static const double outside[][2] = {{1 + 1e-6, 0.5},  {0.5, -1e-6},
                                        {-1e-6, 0.3},     {0.7, 1 + 1e-6},
                                        {1 + 1e-6, 1 + 1e-6},
                                        {-1e-6, -1e-6}};
    ray_vec3 flat[16], cup[16];
    ray_parametric_surface s[2];
    size_t i;
    int k;
    ray_hit h;

    bilinear_patch(flat, vec(0, 0, 0), vec(1, 0, 0), vec(0, 1, 0),
                   vec(1, 1, 0));
    paraboloid_patch(cup, 1, 0, 0, vec(0, 0, 0));
    ck_assert_int_eq(ray_bezier_surface(flat, &s[0]), RAY_OK);
    ck_assert_int_eq(ray_bezier_surface(cup, &s[1]), RAY_OK);
    for (k = 0; k < 2; k++) {
        double tol = patch_tol(k ? cup : flat);
        ray_ray in = ray_from(vec(1 - 1e-6, 0.5, 5), vec(0, 0, -1));

        for (i = 0; i < sizeof outside / sizeof outside[0]; i++) {
            ray_ray r = ray_from(vec(outside[i][0], outside[i][1], 5),
                                 vec(0, 0, -1));
            hit_poison(&h);
            ck_assert_int_eq(ray_parametric(&r, &s[k], &h), 0);
            ck_assert(hit_is_poisoned(&h));
        }
        ck_assert_int_eq(ray_parametric(&in, &s[k], &h), 1);
        /* Vertical ray: |F| <= tol bounds the error of u = x directly. */
        ck_assert_double_eq_tol(h.u, 1 - 1e-6, tol);
        ck_assert_double_eq_tol(h.v, 0.5, tol);
        ck_assert(hit_is_finite(&h));
    }
}
END_TEST

/* A ray in the plane of a flat patch, and parallel to it 1e-6 above,
** misses (Newton's system is singular: no step); a ray crossing it at
** 1e-3 radians hits at the right t. */
START_TEST(parametric_should_handle_rays_parallel_to_a_flat_patch)
{
    ray_vec3 flat[16];
    ray_parametric_surface s;
    ray_ray in_plane = ray_from(vec(-1, 0.5, 0), vec(1, 0.2, 0));
    ray_ray above = ray_from(vec(-1, 0.5, 1e-6), vec(1, 0.2, 0));
    ray_ray grazing = ray_from(vec(-1, 0.5, 1e-3), unit(vec(1, 0, -1e-3)));
    double tol;
    ray_hit h;

    bilinear_patch(flat, vec(0, 0, 0), vec(1, 0, 0), vec(0, 1, 0),
                   vec(1, 1, 0));
    ck_assert_int_eq(ray_bezier_surface(flat, &s), RAY_OK);
    tol = patch_tol(flat);
    hit_poison(&h);
    ck_assert_int_eq(ray_parametric(&in_plane, &s, &h), 0);
    ck_assert_int_eq(ray_parametric(&above, &s, &h), 0);
    ck_assert(hit_is_poisoned(&h));
    ck_assert_int_eq(ray_parametric(&grazing, &s, &h), 1);
    /* Crosses z = 0 at x = 0, t = sqrt(1 + 1e-6); cosine 1e-3, so t
    ** within tol / 1e-3 (factor 2 for rounding). */
    ck_assert_double_eq_tol(h.t, sqrt(1 + 1e-6), 2 * tol / 1e-3);
    ck_assert_vec_eq_tol(h.n, vec(0, 0, 1), 4 * DBL_EPSILON);
}
END_TEST

/*
** A cap z = -((x - .4)^2 + (y - .43)^2) with its apex (z = 0) off the
** quad tree's cuts, so its boxes do not end at the apex.  Horizontal
** rays 1e-6 above it miss (the refinement's boxes prove it); 1e-6 below
** they cross twice, 2e-3 apart, and the nearer crossing is the hit; a
** ray exactly tangent may hit (near the apex) or miss, but never fails.
*/
START_TEST(parametric_should_resolve_rays_grazing_a_cap)
{
    static const double dirs[][2] = {{1, 0}, {0, 1}, {1, 1}, {-1, 0.5}};
    ray_vec3 cap[16], apex = vec(0.4, 0.43, 0);
    ray_parametric_surface s;
    size_t i;
    double tol;

    paraboloid_patch(cap, -1, 0.4, 0.43, vec(0, 0, 0));
    ck_assert_int_eq(ray_bezier_surface(cap, &s), RAY_OK);
    tol = patch_tol(cap);
    for (i = 0; i < sizeof dirs / sizeof dirs[0]; i++) {
        ray_vec3 d = unit(vec(dirs[i][0], dirs[i][1], 0));
        ray_vec3 from = vsub(apex, d);       /* 1 before the apex */
        ray_ray above = ray_from(vadd(from, vec(0, 0, 1e-6)), d);
        ray_ray below = ray_from(vadd(from, vec(0, 0, -1e-6)), d);
        ray_ray tangent = ray_from(from, d);
        ray_hit h;
        int rc;

        hit_poison(&h);
        ck_assert_int_eq(ray_parametric(&above, &s, &h), 0);
        ck_assert(hit_is_poisoned(&h));
        ck_assert_int_eq(ray_parametric(&below, &s, &h), 1);
        /* Crossing 1e-3 before the apex, where the slope is 2e-3: the
        ** cosine is ~2e-3, so t is within tol / 2e-3 (factor 2). */
        ck_assert_double_eq_tol(h.t, 1 - 1e-3, 2 * tol / 2e-3);
        rc = ray_parametric(&tangent, &s, &h);
        ck_assert(rc == 0 || rc == 1);
        /* At a double root |F| ~ (distance along the ray)^2, so an
        ** accepted iterate is within sqrt(tol) of the apex; x10 margin. */
        if (rc == 1)
            ck_assert(vdist(h.p, apex) <= 10 * sqrt(tol));
    }
    /* The deepest quad tree with 8 levels of refinement on top: the
    ** traversal's fixed stack holds (ASan would say otherwise). */
    s.subdivisions = 12;
    {
        ray_ray above = ray_from(vec(-1, 0.43, 1e-6), vec(1, 0, 0));
        ray_hit h;
        ck_assert_int_eq(ray_parametric(&above, &s, &h), 0);
    }
}
END_TEST

/* --------------------------------------------------- (4) non-convergence */

/*
** S(u, v) = (h(u), v, u) with h(u) = sign(u - c) sqrt|u - c|: Newton on
** h jumps from u to 2c - u forever (the textbook cycle of sqrt).  With
** c = 1/3, whose binary digits alternate, c sits a sixth of a rectangle
** from the centre of every dyadic rectangle holding it, so the cycle
** stays inside at every refinement: non-convergence, not a miss.
*/
static double signed_sqrt(double x)
{
    return x < 0 ? -sqrt(-x) : sqrt(x);
}

static void cycle_eval(void *ud, double u, double v, ray_vec3 *s,
                       ray_vec3 *s_u, ray_vec3 *s_v)
{
    double c = *(const double *)ud, r = sqrt(fabs(u - c));

    *s = vec(signed_sqrt(u - c), v, u);
    /* h' = 1 / (2 sqrt|u - c|); u never equals c (centres are dyadic). */
    *s_u = vec(r > 0 ? 0.5 / r : 1.0, 0, 1);
    *s_v = vec(0, 1, 0);
}

static void cycle_bounds(void *ud, double u0, double u1, double v0,
                         double v1, ray_vec3 *lo, ray_vec3 *hi)
{
    double c = *(const double *)ud;

    /* h is increasing, and sqrt is correctly rounded, so monotone. */
    *lo = vec(signed_sqrt(u0 - c), v0, u0);
    *hi = vec(signed_sqrt(u1 - c), v1, u1);
}

/* The plane z = 0 with partials reported 1000 times too long: each
** Newton step covers 1/1000 of the way in (u, v), so no start gets within
** the tolerance in 16 steps, at any refinement (1/3 again keeps the root
** a sixth of a rectangle from every centre). */
static void crawl_eval(void *ud, double u, double v, ray_vec3 *s,
                       ray_vec3 *s_u, ray_vec3 *s_v)
{
    (void)ud;
    *s = vec(u, v, 0);
    *s_u = vec(1000, 0, 0);
    *s_v = vec(0, 1000, 0);
}

static void plane_bounds(void *ud, double u0, double u1, double v0,
                         double v1, ray_vec3 *lo, ray_vec3 *hi);

START_TEST(parametric_should_report_non_convergence)
{
    double c = 1.0 / 3;
    ray_parametric_surface s = {cycle_eval, cycle_bounds, &c, 0, 0, 0, 0,
                                0, 0, 0};
    ray_parametric_surface crawl = {crawl_eval, plane_bounds, NULL, 0, 0,
                                    0, 0, 0, 0, 0};
    ray_ray r = ray_from(vec(0, 0.3, -5), vec(0, 0, 1));
    ray_ray down = ray_from(vec(1.0 / 3, 1.0 / 3, 5), vec(0, 0, -1));
    ray_hit h;

    hit_poison(&h);
    ck_assert_int_eq(ray_parametric(&r, &s, &h), -RAY_ELIMIT);
    ck_assert(hit_is_poisoned(&h));
    ck_assert_int_eq(ray_parametric(&down, &crawl, &h), -RAY_ELIMIT);
    ck_assert(hit_is_poisoned(&h));
    /* With enough steps the crawl does arrive: 1/1000 per step needs
    ** ~2e4 steps for 1e-9; 100000 is plenty. */
    crawl.max_iterations = 100000;
    ck_assert_int_eq(ray_parametric(&down, &crawl, &h), 1);
    /* |F| <= tol ~ 2.4e-9 bounds |u - 1/3| on this plane. */
    ck_assert_double_eq_tol(h.u, 1.0 / 3, 1e-8);
}
END_TEST

/* ------------------------------------------------------ (5) invalid input */

static void plane_eval(void *ud, double u, double v, ray_vec3 *s,
                       ray_vec3 *s_u, ray_vec3 *s_v)
{
    (void)ud;
    *s = vec(u, v, 0);
    *s_u = vec(1, 0, 0);
    *s_v = vec(0, 1, 0);
}

/* The exact box of the plane piece; records the widest rectangle asked
** for in *ud when ud is not NULL. */
typedef struct asked {
    double u0, u1, v0, v1;
} asked;

static void plane_bounds(void *ud, double u0, double u1, double v0,
                         double v1, ray_vec3 *lo, ray_vec3 *hi)
{
    asked *a = ud;

    if (a != NULL) {
        a->u0 = fmin(a->u0, u0);
        a->u1 = fmax(a->u1, u1);
        a->v0 = fmin(a->v0, v0);
        a->v1 = fmax(a->v1, v1);
    }
    *lo = vec(u0, v0, 0);
    *hi = vec(u1, v1, 0);
}

static void nan_eval(void *ud, double u, double v, ray_vec3 *s,
                     ray_vec3 *s_u, ray_vec3 *s_v)
{
    plane_eval(ud, u, v, s, s_u, s_v);
    s->z = (double)NAN;
}

static void inf_bounds(void *ud, double u0, double u1, double v0, double v1,
                       ray_vec3 *lo, ray_vec3 *hi)
{
    plane_bounds(ud, u0, u1, v0, v1, lo, hi);
    hi->z = HUGE_VAL;
}

static void inverted_bounds(void *ud, double u0, double u1, double v0,
                            double v1, ray_vec3 *lo, ray_vec3 *hi)
{
    plane_bounds(ud, u0, u1, v0, v1, hi, lo);
}

/* Every call must return "want" and leave the hit record untouched. */
static void expect_untouched(const ray_ray *r, const ray_parametric_surface *s,
                             int want)
{
    ray_hit h;

    hit_poison(&h);
    ck_assert_int_eq(ray_parametric(r, s, &h), want);
    ck_assert(hit_is_poisoned(&h));
}

START_TEST(parametric_should_reject_invalid_descriptors)
{
    ray_parametric_surface ok = {plane_eval, plane_bounds, NULL, 0, 0, 0, 0,
                                 0, 0, 0};
    ray_parametric_surface s;
    ray_ray r = ray_from(vec(0.5, 0.5, 1), vec(0, 0, -1));
    ray_hit h;

    hit_poison(&h);
    ck_assert_int_eq(ray_parametric(NULL, &ok, &h), -RAY_EINVAL);
    ck_assert_int_eq(ray_parametric(&r, NULL, &h), -RAY_EINVAL);
    ck_assert_int_eq(ray_parametric(&r, &ok, NULL), -RAY_EINVAL);
    ck_assert(hit_is_poisoned(&h));
    s = ok;
    s.eval = NULL;
    expect_untouched(&r, &s, -RAY_EINVAL);
    s = ok;
    s.bounds = NULL;
    expect_untouched(&r, &s, -RAY_EINVAL);
    s = ok;                              /* empty: u0 = u1, not all 0 */
    s.u0 = s.u1 = 0.5;
    s.v1 = 1;
    expect_untouched(&r, &s, -RAY_EINVAL);
    s = ok;                              /* reversed */
    s.u0 = 1;
    s.v1 = 1;
    expect_untouched(&r, &s, -RAY_EINVAL);
    s = ok;
    s.u1 = 1;                            /* v0 = v1 = 0 alone */
    expect_untouched(&r, &s, -RAY_EINVAL);
    s = ok;
    s.u0 = (double)NAN;
    s.u1 = s.v1 = 1;
    expect_untouched(&r, &s, -RAY_EINVAL);
    s = ok;
    s.u1 = HUGE_VAL;
    s.v1 = 1;
    expect_untouched(&r, &s, -RAY_EINVAL);
    s = ok;
    s.subdivisions = 13;                 /* above the documented 12 */
    expect_untouched(&r, &s, -RAY_EINVAL);
    s = ok;
    s.tolerance = -1e-9;
    expect_untouched(&r, &s, -RAY_EINVAL);
    s.tolerance = (double)NAN;
    expect_untouched(&r, &s, -RAY_EINVAL);
    s.tolerance = HUGE_VAL;
    expect_untouched(&r, &s, -RAY_EINVAL);
    /* The valid descriptor hits. */
    ck_assert_int_eq(ray_parametric(&r, &ok, &h), 1);
}
END_TEST

START_TEST(parametric_should_miss_invalid_rays)
{
    ray_parametric_surface s = {plane_eval, plane_bounds, NULL, 0, 0, 0, 0,
                                0, 0, 0};
    ray_ray r = ray_from(vec(0.5, 0.5, 1), vec(0, 0, -1)), b;

    b = r;
    b.org.x = (double)NAN;
    expect_untouched(&b, &s, 0);
    b = r;
    b.dir.z = -HUGE_VAL;
    expect_untouched(&b, &s, 0);
    b = r;
    b.dir = vec(0, 0, 0);
    expect_untouched(&b, &s, 0);
    b = r;
    b.tmin = b.tmax = 1;
    expect_untouched(&b, &s, 0);
    b = r;
    b.tmin = 2;
    b.tmax = 0.5;
    expect_untouched(&b, &s, 0);
    b = r;
    b.tmin = (double)NAN;
    expect_untouched(&b, &s, 0);
    b = r;
    b.tmax = (double)NAN;
    expect_untouched(&b, &s, 0);
}
END_TEST

START_TEST(parametric_should_reject_non_finite_callback_values)
{
    ray_parametric_surface s = {nan_eval, plane_bounds, NULL, 0, 0, 0, 0, 0,
                                0, 0};
    ray_ray r = ray_from(vec(0.5, 0.5, 1), vec(0, 0, -1));

    expect_untouched(&r, &s, -RAY_EINVAL);
    s.eval = plane_eval;
    s.bounds = inf_bounds;
    expect_untouched(&r, &s, -RAY_EINVAL);
    s.bounds = inverted_bounds;          /* lo > hi: a broken callback */
    expect_untouched(&r, &s, -RAY_EINVAL);
}
END_TEST

START_TEST(bezier_surface_should_validate_control_points)
{
    ray_vec3 cp[16];
    ray_parametric_surface s, ref;
    int k;

    bilinear_patch(cp, vec(0, 0, 0), vec(1, 0, 0), vec(0, 1, 0),
                   vec(1, 1, 0));
    memset(&ref, 0x5A, sizeof ref);
    s = ref;
    ck_assert_int_eq(ray_bezier_surface(NULL, &s), RAY_EINVAL);
    ck_assert_int_eq(ray_bezier_surface(cp, NULL), RAY_EINVAL);
    for (k = 0; k < 3; k++) {
        ray_vec3 keep = cp[5];
        cp[5].y = k == 0 ? (double)NAN : (k == 1 ? HUGE_VAL : -HUGE_VAL);
        ck_assert_int_eq(ray_bezier_surface(cp, &s), RAY_EINVAL);
        cp[5] = keep;
    }
    ck_assert(memcmp(&s, &ref, sizeof s) == 0);
    ck_assert_int_eq(ray_bezier_surface(cp, &s), RAY_OK);
    ck_assert(s.eval != NULL && s.bounds != NULL);
    ck_assert_ptr_eq(s.ud, (void *)cp);  /* borrowed, not copied */
    ck_assert(s.u0 == 0 && s.u1 == 1 && s.v0 == 0 && s.v1 == 1);
    ck_assert_uint_eq(s.subdivisions, 0);
    ck_assert_uint_eq(s.max_iterations, 0);
    ck_assert(s.tolerance == 0);
}
END_TEST

/* -------------------------------------------------- (6) collapsed edge */

/*
** The dome's v = 0 row is a single point, where S_u = 0 and S_u x S_v
** vanishes.  Hits at and around the apex still get a finite unit normal,
** taken a little inside the domain: vertical there (the first two rows
** are at the same height) and on the same side as elsewhere on the dome.
*/
START_TEST(parametric_collapsed_edge_should_give_a_unit_normal)
{
    static const double at[][2] = {{0, 0},       {1e-12, 1e-12}, {1e-9, 0},
                                   {1e-7, 3e-7}, {1e-5, 2e-5},   {0.01, 0.02}};
    static const double slopes[] = {-0.014, -0.04, -0.2, -1, 0.014, 0.2};
    ray_vec3 cp[16];
    ray_parametric_surface s;
    ray_ray bulk = ray_from(vec(0.3, 0.3, 5), vec(0, 0, -1));
    ray_hit h;
    double side, tol;
    size_t i;

    collapsed_dome(cp);
    ck_assert_int_eq(ray_bezier_surface(cp, &s), RAY_OK);
    tol = patch_tol(cp);
    ck_assert_int_eq(ray_parametric(&bulk, &s, &h), 1);
    side = h.n.z > 0 ? 1 : -1;
    for (i = 0; i < sizeof at / sizeof at[0]; i++) {
        ray_ray r = ray_from(vec(at[i][0], at[i][1], 5), vec(0, 0, -1));

        ck_assert_int_eq(ray_parametric(&r, &s, &h), 1);
        ck_assert(hit_is_finite(&h));
        ck_assert(is_unit(h.n));
        ck_assert(h.n.z * side > 0);
        /* Near the apex the dome is flat to first order: within 0.02 of
        ** it the normal is vertical to 0.1 (slope ~ 2 * 0.55^-2 * r). */
        ck_assert(fabs(h.n.z) > 0.99);
        if (at[i][0] == 0 && at[i][1] == 0) {
            /* The apex itself: t = 4 within the tolerance (cosine 1). */
            ck_assert_double_eq_tol(h.t, 4, 2 * tol);
            ck_assert_vec_eq_tol(h.p, vec(0, 0, 1), 2 * tol);
            /* The normal from 1e-6 inside: vertical to ~1e-6. */
            ck_assert_double_eq_tol(fabs(h.n.z), 1, 1e-6);
        }
    }
    /* Rays through the apex at grazing angles, from outside the quarter:
    ** Newton's u step is huge near the collapsed edge (S_u ~ v), yet the
    ** start slides to the apex rather than leaving (or exhausting the
    ** refinement on every rectangle along the edge).  t = 1 within
    ** tol / |d.z| (the cosine with the vertical normal there). */
    for (i = 0; i < sizeof slopes / sizeof slopes[0]; i++) {
        ray_vec3 d = unit(vec(2, 1, slopes[i] * sqrt(5.0)));
        ray_ray r = ray_from(vsub(vec(0, 0, 1), d), d);

        ck_assert_int_eq(ray_parametric(&r, &s, &h), 1);
        ck_assert_double_eq_tol(h.t, 1, 2 * tol / fabs(d.z));
        ck_assert(hit_is_finite(&h) && is_unit(h.n));
        ck_assert_double_eq_tol(fabs(h.n.z), 1, 1e-5);
    }
}
END_TEST

/* ------------------------------------------------------- (7) self-hits */

/*
** A ray leaving a point of the surface: with tmin = 1e-6 the root at
** t ~ 0 is outside the interval (a miss if nothing else is hit); with
** tmin = 0 that root may be reported at |t| <= tol, as for every
** primitive -- the caller chooses tmin, or uses ray_spawn, whose offset
** (2 p_err along n) puts the origin off the surface by more than the
** tolerance, so the spawned ray never finds its own root at t > 0.
*/
START_TEST(parametric_should_not_hit_itself_from_the_surface)
{
    ray_vec3 cp[16], p, su, sv, n;
    ray_parametric_surface s;
    rng g = {99};
    ray_hit h;
    double tol;
    int k, rc, spawned = 0;

    paraboloid_patch(cp, 1, 0, 0, vec(0, 0, 0));
    ck_assert_int_eq(ray_bezier_surface(cp, &s), RAY_OK);
    tol = patch_tol(cp);
    s.eval(s.ud, 0.3, 0.6, &p, &su, &sv);
    n = unit(vcross(su, sv));
    for (k = -1; k <= 1; k += 2) {
        ray_ray r = make_ray(p, vscale(n, k), 1e-6, HUGE_VAL);
        hit_poison(&h);
        ck_assert_int_eq(ray_parametric(&r, &s, &h), 0);
        ck_assert(hit_is_poisoned(&h));
        r.tmin = 0;
        rc = ray_parametric(&r, &s, &h);
        ck_assert(rc == 0 || (rc == 1 && h.t <= tol));
    }
    for (k = 0; k < 200; k++) {
        ray_vec3 from = vec(rng_range(&g, -1, 2), rng_range(&g, -1, 2), 3);
        ray_vec3 aim = vec(rng_range(&g, 0.05, 0.95),
                           rng_range(&g, 0.05, 0.95), 0);
        ray_ray r, out;

        aim.z = aim.x * aim.x + aim.y * aim.y;
        r = ray_from(from, unit(vsub(aim, from)));
        if (ray_parametric(&r, &s, &h) != 1 || fabs(vdot(r.dir, h.n)) < 0.05)
            continue;
        spawned++;
        ck_assert_int_eq(ray_spawn(&h, ray_reflect(r.dir, h.n), &out), RAY_OK);
        rc = ray_parametric(&out, &s, &h);
        /* The reflected ray leaves at more than 0.05 rad, so a real second
        ** crossing of the cup is far (> 0.05 / curvature 2); 1e-3 only
        ** excludes the point it left. */
        ck_assert(rc == 0 || (rc == 1 && h.t > 1e-3));
    }
    ck_assert_int_gt(spawned, 100);
}
END_TEST

/* ------------------------------------------------------ (9) the domain */

START_TEST(parametric_should_use_the_default_and_a_custom_domain)
{
    asked a = {HUGE_VAL, -HUGE_VAL, HUGE_VAL, -HUGE_VAL};
    ray_parametric_surface s = {plane_eval, plane_bounds, &a, 0, 0, 0, 0,
                                0, 0, 0};
    ray_ray in = ray_from(vec(0.5, 0.25, 1), vec(0, 0, -1));
    ray_ray beyond = ray_from(vec(1.5, 0.5, 1), vec(0, 0, -1));
    ray_ray low = ray_from(vec(-0.5, 0.3, 1), vec(0, 0, -1));
    ray_ray high = ray_from(vec(0.5, 0.9, 1), vec(0, 0, -1));
    /* The plane is exact: 1 Newton step from the centre; the default
    ** tolerance 1e-9 * (sqrt 2 + 1) bounds the error anyway. */
    double tol = 1e-8;
    ray_hit h;

    ck_assert_int_eq(ray_parametric(&in, &s, &h), 1);
    ck_assert_double_eq_tol(h.u, 0.5, tol);
    ck_assert_double_eq_tol(h.v, 0.25, tol);
    ck_assert_double_eq_tol(h.t, 1, tol);
    ck_assert_int_eq(ray_parametric(&beyond, &s, &h), 0);
    ck_assert_int_eq(ray_parametric(&low, &s, &h), 0);
    /* Only rectangles of [0, 1]^2 were asked for. */
    ck_assert(a.u0 >= 0 && a.u1 <= 1 && a.v0 >= 0 && a.v1 <= 1);

    s.u0 = -1;
    s.u1 = 2;
    s.v0 = 0.25;
    s.v1 = 0.75;
    a.u0 = a.v0 = HUGE_VAL;
    a.u1 = a.v1 = -HUGE_VAL;
    ck_assert_int_eq(ray_parametric(&beyond, &s, &h), 1);
    ck_assert_double_eq_tol(h.u, 1.5, tol);
    ck_assert_double_eq_tol(h.v, 0.5, tol);
    ck_assert_int_eq(ray_parametric(&low, &s, &h), 1);
    ck_assert_double_eq_tol(h.u, -0.5, tol);
    ck_assert_int_eq(ray_parametric(&high, &s, &h), 0);
    /* v = 0.25 is on the border: the domain is closed, like a triangle's
    ** edges. */
    ck_assert_int_eq(ray_parametric(&in, &s, &h), 1);
    ck_assert_double_eq_tol(h.v, 0.25, tol);
    ck_assert(a.u0 >= -1 && a.u1 <= 2 && a.v0 >= 0.25 && a.v1 <= 0.75);
}
END_TEST

/* The half cylinder (cos u, sin u, v), u in [0, pi], v in [-1, 1]. */
#define HALF_PI (3.14159265358979323846 / 2)

static void cylinder_eval(void *ud, double u, double v, ray_vec3 *s,
                          ray_vec3 *s_u, ray_vec3 *s_v)
{
    (void)ud;
    *s = vec(cos(u), sin(u), v);
    *s_u = vec(-sin(u), cos(u), 0);
    *s_v = vec(0, 0, 1);
}

/* cos decreases on [0, pi]; sin peaks at pi/2.  Grown by 4 ulps of 1 for
** libm's rounding of cos and sin (within 1 ulp in glibc). */
static void cylinder_bounds(void *ud, double u0, double u1, double v0,
                            double v1, ray_vec3 *lo, ray_vec3 *hi)
{
    double g = 4 * DBL_EPSILON;
    double top = (u0 <= HALF_PI && u1 >= HALF_PI)
                     ? 1.0 : fmax(sin(u0), sin(u1));

    (void)ud;
    *lo = vec(cos(u1) - g, fmin(sin(u0), sin(u1)) - g, v0);
    *hi = vec(cos(u0) + g, top + g, v1);
}

START_TEST(parametric_cylinder_should_hit_over_its_domain)
{
    const double pi = 3.14159265358979323846;
    ray_parametric_surface s = {cylinder_eval, cylinder_bounds, NULL, 0, pi,
                                -1, 1, 0, 0, 0};
    ray_ray down = ray_from(vec(0, 5, 0), vec(0, -1, 0));
    ray_ray inside = ray_from(vec(0.5, 0, 0.3), vec(0, 1, 0));
    ray_ray over = ray_from(vec(0, 5, 1.5), vec(0, -1, 0));
    /* Box of the domain: diagonal ~sqrt(8), largest coordinate 1, so the
    ** default tolerance is ~4e-9; both rays cross at cosine >= 0.86. */
    double tol = 1e-8;
    ray_hit h;

    ck_assert_int_eq(ray_parametric(&down, &s, &h), 1);
    ck_assert_double_eq_tol(h.t, 4, tol);
    ck_assert_double_eq_tol(h.u, pi / 2, tol);
    ck_assert_double_eq_tol(h.v, 0, tol);
    /* S_u x S_v is the outward normal (cos u, sin u, 0). */
    ck_assert_vec_eq_tol(h.n, vec(0, 1, 0), tol);
    ck_assert_int_eq(ray_parametric(&inside, &s, &h), 1);
    ck_assert_double_eq_tol(h.t, sqrt(0.75), tol);
    ck_assert_double_eq_tol(h.u, pi / 3, tol);
    ck_assert_double_eq_tol(h.v, 0.3, tol);
    ck_assert_vec_eq_tol(h.n, vec(0.5, sqrt(0.75), 0), tol);
    ck_assert_int_eq(ray_parametric(&over, &s, &h), 0);
}
END_TEST

/* ------------------------------------------------------ (10) the boxes */

/*
** The box of every sub-rectangle contains the patch there: random nets,
** random sub-rectangles, random points.  Slack: the evaluation's own
** rounding (bezier.c counts 18 roundings of max |cp|; 64 ulps of max
** |cp| leaves room).  And the boxes are tight: over a w x w piece the
** sub-control points differ by w/3 times control points of S_u (or S_v),
** which are at most 3 max |cp_k+1 - cp_k|, so they spread by at most
** 3 w max |cp_k+1 - cp_k| along u and as much along v.
*/
START_TEST(bezier_bounds_should_contain_the_patch)
{
    double o = test_offset(_i);
    rng g = {1234};
    int net, k, q;

    for (net = 0; net < 40; net++) {
        ray_vec3 cp[16];
        ray_parametric_surface s;
        double big = 0;

        for (k = 0; k < 16; k++) {
            cp[k] = vadd(vec(o, o, o), rng_point(&g, -1, 1));
            big = fmax(big, fmax(fabs(cp[k].x),
                                 fmax(fabs(cp[k].y), fabs(cp[k].z))));
        }
        ck_assert_int_eq(ray_bezier_surface(cp, &s), RAY_OK);
        for (q = 0; q < 20; q++) {
            double u0 = rng_unit(&g), u1 = rng_unit(&g);
            double v0 = rng_unit(&g), v1 = rng_unit(&g);
            double slack = 64 * DBL_EPSILON * big;
            ray_vec3 lo, hi;

            if (u0 > u1) {
                double x = u0;
                u0 = u1;
                u1 = x;
            }
            if (v0 > v1) {
                double x = v0;
                v0 = v1;
                v1 = x;
            }
            s.bounds(s.ud, u0, u1, v0, v1, &lo, &hi);
            for (k = 0; k < 10; k++) {
                ray_vec3 p, su, sv;
                double u = u0 + (u1 - u0) * rng_unit(&g);
                double v = v0 + (v1 - v0) * rng_unit(&g);
                s.eval(s.ud, k == 0 ? u0 : u, k == 0 ? v0 : v, &p, &su, &sv);
                ck_assert(p.x >= lo.x - slack && p.x <= hi.x + slack);
                ck_assert(p.y >= lo.y - slack && p.y <= hi.y + slack);
                ck_assert(p.z >= lo.z - slack && p.z <= hi.z + slack);
            }
        }
        {
            double u = 0.9 * rng_unit(&g), v = 0.9 * rng_unit(&g), w = 1e-3;
            /* The net spans [-1, 1]^3 + o: |cp_k+1 - cp_k| <= 2, so the
            ** width is below 6 w * 2; plus the growth and roundings of
            ** the box, ~1e-14 big. */
            double width = 6 * w * 2 + 1e-13 * big;
            ray_vec3 lo, hi;

            s.bounds(s.ud, u, u + w, v, v + w, &lo, &hi);
            ck_assert(hi.x - lo.x < width);
            ck_assert(hi.y - lo.y < width);
            ck_assert(hi.z - lo.z < width);
        }
    }
}
END_TEST

/* An affine patch's sub-patch boxes are exactly the image rectangles. */
START_TEST(bezier_bounds_should_be_exact_for_an_affine_patch)
{
    ray_vec3 cp[16], lo, hi;
    ray_parametric_surface s;

    bilinear_patch(cp, vec(0, 0, 0.5), vec(2, 0, 0.5), vec(0, 3, 0.5),
                   vec(2, 3, 0.5));
    ck_assert_int_eq(ray_bezier_surface(cp, &s), RAY_OK);
    s.bounds(s.ud, 0.25, 0.5, 0.125, 0.75, &lo, &hi);
    /* The growth gamma(20) * 3 ~ 7e-15 plus a few roundings of 3. */
    ck_assert_vec_eq_tol(lo, vec(0.5, 0.375, 0.5), 1e-14);
    ck_assert_vec_eq_tol(hi, vec(1, 2.25, 0.5), 1e-14);
    ck_assert(lo.x <= 0.5 && lo.y <= 0.375 && lo.z <= 0.5);
    ck_assert(hi.x >= 1 && hi.y >= 2.25 && hi.z >= 0.5);
}
END_TEST

/*
** The Bezier fast path (control nets halved down the quad tree) against
** the generic one: the same patch through callbacks that forward to
** ray_bezier_surface's, which ray_parametric does not recognise, so each
** box comes from the bounds callback (blossoming).  Both boxes contain
** the sub-patches, so both searches find the nearest root; the roots
** may differ by where Newton stops (a box differing by rounding moves
** the start).  Each accepted root is within tol of the ray, so along a
** unit ray crossing at cosine c each is within tol / c of the exact
** crossing in t (see the top of the file), and they are within 2 tol / c
** of each other; 1 + 1e-3 leaves room for the term quadratic in tol.
** A ray hitting in one and missing in the other is allowed only within
** (u, v) BORDER_NEAR of the domain's border, where both are right up
** to the tolerance; the random patches are mild (heights in [-0.5,
** 0.5] over a unit square), so there are no grazing double roots.
*/
static void forward_eval(void *ud, double u, double v, ray_vec3 *s,
                         ray_vec3 *s_u, ray_vec3 *s_v)
{
    const ray_parametric_surface *inner = ud;

    inner->eval(inner->ud, u, v, s, s_u, s_v);
}

static void forward_bounds(void *ud, double u0, double u1, double v0,
                           double v1, ray_vec3 *lo, ray_vec3 *hi)
{
    const ray_parametric_surface *inner = ud;

    inner->bounds(inner->ud, u0, u1, v0, v1, lo, hi);
}

static int near_border(const ray_hit *h)
{
    /* Far above the (u, v) a tolerance of ~1e-9 of the patch moves. */
    const double border_near = 1e-6;

    return h->u < border_near || h->u > 1 - border_near ||
           h->v < border_near || h->v > 1 - border_near;
}

START_TEST(bezier_fast_path_should_agree_with_the_callbacks)
{
    rng g = {8080};
    int patch, k, i, j, hits = 0;

    for (patch = 0; patch < 4; patch++) {
        ray_vec3 cp[16];
        ray_parametric_surface fast, slow;
        double tol;

        for (i = 0; i < 4; i++)
            for (j = 0; j < 4; j++)
                cp[4 * i + j] = vec(j / 3.0 + rng_range(&g, -0.1, 0.1),
                                    i / 3.0 + rng_range(&g, -0.1, 0.1),
                                    rng_range(&g, -0.5, 0.5));
        ck_assert_int_eq(ray_bezier_surface(cp, &fast), RAY_OK);
        slow = fast;
        slow.eval = forward_eval;
        slow.bounds = forward_bounds;
        slow.ud = &fast;
        tol = patch_tol(cp);
        for (k = 0; k < 500; k++) {
            ray_vec3 aim = vec(rng_range(&g, -0.2, 1.2),
                               rng_range(&g, -0.2, 1.2),
                               rng_range(&g, -0.5, 0.5));
            ray_vec3 org = vadd(vec(0.5, 0.5, 0), vscale(rng_dir(&g), 3));
            ray_ray r = ray_from(org, unit(vsub(aim, org)));
            ray_hit a, b;
            int ha = ray_parametric(&r, &fast, &a);
            int hb = ray_parametric(&r, &slow, &b);

            ck_assert(ha >= 0 && hb >= 0);
            if (ha != hb) {
                ck_assert(near_border(ha ? &a : &b));
            } else if (ha) {
                double c = fabs(vdot(r.dir, a.n));
                ck_assert(fabs(a.t - b.t) <= 2 * tol / c * (1 + 1e-3));
                hits++;
            }
        }
    }
    /* About a third of the rays hit (726 of 2000): not a vacuous pass. */
    ck_assert_int_gt(hits, 500);
}
END_TEST

Suite *parametric_suite(void)
{
    Suite *s = suite_create("parametric");
    TCase *core = tcase_create("hits");
    TCase *hard = tcase_create("hard");
    TCase *bad = tcase_create("errors");
    TCase *box = tcase_create("bezier");

    tcase_add_loop_test(core,
                        parametric_planar_patch_should_agree_with_two_triangles,
                        0, N_OFFSETS);
    tcase_add_test(core, parametric_paraboloid_patch_should_match_its_quadratic);
    tcase_add_test(core, parametric_should_respect_open_interval);
    tcase_add_test(core, parametric_hit_should_not_depend_on_subdivisions);
    tcase_add_test(core, parametric_should_use_the_default_and_a_custom_domain);
    tcase_add_test(core, parametric_cylinder_should_hit_over_its_domain);
    tcase_add_test(hard, parametric_should_miss_just_outside_the_border);
    tcase_add_test(hard, parametric_should_handle_rays_parallel_to_a_flat_patch);
    tcase_add_test(hard, parametric_should_resolve_rays_grazing_a_cap);
    tcase_add_test(hard, parametric_collapsed_edge_should_give_a_unit_normal);
    tcase_add_test(hard, parametric_should_not_hit_itself_from_the_surface);
    tcase_add_test(bad, parametric_should_report_non_convergence);
    tcase_add_test(bad, parametric_should_reject_invalid_descriptors);
    tcase_add_test(bad, parametric_should_miss_invalid_rays);
    tcase_add_test(bad, parametric_should_reject_non_finite_callback_values);
    tcase_add_test(bad, bezier_surface_should_validate_control_points);
    tcase_add_loop_test(box, bezier_bounds_should_contain_the_patch, 0,
                        N_OFFSETS);
    tcase_add_test(box, bezier_bounds_should_be_exact_for_an_affine_patch);
    tcase_add_test(box, bezier_fast_path_should_agree_with_the_callbacks);
    suite_add_tcase(s, core);
    suite_add_tcase(s, hard);
    suite_add_tcase(s, bad);
    suite_add_tcase(s, box);
    return s;
}
