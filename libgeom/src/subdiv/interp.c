/*
 * Vertex data refinement: face points, then edge points, then vertex points
 * of one level from the previous one, with the masks of masks.c applied in
 * OpenSubdiv's order (face weights, then edge weights, then the vertex's
 * own), so results agree with PrimvarRefinerReal<double>::Interpolate to
 * rounding. The common smooth cases take a direct path.
 */
#include "masks.h"

SD_KERNEL void edge_points(const sd_opts *o, const sd_level *p, const sd_level *c, size_t n,
                        const double *src, double *dst, double *fbuf)
{
    int loop = o->scheme == GEOM_SUBDIV_LOOP;
    int bilinear = o->scheme == GEOM_SUBDIV_BILINEAR;
    uint32_t e0 = loop ? 0 : p->nf;
    for (uint32_t e = 0; e < p->ne; e++) {
        uint32_t cv = e0 + e;
        const uint32_t *ev = p->ev + 2 * (size_t)e;
        double *d = dst + (size_t)cv * n;
        uint32_t fo = p->ef_off[e], nf = p->ef_off[e + 1] - fo;
        if (bilinear) {
            sd_set_w(d, src + (size_t)ev[0] * n, 0.5, n);
            sd_add_w(d, src + (size_t)ev[1] * n, 0.5, n);
            continue;
        }
        if (p->esharp[e] <= 0.0f && nf == 2 && !o->smooth_tri) {
            /* smooth edge, two faces */
            if (loop) {
                sd_set_w(d, src + (size_t)ev[0] * n, 0.375, n);
                sd_add_w(d, src + (size_t)ev[1] * n, 0.375, n);
                for (uint32_t i = 0; i < 2; i++) {
                    uint32_t f = p->ef[fo + i], fi = p->ef_loc[fo + i];
                    uint32_t opp = p->fv[3 * (size_t)f + (fi + 2) % 3];
                    sd_add_w(d, src + (size_t)opp * n, 0.125, n);
                }
            } else {
                sd_set_w(d, src + (size_t)ev[0] * n, 0.25, n);
                sd_add_w(d, src + (size_t)ev[1] * n, 0.25, n);
                sd_add_w(d, dst + (size_t)p->ef[fo] * n, 0.25, n);
                sd_add_w(d, dst + (size_t)p->ef[fo + 1] * n, 0.25, n);
            }
            continue;
        }
        double vw[2];
        sd_mask m;
        m.f = fbuf;
        sd_edge_mask(o, p, e, c->vtag[cv] & SD_V_RULE, vw, &m);
        sd_edge_apply(p, e, &m, vw, ev, n, p->fv, NULL, src, dst, d);
    }
}

SD_KERNEL void vertex_points(const sd_opts *o, const sd_level *p, const sd_level *c, size_t n,
                          const double *src, double *dst, sd_scratch *s)
{
    int loop = o->scheme == GEOM_SUBDIV_LOOP;
    uint32_t v0 = (loop ? 0 : p->nf) + p->ne;
    double *ew = s->w, *fw = s->w + s->cap;
    for (uint32_t v = 0; v < p->nv; v++) {
        uint32_t cv = v0 + v;
        double *d = dst + (size_t)cv * n;
        const double *sv = src + (size_t)v * n;
        int rule = p->vtag[v] & SD_V_RULE;
        uint32_t eo = p->ve_off[v], ne = p->ve_off[v + 1] - eo;
        uint32_t fo = p->vf_off[v], nf = p->vf_off[v + 1] - fo;
        if (o->scheme == GEOM_SUBDIV_BILINEAR) {
            sd_set_w(d, sv, 1.0, n);
            continue;
        }
        sd_mask m;
        m.e = ew;
        m.f = fw;
        if (rule == SD_RULE_SMOOTH || rule == SD_RULE_DART) {
            /* direct smooth masks */
            double e, vw;
            sd_smooth_weights(loop, nf, &e, &vw);
            sd_zero(d, n);
            if (loop) {
                for (uint32_t i = 0; i < ne; i++) {
                    const uint32_t *ev = p->ev + 2 * (size_t)p->ve[eo + i];
                    uint32_t ov = ev[0] == v ? ev[1] : ev[0];
                    sd_add_w(d, src + (size_t)ov * n, e, n);
                }
                sd_add_w(d, sv, vw, n);
            } else {
                for (uint32_t i = 0; i < nf; i++)
                    sd_add_w(d, dst + (size_t)p->vf[fo + i] * n, e, n);
                for (uint32_t i = 0; i < ne; i++) {
                    const uint32_t *ev = p->ev + 2 * (size_t)p->ve[eo + i];
                    uint32_t ov = ev[0] == v ? ev[1] : ev[0];
                    sd_add_w(d, src + (size_t)ov * n, e, n);
                }
                sd_add_w(d, sv, vw, n);
            }
            continue;
        }
        sd_vertex_mask(o, p, c, v, cv, &m, s);
        sd_zero(d, n);
        if (m.nf > 0) {
            for (uint32_t i = 0; i < nf; i++)
                sd_add_w(d, dst + (size_t)p->vf[fo + i] * n, m.f[i], n);
        }
        if (m.ne > 0) {
            for (uint32_t i = 0; i < ne; i++) {
                const uint32_t *ev = p->ev + 2 * (size_t)p->ve[eo + i];
                uint32_t ov = ev[0] == v ? ev[1] : ev[0];
                sd_add_w(d, src + (size_t)ov * n, m.e[i], n);
            }
        }
        sd_add_w(d, sv, m.v, n);
    }
}

