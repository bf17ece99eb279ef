/* B-spline and NURBS surfaces intersected directly: rational Bezier patches
 * (built once), the ray as the intersection of two planes (Kajiya 1982;
 * Nishita, Sederberg and Kakimoto, "Ray Tracing Trimmed Rational Surface
 * Patches", SIGGRAPH 1990), subdivision of the projected 2D patch while its
 * control points' bounding box contains the origin, and Newton's method on
 * S(u, v) = o + t d with the surface's exact derivatives. */
#include "ray/ray_internal.h"
#include "geom/curve.h"

#define SURF_MAX_DEPTH 90
#define SURF_TOL 1e-12

void geom__ray_surface_free(geom__tsurf *sf, const geom_allocator *alloc)
{
    size_t nk_u, nk_v, np;
    if (!sf) return;
    nk_u = sf->s.nu + (size_t)sf->s.degree_u + 1;
    nk_v = sf->s.nv + (size_t)sf->s.degree_v + 1;
    np = sf->s.nu * sf->s.nv;
    if (sf->knots_u) geom__free(alloc, sf->knots_u, nk_u * sizeof(double));
    if (sf->knots_v) geom__free(alloc, sf->knots_v, nk_v * sizeof(double));
    if (sf->points) geom__free(alloc, sf->points, 3 * np * sizeof(double));
    if (sf->weights) geom__free(alloc, sf->weights, np * sizeof(double));
    if (sf->hp) {
        size_t per = (size_t)(sf->s.degree_u + 1) * (size_t)(sf->s.degree_v + 1) * 4;
        geom__free(alloc, sf->hp, sf->np * per * sizeof(double));
        geom__free(alloc, sf->dom, sf->np * 4 * sizeof(double));
        geom__free(alloc, sf->pbox, sf->np * sizeof(geom_aabb));
    }
    geom__free(alloc, sf, sizeof *sf);
}

