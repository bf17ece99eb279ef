/*
 * kd-tree over 2D/3D points (Friedman, Bentley and Finkel 1977): median
 * split along the widest axis of each node's points (quickselect on the key
 * (coordinate, index), so the tree is unique), flat depth-first nodes whose
 * indices follow from the point count alone (so subtrees are built as
 * independent OpenMP tasks writing to known slots), points copied in tree
 * order. Queries descend nearest child first and prune the far child with
 * the distance to its cell accumulated per axis (Arya and Mount 1993), which
 * is a lower bound of every point's computed distance (rounding is
 * monotone), so the answers equal a brute-force scan's exactly.
 */
#include "spatial/spatial_internal.h"

#include <string.h>

#define TASK_MIN 8192

typedef struct kdnode {
    double split;
    uint32_t index; /* interior: right child; leaf: first point */
    uint16_t count; /* leaf: number of points; interior: 0 */
    uint16_t axis;
} kdnode;

struct geom_kdtree {
    geom_allocator alloc;
    int has_alloc;
    int dim;
    size_t n;
    double *pts; /* 3*n in tree order (z = 0 in 2D) */
    uint32_t *ids;
    kdnode *nodes;
    size_t node_count;
    size_t depth;
    uint32_t leaf;
};

typedef struct kpt {
    double p[3];
    uint32_t id;
    uint32_t pad;
} kpt;

static size_t count_nodes(size_t n, uint32_t leaf)
{
    if (n <= leaf)
        return 1;
    return 1 + count_nodes(n / 2, leaf) + count_nodes(n - n / 2, leaf);
}

static size_t tree_depth(size_t n, uint32_t leaf)
{
    size_t d = 1;
    while (n > leaf) {
        n = n - n / 2;
        d++;
    }
    return d;
}

static int kless(const kpt *a, const kpt *b, int ax)
{
    return a->p[ax] < b->p[ax] || (a->p[ax] == b->p[ax] && a->id < b->id);
}

/* Quickselect: place the element of rank m (by (coord, id)) at m, smaller
 * ones before, larger after. Median-of-three pivots; deterministic. */
static void select_rank(kpt *v, size_t n, size_t m, int ax)
{
    size_t lo = 0, hi = n - 1;
    while (hi > lo) {
        size_t mid = lo + (hi - lo) / 2;
        if (kless(&v[mid], &v[lo], ax)) { kpt t = v[mid]; v[mid] = v[lo]; v[lo] = t; }
        if (kless(&v[hi], &v[lo], ax)) { kpt t = v[hi]; v[hi] = v[lo]; v[lo] = t; }
        if (kless(&v[hi], &v[mid], ax)) { kpt t = v[hi]; v[hi] = v[mid]; v[mid] = t; }
        kpt pivot = v[mid];
        size_t i = lo, j = hi;
        while (i <= j) {
            while (kless(&v[i], &pivot, ax)) i++;
            while (kless(&pivot, &v[j], ax)) j--;
            if (i <= j) {
                kpt t = v[i]; v[i] = v[j]; v[j] = t;
                i++;
                if (j == 0)
                    break;
                j--;
            }
        }
        if (m <= j)
            hi = j;
        else if (m >= i)
            lo = i;
        else
            return;
    }
}

