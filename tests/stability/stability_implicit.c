/*
 * Stiff and extreme cases for the implicit module: far-from-origin and
 * tiny-scale contours, steep and overflowing fields, discontinuities, NaN
 * patches, features smaller than a cell, degenerate domains, large grids
 * (topology independent of refinement), extreme intervals, and volumes
 * whose headers promise more data than they hold.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "geom/implicit.h"

static geom_implicit_expr *compile_ok(const char *s)
{
    geom_implicit_expr *e = NULL;
    geom_diag d;
    if (geom_implicit_expr_compile(s, strlen(s), NULL, &e, &d) != GEOM_OK)
        fail_msg("compile '%s': %s", s, d.message);
    return e;
}

static void contour(const char *s, double x0, double y0, double x1, double y1, size_t nx,
                    size_t ny, double iso, int refine, geom_implicit_isolines *out)
{
    geom_implicit_expr *e = compile_ok(s);
    geom_implicit_field f;
    geom_implicit_field_from_expr(e, &f);
    double b[4] = {x0, y0, x1, y1};
    geom_implicit_contour_options o;
    memset(&o, 0, sizeof o);
    o.iso = iso;
    o.refine = refine;
    geom_diag d;
    if (geom_implicit_contour(&f, b, nx, ny, &o, out, &d) != GEOM_OK)
        fail_msg("contour '%s': %s", s, d.message);
    geom_implicit_expr_destroy(e);
}

/* Cheap structural checks for large outputs: finite vertices inside the
 * bounds, valid indices, no zero-length segment. */
static void check_basic(const geom_implicit_isolines *c, const double b[4])
{
    for (size_t v = 0; v < c->n_vertices; v++) {
        double x = c->xy[2 * v], y = c->xy[2 * v + 1];
        assert_true(isfinite(x) && isfinite(y));
        assert_true(x >= b[0] && x <= b[2] && y >= b[1] && y <= b[3]);
    }
    for (size_t k = 0; k < c->n_polylines; k++) {
        size_t s = c->start[k], e = c->start[k + 1];
        assert_true(e - s >= 2);
        for (size_t q = s; q < e; q++) {
            assert_true(c->indices[q] < c->n_vertices);
            uint32_t a = c->indices[q], n = c->indices[q + 1 < e ? q + 1 : s];
            if (q + 1 < e || c->closed[k])
                assert_true(c->xy[2 * a] != c->xy[2 * n] || c->xy[2 * a + 1] != c->xy[2 * n + 1]);
        }
    }
}

static void test_far_and_tiny(void **state)
{
    (void)state;
    geom_implicit_isolines c;
    /* a unit circle 1e8 from the origin: positions to a few ulp of 1e8 */
    contour("sphere(1e8, 0, 0, 1)", 1e8 - 2, -2, 1e8 + 2, 2, 64, 64, 0, 0, &c);
    double b1[4] = {1e8 - 2, -2, 1e8 + 2, 2};
    check_basic(&c, b1);
    assert_int_equal(c.n_polylines, 1);
    assert_true(c.closed[0]);
    for (size_t v = 0; v < c.n_vertices; v++)
        assert_true(fabs(hypot(c.xy[2 * v] - 1e8, c.xy[2 * v + 1]) - 1) < 1e-7);
    geom_implicit_isolines_free(&c);
    /* a circle of radius 1e-150: relative accuracy is kept */
    contour("sphere(1e-150)", -2e-150, -2e-150, 2e-150, 2e-150, 40, 40, 0, 0, &c);
    assert_int_equal(c.n_polylines, 1);
    for (size_t v = 0; v < c.n_vertices; v++)
        assert_true(fabs(hypot(c.xy[2 * v], c.xy[2 * v + 1]) / 1e-150 - 1) < 1e-14);
    geom_implicit_isolines_free(&c);
    /* a circle smaller than a cell between the nodes: nothing, no crash */
    contour("(x - 0.05)^2 + (y - 0.05)^2 - 1e-20", -1, -1, 1, 1, 10, 10, 0, 0, &c);
    assert_int_equal(c.n_polylines, 0);
    geom_implicit_isolines_free(&c);
    /* a domain 1e-10 thin */
    contour("x - 0.3", 0, 0, 1, 1e-10, 100, 1, 0, 0, &c);
    assert_int_equal(c.n_polylines, 1);
    assert_int_equal(c.n_vertices, 2);
    assert_true(fabs(c.xy[0] - 0.3) < 1e-16);
    geom_implicit_isolines_free(&c);
}

