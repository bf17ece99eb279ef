/*
 * Vertex normals against CGAL 5.5's compute_vertex_normals (through
 * gv_vertex_normals, see geom_validate.h for what CGAL computes).
 *
 * Which of ours matches CGAL's scheme (read from
 * CGAL/Polygon_mesh_processing/compute_normal.h, 5.5.1):
 *  - CGAL's default is Aubry et al.'s "most visible" normal (the centre of
 *    the smallest spherical cap holding the incident face normals), falling
 *    back to a sine-weighted sum; neither is one of our weightings in
 *    general;
 *  - its unweighted variant (the sum of the unit face normals, each face's
 *    normal being the normalised fan sum = Newell's area vector) is exactly
 *    GEOM_NORMAL_WEIGHT_UNIFORM: compared on every vertex of irregular
 *    triangle meshes and of a torus of non-planar quads, within 1e-12;
 *  - where the most visible normal is known in closed form ours agree with
 *    CGAL's default: at a box corner (three orthogonal face normals, the
 *    cap's centre is (+-1,+-1,+-1)/sqrt(3) however the faces are
 *    triangulated) our angle weights give exactly that; on the octahedron
 *    (symmetric) and on flat regions every weighting agrees.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "geom/mesh.h"
#include "geom_validate.h"

#define PI 3.14159265358979323846

typedef struct soup {
    size_t nv, nf, ni;
    double *xyz;
    uint32_t *sizes, *idx;
} soup;

static void soup_free(soup *s)
{
    free(s->xyz);
    free(s->sizes);
    free(s->idx);
}

static geom_mesh *soup_mesh(const soup *s)
{
    geom_mesh *m = geom_mesh_create(NULL);
    assert_non_null(m);
    geom_mesh_build_report r;
    assert_int_equal(geom_mesh_build(m, s->nv, s->xyz, s->nf, s->sizes, s->idx, NULL, &r, NULL),
                     GEOM_OK);
    assert_int_equal(r.added_vertices, 0);
    assert_int_equal(r.flipped_faces, 0);
    return m;
}

/* Max |ours - CGAL| over all vertices. */
static double compare(const soup *s, geom_normal_weight ours, int cgal)
{
    geom_mesh *m = soup_mesh(s);
    double *a = malloc(3 * s->nv * sizeof(double)), *b = malloc(3 * s->nv * sizeof(double));
    assert_true(a && b);
    size_t nz = 0, ncopies = 99;
    assert_int_equal(geom_mesh_vertex_normals(m, ours, a, &nz), GEOM_OK);
    assert_int_equal(nz, 0);
    assert_int_equal(gv_vertex_normals(s->nv, s->xyz, s->nf, s->sizes, s->idx, cgal, b, &ncopies),
                     GV_OK);
    assert_int_equal(ncopies, 0);
    double err = 0.0;
    for (size_t i = 0; i < 3 * s->nv; i++)
        err = fmax(err, fabs(a[i] - b[i]));
    free(a);
    free(b);
    geom_mesh_destroy(m);
    return err;
}

static uint64_t rng = 0x243f6a8885a308d3ull;
static double rnd(void)
{
    rng = rng * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(rng >> 11) / 9007199254740992.0;
}

/* Irregular closed triangle mesh: a UV sphere with jittered angles and
 * radii, alternating diagonals. */
