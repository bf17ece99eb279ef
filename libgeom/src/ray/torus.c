/* Torus about z: (|p|^2 + R^2 - r^2)^2 - 4 R^2 (x^2 + y^2) = 0, inside < 0.
 * prm: R (0), r (1). The quartic is formed about the ray point nearest the
 * centre with a unit direction and solved by geom__poly_roots with the
 * coefficients' rounding errors, so tangencies are double roots, not
 * misses, and values above the error bound never give a root. */
#include "ray/ray_internal.h"

static double tfun(double R, double rr, const double *p, double *bound, double g[3])
{
    double x2 = p[0] * p[0], y2 = p[1] * p[1], z2 = p[2] * p[2];
    double s = x2 + y2 + z2 + R * R - rr * rr;
    double w = 4 * R * R * (x2 + y2);
    double f = s * s - w;
    if (bound) *bound = geom__gamma(12) * (fabs(s) * (x2 + y2 + z2 + R * R + rr * rr) + w) * 2;
    if (g) {
        g[0] = 4 * s * p[0] - 8 * R * R * p[0];
        g[1] = 4 * s * p[1] - 8 * R * R * p[1];
        g[2] = 4 * s * p[2];
    }
    return f;
}

geom_status geom__ray_torus(const geom__ray_node *nd, const geom_ray *r, int mode, geom__rhits *out)
{
    double R = nd->prm[0], rr = nd->prm[1];
    double o[3] = {r->origin.x, r->origin.y, r->origin.z}, d[3] = {r->dir.x, r->dir.y, r->dir.z};
    double L = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), dn[3], ts, o2[3], c[5], ce[5];
    double roots[4], ext = R + rr, e, f, A, B, C, g = geom__gamma(8), lo, hi;
    size_t nr, i;
    int k;
    if (!(L > 0) || !isfinite(L)) return GEOM_OK;
    for (k = 0; k < 3; k++) dn[k] = d[k] / L;
    ts = -(o[0] * dn[0] + o[1] * dn[1] + o[2] * dn[2]);
    for (k = 0; k < 3; k++) o2[k] = o[k] + ts * dn[k];
    {
        double dist2 = o2[0] * o2[0] + o2[1] * o2[1] + o2[2] * o2[2];
        if (dist2 > ext * ext * (1 + 1e-12)) return GEOM_OK;
        e = dist2 + R * R - rr * rr;
        f = o2[0] * dn[0] + o2[1] * dn[1] + o2[2] * dn[2];
        A = dn[0] * dn[0] + dn[1] * dn[1];
        B = o2[0] * dn[0] + o2[1] * dn[1];
        C = o2[0] * o2[0] + o2[1] * o2[1];
        c[4] = 1;
        c[3] = 4 * f;
        c[2] = 4 * f * f + 2 * e - 4 * R * R * A;
        c[1] = 4 * f * e - 8 * R * R * B;
        c[0] = e * e - 4 * R * R * C;
        {
            double ea = dist2 + R * R + rr * rr; /* magnitude bound of e */
            ce[4] = 0;
            ce[3] = g * 4 * fabs(f) + 4 * g * ext;
            ce[2] = g * (4 * f * f + 2 * ea + 4 * R * R * A) * 2;
            ce[1] = g * (4 * fabs(f) * ea + 8 * R * R * fabs(B)) * 2 + g * 8 * ext * ea;
            ce[0] = g * (ea * ea + 4 * R * R * C) * 2;
        }
    }
    {
        double half = sqrt(fmax(0.0, ext * ext - (e - R * R + rr * rr))) * 1.001 + ext * 1e-9;
        lo = -half;
        hi = half;
    }
    nr = geom__poly_roots(c, ce, 4, lo, hi, roots);
    for (i = 0; i < nr; i++) {
        double t = (ts + roots[i]) / L, p[3], gr[3], fv, fb;
        geom_ray_hit *h;
        int it, tangent = (i + 1 < nr && roots[i + 1] == roots[i]) || (i > 0 && roots[i - 1] == roots[i]);
        /* Newton polish in the original frame (not at a double root). */
        for (it = 0; it < 3 && !tangent; it++) {
            double pn[3], tn, df, fn;
            for (k = 0; k < 3; k++) p[k] = o[k] + t * d[k];
            fv = tfun(R, rr, p, NULL, gr);
            df = gr[0] * d[0] + gr[1] * d[1] + gr[2] * d[2];
            if (fv == 0 || df == 0) break;
            tn = t - fv / df;
            for (k = 0; k < 3; k++) pn[k] = o[k] + tn * d[k];
            fn = tfun(R, rr, pn, NULL, NULL);
            if (!(fabs(fn) < fabs(fv))) break;
            t = tn;
        }
        h = geom__push_t(out, r, t);
        if (!h) { if (out->failed) return GEOM_ERR_NOMEM; continue; }
        for (k = 0; k < 3; k++) p[k] = o[k] + t * d[k];
        fv = tfun(R, rr, p, &fb, gr);
        h->point = geom__v3(p);
        h->p_error = geom__perr_ray(r, t);
        {
            double rho = hypot(p[0], p[1]);
            geom_vec3 n;
            if (rho > 0) {
                double q[3] = {p[0] - R * p[0] / rho, p[1] - R * p[1] / rho, p[2]};
                n = geom__unit(geom__v3(q));
            } else {
                n = geom__unit(geom__v3(gr));
            }
            h->ng = h->ns = n;
            {
                double gl = geom_vec3_length(geom__v3(gr)), dd = fabs(geom__dot(n, r->dir));
                h->t_error = (gl > 0 && dd > 0) ? (fabs(fv) + fb) / (gl * dd) + DBL_EPSILON * fabs(t)
                                                : INFINITY;
            }
            h->u = atan2(p[1], p[0]) / (2 * GEOM_PI);
            if (h->u < 0) h->u += 1;
            h->v = atan2(p[2], rho - R) / (2 * GEOM_PI);
            if (h->v < 0) h->v += 1;
            if (h->u >= 1) h->u = 0;
            if (h->v >= 1) h->v = 0;
        }
        h->enter = (i % 2) == 0;
        if (mode == GEOM__RAY_ANY) break;
    }
    return GEOM_OK;
}
