/* Writing an isosurface as OBJ straight from its arrays
 * (geom_meshio_write_soup) or chunk by chunk as geom_iso_extract_stream
 * hands it over (geom_meshio_write_soup_part, what geom-iso does for an
 * expression) against writing the
 * half-edge mesh geom_iso_surface_to_mesh builds of it
 * (geom_meshio_write_memory): the same bytes, with and without normals,
 * caps and the inside-above convention; and the soup writer's refusals. */
#define _POSIX_C_SOURCE 200809L
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "geom/implicit.h"
#include "geom/iso.h"
#include "geom/meshio.h"

typedef struct membuf {
    char *p;
    size_t n, cap;
} membuf;

static geom_status to_mem(void *user, const void *data, size_t size)
{
    membuf *b = user;
    if (b->n + size > b->cap) {
        size_t cap = 2 * (b->n + size);
        char *q = realloc(b->p, cap);
        if (!q)
            return GEOM_ERR_NOMEM;
        b->p = q;
        b->cap = cap;
    }
    memcpy(b->p + b->n, data, size);
    b->n += size;
    return GEOM_OK;
}

static void soup_of(const geom_iso_surface *s, geom_meshio_soup *soup)
{
    memset(soup, 0, sizeof *soup);
    soup->n_vertices = s->n_vertices;
    soup->xyz = s->xyz;
    soup->normals = s->normals;
    soup->n_faces = s->n_triangles;
    soup->indices = s->tris;
}

/* The field of expr, the options and the resolution res, res + 1, res + 2
 * of the tests below. */
static void setup(const char *expr, size_t res, int normals, int caps, int above,
                  geom_implicit_expr **e, geom_iso_field *f, geom_iso_options *o, size_t r[3])
{
    *e = NULL;
    assert_int_equal(geom_implicit_expr_compile(expr, strlen(expr), NULL, e, NULL), GEOM_OK);
    assert_int_equal(geom_iso_field_from_expr(*e, f), GEOM_OK);
    memset(o, 0, sizeof *o);
    o->normals = normals;
    o->caps = caps;
    o->inside = above ? GEOM_ISO_INSIDE_ABOVE : GEOM_ISO_INSIDE_BELOW;
    r[0] = res;
    r[1] = res + 1;
    r[2] = res + 2;
}

static void same_bytes(const char *expr, const double b[6], size_t res, int normals, int caps,
                       int above, unsigned omit)
{
    geom_implicit_expr *e;
    geom_iso_field f;
    geom_iso_options o;
    size_t r[3];
    setup(expr, res, normals, caps, above, &e, &f, &o, r);
    geom_iso_surface s;
    assert_int_equal(geom_iso_extract(&f, b, r, &o, &s, NULL), GEOM_OK);
    assert_true(s.n_triangles > 0);
    geom_mesh *m = geom_mesh_create(NULL);
    assert_non_null(m);
    assert_int_equal(geom_iso_surface_to_mesh(&s, m, NULL), GEOM_OK);
    geom_meshio_write_options wo;
    memset(&wo, 0, sizeof wo);
    wo.format = GEOM_MESHIO_FORMAT_OBJ;
    wo.omit = omit;
    void *ref = NULL;
    size_t nref = 0;
    assert_int_equal(geom_meshio_write_memory(m, &wo, &ref, &nref, NULL), GEOM_OK);
    geom_meshio_soup soup;
    soup_of(&s, &soup);
    membuf got = {NULL, 0, 0};
    assert_int_equal(geom_meshio_write_soup_stream(&soup, &wo, to_mem, &got, NULL), GEOM_OK);
    assert_int_equal(got.n, nref);
    assert_memory_equal(got.p, ref, nref);
    /* the file path gives the same bytes */
    char path[96];
    snprintf(path, sizeof path, "/tmp/geom_test_iso_write_%ld.obj", (long)getpid());
    geom_meshio_write_options fo = wo;
    fo.format = GEOM_MESHIO_FORMAT_AUTO;
    assert_int_equal(geom_meshio_write_soup(&soup, path, &fo, NULL), GEOM_OK);
    FILE *fp = fopen(path, "rb");
    assert_non_null(fp);
    char *back = malloc(nref + 1);
    assert_non_null(back);
    assert_int_equal(fread(back, 1, nref + 1, fp), nref);
    fclose(fp);
    assert_memory_equal(back, ref, nref);
    remove(path);
    free(back);
    free(got.p);
    geom_meshio_buffer_free(ref, nref, NULL);
    geom_mesh_destroy(m);
    geom_iso_surface_free(&s);
    geom_implicit_expr_destroy(e);
}

