/*
 * Wachspress coordinates (Wachspress 1975; the formulation of Meyer, Barr,
 * Lee and Desbrun, "Generalized barycentric coordinates on irregular
 * polygons", JGT 7 (2002)): for a strictly convex polygon and p inside,
 *     w_i = C_i / (A_{i-1} A_i),
 * with C_i = orient2d(v_{i-1}, v_i, v_{i+1}) and A_i = orient2d(v_i, v_{i+1}, p)
 * (twice the signed areas), normalised to sum 1. Every orient2d is evaluated
 * with the exact sign and relative error <= 2^-46; the weights are carried as
 * (significand, exponent) pairs so they do not overflow next to the boundary.
 * Exactly on an edge (A_i == 0 exactly): the edge's linear interpolation
 * weights; at a vertex: the unit vector.
 */
#include "bary/bary_internal.h"

#include <limits.h>

/* One pass: w[i] = W_i * 2^-shift (sign-normalised), *gmax the largest
 * exponent. Sets *outside if some A_i has the wrong sign and *edge to 1 +
 * the first i with A_i == 0. */
static void wp_pass(size_t n, const double *poly, const double p[2], int orient, int shift,
                    double *w, int *gmax, int *outside, size_t *edge)
{
    const double *v = poly;
    geom__xval alast = geom__bary_orient2d_acc(v + 2 * (n - 1), v, p);
    geom__xval aprev = alast;
    *gmax = INT_MIN;
    *outside = 0;
    *edge = 0;
    for (size_t i = 0; i < n; i++) {
        size_t h = i == 0 ? n - 1 : i - 1, j = i + 1 == n ? 0 : i + 1;
        geom__xval ai = i + 1 == n ? alast : geom__bary_orient2d_acc(v + 2 * i, v + 2 * j, p);
        if (ai.m * orient < 0.0) {
            *outside = 1;
            return;
        }
        if (ai.m == 0.0 && *edge == 0)
            *edge = i + 1;
        if (ai.m != 0.0 && aprev.m != 0.0) {
            geom__xval ci = geom__bary_orient2d_acc(v + 2 * h, v + 2 * i, v + 2 * j);
            geom__xval wi = geom__xval_div(ci, geom__xval_mul(aprev, ai));
            wi.m = fabs(wi.m); /* the sign of C_i / (A A) is orient's */
            if (wi.e > *gmax)
                *gmax = wi.e;
            wi.e -= shift;
            w[i] = ldexp(wi.m, wi.e < -2000 ? -2000 : wi.e);
        } else {
            w[i] = 0.0;
        }
        aprev = ai;
    }
}

geom_status geom_bary_wachspress(size_t n, const double *poly, const double p[2], double *w)
{
    geom_status st = geom__bary_poly_check(n, poly, p, w);
    if (st != GEOM_OK)
        return st;
    /* Turn signs: collinear consecutive vertices (including repeated ones)
     * are degenerate; mixed signs are not convex. */
    int orient = 0, mixed = 0;
    for (size_t i = 0; i < n; i++) {
        size_t h = i == 0 ? n - 1 : i - 1, j = i + 1 == n ? 0 : i + 1;
        double o = geom_orient2d(poly + 2 * h, poly + 2 * i, poly + 2 * j);
        if (o == 0.0)
            return GEOM_ERR_DEGENERATE;
        int s = o > 0.0 ? 1 : -1;
        if (orient == 0)
            orient = s;
        else if (s != orient)
            mixed = 1;
    }
    if (mixed)
        return GEOM_ERR_DOMAIN;
    /* All turns agree; the polygon is simple (turns once) iff the sign of
     * the edges' x direction changes exactly twice around it. */
    int first = 0, last = 0, flips = 0;
    for (size_t i = 0; i < n; i++) {
        size_t j = i + 1 == n ? 0 : i + 1;
        double x0 = poly[2 * i], x1 = poly[2 * j];
        int s = x1 > x0 ? 1 : (x1 < x0 ? -1 : 0);
        if (s == 0)
            continue;
        if (first == 0)
            first = s;
        else if (s != last)
            flips++;
        last = s;
    }
    if (last != first)
        flips++;
    if (flips > 2)
        return GEOM_ERR_DOMAIN;
    for (size_t i = 0; i < n; i++) {
        if (geom__bary_same2(p, poly + 2 * i)) {
            w[i] = 1.0;
            return GEOM_OK;
        }
    }
    int g, outside;
    size_t edge;
    wp_pass(n, poly, p, orient, 0, w, &g, &outside, &edge);
    if (outside) {
        geom__bary_zero(w, n);
        return GEOM_ERR_DOMAIN;
    }
    if (edge) {
        size_t i = edge - 1, j = edge == n ? 0 : edge;
        geom__bary_zero(w, n);
        geom__bary_edge_weights(poly + 2 * i, poly + 2 * j, p, &w[i], &w[j]);
        return GEOM_OK;
    }
    if (g != INT_MIN && (g > 1000 || g < -900))
        wp_pass(n, poly, p, orient, g, w, &g, &outside, &edge);
    if (!geom__bary_normalise(n, w)) {
        geom__bary_zero(w, n);
        return GEOM_ERR_DEGENERATE;
    }
    return GEOM_OK;
}
