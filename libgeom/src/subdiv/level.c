/*
 * The base level of the subdivision hierarchy: full topology from a list of
 * faces (edges numbered in the order faces first use them, vertex-faces and
 * vertex-edges ordered counter-clockwise around manifold vertices, the
 * leading boundary edge first), non-manifold detection, and the sharpness,
 * tags and rules of OpenSubdiv's TopologyRefinerFactory
 * (prepareComponentTagsAndSharpness), so that refinement matches OpenSubdiv
 * 3 index for index.
 */
#include "subdiv_internal.h"

#include <stdlib.h>

/* ------------------------------------------------------------- memory */

void *sd_calloc(const geom_allocator *a, size_t n, size_t size)
{
    size_t bytes;
    if (geom__size_mul(n ? n : 1, size, &bytes) != GEOM_OK)
        return NULL;
    if (!a || !a->alloc_fn)
        return calloc(1, bytes); /* libc: fresh pages come zeroed, no pass over them */
    void *p = geom__alloc(a, bytes);
    if (p)
        memset(p, 0, bytes);
    return p;
}

void *sd_malloc(const geom_allocator *a, size_t n, size_t size)
{
    size_t bytes;
    if (geom__size_mul(n ? n : 1, size, &bytes) != GEOM_OK)
        return NULL;
    return geom__alloc(a, bytes);
}

void sd_free(const geom_allocator *a, void *p, size_t n, size_t size)
{
    if (p)
        geom__free(a, p, (n ? n : 1) * size);
}

void sd_fvar_free(const geom_allocator *a, const sd_level *l, sd_fvar *f)
{
    if (!f || !l)
        return;
    uint32_t nfv = l->fv_off ? l->fv_off[l->nf] : 0;
    sd_free(a, f->fvals, nfv, sizeof(uint32_t));
    sd_free(a, f->etag, l->ne, 1);
    sd_free(a, f->vsib_count, l->nv, sizeof(uint16_t));
    sd_free(a, f->vsib_off, l->nv, sizeof(uint32_t));
    sd_free(a, f->vf_sib, l->vf_off ? l->vf_off[l->nv] : 0, sizeof(uint16_t));
    sd_free(a, f->slot_value, f->nslots, sizeof(uint32_t));
    sd_free(a, f->slot_tag, f->nslots, 1);
    sd_free(a, f->crease_ends, 2 * (size_t)f->nslots, sizeof(uint16_t));
    sd_free(a, f->parent_src, f->nslots, sizeof(uint16_t));
    if (f->st_off) {
        sd_free(a, f->st_idx, f->st_off[f->nvalues], sizeof(uint32_t));
        sd_free(a, f->st_w, f->st_off[f->nvalues], sizeof(double));
    }
    sd_free(a, f->st_off, (size_t)f->nvalues + 1, sizeof(uint32_t));
    memset(f, 0, sizeof *f);
}

void sd_level_free(const geom_allocator *a, sd_level *l)
{
    if (!l)
        return;
    uint32_t nfv = l->fv_off ? l->fv_off[l->nf] : 0;
    uint32_t nef = l->ef_off ? l->ef_off[l->ne] : 0;
    uint32_t nvf = l->vf_off ? l->vf_off[l->nv] : 0;
    uint32_t nve = l->ve_off ? l->ve_off[l->nv] : 0;
    for (uint32_t c = 0; c < l->nfvar; c++)
        sd_fvar_free(a, l, &l->fvar[c]);
    sd_free(a, l->fvar, l->nfvar, sizeof(sd_fvar));
    sd_free(a, l->fv_off, (size_t)l->nf + 1, sizeof(uint32_t));
    sd_free(a, l->fv, nfv, sizeof(uint32_t));
    sd_free(a, l->fe, nfv, sizeof(uint32_t));
    sd_free(a, l->ev, 2 * (size_t)l->ne, sizeof(uint32_t));
    sd_free(a, l->ef_off, (size_t)l->ne + 1, sizeof(uint32_t));
    sd_free(a, l->ef, nef, sizeof(uint32_t));
    sd_free(a, l->ef_loc, nef, sizeof(uint16_t));
    sd_free(a, l->vf_off, (size_t)l->nv + 1, sizeof(uint32_t));
    sd_free(a, l->vf, nvf, sizeof(uint32_t));
    sd_free(a, l->vf_loc, nvf, sizeof(uint16_t));
    sd_free(a, l->ve_off, (size_t)l->nv + 1, sizeof(uint32_t));
    sd_free(a, l->ve, nve, sizeof(uint32_t));
    sd_free(a, l->ve_loc, nve, sizeof(uint16_t));
    sd_free(a, l->esharp, l->ne, sizeof(float));
    sd_free(a, l->vsharp, l->nv, sizeof(float));
    sd_free(a, l->etag, l->ne, 1);
    sd_free(a, l->vtag, l->nv, sizeof(uint16_t));
    sd_free(a, l->fhole, l->nf, 1);
    sd_free(a, l->face_parent, l->nf, sizeof(uint32_t));
    if (l->st_off) {
        sd_free(a, l->st_idx, l->st_off[l->nv], sizeof(uint32_t));
        sd_free(a, l->st_w, l->st_off[l->nv], sizeof(double));
    }
    sd_free(a, l->st_off, (size_t)l->nv + 1, sizeof(uint32_t));
    sd_free(a, l->vparent, l->nv, sizeof(uint32_t));
    geom__free(a, l, sizeof *l);
}

