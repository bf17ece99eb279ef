/*
 * Quadtree/octree structure and element queries: every item in exactly one
 * node, children contiguous and inside their parent's cell, tight bounds,
 * depth within max_depth, a million coincident points in one leaf, points on
 * cell boundaries and 1e8 offsets, 2:1 balance checked on every pair of
 * adjacent leaves, the same tree for 1 and 4 threads; box, frustum and ray
 * queries on segments and triangles against brute force (ray order: entry
 * parameter, then index; a ray along a shared face misses nothing).
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

static uint64_t rng_state = 0x1d8e4e27c47d124full;
static double urand(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) * 0x1p-53;
}

static int box_in(geom_aabb in, geom_aabb out)
{
    return out.min.x <= in.min.x && out.min.y <= in.min.y && out.min.z <= in.min.z &&
           in.max.x <= out.max.x && in.max.y <= out.max.y && in.max.z <= out.max.z;
}

static void check_structure(const geom_octree *t, size_t n, uint32_t max_depth)
{
    size_t nn, ni;
    const geom_octree_node *nodes = geom_octree_nodes(t, &nn);
    const uint32_t *items = geom_octree_items(t, &ni);
    assert_int_equal(ni, n);
    if (!n)
        return;
    unsigned *seen = calloc(n, sizeof *seen);
    size_t owned = 0, maxlevel = 0;
    for (size_t i = 0; i < nn; i++) {
        const geom_octree_node *nd = &nodes[i];
        assert_true(nd->own_count <= nd->item_total);
        assert_true((size_t)nd->item_start + nd->item_total <= n);
        for (uint32_t k = 0; k < nd->own_count; k++)
            seen[items[nd->item_start + k]]++;
        owned += nd->own_count;
        if (nd->level > maxlevel)
            maxlevel = nd->level;
        assert_true(nd->level <= max_depth);
        if (nd->first_child != GEOM_INVALID_INDEX) {
            uint32_t nc = (uint32_t)__builtin_popcount(nd->child_mask);
            assert_true(nc >= 1 && nd->first_child > i && nd->first_child + nc <= nn);
            size_t start = nd->item_start + nd->own_count, total = nd->own_count;
            for (uint32_t k = 0; k < nc; k++) {
                const geom_octree_node *c = &nodes[nd->first_child + k];
                assert_int_equal(c->level, nd->level + 1);
                assert_int_equal(c->item_start, start);
                start += c->item_total;
                total += c->item_total;
                if (c->item_total)
                    assert_true(box_in(c->bounds, nd->bounds));
                /* child cell inside the parent's cell, half its size */
                assert_true(box_in(c->cell, nd->cell));
            }
            assert_int_equal(total, nd->item_total);
        } else {
            assert_int_equal(nd->own_count, nd->item_total);
        }
    }
    assert_int_equal(owned, n);
    for (size_t i = 0; i < n; i++)
        assert_int_equal(seen[i], 1);
    assert_int_equal(geom_octree_depth(t), maxlevel + 1);
    free(seen);
}

static void same_tree(const geom_octree *a, const geom_octree *b)
{
    size_t na, nb, ia, ib;
    const geom_octree_node *x = geom_octree_nodes(a, &na), *y = geom_octree_nodes(b, &nb);
    const uint32_t *u = geom_octree_items(a, &ia), *v = geom_octree_items(b, &ib);
    assert_int_equal(na, nb);
    assert_int_equal(ia, ib);
    assert_memory_equal(x, y, na * sizeof *x);
    assert_memory_equal(u, v, ia * sizeof *u);
}

