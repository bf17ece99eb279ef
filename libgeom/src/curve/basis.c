/* B-spline span search and basis functions (The NURBS Book A2.1-A2.3). */
#include "curve/bspline_basis.h"

/* ------------------------------------------------------------ public API */

static geom_status check_knots(int degree, size_t n, const double *knots)
{
    if (!knots || degree < 0 || n < (size_t)degree + 1)
        return GEOM_ERR_INVALID_ARG;
    if (!(knots[degree] < knots[n]))
        return GEOM_ERR_INVALID_ARG;
    return GEOM_OK;
}

geom_status geom_curve_bspline_find_span(int degree, size_t n, const double *knots, double u,
                                         unsigned flags, size_t *span)
{
    geom_status st = check_knots(degree, n, knots);
    if (st != GEOM_OK || !span)
        return GEOM_ERR_INVALID_ARG;
    double ue;
    int left;
    st = geom__curve_prepare_param_knots(degree, n, knots, u, flags, &ue, &left);
    if (st != GEOM_OK)
        return st;
    *span = geom__bs_span(degree, n, knots, ue, left);
    return GEOM_OK;
}

geom_status geom_curve_bspline_basis(int degree, size_t n, const double *knots, double u,
                                     unsigned flags, size_t *span, double *basis)
{
    geom_status st = check_knots(degree, n, knots);
    if (st != GEOM_OK || !basis)
        return GEOM_ERR_INVALID_ARG;
    double ue;
    int left;
    st = geom__curve_prepare_param_knots(degree, n, knots, u, flags, &ue, &left);
    if (st != GEOM_OK)
        return st;
    size_t k = geom__bs_span(degree, n, knots, ue, left);
    geom__scratch s;
    st = geom__scratch_init(&s, geom__bs_basis_work(degree));
    if (st == GEOM_OK) {
        geom__bs_basis(degree, knots, k, ue, basis, s.mem);
        if (span)
            *span = k;
    }
    geom__scratch_free(&s);
    return st;
}

geom_status geom_curve_bspline_basis_derivs(int degree, size_t n, const double *knots, double u,
                                            int nderiv, unsigned flags, size_t *span, double *ders)
{
    geom_status st = check_knots(degree, n, knots);
    if (st != GEOM_OK || !ders || nderiv < 0)
        return GEOM_ERR_INVALID_ARG;
    double ue;
    int left;
    st = geom__curve_prepare_param_knots(degree, n, knots, u, flags, &ue, &left);
    if (st != GEOM_OK)
        return st;
    size_t k = geom__bs_span(degree, n, knots, ue, left);
    geom__scratch s;
    st = geom__scratch_init(&s, geom__bs_ders_work(degree));
    if (st == GEOM_OK) {
        geom__bs_ders(degree, knots, k, ue, nderiv, ders, s.mem);
        if (span)
            *span = k;
    }
    geom__scratch_free(&s);
    return st;
}