static const double box2[6] = {-2.16, -1.296, -0.432, 2.16, 1.296, 0.432};
static const char *tori = "min(torus(-0.7,0,0,0.9,0.3),torus(0.7,0,0,0.9,0.3))";

static void test_plain(void **state)
{
    (void)state;
    same_bytes(tori, box2, 24, 0, 0, 0, 0);
}

static void test_normals(void **state)
{
    (void)state;
    same_bytes(tori, box2, 20, 1, 0, 0, 0);
    same_bytes(tori, box2, 20, 1, 0, 0, GEOM_MESHIO_ATTR_NORMAL);
}

static void test_caps_above(void **state)
{
    (void)state;
    /* the box cuts the spheres: caps close them (box node vertices) */
    const double b[6] = {-0.9, -0.9, -0.9, 0.9, 0.9, 0.5};
    same_bytes("sqrt(x*x+y*y+z*z) - 0.8", b, 15, 1, 1, 0, 0);
    same_bytes("sqrt(x*x+y*y+z*z) - 0.8", b, 15, 0, 1, 1, 0);
    /* ambiguous faces and tunnels: a gyroid */
    const double g[6] = {-3, -3, -3, 3, 3, 3};
    same_bytes("sin(x)*cos(y) + sin(y)*cos(z) + sin(z)*cos(x)", g, 11, 1, 1, 0, 0);
}

static void test_refusals(void **state)
{
    (void)state;
    const double xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const uint32_t tri[3] = {0, 1, 2}, bad[3] = {0, 1, 3}, sizes[1] = {2};
    geom_meshio_soup s = {3, xyz, NULL, 1, NULL, tri};
    geom_meshio_write_options wo;
    memset(&wo, 0, sizeof wo);
    wo.format = GEOM_MESHIO_FORMAT_OBJ;
    membuf got = {NULL, 0, 0};
    assert_int_equal(geom_meshio_write_soup_stream(&s, &wo, to_mem, &got, NULL), GEOM_OK);
    got.p[got.n - 1] = 0;
    assert_non_null(strstr(got.p, "\nv 1 0 0\nv 0 1 0\nf 1 2 3"));
    geom_diag d;
    s.indices = bad;
    assert_int_equal(geom_meshio_write_soup_stream(&s, &wo, to_mem, &got, &d),
                     GEOM_ERR_INVALID_ARG);
    assert_non_null(strstr(d.message, "out of range"));
    s.indices = tri;
    s.face_sizes = sizes;
    assert_int_equal(geom_meshio_write_soup_stream(&s, &wo, to_mem, &got, &d),
                     GEOM_ERR_INVALID_ARG);
    s.face_sizes = NULL;
    const double nan_xyz[9] = {0, 0, 0, NAN, 0, 0, 0, 1, 0};
    s.xyz = nan_xyz;
    assert_int_equal(geom_meshio_write_soup_stream(&s, &wo, to_mem, &got, NULL),
                     GEOM_ERR_INVALID_ARG);
    s.xyz = xyz;
    wo.format = GEOM_MESHIO_FORMAT_PLY;
    assert_int_equal(geom_meshio_write_soup_stream(&s, &wo, to_mem, &got, NULL),
                     GEOM_ERR_INVALID_ARG);
    wo.format = GEOM_MESHIO_FORMAT_OBJ;
    assert_int_equal(geom_meshio_write_soup_stream(NULL, &wo, to_mem, &got, NULL),
                     GEOM_ERR_INVALID_ARG);
    assert_int_equal(geom_meshio_write_soup_stream(&s, &wo, NULL, NULL, NULL),
                     GEOM_ERR_INVALID_ARG);
    /* a path with another extension is refused, and nothing is created */
    assert_int_equal(geom_meshio_write_soup(&s, "/tmp/geom_test_iso_write_refused_.ply", NULL,
                                            NULL),
                     GEOM_ERR_INVALID_ARG);
    FILE *fp = fopen("/tmp/geom_test_iso_write_refused_.ply", "rb");
    assert_null(fp);
    /* an empty soup: the header line only */
    geom_meshio_soup e = {0, NULL, NULL, 0, NULL, NULL};
    got.n = 0;
    assert_int_equal(geom_meshio_write_soup_stream(&e, &wo, to_mem, &got, NULL), GEOM_OK);
    assert_true(got.n > 0 && got.p[got.n - 1] == '\n');
    free(got.p);
}