/* ------------------------------------------------------------ creasing */

float sd_decrement(float s)
{
    if (sd_is_smooth(s))
        return 0.0f;
    if (sd_is_inf(s))
        return SD_SHARP_INF;
    if (s > 1.0f)
        return s - 1.0f;
    return 0.0f;
}

int sd_rule_from_count(float vsharp, int sharp_edges)
{
    if (sd_is_sharp(vsharp))
        return SD_RULE_CORNER;
    return sharp_edges > 2 ? SD_RULE_CORNER : (1 << sharp_edges);
}

int sd_rule_from_edges(float vsharp, int n, const float *es)
{
    if (sd_is_sharp(vsharp))
        return SD_RULE_CORNER;
    int c = 0;
    for (int i = 0; i < n; i++)
        c += sd_is_sharp(es[i]);
    return c > 2 ? SD_RULE_CORNER : (1 << c);
}

float sd_subdivide_edge_at_vertex(int chaikin, float es, int n, const float *around)
{
    if (!chaikin || n < 2)
        return sd_decrement(es);
    if (sd_is_smooth(es))
        return 0.0f;
    if (sd_is_inf(es))
        return SD_SHARP_INF;
    float sum = 0.0f;
    int count = 0;
    for (int i = 0; i < n; i++) {
        if (sd_is_semi(around[i])) {
            count++;
            sum += around[i];
        }
    }
    if (count > 1) {
        float avg = (sum - es) / (float)(count - 1);
        es = (0.75f * es) + (0.25f * avg);
    }
    es -= 1.0f;
    return sd_is_sharp(es) ? es : 0.0f;
}

void sd_subdivide_edges_around(int chaikin, int n, const float *p, float *c)
{
    if (!chaikin || n < 2) {
        for (int i = 0; i < n; i++)
            c[i] = sd_decrement(p[i]);
        return;
    }
    float sum = 0.0f;
    int count = 0;
    for (int i = 0; i < n; i++) {
        if (sd_is_semi(p[i])) {
            count++;
            sum += p[i];
        }
    }
    if (count == 0) {
        for (int i = 0; i < n; i++)
            c[i] = p[i];
        return;
    }
    for (int i = 0; i < n; i++) {
        if (sd_is_smooth(p[i]))
            c[i] = 0.0f;
        else if (sd_is_inf(p[i]))
            c[i] = SD_SHARP_INF;
        else if (count == 1)
            c[i] = sd_decrement(p[i]);
        else {
            float other = (sum - p[i]) / (float)(count - 1);
            c[i] = ((0.75f * p[i]) + (0.25f * other)) - 1.0f;
            if (sd_is_smooth(c[i]))
                c[i] = 0.0f;
        }
    }
}

float sd_fractional_weight(int chaikin, float pv, float cv, int n, const float *pe, const float *ce)
{
    int count = 0;
    float sum = 0.0f;
    if (sd_is_sharp(pv) && sd_is_smooth(cv)) {
        count = 1;
        sum = pv;
    }
    if (!chaikin || !ce) {
        for (int i = 0; i < n; i++) {
            if (sd_is_sharp(pe[i]) && pe[i] <= 1.0f) {
                sum += pe[i];
                count++;
            }
        }
    } else {
        for (int i = 0; i < n; i++) {
            if (sd_is_sharp(pe[i]) && sd_is_smooth(ce[i])) {
                sum += pe[i];
                count++;
            }
        }
    }
    if (count == 0)
        return 0.0f;
    float w = sum / (float)count;
    return w > 1.0f ? 1.0f : w;
}

void sd_crease_pair(const float *es, int n, int ends[2])
{
    int a = 0, b = n - 1;
    while (a < n - 1 && sd_is_smooth(es[a]))
        a++;
    while (b > 0 && sd_is_smooth(es[b]))
        b--;
    ends[0] = a;
    ends[1] = b;
}

/* -------------------------------------------------------------- base level */

