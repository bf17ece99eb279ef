/* Curve module: rational curves and exact conics. References: the
 * rational quadratic quarter circle with weights {1, 1, 2} (The NURBS Book
 * Ex. 4.1), whose closed form is z(u) = (1 + iu)/(1 - iu), so
 * z^(k)(u) = 2 k! i^k / (1 - iu)^(k+1); the 9-point circle (A7.1) against
 * radius 1 within 4 ulp; arcs, ellipses and conics against their implicit
 * equations. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "geom/curve.h"

#include <complex.h>
#include <float.h>
#include <math.h>
#include <string.h>

#define PI 3.14159265358979323846

static void assert_near(double got, double want, double tol)
{
    if (!(fabs(got - want) <= tol))
        fail_msg("got %.17g want %.17g (diff %.3g, tol %g)", got, want, fabs(got - want), tol);
}

static void test_quarter_circle_ex41(void **state)
{
    (void)state;
    const double U[6] = {0, 0, 0, 1, 1, 1};
    const double P[6] = {1, 0, 1, 1, 0, 1};
    const double W[3] = {1, 1, 2};
    geom_nurbs_curve c = {2, 3, 2, U, P, W};
    assert_int_equal(geom_curve_nurbs_validate(&c, 6, NULL), GEOM_OK);
    /* C(1/2) = (3/5, 4/5), C'(0) = (0, 2), C'(1) = (-1, 0) */
    double d[2 * 2];
    assert_int_equal(geom_curve_nurbs_derivs(&c, 0.5, 0, 0, d), GEOM_OK);
    assert_near(d[0], 0.6, 2e-16);
    assert_near(d[1], 0.8, 2e-16);
    assert_int_equal(geom_curve_nurbs_derivs(&c, 0.0, 1, 0, d), GEOM_OK);
    assert_true(d[0] == 1 && d[1] == 0);
    assert_near(d[2], 0, 1e-15);
    assert_near(d[3], 2, 1e-15);
    assert_int_equal(geom_curve_nurbs_derivs(&c, 1.0, 1, 0, d), GEOM_OK);
    assert_true(d[0] == 0 && d[1] == 1);
    assert_near(d[2], -1, 1e-15);
    assert_near(d[3], 0, 1e-15);
    /* all orders up to 6 against z^(k) = 2 k! i^k / (1 - iu)^(k+1) */
    for (int i = 0; i <= 64; ++i) {
        double u = i / 64.0, D[7 * 2];
        assert_int_equal(geom_curve_nurbs_derivs(&c, u, 6, 0, D), GEOM_OK);
        double complex z = (1 + I * u) / (1 - I * u);
        assert_near(D[0], creal(z), 3e-16);
        assert_near(D[1], cimag(z), 3e-16);
        double fact = 1.0;
        double complex ik = 1.0;
        for (int k = 1; k <= 6; ++k) {
            fact *= k;
            ik *= I;
            double complex zk = 2.0 * fact * ik / cpow(1 - I * u, k + 1);
            double tol = 1e-13 * fact * (1 << k);
            assert_near(D[2 * k], creal(zk), tol);
            assert_near(D[2 * k + 1], cimag(zk), tol);
        }
    }
}

/* The 9-point unit circle: every point at radius 1 within 4 ulp (hypot),
 * the knots and control points as in The NURBS Book, C(0) = C(1). */