geom_status geom__ray_surface_build(geom__tsurf *sf, const geom_allocator *alloc, geom_diag *diag)
{
    const geom_nurbs_surface *s = &sf->s;
    int pu = s->degree_u, pv = s->degree_v;
    size_t nu = s->nu, nv = s->nv, nsu, nsv, i, j, a, b, su, sv;
    double *H = NULL, *U = NULL, *bu = NULL, *bv = NULL, *row = NULL, *out = NULL;
    geom_nurbs_curve c;
    geom_status st = GEOM_OK;
    size_t per;
    geom_aabb all = geom_aabb_empty();
    /* Segment counts via a curve along each direction. */
    memset(&c, 0, sizeof c);
    c.degree = pu; c.n = nu; c.dim = 4; c.knots = s->knots_u;
    {
        double dummy[4] = {0, 0, 0, 0};
        (void)dummy;
    }
    c.points = s->points; /* only the knots matter for the count */
    c.dim = 3;
    if ((st = geom_curve_nurbs_segments(&c, &nsu)) != GEOM_OK) return st;
    c.degree = pv; c.n = nv; c.knots = s->knots_v;
    if ((st = geom_curve_nurbs_segments(&c, &nsv)) != GEOM_OK) return st;
    per = (size_t)(pu + 1) * (size_t)(pv + 1) * 4;
    H = geom__alloc(alloc, nu * nv * 4 * sizeof(double));
    U = geom__alloc(alloc, nv * nsu * (size_t)(pu + 1) * 4 * sizeof(double));
    bu = geom__alloc(alloc, (nsu + 1) * sizeof(double));
    bv = geom__alloc(alloc, (nsv + 1) * sizeof(double));
    row = geom__alloc(alloc, (nu > nv ? nu : nv) * 4 * sizeof(double));
    out = geom__alloc(alloc, (nsu > nsv ? nsu : nsv) * (size_t)((pu > pv ? pu : pv) + 1) * 4 * sizeof(double));
    sf->np = nsu * nsv;
    sf->hp = geom__alloc(alloc, sf->np * per * sizeof(double));
    sf->dom = geom__alloc(alloc, sf->np * 4 * sizeof(double));
    sf->pbox = geom__alloc(alloc, sf->np * sizeof(geom_aabb));
    if (!H || !U || !bu || !bv || !row || !out || !sf->hp || !sf->dom || !sf->pbox) {
        st = GEOM_ERR_NOMEM;
        goto done;
    }
    for (i = 0; i < nu * nv; i++) {
        double w = s->weights ? s->weights[i] : 1.0;
        H[4 * i] = w * s->points[3 * i];
        H[4 * i + 1] = w * s->points[3 * i + 1];
        H[4 * i + 2] = w * s->points[3 * i + 2];
        H[4 * i + 3] = w;
    }
    /* u direction, for every j. U[(j * nsu * (pu+1) + k) * 4]. */
    c.degree = pu; c.n = nu; c.dim = 4; c.knots = s->knots_u; c.weights = NULL;
    for (j = 0; j < nv; j++) {
        for (i = 0; i < nu; i++) memcpy(row + 4 * i, H + 4 * (i * nv + j), 4 * sizeof(double));
        c.points = row;
        if ((st = geom_curve_nurbs_decompose(&c, U + j * nsu * (size_t)(pu + 1) * 4, NULL, bu, diag)) != GEOM_OK)
            goto done;
    }
    c.degree = pv; c.n = nv; c.knots = s->knots_v;
    for (su = 0; su < nsu; su++)
        for (a = 0; a <= (size_t)pu; a++) {
            for (j = 0; j < nv; j++)
                memcpy(row + 4 * j, U + (j * nsu * (size_t)(pu + 1) + su * (size_t)(pu + 1) + a) * 4,
                       4 * sizeof(double));
            c.points = row;
            if ((st = geom_curve_nurbs_decompose(&c, out, NULL, bv, diag)) != GEOM_OK) goto done;
            for (sv = 0; sv < nsv; sv++)
                for (b = 0; b <= (size_t)pv; b++) {
                    double *dst = sf->hp + (su * nsv + sv) * per + (a * (size_t)(pv + 1) + b) * 4;
                    memcpy(dst, out + (sv * (size_t)(pv + 1) + b) * 4, 4 * sizeof(double));
                }
        }
    for (su = 0; su < nsu; su++)
        for (sv = 0; sv < nsv; sv++) {
            size_t pi = su * nsv + sv, k;
            geom_aabb bx = geom_aabb_empty();
            sf->dom[4 * pi] = bu[su];
            sf->dom[4 * pi + 1] = bu[su + 1];
            sf->dom[4 * pi + 2] = bv[sv];
            sf->dom[4 * pi + 3] = bv[sv + 1];
            for (k = 0; k < per / 4; k++) {
                const double *q = sf->hp + pi * per + 4 * k;
                bx = geom_aabb_extend(bx, geom_vec3_make(q[0] / q[3], q[1] / q[3], q[2] / q[3]));
            }
            {
                double e = geom__gamma(8) * (fabs(bx.min.x) + fabs(bx.min.y) + fabs(bx.min.z) +
                                             fabs(bx.max.x) + fabs(bx.max.y) + fabs(bx.max.z));
                bx.min = geom_vec3_make(bx.min.x - e, bx.min.y - e, bx.min.z - e);
                bx.max = geom_vec3_make(bx.max.x + e, bx.max.y + e, bx.max.z + e);
            }
            sf->pbox[pi] = bx;
            all = geom_aabb_union(all, bx);
        }
    sf->extent = geom_vec3_length(geom_vec3_sub(all.max, all.min));
    sf->wmax = 1;
    if (s->weights)
        for (i = 0; i < nu * nv; i++) sf->wmax = fmax(sf->wmax, s->weights[i]);
    sf->pmag = fmax(fmax(fmax(fabs(all.min.x), fabs(all.max.x)), fmax(fabs(all.min.y), fabs(all.max.y))),
                    fmax(fabs(all.min.z), fabs(all.max.z)));
done:
    if (H) geom__free(alloc, H, nu * nv * 4 * sizeof(double));
    if (U) geom__free(alloc, U, nv * nsu * (size_t)(pu + 1) * 4 * sizeof(double));
    if (bu) geom__free(alloc, bu, (nsu + 1) * sizeof(double));
    if (bv) geom__free(alloc, bv, (nsv + 1) * sizeof(double));
    if (row) geom__free(alloc, row, (nu > nv ? nu : nv) * 4 * sizeof(double));
    if (out) geom__free(alloc, out, (nsu > nsv ? nsu : nsv) * (size_t)((pu > pv ? pu : pv) + 1) * 4 * sizeof(double));
    return st;
}

