/*
 * Linear BVH (Lauterbach et al., "Fast BVH construction on GPUs", 2009):
 * primitives sorted along the Morton curve of their centroids (21 bits per
 * axis over the centroid bounds, ties by index), then split top-down at the
 * highest bit in which a range's first and last codes differ (a binary
 * search, as in Karras 2012). A range whose codes all agree is split in the
 * middle. Boxes are the unions of the primitive boxes, bottom-up. The depth
 * is at most 63 + 32.
 */
#include "spatial/spatial_internal.h"

#include <string.h>

#define TASK_MIN 4096

typedef struct lctx {
    geom__bvh_build *b;
    const uint64_t *codes;
} lctx;

static geom_aabb ref_aabb(const geom__bvh_ref *r)
{
    geom_aabb x = {{r->lo[0], r->lo[1], r->lo[2]}, {r->hi[0], r->hi[1], r->hi[2]}};
    return x;
}

static uint32_t lnode(const lctx *c, size_t start, size_t n)
{
    geom__bvh_build *b = c->b;
    uint32_t id = geom__bvh_tmp_new(b);
    geom__bvh_tmp *t = &b->tmp[id];
    t->start = (uint32_t)start;
    t->count = (uint32_t)n;
    t->left = t->right = UINT32_MAX;
    t->axis = 0;
    t->pad = 0;
    if (n <= b->max_leaf) {
        geom_aabb box = geom_aabb_empty();
        for (size_t i = 0; i < n; i++)
            box = geom_aabb_union(box, ref_aabb(&b->refs[start + i]));
        t->box = box;
        return id;
    }
    const uint64_t *k = c->codes + start;
    uint64_t x = k[0] ^ k[n - 1];
    size_t nl;
    if (x == 0) {
        nl = n / 2;
    } else {
        int bit = 63;
        while (!((x >> bit) & 1))
            bit--;
        /* First position with the bit set: the codes agree above it. */
        size_t lo = 0, hi = n - 1;
        while (lo < hi) {
            size_t mid = lo + (hi - lo) / 2;
            if ((k[mid] >> bit) & 1)
                hi = mid;
            else
                lo = mid + 1;
        }
        nl = lo;
        t->axis = (uint32_t)(bit % 3);
    }
    uint32_t l = 0, r = 0;
    if (n >= TASK_MIN && b->threads > 1) {
#ifdef GEOM_SPATIAL_OPENMP
#pragma omp task shared(l) firstprivate(c, start, nl)
#endif
        l = lnode(c, start, nl);
        r = lnode(c, start + nl, n - nl);
#ifdef GEOM_SPATIAL_OPENMP
#pragma omp taskwait
#endif
    } else {
        l = lnode(c, start, nl);
        r = lnode(c, start + nl, n - nl);
    }
    t->left = l;
    t->right = r;
    t->box = geom_aabb_union(b->tmp[l].box, b->tmp[r].box);
    t->count = 0;
    return id;
}

uint32_t geom__bvh_build_lbvh(geom__bvh_build *b)
{
    size_t n = b->n;
    const geom_allocator *a = b->alloc;
    double clo[3] = {INFINITY, INFINITY, INFINITY}, chi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) {
            double c = b->refs[i].lo[k] + b->refs[i].hi[k];
            if (c < clo[k]) clo[k] = c;
            if (c > chi[k]) chi[k] = c;
        }
    double scale[3];
    for (int k = 0; k < 3; k++)
        scale[k] = chi[k] > clo[k] ? 2097151.0 / (chi[k] - clo[k]) : 0.0;
    uint64_t *codes = geom__alloc(a, n * sizeof *codes);
    uint32_t *perm = geom__alloc(a, n * sizeof *perm);
    geom__bvh_ref *cp = geom__alloc(a, n * sizeof *cp);
    geom__advise_huge(a, codes, n * sizeof *codes, GEOM__BVH_HUGE_MIN);
    geom__advise_huge(a, cp, n * sizeof *cp, GEOM__BVH_HUGE_MIN);
    uint32_t root = UINT32_MAX;
    if (!codes || !perm || !cp)
        goto done;
    {
        const geom__bvh_ref *refs = b->refs;
        ptrdiff_t nn = (ptrdiff_t)n;
#ifdef GEOM_SPATIAL_OPENMP
#pragma omp parallel for schedule(static) num_threads(b->threads) if (n > 65536)
#endif
        for (ptrdiff_t i = 0; i < nn; i++) {
            uint32_t q[3];
            for (int k = 0; k < 3; k++) {
                double c = refs[i].lo[k] + refs[i].hi[k];
                double v = (c - clo[k]) * scale[k];
                q[k] = v >= 2097151.0 ? 2097151u : v > 0 ? (uint32_t)v : 0u;
            }
            codes[i] = geom__morton3(q[0], q[1], q[2]);
            perm[i] = (uint32_t)i;
        }
    }
    if (geom__radix_sort64(a, codes, perm, n) != GEOM_OK)
        goto done;
    memcpy(cp, b->refs, n * sizeof *cp);
    for (size_t i = 0; i < n; i++)
        b->refs[i] = cp[perm[i]];
    lctx c = {b, codes};
#ifdef GEOM_SPATIAL_OPENMP
    if (b->threads > 1 && n >= TASK_MIN) {
#pragma omp parallel num_threads(b->threads)
#pragma omp single
        root = lnode(&c, 0, n);
        goto done;
    }
#endif
    root = lnode(&c, 0, n);
    b->preorder = 1;
done:
    geom__free(a, codes, n * sizeof *codes);
    geom__free(a, perm, n * sizeof *perm);
    geom__free(a, cp, n * sizeof *cp);
    return root;
}
