/*
 * glTF 2.0 binary writer (geom/meshio.h), validated structurally: the GLB
 * header (magic, version 2, total length), the JSON chunk (type, 4-byte
 * padded with spaces, a strict JSON parse by the small parser below),
 * the BIN chunk (type, padded with zeros), asset.version "2.0", accessors
 * within their 4-byte-aligned bufferViews within the buffer, POSITION
 * min/max equal to the data, and the data itself: the cube with UV seams
 * unwelds to 24 vertices whose positions, normals and flipped uvs are those
 * of the OBJ corners, every triangle facing along its corners' normal;
 * 16-bit indices for small meshes and 32-bit ones past 65535 vertices;
 * tangents with w = +-1; an empty mesh; polygons triangulated. The Z-up
 * round trip: written with gltf_z_up and read with it, the cube comes back
 * in its own frame exactly (positions, normals and tangents are the Y-up
 * read's rotated by (x, y, z) -> (x, -z, y), the same corners, normals
 * still along their faces); read without it, the Y-up frame.
 */
#define _XOPEN_SOURCE 700

#include "meshio_testutil.h"

#include <math.h>
#include <unistd.h>

/* ------------------------------------------------- a tiny strict JSON DOM */

typedef enum { J_NULL, J_BOOL, J_NUM, J_STR, J_ARR, J_OBJ } jtype;

typedef struct jval {
    jtype type;
    double num;
    char *str;          /* J_STR; key for object members */
    struct jval *items; /* J_ARR / J_OBJ: n children */
    size_t n;
    char **keys; /* J_OBJ */
} jval;

typedef struct jparser {
    const char *s;
    size_t len, pos;
    int err;
} jparser;

static void jws(jparser *p)
{
    while (p->pos < p->len && strchr(" \t\r\n", p->s[p->pos]))
        p->pos++;
}

static char *jstring(jparser *p)
{
    if (p->pos >= p->len || p->s[p->pos] != '"') {
        p->err = 1;
        return NULL;
    }
    p->pos++;
    size_t b = p->pos;
    while (p->pos < p->len && p->s[p->pos] != '"') {
        if ((unsigned char)p->s[p->pos] < 0x20 || p->s[p->pos] == '\\') {
            p->err = 1; /* the writer never needs escapes */
            return NULL;
        }
        p->pos++;
    }
    if (p->pos >= p->len) {
        p->err = 1;
        return NULL;
    }
    char *out = malloc(p->pos - b + 1);
    memcpy(out, p->s + b, p->pos - b);
    out[p->pos - b] = 0;
    p->pos++;
    return out;
}

