/* Mesh topology: Euler characteristic, genus, boundary loops and components
 * of surfaces with known closed-form topology (sphere, torus, double torus,
 * disk, annulus, several components), and degenerate faces. */
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

/* A growable soup. */
typedef struct soup {
    double *xyz;
    uint32_t *sizes, *idx;
    size_t nv, nf, ni;
} soup;

static uint32_t sv(soup *s, double x, double y, double z)
{
    s->xyz = realloc(s->xyz, (s->nv + 1) * 3 * sizeof(double));
    s->xyz[3 * s->nv] = x;
    s->xyz[3 * s->nv + 1] = y;
    s->xyz[3 * s->nv + 2] = z;
    return (uint32_t)s->nv++;
}

static void sf(soup *s, size_t n, const uint32_t *v)
{
    s->sizes = realloc(s->sizes, (s->nf + 1) * sizeof(uint32_t));
    s->idx = realloc(s->idx, (s->ni + n) * sizeof(uint32_t));
    s->sizes[s->nf++] = (uint32_t)n;
    memcpy(s->idx + s->ni, v, n * sizeof(uint32_t));
    s->ni += n;
}

static void sfree(soup *s)
{
    free(s->xyz);
    free(s->sizes);
    free(s->idx);
    memset(s, 0, sizeof *s);
}

static geom_mesh *mk(const soup *s, geom_mesh_build_report *rep)
{
    geom_mesh *m = geom_mesh_create(NULL);
    geom_mesh_build_report r;
    assert_int_equal(geom_mesh_build(m, s->nv, s->xyz, s->nf, s->sizes, s->idx, NULL,
                                     rep ? rep : &r, NULL),
                     GEOM_OK);
    return m;
}

/* Torus (or cylinder when wrap_v == 0) grid: nu around the tube axis, nv
 * around... u wraps always; v wraps when wrap_v. Offset shifts it. */
static void torus_grid(soup *s, int nu, int nv, int wrap_v, double ox, int skip_face0)
{
    uint32_t base = (uint32_t)s->nv;
    int rows = wrap_v ? nv : nv + 1;
    for (int j = 0; j < rows; ++j)
        for (int i = 0; i < nu; ++i) {
            double u = 2 * PI * i / nu, v = 2 * PI * j / nv;
            if (wrap_v)
                sv(s, ox + (2 + cos(v)) * cos(u), (2 + cos(v)) * sin(u), sin(v));
            else
                sv(s, ox + cos(u), sin(u), (double)j);
        }
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            if (skip_face0 && i == 0 && j == 0)
                continue;
            int j1 = wrap_v ? (j + 1) % nv : j + 1, i1 = (i + 1) % nu;
            uint32_t q[4] = {base + (uint32_t)(j * nu + i), base + (uint32_t)(j * nu + i1),
                             base + (uint32_t)(j1 * nu + i1), base + (uint32_t)(j1 * nu + i)};
            sf(s, 4, q);
        }
}

static void cube(soup *s, double ox)
{
    uint32_t b = (uint32_t)s->nv;
    for (int k = 0; k < 8; ++k)
        sv(s, ox + (k & 1), (k >> 1) & 1, (k >> 2) & 1);
    /* vertex k = (x, y, z) bits; outward quads */
    static const uint32_t q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                     {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (int f = 0; f < 6; ++f) {
        uint32_t v[4] = {b + q[f][0], b + q[f][1], b + q[f][2], b + q[f][3]};
        sf(s, 4, v);
    }
}

static void disk(soup *s, int n, double ox)
{
    uint32_t b = (uint32_t)s->nv;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            sv(s, ox + i, j, 0);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            uint32_t a = b + (uint32_t)(j * (n + 1) + i);
            uint32_t q[4] = {a, a + 1, a + (uint32_t)n + 2, a + (uint32_t)n + 1};
            sf(s, 4, q);
        }
}

