/*
 * OBJ reading and writing (geom/meshio.h): the hand-written cube with UV
 * seams and per-face normals (every corner's v/vt/vn checked against the
 * file), bit-exact round trips of doubles chosen to be hard to print, every
 * syntax variant (w, vertex colours, vt with 1-3 values, v, v/vt, v//vn,
 * v/vt/vn, negative indices, polygons, l, g/o/s/usemtl/mtllib, t tags,
 * comments, CRLF, backslash continuation, unknown statements), malformed
 * input with the line and column the diagnostic must name, element limits,
 * OpenSubdiv's 122 tagged shapes (tags and corners survive a write/read
 * cycle), format names, and the atomic writer (no partial file when the
 * directory is missing, the destination is a directory, the file size limit
 * is hit, or allocation fails at any point).
 */
#define _XOPEN_SOURCE 700

#include "meshio_testutil.h"

#include <dirent.h>
#include <errno.h>
#include <float.h>
#include <math.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

/* ------------------------------------------------------------ cube seams */

/* The (v, vt, vn) triples of data/cube_seams.obj's faces, 1-based. */
static const int cube_faces[6][4][3] = {
    {{1, 1, 3}, {2, 2, 3}, {6, 4, 3}, {5, 3, 3}},   {{5, 3, 2}, {6, 4, 2}, {7, 6, 2}, {8, 5, 2}},
    {{3, 8, 4}, {4, 7, 4}, {8, 5, 4}, {7, 6, 4}},   {{1, 9, 1}, {4, 7, 1}, {3, 8, 1}, {2, 10, 1}},
    {{2, 11, 6}, {3, 12, 6}, {7, 6, 6}, {6, 4, 6}}, {{1, 13, 5}, {5, 3, 5}, {8, 5, 5}, {4, 14, 5}}};

static void check_cube_structure(const geom_mesh *m)
{
    assert_int_equal(geom_mesh_n_vertices(m), 8);
    assert_int_equal(geom_mesh_n_faces(m), 6);
    assert_int_equal(geom_mesh_n_edges(m), 12);
    uint32_t uv = geom_mesh_channel_find(m, "uv", GEOM_MESH_DOMAIN_CORNER);
    uint32_t nm = geom_mesh_channel_find(m, "normal", GEOM_MESH_DOMAIN_CORNER);
    assert_int_not_equal(uv, GEOM_INVALID_INDEX);
    assert_int_not_equal(nm, GEOM_INVALID_INDEX);
    assert_int_equal(geom_mesh_channel_size(m, uv), 14);
    assert_int_equal(geom_mesh_channel_size(m, nm), 6);
    const uint32_t *ui = geom_mesh_corner_cindices(m, uv), *ni = geom_mesh_corner_cindices(m, nm);
    const double *un = geom_mesh_channel_cdata(m, nm);
    const double *p = geom_mesh_cpositions(m);
    for (uint32_t f = 0; f < 6; f++) {
        uint32_t h0 = geom_mesh_face_he(m, f), h = h0;
        for (int k = 0; k < 4; k++) {
            assert_int_equal(geom_mesh_he_vertex(m, h), cube_faces[f][k][0] - 1);
            assert_int_equal(ui[h], cube_faces[f][k][1] - 1);
            assert_int_equal(ni[h], cube_faces[f][k][2] - 1);
            h = geom_mesh_he_next(m, h);
        }
        assert_int_equal(h, h0);
        /* the file's normal is the face's outward normal: every corner of
         * the face lies in the plane x.n = const with the centre below it */
        const double *n = un + 3 * (ni[h0]);
        double d0 = 0;
        for (int k = 0; k < 4; k++) {
            const double *q = p + 3 * (cube_faces[f][k][0] - 1);
            double d = q[0] * n[0] + q[1] * n[1] + q[2] * n[2];
            if (k == 0)
                d0 = d;
            assert_true(d == d0);
        }
        assert_true(0.5 * (n[0] + n[1] + n[2]) < d0);
    }
    geom_mesh_topology t;
    assert_int_equal(geom_mesh_topology_summary(m, &t), GEOM_OK);
    assert_true(t.closed);
    assert_int_equal(t.euler, 2);
    assert_int_equal(t.genus, 0);
    assert_true(mt_volume6(m) == 6.0);
}

static void test_cube_seams_file(void **state)
{
    (void)state;
    char path[1024];
    geom_mesh *m = NULL;
    geom_diag d;
    geom_mesh_build_report r;
    assert_int_equal(geom_meshio_read(mt_path(path, sizeof path, 0, "cube_seams.obj"), NULL, &m,
                                      &r, &d),
                     GEOM_OK);
    check_cube_structure(m);
    assert_int_equal(r.flipped_faces + r.split_vertices + r.invalid_faces, 0);
    assert_int_equal(geom_mesh_mtllib_count(m), 1);
    assert_string_equal(geom_mesh_mtllib_get(m, 0), "cube.mtl");
    assert_int_equal(geom_mesh_group_count(m), 1);
    geom_mesh_group g;
    assert_int_equal(geom_mesh_group_get(m, 0, &g), GEOM_OK);
    assert_null(g.group);
    assert_string_equal(g.object, "cube");
    assert_string_equal(g.material, "grey");
    assert_string_equal(g.smoothing, "off");

    /* write back: same v/vt/vn structure, line for line */
    size_t size;
    char *text = mt_write(m, GEOM_MESHIO_FORMAT_OBJ, 0, &size);
    assert_int_equal(strlen(text), size);
    for (int f = 0; f < 6; f++) {
        char line[128];
        int n = snprintf(line, sizeof line, "\nf");
        for (int k = 0; k < 4; k++)
            n += snprintf(line + n, sizeof line - (size_t)n, " %d/%d/%d", cube_faces[f][k][0],
                          cube_faces[f][k][1], cube_faces[f][k][2]);
        snprintf(line + n, sizeof line - (size_t)n, "\n");
        assert_non_null(strstr(text, line));
    }
    assert_non_null(strstr(text, "\nvt 0.375 0.25\n"));
    assert_non_null(strstr(text, "\nmtllib cube.mtl\n"));
    assert_non_null(strstr(text, "\nusemtl grey\n"));
    geom_mesh *m2 = NULL;
    assert_int_equal(mt_read(text, size, GEOM_MESHIO_FORMAT_OBJ, 0, &m2, NULL, &d, NULL), GEOM_OK);
    check_cube_structure(m2);
    mt_assert_same_positions(m, m2);
    free(text);
    geom_mesh_destroy(m2);
    geom_mesh_destroy(m);
}

/* --------------------------------------------------------- exact doubles */

static uint64_t lcg(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return *s;
}

/* Doubles that are hard to print: random bit patterns over every exponent,
 * subnormals, extremes, and values with no short decimal form. */