/* Newton on S(u, v) - (o + t d) = 0 within [dom]; returns 1 on convergence. */
static int newton(const geom_nurbs_surface *s, const double *dom, const geom_ray *r, double *u, double *v,
                  double *t, double ext, double pmag)
{
    /* Residual accepted: below the rounding of points of this magnitude. */
    double tol = 1e-9 * ext + 256 * DBL_EPSILON * (pmag + fabs(*t) * geom_vec3_length(r->dir));
    double ders[12];
    int it;
    for (it = 0; it < 30; it++) {
        double F[3], J[9], det, du, dv, dt;
        if (geom_surface_derivs(s, *u, *v, 1, 0, ders) != GEOM_OK) return 0;
        F[0] = ders[0] - (r->origin.x + *t * r->dir.x);
        F[1] = ders[1] - (r->origin.y + *t * r->dir.y);
        F[2] = ders[2] - (r->origin.z + *t * r->dir.z);
        /* columns: Su (ders[6..8]), Sv (ders[3..5]), -d */
        J[0] = ders[6]; J[1] = ders[7]; J[2] = ders[8];
        J[3] = ders[3]; J[4] = ders[4]; J[5] = ders[5];
        J[6] = -r->dir.x; J[7] = -r->dir.y; J[8] = -r->dir.z;
        {
            geom_vec3 c0 = geom__v3(J), c1 = geom__v3(J + 3), c2 = geom__v3(J + 6), f = geom__v3(F);
            geom_vec3 x12 = geom_vec3_cross(c1, c2), x20 = geom_vec3_cross(c2, c0), x01 = geom_vec3_cross(c0, c1);
            det = geom__dot(c0, x12);
            if (det == 0 || !isfinite(det)) return 0;
            du = geom__dot(f, x12) / det;
            dv = geom__dot(f, x20) / det;
            dt = geom__dot(f, x01) / det;
        }
        *u -= du;
        *v -= dv;
        *t -= dt;
        if (*u < dom[0]) *u = dom[0];
        if (*u > dom[1]) *u = dom[1];
        if (*v < dom[2]) *v = dom[2];
        if (*v > dom[3]) *v = dom[3];
        if (!isfinite(*t)) return 0;
        if (fabs(du) <= 1e-15 * (dom[1] - dom[0]) && fabs(dv) <= 1e-15 * (dom[3] - dom[2])) {
            /* converged: check the residual */
            double res = sqrt(F[0] * F[0] + F[1] * F[1] + F[2] * F[2]);
            return res <= tol;
        }
    }
    {
        double res;
        if (geom_surface_derivs(s, *u, *v, 0, 0, ders) != GEOM_OK) return 0;
        res = sqrt((ders[0] - (r->origin.x + *t * r->dir.x)) * (ders[0] - (r->origin.x + *t * r->dir.x)) +
                   (ders[1] - (r->origin.y + *t * r->dir.y)) * (ders[1] - (r->origin.y + *t * r->dir.y)) +
                   (ders[2] - (r->origin.z + *t * r->dir.z)) * (ders[2] - (r->origin.z + *t * r->dir.z)));
        return res <= tol;
    }
}

typedef struct cand { double u, v, t; int tangent; } cand;

