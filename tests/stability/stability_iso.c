/*
 * Stiff and extreme inputs for marching cubes. Every output must be a clean
 * mesh (manifold, consistently oriented, no duplicate points or faces, no
 * degenerate triangle) and, where the surface cannot leave the box or caps
 * are on, closed:
 *  - power-of-two scalings of the field (2^900, 2^-900): the same surface,
 *    bit for bit (every decision and interpolation is scale-invariant);
 *    subnormal values (2^-1070): the same topology;
 *  - infinite values, NaN, finite values whose difference overflows;
 *  - large regions exactly at the isovalue; values from {-1, 0, 1} and
 *    small integers on random grids (every kind of tie), with and without
 *    caps; checkerboards (every face a saddle exactly at the isovalue);
 *  - far-off coordinates with small cells (vertices must stay distinct),
 *    very anisotropic cells, grids one cell thick;
 *  - a 1024^3 procedural grid in bounded memory (peak resident size below
 *    2 GiB; a smaller grid under sanitizers).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include "geom/iso.h"
#include "unit/test_iso_util.h"

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define ISO_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define ISO_SANITIZED 1
#endif
#endif
#ifndef ISO_SANITIZED
#define ISO_SANITIZED 0
#endif

static void assert_clean(const geom_iso_surface *s, int closed)
{
    iso_topo r = iso_topology(s->n_vertices, s->xyz, s->n_triangles, s->tris);
    if (!iso_topo_clean(&r) || (closed && r.boundary_edges)) {
        fprintf(stderr,
                "not clean: nonmanifold %ld/%ld misoriented %ld dup points %ld dup faces %ld "
                "degenerate %ld isolated %ld open edges %ld\n",
                r.nonmanifold_edges, r.nonmanifold_vertices, r.misoriented_edges,
                r.duplicate_points, r.duplicate_faces, r.degenerate_faces, r.isolated_vertices,
                r.boundary_edges);
        fail();
    }
}

static geom_iso_surface grid_surface(const double *d, size_t nx, size_t ny, size_t nz, double iso,
                                     int caps)
{
    geom_iso_grid g;
    memset(&g, 0, sizeof g);
    g.dims[0] = nx, g.dims[1] = ny, g.dims[2] = nz;
    g.type = GEOM_ISO_SCALAR_F64;
    g.data = d;
    geom_iso_options o;
    memset(&o, 0, sizeof o);
    o.iso = iso;
    o.caps = caps;
    geom_iso_surface s;
    assert_int_equal(geom_iso_extract_grid(&g, &o, &s, NULL), GEOM_OK);
    return s;
}

/* ------------------------------------------------------------- scaling */

static double scale_factor;

static double scaled_torus(void *u, const double p[3])
{
    return iso_f_torus(u, p) * scale_factor;
}

static void test_scaling(void **state)
{
    (void)state;
    geom_iso_field f;
    memset(&f, 0, sizeof f);
    f.value = scaled_torus;
    double b[6] = {-1.5, -1.5, -0.5, 1.5, 1.5, 0.5};
    size_t res[3] = {33, 31, 12};
    geom_iso_surface ref, s;
    scale_factor = 1;
    assert_int_equal(geom_iso_extract(&f, b, res, NULL, &ref, NULL), GEOM_OK);
    assert_clean(&ref, 1);
    const double exact[2] = {0x1p900, 0x1p-900};
    for (int q = 0; q < 2; q++) {
        scale_factor = exact[q];
        assert_int_equal(geom_iso_extract(&f, b, res, NULL, &s, NULL), GEOM_OK);
        assert_int_equal(s.n_vertices, ref.n_vertices);
        assert_int_equal(s.n_triangles, ref.n_triangles);
        assert_memory_equal(s.xyz, ref.xyz, 3 * s.n_vertices * sizeof(double));
        assert_memory_equal(s.tris, ref.tris, 3 * s.n_triangles * sizeof(uint32_t));
        geom_iso_surface_free(&s);
    }
    /* subnormal values: a few bits of precision, the same topology */
    scale_factor = 0x1p-1070;
    assert_int_equal(geom_iso_extract(&f, b, res, NULL, &s, NULL), GEOM_OK);
    assert_clean(&s, 1);
    iso_topo r = iso_topology(s.n_vertices, s.xyz, s.n_triangles, s.tris);
    assert_int_equal(r.components, 1);
    assert_int_equal(r.euler, 0);
    geom_iso_surface_free(&s);
    geom_iso_surface_free(&ref);
}

