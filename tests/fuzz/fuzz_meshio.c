/*
 * libFuzzer target over the mesh file readers (geom_meshio_read_memory).
 *
 * The first input byte picks the format (low 3 bits: 0 OBJ, 1 OFF, 2 PLY,
 * 3 STL, 4-7 AUTO: from the content) and whether invalid faces are skipped
 * (bit 3); the rest is the file, passed as a buffer of exactly that size
 * (no NUL terminator, so ASan catches any read past the end). Besides memory
 * errors, undefined behaviour, hangs and leaks, it checks the readers'
 * contract and aborts on a violation:
 *  - the status is one the header documents (OK, PARSE, LIMIT, INVALID_ARG,
 *    NOMEM), *out is NULL on error and the diagnostic carries the status,
 *    the source name, and a line within the text (at most one past the last
 *    line) or a byte offset within the input;
 *  - on success the mesh has no structural defect (geom_mesh_validate), and
 *    it can be written in every format (binary STL and GLB may refuse
 *    coordinates beyond float range with GEOM_ERR_INVALID_ARG), the OBJ text
 *    read back giving the same vertices (bit for bit) and faces.
 * Built as a libFuzzer binary (clang -fsanitize=fuzzer,address,undefined)
 * with the seed corpus tests/fuzz/corpus/meshio (one file per format, the
 * first byte choosing it as above).
 */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "geom/meshio.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define CHECK(cond)                                                                        \
    do {                                                                                   \
        if (!(cond)) {                                                                     \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond);       \
            abort();                                                                       \
        }                                                                                  \
    } while (0)

static size_t count_lines(const uint8_t *p, size_t n)
{
    size_t lines = 1;
    for (size_t i = 0; i < n; i++)
        lines += p[i] == '\n';
    return lines;
}

/* True if some coordinate is beyond float range (binary STL and GLB store
 * floats and reject such meshes with GEOM_ERR_INVALID_ARG). */
static int beyond_float(const geom_mesh *m)
{
    const double *p = geom_mesh_cpositions(m);
    for (size_t i = 0; i < 3 * geom_mesh_n_vertices(m); i++)
        if (fabs(p[i]) > FLT_MAX)
            return 1;
    return 0;
}

static void check_roundtrip(const geom_mesh *m)
{
    static const geom_meshio_format fmts[] = {GEOM_MESHIO_FORMAT_OBJ, GEOM_MESHIO_FORMAT_OFF,
                                              GEOM_MESHIO_FORMAT_PLY, GEOM_MESHIO_FORMAT_STL,
                                              GEOM_MESHIO_FORMAT_GLB};
    for (size_t i = 0; i < sizeof fmts / sizeof fmts[0]; i++) {
        geom_meshio_write_options w;
        memset(&w, 0, sizeof w);
        w.format = fmts[i];
        void *buf = NULL;
        size_t n = 0;
        geom_diag d;
        geom_status st = geom_meshio_write_memory(m, &w, &buf, &n, &d);
        if (st == GEOM_ERR_INVALID_ARG &&
            (fmts[i] == GEOM_MESHIO_FORMAT_STL || fmts[i] == GEOM_MESHIO_FORMAT_GLB) &&
            beyond_float(m)) {
            CHECK(buf == NULL);
            continue;
        }
        if (st != GEOM_OK)
            fprintf(stderr, "write %d: %s\n", (int)fmts[i], d.message);
        CHECK(st == GEOM_OK);
        CHECK(buf != NULL);
        if (fmts[i] == GEOM_MESHIO_FORMAT_OBJ) {
            geom_mesh *back = NULL;
            st = geom_meshio_read_memory(buf, n, "roundtrip.obj", NULL, &back, NULL, &d);
            if (st != GEOM_OK)
                fprintf(stderr, "re-read: %zu:%zu %s\n", d.line, d.column, d.message);
            CHECK(st == GEOM_OK);
            CHECK(geom_mesh_n_vertices(back) == geom_mesh_n_live_vertices(m));
            CHECK(geom_mesh_n_faces(back) == geom_mesh_n_live_faces(m));
            if (geom_mesh_n_live_vertices(m) == geom_mesh_n_vertices(m))
                CHECK(memcmp(geom_mesh_cpositions(back), geom_mesh_cpositions(m),
                             3 * sizeof(double) * geom_mesh_n_vertices(m)) == 0);
            geom_mesh_destroy(back);
        }
        free(buf);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    static const geom_meshio_format pick[8] = {
        GEOM_MESHIO_FORMAT_OBJ,  GEOM_MESHIO_FORMAT_OFF,  GEOM_MESHIO_FORMAT_PLY,
        GEOM_MESHIO_FORMAT_STL,  GEOM_MESHIO_FORMAT_AUTO, GEOM_MESHIO_FORMAT_AUTO,
        GEOM_MESHIO_FORMAT_AUTO, GEOM_MESHIO_FORMAT_AUTO};
    geom_meshio_read_options o;
    geom_meshio_read_stats stats;
    memset(&o, 0, sizeof o);
    o.format = pick[data[0] & 7];
    o.build.skip_invalid_faces = (data[0] >> 3) & 1;
    o.max_elements = 1u << 20; /* keep runs fast; the limit path is exercised too */
    o.stats = &stats;
    size_t n = size - 1;
    /* an exact-size copy so that ASan sees reads past the end */
    uint8_t *copy = malloc(n ? n : 1);
    if (!copy)
        return 0;
    memcpy(copy, data + 1, n);

    geom_mesh *m = (geom_mesh *)&o; /* must be overwritten */
    geom_diag d;
    geom_mesh_build_report r;
    geom_status st = geom_meshio_read_memory(copy, n, "fuzz", &o, &m, &r, &d);
    CHECK(st == GEOM_OK || st == GEOM_ERR_PARSE || st == GEOM_ERR_LIMIT ||
          st == GEOM_ERR_INVALID_ARG || st == GEOM_ERR_NOMEM);
    if (st != GEOM_OK) {
        CHECK(m == NULL);
        CHECK(d.status == st);
        CHECK(strcmp(d.source, "fuzz") == 0);
        CHECK(d.message[0] != '\0');
        CHECK(d.line <= count_lines(copy, n) + 1);
        CHECK(d.byte_offset <= n);
    } else {
        CHECK(m != NULL);
        CHECK(d.status == GEOM_OK);
        size_t nd = 0;
        CHECK(geom_mesh_validate(m, NULL, 0, &nd) == GEOM_OK);
        if (nd)
            fprintf(stderr, "%zu defects\n", nd);
        CHECK(nd == 0);
        CHECK(stats.format != GEOM_MESHIO_FORMAT_AUTO);
        check_roundtrip(m);
        geom_mesh_destroy(m);
    }
    free(copy);
    return 0;
}
