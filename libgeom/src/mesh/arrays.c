/* The connectivity as flat arrays (for bindings and array-based callers). */
#include "mesh/mesh_internal.h"

geom_status geom_mesh_halfedge_arrays(const geom_mesh *m, uint32_t *next, uint32_t *prev,
                                      uint32_t *vertex, uint32_t *face)
{
    if (!m)
        return GEOM_ERR_INVALID_ARG;
    size_t nh = geom_mesh_n_halfedges(m);
    for (size_t h = 0; h < nh; h++) {
        uint32_t hh = (uint32_t)h;
        if (next)
            next[h] = geom_mesh_he_next(m, hh);
        if (prev)
            prev[h] = geom_mesh_he_prev(m, hh);
        if (vertex)
            vertex[h] = geom_mesh_he_vertex(m, hh);
        if (face)
            face[h] = geom_mesh_he_face(m, hh);
    }
    return GEOM_OK;
}

geom_status geom_mesh_vertex_rings(const geom_mesh *m, geom_mesh_circ_kind kind, size_t *offsets,
                                   uint32_t *items, size_t capacity, size_t *count)
{
    if (!m || !offsets || !count || (capacity > 0 && !items))
        return GEOM_ERR_INVALID_ARG;
    if (kind != GEOM_MESH_CIRC_VERTEX_OUTGOING && kind != GEOM_MESH_CIRC_VERTEX_FACES &&
        kind != GEOM_MESH_CIRC_VERTEX_VERTICES)
        return GEOM_ERR_INVALID_ARG;
    size_t nv = geom_mesh_n_vertices(m), k = 0;
    offsets[0] = 0;
    for (size_t v = 0; v < nv; v++) {
        if (!geom_mesh_vertex_is_deleted(m, (uint32_t)v)) {
            geom_mesh_circ c = geom_mesh_circ_begin(m, kind, (uint32_t)v);
            uint32_t x;
            while (geom_mesh_circ_next(&c, &x)) {
                if (k < capacity)
                    items[k] = x;
                k++;
            }
        }
        offsets[v + 1] = k;
    }
    *count = k;
    return k > capacity ? GEOM_ERR_LIMIT : GEOM_OK;
}
