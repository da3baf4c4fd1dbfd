/* SPDX-License-Identifier: MIT */
/*
** check_bpt.c -- the examples' Bezier patch file reader (examples/bpt.h):
** valid files read exactly, malformed ones rejected with the right line
** number, allocation failures reported, never a crash (the sanitizer runs
** of this suite check "never a crash" and "no leak").  Every file is a
** string here: the suite needs no network and no data/ directory.
*/
#include <stdio.h>
#include <stdlib.h>

#include "tests.h"

/*
** A realloc that fails once "budget" more calls have succeeded (budget
** < 0: never), so the tests can make each allocation of the reader fail
** in turn.  Check forks per test, so the counter is private to a test.
*/
static long alloc_budget = -1;

static void *failing_realloc(void *p, size_t size)
{
    if (alloc_budget == 0)
        return NULL;
    if (alloc_budget > 0)
        alloc_budget--;
    return realloc(p, size);
}

#define BPT_REALLOC failing_realloc
#include "bpt.h"

static int parse(const char *text, bpt_patches *b, char *err)
{
    return bpt_parse(text, strlen(text), b, err, 256);
}

/* One patch over 16 vertices, listed backwards: vertex k (1-based) is
** (k, k/2, -k/4), all exact in binary. */
static const char one_patch[] =
    "1\n"
    "16, 15, 14, 13, 12, 11, 10, 9, 8, 7, 6, 5, 4, 3, 2, 1\n"
    "16\n"
    "1, 0.5, -0.25\n2, 1, -0.5\n3, 1.5, -0.75\n4, 2, -1\n"
    "5, 2.5, -1.25\n6, 3, -1.5\n7, 3.5, -1.75\n8, 4, -2\n"
    "9, 4.5, -2.25\n10, 5, -2.5\n11, 5.5, -2.75\n12, 6, -3\n"
    "13, 6.5, -3.25\n14, 7, -3.5\n15, 7.5, -3.75\n16, 8, -4\n";

START_TEST(bpt_should_read_one_patch_exactly)
{
    bpt_patches b;
    char err[256];
    int c;

    ck_assert_int_eq(parse(one_patch, &b, err), 0);
    ck_assert_uint_eq(b.count, 1);
    ck_assert_uint_eq(b.vertex_count, 16);
    /* Control point c is vertex 16 - c, in the file's (row-major) order. */
    for (c = 0; c < 16; c++) {
        double k = 16 - c;
        ck_assert_vec_eq(b.patches[0][c], vec(k, k / 2, -k / 4));
    }
    bpt_free(&b);
    ck_assert_ptr_null(b.patches);
    ck_assert_uint_eq(b.count, 0);
}
END_TEST

/*
** Two patches sharing vertices, in the file's looser spellings: blanks
** and tabs around commas, CRLF line ends, blank lines, a leading '+',
** exponents, no newline at the end.
*/
START_TEST(bpt_should_read_loose_spacing_and_shared_vertices)
{
    const char *text =
        "\n 2 \r\n"
        "1,2,3,4,  5 ,6,7,8,9,10,11,12,13,14,15,16\r\n"
        "\n"
        "\t16 , 15,14,13,12,11,10,9,8,7,6,5,4,3,2,+1\t\r\n"
        "16\n"
        "1e-3, -2.5E+2, 0\n0,0,0\n0,0,0\n0,0,0\n0,0,0\n0,0,0\n0,0,0\n"
        "0,0,0\n0,0,0\n0,0,0\n0,0,0\n0,0,0\n0,0,0\n0,0,0\n0,0,0\n"
        "  -0.0 ,\t7 , .5   ";
    bpt_patches b;
    char err[256];

    ck_assert_msg(parse(text, &b, err) == 0, "%s", err);
    ck_assert_uint_eq(b.count, 2);
    ck_assert_vec_eq(b.patches[0][0], vec(1e-3, -2.5e2, 0));
    ck_assert_vec_eq(b.patches[1][15], vec(1e-3, -2.5e2, 0));
    ck_assert_vec_eq(b.patches[0][15], vec(0, 7, 0.5));
    ck_assert_vec_eq(b.patches[1][0], vec(0, 7, 0.5));
    ck_assert(signbit(b.patches[1][0].x));      /* -0.0 kept as written */
    bpt_free(&b);
}
END_TEST

