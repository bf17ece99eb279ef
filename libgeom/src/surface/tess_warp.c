/*
 * Non-uniform grid lines within a tessellation cell (tessellate.c): a
 * monotone map from the grid's uniform fraction f in [0, 1] to the cell's
 * parameter fraction y in [0, 1], placing the lines so that the chord error
 * is about equal on every segment.
 *
 * A chord over a parameter step h deviates from the curve by about
 * k(t) h^2 / 8, k the curve's second derivative normal to its tangent (the
 * tangential part only moves points along the chord). n segments with
 * equal deviation have steps h(t) proportional to 1 / sqrt(k(t)), so the
 * line density is proportional to sqrt(k) and the lines are equally spaced
 * in its integral F(y) = int_0^y sqrt(k) / int_0^1 sqrt(k): the
 * equidistribution principle of de Boor (A Practical Guide to Splines,
 * 1978, ch. III: the optimal breaks for piecewise linear interpolation).
 * Here sqrt(k) is sampled on WARP_N equal parameter intervals (piecewise
 * constant), so F is piecewise linear through (i / WARP_N, F_i) and its
 * inverse, the warp, is piecewise linear too: both evaluate exactly as the
 * inverse of each other up to rounding, and both are strictly increasing.
 */
#include "surface/surface_internal.h"

#include <math.h>

int geom__tess_warp_build(const double *rho, int n, double ratio, double floor_frac, double *F)
{
    double lo = INFINITY, hi = 0.0, sum = 0.0;
    for (int i = 0; i < n; ++i) {
        if (!isfinite(rho[i]) || rho[i] < 0.0)
            return 0;
        lo = fmin(lo, rho[i]);
        hi = fmax(hi, rho[i]);
        sum += rho[i];
    }
    /* nearly uniform density: uniform lines (the caller keeps its own) */
    if (!(hi > 0.0) || !(hi > ratio * lo))
        return 0;
    double fl = floor_frac * sum / (double)n, total = 0.0;
    F[0] = 0.0;
    for (int i = 0; i < n; ++i) {
        total += fmax(rho[i], fl);
        F[i + 1] = total;
    }
    if (!(total > 0.0) || !isfinite(total))
        return 0;
    for (int i = 1; i < n; ++i)
        F[i] /= total;
    F[n] = 1.0;
    for (int i = 0; i < n; ++i)
        if (!(F[i + 1] > F[i]))
            return 0;
    return 1;
}

double geom__tess_warp_y(const double *F, int n, double f)
{
    if (!(f > 0.0))
        return 0.0;
    if (f >= 1.0)
        return 1.0;
    int lo = 0, hi = n; /* F[lo] <= f < F[hi] */
    while (hi - lo > 1) {
        int mid = lo + (hi - lo) / 2;
        if (F[mid] <= f)
            lo = mid;
        else
            hi = mid;
    }
    double r = (f - F[lo]) / (F[lo + 1] - F[lo]);
    double y = ((double)lo + r) / (double)n;
    return y < 1.0 ? y : 1.0;
}

double geom__tess_warp_f(const double *F, int n, double y)
{
    if (!(y > 0.0))
        return 0.0;
    if (y >= 1.0)
        return 1.0;
    double x = y * (double)n;
    int i = (int)x;
    if (i >= n)
        i = n - 1;
    return F[i] + (x - (double)i) * (F[i + 1] - F[i]);
}