static void build(geom_kdtree *t, kpt *v, size_t start, size_t n, size_t node, int nth)
{
    kdnode *nd = &t->nodes[node];
    if (n <= t->leaf) {
        nd->split = 0;
        nd->index = (uint32_t)start;
        nd->count = (uint16_t)n;
        nd->axis = 0;
        return;
    }
    kpt *r = v + start;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) {
            if (r[i].p[k] < lo[k]) lo[k] = r[i].p[k];
            if (r[i].p[k] > hi[k]) hi[k] = r[i].p[k];
        }
    int ax = 0;
    for (int k = 1; k < t->dim; k++)
        if (hi[k] - lo[k] > hi[ax] - lo[ax])
            ax = k;
    size_t nl = n / 2;
    select_rank(r, n, nl, ax);
    nd->split = r[nl].p[ax];
    nd->axis = (uint16_t)ax;
    nd->count = 0;
    size_t right = node + 1 + count_nodes(nl, t->leaf);
    nd->index = (uint32_t)right;
    if (nth > 1 && n >= TASK_MIN) {
#ifdef GEOM_SPATIAL_OPENMP
#pragma omp task firstprivate(t, v, start, nl, node, nth)
#endif
        build(t, v, start, nl, node + 1, nth);
        build(t, v, start + nl, n - nl, right, nth);
#ifdef GEOM_SPATIAL_OPENMP
#pragma omp taskwait
#endif
    } else {
        build(t, v, start, nl, node + 1, 1);
        build(t, v, start + nl, n - nl, right, 1);
    }
}

void geom_kdtree_destroy(geom_kdtree *t)
{
    if (!t)
        return;
    const geom_allocator *a = t->has_alloc ? &t->alloc : NULL;
    geom__free(a, t->pts, 3 * t->n * sizeof *t->pts);
    geom__free(a, t->ids, t->n * sizeof *t->ids);
    geom__free(a, t->nodes, t->node_count * sizeof *t->nodes);
    geom__free(a, t, sizeof *t);
}

geom_status geom_kdtree_build(const double *points, size_t n, int dim,
                              const geom_kdtree_options *opt, geom_kdtree **out, geom_diag *diag)
{
    if (out)
        *out = NULL;
    if (!out || (n && !points) || (dim != 2 && dim != 3))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                             "kd-tree: NULL argument or dimension %d (2 or 3)", dim);
    if (n >= UINT32_MAX)
        return geom__diag_set(diag, GEOM_ERR_LIMIT, "", 0, 0, "kd-tree: %zu points (at most 2^32-2)", n);
    size_t bad = geom__first_nonfinite(points, n, dim);
    if (bad < n)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                             "kd-tree: point %zu has a NaN/Inf coordinate", bad);
    geom_kdtree_options o;
    memset(&o, 0, sizeof o);
    if (opt)
        o = *opt;
    const geom_allocator *a = o.alloc;
    geom_kdtree *t = geom__alloc(a, sizeof *t);
    if (!t)
        return geom__diag_set(diag, GEOM_ERR_NOMEM, "", 0, 0, "kd-tree: out of memory");
    memset(t, 0, sizeof *t);
    if (a) {
        t->alloc = *a;
        t->has_alloc = 1;
    }
    t->dim = dim;
    t->n = n;
    t->leaf = o.leaf_size ? o.leaf_size : 10;
    if (t->leaf > 65535)
        t->leaf = 65535;
    t->node_count = n ? count_nodes(n, t->leaf) : 0;
    t->depth = n ? tree_depth(n, t->leaf) : 0;
    t->pts = geom__alloc(a, 3 * n * sizeof *t->pts);
    t->ids = geom__alloc(a, n * sizeof *t->ids);
    t->nodes = geom__alloc(a, (t->node_count ? t->node_count : 1) * sizeof *t->nodes);
    kpt *v = geom__alloc(a, n * sizeof *v);
    if (!t->pts || !t->ids || !t->nodes || !v) {
        geom__free(a, v, n * sizeof *v);
        if (!t->node_count)
            t->node_count = 1;
        geom_kdtree_destroy(t);
        return geom__diag_set(diag, GEOM_ERR_NOMEM, "", 0, 0, "kd-tree: out of memory");
    }
    for (size_t i = 0; i < n; i++) {
        v[i].p[0] = points[(size_t)dim * i];
        v[i].p[1] = points[(size_t)dim * i + 1];
        v[i].p[2] = dim == 3 ? points[3 * i + 2] : 0.0;
        v[i].id = (uint32_t)i;
        v[i].pad = 0;
    }
    if (n) {
        int nth = geom__spatial_threads(o.threads);
#ifdef GEOM_SPATIAL_OPENMP
        if (nth > 1 && n >= TASK_MIN) {
#pragma omp parallel num_threads(nth)
#pragma omp single
            build(t, v, 0, n, 0, nth);
        } else
#endif
            build(t, v, 0, n, 0, 1);
    }
    for (size_t i = 0; i < n; i++) {
        memcpy(t->pts + 3 * i, v[i].p, 3 * sizeof(double));
        t->ids[i] = v[i].id;
    }
    geom__free(a, v, n * sizeof *v);
    if (!t->node_count)
        t->node_count = 1; /* the allocated placeholder */
    *out = t;
    return GEOM_OK;
}