/* --------------------------------------------------- non-finite values */

static double inf_outside(void *u, const double p[3])
{
    double r = iso_f_sphere(u, p);
    return r > 0.2 ? INFINITY : r;
}

static double nan_shell(void *u, const double p[3])
{
    double r = iso_f_sphere(u, p);
    return r > 0.15 ? NAN : r;
}

static double huge_values(void *u, const double p[3])
{
    /* values near +-DBL_MAX: their differences overflow */
    double r = iso_f_sphere(u, p);
    return r > 0 ? DBL_MAX : (r < -0.3 ? -DBL_MAX : r);
}

static void test_nonfinite(void **state)
{
    (void)state;
    geom_iso_field f;
    memset(&f, 0, sizeof f);
    double b[6] = {-1.5, -1.5, -1.5, 1.5, 1.5, 1.5};
    size_t res[3] = {21, 22, 23};
    geom_iso_surface s;
    geom_iso_value_fn fns[3] = {inf_outside, nan_shell, huge_values};
    for (int q = 0; q < 3; q++) {
        f.value = fns[q];
        geom_iso_options o;
        memset(&o, 0, sizeof o);
        o.refine = 1;
        o.normals = 1;
        f.exact = 1;
        assert_int_equal(geom_iso_extract(&f, b, res, &o, &s, NULL), GEOM_OK);
        assert_clean(&s, 1);
        iso_topo r = iso_topology(s.n_vertices, s.xyz, s.n_triangles, s.tris);
        assert_int_equal(r.components, 1);
        assert_int_equal(r.euler, 2);
        for (size_t i = 0; i < 3 * s.n_vertices; i++) {
            assert_true(isfinite(s.xyz[i]));
            assert_true(isfinite(s.normals[i]));
        }
        assert_true(isfinite(iso_volume(s.xyz, s.n_triangles, s.tris)));
        if (q == 1)
            assert_true(s.report.nan_nodes > 0);
        geom_iso_surface_free(&s);
    }
}

/* ------------------------------------------------------------- ties */

static double flat_ball(void *u, const double p[3])
{
    /* zero in the whole ball, positive outside */
    double r = iso_f_sphere(u, p);
    return r > 0 ? r : 0.0;
}

static void test_flat_regions(void **state)
{
    (void)state;
    geom_iso_field f;
    memset(&f, 0, sizeof f);
    f.value = flat_ball;
    double b[6] = {-1.5, -1.5, -1.5, 1.5, 1.5, 1.5};
    size_t res[3] = {12, 12, 12}; /* nodes on the axes and planes x = 0 */
    geom_iso_surface s;
    assert_int_equal(geom_iso_extract(&f, b, res, NULL, &s, NULL), GEOM_OK);
    assert_true(s.report.iso_nodes > 100);
    assert_clean(&s, 1);
    iso_topo r = iso_topology(s.n_vertices, s.xyz, s.n_triangles, s.tris);
    assert_int_equal(r.components, 1);
    assert_int_equal(r.euler, 2);
    geom_iso_surface_free(&s);
    /* everything at the isovalue: all inside, nothing without caps, the box
     * with caps */
    double d[27];
    for (int i = 0; i < 27; i++)
        d[i] = 3.0;
    s = grid_surface(d, 3, 3, 3, 3.0, 0);
    assert_int_equal(s.n_triangles, 0);
    geom_iso_surface_free(&s);
    s = grid_surface(d, 3, 3, 3, 3.0, 1);
    assert_clean(&s, 1);
    assert_int_equal(s.n_triangles, 6 * 8);
    assert_true(fabs(iso_volume(s.xyz, s.n_triangles, s.tris) - 8.0) < 1e-14);
    geom_iso_surface_free(&s);
}

