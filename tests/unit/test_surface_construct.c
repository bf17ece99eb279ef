/* Surface module: exact constructions against their closed forms (implicit
 * equations of the sphere, torus, cylinder and cone; rotation by Rodrigues'
 * formula for revolutions; the ruled surface's boundary curves and its
 * homogeneous interpolation), and the exact normals of those shapes,
 * including the limit normals at the poles and at a cone's apex. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "geom/surface.h"

#include <float.h>
#include <math.h>
#include <string.h>

#define PI 3.14159265358979323846
#define EPS DBL_EPSILON

static void assert_near(double got, double want, double tol)
{
    if (!(fabs(got - want) <= tol))
        fail_msg("got %.17g want %.17g (diff %.3g, tol %g)", got, want, fabs(got - want), tol);
}

static double len3(const double *a)
{
    return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
}

static void sub3(const double *a, const double *b, double *c)
{
    c[0] = a[0] - b[0], c[1] = a[1] - b[1], c[2] = a[2] - b[2];
}

static double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Every point of the exact sphere lies at radius r within a few ulp; the
 * normal is the radial direction, also at the poles (limit normals). */
static void test_sphere(void **state)
{
    (void)state;
    const double r = 2.5;
    geom_surface_frame f = {{1, -2, 3}, {0, 0, 1}, {1, 0, 0}};
    double ku[12], kv[8], P[135], W[45];
    geom_nurbs_surface s;
    assert_int_equal(geom_surface_sphere(&f, r, ku, kv, P, W, &s), GEOM_OK);
    assert_int_equal(geom_surface_validate(&s, NULL), GEOM_OK);
    assert_int_equal((int)s.nu, 9);
    assert_int_equal((int)s.nv, 5);
    /* the seam rows are identical, the pole rows collapse exactly */
    assert_memory_equal(P, P + 3 * 8 * 5, 5 * 3 * sizeof(double));
    for (int i = 0; i < 9; ++i) {
        const double south[3] = {1, -2, 3 - r}, north[3] = {1, -2, 3 + r};
        assert_memory_equal(P + 3 * (i * 5), south, sizeof south);
        assert_memory_equal(P + 3 * (i * 5 + 4), north, sizeof north);
    }
    double worst = 0.0, worst_n = 0.0;
    for (int i = 0; i <= 64; ++i)
        for (int j = 0; j <= 64; ++j) {
            double u = i / 64.0, v = j / 64.0, S[3], d[3], n[3];
            int how;
            assert_int_equal(geom_surface_eval(&s, u, v, 0, S), GEOM_OK);
            sub3(S, f.center, d);
            double e = fabs(len3(d) - r) / r;
            worst = fmax(worst, e);
            assert_true(e <= 4 * EPS);
            assert_int_equal(geom_surface_normal(&s, u, v, 0, n, &how), GEOM_OK);
            assert_int_equal(how, (j == 0 || j == 64) ? GEOM_SURFACE_NORMAL_LIMIT
                                                      : GEOM_SURFACE_NORMAL_REGULAR);
            double en = 0.0;
            for (int k = 0; k < 3; ++k)
                en = fmax(en, fabs(n[k] - d[k] / r));
            worst_n = fmax(worst_n, en);
            assert_true(en <= 8 * EPS);
        }
    print_message("sphere: radius within %.3g relative, normals within %.3g\n", worst, worst_n);
    /* longitude and latitude in closed form: S(u, v) at u = 1/8 (45
     * degrees), v = 1/2 (the equator) */
    double S[3];
    assert_int_equal(geom_surface_eval(&s, 0.125, 0.5, 0, S), GEOM_OK);
    assert_near(S[0], 1 + r * sqrt(0.5), 4 * EPS * 4);
    assert_near(S[1], -2 + r * sqrt(0.5), 4 * EPS * 4);
    assert_near(S[2], 3.0, 4 * EPS * 4);
}