uint32_t sd_find_edge(const sd_level *l, uint32_t v0, uint32_t v1)
{
    if (v0 >= l->nv || v1 >= l->nv)
        return SD_INVALID;
    /* Search the shorter list: edges between the same two vertices exist
     * only at non-manifold vertices, whose lists keep creation order, so
     * the first match is the same edge in both lists. */
    if (l->ve_off[v1 + 1] - l->ve_off[v1] < l->ve_off[v0 + 1] - l->ve_off[v0]) {
        uint32_t t = v0;
        v0 = v1;
        v1 = t;
    }
    for (uint32_t i = l->ve_off[v0]; i < l->ve_off[v0 + 1]; i++) {
        uint32_t e = l->ve[i];
        const uint32_t *ev = l->ev + 2 * (size_t)e;
        if (v0 != v1) {
            if (ev[0] == v1 || ev[1] == v1)
                return e;
        } else if (ev[0] == ev[1]) {
            return e;
        }
    }
    return SD_INVALID;
}

static uint32_t find_in(const uint32_t *a, uint32_t n, uint32_t x)
{
    for (uint32_t i = 0; i < n; i++)
        if (a[i] == x)
            return i;
    return n;
}

/* Order the faces and edges of v counter-clockwise (OpenSubdiv's
 * Level::orderVertexFacesAndEdges); 0 when v is not locally manifold. */
static int order_vertex(const sd_level *l, uint32_t v, uint32_t *fo, uint32_t *eo)
{
    const uint32_t *vF = l->vf + l->vf_off[v], *vE = l->ve + l->ve_off[v];
    long fc = (long)(l->vf_off[v + 1] - l->vf_off[v]);
    long ec = (long)(l->ve_off[v + 1] - l->ve_off[v]);
    if (fc == 0 || ec < 2 || ec - fc > 1)
        return 0;
    uint32_t fStart = SD_INVALID, eStart = SD_INVALID, fvStart = 0;
    if (ec == fc) {
        fStart = vF[0];
        fvStart = find_in(l->fv + l->fv_off[fStart], l->fv_off[fStart + 1] - l->fv_off[fStart], v);
        if (fvStart >= l->fv_off[fStart + 1] - l->fv_off[fStart])
            return 0;
        eStart = l->fe[l->fv_off[fStart] + fvStart];
    } else {
        for (long i = 0; i < ec; i++) {
            uint32_t e = vE[i];
            if (l->ef_off[e + 1] - l->ef_off[e] == 1) {
                eStart = e;
                fStart = l->ef[l->ef_off[e]];
                fvStart = find_in(l->fv + l->fv_off[fStart],
                                  l->fv_off[fStart + 1] - l->fv_off[fStart], v);
                if (fvStart >= l->fv_off[fStart + 1] - l->fv_off[fStart])
                    return 0;
                if (eStart == l->fe[l->fv_off[fStart] + fvStart])
                    break;
            }
        }
        if (eStart == SD_INVALID)
            return 0;
    }
    long eCount = 1, fCount = 1;
    fo[0] = fStart;
    eo[0] = eStart;
    uint32_t eFirst = eStart;
    while (eCount < ec) {
        uint32_t n = l->fv_off[fStart + 1] - l->fv_off[fStart];
        const uint32_t *fE = l->fe + l->fv_off[fStart];
        uint32_t feNext = fvStart ? fvStart - 1 : n - 1;
        uint32_t eNext = fE[feNext];
        if (eNext == eStart || eNext == eFirst)
            return 0;
        eo[eCount++] = eNext;
        if (fCount < fc) {
            uint32_t nef = l->ef_off[eNext + 1] - l->ef_off[eNext];
            const uint32_t *eF = l->ef + l->ef_off[eNext];
            if (nef == 0)
                return 0;
            if (nef == 1 && eF[0] == fStart)
                return 0;
            fStart = eF[eF[0] == fStart ? 1 : 0];
            uint32_t m = l->fv_off[fStart + 1] - l->fv_off[fStart];
            fvStart = find_in(l->fe + l->fv_off[fStart], m, eNext);
            if (fvStart >= m)
                return 0;
            fo[fCount++] = fStart;
        }
        eStart = eNext;
    }
    return eCount == ec && fCount == fc;
}

/* Vertices with at most this many faces are ordered by order_vertex_local. */
#define SD_LOCAL_ORDER_MAX 64

/* Uses of edge e among the corners at v: out[i] (the edge leaving v in
 * face i of v) and in[i] (the edge arriving); *other receives the last
 * face other than `not` that uses e (n when none). */
static uint32_t local_uses(const uint32_t *out, const uint32_t *in, uint32_t n, uint32_t e,
                           uint32_t not, uint32_t *other)
{
    uint32_t c = 0;
    *other = n;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t u = (out[i] == e) + (in[i] == e);
        c += u;
        if (u && i != not)
            *other = i;
    }
    return c;
}

