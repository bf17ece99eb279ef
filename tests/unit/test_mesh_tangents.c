/*
 * MikkTSpace-compatible tangents against closed forms:
 *  - a tilted planar grid with an affine UV map uv = A (s, t) + b over plane
 *    coordinates (s, t): P is affine in (u, v), so every tangent must be
 *    dP/du = E A^-1 e_u exactly (normalised) and the bitangent sign
 *    w = sign(det A); mirroring u flips the tangent and w;
 *  - a strip whose right half is UV-mirrored about the shared edge: the seam
 *    corners keep their own side's frame (groups split by orientation);
 *  - an open cylinder with uv = (angle / 2 pi, z): tangent (-sin, cos, 0),
 *    w = +1, after Gram-Schmidt against smooth normals;
 *  - degenerate UVs: finite unit tangents orthogonal to the normal.
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

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static void cross3(const double *a, const double *b, double *o)
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}
static void unit(double *v)
{
    double l = sqrt(dot3(v, v));
    v[0] /= l;
    v[1] /= l;
    v[2] /= l;
}

/* Give every corner its own UV pool entry computed by fn(vertex position,
 * face) so seams can be made per face. */
typedef void (*uv_fn)(const double *p, uint32_t face, void *user, double uv[2]);
static uint32_t set_uv(geom_mesh *m, uv_fn fn, void *user)
{
    uint32_t id;
    assert_int_equal(geom_mesh_channel_add(m, "uv", GEOM_MESH_DOMAIN_CORNER, 2, &id), GEOM_OK);
    size_t nh = geom_mesh_n_halfedges(m), n = 0;
    for (uint32_t h = 0; h < nh; h++)
        n += geom_mesh_he_face(m, h) != GEOM_INVALID_INDEX;
    assert_int_equal(geom_mesh_corner_pool_resize(m, id, n), GEOM_OK);
    uint32_t *ix = geom_mesh_corner_indices(m, id);
    double *d = geom_mesh_channel_data(m, id);
    const double *p = geom_mesh_cpositions(m);
    uint32_t k = 0;
    for (uint32_t h = 0; h < nh; h++) {
        uint32_t f = geom_mesh_he_face(m, h);
        if (f == GEOM_INVALID_INDEX)
            continue;
        fn(p + 3 * geom_mesh_he_vertex(m, h), f, user, d + 2 * k);
        ix[h] = k++;
    }
    return id;
}

/* ------------------------------------------------------- affine plane */

typedef struct plane_map {
    double o[3], e1[3], e2[3]; /* plane frame: P = o + s e1 + t e2 */
    double A[4];               /* uv = A (s,t) + b, row-major */
    double b[2];
} plane_map;

static void plane_uv(const double *p, uint32_t f, void *user, double uv[2])
{
    (void)f;
    const plane_map *pm = user;
    double d[3] = {p[0] - pm->o[0], p[1] - pm->o[1], p[2] - pm->o[2]};
    double s = dot3(d, pm->e1), t = dot3(d, pm->e2);
    uv[0] = pm->A[0] * s + pm->A[1] * t + pm->b[0];
    uv[1] = pm->A[2] * s + pm->A[3] * t + pm->b[1];
}

static geom_mesh *plane_grid(const plane_map *pm, int nx, int ny)
{
    size_t nv = (size_t)(nx + 1) * (ny + 1);
    double *xyz = malloc(3 * nv * sizeof(double));
    uint32_t *sizes = malloc((size_t)nx * ny * sizeof(uint32_t));
    uint32_t *idx = malloc(4 * (size_t)nx * ny * sizeof(uint32_t));
    assert_true(xyz && sizes && idx);
    for (int j = 0; j <= ny; j++) {
        for (int i = 0; i <= nx; i++) {
            /* irregular spacing: the map stays affine */
            double s = i + 0.3 * sin(1.7 * i + j), t = j + 0.25 * cos(2.3 * j + i);
            double *q = xyz + 3 * ((size_t)j * (nx + 1) + i);
            for (int k = 0; k < 3; k++)
                q[k] = pm->o[k] + s * pm->e1[k] + t * pm->e2[k];
        }
    }
    size_t f = 0;
    for (int j = 0; j < ny; j++) {
        for (int i = 0; i < nx; i++) {
            uint32_t a = (uint32_t)(j * (nx + 1) + i);
            uint32_t q[4] = {a, a + 1, a + 1 + (uint32_t)(nx + 1), a + (uint32_t)(nx + 1)};
            memcpy(idx + 4 * f, q, sizeof q);
            sizes[f++] = 4;
        }
    }
    geom_mesh *m = mk(nv, xyz, f, sizes, idx);
    free(xyz);
    free(sizes);
    free(idx);
    return m;
}

