/*
 * libFuzzer target over the STEP reader (geom_step_read_memory: the Part 21
 * parser and the B-rep mapping), given an exact-size buffer so that ASan
 * sees any read past the end. Besides memory errors, undefined behaviour,
 * hangs and leaks it checks the contract and aborts on a violation:
 *  - the status is one the header documents (OK, PARSE, LIMIT, NOMEM); *out
 *    is NULL on error and the diagnostic carries the status, the source
 *    name, a message and a line within the text;
 *  - on success every index in the B-rep is in range, and when the B-rep
 *    is small it tessellates at a coarse tolerance with a documented
 *    status and a mesh whose triangles are counted in the stats.
 * Built as a libFuzzer binary with -DGEOM_FUZZ=ON (clang), and in every
 * build with driver.c over the seed corpus tests/fuzz/corpus/step.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "geom/step.h"

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

static void check_brep(const geom_brep *b)
{
    for (size_t k = 0; k < b->nsolids; k++)
        CHECK((size_t)b->solids[k].first_shell + b->solids[k].nshells <= b->nshells);
    for (size_t k = 0; k < b->nshells; k++)
        CHECK((size_t)b->shells[k].first_face + b->shells[k].nfaces <= b->nfaces);
    for (size_t k = 0; k < b->nfaces; k++) {
        CHECK(b->faces[k].surface < b->nsurfaces);
        CHECK((size_t)b->faces[k].first_loop + b->faces[k].nloops <= b->nloops);
    }
    for (size_t k = 0; k < b->nloops; k++)
        CHECK((size_t)b->loops[k].first + b->loops[k].n <= b->ncoedges);
    for (size_t k = 0; k < b->ncoedges; k++)
        CHECK(b->coedges[k].edge < b->nedges);
    for (size_t k = 0; k < b->nedges; k++) {
        CHECK(b->edges[k].v0 < b->nvertices && b->edges[k].v1 < b->nvertices);
        CHECK(b->edges[k].curve < b->ncurves);
    }
    for (size_t k = 0; k < b->nvertices; k++)
        CHECK(isfinite(b->vertices[k].p[0]) && isfinite(b->vertices[k].p[1]) &&
              isfinite(b->vertices[k].p[2]));
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    uint8_t *copy = malloc(size ? size : 1);
    if (!copy)
        return 0;
    if (size)
        memcpy(copy, data, size);
    geom_brep *b = (geom_brep *)(void *)copy; /* must become NULL on error */
    geom_diag d;
    memset(&d, 0, sizeof d);
    geom_step_read_options o;
    memset(&o, 0, sizeof o);
    o.max_depth = 16;
    geom_status st = geom_step_read_memory(copy, size, "fuzz.step", &o, &b, &d);
    if (st != GEOM_OK) {
        CHECK(st == GEOM_ERR_PARSE || st == GEOM_ERR_LIMIT || st == GEOM_ERR_NOMEM);
        CHECK(b == NULL);
        CHECK(d.status == st);
        CHECK(strcmp(d.source, "fuzz.step") == 0);
        CHECK(d.line <= count_lines(copy, size));
        CHECK(d.message[0] != '\0');
    } else {
        CHECK(b != NULL);
        check_brep(b);
        if (b->nfaces <= 8 && b->nedges <= 64) {
            geom_mesh *m = geom_mesh_create(NULL);
            if (m) {
                geom_brep_tess_options to;
                memset(&to, 0, sizeof to);
                to.max_triangles = 20000;
                geom_brep_tess_stats stats;
                geom_error_report rep;
                geom_status ts = geom_step_tessellate(b, &to, m, &rep, NULL, &stats, &d);
                CHECK(ts == GEOM_OK || ts == GEOM_ERR_LIMIT || ts == GEOM_ERR_NOMEM ||
                      ts == GEOM_ERR_INVALID_ARG);
                if (ts == GEOM_OK)
                    CHECK(stats.triangles == geom_mesh_n_faces(m));
                geom_mesh_destroy(m);
            }
        }
        geom_step_destroy(b);
    }
    free(copy);
    return 0;
}