static geom_mesh_topology topo(const geom_mesh *m)
{
    geom_mesh_topology t;
    assert_int_equal(geom_mesh_topology_summary(m, &t), GEOM_OK);
    assert_true(t.manifold);
    return t;
}

static void test_sphere_like(void **state)
{
    (void)state;
    soup s = {0};
    cube(&s, 0);
    geom_mesh *m = mk(&s, NULL);
    geom_mesh_topology t = topo(m);
    assert_int_equal(t.vertices, 8);
    assert_int_equal(t.edges, 12);
    assert_int_equal(t.faces, 6);
    assert_int_equal(t.euler, 2);
    assert_int_equal(t.genus, 0);
    assert_int_equal(t.boundary_loops, 0);
    assert_int_equal(t.components, 1);
    assert_true(t.closed);
    assert_int_equal(t.degenerate_faces, 0);
    assert_int_equal(t.isolated_vertices, 0);
    geom_aabb b = geom_mesh_bbox(m);
    assert_true(b.min.x == 0 && b.max.x == 1 && b.min.z == 0 && b.max.z == 1);
    geom_mesh_destroy(m);
    sfree(&s);

    /* UV sphere: poles + rings of quads and triangle caps */
    int nu = 10, nr = 6;
    sv(&s, 0, 0, 1);
    for (int j = 1; j < nr; ++j)
        for (int i = 0; i < nu; ++i) {
            double th = PI * j / nr, ph = 2 * PI * i / nu;
            sv(&s, sin(th) * cos(ph), sin(th) * sin(ph), cos(th));
        }
    uint32_t south = sv(&s, 0, 0, -1);
    for (int i = 0; i < nu; ++i) {
        uint32_t t3[3] = {0, 1 + (uint32_t)i, 1 + (uint32_t)((i + 1) % nu)};
        sf(&s, 3, t3);
    }
    for (int j = 1; j + 1 < nr; ++j)
        for (int i = 0; i < nu; ++i) {
            uint32_t a = 1 + (uint32_t)((j - 1) * nu), c = a + (uint32_t)nu;
            uint32_t q[4] = {a + (uint32_t)i, c + (uint32_t)i, c + (uint32_t)((i + 1) % nu),
                             a + (uint32_t)((i + 1) % nu)};
            sf(&s, 4, q);
        }
    for (int i = 0; i < nu; ++i) {
        uint32_t a = 1 + (uint32_t)((nr - 2) * nu);
        uint32_t t3[3] = {south, a + (uint32_t)((i + 1) % nu), a + (uint32_t)i};
        sf(&s, 3, t3);
    }
    geom_mesh_build_report r;
    m = mk(&s, &r);
    assert_int_equal(r.flipped_faces, 0);
    t = topo(m);
    assert_int_equal(t.euler, 2);
    assert_int_equal(t.genus, 0);
    assert_true(t.closed);
    assert_int_equal(t.vertices, 2 + (size_t)(nr - 1) * nu);
    geom_mesh_destroy(m);
    sfree(&s);
}

static void test_torus(void **state)
{
    (void)state;
    soup s = {0};
    torus_grid(&s, 8, 5, 1, 0, 0);
    geom_mesh_build_report r;
    geom_mesh *m = mk(&s, &r);
    assert_int_equal(r.flipped_faces + r.nonmanifold_edges + r.added_vertices, 0);
    geom_mesh_topology t = topo(m);
    assert_int_equal(t.vertices, 40);
    assert_int_equal(t.edges, 80);
    assert_int_equal(t.faces, 40);
    assert_int_equal(t.euler, 0);
    assert_int_equal(t.genus, 1);
    assert_true(t.closed);
    assert_int_equal(t.components, 1);
    for (uint32_t v = 0; v < 40; ++v)
        assert_int_equal(geom_mesh_vertex_valence(m, v), 4);
    geom_mesh_destroy(m);
    sfree(&s);
}

