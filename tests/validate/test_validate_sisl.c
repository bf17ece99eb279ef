/* Curves and surfaces against SISL (s1221 / s1227 for curves, s1421 for
 * surfaces): random B-spline and NURBS curves and surfaces of degree 1 to 7
 * with weights from 1e-3 to 1e3 (log-uniform) and interior knots of every
 * multiplicity up to the degree (and degree+1 for curves, evaluated from
 * both sides), evaluated at random parameters, at every knot and at both
 * ends of the domain. Points and first and second derivatives must agree
 * within 1e-12 relative: |ours - SISL| <= 1e-12 * (the largest magnitude of
 * that derivative order over the samples of the same curve or surface).
 *
 * With weights a million apart neither library is always that accurate
 * (the rational quotient amplifies rounding by up to the weight ratio), so
 * where the two differ by more, an arbiter decides: the same algorithms
 * (A2.3, A3.6, A4.2, A4.4) in 64-bit-mantissa long double on the same
 * double inputs, about 2000 times more precise. The case passes when ours
 * is within 1e-12 of the arbiter and closer to it than SISL; the count of
 * such cases is printed.
 *
 * The NURBS Book's worked examples (Ex. 2.3 basis functions, Ex. 4.1 rational
 * quarter circle, as a curve and extruded as a surface) are checked against
 * their closed forms through both libraries.
 *
 * When the CGAL part of the shim is built too (GV_HAVE_CGAL), the
 * tessellations of the teapot's body, the sphere and the torus are checked
 * by CGAL's Polygon_mesh_processing (gv_soup_check): an oriented 2-manifold
 * as given, the number of border cycles and components, the genus, and no
 * self-intersection. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "geom/curve.h"
#include "geom/surface.h"
#include "validate/geom_validate_sisl.h"
#ifdef GV_HAVE_CGAL
#include "validate/geom_validate.h"
#endif

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define REL_TOL 1e-12
#define MAXN 16

/* xorshift64*: deterministic random numbers without global state */
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

static int rndi(rng *r, int lo, int hi)
{
    return lo + (int)(rnd(r) * (double)(hi - lo + 1)) % (hi - lo + 1);
}

/* Clamped knots for n points of degree p on [0, 1] with random interior
 * values of random multiplicity (1 .. maxmult). Returns the knot count. */
static size_t random_knots(rng *r, int p, size_t n, int maxmult, double *U)
{
    size_t m = n + (size_t)p + 1, k = 0;
    for (int i = 0; i <= p; ++i)
        U[k++] = 0.0;
    size_t interior = n - (size_t)p - 1;
    double x = 0.0;
    while (interior > 0) {
        int mult = rndi(r, 1, maxmult);
        if ((size_t)mult > interior)
            mult = (int)interior;
        x += 0.05 + rnd(r);
        for (int j = 0; j < mult; ++j)
            U[k++] = x;
        interior -= (size_t)mult;
    }
    double end = x + 0.05 + rnd(r);
    for (int i = 0; i <= p; ++i)
        U[k++] = end;
    for (size_t i = 0; i < m; ++i)
        U[i] /= end; /* domain [0, 1] */
    return m;
}

static double norm_n(const double *v, size_t n)
{
    double s = 0.0;
    for (size_t i = 0; i < n; ++i)
        s += v[i] * v[i];
    return sqrt(s);
}

static double diff_n(const double *a, const double *b, size_t n)
{
    double s = 0.0;
    for (size_t i = 0; i < n; ++i)
        s += (a[i] - b[i]) * (a[i] - b[i]);
    return sqrt(s);
}

/* A difference relative to a scale; an order that vanishes everywhere (a
 * second derivative of degree 1) must then be exactly zero. */
static double rel(double diff, double scale)
{
    return scale > 0.0 ? diff / scale : diff;
}


/* ---------------------------------------------------- long double arbiter */

typedef long double ld;

