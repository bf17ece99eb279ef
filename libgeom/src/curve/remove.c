/* Knot removal within a tolerance (The NURBS Book A5.8). */
#include "curve/bspline_basis.h"

static double hdist(size_t D, const double *a, const double *b)
{
    double s = 0.0;
    for (size_t d = 0; d < D; ++d) {
        double t = a[d] - b[d];
        s += t * t;
    }
    return sqrt(s);
}

geom_status geom_curve_nurbs_remove_knot(const geom_nurbs_curve *c, double u, size_t times,
                                         double tol, double *knots, double *points, double *weights,
                                         geom_nurbs_curve *out, size_t *removed, geom_diag *diag)
{
    geom_status st = geom__curve_check_knot_op(c, knots, points, weights, out, diag);
    if (st != GEOM_OK)
        return st;
    if (!isfinite(u) || !(tol >= 0.0) || !isfinite(tol))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "curve: knot or tolerance not finite (or tolerance < 0)");
    const double *U0 = c->knots;
    size_t N = c->n, pz = (size_t)c->degree, M = N + pz + 1;
    if (!(u > U0[pz] && u < U0[N]))
        return geom__diag_set(diag, GEOM_ERR_DOMAIN, NULL, 0, 0,
                             "curve: %.17g is not inside the domain (%.17g, %.17g)", u, U0[pz],
                             U0[N]);
    size_t rz = M, s = 0;
    for (size_t i = 0; i < M; ++i)
        if (U0[i] == u) {
            rz = i;
            ++s;
        }
    if (s == 0)
        return geom__diag_set(diag, GEOM_ERR_DOMAIN, NULL, 0, 0, "curve: %.17g is not a knot", u);
    size_t D = geom__curve_hdim(c);
    geom__curve_hbuf hb = {points, c->weights ? weights : NULL, c->dim};
    memcpy(knots, U0, M * sizeof(double));
    double h[GEOM_CURVE_HDIM_MAX], g[GEOM_CURVE_HDIM_MAX];
    for (size_t i = 0; i < N; ++i) {
        geom__curve_hget(c, i, h);
        geom__curve_hbuf_set(&hb, i, h);
    }
    double TOL = tol;
    if (c->weights) {
        double wmin = INFINITY, pmax = 0.0;
        for (size_t i = 0; i < N; ++i) {
            wmin = fmin(wmin, c->weights[i]);
            double s2 = 0.0;
            for (size_t d = 0; d < c->dim; ++d)
                s2 += c->points[i * c->dim + d] * c->points[i * c->dim + d];
            pmax = fmax(pmax, sqrt(s2));
        }
        TOL = tol * wmin / (1.0 + pmax);
    }
    size_t num = times < s ? times : s;
    geom__scratch sc;
    st = geom__scratch_init(&sc, (2 * pz + 4) * D);
    if (st != GEOM_OK) {
        geom__scratch_free(&sc);
        return geom__diag_set(diag, st, NULL, 0, 0, "curve: out of memory");
    }
    double *temp = sc.mem;
#define TMP(i) (temp + (size_t)(i)*D)
    double *Uw = knots;
    long p = (long)pz, r = (long)rz, sl = (long)s, ord = p + 1;
    long n = (long)N - 1, m = (long)M - 1;
    long fout = (2 * r - sl - p) / 2;
    long last = r - sl, first = r - p;
    long t;
    for (t = 0; t < (long)num; ++t) {
        long off = first - 1;
        geom__curve_hbuf_get(&hb, (size_t)off, TMP(0));
        geom__curve_hbuf_get(&hb, (size_t)(last + 1), TMP(last + 1 - off));
        long i = first, j = last, ii = 1, jj = last - off;
        int remflag = 0;
        while (j - i > t) {
            double alfi = (u - Uw[i]) / (Uw[i + ord + t] - Uw[i]);
            double alfj = (u - Uw[j - t]) / (Uw[j + ord] - Uw[j - t]);
            geom__curve_hbuf_get(&hb, (size_t)i, h);
            for (size_t d = 0; d < D; ++d)
                TMP(ii)[d] = (h[d] - (1.0 - alfi) * TMP(ii - 1)[d]) / alfi;
            geom__curve_hbuf_get(&hb, (size_t)j, h);
            for (size_t d = 0; d < D; ++d)
                TMP(jj)[d] = (h[d] - alfj * TMP(jj + 1)[d]) / (1.0 - alfj);
            ++i;
            ++ii;
            --j;
            --jj;
        }
        if (j - i < t) {
            if (hdist(D, TMP(ii - 1), TMP(jj + 1)) <= TOL)
                remflag = 1;
        } else {
            double alfi = (u - Uw[i]) / (Uw[i + ord + t] - Uw[i]);
            geom__curve_hcomb(D, g, alfi, TMP(ii + t + 1), 1.0 - alfi, TMP(ii - 1));
            geom__curve_hbuf_get(&hb, (size_t)i, h);
            if (hdist(D, h, g) <= TOL)
                remflag = 1;
        }
        if (!remflag)
            break;
        i = first;
        j = last;
        while (j - i > t) {
            geom__curve_hbuf_set(&hb, (size_t)i, TMP(i - off));
            geom__curve_hbuf_set(&hb, (size_t)j, TMP(j - off));
            ++i;
            --j;
        }
        --first;
        ++last;
    }
#undef TMP
    geom__scratch_free(&sc);
    if (t > 0) {
        for (long k = r + 1; k <= m; ++k)
            Uw[k - t] = Uw[k];
        long j = fout, i = j;
        for (long k = 1; k < t; ++k) {
            if (k % 2 == 1)
                ++i;
            else
                --j;
        }
        for (long k = i + 1; k <= n; ++k) {
            geom__curve_hbuf_get(&hb, (size_t)k, h);
            geom__curve_hbuf_set(&hb, (size_t)j, h);
            ++j;
        }
    }
    size_t nn = N - (size_t)t;
    geom__curve_hbuf_result(&hb, c->degree, nn, knots, out);
    if (removed)
        *removed = (size_t)t;
    return GEOM_OK;
}
