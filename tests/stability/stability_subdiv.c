/*
 * Stiff and extreme cases for geom_subdiv: coordinates near the ends of the
 * double range, degenerate geometry, a pole of valence 2000 and one beyond
 * the valence limit, absurd sharpness values, size guards, every
 * allocation failing in turn, and random non-manifold soups.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "geom/subdiv.h"

static const double cube_v[] = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1,
                                -1, -1, 1,  1, -1, 1,  1, 1, 1,  -1, 1, 1};
static const uint32_t cube_f[] = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4,
                                  1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7};
static const uint32_t four[6] = {4, 4, 4, 4, 4, 4};

/* Refine a soup `levels` times and return the positions of the last level
 * and its limit normals (caller frees *pos, *nrm). */
static void refine_soup(size_t nv, const double *xyz, size_t nf, const uint32_t *sz,
                        const uint32_t *idx, geom_subdiv_scheme s, int levels, double **pos_out,
                        double **nrm_out, size_t *nv_out, size_t *bad)
{
    geom_subdiv_options o;
    memset(&o, 0, sizeof o);
    o.scheme = s;
    geom_subdiv_refiner *r = NULL;
    assert_int_equal(geom_subdiv_refiner_create_soup(nv, nf, sz, idx, &o, &r, NULL), GEOM_OK);
    assert_int_equal(geom_subdiv_refiner_refine(r, levels), GEOM_OK);
    double *p = malloc(3 * nv * sizeof(double));
    memcpy(p, xyz, 3 * nv * sizeof(double));
    size_t n = nv;
    for (int l = 1; l <= levels; l++) {
        geom_subdiv_level_info li;
        geom_subdiv_refiner_level_info(r, l, &li);
        double *q = malloc(3 * li.vertices * sizeof(double));
        assert_int_equal(geom_subdiv_interpolate(r, l, 3, p, q), GEOM_OK);
        free(p);
        p = q;
        n = li.vertices;
    }
    double *nrm = malloc(3 * n * sizeof(double));
    assert_int_equal(geom_subdiv_limit_normals(r, p, nrm, bad), GEOM_OK);
    geom_subdiv_refiner_destroy(r);
    *pos_out = p;
    *nrm_out = nrm;
    *nv_out = n;
}

/* The cube scaled to 1e300 and to 1e-300: positions scale exactly with the
 * input (powers of two would be exact; here within a few ulp) and the
 * limit normals are the same unit vectors, without overflow or underflow. */
static void test_extreme_scales(void **state)
{
    (void)state;
    double *p1, *n1;
    size_t nv, bad;
    refine_soup(8, cube_v, 6, four, cube_f, GEOM_SUBDIV_CATMULL_CLARK, 3, &p1, &n1, &nv, &bad);
    assert_int_equal(bad, 0);
    const double scales[4] = {1e300, 1e-300, 0x1p1000, 0x1p-1060};
    for (int t = 0; t < 4; t++) {
        double v[24];
        for (int i = 0; i < 24; i++)
            v[i] = cube_v[i] * scales[t];
        double *p, *n;
        size_t nv2;
        refine_soup(8, v, 6, four, cube_f, GEOM_SUBDIV_CATMULL_CLARK, 3, &p, &n, &nv2, &bad);
        assert_int_equal(nv2, nv);
        assert_int_equal(bad, 0);
        for (size_t i = 0; i < 3 * nv; i++) {
            assert_true(isfinite(p[i]));
            double expect = p1[i] * scales[t];
            /* rounding relative to the coordinates' size; subnormal results
             * are quantised to DBL_TRUE_MIN */
            double tol = fmax(1e-14 * scales[t], 64 * DBL_TRUE_MIN);
            if (!(fabs(p[i] - expect) <= tol))
                print_error("scale %g: %.17g vs %.17g\n", scales[t], p[i], expect);
            assert_true(fabs(p[i] - expect) <= tol);
            /* at the subnormal scale the positions carry ~5 digits */
            double ntol = scales[t] < 1e-290 ? 1e-3 : 1e-12;
            assert_true(fabs(n[i] - n1[i]) <= ntol);
        }
        free(p);
        free(n);
    }
    free(p1);
    free(n1);
}

/* All vertices at one point: refinement stays there, normals are zero and
 * counted, never NaN. */
