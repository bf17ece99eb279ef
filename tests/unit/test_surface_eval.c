/* Surface module: evaluation, partial derivatives and normals against closed
 * forms. References: Bernstein polynomials and the forward-difference form
 * of Bezier patch derivatives, S^(k,l) = p!/(p-k)! q!/(q-l)! sum
 * Delta^(k,l) P_ij B_(i,p-k)(u) B_(j,q-l)(v), evaluated in long double; the
 * bilinear patch; The NURBS Book Ex. 4.1 (the rational quarter circle with
 * weights {1, 1, 2}, z(u) = (1 + iu)/(1 - iu), z^(k) = 2 k! i^k /
 * (1 - iu)^(k+1)) extruded along z; normals of planar and degenerate
 * patches in closed form. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "geom/surface.h"

#include <complex.h>
#include <float.h>
#include <math.h>
#include <string.h>

static void assert_near(double got, double want, double tol)
{
    if (!(fabs(got - want) <= tol))
        fail_msg("got %.17g want %.17g (diff %.3g, tol %g)", got, want, fabs(got - want), tol);
}

typedef struct rng {
    uint64_t s;
} rng;

static double rnd(rng *r)
{
    r->s ^= r->s >> 12;
    r->s ^= r->s << 25;
    r->s ^= r->s >> 27;
    return (double)((r->s * 2685821657736338717ull) >> 11) * (1.0 / 9007199254740992.0);
}

/* ------------------------------------------------- Bezier closed form */

static long double lbinom(int n, int k)
{
    long double b = 1.0L;
    for (int i = 1; i <= k; ++i)
        b = b * (n - k + i) / i;
    return b;
}

static long double bern(int n, int i, long double t)
{
    long double r = lbinom(n, i);
    for (int k = 0; k < i; ++k)
        r *= t;
    for (int k = 0; k < n - i; ++k)
        r *= 1.0L - t;
    return r;
}

/* S^(k,l) of a Bezier patch (points (p+1) x (q+1)) by forward differences. */
static void bezier_ref(int p, int q, const double *P, double u, double v, int k, int l, double *out)
{
    long double acc[3] = {0, 0, 0};
    if (k > p || l > q) {
        out[0] = out[1] = out[2] = 0.0;
        return;
    }
    long double fk = 1.0L, fl = 1.0L;
    for (int i = 0; i < k; ++i)
        fk *= p - i;
    for (int j = 0; j < l; ++j)
        fl *= q - j;
    for (int i = 0; i <= p - k; ++i)
        for (int j = 0; j <= q - l; ++j) {
            long double d[3] = {0, 0, 0};
            for (int a = 0; a <= k; ++a)
                for (int b = 0; b <= l; ++b) {
                    long double c = lbinom(k, a) * lbinom(l, b) * (((k - a + l - b) & 1) ? -1 : 1);
                    const double *X = P + 3 * ((size_t)(i + a) * (size_t)(q + 1) + (size_t)(j + b));
                    for (int x = 0; x < 3; ++x)
                        d[x] += c * X[x];
                }
            long double B = bern(p - k, i, u) * bern(q - l, j, v);
            for (int x = 0; x < 3; ++x)
                acc[x] += d[x] * B;
        }
    for (int x = 0; x < 3; ++x)
        out[x] = (double)(acc[x] * fk * fl);
}

