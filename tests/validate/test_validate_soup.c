/*
 * Tests of the validation shim's polygon-soup checker and vertex normals
 * (geom_validate.h, CGAL part) on small soups whose answers are known in
 * closed form: Euler characteristic, genus, boundary loops and normals of
 * tetrahedra, squares, tori, cylinders, cubes and non-manifold configurations.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "validate/geom_validate.h"

/* A soup under construction. */
typedef struct soup {
    size_t nv, nf, ni;
    double xyz[3 * 256];
    uint32_t sizes[256];
    uint32_t idx[1024];
} soup;

static void add_v(soup *s, double x, double y, double z)
{
    assert_true(s->nv < 256);
    s->xyz[3 * s->nv + 0] = x;
    s->xyz[3 * s->nv + 1] = y;
    s->xyz[3 * s->nv + 2] = z;
    s->nv++;
}

static void add_f(soup *s, uint32_t n, const uint32_t *v)
{
    assert_true(s->nf < 256 && s->ni + n <= 1024);
    s->sizes[s->nf++] = n;
    for (uint32_t i = 0; i < n; ++i)
        s->idx[s->ni++] = v[i];
}

static void add_tri(soup *s, uint32_t a, uint32_t b, uint32_t c)
{
    const uint32_t v[3] = {a, b, c};
    add_f(s, 3, v);
}

static void add_quad(soup *s, uint32_t a, uint32_t b, uint32_t c, uint32_t d)
{
    const uint32_t v[4] = {a, b, c, d};
    add_f(s, 4, v);
}

static gv_soup_info check(const soup *s)
{
    gv_soup_info info;
    assert_int_equal(gv_soup_check(s->nv, s->xyz, s->nf, s->sizes, s->idx, &info), GV_OK);
    return info;
}

/* Unit tetrahedron, faces oriented outward; base vertex index `o`. */
static void add_tetra(soup *s, double dx)
{
    const uint32_t o = (uint32_t)s->nv;
    add_v(s, dx + 0, 0, 0);
    add_v(s, dx + 1, 0, 0);
    add_v(s, dx + 0, 1, 0);
    add_v(s, dx + 0, 0, 1);
    add_tri(s, o + 0, o + 2, o + 1);
    add_tri(s, o + 0, o + 1, o + 3);
    add_tri(s, o + 0, o + 3, o + 2);
    add_tri(s, o + 1, o + 2, o + 3);
}

/* n x m quad torus (major radius 2, minor 0.5) centred at (dx, 0, 0),
 * quads oriented outward. */
static void add_torus(soup *s, uint32_t n, uint32_t m, double dx)
{
    const uint32_t o = (uint32_t)s->nv;
    const double pi = 3.14159265358979323846;
    for (uint32_t i = 0; i < n; ++i)
        for (uint32_t j = 0; j < m; ++j) {
            const double u = 2 * pi * i / n, v = 2 * pi * j / m;
            add_v(s, dx + (2 + 0.5 * cos(v)) * cos(u), (2 + 0.5 * cos(v)) * sin(u), 0.5 * sin(v));
        }
    for (uint32_t i = 0; i < n; ++i)
        for (uint32_t j = 0; j < m; ++j) {
            const uint32_t i1 = (i + 1) % n, j1 = (j + 1) % m;
            add_quad(s, o + i * m + j, o + i1 * m + j, o + i1 * m + j1, o + i * m + j1);
        }
}

static void test_tetrahedron(void **state)
{
    (void)state;
    soup s = {0};
    add_tetra(&s, 0);
    const gv_soup_info r = check(&s);
    assert_int_equal(r.is_polygon_soup_a_polygon_mesh, 1);
    assert_int_equal(r.reoriented, 0);
    assert_int_equal(r.valid, 1);
    assert_int_equal(r.closed, 1);
    assert_int_equal(r.vertices, 4);
    assert_int_equal(r.edges, 6);
    assert_int_equal(r.faces, 4);
    assert_int_equal(r.components, 1);
    assert_int_equal(r.border_cycles, 0);
    assert_int_equal(r.euler_characteristic, 2);
    assert_int_equal(r.genus, 0);
    assert_int_equal(r.isolated_vertices, 0);
    assert_int_equal(r.self_intersecting, 0);
}

