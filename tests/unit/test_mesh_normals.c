/*
 * Face, vertex and corner normals against closed forms:
 *  - an axis-aligned box [0,a]x[0,b]x[0,c] whose faces are split along one
 *    diagonal (so corners lie in 1 or 2 triangles of a face): uniform and
 *    area weights give sum_f count_f(v) * w_f * n_f, angle weights
 *    (+-1,+-1,+-1)/sqrt(3) (the angles of a face at a corner always sum to
 *    pi/2), Max weights the radial direction (v - centre) (the corners lie
 *    on the circumscribed sphere; per face the weights add to n_f / (p q));
 *  - the octahedron, where symmetry makes every weighting radial;
 *  - a UV sphere with randomly jittered vertices on the sphere, where only
 *    Max's weights are exact (Max 1999);
 *  - degenerate faces, isolated vertices, polygons, corner normals with
 *    crease angles and seams.
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

#define PI 3.14159265358979323846

static geom_mesh *mk(size_t nv, const double *xyz, size_t nf, const uint32_t *sizes,
                     const uint32_t *idx)
{
    geom_mesh *m = geom_mesh_create(NULL);
    assert_non_null(m);
    assert_int_equal(geom_mesh_build(m, nv, xyz, nf, sizes, idx, NULL, NULL, NULL), GEOM_OK);
    return m;
}

static void expect_vec(const double *got, double x, double y, double z, double tol)
{
    double l = sqrt(x * x + y * y + z * z);
    if (l > 0) {
        x /= l;
        y /= l;
        z /= l;
    }
    if (!(fabs(got[0] - x) <= tol && fabs(got[1] - y) <= tol && fabs(got[2] - z) <= tol))
        fail_msg("got (%.17g %.17g %.17g) expected (%.17g %.17g %.17g)", got[0], got[1], got[2],
                 x, y, z);
}

/* ------------------------------------------------------------------ box */

static const uint32_t box_quads[6][4] = {
    {0, 2, 3, 1}, /* z = 0, -z */
    {4, 5, 7, 6}, /* z = c, +z */
    {0, 1, 5, 4}, /* y = 0, -y */
    {2, 6, 7, 3}, /* y = b, +y */
    {0, 4, 6, 2}, /* x = 0, -x */
    {1, 3, 7, 5}, /* x = a, +x */
};
static const double box_fn[6][3] = {{0, 0, -1}, {0, 0, 1}, {0, -1, 0},
                                    {0, 1, 0},  {-1, 0, 0}, {1, 0, 0}};

static void box_points(double a, double b, double c, double *xyz)
{
    for (int v = 0; v < 8; v++) {
        xyz[3 * v] = (v & 1) ? a : 0.0;
        xyz[3 * v + 1] = (v & 2) ? b : 0.0;
        xyz[3 * v + 2] = (v & 4) ? c : 0.0;
    }
}

/* Box with each quad (q0 q1 q2 q3) split into (q0 q1 q2), (q0 q2 q3). */
static geom_mesh *box_tris(double a, double b, double c)
{
    double xyz[24];
    box_points(a, b, c, xyz);
    uint32_t sizes[12], idx[36];
    for (int f = 0; f < 6; f++) {
        const uint32_t *q = box_quads[f];
        uint32_t t[6] = {q[0], q[1], q[2], q[0], q[2], q[3]};
        memcpy(idx + 6 * f, t, sizeof t);
        sizes[2 * f] = sizes[2 * f + 1] = 3;
    }
    return mk(8, xyz, 12, sizes, idx);
}

static geom_mesh *box_quadmesh(double a, double b, double c)
{
    double xyz[24];
    box_points(a, b, c, xyz);
    uint32_t sizes[6] = {4, 4, 4, 4, 4, 4}, idx[24];
    memcpy(idx, box_quads, sizeof idx);
    return mk(8, xyz, 6, sizes, idx);
}

/* Area of a box face ⟂ its axis. */
static double box_face_area(int f, double a, double b, double c)
{
    int axis = f / 2; /* 0: z, 1: y, 2: x */
    return axis == 0 ? a * b : (axis == 1 ? a * c : b * c);
}

