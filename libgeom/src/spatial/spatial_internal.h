/* Private to the spatial module. */
#ifndef GEOM_SRC_SPATIAL_INTERNAL_H
#define GEOM_SRC_SPATIAL_INTERNAL_H

#include "core/internal.h"
#include "geom/spatial.h"

#include <stdint.h>

#ifdef GEOM_SPATIAL_OPENMP
#include <omp.h>
#endif

/* Thread count for a parallel region: 0 = all available. */
static inline int geom__spatial_threads(int threads)
{
#ifdef GEOM_SPATIAL_OPENMP
    return threads > 0 ? threads : omp_get_max_threads();
#else
    (void)threads;
    return 1;
#endif
}

/* A primitive reference during a BVH build: its box and its index. */
typedef struct geom__bvh_ref {
    double lo[3], hi[3];
    uint32_t id;
    uint32_t pad;
} geom__bvh_ref;

/* Temporary binary node of a build (before the depth-first flattening). */
typedef struct geom__bvh_tmp {
    geom_aabb box;
    uint32_t left, right; /* temp node ids; leaf: UINT32_MAX */
    uint32_t start, count;
    uint32_t axis;
    uint32_t pad;
} geom__bvh_tmp;

typedef struct geom__bvh_build {
    geom__bvh_ref *refs; /* LBVH only (the SAH build makes its own copy) */
    double scene_lo[3], scene_hi[3]; /* union of the primitive boxes */
    size_t n;
    geom__bvh_tmp *tmp; /* capacity 2n */
    size_t tmp_count;   /* atomically incremented */
    uint32_t max_leaf;
    uint32_t bins;
    int threads;
    const geom_allocator *alloc;
    uint32_t *order; /* set by a builder that consumes refs: the leaves'
                        primitive order (n entries, freed by the caller) */
    int preorder;    /* set by a builder that ran sequentially: the temp ids
                        are already the depth-first layout (left = id + 1) */
    /* Exact box of primitive i (a builder that consumes refs uses it). */
    void (*box_fn)(const void *src, size_t i, geom__bvh_ref *r);
    const void *src;
} geom__bvh_build;

struct geom_bvh {
    geom_allocator alloc;
    int has_alloc;
    geom_bvh_node *nodes;
    size_t node_count;
    uint32_t *prims;
    size_t prim_count;
    size_t depth;
};

/* Huge-page advice for the BVH builders' and meshdist's large arrays. */
#define GEOM__BVH_HUGE_MIN ((size_t)8 << 20)

/* Take a temp node slot (thread safe). */
uint32_t geom__bvh_tmp_new(geom__bvh_build *b);
/* Builders: fill b->tmp, return the root's temp id. */
uint32_t geom__bvh_build_sah(geom__bvh_build *b);
uint32_t geom__bvh_build_lbvh(geom__bvh_build *b);

/* Morton codes: 21 bits per axis interleaved (x lowest), and 2D with 32 bits. */
static inline uint64_t geom__morton_spread3(uint64_t v)
{
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffULL;
    v = (v | v << 16) & 0x1f0000ff0000ffULL;
    v = (v | v << 8) & 0x100f00f00f00f00fULL;
    v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
    v = (v | v << 2) & 0x1249249249249249ULL;
    return v;
}
static inline uint64_t geom__morton3(uint32_t x, uint32_t y, uint32_t z)
{
    return geom__morton_spread3(x) | geom__morton_spread3(y) << 1 | geom__morton_spread3(z) << 2;
}
static inline uint64_t geom__morton_spread2(uint64_t v)
{
    v &= 0xffffffffULL;
    v = (v | v << 16) & 0x0000ffff0000ffffULL;
    v = (v | v << 8) & 0x00ff00ff00ff00ffULL;
    v = (v | v << 4) & 0x0f0f0f0f0f0f0f0fULL;
    v = (v | v << 2) & 0x3333333333333333ULL;
    v = (v | v << 1) & 0x5555555555555555ULL;
    return v;
}

/* Sort (key, value) pairs by key then value (LSD radix sort, stable, so with
 * values given in increasing order the order is fully determined). keys and
 * vals are n entries; tmp space of the same size is allocated. */
geom_status geom__radix_sort64(const geom_allocator *a, uint64_t *keys, uint32_t *vals, size_t n);

#endif

/* ---- result rows (radius/box queries), filled per query, assembled in order */
typedef struct geom__hit {
    double d2; /* squared distance (or 0 for box queries) */
    uint32_t idx;
    uint32_t pad;
} geom__hit;

typedef struct geom__hits {
    geom__hit *h;
    size_t n, cap;
    const geom_allocator *a;
} geom__hits;

/* Append; returns 0 or -1 when out of memory. */
static inline int geom__hits_push(geom__hits *hs, uint32_t idx, double d2)
{
    if (hs->n == hs->cap &&
        geom__grow(hs->a, (void **)&hs->h, &hs->cap, hs->n + 1, sizeof *hs->h) != GEOM_OK)
        return -1;
    hs->h[hs->n].d2 = d2;
    hs->h[hs->n].idx = idx;
    hs->h[hs->n].pad = 0;
    hs->n++;
    return 0;
}

/* Sort hits[from..n) by (d2, idx). */
void geom__hits_sort(geom__hits *hs, size_t from);

/* Appends the answers of query q to h (sorted as they should be output);
 * returns GEOM_OK or GEOM_ERR_NOMEM. */
typedef geom_status (*geom__row_fn)(const void *ctx, size_t q, geom__hits *h);

/* Run fn over nq queries in parallel (chunks, assembled in query order) into
 * out; with_dist: 1 distance = sqrt(d2) of each hit, 2 distance = d2 as is,
 * 0 distance NULL. */
