/* Surface module: the tessellation's error measure (issue 14), checked
 * against closed forms, and the segment-count bound of its grid search.
 *
 * The reported (and refinement-driving) error is the distance from the
 * surface point at each sample of a triangle's parameter-space image to
 * the 3D triangle (to the triangle's side for samples on a side), not to
 * the triangle's point at the same parameters:
 *  - a plane with rational weights 0.1..10 lies on its triangles: error 0
 *    (the equal-parameter distance counted its uneven parametrisation);
 *  - a cylinder's 90-degree rational span cut into 2 columns: the chord
 *    of 45 degrees deviates by R (1 - cos 22.5 deg) (dense samples reach it
 *    within 1e-3 and never exceed it), less than the equal-parameter
 *    distance at the same samples;
 *  - the NURBS sphere octant as one triangle: 1 - 1/sqrt(3) (its plane is
 *    at distance 1/sqrt(3) from the centre), within 1e-3;
 *  - extreme weights on a plane and on a sphere octant: adaptive at 1e-3
 *    needs at most a small factor of the triangles of the same shape with
 *    ordinary weights (the octant: at most 2x with weights 0.1..10 and
 *    0.01..100, the grid lines placed by the chord error, not uniformly in
 *    the parameter), and the reported error is checked against the closed
 *    form: a triangle with its corners on the unit sphere is farthest from
 *    the sphere at its point nearest the centre, 1 - that distance; the
 *    upper hemisphere as four weighted octants welded along their
 *    meridians stays one watertight disc with the same bounds;
 *  - fold guard: a plane patch whose parametrisation folds over itself
 *    (x(u) goes back and forth) lies on its two triangles, but the sample
 *    lattice's triangles face against them, so the error there is the
 *    equal-parameter one and the fold is refined, not hidden.
 * The grid-line placement (geom__tess_warp_*) against the density's
 * integral summed here. Then geom__tess_lines_bound (the smallest segment count whose chords pass
 * along given curves) against a linear scan written here, on curves whose
 * check is not monotone in the count (kinks at rational parameters). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "geom/surface.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

/* Internal (libgeom/src/surface/surface_internal.h; the tests link the
 * static library). */
typedef void (*geom__tess_line_fn)(void *user, int line, double t, double out[3]);
int geom__tess_lines_pass(geom__tess_line_fn fn, void *user, int nlines, double a, double b, int K,
                          uint32_t n, double tol, double *hint);
uint32_t geom__tess_lines_bound(geom__tess_line_fn fn, void *user, int nlines, double a, double b,
                                int K, uint32_t cap, double tol);
int geom__tess_warp_build(const double *rho, int n, double ratio, double floor_frac, double *F);
double geom__tess_warp_y(const double *F, int n, double f);
double geom__tess_warp_f(const double *F, int n, double y);

static size_t tess(const geom_nurbs_surface *s, size_t n, const geom_surface_tess_options *o,
                   double *err, geom_mesh **keep)
{
    geom_mesh *m = geom_mesh_create(NULL);
    assert_non_null(m);
    geom_error_report rep;
    geom_surface_tess_stats st;
    geom_diag d;
    geom_diag_clear(&d);
    geom_status rc = geom_surface_tessellate(s, n, o, m, &rep, &st, &d);
    if (rc != GEOM_OK)
        fail_msg("tessellate: %s (%s)", geom_status_str(rc), d.message);
    *err = rep.max_error;
    size_t t = st.triangles;
    if (keep)
        *keep = m;
    else
        geom_mesh_destroy(m);
    return t;
}

static size_t uniform(const geom_nurbs_surface *s, int gu, int gv, int K, double *err)
{
    geom_surface_tess_options o;
    memset(&o, 0, sizeof o);
    o.mode = GEOM_SURFACE_TESS_UNIFORM;
    o.grid_u = gu;
    o.grid_v = gv;
    o.check_subdivisions = K;
    return tess(s, 1, &o, err, NULL);
}

