/* Building half-edge meshes from polygon soups, with repairs: closed cube,
 * flipped faces, vertices shared by two closed surfaces, edges shared by
 * three or four faces, Moebius strip, bow-tie, duplicated faces, invalid
 * faces, isolated vertices, high valence. Every result is checked against the
 * input soup (vertex and face origins, positions, face order, corner
 * mapping) and must validate with zero defects. */
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

/* Internal helper of the mesh module (libgeom/src/mesh/mesh_internal.h),
 * used by file readers to place per-corner data after a build. */
uint32_t geom__mesh_input_corner_he(const geom_mesh *m, uint32_t f, uint32_t k);

typedef struct soup {
    size_t nv, nf;
    const double *xyz;
    const uint32_t *sizes, *idx;
} soup;

static void assert_valid(const geom_mesh *m)
{
    geom_mesh_defect d[4];
    size_t n = 99;
    assert_int_equal(geom_mesh_validate(m, d, 4, &n), GEOM_OK);
    if (n)
        fail_msg("%zu defects, first kind %d element %u", n, (int)d[0].kind, d[0].element);
}

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

/* No two edges join the same two vertices (a polygon mesh: rebuilding its
 * soup needs no repair). */
static void assert_no_double_edges(const geom_mesh *m)
{
    size_t ne = geom_mesh_n_edges(m), n = 0;
    uint64_t *key = malloc((ne + 1) * sizeof(uint64_t));
    assert_non_null(key);
    for (uint32_t e = 0; e < ne; ++e) {
        uint32_t a = geom_mesh_he_vertex(m, 2 * e), b = geom_mesh_he_vertex(m, 2 * e + 1);
        key[n++] = a < b ? ((uint64_t)a << 32 | b) : ((uint64_t)b << 32 | a);
    }
    qsort(key, n, sizeof key[0], cmp_u64);
    for (size_t i = 1; i < n; ++i)
        if (key[i] == key[i - 1])
            fail_msg("two edges join vertices %u and %u", (unsigned)(key[i] >> 32),
                     (unsigned)(key[i] & 0xffffffffu));
    free(key);
}

/* Build and check everything that must hold for any input. */
static geom_mesh *build(const soup *s, const geom_mesh_build_options *opt,
                        geom_mesh_build_report *r)
{
    geom_mesh *m = geom_mesh_create(NULL);
    assert_non_null(m);
    geom_diag diag;
    geom_status st = geom_mesh_build(m, s->nv, s->xyz, s->nf, s->sizes, s->idx, opt, r, &diag);
    if (st != GEOM_OK)
        fail_msg("build failed: %s", diag.message);
    assert_valid(m);
    assert_no_double_edges(m);
    const uint32_t *vo = geom_mesh_vertex_origin(m), *fo = geom_mesh_face_origin(m);
    assert_non_null(vo);
    assert_non_null(fo);
    size_t nv = geom_mesh_n_vertices(m), nf = geom_mesh_n_faces(m);
    assert_int_equal(nv, s->nv + r->added_vertices);
    assert_int_equal(nf, s->nf - r->invalid_faces);
    const double *p = geom_mesh_cpositions(m);
    for (size_t v = 0; v < nv; ++v) {
        if (v < s->nv)
            assert_int_equal(vo[v], v);
        assert_true(vo[v] < s->nv);
        assert_memory_equal(p + 3 * v, s->xyz + 3 * (size_t)vo[v], 3 * sizeof(double));
    }
    size_t *off = malloc((s->nf + 1) * sizeof(size_t));
    off[0] = 0;
    for (size_t f = 0; f < s->nf; ++f)
        off[f + 1] = off[f] + s->sizes[f];
    size_t ni;
    assert_int_equal(geom_mesh_to_soup(m, NULL, NULL, &ni), GEOM_OK);
    uint32_t *osz = malloc((nf + 1) * sizeof(uint32_t)), *oix = malloc((ni + 1) * sizeof(uint32_t));
    assert_int_equal(geom_mesh_to_soup(m, osz, oix, &ni), GEOM_OK);
    size_t o = 0, reversed = 0, isolated = 0;
    uint8_t *used = calloc(s->nv + 1, 1);
    for (size_t f = 0; f < nf; ++f) {
        uint32_t in = fo[f];
        assert_true(in < s->nf);
        if (f > 0)
            assert_true(in > fo[f - 1]); /* input order kept */
        size_t n = s->sizes[in];
        assert_int_equal(osz[f], n);
        assert_int_equal(geom_mesh_face_valence(m, (uint32_t)f), n);
        const uint32_t *want = s->idx + off[in];
        /* forward, or reversed keeping the first vertex first */
        int fwd = 1, rev = 1;
        for (size_t k = 0; k < n; ++k) {
            uint32_t got = vo[oix[o + k]];
            fwd &= got == want[k];
            rev &= got == want[(n - k) % n];
            used[got] = 1;
        }
        assert_true(fwd || rev);
        reversed += !fwd;
        /* the corner helper finds input corner k at the halfedge pointing to it */
        for (uint32_t k = 0; k < n; ++k) {
            uint32_t h = geom__mesh_input_corner_he(m, (uint32_t)f, k);
            assert_int_not_equal(h, INV);
            assert_int_equal(geom_mesh_he_face(m, h), f);
            assert_int_equal(vo[geom_mesh_he_vertex(m, h)], want[k]);
        }
        o += n;
    }
    assert_int_equal(o, ni);
    assert_int_equal(reversed, r->flipped_faces);
    for (size_t v = 0; v < s->nv; ++v)
        if (!used[v]) {
            isolated++;
            assert_true(geom_mesh_vertex_is_isolated(m, (uint32_t)v));
        }
    assert_int_equal(isolated, r->isolated_vertices);
    free(used);
    free(off);
    free(osz);
    free(oix);
    return m;
}

