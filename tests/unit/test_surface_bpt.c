/* Surface module: the .bpt Bezier patch reader (Newell's teapot format) and
 * surface sets. The teapot's values are those of the file (its first
 * patch's rows start with points 1..4 = (1.4, 0, 2.4), (1.4, -0.784, 2.4),
 * (0.784, -1.4, 2.4), (0, -1.4, 2.4)); malformed inputs must name the line
 * and column. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "geom/surface.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void test_teapot_file(void **state)
{
    (void)state;
    const char *dir = getenv("GEOM_TEST_DATA");
    char path[1024];
    snprintf(path, sizeof path, "%s/teapot.bpt", dir ? dir : "data");
    geom_surface_set *set = NULL;
    geom_diag d;
    assert_int_equal(geom_surface_read_bpt(path, NULL, &set, &d), GEOM_OK);
    assert_int_equal((int)geom_surface_set_count(set), 32);
    const geom_nurbs_surface *S = geom_surface_set_data(set);
    for (int k = 0; k < 32; ++k) {
        assert_int_equal(S[k].degree_u, 3);
        assert_int_equal(S[k].degree_v, 3);
        assert_int_equal((int)S[k].nu, 4);
        assert_null(S[k].weights);
        assert_int_equal(geom_surface_validate(&S[k], NULL), GEOM_OK);
    }
    /* first row of the first patch runs along u: control points (i, 0) */
    const double row[4][3] = {{1.4, 0, 2.4}, {1.4, -0.784, 2.4}, {0.784, -1.4, 2.4},
                              {0, -1.4, 2.4}};
    for (int i = 0; i < 4; ++i)
        assert_memory_equal(S[0].points + 3 * (i * 4 + 0), row[i], 3 * sizeof(double));
    /* patch 1's second line is points 5..8: (1.3375, 0, 2.53125), ... */
    const double p5[3] = {1.3375, 0.0, 2.53125};
    assert_memory_equal(S[0].points + 3 * (0 * 4 + 1), p5, sizeof p5);
    assert_string_equal(geom_surface_set_name(set, 31), "patch 32");
    assert_null(geom_surface_set_name(set, 32));
    geom_surface_set_destroy(set);
    assert_int_equal(geom_surface_read_bpt("/nonexistent/teapot.bpt", NULL, &set, &d),
                     GEOM_ERR_IO);
    assert_null(set);
}

static geom_status parse(const char *text, geom_surface_set **set, geom_diag *d)
{
    return geom_surface_read_bpt_memory(text, strlen(text), "t.bpt", NULL, set, d);
}

#define IDX16 "1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16\n"
#define PTS16                                                                                     \
    "0 0 0\n1 0 0\n2 0 0\n3 0 0\n0 1 0\n1 1 1\n2 1 1\n3 1 0\n"                                    \
    "0 2 0\n1 2 1\n2 2 1\n3 2 0\n0 3 0\n1 3 0\n2 3 0\n3 3 0\n"