static void test_degenerate_geometry(void **state)
{
    (void)state;
    double v[24];
    for (int i = 0; i < 24; i++)
        v[i] = 3.5;
    double *p, *n;
    size_t nv, bad;
    refine_soup(8, v, 6, four, cube_f, GEOM_SUBDIV_CATMULL_CLARK, 2, &p, &n, &nv, &bad);
    assert_int_equal(bad, nv);
    for (size_t i = 0; i < 3 * nv; i++) {
        assert_true(fabs(p[i] - 3.5) <= 1e-15);
        assert_true(n[i] == 0.0);
    }
    free(p);
    free(n);
}

/* A planar fan of 2000 triangles (a pole of valence 2000): finite
 * positions on the plane and the plane's normal at the pole. One vertex
 * with 70000 faces is beyond the valence limit: GEOM_ERR_LIMIT. */
static void test_high_valence(void **state)
{
    (void)state;
    for (int big = 0; big < 2; big++) {
        size_t k = big ? 70000 : 2000;
        double *v = malloc(3 * (k + 1) * sizeof(double));
        uint32_t *sz = malloc(k * sizeof(uint32_t)), *idx = malloc(3 * k * sizeof(uint32_t));
        v[0] = v[1] = v[2] = 0.0;
        for (size_t i = 0; i < k; i++) {
            double a = 2.0 * 3.14159265358979323846 * (double)i / (double)k;
            v[3 * (i + 1)] = cos(a);
            v[3 * (i + 1) + 1] = sin(a);
            v[3 * (i + 1) + 2] = 0.0;
            sz[i] = 3;
            idx[3 * i] = 0;
            idx[3 * i + 1] = (uint32_t)(i + 1);
            idx[3 * i + 2] = (uint32_t)((i + 1) % k + 1);
        }
        if (big) {
            geom_subdiv_refiner *r = NULL;
            geom_diag d;
            assert_int_equal(geom_subdiv_refiner_create_soup(k + 1, k, sz, idx, NULL, &r, &d),
                             GEOM_ERR_LIMIT);
            assert_null(r);
        } else {
            for (int s = 0; s < 2; s++) {
                double *p, *n;
                size_t nv, bad;
                refine_soup(k + 1, v, k, sz, idx, s ? GEOM_SUBDIV_LOOP : GEOM_SUBDIV_CATMULL_CLARK,
                            2, &p, &n, &nv, &bad);
                for (size_t i = 0; i < nv; i++) {
                    assert_true(isfinite(p[3 * i]) && isfinite(p[3 * i + 1]));
                    assert_true(p[3 * i + 2] == 0.0);
                }
                /* a planar disc: every limit normal is +z, the pole's too */
                assert_int_equal(bad, 0);
                for (size_t i = 0; i < nv; i++)
                    assert_true(fabs(n[3 * i + 2] - 1.0) <= 1e-9);
                free(p);
                free(n);
            }
        }
        free(v);
        free(sz);
        free(idx);
    }
}

/* Sharpness NaN, negative, infinite or huge: clamped (NaN and negatives are
 * smooth, anything >= 10 infinitely sharp), never a crash or a NaN. */
static void test_absurd_sharpness(void **state)
{
    (void)state;
    uint32_t ev[8] = {0, 1, 1, 2, 2, 3, 4, 5};
    double s[4] = {NAN, -INFINITY, INFINITY, 1e300};
    double cs[2] = {NAN, 1e308};
    uint32_t cv[2] = {6, 7};
    geom_subdiv_options o;
    memset(&o, 0, sizeof o);
    o.n_creases = 4;
    o.crease_verts = ev;
    o.crease_sharpness = s;
    o.n_corners = 2;
    o.corner_verts = cv;
    o.corner_sharpness = cs;
    o.crease_method = GEOM_SUBDIV_CREASE_CHAIKIN;
    geom_subdiv_refiner *r = NULL;
    assert_int_equal(geom_subdiv_refiner_create_soup(8, 6, four, cube_f, &o, &r, NULL), GEOM_OK);
    assert_int_equal(geom_subdiv_refiner_refine(r, 3), GEOM_OK);
    float es[12];
    uint32_t e2[24];
    geom_subdiv_refiner_edges(r, 0, e2, es);
    for (int i = 0; i < 12; i++) {
        assert_false(isnan(es[i]));
        assert_true(es[i] >= 0.0f);
    }
    float vs[8];
    geom_subdiv_refiner_vertex_rules(r, 0, vs, NULL);
    assert_true(vs[6] == 0.0f);
    assert_true(vs[7] >= 10.0f);
    double p[26 * 3], q[98 * 3], w[386 * 3];
    assert_int_equal(geom_subdiv_interpolate(r, 1, 3, cube_v, p), GEOM_OK);
    assert_int_equal(geom_subdiv_interpolate(r, 2, 3, p, q), GEOM_OK);
    assert_int_equal(geom_subdiv_interpolate(r, 3, 3, q, w), GEOM_OK);
    for (int i = 0; i < 386 * 3; i++)
        assert_true(isfinite(w[i]));
    /* the infinitely sharp corner 7 stays */
    uint32_t c = 7;
    for (int l = 0; l < 3; l++)
        c = geom_subdiv_refiner_child_vertex(r, l, GEOM_SUBDIV_FROM_VERTEX, c);
    assert_memory_equal(w + 3 * c, cube_v + 21, 3 * sizeof(double));
    geom_subdiv_refiner_destroy(r);
}