/* order_vertex for a vertex that occurs once in each of its faces, from
 * each face's two edges at v (out[i] leaving v, in[i] arriving, and v's
 * index in the face at vf_loc: written with the vertex-face lists, in face
 * order) instead of walking edge-faces (dependent loads over the whole
 * level): the same orders and the same verdict (2 ordered, with loc[i] the
 * index of v in face fo[i]; 0 not manifold). -1 when it cannot say (v
 * twice in a face, an edge with more than two uses, many faces):
 * order_vertex decides. v is not tagged non-manifold, so its edges are
 * used at most twice, by different faces, in opposite directions. */
static int order_vertex_local(const sd_level *l, uint32_t v, uint32_t *fo, uint32_t *eo,
                              const uint32_t *out, const uint32_t *in, uint16_t *loc)
{
    const uint16_t *kk = l->vf_loc + l->vf_off[v];
    const uint32_t *vF = l->vf + l->vf_off[v], *vE = l->ve + l->ve_off[v];
    uint32_t fc = l->vf_off[v + 1] - l->vf_off[v], ec = l->ve_off[v + 1] - l->ve_off[v];
    if (fc == 0 || ec < 2 || ec > fc + 1)
        return 0;
    if (fc > SD_LOCAL_ORDER_MAX)
        return -1;
    /* the entries of one face are adjacent (written in face order) */
    for (uint32_t i = 1; i < fc; i++)
        if (vF[i] == vF[i - 1])
            return -1;
    uint32_t cur = 0, eStart = SD_INVALID, other;
    if (ec == fc) {
        eStart = out[0];
    } else {
        /* the first one-face edge (in vE order) leaving v in its face; a
         * last one-face edge that does not leave v ends the walk at once */
        for (uint32_t j = 0; j < ec; j++) {
            uint32_t e = vE[j], c = local_uses(out, in, fc, e, SD_INVALID, &other);
            if (c > 2)
                return -1;
            if (c != 1)
                continue;
            eStart = e;
            cur = other;
            if (out[cur] == e)
                break;
        }
        if (eStart == SD_INVALID || out[cur] != eStart)
            return 0;
    }
    uint32_t eCount = 1, fCount = 1, eFirst = eStart;
    fo[0] = vF[cur];
    loc[0] = kk[cur];
    eo[0] = eStart;
    while (eCount < ec) {
        uint32_t eNext = in[cur];
        if (eNext == eStart || eNext == eFirst)
            return 0;
        eo[eCount++] = eNext;
        if (fCount < fc) {
            uint32_t c = local_uses(out, in, fc, eNext, cur, &other);
            if (c > 2 || (c == 2 && (other == fc || out[other] != eNext)))
                return -1;
            if (c == 1)
                return 0; /* a boundary before the fan is done */
            cur = other;
            loc[fCount] = kk[cur];
            fo[fCount++] = vF[cur];
        }
        eStart = eNext;
    }
    return eCount == ec && fCount == fc ? 2 : 0;
}

/* A vertex pair and the first edge made between them (sd_level_complete). */
typedef struct edge_slot {
    uint32_t lo, hi, e;
} edge_slot;

/* Counting sort: for each key in keys[0..n), in order, append position
 * value val(i) to the list of key; off has nk + 1 entries. */
static void csr_fill(uint32_t nk, uint32_t n, const uint32_t *keys, uint32_t *off, uint32_t *cursor,
                     uint32_t *out, uint32_t div)
{
    memset(off, 0, ((size_t)nk + 1) * sizeof(uint32_t));
    for (uint32_t i = 0; i < n; i++)
        off[keys[i] + 1]++;
    for (uint32_t k = 0; k < nk; k++)
        off[k + 1] += off[k];
    memcpy(cursor, off, (size_t)nk * sizeof(uint32_t));
    for (uint32_t i = 0; i < n; i++)
        out[cursor[keys[i]]++] = i / div;
}

geom_status sd_level_complete(const geom_allocator *a, sd_level *l, geom_diag *diag);

