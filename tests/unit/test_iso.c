/*
 * Tests of the iso module: the sampled-grid field against closed forms,
 * argument checks, and marching cubes of fields with known answers (unit
 * sphere: radius, enclosed volume 4 pi / 3, normals p / |p|; spherical caps
 * closed against the box: hemisphere, quarter and eighth of the ball with
 * volumes 2 pi / 3, pi / 3, pi / 6; planes through grid nodes; NaN
 * regions), the error measure on an octahedron (closed forms), determinism
 * across thread counts and slab sizes, the batch callback, the half-edge
 * mesh conversion and a counting allocator.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <stdatomic.h>
#include <string.h>

#include "geom/iso.h"
#include "geom/mesh.h"
#include "unit/test_iso_util.h"

#define PI 3.14159265358979323846

static geom_iso_field field_of(geom_iso_value_fn f, geom_iso_gradient_fn g, int exact)
{
    geom_iso_field fl;
    memset(&fl, 0, sizeof fl);
    fl.value = f;
    fl.gradient = g;
    fl.exact = exact;
    return fl;
}

static void assert_clean_closed(const geom_iso_surface *s, long components, long euler)
{
    iso_topo r = iso_topology(s->n_vertices, s->xyz, s->n_triangles, s->tris);
    assert_true(iso_topo_clean(&r));
    assert_int_equal(r.boundary_edges, 0);
    assert_int_equal(r.components, components);
    assert_int_equal(r.euler, euler);
}

/* ------------------------------------------------------------ grid helper */

static double lin(double x, double y, double z)
{
    return 2 * x - 3 * y + 0.5 * z + 1;
}

static void test_grid_linear(void **state)
{
    (void)state;
    enum { NX = 4, NY = 5, NZ = 6 };
    double data[NX * NY * NZ];
    geom_iso_grid g;
    memset(&g, 0, sizeof g);
    g.dims[0] = NX, g.dims[1] = NY, g.dims[2] = NZ;
    g.type = GEOM_ISO_SCALAR_F64;
    g.data = data;
    g.spacing[0] = 0.5, g.spacing[1] = 0.25, g.spacing[2] = 2;
    g.origin[0] = 1, g.origin[1] = -2, g.origin[2] = 3;
    for (int k = 0; k < NZ; k++)
        for (int j = 0; j < NY; j++)
            for (int i = 0; i < NX; i++)
                data[i + NX * (j + NY * k)] = lin(1 + 0.5 * i, -2 + 0.25 * j, 3 + 2.0 * k);
    assert_int_equal(geom_iso_grid_check(&g), GEOM_OK);
    /* exact at samples (positions exactly representable here) */
    for (int k = 0; k < NZ; k++)
        for (int j = 0; j < NY; j++)
            for (int i = 0; i < NX; i++) {
                double p[3] = {1 + 0.5 * i, -2 + 0.25 * j, 3 + 2.0 * k};
                assert_true(geom_iso_grid_value(&g, p) == data[i + NX * (j + NY * k)]);
            }
    /* trilinear interpolation reproduces a linear function; the gradient
     * (central and one-sided differences) is exact for it */
    for (int q = 0; q < 50; q++) {
        double p[3] = {1 + 1.5 * (q % 7) / 6.0, -2 + 1.0 * (q % 5) / 4.3, 3 + 10.0 * (q % 11) / 10.7};
        assert_true(fabs(geom_iso_grid_value(&g, p) - lin(p[0], p[1], p[2])) < 1e-13);
        double gr[3];
        geom_iso_grid_gradient(&g, p, gr);
        assert_true(fabs(gr[0] - 2) < 1e-12);
        assert_true(fabs(gr[1] + 3) < 1e-12);
        assert_true(fabs(gr[2] - 0.5) < 1e-12);
    }
    /* outside: clamped onto the box */
    double out[3] = {-5, 100, 3.5}, cl[3] = {1, -2 + 0.25 * (NY - 1), 3.5};
    assert_true(geom_iso_grid_value(&g, out) == geom_iso_grid_value(&g, cl));
    double nanp[3] = {NAN, 0, 0};
    assert_true(isnan(geom_iso_grid_value(&g, nanp)));
    /* the field adapter */
    geom_iso_field f;
    assert_int_equal(geom_iso_field_from_grid(&g, &f), GEOM_OK);
    double p[3] = {1.7, -1.3, 7.1};
    assert_true(f.value(f.user, p) == geom_iso_grid_value(&g, p));
    assert_int_equal(f.exact, 0);
}

