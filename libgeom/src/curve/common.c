/* Curve module plumbing: scratch memory, the cheap checks every evaluation
 * does, parameter reduction, and homogeneous output buffers. */
#include "curve/bspline_basis.h"

geom_status geom_curve_scratch_init(geom_curve_scratch *s, size_t ndoubles)
{
    s->heap = 0;
    s->size = ndoubles;
    if (ndoubles <= GEOM_CURVE_SCRATCH_LOCAL) {
        s->mem = s->local;
        return GEOM_OK;
    }
    size_t bytes;
    if (geom_size_mul(ndoubles, sizeof(double), &bytes) != GEOM_OK) {
        s->mem = NULL;
        s->size = 0;
        return GEOM_ERR_LIMIT;
    }
    s->mem = (double *)geom_alloc(NULL, bytes);
    if (!s->mem) {
        s->size = 0;
        return GEOM_ERR_NOMEM;
    }
    s->heap = 1;
    return GEOM_OK;
}

void geom_curve_scratch_free(geom_curve_scratch *s)
{
    if (s->heap && s->mem)
        geom_free(NULL, s->mem, s->size * sizeof(double));
    s->mem = NULL;
    s->heap = 0;
    s->size = 0;
}

geom_status geom_curve_check_cheap(const geom_nurbs_curve *c)
{
    if (!c || !c->knots || !c->points)
        return GEOM_ERR_INVALID_ARG;
    if (c->degree < 1 || c->dim < 1 || c->dim > GEOM_CURVE_MAX_DIM)
        return GEOM_ERR_INVALID_ARG;
    if (c->n < (size_t)c->degree + 1)
        return GEOM_ERR_INVALID_ARG;
    return GEOM_OK;
}

/* Shared by the curve functions and the public basis functions. */
static geom_status prepare(int p, size_t n, const double *U, double u, unsigned flags,
                           double *u_eval, int *left)
{
    if (!isfinite(u))
        return GEOM_ERR_INVALID_ARG;
    double a = U[p], b = U[n];
    int want_left = (flags & GEOM_CURVE_LEFT_LIMIT) != 0;
    if (u >= a && u <= b) {
        if ((flags & GEOM_CURVE_WRAP) && u == b && !want_left)
            u = a; /* the seam of a periodic curve, from the right */
        *u_eval = u;
        *left = want_left;
        return GEOM_OK;
    }
    if (!(flags & GEOM_CURVE_WRAP))
        return GEOM_ERR_DOMAIN;
    double L = b - a;
    if (!(L > 0.0) || !isfinite(L))
        return GEOM_ERR_DOMAIN;
    double x = fmod(u - a, L);
    if (x < 0.0)
        x += L;
    double r = a + x;
    if (!(r < b)) /* rounding pushed it to the seam */
        r = a;
    if (r < a)
        r = a;
    if (r == a && want_left)
        r = b;
    *u_eval = r;
    *left = want_left;
    return GEOM_OK;
}

geom_status geom_curve_prepare_param_knots(int p, size_t n, const double *U, double u,
                                           unsigned flags, double *u_eval, int *left)
{
    return prepare(p, n, U, u, flags, u_eval, left);
}

geom_status geom_curve_prepare_param(const geom_nurbs_curve *c, double u, unsigned flags,
                                     double *u_eval, int *left)
{
    return prepare(c->degree, c->n, c->knots, u, flags, u_eval, left);
}

void geom_curve_hbuf_finish(const geom_curve_hbuf *b, size_t n)
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
