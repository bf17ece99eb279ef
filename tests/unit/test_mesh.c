/* Half-edge mesh core: navigation, circulators (interior, boundary and
 * isolated vertices), add_face rejections, deletion and compaction with maps
 * and channels, channels in all four domains, tags, groups, mtllibs,
 * polylines and clone. References are hand-derived incidences and exact
 * values written into channels by the test. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "geom/mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define INV GEOM_INVALID_INDEX
#define PI 3.14159265358979323846

static void assert_valid(const geom_mesh *m)
{
    geom_mesh_defect d[4];
    size_t n = 99;
    assert_int_equal(geom_mesh_validate(m, d, 4, &n), GEOM_OK);
    if (n)
        fail_msg("%zu defects, first kind %d element %u", n, (int)d[0].kind, d[0].element);
}

/* Hexagon fan: center 0 at the origin, ring 1..6 counter-clockwise. */
static geom_mesh *hexagon_fan(void)
{
    geom_mesh *m = geom_mesh_create(NULL);
    assert_non_null(m);
    double c[3] = {0, 0, 0};
    assert_int_equal(geom_mesh_add_vertex(m, c, NULL), GEOM_OK);
    for (int i = 0; i < 6; ++i) {
        double p[3] = {cos(PI / 3 * i), sin(PI / 3 * i), 0};
        uint32_t v;
        assert_int_equal(geom_mesh_add_vertex(m, p, &v), GEOM_OK);
        assert_int_equal(v, (uint32_t)(i + 1));
    }
    for (uint32_t i = 0; i < 6; ++i) {
        uint32_t f[3] = {0, 1 + i, 1 + (i + 1) % 6}, id;
        assert_int_equal(geom_mesh_add_face(m, 3, f, &id), GEOM_OK);
        assert_int_equal(id, i);
    }
    return m;
}

static void test_empty(void **state)
{
    (void)state;
    geom_mesh_destroy(NULL);
    geom_mesh *m = geom_mesh_create(NULL);
    assert_non_null(m);
    assert_int_equal(geom_mesh_n_vertices(m), 0);
    assert_int_equal(geom_mesh_n_edges(m), 0);
    assert_int_equal(geom_mesh_n_faces(m), 0);
    assert_int_equal(geom_mesh_channel_count(m), 1);
    assert_string_equal(geom_mesh_channel_name(m, 0), "position");
    assert_int_equal(geom_mesh_channel_ncomp(m, 0), 3);
    assert_int_equal(geom_mesh_channel_find(m, "position", GEOM_MESH_DOMAIN_VERTEX), 0);
    assert_true(geom_aabb_is_empty(geom_mesh_bbox(m)));
    assert_null(geom_mesh_vertex_origin(m));
    assert_valid(m);
    /* out-of-range navigation never reads out of bounds */
    assert_int_equal(geom_mesh_he_next(m, 0), INV);
    assert_int_equal(geom_mesh_vertex_he(m, 5), INV);
    assert_false(geom_mesh_he_is_boundary(m, 3));
    assert_int_equal(geom_mesh_vertex_valence(m, 2), 0);
    geom_mesh_circ c = geom_mesh_circ_begin(m, GEOM_MESH_CIRC_FACE_VERTICES, 0);
    uint32_t x;
    assert_false(geom_mesh_circ_next(&c, &x));
    assert_int_equal(geom_mesh_validate(NULL, NULL, 0, NULL), GEOM_ERR_INVALID_ARG);
    geom_mesh_destroy(m);
}