/* The span rules of geom/curve.h: right limit (u_k <= u < u_k+1, the last
 * non-empty span at the end) or left limit (u_k < u <= u_k+1). */
static size_t ld_span(int p, size_t n, const double *U, double u, int left)
{
    if (left && u > U[p]) {
        for (size_t k = (size_t)p; k < n; ++k)
            if (U[k] < u && u <= U[k + 1])
                return k;
    }
    size_t last = (size_t)p;
    for (size_t k = (size_t)p; k < n; ++k) {
        if (U[k] < U[k + 1])
            last = k;
        if (U[k] <= u && u < U[k + 1])
            return k;
    }
    return last;
}

/* A2.3 in long double: ders[j*(p+1) + r], j <= nd. */
static void ld_basis_ders(int p, const double *U, size_t k, ld u, int nd, ld *ders)
{
    ld ndu[9][9], a[2][9], left[9], right[9];
    ndu[0][0] = 1.0L;
    for (int j = 1; j <= p; ++j) {
        left[j] = u - (ld)U[k + 1 - (size_t)j];
        right[j] = (ld)U[k + (size_t)j] - u;
        ld saved = 0.0L;
        for (int r = 0; r < j; ++r) {
            ndu[j][r] = right[r + 1] + left[j - r];
            ld t = ndu[r][j - 1] / ndu[j][r];
            ndu[r][j] = saved + right[r + 1] * t;
            saved = left[j - r] * t;
        }
        ndu[j][j] = saved;
    }
    for (int j = 0; j <= nd; ++j)
        for (int r = 0; r <= p; ++r)
            ders[j * (p + 1) + r] = 0.0L;
    for (int r = 0; r <= p; ++r)
        ders[r] = ndu[r][p];
    for (int r = 0; r <= p; ++r) {
        int s1 = 0, s2 = 1;
        a[0][0] = 1.0L;
        for (int kk = 1; kk <= nd && kk <= p; ++kk) {
            ld d = 0.0L;
            int rk = r - kk, pk = p - kk;
            if (r >= kk) {
                a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
                d = a[s2][0] * ndu[rk][pk];
            }
            int j1 = rk >= -1 ? 1 : -rk;
            int j2 = (r - 1 <= pk) ? kk - 1 : p - r;
            for (int j = j1; j <= j2; ++j) {
                a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][rk + j];
                d += a[s2][j] * ndu[rk + j][pk];
            }
            if (r <= pk) {
                a[s2][kk] = -a[s1][kk - 1] / ndu[pk + 1][r];
                d += a[s2][kk] * ndu[r][pk];
            }
            ders[kk * (p + 1) + r] = d;
            int t = s1;
            s1 = s2;
            s2 = t;
        }
    }
    int r = p;
    for (int kk = 1; kk <= nd && kk <= p; ++kk) {
        for (int j = 0; j <= p; ++j)
            ders[kk * (p + 1) + j] *= r;
        r *= p - kk;
    }
}

static ld ld_binom(int n, int k)
{
    ld b = 1.0L;
    for (int i = 1; i <= k; ++i)
        b = b * (n - k + i) / i;
    return b;
}

/* Curve derivatives 0..2 (A3.2 homogeneous, then A4.2). */
static void ld_curve(int p, size_t n, size_t dim, const double *U, const double *P,
                     const double *W, double u, int left, double *out)
{
    size_t k = ld_span(p, n, U, u, left);
    ld N[3 * 8], A[3][5] = {{0}};
    ld_basis_ders(p, U, k, (ld)u, 2, N);
    for (int j = 0; j <= 2; ++j)
        for (int r = 0; r <= p; ++r) {
            size_t i = k - (size_t)p + (size_t)r;
            ld w = W ? (ld)W[i] : 1.0L;
            for (size_t d = 0; d < dim; ++d)
                A[j][d] += N[j * (p + 1) + r] * w * (ld)P[i * dim + d];
            A[j][dim] += N[j * (p + 1) + r] * w;
        }
    ld C[3][4];
    for (int kk = 0; kk <= 2; ++kk)
        for (size_t d = 0; d < dim; ++d) {
            ld v = A[kk][d];
            for (int i = 1; i <= kk; ++i)
                v -= ld_binom(kk, i) * A[i][dim] * C[kk - i][d];
            C[kk][d] = v / A[0][dim];
            out[(size_t)kk * dim + d] = (double)C[kk][d];
        }
}