static void test_small_inputs(void **state)
{
    (void)state;
    geom_surface_set *set = NULL;
    geom_diag d;
    /* comments, blank lines, CRLF, blanks and commas mixed */
    const char *ok = "# one patch\r\n1\r\n\r\n1 2 3 4, 5 6 7 8,9,10,11,12 13 14 15 16\r\n16\r\n" PTS16;
    assert_int_equal(parse(ok, &set, &d), GEOM_OK);
    assert_int_equal((int)geom_surface_set_count(set), 1);
    const geom_nurbs_surface *s = geom_surface_set_data(set);
    double p[3];
    assert_int_equal(geom_surface_eval(s, 1.0, 1.0, 0, p), GEOM_OK);
    assert_true(p[0] == 3.0 && p[1] == 3.0 && p[2] == 0.0);
    /* item 4*r + c is control point (c, r): the point at (u, v) = (1, 0)
     * is item 3, (3, 0, 0) */
    assert_int_equal(geom_surface_eval(s, 1.0, 0.0, 0, p), GEOM_OK);
    assert_true(p[0] == 3.0 && p[1] == 0.0);
    geom_surface_set_destroy(set);

    struct {
        const char *text;
        geom_status st;
        size_t line, col;
        const char *msg;
    } bad[] = {
        {"x\n", GEOM_ERR_PARSE, 1, 1, "invalid number 'x'"},
        {"0\n", GEOM_ERR_PARSE, 1, 1, "positive integer"},
        {"1\n1,2,3\n", GEOM_ERR_PARSE, 2, 1, "3 values, 16 expected"},
        {"1\n" IDX16 "2\n" "0 0 0\n", GEOM_ERR_PARSE, 4, 0, "point 2 of 2"},
        {"1\n" IDX16 "15\n", GEOM_ERR_PARSE, 3, 1, "larger than the input can hold"},
        {"1\n0,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16\n", GEOM_ERR_PARSE, 2, 1, "index 1 is 0"},
        {"1\n" IDX16 "2\n0 0 0\n1 1 1\n", GEOM_ERR_PARSE, 2, 1, "index 3 is 3"},
        {"1\n" IDX16 "16\n" PTS16 "extra\n", GEOM_ERR_PARSE, 20, 1, "after the 16 points"},
        {"1\n1,,2,3,4,5,6,7,8,9,10,11,12,13,14,15\n", GEOM_ERR_PARSE, 2, 3, "empty field"},
        {"1\n1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,\n", GEOM_ERR_PARSE, 2, 0, "trailing ','"},
        {"1\n" IDX16 "1\n1.2.3 0 0\n", GEOM_ERR_PARSE, 4, 1, "invalid number '1.2.3'"},
        {"1\n" IDX16 "1\n1e999 0 0\n", GEOM_ERR_PARSE, 4, 1, "invalid number"},
        {"1\n" IDX16 "1\nnan 0 0\n", GEOM_ERR_PARSE, 4, 1, "invalid number"},
        {"1\n" IDX16 "1\n0 0\n", GEOM_ERR_PARSE, 4, 1, "2 values, 3 expected"},
        {"99999999\n", GEOM_ERR_LIMIT, 1, 1, "above the limit"},
        {"1000\n" IDX16, GEOM_ERR_PARSE, 1, 1, "larger than the input"},
        {"", GEOM_ERR_PARSE, 0, 0, "unexpected end"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        geom_diag_clear(&d);
        set = (geom_surface_set *)1;
        geom_status st = parse(bad[i].text, &set, &d);
        if (st != bad[i].st || !strstr(d.message, bad[i].msg) ||
            (bad[i].line && d.line != bad[i].line) || (bad[i].col && d.column != bad[i].col))
            fail_msg("case %zu: status %d, %s:%zu:%zu: %s", i, st, d.source, d.line, d.column,
                     d.message);
        assert_null(set);
        assert_string_equal(d.source, "t.bpt");
    }
    /* never reads past size: the text without its final newline and digits */
    const char *cut = "1\n" IDX16 "16\n" PTS16;
    assert_int_equal(geom_surface_read_bpt_memory(cut, strlen(cut) - 3, "cut", NULL, &set, &d),
                     GEOM_ERR_PARSE);
}

static void test_set(void **state)
{
    (void)state;
    geom_surface_set *set = geom_surface_set_create(NULL);
    assert_non_null(set);
    assert_int_equal((int)geom_surface_set_count(set), 0);
    assert_null(geom_surface_set_data(set));
    double ku[12], kv[8], P[135], W[45];
    geom_nurbs_surface s;
    assert_int_equal(geom_surface_sphere(NULL, 1.0, ku, kv, P, W, &s), GEOM_OK);
    for (int i = 0; i < 20; ++i)
        assert_int_equal(geom_surface_set_add(set, &s, i == 3 ? "three" : NULL), GEOM_OK);
    assert_int_equal((int)geom_surface_set_count(set), 20);
    const geom_nurbs_surface *v = geom_surface_set_data(set);
    /* deep copies: changing the source changes nothing */
    P[0] = 42.0;
    assert_true(v[19].points[0] != 42.0);
    assert_memory_equal(v[5].weights, W, sizeof W);
    assert_string_equal(geom_surface_set_name(set, 3), "three");
    assert_string_equal(geom_surface_set_name(set, 4), "");
    assert_int_equal(geom_surface_set_add(set, NULL, NULL), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_surface_set_add(NULL, &s, NULL), GEOM_ERR_INVALID_ARG);
    geom_surface_set_destroy(set);
    geom_surface_set_destroy(NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_teapot_file),
        cmocka_unit_test(test_small_inputs),
        cmocka_unit_test(test_set),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
