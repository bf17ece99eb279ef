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

geom_status geom_curve_bspline_basis_many(int degree, size_t n, const double *knots, size_t m,
                                          const double *u, int nderiv, unsigned flags,
                                          size_t *spans, double *ders, int32_t *status,
                                          size_t *n_failed)
{
    if (n_failed)
        *n_failed = 0;
    if (m == 0)
        return GEOM_OK;
    if (!knots || !u || !ders || degree < 0 || nderiv < 0)
        return GEOM_ERR_INVALID_ARG;
    size_t row = (size_t)(nderiv + 1) * (size_t)(degree + 1), failed = 0;
    for (size_t i = 0; i < m; i++) {
        size_t span = 0;
        geom_status st = geom_curve_bspline_basis_derivs(degree, n, knots, u[i], nderiv, flags,
                                                         &span, ders + row * i);
        if (st != GEOM_OK) {
            for (size_t j = 0; j < row; j++)
                ders[row * i + j] = NAN;
            failed++;
        }
        if (spans)
            spans[i] = st == GEOM_OK ? span : (size_t)-1;
        if (status)
            status[i] = (int32_t)st;
    }
    if (n_failed)
        *n_failed = failed;
    return GEOM_OK;
}
