/*
 * Feature edges and polylines:
 *  - a triangulated cube at 30 degrees: the 12 cube edges are creases (the
 *    face diagonals are flat), each corner has three, so 12 two-vertex
 *    polylines;
 *  - an open cylinder: two closed boundary loops, no creases;
 *  - the silhouette of a UV sphere of radius R seen from an eye at distance
 *    D from its centre: the exact contour is the circle of points p with
 *    (p - c).a = R^2 / D (a the unit direction to the eye), radius
 *    R sqrt(1 - R^2/D^2); silhouette vertices must lie within a facet of it
 *    and go all around it.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "unit/test_util.h"
#include "geom/mesh.h"

#define PI 3.14159265358979323846

static geom_mesh *mk(size_t nv, const double *xyz, size_t nf, const uint32_t *sizes,
                     const uint32_t *idx)
{
    geom_mesh *m = geom_mesh_create(NULL);
    assert_non_null(m);
    assert_int_equal(geom_mesh_build(m, nv, xyz, nf, sizes, idx, NULL, NULL, NULL), GEOM_OK);
    return m;
}

/* Bits set in a 3-bit cube vertex index difference. */
static int popcount3(uint32_t x)
{
    return (int)(x & 1u) + (int)((x >> 1) & 1u) + (int)((x >> 2) & 1u);
}