static void test_torus(void **state)
{
    (void)state;
    const double R = 3.0, r = 0.75;
    double ku[12], kv[12], P[243], W[81];
    geom_nurbs_surface s;
    assert_int_equal(geom_surface_torus(NULL, R, r, ku, kv, P, W, &s), GEOM_OK);
    assert_int_equal(geom_surface_validate(&s, NULL), GEOM_OK);
    for (int i = 0; i < 9; ++i)
        assert_memory_equal(P + 3 * (i * 9), P + 3 * (i * 9 + 8), 3 * sizeof(double));
    for (int i = 0; i <= 48; ++i)
        for (int j = 0; j <= 48; ++j) {
            double u = i / 48.0, v = j / 48.0, S[3], n[3];
            assert_int_equal(geom_surface_eval(&s, u, v, 0, S), GEOM_OK);
            double rho = hypot(S[0], S[1]);
            double e = hypot(rho - R, S[2]) - r;
            assert_true(fabs(e) <= 8 * EPS * (R + r));
            /* normal: from the tube's centre circle outward */
            assert_int_equal(geom_surface_normal(&s, u, v, 0, n, NULL), GEOM_OK);
            double c[3] = {R * S[0] / rho, R * S[1] / rho, 0.0}, d[3];
            sub3(S, c, d);
            for (int k = 0; k < 3; ++k)
                assert_near(n[k], d[k] / r, 32 * EPS);
        }
    /* u = 0, v = 0 is the outer equator at +x */
    double S[3];
    assert_int_equal(geom_surface_eval(&s, 0.0, 0.0, 0, S), GEOM_OK);
    assert_true(S[0] == R + r && S[1] == 0.0 && S[2] == 0.0);
}

static void test_cylinder_and_cone(void **state)
{
    (void)state;
    const double r = 1.5, h = 4.0;
    double ku[12], kv[4], P[54], W[18];
    geom_nurbs_surface s;
    assert_int_equal(geom_surface_cylinder(NULL, r, h, ku, kv, P, W, &s), GEOM_OK);
    for (int i = 0; i <= 32; ++i)
        for (int j = 0; j <= 4; ++j) {
            double u = i / 32.0, v = j / 4.0, S[3], n[3];
            assert_int_equal(geom_surface_eval(&s, u, v, 0, S), GEOM_OK);
            assert_near(hypot(S[0], S[1]), r, 4 * EPS * r);
            assert_near(S[2], h * v, 4 * EPS * h);
            assert_int_equal(geom_surface_normal(&s, u, v, 0, n, NULL), GEOM_OK);
            assert_near(n[0], S[0] / r, 8 * EPS);
            assert_near(n[1], S[1] / r, 8 * EPS);
            assert_near(n[2], 0.0, 8 * EPS);
        }
    /* cone: radius 2 at z = 0 closing to an apex at z = 3. The normal along
     * the ruling at angle t is (h cos t, h sin t, r0) / sqrt(h^2 + r0^2),
     * at the apex too (the limit along that ruling). */
    const double r0 = 2.0, hc = 3.0;
    assert_int_equal(geom_surface_cone(NULL, r0, 0.0, hc, ku, kv, P, W, &s), GEOM_OK);
    for (int i = 0; i <= 32; ++i)
        for (int j = 0; j <= 4; ++j) {
            double u = i / 32.0, v = j / 4.0, S[3], n[3];
            int how;
            assert_int_equal(geom_surface_eval(&s, u, v, 0, S), GEOM_OK);
            assert_near(hypot(S[0], S[1]), r0 * (1 - v), 8 * EPS * r0);
            assert_int_equal(geom_surface_normal(&s, u, v, 0, n, &how), GEOM_OK);
            assert_int_equal(how, j == 4 ? GEOM_SURFACE_NORMAL_LIMIT : GEOM_SURFACE_NORMAL_REGULAR);
            /* the ruling's angle from a point of the base circle at u */
            double B[3];
            assert_int_equal(geom_surface_eval(&s, u, 0.0, 0, B), GEOM_OK);
            double t = atan2(B[1], B[0]), l = hypot(hc, r0);
            assert_near(n[0], hc * cos(t) / l, 16 * EPS);
            assert_near(n[1], hc * sin(t) / l, 16 * EPS);
            assert_near(n[2], r0 / l, 16 * EPS);
        }
    assert_int_equal(geom_surface_cone(NULL, 0.0, 0.0, 1.0, ku, kv, P, W, &s), GEOM_ERR_DOMAIN);
    assert_int_equal(geom_surface_cylinder(NULL, 1.0, 0.0, ku, kv, P, W, &s), GEOM_ERR_DOMAIN);
    assert_int_equal(geom_surface_sphere(NULL, -1.0, ku, kv, P, W, &s), GEOM_ERR_DOMAIN);
    geom_surface_frame bad = {{0, 0, 0}, {0, 0, 1}, {1, 0, 0.1}};
    assert_int_equal(geom_surface_sphere(&bad, 1.0, ku, kv, P, W, &s), GEOM_ERR_INVALID_ARG);
}

