/*
 * Batch barycentric coordinates (geom_bary_simplex_many) against the
 * single-point functions: the shared-simplex loops (all vertex strides 0)
 * must give the same statuses, the same exact zeros and ones on faces and at
 * vertices, bitwise the same tri2 and tet weights; non-finite and
 * degenerate rows fail as the single functions fail.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "geom/bary.h"

#define N 4000

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static double urand(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) * 0x1p-53;
}

/* Points: random, then every vertex, edge midpoints and points on the
 * lines through edges (exact zeros), then NaN and Inf rows. */
static size_t fill_points(double *p, size_t dim, const double *v, size_t nv)
{
    size_t n = 0;
    for (; n < N - 64; n++)
        for (size_t k = 0; k < dim; k++)
            p[dim * n + k] = -1.0 + 4.0 * urand();
    for (size_t i = 0; i < nv; i++, n++)
        memcpy(p + dim * n, v + dim * i, dim * sizeof(double));
    for (size_t i = 0; i < nv; i++)
        for (size_t j = i + 1; j < nv; j++, n++)
            for (size_t k = 0; k < dim; k++)
                p[dim * n + k] = 0.5 * (v[dim * i + k] + v[dim * j + k]);
    for (size_t k = 0; k < dim; k++)
        p[dim * n + k] = NAN;
    n++;
    for (size_t k = 0; k < dim; k++)
        p[dim * n + k] = k ? 0.0 : INFINITY;
    n++;
    /* points near the vertices (uncertified by the filter, exact path) */
    for (size_t i = 0; i < nv; i++, n++)
        for (size_t k = 0; k < dim; k++)
            p[dim * n + k] = v[dim * i + k] + (k ? 0x1p-50 : 0.0);
    return n;
}

static void check_rows(size_t n, size_t k, const double *got, const int32_t *gst,
                       const double *want, const int32_t *wst, double rel)
{
    for (size_t i = 0; i < n; i++) {
        if (gst[i] != wst[i])
            fail_msg("row %zu: status %d, single %d", i, (int)gst[i], (int)wst[i]);
        if (wst[i] != GEOM_OK) {
            for (size_t j = 0; j < k; j++)
                assert_true(isnan(got[k * i + j]));
            continue;
        }
        for (size_t j = 0; j < k; j++) {
            double g = got[k * i + j], w = want[k * i + j];
            if (w == 0.0 || w == 1.0 || rel == 0.0) {
                if (memcmp(&g, &w, sizeof g) != 0)
                    fail_msg("row %zu weight %zu: %.17g, single %.17g", i, j, g, w);
            } else if (!(fabs(g - w) <= rel * fabs(w)) || signbit(g) != signbit(w)) {
                fail_msg("row %zu weight %zu: %.17g, single %.17g", i, j, g, w);
            }
        }
    }
}

static void test_tri2_shared(void **state)
{
    (void)state;
    static double p[2 * N], got[3 * N], want[3 * N];
    static int32_t gst[N], wst[N];
    const double v[6] = {0.1, 0.2, 3.0, 0.5, 1.0, 2.5};
    size_t n = fill_points(p, 2, v, 3);
    const double *pts[5] = {v, v + 2, v + 4, p, NULL};
    const size_t strides[5] = {0, 0, 0, 2, 0};
    size_t failed = 0;
    assert_int_equal(geom_bary_simplex_many(GEOM_BARY_TRI2, n, pts, strides, got, gst, &failed),
                     GEOM_OK);
    size_t wfail = 0;
    for (size_t i = 0; i < n; i++) {
        wst[i] = geom_bary_tri2(v, v + 2, v + 4, p + 2 * i, want + 3 * i);
        wfail += wst[i] != GEOM_OK;
    }
    assert_int_equal(failed, wfail);
    assert_int_equal(wfail, 2); /* the NaN and Inf rows */
    check_rows(n, 3, got, gst, want, wst, 0.0);
    /* a vertex gives exactly (1, 0, 0) */
    assert_true(got[3 * (N - 64)] == 1.0 && got[3 * (N - 64) + 1] == 0.0);
}

static void test_tri2_degenerate_shared(void **state)
{
    (void)state;
    const double a[2] = {0, 0}, b[2] = {1, 1}, c[2] = {2, 2}, p[4] = {0.5, 0.2, 1, 1};
    const double *pts[5] = {a, b, c, p, NULL};
    const size_t strides[5] = {0, 0, 0, 2, 0};
    double out[6];
    int32_t st[2];
    size_t failed = 0;
    assert_int_equal(geom_bary_simplex_many(GEOM_BARY_TRI2, 2, pts, strides, out, st, &failed),
                     GEOM_OK);
    assert_int_equal(failed, 2);
    assert_int_equal(st[0], GEOM_ERR_DEGENERATE);
    assert_int_equal(st[1], GEOM_ERR_DEGENERATE);
    assert_true(isnan(out[0]));
}