static void test_navigation_square(void **state)
{
    (void)state;
    geom_mesh *m = geom_mesh_create(NULL);
    double p[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    for (int i = 0; i < 4; ++i)
        assert_int_equal(geom_mesh_add_vertex(m, p[i], NULL), GEOM_OK);
    uint32_t f0[3] = {0, 1, 2}, f1[3] = {0, 2, 3};
    assert_int_equal(geom_mesh_add_face(m, 3, f0, NULL), GEOM_OK);
    assert_int_equal(geom_mesh_add_face(m, 3, f1, NULL), GEOM_OK);
    assert_valid(m);
    assert_int_equal(geom_mesh_n_edges(m), 5);
    assert_int_equal(geom_mesh_n_halfedges(m), 10);
    assert_int_equal(geom_mesh_n_live_faces(m), 2);

    uint32_t h01 = geom_mesh_find_halfedge(m, 0, 1);
    assert_int_not_equal(h01, INV);
    assert_int_equal(geom_mesh_he_from(m, h01), 0);
    assert_int_equal(geom_mesh_he_vertex(m, h01), 1);
    assert_int_equal(geom_mesh_he_face(m, h01), 0);
    assert_int_equal(geom_mesh_he_opposite(m, h01), h01 ^ 1u);
    assert_true(geom_mesh_he_is_boundary(m, h01 ^ 1u));
    assert_int_equal(geom_mesh_he_edge(m, h01), h01 >> 1);
    assert_int_equal(geom_mesh_edge_he(m, h01 >> 1, (int)(h01 & 1)), h01);
    assert_int_equal(geom_mesh_find_edge(m, 1, 0), h01 >> 1);
    /* the triangle cycle 0 -> 1 -> 2 -> 0 */
    uint32_t h12 = geom_mesh_he_next(m, h01);
    assert_int_equal(geom_mesh_he_vertex(m, h12), 2);
    uint32_t h20 = geom_mesh_he_next(m, h12);
    assert_int_equal(geom_mesh_he_vertex(m, h20), 0);
    assert_int_equal(geom_mesh_he_next(m, h20), h01);
    assert_int_equal(geom_mesh_he_prev(m, h01), h20);
    /* face_he points to the first listed vertex */
    assert_int_equal(geom_mesh_he_vertex(m, geom_mesh_face_he(m, 0)), 0);
    assert_int_equal(geom_mesh_he_vertex(m, geom_mesh_face_he(m, 1)), 0);
    /* the diagonal is interior, the sides are boundary */
    uint32_t e02 = geom_mesh_find_edge(m, 0, 2);
    assert_false(geom_mesh_edge_is_boundary(m, e02));
    assert_true(geom_mesh_edge_is_boundary(m, geom_mesh_find_edge(m, 2, 3)));
    assert_int_equal(geom_mesh_find_edge(m, 1, 3), INV);
    /* valences */
    assert_int_equal(geom_mesh_vertex_valence(m, 0), 3);
    assert_int_equal(geom_mesh_vertex_valence(m, 1), 2);
    assert_int_equal(geom_mesh_vertex_valence(m, 2), 3);
    assert_int_equal(geom_mesh_face_valence(m, 1), 3);
    for (uint32_t v = 0; v < 4; ++v) {
        assert_true(geom_mesh_vertex_is_boundary(m, v));
        assert_true(geom_mesh_he_is_boundary(m, geom_mesh_vertex_he(m, v)));
        assert_int_equal(geom_mesh_he_from(m, geom_mesh_vertex_he(m, v)), v);
    }
    /* boundary loop: 4 halfedges, in the opposite direction of the faces */
    size_t nl;
    uint32_t lab[10];
    assert_int_equal(geom_mesh_boundary_loops(m, &nl, lab), GEOM_OK);
    assert_int_equal(nl, 1);
    size_t nb = 0;
    for (int h = 0; h < 10; ++h)
        nb += lab[h] != INV;
    assert_int_equal(nb, 4);
    assert_int_equal(lab[h01 ^ 1u], 0);
    geom_aabb b = geom_mesh_bbox(m);
    assert_true(b.min.x == 0 && b.min.y == 0 && b.max.x == 1 && b.max.y == 1 && b.max.z == 0);
    geom_mesh_destroy(m);
}

static void collect(const geom_mesh *m, geom_mesh_circ_kind k, uint32_t e, uint32_t *out,
                    size_t *n)
{
    geom_mesh_circ c = geom_mesh_circ_begin(m, k, e);
    uint32_t x;
    *n = 0;
    while (geom_mesh_circ_next(&c, &x)) {
        out[(*n)++] = x;
        assert_true(*n < 64);
    }
}

/* true if b is a cyclic rotation of a */
static int cyclic_equal(const uint32_t *a, const uint32_t *b, size_t n)
{
    for (size_t s = 0; s < n; ++s) {
        size_t i;
        for (i = 0; i < n; ++i)
            if (a[i] != b[(i + s) % n])
                break;
        if (i == n)
            return 1;
    }
    return 0;
}

static void test_circulators(void **state)
{
    (void)state;
    geom_mesh *m = hexagon_fan();
    assert_valid(m);
    uint32_t out[64];
    size_t n;
    /* interior vertex: counter-clockwise neighbours 1..6 */
    collect(m, GEOM_MESH_CIRC_VERTEX_VERTICES, 0, out, &n);
    uint32_t ring[6] = {1, 2, 3, 4, 5, 6};
    assert_int_equal(n, 6);
    assert_true(cyclic_equal(ring, out, 6));
    collect(m, GEOM_MESH_CIRC_VERTEX_FACES, 0, out, &n);
    uint32_t faces[6] = {0, 1, 2, 3, 4, 5};
    assert_int_equal(n, 6);
    assert_true(cyclic_equal(faces, out, 6));
    collect(m, GEOM_MESH_CIRC_VERTEX_OUTGOING, 0, out, &n);
    assert_int_equal(n, 6);
    for (size_t i = 0; i < n; ++i)
        assert_int_equal(geom_mesh_he_from(m, out[i]), 0);
    assert_false(geom_mesh_vertex_is_boundary(m, 0));
    assert_int_equal(geom_mesh_vertex_valence(m, 0), 6);

    /* boundary vertex 1 at angle 0: neighbours counter-clockwise from the
     * boundary: 6 (direction 240 deg), 2 (120 deg + 360), 0 (180 deg + 360) */
    collect(m, GEOM_MESH_CIRC_VERTEX_VERTICES, 1, out, &n);
    assert_int_equal(n, 3);
    assert_int_equal(out[0], 6);
    assert_int_equal(out[1], 2);
    assert_int_equal(out[2], 0);
    collect(m, GEOM_MESH_CIRC_VERTEX_OUTGOING, 1, out, &n);
    assert_int_equal(n, 3);
    assert_true(geom_mesh_he_is_boundary(m, out[0]));
    collect(m, GEOM_MESH_CIRC_VERTEX_FACES, 1, out, &n);
    assert_int_equal(n, 2); /* the boundary gap is skipped */
    assert_int_equal(out[0], 0); /* face (0,1,2) */
    assert_int_equal(out[1], 5); /* face (0,6,1) */

    /* faces */
    collect(m, GEOM_MESH_CIRC_FACE_VERTICES, 2, out, &n);
    assert_int_equal(n, 3);
    assert_int_equal(out[0], 0);
    assert_int_equal(out[1], 3);
    assert_int_equal(out[2], 4);
    collect(m, GEOM_MESH_CIRC_FACE_HALFEDGES, 2, out, &n);
    assert_int_equal(n, 3);
    for (size_t i = 0; i < 3; ++i) {
        assert_int_equal(geom_mesh_he_face(m, out[i]), 2);
        assert_int_equal(geom_mesh_he_next(m, out[i]), out[(i + 1) % 3]);
    }

    /* isolated vertex: nothing */
    double p[3] = {5, 5, 5};
    uint32_t iso;
    assert_int_equal(geom_mesh_add_vertex(m, p, &iso), GEOM_OK);
    assert_true(geom_mesh_vertex_is_isolated(m, iso));
    assert_true(geom_mesh_vertex_is_boundary(m, iso));
    assert_int_equal(geom_mesh_vertex_valence(m, iso), 0);
    for (int k = 0; k <= 2; ++k) {
        collect(m, (geom_mesh_circ_kind)k, iso, out, &n);
        assert_int_equal(n, 0);
    }
    assert_valid(m);
    geom_mesh_destroy(m);
}

static void assert_unchanged(const geom_mesh *m, size_t nv, size_t ne, size_t nf)
{
    assert_int_equal(geom_mesh_n_vertices(m), nv);
    assert_int_equal(geom_mesh_n_edges(m), ne);
    assert_int_equal(geom_mesh_n_faces(m), nf);
    assert_valid(m);
}

static void test_add_face_rejections(void **state)
{
    (void)state;
    geom_mesh *m = hexagon_fan();
    double p[3] = {3, 3, 0};
    uint32_t a, b;
    assert_int_equal(geom_mesh_add_vertex(m, p, &a), GEOM_OK);
    p[0] = 4;
    assert_int_equal(geom_mesh_add_vertex(m, p, &b), GEOM_OK);
    size_t nv = geom_mesh_n_vertices(m), ne = geom_mesh_n_edges(m), nf = geom_mesh_n_faces(m);

    /* invalid arguments */
    uint32_t bad[3] = {0, 1, 99};
    assert_int_equal(geom_mesh_add_face(m, 3, bad, NULL), GEOM_ERR_INVALID_ARG);
    uint32_t rep[3] = {1, 2, 1};
    assert_int_equal(geom_mesh_add_face(m, 3, rep, NULL), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_mesh_add_face(m, 2, rep, NULL), GEOM_ERR_INVALID_ARG);
    /* interior vertex 0: no gap */
    uint32_t f1[3] = {0, a, b};
    assert_int_equal(geom_mesh_add_face(m, 3, f1, NULL), GEOM_ERR_NONMANIFOLD);
    /* edge 1->2 already has a face on that side (orientation inconsistent) */
    uint32_t f2[3] = {1, 2, a};
    assert_int_equal(geom_mesh_add_face(m, 3, f2, NULL), GEOM_ERR_NONMANIFOLD);
    /* a second fan at boundary vertex 1 (bow-tie) */
    uint32_t f3[3] = {1, a, b};
    assert_int_equal(geom_mesh_add_face(m, 3, f3, NULL), GEOM_ERR_NONMANIFOLD);
    assert_unchanged(m, nv, ne, nf);

    /* a consistent face on the boundary edge 2->1 is accepted */
    uint32_t ok[3] = {2, 1, a}, id;
    assert_int_equal(geom_mesh_add_face(m, 3, ok, &id), GEOM_OK);
    assert_int_equal(id, nf);
    assert_unchanged(m, nv, ne + 2, nf + 1);
    /* a face over two existing boundary halfedges (3->2 and 2->a) closes the
     * gap at vertex 2, adding only the edge a->3 */
    uint32_t fill[3] = {3, 2, a};
    assert_int_equal(geom_mesh_add_face(m, 3, fill, NULL), GEOM_OK);
    assert_unchanged(m, nv, ne + 3, nf + 2);
    geom_mesh_destroy(m);
}

/* n x n vertex grid of quads in the xy plane, vertex (i, j) = j*n + i. */
static geom_mesh *quad_grid(int n)
{
    geom_mesh *m = geom_mesh_create(NULL);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            double p[3] = {i, j, 0};
            assert_int_equal(geom_mesh_add_vertex(m, p, NULL), GEOM_OK);
        }
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            uint32_t a = (uint32_t)(j * n + i);
            uint32_t q[4] = {a, a + 1, a + 1 + (uint32_t)n, a + (uint32_t)n};
            assert_int_equal(geom_mesh_add_face(m, 4, q, NULL), GEOM_OK);
        }
    return m;
}

