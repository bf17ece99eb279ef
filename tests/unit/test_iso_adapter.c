/* Fields and grids for marching cubes from the implicit module's
 * expressions and volumes (libgeom/src/iso/implicit_adapter.c). */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "geom/iso.h"

static geom_implicit_volume *make_volume(size_t nx, size_t ny, size_t nz,
                                         geom_implicit_scalar type, double sp, double org,
                                         double (*fn)(double, double, double))
{
    geom_implicit_volume_desc d;
    memset(&d, 0, sizeof d);
    d.dims[0] = nx, d.dims[1] = ny, d.dims[2] = nz;
    d.type = type;
    for (int a = 0; a < 3; a++) {
        d.spacing[a] = sp * (a + 1);
        d.origin[a] = org;
    }
    geom_implicit_volume *v;
    assert_int_equal(geom_implicit_volume_create(&d, NULL, &v), GEOM_OK);
    void *data = geom_implicit_volume_data(v);
    for (size_t k = 0; k < nz; k++)
        for (size_t j = 0; j < ny; j++)
            for (size_t i = 0; i < nx; i++) {
                double x = org + i * sp, y = org + j * 2 * sp, z = org + k * 3 * sp;
                size_t idx = i + nx * (j + ny * k);
                if (type == GEOM_IMPLICIT_SCALAR_F32)
                    ((float *)data)[idx] = (float)fn(x, y, z);
                else
                    ((double *)data)[idx] = fn(x, y, z);
            }
    return v;
}

/* The adapters to the marching cubes module's structs. */
static double sphere_fn(double x, double y, double z) { return sqrt(x * x + y * y + z * z) - 1; }

static void test_iso_adapters(void **state)
{
    (void)state;
    const char *text = "smooth_union(sphere(1), torus(1.5, 0.3), 0.2) + 0.1*gyroid(3)";
    geom_implicit_expr *e;
    assert_int_equal(geom_implicit_expr_compile(text, strlen(text), NULL, &e, NULL), GEOM_OK);
    geom_iso_field f;
    assert_int_equal(geom_iso_field_from_expr(e, &f), GEOM_OK);
    assert_true(f.exact == 1 && f.values != NULL && f.gradient != NULL);
    enum { N = 1000 };
    double *pts = malloc(3 * N * sizeof(double)), *vals = malloc(N * sizeof(double));
    for (int i = 0; i < N; i++) {
        pts[3 * i] = -2 + 4.0 * (i % 10) / 9.0;
        pts[3 * i + 1] = -2 + 4.0 * ((i / 10) % 10) / 9.0;
        pts[3 * i + 2] = -2 + 4.0 * (i / 100) / 9.0;
    }
    f.values(f.user, N, pts, vals);
    for (int i = 0; i < N; i++) {
        double g1[3], g2[3];
        assert_true(vals[i] == f.value(f.user, &pts[3 * i]));
        assert_true(vals[i] == geom_implicit_expr_eval(e, &pts[3 * i]));
        f.gradient(f.user, &pts[3 * i], g1);
        geom_implicit_expr_eval_grad(e, &pts[3 * i], g2);
        assert_memory_equal(g1, g2, sizeof g1);
    }
    free(pts);
    free(vals);
    geom_implicit_expr_destroy(e);
    assert_int_equal(geom_iso_field_from_expr(NULL, &f), GEOM_ERR_INVALID_ARG);
    assert_null(f.value);

    geom_implicit_volume *v = make_volume(9, 9, 9, GEOM_IMPLICIT_SCALAR_F32, 0.25, -1, sphere_fn);
    assert_int_equal(geom_iso_field_from_volume(v, &f), GEOM_OK);
    assert_false(f.exact);
    double p[3] = {0.1, 0.2, 0.3}, g[3], g2[3];
    assert_true(f.value(f.user, p) == geom_implicit_volume_eval(v, p));
    f.gradient(f.user, p, g);
    geom_implicit_volume_eval_grad(v, p, g2);
    assert_memory_equal(g, g2, sizeof g);
    geom_iso_grid grid;
    assert_int_equal(geom_iso_grid_from_volume(v, &grid), GEOM_OK);
    assert_true(grid.dims[0] == 9 && grid.type == GEOM_ISO_SCALAR_F32);
    assert_true(grid.spacing[1] == 0.5 && grid.origin[2] == -1);
    assert_ptr_equal(grid.data, geom_implicit_volume_cdata(v));
    geom_implicit_volume_destroy(v);
}

/* The error report measured through the batched value-and-gradient
 * callback equals, bit for bit, the one measured point by point (value and
 * gradient callbacks), with the same evaluation count. */
