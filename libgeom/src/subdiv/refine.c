/*
 * Uniform refinement of the topology, sharpness and rules of one level
 * (quad split for Catmull-Clark and bilinear, triangle split for Loop),
 * numbering and ordering every child component as OpenSubdiv's
 * Vtr::QuadRefinement / Vtr::TriRefinement do with face points first, and
 * subdividing sharpness and reclassifying rules as Vtr::Refinement does.
 */
#include "subdiv_internal.h"

static geom_status alloc_child(const geom_allocator *a, sd_level *c, uint32_t face_size)
{
    uint32_t nfv = c->nf * face_size;
    c->fv_off = sd_malloc(a, (size_t)c->nf + 1, sizeof(uint32_t));
    c->fv = sd_malloc(a, nfv, sizeof(uint32_t));
    c->fe = sd_malloc(a, nfv, sizeof(uint32_t));
    c->ev = sd_malloc(a, 2 * (size_t)c->ne, sizeof(uint32_t));
    c->esharp = sd_malloc(a, c->ne, sizeof(float));
    c->vsharp = sd_malloc(a, c->nv, sizeof(float));
    c->etag = sd_malloc(a, c->ne, 1);
    c->vtag = sd_malloc(a, c->nv, sizeof(uint16_t));
    c->fhole = sd_malloc(a, c->nf, 1);
    c->face_parent = sd_malloc(a, c->nf, sizeof(uint32_t));
    if (!c->fv_off || !c->fv || !c->fe || !c->ev || !c->esharp || !c->vsharp || !c->etag ||
        !c->vtag || !c->fhole || !c->face_parent)
        return GEOM_ERR_NOMEM;
    for (uint32_t f = 0; f <= c->nf; f++)
        c->fv_off[f] = f * face_size;
    c->max_face_size = face_size;
    return GEOM_OK;
}

/* The incidence relations of a child level (edge-faces, vertex-faces,
 * vertex-edges with their local indices); SD_REL_LIMIT: only the vertex
 * offsets and vertex-edges, and the vertex-faces of quad schemes (what
 * geom_subdiv_limit reads; Loop's limit masks have no face weights). */
static geom_status alloc_relations(const geom_allocator *a, const sd_opts *o, sd_level *c,
                                   int mode)
{
    uint32_t nfv = c->fv_off[c->nf];
    int full = mode == SD_REL_FULL, vf = full || sd_quad_split(o);
    c->vf_off = sd_malloc(a, (size_t)c->nv + 1, sizeof(uint32_t));
    c->ve_off = sd_malloc(a, (size_t)c->nv + 1, sizeof(uint32_t));
    c->ve = sd_malloc(a, 2 * (size_t)c->ne, sizeof(uint32_t));
    c->ve_loc = sd_malloc(a, 2 * (size_t)c->ne, sizeof(uint16_t));
    if (!c->vf_off || !c->ve_off || !c->ve || !c->ve_loc)
        return GEOM_ERR_NOMEM;
    if (vf) {
        c->vf = sd_malloc(a, nfv, sizeof(uint32_t));
        c->vf_loc = sd_malloc(a, nfv, sizeof(uint16_t));
        if (!c->vf || !c->vf_loc)
            return GEOM_ERR_NOMEM;
    }
    if (!full)
        return GEOM_OK;
    c->ef_off = sd_malloc(a, (size_t)c->ne + 1, sizeof(uint32_t));
    c->ef = sd_malloc(a, nfv, sizeof(uint32_t));
    c->ef_loc = sd_malloc(a, nfv, sizeof(uint16_t));
    if (!c->ef_off || !c->ef || !c->ef_loc)
        return GEOM_ERR_NOMEM;
    return GEOM_OK;
}

/* Free the relations of a level made with SD_REL_LIMIT (before the full
 * ones are made). */
