/* Curve module: Bezier curves (de Casteljau against the Bernstein closed
 * form in exact dyadic arithmetic, hodograph derivatives, split, degree
 * elevation, boxes), cubic Hermite segments and splines, Catmull-Rom
 * (Barry-Goldman) and Kochanek-Bartels splines. */
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

static int64_t binom(int n, int k)
{
    int64_t b = 1;
    for (int i = 1; i <= k; ++i)
        b = b * (n - k + i) / i;
    return b;
}

/* Degree 4, integer control points, t = k/8: every de Casteljau step is
 * exact in double, so the result must equal the Bernstein sum
 * sum C(4,i) (8-k)^(4-i) k^i P_i / 8^4 computed in integers. The first
 * derivative 4 sum (P_{i+1}-P_i) B_{i,3} is exact as well. */
static void test_bezier_dyadic(void **state)
{
    (void)state;
    const double P[5 * 2] = {3, -7, 100, 25, -40, 61, 17, -90, 5, 12};
    for (int k = 0; k <= 8; ++k) {
        double t = k / 8.0, out[2], ders[3 * 2];
        assert_int_equal(geom_curve_bezier_eval(4, 2, P, t, out), GEOM_OK);
        assert_int_equal(geom_curve_bezier_derivs(4, 2, P, t, 2, ders), GEOM_OK);
        for (int d = 0; d < 2; ++d) {
            int64_t s = 0, s1 = 0, s2 = 0;
            for (int i = 0; i <= 4; ++i) {
                int64_t b = binom(4, i);
                for (int j = 0; j < 4 - i; ++j)
                    b *= 8 - k;
                for (int j = 0; j < i; ++j)
                    b *= k;
                s += b * (int64_t)P[2 * i + d];
            }
            for (int i = 0; i <= 3; ++i) {
                int64_t b = binom(3, i);
                for (int j = 0; j < 3 - i; ++j)
                    b *= 8 - k;
                for (int j = 0; j < i; ++j)
                    b *= k;
                s1 += b * (int64_t)(P[2 * (i + 1) + d] - P[2 * i + d]);
            }
            for (int i = 0; i <= 2; ++i) {
                int64_t b = binom(2, i);
                for (int j = 0; j < 2 - i; ++j)
                    b *= 8 - k;
                for (int j = 0; j < i; ++j)
                    b *= k;
                s2 += b * (int64_t)(P[2 * (i + 2) + d] - 2 * P[2 * (i + 1) + d] + P[2 * i + d]);
            }
            assert_true(out[d] == (double)s / 4096.0);
            assert_true(ders[d] == out[d]);
            assert_true(ders[2 + d] == 4.0 * (double)s1 / 512.0);
            assert_true(ders[4 + d] == 12.0 * (double)s2 / 64.0);
        }
    }
    /* derivatives beyond the degree are exactly zero */
    double d6[7 * 2];
    assert_int_equal(geom_curve_bezier_derivs(4, 2, P, 0.3, 6, d6), GEOM_OK);
    for (int i = 5 * 2; i < 7 * 2; ++i)
        assert_true(d6[i] == 0.0);
    /* bad arguments */
    double o[2];
    assert_int_equal(geom_curve_bezier_eval(4, 2, P, NAN, o), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_curve_bezier_eval(-1, 2, P, 0.5, o), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_curve_bezier_eval(4, 0, P, 0.5, o), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_curve_bezier_derivs(4, 2, P, INFINITY, 1, d6), GEOM_ERR_INVALID_ARG);
}

/* A cubic Bezier of a known polynomial: x(t) = t^3 - 2t + 1 has control
 * points 1, 1/3, -1/3, 0 (blossoms); derivatives 3t^2 - 2, 6t, 6. */
static void test_bezier_polynomial(void **state)
{
    (void)state;
    const double P[4] = {1, 1.0 / 3, -1.0 / 3, 0};
    for (int i = 0; i <= 100; ++i) {
        double t = i / 100.0, d[4];
        assert_int_equal(geom_curve_bezier_derivs(3, 1, P, t, 3, d), GEOM_OK);
        assert_near(d[0], t * t * t - 2 * t + 1, 1e-15);
        assert_near(d[1], 3 * t * t - 2, 1e-14);
        assert_near(d[2], 6 * t, 1e-14);
        assert_near(d[3], 6, 1e-14);
    }
}