/* A bad face at the end of a soup larger than the writer's buffer: the
 * error comes before any byte reaches the stream (the faces are checked
 * first), so a caller's stream never gets a partial OBJ. */
static void test_bad_face_writes_nothing(void **state)
{
    (void)state;
    const size_t nv = 200000, nf = nv - 2;
    double *xyz = malloc(3 * nv * sizeof(double));
    uint32_t *ix = malloc(3 * nf * sizeof(uint32_t));
    uint32_t *sizes = malloc(nf * sizeof(uint32_t));
    assert_non_null(xyz);
    assert_non_null(ix);
    assert_non_null(sizes);
    for (size_t v = 0; v < nv; v++) {
        xyz[3 * v] = 0.1 * (double)v;
        xyz[3 * v + 1] = (double)(v % 7) / 3.0;
        xyz[3 * v + 2] = 1e-3 * (double)v;
    }
    for (size_t f = 0; f < nf; f++) {
        ix[3 * f] = (uint32_t)f;
        ix[3 * f + 1] = (uint32_t)f + 1;
        ix[3 * f + 2] = (uint32_t)f + 2;
        sizes[f] = 3;
    }
    geom_meshio_soup s = {nv, xyz, xyz, nf, NULL, ix};
    geom_meshio_write_options wo;
    memset(&wo, 0, sizeof wo);
    wo.format = GEOM_MESHIO_FORMAT_OBJ;
    membuf got = {NULL, 0, 0};
    assert_int_equal(geom_meshio_write_soup_stream(&s, &wo, to_mem, &got, NULL), GEOM_OK);
    assert_true(got.n > (size_t)1 << 22); /* more than any write buffer */
    geom_diag d;
    ix[3 * nf - 1] = (uint32_t)nv; /* the last face's last index */
    got.n = 0;
    assert_int_equal(geom_meshio_write_soup_stream(&s, &wo, to_mem, &got, &d),
                     GEOM_ERR_INVALID_ARG);
    assert_non_null(strstr(d.message, "out of range"));
    assert_int_equal(got.n, 0);
    ix[3 * nf - 1] = (uint32_t)nv - 1;
    s.face_sizes = sizes;
    sizes[nf - 1] = 2; /* a 2-gon last */
    assert_int_equal(geom_meshio_write_soup_stream(&s, &wo, to_mem, &got, &d),
                     GEOM_ERR_INVALID_ARG);
    assert_int_equal(got.n, 0);
    free(got.p);
    free(xyz);
    free(ix);
    free(sizes);
}

/* geom_iso_extract_stream's chunks, collected, and written as OBJ parts. */
typedef struct collect {
    double *xyz, *nrm;
    uint32_t *tris;
    size_t nv, nt, ncap, chunks;
    int saw_caps, fail_at, normals;
    membuf obj;
} collect;

static geom_status collect_chunk(void *user, const geom_iso_chunk *ch)
{
    collect *c = user;
    if (c->fail_at && (int)c->chunks + 1 == c->fail_at)
        return GEOM_ERR_IO;
    assert_int_equal(ch->first_vertex, c->nv);
    assert_false(c->saw_caps); /* the caps come last */
    assert_true(ch->n_vertices || ch->n_triangles); /* empty chunks are skipped */
    c->chunks++;
    assert_int_equal(ch->normals != NULL, c->normals);
    if (ch->caps) {
        c->saw_caps = 1;
        assert_int_equal(ch->n_vertices, 0);
        c->ncap += ch->n_triangles;
    }
    c->xyz = realloc(c->xyz, 3 * (c->nv + ch->n_vertices + 1) * sizeof(double));
    c->nrm = realloc(c->nrm, 3 * (c->nv + ch->n_vertices + 1) * sizeof(double));
    c->tris = realloc(c->tris, 3 * (c->nt + ch->n_triangles + 1) * sizeof(uint32_t));
    assert_true(c->xyz && c->nrm && c->tris);
    if (ch->n_vertices)
        memcpy(c->xyz + 3 * c->nv, ch->xyz, 3 * ch->n_vertices * sizeof(double));
    if (ch->normals)
        memcpy(c->nrm + 3 * c->nv, ch->normals, 3 * ch->n_vertices * sizeof(double));
    for (size_t q = 0; q < 3 * ch->n_triangles; q++)
        assert_true(ch->tris[q] < ch->first_vertex + ch->n_vertices);
    if (ch->n_triangles)
        memcpy(c->tris + 3 * c->nt, ch->tris, 3 * ch->n_triangles * sizeof(uint32_t));
    geom_meshio_soup soup = {ch->n_vertices, ch->xyz, ch->normals, ch->n_triangles, NULL,
                             ch->tris};
    geom_meshio_write_options wo;
    memset(&wo, 0, sizeof wo);
    wo.format = GEOM_MESHIO_FORMAT_OBJ;
    assert_int_equal(geom_meshio_write_soup_part(&soup, ch->first_vertex, c->chunks == 1, &wo,
                                                 to_mem, &c->obj, NULL),
                     GEOM_OK);
    c->nv += ch->n_vertices;
    c->nt += ch->n_triangles;
    return GEOM_OK;
}

