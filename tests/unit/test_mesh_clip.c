/*
 * Plane and frustum clipping against closed forms: areas and volumes of
 * clipped boxes (with and without caps), exact linearity of interpolated
 * attributes, closedness of capped results (also with a hole in the cap),
 * non-convex faces split into several pieces, vertices on the plane, and
 * the frustum section of a large grid.
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

/* Surface area and enclosed (signed) volume from the live faces. */
static void area_volume(const geom_mesh *m, double *area, double *vol)
{
    const double *p = geom_mesh_cpositions(m);
    double A = 0.0, V = 0.0;
    for (uint32_t f = 0; f < geom_mesh_n_faces(m); f++) {
        if (geom_mesh_face_is_deleted(m, f))
            continue;
        uint32_t h0 = geom_mesh_face_he(m, f);
        const double *a = p + 3 * geom_mesh_he_vertex(m, h0);
        uint32_t h = geom_mesh_he_next(m, h0);
        double n[3] = {0, 0, 0};
        for (;;) {
            uint32_t hn = geom_mesh_he_next(m, h);
            if (hn == h0)
                break;
            const double *b = p + 3 * geom_mesh_he_vertex(m, h), *c = p + 3 * geom_mesh_he_vertex(m, hn);
            double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
            double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
            n[0] += u[1] * w[2] - u[2] * w[1];
            n[1] += u[2] * w[0] - u[0] * w[2];
            n[2] += u[0] * w[1] - u[1] * w[0];
            V += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                  a[2] * (b[0] * c[1] - b[1] * c[0])) /
                 6.0;
            h = hn;
        }
        A += 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    }
    *area = A;
    if (vol)
        *vol = V;
}

static size_t boundary_loops(const geom_mesh *m)
{
    size_t n = 99;
    assert_int_equal(geom_mesh_boundary_loops(m, &n, NULL), GEOM_OK);
    return n;
}

static int is_valid(const geom_mesh *m)
{
    size_t nd = 99;
    assert_int_equal(geom_mesh_validate(m, NULL, 0, &nd), GEOM_OK);
    return nd == 0;
}

