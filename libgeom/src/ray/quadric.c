/* General quadric F(x) = x^T A x + 2 b.x + j, inside F < 0, optionally
 * restricted to a box and capped by it. prm: a..j (0..9), clip min (10..12),
 * max (13..15), clip flag (16). */
#include "ray/ray_internal.h"

static double qeval(const double *q, const double *p, double *bound, double grad[3])
{
    double x = p[0], y = p[1], z = p[2];
    double t[10];
    double s = 0, m = 0;
    int i;
    t[0] = q[0] * x * x; t[1] = q[1] * y * y; t[2] = q[2] * z * z;
    t[3] = 2 * q[3] * x * y; t[4] = 2 * q[4] * y * z; t[5] = 2 * q[5] * x * z;
    t[6] = 2 * q[6] * x; t[7] = 2 * q[7] * y; t[8] = 2 * q[8] * z; t[9] = q[9];
    for (i = 0; i < 10; i++) {
        s += t[i];
        m += fabs(t[i]);
    }
    if (bound) *bound = geom__gamma(14) * m;
    if (grad) {
        grad[0] = 2 * (q[0] * x + q[3] * y + q[5] * z + q[6]);
        grad[1] = 2 * (q[3] * x + q[1] * y + q[4] * z + q[7]);
        grad[2] = 2 * (q[5] * x + q[4] * y + q[2] * z + q[8]);
    }
    return s;
}

/* Polish t by Newton on F(o + t d), keeping the step only if |F| drops. */
static double polish(const double *q, const geom_ray *r, double t)
{
    int it;
    for (it = 0; it < 2; it++) {
        double p[3] = {r->origin.x + t * r->dir.x, r->origin.y + t * r->dir.y,
                       r->origin.z + t * r->dir.z};
        double g[3], f = qeval(q, p, NULL, g), df = g[0] * r->dir.x + g[1] * r->dir.y + g[2] * r->dir.z;
        double tn, fn, pn[3];
        if (f == 0 || df == 0 || !isfinite(df)) break;
        tn = t - f / df;
        pn[0] = r->origin.x + tn * r->dir.x;
        pn[1] = r->origin.y + tn * r->dir.y;
        pn[2] = r->origin.z + tn * r->dir.z;
        fn = qeval(q, pn, NULL, NULL);
        if (!(fabs(fn) < fabs(f))) break;
        t = tn;
    }
    return t;
}

typedef struct qev { double t; int face; int enter; } qev; /* face -1: quadric */

static int inside_clip(const double *lo, const double *hi, const double *p, double tol)
{
    int k;
    for (k = 0; k < 3; k++)
        if (p[k] < lo[k] - tol || p[k] > hi[k] + tol) return 0;
    return 1;
}

