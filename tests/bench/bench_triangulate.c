/*
 * bench_triangulate: time of geom_polygon_triangulate (above 64 vertices the
 * monotone-decomposition sweep, libgeom/src/mesh/triangulate_sweep.c) on the
 * polygons of triangulate_shapes.h at 10k, 100k and 1M vertices, next to the
 * library's ear clipper (grid-bounded emptiness tests, the path used before
 * the sweep and still its fallback; geom__polygon_earclip) on the same input
 * in the same run, up to 100k vertices (best of 3; one run at 100k; not
 * run at a size when it took more than 2 s of CPU at the previous one).
 *
 * Columns: n, the sweep's time (best of 3; wall clock and, in parentheses,
 * this process's CPU time: under load the CPU time is the steadier figure),
 * the ear clipper's, their ratio (CPU),
 * whether the sweep accepted the polygon (else the ear clipper ran) and how
 * many monotone pieces it handed to the ear clipper, the negative and the
 * zero-area triangles by the exact predicate (zero-area ones are forced only
 * by repeated vertices: "forced" counts those), the smallest triangle
 * quality (2 area / longest edge^2) of the sweep and of the ear clipper, and
 * the relative difference between the triangles' area sum and the polygon's
 * (compensated sums, relative to vertex 0).
 *
 * Output: a Markdown table. Usage: bench_triangulate [NMAX [NMIN]]
 * (defaults 1000000 and 10000; sizes NMIN, 10 NMIN, ... up to NMAX).
 */
#define _POSIX_C_SOURCE 199309L

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "../../libgeom/src/mesh/triangulate_internal.h"
#include "bench/triangulate_shapes.h"
#include "geom/core.h"
#include "geom/mesh.h"

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double cpu_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void nsum(double *s, double *c, double x)
{
    double t = *s + x;
    *c += fabs(*s) >= fabs(x) ? (*s - t) + x : (x - t) + *s;
    *s = t;
}

typedef struct stats {
    size_t neg, zero;
    double qmin, area_rel;
} stats;

static stats measure(size_t n, const double *xy, const uint32_t *t)
{
    stats r = {0, 0, INFINITY, 0.0};
    double as = 0, ac = 0, ps = 0, pc = 0;
    for (size_t k = 0; k + 2 < n; ++k) {
        const double *a = xy + 2 * t[3 * k], *b = xy + 2 * t[3 * k + 1], *c = xy + 2 * t[3 * k + 2];
        double o = geom_orient2d(a, b, c);
        r.neg += o < 0.0;
        r.zero += o == 0.0;
        double ux = b[0] - a[0], uy = b[1] - a[1], vx = c[0] - a[0], vy = c[1] - a[1];
        double ar = ux * vy - uy * vx;
        nsum(&as, &ac, 0.5 * ar);
        double l = fmax(ux * ux + uy * uy, fmax(vx * vx + vy * vy,
                                                (c[0] - b[0]) * (c[0] - b[0]) +
                                                    (c[1] - b[1]) * (c[1] - b[1])));
        double q = l > 0.0 ? fabs(ar) / l : 0.0;
        r.qmin = q < r.qmin ? q : r.qmin;
    }
    for (size_t i = 0; i < n; ++i) {
        size_t j = (i + 1) % n;
        double xi = xy[2 * i] - xy[0], yi = xy[2 * i + 1] - xy[1];
        double xj = xy[2 * j] - xy[0], yj = xy[2 * j + 1] - xy[1];
        nsum(&ps, &pc, 0.5 * xi * yj);
        nsum(&ps, &pc, -0.5 * xj * yi);
    }
    r.area_rel = fabs((as + ac) - (ps + pc)) / fabs(ps + pc);
    return r;
}

