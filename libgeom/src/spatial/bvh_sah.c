/*
 * Binned SAH BVH build (Wald, "On fast construction of SAH-based bounding
 * volume hierarchies", 2007): at each node the primitive centroids are binned
 * along each axis, the split minimising area(L)*|L| + area(R)*|R| over the
 * bin boundaries is taken, and the references are partitioned in place.
 * Subtrees are built as OpenMP tasks; every decision depends only on the
 * node's references (in a fixed order), so the tree does not depend on the
 * thread count. Centroids are (lo + hi), twice the box centre.
 *
 * The decisions are taken on a compact single-precision copy of the
 * primitive boxes (32 bytes a reference, relative to the centre of the scene
 * and scaled by its extent, so that a 1e8 offset costs no precision); the
 * node boxes are then recomputed exactly, in double, as unions of the
 * primitive boxes. Rounding only moves where a split falls, never a box.
 *
 * Nodes of more than 4096 primitives are binned along their widest centroid
 * axis only, smaller ones along all three.
 *
 * A node with at most max_leaf_size primitives becomes a leaf; a larger node
 * whose (single-precision) centroids all coincide is split at its middle (the
 * references keep their input order); below depth 64 nodes are split at the
 * median centroid along their widest axis, so the depth stays below 64 + 32.
 */
#include "spatial/spatial_internal.h"

#include <stdlib.h>
#include <string.h>
#ifdef __SSE2__
#include <emmintrin.h>
#elif defined(__SSE__)
#include <xmmintrin.h>
#endif

#define MAX_BINS 256
#define SAH_DEPTH 64
#define TASK_MIN 4096
#define WIDE_ONLY 4096

/* A reference: lanes 0..2 are x, y, z; lane 3 is unused (0). */
typedef struct fref {
    float lo[4], hi[4];
} fref;

typedef struct bin {
    float lo[4], hi[4];   /* box of the references */
    float clo[4], chi[4]; /* bounds of their centroids */
    uint32_t count;
} bin;

typedef struct sctx {
    geom__bvh_build *b;
    fref *r;       /* n references, permuted with ids */
    uint32_t *ids; /* primitive index of each reference */
} sctx;

static void bin_clear(bin *b)
{
    for (int k = 0; k < 4; k++) {
        b->lo[k] = b->clo[k] = INFINITY;
        b->hi[k] = b->chi[k] = -INFINITY;
    }
    b->count = 0;
}

static inline void bin_merge_box(bin *a, const bin *b)
{
    for (int k = 0; k < 4; k++) {
        a->lo[k] = b->lo[k] < a->lo[k] ? b->lo[k] : a->lo[k];
        a->hi[k] = b->hi[k] > a->hi[k] ? b->hi[k] : a->hi[k];
    }
    a->count += b->count;
}

static inline void bin_add(bin *bb, const fref *r)
{
#ifdef __SSE__
    /* The same min/max, four lanes at once (lane 3 is 0 in every reference). */
    _mm_storeu_ps(bb->lo, _mm_min_ps(_mm_loadu_ps(r->lo), _mm_loadu_ps(bb->lo)));
    _mm_storeu_ps(bb->hi, _mm_max_ps(_mm_loadu_ps(r->hi), _mm_loadu_ps(bb->hi)));
#else
    for (int q = 0; q < 4; q++) {
        bb->lo[q] = r->lo[q] < bb->lo[q] ? r->lo[q] : bb->lo[q];
        bb->hi[q] = r->hi[q] > bb->hi[q] ? r->hi[q] : bb->hi[q];
    }
#endif
    bb->count++;
}

static inline void centroid_add(bin *bb, const fref *r)
{
#ifdef __SSE__
    __m128 c = _mm_add_ps(_mm_loadu_ps(r->lo), _mm_loadu_ps(r->hi));
    _mm_storeu_ps(bb->clo, _mm_min_ps(c, _mm_loadu_ps(bb->clo)));
    _mm_storeu_ps(bb->chi, _mm_max_ps(c, _mm_loadu_ps(bb->chi)));
#else
    for (int q = 0; q < 4; q++) {
        float c = r->lo[q] + r->hi[q];
        bb->clo[q] = c < bb->clo[q] ? c : bb->clo[q];
        bb->chi[q] = c > bb->chi[q] ? c : bb->chi[q];
    }
#endif
}

static float half_area(const float lo[4], const float hi[4])
{
    float dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
    return dx * dy + dy * dz + dz * dx;
}

