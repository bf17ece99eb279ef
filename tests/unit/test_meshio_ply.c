/*
 * PLY reading and writing (geom/meshio.h): the generated binary pyramid
 * (float coordinates, uchar colours, an unknown element with a list and
 * unknown properties), an ASCII file using many scalar and list types,
 * property aliases, CRLF and MeshLab texcoord lists, the same mesh hand-
 * encoded little and big endian, bit-exact round trips in ascii,
 * binary_little_endian and binary_big_endian, every truncation of a binary
 * file, absurd header counts, and malformed headers and data with the line
 * or byte offset the diagnostic must name.
 */
#include "meshio_testutil.h"

#include <math.h>

/* ----------------------------------------------------------- the pyramid */

static const double pyr_xyz[5][3] = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}, {0, 0, 1}};
static const double pyr_rgb[5][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {1, 1, 1}};
static const int pyr_faces[5][4] = {{0, 3, 2, 1}, {0, 1, 4, -1}, {1, 2, 4, -1}, {2, 3, 4, -1},
                                    {3, 0, 4, -1}};

static void check_pyramid(const geom_mesh *m, int colors)
{
    assert_int_equal(geom_mesh_n_vertices(m), 5);
    assert_int_equal(geom_mesh_n_faces(m), 5);
    const double *p = geom_mesh_cpositions(m);
    for (int v = 0; v < 5; v++)
        for (int k = 0; k < 3; k++)
            assert_true(p[3 * v + k] == pyr_xyz[v][k]);
    for (uint32_t f = 0; f < 5; f++) {
        uint32_t vs[4];
        size_t n = mt_face_verts(m, f, vs, 4);
        assert_int_equal(n, f == 0 ? 4 : 3);
        for (size_t k = 0; k < n; k++)
            assert_int_equal(vs[k], pyr_faces[f][k]);
    }
    /* 6 * (1/3 * base 4 * height 1) */
    assert_true(mt_volume6(m) == 8.0);
    geom_mesh_topology t;
    assert_int_equal(geom_mesh_topology_summary(m, &t), GEOM_OK);
    assert_true(t.closed);
    assert_int_equal(t.euler, 2);
    if (colors) {
        uint32_t c = geom_mesh_channel_find(m, "color", GEOM_MESH_DOMAIN_VERTEX);
        assert_int_not_equal(c, GEOM_INVALID_INDEX);
        assert_int_equal(geom_mesh_channel_ncomp(m, c), 3);
        const double *cd = geom_mesh_channel_cdata(m, c);
        for (int v = 0; v < 5; v++)
            for (int k = 0; k < 3; k++)
                assert_true(cd[3 * v + k] == pyr_rgb[v][k]);
    }
}

static void test_pyramid_file(void **state)
{
    (void)state;
    char path[1024];
    geom_mesh *m = NULL;
    geom_diag d;
    geom_meshio_read_options o;
    geom_meshio_read_stats st;
    memset(&o, 0, sizeof o);
    o.stats = &st;
    assert_int_equal(geom_meshio_read(mt_path(path, sizeof path, 0, "pyramid.ply"), &o, &m, NULL,
                                      &d),
                     GEOM_OK);
    check_pyramid(m, 1);
    assert_int_equal(st.format, GEOM_MESHIO_FORMAT_PLY);
    assert_int_equal(st.binary, 1);
    assert_int_equal(st.skipped_elements, 1);   /* material */
    assert_int_equal(st.skipped_properties, 2); /* quality, flags */

    /* round trips: exact in every encoding */
    const geom_meshio_encoding encs[] = {GEOM_MESHIO_ENCODING_DEFAULT, GEOM_MESHIO_ENCODING_ASCII,
                                         GEOM_MESHIO_ENCODING_BINARY_BE};
    const char *heads[] = {"format binary_little_endian 1.0\n", "format ascii 1.0\n",
                           "format binary_big_endian 1.0\n"};
    for (int i = 0; i < 3; i++) {
        size_t size;
        char *data = mt_write(m, GEOM_MESHIO_FORMAT_PLY, encs[i], &size);
        assert_non_null(strstr(data, heads[i]));
        assert_non_null(strstr(data, "property uchar red\n"));
        assert_non_null(strstr(data, "property list uchar int vertex_indices\n"));
        geom_mesh *m2 = NULL;
        assert_int_equal(mt_read(data, size, GEOM_MESHIO_FORMAT_PLY, 0, &m2, NULL, &d, NULL),
                         GEOM_OK);
        check_pyramid(m2, 1);
        mt_assert_same_positions(m, m2);
        geom_mesh_destroy(m2);
        free(data);
    }
    geom_mesh_destroy(m);
}

