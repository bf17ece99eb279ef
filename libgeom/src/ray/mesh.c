/* Triangle meshes through the spatial module's BVH: conservative slab tests
 * (Ize, "Robust BVH Ray Traversal", JCGT 2013: the far distance widened by
 * 2 gamma(3), the near one narrowed alike) with ordered traversal, and the
 * watertight triangle test (wbw.h).
 *
 * The binary BVH is collapsed once, at build time, into an 8-wide BVH owned
 * by this module (Wald, Benthin and Boulos, "Getting Rid of Packets", 2008;
 * Dammertz et al., "Shallow Bounding Volume Hierarchies", 2008): the wide
 * node repeatedly opens the child of largest surface area, and holds its
 * eight children's boxes quantized to 8 bits per plane relative to the
 * node's own box (Ylitie, Karras and Laine 2017), each plane rounded outward
 * from a float box itself rounded outward from the exact double box, and
 * checked at build in the traversal's own float arithmetic: every decoded
 * box contains the exact one, so the tree stays conservative
 * (test_ray_mesh_prefilter: test_quantized_boxes fails otherwise). The eight
 * slabs are computed in float SSE2 from the decoded planes, four lanes at a
 * time, with bounds that cover the float arithmetic and the ray's rounding
 * to float (w4f_node), or in double from the decoded floats exactly
 * converted with Ize's bounds (w4d_node: rays or boxes beyond 2^60, targets
 * without SSE2). A node is 128 bytes, two cache lines: the boxes in the
 * first, the children in the second (W4_W lanes; 8 measured faster than 4
 * in bench_ray, the tree being about half as deep; the quantized node of
 * half the bytes of the float one it replaced). A box beyond the float
 * range (a vertex beyond about 3.4e38) cannot be quantized: the binary tree
 * is then traversed. When rounding to
 * float would grow the boxes' total surface by more than 5 % (a mesh far
 * from the origin for its size) the wide tree is not built and the binary
 * double-precision tree is traversed. A ray tests the eight boxes of a node
 * in one pass with its precomputed reciprocal direction and per-axis
 * near/far planes chosen by the direction's sign, visits the hit children
 * nearest first, and skips a popped child whose entry distance is beyond the
 * closest hit so far; a single hit child is visited next without the
 * stack. Triangles are stored in leaf order (9 doubles each), so a leaf is
 * one contiguous run, and a hit is filled from that copy. Each leaf (at most
 * 4 triangles; the wide tree is not built otherwise) also has a packet of
 * its vertices in float (geom__rpack4, 144 bytes: half the bytes of the
 * doubles): on float-path rays a conservative SSE2 pre-test of the four
 * triangles at once (pk_filter, Woop's shear in float with a proven bound on
 * the difference to the double edge functions) drops the triangles it
 * proves missed, and only the others (about one per leaf a ray really
 * crosses) go through the exact watertight test, which alone decides. */
#include "ray/ray_internal.h"
#include "ray/wbw.h"
#include "geom/spatial.h"

#include <stddef.h>

#if defined(__SSE2__) || defined(_M_X64)
#include <emmintrin.h>
#define W4_SSE 1
#else
#define W4_SSE 0
#endif

/* An AVX2 + FMA copy of the wide traversal (all eight lanes of a node in
 * one 256-bit test), compiled with a target attribute in this file and
 * chosen once per tree at build time from the CPU (W4_ISA_AVX2 in
 * geom__rbvh4.isa); the SSE2 traversal stays for other CPUs. Both are
 * conservative (the AVX2 node test in the ray-side form, w8_node_rs, with
 * its own bound) and the exact watertight test alone decides, so they give
 * the same hits (test_ray_simd_paths forces each path and compares them bit
 * for bit, and with brute force). */
#if W4_SSE && defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define W4_AVX2 1
#define W4_TGT __attribute__((target("avx2,fma")))
#else
#define W4_AVX2 0
#endif
#define W4_ISA_SSE2 0
#define W4_ISA_AVX2 1

/* One wide node (W4_W lanes): lane j is a child box [lo[.][j], hi[.][j]]; count[j] > 0
 * is a leaf holding the triangle slots child[j] .. child[j] + count[j],
 * count[j] == 0 an inner node child[j] (GEOM_INVALID_INDEX: empty lane,
 * whose box is empty so that no ray hits it). */
/* Lanes per node (a multiple of 4: the SSE2 test takes four at a time). */
#define W4_W 8

/* The boxes are quantized (Ylitie, Karras and Laine, "Efficient Incoherent
 * Ray Traversal on GPUs Through Compressed Wide BVHs", HPG 2017): on axis k
 * lane j spans [px[k] + qlo[k][j] 2^ex[k], px[k] + qhi[k][j] 2^ex[k]], each
 * bound decoded in float exactly as the traversal does it (w4_dec: the
 * product is exact, 8 bits times a power of two not below 2^-100, so one
 * rounding, fused or not). The builder rounds each bound outward and checks
 * the decoded float against the float box (itself rounded outward from the
 * exact double box), stepping the 8-bit code outward until it contains it:
 * the decoded box always contains the exact one (test_ray_mesh_quant). The
 * first cache line holds the boxes, the second the children: 128 bytes. */
typedef struct geom__rnode4 {
    float px[3];
    int8_t ex[3];
    uint8_t pad;
    uint8_t qlo[3][W4_W], qhi[3][W4_W];
    uint32_t child[W4_W];
    uint32_t count[W4_W];
} geom__rnode4;

/* w4f_node decodes two halves of four lanes. */
typedef char w4_width_is_8[W4_W == 8 ? 1 : -1];

/* A node's boxes in float while it is built (rounded outward). */
typedef struct w4fbox {
    float lo[3][W4_W], hi[3][W4_W];
} w4fbox;

/* A leaf's triangles in float for the conservative pre-test (pk_filter):
 * v[vertex][axis][lane], each coordinate rounded to nearest; lanes past the
 * leaf's count are zero (masked off). 144 bytes, 16-byte aligned. */
typedef struct geom__rpack4 {
    float v[3][3][4];
} geom__rpack4;

/* A leaf lane's count[j]: the triangle count (1..4) in the low 3 bits and
 * its packet's index above them. */
#define W4_LEAF(cnt, pk) ((uint32_t)(cnt) | ((uint32_t)(pk) << 3))
#define W4_CNT(c) ((c) & 7u)
#define W4_PK(c) ((c) >> 3)

struct geom__rbvh4 {
    geom__rnode4 *node; /* 64-byte aligned, inside mem */
    void *mem;
    size_t n, cap;
    geom__rpack4 *pk;   /* one packet per leaf, 64-byte aligned, inside pkmem */
    void *pkmem;
    size_t npk, pkcap;
    double mag;         /* largest |coordinate| of a vertex (a float: rounded up; at most
                           2^60 when fbox, the only case the packets are read) */
    double area_d, area_f; /* total half-area of the lanes' boxes: exact, rounded to float */
    int fbox;              /* every float box coordinate within +-W4_FMAX: the float slab test may run */
    int isa;               /* W4_ISA_AVX2: the AVX2 traversal (the CPU has AVX2 and FMA), else SSE2 */
    double pmax;           /* largest |px + q 2^ex| over the nodes' planes (q in 0..255), exact */
};

/* The float slab test (w4_sse) runs for a ray when the boxes, the origin and
 * the reciprocal direction are all within +-2^60 (zero direction components
 * excepted): no product or difference can then overflow a float (a decoded
 * quantized plane lies at most a few 8-bit steps, each below 2^60 / 32,
 * outside its float box: within 2^61, differences within 2^62, products
 * within 2^122). */
#define W4_FMAX 1152921504606846976.0 /* 2^60 */

/* Start loading a node or a leaf's triangles before they are needed: the
 * traversal is bound by memory latency, and the children hit by a ray are
 * known one step before they are visited. */
#if defined(__GNUC__) || defined(__clang__)
#define W4_PREFETCH(p) __builtin_prefetch((const void *)(p), 0, 3)
#else
#define W4_PREFETCH(p) ((void)(p))
#endif

/* The lowest set bit of a nonzero lane mask. */
static inline int w4_ctz(unsigned m)
{
#if defined(__GNUC__) || defined(__clang__)
    return __builtin_ctz(m);
#else
    int j = 0;
    for (; !(m & 1u); m >>= 1) j++;
    return j;
#endif
}

/* Ask for transparent huge pages on a large traversal array from the
 * default allocator, before its first touch: random rays reach any node
 * and any leaf, and 4 KiB pages then miss the TLB on most of them. Advice
 * only; a caller's allocator is left alone. */
/* Traversal stack entries per query; a wide tree deeper than
 * (W4_STACK - W4_W) / (W4_W - 1) levels is not built (the binary traversal is used). */
#define W4_STACK 512

static double half_area(const geom_aabb *b)
{
    double dx = b->max.x - b->min.x, dy = b->max.y - b->min.y, dz = b->max.z - b->min.z;
    return dx * dy + dy * dz + dz * dx;
}

static void wide_free(struct geom__rbvh4 *w, const geom_allocator *alloc)
{
    if (!w) return;
    if (w->mem) geom__free(alloc, w->mem, (w->cap + 1) * sizeof *w->node);
    if (w->pkmem) geom__free(alloc, w->pkmem, w->pkcap * sizeof *w->pk + 64);
    geom__free(alloc, w, sizeof *w);
}

/* x rounded to a float toward -inf (down) or +inf (up); beyond the float
 * range the result is +-FLT_MAX or +-inf, still on the right side (the
 * range is checked first: converting an out-of-range double is undefined). */
static float f_down(double x)
{
    float f;
    if (x > FLT_MAX) return FLT_MAX;
    if (x < -FLT_MAX) return -INFINITY;
    f = (float)x;
    if ((double)f > x) f = nextafterf(f, -INFINITY);
    return f;
}
static float f_up(double x)
{
    float f;
    if (x > FLT_MAX) return INFINITY;
    if (x < -FLT_MAX) return -FLT_MAX;
    f = (float)x;
    if ((double)f < x) f = nextafterf(f, INFINITY);
    return f;
}

/* f_up and f_down without a library call in the common range: x scaled
 * away from zero by 2^-22 before rounding to nearest (relative error at most
 * 2^-24) lands on the right side of x. */
static inline float f_up_fast(double x)
{
    if (x >= 0x1p-100 && x <= 0x1p100) return (float)(x * (1 + 0x1p-22));
    if (x <= -0x1p-100 && x >= -0x1p100) return (float)(x * (1 - 0x1p-22));
    return x == 0 ? 0.0f : f_up(x);
}
#if W4_SSE /* read by the float traversal only */
static inline float f_down_fast(double x)
{
    if (x >= 0x1p-100 && x <= 0x1p100) return (float)(x * (1 - 0x1p-22));
    if (x <= -0x1p-100 && x >= -0x1p100) return (float)(x * (1 + 0x1p-22));
    return x == 0 ? 0.0f : f_down(x);
}
#endif

static void lane_set(struct geom__rbvh4 *w, geom__rnode4 *q, w4fbox *fq, int j, const geom_aabb *b,
                     uint32_t child, uint32_t count)
{
    const double *lo = &b->min.x, *hi = &b->max.x;
    int k;
    for (k = 0; k < 3; k++) {
        fq->lo[k][j] = f_down(lo[k]);
        fq->hi[k][j] = f_up(hi[k]);
    }
    q->child[j] = child;
    q->count[j] = count;
    if (child != GEOM_INVALID_INDEX) {
        for (k = 0; k < 3; k++)
            if (!(fq->lo[k][j] >= -W4_FMAX && fq->hi[k][j] <= W4_FMAX)) w->fbox = 0;
        geom_aabb fb;
        fb.min.x = fq->lo[0][j]; fb.min.y = fq->lo[1][j]; fb.min.z = fq->lo[2][j];
        fb.max.x = fq->hi[0][j]; fb.max.y = fq->hi[1][j]; fb.max.z = fq->hi[2][j];
        w->area_d += half_area(b);
        w->area_f += half_area(&fb);
    }
}

/* 2^e as a float, e in [-100, 119]. */
static inline float w4_pow2(int e)
{
    union { uint32_t u; float f; } c;
    c.u = (uint32_t)(e + 127) << 23;
    return c.f;
}

/* The decoded bound px + q 2^e, as the traversal computes it. */
static inline float w4_dec(float px, float s, unsigned q)
{
#if W4_SSE
    return _mm_cvtss_f32(_mm_add_ss(_mm_set_ss(px), _mm_mul_ss(_mm_set_ss((float)q), _mm_set_ss(s))));
#else
    volatile float r = px + (float)q * s; /* stored: no excess precision */
    return r;
#endif
}

/* Quantize node q's float boxes fq (lanes with a child); 0 when a bound is
 * not finite or needs a scale beyond 2^119 (the wide tree is then not
 * built). */
