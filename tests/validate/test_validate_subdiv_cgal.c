/*
 * Loop and Catmull-Clark subdivision against CGAL's Subdivision_method_3
 * (gv_subdiv_cgal, validate_subdiv_cgal.cpp) on closed, crease-free meshes,
 * where both implement the same textbook rules (geom_validate.h lists CGAL's:
 * Loop's original vertex weights and the original Catmull-Clark rule, the
 * rules OpenSubdiv and libgeom use on smooth interior vertices), so boundary,
 * crease and corner rules, where they differ, never apply.
 *
 * Meshes: built here (a cube of quads, an octahedron and an icosahedron as
 * the outward-oriented triangles of their edge graphs, a torus quad grid and
 * that grid triangulated) and closed, untagged-or-irrelevantly-tagged
 * OpenSubdiv regression shapes (tests/data/osd-shapes: catmark_cube,
 * catmark_torus, catmark_pyramid, catmark_toroidal_tet, loop_cube,
 * loop_icosahedron, whose only tag is interpolateboundary, loop_tetrahedron,
 * loop_toroidal_tet), read with geom_meshio_read (keep_orientation) and
 * refined as their soups, so tags are not read at all. Every mesh is
 * checked to be closed (each directed edge once, its reverse once).
 * Catmull-Clark runs on every mesh (triangles and mixed polygons too, which
 * both treat with the plain rule), Loop on the triangle meshes; levels 1-3.
 *
 * For each mesh, scheme and level: CGAL refines the level-0 mesh `level`
 * times; ours refines it with geom_subdiv_refiner_create_soup (default
 * options) and geom_subdiv_interpolate. CGAL numbers vertices in its own
 * order, so vertices are matched by position: our refined vertices must be
 * pairwise farther apart than 1e-6 of the bounding-box diagonal d of level 0,
 * each CGAL vertex's nearest vertex of ours (brute force) must lie within
 * 1e-12 d, and the matching must be one-to-one. Then the face counts must be
 * equal, and the faces too: each CGAL face, mapped through the matching and
 * rotated to start at its smallest index, must be one of ours (same
 * orientation), as sorted lists. The largest distance met is printed per mesh
 * (in units of d). test_closed_forms checks one vertex point and one edge
 * point of each scheme against hand-computed values (Loop's original weights,
 * not Warren's).
 */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "geom/mesh.h"
#include "geom/meshio.h"
#include "geom/subdiv.h"
#include "validate/geom_validate.h"

#define LEVELS 3
#define TOL 1e-12          /* agreement, relative to the bbox diagonal */
#define MIN_SEPARATION 1e-6 /* our refined vertices are at least this far apart */

typedef struct soup {
    size_t nv, nf, ni;
    double *xyz;
    uint32_t *sizes;
    uint32_t *idx;
} soup;

static void soup_free(soup *s)
{
    free(s->xyz);
    free(s->sizes);
    free(s->idx);
    memset(s, 0, sizeof *s);
}

static void soup_alloc(soup *s, size_t nv, size_t nf, size_t ni)
{
    s->nv = nv;
    s->nf = nf;
    s->ni = ni;
    s->xyz = malloc((nv ? nv : 1) * 3 * sizeof(double));
    s->sizes = malloc((nf ? nf : 1) * sizeof(uint32_t));
    s->idx = malloc((ni ? ni : 1) * sizeof(uint32_t));
    assert_true(s->xyz && s->sizes && s->idx);
}

/* ----------------------------------------------------------- closedness */

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

/* Every directed edge appears once and its reverse once: closed, oriented,
 * manifold along edges. */
static void assert_closed(const soup *s)
{
    uint64_t *e = malloc(s->ni * sizeof *e);
    assert_non_null(e);
    size_t at = 0;
    for (size_t f = 0; f < s->nf; f++) {
        const uint32_t k = s->sizes[f];
        for (uint32_t j = 0; j < k; j++) {
            const uint64_t a = s->idx[at + j], b = s->idx[at + (j + 1) % k];
            assert_true(a != b);
            e[at + j] = (a << 32) | b;
        }
        at += k;
    }
    qsort(e, s->ni, sizeof *e, cmp_u64);
    for (size_t i = 0; i < s->ni; i++) {
        if (i > 0)
            assert_true(e[i] != e[i - 1]);
        const uint64_t rev = (e[i] << 32) | (e[i] >> 32);
        assert_non_null(bsearch(&rev, e, s->ni, sizeof *e, cmp_u64));
    }
    free(e);
}

