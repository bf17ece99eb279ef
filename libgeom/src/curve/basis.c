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
    return geom__curve_locate_knots(degree, n, knots, u, flags, &ue, span);
}

/* The basis functions at u (nderiv < 0: their values, through
 * geom__bs_basis) or their derivatives 0..nderiv (geom__bs_ders) into out,
 * the span into *span (NULL allowed): both public entry points after their
 * argument checks. */
static geom_status basis_at(int degree, size_t n, const double *knots, double u, unsigned flags,
                            int nderiv, size_t *span, double *out)
{
    double ue;
    size_t k;
    geom_status st = geom__curve_locate_knots(degree, n, knots, u, flags, &ue, &k);
    if (st != GEOM_OK)
        return st;
    geom__scratch s;
    st = geom__scratch_init(&s, nderiv < 0 ? geom__bs_basis_work(degree)
                                           : geom__bs_ders_work(degree));
    if (st == GEOM_OK) {
        if (nderiv < 0)
            geom__bs_basis(degree, knots, k, ue, out, s.mem);
        else
            geom__bs_ders(degree, knots, k, ue, nderiv, out, s.mem);
        if (span)
            *span = k;
    }
    geom__scratch_free(&s);
    return st;
}

geom_status geom_curve_bspline_basis(int degree, size_t n, const double *knots, double u,
                                     unsigned flags, size_t *span, double *basis)
{
    geom_status st = check_knots(degree, n, knots);
    if (st != GEOM_OK || !basis)
        return GEOM_ERR_INVALID_ARG;
    return basis_at(degree, n, knots, u, flags, -1, span, basis);
}

geom_status geom_curve_bspline_basis_derivs(int degree, size_t n, const double *knots, double u,
                                            int nderiv, unsigned flags, size_t *span, double *ders)
{
    geom_status st = check_knots(degree, n, knots);
    if (st != GEOM_OK || !ders || nderiv < 0)
        return GEOM_ERR_INVALID_ARG;
    return basis_at(degree, n, knots, u, flags, nderiv, span, ders);
}
