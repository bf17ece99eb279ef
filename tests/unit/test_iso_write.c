/* Writing an isosurface as OBJ straight from its arrays
 * (geom_meshio_write_soup, what geom-iso does) against writing the
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

static void same_bytes(const char *expr, const double b[6], size_t res, int normals, int caps,
                       int above, unsigned omit)
{
    geom_implicit_expr *e = NULL;
    assert_int_equal(geom_implicit_expr_compile(expr, strlen(expr), NULL, &e, NULL), GEOM_OK);
    geom_iso_field f;
    assert_int_equal(geom_iso_field_from_expr(e, &f), GEOM_OK);
    geom_iso_options o;
    memset(&o, 0, sizeof o);
    o.normals = normals;
    o.caps = caps;
    o.inside = above ? GEOM_ISO_INSIDE_ABOVE : GEOM_ISO_INSIDE_BELOW;
    size_t r[3] = {res, res + 1, res + 2};
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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_plain),
        cmocka_unit_test(test_normals),
        cmocka_unit_test(test_caps_above),
        cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_bad_face_writes_nothing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
