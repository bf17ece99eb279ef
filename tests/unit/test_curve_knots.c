/* Curve module: knot insertion (A5.1), refinement (A5.4), removal (A5.8),
 * degree elevation (A5.9), clamping and Bezier decomposition (A5.6). Each
 * operation must leave the curve unchanged: checked by evaluating old and
 * new curves at 1000 parameters (and both one-sided limits at knots). */
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

/* Largest distance between a and b over 1001 uniform parameters of a's
 * domain plus both one-sided values at every knot of a and b. */
static double curve_gap(const geom_nurbs_curve *a, const geom_nurbs_curve *b)
{
    double u0, u1, v0, v1;
    assert_int_equal(geom_curve_nurbs_domain(a, &u0, &u1), GEOM_OK);
    assert_int_equal(geom_curve_nurbs_domain(b, &v0, &v1), GEOM_OK);
    assert_near(v0, u0, 0.0);
    assert_near(v1, u1, 0.0);
    double gap = 0.0;
    size_t nk = a->n + (size_t)a->degree + 1 + b->n + (size_t)b->degree + 1;
    for (size_t i = 0; i <= 1000 + nk; ++i) {
        double u;
        if (i <= 1000)
            u = i == 1000 ? u1 : u0 + (u1 - u0) * (double)i / 1000.0;
        else {
            size_t j = i - 1001, na = a->n + (size_t)a->degree + 1;
            u = j < na ? a->knots[j] : b->knots[j - na];
            if (u < u0 || u > u1)
                continue;
        }
        for (unsigned f = 0; f <= GEOM_CURVE_LEFT_LIMIT; ++f) {
            double pa[4], pb[4];
            assert_int_equal(geom_curve_nurbs_eval(a, u, f, pa), GEOM_OK);
            assert_int_equal(geom_curve_nurbs_eval(b, u, f, pb), GEOM_OK);
            for (size_t d = 0; d < a->dim; ++d)
                gap = fmax(gap, fabs(pa[d] - pb[d]));
        }
    }
    return gap;
}

/* A clamped cubic with interior knots of multiplicity 1, 2 and 3 (a C0
 * kink), in 3D, optionally rational. */
static const double KU[] = {0, 0, 0, 0, 0.1, 0.25, 0.25, 0.4, 0.6, 0.6, 0.6, 0.85, 1, 1, 1, 1};
#define KN 12
static const double KP[KN * 3] = {0,   0,    0,   0.2, 0.8, 0.1, 0.5, 1.0, -0.3, 0.9, 0.6, 0.4,
                                  1.1, -0.2, 0.2, 1.4, 0.3, 0.9, 1.7, 0.9, 0.1,  2.0, 0.2, -0.4,
                                  2.3, -0.6, 0.0, 2.6, 0.1, 0.5, 3.0, 0.9, 0.3,  3.3, 0.4, -0.1};
static const double KW[KN] = {1, 0.6, 1.8, 0.9, 1.3, 0.7, 2.2, 1.0, 0.5, 1.6, 0.8, 1};

static geom_nurbs_curve test_curve(int rational)
{
    geom_nurbs_curve c = {3, KN, 3, KU, KP, rational ? KW : NULL};
    return c;
}

static void test_insert(void **state)
{
    (void)state;
    for (int rational = 0; rational < 2; ++rational) {
        geom_nurbs_curve c = test_curve(rational);
        assert_int_equal(geom_curve_nurbs_validate(&c, KN + 4, NULL), GEOM_OK);
        const struct {
            double u;
            size_t r;
        } ins[] = {{0.37, 1}, {0.37, 3}, {0.1, 2}, {0.25, 1}, {0.0, 0}, {0.05, 3}, {0.9, 2}};
        for (size_t t = 0; t < sizeof ins / sizeof ins[0]; ++t) {
            double U[KN + 4 + 3], P[(KN + 3) * 3], W[KN + 3];
            geom_nurbs_curve o;
            geom_diag d;
            assert_int_equal(geom_curve_nurbs_insert_knot(&c, ins[t].u, ins[t].r, U, P, W, &o, &d),
                             GEOM_OK);
            assert_int_equal(o.n, KN + ins[t].r);
            assert_int_equal(geom_curve_nurbs_validate(&o, o.n + 4, NULL), GEOM_OK);
            double gap = curve_gap(&c, &o);
            if (gap > 1e-14)
                fail_msg("insert %g x%zu (rational %d): gap %.3g", ins[t].u, ins[t].r, rational,
                         gap);
        }
        /* multiplicity above the degree, outside the domain */
        double U[KN + 8], P[(KN + 4) * 3], W[KN + 4];
        geom_nurbs_curve o;
        geom_diag d;
        assert_int_equal(geom_curve_nurbs_insert_knot(&c, 0.6, 1, U, P, W, &o, &d),
                         GEOM_ERR_DOMAIN);
        assert_non_null(strstr(d.message, "multiplicity"));
        assert_int_equal(geom_curve_nurbs_insert_knot(&c, 0.25, 2, U, P, W, &o, &d),
                         GEOM_ERR_DOMAIN);
        assert_int_equal(geom_curve_nurbs_insert_knot(&c, 1.0, 1, U, P, W, &o, &d),
                         GEOM_ERR_DOMAIN);
        assert_int_equal(geom_curve_nurbs_insert_knot(&c, 1.5, 1, U, P, W, &o, &d),
                         GEOM_ERR_DOMAIN);
        assert_int_equal(geom_curve_nurbs_insert_knot(&c, NAN, 1, U, P, W, &o, &d),
                         GEOM_ERR_INVALID_ARG);
    }
}

