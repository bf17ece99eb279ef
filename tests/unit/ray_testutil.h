/* Test helpers for the ray tests: an outward icosphere, a uniform random
 * number in [0, 1) from a xorshift64 state, whether the CPU has AVX2 and
 * FMA (ray_cpu_avx2), a ray from origin and direction over [0, inf]
 * (mkray) or [0, tmax] (mkray_to), and bitwise equality of hits
 * (ray_same_hit). */
#ifndef GEOM_TESTS_RAY_TESTUTIL_H
#define GEOM_TESTS_RAY_TESTUTIL_H

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "geom/ray.h"

/* The CPU has AVX2 and FMA (the mesh traversal's AVX2 path and packets). */
static inline int ray_cpu_avx2(void)
{
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
    return 0;
#endif
}

static inline double ray_urand(uint64_t *rng)
{
    *rng ^= *rng << 13;
    *rng ^= *rng >> 7;
    *rng ^= *rng << 17;
    return (double)(*rng >> 11) * 0x1p-53;
}

/* A ray from origin o and direction d over [0, tmax]. */
static inline geom_ray mkray_to(double ox, double oy, double oz, double dx, double dy, double dz,
                                double tmax)
{
    geom_ray r;
    r.origin = geom_vec3_make(ox, oy, oz);
    r.dir = geom_vec3_make(dx, dy, dz);
    r.tmin = 0;
    r.tmax = tmax;
    return r;
}

static inline geom_ray mkray(double ox, double oy, double oz, double dx, double dy, double dz)
{
    return mkray_to(ox, oy, oz, dx, dy, dz, INFINITY);
}

/* Two hits equal bit for bit, field by field (no padding compared). */
static inline int ray_same_hit(const geom_ray_hit *a, const geom_ray_hit *b)
{
    return memcmp(&a->t, &b->t, sizeof a->t) == 0 && memcmp(&a->point, &b->point, sizeof a->point) == 0 &&
           memcmp(&a->ng, &b->ng, sizeof a->ng) == 0 && memcmp(&a->ns, &b->ns, sizeof a->ns) == 0 &&
           memcmp(&a->u, &b->u, sizeof a->u) == 0 && memcmp(&a->v, &b->v, sizeof a->v) == 0 &&
           a->prim == b->prim && a->object == b->object && a->enter == b->enter &&
           memcmp(&a->t_error, &b->t_error, sizeof a->t_error) == 0 &&
           memcmp(&a->p_error, &b->p_error, sizeof a->p_error) == 0;
}

typedef struct tmesh {
    double *p;
    uint32_t *t;
    size_t nv, nt;
} tmesh;

/* Target i of the watertightness rays: vertex i for i < nv, else the
 * midpoint of edge (i - nv) % 3 of triangle (i - nv) / 3. */
static inline void tmesh_target(const tmesh *m, size_t i, double tgt[3])
{
    if (i < m->nv) {
        memcpy(tgt, m->p + 3 * i, 3 * sizeof(double));
    } else {
        size_t t = (i - m->nv) / 3, e = (i - m->nv) % 3;
        const double *a = m->p + 3 * m->t[3 * t + e], *b = m->p + 3 * m->t[3 * t + (e + 1) % 3];
        int k;
        for (k = 0; k < 3; k++) tgt[k] = 0.5 * (a[k] + b[k]);
    }
}

static inline uint32_t midpoint(tmesh *m, uint32_t a, uint32_t b, uint32_t *cache, size_t cap)
{
    /* cache: pairs (a, b, v) linear search (small meshes) */
    size_t i;
    uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
    for (i = 0; i < cap && cache[3 * i + 2] != UINT32_MAX; i++)
        if (cache[3 * i] == lo && cache[3 * i + 1] == hi) return cache[3 * i + 2];
    {
        double *q = m->p + 3 * m->nv, l;
        int k;
        for (k = 0; k < 3; k++) q[k] = 0.5 * (m->p[3 * a + k] + m->p[3 * b + k]);
        l = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
        for (k = 0; k < 3; k++) q[k] /= l;
        cache[3 * i] = lo;
        cache[3 * i + 1] = hi;
        cache[3 * i + 2] = (uint32_t)m->nv;
        if (i + 1 < cap) cache[3 * (i + 1) + 2] = UINT32_MAX;
        return (uint32_t)m->nv++;
    }
}

static inline tmesh icosphere(int levels)
{
    static const double X = 0.525731112119133606, Z = 0.850650808352039932;
    static const double v0[12][3] = {{-X, 0, Z}, {X, 0, Z}, {-X, 0, -Z}, {X, 0, -Z}, {0, Z, X}, {0, Z, -X},
                                     {0, -Z, X}, {0, -Z, -X}, {Z, X, 0}, {-Z, X, 0}, {Z, -X, 0}, {-Z, -X, 0}};
    static const uint32_t f0[20][3] = {{0, 4, 1}, {0, 9, 4}, {9, 5, 4}, {4, 5, 8}, {4, 8, 1}, {8, 10, 1}, {8, 3, 10},
                                       {5, 3, 8}, {5, 2, 3}, {2, 7, 3}, {7, 10, 3}, {7, 6, 10}, {7, 11, 6}, {11, 0, 6},
                                       {0, 1, 6}, {6, 1, 10}, {9, 0, 11}, {9, 11, 2}, {9, 2, 5}, {7, 2, 11}};
    tmesh m;
    size_t maxv = 12, maxt = 20;
    int l;
    for (l = 0; l < levels; l++) {
        maxv += maxt * 3 / 2;
        maxt *= 4;
    }
    m.p = malloc(maxv * 3 * sizeof(double));
    m.t = malloc(maxt * 3 * sizeof(uint32_t));
    memcpy(m.p, v0, sizeof v0);
    for (l = 0; l < 20; l++) { /* the classic list is clockwise: make it outward */
        m.t[3 * l] = f0[l][0];
        m.t[3 * l + 1] = f0[l][2];
        m.t[3 * l + 2] = f0[l][1];
    }
    m.nv = 12;
    m.nt = 20;
    for (l = 0; l < levels; l++) {
        uint32_t *nt = malloc(m.nt * 4 * 3 * sizeof(uint32_t));
        size_t cap = m.nt * 3, i;
        uint32_t *cache = malloc(cap * 3 * sizeof(uint32_t));
        cache[2] = UINT32_MAX;
        for (i = 0; i < m.nt; i++) {
            uint32_t a = m.t[3 * i], b = m.t[3 * i + 1], c = m.t[3 * i + 2];
            uint32_t ab = midpoint(&m, a, b, cache, cap), bc = midpoint(&m, b, c, cache, cap),
                     ca = midpoint(&m, c, a, cache, cap);
            uint32_t f[12] = {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca};
            memcpy(nt + 12 * i, f, sizeof f);
        }
        free(cache);
        free(m.t);
        m.t = nt;
        m.nt *= 4;
    }
    return m;
}

#endif
