/*
 * geom_surface_eval_many (blocks of parameter pairs, basis lane by lane,
 * AVX2/AVX-512 clones) against geom_surface_eval at every row, bit for bit,
 * with the same status: polynomial and rational surfaces of degrees 1-4 and
 * one above the block kernel's largest degree, several spans, parameters on
 * knots (both limits), outside the domain, NaN and Inf, block tails.
 */
#include "unit/test_util.h"

#include <string.h>

#include "geom/surface.h"

static uint64_t rng_state = 0x243F6A8885A308D3ull;

static double urand(void) { return test_urand(&rng_state); }

/* Clamped knots of degree p for n points, interior knots at i / (n - p),
 * one of them doubled when n allows. */
static void knots(int p, size_t n, double *U)
{
    size_t m = n + (size_t)p + 1;
    for (size_t i = 0; i < m; i++) {
        if (i <= (size_t)p)
            U[i] = 0.0;
        else if (i >= n)
            U[i] = 1.0;
        else
            U[i] = (double)(i - (size_t)p) / (double)(n - (size_t)p);
    }
    if (n >= (size_t)p + 3)
        U[p + 2] = U[p + 1]; /* a double interior knot */
}

static void check_surface(int p, int q, size_t nu, size_t nv, int rational)
{
    double *U = malloc((nu + (size_t)p + 1) * sizeof(double));
    double *V = malloc((nv + (size_t)q + 1) * sizeof(double));
    double *P = malloc(3 * nu * nv * sizeof(double)), *W = malloc(nu * nv * sizeof(double));
    assert_true(U && V && P && W);
    knots(p, nu, U);
    knots(q, nv, V);
    for (size_t i = 0; i < 3 * nu * nv; i++)
        P[i] = 4.0 * urand() - 2.0;
    for (size_t i = 0; i < nu * nv; i++)
        W[i] = 0.25 + 2.0 * urand();
    geom_nurbs_surface s = {p, q, nu, nv, U, V, P, rational ? W : NULL};
    enum { N = 1037 };
    double *uv = malloc(2 * N * sizeof(double)), *out = malloc(3 * N * sizeof(double));
    int32_t *st = malloc(N * sizeof(int32_t));
    assert_true(uv && out && st);
    static const double special[] = {NAN, INFINITY, -INFINITY, -0.0, 1.0, -1e-300, 1.5};
    for (size_t i = 0; i < 2 * N; i++) {
        uv[i] = 1.2 * urand() - 0.1;
        if (i % 13 == 3) /* on a knot */
            uv[i] = (i & 1 ? V : U)[(size_t)(i / 13) % ((i & 1 ? nv : nu) + 1)];
        if (i % 31 == 5)
            uv[i] = special[(i / 31) % (sizeof special / sizeof special[0])];
    }
    for (unsigned flags = 0; flags < 4; flags++) {
        static const size_t counts[] = {N, 1, 15, 16, 17, 100};
        for (size_t c = 0; c < sizeof counts / sizeof counts[0]; c++) {
            size_t n = counts[c], failed = 0, nf = 0;
            assert_int_equal(geom_surface_eval_many(&s, n, uv, flags, 0, out, st, &nf), GEOM_OK);
            for (size_t i = 0; i < n; i++) {
                double o[3];
                geom_status r = geom_surface_eval(&s, uv[2 * i], uv[2 * i + 1], flags, o);
                if (r != st[i])
                    fail_msg("p=%d q=%d rational=%d row %zu (%g, %g): status %d, single %d", p,
                             q, rational, i, uv[2 * i], uv[2 * i + 1], st[i], r);
                if (r != GEOM_OK) {
                    failed++;
                    assert_true(isnan(out[3 * i]) && isnan(out[3 * i + 2]));
                    continue;
                }
                for (int d = 0; d < 3; d++)
                    if (!same_bits_or_nan(o[d], out[3 * i + d]))
                        fail_msg("p=%d q=%d rational=%d flags=%u row %zu (%.17g, %.17g): "
                                 "batch %.17g, single %.17g",
                                 p, q, rational, flags, i, uv[2 * i], uv[2 * i + 1],
                                 out[3 * i + d], o[d]);
            }
            assert_int_equal(nf, failed);
        }
    }
    free(U);
    free(V);
    free(P);
    free(W);
    free(uv);
    free(out);
    free(st);
}

static void test_surface_eval_many_bitwise(void **state)
{
    (void)state;
    for (int rational = 0; rational < 2; rational++) {
        check_surface(3, 3, 4, 4, rational); /* one bicubic Bezier patch */
        check_surface(1, 1, 2, 3, rational);
        check_surface(2, 3, 6, 5, rational);
        check_surface(4, 2, 9, 7, rational);
        check_surface(3, 1, 12, 2, rational);
        check_surface(9, 2, 10, 4, rational); /* above the block kernel: point by point */
    }
}

static void test_surface_eval_many_bad_input(void **state)
{
    (void)state;
    double uv[2] = {0.5, 0.5}, out[3];
    int32_t st = 0;
    size_t nf = 7;
    assert_int_equal(geom_surface_eval_many(NULL, 1, uv, 0, 0, out, &st, &nf),
                     GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_surface_eval_many(NULL, 0, uv, 0, 0, out, &st, &nf), GEOM_OK);
    assert_int_equal(nf, 0);
    /* an invalid surface: every row fails as geom_surface_eval does */
    double U[4] = {0, 0, 1, 1}, P[12] = {0};
    geom_nurbs_surface s = {0, 1, 2, 2, U, U, P, NULL};
    assert_int_equal(geom_surface_eval_many(&s, 1, uv, 0, 0, out, &st, &nf), GEOM_OK);
    assert_int_equal(st, GEOM_ERR_INVALID_ARG);
    assert_int_equal(nf, 1);
    assert_true(isnan(out[0]));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_surface_eval_many_bitwise),
        cmocka_unit_test(test_surface_eval_many_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