static void test_box_weights(void **state)
{
    (void)state;
    const double a = 1.0, b = 2.0, c = 3.0;
    geom_mesh *m = box_tris(a, b, c);
    double n[24];
    size_t nz = 99;

    /* uniform and area: count triangles of each face at each vertex */
    for (int w = 0; w < 2; w++) {
        geom_normal_weight wt = w == 0 ? GEOM_NORMAL_WEIGHT_UNIFORM : GEOM_NORMAL_WEIGHT_AREA;
        assert_int_equal(geom_mesh_vertex_normals(m, wt, n, &nz), GEOM_OK);
        assert_int_equal(nz, 0);
        for (uint32_t v = 0; v < 8; v++) {
            double e[3] = {0, 0, 0};
            for (int f = 0; f < 6; f++) {
                const uint32_t *q = box_quads[f];
                int count = (v == q[0] || v == q[2]) ? 2 : ((v == q[1] || v == q[3]) ? 1 : 0);
                double wf = w == 0 ? 1.0 : 0.5 * box_face_area(f, a, b, c);
                for (int k = 0; k < 3; k++)
                    e[k] += count * wf * box_fn[f][k];
            }
            expect_vec(n + 3 * v, e[0], e[1], e[2], 1e-15);
        }
    }
    /* vertex 1 by hand: -z face (0 2 3 1): q3, 1 triangle; -y face
     * (0 1 5 4): q1, 1 triangle; +x face (1 3 7 5): q0, 2 triangles. So
     * uniform (2, -1, -1)/sqrt(6), but angle (1, -1, -1)/sqrt(3). */
    assert_int_equal(geom_mesh_vertex_normals(m, GEOM_NORMAL_WEIGHT_UNIFORM, n, NULL), GEOM_OK);
    expect_vec(n + 3, 2, -1, -1, 1e-15);
    assert_int_equal(geom_mesh_vertex_normals(m, GEOM_NORMAL_WEIGHT_ANGLE, n, NULL), GEOM_OK);
    expect_vec(n + 3, 1, -1, -1, 1e-15);
    for (uint32_t v = 0; v < 8; v++)
        expect_vec(n + 3 * v, (v & 1) ? 1 : -1, (v & 2) ? 1 : -1, (v & 4) ? 1 : -1, 1e-15);
    /* Max: radial from the box centre */
    assert_int_equal(geom_mesh_vertex_normals(m, GEOM_NORMAL_WEIGHT_MAX, n, NULL), GEOM_OK);
    for (uint32_t v = 0; v < 8; v++)
        expect_vec(n + 3 * v, (v & 1) ? a / 2 : -a / 2, (v & 2) ? b / 2 : -b / 2,
                   (v & 4) ? c / 2 : -c / 2, 1e-15);
    /* and the default (zero) weight is the angle weight */
    assert_int_equal(GEOM_NORMAL_WEIGHT_ANGLE, 0);
    geom_mesh_destroy(m);
}

static void test_box_polygons(void **state)
{
    (void)state;
    const double a = 1.0, b = 2.0, c = 3.0;
    geom_mesh *m = box_quadmesh(a, b, c);
    double n[24];
    size_t nz;
    /* one face of each axis per corner: uniform and angle give
     * (+-1,+-1,+-1)/sqrt(3); area weights (+-bc, +-ac, +-ab); Max radial */
    assert_int_equal(geom_mesh_vertex_normals(m, GEOM_NORMAL_WEIGHT_UNIFORM, n, &nz), GEOM_OK);
    assert_int_equal(nz, 0);
    for (uint32_t v = 0; v < 8; v++)
        expect_vec(n + 3 * v, (v & 1) ? 1 : -1, (v & 2) ? 1 : -1, (v & 4) ? 1 : -1, 1e-15);
    assert_int_equal(geom_mesh_vertex_normals(m, GEOM_NORMAL_WEIGHT_ANGLE, n, &nz), GEOM_OK);
    for (uint32_t v = 0; v < 8; v++)
        expect_vec(n + 3 * v, (v & 1) ? 1 : -1, (v & 2) ? 1 : -1, (v & 4) ? 1 : -1, 1e-15);
    assert_int_equal(geom_mesh_vertex_normals(m, GEOM_NORMAL_WEIGHT_AREA, n, &nz), GEOM_OK);
    for (uint32_t v = 0; v < 8; v++)
        expect_vec(n + 3 * v, (v & 1) ? b * c : -b * c, (v & 2) ? a * c : -a * c,
                   (v & 4) ? a * b : -a * b, 1e-15);
    assert_int_equal(geom_mesh_vertex_normals(m, GEOM_NORMAL_WEIGHT_MAX, n, &nz), GEOM_OK);
    for (uint32_t v = 0; v < 8; v++)
        expect_vec(n + 3 * v, (v & 1) ? a : -a, (v & 2) ? b : -b, (v & 4) ? c : -c, 1e-15);
    /* face normals of the quads */
    for (uint32_t f = 0; f < 6; f++) {
        double fn[3];
        assert_int_equal(geom_mesh_face_normal(m, f, fn), GEOM_OK);
        expect_vec(fn, box_fn[f][0], box_fn[f][1], box_fn[f][2], 0.0);
    }
    geom_mesh_destroy(m);
}

