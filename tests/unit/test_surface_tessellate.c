/* Surface module: tessellation. Topology of the results against what the
 * shapes are (a sphere is closed with genus 0, a torus genus 1; Newell's
 * teapot has four parts -- body, lid, handle, spout -- with one, one, two
 * and two open rims), triangle counts of uniform grids in closed form, the
 * chordal error measured independently against the exact sphere and
 * torus, analytic normals, texture coordinates and tangents, and crack-free
 * joins of patches tessellated at different resolutions. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "bench/tess_shapes.h"
#include "geom/surface.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

static geom_mesh_topology topo(const geom_mesh *m)
{
    geom_mesh_topology t;
    assert_int_equal(geom_mesh_topology_summary(m, &t), GEOM_OK);
    return t;
}

static geom_mesh *tess(const geom_nurbs_surface *s, size_t n, const geom_surface_tess_options *o,
                       geom_error_report *rep, geom_surface_tess_stats *st)
{
    geom_mesh *m = geom_mesh_create(NULL);
    assert_non_null(m);
    geom_diag d;
    geom_diag_clear(&d);
    geom_status rc = geom_surface_tessellate(s, n, o, m, rep, st, &d);
    if (rc != GEOM_OK)
        fail_msg("tessellate: %s (%s)", geom_status_str(rc), d.message);
    return m;
}

/* ----------------------------------------------------------------- teapot */

static void test_teapot(void **state)
{
    (void)state;
    geom_surface_set *set = tess_test_teapot();
    assert_int_equal((int)geom_surface_set_count(set), 32);
    const geom_nurbs_surface *S = geom_surface_set_data(set);
    geom_surface_tess_options o;
    memset(&o, 0, sizeof o);
    const double tols[3] = {1e-2, 3e-3, 1e-3};
    for (int t = 0; t < 3; ++t) {
        o.tolerance = tols[t];
        geom_error_report rep;
        geom_surface_tess_stats st;
        geom_mesh *m = tess(S, 32, &o, &rep, &st);
        geom_mesh_topology tp = topo(m);
        /* body (rim, body, bottom), lid, handle and spout */
        assert_int_equal((int)tp.components, 4);
        assert_int_equal((int)tp.boundary_loops, 6);
        assert_int_equal((int)tp.euler, 2);
        assert_true(tp.manifold);
        assert_int_equal((int)tp.degenerate_faces, 0);
        assert_int_equal(rep.method, GEOM_ERROR_SAMPLED);
        assert_true(rep.max_error <= tols[t] && rep.max_error > 0.05 * tols[t]);
        assert_true(rep.mean_error <= rep.max_error);
        assert_int_equal((int)st.flipped_surfaces, 0);
        /* the collapsed edges: the centre of the bottom and of the lid */
        assert_int_equal((int)st.collapsed_edges, 8);
        geom_mesh_destroy(m);
    }
    /* the body alone (rim, body and bottom patches: 1-12, 29-32) is one
     * watertight piece whose only boundary is the opening at z = 2.4 */
    geom_nurbs_surface body[16];
    for (int i = 0; i < 12; ++i)
        body[i] = S[i];
    for (int i = 0; i < 4; ++i)
        body[12 + i] = S[28 + i];
    o.tolerance = 1e-3;
    geom_mesh *m = tess(body, 16, &o, NULL, NULL);
    geom_mesh_topology tp = topo(m);
    assert_int_equal((int)tp.components, 1);
    assert_int_equal((int)tp.boundary_loops, 1);
    assert_int_equal((int)tp.euler, 1);
    assert_true(tp.manifold);
    const double *X = geom_mesh_cpositions(m);
    size_t nb = 0;
    for (uint32_t v = 0; v < geom_mesh_n_vertices(m); ++v)
        if (geom_mesh_vertex_is_boundary(m, v)) {
            assert_true(fabs(X[3 * v + 2] - 2.4) <= 1e-14);
            /* the rim is Newell's cubic quarter circles with inner control
             * points at 0.56 of the radius: the radius grows to
             * (4 + 3*0.56)/8 * sqrt(2) = 1.004092 times 1.4 mid-arc */
            double r = hypot(X[3 * v], X[3 * v + 1]);
            assert_true(r >= 1.4 * (1 - 1e-15) && r <= 1.4 * 1.004093);
            nb++;
        }
    assert_true(nb >= 16);
    geom_mesh_destroy(m);
    geom_surface_set_destroy(set);
}

