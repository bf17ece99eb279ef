/*
 * Marching cubes samples an expression row by row (y and z fixed along a
 * grid row) with geom__implicit_expr_row: every value bit for bit
 * geom_implicit_expr_eval's, for every operation and primitive, constant
 * and varying primitive arguments, rows shorter and longer than a block,
 * NaN/Inf/huge coordinates and programs deeper than the block stack. Then
 * whole extractions: an expression field against the same expression
 * behind other callbacks (the generic batch path), sparse and dense,
 * arrays and stream, bit for bit.
 */
#include "unit/test_util.h"

#include <string.h>

#include "geom/iso.h"
/* the row evaluator (the static library the tests link exports it; the
 * library's include path is this test's, tests/CMakeLists.txt) */
#include "implicit/implicit_internal.h"

static uint64_t rng_state = 0x2545F4914F6CDD1Dull;

static geom_implicit_expr *compile(const char *text)
{
    geom_implicit_expr *e = NULL;
    assert_int_equal(geom_implicit_expr_compile(text, strlen(text), NULL, &e, NULL), GEOM_OK);
    return e;
}

/* Primitives with constant arguments (one lane loop each in the row
 * evaluator), with arguments of x (lane by lane), of y and z only
 * (constants of the row), the smooth operations and clamp both ways, and
 * every operation on x, y, z. */
static const char *const row_exprs[] = {
    "sphere(1)", "sphere(0.3, 0.1, -0.2, 0.7)", "ellipsoid(1, 0.5, 2)",
    "ellipsoid(0.1, -0.2, 0.3, 1, 0.5, 2)", "torus(1, 0.3)", "torus(-0.7, 0, 0, 0.9, 0.3)",
    "min(torus(-0.7,0,0,0.9,0.3),torus(0.7,0,0,0.9,0.3))", "box(0.5, 0.7, 0.2)",
    "box(0.1, 0.2, -0.3, 0.5, 0.7, 0.2)", "cylinder(0.5, 0.8)", "cylinder(0.1, 0, 0.2, 0.5, 0.8)",
    "plane(1, -2, 0.5, 0.1)", "capsule(-1, 0, 0, 1, 0.5, 0, 0.2)", "gyroid()", "gyroid(3)",
    "gyroid(4, 0.2)", "sphere(t)", "sphere(y, z, 0, 1)", "torus(y, 0, z, 1, 0.25)",
    "sphere(x, 0, 0, 1)", "box(0, 0, 0, x, 1, 1)", "torus(0.5 * y, 0.2)",
    "smooth_union(sphere(0.5), box(0.3, 0.3, 0.3), 0.2)", "smooth_union(y, z, 0.2)",
    "smooth_intersection(y, x, z)", "smooth_difference(box(1, 1, 1), sphere(1.2), y)",
    "clamp(y * 3, -1, 1)", "clamp(x * 3, y, z)", "clamp(t, x, y)", "x + y - z", "x*y*z",
    "y*z + x", "x*y - z*y", "y / z - x", "sqrt(y) + x", "sqrt(x) - 0.5", "abs(y) * 2 + x",
    "x^3 + y^2", "pow(y, z) + pow(x, y)", "atan2(y, x) + atan2(z, y)", "exp(y) * sin(x)",
    "log(z) - cos(x) + tan(y)", "min(x, y, z)", "max(y, z) - x", "-y + x", "t * 2 + y",
    "1e300 * x * y", "(x + 1e16) - 1e16",
    /* constants of the row folded through several operations, into sums of
     * products, constant lanes, primitive arguments and the result */
    "x*y + z*x - y*z", "x*(y*y + 1) + (z - y)*x", "sqrt(x*x + y*y + z*z) - 1",
    "x^2 + y^2 + z^2 - 1", "sqrt(x^2 + (y - 0.5)^2) - z", "y*z", "sin(y) * cos(z) + 2",
    "sphere(sin(y), cos(z) * 0.5, y*z, 1 + y^2)", "clamp(x, min(y, z), max(y, z) + 1)",
    "smooth_union(x - y, torus(y*z, 0.2), abs(z) + 0.1)", "exp(-(y*y + z*z)) * x + y",
};

