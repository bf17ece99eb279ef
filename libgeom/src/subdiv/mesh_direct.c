/*
 * The half-edge mesh of a refined level, made directly from the level's own
 * face-vertex and face-edge relations: no polygon soup and no rebuild by
 * geom_mesh_build, whose fast path (mesh/build_fast.c) would only find again,
 * by sorting corners by vertex, the edges the refinement already numbered.
 *
 * The result is element for element the mesh geom_mesh_build makes from the
 * level's soup (edges numbered in the order of their first corner, the
 * first use as halfedge 2e, face halfedge the last corner's, outgoing
 * halfedges the lowest interior one or the boundary one, identity origin
 * maps), so outputs do not change. It applies to levels that are oriented
 * manifolds whose vertex pairs name one edge each: sd_mesh_direct_applies
 * says which from the base level's tags; the build itself re-checks every
 * edge (at most two uses, in opposite directions; debug builds also every
 * vertex's single fan) and declines (SD_DIRECT_DECLINED, m left empty)
 * otherwise, and the caller then builds from the soup. test_subdiv
 * compares it with geom_mesh_build element for element.
 */
#include "subdiv_internal.h"

#include "mesh/mesh_internal.h"

#define INV GEOM_INVALID_INDEX
#define FIRST_MET 0x80000000u

int sd_mesh_direct_applies(const geom_subdiv_refiner *r, int level)
{
    int s = r->o.scheme;
    if (level < 1 || (s != GEOM_SUBDIV_CATMULL_CLARK && s != GEOM_SUBDIV_BILINEAR &&
                      s != GEOM_SUBDIV_LOOP))
        return 0;
    const sd_level *l0 = r->lv[0];
    for (uint32_t e = 0; e < l0->ne; e++)
        if (l0->etag[e] & SD_E_NONMANIFOLD)
            return 0;
    for (uint32_t v = 0; v < l0->nv; v++) {
        if (l0->vtag[v] & SD_V_NONMANIFOLD)
            return 0;
        /* Loop: two triangles sharing two edges (an interior vertex of
         * valence 2) give their children two edges between the same two
         * vertices, which geom_mesh_build repairs */
        if (s == GEOM_SUBDIV_LOOP && l0->ve_off[v + 1] - l0->ve_off[v] == 2 &&
            l0->vf_off[v + 1] - l0->vf_off[v] == 2)
            return 0;
    }
    return 1;
}

/* Face cycles: halfedge hs[k] for corner k of each face, 2e for an edge's
 * first corner (in corner order) and 2e + 1 for its second; a one-use
 * edge's 2e + 1 is a boundary halfedge. Returns 0, or 1 to decline. */
static int direct_halfedges(const sd_level *l, geom_mesh *m, uint32_t *en, const uint8_t *uses,
                            uint32_t *hs)
{
    for (uint32_t f = 0; f < l->nf; f++) {
        uint32_t s = l->fv_off[f], n = l->fv_off[f + 1] - s;
        for (uint32_t k = 0; k < n; k++) {
            uint32_t e = l->fe[s + k];
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
            uint32_t h = hs[k], from = l->fv[s + k], to = l->fv[s + (k + 1 < n ? k + 1 : 0)];
            /* a second use runs the other way (its first use, in an
             * earlier face, is written) */
            if (from == to || ((h & 1u) && m->he_vertex[h ^ 1u] != from))
                return 1;
            m->he_vertex[h] = to;
            m->he_face[h] = f;
            geom__mesh_link(m, hs[k ? k - 1 : n - 1], h);
            if (uses[l->fe[s + k]] == 1) {
                m->he_vertex[h ^ 1u] = from;
                m->he_face[h ^ 1u] = INV;
            }
        }
        m->f_he[f] = hs[n - 1];
        m->face_origin[f] = f;
    }
    return 0;
}

/* Outgoing halfedges (the lowest interior one; the boundary one where
 * there is one), boundary cycles, and (debug builds) the one-fan check:
 * sd_mesh_direct_applies made sure of it, as level 0 orders every vertex's
 * faces in one fan or tags it non-manifold. cnt: nv entries. Returns 0, or
 * 1 to decline. */
static int direct_vertices(geom_mesh *m, uint32_t *cnt)
{
#ifdef NDEBUG
    cnt = NULL; /* the fan check runs in debug builds only */
#endif
    if (geom__mesh_link_vertices(m, cnt, NULL))
        return 1;
    for (size_t v = 0; v < m->nv; ++v)
        m->vertex_origin[v] = (uint32_t)v;
    return 0;
}

geom_status sd_mesh_direct(const geom_allocator *a, const sd_level *l, const double *positions,
                           geom_mesh *m)
{
    const uint32_t ne = l->ne, C = l->fv_off[l->nf];
    uint32_t *en = sd_malloc(a, ne, sizeof(uint32_t));
    uint8_t *uses = sd_calloc(a, ne, 1);
    uint32_t *hs = sd_malloc(a, l->max_face_size ? l->max_face_size : 1, sizeof(uint32_t));
    uint32_t *cnt = NULL;
    geom_status st = GEOM_ERR_NOMEM;
    int declined = 0;
    if (!en || !uses || !hs)
        goto out;
    /* edges in the order of their first corner; at most two uses */
    memset(en, 0xff, (size_t)ne * sizeof(uint32_t));
    uint32_t E = 0;
    for (uint32_t c = 0; c < C && !declined; c++) {
        uint32_t e = l->fe[c];
        if (en[e] == INV)
            en[e] = E++;
        declined = ++uses[e] > 2;
    }
    if (declined)
        goto out;
    st = geom__mesh_build_storage(m, l->nv, 2 * (size_t)E, l->nf);
    if (st != GEOM_OK)
        goto out;
#ifndef NDEBUG
    cnt = sd_malloc(a, l->nv ? l->nv : 1, sizeof(uint32_t));
    if (!cnt) {
        st = GEOM_ERR_NOMEM;
        goto out;
    }
#endif
    declined = direct_halfedges(l, m, en, uses, hs);
    /* the edge arrays are done: freed before the vertex pass */
    sd_free(a, en, ne, sizeof(uint32_t));
    sd_free(a, uses, ne, 1);
    en = NULL;
    uses = NULL;
    if (!declined)
        declined = direct_vertices(m, cnt);
    if (!declined && l->nv)
        memcpy(geom__mesh_pos(m), positions, 3 * (size_t)l->nv * sizeof(double));
out:
    sd_free(a, en, ne, sizeof(uint32_t));
    sd_free(a, uses, ne, 1);
    sd_free(a, hs, l->max_face_size ? l->max_face_size : 1, sizeof(uint32_t));
    sd_free(a, cnt, l->nv ? l->nv : 1, sizeof(uint32_t));
    if (declined || st != GEOM_OK)
        geom__mesh_clear_all(m);
    return declined && st == GEOM_OK ? SD_DIRECT_DECLINED : st;
}

geom_status sd_mesh_direct_attach(geom_mesh *m, const geom_mesh_build_channel *chans, size_t n)
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