geom_status sd_level0_build(const geom_allocator *a, uint32_t nv, uint32_t nf,
                            const uint32_t *sizes, const uint32_t *idx, sd_level **out,
                            geom_diag *diag)
{
    *out = NULL;
    sd_level *l = sd_calloc(a, 1, sizeof *l);
    if (!l)
        return GEOM_ERR_NOMEM;
    l->nv = nv;
    l->nf = nf;
    l->fv_off = sd_calloc(a, (size_t)nf + 1, sizeof(uint32_t));
    if (!l->fv_off) {
        sd_level_free(a, l);
        return GEOM_ERR_NOMEM;
    }
    uint64_t total = 0;
    for (uint32_t f = 0; f < nf; f++) {
        if (sizes[f] < 3) {
            l->nf = 0;
            sd_level_free(a, l);
            return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                                 "face %u has %u vertices (at least 3 needed)", f, sizes[f]);
        }
        if (sizes[f] > SD_VALENCE_LIMIT) {
            l->nf = 0;
            sd_level_free(a, l);
            return geom__diag_set(diag, GEOM_ERR_LIMIT, NULL, 0, 0,
                                 "face %u has %u vertices (at most %u)", f, sizes[f],
                                 SD_VALENCE_LIMIT);
        }
        l->fv_off[f] = (uint32_t)total;
        total += sizes[f];
        if (total > (uint64_t)INT32_MAX) {
            l->nf = 0;
            sd_level_free(a, l);
            return geom__diag_set(diag, GEOM_ERR_LIMIT, NULL, 0, 0, "too many face vertices");
        }
    }
    l->fv_off[nf] = (uint32_t)total;
    l->fv = sd_calloc(a, total, sizeof(uint32_t));
    if (!l->fv) {
        sd_level_free(a, l);
        return GEOM_ERR_NOMEM;
    }
    for (uint64_t i = 0; i < total; i++) {
        if (idx[i] >= nv) {
            uint32_t f = 0;
            while (f + 1 < nf && l->fv_off[f + 1] <= i)
                f++;
            sd_level_free(a, l);
            return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, NULL, 0, 0,
                                 "face %u uses vertex %u (only %u vertices)", f, idx[i], nv);
        }
        l->fv[i] = idx[i];
    }
    geom_status st = sd_level_complete(a, l, diag);
    if (st != GEOM_OK) {
        sd_level_free(a, l);
        return st;
    }
    l->complete = 1;
    *out = l;
    return GEOM_OK;
}

/* Edges and all incidence relations of a level whose nv, nf, fv_off and fv
 * are set (OpenSubdiv's Level::completeTopologyFromFaceVertices). */