static void test_bezier_split_elevate(void **state)
{
    (void)state;
    const double P[6 * 3] = {0, 0, 0, 1, 2, 0.5, 2, -1, 1, 3, 3, -1, 4, 0.5, 2, 5, 1, 0};
    const double ts[] = {0.0, 0.3, 0.5, 0.77, 1.0};
    for (size_t k = 0; k < 5; ++k) {
        double t = ts[k], L[18], R[18];
        assert_int_equal(geom_curve_bezier_split(5, 3, P, t, L, R), GEOM_OK);
        for (int d = 0; d < 3; ++d)
            assert_true(L[15 + d] == R[d]); /* the shared point is bit-identical */
        for (int i = 0; i <= 40; ++i) {
            double s = i / 40.0, a[3], b[3], c[3];
            geom_curve_bezier_eval(5, 3, L, s, a);
            geom_curve_bezier_eval(5, 3, P, t * s, c);
            for (int d = 0; d < 3; ++d)
                assert_near(a[d], c[d], 1e-14);
            geom_curve_bezier_eval(5, 3, R, s, b);
            geom_curve_bezier_eval(5, 3, P, t + (1 - t) * s, c);
            for (int d = 0; d < 3; ++d)
                assert_near(b[d], c[d], 1e-14);
        }
    }
    double L[18];
    assert_int_equal(geom_curve_bezier_split(5, 3, P, 1.5, L, NULL), GEOM_ERR_DOMAIN);
    assert_int_equal(geom_curve_bezier_split(5, 3, P, 0.5, NULL, NULL), GEOM_OK);
    /* in place: left may alias the input */
    double Q[18];
    memcpy(Q, P, sizeof Q);
    assert_int_equal(geom_curve_bezier_split(5, 3, Q, 0.4, Q, NULL), GEOM_OK);
    double a[3], b[3];
    geom_curve_bezier_eval(5, 3, Q, 0.5, a);
    geom_curve_bezier_eval(5, 3, P, 0.2, b);
    for (int d = 0; d < 3; ++d)
        assert_near(a[d], b[d], 1e-14);

    /* elevation: a line stays evenly spaced; any curve is unchanged */
    const double line[2 * 2] = {1, 2, 4, 8};
    double e[5 * 2];
    assert_int_equal(geom_curve_bezier_elevate(1, 2, line, 3, e), GEOM_OK);
    for (int i = 0; i <= 4; ++i) {
        assert_near(e[2 * i], 1 + 3 * i / 4.0, 1e-15);
        assert_near(e[2 * i + 1], 2 + 6 * i / 4.0, 1e-15);
    }
    double E[11 * 3];
    assert_int_equal(geom_curve_bezier_elevate(5, 3, P, 5, E), GEOM_OK);
    for (int i = 0; i <= 50; ++i) {
        double t = i / 50.0;
        geom_curve_bezier_eval(5, 3, P, t, a);
        geom_curve_bezier_eval(10, 3, E, t, b);
        for (int d = 0; d < 3; ++d)
            assert_near(b[d], a[d], 1e-14);
    }
}

/* x(t) = 3t(1-t)^2 - 3t^2(1-t) (control 0, 1, -1, 0) has extremes
 * +-sqrt(3)/6 at t = (3 -+ sqrt(3))/6; y(t) = t^2 (control 0, 0, 1/3, 1)
 * has range [0, 1]. */
