/*
 * Face-varying topology: which values meet at each vertex ("siblings"),
 * where the value topology departs from the vertex topology (seams and, per
 * the linear-interpolation option, boundaries and corners), how each value
 * is to be interpolated (smooth, crease along its span of faces, or
 * corner), and how all of this is inherited by the refined levels. Follows
 * OpenSubdiv's Vtr::FVarLevel::completeTopologyFromFaceValues and
 * Vtr::FVarRefinement so values are numbered and tagged the same way.
 */
#include "subdiv_internal.h"

typedef struct span {
    int size, start, disjoint, semi;
} span;

static void gather_spans(const sd_level *l, const sd_fvar *f, uint32_t v, span *sp)
{
    const uint32_t *vE = l->ve + l->ve_off[v];
    uint32_t nfv = l->vf_off[v + 1] - l->vf_off[v], nev = l->ve_off[v + 1] - l->ve_off[v];
    const uint16_t *sib = f->vf_sib + l->vf_off[v];
    int single = f->vsib_count[v] == 1;
    int boundary = nev > nfv;
    if (single) {
        for (uint32_t i = 0; i < nev; i++) {
            uint32_t e = vE[i];
            if (f->etag[e] & SD_FE_MISMATCH) {
                if (sp[0].size) {
                    sp[0].disjoint = 1;
                    break;
                }
                sp[0].size = (int)nfv;
                sp[0].start = (int)i;
            } else if (l->etag[e] & SD_E_INFSHARP) {
                sp[0].disjoint = 1;
                break;
            } else if (l->etag[e] & SD_E_SEMISHARP) {
                sp[0].semi++;
            }
        }
        return;
    }
    sp[0].size = 1;
    sp[0].start = 0;
    if (!boundary && sib[nfv - 1] == 0) {
        uint32_t e = vE[0];
        if (f->etag[e] & SD_FE_MISMATCH)
            sp[0].disjoint = 1;
        else if (l->etag[e] & SD_E_INFSHARP)
            sp[0].disjoint = 1;
        else if (l->etag[e] & SD_E_SEMISHARP)
            sp[0].semi++;
    }
    for (uint32_t i = 1; i < nfv; i++) {
        if (sib[i] == sib[i - 1]) {
            uint32_t e = vE[i];
            if (f->etag[e] & SD_FE_MISMATCH)
                sp[sib[i]].disjoint++;
            else if (l->etag[e] & SD_E_INFSHARP)
                sp[sib[i]].disjoint = 1;
            else if (l->etag[e] & SD_E_SEMISHARP)
                sp[sib[i]].semi++;
        } else {
            if (sp[sib[i]].size > 0)
                sp[sib[i]].disjoint++;
            sp[sib[i]].start = (int)i;
        }
        sp[sib[i]].size++;
    }
    if (sib[nfv - 1] == 0 && !boundary)
        sp[0].disjoint--;
}

static void mark_discts(const sd_level *l, sd_fvar *f, uint8_t *mismatch, uint32_t e, uint32_t v)
{
    const uint32_t *ev = l->ev + 2 * (size_t)e;
    mismatch[ev[0]] = 1;
    mismatch[ev[1]] = 1;
    uint8_t t = f->etag[e] & (uint8_t) ~(SD_FE_DISCTS_V0 | SD_FE_DISCTS_V1 | SD_FE_LINEAR);
    if (ev[0] == v)
        t |= SD_FE_DISCTS_V0;
    if (ev[1] == v)
        t |= SD_FE_DISCTS_V1;
    t |= SD_FE_MISMATCH;
    if (f->linear_boundaries)
        t |= SD_FE_LINEAR;
    f->etag[e] = t;
}