/* Uniform grids: every patch gets n x n quads; the 8 collapsed edges (bottom
 * and lid centres) each lose n triangles. (n = 1 is not a tessellation of
 * the handle and spout: their tubes are two patches around, so one quad
 * per patch flattens each tube into coincident faces.) */
static void test_teapot_uniform_counts(void **state)
{
    (void)state;
    geom_surface_set *set = tess_test_teapot();
    geom_surface_tess_options o;
    memset(&o, 0, sizeof o);
    o.mode = GEOM_SURFACE_TESS_UNIFORM;
    for (int n = 2; n <= 10; n += 4) {
        o.grid_u = o.grid_v = n;
        geom_error_report rep;
        geom_surface_tess_stats st;
        geom_mesh *m = tess(geom_surface_set_data(set), 32, &o, &rep, &st);
        assert_int_equal((int)geom_mesh_n_faces(m), 32 * 2 * n * n - 8 * n);
        geom_mesh_topology tp = topo(m);
        assert_int_equal((int)tp.components, 4);
        assert_int_equal((int)tp.boundary_loops, 6);
        assert_true(rep.max_error > 0.0);
        geom_mesh_destroy(m);
    }
    geom_surface_set_destroy(set);
}

/* ------------------------------------------------------ sphere and torus */

static double len3(const double *a)
{
    return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
}

/* Largest distance from the exact shape over 10 barycentric points per
 * triangle (not the library's sample points). */
static double shape_error(const geom_mesh *m, int torus, double R, double r)
{
    const double *X = geom_mesh_cpositions(m);
    static const double bary[10][3] = {{1. / 3, 1. / 3, 1. / 3}, {.5, .5, 0}, {.5, 0, .5},
                                       {0, .5, .5},             {.7, .2, .1}, {.1, .7, .2},
                                       {.2, .1, .7},            {.45, .45, .1},
                                       {.1, .45, .45},          {.45, .1, .45}};
    double worst = 0.0;
    for (uint32_t f = 0; f < geom_mesh_n_faces(m); ++f) {
        uint32_t h = geom_mesh_face_he(m, f), v[3];
        for (int k = 0; k < 3; ++k) {
            v[k] = geom_mesh_he_vertex(m, h);
            h = geom_mesh_he_next(m, h);
        }
        for (int b = 0; b < 10; ++b) {
            double p[3];
            for (int x = 0; x < 3; ++x)
                p[x] = bary[b][0] * X[3 * v[0] + x] + bary[b][1] * X[3 * v[1] + x] +
                       bary[b][2] * X[3 * v[2] + x];
            double e;
            if (torus)
                e = fabs(hypot(hypot(p[0], p[1]) - R, p[2]) - r);
            else
                e = fabs(len3(p) - R);
            worst = fmax(worst, e);
        }
    }
    return worst;
}

