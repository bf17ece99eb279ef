/*
 * The B-spline kernel shared by the curve and surface modules (core/bspline.c).
 * Private, not installed. No argument checking: callers validate once and
 * call these in inner loops. Knot vectors: degree p >= 0, n >= p+1 control
 * points, n+p+1 nondecreasing knots, u_p < u_n.
 */
#ifndef GEOM_SRC_CORE_BSPLINE_H
#define GEOM_SRC_CORE_BSPLINE_H

#include "core/internal.h"

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
 */
void geom__bs_ders(int p, const double *U, size_t k, double u, int nd, double *ders,
                        double *work);

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

#endif