static void test_bezier_closed_form(void **state)
{
    (void)state;
    rng r = {12345};
    double worst = 0.0;
    for (int p = 1; p <= 9; ++p)
        for (int q = 1; q <= 6; ++q) {
            double P[3 * 10 * 7], ku[20], kv[14];
            for (int i = 0; i < 3 * (p + 1) * (q + 1); ++i)
                P[i] = 2.0 * rnd(&r) - 1.0;
            geom_nurbs_surface s;
            assert_int_equal(geom_surface_bezier(p, q, P, NULL, ku, kv, &s), GEOM_OK);
            assert_int_equal(geom_surface_validate(&s, NULL), GEOM_OK);
            const int d = 4;
            double D[3 * 25];
            for (int t = 0; t < 12; ++t) {
                double u = t < 2 ? (double)t : rnd(&r), v = t < 2 ? 1.0 - t : rnd(&r);
                assert_int_equal(geom_surface_derivs(&s, u, v, d, 0, D), GEOM_OK);
                for (int k = 0; k <= d; ++k)
                    for (int l = 0; l <= d; ++l) {
                        const double *got = D + 3 * (k * (d + 1) + l);
                        if (k + l > d || k > p || l > q) {
                            /* beyond the table or the degree: exactly zero */
                            assert_true(got[0] == 0.0 && got[1] == 0.0 && got[2] == 0.0);
                            continue;
                        }
                        double want[3];
                        bezier_ref(p, q, P, u, v, k, l, want);
                        /* scale: the largest difference coefficient times the factorials */
                        double sc = pow(2.0, k + l);
                        for (int i = 0; i < k; ++i)
                            sc *= p - i;
                        for (int j = 0; j < l; ++j)
                            sc *= q - j;
                        for (int x = 0; x < 3; ++x) {
                            double e = fabs(got[x] - want[x]) / sc;
                            worst = fmax(worst, e);
                            if (!(e <= 2e-15))
                                fail_msg("Bezier (%d,%d) S^(%d,%d)[%d] at (%g,%g): %.17g vs %.17g",
                                         p, q, k, l, x, u, v, got[x], want[x]);
                        }
                    }
                double pt[3];
                assert_int_equal(geom_surface_eval(&s, u, v, 0, pt), GEOM_OK);
                assert_memory_equal(pt, D, sizeof pt); /* S^(0,0) is the point, bit for bit */
            }
        }
    print_message("Bezier patches up to degree (9, 6), orders <= 4: worst scaled error %.3g\n",
                  worst);
}

static void test_bilinear(void **state)
{
    (void)state;
    const double a[3] = {0, 0, 0}, b[3] = {2, 0, 1}, c[3] = {0, 3, -1}, d[3] = {2, 3, 5};
    double ku[4], kv[4], P[12];
    geom_nurbs_surface s;
    assert_int_equal(geom_surface_bilinear(a, b, c, d, ku, kv, P, &s), GEOM_OK);
    for (int i = 0; i <= 8; ++i)
        for (int j = 0; j <= 8; ++j) {
            double u = i / 8.0, v = j / 8.0, D[27];
            assert_int_equal(geom_surface_derivs(&s, u, v, 2, 0, D), GEOM_OK);
            for (int x = 0; x < 3; ++x) {
                double S = (1 - u) * (1 - v) * a[x] + u * (1 - v) * b[x] + (1 - u) * v * c[x] +
                           u * v * d[x];
                double Su = (1 - v) * (b[x] - a[x]) + v * (d[x] - c[x]);
                double Sv = (1 - u) * (c[x] - a[x]) + u * (d[x] - b[x]);
                double Suv = a[x] - b[x] - c[x] + d[x];
                assert_near(D[x], S, 1e-15 * 8);
                assert_near(D[3 * 3 + x], Su, 1e-15 * 8);  /* (1,0) */
                assert_near(D[3 * 1 + x], Sv, 1e-15 * 8);  /* (0,1) */
                assert_near(D[3 * 4 + x], Suv, 1e-15 * 8); /* (1,1) */
                assert_true(D[3 * 6 + x] == 0.0 && D[3 * 2 + x] == 0.0); /* (2,0), (0,2) */
            }
        }
    /* corners are the control points exactly */
    double pt[3];
    assert_int_equal(geom_surface_eval(&s, 1.0, 1.0, 0, pt), GEOM_OK);
    assert_memory_equal(pt, d, sizeof pt);
    assert_int_equal(geom_surface_eval(&s, 1.0, 0.0, 0, pt), GEOM_OK);
    assert_memory_equal(pt, b, sizeof pt);
}