static void free_relations(const geom_allocator *a, sd_level *c)
{
    uint32_t nfv = c->fv_off[c->nf];
    sd_free(a, c->vf, nfv, sizeof(uint32_t));
    sd_free(a, c->vf_loc, nfv, sizeof(uint16_t));
    sd_free(a, c->vf_off, (size_t)c->nv + 1, sizeof(uint32_t));
    sd_free(a, c->ve_off, (size_t)c->nv + 1, sizeof(uint32_t));
    sd_free(a, c->ve, 2 * (size_t)c->ne, sizeof(uint32_t));
    sd_free(a, c->ve_loc, 2 * (size_t)c->ne, sizeof(uint16_t));
    c->vf = c->vf_off = c->ve_off = c->ve = NULL;
    c->vf_loc = c->ve_loc = NULL;
    c->complete = 0;
}

#define PNF(p, f) ((p)->fv_off[(f) + 1] - (p)->fv_off[f])
#define PNEF(p, e) ((p)->ef_off[(e) + 1] - (p)->ef_off[e])

/* Sharpness and tags of the child (Vtr::Refinement::propagateComponentTags,
 * subdivideSharpnessValues, reclassifySemisharpVertices). ce0: first child
 * edge from parent edges; vfe0/vfv0: first child vertex from edges/vertices. */
static void propagate(const sd_opts *o, const sd_level *p, sd_level *c, uint32_t ce0, uint32_t vfe0,
                      uint32_t vfv0, float *buf)
{
    for (uint32_t pe = 0; pe < p->ne; pe++) {
        for (uint32_t j = 0; j < 2; j++) {
            uint32_t ce = ce0 + 2 * pe + j;
            uint8_t t = p->etag[pe];
            float s = 0.0f;
            if (t & SD_E_INFSHARP) {
                s = SD_SHARP_INF;
            } else if (t & SD_E_SEMISHARP) {
                float ps = p->esharp[pe];
                if (!o->chaikin) {
                    s = sd_decrement(ps);
                } else {
                    uint32_t pv = p->ev[2 * pe + j];
                    uint32_t n = p->ve_off[pv + 1] - p->ve_off[pv];
                    for (uint32_t i = 0; i < n; i++)
                        buf[i] = p->esharp[p->ve[p->ve_off[pv] + i]];
                    s = sd_subdivide_edge_at_vertex(1, ps, (int)n, buf);
                }
                if (!sd_is_sharp(s))
                    t &= (uint8_t)~SD_E_SEMISHARP;
            }
            c->etag[ce] = t;
            c->esharp[ce] = s;
        }
    }
    memset(c->etag, 0, ce0);
    memset(c->esharp, 0, (size_t)ce0 * sizeof(float));
    memset(c->vsharp, 0, (size_t)vfv0 * sizeof(float));
    for (uint32_t v = 0; v < vfe0; v++)
        c->vtag[v] = SD_RULE_SMOOTH;
    for (uint32_t pe = 0; pe < p->ne; pe++) {
        uint8_t et = p->etag[pe];
        uint16_t t = 0;
        if (et & SD_E_NONMANIFOLD)
            t |= SD_V_NONMANIFOLD;
        if (et & SD_E_BOUNDARY)
            t |= SD_V_BOUNDARY;
        if (et & SD_E_SEMISHARP)
            t |= SD_V_SEMISHARP_EDGES;
        if (et & SD_E_INFSHARP)
            t |= SD_V_INFSHARP_EDGES;
        t |= (et & (SD_E_SEMISHARP | SD_E_INFSHARP)) ? SD_RULE_CREASE : SD_RULE_SMOOTH;
        c->vtag[vfe0 + pe] = t;
    }
    for (uint32_t pv = 0; pv < p->nv; pv++) {
        uint32_t cv = vfv0 + pv;
        uint16_t t = p->vtag[pv];
        float s = 0.0f;
        if (t & SD_V_INFSHARP) {
            s = SD_SHARP_INF;
        } else if (t & SD_V_SEMISHARP) {
            s = sd_decrement(p->vsharp[pv]);
            if (!sd_is_sharp(s))
                t &= (uint16_t)~SD_V_SEMISHARP;
        }
        c->vtag[cv] = t;
        c->vsharp[cv] = s;
    }
    /* Reclassify vertices whose semi-sharp features decayed. */
    for (uint32_t pe = 0; pe < p->ne; pe++) {
        uint32_t cv = vfe0 + pe;
        uint16_t t = c->vtag[cv];
        if (!(t & SD_V_SEMISHARP_EDGES))
            continue;
        int n = ((c->etag[ce0 + 2 * pe] & SD_E_SEMISHARP) != 0) +
                ((c->etag[ce0 + 2 * pe + 1] & SD_E_SEMISHARP) != 0);
        t &= (uint16_t) ~(SD_V_SEMISHARP_EDGES | SD_V_RULE);
        if (n > 0)
            t |= SD_V_SEMISHARP_EDGES;
        t |= (uint16_t)sd_rule_from_count(0.0f, n);
        c->vtag[cv] = t;
    }
    for (uint32_t pv = 0; pv < p->nv; pv++) {
        uint16_t pt = p->vtag[pv];
        if (!(pt & (SD_V_SEMISHARP | SD_V_SEMISHARP_EDGES)))
            continue;
        uint32_t cv = vfv0 + pv;
        uint16_t t = c->vtag[cv];
        int decayed = (pt & SD_V_SEMISHARP) && !(t & SD_V_SEMISHARP);
        if ((pt & SD_V_SEMISHARP_EDGES) || decayed) {
            int ninf = 0, nsemi = 0;
            for (uint32_t i = p->ve_off[pv]; i < p->ve_off[pv + 1]; i++) {
                uint8_t et = c->etag[ce0 + 2 * p->ve[i] + p->ve_loc[i]];
                ninf += (et & SD_E_INFSHARP) != 0;
                nsemi += (et & SD_E_SEMISHARP) != 0;
            }
            t &= (uint16_t)~SD_V_SEMISHARP_EDGES;
            if (nsemi > 0)
                t |= SD_V_SEMISHARP_EDGES;
            if (!(t & (SD_V_SEMISHARP | SD_V_INFSHARP))) {
                t &= (uint16_t)~SD_V_RULE;
                t |= (uint16_t)sd_rule_from_count(0.0f, ninf + nsemi);
            }
            c->vtag[cv] = t;
        }
    }
}

