/*
 * Binned SAH BVH build (Wald, "On fast construction of SAH-based bounding
 * volume hierarchies", 2007): at each node the primitive centroids are binned
 * along each axis, the split minimising area(L)*|L| + area(R)*|R| over the
 * bin boundaries is taken, and the references are partitioned in place.
 * Subtrees are built as OpenMP tasks; every decision depends only on the
 * node's references (in a fixed order), so the tree does not depend on the
 * thread count. Centroids are (lo + hi), twice the box centre.
 *
 * Nodes of more than 4096 primitives are binned along their widest centroid
 * axis only, smaller ones along all three.
 *
 * A node with at most max_leaf_size primitives becomes a leaf; a larger node
 * whose centroids all coincide is split at its middle (the references keep
 * their input order); below depth 64 nodes are split at the median centroid
 * along their widest axis, so the depth stays below 64 + 32.
 */
#include "spatial/spatial_internal.h"

#include <stdlib.h>
#include <string.h>

#define MAX_BINS 64
#define SAH_DEPTH 64
#define TASK_MIN 4096
#define WIDE_ONLY 4096

typedef struct bin {
    double lo[3], hi[3];   /* box of the references */
    double clo[3], chi[3]; /* bounds of their centroids */
    uint32_t count;
} bin;

static void bin_clear(bin *b)
{
    for (int k = 0; k < 3; k++) {
        b->lo[k] = b->clo[k] = INFINITY;
        b->hi[k] = b->chi[k] = -INFINITY;
    }
    b->count = 0;
}

static inline void bin_merge_box(bin *a, const bin *b)
{
    for (int k = 0; k < 3; k++) {
        if (b->lo[k] < a->lo[k]) a->lo[k] = b->lo[k];
        if (b->hi[k] > a->hi[k]) a->hi[k] = b->hi[k];
    }
    a->count += b->count;
}

static double half_area(const double lo[3], const double hi[3])
{
    double dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
    return dx * dy + dy * dz + dz * dx;
}

static void set_box(geom__bvh_tmp *t, const bin *all)
{
    t->box.min = (geom_vec3){all->lo[0], all->lo[1], all->lo[2]};
    t->box.max = (geom_vec3){all->hi[0], all->hi[1], all->hi[2]};
}

static void summarize(const geom__bvh_ref *r, size_t n, bin *out)
{
    bin_clear(out);
    for (size_t i = 0; i < n; i++) {
        for (int k = 0; k < 3; k++) {
            double c = r[i].lo[k] + r[i].hi[k];
            if (r[i].lo[k] < out->lo[k]) out->lo[k] = r[i].lo[k];
            if (r[i].hi[k] > out->hi[k]) out->hi[k] = r[i].hi[k];
            if (c < out->clo[k]) out->clo[k] = c;
            if (c > out->chi[k]) out->chi[k] = c;
        }
    }
    out->count = (uint32_t)n;
}

typedef struct keyed {
    double c;
    uint32_t pos;
} keyed;

static int keyed_cmp(const void *pa, const void *pb)
{
    const keyed *a = pa, *b = pb;
    if (a->c < b->c) return -1;
    if (a->c > b->c) return 1;
    return (a->pos > b->pos) - (a->pos < b->pos);
}

/* Sort the references by centroid along axis (ties by current position);
 * returns 0 on success, -1 when out of memory (order left unchanged). */
static int sort_axis(const geom_allocator *a, geom__bvh_ref *r, size_t n, int axis)
{
    keyed *k = geom_alloc(a, n * sizeof *k);
    geom__bvh_ref *cp = geom_alloc(a, n * sizeof *cp);
    if (!k || !cp) {
        geom_free(a, k, n * sizeof *k);
        geom_free(a, cp, n * sizeof *cp);
        return -1;
    }
    for (size_t i = 0; i < n; i++) {
        k[i].c = r[i].lo[axis] + r[i].hi[axis];
        k[i].pos = (uint32_t)i;
    }
    qsort(k, n, sizeof *k, keyed_cmp);
    memcpy(cp, r, n * sizeof *cp);
    for (size_t i = 0; i < n; i++)
        r[i] = cp[k[i].pos];
    geom_free(a, k, n * sizeof *k);
    geom_free(a, cp, n * sizeof *cp);
    return 0;
}

