/*
 * Barycentric coordinates: closed forms, exact zeros on edges and exact unit
 * vectors at vertices, degenerate and non-finite input, tetrahedra, 3D
 * triangles with off-plane points, mean value and Wachspress coordinates,
 * interpolation, and perspective correction checked against a perspective
 * projection built by hand.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>

#include "geom/bary.h"

#define PI 3.14159265358979323846

static int has_nan(const double *v, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (isnan(v[i]))
            return 1;
    return 0;
}

static void assert_close(double x, double y, double tol)
{
    if (!(fabs(x - y) <= tol))
        fail_msg("%.17g != %.17g (tol %g)", x, y, tol);
}

static uint64_t rng_state = 0x2545f4914f6cdd1dull;
static double urand(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) * 0x1p-53;
}

/* ------------------------------------------------------------- triangle 2D */

static void test_tri2_closed_form(void **state)
{
    (void)state;
    const double a[2] = {0, 0}, b[2] = {1, 0}, c[2] = {0, 1}, p[2] = {0.25, 0.5};
    double l[3];
    assert_int_equal(geom_bary_tri2(a, b, c, p, l), GEOM_OK);
    assert_true(l[0] == 0.25 && l[1] == 0.25 && l[2] == 0.5);
    /* clockwise order gives the same coordinates for the same vertices */
    assert_int_equal(geom_bary_tri2(a, c, b, p, l), GEOM_OK);
    assert_true(l[0] == 0.25 && l[1] == 0.5 && l[2] == 0.25);
    /* outside: negative coordinate with the exact value */
    const double q[2] = {-0.5, 0.25};
    assert_int_equal(geom_bary_tri2(a, b, c, q, l), GEOM_OK);
    assert_true(l[0] == 1.25 && l[1] == -0.5 && l[2] == 0.25);

    /* A general triangle with p = (3a + 4b + c) / 8, all dyadic: the exact
     * coordinates are (3/8, 1/2, 1/8) and linear precision holds. */
    const double A[2] = {1.25, -3.5}, B[2] = {7.75, 2.0}, C[2] = {-2.5, 6.25};
    double P[2];
    for (int k = 0; k < 2; k++)
        P[k] = (3 * A[k] + 4 * B[k] + C[k]) / 8;
    assert_int_equal(geom_bary_tri2(A, B, C, P, l), GEOM_OK);
    assert_close(l[0], 0.375, 1e-15);
    assert_close(l[1], 0.5, 1e-15);
    assert_close(l[2], 0.125, 1e-15);
    assert_close(l[0] + l[1] + l[2], 1.0, 4e-16);
}

static void test_tri2_vertices_edges(void **state)
{
    (void)state;
    /* generic (not axis-aligned) triangles, random and dyadic */
    for (int it = 0; it < 2000; it++) {
        double v[3][2];
        for (int i = 0; i < 3; i++)
            for (int k = 0; k < 2; k++)
                v[i][k] = (urand() - 0.5) * 100.0 + (it % 2 ? 1e6 : 0.0);
        double l[3];
        for (int i = 0; i < 3; i++) {
            assert_int_equal(geom_bary_tri2(v[0], v[1], v[2], v[i], l), GEOM_OK);
            for (int j = 0; j < 3; j++)
                assert_true(l[j] == (i == j ? 1.0 : 0.0));
        }
        /* points exactly on the edges: a + t (b - a) rounded is not on the
         * edge in general, so use the exact dyadic midpoint of a dyadic
         * edge. */
        double w[3][2];
        for (int i = 0; i < 3; i++)
            for (int k = 0; k < 2; k++)
                w[i][k] = ldexp(floor(ldexp(v[i][k], 20)), -20); /* 2^-20 grid */
        for (int e = 0; e < 3; e++) {
            int i = (e + 1) % 3, j = (e + 2) % 3; /* edge opposite vertex e */
            double m[2] = {(w[i][0] + w[j][0]) / 2, (w[i][1] + w[j][1]) / 2};
            geom_status st = geom_bary_tri2(w[0], w[1], w[2], m, l);
            assert_int_equal(st, GEOM_OK);
            assert_true(l[e] == 0.0);
            assert_close(l[i], 0.5, 1e-12);
            assert_close(l[j], 0.5, 1e-12);
        }
    }
    /* axis-aligned edges */
    const double a[2] = {0, 0}, b[2] = {4, 0}, c[2] = {0, 3}, p[2] = {1, 0};
    double l[3];
    assert_int_equal(geom_bary_tri2(a, b, c, p, l), GEOM_OK);
    assert_true(l[0] == 0.75 && l[1] == 0.25 && l[2] == 0.0);
}