static void finish_counts(const sd_level *p, sd_level *c)
{
    c->max_valence = 0;
    for (uint32_t v = 0; v < c->nv; v++) {
        uint32_t a = c->vf_off[v + 1] - c->vf_off[v], b = c->ve_off[v + 1] - c->ve_off[v];
        if (a > c->max_valence)
            c->max_valence = a;
        if (b > c->max_valence)
            c->max_valence = b;
    }
    c->max_edge_faces = p->max_edge_faces > 2 ? p->max_edge_faces : 2;
    c->depth = p->depth + 1;
}

/* The two child edges of each parent edge pe (CE0 + 2 pe + j, from the
 * edge's midpoint vertex E0 + pe to the child of its end j, the vertices of
 * level c numbered from V0), then the tags and sharpness (propagate):
 * the same for both splits. */
static void split_edges(const sd_opts *o, const sd_level *p, sd_level *c, uint32_t CE0,
                        uint32_t E0, uint32_t V0, float *buf)
{
    for (uint32_t pe = 0; pe < p->ne; pe++) {
        for (uint32_t j = 0; j < 2; j++) {
            size_t ce = CE0 + 2 * (size_t)pe + j;
            c->ev[2 * ce] = E0 + pe;
            c->ev[2 * ce + 1] = V0 + p->ev[2 * (size_t)pe + j];
        }
    }
    propagate(o, p, c, CE0, E0, V0, buf);
}

