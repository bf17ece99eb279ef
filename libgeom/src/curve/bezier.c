/* Bezier curves: de Casteljau evaluation, hodograph derivatives, split,
 * degree elevation and bounding boxes. */
#include "curve/bspline_basis.h"

static int bad_bezier(int degree, size_t dim, const double *ctrl)
{
    return degree < 0 || dim < 1 || dim > GEOM_CURVE_MAX_DIM || !ctrl;
}

/* de Casteljau on q points of dim doubles in work (destroyed). */
static void casteljau(size_t q, size_t dim, double *work, double t, double *out)
{
    double s = 1.0 - t;
    for (size_t r = 1; r < q; ++r)
        for (size_t i = 0; i + r < q; ++i)
            for (size_t d = 0; d < dim; ++d)
                work[i * dim + d] = s * work[i * dim + d] + t * work[(i + 1) * dim + d];
    memcpy(out, work, dim * sizeof(double));
}

geom_status geom_curve_bezier_eval(int degree, size_t dim, const double *ctrl, double t,
                                   double *out)
{
    if (bad_bezier(degree, dim, ctrl) || !out || !isfinite(t))
        return GEOM_ERR_INVALID_ARG;
    size_t q = (size_t)degree + 1;
    geom__scratch s;
    geom_status st = geom__scratch_init(&s, q * dim);
    if (st == GEOM_OK) {
        memcpy(s.mem, ctrl, q * dim * sizeof(double));
        casteljau(q, dim, s.mem, t, out);
    }
    geom__scratch_free(&s);
    return st;
}

geom_status geom_curve_bezier_derivs(int degree, size_t dim, const double *ctrl, double t,
                                     int nderiv, double *ders)
{
    if (bad_bezier(degree, dim, ctrl) || !ders || !isfinite(t) || nderiv < 0)
        return GEOM_ERR_INVALID_ARG;
    size_t q = (size_t)degree + 1;
    geom__scratch s;
    geom_status st = geom__scratch_init(&s, q * dim);
    if (st != GEOM_OK) {
        geom__scratch_free(&s);
        return st;
    }
    double *w = s.mem;
    double factor = 1.0; /* p!/(p-k)! */
    for (int k = 0; k <= nderiv; ++k) {
        double *out = ders + (size_t)k * dim;
        if (k > degree) {
            for (size_t d = 0; d < dim; ++d)
                out[d] = 0.0;
            continue;
        }
        if (k > 0)
            factor *= (double)(degree - k + 1);
        memcpy(w, ctrl, q * dim * sizeof(double));
        /* k forward differences: Delta^k P_i, i = 0..p-k */
        for (int r = 1; r <= k; ++r)
            for (size_t i = 0; i + (size_t)r < q; ++i)
                for (size_t d = 0; d < dim; ++d)
                    w[i * dim + d] = w[(i + 1) * dim + d] - w[i * dim + d];
        casteljau(q - (size_t)k, dim, w, t, out);
        for (size_t d = 0; d < dim; ++d)
            out[d] *= factor;
    }
    geom__scratch_free(&s);
    return GEOM_OK;
}

geom_status geom_curve_bezier_split(int degree, size_t dim, const double *ctrl, double t,
                                    double *left, double *right)
{
    if (bad_bezier(degree, dim, ctrl) || !isfinite(t))
        return GEOM_ERR_INVALID_ARG;
    if (!(t >= 0.0 && t <= 1.0))
        return GEOM_ERR_DOMAIN;
    size_t q = (size_t)degree + 1;
    geom__scratch s;
    geom_status st = geom__scratch_init(&s, q * dim);
    if (st == GEOM_OK)
        geom__curve_hsplit(degree, dim, ctrl, t, left, right, s.mem);
    geom__scratch_free(&s);
    return st;
}

