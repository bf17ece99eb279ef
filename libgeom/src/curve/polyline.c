/* Adaptive polylines to a chordal tolerance: each span's Bezier segment is
 * subdivided until every piece is within the tolerance of its chord. */
#include "curve/bspline_basis.h"


double geom_curve_segment_distance(size_t dim, const double *a, const double *b, const double *q)
{
    /* Differences halved (never overflow), then scaled to at most 1 before
     * squaring: exact powers of two, so nothing is lost but the range. */
    double e[GEOM_CURVE_MAX_DIM], x[GEOM_CURVE_MAX_DIM], scale = 0.0;
    if (dim == 0 || dim > GEOM_CURVE_MAX_DIM)
        return NAN;
    for (size_t d = 0; d < dim; ++d) {
        e[d] = 0.5 * b[d] - 0.5 * a[d];
        x[d] = 0.5 * q[d] - 0.5 * a[d];
        if (isnan(e[d]) || isnan(x[d]))
            return NAN;
        scale = fmax(scale, fmax(fabs(e[d]), fabs(x[d])));
    }
    if (scale == 0.0)
        return 0.0;
    if (!isfinite(scale))
        return INFINITY;
    int ex;
    frexp(scale, &ex);
    double ab2 = 0.0, t = 0.0;
    for (size_t d = 0; d < dim; ++d) {
        e[d] = ldexp(e[d], -ex);
        x[d] = ldexp(x[d], -ex);
        ab2 += e[d] * e[d];
        t += x[d] * e[d];
    }
    t = ab2 > 0.0 ? fmin(fmax(t / ab2, 0.0), 1.0) : 0.0;
    double s = 0.0;
    for (size_t d = 0; d < dim; ++d) {
        double r = x[d] - t * e[d];
        s += r * r;
    }
    return 2.0 * ldexp(sqrt(s), ex);
}

static double seg_dist(const double *X, const double *A, const double *Bp, size_t dim)
{
    return geom_curve_segment_distance(dim, A, Bp, X);
}

typedef struct pl_ctx {
    size_t dim, D, q1;
    double *params, *points;
    size_t capacity, count, max_points;
    double max_err, sum_err;
    size_t segs, evals;
    int method;
    double tol;
    int overflow, nonfinite;
    double last[GEOM_CURVE_MAX_DIM];
} pl_ctx;

static void to_euclid(const pl_ctx *x, const double *h, double *out)
{
    double w = x->D > x->dim ? h[x->dim] : 1.0;
    for (size_t d = 0; d < x->dim; ++d)
        out[d] = h[d] / w;
}

static void emit(pl_ctx *x, double u, const double *pt)
{
    if (x->count >= x->max_points) {
        x->overflow = 1;
        return;
    }
    if (x->points && x->count < x->capacity) {
        memcpy(x->points + x->count * x->dim, pt, x->dim * sizeof(double));
        if (x->params)
            x->params[x->count] = u;
    } else if (!x->points && x->params && x->count < x->capacity) {
        x->params[x->count] = u;
    }
    memcpy(x->last, pt, x->dim * sizeof(double));
    ++x->count;
}

/* Deviation of the homogeneous Bezier piece b from its chord. */
static double deviation(pl_ctx *x, const double *b, double *work)
{
    size_t dim = x->dim, D = x->D, p = x->q1 - 1;
    double A[GEOM_CURVE_MAX_DIM], Bp[GEOM_CURVE_MAX_DIM], X[GEOM_CURVE_MAX_DIM];
    to_euclid(x, b, A);
    to_euclid(x, b + p * D, Bp);
    double e = 0.0;
    if (x->method == GEOM_ERROR_SAMPLED) {
        for (int j = 1; j <= 7; ++j) {
            double t = (double)j / 8.0, s = 1.0 - t;
            memcpy(work, b, x->q1 * D * sizeof(double));
            for (size_t r = 1; r <= p; ++r)
                for (size_t i = 0; i + r <= p; ++i)
                    geom__curve_hcomb(D, work + i * D, s, work + i * D, t, work + (i + 1) * D);
            to_euclid(x, work, X);
            e = fmax(e, seg_dist(X, A, Bp, dim));
            ++x->evals;
        }
    } else {
        for (size_t i = 1; i < p; ++i) {
            to_euclid(x, b + i * D, X);
            e = fmax(e, seg_dist(X, A, Bp, dim));
        }
    }
    return e;
}

typedef struct pl_piece {
    double a, b;
    int depth;
} pl_piece;

static void span_polyline(pl_ctx *x, double *stack, pl_piece *info, double *work, double a,
                          double bnd)
{
    size_t P = x->q1 * x->D;
    info[0].a = a;
    info[0].b = bnd;
    info[0].depth = 0;
    int top = 1;
    while (top > 0 && !x->overflow) {
        --top;
        double *b = stack + (size_t)top * P;
        pl_piece pc = info[top];
        double e = deviation(x, b, work);
        if (isnan(e)) { /* points beyond the range of double: no silent 0 */
            x->nonfinite = 1;
            return;
        }
        double m = 0.5 * (pc.a + pc.b);
        if (e <= x->tol || pc.depth >= GEOM__CURVE_PL_MAX_DEPTH || !(m > pc.a && m < pc.b) ||
            top + 2 > GEOM__CURVE_PL_MAX_DEPTH + 2) {
            double E[GEOM_CURVE_MAX_DIM];
            to_euclid(x, b + (x->q1 - 1) * x->D, E);
            emit(x, pc.b, E);
            x->max_err = fmax(x->max_err, e);
            x->sum_err += e;
            ++x->segs;
            continue;
        }
        double *right = stack + (size_t)(top + 1) * P;
        geom__curve_hsplit((int)(x->q1 - 1), x->D, b, 0.5, b, right, work);
        ++x->evals;
        /* left half on top of the stack */
        memcpy(work, b, P * sizeof(double));
        memcpy(b, right, P * sizeof(double));
        memcpy(right, work, P * sizeof(double));
        info[top].a = m;
        info[top].b = pc.b;
        info[top].depth = pc.depth + 1;
        info[top + 1].a = pc.a;
        info[top + 1].b = m;
        info[top + 1].depth = pc.depth + 1;
        top += 2;
    }
}