static void test_open_square(void **state)
{
    (void)state;
    /* A 3 x 3 grid of vertices, 2 x 2 quads: a disk. */
    soup s = {0};
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i)
            add_v(&s, i, j, 0);
    for (uint32_t j = 0; j < 2; ++j)
        for (uint32_t i = 0; i < 2; ++i)
            add_quad(&s, 3 * j + i, 3 * j + i + 1, 3 * (j + 1) + i + 1, 3 * (j + 1) + i);
    const gv_soup_info r = check(&s);
    assert_int_equal(r.is_polygon_soup_a_polygon_mesh, 1);
    assert_int_equal(r.valid, 1);
    assert_int_equal(r.closed, 0);
    assert_int_equal(r.vertices, 9);
    assert_int_equal(r.edges, 12);
    assert_int_equal(r.faces, 4);
    assert_int_equal(r.components, 1);
    assert_int_equal(r.border_cycles, 1);
    assert_int_equal(r.euler_characteristic, 1);
    assert_int_equal(r.genus, 0);
    assert_int_equal(r.self_intersecting, 0);
}

static void test_torus(void **state)
{
    (void)state;
    soup s = {0};
    add_torus(&s, 8, 5, 0);
    gv_soup_info r = check(&s);
    assert_int_equal(r.is_polygon_soup_a_polygon_mesh, 1);
    assert_int_equal(r.valid, 1);
    assert_int_equal(r.closed, 1);
    assert_int_equal(r.vertices, 40);
    assert_int_equal(r.edges, 80);
    assert_int_equal(r.faces, 40);
    assert_int_equal(r.components, 1);
    assert_int_equal(r.border_cycles, 0);
    assert_int_equal(r.euler_characteristic, 0);
    assert_int_equal(r.genus, 1);
    assert_int_equal(r.self_intersecting, 0);

    /* Two disjoint tori: genus adds up, chi = 0. */
    add_torus(&s, 6, 4, 10);
    r = check(&s);
    assert_int_equal(r.components, 2);
    assert_int_equal(r.closed, 1);
    assert_int_equal(r.euler_characteristic, 0);
    assert_int_equal(r.genus, 2);
    assert_int_equal(r.self_intersecting, 0);
}

static void test_cylinder_and_isolated(void **state)
{
    (void)state;
    /* Open cylinder: 8 quads around, two boundary loops, chi = 0, genus 0. */
    soup s = {0};
    const uint32_t n = 8;
    for (uint32_t i = 0; i < n; ++i) {
        const double u = 2 * 3.14159265358979323846 * i / n;
        add_v(&s, cos(u), sin(u), 0);
        add_v(&s, cos(u), sin(u), 1);
    }
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t i1 = (i + 1) % n;
        add_quad(&s, 2 * i, 2 * i1, 2 * i1 + 1, 2 * i + 1);
    }
    /* And a separate tetrahedron, then an isolated vertex. */
    add_tetra(&s, 20);
    gv_soup_info r = check(&s);
    assert_int_equal(r.valid, 1);
    assert_int_equal(r.components, 2);
    assert_int_equal(r.border_cycles, 2);
    assert_int_equal(r.euler_characteristic, 2);
    assert_int_equal(r.genus, 0);
    add_v(&s, 5, 5, 5);
    r = check(&s);
    assert_int_equal(r.is_polygon_soup_a_polygon_mesh, 1);
    /* CGAL 5.5's is_valid_polygon_mesh rejects isolated vertices. */
    assert_int_equal(r.valid, 0);
    assert_int_equal(r.closed, 0);
    assert_int_equal(r.vertices, 16 + 4 + 1);
    assert_int_equal(r.isolated_vertices, 1);
    assert_int_equal(r.components, 2);
    assert_int_equal(r.border_cycles, 2);
    /* cylinder 0, isolated vertex 1, tetrahedron 2 */
    assert_int_equal(r.euler_characteristic, 3);
    assert_int_equal(r.genus, 0);
    assert_int_equal(r.self_intersecting, 0);
}

