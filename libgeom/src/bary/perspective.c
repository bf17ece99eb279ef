/*
 * Perspective-correct interpolation weights: lp[i] = (l[i]/w[i]) / sum_j
 * (l[j]/w[j]). The quotients are formed directly when they are in range;
 * otherwise as (significand, exponent) pairs scaled by a common power of two,
 * so that no quotient overflows even for w near the double range's ends.
 */
#include "bary/bary_internal.h"

#include <limits.h>

geom_status geom_bary_perspective(const double l[3], const double w[3], double lp[3])
{
    if (!lp)
        return GEOM_ERR_INVALID_ARG;
    if (!l || !w || !geom__isfinite3(l) || !geom__isfinite3(w)) {
        geom__bary_set3(lp, 0.0, 0.0, 0.0);
        return GEOM_ERR_INVALID_ARG;
    }
    if (w[0] == 0.0 || w[1] == 0.0 || w[2] == 0.0) {
        geom__bary_set3(lp, 0.0, 0.0, 0.0);
        return GEOM_ERR_DEGENERATE;
    }
    double q[3] = {l[0] / w[0], l[1] / w[1], l[2] / w[2]};
    double s = q[0] + q[1] + q[2];
    double big = fmax(fabs(q[0]), fmax(fabs(q[1]), fabs(q[2])));
    if (!(big < 0x1p1000 && (big > 0x1p-1000 || big == 0.0))) {
        /* Out of the comfortable range: rescale by a common power of two. */
        geom__xval x[3];
        int g = INT_MIN;
        for (int i = 0; i < 3; i++) {
            x[i] = geom__xval_div(geom__xval_from_double(l[i]), geom__xval_from_double(w[i]));
            if (x[i].m != 0.0 && x[i].e > g)
                g = x[i].e;
        }
        for (int i = 0; i < 3; i++)
            q[i] = x[i].m == 0.0 ? 0.0 : ldexp(x[i].m, x[i].e - g < -2000 ? -2000 : x[i].e - g);
        s = q[0] + q[1] + q[2];
    }
    if (s == 0.0 || !isfinite(s)) {
        geom__bary_set3(lp, 0.0, 0.0, 0.0);
        return GEOM_ERR_DEGENERATE;
    }
    geom__bary_set3(lp, q[0] / s, q[1] / s, q[2] / s);
    return GEOM_OK;
}