/* ------------------------------------------------------------ octahedron */

static void test_octahedron_radial(void **state)
{
    (void)state;
    const double r = 3.0, cx = 1.0, cy = -2.0, cz = 0.5;
    double xyz[18] = {r, 0, 0, -r, 0, 0, 0, r, 0, 0, -r, 0, 0, 0, r, 0, 0, -r};
    for (int i = 0; i < 6; i++) {
        xyz[3 * i] += cx;
        xyz[3 * i + 1] += cy;
        xyz[3 * i + 2] += cz;
    }
    /* faces (+-x, +-y, +-z) counter-clockwise from outside */
    uint32_t idx[24] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
    uint32_t sizes[8] = {3, 3, 3, 3, 3, 3, 3, 3};
    geom_mesh *m = mk(6, xyz, 8, sizes, idx);
    geom_normal_weight ws[4] = {GEOM_NORMAL_WEIGHT_ANGLE, GEOM_NORMAL_WEIGHT_UNIFORM,
                                GEOM_NORMAL_WEIGHT_AREA, GEOM_NORMAL_WEIGHT_MAX};
    for (int w = 0; w < 4; w++) {
        double n[18];
        size_t nz;
        assert_int_equal(geom_mesh_vertex_normals(m, ws[w], n, &nz), GEOM_OK);
        assert_int_equal(nz, 0);
        for (int v = 0; v < 6; v++)
            expect_vec(n + 3 * v, xyz[3 * v] - cx, xyz[3 * v + 1] - cy, xyz[3 * v + 2] - cz,
                       1e-15);
    }
    /* face normal (1,1,1)/sqrt(3) of face 0 */
    double fn[3];
    assert_int_equal(geom_mesh_face_normal(m, 0, fn), GEOM_OK);
    expect_vec(fn, 1, 1, 1, 1e-15);
    geom_mesh_destroy(m);
}

/* ------------------------------------------------- jittered UV sphere */

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static double rnd(void)
{
    rng_state = rng_state * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(rng_state >> 11) / 9007199254740992.0;
}

/* UV sphere (nlat rings between the poles, nlon segments) of radius R at
 * centre c; ring and segment angles jittered, so every vertex is on the
 * sphere but the mesh has no symmetry. */
