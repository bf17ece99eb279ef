/* Closest point on a triangle (Ericson, Real-Time Collision Detection, 2005,
 * 5.1.5: Voronoi regions of vertices, edges and face) and on a triangle mesh
 * through its BVH. */
#include "spatial/spatial_internal.h"

#include <string.h>

static double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void sub3(const double *a, const double *b, double *o)
{
    o[0] = a[0] - b[0];
    o[1] = a[1] - b[1];
    o[2] = a[2] - b[2];
}

/* Closest point on segment a-b; t in [0, 1] from a. */
static double seg_closest(const double p[3], const double a[3], const double b[3], double *t)
{
    double ab[3], ap[3];
    sub3(b, a, ab);
    sub3(p, a, ap);
    double l = dot3(ab, ab), s = 0;
    if (l > 0) {
        s = dot3(ap, ab) / l;
        s = s < 0 ? 0 : s > 1 ? 1 : s;
    }
    *t = s;
    double c[3] = {a[0] + s * ab[0], a[1] + s * ab[1], a[2] + s * ab[2]};
    return geom__d2(c, p);
}

static inline double closest_tri(const double p[3], const double a[3], const double b[3],
                                 const double c[3], double out[3], double bary[3])
{
    double ab[3], ac[3], ap[3], bp[3], cp[3];
    sub3(b, a, ab);
    sub3(c, a, ac);
    sub3(p, a, ap);
    double d1 = dot3(ab, ap), d2 = dot3(ac, ap);
    if (d1 <= 0 && d2 <= 0) {
        memcpy(out, a, 3 * sizeof *out);
        bary[0] = 1, bary[1] = 0, bary[2] = 0;
        return geom__d2(out, p);
    }
    sub3(p, b, bp);
    double d3 = dot3(ab, bp), d4 = dot3(ac, bp);
    if (d3 >= 0 && d4 <= d3) {
        memcpy(out, b, 3 * sizeof *out);
        bary[0] = 0, bary[1] = 1, bary[2] = 0;
        return geom__d2(out, p);
    }
    double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0 && d1 - d3 > 0) {
        double v = d1 / (d1 - d3);
        for (int k = 0; k < 3; k++)
            out[k] = a[k] + v * ab[k];
        bary[0] = 1 - v, bary[1] = v, bary[2] = 0;
        return geom__d2(out, p);
    }
    sub3(p, c, cp);
    double d5 = dot3(ab, cp), d6 = dot3(ac, cp);
    if (d6 >= 0 && d5 <= d6) {
        memcpy(out, c, 3 * sizeof *out);
        bary[0] = 0, bary[1] = 0, bary[2] = 1;
        return geom__d2(out, p);
    }
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0 && d2 - d6 > 0) {
        double w = d2 / (d2 - d6);
        for (int k = 0; k < 3; k++)
            out[k] = a[k] + w * ac[k];
        bary[0] = 1 - w, bary[1] = 0, bary[2] = w;
        return geom__d2(out, p);
    }
    double va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0 && (d4 - d3) + (d5 - d6) > 0) {
        double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        for (int k = 0; k < 3; k++)
            out[k] = b[k] + w * (c[k] - b[k]);
        bary[0] = 0, bary[1] = 1 - w, bary[2] = w;
        return geom__d2(out, p);
    }
    double den = va + vb + vc;
    if (den > 0 && isfinite(den)) {
        double v = vb / den, w = vc / den;
        for (int k = 0; k < 3; k++)
            out[k] = a[k] + ab[k] * v + ac[k] * w;
        bary[0] = 1 - v - w, bary[1] = v, bary[2] = w;
        return geom__d2(out, p);
    }
    /* Degenerate (or rounding put us here): the nearest of the three edges. */
    double t, best, d;
    best = seg_closest(p, a, b, &t);
    double bb[3] = {1 - t, t, 0};
    const double *e0 = a, *e1 = b;
    int which = 0;
    d = seg_closest(p, b, c, &t);
    if (d < best) {
        best = d, which = 1, e0 = b, e1 = c;
        bb[0] = 0, bb[1] = 1 - t, bb[2] = t;
    }
    double t2;
    d = seg_closest(p, a, c, &t2);
    if (d < best) {
        best = d, which = 2, e0 = a, e1 = c;
        bb[0] = 1 - t2, bb[1] = 0, bb[2] = t2;
    }
    double s = which == 0 ? bb[1] : which == 1 ? bb[2] : bb[2];
    for (int k = 0; k < 3; k++)
        out[k] = e0[k] + s * (e1[k] - e0[k]);
    memcpy(bary, bb, sizeof bb);
    return geom__d2(out, p);
}