/* --------------------------------------------------------- built meshes */

/* Outward-oriented triangles of a convex polyhedron whose edges are exactly
 * the vertex pairs at distance `edge` (octahedron, icosahedron): the
 * triangles of the edge graph. */
static void convex_triangles(soup *s, size_t nv, const double *xyz, double edge, size_t nf)
{
    soup_alloc(s, nv, nf, 3 * nf);
    memcpy(s->xyz, xyz, nv * 3 * sizeof(double));
    size_t f = 0;
#define ADJ(i, j)                                                                              \
    (fabs(sqrt((xyz[3 * (i)] - xyz[3 * (j)]) * (xyz[3 * (i)] - xyz[3 * (j)]) +                 \
               (xyz[3 * (i) + 1] - xyz[3 * (j) + 1]) * (xyz[3 * (i) + 1] - xyz[3 * (j) + 1]) + \
               (xyz[3 * (i) + 2] - xyz[3 * (j) + 2]) * (xyz[3 * (i) + 2] - xyz[3 * (j) + 2])) - \
          edge) < 1e-9)
    for (uint32_t a = 0; a < nv; a++)
        for (uint32_t b = a + 1; b < nv; b++)
            for (uint32_t c = b + 1; c < nv; c++) {
                if (!ADJ(a, b) || !ADJ(b, c) || !ADJ(a, c))
                    continue;
                const double *p = xyz + 3 * a, *q = xyz + 3 * b, *r = xyz + 3 * c;
                const double u[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
                const double v[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
                const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                                     u[0] * v[1] - u[1] * v[0]};
                /* the centre is the origin: outward when n . p > 0 */
                const int out = n[0] * p[0] + n[1] * p[1] + n[2] * p[2] > 0;
                assert_true(f < nf);
                s->sizes[f] = 3;
                s->idx[3 * f] = a;
                s->idx[3 * f + 1] = out ? b : c;
                s->idx[3 * f + 2] = out ? c : b;
                f++;
            }
#undef ADJ
    assert_int_equal(f, nf);
}

static void make_octahedron(soup *s)
{
    static const double v[6 * 3] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
    convex_triangles(s, 6, v, sqrt(2.0), 8);
}

static void make_icosahedron(soup *s)
{
    const double g = (1.0 + sqrt(5.0)) / 2.0;
    double v[12 * 3];
    size_t n = 0;
    for (int i = 0; i < 4; i++) {
        const double a = (i & 1) ? -1.0 : 1.0, b = (i & 2) ? -g : g;
        const double t[3][3] = {{0, a, b}, {a, b, 0}, {b, 0, a}};
        for (int j = 0; j < 3; j++, n++)
            memcpy(v + 3 * n, t[j], sizeof t[j]);
    }
    convex_triangles(s, 12, v, 2.0, 20);
}

static void make_cube(soup *s)
{
    static const double v[8 * 3] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0,
                                    0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
    static const uint32_t f[6 * 4] = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4,
                                      1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7};
    soup_alloc(s, 8, 6, 24);
    memcpy(s->xyz, v, sizeof v);
    memcpy(s->idx, f, sizeof f);
    for (size_t i = 0; i < 6; i++)
        s->sizes[i] = 4;
}

/* An m x n quad grid on a torus (radii 2 and 0.75, slightly twisted so no
 * symmetry hides an index mix-up), or the same grid with each quad split
 * into two triangles (every vertex of valence 6). */
static void make_torus(soup *s, int triangles)
{
    const uint32_t m = 8, n = 6;
    const size_t nq = (size_t)m * n;
    soup_alloc(s, nq, triangles ? 2 * nq : nq, triangles ? 6 * nq : 4 * nq);
    const double pi = acos(-1.0);
    for (uint32_t i = 0; i < m; i++)
        for (uint32_t j = 0; j < n; j++) {
            const double u = 2 * pi * i / m, w = 2 * pi * j / n + 0.3 * u;
            double *p = s->xyz + 3 * ((size_t)i * n + j);
            p[0] = (2.0 + 0.75 * cos(w)) * cos(u);
            p[1] = (2.0 + 0.75 * cos(w)) * sin(u);
            p[2] = 0.75 * sin(w) + 0.05 * cos(3 * u);
        }
    size_t f = 0, at = 0;
    for (uint32_t i = 0; i < m; i++)
        for (uint32_t j = 0; j < n; j++) {
            const uint32_t a = i * n + j, b = ((i + 1) % m) * n + j;
            const uint32_t c = ((i + 1) % m) * n + (j + 1) % n, d = i * n + (j + 1) % n;
            if (triangles) {
                const uint32_t t[6] = {a, b, c, a, c, d};
                memcpy(s->idx + at, t, sizeof t);
                s->sizes[f++] = 3;
                s->sizes[f++] = 3;
                at += 6;
            } else {
                const uint32_t q[4] = {a, b, c, d};
                memcpy(s->idx + at, q, sizeof q);
                s->sizes[f++] = 4;
                at += 4;
            }
        }
}