static geom_status refine_quad(const geom_allocator *a, const sd_opts *o, const sd_level *p,
                               sd_level *c, float *buf)
{
    uint32_t nfv = p->fv_off[p->nf];
    uint64_t nv = (uint64_t)p->nf + p->ne + p->nv, ne = (uint64_t)nfv + 2 * (uint64_t)p->ne;
    if (nv > INT32_MAX || ne > INT32_MAX || 4 * (uint64_t)nfv > INT32_MAX)
        return GEOM_ERR_LIMIT;
    c->nf = nfv;
    c->ne = (uint32_t)ne;
    c->nv = (uint32_t)nv;
    geom_status st = alloc_child(a, c, 4);
    if (st != GEOM_OK)
        return st;
    const uint32_t E0 = p->nf, V0 = p->nf + p->ne, CE0 = nfv;
    for (uint32_t pf = 0; pf < p->nf; pf++) {
        uint32_t off = p->fv_off[pf], n = PNF(p, pf);
        for (uint32_t j = 0; j < n; j++) {
            uint32_t cf = off + j, jp = j ? j - 1 : n - 1;
            uint32_t cVF = pf, cVEp = E0 + p->fe[off + jp], cVV = V0 + p->fv[off + j],
                     cVEn = E0 + p->fe[off + j];
            uint32_t *cfv = c->fv + 4 * (size_t)cf, *cfe = c->fe + 4 * (size_t)cf;
            uint32_t pPrev = p->fe[off + jp], pNext = p->fe[off + j], corner = p->fv[off + j];
            const uint32_t *evp = p->ev + 2 * (size_t)pPrev, *evn = p->ev + 2 * (size_t)pNext;
            uint32_t inPrev = (evp[0] != evp[1]) ? (evp[0] != corner) : 1;
            uint32_t inNext = (evn[0] != evn[1]) ? (evn[0] != corner) : 0;
            uint32_t cEPrev = CE0 + 2 * pPrev + inPrev, cENext = CE0 + 2 * pNext + inNext;
            uint32_t perpPrev = off + jp, perpNext = off + j;
            if (n == 4) {
                uint32_t jn = (j + 1) & 3, jo = (j + 2) & 3;
                cfv[j] = cVV;
                cfv[jn] = cVEn;
                cfv[jo] = cVF;
                cfv[jp] = cVEp;
                cfe[j] = cENext;
                cfe[jn] = perpNext;
                cfe[jo] = perpPrev;
                cfe[jp] = cEPrev;
            } else {
                cfv[0] = cVV;
                cfv[1] = cVEn;
                cfv[2] = cVF;
                cfv[3] = cVEp;
                cfe[0] = cENext;
                cfe[1] = perpNext;
                cfe[2] = perpPrev;
                cfe[3] = cEPrev;
            }
            c->face_parent[cf] = pf;
            c->fhole[cf] = p->fhole[pf];
            c->ev[2 * (size_t)(off + j)] = pf;
            c->ev[2 * (size_t)(off + j) + 1] = E0 + p->fe[off + j];
        }
    }
    split_edges(o, p, c, CE0, E0, V0, buf);
    return GEOM_OK;
}

/* The edge-face offsets of level c, for both splits: the CE0 interior
 * child edges (inside a parent face) have two faces each, the two halves of
 * a parent edge as many as the parent edge. */
static void edge_face_offsets(const sd_level *p, sd_level *c, uint32_t CE0)
{
    uint32_t k = 0;
    for (uint32_t ce = 0; ce < CE0; ce++) {
        c->ef_off[ce] = k;
        k += 2;
    }
    for (uint32_t pe = 0; pe < p->ne; pe++) {
        c->ef_off[CE0 + 2 * pe] = k;
        k += PNEF(p, pe);
        c->ef_off[CE0 + 2 * pe + 1] = k;
        k += PNEF(p, pe);
    }
    c->ef_off[c->ne] = k;
}

/* Edge-faces. */
static void quad_edge_faces(const sd_level *p, sd_level *c)
{
    const uint32_t CE0 = p->fv_off[p->nf];
    edge_face_offsets(p, c, CE0);
    for (uint32_t pf = 0; pf < p->nf; pf++) {
        uint32_t off = p->fv_off[pf], n = PNF(p, pf);
        for (uint32_t j = 0; j < n; j++) {
            uint32_t jn = (j + 1 < n) ? j + 1 : 0, at = c->ef_off[off + j];
            c->ef[at] = off + j;
            c->ef_loc[at] = (uint16_t)(n == 4 ? jn : 1);
            c->ef[at + 1] = off + jn;
            c->ef_loc[at + 1] = (uint16_t)(n == 4 ? ((jn + 2) & 3) : 2);
        }
    }
    for (uint32_t pe = 0; pe < p->ne; pe++) {
        const uint32_t *pev = p->ev + 2 * (size_t)pe;
        for (uint32_t j = 0; j < 2; j++) {
            uint32_t at = c->ef_off[CE0 + 2 * pe + j];
            for (uint32_t i = p->ef_off[pe]; i < p->ef_off[pe + 1]; i++) {
                uint32_t pf = p->ef[i], ein = p->ef_loc[i], n = PNF(p, pf);
                uint32_t childOfEdge =
                    (pev[0] == pev[1]) ? j : (p->fv[p->fv_off[pf] + ein] != pev[j]);
                uint32_t cin = ein + childOfEdge;
                if (cin == n)
                    cin = 0;
                c->ef[at] = p->fv_off[pf] + cin;
                c->ef_loc[at] = (uint16_t)(n == 4 ? ein : (childOfEdge ? 3 : 0));
                at++;
            }
        }
    }
}