static geom_mesh_topology topo(const geom_mesh *m)
{
    geom_mesh_topology t;
    assert_int_equal(geom_mesh_topology_summary(m, &t), GEOM_OK);
    return t;
}

/* Signed volume of a closed triangle/polygon mesh (fan triangulation). */
static double volume(const geom_mesh *m)
{
    const double *p = geom_mesh_cpositions(m);
    double vol = 0;
    for (uint32_t f = 0; f < geom_mesh_n_faces(m); ++f) {
        uint32_t h0 = geom_mesh_face_he(m, f), h1 = geom_mesh_he_next(m, h0);
        const double *a = p + 3 * geom_mesh_he_vertex(m, h0);
        for (uint32_t h = geom_mesh_he_next(m, h1); h != h0; h1 = h, h = geom_mesh_he_next(m, h)) {
            const double *b = p + 3 * geom_mesh_he_vertex(m, h1), *c = p + 3 * geom_mesh_he_vertex(m, h);
            vol += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                    a[2] * (b[0] * c[1] - b[1] * c[0])) /
                   6.0;
        }
    }
    return vol;
}

static const double cube_xyz[8 * 3] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0,
                                       0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
static const uint32_t cube_sizes[6] = {4, 4, 4, 4, 4, 4};
/* outward (counter-clockwise seen from outside) */
static const uint32_t cube_idx[24] = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4,
                                      1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7};

static void test_cube(void **state)
{
    (void)state;
    soup s = {8, 6, cube_xyz, cube_sizes, cube_idx};
    geom_mesh_build_report r;
    geom_mesh *m = build(&s, NULL, &r);
    geom_mesh_build_report zero;
    memset(&zero, 0, sizeof zero);
    assert_memory_equal(&r, &zero, sizeof r);
    assert_int_equal(geom_mesh_n_edges(m), 12);
    geom_mesh_topology t = topo(m);
    assert_true(t.closed);
    assert_int_equal(t.euler, 2);
    assert_int_equal(t.genus, 0);
    assert_int_equal(t.components, 1);
    assert_true(fabs(volume(m) - 1.0) < 1e-15);
    /* exact round trip */
    uint32_t sz[6], ix[24];
    size_t ni;
    assert_int_equal(geom_mesh_to_soup(m, sz, ix, &ni), GEOM_OK);
    assert_int_equal(ni, 24);
    assert_memory_equal(ix, cube_idx, sizeof ix);
    for (uint32_t v = 0; v < 8; ++v) {
        assert_int_equal(geom_mesh_vertex_valence(m, v), 3);
        assert_false(geom_mesh_vertex_is_boundary(m, v));
    }
    /* building again replaces the contents */
    geom_mesh_build_report r2;
    assert_int_equal(geom_mesh_build(m, 8, cube_xyz, 1, cube_sizes, cube_idx, NULL, &r2, NULL),
                     GEOM_OK);
    assert_int_equal(geom_mesh_n_faces(m), 1);
    assert_int_equal(r2.isolated_vertices, 4);
    assert_valid(m);
    geom_mesh_destroy(m);
}

static const double tet_xyz[4 * 3] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
static const uint32_t tri4[4] = {3, 3, 3, 3};