/* Surface derivatives k + l <= 2 (A3.6 homogeneous, then A4.4), right
 * limits, out[3*(3k + l)]. */
static void ld_surface(const geom_nurbs_surface *s, double u, double v, double *out)
{
    int p = s->degree_u, q = s->degree_v;
    size_t ku = ld_span(p, s->nu, s->knots_u, u, 0), kv = ld_span(q, s->nv, s->knots_v, v, 0);
    ld Nu[3 * 8], Nv[3 * 8], A[3][3][4] = {{{0}}};
    ld_basis_ders(p, s->knots_u, ku, (ld)u, 2, Nu);
    ld_basis_ders(q, s->knots_v, kv, (ld)v, 2, Nv);
    for (int k = 0; k <= 2; ++k)
        for (int l = 0; k + l <= 2; ++l)
            for (int r = 0; r <= p; ++r)
                for (int t = 0; t <= q; ++t) {
                    size_t i = ku - (size_t)p + (size_t)r, j = kv - (size_t)q + (size_t)t;
                    ld w = s->weights ? (ld)s->weights[i * s->nv + j] : 1.0L;
                    ld b = Nu[k * (p + 1) + r] * Nv[l * (q + 1) + t] * w;
                    for (int d = 0; d < 3; ++d)
                        A[k][l][d] += b * (ld)s->points[3 * (i * s->nv + j) + (size_t)d];
                    A[k][l][3] += b;
                }
    ld S[3][3][3];
    for (int k = 0; k <= 2; ++k)
        for (int l = 0; k + l <= 2; ++l)
            for (int d = 0; d < 3; ++d) {
                ld x = A[k][l][d];
                for (int j = 1; j <= l; ++j)
                    x -= ld_binom(l, j) * A[0][j][3] * S[k][l - j][d];
                for (int i = 1; i <= k; ++i) {
                    x -= ld_binom(k, i) * A[i][0][3] * S[k - i][l][d];
                    ld x2 = 0.0L;
                    for (int j = 1; j <= l; ++j)
                        x2 += ld_binom(l, j) * A[i][j][3] * S[k - i][l - j][d];
                    x -= ld_binom(k, i) * x2;
                }
                S[k][l][d] = x / A[0][0][3];
            }
    memset(out, 0, 27 * sizeof(double));
    for (int k = 0; k <= 2; ++k)
        for (int l = 0; k + l <= 2; ++l)
            for (int d = 0; d < 3; ++d)
                out[3 * (3 * k + l) + d] = (double)S[k][l][d];
}

/* The pass rule of the header comment; counts arbitrated cases. */
static int agree(const double *ours, const double *sisl, const double *exact, size_t dim,
                 double scale, double *worst, int *arbitrated)
{
    double e = rel(diff_n(ours, sisl, dim), scale);
    double eo = rel(diff_n(ours, exact, dim), scale), es = rel(diff_n(sisl, exact, dim), scale);
    if (e > worst[0])
        worst[0] = e;
    if (eo > worst[3])
        worst[3] = eo;
    if (es > worst[6])
        worst[6] = es;
    if (e <= REL_TOL)
        return 1;
    if (eo <= REL_TOL && eo < es) {
        (*arbitrated)++;
        return 1;
    }
    return 0;
}

/* ------------------------------------------------------------------ curves */

#define NSAMP 64