static void test_sphere_torus(void **state)
{
    (void)state;
    double ku[12], kv[12], P[243], W[81];
    geom_nurbs_surface s;
    geom_surface_tess_options o;
    memset(&o, 0, sizeof o);
    for (int shape = 0; shape < 2; ++shape) {
        if (shape == 0)
            assert_int_equal(geom_surface_sphere(NULL, 1.0, ku, kv, P, W, &s), GEOM_OK);
        else
            assert_int_equal(geom_surface_torus(NULL, 2.0, 0.5, ku, kv, P, W, &s), GEOM_OK);
        const double tols[3] = {1e-2, 1e-3, 1e-4};
        for (int t = 0; t < 3; ++t) {
            o.tolerance = tols[t];
            geom_error_report rep;
            geom_surface_tess_stats st;
            geom_mesh *m = tess(&s, 1, &o, &rep, &st);
            geom_mesh_topology tp = topo(m);
            assert_true(tp.closed);
            assert_true(tp.manifold);
            assert_int_equal((int)tp.components, 1);
            assert_int_equal((int)tp.genus, shape);
            assert_true(rep.max_error <= tols[t]);
            double e = shape_error(m, shape, shape ? 2.0 : 1.0, 0.5);
            assert_true(e <= tols[t]);
            geom_mesh_destroy(m);
        }
    }
}

/* Uniform per span on the sphere (4 x 2 spans): 8 cells of n x n quads,
 * minus the n triangles each of the 8 cells at a pole loses; a closed
 * genus-0 triangulation has V = F/2 + 2. Per surface: one n x n grid. */
static void test_sphere_uniform_counts(void **state)
{
    (void)state;
    double ku[12], kv[8], P[135], W[45];
    geom_nurbs_surface s;
    assert_int_equal(geom_surface_sphere(NULL, 1.0, ku, kv, P, W, &s), GEOM_OK);
    geom_surface_tess_options o;
    memset(&o, 0, sizeof o);
    o.mode = GEOM_SURFACE_TESS_UNIFORM;
    for (int n = 1; n <= 6; ++n) {
        o.grid_u = o.grid_v = n;
        o.per_surface = 0;
        geom_mesh *m = tess(&s, 1, &o, NULL, NULL);
        size_t F = geom_mesh_n_faces(m);
        assert_int_equal((int)F, 8 * 2 * n * n - 8 * n);
        assert_int_equal((int)geom_mesh_n_vertices(m), (int)(F / 2 + 2));
        assert_true(topo(m).closed);
        geom_mesh_destroy(m);
        if (n < 3) /* two quads around: the two triangles at a pole coincide */
            continue;
        o.per_surface = 1;
        m = tess(&s, 1, &o, NULL, NULL);
        F = geom_mesh_n_faces(m);
        assert_int_equal((int)F, 2 * n * n - 2 * n);
        assert_int_equal((int)geom_mesh_n_vertices(m), (int)(F / 2 + 2));
        geom_mesh_destroy(m);
    }
}

/* Corner channels of the sphere: unit outward normals (the limit ones at
 * the poles), parameters in the domain, unit tangents along dP/du. */
