/* NURBS curve points and derivatives (The NURBS Book A3.1, A3.2, A4.1,
 * A4.2), curvature and torsion. */
#include "curve/bspline_basis.h"

void geom__curve_hderivs(const geom_nurbs_curve *c, size_t k, double u, int nd, double *out,
                        double *work)
{
    int p = c->degree;
    size_t q = (size_t)p + 1, D = geom__curve_hdim(c);
    double *ders = work;
    double *w2 = work + (size_t)(nd + 1) * q;
    geom__bs_ders(p, c->knots, k, u, nd, ders, w2);
    for (size_t i = 0; i < (size_t)(nd + 1) * D; ++i)
        out[i] = 0.0;
    double h[GEOM_CURVE_HDIM_MAX];
    for (size_t j = 0; j < q; ++j) {
        geom__curve_hget(c, k - (size_t)p + j, h);
        for (int r = 0; r <= nd && r <= p; ++r) {
            double b = ders[(size_t)r * q + j];
            for (size_t d = 0; d < D; ++d)
                out[(size_t)r * D + d] += b * h[d];
        }
    }
}

/* sum_j R_j P_j with R_j = N_j w_j / W (or N_j P_j): exact control points
 * where the basis is exactly one-hot. */
static void combine_point(const geom_nurbs_curve *c, size_t k, const double *N, double *out)
{
    int p = c->degree;
    size_t dim = c->dim;
    for (size_t d = 0; d < dim; ++d)
        out[d] = 0.0;
    size_t first = k - (size_t)p;
    if (c->weights) {
        double W = 0.0;
        for (int j = 0; j <= p; ++j)
            W += N[j] * c->weights[first + (size_t)j];
        for (int j = 0; j <= p; ++j) {
            double R = (N[j] * c->weights[first + (size_t)j]) / W;
            const double *P = c->points + (first + (size_t)j) * dim;
            for (size_t d = 0; d < dim; ++d)
                out[d] += R * P[d];
        }
    } else {
        for (int j = 0; j <= p; ++j) {
            const double *P = c->points + (first + (size_t)j) * dim;
            for (size_t d = 0; d < dim; ++d)
                out[d] += N[j] * P[d];
        }
    }
}

geom_status geom_curve_nurbs_eval(const geom_nurbs_curve *c, double u, unsigned flags, double *out)
{
    geom_status st = geom__curve_check_cheap(c);
    if (st != GEOM_OK || !out)
        return GEOM_ERR_INVALID_ARG;
    double ue;
    size_t k;
    st = geom__curve_locate_knots(c->degree, c->n, c->knots, u, flags, &ue, &k);
    if (st != GEOM_OK)
        return st;
    size_t q = (size_t)c->degree + 1;
    geom__scratch s;
    st = geom__scratch_init(&s, q + geom__bs_basis_work(c->degree));
    if (st == GEOM_OK) {
        geom__bs_basis(c->degree, c->knots, k, ue, s.mem, s.mem + q);
        combine_point(c, k, s.mem, out);
    }
    geom__scratch_free(&s);
    return st;
}

void geom__curve_span_derivs(const geom_nurbs_curve *c, size_t k, double u, int nd, double *ders,
                            double *work)
{
    size_t D = geom__curve_hdim(c), nd1 = (size_t)nd + 1;
    double *hd = work, *w2 = work + nd1 * D;
    geom__curve_hderivs(c, k, u, nd, hd, w2);
    if (!c->weights) {
        memcpy(ders, hd, nd1 * c->dim * sizeof(double));
        return;
    }
    /* The point from the rational basis (row 0 of the basis derivatives
     * left in w2), so that it matches geom_curve_nurbs_eval exactly; then
     * the A4.2 recurrence with that point. */
    combine_point(c, k, w2, ders);
    size_t dim = c->dim;
    double w0 = hd[dim];
    for (int kk = 1; kk <= nd; ++kk) {
        double v[GEOM_CURVE_MAX_DIM];
        for (size_t d = 0; d < dim; ++d)
            v[d] = hd[(size_t)kk * D + d];
        double bin = 1.0;
        for (int i = 1; i <= kk; ++i) {
            bin = bin * (double)(kk - i + 1) / (double)i;
            double wi = hd[(size_t)i * D + dim];
            for (size_t d = 0; d < dim; ++d)
                v[d] -= bin * wi * ders[(size_t)(kk - i) * dim + d];
        }
        for (size_t d = 0; d < dim; ++d)
            ders[(size_t)kk * dim + d] = v[d] / w0;
    }
}