static void test_points_structure(void **st)
{
    (void)st;
    size_t n = 200000;
    double *p = malloc(3 * n * sizeof *p);
    for (int kind = 0; kind < 3; kind++) {
        for (size_t i = 0; i < 3 * n; i++)
            p[i] = kind == 0 ? urand() : kind == 1 ? 1e8 + (double)(int)(urand() * 8) * 0.125 /* on cell boundaries */
                                                   : urand() * urand() * urand();
        geom_octree *a = NULL, *b = NULL;
        geom_octree_options o = {0};
        o.threads = 1;
        assert_int_equal(geom_octree_build_points(p, n, 3, &o, &a, NULL), GEOM_OK);
        o.threads = 4;
        assert_int_equal(geom_octree_build_points(p, n, 3, &o, &b, NULL), GEOM_OK);
        check_structure(a, n, 19);
        same_tree(a, b);
        geom_octree_destroy(a);
        geom_octree_destroy(b);
        o.max_depth = 4;
        assert_int_equal(geom_octree_build_points(p, n, 2, &o, &a, NULL), GEOM_OK);
        check_structure(a, n, 4);
        assert_true(geom_octree_depth(a) <= 5);
        geom_octree_destroy(a);
    }
    /* A million copies of one point: one leaf. */
    free(p);
    n = 1000000;
    p = malloc(3 * n * sizeof *p);
    for (size_t i = 0; i < 3 * n; i++)
        p[i] = 0.3;
    geom_octree *t = NULL;
    assert_int_equal(geom_octree_build_points(p, n, 3, NULL, &t, NULL), GEOM_OK);
    size_t nn;
    geom_octree_nodes(t, &nn);
    assert_int_equal(nn, 1);
    assert_int_equal(geom_octree_depth(t), 1);
    assert_true(geom_octree_bytes(t) < 64 * n);
    uint32_t k3[3];
    assert_int_equal(geom_octree_knn(t, p, 1, 3, k3, NULL, 0, NULL), GEOM_OK);
    assert_true(k3[0] == 0 && k3[1] == 1 && k3[2] == 2);
    geom_octree_destroy(t);
    /* Two clusters of coincident points plus one stray: bounded depth. */
    for (size_t i = 0; i < n; i++)
        p[3 * i] = i % 2 ? 0.3 : 0.3 + 1e-300;
    assert_int_equal(geom_octree_build_points(p, n, 3, NULL, &t, NULL), GEOM_OK);
    check_structure(t, n, 19);
    geom_octree_destroy(t);
    /* NaN. */
    p[3 * 17 + 1] = NAN;
    geom_diag d;
    assert_int_equal(geom_octree_build_points(p, n, 3, NULL, &t, &d), GEOM_ERR_INVALID_ARG);
    assert_non_null(strstr(d.message, "point 17"));
    free(p);
}

/* 2:1 balance: for every pair of leaves whose cells touch (share a face,
 * edge or corner), the levels differ by at most one. */
static void check_balance(const geom_octree *t)
{
    size_t nn;
    const geom_octree_node *nodes = geom_octree_nodes(t, &nn);
    size_t nl = 0;
    uint32_t *leaves = malloc(nn * sizeof *leaves);
    for (size_t i = 0; i < nn; i++)
        if (nodes[i].first_child == GEOM_INVALID_INDEX)
            leaves[nl++] = (uint32_t)i;
    for (size_t i = 0; i < nl; i++)
        for (size_t j = i + 1; j < nl; j++) {
            const geom_aabb a = nodes[leaves[i]].cell, b = nodes[leaves[j]].cell;
            int touch = a.min.x <= b.max.x && b.min.x <= a.max.x && a.min.y <= b.max.y &&
                        b.min.y <= a.max.y && a.min.z <= b.max.z && b.min.z <= a.max.z;
            if (touch) {
                int dl = (int)nodes[leaves[i]].level - (int)nodes[leaves[j]].level;
                if (dl > 1 || dl < -1)
                    fail_msg("leaves %u (level %u) and %u (level %u) touch", leaves[i],
                             nodes[leaves[i]].level, leaves[j], nodes[leaves[j]].level);
            }
        }
    free(leaves);
}

static void test_balance(void **st)
{
    (void)st;
    for (int dim = 2; dim <= 3; dim++) {
        /* A dense cluster in a corner and a few far points: deep leaves next
         * to shallow ones before balancing. */
        size_t n = 600;
        double *p = malloc((size_t)dim * n * sizeof *p);
        for (size_t i = 0; i < n; i++)
            for (int k = 0; k < dim; k++)
                p[(size_t)dim * i + (size_t)k] = i < n - 4 ? 1e-3 * urand() : urand();
        geom_octree_options o = {0};
        o.bucket_size = 2;
        o.balance = 1;
        geom_octree *t = NULL;
        assert_int_equal(geom_octree_build_points(p, n, dim, &o, &t, NULL), GEOM_OK);
        check_structure(t, n, dim == 3 ? 19 : 28);
        check_balance(t);
        size_t nn;
        const geom_octree_node *nodes = geom_octree_nodes(t, &nn);
        for (size_t i = 0; i < nn; i++)
            if (nodes[i].first_child != GEOM_INVALID_INDEX)
                assert_int_equal(nodes[i].child_mask, (1u << (1 << dim)) - 1);
        geom_octree_destroy(t);
        free(p);
    }
}

