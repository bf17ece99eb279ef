/*
 * Unit tests of geom_subdiv against closed forms: the Catmull-Clark limit of
 * a cube corner from the limit mask by hand, Loop's box-spline limit on a
 * regular grid (planarity, linear and quadratic reproduction), exact
 * midpoint subdivision for bilinear, interpolation for butterfly, the 3^k
 * face growth of sqrt(3), crease rules, limit normals by symmetry, the
 * face-varying boundary options, parent/child maps, holes, non-manifold
 * input and error statuses.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "geom/meshio.h"
#include "geom/subdiv.h"
#include "test_util.h"

/* ------------------------------------------------------------ helpers */

static void check_close(double a, double b, double tol, const char *file, int line)
{
    if (!(fabs(a - b) <= tol)) {
        print_error("%.17g != %.17g (tolerance %g)\n", a, b, tol);
        _fail(file, line);
    }
}
#define assert_double_equal(a, b, tol) check_close((a), (b), (tol), __FILE__, __LINE__)

static geom_mesh *build(size_t nv, const double *xyz, size_t nf, const uint32_t *sizes,
                        const uint32_t *idx)
{
    geom_mesh *m = geom_mesh_create(NULL);
    assert_non_null(m);
    assert_int_equal(geom_mesh_build(m, nv, xyz, nf, sizes, idx, NULL, NULL, NULL), GEOM_OK);
    return m;
}

/* The cube [-1,1]^3, faces counter-clockwise seen from outside. */
static const double cube_v[] = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1,
                                -1, -1, 1,  1, -1, 1,  1, 1, 1,  -1, 1, 1};
static const uint32_t cube_f[] = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4,
                                  1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7};
static const uint32_t quad_sizes[64] = {4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4,
                                        4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4,
                                        4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4,
                                        4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4};

/* A CORNER "uv" channel with seams on the cube: every face gets its own
 * four UVs (0,0) (1,0) (1,1) (0,1). */
static void add_seamed_uv(geom_mesh *m)
{
    uint32_t uv;
    assert_int_equal(geom_mesh_channel_add(m, "uv", GEOM_MESH_DOMAIN_CORNER, 2, &uv), GEOM_OK);
    assert_int_equal(geom_mesh_corner_pool_resize(m, uv, 24), GEOM_OK);
    double *pool = geom_mesh_channel_data(m, uv);
    uint32_t *ci = geom_mesh_corner_indices(m, uv);
    for (uint32_t f = 0; f < 6; f++) {
        uint32_t h0 = geom_mesh_face_he(m, f), h = h0, k = 0;
        do {
            ci[h] = 4 * f + k;
            pool[2 * (4 * f + k)] = (k == 1 || k == 2);
            pool[2 * (4 * f + k) + 1] = (k >= 2);
            k++;
            h = geom_mesh_he_next(m, h);
        } while (h != h0);
    }
}

static geom_subdiv_refiner *refiner_for(const geom_mesh *m, geom_subdiv_scheme s, int levels)
{
    geom_subdiv_options o;
    memset(&o, 0, sizeof o);
    o.scheme = s;
    geom_subdiv_refiner *r = NULL;
    assert_int_equal(geom_subdiv_refiner_create(m, &o, &r, NULL), GEOM_OK);
    assert_int_equal(geom_subdiv_refiner_refine(r, levels), GEOM_OK);
    return r;
}

/* Positions of every level: pos[l] for l = 0..levels (caller frees). */
static double **refine_positions(const geom_subdiv_refiner *r, const geom_mesh *m)
{
    int L = geom_subdiv_refiner_max_level(r);
    double **pos = calloc((size_t)L + 1, sizeof *pos);
    geom_subdiv_level_info li;
    geom_subdiv_refiner_level_info(r, 0, &li);
    pos[0] = malloc(3 * li.vertices * sizeof(double));
    memcpy(pos[0], geom_mesh_cpositions(m), 3 * li.vertices * sizeof(double));
    for (int l = 1; l <= L; l++) {
        geom_subdiv_refiner_level_info(r, l, &li);
        pos[l] = malloc(3 * li.vertices * sizeof(double));
        assert_int_equal(geom_subdiv_interpolate(r, l, 3, pos[l - 1], pos[l]), GEOM_OK);
    }
    return pos;
}

static void free_positions(double **pos, int L)
{
    for (int l = 0; l <= L; l++)
        free(pos[l]);
    free(pos);
}

/* A regular triangulated grid of n x n squares in the plane z = a x + b y
 * + c, cut along alternating... every square split by the same diagonal,
 * so interior vertices have valence 6. Vertices (i, j) at (i, j). */
static geom_mesh *tri_grid(int n, double a, double b, double c, double (*zf)(double, double))
{
    size_t nv = (size_t)(n + 1) * (n + 1), nf = 2 * (size_t)n * n;
    double *xyz = malloc(3 * nv * sizeof(double));
    uint32_t *sz = malloc(nf * sizeof(uint32_t)), *idx = malloc(3 * nf * sizeof(uint32_t));
    for (int j = 0; j <= n; j++)
        for (int i = 0; i <= n; i++) {
            size_t v = (size_t)j * (n + 1) + i;
            xyz[3 * v] = i;
            xyz[3 * v + 1] = j;
            xyz[3 * v + 2] = zf ? zf(i, j) : a * i + b * j + c;
        }
    size_t f = 0;
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            uint32_t v00 = (uint32_t)(j * (n + 1) + i), v10 = v00 + 1, v01 = v00 + (uint32_t)n + 1,
                     v11 = v01 + 1;
            uint32_t t[6] = {v00, v10, v11, v00, v11, v01};
            memcpy(idx + 3 * f, t, sizeof t);
            sz[f] = sz[f + 1] = 3;
            f += 2;
        }
    geom_mesh *m = build(nv, xyz, nf, sz, idx);
    free(xyz);
    free(sz);
    free(idx);
    return m;
}

static geom_mesh *quad_grid(int n, double (*zf)(double, double))
{
    size_t nv = (size_t)(n + 1) * (n + 1), nf = (size_t)n * n;
    double *xyz = malloc(3 * nv * sizeof(double));
    uint32_t *sz = malloc(nf * sizeof(uint32_t)), *idx = malloc(4 * nf * sizeof(uint32_t));
    for (int j = 0; j <= n; j++)
        for (int i = 0; i <= n; i++) {
            size_t v = (size_t)j * (n + 1) + i;
            xyz[3 * v] = i;
            xyz[3 * v + 1] = j;
            xyz[3 * v + 2] = zf ? zf(i, j) : 0.0;
        }
    size_t f = 0;
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            uint32_t v00 = (uint32_t)(j * (n + 1) + i);
            uint32_t q[4] = {v00, v00 + 1, v00 + (uint32_t)n + 2, v00 + (uint32_t)n + 1};
            memcpy(idx + 4 * f, q, sizeof q);
            sz[f++] = 4;
        }
    geom_mesh *m = build(nv, xyz, nf, sz, idx);
    free(xyz);
    free(sz);
    free(idx);
    return m;
}

/* ---------------------------------------------------- Catmull-Clark */

/* The limit of the corner (1,1,1) of the cube under Catmull-Clark, from the
 * limit mask (n^2 v + 4 sum e + sum f) / (n (n + 5)) with n = 3: each
 * coordinate (9 * 1 + 4 * (-1 + 1 + 1) + (-1 - 1 + 1)) / 24 = 1/2. */
static void test_cc_cube_corner_limit(void **state)
{
    (void)state;
    geom_mesh *m = build(8, cube_v, 6, quad_sizes, cube_f);
    const int L = 7;
    geom_subdiv_refiner *r = refiner_for(m, GEOM_SUBDIV_CATMULL_CLARK, L);
    double **pos = refine_positions(r, m);
    /* Follow vertex 6 = (1,1,1) down the levels. */
    uint32_t v = 6;
    double prev = INFINITY;
    for (int l = 1; l <= L; l++) {
        v = geom_subdiv_refiner_child_vertex(r, l - 1, GEOM_SUBDIV_FROM_VERTEX, v);
        assert_int_not_equal(v, GEOM_INVALID_INDEX);
        double d = 0.0;
        for (int k = 0; k < 3; k++)
            d = fmax(d, fabs(pos[l][3 * v + k] - 0.5));
        /* The vertex point converges toward the limit: (1/4 + 1/12)... at
         * least halving the distance per level for valence 3. */
        assert_true(d < prev * 0.5);
        prev = d;
    }
    assert_true(prev < 1e-4);
    /* The limit mask at the finest level gives exactly the same point. */
    geom_subdiv_level_info li;
    geom_subdiv_refiner_level_info(r, L, &li);
    double *lim = malloc(3 * li.vertices * sizeof(double));
    assert_int_equal(geom_subdiv_limit(r, 3, pos[L], lim, NULL, NULL), GEOM_OK);
    for (int k = 0; k < 3; k++)
        assert_double_equal(lim[3 * v + k], 0.5, 1e-14);
    /* By symmetry every corner's limit normal is its diagonal. */
    double *nrm = malloc(3 * li.vertices * sizeof(double));
    size_t bad = 99;
    assert_int_equal(geom_subdiv_limit_normals(r, pos[L], nrm, &bad), GEOM_OK);
    assert_int_equal(bad, 0);
    for (int k = 0; k < 3; k++)
        assert_double_equal(nrm[3 * v + k], 1.0 / sqrt(3.0), 1e-12);
    free(lim);
    free(nrm);
    /* Level 0 limit directly from the cube's own vertices. */
    geom_subdiv_refiner *r0 = refiner_for(m, GEOM_SUBDIV_CATMULL_CLARK, 0);
    double l0[24];
    assert_int_equal(geom_subdiv_limit(r0, 3, cube_v, l0, NULL, NULL), GEOM_OK);
    for (int i = 0; i < 24; i++)
        assert_double_equal(l0[i], cube_v[i] * 0.5, 1e-15);
    geom_subdiv_refiner_destroy(r0);
    free_positions(pos, L);
    geom_subdiv_refiner_destroy(r);
    geom_mesh_destroy(m);
}