static int quantize(geom__rnode4 *q, const w4fbox *fq)
{
    int k, j;
    for (k = 0; k < 3; k++) {
        float plo = INFINITY, phi = -INFINITY, s;
        int e;
        for (j = 0; j < W4_W; j++) {
            q->qlo[k][j] = 0;
            q->qhi[k][j] = 0;
            if (q->child[j] == GEOM_INVALID_INDEX) continue;
            if (fq->lo[k][j] < plo) plo = fq->lo[k][j];
            if (fq->hi[k][j] > phi) phi = fq->hi[k][j];
        }
        if (plo > phi) { plo = phi = 0; } /* no child (cannot happen) */
        if (!(fabsf(plo) <= FLT_MAX && fabsf(phi) <= FLT_MAX)) return 0;
        frexp(((double)phi - (double)plo) / 255, &e);
        if (e < -100) e = -100;
        for (;; e++) {
            if (e > 119) return 0;
            if (w4_dec(plo, w4_pow2(e), 255) >= phi) break;
        }
        s = w4_pow2(e);
        q->px[k] = plo;
        q->ex[k] = (int8_t)e;
        for (j = 0; j < W4_W; j++) {
            double a, b;
            unsigned ql, qh;
            if (q->child[j] == GEOM_INVALID_INDEX) continue;
            a = floor(((double)fq->lo[k][j] - plo) / s);
            b = ceil(((double)fq->hi[k][j] - plo) / s);
            ql = a < 0 ? 0u : a > 255 ? 255u : (unsigned)a;
            qh = b < 0 ? 0u : b > 255 ? 255u : (unsigned)b;
            while (ql > 0 && w4_dec(plo, s, ql) > fq->lo[k][j]) ql--;
            while (qh < 255 && w4_dec(plo, s, qh) < fq->hi[k][j]) qh++;
            if (!(w4_dec(plo, s, ql) <= fq->lo[k][j] && w4_dec(plo, s, qh) >= fq->hi[k][j])) return 0;
            q->qlo[k][j] = (uint8_t)ql;
            q->qhi[k][j] = (uint8_t)qh;
        }
    }
    return 1;
}

/* w->pmax covers the planes of node q, every code 0..255 (exact: px and
 * 255 2^ex are floats, their sum rounded up in magnitude below is an upper
 * bound). */
static void note_planes(struct geom__rbvh4 *w, const geom__rnode4 *q)
{
    int k;
    for (k = 0; k < 3; k++) {
        double a = fabs((double)q->px[k]), b = fabs((double)q->px[k] + 255.0 * ldexp(1.0, q->ex[k]));
        double m = (a > b ? a : b) * (1 + 0x1p-50);
        if (m > w->pmax) w->pmax = m;
    }
}

/* The packet of the leaf holding slots first .. first + count - 1 of m->tv
 * (count <= 4): its index, or -1 when there is no room (cannot happen). */
static long pack_leaf(struct geom__rbvh4 *w, const double *tv, uint32_t first, uint32_t count)
{
    geom__rpack4 *p;
    uint32_t i;
    int a, k;
    if (w->npk >= w->pkcap || count > 4) return -1;
    p = &w->pk[w->npk];
    memset(p, 0, sizeof *p);
    for (i = 0; i < count; i++)
        for (a = 0; a < 3; a++)
            for (k = 0; k < 3; k++) {
                double x = tv[9 * ((size_t)first + i) + 3 * (size_t)a + (size_t)k];
                /* beyond 2^60 the float boxes are too (fbox == 0): the
                 * packets are then never read */
                p->v[a][k][i] = fabs(x) <= W4_FMAX ? (float)x : 0.0f;
                if (!(fabs(x) <= w->mag)) w->mag = (double)f_up(fabs(x));
            }
    return (long)w->npk++;
}

/* The fastest traversal this CPU runs (W4_ISA_*). */
static int isa_best(void)
{
#if W4_AVX2
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return W4_ISA_AVX2;
#endif
    return W4_ISA_SSE2;
}

/* Collapse the binary BVH into *out (NULL when the wide tree would be too
 * deep for the traversal stack, or a leaf holds more than 4 triangles). */
static geom_status wide_build(const geom_bvh *b, const double *tv, const geom_allocator *alloc,
                              struct geom__rbvh4 **out)
{
    size_t nn = 0, head = 0, tail = 0, maxd = 0, i, nleaf = 0;
    long pk;
    const geom_bvh_node *bn = geom_bvh_nodes(b, &nn);
    struct geom__rbvh4 *w;
    uint32_t *qb, *qw, *qd;
    geom_aabb empty;
    geom_status st = GEOM_OK;
    int qfail = 0; /* a node's boxes cannot be quantized: the binary tree is traversed */
    *out = NULL;
    if (nn == 0) return GEOM_OK;
    for (i = 0; i < nn; i++) {
        if (bn[i].count > 4) return GEOM_OK; /* no packet for it: the binary tree is traversed */
        nleaf += bn[i].count > 0;
    }
    empty.min.x = empty.min.y = empty.min.z = INFINITY;
    empty.max.x = empty.max.y = empty.max.z = -INFINITY;
    w = geom__alloc(alloc, sizeof *w);
    if (!w) return GEOM_ERR_NOMEM;
    memset(w, 0, sizeof *w);
    w->fbox = 1;
    w->cap = nn;
    w->n = 1;
    w->mem = geom__alloc(alloc, (w->cap + 1) * sizeof *w->node);
    if (w->mem) w->node = (geom__rnode4 *)(((uintptr_t)w->mem + 63) & ~(uintptr_t)63);
    w->pkcap = nleaf;
    w->pkmem = geom__alloc(alloc, w->pkcap * sizeof *w->pk + 64);
    if (w->pkmem) {
        w->pk = (geom__rpack4 *)(((uintptr_t)w->pkmem + 63) & ~(uintptr_t)63);
        geom__advise_huge(alloc, w->pkmem, w->pkcap * sizeof *w->pk + 64, (size_t)2 << 20);
    }
    qb = geom__alloc(alloc, 3 * nn * sizeof(uint32_t));
    if (!w->mem || !w->pkmem || !qb) {
        if (qb) geom__free(alloc, qb, 3 * nn * sizeof(uint32_t));
        wide_free(w, alloc);
        return GEOM_ERR_NOMEM;
    }
    qw = qb + nn;
    qd = qw + nn;
    if (bn[0].count > 0) { /* a single leaf */
        int j;
        pk = pack_leaf(w, tv, bn[0].index, bn[0].count);
        if (pk < 0) { st = GEOM_ERR_LIMIT; goto done; } /* cannot happen */
        w4fbox fq;
        lane_set(w, &w->node[0], &fq, 0, &bn[0].box, bn[0].index, W4_LEAF(bn[0].count, pk));
        for (j = 1; j < W4_W; j++) lane_set(w, &w->node[0], &fq, j, &empty, GEOM_INVALID_INDEX, 0);
        if (!quantize(&w->node[0], &fq)) { qfail = 1; goto done; }
        note_planes(w, &w->node[0]);
        maxd = 1;
    } else {
        qb[tail] = 0; qw[tail] = 0; qd[tail] = 1; tail++;
    }
    while (head < tail) {
        uint32_t bi = qb[head], wi = qw[head], d = qd[head];
        uint32_t list[W4_W];
        w4fbox fq;
        int nl = 2, j;
        head++;
        if (d > maxd) maxd = d;
        list[0] = bi + 1;
        list[1] = bn[bi].index;
        while (nl < W4_W) {
            int best = -1;
            double ba = -1;
            for (j = 0; j < nl; j++) {
                double a;
                if (bn[list[j]].count > 0) continue;
                a = half_area(&bn[list[j]].box);
                if (a > ba) { ba = a; best = j; }
            }
            if (best < 0) break;
            {
                uint32_t c = list[best];
                list[best] = c + 1;
                list[nl++] = bn[c].index;
            }
        }
        for (j = 0; j < W4_W; j++) {
            geom__rnode4 *q = &w->node[wi];
            if (j >= nl) { lane_set(w, q, &fq, j, &empty, GEOM_INVALID_INDEX, 0); continue; }
            if (bn[list[j]].count > 0) {
                pk = pack_leaf(w, tv, bn[list[j]].index, bn[list[j]].count);
                if (pk < 0 || (size_t)pk >= ((size_t)1 << 29)) { st = GEOM_ERR_LIMIT; goto done; } /* cannot happen */
                lane_set(w, q, &fq, j, &bn[list[j]].box, bn[list[j]].index, W4_LEAF(bn[list[j]].count, pk));
            } else {
                if (w->n >= w->cap || tail >= nn) { st = GEOM_ERR_LIMIT; goto done; } /* cannot happen */
                lane_set(w, q, &fq, j, &bn[list[j]].box, (uint32_t)w->n, 0);
                qb[tail] = list[j]; qw[tail] = (uint32_t)w->n; qd[tail] = d + 1; tail++;
                w->n++;
            }
        }
        if (!quantize(&w->node[wi], &fq)) { qfail = 1; goto done; }
        note_planes(w, &w->node[wi]);
    }
done:
    geom__free(alloc, qb, 3 * nn * sizeof(uint32_t));
    if (st != GEOM_OK || qfail || (W4_W - 1) * maxd + W4_W > W4_STACK || !(w->area_f <= 1.05 * w->area_d)) {
        wide_free(w, alloc);
        return st;
    }
    /* Keep only the nodes made (about a third of the binary node count). */
    if (w->n + 1 < w->cap) {
        void *mem = geom__alloc(alloc, (w->n + 1) * sizeof *w->node);
        if (mem) {
            geom__rnode4 *nd = (geom__rnode4 *)(((uintptr_t)mem + 63) & ~(uintptr_t)63);
            geom__advise_huge(alloc, mem, (w->n + 1) * sizeof *w->node, (size_t)2 << 20);
            memcpy(nd, w->node, w->n * sizeof *nd);
            geom__free(alloc, w->mem, (w->cap + 1) * sizeof *w->node);
            w->mem = mem;
            w->node = nd;
            w->cap = w->n;
        }
    }
    w->isa = isa_best();
    *out = w;
    return GEOM_OK;
}

geom_status geom__ray_mesh_build(geom__tmesh *m, const geom_ray_build_options *opt,
                                 const geom_allocator *alloc, geom_diag *diag)
{
    geom_bvh_options bo;
    geom_bvh *b = NULL;
    geom_status st;
    if (m->bvh) return GEOM_OK;
    memset(&bo, 0, sizeof bo);
    if (opt) {
        bo.method = opt->bvh_method == 1 ? GEOM_BVH_LBVH : GEOM_BVH_SAH;
        bo.threads = opt->bvh_threads;
    }
    bo.alloc = alloc;
    st = geom_bvh_build_triangles(m->pos, m->nv, m->tri, m->nt, &bo, &b, diag);
    if (st != GEOM_OK) return st;
    m->bvh = b;
    /* Vertices copied in leaf order: one contiguous run per leaf. */
    {
        size_t np = 0, i;
        const uint32_t *pr = geom_bvh_prim_indices(b, &np);
        m->tv = geom__alloc(alloc, (np ? np : 1) * 9 * sizeof(double));
        m->tid = geom__alloc(alloc, (np ? np : 1) * sizeof(uint32_t));
        if (!m->tv || !m->tid) return GEOM_ERR_NOMEM;
        geom__advise_huge(alloc, m->tv, np * 9 * sizeof(double), (size_t)2 << 20);
        for (i = 0; i < np; i++) {
            const uint32_t *t = m->tri + 3 * (size_t)pr[i];
            int k;
            for (k = 0; k < 3; k++) memcpy(m->tv + 9 * i + 3 * k, m->pos + 3 * (size_t)t[k], 3 * sizeof(double));
            m->tid[i] = pr[i];
        }
    }
    return wide_build(b, m->tv, alloc, &m->wide);
}

void geom__ray_mesh_free(geom__tmesh *m, const geom_allocator *alloc)
{
    if (!m) return;
    if (m->bvh) {
        size_t np = 0;
        geom_bvh_prim_indices(m->bvh, &np);
        if (m->tv) geom__free(alloc, m->tv, (np ? np : 1) * 9 * sizeof(double));
        if (m->tid) geom__free(alloc, m->tid, (np ? np : 1) * sizeof(uint32_t));
    }
    geom_bvh_destroy(m->bvh);
    wide_free(m->wide, alloc);
    geom__free(alloc, m->pos, 3 * m->nv * sizeof(double));
    if (m->nrm) geom__free(alloc, m->nrm, 3 * m->nv * sizeof(double));
    geom__free(alloc, m->tri, 3 * m->nt * sizeof(uint32_t));
    if (m->face) geom__free(alloc, m->face, m->nt * sizeof(uint32_t));
    geom__free(alloc, m, sizeof *m);
}

size_t geom__ray_mesh_bvh_nodes(const geom__tmesh *m, size_t *bytes)
{
    size_t n = 0;
    if (!m->bvh) { if (bytes) *bytes = 0; return 0; }
    geom_bvh_nodes(m->bvh, &n);
    if (bytes)
        *bytes = geom_bvh_bytes(m->bvh) +
                 (m->wide ? (m->wide->cap + 1) * sizeof(geom__rnode4) + m->wide->pkcap * sizeof(geom__rpack4) : 0);
    return n;
}

geom_aabb geom__ray_mesh_bounds(const geom__tmesh *m)
{
    geom_aabb b = geom_aabb_empty();
    size_t i;
    for (i = 0; i < m->nt; i++) {
        int k;
        for (k = 0; k < 3; k++) b = geom_aabb_extend(b, geom__v3(m->pos + 3 * m->tri[3 * i + k]));
    }
    return b;
}

typedef struct slabray {
    double o[3], inv[3];
    int zero[3];
    int neg[3];
} slabray;

