/*
 * libFuzzer target over the .bpt Bezier patch reader
 * (geom_surface_read_bpt_memory), given the input as a buffer of exactly
 * `size` bytes (no NUL terminator, so ASan catches any read past the end).
 * Besides memory errors, undefined behaviour, hangs and leaks, it checks the
 * reader's contract and aborts on a violation:
 *  - the status is one the header documents (OK, PARSE, LIMIT, NOMEM);
 *    *out is NULL on error and the diagnostic carries the status, the
 *    source name and a line within the text (at most one past the last);
 *  - on success the set holds at least one surface, each a valid bicubic
 *    Bezier patch (geom_surface_validate) with knots {0,0,0,0,1,1,1,1} in
 *    both directions and finite control points, named "patch <k>";
 *  - the set tessellates uniformly (2 x 2 quads per patch) either with
 *    GEOM_OK and a structurally valid mesh (geom_mesh_validate) of at most
 *    8 triangles per patch and 3 vertices per triangle (geom_mesh_build
 *    splits non-manifold vertices, e.g. where a patch's corners
 *    coincide), or with a documented status (LIMIT, NOMEM, INVALID_ARG only for the non-manifold repairs
 *    geom_mesh_build may refuse).
 * Built as a libFuzzer binary with -DGEOM_FUZZ=ON (clang), and in every
 * build with driver.c, which runs the seed corpus tests/fuzz/corpus/bpt.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "geom/mesh.h"
#include "geom/surface.h"

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

static void check_patch(const geom_surface_set *set, size_t k, const geom_nurbs_surface *s)
{
    static const double bez[8] = {0, 0, 0, 0, 1, 1, 1, 1};
    geom_diag d;
    if (geom_surface_validate(s, &d) != GEOM_OK)
        fprintf(stderr, "patch %zu: %s\n", k + 1, d.message);
    CHECK(geom_surface_validate(s, NULL) == GEOM_OK);
    CHECK(s->degree_u == 3 && s->degree_v == 3);
    CHECK(s->nu == 4 && s->nv == 4);
    CHECK(s->weights == NULL);
    CHECK(memcmp(s->knots_u, bez, sizeof bez) == 0);
    CHECK(memcmp(s->knots_v, bez, sizeof bez) == 0);
    for (int i = 0; i < 48; i++)
        CHECK(isfinite(s->points[i]));
    char name[32];
    snprintf(name, sizeof name, "patch %zu", k + 1);
    CHECK(strcmp(geom_surface_set_name(set, k), name) == 0);
}

static void check_tessellation(const geom_nurbs_surface *s, size_t n)
{
    geom_surface_tess_options o;
    memset(&o, 0, sizeof o);
    o.mode = GEOM_SURFACE_TESS_UNIFORM;
    o.grid_u = 2;
    o.grid_v = 2;
    o.attributes = GEOM_SURFACE_ATTR_NORMAL | GEOM_SURFACE_ATTR_UV | GEOM_SURFACE_ATTR_SOURCE;
    geom_mesh *m = geom_mesh_create(NULL);
    if (!m)
        return;
    geom_surface_tess_stats stats;
    geom_error_report rep;
    geom_diag d;
    geom_status st = geom_surface_tessellate(s, n, &o, m, &rep, &stats, &d);
    if (st == GEOM_OK) {
        CHECK(geom_mesh_n_faces(m) == stats.triangles);
        CHECK(geom_mesh_n_vertices(m) == stats.vertices);
        CHECK(stats.triangles <= 8 * n);
        /* welding only merges, but geom_mesh_build may split a non-manifold
         * vertex (a patch whose corners coincide): at most 3 per triangle */
        CHECK(stats.vertices <= 3 * stats.triangles);
        CHECK(stats.cells == n);
        size_t nd = 0;
        geom_mesh_defect def[4];
        CHECK(geom_mesh_validate(m, def, 4, &nd) == GEOM_OK);
        CHECK(nd == 0);
    } else {
        if (st != GEOM_ERR_LIMIT && st != GEOM_ERR_NOMEM && st != GEOM_ERR_INVALID_ARG)
            fprintf(stderr, "tessellate: status %d: %s\n", (int)st, d.message);
        CHECK(st == GEOM_ERR_LIMIT || st == GEOM_ERR_NOMEM || st == GEOM_ERR_INVALID_ARG);
        CHECK(d.status == st);
    }
    geom_mesh_destroy(m);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    /* an exact-size copy so that ASan sees reads past the end */
    uint8_t *copy = malloc(size ? size : 1);
    if (!copy)
        return 0;
    if (size)
        memcpy(copy, data, size);
    static char sentinel;
    geom_surface_set *set = (geom_surface_set *)(void *)&sentinel; /* must become NULL */
    geom_diag d;
    memset(&d, 0, sizeof d);
    geom_status st = geom_surface_read_bpt_memory(copy, size, "fuzz.bpt", NULL, &set, &d);
    if (st != GEOM_OK) {
        CHECK(st == GEOM_ERR_PARSE || st == GEOM_ERR_LIMIT || st == GEOM_ERR_NOMEM);
        CHECK(set == NULL);
        CHECK(d.status == st);
        CHECK(strcmp(d.source, "fuzz.bpt") == 0);
        CHECK(d.line <= count_lines(copy, size));
        CHECK(d.message[0] != '\0');
    } else {
        CHECK(set != NULL);
        size_t n = geom_surface_set_count(set);
        CHECK(n >= 1);
        const geom_nurbs_surface *s = geom_surface_set_data(set);
        CHECK(s != NULL);
        for (size_t k = 0; k < n; k++)
            check_patch(set, k, &s[k]);
        check_tessellation(s, n);
        geom_surface_set_destroy(set);
    }
    free(copy);
    return 0;
}