static void jparse(jparser *p, jval *v, int depth)
{
    memset(v, 0, sizeof *v);
    jws(p);
    if (p->err || p->pos >= p->len || depth > 64) {
        p->err = 1;
        return;
    }
    char ch = p->s[p->pos];
    if (ch == '{' || ch == '[') {
        int obj = ch == '{';
        v->type = obj ? J_OBJ : J_ARR;
        p->pos++;
        jws(p);
        if (p->pos < p->len && p->s[p->pos] == (obj ? '}' : ']')) {
            p->pos++;
            return;
        }
        for (;;) {
            v->items = realloc(v->items, (v->n + 1) * sizeof *v->items);
            if (obj) {
                v->keys = realloc(v->keys, (v->n + 1) * sizeof *v->keys);
                jws(p);
                v->keys[v->n] = jstring(p);
                jws(p);
                if (p->err || p->pos >= p->len || p->s[p->pos] != ':') {
                    p->err = 1;
                    v->n++;
                    v->items[v->n - 1].type = J_NULL;
                    v->items[v->n - 1].n = 0;
                    return;
                }
                p->pos++;
            }
            jparse(p, &v->items[v->n], depth + 1);
            v->n++;
            jws(p);
            if (p->err || p->pos >= p->len) {
                p->err = 1;
                return;
            }
            if (p->s[p->pos] == ',') {
                p->pos++;
                continue;
            }
            if (p->s[p->pos] == (obj ? '}' : ']')) {
                p->pos++;
                return;
            }
            p->err = 1;
            return;
        }
    }
    if (ch == '"') {
        v->type = J_STR;
        v->str = jstring(p);
        return;
    }
    if (!strncmp(p->s + p->pos, "true", 4) || !strncmp(p->s + p->pos, "null", 4)) {
        v->type = ch == 't' ? J_BOOL : J_NULL;
        v->num = 1;
        p->pos += 4;
        return;
    }
    if (!strncmp(p->s + p->pos, "false", 5)) {
        v->type = J_BOOL;
        p->pos += 5;
        return;
    }
    /* number: JSON grammar -?(0|[1-9]d*)(.d+)?([eE][+-]?d+)? */
    size_t b = p->pos;
    if (p->s[p->pos] == '-')
        p->pos++;
    if (p->pos < p->len && p->s[p->pos] == '0')
        p->pos++;
    else if (p->pos < p->len && p->s[p->pos] >= '1' && p->s[p->pos] <= '9')
        while (p->pos < p->len && p->s[p->pos] >= '0' && p->s[p->pos] <= '9')
            p->pos++;
    else {
        p->err = 1;
        return;
    }
    if (p->pos < p->len && p->s[p->pos] == '.') {
        p->pos++;
        if (p->pos >= p->len || p->s[p->pos] < '0' || p->s[p->pos] > '9') {
            p->err = 1;
            return;
        }
        while (p->pos < p->len && p->s[p->pos] >= '0' && p->s[p->pos] <= '9')
            p->pos++;
    }
    if (p->pos < p->len && (p->s[p->pos] == 'e' || p->s[p->pos] == 'E')) {
        p->pos++;
        if (p->pos < p->len && (p->s[p->pos] == '+' || p->s[p->pos] == '-'))
            p->pos++;
        if (p->pos >= p->len || p->s[p->pos] < '0' || p->s[p->pos] > '9') {
            p->err = 1;
            return;
        }
        while (p->pos < p->len && p->s[p->pos] >= '0' && p->s[p->pos] <= '9')
            p->pos++;
    }
    char buf[64];
    size_t n = p->pos - b < 63 ? p->pos - b : 63;
    memcpy(buf, p->s + b, n);
    buf[n] = 0;
    v->type = J_NUM;
    v->num = strtod(buf, NULL);
}

static void jfree(jval *v)
{
    for (size_t i = 0; i < v->n; i++) {
        jfree(&v->items[i]);
        if (v->keys)
            free(v->keys[i]);
    }
    free(v->items);
    free(v->keys);
    free(v->str);
}

static const jval *jget(const jval *o, const char *key)
{
    if (!o || o->type != J_OBJ)
        return NULL;
    for (size_t i = 0; i < o->n; i++)
        if (o->keys[i] && strcmp(o->keys[i], key) == 0)
            return &o->items[i];
    return NULL;
}

static const jval *jat(const jval *a, size_t i)
{
    return a && a->type == J_ARR && i < a->n ? &a->items[i] : NULL;
}

static double jnum(const jval *v)
{
    assert_non_null(v);
    assert_int_equal(v->type, J_NUM);
    return v->num;
}

/* --------------------------------------------------------------- the GLB */

typedef struct glb {
    jval json;
    const unsigned char *bin;
    size_t bin_len;
} glb;

static uint32_t rd32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

/* Check the container and parse it; g->bin points into data. */
static void parse_glb(const unsigned char *data, size_t size, glb *g)
{
    memset(g, 0, sizeof *g);
    assert_true(size >= 20);
    assert_int_equal(rd32(data), 0x46546C67u); /* "glTF" */
    assert_int_equal(rd32(data + 4), 2);
    assert_int_equal(rd32(data + 8), size);
    assert_int_equal(size % 4, 0);
    uint32_t jl = rd32(data + 12);
    assert_int_equal(rd32(data + 16), 0x4E4F534Au); /* JSON */
    assert_int_equal(jl % 4, 0);
    assert_true(20 + (size_t)jl <= size);
    const char *js = (const char *)data + 20;
    /* padding: trailing spaces only */
    size_t end = jl;
    while (end > 0 && js[end - 1] == ' ')
        end--;
    assert_true(jl - end < 4);
    jparser p = {js, end, 0, 0};
    jparse(&p, &g->json, 0);
    jws(&p);
    assert_false(p.err);
    assert_int_equal(p.pos, end); /* nothing after the value */
    size_t off = 20 + jl;
    if (off < size) {
        uint32_t bl = rd32(data + off);
        assert_int_equal(rd32(data + off + 4), 0x004E4942u); /* BIN */
        assert_int_equal(bl % 4, 0);
        assert_int_equal(off + 8 + bl, size);
        g->bin = data + off + 8;
        g->bin_len = bl;
    }
    const jval *asset = jget(&g->json, "asset");
    assert_non_null(asset);
    const jval *ver = jget(asset, "version");
    assert_non_null(ver);
    assert_string_equal(ver->str, "2.0");
    if (g->bin) {
        const jval *buf = jat(jget(&g->json, "buffers"), 0);
        assert_true(jnum(jget(buf, "byteLength")) <= (double)g->bin_len);
        assert_true(jnum(jget(buf, "byteLength")) + 3 >= (double)g->bin_len);
    }
}

