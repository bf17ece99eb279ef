/* Surface module: stiff and extreme cases, one test each. References: the
 * exact shapes (sphere, planes), invariances that hold exactly in exact
 * arithmetic (scaling all weights, translating, scaling the model), and a
 * long double evaluation of the same surfaces (A3.6/A4.4 with 64-bit
 * mantissas) for the rational and high-degree cases. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "geom/surface.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define EPS DBL_EPSILON

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

static double len3(const double *a)
{
    return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
}

static double dist3(const double *a, const double *b)
{
    double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    return len3(d);
}

/* ------------------------------------------- long double reference point */

typedef long double ld;

/* Cox-de Boor in long double: all basis functions of degree p at u (span k
 * with U[k] <= u < U[k+1], or the last span at the end). */
static size_t ld_basis(int p, size_t n, const double *U, ld u, ld *N)
{
    size_t k = (size_t)p;
    for (size_t i = (size_t)p; i < n; ++i)
        if (U[i] < U[i + 1] && (ld)U[i] <= u)
            k = i;
    ld left[64], right[64];
    N[0] = 1.0L;
    for (int j = 1; j <= p; ++j) {
        left[j] = u - (ld)U[k + 1 - (size_t)j];
        right[j] = (ld)U[k + (size_t)j] - u;
        ld saved = 0.0L;
        for (int r = 0; r < j; ++r) {
            ld t = N[r] / (right[r + 1] + left[j - r]);
            N[r] = saved + right[r + 1] * t;
            saved = left[j - r] * t;
        }
        N[j] = saved;
    }
    return k;
}

static void ld_point(const geom_nurbs_surface *s, double u, double v, double *out)
{
    ld Nu[64], Nv[64], A[4] = {0, 0, 0, 0};
    size_t ku = ld_basis(s->degree_u, s->nu, s->knots_u, u, Nu);
    size_t kv = ld_basis(s->degree_v, s->nv, s->knots_v, v, Nv);
    for (int i = 0; i <= s->degree_u; ++i)
        for (int j = 0; j <= s->degree_v; ++j) {
            size_t a = ku - (size_t)s->degree_u + (size_t)i, b = kv - (size_t)s->degree_v + (size_t)j;
            ld w = s->weights ? (ld)s->weights[a * s->nv + b] : 1.0L;
            ld c = Nu[i] * Nv[j] * w;
            for (int x = 0; x < 3; ++x)
                A[x] += c * (ld)s->points[3 * (a * s->nv + b) + (size_t)x];
            A[3] += c;
        }
    for (int x = 0; x < 3; ++x)
        out[x] = (double)(A[x] / A[3]);
}

/* ----------------------------------------------------------------- weights */

/* Scaling every weight by 1e8 or 1e-8 leaves a NURBS surface unchanged. */
static void test_weights_scaled(void **state)
{
    (void)state;
    double ku[12], kv[8], P[135], W[45], W2[45];
    geom_nurbs_surface s;
    assert_int_equal(geom_surface_sphere(NULL, 1.0, ku, kv, P, W, &s), GEOM_OK);
    const double scales[2] = {1e8, 1e-8};
    for (int k = 0; k < 2; ++k) {
        for (int i = 0; i < 45; ++i)
            W2[i] = W[i] * scales[k];
        geom_nurbs_surface t = s;
        t.weights = W2;
        for (int i = 0; i <= 32; ++i)
            for (int j = 0; j <= 32; ++j) {
                double u = i / 32.0, v = j / 32.0, a[3], b[3], na[3], nb[3];
                assert_int_equal(geom_surface_eval(&s, u, v, 0, a), GEOM_OK);
                assert_int_equal(geom_surface_eval(&t, u, v, 0, b), GEOM_OK);
                assert_true(dist3(a, b) <= 4 * EPS);
                assert_true(fabs(len3(b) - 1.0) <= 4 * EPS);
                assert_int_equal(geom_surface_normal(&s, u, v, 0, na, NULL), GEOM_OK);
                assert_int_equal(geom_surface_normal(&t, u, v, 0, nb, NULL), GEOM_OK);
                assert_true(dist3(na, nb) <= 8 * EPS);
            }
        geom_surface_tess_options o;
        memset(&o, 0, sizeof o);
        o.tolerance = 1e-3;
        geom_mesh *m = geom_mesh_create(NULL);
        geom_error_report rep;
        assert_int_equal(geom_surface_tessellate(&t, 1, &o, m, &rep, NULL, NULL), GEOM_OK);
        geom_mesh_topology tp;
        geom_mesh_topology_summary(m, &tp);
        assert_true(tp.closed && tp.manifold && tp.genus == 0);
        assert_true(rep.max_error <= 1e-3);
        geom_mesh_destroy(m);
    }
}