/* Row points: some special coordinates among random ones. */
static void fill_x(double *x, size_t n)
{
    static const double special[] = {NAN, INFINITY, -INFINITY, 0.0, -0.0, 1e300, -1e300,
                                     1e-310, 0.5, 1e8 + 0.25};
    for (size_t i = 0; i < n; i++) {
        x[i] = -2.5 + 5 * test_urand(&rng_state);
        if (i % 13 == 5)
            x[i] = special[(i / 13) % (sizeof special / sizeof special[0])];
    }
}

static void check_rows(geom_implicit_expr *e, const char *text)
{
    static const size_t counts[] = {1, 2, 7, 63, 64, 65, 130, 513};
    static const double ys[] = {0.25, -1.75, 0.0, -0.0, NAN, INFINITY, 1e8, 1e-310};
    static const double zs[] = {0.5, -0.125, 1e300, -INFINITY};
    double x[513], out[513];
    /* one row plan for every row, in a changing order of y and z */
    geom__expr_rows *plan = NULL;
    assert_int_equal(geom__implicit_expr_rows_create(e, NULL, &plan), GEOM_OK);
    for (size_t c = 0; c < sizeof counts / sizeof counts[0]; c++)
        for (size_t yi = 0; yi < sizeof ys / sizeof ys[0]; yi++)
            for (size_t zi = 0; zi < sizeof zs / sizeof zs[0]; zi++) {
                size_t n = counts[c];
                fill_x(x, n);
                for (int way = 0; way < 2; way++) {
                    memset(out, 0xA5, sizeof out);
                    if (way == 0)
                        geom__implicit_expr_row(e, n, x, ys[yi], zs[zi], out);
                    else
                        geom__implicit_expr_rows(plan, n, x, ys[yi], zs[zi], out);
                    for (size_t i = 0; i < n; i++) {
                        double p[3] = {x[i], ys[yi], zs[zi]};
                        double v = geom_implicit_expr_eval(e, p);
                        if (!same_bits_or_nan(v, out[i]))
                            fail_msg("%s, row of %zu (%s), point %zu (%g, %g, %g): row %.17g, "
                                     "single %.17g",
                                     text, n, way ? "one plan" : "own plan", i, p[0], p[1],
                                     p[2], out[i], v);
                    }
                }
                /* nothing written past the row */
                for (size_t i = n; i < 513; i++) {
                    uint64_t bits;
                    memcpy(&bits, &out[i], sizeof bits);
                    assert_true(bits == 0xA5A5A5A5A5A5A5A5ull);
                }
            }
    geom__implicit_expr_rows_destroy(plan);
}

static void test_rows_bitwise(void **state)
{
    (void)state;
    for (size_t k = 0; k < sizeof row_exprs / sizeof row_exprs[0]; k++) {
        geom_implicit_expr *e = compile(row_exprs[k]);
        static const double times[] = {0.25, -1.5, NAN};
        for (size_t ti = 0; ti < 3; ti++) {
            geom_implicit_expr_set_time(e, times[ti]);
            check_rows(e, row_exprs[k]);
        }
        geom_implicit_expr_destroy(e);
    }
}

/* A program deeper than the block stack: the point-by-point fallback. */
static void test_rows_deep(void **state)
{
    (void)state;
    char text[64 * 4 + 8];
    size_t k = 0;
    for (int i = 0; i < 60; i++) {
        memcpy(text + k, "y+(", 3);
        k += 3;
    }
    text[k++] = 'x';
    for (int i = 0; i < 60; i++)
        text[k++] = ')';
    text[k] = '\0';
    geom_implicit_expr *e = compile(text);
    check_rows(e, "60 nested sums");
    geom_implicit_expr_destroy(e);
}

/* The expression behind callbacks marching cubes does not recognise: the
 * generic batch path (f->values on gathered points). */
static double other_value(void *u, const double p[3])
{
    return geom_implicit_expr_eval(u, p);
}
static void other_values(void *u, size_t n, const double *p, double *out)
{
    geom_implicit_expr_eval_many(u, n, p, out);
}

typedef struct chunks {
    double *xyz;
    uint32_t *tris;
    size_t nv, nt;
} chunks;

