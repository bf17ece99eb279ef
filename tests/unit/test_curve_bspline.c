/* Curve module: B-spline basis functions, span rules, evaluation and
 * derivatives of B-spline and NURBS curves, validation, periodic curves.
 * References: The NURBS Book Ex. 2.3/2.4 values (checked against the
 * closed-form basis polynomials), polynomial reproduction through blossoms
 * (closed forms), finite differences with Richardson extrapolation. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "geom/curve.h"

#include <float.h>
#include <math.h>
#include <string.h>

static void assert_near(double got, double want, double tol)
{
    if (!(fabs(got - want) <= tol))
        fail_msg("got %.17g want %.17g (diff %.3g, tol %g)", got, want, fabs(got - want), tol);
}

/* NURBS Book Ex. 2.3: p = 2, U = {0,0,0,1,2,3,4,4,5,5,5}, u = 5/2 lies in
 * span 4 and N_{2,2} = 1/8, N_{3,2} = 6/8, N_{4,2} = 1/8. On [2, 3] the
 * three functions are (3-u)^2/2, (u-1)(3-u)/2 + (4-u)(u-2)/2, (u-2)^2/2, so
 * their first derivatives are -1/2, 0, 1/2 (Ex. 2.4) and second 1, -2, 1. */
static const double EX23_U[11] = {0, 0, 0, 1, 2, 3, 4, 4, 5, 5, 5};

static void test_ex23_basis(void **state)
{
    (void)state;
    double N[3];
    size_t span = 0;
    assert_int_equal(geom_curve_bspline_basis(2, 8, EX23_U, 2.5, 0, &span, N), GEOM_OK);
    assert_int_equal(span, 4);
    assert_near(N[0], 1.0 / 8, 2e-16);
    assert_near(N[1], 6.0 / 8, 2e-16);
    assert_near(N[2], 1.0 / 8, 2e-16);
    double D[4 * 3];
    assert_int_equal(geom_curve_bspline_basis_derivs(2, 8, EX23_U, 2.5, 3, 0, &span, D), GEOM_OK);
    assert_int_equal(span, 4);
    const double want[4][3] = {{0.125, 0.75, 0.125}, {-0.5, 0, 0.5}, {1, -2, 1}, {0, 0, 0}};
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 3; ++j)
            assert_near(D[k * 3 + j], want[k][j], 1e-15);
    /* the closed forms over the whole span [2, 3] */
    for (int i = 0; i <= 64; ++i) {
        double u = 2.0 + i / 64.0;
        if (u == 3.0)
            break;
        assert_int_equal(geom_curve_bspline_basis_derivs(2, 8, EX23_U, u, 1, 0, &span, D), GEOM_OK);
        assert_near(D[0], 0.5 * (3 - u) * (3 - u), 1e-15);
        assert_near(D[1], 0.5 * (u - 1) * (3 - u) + 0.5 * (4 - u) * (u - 2), 1e-15);
        assert_near(D[2], 0.5 * (u - 2) * (u - 2), 1e-15);
        assert_near(D[3], -(3 - u), 1e-15);
        assert_near(D[5], u - 2, 1e-15);
    }
}