/* Box [0,a]x[0,b]x[0,c], quads split into triangles when tris != 0. */
static geom_mesh *box(double a, double b, double c, int tris)
{
    static const uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                         {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    double xyz[24];
    for (int v = 0; v < 8; v++) {
        xyz[3 * v] = (v & 1) ? a : 0.0;
        xyz[3 * v + 1] = (v & 2) ? b : 0.0;
        xyz[3 * v + 2] = (v & 4) ? c : 0.0;
    }
    uint32_t sizes[12], idx[36];
    if (!tris) {
        for (int f = 0; f < 6; f++)
            sizes[f] = 4;
        memcpy(idx, quads, sizeof quads);
        return mk(8, xyz, 6, sizes, idx);
    }
    for (int f = 0; f < 6; f++) {
        const uint32_t *q = quads[f];
        uint32_t t[6] = {q[0], q[1], q[2], q[0], q[2], q[3]};
        memcpy(idx + 6 * f, t, sizeof t);
        sizes[2 * f] = sizes[2 * f + 1] = 3;
    }
    return mk(8, xyz, 12, sizes, idx);
}

static void test_box_plane(void **state)
{
    (void)state;
    for (int tris = 0; tris < 2; tris++) {
        geom_mesh *m = box(1, 1, 1, tris);
        geom_mesh *o = NULL;
        double pl[4] = {0, 0, 2, -0.6}; /* z >= 0.3, unnormalised */
        geom_clip_options opt = {0};
        assert_int_equal(geom_mesh_clip_plane(m, pl, &opt, &o), GEOM_OK);
        double A, V;
        area_volume(o, &A, &V);
        assert_true(fabs(A - 3.8) < 1e-14);
        assert_int_equal(boundary_loops(o), 1);
        assert_true(is_valid(o));
        const double *p = geom_mesh_cpositions(o);
        for (size_t v = 0; v < geom_mesh_n_vertices(o); v++)
            assert_true(p[3 * v + 2] >= 0.3 - 1e-15);
        geom_mesh_destroy(o);
        /* with caps: closed, volume 0.7 */
        opt.cap = 1;
        assert_int_equal(geom_mesh_clip_plane(m, pl, &opt, &o), GEOM_OK);
        area_volume(o, &A, &V);
        assert_true(fabs(A - 4.8) < 1e-14);
        assert_true(fabs(V - 0.7) < 1e-14);
        assert_int_equal(boundary_loops(o), 0);
        assert_true(is_valid(o));
        geom_mesh_destroy(o);

        /* oblique: x + z >= 0.5 removes a prism of volume 1/8; the cap is
         * a 1 x sqrt(1/2) rectangle */
        double ob[4] = {1, 0, 1, -0.5};
        assert_int_equal(geom_mesh_clip_plane(m, ob, &opt, &o), GEOM_OK);
        area_volume(o, &A, &V);
        assert_true(fabs(V - 0.875) < 1e-14);
        /* removed: two 1/8 triangles (y = 0, 1), half of x = 0 and of z = 0 */
        assert_true(fabs(A - (6.0 - 0.25 - 0.5 - 0.5 + sqrt(0.5))) < 1e-14);
        assert_int_equal(boundary_loops(o), 0);
        geom_mesh_destroy(o);

        /* through the centre x + y + z >= 1.5: half the volume, a regular
         * hexagon of side sqrt(1/2) as the cap, half the surface */
        double hx[4] = {1, 1, 1, -1.5};
        assert_int_equal(geom_mesh_clip_plane(m, hx, &opt, &o), GEOM_OK);
        area_volume(o, &A, &V);
        assert_true(fabs(V - 0.5) < 1e-14);
        assert_true(fabs(A - (3.0 + 3.0 * sqrt(3.0) / 4.0)) < 1e-14);
        assert_int_equal(boundary_loops(o), 0);
        assert_true(is_valid(o));
        geom_mesh_topology t;
        assert_int_equal(geom_mesh_topology_summary(o, &t), GEOM_OK);
        assert_int_equal(t.euler, 2);
        assert_true(t.closed);
        geom_mesh_destroy(o);
        geom_mesh_destroy(m);
    }
}

/* Planes through vertices, edges and faces of the box. */
static void test_planes_through_elements(void **state)
{
    (void)state;
    geom_clip_options opt = {1};
    for (int tris = 0; tris < 2; tris++) {
        geom_mesh *m = box(1, 1, 1, tris);
        geom_mesh *o = NULL;
        double A, V;
        /* x - y >= 0 through four vertices (a diagonal plane): half the
         * cube, a 1 x sqrt(2) cap */
        double dg[4] = {1, -1, 0, 0};
        assert_int_equal(geom_mesh_clip_plane(m, dg, &opt, &o), GEOM_OK);
        area_volume(o, &A, &V);
        assert_true(fabs(V - 0.5) < 1e-15);
        assert_true(fabs(A - (3.0 + sqrt(2.0))) < 1e-14);
        assert_int_equal(boundary_loops(o), 0);
        assert_true(is_valid(o));
        assert_int_equal(geom_mesh_n_vertices(o), 6);
        geom_mesh_destroy(o);
        /* x <= 1 contains the face x = 1 (facing away from the kept side):
         * the whole cube */
        double le[4] = {-1, 0, 0, 1};
        assert_int_equal(geom_mesh_clip_plane(m, le, &opt, &o), GEOM_OK);
        area_volume(o, &A, &V);
        assert_true(fabs(V - 1.0) < 1e-15 && fabs(A - 6.0) < 1e-15);
        assert_int_equal(boundary_loops(o), 0);
        geom_mesh_destroy(o);
        /* x >= 1 keeps nothing with area */
        double ge[4] = {1, 0, 0, -1};
        assert_int_equal(geom_mesh_clip_plane(m, ge, &opt, &o), GEOM_OK);
        assert_int_equal(geom_mesh_n_live_faces(o), 0);
        geom_mesh_destroy(o);
        /* through an edge: x + z >= 1 keeps the prism on the x = z = 1
         * edge's side: volume 1/2, cap sqrt(2) x 1 */
        double ed[4] = {1, 0, 1, -1};
        assert_int_equal(geom_mesh_clip_plane(m, ed, &opt, &o), GEOM_OK);
        area_volume(o, &A, &V);
        assert_true(fabs(V - 0.5) < 1e-15);
        assert_true(fabs(A - (3.0 + sqrt(2.0))) < 1e-14);
        assert_int_equal(boundary_loops(o), 0);
        geom_mesh_destroy(o);
        geom_mesh_destroy(m);
    }
}

/* A UV sphere cut by many planes: every capped result is a valid closed
 * genus-0 mesh whose volume is the convex polyhedron's cut, which lies
 * between the cut volumes of the inscribed and the exact ball (checked via
 * the cap's area against the exact disc). */
static void test_sphere_random_planes(void **state)
{
    (void)state;
    const int nlat = 20, nlon = 40;
    size_t nv = (size_t)nlat * nlon + 2;
    double *xyz = malloc(3 * nv * sizeof(double));
    uint32_t *sizes = malloc((size_t)2 * nlat * nlon * sizeof(uint32_t));
    uint32_t *idx = malloc((size_t)6 * nlat * nlon * sizeof(uint32_t));
    assert_true(xyz && sizes && idx);
    for (int i = 0; i < nlat; i++) {
        for (int j = 0; j < nlon; j++) {
            double th = PI * (i + 1) / (nlat + 1), ph = 2 * PI * j / nlon;
            double *p = xyz + 3 * ((size_t)i * nlon + j);
            p[0] = sin(th) * cos(ph);
            p[1] = sin(th) * sin(ph);
            p[2] = cos(th);
        }
    }
    uint32_t N = (uint32_t)nlat * nlon, S = N + 1;
    xyz[3 * N] = 0;
    xyz[3 * N + 1] = 0;
    xyz[3 * N + 2] = 1;
    xyz[3 * S] = 0;
    xyz[3 * S + 1] = 0;
    xyz[3 * S + 2] = -1;
    size_t f = 0;
    for (int j = 0; j < nlon; j++) {
        uint32_t j1 = (uint32_t)((j + 1) % nlon), base = (uint32_t)(nlat - 1) * nlon;
        uint32_t t[6] = {N, (uint32_t)j, j1, S, base + j1, base + (uint32_t)j};
        memcpy(idx + 3 * f, t, sizeof t);
        f += 2;
    }
    for (int i = 0; i + 1 < nlat; i++) {
        for (int j = 0; j < nlon; j++) {
            uint32_t j1 = (uint32_t)((j + 1) % nlon);
            uint32_t a = (uint32_t)i * nlon + (uint32_t)j, b = (uint32_t)i * nlon + j1;
            uint32_t t[6] = {a, a + (uint32_t)nlon, b + (uint32_t)nlon, a, b + (uint32_t)nlon, b};
            memcpy(idx + 3 * f, t, sizeof t);
            f += 2;
        }
    }
    for (size_t i = 0; i < f; i++)
        sizes[i] = 3;
    geom_mesh *m = mk(nv, xyz, f, sizes, idx);
    free(xyz);
    free(sizes);
    free(idx);
    double A0, V0;
    area_volume(m, &A0, &V0);
    uint64_t st = 12345;
    geom_clip_options opt = {1};
    for (int k = 0; k < 40; k++) {
        double r[4];
        for (int q = 0; q < 4; q++) {
            st = st * 6364136223846793005ull + 1442695040888963407ull;
            r[q] = (double)(st >> 11) / 9007199254740992.0 * 2.0 - 1.0;
        }
        double l = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
        double pl[4] = {r[0] / l, r[1] / l, r[2] / l, 0.8 * r[3]};
        geom_mesh *o = NULL;
        assert_int_equal(geom_mesh_clip_plane(m, pl, &opt, &o), GEOM_OK);
        assert_true(is_valid(o));
        assert_int_equal(boundary_loops(o), 0);
        geom_mesh_topology t;
        assert_int_equal(geom_mesh_topology_summary(o, &t), GEOM_OK);
        assert_int_equal(t.euler, 2);
        assert_int_equal(t.components, 1);
        double A, V;
        area_volume(o, &A, &V);
        /* the kept part of the polyhedron, with its complement, makes the
         * whole: clip the other side and add up */
        double npl[4] = {-pl[0], -pl[1], -pl[2], -pl[3]};
        geom_mesh *o2 = NULL;
        assert_int_equal(geom_mesh_clip_plane(m, npl, &opt, &o2), GEOM_OK);
        double A2, V2;
        area_volume(o2, &A2, &V2);
        assert_true(V > 0 && V2 > 0);
        assert_true(fabs(V + V2 - V0) < 1e-13);
        /* cap area (the same on both sides) = (A + A2 - A0) / 2, at most the
         * exact disc pi (1 - d^2) */
        double cap = 0.5 * (A + A2 - A0);
        double d = pl[3];
        assert_true(cap <= PI * (1.0 - d * d) + 1e-12);
        assert_true(cap > 0.9 * PI * (1.0 - d * d));
        geom_mesh_destroy(o);
        geom_mesh_destroy(o2);
    }
    geom_mesh_destroy(m);
}

static void test_keep_all_or_nothing(void **state)
{
    (void)state;
    geom_mesh *m = box(1, 1, 1, 1);
    geom_mesh *o = NULL;
    double all[4] = {0, 0, 1, 5}, none[4] = {0, 0, 1, -5};
    assert_int_equal(geom_mesh_clip_plane(m, all, NULL, &o), GEOM_OK);
    assert_int_equal(geom_mesh_n_live_faces(o), 12);
    geom_mesh_destroy(o);
    assert_int_equal(geom_mesh_clip_plane(m, none, NULL, &o), GEOM_OK);
    assert_int_equal(geom_mesh_n_live_faces(o), 0);
    assert_int_equal(geom_mesh_n_live_vertices(o), 0);
    geom_mesh_destroy(o);
    double zero[4] = {0, 0, 0, 1}, bad[4] = {0, NAN, 1, 0};
    assert_int_equal(geom_mesh_clip_plane(m, zero, NULL, &o), GEOM_ERR_DEGENERATE);
    assert_null(o);
    assert_int_equal(geom_mesh_clip_plane(m, bad, NULL, &o), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_mesh_clip_plane(m, all, NULL, NULL), GEOM_ERR_INVALID_ARG);
    geom_mesh_destroy(m);
}

/* ---------------------------------------------------------- attributes */

static double L0(const double *p) { return 2.0 * p[0] - p[1] + 3.0 * p[2] + 1.0; }
static double L1(const double *p) { return 0.5 * p[0] + 7.0 - 0.25 * p[2]; }

static void test_linear_attributes(void **state)
{
    (void)state;
    geom_mesh *m = box(2, 1, 1.5, 1);
    size_t nv = geom_mesh_n_vertices(m), nf = geom_mesh_n_faces(m), nh = geom_mesh_n_halfedges(m);
    const double *p = geom_mesh_cpositions(m);
    uint32_t vc, cc, fc, nc;
    assert_int_equal(geom_mesh_channel_add(m, "lin", GEOM_MESH_DOMAIN_VERTEX, 2, &vc), GEOM_OK);
    double *vd = geom_mesh_channel_data(m, vc);
    for (size_t v = 0; v < nv; v++) {
        vd[2 * v] = L0(p + 3 * v);
        vd[2 * v + 1] = L1(p + 3 * v);
    }
    /* corner channel with a seam on every edge: one value per corner */
    assert_int_equal(geom_mesh_channel_add(m, "uv", GEOM_MESH_DOMAIN_CORNER, 2, &cc), GEOM_OK);
    assert_int_equal(geom_mesh_corner_pool_resize(m, cc, nh), GEOM_OK);
    {
        uint32_t *ix = geom_mesh_corner_indices(m, cc);
        double *cd = geom_mesh_channel_data(m, cc);
        for (uint32_t h = 0; h < nh; h++) {
            if (geom_mesh_he_face(m, h) == GEOM_INVALID_INDEX)
                continue;
            const double *q = p + 3 * geom_mesh_he_vertex(m, h);
            /* per-face offset makes each face's values distinct */
            cd[2 * h] = L1(q) + geom_mesh_he_face(m, h);
            cd[2 * h + 1] = L0(q);
            ix[h] = h;
        }
    }
    assert_int_equal(geom_mesh_channel_add(m, "fid", GEOM_MESH_DOMAIN_FACE, 1, &fc), GEOM_OK);
    double *fd = geom_mesh_channel_data(m, fc);
    for (size_t f = 0; f < nf; f++)
        fd[f] = (double)f;
    geom_corner_normal_options no;
    memset(&no, 0, sizeof no);
    no.crease_degrees = 30;
    assert_int_equal(geom_mesh_corner_normals(m, &no, &nc), GEOM_OK);

    geom_mesh *o = NULL;
    double pl[4] = {0.3, -0.2, 1.0, -0.9};
    geom_clip_options opt = {1};
    assert_int_equal(geom_mesh_clip_plane(m, pl, &opt, &o), GEOM_OK);
    assert_true(is_valid(o));
    assert_int_equal(boundary_loops(o), 0);
    /* channels kept in the same order and shape */
    assert_int_equal(geom_mesh_channel_count(o), geom_mesh_channel_count(m));
    uint32_t ovc = geom_mesh_channel_find(o, "lin", GEOM_MESH_DOMAIN_VERTEX);
    uint32_t occ = geom_mesh_channel_find(o, "uv", GEOM_MESH_DOMAIN_CORNER);
    uint32_t ofc = geom_mesh_channel_find(o, "fid", GEOM_MESH_DOMAIN_FACE);
    uint32_t onc = geom_mesh_channel_find(o, "normal", GEOM_MESH_DOMAIN_CORNER);
    assert_true(ovc != GEOM_INVALID_INDEX && occ != GEOM_INVALID_INDEX &&
                ofc != GEOM_INVALID_INDEX && onc != GEOM_INVALID_INDEX);
    const double *op = geom_mesh_cpositions(o), *ovd = geom_mesh_channel_cdata(o, ovc);
    size_t onv = geom_mesh_n_vertices(o);
    size_t n_new = 0;
    for (size_t v = 0; v < onv; v++) {
        const double *q = op + 3 * v;
        /* a linear function stays linear (up to rounding) */
        assert_true(fabs(ovd[2 * v] - L0(q)) < 1e-14 * 8);
        assert_true(fabs(ovd[2 * v + 1] - L1(q)) < 1e-14 * 8);
        double s = pl[0] * q[0] + pl[1] * q[1] + pl[2] * q[2] + pl[3];
        assert_true(s >= -1e-15);
        n_new += fabs(s) < 1e-12;
    }
    assert_true(n_new >= 3);
    const uint32_t *oix = geom_mesh_corner_cindices(o, occ), *onx = geom_mesh_corner_cindices(o, onc);
    const double *ocd = geom_mesh_channel_cdata(o, occ), *ond = geom_mesh_channel_cdata(o, onc);
    const double *ofd = geom_mesh_channel_cdata(o, ofc);
    double plen = sqrt(pl[0] * pl[0] + pl[1] * pl[1] + pl[2] * pl[2]);
    size_t ncap = 0;
    for (uint32_t f = 0; f < geom_mesh_n_faces(o); f++) {
        double fn[3];
        assert_int_equal(geom_mesh_face_normal(o, f, fn), GEOM_OK);
        uint32_t h0 = geom_mesh_face_he(o, f), h = h0;
        /* is it a cap? its face normal is -plane normal */
        int cap = fabs(fn[0] + pl[0] / plen) < 1e-12 && fabs(fn[1] + pl[1] / plen) < 1e-12 &&
                  fabs(fn[2] + pl[2] / plen) < 1e-12;
        if (cap) {
            ncap++;
            assert_true(ofd[f] == 0.0);
        } else {
            /* the face's copied id names an original face with its normal */
            uint32_t of = (uint32_t)ofd[f];
            double ofn[3];
            assert_int_equal(geom_mesh_face_normal(m, of, ofn), GEOM_OK);
            for (int k = 0; k < 3; k++)
                assert_true(fabs(ofn[k] - fn[k]) < 1e-12);
        }
        do {
            const double *q = op + 3 * geom_mesh_he_vertex(o, h);
            const double *n3 = ond + 3 * onx[h];
            for (int k = 0; k < 3; k++)
                assert_true(fabs(n3[k] - fn[k]) < 1e-12); /* hard normals kept */
            if (cap) {
                assert_true(ocd[2 * oix[h]] == 0.0 && ocd[2 * oix[h] + 1] == 0.0);
            } else {
                double off = floor(ocd[2 * oix[h]] - L1(q) + 0.5);
                assert_true(fabs(ocd[2 * oix[h]] - (L1(q) + off)) < 1e-13);
                assert_true(fabs(ocd[2 * oix[h] + 1] - L0(q)) < 1e-13);
            }
            h = geom_mesh_he_next(o, h);
        } while (h != h0);
    }
    assert_true(ncap >= 1);
    geom_mesh_destroy(o);
    geom_mesh_destroy(m);
}

/* ------------------------------------------------- on-plane vertices */

static geom_mesh *grid(int n, double x0, double x1)
{
    size_t nv = (size_t)(n + 1) * (n + 1);
    double *xyz = malloc(3 * nv * sizeof(double));
    uint32_t *sizes = malloc((size_t)n * n * 2 * sizeof(uint32_t));
    uint32_t *idx = malloc((size_t)n * n * 6 * sizeof(uint32_t));
    assert_true(xyz && sizes && idx);
    for (int j = 0; j <= n; j++) {
        for (int i = 0; i <= n; i++) {
            double *q = xyz + 3 * ((size_t)j * (n + 1) + i);
            q[0] = x0 + (x1 - x0) * i / n;
            q[1] = x0 + (x1 - x0) * j / n;
            q[2] = 0.0;
        }
    }
    size_t f = 0;
    for (int j = 0; j < n; j++) {
        for (int i = 0; i < n; i++) {
            uint32_t a = (uint32_t)(j * (n + 1) + i), b = a + 1, c = a + (uint32_t)(n + 1) + 1,
                     d = a + (uint32_t)(n + 1);
            uint32_t t[6] = {a, b, c, a, c, d};
            memcpy(idx + 3 * f, t, sizeof t);
            sizes[f] = sizes[f + 1] = 3;
            f += 2;
        }
    }
    geom_mesh *m = mk(nv, xyz, f, sizes, idx);
    free(xyz);
    free(sizes);
    free(idx);
    return m;
}

static void test_vertices_on_plane(void **state)
{
    (void)state;
    geom_mesh *m = grid(4, 0.0, 1.0); /* vertices at x = 0, .25, .5, .75, 1 */
    /* exactly on the plane, and off by far less than the tolerance */
    const double offs[3] = {0.0, 3e-17, -2e-16};
    for (int k = 0; k < 3; k++) {
        double pl[4] = {1, 0, 0, -(0.5 + offs[k])};
        geom_mesh *o = NULL;
        assert_int_equal(geom_mesh_clip_plane(m, pl, NULL, &o), GEOM_OK);
        /* no new vertex: 3 columns of 5 */
        assert_int_equal(geom_mesh_n_vertices(o), 15);
        assert_int_equal(geom_mesh_n_live_faces(o), 16);
        double A;
        area_volume(o, &A, NULL);
        assert_true(fabs(A - 0.5) < 1e-15);
        /* no sliver: every face has area 1/32 */
        for (uint32_t f = 0; f < geom_mesh_n_faces(o); f++)
            assert_false(geom_mesh_face_is_degenerate(o, f));
        const double *p = geom_mesh_cpositions(o);
        for (size_t v = 0; v < 15; v++)
            assert_true(fabs(p[3 * v] - (0.5 + offs[k])) < 1e-16 || p[3 * v] >= 0.75);
        geom_mesh_destroy(o);
    }
    /* a diagonal plane through grid vertices: x - y >= 0 keeps the lower
     * right half (the grid diagonals run along x = y); no slivers */
    double pl[4] = {1, -1, 0, 0};
    geom_mesh *o = NULL;
    assert_int_equal(geom_mesh_clip_plane(m, pl, NULL, &o), GEOM_OK);
    assert_int_equal(geom_mesh_n_live_faces(o), 16);
    assert_int_equal(geom_mesh_n_vertices(o), 15);
    double A;
    area_volume(o, &A, NULL);
    assert_true(fabs(A - 0.5) < 1e-15);
    geom_mesh_destroy(o);
    geom_mesh_destroy(m);
}

/* ------------------------------------------------- non-convex polygon */

static void test_nonconvex_pieces(void **state)
{
    (void)state;
    /* U shape: [0,3]^2 minus the notch [1,2]x[1,3] */
    double xyz[] = {0, 0, 0, 3, 0, 0, 3, 3, 0, 2, 3, 0, 2, 1, 0, 1, 1, 0, 1, 3, 0, 0, 3, 0};
    uint32_t sizes[] = {8}, idx[] = {0, 1, 2, 3, 4, 5, 6, 7};
    geom_mesh *m = mk(8, xyz, 1, sizes, idx);
    geom_mesh *o = NULL;
    double up[4] = {0, 1, 0, -2}; /* y >= 2: the two arm tips */
    assert_int_equal(geom_mesh_clip_plane(m, up, NULL, &o), GEOM_OK);
    assert_int_equal(geom_mesh_n_live_faces(o), 2);
    double A;
    area_volume(o, &A, NULL);
    assert_true(A == 2.0);
    for (uint32_t f = 0; f < 2; f++) {
        assert_int_equal(geom_mesh_face_valence(o, f), 4);
        double fn[3];
        assert_int_equal(geom_mesh_face_normal(o, f, fn), GEOM_OK);
        assert_true(fn[2] == 1.0);
    }
    geom_mesh_destroy(o);
    double down[4] = {0, -1, 0, 2}; /* y <= 2: one piece of area 5 */
    assert_int_equal(geom_mesh_clip_plane(m, down, NULL, &o), GEOM_OK);
    assert_int_equal(geom_mesh_n_live_faces(o), 1);
    area_volume(o, &A, NULL);
    assert_true(A == 5.0);
    geom_mesh_destroy(o);
    geom_mesh_destroy(m);
}

/* ---------------------------------------------- cap with a hole */

static void test_cap_with_hole(void **state)
{
    (void)state;
    /* square frame: [0,3]^2 minus [1,2]^2, z in [0,1]; vertices: outer
     * bottom 0-3, inner bottom 4-7, outer top 8-11, inner top 12-15 */
    const double O[4][2] = {{0, 0}, {3, 0}, {3, 3}, {0, 3}};
    const double I[4][2] = {{1, 1}, {2, 1}, {2, 2}, {1, 2}};
    double xyz[48];
    for (int k = 0; k < 4; k++) {
        double *ob = xyz + 3 * k, *ib = xyz + 3 * (4 + k), *ot = xyz + 3 * (8 + k),
               *it = xyz + 3 * (12 + k);
        ob[0] = ot[0] = O[k][0];
        ob[1] = ot[1] = O[k][1];
        ib[0] = it[0] = I[k][0];
        ib[1] = it[1] = I[k][1];
        ob[2] = ib[2] = 0.0;
        ot[2] = it[2] = 1.0;
    }
    uint32_t idx[64], sizes[16];
    size_t f = 0;
    for (uint32_t k = 0; k < 4; k++) {
        uint32_t k1 = (k + 1) % 4;
        uint32_t top[4] = {8 + k, 8 + k1, 12 + k1, 12 + k};
        uint32_t bot[4] = {k, 4 + k, 4 + k1, k1};
        uint32_t outw[4] = {k, k1, 8 + k1, 8 + k};
        uint32_t inw[4] = {4 + k1, 4 + k, 12 + k, 12 + k1};
        memcpy(idx + 4 * f++, top, sizeof top);
        memcpy(idx + 4 * f++, bot, sizeof bot);
        memcpy(idx + 4 * f++, outw, sizeof outw);
        memcpy(idx + 4 * f++, inw, sizeof inw);
    }
    for (size_t i = 0; i < 16; i++)
        sizes[i] = 4;
    geom_mesh *m = mk(16, xyz, 16, sizes, idx);
    double A0, V0;
    area_volume(m, &A0, &V0);
    assert_true(fabs(V0 - 8.0) < 1e-14); /* orientation check of the input */
    geom_mesh *o = NULL;
    double pl[4] = {0, 0, 1, -0.5};
    geom_clip_options opt = {1};
    assert_int_equal(geom_mesh_clip_plane(m, pl, &opt, &o), GEOM_OK);
    double A, V;
    area_volume(o, &A, &V);
    assert_true(fabs(V - 4.0) < 1e-14);
    /* top 8 + outer walls 4*3*0.5 + inner walls 4*1*0.5 + cap 8 */
    assert_true(fabs(A - (8.0 + 6.0 + 2.0 + 8.0)) < 1e-14);
    assert_int_equal(boundary_loops(o), 0);
    assert_true(is_valid(o));
    geom_mesh_topology t;
    assert_int_equal(geom_mesh_topology_summary(o, &t), GEOM_OK);
    assert_int_equal(t.genus, 1);
    assert_int_equal(t.degenerate_faces, 0);
    geom_mesh_destroy(o);
    geom_mesh_destroy(m);
}

/* ------------------------------------------------------------ frustum */

static void test_frustum_grid(void **state)
{
    (void)state;
    geom_mesh *m = grid(60, -10.0, 10.0);
    geom_mat4 view, proj;
    assert_int_equal(geom_mat4_lookat(geom_vec3_make(0, 0, 5), geom_vec3_make(0, 0, 0),
                                      geom_vec3_make(0, 1, 0), &view),
                     GEOM_OK);
    const double fovy = PI / 3.0, aspect = 1.5;
    assert_int_equal(geom_mat4_perspective(fovy, aspect, 1.0, 100.0, &proj), GEOM_OK);
    geom_mat4 vp = geom_mat4_mul(proj, view);
    geom_mesh *o = NULL;
    assert_int_equal(geom_mesh_clip_frustum(m, vp, NULL, &o), GEOM_OK);
    /* the frustum meets z = 0 at distance 5 in a 2 h aspect x 2 h
     * rectangle, h = 5 tan(fovy / 2) */
    double h = 5.0 * tan(fovy / 2.0);
    double A;
    area_volume(o, &A, NULL);
    assert_true(fabs(A - 4.0 * h * h * aspect) < 1e-11);
    const double *p = geom_mesh_cpositions(o);
    for (size_t v = 0; v < geom_mesh_n_vertices(o); v++) {
        assert_true(fabs(p[3 * v]) <= h * aspect + 1e-12);
        assert_true(fabs(p[3 * v + 1]) <= h + 1e-12);
    }
    assert_int_equal(boundary_loops(o), 1);
    assert_true(is_valid(o));
    geom_mesh_destroy(o);
    geom_mesh_destroy(m);
}

/* A triangulated torus (planar quads split along a diagonal, so cuts meet
 * collinear points on the caps; genus 1, so caps can have holes) cut by
 * many planes, including planes through vertices and planes nearly
 * tangent to it: both capped halves are valid closed meshes without
 * degenerate faces whose volumes add up to the torus's. */
static void test_torus_random_planes(void **state)
{
    (void)state;
    const int nu = 40, nv = 20;
    size_t NV = (size_t)nu * nv;
    double *xyz = malloc(3 * NV * sizeof(double));
    uint32_t *idx = malloc(6 * NV * sizeof(uint32_t)), *sizes = malloc(2 * NV * sizeof(uint32_t));
    assert_true(xyz && idx && sizes);
    for (int i = 0; i < nu; i++) {
        for (int j = 0; j < nv; j++) {
            double u = 2 * PI * i / nu, v = 2 * PI * j / nv;
            double *p = xyz + 3 * ((size_t)i * nv + j);
            p[0] = (3 + cos(v)) * cos(u);
            p[1] = (3 + cos(v)) * sin(u);
            p[2] = sin(v);
        }
    }
    size_t f = 0;
    for (int i = 0; i < nu; i++) {
        for (int j = 0; j < nv; j++) {
            uint32_t a = (uint32_t)(i * nv + j), b = (uint32_t)(((i + 1) % nu) * nv + j);
            uint32_t c = (uint32_t)(((i + 1) % nu) * nv + (j + 1) % nv);
            uint32_t d = (uint32_t)(i * nv + (j + 1) % nv);
            uint32_t t[6] = {a, b, c, a, c, d};
            memcpy(idx + 3 * f, t, sizeof t);
            sizes[f] = sizes[f + 1] = 3;
            f += 2;
        }
    }
    geom_mesh *m = mk(NV, xyz, f, sizes, idx);
    double A0, V0;
    area_volume(m, &A0, &V0);
    uint64_t st = 7;
    geom_clip_options opt = {1};
    for (int it = 0; it < 200; it++) {
        double r[4];
        for (int q = 0; q < 4; q++) {
            st = st * 6364136223846793005ull + 1442695040888963407ull;
            r[q] = (double)(st >> 11) / 9007199254740992.0 * 2.0 - 1.0;
        }
        double pl[4] = {r[0], r[1], it % 5 == 0 ? 0.0 : r[2], 3.5 * r[3]};
        if (it % 7 == 0) { /* exactly through a vertex */
            const double *p = xyz + 3 * ((st >> 20) % NV);
            pl[3] = -(pl[0] * p[0] + pl[1] * p[1] + pl[2] * p[2]);
        }
        if (it % 11 == 0) { /* nearly tangent to the top circle z = 1 */
            pl[0] = 1e-3 * r[0];
            pl[1] = 1e-3 * r[1];
            pl[2] = 1.0;
            pl[3] = -1.0 + 1e-6 * r[3];
        }
        double npl[4] = {-pl[0], -pl[1], -pl[2], -pl[3]};
        geom_mesh *a = NULL, *b = NULL;
        assert_int_equal(geom_mesh_clip_plane(m, pl, &opt, &a), GEOM_OK);
        assert_int_equal(geom_mesh_clip_plane(m, npl, &opt, &b), GEOM_OK);
        double Aa, Va, Ab, Vb;
        area_volume(a, &Aa, &Va);
        area_volume(b, &Ab, &Vb);
        assert_true(fabs(Va + Vb - V0) < 1e-12 * V0);
        assert_int_equal(boundary_loops(a), 0);
        assert_int_equal(boundary_loops(b), 0);
        assert_true(is_valid(a) && is_valid(b));
        geom_mesh_topology ta, tb;
        assert_int_equal(geom_mesh_topology_summary(a, &ta), GEOM_OK);
        assert_int_equal(geom_mesh_topology_summary(b, &tb), GEOM_OK);
        assert_int_equal(ta.degenerate_faces, 0);
        assert_int_equal(tb.degenerate_faces, 0);
        geom_mesh_destroy(a);
        geom_mesh_destroy(b);
    }
    geom_mesh_destroy(m);
    free(xyz);
    free(idx);
    free(sizes);
}

/* ------------------------------------------------ allocation failures */

static void test_out_of_memory(void **state)
{
    (void)state;
    geom_mesh *src = box(1, 1, 1, 1);
    size_t ni = 0, nf = geom_mesh_n_faces(src);
    assert_int_equal(geom_mesh_to_soup(src, NULL, NULL, &ni), GEOM_OK);
    uint32_t *sizes = malloc(nf * sizeof(uint32_t)), *idx = malloc(ni * sizeof(uint32_t));
    assert_true(sizes && idx);
    assert_int_equal(geom_mesh_to_soup(src, sizes, idx, &ni), GEOM_OK);
    int ok = 0;
    for (long k = 0; k < 2000 && !ok; k++) {
        oom_state s = {-1, 0, 0};
        geom_allocator a = {oom_alloc, NULL, oom_free, &s};
        geom_mesh *m = geom_mesh_create(&a);
        assert_non_null(m);
        assert_int_equal(geom_mesh_build(m, 8, geom_mesh_cpositions(src), nf, sizes, idx, NULL,
                                         NULL, NULL),
                         GEOM_OK);
        geom_corner_normal_options no = {GEOM_NORMAL_WEIGHT_ANGLE, 30.0, 0};
        assert_int_equal(geom_mesh_corner_normals(m, &no, NULL), GEOM_OK);
        uint32_t vc;
        assert_int_equal(geom_mesh_channel_add(m, "w", GEOM_MESH_DOMAIN_VERTEX, 1, &vc), GEOM_OK);
        assert_int_equal(geom_mesh_channel_add(m, "f", GEOM_MESH_DOMAIN_FACE, 2, NULL), GEOM_OK);
        assert_int_equal(geom_mesh_channel_add(m, "e", GEOM_MESH_DOMAIN_EDGE, 1, NULL), GEOM_OK);
        double pl[4] = {1, 1, 1, -1.5};
        geom_clip_options opt = {1};
        geom_mesh *o = NULL;
        s.budget = k;
        geom_status st = geom_mesh_clip_plane(m, pl, &opt, &o);
        assert_true(st == GEOM_OK || st == GEOM_ERR_NOMEM);
        s.budget = -1;
        if (st == GEOM_OK) {
            ok = 1;
            assert_non_null(o);
            assert_int_equal(boundary_loops(o), 0);
            assert_int_equal(geom_mesh_channel_count(o), geom_mesh_channel_count(m));
        } else {
            assert_null(o);
        }
        geom_mesh_destroy(o);
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
        cmocka_unit_test(test_box_plane),
        cmocka_unit_test(test_keep_all_or_nothing),
        cmocka_unit_test(test_planes_through_elements),
        cmocka_unit_test(test_sphere_random_planes),
        cmocka_unit_test(test_torus_random_planes),
        cmocka_unit_test(test_linear_attributes),
        cmocka_unit_test(test_vertices_on_plane),
        cmocka_unit_test(test_nonconvex_pieces),
        cmocka_unit_test(test_cap_with_hole),
        cmocka_unit_test(test_frustum_grid),
        cmocka_unit_test(test_out_of_memory),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