static void test_attributes(void **state)
{
    (void)state;
    double ku[12], kv[8], P[135], W[45];
    geom_nurbs_surface s;
    assert_int_equal(geom_surface_sphere(NULL, 1.0, ku, kv, P, W, &s), GEOM_OK);
    geom_surface_tess_options o;
    memset(&o, 0, sizeof o);
    o.tolerance = 1e-3;
    o.attributes = GEOM_SURFACE_ATTR_NORMAL | GEOM_SURFACE_ATTR_UV | GEOM_SURFACE_ATTR_TANGENT |
                   GEOM_SURFACE_ATTR_SOURCE;
    for (int norm = 0; norm < 2; ++norm) {
        o.uv_normalized = norm;
        geom_surface_tess_stats st;
        geom_mesh *m = tess(&s, 1, &o, NULL, &st);
        assert_true(st.limit_normals > 0);
        uint32_t cn = geom_mesh_channel_find(m, "normal", GEOM_MESH_DOMAIN_CORNER);
        uint32_t cu = geom_mesh_channel_find(m, "uv", GEOM_MESH_DOMAIN_CORNER);
        uint32_t ct = geom_mesh_channel_find(m, "tangent", GEOM_MESH_DOMAIN_CORNER);
        uint32_t cs = geom_mesh_channel_find(m, "surface", GEOM_MESH_DOMAIN_FACE);
        assert_true(cn != GEOM_INVALID_INDEX && cu != GEOM_INVALID_INDEX &&
                    ct != GEOM_INVALID_INDEX && cs != GEOM_INVALID_INDEX);
        const uint32_t *in = geom_mesh_corner_cindices(m, cn);
        const uint32_t *iu = geom_mesh_corner_cindices(m, cu);
        const uint32_t *it = geom_mesh_corner_cindices(m, ct);
        const double *N = geom_mesh_channel_cdata(m, cn), *UV = geom_mesh_channel_cdata(m, cu);
        const double *T = geom_mesh_channel_cdata(m, ct), *X = geom_mesh_cpositions(m);
        const double *SF = geom_mesh_channel_cdata(m, cs);
        for (uint32_t f = 0; f < geom_mesh_n_faces(m); ++f) {
            assert_true(SF[f] == 0.0);
            uint32_t h0 = geom_mesh_face_he(m, f), h = h0;
            do {
                uint32_t v = geom_mesh_he_vertex(m, h);
                const double *p = X + 3 * v, *n = N + 3 * in[h], *uv = UV + 2 * iu[h];
                const double *t = T + 4 * it[h];
                for (int k = 0; k < 3; ++k)
                    assert_true(isfinite(n[k]) && isfinite(t[k]));
                double d = (n[0] * p[0] + n[1] * p[1] + n[2] * p[2]) / len3(p);
                assert_true(d > 1.0 - 1e-12);
                assert_true(fabs(len3(n) - 1.0) <= 1e-15 * 4);
                assert_true(uv[0] >= 0.0 && uv[0] <= 1.0 && uv[1] >= 0.0 && uv[1] <= 1.0);
                assert_true(fabs(len3(t) - 1.0) <= 1e-15 * 4);
                assert_true(t[3] == 1.0);
                assert_true(fabs(t[0] * n[0] + t[1] * n[1] + t[2] * n[2]) <= 1e-12);
                /* dP/du points east: (-sin, cos, 0) of the corner's longitude
                 * (at the poles: its limit, horizontal) */
                if (fabs(p[2]) < 1.0 - 1e-9) {
                    double lon = atan2(p[1], p[0]);
                    assert_true(fabs(t[0] + sin(lon)) <= 1e-12 && fabs(t[1] - cos(lon)) <= 1e-12);
                } else {
                    assert_true(fabs(t[2]) <= 1e-12);
                }
                h = geom_mesh_he_next(m, h);
            } while (h != h0);
        }
        geom_mesh_destroy(m);
    }
}

/* Angle tolerance: the normals at the corners of every triangle agree
 * within the angle. */
static void test_angle_tolerance(void **state)
{
    (void)state;
    double ku[12], kv[12], P[243], W[81];
    geom_nurbs_surface s;
    assert_int_equal(geom_surface_torus(NULL, 2.0, 0.5, ku, kv, P, W, &s), GEOM_OK);
    geom_surface_tess_options o;
    memset(&o, 0, sizeof o);
    o.tolerance = 0.05;
    o.angle_degrees = 5.0;
    o.attributes = GEOM_SURFACE_ATTR_NORMAL;
    geom_mesh *m = tess(&s, 1, &o, NULL, NULL);
    uint32_t cn = geom_mesh_channel_find(m, "normal", GEOM_MESH_DOMAIN_CORNER);
    const uint32_t *in = geom_mesh_corner_cindices(m, cn);
    const double *N = geom_mesh_channel_cdata(m, cn);
    double worst = 0.0;
    for (uint32_t f = 0; f < geom_mesh_n_faces(m); ++f) {
        uint32_t h = geom_mesh_face_he(m, f), c[3];
        for (int k = 0; k < 3; ++k) {
            c[k] = in[h];
            h = geom_mesh_he_next(m, h);
        }
        for (int a = 0; a < 3; ++a)
            for (int b = a + 1; b < 3; ++b) {
                const double *x = N + 3 * c[a], *y = N + 3 * c[b];
                double d = fmin(1.0, x[0] * y[0] + x[1] * y[1] + x[2] * y[2]);
                worst = fmax(worst, acos(d) * 180.0 / PI);
            }
    }
    assert_true(worst <= 5.0);
    /* the same tolerance without the angle criterion needs fewer triangles */
    size_t F = geom_mesh_n_faces(m);
    geom_mesh_destroy(m);
    o.angle_degrees = 0.0;
    m = tess(&s, 1, &o, NULL, NULL);
    assert_true(geom_mesh_n_faces(m) < F);
    geom_mesh_destroy(m);
}