static double hard_double(uint64_t *s, size_t i)
{
    static const double special[] = {0.1,     1.0 / 3.0, -0.0,   DBL_MIN, DBL_MAX,      -DBL_MAX,
                                     5e-324,  1e22,      1e23,   2.5e-308, 9007199254740993.0,
                                     0.3,     -2.0 / 3.0, 123456789.123456789, 1e-7, 6.02214076e23};
    if (i < sizeof special / sizeof special[0])
        return special[i];
    for (;;) {
        uint64_t bits = lcg(s);
        double x;
        memcpy(&x, &bits, sizeof x);
        if (isfinite(x))
            return x;
    }
}

static void test_exact_doubles(void **state)
{
    (void)state;
    enum { N = 3000 };
    static double xyz[3 * N];
    static uint32_t sizes[N - 2], idx[3 * (N - 2)];
    uint64_t s = 12345;
    for (size_t i = 0; i < 3 * N; i++)
        xyz[i] = hard_double(&s, i);
    for (uint32_t f = 0; f < N - 2; f++) {
        sizes[f] = 3;
        idx[3 * f] = f;
        idx[3 * f + 1] = f % 2 ? f + 2 : f + 1;
        idx[3 * f + 2] = f % 2 ? f + 1 : f + 2;
    }
    geom_mesh *m = geom_mesh_create(NULL);
    assert_int_equal(geom_mesh_build(m, N, xyz, N - 2, sizes, idx, NULL, NULL, NULL), GEOM_OK);
    /* a uv corner channel with hard values too */
    uint32_t uv;
    assert_int_equal(geom_mesh_channel_add(m, "uv", GEOM_MESH_DOMAIN_CORNER, 2, &uv), GEOM_OK);
    size_t nh = geom_mesh_n_halfedges(m);
    assert_int_equal(geom_mesh_corner_pool_resize(m, uv, nh), GEOM_OK);
    double *uvd = geom_mesh_channel_data(m, uv);
    for (size_t i = 0; i < 2 * nh; i++)
        uvd[i] = hard_double(&s, 1000);
    uint32_t *ci = geom_mesh_corner_indices(m, uv);
    for (uint32_t h = 0; h < nh; h++)
        ci[h] = geom_mesh_he_face(m, h) == GEOM_INVALID_INDEX ? GEOM_INVALID_INDEX : h;

    for (int prec = 0; prec <= 17; prec += 17) {
        geom_meshio_write_options w;
        memset(&w, 0, sizeof w);
        w.format = GEOM_MESHIO_FORMAT_OBJ;
        w.precision = prec;
        void *data;
        size_t size;
        geom_diag d;
        assert_int_equal(geom_meshio_write_memory(m, &w, &data, &size, &d), GEOM_OK);
        if (prec == 0) /* the shortest form: 0.1 is written as 0.1 */
            assert_non_null(strstr(data, "v 0.1 0.3333333333333333 -0\n"));
        geom_mesh *m2 = NULL;
        assert_int_equal(mt_read(data, size, GEOM_MESHIO_FORMAT_OBJ, 0, &m2, NULL, &d, NULL),
                         GEOM_OK);
        mt_assert_same_positions(m, m2);
        uint32_t uv2 = geom_mesh_channel_find(m2, "uv", GEOM_MESH_DOMAIN_CORNER);
        const double *a = geom_mesh_channel_cdata(m, uv), *b = geom_mesh_channel_cdata(m2, uv2);
        const uint32_t *ia = geom_mesh_corner_cindices(m, uv),
                       *ib = geom_mesh_corner_cindices(m2, uv2);
        assert_int_equal(geom_mesh_n_halfedges(m2), nh);
        for (uint32_t h = 0; h < nh; h++) {
            if (ia[h] == GEOM_INVALID_INDEX)
                continue;
            assert_true(mt_same_bits(a[2 * ia[h]], b[2 * ib[h]]));
            assert_true(mt_same_bits(a[2 * ia[h] + 1], b[2 * ib[h] + 1]));
        }
        geom_mesh_destroy(m2);
        free(data);
    }
    geom_mesh_destroy(m);
}

/* ------------------------------------------------------- syntax variants */

static const char variants[] =
    "# comment line\r\n"
    "mtllib a.mtl   b.mtl\r\n"
    "v 0 0 0 # trailing comment\r\n"
    "v 1 0 0 0.5\r\n"
    "\tv 1 1 0 0.25 0.5 0.75\r\n"
    "v 0 1 0 2 0.1 0.2 0.3\r\n"
    "v 0.5 0.5 \\\r\n"
    "  1\r\n"
    "vt 0 0\n"
    "vt 1\n"
    "vt 1 1 0\n"
    "vt 0 1\n"
    "vn 0 0 1\n"
    "\n"
    "vp 0.1 0.2\n"
    "g grp1 grp2\n"
    "o obj\n"
    "usemtl red\n"
    "s 1\n"
    "f 1/1/1 2/2/1 3/3/1\n"
    "f -5 -3 -2\n"
    "usemtl blue\n"
    "f 1//1 4//1 5//1\n"
    "f 2/2 5/4 4/3 3/3\n"
    "cstype bspline\n"
    "l 1 2/2 3\n"
    "t crease 2/1/0 0 1 2.5\n"
    "t name 0/0/2 a b\n";