geom_status geom__ray_quadric(const geom__ray_node *nd, const geom_ray *r, int mode, geom__rhits *out)
{
    const double *q = nd->prm, *lo = nd->prm + 10, *hi = nd->prm + 13;
    int clip = nd->prm[16] != 0;
    double o[3] = {r->origin.x, r->origin.y, r->origin.z}, d[3] = {r->dir.x, r->dir.y, r->dir.z};
    double ref[3] = {0, 0, 0}, ts, o2[3], qa, qb, qc, Ad[3], roots[2];
    int nroots = 0, k;
    double tb0 = -INFINITY, tb1 = INFINITY;
    int fb0 = -1, fb1 = -1;
    qev ev[4];
    int nev = 0, i;
    (void)mode;
    /* Shift the origin to the ray point nearest the clip box centre (or the
     * local origin) so the quadratic's coefficients keep their digits. */
    if (clip)
        for (k = 0; k < 3; k++) ref[k] = isfinite(lo[k] + hi[k]) ? 0.5 * (lo[k] + hi[k]) : 0;
    ts = ((ref[0] - o[0]) * d[0] + (ref[1] - o[1]) * d[1] + (ref[2] - o[2]) * d[2]) /
         (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (k = 0; k < 3; k++) o2[k] = o[k] + ts * d[k];
    Ad[0] = q[0] * d[0] + q[3] * d[1] + q[5] * d[2];
    Ad[1] = q[3] * d[0] + q[1] * d[1] + q[4] * d[2];
    Ad[2] = q[5] * d[0] + q[4] * d[1] + q[2] * d[2];
    qa = Ad[0] * d[0] + Ad[1] * d[1] + Ad[2] * d[2];
    qb = Ad[0] * o2[0] + Ad[1] * o2[1] + Ad[2] * o2[2] + q[6] * d[0] + q[7] * d[1] + q[8] * d[2];
    qc = qeval(q, o2, NULL, NULL);
    /* Inside intervals of F along the ray: F(s) = qa s^2 + 2 qb s + qc. */
    {
        double scale = fabs(qa) + fabs(qb) + fabs(qc);
        double disc = qb * qb - qa * qc;
        if (fabs(qa) <= 1e-15 * scale) {
            if (qb != 0) {
                roots[0] = -qc / (2 * qb);
                nroots = 1;
            }
        } else if (disc >= 0) {
            double qq = -(qb + copysign(sqrt(disc), qb));
            if (qq != 0) {
                roots[0] = qq / qa;
                roots[1] = qc / qq;
            } else {
                roots[0] = roots[1] = -qb / qa;
            }
            if (roots[0] > roots[1]) {
                double tt = roots[0]; roots[0] = roots[1]; roots[1] = tt;
            }
            nroots = 2;
        }
    }
    for (i = 0; i < nroots; i++) roots[i] = polish(q, r, roots[i] + ts);
    if (nroots == 2 && roots[0] > roots[1]) {
        double tt = roots[0]; roots[0] = roots[1]; roots[1] = tt;
    }
    if (clip) {
        double a = -INFINITY, b = INFINITY;
        for (k = 0; k < 3; k++) {
            if (d[k] == 0) {
                if (o[k] < lo[k] || o[k] > hi[k]) return GEOM_OK;
                continue;
            }
            {
                double tn = (lo[k] - o[k]) / d[k], tf = (hi[k] - o[k]) / d[k];
                int fn = 2 * k, ff = 2 * k + 1;
                if (tn > tf) { double tt = tn; tn = tf; tf = tt; fn = 2 * k + 1; ff = 2 * k; }
                if (tn > a) { a = tn; fb0 = fn; }
                if (tf < b) { b = tf; fb1 = ff; }
            }
        }
        if (!(a <= b)) return GEOM_OK;
        tb0 = a; tb1 = b;
    }
    if (nd->capped && clip) {
        /* Solid {F < 0} inter box: intervals, then intersect with [tb0, tb1]. */
        double iv[4];
        int niv = 0;
        double sgn_inf; /* sign of F at t -> +inf */
        if (nroots == 2) {
            if (qa > 0) { iv[0] = roots[0]; iv[1] = roots[1]; niv = 2; }
            else { iv[0] = -INFINITY; iv[1] = roots[0]; iv[2] = roots[1]; iv[3] = INFINITY; niv = 4; }
        } else if (nroots == 1) {
            sgn_inf = qb;
            if (sgn_inf > 0) { iv[0] = -INFINITY; iv[1] = roots[0]; }
            else { iv[0] = roots[0]; iv[1] = INFINITY; }
            niv = 2;
        } else {
            if (fabs(qa) > 0 ? qa < 0 : qc < 0) { iv[0] = -INFINITY; iv[1] = INFINITY; niv = 2; }
        }
        for (i = 0; i < niv; i += 2) {
            double s0 = iv[i], s1 = iv[i + 1];
            int f0 = -1, f1 = -1;
            if (tb0 > s0) { s0 = tb0; f0 = fb0; }
            if (tb1 < s1) { s1 = tb1; f1 = fb1; }
            if (!(s0 <= s1)) continue;
            ev[nev].t = s0; ev[nev].face = f0; ev[nev].enter = 1; nev++;
            ev[nev].t = s1; ev[nev].face = f1; ev[nev].enter = 0; nev++;
        }
    } else {
        for (i = 0; i < nroots; i++) {
            double p[3];
            if (clip) {
                for (k = 0; k < 3; k++) p[k] = o[k] + roots[i] * d[k];
                if (!inside_clip(lo, hi, p, 0)) continue;
            }
            ev[nev].t = roots[i];
            ev[nev].face = -1;
            ev[nev].enter = nroots == 2 ? ((qa > 0) == (i == 0)) : (qb < 0);
            nev++;
        }
    }
    for (i = 0; i < nev; i++) {
        geom_ray_hit *h;
        double p[3], g[3], fb, f;
        if (!isfinite(ev[i].t)) continue;
        h = geom__push_t(out, r, ev[i].t);
        if (!h) { if (out->failed) return GEOM_ERR_NOMEM; continue; }
        for (k = 0; k < 3; k++) p[k] = o[k] + ev[i].t * d[k];
        h->point = geom__v3(p);
        h->p_error = geom__perr_ray(r, ev[i].t);
        h->enter = ev[i].enter;
        if (ev[i].face >= 0) {
            int ax = ev[i].face / 2;
            double n[3] = {0, 0, 0};
            n[ax] = (ev[i].face & 1) ? 1 : -1;
            p[ax] = (ev[i].face & 1) ? hi[ax] : lo[ax];
            h->point = geom__v3(p);
            h->ng = h->ns = geom__v3(n);
            h->prim = 1 + (uint32_t)ev[i].face;
            h->t_error = geom__terr(r, ev[i].t, 0, h->ng);
        } else {
            geom_vec3 n;
            f = qeval(q, p, &fb, g);
            n = geom__unit(geom__v3(g));
            if (g[0] == 0 && g[1] == 0 && g[2] == 0) n = geom__unit(geom_vec3_neg(r->dir));
            h->ng = h->ns = n;
            {
                double gl = geom_vec3_length(geom__v3(g));
                double dn = fabs(geom__dot(n, r->dir));
                h->t_error = (gl > 0 && dn > 0)
                                 ? (fabs(f) + fb) / (gl * dn) + DBL_EPSILON * fabs(ev[i].t)
                                 : INFINITY;
            }
        }
        h->u = atan2(p[1], p[0]) / (2 * GEOM_PI);
        if (h->u < 0) h->u += 1;
        if (h->u >= 1) h->u = 0;
        h->v = p[2];
        if (mode == GEOM__RAY_ANY) break;
    }
    return GEOM_OK;
}

geom_status geom_ray_quadric_make(geom_ray_quadric_shape shape, const double *p, double q[10])
{
    int k, np = (shape == GEOM_RAY_QUADRIC_ELLIPSOID) ? 3
                : (shape == GEOM_RAY_QUADRIC_HYPERBOLOID1 || shape == GEOM_RAY_QUADRIC_HYPERBOLOID2) ? 2
                                                                                                  : 1;
    if (!p || !q) return GEOM_ERR_INVALID_ARG;
    for (k = 0; k < np; k++) {
        if (isnan(p[k]) || !isfinite(p[k])) return GEOM_ERR_INVALID_ARG;
        if (!(p[k] > 0)) return GEOM_ERR_DOMAIN;
    }
    for (k = 0; k < 10; k++) q[k] = 0;
    switch (shape) {
    case GEOM_RAY_QUADRIC_ELLIPSOID:
        q[0] = 1 / (p[0] * p[0]); q[1] = 1 / (p[1] * p[1]); q[2] = 1 / (p[2] * p[2]); q[9] = -1;
        break;
    case GEOM_RAY_QUADRIC_CYLINDER:
        q[0] = 1; q[1] = 1; q[9] = -p[0] * p[0];
        break;
    case GEOM_RAY_QUADRIC_CONE:
        q[0] = 1; q[1] = 1; q[2] = -p[0] * p[0];
        break;
    case GEOM_RAY_QUADRIC_PARABOLOID:
        q[0] = 1; q[1] = 1; q[8] = -0.5 * p[0];
        break;
    case GEOM_RAY_QUADRIC_HYPERBOLOID1:
        q[0] = q[1] = 1 / (p[0] * p[0]); q[2] = -1 / (p[1] * p[1]); q[9] = -1;
        break;
    case GEOM_RAY_QUADRIC_HYPERBOLOID2:
        q[0] = q[1] = 1 / (p[0] * p[0]); q[2] = -1 / (p[1] * p[1]); q[9] = 1;
        break;
    default:
        return GEOM_ERR_INVALID_ARG;
    }
    return GEOM_OK;
}
