/* Real roots of a polynomial in an interval: critical points split the
 * interval into monotone pieces, each sign change is one root (safeguarded
 * Newton/bisection), a critical point with |p| within the evaluation error
 * bound is a touching (double) root. */
#include "ray/ray_internal.h"

#define POLY_MAX_DEG 8

/* p(x) by Horner with Higham's running error bound (Algorithm 5.1) plus the
 * coefficients' own errors. */
static double horner(const double *c, const double *cerr, int deg, double x, double *bound)
{
    double y = c[deg], mu, ax = fabs(x), xp = 1, ce = 0;
    int i;
    mu = fabs(y) * 0.5;
    for (i = deg - 1; i >= 0; i--) {
        y = x * y + c[i];
        mu = ax * mu + fabs(y);
    }
    if (cerr) {
        for (i = 0; i <= deg; i++) {
            ce += cerr[i] * xp;
            xp *= ax;
        }
    }
    if (bound) *bound = DBL_EPSILON * (2 * mu - fabs(y)) + ce;
    return y;
}

static double deriv_eval(const double *c, int deg, double x)
{
    double y = deg * c[deg];
    int i;
    for (i = deg - 1; i >= 1; i--) y = x * y + i * c[i];
    return y;
}

/* The one root in [a, b] where p(a), p(b) have opposite signs. */
static double refine(const double *c, int deg, double a, double b, double pa)
{
    double x = 0.5 * (a + b);
    int it;
    for (it = 0; it < 200; it++) {
        double px = horner(c, NULL, deg, x, NULL), dx, xn;
        if (px == 0) return x;
        if ((px < 0) == (pa < 0)) { a = x; pa = px; }
        else b = x;
        dx = deriv_eval(c, deg, x);
        xn = dx != 0 ? x - px / dx : 0.5 * (a + b);
        if (!(xn > a && xn < b)) xn = 0.5 * (a + b);
        if (xn == x || b - a <= 2 * DBL_EPSILON * fmax(fabs(a), fabs(b)) ||
            0.5 * (a + b) == a || 0.5 * (a + b) == b) {
            x = xn;
            break;
        }
        x = xn;
    }
    return x;
}

size_t geom__poly_roots(const double *c, const double *cerr, int deg, double lo, double hi,
                        double *roots)
{
    double cc[POLY_MAX_DEG + 1], ce[POLY_MAX_DEG + 1];
    double dc[POLY_MAX_DEG], crit[POLY_MAX_DEG + 2], pts[POLY_MAX_DEG + 2], val[POLY_MAX_DEG + 2];
    int zero[POLY_MAX_DEG + 2];
    size_t nc, npts, nr = 0, i, j;
    int d = deg, k;
    if (!(lo <= hi) || deg < 0 || deg > POLY_MAX_DEG) return 0;
    /* Drop leading coefficients that are zero (or within their error). */
    while (d > 0 && (c[d] == 0 || (cerr && fabs(c[d]) <= cerr[d]))) d--;
    for (k = 0; k <= d; k++) {
        cc[k] = c[k];
        ce[k] = cerr ? cerr[k] : 0;
    }
    if (d == 0) return 0;
    if (d == 1) {
        double r = -cc[0] / cc[1];
        if (r >= lo && r <= hi) roots[nr++] = r;
        return nr;
    }
    for (k = 1; k <= d; k++) dc[k - 1] = k * cc[k];
    {
        double dce[POLY_MAX_DEG];
        for (k = 1; k <= d; k++) dce[k - 1] = k * ce[k];
        nc = geom__poly_roots(dc, dce, d - 1, lo, hi, crit);
    }
    /* Unique, strictly inside (lo, hi). */
    npts = 0;
    pts[npts++] = lo;
    for (i = 0; i < nc; i++)
        if (crit[i] > pts[npts - 1] && crit[i] < hi) pts[npts++] = crit[i];
    pts[npts++] = hi;
    for (i = 0; i < npts; i++) {
        double b;
        val[i] = horner(cc, ce, d, pts[i], &b);
        zero[i] = fabs(val[i]) <= b;
        if (i == 0 || i == npts - 1) zero[i] = val[i] == 0; /* ends: exact zeros only */
    }
    for (i = 0; i + 1 < npts; i++) {
        if (i == 0 && zero[0]) roots[nr++] = pts[0];
        if (!zero[i] && !zero[i + 1] && (val[i] < 0) != (val[i + 1] < 0))
            roots[nr++] = refine(cc, d, pts[i], pts[i + 1], val[i]);
        if (i + 1 < npts - 1 && zero[i + 1]) {
            /* A critical point with p ~ 0: a crossing if the neighbours
             * (the next non-zero values) differ in sign, else a touch. */
            double left = 0, right = 0;
            for (j = i + 1; j-- > 0;)
                if (!zero[j]) { left = val[j]; break; }
            for (j = i + 2; j < npts; j++)
                if (!zero[j]) { right = val[j]; break; }
            roots[nr++] = pts[i + 1];
            if (left != 0 && right != 0 && (left < 0) == (right < 0)) roots[nr++] = pts[i + 1];
        }
        if (i + 1 == npts - 1 && zero[i + 1] && npts > 1) roots[nr++] = pts[i + 1];
        if (nr >= (size_t)d) break;
    }
    if (nr > (size_t)d) nr = (size_t)d;
    return nr;
}

size_t geom_ray_poly_roots(const double *c, int deg, double lo, double hi, double *roots)
{
    if (!c || !roots || !isfinite(lo) || !isfinite(hi)) return 0;
    return geom__poly_roots(c, NULL, deg, lo, hi, roots);
}
