/* NURBS surface points and partial derivatives (The NURBS Book A3.5, A3.6,
 * A4.3, A4.4), validation and the domain. */
#include "surface/surface_internal.h"

#include <float.h>

geom_status geom__surface_check_cheap(const geom_nurbs_surface *s)
{
    if (!s || !s->knots_u || !s->knots_v || !s->points)
        return GEOM_ERR_INVALID_ARG;
    if (s->degree_u < 1 || s->degree_v < 1)
        return GEOM_ERR_INVALID_ARG;
    if (s->nu < (size_t)s->degree_u + 1 || s->nv < (size_t)s->degree_v + 1)
        return GEOM_ERR_INVALID_ARG;
    return GEOM_OK;
}

/* Knot rules of one direction, through the curve validator (dimension 1,
 * its points only need to be finite: the surface's first n coordinates). */
static geom_status check_knots(const char *what, int p, size_t n, const double *U,
                               const double *pts, geom_diag *diag)
{
    size_t nk = n + (size_t)p + 1;
    geom_nurbs_curve c = {p, n, 1, U, pts, NULL};
    geom_diag d;
    geom_diag_clear(&d);
    geom_status st = geom_curve_nurbs_validate(&c, nk, &d);
    if (st != GEOM_OK)
        return geom__diag_set(diag, st, NULL, 0, 0, "surface: %s: %s", what, d.message);
    return GEOM_OK;
}

geom_status geom_surface_validate(const geom_nurbs_surface *s, geom_diag *diag)
{
    if (!s)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0, "surface: NULL surface");
    if (!s->knots_u || !s->knots_v || !s->points)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "surface: NULL knots or points");
    if (s->degree_u < 1 || s->degree_v < 1)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "surface: degrees (%d, %d) must be >= 1", s->degree_u, s->degree_v);
    if (s->nu < (size_t)s->degree_u + 1 || s->nv < (size_t)s->degree_v + 1)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "surface: %zu x %zu control points are too few for degrees "
                             "(%d, %d)",
                             s->nu, s->nv, s->degree_u, s->degree_v);
    size_t total;
    if (geom__size_mul(s->nu, s->nv, &total) != GEOM_OK || total > SIZE_MAX / 24)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                             "surface: %zu x %zu control points overflow", s->nu, s->nv);
    geom_status st = check_knots("knots_u", s->degree_u, s->nu, s->knots_u, s->points, diag);
    if (st != GEOM_OK)
        return st;
    st = check_knots("knots_v", s->degree_v, s->nv, s->knots_v, s->points, diag);
    if (st != GEOM_OK)
        return st;
    for (size_t i = 0; i < s->nu; ++i)
        for (size_t j = 0; j < s->nv; ++j) {
            const double *P = s->points + 3 * (i * s->nv + j);
            if (!geom__isfinite3(P))
                return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                                     "surface: points: point (%zu, %zu) is not finite", i, j);
            if (s->weights) {
                double w = s->weights[i * s->nv + j];
                if (!isfinite(w) || !(w > 0.0))
                    return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                                         "surface: weights: weight (%zu, %zu) is %.17g, not a "
                                         "finite value > 0",
                                         i, j, w);
            }
        }
    return GEOM_OK;
}

geom_status geom_surface_domain(const geom_nurbs_surface *s, double domain[4])
{
    if (geom__surface_check_cheap(s) != GEOM_OK || !domain)
        return GEOM_ERR_INVALID_ARG;
    domain[0] = s->knots_u[s->degree_u];
    domain[1] = s->knots_u[s->nu];
    domain[2] = s->knots_v[s->degree_v];
    domain[3] = s->knots_v[s->nv];
    return GEOM_OK;
}

