/* Batch evaluation of a curve over an array of parameters (for bindings). */
#include "curve/basis_lanes.h"
#include "curve/bspline_basis.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

/* Parameters per block of the batch loop, and the largest degree it takes
 * (higher degrees go point by point through geom_curve_nurbs_eval). */
#define EM_BLOCK GEOM__BS_LANES
#define EM_MAXP GEOM__BS_LANES_MAXP

/* geom__bs_basis and combine_point of eval.c for EM_BLOCK parameters ue of
 * spans k (one span per lane), lane by lane: every lane does the very
 * operations of the single function in the same order (no reciprocal, no
 * reassociation), so the results are bitwise those of geom_curve_nurbs_eval.
 * The loops over the lanes are what the compiler vectorises (one divpd
 * serves two or more parameters); knots and control points are gathered per
 * lane. Writes m rows of dim doubles. */
GEOM_SIMD_CLONES
static void eval_block(const geom_nurbs_curve *c, const size_t *k, const double *ue, size_t m,
                       double *out)
{
    enum { B = EM_BLOCK };
    int p = c->degree;
    size_t dim = c->dim;
    double N[EM_MAXP + 1][B];
    geom__bs_basis_lanes(p, c->knots, k, ue, N);
    double acc[GEOM_CURVE_MAX_DIM][B], Pj[GEOM_CURVE_MAX_DIM][B];
    for (size_t d = 0; d < dim; ++d)
        for (int i = 0; i < B; ++i)
            acc[d][i] = 0.0;
    double W[B], wj[B], Rj[B];
    if (c->weights) {
        for (int i = 0; i < B; ++i)
            W[i] = 0.0;
        for (int j = 0; j <= p; ++j) {
            for (int i = 0; i < B; ++i)
                wj[i] = c->weights[k[i] - (size_t)p + (size_t)j];
            for (int i = 0; i < B; ++i)
                W[i] += N[j][i] * wj[i];
        }
    }
    int same = 1; /* one span for every lane (the common case): no gathers */
    for (int i = 1; i < B; ++i)
        same &= k[i] == k[0];
    for (int j = 0; j <= p; ++j) {
        if (c->weights) {
            for (int i = 0; i < B; ++i)
                wj[i] = c->weights[k[i] - (size_t)p + (size_t)j];
            for (int i = 0; i < B; ++i)
                Rj[i] = (N[j][i] * wj[i]) / W[i];
        } else {
            for (int i = 0; i < B; ++i)
                Rj[i] = N[j][i];
        }
        if (same) {
            const double *P = c->points + (k[0] - (size_t)p + (size_t)j) * dim;
            for (size_t d = 0; d < dim; ++d) {
                double pd = P[d];
                for (int i = 0; i < B; ++i)
                    acc[d][i] += Rj[i] * pd;
            }
            continue;
        }
        for (int i = 0; i < B; ++i) {
            const double *P = c->points + (k[i] - (size_t)p + (size_t)j) * dim;
            for (size_t d = 0; d < dim; ++d)
                Pj[d][i] = P[d];
        }
        for (size_t d = 0; d < dim; ++d)
            for (int i = 0; i < B; ++i)
                acc[d][i] += Rj[i] * Pj[d][i];
    }
    if (dim == 3 && m == B) { /* a fixed count: the interleave vectorises */
        for (int i = 0; i < B; ++i) {
            out[3 * i] = acc[0][i];
            out[3 * i + 1] = acc[1][i];
            out[3 * i + 2] = acc[2][i];
        }
    } else if (dim == 3) {
        for (size_t i = 0; i < m; ++i) {
            out[3 * i] = acc[0][i];
            out[3 * i + 1] = acc[1][i];
            out[3 * i + 2] = acc[2][i];
        }
    } else if (dim == 2) {
        for (size_t i = 0; i < m; ++i) {
            out[2 * i] = acc[0][i];
            out[2 * i + 1] = acc[1][i];
        }
    } else {
        for (size_t i = 0; i < m; ++i)
            for (size_t d = 0; d < dim; ++d)
                out[i * dim + d] = acc[d][i];
    }
}

/* Do the EM_BLOCK parameters u all lie strictly between a and b? */
static int in_span(const double *u, double a, double b)
{
    int in = 1;
    for (int i = 0; i < EM_BLOCK; ++i)
        in &= (a < u[i]) & (u[i] < b);
    return in;
}

static void fail_row(double *o, size_t dim, geom_status st, int32_t *status, size_t i,
                     size_t *failed)
{
    if (st != GEOM_OK) {
        for (size_t j = 0; j < dim; j++)
            o[j] = NAN;
        (*failed)++;
    }
    if (status)
        status[i] = (int32_t)st;
}

