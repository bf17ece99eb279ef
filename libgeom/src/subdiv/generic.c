/*
 * Two schemes beyond OpenSubdiv, on triangle meshes:
 *
 * Modified butterfly (Zorin, Schroeder and Sweldens, "Interpolating
 * subdivision for meshes with arbitrary topology", SIGGRAPH 1996): the
 * 1-to-4 split of Loop; vertices stay; an edge point is the 8-point
 * butterfly (1/2, 1/2, 1/8, 1/8, -1/16 x 4) between two regular (valence 6)
 * interior vertices, the valence-k stencil of an extraordinary interior end
 * (3/4 for the vertex and s_j = (1/4 + cos(2 pi j/k) + cos(4 pi j/k)/2)/k,
 * k = 3: 5/12, -1/12, -1/12; k = 4: 3/8, 0, -1/8, 0) and the average of the
 * two stencils when both ends are extraordinary. Boundary edges use the
 * 4-point rule (-1/16, 9/16, 9/16, -1/16) along the boundary; an interior
 * edge with one boundary end uses the stencil of its interior end; an
 * interior edge between two boundary vertices uses (3/8, 3/8, 1/8, 1/8);
 * non-manifold edges and edges whose neighbourhood is incomplete take the
 * midpoint. Face-varying data is interpolated linearly.
 *
 * sqrt(3) subdivision (Kobbelt, "sqrt(3)-subdivision", SIGGRAPH 2000): a
 * vertex is inserted at the centroid of every triangle, every interior edge
 * is flipped to join the centroids of its two triangles, and interior
 * vertices are relaxed to (1 - a_n) p + a_n mean(neighbours), a_n = (4 - 2
 * cos(2 pi / n)) / 9, so the face count grows by 3 per step. Boundary and
 * non-manifold edges are not flipped (the boundary polygon is kept; a
 * simplification of Kobbelt's boundary rule) and boundary and non-manifold
 * vertices stay. Face-varying data is linear: centroids get the mean of
 * their face's values; the two triangles made by flipping an edge take the
 * values at its ends from the edge's first face, so across a UV seam they
 * mix two charts (the topology does not depend on the data).
 */
#include "subdiv_internal.h"

/* -------------------------------------------------------------- helpers */

typedef struct stb {
    uint32_t *idx;
    double *w;
    size_t n, cap;
    size_t start; /* first entry of the stencil being built */
    const geom_allocator *a;
    int failed;
} stb;

static void stb_free(stb *s)
{
    sd_free(s->a, s->idx, s->cap, sizeof(uint32_t));
    sd_free(s->a, s->w, s->cap, sizeof(double));
    s->idx = NULL;
    s->w = NULL;
}

/* The stencil offsets (c->nv + 1) and vertex parents of level c: 0 when out
 * of memory (butterfly and sqrt(3) alike). */
static int stencils_alloc(const geom_allocator *a, sd_level *c)
{
    c->st_off = sd_calloc(a, (size_t)c->nv + 1, sizeof(uint32_t));
    c->vparent = sd_calloc(a, c->nv, sizeof(uint32_t));
    return c->st_off && c->vparent;
}

/* Start the stencil of child vertex cv, made from element i of the parent
 * (`from`: GEOM_SUBDIV_FROM_FACE, _EDGE or _VERTEX). */
static void stb_begin(stb *s, sd_level *c, uint32_t cv, uint32_t from, uint32_t i)
{
    c->st_off[cv] = (uint32_t)s->n;
    s->start = s->n;
    c->vparent[cv] = (from << 30) | i;
}