static void test_tetra_flipped(void **state)
{
    (void)state;
    /* outward tetrahedron with face 2 given reversed */
    uint32_t idx[12] = {0, 2, 1, 0, 1, 3, 1, 3, 2, 0, 3, 2};
    /* face 2 outward would be 1 2 3 */
    soup s = {4, 4, tet_xyz, tri4, idx};
    geom_mesh_build_report r;
    geom_mesh *m = build(&s, NULL, &r);
    assert_int_equal(r.flipped_faces, 1);
    assert_int_equal(r.first_flipped_faces[0], 2);
    assert_int_equal(r.nonmanifold_edges + r.detached_faces + r.split_vertices, 0);
    assert_int_equal(r.nonorientable_components, 0);
    assert_true(fabs(volume(m) - 1.0 / 6.0) < 1e-16);
    assert_true(topo(m).closed);
    /* the flipped face lists its first input vertex first, then reversed */
    uint32_t h = geom_mesh_face_he(m, 2);
    assert_int_equal(geom_mesh_he_vertex(m, h), 1);
    assert_int_equal(geom_mesh_he_vertex(m, geom_mesh_he_next(m, h)), 2);
    assert_int_equal(geom_mesh_he_vertex(m, geom_mesh_he_prev(m, h)), 3);
    geom_mesh_destroy(m);

    /* face 0 reversed instead: everything follows face 0 (inside out) */
    uint32_t idx2[12] = {0, 1, 2, 0, 1, 3, 1, 2, 3, 0, 3, 2};
    soup s2 = {4, 4, tet_xyz, tri4, idx2};
    m = build(&s2, NULL, &r);
    assert_int_equal(r.flipped_faces, 3);
    assert_int_equal(r.first_flipped_faces[0], 1);
    assert_int_equal(r.first_flipped_faces[1], 2);
    assert_int_equal(r.first_flipped_faces[2], 3);
    assert_true(fabs(volume(m) + 1.0 / 6.0) < 1e-16);
    geom_mesh_destroy(m);

    /* keep_orientation: the inconsistent face is detached, nothing flipped */
    geom_mesh_build_options keep = {.keep_orientation = 1};
    m = build(&s, &keep, &r);
    assert_int_equal(r.flipped_faces, 0);
    assert_int_equal(r.nonmanifold_edges, 3);
    assert_int_equal(r.detached_faces, 1);
    assert_int_equal(r.first_detached_faces[0], 2);
    assert_int_equal(r.added_vertices, 3);
    geom_mesh_topology t = topo(m);
    assert_int_equal(t.components, 2);
    assert_int_equal(t.boundary_loops, 2);
    geom_mesh_destroy(m);
}

static void test_random_orientation_grid(void **state)
{
    (void)state;
    /* 20x20 quads, ~1/3 reversed at random: exactly the faces whose
     * reversal differs from face 0's are flipped */
    enum { N = 21 };
    double *xyz = malloc(N * N * 3 * sizeof(double));
    uint32_t sizes[(N - 1) * (N - 1)], idx[(N - 1) * (N - 1) * 4];
    uint8_t rev[(N - 1) * (N - 1)];
    for (int j = 0; j < N; ++j)
        for (int i = 0; i < N; ++i) {
            xyz[3 * (j * N + i)] = i;
            xyz[3 * (j * N + i) + 1] = j;
            xyz[3 * (j * N + i) + 2] = sin(i + j);
        }
    uint64_t rng = 12345;
    size_t f = 0;
    for (int j = 0; j + 1 < N; ++j)
        for (int i = 0; i + 1 < N; ++i, ++f) {
            uint32_t a = (uint32_t)(j * N + i);
            uint32_t q[4] = {a, a + 1, a + 1 + N, a + N};
            rng = rng * 6364136223846793005ull + 1442695040888963407ull;
            rev[f] = (rng >> 33) % 3 == 0;
            sizes[f] = 4;
            for (int k = 0; k < 4; ++k)
                idx[4 * f + (size_t)k] = rev[f] ? q[(4 - k) % 4] : q[k];
        }
    soup s = {N * N, f, xyz, sizes, idx};
    geom_mesh_build_report r;
    geom_mesh *m = build(&s, NULL, &r);
    size_t want = 0;
    for (size_t i = 0; i < f; ++i)
        want += rev[i] != rev[0];
    assert_true(want > 50);
    assert_int_equal(r.flipped_faces, want);
    assert_int_equal(r.nonmanifold_edges + r.added_vertices, 0);
    geom_mesh_topology t = topo(m);
    assert_int_equal(t.euler, 1);
    assert_int_equal(t.boundary_loops, 1);
    geom_mesh_destroy(m);
    free(xyz);
}

