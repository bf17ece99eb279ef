/*
 * Barycentric coordinates of the orthogonal projection of p onto the plane of
 * a 3D triangle: l[i] = (n . n_i) / (n . n), n = (b-a) x (c-a), n_i the normal
 * of the sub-triangle opposite vertex i with p in place of vertex i. Both
 * are degree-4 polynomials in the input. Fast path in floating point with a
 * running-error bound (each degree-4 term passes through at most 11
 * roundings, so the error is below 12 eps times the same sum of absolute
 * values); whatever the filter cannot certify is evaluated exactly
 * (expansions).
 */
#include "bary/bary_internal.h"

geom_status geom_bary_tri3(const double a[3], const double b[3], const double c[3],
                           const double p[3], double l[3])
{
    if (!l)
        return GEOM_ERR_INVALID_ARG;
    if (!a || !b || !c || !p || !geom__isfinite3(a) || !geom__isfinite3(b) || !geom__isfinite3(c) ||
        !geom__isfinite3(p)) {
        geom__bary_set3(l, 0.0, 0.0, 0.0);
        return GEOM_ERR_INVALID_ARG;
    }
    double u[3], v[3], e0[3], f0[3], e1[3], f1[3], f2[3];
    for (int k = 0; k < 3; k++) {
        u[k] = b[k] - a[k];
        v[k] = c[k] - a[k];
        e0[k] = c[k] - b[k];
        f0[k] = p[k] - b[k];
        e1[k] = a[k] - c[k];
        f1[k] = p[k] - c[k];
        f2[k] = p[k] - a[k];
    }
    double n[3], na[3], m[3], ma[3], d, nv[3];
    geom__bary_cross_abs(u, v, n, na);
    unsigned slow = 0; /* bit i: numerator i uncertified; bit 3: denominator */
    if (!geom__bary_dot3_ok(n, na, n, na, &d))
        slow |= 8u;
    geom__bary_cross_abs(e0, f0, m, ma);
    if (!geom__bary_dot3_ok(n, na, m, ma, &nv[0]))
        slow |= 1u;
    geom__bary_cross_abs(e1, f1, m, ma);
    if (!geom__bary_dot3_ok(n, na, m, ma, &nv[1]))
        slow |= 2u;
    geom__bary_cross_abs(u, f2, m, ma);
    if (!geom__bary_dot3_ok(n, na, m, ma, &nv[2]))
        slow |= 4u;
    if (!slow) {
        geom__bary_set3(l, geom__bary_quot(nv[0], d), geom__bary_quot(nv[1], d),
                        geom__bary_quot(nv[2], d));
        return GEOM_OK;
    }
    /* Evaluate exactly what the filter could not certify. */
    geom__xval num[3], den;
    geom__xeval_tri3(a, b, c, p, slow, num, &den);
    if (!(slow & 8u))
        den = geom__xval_from_double(d);
    if (den.m == 0.0) {
        geom__bary_set3(l, 0.0, 0.0, 0.0);
        return GEOM_ERR_DEGENERATE;
    }
    if (geom__bary_same3(p, a)) {
        geom__bary_set3(l, 1.0, 0.0, 0.0);
    } else if (geom__bary_same3(p, b)) {
        geom__bary_set3(l, 0.0, 1.0, 0.0);
    } else if (geom__bary_same3(p, c)) {
        geom__bary_set3(l, 0.0, 0.0, 1.0);
    } else {
        for (int i = 0; i < 3; i++)
            l[i] = (slow & (1u << i)) ? geom__xval_ratio(num[i], den)
                                      : geom__xval_ratio(geom__xval_from_double(nv[i]), den);
    }
    return GEOM_OK;
}