static size_t adaptive(const geom_nurbs_surface *s, double tol, double *err)
{
    geom_surface_tess_options o;
    memset(&o, 0, sizeof o);
    o.tolerance = tol;
    return tess(s, 1, &o, err, NULL);
}

/* A biquadratic patch: control points (i/2, j/2, 0), weights a^i b^j / c. */
static void plane_patch(double a, double b, double c, double *P, double *W, double *ku, double *kv,
                        geom_nurbs_surface *s)
{
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double *p = P + 3 * (i * 3 + j);
            p[0] = 0.5 * i, p[1] = 0.5 * j, p[2] = 0.0;
            W[i * 3 + j] = pow(a, i) * pow(b, j) / c;
        }
    assert_int_equal(geom_surface_bezier(2, 2, P, W, ku, kv, s), GEOM_OK);
}

static void test_plane_weights(void **state)
{
    (void)state;
    double P[27], W[9], ku[6], kv[6], P1[27], W1[9], ku1[6], kv1[6];
    geom_nurbs_surface s, s1;
    double r10 = sqrt(10.0);
    plane_patch(r10, r10, 10.0, P, W, ku, kv, &s); /* weights 0.1 .. 10 */
    plane_patch(1.0, 1.0, 1.0, P1, W1, ku1, kv1, &s1);
    double e, e1;
    /* on its triangles, however uneven the parametrisation */
    uniform(&s, 4, 4, 8, &e);
    assert_true(e <= 1e-14);
    size_t n = adaptive(&s, 1e-3, &e), n1 = adaptive(&s1, 1e-3, &e1);
    print_message("plane weights 0.1..10: %zu triangles (error %g); unit weights %zu (%g)\n", n,
                  e, n1, e1);
    assert_true(e <= 1e-3 && e1 <= 1e-3);
    assert_true(n <= 2 * n1);
}

/* The sphere octant (u in [0, 1/4], v in [1/2, 1] of geom_surface_sphere)
 * as a biquadratic rational Bezier patch, weights times a^i b^j / c. */
static void octant(double a, double b, double c, double *P, double *W, double *ku, double *kv,
                   geom_nurbs_surface *s)
{
    double sku[12], skv[8], SP[135], SW[45];
    geom_nurbs_surface sph;
    assert_int_equal(geom_surface_sphere(NULL, 1.0, sku, skv, SP, SW, &sph), GEOM_OK);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            memcpy(P + 3 * (i * 3 + j), SP + 3 * (i * 5 + j + 2), 3 * sizeof(double));
            W[i * 3 + j] = SW[i * 5 + j + 2] * pow(a, i) * pow(b, j) / c;
        }
    assert_int_equal(geom_surface_bezier(2, 2, P, W, ku, kv, s), GEOM_OK);
}

static double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Distance from the origin to segment ab. */
static double origin_seg(const double *a, const double *b)
{
    double d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, p[3];
    double t = -dot3(a, d) / dot3(d, d);
    t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
    for (int k = 0; k < 3; ++k)
        p[k] = a[k] + t * d[k];
    return sqrt(dot3(p, p));
}

/* Distance from the origin to triangle abc: |x|^2 is convex, so its
 * minimum is the plane's foot when that lies inside, else on a side. */
