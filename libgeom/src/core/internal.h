/* Private helpers shared by libgeom's sources. Not installed. */
#ifndef GEOM_SRC_CORE_INTERNAL_H
#define GEOM_SRC_CORE_INTERNAL_H

#include "geom/core.h"

#include <math.h>
#include <stdarg.h>
#include <stdint.h>

#define GEOM_PI 3.14159265358979323846

#if defined(__GNUC__) || defined(__clang__)
#define GEOM_PRINTF(fmt, args) __attribute__((format(printf, fmt, args)))
#else
#define GEOM_PRINTF(fmt, args)
#endif

/* Batch kernels whose lane loops vectorise are also compiled for AVX2 and
 * AVX-512 and chosen when the library loads (ifunc), on x86-64 ELF with GCC
 * or Clang. The build's -ffp-contract=off keeps every clone's results
 * bitwise those of the baseline. Off under the sanitizers. */
#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(undefined_behavior_sanitizer)
#define GEOM__NO_CLONES 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define GEOM__NO_CLONES 1
#endif
#if defined(__x86_64__) && defined(__ELF__) && defined(__has_attribute) && !defined(GEOM__NO_CLONES)
#if __has_attribute(target_clones)
#define GEOM_SIMD_CLONES __attribute__((target_clones("default", "avx2", "avx512f")))
#endif
#endif
#ifndef GEOM_SIMD_CLONES
#define GEOM_SIMD_CLONES
#endif
/* A helper of a GEOM_SIMD_CLONES kernel: inlined into each clone, so it is
 * compiled for that clone's instruction set (a call would run the default). */
#if defined(__GNUC__)
#define GEOM__CLONE_INLINE static inline __attribute__((always_inline))
#else
#define GEOM__CLONE_INLINE static inline
#endif

/* Fill d (if non-NULL) with status, source, line, column and a printf-style
 * message; returns status so callers can `return geom__diag_set(...)`. */
geom_status geom__diag_set(geom_diag *d, geom_status status, const char *source, size_t line,
                          size_t column, const char *fmt, ...) GEOM_PRINTF(6, 7);
/* As geom__diag_set, for binary input: records a byte offset instead of a line. */
geom_status geom__diag_set_offset(geom_diag *d, geom_status status, const char *source,
                                 uint64_t offset, const char *fmt, ...) GEOM_PRINTF(5, 6);

/* Allocation through an optional allocator (NULL or zeroed = libc). Sizes
 * are the caller's; free needs the size that was allocated. */
void *geom__alloc(const geom_allocator *a, size_t size);
void *geom__realloc(const geom_allocator *a, void *ptr, size_t old_size, size_t new_size);
void geom__free(const geom_allocator *a, void *ptr, size_t size);
/* Advice only: ask for transparent huge pages on a large array from libc's
 * malloc (bytes >= min_bytes; the first touch of a 100 MB array otherwise
 * costs tens of thousands of page faults). A caller's allocator is left
 * alone; no-op where madvise has no MADV_HUGEPAGE. */
void geom__advise_huge(const geom_allocator *a, void *p, size_t bytes, size_t min_bytes);
/* n*size with overflow check: returns 0 and sets *out, or GEOM_ERR_LIMIT. */
geom_status geom__size_mul(size_t n, size_t size, size_t *out);

/* The system's text for errno value err into buf (reentrant strerror_r). */
void geom__sys_reason(int err, char *buf, size_t size);

/* Release the memory pages of a mapped geom_file (no-op when it was read):
 * the mapping stays valid and reads the file's bytes again if touched. */
void geom__file_drop_pages(geom_file *f);
/* Monotonic wall-clock seconds (an arbitrary origin), for the error
 * reports' timings (core/clock.c). */
double geom__seconds(void);

/* ------------------------------------------------ growable arrays (grow.c) */
/* Make the array *p of *cap elements of elem bytes hold at least need
 * elements (capacity doubles, from 8). GEOM_OK (nothing done when need <=
 * *cap), GEOM_ERR_LIMIT (byte size overflows), GEOM_ERR_NOMEM (then *p and
 * *cap are unchanged). */
geom_status geom__grow(const geom_allocator *a, void **p, size_t *cap, size_t need, size_t elem);
/* Append the elem bytes at item to the array (*p, *n, *cap), growing it
 * through geom__grow; statuses as geom__grow. */
geom_status geom__push(const geom_allocator *a, void **p, size_t *n, size_t *cap, size_t elem,
                       const void *item);

/* ---------------------------------------------------- union-find (unionfind.c) */
/* Disjoint sets over parent[0..n): init makes n singletons; find returns a
 * set's root (path halving); union joins two sets and returns the new root.
 * A set's root is always its smallest member. */
void geom__uf_init(uint32_t *parent, size_t n);
uint32_t geom__uf_find(uint32_t *parent, uint32_t x);
uint32_t geom__uf_union(uint32_t *parent, uint32_t a, uint32_t b);

/* ------------------------------------------------------------ hash (hash.c) */
/* Mix v into the running hash h (splitmix64 finaliser). */
uint64_t geom__hash_mix(uint64_t h, uint64_t v);
/* Hash of n doubles by their bits, -0 and 0 alike. */
uint64_t geom__hash_doubles(const double *v, size_t n);
/* Open-addressing index of uint32 ids keyed by a caller-computed 64-bit hash;
 * the caller compares the candidates itself. Zero-initialise. */
typedef struct geom__hindex {
    uint64_t *slot; /* (hash high 32 bits << 32) | (id + 1); 0 = empty */
    size_t cap, n;
} geom__hindex;
/* Make room for n entries (load <= 1/2). GEOM_ERR_NOMEM, GEOM_ERR_LIMIT. */
geom_status geom__hindex_reserve(geom__hindex *h, const geom_allocator *a, size_t n);
/* The candidates for `hash`: start with *it = 0; returns the next candidate
 * id, or UINT32_MAX when there is none (then *it is where
 * geom__hindex_insert_at may insert). */
uint32_t geom__hindex_next(const geom__hindex *h, uint64_t hash, size_t *it);
/* Insert id at the free slot the last geom__hindex_next stopped at (no growth
 * here: reserve first). */
void geom__hindex_insert_at(geom__hindex *h, uint64_t hash, size_t it, uint32_t id);
void geom__hindex_free(geom__hindex *h, const geom_allocator *a);

static inline int geom__isfinite3(const double p[3])
{
    return isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]);
}

/* geom_orient2d and geom_orient3d over n rows (strides in doubles), bitwise
 * their results: the fast paths of geom_predicate_many (predicates.c). */
void geom__orient2d_many(size_t n, const double *a, size_t sa, const double *b, size_t sb,
                         const double *c, size_t sc, double *out);
void geom__orient3d_many(size_t n, const double *a, size_t sa, const double *b, size_t sb,
                         const double *c, size_t sc, const double *d, size_t sd, double *out);

#endif
