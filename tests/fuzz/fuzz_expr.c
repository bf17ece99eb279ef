/*
 * libFuzzer target over the implicit module's text parsers: the expression
 * compiler (geom_implicit_expr_compile) and the NRRD reader
 * (geom_implicit_volume_read_nrrd_memory), each given the input as a buffer
 * of exactly `size` bytes (no NUL terminator, so ASan catches any read past
 * the end). Besides memory errors, undefined behaviour, stack exhaustion
 * and leaks, it checks the contracts and aborts on a violation:
 *  - compiling: the status is OK, PARSE or LIMIT; on error *out is NULL and
 *    the diagnostic has the status, the source "expression", a line >= 1
 *    and a column within the text (1..size+1 on its line);
 *  - a compiled expression: at a few points the value from eval, eval_grad
 *    and eval_many agree bit for bit (or are all NaN); interval bounds over
 *    a few boxes enclose every finite value at the boxes' corners and
 *    centres; marching squares over a small grid gives a structurally valid
 *    result (indices in range, no zero-length segment);
 *  - NRRD: the status is one the header documents, *out NULL on error, and
 *    on success the samples can be evaluated.
 * Built as a libFuzzer binary with -DGEOM_FUZZ=ON (clang), and in every
 * build with driver.c, which runs the seed corpus tests/fuzz/corpus/expr.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "geom/implicit.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define CHECK(cond)                                                                        \
    do {                                                                                   \
        if (!(cond)) {                                                                     \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond);       \
            abort();                                                                       \
        }                                                                                  \
    } while (0)

static int same(double a, double b)
{
    return (isnan(a) && isnan(b)) || memcmp(&a, &b, sizeof a) == 0;
}

static void check_expr(const geom_implicit_expr *e)
{
    static const double pts[6][3] = {{0, 0, 0},    {0.5, -0.25, 1},  {-3, 2, 0.125},
                                     {1e-300, 0, 0}, {1e10, -1e10, 1}, {2, 2, -2}};
    double many[6];
    geom_implicit_expr_eval_many(e, 6, &pts[0][0], many);
    for (int i = 0; i < 6; i++) {
        double g[3];
        double v = geom_implicit_expr_eval(e, pts[i]);
        double w = geom_implicit_expr_eval_grad(e, pts[i], g);
        CHECK(same(v, w));
        CHECK(same(v, many[i]));
    }
    static const double boxes[4][6] = {{-1, -1, -1, 1, 1, 1},
                                       {0.25, 0.5, -2, 0.75, 3, -1},
                                       {0, 0, 0, 0, 0, 0},
                                       {-100, 5, -1e-3, 50, 6, 1e-3}};
    for (int b = 0; b < 4; b++) {
        const double *lo = boxes[b], *hi = boxes[b] + 3;
        double iv[2];
        CHECK(geom_implicit_expr_eval_interval(e, lo, hi, iv) == GEOM_OK);
        CHECK((isnan(iv[0]) && isnan(iv[1])) || (!isnan(iv[0]) && !isnan(iv[1]) && iv[0] <= iv[1]));
        for (int c = 0; c < 9; c++) {
            double p[3];
            for (int a = 0; a < 3; a++)
                p[a] = c == 8 ? 0.5 * (lo[a] + hi[a]) : ((c >> a) & 1) ? hi[a] : lo[a];
            double v = geom_implicit_expr_eval(e, p);
            if (isfinite(v)) {
                if (!(iv[0] <= v && v <= iv[1])) {
                    fprintf(stderr, "value %.17g at (%.17g, %.17g, %.17g) outside [%.17g, %.17g]\n",
                            v, p[0], p[1], p[2], iv[0], iv[1]);
                    abort();
                }
            }
        }
    }
    geom_implicit_field f;
    geom_implicit_field_from_expr(e, &f);
    double bounds[4] = {-2, -1.5, 2, 1.5};
    geom_implicit_contour_options o;
    memset(&o, 0, sizeof o);
    o.max_iterations = 30;
    geom_implicit_isolines c;
    geom_status st = geom_implicit_contour(&f, bounds, 6, 5, &o, &c, NULL);
    CHECK(st == GEOM_OK);
    for (size_t k = 0; k < c.n_polylines; k++) {
        size_t s = c.start[k], n = c.start[k + 1] - s;
        CHECK(n >= 2);
        for (size_t q = 0; q < n; q++) {
            CHECK(c.indices[s + q] < c.n_vertices);
            if (q + 1 < n)
                CHECK(c.indices[s + q] != c.indices[s + q + 1]);
        }
    }
    for (size_t v = 0; v < c.n_vertices; v++) {
        CHECK(c.xy[2 * v] >= -2 && c.xy[2 * v] <= 2);
        CHECK(c.xy[2 * v + 1] >= -1.5 && c.xy[2 * v + 1] <= 1.5);
    }
    geom_implicit_isolines_free(&c);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > 8192)
        return 0;
    char *text = malloc(size ? size : 1);
    if (!text)
        return 0;
    if (size)
        memcpy(text, data, size);
    geom_implicit_expr *e = (geom_implicit_expr *)&size; /* must be reset */
    geom_diag d;
    geom_diag_clear(&d);
    geom_status st = geom_implicit_expr_compile(text, size, NULL, &e, &d);
    if (st == GEOM_OK) {
        CHECK(e != NULL);
        CHECK(geom_implicit_expr_size(e) >= 1);
        CHECK((geom_implicit_expr_variables(e) & ~15u) == 0);
        check_expr(e);
        geom_implicit_expr_destroy(e);
    } else {
        CHECK(st == GEOM_ERR_PARSE || st == GEOM_ERR_LIMIT);
        CHECK(e == NULL);
        CHECK(d.status == st);
        CHECK(strcmp(d.source, "expression") == 0);
        CHECK(d.line >= 1 && d.column >= 1 && d.column <= size + 1);
        CHECK(d.message[0] != '\0');
    }

    geom_implicit_volume *v = (geom_implicit_volume *)&size;
    geom_diag_clear(&d);
    st = geom_implicit_volume_read_nrrd_memory(text, size, "fuzz.nrrd", NULL, &v, &d);
    if (st == GEOM_OK) {
        CHECK(v != NULL);
        geom_implicit_volume_desc desc;
        geom_implicit_volume_get_desc(v, &desc);
        double p[3] = {desc.origin[0], desc.origin[1], desc.origin[2]}, g[3];
        double a = geom_implicit_volume_eval(v, p);
        double b = geom_implicit_volume_eval_grad(v, p, g);
        CHECK(same(a, b));
        CHECK(same(a, geom_implicit_volume_at(v, 0, 0, 0)));
        geom_implicit_volume_destroy(v);
    } else {
        CHECK(st == GEOM_ERR_PARSE || st == GEOM_ERR_LIMIT || st == GEOM_ERR_NOMEM);
        CHECK(v == NULL);
        CHECK(d.status == st);
    }
    free(text);
    return 0;
}
