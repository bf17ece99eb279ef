/* B-spline span search and basis functions (The NURBS Book A2.1-A2.3). */
#include "curve/bspline_basis.h"

size_t geom_curve_bs_span(int p, size_t n, const double *U, double u, int left)
{
    size_t lo = (size_t)p, hi = n - 1;
    if (left && u > U[p] && u < U[n]) {
        /* smallest k with U[k+1] >= u: then U[k] < u <= U[k+1] */
        while (lo < hi) {
            size_t mid = lo + (hi - lo) / 2;
            if (U[mid + 1] >= u)
                hi = mid;
            else
                lo = mid + 1;
        }
        return lo;
    }
    if (u >= U[n]) {
        /* last non-empty span: largest k with U[k] < U[n] */
        double v = U[n];
        while (lo < hi) {
            size_t mid = lo + (hi - lo + 1) / 2;
            if (U[mid] < v)
                lo = mid;
            else
                hi = mid - 1;
        }
        return lo;
    }
    /* largest k with U[k] <= u (u < U[n], so U[k+1] > u) */
    while (lo < hi) {
        size_t mid = lo + (hi - lo + 1) / 2;
        if (U[mid] <= u)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

void geom_curve_bs_basis(int p, const double *U, size_t k, double u, double *N, double *work)
{
    double *left = work, *right = work + (p + 1);
    N[0] = 1.0;
    for (int j = 1; j <= p; ++j) {
        left[j] = u - U[k + 1 - (size_t)j];
        right[j] = U[k + (size_t)j] - u;
        double saved = 0.0;
        for (int r = 0; r < j; ++r) {
            double den = right[r + 1] + left[j - r];
            double nr = N[r];
            /* (right*N)/den, not right*(N/den): exact when right == den */
            N[r] = saved + (right[r + 1] * nr) / den;
            saved = (left[j - r] * nr) / den;
        }
        N[j] = saved;
    }
}

void geom_curve_bs_ders(int p, const double *U, size_t k, double u, int nd, double *ders,
                        double *work)
{
    size_t q = (size_t)p + 1;
    double *ndu = work;         /* ndu[j*q + r]: row j, column r */
    double *left = ndu + q * q; /* q */
    double *right = left + q;   /* q */
    double *a = right + q;      /* 2 rows of q */
#define NDU(j, r) ndu[(size_t)(j)*q + (size_t)(r)]
#define A(s, j) a[(size_t)(s)*q + (size_t)(j)]
#define D(kk, j) ders[(size_t)(kk)*q + (size_t)(j)]
    NDU(0, 0) = 1.0;
    for (int j = 1; j <= p; ++j) {
        left[j] = u - U[k + 1 - (size_t)j];
        right[j] = U[k + (size_t)j] - u;
        double saved = 0.0;
        for (int r = 0; r < j; ++r) {
            NDU(j, r) = right[r + 1] + left[j - r]; /* lower triangle: knot differences */
            double t = NDU(r, j - 1);
            NDU(r, j) = saved + (right[r + 1] * t) / NDU(j, r);
            saved = (left[j - r] * t) / NDU(j, r);
        }
        NDU(j, j) = saved;
    }
    for (int j = 0; j <= p; ++j)
        D(0, j) = NDU(j, p);
    int ne = nd < p ? nd : p;
    for (int r = 0; r <= p; ++r) {
        int s1 = 0, s2 = 1;
        A(0, 0) = 1.0;
        for (int kk = 1; kk <= ne; ++kk) {
            double d = 0.0;
            int rk = r - kk, pk = p - kk;
            if (r >= kk) {
                A(s2, 0) = A(s1, 0) / NDU(pk + 1, rk);
                d = A(s2, 0) * NDU(rk, pk);
            }
            int j1 = rk >= -1 ? 1 : -rk;
            int j2 = (r - 1 <= pk) ? kk - 1 : p - r;
            for (int j = j1; j <= j2; ++j) {
                A(s2, j) = (A(s1, j) - A(s1, j - 1)) / NDU(pk + 1, rk + j);
                d += A(s2, j) * NDU(rk + j, pk);
            }
            if (r <= pk) {
                A(s2, kk) = -A(s1, kk - 1) / NDU(pk + 1, r);
                d += A(s2, kk) * NDU(r, pk);
            }
            D(kk, r) = d;
            int t = s1;
            s1 = s2;
            s2 = t;
        }
    }
    double f = (double)p;
    for (int kk = 1; kk <= ne; ++kk) {
        for (int j = 0; j <= p; ++j)
            D(kk, j) *= f;
        f *= (double)(p - kk);
    }
    for (int kk = ne + 1; kk <= nd; ++kk)
        for (int j = 0; j <= p; ++j)
            D(kk, j) = 0.0;
#undef NDU
#undef A
#undef D
}

/* ------------------------------------------------------------ public API */

static geom_status check_knots(int degree, size_t n, const double *knots)
{
    if (!knots || degree < 0 || n < (size_t)degree + 1)
        return GEOM_ERR_INVALID_ARG;
    if (!(knots[degree] < knots[n]))
        return GEOM_ERR_INVALID_ARG;
    return GEOM_OK;
}

geom_status geom_curve_bspline_find_span(int degree, size_t n, const double *knots, double u,
                                         unsigned flags, size_t *span)
{
    geom_status st = check_knots(degree, n, knots);
    if (st != GEOM_OK || !span)
        return GEOM_ERR_INVALID_ARG;
    double ue;
    int left;
    st = geom_curve_prepare_param_knots(degree, n, knots, u, flags, &ue, &left);
    if (st != GEOM_OK)
        return st;
    *span = geom_curve_bs_span(degree, n, knots, ue, left);
    return GEOM_OK;
}

geom_status geom_curve_bspline_basis(int degree, size_t n, const double *knots, double u,
                                     unsigned flags, size_t *span, double *basis)
{
    geom_status st = check_knots(degree, n, knots);
    if (st != GEOM_OK || !basis)
        return GEOM_ERR_INVALID_ARG;
    double ue;
    int left;
    st = geom_curve_prepare_param_knots(degree, n, knots, u, flags, &ue, &left);
    if (st != GEOM_OK)
        return st;
    size_t k = geom_curve_bs_span(degree, n, knots, ue, left);
    geom_curve_scratch s;
    st = geom_curve_scratch_init(&s, geom_curve_bs_basis_work(degree));
    if (st == GEOM_OK) {
        geom_curve_bs_basis(degree, knots, k, ue, basis, s.mem);
        if (span)
            *span = k;
    }
    geom_curve_scratch_free(&s);
    return st;
}

geom_status geom_curve_bspline_basis_derivs(int degree, size_t n, const double *knots, double u,
                                            int nderiv, unsigned flags, size_t *span, double *ders)
{
    geom_status st = check_knots(degree, n, knots);
    if (st != GEOM_OK || !ders || nderiv < 0)
        return GEOM_ERR_INVALID_ARG;
    double ue;
    int left;
    st = geom_curve_prepare_param_knots(degree, n, knots, u, flags, &ue, &left);
    if (st != GEOM_OK)
        return st;
    size_t k = geom_curve_bs_span(degree, n, knots, ue, left);
    geom_curve_scratch s;
    st = geom_curve_scratch_init(&s, geom_curve_bs_ders_work(degree));
    if (st == GEOM_OK) {
        geom_curve_bs_ders(degree, knots, k, ue, nderiv, ders, s.mem);
        if (span)
            *span = k;
    }
    geom_curve_scratch_free(&s);
    return st;
}