static void check_variants(const geom_mesh *m)
{
    assert_int_equal(geom_mesh_n_vertices(m), 5);
    assert_int_equal(geom_mesh_n_faces(m), 4);
    const double *p = geom_mesh_cpositions(m);
    assert_true(p[12] == 0.5 && p[13] == 0.5 && p[14] == 1.0);
    uint32_t w = geom_mesh_channel_find(m, "weight", GEOM_MESH_DOMAIN_VERTEX);
    uint32_t c = geom_mesh_channel_find(m, "color", GEOM_MESH_DOMAIN_VERTEX);
    assert_int_not_equal(w, GEOM_INVALID_INDEX);
    assert_int_not_equal(c, GEOM_INVALID_INDEX);
    const double want_w[5] = {1, 0.5, 1, 2, 1};
    const double want_c[15] = {1, 1, 1, 1, 1, 1, 0.25, 0.5, 0.75, 0.1, 0.2, 0.3, 1, 1, 1};
    const double *wd = geom_mesh_channel_cdata(m, w), *cd = geom_mesh_channel_cdata(m, c);
    for (int i = 0; i < 5; i++)
        assert_true(wd[i] == want_w[i]);
    for (int i = 0; i < 15; i++)
        assert_true(cd[i] == want_c[i]);
    uint32_t uv = geom_mesh_channel_find(m, "uv", GEOM_MESH_DOMAIN_CORNER);
    uint32_t nm = geom_mesh_channel_find(m, "normal", GEOM_MESH_DOMAIN_CORNER);
    assert_int_equal(geom_mesh_channel_size(m, uv), 4);
    const double want_uv[8] = {0, 0, 1, 0, 1, 1, 0, 1};
    for (int i = 0; i < 8; i++)
        assert_true(geom_mesh_channel_cdata(m, uv)[i] == want_uv[i]);
    /* faces: vertices and (uv, normal) per corner, 0-based, -1 = none */
    const int want[4][4][3] = {{{0, 0, 0}, {1, 1, 0}, {2, 2, 0}, {-9, 0, 0}},
                               {{0, -1, -1}, {2, -1, -1}, {3, -1, -1}, {-9, 0, 0}},
                               {{0, -1, 0}, {3, -1, 0}, {4, -1, 0}, {-9, 0, 0}},
                               {{1, 1, -1}, {4, 3, -1}, {3, 2, -1}, {2, 2, -1}}};
    const uint32_t *ui = geom_mesh_corner_cindices(m, uv), *ni = geom_mesh_corner_cindices(m, nm);
    for (uint32_t f = 0; f < 4; f++) {
        uint32_t h = geom_mesh_face_he(m, f);
        size_t n = geom_mesh_face_valence(m, f);
        assert_int_equal(n, f == 3 ? 4 : 3);
        for (size_t k = 0; k < n; k++) {
            assert_int_equal(geom_mesh_he_vertex(m, h), want[f][k][0]);
            assert_int_equal(ui[h], want[f][k][1] < 0 ? GEOM_INVALID_INDEX : (uint32_t)want[f][k][1]);
            assert_int_equal(ni[h], want[f][k][2] < 0 ? GEOM_INVALID_INDEX : (uint32_t)want[f][k][2]);
            h = geom_mesh_he_next(m, h);
        }
    }
    geom_mesh_topology t;
    assert_int_equal(geom_mesh_topology_summary(m, &t), GEOM_OK);
    assert_int_equal(t.edges, 8);
    assert_int_equal(t.euler, 1);
    assert_int_equal(t.boundary_loops, 1);
    /* groups */
    assert_int_equal(geom_mesh_group_count(m), 2);
    const uint32_t *fg = geom_mesh_face_cgroups(m);
    assert_non_null(fg);
    assert_int_equal(fg[0], 0);
    assert_int_equal(fg[1], 0);
    assert_int_equal(fg[2], 1);
    assert_int_equal(fg[3], 1);
    geom_mesh_group g;
    assert_int_equal(geom_mesh_group_get(m, 1, &g), GEOM_OK);
    assert_string_equal(g.group, "grp1 grp2");
    assert_string_equal(g.object, "obj");
    assert_string_equal(g.material, "blue");
    assert_string_equal(g.smoothing, "1");
    assert_int_equal(geom_mesh_mtllib_count(m), 1);
    assert_string_equal(geom_mesh_mtllib_get(m, 0), "a.mtl b.mtl");
    /* polyline */
    assert_int_equal(geom_mesh_polyline_count(m), 1);
    size_t pn;
    const uint32_t *pv;
    assert_int_equal(geom_mesh_polyline_get(m, 0, &pn, &pv), GEOM_OK);
    assert_int_equal(pn, 3);
    assert_int_equal(pv[0], 0);
    assert_int_equal(pv[1], 1);
    assert_int_equal(pv[2], 2);
    /* tags */
    assert_int_equal(geom_mesh_tag_count(m), 2);
    geom_mesh_tag tg;
    assert_int_equal(geom_mesh_tag_get(m, 0, &tg), GEOM_OK);
    assert_string_equal(tg.name, "crease");
    assert_int_equal(tg.nint, 2);
    assert_int_equal(tg.nfloat, 1);
    assert_int_equal(tg.nstring, 0);
    assert_int_equal(tg.ints[0], 0);
    assert_int_equal(tg.ints[1], 1);
    assert_true(tg.floats[0] == 2.5);
    assert_int_equal(geom_mesh_tag_get(m, 1, &tg), GEOM_OK);
    assert_string_equal(tg.name, "name");
    assert_int_equal(tg.nstring, 2);
    assert_string_equal(tg.strings[0], "a");
    assert_string_equal(tg.strings[1], "b");
}

static void test_syntax_variants(void **state)
{
    (void)state;
    geom_mesh *m = NULL;
    geom_diag d;
    geom_meshio_read_stats st;
    geom_status s = mt_read(variants, (size_t)-1, GEOM_MESHIO_FORMAT_OBJ, 0, &m, NULL, &d, &st);
    if (s != GEOM_OK)
        fprintf(stderr, "%zu:%zu %s\n", d.line, d.column, d.message);
    assert_int_equal(s, GEOM_OK);
    assert_int_equal(st.format, GEOM_MESHIO_FORMAT_OBJ);
    assert_int_equal(st.skipped_statements, 3); /* vt w, vp, cstype */
    assert_string_equal(st.first_skipped, "vt w");
    check_variants(m);

    /* written back and read again: everything survives */
    size_t size;
    char *text = mt_write(m, GEOM_MESHIO_FORMAT_OBJ, 0, &size);
    assert_non_null(strstr(text, "\nv 1 0 0 0.5 1 1 1\n"));
    assert_non_null(strstr(text, "\nv 0 1 0 2 0.1 0.2 0.3\n"));
    assert_non_null(strstr(text, "\nf 1/1/1 2/2/1 3/3/1\n"));
    assert_non_null(strstr(text, "\nf 1 3 4\n"));
    assert_non_null(strstr(text, "\nf 1//1 4//1 5//1\n"));
    assert_non_null(strstr(text, "\nf 2/2 5/4 4/3 3/3\n"));
    assert_non_null(strstr(text, "\nt crease 2/1/0 0 1 2.5\n"));
    assert_non_null(strstr(text, "\nt name 0/0/2 a b\n"));
    assert_non_null(strstr(text, "\nl 1 2 3\n"));
    geom_mesh *m2 = NULL;
    assert_int_equal(mt_read(text, size, GEOM_MESHIO_FORMAT_OBJ, 0, &m2, NULL, &d, &st), GEOM_OK);
    assert_int_equal(st.skipped_statements, 0);
    check_variants(m2);
    free(text);
    geom_mesh_destroy(m2);
    geom_mesh_destroy(m);

    /* names ending in a backslash (a continuation joined with a blank line)
     * are written so that they do not swallow the next line */
    const char *bs = "mtllib a\\b\\\n\ng x\\\\\n\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"
                     "t s 0/0/1 q\\\\\n\n";
    assert_int_equal(mt_read(bs, (size_t)-1, GEOM_MESHIO_FORMAT_OBJ, 0, &m, NULL, &d, NULL),
                     GEOM_OK);
    assert_string_equal(geom_mesh_mtllib_get(m, 0), "a\\b");
    geom_mesh_group g0;
    assert_int_equal(geom_mesh_group_get(m, 0, &g0), GEOM_OK);
    assert_string_equal(g0.group, "x\\");
    text = mt_write(m, GEOM_MESHIO_FORMAT_OBJ, 0, &size);
    assert_int_equal(mt_read(text, size, GEOM_MESHIO_FORMAT_OBJ, 0, &m2, NULL, &d, NULL), GEOM_OK);
    assert_int_equal(geom_mesh_n_vertices(m2), 3);
    assert_int_equal(geom_mesh_n_faces(m2), 1);
    geom_mesh_group g1;
    assert_int_equal(geom_mesh_group_get(m2, 0, &g1), GEOM_OK);
    assert_string_equal(g1.group, "x\\");
    geom_mesh_tag tg;
    assert_int_equal(geom_mesh_tag_get(m2, 0, &tg), GEOM_OK);
    assert_string_equal(tg.strings[0], "q\\");
    free(text);
    geom_mesh_destroy(m2);
    geom_mesh_destroy(m);

    /* a file without a final newline, and old Mac line ends inside a line */
    assert_int_equal(mt_read("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3", (size_t)-1,
                             GEOM_MESHIO_FORMAT_OBJ, 0, &m, NULL, &d, NULL),
                     GEOM_OK);
    assert_int_equal(geom_mesh_n_faces(m), 1);
    geom_mesh_destroy(m);
    /* an empty file is an empty mesh */
    assert_int_equal(mt_read("", 0, GEOM_MESHIO_FORMAT_OBJ, 0, &m, NULL, &d, NULL), GEOM_OK);
    assert_int_equal(geom_mesh_n_vertices(m), 0);
    geom_mesh_destroy(m);
}