static geom_mesh *jittered_sphere(int nlat, int nlon, double R, const double c[3])
{
    size_t nv = (size_t)nlat * nlon + 2;
    double *xyz = malloc(3 * nv * sizeof(double));
    size_t nf = (size_t)2 * nlon * nlat;
    uint32_t *sizes = malloc(nf * sizeof(uint32_t)), *idx = malloc(3 * nf * sizeof(uint32_t));
    assert_non_null(xyz);
    assert_non_null(sizes);
    assert_non_null(idx);
    for (int i = 0; i < nlat; i++) {
        for (int j = 0; j < nlon; j++) {
            double th = PI * (i + 1 + 0.35 * (rnd() - 0.5)) / (nlat + 1);
            double ph = 2 * PI * (j + 0.35 * (rnd() - 0.5)) / nlon;
            double *p = xyz + 3 * ((size_t)i * nlon + j);
            p[0] = c[0] + R * sin(th) * cos(ph);
            p[1] = c[1] + R * sin(th) * sin(ph);
            p[2] = c[2] + R * cos(th);
        }
    }
    uint32_t N = (uint32_t)nlat * nlon, S = N + 1;
    xyz[3 * N] = c[0];
    xyz[3 * N + 1] = c[1];
    xyz[3 * N + 2] = c[2] + R;
    xyz[3 * S] = c[0];
    xyz[3 * S + 1] = c[1];
    xyz[3 * S + 2] = c[2] - R;
    size_t f = 0;
    for (int j = 0; j < nlon; j++) {
        uint32_t j1 = (uint32_t)((j + 1) % nlon);
        uint32_t t[3] = {N, (uint32_t)j, j1};
        memcpy(idx + 3 * f, t, sizeof t);
        f++;
        uint32_t base = (uint32_t)(nlat - 1) * nlon;
        uint32_t u[3] = {S, base + j1, base + (uint32_t)j};
        memcpy(idx + 3 * f, u, sizeof u);
        f++;
    }
    for (int i = 0; i + 1 < nlat; i++) {
        for (int j = 0; j < nlon; j++) {
            uint32_t j1 = (uint32_t)((j + 1) % nlon);
            uint32_t a = (uint32_t)i * nlon + (uint32_t)j, b = (uint32_t)i * nlon + j1;
            uint32_t cc = (uint32_t)(i + 1) * nlon + (uint32_t)j, d = (uint32_t)(i + 1) * nlon + j1;
            /* alternate the diagonal for more irregularity */
            if ((i + j) % 2) {
                uint32_t t1[3] = {a, cc, d}, t2[3] = {a, d, b};
                memcpy(idx + 3 * f, t1, sizeof t1);
                memcpy(idx + 3 * f + 3, t2, sizeof t2);
            } else {
                uint32_t t1[3] = {a, cc, b}, t2[3] = {b, cc, d};
                memcpy(idx + 3 * f, t1, sizeof t1);
                memcpy(idx + 3 * f + 3, t2, sizeof t2);
            }
            f += 2;
        }
    }
    for (size_t i = 0; i < f; i++)
        sizes[i] = 3;
    geom_mesh *m = mk(nv, xyz, f, sizes, idx);
    free(xyz);
    free(sizes);
    free(idx);
    return m;
}

static void test_max_exact_on_sphere(void **state)
{
    (void)state;
    const double c[3] = {1.0, -2.0, 0.5}, R = 2.5;
    geom_mesh *m = jittered_sphere(9, 14, R, c);
    size_t nv = geom_mesh_n_vertices(m);
    double *n = malloc(3 * nv * sizeof(double));
    assert_non_null(n);
    const double *p = geom_mesh_cpositions(m);
    /* check the mesh really is outward: face 0 normal points away from c */
    double fn[3];
    assert_int_equal(geom_mesh_face_normal(m, 0, fn), GEOM_OK);
    assert_true(fn[2] > 0.5);

    assert_int_equal(geom_mesh_vertex_normals(m, GEOM_NORMAL_WEIGHT_MAX, n, NULL), GEOM_OK);
    double maxerr = 0.0;
    for (size_t v = 0; v < nv; v++) {
        for (int k = 0; k < 3; k++)
            maxerr = fmax(maxerr, fabs(n[3 * v + k] - (p[3 * v + k] - c[k]) / R));
    }
    assert_true(maxerr < 1e-13);
    /* the angle weights are not exact on this irregular mesh */
    assert_int_equal(geom_mesh_vertex_normals(m, GEOM_NORMAL_WEIGHT_ANGLE, n, NULL), GEOM_OK);
    double angerr = 0.0;
    for (size_t v = 0; v < nv; v++) {
        for (int k = 0; k < 3; k++)
            angerr = fmax(angerr, fabs(n[3 * v + k] - (p[3 * v + k] - c[k]) / R));
    }
    assert_true(angerr > 1e-4);
    free(n);
    geom_mesh_destroy(m);
}