/* Bin, choose the SAH split, partition. Returns the split axis (-1: none
 * found) with the left count and the children's summaries. Kept out of
 * build_node so that the bins are not on the stack during the recursion. */
static int sah_split(const geom__bvh_build *b, geom__bvh_ref *r, size_t n, const bin *all,
                     const double ext[3], size_t *nl_out, bin *lb, bin *rb)
{
    /* Fewer bins than references only wastes the sweeps. */
    uint32_t nb = b->bins < n ? b->bins : (uint32_t)n;
    if (nb < 2)
        nb = 2;
    bin bins[3][MAX_BINS];
    double scale[3];
    for (int k = 0; k < 3; k++) {
        scale[k] = ext[k] > 0 ? (double)nb * (1.0 - 1e-9) / ext[k] : 0.0;
        for (uint32_t j = 0; j < nb; j++)
            bin_clear(&bins[k][j]);
    }
    /* Large nodes are binned along their widest centroid axis only (where
     * the SAH split almost always lies; a third of the work), smaller ones
     * along all three. */
    int k0 = 0, k1 = 3;
    if (n > WIDE_ONLY) {
        int w = 0;
        if (ext[1] > ext[w]) w = 1;
        if (ext[2] > ext[w]) w = 2;
        k0 = w;
        k1 = w + 1;
    }
    for (size_t i = 0; i < n; i++) {
        for (int k = k0; k < k1; k++) {
            double ck = r[i].lo[k] + r[i].hi[k];
            int j = (int)((ck - all->clo[k]) * scale[k]);
            if (j >= (int)nb) j = (int)nb - 1;
            if (j < 0) j = 0;
            bin *bb = &bins[k][j];
            for (int q = 0; q < 3; q++) {
                if (r[i].lo[q] < bb->lo[q]) bb->lo[q] = r[i].lo[q];
                if (r[i].hi[q] > bb->hi[q]) bb->hi[q] = r[i].hi[q];
            }
            bb->count++;
        }
    }
    double best = INFINITY;
    int axis = -1;
    uint32_t split = 0;
    for (int k = k0; k < k1; k++) {
        if (!(ext[k] > 0))
            continue;
        double rcost[MAX_BINS];
        bin acc;
        bin_clear(&acc);
        for (uint32_t j = nb - 1; j > 0; j--) {
            bin_merge_box(&acc, &bins[k][j]);
            rcost[j] = acc.count ? half_area(acc.lo, acc.hi) * acc.count : 0.0;
        }
        bin_clear(&acc);
        for (uint32_t j = 0; j + 1 < nb; j++) {
            bin_merge_box(&acc, &bins[k][j]);
            if (acc.count == 0 || acc.count == n)
                continue;
            double cost = half_area(acc.lo, acc.hi) * acc.count + rcost[j + 1];
            if (cost < best) {
                best = cost;
                axis = k;
                split = j;
            }
        }
    }
    if (axis < 0)
        return -1;
    double lo = all->clo[axis], sc = scale[axis];
    size_t i = 0, j = n;
    bin_clear(lb);
    bin_clear(rb);
    /* In-place partition: left = bin index <= split. The expression is the
     * binning one, so each reference lands on the side its bin was counted
     * on. The children's centroid bounds are gathered on the way. */
    while (i < j) {
        double c = r[i].lo[axis] + r[i].hi[axis];
        int q = (int)((c - lo) * sc);
        if (q >= (int)nb) q = (int)nb - 1;
        if (q < 0) q = 0;
        bin *side;
        if ((uint32_t)q <= split) {
            side = lb;
        } else {
            j--;
            geom__bvh_ref tmp = r[i];
            r[i] = r[j];
            r[j] = tmp;
            side = rb;
        }
        const geom__bvh_ref *e = side == lb ? &r[i] : &r[j];
        for (int k = 0; k < 3; k++) {
            double ck = e->lo[k] + e->hi[k];
            if (ck < side->clo[k]) side->clo[k] = ck;
            if (ck > side->chi[k]) side->chi[k] = ck;
        }
        if (side == lb)
            i++;
    }
    *nl_out = i;
    for (uint32_t q = 0; q < nb; q++)
        bin_merge_box(q <= split ? lb : rb, &bins[axis][q]);
    return axis;
}