static void check_curve(rng *r, int p, size_t dim, int rational, int maxmult, double *worst,
                        int *arbitrated)
{
    size_t n = (size_t)p + 1 + (size_t)rndi(r, 0, 8);
    double U[MAXN + 8 + 1 + 8], P[(MAXN)*4], W[MAXN];
    size_t m = random_knots(r, p, n, maxmult, U);
    for (size_t i = 0; i < n * dim; ++i)
        P[i] = 2.0 * rnd(r) - 1.0;
    for (size_t i = 0; i < n; ++i)
        W[i] = pow(10.0, 6.0 * rnd(r) - 3.0);
    geom_nurbs_curve c = {p, n, dim, U, P, rational ? W : NULL};
    assert_int_equal(geom_curve_nurbs_validate(&c, m, NULL), GEOM_OK);
    /* samples: random, every knot from both sides, the ends */
    double us[NSAMP + 2 * (MAXN + 16)];
    int left[NSAMP + 2 * (MAXN + 16)];
    size_t ns = 0;
    for (int i = 0; i < NSAMP; ++i)
        us[ns] = rnd(r), left[ns++] = 0;
    for (size_t i = (size_t)p; i <= n; ++i) {
        us[ns] = U[i], left[ns++] = 0;
        if (i > (size_t)p)
            us[ns] = U[i], left[ns++] = 1;
    }
    double ours[NSAMP + 2 * (MAXN + 16)][3 * 4], ref[NSAMP + 2 * (MAXN + 16)][3 * 4];
    double scale[3] = {0.0, 0.0, 0.0};
    for (size_t s = 0; s < ns; ++s) {
        unsigned flags = left[s] ? GEOM_CURVE_LEFT_LIMIT : 0u;
        assert_int_equal(geom_curve_nurbs_derivs(&c, us[s], 2, flags, ours[s]), GEOM_OK);
        assert_int_equal(gv_sisl_curve_derivs(p, n, dim, U, P, c.weights, us[s], 2, left[s],
                                              ref[s]),
                         GV_SISL_OK);
        for (int k = 0; k < 3; ++k)
            scale[k] = fmax(scale[k], norm_n(ref[s] + (size_t)k * dim, dim));
    }
    for (size_t s = 0; s < ns; ++s) {
        double exact[3 * 4];
        ld_curve(p, n, dim, U, P, c.weights, us[s], left[s], exact);
        for (int k = 0; k < 3; ++k)
            if (!agree(ours[s] + (size_t)k * dim, ref[s] + (size_t)k * dim,
                       exact + (size_t)k * dim, dim, scale[k], worst + k, arbitrated))
                fail_msg("curve p=%d n=%zu dim=%zu rational=%d: order %d at u=%.17g (%s): "
                         "ours %.17g SISL %.17g exact %.17g (first coordinate, scale %.3g)",
                         p, n, dim, rational, k, us[s], left[s] ? "left" : "right",
                         ours[s][(size_t)k * dim], ref[s][(size_t)k * dim],
                         exact[(size_t)k * dim], scale[k]);
    }
}

static void test_curves_vs_sisl(void **state)
{
    (void)state;
    rng r = {0x9e3779b97f4a7c15ull};
    if (LDBL_MANT_DIG < 64)
        skip();
    double worst[9] = {0}; /* vs SISL, ours vs exact, SISL vs exact; orders 0..2 */
    int count = 0, arbitrated = 0;
    for (int p = 1; p <= 7; ++p)
        for (int rational = 0; rational <= 1; ++rational)
            for (int rep = 0; rep < 20; ++rep) {
                /* multiplicities up to p (C0 joins) and p+1 (discontinuities) */
                int maxmult = rep % 2 ? p + 1 : p;
                check_curve(&r, p, rep % 3 == 0 ? 2 : 3, rational, maxmult, worst, &arbitrated);
                count++;
            }
    print_message("%d curves, orders 0/1/2: ours vs SISL %.2g %.2g %.2g; vs the long double "
                  "arbiter: ours %.2g %.2g %.2g, SISL %.2g %.2g %.2g; %d values beyond 1e-12 "
                  "where ours is the closer\n",
                  count, worst[0], worst[1], worst[2], worst[3], worst[4], worst[5], worst[6],
                  worst[7], worst[8], arbitrated);
}