static void test_two_tets_one_vertex(void **state)
{
    (void)state;
    /* two outward tetrahedra sharing vertex 3 (the apex of the first, a
     * base vertex of the second) */
    double xyz[7 * 3] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 0, 1, 1, 0, 0, 2};
    uint32_t sizes[8] = {3, 3, 3, 3, 3, 3, 3, 3};
    uint32_t idx[24] = {0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2, /* tet 0 1 2 3 */
                        3, 5, 4, 3, 4, 6, 4, 5, 6, 3, 6, 5};
    soup s = {7, 8, xyz, sizes, idx};
    geom_mesh_build_report r;
    geom_mesh *m = build(&s, NULL, &r);
    assert_int_equal(r.split_vertices, 1);
    assert_int_equal(r.first_split_vertices[0], 3);
    assert_int_equal(r.added_vertices, 1);
    assert_int_equal(geom_mesh_vertex_origin(m)[7], 3);
    assert_int_equal(r.flipped_faces + r.nonmanifold_edges + r.detached_faces, 0);
    geom_mesh_topology t = topo(m);
    assert_int_equal(t.components, 2);
    assert_true(t.closed);
    assert_int_equal(t.euler, 4);
    assert_int_equal(t.genus, 0);
    assert_int_equal(geom_mesh_vertex_valence(m, 3), 3);
    assert_int_equal(geom_mesh_vertex_valence(m, 7), 3);
    geom_mesh_destroy(m);
}

static void test_three_faces_on_edge(void **state)
{
    (void)state;
    /* edge 0-1 with three fins: 0 1 2 and 1 0 3 are compatible, 0 1 4 is
     * not (same direction as the first) and is detached */
    double xyz[5 * 3] = {0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -1, 0, 0.5, 0, 1};
    uint32_t sizes[3] = {3, 3, 3}, idx[9] = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    soup s = {5, 3, xyz, sizes, idx};
    geom_mesh_build_report r;
    geom_mesh_build_options keep = {.keep_orientation = 1}; /* do not flip the fin */
    geom_mesh *m = build(&s, &keep, &r);
    assert_int_equal(r.nonmanifold_edges, 1);
    assert_int_equal(r.detached_faces, 1);
    assert_int_equal(r.first_detached_faces[0], 2);
    assert_int_equal(r.first_nonmanifold_faces[0], 0);
    assert_int_equal(r.first_nonmanifold_faces[1], 1);
    assert_int_equal(r.first_nonmanifold_faces[2], 2);
    assert_int_equal(r.added_vertices, 2);
    assert_int_equal(r.split_vertices, 2);
    geom_mesh_topology t = topo(m);
    assert_int_equal(t.components, 2);
    assert_int_equal(t.boundary_loops, 2);
    /* faces 0 and 1 share the kept edge */
    uint32_t e = geom_mesh_find_edge(m, 0, 1);
    assert_int_not_equal(e, INV);
    assert_false(geom_mesh_edge_is_boundary(m, e));
    geom_mesh_destroy(m);

    /* the fin order changed: the first use's first compatible partner is
     * the third face, so the second face is detached */
    uint32_t idx2[9] = {0, 1, 2, 0, 1, 4, 1, 0, 3};
    soup s2 = {5, 3, xyz, sizes, idx2};
    m = build(&s2, &keep, &r);
    assert_int_equal(r.detached_faces, 1);
    assert_int_equal(r.first_detached_faces[0], 1);
    geom_mesh_destroy(m);

    /* four faces on one edge: two tetrahedra sharing edge 0-1 become two
     * closed surfaces (the second pair glued among themselves) */
    double x2[6 * 3] = {0, 0, 0, 0, 0, 1, 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0};
    uint32_t sz8[8] = {3, 3, 3, 3, 3, 3, 3, 3};
    /* tet (0,1,2,3) and tet (0,1,4,5), outward */
    uint32_t id8[24] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3, 0, 4, 1, 0, 1, 5, 0, 5, 4, 1, 4, 5};
    soup s3 = {6, 8, x2, sz8, id8};
    m = build(&s3, NULL, &r);
    assert_int_equal(r.nonmanifold_edges, 1);
    assert_int_equal(r.detached_faces, 2);
    assert_int_equal(r.first_detached_faces[0], 4);
    assert_int_equal(r.first_detached_faces[1], 5);
    assert_int_equal(r.added_vertices, 2);
    t = topo(m);
    assert_int_equal(t.components, 2);
    assert_true(t.closed);
    assert_int_equal(t.euler, 4);
    assert_true(fabs(volume(m) - 2.0 / 6.0) < 1e-15);
    geom_mesh_destroy(m);
}

/* Outward tetrahedra (0,1,2,3) and (0,1,4,5) sharing edge 0-1, each face
 * of one listed between faces of the other. Regression: compatible pairs
 * were glued in input order (tet A's first face with tet B's first face,
 * then the second faces), which joined both tetrahedra into one surface
 * with two edges between vertices 0 and 1 and split no vertex; the faces
 * that close a surface around both ends of the edge are now glued first. */