static void test_cube_creases(void **state)
{
    (void)state;
    static const uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                         {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    double xyz[24];
    for (int v = 0; v < 8; v++) {
        xyz[3 * v] = v & 1;
        xyz[3 * v + 1] = (v >> 1) & 1;
        xyz[3 * v + 2] = (v >> 2) & 1;
    }
    uint32_t sizes[12], idx[36];
    for (int f = 0; f < 6; f++) {
        const uint32_t *q = quads[f];
        uint32_t t[6] = {q[0], q[1], q[2], q[0], q[2], q[3]};
        memcpy(idx + 6 * f, t, sizeof t);
        sizes[2 * f] = sizes[2 * f + 1] = 3;
    }
    geom_mesh *m = mk(8, xyz, 12, sizes, idx);
    size_t ne = geom_mesh_n_edges(m);
    assert_int_equal(ne, 18);
    uint8_t kind[18];
    size_t npl = 0;
    geom_feature_options o;
    memset(&o, 0, sizeof o);
    o.crease_degrees = 30.0;
    assert_int_equal(geom_mesh_features(m, &o, kind, &npl), GEOM_OK);
    size_t ncrease = 0;
    for (uint32_t e = 0; e < ne; e++) {
        uint32_t a = geom_mesh_he_vertex(m, 2 * e), b = geom_mesh_he_vertex(m, 2 * e + 1);
        int diff = popcount3(a ^ b); /* cube edge: one coordinate differs */
        assert_int_equal(kind[e], diff == 1 ? GEOM_FEATURE_CREASE : 0);
        ncrease += kind[e] != 0;
    }
    assert_int_equal(ncrease, 12);
    assert_int_equal(npl, 12);
    assert_int_equal(geom_mesh_polyline_count(m), 12);
    for (size_t i = 0; i < 12; i++) {
        size_t n;
        const uint32_t *v;
        assert_int_equal(geom_mesh_polyline_get(m, i, &n, &v), GEOM_OK);
        assert_int_equal(n, 2);
        assert_int_equal(popcount3(v[0] ^ v[1]), 1);
    }
    /* default options (0): 30 degrees too, boundary | crease */
    assert_int_equal(geom_mesh_features(m, NULL, kind, &npl), GEOM_OK);
    assert_int_equal(npl, 12);
    /* at 100 degrees nothing is a crease */
    o.crease_degrees = 100.0;
    assert_int_equal(geom_mesh_features(m, &o, kind, &npl), GEOM_OK);
    assert_int_equal(npl, 0);
    for (uint32_t e = 0; e < ne; e++)
        assert_int_equal(kind[e], 0);
    o.crease_degrees = -5.0;
    assert_int_equal(geom_mesh_features(m, &o, kind, &npl), GEOM_ERR_INVALID_ARG);
    geom_mesh_destroy(m);
}

static void test_open_cylinder(void **state)
{
    (void)state;
    const int nseg = 32, nring = 3;
    size_t nv = (size_t)nseg * (nring + 1);
    double *xyz = malloc(3 * nv * sizeof(double));
    uint32_t *sizes = malloc((size_t)nseg * nring * sizeof(uint32_t));
    uint32_t *idx = malloc(4 * (size_t)nseg * nring * sizeof(uint32_t));
    assert_true(xyz && sizes && idx);
    for (int r = 0; r <= nring; r++) {
        for (int s = 0; s < nseg; s++) {
            double a = 2 * PI * s / nseg;
            double *q = xyz + 3 * ((size_t)r * nseg + s);
            q[0] = cos(a);
            q[1] = sin(a);
            q[2] = r;
        }
    }
    size_t f = 0;
    for (int r = 0; r < nring; r++) {
        for (int s = 0; s < nseg; s++) {
            uint32_t a = (uint32_t)(r * nseg + s), b = (uint32_t)(r * nseg + (s + 1) % nseg);
            uint32_t q[4] = {a, b, b + (uint32_t)nseg, a + (uint32_t)nseg};
            memcpy(idx + 4 * f, q, sizeof q);
            sizes[f++] = 4;
        }
    }
    geom_mesh *m = mk(nv, xyz, f, sizes, idx);
    size_t ne = geom_mesh_n_edges(m);
    uint8_t *kind = malloc(ne);
    assert_non_null(kind);
    size_t npl;
    assert_int_equal(geom_mesh_features(m, NULL, kind, &npl), GEOM_OK);
    assert_int_equal(npl, 2);
    size_t nb = 0;
    for (uint32_t e = 0; e < ne; e++) {
        assert_true(kind[e] == 0 || kind[e] == GEOM_FEATURE_BOUNDARY);
        nb += kind[e] != 0;
    }
    assert_int_equal(nb, 2 * (size_t)nseg);
    const double *p = geom_mesh_cpositions(m);
    int seen_bottom = 0, seen_top = 0;
    for (size_t i = 0; i < 2; i++) {
        size_t n;
        const uint32_t *v;
        assert_int_equal(geom_mesh_polyline_get(m, i, &n, &v), GEOM_OK);
        assert_int_equal(n, (size_t)nseg + 1);
        assert_int_equal(v[0], v[n - 1]); /* closed */
        double z = p[3 * v[0] + 2];
        for (size_t j = 0; j < n; j++)
            assert_true(p[3 * v[j] + 2] == z);
        /* consecutive vertices are neighbours on the ring */
        for (size_t j = 0; j + 1 < n; j++)
            assert_true(geom_mesh_find_edge(m, v[j], v[j + 1]) != GEOM_INVALID_INDEX);
        seen_bottom |= z == 0.0;
        seen_top |= z == nring;
    }
    assert_true(seen_bottom && seen_top);
    free(kind);
    free(xyz);
    free(sizes);
    free(idx);
    geom_mesh_destroy(m);
}

static void test_sphere_silhouette(void **state)
{
    (void)state;
    const int nlat = 48, nlon = 96;
    const double R = 1.5, c[3] = {0.5, -1.0, 2.0}, D = 3.0 * R;
    size_t nv = (size_t)nlat * nlon + 2;
    double *xyz = malloc(3 * nv * sizeof(double));
    size_t nfmax = (size_t)2 * nlon * nlat;
    uint32_t *sizes = malloc(nfmax * sizeof(uint32_t)), *idx = malloc(3 * nfmax * sizeof(uint32_t));
    assert_true(xyz && sizes && idx);
    for (int i = 0; i < nlat; i++) {
        for (int j = 0; j < nlon; j++) {
            double th = PI * (i + 1) / (nlat + 1), ph = 2 * PI * j / nlon;
            double *p = xyz + 3 * ((size_t)i * nlon + j);
            p[0] = c[0] + R * sin(th) * cos(ph);
            p[1] = c[1] + R * sin(th) * sin(ph);
            p[2] = c[2] + R * cos(th);
        }
    }
    uint32_t N = (uint32_t)nlat * nlon, S = N + 1;
    double pn[3] = {c[0], c[1], c[2] + R}, ps[3] = {c[0], c[1], c[2] - R};
    memcpy(xyz + 3 * N, pn, sizeof pn);
    memcpy(xyz + 3 * S, ps, sizeof ps);
    size_t f = 0;
    for (int j = 0; j < nlon; j++) {
        uint32_t j1 = (uint32_t)((j + 1) % nlon), base = (uint32_t)(nlat - 1) * nlon;
        uint32_t t[6] = {N, (uint32_t)j, j1, S, base + j1, base + (uint32_t)j};
        memcpy(idx + 3 * f, t, sizeof t);
        f += 2;
    }
    for (int i = 0; i + 1 < nlat; i++) {
        for (int j = 0; j < nlon; j++) {
            uint32_t j1 = (uint32_t)((j + 1) % nlon);
            uint32_t a = (uint32_t)i * nlon + (uint32_t)j, b = (uint32_t)i * nlon + j1;
            uint32_t cc = a + (uint32_t)nlon, d = b + (uint32_t)nlon;
            uint32_t t[6] = {a, cc, d, a, d, b};
            memcpy(idx + 3 * f, t, sizeof t);
            f += 2;
        }
    }
    for (size_t i = 0; i < f; i++)
        sizes[i] = 3;
    geom_mesh *m = mk(nv, xyz, f, sizes, idx);
    free(sizes);
    free(idx);

    double a[3] = {1.0, 0.5, 0.3};
    double al = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    for (int k = 0; k < 3; k++)
        a[k] /= al;
    geom_feature_options o;
    memset(&o, 0, sizeof o);
    o.kinds = GEOM_FEATURE_SILHOUETTE;
    for (int k = 0; k < 3; k++)
        o.eye[k] = c[k] + D * a[k];
    size_t ne = geom_mesh_n_edges(m);
    uint8_t *kind = malloc(ne);
    assert_non_null(kind);
    size_t npl = 0;
    assert_int_equal(geom_mesh_features(m, &o, kind, &npl), GEOM_OK);
    assert_true(npl >= 1);
    /* expected circle: centre c + (R^2/D) a, radius R sqrt(1 - R^2/D^2) */
    const double h = R * R / D, rc = R * sqrt(1.0 - (R / D) * (R / D));
    /* a facet spans at most pi/(nlat+1) in latitude and 2pi/nlon in
     * longitude: silhouette vertices are within two facets of the contour */
    const double tol = 2.0 * R * (2.0 * PI / nlon);
    int sector[12] = {0};
    double u[3] = {-a[1], a[0], 0.0}; /* a frame orthogonal to a */
    double ul = sqrt(u[0] * u[0] + u[1] * u[1]);
    u[0] /= ul;
    u[1] /= ul;
    double w[3] = {a[1] * u[2] - a[2] * u[1], a[2] * u[0] - a[0] * u[2], a[0] * u[1] - a[1] * u[0]};
    size_t nsil = 0;
    double sum_dev = 0.0;
    for (uint32_t e = 0; e < ne; e++) {
        if (!kind[e])
            continue;
        assert_int_equal(kind[e], GEOM_FEATURE_SILHOUETTE);
        for (int s = 0; s < 2; s++) {
            const double *p = xyz + 3 * geom_mesh_he_vertex(m, 2 * e + (uint32_t)s);
            double q[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
            double along = q[0] * a[0] + q[1] * a[1] + q[2] * a[2];
            double x = q[0] * u[0] + q[1] * u[1] + q[2] * u[2];
            double y = q[0] * w[0] + q[1] * w[1] + q[2] * w[2];
            double rad = sqrt(x * x + y * y);
            assert_true(fabs(along - h) < tol);
            assert_true(fabs(rad - rc) < tol);
            sum_dev += fabs(along - h);
            double ang = atan2(y, x) + PI;
            int sct = (int)(ang / (2 * PI) * 12.0);
            sector[sct > 11 ? 11 : sct] = 1;
        }
        nsil++;
    }
    /* all the way around */
    for (int s = 0; s < 12; s++)
        assert_true(sector[s]);
    /* and on average much closer than the bound */
    assert_true(sum_dev / (2.0 * nsil) < tol / 4);
    /* the silhouette is a loop: at least 2 pi rc / (longest edge) edges */
    assert_true((double)nsil >= 2 * PI * rc / (2 * PI * R / nlon));
    free(kind);
    free(xyz);
    geom_mesh_destroy(m);
}

/* ------------------------------------------------ allocation failures */

static void test_out_of_memory(void **state)
{
    (void)state;
    /* an open box (no top): 4 boundary edges and 8 creases */
    double xyz[24];
    for (int v = 0; v < 8; v++) {
        xyz[3 * v] = v & 1;
        xyz[3 * v + 1] = (v >> 1) & 1;
        xyz[3 * v + 2] = (v >> 2) & 1;
    }
    uint32_t sizes[5] = {4, 4, 4, 4, 4};
    uint32_t idx[20] = {0, 2, 3, 1, 0, 1, 5, 4, 2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5};
    int ok = 0;
    for (long k = 0; k < 200 && !ok; k++) {
        oom_state s = {-1, 0, 0};
        geom_allocator a = {oom_alloc, NULL, oom_free, &s};
        geom_mesh *m = geom_mesh_create(&a);
        assert_non_null(m);
        assert_int_equal(geom_mesh_build(m, 8, xyz, 5, sizes, idx, NULL, NULL, NULL), GEOM_OK);
        size_t npl = 99;
        s.budget = k;
        geom_status st = geom_mesh_features(m, NULL, NULL, &npl);
        assert_true(st == GEOM_OK || st == GEOM_ERR_NOMEM);
        s.budget = -1;
        if (st == GEOM_OK) {
            ok = 1;
            /* every corner has three feature edges (rim corners: two
             * boundary edges and a crease), so each edge is a polyline */
            assert_int_equal(npl, 12);
            for (size_t i = 0; i < npl; i++) {
                size_t n;
                const uint32_t *v;
                assert_int_equal(geom_mesh_polyline_get(m, i, &n, &v), GEOM_OK);
                assert_int_equal(n, 2);
            }
        }
        geom_mesh_destroy(m);
        assert_int_equal(s.live, 0);
        assert_false(s.bad_free);
    }
    assert_true(ok);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cube_creases),
        cmocka_unit_test(test_open_cylinder),
        cmocka_unit_test(test_sphere_silhouette),
        cmocka_unit_test(test_out_of_memory),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