static void test_grid_trilinear_f32(void **state)
{
    (void)state;
    /* x y z is trilinear, so the interpolant reproduces it; float samples
     * of small integers are exact */
    float data[27];
    geom_iso_grid g;
    memset(&g, 0, sizeof g);
    g.dims[0] = g.dims[1] = g.dims[2] = 3;
    g.type = GEOM_ISO_SCALAR_F32;
    g.data = data;
    for (int k = 0; k < 3; k++)
        for (int j = 0; j < 3; j++)
            for (int i = 0; i < 3; i++)
                data[i + 3 * (j + 3 * k)] = (float)(i * j * k);
    for (int q = 0; q < 40; q++) {
        double p[3] = {0.05 * q, 2.0 - 0.037 * q, 0.3 + 0.041 * q};
        assert_true(fabs(geom_iso_grid_value(&g, p) - p[0] * p[1] * p[2]) < 1e-12);
    }
    /* central differences at the middle sample are exact for x y z */
    double mid[3] = {1, 1, 1}, gr[3];
    geom_iso_grid_gradient(&g, mid, gr);
    assert_true(fabs(gr[0] - 1) < 1e-12 && fabs(gr[1] - 1) < 1e-12 && fabs(gr[2] - 1) < 1e-12);
}

static void test_grid_check(void **state)
{
    (void)state;
    double d[8] = {0};
    geom_iso_grid g;
    memset(&g, 0, sizeof g);
    g.dims[0] = g.dims[1] = g.dims[2] = 2;
    g.type = GEOM_ISO_SCALAR_F64;
    g.data = d;
    assert_int_equal(geom_iso_grid_check(&g), GEOM_OK);
    assert_int_equal(geom_iso_grid_check(NULL), GEOM_ERR_INVALID_ARG);
    g.dims[1] = 0;
    assert_int_equal(geom_iso_grid_check(&g), GEOM_ERR_INVALID_ARG);
    g.dims[1] = 2;
    g.type = (geom_iso_scalar)7;
    assert_int_equal(geom_iso_grid_check(&g), GEOM_ERR_INVALID_ARG);
    g.type = GEOM_ISO_SCALAR_F64;
    g.spacing[2] = -1;
    assert_int_equal(geom_iso_grid_check(&g), GEOM_ERR_INVALID_ARG);
    g.spacing[2] = 0;
    g.origin[0] = INFINITY;
    assert_int_equal(geom_iso_grid_check(&g), GEOM_ERR_INVALID_ARG);
    g.origin[0] = 0;
    g.data = NULL;
    assert_int_equal(geom_iso_grid_check(&g), GEOM_ERR_INVALID_ARG);
    g.data = d;
    g.dims[0] = g.dims[1] = g.dims[2] = SIZE_MAX / 2;
    assert_int_equal(geom_iso_grid_check(&g), GEOM_ERR_LIMIT);
}

/* ------------------------------------------------------------- arguments */

