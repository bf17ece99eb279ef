/* Invariant checks of the half-edge structure, reported as typed defects. */
#include "mesh/mesh_internal.h"

#define INV GEOM_INVALID_INDEX

typedef struct dlist {
    geom_mesh_defect *d;
    size_t max, n;
} dlist;

static void add(dlist *l, geom_mesh_defect_kind k, size_t elem)
{
    if (l->n < l->max) {
        l->d[l->n].kind = k;
        l->d[l->n].element = (uint32_t)elem;
    }
    l->n++;
}

geom_status geom_mesh_validate(const geom_mesh *m, geom_mesh_defect *defects,
                               size_t max_defects, size_t *n_defects)
{
    if (!m || (max_defects && !defects))
        return GEOM_ERR_INVALID_ARG;
    dlist L = {defects, max_defects, 0};
    size_t nv = m->nv, nh = m->nh, nf = m->nf;
    int bad_links = 0;

    /* ---- halfedges: indices and deleted references */
    for (size_t h = 0; h < nh; ++h) {
        if (m->e_del[h >> 1])
            continue;
        uint32_t nx = m->he_next[h], pv = m->he_prev[h], vx = m->he_vertex[h],
                 fc = m->he_face[h];
        if ((size_t)nx >= nh || (size_t)pv >= nh || (size_t)vx >= nv ||
            (fc != INV && (size_t)fc >= nf)) {
            add(&L, GEOM_MESH_DEFECT_BAD_INDEX, h);
            bad_links = 1;
            continue;
        }
        if (m->e_del[nx >> 1] || m->e_del[pv >> 1] || m->v_del[vx] ||
            (fc != INV && m->f_del[fc]))
            add(&L, GEOM_MESH_DEFECT_DELETED_REFERENCE, h);
    }
    for (size_t v = 0; v < nv; ++v) {
        if (m->v_del[v])
            continue;
        uint32_t h = m->v_he[v];
        if (h != INV && (size_t)h >= nh) {
            add(&L, GEOM_MESH_DEFECT_BAD_INDEX, v);
            bad_links = 1;
        } else if (h != INV && m->e_del[h >> 1])
            add(&L, GEOM_MESH_DEFECT_DELETED_REFERENCE, v);
    }
    for (size_t f = 0; f < nf; ++f) {
        if (m->f_del[f])
            continue;
        uint32_t h = m->f_he[f];
        if ((size_t)h >= nh) {
            add(&L, GEOM_MESH_DEFECT_BAD_INDEX, f);
            bad_links = 1;
        } else if (m->e_del[h >> 1])
            add(&L, GEOM_MESH_DEFECT_DELETED_REFERENCE, f);
    }
    if (bad_links)
        goto done;

    /* ---- next/prev, cycle consistency */
    for (size_t h = 0; h < nh; ++h) {
        if (m->e_del[h >> 1])
            continue;
        uint32_t nx = m->he_next[h];
        if (m->he_prev[nx] != h)
            add(&L, GEOM_MESH_DEFECT_NEXT_PREV, h);
        if (m->he_face[nx] != m->he_face[h] || m->he_vertex[nx ^ 1u] != m->he_vertex[h] ||
            m->he_vertex[h] == m->he_vertex[h ^ 1u])
            add(&L, GEOM_MESH_DEFECT_FACE_CYCLE, h);
    }

    /* ---- faces */
    for (size_t f = 0; f < nf; ++f) {
        if (m->f_del[f])
            continue;
        uint32_t h0 = m->f_he[f], h = h0;
        if (m->he_face[h0] != f) {
            add(&L, GEOM_MESH_DEFECT_FACE_CYCLE, f);
            continue;
        }
        size_t n = 0;
        int ok = 1;
        do {
            if (m->he_face[h] != f || n > nh) {
                ok = 0;
                break;
            }
            ++n;
            h = m->he_next[h];
        } while (h != h0);
        if (!ok)
            add(&L, GEOM_MESH_DEFECT_FACE_CYCLE, f);
        else if (n < 3)
            add(&L, GEOM_MESH_DEFECT_SMALL_FACE, f);
    }

    /* ---- vertices: outgoing halfedge, boundary first, single fan */
    {
        size_t nb;
        uint32_t *cnt = NULL;
        if (geom__size_mul(nv ? nv : 1, 2 * sizeof(uint32_t), &nb) != GEOM_OK ||
            !(cnt = geom__alloc(&m->alloc, nb)))
            return GEOM_ERR_NOMEM;
        uint32_t *bcnt = cnt + nv;
        memset(cnt, 0, nb);
        for (size_t h = 0; h < nh; ++h) {
            if (m->e_del[h >> 1])
                continue;
            uint32_t v = m->he_vertex[h ^ 1u];
            cnt[v]++;
            if (m->he_face[h] == INV)
                bcnt[v]++;
        }
        for (size_t v = 0; v < nv; ++v) {
            if (m->v_del[v])
                continue;
            uint32_t h0 = m->v_he[v];
            if (h0 == INV) {
                if (cnt[v])
                    add(&L, GEOM_MESH_DEFECT_VERTEX_HALFEDGE, v);
                continue;
            }
            if (m->he_vertex[h0 ^ 1u] != v) {
                add(&L, GEOM_MESH_DEFECT_VERTEX_HALFEDGE, v);
                continue;
            }
            if (bcnt[v] && m->he_face[h0] != INV)
                add(&L, GEOM_MESH_DEFECT_BOUNDARY_NOT_FIRST, v);
            /* circulate the fan of v_he */
            size_t k = 0;
            uint32_t h = h0;
            int ok = 1;
            do {
                if (m->he_vertex[h ^ 1u] != v || k > cnt[v]) {
                    ok = 0;
                    break;
                }
                ++k;
                h = m->he_prev[h] ^ 1u;
            } while (h != h0);
            if (!ok)
                add(&L, GEOM_MESH_DEFECT_VERTEX_HALFEDGE, v);
            else if (k != cnt[v] || bcnt[v] > 1)
                add(&L, GEOM_MESH_DEFECT_NONMANIFOLD_VERTEX, v);
        }
        geom__free(&m->alloc, cnt, nb);
    }

    /* ---- corner channels */
    for (size_t i = 0; i < m->n_channels; ++i) {
        const geom__mesh_channel *c = &m->channels[i];
        if (c->domain != GEOM_MESH_DOMAIN_CORNER)
            continue;
        for (size_t h = 0; h < nh; ++h) {
            if (m->e_del[h >> 1])
                continue;
            uint32_t x = c->corner[h];
            if (x == INV)
                continue;
            if ((size_t)x >= c->pool || m->he_face[h] == INV)
                add(&L, GEOM_MESH_DEFECT_CHANNEL, h);
        }
    }
done:
    if (n_defects)
        *n_defects = L.n;
    return GEOM_OK;
}
