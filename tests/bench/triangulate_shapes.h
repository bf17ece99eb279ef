/*
 * The polygons of the triangulation benchmarks (bench_triangulate.c and its
 * CGAL peer bench_triangulate_cgal.cpp): each writes at most n vertices
 * (x, y pairs) of a counter-clockwise polygon to xy and returns the count.
 * Valid C and C++.
 *
 *  star       random star-shaped, radii uniform in [0.2, 1]
 *  jagged     star with jittered angles, radii alternating 0.01-0.06 / 0.5-1
 *  spiral     a two-turn spiral arm of width 0.8
 *  comb       long thin teeth on an integer grid
 *  random     random simple polygon by space partitioning (Auer & Held 1996,
 *             "Heuristics for the generation of random polygons"): random
 *             points, a chain through each side of a random line, split
 *             recursively by random lines through a chosen point and a
 *             point of the current segment
 *  collinear  a square with n/4 integer points on each side, every 8th
 *             vertex repeated (collinear runs and duplicate vertices)
 *  holes      a square with n/12 square holes, each joined to the outer
 *             boundary by a bridge walked both ways (weakly simple, as
 *             geom_mesh_clip_plane's caps)
 */
#ifndef GEOM_BENCH_TRIANGULATE_SHAPES_H
#define GEOM_BENCH_TRIANGULATE_SHAPES_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>

#include "geom/core.h"

#define TS_PI 3.14159265358979323846

static inline uint64_t ts_lcg(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return *s >> 11;
}

static inline double ts_unif(uint64_t *s) { return (double)ts_lcg(s) * 0x1p-53; }

static inline size_t ts_star(size_t n, double *xy, uint64_t s)
{
    for (size_t i = 0; i < n; ++i) {
        double r = 0.2 + 0.8 * ts_unif(&s), th = 2 * TS_PI * (double)i / (double)n;
        xy[2 * i] = r * cos(th);
        xy[2 * i + 1] = r * sin(th);
    }
    return n;
}

static inline size_t ts_jagged(size_t n, double *xy, uint64_t s)
{
    for (size_t i = 0; i < n; ++i) {
        double th = 2 * TS_PI * ((double)i + 0.9 * ts_unif(&s)) / (double)n;
        double r = i % 2 ? 0.01 + 0.05 * ts_unif(&s) : 0.5 + 0.5 * ts_unif(&s);
        xy[2 * i] = r * cos(th);
        xy[2 * i + 1] = r * sin(th);
    }
    return n;
}

static inline size_t ts_spiral(size_t n, double *xy, uint64_t s)
{
    (void)s;
    size_t M = n / 2, k = 0;
    for (size_t j = 0; j < 2 * M; ++j) {
        size_t i = j < M ? j : 2 * M - 1 - j;
        double th = 4 * TS_PI * (double)i / (double)(M - 1), r = 1 + th / TS_PI + (j < M ? 0.4 : -0.4);
        xy[2 * k] = r * cos(th);
        xy[2 * k + 1] = r * sin(th);
        ++k;
    }
    return k;
}

static inline size_t ts_comb(size_t n, double *xy, uint64_t s)
{
    (void)s;
    size_t K = n / 4, m = 0;
#define TS_P(x, y) (xy[2 * m] = (double)(x), xy[2 * m + 1] = (double)(y), ++m)
    TS_P(0, 0);
    TS_P(2 * K - 1, 0);
    for (size_t i = K; i-- > 0;) {
        TS_P(2 * i + 1, 3);
        TS_P(2 * i, 3);
        if (i > 0) {
            TS_P(2 * i, 1);
            TS_P(2 * i - 1, 1);
        }
    }
#undef TS_P
    return m;
}

/* Chain from p to q (both excluded) through the points idx[0..k), appended
 * to out. */
