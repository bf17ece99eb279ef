/* geom_mesh_build with attribute streams and the trusted flag. The trusted
 * build must give, element for element, what the repairing build gives
 * (the repairing build is the reference: it is the general path, tested on
 * its own in test_mesh_build.c): on clean meshes (grids of triangles and
 * quads, closed tori, polygons, isolated vertices) and on input that needs
 * repair (flipped faces, bow-ties, edges with three faces, invalid faces),
 * where the trusted build must fall back. Streams: vertex, face and corner
 * values follow their input element through flips, splits and skipped
 * faces; invalid streams are rejected. */
#include "unit/test_util.h"

#include "geom/mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define INV GEOM_INVALID_INDEX

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
    memset(s, 0, sizeof *s);
}

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static uint32_t rnd(uint32_t n)
{
    return (uint32_t)(test_xorshift64(&rng_state) % n);
}

/* nu x nv grid (closed into a torus when `closed`), quads or triangles,
 * faces in random order with random starting corners; `drop` faces left
 * out at random (bow-ties and holes), `extra` isolated vertices. */
static soup grid(uint32_t nu, uint32_t nv, int tris, int closed, uint32_t drop, uint32_t extra)
{
    soup s;
    uint32_t cu = closed ? nu : nu + 1, cv = closed ? nv : nv + 1;
    s.nv = (size_t)cu * cv + extra;
    s.xyz = malloc(3 * s.nv * sizeof(double));
    for (size_t i = 0; i < s.nv; i++) {
        s.xyz[3 * i] = (double)(i % cu) + 0.1 * rnd(7);
        s.xyz[3 * i + 1] = (double)(i / cu) + 0.1 * rnd(5);
        s.xyz[3 * i + 2] = 0.01 * rnd(100);
    }
    size_t nq = (size_t)nu * nv, maxf = tris ? 2 * nq : nq;
    uint32_t *fv = malloc(4 * maxf * sizeof(uint32_t));
    uint32_t *fn = malloc(maxf * sizeof(uint32_t));
    size_t nf = 0;
    for (uint32_t j = 0; j < nv; j++)
        for (uint32_t i = 0; i < nu; i++) {
            uint32_t a = j * cu + i, b = j * cu + (i + 1) % cu, c = ((j + 1) % cv) * cu + (i + 1) % cu,
                     d = ((j + 1) % cv) * cu + i;
            if (tris) {
                uint32_t t[6] = {a, b, c, a, c, d};
                memcpy(fv + 4 * nf, t, 3 * sizeof(uint32_t));
                fn[nf++] = 3;
                memcpy(fv + 4 * nf, t + 3, 3 * sizeof(uint32_t));
                fn[nf++] = 3;
            } else {
                uint32_t q[4] = {a, b, c, d};
                memcpy(fv + 4 * nf, q, sizeof q);
                fn[nf++] = 4;
            }
        }
    for (uint32_t k = 0; k < drop && nf > 1; k++) {
        size_t f = rnd((uint32_t)nf);
        memmove(fv + 4 * f, fv + 4 * (f + 1), 4 * (nf - f - 1) * sizeof(uint32_t));
        memmove(fn + f, fn + f + 1, (nf - f - 1) * sizeof(uint32_t));
        nf--;
    }
    for (size_t f = nf; f > 1; f--) { /* shuffle */
        size_t g = rnd((uint32_t)f);
        uint32_t t[4], tn = fn[f - 1];
        memcpy(t, fv + 4 * (f - 1), sizeof t);
        memcpy(fv + 4 * (f - 1), fv + 4 * g, sizeof t);
        memcpy(fv + 4 * g, t, sizeof t);
        fn[f - 1] = fn[g];
        fn[g] = tn;
    }
    s.nf = nf;
    s.sizes = malloc((nf ? nf : 1) * sizeof(uint32_t));
    s.idx = malloc((4 * nf + 1) * sizeof(uint32_t));
    s.ni = 0;
    for (size_t f = 0; f < nf; f++) {
        uint32_t n = fn[f], r = rnd(n);
        s.sizes[f] = n;
        for (uint32_t k = 0; k < n; k++)
            s.idx[s.ni++] = fv[4 * f + (k + r) % n];
    }
    free(fv);
    free(fn);
    return s;
}

