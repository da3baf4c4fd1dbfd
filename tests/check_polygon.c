/* SPDX-License-Identifier: MIT */
/*
** check_polygon.c -- ray_polygon: convex, concave, self-intersecting,
** shared edges and vertices.
*/
#include "tests.h"

/* Copy 2-D points (x, y) into 3-D vertices (o + x, o + y, o). */
static void lift(const double (*xy)[2], size_t n, double o, ray_vec3 *out)
{
    size_t i;
    for (i = 0; i < n; i++)
        out[i] = vec(o + xy[i][0], o + xy[i][1], o);
}

/* Does a ray straight down onto (x, y) of the plane z = o hit? */
static int hits_at(const ray_vec3 *v, size_t n, double o, double x, double y)
{
    ray_ray r = ray_from(vec(o + x, o + y, o + 1), vec(0, 0, -1));
    ray_hit h;
    return ray_polygon(&r, v, n, &h);
}

START_TEST(polygon_should_hit_square_with_plane_coordinates)
{
    double o = test_offset(_i), tol = tol_at(o);
    static const double sq[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    ray_vec3 v[4];
    ray_ray r = ray_from(vec(o + 0.5, o + 0.25, o + 2), vec(0, 0, -1));
    ray_hit h;

    lift(sq, 4, o, v);
    ck_assert_int_eq(ray_polygon(&r, v, 4, &h), 1);
    ck_assert_double_eq_tol(h.t, 2.0, tol);
    ck_assert_vec_eq_tol(h.p, vec(o + 0.5, o + 0.25, o), tol);
    ck_assert_vec_eq_tol(h.n, vec(0, 0, 1), 4 * DBL_EPSILON);
    /* For n = +z the tangent frame is t1 = +x, t2 = +y, from v[0]. */
    ck_assert_double_eq_tol(h.u, 0.5, tol);
    ck_assert_double_eq_tol(h.v, 0.25, tol);
    ck_assert(hit_is_finite(&h));
}
END_TEST

/* Clockwise order flips the normal (counter-clockwise is the front). */
START_TEST(polygon_should_follow_winding_for_normal)
{
    static const double sq[4][2] = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
    ray_vec3 v[4];
    ray_ray r = ray_from(vec(0.5, 0.5, 1), vec(0, 0, -1));
    ray_hit h;

    lift(sq, 4, 0, v);
    ck_assert_int_eq(ray_polygon(&r, v, 4, &h), 1);
    ck_assert_vec_eq_tol(h.n, vec(0, 0, -1), 4 * DBL_EPSILON);
}
END_TEST

/* The notched pentagon of robustness.md section 4.3: the vertex (1, 1)
** lies on the test line y = 1 of two of the points. */
START_TEST(polygon_should_handle_concave_notch)
{
    double o = test_offset(_i);
    static const double pent[5][2] = {{0, 0}, {2, 0}, {2, 2}, {1, 1}, {0, 2}};
    ray_vec3 v[5];

    lift(pent, 5, o, v);
    ck_assert_int_eq(hits_at(v, 5, o, 0.5, 1.0), 1);
    ck_assert_int_eq(hits_at(v, 5, o, 1.5, 1.0), 1);
    ck_assert_int_eq(hits_at(v, 5, o, 1.0, 0.5), 1);
    ck_assert_int_eq(hits_at(v, 5, o, 1.0, 1.5), 0);
    ck_assert_int_eq(hits_at(v, 5, o, 3.0, 1.0), 0);
    ck_assert_int_eq(hits_at(v, 5, o, -1.0, 1.0), 0);
    ck_assert_int_eq(hits_at(v, 5, o, 0.2, 1.7), 1);   /* left arm */
    ck_assert_int_eq(hits_at(v, 5, o, 0.5, 1.9), 0);   /* above it */
}
END_TEST

/* Even-odd: the pentagram's centre is a hole, its points are inside. */
START_TEST(polygon_should_use_even_odd_rule)
{
    double star[5][2];
    ray_vec3 v[5];
    int k;

    for (k = 0; k < 5; k++) {
        double a = 3.14159265358979323846 * (0.5 + 0.8 * k);
        star[k][0] = cos(a);
        star[k][1] = sin(a);
    }
    lift((const double (*)[2])star, 5, 0, v);
    ck_assert_int_eq(hits_at(v, 5, 0, 0.0, 0.0), 0);
    ck_assert_int_eq(hits_at(v, 5, 0, 0.0, 0.8), 1);
}
END_TEST

/*
** A ray exactly through a vertex or an edge shared by polygons that tile
** the plane around it: an odd number of them, in fact exactly one here,
** claims the point.  Four unit squares meet at (1, 1).
*/
START_TEST(polygon_should_give_shared_vertex_and_edges_to_one_polygon)
{
    double o = test_offset(_i);
    ray_vec3 quads[4][4];
    double pts[5][2] = {{1, 1}, {1, 0.5}, {0.5, 1}, {1, 1.5}, {1.5, 1}};
    int q, k;

    for (q = 0; q < 4; q++) {
        double x0 = q % 2, y0 = q / 2;
        double sq[4][2];
        sq[0][0] = x0;     sq[0][1] = y0;
        sq[1][0] = x0 + 1; sq[1][1] = y0;
        sq[2][0] = x0 + 1; sq[2][1] = y0 + 1;
        sq[3][0] = x0;     sq[3][1] = y0 + 1;
        lift((const double (*)[2])sq, 4, o, quads[q]);
    }
    for (k = 0; k < 5; k++) {
        int count = 0;
        for (q = 0; q < 4; q++)
            count += hits_at(quads[q], 4, o, pts[k][0], pts[k][1]);
        ck_assert_msg(count == 1, "point %d claimed by %d squares", k, count);
    }
}
END_TEST

/*
** The skewed quad of robustness.md 4.3 split along its diagonal AC: 20000
** rays from random origins aimed at points interpolated along AC.  Each
** must hit exactly one of the two triangles-as-polygons (the naive
** crossings-multiply test disagrees on ~48% of such points).
*/
START_TEST(polygon_should_partition_points_near_shared_edge)
{
    double o = test_offset(_i);
    ray_vec3 A = vec(o + 0.1, o + 0.2, o), B = vec(o + 3.7, o + 0.3, o),
             C = vec(o + 2.9, o + 4.1, o), D = vec(o + 0.2, o + 3.3, o);
    ray_vec3 left[3], right[3];
    rng g = {11};
    int k;

    left[0] = A; left[1] = B; left[2] = C;
    right[0] = A; right[1] = C; right[2] = D;
    for (k = 0; k < 20000; k++) {
        double s = rng_range(&g, 0.01, 0.99);
        ray_vec3 P = vadd(vscale(A, 1 - s), vscale(C, s));
        ray_vec3 org = vadd(P, vec(rng_range(&g, -2, 2), rng_range(&g, -2, 2),
                                   rng_range(&g, 0.5, 3)));
        ray_ray r = ray_from(org, vsub(P, org));
        ray_hit h;
        int count = ray_polygon(&r, left, 3, &h) + ray_polygon(&r, right, 3, &h);
        ck_assert_msg(count == 1, "ray %d: %d hits", k, count);
    }
}
END_TEST

/*
** A closed cube of six quads; 20000 rays from inside aimed exactly at its
** vertices and at points on its edges.  None may escape (zero hits).
*/
START_TEST(polygon_should_not_leak_from_closed_cube)
{
    double o = test_offset(_i);
    /* corner k = (bit 0 ? +1 : -1, bit 1 ? .., bit 2 ? ..) + (o, o, o) */
    static const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                    {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    ray_vec3 corner[8], quads[6][4];
    rng g = {5};
    int f, k;

    for (k = 0; k < 8; k++)
        corner[k] = vec(o + (k & 1 ? 1 : -1), o + (k & 2 ? 1 : -1),
                        o + (k & 4 ? 1 : -1));
    for (f = 0; f < 6; f++)
        for (k = 0; k < 4; k++)
            quads[f][k] = corner[faces[f][k]];
    for (k = 0; k < 20000; k++) {
        int i0 = (int)(rng_next(&g) % 8), i1 = (int)(rng_next(&g) % 8);
        double s = (k & 1) ? 0.0 : rng_unit(&g);
        ray_vec3 P = vadd(vscale(corner[i0], 1 - s), vscale(corner[i1], s));
        ray_vec3 org = vadd(vec(o, o, o), rng_point(&g, -0.9, 0.9));
        ray_ray r = ray_from(org, vsub(P, org));
        ray_hit h;
        int count = 0;
        if ((k & 1) == 0 && (fabs(corner[i0].x - corner[i1].x) +
                             fabs(corner[i0].y - corner[i1].y) +
                             fabs(corner[i0].z - corner[i1].z)) != 2.0)
            P = corner[i0];   /* not a cube edge: aim at the vertex */
        r.dir = vsub(P, org);
        for (f = 0; f < 6; f++)
            count += ray_polygon(&r, quads[f], 4, &h);
        ck_assert_msg(count >= 1, "ray %d escaped", k);
    }
}
END_TEST

/*
** A scene's polygons (beside a sphere, so that the query is the general
** one, which tests them without the kinds' dispatch) each name
** themselves: geom_id, prim_id 0, no instance, and the record
** ray_polygon gives, bit for bit; rays toward each in turn, and
** ray_occluded agrees.  The faces of a cube seen from inside, one
** polygon each, and the sphere far away.
*/
START_TEST(polygons_in_a_scene_should_name_themselves)
{
    static const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                    {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    ray_vec3 corner[8], quads[6][4];
    ray_scene *s;
    rng g = {41};
    unsigned id[6];
    int f, k, c;

    for (k = 0; k < 8; k++)
        corner[k] = vec(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1);
    ck_assert_int_eq(ray_scene_new(&s, NULL, NULL), RAY_OK);
    ck_assert_int_eq(ray_scene_add_sphere(s, vec(50, 50, 50), 1,
                                          RAY_NO_MATERIAL, NULL), RAY_OK);
    for (f = 0; f < 6; f++) {
        for (k = 0; k < 4; k++)
            quads[f][k] = corner[faces[f][k]];
        ck_assert_int_eq(ray_scene_add_polygon(s, quads[f], 4,
                                               RAY_NO_MATERIAL, &id[f]),
                         RAY_OK);
    }
    ck_assert_int_eq(ray_scene_commit(s), RAY_OK);
    for (k = 0; k < 600; k++) {
        ray_vec3 org = rng_point(&g, -0.5, 0.5);
        ray_vec3 to = vec(0, 0, 0);
        ray_hit h, want;
        f = k % 6;              /* a point well inside face f, beyond it */
        for (c = 0; c < 4; c++)
            to = vadd(to, vscale(quads[f][c], 0.25));
        to = vadd(vscale(to, 1.5), rng_point(&g, -0.2, 0.2));
        {
            ray_ray r = ray_from(org, vsub(to, org));
            memset(&h, 0xab, sizeof h);
            ck_assert_int_eq(ray_intersect(s, &r, &h, NULL), 1);
            ck_assert_int_eq(ray_polygon(&r, quads[f], 4, &want), 1);
            ck_assert_uint_eq(h.geom_id, id[f]);
            ck_assert_uint_eq(h.prim_id, 0);
            ck_assert_uint_eq(h.inst_id, RAY_INVALID_ID);
            ck_assert(h.t == want.t);
            ck_assert(memcmp(&h.p, &want.p, sizeof h.p) == 0);
            ck_assert(memcmp(&h.n, &want.n, sizeof h.n) == 0);
            ck_assert_int_eq(ray_occluded(s, &r, NULL), 1);
        }
    }
    ray_scene_free(s);
}
END_TEST

START_TEST(polygon_should_miss_degenerate_polygons)
{
    static const double line[4][2] = {{0, 0}, {1, 0}, {2, 0}, {3, 0}};
    static const double sq[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    ray_vec3 v[4], s[4];
    ray_ray r = ray_from(vec(1, 0, 1), vec(0, 0, -1));
    ray_ray r2 = ray_from(vec(0.5, 0.5, 1), vec(0, 0, -1));
    ray_hit h;

    lift(line, 4, 0, v);
    lift(sq, 4, 0, s);
    hit_poison(&h);
    ck_assert_int_eq(ray_polygon(&r, v, 4, &h), 0);
    ck_assert_int_eq(ray_polygon(&r2, s, 2, &h), 0);
    ck_assert_int_eq(ray_polygon(&r2, s, 0, &h), 0);
    ck_assert_int_eq(ray_polygon(&r2, NULL, 4, &h), 0);
    s[1] = s[0];
    s[2] = s[0];
    s[3] = s[0];
    ck_assert_int_eq(ray_polygon(&r2, s, 4, &h), 0);
    ck_assert(hit_is_poisoned(&h));
}
END_TEST

START_TEST(polygon_should_miss_on_bad_input)
{
    static const double sq[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    double nan = (double)NAN, inf = HUGE_VAL;
    ray_vec3 v[4];
    ray_ray good = ray_from(vec(0.5, 0.5, 1), vec(0, 0, -1)), r;
    ray_hit h;
    int k;

    lift(sq, 4, 0, v);
    hit_poison(&h);
    for (k = 0; k < 8; k++) {
        r = good;
        switch (k) {
        case 0: r.org.x = nan; break;
        case 1: r.dir.z = nan; break;
        case 2: r.org.z = inf; break;
        case 3: r.dir.x = inf; break;
        case 4: r.dir = vec(0, 0, 0); break;
        case 5: r.dir = vec(1, 0, 0); break;     /* parallel */
        case 6: r.tmax = 1.0; break;             /* t exactly at tmax */
        case 7: r.tmin = nan; break;
        }
        ck_assert_msg(ray_polygon(&r, v, 4, &h) == 0, "case %d", k);
    }
    v[2].z = nan;
    ck_assert_int_eq(ray_polygon(&good, v, 4, &h), 0);
    v[2].z = inf;
    ck_assert_int_eq(ray_polygon(&good, v, 4, &h), 0);
    ck_assert(hit_is_poisoned(&h));
}
END_TEST

Suite *polygon_suite(void)
{
    Suite *s = suite_create("polygon");
    TCase *core = tcase_create("hits");
    TCase *hard = tcase_create("hard");

    tcase_add_loop_test(core, polygon_should_hit_square_with_plane_coordinates, 0, N_OFFSETS);
    tcase_add_test(core, polygon_should_follow_winding_for_normal);
    tcase_add_loop_test(core, polygon_should_handle_concave_notch, 0, N_OFFSETS);
    tcase_add_test(core, polygon_should_use_even_odd_rule);
    tcase_add_loop_test(hard, polygon_should_give_shared_vertex_and_edges_to_one_polygon, 0, N_OFFSETS);
    tcase_add_loop_test(hard, polygon_should_partition_points_near_shared_edge, 0, N_OFFSETS);
    tcase_add_loop_test(hard, polygon_should_not_leak_from_closed_cube, 0, N_OFFSETS);
    tcase_add_test(hard, polygon_should_miss_degenerate_polygons);
    tcase_add_test(hard, polygons_in_a_scene_should_name_themselves);
    tcase_add_test(hard, polygon_should_miss_on_bad_input);
    suite_add_tcase(s, core);
    suite_add_tcase(s, hard);
    return s;
}
