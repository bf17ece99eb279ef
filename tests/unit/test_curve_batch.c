/*
 * Batch evaluation and the polyline estimate of the curve module:
 *  - geom_curve_nurbs_eval_many gives bitwise geom_curve_nurbs_eval's point
 *    and status for every row (random polynomial and rational curves of
 *    degree 1-9 in 1-4 dimensions, parameters at knots, outside the domain,
 *    NaN and Inf, every flag; blocks of one span and of mixed spans);
 *  - geom_curve_nurbs_polyline_estimate is at least the count of
 *    geom_curve_nurbs_polyline (brute force) for polynomial curves, within
 *    the documented factor in 2-4D, and refuses what the polyline refuses.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "geom/curve.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static uint64_t rng_state = 88172645463325252ull;

static double urand(void) /* [0, 1) */
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) * 0x1p-53;
}

typedef struct rcurve {
    double knots[32], points[4 * 20], weights[20];
    geom_nurbs_curve c;
} rcurve;

static void random_curve(rcurve *r, int p, size_t n, size_t dim, int rational)
{
    size_t m = n + (size_t)p + 1;
    for (size_t i = 0; i < m; ++i) {
        if (i <= (size_t)p)
            r->knots[i] = 0.0;
        else if (i >= n)
            r->knots[i] = 1.0;
        else
            r->knots[i] = urand();
    }
    /* sort the interior knots (insertion), one of them doubled */
    for (size_t i = (size_t)p + 1; i < n; ++i)
        for (size_t j = i; j > (size_t)p + 1 && r->knots[j - 1] > r->knots[j]; --j) {
            double t = r->knots[j];
            r->knots[j] = r->knots[j - 1];
            r->knots[j - 1] = t;
        }
    if (n > (size_t)p + 2)
        r->knots[p + 2] = r->knots[p + 1];
    for (size_t i = 0; i < n * dim; ++i)
        r->points[i] = 4.0 * urand() - 2.0;
    for (size_t i = 0; i < n; ++i)
        r->weights[i] = 0.25 + 3.0 * urand();
    memset(&r->c, 0, sizeof r->c);
    r->c.degree = p;
    r->c.n = n;
    r->c.dim = dim;
    r->c.knots = r->knots;
    r->c.points = r->points;
    r->c.weights = rational ? r->weights : NULL;
}

static void test_eval_many_bitwise(void **state)
{
    (void)state;
    enum { NU = 700 };
    static double u[NU], out[NU * 4];
    int32_t status[NU];
    for (int trial = 0; trial < 120; ++trial) {
        int p = 1 + trial % 9;
        size_t dim = 1 + (size_t)(trial % 4), n = (size_t)p + 1 + (size_t)(trial % 7);
        rcurve r;
        random_curve(&r, p, n, dim, trial % 3 == 0);
        size_t m = n + (size_t)p + 1, nu = 0;
        for (size_t i = 0; i < m; ++i)
            u[nu++] = r.knots[i];
        u[nu++] = NAN;
        u[nu++] = INFINITY;
        u[nu++] = -0.25;
        u[nu++] = 1.5;
        while (nu < 300)
            u[nu++] = urand() * 1.2 - 0.1; /* mixed spans, some outside */
        double u0 = 0.3 + 0.01 * urand();
        while (nu < NU) /* long runs in one span */
            u[nu++] = u0 + 1e-6 * urand();
        for (unsigned flags = 0; flags < 4; ++flags) {
            size_t failed = 0, want_failed = 0;
            assert_int_equal(geom_curve_nurbs_eval_many(&r.c, nu, u, flags, out, status, &failed),
                             GEOM_OK);
            for (size_t i = 0; i < nu; ++i) {
                double one[4];
                geom_status st = geom_curve_nurbs_eval(&r.c, u[i], flags, one);
                assert_int_equal(status[i], st);
                if (st != GEOM_OK) {
                    ++want_failed;
                    assert_true(isnan(out[i * dim]));
                    continue;
                }
                assert_memory_equal(one, out + i * dim, dim * sizeof(double));
            }
            assert_int_equal(failed, want_failed);
        }
    }
}

static void test_eval_many_args(void **state)
{
    (void)state;
    rcurve r;
    random_curve(&r, 3, 6, 3, 0);
    double u = 0.5, out[3];
    size_t failed = 7;
    assert_int_equal(geom_curve_nurbs_eval_many(&r.c, 0, NULL, 0, NULL, NULL, &failed), GEOM_OK);
    assert_int_equal(failed, 0);
    assert_int_equal(geom_curve_nurbs_eval_many(NULL, 1, &u, 0, out, NULL, NULL),
                     GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_curve_nurbs_eval_many(&r.c, 1, NULL, 0, out, NULL, NULL),
                     GEOM_ERR_INVALID_ARG);
    /* a degree above the blocked path's goes point by point, same answer */
    rcurve h;
    random_curve(&h, 12, 14, 2, 1);
    double many[2 * 40], one[2];
    double us[40];
    for (int i = 0; i < 40; ++i)
        us[i] = urand();
    assert_int_equal(geom_curve_nurbs_eval_many(&h.c, 40, us, 0, many, NULL, &failed), GEOM_OK);
    assert_int_equal(failed, 0);
    for (int i = 0; i < 40; ++i) {
        assert_int_equal(geom_curve_nurbs_eval(&h.c, us[i], 0, one), GEOM_OK);
        assert_memory_equal(one, many + 2 * i, sizeof one);
    }
}

