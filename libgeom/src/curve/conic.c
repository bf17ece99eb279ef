/* Exact conics as rational quadratic NURBS: arcs, circles and ellipses (The
 * NURBS Book A7.1) and conic arcs through a point or with a weight (A7.2). */
#include "curve/bspline_basis.h"

#define HALF_PI (GEOM_PI / 2.0)

geom_status geom_curve_nurbs_arc_bound(double start, double end, size_t *n, size_t *nknots)
{
    if (!isfinite(start) || !isfinite(end))
        return GEOM_ERR_INVALID_ARG;
    double sweep = fabs(end - start);
    if (!(sweep > 0.0) || sweep > 2.0 * GEOM_PI * (1.0 + 1e-12))
        return GEOM_ERR_DOMAIN;
    double q = ceil(sweep / HALF_PI - 1e-12);
    size_t narcs = q < 1.0 ? 1 : (size_t)q;
    if (narcs > 4)
        narcs = 4;
    if (n)
        *n = 2 * narcs + 1;
    if (nknots)
        *nknots = 2 * narcs + 4;
    return GEOM_OK;
}

/* cos and sin, exact when theta is a multiple of pi/2 as a double. */
static void sincos_exact(double theta, double *c, double *s)
{
    double k = nearbyint(theta / HALF_PI);
    if (fabs(k) < 1e6 && k * HALF_PI == theta) {
        long m = ((long)k % 4 + 4) % 4;
        static const double tc[4] = {1.0, 0.0, -1.0, 0.0}, ts[4] = {0.0, 1.0, 0.0, -1.0};
        *c = tc[m];
        *s = ts[m];
        return;
    }
    *c = cos(theta);
    *s = sin(theta);
}

static double dot(const double *a, const double *b, size_t dim)
{
    double s = 0.0;
    for (size_t d = 0; d < dim; ++d)
        s += a[d] * b[d];
    return s;
}

static geom_status ellipse_arc(size_t dim, const double *C, const double *X, const double *Y,
                               double start, double end, double *knots, double *points,
                               double *weights, geom_nurbs_curve *out, geom_diag *diag)
{
    size_t n, nk;
    geom_status st = geom_curve_nurbs_arc_bound(start, end, &n, &nk);
    if (st != GEOM_OK)
        return geom__diag_set(diag, st, NULL, 0, 0,
                             "curve: arc sweep %.17g is zero, not finite or above 2 pi",
                             end - start);
    /* the axes must span a plane: |X|^2 |Y|^2 - (X.Y)^2 > 0 (relative) */
    double xx = dot(X, X, dim), yy = dot(Y, Y, dim), xy = dot(X, Y, dim);
    if (!(xx * yy - xy * xy > 1e-24 * xx * yy) || !(xx > 0.0) || !(yy > 0.0))
        return geom__diag_set(diag, GEOM_ERR_DEGENERATE, NULL, 0, 0,
                             "curve: ellipse axes are zero or parallel");
    size_t narcs = (n - 1) / 2;
    double dth = (end - start) / (double)narcs;
    double w1 = cos(0.5 * fabs(dth));
    double denom = 1.0 + cos(dth); /* M = C + (E_a - C + E_b - C) / (1 + cos dth) */
    double ca, sa;
    sincos_exact(start, &ca, &sa);
    for (size_t d = 0; d < dim; ++d)
        points[d] = C[d] + ca * X[d] + sa * Y[d];
    weights[0] = 1.0;
    for (size_t i = 1; i <= narcs; ++i) {
        double th = i == narcs ? end : start + (double)i * dth;
        double cb, sb;
        sincos_exact(th, &cb, &sb);
        double *M = points + (2 * i - 1) * dim, *E = points + 2 * i * dim;
        double cm = (ca + cb) / denom, sm = (sa + sb) / denom;
        for (size_t d = 0; d < dim; ++d) {
            M[d] = C[d] + cm * X[d] + sm * Y[d];
            E[d] = C[d] + cb * X[d] + sb * Y[d];
        }
        weights[2 * i - 1] = w1;
        weights[2 * i] = 1.0;
        ca = cb;
        sa = sb;
    }
    size_t k = 0;
    for (int j = 0; j < 3; ++j)
        knots[k++] = 0.0;
    for (size_t i = 1; i < narcs; ++i) {
        double v = (double)i / (double)narcs;
        knots[k++] = v;
        knots[k++] = v;
    }
    for (int j = 0; j < 3; ++j)
        knots[k++] = 1.0;
    out->degree = 2;
    out->n = n;
    out->dim = dim;
    out->knots = knots;
    out->points = points;
    out->weights = weights;
    return GEOM_OK;
}

