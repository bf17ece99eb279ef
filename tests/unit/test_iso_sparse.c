/* The sparse path of marching cubes (blocks the surface provably misses
 * are skipped) against the dense path: the same vertices, triangles,
 * order, normals, caps and report counts, bit for bit. Also the interval
 * bounds with definedness it relies on, against point evaluation. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "geom/iso.h"

/* Extract with the dense and the sparse path and compare everything. */
static void same_both_ways(const geom_iso_field *f, const double b[6], const size_t res[3],
                           const geom_iso_options *base, size_t *evaluated)
{
    geom_iso_options o = *base;
    geom_iso_surface d, s;
    o.dense = 1;
    assert_int_equal(geom_iso_extract(f, b, res, &o, &d, NULL), GEOM_OK);
    o.dense = 0;
    assert_int_equal(geom_iso_extract(f, b, res, &o, &s, NULL), GEOM_OK);
    assert_int_equal(d.n_vertices, s.n_vertices);
    assert_int_equal(d.n_triangles, s.n_triangles);
    assert_int_equal(d.n_cap_triangles, s.n_cap_triangles);
    if (d.n_vertices)
        assert_memory_equal(d.xyz, s.xyz, 3 * d.n_vertices * sizeof(double));
    if (d.n_triangles)
        assert_memory_equal(d.tris, s.tris, 3 * d.n_triangles * sizeof(uint32_t));
    assert_true((d.normals == NULL) == (s.normals == NULL));
    if (d.normals && d.n_vertices)
        assert_memory_equal(d.normals, s.normals, 3 * d.n_vertices * sizeof(double));
    assert_int_equal(d.report.active_cells, s.report.active_cells);
    assert_int_equal(d.report.ambiguous_faces, s.report.ambiguous_faces);
    assert_int_equal(d.report.tunnels, s.report.tunnels);
    assert_int_equal(d.report.iso_nodes, s.report.iso_nodes);
    assert_int_equal(d.report.nan_nodes, s.report.nan_nodes);
    assert_int_equal(d.report.refined, s.report.refined);
    assert_true(d.report.error.max_error == s.report.error.max_error);
    assert_true(d.report.signed_volume == s.report.signed_volume);
    assert_int_equal(d.report.cells_evaluated, d.report.cells);
    assert_int_equal(d.report.blocks, 0);
    assert_true(s.report.cells_evaluated <= s.report.cells);
    if (evaluated)
        *evaluated = s.report.cells_evaluated;
    geom_iso_surface_free(&d);
    geom_iso_surface_free(&s);
}

static geom_implicit_expr *compile(const char *text)
{
    geom_implicit_expr *e = NULL;
    assert_int_equal(geom_implicit_expr_compile(text, strlen(text), NULL, &e, NULL), GEOM_OK);
    return e;
}

static void check_expr(const char *text, const double b[6], const size_t res[3], double iso,
                       size_t *evaluated)
{
    geom_implicit_expr *e = compile(text);
    geom_iso_field f;
    assert_int_equal(geom_iso_field_from_expr(e, &f), GEOM_OK);
    assert_non_null(f.bounds);
    geom_iso_options o;
    memset(&o, 0, sizeof o);
    o.iso = iso;
    same_both_ways(&f, b, res, &o, evaluated);
    /* every option that changes what is made */
    o.caps = 1;
    same_both_ways(&f, b, res, &o, NULL);
    o.normals = 1;
    o.refine = 1;
    same_both_ways(&f, b, res, &o, NULL);
    o.caps = 0;
    o.inside = GEOM_ISO_INSIDE_ABOVE;
    same_both_ways(&f, b, res, &o, NULL);
    memset(&o, 0, sizeof o);
    o.iso = iso;
    o.threads = 1;
    o.slab_layers = 3;
    for (size_t bs = 1; bs <= 5; bs += 2) {
        o.block_size = bs;
        same_both_ways(&f, b, res, &o, NULL);
    }
    geom_implicit_expr_destroy(e);
}