/* A small valid file's parts, to build the malformed ones from: a patch
** line of 16 indices into 2 vertices, and those 2 vertices. */
#define PATCH "1,1,1,1,1,1,1,1,1,1,1,1,1,1,1,2\n"
#define VERTS "2\n0,0,0\n1,1,1\n"

/* Each malformed input: rejected, and the message names the line. */
START_TEST(bpt_should_reject_malformed_input_with_line_numbers)
{
    static const struct {
        const char *text, *expect;
    } cases[] = {
        /* Truncated files, and missing counts. */
        {"", "line 1: file ends where the number of patches was expected"},
        {"\n \n", "line 3: file ends where the number of patches"},
        {"1\n", "line 2: file ends where patch 1 of 1 was expected"},
        {"2\n" PATCH, "line 3: file ends where patch 2 of 2"},
        {"1\n" PATCH, "line 3: file ends where the number of vertices"},
        {"1\n" PATCH "2\n0,0,0\n", "line 5: file ends where vertex 2 of 2"},
        {PATCH VERTS, "line 1: expected the number of patches, found a list"},
        {"1\n" PATCH "0,0,0\n1,1,1\n",
         "line 3: expected the number of vertices, found a list"},
        /* More lines than the counts say. */
        {"1\n" PATCH PATCH VERTS,
         "line 3: expected the number of vertices, found a list"},
        {"1\n" PATCH VERTS "1,1,1\n", "line 6: text after the last vertex"},
        {"1\n" PATCH VERTS "\n\nend\n", "line 8: text after the last vertex"},
        /* Bad counts. */
        {"x\n", "line 1: expected the number of patches, found 'x'"},
        {"0\n", "line 1: the number of patches must be positive, not 0"},
        {"-3 \n", "line 1: the number of patches must be positive, not -3"},
        {"1000001\n", "line 1: too many patches (more than 1000000)"},
        {"99999999999999999999999\n", "line 1: too many patches"},
        {"-99999999999999999999999\n", "line 1: the number of patches must "
                                       "be positive, not -9999999999999"},
        {"1000000\n" PATCH, "line 3: file ends where patch 2 of 1000000"},
        {"1 2\n", "line 1: text after the number of patches: '2'"},
        {"1.0\n", "line 1: text after the number of patches: '.0'"},
        {"1\n" PATCH "0\n", "line 3: the number of vertices must be positive"},
        {"1\n" PATCH "1000001\n", "line 3: too many vertices"},
        {"1\n" PATCH "two\n", "line 3: expected the number of vertices, "
                              "found 'two'"},
        /* Bad patch lines. */
        {"1\n1,1,1,1,1,1,1,0,1,1,1,1,1,1,1,2\n" VERTS,
         "line 2: vertex index 0 (indices start at 1)"},
        {"1\n1,1,1,1,1,1,1,-1,1,1,1,1,1,1,1,2\n" VERTS,
         "line 2: vertex index -1 (indices start at 1)"},
        {"1\n1,1,1,1,1,1,1,1,1,1,1,1,1,1,1,3\n" VERTS,
         "line 2: vertex index 3 out of range (2 vertices)"},
        {"2\n\n" PATCH "\n1,1,1,1,1,1,1,1,1,1,1,1,1,1,1,9\n\n" VERTS,
         "line 5: vertex index 9 out of range (2 vertices)"},
        {"1\n1,1,1,1,1,1,1,1,1,1,1,1,1,1,1,99999999999\n" VERTS,
         "line 2: vertex index out of range (more than 1000000)"},
        {"1\n1,1,1,1,1,1,1,1,1,1,1,1,1,1,1\n" VERTS,
         "line 2: expected 16 vertex indices, found 15"},
        {"1\n1,1,1,1,1,1,1,1,1,1,1,1,1,1,2,\n" VERTS,
         "line 2: expected 16 vertex indices, found 15"},
        {"1\n1,1,1,1,1,1,1,1,1,1,1,1,1,1,1,1,2\n" VERTS,
         "line 2: more than 16 vertex indices"},
        {"1\n1,1,1,1,1,1,1,1,1,1,1,1,1,1,2,1,\n" VERTS,
         "line 2: more than 16 vertex indices"},
        {"1\n1,,1,1,1,1,1,1,1,1,1,1,1,1,1,2\n" VERTS,
         "line 2: field 2: not an integer: ',1,1"},
        {"1\n1 1 1 1 1 1 1 1 1 1 1 1 1 1 1 2\n" VERTS,
         "line 2: expected ',' after field 1, found '1 1"},
        {"1\n1,1,1.5,1,1,1,1,1,1,1,1,1,1,1,1,2\n" VERTS,
         "line 2: field 3: not an integer: '1.5"},
        {"1\n1,1,1e0,1,1,1,1,1,1,1,1,1,1,1,1,2\n" VERTS,
         "line 2: field 3: not an integer"},
        {"1\nx,1,1,1,1,1,1,1,1,1,1,1,1,1,1,2\n" VERTS,
         "line 2: field 1: not an integer: 'x"},
        {"1\n1,1,1,1,1,1,1,1,1,1,1,1,1,1,1,2 #\n" VERTS,
         "line 2: text after the vertex indices: '#'"},
        /* Bad vertex lines. */
        {"1\n" PATCH "2\n0,0,0\n1,1\n", "line 5: expected 3 coordinates, "
                                        "found 2"},
        {"1\n" PATCH "2\n0,0,0\n1,1,\n", "line 5: expected 3 coordinates, "
                                         "found 2"},
        {"1\n" PATCH "2\n0,0,0\n1,1,1,1\n", "line 5: more than 3 coordinates"},
        {"1\n" PATCH "2\n0,x,0\n1,1,1\n", "line 4: field 2: not a number: 'x"},
        {"1\n" PATCH "2\nnan,0,0\n1,1,1\n", "line 4: field 1: not finite"},
        {"1\n" PATCH "2\n0,-inf,0\n1,1,1\n", "line 4: field 2: not finite"},
        {"1\n" PATCH "2\n0,0,1e999\n1,1,1\n", "line 4: field 3: not finite"},
        {"1\n" PATCH "2\n0,0,0 junk\n1,1,1\n",
         "line 4: text after the coordinates: 'junk'"},
        {"1\n" PATCH "2\n0 0 0\n1,1,1\n",
         "line 4: expected ',' after field 1"},
    };
    size_t k;

    for (k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        bpt_patches b;
        char err[256] = "";
        ck_assert_msg(parse(cases[k].text, &b, err) == -1, "case %zu", k);
        ck_assert_msg(strstr(err, cases[k].expect) == err,
                      "case %zu: '%s' does not start '%s'", k, err,
                      cases[k].expect);
        ck_assert_ptr_null(b.patches);
        ck_assert_uint_eq(b.count, 0);
    }
}
END_TEST