/* Shared with the surface tessellator's error check (spatial_internal.h). */
double geom__closest_tri_d2(const double p[3], const double a[3], const double b[3],
                            const double c[3])
{
    double out[3], bary[3];
    return closest_tri(p, a, b, c, out, bary);
}

double geom__closest_seg_d2(const double p[3], const double a[3], const double b[3])
{
    double t;
    return seg_closest(p, a, b, &t);
}

/* Prune margin: the computed closest point can sit a rounding error outside
 * its triangle's box. */
#define PRUNE(d2) ((d2) * (1.0 + 0x1p-40) + 0x1p-1000)

/* Queries per parallel work item (each runs in Morton order with the
 * previous answer as its starting bound). */
#define CHUNK 256

/* hint: a primitive slot (position in the BVH's primitive order) whose
 * triangle gives the starting bound, or UINT32_MAX; *slot_out receives the
 * answer's slot. The answer does not depend on the hint: every triangle whose
 * distance is at most the final one is still visited, and ties go to the
 * smaller triangle index. */
static void closest_one(const geom_meshdist *m, const double q[3], uint32_t hint, double pt[3],
                        uint32_t *tri, double bary[3], double *d2out, uint32_t *slot_out)
{
    size_t nn;
    const geom_bvh_node *nodes = geom_bvh_nodes(m->bvh, &nn);
    const uint32_t *prims = geom_bvh_prim_indices(m->bvh, NULL);
    double best = INFINITY;
    uint32_t bt = GEOM_INVALID_INDEX, bslot = UINT32_MAX;
    double bp[3] = {0, 0, 0}, bbary[3] = {0, 0, 0};
    if (nn && hint < m->nt) {
        const double *tv = m->tv + 9 * (size_t)hint;
        best = closest_tri(q, tv, tv + 3, tv + 6, bp, bbary);
        bt = prims[hint];
        bslot = hint;
    }
    if (nn) {
        uint32_t stack[256];
        double sd[256];
        int sp = 0;
        stack[sp] = 0;
        sd[sp++] = geom__box_d2(&nodes[0].box, q);
        while (sp > 0) {
            sp--;
            if (sd[sp] > PRUNE(best))
                continue;
            const geom_bvh_node *nd = &nodes[stack[sp]];
            if (nd->count) {
                const double *tv = m->tv + 9 * (size_t)nd->index;
                for (uint32_t k = 0; k < nd->count; k++, tv += 9) {
                    uint32_t t = prims[nd->index + k];
                    double c[3], l[3];
                    double d2 = closest_tri(q, tv, tv + 3, tv + 6, c, l);
                    if (d2 < best || (d2 == best && t < bt)) {
                        best = d2;
                        bt = t;
                        bslot = nd->index + k;
                        memcpy(bp, c, sizeof bp);
                        memcpy(bbary, l, sizeof bbary);
                    }
                }
                continue;
            }
            uint32_t li = stack[sp] + 1, ri = nd->index;
            double dl = geom__box_d2(&nodes[li].box, q), dr = geom__box_d2(&nodes[ri].box, q);
            /* Push the farther first so the nearer is popped first; skip
             * what is already farther than the best. */
            double lim = PRUNE(best);
            if (dl <= dr) {
                if (dr <= lim)
                    stack[sp] = ri, sd[sp++] = dr;
                if (dl <= lim)
                    stack[sp] = li, sd[sp++] = dl;
            } else {
                if (dl <= lim)
                    stack[sp] = li, sd[sp++] = dl;
                if (dr <= lim)
                    stack[sp] = ri, sd[sp++] = dr;
            }
        }
    }
    if (pt)
        memcpy(pt, bp, sizeof bp);
    if (bary)
        memcpy(bary, bbary, sizeof bbary);
    *tri = bt;
    *d2out = best;
    if (slot_out)
        *slot_out = bslot;
}