/* tri3 in one shared triangle: bitwise geom_bary_tri3 (points off the
 * plane, on its edges and vertices, near the vertices: the exact path, NaN
 * and Inf rows); packed points and a stride of 4 (the gathered path). */
static void test_tri3_shared(void **state)
{
    (void)state;
    static double p[3 * N], p4[4 * N], got[3 * N], want[3 * N];
    static int32_t gst[N], wst[N];
    const double v[9] = {0.3, -0.2, 0.1, 2.0, 0.1, -0.4, 0.2, 1.7, 0.3};
    size_t n = fill_points(p, 3, v, 3);
    for (size_t i = 0; i < n; i++)
        memcpy(p4 + 4 * i, p + 3 * i, 3 * sizeof(double));
    size_t wfail = 0;
    for (size_t i = 0; i < n; i++) {
        wst[i] = geom_bary_tri3(v, v + 3, v + 6, p + 3 * i, want + 3 * i);
        wfail += wst[i] != GEOM_OK;
    }
    assert_int_equal(wfail, 2);
    for (int packed = 0; packed < 2; packed++) {
        const double *pts[5] = {v, v + 3, v + 6, packed ? p : p4, NULL};
        const size_t strides[5] = {0, 0, 0, packed ? 3 : 4, 0};
        size_t failed = 0;
        assert_int_equal(
            geom_bary_simplex_many(GEOM_BARY_TRI3, n, pts, strides, got, gst, &failed), GEOM_OK);
        assert_int_equal(failed, wfail);
        check_rows(n, 3, got, gst, want, wst, 0.0); /* bitwise */
    }
    /* a vertex gives exactly (1, 0, 0); the weights sum to 1 */
    assert_true(got[3 * (N - 64)] == 1.0 && got[3 * (N - 64) + 1] == 0.0);
    for (size_t i = 0; i < n; i++)
        if (gst[i] == GEOM_OK)
            assert_true(fabs(got[3 * i] + got[3 * i + 1] + got[3 * i + 2] - 1.0) < 1e-11);
    /* a degenerate (collinear) shared triangle fails every row as tri3 does */
    const double w[9] = {0, 0, 0, 1, 1, 1, 2, 2, 2};
    const double *dpts[5] = {w, w + 3, w + 6, p, NULL};
    const size_t dstr[5] = {0, 0, 0, 3, 0};
    assert_int_equal(geom_bary_simplex_many(GEOM_BARY_TRI3, 100, dpts, dstr, got, gst, NULL),
                     GEOM_OK);
    for (size_t i = 0; i < 100; i++)
        assert_int_equal(gst[i], geom_bary_tri3(w, w + 3, w + 6, p + 3 * i, want));
}

static void test_tet_shared(void **state)
{
    (void)state;
    static double p[3 * N], got[4 * N], want[4 * N];
    static int32_t gst[N], wst[N];
    const double v[12] = {0.3, -0.2, 0.1, 2.0, 0.1, -0.4, 0.2, 1.7, 0.3, -0.1, 0.4, 2.2};
    size_t n = fill_points(p, 3, v, 4);
    const double *pts[5] = {v, v + 3, v + 6, v + 9, p};
    const size_t strides[5] = {0, 0, 0, 0, 3};
    size_t failed = 0;
    assert_int_equal(geom_bary_simplex_many(GEOM_BARY_TET, n, pts, strides, got, gst, &failed),
                     GEOM_OK);
    size_t wfail = 0;
    for (size_t i = 0; i < n; i++) {
        wst[i] = geom_bary_tet(v, v + 3, v + 6, v + 9, p + 3 * i, want + 4 * i);
        wfail += wst[i] != GEOM_OK;
    }
    assert_int_equal(failed, wfail);
    assert_int_equal(wfail, 2);
    check_rows(n, 4, got, gst, want, wst, 0.0); /* bitwise */
    /* the weights reproduce the point and sum to 1 */
    for (size_t i = 0; i < n; i++) {
        if (gst[i] != GEOM_OK)
            continue;
        const double *l = got + 4 * i;
        double s = l[0] + l[1] + l[2] + l[3];
        assert_true(fabs(s - 1.0) < 1e-11 * (1.0 + fabs(l[0]) + fabs(l[1]) + fabs(l[2])));
        for (int k = 0; k < 3; k++) {
            double x = l[0] * v[k] + l[1] * v[3 + k] + l[2] * v[6 + k] + l[3] * v[9 + k];
            assert_true(fabs(x - p[3 * i + k]) < 1e-10);
        }
    }
}

