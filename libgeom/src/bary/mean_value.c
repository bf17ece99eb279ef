/*
 * Mean value coordinates (Floater 2003) in the formulation of Hormann and
 * Floater, "Mean value coordinates for arbitrary planar polygons", ACM TOG 25
 * (2006): with s_i = v_i - p, r_i = |s_i|, C_i = s_i x s_{i+1} and
 * D_i = s_i . s_{i+1},
 *     w_i = (tan(a_{i-1}/2) + tan(a_i/2)) / r_i,   a_i the signed angle at p,
 * normalised to sum 1. Robustness:
 *  - C_i is evaluated with the exact sign (and relative error <= 2^-46), so a
 *    point exactly on an edge, or exactly on an edge's supporting line, is
 *    recognised exactly; on an edge the weights are the edge's linear
 *    interpolation weights, at a vertex the unit vector;
 *  - tan(a/2) is computed without cancellation: C / (r r' + D) when D >= 0,
 *    (r r' - D) / C when D < 0 (the first is HF06's formula's conjugate);
 *  - the weights are carried as (significand, exponent) pairs and scaled by a
 *    common power of two before normalisation, so they never overflow near
 *    the boundary; coordinates are scaled by a power of two when they are
 *    huge or tiny.
 */
#include "bary/bary_internal.h"

#include <limits.h>

typedef struct mvc_ctx {
    size_t n;
    const double *poly;
    const double *p;
    geom__bary_scale sc;
    double ps[2]; /* scaled p */
} mvc_ctx;

/* s = scaled(v_i) - scaled(p), r = |s|. */
static void mvc_vec(const mvc_ctx *c, size_t i, double s[2], double *r)
{
    s[0] = geom__bary_scaled(&c->sc, c->poly[2 * i]) - c->ps[0];
    s[1] = geom__bary_scaled(&c->sc, c->poly[2 * i + 1]) - c->ps[1];
    *r = hypot(s[0], s[1]);
}

/* tan(a/2) for the edge (i, j) as an xval, or 1 if p lies on the edge. */
static int mvc_tan(const mvc_ctx *c, size_t i, size_t j, const double si[2], double ri,
                   const double sj[2], double rj, geom__xval *t)
{
    const double *vi = c->poly + 2 * i, *vj = c->poly + 2 * j;
    geom__xval cx = geom__bary_orient2d_acc(vi, vj, c->p); /* (v_i - p) x (v_j - p) */
    if (cx.m == 0.0) {
        if (geom__bary_between(vi, vj, c->p))
            return 1;
        *t = geom__xval_from_double(0.0); /* on the supporting line, outside */
        return 0;
    }
    cx.e += 2 * c->sc.k; /* into scaled units */
    if (fmin(ri, rj) >= 0x1p-400) {
        double d = si[0] * sj[0] + si[1] * sj[1];
        double r = ri * rj;
        if (d >= 0.0)
            *t = geom__xval_div(cx, geom__xval_from_double(r + d));
        else
            *t = geom__xval_div(geom__xval_from_double(r - d), cx);
    } else {
        /* p extremely close to a vertex: the same in (significand,
         * exponent) arithmetic, which cannot underflow. */
        geom__xval d = geom__xval_add(
            geom__xval_mul(geom__xval_from_double(si[0]), geom__xval_from_double(sj[0])),
            geom__xval_mul(geom__xval_from_double(si[1]), geom__xval_from_double(sj[1])));
        geom__xval r = geom__xval_mul(geom__xval_from_double(ri), geom__xval_from_double(rj));
        if (d.m >= 0.0) {
            *t = geom__xval_div(cx, geom__xval_add(r, d));
        } else {
            d.m = -d.m;
            *t = geom__xval_div(geom__xval_add(r, d), cx);
        }
    }
    return 0;
}

/* One pass over the polygon: w[i] = W_i * 2^-shift, *gmax = the largest
 * exponent of the W_i. Returns the index + 1 of an edge p lies on (then w
 * is not filled), else 0. */