static void test_delete_compact(void **state)
{
    (void)state;
    /* 5x5 vertices, 16 quads (face j*4+i), 40 edges */
    const int N = 5;
    geom_mesh *m = quad_grid(N);
    assert_valid(m);
    assert_int_equal(geom_mesh_n_edges(m), 40);
    uint32_t wv, wf, we, wc;
    assert_int_equal(geom_mesh_channel_add(m, "w", GEOM_MESH_DOMAIN_VERTEX, 1, &wv), GEOM_OK);
    assert_int_equal(geom_mesh_channel_add(m, "w", GEOM_MESH_DOMAIN_FACE, 2, &wf), GEOM_OK);
    assert_int_equal(geom_mesh_channel_add(m, "w", GEOM_MESH_DOMAIN_EDGE, 1, &we), GEOM_OK);
    assert_int_equal(geom_mesh_channel_add(m, "w", GEOM_MESH_DOMAIN_CORNER, 2, &wc), GEOM_OK);
    double *dv = geom_mesh_channel_data(m, wv);
    for (int v = 0; v < 25; ++v)
        dv[v] = 100 + v;
    double *df = geom_mesh_channel_data(m, wf);
    for (int f = 0; f < 16; ++f) {
        df[2 * f] = f;
        df[2 * f + 1] = -f;
    }
    /* edge value: the sum of its vertices' indices */
    double *de = geom_mesh_channel_data(m, we);
    for (uint32_t e = 0; e < 40; ++e)
        de[e] = geom_mesh_he_vertex(m, 2 * e) + geom_mesh_he_vertex(m, 2 * e + 1);
    /* corner: one pool value per face corner, (face, vertex) */
    assert_int_equal(geom_mesh_corner_pool_resize(m, wc, 64), GEOM_OK);
    uint32_t *ci = geom_mesh_corner_indices(m, wc);
    double *dc = geom_mesh_channel_data(m, wc);
    uint32_t k = 0;
    for (uint32_t h = 0; h < geom_mesh_n_halfedges(m); ++h) {
        if (geom_mesh_he_is_boundary(m, h)) {
            assert_int_equal(ci[h], INV);
            continue;
        }
        ci[h] = k;
        dc[2 * k] = geom_mesh_he_face(m, h);
        dc[2 * k + 1] = geom_mesh_he_vertex(m, h);
        k++;
    }
    assert_int_equal(k, 64);
    assert_valid(m);

    /* interior face 10 (vertices 12 13 18 17): a hole, nothing else goes */
    assert_int_equal(geom_mesh_delete_face(m, 10), GEOM_OK);
    assert_true(geom_mesh_face_is_deleted(m, 10));
    assert_int_equal(geom_mesh_n_live_faces(m), 15);
    assert_int_equal(geom_mesh_n_live_edges(m), 40);
    assert_int_equal(geom_mesh_n_live_vertices(m), 25);
    size_t nl;
    assert_int_equal(geom_mesh_boundary_loops(m, &nl, NULL), GEOM_OK);
    assert_int_equal(nl, 2);
    assert_valid(m);
    /* corner face 0: vertex 0 and the two outer edges go */
    assert_int_equal(geom_mesh_delete_face(m, 0), GEOM_OK);
    assert_true(geom_mesh_vertex_is_deleted(m, 0));
    assert_false(geom_mesh_vertex_is_deleted(m, 1));
    assert_int_equal(geom_mesh_n_live_vertices(m), 24);
    assert_int_equal(geom_mesh_n_live_edges(m), 38);
    assert_int_equal(geom_mesh_n_live_faces(m), 14);
    assert_valid(m);
    /* corner vertex 20 takes face 12 and its two outer edges with it */
    assert_int_equal(geom_mesh_delete_vertex(m, 20), GEOM_OK);
    assert_true(geom_mesh_face_is_deleted(m, 12));
    assert_int_equal(geom_mesh_n_live_faces(m), 13);
    assert_int_equal(geom_mesh_n_live_vertices(m), 23);
    assert_int_equal(geom_mesh_n_live_edges(m), 36);
    assert_valid(m);

    uint32_t vmap[25], fmap[16];
    assert_int_equal(geom_mesh_compact(m, vmap, fmap), GEOM_OK);
    assert_int_equal(geom_mesh_n_vertices(m), 23);
    assert_int_equal(geom_mesh_n_edges(m), 36);
    assert_int_equal(geom_mesh_n_faces(m), 13);
    assert_int_equal(geom_mesh_n_live_faces(m), 13);
    assert_valid(m);
    for (int v = 0; v < 25; ++v) {
        uint32_t want = v == 0 || v == 20 ? INV : (uint32_t)(v - 1 - (v > 20));
        assert_int_equal(vmap[v], want);
    }
    for (int f = 0; f < 16; ++f) {
        uint32_t want = f == 0 || f == 10 || f == 12 ? INV
                                                     : (uint32_t)(f - 1 - (f > 10) - (f > 12));
        assert_int_equal(fmap[f], want);
    }
    /* channels followed their elements */
    dv = geom_mesh_channel_data(m, wv);
    const double *pos = geom_mesh_cpositions(m);
    for (int v = 0; v < 25; ++v) {
        if (vmap[v] == INV)
            continue;
        assert_true(dv[vmap[v]] == 100 + v);
        assert_true(pos[3 * vmap[v]] == v % N && pos[3 * vmap[v] + 1] == v / N);
    }
    df = geom_mesh_channel_data(m, wf);
    for (int f = 0; f < 16; ++f)
        if (fmap[f] != INV)
            assert_true(df[2 * fmap[f]] == f && df[2 * fmap[f] + 1] == -f);
    /* invert the maps to compare old indices */
    uint32_t old_of[23], old_face[13];
    for (int v = 0; v < 25; ++v)
        if (vmap[v] != INV)
            old_of[vmap[v]] = (uint32_t)v;
    for (int f = 0; f < 16; ++f)
        if (fmap[f] != INV)
            old_face[fmap[f]] = (uint32_t)f;
    de = geom_mesh_channel_data(m, we);
    for (uint32_t e = 0; e < 36; ++e)
        assert_true(de[e] == old_of[geom_mesh_he_vertex(m, 2 * e)] +
                                 old_of[geom_mesh_he_vertex(m, 2 * e + 1)]);
    ci = geom_mesh_corner_indices(m, wc);
    dc = geom_mesh_channel_data(m, wc);
    assert_int_equal(geom_mesh_channel_size(m, wc), 64); /* pool kept */
    size_t ncorner = 0;
    for (uint32_t h = 0; h < geom_mesh_n_halfedges(m); ++h) {
        if (geom_mesh_he_is_boundary(m, h)) {
            assert_int_equal(ci[h], INV);
            continue;
        }
        ncorner++;
        assert_true(ci[h] < 64);
        assert_true(dc[2 * ci[h]] == old_face[geom_mesh_he_face(m, h)]);
        assert_true(dc[2 * ci[h] + 1] == old_of[geom_mesh_he_vertex(m, h)]);
    }
    assert_int_equal(ncorner, 52);
    geom_mesh_topology t;
    assert_int_equal(geom_mesh_topology_summary(m, &t), GEOM_OK);
    assert_int_equal(t.euler, 23 - 36 + 13);
    assert_int_equal(t.boundary_loops, 2);
    assert_int_equal(t.components, 1);
    assert_true(t.manifold);
    geom_mesh_destroy(m);

    /* deleting faces diagonally across a vertex leaves it with two gaps */
    m = quad_grid(3);
    assert_int_equal(geom_mesh_delete_face(m, 0), GEOM_OK);
    assert_int_equal(geom_mesh_delete_face(m, 3), GEOM_OK);
    geom_mesh_defect d;
    size_t nd;
    geom_mesh_validate(m, &d, 1, &nd);
    assert_int_equal(nd, 1);
    assert_int_equal(d.kind, GEOM_MESH_DEFECT_NONMANIFOLD_VERTEX);
    assert_int_equal(d.element, 4);
    geom_mesh_destroy(m);

    /* deleting the center of a fan deletes everything */
    m = hexagon_fan();
    assert_int_equal(geom_mesh_delete_vertex(m, 0), GEOM_OK);
    assert_int_equal(geom_mesh_n_live_vertices(m), 0);
    assert_int_equal(geom_mesh_n_live_edges(m), 0);
    assert_int_equal(geom_mesh_n_live_faces(m), 0);
    assert_valid(m);
    assert_int_equal(geom_mesh_compact(m, NULL, NULL), GEOM_OK);
    assert_int_equal(geom_mesh_n_vertices(m), 0);
    assert_int_equal(geom_mesh_n_halfedges(m), 0);
    assert_valid(m);
    geom_mesh_destroy(m);
}