static inline int node_hit(const slabray *s, const geom_aabb *b, double tmin, double tmax, double *tnear)
{
    const double *lo = &b->min.x, *hi = &b->max.x;
    double tn = -INFINITY, tf = INFINITY;
    const double w = 2 * geom__gamma(3);
    int k;
    for (k = 0; k < 3; k++) {
        double a, c;
        if (s->zero[k]) {
            if (s->o[k] < lo[k] || s->o[k] > hi[k]) return 0;
            continue;
        }
        a = ((s->neg[k] ? hi[k] : lo[k]) - s->o[k]) * s->inv[k];
        c = ((s->neg[k] ? lo[k] : hi[k]) - s->o[k]) * s->inv[k];
        if (a > tn) tn = a;
        if (c < tf) tf = c;
    }
    tn -= fabs(tn) * w;
    tf += fabs(tf) * w;
    *tnear = tn;
    return tn <= tf && tf >= tmin && tn <= tmax;
}

/* The hit on the triangle in leaf slot `slot` (its vertices are read from
 * the leaf-order copy, already in cache after the test). */
static void fill(const geom__tmesh *m, const geom_ray *r, uint32_t slot, double t, const double *b,
                 geom_ray_hit *h)
{
    const double *v = m->tv + 9 * (size_t)slot;
    uint32_t ti = m->tid[slot];
    geom__tri_fill(r, v, v + 3, v + 6, t, b, h);
    h->prim = m->face ? m->face[ti] : ti;
    h->object = 0;
    if (m->nrm) {
        const uint32_t *tv = m->tri + 3 * (size_t)ti;
        geom_vec3 n = {0, 0, 0};
        int k;
        for (k = 0; k < 3; k++) {
            const double *vn = m->nrm + 3 * tv[k];
            n.x += b[k] * vn[0];
            n.y += b[k] * vn[1];
            n.z += b[k] * vn[2];
        }
        if (geom_vec3_normalize(n, &h->ns) != GEOM_OK) h->ns = h->ng;
    }
}

/* The wide traversal. */
typedef struct w4entry {
    double tn;
    uint32_t child, count;
} w4entry;

/* The triangles first..first+count-1 (leaf order) against the ray: every hit
 * pushed (GEOM__RAY_ALL), or the closest kept in best (its leaf slot)/best_t/
 * best_b with tmax shrunk to it (ties by the smaller triangle index). The one leaf loop of both
 * traversals; kx, ky, kz are the ray's Woop axes, constants in each copy that
 * leaf_hits makes. Returns -1 when out of memory, 1 when an any-hit query is
 * answered, 0 otherwise. */
GEOM__WBW_INLINE int leaf_hits_k(const geom__tmesh *m, const geom_ray *r, const geom__wbw *w,
                                 const int kx, const int ky, const int kz,
                                 uint32_t first, uint32_t count, double tmin, double *tmax,
                                 int mode, uint32_t *best, double *best_t, double best_b[3],
                                 geom__rhits *out)
{
    for (uint32_t i = 0; i < count; i++) {
        const double *tvp = m->tv + 9 * (size_t)(first + i);
        double t, bc[3];
        if (!geom__wbw_hit_k(w, kx, ky, kz, tvp, tvp + 3, tvp + 6, tmin, *tmax, &t, bc)) continue;
        if (mode == GEOM__RAY_ALL) {
            geom_ray_hit *h = geom__rhits_push_raw(out);
            if (!h) return -1;
            fill(m, r, first + i, t, bc, h);
        } else {
            if (*best == GEOM_INVALID_INDEX || t < *best_t ||
                (t == *best_t && m->tid[first + i] < m->tid[*best])) {
                *best = first + i;
                *best_t = t;
                memcpy(best_b, bc, sizeof bc);
                *tmax = t;
            }
            if (mode == GEOM__RAY_ANY) return 1;
        }
    }
    return 0;
}

/* leaf_hits_k for the ray's axes (w->kx, w->ky, w->kz: one of six). */
static int leaf_hits(const geom__tmesh *m, const geom_ray *r, const geom__wbw *w, uint32_t first,
                     uint32_t count, double tmin, double *tmax, int mode, uint32_t *best,
                     double *best_t, double best_b[3], geom__rhits *out)
{
#define LEAF_K(x, y, z) leaf_hits_k(m, r, w, x, y, z, first, count, tmin, tmax, mode, best, best_t, best_b, out)
    switch (w->kz * 4 + w->kx) {
    case 0 * 4 + 1: return LEAF_K(1, 2, 0);
    case 0 * 4 + 2: return LEAF_K(2, 1, 0);
    case 1 * 4 + 2: return LEAF_K(2, 0, 1);
    case 1 * 4 + 0: return LEAF_K(0, 2, 1);
    case 2 * 4 + 0: return LEAF_K(0, 1, 2);
    case 2 * 4 + 1: return LEAF_K(1, 0, 2);
    default: return LEAF_K(w->kx, w->ky, w->kz); /* not reached */
    }
#undef LEAF_K
}

/* Per-ray state of the float slab test of a wide node (Ize, "Robust BVH
 * Ray Traversal", JCGT 2013, in float). For an axis with direction d != 0,
 * the exact slab distance (L - o) / d of a plane L (a float: the boxes are
 * stored rounded outward) is computed as fl(fl(L - of) * inv) with of the
 * origin and inv the reciprocal each rounded to float: that is
 * (L - of) / d with a relative error of at most gamma(3) in float plus
 * underflow, and (L - of) / d differs from (L - o) / d by at most
 * e = |o - of| |1 / d|. So the near distance minus |near| c minus E, and the
 * far distance plus |far| c plus E, with c = 2^-20 (16 float ulps: gamma(3)
 * and the rounding of these two operations) and E = 2 max e + 2^-60 (the
 * rounding of e, and underflow or flush-to-zero of a product: below 2^-126
 * times |1/d| <= 2^60), bracket the exact slab interval. For d == 0 the
 * reciprocal is +-inf: L - of has the sign of L - o or is zero (rounding is
 * monotone and L is a float), so the distance is the exact +-inf or NaN,
 * which the min/max below ignore (the ray lies in the slab, conservatively).
 * The maximum of the near distances and the minimum of the far ones carry
 * the bounds of the axis they come from, so the widened interval contains
 * the exact one: no box a ray touches is ever skipped. */
typedef struct w4f {
    float of[3], inv[3];
    float e;
    /* The ray-side form (w8_node_rs): the origin and reciprocal again with
     * a zero fourth lane, and its bound; rs = 0 when a direction component
     * is zero (the decoding form w8_node is used). */
    float of4[4], inv4[4];
    float ers;
    int rs;
    int nhi[3];          /* 1: the near plane of axis k is the box's hi (direction < 0) */
    size_t noff[3], foff[3]; /* byte offsets in a node of axis k's near and far plane codes */
} w4f;

/* Fill f for the ray (o, d); 0 when the float test cannot be used for it
 * (a coordinate or reciprocal beyond 2^60, or boxes beyond it): the double
 * slab test is used instead. */
static int w4f_setup(const struct geom__rbvh4 *W, const double o[3], const double d[3], const double inv[3],
                     w4f *f)
{
    double e = 0;
    int k;
    if (!W->fbox) return 0;
    for (k = 0; k < 3; k++) {
        double iv, ek;
        if (!(fabs(o[k]) <= W4_FMAX)) return 0;
        f->of[k] = (float)o[k];
        f->nhi[k] = signbit(d[k]) != 0;
        f->noff[k] = (f->nhi[k] ? offsetof(geom__rnode4, qhi) : offsetof(geom__rnode4, qlo)) + W4_W * (size_t)k;
        f->foff[k] = (f->nhi[k] ? offsetof(geom__rnode4, qlo) : offsetof(geom__rnode4, qhi)) + W4_W * (size_t)k;
        if (d[k] == 0) {
            f->inv[k] = f->nhi[k] ? -INFINITY : INFINITY;
            continue;
        }
        iv = inv[k];
        if (!(fabs(iv) <= W4_FMAX)) return 0;
        f->inv[k] = (float)iv;
        ek = fabs(o[k] - (double)f->of[k]) * fabs(iv);
        if (ek > e) e = ek;
    }
    f->e = f_up_fast(2 * e * (1 + 0x1p-40) + 0x1p-60);
    /* The ray-side form's extra term (w8_node_rs): 2^-21 (pmax + |of|) |inv|. */
    f->rs = d[0] != 0 && d[1] != 0 && d[2] != 0;
    {
        double fr = 0;
        for (k = 0; k < 3; k++) {
            double a = 0x1p-21 * (W->pmax + fabs((double)f->of[k])) * fabs((double)f->inv[k]);
            if (a > fr) fr = a;
            f->of4[k] = f->of[k];
            f->inv4[k] = f->inv[k];
        }
        f->of4[3] = f->inv4[3] = 0;
        f->ers = f_up_fast((2 * e + fr) * (1 + 0x1p-40) + 0x1p-60);
    }
    return 1;
}

#if W4_SSE
/* Eight 8-bit plane codes decoded (w4_dec) into lanes 0-3 and 4-7. */
static inline void w4_dec8(const uint8_t *qb, __m128 px, __m128 s, __m128 *a, __m128 *b)
{
    const __m128i z = _mm_setzero_si128();
    __m128i v = _mm_unpacklo_epi8(_mm_loadl_epi64((const __m128i *)qb), z);
    *a = _mm_add_ps(px, _mm_mul_ps(_mm_cvtepi32_ps(_mm_unpacklo_epi16(v, z)), s));
    *b = _mm_add_ps(px, _mm_mul_ps(_mm_cvtepi32_ps(_mm_unpackhi_epi16(v, z)), s));
}

/* The W4_W children of q against the ray: a bit mask of the lanes hit and
 * their (conservative, never later than exact) entry distances. The planes
 * are the decoded floats (each containing the exact box), so the bounds
 * above hold unchanged. */
static inline int w4f_node(const geom__rnode4 *q, const w4f *f, const __m128 vo[3], const __m128 vi[3],
                           __m128 vtmin, __m128 vtmax, float tn_out[W4_W])
{
    const __m128 absmask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
    const __m128 vc = _mm_set1_ps(0x1p-20f), ve = _mm_set1_ps(f->e);
    const __m128i none = _mm_set1_epi32(-1);
    __m128 tn0 = vtmin, tf0 = vtmax, tn1 = vtmin, tf1 = vtmax;
    int k, mask;
    for (k = 0; k < 3; k++) {
        const __m128 px = _mm_set1_ps(q->px[k]);
        const __m128 sc = _mm_castsi128_ps(_mm_set1_epi32(((int)q->ex[k] + 127) << 23));
        __m128 n0, n1, f0, f1;
        w4_dec8((const uint8_t *)q + f->noff[k], px, sc, &n0, &n1);
        w4_dec8((const uint8_t *)q + f->foff[k], px, sc, &f0, &f1);
        /* maxps/minps return the second operand when either is NaN */
        tn0 = _mm_max_ps(_mm_mul_ps(_mm_sub_ps(n0, vo[k]), vi[k]), tn0);
        tn1 = _mm_max_ps(_mm_mul_ps(_mm_sub_ps(n1, vo[k]), vi[k]), tn1);
        tf0 = _mm_min_ps(_mm_mul_ps(_mm_sub_ps(f0, vo[k]), vi[k]), tf0);
        tf1 = _mm_min_ps(_mm_mul_ps(_mm_sub_ps(f1, vo[k]), vi[k]), tf1);
    }
    tn0 = _mm_sub_ps(_mm_sub_ps(tn0, _mm_mul_ps(_mm_and_ps(tn0, absmask), vc)), ve);
    tn1 = _mm_sub_ps(_mm_sub_ps(tn1, _mm_mul_ps(_mm_and_ps(tn1, absmask), vc)), ve);
    tf0 = _mm_add_ps(_mm_add_ps(tf0, _mm_mul_ps(_mm_and_ps(tf0, absmask), vc)), ve);
    tf1 = _mm_add_ps(_mm_add_ps(tf1, _mm_mul_ps(_mm_and_ps(tf1, absmask), vc)), ve);
    _mm_storeu_ps(tn_out, tn0);
    _mm_storeu_ps(tn_out + 4, tn1);
    mask = (_mm_movemask_ps(_mm_cmple_ps(tn0, tf0)) &
            ~_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(_mm_load_si128((const __m128i *)q->child), none)))) |
           ((_mm_movemask_ps(_mm_cmple_ps(tn1, tf1)) &
             ~_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(_mm_load_si128((const __m128i *)(q->child + 4)), none))))
            << 4);
    return mask;
}
#endif

#if W4_SSE
/* The conservative float pre-test of a leaf's triangles (pk_filter): per ray,
 * the origin and the shear of the watertight test (wbw.h) in float, and the
 * bound on the error of a sheared float coordinate.
 *
 * Why it never drops a triangle the exact test hits. The double test
 * computes a sheared coordinate X_d = fl(fl(vx - ox) - fl(sx fl(vz - oz)))
 * (x standing for kx or ky) with sx = fl(dx / dz), |sx| <= 1, and decides
 * from the exact signs of the edge functions e = bx_d cy_d - by_d cx_d,
 * rejecting the triangle whenever one is < 0 and another > 0. Let X* be the
 * exact (vx - ox) - sx (vz - oz) and M = |vx| + |ox| + |sx| (|vz| + |oz|)
 * <= 2 (mag + |o|max) with mag the largest vertex coordinate. Then
 * |X_d - X*| <= gamma_d(3) M, and the same expression evaluated in float
 * from the rounded vertex, origin and sx (relative errors 2^-24 each, then
 * three float operations) gives |X_f - X*| <= gamma_f(5) M + 2^-120 M + 2^-100
 * (the last terms: an sx below the float range, and underflow or
 * flush-to-zero of the vertex, origin or results; fused multiply-adds only
 * remove roundings), so |X_f - X_d| <= delta = 2^-20 (mag + |o|max) +
 * 2^-100, as 2 (gamma_f(5) + gamma_d(3) + 2^-120) < 2^-20.
 * For an edge function, |bx_f cy_f - bx_d cy_d| <= delta (|bx_f| + |cy_f| +
 * delta), and the float evaluation adds at most gamma_f(2) (|bx_f cy_f| +
 * |by_f cx_f|) <= 2^-22 sb sc (sb = |bx_f| + |by_f|, sc = |cx_f| + |cy_f|)
 * plus 2^-100 of underflow. So with
 *     B = delta (sb + sc + 2 delta) + 2^-22 sb sc + 2^-99,
 * e_f < -B proves e < 0 and e_f > B proves e > 0: a lane is dropped only
 * when one edge function is proven negative and another positive, which the
 * exact test rejects too. B is computed in float from constants enlarged by
 * 2^-18 relative, more than the at most 6 roundings of the expression can
 * take away. NaN (an overflow cannot occur: every coordinate and |o| are
 * below 2^60, so the products stay below 2^126) fails both comparisons and
 * keeps the lane. */