static void test_arguments(void **state)
{
    (void)state;
    geom_iso_field f = field_of(iso_f_sphere, NULL, 1);
    double b[6] = {-1.5, -1.5, -1.5, 1.5, 1.5, 1.5};
    size_t res[3] = {4, 4, 4};
    geom_iso_surface s;
    geom_diag d;
    memset(&d, 0, sizeof d);
    assert_int_equal(geom_iso_extract(NULL, b, res, NULL, &s, &d), GEOM_ERR_INVALID_ARG);
    assert_true(s.xyz == NULL && s.n_vertices == 0);
    assert_int_equal(d.status, GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_iso_extract(&f, NULL, res, NULL, &s, NULL), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_iso_extract(&f, b, NULL, NULL, &s, NULL), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_iso_extract(&f, b, res, NULL, NULL, NULL), GEOM_ERR_INVALID_ARG);
    double bad[6] = {1, -1.5, -1.5, -1, 1.5, 1.5};
    assert_int_equal(geom_iso_extract(&f, bad, res, NULL, &s, NULL), GEOM_ERR_INVALID_ARG);
    double nanb[6] = {NAN, -1.5, -1.5, 1, 1.5, 1.5};
    assert_int_equal(geom_iso_extract(&f, nanb, res, NULL, &s, NULL), GEOM_ERR_INVALID_ARG);
    size_t zero[3] = {4, 0, 4};
    assert_int_equal(geom_iso_extract(&f, b, zero, NULL, &s, NULL), GEOM_ERR_INVALID_ARG);
    geom_iso_options o;
    memset(&o, 0, sizeof o);
    o.iso = NAN;
    assert_int_equal(geom_iso_extract(&f, b, res, &o, &s, NULL), GEOM_ERR_INVALID_ARG);
    geom_iso_field nf = field_of(NULL, NULL, 0);
    assert_int_equal(geom_iso_extract(&nf, b, res, NULL, &s, NULL), GEOM_ERR_INVALID_ARG);
    /* freeing a zeroed surface is a no-op */
    geom_iso_surface_free(&s);
    geom_iso_surface_free(NULL);
    /* an empty surface (the sphere outside the box) is fine */
    double far[6] = {5, 5, 5, 6, 6, 6};
    assert_int_equal(geom_iso_extract(&f, far, res, NULL, &s, NULL), GEOM_OK);
    assert_int_equal(s.n_vertices, 0);
    assert_int_equal(s.n_triangles, 0);
    assert_int_equal(s.report.cells, 64);
    geom_iso_surface_free(&s);
}

/* ---------------------------------------------------------------- sphere */

static void test_sphere(void **state)
{
    (void)state;
    geom_iso_field f = field_of(iso_f_sphere, iso_g_sphere, 1);
    double b[6] = {-1.31, -1.27, -1.4, 1.33, 1.29, 1.22};
    size_t res[3] = {26, 25, 27};
    double h = 2.7 / 25;
    geom_iso_options o;
    memset(&o, 0, sizeof o);
    o.normals = 1;
    geom_iso_surface s;
    assert_int_equal(geom_iso_extract(&f, b, res, &o, &s, NULL), GEOM_OK);
    assert_clean_closed(&s, 1, 2);
    assert_int_equal(s.n_cap_triangles, 0);
    /* vertices: linear interpolation of the distance |p| - 1 along an edge
     * is off by at most (chord sagitta) h^2 / 2 */
    for (size_t v = 0; v < s.n_vertices; v++) {
        double r = sqrt(s.xyz[3 * v] * s.xyz[3 * v] + s.xyz[3 * v + 1] * s.xyz[3 * v + 1] +
                        s.xyz[3 * v + 2] * s.xyz[3 * v + 2]);
        assert_true(fabs(r - 1) <= 0.5 * h * h);
        /* normals from the exact gradient: p / |p| */
        for (int k = 0; k < 3; k++)
            assert_true(fabs(s.normals[3 * v + k] - s.xyz[3 * v + k] / r) < 1e-12);
    }
    /* counter-clockwise from outside: positive enclosed volume, within
     * O(h^2) of 4 pi / 3 */
    double vol = iso_volume(s.xyz, s.n_triangles, s.tris);
    assert_true(fabs(vol - 4 * PI / 3) < 4 * PI / 3 * h * h);
    assert_true(vol < 4 * PI / 3); /* a polyhedron inscribed in a convex body */
    assert_int_equal(s.report.vertex_error.method, GEOM_ERROR_SAMPLED);
    assert_true(s.report.vertex_error.max_error <= 0.5 * h * h);
    assert_true(s.report.sample_error.max_error > s.report.vertex_error.max_error);
    assert_true(s.report.sample_error.max_error < h * h);
    assert_true(s.report.active_cells > 0 && s.report.cells == 26 * 25 * 27);
    assert_true(s.report.seconds >= 0);
    geom_iso_surface_free(&s);

    /* refined: vertices are roots of f to rounding */
    o.refine = 1;
    assert_int_equal(geom_iso_extract(&f, b, res, &o, &s, NULL), GEOM_OK);
    assert_clean_closed(&s, 1, 2);
    assert_true(s.report.refined > 0);
    for (size_t v = 0; v < s.n_vertices; v++) {
        double r = sqrt(s.xyz[3 * v] * s.xyz[3 * v] + s.xyz[3 * v + 1] * s.xyz[3 * v + 1] +
                        s.xyz[3 * v + 2] * s.xyz[3 * v + 2]);
        assert_true(fabs(r - 1) < 1e-14);
    }
    assert_true(s.report.vertex_error.max_error < 1e-14);
    /* triangle samples of a polyhedron inscribed in the unit sphere: the
     * deepest is a centroid, at most the sagitta of an edge of length
     * <= sqrt(3) h */
    assert_true(s.report.sample_error.max_error < 3 * h * h / 8 + 1e-12);
    geom_iso_surface_free(&s);
}

