/* Curve module: arc length, closest point and adaptive polylines. References:
 * 2 pi r and r * sweep for circles and arcs, |B - A| for straight lines,
 * radial projection onto circles, a dense brute-force scan for a space
 * curve, and the chordal deviation re-measured at dense samples. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "geom/curve.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

static void assert_near(double got, double want, double tol)
{
    if (!(fabs(got - want) <= tol))
        fail_msg("got %.17g want %.17g (diff %.3g, tol %g)", got, want, fabs(got - want), tol);
}

static uint64_t rng = 0x13198a2e03707344ull;
static double urand(void) /* [0, 1) */
{
    uint64_t z = (rng += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return (double)(z >> 11) * 0x1.0p-53;
}

static void test_arc_length_circle(void **state)
{
    (void)state;
    const double C[2] = {0.3, -7}, X[2] = {1, 0}, Y[2] = {0, 1};
    const double radii[] = {1.0, 3.7, 1e-3, 250.0};
    for (size_t i = 0; i < 4; ++i) {
        double U[12], P[18], W[9], L;
        geom_nurbs_curve c;
        assert_int_equal(geom_curve_nurbs_circle(2, C, X, Y, radii[i], U, P, W, &c, NULL), GEOM_OK);
        geom_error_report rep;
        assert_int_equal(geom_curve_nurbs_arc_length(&c, 0, 1, 0, &L, &rep, NULL), GEOM_OK);
        assert_near(L, 2 * PI * radii[i], 1e-12 * 2 * PI * radii[i]);
        assert_int_equal(rep.method, GEOM_ERROR_ESTIMATE);
        assert_true(rep.evaluations >= 8 * 4);
        assert_true(rep.max_error <= 1e-12 * L);
        assert_true(rep.mean_error <= rep.max_error);
    }
    /* arcs of any sweep: r * |sweep| */
    const double sweeps[] = {0.1, 1.0, 2.5, 4.0, 6.0};
    for (size_t i = 0; i < 5; ++i) {
        double U[12], P[18], W[9], L;
        geom_nurbs_curve c;
        assert_int_equal(
            geom_curve_nurbs_arc(2, C, X, Y, 2.0, 0.3, 0.3 + sweeps[i], U, P, W, &c, NULL),
            GEOM_OK);
        assert_int_equal(geom_curve_nurbs_arc_length(&c, 0, 1, 1e-14, &L, NULL, NULL), GEOM_OK);
        assert_near(L, 2.0 * sweeps[i], 1e-13 * L);
    }
}

/* Straight lines: a cubic with collinear, unevenly spaced control points
 * has non-constant speed, yet its length is |B - A| (the speed is a
 * polynomial of degree 2 there, which 8-point Gauss-Legendre integrates
 * exactly), also over partial intervals. */
static void test_arc_length_line(void **state)
{
    (void)state;
    const double A[3] = {1, -2, 0.5}, Bv[3] = {4, 2, -11.5};
    const double s[6] = {0, 0.05, 0.2, 0.3, 0.9, 1};
    double P[6 * 3];
    for (int i = 0; i < 6; ++i)
        for (int d = 0; d < 3; ++d)
            P[3 * i + d] = A[d] + s[i] * (Bv[d] - A[d]);
    const double U[10] = {0, 0, 0, 0, 0.4, 0.7, 1, 1, 1, 1};
    geom_nurbs_curve c = {3, 6, 3, U, P, NULL};
    double L, want = 13.0; /* |(3, 4, -12)| */
    assert_int_equal(geom_curve_nurbs_arc_length(&c, 0, 1, 0, &L, NULL, NULL), GEOM_OK);
    assert_near(L, want, 4 * DBL_EPSILON * want);
    for (int k = 0; k < 20; ++k) {
        double u0 = urand(), u1 = urand();
        if (u0 > u1) {
            double t = u0;
            u0 = u1;
            u1 = t;
        }
        double a[3], b[3];
        geom_curve_nurbs_eval(&c, u0, 0, a);
        geom_curve_nurbs_eval(&c, u1, 0, b);
        double chord = sqrt((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) +
                            (b[2] - a[2]) * (b[2] - a[2]));
        assert_int_equal(geom_curve_nurbs_arc_length(&c, u0, u1, 0, &L, NULL, NULL), GEOM_OK);
        assert_near(L, chord, 1e-14 * want);
    }
    /* empty interval, bad arguments */
    assert_int_equal(geom_curve_nurbs_arc_length(&c, 0.5, 0.5, 0, &L, NULL, NULL), GEOM_OK);
    assert_near(L, 0.0, 0.0);
    assert_int_equal(geom_curve_nurbs_arc_length(&c, 0.5, 0.4, 0, &L, NULL, NULL), GEOM_ERR_DOMAIN);
    assert_int_equal(geom_curve_nurbs_arc_length(&c, 0.0, 1.5, 0, &L, NULL, NULL), GEOM_ERR_DOMAIN);
    assert_int_equal(geom_curve_nurbs_arc_length(&c, NAN, 1.0, 0, &L, NULL, NULL),
                     GEOM_ERR_INVALID_ARG);
}

/* Closest point on a circle: the radial projection of q. */
static void test_closest_circle(void **state)
{
    (void)state;
    const double C[2] = {0.5, -0.25}, X[2] = {1, 0}, Y[2] = {0, 1}, r = 2.0;
    double U[12], P[18], W[9];
    geom_nurbs_curve c;
    assert_int_equal(geom_curve_nurbs_circle(2, C, X, Y, r, U, P, W, &c, NULL), GEOM_OK);
    for (int i = 0; i < 2000; ++i) {
        double ang = 2 * PI * urand(), rho = r * (0.05 + 2.5 * urand());
        double q[2] = {C[0] + rho * cos(ang), C[1] + rho * sin(ang)};
        double u, pt[2], dist;
        assert_int_equal(geom_curve_nurbs_closest_point(&c, q, &u, pt, &dist, NULL), GEOM_OK);
        double len = hypot(q[0] - C[0], q[1] - C[1]);
        double want[2] = {C[0] + r * (q[0] - C[0]) / len, C[1] + r * (q[1] - C[1]) / len};
        assert_near(dist, fabs(len - r), 1e-14 * r);
        assert_near(pt[0], want[0], 1e-7 * r); /* position: sqrt of the distance error */
        assert_near(pt[1], want[1], 1e-7 * r);
        double e[2];
        geom_curve_nurbs_eval(&c, u, 0, e);
        assert_near(e[0], pt[0], 1e-15 * r);
        assert_near(e[1], pt[1], 1e-15 * r);
        /* the returned point is (to rounding) a foot point: q - C(u) is
         * normal to the curve */
        double d[4];
        geom_curve_nurbs_derivs(&c, u, 1, 0, d);
        double dot = (q[0] - pt[0]) * d[2] + (q[1] - pt[1]) * d[3];
        assert_near(dot / (hypot(d[2], d[3]) * fmax(dist, 1e-300)), 0.0, 1e-6);
    }
    /* the centre: every point is closest, any one will do */
    double u, pt[2], dist;
    assert_int_equal(geom_curve_nurbs_closest_point(&c, C, &u, pt, &dist, NULL), GEOM_OK);
    assert_near(dist, r, 1e-14);
}

/* A 3D cubic with a loop-like shape: compare with a dense scan. */
static void test_closest_space_curve(void **state)
{
    (void)state;
    const double U[] = {0, 0, 0, 0, 0.2, 0.5, 0.5, 0.8, 1, 1, 1, 1};
    const double P[] = {0,  0, 0,  2, 3, 1, 4, -1, 0, 1, -3, 2,
                        -1, 2, -1, 3, 4, 1, 5, 0,  2, 2, -2, 0};
    const double W[] = {1, 2, 0.5, 1, 3, 0.7, 1.2, 1};
    enum { NS = 200000 };
    double *scan = malloc((NS + 1) * 3 * sizeof(double));
    assert_non_null(scan);
    for (int rational = 0; rational < 2; ++rational) {
        geom_nurbs_curve c = {3, 8, 3, U, P, rational ? W : NULL};
        for (int i = 0; i <= NS; ++i)
            geom_curve_nurbs_eval(&c, i / (double)NS, 0, scan + 3 * i);
        for (int k = 0; k < 30; ++k) {
            double q[3] = {-2 + 8 * urand(), -4 + 8 * urand(), -2 + 5 * urand()};
            double u, pt[3], dist;
            assert_int_equal(geom_curve_nurbs_closest_point(&c, q, &u, pt, &dist, NULL), GEOM_OK);
            double best = INFINITY;
            for (int i = 0; i <= NS; ++i) {
                double dx = scan[3 * i] - q[0], dy = scan[3 * i + 1] - q[1],
                       dz = scan[3 * i + 2] - q[2];
                best = fmin(best, sqrt(dx * dx + dy * dy + dz * dz));
            }
            /* global: never worse than the scan; the scan's spacing (< 1e-4)
             * bounds how much better it can be */
            assert_true(dist <= best + 1e-13);
            assert_true(best - dist <= 1e-7);
            double chk = sqrt((pt[0] - q[0]) * (pt[0] - q[0]) + (pt[1] - q[1]) * (pt[1] - q[1]) +
                              (pt[2] - q[2]) * (pt[2] - q[2]));
            assert_near(chk, dist, 1e-14);
        }
    }
    free(scan);
    const double q[3] = {NAN, 0, 0};
    geom_nurbs_curve c = {3, 8, 3, U, P, NULL};
    double u;
    assert_int_equal(geom_curve_nurbs_closest_point(&c, q, &u, NULL, NULL, NULL),
                     GEOM_ERR_INVALID_ARG);
}

/* Distance from X to the segment AB. */
static double seg_dist(const double *X, const double *A, const double *B, size_t dim)
{
    double ab2 = 0, t = 0;
    for (size_t d = 0; d < dim; ++d) {
        ab2 += (B[d] - A[d]) * (B[d] - A[d]);
        t += (X[d] - A[d]) * (B[d] - A[d]);
    }
    t = ab2 > 0 ? fmin(1.0, fmax(0.0, t / ab2)) : 0.0;
    double s = 0;
    for (size_t d = 0; d < dim; ++d) {
        double r = X[d] - (A[d] + t * (B[d] - A[d]));
        s += r * r;
    }
    return sqrt(s);
}

/* Re-measure the polyline: for each edge, the curve between its end
 * parameters must stay within tol of the edge (200 samples per edge). */
static double measure(const geom_nurbs_curve *c, const double *par, const double *pts, size_t count)
{
    double worst = 0;
    size_t dim = c->dim;
    for (size_t i = 0; i + 1 < count; ++i) {
        if (par[i + 1] == par[i])
            continue; /* a jump */
        for (int k = 1; k < 200; ++k) {
            double u = par[i] + (par[i + 1] - par[i]) * k / 200.0, x[4];
            geom_curve_nurbs_eval(c, u, 0, x);
            worst = fmax(worst, seg_dist(x, pts + i * dim, pts + (i + 1) * dim, dim));
        }
    }
    return worst;
}

static void test_polyline(void **state)
{
    (void)state;
    const double C[2] = {0, 0}, X[2] = {1, 0}, Y[2] = {0, 1};
    double U[12], P[18], W[9];
    geom_nurbs_curve circ;
    assert_int_equal(geom_curve_nurbs_circle(2, C, X, Y, 1.0, U, P, W, &circ, NULL), GEOM_OK);
    const double Uc[] = {0, 0, 0, 0, 0.2, 0.5, 0.5, 0.8, 1, 1, 1, 1};
    const double Pc[] = {0,  0, 0,  2, 3, 1, 4, -1, 0, 1, -3, 2,
                         -1, 2, -1, 3, 4, 1, 5, 0,  2, 2, -2, 0};
    geom_nurbs_curve cub = {3, 8, 3, Uc, Pc, NULL};
    const geom_nurbs_curve *curves[2] = {&circ, &cub};
    const double tols[] = {1e-2, 1e-4, 1e-6};
    for (int ci = 0; ci < 2; ++ci)
        for (int ti = 0; ti < 3; ++ti)
            for (int method = GEOM_ERROR_BOUND; method <= GEOM_ERROR_SAMPLED; ++method) {
                const geom_nurbs_curve *c = curves[ci];
                geom_curve_polyline_options opt = {tols[ti], method, 0};
                size_t need;
                geom_error_report rep;
                assert_int_equal(
                    geom_curve_nurbs_polyline(c, &opt, NULL, NULL, 0, &need, &rep, NULL), GEOM_OK);
                double *par = malloc(need * sizeof(double));
                double *pts = malloc(need * c->dim * sizeof(double));
                size_t count;
                assert_int_equal(
                    geom_curve_nurbs_polyline(c, &opt, par, pts, need, &count, &rep, NULL),
                    GEOM_OK);
                assert_int_equal(count, need);
                assert_int_equal(rep.method, method);
                assert_true(rep.max_error <= tols[ti]);
                assert_true(rep.mean_error <= rep.max_error);
                assert_true(rep.evaluations > 0);
                /* vertices are curve points; the ends are exact */
                for (size_t i = 0; i < count; ++i) {
                    double x[3];
                    geom_curve_nurbs_eval(c, par[i], i + 1 == count ? GEOM_CURVE_LEFT_LIMIT : 0, x);
                    for (size_t d = 0; d < c->dim; ++d)
                        assert_near(pts[i * c->dim + d], x[d], 1e-14);
                    if (i > 0)
                        assert_true(par[i] > par[i - 1]);
                }
                assert_true(par[0] == 0.0 && par[count - 1] == 1.0);
                for (size_t d = 0; d < c->dim; ++d) {
                    assert_true(pts[d] == c->points[d]);
                    assert_true(pts[(count - 1) * c->dim + d] ==
                                c->points[(c->n - 1) * c->dim + d]);
                }
                double worst = measure(c, par, pts, count);
                if (method == GEOM_ERROR_BOUND)
                    assert_true(worst <= tols[ti]); /* guaranteed */
                else
                    assert_true(worst <= 1.5 * tols[ti]); /* sampled: close */
                /* a circle to tolerance t needs about pi / acos(1 - t) edges */
                if (ci == 0) {
                    double ideal = PI / acos(1 - tols[ti]);
                    assert_true((double)(count - 1) >= ideal * 0.99);
                    assert_true((double)(count - 1) <= ideal * 4.0);
                }
                /* too small a buffer: GEOM_ERR_LIMIT and the size needed */
                size_t c2;
                assert_int_equal(
                    geom_curve_nurbs_polyline(c, &opt, par, pts, count - 1, &c2, NULL, NULL),
                    GEOM_ERR_LIMIT);
                assert_int_equal(c2, count);
                free(par);
                free(pts);
            }
    /* max_points */
    geom_curve_polyline_options opt = {1e-9, 0, 10};
    size_t cnt;
    assert_int_equal(geom_curve_nurbs_polyline(&circ, &opt, NULL, NULL, 0, &cnt, NULL, NULL),
                     GEOM_ERR_LIMIT);
    /* default options (zero-initialised): tolerance 1e-3 of the box diagonal */
    geom_curve_polyline_options zero;
    memset(&zero, 0, sizeof zero);
    geom_error_report rep;
    assert_int_equal(geom_curve_nurbs_polyline(&circ, &zero, NULL, NULL, 0, &cnt, &rep, NULL),
                     GEOM_OK);
    assert_true(rep.max_error <= 1e-3 * sqrt(8.0));
    assert_int_equal(geom_curve_nurbs_polyline(&circ, NULL, NULL, NULL, 0, &cnt, &rep, NULL),
                     GEOM_OK);
}

/* A curve with a jump: the polyline has both one-sided points at the same
 * parameter and does not bridge the gap. */
static void test_polyline_jump(void **state)
{
    (void)state;
    const double U[] = {0, 0, 0, 0.5, 0.5, 0.5, 1, 1, 1};
    const double P[] = {0, 0, 1, 1, 2, 0, 5, 5, 6, 4, 7, 6};
    geom_nurbs_curve c = {2, 6, 2, U, P, NULL};
    geom_curve_polyline_options opt = {1e-3, 0, 0};
    double par[512], pts[1024];
    size_t count;
    assert_int_equal(geom_curve_nurbs_polyline(&c, &opt, par, pts, 512, &count, NULL, NULL),
                     GEOM_OK);
    size_t jumps = 0;
    for (size_t i = 0; i + 1 < count; ++i)
        if (par[i] == par[i + 1]) {
            ++jumps;
            assert_true(pts[2 * i] == 2 && pts[2 * i + 1] == 0);
            assert_true(pts[2 * i + 2] == 5 && pts[2 * i + 3] == 5);
        }
    assert_int_equal(jumps, 1);
    assert_true(measure(&c, par, pts, count) <= 1e-3);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_arc_length_circle), cmocka_unit_test(test_arc_length_line),
        cmocka_unit_test(test_closest_circle),    cmocka_unit_test(test_closest_space_curve),
        cmocka_unit_test(test_polyline),          cmocka_unit_test(test_polyline_jump),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