/* ---------------------------------------------- degenerate and isolated */

static void test_degenerate_and_isolated(void **state)
{
    (void)state;
    /* triangle 0 (0,1,2) in z = 0; triangle 1 (0,2,3) with 3 on the line
     * through 0 and 2 (zero area); triangle 2 (2,1,5) with 5 at the
     * position of 1 (zero area); vertices 4 and 6 isolated. */
    double xyz[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 2, 0, 7, 7, 7, 1, 0, 0, 5, 5, 0};
    uint32_t sizes[] = {3, 3, 3};
    uint32_t idx[] = {0, 1, 2, 0, 2, 3, 2, 1, 5};
    geom_mesh *m = mk(7, xyz, 3, sizes, idx);
    assert_int_equal(geom_mesh_n_vertices(m), 7);
    geom_normal_weight ws[4] = {GEOM_NORMAL_WEIGHT_ANGLE, GEOM_NORMAL_WEIGHT_UNIFORM,
                                GEOM_NORMAL_WEIGHT_AREA, GEOM_NORMAL_WEIGHT_MAX};
    for (int w = 0; w < 4; w++) {
        double n[21];
        size_t nz = 0;
        assert_int_equal(geom_mesh_vertex_normals(m, ws[w], n, &nz), GEOM_OK);
        for (int i = 0; i < 21; i++)
            assert_false(isnan(n[i]));
        expect_vec(n + 0, 0, 0, 1, 0.0);
        expect_vec(n + 3, 0, 0, 1, 0.0);
        expect_vec(n + 6, 0, 0, 1, 0.0);
        /* 3: only the degenerate triangle; 4: isolated; 5, 6: degenerate */
        for (int v = 3; v < 7; v++)
            expect_vec(n + 3 * v, 0, 0, 0, 0.0);
        assert_int_equal(nz, 4);
    }
    double fn[3] = {9, 9, 9};
    assert_int_equal(geom_mesh_face_normal(m, 1, fn), GEOM_ERR_DEGENERATE);
    expect_vec(fn, 0, 0, 0, 0.0);
    assert_int_equal(geom_mesh_face_normal(m, 2, fn), GEOM_ERR_DEGENERATE);
    assert_int_equal(geom_mesh_face_normal(m, 99, fn), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_mesh_vertex_normals(m, (geom_normal_weight)17, fn, NULL),
                     GEOM_ERR_INVALID_ARG);
    geom_mesh_destroy(m);
}

static void test_nonconvex_polygon(void **state)
{
    (void)state;
    /* L-shaped hexagon in the plane x + y + z = 1 (tilted): the normal of a
     * planar polygon is exact, and the reflex corner's angle is 3 pi / 2. */
    double uv[6][2] = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
    /* orthonormal basis of the plane */
    double e1[3] = {1 / sqrt(2.0), -1 / sqrt(2.0), 0};
    double e2[3] = {1 / sqrt(6.0), 1 / sqrt(6.0), -2 / sqrt(6.0)};
    /* e1 x e2 = (1,1,1)/sqrt(3) */
    double xyz[18];
    for (int i = 0; i < 6; i++)
        for (int k = 0; k < 3; k++)
            xyz[3 * i + k] = 0.25 + uv[i][0] * e1[k] + uv[i][1] * e2[k];
    uint32_t sizes[1] = {6}, idx[6] = {0, 1, 2, 3, 4, 5};
    geom_mesh *m = mk(6, xyz, 1, sizes, idx);
    double fn[3];
    assert_int_equal(geom_mesh_face_normal(m, 0, fn), GEOM_OK);
    expect_vec(fn, 1, 1, 1, 1e-15);
    double n[18];
    geom_normal_weight ws[4] = {GEOM_NORMAL_WEIGHT_ANGLE, GEOM_NORMAL_WEIGHT_UNIFORM,
                                GEOM_NORMAL_WEIGHT_AREA, GEOM_NORMAL_WEIGHT_MAX};
    for (int w = 0; w < 4; w++) {
        size_t nz;
        assert_int_equal(geom_mesh_vertex_normals(m, ws[w], n, &nz), GEOM_OK);
        for (int v = 0; v < 6; v++) {
            if (ws[w] == GEOM_NORMAL_WEIGHT_MAX && v == 3) {
                /* Max at a reflex corner: sin(3 pi / 2) < 0 flips it */
                expect_vec(n + 3 * v, -1, -1, -1, 1e-15);
            } else {
                expect_vec(n + 3 * v, 1, 1, 1, 1e-15);
            }
        }
    }
    geom_mesh_destroy(m);
}