static void test_refine(void **state)
{
    (void)state;
    for (int rational = 0; rational < 2; ++rational) {
        geom_nurbs_curve c = test_curve(rational);
        const double X[] = {0.05, 0.1, 0.1, 0.2, 0.25, 0.3, 0.3, 0.3, 0.5, 0.75, 0.99};
        size_t nx = sizeof X / sizeof X[0];
        double U[KN + 4 + 11], P[(KN + 11) * 3], W[KN + 11];
        geom_nurbs_curve o;
        geom_diag d;
        assert_int_equal(geom_curve_nurbs_refine(&c, X, nx, U, P, W, &o, &d), GEOM_OK);
        assert_int_equal(o.n, KN + nx);
        assert_int_equal(geom_curve_nurbs_validate(&o, o.n + 4, NULL), GEOM_OK);
        assert_true(curve_gap(&c, &o) <= 1e-14);
        /* the same single knot by A5.4 and by A5.1 */
        double U1[KN + 6], P1[(KN + 2) * 3], W1[KN + 2];
        geom_nurbs_curve o1;
        const double two[] = {0.37, 0.37};
        assert_int_equal(geom_curve_nurbs_refine(&c, two, 2, U, P, W, &o, &d), GEOM_OK);
        assert_int_equal(geom_curve_nurbs_insert_knot(&c, 0.37, 2, U1, P1, W1, &o1, &d), GEOM_OK);
        for (size_t i = 0; i < o.n + 4; ++i)
            assert_near(U[i], U1[i], 0.0);
        for (size_t i = 0; i < o.n * 3; ++i)
            assert_near(P[i], P1[i], 1e-15);
        /* errors */
        const double bad[] = {0.6};
        assert_int_equal(geom_curve_nurbs_refine(&c, bad, 1, U, P, W, &o, &d), GEOM_ERR_DOMAIN);
        const double dec[] = {0.5, 0.4};
        assert_int_equal(geom_curve_nurbs_refine(&c, dec, 2, U, P, W, &o, &d),
                         GEOM_ERR_INVALID_ARG);
        const double out[] = {1.2};
        assert_int_equal(geom_curve_nurbs_refine(&c, out, 1, U, P, W, &o, &d), GEOM_ERR_DOMAIN);
    }
}

/* Unclamped curves: refinement at the domain ends and clamping. */
static void test_unclamped_refine_clamp(void **state)
{
    (void)state;
    const double U[] = {-3, -2, -1.5, 0, 1, 1.5, 2.25, 3, 4, 5.5, 6};
    const double P[] = {0, 0, 1, 2, 2, -1, 3, 1, 4, 3, 5, 0, 6, 2};
    const double W[] = {1, 2, 0.5, 1, 3, 0.7, 1.2};
    for (int rational = 0; rational < 2; ++rational) {
        geom_nurbs_curve c = {3, 7, 2, U, P, rational ? W : NULL};
        assert_int_equal(geom_curve_nurbs_validate(&c, 11, NULL), GEOM_OK);
        /* domain [0, 3]: insert both ends twice */
        const double X[] = {0, 0, 1.2, 3, 3};
        double Ur[16], Pr[24], Wr[12];
        geom_nurbs_curve o;
        assert_int_equal(geom_curve_nurbs_refine(&c, X, 5, Ur, Pr, Wr, &o, NULL), GEOM_OK);
        assert_true(curve_gap(&c, &o) <= 1e-14);
        double Uc[7 + 6 + 4], Pc[(7 + 6) * 2], Wc[7 + 6];
        geom_nurbs_curve cl;
        assert_int_equal(geom_curve_nurbs_clamp(&c, Uc, Pc, Wc, &cl, NULL), GEOM_OK);
        assert_int_equal(geom_curve_nurbs_validate(&cl, cl.n + 4, NULL), GEOM_OK);
        for (int i = 0; i <= 3; ++i) {
            assert_near(Uc[i], 0.0, 0.0);
            assert_near(Uc[cl.n + (size_t)i], 3.0, 0.0);
        }
        assert_int_equal(cl.n, 7); /* p+1 plus the interior knots 1, 1.5, 2.25 */
        assert_true(curve_gap(&c, &cl) <= 1e-14);
        /* a clamped curve is copied unchanged */
        geom_nurbs_curve cl2;
        double Uc2[17], Pc2[26], Wc2[13];
        assert_int_equal(geom_curve_nurbs_clamp(&cl, Uc2, Pc2, Wc2, &cl2, NULL), GEOM_OK);
        assert_int_equal(cl2.n, cl.n);
        for (size_t i = 0; i < cl.n * 2; ++i)
            assert_near(Pc2[i], Pc[i], 2e-16 * (1 + fabs(Pc[i])));
    }
}

