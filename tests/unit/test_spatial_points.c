/*
 * Point queries (kNN, radius, box) of the kd-tree and the quadtree/octree
 * (plain and 2:1 balanced)
 * against a brute-force scan, on random, clustered, duplicated, grid-aligned
 * (many equal distances: the tie order by index is checked) and 1e8-offset
 * points, in 2D and 3D; same answers for 1 and several threads; a point at
 * exactly the radius is inside; NaN/Inf rejected with the index.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "geom/spatial.h"

static uint64_t rng_state = 0x2545f4914f6cdd1dull;
static double urand(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) * 0x1p-53;
}

enum { RANDOM, CLUSTERED, DUPLICATED, GRID, OFFSET, NKINDS };
static const char *kind_name[] = {"random", "clustered", "duplicated", "grid", "offset"};

static double *make_points(int kind, size_t n, int dim)
{
    double *p = malloc((size_t)dim * n * sizeof *p);
    for (size_t i = 0; i < n; i++)
        for (int k = 0; k < dim; k++) {
            double v;
            switch (kind) {
            case CLUSTERED: v = (double)(i % 7) + 1e-4 * urand(); break;
            case DUPLICATED: v = (double)((i * 7919) % 13) * 0.125; break;
            case GRID: v = (double)((i / (k == 0 ? 1 : k == 1 ? 10 : 100)) % 10); break;
            case OFFSET: v = 1e8 + urand(); break;
            default: v = urand(); break;
            }
            p[(size_t)dim * i + (size_t)k] = v;
        }
    return p;
}

static double *make_queries(int kind, size_t nq, int dim)
{
    double *q = malloc((size_t)dim * nq * sizeof *q);
    for (size_t i = 0; i < nq; i++)
        for (int k = 0; k < dim; k++) {
            double v = urand();
            if (kind == GRID)
                v = (double)(int)(v * 12) - 1 + (i % 3 == 0 ? 0.5 : 0.0); /* on grid points and midpoints */
            else if (kind == OFFSET)
                v = 1e8 + v;
            else if (kind == CLUSTERED)
                v = (double)(i % 7) + 1e-4 * v;
            else if (kind == DUPLICATED)
                v = (double)(int)(v * 14) * 0.125;
            q[(size_t)dim * i + (size_t)k] = v;
        }
    return q;
}

typedef struct bf {
    double d2;
    uint32_t i;
} bf;

static int bf_cmp(const void *pa, const void *pb)
{
    const bf *a = pa, *b = pb;
    if (a->d2 != b->d2)
        return a->d2 < b->d2 ? -1 : 1;
    return (a->i > b->i) - (a->i < b->i);
}

static double dist2(const double *p, const double *q, int dim)
{
    double dx = p[0] - q[0], dy = p[1] - q[1], dz = dim == 3 ? p[2] - q[2] : 0.0;
    return dx * dx + dy * dy + dz * dz;
}

/* Brute force: all points sorted by (d2, index). */
static bf *brute(const double *pts, size_t n, const double *q, int dim)
{
    bf *v = malloc((n ? n : 1) * sizeof *v);
    for (size_t i = 0; i < n; i++) {
        v[i].d2 = dist2(pts + (size_t)dim * i, q, dim);
        v[i].i = (uint32_t)i;
    }
    qsort(v, n, sizeof *v, bf_cmp);
    return v;
}

/* Query interface over the two structures. */
typedef struct index_ops {
    const char *name;
    geom_status (*knn)(const void *t, const double *q, size_t nq, size_t k, uint32_t *idx,
                       double *d, int threads);
    geom_status (*radius)(const void *t, const double *q, size_t nq, double r, geom_neighbors *out,
                          int threads);
    geom_status (*box)(const void *t, const double *lo, const double *hi, geom_neighbors *out);
} index_ops;