START_TEST(bpt_should_reject_nul_bytes_and_long_lines)
{
    static const char with_nul[] = "1\n1,1,1\0,1\n";
    char *long_line;
    bpt_patches b;
    char err[256];
    size_t n = 5000;

    ck_assert_int_eq(bpt_parse(with_nul, sizeof with_nul - 1, &b, err,
                               sizeof err), -1);
    ck_assert_str_eq(err, "line 2: NUL byte in text");
    long_line = malloc(n + 1);
    ck_assert_ptr_nonnull(long_line);
    memset(long_line, ' ', n);
    long_line[0] = '1';
    long_line[n] = '\0';
    ck_assert_int_eq(parse(long_line, &b, err), -1);
    ck_assert_str_eq(err, "line 1: line longer than 4095 bytes");
    free(long_line);
}
END_TEST

/* A message cut to a short buffer is still a string; none is allowed. */
START_TEST(bpt_should_truncate_messages_to_the_buffer)
{
    bpt_patches b;
    char err[8];

    memset(err, 'z', sizeof err);
    ck_assert_int_eq(bpt_parse("0\n", 2, &b, err, sizeof err), -1);
    ck_assert_str_eq(err, "line 1:");
    ck_assert_int_eq(bpt_parse("0\n", 2, &b, NULL, 0), -1);
}
END_TEST