/* Requests that would need more than 2^28 elements fail up front. */
static void test_size_guard(void **state)
{
    (void)state;
    geom_subdiv_refiner *r = NULL;
    assert_int_equal(geom_subdiv_refiner_create_soup(8, 6, four, cube_f, NULL, &r, NULL), GEOM_OK);
    assert_int_equal(geom_subdiv_refiner_refine(r, 12), GEOM_ERR_LIMIT);
    assert_int_equal(geom_subdiv_refiner_max_level(r), 0);
    assert_int_equal(geom_subdiv_refiner_refine(r, 13), GEOM_ERR_LIMIT);
    assert_int_equal(geom_subdiv_refiner_refine(r, 2), GEOM_OK);
    assert_int_equal(geom_subdiv_refiner_max_level(r), 2);
    geom_subdiv_refiner_destroy(r);
}

/* An allocator that fails the n-th allocation. */
typedef struct failing {
    long countdown;
    long live;
} failing;

static void *f_alloc(void *user, size_t size)
{
    failing *f = user;
    if (f->countdown-- == 0)
        return NULL;
    f->live++;
    return malloc(size);
}

static void f_free(void *user, void *p, size_t size)
{
    (void)size;
    failing *f = user;
    if (p)
        f->live--;
    free(p);
}

static void test_allocation_failures(void **state)
{
    (void)state;
    geom_mesh *m = geom_mesh_create(NULL);
    assert_int_equal(geom_mesh_build(m, 8, cube_v, 6, four, cube_f, NULL, NULL, NULL), GEOM_OK);
    uint32_t uv;
    assert_int_equal(geom_mesh_channel_add(m, "uv", GEOM_MESH_DOMAIN_CORNER, 2, &uv), GEOM_OK);
    assert_int_equal(geom_mesh_corner_pool_resize(m, uv, 4), GEOM_OK);
    uint32_t *ci = geom_mesh_corner_indices(m, uv);
    for (uint32_t h = 0; h < geom_mesh_n_halfedges(m); h++)
        ci[h] = geom_mesh_he_face(m, h) == GEOM_INVALID_INDEX ? GEOM_INVALID_INDEX : h % 4;
    int succeeded = 0;
    for (long n = 0; n < 4000 && !succeeded; n++) {
        failing f = {n, 0};
        geom_allocator a = {f_alloc, NULL, f_free, &f};
        geom_subdiv_options o;
        memset(&o, 0, sizeof o);
        o.alloc = &a;
        o.fvar_boundary = GEOM_SUBDIV_FVAR_NONE;
        geom_mesh *out = NULL;
        geom_subdiv_report rep;
        geom_status st =
            geom_subdiv_mesh(m, &o, 2, GEOM_SUBDIV_NORMALS | GEOM_SUBDIV_LIMIT, &out, &rep, NULL);
        if (st == GEOM_OK) {
            succeeded = 1;
            assert_int_equal(geom_mesh_n_faces(out), 96);
            geom_mesh_destroy(out);
        } else {
            assert_int_equal(st, GEOM_ERR_NOMEM);
            assert_null(out);
        }
        assert_int_equal(f.live, 0);
    }
    assert_true(succeeded);
    geom_mesh_destroy(m);
}