/* Counts: V' = V + E + F, F' = sum of face sizes, E' = 2E + sum of sizes. */
static void test_cc_counts_and_maps(void **state)
{
    (void)state;
    geom_mesh *m = build(8, cube_v, 6, quad_sizes, cube_f);
    geom_subdiv_refiner *r = refiner_for(m, GEOM_SUBDIV_CATMULL_CLARK, 2);
    geom_subdiv_level_info a, b;
    assert_int_equal(geom_subdiv_refiner_level_info(r, 0, &a), GEOM_OK);
    assert_int_equal(a.vertices, 8);
    assert_int_equal(a.edges, 12);
    assert_int_equal(a.faces, 6);
    assert_int_equal(geom_subdiv_refiner_level_info(r, 1, &b), GEOM_OK);
    assert_int_equal(b.vertices, 8 + 12 + 6);
    assert_int_equal(b.faces, 24);
    assert_int_equal(b.edges, 2 * 12 + 24);
    /* Face points first, then edge points, then vertex points. */
    for (uint32_t f = 0; f < 6; f++) {
        geom_subdiv_origin k;
        uint32_t p;
        uint32_t c = geom_subdiv_refiner_child_vertex(r, 0, GEOM_SUBDIV_FROM_FACE, f);
        assert_int_equal(c, f);
        assert_int_equal(geom_subdiv_refiner_vertex_parent(r, 1, c, &k, &p), GEOM_OK);
        assert_int_equal(k, GEOM_SUBDIV_FROM_FACE);
        assert_int_equal(p, f);
    }
    for (uint32_t e = 0; e < 12; e++)
        assert_int_equal(geom_subdiv_refiner_child_vertex(r, 0, GEOM_SUBDIV_FROM_EDGE, e), 6 + e);
    for (uint32_t v = 0; v < 8; v++)
        assert_int_equal(geom_subdiv_refiner_child_vertex(r, 0, GEOM_SUBDIV_FROM_VERTEX, v),
                         18 + v);
    for (uint32_t f = 0; f < 24; f++)
        assert_int_equal(geom_subdiv_refiner_face_parent(r, 1, f), f / 4);
    assert_int_equal(geom_subdiv_refiner_child_vertex(r, 2, GEOM_SUBDIV_FROM_FACE, 0),
                     GEOM_INVALID_INDEX);
    assert_int_equal(geom_subdiv_refiner_face_parent(r, 0, 0), GEOM_INVALID_INDEX);
    /* Closed quad mesh: every level-1 vertex has one of the CC rules. */
    uint8_t rules[26];
    assert_int_equal(geom_subdiv_refiner_vertex_rules(r, 1, NULL, rules), GEOM_OK);
    for (int i = 0; i < 26; i++)
        assert_int_equal(rules[i], 1);
    geom_subdiv_refiner_destroy(r);
    geom_mesh_destroy(m);
}

/* Face point = centroid; smooth edge point = (v0 + v1 + f0 + f1) / 4;
 * smooth vertex point (n - 2)/n v + (sum e + sum f)/n^2 (Catmull & Clark). */
static void test_cc_masks_by_hand(void **state)
{
    (void)state;
    geom_mesh *m = build(8, cube_v, 6, quad_sizes, cube_f);
    geom_subdiv_refiner *r = refiner_for(m, GEOM_SUBDIV_CATMULL_CLARK, 1);
    double **pos = refine_positions(r, m);
    const double *p = pos[1];
    /* face 1 = (4,5,6,7): the +z face, centroid (0,0,1) */
    assert_double_equal(p[3 * 1 + 0], 0.0, 0);
    assert_double_equal(p[3 * 1 + 1], 0.0, 0);
    assert_double_equal(p[3 * 1 + 2], 1.0, 0);
    /* vertex 6 (1,1,1): faces centroids (1,0,0),(0,1,0),(0,0,1) and edge
     * neighbours: (2/3 n^-0 ...) = 1/3*(1,1,1) + ((sum e)+(sum f))/9 */
    uint32_t cv = geom_subdiv_refiner_child_vertex(r, 0, GEOM_SUBDIV_FROM_VERTEX, 6);
    double expect = 1.0 / 3.0 + (1.0 + 1.0) / 9.0; /* e: x sum = 1, f: x sum = 1 */
    for (int k = 0; k < 3; k++)
        assert_double_equal(p[3 * cv + k], expect, 1e-15);
    free_positions(pos, 1);
    geom_subdiv_refiner_destroy(r);
    geom_mesh_destroy(m);
}

/* Infinitely sharp creases keep the cube's edges as B-spline curves: with
 * all 12 edges sharp (sharpness 10), edge points are midpoints and corners
 * (3 sharp edges) stay; sharpness 1 still gives the midpoint at level 1
 * (fractional weight 1), while sharpness 0.5 blends halfway. */
static void test_cc_creases(void **state)
{
    (void)state;
    geom_mesh *m = build(8, cube_v, 6, quad_sizes, cube_f);
    uint32_t ev[24];
    const uint32_t edges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6},
                                   {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
    for (int i = 0; i < 12; i++)
        ev[2 * i] = edges[i][0], ev[2 * i + 1] = edges[i][1];
    double sharp[12];
    const double values[3] = {10.0, 1.0, 0.5};
    double mid_smooth = 0.0;
    for (int t = 0; t < 3; t++) {
        for (int i = 0; i < 12; i++)
            sharp[i] = values[t];
        geom_subdiv_options o;
        memset(&o, 0, sizeof o);
        o.n_creases = 12;
        o.crease_verts = ev;
        o.crease_sharpness = sharp;
        geom_subdiv_refiner *r = NULL;
        assert_int_equal(geom_subdiv_refiner_create(m, &o, &r, NULL), GEOM_OK);
        assert_int_equal(geom_subdiv_refiner_refine(r, 1), GEOM_OK);
        double p1[26 * 3];
        assert_int_equal(geom_subdiv_interpolate(r, 1, 3, cube_v, p1), GEOM_OK);
        /* edge (5,6): from (1,-1,1) to (1,1,1), midpoint (1,0,1) */
        uint32_t e = 0;
        uint32_t all[24];
        float es[12];
        assert_int_equal(geom_subdiv_refiner_edges(r, 0, all, es), GEOM_OK);
        while (!((all[2 * e] == 5 && all[2 * e + 1] == 6) || (all[2 * e] == 6 && all[2 * e + 1] == 5)))
            e++;
        assert_true(es[e] == (float)values[t]);
        uint32_t c = geom_subdiv_refiner_child_vertex(r, 0, GEOM_SUBDIV_FROM_EDGE, e);
        /* smooth edge point x = (1 + 1 + 1 + 0)/4 = 0.75 (faces (1,0,0), (0,0,1)) */
        double smooth_x = 0.75;
        if (t < 2) {
            assert_double_equal(p1[3 * c], 1.0, 0);
            assert_double_equal(p1[3 * c + 1], 0.0, 0);
            assert_double_equal(p1[3 * c + 2], 1.0, 0);
        } else {
            assert_double_equal(p1[3 * c], 0.5 * 1.0 + 0.5 * smooth_x, 1e-15);
            mid_smooth = p1[3 * c];
        }
        uint32_t cv = geom_subdiv_refiner_child_vertex(r, 0, GEOM_SUBDIV_FROM_VERTEX, 6);
        if (t == 0) {
            for (int k = 0; k < 3; k++)
                assert_double_equal(p1[3 * cv + k], 1.0, 0);
            uint8_t rules[26];
            geom_subdiv_refiner_vertex_rules(r, 1, NULL, rules);
            assert_int_equal(rules[cv], 8);   /* corner */
            assert_int_equal(rules[c], 4);    /* crease */
        }
        geom_subdiv_refiner_destroy(r);
    }
    assert_true(mid_smooth > 0.75 && mid_smooth < 1.0);
    geom_mesh_destroy(m);
}

/* Sharpness decays by one per level (uniform) and by Chaikin's rule:
 * with two semi-sharp edges 2 and 1 meeting at a vertex, uniform gives
 * 1 and 0 at level 1, Chaikin 3/4*2 + 1/4*1 - 1 = 0.75 and
 * 3/4*1 + 1/4*2 - 1 = 0.25 on the children at that vertex. */
