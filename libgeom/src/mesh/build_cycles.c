/*
 * A half-edge mesh made directly from face cycles whose edges the caller has
 * already numbered (subdivision's refined levels know each corner's edge):
 * no sorting of corners by vertex to find the edges again, as the fast
 * build (build_fast.c) would. The result is element for element the mesh
 * geom_mesh_build makes from the same faces when they form an oriented
 * manifold (edges numbered in the order of their first corner, the first
 * use as halfedge 2e, each face's halfedge the last corner's, outgoing
 * halfedges the lowest interior one or the boundary one, identity origin
 * maps); anything else is declined for the caller to build through
 * geom_mesh_build. test_subdiv compares the two element for element.
 */
#include "mesh/build_internal.h"

#define INV GEOM_INVALID_INDEX
#define FIRST_MET 0x80000000u

/* Face cycles: halfedge hs[k] for corner k of each face, 2e for an edge's
 * first corner (in corner order) and 2e + 1 for its second; a one-use
 * edge's 2e + 1 is a boundary halfedge. Returns 0, or 1 to decline. */
static int cycle_halfedges(geom_mesh *m, size_t nf, const uint32_t *fv_off, const uint32_t *fv,
                           const uint32_t *fe, uint32_t *en, const uint8_t *uses, uint32_t *hs)
{
    for (uint32_t f = 0; f < nf; f++) {
        uint32_t s = fv_off[f], n = fv_off[f + 1] - s;
        for (uint32_t k = 0; k < n; k++) {
            uint32_t e = fe[s + k];
            if (en[e] & FIRST_MET) {
                uint32_t h = 2 * (en[e] & ~FIRST_MET) + 1;
                for (uint32_t j = 0; j < k; j++)
                    if (hs[j] == (h ^ 1u))
                        return 1; /* one face uses the edge twice */
                hs[k] = h;
            } else {
                hs[k] = 2 * en[e];
                en[e] |= FIRST_MET;
            }
        }
        for (uint32_t k = 0; k < n; k++) {
            uint32_t h = hs[k], from = fv[s + k], to = fv[s + (k + 1 < n ? k + 1 : 0)];
            /* a second use runs the other way (its first use, in an
             * earlier face, is written) */
            if (from == to || ((h & 1u) && m->he_vertex[h ^ 1u] != from))
                return 1;
            m->he_vertex[h] = to;
            m->he_face[h] = f;
            geom__mesh_link(m, hs[k ? k - 1 : n - 1], h);
            if (uses[fe[s + k]] == 1) {
                m->he_vertex[h ^ 1u] = from;
                m->he_face[h ^ 1u] = INV;
            }
        }
        m->f_he[f] = hs[n - 1];
        m->face_origin[f] = f;
    }
    return 0;
}

/* Streams attached as geom_mesh_build attaches them (corner indices in face
 * order, from each face's first corner). */
static geom_status cycle_attach(geom_mesh *m, const geom_mesh_build_channel *chans, size_t n)
{
    for (size_t i = 0; i < n; ++i) {
        const geom_mesh_build_channel *c = &chans[i];
        const size_t nc = c->ncomp;
        uint32_t id;
        geom_status st = geom_mesh_channel_add(m, c->name, c->domain, nc, &id);
        if (st != GEOM_OK)
            return st;
        if (c->domain == GEOM_MESH_DOMAIN_VERTEX || c->domain == GEOM_MESH_DOMAIN_FACE) {
            size_t cnt = c->domain == GEOM_MESH_DOMAIN_VERTEX ? m->nv : m->nf;
            if (cnt)
                memcpy(m->channels[id].data, c->values, cnt * nc * sizeof(double));
            continue;
        }
        if ((st = geom_mesh_corner_pool_resize(m, id, c->n_values)) != GEOM_OK)
            return st;
        geom__mesh_channel *ch = &m->channels[id];
        if (c->n_values)
            memcpy(ch->data, c->values, c->n_values * nc * sizeof(double));
        /* face f's corner k sits at the halfedge k next-steps from f_he */
        const uint32_t *src = c->indices;
        for (size_t f = 0; f < m->nf; ++f) {
            uint32_t h0 = m->f_he[f], h = h0;
            do {
                ch->corner[h] = *src++;
                h = m->he_next[h];
            } while (h != h0);
        }
    }
    return GEOM_OK;
}

geom_status geom__mesh_build_cycles(geom_mesh *m, const geom__mesh_cycles *c,
                                    const geom_mesh_build_channel *chans, size_t nchans)
{
    const geom_allocator *a = &m->alloc;
    const size_t ne = c->ne, nv = c->nv, C = c->fv_off[c->nf];
    const size_t hsn = c->max_face_size ? c->max_face_size : 1;
    uint32_t *en = geom__alloc(a, (ne ? ne : 1) * sizeof(uint32_t));
    uint8_t *uses = geom__alloc(a, ne ? ne : 1);
    uint32_t *hs = geom__alloc(a, hsn * sizeof(uint32_t));
    uint32_t *cnt = NULL;
    geom_status st = GEOM_ERR_NOMEM;
    int declined = 0;
    if (!en || !uses || !hs)
        goto out;
    /* edges in the order of their first corner; at most two uses */
    memset(en, 0xff, ne * sizeof(uint32_t));
    memset(uses, 0, ne);
    uint32_t E = 0;
    for (size_t k = 0; k < C && !declined; k++) {
        uint32_t e = c->fe[k];
        if (en[e] == INV)
            en[e] = E++;
        declined = ++uses[e] > 2;
    }
    if (declined)
        goto out;
    st = geom__mesh_build_storage(m, nv, 2 * (size_t)E, c->nf);
    if (st != GEOM_OK)
        goto out;
#ifndef NDEBUG
    /* the one-fan check runs in debug builds only: the caller knows its
     * vertices have one fan each */
    cnt = geom__alloc(a, (nv ? nv : 1) * sizeof(uint32_t));
    if (!cnt) {
        st = GEOM_ERR_NOMEM;
        goto out;
    }
#endif
    declined = cycle_halfedges(m, c->nf, c->fv_off, c->fv, c->fe, en, uses, hs);
    /* the edge arrays are done: freed before the vertex pass */
    geom__free(a, en, (ne ? ne : 1) * sizeof(uint32_t));
    geom__free(a, uses, ne ? ne : 1);
    en = NULL;
    uses = NULL;
    if (!declined)
        declined = geom__mesh_link_vertices(m, cnt, NULL);
    if (!declined) {
        for (size_t v = 0; v < m->nv; ++v)
            m->vertex_origin[v] = (uint32_t)v;
        if (nv)
            memcpy(geom__mesh_pos(m), c->xyz, 3 * nv * sizeof(double));
        st = cycle_attach(m, chans, nchans);
    }
out:
    geom__free(a, en, (ne ? ne : 1) * sizeof(uint32_t));
    geom__free(a, uses, ne ? ne : 1);
    geom__free(a, hs, hsn * sizeof(uint32_t));
    geom__free(a, cnt, (nv ? nv : 1) * sizeof(uint32_t));
    if (declined || st != GEOM_OK)
        geom__mesh_clear_all(m);
    return declined && st == GEOM_OK ? GEOM_MESH__CYCLES_DECLINED : st;
}