static void test_delete_then_refill(void **state)
{
    (void)state;
    /* deleting two opposite faces of the fan leaves vertex 0 with two gaps
     * (as pmp's delete_face); adding them back re-links the patches */
    geom_mesh *m = hexagon_fan();
    assert_int_equal(geom_mesh_delete_face(m, 0), GEOM_OK);
    assert_int_equal(geom_mesh_delete_face(m, 3), GEOM_OK);
    size_t nd;
    geom_mesh_validate(m, NULL, 0, &nd);
    assert_int_equal(nd, 1); /* vertex 0: two boundary gaps */
    geom_mesh_defect d;
    geom_mesh_validate(m, &d, 1, &nd);
    assert_int_equal(d.kind, GEOM_MESH_DEFECT_NONMANIFOLD_VERTEX);
    assert_int_equal(d.element, 0);
    uint32_t f0[3] = {0, 1, 2}, f3[3] = {0, 4, 5};
    assert_int_equal(geom_mesh_add_face(m, 3, f0, NULL), GEOM_OK);
    assert_int_equal(geom_mesh_add_face(m, 3, f3, NULL), GEOM_OK);
    assert_int_equal(geom_mesh_compact(m, NULL, NULL), GEOM_OK);
    assert_valid(m);
    assert_int_equal(geom_mesh_n_faces(m), 6);
    assert_int_equal(geom_mesh_vertex_valence(m, 0), 6);
    assert_false(geom_mesh_vertex_is_boundary(m, 0));
    geom_mesh_destroy(m);

    /* three fans at vertex 0 (faces 0, 2, 4 deleted); the face 4 0 1 joins
     * the gaps after fans {3} and {5}, so fan {1} must be re-linked into the
     * third gap (OpenMesh/pmp patch re-linking). The vertex stays
     * non-manifold (two fans), but every link is consistent. */
    m = hexagon_fan();
    for (uint32_t f = 0; f < 6; f += 2)
        assert_int_equal(geom_mesh_delete_face(m, f), GEOM_OK);
    uint32_t h40 = geom_mesh_find_halfedge(m, 4, 0), h01 = geom_mesh_find_halfedge(m, 0, 1);
    assert_int_not_equal(geom_mesh_he_next(m, h40), h01);
    uint32_t j[3] = {4, 0, 1}, id;
    assert_int_equal(geom_mesh_add_face(m, 3, j, &id), GEOM_OK);
    assert_int_equal(geom_mesh_he_next(m, h40), h01);
    geom_mesh_defect dd[4];
    geom_mesh_validate(m, dd, 4, &nd);
    assert_int_equal(nd, 1);
    assert_int_equal(dd[0].kind, GEOM_MESH_DEFECT_NONMANIFOLD_VERTEX);
    assert_int_equal(dd[0].element, 0);
    /* boundary: 3->2 2->0 0->3 5->4 0->5 1->6 6->0 4->1 (how they chain at
     * vertex 0 is a free choice) */
    uint32_t lab[64];
    size_t nl, nbh = 0;
    assert_true(geom_mesh_n_halfedges(m) <= 64);
    assert_int_equal(geom_mesh_boundary_loops(m, &nl, lab), GEOM_OK);
    assert_true(nl == 1 || nl == 2);
    for (uint32_t h = 0; h < geom_mesh_n_halfedges(m); ++h)
        if (!geom_mesh_edge_is_deleted(m, h >> 1) && lab[h] != INV)
            nbh++;
    assert_int_equal(nbh, 8);
    assert_int_equal(geom_mesh_delete_face(m, id), GEOM_OK);
    geom_mesh_validate(m, dd, 4, &nd);
    assert_int_equal(nd, 1);
    geom_mesh_destroy(m);
}

