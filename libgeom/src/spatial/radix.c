/* LSD radix sort of 64-bit keys carrying 32-bit values (stable), used by the
 * Morton-ordered builds (LBVH, quadtree/octree). */
#include "spatial/spatial_internal.h"

#include <string.h>

geom_status geom__radix_sort64(const geom_allocator *a, uint64_t *keys, uint32_t *vals, size_t n)
{
    if (n < 2)
        return GEOM_OK;
    uint64_t *k2 = geom__alloc(a, n * sizeof *k2);
    uint32_t *v2 = geom__alloc(a, n * sizeof *v2);
    if (!k2 || !v2) {
        geom__free(a, k2, n * sizeof *k2);
        geom__free(a, v2, n * sizeof *v2);
        return GEOM_ERR_NOMEM;
    }
    /* Skip the 16-bit digits in which all keys agree. */
    uint64_t all_or = 0, all_and = ~(uint64_t)0;
    for (size_t i = 0; i < n; i++) {
        all_or |= keys[i];
        all_and &= keys[i];
    }
    uint64_t differ = all_or ^ all_and;
    uint64_t *src_k = keys, *dst_k = k2;
    uint32_t *src_v = vals, *dst_v = v2;
    static const size_t radix = 1u << 16;
    size_t *count = geom__alloc(a, radix * sizeof *count);
    if (!count) {
        geom__free(a, k2, n * sizeof *k2);
        geom__free(a, v2, n * sizeof *v2);
        return GEOM_ERR_NOMEM;
    }
    for (int shift = 0; shift < 64; shift += 16) {
        if (((differ >> shift) & 0xffff) == 0)
            continue;
        memset(count, 0, radix * sizeof *count);
        for (size_t i = 0; i < n; i++)
            count[(src_k[i] >> shift) & 0xffff]++;
        size_t sum = 0;
        for (size_t d = 0; d < radix; d++) {
            size_t c = count[d];
            count[d] = sum;
            sum += c;
        }
        for (size_t i = 0; i < n; i++) {
            size_t p = count[(src_k[i] >> shift) & 0xffff]++;
            dst_k[p] = src_k[i];
            dst_v[p] = src_v[i];
        }
        uint64_t *tk = src_k;
        src_k = dst_k;
        dst_k = tk;
        uint32_t *tv = src_v;
        src_v = dst_v;
        dst_v = tv;
    }
    if (src_k != keys) {
        memcpy(keys, src_k, n * sizeof *keys);
        memcpy(vals, src_v, n * sizeof *vals);
    }
    geom__free(a, count, radix * sizeof *count);
    geom__free(a, k2, n * sizeof *k2);
    geom__free(a, v2, n * sizeof *v2);
    return GEOM_OK;
}
