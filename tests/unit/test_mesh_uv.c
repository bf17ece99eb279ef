/*
 * UV data: charts, seams, areas, flipped and degenerate UV faces, bounds,
 * on layouts whose answers are known by construction.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "unit/test_util.h"
#include "geom/mesh.h"

static geom_mesh *mk(size_t nv, const double *xyz, size_t nf, const uint32_t *sizes,
                     const uint32_t *idx)
{
    geom_mesh *m = geom_mesh_create(NULL);
    assert_non_null(m);
    assert_int_equal(geom_mesh_build(m, nv, xyz, nf, sizes, idx, NULL, NULL, NULL), GEOM_OK);
    return m;
}

/* Set the uv corner indices of face f, in its order from face_he, to
 * ids[0..k). */
static void set_face_uv(geom_mesh *m, uint32_t ch, uint32_t f, const uint32_t *ids)
{
    uint32_t *ix = geom_mesh_corner_indices(m, ch);
    uint32_t h0 = geom_mesh_face_he(m, f), h = h0;
    size_t k = 0;
    do {
        ix[h] = ids[k++];
        h = geom_mesh_he_next(m, h);
    } while (h != h0);
}

/* The cube with each face mapped to its own unit square at u offset 1.5 f:
 * six charts, every edge a seam, UV area 6. */