static void test_channels(void **state)
{
    (void)state;
    geom_mesh *m = hexagon_fan(); /* 7 vertices, 12 edges, 6 faces */
    uint32_t id[4];
    geom_mesh_domain dom[4] = {GEOM_MESH_DOMAIN_VERTEX, GEOM_MESH_DOMAIN_FACE,
                               GEOM_MESH_DOMAIN_EDGE, GEOM_MESH_DOMAIN_CORNER};
    size_t want[4] = {7, 6, 12, 0};
    for (int i = 0; i < 4; ++i) {
        assert_int_equal(geom_mesh_channel_add(m, "c", dom[i], (size_t)i + 1, &id[i]), GEOM_OK);
        assert_int_equal(id[i], (uint32_t)(i + 1));
        assert_int_equal(geom_mesh_channel_domain(m, id[i]), dom[i]);
        assert_int_equal(geom_mesh_channel_ncomp(m, id[i]), (size_t)i + 1);
        assert_int_equal(geom_mesh_channel_size(m, id[i]), want[i]);
        assert_int_equal(geom_mesh_channel_find(m, "c", dom[i]), id[i]);
        const double *d = geom_mesh_channel_cdata(m, id[i]);
        for (size_t k = 0; k < want[i] * ((size_t)i + 1); ++k)
            assert_true(d[k] == 0.0);
    }
    assert_null(geom_mesh_corner_indices(m, id[0]));
    const uint32_t *ci = geom_mesh_corner_cindices(m, id[3]);
    for (size_t h = 0; h < geom_mesh_n_halfedges(m); ++h)
        assert_int_equal(ci[h], INV);
    /* rejections */
    assert_int_equal(geom_mesh_channel_add(m, "c", GEOM_MESH_DOMAIN_FACE, 1, NULL),
                     GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_mesh_channel_add(m, "", GEOM_MESH_DOMAIN_FACE, 1, NULL),
                     GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_mesh_channel_add(m, "z", GEOM_MESH_DOMAIN_FACE, 0, NULL),
                     GEOM_ERR_INVALID_ARG);
    char name[65];
    memset(name, 'n', 64);
    name[64] = 0;
    assert_int_equal(geom_mesh_channel_add(m, name, GEOM_MESH_DOMAIN_FACE, 1, NULL),
                     GEOM_ERR_INVALID_ARG);
    name[63] = 0; /* 63 bytes is allowed */
    uint32_t longid;
    assert_int_equal(geom_mesh_channel_add(m, name, GEOM_MESH_DOMAIN_FACE, 1, &longid), GEOM_OK);
    assert_string_equal(geom_mesh_channel_name(m, longid), name);
    assert_int_equal(geom_mesh_channel_remove(m, 0), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_mesh_channel_find(m, "missing", GEOM_MESH_DOMAIN_VERTEX), INV);

    /* values survive growth; new elements read zero */
    double *dv = geom_mesh_channel_data(m, id[0]);
    for (int v = 0; v < 7; ++v)
        dv[v] = v + 0.5;
    for (int i = 0; i < 100; ++i) {
        double p[3] = {i, -1, 0};
        assert_int_equal(geom_mesh_add_vertex(m, p, NULL), GEOM_OK);
    }
    dv = geom_mesh_channel_data(m, id[0]);
    assert_int_equal(geom_mesh_channel_size(m, id[0]), 107);
    for (int v = 0; v < 7; ++v)
        assert_true(dv[v] == v + 0.5);
    for (int v = 7; v < 107; ++v)
        assert_true(dv[v] == 0.0);
    assert_true(geom_mesh_positions(m)[3 * 106] == 99.0);
    /* corner pool: zero-filled on growth, kept on shrink */
    assert_int_equal(geom_mesh_corner_pool_resize(m, id[3], 5), GEOM_OK);
    double *dc = geom_mesh_channel_data(m, id[3]);
    for (int k = 0; k < 20; ++k)
        assert_true(dc[k] == 0.0);
    dc[0] = 7;
    assert_int_equal(geom_mesh_corner_pool_resize(m, id[3], 1), GEOM_OK);
    assert_int_equal(geom_mesh_corner_pool_resize(m, id[3], 3), GEOM_OK);
    dc = geom_mesh_channel_data(m, id[3]);
    assert_true(dc[0] == 7 && dc[4] == 0 && dc[11] == 0);
    assert_int_equal(geom_mesh_corner_pool_resize(m, id[0], 3), GEOM_ERR_INVALID_ARG);
    /* a corner index outside its pool is a defect */
    uint32_t *cw = geom_mesh_corner_indices(m, id[3]);
    uint32_t h = geom_mesh_face_he(m, 0);
    cw[h] = 3;
    size_t nd;
    geom_mesh_defect d;
    geom_mesh_validate(m, &d, 1, &nd);
    assert_int_equal(nd, 1);
    assert_int_equal(d.kind, GEOM_MESH_DEFECT_CHANNEL);
    assert_int_equal(d.element, h);
    cw[h] = 2;
    assert_valid(m);

    /* removal renumbers the channels after it */
    assert_int_equal(geom_mesh_channel_remove(m, id[1]), GEOM_OK);
    assert_int_equal(geom_mesh_channel_find(m, "c", GEOM_MESH_DOMAIN_EDGE), id[1]);
    assert_int_equal(geom_mesh_channel_find(m, "c", GEOM_MESH_DOMAIN_FACE), INV);
    assert_int_equal(geom_mesh_channel_count(m), 5);
    geom_mesh_clear(m);
    assert_int_equal(geom_mesh_channel_count(m), 1);
    assert_int_equal(geom_mesh_n_vertices(m), 0);
    geom_mesh_destroy(m);
}

