/* Ear-clipping triangulation: convex, comb and spiral polygons, collinear
 * vertices, clockwise input, 3D planar polygons rotated arbitrarily, and
 * in-place mesh triangulation keeping corner channels, face channels and
 * groups. Every polygon triangulation is checked to be a proper one: n-2
 * triangles, each with the polygon's orientation (exact orient2d), every
 * polygon side used once and every diagonal twice, and total area equal to
 * the shoelace area. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "geom/mesh.h"
#include "bench/triangulate_shapes.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define INV GEOM_INVALID_INDEX
#define PI 3.14159265358979323846

static double shoelace(size_t n, const double *xy)
{
    double a = 0;
    for (size_t i = 0; i < n; ++i) {
        size_t j = (i + 1) % n;
        a += xy[2 * i] * xy[2 * j + 1] - xy[2 * j] * xy[2 * i + 1];
    }
    return 0.5 * a;
}

/* Check tris (from the 3D points) against the 2D polygon xy. sign: +1 for a
 * counter-clockwise polygon, -1 for clockwise. */
static void check_triangulation(size_t n, const double *xy, const uint32_t *tris, int sign)
{
    double area = 0;
    int *use = calloc(n * n, sizeof(int));
    for (size_t t = 0; t < n - 2; ++t) {
        const uint32_t *v = tris + 3 * t;
        for (int k = 0; k < 3; ++k) {
            assert_true(v[k] < n);
            uint32_t a = v[k], b = v[(k + 1) % 3];
            use[a * n + b]++;
        }
        double o = geom_orient2d(xy + 2 * v[0], xy + 2 * v[1], xy + 2 * v[2]);
        if (!(o * sign > 0))
            fail_msg("triangle %zu (%u %u %u) has orientation %g", t, v[0], v[1], v[2], o);
        double tri[6] = {xy[2 * v[0]], xy[2 * v[0] + 1], xy[2 * v[1]],
                         xy[2 * v[1] + 1], xy[2 * v[2]], xy[2 * v[2] + 1]};
        area += shoelace(3, tri);
    }
    /* sides once in polygon order; diagonals once each way */
    for (size_t a = 0; a < n; ++a)
        for (size_t b = 0; b < n; ++b) {
            int u = use[a * n + b];
            assert_true(u <= 1);
            if (b == (a + 1) % n)
                assert_int_equal(u, 1);
            else if (a == (b + 1) % n)
                assert_int_equal(u, 0);
            else
                assert_int_equal(u, use[b * n + a]);
        }
    free(use);
    double want = shoelace(n, xy);
    if (!(fabs(area - want) <= 1e-12 * fabs(want)))
        fail_msg("area %.17g want %.17g", area, want);
}

/* Triangulate a polygon given in 2D (embedded as z = 0) and check. */
static void tri2d(size_t n, const double *xy, int sign)
{
    double *p = malloc(3 * n * sizeof(double));
    uint32_t *t = malloc(3 * (n - 2) * sizeof(uint32_t));
    for (size_t i = 0; i < n; ++i) {
        p[3 * i] = xy[2 * i];
        p[3 * i + 1] = xy[2 * i + 1];
        p[3 * i + 2] = 0;
    }
    assert_int_equal(geom_polygon_triangulate(n, p, t), GEOM_OK);
    check_triangulation(n, xy, t, sign);
    free(p);
    free(t);
}

/* The comb of K teeth: 4K vertices (tests/bench/triangulate_shapes.h). */
static size_t comb(int K, double *xy)
{
    return ts_comb(4 * (size_t)K, xy, 0);
}

static size_t spiral(int M, double *xy)
{
    /* a two-turn arm of width 0.8 around r = 1 + theta/pi */
    size_t n = 0;
    double T = 4 * PI;
    for (int i = 0; i < M; ++i) {
        double th = T * i / (M - 1), r = 1 + th / PI + 0.4;
        xy[2 * n] = r * cos(th);
        xy[2 * n + 1] = r * sin(th);
        ++n;
    }
    for (int i = M - 1; i >= 0; --i) {
        double th = T * i / (M - 1), r = 1 + th / PI - 0.4;
        xy[2 * n] = r * cos(th);
        xy[2 * n + 1] = r * sin(th);
        ++n;
    }
    return n;
}

static void test_convex(void **state)
{
    (void)state;
    double xy[2 * 40];
    for (size_t n = 3; n <= 40; ++n) {
        for (size_t i = 0; i < n; ++i) {
            xy[2 * i] = cos(2 * PI * (double)i / (double)n);
            xy[2 * i + 1] = sin(2 * PI * (double)i / (double)n);
        }
        tri2d(n, xy, 1);
    }
}

