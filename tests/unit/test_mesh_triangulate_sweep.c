/* Monotone-decomposition triangulation (libgeom/src/mesh/triangulate_sweep.c)
 * checked by brute force, called directly (so small polygons exercise the
 * sweep too) and through geom_polygon_triangulate for large ones:
 *  - n-2 triangles with valid distinct corners; every triangle positively
 *    oriented by the exact predicate (zero-area ones only where a duplicate
 *    vertex or a zero-width spike forces them, and exactly that many);
 *  - every polygon side used once in polygon order, every diagonal once
 *    each way (a combinatorial disk);
 *  - the triangles' areas sum to the polygon's (exact on integer grids,
 *    compensated sums otherwise);
 *  - on small polygons, triangles pairwise interior-disjoint (an edge line of
 *    one separates them, exact predicate).
 * Inputs: thousands of random simple polygons made by 2-opt untangling of
 * random points (real and small integer grids: collinear vertices, shared
 * y and x coordinates), combs, spirals, jagged stars, collinear runs,
 * duplicate vertices and spikes, 1e8 offsets, 2^-1000 and 2^1000 scales,
 * clockwise input, and a square with holes joined by bridges (weakly
 * simple). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "../../libgeom/src/mesh/triangulate_internal.h"
#include "bench/triangulate_shapes.h"
#include "geom/mesh.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>


static size_t n_polygons, n_triangles, n_zero, n_fallback_pieces, n_disjoint_pairs;

static uint64_t lcg(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return *s >> 11;
}

static double unif(uint64_t *s) { return (double)lcg(s) * 0x1p-53; }

static double ori(const double *xy, uint32_t a, uint32_t b, uint32_t c)
{
    return geom_orient2d(xy + 2 * (size_t)a, xy + 2 * (size_t)b, xy + 2 * (size_t)c);
}

static void nsum(double *s, double *c, double x)
{
    double t = *s + x;
    *c += fabs(*s) >= fabs(x) ? (*s - t) + x : (x - t) + *s;
    *s = t;
}

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

static int has_key(const uint64_t *k, size_t m, uint64_t key)
{
    return bsearch(&key, k, m, sizeof *k, cmp_u64) != NULL;
}

/* Interiors of the positive triangles t and u are disjoint: some edge line
 * of one has all of the other on its closed outer side. */
static int disjoint(const double *xy, const uint32_t *t, const uint32_t *u)
{
    for (int side = 0; side < 2; ++side) {
        const uint32_t *a = side ? u : t, *b = side ? t : u;
        for (int e = 0; e < 3; ++e) {
            int out = 1;
            for (int k = 0; k < 3 && out; ++k)
                out = ori(xy, a[e], a[(e + 1) % 3], b[k]) <= 0.0;
            if (out)
                return 1;
        }
    }
    return 0;
}

/* The full check of a triangulation of the counter-clockwise polygon xy
 * (2n doubles; area_scale multiplies the areas back, for scaled input). */