/* ---------------------------------------------------------------- surfaces */

#define NS2 40

static void check_surface(rng *r, int pu, int pv, int rational, double *worst,
                          int *arbitrated)
{
    size_t nu = (size_t)pu + 1 + (size_t)rndi(r, 0, 5), nv = (size_t)pv + 1 + (size_t)rndi(r, 0, 5);
    double Ku[MAXN + 8], Kv[MAXN + 8], P[3 * MAXN * MAXN], W[MAXN * MAXN];
    random_knots(r, pu, nu, pu, Ku);
    random_knots(r, pv, nv, pv, Kv);
    for (size_t i = 0; i < 3 * nu * nv; ++i)
        P[i] = 2.0 * rnd(r) - 1.0;
    for (size_t i = 0; i < nu * nv; ++i)
        W[i] = pow(10.0, 6.0 * rnd(r) - 3.0);
    geom_nurbs_surface s = {pu, pv, nu, nv, Ku, Kv, P, rational ? W : NULL};
    assert_int_equal(geom_surface_validate(&s, NULL), GEOM_OK);
    gv_sisl_surface *ss = gv_sisl_surface_create(pu, pv, nu, nv, Ku, Kv, P, s.weights);
    assert_non_null(ss);
    /* random points, knot lines and the corners */
    double uv[NS2 + 4 * MAXN + 8][2];
    size_t ns = 0;
    for (int i = 0; i < NS2; ++i)
        uv[ns][0] = rnd(r), uv[ns][1] = rnd(r), ns++;
    for (size_t i = (size_t)pu; i <= nu; ++i)
        uv[ns][0] = Ku[i], uv[ns][1] = rnd(r), ns++;
    for (size_t j = (size_t)pv; j <= nv; ++j)
        uv[ns][0] = rnd(r), uv[ns][1] = Kv[j], ns++;
    for (int c = 0; c < 4; ++c)
        uv[ns][0] = (c & 1) ? 1.0 : 0.0, uv[ns][1] = (c & 2) ? 1.0 : 0.0, ns++;
    /* orders (k,l) with k + l <= 2: index 3*(k*3 + l) */
    static double ours[NS2 + 4 * MAXN + 8][27], ref[NS2 + 4 * MAXN + 8][27];
    double scale[9] = {0};
    for (size_t q = 0; q < ns; ++q) {
        assert_int_equal(geom_surface_derivs(&s, uv[q][0], uv[q][1], 2, 0, ours[q]), GEOM_OK);
        assert_int_equal(gv_sisl_surface_eval(ss, uv[q][0], uv[q][1], 2, ref[q]), GV_SISL_OK);
        for (int k = 0; k < 9; ++k)
            scale[k] = fmax(scale[k], norm_n(ref[q] + 3 * k, 3));
    }
    gv_sisl_surface_destroy(ss);
    for (size_t q = 0; q < ns; ++q) {
        double exact[27];
        ld_surface(&s, uv[q][0], uv[q][1], exact);
        for (int k = 0; k <= 2; ++k)
            for (int l = 0; k + l <= 2; ++l) {
                int x = 3 * k + l;
                if (!agree(ours[q] + 3 * x, ref[q] + 3 * x, exact + 3 * x, 3, scale[x],
                           worst + k + l, arbitrated))
                    fail_msg("surface (%d,%d) %zux%zu rational=%d: S^(%d,%d) at (%.17g, %.17g): "
                             "ours %.17g SISL %.17g exact %.17g (x, scale %.3g)",
                             pu, pv, nu, nv, rational, k, l, uv[q][0], uv[q][1], ours[q][3 * x],
                             ref[q][3 * x], exact[3 * x], scale[x]);
            }
    }
}