/* The same surface whatever the thread count and slab size. */
static void test_determinism(void **state)
{
    (void)state;
    geom_iso_field f = field_of(iso_f_gyroid, NULL, 1);
    double b[6] = {-3.1, -2.9, -3.3, 3.2, 3.0, 2.8};
    size_t res[3] = {23, 21, 37};
    geom_iso_options o;
    memset(&o, 0, sizeof o);
    o.normals = 1;
    o.caps = 1;
    o.refine = 1;
    o.threads = 1;
    o.slab_layers = 0;
    geom_iso_surface ref;
    assert_int_equal(geom_iso_extract(&f, b, res, &o, &ref, NULL), GEOM_OK);
    assert_true(ref.n_triangles > 1000);
    iso_topo r = iso_topology(ref.n_vertices, ref.xyz, ref.n_triangles, ref.tris);
    assert_true(iso_topo_clean(&r));
    assert_int_equal(r.boundary_edges, 0);
    const int threads[] = {2, 3, 1, 0};
    const size_t layers[] = {1, 3, 37, 100};
    for (int q = 0; q < 4; q++) {
        o.threads = threads[q];
        o.slab_layers = layers[q];
        geom_iso_surface s;
        assert_int_equal(geom_iso_extract(&f, b, res, &o, &s, NULL), GEOM_OK);
        assert_int_equal(s.n_vertices, ref.n_vertices);
        assert_int_equal(s.n_triangles, ref.n_triangles);
        assert_int_equal(s.n_cap_triangles, ref.n_cap_triangles);
        assert_memory_equal(s.xyz, ref.xyz, 3 * ref.n_vertices * sizeof(double));
        assert_memory_equal(s.normals, ref.normals, 3 * ref.n_vertices * sizeof(double));
        assert_memory_equal(s.tris, ref.tris, 3 * ref.n_triangles * sizeof(uint32_t));
        assert_true(s.report.vertex_error.max_error == ref.report.vertex_error.max_error);
        assert_true(s.report.sample_error.mean_error == ref.report.sample_error.mean_error);
        geom_iso_surface_free(&s);
    }
    geom_iso_surface_free(&ref);
}

/* ------------------------------------------------------------------ caps */

static void cap_case(const double b[6], double volume, long euler)
{
    geom_iso_field f = field_of(iso_f_sphere, iso_g_sphere, 1);
    size_t res[3] = {40, 41, 39};
    double h = 0;
    for (int a = 0; a < 3; a++)
        h = fmax(h, (b[a + 3] - b[a]) / (double)res[a]);
    geom_iso_options o;
    memset(&o, 0, sizeof o);
    o.caps = 1;
    o.refine = 1;
    geom_iso_surface s;
    assert_int_equal(geom_iso_extract(&f, b, res, &o, &s, NULL), GEOM_OK);
    assert_clean_closed(&s, 1, euler);
    assert_true(s.n_cap_triangles > 0);
    /* cap triangles lie on the box faces */
    for (size_t t = s.n_triangles - s.n_cap_triangles; t < s.n_triangles; t++) {
        int on = 0;
        for (int a = 0; a < 3 && !on; a++)
            for (int side = 0; side < 2 && !on; side++) {
                double c = b[a + 3 * side];
                on = s.xyz[3 * s.tris[3 * t] + a] == c && s.xyz[3 * s.tris[3 * t + 1] + a] == c &&
                     s.xyz[3 * s.tris[3 * t + 2] + a] == c;
            }
        assert_true(on);
    }
    double vol = iso_volume(s.xyz, s.n_triangles, s.tris);
    assert_true(fabs(vol - volume) < volume * 2 * h * h);
    geom_iso_surface_free(&s);
}