/* Index of the lowest set bit of a nonzero 4-bit mask. */
static inline int lane_first(int m)
{
    return (m & 1) ? 0 : (m & 2) ? 1 : (m & 4) ? 2 : 3;
}

typedef struct pkray {
    __m128 o[3];          /* origin in float, by axis kx, ky, kz */
    __m128 sx, sy;        /* the shear in float */
    __m128 d1, d2, c2, eta; /* delta, 2 delta, 2^-22, 2^-99, each enlarged */
    int kx, ky, kz;
} pkray;

static void pk_setup(pkray *p, const geom__wbw *w, const struct geom__rbvh4 *W)
{
    const double e = 1 + 0x1p-18;
    double om = fabs(w->o[0]), delta;
    if (fabs(w->o[1]) > om) om = fabs(w->o[1]);
    if (fabs(w->o[2]) > om) om = fabs(w->o[2]);
    delta = (0x1p-20 * (W->mag + om) + 0x1p-100) * e;
    p->kx = w->kx; p->ky = w->ky; p->kz = w->kz;
    p->o[0] = _mm_set1_ps((float)w->o[w->kx]);
    p->o[1] = _mm_set1_ps((float)w->o[w->ky]);
    p->o[2] = _mm_set1_ps((float)w->o[w->kz]);
    p->sx = _mm_set1_ps((float)w->sx);
    p->sy = _mm_set1_ps((float)w->sy);
    p->d1 = _mm_set1_ps(f_up_fast(delta));
    p->d2 = _mm_set1_ps(f_up_fast(2 * delta));
    p->c2 = _mm_set1_ps((float)(0x1p-22 * e));
    p->eta = _mm_set1_ps((float)(0x1p-99 * e));
}

/* The lanes (bit i: triangle i of the packet) the exact test must still
 * see: those not proven missed (see pkray). */
static inline int pk_filter(const geom__rpack4 *q, const pkray *p)
{
    const __m128 absmask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
    const __m128 sgn = _mm_castsi128_ps(_mm_set1_epi32((int)0x80000000u));
    __m128 x[3], y[3], sa[3], e[3], neg, pos;
    int i;
    for (i = 0; i < 3; i++) {
        __m128 z = _mm_sub_ps(_mm_load_ps(q->v[i][p->kz]), p->o[2]);
        x[i] = _mm_sub_ps(_mm_sub_ps(_mm_load_ps(q->v[i][p->kx]), p->o[0]), _mm_mul_ps(p->sx, z));
        y[i] = _mm_sub_ps(_mm_sub_ps(_mm_load_ps(q->v[i][p->ky]), p->o[1]), _mm_mul_ps(p->sy, z));
        sa[i] = _mm_add_ps(_mm_and_ps(x[i], absmask), _mm_and_ps(y[i], absmask));
    }
    neg = _mm_setzero_ps();
    pos = _mm_setzero_ps();
    for (i = 0; i < 3; i++) {
        /* e[0]: edge v1 -> v2, e[1]: v2 -> v0, e[2]: v0 -> v1 (wbw.h) */
        const int a = (i + 1) % 3, b = (i + 2) % 3;
        __m128 bnd;
        e[i] = _mm_sub_ps(_mm_mul_ps(x[a], y[b]), _mm_mul_ps(y[a], x[b]));
        bnd = _mm_add_ps(_mm_add_ps(_mm_mul_ps(p->d1, _mm_add_ps(_mm_add_ps(sa[a], sa[b]), p->d2)),
                                    _mm_mul_ps(p->c2, _mm_mul_ps(sa[a], sa[b]))),
                         p->eta);
        neg = _mm_or_ps(neg, _mm_cmplt_ps(e[i], _mm_xor_ps(bnd, sgn)));
        pos = _mm_or_ps(pos, _mm_cmpgt_ps(e[i], bnd));
    }
    return ~_mm_movemask_ps(_mm_and_ps(neg, pos)) & 15;
}
#endif

#if W4_AVX2
/* w4f_node with all eight lanes in one AVX2 register: the same float
 * operations in the same order, so the same distances bit for bit and the
 * same bounds (w4f). The decode px + q 2^e is one fused multiply-add, equal
 * to w4_dec's multiply then add: the product of the 8-bit code and the
 * power of two is exact (w4_dec), so the fused and the unfused sum are the
 * same single rounding. */
W4_TGT static inline int w8_node(const geom__rnode4 *q, const w4f *f, float tmin, float tmax,
                                 float tn_out[W4_W])
{
    const __m256 absmask = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff));
    const __m256 vc = _mm256_set1_ps(0x1p-20f), ve = _mm256_set1_ps(f->e);
    __m256 tn = _mm256_set1_ps(tmin), tf = _mm256_set1_ps(tmax);
    __m256i none;
    int k;
    for (k = 0; k < 3; k++) {
        const __m256 px = _mm256_broadcast_ss(&q->px[k]);
        const __m256 sc = _mm256_castsi256_ps(_mm256_set1_epi32(((int)q->ex[k] + 127) << 23));
        const __m256 vo = _mm256_broadcast_ss(&f->of[k]), vi = _mm256_broadcast_ss(&f->inv[k]);
        __m256 n = _mm256_cvtepi32_ps(
            _mm256_cvtepu8_epi32(_mm_loadl_epi64((const __m128i *)((const uint8_t *)q + f->noff[k]))));
        __m256 c = _mm256_cvtepi32_ps(
            _mm256_cvtepu8_epi32(_mm_loadl_epi64((const __m128i *)((const uint8_t *)q + f->foff[k]))));
        n = _mm256_fmadd_ps(n, sc, px);
        c = _mm256_fmadd_ps(c, sc, px);
        /* maxps/minps return the second operand when either is NaN */
        tn = _mm256_max_ps(_mm256_mul_ps(_mm256_sub_ps(n, vo), vi), tn);
        tf = _mm256_min_ps(_mm256_mul_ps(_mm256_sub_ps(c, vo), vi), tf);
    }
    tn = _mm256_sub_ps(_mm256_sub_ps(tn, _mm256_mul_ps(_mm256_and_ps(tn, absmask), vc)), ve);
    tf = _mm256_add_ps(_mm256_add_ps(tf, _mm256_mul_ps(_mm256_and_ps(tf, absmask), vc)), ve);
    _mm256_storeu_ps(tn_out, tn);
    none = _mm256_cmpeq_epi32(_mm256_load_si256((const __m256i *)q->child), _mm256_set1_epi32(-1));
    return _mm256_movemask_ps(_mm256_cmp_ps(tn, tf, _CMP_LE_OQ)) & ~_mm256_movemask_ps(_mm256_castsi256_ps(none));
}

/* Ylitie, Karras and Laine's ray-side form of the quantized slab test: the
 * node's origin px and scale 2^ex folded into the ray, once per node,
 * A = 2^ex inv and B = (px - of) inv, so that a plane of code q is at
 * distance fma(q, A, B), one fused multiply-add per plane with no decode.
 * For rays with no zero direction component (f->rs).
 *
 * Why it is still conservative. Let n = fl(px + q 2^ex) be the decoded
 * plane the builder checked (it contains the exact box: w4_dec) and
 * P = px + q 2^ex the real sum, |P - n| <= 2^-24 |n| <= 2^-24 pmax. A is
 * exact (a power of two times a float, |A| <= 2^115: no overflow; an
 * underflow below 2^-126 costs at most 255 2^-149), B =
 * (px - of) inv (1 + d1)(1 + d2) with |di| <= 2^-24, so
 *     fma(q, A, B) = ((P - of) inv + r)(1 + d3),
 *     |r| <= gamma(2) |px - of| |inv| <= gamma(2) (pmax + |of|) |inv|,
 * and (P - of) inv = (n - of) inv + (P - n) inv with
 * |(P - n) inv| <= 2^-24 pmax |inv|. So the computed distance is
 * (n - of) inv (1 + d3) plus at most 3.01 2^-24 (pmax + |of|) |inv|
 * < 2^-21 (pmax + |of|) |inv| (and 2^-140 of underflow): the relative part
 * is one rounding, within w4f's c = 2^-20 which covers three, and the
 * absolute part is added to w4f's E (f->ers = E + that term, rounded up).
 * The distances differ from w8_node's by rounding, so the nodes a ray
 * visits may differ, never the hits: both contain every box the ray
 * touches, and the exact test alone decides. */
W4_TGT static inline __m256 w8_lane(__m128 v, int k)
{
    return _mm256_broadcastss_ps(k == 0 ? v : k == 1 ? _mm_movehdup_ps(v) : _mm_movehl_ps(v, v));
}

W4_TGT static inline int w8_node_rs(const geom__rnode4 *q, const w4f *f, float tmin, float tmax,
                                    float tn_out[W4_W])
{
    const __m256 absmask = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff));
    const __m256 vc = _mm256_set1_ps(0x1p-20f), ve = _mm256_set1_ps(f->ers);
    const __m128 m3 = _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0));
    const __m128 vinv = _mm_loadu_ps(f->inv4);
    int32_t exw;
    __m128 px, sc, A, B;
    __m256 tn = _mm256_set1_ps(tmin), tf = _mm256_set1_ps(tmax);
    __m256i none;
    int k;
    memcpy(&exw, q->ex, sizeof exw); /* ex[0..2], pad (0) */
    px = _mm_and_ps(_mm_loadu_ps(q->px), m3); /* the fourth lane (ex bytes) zeroed */
    sc = _mm_castsi128_ps(_mm_slli_epi32(_mm_add_epi32(_mm_cvtepi8_epi32(_mm_cvtsi32_si128(exw)),
                                                       _mm_set1_epi32(127)), 23));
    A = _mm_mul_ps(sc, vinv);
    B = _mm_mul_ps(_mm_sub_ps(px, _mm_loadu_ps(f->of4)), vinv);
    for (k = 0; k < 3; k++) {
        const __m256 a = w8_lane(A, k), b = w8_lane(B, k);
        __m256 n = _mm256_cvtepi32_ps(
            _mm256_cvtepu8_epi32(_mm_loadl_epi64((const __m128i *)((const uint8_t *)q + f->noff[k]))));
        __m256 c = _mm256_cvtepi32_ps(
            _mm256_cvtepu8_epi32(_mm_loadl_epi64((const __m128i *)((const uint8_t *)q + f->foff[k]))));
        tn = _mm256_max_ps(_mm256_fmadd_ps(n, a, b), tn);
        tf = _mm256_min_ps(_mm256_fmadd_ps(c, a, b), tf);
    }
    tn = _mm256_sub_ps(_mm256_sub_ps(tn, _mm256_mul_ps(_mm256_and_ps(tn, absmask), vc)), ve);
    tf = _mm256_add_ps(_mm256_add_ps(tf, _mm256_mul_ps(_mm256_and_ps(tf, absmask), vc)), ve);
    _mm256_storeu_ps(tn_out, tn);
    none = _mm256_cmpeq_epi32(_mm256_load_si256((const __m256i *)q->child), _mm256_set1_epi32(-1));
    return _mm256_movemask_ps(_mm256_cmp_ps(tn, tf, _CMP_LE_OQ)) & ~_mm256_movemask_ps(_mm256_castsi256_ps(none));
}

/* pk_filter with the sheared x and y of the four triangles in one AVX2
 * register (x in lanes 0-3, y in 4-7): the same float operations in the
 * same order (no fused multiply-add), so the same lanes bit for bit and
 * the same proof (pkray). */