static geom_status kd_knn(const void *t, const double *q, size_t nq, size_t k, uint32_t *idx,
                          double *d, int threads)
{
    return geom_kdtree_knn(t, q, nq, k, idx, d, threads, NULL);
}
static geom_status kd_radius(const void *t, const double *q, size_t nq, double r,
                             geom_neighbors *out, int threads)
{
    return geom_kdtree_radius(t, q, nq, r, out, threads, NULL);
}
static geom_status kd_box(const void *t, const double *lo, const double *hi, geom_neighbors *out)
{
    return geom_kdtree_box(t, lo, hi, out);
}
static const index_ops kd_ops = {"kdtree", kd_knn, kd_radius, kd_box};

static geom_status oc_knn(const void *t, const double *q, size_t nq, size_t k, uint32_t *idx,
                          double *d, int threads)
{
    return geom_octree_knn(t, q, nq, k, idx, d, threads, NULL);
}
static geom_status oc_radius(const void *t, const double *q, size_t nq, double r,
                             geom_neighbors *out, int threads)
{
    return geom_octree_radius(t, q, nq, r, out, threads, NULL);
}
static geom_status oc_box(const void *t, const double *lo, const double *hi, geom_neighbors *out)
{
    return geom_octree_box(t, lo, hi, out);
}
static const index_ops oc_ops = {"octree", oc_knn, oc_radius, oc_box};

static void check_queries(const index_ops *ops, const void *t, const double *pts, size_t n,
                          int dim, int kind)
{
    size_t nq = 60;
    double *q = make_queries(kind, nq, dim);
    /* a query exactly at a data point */
    memcpy(q, pts + (size_t)dim * (n / 2), (size_t)dim * sizeof *q);
    bf **bfs = malloc(nq * sizeof *bfs);
    for (size_t j = 0; j < nq; j++)
        bfs[j] = brute(pts, n, q + (size_t)dim * j, dim);
    const size_t ks[] = {1, 8, 17};
    for (size_t ki = 0; ki < 3; ki++) {
        size_t k = ks[ki];
        uint32_t *idx = malloc(nq * k * sizeof *idx), *idx2 = malloc(nq * k * sizeof *idx2);
        double *d = malloc(nq * k * sizeof *d), *dd2 = malloc(nq * k * sizeof *dd2);
        assert_int_equal(ops->knn(t, q, nq, k, idx, d, 1), GEOM_OK);
        assert_int_equal(ops->knn(t, q, nq, k, idx2, dd2, 2), GEOM_OK);
        assert_memory_equal(idx, idx2, nq * k * sizeof *idx);
        assert_memory_equal(d, dd2, nq * k * sizeof *d);
        for (size_t j = 0; j < nq; j++) {
            bf *v = bfs[j];
            for (size_t m = 0; m < k; m++) {
                if (m < n) {
                    if (idx[j * k + m] != v[m].i)
                        fail_msg("%s %s dim %d k %zu query %zu rank %zu: got %u want %u", ops->name,
                                 kind_name[kind], dim, k, j, m, idx[j * k + m], v[m].i);
                    assert_true(d[j * k + m] == sqrt(v[m].d2));
                } else {
                    assert_int_equal(idx[j * k + m], GEOM_INVALID_INDEX);
                    assert_true(isinf(d[j * k + m]));
                }
            }
        }
        free(idx);
        free(idx2);
        free(d);
        free(dd2);
    }
    /* Radius: include a radius equal to a realised distance (inclusive). */
    for (int ri = 0; ri < 3; ri++) {
        geom_neighbors a = {0}, b = {0};
        double r = ri == 0 ? 0.0 : ri == 1 ? 0.15 : 1.0;
        if (ri == 1) {
            r = sqrt(bfs[0][n > 5 ? 5 : 0].d2); /* exactly the 6th distance of query 0 */
        }
        assert_int_equal(ops->radius(t, q, nq, r, &a, 1), GEOM_OK);
        assert_int_equal(ops->radius(t, q, nq, r, &b, 3), GEOM_OK);
        assert_int_equal(a.query_count, nq);
        assert_memory_equal(a.offsets, b.offsets, (nq + 1) * sizeof *a.offsets);
        size_t tot = a.offsets[nq];
        if (tot) {
            assert_memory_equal(a.index, b.index, tot * sizeof *a.index);
            assert_memory_equal(a.distance, b.distance, tot * sizeof *a.distance);
        }
        for (size_t j = 0; j < nq; j++) {
            bf *v = bfs[j];
            size_t m = 0;
            while (m < n && sqrt(v[m].d2) <= r)
                m++;
            if (a.offsets[j + 1] - a.offsets[j] != m)
                fail_msg("%s %s dim %d radius %.17g query %zu: %zu hits, want %zu", ops->name,
                         kind_name[kind], dim, r, j, a.offsets[j + 1] - a.offsets[j], m);
            for (size_t x = 0; x < m; x++) {
                assert_int_equal(a.index[a.offsets[j] + x], v[x].i);
                assert_true(a.distance[a.offsets[j] + x] == sqrt(v[x].d2));
            }
            if (ri == 1 && j == 0 && n > 5)
                assert_true(m >= 6);
        }
        geom_neighbors_free(&a);
        geom_neighbors_free(&b);
    }
    /* Box: boundary included, index order. */
    for (int bi = 0; bi < 4; bi++) {
        double lo[3], hi[3];
        for (int k = 0; k < dim; k++) {
            double a0 = pts[(size_t)dim * ((size_t)bi * 7 % n) + (size_t)k];
            double a1 = pts[(size_t)dim * ((size_t)bi * 13 % n) + (size_t)k];
            lo[k] = a0 < a1 ? a0 : a1;
            hi[k] = a0 < a1 ? a1 : a0;
            if (bi == 3)
                hi[k] = lo[k] - 1; /* empty */
        }
        geom_neighbors out = {0};
        assert_int_equal(ops->box(t, lo, hi, &out), GEOM_OK);
        size_t m = 0;
        for (size_t i = 0; i < n; i++) {
            int in = 1;
            for (int k = 0; k < dim; k++)
                in &= pts[(size_t)dim * i + (size_t)k] >= lo[k] && pts[(size_t)dim * i + (size_t)k] <= hi[k];
            if (in) {
                assert_true(m < out.offsets[1]);
                assert_int_equal(out.index[m], i);
                m++;
            }
        }
        assert_int_equal(out.offsets[1], m);
        if (bi == 0)
            assert_true(m >= 1); /* the corners are data points */
        geom_neighbors_free(&out);
    }
    for (size_t j = 0; j < nq; j++)
        free(bfs[j]);
    free(bfs);
    free(q);
}