/* ------------------------------------------------------- welding, cracks */

/* Two bicubic patches sharing the edge u = 1 of A, which is B's edge
 * u = 0 traversed backwards in v (B's v runs the other way): B is strongly
 * curved, A is flat, so their cells want very different resolutions. */
static void two_patches(double *A, double *B, int flip_b)
{
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            double *a = A + 3 * (i * 4 + j);
            a[0] = i / 3.0;
            a[1] = j / 3.0;
            a[2] = 0.0;
            /* B(i, j) continues at x = 1 + i/3 with y = 1 - j/3 */
            double *b = B + 3 * (i * 4 + j);
            b[0] = 1.0 + i / 3.0;
            b[1] = 1.0 - j / 3.0;
            b[2] = i == 0 ? 0.0 : 0.8 * sin(3.0 * i) * cos(2.0 * j);
        }
    /* B's v runs backwards, so B as given faces -z where A faces +z:
     * consistent orientation needs B's u reversed too (flip_b == 0) */
    if (!flip_b) {
        double T[48];
        memcpy(T, B, sizeof T);
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j)
                memcpy(B + 3 * (i * 4 + j), T + 3 * (i * 4 + 3 - j), 3 * sizeof(double));
        /* now v runs forward: B's u = 0 edge is A's u = 1 edge, same direction */
    }
}

static void test_crack_free(void **state)
{
    (void)state;
    for (int flip = 0; flip < 2; ++flip) {
        double A[48], B[48], ka[8], kb[8], kc[8], kd[8];
        two_patches(A, B, flip);
        geom_nurbs_surface s[2];
        geom_surface_bezier(3, 3, A, NULL, ka, kb, &s[0]);
        geom_surface_bezier(3, 3, B, NULL, kc, kd, &s[1]);
        geom_surface_tess_options o;
        memset(&o, 0, sizeof o);
        o.tolerance = 1e-4;
        o.attributes = GEOM_SURFACE_ATTR_NORMAL;
        geom_surface_tess_stats st;
        geom_error_report rep;
        geom_mesh *m = tess(s, 2, &o, &rep, &st);
        geom_mesh_topology tp = topo(m);
        /* one piece with one outer boundary: no crack, no T-junction */
        assert_int_equal((int)tp.components, 1);
        assert_int_equal((int)tp.boundary_loops, 1);
        assert_true(tp.manifold);
        assert_int_equal((int)st.welded_edges, 1);
        assert_int_equal((int)st.flipped_surfaces, flip);
        assert_true(rep.max_error <= 1e-4);
        /* faces agree with their corner normals (flipped patch included) */
        uint32_t cn = geom_mesh_channel_find(m, "normal", GEOM_MESH_DOMAIN_CORNER);
        const uint32_t *in = geom_mesh_corner_cindices(m, cn);
        const double *N = geom_mesh_channel_cdata(m, cn);
        for (uint32_t f = 0; f < geom_mesh_n_faces(m); ++f) {
            double fn[3];
            assert_int_equal(geom_mesh_face_normal(m, f, fn), GEOM_OK);
            uint32_t h = geom_mesh_face_he(m, f);
            const double *n = N + 3 * in[h];
            assert_true(fn[0] * n[0] + fn[1] * n[1] + fn[2] * n[2] > 0.5);
        }
        geom_mesh_destroy(m);
        /* without welding: two pieces */
        o.no_weld = 1;
        m = tess(s, 2, &o, NULL, NULL);
        assert_int_equal((int)topo(m).components, 2);
        geom_mesh_destroy(m);
    }
}

