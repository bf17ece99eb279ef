/* Global closest point on a NURBS curve: branch and bound over the Bezier
 * segments of all spans, with a Bernstein sign test on the derivative of the
 * squared distance, finished by Newton steps safeguarded by bisection. */
#include "curve/bspline_basis.h"

#include <float.h>

#define CP_MAX_DEPTH 60
#define CP_MAX_PIECES 200000

typedef struct cp_ctx {
    const geom_nurbs_curve *c;
    const double *q;
    size_t dim, D, q1; /* q1 = p+1 */
    double best_d2;
    double best_u;
    double best_pt[GEOM_CURVE_MAX_DIM];
    double *ders;  /* 3*dim */
    double *work;  /* span derivs work */
    double *prod;  /* coefficients of the sign polynomial */
    double *tmpD;  /* 2p-1 homogeneous (or 2p) coefficients */
    double *binom; /* table of binomials, (3p+1)^2 */
    size_t nb;     /* binomial table stride */
} cp_ctx;

static double B(const cp_ctx *x, size_t n, size_t k)
{
    return x->binom[n * x->nb + k];
}

static void consider(cp_ctx *x, double u, const double *pt)
{
    double d2 = 0.0;
    for (size_t d = 0; d < x->dim; ++d) {
        double t = pt[d] - x->q[d];
        d2 += t * t;
    }
    if (d2 < x->best_d2) {
        x->best_d2 = d2;
        x->best_u = u;
        memcpy(x->best_pt, pt, x->dim * sizeof(double));
    }
}

/* g'(u) = (C(u) - q) . C'(u) on span k; also fills ders with C, C', C''. */
static double gprime(cp_ctx *x, size_t k, double u, double *g2)
{
    geom__curve_span_derivs(x->c, k, u, 2, x->ders, x->work);
    const double *C = x->ders, *C1 = x->ders + x->dim, *C2 = x->ders + 2 * x->dim;
    double g1 = 0.0, gg = 0.0;
    for (size_t d = 0; d < x->dim; ++d) {
        double r = C[d] - x->q[d];
        g1 += r * C1[d];
        gg += C1[d] * C1[d] + r * C2[d];
    }
    if (g2)
        *g2 = gg;
    return g1;
}

/* The unique interior minimum of the distance on [a, b] of span k, where
 * g' goes from negative to positive: Newton on g' kept inside a shrinking
 * bracket, bisecting whenever Newton leaves it or stalls. */
static void newton(cp_ctx *x, size_t k, double a, double b)
{
    double fa = gprime(x, k, a, NULL);
    double fb = gprime(x, k, b, NULL);
    if (!(fa < 0.0 && fb > 0.0))
        return; /* no root seen numerically: the ends were already considered */
    double u = 0.5 * (a + b), prev_width = b - a;
    for (int it = 0; it < 200; ++it) {
        double g2;
        double f = gprime(x, k, u, &g2);
        consider(x, u, x->ders);
        if (f == 0.0)
            break;
        if (f < 0.0)
            a = u;
        else
            b = u;
        double un = (g2 > 0.0) ? u - f / g2 : NAN;
        if (!(un > a && un < b) || (b - a) > 0.5 * prev_width)
            un = 0.5 * (a + b);
        prev_width = b - a;
        if (!(un > a && un < b) || un == u)
            break;
        if (fabs(un - u) <= 4.0 * DBL_EPSILON * fmax(fabs(u), fabs(b - a))) {
            u = un;
            gprime(x, k, u, NULL);
            consider(x, u, x->ders);
            break;
        }
        u = un;
    }
}

/* Bernstein coefficients (local parameter) of the polynomial N with
 * sign(N) = sign(g'): (C - q).C' for polynomial pieces (degree 2p-1), and
 * (A - q w).(A' w - A w') for rational ones (degree 3p-1). Returns the
 * number of coefficients, and *wmin the smallest weight coefficient. */