static void test_caps(void **state)
{
    (void)state;
    /* half, quarter and eighth of the unit ball: the box faces through the
     * centre cut it; box edges and a box corner lie inside */
    const double half[6] = {0, -1.2, -1.3, 1.25, 1.3, 1.2};
    cap_case(half, 2 * PI / 3, 2);
    const double quarter[6] = {0, 0, -1.3, 1.25, 1.3, 1.2};
    cap_case(quarter, PI / 3, 2);
    const double eighth[6] = {0, 0, 0, 1.25, 1.3, 1.2};
    cap_case(eighth, PI / 6, 2);
    /* the whole box inside: the caps are the box (6 faces, volume 1) */
    geom_iso_field f = field_of(iso_f_sphere, NULL, 1);
    double b[6] = {-0.5, -0.5, -0.5, 0.5, 0.5, 0.5};
    size_t res[3] = {3, 4, 5};
    geom_iso_options o;
    memset(&o, 0, sizeof o);
    o.caps = 1;
    geom_iso_surface s;
    assert_int_equal(geom_iso_extract(&f, b, res, &o, &s, NULL), GEOM_OK);
    assert_clean_closed(&s, 1, 2);
    assert_int_equal(s.n_cap_triangles, s.n_triangles);
    assert_int_equal(s.n_triangles, 2 * 2 * (3 * 4 + 4 * 5 + 3 * 5));
    assert_true(fabs(iso_volume(s.xyz, s.n_triangles, s.tris) - 1.0) < 1e-14);
    assert_int_equal(s.report.vertex_error.method, GEOM_ERROR_SAMPLED);
    geom_iso_surface_free(&s);
}

/* ------------------------------------------------- values equal to iso */

static double plane_x(void *u, const double p[3])
{
    (void)u;
    return p[0] - 0.5;
}

static double abs_plane(void *u, const double p[3])
{
    (void)u;
    return fabs(p[0] - 0.5);
}

static double sq_sphere(void *u, const double p[3])
{
    (void)u;
    return p[0] * p[0] + p[1] * p[1] + p[2] * p[2] - 1.0;
}

static void test_iso_on_nodes(void **state)
{
    (void)state;
    double b[6] = {0, 0, 0, 1, 1, 1};
    size_t res[3] = {4, 4, 4};
    geom_iso_options o;
    memset(&o, 0, sizeof o);
    geom_iso_surface s;
    /* a plane through a layer of nodes (x = 0.5): those nodes are inside,
     * the surface passes just above them */
    geom_iso_field f = field_of(plane_x, NULL, 1);
    assert_int_equal(geom_iso_extract(&f, b, res, &o, &s, NULL), GEOM_OK);
    assert_int_equal(s.report.iso_nodes, 25);
    iso_topo r = iso_topology(s.n_vertices, s.xyz, s.n_triangles, s.tris);
    assert_true(iso_topo_clean(&r));
    assert_int_equal(r.components, 1);
    assert_int_equal(r.boundary_loops, 1);
    assert_int_equal(r.euler, 1);
    assert_int_equal(s.n_vertices, 25);
    assert_int_equal(s.n_triangles, 32);
    for (size_t v = 0; v < s.n_vertices; v++) {
        assert_true(s.xyz[3 * v] > 0.5);
        assert_true(s.xyz[3 * v] < 0.5 + 1e-6);
    }
    geom_iso_surface_free(&s);
    /* with caps: a closed box of volume 1/2 (up to the offset) */
    o.caps = 1;
    assert_int_equal(geom_iso_extract(&f, b, res, &o, &s, NULL), GEOM_OK);
    assert_clean_closed(&s, 1, 2);
    assert_true(fabs(iso_volume(s.xyz, s.n_triangles, s.tris) - 0.5) < 1e-6);
    geom_iso_surface_free(&s);
    /* |x - 0.5| = 0: the zero set is a sheet the field touches from
     * above; extracted at iso + eps it is a thin closed slab around it */
    f = field_of(abs_plane, NULL, 1);
    assert_int_equal(geom_iso_extract(&f, b, res, &o, &s, NULL), GEOM_OK);
    assert_clean_closed(&s, 1, 2);
    double vol = iso_volume(s.xyz, s.n_triangles, s.tris);
    assert_true(vol > 0 && vol < 1e-6);
    geom_iso_surface_free(&s);
    /* |p|^2 - 1 on a grid with nodes on the sphere (0, 0, +-1), (+-1, 0, 0),
     * ... and a point-contact with the box at the corners of the octants */
    f = field_of(sq_sphere, NULL, 1);
    double b2[6] = {-1, -1, -1, 1, 1, 1};
    size_t res2[3] = {8, 8, 8};
    o.caps = 0;
    assert_int_equal(geom_iso_extract(&f, b2, res2, &o, &s, NULL), GEOM_OK);
    assert_true(s.report.iso_nodes >= 6);
    r = iso_topology(s.n_vertices, s.xyz, s.n_triangles, s.tris);
    assert_true(iso_topo_clean(&r));
    geom_iso_surface_free(&s);
    o.caps = 1;
    assert_int_equal(geom_iso_extract(&f, b2, res2, &o, &s, NULL), GEOM_OK);
    assert_clean_closed(&s, 1, 2);
    geom_iso_surface_free(&s);
}