/* The file's soup (read with keep_orientation; no vertex may have been
 * split, so our vertices are the file's). Returns 0 when the file is
 * missing. */
static int read_shape(const char *name, soup *s)
{
    const char *shared = getenv("GEOM_SHARED_DATA");
    char path[1024];
    snprintf(path, sizeof path, "%s/osd-shapes/%s", shared ? shared : "tests/data", name);
    FILE *fp = fopen(path, "rb");
    if (!fp) {
        print_message("%s: missing, skipped\n", path);
        return 0;
    }
    fclose(fp);
    geom_meshio_read_options o;
    memset(&o, 0, sizeof o);
    o.build.keep_orientation = 1;
    geom_meshio_read_stats st;
    o.stats = &st;
    geom_mesh *m = NULL;
    geom_diag d;
    memset(&d, 0, sizeof d);
    assert_int_equal(geom_meshio_read(path, &o, &m, NULL, &d), GEOM_OK);
    const size_t nv = geom_mesh_n_vertices(m);
    assert_int_equal(nv, st.input_vertices);
    size_t ni = 0;
    assert_int_equal(geom_mesh_to_soup(m, NULL, NULL, &ni), GEOM_OK);
    soup_alloc(s, nv, geom_mesh_n_live_faces(m), ni);
    memcpy(s->xyz, geom_mesh_cpositions(m), nv * 3 * sizeof(double));
    assert_int_equal(geom_mesh_to_soup(m, s->sizes, s->idx, &ni), GEOM_OK);
    assert_int_equal(ni, s->ni);
    geom_mesh_destroy(m);
    return 1;
}

/* ------------------------------------------------------------ comparing */