static void test_double_torus(void **state)
{
    (void)state;
    /* connected sum of two tori: remove one quad from each and join the two
     * square holes with a tube of four quads */
    soup s = {0};
    torus_grid(&s, 8, 6, 1, 0, 1);
    torus_grid(&s, 8, 6, 1, 10, 1);
    /* hole of the first: vertices 0, 1, 9, 8 (face 0 = 0 1 9 8); second: +48 */
    uint32_t a[4] = {0, 1, 9, 8}, b[4] = {48, 49, 57, 56};
    for (int k = 0; k < 4; ++k) {
        uint32_t q[4] = {a[k], a[(k + 1) % 4], b[(k + 1) % 4], b[k]};
        sf(&s, 4, q);
    }
    geom_mesh_build_report r;
    geom_mesh *m = mk(&s, &r);
    assert_int_equal(r.nonmanifold_edges + r.added_vertices + r.nonorientable_components, 0);
    geom_mesh_topology t = topo(m);
    assert_int_equal(t.vertices, 96);
    assert_int_equal(t.faces, 2 * 47 + 4);
    assert_int_equal(t.edges, 2 * 96 + 4);
    assert_int_equal(t.euler, -2);
    assert_int_equal(t.genus, 2);
    assert_true(t.closed);
    assert_int_equal(t.components, 1);
    assert_int_equal(t.boundary_loops, 0);
    geom_mesh_destroy(m);
    sfree(&s);
}

static void test_disk_annulus(void **state)
{
    (void)state;
    soup s = {0};
    disk(&s, 4, 0);
    geom_mesh *m = mk(&s, NULL);
    geom_mesh_topology t = topo(m);
    assert_int_equal(t.euler, 1);
    assert_int_equal(t.genus, 0);
    assert_int_equal(t.boundary_loops, 1);
    assert_false(t.closed);
    size_t nl;
    uint32_t *lab = malloc(geom_mesh_n_halfedges(m) * sizeof(uint32_t));
    assert_int_equal(geom_mesh_boundary_loops(m, &nl, lab), GEOM_OK);
    size_t nb = 0;
    for (size_t h = 0; h < geom_mesh_n_halfedges(m); ++h) {
        assert_true((lab[h] == INV) == !geom_mesh_he_is_boundary(m, (uint32_t)h));
        nb += lab[h] == 0;
    }
    assert_int_equal(nb, 16); /* perimeter of a 4x4 grid */
    free(lab);
    geom_mesh_destroy(m);
    sfree(&s);

    /* annulus: a cylinder of 7 x 3 quads */
    torus_grid(&s, 7, 3, 0, 0, 0);
    m = mk(&s, NULL);
    t = topo(m);
    assert_int_equal(t.vertices, 28);
    assert_int_equal(t.edges, 7 * 4 + 7 * 3);
    assert_int_equal(t.faces, 21);
    assert_int_equal(t.euler, 0);
    assert_int_equal(t.genus, 0);
    assert_int_equal(t.boundary_loops, 2);
    lab = malloc(geom_mesh_n_halfedges(m) * sizeof(uint32_t));
    assert_int_equal(geom_mesh_boundary_loops(m, &nl, lab), GEOM_OK);
    assert_int_equal(nl, 2);
    size_t per[2] = {0, 0};
    for (size_t h = 0; h < geom_mesh_n_halfedges(m); ++h)
        if (lab[h] != INV) {
            assert_true(lab[h] < 2);
            per[lab[h]]++;
            /* a loop's halfedges follow each other */
            assert_int_equal(lab[geom_mesh_he_next(m, (uint32_t)h)], lab[h]);
        }
    assert_int_equal(per[0], 7);
    assert_int_equal(per[1], 7);
    free(lab);
    geom_mesh_destroy(m);
    sfree(&s);
}

