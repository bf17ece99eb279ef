/*
 * libFuzzer target over the JSON curve and surface reader of the tools
 * (sj_read_memory in tools/surface_json.c, through cJSON), given the input
 * as a buffer of exactly `size` bytes (no NUL terminator, so ASan catches
 * any read past the end). Besides memory errors, undefined behaviour, hangs
 * and leaks, it checks the reader's contract and aborts on a violation:
 *  - the status is one the header documents (OK, PARSE, NOMEM); on error
 *    *out is all zero and the diagnostic carries the status, the source
 *    name and a line within the text (at most one past the last);
 *  - on success every curve passes geom_curve_nurbs_validate with its
 *    n + degree + 1 knots and evaluates at both ends and the middle of its
 *    domain, and every surface passes geom_surface_validate and evaluates
 *    at its domain's corners and centre;
 *  - the surfaces tessellate uniformly (2 x 2 quads over each piece between
 *    discontinuities) either with GEOM_OK and a structurally valid mesh
 *    (geom_mesh_validate) of at most 8 triangles per cell, or with LIMIT,
 *    NOMEM or INVALID_ARG (the non-manifold input geom_mesh_build may
 *    refuse).
 * Built as a libFuzzer binary with -DGEOM_FUZZ=ON (clang), and in every
 * build with driver.c, which runs the seed corpus
 * tests/fuzz/corpus/surface_json; both only when cJSON is found (the
 * helper library geom_surface_json exists).
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "geom/curve.h"
#include "geom/mesh.h"
#include "geom/surface.h"
#include "surface_json.h"

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

static void check_curve(const sj_curve *sc)
{
    const geom_nurbs_curve *c = &sc->c;
    geom_diag d;
    geom_status st = geom_curve_nurbs_validate(c, c->n + (size_t)c->degree + 1, &d);
    if (st != GEOM_OK)
        fprintf(stderr, "curve \"%s\" (%s): %s\n", sc->name, sc->type, d.message);
    CHECK(st == GEOM_OK);
    CHECK(c->points == sc->points && c->knots == sc->knots && c->weights == sc->weights);
    double u0, u1;
    CHECK(geom_curve_nurbs_domain(c, &u0, &u1) == GEOM_OK);
    CHECK(u0 < u1);
    const double us[3] = {u0, u0 + 0.5 * (u1 - u0), u1};
    for (int i = 0; i < 3; i++) {
        double out[GEOM_CURVE_MAX_DIM];
        CHECK(geom_curve_nurbs_eval(c, us[i], 0, out) == GEOM_OK);
    }
}

static void check_surface(const geom_nurbs_surface *s)
{
    geom_diag d;
    geom_status st = geom_surface_validate(s, &d);
    if (st != GEOM_OK)
        fprintf(stderr, "surface: %s\n", d.message);
    CHECK(st == GEOM_OK);
    double dom[4];
    CHECK(geom_surface_domain(s, dom) == GEOM_OK);
    CHECK(dom[0] < dom[1] && dom[2] < dom[3]);
    const double uv[5][2] = {{dom[0], dom[2]},
                             {dom[1], dom[2]},
                             {dom[0], dom[3]},
                             {dom[1], dom[3]},
                             {dom[0] + 0.5 * (dom[1] - dom[0]), dom[2] + 0.5 * (dom[3] - dom[2])}};
    for (int i = 0; i < 5; i++) {
        double p[3];
        st = geom_surface_eval(s, uv[i][0], uv[i][1], 0, p);
        CHECK(st == GEOM_OK || st == GEOM_ERR_NOMEM);
    }
}

static void check_tessellation(const geom_nurbs_surface *s, size_t n)
{
    geom_surface_tess_options o;
    memset(&o, 0, sizeof o);
    o.mode = GEOM_SURFACE_TESS_UNIFORM;
    o.grid_u = 2;
    o.grid_v = 2;
    o.per_surface = 1;
    o.attributes = GEOM_SURFACE_ATTR_NORMAL | GEOM_SURFACE_ATTR_UV;
    geom_mesh *m = geom_mesh_create(NULL);
    if (!m)
        return;
    geom_surface_tess_stats stats;
    geom_diag d;
    geom_status st = geom_surface_tessellate(s, n, &o, m, NULL, &stats, &d);
    if (st == GEOM_OK) {
        CHECK(geom_mesh_n_faces(m) == stats.triangles);
        /* per_surface: one cell per piece between discontinuities (a knot
         * of multiplicity degree + 1), at most one per knot span */
        size_t spans = 0;
        for (size_t i = 0; i < n; i++)
            spans += (s[i].nu - (size_t)s[i].degree_u) * (s[i].nv - (size_t)s[i].degree_v);
        CHECK(stats.cells >= n && stats.cells <= spans);
        CHECK(stats.triangles <= 8 * stats.cells);
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
    char *copy = malloc(size ? size : 1);
    if (!copy)
        return 0;
    if (size)
        memcpy(copy, data, size);
    sj_file f;
    memset(&f, 0xA5, sizeof f); /* must be zeroed or filled */
    geom_diag d;
    memset(&d, 0, sizeof d);
    geom_status st = sj_read_memory(copy, size, "fuzz.json", &f, &d);
    if (st != GEOM_OK) {
        CHECK(st == GEOM_ERR_PARSE || st == GEOM_ERR_NOMEM);
        CHECK(f.curves == NULL && f.ncurves == 0 && f.surfaces == NULL);
        CHECK(d.status == st);
        CHECK(strcmp(d.source, "fuzz.json") == 0);
        CHECK(d.line <= count_lines((const uint8_t *)copy, size));
        CHECK(d.message[0] != '\0');
    } else {
        CHECK(f.surfaces != NULL);
        CHECK(f.ncurves == 0 || f.curves != NULL);
        for (size_t i = 0; i < f.ncurves; i++)
            check_curve(&f.curves[i]);
        size_t n = geom_surface_set_count(f.surfaces);
        const geom_nurbs_surface *s = geom_surface_set_data(f.surfaces);
        for (size_t i = 0; i < n; i++)
            check_surface(&s[i]);
        if (n)
            check_tessellation(s, n);
        sj_free(&f);
    }
    free(copy);
    return 0;
}