static soup bumpy_sphere(int nlat, int nlon)
{
    soup s;
    s.nv = (size_t)nlat * nlon + 2;
    s.nf = (size_t)2 * nlat * nlon;
    s.xyz = malloc(3 * s.nv * sizeof(double));
    s.sizes = malloc(s.nf * sizeof(uint32_t));
    s.idx = malloc(3 * s.nf * sizeof(uint32_t));
    assert_true(s.xyz && s.sizes && s.idx);
    for (int i = 0; i < nlat; i++) {
        for (int j = 0; j < nlon; j++) {
            double th = PI * (i + 1 + 0.3 * (rnd() - 0.5)) / (nlat + 1);
            double ph = 2 * PI * (j + 0.3 * (rnd() - 0.5)) / nlon;
            double r = 1.0 + 0.05 * (rnd() - 0.5);
            double *p = s.xyz + 3 * ((size_t)i * nlon + j);
            p[0] = r * sin(th) * cos(ph);
            p[1] = r * sin(th) * sin(ph);
            p[2] = r * cos(th);
        }
    }
    uint32_t N = (uint32_t)nlat * nlon, S = N + 1;
    double pn[3] = {0, 0, 1}, ps[3] = {0, 0, -1};
    memcpy(s.xyz + 3 * N, pn, sizeof pn);
    memcpy(s.xyz + 3 * S, ps, sizeof ps);
    size_t f = 0;
    for (int j = 0; j < nlon; j++) {
        uint32_t j1 = (uint32_t)((j + 1) % nlon), base = (uint32_t)(nlat - 1) * nlon;
        uint32_t t[6] = {N, (uint32_t)j, j1, S, base + j1, base + (uint32_t)j};
        memcpy(s.idx + 3 * f, t, sizeof t);
        f += 2;
    }
    for (int i = 0; i + 1 < nlat; i++) {
        for (int j = 0; j < nlon; j++) {
            uint32_t j1 = (uint32_t)((j + 1) % nlon);
            uint32_t a = (uint32_t)i * nlon + (uint32_t)j, b = (uint32_t)i * nlon + j1;
            uint32_t c = a + (uint32_t)nlon, d = b + (uint32_t)nlon;
            if ((i + j) % 2) {
                uint32_t t[6] = {a, c, d, a, d, b};
                memcpy(s.idx + 3 * f, t, sizeof t);
            } else {
                uint32_t t[6] = {a, c, b, b, c, d};
                memcpy(s.idx + 3 * f, t, sizeof t);
            }
            f += 2;
        }
    }
    s.nf = f;
    for (size_t i = 0; i < f; i++)
        s.sizes[i] = 3;
    s.ni = 3 * f;
    return s;
}

/* Torus of quads, each vertex moved randomly: the quads are not planar. */
static soup bumpy_torus(int nu, int nv)
{
    soup s;
    s.nv = (size_t)nu * nv;
    s.nf = s.nv;
    s.xyz = malloc(3 * s.nv * sizeof(double));
    s.sizes = malloc(s.nf * sizeof(uint32_t));
    s.idx = malloc(4 * s.nf * sizeof(uint32_t));
    assert_true(s.xyz && s.sizes && s.idx);
    for (int i = 0; i < nu; i++) {
        for (int j = 0; j < nv; j++) {
            double u = 2 * PI * i / nu, v = 2 * PI * j / nv;
            double *p = s.xyz + 3 * ((size_t)i * nv + j);
            p[0] = (3.0 + cos(v)) * cos(u) + 0.04 * (rnd() - 0.5);
            p[1] = (3.0 + cos(v)) * sin(u) + 0.04 * (rnd() - 0.5);
            p[2] = sin(v) + 0.04 * (rnd() - 0.5);
        }
    }
    for (int i = 0; i < nu; i++) {
        for (int j = 0; j < nv; j++) {
            uint32_t a = (uint32_t)(i * nv + j), b = (uint32_t)(((i + 1) % nu) * nv + j);
            uint32_t c = (uint32_t)(((i + 1) % nu) * nv + (j + 1) % nv);
            uint32_t d = (uint32_t)(i * nv + (j + 1) % nv);
            uint32_t q[4] = {a, b, c, d};
            memcpy(s.idx + 4 * ((size_t)i * nv + j), q, sizeof q);
            s.sizes[(size_t)i * nv + j] = 4;
        }
    }
    s.ni = 4 * s.nf;
    return s;
}

static void test_uniform_is_cgal_unweighted(void **state)
{
    (void)state;
    soup s = bumpy_sphere(30, 50);
    assert_true(compare(&s, GEOM_NORMAL_WEIGHT_UNIFORM, GV_NORMALS_UNWEIGHTED) < 1e-12);
    /* and the other weightings are really different on this mesh */
    assert_true(compare(&s, GEOM_NORMAL_WEIGHT_AREA, GV_NORMALS_UNWEIGHTED) > 1e-4);
    soup_free(&s);
    soup t = bumpy_torus(48, 24);
    assert_true(compare(&t, GEOM_NORMAL_WEIGHT_UNIFORM, GV_NORMALS_UNWEIGHTED) < 1e-12);
    soup_free(&t);
}