static void stb_push(stb *s, uint32_t i, double w)
{
    if (s->failed)
        return;
    for (size_t k = s->n; k-- > s->start;) {
        if (s->idx[k] == i) {
            s->w[k] += w;
            return;
        }
    }
    if (s->n == s->cap) {
        size_t nc = s->cap ? 2 * s->cap : 1024;
        uint32_t *ni = sd_calloc(s->a, nc, sizeof(uint32_t));
        double *nw = sd_calloc(s->a, nc, sizeof(double));
        if (!ni || !nw) {
            sd_free(s->a, ni, nc, sizeof(uint32_t));
            sd_free(s->a, nw, nc, sizeof(double));
            s->failed = 1;
            return;
        }
        if (s->n) {
            memcpy(ni, s->idx, s->n * sizeof(uint32_t));
            memcpy(nw, s->w, s->n * sizeof(double));
        }
        stb_free(s);
        s->idx = ni;
        s->w = nw;
        s->cap = nc;
    }
    s->idx[s->n] = i;
    s->w[s->n] = w;
    s->n++;
}

/* Move the builder's arrays into exactly sized ones. */
static geom_status stb_finish(stb *s, uint32_t **idx, double **w)
{
    if (s->failed)
        return GEOM_ERR_NOMEM;
    *idx = sd_calloc(s->a, s->n, sizeof(uint32_t));
    *w = sd_calloc(s->a, s->n, sizeof(double));
    if (!*idx || !*w)
        return GEOM_ERR_NOMEM;
    memcpy(*idx, s->idx, s->n * sizeof(uint32_t));
    memcpy(*w, s->w, s->n * sizeof(double));
    return GEOM_OK;
}

static inline uint32_t other_end(const sd_level *l, uint32_t e, uint32_t v)
{
    const uint32_t *ev = l->ev + 2 * (size_t)e;
    return ev[0] == v ? ev[1] : ev[0];
}

static inline int interior_manifold(const sd_level *l, uint32_t v)
{
    return !(l->vtag[v] & (SD_V_BOUNDARY | SD_V_NONMANIFOLD)) &&
           l->ve_off[v + 1] - l->ve_off[v] == l->vf_off[v + 1] - l->vf_off[v] &&
           l->ve_off[v + 1] > l->ve_off[v];
}

/* Third vertex of triangle f opposite edge e (local index ein). */
static inline uint32_t tri_opposite(const sd_level *l, uint32_t f, uint32_t ein)
{
    return l->fv[l->fv_off[f] + (ein + 2) % 3];
}

/* The triangle across edge e from face f (manifold edges), or SD_INVALID. */
static uint32_t across(const sd_level *l, uint32_t e, uint32_t f, uint32_t *ein)
{
    if (l->ef_off[e + 1] - l->ef_off[e] != 2)
        return SD_INVALID;
    uint32_t i = l->ef_off[e];
    uint32_t g = l->ef[i] == f ? l->ef[i + 1] : l->ef[i];
    *ein = l->ef[i] == f ? l->ef_loc[i + 1] : l->ef_loc[i];
    return g;
}

/* Edge of face f joining vertices a and b. */
static uint32_t face_edge(const sd_level *l, uint32_t f, uint32_t a, uint32_t b, uint32_t *ein)
{
    uint32_t o = l->fv_off[f];
    for (uint32_t k = 0; k < 3; k++) {
        uint32_t x = l->fv[o + k], y = l->fv[o + (k + 1) % 3];
        if ((x == a && y == b) || (x == b && y == a)) {
            *ein = k;
            return l->fe[o + k];
        }
    }
    return SD_INVALID;
}

/* Zorin's stencil around interior vertex v for its edge e (weight scale s). */
static void k_stencil(const sd_level *l, uint32_t v, uint32_t e, double s, stb *b)
{
    uint32_t eo = l->ve_off[v], k = l->ve_off[v + 1] - eo, i0 = 0;
    while (i0 < k && l->ve[eo + i0] != e)
        i0++;
    stb_push(b, v, 0.75 * s);
    for (uint32_t j = 0; j < k; j++) {
        double w;
        if (k == 3)
            w = j == 0 ? 5.0 / 12.0 : -1.0 / 12.0;
        else if (k == 4)
            w = j == 0 ? 3.0 / 8.0 : (j == 2 ? -1.0 / 8.0 : 0.0);
        else
            w = (0.25 + cos(2.0 * GEOM_PI * j / k) + 0.5 * cos(4.0 * GEOM_PI * j / k)) / k;
        if (w != 0.0)
            stb_push(b, other_end(l, l->ve[eo + (i0 + j) % k], v), w * s);
    }
}