static void check(size_t n, const double *xy, const uint32_t *tris, size_t want_zero, int brute)
{
    size_t m = 3 * (n - 2), zero = 0;
    uint64_t *keys = malloc(m * sizeof *keys);
    assert_non_null(keys);
    double as = 0, ac = 0, ps = 0, pc = 0;
    for (size_t t = 0; t + 2 < n; ++t) {
        const uint32_t *v = tris + 3 * t;
        for (int k = 0; k < 3; ++k) {
            assert_true(v[k] < n);
            keys[3 * t + (size_t)k] = (uint64_t)v[k] << 32 | v[(k + 1) % 3];
        }
        assert_true(v[0] != v[1] && v[1] != v[2] && v[0] != v[2]);
        double o = ori(xy, v[0], v[1], v[2]);
        if (o < 0.0)
            fail_msg("n %zu: triangle %zu (%u %u %u) is negative", n, t, v[0], v[1], v[2]);
        zero += o == 0.0;
        const double *a = xy + 2 * (size_t)v[0], *b = xy + 2 * (size_t)v[1],
                     *c = xy + 2 * (size_t)v[2];
        nsum(&as, &ac, 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])));
    }
    if (zero != want_zero)
        fail_msg("n %zu: %zu zero-area triangles, %zu forced", n, zero, want_zero);
    qsort(keys, m, sizeof *keys, cmp_u64);
    for (size_t k = 1; k < m; ++k)
        assert_true(keys[k] != keys[k - 1]); /* no directed edge twice */
    for (size_t k = 0; k < m; ++k) {
        uint32_t a = (uint32_t)(keys[k] >> 32), b = (uint32_t)keys[k];
        if (b == (a + 1) % n)
            continue;
        assert_false(a == (b + 1) % n);                              /* a side backwards */
        assert_true(has_key(keys, m, (uint64_t)b << 32 | a));        /* diagonal both ways */
    }
    for (size_t a = 0; a < n; ++a)
        assert_true(has_key(keys, m, (uint64_t)a << 32 | (uint32_t)((a + 1) % n)));
    free(keys);
    for (size_t i = 0; i < n; ++i) { /* relative to vertex 0 (exact near 1e8) */
        size_t j = (i + 1) % n;
        double xi = xy[2 * i] - xy[0], yi = xy[2 * i + 1] - xy[1];
        double xj = xy[2 * j] - xy[0], yj = xy[2 * j + 1] - xy[1];
        nsum(&ps, &pc, 0.5 * xi * yj);
        nsum(&ps, &pc, -0.5 * xj * yi);
    }
    double area = as + ac, want = ps + pc;
    if (!(fabs(area - want) <= 1e-12 * fabs(want)))
        fail_msg("n %zu: area %.17g want %.17g", n, area, want);
    if (brute)
        for (size_t t = 0; t + 2 < n; ++t)
            for (size_t u = t + 1; u + 2 < n; ++u) {
                const uint32_t *a = tris + 3 * t, *b = tris + 3 * u;
                if (ori(xy, a[0], a[1], a[2]) == 0.0 || ori(xy, b[0], b[1], b[2]) == 0.0)
                    continue;
                if (!disjoint(xy, a, b))
                    fail_msg("n %zu: triangles %zu and %zu overlap", n, t, u);
                n_disjoint_pairs++;
            }
    n_polygons++;
    n_triangles += n - 2;
    n_zero += zero;
}

/* Triangulate xy (embedded at z = 0, or mirrored to z = x when `cw`: then the
 * input is clockwise in its own frame) with the sweep directly (sweep = 1)
 * or the public function, and check. */
static void run(size_t n, const double *xy, size_t want_zero, int sweep, int brute)
{
    double *p = malloc(3 * n * sizeof(double));
    uint32_t *t = malloc(3 * n * sizeof(uint32_t));
    assert_non_null(p);
    assert_non_null(t);
    for (size_t i = 0; i < n; ++i) {
        p[3 * i] = xy[2 * i];
        p[3 * i + 1] = xy[2 * i + 1];
        p[3 * i + 2] = 0.0;
    }
    if (sweep) {
        size_t fb = 0;
        geom_status st = geom__polygon_triangulate_sweep_ex(n, p, 0, 1, t, &fb);
        if (st != GEOM_OK)
            fail_msg("n %zu: sweep rejected a simple polygon (%d)", n, (int)st);
        n_fallback_pieces += fb;
    } else
        assert_int_equal(geom_polygon_triangulate(n, p, t), GEOM_OK);
    check(n, xy, t, want_zero, brute);
    /* the same polygon clockwise (x and y swapped): triangles keep the
     * input's winding */
    for (size_t i = 0; i < n; ++i) {
        p[3 * i] = xy[2 * i + 1];
        p[3 * i + 1] = xy[2 * i];
    }
    geom_status st = sweep ? geom__polygon_triangulate_sweep(n, p, 0, 1, t)
                           : geom_polygon_triangulate(n, p, t);
    assert_int_equal(st, GEOM_OK);
    check(n, xy, t, want_zero, 0); /* same indices, so xy's frame: ccw */
    free(p);
    free(t);
}

/* ------------------------------------------------------ random polygons */

static int on_seg(const double *a, const double *b, const double *p)
{
    return fmin(a[0], b[0]) <= p[0] && p[0] <= fmax(a[0], b[0]) && fmin(a[1], b[1]) <= p[1] &&
           p[1] <= fmax(a[1], b[1]);
}