geom_status geom__surface_locate(const geom_nurbs_surface *s, double u, double v, unsigned flags,
                                size_t *ku, size_t *kv)
{
    double ue, ve;
    int lu, lv;
    geom_status st = geom__bs_param(s->degree_u, s->nu, s->knots_u, u, 0,
                                    (flags & GEOM_SURFACE_U_LEFT) != 0, &ue, &lu);
    if (st != GEOM_OK)
        return st;
    st = geom__bs_param(s->degree_v, s->nv, s->knots_v, v, 0, (flags & GEOM_SURFACE_V_LEFT) != 0,
                        &ve, &lv);
    if (st != GEOM_OK)
        return st;
    *ku = geom__bs_span(s->degree_u, s->nu, s->knots_u, ue, lu);
    *kv = geom__bs_span(s->degree_v, s->nv, s->knots_v, ve, lv);
    return GEOM_OK;
}

size_t geom__surface_point_work(const geom_nurbs_surface *s)
{
    size_t p1 = (size_t)s->degree_u + 1, q1 = (size_t)s->degree_v + 1;
    return p1 + q1 + geom__bs_basis_work(s->degree_u > s->degree_v ? s->degree_u
                                                                          : s->degree_v);
}

/* sum R_ij P_ij from the basis values Nu (p+1) and Nv (q+1) of spans
 * (ku, kv): exact control points where both are one-hot. */
static void combine_point(const geom_nurbs_surface *s, size_t ku, size_t kv, const double *Nu,
                          const double *Nv, double *out)
{
    int p = s->degree_u, q = s->degree_v;
    size_t i0 = ku - (size_t)p, j0 = kv - (size_t)q, nv = s->nv;
    out[0] = out[1] = out[2] = 0.0;
    if (s->weights) {
        double W = 0.0;
        for (int i = 0; i <= p; ++i)
            for (int j = 0; j <= q; ++j)
                W += Nu[i] * Nv[j] * s->weights[(i0 + (size_t)i) * nv + j0 + (size_t)j];
        for (int i = 0; i <= p; ++i)
            for (int j = 0; j <= q; ++j) {
                size_t idx = (i0 + (size_t)i) * nv + j0 + (size_t)j;
                double R = (Nu[i] * Nv[j] * s->weights[idx]) / W;
                const double *P = s->points + 3 * idx;
                out[0] += R * P[0];
                out[1] += R * P[1];
                out[2] += R * P[2];
            }
    } else {
        for (int i = 0; i <= p; ++i) {
            double t[3] = {0.0, 0.0, 0.0};
            const double *P = s->points + 3 * ((i0 + (size_t)i) * nv + j0);
            for (int j = 0; j <= q; ++j, P += 3) {
                t[0] += Nv[j] * P[0];
                t[1] += Nv[j] * P[1];
                t[2] += Nv[j] * P[2];
            }
            out[0] += Nu[i] * t[0];
            out[1] += Nu[i] * t[1];
            out[2] += Nu[i] * t[2];
        }
    }
}

void geom__surface_span_point(const geom_nurbs_surface *s, size_t ku, size_t kv, double u,
                             double v, double out[3], double *work)
{
    int p = s->degree_u, q = s->degree_v;
    double *Nu = work, *Nv = work + p + 1, *w2 = Nv + q + 1;
    geom__bs_basis(p, s->knots_u, ku, u, Nu, w2);
    geom__bs_basis(q, s->knots_v, kv, v, Nv, w2);
    combine_point(s, ku, kv, Nu, Nv, out);
}

void geom__surface_span_combine(const geom_nurbs_surface *s, size_t ku, size_t kv, const double *Nu,
                               const double *Nv, double out[3])
{
    combine_point(s, ku, kv, Nu, Nv, out);
}

