/* Batch evaluation of a surface over arrays of parameters (for bindings). */
#include "curve/basis_lanes.h"
#include "surface/surface_internal.h"

#include <math.h>
#include <string.h>

enum { SB = GEOM__BS_LANES };

/* geom__surface_span_point for SB parameter pairs (ue, ve) of spans (ku, kv)
 * (one pair per lane), lane by lane: the basis of each direction through
 * geom__bs_basis_lanes, then eval.c's combine_point with the very
 * operations in the same order, so the results are bitwise those of
 * geom_surface_eval. Control points (and weights) are shared when every
 * lane is in the same span pair (the common case), else gathered per lane.
 * Writes m rows of 3 doubles. */
GEOM_SIMD_CLONES
static void eval_block(const geom_nurbs_surface *s, const size_t *ku, const size_t *kv,
                       const double *ue, const double *ve, size_t m, double *out)
{
    int p = s->degree_u, q = s->degree_v;
    size_t nv = s->nv;
    double Nu[GEOM__BS_LANES_MAXP + 1][SB], Nv[GEOM__BS_LANES_MAXP + 1][SB];
    geom__bs_basis_lanes(p, s->knots_u, ku, ue, Nu);
    geom__bs_basis_lanes(q, s->knots_v, kv, ve, Nv);
    int same = 1;
    for (int l = 1; l < SB; ++l)
        same &= (ku[l] == ku[0]) & (kv[l] == kv[0]);
    double o[3][SB], P[3][SB], w[SB];
    for (int d = 0; d < 3; ++d)
        for (int l = 0; l < SB; ++l)
            o[d][l] = 0.0;
    /* control point (i, j) of each lane's span into P (and its weight into w) */
#define SB_LOAD(i, j)                                                                          \
    do {                                                                                       \
        if (same) {                                                                            \
            size_t idx = (ku[0] - (size_t)p + (size_t)(i)) * nv + kv[0] - (size_t)q + (size_t)(j); \
            for (int l = 0; l < SB; ++l) {                                                     \
                P[0][l] = s->points[3 * idx];                                                  \
                P[1][l] = s->points[3 * idx + 1];                                              \
                P[2][l] = s->points[3 * idx + 2];                                              \
                w[l] = s->weights ? s->weights[idx] : 1.0;                                     \
            }                                                                                  \
        } else {                                                                               \
            for (int l = 0; l < SB; ++l) {                                                     \
                size_t idx = (ku[l] - (size_t)p + (size_t)(i)) * nv + kv[l] - (size_t)q +      \
                             (size_t)(j);                                                      \
                P[0][l] = s->points[3 * idx];                                                  \
                P[1][l] = s->points[3 * idx + 1];                                              \
                P[2][l] = s->points[3 * idx + 2];                                              \
                w[l] = s->weights ? s->weights[idx] : 1.0;                                     \
            }                                                                                  \
        }                                                                                      \
    } while (0)
    if (s->weights) {
        double W[SB];
        for (int l = 0; l < SB; ++l)
            W[l] = 0.0;
        for (int i = 0; i <= p; ++i)
            for (int j = 0; j <= q; ++j) {
                SB_LOAD(i, j);
                for (int l = 0; l < SB; ++l)
                    W[l] += Nu[i][l] * Nv[j][l] * w[l];
            }
        for (int i = 0; i <= p; ++i)
            for (int j = 0; j <= q; ++j) {
                SB_LOAD(i, j);
                for (int l = 0; l < SB; ++l) {
                    double R = (Nu[i][l] * Nv[j][l] * w[l]) / W[l];
                    o[0][l] += R * P[0][l];
                    o[1][l] += R * P[1][l];
                    o[2][l] += R * P[2][l];
                }
            }
    } else {
        for (int i = 0; i <= p; ++i) {
            double t[3][SB];
            for (int d = 0; d < 3; ++d)
                for (int l = 0; l < SB; ++l)
                    t[d][l] = 0.0;
            for (int j = 0; j <= q; ++j) {
                SB_LOAD(i, j);
                for (int l = 0; l < SB; ++l) {
                    t[0][l] += Nv[j][l] * P[0][l];
                    t[1][l] += Nv[j][l] * P[1][l];
                    t[2][l] += Nv[j][l] * P[2][l];
                }
            }
            for (int l = 0; l < SB; ++l) {
                o[0][l] += Nu[i][l] * t[0][l];
                o[1][l] += Nu[i][l] * t[1][l];
                o[2][l] += Nu[i][l] * t[2][l];
            }
        }
    }
#undef SB_LOAD
    for (size_t l = 0; l < m; ++l) {
        out[3 * l] = o[0][l];
        out[3 * l + 1] = o[1][l];
        out[3 * l + 2] = o[2][l];
    }
}

