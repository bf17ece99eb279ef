/*
 * Private B-spline kernels of the curve module. Not installed.
 *
 * These functions do no argument checking: callers validate once (see
 * geom_curve_nurbs_validate / geom_curve_check_eval) and then call them in
 * inner loops. All knot vectors follow the rules in geom/curve.h: degree
 * p >= 0, n >= p+1 control points, n+p+1 nondecreasing knots, u_p < u_n.
 *
 * The span search, basis functions, parameter reduction and scratch memory
 * are core's (core/bspline.h), shared with the surface module. Functions
 * that need temporary arrays whose size grows with the degree take them from
 * the caller (`work`, sized by the matching *_work() function), so they never
 * allocate. geom__scratch gives callers a stack buffer with a heap fallback.
 *
 * Symbols are prefixed geom_curve_ so that the link-minimality check
 * (tests/link) attributes them to this module.
 */
#ifndef GEOM_SRC_CURVE_BSPLINE_BASIS_H
#define GEOM_SRC_CURVE_BSPLINE_BASIS_H

#include "core/bspline.h"
#include "core/internal.h"
#include "geom/curve.h"

#include <string.h>

/* ------------------------------------------------------ homogeneous points */

/** Homogeneous dimension: dim + 1 for rational curves, dim otherwise. */
#define GEOM_CURVE_HDIM_MAX (GEOM_CURVE_MAX_DIM + 1)

static inline size_t geom__curve_hdim(const geom_nurbs_curve *c)
{
    return c->dim + (c->weights ? 1 : 0);
}

/** h = (w P_i, w) for rational curves, P_i otherwise (hdim doubles). */
static inline void geom__curve_hget(const geom_nurbs_curve *c, size_t i, double *h)
{
    const double *P = c->points + i * c->dim;
    if (c->weights) {
        double w = c->weights[i];
        for (size_t d = 0; d < c->dim; ++d)
            h[d] = w * P[d];
        h[c->dim] = w;
    } else {
        for (size_t d = 0; d < c->dim; ++d)
            h[d] = P[d];
    }
}

/** r = a*x + b*y on D components (r may alias x or y). */
static inline void geom__curve_hcomb(size_t D, double *r, double a, const double *x, double b,
                                    const double *y)
{
    for (size_t d = 0; d < D; ++d)
        r[d] = a * x[d] + b * y[d];
}

/**
 * Output curve being built in homogeneous form inside the caller's split
 * buffers: point i is pts[i*dim ..] (holding w*P while building) and w[i]
 * (w == NULL for polynomial curves).
 */
typedef struct geom__curve_hbuf {
    double *pts;
    double *w;
    size_t dim;
} geom__curve_hbuf;

static inline void geom__curve_hbuf_set(const geom__curve_hbuf *b, size_t i, const double *h)
{
    memcpy(b->pts + i * b->dim, h, b->dim * sizeof(double));
    if (b->w)
        b->w[i] = h[b->dim];
}

static inline void geom__curve_hbuf_get(const geom__curve_hbuf *b, size_t i, double *h)
{
    memcpy(h, b->pts + i * b->dim, b->dim * sizeof(double));
    if (b->w)
        h[b->dim] = b->w[i];
}

/** Turn points [0, n) of b from (w P, w) back into Euclidean P. */
void geom__curve_hbuf_finish(const geom__curve_hbuf *b, size_t n);

/** geom__curve_hbuf_finish(b, n), then out = the curve of that degree, n
 *  points and knots, whose points and weights are b's (weights NULL for a
 *  polynomial curve). */
void geom__curve_hbuf_result(const geom__curve_hbuf *b, int degree, size_t n,
                             const double *knots, geom_nurbs_curve *out);

/* -------------------------------------------------------- shared helpers */

/** 1 if v[0..n) are all finite, 0 otherwise. */
static inline int geom__curve_finite_n(const double *v, size_t n)
{
    for (size_t i = 0; i < n; ++i)
        if (!isfinite(v[i]))
            return 0;
    return 1;
}

/**
 * Cheap checks done on every evaluation: non-NULL curve and arrays,
 * degree >= 1, n >= degree+1, 1 <= dim <= GEOM_CURVE_MAX_DIM.
 */
geom_status geom__curve_check_cheap(const geom_nurbs_curve *c);

