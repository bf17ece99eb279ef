/* Topological and simple geometric queries: bounding box, boundary loops,
 * connected components, the topology summary (Euler characteristic, genus)
 * and degenerate faces. */
#include "mesh/mesh_internal.h"

#define INV GEOM_INVALID_INDEX

geom_aabb geom_mesh_bbox(const geom_mesh *m)
{
    geom_aabb b = geom_aabb_empty();
    if (!m)
        return b;
    const double *p = geom__mesh_pos(m);
    for (size_t v = 0; v < m->nv; ++v)
        if (!m->v_del[v])
            b = geom_aabb_extend(b, geom_vec3_make(p[3 * v], p[3 * v + 1], p[3 * v + 2]));
    return b;
}

geom_status geom_mesh_boundary_loops(const geom_mesh *m, size_t *n_loops,
                                     uint32_t *loop_of_halfedge)
{
    if (!m)
        return GEOM_ERR_INVALID_ARG;
    uint32_t *lab = loop_of_halfedge;
    if (!lab) {
        lab = geom__alloc(&m->alloc, (m->nh ? m->nh : 1) * sizeof(uint32_t));
        if (!lab)
            return GEOM_ERR_NOMEM;
    }
    for (size_t h = 0; h < m->nh; ++h)
        lab[h] = INV;
    size_t n = 0;
    for (size_t h0 = 0; h0 < m->nh; ++h0) {
        if (m->e_del[h0 >> 1] || m->he_face[h0] != INV || lab[h0] != INV)
            continue;
        uint32_t h = (uint32_t)h0;
        size_t guard = 0;
        do {
            lab[h] = (uint32_t)n;
            h = m->he_next[h];
        } while (h != h0 && lab[h] == INV && ++guard <= m->nh);
        n++;
    }
    if (lab != loop_of_halfedge)
        geom__free(&m->alloc, lab, (m->nh ? m->nh : 1) * sizeof(uint32_t));
    if (n_loops)
        *n_loops = n;
    return GEOM_OK;
}

/* Component labels of live vertices (lab, nv entries, INV for deleted ones),
 * numbered by their lowest vertex. Returns the count. lab doubles as the
 * union-find array. */
static size_t vertex_components(const geom_mesh *m, uint32_t *lab)
{
    size_t nv = m->nv;
    geom__uf_init(lab, nv);
    for (size_t e = 0; e < m->nh / 2; ++e)
        if (!m->e_del[e])
            geom__uf_union(lab, m->he_vertex[2 * e], m->he_vertex[2 * e + 1]);
    /* full compression (roots are the smallest members), then relabel in
     * one ascending pass: a root is met before the rest of its set */
    for (size_t v = 0; v < nv; ++v)
        lab[v] = geom__uf_find(lab, (uint32_t)v);
    size_t n = 0;
    for (size_t v = 0; v < nv; ++v) {
        uint32_t r = lab[v];
        if (m->v_del[v])
            lab[v] = INV;
        else if (r == v)
            lab[v] = (uint32_t)n++;
        else
            lab[v] = lab[r];
    }
    return n;
}

geom_status geom_mesh_components(const geom_mesh *m, size_t *n, uint32_t *vertex_component,
                                 uint32_t *face_component)
{
    if (!m)
        return GEOM_ERR_INVALID_ARG;
    if (m->nv >= (size_t)UINT32_MAX / 2)
        return GEOM_ERR_LIMIT;
    uint32_t *lab = vertex_component;
    if (!lab) {
        lab = geom__alloc(&m->alloc, (m->nv ? m->nv : 1) * sizeof(uint32_t));
        if (!lab)
            return GEOM_ERR_NOMEM;
    }
    size_t nc = vertex_components(m, lab);
    if (face_component)
        for (size_t f = 0; f < m->nf; ++f)
            face_component[f] = m->f_del[f] ? INV : lab[m->he_vertex[m->f_he[f]]];
    if (lab != vertex_component)
        geom__free(&m->alloc, lab, (m->nv ? m->nv : 1) * sizeof(uint32_t));
    if (n)
        *n = nc;
    return GEOM_OK;
}