typedef struct view {
    const unsigned char *p;
    size_t count, ncomp;
    unsigned ctype;
} view;

static size_t type_ncomp(const char *t)
{
    if (!strcmp(t, "SCALAR"))
        return 1;
    if (!strcmp(t, "VEC2"))
        return 2;
    if (!strcmp(t, "VEC3"))
        return 3;
    if (!strcmp(t, "VEC4"))
        return 4;
    fail();
    return 0;
}

/* Accessor i, checked to lie in its aligned bufferView inside the buffer. */
static view accessor(const glb *g, size_t i)
{
    const jval *a = jat(jget(&g->json, "accessors"), i);
    assert_non_null(a);
    const jval *bv = jat(jget(&g->json, "bufferViews"), (size_t)jnum(jget(a, "bufferView")));
    assert_non_null(bv);
    assert_true(jnum(jget(bv, "buffer")) == 0);
    size_t off = (size_t)jnum(jget(bv, "byteOffset")), len = (size_t)jnum(jget(bv, "byteLength"));
    assert_int_equal(off % 4, 0);
    assert_true(off + len <= g->bin_len);
    view v;
    v.ctype = (unsigned)jnum(jget(a, "componentType"));
    v.count = (size_t)jnum(jget(a, "count"));
    v.ncomp = type_ncomp(jget(a, "type")->str);
    size_t csize = v.ctype == 5126 || v.ctype == 5125 ? 4 : v.ctype == 5123 ? 2 : 0;
    assert_true(csize > 0);
    assert_true(v.count * v.ncomp * csize <= len);
    v.p = g->bin + off;
    return v;
}

static float fget(const view *v, size_t i, size_t c)
{
    float f;
    memcpy(&f, v->p + 4 * (i * v->ncomp + c), 4);
    return f;
}

static uint32_t iget(const view *v, size_t i)
{
    if (v->ctype == 5123)
        return (uint32_t)v->p[2 * i] | (uint32_t)v->p[2 * i + 1] << 8;
    return rd32(v->p + 4 * i);
}

static const jval *attributes(const glb *g)
{
    const jval *prim = jat(jget(jat(jget(&g->json, "meshes"), 0), "primitives"), 0);
    assert_non_null(prim);
    return prim;
}

/* ------------------------------------------------------------------ tests */

static geom_mesh *read_cube(void)
{
    char path[1024];
    geom_mesh *m = NULL;
    assert_int_equal(
        geom_meshio_read(mt_path(path, sizeof path, 0, "cube_seams.obj"), NULL, &m, NULL, NULL),
        GEOM_OK);
    return m;
}