/* Rodrigues: v rotated by angle t about the unit axis k. */
static void rotate(const double *v, const double *k, double t, double *out)
{
    double c = cos(t), sn = sin(t), kv = dot3(k, v);
    double x[3] = {k[1] * v[2] - k[2] * v[1], k[2] * v[0] - k[0] * v[2], k[0] * v[1] - k[1] * v[0]};
    for (int i = 0; i < 3; ++i)
        out[i] = v[i] * c + x[i] * sn + k[i] * kv * (1 - c);
}

static void test_revolve(void **state)
{
    (void)state;
    /* a cubic 3D profile revolved about a tilted axis through o */
    const double U[8] = {0, 0, 0, 0, 1, 1, 1, 1};
    const double Q[12] = {2, 0, 0, 2.5, 1, 1, 1.5, 2, 2, 2, 0.5, 3};
    const double o[3] = {0.5, -1, 0.25}, ax[3] = {1, 2, 2};
    const double k[3] = {1 / 3.0, 2 / 3.0, 2 / 3.0};
    geom_nurbs_curve c = {3, 4, 3, U, Q, NULL};
    for (int t = 0; t < 3; ++t) {
        double angle = t == 0 ? 2 * PI : (t == 1 ? 0.75 * PI : -2.0);
        size_t nu, nk;
        assert_int_equal(geom_surface_revolve_bound(angle, &nu, &nk), GEOM_OK);
        double ku[16], kv[8], P[3 * 9 * 4], W[9 * 4];
        geom_nurbs_surface s;
        assert_int_equal(geom_surface_revolve(&c, o, ax, NULL, angle, ku, kv, P, W, &s, NULL),
                         GEOM_OK);
        assert_int_equal((int)s.nu, (int)nu);
        assert_int_equal(geom_surface_validate(&s, NULL), GEOM_OK);
        for (int j = 0; j <= 8; ++j) {
            double v = j / 8.0, C[3], d[3];
            assert_int_equal(geom_curve_nurbs_eval(&c, v, 0, C), GEOM_OK);
            sub3(C, o, d);
            for (int i = 0; i <= 16; ++i) {
                double u = i / 16.0, S[3], want[3];
                assert_int_equal(geom_surface_eval(&s, u, v, 0, S), GEOM_OK);
                /* the surface point is the profile point turned about the
                 * axis; its angle follows the rational arc, so compare the
                 * invariants: height along the axis and distance from it */
                double e[3];
                sub3(S, o, e);
                assert_near(dot3(e, k), dot3(d, k), 32 * EPS);
                double pe[3] = {e[0] - dot3(e, k) * k[0], e[1] - dot3(e, k) * k[1],
                                e[2] - dot3(e, k) * k[2]};
                double pd[3] = {d[0] - dot3(d, k) * k[0], d[1] - dot3(d, k) * k[1],
                                d[2] - dot3(d, k) * k[2]};
                assert_near(len3(pe), len3(pd), 32 * EPS);
                if (i == 16) { /* the end of the sweep: turned by the whole angle */
                    rotate(d, k, angle, want);
                    for (int x = 0; x < 3; ++x)
                        assert_near(S[x], o[x] + want[x], 64 * EPS);
                }
                if (i == 0)
                    for (int x = 0; x < 3; ++x)
                        assert_near(S[x], C[x], 8 * EPS);
            }
        }
    }
    double ku[16], kv[8], P[3 * 9 * 4], W[9 * 4];
    geom_nurbs_surface s;
    const double zero[3] = {0, 0, 0};
    assert_int_equal(geom_surface_revolve(&c, o, zero, NULL, PI, ku, kv, P, W, &s, NULL),
                     GEOM_ERR_DEGENERATE);
    assert_int_equal(geom_surface_revolve(&c, o, ax, NULL, 7.0, ku, kv, P, W, &s, NULL),
                     GEOM_ERR_DOMAIN);
    assert_int_equal(geom_surface_revolve(&c, o, ax, NULL, 0.0, ku, kv, P, W, &s, NULL),
                     GEOM_ERR_DOMAIN);
}