/* Closed segments ab and cd meet. */
static int meet(const double *a, const double *b, const double *c, const double *d)
{
    double o1 = geom_orient2d(a, b, c), o2 = geom_orient2d(a, b, d);
    double o3 = geom_orient2d(c, d, a), o4 = geom_orient2d(c, d, b);
    if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0)))
        return 1;
    return (o1 == 0 && on_seg(a, b, c)) || (o2 == 0 && on_seg(a, b, d)) ||
           (o3 == 0 && on_seg(c, d, a)) || (o4 == 0 && on_seg(c, d, b));
}

/* Simple (brute force): non-adjacent sides never meet; adjacent sides meet
 * only at their shared vertex. */
static int simple(size_t n, const double *xy)
{
    for (size_t i = 0; i < n; ++i) {
        const double *a = xy + 2 * i, *b = xy + 2 * ((i + 1) % n);
        for (size_t j = i + 1; j < n; ++j) {
            const double *c = xy + 2 * j, *d = xy + 2 * ((j + 1) % n);
            if (j == i + 1) { /* b == c shared */
                if (geom_orient2d(a, b, d) == 0 && (on_seg(a, b, d) || on_seg(c, d, a)))
                    return 0;
            } else if (i == 0 && j == n - 1) { /* d == a shared */
                if (geom_orient2d(c, d, b) == 0 && (on_seg(c, d, b) || on_seg(a, b, c)))
                    return 0;
            } else if (meet(a, b, c, d))
                return 0;
        }
    }
    return 1;
}

static double shoelace(size_t n, const double *xy)
{
    double s = 0, c = 0;
    for (size_t i = 0; i < n; ++i) {
        size_t j = (i + 1) % n;
        nsum(&s, &c, xy[2 * i] * xy[2 * j + 1]);
        nsum(&s, &c, -xy[2 * j] * xy[2 * i + 1]);
    }
    return s + c;
}

static void reverse(double *xy, size_t i, size_t j)
{
    for (; i < j; ++i, --j)
        for (int k = 0; k < 2; ++k) {
            double t = xy[2 * i + (size_t)k];
            xy[2 * i + (size_t)k] = xy[2 * j + (size_t)k];
            xy[2 * j + (size_t)k] = t;
        }
}

/* A random simple counter-clockwise polygon of n vertices by 2-opt
 * untangling of random points: grid = 0 real in [0,1)^2, else integers in
 * [0, grid) (distinct). Returns 0 if untangling did not finish. */
static int random_polygon(size_t n, int grid, uint64_t *s, double *xy)
{
    for (size_t i = 0; i < n; ++i) {
        for (;;) {
            double x = unif(s), y = unif(s);
            if (grid) {
                x = floor(x * grid);
                y = floor(y * grid);
            }
            size_t j = 0;
            while (j < i && !(xy[2 * j] == x && xy[2 * j + 1] == y))
                ++j;
            if (j == i) {
                xy[2 * i] = x;
                xy[2 * i + 1] = y;
                break;
            }
        }
    }
    for (int swaps = 0; swaps < 20000; ++swaps) {
        int found = 0;
        for (size_t i = 0; i < n && !found; ++i)
            for (size_t j = i + 2; j < n && !found; ++j) {
                if (i == 0 && j == n - 1)
                    continue;
                if (meet(xy + 2 * i, xy + 2 * (i + 1), xy + 2 * j, xy + 2 * ((j + 1) % n))) {
                    reverse(xy, i + 1, j);
                    found = 1;
                }
            }
        if (!found)
            break;
    }
    if (!simple(n, xy))
        return 0;
    if (shoelace(n, xy) < 0)
        reverse(xy, 0, n - 1);
    return 1;
}