static void test_unit_circle_ulp(void **state)
{
    (void)state;
    const double O[2] = {0, 0}, X[2] = {1, 0}, Y[2] = {0, 1};
    double U[12], P[18], W[9];
    geom_nurbs_curve c;
    assert_int_equal(geom_curve_nurbs_circle(2, O, X, Y, 1.0, U, P, W, &c, NULL), GEOM_OK);
    assert_int_equal(c.n, 9);
    const double wantU[12] = {0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1};
    const double wantP[18] = {1, 0, 1, 1, 0, 1, -1, 1, -1, 0, -1, -1, 0, -1, 1, -1, 1, 0};
    for (int i = 0; i < 12; ++i)
        assert_true(U[i] == wantU[i]);
    for (int i = 0; i < 18; ++i)
        assert_true(P[i] == wantP[i]);
    for (int i = 0; i < 9; ++i)
        assert_true(W[i] == (i % 2 ? sqrt(0.5) : 1.0));
    double worst = 0.0;
    for (int i = 0; i <= 10000; ++i) {
        double u = i / 10000.0, p[2];
        assert_int_equal(geom_curve_nurbs_eval(&c, u, 0, p), GEOM_OK);
        worst = fmax(worst, fabs(hypot(p[0], p[1]) - 1.0));
    }
    if (worst > 4 * DBL_EPSILON)
        fail_msg("radius error %.3g > 4 ulp", worst);
    double a[2], b[2];
    geom_curve_nurbs_eval(&c, 0.0, 0, a);
    geom_curve_nurbs_eval(&c, 1.0, 0, b);
    assert_true(a[0] == 1 && a[1] == 0 && b[0] == 1 && b[1] == 0);
    /* the quarter points are exact */
    for (int q = 0; q < 4; ++q) {
        geom_curve_nurbs_eval(&c, q * 0.25, 0, a);
        assert_true(a[0] == wantP[4 * q] && a[1] == wantP[4 * q + 1]);
    }
    /* the angle is a monotone function of u, and the speed never vanishes */
    double prev = -1.0;
    for (int i = 0; i < 1000; ++i) {
        double d[4];
        geom_curve_nurbs_derivs(&c, i / 1000.0, 1, 0, d);
        double ang = atan2(d[1], d[0]);
        if (ang < 0)
            ang += 2 * PI;
        if (i > 0)
            assert_true(ang > prev);
        prev = ang;
        assert_true(hypot(d[2], d[3]) > 1.0);
    }
}

/* Arcs of any sweep: points on the circle, ends exact, at most 90 degrees
 * per piece; a 3D circle in a tilted plane. */
static void test_arcs(void **state)
{
    (void)state;
    const double C[3] = {1.5, -2, 0.25};
    const double X[3] = {0.6, 0.8, 0}, Y[3] = {0, 0, 1};
    const double sweeps[][2] = {{0, 0.3},   {0.2, 1.4},    {0, PI / 2},        {1, 3},
                                {-0.5, PI}, {0, 4},        {2, 7.5},           {0, 2 * PI},
                                {0, -1},    {PI, -PI / 2}, {0.1, 0.1 + 2 * PI}};
    for (size_t s = 0; s < sizeof sweeps / sizeof sweeps[0]; ++s) {
        double a0 = sweeps[s][0], a1 = sweeps[s][1], r = 2.25;
        size_t n, nk;
        assert_int_equal(geom_curve_nurbs_arc_bound(a0, a1, &n, &nk), GEOM_OK);
        size_t narcs = (size_t)ceil(fabs(a1 - a0) / (PI / 2) - 1e-12);
        assert_int_equal(n, 2 * narcs + 1);
        double U[12], P[9 * 3], W[9];
        geom_nurbs_curve c;
        assert_int_equal(geom_curve_nurbs_arc(3, C, X, Y, r, a0, a1, U, P, W, &c, NULL), GEOM_OK);
        assert_int_equal(geom_curve_nurbs_validate(&c, nk, NULL), GEOM_OK);
        for (int i = 0; i <= 1000; ++i) {
            double u = i / 1000.0, p[3];
            assert_int_equal(geom_curve_nurbs_eval(&c, u, 0, p), GEOM_OK);
            double v[3] = {p[0] - C[0], p[1] - C[1], p[2] - C[2]};
            double x = v[0] * X[0] + v[1] * X[1], y = v[2];
            double off = v[0] * -X[1] + v[1] * X[0]; /* out of the plane */
            assert_near(hypot(x, y), r, 8e-16 * r * 4);
            assert_near(off, 0.0, 1e-15 * r);
            if (i == 0 || i == 1000) {
                double ang = i == 0 ? a0 : a1;
                assert_near(x, r * cos(ang), 4e-16 * 4 * r);
                assert_near(y, r * sin(ang), 4e-16 * 4 * r);
            }
        }
        /* the sweep is covered monotonically: the angle advances in the
         * direction of a1 - a0 by |a1 - a0| in total */
        double total = 0.0, prev = a0;
        for (int i = 1; i <= 2000; ++i) {
            double p[3];
            geom_curve_nurbs_eval(&c, i / 2000.0, 0, p);
            double v[3] = {p[0] - C[0], p[1] - C[1], p[2] - C[2]};
            double ang = atan2(v[2], v[0] * X[0] + v[1] * X[1]);
            double step = remainder(ang - prev, 2 * PI);
            assert_true((a1 - a0) * step >= 0.0);
            total += step;
            prev = ang;
        }
        assert_near(total, a1 - a0, 1e-12);
    }
    double U[12], P[27], W[9];
    geom_nurbs_curve c;
    geom_diag d;
    assert_int_equal(geom_curve_nurbs_arc(3, C, X, Y, 1.0, 0, 7, U, P, W, &c, &d), GEOM_ERR_DOMAIN);
    assert_int_equal(geom_curve_nurbs_arc(3, C, X, Y, 1.0, 1, 1, U, P, W, &c, &d), GEOM_ERR_DOMAIN);
    const double Xbad[3] = {1, 1, 0};
    assert_int_equal(geom_curve_nurbs_arc(3, C, Xbad, Y, 1.0, 0, 1, U, P, W, &c, &d),
                     GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_curve_nurbs_arc(3, C, X, Y, -1.0, 0, 1, U, P, W, &c, &d),
                     GEOM_ERR_INVALID_ARG);
}