int main(int argc, char **argv)
{
    size_t nmax = argc > 1 ? (size_t)strtoull(argv[1], NULL, 10) : 1000000;
    size_t nmin = argc > 2 ? (size_t)strtoull(argv[2], NULL, 10) : 10000;
    if (nmin < 100)
        nmin = 100;
    if (nmax < nmin)
        nmax = nmin;
    double *xy = malloc(2 * nmax * sizeof(double)), *p = malloc(3 * nmax * sizeof(double));
    double *P = malloc(2 * nmax * sizeof(double));
    uint32_t *t = malloc(3 * nmax * sizeof(uint32_t)), *te = malloc(3 * nmax * sizeof(uint32_t));
    uint32_t *i1 = malloc(nmax * sizeof(uint32_t)), *i2 = malloc(nmax * sizeof(uint32_t));
    if (!xy || !p || !P || !t || !te || !i1 || !i2)
        return 1;
    static const char *names[] = {"star",   "jagged",    "spiral", "comb",
                                  "random", "collinear", "holes"};
    printf("| polygon | n | sweep s wall (cpu), best of 3 | ear clipper s wall (cpu) | ratio ear/sweep (cpu) | sweep "
           "accepted (pieces ear-clipped) | negative | zero-area (forced) | min quality sweep "
           "| min quality ear | area rel. diff |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
    double eprev = 0.0; /* the ear clipper's time at the previous size */
    for (int shape = 0; shape < 7; ++shape)
        for (size_t n0 = nmin; n0 <= nmax; n0 *= 10) {
            if (n0 == nmin)
                eprev = 0.0;
            size_t n = 0;
            switch (shape) {
            case 0: n = ts_star(n0, xy, 12345); break;
            case 1: n = ts_jagged(n0, xy, 777); break;
            case 2: n = ts_spiral(n0, xy, 0); break;
            case 3: n = ts_comb(n0, xy, 0); break;
            case 4: n = ts_random(n0, xy, 4242, P, i1, i2); break;
            case 5: n = ts_collinear(n0, xy, 0); break;
            default: n = ts_holes(n0, xy, 0); break;
            }
            size_t forced = 0;
            for (size_t i = 0; i < n; ++i) {
                size_t j = (i + 1) % n;
                forced += xy[2 * i] == xy[2 * j] && xy[2 * i + 1] == xy[2 * j + 1];
                p[3 * i] = xy[2 * i];
                p[3 * i + 1] = xy[2 * i + 1];
                p[3 * i + 2] = 0.0;
            }
            double best = INFINITY, cbest = INFINITY;
            geom_status st = GEOM_OK;
            for (int rep = 0; rep < 3; ++rep) {
                double t0 = now_s(), c0 = cpu_s();
                st = geom_polygon_triangulate(n, p, t);
                double dt = now_s() - t0, dc = cpu_s() - c0;
                best = dt < best ? dt : best;
                cbest = dc < cbest ? dc : cbest;
            }
            stats r = measure(n, xy, t);
            size_t pieces = 0;
            geom_status sw = geom__polygon_triangulate_sweep_ex(n, p, 0, 1, te, &pieces);
            double ebest = INFINITY, ecbest = INFINITY;
            stats re = {0, 0, NAN, 0.0};
            if (n <= 100000 && eprev < 2.0) {
                for (int rep = 0; rep < (n >= 100000 ? 1 : 3); ++rep) {
                    double t0 = now_s(), c0 = cpu_s();
                    (void)geom__polygon_earclip(n, p, te);
                    double dt = now_s() - t0, dc = cpu_s() - c0;
                    ebest = dt < ebest ? dt : ebest;
                    ecbest = dc < ecbest ? dc : ecbest;
                }
                re = measure(n, xy, te);
            }
            eprev = ecbest;
            char es[32] = "-", ra[32] = "-";
            if (isfinite(ebest)) {
                snprintf(es, sizeof es, "%.4f (%.4f)", ebest, ecbest);
                snprintf(ra, sizeof ra, "%.1f", ecbest / cbest);
            }
            printf("| %s | %zu | %.4f (%.4f) | %s | %s | %s (%zu) | %zu | %zu (%zu) | %.3g | %.3g | %.2g |%s\n",
                   names[shape], n, best, cbest, es, ra, sw == GEOM_OK ? "yes" : "no", pieces, r.neg,
                   r.zero, forced, r.qmin, re.qmin, r.area_rel,
                   st == GEOM_OK ? "" : " status not OK");
            fflush(stdout);
        }
    free(xy);
    free(p);
    free(P);
    free(t);
    free(te);
    free(i1);
    free(i2);
    return 0;
}