size_t geom__surface_derivs_work(const geom_nurbs_surface *s, int d)
{
    size_t p1 = (size_t)s->degree_u + 1, q1 = (size_t)s->degree_v + 1;
    size_t d1 = (size_t)d + 1;
    size_t du = (size_t)(d < s->degree_u ? d : s->degree_u) + 1;
    size_t dv = (size_t)(d < s->degree_v ? d : s->degree_v) + 1;
    int pm = s->degree_u > s->degree_v ? s->degree_u : s->degree_v;
    /* Nu ders, Nv ders, basis work, partial sums (du+1)(q+1)*4,
     * homogeneous table d1*d1*4 */
    return du * p1 + dv * q1 + geom__bs_ders_work(pm) + 4 * du * q1 + 4 * d1 * d1;
}

void geom__surface_span_derivs(const geom_nurbs_surface *s, size_t ku, size_t kv, double u,
                              double v, int d, double *ders, double *work)
{
    int p = s->degree_u, q = s->degree_v;
    size_t p1 = (size_t)p + 1, q1 = (size_t)q + 1, d1 = (size_t)d + 1;
    int du = d < p ? d : p, dv = d < q ? d : q;
    int pm = p > q ? p : q;
    double *Nu = work;                              /* (du+1)*(p+1) */
    double *Nv = Nu + (size_t)(du + 1) * p1;        /* (dv+1)*(q+1) */
    double *bw = Nv + (size_t)(dv + 1) * q1;        /* basis work */
    double *net = bw + geom__bs_ders_work(pm); /* (du+1)(q+1)*4 */
    double *H = net + 4 * (size_t)(du + 1) * q1;    /* d1*d1*4 homogeneous table */
    geom__bs_ders(p, s->knots_u, ku, u, du, Nu, bw);
    geom__bs_ders(q, s->knots_v, kv, v, dv, Nv, bw);
    size_t i0 = ku - (size_t)p, j0 = kv - (size_t)q, nv = s->nv;
    const double *Pref = s->points + 3 * (i0 * nv + j0);
    int rational = s->weights != NULL;
    /* T_k[j] = sum_i N_i^(k)(u) Pw_ij with Pw the span's homogeneous net
     * relative to its first point (w (P - P_ref), w), then
     * H(k, l) = sum_j M_j^(l)(v) T_k[j]. D = 3 for polynomial surfaces. */
    size_t D = rational ? 4 : 3;
    double *Tk = net; /* (du+1) * (q+1) * D, in place of the net */
    for (size_t t = 0; t < (size_t)(du + 1) * q1 * D; ++t)
        Tk[t] = 0.0;
    for (int i = 0; i <= p; ++i) {
        const double *P = s->points + 3 * ((i0 + (size_t)i) * nv + j0);
        const double *wr = rational ? s->weights + (i0 + (size_t)i) * nv + j0 : NULL;
        for (int j = 0; j <= q; ++j, P += 3) {
            double w = rational ? wr[j] : 1.0;
            double x = w * (P[0] - Pref[0]), y = w * (P[1] - Pref[1]), z = w * (P[2] - Pref[2]);
            for (int k = 0; k <= du; ++k) {
                double b = Nu[(size_t)k * p1 + (size_t)i];
                double *T = Tk + ((size_t)k * q1 + (size_t)j) * D;
                T[0] += b * x;
                T[1] += b * y;
                T[2] += b * z;
                if (rational)
                    T[3] += b * w;
            }
        }
    }
    for (size_t t = 0; t < 4 * d1 * d1; ++t)
        H[t] = 0.0;
    for (int k = 0; k <= du; ++k)
        for (int l = 0; l <= dv && k + l <= d; ++l) {
            double *A = H + 4 * ((size_t)k * d1 + (size_t)l);
            const double *bv = Nv + (size_t)l * q1;
            const double *T = Tk + (size_t)k * q1 * D;
            double a0 = 0.0, a1 = 0.0, a2 = 0.0, a3 = 0.0;
            for (int j = 0; j <= q; ++j, T += D) {
                double b = bv[j];
                a0 += b * T[0];
                a1 += b * T[1];
                a2 += b * T[2];
                if (rational)
                    a3 += b * T[3];
            }
            A[0] = a0, A[1] = a1, A[2] = a2, A[3] = a3;
        }
    for (size_t t = 0; t < 3 * d1 * d1; ++t)
        ders[t] = 0.0;
    if (!rational) {
        for (int k = 0; k <= d; ++k)
            for (int l = 0; k + l <= d; ++l)
                for (int c = 0; c < 3; ++c)
                    ders[3 * ((size_t)k * d1 + (size_t)l) + (size_t)c] =
                        H[4 * ((size_t)k * d1 + (size_t)l) + (size_t)c];
    } else {
        /* A4.4 on the local coordinates */
        double w0 = H[3];
#define HW(k, l) H[4 * ((size_t)(k)*d1 + (size_t)(l)) + 3]
#define SK(k, l, c) ders[3 * ((size_t)(k)*d1 + (size_t)(l)) + (size_t)(c)]
        for (int k = 0; k <= d; ++k)
            for (int l = 0; k + l <= d; ++l) {
                double vv[3];
                for (int c = 0; c < 3; ++c)
                    vv[c] = H[4 * ((size_t)k * d1 + (size_t)l) + (size_t)c];
                for (int j = 1; j <= l; ++j) {
                    double b = (j == 1 ? (double)l : geom__binom(l, j)) * HW(0, j);
                    for (int c = 0; c < 3; ++c)
                        vv[c] -= b * SK(k, l - j, c);
                }
                for (int i = 1; i <= k; ++i) {
                    double bi = i == 1 ? (double)k : geom__binom(k, i);
                    double b = bi * HW(i, 0);
                    for (int c = 0; c < 3; ++c)
                        vv[c] -= b * SK(k - i, l, c);
                    double v2[3] = {0.0, 0.0, 0.0};
                    for (int j = 1; j <= l; ++j) {
                        double bj = (j == 1 ? (double)l : geom__binom(l, j)) * HW(i, j);
                        for (int c = 0; c < 3; ++c)
                            v2[c] += bj * SK(k - i, l - j, c);
                    }
                    for (int c = 0; c < 3; ++c)
                        vv[c] -= bi * v2[c];
                }
                for (int c = 0; c < 3; ++c)
                    SK(k, l, c) = vv[c] / w0;
            }
#undef HW
#undef SK
    }
    /* the point itself, without the offset, from row 0 of the basis
     * derivatives (the same values as geom__bs_basis) */
    combine_point(s, ku, kv, Nu, Nv, ders);
}