/* -------------------------------------------------------------- malformed */

static void test_malformed(void **state)
{
    (void)state;
    static const struct {
        const char *text;
        geom_status status;
        size_t line, col;
        const char *msg; /* a substring of the message */
    } cases[] = {
        {"v 1 2\n", GEOM_ERR_PARSE, 1, 1, "found 2 numbers"},
        {"v 1 2 3 4 5\n", GEOM_ERR_PARSE, 1, 1, "found 5 numbers"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", GEOM_ERR_PARSE, 4, 7, "3 vertices are defined"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2/2 3/3\n", GEOM_ERR_PARSE, 4, 5,
         "texture coordinate"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1//1 2//1 3//1\n", GEOM_ERR_PARSE, 5, 6, "normal"},
        {"v 1 2 x\n", GEOM_ERR_PARSE, 1, 7, "expected a number"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", GEOM_ERR_PARSE, 4, 3, "index 0"},
        {"v 1e999 0 0\n", GEOM_ERR_PARSE, 1, 3, "out of range"},
        {"v 0x10 0 0\n", GEOM_ERR_PARSE, 1, 3, "expected a number"},
        {"v nan 0 0\n", GEOM_ERR_PARSE, 1, 3, "expected a number"},
        {"v 0 -inf 0\n", GEOM_ERR_PARSE, 1, 5, "expected a number"},
        {"v 0 0 0\r\nv 1 0 0\r\n\r\nf 1 2 -9\r\n", GEOM_ERR_PARSE, 4, 7, "vertex -9"},
        {"v 0 0 \\\n0\nv 1 0 0\nv 0 1 0\nf 1 2 q\n", GEOM_ERR_PARSE, 5, 7, "expected an index"},
        {"f 1 2 3\n", GEOM_ERR_PARSE, 1, 3, "0 vertices are defined"},
        {"v 0 0 0\nf 1/2/3/4\n", GEOM_ERR_PARSE, 2, 3, "expected v, v/vt"},
        {"vn 1 2\n", GEOM_ERR_PARSE, 1, 1, "vn x y z"},
        {"vt\n", GEOM_ERR_PARSE, 1, 1, "vt u"},
        {"t crease 2/1 0 1 2.0\n", GEOM_ERR_PARSE, 1, 10, "tag counts"},
        {"t crease 2/1/0 0 1\n", GEOM_ERR_PARSE, 1, 0, "line ends"},
        {"t crease 2/1/0 0 1 2.0 extra\n", GEOM_ERR_PARSE, 1, 24, "unexpected"},
        {"t crease 2/1/0 0 x 2.0\n", GEOM_ERR_PARSE, 1, 18, "integer"},
        {"t x 1000000/0/0 1\n", GEOM_ERR_PARSE, 1, 5, "exceed"},
        {"v 0 0 0\nv 1 0 0\nl 1\n", GEOM_ERR_PARSE, 3, 1, "at least 2"},
        {"v 0 0 0\nv 1 0 0\nl 1//2 2\n", GEOM_ERR_PARSE, 3, 6, "v or v/vt"},
        {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 2\n", GEOM_ERR_PARSE, 4, 0, "appears twice"},
        {"v 0 0 0\nv 1 0 0\nf 1 2\n", GEOM_ERR_PARSE, 3, 0, "at least 3"},
        {"v 0 0 0\nv 1 0 0\nf\n", GEOM_ERR_PARSE, 3, 1, "vertex references"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        geom_mesh *m = (geom_mesh *)&cases; /* must be reset to NULL */
        geom_diag d;
        geom_mesh_build_report r;
        geom_status st =
            mt_read(cases[i].text, (size_t)-1, GEOM_MESHIO_FORMAT_OBJ, 0, &m, &r, &d, NULL);
        if (st != cases[i].status || d.line != cases[i].line ||
            (cases[i].col && d.column != cases[i].col) || !strstr(d.message, cases[i].msg)) {
            fprintf(stderr, "case %zu: status %d at %zu:%zu '%s'\n", i, st, d.line, d.column,
                    d.message);
            fail();
        }
        assert_null(m);
        assert_int_equal(d.status, cases[i].status);
        assert_string_equal(d.source, "test");
        char buf[512];
        geom_diag_format(&d, buf, sizeof buf);
        assert_true(strncmp(buf, "test:", 5) == 0);
    }
}

static void test_skip_invalid(void **state)
{
    (void)state;
    const char *text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 4\nf 1 2\nf 2 4 3\n";
    geom_mesh *m = NULL;
    geom_diag d;
    geom_mesh_build_report r;
    assert_int_equal(mt_read(text, (size_t)-1, GEOM_MESHIO_FORMAT_OBJ, 0, &m, &r, &d, NULL),
                     GEOM_ERR_PARSE);
    mt_assert_diag_at(&d, 6, 0);
    assert_int_equal(mt_read(text, (size_t)-1, GEOM_MESHIO_FORMAT_OBJ, 1, &m, &r, &d, NULL),
                     GEOM_OK);
    assert_int_equal(geom_mesh_n_faces(m), 2);
    assert_int_equal(r.invalid_faces, 2);
    assert_int_equal(r.first_invalid_faces[0], 1);
    assert_int_equal(r.first_invalid_faces[1], 2);
    geom_mesh_destroy(m);
}

/* Face locations are kept as runs of evenly stepping lines: an invalid face
 * anywhere (after even gaps, uneven gaps, a step back to the same line
 * through a continuation, and a run of one) is reported at its own line,
 * counted here by brute force. */
static void test_face_lines(void **state)
{
    (void)state;
    /* gap pattern before each face: 0 = none, k = k comment lines */
    static const int gaps[] = {0, 0, 0, 2, 2, 2, 0, 5, 1, 0, 0, 3, 0, 7, 7, 0, 1, 1, 1, 0};
    const size_t nf = sizeof gaps / sizeof gaps[0];
    char *text = malloc(8192);
    assert_non_null(text);
    for (size_t bad = 0; bad < nf; bad++) {
        size_t n = 0, line = 0, bad_line = 0;
        n += (size_t)sprintf(text + n, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n");
        line = 4;
        for (size_t f = 0; f < nf; f++) {
            for (int g = 0; g < gaps[f]; g++, line++)
                n += (size_t)sprintf(text + n, "# gap\n");
            line++;
            if (f == bad) {
                bad_line = line;
                n += (size_t)sprintf(text + n, "f 1 2 2\n");
            } else {
                n += (size_t)sprintf(text + n, "f %zu %zu 4\n", 1 + f % 2, 2 - f % 2);
            }
        }
        geom_mesh *m = NULL;
        geom_diag d;
        geom_mesh_build_report r;
        assert_int_equal(mt_read(text, n, GEOM_MESHIO_FORMAT_OBJ, 0, &m, &r, &d, NULL),
                         GEOM_ERR_PARSE);
        if (d.line != bad_line)
            fprintf(stderr, "bad face %zu: line %zu, expected %zu\n", bad, d.line, bad_line);
        assert_int_equal(d.line, bad_line);
        assert_null(m);
    }
    free(text);
}

/* Integers are written digit pairs at a time: every length from 1 to 20
 * digits, both sides of each power of ten, 0 and the int64 extremes, as
 * printf writes them (tag integers go through the same printer as indices). */
static void test_integer_text(void **state)
{
    (void)state;
    int64_t v[64];
    size_t n = 0;
    v[n++] = 0;
    v[n++] = INT64_MAX;
    v[n++] = INT64_MIN;
    v[n++] = INT64_MIN + 1;
    int64_t p = 1;
    for (int k = 0; k < 19; k++) { /* p = 10^k; 10^19 would overflow */
        v[n++] = p;
        v[n++] = p - 1 > 0 ? p - 1 : 7;
        v[n++] = -(p + 1);
        if (k < 18)
            p *= 10;
    }
    geom_mesh *m = geom_mesh_create(NULL);
    assert_non_null(m);
    geom_mesh_tag t = {"ints", n, 0, 0, v, NULL, NULL};
    assert_int_equal(geom_mesh_tag_add(m, &t), GEOM_OK);
    size_t size;
    char *data = mt_write(m, GEOM_MESHIO_FORMAT_OBJ, GEOM_MESHIO_ENCODING_DEFAULT, &size);
    char want[2048];
    size_t w = (size_t)snprintf(want, sizeof want, "t ints %zu/0/0", n);
    for (size_t i = 0; i < n; i++)
        w += (size_t)snprintf(want + w, sizeof want - w, " %lld", (long long)v[i]);
    snprintf(want + w, sizeof want - w, "\n");
    if (!strstr(data, want))
        fprintf(stderr, "expected '%s' in\n%s\n", want, data);
    assert_non_null(strstr(data, want));
    geom_meshio_buffer_free(data, size, NULL);
    geom_mesh_destroy(m);
}

static void test_limits(void **state)
{
    (void)state;
    geom_meshio_read_options o;
    memset(&o, 0, sizeof o);
    o.max_elements = 3;
    geom_mesh *m = NULL;
    geom_diag d;
    const char *text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n";
    assert_int_equal(geom_meshio_read_memory(text, strlen(text), "x.obj", &o, &m, NULL, &d),
                     GEOM_ERR_LIMIT);
    mt_assert_diag_at(&d, 4, 0);
    assert_null(m);
    o.max_elements = 4;
    assert_int_equal(geom_meshio_read_memory(text, strlen(text), "x.obj", &o, &m, NULL, &d),
                     GEOM_OK);
    geom_mesh_destroy(m);
    /* corners count too */
    o.max_elements = 5;
    const char *t2 = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 3 2\n";
    assert_int_equal(geom_meshio_read_memory(t2, strlen(t2), "x.obj", &o, &m, NULL, &d),
                     GEOM_ERR_LIMIT);
    mt_assert_diag_at(&d, 5, 0);
}

/* -------------------------------------------------- OpenSubdiv's shapes */

static size_t count_prefix(const char *text, const char *prefix)
{
    size_t n = 0, pl = strlen(prefix);
    for (const char *p = text; p && *p;) {
        if (strncmp(p, prefix, pl) == 0)
            n++;
        p = strchr(p, '\n');
        if (p)
            p++;
    }
    return n;
}

static void test_osd_shapes(void **state)
{
    (void)state;
    char dir[1024];
    mt_path(dir, sizeof dir, 1, "osd-shapes");
    DIR *dp = opendir(dir);
    if (!dp) {
        fprintf(stderr, "no %s: skipped\n", dir);
        skip();
    }
    struct dirent *de;
    size_t files = 0, tags_total = 0;
    while ((de = readdir(dp))) {
        size_t len = strlen(de->d_name);
        if (len < 5 || strcmp(de->d_name + len - 4, ".obj") != 0)
            continue;
        char path[2048];
        snprintf(path, sizeof path, "%s/%s", dir, de->d_name);
        size_t size;
        char *text = (char *)mt_slurp(path, &size);
        assert_non_null(text);
        geom_meshio_read_options o;
        geom_meshio_read_stats st;
        memset(&o, 0, sizeof o);
        o.build.skip_invalid_faces = 1; /* some shapes have faces with repeated vertices */
        o.stats = &st;
        geom_mesh *m = NULL;
        geom_diag d;
        geom_mesh_build_report r;
        geom_status s = geom_meshio_read(path, &o, &m, &r, &d);
        if (s != GEOM_OK)
            fprintf(stderr, "%s: %s\n", path, d.message);
        assert_int_equal(s, GEOM_OK);
        /* an independent count of the statements */
        assert_int_equal(st.input_vertices, count_prefix(text, "v "));
        assert_int_equal(st.input_faces, count_prefix(text, "f "));
        assert_int_equal(geom_mesh_tag_count(m), count_prefix(text, "t "));
        tags_total += geom_mesh_tag_count(m);
        files++;

        /* write, read back: positions, faces, uv corners and tags survive */
        size_t wsize;
        char *out = mt_write(m, GEOM_MESHIO_FORMAT_OBJ, 0, &wsize);
        geom_mesh *m2 = NULL;
        memset(&o, 0, sizeof o);
        geom_mesh_build_report r2;
        s = geom_meshio_read_memory(out, wsize, "again.obj", &o, &m2, &r2, &d);
        if (s != GEOM_OK)
            fprintf(stderr, "%s again: %zu: %s\n", path, d.line, d.message);
        assert_int_equal(s, GEOM_OK);
        assert_int_equal(r2.invalid_faces + r2.flipped_faces + r2.split_vertices +
                             r2.detached_faces,
                         0);
        mt_assert_same_positions(m, m2);
        assert_int_equal(geom_mesh_n_faces(m2), geom_mesh_n_live_faces(m));
        uint32_t uv1 = geom_mesh_channel_find(m, "uv", GEOM_MESH_DOMAIN_CORNER);
        uint32_t uv2 = geom_mesh_channel_find(m2, "uv", GEOM_MESH_DOMAIN_CORNER);
        assert_int_equal(uv1 == GEOM_INVALID_INDEX, uv2 == GEOM_INVALID_INDEX);
        for (uint32_t f = 0; f < geom_mesh_n_faces(m2); f++) {
            uint32_t a = geom_mesh_face_he(m, f), b = geom_mesh_face_he(m2, f);
            size_t n = geom_mesh_face_valence(m, f);
            assert_int_equal(n, geom_mesh_face_valence(m2, f));
            for (size_t k = 0; k < n; k++) {
                assert_int_equal(geom_mesh_he_vertex(m, a), geom_mesh_he_vertex(m2, b));
                if (uv1 != GEOM_INVALID_INDEX) {
                    uint32_t i1 = geom_mesh_corner_cindices(m, uv1)[a];
                    uint32_t i2 = geom_mesh_corner_cindices(m2, uv2)[b];
                    assert_int_equal(i1, i2);
                }
                a = geom_mesh_he_next(m, a);
                b = geom_mesh_he_next(m2, b);
            }
        }
        assert_int_equal(geom_mesh_tag_count(m2), geom_mesh_tag_count(m));
        for (size_t i = 0; i < geom_mesh_tag_count(m); i++) {
            geom_mesh_tag t1, t2;
            assert_int_equal(geom_mesh_tag_get(m, i, &t1), GEOM_OK);
            assert_int_equal(geom_mesh_tag_get(m2, i, &t2), GEOM_OK);
            assert_string_equal(t1.name, t2.name);
            assert_int_equal(t1.nint, t2.nint);
            assert_int_equal(t1.nfloat, t2.nfloat);
            assert_int_equal(t1.nstring, t2.nstring);
            for (size_t j = 0; j < t1.nint; j++)
                assert_int_equal(t1.ints[j], t2.ints[j]);
            for (size_t j = 0; j < t1.nfloat; j++)
                assert_true(mt_same_bits(t1.floats[j], t2.floats[j]));
            for (size_t j = 0; j < t1.nstring; j++)
                assert_string_equal(t1.strings[j], t2.strings[j]);
        }
        free(out);
        free(text);
        geom_mesh_destroy(m2);
        geom_mesh_destroy(m);
    }
    closedir(dp);
    assert_int_equal(files, 122);
    assert_true(tags_total > 1000);
}

/* ------------------------------------------------------------- format names */

static void test_format_names(void **state)
{
    (void)state;
    assert_int_equal(geom_meshio_format_from_name("a/b.c/mesh.OBJ"), GEOM_MESHIO_FORMAT_OBJ);
    assert_int_equal(geom_meshio_format_from_name("x.Off"), GEOM_MESHIO_FORMAT_OFF);
    assert_int_equal(geom_meshio_format_from_name("ply"), GEOM_MESHIO_FORMAT_PLY);
    assert_int_equal(geom_meshio_format_from_name(".stl"), GEOM_MESHIO_FORMAT_STL);
    assert_int_equal(geom_meshio_format_from_name("scene.glb"), GEOM_MESHIO_FORMAT_GLB);
    assert_int_equal(geom_meshio_format_from_name("scene.gltf"), GEOM_MESHIO_FORMAT_AUTO);
    assert_int_equal(geom_meshio_format_from_name("dir.obj/mesh"), GEOM_MESHIO_FORMAT_AUTO);
    assert_int_equal(geom_meshio_format_from_name(""), GEOM_MESHIO_FORMAT_AUTO);
    assert_int_equal(geom_meshio_format_from_name(NULL), GEOM_MESHIO_FORMAT_AUTO);
    assert_string_equal(geom_meshio_format_name(GEOM_MESHIO_FORMAT_PLY), "ply");
    assert_string_equal(geom_meshio_format_name(GEOM_MESHIO_FORMAT_AUTO), "auto");
    assert_string_equal(geom_meshio_format_name((geom_meshio_format)42), "unknown");
    assert_int_equal(geom_meshio_format_sniff("ply\nformat ascii 1.0\n", 20),
                     GEOM_MESHIO_FORMAT_PLY);
    assert_int_equal(geom_meshio_format_sniff("# c\nCOFF\n", 9), GEOM_MESHIO_FORMAT_OFF);
    assert_int_equal(geom_meshio_format_sniff("  solid x\n", 10), GEOM_MESHIO_FORMAT_STL);
    assert_int_equal(geom_meshio_format_sniff("v 0 0 0\n", 8), GEOM_MESHIO_FORMAT_OBJ);
    assert_int_equal(geom_meshio_format_sniff(NULL, 0), GEOM_MESHIO_FORMAT_OBJ);
    /* read_memory with an unknown name sniffs the content */
    geom_mesh *m = NULL;
    geom_meshio_read_options o;
    geom_meshio_read_stats st;
    memset(&o, 0, sizeof o);
    o.stats = &st;
    const char *off = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    assert_int_equal(geom_meshio_read_memory(off, strlen(off), "<stdin>", &o, &m, NULL, NULL),
                     GEOM_OK);
    assert_int_equal(st.format, GEOM_MESHIO_FORMAT_OFF);
    geom_mesh_destroy(m);
    /* a glb cut short is a parse error (the reader is gltf_read.c) */
    geom_diag d;
    assert_int_equal(geom_meshio_read_memory("glTF", 4, "x.glb", NULL, &m, NULL, &d),
                     GEOM_ERR_PARSE);
    /* argument checks */
    assert_int_equal(geom_meshio_read_memory(NULL, 3, "x.obj", NULL, &m, NULL, &d),
                     GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_meshio_read(NULL, NULL, &m, NULL, &d), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_meshio_read("/nonexistent/dir/x.obj", NULL, &m, NULL, &d), GEOM_ERR_IO);
    assert_string_equal(d.source, "/nonexistent/dir/x.obj");
    void *buf;
    size_t size;
    geom_meshio_write_options w;
    memset(&w, 0, sizeof w);
    geom_mesh *e = geom_mesh_create(NULL);
    assert_int_equal(geom_meshio_write_memory(e, &w, &buf, &size, &d), GEOM_ERR_INVALID_ARG);
    assert_null(buf);
    w.format = GEOM_MESHIO_FORMAT_STL;
    w.encoding = GEOM_MESHIO_ENCODING_BINARY_BE;
    assert_int_equal(geom_meshio_write_memory(e, &w, &buf, &size, &d), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_meshio_write(e, "/tmp/x.unknown", NULL, &d), GEOM_ERR_INVALID_ARG);
    geom_mesh_destroy(e);
}

/* --------------------------------------------------------- atomic writes */

/* Names in dir other than "." and "..", joined with '|'. */
static void list_dir(const char *dir, char *out, size_t size)
{
    out[0] = 0;
    DIR *dp = opendir(dir);
    assert_non_null(dp);
    struct dirent *de;
    while ((de = readdir(dp))) {
        if (strcmp(de->d_name, ".") == 0 || strcmp(de->d_name, "..") == 0)
            continue;
        strncat(out, de->d_name, size - strlen(out) - 2);
        strcat(out, "|");
    }
    closedir(dp);
}

static geom_mesh *cube_mesh(void)
{
    char path[1024];
    geom_mesh *m = NULL;
    assert_int_equal(
        geom_meshio_read(mt_path(path, sizeof path, 0, "cube_seams.obj"), NULL, &m, NULL, NULL),
        GEOM_OK);
    return m;
}

typedef struct failing_alloc {
    int left; /* allocations that still succeed */
    int live;
} failing_alloc;

static void *fa_alloc(void *user, size_t size)
{
    failing_alloc *f = user;
    if (f->left-- <= 0)
        return NULL;
    f->live++;
    return malloc(size);
}
static void *fa_realloc(void *user, void *p, size_t old, size_t size)
{
    failing_alloc *f = user;
    (void)old;
    if (f->left-- <= 0)
        return NULL;
    if (!p)
        f->live++;
    return realloc(p, size);
}
static void fa_free(void *user, void *p, size_t size)
{
    failing_alloc *f = user;
    (void)size;
    if (p)
        f->live--;
    free(p);
}

static void test_atomic_write(void **state)
{
    (void)state;
    char dir[] = "/tmp/geom-meshio-test.XXXXXX";
    assert_non_null(mkdtemp(dir));
    geom_mesh *m = cube_mesh();
    char path[256], listing[4096];
    geom_diag d;

    /* a fresh file, then replacing it */
    snprintf(path, sizeof path, "%s/out.obj", dir);
    assert_int_equal(geom_meshio_write(m, path, NULL, &d), GEOM_OK);
    list_dir(dir, listing, sizeof listing);
    assert_string_equal(listing, "out.obj|");
    geom_mesh *back = NULL;
    assert_int_equal(geom_meshio_read(path, NULL, &back, NULL, &d), GEOM_OK);
    check_cube_structure(back);
    geom_mesh_destroy(back);
    FILE *fp = fopen(path, "w");
    fputs("old content\n", fp);
    fclose(fp);

    /* the directory does not exist */
    char missing[300];
    snprintf(missing, sizeof missing, "%s/no/such/dir/out.obj", dir);
    assert_int_equal(geom_meshio_write(m, missing, NULL, &d), GEOM_ERR_IO);
    assert_string_equal(d.source, missing);
    list_dir(dir, listing, sizeof listing);
    assert_string_equal(listing, "out.obj|");

    /* the destination is a directory: rename fails, the temp file goes */
    char sub[300];
    snprintf(sub, sizeof sub, "%s/sub.obj", dir);
    assert_int_equal(mkdir(sub, 0755), 0);
    assert_int_equal(geom_meshio_write(m, sub, NULL, &d), GEOM_ERR_IO);
    list_dir(dir, listing, sizeof listing);
    assert_true(strcmp(listing, "out.obj|sub.obj|") == 0 || strcmp(listing, "sub.obj|out.obj|") == 0);
    rmdir(sub);

    /* writes fail with EFBIG past a file size limit: nothing partial stays */
    struct rlimit old;
    assert_int_equal(getrlimit(RLIMIT_FSIZE, &old), 0);
    void (*old_handler)(int) = signal(SIGXFSZ, SIG_IGN);
    struct rlimit lim = old;
    lim.rlim_cur = 100;
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &lim), 0);
    geom_status st = geom_meshio_write(m, path, NULL, &d);
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &old), 0);
    signal(SIGXFSZ, old_handler);
    assert_int_equal(st, GEOM_ERR_IO);
    list_dir(dir, listing, sizeof listing);
    assert_string_equal(listing, "out.obj|");
    size_t size;
    char *content = (char *)mt_slurp(path, &size);
    assert_string_equal(content, "old content\n");
    free(content);

    /* every allocation failure leaves the old file and no temporary */
    for (int fmt = GEOM_MESHIO_FORMAT_OBJ; fmt <= GEOM_MESHIO_FORMAT_GLB; fmt++) {
        int ok = 0;
        for (int left = 0; left < 200 && !ok; left++) {
            failing_alloc fa = {left, 0};
            geom_allocator al = {fa_alloc, fa_realloc, fa_free, &fa};
            geom_meshio_write_options w;
            memset(&w, 0, sizeof w);
            w.format = (geom_meshio_format)fmt;
            w.alloc = &al;
            st = geom_meshio_write(m, path, &w, &d);
            assert_int_equal(fa.live, 0);
            list_dir(dir, listing, sizeof listing);
            assert_string_equal(listing, "out.obj|");
            if (st == GEOM_OK) {
                ok = 1;
                break;
            }
            assert_int_equal(st, GEOM_ERR_NOMEM);
            content = (char *)mt_slurp(path, &size);
            assert_string_equal(content, "old content\n");
            free(content);
            /* write_memory under the same failure frees everything too */
            fa.left = left;
            void *buf = NULL;
            st = geom_meshio_write_memory(m, &w, &buf, &size, &d);
            if (st == GEOM_OK)
                geom_meshio_buffer_free(buf, size, &al);
            assert_int_equal(fa.live, 0);
        }
        assert_true(ok);
        /* restore the old content for the next format */
        fp = fopen(path, "w");
        fputs("old content\n", fp);
        fclose(fp);
    }

    /* a directory we may not write into (not testable as root) */
    if (geteuid() != 0) {
        char ro[300];
        snprintf(ro, sizeof ro, "%s/ro", dir);
        assert_int_equal(mkdir(ro, 0555), 0);
        char p2[400];
        snprintf(p2, sizeof p2, "%s/out.obj", ro);
        assert_int_equal(geom_meshio_write(m, p2, NULL, &d), GEOM_ERR_IO);
        list_dir(ro, listing, sizeof listing);
        assert_string_equal(listing, "");
        rmdir(ro);
    }
    unlink(path);
    assert_int_equal(rmdir(dir), 0);
    geom_mesh_destroy(m);
}

/* Reading with an allocator that fails at every point: no leak, NOMEM. */
/* geom_meshio_read_file releases a mapped file's pages before building the
 * mesh: the mapping must still hold the file's bytes afterwards. */
static void test_read_file_mapped(void **state)
{
    (void)state;
    char path[] = "/tmp/geom-meshio-map-XXXXXX";
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    const char text[] = "v 0 0 0\nv 1 0 0\nv 0.1 1e-3 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\n";
    assert_int_equal(write(fd, text, sizeof text - 1), (ssize_t)(sizeof text - 1));
    close(fd);
    geom_file f;
    geom_diag d;
    assert_int_equal(geom_file_map(path, NULL, &f, &d), GEOM_OK);
    geom_meshio_read_options o;
    memset(&o, 0, sizeof o);
    o.format = GEOM_MESHIO_FORMAT_OBJ;
    geom_mesh *m = NULL;
    assert_int_equal(geom_meshio_read_file(&f, path, &o, &m, NULL, &d), GEOM_OK);
    assert_int_equal(geom_mesh_n_faces(m), 2);
    const double *p = geom_mesh_positions(m);
    assert_true(p[6] == 0.1 && p[7] == 1e-3);
    assert_int_equal(f.size, sizeof text - 1);
    assert_memory_equal(f.data, text, sizeof text - 1);
    geom_file_unmap(&f);
    geom_mesh_destroy(m);
    assert_int_equal(geom_meshio_read_file(NULL, path, &o, &m, NULL, &d), GEOM_ERR_INVALID_ARG);
    assert_null(m);
    unlink(path);
}

/* geom_meshio_write_stream: the pieces, joined, are the file (read back to
 * the same positions), in pieces of at most 64 KiB; a callback's failure
 * stops the write with its status. */
typedef struct stream_buf {
    char *p;
    size_t n, cap, calls, fail_at, max_piece;
} stream_buf;

static geom_status stream_collect(void *user, const void *data, size_t size)
{
    stream_buf *b = user;
    b->calls++;
    if (b->fail_at && b->calls == b->fail_at)
        return GEOM_ERR_IO;
    if (size > b->max_piece)
        b->max_piece = size;
    if (b->n + size + 1 > b->cap) {
        b->cap = 2 * (b->n + size + 1);
        b->p = realloc(b->p, b->cap);
        assert_non_null(b->p);
    }
    memcpy(b->p + b->n, data, size);
    b->n += size;
    b->p[b->n] = 0;
    return GEOM_OK;
}

static void test_write_stream(void **state)
{
    (void)state;
    /* a 60 x 60 grid of quads with shortest-form coordinates: > 64 KiB of OBJ */
    enum { N = 60 };
    double *xyz = malloc(3 * (N + 1) * (N + 1) * sizeof(double));
    uint32_t *sizes = malloc(N * N * sizeof(uint32_t)), *idx = malloc(4 * N * N * sizeof(uint32_t));
    assert_true(xyz && sizes && idx);
    for (int j = 0; j <= N; j++)
        for (int i = 0; i <= N; i++) {
            double *p = xyz + 3 * (j * (N + 1) + i);
            p[0] = i / 7.0;
            p[1] = j / 3.0;
            p[2] = (i * j) / 11.0;
        }
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++) {
            uint32_t a = (uint32_t)(j * (N + 1) + i), *q = idx + 4 * (j * N + i);
            sizes[j * N + i] = 4;
            q[0] = a, q[1] = a + 1, q[2] = a + N + 2, q[3] = a + N + 1;
        }
    geom_mesh *m = geom_mesh_create(NULL);
    assert_int_equal(geom_mesh_build(m, (N + 1) * (N + 1), xyz, N * N, sizes, idx, NULL, NULL,
                                     NULL),
                     GEOM_OK);
    geom_meshio_write_options w;
    memset(&w, 0, sizeof w);
    w.format = GEOM_MESHIO_FORMAT_OBJ;
    stream_buf b;
    memset(&b, 0, sizeof b);
    geom_diag d;
    assert_int_equal(geom_meshio_write_stream(m, &w, stream_collect, &b, &d), GEOM_OK);
    assert_true(b.n > 65536);
    assert_true(b.calls >= 2);
    assert_true(b.max_piece <= 65536);
    geom_mesh *m2 = NULL;
    assert_int_equal(mt_read(b.p, b.n, GEOM_MESHIO_FORMAT_OBJ, 0, &m2, NULL, &d, NULL), GEOM_OK);
    mt_assert_same_positions(m, m2);
    assert_int_equal(geom_mesh_n_faces(m2), N * N);
    geom_mesh_destroy(m2);
    /* a failing callback: its status, a message, no further calls */
    stream_buf f;
    memset(&f, 0, sizeof f);
    f.fail_at = 2;
    assert_int_equal(geom_meshio_write_stream(m, &w, stream_collect, &f, &d), GEOM_ERR_IO);
    assert_int_equal(d.status, GEOM_ERR_IO);
    assert_int_equal(f.calls, 2);
    /* refused arguments: nothing passed */
    stream_buf z;
    memset(&z, 0, sizeof z);
    w.format = GEOM_MESHIO_FORMAT_AUTO;
    assert_int_equal(geom_meshio_write_stream(m, &w, stream_collect, &z, &d), GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_meshio_write_stream(m, NULL, NULL, &z, &d), GEOM_ERR_INVALID_ARG);
    assert_int_equal(z.calls, 0);
    free(b.p);
    free(f.p);
    geom_mesh_destroy(m);
    free(xyz);
    free(sizes);
    free(idx);
}