static void test_bezier_bbox(void **state)
{
    (void)state;
    const double P[4 * 2] = {0, 0, 1, 0, -1, 1.0 / 3, 0, 1};
    double lo[2], hi[2];
    assert_int_equal(geom_curve_bezier_bbox(3, 2, P, lo, hi), GEOM_OK);
    assert_near(lo[0], -1, 0);
    assert_near(hi[0], 1, 0);
    assert_int_equal(geom_curve_bezier_bbox_tight(3, 2, P, lo, hi), GEOM_OK);
    double r = sqrt(3.0) / 6;
    assert_true(lo[0] <= -r && hi[0] >= r); /* encloses */
    assert_near(lo[0], -r, 4e-15);
    assert_near(hi[0], r, 4e-15);
    assert_near(lo[1], 0.0, 0.0);
    assert_near(hi[1], 1.0, 0.0);
    /* a higher degree: x(t) = sin-like quintic, checked against a dense scan */
    const double Q[6] = {0, 3, -2, 4, -3, 1};
    assert_int_equal(geom_curve_bezier_bbox_tight(5, 1, Q, lo, hi), GEOM_OK);
    double smin = INFINITY, smax = -INFINITY;
    for (int i = 0; i <= 200000; ++i) {
        double v;
        geom_curve_bezier_eval(5, 1, Q, i / 200000.0, &v);
        smin = fmin(smin, v);
        smax = fmax(smax, v);
    }
    assert_true(lo[0] <= smin && hi[0] >= smax);
    assert_near(lo[0], smin, 1e-9);
    assert_near(hi[0], smax, 1e-9);
}

/* Hermite: the cubic with h00..h11 basis (closed form), its end
 * derivatives, and a Hermite spline as a C1 cubic B-spline. */
static void test_hermite(void **state)
{
    (void)state;
    const double p0[2] = {1, 2}, m0[2] = {3, -1}, p1[2] = {4, 0}, m1[2] = {-2, 5};
    double B[8];
    assert_int_equal(geom_curve_hermite_to_bezier(2, p0, m0, p1, m1, B), GEOM_OK);
    assert_near(B[2], 2, 0);
    assert_near(B[3], 2 - 1.0 / 3, 1e-16);
    assert_near(B[4], 4 + 2.0 / 3, 1e-15);
    assert_near(B[5], -5.0 / 3, 1e-15);
    for (int i = 0; i <= 32; ++i) {
        double t = i / 32.0, d[3 * 2];
        assert_int_equal(geom_curve_hermite_eval(2, p0, m0, p1, m1, t, 2, d), GEOM_OK);
        double h00 = 2 * t * t * t - 3 * t * t + 1, h10 = t * t * t - 2 * t * t + t,
               h01 = -2 * t * t * t + 3 * t * t, h11 = t * t * t - t * t;
        for (int k = 0; k < 2; ++k)
            assert_near(d[k], h00 * p0[k] + h10 * m0[k] + h01 * p1[k] + h11 * m1[k], 1e-14);
        double g00 = 6 * t * t - 6 * t, g10 = 3 * t * t - 4 * t + 1, g01 = -6 * t * t + 6 * t,
               g11 = 3 * t * t - 2 * t;
        for (int k = 0; k < 2; ++k)
            assert_near(d[2 + k], g00 * p0[k] + g10 * m0[k] + g01 * p1[k] + g11 * m1[k], 1e-13);
    }
    double d[2 * 2];
    geom_curve_hermite_eval(2, p0, m0, p1, m1, 0.0, 1, d);
    assert_true(d[0] == 1 && d[1] == 2);
    assert_near(d[2], 3, 1e-15);
    assert_near(d[3], -1, 1e-15);
    geom_curve_hermite_eval(2, p0, m0, p1, m1, 1.0, 1, d);
    assert_true(d[0] == 4 && d[1] == 0);
    assert_near(d[2], -2, 1e-14);
    assert_near(d[3], 5, 1e-14);

    /* spline through 4 points with non-uniform parameters */
    const double pts[4 * 2] = {0, 0, 1, 2, 3, 1, 4, 4};
    const double tan[4 * 2] = {1, 1, 2, 0, 0, 2, 1, 3};
    const double par[4] = {0, 0.5, 2, 2.25};
    double bz[10 * 2], U[14];
    assert_int_equal(geom_curve_hermite_spline_to_bezier(2, 4, pts, tan, par, bz), GEOM_OK);
    assert_int_equal(geom_curve_piecewise_bezier_knots(3, 3, par, U), GEOM_OK);
    geom_nurbs_curve c = {3, 10, 2, U, bz, NULL};
    assert_int_equal(geom_curve_nurbs_validate(&c, 14, NULL), GEOM_OK);
    for (int i = 0; i < 4; ++i)
        for (unsigned f = 0; f <= GEOM_CURVE_LEFT_LIMIT; ++f) {
            double dd[2 * 2];
            assert_int_equal(geom_curve_nurbs_derivs(&c, par[i], 1, f, dd), GEOM_OK);
            assert_true(dd[0] == pts[2 * i] && dd[1] == pts[2 * i + 1]);
            assert_near(dd[2], tan[2 * i], 1e-13);
            assert_near(dd[3], tan[2 * i + 1], 1e-13);
        }
    const double badpar[4] = {0, 1, 1, 2};
    assert_int_equal(geom_curve_hermite_spline_to_bezier(2, 4, pts, tan, badpar, bz),
                     GEOM_ERR_DOMAIN);
}