/* Every array the public API shows, compared element by element. */
static void assert_same_mesh(const geom_mesh *a, const geom_mesh *b)
{
    assert_same_connectivity(a, b);
    const uint32_t *va = geom_mesh_vertex_origin(a), *vb = geom_mesh_vertex_origin(b);
    const uint32_t *fa = geom_mesh_face_origin(a), *fb = geom_mesh_face_origin(b);
    assert_non_null(va);
    assert_non_null(vb);
    assert_non_null(fa);
    assert_non_null(fb);
    assert_memory_equal(va, vb, geom_mesh_n_vertices(a) * sizeof(uint32_t));
    if (geom_mesh_n_faces(a))
        assert_memory_equal(fa, fb, geom_mesh_n_faces(a) * sizeof(uint32_t));
    assert_int_equal(geom_mesh_channel_count(a), geom_mesh_channel_count(b));
    for (uint32_t c = 0; c < geom_mesh_channel_count(a); c++) {
        assert_string_equal(geom_mesh_channel_name(a, c), geom_mesh_channel_name(b, c));
        assert_int_equal(geom_mesh_channel_domain(a, c), geom_mesh_channel_domain(b, c));
        size_t n = geom_mesh_channel_size(a, c), nc = geom_mesh_channel_ncomp(a, c);
        assert_int_equal(n, geom_mesh_channel_size(b, c));
        if (n)
            assert_memory_equal(geom_mesh_channel_cdata(a, c), geom_mesh_channel_cdata(b, c),
                                n * nc * sizeof(double));
        if (geom_mesh_channel_domain(a, c) == GEOM_MESH_DOMAIN_CORNER &&
            geom_mesh_n_halfedges(a))
            assert_memory_equal(geom_mesh_corner_cindices(a, c), geom_mesh_corner_cindices(b, c),
                                geom_mesh_n_halfedges(a) * sizeof(uint32_t));
    }
}

static void assert_valid(const geom_mesh *m)
{
    size_t n = 99;
    assert_int_equal(geom_mesh_validate(m, NULL, 0, &n), GEOM_OK);
    assert_int_equal(n, 0);
}

/* Streams for a soup: a vertex channel (the vertex index), a face channel
 * (the face index) and a corner channel whose pool holds one value per
 * corner (the corner's input vertex and face), with every seventh corner
 * left without a value. */
typedef struct streams {
    double *vval, *fval, *cval;
    uint32_t *cidx;
    geom_mesh_build_channel ch[3];
} streams;

static void make_streams(streams *t, const soup *s)
{
    t->vval = malloc((s->nv + 1) * 2 * sizeof(double));
    t->fval = malloc((s->nf + 1) * sizeof(double));
    t->cval = malloc((s->ni + 1) * 2 * sizeof(double));
    t->cidx = malloc((s->ni + 1) * sizeof(uint32_t));
    for (size_t v = 0; v < s->nv; v++) {
        t->vval[2 * v] = (double)v;
        t->vval[2 * v + 1] = -(double)v;
    }
    size_t c = 0;
    for (size_t f = 0; f < s->nf; f++) {
        t->fval[f] = (double)f + 0.5;
        for (uint32_t k = 0; k < s->sizes[f]; k++, c++) {
            t->cval[2 * c] = (double)s->idx[c];
            t->cval[2 * c + 1] = (double)f;
            t->cidx[c] = c % 7 == 3 ? INV : (uint32_t)c;
        }
    }
    geom_mesh_build_channel v = {"vid", GEOM_MESH_DOMAIN_VERTEX, 2, 0, t->vval, NULL};
    geom_mesh_build_channel f = {"fid", GEOM_MESH_DOMAIN_FACE, 1, 0, t->fval, NULL};
    geom_mesh_build_channel k = {"uv", GEOM_MESH_DOMAIN_CORNER, 2, s->ni, t->cval, t->cidx};
    t->ch[0] = v;
    t->ch[1] = f;
    t->ch[2] = k;
}