static void test_steep_and_overflowing(void **state)
{
    (void)state;
    geom_implicit_isolines c;
    double b[4] = {-1, -1, 1, 1};
    /* exp(80 x) - 1: values from 1e-35 to 5e34; the root x = 0 is found */
    contour("exp(80*x) - 1", -1, -1, 1, 1, 7, 7, 0, 0, &c);
    check_basic(&c, b);
    assert_int_equal(c.n_polylines, 1);
    for (size_t v = 0; v < c.n_vertices; v++)
        assert_true(fabs(c.xy[2 * v]) < 1e-15);
    assert_true(c.report.error.max_error < 1e-15);
    geom_implicit_isolines_free(&c);
    /* values overflowing to +-inf at most nodes */
    contour("1e300 * x * 1e10 + y * 0", -1, -1, 1, 1, 7, 8, 0, 0, &c);
    check_basic(&c, b);
    assert_int_equal(c.n_polylines, 1);
    for (size_t v = 0; v < c.n_vertices; v++)
        assert_true(c.xy[2 * v] == 0.0);
    geom_implicit_isolines_free(&c);
    /* an isovalue beyond every value */
    contour("sphere(1)", -1, -1, 1, 1, 8, 8, 1e300, 0, &c);
    assert_int_equal(c.n_polylines, 0);
    geom_implicit_isolines_free(&c);
    /* a jump (x / |x| - 0.5): the crossing converges onto the discontinuity
     * within the iteration limit */
    contour("x / abs(x) - 0.5 + 0*y", -1, -1, 1.3, 1, 10, 4, 0, 0, &c);
    check_basic(&c, b);
    assert_int_equal(c.n_polylines, 1);
    for (size_t v = 0; v < c.n_vertices; v++)
        assert_true(fabs(c.xy[2 * v]) < 1e-300 || fabs(c.xy[2 * v]) < 1e-15);
    geom_implicit_isolines_free(&c);
    /* NaN patches: sqrt of a sign-changing function */
    contour("sqrt(sin(7*x)) - 0.5", -1, -1, 1, 1, 50, 20, 0, 0, &c);
    check_basic(&c, b);
    assert_true(c.report.skipped_cells > 0);
    /* on the isoline, or (NaN is outside, as +inf) on the edge of a NaN
     * region, where sin(7x) reaches 0 */
    size_t on_nan_edge = 0;
    for (size_t v = 0; v < c.n_vertices; v++) {
        double s7 = sin(7 * c.xy[2 * v]);
        if (fabs(s7) < 1e-12)
            on_nan_edge++;
        else
            assert_true(fabs(s7 - 0.25) < 1e-13);
    }
    assert_true(on_nan_edge > 0);
    geom_implicit_isolines_free(&c);
    /* a field zero on every node: sin(pi x) sin(pi y) on integer nodes is
     * +-1e-16 there; the output stays structurally valid */
    contour("sin(pi*x) * sin(pi*y)", -2, -2, 2, 2, 4, 4, 0, 0, &c);
    double b2[4] = {-2, -2, 2, 2};
    check_basic(&c, b2);
    geom_implicit_isolines_free(&c);
}

