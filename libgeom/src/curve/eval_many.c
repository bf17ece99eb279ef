/* Batch evaluation of a curve over an array of parameters (for bindings). */
#include "curve/bspline_basis.h"

#include <math.h>

geom_status geom_curve_nurbs_eval_many(const geom_nurbs_curve *c, size_t n, const double *u,
                                       unsigned flags, double *out, int32_t *status,
                                       size_t *n_failed)
{
    if (n_failed)
        *n_failed = 0;
    if (n == 0)
        return GEOM_OK;
    if (!c || !u || !out || c->dim < 1 || c->dim > GEOM_CURVE_MAX_DIM)
        return GEOM_ERR_INVALID_ARG;
    size_t failed = 0, dim = c->dim;
    for (size_t i = 0; i < n; i++) {
        geom_status st = geom_curve_nurbs_eval(c, u[i], flags, out + dim * i);
        if (st != GEOM_OK) {
            for (size_t j = 0; j < dim; j++)
                out[dim * i + j] = NAN;
            failed++;
        }
        if (status)
            status[i] = (int32_t)st;
    }
    if (n_failed)
        *n_failed = failed;
    return GEOM_OK;
}