static void summarize(const fref *r, size_t n, bin *out)
{
    bin_clear(out);
    for (size_t i = 0; i < n; i++) {
        bin_add(out, &r[i]);
        centroid_add(out, &r[i]);
    }
    out->count = (uint32_t)n;
}

typedef struct keyed {
    float c;
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
static int sort_axis(const geom_allocator *a, fref *r, uint32_t *ids, size_t n, int axis)
{
    keyed *k = geom__alloc(a, n * sizeof *k);
    fref *cp = geom__alloc(a, n * sizeof *cp);
    uint32_t *ci = geom__alloc(a, n * sizeof *ci);
    int ok = k && cp && ci;
    if (ok) {
        for (size_t i = 0; i < n; i++) {
            k[i].c = r[i].lo[axis] + r[i].hi[axis];
            k[i].pos = (uint32_t)i;
        }
        qsort(k, n, sizeof *k, keyed_cmp);
        memcpy(cp, r, n * sizeof *cp);
        memcpy(ci, ids, n * sizeof *ci);
        for (size_t i = 0; i < n; i++) {
            r[i] = cp[k[i].pos];
            ids[i] = ci[k[i].pos];
        }
    }
    geom__free(a, k, n * sizeof *k);
    geom__free(a, cp, n * sizeof *cp);
    geom__free(a, ci, n * sizeof *ci);
    return ok ? 0 : -1;
}

static inline int bin_of(float c, float lo, float sc, int nb)
{
    float f = (c - lo) * sc;
    return f < (float)nb ? (f > 0.0f ? (int)f : 0) : nb - 1;
}

/* Bin, choose the SAH split, partition. Returns the split axis (-1: none
 * found) with the left count and the children's summaries. Kept out of
 * build_node so that the bins are not on the stack during the recursion. */
static int sah_split(const sctx *s, fref *r, uint32_t *ids, size_t n, const bin *all,
                     const float ext[3], size_t *nl_out, bin *lb, bin *rb)
{
    const geom__bvh_build *b = s->b;
    /* Fewer bins than references only wastes the sweeps. */
    uint32_t nb = b->bins < n ? b->bins : (uint32_t)n;
    if (nb < 2)
        nb = 2;
    bin bins[3][MAX_BINS];
    float scale[3];
    int k0 = 0, k1 = 3;
    /* Large nodes are binned along their widest centroid axis only (where
     * the SAH split almost always lies; a third of the work), smaller ones
     * along all three. */
    if (n > WIDE_ONLY) {
        int w = 0;
        if (ext[1] > ext[w]) w = 1;
        if (ext[2] > ext[w]) w = 2;
        k0 = w;
        k1 = w + 1;
    }
    for (int k = 0; k < 3; k++) {
        scale[k] = ext[k] > 0 ? (float)((double)nb * (1.0 - 1e-6) / (double)ext[k]) : 0.0f;
        if (!(scale[k] < INFINITY))
            scale[k] = 0.0f;
    }
    for (int k = k0; k < k1; k++)
        for (uint32_t j = 0; j < nb; j++)
            bin_clear(&bins[k][j]);
    if (k1 - k0 == 3) {
#ifdef __SSE2__
        /* bin_of on the three axes at once: the same float operations and
         * the same clamping, so the indices agree with the partition's. */
        const __m128 vlo = _mm_setr_ps(all->clo[0], all->clo[1], all->clo[2], 0.0f);
        const __m128 vsc = _mm_setr_ps(scale[0], scale[1], scale[2], 0.0f);
        const __m128 vtop = _mm_set1_ps((float)nb);
        const __m128i vlast = _mm_set1_epi32((int)nb - 1);
        for (size_t i = 0; i < n; i++) {
            const fref *e = &r[i];
            __m128 f = _mm_mul_ps(_mm_sub_ps(_mm_add_ps(_mm_loadu_ps(e->lo), _mm_loadu_ps(e->hi)), vlo), vsc);
            __m128 pos = _mm_max_ps(f, _mm_setzero_ps()); /* f > 0 ? f : 0 */
            __m128i q = _mm_cvttps_epi32(pos);
            __m128i below = _mm_castps_si128(_mm_cmplt_ps(f, vtop));
            q = _mm_or_si128(_mm_and_si128(below, q), _mm_andnot_si128(below, vlast));
            int qi[4];
            _mm_storeu_si128((__m128i *)(void *)qi, q);
            bin_add(&bins[0][qi[0]], e);
            bin_add(&bins[1][qi[1]], e);
            bin_add(&bins[2][qi[2]], e);
        }
#else
        for (size_t i = 0; i < n; i++) {
            const fref *e = &r[i];
            bin_add(&bins[0][bin_of(e->lo[0] + e->hi[0], all->clo[0], scale[0], (int)nb)], e);
            bin_add(&bins[1][bin_of(e->lo[1] + e->hi[1], all->clo[1], scale[1], (int)nb)], e);
            bin_add(&bins[2][bin_of(e->lo[2] + e->hi[2], all->clo[2], scale[2], (int)nb)], e);
        }
#endif
    } else {
        int k = k0;
        float lo = all->clo[k], sc = scale[k];
        for (size_t i = 0; i < n; i++)
            bin_add(&bins[k][bin_of(r[i].lo[k] + r[i].hi[k], lo, sc, (int)nb)], &r[i]);
    }
    float best = INFINITY;
    int axis = -1;
    uint32_t split = 0;
    for (int k = k0; k < k1; k++) {
        if (!(ext[k] > 0))
            continue;
        float rcost[MAX_BINS];
        bin acc;
        bin_clear(&acc);
        for (uint32_t j = nb - 1; j > 0; j--) {
            bin_merge_box(&acc, &bins[k][j]);
            rcost[j] = acc.count ? half_area(acc.lo, acc.hi) * (float)acc.count : 0.0f;
        }
        bin_clear(&acc);
        for (uint32_t j = 0; j + 1 < nb; j++) {
            bin_merge_box(&acc, &bins[k][j]);
            if (acc.count == 0 || acc.count == n)
                continue;
            float cost = half_area(acc.lo, acc.hi) * (float)acc.count + rcost[j + 1];
            if (cost < best) {
                best = cost;
                axis = k;
                split = j;
            }
        }
    }
    if (axis < 0)
        return -1;
    float lo = all->clo[axis], sc = scale[axis];
    size_t i = 0, j = n;
    bin_clear(lb);
    bin_clear(rb);
    /* In-place partition: left = bin index <= split. The expression is the
     * binning one, so each reference lands on the side its bin was counted
     * on. The children's centroid bounds are gathered on the way. */
    while (i < j) {
        if ((uint32_t)bin_of(r[i].lo[axis] + r[i].hi[axis], lo, sc, (int)nb) <= split) {
            centroid_add(lb, &r[i]);
            i++;
        } else {
            j--;
            fref tmp = r[i];
            r[i] = r[j];
            r[j] = tmp;
            uint32_t t = ids[i];
            ids[i] = ids[j];
            ids[j] = t;
            centroid_add(rb, &r[j]);
        }
    }
    *nl_out = i;
    for (uint32_t q = 0; q < nb; q++)
        bin_merge_box(q <= split ? lb : rb, &bins[axis][q]);
    return axis;
}

static uint32_t build_node(const sctx *s, size_t start, size_t n, const bin *all, int depth);

static void build_children(const sctx *s, geom__bvh_tmp *t, size_t start, size_t nl, size_t n,
                           const bin *lb, const bin *rb, int depth)
{
    uint32_t l = 0, r = 0;
    if (n >= TASK_MIN && s->b->threads > 1) {
#ifdef GEOM_SPATIAL_OPENMP
#pragma omp task shared(l) firstprivate(s, start, nl, lb, depth)
#endif
        l = build_node(s, start, nl, lb, depth + 1);
        r = build_node(s, start + nl, n - nl, rb, depth + 1);
#ifdef GEOM_SPATIAL_OPENMP
#pragma omp taskwait
#endif
    } else {
        l = build_node(s, start, nl, lb, depth + 1);
        r = build_node(s, start + nl, n - nl, rb, depth + 1);
    }
    t->left = l;
    t->right = r;
}

static uint32_t build_node(const sctx *s, size_t start, size_t n, const bin *all, int depth)
{
    geom__bvh_build *b = s->b;
    uint32_t id = geom__bvh_tmp_new(b);
    geom__bvh_tmp *t = &b->tmp[id];
    fref *r = s->r + start;
    uint32_t *ids = s->ids + start;
    t->start = (uint32_t)start;
    t->count = (uint32_t)n;
    t->left = t->right = UINT32_MAX;
    t->axis = 0;
    t->pad = 0;
    if (n <= b->max_leaf)
        return id;

    /* Widest centroid axis. */
    int wide = 0;
    float ext[3];
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
            sort_axis(b->alloc, r, ids, n, wide); /* on failure the middle split still terminates */
        nl = n / 2;
    } else {
        bin lb, rb;
        int ax = sah_split(s, r, ids, n, all, ext, &nl, &lb, &rb);
        if (ax >= 0) {
            t->axis = (uint32_t)ax;
            build_children(s, t, start, nl, n, &lb, &rb, depth);
            return id;
        }
        nl = n / 2; /* cannot happen with ext > 0; kept for safety */
    }
    t->axis = (uint32_t)axis;
    bin lb, rb;
    summarize(r, nl, &lb);
    summarize(r + nl, n - nl, &rb);
    build_children(s, t, start, nl, n, &lb, &rb, depth);
    return id;
}

