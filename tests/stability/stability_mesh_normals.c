/*
 * Normals on stiff and extreme inputs: coordinates scaled by 1e+-150 and
 * 1e+-300 (scale-invariant answers must not change), meshes far from the
 * origin, slivers, nearly flat dihedral angles, non-finite positions, and
 * random soups of mixed magnitudes. A normal is always finite, and unit or
 * zero.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "geom/mesh.h"

static const geom_normal_weight WS[4] = {GEOM_NORMAL_WEIGHT_ANGLE, GEOM_NORMAL_WEIGHT_UNIFORM,
                                         GEOM_NORMAL_WEIGHT_AREA, GEOM_NORMAL_WEIGHT_MAX};

static geom_mesh *mk(size_t nv, const double *xyz, size_t nf, const uint32_t *sizes,
                     const uint32_t *idx)
{
    geom_mesh *m = geom_mesh_create(NULL);
    assert_non_null(m);
    assert_int_equal(geom_mesh_build(m, nv, xyz, nf, sizes, idx, NULL, NULL, NULL), GEOM_OK);
    return m;
}

/* Finite, and unit length or exactly zero. */
static void check_normals(const double *n, size_t nv)
{
    for (size_t v = 0; v < nv; v++) {
        const double *q = n + 3 * v;
        assert_true(isfinite(q[0]) && isfinite(q[1]) && isfinite(q[2]));
        double l = q[0] * q[0] + q[1] * q[1] + q[2] * q[2];
        assert_true(l == 0.0 || fabs(l - 1.0) < 1e-14);
    }
}

/* Box [0,1]x[0,2]x[0,3] triangulated asymmetrically, scaled by s and
 * moved by t (per axis). */