static void test_remove(void **state)
{
    (void)state;
    for (int rational = 0; rational < 2; ++rational) {
        geom_nurbs_curve c = test_curve(rational);
        /* insert a new knot once and twice, an existing one once; removal
         * restores the original knots exactly and points to rounding */
        const struct {
            double u;
            size_t r;
        } cases[] = {{0.37, 1}, {0.37, 2}, {0.37, 3}, {0.1, 2}, {0.25, 1}, {0.85, 2}};
        for (size_t t = 0; t < sizeof cases / sizeof cases[0]; ++t) {
            double U[KN + 7], P[(KN + 3) * 3], W[KN + 3];
            geom_nurbs_curve o;
            assert_int_equal(
                geom_curve_nurbs_insert_knot(&c, cases[t].u, cases[t].r, U, P, W, &o, NULL),
                GEOM_OK);
            double U2[KN + 7], P2[(KN + 3) * 3], W2[KN + 3];
            geom_nurbs_curve back;
            size_t removed = 99;
            geom_diag d;
            assert_int_equal(geom_curve_nurbs_remove_knot(&o, cases[t].u, cases[t].r, 1e-12, U2, P2,
                                                          W2, &back, &removed, &d),
                             GEOM_OK);
            assert_int_equal(removed, cases[t].r);
            assert_int_equal(back.n, KN);
            for (size_t i = 0; i < KN + 4; ++i)
                assert_near(U2[i], KU[i], 0.0);
            for (size_t i = 0; i < KN * 3; ++i)
                assert_near(P2[i], KP[i], 1e-13);
            if (rational)
                for (size_t i = 0; i < KN; ++i)
                    assert_near(W2[i], KW[i], 1e-13);
            assert_true(curve_gap(&c, &back) <= 1e-13);
        }
        /* a genuine knot is not removable with a small tolerance... */
        double U[KN + 4], P[KN * 3], W[KN];
        geom_nurbs_curve o;
        size_t removed = 99;
        assert_int_equal(
            geom_curve_nurbs_remove_knot(&c, 0.4, 1, 1e-9, U, P, W, &o, &removed, NULL), GEOM_OK);
        assert_int_equal(removed, 0);
        assert_int_equal(o.n, KN);
        assert_true(curve_gap(&c, &o) <= 1e-15);
        /* ...but is with a large one, and the curve moves by at most tol */
        assert_int_equal(geom_curve_nurbs_remove_knot(&c, 0.4, 1, 1e3, U, P, W, &o, &removed, NULL),
                         GEOM_OK);
        assert_int_equal(removed, 1);
        assert_int_equal(o.n, KN - 1);
        assert_int_equal(geom_curve_nurbs_validate(&o, o.n + 4, NULL), GEOM_OK);
        /* errors: not a knot, domain end */
        geom_diag d;
        assert_int_equal(geom_curve_nurbs_remove_knot(&c, 0.5, 1, 1.0, U, P, W, &o, &removed, &d),
                         GEOM_ERR_DOMAIN);
        assert_int_equal(geom_curve_nurbs_remove_knot(&c, 1.0, 1, 1.0, U, P, W, &o, &removed, &d),
                         GEOM_ERR_DOMAIN);
    }
}

/* Tolerance removal on a polynomial curve where the bound is checkable: a
 * cubic with a knot of multiplicity 1 removed with tol = t moves the curve
 * by at most t (the difference is one B-spline times a coefficient). */