static geom_status check_arc_args(size_t dim, const double *center, const double *xaxis,
                                  const double *yaxis, const double *knots, const double *points,
                                  const double *weights, const geom_nurbs_curve *out,
                                  geom_diag *diag)
{
    if (dim < 2 || dim > GEOM_CURVE_MAX_DIM || !center || !xaxis || !yaxis || !knots || !points ||
        !weights || !out)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "curve: bad dimension or NULL argument");
    if (!geom__curve_finite_n(center, dim) || !geom__curve_finite_n(xaxis, dim) ||
        !geom__curve_finite_n(yaxis, dim))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "curve: center or axes not finite");
    return GEOM_OK;
}

geom_status geom_curve_nurbs_ellipse_arc(size_t dim, const double *center, const double *xaxis,
                                         const double *yaxis, double start, double end,
                                         double *knots, double *points, double *weights,
                                         geom_nurbs_curve *out, geom_diag *diag)
{
    geom_status st = check_arc_args(dim, center, xaxis, yaxis, knots, points, weights, out, diag);
    if (st != GEOM_OK)
        return st;
    return ellipse_arc(dim, center, xaxis, yaxis, start, end, knots, points, weights, out, diag);
}

static geom_status scaled_axes(size_t dim, const double *xaxis, const double *yaxis, double r,
                               double *X, double *Y, geom_diag *diag)
{
    if (!isfinite(r) || !(r > 0.0))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "curve: radius %g is not positive and finite", r);
    double xx = dot(xaxis, xaxis, dim), yy = dot(yaxis, yaxis, dim), xy = dot(xaxis, yaxis, dim);
    if (fabs(xx - 1.0) > 1e-12 || fabs(yy - 1.0) > 1e-12 || fabs(xy) > 1e-12)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "curve: circle axes are not orthonormal");
    for (size_t d = 0; d < dim; ++d) {
        X[d] = r * xaxis[d];
        Y[d] = r * yaxis[d];
    }
    return GEOM_OK;
}

geom_status geom_curve_nurbs_arc(size_t dim, const double *center, const double *xaxis,
                                 const double *yaxis, double radius, double start, double end,
                                 double *knots, double *points, double *weights,
                                 geom_nurbs_curve *out, geom_diag *diag)
{
    geom_status st = check_arc_args(dim, center, xaxis, yaxis, knots, points, weights, out, diag);
    if (st != GEOM_OK)
        return st;
    double X[GEOM_CURVE_MAX_DIM], Y[GEOM_CURVE_MAX_DIM];
    st = scaled_axes(dim, xaxis, yaxis, radius, X, Y, diag);
    if (st != GEOM_OK)
        return st;
    return ellipse_arc(dim, center, X, Y, start, end, knots, points, weights, out, diag);
}

geom_status geom_curve_nurbs_circle(size_t dim, const double *center, const double *xaxis,
                                    const double *yaxis, double radius, double *knots,
                                    double *points, double *weights, geom_nurbs_curve *out,
                                    geom_diag *diag)
{
    return geom_curve_nurbs_arc(dim, center, xaxis, yaxis, radius, 0.0, 2.0 * GEOM_PI, knots,
                                points, weights, out, diag);
}

/* Closest approach of the lines P + a T and Q + b S: returns 0 and the
 * intersection in X when they meet (within a relative 1e-9), -1 when
 * parallel, -2 when skew. */
static int intersect_lines(size_t dim, const double *P, const double *T, const double *Q,
                           const double *S, double *a_out, double *b_out, double *X)
{
    double tt = dot(T, T, dim), ss = dot(S, S, dim), ts = dot(T, S, dim);
    double r[GEOM_CURVE_MAX_DIM];
    for (size_t d = 0; d < dim; ++d)
        r[d] = Q[d] - P[d];
    double det = tt * ss - ts * ts;
    if (!(det > 1e-24 * tt * ss))
        return -1;
    double rt = dot(r, T, dim), rs = dot(r, S, dim);
    /* a T - b S = r in the least-squares sense */
    double a = (rt * ss - rs * ts) / det;
    double b = (rt * ts - rs * tt) / det;
    double gap = 0.0, scale = sqrt(dot(r, r, dim));
    for (size_t d = 0; d < dim; ++d) {
        double x = P[d] + a * T[d], y = Q[d] + b * S[d];
        X[d] = 0.5 * (x + y);
        gap += (x - y) * (x - y);
        scale = fmax(scale, fmax(fabs(x), fabs(y)));
    }
    if (sqrt(gap) > 1e-9 * scale)
        return -2;
    *a_out = a;
    *b_out = b;
    return 0;
}