static geom_mesh *box(double s, double t)
{
    static const uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                         {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    double xyz[24];
    for (int v = 0; v < 8; v++) {
        xyz[3 * v] = ((v & 1) ? 1.0 : 0.0) * s + t;
        xyz[3 * v + 1] = ((v & 2) ? 2.0 : 0.0) * s + t;
        xyz[3 * v + 2] = ((v & 4) ? 3.0 : 0.0) * s + t;
    }
    uint32_t sizes[12], idx[36];
    for (int f = 0; f < 6; f++) {
        const uint32_t *q = quads[f];
        uint32_t tr[6] = {q[0], q[1], q[2], q[0], q[2], q[3]};
        memcpy(idx + 6 * f, tr, sizeof tr);
        sizes[2 * f] = sizes[2 * f + 1] = 3;
    }
    return mk(8, xyz, 12, sizes, idx);
}

static void test_extreme_scales(void **state)
{
    (void)state;
    geom_mesh *ref = box(1.0, 0.0);
    const double scales[] = {1e150, 1e-150, 1e300, 1e-300, 0x1p-1060, 1.7e308 / 4};
    for (int w = 0; w < 4; w++) {
        double nr[24];
        size_t nz;
        assert_int_equal(geom_mesh_vertex_normals(ref, WS[w], nr, &nz), GEOM_OK);
        for (size_t k = 0; k < sizeof scales / sizeof scales[0]; k++) {
            geom_mesh *m = box(scales[k], 0.0);
            double n[24];
            assert_int_equal(geom_mesh_vertex_normals(m, WS[w], n, &nz), GEOM_OK);
            check_normals(n, 8);
            /* powers of ten are inexact, so the box is slightly off
             * square; the subnormal one (exact) must agree as well */
            assert_int_equal(nz, 0);
            for (int i = 0; i < 24; i++)
                assert_true(fabs(n[i] - nr[i]) < 1e-15);
            for (uint32_t f = 0; f < 12; f++) {
                double fn[3], fr[3];
                assert_int_equal(geom_mesh_face_normal(m, f, fn), GEOM_OK);
                assert_int_equal(geom_mesh_face_normal(ref, f, fr), GEOM_OK);
                for (int i = 0; i < 3; i++)
                    assert_true(fabs(fn[i] - fr[i]) < 1e-15);
            }
            geom_mesh_destroy(m);
        }
    }
    geom_mesh_destroy(ref);
}

static void test_far_from_origin(void **state)
{
    (void)state;
    /* a box of size 1e146 at 1e150: differences keep ~40 bits */
    geom_mesh *ref = box(1.0, 0.0);
    geom_mesh *m = box(1e146, 1e150);
    for (int w = 0; w < 4; w++) {
        double nr[24], n[24];
        assert_int_equal(geom_mesh_vertex_normals(ref, WS[w], nr, NULL), GEOM_OK);
        assert_int_equal(geom_mesh_vertex_normals(m, WS[w], n, NULL), GEOM_OK);
        check_normals(n, 8);
        for (int i = 0; i < 24; i++)
            assert_true(fabs(n[i] - nr[i]) < 1e-9);
    }
    /* a unit box at 1e15 (half the mantissa left) */
    geom_mesh *m2 = box(1.0, 1e15);
    for (int w = 0; w < 4; w++) {
        double nr[24], n[24];
        assert_int_equal(geom_mesh_vertex_normals(ref, WS[w], nr, NULL), GEOM_OK);
        assert_int_equal(geom_mesh_vertex_normals(m2, WS[w], n, NULL), GEOM_OK);
        for (int i = 0; i < 24; i++)
            assert_true(fabs(n[i] - nr[i]) < 1e-15);
    }
    geom_mesh_destroy(m);
    geom_mesh_destroy(m2);
    geom_mesh_destroy(ref);
}

static void test_slivers_and_flat_dihedrals(void **state)
{
    (void)state;
    /* two triangles sharing edge (0,1) along x; the far vertices at
     * heights eps (sliver) and folded by a tiny angle */
    const double epss[] = {1e-6, 1e-10, 1e-13, 1e-20};
    for (size_t k = 0; k < sizeof epss / sizeof epss[0]; k++) {
        double e = epss[k];
        /* triangle A in z = 0 (0,1,2) with 2 at (0.5, e, 0) (a sliver);
         * triangle B (1,0,3) with 3 at (0.5, -1, e) (dihedral ~ e) */
        double xyz[] = {0, 0, 0, 1, 0, 0, 0.5, e, 0, 0.5, -1, e};
        uint32_t sizes[] = {3, 3}, idx[] = {0, 1, 2, 1, 0, 3};
        geom_mesh *m = mk(4, xyz, 2, sizes, idx);
        for (int w = 0; w < 4; w++) {
            double n[12];
            size_t nz;
            assert_int_equal(geom_mesh_vertex_normals(m, WS[w], n, &nz), GEOM_OK);
            check_normals(n, 4);
            /* every normal is within angle ~e of +z */
            for (int v = 0; v < 4; v++) {
                if (n[3 * v] == 0 && n[3 * v + 1] == 0 && n[3 * v + 2] == 0)
                    continue;
                assert_true(n[3 * v + 2] > 1.0 - 4 * e * e + -1e-15);
                assert_true(fabs(n[3 * v]) <= 2 * e + 1e-15 && fabs(n[3 * v + 1]) <= 2 * e + 1e-15);
            }
            /* vertex 3 lies only in triangle B, whose normal is
             * (0, e, 1)/|.| */
            assert_true(fabs(n[10] - e / sqrt(1 + e * e)) < 1e-15 * e + 1e-300);
        }
        geom_corner_normal_options o;
        memset(&o, 0, sizeof o);
        o.crease_degrees = 1e-9; /* hard only when the fold is larger */
        uint32_t id;
        assert_int_equal(geom_mesh_corner_normals(m, &o, &id), GEOM_OK);
        size_t pool = geom_mesh_channel_size(m, id);
        double fold = atan(e) * 180.0 / 3.14159265358979323846;
        assert_int_equal(pool, fold > 1e-9 ? 6u : 4u);
        const double *d = geom_mesh_channel_cdata(m, id);
        check_normals(d, pool);
        geom_mesh_destroy(m);
    }
}

static void test_nonfinite_positions(void **state)
{
    (void)state;
    const double bad[3] = {NAN, INFINITY, -INFINITY};
    for (int b = 0; b < 3; b++) {
        geom_mesh *m = box(1.0, 0.0);
        geom_mesh *ref = box(1.0, 0.0);
        double *p = geom_mesh_positions(m);
        p[b] = bad[b]; /* a coordinate of vertex 0 */
        for (int w = 0; w < 4; w++) {
            double n[24];
            size_t nz = 0;
            assert_int_equal(geom_mesh_vertex_normals(m, WS[w], n, &nz), GEOM_OK);
            check_normals(n, 8);
            /* vertex 0 has no usable face; the others keep some */
            assert_int_equal(nz, 1);
            assert_true(n[0] == 0 && n[1] == 0 && n[2] == 0);
            /* vertex 7 has no face at vertex 0: unchanged */
            double nr[24];
            assert_int_equal(geom_mesh_vertex_normals(ref, WS[w], nr, NULL), GEOM_OK);
            for (int k = 21; k < 24; k++)
                assert_true(n[k] == nr[k]);
        }
        uint32_t id;
        assert_int_equal(geom_mesh_corner_normals(m, NULL, &id), GEOM_OK);
        check_normals(geom_mesh_channel_cdata(m, id), geom_mesh_channel_size(m, id));
        double fn[3];
        assert_int_equal(geom_mesh_face_normal(m, 0, fn), GEOM_ERR_DEGENERATE);
        assert_true(fn[0] == 0 && fn[1] == 0 && fn[2] == 0);
        geom_mesh_destroy(m);
        geom_mesh_destroy(ref);
    }
}

static uint64_t rs = 88172645463325252ull;
static double urand(void)
{
    rs ^= rs << 13;
    rs ^= rs >> 7;
    rs ^= rs << 17;
    return (double)(rs >> 11) / 9007199254740992.0;
}

/* Random strips of triangles whose vertices have magnitudes from 1e-300
 * to 1e300: never NaN, always unit or zero. */
static void test_random_magnitudes(void **state)
{
    (void)state;
    const size_t n = 200;
    double *xyz = malloc(3 * (n + 2) * sizeof(double));
    uint32_t *sizes = malloc(n * sizeof(uint32_t)), *idx = malloc(3 * n * sizeof(uint32_t));
    double *nn = malloc(3 * (n + 2) * sizeof(double));
    assert_true(xyz && sizes && idx && nn);
    for (int trial = 0; trial < 20; trial++) {
        double mag = pow(10.0, -300.0 + 600.0 * urand());
        for (size_t i = 0; i < n + 2; i++) {
            xyz[3 * i] = (double)i * mag * (1.0 + 0.1 * urand());
            xyz[3 * i + 1] = (i % 2 ? 1.0 : 0.0) * mag * pow(10.0, -20.0 * urand());
            xyz[3 * i + 2] = (urand() - 0.5) * mag * pow(10.0, -15.0 * urand());
        }
        for (size_t t = 0; t < n; t++) {
            sizes[t] = 3;
            if (t % 2 == 0) {
                idx[3 * t] = (uint32_t)t;
                idx[3 * t + 1] = (uint32_t)t + 2;
                idx[3 * t + 2] = (uint32_t)t + 1;
            } else {
                idx[3 * t] = (uint32_t)t;
                idx[3 * t + 1] = (uint32_t)t + 1;
                idx[3 * t + 2] = (uint32_t)t + 2;
            }
        }
        geom_mesh *m = mk(n + 2, xyz, n, sizes, idx);
        for (int w = 0; w < 4; w++) {
            assert_int_equal(geom_mesh_vertex_normals(m, WS[w], nn, NULL), GEOM_OK);
            check_normals(nn, n + 2);
        }
        uint32_t id;
        geom_corner_normal_options o;
        memset(&o, 0, sizeof o);
        o.crease_degrees = 20;
        assert_int_equal(geom_mesh_corner_normals(m, &o, &id), GEOM_OK);
        check_normals(geom_mesh_channel_cdata(m, id), geom_mesh_channel_size(m, id));
        for (uint32_t f = 0; f < n; f++) {
            double fn[3];
            geom_status st = geom_mesh_face_normal(m, f, fn);
            assert_true(st == GEOM_OK || st == GEOM_ERR_DEGENERATE);
            check_normals(fn, 1);
        }
        geom_mesh_destroy(m);
    }
    free(xyz);
    free(sizes);
    free(idx);
    free(nn);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_extreme_scales),
        cmocka_unit_test(test_far_from_origin),
        cmocka_unit_test(test_slivers_and_flat_dihedrals),
        cmocka_unit_test(test_nonfinite_positions),
        cmocka_unit_test(test_random_magnitudes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