static void test_metadata_and_clone(void **state)
{
    (void)state;
    geom_mesh *m = hexagon_fan();
    int64_t ints[2] = {1, -2};
    double fl[1] = {2.5};
    const char *strs[2] = {"edge", "corner"};
    geom_mesh_tag t = {"crease", 2, 1, 2, ints, fl, strs};
    assert_int_equal(geom_mesh_tag_add(m, &t), GEOM_OK);
    geom_mesh_tag t2 = {"hole", 0, 0, 0, NULL, NULL, NULL};
    assert_int_equal(geom_mesh_tag_add(m, &t2), GEOM_OK);
    assert_int_equal(geom_mesh_tag_count(m), 2);
    geom_mesh_tag g;
    assert_int_equal(geom_mesh_tag_get(m, 2, &g), GEOM_ERR_INVALID_ARG);

    assert_null(geom_mesh_face_cgroups(m));
    geom_mesh_group gr = {"top skin", "obj", "red", "off"}, gr2 = {NULL, NULL, "blue", NULL};
    uint32_t g0, g1;
    assert_int_equal(geom_mesh_group_add(m, &gr, &g0), GEOM_OK);
    assert_int_equal(geom_mesh_group_add(m, &gr2, &g1), GEOM_OK);
    assert_int_equal(g1, 1);
    uint32_t *fg = geom_mesh_face_groups(m);
    assert_non_null(fg);
    for (int f = 0; f < 6; ++f)
        assert_int_equal(fg[f], INV);
    fg[2] = g1;
    assert_int_equal(geom_mesh_mtllib_add(m, "a.mtl"), GEOM_OK);
    assert_int_equal(geom_mesh_mtllib_add(m, "b.mtl"), GEOM_OK);
    uint32_t pl[3] = {1, 0, 4};
    assert_int_equal(geom_mesh_polyline_add(m, 3, pl), GEOM_OK);
    assert_int_equal(geom_mesh_polyline_add(m, 2, pl + 1), GEOM_OK);
    uint32_t cv;
    assert_int_equal(geom_mesh_channel_add(m, "uv", GEOM_MESH_DOMAIN_CORNER, 2, &cv), GEOM_OK);
    assert_int_equal(geom_mesh_corner_pool_resize(m, cv, 2), GEOM_OK);
    geom_mesh_channel_data(m, cv)[3] = 9.0;
    geom_mesh_corner_indices(m, cv)[geom_mesh_face_he(m, 1)] = 1;

    geom_mesh *c = NULL;
    assert_int_equal(geom_mesh_clone(m, &c), GEOM_OK);
    /* edit the original: the clone must not change */
    geom_mesh_positions(m)[0] = 42;
    geom_mesh_channel_data(m, cv)[3] = -1;
    fg[2] = INV;
    geom_mesh_destroy(m);

    assert_valid(c);
    assert_int_equal(geom_mesh_n_faces(c), 6);
    assert_true(geom_mesh_cpositions(c)[0] == 0.0);
    assert_int_equal(geom_mesh_tag_count(c), 2);
    assert_int_equal(geom_mesh_tag_get(c, 0, &g), GEOM_OK);
    assert_string_equal(g.name, "crease");
    assert_int_equal(g.nint, 2);
    assert_int_equal(g.nfloat, 1);
    assert_int_equal(g.nstring, 2);
    assert_true(g.ints[0] == 1 && g.ints[1] == -2 && g.floats[0] == 2.5);
    assert_string_equal(g.strings[0], "edge");
    assert_string_equal(g.strings[1], "corner");
    assert_int_equal(geom_mesh_tag_get(c, 1, &g), GEOM_OK);
    assert_string_equal(g.name, "hole");
    assert_int_equal(g.nint + g.nfloat + g.nstring, 0);
    assert_int_equal(geom_mesh_group_count(c), 2);
    geom_mesh_group gg;
    assert_int_equal(geom_mesh_group_get(c, 0, &gg), GEOM_OK);
    assert_string_equal(gg.group, "top skin");
    assert_string_equal(gg.object, "obj");
    assert_string_equal(gg.material, "red");
    assert_string_equal(gg.smoothing, "off");
    assert_int_equal(geom_mesh_group_get(c, 1, &gg), GEOM_OK);
    assert_null(gg.group);
    assert_string_equal(gg.material, "blue");
    const uint32_t *cg = geom_mesh_face_cgroups(c);
    assert_non_null(cg);
    assert_int_equal(cg[2], 1);
    assert_int_equal(cg[0], INV);
    assert_int_equal(geom_mesh_mtllib_count(c), 2);
    assert_string_equal(geom_mesh_mtllib_get(c, 1), "b.mtl");
    assert_null(geom_mesh_mtllib_get(c, 2));
    assert_int_equal(geom_mesh_polyline_count(c), 2);
    size_t n;
    const uint32_t *pv;
    assert_int_equal(geom_mesh_polyline_get(c, 0, &n, &pv), GEOM_OK);
    assert_int_equal(n, 3);
    assert_true(pv[0] == 1 && pv[1] == 0 && pv[2] == 4);
    assert_int_equal(geom_mesh_polyline_get(c, 1, &n, &pv), GEOM_OK);
    assert_int_equal(n, 2);
    assert_true(pv[0] == 0 && pv[1] == 4);
    assert_int_equal(geom_mesh_polyline_get(c, 2, &n, &pv), GEOM_ERR_INVALID_ARG);
    uint32_t ccv = geom_mesh_channel_find(c, "uv", GEOM_MESH_DOMAIN_CORNER);
    assert_int_equal(ccv, cv);
    assert_int_equal(geom_mesh_channel_size(c, ccv), 2);
    assert_true(geom_mesh_channel_cdata(c, ccv)[3] == 9.0);
    assert_int_equal(geom_mesh_corner_cindices(c, ccv)[geom_mesh_face_he(c, 1)], 1);

    /* polylines follow compaction: vertex 0 deleted is dropped */
    assert_int_equal(geom_mesh_delete_vertex(c, 0), GEOM_OK);
    assert_int_equal(geom_mesh_compact(c, NULL, NULL), GEOM_OK);
    assert_int_equal(geom_mesh_polyline_get(c, 0, &n, &pv), GEOM_OK);
    assert_int_equal(n, 0); /* the whole fan is gone: 1 and 4 too */
    geom_mesh_clear(c);
    assert_int_equal(geom_mesh_tag_count(c), 0);
    assert_int_equal(geom_mesh_polyline_count(c), 0);
    assert_int_equal(geom_mesh_group_count(c), 0);
    assert_int_equal(geom_mesh_mtllib_count(c), 0);
    geom_mesh_destroy(c);
}