static void test_nonconvex(void **state)
{
    (void)state;
    double xy[2 * 400];
    for (int K = 1; K <= 12; ++K) {
        size_t n = comb(K, xy);
        assert_true(fabs(shoelace(n, xy) - (4 * K - 1)) < 1e-12);
        tri2d(n, xy, 1);
    }
    size_t n = spiral(60, xy);
    assert_true(shoelace(n, xy) > 0);
    tri2d(n, xy, 1);
    /* an L-shape and an arrow */
    double L[12] = {0, 0, 2, 0, 2, 1, 1, 1, 1, 2, 0, 2};
    tri2d(6, L, 1);
    double arrow[8] = {0, 0, 2, 1, 0, 2, 0.5, 1};
    tri2d(4, arrow, 1);
}

static void test_clockwise(void **state)
{
    (void)state;
    double xy[2 * 100], rv[2 * 100];
    size_t n = comb(5, xy);
    for (size_t i = 0; i < n; ++i) {
        rv[2 * i] = xy[2 * (n - 1 - i)];
        rv[2 * i + 1] = xy[2 * (n - 1 - i) + 1];
    }
    assert_true(shoelace(n, rv) < 0);
    tri2d(n, rv, -1);
}

static void test_collinear(void **state)
{
    (void)state;
    /* a 3x3 square with two extra points on every side */
    double sq[24] = {0, 0, 1, 0, 2, 0, 3, 0, 3, 1, 3, 2, 3, 3, 2, 3, 1, 3, 0, 3, 0, 2, 0, 1};
    tri2d(12, sq, 1);
    /* many points on one side only: every triangle must use the far corner */
    double fan[2 * 12];
    for (int i = 0; i < 10; ++i) {
        fan[2 * i] = i;
        fan[2 * i + 1] = 0;
    }
    fan[20] = 9;
    fan[21] = 1;
    fan[22] = 0;
    fan[23] = 1;
    tri2d(12, fan, 1);
    /* the comb with midpoints inserted on every side */
    double c[2 * 100], cm[2 * 200];
    size_t n = comb(4, c), k = 0;
    for (size_t i = 0; i < n; ++i) {
        size_t j = (i + 1) % n;
        cm[2 * k] = c[2 * i];
        cm[2 * k + 1] = c[2 * i + 1];
        cm[2 * k + 2] = 0.5 * (c[2 * i] + c[2 * j]);
        cm[2 * k + 3] = 0.5 * (c[2 * i + 1] + c[2 * j + 1]);
        k += 2;
    }
    tri2d(k, cm, 1);
}

static void test_rotated_3d(void **state)
{
    (void)state;
    double xy[2 * 200];
    size_t sizes[3];
    double polys[3][2 * 200];
    sizes[0] = comb(6, polys[0]);
    sizes[1] = spiral(40, polys[1]);
    double sq[24] = {0, 0, 1, 0, 2, 0, 3, 0, 3, 1, 3, 2, 3, 3, 2, 3, 1, 3, 0, 3, 0, 2, 0, 1};
    memcpy(polys[2], sq, sizeof sq);
    sizes[2] = 12;
    /* rotations about several axes, with an offset */
    double axes[4][3] = {{1, 2, 3}, {0, 1, 0}, {1, 0, 0}, {-3, 0.5, 0.25}};
    double angles[4] = {0.7, 2.5, -1.2, 4.0};
    for (int p = 0; p < 3; ++p)
        for (int a = 0; a < 4; ++a) {
            size_t n = sizes[p];
            memcpy(xy, polys[p], 2 * n * sizeof(double));
            geom_mat4 R;
            double *ax = axes[a];
            assert_int_equal(geom_mat4_rotate(geom_vec3_make(ax[0], ax[1], ax[2]), angles[a], &R),
                             GEOM_OK);
            double *pts = malloc(3 * n * sizeof(double));
            uint32_t *t = malloc(3 * (n - 2) * sizeof(uint32_t));
            for (size_t i = 0; i < n; ++i) {
                geom_vec3 q = geom_mat4_transform_dir(R, geom_vec3_make(xy[2 * i], xy[2 * i + 1], 0));
                pts[3 * i] = q.x + 10;
                pts[3 * i + 1] = q.y - 7;
                pts[3 * i + 2] = q.z + 3;
            }
            assert_int_equal(geom_polygon_triangulate(n, pts, t), GEOM_OK);
            check_triangulation(n, xy, t, 1);
            free(pts);
            free(t);
        }
}

