/*
 * Face-varying data refinement and limit (OpenSubdiv's
 * PrimvarRefiner::InterpolateFaceVarying and LimitFaceVarying): values
 * whose topology matches the vertex topology use the vertex masks; values
 * split by seams or made linear by the face-varying option are creases
 * (B-spline along their span of faces, with fractional blending while
 * semi-sharp) or corners (copied).
 */
#include "masks.h"

static inline uint32_t vval(const sd_fvar *f, uint32_t v, uint32_t sib)
{
    return f->slot_value[f->vsib_off[v] + sib];
}

static void edge_face_values(const sd_fvar *f, const sd_level *l, uint32_t e, uint32_t finc,
                             uint32_t out[2])
{
    const uint32_t *ev = l->ev + 2 * (size_t)e;
    if (f->vsib_count[ev[0]] + f->vsib_count[ev[1]] > 2) {
        uint32_t fc = l->ef[l->ef_off[e] + finc], ein = l->ef_loc[l->ef_off[e] + finc];
        uint32_t fo = l->fv_off[fc], n = l->fv_off[fc + 1] - fo;
        out[0] = f->fvals[fo + ein];
        out[1] = f->fvals[fo + (ein + 1 < n ? ein + 1 : 0)];
        if (ev[0] != l->fv[fo + ein]) {
            uint32_t t = out[0];
            out[0] = out[1];
            out[1] = t;
        }
    } else {
        out[0] = vval(f, ev[0], 0);
        out[1] = vval(f, ev[1], 0);
    }
}

static void vertex_edge_values(const sd_fvar *f, const sd_level *l, uint32_t v, uint32_t *out)
{
    uint32_t eo = l->ve_off[v], ne = l->ve_off[v + 1] - eo, fo = l->vf_off[v];
    int boundary = (l->vtag[v] & SD_V_BOUNDARY) != 0;
    int manifold = !(l->vtag[v] & SD_V_NONMANIFOLD);
    for (uint32_t i = 0; i < ne; i++) {
        uint32_t e = l->ve[eo + i];
        uint32_t other = l->ev[2 * (size_t)e + !l->ve_loc[eo + i]];
        if (f->vsib_count[other] == 1) {
            out[i] = vval(f, other, 0);
        } else if (manifold) {
            if (boundary && i == ne - 1) {
                uint32_t fc = l->vf[fo + i - 1], vin = l->vf_loc[fo + i - 1];
                uint32_t n = l->fv_off[fc + 1] - l->fv_off[fc];
                uint32_t prev = vin ? vin - 1 : n - 1;
                out[i] = f->fvals[l->fv_off[fc] + prev];
            } else {
                uint32_t fc = l->vf[fo + i], vin = l->vf_loc[fo + i];
                uint32_t n = l->fv_off[fc + 1] - l->fv_off[fc];
                uint32_t next = vin == n - 1 ? 0 : vin + 1;
                out[i] = f->fvals[l->fv_off[fc] + next];
            }
        } else {
            uint32_t fc = l->ef[l->ef_off[e]], ein = l->ef_loc[l->ef_off[e]];
            uint32_t o = l->fv_off[fc], n = l->fv_off[fc + 1] - o;
            if (other == l->fv[o + ein])
                out[i] = f->fvals[o + ein];
            else
                out[i] = f->fvals[o + (ein == n - 1 ? 0 : ein + 1)];
        }
    }
}

static void crease_end_values(const sd_fvar *f, const sd_level *l, uint32_t v, uint32_t sib,
                              uint32_t out[2])
{
    const uint16_t *ends = f->crease_ends + 2 * (size_t)(f->vsib_off[v] + sib);
    uint32_t fo = l->vf_off[v];
    uint32_t f0 = l->vf[fo + ends[0]], f1 = l->vf[fo + ends[1]];
    uint32_t n0 = l->fv_off[f0 + 1] - l->fv_off[f0], n1 = l->fv_off[f1 + 1] - l->fv_off[f1];
    uint32_t i0 = l->vf_loc[fo + ends[0]], i1 = l->vf_loc[fo + ends[1]];
    i0 = (i0 == n0 - 1) ? 0 : i0 + 1;
    i1 = (i1 ? i1 : n1) - 1;
    out[0] = f->fvals[l->fv_off[f0] + i0];
    out[1] = f->fvals[l->fv_off[f1] + i1];
}