static void test_large_grid(void **state)
{
    (void)state;
    /* 1000 x 1000 cells of an egg-crate field: many loops; refinement
     * moves vertices but never changes the topology */
    geom_implicit_isolines lin, ref;
    double b[4] = {-3, -3, 3, 3};
    contour("0.2 - sin(10*x)*sin(10*y) + 0.01*x", -3, -3, 3, 3, 1000, 1000, 0, GEOM_IMPLICIT_REFINE_NEVER, &lin);
    contour("0.2 - sin(10*x)*sin(10*y) + 0.01*x", -3, -3, 3, 3, 1000, 1000, 0, GEOM_IMPLICIT_REFINE_AUTO, &ref);
    check_basic(&lin, b);
    check_basic(&ref, b);
    assert_true(lin.n_polylines > 50);
    assert_int_equal(lin.n_polylines, ref.n_polylines);
    assert_int_equal(lin.n_vertices, ref.n_vertices);
    for (size_t k = 0; k <= lin.n_polylines; k++)
        assert_int_equal(lin.start[k], ref.start[k]);
    assert_memory_equal(lin.indices, ref.indices, lin.start[lin.n_polylines] * sizeof(uint32_t));
    assert_true(ref.report.error.max_error < 1e-13);
    assert_true(lin.report.error.max_error > 1e-9 && lin.report.error.max_error < 1e-4);
    geom_implicit_isolines_free(&lin);
    geom_implicit_isolines_free(&ref);
}

static void test_extreme_intervals(void **state)
{
    (void)state;
    const char *exprs[] = {"x*y*z", "sin(x) + cos(y)", "exp(x)", "log(abs(x) + 1)",
                           "sphere(1) * 1e300", "1e308 * x + 1e308 * y", "x^7 - y^6",
                           "atan2(y, x)", "tan(x)", "x / y"};
    double lo[3] = {-1e300, -1e300, -1e300}, hi[3] = {1e300, 1e300, 1e300};
    for (size_t k = 0; k < sizeof exprs / sizeof exprs[0]; k++) {
        geom_implicit_expr *e = compile_ok(exprs[k]);
        double iv[2];
        assert_int_equal(geom_implicit_expr_eval_interval(e, lo, hi, iv), GEOM_OK);
        assert_false(isnan(iv[0]));
        for (int s = 0; s < 27; s++) {
            double p[3];
            for (int a = 0; a < 3; a++) {
                int d = (s / (a == 0 ? 1 : a == 1 ? 3 : 9)) % 3;
                p[a] = d == 0 ? lo[a] : d == 1 ? 0.37 : hi[a];
            }
            double v = geom_implicit_expr_eval(e, p);
            if (isfinite(v) && !(iv[0] <= v && v <= iv[1]))
                fail_msg("%s: %.17g outside [%.17g, %.17g]", exprs[k], v, iv[0], iv[1]);
        }
        geom_implicit_expr_destroy(e);
    }
    /* subnormal boxes */
    geom_implicit_expr *e = compile_ok("x*y + sqrt(x) - 1/x");
    double slo[3] = {DBL_TRUE_MIN, DBL_TRUE_MIN, 0}, shi[3] = {4 * DBL_TRUE_MIN, DBL_MIN, 0};
    double iv[2];
    assert_int_equal(geom_implicit_expr_eval_interval(e, slo, shi, iv), GEOM_OK);
    double p[3] = {2 * DBL_TRUE_MIN, DBL_MIN / 3, 0};
    double v = geom_implicit_expr_eval(e, p);
    assert_true(!isfinite(v) || (iv[0] <= v && v <= iv[1]));
    geom_implicit_expr_destroy(e);
}

static void test_expression_limits(void **state)
{
    (void)state;
    /* exactly at the default depth limit, and a constant chain folded away */
    char buf[512];
    size_t n = 0;
    for (int i = 0; i < 63; i++)
        buf[n++] = '(';
    buf[n++] = 'x';
    for (int i = 0; i < 63; i++)
        buf[n++] = ')';
    geom_implicit_expr *e;
    assert_int_equal(geom_implicit_expr_compile(buf, n, NULL, &e, NULL), GEOM_OK);
    geom_implicit_expr_destroy(e);
    e = compile_ok("1e308 * 10 - 1e308 * 10 + 0 * x");
    double p[3] = {1, 2, 3};
    assert_true(isnan(geom_implicit_expr_eval(e, p)));
    geom_implicit_expr_destroy(e);
    /* numbers at the edges of the double range */
    e = compile_ok("1.7976931348623157e308 + 4.9406564584124654e-324 * x + 1e-400");
    assert_true(geom_implicit_expr_eval(e, p) == DBL_MAX);
    geom_implicit_expr_destroy(e);
    /* a 400-digit number is accepted, 401 is a limit */
    memset(buf, '1', 399);
    buf[399] = 'e';
    buf[400] = '\0';
    assert_int_equal(geom_implicit_expr_compile(buf, 399, NULL, &e, NULL), GEOM_ERR_PARSE);
    memset(buf, '0', 399);
    buf[0] = '1';
    buf[1] = '.';
    assert_int_equal(geom_implicit_expr_compile(buf, 399, NULL, &e, NULL), GEOM_OK);
    assert_true(geom_implicit_expr_eval(e, p) == 1.0);
    geom_implicit_expr_destroy(e);
}