static void test_cube_six_charts(void **state)
{
    (void)state;
    double xyz[24];
    for (int v = 0; v < 8; v++) {
        xyz[3 * v] = v & 1;
        xyz[3 * v + 1] = (v >> 1) & 1;
        xyz[3 * v + 2] = (v >> 2) & 1;
    }
    uint32_t sizes[6] = {4, 4, 4, 4, 4, 4};
    uint32_t idx[24] = {0, 2, 3, 1, 4, 5, 7, 6, 0, 1, 5, 4, 2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5};
    geom_mesh *m = mk(8, xyz, 6, sizes, idx);
    uint32_t ch;
    assert_int_equal(geom_mesh_channel_add(m, "uv", GEOM_MESH_DOMAIN_CORNER, 2, &ch), GEOM_OK);
    assert_int_equal(geom_mesh_corner_pool_resize(m, ch, 24), GEOM_OK);
    double *d = geom_mesh_channel_data(m, ch);
    const double sq[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (uint32_t f = 0; f < 6; f++) {
        uint32_t ids[4];
        for (int k = 0; k < 4; k++) {
            ids[k] = 4 * f + (uint32_t)k;
            d[2 * ids[k]] = 1.5 * f + sq[k][0];
            d[2 * ids[k] + 1] = sq[k][1];
        }
        set_face_uv(m, ch, f, ids);
    }
    geom_uv_report r;
    assert_int_equal(geom_mesh_uv_data(m, ch, &r, NULL, NULL, NULL), GEOM_OK);
    assert_int_equal(r.charts, 6);
    assert_int_equal(r.seam_edges, 12);
    assert_int_equal(r.flipped_faces, 0);
    assert_int_equal(r.degenerate_uv_faces, 0);
    assert_true(r.uv_area == 6.0);
    assert_true(r.uv_min[0] == 0.0 && r.uv_min[1] == 0.0);
    assert_true(r.uv_max[0] == 8.5 && r.uv_max[1] == 1.0);
    double bounds[24];
    uint32_t fc[6];
    uint8_t seam[12];
    assert_int_equal(geom_mesh_uv_data(m, ch, &r, bounds, fc, seam), GEOM_OK);
    for (uint32_t f = 0; f < 6; f++) {
        uint32_t c = fc[f];
        assert_true(c < 6);
        assert_true(bounds[4 * c] == 1.5 * f && bounds[4 * c + 1] == 0.0);
        assert_true(bounds[4 * c + 2] == 1.5 * f + 1.0 && bounds[4 * c + 3] == 1.0);
    }
    for (int e = 0; e < 12; e++)
        assert_int_equal(seam[e], 1);
    geom_mesh_destroy(m);
}

/* A strip of three quads and a triangle:
 *   4---5---6---7
 *   | 0 | 1 | 2 |
 *   0---1---2---3 --- triangle 3 (3, 8, 7)
 * faces 0 and 1 share uv indices along edge 1-5 (one chart, area 2 with
 * unit squares); face 2 has its own indices, mirrored (flipped, area 1);
 * the triangle has all corners at one uv (degenerate). */
static void test_strip(void **state)
{
    (void)state;
    double xyz[] = {0, 0, 0, 1, 0, 0, 2, 0, 0, 3, 0, 0, 0, 1, 0,
                    1, 1, 0, 2, 1, 0, 3, 1, 0, 4, 0.5, 0};
    uint32_t sizes[] = {4, 4, 4, 3};
    uint32_t idx[] = {0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 8, 7};
    geom_mesh *m = mk(9, xyz, 4, sizes, idx);
    uint32_t ch;
    assert_int_equal(geom_mesh_channel_add(m, "uv", GEOM_MESH_DOMAIN_CORNER, 2, &ch), GEOM_OK);
    /* pool: 0..5 the shared grid (0,0) (1,0) (2,0) (0,1) (1,1) (2,1);
     * 6..9 face 2 mirrored at u in [5, 6]; 10 the degenerate point */
    double pool[] = {0, 0, 1, 0, 2, 0, 0, 1, 1, 1, 2, 1, 6, 0, 5, 0, 5, 1, 6, 1, 9, 9};
    assert_int_equal(geom_mesh_corner_pool_resize(m, ch, 11), GEOM_OK);
    memcpy(geom_mesh_channel_data(m, ch), pool, sizeof pool);
    uint32_t f0[] = {0, 1, 4, 3}, f1[] = {1, 2, 5, 4}, f2[] = {6, 7, 8, 9}, f3[] = {10, 10, 10};
    set_face_uv(m, ch, 0, f0);
    set_face_uv(m, ch, 1, f1);
    set_face_uv(m, ch, 2, f2);
    set_face_uv(m, ch, 3, f3);
    geom_uv_report r;
    double b[12];
    uint32_t fc[4];
    size_t ne = geom_mesh_n_edges(m);
    uint8_t seam[16];
    assert_true(ne <= 16);
    assert_int_equal(geom_mesh_uv_data(m, ch, &r, b, fc, seam), GEOM_OK);
    assert_int_equal(r.charts, 3);
    assert_int_equal(r.seam_edges, 2); /* edges 2-6 and 3-7 */
    assert_int_equal(r.flipped_faces, 1);
    assert_int_equal(r.degenerate_uv_faces, 1);
    assert_true(r.uv_area == 3.0);
    assert_true(r.uv_min[0] == 0.0 && r.uv_min[1] == 0.0);
    assert_true(r.uv_max[0] == 9.0 && r.uv_max[1] == 9.0);
    assert_int_equal(fc[0], fc[1]);
    assert_true(fc[2] != fc[0] && fc[3] != fc[0] && fc[3] != fc[2]);
    const double *c0 = b + 4 * fc[0], *c2 = b + 4 * fc[2], *c3 = b + 4 * fc[3];
    assert_true(c0[0] == 0 && c0[1] == 0 && c0[2] == 2 && c0[3] == 1);
    assert_true(c2[0] == 5 && c2[1] == 0 && c2[2] == 6 && c2[3] == 1);
    assert_true(c3[0] == 9 && c3[1] == 9 && c3[2] == 9 && c3[3] == 9);
    for (uint32_t e = 0; e < ne; e++) {
        uint32_t a = geom_mesh_he_vertex(m, 2 * e), c = geom_mesh_he_vertex(m, 2 * e + 1);
        int expect = (a == 2 && c == 6) || (a == 6 && c == 2) || (a == 3 && c == 7) ||
                     (a == 7 && c == 3);
        assert_int_equal(seam[e], expect);
    }
    /* a seam at one end only still counts: give face 1 its own copy of
     * (1,1) at vertex 5 */
    double *d = geom_mesh_channel_data(m, ch);
    (void)d;
    assert_int_equal(geom_mesh_corner_pool_resize(m, ch, 12), GEOM_OK);
    d = geom_mesh_channel_data(m, ch);
    d[22] = 1;
    d[23] = 1;
    uint32_t f1b[] = {1, 2, 5, 11};
    set_face_uv(m, ch, 1, f1b);
    assert_int_equal(geom_mesh_uv_data(m, ch, &r, NULL, NULL, NULL), GEOM_OK);
    assert_int_equal(r.seam_edges, 3);
    assert_int_equal(r.charts, 4);
    /* a face without uv: no chart, counted degenerate */
    uint32_t none[] = {GEOM_INVALID_INDEX, 0, 1};
    set_face_uv(m, ch, 3, none);
    assert_int_equal(geom_mesh_uv_data(m, ch, &r, NULL, fc, NULL), GEOM_OK);
    assert_int_equal(fc[3], GEOM_INVALID_INDEX);
    assert_int_equal(r.degenerate_uv_faces, 1);
    assert_int_equal(r.charts, 3);
    /* not a corner channel / out of range */
    assert_int_equal(geom_mesh_uv_data(m, 0, &r, NULL, NULL, NULL), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_mesh_uv_data(m, 99, &r, NULL, NULL, NULL), GEOM_ERR_INVALID_ARG);
    geom_mesh_destroy(m);
}

/* ------------------------------------------------ allocation failures */

static void test_out_of_memory(void **state)
{
    (void)state;
    double xyz[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
    uint32_t sizes[] = {3, 3}, idx[] = {0, 1, 3, 0, 3, 2};
    int ok = 0;
    for (long k = 0; k < 50 && !ok; k++) {
        oom_state s = {-1, 0, 0};
        geom_allocator a = {oom_alloc, NULL, oom_free, &s};
        geom_mesh *m = geom_mesh_create(&a);
        assert_non_null(m);
        assert_int_equal(geom_mesh_build(m, 4, xyz, 2, sizes, idx, NULL, NULL, NULL), GEOM_OK);
        uint32_t ch;
        assert_int_equal(geom_mesh_channel_add(m, "uv", GEOM_MESH_DOMAIN_CORNER, 2, &ch), GEOM_OK);
        assert_int_equal(geom_mesh_corner_pool_resize(m, ch, 6), GEOM_OK);
        double *d = geom_mesh_channel_data(m, ch);
        const double uv[12] = {0, 0, 1, 0, 1, 1, 0, 0, 1, 1, 0, 1};
        memcpy(d, uv, sizeof uv);
        uint32_t f0[] = {0, 1, 2}, f1[] = {3, 4, 5};
        set_face_uv(m, ch, 0, f0);
        set_face_uv(m, ch, 1, f1);
        geom_uv_report r;
        s.budget = k;
        geom_status st = geom_mesh_uv_data(m, ch, &r, NULL, NULL, NULL);
        assert_true(st == GEOM_OK || st == GEOM_ERR_NOMEM);
        s.budget = -1;
        if (st == GEOM_OK) {
            ok = 1;
            assert_int_equal(r.charts, 2);
            assert_int_equal(r.seam_edges, 1);
            assert_true(r.uv_area == 1.0);
        }
        geom_mesh_destroy(m);
        assert_int_equal(s.live, 0);
        assert_false(s.bad_free);
    }
    assert_true(ok);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cube_six_charts),
        cmocka_unit_test(test_strip),
        cmocka_unit_test(test_out_of_memory),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
