/* Curve validation, uniform knot vectors and periodic curves. */
#include "curve/bspline_basis.h"

geom_status geom_curve_nurbs_validate(const geom_nurbs_curve *c, size_t nknots, geom_diag *diag)
{
    const geom_status E = GEOM_ERR_INVALID_ARG;
    if (!c)
        return geom__diag_set(diag, E, NULL, 0, 0, "curve: NULL curve");
    int p = c->degree;
    if (p < 1)
        return geom__diag_set(diag, E, NULL, 0, 0, "curve: degree %d is below 1", p);
    if (c->dim < 1 || c->dim > GEOM_CURVE_MAX_DIM)
        return geom__diag_set(diag, E, NULL, 0, 0, "curve: dimension %zu is not in 1..%d", c->dim,
                             GEOM_CURVE_MAX_DIM);
    if (c->n < (size_t)p + 1)
        return geom__diag_set(diag, E, NULL, 0, 0,
                             "curve: %zu control points, degree %d needs at least %d", c->n, p,
                             p + 1);
    size_t m = c->n + (size_t)p + 1;
    if (nknots != m)
        return geom__diag_set(diag, E, NULL, 0, 0,
                             "curve: %zu knots, but %zu control points of degree %d need "
                             "n + p + 1 = %zu",
                             nknots, c->n, p, m);
    if (!c->knots || !c->points)
        return geom__diag_set(diag, E, NULL, 0, 0, "curve: NULL knots or points");
    const double *U = c->knots;
    size_t run = 1;
    for (size_t i = 0; i < m; ++i) {
        if (!isfinite(U[i]))
            return geom__diag_set(diag, E, NULL, 0, 0, "curve: knot %zu is not finite", i);
        if (i > 0) {
            if (U[i] < U[i - 1])
                return geom__diag_set(diag, E, NULL, 0, 0,
                                     "curve: knots decrease: knot %zu (%.17g) < knot %zu (%.17g)",
                                     i, U[i], i - 1, U[i - 1]);
            run = U[i] == U[i - 1] ? run + 1 : 1;
            if (run > (size_t)p + 1)
                return geom__diag_set(diag, E, NULL, 0, 0,
                                     "curve: knot value %.17g (ending at index %zu) has "
                                     "multiplicity above degree + 1 = %d",
                                     U[i], i, p + 1);
        }
    }
    if (!(U[p] < U[c->n]))
        return geom__diag_set(diag, E, NULL, 0, 0,
                             "curve: empty domain: knot %d (%.17g) == knot %zu (%.17g)", p, U[p],
                             c->n, U[c->n]);
    for (size_t i = 0; i < c->n * c->dim; ++i)
        if (!isfinite(c->points[i]))
            return geom__diag_set(diag, E, NULL, 0, 0,
                                 "curve: control point %zu has a non-finite coordinate",
                                 i / c->dim);
    if (c->weights)
        for (size_t i = 0; i < c->n; ++i) {
            double w = c->weights[i];
            if (!isfinite(w))
                return geom__diag_set(diag, E, NULL, 0, 0, "curve: weight %zu is not finite", i);
            if (!(w > 0.0))
                return geom__diag_set(diag, E, NULL, 0, 0,
                                     "curve: weight %zu (%.17g) is not positive", i, w);
        }
    return GEOM_OK;
}

geom_status geom_curve_bspline_uniform_knots(geom_knot_kind kind, int degree, size_t n,
                                             double *knots)
{
    if (!knots || degree < 1 || n < (size_t)degree + 1)
        return GEOM_ERR_INVALID_ARG;
    size_t p = (size_t)degree, m = n + p + 1;
    double segs = (double)(n - p);
    switch (kind) {
    case GEOM_KNOTS_CLAMPED:
        for (size_t i = 0; i < m; ++i) {
            if (i <= p)
                knots[i] = 0.0;
            else if (i >= n)
                knots[i] = 1.0;
            else
                knots[i] = (double)(i - p) / segs;
        }
        return GEOM_OK;
    case GEOM_KNOTS_UNCLAMPED:
    case GEOM_KNOTS_PERIODIC:
        for (size_t i = 0; i < m; ++i)
            knots[i] = ((double)i - (double)p) / segs;
        return GEOM_OK;
    }
    return GEOM_ERR_INVALID_ARG;
}

geom_status geom_curve_nurbs_periodic(int degree, size_t m, size_t dim, const double *points,
                                      const double *weights, double *knots, double *points_out,
                                      double *weights_out, geom_nurbs_curve *out)
{
    if (degree < 1 || dim < 1 || dim > GEOM_CURVE_MAX_DIM || m < (size_t)degree + 1 || !points ||
        !knots || !points_out || !out || (weights && !weights_out))
        return GEOM_ERR_INVALID_ARG;
    size_t p = (size_t)degree, n = m + p;
    for (size_t i = 0; i < m * dim; ++i)
        if (!isfinite(points[i]))
            return GEOM_ERR_INVALID_ARG;
    if (weights)
        for (size_t i = 0; i < m; ++i)
            if (!isfinite(weights[i]) || !(weights[i] > 0.0))
                return GEOM_ERR_INVALID_ARG;
    geom_status st = geom_curve_bspline_uniform_knots(GEOM_KNOTS_PERIODIC, degree, n, knots);
    if (st != GEOM_OK)
        return st;
    for (size_t i = 0; i < n; ++i) {
        memcpy(points_out + i * dim, points + (i % m) * dim, dim * sizeof(double));
        if (weights)
            weights_out[i] = weights[i % m];
    }
    out->degree = degree;
    out->n = n;
    out->dim = dim;
    out->knots = knots;
    out->points = points_out;
    out->weights = weights ? weights_out : NULL;
    return GEOM_OK;
}