static double bbox_diagonal(const soup *s)
{
    double lo[3], hi[3];
    for (int k = 0; k < 3; k++)
        lo[k] = hi[k] = s->xyz[k];
    for (size_t i = 0; i < s->nv; i++)
        for (int k = 0; k < 3; k++) {
            const double x = s->xyz[3 * i + k];
            lo[k] = x < lo[k] ? x : lo[k];
            hi[k] = x > hi[k] ? x : hi[k];
        }
    return sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

static double dist(const double *a, const double *b)
{
    const double x = a[0] - b[0], y = a[1] - b[1], z = a[2] - b[2];
    return sqrt(x * x + y * y + z * z);
}

/* Faces as sorted, rotation-normalised index lists; face i occupies
 * stride slots (size, then indices, padded with UINT32_MAX). */
#define MAXK 8

/* Any consistent total order will do (only equality of the sorted lists
 * is checked). */
static int cmp_face(const void *a, const void *b)
{
    return memcmp(a, b, (MAXK + 1) * sizeof(uint32_t));
}

static uint32_t *canonical_faces(size_t nf, const uint32_t *sizes, const uint32_t *idx,
                                 const uint32_t *map)
{
    uint32_t *out = malloc((nf ? nf : 1) * (MAXK + 1) * sizeof(uint32_t));
    assert_non_null(out);
    size_t at = 0;
    for (size_t f = 0; f < nf; f++) {
        const uint32_t k = sizes[f];
        assert_true(k >= 3 && k <= MAXK);
        uint32_t *row = out + f * (MAXK + 1);
        for (uint32_t j = 0; j <= MAXK; j++)
            row[j] = UINT32_MAX;
        row[0] = k;
        uint32_t first = 0;
        for (uint32_t j = 1; j < k; j++)
            if ((map ? map[idx[at + j]] : idx[at + j]) < (map ? map[idx[at + first]] : idx[at + first]))
                first = j;
        for (uint32_t j = 0; j < k; j++) {
            const uint32_t v = idx[at + (first + j) % k];
            row[1 + j] = map ? map[v] : v;
        }
        at += k;
    }
    qsort(out, nf, (MAXK + 1) * sizeof(uint32_t), cmp_face);
    return out;
}

/* Refine s with ours and CGAL's, levels 1..LEVELS, and compare. Returns the
 * largest vertex distance met, relative to the diagonal. */
static double compare(const char *name, const soup *s, geom_subdiv_scheme ours, int theirs)
{
    assert_closed(s);
    const double diag = bbox_diagonal(s);
    assert_true(diag > 0);

    geom_subdiv_options opt;
    memset(&opt, 0, sizeof opt);
    opt.scheme = ours;
    geom_subdiv_refiner *r = NULL;
    geom_diag d;
    memset(&d, 0, sizeof d);
    assert_int_equal(geom_subdiv_refiner_create_soup(s->nv, s->nf, s->sizes, s->idx, &opt, &r, &d),
                     GEOM_OK);
    assert_int_equal(geom_subdiv_refiner_refine(r, LEVELS), GEOM_OK);
    geom_subdiv_level_info info;
    assert_int_equal(geom_subdiv_refiner_level_info(r, 0, &info), GEOM_OK);
    /* closed: nothing is sharp, so no boundary or crease rule applies */
    assert_int_equal(info.sharp_edges, 0);

    double *pos = malloc(s->nv * 3 * sizeof(double));
    assert_non_null(pos);
    memcpy(pos, s->xyz, s->nv * 3 * sizeof(double));
    double worst = 0.0;
    for (int level = 1; level <= LEVELS; level++) {
        assert_int_equal(geom_subdiv_refiner_level_info(r, level, &info), GEOM_OK);
        assert_int_equal(info.sharp_edges, 0);
        double *next = malloc(info.vertices * 3 * sizeof(double));
        assert_non_null(next);
        assert_int_equal(geom_subdiv_interpolate(r, level, 3, pos, next), GEOM_OK);
        free(pos);
        pos = next;
        uint32_t *sizes = malloc(info.faces * sizeof(uint32_t));
        uint32_t *idx = malloc(info.face_vertices * sizeof(uint32_t));
        assert_true(sizes && idx);
        assert_int_equal(geom_subdiv_refiner_faces(r, level, sizes, idx, NULL), GEOM_OK);

        gv_subdiv_result c;
        assert_int_equal(gv_subdiv_cgal(theirs, level, s->nv, s->xyz, s->nf, s->sizes, s->idx, &c),
                         GV_OK);
        assert_int_equal(c.nverts, info.vertices);
        assert_int_equal(c.nfaces, info.faces);
        assert_int_equal(c.nindices, info.face_vertices);

        /* our vertices are distinct */
        for (size_t i = 0; i < info.vertices; i++)
            for (size_t j = i + 1; j < info.vertices; j++)
                assert_true(dist(pos + 3 * i, pos + 3 * j) > MIN_SEPARATION * diag);
        /* nearest-neighbour matching, one-to-one */
        uint32_t *map = malloc(c.nverts * sizeof(uint32_t));
        uint8_t *used = calloc(info.vertices, 1);
        assert_true(map && used);
        double lvl_worst = 0.0;
        for (size_t i = 0; i < c.nverts; i++) {
            size_t best = 0;
            double bd = INFINITY;
            for (size_t j = 0; j < info.vertices; j++) {
                const double dd = dist(c.xyz + 3 * i, pos + 3 * j);
                if (dd < bd) {
                    bd = dd;
                    best = j;
                }
            }
            if (!(bd <= TOL * diag))
                print_message("%s level %d: CGAL vertex %zu (%.17g %.17g %.17g) is %.3g d from "
                              "ours\n",
                              name, level, i, c.xyz[3 * i], c.xyz[3 * i + 1], c.xyz[3 * i + 2],
                              bd / diag);
            assert_true(bd <= TOL * diag);
            assert_int_equal(used[best], 0);
            used[best] = 1;
            map[i] = (uint32_t)best;
            lvl_worst = bd / diag > lvl_worst ? bd / diag : lvl_worst;
        }
        /* faces, orientation included */
        uint32_t *fo = canonical_faces(info.faces, sizes, idx, NULL);
        uint32_t *fc = canonical_faces(c.nfaces, c.face_sizes, c.indices, map);
        assert_memory_equal(fo, fc, info.faces * (MAXK + 1) * sizeof(uint32_t));
        print_message("%-24s %-13s level %d: %6zu vertices, %6zu faces, max |ours - CGAL| = "
                      "%.3g d\n",
                      name, geom_subdiv_scheme_name(ours), level, info.vertices, info.faces,
                      lvl_worst);
        worst = lvl_worst > worst ? lvl_worst : worst;
        free(fo);
        free(fc);
        free(map);
        free(used);
        free(sizes);
        free(idx);
        gv_subdiv_result_free(&c);
    }
    free(pos);
    geom_subdiv_refiner_destroy(r);
    return worst;
}

static int all_triangles(const soup *s)
{
    for (size_t f = 0; f < s->nf; f++)
        if (s->sizes[f] != 3)
            return 0;
    return 1;
}

/* Catmull-Clark always; Loop when s is all triangles. */
static void check(const char *name, soup *s, double *worst_cc, double *worst_loop)
{
    double w = compare(name, s, GEOM_SUBDIV_CATMULL_CLARK, GV_SUBDIV_CATMULL_CLARK);
    *worst_cc = w > *worst_cc ? w : *worst_cc;
    if (all_triangles(s)) {
        w = compare(name, s, GEOM_SUBDIV_LOOP, GV_SUBDIV_LOOP);
        *worst_loop = w > *worst_loop ? w : *worst_loop;
    }
    soup_free(s);
}

/* ---------------------------------------------------------------- tests */

static void test_built_meshes(void **state)
{
    (void)state;
    double wcc = 0, wl = 0;
    soup s;
    make_cube(&s);
    check("cube (quads)", &s, &wcc, &wl);
    make_octahedron(&s);
    check("octahedron", &s, &wcc, &wl);
    make_icosahedron(&s);
    check("icosahedron", &s, &wcc, &wl);
    make_torus(&s, 0);
    check("torus 8x6 quads", &s, &wcc, &wl);
    make_torus(&s, 1);
    check("torus 8x6 triangles", &s, &wcc, &wl);
    print_message("built meshes: max |ours - CGAL| = %.3g d (Catmull-Clark), %.3g d (Loop)\n",
                  wcc, wl);
}

static void test_osd_shapes(void **state)
{
    (void)state;
    static const char *const names[] = {"catmark_cube.obj",        "catmark_torus.obj",
                                        "catmark_pyramid.obj",     "catmark_toroidal_tet.obj",
                                        "loop_cube.obj",           "loop_icosahedron.obj",
                                        "loop_tetrahedron.obj",    "loop_toroidal_tet.obj"};
    double wcc = 0, wl = 0;
    int n = 0;
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        soup s;
        if (!read_shape(names[i], &s))
            continue;
        check(names[i], &s, &wcc, &wl);
        n++;
    }
    assert_true(n > 0);
    print_message("osd-shapes (%d): max |ours - CGAL| = %.3g d (Catmull-Clark), %.3g d (Loop)\n",
                  n, wcc, wl);
}