static geom_status collect(void *user, const geom_iso_chunk *ch)
{
    chunks *c = user;
    assert_int_equal(ch->first_vertex, c->nv);
    c->xyz = realloc(c->xyz, (c->nv + ch->n_vertices) * 3 * sizeof(double) + 8);
    c->tris = realloc(c->tris, (c->nt + ch->n_triangles) * 3 * sizeof(uint32_t) + 4);
    assert_non_null(c->xyz);
    assert_non_null(c->tris);
    if (ch->n_vertices)
        memcpy(c->xyz + 3 * c->nv, ch->xyz, 3 * ch->n_vertices * sizeof(double));
    if (ch->n_triangles)
        memcpy(c->tris + 3 * c->nt, ch->tris, 3 * ch->n_triangles * sizeof(uint32_t));
    c->nv += ch->n_vertices;
    c->nt += ch->n_triangles;
    return GEOM_OK;
}

static void test_rows_extract_same(void **state)
{
    (void)state;
    static const char *const texts[] = {
        "min(torus(-0.7,0,0,0.9,0.3),torus(0.7,0,0,0.9,0.3))", "gyroid(6)",
        "sphere(y, 0, 0, 0.5) - 0.1 * x", "sqrt(x) - 0.5"};
    const double b[6] = {-1.08, -1.296, -0.432, 2.16, 1.296, 0.432};
    const size_t res[3] = {83, 41, 17};
    for (size_t k = 0; k < sizeof texts / sizeof texts[0]; k++) {
        geom_implicit_expr *e = compile(texts[k]);
        geom_iso_field fe, fo;
        assert_int_equal(geom_iso_field_from_expr(e, &fe), GEOM_OK);
        fo = fe;
        fo.value = other_value;
        fo.values = other_values;
        for (int dense = 0; dense <= 1; dense++)
            for (int caps = 0; caps <= 1; caps++) {
                geom_iso_options o;
                memset(&o, 0, sizeof o);
                o.dense = dense;
                o.caps = caps;
                o.block_size = caps ? 3 : 0;
                /* several threads over one-layer slabs: the stream path
                 * hands slabs over while later ones are computed, and its
                 * error samples thin out as the stride doubles */
                o.threads = 3;
                o.slab_layers = 1 + (size_t)caps;
                o.error_samples = 300;
                o.error = GEOM_ISO_ERROR_ALWAYS;
                geom_iso_surface a, g;
                assert_int_equal(geom_iso_extract(&fe, b, res, &o, &a, NULL), GEOM_OK);
                assert_int_equal(geom_iso_extract(&fo, b, res, &o, &g, NULL), GEOM_OK);
                assert_true(a.n_vertices > 0);
                assert_int_equal(a.n_vertices, g.n_vertices);
                assert_int_equal(a.n_triangles, g.n_triangles);
                assert_memory_equal(a.xyz, g.xyz, 3 * a.n_vertices * sizeof(double));
                assert_memory_equal(a.tris, g.tris, 3 * a.n_triangles * sizeof(uint32_t));
                assert_int_equal(a.report.vertex_error.evaluations,
                                 g.report.vertex_error.evaluations);
                assert_true(a.report.error.max_error == g.report.error.max_error);
                /* and the stream path over the expression */
                chunks c = {NULL, NULL, 0, 0};
                geom_iso_surface s;
                assert_int_equal(geom_iso_extract_stream(&fe, b, res, &o, collect, &c, &s, NULL),
                                 GEOM_OK);
                assert_int_equal(c.nv, a.n_vertices);
                assert_int_equal(c.nt, a.n_triangles);
                assert_memory_equal(c.xyz, a.xyz, 3 * a.n_vertices * sizeof(double));
                assert_memory_equal(c.tris, a.tris, 3 * a.n_triangles * sizeof(uint32_t));
                assert_true(s.report.error.max_error == a.report.error.max_error);
                assert_true(s.report.vertex_error.max_error == a.report.vertex_error.max_error);
                assert_int_equal(s.report.error_stride, a.report.error_stride);
                assert_true(a.report.error_stride > 1);
                assert_int_equal(s.report.error.pieces, a.report.error.pieces);
                assert_int_equal(s.report.unmeasured, a.report.unmeasured);
                assert_true(s.report.signed_volume == a.report.signed_volume);
                free(c.xyz);
                free(c.tris);
                geom_iso_surface_free(&s);
                geom_iso_surface_free(&a);
                geom_iso_surface_free(&g);
            }
        geom_implicit_expr_destroy(e);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rows_bitwise),
        cmocka_unit_test(test_rows_deep),
        cmocka_unit_test(test_rows_extract_same),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