size_t geom_kdtree_node_count(const geom_kdtree *t)
{
    return t && t->n ? t->node_count : 0;
}

size_t geom_kdtree_depth(const geom_kdtree *t)
{
    return t ? t->depth : 0;
}

size_t geom_kdtree_bytes(const geom_kdtree *t)
{
    if (!t)
        return 0;
    return sizeof *t + t->n * (3 * sizeof(double) + sizeof(uint32_t)) +
           t->node_count * sizeof(kdnode);
}

/* ------------------------------------------------------------------ kNN */

static void knn_rec(const geom_kdtree *t, size_t node, const double q[3], double off[3], geom__kbest *b)
{
    const kdnode *nd = &t->nodes[node];
    if (nd->count) {
        const double *p = t->pts + 3 * (size_t)nd->index;
        const uint32_t *ids = t->ids + nd->index;
        for (uint32_t i = 0; i < nd->count; i++, p += 3)
            geom__kbest_insert(b, geom__d2(p, q), ids[i]);
        return;
    }
    int ax = nd->axis;
    double diff = q[ax] - nd->split;
    size_t near = diff < 0 ? node + 1 : nd->index, far = diff < 0 ? nd->index : node + 1;
    knn_rec(t, near, q, off, b);
    double old = off[ax];
    off[ax] = diff;
    double rd = off[0] * off[0] + off[1] * off[1] + off[2] * off[2];
    if (b->count < b->k || rd <= b->d2[b->k - 1])
        knn_rec(t, far, q, off, b);
    off[ax] = old;
}


static void kd_knn_one(const void *ctx, const double q[3], geom__kbest *b)
{
    const geom_kdtree *t = ctx;
    double off[3] = {0, 0, 0};
    if (b->k)
        knn_rec(t, 0, q, off, b);
}

geom_status geom_kdtree_knn(const geom_kdtree *t, const double *queries, size_t nq, size_t k,
                            uint32_t *index, double *distance, int threads, geom_diag *diag)
{
    if (!t)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0, "kNN: NULL argument");
    return geom__knn_batch(t->has_alloc ? &t->alloc : NULL, t, kd_knn_one, t->dim, t->n, queries, nq,
                           k, index, distance, threads, diag);
}

/* --------------------------------------------------------------- radius */

typedef struct rctx {
    const geom_kdtree *t;
    const double *queries;
    double r, r2b;
    const double *lo, *hi;
} rctx;

static int radius_rec(const geom_kdtree *t, size_t node, const double q[3], double off[3],
                      double r, double r2b, geom__hits *h)
{
    const kdnode *nd = &t->nodes[node];
    if (nd->count) {
        const double *p = t->pts + 3 * (size_t)nd->index;
        for (uint32_t i = 0; i < nd->count; i++, p += 3) {
            double d2 = geom__d2(p, q);
            if (d2 <= r2b && sqrt(d2) <= r)
                if (geom__hits_push(h, t->ids[nd->index + i], d2))
                    return -1;
        }
        return 0;
    }
    int ax = nd->axis;
    double diff = q[ax] - nd->split;
    size_t near = diff < 0 ? node + 1 : nd->index, far = diff < 0 ? nd->index : node + 1;
    if (radius_rec(t, near, q, off, r, r2b, h))
        return -1;
    double old = off[ax];
    off[ax] = diff;
    double rd = off[0] * off[0] + off[1] * off[1] + off[2] * off[2];
    int rc = 0;
    if (rd <= r2b)
        rc = radius_rec(t, far, q, off, r, r2b, h);
    off[ax] = old;
    return rc;
}