static void test_random_simple(void **state)
{
    (void)state;
    uint64_t s = 2026;
    double xy[2 * 64];
    static const int grids[] = {0, 4, 6, 10, 1000};
    size_t made = 0, tried = 0;
    for (int it = 0; it < 3000; ++it) {
        int grid = grids[it % 5];
        size_t n = 3 + (size_t)(lcg(&s) % (grid == 4 ? 10 : grid == 6 ? 20 : 38));
        tried++;
        if (!random_polygon(n, grid, &s, xy))
            continue;
        made++;
        run(n, xy, 0, 1, 1);
    }
    print_message("random simple polygons: %zu of %zu untangled and checked\n", made, tried);
    assert_true(made > 2500);
}

/* ------------------------------------------------- structured polygons */

/* comb(K): 4K vertices; spiral(M): 2M; jagged: tests/bench/triangulate_shapes.h */
static size_t comb(size_t K, double *xy) { return ts_comb(4 * K, xy, 0); }
static size_t spiral(size_t M, double *xy) { return ts_spiral(2 * M, xy, 0); }
static size_t jagged(size_t n, uint64_t *s, double *xy) { return ts_jagged(n, xy, lcg(s)); }

/* A rectangle (or an integer staircase) with collinear runs on every side. */
static size_t collinear_box(size_t per_side, double *xy)
{
    size_t m = 0, q = per_side;
    for (size_t i = 0; i < q; ++i)
        xy[2 * m] = (double)i, xy[2 * m + 1] = 0, ++m;
    for (size_t i = 0; i < q; ++i)
        xy[2 * m] = (double)q, xy[2 * m + 1] = (double)i, ++m;
    for (size_t i = 0; i < q; ++i)
        xy[2 * m] = (double)(q - i), xy[2 * m + 1] = (double)q, ++m;
    for (size_t i = 0; i < q; ++i)
        xy[2 * m] = 0, xy[2 * m + 1] = (double)(q - i), ++m;
    return m;
}

static size_t staircase(size_t steps, double *xy)
{
    size_t m = 0;
    for (size_t k = 0; k < steps; ++k) {
        xy[2 * m] = (double)k, xy[2 * m + 1] = (double)k, ++m;
        xy[2 * m] = (double)k + 0.5, xy[2 * m + 1] = (double)k, ++m;
    }
    for (size_t x = steps + 1; x-- > 0;)
        xy[2 * m] = (double)x, xy[2 * m + 1] = (double)steps, ++m;
    return m;
}

/* Zig-zag with collinear teeth tips on two horizontal lines (many shared y). */
static size_t zigzag(size_t K, double *xy)
{
    size_t m = 0;
    for (size_t i = 0; i <= 2 * K; ++i)
        xy[2 * m] = (double)i, xy[2 * m + 1] = i % 2 ? 1.0 : 0.0, ++m;
    for (size_t i = 2 * K + 1; i-- > 0;)
        xy[2 * m] = (double)i, xy[2 * m + 1] = i % 2 ? 3.0 : 4.0, ++m;
    return m;
}

static void run_sizes(size_t (*make)(size_t, double *), const size_t *sizes, size_t ns,
                      size_t cap, int sweep_too)
{
    double *xy = malloc(2 * cap * sizeof(double));
    assert_non_null(xy);
    for (size_t k = 0; k < ns; ++k) {
        size_t n = make(sizes[k], xy);
        assert_true(n <= cap);
        run(n, xy, 0, 0, n <= 200);
        if (sweep_too)
            run(n, xy, 0, 1, n <= 200);
    }
    free(xy);
}

static size_t comb_n(size_t k, double *xy) { return comb(k, xy); }
static size_t spiral_n(size_t k, double *xy) { return spiral(k, xy); }

static void test_structured(void **state)
{
    (void)state;
    static const size_t kc[] = {2, 3, 5, 17, 40, 2500, 25000};
    run_sizes(comb_n, kc, 7, 100000, 1);
    static const size_t ks[] = {20, 33, 100, 5000, 50000};
    run_sizes(spiral_n, ks, 5, 100000, 1);
    static const size_t kb[] = {1, 2, 3, 10, 50, 1000, 25000};
    run_sizes(collinear_box, kb, 7, 100000, 1);
    static const size_t kst[] = {1, 2, 5, 30, 10000};
    run_sizes(staircase, kst, 5, 40000, 1);
    static const size_t kz[] = {1, 2, 7, 30, 20000};
    run_sizes(zigzag, kz, 5, 100000, 1);
    uint64_t s = 5;
    double *xy = malloc(2 * 100000 * sizeof(double));
    assert_non_null(xy);
    static const size_t kj[] = {5, 8, 31, 100, 1000, 100000};
    for (size_t k = 0; k < 6; ++k) {
        size_t n = jagged(kj[k], &s, xy);
        run(n, xy, 0, 1, n <= 200);
        run(n, xy, 0, 0, 0);
    }
    free(xy);
}