static void test_components(void **state)
{
    (void)state;
    soup s = {0};
    cube(&s, 0);           /* vertices 0..7, faces 0..5 */
    disk(&s, 2, 5);        /* vertices 8..16, faces 6..9 */
    sv(&s, 100, 100, 100); /* isolated vertex 17 */
    torus_grid(&s, 6, 4, 1, 20, 0); /* vertices 18..41, faces 10..33 */
    geom_mesh *m = mk(&s, NULL);
    size_t n;
    uint32_t vc[42], fc[34];
    assert_int_equal(geom_mesh_components(m, &n, vc, fc), GEOM_OK);
    assert_int_equal(n, 4);
    for (int v = 0; v < 42; ++v) {
        uint32_t want = v < 8 ? 0 : v < 17 ? 1 : v == 17 ? 2 : 3;
        assert_int_equal(vc[v], want);
    }
    for (int f = 0; f < 34; ++f)
        assert_int_equal(fc[f], f < 6 ? 0u : f < 10 ? 1u : 3u);
    geom_mesh_topology t = topo(m);
    assert_int_equal(t.components, 4);
    assert_int_equal(t.isolated_vertices, 1);
    assert_int_equal(t.boundary_loops, 1);
    assert_int_equal(t.euler, 2 + 1 + 1 + 0);
    assert_int_equal(t.genus, 1);
    assert_false(t.closed);
    /* deleting the disk's faces leaves no component behind */
    for (uint32_t f = 6; f < 10; ++f)
        assert_int_equal(geom_mesh_delete_face(m, f), GEOM_OK);
    assert_int_equal(geom_mesh_components(m, &n, NULL, NULL), GEOM_OK);
    assert_int_equal(n, 3);
    t = topo(m);
    assert_true(t.closed);
    assert_int_equal(t.euler, 2 + 1 + 0);
    geom_mesh_destroy(m);
    sfree(&s);
}

static void test_degenerate_faces(void **state)
{
    (void)state;
    soup s = {0};
    sv(&s, 0, 0, 0);
    sv(&s, 1, 0, 0);
    sv(&s, 2, 0, 0);   /* 2: collinear with 0 and 1 */
    sv(&s, 0, 1, 0);
    sv(&s, 1, 0, 0);   /* 4: same position as 1 */
    sv(&s, 1e-9, 0, 5); /* 5 */
    sv(&s, 0, 1e-9, 5); /* 6 */
    sv(&s, 0, 0, 5);   /* 7 */
    sv(&s, 1, 1e-15, 0); /* 8: sliver apex */
    uint32_t f0[3] = {0, 1, 3};          /* fine */
    uint32_t f1[3] = {0, 2, 1};          /* zero area (collinear) */
    uint32_t f2[4] = {0, 1, 4, 3};       /* coincident vertices 1 and 4 */
    uint32_t f3[3] = {7, 5, 6};          /* tiny but well shaped */
    uint32_t f4[3] = {0, 2, 8};          /* sliver: area 1e-15 vs edge 2 */
    sf(&s, 3, f0);
    sf(&s, 3, f1);
    sf(&s, 4, f2);
    sf(&s, 3, f3);
    sf(&s, 3, f4);
    geom_mesh_build_options skip = {.keep_orientation = 1};
    geom_mesh *m = geom_mesh_create(NULL);
    geom_mesh_build_report r;
    assert_int_equal(
        geom_mesh_build(m, s.nv, s.xyz, s.nf, s.sizes, s.idx, &skip, &r, NULL), GEOM_OK);
    assert_false(geom_mesh_face_is_degenerate(m, 0));
    assert_true(geom_mesh_face_is_degenerate(m, 1));
    assert_true(geom_mesh_face_is_degenerate(m, 2));
    assert_false(geom_mesh_face_is_degenerate(m, 3));
    assert_true(geom_mesh_face_is_degenerate(m, 4));
    assert_false(geom_mesh_face_is_degenerate(m, 99));
    geom_mesh_topology t = topo(m);
    assert_int_equal(t.degenerate_faces, 3);
    geom_mesh_destroy(m);
    sfree(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sphere_like),  cmocka_unit_test(test_torus),
        cmocka_unit_test(test_double_torus), cmocka_unit_test(test_disk_annulus),
        cmocka_unit_test(test_components),   cmocka_unit_test(test_degenerate_faces),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
