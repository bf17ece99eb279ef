/* Mesh core on extreme input: huge (1e150, 1e200) and tiny (1e-150)
 * coordinates, large offsets (1e8), degenerate faces, nearly collinear
 * polygons, and non-finite coordinates (rejected). References are exact
 * (orient2d signs, integer topology) or closed-form areas scaled exactly by
 * powers of the scale factor. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "geom/mesh.h"
#include "bench/triangulate_shapes.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define INV GEOM_INVALID_INDEX

static void assert_valid(const geom_mesh *m)
{
    size_t n = 99;
    assert_int_equal(geom_mesh_validate(m, NULL, 0, &n), GEOM_OK);
    assert_int_equal(n, 0);
}

/* n x n quad grid scaled by s and shifted by o (in x and y). */
static geom_mesh *grid(int n, double s, double o)
{
    size_t nv = (size_t)n * n, nf = (size_t)(n - 1) * (n - 1);
    double *xyz = malloc(3 * nv * sizeof(double));
    uint32_t *sz = malloc(nf * sizeof(uint32_t)), *ix = malloc(4 * nf * sizeof(uint32_t));
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            xyz[3 * (j * n + i)] = o + s * i;
            xyz[3 * (j * n + i) + 1] = o + s * j;
            xyz[3 * (j * n + i) + 2] = s * ((i * j) % 3); /* non-planar quads */
        }
    size_t f = 0;
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i, ++f) {
            uint32_t a = (uint32_t)(j * n + i);
            sz[f] = 4;
            ix[4 * f] = a;
            ix[4 * f + 1] = a + 1;
            ix[4 * f + 2] = a + 1 + (uint32_t)n;
            ix[4 * f + 3] = a + (uint32_t)n;
        }
    geom_mesh *m = geom_mesh_create(NULL);
    geom_mesh_build_report r;
    assert_int_equal(geom_mesh_build(m, nv, xyz, nf, sz, ix, NULL, &r, NULL), GEOM_OK);
    assert_int_equal(r.flipped_faces + r.added_vertices + r.nonmanifold_edges, 0);
    free(xyz);
    free(sz);
    free(ix);
    return m;
}

static void check_grid(geom_mesh *m, int n, double s, double o)
{
    assert_valid(m);
    geom_mesh_topology t;
    assert_int_equal(geom_mesh_topology_summary(m, &t), GEOM_OK);
    assert_int_equal(t.euler, 1);
    assert_int_equal(t.degenerate_faces, 0);
    assert_true(t.manifold);
    geom_aabb b = geom_mesh_bbox(m);
    assert_true(b.min.x == o && b.min.y == o && b.max.x == o + s * (n - 1));
    assert_true(b.max.z == 2 * s);
    size_t added;
    assert_int_equal(geom_mesh_triangulate(m, &added), GEOM_OK);
    assert_int_equal(added, (size_t)(n - 1) * (n - 1));
    assert_valid(m);
    assert_int_equal(geom_mesh_topology_summary(m, &t), GEOM_OK);
    assert_int_equal(t.euler, 1);
    assert_int_equal(t.degenerate_faces, 0);
}

static void test_huge_tiny_offset_grids(void **state)
{
    (void)state;
    double scales[5] = {1e150, 1e200, 1e-150, 1.0, 1e-3};
    double offsets[5] = {0, 0, 0, 1e8, 1e8};
    for (int k = 0; k < 5; ++k) {
        geom_mesh *m = grid(12, scales[k], offsets[k]);
        check_grid(m, 12, scales[k], offsets[k]);
        geom_mesh_destroy(m);
    }
}

/* The comb of K teeth: 4K vertices (tests/bench/triangulate_shapes.h). */
static size_t comb(int K, double *xy)
{
    return ts_comb(4 * (size_t)K, xy, 0);
}

/* Triangulate the comb scaled by s (a power of two or ten) and shifted by o,
 * in the plane z = zc. Orientation is checked exactly on the input
 * coordinates; the area on the unshifted comb, where it is 4K - 1. */