static void test_interleaved_tets_on_edge(void **state)
{
    (void)state;
    double xyz[6 * 3] = {0, 0, 0, 0, 0, 1, 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0};
    uint32_t sz8[8] = {3, 3, 3, 3, 3, 3, 3, 3};
    /* A0 B0 A1 B1 (the four faces on edge 0-1), then the others */
    uint32_t id8[24] = {0, 2, 1, 0, 4, 1, 0, 1, 3, 0, 1, 5, 0, 3, 2, 1, 2, 3, 0, 5, 4, 1, 4, 5};
    soup s = {6, 8, xyz, sz8, id8};
    geom_mesh_build_report r;
    geom_mesh *m = build(&s, NULL, &r);
    assert_int_equal(r.flipped_faces, 0);
    assert_int_equal(r.nonmanifold_edges, 1);
    /* faces 0 and 2 are kept (tet A's), 1 and 3 detached onto copies of
     * vertices 0 and 1 */
    assert_int_equal(r.detached_faces, 2);
    assert_int_equal(r.first_detached_faces[0], 1);
    assert_int_equal(r.first_detached_faces[1], 3);
    assert_int_equal(r.split_vertices, 2);
    assert_int_equal(r.added_vertices, 2);
    geom_mesh_topology t = topo(m);
    assert_int_equal(t.vertices, 8);
    assert_int_equal(t.edges, 12);
    assert_int_equal(t.components, 2);
    assert_true(t.closed);
    assert_int_equal(t.euler, 4);
    assert_int_equal(t.genus, 0);
    assert_true(fabs(volume(m) - 2.0 / 6.0) < 1e-15);
    /* the output is a polygon mesh: its soup builds again without repair */
    size_t ni;
    uint32_t osz[8], oix[24];
    assert_int_equal(geom_mesh_to_soup(m, osz, oix, &ni), GEOM_OK);
    soup s2 = {geom_mesh_n_vertices(m), 8, geom_mesh_cpositions(m), osz, oix};
    geom_mesh_build_report r2;
    geom_mesh *m2 = build(&s2, NULL, &r2);
    assert_int_equal(r2.flipped_faces + r2.nonmanifold_edges + r2.detached_faces +
                         r2.split_vertices + r2.added_vertices,
                     0);
    geom_mesh_destroy(m2);
    geom_mesh_destroy(m);

    /* every order of the eight faces gives the same two tetrahedra */
    uint64_t rng = 77;
    for (int it = 0; it < 200; ++it) {
        uint32_t perm[8] = {0, 1, 2, 3, 4, 5, 6, 7}, id[24];
        for (int i = 7; i > 0; --i) {
            rng = rng * 6364136223846793005ull + 1442695040888963407ull;
            int j = (int)((rng >> 33) % (uint64_t)(i + 1));
            uint32_t tmp = perm[i];
            perm[i] = perm[j];
            perm[j] = tmp;
        }
        for (int f = 0; f < 8; ++f)
            memcpy(id + 3 * f, id8 + 3 * perm[f], 3 * sizeof(uint32_t));
        soup sp = {6, 8, xyz, sz8, id};
        m = build(&sp, NULL, &r);
        t = topo(m);
        assert_int_equal(t.components, 2);
        assert_true(t.closed);
        assert_int_equal(t.edges, 12);
        assert_int_equal(r.added_vertices, 2);
        assert_true(fabs(fabs(volume(m)) - 2.0 / 6.0) < 1e-15);
        geom_mesh_destroy(m);
    }
}

/* A cube with an open square tube standing on its top face: each of the
 * four top edges has three faces (top, side, tube). The cube's two faces are
 * glued on every one of them (each glue joins fans whose other ends are the
 * next top edge's unglued uses; those meet and are glued in turn), so the
 * cube stays closed and the tube is detached with its two boundary loops. */
static void test_tube_on_cube(void **state)
{
    (void)state;
    double xyz[12 * 3];
    memcpy(xyz, cube_xyz, sizeof cube_xyz);
    for (int i = 0; i < 4; ++i) {
        xyz[3 * (8 + i)] = cube_xyz[3 * (4 + i)];
        xyz[3 * (8 + i) + 1] = cube_xyz[3 * (4 + i) + 1];
        xyz[3 * (8 + i) + 2] = 2;
    }
    uint32_t sizes[10] = {4, 4, 4, 4, 4, 4, 4, 4, 4, 4}, idx[40];
    memcpy(idx, cube_idx, sizeof cube_idx);
    for (uint32_t i = 0; i < 4; ++i) {
        uint32_t a = 4 + i, b = 4 + (i + 1) % 4;
        uint32_t q[4] = {a, b, b + 4, a + 4};
        memcpy(idx + 24 + 4 * i, q, sizeof q);
    }
    soup s = {12, 10, xyz, sizes, idx};
    geom_mesh_build_report r;
    geom_mesh *m = build(&s, NULL, &r);
    assert_int_equal(r.nonmanifold_edges, 4);
    assert_int_equal(r.detached_faces, 4);
    for (int i = 0; i < 4; ++i)
        assert_int_equal(r.first_detached_faces[i], 6 + i);
    assert_int_equal(r.added_vertices, 4);
    geom_mesh_topology t = topo(m);
    assert_int_equal(t.components, 2);
    assert_int_equal(t.boundary_loops, 2);
    assert_int_equal(t.vertices, 16);
    assert_int_equal(t.euler, 2);
    assert_int_equal(t.genus, 0);
    /* the cube's faces form a closed component */
    uint32_t fc[10];
    size_t nc;
    assert_int_equal(geom_mesh_components(m, &nc, NULL, fc), GEOM_OK);
    for (uint32_t f = 0; f < 10; ++f) {
        assert_int_equal(fc[f] == fc[0], f < 6);
        uint32_t h0 = geom_mesh_face_he(m, f), h = h0;
        size_t nb = 0;
        do {
            nb += geom_mesh_he_is_boundary(m, geom_mesh_he_opposite(m, h));
            h = geom_mesh_he_next(m, h);
        } while (h != h0);
        assert_int_equal(nb, f < 6 ? 0 : 2); /* a tube quad: bottom and top edges */
    }
    geom_mesh_destroy(m);
}