/* ------------------------------------------------ hand-encoded binaries */

typedef struct bytes {
    unsigned char b[4096];
    size_t n;
} bytes;

static void put_raw(bytes *o, const void *p, size_t n, int be)
{
    const unsigned char *s = p;
    for (size_t i = 0; i < n; i++)
        o->b[o->n + i] = s[be ? n - 1 - i : i]; /* the host is little endian (checked) */
    o->n += n;
}
static void put_str(bytes *o, const char *s) { put_raw(o, s, strlen(s), 0); }
static void put_f64(bytes *o, double v, int be) { put_raw(o, &v, 8, be); }
static void put_i32(bytes *o, int32_t v, int be) { put_raw(o, &v, 4, be); }
static void put_u16(bytes *o, uint16_t v, int be) { put_raw(o, &v, 2, be); }

/* The pyramid with double coordinates, ushort list counts and int indices,
 * and an unknown double "confidence" list per vertex. */
static void encode_pyramid(bytes *o, int be)
{
    o->n = 0;
    put_str(o, "ply\n");
    put_str(o, be ? "format binary_big_endian 1.0\n" : "format binary_little_endian 1.0\n");
    put_str(o, "element vertex 5\nproperty double x\nproperty double y\nproperty double z\n"
               "property list uchar double confidence\n"
               "element face 5\nproperty list ushort int vertex_indices\nend_header\n");
    for (int v = 0; v < 5; v++) {
        for (int k = 0; k < 3; k++)
            put_f64(o, pyr_xyz[v][k], be);
        unsigned char cnt = (unsigned char)v;
        put_raw(o, &cnt, 1, be);
        for (int k = 0; k < v; k++)
            put_f64(o, 0.5 * k, be);
    }
    for (int f = 0; f < 5; f++) {
        int n = f == 0 ? 4 : 3;
        put_u16(o, (uint16_t)n, be);
        for (int k = 0; k < n; k++)
            put_i32(o, pyr_faces[f][k], be);
    }
}

static void test_endianness(void **state)
{
    (void)state;
    uint16_t probe = 1;
    unsigned char first;
    memcpy(&first, &probe, 1);
    if (first != 1)
        skip(); /* encode_pyramid assumes a little-endian host */
    static bytes le, be;
    encode_pyramid(&le, 0);
    encode_pyramid(&be, 1);
    for (int i = 0; i < 2; i++) {
        bytes *b = i ? &be : &le;
        geom_mesh *m = NULL;
        geom_diag d;
        geom_meshio_read_stats st;
        geom_status s = mt_read(b->b, b->n, GEOM_MESHIO_FORMAT_PLY, 0, &m, NULL, &d, &st);
        if (s != GEOM_OK)
            fprintf(stderr, "%s\n", d.message);
        assert_int_equal(s, GEOM_OK);
        check_pyramid(m, 0);
        assert_int_equal(st.skipped_properties, 1);
        geom_mesh_destroy(m);
    }
    /* every truncation of the binary data is a parse error with an offset */
    const char *eh = strstr((const char *)le.b, "end_header\n");
    size_t header = (size_t)(eh - (const char *)le.b) + 11;
    for (size_t cut = 0; cut < le.n; cut++) {
        geom_mesh *m = NULL;
        geom_diag d;
        geom_status s = mt_read(le.b, cut, GEOM_MESHIO_FORMAT_PLY, 0, &m, NULL, &d, NULL);
        assert_int_equal(s, GEOM_ERR_PARSE);
        assert_null(m);
        if (cut > header) {
            /* either the size check before reading (a line) or a read past
             * the end (the offset where it happened) */
            assert_true(d.line != 0 || (d.byte_offset >= header && d.byte_offset <= cut));
        }
    }
}