/* Without welding the sphere's seam stays open (one boundary loop from
 * pole to pole and back); the poles stay collapsed. */
static void test_no_weld_sphere(void **state)
{
    (void)state;
    double ku[12], kv[8], P[135], W[45];
    geom_nurbs_surface s;
    assert_int_equal(geom_surface_sphere(NULL, 1.0, ku, kv, P, W, &s), GEOM_OK);
    geom_surface_tess_options o;
    memset(&o, 0, sizeof o);
    o.no_weld = 1;
    o.tolerance = 1e-2;
    geom_mesh *m = tess(&s, 1, &o, NULL, NULL);
    geom_mesh_topology tp = topo(m);
    assert_false(tp.closed);
    assert_int_equal((int)tp.boundary_loops, 1);
    assert_int_equal((int)tp.euler, 1);
    geom_mesh_destroy(m);
}

static void test_errors(void **state)
{
    (void)state;
    double ku[12], kv[8], P[135], W[45];
    geom_nurbs_surface s[2];
    assert_int_equal(geom_surface_sphere(NULL, 1.0, ku, kv, P, W, &s[0]), GEOM_OK);
    s[1] = s[0];
    double W2[45];
    memcpy(W2, W, sizeof W2);
    W2[7] = 0.0;
    s[1].weights = W2;
    geom_mesh *m = geom_mesh_create(NULL);
    geom_diag d;
    geom_surface_tess_options o;
    memset(&o, 0, sizeof o);
    assert_int_equal(geom_surface_tessellate(s, 2, &o, m, NULL, NULL, &d), GEOM_ERR_INVALID_ARG);
    assert_non_null(strstr(d.message, "surface 1"));
    assert_int_equal(geom_surface_tessellate(s, 0, &o, m, NULL, NULL, &d), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_surface_tessellate(NULL, 1, &o, m, NULL, NULL, &d),
                     GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_surface_tessellate(s, 1, &o, NULL, NULL, NULL, &d),
                     GEOM_ERR_INVALID_ARG);
    o.tolerance = -1.0;
    assert_int_equal(geom_surface_tessellate(s, 1, &o, m, NULL, NULL, &d), GEOM_ERR_INVALID_ARG);
    o.tolerance = 1e-7;
    o.max_triangles = 1000;
    assert_int_equal(geom_surface_tessellate(s, 1, &o, m, NULL, NULL, &d), GEOM_ERR_LIMIT);
    memset(&o, 0, sizeof o);
    o.mode = GEOM_SURFACE_TESS_UNIFORM;
    o.grid_u = -1;
    assert_int_equal(geom_surface_tessellate(s, 1, &o, m, NULL, NULL, &d), GEOM_ERR_INVALID_ARG);
    /* a surface that is a single point: no triangles, no error */
    double Q[48], qu[8], qv[8];
    for (int i = 0; i < 48; ++i)
        Q[i] = 1.0;
    geom_surface_bezier(3, 3, Q, NULL, qu, qv, &s[0]);
    memset(&o, 0, sizeof o);
    geom_error_report rep;
    assert_int_equal(geom_surface_tessellate(s, 1, &o, m, &rep, NULL, &d), GEOM_OK);
    assert_int_equal((int)geom_mesh_n_faces(m), 0);
    assert_true(rep.max_error == 0.0);
    geom_mesh_destroy(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_teapot),
        cmocka_unit_test(test_teapot_uniform_counts),
        cmocka_unit_test(test_sphere_torus),
        cmocka_unit_test(test_sphere_uniform_counts),
        cmocka_unit_test(test_attributes),
        cmocka_unit_test(test_angle_tolerance),
        cmocka_unit_test(test_crack_free),
        cmocka_unit_test(test_no_weld_sphere),
        cmocka_unit_test(test_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
