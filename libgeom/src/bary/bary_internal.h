/* Private helpers shared by the barycentric sources. Not installed. */
#ifndef GEOM_SRC_BARY_INTERNAL_H
#define GEOM_SRC_BARY_INTERNAL_H

#include "core/expansion.h"
#include "core/internal.h"
#include "geom/bary.h"

#include <string.h>

/* Shewchuk's stage-A relative error bounds (eps = 2^-53). */
#define GEOM_BARY_EPS 0x1p-53
#define GEOM_BARY_CCW_A ((3.0 + 16.0 * GEOM_BARY_EPS) * GEOM_BARY_EPS)
#define GEOM_BARY_O3D_A ((7.0 + 56.0 * GEOM_BARY_EPS) * GEOM_BARY_EPS)
/* Absolute allowance for underflowed products (see predicates.c); normal,
 * since subnormal operands are slow. */
#define GEOM_BARY_TINY 0x1p-960
/* Filter sums at or above this go to the exact path (no overflow). */
#define GEOM_BARY_BIG 0x1p1000

/*
 * The fast paths accept a floating-point determinant only when its certified
 * relative error is at most 2^-42 (about 2.3e-13): |det| >= A * 2^42 * sum,
 * where A * sum bounds the absolute error. A coordinate (ratio of two such
 * values, then rounded) is then within 2^-41 + 2^-53 (about 4.6e-13) of its
 * exact value, relatively. The polygon coordinates use 2^-46.
 */
#define GEOM_BARY_REL 0x1p42
#define GEOM_BARY_REL_POLY 0x1p46

/* x1*y2 - y1*x2 with a certified relative error (1), or not certified (0).
 * An exactly zero value (both products with a zero factor) is certified. */
static inline int geom__bary_det2(double x1, double y2, double y1, double x2, double rel,
                                 double *out)
{
    double t1 = x1 * y2, t2 = y1 * x2;
    double det = t1 - t2;
    double sum = fabs(t1) + fabs(t2);
    *out = det;
    if (fabs(det) >= (GEOM_BARY_CCW_A * rel) * sum + GEOM_BARY_TINY && sum < GEOM_BARY_BIG)
        return 1;
    if (sum == 0.0 && (x1 == 0.0 || y2 == 0.0) && (y1 == 0.0 || x2 == 0.0)) {
        *out = 0.0;
        return 1;
    }
    return 0;
}

/* orient2d(a, b, c) = (a-c) x (b-c) as an xval with relative error at most
 * 2^-46 and the exact sign (exact value when the filter cannot certify). */
static inline geom__xval geom__bary_orient2d_acc(const double a[2], const double b[2],
                                               const double c[2])
{
    double det;
    if (geom__bary_det2(a[0] - c[0], b[1] - c[1], a[1] - c[1], b[0] - c[0], GEOM_BARY_REL_POLY,
                       &det))
        return geom__xval_from_double(det);
    return geom__xeval_orient2d(a, b, c);
}

/* det[a-d; b-d; c-d] in floating point; 1 if its relative error is
 * certified to be at most 2^-42 (without branches: the batch kernel runs it
 * lane by lane). geom_bary_tet's determinants, and the batch's. */
static inline int geom__bary_det3(const double a[3], const double b[3], const double c[3],
                                  const double d[3], double *out)
{
    double perm, zterm;
    double det = geom__orient3d_fast(a, b, c, d, &perm, &zterm);
    *out = det;
    return (fabs(det) >= (GEOM_BARY_O3D_A * GEOM_BARY_REL) * perm + GEOM_BARY_TINY * zterm) &
           (perm < GEOM_BARY_BIG);
}

/* geom_bary_tri3's terms (degree-4 polynomials, each through at most 11
 * roundings: error below 12 eps times the sum of absolute values); 12 eps *
 * 2^42: the accepted relative error is 2^-42. */
#define GEOM_BARY_TRI3_K (12.0 * GEOM_BARY_EPS * GEOM_BARY_REL)

/* n = u x v in floating point, with the sums of the absolute products
 * (inlined into the batch's vector clones). */
GEOM__CLONE_INLINE void geom__bary_cross_abs(const double u[3], const double v[3], double n[3],
                                             double na[3])
{
    /* component k from i = k + 1, j = k + 2 (mod 3): t1 = u[i] v[j], t2 = u[j] v[i];
     * written out, so that the batch's lane loop has no inner loop */
    double t1 = u[1] * v[2], t2 = u[2] * v[1];
    n[0] = t1 - t2;
    na[0] = fabs(t1) + fabs(t2);
    t1 = u[2] * v[0], t2 = u[0] * v[2];
    n[1] = t1 - t2;
    na[1] = fabs(t1) + fabs(t2);
    t1 = u[0] * v[1], t2 = u[1] * v[0];
    n[2] = t1 - t2;
    na[2] = fabs(t1) + fabs(t2);
}

/* x . y with the certification test, without branches; 1 if accepted (a
 * certified value is never 0). */