geom_status sd_level_complete(const geom_allocator *a, sd_level *l, geom_diag *diag)
{
    uint32_t nv = l->nv, nf = l->nf, total = l->fv_off[nf];
    geom_status st = GEOM_ERR_NOMEM;
    uint32_t cap = total;
    /* The first edge made between two vertices, by the vertex pair (open
     * addressing, at most half full). OpenSubdiv walks v0's edges in
     * creation order for it; the first one joining v0 and v1 is the one
     * made first, which the table keeps (a later edge between the same
     * two vertices, made for a non-manifold use, never replaces it). */
    unsigned bits = 1;
    while (bits < 63 && ((size_t)1 << bits) < 2 * (size_t)cap)
        bits++;
    const size_t hmask = ((size_t)1 << bits) - 1;
    edge_slot *ht = sd_malloc(a, hmask + 1, sizeof(edge_slot));
    uint32_t *ecount = sd_calloc(a, cap, sizeof(uint32_t));
    uint32_t *elast = sd_calloc(a, cap, sizeof(uint32_t));
    uint8_t *enm = sd_calloc(a, cap, 1);
    uint32_t *ev = sd_calloc(a, 2 * (size_t)cap, sizeof(uint32_t));
    uint32_t *cursor = NULL, *tmpf = NULL, *tmpe = NULL;
    uint32_t *vout = sd_malloc(a, total, sizeof(uint32_t));
    uint32_t *vin = sd_malloc(a, total, sizeof(uint32_t));
    l->fe = sd_calloc(a, total, sizeof(uint32_t));
    if (!ht || !ecount || !elast || !enm || !ev || !l->fe || !vout || !vin)
        goto done;
    for (size_t i = 0; i <= hmask; i++)
        ht[i].e = SD_INVALID;
    uint32_t ne = 0;
    for (uint32_t f = 0; f < nf; f++) {
        uint32_t o = l->fv_off[f], n = l->fv_off[f + 1] - o;
        for (uint32_t i = 0; i < n; i++) {
            uint32_t v0 = l->fv[o + i], v1 = l->fv[o + (i + 1) % n];
            uint32_t e = SD_INVALID;
            edge_slot *slot = NULL;
            if (v0 != v1) {
                uint32_t lo = v0 < v1 ? v0 : v1, hi = v0 < v1 ? v1 : v0;
                size_t h = (size_t)((((uint64_t)lo << 32 | hi) * 0x9E3779B97F4A7C15ull) >>
                                    (64 - bits));
                while (ht[h].e != SD_INVALID && (ht[h].lo != lo || ht[h].hi != hi))
                    h = (h + 1) & hmask;
                slot = &ht[h];
                e = slot->e;
                if (e == SD_INVALID) {
                    slot->lo = lo;
                    slot->hi = hi;
                }
            } else {
                enm[ne] = 1;
            }
            if (e != SD_INVALID) {
                if (elast[e] == f) {
                    enm[e] = 1;
                    enm[ne] = 1;
                    e = SD_INVALID;
                } else if (ecount[e] > 1) {
                    enm[e] = 1;
                } else if (v0 == ev[2 * e]) {
                    enm[e] = 1;
                }
            }
            if (e == SD_INVALID) {
                e = ne++;
                ev[2 * e] = v0;
                ev[2 * e + 1] = v1;
                if (slot && slot->e == SD_INVALID)
                    slot->e = e;
            }
            ecount[e]++;
            elast[e] = f;
            l->fe[o + i] = e;
        }
    }
    l->ne = ne;
    l->ev = sd_calloc(a, 2 * (size_t)ne, sizeof(uint32_t));
    l->ef_off = sd_calloc(a, (size_t)ne + 1, sizeof(uint32_t));
    l->ef = sd_calloc(a, total, sizeof(uint32_t));
    l->ef_loc = sd_calloc(a, total, sizeof(uint16_t));
    l->vf_off = sd_calloc(a, (size_t)nv + 1, sizeof(uint32_t));
    l->vf = sd_calloc(a, total, sizeof(uint32_t));
    l->vf_loc = sd_calloc(a, total, sizeof(uint16_t));
    l->ve_off = sd_calloc(a, (size_t)nv + 1, sizeof(uint32_t));
    l->ve = sd_calloc(a, 2 * (size_t)ne, sizeof(uint32_t));
    l->ve_loc = sd_calloc(a, 2 * (size_t)ne, sizeof(uint16_t));
    l->esharp = sd_calloc(a, ne, sizeof(float));
    l->vsharp = sd_calloc(a, nv, sizeof(float));
    l->etag = sd_calloc(a, ne, 1);
    l->vtag = sd_calloc(a, nv, sizeof(uint16_t));
    l->fhole = sd_calloc(a, nf, 1);
    cursor = sd_calloc(a, (size_t)(nv > ne ? nv : ne) + 1, sizeof(uint32_t));
    if (!l->ev || !l->ef_off || !l->ef || !l->ef_loc || !l->vf_off || !l->vf || !l->vf_loc ||
        !l->ve_off || !l->ve || !l->ve_loc || !l->esharp || !l->vsharp || !l->etag || !l->vtag ||
        !l->fhole || !cursor)
        goto done;
    memcpy(l->ev, ev, 2 * (size_t)ne * sizeof(uint32_t));
    /* Edge-faces, vertex-faces and vertex-edges in creation order. */
    {
        /* edge-faces: faces in face order; keys fe, value = face of position */
        memset(l->ef_off, 0, ((size_t)ne + 1) * sizeof(uint32_t));
        for (uint32_t i = 0; i < total; i++)
            l->ef_off[l->fe[i] + 1]++;
        for (uint32_t e = 0; e < ne; e++)
            l->ef_off[e + 1] += l->ef_off[e];
        memcpy(cursor, l->ef_off, (size_t)ne * sizeof(uint32_t));
        for (uint32_t f = 0; f < nf; f++)
            for (uint32_t i = l->fv_off[f]; i < l->fv_off[f + 1]; i++)
                l->ef[cursor[l->fe[i]]++] = f;
        memset(l->vf_off, 0, ((size_t)nv + 1) * sizeof(uint32_t));
        for (uint32_t i = 0; i < total; i++)
            l->vf_off[l->fv[i] + 1]++;
        for (uint32_t v = 0; v < nv; v++)
            l->vf_off[v + 1] += l->vf_off[v];
        memcpy(cursor, l->vf_off, (size_t)nv * sizeof(uint32_t));
        /* with each entry, the corner's index in the face and its edges
         * leaving (vout) and arriving at (vin) the vertex: what ordering
         * the vertex reads, written here in face order instead of gathered
         * from every face again */
        for (uint32_t f = 0; f < nf; f++) {
            uint32_t o = l->fv_off[f], n = l->fv_off[f + 1] - o;
            for (uint32_t k = 0; k < n; k++) {
                uint32_t slot = cursor[l->fv[o + k]]++;
                l->vf[slot] = f;
                l->vf_loc[slot] = (uint16_t)k;
                vout[slot] = l->fe[o + k];
                vin[slot] = l->fe[o + (k ? k - 1 : n - 1)];
            }
        }
        csr_fill(nv, 2 * ne, l->ev, l->ve_off, cursor, l->ve, 2);
    }
    for (uint32_t v = 0; v < nv; v++) {
        uint32_t nfv = l->vf_off[v + 1] - l->vf_off[v], nev = l->ve_off[v + 1] - l->ve_off[v];
        if (nfv > SD_VALENCE_LIMIT || nev > SD_VALENCE_LIMIT) {
            st = geom__diag_set(diag, GEOM_ERR_LIMIT, NULL, 0, 0,
                               "vertex %u has %u faces and %u edges (at most %u)", v, nfv, nev,
                               SD_VALENCE_LIMIT);
            goto done;
        }
        if (nfv > l->max_valence)
            l->max_valence = nfv;
        if (nev > l->max_valence)
            l->max_valence = nev;
    }
    for (uint32_t e = 0; e < ne; e++) {
        uint32_t c = l->ef_off[e + 1] - l->ef_off[e];
        if (c > l->max_edge_faces)
            l->max_edge_faces = c;
        if (enm[e]) {
            l->etag[e] |= SD_E_NONMANIFOLD;
            l->vtag[l->ev[2 * e]] |= SD_V_NONMANIFOLD;
            l->vtag[l->ev[2 * e + 1]] |= SD_V_NONMANIFOLD;
        }
    }
    for (uint32_t f = 0; f < nf; f++)
        if (l->fv_off[f + 1] - l->fv_off[f] > l->max_face_size)
            l->max_face_size = l->fv_off[f + 1] - l->fv_off[f];
    /* Orient the incident faces and edges of manifold vertices. */
    tmpf = sd_calloc(a, (size_t)l->max_valence + 1, sizeof(uint32_t));
    tmpe = sd_calloc(a, (size_t)l->max_valence + 1, sizeof(uint32_t));
    if (!tmpf || !tmpe)
        goto done;
    /* and the vertex's index in each of its faces (OpenSubdiv's
     * Level::populateLocalIndices), known already where order_vertex_local
     * ordered them */
    for (uint32_t v = 0; v < nv; v++) {
        if (!(l->vtag[v] & SD_V_NONMANIFOLD)) {
            uint16_t lloc[SD_LOCAL_ORDER_MAX];
            int ok = order_vertex_local(l, v, tmpf, tmpe, vout + l->vf_off[v],
                                        vin + l->vf_off[v], lloc);
            if (ok < 0)
                ok = order_vertex(l, v, tmpf, tmpe);
            if (ok) {
                memcpy(l->vf + l->vf_off[v], tmpf,
                       (size_t)(l->vf_off[v + 1] - l->vf_off[v]) * sizeof(uint32_t));
                memcpy(l->ve + l->ve_off[v], tmpe,
                       (size_t)(l->ve_off[v + 1] - l->ve_off[v]) * sizeof(uint32_t));
            } else {
                l->vtag[v] |= SD_V_NONMANIFOLD;
            }
            if (ok == 2) {
                memcpy(l->vf_loc + l->vf_off[v], lloc,
                       (size_t)(l->vf_off[v + 1] - l->vf_off[v]) * sizeof(uint16_t));
                continue;
            }
        }
        uint32_t last = SD_INVALID;
        for (uint32_t i = l->vf_off[v]; i < l->vf_off[v + 1]; i++) {
            uint32_t f = l->vf[i], o = l->fv_off[f], n = l->fv_off[f + 1] - o;
            uint32_t start = (f == last) ? (uint32_t)l->vf_loc[i - 1] + 1 : 0;
            uint32_t k = start;
            while (k < n && l->fv[o + k] != v)
                k++;
            l->vf_loc[i] = (uint16_t)k;
            last = f;
        }
    }
    /* Local indices of the edges (OpenSubdiv's Level::populateLocalIndices). */
    for (uint32_t v = 0; v < nv; v++) {
        for (uint32_t i = l->ve_off[v]; i < l->ve_off[v + 1]; i++) {
            uint32_t e = l->ve[i];
            if (l->ev[2 * e] != l->ev[2 * e + 1])
                l->ve_loc[i] = (uint16_t)(v == l->ev[2 * e + 1]);
            else
                l->ve_loc[i] = (uint16_t)(i > l->ve_off[v] && l->ve[i] == l->ve[i - 1]);
        }
    }
    for (uint32_t e = 0; e < ne; e++) {
        uint32_t last = SD_INVALID;
        for (uint32_t i = l->ef_off[e]; i < l->ef_off[e + 1]; i++) {
            uint32_t f = l->ef[i], o = l->fv_off[f], n = l->fv_off[f + 1] - o;
            uint32_t k = (f == last) ? (uint32_t)l->ef_loc[i - 1] + 1 : 0;
            while (k < n && l->fe[o + k] != e)
                k++;
            l->ef_loc[i] = (uint16_t)k;
            last = f;
        }
    }
    st = GEOM_OK;
done:
    sd_free(a, vout, total, sizeof(uint32_t));
    sd_free(a, vin, total, sizeof(uint32_t));
    sd_free(a, ht, hmask + 1, sizeof(edge_slot));
    sd_free(a, ecount, cap, sizeof(uint32_t));
    sd_free(a, elast, cap, sizeof(uint32_t));
    sd_free(a, enm, cap, 1);
    sd_free(a, ev, 2 * (size_t)cap, sizeof(uint32_t));
    sd_free(a, cursor, (size_t)(nv > l->ne ? nv : l->ne) + 1, sizeof(uint32_t));
    sd_free(a, tmpf, (size_t)l->max_valence + 1, sizeof(uint32_t));
    sd_free(a, tmpe, (size_t)l->max_valence + 1, sizeof(uint32_t));
    return st;
}