static inline void ts_chain(const double *P, uint32_t p, uint32_t q, uint32_t *idx, size_t k,
                     uint32_t *out, size_t *no, uint64_t *s)
{
    while (k > 0) {
        size_t ri = (size_t)(ts_lcg(s) % k);
        uint32_t r = idx[ri];
        idx[ri] = idx[k - 1];
        k--;
        double t = 0.25 + 0.5 * ts_unif(s);
        double sp[2] = {P[2 * p] + t * (P[2 * q] - P[2 * p]),
                        P[2 * p + 1] + t * (P[2 * q + 1] - P[2 * p + 1])};
        double side = geom_orient2d(P + 2 * (size_t)r, sp, P + 2 * (size_t)p);
        size_t kp = 0;
        for (size_t i = 0; i < k; ++i) {
            double o = geom_orient2d(P + 2 * (size_t)r, sp, P + 2 * (size_t)idx[i]);
            if (o == 0.0 || (o > 0.0) == (side > 0.0)) {
                uint32_t w = idx[i];
                idx[i] = idx[kp];
                idx[kp++] = w;
            }
        }
        ts_chain(P, p, r, idx, kp, out, no, s);
        out[(*no)++] = r;
        /* tail: chain(r, q, idx + kp, k - kp) */
        p = r;
        idx += kp;
        k -= kp;
    }
}

/* scratch: P (2n doubles), idx and out (n each), caller-provided */
static inline size_t ts_random(size_t n, double *xy, uint64_t s, double *P, uint32_t *idx, uint32_t *out)
{
    for (size_t i = 0; i < n; ++i) {
        P[2 * i] = ts_unif(&s);
        P[2 * i + 1] = ts_unif(&s);
    }
    size_t kr = 0, kl = 0;
    for (size_t i = 2; i < n; ++i) /* right of 0 -> 1 first, then left */
        if (geom_orient2d(P, P + 2, P + 2 * i) < 0.0)
            idx[kr++] = (uint32_t)i;
    for (size_t i = 2; i < n; ++i)
        if (!(geom_orient2d(P, P + 2, P + 2 * i) < 0.0))
            idx[kr + kl++] = (uint32_t)i;
    size_t no = 0;
    out[no++] = 0;
    ts_chain(P, 0, 1, idx, kr, out, &no, &s);
    out[no++] = 1;
    ts_chain(P, 1, 0, idx + kr, kl, out, &no, &s);
    for (size_t i = 0; i < no; ++i) {
        xy[2 * i] = P[2 * (size_t)out[i]];
        xy[2 * i + 1] = P[2 * (size_t)out[i] + 1];
    }
    return no;
}

static inline size_t ts_collinear(size_t n, double *xy, uint64_t s)
{
    (void)s;
    size_t q = n / 4 - n / 32, m = 0, c = 0;
    for (int side = 0; side < 4; ++side)
        for (size_t i = 0; i < q; ++i) {
            double a = (double)i, b = (double)q;
            double x = side == 0 ? a : side == 1 ? b : side == 2 ? b - a : 0;
            double y = side == 0 ? 0 : side == 1 ? a : side == 2 ? b : b - a;
            int reps = c++ % 8 == 7 ? 2 : 1;
            for (int d = 0; d < reps && m < n; ++d)
                xy[2 * m] = x, xy[2 * m + 1] = y, ++m;
        }
    return m;
}

static inline size_t ts_holes(size_t n, double *xy, uint64_t s)
{
    (void)s;
    size_t k = (n - 4) / 8, m = 0;
    double W = 4.0 * (double)k;
#define TS_P(x, y) (xy[2 * m] = (x), xy[2 * m + 1] = (y), ++m)
    TS_P(0.0, 0.0);
    for (size_t h = 0; h < k; ++h) {
        double x0 = 4.0 * (double)h + 1.5;
        TS_P(x0, 0.0);
        TS_P(x0, 1.0);
        TS_P(x0 - 0.5, 1.0); /* the hole, clockwise */
        TS_P(x0 - 0.5, 2.0);
        TS_P(x0 + 0.5, 2.0);
        TS_P(x0 + 0.5, 1.0);
        TS_P(x0, 1.0);
        TS_P(x0, 0.0);
    }
    TS_P(W, 0.0);
    TS_P(W, 3.0);
    TS_P(0.0, 3.0);
#undef TS_P
    return m;
}

#endif