/* Homogeneous weight function w(u) = sum N_i(u) w_i of a curve. */
static double weight_fn(const geom_nurbs_curve *c, double u)
{
    if (!c->weights)
        return 1.0;
    double N[16];
    size_t span;
    assert_int_equal(geom_curve_bspline_basis(c->degree, c->n, c->knots, u, 0, &span, N),
                     GEOM_OK);
    double w = 0.0;
    for (int j = 0; j <= c->degree; ++j)
        w += N[j] * c->weights[span - (size_t)c->degree + (size_t)j];
    return w;
}

static void test_ruled_and_extrude(void **state)
{
    (void)state;
    /* c0: a cubic B-spline on [2, 5] with an interior knot; c1: the Ex. 4.1
     * rational quarter circle (2D, z = 0) */
    const double U0[9] = {2, 2, 2, 2, 3.5, 5, 5, 5, 5};
    const double Q0[15] = {0, 0, 1, 1, 0, 2, 2, 1, 1, 3, 0, 2, 4, 1, 1};
    const double U1[6] = {0, 0, 0, 1, 1, 1};
    const double Q1[6] = {1, 0, 1, 1, 0, 1};
    const double W1[3] = {1, 1, 2};
    geom_nurbs_curve c0 = {3, 5, 3, U0, Q0, NULL};
    geom_nurbs_curve c1 = {2, 3, 2, U1, Q1, W1};
    size_t nu, nk;
    assert_int_equal(geom_surface_ruled_bound(&c0, &c1, &nu, &nk), GEOM_OK);
    assert_true(nu >= 5 && nk == nu + 4);
    double ku[64], kv[4], P[3 * 2 * 60], W[2 * 60];
    assert_true(nk <= 64 && nu <= 60);
    geom_nurbs_surface s;
    assert_int_equal(geom_surface_ruled(&c0, &c1, ku, kv, P, W, &s, NULL), GEOM_OK);
    assert_int_equal(geom_surface_validate(&s, NULL), GEOM_OK);
    assert_int_equal(s.degree_u, 3);
    assert_int_equal(s.degree_v, 1);
    assert_int_equal((int)s.nu, (int)nu);
    for (int i = 0; i <= 40; ++i) {
        double t = i / 40.0, A[3], B[3] = {0, 0, 0};
        double u0 = 2.0 + 3.0 * t;
        assert_int_equal(geom_curve_nurbs_eval(&c0, u0, 0, A), GEOM_OK);
        assert_int_equal(geom_curve_nurbs_eval(&c1, t, 0, B), GEOM_OK);
        double w0 = weight_fn(&c0, u0), w1 = weight_fn(&c1, t);
        for (int j = 0; j <= 4; ++j) {
            double v = j / 4.0, S[3];
            assert_int_equal(geom_surface_eval(&s, t, v, 0, S), GEOM_OK);
            for (int x = 0; x < 3; ++x) {
                double want = ((1 - v) * w0 * A[x] + v * w1 * B[x]) / ((1 - v) * w0 + v * w1);
                assert_near(S[x], want, 1e-14);
            }
        }
    }
    /* extrusion of the same quarter circle: S = C(u) + v d */
    const double d[3] = {0.5, -1, 3};
    double eku[6], ekv[4], EP[18], EW[6];
    assert_int_equal(geom_surface_extrude(&c1, d, eku, ekv, EP, EW, &s, NULL), GEOM_OK);
    for (int i = 0; i <= 16; ++i)
        for (int j = 0; j <= 4; ++j) {
            double u = i / 16.0, v = j / 4.0, C[2], S[3];
            assert_int_equal(geom_curve_nurbs_eval(&c1, u, 0, C), GEOM_OK);
            assert_int_equal(geom_surface_eval(&s, u, v, 0, S), GEOM_OK);
            assert_near(S[0], C[0] + v * d[0], 4 * EPS * 4);
            assert_near(S[1], C[1] + v * d[1], 4 * EPS * 4);
            assert_near(S[2], v * d[2], 4 * EPS * 4);
        }
    const double zero[3] = {0, 0, 0};
    assert_int_equal(geom_surface_extrude(&c1, zero, eku, ekv, EP, EW, &s, NULL),
                     GEOM_ERR_DEGENERATE);
    double bk[8];
    assert_int_equal(geom_surface_bezier_knots(3, bk), GEOM_OK);
    assert_true(bk[3] == 0.0 && bk[4] == 1.0);
    assert_int_equal(geom_surface_bezier_knots(0, bk), GEOM_ERR_INVALID_ARG);
}