geom_status geom_subdiv_interpolate(const geom_subdiv_refiner *r, int level, size_t ncomp,
                                    const double *src, double *dst)
{
    geom_status st = sd_check_interp(r, level, ncomp, src, dst);
    if (st != GEOM_OK)
        return st;
    const sd_level *p = r->lv[level - 1], *c = r->lv[level];
    if (c->st_off) {
        sd_stencils_apply(c->nv, c->st_off, c->st_idx, c->st_w, ncomp, src, dst);
        return GEOM_OK;
    }
    const geom_allocator *a = sd_alloc(r);
    sd_scratch s;
    if (sd_scratch_init(a, &s, sd_mask_room(p)) != GEOM_OK)
        return GEOM_ERR_NOMEM;
    if (ncomp == 3) {
        if (sd_quad_split(&r->o))
            sd_face_points(p, 3, p->fv, NULL, src, dst);
        edge_points(&r->o, p, c, 3, src, dst, s.w);
        vertex_points(&r->o, p, c, 3, src, dst, &s);
    } else {
        if (sd_quad_split(&r->o))
            sd_face_points(p, ncomp, p->fv, NULL, src, dst);
        edge_points(&r->o, p, c, ncomp, src, dst, s.w);
        vertex_points(&r->o, p, c, ncomp, src, dst, &s);
    }
    sd_scratch_free(a, &s);
    return GEOM_OK;
}

geom_status geom_subdiv_interpolate_varying(const geom_subdiv_refiner *r, int level, size_t ncomp,
                                            const double *src, double *dst)
{
    geom_status st = sd_check_interp(r, level, ncomp, src, dst);
    if (st != GEOM_OK)
        return st;
    const sd_level *p = r->lv[level - 1], *c = r->lv[level];
    size_t n = ncomp;
    if (c->st_off) {
        /* generic schemes: linear interpolation from the parent of each vertex */
        for (uint32_t v = 0; v < c->nv; v++) {
            uint32_t kind = c->vparent[v] >> 30, par = c->vparent[v] & 0x3fffffffu;
            double *d = dst + (size_t)v * n;
            if (kind == GEOM_SUBDIV_FROM_VERTEX) {
                sd_set_w(d, src + (size_t)par * n, 1.0, n);
            } else if (kind == GEOM_SUBDIV_FROM_EDGE) {
                sd_set_w(d, src + (size_t)p->ev[2 * (size_t)par] * n, 0.5, n);
                sd_add_w(d, src + (size_t)p->ev[2 * (size_t)par + 1] * n, 0.5, n);
            } else {
                uint32_t o = p->fv_off[par], m = p->fv_off[par + 1] - o;
                for (size_t k = 0; k < n; k++)
                    d[k] = 0.0;
                for (uint32_t i = 0; i < m; i++)
                    sd_add_w(d, src + (size_t)p->fv[o + i] * n, 1.0 / (double)m, n);
            }
        }
        return GEOM_OK;
    }
    int quad = sd_quad_split(&r->o);
    if (quad)
        sd_face_points(p, n, p->fv, NULL, src, dst);
    uint32_t e0 = quad ? p->nf : 0, v0 = e0 + p->ne;
    for (uint32_t e = 0; e < p->ne; e++) {
        double *d = dst + (size_t)(e0 + e) * n;
        sd_set_w(d, src + (size_t)p->ev[2 * (size_t)e] * n, 0.5, n);
        sd_add_w(d, src + (size_t)p->ev[2 * (size_t)e + 1] * n, 0.5, n);
    }
    for (uint32_t v = 0; v < p->nv; v++)
        sd_set_w(dst + (size_t)(v0 + v) * n, src + (size_t)v * n, 1.0, n);
    return GEOM_OK;
}

geom_status geom_subdiv_interpolate_face(const geom_subdiv_refiner *r, int level, size_t ncomp,
                                         const double *src, double *dst)
{
    geom_status st = sd_check_interp(r, level, ncomp, src, dst);
    if (st != GEOM_OK)
        return st;
    const sd_level *c = r->lv[level];
    for (uint32_t f = 0; f < c->nf; f++)
        memcpy(dst + (size_t)f * ncomp, src + (size_t)c->face_parent[f] * ncomp,
               ncomp * sizeof(double));
    return GEOM_OK;
}