static double fractional_weight(const sd_opts *o, const sd_level *p, const sd_fvar *pf,
                                const sd_level *c, uint32_t pv, uint32_t psib, uint32_t cv,
                                float *buf)
{
    const uint32_t *pE = p->ve + p->ve_off[pv], *cE = c->ve + c->ve_off[cv];
    uint32_t ne = p->ve_off[pv + 1] - p->ve_off[pv];
    float *pes = buf, *ces = buf + ne;
    const uint16_t *ends = pf->crease_ends + 2 * (size_t)(pf->vsib_off[pv] + psib);
    uint32_t s0 = ends[0], s1 = ends[1];
    int k = 0;
    if (s1 > s0) {
        for (uint32_t i = s0 + 1; i <= s1; i++, k++) {
            pes[k] = p->esharp[pE[i]];
            ces[k] = c->esharp[cE[i]];
        }
    } else if (s0 > s1) {
        for (uint32_t i = s0 + 1; i < ne; i++, k++) {
            pes[k] = p->esharp[pE[i]];
            ces[k] = c->esharp[cE[i]];
        }
        for (uint32_t i = 0; i <= s1; i++, k++) {
            pes[k] = p->esharp[pE[i]];
            ces[k] = c->esharp[cE[i]];
        }
    }
    return (double)sd_fractional_weight(o->chaikin, p->vsharp[pv], c->vsharp[cv], k, pes, ces);
}