static void test_bowtie(void **state)
{
    (void)state;
    /* Two triangles sharing only vertex 0: a non-manifold vertex. */
    soup s = {0};
    add_v(&s, 0, 0, 0);
    add_v(&s, 1, -0.5, 0);
    add_v(&s, 1, 0.5, 0);
    add_v(&s, -1, 0.5, 0);
    add_v(&s, -1, -0.5, 0);
    add_tri(&s, 0, 1, 2);
    add_tri(&s, 0, 3, 4);
    const gv_soup_info r = check(&s);
    assert_int_equal(r.is_polygon_soup_a_polygon_mesh, 0);
    assert_int_equal(r.reoriented, 1);
    assert_int_equal(r.duplicated_vertices, 1);
    assert_int_equal(r.reversed_faces, 0);
    assert_int_equal(r.valid, 1);
    assert_int_equal(r.closed, 0);
    assert_int_equal(r.vertices, 6);
    assert_int_equal(r.edges, 6);
    assert_int_equal(r.faces, 2);
    assert_int_equal(r.components, 2);
    assert_int_equal(r.border_cycles, 2);
    assert_int_equal(r.euler_characteristic, 2);
    assert_int_equal(r.genus, 0);
    /* the copy of vertex 0 touches the original */
    assert_int_equal(r.self_intersecting, 1);
}

static void test_inconsistent_and_nonmanifold_edge(void **state)
{
    (void)state;
    /* Two triangles sharing edge 0-1 traversed the same way: one is reversed. */
    soup s = {0};
    add_v(&s, 0, 0, 0);
    add_v(&s, 1, 0, 0);
    add_v(&s, 0, 1, 0);
    add_v(&s, 0, -1, 0);
    add_tri(&s, 0, 1, 2);
    add_tri(&s, 0, 1, 3);
    gv_soup_info r = check(&s);
    assert_int_equal(r.is_polygon_soup_a_polygon_mesh, 0);
    assert_int_equal(r.reversed_faces, 1);
    assert_int_equal(r.duplicated_vertices, 0);
    assert_int_equal(r.valid, 1);
    assert_int_equal(r.components, 1);
    assert_int_equal(r.border_cycles, 1);
    assert_int_equal(r.euler_characteristic, 1);
    assert_int_equal(r.self_intersecting, 0);

    /* Three triangles on one edge: the edge's endpoints get copies. */
    soup t = {0};
    add_v(&t, 0, 0, 0);
    add_v(&t, 1, 0, 0);
    add_v(&t, 0, 1, 0);
    add_v(&t, 0, -1, 0);
    add_v(&t, 0, 0, 1);
    add_tri(&t, 0, 1, 2);
    add_tri(&t, 1, 0, 3);
    add_tri(&t, 1, 0, 4);
    r = check(&t);
    assert_int_equal(r.is_polygon_soup_a_polygon_mesh, 0);
    assert_true(r.duplicated_vertices >= 2);
    assert_int_equal(r.valid, 1);
    assert_int_equal(r.vertices, 5 + r.duplicated_vertices);
    assert_int_equal(r.faces, 3);
    assert_int_equal(r.self_intersecting, 1);
}

static void test_self_intersection(void **state)
{
    (void)state;
    /* Two triangles piercing each other. */
    soup s = {0};
    add_v(&s, -1, -1, 0);
    add_v(&s, 1, -1, 0);
    add_v(&s, 0, 1, 0);
    add_v(&s, 0, 0, -1);
    add_v(&s, 0, 0, 1);
    add_v(&s, 0, 2, 0.5);
    add_tri(&s, 0, 1, 2);
    add_tri(&s, 3, 4, 5);
    gv_soup_info r = check(&s);
    assert_int_equal(r.is_polygon_soup_a_polygon_mesh, 1);
    assert_int_equal(r.components, 2);
    assert_int_equal(r.self_intersecting, 1);

    /* A quad folded through a triangle: exercises the triangulated copy. */
    soup q = {0};
    add_v(&q, -1, -1, 0);
    add_v(&q, 1, -1, 0);
    add_v(&q, 1, 1, 0);
    add_v(&q, -1, 1, 0);
    add_v(&q, 0, 0, -1);
    add_v(&q, 0.2, 0, 1);
    add_v(&q, 0, 0.2, 1);
    add_quad(&q, 0, 1, 2, 3);
    add_tri(&q, 4, 5, 6);
    r = check(&q);
    assert_int_equal(r.self_intersecting, 1);
    /* Move the triangle away: no intersection. */
    q.xyz[3 * 4 + 2] = 0.5;
    r = check(&q);
    assert_int_equal(r.self_intersecting, 0);

    /* A zero-area triangle counts as self-intersecting. */
    soup d = {0};
    add_v(&d, 0, 0, 0);
    add_v(&d, 1, 1, 1);
    add_v(&d, 2, 2, 2);
    add_tri(&d, 0, 1, 2);
    r = check(&d);
    assert_int_equal(r.self_intersecting, 1);
}