/* The vertex-face and vertex-edge offsets of the children of the parent's
 * vertices (numbered from V0, the last of level c), which keep their
 * parent's counts, after kf faces and ke edges of the other children. */
static void vertex_child_offsets(const sd_level *p, sd_level *c, uint32_t V0, uint32_t kf,
                                 uint32_t ke)
{
    for (uint32_t pv = 0; pv < p->nv; pv++) {
        c->vf_off[V0 + pv] = kf;
        c->ve_off[V0 + pv] = ke;
        kf += p->vf_off[pv + 1] - p->vf_off[pv];
        ke += p->ve_off[pv + 1] - p->ve_off[pv];
    }
    c->vf_off[c->nv] = kf;
    c->ve_off[c->nv] = ke;
}

/* Vertex-faces and vertex-edges (vf, vf_loc and ve_loc when present). */
static void quad_vertex_relations(const sd_level *p, sd_level *c)
{
    const uint32_t E0 = p->nf, V0 = p->nf + p->ne, CE0 = p->fv_off[p->nf];
    uint32_t kf = 0, ke = 0;
    for (uint32_t pf = 0; pf < p->nf; pf++) {
        c->vf_off[pf] = kf;
        c->ve_off[pf] = ke;
        kf += PNF(p, pf);
        ke += PNF(p, pf);
    }
    for (uint32_t pe = 0; pe < p->ne; pe++) {
        c->vf_off[E0 + pe] = kf;
        c->ve_off[E0 + pe] = ke;
        kf += 2 * PNEF(p, pe);
        ke += PNEF(p, pe) + 2;
    }
    vertex_child_offsets(p, c, V0, kf, ke);
    for (uint32_t pf = 0; pf < p->nf; pf++) {
        uint32_t off = p->fv_off[pf], n = PNF(p, pf), af = c->vf_off[pf], ae = c->ve_off[pf];
        for (uint32_t j = 0; j < n; j++) {
            c->vf[af + j] = off + j;
            c->vf_loc[af + j] = (uint16_t)(n == 4 ? ((j + 2) & 3) : 2);
            uint32_t jl = j ? j - 1 : n - 1;
            c->ve[ae + j] = off + jl;
            c->ve_loc[ae + j] = 0;
        }
    }
    for (uint32_t pe = 0; pe < p->ne; pe++) {
        uint32_t cv = E0 + pe, af = c->vf_off[cv], ae = c->ve_off[cv];
        const uint32_t *pev = p->ev + 2 * (size_t)pe;
        for (uint32_t i = p->ef_off[pe]; i < p->ef_off[pe + 1]; i++) {
            uint32_t pf = p->ef[i], ein = p->ef_loc[i], n = PNF(p, pf);
            uint32_t c0 = ein, c1 = ein + 1 == n ? 0 : ein + 1;
            c->vf[af] = p->fv_off[pf] + c1;
            c->vf_loc[af++] = (uint16_t)(n == 4 ? c0 : 3);
            c->vf[af] = p->fv_off[pf] + c0;
            c->vf_loc[af++] = (uint16_t)(n == 4 ? c1 : 1);
        }
        uint32_t *E = c->ve + ae;
        uint16_t *L = c->ve_loc + ae;
        uint32_t cnt = 0;
        E[cnt] = CE0 + 2 * pe;
        L[cnt++] = 0;
        E[cnt] = CE0 + 2 * pe + 1;
        L[cnt++] = 0;
        for (uint32_t i = p->ef_off[pe]; i < p->ef_off[pe + 1]; i++) {
            uint32_t pf = p->ef[i], ein = p->ef_loc[i];
            E[cnt] = p->fv_off[pf] + ein;
            L[cnt++] = 1;
            if (i == p->ef_off[pe] && cnt == 3) {
                if (pev[0] != pev[1] && p->fv[p->fv_off[pf] + ein] == pev[0]) {
                    uint32_t te = E[0];
                    E[0] = E[1];
                    E[1] = te;
                }
                uint32_t te = E[1];
                E[1] = E[2];
                E[2] = te;
                uint16_t tl = L[1];
                L[1] = L[2];
                L[2] = tl;
            }
        }
    }
    for (uint32_t pv = 0; pv < p->nv; pv++) {
        uint32_t cv = V0 + pv, af = c->vf_off[cv], ae = c->ve_off[cv];
        for (uint32_t i = p->vf_off[pv]; i < p->vf_off[pv + 1]; i++) {
            uint32_t pf = p->vf[i], vin = p->vf_loc[i], n = PNF(p, pf);
            c->vf[af] = p->fv_off[pf] + vin;
            c->vf_loc[af++] = (uint16_t)(n == 4 ? vin : 0);
        }
        for (uint32_t i = p->ve_off[pv]; i < p->ve_off[pv + 1]; i++) {
            c->ve[ae] = CE0 + 2 * p->ve[i] + p->ve_loc[i];
            c->ve_loc[ae++] = 1;
        }
    }
}

