/* The B-spline kernel shared by the curve and surface modules: span search
 * and basis functions (Piegl and Tiller, The NURBS Book, A2.1-A2.3), the
 * parameter reduction, and scratch memory (declared in core/bspline.h). */
#include "core/bspline.h"

geom_status geom__scratch_init(geom__scratch *s, size_t ndoubles)
{
    s->heap = 0;
    s->size = ndoubles;
    if (ndoubles <= GEOM__SCRATCH_LOCAL) {
        s->mem = s->local;
        return GEOM_OK;
    }
    size_t bytes;
    if (geom__size_mul(ndoubles, sizeof(double), &bytes) != GEOM_OK) {
        s->mem = NULL;
        s->size = 0;
        return GEOM_ERR_LIMIT;
    }
    s->mem = (double *)geom__alloc(NULL, bytes);
    if (!s->mem) {
        s->size = 0;
        return GEOM_ERR_NOMEM;
    }
    s->heap = 1;
    return GEOM_OK;
}

void geom__scratch_free(geom__scratch *s)
{
    if (s->heap && s->mem)
        geom__free(NULL, s->mem, s->size * sizeof(double));
    s->mem = NULL;
    s->heap = 0;
    s->size = 0;
}

geom_status geom__bs_param(int p, size_t n, const double *U, double u, int wrap, int want_left,
                           double *u_eval, int *left)
{
    if (!isfinite(u))
        return GEOM_ERR_INVALID_ARG;
    double a = U[p], b = U[n];
    if (u >= a && u <= b) {
        if (wrap && u == b && !want_left)
            u = a; /* the seam of a periodic curve, from the right */
        *u_eval = u;
        *left = want_left;
        return GEOM_OK;
    }
    if (!wrap)
        return GEOM_ERR_DOMAIN;
    double L = b - a;
    if (!(L > 0.0) || !isfinite(L))
        return GEOM_ERR_DOMAIN;
    double x = fmod(u - a, L);
    if (x < 0.0)
        x += L;
    double r = a + x;
    if (!(r < b)) /* rounding pushed it to the seam */
        r = a;
    if (r < a)
        r = a;
    if (r == a && want_left)
        r = b;
    *u_eval = r;
    *left = want_left;
    return GEOM_OK;
}

size_t geom__bs_span(int p, size_t n, const double *U, double u, int left)
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

void geom__bs_basis(int p, const double *U, size_t k, double u, double *N, double *work)
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