geom_status geom__curve_polyline_options(const geom_nurbs_curve *c,
                                         const geom_curve_polyline_options *options,
                                         const void *count, geom_curve_polyline_options *opt,
                                         geom_diag *diag)
{
    geom_status st = geom__curve_check(c, diag);
    if (st != GEOM_OK)
        return st;
    if (!count)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "curve: NULL count");
    geom_curve_polyline_options o = {0.0, 0, 0};
    if (options)
        o = *options;
    if (!isfinite(o.tolerance) || o.tolerance < 0.0 ||
        (o.method != 0 && o.method != GEOM_ERROR_BOUND && o.method != GEOM_ERROR_SAMPLED))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "curve: bad polyline options");
    size_t dim = c->dim;
    if (o.tolerance == 0.0) {
        /* 1e-3 of the control box's diagonal, without overflow */
        double lo[GEOM_CURVE_MAX_DIM], hi[GEOM_CURVE_MAX_DIM], zero[GEOM_CURVE_MAX_DIM] = {0};
        for (size_t d = 0; d < dim; ++d) {
            lo[d] = INFINITY;
            hi[d] = -INFINITY;
            for (size_t i = 0; i < c->n; ++i) {
                lo[d] = fmin(lo[d], c->points[i * dim + d]);
                hi[d] = fmax(hi[d], c->points[i * dim + d]);
            }
            hi[d] = 0.5 * hi[d] - 0.5 * lo[d]; /* half the extent */
        }
        o.tolerance = 2e-3 * geom_curve_segment_distance(dim, zero, zero, hi);
        if (!(o.tolerance > 0.0))
            o.tolerance = 1e-300; /* all control points coincide */
    }
    o.method = o.method == GEOM_ERROR_SAMPLED ? GEOM_ERROR_SAMPLED : GEOM_ERROR_BOUND;
    *opt = o;
    return GEOM_OK;
}

geom_status geom_curve_nurbs_polyline(const geom_nurbs_curve *c,
                                      const geom_curve_polyline_options *options, double *params,
                                      double *points, size_t capacity, size_t *count,
                                      geom_error_report *report, geom_diag *diag)
{
    geom_curve_polyline_options opt;
    geom_status st = geom__curve_polyline_options(c, options, count, &opt, diag);
    if (st != GEOM_OK)
        return st;
    size_t dim = c->dim, p = (size_t)c->degree;
    pl_ctx x;
    memset(&x, 0, sizeof x);
    x.dim = dim;
    x.D = geom__curve_hdim(c);
    x.q1 = p + 1;
    x.params = params;
    x.points = points;
    x.capacity = capacity;
    x.max_points = opt.max_points ? opt.max_points : ((size_t)1 << 20);
    x.method = opt.method;
    x.tol = opt.tolerance;
    size_t P = x.q1 * x.D, nstack = GEOM__CURVE_PL_MAX_DEPTH + 4;
    geom__scratch sc;
    st = geom__scratch_init(&sc, nstack * P + P + geom__curve_span_bezier_work(c));
    if (st != GEOM_OK) {
        geom__scratch_free(&sc);
        return geom__diag_set(diag, st, NULL, 0, 0, "curve: out of memory");
    }
    pl_piece info[GEOM__CURVE_PL_MAX_DEPTH + 4];
    double *stack = sc.mem, *work = sc.mem + nstack * P;
    int first = 1;
    for (size_t k = p; k < c->n && !x.overflow; ++k) {
        if (!(c->knots[k] < c->knots[k + 1]))
            continue;
        geom__curve_span_bezier(c, k, stack, work);
        double S[GEOM_CURVE_MAX_DIM];
        to_euclid(&x, stack, S);
        int differs = first;
        for (size_t d = 0; d < dim && !differs; ++d)
            differs = S[d] != x.last[d];
        if (differs) /* the first point, or the far side of a jump */
            emit(&x, c->knots[k], S);
        first = 0;
        span_polyline(&x, stack, info, work, c->knots[k], c->knots[k + 1]);
    }
    geom__scratch_free(&sc);
    if (report) {
        report->max_error = x.max_err;
        report->mean_error = x.segs ? x.sum_err / (double)x.segs : 0.0;
        report->method = x.method;
        report->evaluations = x.evals;
    }
    if (x.nonfinite) {
        *count = 0;
        return geom__diag_set(diag, GEOM_ERR_DOMAIN, NULL, 0, 0,
                             "curve: the deviation from a chord is not a number (points beyond "
                             "the range of double)");
    }
    if (x.overflow) {
        *count = 0;
        return geom__diag_set(diag, GEOM_ERR_LIMIT, NULL, 0, 0,
                             "curve: the polyline needs more than %zu points", x.max_points);
    }
    *count = x.count;
    if ((points || params) && x.count > capacity)
        return geom__diag_set(diag, GEOM_ERR_LIMIT, NULL, 0, 0,
                             "curve: the polyline needs %zu points, capacity is %zu", x.count,
                             capacity);
    return GEOM_OK;
}