static size_t sign_poly(cp_ctx *x, const double *b, double *wmin)
{
    size_t p = x->q1 - 1, dim = x->dim, D = x->D;
    double *out = x->prod;
    if (D == dim) {
        size_t deg = 2 * p - 1;
        for (size_t k = 0; k <= deg; ++k)
            out[k] = 0.0;
        for (size_t i = 0; i <= p; ++i)
            for (size_t j = 0; j < p; ++j) {
                double s = 0.0;
                for (size_t d = 0; d < dim; ++d)
                    s += (b[i * D + d] - x->q[d]) * (double)p * (b[(j + 1) * D + d] - b[j * D + d]);
                out[i + j] += B(x, p, i) * B(x, p - 1, j) * s;
            }
        for (size_t k = 0; k <= deg; ++k)
            out[k] /= B(x, deg, k);
        *wmin = 1.0;
        return deg + 1;
    }
    /* Dv = A' w - A w', degree 2p-1 (Bernstein, unnormalised then scaled) */
    size_t dd = 2 * p - 1;
    double *Dv = x->tmpD; /* (dd+1) * dim */
    for (size_t k = 0; k < (dd + 1) * dim; ++k)
        Dv[k] = 0.0;
    double wm = INFINITY;
    for (size_t i = 0; i <= p; ++i)
        wm = fmin(wm, b[i * D + dim]);
    for (size_t i = 0; i < p; ++i)        /* A'_i, w'_i: degree p-1 */
        for (size_t j = 0; j <= p; ++j) { /* A_j, w_j: degree p */
            double cij = B(x, p - 1, i) * B(x, p, j) * (double)p;
            double dwi = b[(i + 1) * D + dim] - b[i * D + dim];
            for (size_t d = 0; d < dim; ++d) {
                double dAi = b[(i + 1) * D + d] - b[i * D + d];
                Dv[(i + j) * dim + d] += cij * (dAi * b[j * D + dim] - b[j * D + d] * dwi);
            }
        }
    for (size_t k = 0; k <= dd; ++k)
        for (size_t d = 0; d < dim; ++d)
            Dv[k * dim + d] /= B(x, dd, k);
    size_t deg = p + dd;
    for (size_t k = 0; k <= deg; ++k)
        out[k] = 0.0;
    for (size_t i = 0; i <= p; ++i)
        for (size_t j = 0; j <= dd; ++j) {
            double s = 0.0;
            for (size_t d = 0; d < dim; ++d)
                s += (b[i * D + d] - x->q[d] * b[i * D + dim]) * Dv[j * dim + d];
            out[i + j] += B(x, p, i) * B(x, dd, j) * s;
        }
    for (size_t k = 0; k <= deg; ++k)
        out[k] /= B(x, deg, k);
    *wmin = wm;
    return deg + 1;
}

typedef struct cp_piece {
    double a, b;
    int depth;
} cp_piece;

static geom_status search_span(cp_ctx *x, size_t k, double *stack, cp_piece *info,
                               double *split_work, size_t *pieces)
{
    const geom_nurbs_curve *c = x->c;
    size_t D = x->D, dim = x->dim, q1 = x->q1, P = q1 * D;
    geom__curve_span_bezier(c, k, stack, split_work);
    info[0].a = c->knots[k];
    info[0].b = c->knots[k + 1];
    info[0].depth = 0;
    int top = 1;
    while (top > 0) {
        --top;
        double *b = stack + (size_t)top * P;
        cp_piece pc = info[top];
        ++*pieces;
        /* end points are curve points */
        double e0[GEOM_CURVE_MAX_DIM], e1[GEOM_CURVE_MAX_DIM];
        double w0 = D > dim ? b[dim] : 1.0, w1 = D > dim ? b[(q1 - 1) * D + dim] : 1.0;
        for (size_t d = 0; d < dim; ++d) {
            e0[d] = b[d] / w0;
            e1[d] = b[(q1 - 1) * D + d] / w1;
        }
        if (pc.depth == 0) {
            /* exact curve values at the span ends */
            geom__curve_span_derivs(c, k, pc.a, 0, x->ders, x->work);
            consider(x, pc.a, x->ders);
            geom__curve_span_derivs(c, k, pc.b, 0, x->ders, x->work);
            consider(x, pc.b, x->ders);
        } else {
            consider(x, pc.a, e0);
            consider(x, pc.b, e1);
        }
        /* lower bound: distance from q to the box of the control points */
        double lb2 = 0.0;
        for (size_t d = 0; d < dim; ++d) {
            double lo = INFINITY, hi = -INFINITY;
            for (size_t i = 0; i < q1; ++i) {
                double v = b[i * D + d] / (D > dim ? b[i * D + dim] : 1.0);
                lo = fmin(lo, v);
                hi = fmax(hi, v);
            }
            double g = x->q[d] < lo ? lo - x->q[d] : (x->q[d] > hi ? x->q[d] - hi : 0.0);
            lb2 += g * g;
        }
        if (lb2 >= x->best_d2)
            continue;
        double wmin;
        size_t nc = sign_poly(x, b, &wmin);
        double amax = 0.0;
        int changes = 0, last = 0, first = 0;
        for (size_t i = 0; i < nc; ++i) {
            double v = x->prod[i];
            amax = fmax(amax, fabs(v));
            int sg = v > 0.0 ? 1 : (v < 0.0 ? -1 : 0);
            if (sg == 0)
                continue;
            if (!first)
                first = sg;
            else if (sg != last)
                ++changes;
            last = sg;
        }
        /* |d g / dt| <= amax / wmin^3 (g = |C - q|^2 / 2): if g cannot vary
         * by more than a relative 1e-15 here, the ends are as good */
        double vary = amax / (wmin * wmin * wmin);
        if (changes == 0 || vary <= 0.5e-15 * x->best_d2)
            continue; /* monotone (or flat): the minimum is at an end */
        if (changes == 1) {
            if (first < 0)
                newton(x, k, pc.a, pc.b); /* - then +: one interior minimum */
            continue;                     /* + then -: a maximum inside */
        }
        if (pc.depth >= CP_MAX_DEPTH || *pieces >= CP_MAX_PIECES || top + 2 > CP_MAX_DEPTH + 2) {
            newton(x, k, pc.a, pc.b);
            continue;
        }
        /* split: the right half goes below, the left half on top */
        double m = 0.5 * (pc.a + pc.b);
        double *right = stack + (size_t)(top + 1) * P;
        geom__curve_hsplit((int)(q1 - 1), D, b, 0.5, b, right, split_work);
        /* swap so the left half is processed first (it is at b, push order) */
        info[top].a = m;
        info[top].b = pc.b;
        info[top].depth = pc.depth + 1;
        memcpy(split_work, b, P * sizeof(double));
        memcpy(b, right, P * sizeof(double));
        memcpy(right, split_work, P * sizeof(double));
        info[top + 1].a = pc.a;
        info[top + 1].b = m;
        info[top + 1].depth = pc.depth + 1;
        top += 2;
    }
    return GEOM_OK;
}