static void test_remove_tolerance_bound(void **state)
{
    (void)state;
    geom_nurbs_curve c = test_curve(0);
    const double tols[] = {1e-3, 1e-2, 0.05, 0.2, 1.0};
    for (size_t t = 0; t < 5; ++t) {
        double U[KN + 4], P[KN * 3];
        geom_nurbs_curve o;
        size_t removed;
        assert_int_equal(
            geom_curve_nurbs_remove_knot(&c, 0.4, 1, tols[t], U, P, NULL, &o, &removed, NULL),
            GEOM_OK);
        if (removed == 1) {
            /* sampled max deviation (in each coordinate, then Euclidean) */
            double worst = 0.0;
            for (int i = 0; i <= 2000; ++i) {
                double u = i / 2000.0, a[3], b[3];
                geom_curve_nurbs_eval(&c, u, 0, a);
                geom_curve_nurbs_eval(&o, u, 0, b);
                worst =
                    fmax(worst, sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                                     (a[2] - b[2]) * (a[2] - b[2])));
            }
            assert_true(worst <= tols[t] * (1 + 1e-12));
            assert_true(worst > 0.0);
        }
    }
}

static void test_elevate(void **state)
{
    (void)state;
    for (int rational = 0; rational < 2; ++rational) {
        geom_nurbs_curve c = test_curve(rational);
        for (int t = 0; t <= 3; ++t) {
            size_t n, nk;
            assert_int_equal(geom_curve_nurbs_elevate_bound(&c, t, &n, &nk), GEOM_OK);
            /* 5 distinct interior knot values: n + t*6 */
            assert_int_equal(n, KN + (size_t)t * 6);
            double U[64], P[64 * 3], W[64];
            geom_nurbs_curve o;
            geom_diag d;
            assert_int_equal(geom_curve_nurbs_elevate(&c, t, U, P, W, &o, &d), GEOM_OK);
            assert_int_equal(o.degree, 3 + t);
            assert_int_equal(o.n, n);
            assert_int_equal(geom_curve_nurbs_validate(&o, nk, &d), GEOM_OK);
            /* each multiplicity grew by t */
            size_t cnt = 0;
            for (size_t i = 0; i < nk; ++i)
                cnt += U[i] == 0.25;
            assert_int_equal(cnt, 2 + (size_t)t);
            cnt = 0;
            for (size_t i = 0; i < nk; ++i)
                cnt += U[i] == 0.6;
            assert_int_equal(cnt, 3 + (size_t)t);
            double gap = curve_gap(&c, &o);
            if (gap > 1e-14)
                fail_msg("elevate by %d (rational %d): gap %.3g", t, rational, gap);
        }
    }
}

/* Elevation across a jump (interior multiplicity p+1): both one-sided
 * values must survive. */
static void test_elevate_discontinuous(void **state)
{
    (void)state;
    const double U[] = {0, 0, 0, 0.5, 0.5, 0.5, 1, 1, 1};
    const double P[] = {0, 0, 1, 1, 2, 0, 5, 5, 6, 4, 7, 6};
    geom_nurbs_curve c = {2, 6, 2, U, P, NULL};
    assert_int_equal(geom_curve_nurbs_validate(&c, 9, NULL), GEOM_OK);
    double Ue[20], Pe[40];
    geom_nurbs_curve o;
    size_t n, nk;
    assert_int_equal(geom_curve_nurbs_elevate_bound(&c, 2, &n, &nk), GEOM_OK);
    assert_int_equal(geom_curve_nurbs_elevate(&c, 2, Ue, Pe, NULL, &o, NULL), GEOM_OK);
    assert_int_equal(o.n, n);
    assert_int_equal(n, 10);
    assert_true(curve_gap(&c, &o) <= 1e-14);
    double a[2], b[2];
    geom_curve_nurbs_eval(&o, 0.5, GEOM_CURVE_LEFT_LIMIT, a);
    geom_curve_nurbs_eval(&o, 0.5, 0, b);
    assert_true(a[0] == 2.0 && a[1] == 0.0);
    assert_true(b[0] == 5.0 && b[1] == 5.0);
    /* unclamped input is refused with a reason */
    const double Uu[] = {0, 1, 2, 3, 4, 5, 6, 7, 8};
    geom_nurbs_curve u = {2, 6, 2, Uu, P, NULL};
    geom_diag d;
    assert_int_equal(geom_curve_nurbs_elevate(&u, 1, Ue, Pe, NULL, &o, &d), GEOM_ERR_DOMAIN);
    assert_non_null(strstr(d.message, "clamp"));
}

/* Bezier segments: each evaluates like the curve on its span; A5.6 (clamped
 * path) and blossoming (unclamped path) agree on the same curve. */