/* ------------------------------------------------------------------- NaN */

static double holed(void *u, const double p[3])
{
    (void)u;
    double r = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    return r < 0.4 ? NAN : r - 1.0;
}

static void test_nan(void **state)
{
    (void)state;
    geom_iso_field f = field_of(holed, NULL, 0);
    double b[6] = {-1.3, -1.3, -1.3, 1.3, 1.3, 1.3};
    size_t res[3] = {20, 20, 20};
    geom_iso_surface s;
    assert_int_equal(geom_iso_extract(&f, b, res, NULL, &s, NULL), GEOM_OK);
    assert_true(s.report.nan_nodes > 0);
    /* NaN counts as outside: the inside is a spherical shell, bounded by two
     * spheres */
    assert_clean_closed(&s, 2, 4);
    assert_int_equal(s.report.vertex_error.method, GEOM_ERROR_NONE); /* not exact */
    for (size_t i = 0; i < 3 * s.n_vertices; i++)
        assert_true(isfinite(s.xyz[i]));
    geom_iso_surface_free(&s);
}

/* ---------------------------------------------------------- error measure */

static void test_measure_error(void **state)
{
    (void)state;
    /* the octahedron with vertices on the unit sphere: vertices exact; the
     * face centroids at radius 1/sqrt(3), edge midpoints at 1/sqrt(2), and
     * |grad| = 1 */
    const double xyz[18] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
    const uint32_t tris[24] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4,
                               2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
    geom_iso_field f = field_of(iso_f_sphere, iso_g_sphere, 1);
    geom_error_report ve, se;
    size_t un = 99;
    assert_int_equal(geom_iso_measure_error(&f, 0.0, 6, xyz, 8, tris, &ve, &se, &un), GEOM_OK);
    assert_true(ve.max_error == 0 && ve.mean_error == 0);
    double c = 1 - 1 / sqrt(3.0), m = 1 - 1 / sqrt(2.0);
    assert_true(fabs(se.max_error - c) < 1e-15);
    assert_true(fabs(se.mean_error - (c + 3 * m) / 4) < 1e-15);
    assert_int_equal(un, 0);
    assert_int_equal(se.method, GEOM_ERROR_SAMPLED);
    /* without a gradient callback: central differences, still accurate */
    f.gradient = NULL;
    assert_int_equal(geom_iso_measure_error(&f, 0.0, 6, xyz, 8, tris, &ve, &se, NULL), GEOM_OK);
    assert_true(fabs(se.max_error - c) < 1e-8);
    /* isovalue -0.5 (the sphere of radius 1/2): vertices off by 1/2 */
    f.gradient = iso_g_sphere;
    assert_int_equal(geom_iso_measure_error(&f, -0.5, 6, xyz, 0, tris, &ve, NULL, NULL), GEOM_OK);
    assert_true(fabs(ve.max_error - 0.5) < 1e-15);
    const uint32_t bad[3] = {0, 1, 6};
    assert_int_equal(geom_iso_measure_error(&f, 0.0, 6, xyz, 1, bad, &ve, &se, NULL),
                     GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_iso_measure_error(NULL, 0.0, 6, xyz, 8, tris, &ve, &se, NULL),
                     GEOM_ERR_INVALID_ARG);
}

/* ------------------------------------------------------- batch callback */

static size_t batch_calls;

static void torus_batch(void *u, size_t n, const double *p, double *out)
{
    (void)u;
    batch_calls++;
    for (size_t i = 0; i < n; i++)
        out[i] = iso_f_torus(NULL, p + 3 * i);
}