static void free_streams(streams *t)
{
    free(t->vval);
    free(t->fval);
    free(t->cval);
    free(t->cidx);
}

/* Each stream value sits where its input element went. */
static void assert_streams_follow(const geom_mesh *m, const soup *s)
{
    uint32_t vid = geom_mesh_channel_find(m, "vid", GEOM_MESH_DOMAIN_VERTEX);
    uint32_t fid = geom_mesh_channel_find(m, "fid", GEOM_MESH_DOMAIN_FACE);
    uint32_t uv = geom_mesh_channel_find(m, "uv", GEOM_MESH_DOMAIN_CORNER);
    assert_int_not_equal(vid, INV);
    assert_int_not_equal(fid, INV);
    assert_int_not_equal(uv, INV);
    const uint32_t *vo = geom_mesh_vertex_origin(m), *fo = geom_mesh_face_origin(m);
    const double *vd = geom_mesh_channel_cdata(m, vid), *fd = geom_mesh_channel_cdata(m, fid);
    const double *cd = geom_mesh_channel_cdata(m, uv);
    const uint32_t *ci = geom_mesh_corner_cindices(m, uv);
    for (uint32_t v = 0; v < geom_mesh_n_vertices(m); v++) {
        assert_true(vd[2 * v] == (double)vo[v]);
        assert_true(vd[2 * v + 1] == -(double)vo[v]);
    }
    for (uint32_t f = 0; f < geom_mesh_n_faces(m); f++) {
        assert_true(fd[f] == (double)fo[f] + 0.5);
        uint32_t h0 = geom_mesh_face_he(m, f), h = h0;
        do {
            uint32_t c = ci[h];
            if (c != INV) {
                /* the corner at vertex(h) of f: same input vertex and face */
                assert_true(cd[2 * c] == (double)vo[geom_mesh_he_vertex(m, h)]);
                assert_true(cd[2 * c + 1] == (double)fo[f]);
                assert_int_not_equal(c % 7, 3);
            }
            h = geom_mesh_he_next(m, h);
        } while (h != h0);
    }
    assert_int_equal(geom_mesh_channel_size(m, uv), s->ni);
}

/* Build s twice (trusted and repairing, same options otherwise), with the
 * streams, compare; returns whether the repairing build changed anything. */
static int check_soup(const soup *s, int keep, int skip)
{
    streams t;
    make_streams(&t, s);
    geom_mesh_build_options o;
    memset(&o, 0, sizeof o);
    o.keep_orientation = keep;
    o.skip_invalid_faces = skip;
    o.channels = t.ch;
    o.n_channels = 3;
    geom_mesh *a = geom_mesh_create(NULL), *b = geom_mesh_create(NULL);
    geom_mesh_build_report ra, rb;
    geom_status sa = geom_mesh_build(a, s->nv, s->xyz, s->nf, s->sizes, s->idx, &o, &ra, NULL);
    o.trusted = 1;
    geom_status sb = geom_mesh_build(b, s->nv, s->xyz, s->nf, s->sizes, s->idx, &o, &rb, NULL);
    assert_int_equal(sa, sb);
    int changed = 0;
    if (sa == GEOM_OK) {
        assert_same_mesh(a, b);
        assert_memory_equal(&ra, &rb, sizeof ra);
        assert_valid(b);
        assert_streams_follow(b, s);
        changed = ra.invalid_faces || ra.flipped_faces || ra.nonmanifold_edges ||
                  ra.split_vertices || ra.detached_faces;
    }
    geom_mesh_destroy(a);
    geom_mesh_destroy(b);
    free_streams(&t);
    return changed;
}