/* The boundary neighbour of boundary vertex v other than u, or SD_INVALID. */
static uint32_t boundary_neighbour(const sd_level *l, uint32_t v, uint32_t u)
{
    uint32_t found = SD_INVALID, count = 0;
    for (uint32_t i = l->ve_off[v]; i < l->ve_off[v + 1]; i++) {
        uint32_t e = l->ve[i];
        if (!(l->etag[e] & SD_E_BOUNDARY))
            continue;
        uint32_t o = other_end(l, e, v);
        if (o != u) {
            found = o;
            count++;
        }
    }
    return count == 1 ? found : SD_INVALID;
}

static void butterfly_edge(const sd_level *p, uint32_t e, stb *b)
{
    uint32_t a = p->ev[2 * (size_t)e], c = p->ev[2 * (size_t)e + 1];
    uint32_t nef = p->ef_off[e + 1] - p->ef_off[e];
    if ((p->etag[e] & SD_E_NONMANIFOLD) || nef == 0 || a == c) {
        stb_push(b, a, 0.5);
        stb_push(b, c, 0.5);
        return;
    }
    if (nef == 1) {
        uint32_t ap = boundary_neighbour(p, a, c), cn = boundary_neighbour(p, c, a);
        if (ap == SD_INVALID || cn == SD_INVALID || ap == cn) {
            stb_push(b, a, 0.5);
            stb_push(b, c, 0.5);
            return;
        }
        stb_push(b, ap, -1.0 / 16.0);
        stb_push(b, a, 9.0 / 16.0);
        stb_push(b, c, 9.0 / 16.0);
        stb_push(b, cn, -1.0 / 16.0);
        return;
    }
    int ia = interior_manifold(p, a), ic = interior_manifold(p, c);
    uint32_t ka = p->ve_off[a + 1] - p->ve_off[a], kc = p->ve_off[c + 1] - p->ve_off[c];
    if (ia && ic && ka == 6 && kc == 6) {
        uint32_t i = p->ef_off[e];
        uint32_t f0 = p->ef[i], f1 = p->ef[i + 1];
        uint32_t d0 = tri_opposite(p, f0, p->ef_loc[i]), d1 = tri_opposite(p, f1, p->ef_loc[i + 1]);
        uint32_t tips[4], nt = 0;
        const uint32_t fs[2] = {f0, f1}, ds[2] = {d0, d1};
        for (int s = 0; s < 2; s++) {
            const uint32_t ends[2] = {a, c};
            for (int t = 0; t < 2; t++) {
                uint32_t ein, gin;
                uint32_t ee = face_edge(p, fs[s], ends[t], ds[s], &ein);
                uint32_t g = ee == SD_INVALID ? SD_INVALID : across(p, ee, fs[s], &gin);
                if (g != SD_INVALID && p->fv_off[g + 1] - p->fv_off[g] == 3)
                    tips[nt++] = tri_opposite(p, g, gin);
            }
        }
        if (nt == 4) {
            stb_push(b, a, 0.5);
            stb_push(b, c, 0.5);
            stb_push(b, d0, 0.125);
            stb_push(b, d1, 0.125);
            for (int t = 0; t < 4; t++)
                stb_push(b, tips[t], -1.0 / 16.0);
            return;
        }
    }
    int ea = ia && ka != 6, ec = ic && kc != 6;
    if (ia && ic) {
        if (ea && ec) {
            k_stencil(p, a, e, 0.5, b);
            k_stencil(p, c, e, 0.5, b);
        } else if (ea) {
            k_stencil(p, a, e, 1.0, b);
        } else {
            k_stencil(p, c, e, 1.0, b);
        }
        return;
    }
    if (ia || ic) {
        k_stencil(p, ia ? a : c, e, 1.0, b);
        return;
    }
    /* both ends on a boundary, interior edge */
    uint32_t i = p->ef_off[e];
    stb_push(b, a, 0.375);
    stb_push(b, c, 0.375);
    stb_push(b, tri_opposite(p, p->ef[i], p->ef_loc[i]), 0.125);
    stb_push(b, tri_opposite(p, p->ef[i + 1], p->ef_loc[i + 1]), 0.125);
}