static void make_frame(plane_map *pm)
{
    double e1[3] = {1.0, 2.0, 0.5}, t[3] = {-0.5, 0.3, 1.0}, e2[3];
    unit(e1);
    double d = dot3(t, e1);
    for (int k = 0; k < 3; k++)
        e2[k] = t[k] - d * e1[k];
    unit(e2);
    memcpy(pm->e1, e1, sizeof e1);
    memcpy(pm->e2, e2, sizeof e2);
    pm->o[0] = 3.0;
    pm->o[1] = -1.0;
    pm->o[2] = 2.0;
}

/* dP/du and dP/dv for uv = A (s,t) + b: [dP/du dP/dv] = E A^-1. */
static void plane_derivs(const plane_map *pm, double du[3], double dv[3])
{
    double det = pm->A[0] * pm->A[3] - pm->A[1] * pm->A[2];
    double inv[4] = {pm->A[3] / det, -pm->A[1] / det, -pm->A[2] / det, pm->A[0] / det};
    for (int k = 0; k < 3; k++) {
        du[k] = pm->e1[k] * inv[0] + pm->e2[k] * inv[2];
        dv[k] = pm->e1[k] * inv[1] + pm->e2[k] * inv[3];
    }
}

static void check_plane(const plane_map *pm, double expect_w)
{
    geom_mesh *m = plane_grid(pm, 4, 3);
    set_uv(m, plane_uv, (void *)pm);
    uint32_t tid = 0;
    assert_int_equal(geom_mesh_tangents(m, &tid), GEOM_OK);
    assert_int_equal(tid, geom_mesh_channel_find(m, "tangent", GEOM_MESH_DOMAIN_CORNER));
    assert_int_equal(geom_mesh_channel_ncomp(m, tid), 4);
    /* the normals were computed as they were missing */
    assert_true(geom_mesh_channel_find(m, "normal", GEOM_MESH_DOMAIN_CORNER) !=
                GEOM_INVALID_INDEX);
    double du[3], dv[3], n[3];
    plane_derivs(pm, du, dv);
    cross3(pm->e1, pm->e2, n);
    double tu[3] = {du[0], du[1], du[2]};
    unit(tu);
    const uint32_t *ix = geom_mesh_corner_cindices(m, tid);
    const double *d = geom_mesh_channel_cdata(m, tid);
    size_t nh = geom_mesh_n_halfedges(m);
    for (uint32_t h = 0; h < nh; h++) {
        if (geom_mesh_he_face(m, h) == GEOM_INVALID_INDEX)
            continue;
        const double *t4 = d + 4 * ix[h];
        for (int k = 0; k < 3; k++)
            assert_true(fabs(t4[k] - tu[k]) < 1e-14);
        assert_true(t4[3] == expect_w);
        /* bitangent = w * (n x t) goes along dP/dv */
        double bt[3];
        cross3(n, t4, bt);
        assert_true(t4[3] * dot3(bt, dv) > 0.0);
    }
    geom_mesh_destroy(m);
}