static void test_iso_sparse_same_as_dense(void **state)
{
    (void)state;
    const double b[6] = {-2.16, -1.296, -0.432, 2.16, 1.296, 0.432};
    const size_t res[3] = {80, 48, 16};
    size_t ev = 0;
    /* two tori, the benchmark's field: most blocks are skipped */
    check_expr("min(torus(-0.7,0,0,0.9,0.3),torus(0.7,0,0,0.9,0.3))", b, res, 0.0, NULL);
    const size_t rbig[3] = {160, 96, 32};
    geom_implicit_expr *tt = compile("min(torus(-0.7,0,0,0.9,0.3),torus(0.7,0,0,0.9,0.3))");
    geom_iso_field ft;
    assert_int_equal(geom_iso_field_from_expr(tt, &ft), GEOM_OK);
    geom_iso_options ot;
    memset(&ot, 0, sizeof ot);
    same_both_ways(&ft, b, rbig, &ot, &ev);
    assert_true(ev < rbig[0] * rbig[1] * rbig[2]);
    geom_implicit_expr_destroy(tt);
    tt = compile("sphere(0.5)");
    assert_int_equal(geom_iso_field_from_expr(tt, &ft), GEOM_OK);
    const double bc[6] = {-1, -1, -1, 1, 1, 1};
    const size_t r64[3] = {64, 64, 64};
    same_both_ways(&ft, bc, r64, &ot, &ev);
    assert_true(ev < 64 * 64 * 64 / 4);
    geom_implicit_expr_destroy(tt);
    /* values exactly on the iso value at grid nodes: planes through nodes
     * (power-of-two steps make the node coordinates exact) */
    const double b2[6] = {-1, -1, -1, 1, 1, 1};
    const size_t r2[3] = {16, 16, 16};
    check_expr("x - 0.25", b2, r2, 0.0, NULL);
    check_expr("max(abs(x), abs(y), abs(z)) - 0.5", b2, r2, 0.0, NULL);
    check_expr("x*x + y*y + z*z", b2, r2, 0.25, NULL);
    /* thin features: a plate and a tube much thinner than a cell */
    const size_t r3[3] = {23, 19, 29};
    check_expr("abs(z - 0.01) - 0.001", b2, r3, 0.0, NULL);
    check_expr("torus(0.5, 0.004)", b2, r3, 0.0, NULL);
    check_expr("min(sphere(0.3, 0, 0, 0.02), sphere(-0.31, 0.1, 0.2, 0.5))", b2, r3, 0.0, NULL);
    /* NaN regions (sqrt and log of negatives): never skipped inside */
    check_expr("sqrt(x) - 0.5", b2, r3, 0.0, NULL);
    check_expr("log(x + y) + 0.5", b2, r3, 0.0, NULL);
    check_expr("1 / x - 3", b2, r3, 0.0, NULL);
    /* saddles and tunnels */
    check_expr("gyroid(6)", b2, r3, 0.0, NULL);
    /* the surface misses the box */
    check_expr("sphere(0.1) - 5", b2, r3, 0.0, &ev);
    assert_int_equal(ev, 0);
}

/* The rule the sparse path relies on: bounds with defined = 1 enclose the
 * point evaluation at every point of the box, NaN never occurring. */
static void test_iso_sparse_bounds_enclose(void **state)
{
    (void)state;
    const char *texts[] = {"min(torus(-0.7,0,0,0.9,0.3),torus(0.7,0,0,0.9,0.3))",
                           "sqrt(x) - 0.5",
                           "log(x + y) + 0.5",
                           "1 / x - 3",
                           "x^0.5 + y",
                           "gyroid(6) + smooth_union(box(0.3, 0.2, 0.1), capsule(0,0,0,1,1,1,0.1), 0.2)",
                           "exp(x*y) - tan(z) + atan2(y, x)"};
    unsigned seed = 12345;
    for (size_t t = 0; t < sizeof texts / sizeof texts[0]; t++) {
        geom_implicit_expr *e = compile(texts[t]);
        int seen_defined = 0, seen_undefined = 0;
        for (int box = 0; box < 400; box++) {
            double lo[3], hi[3], out[2];
            for (int a = 0; a < 3; a++) {
                seed = seed * 1103515245u + 12345u;
                double c = ((seed >> 8) & 0xFFFF) / 32768.0 - 1.0;
                seed = seed * 1103515245u + 12345u;
                double w = ((seed >> 8) & 0xFFFF) / 65536.0 * 0.3;
                lo[a] = c - w;
                hi[a] = c + w;
            }
            int defined = -1;
            assert_int_equal(geom_implicit_expr_eval_bounds(e, lo, hi, out, &defined), GEOM_OK);
            double iv[2];
            assert_int_equal(geom_implicit_expr_eval_interval(e, lo, hi, iv), GEOM_OK);
            if (!isnan(iv[0]))
                assert_true(out[0] >= iv[0] && out[1] <= iv[1]); /* as tight or tighter */
            seen_defined += defined == 1;
            seen_undefined += defined == 0;
            for (int q = 0; q < 200; q++) {
                double p[3];
                for (int a = 0; a < 3; a++) {
                    seed = seed * 1103515245u + 12345u;
                    double u = ((seed >> 8) & 0xFFFF) / 65535.0;
                    p[a] = q < 8 ? ((q >> a) & 1 ? hi[a] : lo[a]) : lo[a] + u * (hi[a] - lo[a]);
                }
                double v = geom_implicit_expr_eval(e, p);
                if (defined) {
                    assert_false(isnan(v));
                    assert_true(v >= out[0] && v <= out[1]);
                }
            }
        }
        if (t == 0)
            assert_int_equal(seen_undefined, 0);
        if (t >= 1 && t <= 4)
            assert_true(seen_undefined > 0 && seen_defined > 0);
        geom_implicit_expr_destroy(e);
    }
    double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1}, out[2];
    int defined = 7;
    assert_int_equal(geom_implicit_expr_eval_bounds(NULL, lo, hi, out, &defined),
                     GEOM_ERR_INVALID_ARG);
    assert_int_equal(defined, 0);
    assert_true(isnan(out[0]) && isnan(out[1]));
}