geom_status geom_curve_bezier_elevate(int degree, size_t dim, const double *ctrl, int times,
                                      double *out)
{
    if (bad_bezier(degree, dim, ctrl) || !out || times < 0)
        return GEOM_ERR_INVALID_ARG;
    size_t q = (size_t)degree + 1;
    memcpy(out, ctrl, q * dim * sizeof(double));
    for (int e = 0; e < times; ++e) {
        size_t d = (size_t)degree + (size_t)e; /* current degree */
        double den = (double)(d + 1);
        memcpy(out + (d + 1) * dim, out + d * dim, dim * sizeof(double));
        for (size_t i = d; i >= 1; --i) {
            double a = (double)i / den, b = (double)(d + 1 - i) / den;
            for (size_t k = 0; k < dim; ++k)
                out[i * dim + k] = a * out[(i - 1) * dim + k] + b * out[i * dim + k];
        }
    }
    return GEOM_OK;
}

geom_status geom_curve_bezier_bbox(int degree, size_t dim, const double *ctrl, double *min,
                                   double *max)
{
    if (bad_bezier(degree, dim, ctrl) || !min || !max)
        return GEOM_ERR_INVALID_ARG;
    for (size_t d = 0; d < dim; ++d) {
        min[d] = INFINITY;
        max[d] = -INFINITY;
    }
    for (size_t i = 0; i <= (size_t)degree; ++i)
        for (size_t d = 0; d < dim; ++d) {
            double v = ctrl[i * dim + d];
            if (!isfinite(v))
                return GEOM_ERR_INVALID_ARG;
            min[d] = fmin(min[d], v);
            max[d] = fmax(max[d], v);
        }
    return GEOM_OK;
}

#define BBOX_DEPTH 64

/* Minimum over [0, 1] of the 1D Bernstein polynomial c[0..p], enclosed from
 * below: see geom_curve_bezier_bbox_tight. work: (BBOX_DEPTH + 3) * (p+1). */
static double bernstein_min(int p, const double *c, double tol, double *work)
{
    size_t q = (size_t)p + 1;
    double *cur = work, *split = work + q, *stack = work + 2 * q;
    int depth[BBOX_DEPTH + 1];
    int top = 0;
    memcpy(cur, c, q * sizeof(double));
    int cur_depth = 0;
    double best = fmin(c[0], c[p]);
    double result = best;
    for (;;) {
        double lb = INFINITY;
        for (size_t i = 0; i < q; ++i)
            lb = fmin(lb, cur[i]);
        best = fmin(best, fmin(cur[0], cur[p]));
        int done = 0;
        if (lb >= best) {
            done = 1; /* nothing below the best value in here */
        } else if (lb >= best - tol || cur_depth >= BBOX_DEPTH || top >= BBOX_DEPTH) {
            result = fmin(result, lb);
            done = 1;
        }
        if (!done) {
            /* left half into cur, right half onto the stack */
            geom__curve_hsplit(p, 1, cur, 0.5, cur, stack + (size_t)top * q, split);
            depth[top++] = cur_depth + 1;
            ++cur_depth;
            continue;
        }
        if (top == 0)
            break;
        --top;
        memcpy(cur, stack + (size_t)top * q, q * sizeof(double));
        cur_depth = depth[top];
    }
    return fmin(result, best);
}

geom_status geom_curve_bezier_bbox_tight(int degree, size_t dim, const double *ctrl, double *min,
                                         double *max)
{
    geom_status st = geom_curve_bezier_bbox(degree, dim, ctrl, min, max);
    if (st != GEOM_OK)
        return st;
    size_t q = (size_t)degree + 1;
    geom__scratch s;
    st = geom__scratch_init(&s, (BBOX_DEPTH + 4) * q);
    if (st != GEOM_OK) {
        geom__scratch_free(&s);
        return st;
    }
    double *coef = s.mem, *work = s.mem + q;
    for (size_t d = 0; d < dim; ++d) {
        double extent = max[d] - min[d];
        double tol = 1e-15 * extent;
        for (size_t i = 0; i < q; ++i)
            coef[i] = ctrl[i * dim + d];
        double lo = bernstein_min(degree, coef, tol, work);
        for (size_t i = 0; i < q; ++i)
            coef[i] = -ctrl[i * dim + d];
        double hi = -bernstein_min(degree, coef, tol, work);
        min[d] = lo;
        max[d] = hi;
    }
    geom__scratch_free(&s);
    return GEOM_OK;
}