static void test_surfaces_vs_sisl(void **state)
{
    (void)state;
    rng r = {0x2545f4914f6cdd1dull};
    if (LDBL_MANT_DIG < 64)
        skip();
    double worst[9] = {0}; /* vs SISL, ours vs exact, SISL vs exact; orders 0..2 */
    int count = 0, arbitrated = 0;
    for (int pu = 1; pu <= 7; ++pu)
        for (int pv = 1; pv <= 7; ++pv)
            for (int rational = 0; rational <= 1; ++rational)
                for (int rep = 0; rep < 3; ++rep) {
                    check_surface(&r, pu, pv, rational, worst, &arbitrated);
                    count++;
                }
    print_message("%d surfaces, orders 0/1/2: ours vs SISL %.2g %.2g %.2g; vs the long double "
                  "arbiter: ours %.2g %.2g %.2g, SISL %.2g %.2g %.2g; %d values beyond 1e-12 "
                  "where ours is the closer\n",
                  count, worst[0], worst[1], worst[2], worst[3], worst[4], worst[5], worst[6],
                  worst[7], worst[8], arbitrated);
}

/* The teapot's Bezier patches and the exact sphere and torus (rational,
 * with the double knots of the circles) against SISL too. */
static void test_shapes_vs_sisl(void **state)
{
    (void)state;
    double ku[12], kv[12], P[243], W[81];
    geom_nurbs_surface s[2];
    assert_int_equal(geom_surface_sphere(NULL, 2.0, ku, kv, P, W, &s[0]), GEOM_OK);
    double ku2[12], kv2[12], P2[243], W2[81];
    assert_int_equal(geom_surface_torus(NULL, 3.0, 1.0, ku2, kv2, P2, W2, &s[1]), GEOM_OK);
    for (int k = 0; k < 2; ++k) {
        gv_sisl_surface *ss = gv_sisl_surface_create(s[k].degree_u, s[k].degree_v, s[k].nu,
                                                     s[k].nv, s[k].knots_u, s[k].knots_v,
                                                     s[k].points, s[k].weights);
        assert_non_null(ss);
        for (int i = 0; i <= 32; ++i)
            for (int j = 0; j <= 32; ++j) {
                double u = i / 32.0, v = j / 32.0, a[27], b[27];
                assert_int_equal(geom_surface_derivs(&s[k], u, v, 2, 0, a), GEOM_OK);
                assert_int_equal(gv_sisl_surface_eval(ss, u, v, 2, b), GV_SISL_OK);
                for (int x = 0; x < 9; ++x) {
                    double mag = fmax(norm_n(b + 3 * x, 3), 1.0);
                    double e = diff_n(a + 3 * x, b + 3 * x, 3) / mag;
                    if (!(e <= 1e-13 * 8))
                        fail_msg("shape %d: derivative %d at (%g, %g) differs by %.3g", k, x, u,
                                 v, e);
                }
            }
        gv_sisl_surface_destroy(ss);
    }
}


/* The NURBS Book's worked examples, in closed form, from both libraries:
 * Ex. 2.3 (p = 2, U = {0,0,0,1,2,3,4,4,5,5,5} at u = 5/2: N_2 = N_4 = 1/8,
 * N_3 = 6/8, and the derivatives -1/2, 0, 1/2), evaluated as curves whose
 * coefficients pick one basis function; Ex. 4.1 (the quarter circle with
 * weights {1, 1, 2}: C(u) = ((1-u^2)/(1+u^2), 2u/(1+u^2)), C'(0) = (0, 2),
 * C''(0) = (-4, 0), C'(1) = (-1, 0)) and its extrusion along z as a
 * surface (S_u = C', S_v = (0, 0, 2)). */
