/*
 * The one root finder of the library's contouring (marching squares in
 * geom_implicit_contour, marching cubes' --refine in geom_iso_extract):
 * Illinois regula falsi on a bracket, safeguarded by bisection, with one
 * stopping rule.
 */
#include "implicit/implicit_internal.h"

#include <math.h>

double geom_implicit_bracket_root(geom_implicit_root_fn fn, void *user, double a, double b,
                                  double fa, double fb, double x, int max_iterations,
                                  size_t *evaluations)
{
    if (!fn || !(a < b))
        return x;
    double lo = a, hi = b, flo = fa, fhi = fb; /* scaled by Illinois */
    double tlo = fa, thi = fb;                  /* true values */
    int side = 0;
    double width_prev2 = 2.0 * (b - a), width_prev1 = b - a;
    for (int it = 0; it < max_iterations; it++) {
        if (!(x > lo && x < hi))
            x = lo + 0.5 * (hi - lo);
        if (!(x > lo && x < hi))
            break; /* lo and hi are adjacent doubles */
        double fx = fn(user, x);
        if (evaluations)
            (*evaluations)++;
        if (isnan(fx))
            break;
        if (fx == 0.0)
            return x;
        if ((fx < 0.0) == (tlo < 0.0)) {
            lo = x;
            flo = tlo = fx;
            if (side == -1)
                fhi *= 0.5;
            side = -1;
        } else {
            hi = x;
            fhi = thi = fx;
            if (side == 1)
                flo *= 0.5;
            side = 1;
        }
        double w = hi - lo;
        if (!(nextafter(lo, hi) < hi))
            break;
        /* Bisect when the bracket has not halved over two steps. */
        if (w > 0.5 * width_prev2 || !isfinite(flo) || !isfinite(fhi))
            x = lo + 0.5 * w;
        else
            x = lo - flo * (w / (fhi - flo));
        width_prev2 = width_prev1;
        width_prev1 = w;
    }
    /* The end of the final bracket with the smaller |f| (never an end of
     * the interval, where f is not zero); for a smooth f the bracket ends
     * are adjacent doubles, for a jump they straddle it. */
    int lo_ok = lo > a, hi_ok = hi < b;
    if (lo_ok && hi_ok)
        return fabs(tlo) <= fabs(thi) ? lo : hi;
    if (lo_ok)
        return lo;
    if (hi_ok)
        return hi;
    return x > a && x < b ? x : a + 0.5 * (b - a);
}