geom_status geom_meshdist_closest(const geom_meshdist *m, const double *queries, size_t nq,
                                  double *point, uint32_t *tri, double *bary, double *distance,
                                  int threads, geom_diag *diag)
{
    if (!m || (nq && !queries))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0, "closest point: NULL argument");
    size_t bad = geom__first_nonfinite(queries, nq, 3);
    if (bad < nq)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                             "closest point: query %zu has a NaN/Inf coordinate", bad);
    const geom_allocator *a = m->has_alloc ? &m->alloc : NULL;
    /* Queries in Morton order (of their own bounding box): consecutive
     * queries then touch the same nodes and triangles, and the previous
     * answer's triangle gives a tight starting bound. */
    uint32_t *order = NULL;
    uint64_t *keys = NULL;
    if (nq >= 2 * CHUNK && nq < UINT32_MAX) {
        order = geom__alloc(a, nq * sizeof *order);
        keys = geom__alloc(a, nq * sizeof *keys);
        if (order && keys) {
            double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
            for (size_t i = 0; i < nq; i++)
                for (int k = 0; k < 3; k++) {
                    double v = queries[3 * i + (size_t)k];
                    if (v < lo[k]) lo[k] = v;
                    if (v > hi[k]) hi[k] = v;
                }
            double sc[3];
            for (int k = 0; k < 3; k++)
                sc[k] = hi[k] > lo[k] ? 2097151.0 / (hi[k] - lo[k]) : 0.0;
            for (size_t i = 0; i < nq; i++) {
                uint32_t c[3];
                for (int k = 0; k < 3; k++) {
                    double f = (queries[3 * i + (size_t)k] - lo[k]) * sc[k];
                    c[k] = f > 0 ? (f < 2097151.0 ? (uint32_t)f : 2097151u) : 0u;
                }
                keys[i] = geom__morton3(c[0], c[1], c[2]);
                order[i] = (uint32_t)i;
            }
            if (geom__radix_sort64(a, keys, order, nq) != GEOM_OK) {
                geom__free(a, order, nq * sizeof *order);
                order = NULL;
            }
        } else {
            geom__free(a, order, nq * sizeof *order);
            order = NULL;
        }
        geom__free(a, keys, nq * sizeof *keys);
    }
    ptrdiff_t nchunks = (ptrdiff_t)((nq + CHUNK - 1) / CHUNK);
    int nth = geom__spatial_threads(threads);
    (void)nth;
#ifdef GEOM_SPATIAL_OPENMP
#pragma omp parallel for schedule(dynamic, 1) num_threads(nth) if (nchunks > 1)
#endif
    for (ptrdiff_t c = 0; c < nchunks; c++) {
        size_t end = (size_t)(c + 1) * CHUNK < nq ? (size_t)(c + 1) * CHUNK : nq;
        uint32_t hint = UINT32_MAX;
        for (size_t j = (size_t)c * CHUNK; j < end; j++) {
            size_t i = order ? order[j] : j;
            uint32_t t;
            double d2;
            closest_one(m, queries + 3 * i, hint, point ? point + 3 * i : NULL, &t,
                        bary ? bary + 3 * i : NULL, &d2, &hint);
            if (tri)
                tri[i] = t;
            if (distance)
                distance[i] = sqrt(d2);
        }
    }
    geom__free(a, order, nq * sizeof *order);
    return GEOM_OK;
}