static void test_crease_decay(void **state)
{
    (void)state;
    geom_mesh *m = quad_grid(4, NULL);
    /* edges (6,7) sharpness 2 and (7,8) sharpness 1 along row j = 1 */
    uint32_t ev[4] = {6, 7, 7, 8};
    double s[2] = {2.0, 1.0};
    for (int chaikin = 0; chaikin < 2; chaikin++) {
        geom_subdiv_options o;
        memset(&o, 0, sizeof o);
        o.n_creases = 2;
        o.crease_verts = ev;
        o.crease_sharpness = s;
        o.crease_method = chaikin ? GEOM_SUBDIV_CREASE_CHAIKIN : GEOM_SUBDIV_CREASE_UNIFORM;
        geom_subdiv_refiner *r = NULL;
        assert_int_equal(geom_subdiv_refiner_create(m, &o, &r, NULL), GEOM_OK);
        assert_int_equal(geom_subdiv_refiner_refine(r, 2), GEOM_OK);
        geom_subdiv_level_info li;
        geom_subdiv_refiner_level_info(r, 1, &li);
        uint32_t *ev1 = malloc(2 * li.edges * sizeof(uint32_t));
        float *es1 = malloc(li.edges * sizeof(float));
        geom_subdiv_refiner_edges(r, 1, ev1, es1);
        uint32_t c7 = geom_subdiv_refiner_child_vertex(r, 0, GEOM_SUBDIV_FROM_VERTEX, 7);
        float got[2] = {-1, -1};
        for (size_t e = 0; e < li.edges; e++) {
            if (ev1[2 * e + 1] != c7 && ev1[2 * e] != c7)
                continue;
            uint32_t o2 = ev1[2 * e] == c7 ? ev1[2 * e + 1] : ev1[2 * e];
            geom_subdiv_origin k;
            uint32_t par;
            geom_subdiv_refiner_vertex_parent(r, 1, o2, &k, &par);
            if (k != GEOM_SUBDIV_FROM_EDGE)
                continue;
            uint32_t pv[128];
            geom_subdiv_refiner_edges(r, 0, pv, NULL);
            uint32_t other = pv[2 * par] == 7 ? pv[2 * par + 1] : pv[2 * par];
            if (other == 6)
                got[0] = es1[e];
            if (other == 8)
                got[1] = es1[e];
        }
        if (!chaikin) {
            assert_true(got[0] == 1.0f);
            assert_true(got[1] == 0.0f);
        } else {
            assert_true(got[0] == 0.75f);
            assert_true(got[1] == 0.25f);
        }
        free(ev1);
        free(es1);
        geom_subdiv_refiner_destroy(r);
    }
    geom_mesh_destroy(m);
}

/* ------------------------------------------------------------ Loop */

static double quad_field(double x, double y)
{
    return x * x + y * y;
}

/* Loop on a regular planar grid: planar input stays planar (affine
 * invariance), and the box-spline limit mask at a regular vertex is
 * 1/2 v + 1/12 sum of its 6 neighbours, which for z = x^2 + y^2 gives
 * z(v) + (1/12) * 6 * h^2 with unit edge ... the six neighbours of the
 * grid are at (+-1,0), (0,+-1), (1,1), (-1,-1): sum of squared offsets 8,
 * so the limit is x^2 + y^2 + 8/12. The limit is the same from every level. */
static void test_loop_box_spline(void **state)
{
    (void)state;
    geom_mesh *m = tri_grid(8, 0.25, -0.5, 2.0, NULL);
    geom_subdiv_refiner *r = refiner_for(m, GEOM_SUBDIV_LOOP, 3);
    double **pos = refine_positions(r, m);
    geom_subdiv_level_info li;
    geom_subdiv_refiner_level_info(r, 3, &li);
    for (size_t v = 0; v < li.vertices; v++) {
        const double *p = pos[3] + 3 * v;
        assert_double_equal(p[2], 0.25 * p[0] - 0.5 * p[1] + 2.0, 1e-13);
    }
    double *lim = malloc(3 * li.vertices * sizeof(double));
    double *nrm = malloc(3 * li.vertices * sizeof(double));
    assert_int_equal(geom_subdiv_limit(r, 3, pos[3], lim, NULL, NULL), GEOM_OK);
    assert_int_equal(geom_subdiv_limit_normals(r, pos[3], nrm, NULL), GEOM_OK);
    double nn = sqrt(0.25 * 0.25 + 0.5 * 0.5 + 1.0);
    for (size_t v = 0; v < li.vertices; v++) {
        assert_double_equal(lim[3 * v + 2], 0.25 * lim[3 * v] - 0.5 * lim[3 * v + 1] + 2.0, 1e-13);
        /* normals of the plane, pointing up (faces are counter-clockwise) */
        assert_double_equal(nrm[3 * v], -0.25 / nn, 1e-12);
        assert_double_equal(nrm[3 * v + 1], 0.5 / nn, 1e-12);
        assert_double_equal(nrm[3 * v + 2], 1.0 / nn, 1e-12);
    }
    free(lim);
    free(nrm);
    free_positions(pos, 3);
    geom_subdiv_refiner_destroy(r);
    geom_mesh_destroy(m);

    m = tri_grid(8, 0, 0, 0, quad_field);
    r = refiner_for(m, GEOM_SUBDIV_LOOP, 2);
    pos = refine_positions(r, m);
    double *l0 = malloc(3 * 81 * sizeof(double));
    geom_subdiv_refiner *r0 = refiner_for(m, GEOM_SUBDIV_LOOP, 0);
    assert_int_equal(geom_subdiv_limit(r0, 3, pos[0], l0, NULL, NULL), GEOM_OK);
    geom_subdiv_refiner_level_info(r, 2, &li);
    double *l2 = malloc(3 * li.vertices * sizeof(double));
    assert_int_equal(geom_subdiv_limit(r, 3, pos[2], l2, NULL, NULL), GEOM_OK);
    for (uint32_t j = 2; j <= 6; j++)
        for (uint32_t i = 2; i <= 6; i++) {
            uint32_t v = j * 9 + i;
            /* linear precision in x, y; quadratic field offset 8/12 */
            assert_double_equal(l0[3 * v], i, 1e-14);
            assert_double_equal(l0[3 * v + 1], j, 1e-14);
            assert_double_equal(l0[3 * v + 2], i * i + j * j + 8.0 / 12.0, 1e-13);
            uint32_t c = geom_subdiv_refiner_child_vertex(r, 0, GEOM_SUBDIV_FROM_VERTEX, v);
            c = geom_subdiv_refiner_child_vertex(r, 1, GEOM_SUBDIV_FROM_VERTEX, c);
            for (int k = 0; k < 3; k++)
                assert_double_equal(l2[3 * c + k], l0[3 * v + k], 1e-12);
        }
    free(l0);
    free(l2);
    free_positions(pos, 2);
    geom_subdiv_refiner_destroy(r);
    geom_subdiv_refiner_destroy(r0);
    geom_mesh_destroy(m);
}

/* Loop edge point on an interior edge: 3/8 (a + b) + 1/8 (c + d); regular
 * vertex point 5/8 v + 1/16 sum. */
static void test_loop_masks(void **state)
{
    (void)state;
    geom_mesh *m = tri_grid(4, 0, 0, 0, quad_field);
    geom_subdiv_refiner *r = refiner_for(m, GEOM_SUBDIV_LOOP, 1);
    double **pos = refine_positions(r, m);
    uint32_t ev[2 * 64];
    geom_subdiv_level_info li;
    geom_subdiv_refiner_level_info(r, 0, &li);
    assert_true(li.edges <= 64);
    geom_subdiv_refiner_edges(r, 0, ev, NULL);
    /* vertex 12 = (2,2): neighbours (3,2) (1,2) (2,3) (2,1) (3,3) (1,1) */
    uint32_t c = geom_subdiv_refiner_child_vertex(r, 0, GEOM_SUBDIV_FROM_VERTEX, 12);
    double nz = (3 * 3 + 2 * 2) + (1 + 4) + (4 + 9) + (4 + 1) + (9 + 9) + (1 + 1);
    assert_double_equal(pos[1][3 * c + 2], 0.625 * 8.0 + 0.0625 * nz, 1e-14);
    /* edge (12,13): (2,2)-(3,2), opposite (3,3) and (2,1) */
    uint32_t e = 0;
    while (!((ev[2 * e] == 12 && ev[2 * e + 1] == 13) || (ev[2 * e] == 13 && ev[2 * e + 1] == 12)))
        e++;
    c = geom_subdiv_refiner_child_vertex(r, 0, GEOM_SUBDIV_FROM_EDGE, e);
    assert_double_equal(pos[1][3 * c + 2], 0.375 * (8 + 13) + 0.125 * (18 + 5), 1e-14);
    free_positions(pos, 1);
    geom_subdiv_refiner_destroy(r);
    geom_mesh_destroy(m);
}

/* -------------------------------------------------------- bilinear */