geom_status sd_fvar_level0(const geom_allocator *a, const sd_level *l, const sd_opts *o,
                           uint32_t nvalues, const uint32_t *face_values, sd_fvar *f)
{
    memset(f, 0, sizeof *f);
    uint32_t nfvt = l->fv_off[l->nf], nvf = l->vf_off[l->nv];
    geom_status st = GEOM_ERR_NOMEM;
    f->nvalues = nvalues;
    f->fvals = sd_calloc(a, nfvt, sizeof(uint32_t));
    f->etag = sd_calloc(a, l->ne, 1);
    f->vsib_count = sd_calloc(a, l->nv, sizeof(uint16_t));
    f->vsib_off = sd_calloc(a, l->nv, sizeof(uint32_t));
    f->vf_sib = sd_calloc(a, nvf, sizeof(uint16_t));
    uint8_t *mismatch = sd_calloc(a, l->nv, 1);
    uint32_t cap = l->max_valence + 1;
    uint32_t *vals = sd_calloc(a, cap, sizeof(uint32_t));
    uint32_t *uniq = sd_calloc(a, cap, sizeof(uint32_t));
    uint16_t *sibs = sd_calloc(a, cap, sizeof(uint16_t));
    span *sp = sd_calloc(a, cap, sizeof(span));
    if (!f->fvals || !f->etag || !f->vsib_count || !f->vsib_off || !f->vf_sib || !mismatch ||
        !vals || !uniq || !sibs || !sp)
        goto done;
    memcpy(f->fvals, face_values, (size_t)nfvt * sizeof(uint32_t));
    int fo = o->fvar;
    f->is_linear = fo == SD_FVAR_ALL;
    f->linear_boundaries = fo == SD_FVAR_ALL || fo == SD_FVAR_BOUNDARIES;
    f->dependent_sharpness = fo == SD_FVAR_CORNERS_PLUS1 || fo == SD_FVAR_CORNERS_PLUS2;
    int geom_corners_smooth = o->vtx != SD_VTX_EDGE_AND_CORNER;
    int fvar_corners_sharp = fo != SD_FVAR_NONE;
    int smooth_corners_sharp = geom_corners_smooth && fvar_corners_sharp;
    int sharpen_both = fo == SD_FVAR_CORNERS_PLUS2;
    int sharpen_darts = sharpen_both || f->linear_boundaries;

    uint32_t total = 0;
    for (uint32_t v = 0; v < l->nv; v++) {
        uint32_t vfo = l->vf_off[v], nfv = l->vf_off[v + 1] - vfo;
        for (uint32_t i = 0; i < nfv; i++)
            vals[i] = f->fvals[l->fv_off[l->vf[vfo + i]] + l->vf_loc[vfo + i]];
        int manifold = !(l->vtag[v] & SD_V_NONMANIFOLD);
        int boundary = (l->vtag[v] & SD_V_BOUNDARY) != 0;
        const uint32_t *vE = l->ve + l->ve_off[v];
        uint32_t nev = l->ve_off[v + 1] - l->ve_off[v];
        if (manifold) {
            for (uint32_t i = (uint32_t)boundary; i < nfv; i++) {
                uint32_t prev = i ? i - 1 : nfv - 1;
                if (vals[i] != vals[prev])
                    mark_discts(l, f, mismatch, vE[i], v);
            }
        } else if (nfv > 0) {
            for (uint32_t i = 0; i < nev; i++) {
                uint32_t e = vE[i];
                uint32_t efo = l->ef_off[e], nef = l->ef_off[e + 1] - efo;
                if (nef < 2)
                    continue;
                const uint32_t *ev = l->ev + 2 * (size_t)e;
                uint32_t vin_edge = l->ve_loc[l->ve_off[v] + i];
                int mark = 0;
                uint32_t val0 = 0;
                for (uint32_t j = 0; !mark && j < nef; j++) {
                    uint32_t fc = l->ef[efo + j], fvo = l->fv_off[fc];
                    uint32_t n = l->fv_off[fc + 1] - fvo, ein = l->ef_loc[efo + j];
                    uint32_t rev = ev[0] != l->fv[fvo + ein];
                    uint32_t vin = ein + (vin_edge != rev);
                    if (vin == n)
                        vin = 0;
                    if (j == 0)
                        val0 = f->fvals[fvo + vin];
                    else
                        mark = f->fvals[fvo + vin] != val0;
                }
                if (mark)
                    mark_discts(l, f, mismatch, e, v);
            }
        }
        if (boundary && !mismatch[v]) {
            if (f->linear_boundaries && nfv > 0) {
                mismatch[v] = 1;
                if (manifold) {
                    f->etag[vE[0]] |= SD_FE_LINEAR;
                    f->etag[vE[nev - 1]] |= SD_FE_LINEAR;
                } else {
                    for (uint32_t i = 0; i < nev; i++)
                        if (l->etag[vE[i]] & SD_E_BOUNDARY)
                            f->etag[vE[i]] |= SD_FE_LINEAR;
                }
            } else if (nfv == 1) {
                if (smooth_corners_sharp)
                    mismatch[v] = 1;
            }
        }
        uint32_t count = 1;
        uniq[0] = nfv ? vals[0] : 0;
        sibs[0] = 0;
        for (uint32_t i = 1; i < nfv; i++) {
            if (vals[i] == vals[i - 1]) {
                sibs[i] = sibs[i - 1];
            } else {
                sibs[i] = (uint16_t)count;
                if (count == 1) {
                    uniq[count++] = vals[i];
                } else if (count == 2 && uniq[0] != vals[i]) {
                    uniq[count++] = vals[i];
                } else {
                    uint32_t k = 0;
                    while (k < count && uniq[k] != vals[i])
                        k++;
                    if (k == count)
                        uniq[count++] = vals[i];
                    else
                        sibs[i] = (uint16_t)k;
                }
            }
        }
        /* Several values always mismatch the vertex topology (a non-manifold
         * vertex can have them without a discontinuous edge). */
        if (count > 1)
            mismatch[v] = 1;
        f->vsib_count[v] = (uint16_t)count;
        f->vsib_off[v] = total;
        total += count;
        if (count > 1)
            for (uint32_t i = 0; i < nfv; i++)
                f->vf_sib[vfo + i] = sibs[i];
    }
    f->nslots = total;
    f->slot_value = sd_calloc(a, total, sizeof(uint32_t));
    f->slot_tag = sd_calloc(a, total, 1);
    f->crease_ends = sd_calloc(a, 2 * (size_t)total, sizeof(uint16_t));
    f->parent_src = sd_calloc(a, total, sizeof(uint16_t));
    if (!f->slot_value || !f->slot_tag || !f->crease_ends || !f->parent_src)
        goto done;
    for (uint32_t v = 0; v < l->nv; v++) {
        uint32_t vfo = l->vf_off[v], nfv = l->vf_off[v + 1] - vfo;
        uint32_t so = f->vsib_off[v], cnt = f->vsib_count[v];
        f->slot_value[so] = nfv ? f->fvals[l->fv_off[l->vf[vfo]] + l->vf_loc[vfo]] : 0;
        if (!mismatch[v])
            continue;
        if (cnt > 1) {
            uint32_t next = 1;
            for (uint32_t i = 1; i < nfv; i++) {
                if (f->vf_sib[vfo + i] == next) {
                    f->slot_value[so + next] =
                        f->fvals[l->fv_off[l->vf[vfo + i]] + l->vf_loc[vfo + i]];
                    next++;
                }
            }
        }
        uint16_t vt = l->vtag[v];
        int all_sharp = f->linear_boundaries || (vt & SD_V_INFSHARP) ||
                        (vt & SD_V_NONMANIFOLD) || (f->dependent_sharpness && cnt > 2) ||
                        (sharpen_darts && cnt == 1 && !(vt & SD_V_BOUNDARY));
        if (all_sharp) {
            for (uint32_t i = 0; i < cnt; i++)
                f->slot_tag[so + i] = SD_FV_MISMATCH;
            continue;
        }
        memset(sp, 0, (size_t)cnt * sizeof(span));
        gather_spans(l, f, v, sp);
        all_sharp = 0;
        int dep = 0;
        if (f->dependent_sharpness && cnt == 2) {
            all_sharp = sp[0].disjoint || sp[1].disjoint;
            if (sharpen_both)
                all_sharp |= (sp[0].size == 1) || (sp[1].size == 1);
            dep = sp[0].semi != sp[1].semi;
        }
        if (all_sharp) {
            for (uint32_t i = 0; i < cnt; i++)
                f->slot_tag[so + i] = SD_FV_MISMATCH;
            continue;
        }
        for (uint32_t i = 0; i < cnt; i++) {
            const span *s = &sp[i];
            if (s->disjoint || (s->size == 1 && fvar_corners_sharp)) {
                f->slot_tag[so + i] = SD_FV_MISMATCH;
            } else {
                uint8_t t;
                if (s->semi > 0 || (vt & SD_V_SEMISHARP))
                    t = SD_FV_MISMATCH | SD_FV_SEMISHARP;
                else if (dep)
                    t = SD_FV_MISMATCH | SD_FV_SEMISHARP | SD_FV_DEPSHARP;
                else
                    t = SD_FV_MISMATCH | SD_FV_CREASE;
                f->slot_tag[so + i] = t;
                f->crease_ends[2 * (size_t)(so + i)] = (uint16_t)s->start;
                if (i == 0 && s->start != 0)
                    f->crease_ends[2 * (size_t)(so + i) + 1] =
                        (uint16_t)(s->start + s->size - 1 - (int)nfv);
                else
                    f->crease_ends[2 * (size_t)(so + i) + 1] = (uint16_t)(s->start + s->size - 1);
            }
        }
    }
    st = GEOM_OK;
done:
    sd_free(a, mismatch, l->nv, 1);
    sd_free(a, vals, cap, sizeof(uint32_t));
    sd_free(a, uniq, cap, sizeof(uint32_t));
    sd_free(a, sibs, cap, sizeof(uint16_t));
    sd_free(a, sp, cap, sizeof(span));
    return st;
}

