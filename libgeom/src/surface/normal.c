/* Unit normals everywhere: S_u x S_v at regular points, and at degenerate
 * points (poles, collapsed edges, apexes) the limit along a ray entering
 * the region, from the Taylor expansion of S_u x S_v in the ray parameter. */
#include "surface/surface_internal.h"

#include <float.h>

#define NORD GEOM_SURFACE_NORMAL_ORDER

static double norm3(const double *a)
{
    double m = fmax(fabs(a[0]), fmax(fabs(a[1]), fabs(a[2])));
    if (!(m > 0.0))
        return 0.0;
    double x = a[0] / m, y = a[1] / m, z = a[2] / m;
    return m * sqrt(x * x + y * y + z * z);
}

static void cross3(const double *a, const double *b, double *c)
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

static int unit3(const double *a, double *out)
{
    double l = norm3(a);
    if (!(l > 0.0) || !isfinite(l)) {
        out[0] = out[1] = out[2] = 0.0;
        return 0;
    }
    out[0] = a[0] / l;
    out[1] = a[1] / l;
    out[2] = a[2] / l;
    return 1;
}

size_t geom__surface_normal_work(const geom_nurbs_surface *s)
{
    size_t d1 = NORD + 1;
    int pm = s->degree_u > s->degree_v ? s->degree_u : s->degree_v;
    size_t a = 3 * d1 * d1 + geom__surface_derivs_work(s, NORD);
    size_t b = 2 * ((size_t)s->degree_u + 1) + 2 * ((size_t)s->degree_v + 1) +
               geom__bs_ders_work(pm);
    return a > b ? a : b;
}

/*
 * Rounding noise of the derivative vectors scaled by the span widths, at
 * (u, v): the derivatives are sums of basis derivatives times homogeneous
 * control points relative to the span's first one, divided by the weight
 * function; their rounding error is a few eps times the same sums taken
 * with magnitudes,
 *   (sum |N'_i| M_j w_ij |P_ij - P_ref| + sum |N'_i| M_j w_ij |S - P_ref|) / W
 * (and likewise in v), times the span width and 64 (p + q) eps: the
 * thresholds below which S_u- and S_v-like vectors count as zero. work: 2(p+1) + 2(q+1) + geom__bs_ders_work(max(p, q)).
 */
static void span_noise(const geom_nurbs_surface *s, size_t ku, size_t kv, double u, double v,
                       double wu, double wv, double *work, double *nfu, double *nfv)
{
    int p = s->degree_u, q = s->degree_v;
    size_t p1 = (size_t)p + 1, q1 = (size_t)q + 1;
    double *Nu = work, *Nv = Nu + 2 * p1, *bw = Nv + 2 * q1;
    geom__bs_ders(p, s->knots_u, ku, u, 1, Nu, bw);
    geom__bs_ders(q, s->knots_v, kv, v, 1, Nv, bw);
    size_t i0 = ku - (size_t)p, j0 = kv - (size_t)q, nv = s->nv;
    const double *R = s->points + 3 * (i0 * nv + j0);
    double W = 0.0, mS = 0.0, aU = 0.0, wU = 0.0, aV = 0.0, wV = 0.0;
    for (int i = 0; i <= p; ++i)
        for (int j = 0; j <= q; ++j) {
            size_t idx = (i0 + (size_t)i) * nv + j0 + (size_t)j;
            const double *P = s->points + 3 * idx;
            double w = s->weights ? s->weights[idx] : 1.0;
            double d = fmax(fabs(P[0] - R[0]), fmax(fabs(P[1] - R[1]), fabs(P[2] - R[2])));
            double b = Nu[i] * Nv[j] * w;
            W += b;
            mS += b * d;
            double bu = fabs(Nu[p1 + (size_t)i]) * Nv[j] * w;
            double bv = Nu[i] * fabs(Nv[q1 + (size_t)j]) * w;
            aU += bu * d;
            wU += bu;
            aV += bv * d;
            wV += bv;
        }
    *nfu = *nfv = 0.0;
    if (!(W > 0.0))
        return;
    mS /= W;
    double c = 64.0 * (double)(p + q) * DBL_EPSILON;
    *nfu = c * (aU + wU * mS) / W * wu;
    *nfv = c * (aV + wV * mS) / W * wv;
}