static size_t polyline_count(const geom_nurbs_curve *c, double tol, int method)
{
    geom_curve_polyline_options o = {tol, method, (size_t)1 << 26};
    size_t n = 0;
    assert_int_equal(geom_curve_nurbs_polyline(c, &o, NULL, NULL, 0, &n, NULL, NULL), GEOM_OK);
    return n;
}

static void test_estimate_bounds_count(void **state)
{
    (void)state;
    const double tols[] = {0.0, 1e-1, 1e-3, 1e-6};
    double worst = 0.0;
    for (int trial = 0; trial < 150; ++trial) {
        int p = 1 + trial % 5;
        size_t dim = 2 + (size_t)(trial % 3), n = (size_t)p + 1 + (size_t)(trial % 6);
        rcurve r;
        random_curve(&r, p, n, dim, 0);
        for (int t = 0; t < 4; ++t)
            for (int method = GEOM_ERROR_BOUND; method <= GEOM_ERROR_SAMPLED; ++method) {
                geom_curve_polyline_options o = {tols[t], method, 0};
                double est = -1.0;
                int is_bound = 0;
                assert_int_equal(
                    geom_curve_nurbs_polyline_estimate(&r.c, &o, &est, &is_bound, NULL), GEOM_OK);
                assert_int_equal(is_bound, 1);
                size_t got = polyline_count(&r.c, tols[t], method);
                assert_true(est >= (double)got);
                worst = fmax(worst, est / (double)got);
            }
    }
    /* the documented spread in 2-4D: at most a few times the count */
    assert_true(worst < 8.0);
    /* degree 1: one piece per span, and each span's first point counted
     * (a jump would repeat it): 2 per span for the 4 control points made */
    double line_pts[] = {0, 0, 1, 2, 3, 1, 4, 4};
    double line_knots[] = {0, 0, 0.2, 0.7, 1, 1};
    geom_nurbs_curve line = {1, 4, 2, line_knots, line_pts, NULL};
    double est;
    assert_int_equal(geom_curve_nurbs_polyline_estimate(&line, NULL, &est, NULL, NULL), GEOM_OK);
    assert_true(est == 6.0);
    assert_int_equal(polyline_count(&line, 0.0, 0), 4);
}

static void test_estimate_edges(void **state)
{
    (void)state;
    rcurve r;
    random_curve(&r, 3, 6, 3, 0);
    double est = 0.0;
    geom_diag d;
    geom_diag_clear(&d);
    assert_int_equal(geom_curve_nurbs_polyline_estimate(NULL, NULL, &est, NULL, &d),
                     GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_curve_nurbs_polyline_estimate(&r.c, NULL, NULL, NULL, NULL),
                     GEOM_ERR_INVALID_ARG);
    geom_curve_polyline_options bad = {-1.0, 0, 0};
    assert_int_equal(geom_curve_nurbs_polyline_estimate(&r.c, &bad, &est, NULL, NULL),
                     GEOM_ERR_INVALID_ARG);
    bad.tolerance = NAN;
    assert_int_equal(geom_curve_nurbs_polyline_estimate(&r.c, &bad, &est, NULL, NULL),
                     GEOM_ERR_INVALID_ARG);
    /* a NaN control point is refused by validation, as by the polyline */
    r.points[4] = NAN;
    assert_int_equal(geom_curve_nurbs_polyline_estimate(&r.c, NULL, &est, NULL, NULL),
                     GEOM_ERR_INVALID_ARG);
    /* huge coordinates: finite, and still a bound */
    random_curve(&r, 3, 6, 2, 0);
    for (size_t i = 0; i < 12; ++i)
        r.points[i] *= 1e300;
    int is_bound = 0;
    assert_int_equal(geom_curve_nurbs_polyline_estimate(&r.c, NULL, &est, &is_bound, NULL),
                     GEOM_OK);
    assert_true(isfinite(est) && is_bound);
    assert_true(est >= (double)polyline_count(&r.c, 0.0, 0));
    /* a tolerance below rounding: the depth limit, never an underestimate */
    random_curve(&r, 3, 4, 2, 0);
    geom_curve_polyline_options tiny = {1e-300, 0, 0};
    assert_int_equal(geom_curve_nurbs_polyline_estimate(&r.c, &tiny, &est, NULL, NULL), GEOM_OK);
    assert_true(est == 1.0 + ldexp(1.0, 50));
    /* rational: an estimate, flagged as such (the unit circle's count is
     * within 20% at 1e-3) */
    double s = sqrt(0.5);
    double cp[] = {1, 0, 1, 1, 0, 1, -1, 1, -1, 0, -1, -1, 0, -1, 1, -1, 1, 0};
    double ck[] = {0, 0, 0, .25, .25, .5, .5, .75, .75, 1, 1, 1};
    double cw[] = {1, s, 1, s, 1, s, 1, s, 1};
    geom_nurbs_curve circle = {2, 9, 2, ck, cp, cw};
    geom_curve_polyline_options o = {1e-3, 0, 0};
    assert_int_equal(geom_curve_nurbs_polyline_estimate(&circle, &o, &est, &is_bound, NULL),
                     GEOM_OK);
    assert_int_equal(is_bound, 0);
    size_t got = polyline_count(&circle, 1e-3, 0);
    assert_true(est >= (double)got && est <= 1.2 * (double)got);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_eval_many_bitwise),
        cmocka_unit_test(test_eval_many_args),
        cmocka_unit_test(test_estimate_bounds_count),
        cmocka_unit_test(test_estimate_edges),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