static void test_cube_glb(void **state)
{
    (void)state;
    geom_mesh *m = read_cube();
    size_t size;
    unsigned char *data = mt_write(m, GEOM_MESHIO_FORMAT_GLB, 0, &size);
    glb g;
    parse_glb(data, size, &g);
    const jval *prim = attributes(&g);
    const jval *attr = jget(prim, "attributes");
    assert_true(jnum(jget(prim, "mode")) == 4);
    view pos = accessor(&g, (size_t)jnum(jget(attr, "POSITION")));
    view nrm = accessor(&g, (size_t)jnum(jget(attr, "NORMAL")));
    view uv = accessor(&g, (size_t)jnum(jget(attr, "TEXCOORD_0")));
    view idx = accessor(&g, (size_t)jnum(jget(prim, "indices")));
    assert_null(jget(attr, "TANGENT"));
    /* one vertex per distinct (vertex, uv, normal) corner: the cube's 24 */
    assert_int_equal(pos.count, 24);
    assert_int_equal(nrm.count, 24);
    assert_int_equal(uv.count, 24);
    assert_int_equal(pos.ctype, 5126);
    assert_int_equal(idx.ctype, 5123); /* small: unsigned short */
    assert_int_equal(idx.count, 36);
    /* POSITION min/max, as the spec requires, equal to the data */
    const jval *acc = jat(jget(&g.json, "accessors"), (size_t)jnum(jget(attr, "POSITION")));
    for (int c = 0; c < 3; c++) {
        float mn = INFINITY, mx = -INFINITY;
        for (size_t i = 0; i < pos.count; i++) {
            float f = fget(&pos, i, c);
            mn = f < mn ? f : mn;
            mx = f > mx ? f : mx;
        }
        assert_true(jnum(jat(jget(acc, "min"), (size_t)c)) == mn);
        assert_true(jnum(jat(jget(acc, "max"), (size_t)c)) == mx);
        assert_true(mn == 0.0f && mx == 1.0f);
    }
    /* every triangle faces along its corners' normal, which is a unit axis;
     * every (position, normal, uv) triple is one of the OBJ's corners with v
     * flipped */
    uint32_t uvc = geom_mesh_channel_find(m, "uv", GEOM_MESH_DOMAIN_CORNER);
    uint32_t nmc = geom_mesh_channel_find(m, "normal", GEOM_MESH_DOMAIN_CORNER);
    for (size_t t = 0; t < 12; t++) {
        uint32_t a = iget(&idx, 3 * t), b = iget(&idx, 3 * t + 1), c = iget(&idx, 3 * t + 2);
        assert_true(a < 24 && b < 24 && c < 24);
        float e1[3], e2[3], n[3];
        for (int k = 0; k < 3; k++) {
            e1[k] = fget(&pos, b, k) - fget(&pos, a, k);
            e2[k] = fget(&pos, c, k) - fget(&pos, a, k);
            n[k] = fget(&nrm, a, k);
            assert_true(fget(&nrm, b, k) == n[k] && fget(&nrm, c, k) == n[k]);
        }
        float cr[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                       e1[0] * e2[1] - e1[1] * e2[0]};
        assert_true(cr[0] * n[0] + cr[1] * n[1] + cr[2] * n[2] > 0.5f);
    }
    for (size_t i = 0; i < 24; i++) {
        int found = 0;
        for (uint32_t f = 0; f < 6 && !found; f++) {
            uint32_t h0 = geom_mesh_face_he(m, f), h = h0;
            do {
                const double *p = geom_mesh_cpositions(m) + 3 * geom_mesh_he_vertex(m, h);
                const double *u = geom_mesh_channel_cdata(m, uvc) +
                                  2 * geom_mesh_corner_cindices(m, uvc)[h];
                const double *nn = geom_mesh_channel_cdata(m, nmc) +
                                   3 * geom_mesh_corner_cindices(m, nmc)[h];
                if (fget(&pos, i, 0) == p[0] && fget(&pos, i, 1) == p[1] &&
                    fget(&pos, i, 2) == p[2] && fget(&nrm, i, 0) == nn[0] &&
                    fget(&nrm, i, 1) == nn[1] && fget(&nrm, i, 2) == nn[2] &&
                    fget(&uv, i, 0) == (float)u[0] && fget(&uv, i, 1) == (float)(1.0 - u[1]))
                    found = 1;
                h = geom_mesh_he_next(m, h);
            } while (h != h0);
        }
        assert_true(found);
    }
    jfree(&g.json);
    free(data);

    /* keep v: the uvs are the OBJ's */
    geom_meshio_write_options w;
    memset(&w, 0, sizeof w);
    w.format = GEOM_MESHIO_FORMAT_GLB;
    w.gltf_keep_v = 1;
    w.omit = GEOM_MESHIO_ATTR_NORMAL;
    geom_diag d;
    assert_int_equal(geom_meshio_write_memory(m, &w, (void **)&data, &size, &d), GEOM_OK);
    parse_glb(data, size, &g);
    attr = jget(attributes(&g), "attributes");
    assert_null(jget(attr, "NORMAL"));
    uv = accessor(&g, (size_t)jnum(jget(attr, "TEXCOORD_0")));
    assert_int_equal(uv.count, 14); /* each vt of the file sits at one vertex */
    for (size_t i = 0; i < uv.count; i++) {
        float v = fget(&uv, i, 1);
        assert_true(v == 0.0f || v == 0.25f || v == 0.5f || v == 0.75f || v == 1.0f);
    }
    jfree(&g.json);
    free(data);
    geom_mesh_destroy(m);
}