geom_status sd_butterfly_stencils(const geom_allocator *a, const sd_level *p, sd_level *c)
{
    stb b = {NULL, NULL, 0, 0, 0, a, 0};
    if (!stencils_alloc(a, c))
        return GEOM_ERR_NOMEM;
    for (uint32_t e = 0; e < p->ne; e++) {
        stb_begin(&b, c, e, GEOM_SUBDIV_FROM_EDGE, e);
        butterfly_edge(p, e, &b);
    }
    for (uint32_t v = 0; v < p->nv; v++) {
        stb_begin(&b, c, p->ne + v, GEOM_SUBDIV_FROM_VERTEX, v);
        stb_push(&b, v, 1.0);
    }
    c->st_off[c->nv] = (uint32_t)b.n;
    geom_status st = b.n > INT32_MAX ? GEOM_ERR_LIMIT : stb_finish(&b, &c->st_idx, &c->st_w);
    stb_free(&b);
    return st;
}

/* -------------------------------------------------------------- sqrt(3) */

geom_status sd_refine_sqrt3(const geom_allocator *a, const sd_opts *o, const sd_level *p,
                            sd_level **out)
{
    *out = NULL;
    geom_status st = GEOM_ERR_NOMEM;
    uint64_t nv64 = (uint64_t)p->nf + p->nv;
    if (nv64 > INT32_MAX || 3 * (uint64_t)p->nf * 3 > INT32_MAX)
        return GEOM_ERR_LIMIT;
    uint8_t *flip = sd_calloc(a, p->ne, 1);
    sd_level *c = sd_calloc(a, 1, sizeof *c);
    uint32_t *cfp = NULL;
    stb b = {NULL, NULL, 0, 0, 0, a, 0};
    if (!flip || !c)
        goto fail;
    for (uint32_t e = 0; e < p->ne; e++) {
        uint32_t i = p->ef_off[e];
        if (p->ef_off[e + 1] - i != 2 || (p->etag[e] & SD_E_NONMANIFOLD))
            continue;
        uint32_t f0 = p->ef[i], f1 = p->ef[i + 1];
        if (f0 == f1 || p->fv[p->fv_off[f0] + p->ef_loc[i]] == p->fv[p->fv_off[f1] + p->ef_loc[i + 1]])
            continue;
        flip[e] = 1;
    }
    uint32_t ncf = 0;
    for (uint32_t f = 0; f < p->nf; f++) {
        for (uint32_t j = 0; j < 3; j++) {
            uint32_t e = p->fe[3 * (size_t)f + j];
            if (!flip[e])
                ncf++;
            else if (p->ef[p->ef_off[e]] == f)
                ncf += 2;
        }
    }
    c->nv = (uint32_t)nv64;
    c->nf = ncf;
    c->depth = p->depth + 1;
    c->fv_off = sd_calloc(a, (size_t)ncf + 1, sizeof(uint32_t));
    c->fv = sd_calloc(a, 3 * (size_t)ncf, sizeof(uint32_t));
    cfp = sd_calloc(a, ncf, sizeof(uint32_t));
    if (!c->fv_off || !c->fv || !cfp)
        goto fail;
    uint32_t k = 0;
    for (uint32_t f = 0; f < p->nf; f++) {
        const uint32_t *fv = p->fv + 3 * (size_t)f;
        for (uint32_t j = 0; j < 3; j++) {
            uint32_t e = p->fe[3 * (size_t)f + j], va = fv[j], vb = fv[(j + 1) % 3];
            if (!flip[e]) {
                uint32_t *t = c->fv + 3 * (size_t)k;
                t[0] = p->nf + va, t[1] = p->nf + vb, t[2] = f;
                cfp[k++] = f;
            } else if (p->ef[p->ef_off[e]] == f) {
                uint32_t i = p->ef_off[e];
                uint32_t g = p->ef[i] == f ? p->ef[i + 1] : p->ef[i];
                uint32_t *t = c->fv + 3 * (size_t)k;
                t[0] = p->nf + va, t[1] = g, t[2] = f;
                cfp[k++] = f;
                t = c->fv + 3 * (size_t)k;
                t[0] = p->nf + vb, t[1] = f, t[2] = g;
                cfp[k++] = g;
            }
        }
    }
    for (uint32_t f = 0; f <= ncf; f++)
        c->fv_off[f] = 3 * f;
    st = sd_level_complete(a, c, NULL);
    if (st != GEOM_OK)
        goto fail;
    c->complete = 1;
    {
        sd_opts lo = *o;
        lo.vtx = SD_VTX_EDGE_ONLY;
        int holes = 0;
        sd_level0_tags(c, &lo, &holes);
    }
    c->face_parent = cfp;
    cfp = NULL;
    for (uint32_t f = 0; f < ncf; f++)
        c->fhole[f] = p->fhole[c->face_parent[f]];
    /* Vertex stencils: centroids, then relaxed vertices. */
    st = GEOM_ERR_NOMEM;
    if (!stencils_alloc(a, c))
        goto fail;
    for (uint32_t f = 0; f < p->nf; f++) {
        stb_begin(&b, c, f, GEOM_SUBDIV_FROM_FACE, f);
        for (uint32_t j = 0; j < 3; j++)
            stb_push(&b, p->fv[3 * (size_t)f + j], 1.0 / 3.0);
    }
    for (uint32_t v = 0; v < p->nv; v++) {
        stb_begin(&b, c, p->nf + v, GEOM_SUBDIV_FROM_VERTEX, v);
        uint32_t eo = p->ve_off[v], n = p->ve_off[v + 1] - eo;
        if (!interior_manifold(p, v)) {
            stb_push(&b, v, 1.0);
            continue;
        }
        double al = sd_sqrt3_alpha(n);
        for (uint32_t i = 0; i < n; i++)
            stb_push(&b, other_end(p, p->ve[eo + i], v), al / (double)n);
        stb_push(&b, v, 1.0 - al);
    }
    c->st_off[c->nv] = (uint32_t)b.n;
    st = stb_finish(&b, &c->st_idx, &c->st_w);
    stb_free(&b);
    if (st != GEOM_OK)
        goto fail;
    /* Face-varying channels: centroid values and the parents' values. */
    if (p->nfvar) {
        st = GEOM_ERR_NOMEM;
        c->fvar = sd_calloc(a, p->nfvar, sizeof(sd_fvar));
        if (!c->fvar)
            goto fail;
        c->nfvar = p->nfvar;
        for (uint32_t ch = 0; ch < p->nfvar; ch++) {
            const sd_fvar *pf = &p->fvar[ch];
            sd_fvar *cf = &c->fvar[ch];
            uint32_t *vmap = sd_calloc(a, (size_t)p->fv_off[p->nf] + 1, sizeof(uint32_t));
            cf->fvals = sd_calloc(a, 3 * (size_t)ncf, sizeof(uint32_t));
            if (!vmap || !cf->fvals) {
                sd_free(a, vmap, (size_t)p->fv_off[p->nf] + 1, sizeof(uint32_t));
                goto fail;
            }
            /* child value of each parent face-vertex: one per (vertex, value) */
            uint32_t nval = p->nf;
            for (uint32_t v = 0; v < p->nv; v++) {
                for (uint32_t i = p->vf_off[v]; i < p->vf_off[v + 1]; i++) {
                    uint32_t fvi = p->fv_off[p->vf[i]] + p->vf_loc[i];
                    uint32_t val = pf->fvals[fvi], id = SD_INVALID;
                    for (uint32_t j = p->vf_off[v]; j < i; j++) {
                        uint32_t fvj = p->fv_off[p->vf[j]] + p->vf_loc[j];
                        if (pf->fvals[fvj] == val) {
                            id = vmap[fvj];
                            break;
                        }
                    }
                    vmap[fvi] = id == SD_INVALID ? nval++ : id;
                }
            }
            cf->nvalues = nval;
            cf->st_off = sd_calloc(a, (size_t)nval + 1, sizeof(uint32_t));
            if (!cf->st_off) {
                sd_free(a, vmap, (size_t)p->fv_off[p->nf] + 1, sizeof(uint32_t));
                goto fail;
            }
            stb fb = {NULL, NULL, 0, 0, 0, a, 0};
            uint32_t *first = sd_calloc(a, (size_t)nval + 1, sizeof(uint32_t));
            if (!first) {
                sd_free(a, vmap, (size_t)p->fv_off[p->nf] + 1, sizeof(uint32_t));
                goto fail;
            }
            for (uint32_t i = 0; i < nval; i++)
                first[i] = SD_INVALID;
            for (uint32_t i = 0; i < p->fv_off[p->nf]; i++)
                if (first[vmap[i]] == SD_INVALID)
                    first[vmap[i]] = pf->fvals[i];
            for (uint32_t f = 0; f < p->nf; f++) {
                cf->st_off[f] = (uint32_t)fb.n;
                fb.start = fb.n;
                for (uint32_t j = 0; j < 3; j++)
                    stb_push(&fb, pf->fvals[3 * (size_t)f + j], 1.0 / 3.0);
            }
            for (uint32_t i = p->nf; i < nval; i++) {
                cf->st_off[i] = (uint32_t)fb.n;
                fb.start = fb.n;
                stb_push(&fb, first[i], 1.0);
            }
            cf->st_off[nval] = (uint32_t)fb.n;
            sd_free(a, first, (size_t)nval + 1, sizeof(uint32_t));
            /* child face corners */
            uint32_t t = 0;
            for (uint32_t f = 0; f < p->nf; f++) {
                for (uint32_t j = 0; j < 3; j++) {
                    uint32_t e = p->fe[3 * (size_t)f + j];
                    uint32_t fa = 3 * f + j, fb2 = 3 * f + (j + 1) % 3;
                    if (!flip[e]) {
                        cf->fvals[3 * (size_t)t] = vmap[fa];
                        cf->fvals[3 * (size_t)t + 1] = vmap[fb2];
                        cf->fvals[3 * (size_t)t + 2] = f;
                        t++;
                    } else if (p->ef[p->ef_off[e]] == f) {
                        uint32_t i = p->ef_off[e];
                        uint32_t g = p->ef[i] == f ? p->ef[i + 1] : p->ef[i];
                        cf->fvals[3 * (size_t)t] = vmap[fa];
                        cf->fvals[3 * (size_t)t + 1] = g;
                        cf->fvals[3 * (size_t)t + 2] = f;
                        t++;
                        cf->fvals[3 * (size_t)t] = vmap[fb2];
                        cf->fvals[3 * (size_t)t + 1] = f;
                        cf->fvals[3 * (size_t)t + 2] = g;
                        t++;
                    }
                }
            }
            sd_free(a, vmap, (size_t)p->fv_off[p->nf] + 1, sizeof(uint32_t));
            st = stb_finish(&fb, &cf->st_idx, &cf->st_w);
            stb_free(&fb);
            if (st != GEOM_OK)
                goto fail;
            cf->is_linear = 1;
            st = GEOM_ERR_NOMEM;
        }
    }
    sd_free(a, flip, p->ne, 1);
    *out = c;
    return GEOM_OK;
fail:
    stb_free(&b);
    sd_free(a, flip, p->ne, 1);
    sd_free(a, cfp, c ? c->nf : 0, sizeof(uint32_t));
    sd_level_free(a, c);
    return st == GEOM_OK ? GEOM_ERR_NOMEM : st;
}