/* Catmull-Rom: the Bezier form equals the Barry-Goldman pyramid, passes
 * through every point, and is C1 in its own parameter. */
static void test_catmull_rom(void **state)
{
    (void)state;
    const double pts[6 * 2] = {0, 0, 1, 2, 1.1, 2, 3, 0, 4, 1, 4.5, 3};
    const double alphas[3] = {0.0, 0.5, 1.0};
    const geom_curve_end ends[3] = {GEOM_CURVE_END_EXTRAPOLATE, GEOM_CURVE_END_EXCLUDE,
                                    GEOM_CURVE_END_CLOSED};
    const size_t want_seg[3] = {5, 3, 6};
    for (int a = 0; a < 3; ++a)
        for (int e = 0; e < 3; ++e) {
            size_t nseg;
            assert_int_equal(geom_curve_catmull_rom_segments(6, ends[e], &nseg), GEOM_OK);
            assert_int_equal(nseg, want_seg[e]);
            double bz[(3 * 6 + 1) * 2], par[7];
            assert_int_equal(
                geom_curve_catmull_rom_to_bezier(2, 6, pts, alphas[a], ends[e], bz, par, NULL),
                GEOM_OK);
            size_t first = ends[e] == GEOM_CURVE_END_EXCLUDE ? 1 : 0;
            for (size_t s = 0; s < nseg; ++s) {
                size_t i1 = (first + s) % 6, i2 = (first + s + 1) % 6;
                /* interpolation: segment ends are the points, exactly */
                for (int d = 0; d < 2; ++d) {
                    assert_true(bz[3 * s * 2 + d] == pts[2 * i1 + d]);
                    assert_true(bz[(3 * s + 3) * 2 + d] == pts[2 * i2 + d]);
                }
                /* equals the Barry-Goldman pyramid on interior segments */
                int interior = ends[e] == GEOM_CURVE_END_CLOSED || (s > 0 && s + 1 < nseg) ||
                               ends[e] == GEOM_CURVE_END_EXCLUDE;
                if (!interior)
                    continue;
                size_t i0 = (i1 + 5) % 6, i3 = (i2 + 1) % 6;
                for (int k = 0; k <= 20; ++k) {
                    double t = k / 20.0, x[2], y[2];
                    assert_int_equal(geom_curve_catmull_rom_eval(2, pts + 2 * i0, pts + 2 * i1,
                                                                 pts + 2 * i2, pts + 2 * i3,
                                                                 alphas[a], t, x),
                                     GEOM_OK);
                    geom_curve_bezier_eval(3, 2, bz + 3 * s * 2, t, y);
                    assert_near(y[0], x[0], 1e-14);
                    assert_near(y[1], x[1], 1e-14);
                }
            }
            /* C1 in the Catmull-Rom parameter: a cubic B-spline with knots
             * at the joint parameters has equal one-sided derivatives */
            double U[3 * 6 + 1 + 4];
            assert_int_equal(geom_curve_piecewise_bezier_knots(3, nseg, par, U), GEOM_OK);
            geom_nurbs_curve c = {3, 3 * nseg + 1, 2, U, bz, NULL};
            for (size_t s = 1; s < nseg; ++s) {
                double l[4], r[4];
                geom_curve_nurbs_derivs(&c, par[s], 1, GEOM_CURVE_LEFT_LIMIT, l);
                geom_curve_nurbs_derivs(&c, par[s], 1, 0, r);
                assert_near(l[2], r[2], 1e-13 * (1 + fabs(r[2])));
                assert_near(l[3], r[3], 1e-13 * (1 + fabs(r[3])));
            }
        }
    /* coincident neighbours are degenerate for alpha > 0, fine for 0 */
    const double dup[4 * 2] = {0, 0, 1, 1, 1, 1, 2, 0};
    double bz[10 * 2];
    geom_diag d;
    assert_int_equal(
        geom_curve_catmull_rom_to_bezier(2, 4, dup, 0.5, GEOM_CURVE_END_EXTRAPOLATE, bz, NULL, &d),
        GEOM_ERR_DEGENERATE);
    assert_non_null(strstr(d.message, "coincide"));
    assert_int_equal(
        geom_curve_catmull_rom_to_bezier(2, 4, dup, 0.0, GEOM_CURVE_END_EXTRAPOLATE, bz, NULL, &d),
        GEOM_OK);
    assert_int_equal(
        geom_curve_catmull_rom_to_bezier(2, 3, dup, 0.5, GEOM_CURVE_END_EXCLUDE, bz, NULL, &d),
        GEOM_ERR_INVALID_ARG);
}