static void test_clean_grids(void **state)
{
    (void)state;
    for (int tris = 0; tris < 2; tris++)
        for (int closed = 0; closed < 2; closed++) {
            soup s = grid(13, 9, tris, closed, 0, 3);
            assert_false(check_soup(&s, 1, 0));
            assert_false(check_soup(&s, 0, 0));
            soup_free(&s);
        }
    soup e = grid(1, 1, 0, 0, 0, 0);
    e.nf = 0; /* no faces: every vertex isolated */
    assert_false(check_soup(&e, 1, 0));
    soup_free(&e);
}

/* Grids with faces left out: bow-tie vertices that the trusted build must
 * hand to the repairing one. */
static void test_holes_fall_back(void **state)
{
    (void)state;
    int changed = 0;
    for (int i = 0; i < 40; i++) {
        soup s = grid(4 + rnd(6), 3 + rnd(6), (int)rnd(2), (int)rnd(2), 1 + rnd(12), rnd(3));
        changed += check_soup(&s, 1, 0);
        soup_free(&s);
    }
    assert_true(changed > 0);
}

/* Flipped faces, triple edges, duplicated and invalid faces. */
static void test_dirty_fall_back(void **state)
{
    (void)state;
    int changed = 0;
    for (int i = 0; i < 60; i++) {
        soup s = grid(3 + rnd(5), 3 + rnd(5), (int)rnd(2), (int)rnd(2), 0, 0);
        int kind = i % 4;
        if (kind == 0) { /* flip one face */
            size_t f = rnd((uint32_t)s.nf), off = 0;
            for (size_t g = 0; g < f; g++)
                off += s.sizes[g];
            uint32_t n = s.sizes[f];
            for (uint32_t k = 0; k < n / 2; k++) {
                uint32_t t = s.idx[off + k];
                s.idx[off + k] = s.idx[off + n - 1 - k];
                s.idx[off + n - 1 - k] = t;
            }
        } else if (kind == 1 || kind == 2) { /* duplicate a face (reversed for kind 2) */
            uint32_t n = s.sizes[0];
            s.sizes = realloc(s.sizes, (s.nf + 1) * sizeof(uint32_t));
            s.idx = realloc(s.idx, (s.ni + n) * sizeof(uint32_t));
            for (uint32_t k = 0; k < n; k++)
                s.idx[s.ni + k] = kind == 1 ? s.idx[k] : s.idx[n - 1 - k];
            s.sizes[s.nf++] = n;
            s.ni += n;
        } else { /* a repeated vertex in a face */
            s.idx[1] = s.idx[0];
        }
        changed += check_soup(&s, (int)rnd(2), 1);
        if (kind == 3) { /* without skipping: the same error either way */
            geom_mesh_build_options o;
            memset(&o, 0, sizeof o);
            o.trusted = 1;
            geom_mesh *m = geom_mesh_create(NULL);
            assert_int_equal(geom_mesh_build(m, s.nv, s.xyz, s.nf, s.sizes, s.idx, &o, NULL, NULL),
                             GEOM_ERR_INVALID_ARG);
            geom_mesh_destroy(m);
        }
        soup_free(&s);
    }
    assert_true(changed > 0);
}

