/*
 * bench_bary: time per query and maximum error of libgeom's robust
 * barycentric coordinates (geom_bary_tri2, geom_bary_tri3) next to the
 * textbook formulas evaluated naively in double, on the same queries in the
 * same run, both measured against the exact answer computed with CGAL's
 * exact number types and rounded once (tests/validate, gv_bary_tri2 /
 * gv_bary_tri3, whose own time per query is printed too).
 *
 * Inputs (fixed-seed splitmix64, so every run sees the same queries):
 *  - "random": 10^6 triangles with vertices uniform in [-1,1]^d and query
 *    points that are affine combinations with weights in [-0.5, 1.5];
 *  - "sliver+1e8": 10^5 slivers (area / longest_edge^2 = 10^-U(0,15) before
 *    the shift) moved by offsets in [1e8, 2e8) per axis, queries as above.
 *
 * Textbook formulas: 2D, l1 = ((p-a) x (c-a)) / ((b-a) x (c-a)),
 * l2 = ((b-a) x (p-a)) / ((b-a) x (c-a)), l0 = 1 - l1 - l2; 3D, the dot
 * product form (Ericson, Real-Time Collision Detection, 3.4): with
 * v0 = b-a, v1 = c-a, v2 = p-a and dij = vi.vj, den = d00 d11 - d01^2,
 * l1 = (d11 d20 - d01 d21) / den, l2 = (d00 d21 - d01 d20) / den,
 * l0 = 1 - l1 - l2.
 *
 * Error: max over queries and coordinates of |l_i - exact_i| /
 * max_j |exact_j| (a NaN or infinite result counts as infinite error), and
 * the max over coordinates of |l_i - exact_i| / ulp(exact_i) (error in
 * units of the coordinate's own last place; coordinates exactly 0 in the
 * exact answer count as infinite when the result is not 0). Queries whose
 * triangle is exactly degenerate are counted and left out.
 *
 * Output: a Markdown table. Usage: bench_bary [n_random [n_sliver]].
 */
#define _POSIX_C_SOURCE 199309L

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "geom/bary.h"
#include "validate/geom_validate.h"

typedef struct rng {
    uint64_t s;
} rng;

