/* Mesh to polygon soup. */
#include "mesh/mesh_internal.h"

geom_status geom_mesh_to_soup(const geom_mesh *m, uint32_t *face_sizes, uint32_t *indices,
                              size_t *n_indices)
{
    if (!m)
        return GEOM_ERR_INVALID_ARG;
    size_t total = 0, k = 0;
    for (size_t f = 0; f < m->nf; ++f) {
        if (m->f_del[f])
            continue;
        uint32_t h0 = m->f_he[f], h = h0;
        size_t n = 0;
        do {
            if (indices)
                indices[total + n] = m->he_vertex[h];
            ++n;
            h = m->he_next[h];
        } while (h != h0 && n <= m->nh);
        if (face_sizes)
            face_sizes[k] = (uint32_t)n;
        ++k;
        total += n;
    }
    if (n_indices)
        *n_indices = total;
    return GEOM_OK;
}

uint32_t geom__mesh_input_corner_he(const geom_mesh *m, uint32_t f, uint32_t k)
{
    if (!m || (size_t)f >= m->nf || m->f_del[f])
        return GEOM_INVALID_INDEX;
    size_t n = geom_mesh_face_valence(m, f);
    if ((size_t)k >= n)
        return GEOM_INVALID_INDEX;
    size_t steps = (m->face_flipped && m->face_flipped[f]) ? (n - k) % n : k;
    uint32_t h = m->f_he[f];
    while (steps--)
        h = m->he_next[h];
    return h;
}

size_t geom__mesh_input_corners(const geom_mesh *m, uint32_t f, uint32_t *out)
{
    if (!m || !out || (size_t)f >= m->nf || m->f_del[f])
        return 0;
    size_t n = geom_mesh_face_valence(m, f);
    int flipped = m->face_flipped && m->face_flipped[f];
    uint32_t h = m->f_he[f];
    for (size_t i = 0; i < n; ++i) {
        out[flipped ? (n - i) % n : i] = h;
        h = m->he_next[h];
    }
    return n;
}

const uint32_t *geom_mesh_vertex_origin(const geom_mesh *m) { return m ? m->vertex_origin : NULL; }

const uint32_t *geom_mesh_face_origin(const geom_mesh *m) { return m ? m->face_origin : NULL; }