static void comb_case(int K, double s, double o, double zc)
{
    double xy[2 * 100] = {0}, sh[2 * 100] = {0}, p[3 * 100] = {0};
    uint32_t t[3 * 100];
    size_t n = comb(K, xy);
    for (size_t i = 0; i < n; ++i) {
        sh[2 * i] = o + s * xy[2 * i];
        sh[2 * i + 1] = o + s * xy[2 * i + 1];
        p[3 * i] = sh[2 * i];
        p[3 * i + 1] = sh[2 * i + 1];
        p[3 * i + 2] = zc;
    }
    assert_int_equal(geom_polygon_triangulate(n, p, t), GEOM_OK);
    double area = 0;
    for (size_t k = 0; k + 2 < n; ++k) {
        const uint32_t *v = t + 3 * k;
        assert_true(geom_orient2d(sh + 2 * v[0], sh + 2 * v[1], sh + 2 * v[2]) > 0);
        const double *a = xy + 2 * v[0], *b = xy + 2 * v[1], *c = xy + 2 * v[2];
        area += 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
    }
    assert_true(area == 4.0 * K - 1.0); /* small integers and halves: exact */
}

static void test_triangulate_extreme(void **state)
{
    (void)state;
    comb_case(7, 1e150, 0, 0);
    comb_case(7, 1e-150, 0, 0);
    comb_case(7, 1e200, 0, -1e200);
    comb_case(7, 1.0, 1e8, 1e8);
    comb_case(7, 1e-4, 1e8, 0); /* features 1e-12 relative to the offset */
    comb_case(7, 0x1p-1000, 0x1p-990, 0);
}

static void test_nearly_collinear(void **state)
{
    (void)state;
    /* a thin zigzag strip: bottom on y = 0, top on y = 1e-12 with a bump
     * pattern of 1e-28; the exact predicate decides every ear */
    enum { M = 40 };
    double p[3 * 2 * M] = {0}, xy[2 * 2 * M] = {0};
    size_t n = 0;
    for (int i = 0; i < M; ++i, ++n) {
        xy[2 * n] = i;
        xy[2 * n + 1] = (i % 2) ? 1e-28 : 0;
    }
    for (int i = M - 1; i >= 0; --i, ++n) {
        xy[2 * n] = i;
        xy[2 * n + 1] = 1e-12 + ((i % 3) ? 0 : 1e-28);
    }
    for (size_t i = 0; i < n; ++i) {
        p[3 * i] = xy[2 * i];
        p[3 * i + 1] = xy[2 * i + 1];
        p[3 * i + 2] = 0;
    }
    uint32_t t[3 * 2 * M];
    assert_int_equal(geom_polygon_triangulate(n, p, t), GEOM_OK);
    /* a proper triangulation: sides once, diagonals twice, no clockwise
     * triangle */
    int *use = calloc(n * n, sizeof(int));
    for (size_t k = 0; k + 2 < n; ++k) {
        const uint32_t *v = t + 3 * k;
        assert_true(geom_orient2d(xy + 2 * v[0], xy + 2 * v[1], xy + 2 * v[2]) >= 0);
        for (int j = 0; j < 3; ++j)
            use[v[j] * n + v[(j + 1) % 3]]++;
    }
    for (size_t a = 0; a < n; ++a)
        for (size_t b = 0; b < n; ++b) {
            if (b == (a + 1) % n)
                assert_int_equal(use[a * n + b], 1);
            else if (a != (b + 1) % n)
                assert_int_equal(use[a * n + b], use[b * n + a]);
        }
    free(use);
}