static uint32_t build_node(geom__bvh_build *b, size_t start, size_t n, const bin *all, int depth);

static void build_children(geom__bvh_build *b, geom__bvh_tmp *t, size_t start, size_t nl,
                           size_t n, const bin *lb, const bin *rb, int depth)
{
    uint32_t l = 0, r = 0;
    if (n >= TASK_MIN && b->threads > 1) {
#ifdef GEOM_SPATIAL_OPENMP
#pragma omp task shared(l) firstprivate(b, start, nl, lb, depth)
#endif
        l = build_node(b, start, nl, lb, depth + 1);
        r = build_node(b, start + nl, n - nl, rb, depth + 1);
#ifdef GEOM_SPATIAL_OPENMP
#pragma omp taskwait
#endif
    } else {
        l = build_node(b, start, nl, lb, depth + 1);
        r = build_node(b, start + nl, n - nl, rb, depth + 1);
    }
    t->left = l;
    t->right = r;
}

static uint32_t build_node(geom__bvh_build *b, size_t start, size_t n, const bin *all, int depth)
{
    uint32_t id = geom__bvh_tmp_new(b);
    geom__bvh_tmp *t = &b->tmp[id];
    geom__bvh_ref *r = b->refs + start;
    set_box(t, all);
    t->start = (uint32_t)start;
    t->count = (uint32_t)n;
    t->left = t->right = UINT32_MAX;
    t->axis = 0;
    t->pad = 0;
    if (n <= b->max_leaf)
        return id;

    /* Widest centroid axis. */
    int wide = 0;
    double ext[3];
    for (int k = 0; k < 3; k++)
        ext[k] = all->chi[k] - all->clo[k];
    if (ext[1] > ext[wide]) wide = 1;
    if (ext[2] > ext[wide]) wide = 2;

    size_t nl;
    int axis = wide;
    if (!(ext[wide] > 0) || depth >= SAH_DEPTH) {
        /* Coincident centroids: split in the middle of the current order;
         * too deep: median along the widest axis. */
        if (ext[wide] > 0)
            sort_axis(b->alloc, r, n, wide); /* on failure the middle split still terminates */
        nl = n / 2;
    } else {
        bin lb, rb;
        int ax = sah_split(b, r, n, all, ext, &nl, &lb, &rb);
        if (ax >= 0) {
            t->axis = (uint32_t)ax;
            build_children(b, t, start, nl, n, &lb, &rb, depth);
            return id;
        }
        nl = n / 2; /* cannot happen with ext > 0; kept for safety */
    }
    t->axis = (uint32_t)axis;
    bin lb, rb;
    summarize(r, nl, &lb);
    summarize(r + nl, n - nl, &rb);
    build_children(b, t, start, nl, n, &lb, &rb, depth);
    return id;
}

uint32_t geom__bvh_build_sah(geom__bvh_build *b)
{
    bin all;
    summarize(b->refs, b->n, &all);
    uint32_t root = 0;
#ifdef GEOM_SPATIAL_OPENMP
    if (b->threads > 1 && b->n >= TASK_MIN) {
#pragma omp parallel num_threads(b->threads)
#pragma omp single
        root = build_node(b, 0, b->n, &all, 0);
        return root;
    }
#endif
    root = build_node(b, 0, b->n, &all, 0);
    return root;
}