static void test_tangents(void **state)
{
    (void)state;
    geom_mesh *m = read_cube();
    uint32_t id;
    assert_int_equal(geom_mesh_tangents(m, &id), GEOM_OK);
    size_t size;
    unsigned char *data = mt_write(m, GEOM_MESHIO_FORMAT_GLB, 0, &size);
    glb g;
    parse_glb(data, size, &g);
    const jval *attr = jget(attributes(&g), "attributes");
    view tan = accessor(&g, (size_t)jnum(jget(attr, "TANGENT")));
    view nrm = accessor(&g, (size_t)jnum(jget(attr, "NORMAL")));
    assert_int_equal(tan.ncomp, 4);
    assert_int_equal(tan.count, nrm.count);
    for (size_t i = 0; i < tan.count; i++) {
        float w = fget(&tan, i, 3);
        assert_true(w == 1.0f || w == -1.0f);
        float dot = 0, len = 0;
        for (int k = 0; k < 3; k++) {
            dot += fget(&tan, i, k) * fget(&nrm, i, k);
            len += fget(&tan, i, k) * fget(&tan, i, k);
        }
        assert_true(fabsf(dot) < 1e-6f);
        assert_true(fabsf(len - 1.0f) < 1e-5f);
    }
    jfree(&g.json);
    free(data);
    geom_mesh_destroy(m);
}

static void test_large_and_empty(void **state)
{
    (void)state;
    /* a 300 x 300 grid of quads: 90000 vertices -> 32-bit indices */
    enum { K = 300 };
    double *xyz = malloc(sizeof(double) * 3 * K * K);
    uint32_t *sizes = malloc(sizeof(uint32_t) * (K - 1) * (K - 1));
    uint32_t *idx = malloc(sizeof(uint32_t) * 4 * (K - 1) * (K - 1));
    for (int j = 0; j < K; j++)
        for (int i = 0; i < K; i++) {
            xyz[3 * (j * K + i)] = i;
            xyz[3 * (j * K + i) + 1] = j;
            xyz[3 * (j * K + i) + 2] = 0.5 * ((i + j) % 3);
        }
    size_t nf = 0;
    for (int j = 0; j + 1 < K; j++)
        for (int i = 0; i + 1 < K; i++) {
            sizes[nf] = 4;
            uint32_t a = (uint32_t)(j * K + i);
            idx[4 * nf] = a;
            idx[4 * nf + 1] = a + 1;
            idx[4 * nf + 2] = a + 1 + K;
            idx[4 * nf + 3] = a + K;
            nf++;
        }
    geom_mesh *m = geom_mesh_create(NULL);
    assert_int_equal(geom_mesh_build(m, K * K, xyz, nf, sizes, idx, NULL, NULL, NULL), GEOM_OK);
    size_t size;
    unsigned char *data = mt_write(m, GEOM_MESHIO_FORMAT_GLB, 0, &size);
    glb g;
    parse_glb(data, size, &g);
    const jval *prim = attributes(&g);
    view pos = accessor(&g, (size_t)jnum(jget(jget(prim, "attributes"), "POSITION")));
    view ix = accessor(&g, (size_t)jnum(jget(prim, "indices")));
    assert_int_equal(pos.count, K * K);
    assert_int_equal(ix.ctype, 5125);
    assert_int_equal(ix.count, 6 * nf); /* quads triangulated */
    double area2 = 0;                   /* projected area of the grid, twice */
    for (size_t t = 0; t < ix.count / 3; t++) {
        uint32_t a = iget(&ix, 3 * t), b = iget(&ix, 3 * t + 1), c = iget(&ix, 3 * t + 2);
        assert_true(a < pos.count && b < pos.count && c < pos.count);
        area2 += (fget(&pos, b, 0) - fget(&pos, a, 0)) * (fget(&pos, c, 1) - fget(&pos, a, 1)) -
                 (fget(&pos, b, 1) - fget(&pos, a, 1)) * (fget(&pos, c, 0) - fget(&pos, a, 0));
    }
    assert_true(area2 == 2.0 * (K - 1) * (K - 1));
    const jval *acc = jat(jget(&g.json, "accessors"), 0);
    assert_true(jnum(jat(jget(acc, "max"), 0)) == K - 1);
    assert_true(jnum(jat(jget(acc, "max"), 2)) == 1.0);
    jfree(&g.json);
    free(data);
    geom_mesh_destroy(m);
    free(xyz);
    free(sizes);
    free(idx);

    /* an empty mesh: a valid file with an empty scene and no BIN chunk */
    m = geom_mesh_create(NULL);
    data = mt_write(m, GEOM_MESHIO_FORMAT_GLB, 0, &size);
    parse_glb(data, size, &g);
    assert_null(g.bin);
    assert_null(jget(&g.json, "meshes"));
    jfree(&g.json);
    free(data);
    geom_mesh_destroy(m);
}