GEOM__CLONE_INLINE int geom__bary_dot3_ok(const double x[3], const double xa[3],
                                          const double y[3], const double ya[3], double *out)
{
    double v = x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
    double perm = xa[0] * ya[0] + xa[1] * ya[1] + xa[2] * ya[2];
    /* Products that underflow are off by 2^-1075 and then multiplied by at
     * most one absolute sum. */
    double tiny = GEOM_BARY_TINY * (1.0 + xa[0] + xa[1] + xa[2] + ya[0] + ya[1] + ya[2]);
    *out = v;
    return (fabs(v) >= GEOM_BARY_TRI3_K * perm + tiny) & (perm < GEOM_BARY_BIG);
}

/* n doubles of v all finite? */
static inline int geom__bary_finite(const double *v, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!isfinite(v[i]))
            return 0;
    return 1;
}

static inline void geom__bary_zero(double *w, size_t n)
{
    if (w)
        for (size_t i = 0; i < n; i++)
            w[i] = 0.0;
}

/* The argument check of the polygon coordinates (mean value, Wachspress):
 * GEOM_ERR_INVALID_ARG for NULL w, n < 3, NULL or non-finite poly or p; w
 * (when not NULL) is zeroed in every case. */
static inline geom_status geom__bary_poly_check(size_t n, const double *poly, const double p[2],
                                                double *w)
{
    if (!w)
        return GEOM_ERR_INVALID_ARG;
    if (n < 3 || !poly || !p || !geom__bary_finite(poly, 2 * n) || !geom__bary_finite(p, 2)) {
        geom__bary_zero(w, n);
        return GEOM_ERR_INVALID_ARG;
    }
    geom__bary_zero(w, n);
    return GEOM_OK;
}

/* l = (x, y, z). */
static inline void geom__bary_set3(double l[3], double x, double y, double z)
{
    l[0] = x;
    l[1] = y;
    l[2] = z;
}

/* n / d for certified doubles, keeping the sign of a quotient that
 * underflows. */
static inline double geom__bary_quot(double n, double d)
{
    double r = n / d;
    if (r == 0.0 && n != 0.0)
        r = copysign(DBL_TRUE_MIN, n) * copysign(1.0, d);
    return r;
}

static inline int geom__bary_same2(const double a[2], const double b[2])
{
    return a[0] == b[0] && a[1] == b[1];
}

static inline int geom__bary_same3(const double a[3], const double b[3])
{
    return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
}

/* Is p (collinear with a and b, a != b) strictly between a and b? Exact. */
static inline int geom__bary_between(const double a[2], const double b[2], const double p[2])
{
    if (a[0] != b[0])
        return (a[0] < p[0] && p[0] < b[0]) || (b[0] < p[0] && p[0] < a[0]);
    return (a[1] < p[1] && p[1] < b[1]) || (b[1] < p[1] && p[1] < a[1]);
}

/* Linear-interpolation weights of p strictly inside the segment (a, b):
 * *wa = |b-p| / |b-a|, *wb = |p-a| / |b-a|, computed along the axis of the
 * larger extent (each within a few ulp). */
static inline void geom__bary_edge_weights(const double a[2], const double b[2], const double p[2],
                                          double *wa, double *wb)
{
    int k = fabs(b[0] - a[0]) >= fabs(b[1] - a[1]) ? 0 : 1;
    double s = 1.0;
    double len = b[k] - a[k];
    if (!isfinite(len) || !isfinite(fabs(b[1 - k] - a[1 - k]))) {
        /* Coordinates near DBL_MAX: halve everything (exact at this size). */
        s = 0.25;
        k = fabs(b[0] * s - a[0] * s) >= fabs(b[1] * s - a[1] * s) ? 0 : 1;
        len = b[k] * s - a[k] * s;
    }
    *wa = (b[k] * s - p[k] * s) / len;
    *wb = (p[k] * s - a[k] * s) / len;
}

/* Power-of-two scaling of polygon coordinates: x -> (x * f[0]) * f[1]. */
typedef struct geom__bary_scale {
    double f[2];
    int k; /* total exponent: the scale is 2^k */
} geom__bary_scale;

/* A scale bringing the largest magnitude among the polygon and p near 1, or
 * the identity when everything is comfortably in range. */
static inline geom__bary_scale geom__bary_scale_for(size_t n, const double *poly, const double p[2])
{
    double mx = fmax(fabs(p[0]), fabs(p[1]));
    for (size_t i = 0; i < 2 * n; i++)
        mx = fmax(mx, fabs(poly[i]));
    geom__bary_scale s = {{1.0, 1.0}, 0};
    if (mx == 0.0 || (mx > 0x1p-400 && mx < 0x1p400))
        return s;
    int e;
    (void)frexp(mx, &e);
    s.k = -e;
    s.f[0] = ldexp(1.0, s.k / 2);
    s.f[1] = ldexp(1.0, s.k - s.k / 2);
    return s;
}

static inline double geom__bary_scaled(const geom__bary_scale *s, double x)
{
    return (x * s->f[0]) * s->f[1];
}

/* Normalise weights held as xvals: the caller has stored them in two passes;
 * this helper just divides w by its sum. Returns 0 if the sum is not a
 * usable positive or negative finite number. */
static inline int geom__bary_normalise(size_t n, double *w)
{
    double sum = 0.0;
    for (size_t i = 0; i < n; i++)
        sum += w[i];
    if (!(sum != 0.0) || !isfinite(sum))
        return 0;
    for (size_t i = 0; i < n; i++)
        w[i] /= sum;
    return 1;
}

#endif
