/*
 * Limit positions, tangents and normals at the vertices of the deepest
 * level (OpenSubdiv's PrimvarRefiner::Limit): the eigenvector masks of
 * Catmull-Clark (Halstead, Kass and DeRose 1993) and Loop, the cubic
 * B-spline mask along creases and boundaries, and the limit tangent masks
 * of OpenSubdiv's Sdc schemes (Biermann et al. 2000 at irregular creases).
 * sqrt(3): the dominant left eigenvector of Kobbelt's relaxation step.
 */
#include "masks.h"

double sd_sqrt3_alpha(uint32_t n)
{
    return (4.0 - 2.0 * cos(2.0 * GEOM_PI / (double)n)) / 9.0;
}

static void apply(const sd_level *l, uint32_t v, const sd_mask *m, const uint32_t *eidx,
                  const uint32_t *fidx, size_t n, const double *src, double *d)
{
    sd_zero(d, n);
    for (int i = 0; i < m->nf; i++)
        sd_add_w(d, src + (size_t)fidx[i] * n, m->f[i], n);
    for (int i = 0; i < m->ne; i++)
        sd_add_w(d, src + (size_t)eidx[i] * n, m->e[i], n);
    sd_add_w(d, src + (size_t)v * n, m->v, n);
    (void)l;
}

geom_status geom_subdiv_limit(const geom_subdiv_refiner *r, size_t ncomp, const double *src,
                              double *pos, double *tan1, double *tan2)
{
    if (!r || !src || !pos || ncomp == 0 || (tan1 && !tan2) || (tan2 && !tan1))
        return GEOM_ERR_INVALID_ARG;
    const sd_level *l = r->lv[r->nlevels - 1];
    if (!l->complete)
        return GEOM_ERR_INVALID_ARG;
    const sd_opts *o = &r->o;
    size_t n = ncomp;
    int tangents = tan1 != NULL;
    if (tangents) {
        memset(tan1, 0, (size_t)l->nv * n * sizeof(double));
        memset(tan2, 0, (size_t)l->nv * n * sizeof(double));
    }
    if (o->scheme == GEOM_SUBDIV_BUTTERFLY) {
        memmove(pos, src, (size_t)l->nv * n * sizeof(double));
        return GEOM_OK;
    }
    if (o->scheme == GEOM_SUBDIV_SQRT3) {
        for (uint32_t v = 0; v < l->nv; v++) {
            double *d = pos + (size_t)v * n;
            uint32_t eo = l->ve_off[v], ne = l->ve_off[v + 1] - eo;
            if (ne == 0 || (l->vtag[v] & (SD_V_BOUNDARY | SD_V_NONMANIFOLD))) {
                memcpy(d, src + (size_t)v * n, n * sizeof(double));
                continue;
            }
            double al = sd_sqrt3_alpha(ne);
            double wq = 3.0 * al / (1.0 + 3.0 * al) / (double)ne;
            for (size_t k = 0; k < n; k++)
                d[k] = 0.0;
            for (uint32_t i = 0; i < ne; i++) {
                const uint32_t *ev = l->ev + 2 * (size_t)l->ve[eo + i];
                sd_add_w(d, src + (size_t)(ev[0] == v ? ev[1] : ev[0]) * n, wq, n);
            }
            sd_add_w(d, src + (size_t)v * n, 1.0 / (1.0 + 3.0 * al), n);
        }
        return GEOM_OK;
    }
    const geom_allocator *a = sd_alloc(r);
    uint32_t cap = l->max_valence + 2;
    sd_scratch s;
    if (sd_scratch_init(a, &s, cap) != GEOM_OK)
        return GEOM_ERR_NOMEM;
    double *w = sd_calloc(a, 6 * (size_t)cap, sizeof(double));
    uint32_t *idx = sd_calloc(a, 2 * (size_t)cap, sizeof(uint32_t));
    if (!w || !idx) {
        sd_scratch_free(a, &s);
        sd_free(a, w, 6 * (size_t)cap, sizeof(double));
        sd_free(a, idx, 2 * (size_t)cap, sizeof(uint32_t));
        return GEOM_ERR_NOMEM;
    }
    sd_mask mp = {0}, m1 = {0}, m2 = {0};
    mp.e = w, mp.f = w + cap;
    m1.e = w + 2 * (size_t)cap, m1.f = w + 3 * (size_t)cap;
    m2.e = w + 4 * (size_t)cap, m2.f = w + 5 * (size_t)cap;
    uint32_t *eidx = idx, *fidx = idx + cap;
    for (uint32_t v = 0; v < l->nv; v++) {
        uint32_t eo = l->ve_off[v], ne = l->ve_off[v + 1] - eo;
        uint32_t fo = l->vf_off[v], nf = l->vf_off[v + 1] - fo;
        double *d = pos + (size_t)v * n;
        if (ne == 0) {
            memmove(d, src + (size_t)v * n, n * sizeof(double));
            continue;
        }
        sd_limit_masks(o, l, v, &mp, tangents ? &m1 : NULL, tangents ? &m2 : NULL, &s);
        for (uint32_t i = 0; i < ne; i++) {
            const uint32_t *ev = l->ev + 2 * (size_t)l->ve[eo + i];
            eidx[i] = ev[0] == v ? ev[1] : ev[0];
        }
        if (mp.nf || (tangents && m1.nf)) {
            for (uint32_t i = 0; i < nf; i++) {
                uint32_t f = l->vf[fo + i], off = l->fv_off[f], fs = l->fv_off[f + 1] - off;
                uint32_t opp = l->vf_loc[fo + i] + 2u;
                if (opp >= fs)
                    opp -= fs;
                fidx[i] = l->fv[off + opp];
            }
        }
        apply(l, v, &mp, eidx, fidx, n, src, d);
        if (tangents) {
            apply(l, v, &m1, eidx, fidx, n, src, tan1 + (size_t)v * n);
            apply(l, v, &m2, eidx, fidx, n, src, tan2 + (size_t)v * n);
        }
    }
    sd_scratch_free(a, &s);
    sd_free(a, w, 6 * (size_t)cap, sizeof(double));
    sd_free(a, idx, 2 * (size_t)cap, sizeof(uint32_t));
    return GEOM_OK;
}