static void test_bilinear_midpoints(void **state)
{
    (void)state;
    /* a non-planar quad and a pentagon sharing an edge, integer coordinates */
    const double v[] = {0, 0, 0, 4, 0, 1, 4, 4, -2, 0, 4, 3, 8, 0, 5, 8, 4, 7, 6, 6, 1};
    const uint32_t sz[] = {4, 5};
    const uint32_t idx[] = {0, 1, 2, 3, 1, 4, 5, 6, 2};
    geom_mesh *m = build(7, v, 2, sz, idx);
    geom_subdiv_refiner *r = refiner_for(m, GEOM_SUBDIV_BILINEAR, 2);
    double **pos = refine_positions(r, m);
    for (int l = 1; l <= 2; l++) {
        geom_subdiv_level_info pl, cl;
        geom_subdiv_refiner_level_info(r, l - 1, &pl);
        geom_subdiv_refiner_level_info(r, l, &cl);
        uint32_t *psz = malloc(pl.faces * sizeof(uint32_t)), *pidx = malloc(pl.face_vertices * 4);
        uint32_t *pev = malloc(2 * pl.edges * sizeof(uint32_t));
        geom_subdiv_refiner_faces(r, l - 1, psz, pidx, NULL);
        geom_subdiv_refiner_edges(r, l - 1, pev, NULL);
        size_t k = 0;
        for (uint32_t f = 0; f < pl.faces; f++) {
            uint32_t c = geom_subdiv_refiner_child_vertex(r, l - 1, GEOM_SUBDIV_FROM_FACE, f);
            for (int d = 0; d < 3; d++) {
                double s = 0;
                for (uint32_t i = 0; i < psz[f]; i++)
                    s += pos[l - 1][3 * pidx[k + i] + d];
                assert_double_equal(pos[l][3 * c + d], s / psz[f], 1e-14);
            }
            k += psz[f];
        }
        for (uint32_t e = 0; e < pl.edges; e++) {
            uint32_t c = geom_subdiv_refiner_child_vertex(r, l - 1, GEOM_SUBDIV_FROM_EDGE, e);
            for (int d = 0; d < 3; d++)
                assert_double_equal(pos[l][3 * c + d],
                                    0.5 * (pos[l - 1][3 * pev[2 * e] + d] + pos[l - 1][3 * pev[2 * e + 1] + d]),
                                    0);
        }
        for (uint32_t vv = 0; vv < pl.vertices; vv++) {
            uint32_t c = geom_subdiv_refiner_child_vertex(r, l - 1, GEOM_SUBDIV_FROM_VERTEX, vv);
            assert_memory_equal(pos[l] + 3 * c, pos[l - 1] + 3 * vv, 3 * sizeof(double));
        }
        free(psz);
        free(pidx);
        free(pev);
    }
    /* the bilinear limit is the vertex itself */
    geom_subdiv_level_info li;
    geom_subdiv_refiner_level_info(r, 2, &li);
    double *lim = malloc(3 * li.vertices * sizeof(double));
    assert_int_equal(geom_subdiv_limit(r, 3, pos[2], lim, NULL, NULL), GEOM_OK);
    assert_memory_equal(lim, pos[2], 3 * li.vertices * sizeof(double));
    free(lim);
    free_positions(pos, 2);
    geom_subdiv_refiner_destroy(r);
    geom_mesh_destroy(m);
}

/* ------------------------------------------------------- butterfly */

static const double ico_v[] = {0, 0, 1, 0.894427190999916, 0, 0.447213595499958,
                               0.276393202250021, 0.850650808352040, 0.447213595499958,
                               -0.723606797749979, 0.525731112119134, 0.447213595499958,
                               -0.723606797749979, -0.525731112119134, 0.447213595499958,
                               0.276393202250021, -0.850650808352040, 0.447213595499958,
                               0.723606797749979, 0.525731112119134, -0.447213595499958,
                               -0.276393202250021, 0.850650808352040, -0.447213595499958,
                               -0.894427190999916, 0, -0.447213595499958,
                               -0.276393202250021, -0.850650808352040, -0.447213595499958,
                               0.723606797749979, -0.525731112119134, -0.447213595499958,
                               0, 0, -1};
static const uint32_t ico_f[] = {0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 5, 0, 5, 1,
                                 1, 6, 2, 2, 7, 3, 3, 8, 4, 4, 9, 5, 5, 10, 1,
                                 6, 7, 2, 7, 8, 3, 8, 9, 4, 9, 10, 5, 10, 6, 1,
                                 11, 7, 6, 11, 8, 7, 11, 9, 8, 11, 10, 9, 11, 6, 10};
static const uint32_t tri_sizes[20] = {3, 3, 3, 3, 3, 3, 3, 3, 3, 3,
                                       3, 3, 3, 3, 3, 3, 3, 3, 3, 3};

static void test_butterfly_interpolates(void **state)
{
    (void)state;
    geom_mesh *m = build(12, ico_v, 20, tri_sizes, ico_f);
    const int L = 3;
    geom_subdiv_refiner *r = refiner_for(m, GEOM_SUBDIV_BUTTERFLY, L);
    double **pos = refine_positions(r, m);
    for (uint32_t v = 0; v < 12; v++) {
        uint32_t c = v;
        for (int l = 1; l <= L; l++) {
            c = geom_subdiv_refiner_child_vertex(r, l - 1, GEOM_SUBDIV_FROM_VERTEX, c);
            assert_memory_equal(pos[l] + 3 * c, ico_v + 3 * v, 3 * sizeof(double));
        }
    }
    /* valence-5 ends everywhere on level 0: the edge point is the average of
     * the two k = 5 stencils; by symmetry it lies on the bisector plane of
     * the edge, at the same distance from both ends */
    uint32_t ev[60];
    geom_subdiv_refiner_edges(r, 0, ev, NULL);
    for (uint32_t e = 0; e < 30; e++) {
        uint32_t c = geom_subdiv_refiner_child_vertex(r, 0, GEOM_SUBDIV_FROM_EDGE, e);
        double da = 0, db = 0;
        for (int k = 0; k < 3; k++) {
            da += pow(pos[1][3 * c + k] - ico_v[3 * ev[2 * e] + k], 2);
            db += pow(pos[1][3 * c + k] - ico_v[3 * ev[2 * e + 1] + k], 2);
        }
        assert_double_equal(da, db, 1e-14);
    }
    geom_subdiv_level_info li;
    geom_subdiv_refiner_level_info(r, L, &li);
    assert_int_equal(li.faces, 20 * 64);
    free_positions(pos, L);
    geom_subdiv_refiner_destroy(r);
    geom_mesh_destroy(m);

    /* planar grid stays planar and reproduces linear functions */
    m = tri_grid(6, 0.5, 0.25, -1.0, NULL);
    r = refiner_for(m, GEOM_SUBDIV_BUTTERFLY, 2);
    pos = refine_positions(r, m);
    geom_subdiv_refiner_level_info(r, 2, &li);
    for (size_t v = 0; v < li.vertices; v++)
        assert_double_equal(pos[2][3 * v + 2], 0.5 * pos[2][3 * v] + 0.25 * pos[2][3 * v + 1] - 1.0,
                            1e-13);
    free_positions(pos, 2);
    geom_subdiv_refiner_destroy(r);
    geom_mesh_destroy(m);
}

/* --------------------------------------------------------- sqrt(3) */

static void test_sqrt3_growth(void **state)
{
    (void)state;
    const double tv[] = {1, 1, 1, -1, -1, 1, -1, 1, -1, 1, -1, -1};
    const uint32_t tf[] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
    geom_mesh *m = build(4, tv, 4, tri_sizes, tf);
    const int L = 5;
    geom_subdiv_refiner *r = refiner_for(m, GEOM_SUBDIV_SQRT3, L);
    size_t f = 4, v = 4;
    for (int l = 0; l <= L; l++) {
        geom_subdiv_level_info li;
        assert_int_equal(geom_subdiv_refiner_level_info(r, l, &li), GEOM_OK);
        /* F' = 3 F, V' = V + F, closed: E = 3F/2 and V - E + F = 2 */
        assert_int_equal(li.faces, f);
        assert_int_equal(li.vertices, v);
        assert_int_equal(li.edges, 3 * f / 2);
        assert_int_equal((long)li.vertices - (long)li.edges + (long)li.faces, 2);
        v += f;
        f *= 3;
    }
    double **pos = refine_positions(r, m);
    /* Kobbelt's relaxation by hand at level 1 for vertex 0 (valence 3):
     * a_3 = (4 - 2 cos(2 pi/3))/9 = 5/9; p' = 4/9 p + 5/27 sum of the 3 others */
    uint32_t c = geom_subdiv_refiner_child_vertex(r, 0, GEOM_SUBDIV_FROM_VERTEX, 0);
    for (int k = 0; k < 3; k++) {
        double s = tv[3 + k] + tv[6 + k] + tv[9 + k];
        assert_double_equal(pos[1][3 * c + k], 4.0 / 9.0 * tv[k] + 5.0 / 27.0 * s, 1e-15);
    }
    /* centroids */
    c = geom_subdiv_refiner_child_vertex(r, 0, GEOM_SUBDIV_FROM_FACE, 0);
    assert_double_equal(pos[1][3 * c], (1 - 1 - 1) / 3.0, 1e-15);
    /* the limit of the regular tetrahedron's vertices stays on the line to
     * the centre and converges: positions at level L approach the limit */
    geom_subdiv_level_info li;
    geom_subdiv_refiner_level_info(r, L, &li);
    double *lim = malloc(3 * li.vertices * sizeof(double));
    assert_int_equal(geom_subdiv_limit(r, 3, pos[L], lim, NULL, NULL), GEOM_OK);
    uint32_t cv = 0;
    for (int l = 1; l <= L; l++)
        cv = geom_subdiv_refiner_child_vertex(r, l - 1, GEOM_SUBDIV_FROM_VERTEX, cv);
    assert_double_equal(lim[3 * cv], lim[3 * cv + 1], 1e-14);
    assert_double_equal(lim[3 * cv], lim[3 * cv + 2], 1e-14);
    free(lim);
    free_positions(pos, L);
    geom_subdiv_refiner_destroy(r);
    geom_mesh_destroy(m);

    /* open mesh: F' = 3F still (boundary edges are not flipped) */
    m = tri_grid(3, 0, 0, 0, NULL);
    r = refiner_for(m, GEOM_SUBDIV_SQRT3, 3);
    for (int l = 0; l <= 3; l++) {
        geom_subdiv_refiner_level_info(r, l, &li);
        assert_int_equal(li.faces, 18 * (size_t)pow(3, l));
    }
    pos = refine_positions(r, m);
    geom_subdiv_refiner_level_info(r, 3, &li);
    for (size_t vv = 0; vv < li.vertices; vv++)
        assert_double_equal(pos[3][3 * vv + 2], 0.0, 0);
    free_positions(pos, 3);
    geom_subdiv_refiner_destroy(r);
    geom_mesh_destroy(m);
}