typedef struct sitem { double u0, u1, v0, v1; int depth; size_t off; } sitem;

/* Split a (pu+1)x(pv+1) net of 2D points (net[(a*(pv+1)+b)*2]) in u (dir 0)
 * or v (dir 1) at 1/2 into lo and hi. */
static void split(const double *net, int pu, int pv, int dir, double *lo, double *hi)
{
    int n = dir == 0 ? pu : pv, m = dir == 0 ? pv : pu, i, k, l;
    double tmp[2 * 33];
    for (l = 0; l <= m; l++) {
        for (i = 0; i <= n; i++) {
            int idx = dir == 0 ? (i * (pv + 1) + l) : (l * (pv + 1) + i);
            tmp[2 * i] = net[2 * idx];
            tmp[2 * i + 1] = net[2 * idx + 1];
        }
        for (k = 0; k <= n; k++) {
            int il = dir == 0 ? (k * (pv + 1) + l) : (l * (pv + 1) + k);
            int ih = dir == 0 ? ((n - k) * (pv + 1) + l) : (l * (pv + 1) + (n - k));
            lo[2 * il] = tmp[0];
            lo[2 * il + 1] = tmp[1];
            hi[2 * ih] = tmp[2 * (n - k)];
            hi[2 * ih + 1] = tmp[2 * (n - k) + 1];
            for (i = 0; i < n - k; i++) {
                tmp[2 * i] = 0.5 * (tmp[2 * i] + tmp[2 * i + 2]);
                tmp[2 * i + 1] = 0.5 * (tmp[2 * i + 1] + tmp[2 * i + 3]);
            }
        }
    }
}