/* Weights from 1e-8 to 1e8 in one patch: points stay in the control box and
 * agree with the long double evaluation; normals are unit, never NaN. */
static void test_weights_extreme(void **state)
{
    (void)state;
    rng r = {777};
    double worst = 0.0;
    for (int rep = 0; rep < 20; ++rep) {
        double P[48], W[16], ku[8], kv[8];
        for (int i = 0; i < 48; ++i)
            P[i] = 2.0 * rnd(&r) - 1.0;
        for (int i = 0; i < 16; ++i)
            W[i] = pow(10.0, 16.0 * rnd(&r) - 8.0);
        geom_nurbs_surface s;
        geom_surface_bezier(3, 3, P, W, ku, kv, &s);
        assert_int_equal(geom_surface_validate(&s, NULL), GEOM_OK);
        for (int i = 0; i <= 16; ++i)
            for (int j = 0; j <= 16; ++j) {
                double u = i / 16.0, v = j / 16.0, a[3], b[3], n[3], D[27];
                assert_int_equal(geom_surface_eval(&s, u, v, 0, a), GEOM_OK);
                for (int x = 0; x < 3; ++x)
                    assert_true(a[x] >= -1.0 - 4 * EPS && a[x] <= 1.0 + 4 * EPS);
                ld_point(&s, u, v, b);
                worst = fmax(worst, dist3(a, b));
                assert_true(dist3(a, b) <= 1e-14);
                assert_int_equal(geom_surface_derivs(&s, u, v, 2, 0, D), GEOM_OK);
                for (int x = 0; x < 27; ++x)
                    assert_true(isfinite(D[x]));
                geom_status st = geom_surface_normal(&s, u, v, 0, n, NULL);
                assert_true(st == GEOM_OK);
                assert_true(fabs(len3(n) - 1.0) <= 4 * EPS);
            }
    }
    print_message("weights 1e-8..1e8: points within %.3g of the long double evaluation\n",
                  worst);
}

/* -------------------------------------------------------------------- knots */

/* A bicubic B-spline with a knot span of 1e-12 in u: continuous across it,
 * finite derivatives, and a tessellation with no crack or NaN. */
static void test_tiny_span(void **state)
{
    (void)state;
    const double ku[10] = {0, 0, 0, 0, 0.5, 0.5 + 1e-12, 1, 1, 1, 1};
    const double kv[8] = {0, 0, 0, 0, 1, 1, 1, 1};
    double P[6 * 4 * 3];
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 4; ++j) {
            double *X = P + 3 * (i * 4 + j);
            X[0] = i;
            X[1] = j;
            X[2] = sin(i + 2.0 * j);
        }
    geom_nurbs_surface s = {3, 3, 6, 4, ku, kv, P, NULL};
    assert_int_equal(geom_surface_validate(&s, NULL), GEOM_OK);
    double a[3], b[3], c[3];
    assert_int_equal(geom_surface_eval(&s, 0.5, 0.3, 0, a), GEOM_OK);
    assert_int_equal(geom_surface_eval(&s, 0.5 + 5e-13, 0.3, 0, b), GEOM_OK);
    assert_int_equal(geom_surface_eval(&s, 0.5 + 1e-12, 0.3, 0, c), GEOM_OK);
    assert_true(dist3(a, b) <= 1e-10 && dist3(b, c) <= 1e-10);
    double D[3 * 16];
    assert_int_equal(geom_surface_derivs(&s, 0.5 + 5e-13, 0.3, 3, 0, D), GEOM_OK);
    for (int x = 0; x < 48; ++x)
        assert_true(isfinite(D[x]));
    geom_surface_tess_options o;
    memset(&o, 0, sizeof o);
    o.tolerance = 1e-3;
    o.attributes = GEOM_SURFACE_ATTR_NORMAL;
    geom_mesh *m = geom_mesh_create(NULL);
    geom_error_report rep;
    assert_int_equal(geom_surface_tessellate(&s, 1, &o, m, &rep, NULL, NULL), GEOM_OK);
    geom_mesh_topology tp;
    geom_mesh_topology_summary(m, &tp);
    assert_int_equal((int)tp.components, 1);
    assert_int_equal((int)tp.boundary_loops, 1);
    assert_true(tp.manifold);
    assert_true(rep.max_error <= 1e-3);
    uint32_t cn = geom_mesh_channel_find(m, "normal", GEOM_MESH_DOMAIN_CORNER);
    const double *N = geom_mesh_channel_cdata(m, cn);
    for (size_t i = 0; i < 3 * geom_mesh_channel_size(m, cn); ++i)
        assert_true(isfinite(N[i]));
    geom_mesh_destroy(m);
}

