/* Curve module, stiff and extreme input: weights from 1e-8 to 1e8, knot
 * spans of 1e-12, interior multiplicities p (a kink) and p+1 (a jump),
 * parameters exactly at the domain ends, a degree-25 Bezier curve against
 * an exact integer reference, coordinates offset by 1e8, and NaN/Inf
 * parameters. References are closed forms, exact integer arithmetic, or
 * an independent long double Cox-de Boor evaluation. */
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

static void assert_near(double got, double want, double tol)
{
    if (!(fabs(got - want) <= tol))
        fail_msg("got %.17g want %.17g (diff %.3g, tol %g)", got, want, fabs(got - want), tol);
}

static uint64_t rng = 0xa4093822299f31d0ull;
static double urand(void) /* [0, 1) */
{
    uint64_t z = (rng += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return (double)(z >> 11) * 0x1.0p-53;
}

/* ------------------------------------------------ weights 1e-8 .. 1e8 */

/* The quarter circle z(s) = (1 + is)/(1 - is) with weights {1, 1, 2}
 * reparameterised by rho: weights {1, rho, 2 rho^2} give z(s(t)) with
 * s = rho t / (1 - t + rho t). rho = 1e-4 and 1e4 put the weights in
 * [2e-8, 1] and [1, 2e8]. */
static void test_extreme_weights_circle(void **state)
{
    (void)state;
    const double U[6] = {0, 0, 0, 1, 1, 1};
    const double P[6] = {1, 0, 1, 1, 0, 1};
    const double rhos[] = {1e-4, 1e-2, 1e2, 1e4};
    for (size_t r = 0; r < 4; ++r) {
        double rho = rhos[r];
        const double W[3] = {1, rho, 2 * rho * rho};
        geom_nurbs_curve c = {2, 3, 2, U, P, W};
        assert_int_equal(geom_curve_nurbs_validate(&c, 6, NULL), GEOM_OK);
        for (int i = 0; i <= 1000; ++i) {
            double t = i / 1000.0, d[2 * 2];
            assert_int_equal(geom_curve_nurbs_derivs(&c, t, 1, 0, d), GEOM_OK);
            double den = 1 - t + rho * t, s = rho * t / den, ds = rho / (den * den);
            double complex z = (1 + I * s) / (1 - I * s);
            double complex dz = 2 * I / ((1 - I * s) * (1 - I * s)) * ds;
            assert_near(hypot(d[0], d[1]), 1.0, 4 * DBL_EPSILON);
            assert_near(d[0], creal(z), 8 * DBL_EPSILON);
            assert_near(d[1], cimag(z), 8 * DBL_EPSILON);
            double sc = cabs(dz);
            /* relative, plus a few ulp of the O(1) terms that cancel in
             * (A' - w' C) / w where the speed is tiny */
            assert_near(d[2], creal(dz), 1e-12 * sc + 4 * DBL_EPSILON);
            assert_near(d[3], cimag(dz), 1e-12 * sc + 4 * DBL_EPSILON);
        }
    }
}

/* Independent reference: the textbook Cox-de Boor recursion in long double
 * for all basis functions, then sum N w P / sum N w. */
static long double cox(const double *U, int i, int p, long double u, size_t span)
{
    if (p == 0)
        return (size_t)i == span ? 1.0L : 0.0L;
    long double a = 0, b = 0;
    long double d1 = (long double)U[i + p] - U[i], d2 = (long double)U[i + p + 1] - U[i + 1];
    if (d1 > 0)
        a = (u - U[i]) / d1 * cox(U, i, p - 1, u, span);
    if (d2 > 0)
        b = ((long double)U[i + p + 1] - u) / d2 * cox(U, i + 1, p - 1, u, span);
    return a + b;
}

static void ref_eval(const geom_nurbs_curve *c, double u, double *out)
{
    size_t span;
    assert_int_equal(geom_curve_bspline_find_span(c->degree, c->n, c->knots, u, 0, &span), GEOM_OK);
    long double num[4] = {0, 0, 0, 0}, den = 0;
    for (size_t i = 0; i < c->n; ++i) {
        long double N = cox(c->knots, (int)i, c->degree, u, span);
        long double w = c->weights ? c->weights[i] : 1.0L;
        den += N * w;
        for (size_t d = 0; d < c->dim; ++d)
            num[d] += N * w * c->points[i * c->dim + d];
    }
    for (size_t d = 0; d < c->dim; ++d)
        out[d] = (double)(num[d] / den);
}

static void test_extreme_weights_spline(void **state)
{
    (void)state;
    const double U[] = {0, 0, 0, 0, 0.15, 0.3, 0.45, 0.6, 0.75, 1, 1, 1, 1};
    double P[9 * 3], W[9];
    for (int i = 0; i < 9; ++i) {
        for (int d = 0; d < 3; ++d)
            P[3 * i + d] = 2 * urand() - 1;
        W[i] = pow(10.0, i % 2 ? -8.0 + 2 * urand() : 6.0 + 2 * urand()); /* 1e-8 .. 1e8 */
    }
    geom_nurbs_curve c = {3, 9, 3, U, P, W};
    assert_int_equal(geom_curve_nurbs_validate(&c, 13, NULL), GEOM_OK);
    double worst = 0;
    for (int i = 0; i <= 2000; ++i) {
        double u = i / 2000.0, a[3], b[3];
        assert_int_equal(geom_curve_nurbs_eval(&c, u, 0, a), GEOM_OK);
        ref_eval(&c, u, b);
        for (int d = 0; d < 3; ++d)
            worst = fmax(worst, fabs(a[d] - b[d]));
    }
    if (worst > 8 * DBL_EPSILON)
        fail_msg("extreme weights: error %.3g vs long double reference", worst);
    /* knot insertion and degree elevation stay exact to rounding */
    double Ui[20], Pi[12 * 3], Wi[12];
    geom_nurbs_curve o;
    assert_int_equal(geom_curve_nurbs_insert_knot(&c, 0.5, 2, Ui, Pi, Wi, &o, NULL), GEOM_OK);
    for (int i = 0; i <= 500; ++i) {
        double u = i / 500.0, a[3], b[3];
        geom_curve_nurbs_eval(&c, u, 0, a);
        geom_curve_nurbs_eval(&o, u, 0, b);
        for (int d = 0; d < 3; ++d)
            assert_near(b[d], a[d], 1e-14);
    }
}

/* ------------------------------------------------------ knot spans 1e-12 */

/* The cubic reproducing (u, u^3 - u) through blossoms, with a knot span of
 * 1e-12 (and, second case, two adjacent ones): values and derivatives
 * inside and around the tiny span against the closed forms. */
static double blossom(double x1, double x2, double x3, int which)
{
    if (which == 0)
        return (x1 + x2 + x3) / 3.0;
    return x1 * x2 * x3 - (x1 + x2 + x3) / 3.0;
}

static void check_tiny(const double *U, size_t n, double lo, double hi, double dtol, double d2tol)
{
    double P[2 * 16];
    for (size_t i = 0; i < n; ++i)
        for (int w = 0; w < 2; ++w)
            P[2 * i + (size_t)w] = blossom(U[i + 1], U[i + 2], U[i + 3], w);
    geom_nurbs_curve c = {3, n, 2, U, P, NULL};
    assert_int_equal(geom_curve_nurbs_validate(&c, n + 4, NULL), GEOM_OK);
    for (int i = 0; i <= 200; ++i) {
        double u = lo + (hi - lo) * i / 200.0, d[3 * 2];
        for (unsigned f = 0; f <= GEOM_CURVE_LEFT_LIMIT; ++f) {
            assert_int_equal(geom_curve_nurbs_derivs(&c, u, 2, f, d), GEOM_OK);
            assert_near(d[0], u, 4 * DBL_EPSILON);
            assert_near(d[1], u * u * u - u, 8 * DBL_EPSILON);
            assert_near(d[2], 1.0, dtol);
            assert_near(d[3], 3 * u * u - 1, dtol);
            assert_near(d[5], 6 * u, d2tol);
        }
    }
}

static void test_tiny_spans(void **state)
{
    (void)state;
    const double a = 0.5, e = 1e-12;
    const double U1[] = {0, 0, 0, 0, 0.25, a, a + e, 0.75, 1, 1, 1, 1};
    /* measured: values 2e-16, first derivatives 4e-15, second 2e-14 */
    check_tiny(U1, 8, a - 1e-11, a + 2e-11, 1e-13, 1e-12);
    check_tiny(U1, 8, 0.0, 1.0, 1e-13, 1e-12);
    /* two adjacent tiny spans: second-derivative basis functions divide by
     * 1e-12 * 2e-12, and the cancellation leaves about 3e-3 absolute error
     * there (first derivatives stay at 3e-15) */
    const double U2[] = {0, 0, 0, 0, 0.25, a, a + e, a + 2 * e, 0.75, 1, 1, 1, 1};
    check_tiny(U2, 9, a - 1e-11, a + 3e-11, 1e-13, 3e-2);
}

/* ------------------------------------------- multiplicity p and p + 1 */

static void test_kink_and_jump(void **state)
{
    (void)state;
    /* degree 3, knot 0.5 of multiplicity 3: two Bezier pieces sharing P3 */
    const double Uk[] = {0, 0, 0, 0, 0.5, 0.5, 0.5, 1, 1, 1, 1};
    const double P[] = {0, 0, 1, 2, 2, 3, 3, 1, 5, 0, 6, 3, 7, 1, 9, 2};
    geom_nurbs_curve k = {3, 7, 2, Uk, P, NULL};
    double l[3 * 2], r[3 * 2];
    assert_int_equal(geom_curve_nurbs_derivs(&k, 0.5, 2, GEOM_CURVE_LEFT_LIMIT, l), GEOM_OK);
    assert_int_equal(geom_curve_nurbs_derivs(&k, 0.5, 2, 0, r), GEOM_OK);
    for (int d = 0; d < 2; ++d) {
        assert_true(l[d] == P[6 + d] && r[d] == P[6 + d]); /* C0: the shared point, exactly */
        assert_near(l[2 + d], 3 * (P[6 + d] - P[4 + d]) / 0.5, 1e-13);
        assert_near(r[2 + d], 3 * (P[8 + d] - P[6 + d]) / 0.5, 1e-13);
        assert_near(l[4 + d], 6 * (P[6 + d] - 2 * P[4 + d] + P[2 + d]) / 0.25, 1e-12);
        assert_near(r[4 + d], 6 * (P[10 + d] - 2 * P[8 + d] + P[6 + d]) / 0.25, 1e-12);
    }
    /* rational: C'(0.5-) = 3 (w2/w3) (P3 - P2) / 0.5 and
     * C'(0.5+) = 3 (w4/w3) (P4 - P3) / 0.5 */
    const double W[] = {1, 2, 0.5, 3, 0.25, 1, 1};
    geom_nurbs_curve kw = {3, 7, 2, Uk, P, W};
    assert_int_equal(geom_curve_nurbs_derivs(&kw, 0.5, 1, GEOM_CURVE_LEFT_LIMIT, l), GEOM_OK);
    assert_int_equal(geom_curve_nurbs_derivs(&kw, 0.5, 1, 0, r), GEOM_OK);
    for (int d = 0; d < 2; ++d) {
        assert_true(l[d] == P[6 + d] && r[d] == P[6 + d]);
        assert_near(l[2 + d], 3 * (0.5 / 3) * (P[6 + d] - P[4 + d]) / 0.5, 1e-13);
        assert_near(r[2 + d], 3 * (0.25 / 3) * (P[8 + d] - P[6 + d]) / 0.5, 1e-13);
    }
    /* multiplicity 4 = p+1: a jump from P3 to P4; one-sided derivatives */
    const double Uj[] = {0, 0, 0, 0, 0.5, 0.5, 0.5, 0.5, 1, 1, 1, 1};
    geom_nurbs_curve j = {3, 8, 2, Uj, P, NULL};
    assert_int_equal(geom_curve_nurbs_validate(&j, 12, NULL), GEOM_OK);
    assert_int_equal(geom_curve_nurbs_derivs(&j, 0.5, 1, GEOM_CURVE_LEFT_LIMIT, l), GEOM_OK);
    assert_int_equal(geom_curve_nurbs_derivs(&j, 0.5, 1, 0, r), GEOM_OK);
    for (int d = 0; d < 2; ++d) {
        assert_true(l[d] == P[6 + d]);
        assert_true(r[d] == P[8 + d]);
        assert_near(l[2 + d], 3 * (P[6 + d] - P[4 + d]) / 0.5, 1e-13);
        assert_near(r[2 + d], 3 * (P[10 + d] - P[8 + d]) / 0.5, 1e-13);
    }
    /* approaching the jump from either side converges to the right limit */
    double x[2];
    geom_curve_nurbs_eval(&j, nextafter(0.5, 0.0), 0, x);
    assert_near(x[0], P[6], 1e-14);
    geom_curve_nurbs_eval(&j, nextafter(0.5, 1.0), GEOM_CURVE_LEFT_LIMIT, x);
    assert_near(x[0], P[8], 1e-14);
}

/* -------------------------------------------------------- domain ends */

static void test_domain_ends(void **state)
{
    (void)state;
    /* clamped, rational: exact end points and C'(0) = p (w1/w0)(P1-P0)/u_{p+1} */
    const double U[] = {0, 0, 0, 0, 0.3, 0.6, 1, 1, 1, 1};
    const double P[] = {0.1, 0.7, 1.3, 2.9, 2.2, -0.4, 3.3, 1.7, 4.9, 0.3, 6.1, 2.2};
    const double W[] = {3, 0.7, 1.9, 0.2, 5, 7};
    geom_nurbs_curve c = {3, 6, 2, U, P, W};
    double d[2 * 2];
    for (unsigned f = 0; f <= GEOM_CURVE_LEFT_LIMIT; ++f) {
        assert_int_equal(geom_curve_nurbs_derivs(&c, 0.0, 1, f, d), GEOM_OK);
        assert_true(d[0] == P[0] && d[1] == P[1]);
        assert_near(d[2], 3 * (0.7 / 3) * (P[2] - P[0]) / 0.3, 1e-13);
        assert_near(d[3], 3 * (0.7 / 3) * (P[3] - P[1]) / 0.3, 1e-13);
        assert_int_equal(geom_curve_nurbs_derivs(&c, 1.0, 1, f, d), GEOM_OK);
        assert_true(d[0] == P[10] && d[1] == P[11]);
        assert_near(d[2], 3 * (5.0 / 7) * (P[10] - P[8]) / 0.4, 1e-13);
        assert_near(d[3], 3 * (5.0 / 7) * (P[11] - P[9]) / 0.4, 1e-13);
    }
    double x[2];
    assert_int_equal(geom_curve_nurbs_eval(&c, nextafter(1.0, 2.0), 0, x), GEOM_ERR_DOMAIN);
    assert_int_equal(geom_curve_nurbs_eval(&c, nextafter(0.0, -1.0), 0, x), GEOM_ERR_DOMAIN);
    /* unclamped: the ends of [u_p, u_n] reproduce the polynomial u^2 */
    const double Uu[] = {-0.5, -0.25, 0.125, 0.5, 1, 1.5, 2.5};
    double Pu[4];
    for (int i = 0; i < 4; ++i)
        Pu[i] = Uu[i + 1] * Uu[i + 2]; /* blossom of u^2 */
    geom_nurbs_curve q = {2, 4, 1, Uu, Pu, NULL};
    double v;
    assert_int_equal(geom_curve_nurbs_eval(&q, 0.125, 0, &v), GEOM_OK);
    assert_near(v, 0.125 * 0.125, 1e-17);
    assert_int_equal(geom_curve_nurbs_eval(&q, 1.0, 0, &v), GEOM_OK);
    assert_near(v, 1.0, 2e-16);
    assert_int_equal(geom_curve_nurbs_eval(&q, 1.0, GEOM_CURVE_LEFT_LIMIT, &v), GEOM_OK);
    assert_near(v, 1.0, 2e-16);
    /* knot insertion exactly at u_p of an unclamped curve */
    double Ui[8], Pi[5];
    geom_nurbs_curve o;
    assert_int_equal(geom_curve_nurbs_insert_knot(&q, 0.125, 1, Ui, Pi, NULL, &o, NULL), GEOM_OK);
    assert_int_equal(geom_curve_nurbs_eval(&o, 0.125, 0, &v), GEOM_OK);
    assert_near(v, 0.125 * 0.125, 1e-17);
}

/* --------------------------------------------- degree 25, exact reference */

__extension__ typedef __int128 i128;

/* sum_i C(n,i) (8-k)^(n-i) k^i c_i, exactly. */
static i128 bernstein_sum(int n, int k, const int64_t *c)
{
    i128 s = 0, bin = 1;
    for (int i = 0; i <= n; ++i) {
        if (i > 0)
            bin = bin * (n - i + 1) / i;
        i128 t = bin;
        for (int j = 0; j < n - i; ++j)
            t *= 8 - k;
        for (int j = 0; j < i; ++j)
            t *= k;
        s += t * c[i];
    }
    return s;
}

static void test_degree25_bezier(void **state)
{
    (void)state;
    enum { N = 25 };
    for (int trial = 0; trial < 20; ++trial) {
        int64_t c[N + 1], dc[N];
        double P[N + 1], maxp = 0;
        for (int i = 0; i <= N; ++i) {
            /* alternating signs of size up to 2^20: heavy cancellation */
            c[i] = (int64_t)((urand() * 2 - 1) * 1048576.0);
            if (trial % 2)
                c[i] = (i % 2 ? -1 : 1) * (1048576 - (int64_t)(urand() * 1000));
            P[i] = (double)c[i];
            maxp = fmax(maxp, fabs(P[i]));
        }
        for (int i = 0; i < N; ++i)
            dc[i] = c[i + 1] - c[i];
        for (int k = 0; k <= 8; ++k) {
            double t = k / 8.0, d[2];
            assert_int_equal(geom_curve_bezier_derivs(N, 1, P, t, 1, d), GEOM_OK);
            double ref = ldexp((double)bernstein_sum(N, k, c), -3 * N);
            double dref = N * ldexp((double)bernstein_sum(N - 1, k, dc), -3 * (N - 1));
            /* de Casteljau: convex combinations, error <= ~2 N eps max|P| */
            assert_near(d[0], ref, 2 * N * DBL_EPSILON * maxp);
            assert_near(d[1], dref, 4 * N * N * DBL_EPSILON * maxp);
            double e;
            assert_int_equal(geom_curve_bezier_eval(N, 1, P, t, &e), GEOM_OK);
            assert_true(e == d[0]);
            if (k == 0 || k == 8)
                assert_true(e == P[k == 0 ? 0 : N]);
        }
    }
}

/* ---------------------------------------------------- offset by 1e8 */

static void test_offset_coordinates(void **state)
{
    (void)state;
    const double U[] = {0, 0, 0, 0, 0.2, 0.5, 0.7, 1, 1, 1, 1};
    const double P[] = {0, 0, 1, 2, 2, -1, 3, 1, 4, 3, 5, 0, 6, 2};
    const double W[] = {1, 2, 0.5, 1, 3, 0.7, 1.2};
    const double off = 1e8;
    double Po[14];
    for (int i = 0; i < 14; ++i)
        Po[i] = P[i] + off;
    for (int rational = 0; rational < 2; ++rational) {
        geom_nurbs_curve c = {3, 7, 2, U, P, rational ? W : NULL};
        geom_nurbs_curve co = {3, 7, 2, U, Po, rational ? W : NULL};
        double worst0 = 0, worst1 = 0;
        for (int i = 0; i <= 1000; ++i) {
            double u = i / 1000.0, a[3 * 2], b[3 * 2];
            geom_curve_nurbs_derivs(&c, u, 2, 0, a);
            geom_curve_nurbs_derivs(&co, u, 2, 0, b);
            for (int d = 0; d < 2; ++d) {
                worst0 = fmax(worst0, fabs((b[d] - off) - a[d]));
                worst1 = fmax(worst1, fabs(b[2 + d] - a[2 + d]) / (1 + fabs(a[2 + d])));
            }
        }
        /* positions to a few ulp of 1e8 (1.5e-8), derivatives to the
         * cancellation of sum N' (P + 1e8): ~1e8 eps / span ~ 1e-7 */
        if (worst0 > 4 * off * DBL_EPSILON)
            fail_msg("offset positions: %.3g", worst0);
        if (worst1 > 1e-6)
            fail_msg("offset derivatives: %.3g", worst1);
        /* closest point and arc length are translation invariant */
        const double q[2] = {2.5, 3.0}, qo[2] = {2.5 + off, 3.0 + off};
        double u1, u2, d1, d2;
        assert_int_equal(geom_curve_nurbs_closest_point(&c, q, &u1, NULL, &d1, NULL), GEOM_OK);
        assert_int_equal(geom_curve_nurbs_closest_point(&co, qo, &u2, NULL, &d2, NULL), GEOM_OK);
        assert_near(d2, d1, 1e-7);
        assert_near(u2, u1, 1e-6);
        double L1, L2;
        geom_error_report rep;
        assert_int_equal(geom_curve_nurbs_arc_length(&c, 0, 1, 0, &L1, NULL, NULL), GEOM_OK);
        assert_int_equal(geom_curve_nurbs_arc_length(&co, 0, 1, 1e-6, &L2, &rep, NULL), GEOM_OK);
        assert_near(L2, L1, 1e-7 * L1);
        /* an unreachable tolerance ends (at the evaluation budget) with
         * GEOM_ERR_LIMIT, still returning the estimate */
        assert_int_equal(geom_curve_nurbs_arc_length(&co, 0, 1, 1e-15, &L2, &rep, NULL),
                         GEOM_ERR_LIMIT);
        assert_near(L2, L1, 1e-7 * L1);
        assert_true(rep.evaluations <= ((size_t)1 << 21) + 2048);
    }
}

/* ----------------------------------------------- NaN and Inf parameters */

static void test_nonfinite_parameters(void **state)
{
    (void)state;
    const double U[] = {0, 0, 0, 0.5, 1, 1, 1};
    const double P[] = {0, 0, 1, 1, 2, 0, 3, 1};
    const double W[] = {1, 2, 1, 1};
    geom_nurbs_curve c = {2, 4, 2, U, P, W};
    const double bad[] = {NAN, INFINITY, -INFINITY};
    for (int i = 0; i < 3; ++i) {
        double u = bad[i], out[8], k, tau;
        size_t span;
        for (unsigned f = 0; f <= (GEOM_CURVE_LEFT_LIMIT | GEOM_CURVE_WRAP); ++f) {
            assert_int_equal(geom_curve_nurbs_eval(&c, u, f, out), GEOM_ERR_INVALID_ARG);
            assert_int_equal(geom_curve_nurbs_derivs(&c, u, 2, f, out), GEOM_ERR_INVALID_ARG);
            assert_int_equal(geom_curve_nurbs_curvature(&c, u, f, &k, &tau), GEOM_ERR_INVALID_ARG);
            assert_int_equal(geom_curve_bspline_find_span(2, 4, U, u, f, &span),
                             GEOM_ERR_INVALID_ARG);
            assert_int_equal(geom_curve_bspline_basis(2, 4, U, u, f, &span, out),
                             GEOM_ERR_INVALID_ARG);
            assert_int_equal(geom_curve_bspline_basis_derivs(2, 4, U, u, 1, f, &span, out),
                             GEOM_ERR_INVALID_ARG);
        }
        assert_int_equal(geom_curve_bezier_eval(3, 2, P, u, out), GEOM_ERR_INVALID_ARG);
        assert_int_equal(geom_curve_bezier_derivs(3, 2, P, u, 1, out), GEOM_ERR_INVALID_ARG);
        assert_int_equal(geom_curve_bezier_split(3, 2, P, u, out, NULL), GEOM_ERR_INVALID_ARG);
        assert_int_equal(geom_curve_hermite_eval(2, P, P + 2, P + 4, P + 6, u, 1, out),
                         GEOM_ERR_INVALID_ARG);
        assert_int_equal(geom_curve_catmull_rom_eval(2, P, P + 2, P + 4, P + 6, 0.5, u, out),
                         GEOM_ERR_INVALID_ARG);
        double L;
        assert_int_equal(geom_curve_nurbs_arc_length(&c, 0, u, 0, &L, NULL, NULL),
                         GEOM_ERR_INVALID_ARG);
        assert_int_equal(geom_curve_nurbs_arc_length(&c, u, 1, 0, &L, NULL, NULL),
                         GEOM_ERR_INVALID_ARG);
        double Uo[10], Po[14], Wo[7];
        geom_nurbs_curve o;
        size_t removed;
        geom_diag d;
        assert_int_equal(geom_curve_nurbs_insert_knot(&c, u, 1, Uo, Po, Wo, &o, &d),
                         GEOM_ERR_INVALID_ARG);
        assert_int_equal(geom_curve_nurbs_refine(&c, &u, 1, Uo, Po, Wo, &o, &d),
                         GEOM_ERR_INVALID_ARG);
        assert_int_equal(geom_curve_nurbs_remove_knot(&c, u, 1, 1e-9, Uo, Po, Wo, &o, &removed, &d),
                         GEOM_ERR_INVALID_ARG);
        double q[2] = {u, 0};
        assert_int_equal(geom_curve_nurbs_closest_point(&c, q, &L, NULL, NULL, &d),
                         GEOM_ERR_INVALID_ARG);
        assert_int_equal(geom_curve_nurbs_arc_bound(0, u, NULL, NULL), GEOM_ERR_INVALID_ARG);
        double pts[8];
        assert_int_equal(
            geom_curve_catmull_rom_to_bezier(2, 4, P, u, GEOM_CURVE_END_EXCLUDE, pts, NULL, &d),
            GEOM_ERR_INVALID_ARG);
    }
    /* NaN in the data is caught by the validator */
    double Pn[8];
    memcpy(Pn, P, sizeof Pn);
    Pn[5] = NAN;
    geom_nurbs_curve cn = {2, 4, 2, U, Pn, NULL};
    geom_diag d;
    double L;
    assert_int_equal(geom_curve_nurbs_arc_length(&cn, 0, 1, 0, &L, NULL, &d), GEOM_ERR_INVALID_ARG);
    assert_non_null(strstr(d.message, "control point 2"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_extreme_weights_circle),
        cmocka_unit_test(test_extreme_weights_spline),
        cmocka_unit_test(test_tiny_spans),
        cmocka_unit_test(test_kink_and_jump),
        cmocka_unit_test(test_domain_ends),
        cmocka_unit_test(test_degree25_bezier),
        cmocka_unit_test(test_offset_coordinates),
        cmocka_unit_test(test_nonfinite_parameters),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