static void test_degenerate_input(void **state)
{
    (void)state;
    double line[12] = {0, 0, 0, 1, 1, 1, 2, 2, 2, 3, 3, 3};
    uint32_t t[6];
    assert_int_equal(geom_polygon_triangulate(4, line, t), GEOM_ERR_DEGENERATE);
    uint32_t fan[6] = {0, 1, 2, 0, 2, 3};
    assert_memory_equal(t, fan, sizeof fan);
    assert_int_equal(geom_polygon_triangulate(2, line, t), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_polygon_triangulate(3, NULL, t), GEOM_ERR_INVALID_ARG);
    double nan[9] = {0, 0, 0, 1, 0, 0, 0, NAN, 0};
    assert_int_equal(geom_polygon_triangulate(3, nan, t), GEOM_ERR_INVALID_ARG);
    /* a triangle is itself */
    double tri[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    assert_int_equal(geom_polygon_triangulate(3, tri, t), GEOM_OK);
    assert_true(t[0] == 0 && t[1] == 1 && t[2] == 2);
}

static void assert_valid(const geom_mesh *m)
{
    size_t n = 99;
    assert_int_equal(geom_mesh_validate(m, NULL, 0, &n), GEOM_OK);
    assert_int_equal(n, 0);
}

static void newell(const geom_mesh *m, uint32_t f, double nrm[3])
{
    const double *p = geom_mesh_cpositions(m);
    nrm[0] = nrm[1] = nrm[2] = 0;
    uint32_t h0 = geom_mesh_face_he(m, f), h = h0;
    do {
        const double *a = p + 3 * geom_mesh_he_vertex(m, h);
        const double *b = p + 3 * geom_mesh_he_vertex(m, geom_mesh_he_next(m, h));
        nrm[0] += (a[1] - b[1]) * (a[2] + b[2]);
        nrm[1] += (a[2] - b[2]) * (a[0] + b[0]);
        nrm[2] += (a[0] - b[0]) * (a[1] + b[1]);
        h = geom_mesh_he_next(m, h);
    } while (h != h0);
}

static void test_mesh_triangulate(void **state)
{
    (void)state;
    /* a box 2 x 1 x 1, outward polygons: the top split into an L-hexagon
     * (reflex at 9) and a quad, the front and bottom with collinear
     * vertices (11 and 8 on edge midpoints), the right side a pentagon */
    double xyz[] = {0, 0, 0, 2, 0, 0, 2, 1, 0, 0, 1, 0,      /* 0-3 bottom corners */
                    0, 0, 1, 2, 0, 1, 2, 1, 1, 0, 1, 1,      /* 4-7 top corners */
                    1, 0, 1, 1, 0.5, 1, 2, 0.5, 1, 1, 0, 0}; /* 8-11 */
    uint32_t sizes_f[] = {5, 6, 4, 6, 5, 4, 4};
    uint32_t idx_f[] = {0, 3, 2, 1, 11,    /* bottom z = 0 */
                        4, 8, 9, 10, 6, 7, /* top hexagon */
                        8, 5, 10, 9,       /* top quad */
                        0, 11, 1, 5, 8, 4, /* front y = 0 */
                        1, 2, 6, 10, 5,    /* right x = 2 */
                        2, 3, 7, 6,        /* back y = 1 */
                        3, 0, 4, 7};       /* left x = 0 */
    geom_mesh *m = geom_mesh_create(NULL);
    geom_mesh_build_report r;
    assert_int_equal(geom_mesh_build(m, 12, xyz, 7, sizes_f, idx_f, NULL, &r, NULL), GEOM_OK);
    assert_int_equal(r.flipped_faces + r.nonmanifold_edges + r.added_vertices, 0);
    assert_valid(m);
    geom_mesh_topology t0;
    assert_int_equal(geom_mesh_topology_summary(m, &t0), GEOM_OK);
    assert_int_equal(t0.euler, 2);
    size_t nf0 = geom_mesh_n_faces(m);
    double n0[7][3];
    for (uint32_t f = 0; f < nf0; ++f)
        newell(m, f, n0[f]);
    /* face channel, groups and a corner channel (face, vertex) per corner */
    uint32_t fch, cch, g0, g1;
    assert_int_equal(geom_mesh_channel_add(m, "id", GEOM_MESH_DOMAIN_FACE, 2, &fch), GEOM_OK);
    assert_int_equal(geom_mesh_channel_add(m, "fv", GEOM_MESH_DOMAIN_CORNER, 2, &cch), GEOM_OK);
    double *fd = geom_mesh_channel_data(m, fch);
    for (uint32_t f = 0; f < nf0; ++f) {
        fd[2 * f] = f;
        fd[2 * f + 1] = 10.0 * f;
    }
    geom_mesh_group ga = {"a", NULL, NULL, NULL}, gb = {"b", NULL, "mat", NULL};
    assert_int_equal(geom_mesh_group_add(m, &ga, &g0), GEOM_OK);
    assert_int_equal(geom_mesh_group_add(m, &gb, &g1), GEOM_OK);
    uint32_t *fg = geom_mesh_face_groups(m);
    for (uint32_t f = 0; f < nf0; ++f)
        fg[f] = f % 2 ? g1 : g0;
    size_t ncorner = 0;
    for (uint32_t h = 0; h < geom_mesh_n_halfedges(m); ++h)
        ncorner += !geom_mesh_he_is_boundary(m, h);
    assert_int_equal(geom_mesh_corner_pool_resize(m, cch, ncorner), GEOM_OK);
    uint32_t *ci = geom_mesh_corner_indices(m, cch);
    double *cd = geom_mesh_channel_data(m, cch);
    uint32_t k = 0;
    for (uint32_t h = 0; h < geom_mesh_n_halfedges(m); ++h) {
        if (geom_mesh_he_is_boundary(m, h))
            continue;
        ci[h] = k;
        cd[2 * k] = geom_mesh_he_face(m, h);
        cd[2 * k + 1] = geom_mesh_he_vertex(m, h);
        ++k;
    }

    size_t added = 0;
    assert_int_equal(geom_mesh_triangulate(m, &added), GEOM_OK);
    /* sum over faces of (n - 3): 2 + 3 + 1 + 3 + 2 + 1 + 1 */
    assert_int_equal(added, 13);
    assert_int_equal(geom_mesh_n_faces(m), nf0 + 13);
    assert_valid(m);
    geom_mesh_topology t1;
    assert_int_equal(geom_mesh_topology_summary(m, &t1), GEOM_OK);
    assert_int_equal(t1.euler, 2);
    assert_true(t1.closed);
    const uint32_t *fo = geom_mesh_face_origin(m);
    fd = geom_mesh_channel_data(m, fch);
    fg = geom_mesh_face_groups(m);
    ci = geom_mesh_corner_indices(m, cch);
    cd = geom_mesh_channel_data(m, cch);
    double area[7] = {0};
    const double *p = geom_mesh_cpositions(m);
    for (uint32_t f = 0; f < geom_mesh_n_faces(m); ++f) {
        assert_int_equal(geom_mesh_face_valence(m, f), 3);
        /* which original face: the corner data says */
        uint32_t h = geom_mesh_face_he(m, f);
        uint32_t src = (uint32_t)cd[2 * ci[h]];
        assert_true(src < nf0);
        assert_int_equal(fo[f], src); /* build's face origin is the identity here */
        assert_true(fd[2 * f] == src && fd[2 * f + 1] == 10.0 * src);
        assert_int_equal(fg[f], src % 2 ? g1 : g0);
        for (int j = 0; j < 3; ++j, h = geom_mesh_he_next(m, h)) {
            assert_true(cd[2 * ci[h]] == src);
            assert_true(cd[2 * ci[h] + 1] == geom_mesh_he_vertex(m, h));
        }
        /* same orientation as the polygon it came from */
        double nt[3];
        newell(m, f, nt);
        double dot = nt[0] * n0[src][0] + nt[1] * n0[src][1] + nt[2] * n0[src][2];
        assert_true(dot > 0);
        area[src] += 0.5 * sqrt(nt[0] * nt[0] + nt[1] * nt[1] + nt[2] * nt[2]);
    }
    for (uint32_t f = 0; f < nf0; ++f) {
        double want = 0.5 * sqrt(n0[f][0] * n0[f][0] + n0[f][1] * n0[f][1] + n0[f][2] * n0[f][2]);
        assert_true(fabs(area[f] - want) < 1e-14);
    }
    assert_true(p == geom_mesh_cpositions(m));
    /* triangulating again does nothing */
    assert_int_equal(geom_mesh_triangulate(m, &added), GEOM_OK);
    assert_int_equal(added, 0);
    geom_mesh_destroy(m);
}

/* ---------------------------------------------------------- large polygons */

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

static int has_edge(const uint64_t *keys, size_t m, uint32_t a, uint32_t b)
{
    uint64_t k = (uint64_t)a << 32 | b;
    return bsearch(&k, keys, m, sizeof k, cmp_u64) != NULL;
}

/* Neumaier-compensated sum step. */
static void nsum(double *s, double *c, double x)
{
    double t = *s + x;
    *c += fabs(*s) >= fabs(x) ? (*s - t) + x : (x - t) + *s;
    *s = t;
}

/* check_triangulation for large n (counter-clockwise): n-2 triangles, all
 * positively oriented by the exact predicate, every directed edge used at
 * most once, every side once in polygon order and never reversed, every
 * diagonal once each way, and the areas sum to the polygon's (compensated
 * sums). */
static void check_large(size_t n, const double *xy, const uint32_t *tris)
{
    if (n < 3 || n > 1000000) {
        fail_msg("n = %zu", n);
        return;
    }
    size_t m = 3 * (n - 2);
    uint64_t *keys = malloc(m * sizeof(uint64_t));
    assert_non_null(keys);
    double as = 0, ac = 0;
    for (size_t t = 0; t < n - 2; ++t) {
        const uint32_t *v = tris + 3 * t;
        for (int k = 0; k < 3; ++k) {
            assert_true(v[k] < n);
            keys[3 * t + (size_t)k] = (uint64_t)v[k] << 32 | v[(k + 1) % 3];
        }
        double o = geom_orient2d(xy + 2 * v[0], xy + 2 * v[1], xy + 2 * v[2]);
        if (!(o > 0))
            fail_msg("triangle %zu (%u %u %u) has orientation %g", t, v[0], v[1], v[2], o);
        nsum(&as, &ac, 0.5 * o);
    }
    qsort(keys, m, sizeof(uint64_t), cmp_u64);
    for (size_t k = 1; k < m; ++k)
        assert_true(keys[k] != keys[k - 1]);
    for (size_t k = 0; k < m; ++k) {
        uint32_t a = (uint32_t)(keys[k] >> 32), b = (uint32_t)keys[k];
        if (b == (a + 1) % n)
            continue;
        assert_false(a == (b + 1) % n); /* a side used backwards */
        assert_true(has_edge(keys, m, b, a)); /* diagonals: both ways */
    }
    for (size_t a = 0; a < n; ++a)
        assert_true(has_edge(keys, m, (uint32_t)a, (uint32_t)((a + 1) % n)));
    free(keys);
    double ps = 0, pc = 0;
    for (size_t i = 0; i < n; ++i) {
        size_t j = (i + 1) % n;
        nsum(&ps, &pc, 0.5 * xy[2 * i] * xy[2 * j + 1]);
        nsum(&ps, &pc, -0.5 * xy[2 * j] * xy[2 * i + 1]);
    }
    double area = as + ac, want = ps + pc;
    if (!(fabs(area - want) <= 1e-12 * fabs(want)))
        fail_msg("area %.17g want %.17g", area, want);
}

static void tri2d_large(size_t n, const double *xy)
{
    if (n < 3 || n > 1000000) {
        fail_msg("n = %zu", n);
        return;
    }
    double *p = malloc(3 * n * sizeof(double));
    uint32_t *t = malloc(3 * n * sizeof(uint32_t));
    assert_non_null(p);
    assert_non_null(t);
    for (size_t i = 0; i < n; ++i) {
        p[3 * i] = xy[2 * i];
        p[3 * i + 1] = xy[2 * i + 1];
        p[3 * i + 2] = 0;
    }
    assert_int_equal(geom_polygon_triangulate(n, p, t), GEOM_OK);
    check_large(n, xy, t);
    free(p);
    free(t);
}

static uint64_t lcg(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return *s >> 11;
}

/* Star-shaped around the origin: n angles (equal steps, or jittered within
 * their step) and radii uniform in [rmin, 1]. */
static void star(size_t n, double rmin, int jitter, uint64_t seed, double *xy)
{
    for (size_t i = 0; i < n; ++i) {
        double u = (double)lcg(&seed) * 0x1p-53, w = (double)lcg(&seed) * 0x1p-53;
        double th = 2 * PI * ((double)i + (jitter ? 0.98 * w : 0.0)) / (double)n;
        double r = rmin + (1 - rmin) * u;
        xy[2 * i] = r * cos(th);
        xy[2 * i + 1] = r * sin(th);
    }
}

/* Triangulations of random and structured simple polygons up to 100k
 * vertices, checked exactly. The quadratic ear clipper took about 94 s on
 * one 100k-vertex polygon; this whole test takes well under a second when
 * the emptiness tests are local (they are grid-bounded), so a regression to
 * quadratic time shows up as a ctest timeout rather than a timing
 * assertion. */
static void test_large(void **state)
{
    (void)state;
    size_t nmax = 100000;
    double *xy = malloc(2 * nmax * sizeof(double));
    static const size_t sizes[] = {65, 100, 1000, 10007, 100000};
    for (size_t s = 0; s < sizeof sizes / sizeof *sizes; ++s) {
        star(sizes[s], 0.2, 0, 1 + s, xy);
        tri2d_large(sizes[s], xy);
        star(sizes[s], 0.01, 1, 100 + s, xy);
        tri2d_large(sizes[s], xy);
        star(sizes[s], 0.999, 1, 200 + s, xy); /* nearly a circle */
        tri2d_large(sizes[s], xy);
    }
    /* comb: n = 4K - 2 (long thin teeth: big ear bounding boxes) */
    size_t n = comb(25000, xy);
    assert_true(n <= nmax);
    tri2d_large(n, xy);
    n = comb(200, xy);
    tri2d_large(n, xy);
    /* spiral arm: n = 2M */
    n = spiral(50000, xy);
    tri2d_large(n, xy);
    n = spiral(1000, xy);
    tri2d_large(n, xy);
    /* an integer-grid staircase with collinear runs: exact predicate on
     * collinear vertices in a large polygon */
    n = 0;
    for (int k = 0; k < 20000; ++k) { /* up the stairs, 2 collinear points per tread */
        xy[2 * n] = k, xy[2 * n + 1] = k, ++n;
        xy[2 * n] = k + 0.5, xy[2 * n + 1] = k, ++n;
    }
    for (int x = 20000; x >= 0; --x) /* a collinear top side */
        xy[2 * n] = x, xy[2 * n + 1] = 20000, ++n;
    tri2d_large(n, xy);
    free(xy);
}

/* Non-simple and degenerate input above the grid threshold (random points,
 * points on a 4x4 integer grid with duplicates, all vertices on one line, a
 * circle offset by 1e8 with 1e-12-thin spikes): the fallbacks still write
 * n-2 triangles with valid, distinct corners, every side used once. */
static void test_large_degenerate(void **state)
{
    (void)state;
    uint64_t s = 7;
    for (int it = 0; it < 80; ++it) {
        size_t n = 65 + (size_t)(it * 37 % 300);
        double *p = malloc(3 * n * sizeof(double));
        uint32_t *t = malloc(3 * n * sizeof(uint32_t));
        assert_non_null(p);
        assert_non_null(t);
        int mode = it % 4;
        for (size_t i = 0; i < n; ++i) {
            double u = (double)lcg(&s) * 0x1p-53, w = (double)lcg(&s) * 0x1p-53;
            double th = 2 * PI * (double)i / (double)n;
            double x = cos(th) + 1e8, y = sin(th) * (i % 3 ? 1 : 1e-12);
            if (mode == 0)
                x = u, y = w;
            else if (mode == 1)
                x = floor(4 * u), y = floor(4 * w);
            else if (mode == 2)
                x = (double)(i % 7), y = 2.0 * (double)(i % 7);
            p[3 * i] = x;
            p[3 * i + 1] = y;
            p[3 * i + 2] = 0;
        }
        geom_status st = geom_polygon_triangulate(n, p, t);
        assert_true(st == GEOM_OK || st == GEOM_ERR_DEGENERATE);
        size_t sides = 0;
        for (size_t k = 0; k < n - 2; ++k) {
            const uint32_t *v = t + 3 * k;
            assert_true(v[0] < n && v[1] < n && v[2] < n);
            assert_true(v[0] != v[1] && v[1] != v[2] && v[0] != v[2]);
            for (int j = 0; j < 3; ++j)
                sides += v[(j + 1) % 3] == (v[j] + 1) % n;
        }
        assert_int_equal(sides, n);
        free(p);
        free(t);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_convex),          cmocka_unit_test(test_nonconvex),
        cmocka_unit_test(test_clockwise),       cmocka_unit_test(test_collinear),
        cmocka_unit_test(test_rotated_3d),      cmocka_unit_test(test_degenerate_input),
        cmocka_unit_test(test_mesh_triangulate), cmocka_unit_test(test_large),
        cmocka_unit_test(test_large_degenerate),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