/* Index of a vertex within 1e-15 of p in xyz (n vertices), or -1. */
static long find_point(size_t n, const double *xyz, const double p[3])
{
    for (size_t i = 0; i < n; i++)
        if (dist(xyz + 3 * i, p) <= 1e-15)
            return (long)i;
    return -1;
}

/*
 * Closed forms that pin down which rules both use, one level each:
 *  - Loop on the octahedron (valence 4): the vertex (1,0,0) has neighbours
 *    summing to 0, so it moves to (1 - 4 beta, 0, 0): Loop's beta =
 *    (5/8 - (3/8 + cos(pi/2)/4)^2) / 4 = 31/256 gives 33/64; Warren's
 *    3/(8n) = 3/32 would give 5/8, which neither may produce. The edge
 *    point of (1,0,0)-(0,1,0) is (3 (p1 + p2) + (0,0,1) + (0,0,-1)) / 8 =
 *    (3/8, 3/8, 0);
 *  - Catmull-Clark on the unit cube (valence 3): the corner (0,0,0) goes to
 *    (Q + 2R + 0 v) / 3 with Q = (1/3,1/3,1/3) the mean face point and R =
 *    (1/6,1/6,1/6) the mean edge midpoint: (2/9, 2/9, 2/9); the edge point
 *    of (0,0,0)-(1,0,0) is (1/2, 1/8, 1/8).
 */