static uint64_t next_u64(rng *r)
{
    uint64_t z = (r->s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

static double unif(rng *r) { return (double)(next_u64(r) >> 11) * 0x1p-53; }
static double unif_in(rng *r, double lo, double hi) { return lo + (hi - lo) * unif(r); }

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ---------------------------------------------------------- the inputs */

/* n queries in dimension d: q[i*4*d ...] = a, b, c, p (d doubles each). */
static double *make_queries(size_t n, int d, int sliver, uint64_t seed)
{
    double *q = malloc(n * 4 * (size_t)d * sizeof *q);
    if (q == NULL) {
        fprintf(stderr, "bench_bary: out of memory\n");
        exit(1);
    }
    rng r = {seed};
    for (size_t i = 0; i < n; ++i) {
        double *a = q + i * 4 * (size_t)d, *b = a + d, *c = b + d, *p = c + d;
        for (int j = 0; j < d; ++j) {
            a[j] = unif_in(&r, -1, 1);
            b[j] = unif_in(&r, -1, 1);
            c[j] = unif_in(&r, -1, 1);
        }
        if (sliver) {
            /* c near segment ab, height ratio * |ab| along a perpendicular */
            const double ratio = pow(10.0, -unif_in(&r, 0, 15));
            const double s = unif(&r);
            double e[3] = {0, 0, 0}, perp[3] = {0, 0, 0};
            for (int j = 0; j < d; ++j)
                e[j] = b[j] - a[j];
            if (d == 2) {
                perp[0] = -e[1];
                perp[1] = e[0];
            } else {
                const double w[3] = {unif_in(&r, -1, 1), unif_in(&r, -1, 1), unif_in(&r, -1, 1)};
                perp[0] = e[1] * w[2] - e[2] * w[1];
                perp[1] = e[2] * w[0] - e[0] * w[2];
                perp[2] = e[0] * w[1] - e[1] * w[0];
            }
            double le = 0, lp = 0;
            for (int j = 0; j < d; ++j) {
                le += e[j] * e[j];
                lp += perp[j] * perp[j];
            }
            const double h = ratio * sqrt(le / lp);
            for (int j = 0; j < d; ++j)
                c[j] = a[j] + s * e[j] + h * perp[j];
        }
        const double u = unif_in(&r, -0.5, 1.5), v = unif_in(&r, -0.5, 1.5);
        for (int j = 0; j < d; ++j)
            p[j] = a[j] + u * (b[j] - a[j]) + v * (c[j] - a[j]);
        if (d == 3)
            p[2] += unif_in(&r, -0.5, 0.5); /* off the plane */
        if (sliver)
            for (int j = 0; j < d; ++j) {
                const double off = 1e8 * (1 + unif(&r));
                a[j] += off;
                b[j] += off;
                c[j] += off;
                p[j] += off;
            }
    }
    return q;
}

/* ------------------------------------------------------ the methods */

static void naive_tri2(const double a[2], const double b[2], const double c[2], const double p[2],
                       double l[3])
{
    const double d = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    l[1] = ((p[0] - a[0]) * (c[1] - a[1]) - (p[1] - a[1]) * (c[0] - a[0])) / d;
    l[2] = ((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])) / d;
    l[0] = 1.0 - l[1] - l[2];
}

static void naive_tri3(const double a[3], const double b[3], const double c[3], const double p[3],
                       double l[3])
{
    double v0[3], v1[3], v2[3];
    for (int j = 0; j < 3; ++j) {
        v0[j] = b[j] - a[j];
        v1[j] = c[j] - a[j];
        v2[j] = p[j] - a[j];
    }
    const double d00 = v0[0] * v0[0] + v0[1] * v0[1] + v0[2] * v0[2];
    const double d01 = v0[0] * v1[0] + v0[1] * v1[1] + v0[2] * v1[2];
    const double d11 = v1[0] * v1[0] + v1[1] * v1[1] + v1[2] * v1[2];
    const double d20 = v2[0] * v0[0] + v2[1] * v0[1] + v2[2] * v0[2];
    const double d21 = v2[0] * v1[0] + v2[1] * v1[1] + v2[2] * v1[2];
    const double den = d00 * d11 - d01 * d01;
    l[1] = (d11 * d20 - d01 * d21) / den;
    l[2] = (d00 * d21 - d01 * d20) / den;
    l[0] = 1.0 - l[1] - l[2];
}

enum { M_GEOM, M_NAIVE, M_CGAL, M_COUNT };

/* Run method m on all n queries, writing 3 coordinates each to out and the
 * status (0 ok) to st; returns seconds. */
static double run(int m, int d, size_t n, const double *q, double *out, int *st)
{
    const double t0 = now_s();
    const size_t stride = 4 * (size_t)d;
    for (size_t i = 0; i < n; ++i) {
        const double *a = q + i * stride, *b = a + d, *c = b + d, *p = c + d;
        double *l = out + 3 * i;
        switch (m) {
        case M_GEOM:
            st[i] = d == 2 ? (int)geom_bary_tri2(a, b, c, p, l) : (int)geom_bary_tri3(a, b, c, p, l);
            break;
        case M_NAIVE:
            if (d == 2)
                naive_tri2(a, b, c, p, l);
            else
                naive_tri3(a, b, c, p, l);
            st[i] = 0;
            break;
        default:
            st[i] = d == 2 ? gv_bary_tri2(a, b, c, p, l) : gv_bary_tri3(a, b, c, p, l);
            break;
        }
    }
    return now_s() - t0;
}

typedef struct errs {
    double rel; /* max |l_i - x_i| / max |x| */
    double ulp; /* max |l_i - x_i| / ulp(x_i) */
} errs;

static errs measure(size_t n, const double *got, const int *st, const double *ref, const int *rst)
{
    errs e = {0, 0};
    for (size_t i = 0; i < n; ++i) {
        if (rst[i] != GV_OK)
            continue; /* exactly degenerate: left out */
        const double *l = got + 3 * i, *x = ref + 3 * i;
        if (st[i] != 0) {
            e.rel = e.ulp = INFINITY;
            continue;
        }
        double m = 0;
        for (int j = 0; j < 3; ++j)
            m = fmax(m, fabs(x[j]));
        for (int j = 0; j < 3; ++j) {
            const double err = fabs(l[j] - x[j]);
            if (isnan(err)) {
                e.rel = e.ulp = INFINITY;
                continue;
            }
            e.rel = fmax(e.rel, err / m);
            const double ax = fabs(x[j]);
            const double u = ax == 0 ? (err == 0 ? 1 : 0) : nextafter(ax, INFINITY) - ax;
            e.ulp = fmax(e.ulp, u == 0 ? INFINITY : err / u);
        }
    }
    return e;
}

static void bench(const char *fn, const char *input, int d, size_t n, int sliver, uint64_t seed)
{
    double *q = make_queries(n, d, sliver, seed);
    double *out[M_COUNT];
    int *st[M_COUNT];
    double best[M_COUNT];
    for (int m = 0; m < M_COUNT; ++m) {
        out[m] = malloc(3 * n * sizeof(double));
        st[m] = malloc(n * sizeof(int));
        if (out[m] == NULL || st[m] == NULL) {
            fprintf(stderr, "bench_bary: out of memory\n");
            exit(1);
        }
        best[m] = INFINITY;
    }
    /* geom and naive: best of 5 runs, interleaved; CGAL: one run */
    for (int rep = 0; rep < 5; ++rep)
        for (int m = M_GEOM; m <= M_NAIVE; ++m)
            best[m] = fmin(best[m], run(m, d, n, q, out[m], st[m]));
    best[M_CGAL] = run(M_CGAL, d, n, q, out[M_CGAL], st[M_CGAL]);

    size_t degenerate = 0;
    for (size_t i = 0; i < n; ++i)
        degenerate += st[M_CGAL][i] != GV_OK;
    const errs eg = measure(n, out[M_GEOM], st[M_GEOM], out[M_CGAL], st[M_CGAL]);
    const errs en = measure(n, out[M_NAIVE], st[M_NAIVE], out[M_CGAL], st[M_CGAL]);
    const double ng = 1e9 * best[M_GEOM] / (double)n, nn = 1e9 * best[M_NAIVE] / (double)n;
    const double nc = 1e9 * best[M_CGAL] / (double)n;
    printf("| %s | %s | %zu (%zu degenerate) | %.1f | %.1f | %.2f | %.0f | %.3g | %.3g | %.3g | %.3g |\n", fn,
           input, n, degenerate, ng, nn, ng / nn, nc, eg.rel, en.rel, eg.ulp, en.ulp);
    fflush(stdout);
    for (int m = 0; m < M_COUNT; ++m) {
        free(out[m]);
        free(st[m]);
    }
    free(q);
}

int main(int argc, char **argv)
{
    size_t n_random = 1000000, n_sliver = 100000;
    if (argc > 1)
        n_random = (size_t)strtoull(argv[1], NULL, 10);
    if (argc > 2)
        n_sliver = (size_t)strtoull(argv[2], NULL, 10);
    printf("bench_bary: geom_bary_tri2/tri3 (robust) vs the textbook formulas in double, errors "
           "against the exact answer computed with CGAL (Gmpzf, rounded once), same queries, same "
           "run.\n"
           "Times: best of 5 runs for geom and textbook, one run for CGAL. err/max|l|: max over "
           "coordinates of |l_i - exact_i| / max_j |exact_j|; ulp: max |l_i - exact_i| / "
           "ulp(exact_i).\n\n");
    printf("| function | input | queries | geom ns/query | textbook ns/query | time geom/textbook "
           "| CGAL exact ns/query | geom err/max\\|l\\| | textbook err/max\\|l\\| | geom max ulp "
           "| textbook max ulp |\n");
    printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
    bench("tri2", "random", 2, n_random, 0, 0x2d2d2d2dull);
    bench("tri2", "sliver+1e8", 2, n_sliver, 1, 0x51140e2dull);
    bench("tri3", "random", 3, n_random, 0, 0x3d3d3d3dull);
    bench("tri3", "sliver+1e8", 3, n_sliver, 1, 0x51140e3dull);
    return 0;
}
