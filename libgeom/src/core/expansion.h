/*
 * Private exact-arithmetic toolkit shared by the predicates (core) and the
 * barycentric module (bary). Not installed.
 *
 * Floating-point expansions after J. R. Shewchuk, "Adaptive Precision
 * Floating-Point Arithmetic and Fast Robust Geometric Predicates", Discrete &
 * Computational Geometry 18 (1997): a number is represented exactly as an
 * unevaluated sum of doubles ordered by increasing magnitude, built from the
 * error-free transformations two-sum and two-product (Dekker/Veltkamp
 * splitting; no fused multiply-add is assumed, the library is compiled with
 * -ffp-contract=off). Expansions here are zero-eliminated: a zero value is
 * the one-component expansion {0}.
 *
 * The algorithms are exact only without overflow and underflow, so the
 * exact evaluators below first scale their input by a power of two (exact);
 * when the input's dynamic range is too wide for any scaling to keep every
 * component in the normal range, they fall back to a small arbitrary-
 * precision binary integer ("big float") evaluation, so every result is
 * exact for all finite input.
 */
#ifndef GEOM_SRC_CORE_EXPANSION_H
#define GEOM_SRC_CORE_EXPANSION_H

#include <float.h>
#include <math.h>

#if !defined(FLT_EVAL_METHOD) || (FLT_EVAL_METHOD != 0)
#error "libgeom's exact predicates need FLT_EVAL_METHOD == 0 (no x87 excess precision)"
#endif

/* -------------------------------------------------- error-free transforms */

/* 2^27 + 1: splits a 53-bit significand into two 26-bit halves. */
#define GEOM_XP_SPLITTER 134217729.0

/* x + y == a + b exactly, x = fl(a + b) (Knuth's two-sum). */
static inline void geom__two_sum(double a, double b, double *x, double *y)
{
    double s = a + b;
    double bv = s - a;
    double av = s - bv;
    *x = s;
    *y = (a - av) + (b - bv);
}

/* As geom__two_sum, requires |a| >= |b| (or a == 0) (Dekker's fast two-sum). */
static inline void geom__fast_two_sum(double a, double b, double *x, double *y)
{
    double s = a + b;
    *x = s;
    *y = b - (s - a);
}

/* x + y == a - b exactly, x = fl(a - b). */
static inline void geom__two_diff(double a, double b, double *x, double *y)
{
    double d = a - b;
    double bv = a - d;
    double av = d + bv;
    *x = d;
    *y = (a - av) + (bv - b);
}

/* a == hi + lo with hi and lo each fitting in 26 bits (Veltkamp). */
static inline void geom__split(double a, double *hi, double *lo)
{
    double c = GEOM_XP_SPLITTER * a;
    double big = c - a;
    double h = c - big;
    *hi = h;
    *lo = a - h;
}

/* x + y == a * b exactly, x = fl(a * b) (Dekker's two-product). */
static inline void geom__two_product(double a, double b, double *x, double *y)
{
    double p = a * b;
    double ah, al, bh, bl;
    geom__split(a, &ah, &al);
    geom__split(b, &bh, &bl);
    double e1 = p - ah * bh;
    double e2 = e1 - al * bh;
    double e3 = e2 - ah * bl;
    *x = p;
    *y = al * bl - e3;
}

/* ------------------------------------------------------------- expansions */

/* h = e + f; h must hold elen + flen doubles and not alias e or f. Returns
 * the length of h (>= 1). Inputs must be strongly nonoverlapping (as every
 * expansion produced by these functions is). */
int geom__xp_sum(int elen, const double *e, int flen, const double *f, double *h);
/* h = e * b; h must hold 2 * elen doubles and not alias e. */
int geom__xp_scale(int elen, const double *e, double b, double *h);
/* h = e * f; h must hold 2 * elen * flen doubles, work 2 * (flen + elen * flen)
 * doubles; neither may alias an input. */
int geom__xp_mul(int elen, const double *e, int flen, const double *f, double *h,
                     double *work);
/* e = -e in place. */
void geom__xp_negate(int elen, double *e);
/* h = a - b as an expansion of at most 2 components; returns its length. */
int geom__xp_diff(double a, double b, double h[2]);
/* Compress e in place (Shewchuk's Compress): same value, nonadjacent
 * components, usually far fewer; returns the new length. */
int geom__xp_compress(int elen, double *e);
/* Nearest-ish double to the expansion's value: within 1 ulp (relative error
 * < 2^-52), with the exact sign, 0 only for a zero expansion. Compresses e in
 * place. */
double geom__xp_approx(int elen, double *e);

/* ---------------------------------------------------------- exact values */

/* An exact value rounded to 53 bits, with an unbounded exponent: the value is
 * m * 2^e with m == 0 (and e == 0) or 0.5 <= |m| < 1; m is within 1 ulp of
 * the exact value's significand and has its exact sign. */
typedef struct geom__xval {
    double m;
    int e;
} geom__xval;