static double origin_tri(const double *a, const double *b, const double *c)
{
    double e1[3], e2[3], n[3];
    for (int k = 0; k < 3; ++k)
        e1[k] = b[k] - a[k], e2[k] = c[k] - a[k];
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double nn = dot3(n, n), s = dot3(a, n) / nn, f[3];
    for (int k = 0; k < 3; ++k)
        f[k] = s * n[k]; /* the foot of the origin on the plane */
    double inside = 1;
    const double *X[3] = {a, b, c};
    for (int k = 0; k < 3; ++k) {
        const double *p = X[k], *q = X[(k + 1) % 3];
        double pq[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
        double pf[3] = {f[0] - p[0], f[1] - p[1], f[2] - p[2]}, x[3];
        x[0] = pq[1] * pf[2] - pq[2] * pf[1];
        x[1] = pq[2] * pf[0] - pq[0] * pf[2];
        x[2] = pq[0] * pf[1] - pq[1] * pf[0];
        if (dot3(x, n) < 0.0)
            inside = 0;
    }
    if (inside)
        return sqrt(dot3(f, f));
    return fmin(origin_seg(a, b), fmin(origin_seg(b, c), origin_seg(a, c)));
}

/* An adaptive mesh of a part of the unit sphere: corners on the sphere,
 * one manifold disc; its distance from the sphere (closed form, see the
 * top) and its area to *dist, *area; returns the triangles. */
static size_t sphere_patches(const geom_nurbs_surface *s, size_t ns, double tol, double *err,
                             double *dist, double *area)
{
    geom_surface_tess_options o;
    memset(&o, 0, sizeof o);
    o.tolerance = tol;
    geom_mesh *m = NULL;
    size_t n = tess(s, ns, &o, err, &m);
    geom_mesh_topology t;
    assert_int_equal(geom_mesh_topology_summary(m, &t), GEOM_OK);
    assert_true(t.manifold);
    assert_int_equal(t.components, 1);
    assert_int_equal(t.boundary_loops, 1);
    assert_int_equal(t.euler, 1);
    assert_int_equal(t.degenerate_faces, 0);
    const double *X = geom_mesh_cpositions(m);
    *dist = 0.0, *area = 0.0;
    for (uint32_t f = 0; f < geom_mesh_n_faces(m); ++f) {
        uint32_t h = geom_mesh_face_he(m, f);
        const double *V[3];
        for (int k = 0; k < 3; ++k) {
            V[k] = X + 3 * (size_t)geom_mesh_he_vertex(m, h);
            assert_true(fabs(sqrt(dot3(V[k], V[k])) - 1.0) <= 1e-12);
            h = geom_mesh_he_next(m, h);
        }
        *dist = fmax(*dist, 1.0 - origin_tri(V[0], V[1], V[2]));
        double e1[3], e2[3];
        for (int k = 0; k < 3; ++k)
            e1[k] = V[1][k] - V[0][k], e2[k] = V[2][k] - V[0][k];
        double c[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                       e1[0] * e2[1] - e1[1] * e2[0]};
        *area += 0.5 * sqrt(dot3(c, c));
    }
    geom_mesh_destroy(m);
    return n;
}

static size_t sphere_patch(const geom_nurbs_surface *s, double tol, double *err, double *dist,
                           double *area)
{
    return sphere_patches(s, 1, tol, err, dist, area);
}

static void test_sphere_weights(void **state)
{
    (void)state;
    double P[27], W[9], ku[6], kv[6], P1[27], W1[9], ku1[6], kv1[6];
    geom_nurbs_surface s, s1;
    double r10 = sqrt(10.0);
    octant(1.0, 1.0, 1.0, P1, W1, ku1, kv1, &s1);
    double e1, d1, a1;
    size_t n1 = sphere_patch(&s1, 1e-3, &e1, &d1, &a1);
    /* weights 0.1..10 and 0.01..100 (times the octant's own) */
    const double ab[2] = {r10, 10.0};
    for (int c = 0; c < 2; ++c) {
        octant(ab[c], ab[c], ab[c] * ab[c], P, W, ku, kv, &s);
        double wmin = 1e300, wmax = 0.0;
        for (int k = 0; k < 9; ++k)
            wmin = fmin(wmin, W[k]), wmax = fmax(wmax, W[k]);
        double e, d, a;
        size_t n = sphere_patch(&s, 1e-3, &e, &d, &a);
        print_message("sphere octant weights %.3g..%.3g: %zu triangles (error %g, closed form "
                      "%g, area %.6f); sphere weights %zu (%g, %g, %.6f): %.2fx\n",
                      wmin, wmax, n, e, d, a, n1, e1, d1, a1, (double)n / (double)n1);
        /* the reported error is sampled: never above the closed form, and
         * near it (the lattice samples miss the exact worst point) */
        assert_true(e <= 1e-3 && e1 <= 1e-3);
        assert_true(e <= d + 1e-12 && e1 <= d1 + 1e-12);
        assert_true(d <= 1.05e-3 && d1 <= 1.05e-3);
        assert_true(e >= 0.95 * d && e1 >= 0.95 * d1);
        /* the octant is covered: projecting the mesh radially onto the
         * sphere scales its area by at most 1/|x|^3 <= 1/(1 - d)^3, so an
         * inscribed mesh covering the octant has at least (1 - d)^3 of its
         * area pi/2 (a hole shows in the topology: one boundary loop,
         * Euler characteristic 1) */
        assert_true(a <= PI / 2 && a >= PI / 2 * pow(1.0 - d, 3.0));
        /* 7.8x (0.1..10) with one uniform grid per cell, where the
         * parametric speed varies about 3x along each direction; 1.04x and
         * 1.59x measured with the lines placed by the chord error */
        assert_true(n <= 2 * n1);
    }
    /* one triangle (the other has both corners on the pole): its plane
     * x + y + z = 1 is 1/sqrt(3) from the centre; the surface point over
     * its centroid, (1,1,1)/sqrt(3), is 1 - 1/sqrt(3) from it */
    double closed = 1.0 - 1.0 / sqrt(3.0), e;
    assert_int_equal(uniform(&s1, 1, 1, 64, &e), 1);
    print_message("octant as one triangle: %.9f, closed form %.9f\n", e, closed);
    assert_true(e <= closed + 1e-12 && e >= closed * (1.0 - 1e-3));
}

/* The upper hemisphere as four octants (u quarter q of geom_surface_sphere),
 * weights times a^i b^j / c each: the octants' shared meridians are the
 * same curves with the same parametrisation (their weights differ by a
 * constant factor), so they are welded, and their rows' grid lines must
 * agree for the mesh to stay one watertight disc. */
static void test_hemisphere_weights(void **state)
{
    (void)state;
    double sku[12], skv[8], SP[135], SW[45];
    geom_nurbs_surface sph;
    assert_int_equal(geom_surface_sphere(NULL, 1.0, sku, skv, SP, SW, &sph), GEOM_OK);
    double P[2][4][27], W[2][4][9], ku[2][4][6], kv[2][4][6];
    geom_nurbs_surface s[2][4];
    const double ab[2] = {1.0, sqrt(10.0)};
    size_t n[2];
    for (int c = 0; c < 2; ++c) {
        for (int q = 0; q < 4; ++q) {
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) {
                    size_t k = (size_t)(2 * q + i) * 5 + (size_t)j + 2;
                    memcpy(P[c][q] + 3 * (i * 3 + j), SP + 3 * k, 3 * sizeof(double));
                    W[c][q][i * 3 + j] = SW[k] * pow(ab[c], i) * pow(ab[c], j) / (ab[c] * ab[c]);
                }
            assert_int_equal(geom_surface_bezier(2, 2, P[c][q], W[c][q], ku[c][q], kv[c][q],
                                                 &s[c][q]),
                             GEOM_OK);
        }
        double e, d, a;
        n[c] = sphere_patches(s[c], 4, 1e-3, &e, &d, &a);
        print_message("hemisphere, 4 octants, weights x %.3g..%.3g: %zu triangles (error %g, "
                      "closed form %g, area %.6f)\n",
                      1.0 / (ab[c] * ab[c]), ab[c] * ab[c], n[c], e, d, a);
        assert_true(e <= 1e-3 && e <= d + 1e-12 && d <= 1.05e-3 && e >= 0.95 * d);
        assert_true(a <= 2.0 * PI && a >= 2.0 * PI * pow(1.0 - d, 3.0)); /* the area 2 pi */
    }
    assert_true(n[1] <= 2 * n[0]);
}

