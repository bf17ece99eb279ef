/* The vertex count of geom_curve_nurbs_polyline before the work, from each
 * span's Bezier control points: a bound for polynomial curves. */
#include "curve/bspline_basis.h"

#include <float.h>

/* |v| for v = (a - 2b + c) / 4 (dim doubles each), without overflow. */
static double quarter_second_difference(size_t dim, const double *a, const double *b,
                                        const double *c)
{
    double v[GEOM_CURVE_MAX_DIM], zero[GEOM_CURVE_MAX_DIM] = {0};
    for (size_t d = 0; d < dim; ++d)
        v[d] = (0.25 * a[d] - 0.5 * b[d]) + 0.25 * c[d];
    return geom_curve_segment_distance(dim, zero, zero, v);
}

geom_status geom_curve_nurbs_polyline_estimate(const geom_nurbs_curve *c,
                                               const geom_curve_polyline_options *options,
                                               double *count, int *is_bound, geom_diag *diag)
{
    geom_curve_polyline_options opt;
    geom_status st = geom__curve_polyline_options(c, options, count, &opt, diag);
    if (st != GEOM_OK)
        return st;
    size_t dim = c->dim, p = (size_t)c->degree, D = geom__curve_hdim(c);
    /* A piece whose control polygon has second differences of norm at most
     * M deviates from its chord by at most K M, K = floor(p/2) ceil(p/2) / 2
     * (the discrete Green's function of the second difference); halving a
     * piece's parameter interval scales its second differences by 1/4 or
     * less (they are convex combinations of the span's, times h^2). */
    double K = (double)(p / 2) * (double)((p + 1) / 2) / 2.0;
    geom__scratch sc;
    st = geom__scratch_init(&sc, 2 * (p + 1) * D + (p + 1) * dim);
    if (st != GEOM_OK) {
        geom__scratch_free(&sc);
        return geom__diag_set(diag, st, NULL, 0, 0, "curve: out of memory");
    }
    double *bez = sc.mem, *work = sc.mem + (p + 1) * D, *E = work + (p + 1) * D;
    double total = 0.0;
    int nonfinite = 0;
    for (size_t k = p; k < c->n; ++k) {
        if (!(c->knots[k] < c->knots[k + 1]))
            continue;
        geom__curve_span_bezier(c, k, bez, work);
        double R = 0.0; /* largest coordinate, for the rounding allowance */
        double wmin = INFINITY, wmax = 0.0;
        for (size_t i = 0; i <= p; ++i) {
            double w = D > dim ? bez[i * D + dim] : 1.0;
            wmin = fmin(wmin, fabs(w));
            wmax = fmax(wmax, fabs(w));
            for (size_t d = 0; d < dim; ++d) {
                E[i * dim + d] = bez[i * D + d] / w;
                R = fmax(R, fabs(E[i * dim + d]));
            }
        }
        double M = 0.0;
        for (size_t i = 0; i + 2 <= p; ++i)
            M = fmax(M, quarter_second_difference(dim, E + i * dim, E + (i + 1) * dim,
                                                  E + (i + 2) * dim));
        if (isnan(M) || isnan(R) || !(wmin > 0.0)) {
            nonfinite = 1;
            break;
        }
        /* rational: the weights' spread scales the projected differences
         * (an estimate, not a bound) */
        double spread = D > dim ? wmax / wmin : 1.0;
        /* floating-point subdivision and distances err by a few ulp of the
         * coordinates: keep that much of the tolerance in reserve */
        double tol = opt.tolerance - 8.0 * (double)(p + 2) * DBL_EPSILON * R;
        int depth;
        if (M == 0.0 || K == 0.0)
            depth = 0;
        else if (!(tol > 0.0))
            depth = GEOM__CURVE_PL_MAX_DEPTH;
        else {
            /* smallest depth with 4^-depth * 4 M K spread <= tol, in logs */
            double l = 0.5 * (log2(M) + 2.0 + log2(K) + log2(spread) - log2(tol));
            depth = l <= 0.0 ? 0 : l >= GEOM__CURVE_PL_MAX_DEPTH ? GEOM__CURVE_PL_MAX_DEPTH
                                                                 : (int)ceil(l);
        }
        total += 1.0 + ldexp(1.0, depth);
    }
    geom__scratch_free(&sc);
    if (nonfinite) {
        *count = 0.0;
        return geom__diag_set(diag, GEOM_ERR_DOMAIN, NULL, 0, 0,
                              "curve: the control points' differences are not numbers "
                              "(points beyond the range of double)");
    }
    *count = total;
    if (is_bound)
        *is_bound = c->weights == NULL;
    return GEOM_OK;
}