/** The entry check of the operations on a whole curve: NULL c ->
 *  GEOM_ERR_INVALID_ARG "curve: NULL curve", then geom_curve_nurbs_validate. */
geom_status geom__curve_check(const geom_nurbs_curve *c, geom_diag *diag);

/** Validation shared by the knot operations (insert.c): a valid curve
 *  (geom_curve_nurbs_validate) and non-NULL output buffers. */
geom_status geom__curve_check_knot_op(const geom_nurbs_curve *c, const double *knots,
                                     const double *points, const double *weights,
                                     const geom_nurbs_curve *out, geom_diag *diag);

/**
 * Reduce and check an evaluation parameter: NaN/Inf -> GEOM_ERR_INVALID_ARG;
 * outside [u_p, u_n] -> GEOM_ERR_DOMAIN unless GEOM_CURVE_WRAP, which
 * reduces it. On success *u_eval is the parameter and *left whether to use
 * the left limit.
 */
geom_status geom__curve_prepare_param(const geom_nurbs_curve *c, double u, unsigned flags,
                                     double *u_eval, int *left);

/** The same for a bare knot vector (degree p, n control points), then the
 *  knot span of *u_eval (with the left limit where asked) in *span: the
 *  first step of every single-parameter evaluation. */
geom_status geom__curve_locate_knots(int p, size_t n, const double *U, double u, unsigned flags,
                                     double *u_eval, size_t *span);

/**
 * Homogeneous derivatives 0..nd at u in span k: out[j*D + d] (D = hdim).
 * work: geom__bs_ders_work(p) + (nd+1)*(p+1) doubles.
 */
void geom__curve_hderivs(const geom_nurbs_curve *c, size_t k, double u, int nd, double *out,
                        double *work);

/** Doubles of work for geom__curve_span_derivs. */
static inline size_t geom__curve_span_derivs_work(const geom_nurbs_curve *c, int nd)
{
    size_t q = (size_t)c->degree + 1, nd1 = (size_t)nd + 1;
    return nd1 * geom__curve_hdim(c) + nd1 * q + geom__bs_ders_work(c->degree);
}

/**
 * Euclidean point and derivatives 0..nd at u evaluated on span k (u may be
 * either end of the span: this is how one-sided values at a knot are
 * obtained without a span search). ders: (nd+1)*dim doubles; the point is
 * bit-identical to geom_curve_nurbs_eval's on the same span.
 */
void geom__curve_span_derivs(const geom_nurbs_curve *c, size_t k, double u, int nd, double *ders,
                            double *work);

/** Deepest midpoint subdivision of a span in geom_curve_nurbs_polyline. */
#define GEOM__CURVE_PL_MAX_DEPTH 50

/** The arguments and options geom_curve_nurbs_polyline works with: c
 *  validated, count (the caller's output pointer) non-NULL, the options
 *  checked (the same GEOM_ERR_INVALID_ARG messages), the default tolerance
 *  resolved, method GEOM_ERROR_BOUND or GEOM_ERROR_SAMPLED. Shared with the
 *  estimate. */
geom_status geom__curve_polyline_options(const geom_nurbs_curve *c,
                                         const geom_curve_polyline_options *options,
                                         const void *count, geom_curve_polyline_options *opt,
                                         geom_diag *diag);

/** Doubles of work for geom__curve_span_bezier: (p+1)*hdim. */
static inline size_t geom__curve_span_bezier_work(const geom_nurbs_curve *c)
{
    return ((size_t)c->degree + 1) * geom__curve_hdim(c);
}

/**
 * Homogeneous Bezier control points (p+1)*hdim of the polynomial piece on
 * the non-empty span k, by blossoming: b_j = f(u_k^(p-j), u_{k+1}^j), each
 * blossom value from the de Boor recurrence with those arguments. Valid for
 * any knot vector (clamped or not). End points equal the curve's end values
 * at u_k and u_{k+1}.
 */
void geom__curve_span_bezier(const geom_nurbs_curve *c, size_t k, double *out, double *work);

/**
 * de Casteljau split of a homogeneous Bezier segment (p+1 points of D
 * doubles) at t: left and right receive (p+1)*D doubles each (either may
 * alias b; then b is overwritten). work: (p+1)*D doubles.
 */
void geom__curve_hsplit(int p, size_t D, const double *b, double t, double *left, double *right,
                       double *work);

#endif