typedef struct elems {
    double *pos;
    uint32_t *idx;
    size_t nv, ne;
    int dim, per;
} elems;

static elems make_elems(int dim, size_t ne, int grid)
{
    elems e;
    e.dim = dim;
    e.per = dim == 2 ? 2 : 3;
    e.ne = ne;
    e.nv = (size_t)e.per * ne;
    e.pos = malloc((size_t)dim * e.nv * sizeof *e.pos);
    e.idx = malloc((size_t)e.per * ne * sizeof *e.idx);
    for (size_t i = 0; i < ne; i++) {
        double c[3];
        for (int k = 0; k < dim; k++)
            c[k] = grid ? (double)((i >> (3 * k)) & 7) * 0.125 : urand();
        for (int v = 0; v < e.per; v++) {
            for (int k = 0; k < dim; k++)
                e.pos[(size_t)dim * ((size_t)e.per * i + (size_t)v) + (size_t)k] =
                    grid ? c[k] + (v == k + 1 ? 0.125 : 0.0) : c[k] + (i % 50 == 0 ? 0.5 : 0.05) * (urand() - 0.5);
            e.idx[(size_t)e.per * i + (size_t)v] = (uint32_t)((size_t)e.per * i + (size_t)v);
        }
    }
    return e;
}

static void ebox(const elems *e, size_t i, double lo[3], double hi[3])
{
    for (int k = 0; k < 3; k++)
        lo[k] = INFINITY, hi[k] = -INFINITY;
    for (int v = 0; v < e->per; v++) {
        const double *p = e->pos + (size_t)e->dim * e->idx[(size_t)e->per * i + (size_t)v];
        for (int k = 0; k < 3; k++) {
            double x = k < e->dim ? p[k] : 0.0;
            lo[k] = fmin(lo[k], x);
            hi[k] = fmax(hi[k], x);
        }
    }
}