/* -------------------------------------------------------- corner normals */

static void test_corner_normals_crease(void **state)
{
    (void)state;
    geom_mesh *m = box_tris(1.0, 1.0, 1.0);
    geom_corner_normal_options o;
    memset(&o, 0, sizeof o);
    o.crease_degrees = 30.0;
    uint32_t id = 77;
    assert_int_equal(geom_mesh_corner_normals(m, &o, &id), GEOM_OK);
    assert_int_equal(id, geom_mesh_channel_find(m, "normal", GEOM_MESH_DOMAIN_CORNER));
    assert_int_equal(geom_mesh_channel_ncomp(m, id), 3);
    /* hard at 30 degrees: every corner gets its face's normal; 8 corners x 3
     * faces = 24 fans (the diagonals are flat and do not split) */
    assert_int_equal(geom_mesh_channel_size(m, id), 24);
    const uint32_t *ix = geom_mesh_corner_cindices(m, id);
    const double *d = geom_mesh_channel_cdata(m, id);
    size_t nh = geom_mesh_n_halfedges(m);
    for (uint32_t h = 0; h < nh; h++) {
        uint32_t f = geom_mesh_he_face(m, h);
        if (f == GEOM_INVALID_INDEX) {
            assert_int_equal(ix[h], GEOM_INVALID_INDEX);
            continue;
        }
        const double *fn = box_fn[f / 2];
        expect_vec(d + 3 * ix[h], fn[0], fn[1], fn[2], 1e-15);
    }
    /* smooth at 100 degrees: one fan per vertex, the angle-weighted normal */
    o.crease_degrees = 100.0;
    assert_int_equal(geom_mesh_corner_normals(m, &o, &id), GEOM_OK);
    assert_int_equal(geom_mesh_channel_size(m, id), 8);
    ix = geom_mesh_corner_cindices(m, id);
    d = geom_mesh_channel_cdata(m, id);
    const double *p = geom_mesh_cpositions(m);
    for (uint32_t h = 0; h < nh; h++) {
        if (geom_mesh_he_face(m, h) == GEOM_INVALID_INDEX)
            continue;
        const double *q = p + 3 * geom_mesh_he_vertex(m, h);
        expect_vec(d + 3 * ix[h], q[0] - 0.5, q[1] - 0.5, q[2] - 0.5, 1e-15);
    }
    /* the default (0) means no crease splitting */
    o.crease_degrees = 0.0;
    assert_int_equal(geom_mesh_corner_normals(m, &o, &id), GEOM_OK);
    assert_int_equal(geom_mesh_channel_size(m, id), 8);
    assert_int_equal(geom_mesh_corner_normals(m, NULL, &id), GEOM_OK);
    assert_int_equal(geom_mesh_channel_size(m, id), 8);
    /* exactly one "normal" corner channel */
    size_t count = 0;
    for (uint32_t c = 0; c < geom_mesh_channel_count(m); c++)
        count += strcmp(geom_mesh_channel_name(m, c), "normal") == 0;
    assert_int_equal(count, 1);
    o.crease_degrees = -1.0;
    assert_int_equal(geom_mesh_corner_normals(m, &o, &id), GEOM_ERR_INVALID_ARG);
    geom_mesh_destroy(m);
}

/* A flat 2x1 grid of quads split at a UV seam down the middle: the seam
 * splits the middle vertices' fans, and boundary edges never merge fans. */