static void test_invalid_input(void **state)
{
    (void)state;
    soup s = {0};
    add_tetra(&s, 0);
    gv_soup_info r;
    /* index out of range */
    s.idx[5] = 4;
    assert_int_equal(gv_soup_check(s.nv, s.xyz, s.nf, s.sizes, s.idx, &r), GV_ERR_INVALID);
    assert_int_equal(r.faces, 0);
    /* repeated vertex in a face */
    s.idx[5] = 0;
    assert_int_equal(gv_soup_check(s.nv, s.xyz, s.nf, s.sizes, s.idx, &r), GV_ERR_INVALID);
    s.idx[5] = 3;
    /* face with 2 corners */
    s.sizes[0] = 2;
    assert_int_equal(gv_soup_check(s.nv, s.xyz, s.nf, s.sizes, s.idx, &r), GV_ERR_INVALID);
    s.sizes[0] = 3;
    /* NaN coordinate */
    s.xyz[4] = NAN;
    assert_int_equal(gv_soup_check(s.nv, s.xyz, s.nf, s.sizes, s.idx, &r), GV_ERR_INVALID);
    s.xyz[4] = 0;
    assert_int_equal(gv_soup_check(s.nv, s.xyz, s.nf, s.sizes, s.idx, NULL), GV_ERR_INVALID);
    assert_int_equal(gv_soup_check(s.nv, NULL, s.nf, s.sizes, s.idx, &r), GV_ERR_INVALID);
    assert_int_equal(gv_soup_check(s.nv, s.xyz, s.nf, s.sizes, s.idx, &r), GV_OK);
    /* The empty soup is a valid, closed, empty mesh. */
    r = check(&(soup){0});
    assert_int_equal(r.valid, 1);
    assert_int_equal(r.vertices, 0);
    assert_int_equal(r.components, 0);
}

static void assert_unit_close(const double *n, double x, double y, double z)
{
    const double len = sqrt(x * x + y * y + z * z);
    assert_true(fabs(n[0] - x / len) <= 1e-12);
    assert_true(fabs(n[1] - y / len) <= 1e-12);
    assert_true(fabs(n[2] - z / len) <= 1e-12);
}

static void test_normals_cube(void **state)
{
    (void)state;
    /* Unit cube of quads, vertices listed in a scrambled order: each corner's
     * normal is the normalised sum of its three face normals, (+-1,+-1,+-1)
     * / sqrt(3), under every weighting (equal corner angles). */
    static const uint32_t perm[8] = {5, 2, 7, 0, 3, 6, 1, 4};
    soup s = {0};
    double pos[8][3];
    for (int i = 0; i < 8; ++i) {
        pos[i][0] = (i & 1) ? 1 : 0;
        pos[i][1] = (i & 2) ? 1 : 0;
        pos[i][2] = (i & 4) ? 1 : 0;
    }
    /* soup vertex perm[i] is cube corner i */
    s.nv = 8;
    for (int i = 0; i < 8; ++i)
        memcpy(&s.xyz[3 * perm[i]], pos[i], sizeof pos[i]);
#define P(i) perm[i]
    add_quad(&s, P(0), P(2), P(3), P(1)); /* z = 0, normal -z */
    add_quad(&s, P(4), P(5), P(7), P(6)); /* z = 1, +z */
    add_quad(&s, P(0), P(1), P(5), P(4)); /* y = 0, -y */
    add_quad(&s, P(2), P(6), P(7), P(3)); /* y = 1, +y */
    add_quad(&s, P(0), P(4), P(6), P(2)); /* x = 0, -x */
    add_quad(&s, P(1), P(3), P(7), P(5)); /* x = 1, +x */
#undef P
    const gv_soup_info r = check(&s);
    assert_int_equal(r.is_polygon_soup_a_polygon_mesh, 1);
    assert_int_equal(r.closed, 1);
    assert_int_equal(r.genus, 0);
    for (int w = GV_NORMALS_CGAL; w <= GV_NORMALS_UNWEIGHTED; ++w) {
        double n[3 * 8];
        size_t copies = 99;
        assert_int_equal(gv_vertex_normals(s.nv, s.xyz, s.nf, s.sizes, s.idx, w, n, &copies), GV_OK);
        assert_int_equal(copies, 0);
        for (int i = 0; i < 8; ++i)
            assert_unit_close(&n[3 * perm[i]], pos[i][0] - 0.5, pos[i][1] - 0.5, pos[i][2] - 0.5);
    }
}