/* The NURBS Book Ex. 4.1 quarter circle, extruded by (0, 0, 2). */
static void test_ex41_extrusion(void **state)
{
    (void)state;
    const double U[6] = {0, 0, 0, 1, 1, 1};
    const double P[6] = {1, 0, 1, 1, 0, 1};
    const double W[3] = {1, 1, 2};
    geom_nurbs_curve c = {2, 3, 2, U, P, W};
    const double dir[3] = {0, 0, 2};
    double ku[6], kv[4], SP[18], SW[6];
    geom_nurbs_surface s;
    assert_int_equal(geom_surface_extrude(&c, dir, ku, kv, SP, SW, &s, NULL), GEOM_OK);
    assert_int_equal(geom_surface_validate(&s, NULL), GEOM_OK);
    const int d = 6;
    double D[3 * 49];
    for (int i = 0; i <= 16; ++i)
        for (int j = 0; j <= 4; ++j) {
            double u = i / 16.0, v = j / 4.0;
            assert_int_equal(geom_surface_derivs(&s, u, v, d, 0, D), GEOM_OK);
            double complex z = (1 + I * u) / (1 - I * u);
            assert_near(D[0], creal(z), 3e-16);
            assert_near(D[1], cimag(z), 3e-16);
            assert_near(D[2], 2.0 * v, 4e-16);
            double fact = 1.0;
            double complex ik = 1.0;
            for (int k = 1; k <= d; ++k) {
                fact *= k;
                ik *= I;
                double complex zk = 2.0 * fact * ik / cpow(1 - I * u, k + 1);
                const double *g = D + 3 * (k * (d + 1));
                double mag = cabs(zk);
                assert_near(g[0], creal(zk), 1e-14 * mag);
                assert_near(g[1], cimag(zk), 1e-14 * mag);
                assert_near(g[2], 0.0, 1e-14 * mag);
            }
            /* S_v = (0, 0, 2); every other mixed or v derivative is 0 */
            const double *sv = D + 3 * 1;
            assert_near(sv[0], 0.0, 1e-15);
            assert_near(sv[1], 0.0, 1e-15);
            assert_near(sv[2], 2.0, 1e-15);
            for (int k = 0; k <= d; ++k)
                for (int l = 1; k + l <= d; ++l) {
                    if (k == 0 && l == 1)
                        continue;
                    const double *g = D + 3 * (k * (d + 1) + l);
                    for (int x = 0; x < 3; ++x)
                        assert_near(g[x], 0.0, 1e-12 * pow(4.0, k));
                }
        }
}

/* Two quadratic pieces in u joined at u = 1 by a knot of multiplicity 3
 * (a discontinuity): the left limit is the first piece's end row, the
 * right limit the second piece's start row. */
static void test_one_sided_limits(void **state)
{
    (void)state;
    const double ku[9] = {0, 0, 0, 1, 1, 1, 2, 2, 2};
    const double kv[4] = {0, 0, 1, 1};
    double P[6 * 2 * 3];
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 2; ++j) {
            double *X = P + 3 * (i * 2 + j);
            X[0] = i;
            X[1] = j;
            X[2] = i < 3 ? 0.0 : 10.0; /* the jump */
        }
    geom_nurbs_surface s = {2, 1, 6, 2, ku, kv, P, NULL};
    assert_int_equal(geom_surface_validate(&s, NULL), GEOM_OK);
    double a[3], b[3];
    assert_int_equal(geom_surface_eval(&s, 1.0, 0.25, 0, a), GEOM_OK);
    assert_int_equal(geom_surface_eval(&s, 1.0, 0.25, GEOM_SURFACE_U_LEFT, b), GEOM_OK);
    /* right: row 3 (x = 3, z = 10); left: row 2 (x = 2, z = 0) */
    assert_near(a[0], 3.0, 0.0);
    assert_near(a[2], 10.0, 0.0);
    assert_near(b[0], 2.0, 0.0);
    assert_near(b[2], 0.0, 0.0);
    assert_near(a[1], 0.25, 1e-16);
    /* V_LEFT changes nothing in v (no interior knot) */
    assert_int_equal(geom_surface_eval(&s, 1.0, 0.25, GEOM_SURFACE_V_LEFT, b), GEOM_OK);
    assert_memory_equal(a, b, sizeof a);
    /* the end of the domain is the last piece's end */
    assert_int_equal(geom_surface_eval(&s, 2.0, 1.0, 0, a), GEOM_OK);
    assert_memory_equal(a, P + 3 * 11, sizeof a);
}