static void test_tri2_degenerate_invalid(void **state)
{
    (void)state;
    double l[3] = {7, 7, 7};
    const double a[2] = {0, 0}, b[2] = {1, 1}, c[2] = {3, 3}, p[2] = {0.5, 0.2};
    assert_int_equal(geom_bary_tri2(a, b, c, p, l), GEOM_ERR_DEGENERATE);
    assert_true(l[0] == 0.0 && l[1] == 0.0 && l[2] == 0.0);
    assert_int_equal(geom_bary_tri2(a, a, a, a, l), GEOM_ERR_DEGENERATE);
    assert_true(l[0] == 0.0 && l[1] == 0.0 && l[2] == 0.0);
    /* nearly collinear but not: must not be degenerate */
    const double c2[2] = {3, 3 + 0x1p-51};
    assert_int_equal(geom_bary_tri2(a, b, c2, p, l), GEOM_OK);
    assert_false(has_nan(l, 3));
    /* collinear after rounding of the naive formula, exactly collinear here */
    const double d1[2] = {0.1, 0.3}, d2[2] = {0.2, 0.6}, d3[2] = {0.4, 1.2};
    assert_int_equal(geom_bary_tri2(d1, d2, d3, p, l), GEOM_ERR_DEGENERATE);

    const double bad[3] = {NAN, INFINITY, -INFINITY};
    for (int k = 0; k < 3; k++) {
        for (int pos = 0; pos < 8; pos++) {
            double v[8] = {0, 0, 1, 0, 0, 1, 0.2, 0.2};
            v[pos] = bad[k];
            l[0] = l[1] = l[2] = 5;
            assert_int_equal(geom_bary_tri2(v, v + 2, v + 4, v + 6, l), GEOM_ERR_INVALID_ARG);
            assert_true(l[0] == 0.0 && l[1] == 0.0 && l[2] == 0.0);
        }
    }
    assert_int_equal(geom_bary_tri2(NULL, b, c, p, l), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_bary_tri2(a, b, c, p, NULL), GEOM_ERR_INVALID_ARG);
}

/* Random triangles and points: sum 1, linear precision, and the sign of each
 * coordinate equals the sign of the exact orientation predicate. */
static void test_tri2_random(void **state)
{
    (void)state;
    for (int it = 0; it < 20000; it++) {
        double v[4][2];
        for (int i = 0; i < 4; i++)
            for (int k = 0; k < 2; k++)
                v[i][k] = urand() * 2 - 1;
        double l[3];
        assert_int_equal(geom_bary_tri2(v[0], v[1], v[2], v[3], l), GEOM_OK);
        double o = geom_orient2d(v[0], v[1], v[2]);
        double s0 = geom_orient2d(v[3], v[1], v[2]), s1 = geom_orient2d(v[0], v[3], v[2]),
               s2 = geom_orient2d(v[0], v[1], v[3]);
        assert_true((l[0] > 0) - (l[0] < 0) == ((s0 > 0) - (s0 < 0)) * ((o > 0) - (o < 0)));
        assert_true((l[1] > 0) - (l[1] < 0) == ((s1 > 0) - (s1 < 0)) * ((o > 0) - (o < 0)));
        assert_true((l[2] > 0) - (l[2] < 0) == ((s2 > 0) - (s2 < 0)) * ((o > 0) - (o < 0)));
        double mx = fmax(1.0, fmax(fabs(l[0]), fmax(fabs(l[1]), fabs(l[2]))));
        assert_close(l[0] + l[1] + l[2], 1.0, 1e-12 * mx);
        for (int k = 0; k < 2; k++)
            assert_close(l[0] * v[0][k] + l[1] * v[1][k] + l[2] * v[2][k], v[3][k], 1e-12 * mx);
    }
}

/* ------------------------------------------------------------- triangle 3D */