static int is_inf_sharp_tag(uint8_t t)
{
    return !(t & SD_FV_SEMISHARP) && !(t & SD_FV_CREASE);
}

geom_status sd_fvar_refine(const geom_allocator *a, const sd_opts *o, const sd_level *p,
                           const sd_fvar *pf, const sd_level *c, sd_fvar *cf)
{
    memset(cf, 0, sizeof *cf);
    cf->is_linear = pf->is_linear;
    cf->linear_boundaries = pf->linear_boundaries;
    cf->dependent_sharpness = pf->dependent_sharpness;
    int quad = sd_quad_split(o);
    uint32_t E0 = quad ? p->nf : 0, V0 = E0 + p->ne, CE0 = p->fv_off[p->nf];
    cf->vsib_count = sd_calloc(a, c->nv, sizeof(uint16_t));
    cf->vsib_off = sd_calloc(a, c->nv, sizeof(uint32_t));
    cf->vf_sib = sd_calloc(a, c->vf_off[c->nv], sizeof(uint16_t));
    cf->etag = sd_calloc(a, c->ne, 1);
    cf->fvals = sd_calloc(a, c->fv_off[c->nf], sizeof(uint32_t));
    if (!cf->vsib_count || !cf->vsib_off || !cf->vf_sib || !cf->etag || !cf->fvals)
        return GEOM_ERR_NOMEM;
    uint64_t total = 0;
    for (uint32_t v = 0; v < E0; v++) {
        cf->vsib_off[v] = (uint32_t)total;
        cf->vsib_count[v] = 1;
        total++;
    }
    for (uint32_t e = 0; e < p->ne; e++) {
        uint32_t cv = E0 + e, nef = p->ef_off[e + 1] - p->ef_off[e];
        cf->vsib_off[cv] = (uint32_t)total;
        uint32_t cnt = (pf->etag[e] & SD_FE_MISMATCH) ? (nef > 1 ? nef : 1) : 1;
        cf->vsib_count[cv] = (uint16_t)cnt;
        total += cnt;
    }
    for (uint32_t v = 0; v < p->nv; v++) {
        uint32_t cv = V0 + v;
        cf->vsib_off[cv] = (uint32_t)total;
        uint32_t cnt = (pf->slot_tag[pf->vsib_off[v]] & SD_FV_MISMATCH) ? pf->vsib_count[v] : 1;
        cf->vsib_count[cv] = (uint16_t)cnt;
        total += cnt;
    }
    if (total > INT32_MAX)
        return GEOM_ERR_LIMIT;
    cf->nslots = (uint32_t)total;
    cf->nvalues = cf->nslots;
    cf->slot_value = sd_calloc(a, total, sizeof(uint32_t));
    cf->slot_tag = sd_calloc(a, total, 1);
    cf->crease_ends = sd_calloc(a, 2 * total, sizeof(uint16_t));
    cf->parent_src = sd_calloc(a, total, sizeof(uint16_t));
    if (!cf->slot_value || !cf->slot_tag || !cf->crease_ends || !cf->parent_src)
        return GEOM_ERR_NOMEM;
    for (uint32_t i = 0; i < cf->nslots; i++)
        cf->slot_value[i] = i;
    /* Siblings of edge and vertex children. */
    for (uint32_t e = 0; e < p->ne; e++) {
        uint32_t cv = E0 + e, efo = p->ef_off[e], nef = p->ef_off[e + 1] - efo;
        if (!(pf->etag[e] & SD_FE_MISMATCH) || nef == 1)
            continue;
        uint32_t so = cf->vsib_off[cv];
        for (uint32_t i = 0; i < nef; i++)
            cf->parent_src[so + i] = (uint16_t)i;
        for (uint32_t i = c->vf_off[cv]; i < c->vf_off[cv + 1]; i++) {
            uint32_t pfc = c->face_parent[c->vf[i]];
            if (nef == 2) {
                if (pfc == p->ef[efo + 1])
                    cf->vf_sib[i] = 1;
            } else {
                for (uint32_t j = 0; j < nef; j++)
                    if (pfc == p->ef[efo + j])
                        cf->vf_sib[i] = (uint16_t)j;
            }
        }
    }
    for (uint32_t v = 0; v < p->nv; v++) {
        uint32_t cv = V0 + v, cnt = cf->vsib_count[cv];
        if (cnt <= 1)
            continue;
        uint32_t so = cf->vsib_off[cv];
        for (uint32_t j = 1; j < cnt; j++)
            cf->parent_src[so + j] = (uint16_t)j;
        uint32_t n = c->vf_off[cv + 1] - c->vf_off[cv];
        memcpy(cf->vf_sib + c->vf_off[cv], pf->vf_sib + p->vf_off[v], (size_t)n * sizeof(uint16_t));
    }
    /* Edge tags. */
    for (uint32_t e = 0; e < p->ne; e++) {
        cf->etag[CE0 + 2 * e] = pf->etag[e];
        cf->etag[CE0 + 2 * e + 1] = pf->etag[e];
    }
    /* Value tags. */
    int smooth_bounds = !pf->linear_boundaries;
    uint8_t split_tag = smooth_bounds ? (SD_FV_MISMATCH | SD_FV_CREASE) : SD_FV_MISMATCH;
    for (uint32_t e = 0; e < p->ne; e++) {
        uint32_t cv = E0 + e, so = cf->vsib_off[cv];
        uint8_t t = (pf->etag[e] & (SD_FE_MISMATCH | SD_FE_LINEAR)) ? split_tag : 0;
        for (uint32_t i = 0; i < cf->vsib_count[cv]; i++)
            cf->slot_tag[so + i] = t;
    }
    for (uint32_t v = 0; v < p->nv; v++) {
        uint32_t cv = V0 + v;
        memcpy(cf->slot_tag + cf->vsib_off[cv], pf->slot_tag + pf->vsib_off[v],
               cf->vsib_count[cv]);
    }
    if (smooth_bounds) {
        uint32_t k = quad ? 2 : 3;
        for (uint32_t e = 0; e < p->ne; e++) {
            uint32_t cv = E0 + e, so = cf->vsib_off[cv];
            if (!(cf->slot_tag[so] & SD_FV_MISMATCH))
                continue;
            for (uint32_t i = 0; i < cf->vsib_count[cv]; i++) {
                if (!is_inf_sharp_tag(cf->slot_tag[so + i])) {
                    cf->crease_ends[2 * (size_t)(so + i)] = (uint16_t)(i * k);
                    cf->crease_ends[2 * (size_t)(so + i) + 1] = (uint16_t)(i * k + k - 1);
                }
            }
        }
        for (uint32_t v = 0; v < p->nv; v++) {
            uint32_t cv = V0 + v, so = cf->vsib_off[cv], po = pf->vsib_off[v];
            if (!(cf->slot_tag[so] & SD_FV_MISMATCH))
                continue;
            for (uint32_t i = 0; i < cf->vsib_count[cv]; i++) {
                if (!is_inf_sharp_tag(cf->slot_tag[so + i])) {
                    cf->crease_ends[2 * (size_t)(so + i)] = pf->crease_ends[2 * (size_t)(po + i)];
                    cf->crease_ends[2 * (size_t)(so + i) + 1] =
                        pf->crease_ends[2 * (size_t)(po + i) + 1];
                }
            }
        }
        /* Reclassify semi-sharp values whose sharpness decayed. */
        for (uint32_t v = 0; v < p->nv; v++) {
            uint32_t cv = V0 + v, so = cf->vsib_off[cv], cnt = cf->vsib_count[cv];
            uint8_t *tags = cf->slot_tag + so;
            if (!(tags[0] & SD_FV_MISMATCH))
                continue;
            uint16_t pt = p->vtag[v], ct = c->vtag[cv];
            if (!(pt & (SD_V_SEMISHARP | SD_V_SEMISHARP_EDGES)))
                continue;
            if (ct & (SD_V_SEMISHARP | SD_V_INFSHARP))
                continue;
            if (!(ct & SD_V_SEMISHARP_EDGES)) {
                for (uint32_t j = 0; j < cnt; j++)
                    if (tags[j] & SD_FV_SEMISHARP)
                        tags[j] = (uint8_t)(SD_FV_MISMATCH | SD_FV_CREASE |
                                            (tags[j] & SD_FV_XORDINARY));
                continue;
            }
            const uint32_t *cE = c->ve + c->ve_off[cv];
            uint32_t nce = c->ve_off[cv + 1] - c->ve_off[cv];
            for (uint32_t j = 0; j < cnt; j++) {
                if (!(tags[j] & SD_FV_SEMISHARP) || (tags[j] & SD_FV_DEPSHARP))
                    continue;
                uint32_t s0 = cf->crease_ends[2 * (size_t)(so + j)];
                uint32_t s1 = cf->crease_ends[2 * (size_t)(so + j) + 1];
                int still = 0;
                if (s1 > s0) {
                    for (uint32_t k = s0 + 1; !still && k <= s1; k++)
                        still = (c->etag[cE[k]] & SD_E_SEMISHARP) != 0;
                } else if (s0 > s1) {
                    for (uint32_t k = s0 + 1; !still && k < nce; k++)
                        still = (c->etag[cE[k]] & SD_E_SEMISHARP) != 0;
                    for (uint32_t k = 0; !still && k <= s1; k++)
                        still = (c->etag[cE[k]] & SD_E_SEMISHARP) != 0;
                }
                if (!still)
                    tags[j] = (uint8_t)(SD_FV_MISMATCH | SD_FV_CREASE | (tags[j] & SD_FV_XORDINARY));
            }
            if (cnt == 2 && pf->dependent_sharpness) {
                if ((tags[0] & SD_FV_DEPSHARP) && !(tags[1] & SD_FV_SEMISHARP))
                    tags[0] &= (uint8_t)~SD_FV_DEPSHARP;
                else if ((tags[1] & SD_FV_DEPSHARP) && !(tags[0] & SD_FV_SEMISHARP))
                    tags[1] &= (uint8_t)~SD_FV_DEPSHARP;
            }
        }
    }
    /* Face values from the vertex-face siblings. */
    for (uint32_t i = 0; i < c->fv_off[c->nf]; i++)
        cf->fvals[i] = cf->vsib_off[c->fv[i]];
    for (uint32_t v = 0; v < c->nv; v++) {
        if (cf->vsib_count[v] <= 1)
            continue;
        for (uint32_t j = c->vf_off[v]; j < c->vf_off[v + 1]; j++)
            if (cf->vf_sib[j])
                cf->fvals[c->fv_off[c->vf[j]] + c->vf_loc[j]] += cf->vf_sib[j];
    }
    return GEOM_OK;
}
