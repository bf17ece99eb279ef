/*
 * OFF and STL reading and writing (geom/meshio.h).
 * OFF: the hand-written tetrahedron (orientation checked by its exact
 * volume), COFF/NOFF/STOFF/STCNOFF variants with integer and float colours,
 * counts on the OFF line, comments, face colours, exact round trips, and
 * malformed files with the line and column the diagnostic must name,
 * including header counts larger than the file can hold.
 * STL: the generated binary wedge (welded to 6 vertices, exact volume),
 * ASCII files (upper case, several solids, -0 welded with +0), a binary file
 * whose header starts with "solid", truncations, size mismatches, NaN,
 * degenerate triangles made by welding, and round trips in both encodings.
 */
#include "meshio_testutil.h"

#include <math.h>

/* ------------------------------------------------------------------- OFF */

static void test_tetra_off(void **state)
{
    (void)state;
    char path[1024];
    geom_mesh *m = NULL;
    geom_diag d;
    assert_int_equal(geom_meshio_read(mt_path(path, sizeof path, 0, "tetra.off"), NULL, &m, NULL,
                                      &d),
                     GEOM_OK);
    assert_int_equal(geom_mesh_n_vertices(m), 4);
    assert_int_equal(geom_mesh_n_faces(m), 4);
    assert_true(mt_volume6(m) == 1.0); /* 1/6 of the unit cube, outward faces */
    geom_mesh_topology t;
    assert_int_equal(geom_mesh_topology_summary(m, &t), GEOM_OK);
    assert_true(t.closed);
    assert_int_equal(t.edges, 6);
    size_t size;
    char *text = mt_write(m, GEOM_MESHIO_FORMAT_OFF, 0, &size);
    assert_true(strncmp(text, "OFF\n", 4) == 0);
    assert_non_null(strstr(text, "\n4 4 0\n"));
    assert_non_null(strstr(text, "\n3 0 2 1\n"));
    geom_mesh *m2 = NULL;
    assert_int_equal(mt_read(text, size, GEOM_MESHIO_FORMAT_OFF, 0, &m2, NULL, &d, NULL), GEOM_OK);
    mt_assert_same_positions(m, m2);
    assert_true(mt_volume6(m2) == 1.0);
    free(text);
    geom_mesh_destroy(m2);
    geom_mesh_destroy(m);
}

