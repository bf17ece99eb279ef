/*
 * core's internal utilities (libgeom/src/core/internal.h): the growable
 * array (capacity, contents kept, overflow refused, allocator failure leaves
 * the array unchanged), the union-find (against brute-force connected
 * components of random graphs; roots are the smallest members) and the hash
 * index (against a linear scan, with deliberately colliding hashes).
 */
#include "unit/test_util.h"

#include <stdlib.h>
#include <string.h>

#include "../../libgeom/src/core/internal.h"

static uint64_t rng = 88172645463325252ull;
static uint64_t next(void)
{
    return test_xorshift64(&rng);
}

static void test_grow_push(void **state)
{
    (void)state;
    uint32_t *a = NULL;
    size_t n = 0, cap = 0;
    for (uint32_t i = 0; i < 10000; i++) {
        assert_int_equal(geom__push(NULL, (void **)&a, &n, &cap, sizeof *a, &i), GEOM_OK);
        assert_true(cap >= n);
    }
    assert_int_equal(n, 10000);
    for (uint32_t i = 0; i < 10000; i++)
        assert_int_equal(a[i], i);
    /* nothing to do */
    size_t c0 = cap;
    assert_int_equal(geom__grow(NULL, (void **)&a, &cap, 5, sizeof *a), GEOM_OK);
    assert_int_equal(cap, c0);
    /* a byte size that overflows size_t is refused, array unchanged */
    assert_int_equal(geom__grow(NULL, (void **)&a, &cap, SIZE_MAX / 2, sizeof *a), GEOM_ERR_LIMIT);
    assert_int_equal(cap, c0);
    assert_int_equal(a[9999], 9999);
    free(a);
}

static int fail_after;
static void *fail_alloc(void *user, size_t size)
{
    (void)user;
    return fail_after-- > 0 ? malloc(size) : NULL;
}
static void *fail_realloc(void *user, void *p, size_t old, size_t size)
{
    (void)user, (void)old;
    return fail_after-- > 0 ? realloc(p, size) : NULL;
}
static void fail_free(void *user, void *p, size_t size)
{
    (void)user, (void)size;
    free(p);
}

static void test_grow_nomem(void **state)
{
    (void)state;
    geom_allocator al = {fail_alloc, fail_realloc, fail_free, NULL};
    double *a = NULL;
    size_t cap = 0;
    fail_after = 1;
    assert_int_equal(geom__grow(&al, (void **)&a, &cap, 3, sizeof *a), GEOM_OK);
    assert_int_equal(cap, 8);
    a[0] = 1.5;
    assert_int_equal(geom__grow(&al, (void **)&a, &cap, 100, sizeof *a), GEOM_ERR_NOMEM);
    assert_int_equal(cap, 8);
    assert_true(a[0] == 1.5);
    geom__free(&al, a, cap * sizeof *a);
}

static void test_union_find(void **state)
{
    (void)state;
    enum { N = 300 };
    uint32_t parent[N], comp[N];
    for (int trial = 0; trial < 50; trial++) {
        geom__uf_init(parent, N);
        for (int i = 0; i < N; i++)
            comp[i] = (uint32_t)i;
        int edges = (int)(next() % 400);
        for (int e = 0; e < edges; e++) {
            uint32_t a = (uint32_t)(next() % N), b = (uint32_t)(next() % N);
            uint32_t r = geom__uf_union(parent, a, b);
            /* brute force: relabel b's component to a's (smallest label) */
            uint32_t ca = comp[a], cb = comp[b], lo = ca < cb ? ca : cb, hi = ca < cb ? cb : ca;
            for (int i = 0; i < N; i++)
                if (comp[i] == hi)
                    comp[i] = lo;
            assert_int_equal(r, lo);
        }
        for (uint32_t i = 0; i < N; i++) {
            /* comp holds the smallest member of each component */
            assert_int_equal(geom__uf_find(parent, i), comp[i]);
            assert_true(geom__uf_find(parent, i) <= i);
        }
    }
}

static void test_hash_index(void **state)
{
    (void)state;
    enum { N = 5000 };
    geom__hindex h = {0};
    static uint64_t keys[N];
    size_t nkeys = 0;
    for (int i = 0; i < 3 * N; i++) {
        /* few distinct keys, so lookups hit; hashes with only 16 distinct
         * high halves, so the probe meets many false candidates */
        uint64_t k = next() % N;
        uint64_t hv = (geom__hash_mix(0, k) & 0xffffffffull) | ((k % 16) << 32);
        size_t it = 0;
        uint32_t cand, found = UINT32_MAX;
        while ((cand = geom__hindex_next(&h, hv, &it)) != UINT32_MAX)
            if (keys[cand] == k) {
                found = cand;
                break;
            }
        uint32_t brute = UINT32_MAX;
        for (size_t j = 0; j < nkeys; j++)
            if (keys[j] == k)
                brute = (uint32_t)j;
        assert_int_equal(found, brute);
        if (found == UINT32_MAX) {
            if (nkeys + 1 > h.cap / 2) {
                assert_int_equal(geom__hindex_reserve(&h, NULL, nkeys + 1), GEOM_OK);
                it = 0;
                while (geom__hindex_next(&h, hv, &it) != UINT32_MAX)
                    ;
            }
            geom__hindex_insert_at(&h, hv, it, (uint32_t)nkeys);
            keys[nkeys++] = k;
        }
    }
    assert_int_equal(h.n, nkeys);
    assert_true(h.cap >= 2 * nkeys);
    geom__hindex_free(&h, NULL);
    assert_int_equal(h.cap, 0);
}

static void test_hash_doubles(void **state)
{
    (void)state;
    double a[3] = {0.0, 1.0, -2.5}, b[3] = {-0.0, 1.0, -2.5}, c[3] = {0.0, 1.0, -2.4999999999999996};
    assert_true(geom__hash_doubles(a, 3) == geom__hash_doubles(b, 3));
    assert_true(geom__hash_doubles(a, 3) != geom__hash_doubles(c, 3));
    assert_true(geom__hash_doubles(a, 2) != geom__hash_doubles(a, 3));
    assert_true(geom__hash_mix(0, 1) != geom__hash_mix(0, 2));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_grow_push),   cmocka_unit_test(test_grow_nomem),
        cmocka_unit_test(test_union_find),  cmocka_unit_test(test_hash_index),
        cmocka_unit_test(test_hash_doubles),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
