/* Cubic Hermite segments and splines, and knot vectors for piecewise Bezier
 * curves. */
#include "curve/bspline_basis.h"

geom_status geom_curve_hermite_to_bezier(size_t dim, const double *p0, const double *m0,
                                         const double *p1, const double *m1, double *bezier)
{
    if (dim < 1 || dim > GEOM_CURVE_MAX_DIM || !p0 || !m0 || !p1 || !m1 || !bezier)
        return GEOM_ERR_INVALID_ARG;
    if (!geom__curve_finite_n(p0, dim) || !geom__curve_finite_n(m0, dim) ||
        !geom__curve_finite_n(p1, dim) || !geom__curve_finite_n(m1, dim))
        return GEOM_ERR_INVALID_ARG;
    for (size_t d = 0; d < dim; ++d) {
        bezier[d] = p0[d];
        bezier[dim + d] = p0[d] + m0[d] / 3.0;
        bezier[2 * dim + d] = p1[d] - m1[d] / 3.0;
        bezier[3 * dim + d] = p1[d];
    }
    return GEOM_OK;
}

geom_status geom_curve_hermite_eval(size_t dim, const double *p0, const double *m0,
                                    const double *p1, const double *m1, double t, int nderiv,
                                    double *ders)
{
    double b[4 * GEOM_CURVE_MAX_DIM];
    geom_status st = geom_curve_hermite_to_bezier(dim, p0, m0, p1, m1, b);
    if (st != GEOM_OK)
        return st;
    return geom_curve_bezier_derivs(3, dim, b, t, nderiv, ders);
}

static geom_status check_params(const double *params, size_t n)
{
    if (!params)
        return GEOM_OK;
    for (size_t i = 0; i < n; ++i) {
        if (!isfinite(params[i]))
            return GEOM_ERR_INVALID_ARG;
        if (i > 0 && !(params[i] > params[i - 1]))
            return GEOM_ERR_DOMAIN;
    }
    return GEOM_OK;
}

geom_status geom_curve_hermite_spline_to_bezier(size_t dim, size_t n, const double *points,
                                                const double *tangents, const double *params,
                                                double *bezier)
{
    if (dim < 1 || dim > GEOM_CURVE_MAX_DIM || n < 2 || !points || !tangents || !bezier)
        return GEOM_ERR_INVALID_ARG;
    if (!geom__curve_finite_n(points, n * dim) || !geom__curve_finite_n(tangents, n * dim))
        return GEOM_ERR_INVALID_ARG;
    geom_status st = check_params(params, n);
    if (st != GEOM_OK)
        return st;
    for (size_t i = 0; i + 1 < n; ++i) {
        double h = params ? params[i + 1] - params[i] : 1.0;
        const double *P0 = points + i * dim, *P1 = points + (i + 1) * dim;
        const double *M0 = tangents + i * dim, *M1 = tangents + (i + 1) * dim;
        double *B = bezier + 3 * i * dim;
        for (size_t d = 0; d < dim; ++d) {
            B[d] = P0[d];
            B[dim + d] = P0[d] + h * M0[d] / 3.0;
            B[2 * dim + d] = P1[d] - h * M1[d] / 3.0;
            B[3 * dim + d] = P1[d];
        }
    }
    return GEOM_OK;
}

geom_status geom_curve_piecewise_bezier_knots(int degree, size_t nseg, const double *params,
                                              double *knots)
{
    if (degree < 1 || nseg < 1 || !knots)
        return GEOM_ERR_INVALID_ARG;
    geom_status st = check_params(params, nseg + 1);
    if (st != GEOM_OK)
        return st;
    size_t p = (size_t)degree, k = 0;
    for (size_t i = 0; i <= nseg; ++i) {
        double v = params ? params[i] : (double)i;
        size_t mult = (i == 0 || i == nseg) ? p + 1 : p;
        for (size_t j = 0; j < mult; ++j)
            knots[k++] = v;
    }
    return GEOM_OK;
}