/* Ellipse (x/a)^2 + (y/b)^2 = 1 and a sheared ellipse (non-orthogonal axes:
 * still the image of a circle under the affine map [X Y]). */
static void test_ellipse(void **state)
{
    (void)state;
    const double C[2] = {0, 0};
    const double X[2] = {3, 0}, Y[2] = {0, 0.5};
    double U[12], P[18], W[9];
    geom_nurbs_curve c;
    assert_int_equal(geom_curve_nurbs_ellipse_arc(2, C, X, Y, 0, 2 * PI, U, P, W, &c, NULL),
                     GEOM_OK);
    for (int i = 0; i <= 2000; ++i) {
        double p[2];
        geom_curve_nurbs_eval(&c, i / 2000.0, 0, p);
        assert_near(p[0] * p[0] / 9 + p[1] * p[1] / 0.25, 1.0, 8e-16);
    }
    const double Xs[2] = {2, 1}, Ys[2] = {0.5, 1.5};
    assert_int_equal(geom_curve_nurbs_ellipse_arc(2, C, Xs, Ys, -1, 2.5, U, P, W, &c, NULL),
                     GEOM_OK);
    double det = Xs[0] * Ys[1] - Xs[1] * Ys[0];
    for (int i = 0; i <= 2000; ++i) {
        double p[2];
        geom_curve_nurbs_eval(&c, i / 2000.0, 0, p);
        /* solve [X Y] (cx, sy) = p */
        double cx = (p[0] * Ys[1] - p[1] * Ys[0]) / det, sy = (Xs[0] * p[1] - Xs[1] * p[0]) / det;
        assert_near(hypot(cx, sy), 1.0, 2e-15);
    }
    const double Xp[2] = {1, 1}, Yp[2] = {2, 2};
    geom_diag d;
    assert_int_equal(geom_curve_nurbs_ellipse_arc(2, C, Xp, Yp, 0, 1, U, P, W, &c, &d),
                     GEOM_ERR_DEGENERATE);
}