geom_status geom__batch_rows(const geom_allocator *a, size_t nq, geom__row_fn fn, const void *ctx,
                             int threads, int with_dist, geom_neighbors *out);

/* Squared distance in the one order every structure and test uses. */
static inline double geom__d2(const double *p, const double *q)
{
    double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
    return dx * dx + dy * dy + dz * dz;
}

/* Squared distance from p to triangle a b c (Ericson 5.1.5; a degenerate
 * triangle: to its nearest edge) and to segment a b (closest.c). */
double geom__closest_tri_d2(const double p[3], const double a[3], const double b[3],
                            const double c[3]);
double geom__closest_seg_d2(const double p[3], const double a[3], const double b[3]);

/* Bound on the squared distance a point within radius r can have
 * (sqrt(d2) <= r implies d2 <= this), for conservative pruning. */
static inline double geom__r2_bound(double r)
{
    return r * r * (1.0 + 0x1p-48) + 0x1p-1060;
}

/* First non-finite point among n points of dimension dim, or n. */
size_t geom__first_nonfinite(const double *p, size_t n, int dim);
/* The checks of a radius query's arguments (kd-tree and octree): radius r
 * finite and >= 0, every query finite. GEOM_OK or GEOM_ERR_INVALID_ARG with
 * the reason in diag. */
geom_status geom__radius_query_check(const double *queries, size_t nq, int dim, double r,
                                     geom_diag *diag);

/* ---- distance index over a triangle mesh (meshdist.c, winding.c) */
typedef struct geom__dipole {
    double c[3]; /* area-weighted centre */
    double n[3]; /* sum of area vectors (half cross products) */
    double area; /* sum of triangle areas */
    double r;    /* radius: every vertex of the subtree is within r of c */
    /* For the tighter error term of the signed distance (winding.c), all
     * upper bounds: dev = sum over triangles of |a_t - A_t nu| (a_t the area
     * vector, A_t its length, nu = n/|n|), i2 = integral of |x - c|^2 over
     * the surface, m1 = |integral of (x - c)| (0 up to rounding). */
    double dev, i2, m1;
} geom__dipole;

struct geom_meshdist {
    geom_allocator alloc;
    int has_alloc;
    double *pos;
    size_t nv;
    uint32_t *tris;
    size_t nt;
    geom_bvh *bvh;
    geom__dipole *dip; /* one per BVH node */
    double *tv;        /* 9 per triangle, in BVH primitive order (contiguous leaves) */
    double beta;
    double tolerance;  /* the option (0: none) */
    double area_total; /* total triangle area */
};

/* Signed solid angle of triangle (a, b, c) seen from q (Van Oosterom and
 * Strackee 1983), in steradians. */
double geom__solid_angle(const double q[3], const double a[3], const double b[3],
                         const double c[3]);

/* ---- quadtree / octree (octree.c, octree_query.c) */
struct geom_octree {
    geom_allocator alloc;
    int has_alloc;
    int dim;
    int points; /* items are points (kNN/radius allowed) */
    size_t n;
    uint32_t *items;  /* item index, tree order */
    double *ibox;     /* 6 per item in tree order: lo[3], hi[3] */
    geom_octree_node *nodes;
    size_t node_count, node_cap;
    size_t depth;
};

static inline const geom_allocator *geom__octree_alloc(const geom_octree *t)
{
    return t->has_alloc ? &t->alloc : NULL;
}

/* ---- k best (d2, index) pairs, ascending, for kNN */
typedef struct geom__kbest {
    double *d2;
    uint32_t *id;
    size_t k, count;
} geom__kbest;

static inline void geom__kbest_insert(geom__kbest *b, double d2, uint32_t id)
{
    size_t c = b->count;
    if (c == b->k) {
        double w = b->d2[c - 1];
        if (d2 > w || (d2 == w && id > b->id[c - 1]))
            return;
        c--;
    } else {
        b->count++;
    }
    while (c > 0 && (b->d2[c - 1] > d2 || (b->d2[c - 1] == d2 && b->id[c - 1] > id))) {
        b->d2[c] = b->d2[c - 1];
        b->id[c] = b->id[c - 1];
        c--;
    }
    b->d2[c] = d2;
    b->id[c] = id;
}

/* Squared distance from q to a box (a lower bound of the computed distance
 * of any point inside it). */
static inline double geom__box_d2(const geom_aabb *b, const double q[3])
{
    double lo[3] = {b->min.x, b->min.y, b->min.z}, hi[3] = {b->max.x, b->max.y, b->max.z};
    double s = 0;
    for (int k = 0; k < 3; k++) {
        double d = q[k] < lo[k] ? lo[k] - q[k] : q[k] > hi[k] ? q[k] - hi[k] : 0.0;
        s += d * d;
    }
    return s;
}

/* Run kNN for nq queries: one(ctx, q[3], best) fills best; results written
 * as geom_kdtree_knn documents. */
typedef void (*geom__knn_fn)(const void *ctx, const double q[3], geom__kbest *b);
geom_status geom__knn_batch(const geom_allocator *a, const void *ctx, geom__knn_fn one, int dim,
                            size_t n, const double *queries, size_t nq, size_t k, uint32_t *index,
                            double *distance, int threads, geom_diag *diag);

/* Query q of a dim-strided array as 3 doubles (z = 0 in 2D). */
static inline void geom__load_query(const double *qs, size_t q, int dim, double out[3])
{
    out[0] = qs[(size_t)dim * q];
    out[1] = qs[(size_t)dim * q + 1];
    out[2] = dim == 3 ? qs[3 * q + 2] : 0.0;
}