geom_status geom_curve_nurbs_eval_many(const geom_nurbs_curve *c, size_t n, const double *u,
                                       unsigned flags, double *out, int32_t *status,
                                       size_t *n_failed)
{
    if (n_failed)
        *n_failed = 0;
    if (n == 0)
        return GEOM_OK;
    if (!c || !u || !out || c->dim < 1 || c->dim > GEOM_CURVE_MAX_DIM)
        return GEOM_ERR_INVALID_ARG;
    size_t failed = 0, dim = c->dim;
    if (geom__curve_check_cheap(c) != GEOM_OK || c->degree > EM_MAXP) {
        /* point by point: every row gets geom_curve_nurbs_eval's status */
        for (size_t i = 0; i < n; i++)
            fail_row(out + dim * i, dim, geom_curve_nurbs_eval(c, u[i], flags, out + dim * i),
                     status, i, &failed);
        if (n_failed)
            *n_failed = failed;
        return GEOM_OK;
    }
    /* Blocks of EM_BLOCK parameters: each row's parameter reduction and span
     * as geom_curve_nurbs_eval does them, then the valid rows evaluated
     * together (failed rows are packed out, unused lanes repeat a valid one). */
    size_t kc = SIZE_MAX;
    double ua = c->knots[c->degree], ub = c->knots[c->n];
    int want_left = (flags & GEOM_CURVE_LEFT_LIMIT) != 0;
    for (size_t i0 = 0; i0 < n; i0 += EM_BLOCK) {
        size_t m = n - i0 < EM_BLOCK ? n - i0 : EM_BLOCK, nv = 0;
        double ue[EM_BLOCK];
        size_t k[EM_BLOCK], row[EM_BLOCK];
        if (m == EM_BLOCK && kc != SIZE_MAX && !(flags & GEOM_CURVE_WRAP) &&
            in_span(u + i0, c->knots[kc], c->knots[kc + 1])) {
            /* the whole block strictly inside the last span (and so inside
             * the domain): every row's reduction is the identity and its
             * span kc, as the row-by-row path below finds */
            for (size_t j = 0; j < EM_BLOCK; ++j)
                k[j] = kc;
            if (status)
                memset(status + i0, 0, EM_BLOCK * sizeof *status);
            eval_block(c, k, u + i0, m, out + dim * i0);
            continue;
        }
        for (size_t j = 0; j < m; ++j) {
            int left;
            double e;
            geom_status st = GEOM_OK;
            if (!(flags & GEOM_CURVE_WRAP) && u[i0 + j] >= ua && u[i0 + j] <= ub) {
                e = u[i0 + j]; /* what geom__bs_param does inside the domain */
                left = want_left;
            } else {
                st = geom__curve_prepare_param(c, u[i0 + j], flags, &e, &left);
            }
            if (st == GEOM_OK) {
                ue[nv] = e;
                k[nv] = geom__bs_span_cached(c->degree, c->n, c->knots, e, left, &kc);
                row[nv++] = j;
            } else {
                fail_row(out + dim * (i0 + j), dim, st, status, i0 + j, &failed);
            }
            if (status && st == GEOM_OK)
                status[i0 + j] = GEOM_OK;
        }
        if (nv == 0)
            continue;
        for (size_t j = nv; j < EM_BLOCK; ++j) {
            ue[j] = ue[0];
            k[j] = k[0];
        }
        if (nv == m) {
            eval_block(c, k, ue, m, out + dim * i0);
            continue;
        }
        double tmp[EM_BLOCK * GEOM_CURVE_MAX_DIM];
        eval_block(c, k, ue, nv, tmp);
        for (size_t j = 0; j < nv; ++j)
            memcpy(out + dim * (i0 + row[j]), tmp + dim * j, dim * sizeof(double));
    }
    if (n_failed)
        *n_failed = failed;
    return GEOM_OK;
}

geom_status geom_curve_bspline_basis_many(int degree, size_t n, const double *knots, size_t m,
                                          const double *u, int nderiv, unsigned flags,
                                          size_t *spans, double *ders, int32_t *status,
                                          size_t *n_failed)
{
    if (n_failed)
        *n_failed = 0;
    if (m == 0)
        return GEOM_OK;
    if (!knots || !u || !ders || degree < 0 || nderiv < 0)
        return GEOM_ERR_INVALID_ARG;
    size_t row = (size_t)(nderiv + 1) * (size_t)(degree + 1), failed = 0;
    for (size_t i = 0; i < m; i++) {
        size_t span = 0;
        geom_status st = geom_curve_bspline_basis_derivs(degree, n, knots, u[i], nderiv, flags,
                                                         &span, ders + row * i);
        if (st != GEOM_OK) {
            for (size_t j = 0; j < row; j++)
                ders[row * i + j] = NAN;
            failed++;
        }
        if (spans)
            spans[i] = st == GEOM_OK ? span : (size_t)-1;
        if (status)
            status[i] = (int32_t)st;
    }
    if (n_failed)
        *n_failed = failed;
    return GEOM_OK;
}