/*
** 20000 random mutations (bytes replaced, deleted, truncated) of a valid
** two-patch file: each parses or is rejected with a line number, never
** crashes; parsed patches always have finite control points.
*/
START_TEST(bpt_should_survive_mutated_files)
{
    const char *base =
        "2\n"
        "1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 1, 2, 3, 4\n"
        "4, 3, 2, 1, 12, 11, 10, 9, 8, 7, 6, 5, 4, 3, 2, 1\n"
        "12\n"
        "1.4, 0, 2.4\n1.4, -0.784, 2.4\n0.784, -1.4, 2.4\n0, -1.4, 2.4\n"
        "1.3375, 0, 2.53125\n1.3375, -0.749, 2.53125\n"
        "0.749, -1.3375, 2.53125\n0, -1.3375, 2.53125\n"
        "1.4375, 0, 2.53125\n1.4375, -0.805, 2.53125\n"
        "0.805, -1.4375, 2.53125\n0, -1.4375, 2.53125\n";
    static const char alphabet[] = "0123456789 ,-+.eE\n\r\tnix";
    size_t len = strlen(base);
    rng g = {20240601};
    char buf[1024], err[256];
    int k, parsed = 0;

    ck_assert_uint_lt(len, sizeof buf);
    for (k = 0; k < 20000; k++) {
        size_t n = len;
        bpt_patches b;
        memcpy(buf, base, len);
        mutate(&g, buf, &n, alphabet, sizeof alphabet - 1);
        if (bpt_parse(buf, n, &b, err, sizeof err) == 0) {
            size_t j;
            int c;
            ck_assert_uint_ge(b.count, 1);
            for (j = 0; j < b.count; j++)
                for (c = 0; c < 16; c++)
                    ck_assert(isfinite(b.patches[j][c].x) &&
                              isfinite(b.patches[j][c].y) &&
                              isfinite(b.patches[j][c].z));
            bpt_free(&b);
            parsed++;
        } else {
            ck_assert_msg(strncmp(err, "line ", 5) == 0, "%s", err);
            ck_assert_ptr_null(b.patches);
        }
    }
    /* Some mutations (a digit for a digit) keep the file valid. */
    ck_assert_int_gt(parsed, 0);
}
END_TEST

/* A file of one patch over "vertices" vertices (the patch uses the first
** 16), as a malloc'ed string. */
static char *many_vertices_file(size_t vertices)
{
    size_t cap = 128 + 32 * vertices, len, k;
    char *text = malloc(cap);

    ck_assert_ptr_nonnull(text);
    len = (size_t)snprintf(text, cap, "1\n1,2,3,4,5,6,7,8,9,10,11,12,13,14,"
                                      "15,16\n%zu\n", vertices);
    for (k = 0; k < vertices; k++)
        len += (size_t)snprintf(text + len, cap - len, "%zu, 0.5, -%zu\n",
                                k, k);
    return text;
}

/*
** Each allocation made while parsing fails in turn: the parse reports
** "out of memory" on a line and frees what it had (the sanitizer run
** checks); with enough allocations it succeeds.  200 vertices make the
** vertex array grow several times.
*/
START_TEST(bpt_should_report_each_allocation_failure)
{
    char *text = many_vertices_file(200);
    bpt_patches b;
    char err[256];
    long budget;
    int rc = -1;

    for (budget = 0; budget < 100; budget++) {
        alloc_budget = budget;
        rc = parse(text, &b, err);
        if (rc == 0)
            break;
        ck_assert_msg(strstr(err, ": out of memory") != NULL, "%s", err);
        ck_assert(strncmp(err, "line ", 5) == 0);
        ck_assert_ptr_null(b.patches);
    }
    ck_assert_int_eq(rc, 0);
    /* The patch, 64 -> 128 -> 200 vertices, the output: 5 allocations. */
    ck_assert_int_eq(budget, 5);
    ck_assert_uint_eq(b.vertex_count, 200);
    ck_assert_double_eq(b.patches[0][15].x, 15);
    bpt_free(&b);
    alloc_budget = -1;
    free(text);
}
END_TEST

