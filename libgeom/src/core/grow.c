/* The one growable-array step of the library: capacity doubling through the
 * optional allocator, with the size overflow checks. */
#include "core/internal.h"

#include <stdint.h>
#include <string.h>

geom_status geom__grow(const geom_allocator *a, void **p, size_t *cap, size_t need, size_t elem)
{
    if (need <= *cap)
        return GEOM_OK;
    size_t nc = *cap < 8 ? 8 : *cap;
    while (nc < need) {
        if (nc > SIZE_MAX / 2)
            return GEOM_ERR_LIMIT;
        nc *= 2;
    }
    size_t oldb, newb;
    if (geom__size_mul(nc, elem, &newb) != GEOM_OK || geom__size_mul(*cap, elem, &oldb) != GEOM_OK)
        return GEOM_ERR_LIMIT;
    /* a first allocation is an allocation (a user realloc_fn sees no old size) */
    void *q = *p ? geom__realloc(a, *p, oldb, newb) : geom__alloc(a, newb);
    if (!q)
        return GEOM_ERR_NOMEM;
    *p = q;
    *cap = nc;
    return GEOM_OK;
}

geom_status geom__push(const geom_allocator *a, void **p, size_t *n, size_t *cap, size_t elem,
                       const void *item)
{
    if (*n == SIZE_MAX)
        return GEOM_ERR_LIMIT;
    geom_status st = geom__grow(a, p, cap, *n + 1, elem);
    if (st != GEOM_OK)
        return st;
    memcpy((char *)*p + *n * elem, item, elem);
    (*n)++;
    return GEOM_OK;
}
