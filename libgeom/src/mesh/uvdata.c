/*
 * UV data for renderers: charts (face components across non-seam edges),
 * seam edges, UV-space areas, flipped and degenerate UV faces, and per-chart
 * bounds, from a CORNER channel of 2 (or more; the first two are used)
 * components.
 *
 * Definitions used:
 *  - an interior edge is a seam when the corners of its two faces at either
 *    end have different pool indices (boundary edges are never seams);
 *  - a face's UV area is the shoelace sum over its corners (positive for a
 *    counter-clockwise UV polygon); it is degenerate when |area| is at most
 *    1e-14 times the square of its longest UV edge (the rule of
 *    geom_mesh_face_is_degenerate, in UV space) or a corner has no UV (an
 *    invalid index); flipped when it is not degenerate and the area is < 0;
 *  - faces with a corner without UV belong to no chart (face_chart =
 *    GEOM_INVALID_INDEX) and add nothing to the area or bounds; an edge next
 *    to such a face is not a seam.
 */
#include "mesh/mesh_internal.h"

#define INV GEOM_INVALID_INDEX

static int face_has_uv(const geom_mesh *m, const uint32_t *idx, size_t pool, uint32_t f)
{
    uint32_t h0 = m->f_he[f], h = h0;
    size_t k = 0;
    do {
        if (idx[h] == INV || idx[h] >= pool)
            return 0;
        h = m->he_next[h];
    } while (h != h0 && ++k < m->nh);
    return 1;
}

geom_status geom_mesh_uv_data(const geom_mesh *m, uint32_t uv_channel, geom_uv_report *report,
                              double *chart_bounds, uint32_t *face_chart, uint8_t *seam_edge)
{
    if (report)
        memset(report, 0, sizeof *report);
    if (!m || uv_channel >= m->n_channels)
        return GEOM_ERR_INVALID_ARG;
    const geom__mesh_channel *ch = &m->channels[uv_channel];
    if (ch->domain != GEOM_MESH_DOMAIN_CORNER || ch->ncomp < 2)
        return GEOM_ERR_INVALID_ARG;
    const size_t nf = m->nf, ne = m->nh / 2, nc = ch->ncomp, pool = ch->pool;
    const uint32_t *idx = ch->corner;
    const double *uv = ch->data;
    const geom_allocator *al = &m->alloc;

    uint32_t *parent = geom__alloc(al, (nf ? nf : 1) * sizeof(uint32_t));
    uint8_t *has = geom__alloc(al, nf ? nf : 1);
    if (!parent || !has) {
        geom__free(al, parent, (nf ? nf : 1) * sizeof(uint32_t));
        geom__free(al, has, nf ? nf : 1);
        return GEOM_ERR_NOMEM;
    }
    for (size_t f = 0; f < nf; f++) {
        parent[f] = (uint32_t)f;
        has[f] = !m->f_del[f] && face_has_uv(m, idx, pool, (uint32_t)f);
    }

    size_t seams = 0;
    for (size_t e = 0; e < ne; e++) {
        uint8_t s = 0;
        if (!m->e_del[e]) {
            uint32_t h0 = (uint32_t)(2 * e), h1 = h0 + 1;
            uint32_t f0 = m->he_face[h0], f1 = m->he_face[h1];
            if (f0 != INV && f1 != INV && has[f0] && has[f1]) {
                /* h0: from a to b in f0 (corners prev(h0) at a, h0 at b);
                 * h1: from b to a in f1 (corners prev(h1) at b, h1 at a). */
                if (idx[h0] != idx[m->he_prev[h1]] || idx[m->he_prev[h0]] != idx[h1]) {
                    s = 1;
                    seams++;
                } else {
                    geom__uf_union(parent, f0, f1);
                }
            }
        }
        if (seam_edge)
            seam_edge[e] = s;
    }

    /* chart numbering in order of first face */
    size_t charts = 0;
    uint32_t *chart_of_root = geom__alloc(al, (nf ? nf : 1) * sizeof(uint32_t));
    if (!chart_of_root) {
        geom__free(al, parent, (nf ? nf : 1) * sizeof(uint32_t));
        geom__free(al, has, nf ? nf : 1);
        return GEOM_ERR_NOMEM;
    }
    for (size_t f = 0; f < nf; f++)
        chart_of_root[f] = INV;
    geom_uv_report r;
    memset(&r, 0, sizeof r);
    r.uv_min[0] = r.uv_min[1] = INFINITY;
    r.uv_max[0] = r.uv_max[1] = -INFINITY;
    for (size_t f = 0; f < nf; f++) {
        uint32_t c = INV;
        if (m->f_del[f]) {
            if (face_chart)
                face_chart[f] = INV;
            continue;
        }
        if (!has[f]) {
            r.degenerate_uv_faces++;
            if (face_chart)
                face_chart[f] = INV;
            continue;
        }
        uint32_t root = geom__uf_find(parent, (uint32_t)f);
        if (chart_of_root[root] == INV) {
            chart_of_root[root] = (uint32_t)charts;
            if (chart_bounds) {
                chart_bounds[4 * charts] = chart_bounds[4 * charts + 1] = INFINITY;
                chart_bounds[4 * charts + 2] = chart_bounds[4 * charts + 3] = -INFINITY;
            }
            charts++;
        }
        c = chart_of_root[root];
        if (face_chart)
            face_chart[f] = c;
        /* area (relative to the first corner) and bounds */
        uint32_t h0 = m->f_he[f], h = h0;
        const double *a = uv + (size_t)idx[h0] * nc;
        double area2 = 0.0, L2 = 0.0;
        size_t k = 0;
        do {
            uint32_t hn = m->he_next[h];
            const double *p = uv + (size_t)idx[h] * nc;
            const double *q = uv + (size_t)idx[hn] * nc;
            double pu = p[0] - a[0], pv = p[1] - a[1], qu = q[0] - a[0], qv = q[1] - a[1];
            area2 += pu * qv - pv * qu;
            double du = q[0] - p[0], dv = q[1] - p[1];
            double l2 = du * du + dv * dv;
            if (l2 > L2)
                L2 = l2;
            for (int j = 0; j < 2; j++) {
                if (p[j] < r.uv_min[j])
                    r.uv_min[j] = p[j];
                if (p[j] > r.uv_max[j])
                    r.uv_max[j] = p[j];
                if (chart_bounds) {
                    double *b = chart_bounds + 4 * (size_t)c;
                    if (p[j] < b[j])
                        b[j] = p[j];
                    if (p[j] > b[2 + j])
                        b[2 + j] = p[j];
                }
            }
            h = hn;
        } while (h != h0 && ++k < m->nh);
        double area = 0.5 * area2;
        if (!(fabs(area) > 1e-14 * L2))
            r.degenerate_uv_faces++;
        else if (area < 0.0)
            r.flipped_faces++;
        if (isfinite(area))
            r.uv_area += fabs(area);
    }
    if (r.uv_min[0] > r.uv_max[0]) {
        r.uv_min[0] = r.uv_min[1] = 0.0;
        r.uv_max[0] = r.uv_max[1] = 0.0;
    }
    r.charts = charts;
    r.seam_edges = seams;
    if (report)
        *report = r;
    geom__free(al, parent, (nf ? nf : 1) * sizeof(uint32_t));
    geom__free(al, has, nf ? nf : 1);
    geom__free(al, chart_of_root, (nf ? nf : 1) * sizeof(uint32_t));
    return GEOM_OK;
}