/* Multiplicity p in u (a C0 crease, a roof): the one-sided normals are
 * the two planes' normals; the tessellation keeps one normal per side. */
static void test_crease(void **state)
{
    (void)state;
    const double ku[8] = {0, 0, 0, 1, 1, 2, 2, 2}; /* p = 2: rows 0-2 and 2-4 */
    const double kv[4] = {0, 0, 1, 1};
    double P[5 * 2 * 3];
    for (int i = 0; i < 5; ++i)
        for (int j = 0; j < 2; ++j) {
            double *X = P + 3 * (i * 2 + j);
            X[0] = i * 0.5;
            X[1] = j;
            X[2] = i <= 2 ? i * 0.5 : (4 - i) * 0.5; /* up to x = 1, then down */
        }
    geom_nurbs_surface s = {2, 1, 5, 2, ku, kv, P, NULL};
    double nr[3], nl[3];
    assert_int_equal(geom_surface_normal(&s, 1.0, 0.5, 0, nr, NULL), GEOM_OK);
    assert_int_equal(geom_surface_normal(&s, 1.0, 0.5, GEOM_SURFACE_U_LEFT, nl, NULL), GEOM_OK);
    /* planes z = x (left: normal (-1,0,1)/sqrt2) and z = 2 - x (right: (1,0,1)/sqrt2) */
    const double h = sqrt(0.5);
    assert_true(fabs(nl[0] + h) <= 4 * EPS && fabs(nl[2] - h) <= 4 * EPS);
    assert_true(fabs(nr[0] - h) <= 4 * EPS && fabs(nr[2] - h) <= 4 * EPS);
    geom_surface_tess_options o;
    memset(&o, 0, sizeof o);
    o.mode = GEOM_SURFACE_TESS_UNIFORM;
    o.grid_u = o.grid_v = 2;
    o.attributes = GEOM_SURFACE_ATTR_NORMAL;
    geom_mesh *m = geom_mesh_create(NULL);
    assert_int_equal(geom_surface_tessellate(&s, 1, &o, m, NULL, NULL, NULL), GEOM_OK);
    uint32_t cn = geom_mesh_channel_find(m, "normal", GEOM_MESH_DOMAIN_CORNER);
    /* exactly two distinct normals: one per plane */
    assert_int_equal((int)geom_mesh_channel_size(m, cn), 2);
    geom_mesh_destroy(m);
}

/* Multiplicity p+1 inside (a discontinuity): both one-sided values, and a
 * tessellation in two pieces (the gap is real). */