static void test_batched_error_report(void **state)
{
    (void)state;
    const char *src = "min(torus(-0.7,0,0,0.9,0.3), torus(0.7,0,0,0.9,0.3))";
    geom_implicit_expr *e = NULL;
    assert_int_equal(geom_implicit_expr_compile(src, strlen(src), NULL, &e, NULL), GEOM_OK);
    geom_iso_field f;
    assert_int_equal(geom_iso_field_from_expr(e, &f), GEOM_OK);
    assert_non_null(f.gradients);
    double b[6] = {-2.16, -1.296, -0.432, 2.16, 1.296, 0.432};
    size_t r[3] = {40, 24, 9};
    geom_iso_surface s[2];
    for (int k = 0; k < 2; k++) {
        geom_iso_options o;
        memset(&o, 0, sizeof o);
        o.threads = 1;
        geom_iso_field g = f;
        if (k)
            g.gradients = NULL;
        memset(&s[k], 0, sizeof s[k]);
        assert_int_equal(geom_iso_extract(&g, b, r, &o, &s[k], NULL), GEOM_OK);
    }
    assert_true(s[0].n_triangles > 1000);
    assert_int_equal(s[0].report.vertex_error.method, GEOM_ERROR_SAMPLED);
    const geom_error_report *r0[2] = {&s[0].report.vertex_error, &s[0].report.sample_error};
    const geom_error_report *r1[2] = {&s[1].report.vertex_error, &s[1].report.sample_error};
    for (int k = 0; k < 2; k++) { /* all but the time */
        assert_memory_equal(&r0[k]->max_error, &r1[k]->max_error, sizeof(double));
        assert_memory_equal(&r0[k]->mean_error, &r1[k]->mean_error, sizeof(double));
        assert_int_equal(r0[k]->method, r1[k]->method);
        assert_int_equal(r0[k]->evaluations, r1[k]->evaluations);
        assert_int_equal(r0[k]->pieces, r1[k]->pieces);
    }
    assert_true(s[0].report.error.max_error == fmax(r0[0]->max_error, r0[1]->max_error));
    assert_true(s[0].report.error.mean_error == r0[1]->mean_error);
    assert_int_equal(s[0].report.error.pieces, r0[0]->pieces + r0[1]->pieces);
    assert_true(s[0].report.error.seconds == s[0].report.seconds);
    assert_int_equal(s[0].report.unmeasured, s[1].report.unmeasured);
    geom_iso_surface_free(&s[0]);
    geom_iso_surface_free(&s[1]);
    geom_implicit_expr_destroy(e);
}

/* inside = ABOVE: on a grid of -d (d the distance to a sphere minus its
 * radius) the surface is, bit for bit, that of d with inside below (same
 * vertices, same triangles, same normals); on d itself it is the same
 * surface turned inside out (negative signed volume), and with caps the
 * inside part of the box (box minus ball: positive volume); an invalid
 * inside value is rejected. */
static void test_inside_above(void **state)
{
    (void)state;
    enum { N = 14 };
    static double d[N * N * N], nd[N * N * N];
    for (int k = 0; k < N; k++)
        for (int j = 0; j < N; j++)
            for (int i = 0; i < N; i++) {
                double x = i - 6.3, y = j - 6.6, z = k - 6.45;
                d[i + N * (j + N * k)] = sqrt(x * x + y * y + z * z) - 4.0;
                nd[i + N * (j + N * k)] = -d[i + N * (j + N * k)];
            }
    geom_iso_grid g;
    memset(&g, 0, sizeof g);
    g.dims[0] = g.dims[1] = g.dims[2] = N;
    g.type = GEOM_ISO_SCALAR_F64;
    g.data = d;
    geom_iso_grid gn = g;
    gn.data = nd;
    geom_iso_options o;
    memset(&o, 0, sizeof o);
    o.normals = 1;
    geom_iso_surface a, b, c, e;
    assert_int_equal(geom_iso_extract_grid(&g, &o, &a, NULL), GEOM_OK);
    o.inside = GEOM_ISO_INSIDE_ABOVE;
    assert_int_equal(geom_iso_extract_grid(&gn, &o, &b, NULL), GEOM_OK);
    assert_int_equal(geom_iso_extract_grid(&g, &o, &c, NULL), GEOM_OK);
    assert_true(a.n_triangles > 100);
    assert_int_equal(a.n_vertices, b.n_vertices);
    assert_int_equal(a.n_triangles, b.n_triangles);
    assert_memory_equal(a.xyz, b.xyz, 3 * a.n_vertices * sizeof(double));
    assert_memory_equal(a.normals, b.normals, 3 * a.n_vertices * sizeof(double));
    assert_memory_equal(a.tris, b.tris, 3 * a.n_triangles * sizeof(uint32_t));
    double ball = 4.0 / 3.0 * 3.14159265358979 * 64.0;
    assert_true(fabs(a.report.signed_volume - ball) < 0.06 * ball); /* 4 cells radius */
    assert_true(a.report.signed_volume == b.report.signed_volume);
    assert_int_equal(c.n_triangles, a.n_triangles);
    assert_true(fabs(c.report.signed_volume + a.report.signed_volume) <
                1e-9 * a.report.signed_volume);
    for (size_t v = 0; v < c.n_vertices; v++) /* normals point into the ball */
        assert_true(c.normals[3 * v] * (c.xyz[3 * v] - 6.3) < 1e-9);
    o.caps = 1;
    assert_int_equal(geom_iso_extract_grid(&g, &o, &e, NULL), GEOM_OK);
    double box = 13.0 * 13.0 * 13.0;
    assert_true(fabs(e.report.signed_volume - (box - ball)) < 0.02 * (box - ball));
    geom_iso_surface_free(&a);
    geom_iso_surface_free(&b);
    geom_iso_surface_free(&c);
    geom_iso_surface_free(&e);
    o.inside = 7;
    assert_int_equal(geom_iso_extract_grid(&g, &o, &a, NULL), GEOM_ERR_INVALID_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_iso_adapters),
        cmocka_unit_test(test_batched_error_report),
        cmocka_unit_test(test_inside_above),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