static void test_span_rules(void **state)
{
    (void)state;
    size_t k;
    const struct {
        double u;
        unsigned flags;
        size_t span;
    } cases[] = {
        {0.0, 0, 2}, {0.0, GEOM_CURVE_LEFT_LIMIT, 2}, {0.5, 0, 2},
        {1.0, 0, 3}, {1.0, GEOM_CURVE_LEFT_LIMIT, 2}, {3.99, 0, 5},
        {4.0, 0, 7}, {4.0, GEOM_CURVE_LEFT_LIMIT, 5}, {4.5, GEOM_CURVE_LEFT_LIMIT, 7},
        {5.0, 0, 7}, {5.0, GEOM_CURVE_LEFT_LIMIT, 7},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        assert_int_equal(geom_curve_bspline_find_span(2, 8, EX23_U, cases[i].u, cases[i].flags, &k),
                         GEOM_OK);
        if (k != cases[i].span)
            fail_msg("u = %g flags %u: span %zu, want %zu", cases[i].u, cases[i].flags, k,
                     cases[i].span);
    }
    assert_int_equal(geom_curve_bspline_find_span(2, 8, EX23_U, 5.5, 0, &k), GEOM_ERR_DOMAIN);
    assert_int_equal(geom_curve_bspline_find_span(2, 8, EX23_U, -1e-300, 0, &k), GEOM_ERR_DOMAIN);
    assert_int_equal(geom_curve_bspline_find_span(2, 8, EX23_U, NAN, 0, &k), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_curve_bspline_find_span(2, 8, EX23_U, INFINITY, 0, &k),
                     GEOM_ERR_INVALID_ARG);
    /* wrap: 5 + 2.5 reduces to 2.5, -2.5 to 2.5, 5 with the left flag stays at 5 */
    assert_int_equal(geom_curve_bspline_find_span(2, 8, EX23_U, 7.5, GEOM_CURVE_WRAP, &k), GEOM_OK);
    assert_int_equal(k, 4);
    assert_int_equal(geom_curve_bspline_find_span(2, 8, EX23_U, -2.5, GEOM_CURVE_WRAP, &k),
                     GEOM_OK);
    assert_int_equal(k, 4);
    assert_int_equal(geom_curve_bspline_find_span(2, 8, EX23_U, 10.0,
                                                  GEOM_CURVE_WRAP | GEOM_CURVE_LEFT_LIMIT, &k),
                     GEOM_OK);
    assert_int_equal(k, 7);
}

