/* Knot refinement (The NURBS Book A5.4) and clamping. */
#include "curve/bspline_basis.h"

/*
 * A5.4 in place: on entry U (knots) and hb (homogeneous points) hold the
 * curve with N control points, with room for nx more points and knots; on
 * exit they hold the refined curve. In place is safe because, walking from
 * the end, every write lands at a higher index than any original knot or
 * point still to be read (the write index k stays above the read index i).
 * x: nx >= 1 nondecreasing values in [U[p], U[N]].
 */
static void refine_in_place(int pi, size_t N, double *U, const geom__curve_hbuf *hb, const double *x,
                            size_t nx, size_t D)
{
    size_t p = (size_t)pi, m = N + p; /* last knot index */
    size_t r = nx - 1;
    size_t a = geom__bs_span(pi, N, U, x[0], 0);
    size_t b = geom__bs_span(pi, N, U, x[r], 0) + 1;
    double h[GEOM_CURVE_HDIM_MAX], g[GEOM_CURVE_HDIM_MAX];
    /* tail: Qw[j+r+1] = Pw[j] for j = b-1 .. N-1, descending */
    for (size_t j = N; j-- > b - 1;) {
        geom__curve_hbuf_get(hb, j, h);
        geom__curve_hbuf_set(hb, j + r + 1, h);
    }
    for (size_t j = m + 1; j-- > b + p;)
        U[j + r + 1] = U[j];
    size_t i = b + p - 1, k = b + p + r;
    for (size_t jj = nx; jj-- > 0;) {
        double xj = x[jj];
        while (xj <= U[i] && i > a) {
            geom__curve_hbuf_get(hb, i - p - 1, h);
            geom__curve_hbuf_set(hb, k - p - 1, h);
            U[k] = U[i];
            --k;
            --i;
        }
        geom__curve_hbuf_get(hb, k - p, h);
        geom__curve_hbuf_set(hb, k - p - 1, h);
        for (size_t l = 1; l <= p; ++l) {
            size_t ind = k - p + l;
            double alfa = U[k + l] - xj;
            geom__curve_hbuf_get(hb, ind, h);
            if (fabs(alfa) == 0.0) {
                geom__curve_hbuf_set(hb, ind - 1, h);
            } else {
                alfa = alfa / (U[k + l] - U[i - p + l]);
                geom__curve_hbuf_get(hb, ind - 1, g);
                geom__curve_hcomb(D, g, alfa, g, 1.0 - alfa, h);
                geom__curve_hbuf_set(hb, ind - 1, g);
            }
        }
        U[k] = xj;
        --k;
    }
}

static size_t count_value(const double *U, size_t m, double v)
{
    size_t s = 0;
    for (size_t i = 0; i < m; ++i)
        s += U[i] == v;
    return s;
}

static void copy_in(const geom_nurbs_curve *c, double *knots, const geom__curve_hbuf *hb)
{
    memcpy(knots, c->knots, (c->n + (size_t)c->degree + 1) * sizeof(double));
    double h[GEOM_CURVE_HDIM_MAX];
    for (size_t i = 0; i < c->n; ++i) {
        geom__curve_hget(c, i, h);
        geom__curve_hbuf_set(hb, i, h);
    }
}

geom_status geom_curve_nurbs_refine(const geom_nurbs_curve *c, const double *x, size_t nx,
                                    double *knots, double *points, double *weights,
                                    geom_nurbs_curve *out, geom_diag *diag)
{
    geom_status st = geom__curve_check_knot_op(c, knots, points, weights, out, diag);
    if (st != GEOM_OK)
        return st;
    if (nx > 0 && !x)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "curve: NULL knot list");
    const double *U = c->knots;
    size_t p = (size_t)c->degree, n = c->n, m = n + p + 1;
    for (size_t j = 0; j < nx; ++j) {
        if (!isfinite(x[j]))
            return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                                 "curve: knot %zu to insert is not finite", j);
        if (!(x[j] >= U[p] && x[j] <= U[n]))
            return geom__diag_set(diag, GEOM_ERR_DOMAIN, NULL, 0, 0,
                                 "curve: knot %zu to insert (%.17g) is outside [%.17g, %.17g]", j,
                                 x[j], U[p], U[n]);
        if (j > 0 && x[j] < x[j - 1])
            return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                                 "curve: knots to insert decrease at %zu", j);
        if (j == 0 || x[j] != x[j - 1]) {
            size_t cnt = 1;
            while (j + cnt < nx && x[j + cnt] == x[j])
                ++cnt;
            size_t total = cnt + count_value(U, m, x[j]);
            if (total > p)
                return geom__diag_set(diag, GEOM_ERR_DOMAIN, NULL, 0, 0,
                                     "curve: knot %.17g would get multiplicity %zu > degree %zu",
                                     x[j], total, p);
        }
    }
    geom__curve_hbuf hb = {points, c->weights ? weights : NULL, c->dim};
    copy_in(c, knots, &hb);
    if (nx > 0)
        refine_in_place(c->degree, n, knots, &hb, x, nx, geom__curve_hdim(c));
    geom__curve_hbuf_result(&hb, c->degree, n + nx, knots, out);
    return GEOM_OK;
}

geom_status geom_curve_nurbs_clamp(const geom_nurbs_curve *c, double *knots, double *points,
                                   double *weights, geom_nurbs_curve *out, geom_diag *diag)
{
    geom_status st = geom__curve_check_knot_op(c, knots, points, weights, out, diag);
    if (st != GEOM_OK)
        return st;
    size_t p = (size_t)c->degree, n = c->n, m = n + p + 1;
    double a = c->knots[p], b = c->knots[n];
    size_t sa = count_value(c->knots, m, a), sb = count_value(c->knots, m, b);
    size_t nx = 0;
    geom__scratch sc;
    st = geom__scratch_init(&sc, 2 * p);
    if (st != GEOM_OK) {
        geom__scratch_free(&sc);
        return geom__diag_set(diag, st, NULL, 0, 0, "curve: out of memory");
    }
    double *xs = sc.mem;
    for (size_t i = sa; i < p; ++i)
        xs[nx++] = a;
    for (size_t i = sb; i < p; ++i)
        xs[nx++] = b;
    geom__curve_hbuf hb = {points, c->weights ? weights : NULL, c->dim};
    copy_in(c, knots, &hb);
    if (nx > 0)
        refine_in_place(c->degree, n, knots, &hb, xs, nx, geom__curve_hdim(c));
    geom__scratch_free(&sc);
    size_t N = n + nx, M = N + p + 1;
    size_t ia = p; /* last index of a */
    while (ia + 1 < M && knots[ia + 1] == a)
        ++ia;
    size_t jb = N; /* first index of b */
    while (jb > 0 && knots[jb - 1] == b)
        --jb;
    size_t first = ia - p, nn = jb - ia + p;
    memmove(knots + p + 1, knots + ia + 1, (jb - 1 - ia) * sizeof(double));
    for (size_t i = 0; i <= p; ++i) {
        knots[i] = a;
        knots[nn + i] = b;
    }
    if (first > 0) {
        memmove(points, points + first * c->dim, nn * c->dim * sizeof(double));
        if (hb.w)
            memmove(hb.w, hb.w + first, nn * sizeof(double));
    }
    geom__curve_hbuf_result(&hb, c->degree, nn, knots, out);
    return GEOM_OK;
}