static void test_batch(void **state)
{
    (void)state;
    geom_iso_field f = field_of(iso_f_torus, NULL, 1);
    double b[6] = {-1.5, -1.5, -0.5, 1.5, 1.5, 0.5};
    size_t res[3] = {30, 30, 10};
    geom_iso_surface s1, s2;
    assert_int_equal(geom_iso_extract(&f, b, res, NULL, &s1, NULL), GEOM_OK);
    f.values = torus_batch;
    batch_calls = 0;
    assert_int_equal(geom_iso_extract(&f, b, res, NULL, &s2, NULL), GEOM_OK);
    assert_true(batch_calls >= 31 * 11); /* one call per row */
    assert_int_equal(s1.n_vertices, s2.n_vertices);
    assert_int_equal(s1.n_triangles, s2.n_triangles);
    assert_memory_equal(s1.xyz, s2.xyz, 3 * s1.n_vertices * sizeof(double));
    assert_memory_equal(s1.tris, s2.tris, 3 * s1.n_triangles * sizeof(uint32_t));
    assert_clean_closed(&s2, 1, 0); /* a torus: genus 1 */
    geom_iso_surface_free(&s1);
    geom_iso_surface_free(&s2);
}

/* ------------------------------------- sampled grid = field on its nodes */

static void test_grid_extraction(void **state)
{
    (void)state;
    /* torus samples on nodes whose coordinates are exact in both paths
     * (origin -1.5, spacing 0.125): extracting the samples and extracting
     * the field on the same nodes give the same surface */
    enum { N = 25, NZ = 9 };
    static double data[N * N * NZ];
    for (int k = 0; k < NZ; k++)
        for (int j = 0; j < N; j++)
            for (int i = 0; i < N; i++) {
                double p[3] = {-1.5 + 0.125 * i, -1.5 + 0.125 * j, -0.5 + 0.125 * k};
                data[i + N * (j + N * k)] = iso_f_torus(NULL, p);
            }
    geom_iso_grid g;
    memset(&g, 0, sizeof g);
    g.dims[0] = g.dims[1] = N;
    g.dims[2] = NZ;
    g.type = GEOM_ISO_SCALAR_F64;
    g.data = data;
    g.spacing[0] = g.spacing[1] = g.spacing[2] = 0.125;
    g.origin[0] = g.origin[1] = -1.5;
    g.origin[2] = -0.5;
    geom_iso_options o;
    memset(&o, 0, sizeof o);
    o.normals = 1;
    /* linear interpolation on both sides (the field is exact: the default,
     * GEOM_IMPLICIT_REFINE_AUTO, would refine its vertices) */
    o.refine = GEOM_IMPLICIT_REFINE_NEVER;
    geom_iso_surface sg, sf;
    assert_int_equal(geom_iso_extract_grid(&g, &o, &sg, NULL), GEOM_OK);
    geom_iso_field f = field_of(iso_f_torus, NULL, 1);
    double b[6] = {-1.5, -1.5, -0.5, 1.5, 1.5, 0.5};
    size_t res[3] = {N - 1, N - 1, NZ - 1};
    assert_int_equal(geom_iso_extract(&f, b, res, &o, &sf, NULL), GEOM_OK);
    assert_int_equal(sg.n_vertices, sf.n_vertices);
    assert_int_equal(sg.n_triangles, sf.n_triangles);
    assert_memory_equal(sg.xyz, sf.xyz, 3 * sg.n_vertices * sizeof(double));
    assert_memory_equal(sg.tris, sf.tris, 3 * sg.n_triangles * sizeof(uint32_t));
    assert_clean_closed(&sg, 1, 0);
    /* grid normals (interpolated central differences) agree with the exact
     * gradient's direction to O(h) */
    for (size_t v = 0; v < sg.n_vertices; v++) {
        double d = 0;
        for (int k = 0; k < 3; k++)
            d += sg.normals[3 * v + k] * sf.normals[3 * v + k];
        assert_true(d > 0.9);
    }
    assert_int_equal(sg.report.vertex_error.method, GEOM_ERROR_NONE);
    geom_iso_surface_free(&sg);
    geom_iso_surface_free(&sf);
    /* a grid with a single layer gives nothing */
    g.dims[2] = 1;
    assert_int_equal(geom_iso_extract_grid(&g, &o, &sg, NULL), GEOM_OK);
    assert_int_equal(sg.n_triangles, 0);
    geom_iso_surface_free(&sg);
}

