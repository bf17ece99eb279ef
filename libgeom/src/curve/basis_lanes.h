/*
 * The B-spline basis of geom__bs_basis (core/bspline.c) for a block of
 * parameters, lane by lane: the batch evaluators of curves
 * (curve/eval_many.c) and surfaces (surface/eval_many.c) inline it into
 * their GEOM_SIMD_CLONES kernels. Private; not installed.
 */
#ifndef GEOM_SRC_CURVE_BASIS_LANES_H
#define GEOM_SRC_CURVE_BASIS_LANES_H

#include "core/bspline.h"
#include "core/internal.h"

#include <stddef.h>
#include <stdint.h>

/* Parameters per block, and the largest degree the lanes take. */
#define GEOM__BS_LANES 16
#define GEOM__BS_LANES_MAXP 8

/* N[j][i] (j = 0..p) = the p + 1 nonzero basis functions at ue[i] of span
 * k[i] of the knots U, for GEOM__BS_LANES lanes i: every lane does the very
 * operations of geom__bs_basis in the same order (no reciprocal, no
 * reassociation), so each lane's values are bitwise geom__bs_basis's. The
 * loops over the lanes are what the compiler vectorises (one divpd serves
 * several parameters); knots are gathered per lane. p <= GEOM__BS_LANES_MAXP. */
GEOM__CLONE_INLINE void geom__bs_basis_lanes(int p, const double *U, const size_t *k,
                                             const double *ue,
                                             double N[][GEOM__BS_LANES])
{
    enum { B = GEOM__BS_LANES };
    double L[GEOM__BS_LANES_MAXP + 1][B], R[GEOM__BS_LANES_MAXP + 1][B], saved[B];
    double ua[B], ub[B];
    int same = 1; /* one span for every lane (the common case): no gathers */
    for (int i = 1; i < B; ++i)
        same &= k[i] == k[0];
    for (int i = 0; i < B; ++i)
        N[0][i] = 1.0;
    for (int j = 1; j <= p; ++j) {
        if (same) {
            double a = U[k[0] + 1 - (size_t)j], b = U[k[0] + (size_t)j];
            for (int i = 0; i < B; ++i) {
                ua[i] = a;
                ub[i] = b;
            }
        } else {
            for (int i = 0; i < B; ++i) {
                ua[i] = U[k[i] + 1 - (size_t)j];
                ub[i] = U[k[i] + (size_t)j];
            }
        }
        for (int i = 0; i < B; ++i) {
            L[j][i] = ue[i] - ua[i];
            R[j][i] = ub[i] - ue[i];
            saved[i] = 0.0;
        }
        for (int r = 0; r < j; ++r) {
            const double *rr = R[r + 1], *ll = L[j - r];
            double *nn = N[r];
            for (int i = 0; i < B; ++i) {
                double den = rr[i] + ll[i];
                double nr = nn[i];
                nn[i] = saved[i] + (rr[i] * nr) / den;
                saved[i] = (ll[i] * nr) / den;
            }
        }
        for (int i = 0; i < B; ++i)
            N[j][i] = saved[i];
    }
}

/* The span of ue in the knots U (degree p, n control points): *kc, the
 * span of the previous lookup, when ue lies strictly inside it (every
 * caller's answer there, left limit or not), else geom__bs_span's, which
 * becomes *kc (SIZE_MAX: none yet). */
static inline size_t geom__bs_span_cached(int p, size_t n, const double *U, double ue, int left,
                                          size_t *kc)
{
    size_t k = *kc;
    if (k != SIZE_MAX && U[k] < ue && ue < U[k + 1])
        return k;
    k = geom__bs_span(p, n, U, ue, left);
    *kc = k;
    return k;
}

#endif
