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
#include "geom/mesh.h"

/* Fail unless |x - y| <= tol (NaN fails), printing both to the last bit. */
static inline void assert_close(double x, double y, double tol)
{
    if (!(fabs(x - y) <= tol))
        fail_msg("%.17g != %.17g (tol %g)", x, y, tol);
}

/* Marsaglia's xorshift64 (shifts 13, 7, 17) on *state (nonzero): the
 * reproducible stream the random tests draw from. */
static inline uint64_t test_xorshift64(uint64_t *state)
{
    uint64_t x = *state;
    x ^= x << 13;
    x ^= x >> 7;
    x ^= x << 17;
    return *state = x;
}

/* Fail unless a and b have the same connectivity, element for element:
 * counts, each halfedge's next, prev, vertex and face, each vertex's and
 * each face's halfedge. */
static inline void assert_same_connectivity(const geom_mesh *a, const geom_mesh *b)
{
    assert_int_equal(geom_mesh_n_vertices(a), geom_mesh_n_vertices(b));
    assert_int_equal(geom_mesh_n_halfedges(a), geom_mesh_n_halfedges(b));
    assert_int_equal(geom_mesh_n_faces(a), geom_mesh_n_faces(b));
    for (uint32_t h = 0; h < geom_mesh_n_halfedges(a); h++) {
        assert_int_equal(geom_mesh_he_next(a, h), geom_mesh_he_next(b, h));
        assert_int_equal(geom_mesh_he_prev(a, h), geom_mesh_he_prev(b, h));
        assert_int_equal(geom_mesh_he_vertex(a, h), geom_mesh_he_vertex(b, h));
        assert_int_equal(geom_mesh_he_face(a, h), geom_mesh_he_face(b, h));
    }
    for (uint32_t v = 0; v < geom_mesh_n_vertices(a); v++)
        assert_int_equal(geom_mesh_vertex_he(a, v), geom_mesh_vertex_he(b, v));
    for (uint32_t f = 0; f < geom_mesh_n_faces(a); f++)
        assert_int_equal(geom_mesh_face_he(a, f), geom_mesh_face_he(b, f));
}

/* xorshift64: a double in [0, 1) from the state *s (nonzero). */
static inline double test_urand(uint64_t *s)
{
    return (double)(test_xorshift64(s) >> 11) * 0x1p-53;
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