static inline float to_float(double v, double o, double inv)
{
    double x = (v - o) * inv;
    return (float)(x > 1e30 ? 1e30 : x < -1e30 ? -1e30 : x);
}

uint32_t geom__bvh_build_sah(geom__bvh_build *b)
{
    size_t n = b->n;
    const geom_allocator *a = b->alloc;
    fref *fr = geom__alloc(a, n * sizeof *fr);
    uint32_t *ids = geom__alloc(a, n * sizeof *ids);
    geom__advise_huge(a, fr, n * sizeof *fr, GEOM__BVH_HUGE_MIN);
    if (!fr || !ids) {
        geom__free(a, fr, n * sizeof *fr);
        geom__free(a, ids, n * sizeof *ids);
        return UINT32_MAX;
    }
    /* Centre and extent of the scene for the float copy. */
    const double *lo = b->scene_lo, *hi = b->scene_hi;
    double o[3], ext = 0;
    for (int k = 0; k < 3; k++) {
        o[k] = 0.5 * lo[k] + 0.5 * hi[k];
        double e = hi[k] - lo[k];
        if (e > ext) ext = e;
    }
    double inv = ext > 0 && ext < INFINITY ? 1.0 / ext : 1.0;
    ptrdiff_t nn = (ptrdiff_t)n;
#ifdef GEOM_SPATIAL_OPENMP
#pragma omp parallel for schedule(static) num_threads(b->threads) if (n > 65536)
#endif
    for (ptrdiff_t i = 0; i < nn; i++) {
        geom__bvh_ref r;
        b->box_fn(b->src, (size_t)i, &r);
        for (int k = 0; k < 3; k++) {
            fr[i].lo[k] = to_float(r.lo[k], o[k], inv);
            fr[i].hi[k] = to_float(r.hi[k], o[k], inv);
        }
        fr[i].lo[3] = fr[i].hi[3] = 0.0f;
        ids[i] = (uint32_t)i;
    }
    sctx s = {b, fr, ids};
    bin all;
    summarize(fr, n, &all);
    uint32_t root = 0;
#ifdef GEOM_SPATIAL_OPENMP
    if (b->threads > 1 && n >= TASK_MIN) {
#pragma omp parallel num_threads(b->threads)
#pragma omp single
        root = build_node(&s, 0, n, &all, 0);
    } else
#endif
    {
        root = build_node(&s, 0, n, &all, 0);
    }
    geom__free(a, fr, n * sizeof *fr);
    b->preorder = !(b->threads > 1 && n >= TASK_MIN);
    /* Exact boxes, bottom-up: a node's id is taken before its children's
     * (whatever the threads), so a reverse sweep sees children first. */
    for (size_t j = b->tmp_count; j-- > 0;) {
        geom__bvh_tmp *t = &b->tmp[j];
        geom_aabb box;
        if (t->left == UINT32_MAX) {
            double l[3] = {INFINITY, INFINITY, INFINITY}, h[3] = {-INFINITY, -INFINITY, -INFINITY};
            for (uint32_t i = 0; i < t->count; i++) {
                geom__bvh_ref r;
                b->box_fn(b->src, ids[t->start + i], &r);
                for (int k = 0; k < 3; k++) {
                    if (r.lo[k] < l[k]) l[k] = r.lo[k];
                    if (r.hi[k] > h[k]) h[k] = r.hi[k];
                }
            }
            box.min = (geom_vec3){l[0], l[1], l[2]};
            box.max = (geom_vec3){h[0], h[1], h[2]};
        } else {
            box = geom_aabb_union(b->tmp[t->left].box, b->tmp[t->right].box);
        }
        t->box = box;
    }
    b->order = ids;
    return root;
}