/* ------------------------------------------------------ mesh conversion */

static void test_to_mesh(void **state)
{
    (void)state;
    geom_iso_field f = field_of(iso_f_torus, NULL, 1);
    double b[6] = {-1.5, -1.5, -0.5, 1.5, 1.5, 0.5};
    size_t res[3] = {24, 24, 8};
    geom_iso_options o;
    memset(&o, 0, sizeof o);
    o.normals = 1;
    geom_iso_surface s;
    assert_int_equal(geom_iso_extract(&f, b, res, &o, &s, NULL), GEOM_OK);
    geom_mesh *m = geom_mesh_create(NULL);
    assert_non_null(m);
    assert_int_equal(geom_iso_surface_to_mesh(&s, m, NULL), GEOM_OK);
    geom_mesh_topology t;
    assert_int_equal(geom_mesh_topology_summary(m, &t), GEOM_OK);
    assert_true(t.closed && t.manifold);
    assert_int_equal(t.genus, 1);
    assert_int_equal(t.faces, (long)s.n_triangles);
    uint32_t id = geom_mesh_channel_find(m, "normal", GEOM_MESH_DOMAIN_VERTEX);
    assert_true(id != GEOM_INVALID_INDEX);
    const double *n = geom_mesh_channel_cdata(m, id);
    assert_memory_equal(n, s.normals, 3 * s.n_vertices * sizeof(double));
    assert_memory_equal(geom_mesh_cpositions(m), s.xyz, 3 * s.n_vertices * sizeof(double));
    geom_mesh_destroy(m);
    geom_iso_surface_free(&s);
}

/* ------------------------------------------------------------ allocator */

/* Called from every extraction thread: atomic counters. */
typedef struct counting {
    _Atomic size_t live, bytes, calls;
} counting;

static void *c_alloc(void *u, size_t n)
{
    counting *c = u;
    c->live++;
    c->bytes += n;
    c->calls++;
    return malloc(n);
}

static void c_free(void *u, void *p, size_t n)
{
    counting *c = u;
    c->live--;
    c->bytes -= n;
    free(p);
}

static void test_allocator(void **state)
{
    (void)state;
    counting cnt;
    atomic_init(&cnt.live, 0);
    atomic_init(&cnt.bytes, 0);
    atomic_init(&cnt.calls, 0);
    geom_allocator a = {c_alloc, NULL, c_free, &cnt};
    geom_iso_field f = field_of(iso_f_gyroid, iso_g_gyroid, 1);
    double b[6] = {-2, -2, -2, 2, 2, 2};
    size_t res[3] = {17, 19, 18};
    geom_iso_options o;
    memset(&o, 0, sizeof o);
    o.alloc = &a;
    o.caps = 1;
    o.normals = 1;
    o.slab_layers = 4;
    o.threads = 3;
    geom_iso_surface s;
    assert_int_equal(geom_iso_extract(&f, b, res, &o, &s, NULL), GEOM_OK);
    assert_true(cnt.calls > 0);
    assert_int_equal(cnt.live, 3); /* xyz, normals, tris */
    iso_topo r = iso_topology(s.n_vertices, s.xyz, s.n_triangles, s.tris);
    assert_true(iso_topo_clean(&r));
    assert_int_equal(r.boundary_edges, 0);
    geom_iso_surface_free(&s);
    assert_int_equal(cnt.live, 0);
    assert_int_equal(cnt.bytes, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_grid_linear),
        cmocka_unit_test(test_grid_trilinear_f32),
        cmocka_unit_test(test_grid_check),
        cmocka_unit_test(test_arguments),
        cmocka_unit_test(test_sphere),
        cmocka_unit_test(test_determinism),
        cmocka_unit_test(test_caps),
        cmocka_unit_test(test_iso_on_nodes),
        cmocka_unit_test(test_nan),
        cmocka_unit_test(test_measure_error),
        cmocka_unit_test(test_batch),
        cmocka_unit_test(test_grid_extraction),
        cmocka_unit_test(test_to_mesh),
        cmocka_unit_test(test_allocator),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