/* Conics from end points, tangents and a weight or a point on the curve. */
static void test_conics(void **state)
{
    (void)state;
    const double p0[2] = {1, 0}, t0[2] = {0, 1}, p2[2] = {0, 1}, t2[2] = {-1, 0};
    double U[6], P[6], W[3];
    geom_nurbs_curve c;
    /* weight cos(45 deg): the quarter circle, middle point (1, 1) */
    assert_int_equal(geom_curve_nurbs_conic(2, p0, t0, p2, t2, NULL, sqrt(0.5), U, P, W, &c, NULL),
                     GEOM_OK);
    assert_near(P[2], 1, 1e-15);
    assert_near(P[3], 1, 1e-15);
    for (int i = 0; i <= 100; ++i) {
        double p[2];
        geom_curve_nurbs_eval(&c, i / 100.0, 0, p);
        assert_near(hypot(p[0], p[1]), 1.0, 4e-16);
    }
    /* the shoulder point of the quarter circle gives w = sqrt(2)/2, and so
     * does any other point of the arc (A7.2) */
    const double sh[2] = {sqrt(0.5), sqrt(0.5)};
    assert_int_equal(geom_curve_nurbs_conic(2, p0, t0, p2, t2, sh, 0, U, P, W, &c, NULL), GEOM_OK);
    assert_near(W[1], sqrt(0.5), 1e-15);
    const double on[2] = {cos(0.3), sin(0.3)};
    assert_int_equal(geom_curve_nurbs_conic(2, p0, t0, p2, t2, on, 0, U, P, W, &c, NULL), GEOM_OK);
    assert_near(W[1], sqrt(0.5), 1e-14);
    /* shoulder point S = M + s (P1 - M) gives w = s / (1 - s): a parabola
     * (s = 1/2, w = 1) satisfies y = x^2 for P0 = (-1, 1), P2 = (1, 1),
     * tangents (1, -2) and (1, 2) */
    const double q0[2] = {-1, 1}, u0[2] = {1, -2}, q2[2] = {1, 1}, u2[2] = {1, 2};
    const double S[2] = {0, 0}; /* M = (0, 1), P1 = (0, -1), s = 1/2 */
    assert_int_equal(geom_curve_nurbs_conic(2, q0, u0, q2, u2, S, 0, U, P, W, &c, NULL), GEOM_OK);
    assert_near(P[2], 0, 1e-15);
    assert_near(P[3], -1, 1e-15);
    assert_near(W[1], 1.0, 1e-15);
    for (int i = 0; i <= 100; ++i) {
        double p[2];
        geom_curve_nurbs_eval(&c, i / 100.0, 0, p);
        assert_near(p[1], p[0] * p[0], 1e-15);
    }
    /* hyperbola x y = 1 from (1/2, 2) to (2, 1/2): tangents (1, -4) and
     * (4, -1) meet at (0.8, 0.8); (1.25, 0.8) is a point of the arc */
    const double h0[2] = {0.5, 2}, ht0[2] = {1, -4}, h2[2] = {2, 0.5}, ht2[2] = {4, -1};
    const double hp[2] = {1.25, 0.8};
    assert_int_equal(geom_curve_nurbs_conic(2, h0, ht0, h2, ht2, hp, 0, U, P, W, &c, NULL),
                     GEOM_OK);
    assert_true(W[1] > 1.0); /* a hyperbola */
    for (int i = 0; i <= 100; ++i) {
        double p[2];
        geom_curve_nurbs_eval(&c, i / 100.0, 0, p);
        assert_near(p[0] * p[1], 1.0, 1e-14);
    }
    /* errors: parallel tangents, a point outside the control triangle */
    const double par[2] = {0, 1};
    geom_diag d;
    assert_int_equal(geom_curve_nurbs_conic(2, p0, t0, p2, par, NULL, 0.5, U, P, W, &c, &d),
                     GEOM_ERR_DEGENERATE);
    assert_non_null(strstr(d.message, "parallel"));
    const double outside[2] = {2, 2};
    assert_int_equal(geom_curve_nurbs_conic(2, p0, t0, p2, t2, outside, 0, U, P, W, &c, &d),
                     GEOM_ERR_DOMAIN);
    assert_int_equal(geom_curve_nurbs_conic(2, p0, t0, p2, t2, NULL, -1, U, P, W, &c, &d),
                     GEOM_ERR_DOMAIN);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_quarter_circle_ex41),
        cmocka_unit_test(test_unit_circle_ulp),
        cmocka_unit_test(test_arcs),
        cmocka_unit_test(test_ellipse),
        cmocka_unit_test(test_conics),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