static void test_moebius(void **state)
{
    (void)state;
    enum { N = 12 };
    double xyz[2 * N * 3];
    for (int i = 0; i < N; ++i) {
        double th = 2 * PI * i / N, ph = th / 2;
        for (int s = 0; s < 2; ++s) {
            double w = s ? -0.3 : 0.3;
            double rad = 1 + w * cos(ph);
            xyz[3 * (2 * i + s)] = rad * cos(th);
            xyz[3 * (2 * i + s) + 1] = rad * sin(th);
            xyz[3 * (2 * i + s) + 2] = w * sin(ph);
        }
    }
    uint32_t sizes[N], idx[4 * N];
    for (uint32_t i = 0; i < N; ++i) {
        sizes[i] = 4;
        uint32_t t0 = 2 * i, b0 = 2 * i + 1;
        if (i + 1 < N) {
            uint32_t q[4] = {t0, t0 + 2, b0 + 2, b0};
            memcpy(idx + 4 * i, q, sizeof q);
        } else { /* the half twist: top of the last meets the bottom of the first */
            uint32_t q[4] = {t0, 1, 0, b0};
            memcpy(idx + 4 * i, q, sizeof q);
        }
    }
    soup s = {2 * N, N, xyz, sizes, idx};
    geom_mesh_build_report r;
    geom_mesh *m = build(&s, NULL, &r);
    assert_int_equal(r.nonorientable_components, 1);
    assert_int_equal(r.nonmanifold_edges, 1);
    assert_int_equal(r.detached_faces, 1);
    assert_int_equal(r.added_vertices, 2);
    geom_mesh_topology t = topo(m);
    /* cut open: a disk (a long rectangle) */
    assert_int_equal(t.components, 1);
    assert_int_equal(t.boundary_loops, 1);
    assert_int_equal(t.euler, 1);
    assert_int_equal(t.genus, 0);
    assert_int_equal(t.vertices, 2 * N + 2);
    assert_int_equal(t.faces, N);
    geom_mesh_destroy(m);

    geom_mesh_build_options keep = {.keep_orientation = 1};
    m = build(&s, &keep, &r);
    assert_int_equal(r.flipped_faces, 0);
    assert_int_equal(r.nonmanifold_edges, 1);
    assert_int_equal(r.detached_faces, 1);
    assert_int_equal(r.first_detached_faces[0], N - 1);
    assert_int_equal(topo(m).euler, 1);
    geom_mesh_destroy(m);
}

static void test_bowtie_and_pillow(void **state)
{
    (void)state;
    double xyz[5 * 3] = {0, 0, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0, -1, -1, 0};
    uint32_t sizes[2] = {3, 3}, idx[6] = {0, 1, 2, 0, 3, 4};
    soup s = {5, 2, xyz, sizes, idx};
    geom_mesh_build_report r;
    geom_mesh *m = build(&s, NULL, &r);
    assert_int_equal(r.split_vertices, 1);
    assert_int_equal(r.first_split_vertices[0], 0);
    assert_int_equal(r.added_vertices, 1);
    geom_mesh_topology t = topo(m);
    assert_int_equal(t.components, 2);
    assert_int_equal(t.boundary_loops, 2);
    assert_int_equal(t.euler, 2);
    geom_mesh_destroy(m);

    /* the same triangle twice: the second is flipped and glued on all three
     * edges, a closed two-sided "pillow" (sphere: V - E + F = 3 - 3 + 2) */
    uint32_t idx2[6] = {0, 1, 2, 0, 1, 2};
    soup s2 = {5, 2, xyz, sizes, idx2};
    m = build(&s2, NULL, &r);
    assert_int_equal(r.flipped_faces, 1);
    assert_int_equal(r.isolated_vertices, 2);
    t = topo(m);
    assert_true(t.closed);
    assert_int_equal(t.euler - 2, 2); /* two isolated vertices count too */
    assert_int_equal(t.components, 3);
    assert_int_equal(t.isolated_vertices, 2);
    geom_mesh_destroy(m);
}