geom_status geom_subdiv_interpolate_fvar(const geom_subdiv_refiner *r, uint32_t channel,
                                         int level, size_t ncomp, const double *src,
                                         double *dst)
{
    if (sd_check_interp(r, level, ncomp, src, dst) != GEOM_OK)
        return GEOM_ERR_INVALID_ARG;
    const sd_level *p = r->lv[level - 1], *c = r->lv[level];
    if (channel >= p->nfvar)
        return GEOM_ERR_INVALID_ARG;
    const sd_fvar *pf = &p->fvar[channel], *cf = &c->fvar[channel];
    const sd_opts *o = &r->o;
    size_t n = ncomp;
    if (cf->st_off) {
        /* sqrt3: each value a combination of parent values */
        sd_stencils_apply(cf->nvalues, cf->st_off, cf->st_idx, cf->st_w, n, src, dst);
        return GEOM_OK;
    }
    const geom_allocator *a = sd_alloc(r);
    sd_scratch s;
    uint32_t cap = sd_mask_room(p);
    if (sd_scratch_init(a, &s, cap) != GEOM_OK)
        return GEOM_ERR_NOMEM;
    uint32_t *evals = sd_calloc(a, (size_t)cap, sizeof(uint32_t));
    float *fbuf = sd_calloc(a, 2 * (size_t)cap, sizeof(float));
    double *wbuf = sd_calloc(a, 2 * (size_t)cap, sizeof(double));
    if (!evals || !fbuf || !wbuf) {
        sd_scratch_free(a, &s);
        sd_free(a, evals, (size_t)cap, sizeof(uint32_t));
        sd_free(a, fbuf, 2 * (size_t)cap, sizeof(float));
        sd_free(a, wbuf, 2 * (size_t)cap, sizeof(double));
        return GEOM_ERR_NOMEM;
    }
    int quad = sd_quad_split(o);
    int linear = pf->is_linear || o->scheme == GEOM_SUBDIV_BILINEAR;
    uint32_t E0 = quad ? p->nf : 0, V0 = E0 + p->ne;
    if (quad)
        sd_face_points(p, n, pf->fvals, cf->vsib_off, src, dst);
    for (uint32_t e = 0; e < p->ne; e++) {
        uint32_t cv = E0 + e, c0 = cf->vsib_off[cv];
        if (!(cf->slot_tag[c0] & SD_FV_MISMATCH)) {
            double vw[2] = {0.5, 0.5};
            sd_mask m;
            m.f = wbuf;
            m.nf = 0;
            m.fcenters = 0;
            if (!linear)
                sd_edge_mask(o, p, e, c->vtag[cv] & SD_V_RULE, vw, &m);
            uint32_t ev[2];
            edge_face_values(pf, p, e, 0, ev);
            sd_edge_apply(p, e, &m, vw, ev, n, pf->fvals, cf->vsib_off, src, dst,
                          dst + (size_t)c0 * n);
        } else {
            for (uint32_t i = 0; i < cf->vsib_count[cv]; i++) {
                uint32_t ev[2];
                edge_face_values(pf, p, e, cf->parent_src[c0 + i], ev);
                double *d = dst + (size_t)(c0 + i) * n;
                sd_set_w(d, src + (size_t)ev[0] * n, 0.5, n);
                sd_add_w(d, src + (size_t)ev[1] * n, 0.5, n);
            }
        }
    }
    for (uint32_t v = 0; v < p->nv; v++) {
        uint32_t cv = V0 + v, c0 = cf->vsib_off[cv];
        int matches = !(cf->slot_tag[c0] & SD_FV_MISMATCH);
        double *d = dst + (size_t)c0 * n;
        if (linear && matches) {
            sd_set_w(d, src + (size_t)vval(pf, v, 0) * n, 1.0, n);
            continue;
        }
        if (matches) {
            sd_mask m;
            m.e = s.w;
            m.f = s.w + s.cap;
            sd_vertex_mask(o, p, c, v, cv, &m, &s);
            for (size_t k = 0; k < n; k++)
                d[k] = 0.0;
            if (m.nf > 0) {
                for (uint32_t i = p->vf_off[v]; i < p->vf_off[v + 1]; i++)
                    sd_add_w(d, dst + (size_t)cf->vsib_off[p->vf[i]] * n, m.f[i - p->vf_off[v]], n);
            }
            if (m.ne > 0) {
                vertex_edge_values(pf, p, v, evals);
                uint32_t ne = p->ve_off[v + 1] - p->ve_off[v];
                for (uint32_t i = 0; i < ne; i++)
                    sd_add_w(d, src + (size_t)evals[i] * n, m.e[i], n);
            }
            sd_add_w(d, src + (size_t)vval(pf, v, 0) * n, m.v, n);
            continue;
        }
        const uint8_t *ptags = pf->slot_tag + pf->vsib_off[v];
        const uint8_t *ctags = cf->slot_tag + c0;
        for (uint32_t cs = 0; cs < cf->vsib_count[cv]; cs++) {
            uint32_t ps = cf->parent_src[c0 + cs];
            uint32_t pval = vval(pf, v, ps);
            double *dd = dst + (size_t)(c0 + cs) * n;
            if (linear || !(ctags[cs] & SD_FV_CREASE)) {
                sd_set_w(dd, src + (size_t)pval * n, 1.0, n);
                continue;
            }
            uint32_t ends[2];
            crease_end_values(pf, p, v, ps, ends);
            double vwt = 0.75, ewt = 0.125;
            if (ptags[ps] & SD_FV_SEMISHARP) {
                double wc = (ptags[ps] & SD_FV_DEPSHARP)
                                ? fractional_weight(o, p, pf, c, v, !ps, cv, fbuf)
                                : fractional_weight(o, p, pf, c, v, ps, cv, fbuf);
                double wcr = 1.0 - wc;
                vwt = wcr * 0.75 + wc;
                ewt = wcr * 0.125;
            }
            sd_set_w(dd, src + (size_t)ends[0] * n, ewt, n);
            sd_add_w(dd, src + (size_t)ends[1] * n, ewt, n);
            sd_add_w(dd, src + (size_t)pval * n, vwt, n);
        }
    }
    sd_scratch_free(a, &s);
    sd_free(a, evals, (size_t)cap, sizeof(uint32_t));
    sd_free(a, fbuf, 2 * (size_t)cap, sizeof(float));
    sd_free(a, wbuf, 2 * (size_t)cap, sizeof(double));
    return GEOM_OK;
}