W4_TGT static inline int pk_filter8(const geom__rpack4 *q, const pkray *p)
{
    const __m256 absmask = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff));
    const __m128 sgn = _mm_castsi128_ps(_mm_set1_epi32((int)0x80000000u));
    const __m256 oxy = _mm256_insertf128_ps(_mm256_castps128_ps256(p->o[0]), p->o[1], 1);
    const __m256 sxy = _mm256_insertf128_ps(_mm256_castps128_ps256(p->sx), p->sy, 1);
    __m128 x[3], y[3], sa[3], neg = _mm_setzero_ps(), pos = _mm_setzero_ps();
    int i;
    for (i = 0; i < 3; i++) {
        __m128 z = _mm_sub_ps(_mm_load_ps(q->v[i][p->kz]), p->o[2]);
        __m256 v = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_load_ps(q->v[i][p->kx])),
                                        _mm_load_ps(q->v[i][p->ky]), 1);
        __m256 zz = _mm256_insertf128_ps(_mm256_castps128_ps256(z), z, 1);
        __m256 xy = _mm256_sub_ps(_mm256_sub_ps(v, oxy), _mm256_mul_ps(sxy, zz));
        __m256 ab = _mm256_and_ps(xy, absmask);
        x[i] = _mm256_castps256_ps128(xy);
        y[i] = _mm256_extractf128_ps(xy, 1);
        sa[i] = _mm_add_ps(_mm256_castps256_ps128(ab), _mm256_extractf128_ps(ab, 1));
    }
    for (i = 0; i < 3; i++) {
        const int a = (i + 1) % 3, b = (i + 2) % 3;
        __m128 e = _mm_sub_ps(_mm_mul_ps(x[a], y[b]), _mm_mul_ps(y[a], x[b]));
        __m128 bnd = _mm_add_ps(_mm_add_ps(_mm_mul_ps(p->d1, _mm_add_ps(_mm_add_ps(sa[a], sa[b]), p->d2)),
                                           _mm_mul_ps(p->c2, _mm_mul_ps(sa[a], sa[b]))),
                                p->eta);
        neg = _mm_or_ps(neg, _mm_cmplt_ps(e, _mm_xor_ps(bnd, sgn)));
        pos = _mm_or_ps(pos, _mm_cmpgt_ps(e, bnd));
    }
    return ~_mm_movemask_ps(_mm_and_ps(neg, pos)) & 15;
}
#endif

/* The same in double from the floats exactly converted, with Ize's bounds
 * (2 gamma(3)): the path of rays the float test cannot take, and of targets
 * without SSE2. */
static inline int w4d_node(const geom__rnode4 *q, const double o[3], const double inv[3], const int neg[3],
                           double tmin, double tmax, double tn_out[W4_W])
{
    const double wid = 2 * geom__gamma(3);
    double tn[W4_W], tf[W4_W];
    int j, k, mask = 0;
    for (j = 0; j < W4_W; j++) { tn[j] = -INFINITY; tf[j] = INFINITY; }
    for (k = 0; k < 3; k++) {
        const uint8_t *np = neg[k] ? q->qhi[k] : q->qlo[k];
        const uint8_t *fp = neg[k] ? q->qlo[k] : q->qhi[k];
        const double ok = o[k], iv = inv[k];
        const float px = q->px[k], sc = w4_pow2(q->ex[k]);
        for (j = 0; j < W4_W; j++) {
            double a = ((double)w4_dec(px, sc, np[j]) - ok) * iv, c = ((double)w4_dec(px, sc, fp[j]) - ok) * iv;
            tn[j] = a > tn[j] ? a : tn[j];
            tf[j] = c < tf[j] ? c : tf[j];
        }
    }
    for (j = 0; j < W4_W; j++) {
        double a = tn[j] - fabs(tn[j]) * wid, c = tf[j] + fabs(tf[j]) * wid;
        tn_out[j] = a;
        mask |= ((a <= c) & (c >= tmin) & (a <= tmax) & (q->child[j] != GEOM_INVALID_INDEX)) << j;
    }
    return mask;
}

/* A traversal's end: the closest (or any) hit found, when one was, goes
 * into out; GEOM__RAY_ALL has pushed its hits already. Once per ray, after
 * the traversal loop. */
static inline geom_status finish(const geom__tmesh *m, const geom_ray *r, int mode, uint32_t best,
                                 double best_t, const double best_b[3], geom__rhits *out)
{
    if (mode != GEOM__RAY_ALL && best != GEOM_INVALID_INDEX) {
        geom_ray_hit *h = geom__rhits_push_raw(out);
        if (!h) return GEOM_ERR_NOMEM;
        fill(m, r, best, best_t, best_b, h);
    }
    return GEOM_OK;
}

/* Ask for the memory of the triangles slot .. slot + cnt - 1 (72 bytes each,
 * cnt <= 4: at most six cache lines), without a loop whose trip count a
 * random ray's branch predictor cannot guess: six requests, each clamped to
 * the last byte (the same line asked for again when the run is shorter). */
static inline void fetch_tris(const geom__tmesh *m, uint32_t slot, uint32_t cnt)
{
    const char *c = (const char *)(m->tv + 9 * (size_t)slot), *e = c + 72 * (size_t)cnt - 1;
    int k;
    for (k = 0; k < 5; k++) {
        const char *p = c + 64 * k;
        W4_PREFETCH(p < e ? p : e);
    }
    W4_PREFETCH(e);
}

/* Ask for the memory of a child (count 0: node child, else a leaf's packet). */
static inline void fetch_child(const struct geom__rbvh4 *W, uint32_t child, uint32_t count)
{
    const char *c;
    if (count == 0) {
        c = (const char *)&W->node[child];
        W4_PREFETCH(c);
        W4_PREFETCH(c + 64);
    } else {
        c = (const char *)&W->pk[W4_PK(count)];
        W4_PREFETCH(c);
        W4_PREFETCH(c + 64);
        W4_PREFETCH(c + 128);
    }
}

/* The children of q in mask pushed on stack[sp..] in place by decreasing
 * entry distance (tf[j] when tf is not NULL, the float node test's, else
 * td[j]; the nearest is popped first; no copy through a buffer, which the
 * compiler would make a block move that stalls the next pop), each asked
 * for; returns the new sp. Only the children hit are read and converted. */
GEOM__WBW_INLINE int push_hit(const struct geom__rbvh4 *W, const geom__rnode4 *q, int mask, const float *tf,
                              const double *td, w4entry *stack, int sp)
{
    const int base = sp;
    while (mask) {
        const int j = w4_ctz((unsigned)mask);
        const double t = tf ? (double)tf[j] : td[j];
        int i = sp++;
        mask &= mask - 1;
        while (i > base && stack[i - 1].tn < t) { stack[i] = stack[i - 1]; i--; }
        stack[i].tn = t;
        stack[i].child = q->child[j];
        stack[i].count = q->count[j];
        fetch_child(W, q->child[j], q->count[j]);
    }
    return sp;
}

/* The wide traversal; isa (a constant in each copy below) picks the node
 * and leaf pre-tests. */
GEOM__WBW_INLINE geom_status trace_wide_t(const geom__tmesh *m, const geom_ray *r, const geom__rslab *sl,
                                          int mode, geom__rhits *out, const int isa)
{
    const struct geom__rbvh4 *W = m->wide;
    w4entry stack[W4_STACK], cur;
    int sp = 0, k, use_f;
    double o[3] = {r->origin.x, r->origin.y, r->origin.z}, inv[3];
    int neg[3];
    geom__wbw w;
    w4f f;
#if W4_SSE
    pkray pk;
#endif
    const double tmin = r->tmin;
    double tmax = r->tmax, best_b[3] = {0, 0, 0}, best_t = 0;
    uint32_t best = GEOM_INVALID_INDEX;
#if W4_SSE
    __m128 vo[3], vi[3], vtmin, vtmax;
#endif
    {
        double d[3] = {r->dir.x, r->dir.y, r->dir.z};
        /* A zero component gives an infinite reciprocal: the slab distances
         * are then +-inf, or NaN for an origin on the slab plane, which the
         * comparisons below ignore (the ray lies in the slab). */
        if (sl) { /* computed by the caller with the same definition */
            for (k = 0; k < 3; k++) {
                neg[k] = sl->neg[k];
                inv[k] = sl->inv[k];
            }
        } else {
            for (k = 0; k < 3; k++) {
                neg[k] = signbit(d[k]) != 0;
                inv[k] = d[k] != 0 ? 1.0 / d[k] : (neg[k] ? -INFINITY : INFINITY);
            }
        }
        use_f = W4_SSE && w4f_setup(W, o, d, inv, &f);
    }
    (void)use_f; /* read only where SSE2 is compiled */
    (void)isa;   /* read only where the AVX2 path is compiled */
#if W4_SSE
    if (use_f) {
        for (k = 0; k < 3; k++) {
            vo[k] = _mm_set1_ps(f.of[k]);
            vi[k] = _mm_set1_ps(f.inv[k]);
        }
        vtmin = _mm_set1_ps(f_down_fast(tmin));
        vtmax = _mm_set1_ps(f_up_fast(tmax));
    }
#endif
    w.kz = -1; /* set up at the first leaf: a ray that reaches none needs no shear */
    cur.tn = tmin;
    cur.child = 0;
    cur.count = 0;
    for (;;) {
        if (cur.count == 0) {
            const geom__rnode4 *q = &W->node[cur.child];
            double tn[W4_W];
            float tf4[W4_W]; /* the float node test's entry distances, read as they are (no copy) */
            int j, mask, isf = 0;
#if W4_SSE
            if (use_f) {
#if W4_AVX2
                if (isa == W4_ISA_AVX2)
                    mask = f.rs ? w8_node_rs(q, &f, _mm_cvtss_f32(vtmin), _mm_cvtss_f32(vtmax), tf4)
                                : w8_node(q, &f, _mm_cvtss_f32(vtmin), _mm_cvtss_f32(vtmax), tf4);
                else
#endif
                    mask = w4f_node(q, &f, vo, vi, vtmin, vtmax, tf4);
                isf = 1;
            } else
#endif
            {
                mask = w4d_node(q, o, inv, neg, tmin, tmax, tn);
            }
            if (mask == 0) goto pop;
            if ((mask & (mask - 1)) == 0) { /* one child hit: visit it next, no stack traffic */
                j = w4_ctz((unsigned)mask);
                cur.tn = isf ? (double)tf4[j] : tn[j];
                cur.child = q->child[j];
                cur.count = q->count[j];
                continue;
            }
            if (sp + W4_W > W4_STACK) return GEOM_ERR_LIMIT; /* cannot happen: depth checked at build */
            /* the children hit, nearest on top */
            sp = isf ? push_hit(W, q, mask, tf4, NULL, stack, sp) : push_hit(W, q, mask, NULL, tn, stack, sp);
        } else {
            double tmax0 = tmax;
            int lr = 0;
            uint32_t cnt = W4_CNT(cur.count);
            /* the leaf's triangles asked for now, while its packet comes:
             * the two loads overlap instead of following each other (a
             * random ray waits on both) */
            fetch_tris(m, cur.child, cnt);
            if (w.kz < 0) {
                geom__wbw_setup(&w, r);
#if W4_SSE
                if (use_f) pk_setup(&pk, &w, W);
#endif
            }
#if W4_SSE
            if (use_f) {
                /* Only the triangles the float pre-test cannot rule out. */
                int lanes;
#if W4_AVX2
                if (isa == W4_ISA_AVX2)
                    lanes = pk_filter8(&W->pk[W4_PK(cur.count)], &pk) & ((1 << cnt) - 1);
                else
#endif
                    lanes = pk_filter(&W->pk[W4_PK(cur.count)], &pk) & ((1 << cnt) - 1);
                while (lanes) {
                    int j = lane_first(lanes);
                    lanes &= lanes - 1;
                    lr = leaf_hits(m, r, &w, cur.child + (uint32_t)j, 1, tmin, &tmax, mode, &best, &best_t,
                                   best_b, out);
                    if (lr != 0) break;
                }
            } else
#endif
            {
                lr = leaf_hits(m, r, &w, cur.child, cnt, tmin, &tmax, mode, &best, &best_t, best_b, out);
            }
            if (lr < 0) return GEOM_ERR_NOMEM;
            if (lr > 0) goto done;
#if W4_SSE
            if (use_f && tmax != tmax0) vtmax = _mm_set1_ps(f_up_fast(tmax));
#else
            (void)tmax0;
#endif
        }
    pop:
        do { /* field by field, as pushed: a whole-entry load would wait for the stores */
            if (sp == 0) goto done;
            sp--;
            cur.tn = stack[sp].tn;
            cur.child = stack[sp].child;
            cur.count = stack[sp].count;
        } while (cur.tn > tmax); /* entered beyond the closest hit so far */
    }
done:
    return finish(m, r, mode, best, best_t, best_b, out);
}

static geom_status trace_wide_sse2(const geom__tmesh *m, const geom_ray *r, const geom__rslab *sl, int mode,
                                   geom__rhits *out)
{
    return trace_wide_t(m, r, sl, mode, out, W4_ISA_SSE2);
}

#if W4_AVX2
W4_TGT static geom_status trace_wide_avx2(const geom__tmesh *m, const geom_ray *r, const geom__rslab *sl,
                                          int mode, geom__rhits *out)
{
    return trace_wide_t(m, r, sl, mode, out, W4_ISA_AVX2);
}
#endif

static geom_status trace_wide(const geom__tmesh *m, const geom_ray *r, const geom__rslab *sl, int mode,
                              geom__rhits *out)
{
#if W4_AVX2
    if (m->wide->isa == W4_ISA_AVX2) return trace_wide_avx2(m, r, sl, mode, out);
#endif
    return trace_wide_sse2(m, r, sl, mode, out);
}

/* ---------------------------------------------------------------------
 * Closest hits of many rays, their traversals interleaved (the batch entry
 * point geom_ray_scene_closest_many). A random ray's traversal waits on
 * memory at almost every node and leaf (a first load of a node or a leaf
 * packet: about a third of the single-ray traversal's time). Here W8_K rays
 * are traversed at once, round robin, one step each (a node test, or a
 * leaf): each step ends by choosing the ray's next node or leaf and asking
 * for it (prefetch), and the W8_K - 1 other rays' steps run while it comes
 * from memory (the latency hiding of Aila and Laine's persistent threads,
 * "Understanding the Efficiency of Ray Traversal on GPUs", HPG 2009, done
 * in software on one core). Each ray's own traversal is trace_wide's, step
 * for step (the same node order, pruning and tie rule), so every answer is
 * bit for bit geom_ray_scene_closest's (test_ray_batch). */