/* Proper crossing of segments ab and cd (strict orientation signs). */
static int crosses(const double *a, const double *b, const double *c, const double *d)
{
    double o1 = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    double o2 = (b[0] - a[0]) * (d[1] - a[1]) - (b[1] - a[1]) * (d[0] - a[0]);
    double o3 = (d[0] - c[0]) * (a[1] - c[1]) - (d[1] - c[1]) * (a[0] - c[0]);
    double o4 = (d[0] - c[0]) * (b[1] - c[1]) - (d[1] - c[1]) * (b[0] - c[0]);
    return o1 * o2 < 0 && o3 * o4 < 0;
}

/* Yuksel, Schaefer and Keyser's point: for a segment whose end points are
 * close relative to their neighbours, uniform Catmull-Rom forms a loop,
 * while the centripetal one has neither a cusp nor a self-intersection
 * (their Theorem: never, for centripetal). Checked on a dense polyline. */
static int segment_self_intersects(const double *bz, double *min_speed)
{
    enum { N = 1500 };
    static double poly[(N + 1) * 2];
    *min_speed = INFINITY;
    for (int i = 0; i <= N; ++i) {
        double d[4];
        geom_curve_bezier_derivs(3, 2, bz, i / (double)N, 1, d);
        poly[2 * i] = d[0];
        poly[2 * i + 1] = d[1];
        *min_speed = fmin(*min_speed, hypot(d[2], d[3]));
    }
    for (int i = 0; i < N; ++i)
        for (int j = i + 2; j < N; ++j)
            if (crosses(poly + 2 * i, poly + 2 * i + 2, poly + 2 * j, poly + 2 * j + 2))
                return 1;
    return 0;
}

static void test_centripetal_no_loop(void **state)
{
    (void)state;
    const double pts[4 * 2] = {0, 0, 1, 2, 1.1, 2, 3, 0};
    double bz[4 * 2], ms;
    assert_int_equal(
        geom_curve_catmull_rom_to_bezier(2, 4, pts, 0.0, GEOM_CURVE_END_EXCLUDE, bz, NULL, NULL),
        GEOM_OK);
    assert_true(segment_self_intersects(bz, &ms)); /* uniform: a loop */
    assert_int_equal(
        geom_curve_catmull_rom_to_bezier(2, 4, pts, 0.5, GEOM_CURVE_END_EXCLUDE, bz, NULL, NULL),
        GEOM_OK);
    assert_false(segment_self_intersects(bz, &ms)); /* centripetal: none */
    assert_true(ms > 0.05);                         /* and no cusp */
    assert_int_equal(
        geom_curve_catmull_rom_to_bezier(2, 4, pts, 1.0, GEOM_CURVE_END_EXCLUDE, bz, NULL, NULL),
        GEOM_OK);
    assert_false(segment_self_intersects(bz, &ms)); /* chordal: none either */
}