static void test_normals_weightings(void **state)
{
    (void)state;
    /* Vertex 0 at the origin with two triangles: (0, v1, v2) with unit
     * normal (0,0,1) and a right angle at 0, and (0, v2, v3) with
     * v3 = (-1,1,1): normal v2 x v3 = (1,0,1), unit (1,0,1)/sqrt2, and
     * sin(angle) = |v2 x v3| / (|v2||v3|) = sqrt(2/3).
     *  - unweighted: (0,0,1) + (1,0,1)/sqrt2;
     *  - sine-weighted: (0,0,1) + (1,0,1)/sqrt3;
     *  - CGAL's most visible normal of two face normals: their bisector,
     *    the unweighted sum. */
    soup s = {0};
    add_v(&s, 0, 0, 0);
    add_v(&s, 1, 0, 0);
    add_v(&s, 0, 1, 0);
    add_v(&s, -1, 1, 1);
    add_tri(&s, 0, 1, 2);
    add_tri(&s, 0, 2, 3);
    double n[12];
    const double r2 = sqrt(2.0), r3 = sqrt(3.0);
    assert_int_equal(gv_vertex_normals(s.nv, s.xyz, s.nf, s.sizes, s.idx, GV_NORMALS_UNWEIGHTED, n, NULL),
                     GV_OK);
    assert_unit_close(&n[0], 1 / r2, 0, 1 + 1 / r2);
    assert_unit_close(&n[3], 0, 0, 1); /* vertex 1: one face */
    assert_unit_close(&n[9], 1, 0, 1);  /* vertex 3: one face */
    assert_int_equal(gv_vertex_normals(s.nv, s.xyz, s.nf, s.sizes, s.idx, GV_NORMALS_SINE, n, NULL), GV_OK);
    assert_unit_close(&n[0], 1 / r3, 0, 1 + 1 / r3);
    assert_int_equal(gv_vertex_normals(s.nv, s.xyz, s.nf, s.sizes, s.idx, GV_NORMALS_CGAL, n, NULL), GV_OK);
    assert_unit_close(&n[0], 1 / r2, 0, 1 + 1 / r2);
    assert_unit_close(&n[6], 1 / r2, 0, 1 + 1 / r2); /* vertex 2 has both faces too */

    /* Bow-tie: vertex 0 is split; both fans face +z, so the kept fan gives
     * (0,0,1); an isolated vertex gets (0,0,0). */
    soup b = {0};
    add_v(&b, 0, 0, 0);
    add_v(&b, 1, -0.5, 0);
    add_v(&b, 1, 0.5, 0);
    add_v(&b, -1, 0.5, 0);
    add_v(&b, -1, -0.5, 0);
    add_v(&b, 7, 7, 7);
    add_tri(&b, 0, 1, 2);
    add_tri(&b, 0, 3, 4);
    double m[18];
    size_t copies = 0;
    assert_int_equal(gv_vertex_normals(b.nv, b.xyz, b.nf, b.sizes, b.idx, GV_NORMALS_CGAL, m, &copies), GV_OK);
    assert_int_equal(copies, 1);
    for (int i = 0; i < 5; ++i)
        assert_unit_close(&m[3 * i], 0, 0, 1);
    assert_true(m[15] == 0 && m[16] == 0 && m[17] == 0);

    /* Errors zero the output. */
    assert_int_equal(gv_vertex_normals(b.nv, b.xyz, b.nf, b.sizes, b.idx, 7, m, NULL), GV_ERR_INVALID);
    assert_true(m[2] == 0);
    assert_int_equal(gv_vertex_normals(b.nv, b.xyz, b.nf, b.sizes, b.idx, GV_NORMALS_CGAL, NULL, NULL),
                     GV_ERR_INVALID);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tetrahedron),
        cmocka_unit_test(test_open_square),
        cmocka_unit_test(test_torus),
        cmocka_unit_test(test_cylinder_and_isolated),
        cmocka_unit_test(test_bowtie),
        cmocka_unit_test(test_inconsistent_and_nonmanifold_edge),
        cmocka_unit_test(test_self_intersection),
        cmocka_unit_test(test_invalid_input),
        cmocka_unit_test(test_normals_cube),
        cmocka_unit_test(test_normals_weightings),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