/* Three triangles on one edge and an index out of range. */
static void test_nonmanifold_edge_and_range(void **state)
{
    (void)state;
    double xyz[15] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1};
    uint32_t sizes[3] = {3, 3, 3}, idx[9] = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    soup s = {5, 3, 9, xyz, sizes, idx};
    assert_true(check_soup(&s, 1, 0));
    idx[8] = 5;
    geom_mesh_build_options o;
    memset(&o, 0, sizeof o);
    o.trusted = 1;
    geom_mesh *m = geom_mesh_create(NULL);
    assert_int_equal(geom_mesh_build(m, 5, xyz, 3, sizes, idx, &o, NULL, NULL),
                     GEOM_ERR_INVALID_ARG);
    o.skip_invalid_faces = 1;
    geom_mesh_build_report r;
    assert_int_equal(geom_mesh_build(m, 5, xyz, 3, sizes, idx, &o, &r, NULL), GEOM_OK);
    assert_int_equal(r.invalid_faces, 1);
    assert_int_equal(geom_mesh_n_faces(m), 2);
    geom_mesh_destroy(m);
}

static void test_bad_streams(void **state)
{
    (void)state;
    double xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0}, val[6] = {0};
    uint32_t sizes[1] = {3}, idx[3] = {0, 1, 2}, ci[3] = {0, 1, 2}, bad[3] = {0, 1, 3};
    geom_mesh_build_channel ok = {"uv", GEOM_MESH_DOMAIN_CORNER, 2, 3, val, ci};
    geom_mesh_build_channel cases[7] = {
        {"uv", GEOM_MESH_DOMAIN_CORNER, 2, 3, val, bad},      /* index past the pool */
        {"uv", GEOM_MESH_DOMAIN_CORNER, 2, 3, val, NULL},     /* no indices */
        {"uv", GEOM_MESH_DOMAIN_EDGE, 1, 0, val, NULL},       /* edge domain */
        {"position", GEOM_MESH_DOMAIN_VERTEX, 3, 0, val, NULL},
        {"uv", GEOM_MESH_DOMAIN_CORNER, 0, 3, val, ci},       /* ncomp 0 */
        {"", GEOM_MESH_DOMAIN_FACE, 1, 0, val, NULL},         /* empty name */
        {"uv", GEOM_MESH_DOMAIN_CORNER, 2, 3, NULL, ci},      /* no values */
    };
    geom_mesh *m = geom_mesh_create(NULL);
    for (int i = 0; i < 7; i++)
        for (int tr = 0; tr < 2; tr++) {
            geom_mesh_build_options o;
            memset(&o, 0, sizeof o);
            o.trusted = tr;
            o.channels = &cases[i];
            o.n_channels = 1;
            assert_int_equal(geom_mesh_build(m, 3, xyz, 1, sizes, idx, &o, NULL, NULL),
                             GEOM_ERR_INVALID_ARG);
        }
    geom_mesh_build_channel two[2] = {ok, ok}; /* a repeated name */
    geom_mesh_build_options o;
    memset(&o, 0, sizeof o);
    o.channels = two;
    o.n_channels = 2;
    assert_int_equal(geom_mesh_build(m, 3, xyz, 1, sizes, idx, &o, NULL, NULL),
                     GEOM_ERR_INVALID_ARG);
    o.n_channels = 1;
    o.trusted = 1;
    assert_int_equal(geom_mesh_build(m, 3, xyz, 1, sizes, idx, &o, NULL, NULL), GEOM_OK);
    uint32_t id = geom_mesh_channel_find(m, "uv", GEOM_MESH_DOMAIN_CORNER);
    assert_int_not_equal(id, INV);
    /* corner k of the face at halfedge face_he + k next-steps: values 0,1,2 */
    uint32_t h = geom_mesh_face_he(m, 0);
    for (uint32_t k = 0; k < 3; k++) {
        assert_int_equal(geom_mesh_corner_cindices(m, id)[h], k);
        assert_int_equal(geom_mesh_he_vertex(m, h), idx[k]);
        h = geom_mesh_he_next(m, h);
    }
    geom_mesh_destroy(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_clean_grids),
        cmocka_unit_test(test_holes_fall_back),
        cmocka_unit_test(test_dirty_fall_back),
        cmocka_unit_test(test_nonmanifold_edge_and_range),
        cmocka_unit_test(test_bad_streams),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
