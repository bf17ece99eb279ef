/* Bezier decomposition (The NURBS Book A5.6), per-span Bezier extraction by
 * blossoming, and homogeneous de Casteljau subdivision. */
#include "curve/bspline_basis.h"

geom_status geom_curve_nurbs_segments(const geom_nurbs_curve *c, size_t *nseg)
{
    if (geom__curve_check_cheap(c) != GEOM_OK || !nseg)
        return GEOM_ERR_INVALID_ARG;
    size_t p = (size_t)c->degree, s = 0;
    for (size_t k = p; k < c->n; ++k)
        s += c->knots[k] < c->knots[k + 1];
    *nseg = s;
    return GEOM_OK;
}

void geom__curve_span_bezier(const geom_nurbs_curve *c, size_t k, double *out, double *work)
{
    int p = c->degree;
    size_t D = geom__curve_hdim(c);
    const double *U = c->knots;
    double a = U[k], b = U[k + 1];
    /* b_j = f(b^j, a^(p-j)): de Boor's recurrence with argument b at the
     * first j levels and a at the others (the blossom is symmetric, so the
     * order does not matter; exact knots give alpha exactly 0 or 1). */
    for (int j = 0; j <= p; ++j) {
        for (int i = 0; i <= p; ++i)
            geom__curve_hget(c, k - (size_t)p + (size_t)i, work + (size_t)i * D);
        /* de Boor levels: first j levels at b, then p-j at a */
        for (int r = 1; r <= p; ++r) {
            double x = r <= j ? b : a;
            for (int jj = p; jj >= r; --jj) {
                size_t i = k - (size_t)p + (size_t)jj;
                double den = U[i + (size_t)(p + 1 - r)] - U[i];
                double alpha = (x - U[i]) / den;
                geom__curve_hcomb(D, work + (size_t)jj * D, 1.0 - alpha, work + (size_t)(jj - 1) * D,
                                 alpha, work + (size_t)jj * D);
            }
        }
        memcpy(out + (size_t)j * D, work + (size_t)p * D, D * sizeof(double));
    }
}

void geom__curve_hsplit(int p, size_t D, const double *b, double t, double *left, double *right,
                       double *work)
{
    size_t q = (size_t)p + 1;
    memcpy(work, b, q * D * sizeof(double)); /* b may alias left or right */
    double s = 1.0 - t;
    if (left)
        memcpy(left, work, D * sizeof(double));
    if (right)
        memcpy(right + (size_t)p * D, work + (size_t)p * D, D * sizeof(double));
    /* after level r, work[0] is left[r] and work[p-r] is right[p-r] */
    for (int r = 1; r <= p; ++r) {
        for (int i = 0; i <= p - r; ++i)
            geom__curve_hcomb(D, work + (size_t)i * D, s, work + (size_t)i * D, t,
                             work + (size_t)(i + 1) * D);
        if (left)
            memcpy(left + (size_t)r * D, work, D * sizeof(double));
        if (right)
            memcpy(right + (size_t)(p - r) * D, work + (size_t)(p - r) * D, D * sizeof(double));
    }
}

geom_status geom_curve_nurbs_decompose(const geom_nurbs_curve *c, double *bezier_points,
                                       double *bezier_weights, double *breaks, geom_diag *diag)
{
    geom_status st = geom__curve_check(c, diag);
    if (st != GEOM_OK)
        return st;
    if (!bezier_points || (c->weights && !bezier_weights))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "curve: NULL output buffer");
    size_t p = (size_t)c->degree, n = c->n, D = geom__curve_hdim(c), q = p + 1;
    const double *U = c->knots;
    geom__curve_hbuf hb = {bezier_points, c->weights ? bezier_weights : NULL, c->dim};
    size_t nseg = 0;
    geom_curve_nurbs_segments(c, &nseg);
    if (breaks) {
        size_t s = 0;
        breaks[s++] = U[p];
        for (size_t k = p; k < n; ++k)
            if (U[k] < U[k + 1])
                breaks[s++] = U[k + 1];
    }
    int clamped = U[0] == U[p] && U[n] == U[n + p];
    geom__scratch sc;
    st = geom__scratch_init(&sc, 2 * q * D + q);
    if (st != GEOM_OK) {
        geom__scratch_free(&sc);
        return geom__diag_set(diag, st, NULL, 0, 0, "curve: out of memory");
    }
    if (!clamped) {
        double *seg = sc.mem, *work = sc.mem + q * D;
        size_t s = 0;
        for (size_t k = p; k < n; ++k) {
            if (!(U[k] < U[k + 1]))
                continue;
            geom__curve_span_bezier(c, k, seg, work);
            for (size_t j = 0; j < q; ++j)
                geom__curve_hbuf_set(&hb, s * q + j, seg + j * D);
            ++s;
        }
        geom__curve_hbuf_finish(&hb, nseg * q);
        geom__scratch_free(&sc);
        return GEOM_OK;
    }
    /* A5.6 on a clamped curve; segment nb's point i is hbuf index nb*q + i. */
    double *alphas = sc.mem;
    double h[GEOM_CURVE_HDIM_MAX], g[GEOM_CURVE_HDIM_MAX];
    long P = (long)p, m = (long)(n + p); /* last knot index */
    long a = P, b = P + 1;
    size_t nb = 0;
    for (size_t i = 0; i <= p; ++i) {
        geom__curve_hget(c, i, h);
        geom__curve_hbuf_set(&hb, i, h);
    }
    while (b < m) {
        long i = b;
        while (b < m && U[b + 1] == U[b])
            ++b;
        long mult = b - i + 1;
        if (mult < P) {
            double numer = U[b] - U[a];
            for (long j = P; j > mult; --j)
                alphas[j - mult - 1] = numer / (U[a + j] - U[a]);
            long r = P - mult;
            for (long j = 1; j <= r; ++j) {
                long save = r - j, s = mult + j;
                for (long k = P; k >= s; --k) {
                    double alpha = alphas[k - s];
                    geom__curve_hbuf_get(&hb, nb * q + (size_t)k, h);
                    geom__curve_hbuf_get(&hb, nb * q + (size_t)(k - 1), g);
                    geom__curve_hcomb(D, h, alpha, h, 1.0 - alpha, g);
                    geom__curve_hbuf_set(&hb, nb * q + (size_t)k, h);
                }
                if (b < m) {
                    geom__curve_hbuf_get(&hb, nb * q + p, h);
                    geom__curve_hbuf_set(&hb, (nb + 1) * q + (size_t)save, h);
                }
            }
        }
        ++nb;
        if (b < m) {
            long ml = mult > P ? P : mult; /* multiplicity p+1: no shared point */
            for (long ii = P - ml; ii <= P; ++ii) {
                geom__curve_hget(c, (size_t)(b - P + ii), h);
                geom__curve_hbuf_set(&hb, nb * q + (size_t)ii, h);
            }
            a = b;
            ++b;
        }
    }
    geom__scratch_free(&sc);
    geom__curve_hbuf_finish(&hb, nseg * q);
    return nb == nseg ? GEOM_OK
                      : geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                                      "curve: inconsistent knot vector");
}