static void test_invalid_faces(void **state)
{
    (void)state;
    double xyz[4 * 3] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    /* face 1: out of range; face 2: repeated; face 3: two vertices */
    uint32_t sizes[5] = {3, 3, 3, 2, 3};
    uint32_t idx[14] = {0, 1, 2, 0, 2, 9, 0, 2, 0, 1, 2, 0, 2, 3};
    geom_mesh *m = geom_mesh_create(NULL);
    /* a previous mesh stays when the build fails */
    assert_int_equal(geom_mesh_build(m, 8, cube_xyz, 6, cube_sizes, cube_idx, NULL, NULL, NULL),
                     GEOM_OK);
    geom_diag d;
    geom_mesh_build_report r;
    assert_int_equal(geom_mesh_build(m, 4, xyz, 5, sizes, idx, NULL, &r, &d),
                     GEOM_ERR_INVALID_ARG);
    assert_int_equal(d.status, GEOM_ERR_INVALID_ARG);
    assert_non_null(strstr(d.message, "face 1"));
    assert_int_equal(geom_mesh_n_faces(m), 6);
    assert_valid(m);
    geom_mesh_destroy(m);

    geom_mesh_build_options skip = {.skip_invalid_faces = 1};
    soup s = {4, 5, xyz, sizes, idx};
    m = build(&s, &skip, &r);
    assert_int_equal(r.invalid_faces, 3);
    assert_int_equal(r.first_invalid_faces[0], 1);
    assert_int_equal(r.first_invalid_faces[1], 2);
    assert_int_equal(r.first_invalid_faces[2], 3);
    assert_int_equal(geom_mesh_n_faces(m), 2);
    assert_int_equal(geom_mesh_face_origin(m)[0], 0);
    assert_int_equal(geom_mesh_face_origin(m)[1], 4);
    geom_mesh_destroy(m);

    /* NaN coordinates and NULL arrays */
    double bad[3 * 3] = {0, 0, 0, 1, NAN, 0, 0, 1, 0};
    m = geom_mesh_create(NULL);
    assert_int_equal(geom_mesh_build(m, 3, bad, 1, sizes, idx, NULL, NULL, &d),
                     GEOM_ERR_INVALID_ARG);
    assert_non_null(strstr(d.message, "vertex 1"));
    bad[4] = INFINITY;
    assert_int_equal(geom_mesh_build(m, 3, bad, 1, sizes, idx, NULL, NULL, NULL),
                     GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_mesh_build(m, 3, NULL, 1, sizes, idx, NULL, NULL, NULL),
                     GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_mesh_build(NULL, 3, xyz, 1, sizes, idx, NULL, NULL, NULL),
                     GEOM_ERR_INVALID_ARG);
    /* no faces at all: isolated vertices */
    assert_int_equal(geom_mesh_build(m, 4, xyz, 0, NULL, NULL, NULL, &r, NULL), GEOM_OK);
    assert_int_equal(r.isolated_vertices, 4);
    assert_int_equal(geom_mesh_n_vertices(m), 4);
    assert_valid(m);
    assert_int_equal(geom_mesh_build(m, 0, NULL, 0, NULL, NULL, NULL, &r, NULL), GEOM_OK);
    assert_int_equal(geom_mesh_n_vertices(m), 0);
    geom_mesh_destroy(m);
}

static void test_isolated_and_polygons(void **state)
{
    (void)state;
    /* a pentagon and two triangles around it, plus two unused vertices */
    double xyz[9 * 3];
    for (int i = 0; i < 5; ++i) {
        xyz[3 * i] = cos(2 * PI * i / 5);
        xyz[3 * i + 1] = sin(2 * PI * i / 5);
        xyz[3 * i + 2] = 0;
    }
    double extra[4 * 3] = {2, 0, 0, 0, 2, 0, 7, 7, 7, 8, 8, 8};
    memcpy(xyz + 15, extra, sizeof extra);
    uint32_t sizes[3] = {5, 3, 3}, idx[11] = {0, 1, 2, 3, 4, 1, 0, 5, 2, 1, 6};
    soup s = {9, 3, xyz, sizes, idx};
    geom_mesh_build_report r;
    geom_mesh *m = build(&s, NULL, &r);
    assert_int_equal(r.isolated_vertices, 2);
    assert_int_equal(r.flipped_faces, 0);
    assert_true(geom_mesh_vertex_is_isolated(m, 7));
    assert_true(geom_mesh_vertex_is_isolated(m, 8));
    geom_mesh_topology t = topo(m);
    assert_int_equal(t.components, 3);
    assert_int_equal(t.isolated_vertices, 2);
    assert_int_equal(t.euler, 9 - 9 + 3);
    geom_mesh_destroy(m);
}