static uint64_t rng = 0x243F6A8885A308D3ull;

static uint64_t next_rand(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return rng;
}

static void test_random_ties(void **state)
{
    (void)state;
    enum { N = 9 };
    static double d[N * N * N];
    for (int round = 0; round < 40; round++) {
        int range = 1 + round % 3; /* values in [-range, range] */
        for (int i = 0; i < N * N * N; i++)
            d[i] = (double)((int)(next_rand() % (uint64_t)(2 * range + 1)) - range);
        double isos[2] = {0.0, round % 2 ? 0.5 : 1.0};
        for (int q = 0; q < 2; q++) {
            geom_iso_surface s = grid_surface(d, N, N, N, isos[q], 0);
            assert_clean(&s, 0);
            geom_iso_surface_free(&s);
            s = grid_surface(d, N, N, N, isos[q], 1);
            assert_clean(&s, 1);
            /* the caps close the inside region: a positive volume unless
             * nothing is inside */
            if (s.n_triangles)
                assert_true(iso_volume(s.xyz, s.n_triangles, s.tris) > 0);
            geom_iso_surface_free(&s);
        }
    }
}

static void test_checkerboard(void **state)
{
    (void)state;
    /* +-1 alternating at every node: every face is a saddle exactly at
     * the isovalue 0 (q = 0, decided by the perturbation), every cell the
     * PLANE_CROSS configuration */
    enum { N = 7 };
    double d[N * N * N];
    for (int k = 0; k < N; k++)
        for (int j = 0; j < N; j++)
            for (int i = 0; i < N; i++)
                d[i + N * (j + N * k)] = ((i + j + k) & 1) ? -1.0 : 1.0;
    for (int caps = 0; caps < 2; caps++) {
        geom_iso_surface s = grid_surface(d, N, N, N, 0.0, caps);
        assert_clean(&s, caps);
        assert_true(s.report.ambiguous_faces > 0);
        geom_iso_surface_free(&s);
    }
    /* saddles exactly at the isovalue with unequal values: 2 * 2 =
     * (-1) * (-4) on four faces of the cell */
    double e[8] = {2, -1, -4, 2, -1, 2, 2, -4};
    for (int caps = 0; caps < 2; caps++) {
        geom_iso_surface s = grid_surface(e, 2, 2, 2, 0.0, caps);
        assert_clean(&s, caps);
        geom_iso_surface_free(&s);
    }
}

/* ------------------------------------------------------- coordinates */

static double far_plane(void *u, const double p[3])
{
    (void)u;
    return (p[0] - 1e8) * 0.7 + (p[1] - 1e8) * 0.2 - (p[2] - 1e8) * 0.3 - 1e-7;
}

static double aniso(void *u, const double p[3])
{
    (void)u;
    double x = p[0] / 1e-3, y = p[1], z = p[2] / 1e3;
    return sqrt(x * x + y * y + z * z) - 1.0;
}