static void test_affine_plane(void **state)
{
    (void)state;
    plane_map pm;
    make_frame(&pm);
    /* shear + scale, det > 0 */
    double A[4] = {0.7, 0.4, -0.2, 1.3};
    memcpy(pm.A, A, sizeof A);
    pm.b[0] = 0.25;
    pm.b[1] = -3.0;
    check_plane(&pm, 1.0);
    /* mirrored in u: det < 0, w = -1 and dP/du reverses */
    pm.A[0] = -0.7;
    pm.A[1] = -0.4;
    check_plane(&pm, -1.0);
    /* identity: the tangent is e1 itself */
    double I[4] = {1, 0, 0, 1};
    memcpy(pm.A, I, sizeof I);
    check_plane(&pm, 1.0);
}

/* ------------------------------------------------------ mirrored seam */

static void mirror_uv(const double *p, uint32_t f, void *user, double uv[2])
{
    (void)user;
    /* strip in z = 0, x in [0, 2], y in [0, 1]; faces 0,1 left (x <= 1),
     * 2,3 right: u = x on the left, u = 2 - x on the right */
    uv[0] = f < 2 ? p[0] : 2.0 - p[0];
    uv[1] = p[1];
}

static void test_mirrored_seam(void **state)
{
    (void)state;
    double xyz[] = {0, 0, 0, 0.5, 0, 0, 1, 0, 0, 1.5, 0, 0, 2, 0, 0,
                    0, 1, 0, 0.5, 1, 0, 1, 1, 0, 1.5, 1, 0, 2, 1, 0};
    uint32_t sizes[] = {4, 4, 4, 4};
    uint32_t idx[] = {0, 1, 6, 5, 1, 2, 7, 6, 2, 3, 8, 7, 3, 4, 9, 8};
    geom_mesh *m = mk(10, xyz, 4, sizes, idx);
    set_uv(m, mirror_uv, NULL);
    /* merge the uv indices at the seam so the seam vertices have one
     * identity (same position, normal, uv): only the orientation differs */
    uint32_t uv = geom_mesh_channel_find(m, "uv", GEOM_MESH_DOMAIN_CORNER);
    uint32_t *uix = geom_mesh_corner_indices(m, uv);
    const double *ud = geom_mesh_channel_cdata(m, uv);
    size_t nh = geom_mesh_n_halfedges(m);
    for (uint32_t h = 0; h < nh; h++) {
        for (uint32_t g = 0; g < h; g++) {
            if (uix[h] != GEOM_INVALID_INDEX && uix[g] != GEOM_INVALID_INDEX &&
                geom_mesh_he_vertex(m, h) == geom_mesh_he_vertex(m, g) &&
                ud[2 * uix[h]] == ud[2 * uix[g]] && ud[2 * uix[h] + 1] == ud[2 * uix[g] + 1]) {
                uix[h] = uix[g];
                break;
            }
        }
    }
    uint32_t tid;
    assert_int_equal(geom_mesh_tangents(m, &tid), GEOM_OK);
    const uint32_t *ix = geom_mesh_corner_cindices(m, tid);
    const double *d = geom_mesh_channel_cdata(m, tid);
    for (uint32_t h = 0; h < nh; h++) {
        uint32_t f = geom_mesh_he_face(m, h);
        if (f == GEOM_INVALID_INDEX)
            continue;
        const double *t4 = d + 4 * ix[h];
        double sx = f < 2 ? 1.0 : -1.0;
        assert_true(fabs(t4[0] - sx) < 1e-15);
        assert_true(fabs(t4[1]) < 1e-15 && fabs(t4[2]) < 1e-15);
        assert_true(t4[3] == sx);
    }
    geom_mesh_destroy(m);
}

/* ------------------------------------------------------------ cylinder */

static void cyl_uv(const double *p, uint32_t f, void *user, double uv[2])
{
    (void)user;
    (void)f;
    double a = atan2(p[1], p[0]);
    if (a < 0)
        a += 2 * PI;
    uv[0] = a / (2 * PI);
    uv[1] = p[2];
}