/* Duplicate vertices and zero-width spikes: exactly one zero-area triangle
 * each (they are forced), every other triangle positive. */
static void test_duplicates_spikes(void **state)
{
    (void)state;
    uint64_t s = 77;
    double base[2 * 200], xy[2 * 800];
    for (int it = 0; it < 400; ++it) {
        size_t n0 = 4 + (size_t)(lcg(&s) % 150);
        size_t n = 0, forced = 0;
        if (it % 2)
            n0 = jagged(n0, &s, base);
        else {
            n0 = collinear_box(1 + n0 / 4, base);
        }
        for (size_t i = 0; i < n0; ++i) {
            xy[2 * n] = base[2 * i], xy[2 * n + 1] = base[2 * i + 1], ++n;
            uint64_t r = lcg(&s) % 10;
            if (r < 2) { /* 1 or 2 duplicates */
                for (uint64_t d = 0; d <= r; ++d) {
                    xy[2 * n] = base[2 * i], xy[2 * n + 1] = base[2 * i + 1], ++n;
                    forced++;
                }
            } else if (r == 2 && it % 2 == 0) {
                /* a spike out of the box side's vertex, along the side:
                 * v -> v + 0.25 d -> v (d the side's direction) */
                const double *a = base + 2 * i, *b = base + 2 * ((i + 1) % n0);
                xy[2 * n] = a[0] + 0.25 * (b[0] - a[0]), xy[2 * n + 1] = a[1] + 0.25 * (b[1] - a[1]);
                ++n;
                /* ... goes out along the side and comes back: collinear, not
                 * forced (the next vertex is further along); a real spike
                 * needs a way back: */
                xy[2 * n] = a[0], xy[2 * n + 1] = a[1], ++n;
                forced += 2; /* the tip and the repeated vertex */
            }
        }
        run(n, xy, forced, 1, n <= 200);
        if (n > 64)
            run(n, xy, forced, 0, 0);
    }
}

/* 1e8 offsets, 2^-1000 and 2^1000 scales (exact scaling, same shape). */
static void test_offsets_scales(void **state)
{
    (void)state;
    uint64_t s = 9;
    double *xy = malloc(2 * 20000 * sizeof(double)), *w = malloc(2 * 20000 * sizeof(double));
    assert_non_null(xy);
    assert_non_null(w);
    for (int it = 0; it < 40; ++it) {
        size_t n = it < 30 ? 10 + (size_t)(lcg(&s) % 200) : 20000;
        if (it % 2)
            jagged(n, &s, xy);
        else
            n = comb(n / 4, xy);
        for (int mode = 0; mode < 3; ++mode) {
            for (size_t i = 0; i < 2 * n; ++i)
                w[i] = mode == 0 ? xy[i] + 1e8 : ldexp(xy[i], mode == 1 ? -1000 : 1000);
            if (mode == 0 && n <= 2000 && !simple(n, w))
                continue; /* rounding at 1e8 made it touch: not a simple polygon */
            double *p = malloc(3 * n * sizeof(double));
            uint32_t *t = malloc(3 * n * sizeof(uint32_t));
            for (size_t i = 0; i < n; ++i) {
                p[3 * i] = w[2 * i];
                p[3 * i + 1] = w[2 * i + 1];
                p[3 * i + 2] = 0.0;
            }
            assert_int_equal(geom__polygon_triangulate_sweep(n, p, 0, 1, t), GEOM_OK);
            /* scaled: check in the unscaled frame (same shape exactly) */
            check(n, mode == 0 ? w : xy, t, 0, n <= 200);
            assert_int_equal(geom_polygon_triangulate(n, p, t), GEOM_OK);
            check(n, mode == 0 ? w : xy, t, 0, 0);
            free(p);
            free(t);
        }
    }
    free(xy);
    free(w);
}