/* Taylor coefficients along the ray (a, b) (already scaled by the span
 * widths through D): A_r = 1/r! sum_i C(r,i) a^i b^(r-i) D(1+i, r-i),
 * B_r likewise with D(i, 1+r-i); vectors below the noise are zeroed. */
static void ray_coeffs(const double *D, int a, int b, double nfu, double nfv, double *A,
                       double *B)
{
    size_t d1 = NORD + 1;
    double fact = 1.0;
    for (int r = 0; r < NORD; ++r) {
        if (r > 0)
            fact *= (double)r;
        double *Ar = A + 3 * r, *Br = B + 3 * r;
        Ar[0] = Ar[1] = Ar[2] = Br[0] = Br[1] = Br[2] = 0.0;
        for (int i = 0; i <= r; ++i) {
            double ca = (i == 0 ? 1.0 : (a == 0 ? 0.0 : pow((double)a, i)));
            double cb = (r - i == 0 ? 1.0 : (b == 0 ? 0.0 : pow((double)b, r - i)));
            double c = geom__binom(r, i) * ca * cb;
            if (c == 0.0)
                continue;
            const double *Du = D + 3 * ((size_t)(1 + i) * d1 + (size_t)(r - i));
            const double *Dv = D + 3 * ((size_t)i * d1 + (size_t)(1 + r - i));
            for (int k = 0; k < 3; ++k) {
                Ar[k] += c * Du[k];
                Br[k] += c * Dv[k];
            }
        }
        double g = pow(4.0, r);
        for (int k = 0; k < 3; ++k) {
            Ar[k] /= fact;
            Br[k] /= fact;
        }
        if (norm3(Ar) <= nfu * g)
            Ar[0] = Ar[1] = Ar[2] = 0.0;
        if (norm3(Br) <= nfv * g)
            Br[0] = Br[1] = Br[2] = 0.0;
    }
}

/* First coefficient c_m of S_u x S_v along the ray that stands out of the
 * noise; 1 with its unit vector in n, 0 if none. */
static int ray_normal(const double *A, const double *B, double nfu, double nfv, double *n)
{
    for (int m = 0; m < NORD; ++m) {
        double c[3] = {0.0, 0.0, 0.0}, T = 0.0, noise = 0.0;
        for (int r = 0; r <= m; ++r) {
            double x[3];
            cross3(A + 3 * r, B + 3 * (m - r), x);
            c[0] += x[0];
            c[1] += x[1];
            c[2] += x[2];
            double la = norm3(A + 3 * r), lb = norm3(B + 3 * (m - r));
            T += la * lb;
            noise += nfv * pow(4.0, m - r) * la + nfu * pow(4.0, r) * lb;
        }
        double lc = norm3(c);
        if (T > 0.0 && lc > 1e3 * noise && lc > 1e-12 * T)
            return unit3(c, n);
    }
    return 0;
}

/* First A_r (tangent direction) standing out of the noise. */
static int ray_first(const double *A, double *t)
{
    for (int r = 0; r < NORD; ++r)
        if (unit3(A + 3 * r, t))
            return 1;
    return 0;
}