static void test_off_variants(void **state)
{
    (void)state;
    geom_mesh *m = NULL;
    geom_diag d;
    /* COFF with integer colours (0..255), counts on the OFF line, comments */
    const char *coff = "COFF 3 1 3 # counts here\n"
                       "# a comment line\n"
                       "0 0 0 255 0 0 255\n"
                       "1 0 0 0 255 0 255\n\n"
                       "0 1 0 0 0 255 0\n"
                       "3 0 1 2 255 255 255\n";
    geom_status s = mt_read(coff, (size_t)-1, GEOM_MESHIO_FORMAT_AUTO, 0, &m, NULL, &d, NULL);
    if (s != GEOM_OK)
        fprintf(stderr, "%zu:%zu %s\n", d.line, d.column, d.message);
    assert_int_equal(s, GEOM_OK);
    uint32_t c = geom_mesh_channel_find(m, "color", GEOM_MESH_DOMAIN_VERTEX);
    assert_int_not_equal(c, GEOM_INVALID_INDEX);
    assert_int_equal(geom_mesh_channel_ncomp(m, c), 4);
    const double want[12] = {1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 0};
    for (int i = 0; i < 12; i++)
        assert_true(geom_mesh_channel_cdata(m, c)[i] == want[i]);
    uint32_t fc = geom_mesh_channel_find(m, "color", GEOM_MESH_DOMAIN_FACE);
    assert_int_not_equal(fc, GEOM_INVALID_INDEX);
    assert_int_equal(geom_mesh_channel_ncomp(m, fc), 3);
    assert_true(geom_mesh_channel_cdata(m, fc)[0] == 1.0);
    /* written back as float colours, read back equal */
    size_t size;
    char *text = mt_write(m, GEOM_MESHIO_FORMAT_OFF, 0, &size);
    assert_true(strncmp(text, "COFF\n", 5) == 0);
    assert_non_null(strstr(text, "\n0 0 0 1.0 0.0 0.0 1.0\n"));
    geom_mesh *m2 = NULL;
    assert_int_equal(mt_read(text, size, GEOM_MESHIO_FORMAT_OFF, 0, &m2, NULL, &d, NULL), GEOM_OK);
    uint32_t c2 = geom_mesh_channel_find(m2, "color", GEOM_MESH_DOMAIN_VERTEX);
    for (int i = 0; i < 12; i++)
        assert_true(geom_mesh_channel_cdata(m2, c2)[i] == want[i]);
    free(text);
    geom_mesh_destroy(m2);
    geom_mesh_destroy(m);

    /* STCNOFF: x y z nx ny nz r g b s t, float colours, a quad */
    const char *st = "STCNOFF\n4 1 0\n"
                     "0 0 0 0 0 1 0.5 0.25 0.125 0 0\n"
                     "2 0 0 0 0 1 0.5 0.25 0.125 1 0\n"
                     "2 2 0 0 0 1 0.5 0.25 0.125 1 1\n"
                     "0 2 0 0 0 1 0.5 0.25 0.125 0 1\n"
                     "4 0 1 2 3\n";
    assert_int_equal(mt_read(st, (size_t)-1, GEOM_MESHIO_FORMAT_OFF, 0, &m, NULL, &d, NULL),
                     GEOM_OK);
    uint32_t n = geom_mesh_channel_find(m, "normal", GEOM_MESH_DOMAIN_VERTEX);
    uint32_t uv = geom_mesh_channel_find(m, "uv", GEOM_MESH_DOMAIN_VERTEX);
    c = geom_mesh_channel_find(m, "color", GEOM_MESH_DOMAIN_VERTEX);
    assert_int_not_equal(n, GEOM_INVALID_INDEX);
    assert_int_not_equal(uv, GEOM_INVALID_INDEX);
    assert_int_equal(geom_mesh_channel_ncomp(m, c), 3);
    assert_true(geom_mesh_channel_cdata(m, c)[2] == 0.125);
    assert_true(geom_mesh_channel_cdata(m, uv)[4] == 1 && geom_mesh_channel_cdata(m, uv)[5] == 1);
    assert_int_equal(geom_mesh_face_valence(m, 0), 4);
    text = mt_write(m, GEOM_MESHIO_FORMAT_OFF, 0, &size);
    assert_true(strncmp(text, "STCNOFF\n", 8) == 0);
    assert_non_null(strstr(text, "\n2 2 0 0 0 1 0.5 0.25 0.125 1.0 1 1\n"));
    assert_int_equal(mt_read(text, size, GEOM_MESHIO_FORMAT_OFF, 0, &m2, NULL, &d, NULL), GEOM_OK);
    mt_assert_same_positions(m, m2);
    free(text);
    geom_mesh_destroy(m2);
    geom_mesh_destroy(m);

    /* NOFF, CRLF */
    const char *noff = "NOFF\r\n3 1 0\r\n0 0 0 0 0 -1\r\n1 0 0 0 0 -1\r\n0 1 0 0 0 -1\r\n3 0 2 1\r\n";
    assert_int_equal(mt_read(noff, (size_t)-1, GEOM_MESHIO_FORMAT_OFF, 0, &m, NULL, &d, NULL),
                     GEOM_OK);
    assert_true(geom_mesh_channel_cdata(m, geom_mesh_channel_find(m, "normal",
                                                                  GEOM_MESH_DOMAIN_VERTEX))[2] ==
                -1.0);
    geom_mesh_destroy(m);
    /* no faces: a point cloud */
    assert_int_equal(mt_read("OFF\n2 0 0\n0 0 0\n1 1 1\n", (size_t)-1, GEOM_MESHIO_FORMAT_OFF, 0,
                             &m, NULL, &d, NULL),
                     GEOM_OK);
    assert_int_equal(geom_mesh_n_vertices(m), 2);
    assert_int_equal(geom_mesh_n_faces(m), 0);
    geom_mesh_destroy(m);
}