static inline geom__xval geom__xval_from_double(double x)
{
    geom__xval v;
    if (x == 0.0) {
        v.m = 0.0;
        v.e = 0;
    } else {
        v.m = frexp(x, &v.e);
    }
    return v;
}

/* a / b (b.m != 0), renormalised. */
static inline geom__xval geom__xval_div(geom__xval a, geom__xval b)
{
    if (a.m == 0.0)
        return a;
    geom__xval r;
    int k;
    r.m = frexp(a.m / b.m, &k);
    r.e = a.e - b.e + k;
    return r;
}

static inline geom__xval geom__xval_mul(geom__xval a, geom__xval b)
{
    geom__xval r;
    if (a.m == 0.0 || b.m == 0.0) {
        r.m = 0.0;
        r.e = 0;
        return r;
    }
    int k;
    r.m = frexp(a.m * b.m, &k);
    r.e = a.e + b.e + k;
    return r;
}

/* a + b rounded (a few ulp; terms more than 2^1100 apart contribute nothing). */
static inline geom__xval geom__xval_add(geom__xval a, geom__xval b)
{
    if (b.m == 0.0)
        return a;
    if (a.m == 0.0)
        return b;
    if (a.e < b.e) {
        geom__xval t = a;
        a = b;
        b = t;
    }
    int d = a.e - b.e;
    double s = d > 1100 ? a.m : a.m + ldexp(b.m, -d);
    geom__xval r = {0.0, 0};
    if (s != 0.0) {
        int k;
        r.m = frexp(s, &k);
        r.e = a.e + k;
    }
    return r;
}

/* The double nearest m * 2^e; beyond the double range the result is +-Inf,
 * below it the sign is kept (+-DBL_TRUE_MIN) rather than rounding to 0. */
static inline double geom__xval_to_double(geom__xval v)
{
    if (v.m == 0.0)
        return 0.0;
    if (v.e > 1100)
        return copysign(INFINITY, v.m);
    if (v.e < -1100)
        return copysign(DBL_TRUE_MIN, v.m);
    double r = ldexp(v.m, v.e);
    return r == 0.0 ? copysign(DBL_TRUE_MIN, v.m) : r;
}

/* The double nearest n / d (d.m != 0), with the same range rules. */
static inline double geom__xval_ratio(geom__xval n, geom__xval d)
{
    return geom__xval_to_double(geom__xval_div(n, d));
}

/* The floating-point stage of orient3d: det[a-d; b-d; c-d] as Shewchuk
 * evaluates it, with its permanent (the bound's sum of product magnitudes)
 * and 1 + |adz| + |bdz| + |cdz| (the underflow allowance's factor). One
 * expression for geom_orient3d and the barycentric tet filter. */
static inline double geom__orient3d_fast(const double a[3], const double b[3], const double c[3],
                                         const double d[3], double *permanent, double *zterm)
{
    double adx = a[0] - d[0], bdx = b[0] - d[0], cdx = c[0] - d[0];
    double ady = a[1] - d[1], bdy = b[1] - d[1], cdy = c[1] - d[1];
    double adz = a[2] - d[2], bdz = b[2] - d[2], cdz = c[2] - d[2];
    double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
    double cdxady = cdx * ady, adxcdy = adx * cdy;
    double adxbdy = adx * bdy, bdxady = bdx * ady;
    double aadz = fabs(adz), abdz = fabs(bdz), acdz = fabs(cdz);
    *permanent = (fabs(bdxcdy) + fabs(cdxbdy)) * aadz + (fabs(cdxady) + fabs(adxcdy)) * abdz +
                 (fabs(adxbdy) + fabs(bdxady)) * acdz;
    *zterm = 1.0 + aadz + abdz + acdz;
    return adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
}

/* Exact values of the determinants, for all finite input (the caller checks
 * finiteness). orient2d = (a-c) x (b-c); orient3d = det[a-d; b-d; c-d];
 * incircle = the lifted 3x3 determinant of a-d, b-d, c-d. */
geom__xval geom__xeval_orient2d(const double a[2], const double b[2], const double c[2]);
geom__xval geom__xeval_orient3d(const double a[3], const double b[3], const double c[3],
                                   const double d[3]);
geom__xval geom__xeval_incircle(const double a[2], const double b[2], const double c[2],
                                   const double d[2]);
/* Barycentric numerators and denominator of the 3D triangle (a, b, c) for p:
 * n = (b-a) x (c-a), num[0] = n . ((c-b) x (p-b)), num[1] = n . ((a-c) x (p-c)),
 * num[2] = n . ((b-a) x (p-a)), *den = n . n; all exact. Only num[i] with bit
 * i of mask set, and *den if bit 3 is set, are computed. */
void geom__xeval_tri3(const double a[3], const double b[3], const double c[3],
                          const double p[3], unsigned mask, geom__xval num[3], geom__xval *den);

#endif
