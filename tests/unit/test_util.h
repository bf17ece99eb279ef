/* Helpers shared by the unit tests (cmocka). Header-only: include it after
 * <cmocka.h>'s prerequisites. Public API only. */
#ifndef GEOM_TESTS_TEST_UTIL_H
#define GEOM_TESTS_TEST_UTIL_H

#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "geom/core.h"

/* Fail unless |x - y| <= tol (NaN fails), printing both to the last bit. */
static inline void assert_close(double x, double y, double tol)
{
    if (!(fabs(x - y) <= tol))
        fail_msg("%.17g != %.17g (tol %g)", x, y, tol);
}

/* xorshift64: a double in [0, 1) from the state *s (nonzero). */
static inline double test_urand(uint64_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 7;
    *s ^= *s << 17;
    return (double)(*s >> 11) * 0x1p-53;
}

/* a and b the same bits, or both NaN (NaN payloads are no contract). */
static inline int same_bits_or_nan(double a, double b)
{
    return memcmp(&a, &b, sizeof a) == 0 || (isnan(a) && isnan(b));
}

/* A counting allocator that fails once `budget` allocations have been made
 * (budget < 0: never), and checks that every free names the size that was
 * allocated: use as geom_allocator a = {oom_alloc, NULL, oom_free, &s} with
 * oom_state s = {-1, 0, 0}; then s.live == 0 and !s.bad_free at the end. */
typedef struct oom_state {
    long budget; /* allocations left; < 0: unlimited */
    long live;
    int bad_free;
} oom_state;

static inline void *oom_alloc(void *user, size_t size)
{
    oom_state *s = user;
    if (s->budget == 0)
        return NULL;
    if (s->budget > 0)
        s->budget--;
    size_t *p = malloc(size + 16);
    if (!p)
        return NULL;
    p[0] = size;
    s->live++;
    return (char *)p + 16;
}

static inline void oom_free(void *user, void *ptr, size_t size)
{
    oom_state *s = user;
    size_t *p = (size_t *)((char *)ptr - 16);
    /* geom__alloc turns a 0-byte request into 1 byte */
    if (p[0] != size && !(p[0] == 1 && size == 0))
        s->bad_free = 1;
    s->live--;
    free(p);
}

#endif