/* ---------------------------------------------------- face-varying */

/* UVs equal to x, y of a planar quad grid: with linear ("all") the refined
 * UVs are the bilinear averages; with "none" they follow the vertex rules,
 * so they equal the refined x, y; with "corners only" the 4 grid corners
 * keep their UVs while the positions of those corners move. */
static void test_fvar_options(void **state)
{
    (void)state;
    geom_mesh *m = quad_grid(3, NULL);
    uint32_t uv;
    assert_int_equal(geom_mesh_channel_add(m, "uv", GEOM_MESH_DOMAIN_CORNER, 2, &uv), GEOM_OK);
    size_t nv = geom_mesh_n_vertices(m);
    assert_int_equal(geom_mesh_corner_pool_resize(m, uv, nv), GEOM_OK);
    double *pool = geom_mesh_channel_data(m, uv);
    const double *p = geom_mesh_cpositions(m);
    for (size_t v = 0; v < nv; v++)
        pool[2 * v] = p[3 * v], pool[2 * v + 1] = p[3 * v + 1];
    uint32_t *ci = geom_mesh_corner_indices(m, uv);
    for (uint32_t h = 0; h < geom_mesh_n_halfedges(m); h++)
        ci[h] = geom_mesh_he_face(m, h) == GEOM_INVALID_INDEX ? GEOM_INVALID_INDEX
                                                              : geom_mesh_he_vertex(m, h);
    const geom_subdiv_fvar modes[3] = {GEOM_SUBDIV_FVAR_ALL, GEOM_SUBDIV_FVAR_NONE,
                                       GEOM_SUBDIV_FVAR_CORNERS_ONLY};
    for (int t = 0; t < 3; t++) {
        geom_subdiv_options o;
        memset(&o, 0, sizeof o);
        o.fvar_boundary = modes[t];
        geom_subdiv_refiner *r = NULL;
        assert_int_equal(geom_subdiv_refiner_create(m, &o, &r, NULL), GEOM_OK);
        assert_int_equal(geom_subdiv_refiner_fvar_count(r), 1);
        assert_int_equal(geom_subdiv_refiner_refine(r, 2), GEOM_OK);
        double **pos = refine_positions(r, m);
        double *uvs[3];
        uvs[0] = malloc(2 * nv * sizeof(double));
        memcpy(uvs[0], pool, 2 * nv * sizeof(double));
        for (int l = 1; l <= 2; l++) {
            size_t n = geom_subdiv_fvar_size(r, 0, l);
            uvs[l] = malloc(2 * n * sizeof(double));
            assert_int_equal(geom_subdiv_interpolate_fvar(r, 0, l, 2, uvs[l - 1], uvs[l]), GEOM_OK);
        }
        geom_subdiv_level_info li;
        geom_subdiv_refiner_level_info(r, 2, &li);
        uint32_t *fvals = malloc(li.face_vertices * sizeof(uint32_t));
        uint32_t *fverts = malloc(li.face_vertices * sizeof(uint32_t));
        geom_subdiv_fvar_face_values(r, 0, 2, fvals);
        geom_subdiv_refiner_faces(r, 2, NULL, fverts, NULL);
        /* the level-2 descendants of the grid corner (0,0) */
        uint32_t corner = geom_subdiv_refiner_child_vertex(r, 0, GEOM_SUBDIV_FROM_VERTEX, 0);
        corner = geom_subdiv_refiner_child_vertex(r, 1, GEOM_SUBDIV_FROM_VERTEX, corner);
        for (size_t i = 0; i < li.face_vertices; i++) {
            const double *q = pos[2] + 3 * fverts[i], *u = uvs[2] + 2 * fvals[i];
            if (t == 1) {
                assert_double_equal(u[0], q[0], 1e-14);
                assert_double_equal(u[1], q[1], 1e-14);
            } else if (fverts[i] == corner) {
                assert_double_equal(u[0], 0.0, 0);
                assert_double_equal(u[1], 0.0, 0);
                assert_true(q[0] > 0.0 && q[1] > 0.0);
            }
        }
        if (t == 0) {
            /* linear UVs: refine the UV field bilinearly by hand and compare */
            geom_subdiv_refiner *rb = refiner_for(m, GEOM_SUBDIV_BILINEAR, 2);
            double **bp = refine_positions(rb, m);
            for (size_t i = 0; i < li.face_vertices; i++) {
                assert_double_equal(uvs[2][2 * fvals[i]], bp[2][3 * fverts[i]], 1e-14);
                assert_double_equal(uvs[2][2 * fvals[i] + 1], bp[2][3 * fverts[i] + 1], 1e-14);
            }
            free_positions(bp, 2);
            geom_subdiv_refiner_destroy(rb);
        }
        free(fvals);
        free(fverts);
        for (int l = 0; l <= 2; l++)
            free(uvs[l]);
        free_positions(pos, 2);
        geom_subdiv_refiner_destroy(r);
    }
    geom_mesh_destroy(m);
}

/* ----------------------------------------------- whole-mesh and tags */

static void test_mesh_with_seams_and_tags(void **state)
{
    (void)state;
    geom_mesh *m = build(8, cube_v, 6, quad_sizes, cube_f);
    /* a UV channel with a seam: every face gets its own four UVs */
    add_seamed_uv(m);
    /* hole on face 0, interpolateboundary tag */
    int64_t hole = 0;
    geom_mesh_tag t = {"hole", 1, 0, 0, &hole, NULL, NULL};
    assert_int_equal(geom_mesh_tag_add(m, &t), GEOM_OK);
    int64_t ib = 1;
    geom_mesh_tag t2 = {"interpolateboundary", 1, 0, 0, &ib, NULL, NULL};
    assert_int_equal(geom_mesh_tag_add(m, &t2), GEOM_OK);
    int64_t cr[2] = {4, 5};
    double crs = 3.0;
    geom_mesh_tag t3 = {"crease", 2, 1, 0, cr, &crs, NULL};
    assert_int_equal(geom_mesh_tag_add(m, &t3), GEOM_OK);
    geom_mesh *out = NULL;
    geom_subdiv_report rep;
    assert_int_equal(geom_subdiv_mesh(m, NULL, 2, GEOM_SUBDIV_NORMALS, &out, &rep, NULL), GEOM_OK);
    assert_int_equal(rep.levels, 2);
    assert_int_equal(rep.input_faces, 6);
    assert_int_equal(rep.hole_faces, 16);
    assert_int_equal(rep.faces, 5 * 16);
    assert_int_equal(geom_mesh_n_faces(out), 80);
    assert_int_equal(rep.fvar_channels, 1);
    assert_true(rep.max_limit_distance > 0.0 && rep.max_limit_distance < 0.2);
    assert_true(rep.rms_limit_distance <= rep.max_limit_distance);
    assert_double_equal(rep.bbox_diagonal, sqrt(12.0), 1e-15);
    uint32_t ouv = geom_mesh_channel_find(out, "uv", GEOM_MESH_DOMAIN_CORNER);
    assert_int_not_equal(ouv, GEOM_INVALID_INDEX);
    /* Every face keeps its own chart: UVs in [0,1]^2 and a seam between
     * faces of different parents (their corner indices never shared). */
    const double *opool = geom_mesh_channel_cdata(out, ouv);
    for (size_t i = 0; i < geom_mesh_channel_size(out, ouv); i++) {
        assert_true(opool[2 * i] >= 0.0 && opool[2 * i] <= 1.0);
        assert_true(opool[2 * i + 1] >= 0.0 && opool[2 * i + 1] <= 1.0);
    }
    assert_int_not_equal(geom_mesh_channel_find(out, "normal", GEOM_MESH_DOMAIN_VERTEX),
                         GEOM_INVALID_INDEX);
    /* the crease tag is carried with sharpness 3 - 2 = 1 */
    int found_crease = 0, found_ib = 0;
    for (size_t i = 0; i < geom_mesh_tag_count(out); i++) {
        geom_mesh_tag q;
        geom_mesh_tag_get(out, i, &q);
        if (strcmp(q.name, "crease") == 0) {
            found_crease = 1;
            for (size_t j = 0; j < q.nfloat; j++)
                assert_double_equal(q.floats[j], 1.0, 0);
            assert_int_equal(q.nint, 2 * q.nfloat);
            assert_int_equal(q.nfloat, 4);
        }
        if (strcmp(q.name, "interpolateboundary") == 0)
            found_ib = 1;
    }
    assert_true(found_crease && found_ib);
    geom_mesh_destroy(out);
    /* GEOM_SUBDIV_LIMIT: vertices on the limit surface, distance 0; the
     * level_* fields keep the refined level's distance, bit for bit what
     * the same call without the flag reports */
    geom_subdiv_report plain;
    assert_int_equal(geom_subdiv_mesh(m, NULL, 1, 0, &out, &plain, NULL), GEOM_OK);
    geom_mesh_destroy(out);
    assert_true(plain.max_limit_distance > 0.0);
    assert_true(plain.level_max_limit_distance == plain.max_limit_distance);
    assert_true(plain.level_rms_limit_distance == plain.rms_limit_distance);
    assert_int_equal(geom_subdiv_mesh(m, NULL, 1, GEOM_SUBDIV_LIMIT, &out, &rep, NULL), GEOM_OK);
    assert_double_equal(rep.max_limit_distance, 0.0, 0);
    assert_true(rep.level_max_limit_distance == plain.max_limit_distance);
    assert_true(rep.level_rms_limit_distance == plain.rms_limit_distance);
    geom_mesh_destroy(out);
    geom_mesh_destroy(m);
}