geom_status geom_curve_nurbs_closest_point(const geom_nurbs_curve *c, const double *q, double *u,
                                           double *point, double *distance, geom_diag *diag)
{
    geom_status st = geom__curve_check(c, diag);
    if (st != GEOM_OK)
        return st;
    if (!q)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "curve: NULL query point");
    for (size_t d = 0; d < c->dim; ++d)
        if (!isfinite(q[d]))
            return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                                 "curve: query point not finite");
    size_t p = (size_t)c->degree, q1 = p + 1, D = geom__curve_hdim(c), dim = c->dim;
    size_t P = q1 * D, nb = 3 * p + 1;
    size_t nstack = CP_MAX_DEPTH + 4;
    size_t need = nstack * P + P + 3 * dim + geom__curve_span_derivs_work(c, 2) + (3 * p + 1) +
                  (2 * p + 1) * dim + nb * nb;
    geom__scratch sc;
    st = geom__scratch_init(&sc, need);
    if (st != GEOM_OK) {
        geom__scratch_free(&sc);
        return geom__diag_set(diag, st, NULL, 0, 0, "curve: out of memory");
    }
    cp_piece info[CP_MAX_DEPTH + 4];
    double *stack = sc.mem;
    double *split_work = stack + nstack * P;
    cp_ctx x;
    x.c = c;
    x.q = q;
    x.dim = dim;
    x.D = D;
    x.q1 = q1;
    x.best_d2 = INFINITY;
    x.best_u = c->knots[p];
    x.ders = split_work + P;
    x.work = x.ders + 3 * dim;
    x.prod = x.work + geom__curve_span_derivs_work(c, 2);
    x.tmpD = x.prod + (3 * p + 1);
    x.binom = x.tmpD + (2 * p + 1) * dim;
    x.nb = nb;
    for (size_t n = 0; n < nb; ++n) {
        x.binom[n * nb] = 1.0;
        for (size_t k = 1; k < nb; ++k)
            x.binom[n * nb + k] =
                k > n ? 0.0 : x.binom[n * nb + k - 1] * (double)(n - k + 1) / (double)k;
    }
    size_t pieces = 0;
    for (size_t k = p; k < c->n; ++k)
        if (c->knots[k] < c->knots[k + 1])
            search_span(&x, k, stack, info, split_work, &pieces);
    geom__scratch_free(&sc);
    if (u)
        *u = x.best_u;
    if (point)
        memcpy(point, x.best_pt, dim * sizeof(double));
    if (distance)
        *distance = sqrt(x.best_d2);
    return GEOM_OK;
}