static geom_status refine_tri(const geom_allocator *a, const sd_opts *o, const sd_level *p,
                              sd_level *c, float *buf)
{
    uint64_t nf = 4 * (uint64_t)p->nf, ne = 3 * (uint64_t)p->nf + 2 * (uint64_t)p->ne,
             nv = (uint64_t)p->ne + p->nv;
    if (nv > INT32_MAX || ne > INT32_MAX || 3 * nf > INT32_MAX)
        return GEOM_ERR_LIMIT;
    c->nf = (uint32_t)nf;
    c->ne = (uint32_t)ne;
    c->nv = (uint32_t)nv;
    geom_status st = alloc_child(a, c, 3);
    if (st != GEOM_OK)
        return st;
    const uint32_t V0 = p->ne, CE0 = 3 * p->nf;
    for (uint32_t pf = 0; pf < p->nf; pf++) {
        const uint32_t *pfv = p->fv + 3 * (size_t)pf, *pfe = p->fe + 3 * (size_t)pf;
        uint32_t ecv[3] = {pfe[0], pfe[1], pfe[2]};
        uint32_t vcv[3] = {V0 + pfv[0], V0 + pfv[1], V0 + pfv[2]};
        uint32_t *cfv = c->fv + 12 * (size_t)pf;
        cfv[0] = vcv[0], cfv[1] = ecv[0], cfv[2] = ecv[2];
        cfv[3] = ecv[0], cfv[4] = vcv[1], cfv[5] = ecv[1];
        cfv[6] = ecv[2], cfv[7] = ecv[1], cfv[8] = vcv[2];
        cfv[9] = ecv[1], cfv[10] = ecv[2], cfv[11] = ecv[0];
        uint32_t pec[3][2];
        for (int i = 0; i < 3; i++) {
            const uint32_t *pev = p->ev + 2 * (size_t)pfe[i];
            uint32_t rev = (pev[0] != pev[1]) && (pfv[i] != pev[0]);
            pec[i][0] = CE0 + 2 * pfe[i] + rev;
            pec[i][1] = CE0 + 2 * pfe[i] + !rev;
        }
        uint32_t fce = 3 * pf;
        uint32_t *cfe = c->fe + 12 * (size_t)pf;
        cfe[0] = pec[0][0], cfe[1] = fce + 0, cfe[2] = pec[2][1];
        cfe[3] = pec[0][1], cfe[4] = pec[1][0], cfe[5] = fce + 1;
        cfe[6] = fce + 2, cfe[7] = pec[1][1], cfe[8] = pec[2][0];
        cfe[9] = fce + 2, cfe[10] = fce + 0, cfe[11] = fce + 1;
        for (uint32_t j = 0; j < 4; j++) {
            c->face_parent[4 * pf + j] = pf;
            c->fhole[4 * pf + j] = p->fhole[pf];
        }
        c->ev[2 * (size_t)(fce + 0)] = ecv[0], c->ev[2 * (size_t)(fce + 0) + 1] = ecv[2];
        c->ev[2 * (size_t)(fce + 1)] = ecv[1], c->ev[2 * (size_t)(fce + 1) + 1] = ecv[0];
        c->ev[2 * (size_t)(fce + 2)] = ecv[2], c->ev[2 * (size_t)(fce + 2) + 1] = ecv[1];
    }
    split_edges(o, p, c, CE0, 0, V0, buf);
    return GEOM_OK;
}