geom_status geom_curve_nurbs_conic(size_t dim, const double *p0, const double *t0, const double *p2,
                                   const double *t2, const double *point, double weight,
                                   double *knots, double *points, double *weights,
                                   geom_nurbs_curve *out, geom_diag *diag)
{
    if (dim < 2 || dim > GEOM_CURVE_MAX_DIM || !p0 || !t0 || !p2 || !t2 || !knots || !points ||
        !weights || !out)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "curve: bad dimension or NULL argument");
    if (!geom__curve_finite_n(p0, dim) || !geom__curve_finite_n(t0, dim) ||
        !geom__curve_finite_n(p2, dim) || !geom__curve_finite_n(t2, dim) ||
        (point && !geom__curve_finite_n(point, dim)) || (!point && !isfinite(weight)))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "curve: conic input not finite");
    double P1[GEOM_CURVE_MAX_DIM], a, b;
    int rc = intersect_lines(dim, p0, t0, p2, t2, &a, &b, P1);
    if (rc == -1)
        return geom__diag_set(diag, GEOM_ERR_DEGENERATE, NULL, 0, 0,
                             "curve: conic tangents are parallel or zero (split the arc)");
    if (rc == -2)
        return geom__diag_set(diag, GEOM_ERR_DEGENERATE, NULL, 0, 0,
                             "curve: conic tangent lines do not meet");
    double w1 = weight;
    if (point) {
        /* A7.2: the line P1 -> point meets the chord P0 P2 at alf2 */
        const double *P = point;
        double V1[GEOM_CURVE_MAX_DIM], V02[GEOM_CURVE_MAX_DIM], X[GEOM_CURVE_MAX_DIM];
        for (size_t d = 0; d < dim; ++d) {
            V1[d] = P[d] - P1[d];
            V02[d] = p2[d] - p0[d];
        }
        double alf0, alf2;
        if (intersect_lines(dim, P1, V1, p0, V02, &alf0, &alf2, X) != 0)
            return geom__diag_set(diag, GEOM_ERR_DOMAIN, NULL, 0, 0,
                                 "curve: the point cannot lie on a conic arc with these "
                                 "ends and tangents");
        if (!(alf2 > 0.0 && alf2 < 1.0))
            return geom__diag_set(diag, GEOM_ERR_DOMAIN, NULL, 0, 0,
                                 "curve: the point is outside the control triangle");
        double q = sqrt(alf2 / (1.0 - alf2));
        double u = q / (1.0 + q);
        double a0[GEOM_CURVE_MAX_DIM], a2[GEOM_CURVE_MAX_DIM], a1[GEOM_CURVE_MAX_DIM];
        for (size_t d = 0; d < dim; ++d) {
            a0[d] = P[d] - p0[d];
            a2[d] = P[d] - p2[d];
            a1[d] = P1[d] - P[d];
        }
        double num = (1.0 - u) * (1.0 - u) * dot(a0, a1, dim) + u * u * dot(a2, a1, dim);
        double den = 2.0 * u * (1.0 - u) * dot(a1, a1, dim);
        if (!(den > 0.0))
            return geom__diag_set(diag, GEOM_ERR_DOMAIN, NULL, 0, 0,
                                 "curve: the point coincides with the middle control point");
        w1 = num / den;
    }
    if (!(w1 > 0.0) || !isfinite(w1))
        return geom__diag_set(diag, GEOM_ERR_DOMAIN, NULL, 0, 0,
                             "curve: conic weight %.17g is not positive", w1);
    (void)a;
    (void)b;
    memcpy(points, p0, dim * sizeof(double));
    memcpy(points + dim, P1, dim * sizeof(double));
    memcpy(points + 2 * dim, p2, dim * sizeof(double));
    weights[0] = 1.0;
    weights[1] = w1;
    weights[2] = 1.0;
    for (int i = 0; i < 3; ++i) {
        knots[i] = 0.0;
        knots[3 + i] = 1.0;
    }
    out->degree = 2;
    out->n = 3;
    out->dim = dim;
    out->knots = knots;
    out->points = points;
    out->weights = weights;
    return GEOM_OK;
}
