/* Circulators around vertices (counter-clockwise, starting at the boundary
 * outgoing halfedge) and faces (next order). */
#include "mesh/mesh_internal.h"

#define INV GEOM_INVALID_INDEX

geom_mesh_circ geom_mesh_circ_begin(const geom_mesh *m, geom_mesh_circ_kind kind, uint32_t elem)
{
    geom_mesh_circ c;
    c.mesh = m;
    c.kind = kind;
    c.start = c.current = INV;
    c.active = 0;
    if (!m)
        return c;
    switch (kind) {
    case GEOM_MESH_CIRC_VERTEX_OUTGOING:
    case GEOM_MESH_CIRC_VERTEX_FACES:
    case GEOM_MESH_CIRC_VERTEX_VERTICES:
        if ((size_t)elem < m->nv && !m->v_del[elem] && m->v_he[elem] != INV)
            c.start = m->v_he[elem];
        break;
    case GEOM_MESH_CIRC_FACE_HALFEDGES:
    case GEOM_MESH_CIRC_FACE_VERTICES:
        if ((size_t)elem < m->nf && !m->f_del[elem] && m->f_he[elem] != INV)
            c.start = m->f_he[elem];
        break;
    default: return c;
    }
    if (c.start != INV && (size_t)c.start < m->nh) {
        c.current = c.start;
        c.active = 1;
    }
    return c;
}

bool geom_mesh_circ_next(geom_mesh_circ *c, uint32_t *out)
{
    if (!c || !c->active || !c->mesh)
        return false;
    const geom_mesh *m = c->mesh;
    for (;;) {
        uint32_t h = c->current;
        uint32_t val;
        bool emit = true;
        switch (c->kind) {
        case GEOM_MESH_CIRC_VERTEX_OUTGOING:
            val = h;
            c->current = geom__mesh_ccw(m, h);
            break;
        case GEOM_MESH_CIRC_VERTEX_FACES:
            val = m->he_face[h];
            emit = val != INV;
            c->current = geom__mesh_ccw(m, h);
            break;
        case GEOM_MESH_CIRC_VERTEX_VERTICES:
            val = m->he_vertex[h];
            c->current = geom__mesh_ccw(m, h);
            break;
        case GEOM_MESH_CIRC_FACE_HALFEDGES:
            val = h;
            c->current = m->he_next[h];
            break;
        case GEOM_MESH_CIRC_FACE_VERTICES:
            val = m->he_vertex[h];
            c->current = m->he_next[h];
            break;
        default: c->active = 0; return false;
        }
        if (c->current == c->start || c->current == INV || (size_t)c->current >= m->nh)
            c->active = 0;
        if (emit) {
            if (out)
                *out = val;
            return true;
        }
        if (!c->active)
            return false;
    }
}