/* Write text to a new temporary file; its path into path[64]. */
static void write_temp_file(char *path, const char *text)
{
    int fd;
    FILE *f;

    snprintf(path, 64, "/tmp/libray-check-bpt-XXXXXX");
    fd = mkstemp(path);
    ck_assert_int_ge(fd, 0);
    f = fdopen(fd, "wb");
    ck_assert_ptr_nonnull(f);
    ck_assert_uint_eq(fwrite(text, 1, strlen(text), f), strlen(text));
    ck_assert_int_eq(fclose(f), 0);
}

/* A file larger than the first read buffer (64 kB) reads like the same
** text parsed from memory; a failed buffer is reported with the path. */
START_TEST(bpt_should_load_files)
{
    char *text = many_vertices_file(5000), path[64], err[256];
    bpt_patches b, ref;
    ray_vec3 lo, hi;

    ck_assert_uint_gt(strlen(text), 65536);
    write_temp_file(path, text);
    ck_assert_msg(bpt_load(path, &b, err, sizeof err) == 0, "%s", err);
    ck_assert_int_eq(parse(text, &ref, err), 0);
    ck_assert_uint_eq(b.count, 1);
    ck_assert_uint_eq(b.vertex_count, 5000);
    ck_assert_int_eq(memcmp(b.patches, ref.patches, sizeof *b.patches), 0);
    bpt_bounds(&b, &lo, &hi);
    ck_assert_vec_eq(lo, vec(0, 0.5, -15));
    ck_assert_vec_eq(hi, vec(15, 0.5, 0));
    bpt_free(&b);
    bpt_free(&ref);

    alloc_budget = 0;
    ck_assert_int_eq(bpt_load(path, &b, err, sizeof err), -1);
    alloc_budget = -1;
    ck_assert(strstr(err, path) == err);
    ck_assert_str_eq(err + strlen(path), ": out of memory");
    remove(path);
    free(text);
}
END_TEST

START_TEST(bpt_should_name_the_file_in_errors)
{
    bpt_patches b;
    char path[64], err[256];

    ck_assert_int_eq(bpt_load("/nonexistent/libray.bpt", &b, err, sizeof err),
                     -1);
    ck_assert(strstr(err, "/nonexistent/libray.bpt: ") == err);
    ck_assert_ptr_null(b.patches);
    /* A directory opens (on Linux) but cannot be read. */
    ck_assert_int_eq(bpt_load("/", &b, err, sizeof err), -1);
    ck_assert(strncmp(err, "/: ", 3) == 0);

    write_temp_file(path, "1\n" PATCH "2\n0,0,0\n");
    ck_assert_int_eq(bpt_load(path, &b, err, sizeof err), -1);
    ck_assert(strstr(err, path) == err);
    ck_assert_str_eq(err + strlen(path),
                     ": line 5: file ends where vertex 2 of 2 was expected");
    remove(path);
}
END_TEST

Suite *bpt_suite(void)
{
    Suite *s = suite_create("bpt");
    TCase *tc = tcase_create("bpt");

    tcase_add_test(tc, bpt_should_read_one_patch_exactly);
    tcase_add_test(tc, bpt_should_read_loose_spacing_and_shared_vertices);
    tcase_add_test(tc, bpt_should_reject_malformed_input_with_line_numbers);
    tcase_add_test(tc, bpt_should_reject_nul_bytes_and_long_lines);
    tcase_add_test(tc, bpt_should_truncate_messages_to_the_buffer);
    tcase_add_test(tc, bpt_should_survive_mutated_files);
    tcase_add_test(tc, bpt_should_report_each_allocation_failure);
    tcase_add_test(tc, bpt_should_load_files);
    tcase_add_test(tc, bpt_should_name_the_file_in_errors);
    suite_add_tcase(s, tc);
    return s;
}