static void test_box_corners_match_cgal_default(void **state)
{
    (void)state;
    static const uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                         {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    soup s;
    s.nv = 8;
    s.nf = 12;
    s.ni = 36;
    s.xyz = malloc(24 * sizeof(double));
    s.sizes = malloc(12 * sizeof(uint32_t));
    s.idx = malloc(36 * sizeof(uint32_t));
    assert_true(s.xyz && s.sizes && s.idx);
    for (int v = 0; v < 8; v++) {
        s.xyz[3 * v] = (v & 1) ? 1.0 : 0.0;
        s.xyz[3 * v + 1] = (v & 2) ? 2.0 : 0.0;
        s.xyz[3 * v + 2] = (v & 4) ? 3.0 : 0.0;
    }
    for (int f = 0; f < 6; f++) {
        const uint32_t *q = quads[f];
        uint32_t t[6] = {q[0], q[1], q[2], q[0], q[2], q[3]};
        memcpy(s.idx + 6 * f, t, sizeof t);
        s.sizes[2 * f] = s.sizes[2 * f + 1] = 3;
    }
    assert_true(compare(&s, GEOM_NORMAL_WEIGHT_ANGLE, GV_NORMALS_CGAL) < 1e-15);
    assert_true(compare(&s, GEOM_NORMAL_WEIGHT_UNIFORM, GV_NORMALS_UNWEIGHTED) < 1e-15);
    /* uniform differs from CGAL's default on this asymmetric triangulation */
    assert_true(compare(&s, GEOM_NORMAL_WEIGHT_UNIFORM, GV_NORMALS_CGAL) > 0.05);
    soup_free(&s);
}

static void test_symmetric_and_flat(void **state)
{
    (void)state;
    /* octahedron */
    double oxyz[18] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
    uint32_t oidx[24] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
    uint32_t osz[8] = {3, 3, 3, 3, 3, 3, 3, 3};
    soup o = {6, 8, 24, oxyz, osz, oidx};
    geom_normal_weight ws[4] = {GEOM_NORMAL_WEIGHT_ANGLE, GEOM_NORMAL_WEIGHT_UNIFORM,
                                GEOM_NORMAL_WEIGHT_AREA, GEOM_NORMAL_WEIGHT_MAX};
    for (int w = 0; w < 4; w++) {
        assert_true(compare(&o, ws[w], GV_NORMALS_CGAL) < 1e-15);
        assert_true(compare(&o, ws[w], GV_NORMALS_UNWEIGHTED) < 1e-15);
    }
    /* a tilted flat grid of irregular triangles (an open surface) */
    const int n = 12;
    soup g;
    g.nv = (size_t)(n + 1) * (n + 1);
    g.nf = (size_t)2 * n * n;
    g.ni = 3 * g.nf;
    g.xyz = malloc(3 * g.nv * sizeof(double));
    g.sizes = malloc(g.nf * sizeof(uint32_t));
    g.idx = malloc(g.ni * sizeof(uint32_t));
    assert_true(g.xyz && g.sizes && g.idx);
    for (int j = 0; j <= n; j++) {
        for (int i = 0; i <= n; i++) {
            double s = i + 0.3 * (rnd() - 0.5), t = j + 0.3 * (rnd() - 0.5);
            double *p = g.xyz + 3 * ((size_t)j * (n + 1) + i);
            p[0] = s;
            p[1] = t;
            p[2] = 0.25 * s - 0.5 * t + 2.0;
        }
    }
    size_t f = 0;
    for (int j = 0; j < n; j++) {
        for (int i = 0; i < n; i++) {
            uint32_t a = (uint32_t)(j * (n + 1) + i), b = a + 1, c = a + (uint32_t)n + 2,
                     d = a + (uint32_t)n + 1;
            uint32_t t[6] = {a, b, c, a, c, d};
            memcpy(g.idx + 3 * f, t, sizeof t);
            g.sizes[f] = g.sizes[f + 1] = 3;
            f += 2;
        }
    }
    for (int w = 0; w < 4; w++)
        assert_true(compare(&g, ws[w], GV_NORMALS_CGAL) < 1e-14);
    soup_free(&g);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_uniform_is_cgal_unweighted),
        cmocka_unit_test(test_box_corners_match_cgal_default),
        cmocka_unit_test(test_symmetric_and_flat),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