static void test_glb_file(void **state)
{
    (void)state;
    geom_mesh *m = read_cube();
    char path[] = "/tmp/geom-gltf-test-XXXXXX";
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    close(fd);
    geom_meshio_write_options w;
    memset(&w, 0, sizeof w);
    w.format = GEOM_MESHIO_FORMAT_GLB; /* the name has no extension */
    geom_diag d;
    assert_int_equal(geom_meshio_write(m, path, &w, &d), GEOM_OK);
    size_t size;
    unsigned char *data = mt_slurp(path, &size);
    glb g;
    parse_glb(data, size, &g);
    jfree(&g.json);
    free(data);
    unlink(path);
    /* one triangle: 36 bytes of positions and 6 of indices, the BIN chunk
     * padded with two zero bytes */
    {
        const double xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
        const uint32_t fs[1] = {3}, ix[3] = {0, 1, 2};
        geom_mesh *t = geom_mesh_create(NULL);
        assert_int_equal(geom_mesh_build(t, 3, xyz, 1, fs, ix, NULL, NULL, NULL), GEOM_OK);
        unsigned char *tb = mt_write(t, GEOM_MESHIO_FORMAT_GLB, 0, &size);
        parse_glb(tb, size, &g);
        assert_int_equal(g.bin_len, 44);
        assert_int_equal(g.bin[42], 0);
        assert_int_equal(g.bin[43], 0);
        view ix2 = accessor(&g, (size_t)jnum(jget(attributes(&g), "indices")));
        assert_int_equal(ix2.ctype, 5123);
        assert_int_equal(iget(&ix2, 0), 0);
        assert_int_equal(iget(&ix2, 1), 1);
        assert_int_equal(iget(&ix2, 2), 2);
        jfree(&g.json);
        free(tb);
        geom_mesh_destroy(t);
    }
    /* a non-finite coordinate cannot be written: GEOM_ERR_INVALID_ARG */
    geom_mesh_positions(m)[4] = INFINITY;
    void *buf;
    assert_int_equal(geom_meshio_write_memory(m, &w, &buf, &size, &d), GEOM_ERR_INVALID_ARG);
    assert_null(buf);
    geom_mesh_destroy(m);
}

/* (x, y, z) -> (x, -z, y): glTF's Y-up frame back to Z-up */
static void assert_z_up_of(const double *zup, const double *yup, size_t n, size_t stride)
{
    for (size_t i = 0; i < n; i++) {
        const double *a = zup + i * stride, *b = yup + i * stride;
        assert_true(a[0] == b[0] && a[1] == -b[2] && a[2] == b[1]);
        for (size_t k = 3; k < stride; k++)
            assert_true(a[k] == b[k]);
    }
}