static void test_degenerate_faces_build(void **state)
{
    (void)state;
    /* a fan around vertex 0 with one collinear triangle, one triangle with
     * all three vertices at the same point, and a collinear quad */
    double xyz[] = {0, 0, 0, 1, 0, 0, 2, 0, 0, 1, 1, 0, 0, 1, 0,
                    5, 5, 5, 5, 5, 5, 5, 5, 5,                 /* 5 6 7 coincide */
                    9, 0, 0, 10, 0, 0, 11, 0, 0, 12, 0, 0};    /* 8..11 on a line */
    uint32_t sz[] = {3, 3, 3, 3, 4};
    uint32_t ix[] = {0, 1, 3, 1, 2, 3, 0, 3, 4, 5, 6, 7, 8, 9, 10, 11};
    /* faces: fine, fine, fine, coincident, collinear quad; plus a collinear
     * triangle 0 1 2 as a separate face */
    uint32_t sz2[6], ix2[19];
    memcpy(sz2, sz, sizeof sz);
    sz2[5] = 3;
    memcpy(ix2, ix, sizeof ix);
    ix2[16] = 2;
    ix2[17] = 1;
    ix2[18] = 0;
    geom_mesh *m = geom_mesh_create(NULL);
    geom_mesh_build_report r;
    assert_int_equal(geom_mesh_build(m, 12, xyz, 6, sz2, ix2, NULL, &r, NULL), GEOM_OK);
    assert_valid(m);
    geom_mesh_topology t;
    assert_int_equal(geom_mesh_topology_summary(m, &t), GEOM_OK);
    assert_int_equal(t.degenerate_faces, 3);
    assert_true(geom_mesh_face_is_degenerate(m, 3));
    assert_true(geom_mesh_face_is_degenerate(m, 4));
    assert_true(geom_mesh_face_is_degenerate(m, 5));
    assert_false(geom_mesh_face_is_degenerate(m, 0));
    size_t added;
    assert_int_equal(geom_mesh_triangulate(m, &added), GEOM_OK); /* the quad: a fan */
    assert_int_equal(added, 1);
    assert_valid(m);
    geom_mesh_destroy(m);
}

static void test_nonfinite_rejected(void **state)
{
    (void)state;
    double bad[4] = {NAN, INFINITY, -INFINITY, 1e308 * 10};
    uint32_t sz[1] = {3}, ix[3] = {0, 1, 2};
    geom_mesh *m = geom_mesh_create(NULL);
    for (int k = 0; k < 4; ++k)
        for (int c = 0; c < 9; ++c) {
            double xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
            xyz[c] = bad[k];
            geom_diag d;
            assert_int_equal(geom_mesh_build(m, 3, xyz, 1, sz, ix, NULL, NULL, &d),
                             GEOM_ERR_INVALID_ARG);
            assert_int_equal(geom_mesh_n_vertices(m), 0);
            uint32_t t[3];
            assert_int_equal(geom_polygon_triangulate(3, xyz, t), GEOM_ERR_INVALID_ARG);
        }
    /* a quad whose position later becomes infinite: triangulation refuses
     * without touching the mesh (it used to write through garbage indices) */
    double quad[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    uint32_t qs[1] = {4}, qi[4] = {0, 1, 2, 3};
    assert_int_equal(geom_mesh_build(m, 4, quad, 1, qs, qi, NULL, NULL, NULL), GEOM_OK);
    geom_mesh_positions(m)[4] = INFINITY;
    assert_int_equal(geom_mesh_triangulate(m, NULL), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_mesh_n_faces(m), 1);
    assert_valid(m);
    uint32_t t4[6];
    assert_int_equal(geom_polygon_triangulate(4, geom_mesh_cpositions(m), t4),
                     GEOM_ERR_INVALID_ARG);
    for (int i = 0; i < 6; ++i)
        assert_true(t4[i] < 4); /* a fan, never garbage */
    /* the largest finite coordinates are accepted */
    double big[9] = {-1.7e308, -1.7e308, 0, 1.7e308, -1.7e308, 0, 0, 1.7e308, 0};
    assert_int_equal(geom_mesh_build(m, 3, big, 1, sz, ix, NULL, NULL, NULL), GEOM_OK);
    assert_valid(m);
    assert_false(geom_mesh_face_is_degenerate(m, 0));
    geom_mesh_destroy(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_huge_tiny_offset_grids),
        cmocka_unit_test(test_triangulate_extreme),
        cmocka_unit_test(test_nearly_collinear),
        cmocka_unit_test(test_degenerate_faces_build),
        cmocka_unit_test(test_nonfinite_rejected),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