static geom_status radius_row(const void *ctx, size_t q, geom__hits *h)
{
    const rctx *c = ctx;
    double qq[3], off[3] = {0, 0, 0};
    geom__load_query(c->queries, q, c->t->dim, qq);
    size_t from = h->n;
    if (c->t->n && radius_rec(c->t, 0, qq, off, c->r, c->r2b, h))
        return GEOM_ERR_NOMEM;
    geom__hits_sort(h, from);
    return GEOM_OK;
}

geom_status geom_kdtree_radius(const geom_kdtree *t, const double *queries, size_t nq, double r,
                               geom_neighbors *out, int threads, geom_diag *diag)
{
    if (!t || !out || (nq && !queries))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0, "radius query: NULL argument");
    geom_status st0 = geom__radius_query_check(queries, nq, t->dim, r, diag);
    if (st0 != GEOM_OK)
        return st0;
    rctx c = {t, queries, r, geom__r2_bound(r), NULL, NULL};
    geom_status st = geom__batch_rows(t->has_alloc ? &t->alloc : NULL, nq, radius_row, &c, threads, 1, out);
    if (st != GEOM_OK)
        return geom__diag_set(diag, st, "", 0, 0, "radius query: out of memory");
    return GEOM_OK;
}

/* ------------------------------------------------------------------ box */

static int box_rec(const geom_kdtree *t, size_t node, const double lo[3], const double hi[3],
                   geom__hits *h)
{
    const kdnode *nd = &t->nodes[node];
    if (nd->count) {
        const double *p = t->pts + 3 * (size_t)nd->index;
        for (uint32_t i = 0; i < nd->count; i++, p += 3)
            if (p[0] >= lo[0] && p[0] <= hi[0] && p[1] >= lo[1] && p[1] <= hi[1] &&
                p[2] >= lo[2] && p[2] <= hi[2])
                if (geom__hits_push(h, t->ids[nd->index + i], 0.0))
                    return -1;
        return 0;
    }
    int ax = nd->axis;
    if (lo[ax] <= nd->split && box_rec(t, node + 1, lo, hi, h))
        return -1;
    if (hi[ax] >= nd->split && box_rec(t, nd->index, lo, hi, h))
        return -1;
    return 0;
}

static geom_status box_row(const void *ctx, size_t q, geom__hits *h)
{
    (void)q;
    const rctx *c = ctx;
    double lo[3] = {c->lo[0], c->lo[1], c->t->dim == 3 ? c->lo[2] : 0.0};
    double hi[3] = {c->hi[0], c->hi[1], c->t->dim == 3 ? c->hi[2] : 0.0};
    size_t from = h->n;
    if (c->t->n && box_rec(c->t, 0, lo, hi, h))
        return GEOM_ERR_NOMEM;
    geom__hits_sort(h, from); /* all d2 = 0: index order */
    return GEOM_OK;
}

geom_status geom_kdtree_box(const geom_kdtree *t, const double *lo, const double *hi,
                            geom_neighbors *out)
{
    if (!t || !lo || !hi || !out)
        return GEOM_ERR_INVALID_ARG;
    for (int k = 0; k < t->dim; k++)
        if (isnan(lo[k]) || isnan(hi[k]))
            return GEOM_ERR_INVALID_ARG;
    rctx c = {t, NULL, 0, 0, lo, hi};
    return geom__batch_rows(t->has_alloc ? &t->alloc : NULL, 1, box_row, &c, 1, 0, out);
}