int geom__surface_span_normal(const geom_nurbs_surface *s, size_t ku, size_t kv, double u, double v,
                             int su, int sv, double n[3], double tangent[3], double *work)
{
    double wu = s->knots_u[ku + 1] - s->knots_u[ku];
    double wv = s->knots_v[kv + 1] - s->knots_v[kv];
    double nfu, nfv;
    span_noise(s, ku, kv, u, v, wu, wv, work, &nfu, &nfv);
    double D1[12];
    double *pw = work;
    geom__surface_span_derivs(s, ku, kv, u, v, 1, D1, pw);
    double A0[3] = {D1[6] * wu, D1[7] * wu, D1[8] * wu}; /* S^(1,0) */
    double B0[3] = {D1[3] * wv, D1[4] * wv, D1[5] * wv}; /* S^(0,1) */
    double c0[3];
    cross3(A0, B0, c0);
    double la = norm3(A0), lb = norm3(B0), lc = norm3(c0);
    if (lc > 1e3 * (nfu * lb + nfv * la) && unit3(c0, n)) {
        if (tangent)
            unit3(A0, tangent);
        return GEOM_SURFACE_NORMAL_REGULAR;
    }
    /* degenerate: higher derivatives, scaled by the span widths */
    size_t d1 = NORD + 1;
    double *D = work;
    double *w2 = work + 3 * d1 * d1;
    geom__surface_span_derivs(s, ku, kv, u, v, NORD, D, w2);
    double pu = 1.0;
    for (int k = 0; k <= NORD; ++k) {
        double pv = 1.0;
        for (int l = 0; k + l <= NORD; ++l) {
            double *x = D + 3 * ((size_t)k * d1 + (size_t)l);
            x[0] *= pu * pv;
            x[1] *= pu * pv;
            x[2] *= pu * pv;
            pv *= wv;
        }
        pu *= wu;
    }
    su = su < 0 ? -1 : 1;
    sv = sv < 0 ? -1 : 1;
    int dirs[4][2];
    int nd = 0;
    int azero = la <= 1e3 * nfu, bzero = lb <= 1e3 * nfv;
    if (azero && !bzero) {
        dirs[nd][0] = 0, dirs[nd][1] = sv, nd++;
    } else if (bzero && !azero) {
        dirs[nd][0] = su, dirs[nd][1] = 0, nd++;
    }
    dirs[nd][0] = su, dirs[nd][1] = sv, nd++;
    if (!(azero && !bzero))
        dirs[nd][0] = 0, dirs[nd][1] = sv, nd++;
    if (!(bzero && !azero))
        dirs[nd][0] = su, dirs[nd][1] = 0, nd++;
    double A[3 * NORD], B[3 * NORD];
    for (int t = 0; t < nd; ++t) {
        ray_coeffs(D, dirs[t][0], dirs[t][1], nfu, nfv, A, B);
        if (ray_normal(A, B, nfu, nfv, n)) {
            if (tangent) {
                if (!ray_first(A, tangent)) {
                    /* dP/du vanishes along the ray: perpendicular to n in
                     * the plane of n and dP/dv */
                    double b[3], x[3];
                    if (ray_first(B, b)) {
                        cross3(b, n, x);
                        unit3(x, tangent);
                    } else {
                        tangent[0] = tangent[1] = tangent[2] = 0.0;
                    }
                } else {
                    /* keep the tangent perpendicular to n */
                    double dn = tangent[0] * n[0] + tangent[1] * n[1] + tangent[2] * n[2];
                    double x[3] = {tangent[0] - dn * n[0], tangent[1] - dn * n[1],
                                   tangent[2] - dn * n[2]};
                    if (!unit3(x, tangent)) {
                        double b[3];
                        if (ray_first(B, b)) {
                            cross3(b, n, x);
                            unit3(x, tangent);
                        }
                    }
                }
            }
            return GEOM_SURFACE_NORMAL_LIMIT;
        }
    }
    n[0] = n[1] = n[2] = 0.0;
    if (tangent)
        tangent[0] = tangent[1] = tangent[2] = 0.0;
    return GEOM_SURFACE_NORMAL_NONE;
}

geom_status geom_surface_normal(const geom_nurbs_surface *s, double u, double v, unsigned flags,
                                double n[3], int *how)
{
    if (geom__surface_check_cheap(s) != GEOM_OK || !n)
        return GEOM_ERR_INVALID_ARG;
    size_t ku, kv;
    geom_status st = geom__surface_locate(s, u, v, flags, &ku, &kv);
    if (st != GEOM_OK)
        return st;
    double u0 = s->knots_u[s->degree_u], u1 = s->knots_u[s->nu];
    double v0 = s->knots_v[s->degree_v], v1 = s->knots_v[s->nv];
    /* into the span being evaluated (the side the flags select) when the
     * point is at one of its ends, else toward the domain's middle */
    int su = u < 0.5 * (u0 + u1) ? 1 : -1;
    int sv = v < 0.5 * (v0 + v1) ? 1 : -1;
    if (u == s->knots_u[ku])
        su = 1;
    else if (u == s->knots_u[ku + 1])
        su = -1;
    if (v == s->knots_v[kv])
        sv = 1;
    else if (v == s->knots_v[kv + 1])
        sv = -1;
    geom__scratch sc;
    st = geom__scratch_init(&sc, geom__surface_normal_work(s));
    if (st != GEOM_OK) {
        geom__scratch_free(&sc);
        return st;
    }
    int h = geom__surface_span_normal(s, ku, kv, u, v, su, sv, n, NULL, sc.mem);
    geom__scratch_free(&sc);
    if (how)
        *how = h;
    return h == GEOM_SURFACE_NORMAL_NONE ? GEOM_ERR_DEGENERATE : GEOM_OK;
}