static void test_nurbs_book_examples(void **state)
{
    (void)state;
    const double U[11] = {0, 0, 0, 1, 2, 3, 4, 4, 5, 5, 5};
    const double want[3][3] = {{0.125, 0.75, 0.125}, {-0.5, 0.0, 0.5}, {1.0, -2.0, 1.0}};
    for (int i = 2; i <= 4; ++i) {
        double P[8] = {0};
        P[i] = 1.0;
        geom_nurbs_curve c = {2, 8, 1, U, P, NULL};
        double a[3], b[3];
        assert_int_equal(geom_curve_nurbs_derivs(&c, 2.5, 2, 0, a), GEOM_OK);
        assert_int_equal(gv_sisl_curve_derivs(2, 8, 1, U, P, NULL, 2.5, 2, 0, b), GV_SISL_OK);
        for (int k = 0; k < 3; ++k) {
            assert_true(fabs(a[k] - want[k][i - 2]) <= 1e-15);
            assert_true(fabs(b[k] - want[k][i - 2]) <= 1e-15);
        }
    }
    const double K[6] = {0, 0, 0, 1, 1, 1}, Q[6] = {1, 0, 1, 1, 0, 1}, W[3] = {1, 1, 2};
    geom_nurbs_curve c = {2, 3, 2, K, Q, W};
    for (int i = 0; i <= 8; ++i) {
        double u = i / 8.0, a[6], b[6];
        assert_int_equal(geom_curve_nurbs_derivs(&c, u, 2, 0, a), GEOM_OK);
        assert_int_equal(gv_sisl_curve_derivs(2, 3, 2, K, Q, W, u, 2, 0, b), GV_SISL_OK);
        double d = 1 + u * u;
        double x = (1 - u * u) / d, y = 2 * u / d;
        double dx = -4 * u / (d * d), dy = 2 * (1 - u * u) / (d * d);
        double ddx = (12 * u * u - 4) / (d * d * d), ddy = (4 * u * u * u - 12 * u) / (d * d * d);
        const double ref[6] = {x, y, dx, dy, ddx, ddy};
        for (int k = 0; k < 6; ++k) {
            assert_true(fabs(a[k] - ref[k]) <= 1e-14);
            assert_true(fabs(b[k] - ref[k]) <= 1e-14);
        }
    }
    const double dir[3] = {0, 0, 2};
    double ku[6], kv[4], SP[18], SW[6];
    geom_nurbs_surface s;
    assert_int_equal(geom_surface_extrude(&c, dir, ku, kv, SP, SW, &s, NULL), GEOM_OK);
    double a[27], b[27];
    assert_int_equal(geom_surface_derivs(&s, 0.0, 0.5, 2, 0, a), GEOM_OK);
    assert_int_equal(gv_sisl_surface_derivs(2, 1, 3, 2, ku, kv, SP, SW, 0.0, 0.5, 2, b),
                     GV_SISL_OK);
    /* S = (1, 0, 1); S_u = (0, 2, 0); S_v = (0, 0, 2); S_uu = (-4, 0, 0) */
    const double ref[4][4] = {{0, 1, 0, 1}, {9, 0, 2, 0}, {3, 0, 0, 2}, {18, -4, 0, 0}};
    for (int r = 0; r < 4; ++r)
        for (int x = 0; x < 3; ++x) {
            int at = (int)ref[r][0] + x;
            assert_true(fabs(a[at] - ref[r][1 + x]) <= 1e-14);
            assert_true(fabs(b[at] - ref[r][1 + x]) <= 1e-14);
        }
}

#ifdef GV_HAVE_CGAL
/* The mesh as a soup, checked by CGAL. */
static gv_soup_info cgal_check(const geom_mesh *m)
{
    size_t ni = 0, nf = geom_mesh_n_live_faces(m), nv = geom_mesh_n_vertices(m);
    assert_int_equal(geom_mesh_to_soup(m, NULL, NULL, &ni), GEOM_OK);
    uint32_t *sizes = malloc(nf * sizeof(uint32_t)), *idx = malloc(ni * sizeof(uint32_t));
    assert_non_null(sizes);
    assert_non_null(idx);
    assert_int_equal(geom_mesh_to_soup(m, sizes, idx, &ni), GEOM_OK);
    gv_soup_info info;
    assert_int_equal(gv_soup_check(nv, geom_mesh_cpositions(m), nf, sizes, idx, &info), GV_OK);
    free(sizes);
    free(idx);
    return info;
}