/* ------------------------------------------------------------ ASCII types */

static const char ascii_ply[] =
    "ply\r\n"
    "format ascii 1.0\r\n"
    "comment many types\r\n"
    "obj_info nothing\r\n"
    "element vertex 4\r\n"
    "property double x\r\n"
    "property float32 y\r\n"
    "property int z\r\n"
    "property short nx\r\n"
    "property int8 ny\r\n"
    "property uint nz\r\n"
    "property float texture_u\r\n"
    "property float texture_v\r\n"
    "property ushort red\r\n"
    "property ushort green\r\n"
    "property ushort blue\r\n"
    "property ushort alpha\r\n"
    "element edge 2\r\n"
    "property list int int vertex_pair\r\n"
    "property uchar flag\r\n"
    "element face 2\r\n"
    "property list uint16 int8 vertex_index\r\n"
    "property list uchar float texcoord\r\n"
    "property uchar red\r\n"
    "property uchar green\r\n"
    "property uchar blue\r\n"
    "end_header\r\n"
    "0 0 0 0 0 1 0 0 65535 0 65535 65535\r\n"
    "1.5 0 0 0 0 1 1 0 0 65535 0 0\r\n"
    "1.5 2.25 0 0 0 1 1 1 0 0 65535 65535\r\n"
    "0 2.25 -3 0 0 1 0 1 0 0 0 0\r\n"
    "2 0 1 7\r\n"
    "2 1 2 7\r\n"
    "3 0 1 2 6 0 0 1 0 1 1 255 0 0\r\n"
    "3 0 2 3 0 0 51 255\r\n";