static void test_read_nomem(void **state)
{
    (void)state;
    int ok = 0;
    for (int left = 0; left < 400 && !ok; left++) {
        failing_alloc fa = {left, 0};
        geom_allocator al = {fa_alloc, fa_realloc, fa_free, &fa};
        geom_meshio_read_options o;
        memset(&o, 0, sizeof o);
        o.alloc = &al;
        geom_mesh *m = NULL;
        geom_diag d;
        geom_status st = geom_meshio_read_memory(variants, strlen(variants), "v.obj", &o, &m,
                                                 NULL, &d);
        if (st == GEOM_OK) {
            ok = 1;
            fa.left = 1 << 30; /* the checks allocate too */
            check_variants(m);
            geom_mesh_destroy(m);
        } else {
            assert_int_equal(st, GEOM_ERR_NOMEM);
            assert_null(m);
        }
        assert_int_equal(fa.live, 0);
    }
    assert_true(ok);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cube_seams_file), cmocka_unit_test(test_exact_doubles),
        cmocka_unit_test(test_syntax_variants), cmocka_unit_test(test_malformed),
        cmocka_unit_test(test_skip_invalid),    cmocka_unit_test(test_limits),
        cmocka_unit_test(test_osd_shapes),      cmocka_unit_test(test_format_names),
        cmocka_unit_test(test_atomic_write),    cmocka_unit_test(test_read_nomem),
        cmocka_unit_test(test_read_file_mapped), cmocka_unit_test(test_write_stream),
        cmocka_unit_test(test_face_lines),      cmocka_unit_test(test_integer_text),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
