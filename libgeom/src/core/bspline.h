/*
 * The B-spline kernel shared by the curve and surface modules (core/bspline.c).
 * Private, not installed. No argument checking: callers validate once and
 * call these in inner loops. Knot vectors: degree p >= 0, n >= p+1 control
 * points, n+p+1 nondecreasing knots, u_p < u_n.
 */
#ifndef GEOM_SRC_CORE_BSPLINE_H
#define GEOM_SRC_CORE_BSPLINE_H

#include "core/internal.h"

#include <math.h>
#include <stddef.h>

/* ------------------------------------------------------------------ scratch */

/** Doubles held on the stack by a geom__scratch (8 KiB). */
#define GEOM__SCRATCH_LOCAL 1024

/**
 * Temporary storage: `mem` points into `local` when the request fits, else to
 * a malloc'd block. Always pair geom__scratch_init with
 * geom__scratch_free (also after a failed init: it is then a no-op).
 */
typedef struct geom__scratch {
    double *mem;
    size_t size; /* doubles */
    int heap;
    double local[GEOM__SCRATCH_LOCAL];
} geom__scratch;

/** Make s->mem hold at least ndoubles doubles. GEOM_ERR_NOMEM or
 *  GEOM_ERR_LIMIT (size overflow) on failure, with s->mem == NULL. */
geom_status geom__scratch_init(geom__scratch *s, size_t ndoubles);
void geom__scratch_free(geom__scratch *s);

/* ---------------------------------------------------------- span and basis */

/**
 * A2.1 with the module's rules: the span k in [p, n-1] with u_k < u_{k+1}
 * such that u_k <= u < u_{k+1} (left == 0) or u_k < u <= u_{k+1} (left != 0);
 * u <= u_p gives the first non-empty span, u >= u_n the last. Binary
 * search, O(log n). Memory-safe for any knots (the result is always in
 * [p, n-1]).
 */
size_t geom__bs_span(int p, size_t n, const double *U, double u, int left);

/** Doubles of work needed by geom__bs_basis: 2*(p+1). */
static inline size_t geom__bs_basis_work(int p)
{
    return 2 * ((size_t)p + 1);
}

/**
 * A2.2: N[0..p] = N_{k-p,p}(u) .. N_{k,p}(u) for span k. The recurrence is
 * evaluated as saved + (right * N) / den rather than right * (N / den), so a
 * basis function that equals 1 (u at a knot of multiplicity >= p, e.g. the
 * ends of a clamped curve) is exactly 1 and the others exactly 0.
 */
void geom__bs_basis(int p, const double *U, size_t k, double u, double *N, double *work);

/** Doubles of work needed by geom__bs_ders: (p+1)^2 + 4*(p+1). */
static inline size_t geom__bs_ders_work(int p)
{
    size_t q = (size_t)p + 1;
    return q * q + 4 * q;
}

/**
 * A2.3: ders[j*(p+1) + r] = j-th derivative of N_{k-p+r,p} at u, for
 * j = 0..nd (rows above p are zero). Row 0 equals geom__bs_basis.
 * Inline: the hot callers (surface and curve evaluation) want it in place.
 */
static inline void geom__bs_ders(int p, const double *U, size_t k, double u, int nd,
                                 double *ders, double *work)
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
    /* Order 1 straight from the degree p-1 column (one division a term):
     *   N'_r = p (N_{r-1,p-1} / (u_{k+r} - u_{k+r-p}) - N_{r,p-1} / (u_{k+r+1} - u_{k+r+1-p})).
     * It is A2.3's first step with N/den in place of (1/den)*N, and the
     * common case (points with first derivatives, normals) stops here. */
    if (ne >= 1)
        for (int r = 0; r <= p; ++r) {
            double d = 0.0;
            if (r > 0)
                d += NDU(r - 1, p - 1) / NDU(p, r - 1);
            if (r < p)
                d -= NDU(r, p - 1) / NDU(p, r);
            D(1, r) = d;
        }
    for (int r = 0; ne >= 2 && r <= p; ++r) {
        /* A2.3 from order 2, its coefficients a_{1,j} set as its first step does */
        int s1 = 1, s2 = 0;
        A(1, 0) = r >= 1 ? 1.0 / NDU(p, r - 1) : 0.0;
        if (r <= p - 1)
            A(1, 1) = -1.0 / NDU(p, r);
        for (int kk = 2; kk <= ne; ++kk) {
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

/* ---------------------------------------------------- parameter reduction */

/**
 * Reduce and check an evaluation parameter u on knots U (degree p, n control
 * points): NaN/Inf -> GEOM_ERR_INVALID_ARG; outside [u_p, u_n] ->
 * GEOM_ERR_DOMAIN unless wrap, which reduces it periodically (u_n itself,
 * from the right, becomes u_p). *u_eval is the parameter and *left =
 * want_left (use the left limit at a knot).
 */
geom_status geom__bs_param(int p, size_t n, const double *U, double u, int wrap, int want_left,
                           double *u_eval, int *left);

/* ------------------------------------------------------------- binomials */

/** The binomial coefficient C(n, k) as a double (0 for k < 0 or k > n),
 *  by the product C(n-k+i, i) = C(n-k+i-1, i-1) * (n-k+i) / i, rounded to
 *  the nearest integer: exact while the products stay below 2^53 (every
 *  step is then an exact integer), an integer past that (where intermediate
 *  products round). Curves and surfaces alike. */
static inline double geom__binom(long n, long k)
{
    if (k < 0 || k > n)
        return 0.0;
    if (k > n - k)
        k = n - k;
    double b = 1.0;
    for (long i = 1; i <= k; ++i)
        b = b * (double)(n - k + i) / (double)i;
    return nearbyint(b);
}

#endif