/* Sharpness and tags of the base level (OpenSubdiv's
 * TopologyRefinerFactoryBase::prepareComponentTagsAndSharpness). */
void sd_level0_tags(sd_level *l, const sd_opts *o, int *has_holes)
{
    int neighbourhood = o->scheme == GEOM_SUBDIV_CATMULL_CLARK || o->scheme == GEOM_SUBDIV_LOOP;
    int holes_at_boundary = o->vtx == SD_VTX_NONE && neighbourhood;
    int sharpen_corners = o->vtx == SD_VTX_EDGE_AND_CORNER;
    if (holes_at_boundary) {
        for (uint32_t v = 0; v < l->nv; v++) {
            uint32_t ne = l->ve_off[v + 1] - l->ve_off[v], nf = l->vf_off[v + 1] - l->vf_off[v];
            if (ne == nf && !(l->vtag[v] & SD_V_NONMANIFOLD))
                continue;
            int exclude = 0;
            for (uint32_t i = l->ve_off[v]; !exclude && i < l->ve_off[v + 1]; i++) {
                uint32_t e = l->ve[i];
                exclude = (l->ef_off[e + 1] - l->ef_off[e] == 1) && !sd_is_inf(l->esharp[e]);
            }
            if (exclude) {
                for (uint32_t i = l->vf_off[v]; i < l->vf_off[v + 1]; i++)
                    l->fhole[l->vf[i]] = 1;
            }
        }
    }
    for (uint32_t f = 0; f < l->nf; f++)
        if (l->fhole[f])
            *has_holes = 1;
    for (uint32_t e = 0; e < l->ne; e++) {
        uint8_t t = l->etag[e] & SD_E_NONMANIFOLD;
        if (l->ef_off[e + 1] - l->ef_off[e] < 2)
            t |= SD_E_BOUNDARY;
        if (t & (SD_E_BOUNDARY | SD_E_NONMANIFOLD))
            l->esharp[e] = SD_SHARP_INF;
        if (sd_is_inf(l->esharp[e]))
            t |= SD_E_INFSHARP;
        else if (sd_is_sharp(l->esharp[e]))
            t |= SD_E_SEMISHARP;
        l->etag[e] = t;
    }
    for (uint32_t v = 0; v < l->nv; v++) {
        uint16_t t = l->vtag[v] & SD_V_NONMANIFOLD;
        int nbound = 0, ninf = 0, nsemi = 0, nnm = 0;
        uint32_t ne = l->ve_off[v + 1] - l->ve_off[v], nf = l->vf_off[v + 1] - l->vf_off[v];
        for (uint32_t i = l->ve_off[v]; i < l->ve_off[v + 1]; i++) {
            uint8_t et = l->etag[l->ve[i]];
            nbound += (et & SD_E_BOUNDARY) != 0;
            ninf += (et & SD_E_INFSHARP) != 0;
            nsemi += (et & SD_E_SEMISHARP) != 0;
            nnm += (et & SD_E_NONMANIFOLD) != 0;
        }
        int topo_corner = nf == 1 && ne == 2;
        if (topo_corner && sharpen_corners) {
            l->vsharp[v] = SD_SHARP_INF;
        } else if (t & SD_V_NONMANIFOLD) {
            if (!(nnm == 2 && nbound == 0 && nf > ne))
                l->vsharp[v] = SD_SHARP_INF;
        }
        if (sd_is_inf(l->vsharp[v]))
            t |= SD_V_INFSHARP;
        else if (sd_is_semi(l->vsharp[v]))
            t |= SD_V_SEMISHARP;
        if (nsemi > 0)
            t |= SD_V_SEMISHARP_EDGES;
        if (ninf > 0)
            t |= SD_V_INFSHARP_EDGES;
        if (nbound > 0)
            t |= SD_V_BOUNDARY;
        t |= (uint16_t)sd_rule_from_count(l->vsharp[v], ninf + nsemi);
        l->vtag[v] = t;
    }
}

int sd_vertex_rule(const sd_level *l, uint32_t v)
{
    return l->vtag[v] & SD_V_RULE;
}

void sd_level_count(sd_level *l)
{
    uint32_t ns = 0, nh = 0;
    for (uint32_t e = 0; e < l->ne; e++)
        ns += l->esharp[e] > 0.0f;
    for (uint32_t f = 0; f < l->nf; f++)
        nh += l->fhole[f] != 0;
    l->n_sharp_edges = ns;
    l->n_hole_faces = nh;
}