/* Edge-faces. */
static void tri_edge_faces(const sd_level *p, sd_level *c)
{
    const uint32_t CE0 = 3 * p->nf;
    edge_face_offsets(p, c, CE0);
    for (uint32_t pf = 0; pf < p->nf; pf++) {
        for (uint32_t j = 0; j < 3; j++) {
            uint32_t at = c->ef_off[3 * pf + j];
            c->ef[at] = 4 * pf + j;
            c->ef_loc[at] = (uint16_t)((j + 1) % 3);
            c->ef[at + 1] = 4 * pf + 3;
            c->ef_loc[at + 1] = (uint16_t)((j + 1) % 3);
        }
    }
    for (uint32_t pe = 0; pe < p->ne; pe++) {
        const uint32_t *pev = p->ev + 2 * (size_t)pe;
        for (uint32_t j = 0; j < 2; j++) {
            uint32_t at = c->ef_off[CE0 + 2 * pe + j];
            for (uint32_t i = p->ef_off[pe]; i < p->ef_off[pe + 1]; i++) {
                uint32_t pf = p->ef[i], ein = p->ef_loc[i];
                uint32_t childOfEdge = (pev[0] == pev[1]) ? j : (p->fv[3 * pf + ein] != pev[j]);
                uint32_t cin = (ein + childOfEdge) % 3;
                c->ef[at] = 4 * pf + cin;
                c->ef_loc[at] = (uint16_t)ein;
                at++;
            }
        }
    }
}

/* Vertex-faces (vf and vf_loc when present) and vertex-edges. */
static void tri_vertex_relations(const sd_level *p, sd_level *c)
{
    const uint32_t V0 = p->ne, CE0 = 3 * p->nf;
    int vf = c->vf != NULL;
    uint32_t kf = 0, ke = 0;
    for (uint32_t pe = 0; pe < p->ne; pe++) {
        c->vf_off[pe] = kf;
        c->ve_off[pe] = ke;
        kf += 3 * PNEF(p, pe);
        ke += 2 * PNEF(p, pe) + 2;
    }
    vertex_child_offsets(p, c, V0, kf, ke);
    for (uint32_t pe = 0; pe < p->ne; pe++) {
        uint32_t af = c->vf_off[pe], ae = c->ve_off[pe];
        const uint32_t *pev = p->ev + 2 * (size_t)pe;
        for (uint32_t i = p->ef_off[pe]; i < p->ef_off[pe + 1]; i++) {
            uint32_t pf = p->ef[i], ein = p->ef_loc[i];
            if (vf) {
                c->vf[af] = 4 * pf + (ein + 1) % 3;
                c->vf_loc[af++] = (uint16_t)ein;
                c->vf[af] = 4 * pf + 3;
                c->vf_loc[af++] = (uint16_t)((ein + 2) % 3);
                c->vf[af] = 4 * pf + ein;
                c->vf_loc[af++] = (uint16_t)((ein + 1) % 3);
            }
            uint32_t ce0 = SD_INVALID, ce1 = SD_INVALID;
            if (i == p->ef_off[pe]) {
                uint32_t rev = 0;
                if (pev[0] != pev[1])
                    rev = p->fv[3 * pf + ein] != pev[0];
                ce0 = CE0 + 2 * pe + !rev;
                ce1 = CE0 + 2 * pe + rev;
            }
            if (ce0 != SD_INVALID) {
                c->ve[ae] = ce0;
                c->ve_loc[ae++] = 0;
            }
            c->ve[ae] = 3 * pf + (ein + 1) % 3;
            c->ve_loc[ae++] = 1;
            c->ve[ae] = 3 * pf + ein;
            c->ve_loc[ae++] = 0;
            if (ce1 != SD_INVALID) {
                c->ve[ae] = ce1;
                c->ve_loc[ae++] = 0;
            }
        }
    }
    for (uint32_t pv = 0; pv < p->nv; pv++) {
        uint32_t cv = V0 + pv, af = c->vf_off[cv], ae = c->ve_off[cv];
        for (uint32_t i = p->vf_off[pv]; vf && i < p->vf_off[pv + 1]; i++) {
            uint32_t pf = p->vf[i], vin = p->vf_loc[i];
            c->vf[af] = 4 * pf + vin;
            c->vf_loc[af++] = (uint16_t)vin;
        }
        for (uint32_t i = p->ve_off[pv]; i < p->ve_off[pv + 1]; i++) {
            c->ve[ae] = CE0 + 2 * p->ve[i] + p->ve_loc[i];
            c->ve_loc[ae++] = 1;
        }
    }
}