/* The grid-line placement (tess_warp.c): F is the normalised integral of
 * the floored density, warp_y its inverse; equal steps in f are equal
 * integrals of the density (checked by summing it here). */
static void test_warp(void **state)
{
    (void)state;
    enum { n = 32 };
    double rho[n], F[n + 1];
    for (int i = 0; i < n; ++i)
        rho[i] = 1.0;
    assert_int_equal(geom__tess_warp_build(rho, n, 1.8, 0.3, F), 0); /* even: none */
    rho[3] = NAN;
    assert_int_equal(geom__tess_warp_build(rho, n, 1.8, 0.3, F), 0);
    for (int i = 0; i < n; ++i)
        rho[i] = 0.0;
    assert_int_equal(geom__tess_warp_build(rho, n, 1.8, 0.3, F), 0);
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
        rho[i] = i < 8 ? 0.0 : 1.0 + 10.0 * (double)i / n; /* a flat part: the floor */
        sum += rho[i];
    }
    assert_int_equal(geom__tess_warp_build(rho, n, 1.8, 0.3, F), 1);
    assert_true(F[0] == 0.0 && F[n] == 1.0);
    double fl = 0.3 * sum / n, tot = 0.0;
    for (int i = 0; i < n; ++i) {
        assert_true(F[i + 1] > F[i]);
        tot += fmax(rho[i], fl);
    }
    assert_true(geom__tess_warp_y(F, n, 0.0) == 0.0 && geom__tess_warp_y(F, n, 1.0) == 1.0);
    for (int k = 0; k <= 1000; ++k) {
        double y = k / 1000.0, f = geom__tess_warp_f(F, n, y);
        assert_true(fabs(geom__tess_warp_y(F, n, f) - y) <= 1e-14);
        /* the integral of the floored density up to y, over the total */
        double x = y * n, acc = 0.0;
        for (int i = 0; i < n && i < x; ++i)
            acc += fmax(rho[i], fl) * fmin(1.0, x - i);
        assert_true(fabs(f - acc / tot) <= 1e-14);
    }
}