static void test_watertight_cgal(void **state)
{
    (void)state;
    const char *dir = getenv("GEOM_TEST_DATA");
    char path[1024];
    snprintf(path, sizeof path, "%s/teapot.bpt", dir ? dir : "data");
    geom_surface_set *set = NULL;
    assert_int_equal(geom_surface_read_bpt(path, NULL, &set, NULL), GEOM_OK);
    const geom_nurbs_surface *S = geom_surface_set_data(set);
    geom_nurbs_surface body[16];
    for (int i = 0; i < 12; ++i)
        body[i] = S[i];
    for (int i = 0; i < 4; ++i)
        body[12 + i] = S[28 + i];
    geom_surface_tess_options o;
    memset(&o, 0, sizeof o);
    o.tolerance = 2e-3;
    geom_mesh *m = geom_mesh_create(NULL);
    assert_int_equal(geom_surface_tessellate(body, 16, &o, m, NULL, NULL, NULL), GEOM_OK);
    gv_soup_info info = cgal_check(m);
    assert_int_equal(info.is_polygon_soup_a_polygon_mesh, 1);
    assert_int_equal(info.valid, 1);
    assert_int_equal(info.closed, 0);
    assert_int_equal((int)info.border_cycles, 1); /* the opening under the lid */
    assert_int_equal((int)info.components, 1);
    assert_int_equal((int)info.genus, 0);
    assert_int_equal(info.self_intersecting, 0);
    print_message("teapot body: %zu faces, CGAL: polygon mesh, 1 border cycle, 1 component, "
                  "no self-intersection\n",
                  info.faces);
    /* the whole teapot: four parts, six rims; the handle and spout run
     * into the body without being trimmed, so it self-intersects */
    assert_int_equal(geom_surface_tessellate(S, 32, &o, m, NULL, NULL, NULL), GEOM_OK);
    info = cgal_check(m);
    assert_int_equal(info.is_polygon_soup_a_polygon_mesh, 1);
    assert_int_equal((int)info.components, 4);
    assert_int_equal((int)info.border_cycles, 6);
    assert_int_equal(info.self_intersecting, 1);
    geom_surface_set_destroy(set);
    /* sphere and torus: closed, genus 0 and 1, no self-intersection */
    double ku[12], kv[12], P[243], W[81];
    geom_nurbs_surface s;
    for (int shape = 0; shape < 2; ++shape) {
        if (shape == 0)
            assert_int_equal(geom_surface_sphere(NULL, 1.0, ku, kv, P, W, &s), GEOM_OK);
        else
            assert_int_equal(geom_surface_torus(NULL, 2.0, 0.5, ku, kv, P, W, &s), GEOM_OK);
        assert_int_equal(geom_surface_tessellate(&s, 1, &o, m, NULL, NULL, NULL), GEOM_OK);
        info = cgal_check(m);
        assert_int_equal(info.is_polygon_soup_a_polygon_mesh, 1);
        assert_int_equal(info.closed, 1);
        assert_int_equal((int)info.genus, shape);
        assert_int_equal(info.self_intersecting, 0);
    }
    geom_mesh_destroy(m);
}
#endif

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_curves_vs_sisl),
        cmocka_unit_test(test_surfaces_vs_sisl),
        cmocka_unit_test(test_shapes_vs_sisl),
        cmocka_unit_test(test_nurbs_book_examples),
#ifdef GV_HAVE_CGAL
        cmocka_unit_test(test_watertight_cgal),
#endif
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