/* Sampled grids: block min/max, NaN samples, f32 and f64, inside above. */
static void test_iso_sparse_grid(void **state)
{
    (void)state;
    size_t dims[3] = {41, 27, 33};
    size_t n = dims[0] * dims[1] * dims[2];
    double *dv = malloc(n * sizeof(double));
    float *fv = malloc(n * sizeof(float));
    assert_non_null(dv);
    assert_non_null(fv);
    for (int variant = 0; variant < 3; variant++) {
        for (size_t k = 0; k < dims[2]; k++)
            for (size_t j = 0; j < dims[1]; j++)
                for (size_t i = 0; i < dims[0]; i++) {
                    double x = (double)i / 8 - 2, y = (double)j / 8 - 1.5, z = (double)k / 8 - 2;
                    double v = sqrt(x * x + y * y + z * z) - 1.25;
                    if (variant == 1)
                        v = fmin(v, fabs(z - 0.5) - 0.01); /* a thin plate */
                    if (variant == 2 && (i * 7 + j * 3 + k) % 97 == 0)
                        v = NAN;
                    if (variant == 2 && i == 20)
                        v = 0.0; /* a node layer exactly at iso */
                    size_t at = i + dims[0] * (j + dims[1] * k);
                    dv[at] = v;
                    fv[at] = (float)v;
                }
        for (int type = 0; type < 2; type++) {
            geom_iso_grid g;
            memset(&g, 0, sizeof g);
            memcpy(g.dims, dims, sizeof dims);
            g.type = type ? GEOM_ISO_SCALAR_F32 : GEOM_ISO_SCALAR_F64;
            g.data = type ? (const void *)fv : (const void *)dv;
            for (int opts = 0; opts < 4; opts++) {
                geom_iso_options o;
                memset(&o, 0, sizeof o);
                o.caps = opts & 1;
                o.inside = (opts & 2) ? GEOM_ISO_INSIDE_ABOVE : GEOM_ISO_INSIDE_BELOW;
                o.normals = opts == 3;
                o.block_size = opts == 2 ? 3 : 0;
                geom_iso_surface d, s;
                o.dense = 1;
                assert_int_equal(geom_iso_extract_grid(&g, &o, &d, NULL), GEOM_OK);
                o.dense = 0;
                assert_int_equal(geom_iso_extract_grid(&g, &o, &s, NULL), GEOM_OK);
                assert_true(d.n_triangles > 0);
                assert_int_equal(d.n_vertices, s.n_vertices);
                assert_int_equal(d.n_triangles, s.n_triangles);
                assert_int_equal(d.n_cap_triangles, s.n_cap_triangles);
                assert_memory_equal(d.xyz, s.xyz, 3 * d.n_vertices * sizeof(double));
                assert_memory_equal(d.tris, s.tris, 3 * d.n_triangles * sizeof(uint32_t));
                if (o.normals)
                    assert_memory_equal(d.normals, s.normals, 3 * d.n_vertices * sizeof(double));
                assert_int_equal(d.report.iso_nodes, s.report.iso_nodes);
                assert_int_equal(d.report.nan_nodes, s.report.nan_nodes);
                assert_true(s.report.blocks > 0);
                if (variant == 0)
                    assert_true(s.report.blocks_skipped > 0 &&
                                s.report.cells_evaluated < s.report.cells);
                geom_iso_surface_free(&d);
                geom_iso_surface_free(&s);
            }
        }
    }
    free(dv);
    free(fv);
}

/* The error report's sampling rule: within the budget, the stride
 * reported, every point measured when asked. */