static void run_kdtree(int dim, int kind, size_t n)
{
    double *pts = make_points(kind, n, dim);
    geom_kdtree *t = NULL, *t2 = NULL;
    geom_kdtree_options o = {0};
    o.threads = 1;
    assert_int_equal(geom_kdtree_build(pts, n, dim, &o, &t, NULL), GEOM_OK);
    o.threads = 4;
    o.leaf_size = 3;
    assert_int_equal(geom_kdtree_build(pts, n, dim, &o, &t2, NULL), GEOM_OK);
    assert_true(geom_kdtree_depth(t) >= 1);
    assert_true(geom_kdtree_bytes(t) > n * 3 * sizeof(double));
    check_queries(&kd_ops, t, pts, n, dim, kind);
    check_queries(&kd_ops, t2, pts, n, dim, kind);
    geom_kdtree_destroy(t);
    geom_kdtree_destroy(t2);
    free(pts);
}

static void test_kdtree(void **st)
{
    (void)st;
    for (int dim = 2; dim <= 3; dim++)
        for (int kind = 0; kind < NKINDS; kind++) {
            run_kdtree(dim, kind, 3000);
            run_kdtree(dim, kind, 10000);
        }
    run_kdtree(3, RANDOM, 5);
    run_kdtree(2, RANDOM, 1);
}