/* The lines of an OBJ text regrouped: comments, then v, vn and f lines,
 * each kind in its order (what the parts give, written in one piece). */
static char *regroup(const char *p, size_t n)
{
    char *o = malloc(n + 1);
    assert_non_null(o);
    size_t k = 0;
    const char *kinds[4] = {"#", "v ", "vn ", "f "};
    for (int pass = 0; pass < 4; pass++) {
        const char *l = p;
        while (l < p + n) {
            const char *e = memchr(l, '\n', (size_t)(p + n - l));
            size_t len = e ? (size_t)(e - l) + 1 : (size_t)(p + n - l);
            if (strncmp(l, kinds[pass], strlen(kinds[pass])) == 0) {
                memcpy(o + k, l, len);
                k += len;
            }
            l += len;
        }
    }
    assert_int_equal(k, n);
    return o;
}

/* The stream path gives geom_iso_extract's surface: the same vertices,
 * normals and triangles in the same order, counts, signed volume (summed
 * in the same order: bitwise) and error maxima and stride; its OBJ parts
 * are geom_meshio_write_soup_stream's lines, v and f interleaved. */
static void same_stream(const char *expr, const double b[6], size_t res, int normals, int caps,
                        int above, int dense, size_t layers)
{
    geom_implicit_expr *e;
    geom_iso_field f;
    geom_iso_options o;
    size_t r[3];
    setup(expr, res, normals, caps, above, &e, &f, &o, r);
    o.dense = dense;
    o.slab_layers = layers;
    o.error_samples = 1000; /* a stride > 1 */
    geom_iso_surface s, t;
    assert_int_equal(geom_iso_extract(&f, b, r, &o, &s, NULL), GEOM_OK);
    collect c;
    memset(&c, 0, sizeof c);
    c.normals = normals;
    assert_int_equal(geom_iso_extract_stream(&f, b, r, &o, collect_chunk, &c, &t, NULL), GEOM_OK);
    assert_null(t.xyz);
    assert_null(t.tris);
    assert_int_equal(t.n_vertices, s.n_vertices);
    assert_int_equal(t.n_triangles, s.n_triangles);
    assert_int_equal(t.n_cap_triangles, s.n_cap_triangles);
    assert_int_equal(c.nv, s.n_vertices);
    assert_int_equal(c.nt, s.n_triangles);
    assert_int_equal(c.ncap, s.n_cap_triangles);
    assert_int_equal(c.saw_caps, s.n_cap_triangles > 0);
    if (s.n_vertices)
        assert_memory_equal(c.xyz, s.xyz, 3 * s.n_vertices * sizeof(double));
    if (normals && s.n_vertices)
        assert_memory_equal(c.nrm, s.normals, 3 * s.n_vertices * sizeof(double));
    if (s.n_triangles)
        assert_memory_equal(c.tris, s.tris, 3 * s.n_triangles * sizeof(uint32_t));
    assert_true(t.report.signed_volume == s.report.signed_volume);
    assert_true(t.report.error.max_error == s.report.error.max_error);
    assert_true(t.report.vertex_error.max_error == s.report.vertex_error.max_error);
    assert_int_equal(t.report.error_stride, s.report.error_stride);
    assert_int_equal(t.report.error.pieces, s.report.error.pieces);
    assert_int_equal(t.report.active_cells, s.report.active_cells);
    if (s.n_triangles > 0)
        assert_true(s.report.error_stride > 1 || s.n_vertices + 4 * s.n_triangles <= 1000);
    geom_meshio_soup soup;
    soup_of(&s, &soup);
    geom_meshio_write_options wo;
    memset(&wo, 0, sizeof wo);
    wo.format = GEOM_MESHIO_FORMAT_OBJ;
    membuf ref = {NULL, 0, 0};
    assert_int_equal(geom_meshio_write_soup_stream(&soup, &wo, to_mem, &ref, NULL), GEOM_OK);
    if (c.chunks) {
        assert_int_equal(c.obj.n, ref.n);
        char *g = regroup(c.obj.p, c.obj.n);
        assert_memory_equal(g, ref.p, ref.n);
        free(g);
    }
    /* a failing chunk function stops the extraction with its status */
    if (c.chunks > 1) {
        collect d;
        memset(&d, 0, sizeof d);
        d.fail_at = 2;
        d.normals = normals;
        assert_int_equal(geom_iso_extract_stream(&f, b, r, &o, collect_chunk, &d, &t, NULL),
                         GEOM_ERR_IO);
        assert_int_equal(d.chunks, 1);
        assert_int_equal(t.n_vertices, 0);
        free(d.xyz);
        free(d.nrm);
        free(d.tris);
        free(d.obj.p);
    }
    free(ref.p);
    free(c.xyz);
    free(c.nrm);
    free(c.tris);
    free(c.obj.p);
    geom_iso_surface_free(&s);
    geom_iso_surface_free(&t);
    geom_implicit_expr_destroy(e);
}