geom_status geom_surface_eval(const geom_nurbs_surface *s, double u, double v, unsigned flags,
                              double out[3])
{
    if (geom__surface_check_cheap(s) != GEOM_OK || !out)
        return GEOM_ERR_INVALID_ARG;
    size_t ku, kv;
    geom_status st = geom__surface_locate(s, u, v, flags, &ku, &kv);
    if (st != GEOM_OK)
        return st;
    geom__scratch sc;
    st = geom__scratch_init(&sc, geom__surface_point_work(s));
    if (st == GEOM_OK)
        geom__surface_span_point(s, ku, kv, u, v, out, sc.mem);
    geom__scratch_free(&sc);
    return st;
}

geom_status geom_surface_derivs(const geom_nurbs_surface *s, double u, double v, int d,
                                unsigned flags, double *ders)
{
    if (geom__surface_check_cheap(s) != GEOM_OK || !ders || d < 0)
        return GEOM_ERR_INVALID_ARG;
    if (d > GEOM_SURFACE_MAX_DERIV)
        return GEOM_ERR_LIMIT;
    size_t ku, kv;
    geom_status st = geom__surface_locate(s, u, v, flags, &ku, &kv);
    if (st != GEOM_OK)
        return st;
    geom__scratch sc;
    st = geom__scratch_init(&sc, geom__surface_derivs_work(s, d));
    if (st == GEOM_OK)
        geom__surface_span_derivs(s, ku, kv, u, v, d, ders, sc.mem);
    geom__scratch_free(&sc);
    return st;
}
