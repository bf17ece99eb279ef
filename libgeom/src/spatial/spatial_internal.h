/* Private to the spatial module. */
#ifndef GEOM_SRC_SPATIAL_INTERNAL_H
#define GEOM_SRC_SPATIAL_INTERNAL_H

#include "core/internal.h"
#include "geom/spatial.h"

#include <stdint.h>

#ifdef GEOM_SPATIAL_OPENMP
#include <omp.h>
#endif

/* Thread count for a parallel region: 0 = all available. */
static inline int geom__spatial_threads(int threads)
{
#ifdef GEOM_SPATIAL_OPENMP
    return threads > 0 ? threads : omp_get_max_threads();
#else
    (void)threads;
    return 1;
#endif
}

/* A primitive reference during a BVH build: its box and its index. */
typedef struct geom__bvh_ref {
    double lo[3], hi[3];
    uint32_t id;
    uint32_t pad;
} geom__bvh_ref;

/* Temporary binary node of a build (before the depth-first flattening). */
typedef struct geom__bvh_tmp {
    geom_aabb box;
    uint32_t left, right; /* temp node ids; leaf: UINT32_MAX */
    uint32_t start, count;
    uint32_t axis;
    uint32_t pad;
} geom__bvh_tmp;

typedef struct geom__bvh_build {
    geom__bvh_ref *refs;
    size_t n;
    geom__bvh_tmp *tmp; /* capacity 2n */
    size_t tmp_count;   /* atomically incremented */
    uint32_t max_leaf;
    uint32_t bins;
    int threads;
    const geom_allocator *alloc;
} geom__bvh_build;

struct geom_bvh {
    geom_allocator alloc;
    int has_alloc;
    geom_bvh_node *nodes;
    size_t node_count;
    uint32_t *prims;
    size_t prim_count;
    size_t depth;
};

/* Take a temp node slot (thread safe). */
uint32_t geom__bvh_tmp_new(geom__bvh_build *b);
/* Builders: fill b->tmp, return the root's temp id. */
uint32_t geom__bvh_build_sah(geom__bvh_build *b);
uint32_t geom__bvh_build_lbvh(geom__bvh_build *b);

/* Morton codes: 21 bits per axis interleaved (x lowest), and 2D with 32 bits. */
static inline uint64_t geom__morton_spread3(uint64_t v)
{
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffULL;
    v = (v | v << 16) & 0x1f0000ff0000ffULL;
    v = (v | v << 8) & 0x100f00f00f00f00fULL;
    v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
    v = (v | v << 2) & 0x1249249249249249ULL;
    return v;
}
static inline uint64_t geom__morton3(uint32_t x, uint32_t y, uint32_t z)
{
    return geom__morton_spread3(x) | geom__morton_spread3(y) << 1 | geom__morton_spread3(z) << 2;
}
static inline uint64_t geom__morton_spread2(uint64_t v)
{
    v &= 0xffffffffULL;
    v = (v | v << 16) & 0x0000ffff0000ffffULL;
    v = (v | v << 8) & 0x00ff00ff00ff00ffULL;
    v = (v | v << 4) & 0x0f0f0f0f0f0f0f0fULL;
    v = (v | v << 2) & 0x3333333333333333ULL;
    v = (v | v << 1) & 0x5555555555555555ULL;
    return v;
}

/* Sort (key, value) pairs by key then value (LSD radix sort, stable, so with
 * values given in increasing order the order is fully determined). keys and
 * vals are n entries; tmp space of the same size is allocated. */
geom_status geom__radix_sort64(const geom_allocator *a, uint64_t *keys, uint32_t *vals, size_t n);

#endif
