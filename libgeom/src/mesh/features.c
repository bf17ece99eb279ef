/*
 * Feature edges (boundary, crease, silhouette) joined into polylines.
 *
 * An interior edge is a crease when the angle between the unit (Newell)
 * normals of its two faces exceeds the threshold, a silhouette when
 * (e.n0)(e.n1) <= 0 with e the vector from the eye to the edge's midpoint.
 * Edges next to a degenerate face (no normal) are neither. Polylines follow
 * the feature edges through vertices where exactly two of them meet: each
 * maximal chain from an end (a vertex with one or three or more feature
 * edges) to an end is one polyline, and the remaining cycles become closed
 * polylines that repeat their first vertex at the end. Polylines are
 * oriented along a halfedge of their first edge (for a boundary loop: along
 * its boundary halfedges, i.e. clockwise around the hole seen from outside).
 */
#include "mesh/mesh_internal.h"

#define INV GEOM_INVALID_INDEX

static inline double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* The halfedge of edge e starting at v. */
static inline uint32_t he_from(const geom_mesh *m, uint32_t e, uint32_t v)
{
    uint32_t h = 2 * e;
    return m->he_vertex[h ^ 1u] == v ? h : h ^ 1u;
}

geom_status geom_mesh_features(geom_mesh *m, const geom_feature_options *opt, uint8_t *edge_kind,
                               size_t *n_polylines)
{
    if (n_polylines)
        *n_polylines = 0;
    geom_feature_options o;
    memset(&o, 0, sizeof o);
    if (opt)
        o = *opt;
    if (!m || !(o.crease_degrees >= 0.0) || !isfinite(o.crease_degrees) ||
        !geom__isfinite3(o.eye))
        return GEOM_ERR_INVALID_ARG;
    unsigned kinds = o.kinds ? o.kinds : (GEOM_FEATURE_BOUNDARY | GEOM_FEATURE_CREASE);
    if (kinds & ~(unsigned)(GEOM_FEATURE_BOUNDARY | GEOM_FEATURE_CREASE | GEOM_FEATURE_SILHOUETTE))
        return GEOM_ERR_INVALID_ARG;
    double crease = o.crease_degrees == 0.0 ? 30.0 : o.crease_degrees;
    /* the angle between unit normals as atan2(|n0 x n1|, n0.n1): accurate
     * for tiny and for nearly opposite normals, unlike acos of the dot */
    const double crease_rad = crease * (GEOM_PI / 180.0);

    const size_t nv = m->nv, ne = m->nh / 2, nf = m->nf;
    const geom_allocator *al = &m->alloc;
    const double *pos = geom__mesh_pos(m);
    geom_status st = GEOM_OK;
    double *fn = NULL;
    uint8_t *kind = NULL, *used = NULL, *has_n = NULL;
    uint32_t *deg = NULL, *adj = NULL, *poly = NULL;
    size_t nfeat = 0, poly_cap = 0, added = 0;

    fn = geom__alloc(al, (nf ? nf : 1) * 3 * sizeof(double));
    has_n = geom__alloc(al, nf ? nf : 1);
    kind = geom__alloc(al, ne ? ne : 1);
    used = geom__alloc(al, ne ? ne : 1);
    deg = geom__alloc(al, (nv + 1) * sizeof(uint32_t));
    if (!fn || !has_n || !kind || !used || !deg) {
        st = GEOM_ERR_NOMEM;
        goto done;
    }
    if (kinds & (GEOM_FEATURE_CREASE | GEOM_FEATURE_SILHOUETTE)) {
        for (size_t f = 0; f < nf; f++)
            has_n[f] = !m->f_del[f] && geom_mesh_face_normal(m, (uint32_t)f, fn + 3 * f) == GEOM_OK;
    }

    for (size_t e = 0; e < ne; e++) {
        uint8_t k = 0;
        used[e] = 0;
        if (!m->e_del[e]) {
            uint32_t h = (uint32_t)(2 * e);
            uint32_t f0 = m->he_face[h], f1 = m->he_face[h + 1];
            if (f0 == INV || f1 == INV) {
                if (kinds & GEOM_FEATURE_BOUNDARY)
                    k |= GEOM_FEATURE_BOUNDARY;
            } else if (has_n[f0] && has_n[f1]) {
                const double *n0 = fn + 3 * (size_t)f0, *n1 = fn + 3 * (size_t)f1;
                if (kinds & GEOM_FEATURE_CREASE) {
                    double x[3] = {n0[1] * n1[2] - n0[2] * n1[1], n0[2] * n1[0] - n0[0] * n1[2],
                                   n0[0] * n1[1] - n0[1] * n1[0]};
                    if (atan2(sqrt(dot3(x, x)), dot3(n0, n1)) > crease_rad)
                        k |= GEOM_FEATURE_CREASE;
                }
                if (kinds & GEOM_FEATURE_SILHOUETTE) {
                    const double *a = pos + 3 * (size_t)m->he_vertex[h];
                    const double *b = pos + 3 * (size_t)m->he_vertex[h + 1];
                    double d[3];
                    for (int j = 0; j < 3; j++)
                        d[j] = (0.5 * a[j] + 0.5 * b[j]) - o.eye[j];
                    double s0 = dot3(d, n0), s1 = dot3(d, n1);
                    /* compare signs rather than multiply (no overflow) */
                    if ((s0 <= 0.0 && s1 >= 0.0) || (s0 >= 0.0 && s1 <= 0.0))
                        k |= GEOM_FEATURE_SILHOUETTE;
                }
            }
        }
        kind[e] = k;
        if (edge_kind)
            edge_kind[e] = k;
        if (k)
            nfeat++;
    }

    /* CSR adjacency: feature edges per vertex */
    memset(deg, 0, (nv + 1) * sizeof(uint32_t));
    for (size_t e = 0; e < ne; e++) {
        if (!kind[e])
            continue;
        deg[m->he_vertex[2 * e] + 1]++;
        deg[m->he_vertex[2 * e + 1] + 1]++;
    }
    for (size_t v = 0; v < nv; v++)
        deg[v + 1] += deg[v];
    adj = geom__alloc(al, (2 * nfeat + 1) * sizeof(uint32_t));
    if (!adj) {
        st = GEOM_ERR_NOMEM;
        goto done;
    }
    {
        uint32_t *fill = geom__alloc(al, (nv ? nv : 1) * sizeof(uint32_t));
        if (!fill) {
            st = GEOM_ERR_NOMEM;
            goto done;
        }
        memcpy(fill, deg, nv * sizeof(uint32_t));
        for (size_t e = 0; e < ne; e++) {
            if (!kind[e])
                continue;
            adj[fill[m->he_vertex[2 * e]]++] = (uint32_t)e;
            adj[fill[m->he_vertex[2 * e + 1]]++] = (uint32_t)e;
        }
        geom__free(al, fill, (nv ? nv : 1) * sizeof(uint32_t));
    }
#define VDEG(v) (deg[(v) + 1] - deg[(v)])

    /* Two passes: chains from ends, then the remaining cycles. */
    for (int pass = 0; pass < 2; pass++) {
        for (size_t v0 = 0; v0 < nv; v0++) {
            if (pass == 0 && VDEG(v0) == 2)
                continue;
            for (uint32_t s = deg[v0]; s < deg[v0 + 1]; s++) {
                uint32_t e = adj[s];
                if (used[e])
                    continue;
                size_t n = 0;
                uint32_t v = (uint32_t)v0;
                /* orient a cycle along the halfedge of its first edge that
                 * is a boundary one, if any, else the one leaving v0 */
                if (pass == 1) {
                    uint32_t hb = 2 * e;
                    if (m->he_face[hb] != INV && m->he_face[hb + 1] == INV)
                        hb++;
                    v = m->he_vertex[hb ^ 1u];
                }
                for (;;) {
                    st = geom__grow(al, (void **)&poly, &poly_cap, n + 2, sizeof(uint32_t));
                    if (st != GEOM_OK)
                        goto done;
                    poly[n++] = v;
                    used[e] = 1;
                    uint32_t w = m->he_vertex[he_from(m, e, v)];
                    if (VDEG(w) != 2) {
                        poly[n++] = w;
                        break;
                    }
                    uint32_t e2 = adj[deg[w]] == e ? adj[deg[w] + 1] : adj[deg[w]];
                    if (used[e2]) {
                        poly[n++] = w; /* closed cycle: w is the first vertex */
                        break;
                    }
                    v = w;
                    e = e2;
                }
                st = geom_mesh_polyline_add(m, n, poly);
                if (st != GEOM_OK)
                    goto done;
                added++;
                if (pass == 1)
                    break; /* v0's other edge belongs to this cycle */
            }
        }
    }
#undef VDEG
    if (n_polylines)
        *n_polylines = added;

done:
    geom__free(al, fn, (nf ? nf : 1) * 3 * sizeof(double));
    geom__free(al, has_n, nf ? nf : 1);
    geom__free(al, kind, ne ? ne : 1);
    geom__free(al, used, ne ? ne : 1);
    geom__free(al, deg, (nv + 1) * sizeof(uint32_t));
    geom__free(al, adj, (2 * nfeat + 1) * sizeof(uint32_t));
    geom__free(al, poly, poly_cap * sizeof(uint32_t));
    return st;
}