static void test_cylinder_closed_form(void **state)
{
    (void)state;
    double ku[12], kv[4], P[54], W[18];
    geom_nurbs_surface s;
    double R = 2.0;
    assert_int_equal(geom_surface_cylinder(NULL, R, 3.0, ku, kv, P, W, &s), GEOM_OK);
    double e;
    /* one chord per 90-degree span: symmetric, the middle sample is the
     * arc's middle */
    uniform(&s, 1, 1, 4, &e);
    double c1 = R * (1.0 - cos(PI / 4.0));
    assert_true(fabs(e - c1) <= 1e-12);
    /* two columns per span: parameter 1/2 is 45 degrees, each chord spans
     * 45 degrees but its parameter is not uniform in the angle */
    double c2 = R * (1.0 - cos(PI / 8.0));
    uniform(&s, 2, 1, 64, &e);
    print_message("cylinder 2 columns per span: %.9f, closed form %.9f\n", e, c2);
    assert_true(e <= c2 + 1e-12 && e >= c2 * (1.0 - 1e-3));
    /* with 4 samples per side the nearest sample to the chord's middle is
     * at 21.6 degrees: below the closed form, and the equal-parameter
     * distance there (the chord's middle point) is above it */
    uniform(&s, 2, 1, 4, &e);
    double t = 0.25, w = sqrt(0.5);
    double den = (1 - t) * (1 - t) + 2 * t * (1 - t) * w + t * t;
    double x = ((1 - t) * (1 - t) + 2 * t * (1 - t) * w) / den;
    double y = (2 * t * (1 - t) * w + t * t) / den;
    double phi = atan2(y, x), half = PI / 8.0;
    double expect = R * (cos(phi - half) - cos(half));
    assert_true(fabs(e - expect) <= 1e-12);
    double mid[2] = {R * 0.5 * (1.0 + cos(2 * half)), R * 0.5 * sin(2 * half)};
    double eq = hypot(R * x - mid[0], R * y - mid[1]);
    assert_true(eq > c2 && e < eq);
}