/* A comment glued to a number, as in CGAL's mesh_with_colors.off. */
static void test_off_glued_comment(void **state)
{
    (void)state;
    geom_mesh *m = NULL;
    geom_diag d;
    const char *off = "OFF\n3 1 0\n0 0 0#first\n1 0 0\n0 1 0 # last\n3 0 1 2#red\n";
    assert_int_equal(mt_read(off, (size_t)-1, GEOM_MESHIO_FORMAT_OFF, 0, &m, NULL, &d, NULL),
                     GEOM_OK);
    assert_int_equal(geom_mesh_n_vertices(m), 3);
    assert_int_equal(geom_mesh_n_faces(m), 1);
    assert_true(geom_mesh_cpositions(m)[3] == 1.0);
    geom_mesh_destroy(m);
}

static void test_off_malformed(void **state)
{
    (void)state;
    static const struct {
        const char *text;
        geom_status status;
        size_t line, col;
        const char *msg;
    } cases[] = {
        {"", GEOM_ERR_PARSE, 1, 1, "empty"},
        {"# only a comment\n", GEOM_ERR_PARSE, 1, 1, "empty"},
        {"OF\n", GEOM_ERR_PARSE, 1, 1, "[ST][C][N]OFF"},
        {"4OFF\n", GEOM_ERR_PARSE, 1, 1, "not supported"},
        {"OFF BINARY\n", GEOM_ERR_PARSE, 1, 5, "binary"},
        {"OFF\n", GEOM_ERR_PARSE, 2, 1, "counts"},
        {"OFF\n3\n", GEOM_ERR_PARSE, 2, 1, "nvertices nfaces"},
        {"OFF\n3 x 0\n", GEOM_ERR_PARSE, 2, 3, "number of faces"},
        {"OFF\n-3 1 0\n", GEOM_ERR_PARSE, 2, 1, "number of vertices"},
        {"OFF\n300000000 1 0\n", GEOM_ERR_LIMIT, 2, 1, "limit"},
        {"OFF\n100000 1 0\n0 0 0\n", GEOM_ERR_PARSE, 2, 1, "only 6 bytes"},
        {"OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n", GEOM_ERR_PARSE, 4, 1, "found 2 values"},
        {"OFF\n3 1 0\n0 0 0\n1 0 0 5\n0 1 0\n3 0 1 2\n", GEOM_ERR_PARSE, 4, 1, "found 4 values"},
        {"OFF\n3 1 0\n0 0 0\n1 y 0\n0 1 0\n3 0 1 2\n", GEOM_ERR_PARSE, 4, 3, "expected a number"},
        {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", GEOM_ERR_PARSE, 6, 7, "out of range"},
        {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n", GEOM_ERR_PARSE, 6, 6, "line has 2"},
        {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 0.5\n", GEOM_ERR_PARSE, 6, 9, "colour"},
        {"OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", GEOM_ERR_PARSE, 7, 1, "face 1 (0-based) of 2"},
        {"OFF\n3 1 0\n0 0 0\n1 0 0\n", GEOM_ERR_PARSE, 2, 1, "only 12 bytes"},
        {"OFF\n3 1 0\n0 0 0\n1 0 0\n# a comment long enough to pass the size check\n",
         GEOM_ERR_PARSE, 6, 1, "vertex 2 (0-based) of 3"},
        {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\nx 0 1 2\n", GEOM_ERR_PARSE, 6, 1, "vertex count"},
        {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 1\n", GEOM_ERR_PARSE, 6, 0, "appears twice"},
        {"COFF\n2 0 0\n0 0 0 1 0 0\n0 0 0 1 0 0 1\n", GEOM_ERR_PARSE, 4, 7, "3 colour"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        geom_mesh *m = NULL;
        geom_diag d;
        geom_status st = mt_read(cases[i].text, (size_t)-1, GEOM_MESHIO_FORMAT_OFF, 0, &m, NULL,
                                 &d, NULL);
        if (st != cases[i].status || d.line != cases[i].line ||
            (cases[i].col && d.column != cases[i].col) || !strstr(d.message, cases[i].msg)) {
            fprintf(stderr, "case %zu: status %d at %zu:%zu '%s'\n", i, st, d.line, d.column,
                    d.message);
            fail();
        }
        assert_null(m);
    }
}

/* ------------------------------------------------------------------- STL */

static void test_wedge_stl(void **state)
{
    (void)state;
    char path[1024];
    geom_mesh *m = NULL;
    geom_diag d;
    geom_meshio_read_options o;
    geom_meshio_read_stats st;
    memset(&o, 0, sizeof o);
    o.stats = &st;
    assert_int_equal(geom_meshio_read(mt_path(path, sizeof path, 0, "wedge.stl"), &o, &m, NULL,
                                      &d),
                     GEOM_OK);
    assert_int_equal(st.binary, 1);
    assert_int_equal(st.welded_corners, 24 - 6);
    /* every truncation is a parse error, never a crash or a partial mesh */
    {
        size_t fsize;
        unsigned char *raw = mt_slurp(path, &fsize);
        assert_int_equal(fsize, 84 + 50 * 8);
        for (size_t cut = 0; cut < fsize; cut++) {
            geom_mesh *t = NULL;
            unsigned char *copy = malloc(cut ? cut : 1);
            memcpy(copy, raw, cut);
            assert_int_equal(mt_read(copy, cut, GEOM_MESHIO_FORMAT_STL, 0, &t, NULL, &d, NULL),
                             GEOM_ERR_PARSE);
            assert_null(t);
            assert_true(d.byte_offset <= cut);
            free(copy);
        }
        free(raw);
    }
    assert_int_equal(geom_mesh_n_vertices(m), 6);
    assert_int_equal(geom_mesh_n_faces(m), 8);
    assert_true(mt_volume6(m) == 6.0); /* area 1/2 times height 2 */
    geom_mesh_topology t;
    assert_int_equal(geom_mesh_topology_summary(m, &t), GEOM_OK);
    assert_true(t.closed);
    assert_int_equal(t.euler, 2);
    for (int e = 0; e < 2; e++) {
        size_t size;
        char *data = mt_write(m, GEOM_MESHIO_FORMAT_STL,
                              e ? GEOM_MESHIO_ENCODING_ASCII : GEOM_MESHIO_ENCODING_DEFAULT, &size);
        if (e) {
            assert_true(strncmp(data, "solid ", 6) == 0);
        } else {
            assert_int_equal(size, 84 + 50 * 8);
            assert_true(strncmp(data, "solid", 5) != 0);
        }
        geom_mesh *m2 = NULL;
        assert_int_equal(mt_read(data, size, GEOM_MESHIO_FORMAT_AUTO, 0, &m2, NULL, &d, &st),
                         GEOM_OK);
        assert_int_equal(st.format, GEOM_MESHIO_FORMAT_STL);
        assert_int_equal(st.binary, !e);
        mt_assert_same_positions(m, m2);
        assert_true(mt_volume6(m2) == 6.0);
        free(data);
        geom_mesh_destroy(m2);
    }
    geom_mesh_destroy(m);
}

static void test_stl_ascii(void **state)
{
    (void)state;
    /* two solids, upper-case keywords, -0 equal to +0, a quad loop */
    const char *text = "solid part one\n"
                       "  FACET NORMAL 0 0 -1\n"
                       "    OUTER LOOP\n"
                       "      VERTEX 0 0 0\n"
                       "      VERTEX 0 1 0\n"
                       "      VERTEX 1 0 0\n"
                       "    ENDLOOP\n"
                       "  ENDFACET\n"
                       "endsolid part one\n"
                       "solid two\n"
                       "facet normal 0 0 1\nouter loop\n"
                       "vertex -0 0 0\nvertex 1 0 -0.0\nvertex 1 1 0\nvertex 0 1 0\n"
                       "endloop\nendfacet\n"
                       "endsolid";
    geom_mesh *m = NULL;
    geom_diag d;
    geom_meshio_read_stats st;
    geom_status s = mt_read(text, (size_t)-1, GEOM_MESHIO_FORMAT_AUTO, 0, &m, NULL, &d, &st);
    if (s != GEOM_OK)
        fprintf(stderr, "%zu:%zu %s\n", d.line, d.column, d.message);
    assert_int_equal(s, GEOM_OK);
    assert_int_equal(st.binary, 0);
    assert_int_equal(geom_mesh_n_vertices(m), 4);
    assert_int_equal(geom_mesh_n_faces(m), 2);
    assert_int_equal(st.welded_corners, 3);
    /* the welded -0 stored as +0 */
    const double *p = geom_mesh_cpositions(m);
    for (int i = 0; i < 12; i++)
        assert_false(signbit(p[i]));
    geom_mesh_destroy(m);

    /* binary whose 80-byte header starts with "solid": detected by size */
    unsigned char bin[84 + 50];
    memset(bin, 0, sizeof bin);
    memcpy(bin, "solid but binary", 16);
    bin[80] = 1;
    float tri[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    memcpy(bin + 84 + 12, tri, sizeof tri);
    assert_int_equal(mt_read(bin, sizeof bin, GEOM_MESHIO_FORMAT_STL, 0, &m, NULL, &d, &st),
                     GEOM_OK);
    assert_int_equal(st.binary, 1);
    assert_int_equal(geom_mesh_n_faces(m), 1);
    geom_mesh_destroy(m);
    /* truncated by one byte: a size mismatch, reported at the count */
    assert_int_equal(mt_read(bin, sizeof bin - 1, GEOM_MESHIO_FORMAT_STL, 0, &m, NULL, &d, &st),
                     GEOM_ERR_PARSE);
    assert_int_equal(d.byte_offset, 80);
    assert_non_null(strstr(d.message, "declares 1 triangles"));
    /* an absurd count */
    bin[83] = 0x7f;
    assert_int_equal(mt_read(bin, sizeof bin, GEOM_MESHIO_FORMAT_STL, 0, &m, NULL, &d, &st),
                     GEOM_ERR_PARSE);
    assert_int_equal(d.byte_offset, 80);
    bin[83] = 0;
    /* NaN */
    uint32_t nan_bits = 0x7fc00000u;
    memcpy(bin + 84 + 12 + 16, &nan_bits, 4);
    assert_int_equal(mt_read(bin, sizeof bin, GEOM_MESHIO_FORMAT_STL, 0, &m, NULL, &d, &st),
                     GEOM_ERR_PARSE);
    assert_int_equal(d.byte_offset, 84 + 12 + 16);
    /* a triangle that welding makes degenerate: error, or skipped */
    memcpy(bin + 84 + 12, tri, sizeof tri);
    memcpy(bin + 84 + 12 + 24, tri, 12); /* third corner = first */
    geom_mesh_build_report r;
    assert_int_equal(mt_read(bin, sizeof bin, GEOM_MESHIO_FORMAT_STL, 0, &m, &r, &d, &st),
                     GEOM_ERR_PARSE);
    assert_int_equal(d.byte_offset, 84);
    assert_non_null(strstr(d.message, "appears twice"));
    assert_int_equal(mt_read(bin, sizeof bin, GEOM_MESHIO_FORMAT_STL, 1, &m, &r, &d, &st),
                     GEOM_OK);
    assert_int_equal(r.invalid_faces, 1);
    assert_int_equal(r.first_invalid_faces[0], 0);
    assert_int_equal(geom_mesh_n_faces(m), 0);
    geom_mesh_destroy(m);
    /* too short for binary and not ASCII */
    assert_int_equal(mt_read("xyz", 3, GEOM_MESHIO_FORMAT_STL, 0, &m, NULL, &d, NULL),
                     GEOM_ERR_PARSE);
}

static void test_stl_malformed(void **state)
{
    (void)state;
    static const struct {
        const char *text;
        size_t line, col;
        const char *msg;
    } cases[] = {
        {"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
         "endloop\nendfacet\n",
         9, 1, "'endsolid'"},
        {"solid x\nfacet normal 0 0\nouter loop\n", 3, 1, "expected a number"},
        {"solid x\nfacet normal 0 0 1\nouter lop\n", 3, 7, "'loop'"},
        {"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 z\n", 5, 12,
         "expected a number"},
        {"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvert 1 0 0\n", 5, 1,
         "'vertex' or 'endloop'"},
        {"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
         "endloop\nendfacet\nendsolid x\ngarbage\n",
         10, 1, "after 'endsolid'"},
        {"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\n"
         "endfacet\nendsolid\n",
         2, 0, "at least 3"},
        {"solid x\nfoo\n", 2, 1, "'facet' or 'endsolid'"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        geom_mesh *m = NULL;
        geom_diag d;
        geom_status st = mt_read(cases[i].text, (size_t)-1, GEOM_MESHIO_FORMAT_STL, 0, &m, NULL,
                                 &d, NULL);
        if (st != GEOM_ERR_PARSE || d.line != cases[i].line ||
            (cases[i].col && d.column != cases[i].col) || !strstr(d.message, cases[i].msg)) {
            fprintf(stderr, "case %zu: status %d at %zu:%zu '%s'\n", i, st, d.line, d.column,
                    d.message);
            fail();
        }
        assert_null(m);
    }
}

/* Writing a polygon mesh to STL triangulates a copy; the normal is the
 * face's. */
static void test_stl_polygons(void **state)
{
    (void)state;
    char path[1024];
    geom_mesh *m = NULL;
    assert_int_equal(geom_meshio_read(mt_path(path, sizeof path, 0, "cube_seams.obj"), NULL, &m,
                                      NULL, NULL),
                     GEOM_OK);
    size_t size;
    unsigned char *data = mt_write(m, GEOM_MESHIO_FORMAT_STL, 0, &size);
    assert_int_equal(size, 84 + 50 * 12);
    for (int t = 0; t < 12; t++) {
        float f[12];
        memcpy(f, data + 84 + 50 * t, sizeof f);
        /* the stored normal is a unit axis vector, and the corners lie in
         * the face plane it defines */
        int axis = -1;
        for (int k = 0; k < 3; k++)
            if (f[k] != 0)
                axis = k;
        assert_true(axis >= 0 && fabsf(f[axis]) == 1.0f);
        float plane = f[axis] > 0 ? 1.0f : 0.0f;
        for (int c = 0; c < 3; c++)
            assert_true(f[3 + 3 * c + axis] == plane);
    }
    geom_mesh *m2 = NULL;
    geom_diag d;
    assert_int_equal(mt_read(data, size, GEOM_MESHIO_FORMAT_STL, 0, &m2, NULL, &d, NULL), GEOM_OK);
    assert_int_equal(geom_mesh_n_vertices(m2), 8);
    assert_true(mt_volume6(m2) == 6.0);
    free(data);
    geom_mesh_destroy(m2);
    geom_mesh_destroy(m);
}

/* STL and GLB triangulate polygons one face at a time: the files are the
 * ones written from the mesh geom_mesh_triangulate makes (nonconvex
 * polygons, a deleted face, corner uvs for GLB). */
static void test_polygons_as_triangulated(void **state)
{
    (void)state;
    const char *obj = "v 0 0 0\nv 4 0 0\nv 4 3 0\nv 2 1 0\nv 0 3 0\nv 0 0 2\nv 4 0 2\n"
                      "v 1 5 1\nv 3 5 1.5\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0.5 0.25\nvt 0 1\n"
                      "f 1/1 2/2 3/3 4/4 5/5\nf 2/1 1/2 6/3 7/4\nf 3/1 9/2 8/3 5/4 4/5\n"
                      "f 2/2 7/3 3/1\n";
    geom_mesh *m = NULL;
    geom_diag d;
    assert_int_equal(mt_read(obj, (size_t)-1, GEOM_MESHIO_FORMAT_OBJ, 0, &m, NULL, &d, NULL),
                     GEOM_OK);
    for (int del = 0; del < 2; del++) {
        if (del)
            assert_int_equal(geom_mesh_delete_face(m, 1), GEOM_OK);
        geom_mesh *t = NULL;
        assert_int_equal(geom_mesh_clone(m, &t), GEOM_OK);
        assert_int_equal(geom_mesh_triangulate(t, NULL), GEOM_OK);
        const geom_meshio_format fmt[3] = {GEOM_MESHIO_FORMAT_STL, GEOM_MESHIO_FORMAT_STL,
                                           GEOM_MESHIO_FORMAT_GLB};
        const geom_meshio_encoding enc[3] = {0, GEOM_MESHIO_ENCODING_ASCII, 0};
        for (int k = 0; k < 3; k++) {
            size_t na, nb;
            void *a = mt_write(m, fmt[k], enc[k], &na);
            void *b = mt_write(t, fmt[k], enc[k], &nb);
            assert_int_equal(na, nb);
            assert_memory_equal(a, b, na);
            free(a);
            free(b);
        }
        geom_mesh_destroy(t);
    }
    geom_mesh_destroy(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tetra_off),   cmocka_unit_test(test_off_variants),
        cmocka_unit_test(test_off_glued_comment),
        cmocka_unit_test(test_off_malformed), cmocka_unit_test(test_wedge_stl),
        cmocka_unit_test(test_stl_ascii),   cmocka_unit_test(test_stl_malformed),
        cmocka_unit_test(test_stl_polygons), cmocka_unit_test(test_polygons_as_triangulated),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
