/* SPDX-License-Identifier: MIT */
/*
** check_obj.c -- the examples' OBJ reader (examples/obj.h): valid files,
** and malformed ones rejected with a line number, never a crash (the
** sanitizer runs of this suite check "never a crash" and "no leak").
*/
#include "obj.h"
#include "tests.h"

static int parse(const char *text, obj_mesh *m, char *err)
{
    return obj_parse(text, strlen(text), m, err, 256);
}

START_TEST(obj_should_read_quads_and_negative_indices)
{
    const char *text =
        "# a unit square as one quad, then a triangle by negative indices\n"
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
        "f 1 2 3 4\n"
        "v 5 5 5\n"
        "f -1 -4 -3\n";
    obj_mesh m;
    char err[256];

    ck_assert_int_eq(parse(text, &m, err), 0);
    ck_assert_uint_eq(m.vertex_count, 5);
    ck_assert_uint_eq(m.triangle_count, 3);
    ck_assert_ptr_null(m.normals);
    ck_assert_ptr_null(m.texcoords);
    /* Fan: (1,2,3), (1,3,4); then (5, 2, 3). */
    ck_assert_uint_eq(m.indices[3], 0);
    ck_assert_uint_eq(m.indices[4], 2);
    ck_assert_uint_eq(m.indices[5], 3);
    ck_assert_uint_eq(m.indices[6], 4);
    ck_assert_uint_eq(m.indices[7], 1);
    ck_assert_uint_eq(m.indices[8], 2);
    ck_assert_double_eq(m.vertices[4].z, 5.0);
    obj_free(&m);
}
END_TEST

START_TEST(obj_should_read_texcoords_and_normals)
{
    const char *text =
        "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
        "vt 0.25 0.5\nvt 1 0\nvt 0 1\n"
        "vn 0 0 1\r\n"
        "f 1/1/1 2/2/1 3/3/1\n"
        "f 1//1 3//1 2//1\n";
    obj_mesh m;
    char err[256];

    ck_assert_int_eq(parse(text, &m, err), 0);
    ck_assert_uint_eq(m.triangle_count, 2);
    ck_assert_uint_eq(m.vertex_count, 6);
    ck_assert_ptr_nonnull(m.normals);
    ck_assert_ptr_nonnull(m.texcoords);
    ck_assert_double_eq(m.texcoords[0], 0.25);
    ck_assert_double_eq(m.texcoords[1], 0.5);
    ck_assert_double_eq(m.normals[4].z, 1.0);
    ck_assert_double_eq(m.texcoords[8], 0.0);   /* corner without vt */
    obj_free(&m);
}
END_TEST

/* Each malformed input: rejected, and the message names the line. */
START_TEST(obj_should_reject_malformed_input_with_line_numbers)
{
    static const struct {
        const char *text, *expect;
    } cases[] = {
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2", "line 4: a face needs 3"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "line 4: vertex index 0"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "line 4: vertex index 4 out"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", "line 4: vertex index -4"},
        {"v 0 0 0\nv 1 x 0\n", "line 2: not a number"},
        {"v 0 0 0\nv 1 0\n", "line 2: expected 3 numbers"},
        {"v nan 0 0\n", "line 1: number out of range"},
        {"v 1e999 0 0\n", "line 1: number out of range"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999999\n",
         "line 4: vertex index out of range"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/5 2 3\n", "line 4: texture index 5"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//2 2 3\n", "line 4: normal index 2"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2x 3\n", "line 4: bad face corner"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf a b c\n", "line 4: bad vertex index"},
        {"v 0 0 0\n", "line 0: no faces"},
        {"", "line 0: no faces"},
    };
    size_t k;

    for (k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        obj_mesh m;
        char err[256] = "";
        ck_assert_msg(parse(cases[k].text, &m, err) == -1, "case %zu", k);
        ck_assert_msg(strstr(err, cases[k].expect) != NULL,
                      "case %zu: '%s' lacks '%s'", k, err, cases[k].expect);
    }
}
END_TEST

/*
** 20000 random mutations (bytes replaced, deleted, truncated) of a valid
** file: each parses or is rejected, never crashes; a parsed mesh always
** has in-range indices and finite vertices (what ray_scene_add_mesh
** checks again).
*/
START_TEST(obj_should_survive_mutated_files)
{
    const char *base =
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 1\nvn 0 0 1\n"
        "f 1/1/1 2/2/1 3/1/1 4/2/1\nf -1 -2 -3\n";
    static const char alphabet[] = "0123456789 /-.enfvt#\n\t+x";
    size_t len = strlen(base);
    rng g = {31337};
    char buf[256], err[256];
    int k;

    for (k = 0; k < 20000; k++) {
        size_t n = len;
        obj_mesh m;
        memcpy(buf, base, len);
        mutate(&g, buf, &n, alphabet, sizeof alphabet - 1);
        if (obj_parse(buf, n, &m, err, sizeof err) == 0) {
            size_t j;
            for (j = 0; j < 3 * m.triangle_count; j++)
                ck_assert_uint_lt(m.indices[j], m.vertex_count);
            for (j = 0; j < m.vertex_count; j++)
                ck_assert(isfinite(m.vertices[j].x) && isfinite(m.vertices[j].y) &&
                          isfinite(m.vertices[j].z));
            obj_free(&m);
        } else
            ck_assert(strncmp(err, "line ", 5) == 0);
    }
}
END_TEST

START_TEST(obj_should_report_missing_files)
{
    obj_mesh m;
    char err[256];

    ck_assert_int_eq(obj_load("/nonexistent/libray.obj", &m, err, sizeof err), -1);
    ck_assert(strstr(err, "/nonexistent/libray.obj: ") == err);
}
END_TEST

Suite *obj_suite(void)
{
    Suite *s = suite_create("obj");
    TCase *tc = tcase_create("obj");

    tcase_add_test(tc, obj_should_read_quads_and_negative_indices);
    tcase_add_test(tc, obj_should_read_texcoords_and_normals);
    tcase_add_test(tc, obj_should_reject_malformed_input_with_line_numbers);
    tcase_add_test(tc, obj_should_survive_mutated_files);
    tcase_add_test(tc, obj_should_report_missing_files);
    suite_add_tcase(s, tc);
    return s;
}