static void test_discontinuity(void **state)
{
    (void)state;
    const double ku[8] = {0, 0, 1, 1, 2, 2, 3, 3}; /* p = 1, knot 1 and 2 twice */
    const double kv[4] = {0, 0, 1, 1};
    double P[6 * 2 * 3];
    for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 2; ++j) {
            double *X = P + 3 * (i * 2 + j);
            X[0] = i;
            X[1] = j;
            X[2] = (i / 2) * 10.0; /* pieces at z = 0, 10, 20 */
        }
    geom_nurbs_surface s = {1, 1, 6, 2, ku, kv, P, NULL};
    assert_int_equal(geom_surface_validate(&s, NULL), GEOM_OK);
    double a[3], b[3];
    assert_int_equal(geom_surface_eval(&s, 1.0, 0.0, 0, a), GEOM_OK);
    assert_int_equal(geom_surface_eval(&s, 1.0, 0.0, GEOM_SURFACE_U_LEFT, b), GEOM_OK);
    assert_true(a[2] == 10.0 && b[2] == 0.0 && a[0] == 2.0 && b[0] == 1.0);
    geom_surface_tess_options o;
    memset(&o, 0, sizeof o);
    geom_mesh *m = geom_mesh_create(NULL);
    assert_int_equal(geom_surface_tessellate(&s, 1, &o, m, NULL, NULL, NULL), GEOM_OK);
    geom_mesh_topology tp;
    geom_mesh_topology_summary(m, &tp);
    assert_int_equal((int)tp.components, 3);
    geom_mesh_destroy(m);
}

/* Parameters exactly at the domain ends: corners are the control points
 * bit for bit, the next double outside is a domain error. */
static void test_domain_ends(void **state)
{
    (void)state;
    rng r = {99};
    for (int rep = 0; rep < 50; ++rep) {
        int p = 1 + rep % 5, q = 1 + (rep / 5) % 4;
        size_t nu = (size_t)p + 3, nv = (size_t)q + 2;
        double ku[16], kv[16], P[3 * 8 * 8], W[64];
        double a = -3.0 + rnd(&r), b = 2.0 + rnd(&r);
        for (size_t i = 0; i <= (size_t)p; ++i)
            ku[i] = a, ku[nu + i] = b;
        for (size_t i = (size_t)p + 1; i < nu; ++i)
            ku[i] = a + (b - a) * (double)(i - (size_t)p) / (double)(nu - (size_t)p);
        for (size_t j = 0; j <= (size_t)q; ++j)
            kv[j] = 0.25, kv[nv + j] = 0.75;
        for (size_t j = (size_t)q + 1; j < nv; ++j)
            kv[j] = 0.25 + 0.5 * (double)(j - (size_t)q) / (double)(nv - (size_t)q);
        for (size_t i = 0; i < 3 * nu * nv; ++i)
            P[i] = 10.0 * rnd(&r) - 5.0;
        for (size_t i = 0; i < nu * nv; ++i)
            W[i] = pow(10.0, 4.0 * rnd(&r) - 2.0);
        geom_nurbs_surface s = {p, q, nu, nv, ku, kv, P, rep % 2 ? W : NULL};
        assert_int_equal(geom_surface_validate(&s, NULL), GEOM_OK);
        const double us[2] = {a, b}, vs[2] = {0.25, 0.75};
        for (int x = 0; x < 2; ++x)
            for (int y = 0; y < 2; ++y) {
                double S[3];
                assert_int_equal(geom_surface_eval(&s, us[x], vs[y], 0, S), GEOM_OK);
                size_t i = x ? nu - 1 : 0, j = y ? nv - 1 : 0;
                assert_memory_equal(S, P + 3 * (i * nv + j), sizeof S);
            }
        double S[3];
        assert_int_equal(geom_surface_eval(&s, nextafter(b, INFINITY), 0.5, 0, S),
                         GEOM_ERR_DOMAIN);
        assert_int_equal(geom_surface_eval(&s, a, nextafter(0.25, 0.0), 0, S), GEOM_ERR_DOMAIN);
        /* the end of the domain is the left limit there */
        double L[3];
        assert_int_equal(geom_surface_eval(&s, b, 0.5, 0, S), GEOM_OK);
        assert_int_equal(geom_surface_eval(&s, b, 0.5, GEOM_SURFACE_U_LEFT, L), GEOM_OK);
        assert_memory_equal(S, L, sizeof S);
    }
}

/* ----------------------------------------------------------------- degree */