static void finish_row(double *o, geom_status st, int32_t *status, size_t i, size_t *failed)
{
    if (st != GEOM_OK) {
        o[0] = o[1] = o[2] = NAN;
        (*failed)++;
    }
    if (status)
        status[i] = (int32_t)st;
}

/* The parameter t of one direction (degree p, n points, knots U) reduced as
 * geom__surface_locate does it, and its span (cached in *kc). */
static geom_status locate_one(int p, size_t n, const double *U, double t, int want_left,
                              double *te, size_t *k, size_t *kc)
{
    int left = want_left;
    if (isfinite(t) && t >= U[p] && t <= U[n]) { /* geom__bs_param inside the domain */
        *te = t;
    } else {
        geom_status st = geom__bs_param(p, n, U, t, 0, want_left, te, &left);
        if (st != GEOM_OK)
            return st;
    }
    *k = geom__bs_span_cached(p, n, U, *te, left, kc);
    return GEOM_OK;
}

geom_status geom_surface_eval_many(const geom_nurbs_surface *s, size_t n, const double *uv,
                                   unsigned flags, int normals, double *out, int32_t *status,
                                   size_t *n_failed)
{
    if (n_failed)
        *n_failed = 0;
    if (n == 0)
        return GEOM_OK;
    if (!s || !uv || !out)
        return GEOM_ERR_INVALID_ARG;
    size_t failed = 0;
    if (normals || geom__surface_check_cheap(s) != GEOM_OK ||
        s->degree_u > GEOM__BS_LANES_MAXP || s->degree_v > GEOM__BS_LANES_MAXP) {
        for (size_t i = 0; i < n; i++) {
            double *o = out + 3 * i;
            geom_status st = normals
                                 ? geom_surface_normal(s, uv[2 * i], uv[2 * i + 1], flags, o, NULL)
                                 : geom_surface_eval(s, uv[2 * i], uv[2 * i + 1], flags, o);
            finish_row(o, st, status, i, &failed);
        }
        if (n_failed)
            *n_failed = failed;
        return GEOM_OK;
    }
    /* Blocks of SB rows: each row's parameters reduced and located as
     * geom_surface_eval does it, then the valid rows evaluated together
     * (failed rows are packed out, unused lanes repeat a valid one). */
    size_t kcu = SIZE_MAX, kcv = SIZE_MAX;
    int lu = (flags & GEOM_SURFACE_U_LEFT) != 0, lv = (flags & GEOM_SURFACE_V_LEFT) != 0;
    for (size_t i0 = 0; i0 < n; i0 += SB) {
        size_t m = n - i0 < SB ? n - i0 : SB, nvalid = 0;
        double ue[SB], ve[SB];
        size_t ku[SB], kv[SB], row[SB];
        for (size_t j = 0; j < m; ++j) {
            const double *t = uv + 2 * (i0 + j);
            geom_status st = locate_one(s->degree_u, s->nu, s->knots_u, t[0], lu, &ue[nvalid],
                                        &ku[nvalid], &kcu);
            if (st == GEOM_OK)
                st = locate_one(s->degree_v, s->nv, s->knots_v, t[1], lv, &ve[nvalid],
                                &kv[nvalid], &kcv);
            if (st == GEOM_OK)
                row[nvalid++] = j;
            finish_row(out + 3 * (i0 + j), st, status, i0 + j, &failed);
        }
        if (nvalid == 0)
            continue;
        for (size_t j = nvalid; j < SB; ++j) {
            ue[j] = ue[0];
            ve[j] = ve[0];
            ku[j] = ku[0];
            kv[j] = kv[0];
        }
        if (nvalid == m) {
            eval_block(s, ku, kv, ue, ve, m, out + 3 * i0);
            continue;
        }
        double tmp[3 * SB];
        eval_block(s, ku, kv, ue, ve, nvalid, tmp);
        for (size_t j = 0; j < nvalid; ++j)
            memcpy(out + 3 * (i0 + row[j]), tmp + 3 * j, 3 * sizeof(double));
    }
    if (n_failed)
        *n_failed = failed;
    return GEOM_OK;
}