static void check_elems(int dim, int grid)
{
    elems e = make_elems(dim, 4000, grid);
    geom_octree *t = NULL;
    geom_status s = dim == 2 ? geom_octree_build_segments(e.pos, e.nv, e.idx, e.ne, NULL, &t, NULL)
                             : geom_octree_build_triangles(e.pos, e.nv, e.idx, e.ne, NULL, &t, NULL);
    assert_int_equal(s, GEOM_OK);
    check_structure(t, e.ne, dim == 3 ? 19 : 28);
    geom_neighbors out = {0};
    for (int qi = 0; qi < 20; qi++) {
        /* box */
        double lo[3] = {urand(), urand(), urand()}, hi[3];
        for (int k = 0; k < 3; k++)
            hi[k] = lo[k] + 0.2 * urand();
        assert_int_equal(geom_octree_box(t, lo, hi, &out), GEOM_OK);
        size_t m = 0;
        for (size_t i = 0; i < e.ne; i++) {
            double a[3], b[3];
            ebox(&e, i, a, b);
            int in = 1;
            for (int k = 0; k < dim; k++)
                in &= a[k] <= hi[k] && b[k] >= lo[k];
            if (in) {
                assert_true(m < out.offsets[1]);
                assert_int_equal(out.index[m++], i);
            }
        }
        assert_int_equal(out.offsets[1], m);
        /* frustum: an axis box written as six planes (exact then) */
        double pl[24] = {1, 0, 0, -lo[0], -1, 0, 0, hi[0], 0, 1, 0, -lo[1],
                         0, -1, 0, hi[1], 0, 0, 1, -(dim == 3 ? lo[2] : -1), 0, 0, -1, dim == 3 ? hi[2] : 1};
        assert_int_equal(geom_octree_frustum(t, pl, &out), GEOM_OK);
        m = 0;
        for (size_t i = 0; i < e.ne; i++) {
            double a[3], b[3];
            ebox(&e, i, a, b);
            int in = 1;
            for (int k = 0; k < dim; k++)
                in &= a[k] <= hi[k] && b[k] >= lo[k];
            if (in) {
                assert_true(m < out.offsets[1]);
                assert_int_equal(out.index[m++], i);
            }
        }
        assert_int_equal(out.offsets[1], m);
        /* ray: against geom_ray_aabb on every element box */
        geom_ray r;
        r.origin = geom_vec3_make(-0.5, urand(), dim == 3 ? urand() : 0);
        r.dir = geom_vec3_make(1, urand() - 0.5, dim == 3 ? urand() - 0.5 : 0);
        if (grid && qi % 2) { /* along grid lines: shared faces and edges */
            r.origin = geom_vec3_make(-1, 0.25, dim == 3 ? 0.375 : 0);
            r.dir = geom_vec3_make(1, 0, 0);
        }
        r.tmin = 0;
        r.tmax = INFINITY;
        assert_int_equal(geom_octree_ray(t, &r, &out), GEOM_OK);
        typedef struct { double t; uint32_t i; } th;
        th *want = malloc(e.ne * sizeof *want);
        m = 0;
        for (size_t i = 0; i < e.ne; i++) {
            double a[3], b[3], t0;
            ebox(&e, i, a, b);
            geom_aabb bx = {{a[0], a[1], a[2]}, {b[0], b[1], b[2]}};
            if (geom_ray_aabb(&r, bx, &t0, NULL)) {
                size_t j = m++;
                while (j > 0 && (want[j - 1].t > t0)) {
                    want[j] = want[j - 1];
                    j--;
                }
                want[j].t = t0;
                want[j].i = (uint32_t)i;
            }
        }
        assert_int_equal(out.offsets[1], m);
        for (size_t j = 0; j < m; j++) {
            assert_int_equal(out.index[j], want[j].i);
            assert_true(out.distance[j] == want[j].t);
        }
        if (grid && qi % 2)
            assert_true(m > 0);
        free(want);
    }
    geom_neighbors_free(&out);
    geom_octree_destroy(t);
    free(e.pos);
    free(e.idx);
}

static void test_elements(void **st)
{
    (void)st;
    check_elems(2, 0);
    check_elems(3, 0);
    check_elems(2, 1);
    check_elems(3, 1);
    /* bad index, NaN */
    elems e = make_elems(3, 10, 0);
    geom_octree *t = NULL;
    geom_diag d;
    e.idx[3 * 4 + 1] = 999;
    assert_int_equal(geom_octree_build_triangles(e.pos, e.nv, e.idx, e.ne, NULL, &t, &d), GEOM_ERR_INVALID_ARG);
    assert_non_null(strstr(d.message, "triangle 4"));
    e.idx[3 * 4 + 1] = 0;
    e.pos[3 * e.idx[3 * 6] + 2] = NAN;
    assert_int_equal(geom_octree_build_triangles(e.pos, e.nv, e.idx, e.ne, NULL, &t, &d), GEOM_ERR_INVALID_ARG);
    assert_non_null(strstr(d.message, "triangle 6"));
    /* kNN on an element tree is refused */
    e.pos[3 * e.idx[3 * 6] + 2] = 0;
    assert_int_equal(geom_octree_build_triangles(e.pos, e.nv, e.idx, e.ne, NULL, &t, &d), GEOM_OK);
    uint32_t k;
    assert_int_equal(geom_octree_knn(t, e.pos, 1, 1, &k, NULL, 0, NULL), GEOM_ERR_INVALID_ARG);
    geom_octree_destroy(t);
    free(e.pos);
    free(e.idx);
    /* empty */
    assert_int_equal(geom_octree_build_points(NULL, 0, 3, NULL, &t, NULL), GEOM_OK);
    geom_neighbors out = {0};
    double lo[3] = {0, 0, 0};
    assert_int_equal(geom_octree_box(t, lo, lo, &out), GEOM_OK);
    assert_int_equal(out.offsets[1], 0);
    geom_neighbors_free(&out);
    geom_octree_destroy(t);
    geom_octree_destroy(NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_points_structure),
        cmocka_unit_test(test_balance),
        cmocka_unit_test(test_elements),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
