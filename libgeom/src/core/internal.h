/* Private helpers shared by libgeom's sources. Not installed. */
#ifndef GEOM_SRC_CORE_INTERNAL_H
#define GEOM_SRC_CORE_INTERNAL_H

#include "geom/core.h"

#include <math.h>
#include <stdarg.h>

#define GEOM_PI 3.14159265358979323846

#if defined(__GNUC__) || defined(__clang__)
#define GEOM_PRINTF(fmt, args) __attribute__((format(printf, fmt, args)))
#else
#define GEOM_PRINTF(fmt, args)
#endif

/* Fill d (if non-NULL) with status, source, line, column and a printf-style
 * message; returns status so callers can `return geom_diag_set(...)`. */
geom_status geom_diag_set(geom_diag *d, geom_status status, const char *source, size_t line,
                          size_t column, const char *fmt, ...) GEOM_PRINTF(6, 7);
/* As geom_diag_set, for binary input: records a byte offset instead of a line. */
geom_status geom_diag_set_offset(geom_diag *d, geom_status status, const char *source,
                                 uint64_t offset, const char *fmt, ...) GEOM_PRINTF(5, 6);

/* Allocation through an optional allocator (NULL or zeroed = libc). Sizes
 * are the caller's; free needs the size that was allocated. */
void *geom_alloc(const geom_allocator *a, size_t size);
void *geom_realloc(const geom_allocator *a, void *ptr, size_t old_size, size_t new_size);
void geom_free(const geom_allocator *a, void *ptr, size_t size);
/* n*size with overflow check: returns 0 and sets *out, or GEOM_ERR_LIMIT. */
geom_status geom_size_mul(size_t n, size_t size, size_t *out);

/* The system's text for errno value err into buf (reentrant strerror_r). */
void geom__sys_reason(int err, char *buf, size_t size);

/* Release the memory pages of a mapped geom_file (no-op when it was read):
 * the mapping stays valid and reads the file's bytes again if touched. */
void geom__file_drop_pages(geom_file *f);
/* Monotonic wall-clock seconds (an arbitrary origin), for the error
 * reports' timings (core/clock.c). */
double geom__seconds(void);

static inline int geom_isfinite3(const double p[3])
{
    return isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]);
}

#endif