geom_status geom_subdiv_limit_normals(const geom_subdiv_refiner *r, const double *src,
                                      double *normals, size_t *n_degenerate)
{
    if (n_degenerate)
        *n_degenerate = 0;
    if (!r || !src || !normals)
        return GEOM_ERR_INVALID_ARG;
    if (r->o.scheme == GEOM_SUBDIV_BUTTERFLY || r->o.scheme == GEOM_SUBDIV_SQRT3)
        return GEOM_ERR_INVALID_ARG;
    const sd_level *l = r->lv[r->nlevels - 1];
    const geom_allocator *a = sd_alloc(r);
    size_t nv = l->nv;
    double *buf = sd_calloc(a, 9 * (nv ? nv : 1), sizeof(double));
    if (!buf)
        return GEOM_ERR_NOMEM;
    double *pos = buf, *t1 = buf + 3 * nv, *t2 = buf + 6 * nv;
    geom_status st = geom_subdiv_limit(r, 3, src, pos, t1, t2);
    if (st == GEOM_OK) {
        size_t bad = 0;
        for (size_t v = 0; v < nv; v++) {
            geom_vec3 a3 = {t1[3 * v], t1[3 * v + 1], t1[3 * v + 2]};
            geom_vec3 b3 = {t2[3 * v], t2[3 * v + 1], t2[3 * v + 2]};
            geom_vec3 ua, ub, nrm = {0.0, 0.0, 0.0};
            /* unit tangents first: no overflow or underflow in the cross product */
            if (geom_vec3_normalize(a3, &ua) != GEOM_OK ||
                geom_vec3_normalize(b3, &ub) != GEOM_OK ||
                geom_vec3_normalize(geom_vec3_cross(ua, ub), &nrm) != GEOM_OK) {
                nrm.x = nrm.y = nrm.z = 0.0;
                bad++;
            }
            normals[3 * v] = nrm.x;
            normals[3 * v + 1] = nrm.y;
            normals[3 * v + 2] = nrm.z;
        }
        if (n_degenerate)
            *n_degenerate = bad;
    }
    sd_free(a, buf, 9 * (nv ? nv : 1), sizeof(double));
    return st;
}