static int cmp_xyz(const void *a, const void *b)
{
    const double *p = a, *q = b;
    for (int k = 0; k < 3; k++) {
        if (p[k] < q[k] - 1e-9)
            return -1;
        if (p[k] > q[k] + 1e-9)
            return 1;
    }
    return 0;
}

/* Refining the output of geom_subdiv_mesh again continues the surface: the
 * decayed creases and corners travel as tags (Chaikin creasing, semi-sharp
 * edges, a semi-sharp corner), so 2 + 1 levels give the same vertices as 3. */
static void test_mesh_refine_again(void **state)
{
    (void)state;
    geom_mesh *m = build(8, cube_v, 6, quad_sizes, cube_f);
    int64_t cr[4] = {4, 5, 5, 6};
    double crs[2] = {2.5, 1.25};
    geom_mesh_tag t1 = {"crease", 4, 2, 0, cr, crs, NULL};
    int64_t co = 0;
    double cos_ = 1.5;
    geom_mesh_tag t2 = {"corner", 1, 1, 0, &co, &cos_, NULL};
    const char *chaikin = "chaikin";
    geom_mesh_tag t3 = {"creasemethod", 0, 0, 1, NULL, NULL, &chaikin};
    assert_int_equal(geom_mesh_tag_add(m, &t1), GEOM_OK);
    assert_int_equal(geom_mesh_tag_add(m, &t2), GEOM_OK);
    assert_int_equal(geom_mesh_tag_add(m, &t3), GEOM_OK);
    geom_mesh *a = NULL, *b = NULL, *c = NULL;
    assert_int_equal(geom_subdiv_mesh(m, NULL, 3, 0, &a, NULL, NULL), GEOM_OK);
    assert_int_equal(geom_subdiv_mesh(m, NULL, 2, 0, &b, NULL, NULL), GEOM_OK);
    assert_int_equal(geom_subdiv_mesh(b, NULL, 1, 0, &c, NULL, NULL), GEOM_OK);
    size_t n = geom_mesh_n_vertices(a);
    assert_int_equal(geom_mesh_n_vertices(c), n);
    double *pa = malloc(3 * n * sizeof(double)), *pc = malloc(3 * n * sizeof(double));
    memcpy(pa, geom_mesh_cpositions(a), 3 * n * sizeof(double));
    memcpy(pc, geom_mesh_cpositions(c), 3 * n * sizeof(double));
    qsort(pa, n, 3 * sizeof(double), cmp_xyz);
    qsort(pc, n, 3 * sizeof(double), cmp_xyz);
    for (size_t i = 0; i < 3 * n; i++)
        assert_double_equal(pa[i], pc[i], 1e-14);
    free(pa);
    free(pc);
    geom_mesh_destroy(a);
    geom_mesh_destroy(b);
    geom_mesh_destroy(c);
    geom_mesh_destroy(m);
}

/* ------------------------------------------- non-manifold and errors */

static void test_nonmanifold_soup(void **state)
{
    (void)state;
    /* three quads on one edge (0,1), and a triangle touching vertex 4 only */
    const double v[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1,
                        1, -1, 0, 0, -1, 0, 2, 0, 1, 2, 1, 1};
    const uint32_t sz[] = {4, 4, 4, 3};
    const uint32_t idx[] = {0, 1, 2, 3, 1, 0, 5, 4, 0, 1, 6, 7, 4, 8, 9};
    geom_subdiv_refiner *r = NULL;
    for (int s = 0; s < 3; s += 2) {
        geom_subdiv_options o;
        memset(&o, 0, sizeof o);
        o.scheme = (geom_subdiv_scheme)s;
        assert_int_equal(geom_subdiv_refiner_create_soup(10, 4, sz, idx, &o, &r, NULL), GEOM_OK);
        assert_int_equal(geom_subdiv_refiner_refine(r, 3), GEOM_OK);
        double *p[4];
        p[0] = malloc(sizeof v);
        memcpy(p[0], v, sizeof v);
        for (int l = 1; l <= 3; l++) {
            geom_subdiv_level_info li;
            geom_subdiv_refiner_level_info(r, l, &li);
            p[l] = malloc(3 * li.vertices * sizeof(double));
            assert_int_equal(geom_subdiv_interpolate(r, l, 3, p[l - 1], p[l]), GEOM_OK);
            for (size_t i = 0; i < 3 * li.vertices; i++)
                assert_true(isfinite(p[l][i]));
        }
        /* the non-manifold edge is infinitely sharp: its vertices 0 and 1
         * (non-manifold, sharpened) stay put */
        uint32_t c = 0;
        for (int l = 1; l <= 3; l++)
            c = geom_subdiv_refiner_child_vertex(r, l - 1, GEOM_SUBDIV_FROM_VERTEX, c);
        assert_memory_equal(p[3] + 3 * c, v, 3 * sizeof(double));
        geom_subdiv_level_info li;
        geom_subdiv_refiner_level_info(r, 3, &li);
        double *lim = malloc(9 * li.vertices * sizeof(double));
        assert_int_equal(geom_subdiv_limit(r, 3, p[3], lim, lim + 3 * li.vertices,
                                           lim + 6 * li.vertices),
                         GEOM_OK);
        free(lim);
        for (int l = 0; l <= 3; l++)
            free(p[l]);
        geom_subdiv_refiner_destroy(r);
    }
    /* a face using a vertex twice */
    const uint32_t sz2[] = {5};
    const uint32_t idx2[] = {0, 1, 2, 1, 3};
    assert_int_equal(geom_subdiv_refiner_create_soup(4, 1, sz2, idx2, NULL, &r, NULL), GEOM_OK);
    assert_int_equal(geom_subdiv_refiner_refine(r, 2), GEOM_OK);
    geom_subdiv_refiner_destroy(r);
}

/* The refined level's mesh made by geom_subdiv_build_mesh (directly from
 * the level's relations where it is a manifold) against geom_mesh_build
 * over the same level's soup (the repairing builder, a separate path): the
 * same halfedges, faces, vertices, positions and UV corners, element for
 * element. Closed, open (boundary), quad, triangle, with a UV channel with
 * seams, and a Loop mesh with an interior vertex of valence 2 (whose
 * children have two edges between one pair of vertices: geom_mesh_build
 * repairs them, and so must the direct path's fallback). */
