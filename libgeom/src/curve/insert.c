/* Knot insertion (The NURBS Book A5.1). */
#include "curve/bspline_basis.h"

/* Checks shared by the knot operations: a valid curve, output buffers. */
geom_status geom__curve_check_knot_op(const geom_nurbs_curve *c, const double *knots,
                                     const double *points, const double *weights,
                                     const geom_nurbs_curve *out, geom_diag *diag)
{
    geom_status st = geom__curve_check(c, diag);
    if (st != GEOM_OK)
        return st;
    if (!knots || !points || !out || (c->weights && !weights))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "curve: NULL output buffer");
    return GEOM_OK;
}

geom_status geom_curve_nurbs_insert_knot(const geom_nurbs_curve *c, double u, size_t times,
                                         double *knots, double *points, double *weights,
                                         geom_nurbs_curve *out, geom_diag *diag)
{
    geom_status st = geom__curve_check_knot_op(c, knots, points, weights, out, diag);
    if (st != GEOM_OK)
        return st;
    if (!isfinite(u))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "curve: knot to insert is not finite");
    const double *U = c->knots;
    size_t p = (size_t)c->degree, n = c->n, m = n + p + 1;
    if (!(u >= U[p] && u < U[n]))
        return geom__diag_set(diag, GEOM_ERR_DOMAIN, NULL, 0, 0,
                             "curve: knot %.17g is outside [%.17g, %.17g)", u, U[p], U[n]);
    size_t k = geom__bs_span(c->degree, n, U, u, 0);
    size_t s = 0;
    for (size_t i = k + 1; i-- > 0 && U[i] == u;)
        ++s;
    if (times > 0 && (times > p || s + times > p))
        return geom__diag_set(diag, GEOM_ERR_DOMAIN, NULL, 0, 0,
                             "curve: inserting %.17g %zu times would give multiplicity %zu > "
                             "degree %zu",
                             u, times, s + times, p);
    size_t r = times, D = geom__curve_hdim(c);
    geom__curve_hbuf hb = {points, c->weights ? weights : NULL, c->dim};
    if (r == 0) { /* a copy (s may be p+1 here, e.g. at a clamped end) */
        memcpy(knots, U, m * sizeof(double));
        memcpy(points, c->points, n * c->dim * sizeof(double));
        if (c->weights)
            memcpy(weights, c->weights, n * sizeof(double));
        *out = *c;
        out->knots = knots;
        out->points = points;
        out->weights = hb.w;
        return GEOM_OK;
    }

    for (size_t i = 0; i <= k; ++i)
        knots[i] = U[i];
    for (size_t i = 1; i <= r; ++i)
        knots[k + i] = u;
    for (size_t i = k + 1; i < m; ++i)
        knots[i + r] = U[i];

    double h[GEOM_CURVE_HDIM_MAX];
    for (size_t i = 0; i <= k - p; ++i) {
        geom__curve_hget(c, i, h);
        geom__curve_hbuf_set(&hb, i, h);
    }
    for (size_t i = k - s; i < n; ++i) {
        geom__curve_hget(c, i, h);
        geom__curve_hbuf_set(&hb, i + r, h);
    }
    if (r > 0) {
        geom__scratch sc;
        st = geom__scratch_init(&sc, (p + 1) * D);
        if (st != GEOM_OK) {
            geom__scratch_free(&sc);
            return geom__diag_set(diag, st, NULL, 0, 0, "curve: out of memory");
        }
        double *R = sc.mem;
        for (size_t i = 0; i <= p - s; ++i)
            geom__curve_hget(c, k - p + i, R + i * D);
        size_t L = 0;
        for (size_t j = 1; j <= r; ++j) {
            L = k - p + j;
            for (size_t i = 0; i + j + s <= p; ++i) {
                double alpha = (u - U[L + i]) / (U[i + k + 1] - U[L + i]);
                geom__curve_hcomb(D, R + i * D, alpha, R + (i + 1) * D, 1.0 - alpha, R + i * D);
            }
            geom__curve_hbuf_set(&hb, L, R);
            geom__curve_hbuf_set(&hb, k + r - j - s, R + (p - j - s) * D);
        }
        for (size_t i = L + 1; i < k - s; ++i)
            geom__curve_hbuf_set(&hb, i, R + (i - L) * D);
        geom__scratch_free(&sc);
    }
    geom__curve_hbuf_result(&hb, c->degree, n + r, knots, out);
    return GEOM_OK;
}