static void test_volume_promises(void **state)
{
    (void)state;
    geom_implicit_volume *v;
    geom_diag d;
    /* sizes whose product is huge but fits size_t: the size check fails
     * before any allocation */
    const char *h = "NRRD0004\ntype: double\ndimension: 3\nsizes: 100000 100000 100000\n"
                    "endian: little\nencoding: raw\n\n12345678";
    assert_int_equal(geom_implicit_volume_read_nrrd_memory(h, strlen(h), NULL, NULL, &v, &d),
                     GEOM_ERR_PARSE);
    assert_non_null(strstr(d.message, "need 8000000000000000"));
    h = "NRRD0004\ntype: float\ndimension: 3\nsizes: 1000000 1000000 1000000\nencoding: ascii\n\n1";
    assert_int_equal(geom_implicit_volume_read_nrrd_memory(h, strlen(h), NULL, NULL, &v, &d),
                     GEOM_ERR_PARSE);
    /* sizes overflowing size_t */
    h = "NRRD0004\ntype: float\ndimension: 3\nsizes: 4294967296 4294967296 4294967296\n"
        "endian: big\nencoding: raw\n\n";
    assert_int_equal(geom_implicit_volume_read_nrrd_memory(h, strlen(h), NULL, NULL, &v, &d),
                     GEOM_ERR_LIMIT);
    /* a NaN sample and an infinite one: trilinear evaluation away from them
     * stays finite, contouring takes the NaN node as outside */
    geom_implicit_volume_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.dims[0] = 5, desc.dims[1] = 5, desc.dims[2] = 1;
    desc.type = GEOM_IMPLICIT_SCALAR_F64;
    assert_int_equal(geom_implicit_volume_create(&desc, NULL, &v), GEOM_OK);
    double *s = geom_implicit_volume_data(v);
    for (int j = 0; j < 5; j++)
        for (int i = 0; i < 5; i++)
            s[i + 5 * j] = i - 2.5;
    s[0] = NAN;
    s[24] = INFINITY;
    double p[3] = {2.5, 2.5, 0};
    assert_true(geom_implicit_volume_eval(v, p) == 0.0);
    double node[3] = {1, 0, 0};
    assert_true(geom_implicit_volume_eval(v, node) == -1.5); /* the NaN neighbour has weight 0 */
    geom_implicit_field f;
    geom_implicit_field_from_volume(v, &f);
    double b[4] = {0, 0, 4, 4};
    geom_implicit_isolines c;
    assert_int_equal(geom_implicit_contour(&f, b, 4, 4, NULL, &c, NULL), GEOM_OK);
    assert_int_equal(c.report.skipped_cells, 1);
    assert_int_equal(c.report.nan_nodes, 1);
    /* the line x = 2.5, and the NaN corner (outside, as +inf, as in 3D)
     * cut off its cell by a segment between its edges' midpoints (an
     * infinite end: the midpoint; a sampled field is not refined) */
    assert_int_equal(c.n_polylines, 2);
    size_t corner = 0;
    for (size_t q = 0; q < c.n_vertices; q++) {
        double x = c.xy[2 * q], y = c.xy[2 * q + 1];
        if ((x == 0.5 && y == 0) || (x == 0 && y == 0.5))
            corner++;
        else
            assert_true(x == 2.5);
    }
    assert_int_equal(corner, 2);
    geom_implicit_isolines_free(&c);
    geom_implicit_volume_destroy(v);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_far_and_tiny),
        cmocka_unit_test(test_steep_and_overflowing),
        cmocka_unit_test(test_large_grid),
        cmocka_unit_test(test_extreme_intervals),
        cmocka_unit_test(test_expression_limits),
        cmocka_unit_test(test_volume_promises),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