static uint64_t rng = 0x243f6a8885a308d3ull;
static double urand(void) /* [0, 1) */
{
    uint64_t z = (rng += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return (double)(z >> 11) * 0x1.0p-53;
}

static void test_partition_of_unity(void **state)
{
    (void)state;
    for (int p = 1; p <= 7; ++p) {
        double U[40];
        size_t n = 12, m = n + (size_t)p + 1;
        U[0] = 0.0;
        int run = 1;
        for (size_t i = 1; i < m; ++i) { /* random nondecreasing, runs <= p */
            int rep = urand() < 0.2 && run < p;
            U[i] = U[i - 1] + (rep ? 0.0 : 0.05 + urand());
            run = rep ? run + 1 : 1;
        }
        for (int t = 0; t < 200; ++t) {
            double u = U[p] + urand() * (U[n] - U[p]);
            double N[8], D[3 * 8];
            size_t k;
            if (geom_curve_bspline_basis(p, n, U, u, 0, &k, N) != GEOM_OK)
                continue;
            double s = 0.0;
            for (int j = 0; j <= p; ++j) {
                assert_true(N[j] >= -1e-15);
                s += N[j];
            }
            assert_near(s, 1.0, 8 * DBL_EPSILON);
            assert_int_equal(geom_curve_bspline_basis_derivs(p, n, U, u, 2, 0, &k, D), GEOM_OK);
            double s1 = 0.0, s2 = 0.0, scale = 0.0;
            for (int j = 0; j <= p; ++j) {
                assert_near(D[j], N[j], 4 * DBL_EPSILON); /* A2.3 row 0 == A2.2 */
                s1 += D[(p + 1) + j];
                s2 += D[2 * (p + 1) + j];
                scale += fabs(D[(p + 1) + j]) + fabs(D[2 * (p + 1) + j]);
            }
            assert_near(s1, 0.0, 64 * DBL_EPSILON * scale); /* d/du of the sum 1 */
            assert_near(s2, 0.0, 64 * DBL_EPSILON * scale);
        }
    }
}

/* Blossom of y = a0 + a1 u + a2 u^2 + a3 u^3 (symmetric, multi-affine). */
static double blossom3(const double c[4], double x1, double x2, double x3)
{
    return c[0] + c[1] * (x1 + x2 + x3) / 3.0 + c[2] * (x1 * x2 + x1 * x3 + x2 * x3) / 3.0 +
           c[3] * x1 * x2 * x3;
}

/* A cubic B-spline reproducing (u, u^3): control points are blossom values
 * at consecutive knot triples; its derivatives are (1, 3u^2), (0, 6u),
 * (0, 6), 0. Clamped and unclamped knot vectors, multiplicities 1..3. */
static void check_cubic_reproduction(const double *U, size_t n)
{
    double P[2 * 32];
    const double cx[4] = {0, 1, 0, 0}, cy[4] = {0, 0, 0, 1};
    for (size_t i = 0; i < n; ++i) {
        P[2 * i] = blossom3(cx, U[i + 1], U[i + 2], U[i + 3]);
        P[2 * i + 1] = blossom3(cy, U[i + 1], U[i + 2], U[i + 3]);
    }
    geom_nurbs_curve c = {3, n, 2, U, P, NULL};
    assert_int_equal(geom_curve_nurbs_validate(&c, n + 4, NULL), GEOM_OK);
    double a = U[3], b = U[n];
    for (int i = 0; i <= 1000; ++i) {
        double u = a + (b - a) * i / 1000.0;
        if (i == 1000)
            u = b;
        double d[5 * 2];
        for (unsigned flags = 0; flags <= GEOM_CURVE_LEFT_LIMIT; ++flags) {
            assert_int_equal(geom_curve_nurbs_derivs(&c, u, 4, flags, d), GEOM_OK);
            double sc = 1.0 + fabs(u) * fabs(u) * fabs(u);
            assert_near(d[0], u, 1e-15 * sc);
            assert_near(d[1], u * u * u, 4e-15 * sc);
            assert_near(d[2], 1.0, 1e-13);
            assert_near(d[3], 3 * u * u, 1e-13 * sc);
            assert_near(d[4], 0.0, 1e-12);
            assert_near(d[5], 6 * u, 1e-12 * sc);
            assert_near(d[6], 0.0, 1e-10);
            assert_near(d[7], 6.0, 1e-10 * sc);
            assert_near(d[8], 0.0, 0.0); /* order 4 > degree: exactly zero */
            assert_near(d[9], 0.0, 0.0);
            double pt[2];
            assert_int_equal(geom_curve_nurbs_eval(&c, u, flags, pt), GEOM_OK);
            assert_near(pt[0], d[0], 2e-16 * sc);
            assert_near(pt[1], d[1], 2e-16 * sc);
        }
    }
}

static void test_polynomial_reproduction(void **state)
{
    (void)state;
    const double clamped[] = {-1, -1, -1, -1, -0.25, 0.5, 0.5, 1.25, 1.25, 1.25, 3, 3, 3, 3};
    check_cubic_reproduction(clamped, sizeof clamped / sizeof clamped[0] - 4);
    const double unclamped[] = {0, 0.5, 1, 1.75, 2, 2, 3.5, 4, 4.25, 5, 6, 7};
    check_cubic_reproduction(unclamped, sizeof unclamped / sizeof unclamped[0] - 4);
}

/* A rational cubic with uneven weights; derivatives of orders 1..3 against
 * central differences refined by one Richardson step (error O(h^4)). */
static void test_derivs_vs_richardson(void **state)
{
    (void)state;
    const double U[] = {0, 0, 0, 0, 0.3, 0.45, 0.7, 1, 1, 1, 1};
    const double P[] = {0, 0, 1, 2, 2.5, -0.5, 3, 1, 4, 2.5, 3.5, -1, 5, 0.5};
    const double W[] = {1, 0.5, 2.5, 0.8, 1.7, 3.0, 1};
    geom_nurbs_curve c = {3, 7, 2, U, P, W};
    assert_int_equal(geom_curve_nurbs_validate(&c, 11, NULL), GEOM_OK);
    const double us[] = {0.1, 0.2, 0.37, 0.5, 0.6, 0.85, 0.95};
    for (size_t t = 0; t < sizeof us / sizeof us[0]; ++t) {
        double u = us[t], d[4 * 2];
        assert_int_equal(geom_curve_nurbs_derivs(&c, u, 3, 0, d), GEOM_OK);
        for (int order = 1; order <= 3; ++order) {
            double h = 2e-4; /* measured: truncation ~1e-11, rounding ~1e-12 */
            double est[2][2];
            for (int level = 0; level < 2; ++level) {
                double hh = level ? h / 2 : h;
                /* central difference of the (order-1)-th derivative */
                double a[4 * 2], b[4 * 2];
                assert_int_equal(geom_curve_nurbs_derivs(&c, u + hh, order - 1, 0, a), GEOM_OK);
                assert_int_equal(geom_curve_nurbs_derivs(&c, u - hh, order - 1, 0, b), GEOM_OK);
                for (int k = 0; k < 2; ++k)
                    est[level][k] = (a[2 * (order - 1) + k] - b[2 * (order - 1) + k]) / (2 * hh);
            }
            for (int k = 0; k < 2; ++k) {
                double rich = (4 * est[1][k] - est[0][k]) / 3;
                double want = d[2 * order + k];
                assert_near(rich, want, 1e-8 * (1 + fabs(want)));
            }
        }
    }
}

static void test_validate(void **state)
{
    (void)state;
    double U[] = {0, 0, 0, 0.5, 1, 1, 1};
    double P[] = {0, 0, 1, 1, 2, 0, 3, 1};
    double W[] = {1, 1, 1, 1};
    geom_nurbs_curve c = {2, 4, 2, U, P, W};
    geom_diag d;
    assert_int_equal(geom_curve_nurbs_validate(&c, 7, &d), GEOM_OK);
    assert_int_equal(geom_curve_nurbs_validate(NULL, 7, &d), GEOM_ERR_INVALID_ARG);
    /* count that does not match n + p + 1 */
    assert_int_equal(geom_curve_nurbs_validate(&c, 8, &d), GEOM_ERR_INVALID_ARG);
    assert_non_null(strstr(d.message, "n + p + 1"));
    assert_int_equal(d.status, GEOM_ERR_INVALID_ARG);
    /* decreasing knots */
    U[3] = -0.5;
    assert_int_equal(geom_curve_nurbs_validate(&c, 7, &d), GEOM_ERR_INVALID_ARG);
    assert_non_null(strstr(d.message, "decrease"));
    U[3] = 0.5;
    /* weights <= 0 and non-finite */
    W[2] = 0.0;
    assert_int_equal(geom_curve_nurbs_validate(&c, 7, &d), GEOM_ERR_INVALID_ARG);
    assert_non_null(strstr(d.message, "weight 2"));
    W[2] = -1.0;
    assert_int_equal(geom_curve_nurbs_validate(&c, 7, &d), GEOM_ERR_INVALID_ARG);
    W[2] = NAN;
    assert_int_equal(geom_curve_nurbs_validate(&c, 7, &d), GEOM_ERR_INVALID_ARG);
    assert_non_null(strstr(d.message, "not finite"));
    W[2] = INFINITY;
    assert_int_equal(geom_curve_nurbs_validate(&c, 7, &d), GEOM_ERR_INVALID_ARG);
    W[2] = 1.0;
    /* non-finite point and knot */
    P[3] = NAN;
    assert_int_equal(geom_curve_nurbs_validate(&c, 7, &d), GEOM_ERR_INVALID_ARG);
    assert_non_null(strstr(d.message, "control point 1"));
    P[3] = 1.0;
    U[3] = INFINITY;
    assert_int_equal(geom_curve_nurbs_validate(&c, 7, &d), GEOM_ERR_INVALID_ARG);
    U[3] = 0.5;
    /* interior multiplicity above degree + 1: p = 1, a knot repeated 3 times */
    double U1[] = {0, 0, 0.5, 0.5, 0.5, 1, 1};
    double P1[] = {0, 1, 2, 3, 4};
    geom_nurbs_curve c1 = {1, 5, 1, U1, P1, NULL};
    assert_int_equal(geom_curve_nurbs_validate(&c1, 7, &d), GEOM_ERR_INVALID_ARG);
    assert_non_null(strstr(d.message, "multiplicity"));
    /* multiplicity degree + 1 inside is allowed (a jump) */
    double U2[] = {0, 0, 0.5, 0.5, 1, 1};
    geom_nurbs_curve c2 = {1, 4, 1, U2, P1, NULL};
    assert_int_equal(geom_curve_nurbs_validate(&c2, 6, &d), GEOM_OK);
    /* empty domain, too few points, bad degree and dimension */
    double U3[] = {0, 0, 0, 0, 0, 0, 0};
    c.knots = U3;
    assert_int_equal(geom_curve_nurbs_validate(&c, 7, &d), GEOM_ERR_INVALID_ARG);
    c.knots = U;
    c.n = 2;
    assert_int_equal(geom_curve_nurbs_validate(&c, 5, &d), GEOM_ERR_INVALID_ARG);
    c.n = 4;
    c.degree = 0;
    assert_int_equal(geom_curve_nurbs_validate(&c, 5, &d), GEOM_ERR_INVALID_ARG);
    c.degree = 2;
    c.dim = 5;
    assert_int_equal(geom_curve_nurbs_validate(&c, 7, &d), GEOM_ERR_INVALID_ARG);
    c.dim = 2;
    assert_int_equal(geom_curve_nurbs_validate(&c, 7, &d), GEOM_OK);
}

static void test_eval_args(void **state)
{
    (void)state;
    double U[] = {0, 0, 0, 0.5, 1, 1, 1};
    double P[] = {0, 0, 1, 1, 2, 0, 3, 1};
    geom_nurbs_curve c = {2, 4, 2, U, P, NULL};
    double out[6];
    assert_int_equal(geom_curve_nurbs_eval(&c, 1.5, 0, out), GEOM_ERR_DOMAIN);
    assert_int_equal(geom_curve_nurbs_eval(&c, -0.1, 0, out), GEOM_ERR_DOMAIN);
    assert_int_equal(geom_curve_nurbs_eval(&c, NAN, 0, out), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_curve_nurbs_eval(&c, -INFINITY, GEOM_CURVE_WRAP, out),
                     GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_curve_nurbs_derivs(&c, 0.5, -1, 0, out), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_curve_nurbs_eval(NULL, 0.5, 0, out), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_curve_nurbs_eval(&c, 0.5, 0, NULL), GEOM_ERR_INVALID_ARG);
    double u0, u1;
    assert_int_equal(geom_curve_nurbs_domain(&c, &u0, &u1), GEOM_OK);
    assert_true(u0 == 0.0 && u1 == 1.0);
    /* clamped ends are exact control points */
    assert_int_equal(geom_curve_nurbs_eval(&c, 0.0, 0, out), GEOM_OK);
    assert_true(out[0] == 0.0 && out[1] == 0.0);
    assert_int_equal(geom_curve_nurbs_eval(&c, 1.0, 0, out), GEOM_OK);
    assert_true(out[0] == 3.0 && out[1] == 1.0);
}

/* Periodic curves: closed and C^{p-1} at the seam; wrap reduces any u. */
static void test_periodic(void **state)
{
    (void)state;
    const double pts[] = {0, 0, 0.7, 1, 0, 1.6, 1.2, 2.2, 2.2, 0.8, 1.4, -0.6};
    const double w[] = {1, 2, 0.5, 1.5, 1, 3};
    for (int p = 1; p <= 4; ++p) {
        for (int rational = 0; rational < 2; ++rational) {
            double U[6 + 2 * 4 + 1], P[(6 + 4) * 2], W[6 + 4];
            geom_nurbs_curve c;
            assert_int_equal(
                geom_curve_nurbs_periodic(p, 6, 2, pts, rational ? w : NULL, U, P, W, &c), GEOM_OK);
            assert_int_equal(c.n, 6 + (size_t)p);
            assert_int_equal(geom_curve_nurbs_validate(&c, c.n + (size_t)p + 1, NULL), GEOM_OK);
            double u0, u1;
            geom_curve_nurbs_domain(&c, &u0, &u1);
            assert_near(u0, 0.0, 0.0);
            assert_near(u1, 1.0, 1e-15);
            double a[5 * 2], b[5 * 2];
            assert_int_equal(geom_curve_nurbs_derivs(&c, u0, p, 0, a), GEOM_OK);
            assert_int_equal(geom_curve_nurbs_derivs(&c, u1, p, GEOM_CURVE_LEFT_LIMIT, b), GEOM_OK);
            for (int k = 0; k < p; ++k) /* C^{p-1} */
                for (int d = 0; d < 2; ++d)
                    assert_near(a[2 * k + d], b[2 * k + d],
                                1e-12 * (1 + fabs(a[2 * k + d])) * pow(10.0, k));
            double x[2], y[2];
            for (int i = 0; i < 50; ++i) {
                double u = urand();
                assert_int_equal(geom_curve_nurbs_eval(&c, u, 0, x), GEOM_OK);
                assert_int_equal(geom_curve_nurbs_eval(&c, u + 3.0, GEOM_CURVE_WRAP, y), GEOM_OK);
                assert_near(y[0], x[0], 1e-14);
                assert_near(y[1], x[1], 1e-14);
                assert_int_equal(geom_curve_nurbs_eval(&c, u - 2.0, GEOM_CURVE_WRAP, y), GEOM_OK);
                assert_near(y[0], x[0], 1e-14);
                assert_near(y[1], x[1], 1e-14);
            }
            assert_int_equal(geom_curve_nurbs_eval(&c, 1.5, 0, x), GEOM_ERR_DOMAIN);
        }
    }
}

static void test_uniform_knots(void **state)
{
    (void)state;
    double U[10];
    assert_int_equal(geom_curve_bspline_uniform_knots(GEOM_KNOTS_CLAMPED, 3, 6, U), GEOM_OK);
    const double want[10] = {0, 0, 0, 0, 1.0 / 3, 2.0 / 3, 1, 1, 1, 1};
    for (int i = 0; i < 10; ++i)
        assert_near(U[i], want[i], 0.0);
    assert_int_equal(geom_curve_bspline_uniform_knots(GEOM_KNOTS_UNCLAMPED, 3, 6, U), GEOM_OK);
    for (int i = 0; i < 10; ++i)
        assert_near(U[i], (i - 3) / 3.0, 1e-16);
    assert_int_equal(geom_curve_bspline_uniform_knots(GEOM_KNOTS_CLAMPED, 3, 3, U),
                     GEOM_ERR_INVALID_ARG);
}

/* Curvature: a circle of radius r has 1/r (signed in 2D: negative when
 * clockwise); the twisted cubic (t, t^2, t^3) as a cubic Bezier has
 * kappa = sqrt(36t^4 + 36t^2 + 4) / (1 + 4t^2 + 9t^4)^(3/2) and
 * tau = 12 / (36t^4 + 36t^2 + 4). */
static void test_curvature_torsion(void **state)
{
    (void)state;
    double U[12], P[9 * 2], W[9];
    geom_nurbs_curve c;
    const double C[2] = {0.5, -1}, X[2] = {1, 0}, Y[2] = {0, 1}, Yneg[2] = {0, -1};
    assert_int_equal(geom_curve_nurbs_circle(2, C, X, Y, 2.5, U, P, W, &c, NULL), GEOM_OK);
    for (int i = 0; i < 100; ++i) {
        double k, tau;
        assert_int_equal(geom_curve_nurbs_curvature(&c, i / 100.0, 0, &k, &tau), GEOM_OK);
        assert_near(k, 1 / 2.5, 1e-14);
        assert_near(tau, 0.0, 0.0);
    }
    assert_int_equal(geom_curve_nurbs_circle(2, C, X, Yneg, 2.5, U, P, W, &c, NULL), GEOM_OK);
    double k;
    assert_int_equal(geom_curve_nurbs_curvature(&c, 0.3, 0, &k, NULL), GEOM_OK);
    assert_near(k, -1 / 2.5, 1e-14);

    const double U3[] = {0, 0, 0, 0, 1, 1, 1, 1};
    const double P3[] = {0, 0, 0, 1.0 / 3, 0, 0, 2.0 / 3, 1.0 / 3, 0, 1, 1, 1};
    geom_nurbs_curve t3 = {3, 4, 3, U3, P3, NULL};
    for (int i = 0; i <= 20; ++i) {
        double t = i / 20.0, kk, tau;
        assert_int_equal(geom_curve_nurbs_curvature(&t3, t, 0, &kk, &tau), GEOM_OK);
        double n2 = 36 * t * t * t * t + 36 * t * t + 4;
        double s = 1 + 4 * t * t + 9 * t * t * t * t;
        assert_near(kk, sqrt(n2) / (s * sqrt(s)), 1e-14);
        assert_near(tau, 12 / n2, 1e-14);
    }
    /* torsion is not defined for 4D, and a stationary point has no curvature */
    const double Pz[] = {0, 0, 0, 0, 1, 1};
    const double Uz[] = {0, 0, 0, 1, 1, 1};
    geom_nurbs_curve z = {2, 3, 2, Uz, Pz, NULL};
    double tau;
    assert_int_equal(geom_curve_nurbs_curvature(&z, 0.0, 0, &k, &tau), GEOM_ERR_DEGENERATE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ex23_basis),
        cmocka_unit_test(test_span_rules),
        cmocka_unit_test(test_partition_of_unity),
        cmocka_unit_test(test_polynomial_reproduction),
        cmocka_unit_test(test_derivs_vs_richardson),
        cmocka_unit_test(test_validate),
        cmocka_unit_test(test_eval_args),
        cmocka_unit_test(test_periodic),
        cmocka_unit_test(test_uniform_knots),
        cmocka_unit_test(test_curvature_torsion),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
