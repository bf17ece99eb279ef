/* The one hash of the library: a 64-bit mixer (splitmix64's finaliser,
 * Steele, Lea and Flood 2014) and an open-addressing index (linear probing,
 * load <= 1/2) of uint32 ids keyed by a caller-computed 64-bit hash. The
 * index stores the hash's high half with each id, so most mismatches are
 * rejected without touching the caller's data. */
#include "core/internal.h"

#include <string.h>

uint64_t geom__hash_mix(uint64_t h, uint64_t v)
{
    uint64_t z = h ^ (v + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2));
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

uint64_t geom__hash_doubles(const double *v, size_t n)
{
    uint64_t h = 0x9e3779b97f4a7c15ull;
    for (size_t i = 0; i < n; i++) {
        double x = v[i] == 0.0 ? 0.0 : v[i]; /* -0 and 0 hash alike */
        uint64_t b;
        memcpy(&b, &x, sizeof b);
        h = geom__hash_mix(h, b);
    }
    return h;
}

/* the start slot depends only on the stored high half of the hash */
static size_t start_slot(uint64_t hi, size_t cap)
{
    return (size_t)((hi * 0x9e3779b97f4a7c15ull) >> 20) & (cap - 1);
}

static void put(uint64_t *slot, size_t cap, uint64_t e)
{
    size_t mask = cap - 1, i = start_slot(e >> 32, cap);
    while (slot[i])
        i = (i + 1) & mask;
    slot[i] = e;
}

geom_status geom__hindex_reserve(geom__hindex *h, const geom_allocator *a, size_t n)
{
    if (n <= h->cap / 2 && h->cap)
        return GEOM_OK;
    size_t cap = h->cap ? h->cap : 64;
    while (cap / 2 < n) {
        if (cap > SIZE_MAX / 4)
            return GEOM_ERR_LIMIT;
        cap *= 2;
    }
    size_t bytes;
    if (geom__size_mul(cap, sizeof(uint64_t), &bytes) != GEOM_OK)
        return GEOM_ERR_LIMIT;
    uint64_t *s = geom__alloc(a, bytes);
    if (!s)
        return GEOM_ERR_NOMEM;
    memset(s, 0, bytes);
    for (size_t i = 0; i < h->cap; i++)
        if (h->slot[i])
            put(s, cap, h->slot[i]);
    geom__free(a, h->slot, h->cap * sizeof(uint64_t));
    h->slot = s;
    h->cap = cap;
    return GEOM_OK;
}

uint32_t geom__hindex_next(const geom__hindex *h, uint64_t hash, size_t *it)
{
    if (!h->cap)
        return UINT32_MAX;
    size_t mask = h->cap - 1;
    uint64_t hi = hash >> 32;
    /* *it counts the probes already made; the slot is start + *it */
    size_t i = (start_slot(hi, h->cap) + *it) & mask;
    for (;;) {
        uint64_t e = h->slot[i];
        if (!e)
            return UINT32_MAX;
        (*it)++;
        i = (i + 1) & mask;
        if ((e >> 32) == hi)
            return (uint32_t)((e & 0xffffffffu) - 1);
    }
}

void geom__hindex_insert_at(geom__hindex *h, uint64_t hash, size_t it, uint32_t id)
{
    size_t mask = h->cap - 1;
    size_t i = (start_slot(hash >> 32, h->cap) + it) & mask;
    while (h->slot[i]) /* the probe stopped at a free slot; stay safe anyway */
        i = (i + 1) & mask;
    h->slot[i] = ((hash >> 32) << 32) | ((uint64_t)id + 1);
    h->n++;
}

void geom__hindex_free(geom__hindex *h, const geom_allocator *a)
{
    geom__free(a, h->slot, h->cap * sizeof(uint64_t));
    h->slot = NULL;
    h->cap = h->n = 0;
}