bool geom_mesh_face_is_degenerate(const geom_mesh *m, uint32_t f)
{
    if (!m || (size_t)f >= m->nf || m->f_del[f])
        return false;
    const double *p = geom__mesh_pos(m);
    uint32_t h0 = m->f_he[f], h;
    const double *o = p + 3 * (size_t)m->he_vertex[h0];
    /* scale: largest coordinate difference from the first vertex, of the
     * halved coordinates (no overflow even at +-DBL_MAX) */
    double s = 0.0;
    size_t n = 0;
    h = h0;
    do {
        const double *q = p + 3 * (size_t)m->he_vertex[h];
        for (int k = 0; k < 3; ++k) {
            double d = fabs(0.5 * q[k] - 0.5 * o[k]);
            if (d > s)
                s = d;
        }
        ++n;
        h = m->he_next[h];
    } while (h != h0 && n <= m->nh);
    if (!(s > 0.0))
        return true; /* all vertices coincide (or NaN) */
    double inv = 1.0 / s;
    double nx = 0, ny = 0, nz = 0, emax = 0;
    int coincident = 0;
    h = h0;
    size_t i = 0;
    do {
        uint32_t hn = m->he_next[h];
        const double *a = p + 3 * (size_t)m->he_vertex[h], *b = p + 3 * (size_t)m->he_vertex[hn];
        double ax = (0.5 * a[0] - 0.5 * o[0]) * inv, ay = (0.5 * a[1] - 0.5 * o[1]) * inv,
               az = (0.5 * a[2] - 0.5 * o[2]) * inv;
        double bx = (0.5 * b[0] - 0.5 * o[0]) * inv, by = (0.5 * b[1] - 0.5 * o[1]) * inv,
               bz = (0.5 * b[2] - 0.5 * o[2]) * inv;
        nx += (ay - by) * (az + bz);
        ny += (az - bz) * (ax + bx);
        nz += (ax - bx) * (ay + by);
        double ex = bx - ax, ey = by - ay, ez = bz - az, e2 = ex * ex + ey * ey + ez * ez;
        if (e2 > emax)
            emax = e2;
        /* coincident vertices: every pair for small faces, consecutive ones
         * for large faces */
        if (n <= 64) {
            uint32_t g = hn;
            for (size_t j = i + 1; j < n; ++j, g = m->he_next[g]) {
                const double *c = p + 3 * (size_t)m->he_vertex[g];
                if (a[0] == c[0] && a[1] == c[1] && a[2] == c[2])
                    coincident = 1;
            }
        } else if (a[0] == b[0] && a[1] == b[1] && a[2] == b[2])
            coincident = 1;
        ++i;
        h = hn;
    } while (h != h0 && i <= m->nh);
    if (coincident)
        return true;
    double area = 0.5 * sqrt(nx * nx + ny * ny + nz * nz);
    return !(area > 1e-14 * emax);
}