#if W4_SSE
/* Rays in flight per batch. */
#ifndef W8_K
#define W8_K 8
#endif

typedef struct w8slot {
    pkray pk;              /* first: 16-byte aligned */
    w4f f;
    geom__wbw w;
    const geom_ray *r;
    size_t idx;            /* the ray's index in the batch */
    double tmin, tmax, best_t, best_b[3];
    float ftmin, ftmax;
    uint32_t best;
    int sp;
    int pend;              /* lanes of the current leaf the exact test is still to see */
    w4entry cur;
    w4entry *stack;        /* W4_STACK entries */
    __m128 vo[3], vi[3];
} w8slot;

/* Start ray r in slot t; 0 when the float node test cannot take it (the
 * caller then traces it alone). */
static int w8_start(const geom__tmesh *m, w8slot *t, const geom_ray *r, size_t idx)
{
    const struct geom__rbvh4 *W = m->wide;
    double o[3] = {r->origin.x, r->origin.y, r->origin.z}, d[3] = {r->dir.x, r->dir.y, r->dir.z}, inv[3];
    int k;
    for (k = 0; k < 3; k++) inv[k] = d[k] != 0 ? 1.0 / d[k] : (signbit(d[k]) ? -INFINITY : INFINITY);
    if (!w4f_setup(W, o, d, inv, &t->f)) return 0;
    for (k = 0; k < 3; k++) {
        t->vo[k] = _mm_set1_ps(t->f.of[k]);
        t->vi[k] = _mm_set1_ps(t->f.inv[k]);
    }
    t->r = r;
    t->idx = idx;
    t->tmin = r->tmin;
    t->tmax = r->tmax;
    t->ftmin = f_down_fast(r->tmin);
    t->ftmax = f_up_fast(r->tmax);
    t->best = GEOM_INVALID_INDEX;
    t->best_t = 0;
    t->best_b[0] = t->best_b[1] = t->best_b[2] = 0;
    t->w.kz = -1;
    t->sp = 0;
    t->pend = 0;
    t->cur.tn = r->tmin;
    t->cur.child = 0;
    t->cur.count = 0;
    return 1;
}

/* Ask for the memory of the slot's current node or leaf packet. */
static inline void w8_fetch(const struct geom__rbvh4 *W, const w8slot *t)
{
    fetch_child(W, t->cur.child, t->cur.count);
}

/* One step of slot t's traversal (trace_wide's loop body, closest mode):
 * 1 while the ray goes on (its next node or leaf asked for), 0 when it is
 * done. */
GEOM__WBW_INLINE int w8_step(const geom__tmesh *m, w8slot *t, const int isa)
{
    (void)isa;
    const struct geom__rbvh4 *W = m->wide;
    w4entry *stack = t->stack;
    int sp = t->sp;
    if (t->cur.count == 0) {
        const geom__rnode4 *q = &W->node[t->cur.child];
        float tn[W4_W];
        int j, mask;
#if W4_AVX2
        if (isa == W4_ISA_AVX2)
            mask = t->f.rs ? w8_node_rs(q, &t->f, t->ftmin, t->ftmax, tn) : w8_node(q, &t->f, t->ftmin, t->ftmax, tn);
        else
#endif
            mask = w4f_node(q, &t->f, t->vo, t->vi, _mm_set1_ps(t->ftmin), _mm_set1_ps(t->ftmax), tn);
        if (mask == 0) goto pop;
        if ((mask & (mask - 1)) == 0) { /* one child: next */
            j = w4_ctz((unsigned)mask);
            t->cur.tn = (double)tn[j];
            t->cur.child = q->child[j];
            t->cur.count = q->count[j];
            w8_fetch(W, t);
            return 1;
        }
        /* sp + W4_W <= W4_STACK: the depth is checked at build */
        sp = push_hit(W, q, mask, tn, NULL, stack, sp);
    } else if (t->pend) { /* the exact test of the lanes kept (their triangles asked for) */
        double tmax0 = t->tmax;
        int lanes = t->pend;
        t->pend = 0;
        while (lanes) {
            int j = lane_first(lanes);
            lanes &= lanes - 1;
            /* closest mode: never -1 (no list) nor 1 (not any-hit) */
            (void)leaf_hits(m, t->r, &t->w, t->cur.child + (uint32_t)j, 1, t->tmin, &t->tmax, GEOM__RAY_CLOSEST,
                            &t->best, &t->best_t, t->best_b, NULL);
        }
        if (t->tmax != tmax0) t->ftmax = f_up_fast(t->tmax);
    } else { /* the float pre-test; the exact test of the lanes kept at the slot's next turn */
        uint32_t cnt = W4_CNT(t->cur.count);
        int lanes;
        if (t->w.kz < 0) {
            geom__wbw_setup(&t->w, t->r);
            pk_setup(&t->pk, &t->w, W);
        }
#if W4_AVX2
        if (isa == W4_ISA_AVX2)
            lanes = pk_filter8(&W->pk[W4_PK(t->cur.count)], &t->pk) & ((1 << cnt) - 1);
        else
#endif
            lanes = pk_filter(&W->pk[W4_PK(t->cur.count)], &t->pk) & ((1 << cnt) - 1);
        if (lanes) {
            int l = lanes;
            while (l) { /* 72 bytes a triangle: at most two cache lines each */
                const char *c = (const char *)(m->tv + 9 * (size_t)(t->cur.child + (uint32_t)lane_first(l)));
                l &= l - 1;
                W4_PREFETCH(c);
                W4_PREFETCH(c + 71);
            }
            t->pend = lanes;
            return 1;
        }
    }
pop:
    do {
        if (sp == 0) {
            t->sp = 0;
            return 0;
        }
        sp--;
        t->cur = stack[sp];
    } while (t->cur.tn > t->tmax);
    t->sp = sp;
    w8_fetch(W, t);
    return 1;
}

/* The batch (rays idx[0 .. n), each valid with tmin <= tmax): hits[idx[i]]
 * and found[idx[i]] as geom__ray_mesh in closest mode would give them. */
GEOM__WBW_INLINE geom_status w8_many_t(const geom__tmesh *m, const geom_ray *rays, const size_t *idx, size_t n,
                                       geom_ray_hit *hits, int *found, w8slot *slot,
                                       const geom_allocator *alloc, const int isa)
{
    size_t next = 0;
    int live = 0, k;
    for (k = 0; k < W8_K; k++) slot[k].r = NULL;
    for (;;) {
        for (k = 0; k < W8_K; k++) {
            w8slot *t = &slot[k];
            if (!t->r) { /* refill: the next ray the float test takes */
                while (next < n) {
                    size_t i = idx[next++];
                    if (w8_start(m, t, &rays[i], i)) {
                        live++;
                        w8_fetch(m->wide, t);
                        break;
                    } else {
                        geom__rhits l;
                        geom_status st;
                        geom__rhits_init(&l, alloc);
                        st = trace_wide(m, &rays[i], NULL, GEOM__RAY_CLOSEST, &l);
                        if (st == GEOM_OK && l.n > 0) {
                            hits[i] = l.h[0];
                            found[i] = 1;
                        }
                        geom__rhits_free(&l);
                        if (st != GEOM_OK) return st;
                    }
                }
                if (!t->r) continue;
            }
            if (!w8_step(m, t, isa)) {
                if (t->best != GEOM_INVALID_INDEX) {
                    fill(m, t->r, t->best, t->best_t, t->best_b, &hits[t->idx]);
                    found[t->idx] = 1;
                }
                t->r = NULL;
                live--;
            }
        }
        if (live == 0 && next >= n) return GEOM_OK;
    }
}

static geom_status w8_many_sse2(const geom__tmesh *m, const geom_ray *rays, const size_t *idx, size_t n,
                                geom_ray_hit *hits, int *found, w8slot *slot, const geom_allocator *alloc)
{
    return w8_many_t(m, rays, idx, n, hits, found, slot, alloc, W4_ISA_SSE2);
}

#if W4_AVX2
W4_TGT static geom_status w8_many_avx2(const geom__tmesh *m, const geom_ray *rays, const size_t *idx, size_t n,
                                       geom_ray_hit *hits, int *found, w8slot *slot, const geom_allocator *alloc)
{
    return w8_many_t(m, rays, idx, n, hits, found, slot, alloc, W4_ISA_AVX2);
}
#endif
#endif

/* ---------------------------------------------------------------------
 * Packets of coherent rays (the batch's AVX2 path): eight rays of the same
 * direction octant, close in origin and direction (camera rays of one image
 * row), traverse the wide tree together on one node stack (Wald, Slusallek,
 * Benthin and Wagner, "Interactive Rendering with Coherent Ray Tracing",
 * 2001; with wide nodes, Dammertz et al. 2008). A node's plane codes are
 * read once for the packet, then each child is tested against the eight
 * rays at once, one ray per AVX2 lane, with the same float operations as
 * the single-ray test for each ray: w8_node_rs's ray-side form (A and B per
 * lane, one fused multiply-add per plane, widened by c |t| and the ray's
 * ers) when no ray of the packet has a zero direction component, else
 * w8_node's (the planes decoded, fl(fl(L - of) inv), widened by c |t| and
 * the ray's e); so the same proofs make each lane conservative (w4f, w8_node_rs).
 * Each stack entry carries the rays that enter the child and their entry
 * distances; a ray whose closest hit so far is nearer than its entry is
 * dropped from the entry when it is popped. At a leaf each ray of the entry
 * runs its own float pre-test (pk_filter8) and the exact watertight test,
 * as in trace_wide. The boxes being conservative and the exact test alone
 * deciding (ties by the smaller triangle index, whatever the order), each
 * ray's answer is bit for bit trace_wide's (test_ray_batch). The rays the
 * grouping cannot take (another octant, spread too wide, a ray the float
 * test cannot take) go through the interleaved path (w8_many_t). */
#if W4_AVX2
#define PK8_N 8

typedef struct pk8entry {
    __m256 tn;          /* each ray's entry distance (conservative) */
    uint32_t child, count;
    int mask;           /* the rays that enter it */
    float key;          /* the order on the stack: the entry distance of its first ray */
} pk8entry;

typedef struct pk8ray {
    pkray pk;           /* first: 16-byte aligned */
    geom__wbw w;
    const geom_ray *r;
    size_t idx;
    double tmin, tmax, best_t, best_b[3];
    uint32_t best;
} pk8ray;

typedef struct pk8 {
    __m256 o[3], inv[3], e, tmin; /* lane i: ray i's w4f origin, reciprocal, bound, and tmin rounded down */
    __m256 ers;                   /* lane i: ray i's bound of the ray-side form (w4f ers) */
    int rs;                       /* every ray takes the ray-side form (no zero direction component) */
    float tmaxf[PK8_N];           /* ray i's tmax rounded up */
    size_t noff[3], foff[3];      /* the packet's near and far plane codes (one octant) */
    int n, wset;                  /* rays; those whose shear is set up */
    pk8ray ray[PK8_N];
} pk8;

/* q's eight children's plane codes, per axis, as floats (rs: with each
 * ray's A and B of the ray-side form; else decoded into planes), then each
 * valid child against the packet's rays: cm[j] the rays in `active` that
 * enter child j, tnv[j] their entry distances. Returns the children entered
 * by some ray. */
W4_TGT GEOM__WBW_INLINE int pk8_node_t(const geom__rnode4 *q, const pk8 *P, int active, __m256 tmaxv,
                                        int cm[W4_W], __m256 tnv[W4_W], const int rs)
{
    const __m256 absmask = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff));
    const __m256 vc = _mm256_set1_ps(0x1p-20f);
    __m256 nv[3], fv[3], A[3], B[3];
    int k, valid, hit = 0;
    for (k = 0; k < 3; k++) {
        const __m256 px = _mm256_broadcast_ss(&q->px[k]);
        const __m256 sc = _mm256_castsi256_ps(_mm256_set1_epi32(((int)q->ex[k] + 127) << 23));
        nv[k] = _mm256_cvtepi32_ps(
            _mm256_cvtepu8_epi32(_mm_loadl_epi64((const __m128i *)((const uint8_t *)q + P->noff[k]))));
        fv[k] = _mm256_cvtepi32_ps(
            _mm256_cvtepu8_epi32(_mm_loadl_epi64((const __m128i *)((const uint8_t *)q + P->foff[k]))));
        if (rs) { /* w8_node_rs's A and B, lane i for ray i */
            A[k] = _mm256_mul_ps(sc, P->inv[k]);
            B[k] = _mm256_mul_ps(_mm256_sub_ps(px, P->o[k]), P->inv[k]);
        } else { /* the planes decoded (w8_node) */
            nv[k] = _mm256_fmadd_ps(nv[k], sc, px);
            fv[k] = _mm256_fmadd_ps(fv[k], sc, px);
        }
    }
    valid = ~_mm256_movemask_ps(_mm256_castsi256_ps(
                _mm256_cmpeq_epi32(_mm256_load_si256((const __m256i *)q->child), _mm256_set1_epi32(-1)))) &
            0xff;
    while (valid) {
        const int j = __builtin_ctz((unsigned)valid);
        const __m256i ix = _mm256_set1_epi32(j);
        __m256 tn = P->tmin, tf = tmaxv, e;
        int mj;
        valid &= valid - 1;
        /* maxps/minps return the second operand when either is NaN */
        if (rs) {
            for (k = 0; k < 3; k++) {
                tn = _mm256_max_ps(_mm256_fmadd_ps(_mm256_permutevar8x32_ps(nv[k], ix), A[k], B[k]), tn);
                tf = _mm256_min_ps(_mm256_fmadd_ps(_mm256_permutevar8x32_ps(fv[k], ix), A[k], B[k]), tf);
            }
            e = P->ers;
        } else {
            for (k = 0; k < 3; k++) {
                tn = _mm256_max_ps(
                    _mm256_mul_ps(_mm256_sub_ps(_mm256_permutevar8x32_ps(nv[k], ix), P->o[k]), P->inv[k]), tn);
                tf = _mm256_min_ps(
                    _mm256_mul_ps(_mm256_sub_ps(_mm256_permutevar8x32_ps(fv[k], ix), P->o[k]), P->inv[k]), tf);
            }
            e = P->e;
        }
        tn = _mm256_sub_ps(_mm256_sub_ps(tn, _mm256_mul_ps(_mm256_and_ps(tn, absmask), vc)), e);
        tf = _mm256_add_ps(_mm256_add_ps(tf, _mm256_mul_ps(_mm256_and_ps(tf, absmask), vc)), e);
        mj = _mm256_movemask_ps(_mm256_cmp_ps(tn, tf, _CMP_LE_OQ)) & active;
        cm[j] = mj;
        tnv[j] = tn;
        hit |= (mj != 0) << j;
    }
    return hit;
}

