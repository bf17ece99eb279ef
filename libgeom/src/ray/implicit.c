/* Implicit surfaces f = 0 of compiled expressions: guaranteed hits by
 * interval arithmetic over the boxes enclosing ray segments (Mitchell,
 * "Robust Ray Intersection with Interval Arithmetic", GI 1990), then
 * bisection on a sign change to full precision. Optional sphere tracing
 * (Hart 1996) with a user Lipschitz bound skips empty space first.
 * prm: bounds (0..5), Lipschitz bound (6). */
#include "ray/ray_internal.h"

static double feval(const geom_implicit_expr *e, const geom_ray *r, double t)
{
    double p[3] = {r->origin.x + t * r->dir.x, r->origin.y + t * r->dir.y, r->origin.z + t * r->dir.z};
    return geom_implicit_expr_eval(e, p);
}

/* Clip the ray to box b (6 doubles); 0 if it misses. */
static int clip_box(const geom_ray *r, const double *b, double *t0, double *t1)
{
    geom_aabb bx;
    bx.min = geom__v3(b);
    bx.max = geom__v3(b + 3);
    return geom_ray_aabb(r, bx, t0, t1);
}

static geom_status emit(const geom__ray_node *nd, const geom_ray *r, double t, double width, int enter,
                        geom__rhits *out)
{
    geom_ray_hit *h = geom__push_t(out, r, t);
    double p[3], g[3];
    int k;
    if (!h) return out->failed ? GEOM_ERR_NOMEM : GEOM_OK;
    p[0] = r->origin.x + t * r->dir.x;
    p[1] = r->origin.y + t * r->dir.y;
    p[2] = r->origin.z + t * r->dir.z;
    geom_implicit_expr_eval_grad(nd->expr, p, g);
    h->point = geom__v3(p);
    h->ng = h->ns = geom__unit(geom__v3(g));
    if (g[0] == 0 && g[1] == 0 && g[2] == 0) h->ng = h->ns = geom__unit(geom_vec3_neg(r->dir));
    h->enter = enter;
    h->t_error = width + DBL_EPSILON * fabs(t);
    h->p_error = geom__perr_ray(r, t);
    for (k = 0; k < 3; k++) (&h->p_error.x)[k] += width * fabs((&r->dir.x)[k]);
    h->u = h->v = 0;
    return GEOM_OK;
}

geom_status geom__ray_implicit(const geom__ray_node *nd, const geom_ray *r, int mode, geom__rhits *out)
{
    const double *bx = nd->prm;
    double t0, t1, tol, diag, dl;
    struct seg { double a, b; } stack[200];
    int sp = 0;
    size_t found = 0;
    if (!clip_box(r, bx, &t0, &t1)) return GEOM_OK;
    dl = geom_vec3_length(r->dir);
    diag = sqrt((bx[3] - bx[0]) * (bx[3] - bx[0]) + (bx[4] - bx[1]) * (bx[4] - bx[1]) +
                (bx[5] - bx[2]) * (bx[5] - bx[2]));
    tol = 1e-10 * diag / dl;
    /* Sphere tracing: safe steps |f| / L while outside (first hit only). */
    if (nd->prm[6] > 0 && mode != GEOM__RAY_ALL) {
        double L = nd->prm[6];
        int it;
        for (it = 0; it < 1000 && t0 < t1; it++) {
            double f = feval(nd->expr, r, t0);
            if (!(f > 1e-6 * diag * L)) break;
            t0 += f / (L * dl) * 0.999;
        }
        if (t0 >= t1) return GEOM_OK;
    }
    stack[sp].a = t0;
    stack[sp].b = t1;
    sp++;
    while (sp > 0) {
        struct seg sg = stack[--sp];
        double lo[3], hi[3], iv[2], pa[3], pb[3];
        int k;
        for (k = 0; k < 3; k++) {
            pa[k] = (&r->origin.x)[k] + sg.a * (&r->dir.x)[k];
            pb[k] = (&r->origin.x)[k] + sg.b * (&r->dir.x)[k];
            lo[k] = fmin(pa[k], pb[k]);
            hi[k] = fmax(pa[k], pb[k]);
            /* widen by the rounding of the points */
            lo[k] -= geom__gamma(3) * (fabs(lo[k]) + fabs(hi[k]));
            hi[k] += geom__gamma(3) * (fabs(lo[k]) + fabs(hi[k]));
        }
        if (geom_implicit_expr_eval_interval(nd->expr, lo, hi, iv) != GEOM_OK) continue;
        if (isnan(iv[0]) || iv[0] > 0 || iv[1] < 0) continue;
        if (sg.b - sg.a <= tol || sp + 2 > (int)(sizeof stack / sizeof stack[0])) {
            double fa = feval(nd->expr, r, sg.a), fb = feval(nd->expr, r, sg.b), a = sg.a, b = sg.b;
            int it;
            geom_status st;
            if (fa == 0 && sg.a > t0) continue; /* reported by the previous segment */
            if (!((fa <= 0 && fb > 0) || (fa > 0 && fb <= 0) || (fa < 0 && fb >= 0) || (fa >= 0 && fb < 0)))
                continue;
            {
                int enter = fa > 0 || (fa == 0 && fb < 0);
                for (it = 0; it < 200; it++) {
                    double m = 0.5 * (a + b), fm;
                    if (m <= a || m >= b) break;
                    fm = feval(nd->expr, r, m);
                    if ((fm > 0) == (fa > 0) && fm != 0) { a = m; fa = fm; }
                    else b = m;
                }
                st = emit(nd, r, fa == 0 ? a : b, b - a, enter, out);
            }
            if (st != GEOM_OK) return st;
            found++;
            if (mode != GEOM__RAY_ALL) return GEOM_OK;
            continue;
        }
        {
            double m = 0.5 * (sg.a + sg.b);
            stack[sp].a = m; stack[sp].b = sg.b; sp++;
            stack[sp].a = sg.a; stack[sp].b = m; sp++;
        }
    }
    (void)found;
    return GEOM_OK;
}