static void check_like_soup_build(const geom_mesh *m, geom_subdiv_scheme s, int levels)
{
    geom_subdiv_refiner *r = refiner_for(m, s, levels);
    double **pos = refine_positions(r, m);
    geom_mesh *out = NULL;
    assert_int_equal(geom_subdiv_build_mesh(r, levels, pos[levels], NULL, m, &out, NULL, NULL),
                     GEOM_OK);
    geom_subdiv_level_info li;
    assert_int_equal(geom_subdiv_refiner_level_info(r, levels, &li), GEOM_OK);
    uint32_t *sz = malloc(li.faces * sizeof(uint32_t)), *ix = malloc(li.face_vertices * 4);
    assert_int_equal(geom_subdiv_refiner_faces(r, levels, sz, ix, NULL), GEOM_OK);
    geom_mesh_build_options bo;
    memset(&bo, 0, sizeof bo);
    bo.skip_invalid_faces = 1;
    bo.keep_orientation = 1;
    geom_mesh *ref = geom_mesh_create(NULL);
    assert_int_equal(geom_mesh_build(ref, li.vertices, pos[levels], li.faces, sz, ix, &bo, NULL,
                                     NULL),
                     GEOM_OK);
    assert_same_connectivity(out, ref);
    assert_memory_equal(geom_mesh_cpositions(out), geom_mesh_cpositions(ref),
                        3 * geom_mesh_n_vertices(ref) * sizeof(double));
    uint32_t uv = geom_mesh_channel_find(out, "uv", GEOM_MESH_DOMAIN_CORNER);
    if (uv != GEOM_INVALID_INDEX) {
        /* corner k of face f in the level's order holds the level's value */
        size_t nvals = geom_subdiv_fvar_size(r, 0, levels);
        uint32_t *fv = malloc(li.face_vertices * sizeof(uint32_t));
        assert_int_equal(geom_subdiv_fvar_face_values(r, 0, levels, fv), GEOM_OK);
        assert_int_equal(geom_mesh_channel_size(out, uv), nvals);
        const uint32_t *ci = geom_mesh_corner_cindices(out, uv);
        size_t k = 0;
        for (uint32_t f = 0; f < geom_mesh_n_faces(out); f++) {
            uint32_t h0 = geom_mesh_face_he(out, f), h = h0;
            do {
                assert_int_equal(ci[h], fv[k++]);
                h = geom_mesh_he_next(out, h);
            } while (h != h0);
        }
        free(fv);
    }
    geom_mesh_destroy(ref);
    geom_mesh_destroy(out);
    free(sz);
    free(ix);
    free_positions(pos, levels);
    geom_subdiv_refiner_destroy(r);
}