static void test_corner_normals_seam(void **state)
{
    (void)state;
    double xyz[] = {0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 1, 1, 0, 2, 1, 0};
    uint32_t sizes[] = {4, 4}, idx[] = {0, 1, 4, 3, 1, 2, 5, 4};
    geom_mesh *m = mk(6, xyz, 2, sizes, idx);
    uint32_t uv;
    assert_int_equal(geom_mesh_channel_add(m, "uv", GEOM_MESH_DOMAIN_CORNER, 2, &uv), GEOM_OK);
    assert_int_equal(geom_mesh_corner_pool_resize(m, uv, 8), GEOM_OK);
    uint32_t *ix = geom_mesh_corner_indices(m, uv);
    /* left face corners 0..3, right face corners 4..7: no sharing */
    uint32_t next = 0;
    for (uint32_t f = 0; f < 2; f++) {
        uint32_t h0 = geom_mesh_face_he(m, f), h = h0;
        do {
            ix[h] = next++;
            h = geom_mesh_he_next(m, h);
        } while (h != h0);
    }
    geom_corner_normal_options o;
    memset(&o, 0, sizeof o);
    uint32_t id;
    assert_int_equal(geom_mesh_corner_normals(m, &o, &id), GEOM_OK);
    assert_int_equal(geom_mesh_channel_size(m, id), 6); /* one per vertex */
    o.split_at_channel_plus_one = uv + 1;
    assert_int_equal(geom_mesh_corner_normals(m, &o, &id), GEOM_OK);
    assert_int_equal(geom_mesh_channel_size(m, id), 8); /* middle vertices split */
    const double *d = geom_mesh_channel_cdata(m, id);
    for (size_t i = 0; i < 8; i++)
        expect_vec(d + 3 * i, 0, 0, 1, 0.0);
    o.split_at_channel_plus_one = 1; /* "position" is not a corner channel */
    assert_int_equal(geom_mesh_corner_normals(m, &o, &id), GEOM_ERR_INVALID_ARG);
    geom_mesh_destroy(m);
}

/* ------------------------------------------------ allocation failures */

static void test_out_of_memory(void **state)
{
    (void)state;
    double xyz[24];
    box_points(1.0, 2.0, 3.0, xyz);
    uint32_t sizes[6] = {4, 4, 4, 4, 4, 4}, idx[24];
    memcpy(idx, box_quads, sizeof idx);
    int ok_v = 0, ok_c = 0;
    for (long k = 0; k < 200 && !(ok_v && ok_c); k++) {
        oom_state s = {-1, 0, 0};
        geom_allocator a = {oom_alloc, NULL, oom_free, &s};
        geom_mesh *m = geom_mesh_create(&a);
        assert_non_null(m);
        assert_int_equal(geom_mesh_build(m, 8, xyz, 6, sizes, idx, NULL, NULL, NULL), GEOM_OK);
        double n[24];
        s.budget = k;
        geom_status st = geom_mesh_vertex_normals(m, GEOM_NORMAL_WEIGHT_AREA, n, NULL);
        assert_true(st == GEOM_OK || st == GEOM_ERR_NOMEM);
        ok_v |= st == GEOM_OK;
        s.budget = k;
        geom_corner_normal_options o = {GEOM_NORMAL_WEIGHT_ANGLE, 30.0, 0};
        uint32_t id;
        st = geom_mesh_corner_normals(m, &o, &id);
        assert_true(st == GEOM_OK || st == GEOM_ERR_NOMEM);
        s.budget = -1;
        if (st == GEOM_OK) {
            ok_c = 1;
            assert_int_equal(geom_mesh_channel_size(m, id), 24);
        }
        size_t nd;
        assert_int_equal(geom_mesh_validate(m, NULL, 0, &nd), GEOM_OK);
        assert_int_equal(nd, 0);
        geom_mesh_destroy(m);
        assert_int_equal(s.live, 0);
        assert_false(s.bad_free);
    }
    assert_true(ok_v && ok_c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_box_weights),
        cmocka_unit_test(test_box_polygons),
        cmocka_unit_test(test_octahedron_radial),
        cmocka_unit_test(test_max_exact_on_sphere),
        cmocka_unit_test(test_degenerate_and_isolated),
        cmocka_unit_test(test_nonconvex_polygon),
        cmocka_unit_test(test_corner_normals_crease),
        cmocka_unit_test(test_corner_normals_seam),
        cmocka_unit_test(test_out_of_memory),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