static void test_high_valence(void **state)
{
    (void)state;
    /* a fan of 5000 triangles around vertex 0, listed in scrambled order
     * and with every third one reversed */
    enum { K = 5000 };
    double *xyz = malloc((K + 1) * 3 * sizeof(double));
    uint32_t *sizes = malloc(K * sizeof(uint32_t)), *idx = malloc(3 * K * sizeof(uint32_t));
    xyz[0] = xyz[1] = xyz[2] = 0;
    for (int i = 0; i < K; ++i) {
        xyz[3 * (i + 1)] = cos(2 * PI * i / K);
        xyz[3 * (i + 1) + 1] = sin(2 * PI * i / K);
        xyz[3 * (i + 1) + 2] = 0;
    }
    for (uint32_t j = 0; j < K; ++j) {
        uint32_t i = (j * 2693u) % K; /* 2693 is prime to 5000 */
        uint32_t a = 1 + i, b = 1 + (i + 1) % K;
        sizes[j] = 3;
        idx[3 * j] = 0;
        idx[3 * j + 1] = j % 3 == 1 ? b : a;
        idx[3 * j + 2] = j % 3 == 1 ? a : b;
    }
    soup s = {K + 1, K, xyz, sizes, idx};
    geom_mesh_build_report r;
    geom_mesh *m = build(&s, NULL, &r);
    assert_int_equal(r.flipped_faces, (K + 1) / 3);
    assert_int_equal(geom_mesh_vertex_valence(m, 0), K);
    assert_false(geom_mesh_vertex_is_boundary(m, 0));
    geom_mesh_topology t = topo(m);
    assert_int_equal(t.euler, 1);
    assert_int_equal(t.boundary_loops, 1);
    geom_mesh_destroy(m);
    free(xyz);
    free(sizes);
    free(idx);
}

static uint32_t rnd(uint64_t *s, size_t n)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (uint32_t)((*s >> 33) % (uint64_t)n);
}

static void test_random_soups(void **state)
{
    (void)state;
    /* random polygons over few vertices: many edges used 3+ times, in both
     * directions, non-manifold vertices, repeated and out-of-range indices.
     * Every build must satisfy all the invariants checked by build(). */
    uint64_t rng = 0x9e3779b97f4a7c15ull;
#define RND(n) rnd(&rng, (n))
    double xyz[3 * 24];
    for (int i = 0; i < 3 * 24; ++i)
        xyz[i] = RND(1000) / 100.0;
    uint32_t sizes[60], idx[60 * 6];
    size_t tot[6] = {0};
    for (int it = 0; it < 400; ++it) {
        size_t nv = 4 + RND(20), nf = 1 + RND(60), ni = 0;
        for (size_t f = 0; f < nf; ++f) {
            uint32_t sz = 3 + RND(4), small = RND(20) == 0;
            sizes[f] = sz - (small ? 2 : 0);
            for (uint32_t k = 0; k < sizes[f]; ++k) {
                uint32_t out_of_range = RND(30) == 0;
                idx[ni++] = RND(nv + out_of_range);
            }
        }
        soup s = {nv, nf, xyz, sizes, idx};
        for (int mode = 0; mode < 2; ++mode) {
            geom_mesh_build_options o = {.skip_invalid_faces = 1, .keep_orientation = mode};
            geom_mesh_build_report r;
            geom_mesh *m = build(&s, &o, &r);
            if (mode)
                assert_int_equal(r.flipped_faces, 0);
            tot[0] += r.invalid_faces;
            tot[1] += r.flipped_faces;
            tot[2] += r.nonmanifold_edges;
            tot[3] += r.detached_faces;
            tot[4] += r.split_vertices;
            tot[5] += r.nonorientable_components;
            geom_mesh_topology t = topo(m);
            assert_true(t.manifold);
            geom_mesh_destroy(m);
        }
    }
#undef RND
    for (int k = 0; k < 6; ++k) /* every kind of repair happened */
        assert_true(tot[k] > 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cube),
        cmocka_unit_test(test_tetra_flipped),
        cmocka_unit_test(test_random_orientation_grid),
        cmocka_unit_test(test_two_tets_one_vertex),
        cmocka_unit_test(test_three_faces_on_edge),
        cmocka_unit_test(test_interleaved_tets_on_edge),
        cmocka_unit_test(test_tube_on_cube),
        cmocka_unit_test(test_moebius),
        cmocka_unit_test(test_bowtie_and_pillow),
        cmocka_unit_test(test_invalid_faces),
        cmocka_unit_test(test_isolated_and_polygons),
        cmocka_unit_test(test_high_valence),
        cmocka_unit_test(test_random_soups),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
