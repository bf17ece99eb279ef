/*
 * Batch entry points of the barycentric functions: one call over n rows,
 * each argument either one row per query (stride = its size) or the same
 * for every row (stride 0), so bindings (numpy) pay the call overhead once.
 */
#include "bary/bary_internal.h"

#include <math.h>
#include <string.h>

static void finish_row(geom_status st, double *out, size_t k, int32_t *status, size_t i,
                       size_t *failed)
{
    if (st != GEOM_OK) {
        for (size_t j = 0; j < k; j++)
            out[j] = NAN;
        (*failed)++;
    }
    if (status)
        status[i] = (int32_t)st;
}

geom_status geom_bary_simplex_many(geom_bary_simplex kind, size_t n, const double *const pts[5],
                                   const size_t strides[5], double *out, int32_t *status,
                                   size_t *n_failed)
{
    size_t failed = 0;
    if (n_failed)
        *n_failed = 0;
    if (n == 0)
        return GEOM_OK;
    int np = kind == GEOM_BARY_TET ? 5 : 4;
    size_t k = kind == GEOM_BARY_TET ? 4 : 3;
    if (!pts || !strides || !out || (kind != GEOM_BARY_TRI2 && kind != GEOM_BARY_TRI3 &&
                                      kind != GEOM_BARY_TET))
        return GEOM_ERR_INVALID_ARG;
    for (int a = 0; a < np; a++)
        if (!pts[a])
            return GEOM_ERR_INVALID_ARG;
    const double *a = pts[0], *b = pts[1], *c = pts[2], *d = pts[3], *p = pts[np - 1];
    size_t sa = strides[0], sb = strides[1], sc = strides[2], sd = strides[3],
           sp = strides[np - 1];
    for (size_t i = 0; i < n; i++) {
        double *o = out + k * i;
        geom_status st;
        if (kind == GEOM_BARY_TRI2)
            st = geom_bary_tri2(a + i * sa, b + i * sb, c + i * sc, p + i * sp, o);
        else if (kind == GEOM_BARY_TRI3)
            st = geom_bary_tri3(a + i * sa, b + i * sb, c + i * sc, p + i * sp, o);
        else
            st = geom_bary_tet(a + i * sa, b + i * sb, c + i * sc, d + i * sd, p + i * sp, o);
        finish_row(st, o, k, status, i, &failed);
    }
    if (n_failed)
        *n_failed = failed;
    return GEOM_OK;
}

geom_status geom_bary_polygon_many(int wachspress, size_t nv, const double *poly, size_t n,
                                   const double *p, double *w, int32_t *status, size_t *n_failed)
{
    size_t failed = 0;
    if (n_failed)
        *n_failed = 0;
    if (n == 0)
        return GEOM_OK;
    if (!poly || !p || !w || nv < 3)
        return GEOM_ERR_INVALID_ARG;
    for (size_t i = 0; i < n; i++) {
        double *o = w + nv * i;
        geom_status st = wachspress ? geom_bary_wachspress(nv, poly, p + 2 * i, o)
                                    : geom_bary_mean_value(nv, poly, p + 2 * i, o);
        finish_row(st, o, nv, status, i, &failed);
    }
    if (n_failed)
        *n_failed = failed;
    return GEOM_OK;
}