static void run_octree(int dim, int kind, size_t n, int balance)
{
    double *pts = make_points(kind, n, dim);
    geom_octree *t = NULL;
    geom_octree_options o = {0};
    o.balance = balance;
    o.bucket_size = balance ? 4 : 0;
    assert_int_equal(geom_octree_build_points(pts, n, dim, &o, &t, NULL), GEOM_OK);
    assert_int_equal(geom_octree_dim(t), dim);
    check_queries(&oc_ops, t, pts, n, dim, kind);
    geom_octree_destroy(t);
    free(pts);
}

static void test_octree(void **st)
{
    (void)st;
    for (int dim = 2; dim <= 3; dim++)
        for (int kind = 0; kind < NKINDS; kind++) {
            run_octree(dim, kind, 3000, 0);
            run_octree(dim, kind, 10000, 0);
            run_octree(dim, kind, 3000, 1);
        }
    run_octree(3, RANDOM, 5, 0);
    run_octree(2, RANDOM, 1, 0);
}

static void test_kdtree_edges(void **st)
{
    (void)st;
    geom_kdtree *t = NULL;
    geom_diag d;
    double p[9] = {0, 0, 0, 1, 1, 1, 2, NAN, 2};
    assert_int_equal(geom_kdtree_build(p, 3, 3, NULL, &t, &d), GEOM_ERR_INVALID_ARG);
    assert_null(t);
    assert_non_null(strstr(d.message, "point 2"));
    assert_int_equal(geom_kdtree_build(p, 2, 4, NULL, &t, &d), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_kdtree_build(p, 2, 3, NULL, &t, &d), GEOM_OK);
    double q[6] = {0, 0, 0, INFINITY, 0, 0};
    uint32_t idx[2];
    assert_int_equal(geom_kdtree_knn(t, q, 2, 1, idx, NULL, 0, &d), GEOM_ERR_INVALID_ARG);
    assert_non_null(strstr(d.message, "query 1"));
    geom_neighbors nb = {0};
    assert_int_equal(geom_kdtree_radius(t, q, 1, -1.0, &nb, 0, NULL), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_kdtree_radius(t, q, 1, NAN, &nb, 0, NULL), GEOM_ERR_INVALID_ARG);
    /* exactly at the radius: sqrt(3) from the origin */
    assert_int_equal(geom_kdtree_radius(t, q, 1, sqrt(3.0), &nb, 0, NULL), GEOM_OK);
    assert_int_equal(nb.offsets[1], 2);
    assert_int_equal(nb.index[1], 1);
    geom_neighbors_free(&nb);
    geom_neighbors_free(&nb);
    geom_kdtree_destroy(t);
    /* Empty tree. */
    assert_int_equal(geom_kdtree_build(NULL, 0, 3, NULL, &t, NULL), GEOM_OK);
    assert_int_equal(geom_kdtree_knn(t, q, 1, 2, idx, NULL, 0, NULL), GEOM_OK);
    assert_int_equal(idx[0], GEOM_INVALID_INDEX);
    assert_int_equal(geom_kdtree_radius(t, q, 1, 1.0, &nb, 0, NULL), GEOM_OK);
    assert_int_equal(nb.offsets[1], 0);
    geom_neighbors_free(&nb);
    geom_kdtree_destroy(t);
    geom_kdtree_destroy(NULL);
    /* A million copies of one point: depth stays log(n), answers by index. */
    size_t n = 1000000;
    double *same = malloc(3 * n * sizeof *same);
    for (size_t i = 0; i < 3 * n; i++)
        same[i] = 0.25;
    assert_int_equal(geom_kdtree_build(same, n, 3, NULL, &t, NULL), GEOM_OK);
    assert_true(geom_kdtree_depth(t) <= 20);
    uint32_t k8[8];
    assert_int_equal(geom_kdtree_knn(t, same, 1, 8, k8, NULL, 0, NULL), GEOM_OK);
    for (uint32_t i = 0; i < 8; i++)
        assert_int_equal(k8[i], i);
    geom_kdtree_destroy(t);
    free(same);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_kdtree),
        cmocka_unit_test(test_kdtree_edges),
        cmocka_unit_test(test_octree),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
