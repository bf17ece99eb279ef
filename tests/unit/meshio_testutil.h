/* Helpers shared by the meshio tests (test_meshio_*.c). Header-only. */
#ifndef GEOM_TESTS_MESHIO_TESTUTIL_H
#define GEOM_TESTS_MESHIO_TESTUTIL_H

#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "geom/meshio.h"

/* Path of a file under $GEOM_TEST_DATA (or $GEOM_SHARED_DATA when shared). */
static inline const char *mt_path(char *buf, size_t size, int shared, const char *name)
{
    const char *dir = getenv(shared ? "GEOM_SHARED_DATA" : "GEOM_TEST_DATA");
    if (!dir)
        dir = shared ? "tests/data" : "data";
    snprintf(buf, size, "%s/%s", dir, name);
    return buf;
}

/* Whole file into a malloc'd buffer (NUL-terminated; *size without it). */
static inline unsigned char *mt_slurp(const char *path, size_t *size)
{
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return NULL;
    size_t cap = 4096, n = 0;
    unsigned char *buf = malloc(cap + 1);
    for (;;) {
        if (n == cap) {
            cap *= 2;
            buf = realloc(buf, cap + 1);
        }
        size_t got = fread(buf + n, 1, cap - n, fp);
        n += got;
        if (!got)
            break;
    }
    fclose(fp);
    buf[n] = 0;
    *size = n;
    return buf;
}

/* Read `size` bytes (a string when size is (size_t)-1) as `fmt`. */
static inline geom_status mt_read(const void *data, size_t size, geom_meshio_format fmt,
                                  int skip_invalid, geom_mesh **m,
                                  geom_mesh_build_report *report, geom_diag *diag,
                                  geom_meshio_read_stats *stats)
{
    geom_meshio_read_options o;
    memset(&o, 0, sizeof o);
    o.format = fmt;
    o.build.skip_invalid_faces = skip_invalid;
    o.stats = stats;
    if (size == (size_t)-1)
        size = strlen(data);
    return geom_meshio_read_memory(data, size, "test", &o, m, report, diag);
}

/* Write m to memory with options (format set) and return the buffer. */
static inline void *mt_write(const geom_mesh *m, geom_meshio_format fmt,
                             geom_meshio_encoding enc, size_t *size)
{
    geom_meshio_write_options w;
    memset(&w, 0, sizeof w);
    w.format = fmt;
    w.encoding = enc;
    void *data = NULL;
    geom_diag d;
    geom_status st = geom_meshio_write_memory(m, &w, &data, size, &d);
    if (st != GEOM_OK)
        fprintf(stderr, "write failed: %s\n", d.message);
    assert_int_equal(st, GEOM_OK);
    return data;
}

static inline int mt_same_bits(double a, double b) { return memcmp(&a, &b, sizeof a) == 0; }

/* Assert that two meshes have bit-identical positions (n vertices). */
static inline void mt_assert_same_positions(const geom_mesh *a, const geom_mesh *b)
{
    assert_int_equal(geom_mesh_n_vertices(a), geom_mesh_n_vertices(b));
    const double *pa = geom_mesh_cpositions(a), *pb = geom_mesh_cpositions(b);
    for (size_t i = 0; i < 3 * geom_mesh_n_vertices(a); i++)
        if (!mt_same_bits(pa[i], pb[i])) {
            fprintf(stderr, "position %zu: %.17g vs %.17g\n", i, pa[i], pb[i]);
            fail();
        }
}

/* The vertices of face f in order (at most max); returns the valence. */
static inline size_t mt_face_verts(const geom_mesh *m, uint32_t f, uint32_t *out, size_t max)
{
    uint32_t h0 = geom_mesh_face_he(m, f), h = h0;
    size_t n = 0;
    do {
        if (n < max)
            out[n] = geom_mesh_he_vertex(m, h);
        n++;
        h = geom_mesh_he_next(m, h);
    } while (h != h0 && n < 100000);
    return n;
}

/* Six times the signed volume enclosed by a closed mesh (sum over faces of
 * the fan triangles' p0 . (p1 x p2)): exact for small integer coordinates. */
static inline double mt_volume6(const geom_mesh *m)
{
    const double *p = geom_mesh_cpositions(m);
    double vol = 0;
    for (uint32_t f = 0; f < geom_mesh_n_faces(m); f++) {
        uint32_t v[64];
        size_t n = mt_face_verts(m, f, v, 64);
        for (size_t i = 1; i + 1 < n && n <= 64; i++) {
            const double *a = p + 3 * v[0], *b = p + 3 * v[i], *c = p + 3 * v[i + 1];
            vol += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                    a[2] * (b[0] * c[1] - b[1] * c[0]));
        }
    }
    return vol;
}

/* Diag must name line `line` (and column `col` when nonzero). */
static inline void mt_assert_diag_at(const geom_diag *d, size_t line, size_t col)
{
    if (d->line != line || (col && d->column != col)) {
        fprintf(stderr, "diag at %zu:%zu (%s), expected %zu:%zu\n", d->line, d->column,
                d->message, line, col);
        fail();
    }
}

#endif