/* pk8_node_t in the packet's form (rs a constant in each copy). */
W4_TGT static inline int pk8_node(const geom__rnode4 *q, const pk8 *P, int active, __m256 tmaxv, int cm[W4_W],
                                  __m256 tnv[W4_W])
{
    return P->rs ? pk8_node_t(q, P, active, tmaxv, cm, tnv, 1) : pk8_node_t(q, P, active, tmaxv, cm, tnv, 0);
}

/* The packet's traversal (closest mode): each ray's best hit in P->ray[i]. */
W4_TGT static void pk8_trace(const geom__tmesh *m, pk8 *P, pk8entry *stack)
{
    const struct geom__rbvh4 *W = m->wide;
    pk8entry cur;
    __m256 tmaxv = _mm256_loadu_ps(P->tmaxf);
    int sp = 0;
    cur.tn = P->tmin;
    cur.child = 0;
    cur.count = 0;
    cur.mask = (1 << P->n) - 1;
    for (;;) {
        if (cur.count == 0) {
            const geom__rnode4 *q = &W->node[cur.child];
            int cm[W4_W], hit, base, j;
            __m256 tnv[W4_W];
            hit = pk8_node(q, P, cur.mask, tmaxv, cm, tnv);
            if (hit == 0) goto pop;
            if ((hit & (hit - 1)) == 0) { /* one child entered: next, no stack traffic */
                j = __builtin_ctz((unsigned)hit);
                cur.tn = tnv[j];
                cur.child = q->child[j];
                cur.count = q->count[j];
                cur.mask = cm[j];
                continue;
            }
            /* pushed by decreasing entry distance of the child's first ray
             * (an order only: any order gives the same answers);
             * sp + W4_W <= W4_STACK: the depth is checked at build */
            base = sp;
            while (hit) {
                float ki;
                int i;
                j = __builtin_ctz((unsigned)hit);
                hit &= hit - 1;
                /* lane ctz(cm[j]) taken in a register (a scalar read of the
                 * vector just stored would wait for it) */
                ki = _mm256_cvtss_f32(
                    _mm256_permutevar8x32_ps(tnv[j], _mm256_set1_epi32(__builtin_ctz((unsigned)cm[j]))));
                i = sp++;
                while (i > base && stack[i - 1].key < ki) {
                    stack[i] = stack[i - 1];
                    i--;
                }
                stack[i].tn = tnv[j];
                stack[i].child = q->child[j];
                stack[i].count = q->count[j];
                stack[i].mask = cm[j];
                stack[i].key = ki;
                fetch_child(W, q->child[j], q->count[j]);
            }
        } else {
            const geom__rpack4 *pq = &W->pk[W4_PK(cur.count)];
            const int cl = (1 << W4_CNT(cur.count)) - 1;
            int rm = cur.mask, changed = 0;
            fetch_tris(m, cur.child, W4_CNT(cur.count)); /* with the packet (trace_wide_t) */
            while (rm) {
                const int i = __builtin_ctz((unsigned)rm);
                pk8ray *R = &P->ray[i];
                double tmax0 = R->tmax;
                int lanes;
                rm &= rm - 1;
                if (!(P->wset & (1 << i))) {
                    geom__wbw_setup(&R->w, R->r);
                    pk_setup(&R->pk, &R->w, W);
                    P->wset |= 1 << i;
                }
                lanes = pk_filter8(pq, &R->pk) & cl;
                while (lanes) {
                    const int j = lane_first(lanes);
                    lanes &= lanes - 1;
                    (void)leaf_hits(m, R->r, &R->w, cur.child + (uint32_t)j, 1, R->tmin, &R->tmax,
                                    GEOM__RAY_CLOSEST, &R->best, &R->best_t, R->best_b, NULL);
                }
                if (R->tmax != tmax0) {
                    P->tmaxf[i] = f_up_fast(R->tmax);
                    changed = 1;
                }
            }
            if (changed) tmaxv = _mm256_loadu_ps(P->tmaxf);
        }
    pop:
        for (;;) { /* the rays whose closest hit so far is nearer than the entry dropped */
            int mk;
            if (sp == 0) return;
            sp--;
            mk = stack[sp].mask & _mm256_movemask_ps(_mm256_cmp_ps(stack[sp].tn, tmaxv, _CMP_LE_OQ));
            if (mk) {
                cur = stack[sp];
                cur.mask = mk;
                break;
            }
        }
    }
}

/* Rays spread (origin, plus direction times the distance across the mesh)
 * up to this fraction of the mesh's largest half extent make a packet. */
#ifndef PK8_SPREAD
#define PK8_SPREAD 0.5
#endif

/* Set P up for rays idx[0 .. n) (2 <= n <= 8) when they make a packet:
 * each taken by the float node test, one direction octant, and close
 * (PK8_SPREAD) for a mesh of centre c and largest half extent hd. */
W4_TGT static int pk8_setup(const struct geom__rbvh4 *W, pk8 *P, const geom_ray *rays, const size_t *idx, int n,
                            const double c[3], double hd)
{
    float of[3][PK8_N], iv[3][PK8_N], e[PK8_N], ers[PK8_N], tmin[PK8_N];
    double O[3][PK8_N], D[3][PK8_N], INV[3][PK8_N], U[3][PK8_N], reach = 0;
    int i, k, rs = 1, h;
    /* The rays' origins and directions by axis (the lanes past n: ray 0's). */
    for (i = 0; i < PK8_N; i++) {
        const geom_ray *r = &rays[idx[i < n ? i : 0]];
        O[0][i] = r->origin.x; O[1][i] = r->origin.y; O[2][i] = r->origin.z;
        D[0][i] = r->dir.x; D[1][i] = r->dir.y; D[2][i] = r->dir.z;
    }
    /* One octant: the direction's sign bits all ray 0's. */
    for (k = 0; k < 3; k++)
        for (i = 1; i < n; i++)
            if ((signbit(D[k][i]) != 0) != (signbit(D[k][0]) != 0)) return 0;
    /* The reciprocals (1 / +-0 = +-inf: trace_wide_t's definition, the
     * same correctly rounded quotients) and the directions scaled to a
     * largest component of 1, four rays at a time. */
    for (h = 0; h < PK8_N; h += 4) {
        const __m256d one = _mm256_set1_pd(1.0), abs = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7fffffffffffffffLL));
        __m256d d[3], l;
        for (k = 0; k < 3; k++) {
            d[k] = _mm256_loadu_pd(&D[k][h]);
            _mm256_storeu_pd(&INV[k][h], _mm256_div_pd(one, d[k]));
        }
        l = _mm256_max_pd(_mm256_and_pd(d[0], abs), _mm256_max_pd(_mm256_and_pd(d[1], abs), _mm256_and_pd(d[2], abs)));
        l = _mm256_div_pd(one, l);
        for (k = 0; k < 3; k++) _mm256_storeu_pd(&U[k][h], _mm256_mul_pd(d[k], l));
    }
    /* Close: origin spread plus direction spread times the way across the mesh. */
    for (k = 0; k < 3; k++) reach = fabs(c[k] - O[k][0]) > reach ? fabs(c[k] - O[k][0]) : reach;
    reach += hd;
    for (i = 1; i < n; i++) {
        double sp = 0, du = 0;
        for (k = 0; k < 3; k++) {
            sp = fabs(O[k][i] - O[k][0]) > sp ? fabs(O[k][i] - O[k][0]) : sp;
            du = fabs(U[k][i] - U[k][0]) > du ? fabs(U[k][i] - U[k][0]) : du;
        }
        if (!(sp + du * reach <= PK8_SPREAD * hd)) return 0;
    }
    /* Each ray's float node-test state: w4f_setup's, four rays at a time,
     * the same double operations in the same order and the same roundings
     * to float (f_up_fast's in its fast range, below 2^100). A ray the
     * float test cannot take, or a bound beyond 2^100, and the run makes
     * no packet (its rays go the interleaved way). */
    for (h = 0; h < PK8_N; h += 4) {
        const __m256d abs = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7fffffffffffffffLL));
        const __m256d zero = _mm256_setzero_pd(), lim = _mm256_set1_pd(W4_FMAX);
        const __m256d c40 = _mm256_set1_pd(1 + 0x1p-40), c60 = _mm256_set1_pd(0x1p-60);
        const __m256d c22 = _mm256_set1_pd(1 + 0x1p-22), big = _mm256_set1_pd(0x1p100);
        __m256d ok = _mm256_castsi256_pd(_mm256_set1_epi64x(-1)), nzall = ok, ev = zero, fr = zero, x, y;
        float ef[4], ersf[4];
        int lanes = n - h >= 4 ? 15 : n - h <= 0 ? 0 : (1 << (n - h)) - 1, m;
        for (k = 0; k < 3; k++) {
            const __m256d o = _mm256_loadu_pd(&O[k][h]), d = _mm256_loadu_pd(&D[k][h]);
            const __m256d iv2 = _mm256_loadu_pd(&INV[k][h]);
            const __m256d nz = _mm256_cmp_pd(d, zero, _CMP_NEQ_OQ);
            const __m128 of4 = _mm256_cvtpd_ps(o), iv4 = _mm256_cvtpd_ps(iv2); /* d == 0: +-inf */
            const __m256d ofd = _mm256_cvtps_pd(of4);
            ok = _mm256_and_pd(ok, _mm256_cmp_pd(_mm256_and_pd(o, abs), lim, _CMP_LE_OQ));
            ok = _mm256_and_pd(ok, _mm256_or_pd(_mm256_cmp_pd(d, zero, _CMP_EQ_OQ),
                                                _mm256_cmp_pd(_mm256_and_pd(iv2, abs), lim, _CMP_LE_OQ)));
            nzall = _mm256_and_pd(nzall, nz);
            /* e: the largest |o - of| |inv| over the axes with d != 0 */
            ev = _mm256_max_pd(_mm256_and_pd(_mm256_mul_pd(_mm256_and_pd(_mm256_sub_pd(o, ofd), abs),
                                                           _mm256_and_pd(iv2, abs)),
                                             nz),
                               ev);
            /* fr: the largest 2^-21 (pmax + |of|) |inv| (NaN ignored, as the scalar test does) */
            fr = _mm256_max_pd(_mm256_mul_pd(_mm256_mul_pd(_mm256_set1_pd(0x1p-21),
                                                           _mm256_add_pd(_mm256_set1_pd(W->pmax),
                                                                         _mm256_and_pd(ofd, abs))),
                                             _mm256_and_pd(_mm256_cvtps_pd(iv4), abs)),
                               fr);
            _mm_storeu_ps(&of[k][h], of4);
            _mm_storeu_ps(&iv[k][h], iv4);
        }
        x = _mm256_add_pd(_mm256_mul_pd(_mm256_mul_pd(_mm256_set1_pd(2), ev), c40), c60);
        y = _mm256_add_pd(_mm256_mul_pd(_mm256_add_pd(_mm256_mul_pd(_mm256_set1_pd(2), ev), fr), c40), c60);
        ok = _mm256_and_pd(ok, _mm256_cmp_pd(x, big, _CMP_LE_OQ));
        m = _mm256_movemask_pd(nzall) & lanes;
        if (m != lanes) rs = 0;
        if ((_mm256_movemask_pd(ok) & lanes) != lanes) return 0;
        if (rs && (_mm256_movemask_pd(_mm256_cmp_pd(y, big, _CMP_LE_OQ)) & lanes) != lanes) return 0;
        _mm_storeu_ps(ef, _mm256_cvtpd_ps(_mm256_mul_pd(x, c22)));
        _mm_storeu_ps(ersf, _mm256_cvtpd_ps(_mm256_mul_pd(y, c22)));
        for (i = 0; i < 4; i++) {
            e[h + i] = ef[i];
            ers[h + i] = ersf[i];
        }
    }
    for (k = 0; k < 3; k++) {
        const int nhi = signbit(D[k][0]) != 0;
        P->noff[k] = (nhi ? offsetof(geom__rnode4, qhi) : offsetof(geom__rnode4, qlo)) + W4_W * (size_t)k;
        P->foff[k] = (nhi ? offsetof(geom__rnode4, qlo) : offsetof(geom__rnode4, qhi)) + W4_W * (size_t)k;
    }
    for (i = 0; i < n; i++) {
        const geom_ray *r = &rays[idx[i]];
        tmin[i] = f_down_fast(r->tmin);
        P->tmaxf[i] = f_up_fast(r->tmax);
        P->ray[i].r = r;
        P->ray[i].idx = idx[i];
        P->ray[i].tmin = r->tmin;
        P->ray[i].tmax = r->tmax;
        P->ray[i].best = GEOM_INVALID_INDEX;
        P->ray[i].best_t = 0;
        P->ray[i].best_b[0] = P->ray[i].best_b[1] = P->ray[i].best_b[2] = 0;
    }
    for (i = n; i < PK8_N; i++) { /* lanes without a ray: masked off */
        for (k = 0; k < 3; k++) of[k][i] = iv[k][i] = 0;
        e[i] = ers[i] = 0;
        tmin[i] = INFINITY;
        P->tmaxf[i] = -INFINITY;
    }
    for (k = 0; k < 3; k++) {
        P->o[k] = _mm256_loadu_ps(of[k]);
        P->inv[k] = _mm256_loadu_ps(iv[k]);
    }
    P->e = _mm256_loadu_ps(e);
    P->ers = _mm256_loadu_ps(ers);
    P->rs = rs;
    P->tmin = _mm256_loadu_ps(tmin);
    P->n = n;
    P->wset = 0;
    return 1;
}