static void test_ascii_types(void **state)
{
    (void)state;
    geom_mesh *m = NULL;
    geom_diag d;
    geom_meshio_read_stats st;
    geom_status s = mt_read(ascii_ply, (size_t)-1, GEOM_MESHIO_FORMAT_AUTO, 0, &m, NULL, &d, &st);
    if (s != GEOM_OK)
        fprintf(stderr, "%zu:%zu %s\n", d.line, d.column, d.message);
    assert_int_equal(s, GEOM_OK);
    assert_int_equal(st.format, GEOM_MESHIO_FORMAT_PLY); /* sniffed */
    assert_int_equal(st.skipped_elements, 2);
    assert_int_equal(geom_mesh_n_vertices(m), 4);
    assert_int_equal(geom_mesh_n_faces(m), 2);
    const double *p = geom_mesh_cpositions(m);
    const double want_p[12] = {0, 0, 0, 1.5, 0, 0, 1.5, 2.25, 0, 0, 2.25, -3};
    for (int i = 0; i < 12; i++)
        assert_true(p[i] == want_p[i]);
    uint32_t n = geom_mesh_channel_find(m, "normal", GEOM_MESH_DOMAIN_VERTEX);
    uint32_t uv = geom_mesh_channel_find(m, "uv", GEOM_MESH_DOMAIN_VERTEX);
    uint32_t c = geom_mesh_channel_find(m, "color", GEOM_MESH_DOMAIN_VERTEX);
    uint32_t tc = geom_mesh_channel_find(m, "uv", GEOM_MESH_DOMAIN_CORNER);
    uint32_t fc = geom_mesh_channel_find(m, "color", GEOM_MESH_DOMAIN_FACE);
    assert_int_not_equal(n, GEOM_INVALID_INDEX);
    assert_int_not_equal(uv, GEOM_INVALID_INDEX);
    assert_int_not_equal(c, GEOM_INVALID_INDEX);
    assert_int_not_equal(tc, GEOM_INVALID_INDEX);
    assert_int_not_equal(fc, GEOM_INVALID_INDEX);
    assert_int_equal(geom_mesh_channel_ncomp(m, c), 4);
    const double *cd = geom_mesh_channel_cdata(m, c);
    /* ushort colours: /65535 gives exactly 0 and 1 */
    const double want_c[16] = {1, 0, 1, 1, 0, 1, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0};
    for (int i = 0; i < 16; i++)
        assert_true(cd[i] == want_c[i]);
    const double *nd = geom_mesh_channel_cdata(m, n);
    for (int v = 0; v < 4; v++)
        assert_true(nd[3 * v] == 0 && nd[3 * v + 1] == 0 && nd[3 * v + 2] == 1);
    const double *ud = geom_mesh_channel_cdata(m, uv);
    const double want_uv[8] = {0, 0, 1, 0, 1, 1, 0, 1};
    for (int i = 0; i < 8; i++)
        assert_true(ud[i] == want_uv[i]);
    /* the texcoord list: face 0 has one (0,0) (1,0) (1,1), face 1 none */
    const uint32_t *ti = geom_mesh_corner_cindices(m, tc);
    const double *td = geom_mesh_channel_cdata(m, tc);
    uint32_t h = geom_mesh_face_he(m, 0);
    for (int k = 0; k < 3; k++) {
        assert_int_not_equal(ti[h], GEOM_INVALID_INDEX);
        assert_true(td[2 * ti[h]] == want_uv[2 * k] && td[2 * ti[h] + 1] == want_uv[2 * k + 1]);
        h = geom_mesh_he_next(m, h);
    }
    h = geom_mesh_face_he(m, 1);
    for (int k = 0; k < 3; k++) {
        assert_int_equal(ti[h], GEOM_INVALID_INDEX);
        h = geom_mesh_he_next(m, h);
    }
    const double *fd = geom_mesh_channel_cdata(m, fc);
    assert_true(fd[0] == 1 && fd[1] == 0 && fd[2] == 0);
    assert_true(fd[3] == 0 && fd[4] == 51.0 / 255.0 && fd[5] == 1);

    /* ascii write and read back, exact */
    size_t size;
    char *text = mt_write(m, GEOM_MESHIO_FORMAT_PLY, GEOM_MESHIO_ENCODING_ASCII, &size);
    geom_mesh *m2 = NULL;
    assert_int_equal(mt_read(text, size, GEOM_MESHIO_FORMAT_PLY, 0, &m2, NULL, &d, NULL), GEOM_OK);
    /* PLY holds uv per vertex: the corners of face 1 (no texcoord) split
     * vertices 0 and 2 from face 0's; the first four keep their numbers */
    assert_int_equal(geom_mesh_n_vertices(m2), 6);
    const double *p2 = geom_mesh_cpositions(m2);
    for (int i = 0; i < 12; i++)
        assert_true(p2[i] == want_p[i]);
    uint32_t fc2 = geom_mesh_channel_find(m2, "color", GEOM_MESH_DOMAIN_FACE);
    assert_int_not_equal(fc2, GEOM_INVALID_INDEX);
    assert_true(geom_mesh_channel_cdata(m2, fc2)[4] == 51.0 / 255.0);
    free(text);
    geom_mesh_destroy(m2);
    geom_mesh_destroy(m);
}

/* ------------------------------------------------- random exact round trip */

static void test_exact_binary(void **state)
{
    (void)state;
    enum { N = 500 };
    static double xyz[3 * N];
    static uint32_t sizes[N - 2], idx[3 * (N - 2)];
    uint64_t s = 99;
    for (size_t i = 0; i < 3 * N; i++) {
        s = s * 6364136223846793005ull + 1442695040888963407ull;
        double x;
        uint64_t bits = s;
        memcpy(&x, &bits, 8);
        xyz[i] = isfinite(x) ? x : (double)(s >> 11) * 1e-300;
    }
    for (uint32_t f = 0; f < N - 2; f++) {
        sizes[f] = 3;
        idx[3 * f] = f;
        idx[3 * f + 1] = f % 2 ? f + 2 : f + 1;
        idx[3 * f + 2] = f % 2 ? f + 1 : f + 2;
    }
    geom_mesh *m = geom_mesh_create(NULL);
    assert_int_equal(geom_mesh_build(m, N, xyz, N - 2, sizes, idx, NULL, NULL, NULL), GEOM_OK);
    for (int e = 1; e <= 3; e++) {
        size_t size;
        void *data = mt_write(m, GEOM_MESHIO_FORMAT_PLY, (geom_meshio_encoding)e, &size);
        geom_mesh *m2 = NULL;
        geom_diag d;
        assert_int_equal(mt_read(data, size, GEOM_MESHIO_FORMAT_PLY, 0, &m2, NULL, &d, NULL),
                         GEOM_OK);
        mt_assert_same_positions(m, m2);
        geom_mesh_destroy(m2);
        free(data);
    }
    geom_mesh_destroy(m);
}