/* The data file's sphere and torus (data/surfaces.json, written from the
 * textbook control nets) are the constructors' nets: checked in
 * tests/tools/test_geom_tessellate.sh, which reads the file. Here: the
 * textbook net of the unit sphere written out by hand. */
static void test_sphere_net(void **state)
{
    (void)state;
    const double s2 = 0.70710678118654757; /* sqrt(2)/2 as a double */
    const double cx[9] = {1, 1, 0, -1, -1, -1, 0, 1, 1}, cy[9] = {0, 1, 1, 1, 0, -1, -1, -1, 0};
    const double px[5] = {0, 1, 1, 1, 0}, pz[5] = {-1, -1, 0, 1, 1};
    const double cw[9] = {1, s2, 1, s2, 1, s2, 1, s2, 1}, pw[5] = {1, s2, 1, s2, 1};
    double ku[12], kv[8], P[135], W[45];
    geom_nurbs_surface s;
    assert_int_equal(geom_surface_sphere(NULL, 1.0, ku, kv, P, W, &s), GEOM_OK);
    for (int i = 0; i < 9; ++i)
        for (int j = 0; j < 5; ++j) {
            const double *X = P + 3 * (i * 5 + j);
            assert_true(X[0] == cx[i] * px[j] && X[1] == cy[i] * px[j] && X[2] == pz[j]);
            assert_near(W[i * 5 + j], cw[i] * pw[j], EPS);
        }
    const double kuw[12] = {0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1};
    const double kvw[8] = {0, 0, 0, 0.5, 0.5, 1, 1, 1};
    assert_memory_equal(ku, kuw, sizeof kuw);
    assert_memory_equal(kv, kvw, sizeof kvw);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sphere),
        cmocka_unit_test(test_torus),
        cmocka_unit_test(test_cylinder_and_cone),
        cmocka_unit_test(test_revolve),
        cmocka_unit_test(test_ruled_and_extrude),
        cmocka_unit_test(test_sphere_net),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