/* An allocator that counts live bytes, to check every free gets its size. */
typedef struct counting {
    size_t live, calls;
} counting;
static void *c_alloc(void *u, size_t n)
{
    counting *c = u;
    c->live += n;
    c->calls++;
    return malloc(n);
}
static void c_free(void *u, void *p, size_t n)
{
    counting *c = u;
    c->live -= n;
    free(p);
}

static void test_allocator_accounting(void **state)
{
    (void)state;
    counting cnt = {0, 0};
    geom_allocator a = {c_alloc, NULL, c_free, &cnt};
    geom_mesh *m = geom_mesh_create(&a);
    assert_non_null(m);
    for (int i = 0; i < 50; ++i) {
        double p[3] = {i, i * i, 0};
        assert_int_equal(geom_mesh_add_vertex(m, p, NULL), GEOM_OK);
    }
    for (uint32_t i = 0; i + 2 < 50; ++i) { /* a consistently oriented strip */
        uint32_t f[3] = {i & 1 ? i + 1 : i, i & 1 ? i : i + 1, i + 2};
        assert_int_equal(geom_mesh_add_face(m, 3, f, NULL), GEOM_OK);
    }
    assert_valid(m);
    uint32_t id;
    assert_int_equal(geom_mesh_channel_add(m, "uv", GEOM_MESH_DOMAIN_CORNER, 2, &id), GEOM_OK);
    assert_int_equal(geom_mesh_corner_pool_resize(m, id, 1000), GEOM_OK);
    assert_non_null(geom_mesh_face_groups(m));
    geom_mesh_tag t = {"x", 0, 0, 0, NULL, NULL, NULL};
    assert_int_equal(geom_mesh_tag_add(m, &t), GEOM_OK);
    geom_mesh *c;
    assert_int_equal(geom_mesh_clone(m, &c), GEOM_OK);
    assert_int_equal(geom_mesh_delete_face(c, 3), GEOM_OK);
    assert_int_equal(geom_mesh_compact(c, NULL, NULL), GEOM_OK);
    geom_mesh_destroy(c);
    geom_mesh_destroy(m);
    assert_true(cnt.calls > 0);
    assert_int_equal(cnt.live, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_empty),
        cmocka_unit_test(test_navigation_square),
        cmocka_unit_test(test_circulators),
        cmocka_unit_test(test_add_face_rejections),
        cmocka_unit_test(test_delete_compact),
        cmocka_unit_test(test_delete_then_refill),
        cmocka_unit_test(test_channels),
        cmocka_unit_test(test_metadata_and_clone),
        cmocka_unit_test(test_allocator_accounting),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