static void check_segments(const geom_nurbs_curve *c, const double *bp, const double *bw,
                           const double *br, size_t nseg)
{
    size_t p = (size_t)c->degree, q = p + 1, dim = c->dim;
    double Ub[2 * 16];
    for (size_t i = 0; i < q; ++i) {
        Ub[i] = 0.0;
        Ub[q + i] = 1.0;
    }
    for (size_t s = 0; s < nseg; ++s) {
        geom_nurbs_curve seg = {(int)p, q, dim, Ub, bp + s * q * dim, bw ? bw + s * q : NULL};
        for (int i = 0; i <= 50; ++i) {
            double t = i / 50.0, u = br[s] + (br[s + 1] - br[s]) * t;
            if (i == 50)
                u = br[s + 1];
            double a[4], b[4];
            assert_int_equal(geom_curve_nurbs_eval(&seg, t, 0, a), GEOM_OK);
            assert_int_equal(geom_curve_nurbs_eval(c, u, i == 50 ? GEOM_CURVE_LEFT_LIMIT : 0, b),
                             GEOM_OK);
            for (size_t d = 0; d < dim; ++d)
                assert_near(a[d], b[d], 1e-14);
        }
    }
}

static void test_decompose(void **state)
{
    (void)state;
    for (int rational = 0; rational < 2; ++rational) {
        geom_nurbs_curve c = test_curve(rational);
        size_t nseg;
        assert_int_equal(geom_curve_nurbs_segments(&c, &nseg), GEOM_OK);
        assert_int_equal(nseg, 6);
        double bp[6 * 4 * 3], bw[6 * 4], br[7];
        assert_int_equal(geom_curve_nurbs_decompose(&c, bp, rational ? bw : NULL, br, NULL),
                         GEOM_OK);
        const double want_br[7] = {0, 0.1, 0.25, 0.4, 0.6, 0.85, 1};
        for (int i = 0; i < 7; ++i)
            assert_near(br[i], want_br[i], 0.0);
        check_segments(&c, bp, rational ? bw : NULL, br, nseg);
        /* the first and last points are the curve's end control points */
        for (int d = 0; d < 3; ++d) {
            assert_near(bp[d], KP[d], 0.0);
            assert_near(bp[(6 * 4 - 1) * 3 + d], KP[(KN - 1) * 3 + d], 0.0);
        }
    }
    /* unclamped: blossoming path, cross-checked with A5.6 after clamping */
    const double U[] = {-3, -2, -1.5, 0, 1, 1.5, 1.5, 3, 4, 5.5, 6};
    const double P[] = {0, 0, 1, 2, 2, -1, 3, 1, 4, 3, 5, 0, 6, 2};
    const double W[] = {1, 2, 0.5, 1, 3, 0.7, 1.2};
    for (int rational = 0; rational < 2; ++rational) {
        geom_nurbs_curve c = {3, 7, 2, U, P, rational ? W : NULL};
        size_t nseg;
        assert_int_equal(geom_curve_nurbs_segments(&c, &nseg), GEOM_OK);
        assert_int_equal(nseg, 3);
        double bp[3 * 4 * 2], bw[3 * 4], br[4];
        assert_int_equal(geom_curve_nurbs_decompose(&c, bp, rational ? bw : NULL, br, NULL),
                         GEOM_OK);
        check_segments(&c, bp, rational ? bw : NULL, br, nseg);
        double Uc[20], Pc[30], Wc[15];
        geom_nurbs_curve cl;
        assert_int_equal(geom_curve_nurbs_clamp(&c, Uc, Pc, Wc, &cl, NULL), GEOM_OK);
        double bp2[3 * 4 * 2], bw2[3 * 4], br2[4];
        assert_int_equal(geom_curve_nurbs_decompose(&cl, bp2, rational ? bw2 : NULL, br2, NULL),
                         GEOM_OK);
        for (int i = 0; i < 4; ++i)
            assert_near(br2[i], br[i], 0.0);
        for (int i = 0; i < 3 * 4 * 2; ++i)
            assert_near(bp2[i], bp[i], 1e-13);
        if (rational)
            for (int i = 0; i < 3 * 4; ++i)
                assert_near(bw2[i], bw[i], 1e-13);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_insert),
        cmocka_unit_test(test_refine),
        cmocka_unit_test(test_unclamped_refine_clamp),
        cmocka_unit_test(test_remove),
        cmocka_unit_test(test_remove_tolerance_bound),
        cmocka_unit_test(test_elevate),
        cmocka_unit_test(test_elevate_discontinuous),
        cmocka_unit_test(test_decompose),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