static void test_fold_guard(void **state)
{
    (void)state;
    /* x(u): cubic with control values 0, 1.5, -0.5, 1 goes 0 -> 0.6 ->
     * 0.4 -> 1 (in [0, 1]: every point lies on the unit square); y = v */
    static const double xs[4] = {0.0, 1.5, -0.5, 1.0};
    double P[24], ku[8], kv[4];
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 2; ++j) {
            double *p = P + 3 * (i * 2 + j);
            p[0] = xs[i], p[1] = (double)j, p[2] = 0.0;
        }
    geom_nurbs_surface s;
    assert_int_equal(geom_surface_bezier(3, 1, P, NULL, ku, kv, &s), GEOM_OK);
    double e;
    /* two triangles over the unit square: the distance to them is 0, the
     * fold makes it the equal-parameter distance */
    uniform(&s, 1, 1, 8, &e);
    print_message("folded plane, 1 x 1: error %g\n", e);
    assert_true(e > 0.1);
    /* adaptive refines until the fold is in the mesh: triangles facing -z */
    geom_surface_tess_options o;
    memset(&o, 0, sizeof o);
    o.tolerance = 1e-3;
    geom_mesh *m = NULL;
    size_t n = tess(&s, 1, &o, &e, &m);
    assert_true(e <= 1e-3 && n > 2);
    size_t down = 0;
    for (uint32_t f = 0; f < geom_mesh_n_faces(m); ++f) {
        double nf[3];
        assert_int_equal(geom_mesh_face_normal(m, f, nf), GEOM_OK);
        down += nf[2] < 0.0;
    }
    print_message("folded plane at 1e-3: %zu triangles, %zu facing -z\n", n, down);
    assert_true(down > 0);
    geom_mesh_destroy(m);
}

/* ------------------------------------------------------ lines bound */

typedef struct kinks {
    int n;       /* kinks of the zigzag: at t_k, heights h_k */
    double t[8], h[8];
} kinks;

/* Line l: (t, f(t) (1 + l), 0) with f piecewise linear through (0, 0),
 * (t_k, h_k), (1, 0). */
static void kink_point(void *user, int l, double t, double out[3])
{
    const kinks *k = user;
    double t0 = 0.0, h0 = 0.0, f = 0.0;
    for (int i = 0; i <= k->n; ++i) {
        double t1 = i < k->n ? k->t[i] : 1.0, h1 = i < k->n ? k->h[i] : 0.0;
        if (t <= t1 || i == k->n) {
            f = t1 > t0 ? h0 + (h1 - h0) * (t - t0) / (t1 - t0) : h1;
            break;
        }
        t0 = t1, h0 = h1;
    }
    out[0] = t, out[1] = f * (1.0 + l), out[2] = 0.0;
}

static double seg_dist(const double *p, const double *a, const double *b)
{
    double ab[3], ap[3], l = 0.0, d = 0.0;
    for (int k = 0; k < 3; ++k)
        ab[k] = b[k] - a[k], ap[k] = p[k] - a[k], l += ab[k] * ab[k], d += ab[k] * ap[k];
    double s = l > 0.0 ? fmin(1.0, fmax(0.0, d / l)) : 0.0;
    double r = 0.0;
    for (int k = 0; k < 3; ++k)
        r += (a[k] + s * ab[k] - p[k]) * (a[k] + s * ab[k] - p[k]);
    return sqrt(r);
}