static void test_build_mesh_like_soup(void **state)
{
    (void)state;
    geom_mesh *cube = build(8, cube_v, 6, quad_sizes, cube_f);
    check_like_soup_build(cube, GEOM_SUBDIV_CATMULL_CLARK, 1);
    check_like_soup_build(cube, GEOM_SUBDIV_CATMULL_CLARK, 2);
    check_like_soup_build(cube, GEOM_SUBDIV_BILINEAR, 2);
    /* with a seamed UV channel */
    add_seamed_uv(cube);
    check_like_soup_build(cube, GEOM_SUBDIV_CATMULL_CLARK, 2);
    geom_mesh_destroy(cube);
    geom_mesh *qg = quad_grid(3, NULL); /* boundary and corners */
    check_like_soup_build(qg, GEOM_SUBDIV_CATMULL_CLARK, 2);
    geom_mesh_destroy(qg);
    geom_mesh *tg = tri_grid(3, 0.1, 0.2, 0.3, NULL);
    check_like_soup_build(tg, GEOM_SUBDIV_LOOP, 1);
    check_like_soup_build(tg, GEOM_SUBDIV_LOOP, 2);
    check_like_soup_build(tg, GEOM_SUBDIV_CATMULL_CLARK, 1);
    geom_mesh_destroy(tg);
    geom_mesh *ico = build(12, ico_v, 20, tri_sizes, ico_f);
    check_like_soup_build(ico, GEOM_SUBDIV_LOOP, 2);
    geom_mesh_destroy(ico);
    /* a pillow: two triangles sharing all three edges (valence-2 vertices) */
    static const double pv[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    static const uint32_t pf[] = {0, 1, 2, 0, 2, 1}, ps[] = {3, 3};
    geom_mesh *pil = build(3, pv, 2, ps, pf);
    check_like_soup_build(pil, GEOM_SUBDIV_LOOP, 1);
    check_like_soup_build(pil, GEOM_SUBDIV_LOOP, 2);
    check_like_soup_build(pil, GEOM_SUBDIV_CATMULL_CLARK, 1);
    geom_mesh_destroy(pil);
}

/* partial_last_level = 2: the deepest level has only what the limit
 * reads; limit positions and tangents equal those of the full level bit
 * for bit, and refining further (which completes the level) gives the
 * same next level as without the option. */
static void check_limit_relations(const geom_mesh *m, geom_subdiv_scheme s)
{
    geom_subdiv_refiner *r[2];
    double *lim[2][3];
    for (int k = 0; k < 2; k++) {
        geom_subdiv_options o;
        memset(&o, 0, sizeof o);
        o.scheme = s;
        o.partial_last_level = 2 * k;
        assert_int_equal(geom_subdiv_refiner_create(m, &o, &r[k], NULL), GEOM_OK);
        assert_int_equal(geom_subdiv_refiner_refine(r[k], 1), GEOM_OK);
        double **pos = refine_positions(r[k], m);
        geom_subdiv_level_info li;
        geom_subdiv_refiner_level_info(r[k], 1, &li);
        for (int j = 0; j < 3; j++)
            lim[k][j] = malloc(3 * li.vertices * sizeof(double));
        assert_int_equal(geom_subdiv_limit(r[k], 3, pos[1], lim[k][0], lim[k][1], lim[k][2]),
                         GEOM_OK);
        if (k)
            for (int j = 0; j < 3; j++)
                assert_memory_equal(lim[0][j], lim[1][j], 3 * li.vertices * sizeof(double));
        free_positions(pos, 1);
        assert_int_equal(geom_subdiv_refiner_refine(r[k], 1), GEOM_OK);
    }
    geom_subdiv_level_info a, b;
    geom_subdiv_refiner_level_info(r[0], 2, &a);
    geom_subdiv_refiner_level_info(r[1], 2, &b);
    assert_memory_equal(&a, &b, sizeof a);
    double **p0 = refine_positions(r[0], m), **p1 = refine_positions(r[1], m);
    assert_memory_equal(p0[2], p1[2], 3 * a.vertices * sizeof(double));
    free_positions(p0, 2);
    free_positions(p1, 2);
    for (int k = 0; k < 2; k++) {
        for (int j = 0; j < 3; j++)
            free(lim[k][j]);
        geom_subdiv_refiner_destroy(r[k]);
    }
}

/* geom_subdiv_level_is_plain: where it says so, the level written as a soup
 * (geom_meshio_write_soup_stream over geom_subdiv_refiner_face_indices)
 * gives the very bytes geom_meshio_write gives for the mesh
 * geom_subdiv_build_mesh makes (the separate, mesh-building path); where
 * the output carries more (holes, creases, UVs), it says no. */
typedef struct membuf {
    char *d;
    size_t n;
} membuf;

static geom_status membuf_write(void *user, const void *data, size_t size)
{
    membuf *b = user;
    char *d = realloc(b->d, b->n + size + 1);
    if (!d)
        return GEOM_ERR_NOMEM;
    memcpy(d + b->n, data, size);
    b->d = d;
    b->n += size;
    return GEOM_OK;
}

static int check_plain(const geom_mesh *m, geom_subdiv_scheme s, int levels, int normals)
{
    geom_subdiv_refiner *r = refiner_for(m, s, levels);
    double **pos = refine_positions(r, m);
    geom_subdiv_level_info li;
    assert_int_equal(geom_subdiv_refiner_level_info(r, levels, &li), GEOM_OK);
    double *nrm = NULL;
    if (normals) {
        nrm = malloc(3 * li.vertices * sizeof(double));
        assert_int_equal(geom_subdiv_limit_normals(r, pos[levels], nrm, NULL), GEOM_OK);
    }
    int plain = geom_subdiv_level_is_plain(r, levels, pos[levels], normals, m);
    /* the indices without a copy are those geom_subdiv_refiner_faces copies */
    const uint32_t *fi = geom_subdiv_refiner_face_indices(r, levels);
    uint32_t *sz = malloc(li.faces * sizeof(uint32_t)), *ix = malloc(li.face_vertices * 4);
    assert_int_equal(geom_subdiv_refiner_faces(r, levels, sz, ix, NULL), GEOM_OK);
    assert_non_null(fi);
    assert_memory_equal(fi, ix, li.face_vertices * sizeof(uint32_t));
    if (plain) {
        geom_mesh *out = NULL;
        assert_int_equal(
            geom_subdiv_build_mesh(r, levels, pos[levels], nrm, m, &out, NULL, NULL), GEOM_OK);
        geom_meshio_write_options wo;
        memset(&wo, 0, sizeof wo);
        wo.format = GEOM_MESHIO_FORMAT_OBJ;
        membuf a = {NULL, 0}, b = {NULL, 0};
        assert_int_equal(geom_meshio_write_stream(out, &wo, membuf_write, &a, NULL), GEOM_OK);
        geom_meshio_soup soup;
        memset(&soup, 0, sizeof soup);
        soup.n_vertices = li.vertices;
        soup.xyz = pos[levels];
        soup.normals = nrm;
        soup.n_faces = li.faces;
        soup.face_sizes = sz;
        soup.indices = fi;
        assert_int_equal(geom_meshio_write_soup_stream(&soup, &wo, membuf_write, &b, NULL),
                         GEOM_OK);
        assert_int_equal(a.n, b.n);
        assert_memory_equal(a.d, b.d, a.n);
        free(a.d);
        free(b.d);
        geom_mesh_destroy(out);
    }
    free(sz);
    free(ix);
    free(nrm);
    free_positions(pos, levels);
    geom_subdiv_refiner_destroy(r);
    return plain;
}

static void test_plain_level_soup(void **state)
{
    (void)state;
    geom_mesh *cube = build(8, cube_v, 6, quad_sizes, cube_f);
    assert_true(check_plain(cube, GEOM_SUBDIV_CATMULL_CLARK, 1, 0));
    assert_true(check_plain(cube, GEOM_SUBDIV_CATMULL_CLARK, 2, 1));
    assert_true(check_plain(cube, GEOM_SUBDIV_BILINEAR, 2, 0));
    /* level 0 is the input as built, not the refiner's soup */
    geom_subdiv_refiner *r = refiner_for(cube, GEOM_SUBDIV_CATMULL_CLARK, 1);
    assert_false(geom_subdiv_level_is_plain(r, 0, cube_v, 0, cube));
    assert_false(geom_subdiv_level_is_plain(r, 2, cube_v, 0, cube));
    assert_false(geom_subdiv_level_is_plain(NULL, 1, cube_v, 0, cube));
    assert_null(geom_subdiv_refiner_face_indices(r, 2));
    assert_null(geom_subdiv_refiner_face_indices(NULL, 0));
    geom_subdiv_refiner_destroy(r);
    /* a crease still sharp at the level: the output carries a crease tag */
    int64_t cr[2] = {4, 5};
    double crs = 3.0;
    geom_mesh_tag t = {"crease", 2, 1, 0, cr, &crs, NULL};
    geom_mesh *creased = build(8, cube_v, 6, quad_sizes, cube_f);
    assert_int_equal(geom_mesh_tag_add(creased, &t), GEOM_OK);
    assert_false(check_plain(creased, GEOM_SUBDIV_CATMULL_CLARK, 1, 0));
    geom_mesh_destroy(creased);
    /* a hole: its faces are left out */
    int64_t hole = 0;
    geom_mesh_tag th = {"hole", 1, 0, 0, &hole, NULL, NULL};
    geom_mesh *holed = build(8, cube_v, 6, quad_sizes, cube_f);
    assert_int_equal(geom_mesh_tag_add(holed, &th), GEOM_OK);
    assert_false(check_plain(holed, GEOM_SUBDIV_CATMULL_CLARK, 1, 0));
    geom_mesh_destroy(holed);
    /* UVs: the output has vt lines */
    add_seamed_uv(cube);
    assert_false(check_plain(cube, GEOM_SUBDIV_CATMULL_CLARK, 1, 0));
    geom_mesh_destroy(cube);
    /* open (boundary edges are sharp but not tagged), triangles */
    geom_mesh *qg = quad_grid(3, NULL);
    assert_true(check_plain(qg, GEOM_SUBDIV_CATMULL_CLARK, 2, 1));
    geom_mesh_destroy(qg);
    geom_mesh *tg = tri_grid(3, 0.1, 0.2, 0.3, NULL);
    assert_true(check_plain(tg, GEOM_SUBDIV_LOOP, 1, 0));
    assert_true(check_plain(tg, GEOM_SUBDIV_LOOP, 2, 1));
    geom_mesh_destroy(tg);
    geom_mesh *ico = build(12, ico_v, 20, tri_sizes, ico_f);
    assert_true(check_plain(ico, GEOM_SUBDIV_LOOP, 2, 0));
    geom_mesh_destroy(ico);
    /* the pillow's valence-2 vertices: the build repairs, so not plain */
    static const double pv[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    static const uint32_t pf[] = {0, 1, 2, 0, 2, 1}, ps[] = {3, 3};
    geom_mesh *pil = build(3, pv, 2, ps, pf);
    assert_false(check_plain(pil, GEOM_SUBDIV_LOOP, 1, 0));
    geom_mesh_destroy(pil);
    /* butterfly levels are not made plain */
    geom_mesh *ico2 = build(12, ico_v, 20, tri_sizes, ico_f);
    assert_false(check_plain(ico2, GEOM_SUBDIV_BUTTERFLY, 1, 0));
    geom_mesh_destroy(ico2);
}

static void test_limit_relations_only(void **state)
{
    (void)state;
    geom_mesh *cube = build(8, cube_v, 6, quad_sizes, cube_f);
    check_limit_relations(cube, GEOM_SUBDIV_CATMULL_CLARK);
    geom_mesh_destroy(cube);
    geom_mesh *tg = tri_grid(4, 0.1, 0.2, 0.3, NULL); /* boundary and corners */
    check_limit_relations(tg, GEOM_SUBDIV_LOOP);
    check_limit_relations(tg, GEOM_SUBDIV_CATMULL_CLARK);
    geom_mesh_destroy(tg);
    geom_mesh *ico = build(12, ico_v, 20, tri_sizes, ico_f);
    check_limit_relations(ico, GEOM_SUBDIV_LOOP);
    geom_mesh_destroy(ico);
}

static void test_errors(void **state)
{
    (void)state;
    geom_mesh *m = build(8, cube_v, 6, quad_sizes, cube_f);
    geom_subdiv_refiner *r = NULL;
    geom_subdiv_options o;
    memset(&o, 0, sizeof o);
    geom_diag d;
    o.scheme = GEOM_SUBDIV_LOOP;
    assert_int_equal(geom_subdiv_refiner_create(m, &o, &r, &d), GEOM_ERR_INVALID_ARG);
    assert_null(r);
    assert_non_null(strstr(d.message, "triangles"));
    o.scheme = (geom_subdiv_scheme)99;
    assert_int_equal(geom_subdiv_refiner_create(m, &o, &r, NULL), GEOM_ERR_INVALID_ARG);
    o.scheme = GEOM_SUBDIV_CATMULL_CLARK;
    uint32_t bad[2] = {0, 6};
    double s = 1;
    o.n_creases = 1;
    o.crease_verts = bad;
    o.crease_sharpness = &s;
    assert_int_equal(geom_subdiv_refiner_create(m, &o, &r, &d), GEOM_ERR_INVALID_ARG);
    assert_non_null(strstr(d.message, "no edge"));
    memset(&o, 0, sizeof o);
    int64_t ib = 7;
    geom_mesh_tag t = {"interpolateboundary", 1, 0, 0, &ib, NULL, NULL};
    geom_mesh *m2 = build(8, cube_v, 6, quad_sizes, cube_f);
    assert_int_equal(geom_mesh_tag_add(m2, &t), GEOM_OK);
    assert_int_equal(geom_subdiv_refiner_create(m2, NULL, &r, NULL), GEOM_ERR_INVALID_ARG);
    o.ignore_tags = 1;
    assert_int_equal(geom_subdiv_refiner_create(m2, &o, &r, NULL), GEOM_OK);
    geom_subdiv_refiner_destroy(r);
    geom_mesh_destroy(m2);
    assert_int_equal(geom_subdiv_refiner_create(NULL, NULL, &r, NULL), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_subdiv_refiner_create(m, NULL, &r, NULL), GEOM_OK);
    assert_int_equal(geom_subdiv_refiner_refine(r, -1), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_subdiv_refiner_refine(r, GEOM_SUBDIV_MAX_LEVEL + 1), GEOM_ERR_LIMIT);
    assert_int_equal(geom_subdiv_refiner_max_level(r), 0);
    double buf[3];
    assert_int_equal(geom_subdiv_interpolate(r, 1, 3, cube_v, buf), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_subdiv_refiner_refine(r, 1), GEOM_OK);
    uint32_t fv[24] = {0};
    assert_int_equal(geom_subdiv_refiner_add_fvar(r, 24, fv, NULL), GEOM_ERR_INVALID_ARG);
    geom_subdiv_refiner_destroy(r);
    geom_subdiv_refiner_destroy(NULL);
    geom_subdiv_scheme sc;
    assert_int_equal(geom_subdiv_scheme_from_name("sqrt3", &sc), GEOM_OK);
    assert_int_equal(sc, GEOM_SUBDIV_SQRT3);
    assert_int_equal(geom_subdiv_scheme_from_name("catmark", &sc), GEOM_OK);
    assert_int_equal(sc, GEOM_SUBDIV_CATMULL_CLARK);
    assert_int_equal(geom_subdiv_scheme_from_name("doo-sabin", &sc), GEOM_ERR_INVALID_ARG);
    assert_string_equal(geom_subdiv_scheme_name(GEOM_SUBDIV_BUTTERFLY), "butterfly");
    geom_mesh_destroy(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cc_cube_corner_limit),
        cmocka_unit_test(test_cc_counts_and_maps),
        cmocka_unit_test(test_cc_masks_by_hand),
        cmocka_unit_test(test_cc_creases),
        cmocka_unit_test(test_crease_decay),
        cmocka_unit_test(test_loop_box_spline),
        cmocka_unit_test(test_loop_masks),
        cmocka_unit_test(test_bilinear_midpoints),
        cmocka_unit_test(test_butterfly_interpolates),
        cmocka_unit_test(test_sqrt3_growth),
        cmocka_unit_test(test_fvar_options),
        cmocka_unit_test(test_mesh_with_seams_and_tags),
        cmocka_unit_test(test_mesh_refine_again),
        cmocka_unit_test(test_nonmanifold_soup),
        cmocka_unit_test(test_build_mesh_like_soup),
        cmocka_unit_test(test_plain_level_soup),
        cmocka_unit_test(test_limit_relations_only),
        cmocka_unit_test(test_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