static void test_closed_forms(void **state)
{
    (void)state;
    for (int scheme = 0; scheme < 2; scheme++) {
        soup s;
        if (scheme == 0)
            make_octahedron(&s);
        else
            make_cube(&s);
        const double vp[2][3] = {{33.0 / 64, 0, 0}, {2.0 / 9, 2.0 / 9, 2.0 / 9}};
        const double ep[2][3] = {{3.0 / 8, 3.0 / 8, 0}, {0.5, 0.125, 0.125}};
        const double warren[3] = {5.0 / 8, 0, 0};
        /* CGAL */
        gv_subdiv_result c;
        assert_int_equal(gv_subdiv_cgal(scheme == 0 ? GV_SUBDIV_LOOP : GV_SUBDIV_CATMULL_CLARK, 1,
                                        s.nv, s.xyz, s.nf, s.sizes, s.idx, &c),
                         GV_OK);
        assert_true(find_point(c.nverts, c.xyz, vp[scheme]) >= 0);
        assert_true(find_point(c.nverts, c.xyz, ep[scheme]) >= 0);
        if (scheme == 0)
            assert_true(find_point(c.nverts, c.xyz, warren) < 0);
        /* ours */
        geom_subdiv_options opt;
        memset(&opt, 0, sizeof opt);
        opt.scheme = scheme == 0 ? GEOM_SUBDIV_LOOP : GEOM_SUBDIV_CATMULL_CLARK;
        geom_subdiv_refiner *r = NULL;
        assert_int_equal(
            geom_subdiv_refiner_create_soup(s.nv, s.nf, s.sizes, s.idx, &opt, &r, NULL), GEOM_OK);
        assert_int_equal(geom_subdiv_refiner_refine(r, 1), GEOM_OK);
        geom_subdiv_level_info info;
        assert_int_equal(geom_subdiv_refiner_level_info(r, 1, &info), GEOM_OK);
        double *pos = malloc(info.vertices * 3 * sizeof(double));
        assert_non_null(pos);
        assert_int_equal(geom_subdiv_interpolate(r, 1, 3, s.xyz, pos), GEOM_OK);
        assert_true(find_point(info.vertices, pos, vp[scheme]) >= 0);
        assert_true(find_point(info.vertices, pos, ep[scheme]) >= 0);
        if (scheme == 0)
            assert_true(find_point(info.vertices, pos, warren) < 0);
        free(pos);
        geom_subdiv_refiner_destroy(r);
        gv_subdiv_result_free(&c);
        soup_free(&s);
    }
}

static void test_invalid(void **state)
{
    (void)state;
    soup s;
    make_cube(&s);
    gv_subdiv_result c;
    /* Loop refuses quads; bad scheme and levels; NULL */
    assert_int_equal(gv_subdiv_cgal(GV_SUBDIV_LOOP, 1, s.nv, s.xyz, s.nf, s.sizes, s.idx, &c),
                     GV_ERR_INVALID);
    assert_int_equal(c.nverts, 0);
    assert_null(c.xyz);
    assert_int_equal(gv_subdiv_cgal(7, 1, s.nv, s.xyz, s.nf, s.sizes, s.idx, &c), GV_ERR_INVALID);
    assert_int_equal(gv_subdiv_cgal(GV_SUBDIV_CATMULL_CLARK, -1, s.nv, s.xyz, s.nf, s.sizes, s.idx,
                                    &c),
                     GV_ERR_INVALID);
    assert_int_equal(gv_subdiv_cgal(GV_SUBDIV_CATMULL_CLARK, 1, s.nv, NULL, s.nf, s.sizes, s.idx,
                                    &c),
                     GV_ERR_INVALID);
    const uint32_t keep = s.idx[5];
    s.idx[5] = 99;
    assert_int_equal(gv_subdiv_cgal(GV_SUBDIV_CATMULL_CLARK, 1, s.nv, s.xyz, s.nf, s.sizes, s.idx,
                                    &c),
                     GV_ERR_INVALID);
    /* level 0 gives the input back */
    s.idx[5] = keep;
    assert_int_equal(gv_subdiv_cgal(GV_SUBDIV_CATMULL_CLARK, 0, s.nv, s.xyz, s.nf, s.sizes, s.idx,
                                    &c),
                     GV_OK);
    assert_int_equal(c.nverts, 8);
    assert_int_equal(c.nfaces, 6);
    assert_memory_equal(c.xyz, s.xyz, 24 * sizeof(double));
    gv_subdiv_result_free(&c);
    gv_subdiv_result_free(NULL);
    soup_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_built_meshes),
        cmocka_unit_test(test_osd_shapes),
        cmocka_unit_test(test_closed_forms),
        cmocka_unit_test(test_invalid),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
