/*
 * The tessellator's lower bound on segment counts along lines of constant
 * parameter (tessellate.c): the smallest n for which every chord of the
 * n-segment polylines (uniform in the parameter) along the given curves
 * keeps the curve within tol at the error check's side samples.
 *
 * The check is not monotone in n (a kink or an inflection on a grid line
 * passes at some n and fails at n + 1), so the answer is found by testing
 * n = 1, 2, ... in turn, as a linear scan would, and is the same value. It
 * is cheap because a failing n is shown to fail by one segment: the segment
 * containing the parameter where the previous n failed is tested first
 * (its chord error changes little from n to n + 1), and only a count that
 * passes there walks every segment. A scan over n = 1..m then costs about
 * (m + the segments of the passing counts) (K + 1) evaluations instead of
 * m^2 K / 2.
 */
#include "surface/surface_internal.h"
#include "spatial/spatial_internal.h"

#include <math.h>

/* Parameter of grid line i of n over [a, b] (the grid search's rounding). */
static double line_t(double a, double b, uint32_t i, uint32_t n)
{
    return i == n ? b : a + (b - a) * (double)i / (double)n;
}

/* Segment i of n of line l: its K-1 samples within tol of the chord
 * (point-segment distance)? The failing sample's parameter to *fail. */
static int seg_pass(geom__tess_line_fn fn, void *user, int l, double a, double b, int K,
                    uint32_t n, uint32_t i, const double P0[3], const double P1[3], double tol,
                    double *fail)
{
    double t0 = line_t(a, b, i, n), t1 = line_t(a, b, i + 1, n);
    for (int m = 1; m < K; ++m) {
        double f = (double)m / K, t = (1.0 - f) * t0 + f * t1, S[3];
        fn(user, l, t, S);
        if (!(sqrt(geom__closest_seg_d2(S, P0, P1)) <= tol)) {
            *fail = t;
            return 0;
        }
    }
    return 1;
}

int geom__tess_lines_pass(geom__tess_line_fn fn, void *user, int nlines, double a, double b, int K,
                          uint32_t n, double tol, double *hint)
{
    if (n == 0)
        return 0;
    /* first the segment where the last count failed */
    if (isfinite(*hint) && *hint >= a && *hint <= b) {
        double f = (*hint - a) / (b - a) * (double)n;
        uint32_t i = f >= (double)n ? n - 1 : (f > 0.0 ? (uint32_t)f : 0);
        for (int l = 0; l < nlines; ++l) {
            double P0[3], P1[3];
            fn(user, l, line_t(a, b, i, n), P0);
            fn(user, l, line_t(a, b, i + 1, n), P1);
            if (!seg_pass(fn, user, l, a, b, K, n, i, P0, P1, tol, hint))
                return 0;
        }
    }
    for (int l = 0; l < nlines; ++l) {
        double P0[3], P1[3];
        fn(user, l, a, P0);
        for (uint32_t i = 0; i < n; ++i) {
            fn(user, l, line_t(a, b, i + 1, n), P1);
            if (!seg_pass(fn, user, l, a, b, K, n, i, P0, P1, tol, hint))
                return 0;
            P0[0] = P1[0], P0[1] = P1[1], P0[2] = P1[2];
        }
    }
    return 1;
}

uint32_t geom__tess_lines_bound(geom__tess_line_fn fn, void *user, int nlines, double a, double b,
                                int K, uint32_t cap, double tol)
{
    double hint = NAN;
    for (uint32_t n = 1; n < cap; ++n)
        if (geom__tess_lines_pass(fn, user, nlines, a, b, K, n, tol, &hint))
            return n;
    return cap;
}