static void test_tet_general_strides(void **state)
{
    (void)state;
    /* one tetrahedron per row (no shared path) gives the single results */
    static double a[3 * 64], p[3 * 64], got[4 * 64], want[4 * 64];
    static int32_t gst[64], wst[64];
    const double b[3] = {1, 0, 0}, c[3] = {0, 1, 0}, d[3] = {0, 0, 1};
    for (size_t i = 0; i < 3 * 64; i++) {
        a[i] = -0.5 * urand();
        p[i] = urand();
    }
    const double *pts[5] = {a, b, c, d, p};
    const size_t strides[5] = {3, 0, 0, 0, 3};
    assert_int_equal(geom_bary_simplex_many(GEOM_BARY_TET, 64, pts, strides, got, gst, NULL),
                     GEOM_OK);
    for (size_t i = 0; i < 64; i++)
        wst[i] = geom_bary_tet(a + 3 * i, b, c, d, p + 3 * i, want + 4 * i);
    check_rows(64, 4, got, gst, want, wst, 0.0);
}

static int same_bits(double x, double y)
{
    return memcmp(&x, &y, sizeof x) == 0;
}

/* geom_bary_perspective_many against geom_bary_perspective: random rows,
 * zero w, a vanishing sum, huge and tiny w (the rescaled path), NaN/Inf;
 * one w per row and one shared w (stride 0). */
static void test_perspective_many(void **state)
{
    (void)state;
    enum { M = 1000 };
    static double l[3 * M], w[3 * M], got[3 * M];
    static int32_t gst[M];
    for (size_t i = 0; i < 3 * M; i++) {
        l[i] = urand();
        w[i] = 0.1 + 10.0 * urand();
    }
    w[3 * 1 + 2] = 0.0;                              /* zero w */
    l[3 * 2] = 1.0, l[3 * 2 + 1] = -1.0, l[3 * 2 + 2] = 0.0; /* sum vanishes */
    w[3 * 2] = w[3 * 2 + 1] = 2.0;
    w[3 * 3] = 1e-300, w[3 * 3 + 1] = 1e300, w[3 * 3 + 2] = -1e-310; /* rescaled */
    l[3 * 4 + 1] = NAN;
    w[3 * 5] = INFINITY;
    w[3 * 6] = -1.0; /* mixed signs */
    l[3 * 7] = 1.0, l[3 * 7 + 1] = 0.0, l[3 * 7 + 2] = 0.0; /* a vertex */
    /* the batch runs blocks of 64 rows: failing and rescaled rows inside a
     * later block and in the last, partial one */
    w[3 * 700 + 1] = 0.0;
    w[3 * 701] = 0x1p-1040, w[3 * 701 + 1] = 0x1p-1050; /* rescaled (huge q) */
    l[3 * 702] = 0x1p-1030, l[3 * 702 + 1] = 0.0, l[3 * 702 + 2] = 0x1p-1060; /* tiny q */
    w[3 * (M - 2) + 2] = -INFINITY;
    for (int shared = 0; shared < 2; shared++) {
        size_t sw = shared ? 0 : 3, failed = 99, want_failed = 0;
        assert_int_equal(geom_bary_perspective_many(M, l, 3, w, sw, got, gst, &failed), GEOM_OK);
        for (size_t i = 0; i < M; i++) {
            double want[3];
            geom_status st = geom_bary_perspective(l + 3 * i, w + i * sw, want);
            assert_int_equal(gst[i], st);
            for (size_t k = 0; k < 3; k++)
                assert_true(st == GEOM_OK ? same_bits(got[3 * i + k], want[k])
                                          : isnan(got[3 * i + k]));
            want_failed += st != GEOM_OK;
        }
        assert_int_equal(failed, want_failed);
        if (!shared) {
            assert_int_equal(want_failed, 6);
            assert_int_equal(gst[700], GEOM_ERR_DEGENERATE);
            assert_int_equal(gst[701], GEOM_OK);
            assert_int_equal(gst[702], GEOM_OK);
            assert_int_equal(gst[M - 2], GEOM_ERR_INVALID_ARG);
            assert_int_equal(gst[1], GEOM_ERR_DEGENERATE);
            assert_int_equal(gst[2], GEOM_ERR_DEGENERATE);
            assert_int_equal(gst[3], GEOM_OK);
            assert_int_equal(gst[4], GEOM_ERR_INVALID_ARG);
            assert_int_equal(gst[5], GEOM_ERR_INVALID_ARG);
        }
    }
    /* NULL status is fine; NULL arrays are refused with n > 0 only */
    assert_int_equal(geom_bary_perspective_many(M, l, 3, w, 3, got, NULL, NULL), GEOM_OK);
    /* in place (lp = l): each row as computed from its own input */
    static double inplace[3 * M];
    memcpy(inplace, l, sizeof l);
    assert_int_equal(geom_bary_perspective_many(M, inplace, 3, w, 3, inplace, NULL, NULL),
                     GEOM_OK);
    for (size_t i = 0; i < 3 * M; i++)
        assert_true(same_bits(inplace[i], got[i]) || (isnan(inplace[i]) && isnan(got[i])));
    assert_int_equal(geom_bary_perspective_many(1, NULL, 3, w, 3, got, NULL, NULL),
                     GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_bary_perspective_many(0, NULL, 3, NULL, 3, NULL, NULL, NULL), GEOM_OK);
}