geom_status geom_curve_nurbs_derivs(const geom_nurbs_curve *c, double u, int nderiv, unsigned flags,
                                    double *ders)
{
    geom_status st = geom__curve_check_cheap(c);
    if (st != GEOM_OK || !ders || nderiv < 0)
        return GEOM_ERR_INVALID_ARG;
    if (nderiv > 4096)
        return GEOM_ERR_LIMIT;
    double ue;
    size_t k;
    st = geom__curve_locate_knots(c->degree, c->n, c->knots, u, flags, &ue, &k);
    if (st != GEOM_OK)
        return st;
    geom__scratch s;
    st = geom__scratch_init(&s, geom__curve_span_derivs_work(c, nderiv));
    if (st == GEOM_OK)
        geom__curve_span_derivs(c, k, ue, nderiv, ders, s.mem);
    geom__scratch_free(&s);
    return st;
}

geom_status geom_curve_nurbs_domain(const geom_nurbs_curve *c, double *u0, double *u1)
{
    if (geom__curve_check_cheap(c) != GEOM_OK)
        return GEOM_ERR_INVALID_ARG;
    if (u0)
        *u0 = c->knots[c->degree];
    if (u1)
        *u1 = c->knots[c->n];
    return GEOM_OK;
}

/* |a x b|^2 in any dimension by Lagrange's identity written as a sum of
 * 2x2 minors (no cancellation between two large terms). */
static double cross_norm2(const double *a, const double *b, size_t dim)
{
    double s = 0.0;
    for (size_t i = 0; i < dim; ++i)
        for (size_t j = i + 1; j < dim; ++j) {
            double m = a[i] * b[j] - a[j] * b[i];
            s += m * m;
        }
    return s;
}

geom_status geom_curve_nurbs_curvature(const geom_nurbs_curve *c, double u, unsigned flags,
                                       double *curvature, double *torsion)
{
    geom_status st = geom__curve_check_cheap(c);
    if (st != GEOM_OK || !curvature)
        return GEOM_ERR_INVALID_ARG;
    size_t dim = c->dim;
    if (torsion && dim != 2 && dim != 3)
        return GEOM_ERR_INVALID_ARG;
    double d[4 * GEOM_CURVE_MAX_DIM];
    int nd = (torsion && dim == 3) ? 3 : 2;
    st = geom_curve_nurbs_derivs(c, u, nd, flags, d);
    if (st != GEOM_OK)
        return st;
    const double *d1 = d + dim, *d2 = d + 2 * dim;
    double s2 = 0.0;
    for (size_t i = 0; i < dim; ++i)
        s2 += d1[i] * d1[i];
    if (!(s2 > 0.0))
        return GEOM_ERR_DEGENERATE;
    double speed = sqrt(s2);
    double s3 = s2 * speed;
    if (dim == 2) {
        *curvature = (d1[0] * d2[1] - d1[1] * d2[0]) / s3;
        if (torsion)
            *torsion = 0.0;
    } else {
        double cn2 = cross_norm2(d1, d2, dim);
        *curvature = sqrt(cn2) / s3;
        if (torsion) {
            const double *d3 = d + 3 * dim;
            double cx = d1[1] * d2[2] - d1[2] * d2[1];
            double cy = d1[2] * d2[0] - d1[0] * d2[2];
            double cz = d1[0] * d2[1] - d1[1] * d2[0];
            double n2 = cx * cx + cy * cy + cz * cz;
            *torsion = n2 > 0.0 ? (cx * d3[0] + cy * d3[1] + cz * d3[2]) / n2 : 0.0;
        }
    }
    return GEOM_OK;
}
