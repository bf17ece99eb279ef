/* Iso-surfaces of sampled volumes: 3D-DDA over the cells (Amanatides and
 * Woo, "A Fast Voxel Traversal Algorithm for Ray Tracing", Eurographics
 * 1987) and, per cell, the exact roots of the trilinear interpolant along
 * the ray, a cubic in t (Parker et al. 1998; Marmitt et al. 2004).
 * prm: iso (0), inside (1: 0 f < iso, 1 f > iso, the normal then against the
 * gradient so that it faces away from the inside). */
#include "ray/ray_internal.h"

/* (a0 + a1 s) (b...) product helpers on polynomials of degree <= 3. */
static void pmul1(const double *p, int deg, double a0, double a1, double *out)
{
    int i;
    double tmp[4] = {0, 0, 0, 0};
    for (i = 0; i <= deg; i++) {
        tmp[i] += p[i] * a0;
        tmp[i + 1] += p[i] * a1;
    }
    memcpy(out, tmp, sizeof tmp);
}

geom_status geom__ray_volume(const geom__ray_node *nd, const geom_ray *r, int mode, geom__rhits *out)
{
    geom_implicit_volume_desc dsc;
    geom_aabb bb;
    double t0, t1, iso = nd->prm[0];
    int above = nd->prm[1] != 0;
    double o[3] = {r->origin.x, r->origin.y, r->origin.z}, d[3] = {r->dir.x, r->dir.y, r->dir.z};
    double sp[3];
    long cell[3], ncell[3], step[3];
    double tmaxv[3], tdelta[3];
    int k;
    geom_implicit_volume_get_desc(nd->vol, &dsc);
    for (k = 0; k < 3; k++) {
        sp[k] = dsc.spacing[k] > 0 ? dsc.spacing[k] : 1;
        ncell[k] = (long)dsc.dims[k] - 1;
        if (ncell[k] < 1) return GEOM_OK;
    }
    bb = geom_implicit_volume_bounds(nd->vol);
    if (!geom_ray_aabb(r, bb, &t0, &t1)) return GEOM_OK;
    if (!isfinite(t0) || !isfinite(t1)) return GEOM_OK;
    {
        double tm = 0.5 * (t0 + t0); /* entry point */
        for (k = 0; k < 3; k++) {
            double x = (o[k] + tm * d[k] - dsc.origin[k]) / sp[k];
            long c = (long)floor(x);
            if (c < 0) c = 0;
            if (c >= ncell[k]) c = ncell[k] - 1;
            cell[k] = c;
            if (d[k] > 0) {
                step[k] = 1;
                tmaxv[k] = (dsc.origin[k] + (double)(c + 1) * sp[k] - o[k]) / d[k];
                tdelta[k] = sp[k] / d[k];
            } else if (d[k] < 0) {
                step[k] = -1;
                tmaxv[k] = (dsc.origin[k] + (double)c * sp[k] - o[k]) / d[k];
                tdelta[k] = -sp[k] / d[k];
            } else {
                step[k] = 0;
                tmaxv[k] = INFINITY;
                tdelta[k] = INFINITY;
            }
        }
    }
    {
        double ta = t0;
        for (;;) {
            double tb = fmin(fmin(tmaxv[0], tmaxv[1]), fmin(tmaxv[2], t1));
            double v[8], xa[3], x1[3], poly[4], cerr[4], roots[3], mag = 0;
            size_t nr, i;
            int axis = 0, last = tb >= t1;
            if (tmaxv[1] < tmaxv[axis]) axis = 1;
            if (tmaxv[2] < tmaxv[axis]) axis = 2;
            if (tb > ta) {
                for (k = 0; k < 8; k++) {
                    v[k] = geom_implicit_volume_at(nd->vol, (size_t)(cell[0] + (k & 1)),
                                                   (size_t)(cell[1] + ((k >> 1) & 1)),
                                                   (size_t)(cell[2] + ((k >> 2) & 1))) -
                           iso;
                    mag += fabs(v[k]);
                }
                for (k = 0; k < 3; k++) {
                    xa[k] = (o[k] + ta * d[k] - dsc.origin[k]) / sp[k] - (double)cell[k];
                    x1[k] = d[k] / sp[k];
                }
                memset(poly, 0, sizeof poly);
                for (k = 0; k < 8; k++) {
                    double p[4] = {v[k], 0, 0, 0};
                    int dg = 0, j;
                    for (j = 0; j < 3; j++) {
                        if ((k >> j) & 1) pmul1(p, dg, xa[j], x1[j], p);
                        else pmul1(p, dg, 1 - xa[j], -x1[j], p);
                        dg++;
                    }
                    for (j = 0; j < 4; j++) poly[j] += p[j];
                }
                for (k = 0; k < 4; k++) cerr[k] = geom__gamma(16) * mag * pow(fabs(x1[0]) + fabs(x1[1]) + fabs(x1[2]) + 1, k);
                nr = geom__poly_roots(poly, cerr, 3, 0, tb - ta, roots);
                for (i = 0; i < nr; i++) {
                    double t = ta + roots[i], p[3], g[3];
                    geom_ray_hit *h;
                    if (roots[i] >= tb - ta && !last) continue; /* the next cell's */
                    if (i > 0 && roots[i] == roots[i - 1]) continue;
                    h = geom__push_t(out, r, t);
                    if (!h) { if (out->failed) return GEOM_ERR_NOMEM; continue; }
                    for (k = 0; k < 3; k++) p[k] = o[k] + t * d[k];
                    geom_implicit_volume_eval_grad(nd->vol, p, g);
                    h->point = geom__v3(p);
                    if (above)
                        for (k = 0; k < 3; k++) g[k] = -g[k];
                    h->ng = h->ns = geom__unit(geom__v3(g));
                    if (g[0] == 0 && g[1] == 0 && g[2] == 0) h->ng = h->ns = geom__unit(geom_vec3_neg(r->dir));
                    h->enter = geom__dot(h->ng, r->dir) < 0;
                    h->prim = (uint32_t)(cell[0] + ncell[0] * (cell[1] + ncell[1] * cell[2]));
                    h->p_error = geom__perr_ray(r, t);
                    h->t_error = geom__terr(r, t, 0, h->ng) + 4 * DBL_EPSILON * (tb - ta);
                    if (mode != GEOM__RAY_ALL) return GEOM_OK;
                }
            }
            if (last) break;
            ta = tb;
            cell[axis] += step[axis];
            if (cell[axis] < 0 || cell[axis] >= ncell[axis]) break;
            tmaxv[axis] += tdelta[axis];
        }
    }
    return GEOM_OK;
}