geom_status geom_mesh_topology_summary(const geom_mesh *m, geom_mesh_topology *t)
{
    if (!m || !t)
        return GEOM_ERR_INVALID_ARG;
    memset(t, 0, sizeof *t);
    if (m->nv >= (size_t)UINT32_MAX / 2)
        return GEOM_ERR_LIMIT;
    size_t nv = m->nv;
    /* Indices must be in range before anything is followed; otherwise only
     * the counts are given and the mesh is reported non-manifold. */
    int bad = 0;
    for (size_t h = 0; h < m->nh && !bad; ++h)
        if (!m->e_del[h >> 1] &&
            ((size_t)m->he_vertex[h] >= nv || (size_t)m->he_next[h] >= m->nh ||
             (m->he_face[h] != INV && (size_t)m->he_face[h] >= m->nf)))
            bad = 1;
    for (size_t f = 0; f < m->nf && !bad; ++f)
        if (!m->f_del[f] && (size_t)m->f_he[f] >= m->nh)
            bad = 1;
    if (bad) {
        t->vertices = m->nv - m->n_del_v;
        t->edges = m->nh / 2 - m->n_del_e;
        t->faces = m->nf - m->n_del_f;
        t->euler = (long)t->vertices - (long)t->edges + (long)t->faces;
        t->manifold = false;
        return GEOM_OK;
    }
    /* lab (nv) + per-component V, E, F, B counters (4 * nv) */
    size_t words = 5 * (nv ? nv : 1);
    uint32_t *buf = geom__alloc(&m->alloc, words * sizeof(uint32_t));
    uint32_t *hl = geom__alloc(&m->alloc, (m->nh ? m->nh : 1) * sizeof(uint32_t));
    if (!buf || !hl) {
        geom__free(&m->alloc, buf, words * sizeof(uint32_t));
        geom__free(&m->alloc, hl, (m->nh ? m->nh : 1) * sizeof(uint32_t));
        return GEOM_ERR_NOMEM;
    }
    uint32_t *lab = buf, *cV = buf + nv, *cE = cV + nv, *cF = cE + nv, *cB = cF + nv;
    size_t nc = vertex_components(m, lab), nloops = 0;
    geom_mesh_boundary_loops(m, &nloops, hl);
    memset(cV, 0, 4 * nv * sizeof(uint32_t));
    for (size_t v = 0; v < nv; ++v) {
        if (m->v_del[v])
            continue;
        cV[lab[v]]++;
        t->vertices++;
        if (m->v_he[v] == INV)
            t->isolated_vertices++;
    }
    t->closed = true;
    for (size_t e = 0; e < m->nh / 2; ++e) {
        if (m->e_del[e])
            continue;
        if (lab[m->he_vertex[2 * e]] != INV)
            cE[lab[m->he_vertex[2 * e]]]++;
        t->edges++;
        for (int j = 0; j < 2; ++j) {
            size_t h = 2 * e + (size_t)j;
            if (m->he_face[h] == INV) {
                t->closed = false;
                /* count each loop once, at its lowest halfedge */
                uint32_t id = hl[h];
                if (id != INV) {
                    if (lab[m->he_vertex[h]] != INV)
                        cB[lab[m->he_vertex[h]]]++;
                    /* mark the loop counted */
                    uint32_t g = m->he_next[h];
                    size_t guard = 0;
                    while (g != h && ++guard <= m->nh) {
                        hl[g] = INV;
                        g = m->he_next[g];
                    }
                    hl[h] = INV;
                }
            }
        }
    }
    for (size_t f = 0; f < m->nf; ++f) {
        if (m->f_del[f])
            continue;
        if (lab[m->he_vertex[m->f_he[f]]] != INV)
            cF[lab[m->he_vertex[m->f_he[f]]]]++;
        t->faces++;
        if (geom_mesh_face_is_degenerate(m, (uint32_t)f))
            t->degenerate_faces++;
    }
    t->boundary_loops = nloops;
    t->components = nc;
    t->euler = (long)t->vertices - (long)t->edges + (long)t->faces;
    long genus = 0;
    for (size_t c = 0; c < nc; ++c) {
        long chi = (long)cV[c] - (long)cE[c] + (long)cF[c];
        genus += (2 - chi - (long)cB[c]) / 2;
    }
    t->genus = genus;
    size_t nd = 0;
    geom_mesh_validate(m, NULL, 0, &nd);
    t->manifold = nd == 0;
    geom__free(&m->alloc, buf, words * sizeof(uint32_t));
    geom__free(&m->alloc, hl, (m->nh ? m->nh : 1) * sizeof(uint32_t));
    return GEOM_OK;
}