static void test_cylinder(void **state)
{
    (void)state;
    const int nseg = 24, nring = 4;
    size_t nv = (size_t)nseg * (nring + 1);
    double *xyz = malloc(3 * nv * sizeof(double));
    uint32_t *sizes = malloc((size_t)nseg * nring * sizeof(uint32_t));
    uint32_t *idx = malloc(4 * (size_t)nseg * nring * sizeof(uint32_t));
    assert_true(xyz && sizes && idx);
    for (int r = 0; r <= nring; r++) {
        for (int s = 0; s < nseg; s++) {
            double a = 2 * PI * (s + 0.5) / nseg;
            double *q = xyz + 3 * ((size_t)r * nseg + s);
            q[0] = 2.0 * cos(a);
            q[1] = 2.0 * sin(a);
            q[2] = 0.5 * r;
        }
    }
    size_t f = 0;
    for (int r = 0; r < nring; r++) {
        for (int s = 0; s < nseg; s++) {
            uint32_t a = (uint32_t)(r * nseg + s), b = (uint32_t)(r * nseg + (s + 1) % nseg);
            uint32_t q[4] = {a, b, b + (uint32_t)nseg, a + (uint32_t)nseg};
            memcpy(idx + 4 * f, q, sizeof q);
            sizes[f++] = 4;
        }
    }
    geom_mesh *m = mk(nv, xyz, f, sizes, idx);
    free(xyz);
    free(sizes);
    free(idx);
    /* uv per corner, with the seam: the last column's corners at angle
     * ~0 get u + 1 */
    uint32_t uv = set_uv(m, cyl_uv, NULL);
    {
        uint32_t *uix = geom_mesh_corner_indices(m, uv);
        double *ud = geom_mesh_channel_data(m, uv);
        size_t nh = geom_mesh_n_halfedges(m);
        for (uint32_t fc = 0; fc < geom_mesh_n_faces(m); fc++) {
            uint32_t h0 = geom_mesh_face_he(m, fc), h = h0;
            double umax = 0;
            do {
                umax = fmax(umax, ud[2 * uix[h]]);
                h = geom_mesh_he_next(m, h);
            } while (h != h0);
            do {
                if (umax - ud[2 * uix[h]] > 0.5)
                    ud[2 * uix[h]] += 1.0;
                h = geom_mesh_he_next(m, h);
            } while (h != h0);
        }
        (void)nh;
    }
    uint32_t tid;
    assert_int_equal(geom_mesh_tangents(m, &tid), GEOM_OK);
    const uint32_t *ix = geom_mesh_corner_cindices(m, tid);
    const double *d = geom_mesh_channel_cdata(m, tid);
    uint32_t nid = geom_mesh_channel_find(m, "normal", GEOM_MESH_DOMAIN_CORNER);
    const uint32_t *nix = geom_mesh_corner_cindices(m, nid);
    const double *nd = geom_mesh_channel_cdata(m, nid);
    const double *p = geom_mesh_cpositions(m);
    size_t nh = geom_mesh_n_halfedges(m);
    for (uint32_t h = 0; h < nh; h++) {
        if (geom_mesh_he_face(m, h) == GEOM_INVALID_INDEX)
            continue;
        const double *q = p + 3 * geom_mesh_he_vertex(m, h);
        double a = atan2(q[1], q[0]);
        const double *t4 = d + 4 * ix[h];
        const double *n = nd + 3 * nix[h];
        assert_true(fabs(t4[0] + sin(a)) < 1e-14);
        assert_true(fabs(t4[1] - cos(a)) < 1e-14);
        assert_true(fabs(t4[2]) < 1e-14);
        assert_true(fabs(dot3(t4, n)) < 1e-14);
        assert_true(t4[3] == 1.0);
    }
    geom_mesh_destroy(m);
}

/* --------------------------------------------------------- degenerate */

static void zero_uv(const double *p, uint32_t f, void *user, double uv[2])
{
    (void)f;
    const int *mode = user;
    if (*mode == 0) {
        uv[0] = uv[1] = 0.0; /* all corners at one UV */
    } else {
        uv[0] = p[0] + p[1]; /* collinear UVs */
        uv[1] = 2.0 * (p[0] + p[1]);
    }
}