/* A square with k square holes, each joined to the outer boundary by a
 * bridge walked both ways (the polygon clip.c makes for caps): weakly
 * simple, with duplicate vertices. Through the public function: proper
 * positive triangles (the sweep or, if it rejects, the ear clipper). */
static void test_bridged_holes(void **state)
{
    (void)state;
    for (size_t k = 1; k <= 40; k += 13) {
        double *xy = malloc(2 * (4 + 12 * k) * sizeof(double));
        size_t n = 0;
        double W = 4.0 * (double)k;
        /* outer ccw, bottom side from (W, 0) leftwards... start at (0,0) */
        xy[2 * n] = 0, xy[2 * n + 1] = 0, ++n;
        for (size_t h = 0; h < k; ++h) {
            /* along the bottom to x0 = 4h + 1.5, up the bridge to the hole
             * (x0, 1), around it clockwise, back down */
            double x0 = 4.0 * (double)h + 1.5;
            xy[2 * n] = x0, xy[2 * n + 1] = 0, ++n;
            xy[2 * n] = x0, xy[2 * n + 1] = 1, ++n;
            xy[2 * n] = x0 - 0.5, xy[2 * n + 1] = 1, ++n; /* hole cw: left, up, right, down */
            xy[2 * n] = x0 - 0.5, xy[2 * n + 1] = 2, ++n;
            xy[2 * n] = x0 + 0.5, xy[2 * n + 1] = 2, ++n;
            xy[2 * n] = x0 + 0.5, xy[2 * n + 1] = 1, ++n;
            xy[2 * n] = x0, xy[2 * n + 1] = 1, ++n;
            xy[2 * n] = x0, xy[2 * n + 1] = 0, ++n;
        }
        xy[2 * n] = W, xy[2 * n + 1] = 0, ++n;
        xy[2 * n] = W, xy[2 * n + 1] = 3, ++n;
        xy[2 * n] = 0, xy[2 * n + 1] = 3, ++n;
        double *p = malloc(3 * n * sizeof(double));
        uint32_t *t = malloc(3 * n * sizeof(uint32_t));
        for (size_t i = 0; i < n; ++i) {
            p[3 * i] = xy[2 * i];
            p[3 * i + 1] = xy[2 * i + 1];
            p[3 * i + 2] = 0.0;
        }
        geom_status st = geom__polygon_triangulate_sweep(n, p, 0, 1, t);
        print_message("bridged square with %zu holes (n = %zu): sweep %s\n", k, n,
                      st == GEOM_OK ? "accepted" : "rejected (ear clipper used)");
        if (st == GEOM_OK)
            check(n, xy, t, 0, 1);
        assert_int_equal(geom_polygon_triangulate(n, p, t), GEOM_OK);
        check(n, xy, t, 0, 1);
        free(p);
        free(t);
        free(xy);
    }
}

/* Non-simple input through the sweep: rejected, or n-2 triangles with
 * valid corners using every side once; never a crash (ASan). */
static void test_non_simple(void **state)
{
    (void)state;
    uint64_t s = 31;
    size_t accepted = 0, pieces = 0;
    for (int it = 0; it < 600; ++it) {
        size_t n = 3 + (size_t)(lcg(&s) % 120);
        double *p = malloc(3 * n * sizeof(double));
        uint32_t *t = malloc(3 * n * sizeof(uint32_t));
        for (size_t i = 0; i < n; ++i) {
            double x = unif(&s), y = unif(&s);
            if (it % 3 == 1)
                x = floor(3 * x), y = floor(3 * y);
            else if (it % 3 == 2)
                x = (double)(i % 5), y = 2.0 * x;
            p[3 * i] = x;
            p[3 * i + 1] = y;
            p[3 * i + 2] = 0.0;
        }
        size_t fb = 0;
        geom_status st = geom__polygon_triangulate_sweep_ex(n, p, 0, 1, t, &fb);
        if (st == GEOM_OK) {
            accepted++;
            pieces += fb;
            size_t sides = 0;
            for (size_t k = 0; k + 2 < n; ++k) {
                const uint32_t *v = t + 3 * k;
                assert_true(v[0] < n && v[1] < n && v[2] < n);
                assert_true(v[0] != v[1] && v[1] != v[2] && v[0] != v[2]);
                for (int j = 0; j < 3; ++j)
                    sides += v[(j + 1) % 3] == (v[j] + 1) % n;
            }
            assert_int_equal(sides, n);
        } else
            assert_int_equal(st, GEOM_ERR_DEGENERATE);
        free(p);
        free(t);
    }
    /* the pieces made of a non-simple polygon exercise the per-piece ear
     * clipping fallback (no simple polygon of these tests needed it) */
    print_message("non-simple: %zu of 600 accepted by the sweep, %zu pieces ear-clipped\n",
                  accepted, pieces);
    assert_true(pieces > 0);
}