static void test_stream(void **state)
{
    (void)state;
    for (int dense = 0; dense < 2; dense++) {
        same_stream(tori, box2, 24, 0, 0, 0, dense, 3);
        same_stream(tori, box2, 20, 1, 0, 0, dense, 0);
    }
    const double b[6] = {-0.9, -0.9, -0.9, 0.9, 0.9, 0.5};
    same_stream("sqrt(x*x+y*y+z*z) - 0.8", b, 15, 1, 1, 0, 0, 2);
    same_stream("sqrt(x*x+y*y+z*z) - 0.8", b, 15, 0, 1, 1, 0, 1);
    const double g[6] = {-3, -3, -3, 3, 3, 3};
    same_stream("sin(x)*cos(y) + sin(y)*cos(z) + sin(z)*cos(x)", g, 11, 1, 1, 0, 0, 4);
    /* an empty surface: no chunk */
    same_stream("sqrt(x*x+y*y+z*z) - 10", b, 6, 0, 0, 0, 0, 2);
    /* refusals */
    geom_implicit_expr *e = NULL;
    assert_int_equal(geom_implicit_expr_compile("x", 1, NULL, &e, NULL), GEOM_OK);
    geom_iso_field f;
    assert_int_equal(geom_iso_field_from_expr(e, &f), GEOM_OK);
    size_t r[3] = {4, 4, 4};
    geom_iso_surface t;
    assert_int_equal(geom_iso_extract_stream(&f, b, r, NULL, NULL, NULL, &t, NULL),
                     GEOM_ERR_INVALID_ARG);
    geom_implicit_expr_destroy(e);
    /* a part whose face uses a vertex beyond it is refused, nothing written */
    const double xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const uint32_t tri[3] = {10, 11, 13};
    geom_meshio_soup soup = {3, xyz, NULL, 1, NULL, tri};
    membuf got = {NULL, 0, 0};
    geom_meshio_write_options wo;
    memset(&wo, 0, sizeof wo);
    wo.format = GEOM_MESHIO_FORMAT_OBJ;
    geom_diag d;
    assert_int_equal(geom_meshio_write_soup_part(&soup, 10, 0, &wo, to_mem, &got, &d),
                     GEOM_ERR_INVALID_ARG);
    assert_non_null(strstr(d.message, "out of range"));
    assert_int_equal(got.n, 0);
    const uint32_t ok[3] = {2, 11, 12};
    soup.indices = ok;
    assert_int_equal(geom_meshio_write_soup_part(&soup, 10, 0, &wo, to_mem, &got, NULL), GEOM_OK);
    assert_int_equal(got.n, strlen("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 3 12 13\n"));
    assert_memory_equal(got.p, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 3 12 13\n", got.n);
    free(got.p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_plain),
        cmocka_unit_test(test_normals),
        cmocka_unit_test(test_caps_above),
        cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_bad_face_writes_nothing),
        cmocka_unit_test(test_stream),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