geom_status geom_subdiv_limit_fvar(const geom_subdiv_refiner *r, uint32_t channel, size_t ncomp,
                                   const double *src, double *dst)
{
    if (!r || !src || !dst || ncomp == 0)
        return GEOM_ERR_INVALID_ARG;
    const sd_level *l = r->lv[r->nlevels - 1];
    if (channel >= l->nfvar)
        return GEOM_ERR_INVALID_ARG;
    const sd_fvar *f = &l->fvar[channel];
    size_t n = ncomp;
    const sd_opts *o = &r->o;
    int generic = o->scheme == GEOM_SUBDIV_BUTTERFLY || o->scheme == GEOM_SUBDIV_SQRT3;
    if (generic || f->is_linear || o->scheme == GEOM_SUBDIV_BILINEAR) {
        memcpy(dst, src, (size_t)f->nvalues * n * sizeof(double));
        return GEOM_OK;
    }
    const geom_allocator *a = sd_alloc(r);
    sd_scratch s;
    uint32_t cap = l->max_valence + 2;
    if (sd_scratch_init(a, &s, cap) != GEOM_OK)
        return GEOM_ERR_NOMEM;
    uint32_t *evals = sd_calloc(a, cap, sizeof(uint32_t));
    if (!evals) {
        sd_scratch_free(a, &s);
        return GEOM_ERR_NOMEM;
    }
    double *pe = sd_calloc(a, 2 * (size_t)cap, sizeof(double));
    if (!pe) {
        sd_scratch_free(a, &s);
        sd_free(a, evals, cap, sizeof(uint32_t));
        return GEOM_ERR_NOMEM;
    }
    for (uint32_t v = 0; v < l->nv; v++) {
        uint32_t so = f->vsib_off[v], cnt = f->vsib_count[v];
        uint32_t ne = l->ve_off[v + 1] - l->ve_off[v];
        if (ne == 0) {
            for (uint32_t i = 0; i < cnt; i++)
                memcpy(dst + (size_t)f->slot_value[so + i] * n,
                       src + (size_t)f->slot_value[so + i] * n, n * sizeof(double));
            continue;
        }
        if (!(f->slot_tag[so] & SD_FV_MISMATCH)) {
            sd_mask m;
            m.e = pe;
            m.f = pe + cap;
            sd_limit_masks(o, l, v, &m, NULL, NULL, &s);
            uint32_t val = f->slot_value[so];
            double *d = dst + (size_t)val * n;
            for (size_t k = 0; k < n; k++)
                d[k] = 0.0;
            if (m.nf > 0) {
                for (uint32_t i = 0; i < (uint32_t)m.nf; i++) {
                    uint32_t fc = l->vf[l->vf_off[v] + i], vin = l->vf_loc[l->vf_off[v] + i];
                    uint32_t fo = l->fv_off[fc], fs = l->fv_off[fc + 1] - fo;
                    uint32_t opp = vin + 2;
                    if (opp >= fs)
                        opp -= fs;
                    sd_add_w(d, src + (size_t)f->fvals[fo + opp] * n, m.f[i], n);
                }
            }
            if (m.ne > 0) {
                vertex_edge_values(f, l, v, evals);
                for (uint32_t i = 0; i < ne; i++)
                    sd_add_w(d, src + (size_t)evals[i] * n, m.e[i], n);
            }
            sd_add_w(d, src + (size_t)val * n, m.v, n);
        } else {
            for (uint32_t i = 0; i < cnt; i++) {
                uint32_t val = f->slot_value[so + i];
                double *d = dst + (size_t)val * n;
                if (!(f->slot_tag[so + i] & SD_FV_CREASE)) {
                    sd_set_w(d, src + (size_t)val * n, 1.0, n);
                } else {
                    uint32_t ends[2];
                    crease_end_values(f, l, v, i, ends);
                    /* single-precision weights, as OpenSubdiv's LimitFaceVarying */
                    sd_set_w(d, src + (size_t)ends[0] * n, (double)(1.0f / 6.0f), n);
                    sd_add_w(d, src + (size_t)ends[1] * n, (double)(1.0f / 6.0f), n);
                    sd_add_w(d, src + (size_t)val * n, (double)(2.0f / 3.0f), n);
                }
            }
        }
    }
    sd_scratch_free(a, &s);
    sd_free(a, evals, cap, sizeof(uint32_t));
    sd_free(a, pe, 2 * (size_t)cap, sizeof(double));
    return GEOM_OK;
}
