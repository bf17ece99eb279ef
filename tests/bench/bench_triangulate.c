/*
 * bench_triangulate: time of geom_polygon_triangulate (ear clipping with
 * grid-bounded emptiness tests) on simple polygons of growing size: random
 * star-shaped polygons (radii uniform in [0.2, 1]), a two-turn spiral arm and
 * a comb with long thin teeth. For each: n, the time (best of 3), the
 * triangle count, whether every triangle is positively oriented by the exact
 * predicate, the smallest triangle quality (2 area / longest edge^2) and the
 * relative difference between the triangles' area sum and the polygon's.
 * There is no peer in this program; the quadratic ear clipper it replaces is
 * recorded in BENCHMARKS.md (94 s for 100k vertices before the change).
 *
 * Output: a Markdown table. Usage: bench_triangulate [NMAX] (default 100000).
 */
#define _POSIX_C_SOURCE 199309L

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "geom/core.h"
#include "geom/mesh.h"

#define PI 3.14159265358979323846

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static size_t star(size_t n, double *xy)
{
    uint64_t s = 12345;
    for (size_t i = 0; i < n; ++i) {
        s = s * 6364136223846793005ull + 1442695040888963407ull;
        double r = 0.2 + 0.8 * (double)(s >> 11) * 0x1p-53, th = 2 * PI * (double)i / (double)n;
        xy[2 * i] = r * cos(th);
        xy[2 * i + 1] = r * sin(th);
    }
    return n;
}

static size_t spiral(size_t n, double *xy)
{
    size_t M = n / 2, k = 0;
    for (size_t j = 0; j < 2 * M; ++j) {
        size_t i = j < M ? j : 2 * M - 1 - j;
        double th = 4 * PI * (double)i / (double)(M - 1), r = 1 + th / PI + (j < M ? 0.4 : -0.4);
        xy[2 * k] = r * cos(th);
        xy[2 * k + 1] = r * sin(th);
        ++k;
    }
    return k;
}

static size_t comb(size_t n, double *xy)
{
    size_t K = (n + 2) / 4, m = 0;
#define P(x, y) (xy[2 * m] = (double)(x), xy[2 * m + 1] = (double)(y), ++m)
    P(0, 0);
    P(2 * K - 1, 0);
    for (size_t i = K; i-- > 0;) {
        P(2 * i + 1, 3);
        P(2 * i, 3);
        if (i > 0) {
            P(2 * i, 1);
            P(2 * i - 1, 1);
        }
    }
#undef P
    return m;
}

int main(int argc, char **argv)
{
    size_t nmax = argc > 1 ? (size_t)strtoull(argv[1], NULL, 10) : 100000;
    if (nmax < 1000)
        nmax = 1000;
    double *xy = malloc(2 * nmax * sizeof(double)), *p = malloc(3 * nmax * sizeof(double));
    uint32_t *t = malloc(3 * nmax * sizeof(uint32_t));
    if (!xy || !p || !t)
        return 1;
    static const char *names[] = {"star", "spiral", "comb"};
    printf("| polygon | n | seconds (best of 3) | triangles | all positive | min quality | "
           "area rel. diff |\n|---|---|---|---|---|---|---|\n");
    for (int shape = 0; shape < 3; ++shape)
        for (size_t n0 = 1000; n0 <= nmax; n0 *= 10) {
            size_t n = shape == 0 ? star(n0, xy) : shape == 1 ? spiral(n0, xy) : comb(n0, xy);
            for (size_t i = 0; i < n; ++i) {
                p[3 * i] = xy[2 * i];
                p[3 * i + 1] = xy[2 * i + 1];
                p[3 * i + 2] = 0.0;
            }
            double best = INFINITY;
            geom_status st = GEOM_OK;
            for (int rep = 0; rep < 3; ++rep) {
                double t0 = now_s();
                st = geom_polygon_triangulate(n, p, t);
                double dt = now_s() - t0;
                best = dt < best ? dt : best;
            }
            int pos = st == GEOM_OK;
            double qmin = INFINITY, area = 0.0, want = 0.0;
            for (size_t k = 0; k + 2 < n; ++k) {
                const double *a = xy + 2 * t[3 * k], *b = xy + 2 * t[3 * k + 1],
                             *c = xy + 2 * t[3 * k + 2];
                double o = geom_orient2d(a, b, c);
                pos = pos && o > 0.0;
                area += 0.5 * o;
                double l = 0.0, e[3] = {hypot(b[0] - a[0], b[1] - a[1]),
                                        hypot(c[0] - b[0], c[1] - b[1]),
                                        hypot(a[0] - c[0], a[1] - c[1])};
                for (int j = 0; j < 3; ++j)
                    l = e[j] > l ? e[j] : l;
                double q = l > 0.0 ? fabs(o) / (l * l) : 0.0;
                qmin = q < qmin ? q : qmin;
            }
            for (size_t i = 0; i < n; ++i) {
                size_t j = (i + 1) % n;
                want += 0.5 * (xy[2 * i] * xy[2 * j + 1] - xy[2 * j] * xy[2 * i + 1]);
            }
            printf("| %s | %zu | %.4f | %zu | %s | %.3g | %.2g |\n", names[shape], n, best, n - 2,
                   pos ? "yes" : "NO", qmin, fabs(area - want) / fabs(want));
            fflush(stdout);
        }
    free(xy);
    free(p);
    free(t);
    return 0;
}