geom_status sd_complete_level(const geom_allocator *a, const sd_opts *o, const sd_level *p,
                              sd_level *c, int mode)
{
    if (c->complete == SD_REL_FULL || c->complete == mode)
        return GEOM_OK;
    if (c->complete)
        free_relations(a, c); /* limit relations, made again with the rest */
    geom_status st = alloc_relations(a, o, c, mode);
    if (st != GEOM_OK)
        return st;
    int quad = sd_quad_split(o);
    if (c->ef)
        (quad ? quad_edge_faces : tri_edge_faces)(p, c);
    (quad ? quad_vertex_relations : tri_vertex_relations)(p, c);
    finish_counts(p, c);
    c->complete = mode;
    return GEOM_OK;
}

geom_status sd_refine_level(const geom_allocator *a, const sd_opts *o, const sd_level *p,
                            int rel, sd_level **out)
{
    *out = NULL;
    if (o->scheme == GEOM_SUBDIV_SQRT3)
        return sd_refine_sqrt3(a, o, p, out);
    sd_level *c = sd_calloc(a, 1, sizeof *c);
    float *buf = sd_calloc(a, (size_t)p->max_valence + 1, sizeof(float));
    geom_status st = GEOM_ERR_NOMEM;
    if (c && buf) {
        c->depth = p->depth + 1;
        st = sd_quad_split(o) ? refine_quad(a, o, p, c, buf) : refine_tri(a, o, p, c, buf);
    }
    sd_free(a, buf, (size_t)p->max_valence + 1, sizeof(float));
    if (!c)
        return GEOM_ERR_NOMEM;
    /* Face-varying channels and butterfly need the child's full topology. */
    if (p->nfvar || o->scheme == GEOM_SUBDIV_BUTTERFLY)
        rel = SD_REL_FULL;
    if (st == GEOM_OK && rel != SD_REL_NONE)
        st = sd_complete_level(a, o, p, c, rel);
    if (st == GEOM_OK && o->scheme == GEOM_SUBDIV_BUTTERFLY)
        st = sd_butterfly_stencils(a, p, c);
    if (st == GEOM_OK && p->nfvar) {
        c->fvar = sd_calloc(a, p->nfvar, sizeof(sd_fvar));
        if (!c->fvar)
            st = GEOM_ERR_NOMEM;
        else
            c->nfvar = p->nfvar;
        for (uint32_t ch = 0; st == GEOM_OK && ch < p->nfvar; ch++)
            st = sd_fvar_refine(a, o, p, &p->fvar[ch], c, &c->fvar[ch]);
    }
    if (st != GEOM_OK) {
        sd_level_free(a, c);
        return st;
    }
    *out = c;
    return GEOM_OK;
}