/* The centre c and largest half extent *hd of m's root box. */
static void pk8_bounds(const geom__tmesh *m, double c[3], double *hd)
{
    size_t nn = 0;
    const geom_bvh_node *bn = geom_bvh_nodes(m->bvh, &nn);
    int k;
    *hd = 0;
    for (k = 0; k < 3; k++) {
        const double lo = (&bn[0].box.min.x)[k], hi = (&bn[0].box.max.x)[k];
        c[k] = 0.5 * (lo + hi);
        *hd = 0.5 * (hi - lo) > *hd ? 0.5 * (hi - lo) : *hd;
    }
}

/* The packets among rays idx[0 .. n), in runs of eight consecutive rays:
 * each answered (hits and found as trace_wide gives them); the rays of the
 * runs that make no packet appended to rest (returns their number). With
 * hits NULL, only the packets counted (returned; rest unused). */
W4_TGT static size_t pk8_many(const geom__tmesh *m, const geom_ray *rays, const size_t *idx, size_t n,
                              geom_ray_hit *hits, int *found, pk8 *P, pk8entry *stack, size_t *rest)
{
    const struct geom__rbvh4 *W = m->wide;
    size_t g, nrest = 0, npk = 0;
    double c[3], hd;
    pk8_bounds(m, c, &hd);
    for (g = 0; g < n; g += PK8_N) {
        const int cnt = n - g < PK8_N ? (int)(n - g) : PK8_N;
        int i;
        if (cnt < 2 || !pk8_setup(W, P, rays, idx + g, cnt, c, hd)) {
            if (hits)
                for (i = 0; i < cnt; i++) rest[nrest++] = idx[g + (size_t)i];
            continue;
        }
        npk++;
        if (!hits) continue;
        pk8_trace(m, P, stack);
        for (i = 0; i < cnt; i++) {
            const pk8ray *R = &P->ray[i];
            if (R->best != GEOM_INVALID_INDEX) {
                fill(m, R->r, R->best, R->best_t, R->best_b, &hits[R->idx]);
                found[R->idx] = 1;
            }
        }
    }
    return hits ? nrest : npk;
}
#endif

#if W4_SSE
/* The interleaved traversal of rays idx[0 .. n) (w8_many_t). */
static geom_status w8_many(const geom__tmesh *m, const geom_ray *rays, const size_t *idx, size_t n,
                           geom_ray_hit *hits, int *found, const geom_allocator *alloc)
{
    const size_t bytes = W8_K * sizeof(w8slot) + 64 + (size_t)W8_K * W4_STACK * sizeof(w4entry);
    w8slot *slot;
    void *mem;
    geom_status st;
    size_t i;
    mem = geom__alloc(alloc, bytes);
    if (!mem) return GEOM_ERR_NOMEM;
    slot = (w8slot *)(((uintptr_t)mem + 63) & ~(uintptr_t)63);
    for (i = 0; i < W8_K; i++) slot[i].stack = (w4entry *)(slot + W8_K) + i * W4_STACK;
#if W4_AVX2
    if (m->wide->isa == W4_ISA_AVX2)
        st = w8_many_avx2(m, rays, idx, n, hits, found, slot, alloc);
    else
#endif
        st = w8_many_sse2(m, rays, idx, n, hits, found, slot, alloc);
    geom__free(alloc, mem, bytes);
    return st;
}
#endif

geom_status geom__ray_mesh_closest_many(const geom__tmesh *m, const geom_ray *rays, const size_t *idx, size_t n,
                                        geom_ray_hit *hits, int *found, const geom_allocator *alloc)
{
    size_t i;
    if (!m->bvh) return GEOM_OK;
#if W4_SSE
    if (m->wide) {
#if W4_AVX2
        if (m->wide->isa == W4_ISA_AVX2 && m->wide->fbox && n >= 2) {
            /* the packets first, then the rays they leave, interleaved */
            const size_t bytes = sizeof(pk8) + W4_STACK * sizeof(pk8entry) + n * sizeof(size_t) + 64;
            void *mem = geom__alloc(alloc, bytes);
            pk8 *P;
            pk8entry *stack;
            size_t *rest, nrest;
            geom_status st = GEOM_OK;
            if (!mem) return GEOM_ERR_NOMEM;
            P = (pk8 *)(((uintptr_t)mem + 63) & ~(uintptr_t)63);
            stack = (pk8entry *)(P + 1);
            rest = (size_t *)(stack + W4_STACK);
            nrest = pk8_many(m, rays, idx, n, hits, found, P, stack, rest);
            if (nrest > 0) st = w8_many(m, rays, rest, nrest, hits, found, alloc);
            geom__free(alloc, mem, bytes);
            return st;
        }
#endif
        return w8_many(m, rays, idx, n, hits, found, alloc);
    }
#endif
    for (i = 0; i < n; i++) {
        geom__rhits l;
        geom_status st;
        geom__rhits_init(&l, alloc);
        st = geom__ray_mesh(m, &rays[idx[i]], GEOM__RAY_CLOSEST, &l);
        if (st == GEOM_OK && l.n > 0) {
            hits[idx[i]] = l.h[0];
            found[idx[i]] = 1;
        }
        geom__rhits_free(&l);
        if (st != GEOM_OK) return st;
    }
    return GEOM_OK;
}

/* The valid rays of rays[0 .. n) with tmin <= tmax into idx (their
 * number); *bad = 1 when some ray is invalid. */
static size_t valid_rays(const geom_ray *rays, size_t n, size_t *idx, int *bad)
{
    size_t i, nv = 0;
    for (i = 0; i < n; i++) {
        if (!geom__ray_valid(&rays[i])) { *bad = 1; continue; }
        if (rays[i].tmin <= rays[i].tmax) idx[nv++] = i;
    }
    return nv;
}

/* The single mesh closest_many traverses for s, or NULL. */
static const geom__tmesh *single_mesh(const geom_ray_scene *s)
{
    const geom__ray_node *nd = s->nroots == 1 ? &s->nodes[s->roots[0]] : NULL;
    if (!nd || (nd->kind != GEOM_RAY_MESH && nd->kind != GEOM_RAY_SUBDIV) || nd->has_xf || !nd->mesh ||
        !nd->mesh->wide)
        return NULL;
    return nd->mesh;
}

size_t geom__ray_scene_packets(const geom_ray_scene *s, const geom_ray *rays, size_t n)
{
    size_t npk = 0;
#if W4_AVX2
    const geom__tmesh *m = s && s->built ? single_mesh(s) : NULL;
    if (m && m->wide->isa == W4_ISA_AVX2 && m->wide->fbox && n > 0) {
        const size_t bytes = sizeof(pk8) + n * sizeof(size_t) + 64;
        void *mem = geom__alloc(s->alloc, bytes);
        pk8 *P;
        size_t *idx, nv;
        int bad = 0;
        if (!mem) return 0;
        P = (pk8 *)(((uintptr_t)mem + 63) & ~(uintptr_t)63);
        idx = (size_t *)(P + 1);
        nv = valid_rays(rays, n, idx, &bad);
        npk = pk8_many(m, rays, idx, nv, NULL, NULL, P, NULL, NULL);
        geom__free(s->alloc, mem, bytes);
    }
#else
    (void)s; (void)rays; (void)n;
#endif
    return npk;
}

int geom__ray_scene_simd(geom_ray_scene *s, int isa)
{
    size_t i;
    int prev = -1;
    for (i = 0; i < s->n; i++) {
        struct geom__rbvh4 *w = s->nodes[i].mesh ? s->nodes[i].mesh->wide : NULL;
        if (!w) continue;
        if (prev < 0) prev = w->isa;
        if (isa == W4_ISA_SSE2 || (isa == W4_ISA_AVX2 && isa_best() == W4_ISA_AVX2)) w->isa = isa;
    }
    return prev;
}

geom_status geom__ray_mesh(const geom__tmesh *m, const geom_ray *r, int mode, geom__rhits *out)
{
    return geom__ray_mesh_sl(m, r, NULL, mode, out);
}

geom_status geom__ray_mesh_sl(const geom__tmesh *m, const geom_ray *r, const geom__rslab *sl, int mode,
                              geom__rhits *out)
{
    const geom_bvh_node *nodes;
    size_t nn = 0;
    uint32_t stack[256];
    int sp = 0;
    slabray s;
    geom__wbw w;
    double tmax = r->tmax, best_b[3] = {0, 0, 0}, best_t = 0;
    uint32_t best = GEOM_INVALID_INDEX;
    int k;
    if (!m->bvh) return GEOM_OK;
    if (m->wide) return trace_wide(m, r, sl && sl->ok >= 0 ? sl : NULL, mode, out);
    nodes = geom_bvh_nodes(m->bvh, &nn);
    if (nn == 0) return GEOM_OK;
    s.o[0] = r->origin.x; s.o[1] = r->origin.y; s.o[2] = r->origin.z;
    {
        double d[3] = {r->dir.x, r->dir.y, r->dir.z};
        for (k = 0; k < 3; k++) {
            s.zero[k] = d[k] == 0;
            s.inv[k] = s.zero[k] ? 0 : 1.0 / d[k];
            s.neg[k] = d[k] < 0;
        }
    }
    geom__wbw_setup(&w, r);
    {
        double tn;
        if (!node_hit(&s, &nodes[0].box, r->tmin, tmax, &tn)) return GEOM_OK;
    }
    stack[sp++] = 0;
    while (sp > 0) {
        uint32_t ni = stack[--sp];
        const geom_bvh_node *nd = &nodes[ni];
        if (nd->count == 0) {
            uint32_t a = ni + 1, b = nd->index;
            double ta = 0, tb = 0;
            int ha = node_hit(&s, &nodes[a].box, r->tmin, tmax, &ta);
            int hb = node_hit(&s, &nodes[b].box, r->tmin, tmax, &tb);
            if (ha && hb) {
                if (sp + 2 > (int)(sizeof stack / sizeof stack[0])) return GEOM_ERR_LIMIT;
                if (ta <= tb) { stack[sp++] = b; stack[sp++] = a; }
                else { stack[sp++] = a; stack[sp++] = b; }
            } else if (ha || hb) {
                if (sp + 1 > (int)(sizeof stack / sizeof stack[0])) return GEOM_ERR_LIMIT;
                stack[sp++] = ha ? a : b;
            }
        } else {
            int lr = leaf_hits(m, r, &w, nd->index, nd->count, r->tmin, &tmax, mode, &best, &best_t,
                               best_b, out);
            if (lr < 0) return GEOM_ERR_NOMEM;
            if (lr > 0) goto done;
        }
    }
done:
    return finish(m, r, mode, best, best_t, best_b, out);
}

geom_status geom_ray_scene_closest_many(const geom_ray_scene *s, const geom_ray *rays, size_t n,
                                        geom_ray_hit *hits, int *found)
{
    const geom__tmesh *m;
    size_t i, nv = 0, *idx;
    int bad = 0;
    geom_status st;
    if (!s || (n && (!rays || !hits || !found))) return GEOM_ERR_INVALID_ARG;
    for (i = 0; i < n; i++) found[i] = 0;
    if (!s->built) return GEOM_ERR_INVALID_ARG;
    m = single_mesh(s);
    if (!m) {
        /* not a single mesh: one ray at a time */
        for (i = 0; i < n; i++) {
            st = geom_ray_scene_closest(s, &rays[i], &hits[i], &found[i]);
            if (st == GEOM_ERR_INVALID_ARG) bad = 1;
            else if (st != GEOM_OK) return st;
        }
        return bad ? GEOM_ERR_INVALID_ARG : GEOM_OK;
    }
    idx = geom__alloc(s->alloc, (n ? n : 1) * sizeof *idx);
    if (!idx) return GEOM_ERR_NOMEM;
    nv = valid_rays(rays, n, idx, &bad);
    st = geom__ray_mesh_closest_many(m, rays, idx, nv, hits, found, s->alloc);
    geom__free(s->alloc, idx, (n ? n : 1) * sizeof *idx);
    if (st != GEOM_OK) return st;
    return bad ? GEOM_ERR_INVALID_ARG : GEOM_OK;
}