static void test_argument_errors(void **state)
{
    (void)state;
    const double ku[4] = {0, 0, 1, 1}, kv[4] = {0, 0, 1, 1};
    double P[12] = {0, 0, 0, 0, 1, 0, 1, 0, 0, 1, 1, 0};
    double W[4] = {1, 1, 1, 1};
    geom_nurbs_surface s = {1, 1, 2, 2, ku, kv, P, NULL};
    double out[3], D[27];
    assert_int_equal(geom_surface_eval(&s, NAN, 0.5, 0, out), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_surface_eval(&s, 0.5, INFINITY, 0, out), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_surface_eval(&s, 1.0000000000000002, 0.5, 0, out), GEOM_ERR_DOMAIN);
    assert_int_equal(geom_surface_eval(&s, 0.5, -1e-300, 0, out), GEOM_ERR_DOMAIN);
    assert_int_equal(geom_surface_eval(NULL, 0.5, 0.5, 0, out), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_surface_eval(&s, 0.5, 0.5, 0, NULL), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_surface_derivs(&s, 0.5, 0.5, -1, 0, D), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_surface_derivs(&s, 0.5, 0.5, 65, 0, D), GEOM_ERR_LIMIT);
    double dom[4];
    assert_int_equal(geom_surface_domain(&s, dom), GEOM_OK);
    assert_true(dom[0] == 0 && dom[1] == 1 && dom[2] == 0 && dom[3] == 1);

    geom_diag d;
    const double bad_u[4] = {0, 0.5, 0.2, 1};
    geom_nurbs_surface b = s;
    b.knots_u = bad_u;
    assert_int_equal(geom_surface_validate(&b, &d), GEOM_ERR_INVALID_ARG);
    assert_non_null(strstr(d.message, "knots_u"));
    b = s;
    W[2] = -1.0;
    b.weights = W;
    assert_int_equal(geom_surface_validate(&b, &d), GEOM_ERR_INVALID_ARG);
    assert_non_null(strstr(d.message, "weight (1, 0)"));
    b = s;
    P[4] = NAN;
    assert_int_equal(geom_surface_validate(&b, &d), GEOM_ERR_INVALID_ARG);
    assert_non_null(strstr(d.message, "point (0, 1)"));
    P[4] = 1.0;
    b = s;
    b.nv = 1;
    assert_int_equal(geom_surface_validate(&b, &d), GEOM_ERR_INVALID_ARG);
    b = s;
    b.degree_v = 0;
    assert_int_equal(geom_surface_validate(&b, &d), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_surface_validate(NULL, &d), GEOM_ERR_INVALID_ARG);
}

/* ---------------------------------------------------------------- normals */

static void check_unit(const double *n, double x, double y, double z, double tol)
{
    assert_near(n[0], x, tol);
    assert_near(n[1], y, tol);
    assert_near(n[2], z, tol);
}

