/* Curve module plumbing: the cheap checks every evaluation does, parameter
 * reduction with the curve flags, and homogeneous output buffers. */
#include "curve/bspline_basis.h"

geom_status geom__curve_check(const geom_nurbs_curve *c, geom_diag *diag)
{
    if (!c)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "curve: NULL curve");
    return geom_curve_nurbs_validate(c, c->n + (size_t)c->degree + 1, diag);
}

geom_status geom__curve_check_cheap(const geom_nurbs_curve *c)
{
    if (!c || !c->knots || !c->points)
        return GEOM_ERR_INVALID_ARG;
    if (c->degree < 1 || c->dim < 1 || c->dim > GEOM_CURVE_MAX_DIM)
        return GEOM_ERR_INVALID_ARG;
    if (c->n < (size_t)c->degree + 1)
        return GEOM_ERR_INVALID_ARG;
    return GEOM_OK;
}

/* Shared by the curve functions and the public basis functions: core's
 * parameter reduction (core/bspline.c) with the curve flags. */
static geom_status prepare(int p, size_t n, const double *U, double u, unsigned flags,
                           double *u_eval, int *left)
{
    return geom__bs_param(p, n, U, u, (flags & GEOM_CURVE_WRAP) != 0,
                          (flags & GEOM_CURVE_LEFT_LIMIT) != 0, u_eval, left);
}

geom_status geom__curve_locate_knots(int p, size_t n, const double *U, double u, unsigned flags,
                                     double *u_eval, size_t *span)
{
    int left;
    geom_status st = prepare(p, n, U, u, flags, u_eval, &left);
    if (st == GEOM_OK)
        *span = geom__bs_span(p, n, U, *u_eval, left);
    return st;
}

geom_status geom__curve_prepare_param(const geom_nurbs_curve *c, double u, unsigned flags,
                                     double *u_eval, int *left)
{
    return prepare(c->degree, c->n, c->knots, u, flags, u_eval, left);
}

void geom__curve_hbuf_finish(const geom__curve_hbuf *b, size_t n)
{
    if (!b->w)
        return;
    for (size_t i = 0; i < n; ++i) {
        double w = b->w[i];
        double *P = b->pts + i * b->dim;
        for (size_t d = 0; d < b->dim; ++d)
            P[d] /= w;
    }
}

void geom__curve_hbuf_result(const geom__curve_hbuf *b, int degree, size_t n,
                             const double *knots, geom_nurbs_curve *out)
{
    geom__curve_hbuf_finish(b, n);
    out->degree = degree;
    out->n = n;
    out->dim = b->dim;
    out->knots = knots;
    out->points = b->pts;
    out->weights = b->w;
}
