/*
 * Barycentric coordinates in a 2D triangle: l[i] = N_i / D with
 * D = orient2d(a, b, c) and N_i the same determinant with p in place of
 * vertex i. Fast path: the four determinants in floating point, each
 * accepted only with a certified relative error <= 2^-42; the ones the
 * filter cannot certify are evaluated exactly (expansions), and the ratios
 * rounded.
 */
#include "bary/bary_internal.h"

geom_status geom_bary_tri2(const double a[2], const double b[2], const double c[2],
                           const double p[2], double l[3])
{
    if (!l)
        return GEOM_ERR_INVALID_ARG;
    if (!a || !b || !c || !p) {
        geom__bary_set3(l, 0.0, 0.0, 0.0);
        return GEOM_ERR_INVALID_ARG;
    }
    if (!geom__bary_finite(a, 2) || !geom__bary_finite(b, 2) || !geom__bary_finite(c, 2) ||
        !geom__bary_finite(p, 2)) {
        geom__bary_set3(l, 0.0, 0.0, 0.0);
        return GEOM_ERR_INVALID_ARG;
    }
    double acx = a[0] - c[0], acy = a[1] - c[1];
    double bcx = b[0] - c[0], bcy = b[1] - c[1];
    double pcx = p[0] - c[0], pcy = p[1] - c[1];
    double apx = a[0] - p[0], apy = a[1] - p[1];
    double bpx = b[0] - p[0], bpy = b[1] - p[1];
    double d, nv[3];
    /* Written so that p == a (b, c) gives the very expression of D for N0
     * (N1, N2): the ratio is then exactly 1. */
    unsigned slow = 0; /* bit i: N_i uncertified; bit 3: D */
    if (!geom__bary_det2(acx, bcy, acy, bcx, GEOM_BARY_REL, &d)) /* (a,b,c) */
        slow |= 8u;
    if (!geom__bary_det2(pcx, bcy, pcy, bcx, GEOM_BARY_REL, &nv[0])) /* (p,b,c) */
        slow |= 1u;
    if (!geom__bary_det2(acx, pcy, acy, pcx, GEOM_BARY_REL, &nv[1])) /* (a,p,c) */
        slow |= 2u;
    if (!geom__bary_det2(apx, bpy, apy, bpx, GEOM_BARY_REL, &nv[2])) /* (a,b,p) */
        slow |= 4u;
    if (!slow) {
        if (d == 0.0) {
            geom__bary_set3(l, 0.0, 0.0, 0.0);
            return GEOM_ERR_DEGENERATE;
        }
        geom__bary_set3(l, geom__bary_quot(nv[0], d), geom__bary_quot(nv[1], d),
                        geom__bary_quot(nv[2], d));
        return GEOM_OK;
    }
    /* Evaluate exactly what the filter could not certify. */
    geom__xval xd = (slow & 8u) ? geom__xeval_orient2d(a, b, c) : geom__xval_from_double(d);
    if (xd.m == 0.0) {
        geom__bary_set3(l, 0.0, 0.0, 0.0);
        return GEOM_ERR_DEGENERATE;
    }
    if (geom__bary_same2(p, a)) {
        geom__bary_set3(l, 1.0, 0.0, 0.0);
        return GEOM_OK;
    }
    if (geom__bary_same2(p, b)) {
        geom__bary_set3(l, 0.0, 1.0, 0.0);
        return GEOM_OK;
    }
    if (geom__bary_same2(p, c)) {
        geom__bary_set3(l, 0.0, 0.0, 1.0);
        return GEOM_OK;
    }
    const double *q[3][3] = {{p, b, c}, {a, p, c}, {a, b, p}};
    for (int i = 0; i < 3; i++) {
        geom__xval xn = (slow & (1u << i)) ? geom__xeval_orient2d(q[i][0], q[i][1], q[i][2])
                                          : geom__xval_from_double(nv[i]);
        l[i] = geom__xval_ratio(xn, xd);
    }
    return GEOM_OK;
}