/* Kochanek-Bartels: zero parameters give uniform Catmull-Rom; tension 1
 * gives zero tangents; continuity and bias follow the closed forms. */
static void test_kochanek_bartels(void **state)
{
    (void)state;
    const double pts[5 * 2] = {0, 0, 1, 2, 3, 2.5, 4, 0, 6, 1};
    double cr[13 * 2], kb[16 * 2]; /* closed: 5 segments, 16 points */
    assert_int_equal(geom_curve_catmull_rom_to_bezier(2, 5, pts, 0.0, GEOM_CURVE_END_EXTRAPOLATE,
                                                      cr, NULL, NULL),
                     GEOM_OK);
    assert_int_equal(geom_curve_kochanek_bartels_to_bezier(2, 5, pts, NULL, 0,
                                                           GEOM_CURVE_END_EXTRAPOLATE, kb, NULL),
                     GEOM_OK);
    for (int i = 0; i < 13 * 2; ++i)
        assert_near(kb[i], cr[i], 1e-15);
    geom_kb_params t1 = {1.0, 0.0, 0.0};
    assert_int_equal(
        geom_curve_kochanek_bartels_to_bezier(2, 5, pts, &t1, 1, GEOM_CURVE_END_CLOSED, kb, NULL),
        GEOM_OK);
    for (int s = 0; s < 5; ++s)
        for (int d = 0; d < 2; ++d) {
            assert_true(kb[(3 * s + 1) * 2 + d] == kb[3 * s * 2 + d]);
            assert_true(kb[(3 * s + 2) * 2 + d] == kb[(3 * s + 3) * 2 + d]);
        }
    /* per-point parameters at point 2 (between segments 1 and 2) */
    geom_kb_params k[5] = {{0, 0, 0}, {0, 0, 0}, {0.2, -0.5, 0.3}, {0, 0, 0}, {0, 0, 0}};
    assert_int_equal(geom_curve_kochanek_bartels_to_bezier(2, 5, pts, k, 5,
                                                           GEOM_CURVE_END_EXTRAPOLATE, kb, NULL),
                     GEOM_OK);
    double t = 0.2, c = -0.5, b = 0.3;
    for (int d = 0; d < 2; ++d) {
        double a = pts[4 + d] - pts[2 + d], e = pts[6 + d] - pts[4 + d];
        double in = (1 - t) * ((1 + b) * (1 - c) * a + (1 - b) * (1 + c) * e) / 2;
        double out = (1 - t) * ((1 + b) * (1 + c) * a + (1 - b) * (1 - c) * e) / 2;
        /* segment 1 ends at P2 with the incoming tangent, segment 2 starts
         * at P2 with the outgoing one */
        assert_near(3 * (kb[6 * 2 + d] - kb[5 * 2 + d]), in, 1e-14);
        assert_near(3 * (kb[7 * 2 + d] - kb[6 * 2 + d]), out, 1e-14);
    }
    assert_int_equal(geom_curve_kochanek_bartels_to_bezier(2, 5, pts, k, 3,
                                                           GEOM_CURVE_END_EXTRAPOLATE, kb, NULL),
                     GEOM_ERR_INVALID_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bezier_dyadic),
        cmocka_unit_test(test_bezier_polynomial),
        cmocka_unit_test(test_bezier_split_elevate),
        cmocka_unit_test(test_bezier_bbox),
        cmocka_unit_test(test_hermite),
        cmocka_unit_test(test_catmull_rom),
        cmocka_unit_test(test_centripetal_no_loop),
        cmocka_unit_test(test_kochanek_bartels),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