/* --------------------------------------------------------------- errors */

static void test_malformed(void **state)
{
    (void)state;
    static const struct {
        const char *text;
        geom_status status;
        size_t line, col;
        const char *msg;
    } cases[] = {
        {"plx\n", GEOM_ERR_PARSE, 1, 1, "'ply'"},
        {"ply\nformat foo 1.0\nend_header\n", GEOM_ERR_PARSE, 2, 8, "binary_big_endian"},
        {"ply\nformat ascii 1.0\nproperty float x\nend_header\n", GEOM_ERR_PARSE, 3, 1,
         "before any"},
        {"ply\nformat ascii 1.0\nelement vertex\nend_header\n", GEOM_ERR_PARSE, 3, 1,
         "element <name> <count>"},
        {"ply\nformat ascii 1.0\nelement vertex 1\nproperty flt x\nend_header\n", GEOM_ERR_PARSE, 4,
         1, "property <type>"},
        {"ply\nformat ascii 1.0\nelement vertex 1\nproperty list float int x\nend_header\n",
         GEOM_ERR_PARSE, 4, 1, "property list"},
        {"ply\nformat ascii 1.0\nelement vertex 0\n", GEOM_ERR_PARSE, 4, 1, "end_header"},
        {"ply\nelement vertex 0\nend_header\n", GEOM_ERR_PARSE, 3, 1, "format"},
        {"ply\nformat ascii 1.0\nbogus line\nend_header\n", GEOM_ERR_PARSE, 3, 1, "bogus"},
        {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float y\nend_header\n0\n",
         GEOM_ERR_PARSE, 1, 0, "x, y and z"},
        {"ply\nformat ascii 1.0\nelement vertex 4294967296\nproperty float x\nend_header\n",
         GEOM_ERR_LIMIT, 3, 16, "limit"},
        {"ply\nformat ascii 1.0\nelement vertex 100000000\nproperty float x\nproperty float "
         "y\nproperty float z\nend_header\n0 0 0\n",
         GEOM_ERR_PARSE, 8, 1, "only 6 bytes"},
        {"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
         "property float z\nend_header\n0 0 0\n1 0 x\n",
         GEOM_ERR_PARSE, 9, 5, "expected a number"},
        {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
         "property float z\nproperty uchar red\nend_header\n0 0 0 1.5\n",
         GEOM_ERR_PARSE, 9, 7, "integer"},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
         "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
         "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n",
         GEOM_ERR_PARSE, 13, 0, "out of range"},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
         "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
         "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n",
         GEOM_ERR_PARSE, 13, 5, "negative"},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
         "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
         "end_header\n0 0 0\n1 0 0\n0 1 0\n200 0 1 2\n",
         GEOM_ERR_PARSE, 13, 1, "list length"},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
         "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
         "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n",
         GEOM_ERR_PARSE, 14, 1, "end of file"},
        {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
         "property float z\nend_header\n0 0 1e400\n",
         GEOM_ERR_PARSE, 8, 5, "out of range"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        geom_mesh *m = NULL;
        geom_diag d;
        geom_status st = mt_read(cases[i].text, (size_t)-1, GEOM_MESHIO_FORMAT_PLY, 0, &m, NULL,
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

/* Binary errors name byte offsets. */
static void test_binary_errors(void **state)
{
    (void)state;
    static bytes b;
    const char *head = "ply\nformat binary_little_endian 1.0\nelement vertex 3\n"
                       "property float x\nproperty float y\nproperty float z\n"
                       "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    size_t hl = strlen(head);
    /* a list count of 255 with 13 bytes left */
    b.n = 0;
    put_str(&b, head);
    float zero = 0, one = 1;
    for (int v = 0; v < 3; v++) {
        put_raw(&b, v == 1 ? &one : &zero, 4, 0);
        put_raw(&b, v == 2 ? &one : &zero, 4, 0);
        put_raw(&b, &zero, 4, 0);
    }
    unsigned char cnt = 255;
    put_raw(&b, &cnt, 1, 0);
    for (int k = 0; k < 3; k++)
        put_i32(&b, k, 0);
    geom_mesh *m = NULL;
    geom_diag d;
    assert_int_equal(mt_read(b.b, b.n, GEOM_MESHIO_FORMAT_PLY, 0, &m, NULL, &d, NULL),
                     GEOM_ERR_PARSE);
    assert_non_null(strstr(d.message, "list length"));
    assert_int_equal(d.byte_offset, hl + 36); /* the count itself */
    /* fix the count: fine */
    b.b[hl + 36] = 3;
    assert_int_equal(mt_read(b.b, b.n, GEOM_MESHIO_FORMAT_PLY, 0, &m, NULL, &d, NULL), GEOM_OK);
    geom_mesh_destroy(m);
    /* a negative int index */
    int32_t neg = -1;
    memcpy(b.b + hl + 37 + 4, &neg, 4);
    assert_int_equal(mt_read(b.b, b.n, GEOM_MESHIO_FORMAT_PLY, 0, &m, NULL, &d, NULL),
                     GEOM_ERR_PARSE);
    assert_int_equal(d.byte_offset, hl + 37 + 4); /* the bad index */
    /* an index past the vertices: the face's offset */
    int32_t big = 3;
    memcpy(b.b + hl + 37 + 4, &big, 4);
    assert_int_equal(mt_read(b.b, b.n, GEOM_MESHIO_FORMAT_PLY, 0, &m, NULL, &d, NULL),
                     GEOM_ERR_PARSE);
    assert_int_equal(d.byte_offset, hl + 36);
    assert_non_null(strstr(d.message, "out of range"));
    /* a NaN coordinate */
    uint32_t nan_bits = 0x7fc00000u;
    memcpy(b.b + hl + 4, &nan_bits, 4);
    assert_int_equal(mt_read(b.b, b.n, GEOM_MESHIO_FORMAT_PLY, 0, &m, NULL, &d, NULL),
                     GEOM_ERR_PARSE);
    assert_int_equal(d.byte_offset, hl + 4); /* the NaN itself */
    /* a header count the data cannot hold */
    const char *absurd = "ply\nformat binary_little_endian 1.0\nelement vertex 200000000\n"
                         "property double x\nproperty double y\nproperty double z\nend_header\n";
    assert_int_equal(mt_read(absurd, (size_t)-1, GEOM_MESHIO_FORMAT_PLY, 0, &m, NULL, &d, NULL),
                     GEOM_ERR_PARSE);
    assert_non_null(strstr(d.message, "4800000000 bytes"));
    /* an element with no properties and a huge count reads nothing */
    const char *empty = "ply\nformat binary_little_endian 1.0\nelement nothing 268435456\n"
                        "end_header\n";
    assert_int_equal(mt_read(empty, (size_t)-1, GEOM_MESHIO_FORMAT_PLY, 0, &m, NULL, &d, NULL),
                     GEOM_OK);
    assert_int_equal(geom_mesh_n_vertices(m), 0);
    geom_mesh_destroy(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pyramid_file), cmocka_unit_test(test_endianness),
        cmocka_unit_test(test_ascii_types),  cmocka_unit_test(test_exact_binary),
        cmocka_unit_test(test_malformed),    cmocka_unit_test(test_binary_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
