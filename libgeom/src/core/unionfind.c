/* The one union-find of the library (Tarjan 1975; path halving, Tarjan and
 * van Leeuwen 1984) over a caller's uint32 parent array. The root of a set is
 * its smallest member, so labels come out in a deterministic order. */
#include "core/internal.h"

void geom__uf_init(uint32_t *parent, size_t n)
{
    for (size_t i = 0; i < n; i++)
        parent[i] = (uint32_t)i;
}

uint32_t geom__uf_find(uint32_t *parent, uint32_t x)
{
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

uint32_t geom__uf_union(uint32_t *parent, uint32_t a, uint32_t b)
{
    a = geom__uf_find(parent, a);
    b = geom__uf_find(parent, b);
    if (a < b) {
        parent[b] = a;
        return a;
    }
    parent[a] = b;
    return b;
}