static size_t mvc_pass(const mvc_ctx *c, int shift, double *w, int *gmax)
{
    size_t n = c->n;
    double s0[2], r0, sl[2], rl, si[2], ri, sj[2], rj;
    geom__xval tlast, tprev, ti;
    mvc_vec(c, 0, s0, &r0);
    mvc_vec(c, n - 1, sl, &rl);
    if (mvc_tan(c, n - 1, 0, sl, rl, s0, r0, &tlast))
        return n;
    tprev = tlast;
    si[0] = s0[0];
    si[1] = s0[1];
    ri = r0;
    *gmax = INT_MIN;
    for (size_t i = 0; i < n; i++) {
        size_t j = i + 1 == n ? 0 : i + 1;
        if (i + 1 == n) {
            ti = tlast;
            sj[0] = s0[0];
            sj[1] = s0[1];
            rj = r0;
        } else {
            mvc_vec(c, j, sj, &rj);
            if (mvc_tan(c, i, j, si, ri, sj, rj, &ti))
                return i + 1;
        }
        geom__xval wi = geom__xval_div(geom__xval_add(tprev, ti), geom__xval_from_double(ri));
        if (wi.m != 0.0 && wi.e > *gmax)
            *gmax = wi.e;
        wi.e -= shift;
        w[i] = wi.m == 0.0 ? 0.0 : ldexp(wi.m, wi.e < -2000 ? -2000 : wi.e);
        tprev = ti;
        si[0] = sj[0];
        si[1] = sj[1];
        ri = rj;
    }
    return 0;
}

geom_status geom_bary_mean_value(size_t n, const double *poly, const double p[2], double *w)
{
    geom_status st = geom__bary_poly_check(n, poly, p, w);
    if (st != GEOM_OK)
        return st;
    for (size_t i = 0; i < n; i++) {
        size_t j = i + 1 == n ? 0 : i + 1;
        if (geom__bary_same2(poly + 2 * i, poly + 2 * j))
            return GEOM_ERR_DEGENERATE;
    }
    int flat = 1;
    for (size_t k = 2; k < n && flat; k++)
        flat = geom_orient2d(poly, poly + 2, poly + 2 * k) == 0.0;
    if (flat)
        return GEOM_ERR_DEGENERATE;
    for (size_t i = 0; i < n; i++) {
        if (geom__bary_same2(p, poly + 2 * i)) {
            w[i] = 1.0;
            return GEOM_OK;
        }
    }
    mvc_ctx c;
    c.n = n;
    c.poly = poly;
    c.p = p;
    c.sc = geom__bary_scale_for(n, poly, p);
    c.ps[0] = geom__bary_scaled(&c.sc, p[0]);
    c.ps[1] = geom__bary_scaled(&c.sc, p[1]);
    for (size_t i = 0; i < n; i++) {
        double s[2], r;
        mvc_vec(&c, i, s, &r);
        if (r == 0.0) { /* only if scaling lost p's distinguishing bits */
            w[i] = 1.0;
            return GEOM_OK;
        }
    }
    int g;
    size_t edge = mvc_pass(&c, 0, w, &g);
    if (edge) {
        size_t i = edge - 1, j = edge == n ? 0 : edge;
        geom__bary_zero(w, n);
        geom__bary_edge_weights(poly + 2 * i, poly + 2 * j, p, &w[i], &w[j]);
        return GEOM_OK;
    }
    if (g != INT_MIN && (g > 1000 || g < -900)) {
        int g2;
        (void)mvc_pass(&c, g, w, &g2);
    }
    if (!geom__bary_normalise(n, w)) {
        /* The weights cancel: only possible for a self-intersecting
         * polygon. */
        geom__bary_zero(w, n);
        return GEOM_ERR_DEGENERATE;
    }
    return GEOM_OK;
}