/* The check at n, segment by segment in order (the reference). */
static int brute_pass(const kinks *k, int nlines, int K, uint32_t n, double tol)
{
    for (int l = 0; l < nlines; ++l)
        for (uint32_t i = 0; i < n; ++i) {
            double t0 = (double)i / n, t1 = i + 1 == n ? 1.0 : (double)(i + 1) / n, P0[3], P1[3];
            kink_point((void *)k, l, t0, P0);
            kink_point((void *)k, l, t1, P1);
            for (int m = 1; m < K; ++m) {
                double f = (double)m / K, S[3];
                kink_point((void *)k, l, (1 - f) * t0 + f * t1, S);
                if (!(seg_dist(S, P0, P1) <= tol))
                    return 0;
            }
        }
    return 1;
}

static void test_lines_bound(void **state)
{
    (void)state;
    /* kinks at 1/3 and 2/3: 3 segments pass exactly, 4 and 5 fail, 6
     * passes: a bisection between 1 and 8 would miss 3 */
    kinks k = {2, {1.0 / 3.0, 2.0 / 3.0}, {0.2, -0.1}};
    double tol = 1e-6;
    assert_int_equal(brute_pass(&k, 2, 4, 3, tol), 1);
    assert_int_equal(brute_pass(&k, 2, 4, 4, tol), 0);
    assert_int_equal(brute_pass(&k, 2, 4, 6, tol), 1);
    assert_int_equal(geom__tess_lines_bound(kink_point, &k, 2, 0.0, 1.0, 4, 64, tol), 3);
    /* random zigzags with kinks at rationals p/q: the bound equals the
     * linear scan's, and every single check agrees with the reference
     * whatever hint it gets */
    uint64_t seed = 12345;
    size_t nonmono = 0;
    for (int trial = 0; trial < 300; ++trial) {
        kinks z;
        memset(&z, 0, sizeof z);
        seed = seed * 6364136223846793005ull + 1442695040888963407ull;
        z.n = 1 + (int)((seed >> 33) % 4);
        int q = 2 + (int)((seed >> 40) % 9);
        double last = 0.0;
        for (int i = 0; i < z.n; ++i) {
            seed = seed * 6364136223846793005ull + 1442695040888963407ull;
            int p = 1 + (int)((seed >> 33) % (uint64_t)(q - 1));
            double t = (double)p / q;
            if (t <= last)
                t = last + 0.5 * (1.0 - last) * ((seed >> 45) % 7 + 1) / 8.0;
            z.t[i] = last = t;
            z.h[i] = ((double)((seed >> 20) % 1000) / 1000.0 - 0.5) * 0.3;
        }
        int K = 2 + trial % 4;
        double tl = trial % 3 ? 1e-9 : 1e-3;
        uint32_t cap = 40, lin = cap;
        int seen_fail_after_pass = 0, passed = 0;
        for (uint32_t n = 1; n < cap; ++n) {
            int b = brute_pass(&z, 2, K, n, tl);
            if (b && lin == cap)
                lin = n;
            if (passed && !b)
                seen_fail_after_pass = 1;
            passed |= b;
            double hint = (trial % 2) ? NAN : (double)((seed >> (n % 30)) % 1000) / 999.0;
            assert_int_equal(geom__tess_lines_pass(kink_point, &z, 2, 0.0, 1.0, K, n, tl, &hint), b);
        }
        nonmono += seen_fail_after_pass;
        assert_int_equal(geom__tess_lines_bound(kink_point, &z, 2, 0.0, 1.0, K, cap, tl), lin);
    }
    print_message("lines bound: 300 zigzags, %zu not monotone in the count\n", nonmono);
    assert_true(nonmono > 50);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_plane_weights),     cmocka_unit_test(test_sphere_weights),
        cmocka_unit_test(test_hemisphere_weights), cmocka_unit_test(test_warp),
        cmocka_unit_test(test_cylinder_closed_form), cmocka_unit_test(test_fold_guard),
        cmocka_unit_test(test_lines_bound),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