static void test_z_up_round_trip(void **state)
{
    (void)state;
    geom_mesh *m = read_cube();
    uint32_t tid;
    assert_int_equal(geom_mesh_tangents(m, &tid), GEOM_OK);
    /* move it off the origin so that a swapped axis shows */
    for (size_t v = 0; v < geom_mesh_n_vertices(m); v++) {
        geom_mesh_positions(m)[3 * v] += 4;
        geom_mesh_positions(m)[3 * v + 1] += 8;
        geom_mesh_positions(m)[3 * v + 2] -= 16;
    }
    geom_meshio_write_options w;
    memset(&w, 0, sizeof w);
    w.format = GEOM_MESHIO_FORMAT_GLB;
    w.gltf_z_up = 1;
    void *buf = NULL;
    size_t size = 0;
    assert_int_equal(geom_meshio_write_memory(m, &w, &buf, &size, NULL), GEOM_OK);
    geom_meshio_read_options r;
    memset(&r, 0, sizeof r);
    geom_mesh *yup = NULL, *zup = NULL;
    assert_int_equal(geom_meshio_read_memory(buf, size, "c.glb", &r, &yup, NULL, NULL), GEOM_OK);
    r.gltf_z_up = 1;
    assert_int_equal(geom_meshio_read_memory(buf, size, "c.glb", &r, &zup, NULL, NULL), GEOM_OK);
    free(buf);
    /* the cube's 8 corners, in its own frame, exactly */
    size_t nv = geom_mesh_n_vertices(zup);
    assert_int_equal(nv, 8);
    assert_int_equal(geom_mesh_n_vertices(yup), 8);
    const double *pz = geom_mesh_cpositions(zup), *p0 = geom_mesh_cpositions(m);
    for (size_t v = 0; v < nv; v++) {
        int found = 0;
        for (size_t u = 0; u < geom_mesh_n_vertices(m); u++)
            found |= memcmp(pz + 3 * v, p0 + 3 * u, 3 * sizeof(double)) == 0;
        assert_true(found);
    }
    assert_z_up_of(pz, geom_mesh_cpositions(yup), nv, 3);
    static const char *const names[] = {"normal", "tangent", "uv"};
    for (int c = 0; c < 3; c++) {
        uint32_t a = geom_mesh_channel_find(zup, names[c], GEOM_MESH_DOMAIN_CORNER);
        uint32_t b = geom_mesh_channel_find(yup, names[c], GEOM_MESH_DOMAIN_CORNER);
        assert_true(a != GEOM_INVALID_INDEX && b != GEOM_INVALID_INDEX);
        size_t n = geom_mesh_channel_size(zup, a), nc = geom_mesh_channel_ncomp(zup, a);
        assert_int_equal(n, geom_mesh_channel_size(yup, b));
        if (c < 2) {
            assert_z_up_of(geom_mesh_channel_cdata(zup, a), geom_mesh_channel_cdata(yup, b), n, nc);
        } else {
            assert_memory_equal(geom_mesh_channel_cdata(zup, a), geom_mesh_channel_cdata(yup, b),
                                n * nc * sizeof(double));
        }
        assert_memory_equal(geom_mesh_corner_cindices(zup, a), geom_mesh_corner_cindices(yup, b),
                            geom_mesh_n_halfedges(zup) * sizeof(uint32_t));
    }
    /* normals along their faces' normals in the Z-up frame */
    uint32_t na = geom_mesh_channel_find(zup, "normal", GEOM_MESH_DOMAIN_CORNER);
    const uint32_t *ci = geom_mesh_corner_cindices(zup, na);
    const double *nv3 = geom_mesh_channel_cdata(zup, na);
    for (uint32_t f = 0; f < geom_mesh_n_faces(zup); f++) {
        double fn[3];
        assert_int_equal(geom_mesh_face_normal(zup, f, fn), GEOM_OK);
        const double *n = nv3 + 3 * ci[geom_mesh_face_he(zup, f)];
        assert_true(fn[0] * n[0] + fn[1] * n[1] + fn[2] * n[2] > 0.99);
    }
    geom_mesh_destroy(yup);
    geom_mesh_destroy(zup);
    geom_mesh_destroy(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cube_glb),
        cmocka_unit_test(test_tangents),
        cmocka_unit_test(test_large_and_empty),
        cmocka_unit_test(test_glb_file),
        cmocka_unit_test(test_z_up_round_trip),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