/* geom_mesh_triangulate on one face of 100k vertices (a jagged star):
 * n-3 faces added, a valid mesh of n-2 positive triangles, Euler
 * characteristic 1. Its diagonal lookup used to be a linear scan per
 * diagonal (quadratic in the face size). */
static void test_mesh_big_face(void **state)
{
    (void)state;
    size_t n = 100000;
    double *xy = malloc(2 * n * sizeof(double)), *p = malloc(3 * n * sizeof(double));
    uint32_t *idx = malloc(n * sizeof(uint32_t)), sz = (uint32_t)n;
    assert_non_null(xy);
    assert_non_null(p);
    assert_non_null(idx);
    uint64_t s = 99;
    jagged(n, &s, xy);
    for (size_t i = 0; i < n; ++i) {
        p[3 * i] = xy[2 * i];
        p[3 * i + 1] = xy[2 * i + 1];
        p[3 * i + 2] = 0.5;
        idx[i] = (uint32_t)i;
    }
    geom_mesh *m = geom_mesh_create(NULL);
    assert_non_null(m);
    assert_int_equal(geom_mesh_build(m, n, p, 1, &sz, idx, NULL, NULL, NULL), GEOM_OK);
    size_t added = 0, nd = 0;
    assert_int_equal(geom_mesh_triangulate(m, &added), GEOM_OK);
    assert_int_equal(added, n - 3);
    assert_int_equal(geom_mesh_n_faces(m), n - 2);
    assert_int_equal(geom_mesh_validate(m, NULL, 0, &nd), GEOM_OK);
    assert_int_equal(nd, 0);
    assert_int_equal(geom_mesh_n_edges(m), n + (n - 3));
    const double *pos = geom_mesh_cpositions(m);
    for (uint32_t f = 0; f < n - 2; ++f) {
        assert_int_equal(geom_mesh_face_valence(m, f), 3);
        uint32_t h = geom_mesh_face_he(m, f), v[3];
        for (int k = 0; k < 3; ++k, h = geom_mesh_he_next(m, h))
            v[k] = geom_mesh_he_vertex(m, h);
        double a[2] = {pos[3 * v[0]], pos[3 * v[0] + 1]}, b[2] = {pos[3 * v[1]], pos[3 * v[1] + 1]},
               c[2] = {pos[3 * v[2]], pos[3 * v[2] + 1]};
        assert_true(geom_orient2d(a, b, c) > 0.0);
    }
    geom_mesh_destroy(m);
    free(xy);
    free(p);
    free(idx);
}

static int report(void **state)
{
    (void)state;
    print_message("checked %zu triangulations, %zu triangles (%zu forced zero-area), %zu "
                  "triangle pairs disjoint by brute force, %zu monotone pieces handed to the "
                  "ear clipper\n",
                  n_polygons, n_triangles, n_zero, n_disjoint_pairs, n_fallback_pieces);
    return 0;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_random_simple),  cmocka_unit_test(test_structured),
        cmocka_unit_test(test_duplicates_spikes), cmocka_unit_test(test_offsets_scales),
        cmocka_unit_test(test_bridged_holes),  cmocka_unit_test(test_non_simple),
        cmocka_unit_test(test_mesh_big_face),
    };
    return cmocka_run_group_tests(tests, NULL, report);
}
