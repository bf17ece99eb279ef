/*
 * geom_bvh_query_boxes against brute force (every primitive box tested
 * against every query box): random boxes on a coarse grid (so many boxes
 * touch at faces, edges and corners), point boxes, 1e8 offsets, empty and
 * infinite queries, both builders, leaf sizes 1 and 8, thread counts 1 and
 * 4 (same output), a triangle BVH with its vertex boxes, an empty BVH, and
 * the argument errors.
 */
#include "unit/test_util.h"

#include "geom/spatial.h"

static uint64_t rng_state = 0x2545f4914f6cdd1dull;
static double urand(void)
{
    return test_urand(&rng_state);
}

/* A box on the grid of step 1/8 in [off, off + 4]^3 (point boxes when
 * point is set), so faces, edges and corners coincide often. */
static geom_aabb grid_box(double off, int point)
{
    double lo[3], hi[3];
    for (int k = 0; k < 3; k++) {
        lo[k] = off + floor(urand() * 32) / 8;
        hi[k] = point ? lo[k] : lo[k] + floor(urand() * 8) / 8;
    }
    geom_aabb b = {{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}};
    return b;
}

static int meet(const geom_aabb *p, const geom_aabb *q)
{
    return p->min.x <= q->max.x && p->max.x >= q->min.x && p->min.y <= q->max.y &&
           p->max.y >= q->min.y && p->min.z <= q->max.z && p->max.z >= q->min.z;
}

/* out's rows equal the brute force over prims, ascending; returns the
 * total number of hits. */
static size_t check_brute(const geom_aabb *prims, size_t n, const geom_aabb *q, size_t m,
                          const geom_neighbors *out)
{
    assert_int_equal(out->query_count, m);
    assert_null(out->distance);
    size_t total = 0;
    for (size_t i = 0; i < m; i++) {
        size_t pos = out->offsets[i];
        for (size_t p = 0; p < n; p++)
            if (meet(&prims[p], &q[i])) {
                assert_true(pos < out->offsets[i + 1]);
                assert_int_equal(out->index[pos], p);
                pos++;
            }
        assert_int_equal(pos, out->offsets[i + 1]);
        total += pos - out->offsets[i];
    }
    return total;
}

static void run_case(double off, int point_prims, int point_queries)
{
    enum { N = 700, M = 300 };
    static geom_aabb prims[N], q[M];
    for (size_t i = 0; i < N; i++)
        prims[i] = grid_box(off, point_prims);
    for (size_t i = 0; i < M; i++)
        q[i] = grid_box(off, point_queries);
    /* an empty query, a whole-space query, a half-infinite one */
    q[0].max.y = q[0].min.y - 1;
    q[1] = (geom_aabb){{-INFINITY, -INFINITY, -INFINITY}, {INFINITY, INFINITY, INFINITY}};
    q[2].max.x = INFINITY;
    for (int method = 0; method < 2; method++)
        for (uint32_t leaf = 1; leaf <= 8; leaf += 7) {
            geom_bvh_options opt = {0};
            opt.method = (geom_bvh_method)method;
            opt.max_leaf_size = leaf;
            geom_bvh *b = NULL;
            assert_int_equal(geom_bvh_build_boxes(prims, N, &opt, &b, NULL), GEOM_OK);
            geom_neighbors one = {0}, four = {0};
            assert_int_equal(geom_bvh_query_boxes(b, prims, q, M, &one, 1, NULL), GEOM_OK);
            size_t total = check_brute(prims, N, q, M, &one);
            assert_true(total > M); /* the case is not trivially empty */
            assert_int_equal(one.offsets[1] - one.offsets[0], 0);
            assert_int_equal(one.offsets[2] - one.offsets[1], N);
            assert_int_equal(geom_bvh_query_boxes(b, prims, q, M, &four, 4, NULL), GEOM_OK);
            assert_memory_equal(one.offsets, four.offsets, (M + 1) * sizeof *one.offsets);
            assert_memory_equal(one.index, four.index, total * sizeof *one.index);
            /* reuse: the struct is freed and refilled */
            assert_int_equal(geom_bvh_query_boxes(b, prims, q + 5, 3, &one, 1, NULL), GEOM_OK);
            check_brute(prims, N, q + 5, 3, &one);
            geom_neighbors_free(&one);
            geom_neighbors_free(&four);
            geom_bvh_destroy(b);
        }
}

static void test_grid_boxes(void **state)
{
    (void)state;
    run_case(0.0, 0, 0);
}

static void test_point_boxes(void **state)
{
    (void)state;
    run_case(0.0, 1, 0); /* point primitives, box queries */
    run_case(0.0, 0, 1); /* box primitives, point queries */
}

