/* Allocation through the optional geom_allocator. */
#if defined(__linux__) && !defined(_DEFAULT_SOURCE)
#define _DEFAULT_SOURCE /* madvise */
#endif
#include "core/internal.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#if defined(__linux__)
#include <sys/mman.h>
#endif

void *geom__alloc(const geom_allocator *a, size_t size)
{
    if (size == 0)
        size = 1;
    if (a && a->alloc_fn)
        return a->alloc_fn(a->user, size);
    return malloc(size);
}

void *geom__realloc(const geom_allocator *a, void *ptr, size_t old_size, size_t new_size)
{
    if (new_size == 0)
        new_size = 1;
    if (old_size == 0)
        old_size = 1;
    if (!a || !a->alloc_fn)
        return realloc(ptr, new_size);
    if (a->realloc_fn)
        return a->realloc_fn(a->user, ptr, old_size, new_size);
    void *q = a->alloc_fn(a->user, new_size);
    if (!q)
        return NULL;
    if (ptr) {
        memcpy(q, ptr, old_size < new_size ? old_size : new_size);
        if (a->free_fn)
            a->free_fn(a->user, ptr, old_size);
    }
    return q;
}

void geom__free(const geom_allocator *a, void *ptr, size_t size)
{
    if (!ptr)
        return;
    if (size == 0) /* geom__alloc turned a 0-byte request into 1 byte */
        size = 1;
    if (a && a->alloc_fn) {
        if (a->free_fn)
            a->free_fn(a->user, ptr, size);
        return;
    }
    free(ptr);
}

geom_status geom__size_mul(size_t n, size_t size, size_t *out)
{
    if (size && n > SIZE_MAX / size)
        return GEOM_ERR_LIMIT;
    *out = n * size;
    return GEOM_OK;
}

void geom__advise_huge(const geom_allocator *a, void *p, size_t bytes, size_t min_bytes)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (a || !p || bytes < min_bytes)
        return;
    uintptr_t lo = ((uintptr_t)p + 4095) & ~(uintptr_t)4095;
    uintptr_t hi = ((uintptr_t)p + bytes) & ~(uintptr_t)4095;
    if (hi > lo)
        (void)madvise((void *)lo, hi - lo, MADV_HUGEPAGE);
#else
    (void)a, (void)p, (void)bytes, (void)min_bytes;
#endif
}