static void test_coordinates(void **state)
{
    (void)state;
    geom_iso_field f;
    memset(&f, 0, sizeof f);
    f.value = far_plane;
    f.exact = 1;
    /* cells of 1e-6 near 1e8: a few ulps wide (the ulp is 1.5e-8) */
    double b[6] = {1e8 - 1e-5, 1e8 - 1e-5, 1e8 - 1e-5, 1e8 + 1e-5, 1e8 + 1e-5, 1e8 + 1e-5};
    size_t res[3] = {20, 20, 20};
    geom_iso_options o;
    memset(&o, 0, sizeof o);
    o.refine = 1;
    geom_iso_surface s;
    assert_int_equal(geom_iso_extract(&f, b, res, &o, &s, NULL), GEOM_OK);
    assert_true(s.n_triangles > 0);
    assert_clean(&s, 0);
    geom_iso_surface_free(&s);
    /* cells 1e-3 x 1 x 1e3 around an ellipsoid */
    f.value = aniso;
    double b2[6] = {-1.3e-3, -1.3, -1.3e3, 1.31e-3, 1.29, 1.32e3};
    size_t res2[3] = {17, 19, 21};
    o.caps = 1;
    assert_int_equal(geom_iso_extract(&f, b2, res2, &o, &s, NULL), GEOM_OK);
    assert_clean(&s, 1);
    assert_int_equal(s.n_cap_triangles, 0);
    iso_topo r = iso_topology(s.n_vertices, s.xyz, s.n_triangles, s.tris);
    assert_int_equal(r.euler, 2);
    geom_iso_surface_free(&s);
    /* one cell thick, with caps: a slab through the sphere */
    f.value = iso_f_sphere;
    double b3[6] = {-1.2, -1.2, -0.1, 1.2, 1.2, 0.05};
    size_t res3[3] = {30, 25, 1};
    assert_int_equal(geom_iso_extract(&f, b3, res3, &o, &s, NULL), GEOM_OK);
    assert_clean(&s, 1);
    r = iso_topology(s.n_vertices, s.xyz, s.n_triangles, s.tris);
    assert_int_equal(r.components, 1);
    assert_int_equal(r.euler, 2);
    geom_iso_surface_free(&s);
}

/* --------------------------------------------------- bounded memory */

static double sphere08(void *u, const double p[3])
{
    (void)u;
    return sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) - 0.8;
}

static void sphere08_rows(void *u, size_t n, const double *p, double *out)
{
    for (size_t i = 0; i < n; i++)
        out[i] = sphere08(u, p + 3 * i);
}

static void test_large_grid(void **state)
{
    (void)state;
    geom_iso_field f;
    memset(&f, 0, sizeof f);
    f.value = sphere08;
    f.values = sphere08_rows;
    size_t n = ISO_SANITIZED ? 256 : 1024;
    double b[6] = {-1, -1, -1, 1, 1, 1};
    size_t res[3] = {n, n, n};
    geom_iso_options o;
    memset(&o, 0, sizeof o);
    o.error = GEOM_ISO_ERROR_NEVER;
    geom_iso_surface s;
    assert_int_equal(geom_iso_extract(&f, b, res, &o, &s, NULL), GEOM_OK);
    assert_int_equal(s.report.cells, n * n * n);
    /* a sphere of radius 0.8 in cells of 2/n: about 4 pi (0.4 n)^2 * 2
     * triangles */
    double expect = 4 * 3.14159265358979 * (0.4 * (double)n) * (0.4 * (double)n) * 2;
    assert_true((double)s.n_triangles > 0.5 * expect && (double)s.n_triangles < 2 * expect);
    struct rusage ru;
    assert_int_equal(getrusage(RUSAGE_SELF, &ru), 0);
    double peak = (double)ru.ru_maxrss * 1024.0; /* kilobytes on Linux */
    if (!ISO_SANITIZED)
        assert_true(peak < 2.0 * 1024 * 1024 * 1024);
    /* the volume enclosed converges to 4 pi 0.8^3 / 3 */
    double vol = iso_volume(s.xyz, s.n_triangles, s.tris);
    double h = 2.0 / (double)n;
    assert_true(fabs(vol - 4 * 3.14159265358979 * 0.512 / 3) < 2.2 * h * h);
    geom_iso_surface_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_scaling),       cmocka_unit_test(test_nonfinite),
        cmocka_unit_test(test_flat_regions),  cmocka_unit_test(test_random_ties),
        cmocka_unit_test(test_checkerboard),  cmocka_unit_test(test_coordinates),
        cmocka_unit_test(test_large_grid),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