/* A degree 25 x 3 Bezier patch against long double; derivatives finite. */
static void test_degree_25(void **state)
{
    (void)state;
    rng r = {25};
    double P[3 * 26 * 4], ku[52], kv[8];
    for (int i = 0; i < 3 * 26 * 4; ++i)
        P[i] = 2.0 * rnd(&r) - 1.0;
    geom_nurbs_surface s;
    assert_int_equal(geom_surface_bezier(25, 3, P, NULL, ku, kv, &s), GEOM_OK);
    double worst = 0.0;
    for (int i = 0; i <= 40; ++i)
        for (int j = 0; j <= 4; ++j) {
            double u = i / 40.0, v = j / 4.0, a[3], b[3], D[3 * 16], n[3];
            assert_int_equal(geom_surface_eval(&s, u, v, 0, a), GEOM_OK);
            ld_point(&s, u, v, b);
            worst = fmax(worst, dist3(a, b));
            assert_true(dist3(a, b) <= 1e-14);
            assert_int_equal(geom_surface_derivs(&s, u, v, 3, 0, D), GEOM_OK);
            for (int x = 0; x < 48; ++x)
                assert_true(isfinite(D[x]));
            assert_int_equal(geom_surface_normal(&s, u, v, 0, n, NULL), GEOM_OK);
            assert_true(fabs(len3(n) - 1.0) <= 4 * EPS);
        }
    print_message("degree 25: points within %.3g of long double\n", worst);
}

/* ----------------------------------------------------------------- offsets */

/* The sphere moved to (1e8, 1e8, 1e8): the derivatives are computed from
 * control points relative to the span, so the normals keep the accuracy of
 * the (rounded) control points, ~1e-8, instead of losing it all. */
static void test_offset_1e8(void **state)
{
    (void)state;
    geom_surface_frame f = {{1e8, 1e8, 1e8}, {0, 0, 1}, {1, 0, 0}};
    double ku[12], kv[8], P[135], W[45], P0[135], W0[45];
    geom_nurbs_surface s, s0;
    assert_int_equal(geom_surface_sphere(&f, 1.0, ku, kv, P, W, &s), GEOM_OK);
    assert_int_equal(geom_surface_sphere(NULL, 1.0, ku, kv, P0, W0, &s0), GEOM_OK);
    for (int i = 0; i <= 32; ++i)
        for (int j = 0; j <= 32; ++j) {
            double u = i / 32.0, v = j / 32.0, a[3], b[3];
            assert_int_equal(geom_surface_normal(&s, u, v, 0, a, NULL), GEOM_OK);
            assert_int_equal(geom_surface_normal(&s0, u, v, 0, b, NULL), GEOM_OK);
            assert_true(dist3(a, b) <= 1e-15 * 8); /* the nets differ by rounding only */
            double D[12], D0[12];
            assert_int_equal(geom_surface_derivs(&s, u, v, 1, 0, D), GEOM_OK);
            assert_int_equal(geom_surface_derivs(&s0, u, v, 1, 0, D0), GEOM_OK);
            assert_true(dist3(D + 3, D0 + 3) <= 1e-14 * fmax(1.0, len3(D0 + 3)));
            assert_true(dist3(D + 6, D0 + 6) <= 1e-14 * fmax(1.0, len3(D0 + 6)));
            double c[3] = {D[0] - 1e8, D[1] - 1e8, D[2] - 1e8};
            assert_true(fabs(len3(c) - 1.0) <= 4e8 * EPS);
        }
    geom_surface_tess_options o;
    memset(&o, 0, sizeof o);
    o.tolerance = 1e-3;
    geom_mesh *m = geom_mesh_create(NULL);
    geom_error_report rep;
    assert_int_equal(geom_surface_tessellate(&s, 1, &o, m, &rep, NULL, NULL), GEOM_OK);
    geom_mesh_topology tp;
    geom_mesh_topology_summary(m, &tp);
    assert_true(tp.closed && tp.manifold && tp.genus == 0);
    assert_true(rep.max_error <= 1e-3);
    geom_mesh_destroy(m);
}

/* Scale invariance over 300 orders of magnitude: the normals of spheres of
 * radius 1e-150 and 1e150 are those of the unit sphere. */