static void test_degenerate_uv(void **state)
{
    (void)state;
    plane_map pm;
    make_frame(&pm);
    for (int mode = 0; mode < 2; mode++) {
        geom_mesh *m = plane_grid(&pm, 2, 2);
        set_uv(m, zero_uv, &mode);
        uint32_t tid;
        assert_int_equal(geom_mesh_tangents(m, &tid), GEOM_OK);
        const uint32_t *ix = geom_mesh_corner_cindices(m, tid);
        const double *d = geom_mesh_channel_cdata(m, tid);
        double n[3];
        cross3(pm.e1, pm.e2, n);
        size_t nh = geom_mesh_n_halfedges(m);
        for (uint32_t h = 0; h < nh; h++) {
            if (geom_mesh_he_face(m, h) == GEOM_INVALID_INDEX)
                continue;
            const double *t4 = d + 4 * ix[h];
            for (int k = 0; k < 4; k++)
                assert_true(isfinite(t4[k]));
            assert_true(fabs(dot3(t4, t4) - 1.0) < 1e-14);
            assert_true(fabs(dot3(t4, n)) < 1e-14);
            assert_true(t4[3] == 1.0 || t4[3] == -1.0);
        }
        geom_mesh_destroy(m);
    }
}

static void test_no_uv(void **state)
{
    (void)state;
    double xyz[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    uint32_t sizes[] = {3}, idx[] = {0, 1, 2};
    geom_mesh *m = mk(3, xyz, 1, sizes, idx);
    uint32_t tid;
    assert_int_equal(geom_mesh_tangents(m, &tid), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_mesh_tangents(NULL, &tid), GEOM_ERR_INVALID_ARG);
    geom_mesh_destroy(m);
}

/* ------------------------------------------------ allocation failures */

static void test_out_of_memory(void **state)
{
    (void)state;
    plane_map pm;
    make_frame(&pm);
    double A[4] = {0.7, 0.4, -0.2, 1.3};
    memcpy(pm.A, A, sizeof A);
    pm.b[0] = pm.b[1] = 0.0;
    geom_mesh *src = plane_grid(&pm, 3, 2);
    set_uv(src, plane_uv, &pm);
    uint32_t *sizes = NULL, *idx = NULL;
    size_t ni = 0, nf = geom_mesh_n_faces(src), nv = geom_mesh_n_vertices(src);
    assert_int_equal(geom_mesh_to_soup(src, NULL, NULL, &ni), GEOM_OK);
    sizes = malloc(nf * sizeof(uint32_t));
    idx = malloc(ni * sizeof(uint32_t));
    assert_true(sizes && idx);
    assert_int_equal(geom_mesh_to_soup(src, sizes, idx, &ni), GEOM_OK);
    int ok = 0;
    for (long k = 0; k < 400 && !ok; k++) {
        oom_state s = {-1, 0, 0};
        geom_allocator a = {oom_alloc, NULL, oom_free, &s};
        geom_mesh *m = geom_mesh_create(&a);
        assert_non_null(m);
        assert_int_equal(geom_mesh_build(m, nv, geom_mesh_cpositions(src), nf, sizes, idx, NULL,
                                         NULL, NULL),
                         GEOM_OK);
        set_uv(m, plane_uv, &pm);
        s.budget = k;
        uint32_t tid;
        geom_status st = geom_mesh_tangents(m, &tid);
        assert_true(st == GEOM_OK || st == GEOM_ERR_NOMEM);
        s.budget = -1;
        if (st == GEOM_OK) {
            ok = 1;
            assert_int_equal(geom_mesh_channel_ncomp(m, tid), 4);
        }
        geom_mesh_destroy(m);
        assert_int_equal(s.live, 0);
        assert_false(s.bad_free);
    }
    assert_true(ok);
    free(sizes);
    free(idx);
    geom_mesh_destroy(src);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_affine_plane),
        cmocka_unit_test(test_mirrored_seam),
        cmocka_unit_test(test_cylinder),
        cmocka_unit_test(test_degenerate_uv),
        cmocka_unit_test(test_no_uv),
        cmocka_unit_test(test_out_of_memory),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