static void test_normals_planar_and_degenerate(void **state)
{
    (void)state;
    /* a planar "triangle": the edge v = 1 collapsed to (0, 1, 0):
     * S = ((1-v)u, v, 0), Su x Sv = (0, 0, 1-v) */
    const double a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, c[3] = {0, 1, 0};
    double ku[4], kv[4], P[12];
    geom_nurbs_surface s;
    assert_int_equal(geom_surface_bilinear(a, b, c, c, ku, kv, P, &s), GEOM_OK);
    double n[3];
    int how = -1;
    assert_int_equal(geom_surface_normal(&s, 0.3, 0.5, 0, n, &how), GEOM_OK);
    assert_int_equal(how, GEOM_SURFACE_NORMAL_REGULAR);
    check_unit(n, 0, 0, 1, 0.0);
    for (int i = 0; i <= 4; ++i) {
        assert_int_equal(geom_surface_normal(&s, i / 4.0, 1.0, 0, n, &how), GEOM_OK);
        assert_int_equal(how, GEOM_SURFACE_NORMAL_LIMIT);
        check_unit(n, 0, 0, 1, 0.0);
    }
    /* bicubic planar patch whose corner (0,0) has P00 = P10 = P01: both
     * S_u and S_v vanish there; the limit along the diagonal is +z */
    double Q[48], qu[8], qv[8];
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            double *X = Q + 3 * (i * 4 + j);
            X[0] = i + 0.1 * j * j;
            X[1] = j + 0.05 * i * j;
            X[2] = 0.0;
        }
    memcpy(Q + 3 * 4, Q, 3 * sizeof(double)); /* P10 = P00 */
    memcpy(Q + 3 * 1, Q, 3 * sizeof(double)); /* P01 = P00 */
    assert_int_equal(geom_surface_bezier(3, 3, Q, NULL, qu, qv, &s), GEOM_OK);
    assert_int_equal(geom_surface_normal(&s, 0.0, 0.0, 0, n, &how), GEOM_OK);
    assert_int_equal(how, GEOM_SURFACE_NORMAL_LIMIT);
    check_unit(n, 0, 0, 1, 0.0);
    /* curved version: the limit agrees with nearby regular normals */
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            Q[3 * (i * 4 + j) + 2] = 0.3 * i * j - 0.2 * i * i + 0.1 * j;
    memcpy(Q + 3 * 4, Q, 3 * sizeof(double));
    memcpy(Q + 3 * 1, Q, 3 * sizeof(double));
    assert_int_equal(geom_surface_normal(&s, 0.0, 0.0, 0, n, &how), GEOM_OK);
    assert_int_equal(how, GEOM_SURFACE_NORMAL_LIMIT);
    double m[3];
    assert_int_equal(geom_surface_normal(&s, 1e-7, 1e-7, 0, m, &how), GEOM_OK);
    assert_int_equal(how, GEOM_SURFACE_NORMAL_REGULAR);
    double dot = n[0] * m[0] + n[1] * m[1] + n[2] * m[2];
    assert_true(dot > 1.0 - 1e-10);
    /* a surface that is a single point has no normal: zeros, never NaN */
    for (int i = 0; i < 16; ++i)
        memcpy(Q + 3 * i, a, 3 * sizeof(double));
    assert_int_equal(geom_surface_normal(&s, 0.5, 0.5, 0, n, &how), GEOM_ERR_DEGENERATE);
    assert_int_equal(how, GEOM_SURFACE_NORMAL_NONE);
    check_unit(n, 0, 0, 0, 0.0);
}

/* Normals of a rational patch against Su x Sv from the closed-form
 * derivatives (Ex. 4.1 extrusion: Su = z'(u), Sv = (0,0,2)). */
static void test_normals_rational(void **state)
{
    (void)state;
    const double U[6] = {0, 0, 0, 1, 1, 1};
    const double P[6] = {1, 0, 1, 1, 0, 1};
    const double W[3] = {1, 1, 2};
    geom_nurbs_curve c = {2, 3, 2, U, P, W};
    const double dir[3] = {0, 0, 2};
    double ku[6], kv[4], SP[18], SW[6];
    geom_nurbs_surface s;
    assert_int_equal(geom_surface_extrude(&c, dir, ku, kv, SP, SW, &s, NULL), GEOM_OK);
    for (int i = 0; i <= 32; ++i) {
        double u = i / 32.0, n[3];
        assert_int_equal(geom_surface_normal(&s, u, 0.5, 0, n, NULL), GEOM_OK);
        /* Su x Sv = (x', y', 0) x (0,0,2) = 2 (y', -x', 0): the outward
         * radial direction z(u) of the circle */
        double complex z = (1 + I * u) / (1 - I * u);
        check_unit(n, creal(z), cimag(z), 0.0, 4e-16);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bezier_closed_form),
        cmocka_unit_test(test_bilinear),
        cmocka_unit_test(test_ex41_extrusion),
        cmocka_unit_test(test_one_sided_limits),
        cmocka_unit_test(test_argument_errors),
        cmocka_unit_test(test_normals_planar_and_degenerate),
        cmocka_unit_test(test_normals_rational),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