static void test_iso_error_sampling(void **state)
{
    (void)state;
    geom_implicit_expr *e = compile("torus(1, 0.4)");
    geom_iso_field f;
    assert_int_equal(geom_iso_field_from_expr(e, &f), GEOM_OK);
    const double b[6] = {-1.5, -1.5, -0.5, 1.5, 1.5, 0.5};
    const size_t res[3] = {60, 60, 20};
    geom_iso_options o;
    memset(&o, 0, sizeof o);
    o.error_samples = SIZE_MAX;
    geom_iso_surface all, some;
    assert_int_equal(geom_iso_extract(&f, b, res, &o, &all, NULL), GEOM_OK);
    assert_int_equal(all.report.error_stride, 1);
    size_t total = all.n_vertices + 4 * all.n_triangles;
    assert_int_equal(all.report.error.pieces + all.report.unmeasured, total);
    o.error_samples = 1000;
    assert_int_equal(geom_iso_extract(&f, b, res, &o, &some, NULL), GEOM_OK);
    size_t s = some.report.error_stride;
    assert_true(s > 1);
    size_t expect = (all.n_vertices + s - 1) / s + 4 * ((all.n_triangles + s - 1) / s);
    assert_true(expect <= 1000);
    /* the smallest power of two within the budget */
    assert_int_equal(s & (s - 1), 0);
    size_t h = s / 2;
    assert_true((all.n_vertices + h - 1) / h + 4 * ((all.n_triangles + h - 1) / h) > 1000);
    assert_int_equal(some.report.error.pieces + some.report.unmeasured, expect);
    /* a subset: its max cannot exceed the full max, and for this smooth
     * field it is close to it */
    assert_true(some.report.error.max_error <= all.report.error.max_error);
    assert_true(some.report.error.max_error >= 0.5 * all.report.error.max_error);
    geom_iso_surface_free(&all);
    geom_iso_surface_free(&some);
    geom_implicit_expr_destroy(e);
}

/* One interpolator: a volume and a grid over the same samples agree bit
 * for bit, values and gradients; samples are exact next to NaN ones. */
static void test_one_interpolator(void **state)
{
    (void)state;
    for (int type = 1; type <= 2; type++) {
        geom_implicit_volume_desc d;
        memset(&d, 0, sizeof d);
        d.dims[0] = 7, d.dims[1] = 5, d.dims[2] = 4;
        d.type = (geom_implicit_scalar)type;
        d.spacing[0] = 0.5, d.spacing[1] = 0.25, d.spacing[2] = 2;
        d.origin[0] = -1, d.origin[1] = 3, d.origin[2] = 0.5;
        geom_implicit_volume *v = NULL;
        assert_int_equal(geom_implicit_volume_create(&d, NULL, &v), GEOM_OK);
        void *data = geom_implicit_volume_data(v);
        size_t n = 7 * 5 * 4;
        for (size_t q = 0; q < n; q++) {
            double val = q == 17 ? NAN : sin((double)q * 1.7) * 3;
            if (type == 1)
                ((float *)data)[q] = (float)val;
            else
                ((double *)data)[q] = val;
        }
        geom_iso_grid g;
        assert_int_equal(geom_iso_grid_from_volume(v, &g), GEOM_OK);
        unsigned seed = 99;
        for (int k = 0; k < 2000; k++) {
            double p[3];
            for (int a = 0; a < 3; a++) {
                seed = seed * 1103515245u + 12345u;
                double u = ((seed >> 8) & 0xFFFF) / 65535.0 * 1.2 - 0.1;
                p[a] = d.origin[a] + u * d.spacing[a] * (double)(d.dims[a] - 1);
            }
            double a1 = geom_implicit_volume_eval(v, p), a2 = geom_iso_grid_value(&g, p);
            assert_memory_equal(&a1, &a2, sizeof a1);
            double g1[3], g2[3];
            geom_implicit_volume_eval_grad(v, p, g1);
            geom_iso_grid_gradient(&g, p, g2);
            assert_memory_equal(g1, g2, sizeof g1);
        }
        /* sample 16 (i = 2, j = 2, k = 0) next to the NaN sample 17 */
        double p[3] = {d.origin[0] + 2 * 0.5, d.origin[1] + 2 * 0.25, d.origin[2]};
        double expect = type == 1 ? (double)((float *)data)[16] : ((double *)data)[16];
        assert_true(geom_implicit_volume_eval(v, p) == expect);
        assert_true(geom_iso_grid_value(&g, p) == expect);
        geom_implicit_volume_destroy(v);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_iso_sparse_same_as_dense),
        cmocka_unit_test(test_iso_sparse_bounds_enclose),
        cmocka_unit_test(test_iso_sparse_grid),
        cmocka_unit_test(test_iso_error_sampling),
        cmocka_unit_test(test_one_interpolator),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