static void test_tri3(void **state)
{
    (void)state;
    /* A triangle in the plane z = x + 2y (normal (-1, -2, 1)); p built from
     * dyadic weights (1/4, 5/8, 1/8) and moved off the plane along the
     * normal: the projection is the in-plane point, so l = the weights. */
    const double a[3] = {1, 2, 5}, b[3] = {9, -3, 3}, c[3] = {-4, 6, 8};
    const double wts[3] = {0.25, 0.625, 0.125};
    double p[3], l[3];
    for (int k = 0; k < 3; k++)
        p[k] = wts[0] * a[k] + wts[1] * b[k] + wts[2] * c[k];
    for (int off = -3; off <= 3; off++) {
        double q[3] = {p[0] - off * 0.5, p[1] - 2 * off * 0.5, p[2] + off * 0.5};
        assert_int_equal(geom_bary_tri3(a, b, c, q, l), GEOM_OK);
        for (int i = 0; i < 3; i++)
            assert_close(l[i], wts[i], 1e-15);
    }
    /* vertices: exactly the unit vectors, also off the plane */
    const double *v[3] = {a, b, c};
    for (int i = 0; i < 3; i++) {
        assert_int_equal(geom_bary_tri3(a, b, c, v[i], l), GEOM_OK);
        for (int j = 0; j < 3; j++)
            assert_true(l[j] == (i == j ? 1.0 : 0.0));
    }
    /* on an edge (exact midpoint), and off the plane above that edge */
    double m[3] = {(a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2};
    assert_int_equal(geom_bary_tri3(a, b, c, m, l), GEOM_OK);
    assert_true(l[2] == 0.0);
    assert_close(l[0], 0.5, 1e-15);
    double mo[3] = {m[0] + 3, m[1] + 6, m[2] - 3};
    assert_int_equal(geom_bary_tri3(a, b, c, mo, l), GEOM_OK);
    assert_true(l[2] == 0.0);
    assert_close(l[1], 0.5, 1e-15);
    /* z = 0: agrees with the 2D coordinates */
    for (int it = 0; it < 1000; it++) {
        double t[4][3], l2[3];
        for (int i = 0; i < 4; i++) {
            t[i][0] = urand();
            t[i][1] = urand();
            t[i][2] = 0.0;
        }
        double t2[4][2] = {{t[0][0], t[0][1]}, {t[1][0], t[1][1]}, {t[2][0], t[2][1]},
                           {t[3][0], t[3][1]}};
        assert_int_equal(geom_bary_tri3(t[0], t[1], t[2], t[3], l), GEOM_OK);
        assert_int_equal(geom_bary_tri2(t2[0], t2[1], t2[2], t2[3], l2), GEOM_OK);
        for (int i = 0; i < 3; i++)
            assert_close(l[i], l2[i], 1e-12 * fmax(1.0, fabs(l2[i])));
    }
    /* degenerate: collinear in 3D; non-finite */
    const double d1[3] = {1, 2, 3}, d2[3] = {2, 4, 6}, d3[3] = {-1, -2, -3};
    l[0] = 9;
    assert_int_equal(geom_bary_tri3(d1, d2, d3, p, l), GEOM_ERR_DEGENERATE);
    assert_true(l[0] == 0.0 && l[1] == 0.0 && l[2] == 0.0);
    double bad[3] = {1, NAN, 2};
    assert_int_equal(geom_bary_tri3(a, b, c, bad, l), GEOM_ERR_INVALID_ARG);
    assert_true(l[0] == 0.0 && l[1] == 0.0 && l[2] == 0.0);
    bad[1] = INFINITY;
    assert_int_equal(geom_bary_tri3(bad, b, c, p, l), GEOM_ERR_INVALID_ARG);
}

/* ----------------------------------------------------------- tetrahedron */

static void test_tet(void **state)
{
    (void)state;
    const double a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, c[3] = {0, 1, 0}, d[3] = {0, 0, 1};
    const double p[3] = {0.125, 0.25, 0.5};
    double l[4];
    assert_int_equal(geom_bary_tet(a, b, c, d, p, l), GEOM_OK);
    assert_true(l[0] == 0.125 && l[1] == 0.125 && l[2] == 0.25 && l[3] == 0.5);
    /* general tetrahedron, p = (a + 2b + 3c + 2d) / 8 */
    const double A[3] = {1.5, -2, 0.25}, B[3] = {4, 1, -1}, C[3] = {-1, 3.5, 2}, D[3] = {0.5, 0, 5};
    double P[3];
    for (int k = 0; k < 3; k++)
        P[k] = (A[k] + 2 * B[k] + 3 * C[k] + 2 * D[k]) / 8;
    assert_int_equal(geom_bary_tet(A, B, C, D, P, l), GEOM_OK);
    const double ex[4] = {0.125, 0.25, 0.375, 0.25};
    for (int i = 0; i < 4; i++)
        assert_close(l[i], ex[i], 1e-15);
    /* vertices and faces */
    const double *v[4] = {A, B, C, D};
    for (int i = 0; i < 4; i++) {
        assert_int_equal(geom_bary_tet(A, B, C, D, v[i], l), GEOM_OK);
        for (int j = 0; j < 4; j++)
            assert_true(l[j] == (i == j ? 1.0 : 0.0));
    }
    /* face (B, C, D) at (B + C + 2D) / 4: l[0] exactly 0 */
    double f[3];
    for (int k = 0; k < 3; k++)
        f[k] = (B[k] + C[k] + 2 * D[k]) / 4;
    assert_int_equal(geom_bary_tet(A, B, C, D, f, l), GEOM_OK);
    assert_true(l[0] == 0.0);
    assert_close(l[3], 0.5, 1e-15);
    /* coplanar: degenerate */
    const double E[3] = {0.5, 0.5, 0};
    assert_int_equal(geom_bary_tet(a, b, c, E, p, l), GEOM_ERR_DEGENERATE);
    assert_true(l[0] == 0.0 && l[1] == 0.0 && l[2] == 0.0 && l[3] == 0.0);
    double bad[3] = {0, -INFINITY, 0};
    assert_int_equal(geom_bary_tet(a, b, c, d, bad, l), GEOM_ERR_INVALID_ARG);
    assert_false(has_nan(l, 4));
    /* random: linear precision */
    for (int it = 0; it < 5000; it++) {
        double t[5][3];
        for (int i = 0; i < 5; i++)
            for (int k = 0; k < 3; k++)
                t[i][k] = urand();
        assert_int_equal(geom_bary_tet(t[0], t[1], t[2], t[3], t[4], l), GEOM_OK);
        double mx = fmax(1.0, fmax(fmax(fabs(l[0]), fabs(l[1])), fmax(fabs(l[2]), fabs(l[3]))));
        assert_close(l[0] + l[1] + l[2] + l[3], 1.0, 1e-12 * mx);
        for (int k = 0; k < 3; k++)
            assert_close(l[0] * t[0][k] + l[1] * t[1][k] + l[2] * t[2][k] + l[3] * t[3][k],
                         t[4][k], 1e-12 * mx);
    }
}

/* ------------------------------------------------- generalized coordinates */

typedef geom_status (*gbc_fn)(size_t, const double *, const double *, double *);

static void check_gbc(gbc_fn f, size_t n, const double *poly, const double p[2], double tol)
{
    double w[32];
    assert_true(n <= 32);
    assert_int_equal(f(n, poly, p, w), GEOM_OK);
    double s = 0, x = 0, y = 0;
    for (size_t i = 0; i < n; i++) {
        s += w[i];
        x += w[i] * poly[2 * i];
        y += w[i] * poly[2 * i + 1];
    }
    assert_close(s, 1.0, tol);
    assert_close(x, p[0], tol);
    assert_close(y, p[1], tol);
}

static void test_gbc_triangle(void **state)
{
    (void)state;
    /* n = 3: both equal the triangle's barycentric coordinates */
    for (int it = 0; it < 500; it++) {
        double poly[6], p[2], w[3], l[3];
        for (int i = 0; i < 6; i++)
            poly[i] = urand() * 4 - 2;
        if (geom_orient2d(poly, poly + 2, poly + 4) == 0)
            continue;
        double t0 = urand(), t1 = urand() * (1 - t0);
        p[0] = t0 * poly[0] + t1 * poly[2] + (1 - t0 - t1) * poly[4];
        p[1] = t0 * poly[1] + t1 * poly[3] + (1 - t0 - t1) * poly[5];
        assert_int_equal(geom_bary_tri2(poly, poly + 2, poly + 4, p, l), GEOM_OK);
        assert_int_equal(geom_bary_mean_value(3, poly, p, w), GEOM_OK);
        for (int i = 0; i < 3; i++)
            assert_close(w[i], l[i], 1e-11);
        geom_status st = geom_bary_wachspress(3, poly, p, w);
        if (st == GEOM_OK) {
            for (int i = 0; i < 3; i++)
                assert_close(w[i], l[i], 1e-11);
        } else {
            /* p rounded onto the outside of an edge */
            assert_int_equal(st, GEOM_ERR_DOMAIN);
        }
        /* MVC is defined outside too and still equals the barycentrics */
        double q[2] = {p[0] + 3, p[1] - 1};
        assert_int_equal(geom_bary_tri2(poly, poly + 2, poly + 4, q, l), GEOM_OK);
        assert_int_equal(geom_bary_mean_value(3, poly, q, w), GEOM_OK);
        for (int i = 0; i < 3; i++)
            assert_close(w[i], l[i], 1e-10 * fmax(1.0, fabs(l[i])));
    }
}

static void test_mean_value(void **state)
{
    (void)state;
    /* regular hexagon: at the centre every weight is 1/6 */
    double hex[12];
    for (int i = 0; i < 6; i++) {
        hex[2 * i] = cos(i * PI / 3);
        hex[2 * i + 1] = sin(i * PI / 3);
    }
    double w[32];
    const double o[2] = {0, 0};
    assert_int_equal(geom_bary_mean_value(6, hex, o, w), GEOM_OK);
    for (int i = 0; i < 6; i++)
        assert_close(w[i], 1.0 / 6, 1e-15);
    /* clockwise order gives the same weights */
    double hexcw[12];
    for (int i = 0; i < 6; i++) {
        hexcw[2 * i] = hex[2 * (5 - i)];
        hexcw[2 * i + 1] = hex[2 * (5 - i) + 1];
    }
    const double q[2] = {0.3, -0.2};
    double w2[32];
    assert_int_equal(geom_bary_mean_value(6, hex, q, w), GEOM_OK);
    assert_int_equal(geom_bary_mean_value(6, hexcw, q, w2), GEOM_OK);
    for (int i = 0; i < 6; i++)
        assert_close(w[i], w2[5 - i], 1e-15);

    /* non-convex polygon (an L shape and a star), points in concave pockets,
     * inside and outside: partition of unity and linear precision */
    const double L[12] = {0, 0, 2, 0, 2, 1, 1, 1, 1, 2, 0, 2};
    double star[20];
    for (int i = 0; i < 10; i++) {
        double r = i % 2 ? 0.4 : 1.0;
        star[2 * i] = r * cos(i * PI / 5);
        star[2 * i + 1] = r * sin(i * PI / 5);
    }
    for (int it = 0; it < 2000; it++) {
        double p[2] = {urand() * 3 - 0.5, urand() * 3 - 0.5};
        check_gbc(geom_bary_mean_value, 6, L, p, 1e-12);
        double s[2] = {urand() * 2.4 - 1.2, urand() * 2.4 - 1.2};
        check_gbc(geom_bary_mean_value, 10, star, s, 1e-11);
    }
    /* outside the convex hull some weight must be negative (the weights sum
     * to 1 and reproduce p) */
    const double pk[2] = {2.5, 2.5};
    assert_int_equal(geom_bary_mean_value(6, L, pk, w), GEOM_OK);
    int neg = 0;
    for (int i = 0; i < 6; i++)
        neg |= w[i] < 0;
    assert_true(neg);

    /* boundary: on an edge -> linear interpolation, others exactly 0 */
    const double e[2] = {1.5, 1}; /* on edge (2,1)-(1,1) */
    assert_int_equal(geom_bary_mean_value(6, L, e, w), GEOM_OK);
    for (int i = 0; i < 6; i++) {
        if (i == 2 || i == 3)
            assert_true(w[i] == 0.5);
        else
            assert_true(w[i] == 0.0);
    }
    const double e2[2] = {0, 0.5}; /* on the closing edge (0,2)-(0,0) */
    assert_int_equal(geom_bary_mean_value(6, L, e2, w), GEOM_OK);
    assert_true(w[5] == 0.25 && w[0] == 0.75 && w[1] == 0.0 && w[2] == 0.0 && w[3] == 0.0 &&
                w[4] == 0.0);
    for (int i = 0; i < 10; i++) {
        double vw[32];
        assert_int_equal(geom_bary_mean_value(10, star, star + 2 * i, vw), GEOM_OK);
        for (int j = 0; j < 10; j++)
            assert_true(vw[j] == (i == j ? 1.0 : 0.0));
    }
    /* on the supporting line of an edge but outside it: a regular point */
    const double ln[2] = {3, 1};
    check_gbc(geom_bary_mean_value, 6, L, ln, 1e-12);
    /* very close to an edge: weights approach the edge's, no overflow */
    const double ne[2] = {1.25, 1 + 0x1p-60};
    assert_int_equal(geom_bary_mean_value(6, L, ne, w), GEOM_OK);
    assert_close(w[2], 0.25, 1e-12);
    assert_close(w[3], 0.75, 1e-12);
    const double nv[2] = {0x1p-1000, 0x1p-1001}; /* next to vertex 0 */
    assert_int_equal(geom_bary_mean_value(6, L, nv, w), GEOM_OK);
    assert_false(has_nan(w, 6));
    assert_close(w[0], 1.0, 1e-15);
    const double nr[2] = {1 - 0x1p-52, 1 - 0x1p-53}; /* next to the reflex vertex 3 */
    assert_int_equal(geom_bary_mean_value(6, L, nr, w), GEOM_OK);
    assert_false(has_nan(w, 6));
    assert_close(w[3], 1.0, 1e-14);
    /* huge and tiny polygons: scale invariance */
    double Lh[12], Lt[12];
    for (int i = 0; i < 12; i++) {
        Lh[i] = L[i] * 0x1p1000;
        Lt[i] = L[i] * 0x1p-1060;
    }
    const double ph[2] = {0.5 * 0x1p1000, 1.5 * 0x1p1000};
    const double pt[2] = {0.5 * 0x1p-1060, 1.5 * 0x1p-1060};
    const double pp[2] = {0.5, 1.5};
    double wh[32], wt[32];
    assert_int_equal(geom_bary_mean_value(6, L, pp, w), GEOM_OK);
    assert_int_equal(geom_bary_mean_value(6, Lh, ph, wh), GEOM_OK);
    assert_int_equal(geom_bary_mean_value(6, Lt, pt, wt), GEOM_OK);
    for (int i = 0; i < 6; i++) {
        assert_close(wh[i], w[i], 1e-15);
        assert_close(wt[i], w[i], 1e-15);
    }

    /* errors */
    const double dup[8] = {0, 0, 1, 0, 1, 0, 0, 1};
    assert_int_equal(geom_bary_mean_value(4, dup, pp, w), GEOM_ERR_DEGENERATE);
    assert_true(w[0] == 0.0 && w[3] == 0.0);
    const double flat[8] = {0, 0, 1, 1, 2, 2, 3, 3};
    assert_int_equal(geom_bary_mean_value(4, flat, pp, w), GEOM_ERR_DEGENERATE);
    assert_int_equal(geom_bary_mean_value(2, L, pp, w), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_bary_mean_value(6, NULL, pp, w), GEOM_ERR_INVALID_ARG);
    double Ln[12];
    for (int i = 0; i < 12; i++)
        Ln[i] = L[i];
    Ln[7] = NAN;
    assert_int_equal(geom_bary_mean_value(6, Ln, pp, w), GEOM_ERR_INVALID_ARG);
    assert_false(has_nan(w, 6));
    const double pinf[2] = {INFINITY, 0};
    assert_int_equal(geom_bary_mean_value(6, L, pinf, w), GEOM_ERR_INVALID_ARG);
}

static void test_wachspress(void **state)
{
    (void)state;
    /* unit square: Wachspress coordinates are the bilinear ones */
    const double sq[8] = {0, 0, 1, 0, 1, 1, 0, 1};
    double w[32];
    for (int it = 0; it < 1000; it++) {
        double x = urand(), y = urand();
        const double p[2] = {x, y};
        if (x == 0 || y == 0)
            continue;
        assert_int_equal(geom_bary_wachspress(4, sq, p, w), GEOM_OK);
        assert_close(w[0], (1 - x) * (1 - y), 1e-14);
        assert_close(w[1], x * (1 - y), 1e-14);
        assert_close(w[2], x * y, 1e-14);
        assert_close(w[3], (1 - x) * y, 1e-14);
    }
    /* regular pentagon: centre 1/5; random interior points: unity and
     * linear precision; clockwise order works */
    double pent[10], pentcw[10];
    for (int i = 0; i < 5; i++) {
        pent[2 * i] = cos(2 * PI * i / 5);
        pent[2 * i + 1] = sin(2 * PI * i / 5);
    }
    for (int i = 0; i < 5; i++) {
        pentcw[2 * i] = pent[2 * (4 - i)];
        pentcw[2 * i + 1] = pent[2 * (4 - i) + 1];
    }
    const double o[2] = {0, 0};
    assert_int_equal(geom_bary_wachspress(5, pent, o, w), GEOM_OK);
    for (int i = 0; i < 5; i++)
        assert_close(w[i], 0.2, 1e-15);
    for (int it = 0; it < 1000; it++) {
        double r = 0.8 * urand(), t = 2 * PI * urand();
        const double p[2] = {r * cos(t), r * sin(t)};
        check_gbc(geom_bary_wachspress, 5, pent, p, 1e-13);
        check_gbc(geom_bary_wachspress, 5, pentcw, p, 1e-13);
        double a[32], b[32];
        assert_int_equal(geom_bary_wachspress(5, pent, p, a), GEOM_OK);
        assert_int_equal(geom_bary_wachspress(5, pentcw, p, b), GEOM_OK);
        for (int i = 0; i < 5; i++) {
            assert_true(a[i] > 0);
            assert_close(a[i], b[4 - i], 1e-15);
        }
    }
    /* boundary: edge midpoint and vertices */
    const double e[2] = {1, 0.25};
    assert_int_equal(geom_bary_wachspress(4, sq, e, w), GEOM_OK);
    assert_true(w[0] == 0.0 && w[1] == 0.75 && w[2] == 0.25 && w[3] == 0.0);
    for (int i = 0; i < 4; i++) {
        assert_int_equal(geom_bary_wachspress(4, sq, sq + 2 * i, w), GEOM_OK);
        for (int j = 0; j < 4; j++)
            assert_true(w[j] == (i == j ? 1.0 : 0.0));
    }
    /* next to an edge: finite, close to the edge's interpolation */
    const double ne[2] = {0.5, 0x1p-1000};
    assert_int_equal(geom_bary_wachspress(4, sq, ne, w), GEOM_OK);
    assert_close(w[0], 0.5, 1e-15);
    assert_close(w[1], 0.5, 1e-15);
    /* outside, non-convex, collinear consecutive vertices, self-intersecting */
    const double out[2] = {1.5, 0.5};
    w[0] = 3;
    assert_int_equal(geom_bary_wachspress(4, sq, out, w), GEOM_ERR_DOMAIN);
    assert_true(w[0] == 0.0 && w[1] == 0.0 && w[2] == 0.0 && w[3] == 0.0);
    const double L[12] = {0, 0, 2, 0, 2, 1, 1, 1, 1, 2, 0, 2};
    const double in[2] = {0.5, 0.5};
    assert_int_equal(geom_bary_wachspress(6, L, in, w), GEOM_ERR_DOMAIN);
    const double col[8] = {0, 0, 1, 0, 2, 0, 0, 1};
    assert_int_equal(geom_bary_wachspress(4, col, in, w), GEOM_ERR_DEGENERATE);
    double star[10]; /* pentagram: every turn has the same sign */
    for (int i = 0; i < 5; i++) {
        star[2 * i] = pent[2 * ((2 * i) % 5)];
        star[2 * i + 1] = pent[2 * ((2 * i) % 5) + 1];
    }
    assert_int_equal(geom_bary_wachspress(5, star, o, w), GEOM_ERR_DOMAIN);
    const double bad[2] = {NAN, 0};
    assert_int_equal(geom_bary_wachspress(4, sq, bad, w), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_bary_wachspress(2, sq, in, w), GEOM_ERR_INVALID_ARG);
}

/* ------------------------------------------------------------ interpolate */

static void test_interpolate(void **state)
{
    (void)state;
    const double l[3] = {0.25, 0.5, 0.25};
    const double attr[6] = {1, 10, 3, 30, 5, 50};
    double out[2];
    assert_int_equal(geom_bary_interpolate(3, l, 2, attr, out), GEOM_OK);
    assert_true(out[0] == 3.0 && out[1] == 30.0);
    assert_int_equal(geom_bary_interpolate(0, l, 2, attr, out), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_bary_interpolate(3, NULL, 2, attr, out), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_bary_interpolate(3, l, 2, NULL, out), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_bary_interpolate(3, l, 2, attr, NULL), GEOM_ERR_INVALID_ARG);
    /* barycentric coordinates reproduce an affine attribute */
    const double a[2] = {0.1, 0.2}, b[2] = {2.3, -0.7}, c[2] = {-1.1, 1.9}, p[2] = {0.4, 0.5};
    double lb[3];
    assert_int_equal(geom_bary_tri2(a, b, c, p, lb), GEOM_OK);
    const double f[3] = {3 * a[0] - 2 * a[1] + 1, 3 * b[0] - 2 * b[1] + 1, 3 * c[0] - 2 * c[1] + 1};
    double fp;
    assert_int_equal(geom_bary_interpolate(3, lb, 1, f, &fp), GEOM_OK);
    assert_close(fp, 3 * p[0] - 2 * p[1] + 1, 1e-14);
}

/* ------------------------------------------------------------ perspective */

/* gluPerspective, row-major 4x4 here, applied to (x, y, z, 1). */
static void project(const double P[4][4], const double x[3], double clip[4])
{
    for (int r = 0; r < 4; r++)
        clip[r] = P[r][0] * x[0] + P[r][1] * x[1] + P[r][2] * x[2] + P[r][3];
}

static void test_perspective(void **state)
{
    (void)state;
    double fovy = 1.0, aspect = 1.5, zn = 0.1, zf = 100.0;
    double f = 1.0 / tan(fovy / 2);
    const double P[4][4] = {{f / aspect, 0, 0, 0},
                            {0, f, 0, 0},
                            {0, 0, (zf + zn) / (zn - zf), 2 * zf * zn / (zn - zf)},
                            {0, 0, -1, 0}};
    for (int it = 0; it < 2000; it++) {
        /* a triangle in front of the camera with very different depths */
        double V[3][3];
        for (int i = 0; i < 3; i++) {
            V[i][2] = -(0.5 + 40 * urand());
            V[i][0] = (urand() - 0.5) * -V[i][2];
            V[i][1] = (urand() - 0.5) * -V[i][2];
        }
        double b0 = urand(), b1 = urand() * (1 - b0), beta[3] = {b0, b1, 1 - b0 - b1};
        double X[3];
        for (int k = 0; k < 3; k++)
            X[k] = beta[0] * V[0][k] + beta[1] * V[1][k] + beta[2] * V[2][k];
        double clip[4][4], ndc[4][2];
        for (int i = 0; i < 4; i++) {
            project(P, i < 3 ? V[i] : X, clip[i]);
            ndc[i][0] = clip[i][0] / clip[i][3];
            ndc[i][1] = clip[i][1] / clip[i][3];
        }
        double l[3], lp[3];
        if (geom_bary_tri2(ndc[0], ndc[1], ndc[2], ndc[3], l) != GEOM_OK)
            continue; /* edge-on triangle */
        double w[3] = {clip[0][3], clip[1][3], clip[2][3]};
        assert_int_equal(geom_bary_perspective(l, w, lp), GEOM_OK);
        /* screen-space coordinates differ from the 3D ones, the corrected
         * ones agree (conditioning limits the tolerance for thin
         * projections) */
        double area = fabs(geom_orient2d(ndc[0], ndc[1], ndc[2]));
        double tol = 1e-12 / fmin(1.0, area * 1e3);
        for (int i = 0; i < 3; i++)
            assert_close(lp[i], beta[i], tol);
    }
    /* vertices and edges stay exact */
    const double l0[3] = {1, 0, 0}, le[3] = {0, 0.5, 0.5}, w[3] = {2, 5, 0.25};
    double lp[3];
    assert_int_equal(geom_bary_perspective(l0, w, lp), GEOM_OK);
    assert_true(lp[0] == 1.0 && lp[1] == 0.0 && lp[2] == 0.0);
    assert_int_equal(geom_bary_perspective(le, w, lp), GEOM_OK);
    assert_true(lp[0] == 0.0);
    assert_close(lp[1], 0.25 / 5.25, 1e-16);
    /* closed form: lp_i = (l_i / w_i) / sum */
    const double lq[3] = {0.25, 0.25, 0.5};
    assert_int_equal(geom_bary_perspective(lq, w, lp), GEOM_OK);
    double s = 0.125 + 0.05 + 2.0;
    assert_close(lp[0], 0.125 / s, 1e-16);
    assert_close(lp[1], 0.05 / s, 1e-16);
    assert_close(lp[2], 2.0 / s, 1e-16);
    /* extreme w: no overflow */
    const double wx[3] = {1e-300, 1e300, 1};
    assert_int_equal(geom_bary_perspective(lq, wx, lp), GEOM_OK);
    assert_close(lp[0], 1.0, 1e-15);
    assert_false(has_nan(lp, 3));
    /* errors */
    const double wz[3] = {1, 0, 1}, lz[3] = {0.5, 0.5, 0}, wm[3] = {1, -1, 1};
    assert_int_equal(geom_bary_perspective(lq, wz, lp), GEOM_ERR_DEGENERATE);
    assert_true(lp[0] == 0.0 && lp[1] == 0.0 && lp[2] == 0.0);
    assert_int_equal(geom_bary_perspective(lz, wm, lp), GEOM_ERR_DEGENERATE);
    const double wn[3] = {1, NAN, 1};
    assert_int_equal(geom_bary_perspective(lq, wn, lp), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_bary_perspective(NULL, w, lp), GEOM_ERR_INVALID_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tri2_closed_form),
        cmocka_unit_test(test_tri2_vertices_edges),
        cmocka_unit_test(test_tri2_degenerate_invalid),
        cmocka_unit_test(test_tri2_random),
        cmocka_unit_test(test_tri3),
        cmocka_unit_test(test_tet),
        cmocka_unit_test(test_gbc_triangle),
        cmocka_unit_test(test_mean_value),
        cmocka_unit_test(test_wachspress),
        cmocka_unit_test(test_interpolate),
        cmocka_unit_test(test_perspective),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
