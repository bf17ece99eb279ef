/*
 * Barycentric coordinates in a tetrahedron: l[i] = N_i / D with
 * D = orient3d(a, b, c, d) = det[a-d; b-d; c-d] and N_i the same determinant
 * with p in place of vertex i. Fast path: Shewchuk's orient3d error bound,
 * each determinant accepted only with a certified relative error <= 2^-42;
 * whatever the filter cannot certify is evaluated exactly (expansions).
 */
#include "bary/bary_internal.h"

static void set4(double l[4], double x, double y, double z, double w)
{
    l[0] = x;
    l[1] = y;
    l[2] = z;
    l[3] = w;
}

geom_status geom_bary_tet(const double a[3], const double b[3], const double c[3],
                          const double d[3], const double p[3], double l[4])
{
    if (!l)
        return GEOM_ERR_INVALID_ARG;
    if (!a || !b || !c || !d || !p || !geom__isfinite3(a) || !geom__isfinite3(b) ||
        !geom__isfinite3(c) || !geom__isfinite3(d) || !geom__isfinite3(p)) {
        set4(l, 0.0, 0.0, 0.0, 0.0);
        return GEOM_ERR_INVALID_ARG;
    }
    double vol, nv[4];
    const double *q[4][4] = {{p, b, c, d}, {a, p, c, d}, {a, b, p, d}, {a, b, c, p}};
    /* p == a (b, c, d) makes N_a (N_b, ...) the very expression of D. */
    unsigned slow = geom__bary_det3(a, b, c, d, &vol) ? 0u : 16u;
    for (int i = 0; i < 4; i++)
        if (!geom__bary_det3(q[i][0], q[i][1], q[i][2], q[i][3], &nv[i]))
            slow |= 1u << i;
    if (!slow) {
        set4(l, geom__bary_quot(nv[0], vol), geom__bary_quot(nv[1], vol),
             geom__bary_quot(nv[2], vol), geom__bary_quot(nv[3], vol));
        return GEOM_OK;
    }
    /* Evaluate exactly what the filter could not certify. */
    geom__xval xd = (slow & 16u) ? geom__xeval_orient3d(a, b, c, d) : geom__xval_from_double(vol);
    if (xd.m == 0.0) {
        set4(l, 0.0, 0.0, 0.0, 0.0);
        return GEOM_ERR_DEGENERATE;
    }
    const double *v[4] = {a, b, c, d};
    for (int i = 0; i < 4; i++) {
        if (geom__bary_same3(p, v[i])) {
            set4(l, 0.0, 0.0, 0.0, 0.0);
            l[i] = 1.0;
            return GEOM_OK;
        }
    }
    for (int i = 0; i < 4; i++) {
        geom__xval xn = (slow & (1u << i))
                           ? geom__xeval_orient3d(q[i][0], q[i][1], q[i][2], q[i][3])
                           : geom__xval_from_double(nv[i]);
        l[i] = geom__xval_ratio(xn, xd);
    }
    return GEOM_OK;
}