static void test_offset_1e8(void **state)
{
    (void)state;
    run_case(1e8, 0, 0);
    run_case(-1e8, 1, 0);
}

/* A triangle BVH queried with the min/max boxes of its triangles. */
static void test_triangles(void **state)
{
    (void)state;
    enum { NV = 400, NT = 500, M = 200 };
    static double pos[3 * NV];
    static uint32_t tris[3 * NT];
    static geom_aabb pb[NT], q[M];
    for (size_t i = 0; i < 3 * NV; i++)
        pos[i] = 1e8 + floor(urand() * 64) / 16;
    for (size_t t = 0; t < NT; t++) {
        for (int k = 0; k < 3; k++)
            tris[3 * t + k] = (uint32_t)(urand() * NV);
        const double *a = pos + 3 * tris[3 * t], *b = pos + 3 * tris[3 * t + 1],
                     *c = pos + 3 * tris[3 * t + 2];
        pb[t] = (geom_aabb){{fmin(a[0], fmin(b[0], c[0])), fmin(a[1], fmin(b[1], c[1])),
                             fmin(a[2], fmin(b[2], c[2]))},
                            {fmax(a[0], fmax(b[0], c[0])), fmax(a[1], fmax(b[1], c[1])),
                             fmax(a[2], fmax(b[2], c[2]))}};
    }
    for (size_t i = 0; i < M; i++)
        q[i] = grid_box(1e8, i % 2);
    geom_bvh *b = NULL;
    assert_int_equal(geom_bvh_build_triangles(pos, NV, tris, NT, NULL, &b, NULL), GEOM_OK);
    geom_neighbors out = {0};
    assert_int_equal(geom_bvh_query_boxes(b, pb, q, M, &out, 0, NULL), GEOM_OK);
    assert_true(check_brute(pb, NT, q, M, &out) > 0);
    geom_neighbors_free(&out);
    geom_bvh_destroy(b);
}

static void test_empty_and_errors(void **state)
{
    (void)state;
    geom_bvh *b = NULL;
    geom_neighbors out = {0};
    assert_int_equal(geom_bvh_build_boxes(NULL, 0, NULL, &b, NULL), GEOM_OK);
    geom_aabb q = {{0, 0, 0}, {1, 1, 1}};
    assert_int_equal(geom_bvh_query_boxes(b, NULL, &q, 1, &out, 1, NULL), GEOM_OK);
    assert_int_equal(out.query_count, 1);
    assert_int_equal(out.offsets[1], 0);
    assert_int_equal(geom_bvh_query_boxes(b, NULL, NULL, 0, &out, 1, NULL), GEOM_OK);
    assert_int_equal(out.query_count, 0);
    assert_int_equal(out.offsets[0], 0);
    geom_bvh_destroy(b);

    geom_aabb prims[2] = {{{0, 0, 0}, {1, 1, 1}}, {{2, 2, 2}, {3, 3, 3}}};
    assert_int_equal(geom_bvh_build_boxes(prims, 2, NULL, &b, NULL), GEOM_OK);
    geom_aabb qs[3] = {{{1, 1, 1}, {2, 2, 2}}, {{0, 0, 0}, {0, 0, NAN}}, {{0, 0, 0}, {0, 0, 0}}};
    geom_diag d = {0};
    assert_int_equal(geom_bvh_query_boxes(b, prims, qs, 3, &out, 1, &d), GEOM_ERR_INVALID_ARG);
    assert_non_null(strstr(d.message, "query box 1"));
    assert_int_equal(geom_bvh_query_boxes(b, NULL, qs, 1, &out, 1, NULL), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_bvh_query_boxes(b, prims, NULL, 1, &out, 1, NULL),
                     GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_bvh_query_boxes(NULL, prims, qs, 1, &out, 1, NULL),
                     GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_bvh_query_boxes(b, prims, qs, 1, NULL, 1, NULL), GEOM_ERR_INVALID_ARG);
    /* corner contact at (1,1,1) and (2,2,2): both boxes; a corner point: one */
    assert_int_equal(geom_bvh_query_boxes(b, prims, qs, 1, &out, 1, NULL), GEOM_OK);
    assert_int_equal(out.offsets[1], 2);
    assert_int_equal(out.index[0], 0);
    assert_int_equal(out.index[1], 1);
    assert_int_equal(geom_bvh_query_boxes(b, prims, qs + 2, 1, &out, 1, NULL), GEOM_OK);
    assert_int_equal(out.offsets[1], 1);
    assert_int_equal(out.index[0], 0);
    geom_neighbors_free(&out);
    geom_bvh_destroy(b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_grid_boxes),
        cmocka_unit_test(test_point_boxes),
        cmocka_unit_test(test_offset_1e8),
        cmocka_unit_test(test_triangles),
        cmocka_unit_test(test_empty_and_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