/* Random soups over few vertices: repeated edges, edges with many faces,
 * faces using a vertex twice, isolated vertices. Refining and the limit
 * with tangents never fail or produce NaN from finite input. */
static void test_random_nonmanifold(void **state)
{
    (void)state;
    uint64_t seed = 0x9e3779b97f4a7c15ull;
    for (int trial = 0; trial < 60; trial++) {
        size_t nv = 6 + (size_t)(trial % 5), nf = 4 + (size_t)(trial % 9);
        double v[3 * 12];
        uint32_t sz[16], idx[16 * 6];
        for (size_t i = 0; i < 3 * nv; i++) {
            seed = seed * 6364136223846793005ull + 1442695040888963407ull;
            v[i] = (double)(seed >> 11) * 0x1p-53 * 2.0 - 1.0;
        }
        size_t k = 0;
        int tri = trial % 2;
        for (size_t f = 0; f < nf; f++) {
            seed = seed * 6364136223846793005ull + 1442695040888963407ull;
            sz[f] = tri ? 3 : 3 + (uint32_t)((seed >> 40) % 4);
            for (uint32_t j = 0; j < sz[f]; j++) {
                seed = seed * 6364136223846793005ull + 1442695040888963407ull;
                idx[k++] = (uint32_t)((seed >> 33) % nv);
            }
        }
        geom_subdiv_options o;
        memset(&o, 0, sizeof o);
        o.scheme = tri ? GEOM_SUBDIV_LOOP : GEOM_SUBDIV_CATMULL_CLARK;
        o.boundary = (geom_subdiv_boundary)(1 + trial % 3);
        geom_subdiv_refiner *r = NULL;
        assert_int_equal(geom_subdiv_refiner_create_soup(nv, nf, sz, idx, &o, &r, NULL), GEOM_OK);
        uint32_t *fvals = malloc(k * sizeof(uint32_t));
        for (size_t i = 0; i < k; i++)
            fvals[i] = (uint32_t)(i % 5);
        assert_int_equal(geom_subdiv_refiner_add_fvar(r, 5, fvals, NULL), GEOM_OK);
        free(fvals);
        assert_int_equal(geom_subdiv_refiner_refine(r, 2), GEOM_OK);
        double *p = malloc(3 * nv * sizeof(double));
        memcpy(p, v, 3 * nv * sizeof(double));
        double *u = calloc(10, sizeof(double));
        for (int i = 0; i < 10; i++)
            u[i] = i * 0.25;
        for (int l = 1; l <= 2; l++) {
            geom_subdiv_level_info li;
            geom_subdiv_refiner_level_info(r, l, &li);
            double *q = malloc(3 * li.vertices * sizeof(double));
            assert_int_equal(geom_subdiv_interpolate(r, l, 3, p, q), GEOM_OK);
            free(p);
            p = q;
            size_t nu = geom_subdiv_fvar_size(r, 0, l);
            double *u2 = malloc(2 * nu * sizeof(double));
            assert_int_equal(geom_subdiv_interpolate_fvar(r, 0, l, 2, u, u2), GEOM_OK);
            free(u);
            u = u2;
            for (size_t i = 0; i < 2 * nu; i++)
                assert_true(isfinite(u[i]));
            for (size_t i = 0; i < 3 * li.vertices; i++)
                assert_true(isfinite(p[i]));
            if (l == 2) {
                double *lim = malloc(9 * li.vertices * sizeof(double));
                assert_int_equal(geom_subdiv_limit(r, 3, p, lim, lim + 3 * li.vertices,
                                                   lim + 6 * li.vertices),
                                 GEOM_OK);
                for (size_t i = 0; i < 9 * li.vertices; i++)
                    assert_true(isfinite(lim[i]));
                double *ul = malloc(2 * nu * sizeof(double));
                assert_int_equal(geom_subdiv_limit_fvar(r, 0, 2, u, ul), GEOM_OK);
                free(ul);
                free(lim);
            }
        }
        free(p);
        free(u);
        geom_subdiv_refiner_destroy(r);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_extreme_scales),      cmocka_unit_test(test_degenerate_geometry),
        cmocka_unit_test(test_high_valence),        cmocka_unit_test(test_absurd_sharpness),
        cmocka_unit_test(test_size_guard),          cmocka_unit_test(test_allocation_failures),
        cmocka_unit_test(test_random_nonmanifold),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