static void test_scale_extremes(void **state)
{
    (void)state;
    double ku[12], kv[8], P[135], W[45], P0[135], W0[45];
    geom_nurbs_surface s, s0;
    assert_int_equal(geom_surface_sphere(NULL, 1.0, ku, kv, P0, W0, &s0), GEOM_OK);
    const double radii[2] = {1e-150, 1e150};
    for (int k = 0; k < 2; ++k) {
        assert_int_equal(geom_surface_sphere(NULL, radii[k], ku, kv, P, W, &s), GEOM_OK);
        for (int i = 0; i <= 16; ++i)
            for (int j = 0; j <= 16; ++j) {
                double u = i / 16.0, v = j / 16.0, a[3], b[3];
                int how;
                assert_int_equal(geom_surface_normal(&s, u, v, 0, a, &how), GEOM_OK);
                assert_int_equal(geom_surface_normal(&s0, u, v, 0, b, NULL), GEOM_OK);
                assert_true(dist3(a, b) <= 8 * EPS);
            }
    }
}

/* ------------------------------------------------------------------- poles */

/* Normals at the poles and at the teapot's collapsed centres: vertical,
 * and nowhere NaN over a dense grid of every teapot patch. */
static void test_poles(void **state)
{
    (void)state;
    double ku[12], kv[8], P[135], W[45];
    geom_nurbs_surface s;
    assert_int_equal(geom_surface_sphere(NULL, 1.0, ku, kv, P, W, &s), GEOM_OK);
    for (int i = 0; i <= 100; ++i) {
        double n[3];
        int how;
        assert_int_equal(geom_surface_normal(&s, i / 100.0, 0.0, 0, n, &how), GEOM_OK);
        assert_int_equal(how, GEOM_SURFACE_NORMAL_LIMIT);
        assert_true(n[0] == 0.0 && n[1] == 0.0 && n[2] == -1.0);
        assert_int_equal(geom_surface_normal(&s, i / 100.0, 1.0, 0, n, &how), GEOM_OK);
        assert_true(n[0] == 0.0 && n[1] == 0.0 && n[2] == 1.0);
        /* a hair away from the pole: regular, and already close to it */
        assert_int_equal(geom_surface_normal(&s, i / 100.0, 1e-9, 0, n, &how), GEOM_OK);
        assert_true(n[2] < -1.0 + 1e-15 * 100);
    }
    const char *dir = getenv("GEOM_TEST_DATA");
    char path[1024];
    snprintf(path, sizeof path, "%s/teapot.bpt", dir ? dir : "data");
    geom_surface_set *set = NULL;
    assert_int_equal(geom_surface_read_bpt(path, NULL, &set, NULL), GEOM_OK);
    const geom_nurbs_surface *T = geom_surface_set_data(set);
    size_t limits = 0;
    for (size_t k = 0; k < geom_surface_set_count(set); ++k)
        for (int i = 0; i <= 40; ++i)
            for (int j = 0; j <= 40; ++j) {
                double n[3], S[3];
                int how;
                geom_status st = geom_surface_normal(&T[k], i / 40.0, j / 40.0, 0, n, &how);
                assert_int_equal(st, GEOM_OK);
                assert_true(fabs(len3(n) - 1.0) <= 4 * EPS);
                if (how != GEOM_SURFACE_NORMAL_LIMIT)
                    continue;
                limits++;
                assert_int_equal(geom_surface_eval(&T[k], i / 40.0, j / 40.0, 0, S), GEOM_OK);
                /* the collapsed points are on the axis: bottom centre
                 * (z = 0, facing down) and lid top (z = 3.15, facing up) */
                assert_true(fabs(S[0]) < 1e-15 && fabs(S[1]) < 1e-15);
                assert_true(fabs(n[0]) < 1e-12 && fabs(n[1]) < 1e-12);
                assert_true(S[2] < 1.0 ? n[2] < 0.0 : n[2] > 0.0);
            }
    assert_int_equal((int)limits, 8 * 41);
    geom_surface_set_destroy(set);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_weights_scaled),
        cmocka_unit_test(test_weights_extreme),
        cmocka_unit_test(test_tiny_span),
        cmocka_unit_test(test_crease),
        cmocka_unit_test(test_discontinuity),
        cmocka_unit_test(test_domain_ends),
        cmocka_unit_test(test_degree_25),
        cmocka_unit_test(test_offset_1e8),
        cmocka_unit_test(test_scale_extremes),
        cmocka_unit_test(test_poles),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