geom_status geom__ray_surface(const geom__tsurf *sf, const geom_ray *r, int mode, geom__rhits *out)
{
    const geom_nurbs_surface *s = &sf->s;
    int pu = s->degree_u, pv = s->degree_v;
    size_t per = (size_t)(pu + 1) * (size_t)(pv + 1), pi;
    size_t stack_cap = 2 * (SURF_MAX_DEPTH + 2) + 2;
    double *nets;
    sitem *stack;
    cand cands[64];
    size_t ncand = 0, i;
    geom_vec3 n1, n2, dn;
    double e1, e2;
    geom_status st = GEOM_OK;
    if (pu > 32 || pv > 32) return GEOM_ERR_LIMIT;
    dn = geom__unit(r->dir);
    geom__frame(dn, &n1, &n2);
    e1 = -geom__dot(n1, r->origin);
    e2 = -geom__dot(n2, r->origin);
    nets = geom__alloc(out->alloc, stack_cap * per * 2 * sizeof(double));
    stack = geom__alloc(out->alloc, stack_cap * sizeof *stack);
    if (!nets || !stack) {
        st = GEOM_ERR_NOMEM;
        goto done;
    }
    for (pi = 0; pi < sf->np; pi++) {
        const double *hp = sf->hp + pi * per * 4, *dom = sf->dom + 4 * pi;
        size_t sp = 0, k;
        if (!geom_ray_aabb(r, sf->pbox[pi], NULL, NULL)) continue;
        for (k = 0; k < per; k++) {
            const double *q = hp + 4 * k;
            nets[2 * k] = n1.x * q[0] + n1.y * q[1] + n1.z * q[2] + e1 * q[3];
            nets[2 * k + 1] = n2.x * q[0] + n2.y * q[1] + n2.z * q[2] + e2 * q[3];
        }
        stack[0].u0 = dom[0]; stack[0].u1 = dom[1]; stack[0].v0 = dom[2]; stack[0].v1 = dom[3];
        stack[0].depth = 0;
        stack[0].off = 0;
        sp = 1;
        while (sp > 0) {
            sitem it = stack[--sp];
            double *net = nets + it.off * per * 2;
            double mnx = INFINITY, mxx = -INFINITY, mny = INFINITY, mxy = -INFINITY, mag = 0;
            double wu = (it.u1 - it.u0) / (dom[1] - dom[0]), wv = (it.v1 - it.v0) / (dom[3] - dom[2]);
            for (k = 0; k < per; k++) {
                mnx = fmin(mnx, net[2 * k]); mxx = fmax(mxx, net[2 * k]);
                mny = fmin(mny, net[2 * k + 1]); mxy = fmax(mxy, net[2 * k + 1]);
                mag = fmax(mag, fabs(net[2 * k]) + fabs(net[2 * k + 1]));
            }
            {
                double slack = 64 * DBL_EPSILON * (mag + sf->extent * 1e-300);
                if (mnx > slack || mxx < -slack || mny > slack || mxy < -slack) continue;
            }
            /* Small enough: Newton from the centre. */
            if (it.depth >= 6 || (wu < 0.02 && wv < 0.02)) {
                double u = 0.5 * (it.u0 + it.u1), v = 0.5 * (it.v0 + it.v1), t, ders[3];
                if (geom_surface_eval(s, u, v, 0, ders) == GEOM_OK) {
                    t = geom__dot(geom_vec3_sub(geom__v3(ders), r->origin), r->dir) / geom__dot(r->dir, r->dir);
                    if (newton(s, dom, r, &u, &v, &t, sf->extent, sf->pmag)) {
                        double mu = 0.05 * (it.u1 - it.u0), mv = 0.05 * (it.v1 - it.v0);
                        if (u >= it.u0 - mu && u <= it.u1 + mu && v >= it.v0 - mv && v <= it.v1 + mv) {
                            /* Transversal and small: one root here. */
                            int dup = 0;
                            for (i = 0; i < ncand; i++)
                                if (fabs(cands[i].u - u) <= 1e-7 * (dom[1] - dom[0]) &&
                                    fabs(cands[i].v - v) <= 1e-7 * (dom[3] - dom[2]))
                                    dup = 1;
                            if (!dup && ncand < 64) {
                                cands[ncand].u = u; cands[ncand].v = v; cands[ncand].t = t;
                                cands[ncand].tangent = 0;
                                ncand++;
                            }
                            if (it.depth >= 10 || (wu < 1e-3 && wv < 1e-3)) continue;
                        }
                    }
                }
            }
            if (it.depth >= SURF_MAX_DEPTH || (wu < SURF_TOL && wv < SURF_TOL) ||
                fmax(mxx - mnx, mxy - mny) <= 1e-10 * sf->extent * sf->wmax) {
                /* Tangency: the region shrank without a Newton root of its own. */
                double u = 0.5 * (it.u0 + it.u1), v = 0.5 * (it.v0 + it.v1), p[3];
                int dup = 0;
                for (i = 0; i < ncand; i++)
                    if (fabs(cands[i].u - u) <= 1e-6 * (dom[1] - dom[0]) &&
                        fabs(cands[i].v - v) <= 1e-6 * (dom[3] - dom[2]))
                        dup = 1;
                if (!dup && ncand < 64 && geom_surface_eval(s, u, v, 0, p) == GEOM_OK) {
                    cands[ncand].u = u; cands[ncand].v = v;
                    cands[ncand].t = geom__dot(geom_vec3_sub(geom__v3(p), r->origin), r->dir) /
                                     geom__dot(r->dir, r->dir);
                    cands[ncand].tangent = 1;
                    ncand++;
                }
                continue;
            }
            {
                /* Split where the projected net varies most (not the longer
                 * parameter side): near a pole or a collapsed edge the
                 * collapsed direction barely varies, and splitting it would
                 * multiply the patches touching the ray without shrinking them. */
                double varu = 0, varv = 0;
                int a, b, dir;
                for (a = 0; a <= pu; a++)
                    for (b = 0; b <= pv; b++) {
                        const double *q = net + 2 * ((size_t)a * (size_t)(pv + 1) + (size_t)b);
                        if (a < pu) varu = fmax(varu, fabs(q[2 * (pv + 1)] - q[0]) + fabs(q[2 * (pv + 1) + 1] - q[1]));
                        if (b < pv) varv = fmax(varv, fabs(q[2] - q[0]) + fabs(q[3] - q[1]));
                    }
                dir = varu >= varv ? 0 : 1;
                if (wu < SURF_TOL) dir = 1;
                if (wv < SURF_TOL) dir = 0;
                sitem lo = it, hi = it;
                size_t offh = sp, offl = sp + 1;
                double *lon, *hin;
                if (sp + 2 > stack_cap) continue;
                /* The popped net may sit in slot offl or offh: copy it out first. */
                {
                    double tmpnet[2 * 33 * 33];
                    memcpy(tmpnet, net, per * 2 * sizeof(double));
                    lon = nets + offl * per * 2;
                    hin = nets + offh * per * 2;
                    split(tmpnet, pu, pv, dir, lon, hin);
                }
                if (dir == 0) {
                    double m = 0.5 * (it.u0 + it.u1);
                    lo.u1 = m; hi.u0 = m;
                } else {
                    double m = 0.5 * (it.v0 + it.v1);
                    lo.v1 = m; hi.v0 = m;
                }
                lo.depth = hi.depth = it.depth + 1;
                lo.off = offl;
                hi.off = offh;
                stack[sp++] = hi;
                stack[sp++] = lo;
            }
        }
    }
    for (i = 0; i < ncand; i++) {
        geom_ray_hit *h;
        double p[3], n[3], ders[12];
        int how;
        /* Drop the same point found from two patches (shared edges). */
        size_t j;
        int dup = 0;
        {
            /* the same point: t within the rounding of the points (shared patch edges) */
            double dl = geom_vec3_length(r->dir);
            double tol = (1e-9 * sf->extent + 256 * DBL_EPSILON * (sf->pmag + fabs(cands[i].t) * dl)) / dl;
            /* the same t is the same point in space (seams, shared patch edges) */
            for (j = 0; j < i; j++)
                if (fabs(cands[j].t - cands[i].t) <= tol)
                    dup = 1;
        }
        if (dup) continue;
        h = geom__push_t(out, r, cands[i].t);
        if (!h) { if (out->failed) { st = GEOM_ERR_NOMEM; goto done; } continue; }
        if (geom_surface_derivs(s, cands[i].u, cands[i].v, 0, 0, ders) != GEOM_OK) {
            out->n--;
            continue;
        }
        memcpy(p, ders, sizeof p);
        h->point = geom__v3(p);
        if (geom_surface_normal(s, cands[i].u, cands[i].v, 0, n, &how) != GEOM_OK) {
            geom_vec3 nn = geom__unit(geom_vec3_neg(r->dir));
            n[0] = nn.x; n[1] = nn.y; n[2] = nn.z;
        }
        h->ng = h->ns = geom__v3(n);
        h->u = cands[i].u;
        h->v = cands[i].v;
        h->enter = geom__dot(h->ng, r->dir) < 0;
        {
            double g = 8 * DBL_EPSILON * sf->extent;
            geom_vec3 rel = geom_vec3_sub(h->point, geom_vec3_add(r->origin, geom_vec3_scale(r->dir, h->t)));
            double dist = geom_vec3_length(rel);
            h->p_error = geom_vec3_make(g + geom__gamma(4) * fabs(p[0]), g + geom__gamma(4) * fabs(p[1]),
                                        g + geom__gamma(4) * fabs(p[2]));
            h->t_error = geom__terr(r, h->t, dist + g, h->ng);
            if (cands[i].tangent) h->t_error = fmax(h->t_error, 1e-6 * sf->extent / geom_vec3_length(r->dir));
        }
        h->prim = 0;
        if (mode == GEOM__RAY_ANY) break;
    }
done:
    if (nets) geom__free(out->alloc, nets, stack_cap * per * 2 * sizeof(double));
    if (stack) geom__free(out->alloc, stack, stack_cap * sizeof *stack);
    return st;
}