/* geom_bary_interpolate_many against geom_bary_interpolate, bitwise, and
 * against a closed form: interpolating the vertex positions gives p. Every
 * k and ncomp the batch has a loop of its own (k 3, 4; ncomp 1..4) and
 * others, with signed zeros (0 + -0 is +0: the sums' order shows), NaN
 * and infinite weights. */
static void test_interpolate_many(void **state)
{
    (void)state;
    enum { M = 500, K = 4, C = 5 };
    static double l[K * M], attr[K * C], got[C * M];
    static const double edge[] = {0.0, -0.0, 1e-310, -1e300, 1e300};
    for (size_t k = 2; k <= K; k++)
        for (size_t nc = 1; nc <= C; nc++) {
            for (size_t i = 0; i < K * M; i++)
                l[i] = i % 7 == 0 ? edge[(i / 7) % 5] : 2.0 * urand() - 0.5;
            for (size_t i = 0; i < K * C; i++)
                attr[i] = i % 3 == 0 ? edge[(i / 3 + k) % 5] : 1e8 + urand();
            l[K * 3 + 1] = NAN;
            l[K * 4 + 2] = INFINITY;
            size_t m = M - k - nc; /* odd row counts too */
            assert_int_equal(geom_bary_interpolate_many(m, k, l, nc, attr, got), GEOM_OK);
            for (size_t i = 0; i < m; i++) {
                double want[C];
                assert_int_equal(geom_bary_interpolate(k, l + k * i, nc, attr, want), GEOM_OK);
                for (size_t j = 0; j < nc; j++)
                    assert_true(isnan(want[j]) ? isnan(got[nc * i + j])
                                               : same_bits(got[nc * i + j], want[j]));
            }
        }
    /* out over the weights (in place, k == ncomp): what the single
     * function does row by row in place */
    double ref[3 * 10];
    for (size_t i = 0; i < 3 * 10; i++)
        l[i] = ref[i] = urand();
    for (size_t i = 0; i < 10; i++)
        assert_int_equal(geom_bary_interpolate(3, ref + 3 * i, 3, attr, ref + 3 * i), GEOM_OK);
    assert_int_equal(geom_bary_interpolate_many(10, 3, l, 3, attr, l), GEOM_OK);
    for (size_t i = 0; i < 3 * 10; i++)
        assert_true(same_bits(l[i], ref[i]));
    l[K * 3 + 1] = NAN;
    assert_int_equal(geom_bary_interpolate_many(M, K, l, C, attr, got), GEOM_OK);
    assert_true(isnan(got[C * 3]));
    /* tri2 weights reproduce the point */
    const double tri[6] = {0, 0, 4, 0, 0, 2}, p[2] = {1, 0.5};
    double w[3], q[2];
    assert_int_equal(geom_bary_tri2(tri, tri + 2, tri + 4, p, w), GEOM_OK);
    assert_int_equal(geom_bary_interpolate_many(1, 3, w, 2, tri, q), GEOM_OK);
    assert_true(q[0] == 1.0 && q[1] == 0.5);
    assert_int_equal(geom_bary_interpolate_many(1, 0, l, C, attr, got), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_bary_interpolate_many(1, K, l, C, NULL, got), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_bary_interpolate_many(0, 0, NULL, 0, NULL, NULL), GEOM_OK);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tri2_shared),
        cmocka_unit_test(test_tri2_degenerate_shared),
        cmocka_unit_test(test_tri3_shared),
        cmocka_unit_test(test_tet_shared),
        cmocka_unit_test(test_tet_general_strides),
        cmocka_unit_test(test_perspective_many),
        cmocka_unit_test(test_interpolate_many),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
