/* Watertight ray/triangle intersection (Woop, Benthin and Wald, JCGT 2013)
 * in double with exact edge-function signs and an edge-ownership rule for
 * zero edge functions, and planar polygons by the winding number in the
 * same sheared frame. */
#include "ray/ray_internal.h"
#include "ray/wbw.h"

void geom__wbw_setup(geom__wbw *w, const geom_ray *r)
{
    double d[3] = {r->dir.x, r->dir.y, r->dir.z};
    int kz = 0, kx, ky;
    if (fabs(d[1]) > fabs(d[kz])) kz = 1;
    if (fabs(d[2]) > fabs(d[kz])) kz = 2;
    kx = (kz + 1) % 3;
    ky = (kx + 1) % 3;
    if (d[kz] < 0) {
        int t = kx; kx = ky; ky = t;
    }
    w->kx = kx; w->ky = ky; w->kz = kz;
    w->sx = d[kx] / d[kz];
    w->sy = d[ky] / d[kz];
    w->sz = 1.0 / d[kz];
    w->o[0] = r->origin.x; w->o[1] = r->origin.y; w->o[2] = r->origin.z;
    memcpy(w->d, d, sizeof d);
}

int geom__wbw_test(const geom__wbw *w, const double *v0, const double *v1, const double *v2,
                   double tmin, double tmax, double *t, double *b)
{
    return geom__wbw_hit(w, v0, v1, v2, tmin, tmax, t, b);
}

void geom__tri_fill(const geom_ray *r, const double *v0, const double *v1, const double *v2,
                    double t, const double *b, geom_ray_hit *h)
{
    double p[3], pe[3], e1[3], e2[3];
    int k;
    for (k = 0; k < 3; k++) {
        p[k] = b[0] * v0[k] + b[1] * v1[k] + b[2] * v2[k];
        pe[k] = geom__gamma(7) * (fabs(b[0] * v0[k]) + fabs(b[1] * v1[k]) + fabs(b[2] * v2[k]));
        e1[k] = v1[k] - v0[k];
        e2[k] = v2[k] - v0[k];
    }
    h->t = t;
    h->point = geom__v3(p);
    h->p_error = geom__v3(pe);
    h->ng = geom__unit(geom_vec3_cross(geom__v3(e1), geom__v3(e2)));
    h->ns = h->ng;
    h->u = b[1];
    h->v = b[2];
    h->enter = geom__dot(r->dir, h->ng) < 0;
    h->t_error = geom__terr(r, t, 0, h->ng);
    {
        /* The point's own error along the normal, over |n.d|. */
        double dn = fabs(geom__dot(h->ng, r->dir));
        double pn = fabs(h->ng.x) * pe[0] + fabs(h->ng.y) * pe[1] + fabs(h->ng.z) * pe[2];
        if (dn > 0) h->t_error += pn / dn;
    }
}

int geom_ray_triangle(const geom_ray *r, const double v0[3], const double v1[3], const double v2[3],
                      geom_ray_hit *hit)
{
    geom__wbw w;
    double t, b[3];
    if (geom_ray_check(r) != GEOM_OK || !v0 || !v1 || !v2 || !hit) return 0;
    geom__wbw_setup(&w, r);
    if (!geom__wbw_test(&w, v0, v1, v2, r->tmin, r->tmax, &t, b)) return 0;
    memset(hit, 0, sizeof *hit);
    geom__tri_fill(r, v0, v1, v2, t, b, hit);
    return 1;
}

geom_status geom__ray_tri(const geom__ray_node *nd, const geom_ray *r, int mode, geom__rhits *out)
{
    geom__wbw w;
    double t, b[3];
    geom_ray_hit *h;
    (void)mode;
    geom__wbw_setup(&w, r);
    if (!geom__wbw_test(&w, nd->prm, nd->prm + 3, nd->prm + 6, r->tmin, r->tmax, &t, b)) return GEOM_OK;
    h = geom__rhits_push(out);
    if (!h) return GEOM_ERR_NOMEM;
    geom__tri_fill(r, nd->prm, nd->prm + 3, nd->prm + 6, t, b, h);
    return GEOM_OK;
}

/* Polygon: prm holds the unit Newell normal (0..2) and centroid (3..5). */
geom_status geom__ray_polygon(const geom__ray_node *nd, const geom_ray *r, int mode, geom__rhits *out)
{
    geom__wbw w;
    const double *v = nd->verts;
    size_t n = nd->nverts, i;
    int wn = 0;
    geom_vec3 nrm = geom__v3(nd->prm), c = geom__v3(nd->prm + 3), p;
    double dn, t;
    geom_ray_hit *h;
    (void)mode;
    geom__wbw_setup(&w, r);
    for (i = 0; i < n; i++) {
        const double *P = v + 3 * i, *Q = v + 3 * ((i + 1) % n);
        double px = (P[w.kx] - w.o[w.kx]) - w.sx * (P[w.kz] - w.o[w.kz]);
        double py = (P[w.ky] - w.o[w.ky]) - w.sy * (P[w.kz] - w.o[w.kz]);
        double qx = (Q[w.kx] - w.o[w.kx]) - w.sx * (Q[w.kz] - w.o[w.kz]);
        double qy = (Q[w.ky] - w.o[w.ky]) - w.sy * (Q[w.kz] - w.o[w.kz]);
        double e;
        /* Crossing of the +x half-line from the origin, half-open in y. */
        if (py <= 0 && qy > 0) {
            e = geom__wbw_edge(px, py, qx, qy);
            if (e > 0 || (e == 0 && geom__wbw_owns(px, py, qx, qy))) wn++;
        } else if (py > 0 && qy <= 0) {
            e = geom__wbw_edge(px, py, qx, qy);
            if (e < 0 || (e == 0 && geom__wbw_owns(px, py, qx, qy))) wn--;
        }
    }
    if (wn == 0) return GEOM_OK;
    dn = geom__dot(r->dir, nrm);
    if (dn == 0) return GEOM_OK;
    t = geom__dot(geom_vec3_sub(c, r->origin), nrm) / dn;
    h = geom__push_t(out, r, t);
    if (!h) return out->failed ? GEOM_ERR_NOMEM : GEOM_OK;
    p = geom_vec3_add(r->origin, geom_vec3_scale(r->dir, t));
    p = geom_vec3_sub(p, geom_vec3_scale(nrm, geom__dot(geom_vec3_sub(p, c), nrm)));
    h->point = p;
    h->p_error = geom__perr_ray(r, t);
    h->ng = h->ns = nrm;
    h->enter = dn < 0;
    h->t_error = geom__terr(r, t, 0, nrm);
    {
        geom_vec3 t1, t2, rel = geom_vec3_sub(p, geom__v3(v));
        geom__frame(nrm, &t1, &t2);
        h->u = geom__dot(rel, t1);
        h->v = geom__dot(rel, t2);
    }
    return GEOM_OK;
}
