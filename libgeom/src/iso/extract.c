/*
 * The marching cubes driver: slabs of cell layers, each evaluated two node
 * layers at a time, processed in parallel (OpenMP) and merged in order.
 *
 * Within a slab, vertices are created lazily in scan order (cell layers,
 * rows, cells) and shared by edge through per-layer index arrays. Vertices
 * on the slab's first and last node layers are also made by the
 * neighbouring slab; each slab lists them by key, and the merge maps the
 * copies of slab s's first layer onto those of slab s-1's last layer. The
 * slab partition depends only on the grid size, so the output does not
 * depend on the number of threads.
 */
#define _POSIX_C_SOURCE 200809L /* nanosleep */
#include "iso/iso_internal.h"
#include "implicit/implicit_internal.h"

#include <stdint.h>

#include <float.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef GEOM_ISO_OPENMP
#include <omp.h>
#endif

#define NONE UINT32_MAX
/* Infinities become +-ISO_BIG and NaN +ISO_BIG: finite stand-ins (the
 * deciders scale each cell's values by a power of two, so no product
 * overflows). */
#define ISO_BIG DBL_MAX

typedef struct iso_key {
    uint64_t key;
    uint32_t id;
} iso_key;

typedef struct ctx {
    const geom_iso_field *field; /* refinement, normals (never NULL) */
    const geom_iso_grid *grid;   /* samples, or NULL: evaluate field */
    /* the field's compiled expression (field->value is the expression's
     * callback): rows are sampled by geom__implicit_expr_rows */
    const geom_implicit_expr *expr;
    size_t n[3];                 /* cells per axis */
    const double *coord[3];      /* node coordinates, n + 1 each */
    double iso;
    int refine, normals, caps;
    int max_iter;
    double tau[3];
    double dstep[3]; /* central-difference steps */
    const iso_case_table *cases;
    const geom_allocator *alloc;
    /* Sparse path: the class of each block of bsz^3 cells (BLK_*), block
     * (bx, by, bz) at bx + nb[0] * (by + nb[1] * bz); NULL = dense. */
    const uint8_t *blk;
    size_t bsz, nb[3];
    /* per block row (by, bz) at by + nb[1] * bz: the class of all its
     * blocks when they are skipped and of one class, else ROW_MIXED */
    const uint8_t *rowcls;
    /* The stream path (geom_iso_extract_stream): the chunks go to sink
     * instead of the output arrays; NULL = arrays. */
    geom_iso_chunk_fn sink;
    void *sink_user;
    /* the stream path: slab arrays handed back, for later slabs */
    struct slab_pool *pool;
} ctx;

/* Block classes of the sparse path. */
enum { BLK_SAMPLE = 0, BLK_OUT = 1, BLK_IN = 2, ROW_MIXED = 0xFF };

#if defined(__GNUC__)
#define ISO_PREFETCH(p) __builtin_prefetch((p), 1)
#else
#define ISO_PREFETCH(p) ((void)(p))
#endif

typedef struct slab {
    size_t k0, k1;
    double *xyz, *nrm;
    size_t nv, capv, capn;
    uint32_t *tri;
    size_t ntri, captri;
    uint32_t *cap;
    size_t ncap, capcap;
    iso_key *bot, *top;
    size_t nbot, capbot, ntop, captop;
    size_t evaluations, active, ambiguous, tunnels, iso_nodes, nan_nodes, refined;
    int has_nan;
    size_t nan_at[3]; /* the slab's first NaN node in scan order */
    geom_status status;
} slab;

/* One node layer: values, signs, per-row sign-change ranges, and the
 * vertex ids of its x and y edges and nodes. An id slot is valid when it is
 * at least the layer's epoch (the slab's vertex count when the layer was
 * evaluated): ids only grow, so stale ids from earlier layers never pass,
 * and no clearing is needed. */
typedef struct layer {
    double *buf;    /* values, when they are not read from the grid itself */
    const double *v; /* the layer's raw values (buf, or the grid's samples) */
    uint8_t *s;
    /* per row: its signs, s + j * (nx + 1) or, for a row of one sign
     * (skipped blocks only), the work's row of that sign (no copy) */
    const uint8_t **sr;
    uint32_t *rlo, *rhi; /* per row: first cell with a sign change, last + 1 */
    uint32_t *xv, *yv, *nv;
    uint32_t epoch;
} layer;

/* A thread's working memory, reused for every slab the thread runs. Id
 * slots hold base + (the slab's local vertex id); base grows from slab to
 * slab, so slots left by earlier slabs (or layers) are below every epoch
 * and the arrays never need clearing, except when base would overflow. */
typedef struct work {
    layer L[2];
    uint32_t *zv;
    uint32_t zepoch;
    uint32_t base;
    uint8_t *ones, *zeros; /* rows of nx + 1 signs, outside and inside */
    uint32_t *act;         /* a cell row's active cells (nx) */
    uint8_t *amask;        /* and their sign masks */
    double *pts;
    /* the sparse path: a node row's runs of sampled nodes ([2q], [2q+1])
     * and, for an expression, their x coordinates and values gathered */
    size_t *runs;
    double *gx, *gv;
    geom__expr_rows *rows; /* c->expr's row plan, made once per thread */
    size_t k; /* current cell layer */
    layer *lb, *lt;
    int ok;
    /* the thread's last slab's vertex and triangle counts, plus 1/8: the
     * next slab's first capacity (no growth by doubling, as a rule) */
    size_t hint_nv, hint_tri;
} work;

/* ------------------------------------------------------------ growth */

static int grow(const geom_allocator *a, void **p, size_t *cap, size_t need, size_t elem)
{
    return geom__grow(a, p, cap, need, elem) == GEOM_OK;
}

static void slab_free(const geom_allocator *a, slab *s)
{
    geom__free(a, s->xyz, s->capv * 3 * sizeof(double));
    geom__free(a, s->nrm, s->capn * 3 * sizeof(double));
    geom__free(a, s->tri, s->captri * 3 * sizeof(uint32_t));
    geom__free(a, s->cap, s->capcap * 3 * sizeof(uint32_t));
    geom__free(a, s->bot, s->capbot * sizeof(iso_key));
    geom__free(a, s->top, s->captop * sizeof(iso_key));
    s->xyz = s->nrm = NULL;
    s->tri = s->cap = NULL;
    s->bot = s->top = NULL;
    s->capv = s->capn = s->captri = s->capcap = s->capbot = s->captop = 0;
}

/* The stream path's spare slab arrays: a slab handed over gives back its
 * vertex, normal and triangle arrays, and a slab starting takes a set,
 * so their pages are faulted in (and cached) once, not per slab. */
typedef struct slab_pool {
    slab *spare; /* only xyz, nrm, tri and their capacities */
    size_t n;
} slab_pool;

/* Move from's vertex, normal and triangle arrays to `to` (whose own are
 * NULL), leaving from without them. */
static void move_arrays(slab *to, slab *from)
{
    to->xyz = from->xyz;
    to->capv = from->capv;
    to->nrm = from->nrm;
    to->capn = from->capn;
    to->tri = from->tri;
    to->captri = from->captri;
    from->xyz = from->nrm = NULL;
    from->tri = NULL;
    from->capv = from->capn = from->captri = 0;
}

static void pool_take(const ctx *c, slab *s)
{
    if (!c->pool)
        return;
#ifdef GEOM_ISO_OPENMP
#pragma omp critical(geom_iso_pool)
#endif
    {
        if (c->pool->n > 0)
            move_arrays(s, &c->pool->spare[--c->pool->n]);
    }
}

static void pool_put(const ctx *c, slab *s)
{
#ifdef GEOM_ISO_OPENMP
#pragma omp critical(geom_iso_pool)
#endif
    move_arrays(&c->pool->spare[c->pool->n++], s);
}

/* ---------------------------------------------------------- vertices */

static uint32_t add_vertex(slab *s, const ctx *c, const double p[3], int axis, double dir)
{
    if (s->status != GEOM_OK)
        return 0;
    if (s->nv >= (size_t)UINT32_MAX / 2 - 2) { /* ids + the thread's slot base fit 32 bits */
        s->status = GEOM_ERR_LIMIT;
        return 0;
    }
    if (!grow(c->alloc, (void **)&s->xyz, &s->capv, s->nv + 1, 3 * sizeof(double)) ||
        (c->normals &&
         !grow(c->alloc, (void **)&s->nrm, &s->capn, s->nv + 1, 3 * sizeof(double)))) {
        s->status = GEOM_ERR_NOMEM;
        return 0;
    }
    double *x = s->xyz + 3 * s->nv;
    x[0] = p[0];
    x[1] = p[1];
    x[2] = p[2];
    if (c->normals) {
        double g[3];
        geom__iso_field_gradient(c->field, p, c->dstep, g, &s->evaluations);
        double n = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
        double *o = s->nrm + 3 * s->nv;
        if (n > 0 && isfinite(n)) {
            o[0] = g[0] / n;
            o[1] = g[1] / n;
            o[2] = g[2] / n;
        } else {
            o[0] = o[1] = o[2] = 0;
            o[axis] = dir;
        }
    }
    return (uint32_t)s->nv++;
}

static void add_key(slab *s, const ctx *c, size_t layer_k, uint64_t key, uint32_t id)
{
    iso_key **keys;
    size_t *n, *cap;
    if (layer_k == s->k0 && s->k0 > 0)
        keys = &s->bot, n = &s->nbot, cap = &s->capbot;
    else if (layer_k == s->k1 && s->k1 < c->n[2])
        keys = &s->top, n = &s->ntop, cap = &s->captop;
    else
        return;
    if (!grow(c->alloc, (void **)keys, cap, *n + 1, sizeof(iso_key))) {
        s->status = GEOM_ERR_NOMEM;
        return;
    }
    (*keys)[*n].key = key;
    (*keys)[*n].id = id;
    (*n)++;
}

/* The field minus iso along an edge: p with p[axis] = x. */
typedef struct edge_fn {
    const ctx *c;
    double p[3];
    int axis;
} edge_fn;

static double along_edge(void *u, double x)
{
    edge_fn *e = u;
    double p[3] = {e->p[0], e->p[1], e->p[2]};
    p[e->axis] = x;
    return e->c->field->value(e->c->field->user, p) - e->c->iso;
}

/* The vertex on the edge from node (i, j, k) along axis, whose end values
 * are ga (at the node) and gb (at the next node along axis). */
static uint32_t edge_vertex(slab *s, const ctx *c, size_t i, size_t j, size_t k, int axis,
                            double ga, double gb)
{
    size_t idx[3] = {i, j, k};
    double pa[3] = {c->coord[0][i], c->coord[1][j], c->coord[2][k]};
    double b = c->coord[axis][idx[axis] + 1];
    double t;
    if (ga == 0)
        t = 0;
    else if (gb == 0)
        t = 1;
    else if (fabs(ga) > 0x1p1020 || fabs(gb) > 0x1p1020)
        t = (0.25 * ga) / (0.25 * ga - 0.25 * gb); /* ga - gb would overflow */
    else
        t = ga / (ga - gb);
    if (!(t >= 0))
        t = 0;
    if (t > 1)
        t = 1;
    double p[3] = {pa[0], pa[1], pa[2]};
    double tau = c->tau[axis];
    if (c->refine && t > 0 && t < 1 && fabs(ga) < ISO_BIG && fabs(gb) < ISO_BIG) {
        /* the library's one root finder, on the edge's coordinate */
        edge_fn e = {c, {pa[0], pa[1], pa[2]}, axis};
        double x0 = pa[axis] + t * (b - pa[axis]);
        double x = geom_implicit_bracket_root(along_edge, &e, pa[axis], b, ga, gb, x0,
                                              c->max_iter, &s->evaluations);
        s->refined++;
        double lo = pa[axis] + tau * (b - pa[axis]), hi = pa[axis] + (1 - tau) * (b - pa[axis]);
        p[axis] = x < lo ? lo : x > hi ? hi : x;
        return add_vertex(s, c, p, axis, gb > ga ? 1.0 : -1.0);
    }
    if (t < tau)
        t = tau;
    if (t > 1 - tau)
        t = 1 - tau;
    p[axis] = pa[axis] + t * (b - pa[axis]);
    return add_vertex(s, c, p, axis, gb > ga ? 1.0 : -1.0);
}

/* ------------------------------------------------------------- layers */

/* Values of nodes [i0, i1) of row j of node layer k into L (nothing to do
 * for a double grid, read in place). */
static void eval_values(slab *s, const ctx *c, work *w, size_t k, layer *L, size_t j, size_t i0,
                        size_t i1)
{
    size_t nx1 = c->n[0] + 1, ny1 = c->n[1] + 1;
    if (c->grid && c->grid->type == GEOM_ISO_SCALAR_F64)
        return;
    double *row = L->buf + j * nx1;
    if (c->grid) {
        const float *src = (const float *)c->grid->data + nx1 * (j + ny1 * k);
        for (size_t i = i0; i < i1; i++)
            row[i] = (double)src[i];
        return;
    }
    const geom_iso_field *f = c->field;
    double y = c->coord[1][j], z = c->coord[2][k];
    if (c->expr) {
        geom__implicit_expr_rows(w->rows, i1 - i0, c->coord[0] + i0, y, z, row + i0);
    } else if (f->values) {
        for (size_t i = i0; i < i1; i++) {
            w->pts[3 * i] = c->coord[0][i];
            w->pts[3 * i + 1] = y;
            w->pts[3 * i + 2] = z;
        }
        f->values(f->user, i1 - i0, w->pts + 3 * i0, row + i0);
    } else {
        double p[3] = {0, y, z};
        for (size_t i = i0; i < i1; i++) {
            p[0] = c->coord[0][i];
            row[i] = f->value(f->user, p);
        }
    }
    s->evaluations += i1 - i0;
}

/* Signs of nodes [i0, i1) of row j of node layer k (values in L); counts
 * f == iso and NaN nodes into *niso and *nnan. */
static void eval_signs(slab *s, const ctx *c, size_t k, layer *L, size_t j, size_t i0,
                       size_t i1, size_t *niso, size_t *nnan)
{
    size_t nx1 = c->n[0] + 1;
    const double iso = c->iso;
    const double *row = L->v + j * nx1;
    uint8_t *sr = L->s + j * nx1;
    /* outside: v - iso > 0, or NaN; zeros and NaN counted on a second
     * pass over the (rare) ranges that have any */
    int special = 0;
    for (size_t i = i0; i < i1; i++) {
        double d = row[i] - iso;
        sr[i] = !(d <= 0);
        special |= !(d < 0 || d > 0);
    }
    if (special)
        for (size_t i = i0; i < i1; i++) {
            double d = row[i] - iso;
            *niso += d == 0;
            *nnan += d != d;
            if (d != d && !s->has_nan) {
                s->has_nan = 1;
                s->nan_at[0] = i;
                s->nan_at[1] = j;
                s->nan_at[2] = k;
            }
        }
}

/* The block rows containing node row j (bys, *ny_ of them) and node layer
 * k (bzs, *nz_): one or two along each axis. */
static void row_blocks(const ctx *c, size_t j, size_t k, size_t bys[2], int *ny_, size_t bzs[2],
                       int *nz_)
{
    size_t B = c->bsz;
    *ny_ = *nz_ = 0;
    if (j / B < c->nb[1])
        bys[(*ny_)++] = j / B;
    if (j % B == 0 && j > 0)
        bys[(*ny_)++] = j / B - 1;
    if (k / B < c->nb[2])
        bzs[(*nz_)++] = k / B;
    if (k % B == 0 && k > 0)
        bzs[(*nz_)++] = k / B - 1;
}

/* Nodes [i0, i1) of a row (signs sr, values vr or NULL) in skipped blocks
 * of class cls. */
static void skipped_nodes(uint8_t *sr, double *vr, size_t i0, size_t i1, uint8_t cls)
{
    memset(sr + i0, cls == BLK_OUT ? 1 : 0, i1 - i0);
    if (vr) {
        double fill = cls == BLK_OUT ? HUGE_VAL : -HUGE_VAL;
        for (size_t i = i0; i < i1; i++)
            vr[i] = fill;
    }
}

/* Row j of node layer k on the sparse path: the nodes of sampled blocks
 * are evaluated; the others lie in skipped blocks only, all of one class,
 * and get its sign (and, with caps, a value of that sign: caps read the
 * values of boundary cells). */
static void sparse_row(slab *s, const ctx *c, work *w, size_t k, layer *L, size_t j,
                       size_t *niso, size_t *nnan)
{
    size_t nx = c->n[0], nx1 = nx + 1, B = c->bsz;
    size_t nbx = c->nb[0], nby = c->nb[1];
    size_t bys[2], bzs[2];
    int ny_, nz_;
    row_blocks(c, j, k, bys, &ny_, bzs, &nz_);
    uint8_t *sr = L->s + j * nx1;
    double *vr = (c->caps && L->buf == L->v) ? L->buf + j * nx1 : NULL;
    size_t run0 = SIZE_MAX; /* first block of the current run of sampled blocks */
    size_t nruns = 0;
    /* nodes [f0, f1) of skipped blocks of class fcls, set in one go */
    size_t f0 = 0, f1 = 0;
    uint8_t fcls = BLK_OUT;
    for (size_t bx = 0; bx <= nbx; bx++) {
        int need = 0;
        uint8_t cls = BLK_SAMPLE;
        if (bx < nbx)
            for (int a = 0; a < ny_ && !need; a++)
                for (int b = 0; b < nz_ && !need; b++) {
                    cls = c->blk[bx + nbx * (bys[a] + nby * bzs[b])];
                    need = cls == BLK_SAMPLE;
                }
        if (need) {
            if (run0 == SIZE_MAX)
                run0 = bx;
            continue;
        }
        if (run0 != SIZE_MAX) {
            w->runs[2 * nruns] = run0 * B;
            w->runs[2 * nruns + 1] = bx * B + 1 < nx1 ? bx * B + 1 : nx1;
            nruns++;
            run0 = SIZE_MAX;
        }
        if (bx == nbx)
            break;
        /* a skipped block: its nodes not shared with a sampled neighbour */
        size_t i0 = bx * B, i1 = (bx + 1) * B < nx ? (bx + 1) * B : nx;
        if (bx > 0 && i0 <= i1) {
            /* node i0 was set by the previous block (sampled or not) */
            i0++;
        }
        if (i0 <= i1) {
            if (f0 < f1 && (i0 != f1 || cls != fcls)) {
                skipped_nodes(sr, vr, f0, f1, fcls);
                f0 = f1;
            }
            if (f0 == f1) {
                f0 = i0;
                fcls = cls;
            }
            f1 = i1 + 1;
        }
    }
    if (f0 < f1)
        skipped_nodes(sr, vr, f0, f1, fcls);
    const size_t *rn = w->runs;
    if (c->expr && nruns > 1) {
        /* the runs' nodes in one call: x gathered, values scattered */
        size_t m = 0;
        for (size_t q = 0; q < nruns; q++)
            for (size_t i = rn[2 * q]; i < rn[2 * q + 1]; i++)
                w->gx[m++] = c->coord[0][i];
        geom__implicit_expr_rows(w->rows, m, w->gx, c->coord[1][j], c->coord[2][k], w->gv);
        s->evaluations += m;
        double *row = L->buf + j * nx1;
        m = 0;
        for (size_t q = 0; q < nruns; q++) {
            size_t n = rn[2 * q + 1] - rn[2 * q];
            memcpy(row + rn[2 * q], w->gv + m, n * sizeof(double));
            m += n;
        }
    } else
        for (size_t q = 0; q < nruns; q++)
            eval_values(s, c, w, k, L, j, rn[2 * q], rn[2 * q + 1]);
    for (size_t q = 0; q < nruns; q++)
        eval_signs(s, c, k, L, j, rn[2 * q], rn[2 * q + 1], niso, nnan);
}

/* The class of every block containing node row j of node layer k when
 * they are all skipped and of one class (the row's nodes then all have its
 * sign), else ROW_MIXED. */
static uint8_t uniform_row(const ctx *c, size_t j, size_t k)
{
    size_t nby = c->nb[1];
    size_t bys[2], bzs[2];
    int ny_, nz_;
    row_blocks(c, j, k, bys, &ny_, bzs, &nz_);
    uint8_t u = c->rowcls[bys[0] + nby * bzs[0]];
    for (int a = 0; a < ny_; a++)
        for (int b = 0; b < nz_; b++)
            if (c->rowcls[bys[a] + nby * bzs[b]] != u)
                return ROW_MIXED;
    return u;
}

static void eval_layer(slab *s, const ctx *c, work *w, size_t k, layer *L, int count)
{
    size_t nx = c->n[0], nx1 = nx + 1, ny1 = c->n[1] + 1;
    size_t niso = 0, nnan = 0;
    if (c->grid && c->grid->type == GEOM_ISO_SCALAR_F64)
        /* read in place: a layer of the grid is nx1 * ny1 contiguous doubles */
        L->v = (const double *)c->grid->data + k * nx1 * ny1;
    else
        L->v = L->buf;
    for (size_t j = 0; j < ny1; j++) {
        uint8_t u = c->blk ? uniform_row(c, j, k) : ROW_MIXED;
        if (u != ROW_MIXED) {
            /* as sparse_row makes it, without a sign change */
            L->sr[j] = u == BLK_OUT ? w->ones : w->zeros;
            if (c->caps && L->buf == L->v) {
                double fill = u == BLK_OUT ? HUGE_VAL : -HUGE_VAL, *vr = L->buf + j * nx1;
                for (size_t i = 0; i < nx1; i++)
                    vr[i] = fill;
            }
            L->rlo[j] = (uint32_t)nx;
            L->rhi[j] = 0;
            continue;
        }
        L->sr[j] = L->s + j * nx1;
        if (c->blk)
            sparse_row(s, c, w, k, L, j, &niso, &nnan);
        else {
            eval_values(s, c, w, k, L, j, 0, nx1);
            eval_signs(s, c, k, L, j, 0, nx1, &niso, &nnan);
        }
        const uint8_t *sr = L->sr[j];
        /* first and last sign change, 8 bytes at a time */
        uint32_t lo = (uint32_t)nx, hi = 0;
        size_t i = 0;
        while (i + 8 < nx1) {
            uint64_t a, b;
            memcpy(&a, sr + i, 8);
            memcpy(&b, sr + i + 1, 8);
            if (a != b)
                break;
            i += 8;
        }
        for (; i < nx; i++)
            if (sr[i] != sr[i + 1]) {
                lo = (uint32_t)i;
                break;
            }
        if (lo < nx) {
            size_t e = nx; /* scan changes at positions < e */
            while (e >= 8 + (size_t)lo) {
                uint64_t a, b;
                memcpy(&a, sr + e - 8, 8);
                memcpy(&b, sr + e - 7, 8);
                if (a != b)
                    break;
                e -= 8;
            }
            for (size_t q = e; q-- > lo;)
                if (sr[q] != sr[q + 1]) {
                    hi = (uint32_t)q + 1;
                    break;
                }
        }
        L->rlo[j] = lo;
        L->rhi[j] = hi;
    }
    if (count) {
        s->iso_nodes += niso;
        s->nan_nodes += nnan;
    }
    L->epoch = w->base + (uint32_t)s->nv;
}

/* f - iso of a raw value; infinities as +-ISO_BIG, NaN as +ISO_BIG (the
 * difference of two finite values may overflow too: clamped likewise). */
static inline double shifted(double v, double iso)
{
    double d = v - iso;
    if (!(d >= -ISO_BIG && d <= ISO_BIG))
        d = d < 0 ? -ISO_BIG : ISO_BIG;
    return d;
}

/* f - iso at corner cc of cell (i, j) of the current cell layer. */
static inline double corner_value(const ctx *c, const work *w, size_t i, size_t j, int cc)
{
    const layer *L = (cc >> 2) ? w->lt : w->lb;
    size_t nx1 = c->n[0] + 1;
    return shifted(L->v[(j + (size_t)((cc >> 1) & 1)) * nx1 + i + (size_t)(cc & 1)], c->iso);
}

/* Make the vertex of cell edge e of cell (i, j) (not made yet). */
static uint32_t make_edge_vertex(slab *s, const ctx *c, work *w, size_t i, size_t j, int e,
                                 const double *g, uint32_t *slot)
{
    size_t nx1 = c->n[0] + 1;
    size_t k = w->k;
    size_t ni, nj, nk;
    int axis;
    if (e < 4) {
        ni = i;
        nj = j + (size_t)(e & 1);
        nk = k + (size_t)(e >> 1);
        axis = 0;
    } else if (e < 8) {
        ni = i + (size_t)(e & 1);
        nj = j;
        nk = k + (size_t)((e - 4) >> 1);
        axis = 1;
    } else {
        ni = i + (size_t)(e & 1);
        nj = j + (size_t)((e - 8) >> 1);
        nk = k;
        axis = 2;
    }
    int a = geom__iso_edge_corners[e][0], b = geom__iso_edge_corners[e][1];
    double ga, gb;
    if (g) {
        ga = g[a];
        gb = g[b];
    } else {
        ga = corner_value(c, w, i, j, a);
        gb = corner_value(c, w, i, j, b);
    }
    uint32_t id = edge_vertex(s, c, ni, nj, nk, axis, ga, gb);
    *slot = w->base + id;
    if (axis < 2)
        add_key(s, c, nk, ((uint64_t)(nj * nx1 + ni) << 2) | (uint64_t)axis, id);
    return id;
}

/* Vertex of cell edge e of cell (i, j) in the current cell layer; g: the
 * cell's corner values, or NULL to read them from the layers. */
static inline uint32_t cell_edge_vertex(slab *s, const ctx *c, work *w, size_t i, size_t j,
                                        int e, const double *g)
{
    size_t nx = c->n[0], nx1 = nx + 1;
    uint32_t *slot, epoch;
    if (e < 4) {
        layer *L = (e >> 1) ? w->lt : w->lb;
        slot = &L->xv[(j + (size_t)(e & 1)) * nx + i];
        epoch = L->epoch;
    } else if (e < 8) {
        layer *L = ((e - 4) >> 1) ? w->lt : w->lb;
        slot = &L->yv[j * nx1 + i + (size_t)(e & 1)];
        epoch = L->epoch;
    } else {
        slot = &w->zv[(j + (size_t)((e - 8) >> 1)) * nx1 + i + (size_t)(e & 1)];
        epoch = w->zepoch;
    }
    uint32_t id = *slot;
    if (id != NONE && id >= epoch)
        return id - w->base;
    return make_edge_vertex(s, c, w, i, j, e, g, slot);
}

/* Vertex at grid node of cell corner cc (caps only). */
static uint32_t cell_node_vertex(slab *s, const ctx *c, work *w, size_t i, size_t j, int cc)
{
    size_t nx1 = c->n[0] + 1;
    int x = cc & 1, y = (cc >> 1) & 1, z = cc >> 2;
    layer *L = z ? w->lt : w->lb;
    size_t ni = i + (size_t)x, nj = j + (size_t)y, nk = w->k + (size_t)z;
    uint32_t *slot = &L->nv[nj * nx1 + ni];
    if (*slot != NONE && *slot >= L->epoch)
        return *slot - w->base;
    double p[3] = {c->coord[0][ni], c->coord[1][nj], c->coord[2][nk]};
    /* A cap vertex: the outward normal of the box face is not known here;
     * use the field's gradient (fallback +x). */
    uint32_t id = add_vertex(s, c, p, 0, 1.0);
    *slot = w->base + id;
    add_key(s, c, nk, ((uint64_t)(nj * nx1 + ni) << 2) | 2u, id);
    return id;
}

static void push_tri(slab *s, const ctx *c, uint32_t **arr, size_t *n, size_t *cap, uint32_t a,
                     uint32_t b, uint32_t d)
{
    if (s->status != GEOM_OK)
        return;
    if (!grow(c->alloc, (void **)arr, cap, *n + 1, 3 * sizeof(uint32_t))) {
        s->status = GEOM_ERR_NOMEM;
        return;
    }
    uint32_t *t = *arr + 3 * *n;
    t[0] = a;
    t[1] = b;
    t[2] = d;
    (*n)++;
}

/* A cell whose case is simple (one contour, nothing ambiguous): its
 * polygon, triangulated directly; g: the corner values, or NULL to load
 * them only when a vertex must be made. Returns 0, making no triangle,
 * when every triangulation has a chord in a cell face (the general path
 * then adds an inner vertex); 1 otherwise. */
static int simple_polygon(slab *s, const ctx *c, work *w, size_t i, size_t j, const iso_case *cs,
                          const double *g)
{
    int n = cs->n;
    uint32_t vid[12];
    for (int q = 0; q < n; q++)
        vid[q] = cell_edge_vertex(s, c, w, i, j, cs->edges[q], g);
    if (s->status != GEOM_OK)
        return 1;
    const double *p[12];
    unsigned fm[12];
    for (int q = 0; q < n; q++) {
        p[q] = s->xyz + 3 * (size_t)vid[q];
        fm[q] = iso_edge_faces(cs->edges[q]);
    }
    uint8_t t[12][3];
    int forced;
    int nt = geom__iso_polygon_tris(n, p, fm, t, &forced);
    if (forced)
        return 0;
    if (!grow(c->alloc, (void **)&s->tri, &s->captri, s->ntri + (size_t)nt,
              3 * sizeof(uint32_t))) {
        s->status = GEOM_ERR_NOMEM;
        return 1;
    }
    uint32_t *o = s->tri + 3 * s->ntri;
    for (int q = 0; q < nt; q++) {
        o[3 * q] = vid[t[q][0]];
        o[3 * q + 1] = vid[t[q][1]];
        o[3 * q + 2] = vid[t[q][2]];
    }
    s->ntri += (size_t)nt;
    s->active++;
    return 1;
}

static void do_cell(slab *s, const ctx *c, work *w, size_t i, size_t j, const double g[8],
                    unsigned mask)
{
    const iso_case *cs = &c->cases->cases[mask];
    if (cs->simple && simple_polygon(s, c, w, i, j, cs, g))
        return;
    double vpos[12][3];
    uint32_t vid[12];
    for (int e = 0; e < 12; e++) {
        int a = geom__iso_edge_corners[e][0], b = geom__iso_edge_corners[e][1];
        if ((g[a] > 0) == (g[b] > 0))
            continue;
        vid[e] = cell_edge_vertex(s, c, w, i, j, e, g);
        if (s->status != GEOM_OK)
            return;
        const double *x = s->xyz + 3 * (size_t)vid[e];
        vpos[e][0] = x[0];
        vpos[e][1] = x[1];
        vpos[e][2] = x[2];
    }
    double lo[3] = {c->coord[0][i], c->coord[1][j], c->coord[2][w->k]};
    double size[3] = {c->coord[0][i + 1] - lo[0], c->coord[1][j + 1] - lo[1],
                      c->coord[2][w->k + 1] - lo[2]};
    iso_cell_result r;
    geom__iso_cell_triangulate(g, (const double(*)[3])vpos, lo, size, &r);
    uint32_t inner[ISO_CELL_MAX_INNER];
    for (int q = 0; q < r.ninner; q++)
        inner[q] = add_vertex(s, c, r.inner[q], 0, 1.0);
    s->active++;
    s->tunnels += (size_t)r.tunnels;
    /* Count each ambiguous face once: the low faces of every cell, and the
     * high faces on the grid's far boundary. */
    for (int f = 0; f < 6; f++) {
        if (!((r.ambiguous >> f) & 1u))
            continue;
        int hi = f & 1, axis = f >> 1;
        size_t idx = axis == 0 ? i : axis == 1 ? j : w->k;
        if (!hi || idx + 1 == c->n[axis])
            s->ambiguous++;
    }
    for (int t = 0; t < r.ntris; t++) {
        uint32_t v[3];
        for (int q = 0; q < 3; q++) {
            int ref = r.tris[t][q];
            v[q] = ref < 12 ? vid[ref] : inner[ref - 12];
        }
        push_tri(s, c, &s->tri, &s->ntri, &s->captri, v[0], v[1], v[2]);
    }
}

/* The cap on face f of cell (i, j) (a face on the box boundary): the part
 * of the face where the interpolant is inside, counter-clockwise seen from
 * outside the box. */
static void do_cap(slab *s, const ctx *c, work *w, size_t i, size_t j, int f, const double g[8])
{
    const uint8_t *p = geom__iso_face_corners[f];
    int in[4], changes;
    if (geom__iso_face_inside(f, g, in, &changes) == 0)
        return;
    if (changes == 4) {
        int jn[2];
        if (!geom__iso_face_join(f, g, jn)) {
            /* inside corners separated: one triangle each */
            for (int k = 0; k < 4; k++) {
                if (!in[k])
                    continue;
                int km = (k + 3) & 3, kp = (k + 1) & 3;
                int e0 = -1, e1 = -1;
                for (int e = 0; e < 12; e++) {
                    int a = geom__iso_edge_corners[e][0], b = geom__iso_edge_corners[e][1];
                    if ((a == p[km] && b == p[k]) || (a == p[k] && b == p[km]))
                        e0 = e;
                    if ((a == p[k] && b == p[kp]) || (a == p[kp] && b == p[k]))
                        e1 = e;
                }
                uint32_t v0 = cell_edge_vertex(s, c, w, i, j, e0, g);
                uint32_t v1 = cell_node_vertex(s, c, w, i, j, p[k]);
                uint32_t v2 = cell_edge_vertex(s, c, w, i, j, e1, g);
                push_tri(s, c, &s->cap, &s->ncap, &s->capcap, v0, v1, v2);
            }
            return;
        }
    }
    uint32_t poly[8];
    int np = 0;
    for (int k = 0; k < 4; k++) {
        int kp = (k + 1) & 3;
        if (in[k])
            poly[np++] = cell_node_vertex(s, c, w, i, j, p[k]);
        if (in[k] != in[kp]) {
            int ee = -1;
            for (int e = 0; e < 12; e++) {
                int a = geom__iso_edge_corners[e][0], b = geom__iso_edge_corners[e][1];
                if ((a == p[k] && b == p[kp]) || (a == p[kp] && b == p[k]))
                    ee = e;
            }
            poly[np++] = cell_edge_vertex(s, c, w, i, j, ee, g);
        }
    }
    if (s->status != GEOM_OK)
        return;
    for (int q = 1; q + 1 < np; q++)
        push_tri(s, c, &s->cap, &s->ncap, &s->capcap, poly[0], poly[q], poly[q + 1]);
}

static int cmp_key(const void *a, const void *b)
{
    uint64_t x = ((const iso_key *)a)->key, y = ((const iso_key *)b)->key;
    return x < y ? -1 : x > y;
}

static void visit_cell(slab *s, const ctx *c, work *w, size_t i, size_t j, int capcell);

/* A simple cell of the row loop, without loading the corner values
 * unless a vertex must be made. */
static void simple_cell(slab *s, const ctx *c, work *w, size_t i, size_t j, const iso_case *cs)
{
    if (!simple_polygon(s, c, w, i, j, cs, NULL))
        visit_cell(s, c, w, i, j, 0); /* the general path adds an inner vertex */
}

/* Cell (i, j) of the current cell layer: its surface and, on the box
 * boundary, its caps. */
static void visit_cell(slab *s, const ctx *c, work *w, size_t i, size_t j, int capcell)
{
    size_t nx1 = c->n[0] + 1;
    const double *gb = w->lb->v, *gt = w->lt->v;
    size_t q0 = j * nx1 + i, q1 = q0 + nx1;
    const double iso = c->iso;
    double g[8] = {shifted(gb[q0], iso), shifted(gb[q0 + 1], iso), shifted(gb[q1], iso),
                   shifted(gb[q1 + 1], iso), shifted(gt[q0], iso), shifted(gt[q0 + 1], iso),
                   shifted(gt[q1], iso), shifted(gt[q1 + 1], iso)};
    unsigned mask = 0;
    for (int q = 0; q < 8; q++)
        mask |= (unsigned)(g[q] > 0) << q;
    if (mask == 0xFFu)
        return; /* all outside: no surface, no cap */
    if (mask != 0)
        do_cell(s, c, w, i, j, g, mask);
    if (capcell) {
        size_t k = w->k;
        if (i == 0)
            do_cap(s, c, w, i, j, 0, g);
        if (i + 1 == c->n[0])
            do_cap(s, c, w, i, j, 1, g);
        if (j == 0)
            do_cap(s, c, w, i, j, 2, g);
        if (j + 1 == c->n[1])
            do_cap(s, c, w, i, j, 3, g);
        if (k == 0)
            do_cap(s, c, w, i, j, 4, g);
        if (k + 1 == c->n[2])
            do_cap(s, c, w, i, j, 5, g);
    }
}

static void work_free(const ctx *c, work *w)
{
    size_t nx = c->n[0], ny = c->n[1], nx1 = nx + 1, ny1 = ny + 1, nn = nx1 * ny1;
    const geom_allocator *al = c->alloc;
    for (int l = 0; l < 2; l++) {
        geom__free(al, w->L[l].buf, nn * sizeof(double));
        geom__free(al, w->L[l].s, nn);
        geom__free(al, (void *)w->L[l].sr, ny1 * sizeof(uint8_t *));
        geom__free(al, w->L[l].rlo, ny1 * sizeof(uint32_t));
        geom__free(al, w->L[l].rhi, ny1 * sizeof(uint32_t));
        geom__free(al, w->L[l].xv, nx * ny1 * sizeof(uint32_t));
        geom__free(al, w->L[l].yv, nx1 * ny * sizeof(uint32_t));
        geom__free(al, w->L[l].nv, nn * sizeof(uint32_t));
    }
    geom__free(al, w->zv, nn * sizeof(uint32_t));
    geom__free(al, w->ones, nx1);
    geom__free(al, w->act, nx * sizeof(uint32_t));
    geom__free(al, w->amask, nx);
    geom__free(al, w->zeros, nx1);
    geom__free(al, w->pts, 3 * nx1 * sizeof(double));
    geom__free(al, w->runs, 2 * (c->nb[0] + 1) * sizeof(size_t));
    geom__free(al, w->gx, nx1 * sizeof(double));
    geom__free(al, w->gv, nx1 * sizeof(double));
    geom__implicit_expr_rows_destroy(w->rows);
    memset(w, 0, sizeof *w);
}

static void work_clear_slots(const ctx *c, work *w)
{
    size_t nx = c->n[0], ny = c->n[1], nx1 = nx + 1, ny1 = ny + 1, nn = nx1 * ny1;
    for (int l = 0; l < 2; l++) {
        memset(w->L[l].xv, 0xFF, nx * ny1 * sizeof(uint32_t));
        memset(w->L[l].yv, 0xFF, nx1 * ny * sizeof(uint32_t));
        if (c->caps)
            memset(w->L[l].nv, 0xFF, nn * sizeof(uint32_t));
    }
    memset(w->zv, 0xFF, nn * sizeof(uint32_t));
    w->base = 0;
}

static void work_init(const ctx *c, work *w)
{
    size_t nx = c->n[0], ny = c->n[1], nx1 = nx + 1, ny1 = ny + 1, nn = nx1 * ny1;
    const geom_allocator *al = c->alloc;
    memset(w, 0, sizeof *w);
    int ok = 1;
    for (int l = 0; l < 2; l++) {
        w->L[l].buf = geom__alloc(al, nn * sizeof(double));
        w->L[l].s = geom__alloc(al, nn);
        w->L[l].sr = geom__alloc(al, ny1 * sizeof(uint8_t *));
        w->L[l].rlo = geom__alloc(al, ny1 * sizeof(uint32_t));
        w->L[l].rhi = geom__alloc(al, ny1 * sizeof(uint32_t));
        w->L[l].xv = geom__alloc(al, nx * ny1 * sizeof(uint32_t));
        w->L[l].yv = geom__alloc(al, nx1 * ny * sizeof(uint32_t));
        w->L[l].nv = c->caps ? geom__alloc(al, nn * sizeof(uint32_t)) : NULL;
        ok = ok && w->L[l].buf && w->L[l].s && w->L[l].sr && w->L[l].rlo && w->L[l].rhi && w->L[l].xv &&
             w->L[l].yv && (!c->caps || w->L[l].nv);
    }
    w->zv = geom__alloc(al, nn * sizeof(uint32_t));
    w->ones = geom__alloc(al, nx1);
    w->zeros = geom__alloc(al, nx1);
    w->act = geom__alloc(al, nx * sizeof(uint32_t));
    w->amask = geom__alloc(al, nx);
    ok = ok && w->ones && w->zeros && w->act && w->amask;
    if (ok) {
        memset(w->ones, 1, nx1);
        memset(w->zeros, 0, nx1);
    }
    if (c->expr)
        ok = ok && geom__implicit_expr_rows_create(c->expr, al, &w->rows) == GEOM_OK;
    if (!c->grid && c->field->values && !c->expr) {
        w->pts = geom__alloc(al, 3 * nx1 * sizeof(double));
        ok = ok && w->pts;
    }
    if (c->blk) {
        w->runs = geom__alloc(al, 2 * (c->nb[0] + 1) * sizeof(size_t));
        ok = ok && w->runs;
        if (c->expr) {
            w->gx = geom__alloc(al, nx1 * sizeof(double));
            w->gv = geom__alloc(al, nx1 * sizeof(double));
            ok = ok && w->gx && w->gv;
        }
    }
    ok = ok && w->zv;
    if (!ok) {
        work_free(c, w);
        return;
    }
    work_clear_slots(c, w);
    w->ok = 1;
}

static void run_slab(const ctx *c, slab *s, work *wp)
{
    size_t nx = c->n[0], ny = c->n[1], nz = c->n[2];
    size_t nx1 = nx + 1;
    if (!wp->ok) {
        s->status = GEOM_ERR_NOMEM;
        return;
    }
    if (wp->base > UINT32_MAX / 2)
        work_clear_slots(c, wp);
    work *w = wp;
    pool_take(c, s);
    if (w->hint_nv &&
        (!grow(c->alloc, (void **)&s->xyz, &s->capv, w->hint_nv, 3 * sizeof(double)) ||
         (c->normals &&
          !grow(c->alloc, (void **)&s->nrm, &s->capn, w->hint_nv, 3 * sizeof(double))) ||
         !grow(c->alloc, (void **)&s->tri, &s->captri, w->hint_tri, 3 * sizeof(uint32_t)))) {
        s->status = GEOM_ERR_NOMEM;
        return;
    }
    w->lb = &w->L[0];
    w->lt = &w->L[1];
    eval_layer(s, c, w, s->k0, w->lb, 1);
    for (size_t k = s->k0; k < s->k1 && s->status == GEOM_OK; k++) {
        w->k = k;
        eval_layer(s, c, w, k + 1, w->lt, k + 1 < s->k1 || k + 1 == nz);
        w->zepoch = w->base + (uint32_t)s->nv;
        int zcap = c->caps && (k == 0 || k + 1 == nz);
        for (size_t j = 0; j < ny && s->status == GEOM_OK; j++) {
            /* Flying-edges-style trimming: the four node rows of this cell
             * row are constant outside [L, R) and agree there. */
            const layer *lb = w->lb, *lt = w->lt;
            size_t L = lb->rlo[j], R = lb->rhi[j];
            const uint32_t los[3] = {lb->rlo[j + 1], lt->rlo[j], lt->rlo[j + 1]};
            const uint32_t his[3] = {lb->rhi[j + 1], lt->rhi[j], lt->rhi[j + 1]};
            for (int q = 0; q < 3; q++) {
                if (los[q] < L)
                    L = los[q];
                if (his[q] > R)
                    R = his[q];
            }
            /* the signs of the four node rows */
            const uint8_t *b0 = lb->sr[j], *b1 = lb->sr[j + 1], *t0 = lt->sr[j],
                          *t1 = lt->sr[j + 1];
            uint8_t f0 = b0[0], f1 = b1[0], f2 = t0[0], f3 = t1[0];
            if (f0 != f1 || f0 != f2 || f0 != f3)
                L = 0;
            uint8_t e0 = b0[nx], e1 = b1[nx], e2 = t0[nx], e3 = t1[nx];
            if (e0 != e1 || e0 != e2 || e0 != e3)
                R = nx;
            if (j + 1 < ny) {
                /* the next cell row's first and last active cells: their
                 * vertex id slots (lines first touched there) */
                size_t jn = j + 1;
                uint32_t Ln = lb->rlo[jn], Rn = lb->rhi[jn];
                const uint32_t lo2[3] = {lb->rlo[jn + 1], lt->rlo[jn], lt->rlo[jn + 1]};
                const uint32_t hi2[3] = {lb->rhi[jn + 1], lt->rhi[jn], lt->rhi[jn + 1]};
                for (int q = 0; q < 3; q++) {
                    Ln = lo2[q] < Ln ? lo2[q] : Ln;
                    Rn = hi2[q] > Rn ? hi2[q] : Rn;
                }
                if (Ln < Rn) {
                    const size_t at[2] = {Ln, Rn - 1};
                    for (int q = 0; q < 2; q++) {
                        ISO_PREFETCH(&lb->xv[(jn + 1) * nx + at[q]]);
                        ISO_PREFETCH(&lt->xv[(jn + 1) * nx + at[q]]);
                        ISO_PREFETCH(&lb->yv[jn * nx1 + at[q]]);
                        ISO_PREFETCH(&lt->yv[jn * nx1 + at[q]]);
                        ISO_PREFETCH(&w->zv[(jn + 1) * nx1 + at[q]]);
                    }
                }
            }
            if (c->caps && (zcap || j == 0 || j + 1 == ny)) {
                for (size_t i = 0; i < nx; i++)
                    visit_cell(s, c, w, i, j, 1);
                continue;
            }
            if (c->caps && L > 0)
                visit_cell(s, c, w, 0, j, 1);
            if (L < R) {
                /* outside masks from the sign bytes, one x column at a time */
                unsigned prev = (unsigned)b0[L] | (unsigned)b1[L] << 2 | (unsigned)t0[L] << 4 |
                                (unsigned)t1[L] << 6;
                size_t na = 0; /* the row's cells with a surface or a cap */
                for (size_t i = L; i < R; i++) {
                    if ((prev == 0 || prev == 0x55u) && !c->caps) {
                        /* node column i of one sign: skip 8 cells at a time
                         * while the next 8 columns have it too (no surface) */
                        const uint64_t one = prev ? UINT64_C(0x0101010101010101) : 0;
                        while (i + 8 <= R) {
                            uint64_t a0, a1, a2, a3;
                            memcpy(&a0, b0 + i + 1, 8);
                            memcpy(&a1, b1 + i + 1, 8);
                            memcpy(&a2, t0 + i + 1, 8);
                            memcpy(&a3, t1 + i + 1, 8);
                            if ((a0 ^ one) | (a1 ^ one) | (a2 ^ one) | (a3 ^ one))
                                break;
                            i += 8;
                        }
                        if (i >= R)
                            break;
                    }
                    unsigned nxt = (unsigned)b0[i + 1] | (unsigned)b1[i + 1] << 2 |
                                   (unsigned)t0[i + 1] << 4 | (unsigned)t1[i + 1] << 6;
                    unsigned mask = prev | nxt << 1;
                    prev = nxt;
                    if ((mask != 0 && mask != 0xFFu) || (c->caps && (i == 0 || i + 1 == nx))) {
                        w->act[na] = (uint32_t)i;
                        w->amask[na++] = (uint8_t)mask;
                    }
                }
                /* the id slots and values the row's active cells read,
                 * fetched together rather than one miss after another */
                for (size_t q = 0; q < na; q++) {
                    size_t i = w->act[q], r0 = j * nx1 + i, r1 = r0 + nx1;
                    ISO_PREFETCH(&lb->xv[j * nx + i]);
                    ISO_PREFETCH(&lb->xv[(j + 1) * nx + i]);
                    ISO_PREFETCH(&lt->xv[j * nx + i]);
                    ISO_PREFETCH(&lt->xv[(j + 1) * nx + i]);
                    ISO_PREFETCH(&lb->yv[r0]);
                    ISO_PREFETCH(&lt->yv[r0]);
                    ISO_PREFETCH(&w->zv[r0]);
                    ISO_PREFETCH(&w->zv[r1]);
                    ISO_PREFETCH(&lb->v[r0]);
                    ISO_PREFETCH(&lb->v[r1]);
                    ISO_PREFETCH(&lt->v[r0]);
                    ISO_PREFETCH(&lt->v[r1]);
                }
                for (size_t q = 0; q < na; q++) {
                    size_t i = w->act[q];
                    unsigned mask = w->amask[q];
                    if (c->caps && (i == 0 || i + 1 == nx))
                        visit_cell(s, c, w, i, j, 1);
                    else if (c->cases->cases[mask].simple)
                        simple_cell(s, c, w, i, j, &c->cases->cases[mask]);
                    else
                        visit_cell(s, c, w, i, j, 0);
                }
            }
            /* the last cell, when outside [L, R) and not the first one */
            if (c->caps && R < nx && !(nx == 1 && L > 0))
                visit_cell(s, c, w, nx - 1, j, 1);
        }
        layer *tmp = w->lb;
        w->lb = w->lt;
        w->lt = tmp;
    }
    if (s->status == GEOM_OK) {
        if (s->nbot > 1)
            qsort(s->bot, s->nbot, sizeof(iso_key), cmp_key);
        if (s->ntop > 1)
            qsort(s->top, s->ntop, sizeof(iso_key), cmp_key);
    }
    /* next slab on this thread: ids above every slot written so far */
    w->base += (uint32_t)s->nv + 1;
    w->hint_nv = s->nv + s->nv / 8;
    w->hint_tri = s->ntri + s->ntri / 8;
}

/* ------------------------------------------------------------ driver */

static double now_seconds(void) { return geom__seconds(); }

static double axis_tau(const double *coord, size_t n)
{
    double m = fmax(fabs(coord[0]), fabs(coord[n]));
    double hmin = HUGE_VAL;
    for (size_t i = 0; i < n; i++)
        hmin = fmin(hmin, coord[i + 1] - coord[i]);
    double tau = 0x1p-26;
    if (hmin > 0 && isfinite(hmin))
        tau = fmax(tau, 8 * DBL_EPSILON * m / hmin);
    return fmin(tau, 0.25);
}

/* ------------------------------------------------------ sparse blocks */

/* Node index range [*i0, *i1] of blocks b0..b1 - 1 along axis a. */
static void block_nodes(const ctx *c, int a, size_t b0, size_t b1, size_t *i0, size_t *i1)
{
    *i0 = b0 * c->bsz;
    *i1 = b1 * c->bsz < c->n[a] ? b1 * c->bsz : c->n[a];
}

/* Class of the box of blocks b0..b1 - 1: from the field's bounds over the
 * box spanned by their nodes, or the min and max of a grid's samples. */
static uint8_t box_class(const ctx *c, const size_t b0[3], const size_t b1[3])
{
    size_t i0[3], i1[3];
    for (int a = 0; a < 3; a++)
        block_nodes(c, a, b0[a], b1[a], &i0[a], &i1[a]);
    double mn, mx;
    if (c->grid) {
        const geom_iso_grid *g = c->grid;
        mn = HUGE_VAL;
        mx = -HUGE_VAL;
        size_t nx1 = g->dims[0], ny1 = g->dims[1];
        for (size_t k = i0[2]; k <= i1[2]; k++)
            for (size_t j = i0[1]; j <= i1[1]; j++) {
                size_t base = nx1 * (j + ny1 * k);
                if (g->type == GEOM_ISO_SCALAR_F64) {
                    const double *r = (const double *)g->data + base;
                    for (size_t i = i0[0]; i <= i1[0]; i++) {
                        double v = r[i];
                        mn = v < mn ? v : mn;
                        mx = v > mx ? v : mx;
                        if (v != v)
                            return BLK_SAMPLE;
                    }
                } else {
                    const float *r = (const float *)g->data + base;
                    for (size_t i = i0[0]; i <= i1[0]; i++) {
                        double v = (double)r[i];
                        mn = v < mn ? v : mn;
                        mx = v > mx ? v : mx;
                        if (v != v)
                            return BLK_SAMPLE;
                    }
                }
            }
    } else {
        double lo[3], hi[3], out[2];
        for (int a = 0; a < 3; a++) {
            lo[a] = c->coord[a][i0[a]];
            hi[a] = c->coord[a][i1[a]];
        }
        if (!c->field->bounds(c->field->user, lo, hi, out) || out[0] != out[0] ||
            out[1] != out[1])
            return BLK_SAMPLE;
        mn = out[0];
        mx = out[1];
    }
    /* strictly on one side: no node equals iso (nor is NaN) in the box */
    if (mn - c->iso > 0)
        return BLK_OUT;
    if (mx - c->iso < 0)
        return BLK_IN;
    return BLK_SAMPLE;
}

/* classify_blocks' context: the grid and the block classes. */
typedef struct blkvisit {
    const ctx *c;
    uint8_t *blk;
} blkvisit;

/* Classify the blocks b0..b1 - 1 by recursive subdivision (an octree over
 * the blocks, geom__block_split): a box proven on one side of iso is
 * classified whole, others are halved along every axis longer than one
 * block, down to single blocks, which are sampled when not proven. */
static int classify_blocks(void *user, const size_t *b0, const size_t *b1, int single)
{
    const blkvisit *v = user;
    const ctx *c = v->c;
    /* a grid's single blocks only: its min and max cost a pass anyway */
    uint8_t cls = (c->grid && !single) ? BLK_SAMPLE : box_class(c, b0, b1);
    if (cls != BLK_SAMPLE || single) {
        for (size_t bz = b0[2]; bz < b1[2]; bz++)
            for (size_t by = b0[1]; by < b1[1]; by++)
                memset(v->blk + b0[0] + c->nb[0] * (by + c->nb[1] * bz), cls, b1[0] - b0[0]);
        return 0;
    }
    return 1;
}

/* Six times the signed volume of the tetrahedron (origin, a, b, c). */
static inline double tri_volume6(const double *a, const double *b, const double *c)
{
    return a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) +
           a[2] * (b[0] * c[1] - b[1] * c[0]);
}

/* The error sampling rule: every s-th vertex and surface triangle (by
 * index, the first one included), s the smallest power of two keeping the
 * points within the budget. A power of two, so that the stream path can
 * sample while the counts grow and halve its samples when the stride
 * doubles (emit_thin). */
static size_t error_budget(const geom_iso_options *opt)
{
    size_t budget = opt && opt->error_samples ? opt->error_samples : 65536;
    return budget < 5 ? 5 : budget; /* one vertex and one triangle's 4 samples */
}

static int over_budget(size_t budget, size_t nv, size_t nst, size_t stride)
{
    return budget != SIZE_MAX &&
           (nv + stride - 1) / stride + 4 * ((nst + stride - 1) / stride) > budget;
}

static size_t error_stride(const geom_iso_options *opt, size_t nv, size_t nst)
{
    size_t budget = error_budget(opt), stride = 1;
    while (over_budget(budget, nv, nst, stride))
        stride *= 2;
    return stride;
}

static int error_wanted(const ctx *c, const geom_iso_options *opt)
{
    int err = opt ? opt->error : GEOM_ISO_ERROR_AUTO;
    return err == GEOM_ISO_ERROR_ALWAYS ||
           (err == GEOM_ISO_ERROR_AUTO && c->field->exact && !c->grid);
}

static void error_report(geom_iso_report *r, const iso_err_acc *acc)
{
    r->vertex_error.max_error = acc->vmax;
    r->vertex_error.mean_error = acc->vcount ? acc->vsum / (double)acc->vcount : 0;
    r->vertex_error.method = GEOM_ERROR_SAMPLED;
    r->sample_error.max_error = acc->smax;
    r->sample_error.mean_error = acc->scount ? acc->ssum / (double)acc->scount : 0;
    r->sample_error.method = GEOM_ERROR_SAMPLED;
    r->unmeasured = acc->unmeasured;
    r->vertex_error.evaluations += acc->evaluations;
    r->vertex_error.pieces = acc->vcount;
    r->sample_error.pieces = acc->scount;
    r->error.max_error = fmax(acc->vmax, acc->smax);
    r->error.mean_error = r->sample_error.mean_error;
    r->error.method = GEOM_ERROR_SAMPLED;
    r->error.pieces = acc->vcount + acc->scount;
}

/* Append n doubles to (*p, *len, *cap); 0 when out of memory. */
static int push_doubles(const geom_allocator *al, double **p, size_t *len, size_t *cap,
                        const double *x, size_t n)
{
    if (n == 0)
        return 1;
    if (!grow(al, (void **)p, cap, *len + n, sizeof(double)))
        return 0;
    memcpy(*p + *len, x, n * sizeof(double));
    *len += n;
    return 1;
}

/* Renumber slab s's vertices into rm (s->nv entries): those of its first
 * node layer found among the previous slab's last-layer keys (top, ntop,
 * numbered by prm) take their numbers, the others the next numbers from
 * *nv on, in order. GEOM_ERR_LIMIT past 2^32 - 2 vertices in all. */
static geom_status renumber(const slab *s, const iso_key *top, size_t ntop, const uint32_t *prm,
                            uint32_t *rm, size_t *nv)
{
    for (size_t v = 0; v < s->nv; v++)
        rm[v] = NONE;
    size_t a = 0, b = 0;
    while (a < s->nbot && b < ntop) {
        if (s->bot[a].key < top[b].key)
            a++;
        else if (s->bot[a].key > top[b].key)
            b++;
        else {
            rm[s->bot[a].id] = prm[top[b].id];
            a++;
            b++;
        }
    }
    for (size_t v = 0; v < s->nv; v++) {
        if (rm[v] != NONE)
            continue;
        if (*nv >= (size_t)UINT32_MAX - 1)
            return GEOM_ERR_LIMIT;
        rm[v] = (uint32_t)(*nv)++;
    }
    return GEOM_OK;
}

/* The stream path (geom_iso_extract_stream): each slab, once it and all
 * the slabs before it are done, is renumbered against the previous one,
 * handed to the sink (its new vertices and its triangles) and freed, by
 * the calling thread, while the other threads go on with later slabs; the
 * cap triangles follow at the end. On the way: the signed volume (the
 * same terms in the same order as signed_volume) and the error sample
 * points (those the array path measures: the vertices and surface
 * triangles whose number is a multiple of the stride, vertices with caps
 * only when a surface triangle uses them), measured at the end. */
typedef struct emitter {
    size_t next;           /* the next slab to hand over */
    uint32_t *rm, *prm;    /* the numbering of that slab and of the one before */
    size_t caprm, capprm;
    size_t nv, nt;         /* vertices and surface triangles handed over */
    double vol;            /* sum of the surface triangles' volume terms */
    double *cx, *cn;       /* a chunk's new vertices and normals */
    uint32_t *ct;          /* a chunk's triangles, renumbered */
    size_t capx, capn, capt;
    uint32_t *cap;         /* the cap triangles, renumbered */
    double *cvol;          /* and their volume terms */
    size_t ncap, capcap, capcvol;
    int measure;
    size_t budget, stride;
    double *ev;            /* every stride-th vertex (3 doubles each) */
    uint8_t *evu;          /* 1: a surface triangle uses it */
    double *et;            /* every stride-th surface triangle's corners (9 doubles) */
    size_t nev, capev, nevu, capevu, net, capet;
    geom_status st;
} emitter;

static void emit_init(const ctx *c, const geom_iso_options *opt, emitter *em)
{
    memset(em, 0, sizeof *em);
    em->measure = error_wanted(c, opt);
    em->budget = error_budget(opt);
    em->stride = 1;
}

static void emit_free(const ctx *c, emitter *em)
{
    const geom_allocator *al = c->alloc;
    geom__free(al, em->rm, em->caprm * sizeof(uint32_t));
    geom__free(al, em->prm, em->capprm * sizeof(uint32_t));
    geom__free(al, em->cx, em->capx * 3 * sizeof(double));
    geom__free(al, em->cn, em->capn * 3 * sizeof(double));
    geom__free(al, em->ct, em->capt * 3 * sizeof(uint32_t));
    geom__free(al, em->cap, em->capcap * 3 * sizeof(uint32_t));
    geom__free(al, em->cvol, em->capcvol * sizeof(double));
    geom__free(al, em->ev, em->capev * sizeof(double));
    geom__free(al, em->evu, em->capevu);
    geom__free(al, em->et, em->capet * sizeof(double));
    memset(em, 0, sizeof *em);
}

/* Double the stride while the counts so far exceed the budget, keeping
 * the samples whose number is a multiple of the new stride (every other
 * one: sample k is number k * stride). */
static void emit_thin(emitter *em)
{
    while (over_budget(em->budget, em->nv, em->nt, em->stride)) {
        em->stride *= 2;
        size_t nv = (em->nevu + 1) / 2, nt = (em->net / 9 + 1) / 2;
        for (size_t k = 0; k < nv; k++) {
            memmove(em->ev + 3 * k, em->ev + 6 * k, 3 * sizeof(double));
            em->evu[k] = em->evu[2 * k];
        }
        for (size_t k = 0; k < nt; k++)
            memmove(em->et + 9 * k, em->et + 18 * k, 9 * sizeof(double));
        em->nev = 3 * nv;
        em->nevu = nv;
        em->net = 9 * nt;
    }
}

/* Hand over slab q (all slabs before it handed over) and free it. */
static void emit_slab(const ctx *c, emitter *em, slab *sl, size_t q)
{
    const geom_allocator *al = c->alloc;
    slab *s = &sl[q];
    if (em->st == GEOM_OK && s->status != GEOM_OK)
        em->st = s->status;
    if (em->st != GEOM_OK)
        goto done;
    if (!grow(al, (void **)&em->rm, &em->caprm, s->nv, sizeof(uint32_t)) ||
        !grow(al, (void **)&em->cx, &em->capx, s->nv, 3 * sizeof(double)) ||
        (c->normals && !grow(al, (void **)&em->cn, &em->capn, s->nv, 3 * sizeof(double))) ||
        !grow(al, (void **)&em->ct, &em->capt, s->ntri, 3 * sizeof(uint32_t)) ||
        !grow(al, (void **)&em->cap, &em->capcap, em->ncap + s->ncap, 3 * sizeof(uint32_t)) ||
        !grow(al, (void **)&em->cvol, &em->capcvol, em->ncap + s->ncap, sizeof(double))) {
        em->st = GEOM_ERR_NOMEM;
        goto done;
    }
    size_t vbase = em->nv;
    em->st = renumber(s, q ? sl[q - 1].top : NULL, q ? sl[q - 1].ntop : 0, em->prm, em->rm,
                      &em->nv);
    if (em->st != GEOM_OK)
        goto done;
    const uint32_t *rm = em->rm;
    const size_t stride = em->stride;
    const int marks = em->measure && c->caps; /* vertices sampled only when used */
    size_t nnew = 0;
    for (size_t v = 0; v < s->nv && em->st == GEOM_OK; v++) {
        if (rm[v] < vbase)
            continue; /* a copy of the previous slab's vertex */
        memcpy(em->cx + 3 * nnew, s->xyz + 3 * v, 3 * sizeof(double));
        if (c->normals)
            memcpy(em->cn + 3 * nnew, s->nrm + 3 * v, 3 * sizeof(double));
        if (em->measure && (vbase + nnew) % stride == 0) {
            uint8_t used = !marks;
            if (!push_doubles(al, &em->ev, &em->nev, &em->capev, s->xyz + 3 * v, 3) ||
                !grow(al, (void **)&em->evu, &em->capevu, em->nevu + 1, 1))
                em->st = GEOM_ERR_NOMEM;
            else
                em->evu[em->nevu++] = used;
        }
        nnew++;
    }
    for (size_t t = 0; t < s->ntri && em->st == GEOM_OK; t++) {
        const uint32_t *lt = s->tri + 3 * t;
        const double *a = s->xyz + 3 * (size_t)lt[0], *b = s->xyz + 3 * (size_t)lt[1],
                     *d = s->xyz + 3 * (size_t)lt[2];
        em->vol += tri_volume6(a, b, d);
        uint32_t *o = em->ct + 3 * t;
        o[0] = rm[lt[0]];
        o[1] = rm[lt[1]];
        o[2] = rm[lt[2]];
        if (marks)
            for (int k = 0; k < 3; k++)
                if (o[k] % stride == 0)
                    em->evu[o[k] / stride] = 1;
        if (em->measure && (em->nt + t) % stride == 0) {
            double p9[9];
            memcpy(p9, a, 3 * sizeof(double));
            memcpy(p9 + 3, b, 3 * sizeof(double));
            memcpy(p9 + 6, d, 3 * sizeof(double));
            if (!push_doubles(al, &em->et, &em->net, &em->capet, p9, 9))
                em->st = GEOM_ERR_NOMEM;
        }
    }
    for (size_t t = 0; t < s->ncap; t++) {
        const uint32_t *lt = s->cap + 3 * t;
        em->cvol[em->ncap] = tri_volume6(s->xyz + 3 * (size_t)lt[0],
                                         s->xyz + 3 * (size_t)lt[1], s->xyz + 3 * (size_t)lt[2]);
        for (int k = 0; k < 3; k++)
            em->cap[3 * em->ncap + (size_t)k] = rm[lt[k]];
        em->ncap++;
    }
    if (em->st == GEOM_OK && (nnew || s->ntri)) {
        geom_iso_chunk ch = {vbase, nnew, em->cx, c->normals ? em->cn : NULL, s->ntri, em->ct, 0};
        em->st = c->sink(c->sink_user, &ch);
    }
    em->nt += s->ntri;
    if (em->measure)
        emit_thin(em);
done:;
    pool_put(c, s);
    /* keep this slab's last-layer keys and numbering for the next one */
    iso_key *top = s->top;
    size_t ntop = s->ntop, captop = s->captop;
    s->top = NULL;
    s->captop = 0;
    slab_free(al, s);
    s->top = top;
    s->ntop = ntop;
    s->captop = captop;
    if (q > 0)
        slab_free(al, &sl[q - 1]);
    uint32_t *t = em->rm;
    size_t ct = em->caprm;
    em->rm = em->prm;
    em->caprm = em->capprm;
    em->prm = t;
    em->capprm = ct;
}

/* Flags shared between the threads of the stream path. */
static inline uint8_t flag_load(const uint8_t *p)
{
    uint8_t v;
#ifdef GEOM_ISO_OPENMP
#pragma omp atomic read seq_cst
#endif
    v = *p;
    return v;
}

static inline void flag_set(uint8_t *p)
{
#ifdef GEOM_ISO_OPENMP
#pragma omp atomic write seq_cst
#endif
    *p = 1;
}

/* Hand over the slabs that are done, in order, from em->next on; sets
 * *halt when the stream has failed (the other slabs are then skipped). */
static void emit_ready(const ctx *c, emitter *em, slab *sl, size_t nslabs, const uint8_t *done,
                       uint8_t *halt)
{
    while (em->next < nslabs && flag_load(&done[em->next])) {
        emit_slab(c, em, sl, em->next);
#ifdef GEOM_ISO_OPENMP
#pragma omp atomic update seq_cst
#endif
        em->next++;
        if (em->st != GEOM_OK)
            flag_set(halt);
    }
}

#ifdef GEOM_ISO_OPENMP
/* The stream path's backpressure: a thread other than the calling one
 * (which hands the slabs over) starts slab q only when at most `ahead`
 * slabs before it wait to be handed over, napping meanwhile (0.1 ms at a
 * time: a nap costs no CPU time), so that slabs done far ahead of the
 * writing do not pile up in memory (sparse extraction is cheaper than
 * writing its output). The calling thread never waits here and, after
 * its last slab, hands over the rest as they come, so every wait ends. */
static void wait_turn(const emitter *em, size_t q, size_t ahead, const uint8_t *halt)
{
    for (;;) {
        size_t next;
#pragma omp atomic read seq_cst
        next = em->next;
        if (q <= next + ahead || flag_load(halt))
            return;
        struct timespec ts = {0, 100000};
        nanosleep(&ts, NULL);
    }
}
#endif

/* After the last slab: the cap triangles, the counts, the signed volume
 * and the error measure. */
static geom_status emit_finish(const ctx *c, emitter *em, int threads, geom_iso_surface *out)
{
    const geom_allocator *al = c->alloc;
    geom_iso_report *r = &out->report;
    out->n_vertices = em->nv;
    out->n_triangles = em->nt + em->ncap;
    out->n_cap_triangles = em->ncap;
    geom_status st = em->st;
    double vol = em->vol;
    if (st == GEOM_OK && em->ncap) {
        for (size_t t = 0; t < em->ncap; t++)
            vol += em->cvol[t];
        /* normals given (with no vertices) when there are: the faces
         * then name theirs */
        geom_iso_chunk ch = {em->nv, 0, NULL, c->normals ? em->cn : NULL, em->ncap, em->cap, 1};
        st = c->sink(c->sink_user, &ch);
    }
    r->signed_volume = vol / 6.0;
    if (st == GEOM_OK && em->measure) {
        /* the sample points: the vertices used, then triangle corners */
        double te = now_seconds();
        size_t nvs = 0, nts = em->net / 9;
        for (size_t k = 0; k < em->nevu; k++)
            if (em->evu[k])
                memmove(em->ev + 3 * nvs++, em->ev + 3 * k, 3 * sizeof(double));
        em->nev = 3 * nvs;
        size_t npts = nvs + 3 * nts;
        uint8_t *vm = geom__alloc(al, npts ? npts : 1);
        uint32_t *ti = geom__alloc(al, (nts ? 3 * nts : 1) * sizeof(uint32_t));
        if (!vm || !ti || !push_doubles(al, &em->ev, &em->nev, &em->capev, em->et, em->net))
            st = GEOM_ERR_NOMEM;
        else {
            memset(vm, 1, nvs);
            memset(vm + nvs, 0, 3 * nts);
            for (size_t q = 0; q < 3 * nts; q++)
                ti[q] = (uint32_t)(nvs + q);
            iso_err_acc acc;
            st = geom__iso_measure(c->field, c->iso, npts, em->ev, vm, nts, ti, 1, c->dstep,
                                   threads, al, &acc);
            if (st == GEOM_OK)
                error_report(r, &acc);
        }
        geom__free(al, vm, npts ? npts : 1);
        geom__free(al, ti, (nts ? 3 * nts : 1) * sizeof(uint32_t));
        r->error_stride = em->stride;
        r->error_seconds = now_seconds() - te;
    }
    return st;
}

static geom_status extract(const ctx *c0, const geom_iso_options *opt, geom_iso_surface *out,
                           double t_start, geom_diag *diag)
{
    ctx c = *c0;
    iso_case_table table;
    geom__iso_case_table_init(&table);
    c.cases = &table;
    const geom_allocator *al = c.alloc;
    size_t nz = c.n[2];
    /* the sparse path: classify the blocks first */
    uint8_t *blk = NULL, *rowcls = NULL;
    size_t nblk = 0, nskipped = 0, cells_eval = c.n[0] * c.n[1] * c.n[2];
    if (!(opt && opt->dense) && (c.grid || c.field->bounds)) {
        size_t B = opt && opt->block_size ? opt->block_size : 8;
        nblk = 1;
        for (int a = 0; a < 3; a++) {
            c.nb[a] = (c.n[a] + B - 1) / B;
            nblk *= c.nb[a]; /* cells fit size_t, blocks do too */
        }
        c.bsz = B;
        blk = geom__alloc(al, nblk);
        if (!blk)
            return geom__diag_set(diag, GEOM_ERR_NOMEM, "", 0, 0, "geom_iso: out of memory");
        size_t b0[3] = {0, 0, 0};
        blkvisit bv = {&c, blk};
        geom__block_split(3, b0, c.nb, classify_blocks, &bv);
        c.blk = blk;
        rowcls = geom__alloc(al, c.nb[1] * c.nb[2]);
        if (!rowcls) {
            geom__free(al, blk, nblk);
            return geom__diag_set(diag, GEOM_ERR_NOMEM, "", 0, 0, "geom_iso: out of memory");
        }
        for (size_t bz = 0; bz < c.nb[2]; bz++)
            for (size_t by = 0; by < c.nb[1]; by++) {
                const uint8_t *row = blk + c.nb[0] * (by + c.nb[1] * bz);
                uint8_t u = row[0] == BLK_SAMPLE ? (uint8_t)ROW_MIXED : row[0];
                for (size_t bx = 1; bx < c.nb[0] && u != ROW_MIXED; bx++)
                    if (row[bx] != u)
                        u = ROW_MIXED;
                rowcls[by + c.nb[1] * bz] = u;
            }
        c.rowcls = rowcls;
        cells_eval = 0;
        for (size_t bz = 0; bz < c.nb[2]; bz++)
            for (size_t by = 0; by < c.nb[1]; by++)
                for (size_t bx = 0; bx < c.nb[0]; bx++) {
                    if (blk[bx + c.nb[0] * (by + c.nb[1] * bz)] != BLK_SAMPLE) {
                        nskipped++;
                        continue;
                    }
                    size_t i0, i1, j0, j1, k0, k1;
                    block_nodes(&c, 0, bx, bx + 1, &i0, &i1);
                    block_nodes(&c, 1, by, by + 1, &j0, &j1);
                    block_nodes(&c, 2, bz, bz + 1, &k0, &k1);
                    cells_eval += (i1 - i0) * (j1 - j0) * (k1 - k0);
                }
    }
    size_t layers = opt && opt->slab_layers ? opt->slab_layers : 0;
    if (layers == 0) {
        layers = (nz + 63) / 64;
        if (layers < 8)
            layers = 8;
    }
    size_t nslabs = (nz + layers - 1) / layers;
    slab *sl = geom__alloc(al, nslabs * sizeof(slab));
    if (!sl) {
        geom__free(al, blk, nblk ? nblk : 1);
        geom__free(al, rowcls, c.nb[1] * c.nb[2]);
        return geom__diag_set(diag, GEOM_ERR_NOMEM, "", 0, 0, "geom_iso: out of memory");
    }
    memset(sl, 0, nslabs * sizeof(slab));
    for (size_t q = 0; q < nslabs; q++) {
        sl[q].k0 = q * layers;
        sl[q].k1 = (q + 1) * layers < nz ? (q + 1) * layers : nz;
    }
    int threads = opt ? opt->threads : 0;
    int used = 1;
    /* the stream path hands slabs over as they are done */
    emitter em;
    uint8_t *done_flags = NULL, halt = 0;
    slab_pool pool = {NULL, 0};
    if (c.sink) {
        emit_init(&c, opt, &em);
        done_flags = geom__alloc(al, nslabs);
        pool.spare = geom__alloc(al, nslabs * sizeof(slab));
        c.pool = &pool;
        if (!done_flags || !pool.spare) {
            geom__free(al, done_flags, nslabs);
            geom__free(al, pool.spare, nslabs * sizeof(slab));
            geom__free(al, sl, nslabs * sizeof(slab));
            geom__free(al, blk, nblk ? nblk : 1);
            geom__free(al, rowcls, c.nb[1] * c.nb[2]);
            return geom__diag_set(diag, GEOM_ERR_NOMEM, "", 0, 0, "geom_iso: out of memory");
        }
        memset(done_flags, 0, nslabs);
        memset(pool.spare, 0, nslabs * sizeof(slab));
    }
    void (*progress)(void *, double) = opt ? opt->progress : NULL;
    void *progress_user = opt ? opt->progress_user : NULL;
#ifdef GEOM_ISO_OPENMP
    int nth = threads > 0 ? threads : omp_get_max_threads();
    if (threads <= 0) {
        /* automatic: no more threads than the work pays for (starting a
         * team costs more than a small grid's extraction) */
        size_t cells = c.n[0] * c.n[1] * c.n[2];
        size_t per = c.grid ? (size_t)1 << 21 : (size_t)1 << 16;
        size_t want = 1 + cells / per;
        if ((size_t)nth > want)
            nth = (int)want;
    }
    if ((size_t)nth > nslabs)
        nth = (int)nslabs;
    if (nth < 1)
        nth = 1;
    used = nth;
    long long ns = (long long)nslabs;
    long long done = 0;
#pragma omp parallel num_threads(nth)
    {
        work w;
        work_init(&c, &w);
#pragma omp for schedule(dynamic, 1) nowait
        for (long long q = 0; q < ns; q++) {
            if (c.sink && omp_get_thread_num() != 0)
                wait_turn(&em, (size_t)q, (size_t)nth, &halt);
            if (!flag_load(&halt))
                run_slab(&c, &sl[q], &w);
            long long d;
#pragma omp atomic capture
            d = ++done;
            /* the callback and the sink only ever run on the calling thread */
            if (progress && omp_get_thread_num() == 0)
                progress(progress_user, (double)d / (double)ns);
            if (c.sink) {
                flag_set(&done_flags[q]);
                if (omp_get_thread_num() == 0)
                    emit_ready(&c, &em, sl, nslabs, done_flags, &halt);
            }
        }
        work_free(&c, &w);
        /* the calling thread hands over the slabs the others finish */
        if (c.sink && omp_get_thread_num() == 0)
            for (;;) {
                emit_ready(&c, &em, sl, nslabs, done_flags, &halt);
                if (em.next == nslabs || flag_load(&halt))
                    break;
                struct timespec ts = {0, 100000};
                nanosleep(&ts, NULL);
            }
    }
#else
    {
        work w;
        work_init(&c, &w);
        for (size_t q = 0; q < nslabs; q++) {
            if (!halt)
                run_slab(&c, &sl[q], &w);
            if (progress)
                progress(progress_user, (double)(q + 1) / (double)nslabs);
            if (c.sink) {
                done_flags[q] = 1;
                emit_ready(&c, &em, sl, nslabs, done_flags, &halt);
            }
        }
        work_free(&c, &w);
    }
#endif
    geom_status st = GEOM_OK;
    uint32_t **remap = NULL;
    size_t nv = 0, nt = 0, ncap = 0;
    if (c.sink) {
        /* the rest (all done), then the caps and the report */
        emit_ready(&c, &em, sl, nslabs, done_flags, &halt);
        st = emit_finish(&c, &em, threads, out);
        emit_free(&c, &em);
        geom__free(al, done_flags, nslabs);
        for (size_t q = 0; q < pool.n; q++)
            slab_free(al, &pool.spare[q]);
        geom__free(al, pool.spare, nslabs * sizeof(slab));
        c.pool = NULL;
    } else {
        for (size_t q = 0; q < nslabs; q++)
            if (sl[q].status != GEOM_OK && st == GEOM_OK)
                st = sl[q].status;
        /* Merge in order. */
        if (st == GEOM_OK) {
            remap = geom__alloc(al, nslabs * sizeof(uint32_t *));
            if (!remap)
                st = GEOM_ERR_NOMEM;
            else
                memset(remap, 0, nslabs * sizeof(uint32_t *));
        }
        for (size_t q = 0; q < nslabs && st == GEOM_OK; q++) {
            slab *s = &sl[q];
            remap[q] = geom__alloc(al, (s->nv ? s->nv : 1) * sizeof(uint32_t));
            if (!remap[q]) {
                st = GEOM_ERR_NOMEM;
                break;
            }
            st = renumber(s, q ? sl[q - 1].top : NULL, q ? sl[q - 1].ntop : 0,
                          q ? remap[q - 1] : NULL, remap[q], &nv);
            nt += s->ntri;
            ncap += s->ncap;
        }
    }
    if (st == GEOM_OK && !c.sink) {
        size_t tb;
        if (geom__size_mul(nt + ncap, 3 * sizeof(uint32_t), &tb) != GEOM_OK ||
            nv > SIZE_MAX / (3 * sizeof(double)))
            st = GEOM_ERR_LIMIT;
        else {
            out->n_vertices = nv;
            out->n_triangles = nt + ncap;
            out->xyz = geom__alloc(al, (nv ? nv : 1) * 3 * sizeof(double));
            out->normals = c.normals ? geom__alloc(al, (nv ? nv : 1) * 3 * sizeof(double)) : NULL;
            out->tris = geom__alloc(al, tb ? tb : 1);
            if (!out->xyz || !out->tris || (c.normals && !out->normals))
                st = GEOM_ERR_NOMEM;
        }
    }
    if (st == GEOM_OK && !c.sink) {
        size_t to = 0;
        for (size_t q = 0; q < nslabs; q++) {
            slab *s = &sl[q];
            for (size_t v = 0; v < s->nv; v++) {
                uint32_t gi = remap[q][v];
                memcpy(out->xyz + 3 * (size_t)gi, s->xyz + 3 * v, 3 * sizeof(double));
                if (c.normals)
                    memcpy(out->normals + 3 * (size_t)gi, s->nrm + 3 * v, 3 * sizeof(double));
            }
            for (size_t t = 0; t < 3 * s->ntri; t++)
                out->tris[to++] = remap[q][s->tri[t]];
        }
        for (size_t q = 0; q < nslabs; q++) {
            slab *s = &sl[q];
            for (size_t t = 0; t < 3 * s->ncap; t++)
                out->tris[to++] = remap[q][s->cap[t]];
        }
        out->n_vertices = nv;
        out->n_triangles = nt + ncap;
        out->n_cap_triangles = ncap;
    }
    geom_iso_report *r = &out->report;
    int nan_found = 0;
    for (size_t q = 0; q < nslabs; q++) {
        slab *s = &sl[q];
        r->vertex_error.evaluations += s->evaluations;
        r->active_cells += s->active;
        r->ambiguous_faces += s->ambiguous;
        r->tunnels += s->tunnels;
        r->iso_nodes += s->iso_nodes;
        r->nan_nodes += s->nan_nodes;
        r->refined += s->refined;
        if (s->has_nan && !nan_found) { /* the first slab with one */
            nan_found = 1;
            for (int a = 0; a < 3; a++) {
                r->nan_first[a] = s->nan_at[a];
                r->nan_point[a] = c.coord[a][s->nan_at[a]];
            }
        }
        if (remap)
            geom__free(al, remap[q], (s->nv ? s->nv : 1) * sizeof(uint32_t));
        slab_free(al, s);
    }
    if (remap)
        geom__free(al, remap, nslabs * sizeof(uint32_t *));
    geom__free(al, sl, nslabs * sizeof(slab));
    r->slabs = nslabs;
    r->threads = used;
    r->cells = c.n[0] * c.n[1] * c.n[2];
    r->cells_evaluated = cells_eval;
    r->blocks = nblk;
    r->blocks_skipped = nskipped;
    geom__free(al, blk, nblk ? nblk : 1);
    geom__free(al, rowcls, c.nb[1] * c.nb[2]);
    c.blk = blk = rowcls = NULL;
    c.rowcls = NULL;

    if (st == GEOM_OK) {
        if (!c.sink && error_wanted(&c, opt)) {
            double te = now_seconds();
            iso_err_acc acc;
            size_t nst = out->n_triangles - out->n_cap_triangles;
            uint8_t *mask = NULL;
            if (out->n_cap_triangles) {
                /* vertices of the caps only (box nodes) are not on the surface */
                mask = geom__alloc(al, out->n_vertices ? out->n_vertices : 1);
                if (!mask)
                    st = GEOM_ERR_NOMEM;
                else {
                    memset(mask, 0, out->n_vertices);
                    for (size_t q = 0; q < 3 * nst; q++)
                        mask[out->tris[q]] = 1;
                }
            }
            size_t stride = error_stride(opt, out->n_vertices, nst);
            r->error_stride = stride;
            if (st == GEOM_OK)
                st = geom__iso_measure(c.field, c.iso, out->n_vertices, out->xyz, mask, nst,
                                       out->tris, stride, c.dstep, threads, al, &acc);
            geom__free(al, mask, out->n_vertices ? out->n_vertices : 1);
            if (st == GEOM_OK)
                error_report(r, &acc);
            r->error_seconds = now_seconds() - te;
        }
        r->sample_error.evaluations = r->vertex_error.evaluations;
    }
    if (st != GEOM_OK) {
        geom_iso_surface_free(out);
        memset(out, 0, sizeof *out);
        return geom__diag_set(diag, st, "", 0, 0, "geom_iso: %s", geom_status_str(st));
    }
    r->seconds = now_seconds() - t_start;
    r->error.evaluations = r->vertex_error.evaluations;
    r->error.seconds = r->vertex_error.seconds = r->sample_error.seconds = r->seconds;
    return GEOM_OK;
}

static void init_out(geom_iso_surface *out, const geom_iso_options *opt)
{
    memset(out, 0, sizeof *out);
    if (opt && opt->alloc)
        out->alloc = *opt->alloc;
}

static geom_status extract_field(const geom_iso_field *field, const double bounds[6],
                                 const size_t res[3], const geom_iso_options *opt,
                                 geom_iso_chunk_fn sink, void *sink_user, geom_iso_surface *out,
                                 geom_diag *diag)
{
    double t0 = now_seconds();
    if (!out)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0, "geom_iso_extract: NULL out");
    memset(out, 0, sizeof *out);
    if (!field || !field->value || !bounds || !res)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                             "geom_iso_extract: NULL argument");
    double iso = opt ? opt->iso : 0.0;
    if (!isfinite(iso))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                             "geom_iso_extract: non-finite isovalue");
    for (int a = 0; a < 3; a++) {
        if (!isfinite(bounds[a]) || !isfinite(bounds[a + 3]) || !(bounds[a] < bounds[a + 3]))
            return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                                 "geom_iso_extract: bounds must be finite with min < max");
        if (res[a] == 0)
            return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                                 "geom_iso_extract: zero resolution");
        if (res[a] >= (size_t)UINT32_MAX / 4)
            return geom__diag_set(diag, GEOM_ERR_LIMIT, "", 0, 0,
                                 "geom_iso_extract: resolution too large");
    }
    size_t layer;
    if (geom__size_mul(res[0] + 1, res[1] + 1, &layer) != GEOM_OK ||
        geom__size_mul(layer, 8 * sizeof(double), &layer) != GEOM_OK)
        return geom__diag_set(diag, GEOM_ERR_LIMIT, "", 0, 0, "geom_iso_extract: grid too large");
    init_out(out, opt);
    const geom_allocator *al = opt ? opt->alloc : NULL;
    double *coord[3] = {NULL, NULL, NULL};
    geom_status st = GEOM_OK;
    for (int a = 0; a < 3 && st == GEOM_OK; a++) {
        coord[a] = geom__alloc(al, (res[a] + 1) * sizeof(double));
        if (!coord[a]) {
            st = GEOM_ERR_NOMEM;
            break;
        }
        double lo = bounds[a], hi = bounds[a + 3];
        double n = (double)res[a];
        for (size_t i = 0; i <= res[a]; i++)
            coord[a][i] = (lo * (n - (double)i) + hi * (double)i) / n;
        coord[a][0] = lo;
        coord[a][res[a]] = hi;
        for (size_t i = 0; i < res[a]; i++)
            if (!(coord[a][i + 1] > coord[a][i]))
                st = GEOM_ERR_INVALID_ARG; /* cells too small for double precision */
    }
    if (st == GEOM_OK) {
        ctx c;
        memset(&c, 0, sizeof c);
        c.field = field;
        c.grid = NULL;
        if (field->value == geom_implicit_expr_value_cb && field->user)
            c.expr = (const geom_implicit_expr *)field->user;
        c.sink = sink;
        c.sink_user = sink_user;
        for (int a = 0; a < 3; a++) {
            c.n[a] = res[a];
            c.coord[a] = coord[a];
            c.tau[a] = axis_tau(coord[a], res[a]);
            c.dstep[a] = 1e-3 * (bounds[a + 3] - bounds[a]) / (double)res[a];
        }
        c.iso = iso;
        int rf = opt ? opt->refine : GEOM_IMPLICIT_REFINE_AUTO;
        c.refine = rf == GEOM_IMPLICIT_REFINE_ALWAYS || (rf == GEOM_IMPLICIT_REFINE_AUTO && field->exact);
        c.normals = opt && opt->normals;
        c.caps = opt && opt->caps;
        c.max_iter = opt && opt->max_iterations > 0 ? opt->max_iterations : 64;
        c.alloc = al;
        st = extract(&c, opt, out, t0, diag);
    } else {
        geom__diag_set(diag, st, "", 0, 0, "geom_iso_extract: %s", geom_status_str(st));
    }
    for (int a = 0; a < 3; a++)
        geom__free(al, coord[a], (res[a] + 1) * sizeof(double));
    return st;
}

static geom_status extract_grid(const geom_iso_grid *grid, const geom_iso_options *opt,
                                geom_iso_surface *out, geom_diag *diag)
{
    double t0 = now_seconds();
    if (!out)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                             "geom_iso_extract_grid: NULL out");
    memset(out, 0, sizeof *out);
    geom_status st = geom_iso_grid_check(grid);
    if (st != GEOM_OK)
        return geom__diag_set(diag, st, "", 0, 0, "geom_iso_extract_grid: invalid grid");
    double iso = opt ? opt->iso : 0.0;
    if (!isfinite(iso))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                             "geom_iso_extract_grid: non-finite isovalue");
    init_out(out, opt);
    if (grid->dims[0] < 2 || grid->dims[1] < 2 || grid->dims[2] < 2) {
        out->report.seconds = now_seconds() - t0;
        return GEOM_OK;
    }
    for (int a = 0; a < 3; a++)
        if (grid->dims[a] - 1 >= (size_t)UINT32_MAX / 4)
            return geom__diag_set(diag, GEOM_ERR_LIMIT, "", 0, 0,
                                 "geom_iso_extract_grid: grid too large");
    const geom_allocator *al = opt ? opt->alloc : NULL;
    geom_iso_field field;
    geom_iso_field_from_grid(grid, &field);
    double *coord[3] = {NULL, NULL, NULL};
    for (int a = 0; a < 3 && st == GEOM_OK; a++) {
        coord[a] = geom__alloc(al, grid->dims[a] * sizeof(double));
        if (!coord[a]) {
            st = GEOM_ERR_NOMEM;
            break;
        }
        double sp = grid->spacing[a] > 0 ? grid->spacing[a] : 1.0;
        for (size_t i = 0; i < grid->dims[a]; i++)
            coord[a][i] = grid->origin[a] + (double)i * sp;
        for (size_t i = 0; i + 1 < grid->dims[a]; i++)
            if (!(coord[a][i + 1] > coord[a][i]))
                st = GEOM_ERR_INVALID_ARG;
    }
    if (st == GEOM_OK) {
        ctx c;
        memset(&c, 0, sizeof c);
        c.field = &field;
        c.grid = grid;
        for (int a = 0; a < 3; a++) {
            c.n[a] = grid->dims[a] - 1;
            c.coord[a] = coord[a];
            c.tau[a] = axis_tau(coord[a], c.n[a]);
            c.dstep[a] = 1e-3 * (grid->spacing[a] > 0 ? grid->spacing[a] : 1.0);
        }
        c.iso = iso;
        c.refine = 0;
        c.normals = opt && opt->normals;
        c.caps = opt && opt->caps;
        c.max_iter = 64;
        c.alloc = al;
        st = extract(&c, opt, out, t0, diag);
    } else {
        geom__diag_set(diag, st, "", 0, 0, "geom_iso_extract_grid: %s", geom_status_str(st));
    }
    for (int a = 0; a < 3; a++)
        geom__free(al, coord[a], grid->dims[a] * sizeof(double));
    return st;
}

/* ------------------------------------------------------ inside above iso */

/* "Inside above": the extraction of -f at -iso. Negation is exact, so the
 * vertices are those of f at iso (edge parameters (iso - f0) / (f1 - f0)
 * unchanged bit for bit), the classification is f >= iso inside (f > iso -
 * epsilon), and the winding, normals and caps follow the inside. */
static double neg_value(void *u, const double p[3])
{
    const geom_iso_field *f = u;
    return -f->value(f->user, p);
}

static double neg_gradient(void *u, const double p[3], double g[3])
{
    const geom_iso_field *f = u;
    double v = f->gradient(f->user, p, g);
    g[0] = -g[0];
    g[1] = -g[1];
    g[2] = -g[2];
    return -v;
}

static void neg_values(void *u, size_t n, const double *p, double *out)
{
    const geom_iso_field *f = u;
    f->values(f->user, n, p, out);
    for (size_t i = 0; i < n; i++)
        out[i] = -out[i];
}

static void neg_gradients(void *u, size_t n, const double *p, double *v, double *g)
{
    const geom_iso_field *f = u;
    f->gradients(f->user, n, p, v, g);
    for (size_t i = 0; i < n; i++)
        v[i] = -v[i];
    for (size_t i = 0; i < 3 * n; i++)
        g[i] = -g[i];
}

static int neg_bounds(void *u, const double lo[3], const double hi[3], double out[2])
{
    const geom_iso_field *f = u;
    double b[2];
    if (!f->bounds(f->user, lo, hi, b))
        return 0;
    out[0] = -b[1];
    out[1] = -b[0];
    return 1;
}

/* Signed volume enclosed by the triangles (divergence theorem; exact for a
 * closed surface, e.g. with caps): positive when they face outward. */
static void signed_volume(geom_iso_surface *out)
{
    double v = 0.0;
    for (size_t t = 0; t < out->n_triangles; t++)
        v += tri_volume6(out->xyz + 3 * (size_t)out->tris[3 * t],
                         out->xyz + 3 * (size_t)out->tris[3 * t + 1],
                         out->xyz + 3 * (size_t)out->tris[3 * t + 2]);
    out->report.signed_volume = v / 6.0;
}

/* geom_iso_extract, to arrays (sink NULL) or to sink (the stream path,
 * which sums the signed volume itself). */
static geom_status extract_top(const geom_iso_field *field, const double bounds[6],
                               const size_t res[3], const geom_iso_options *opt,
                               geom_iso_chunk_fn sink, void *sink_user, geom_iso_surface *out,
                               geom_diag *diag)
{
    geom_status st;
    if (opt && opt->inside == GEOM_ISO_INSIDE_ABOVE && field && field->value) {
        geom_iso_field neg;
        memset(&neg, 0, sizeof neg);
        neg.value = neg_value;
        neg.gradient = field->gradient ? neg_gradient : NULL;
        neg.values = field->values ? neg_values : NULL;
        neg.gradients = field->gradients ? neg_gradients : NULL;
        neg.bounds = field->bounds ? neg_bounds : NULL;
        neg.user = (void *)(uintptr_t)field;
        neg.exact = field->exact;
        geom_iso_options o = *opt;
        o.iso = -opt->iso;
        st = extract_field(&neg, bounds, res, &o, sink, sink_user, out, diag);
    } else if (opt && opt->inside != GEOM_ISO_INSIDE_BELOW && opt->inside != GEOM_ISO_INSIDE_ABOVE) {
        if (out)
            memset(out, 0, sizeof *out);
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                             "geom_iso_extract: inside must be GEOM_ISO_INSIDE_BELOW or _ABOVE");
    } else
        st = extract_field(field, bounds, res, opt, sink, sink_user, out, diag);
    if (st == GEOM_OK && !sink)
        signed_volume(out);
    return st;
}

geom_status geom_iso_extract(const geom_iso_field *field, const double bounds[6],
                             const size_t res[3], const geom_iso_options *opt,
                             geom_iso_surface *out, geom_diag *diag)
{
    return extract_top(field, bounds, res, opt, NULL, NULL, out, diag);
}

geom_status geom_iso_extract_stream(const geom_iso_field *field, const double bounds[6],
                                    const size_t res[3], const geom_iso_options *opt,
                                    geom_iso_chunk_fn fn, void *user, geom_iso_surface *out,
                                    geom_diag *diag)
{
    if (!fn) {
        if (out)
            memset(out, 0, sizeof *out);
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                              "geom_iso_extract_stream: NULL chunk function");
    }
    return extract_top(field, bounds, res, opt, fn, user, out, diag);
}

geom_status geom_iso_extract_grid(const geom_iso_grid *grid, const geom_iso_options *opt,
                                  geom_iso_surface *out, geom_diag *diag)
{
    if (opt && opt->inside != GEOM_ISO_INSIDE_BELOW && opt->inside != GEOM_ISO_INSIDE_ABOVE) {
        if (out)
            memset(out, 0, sizeof *out);
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                             "geom_iso_extract_grid: inside must be GEOM_ISO_INSIDE_BELOW or _ABOVE");
    }
    if (!(opt && opt->inside == GEOM_ISO_INSIDE_ABOVE) || geom_iso_grid_check(grid) != GEOM_OK) {
        geom_status st = extract_grid(grid, opt, out, diag);
        if (st == GEOM_OK)
            signed_volume(out);
        return st;
    }
    /* a negated copy of the samples (exact in either type) */
    const geom_allocator *al = opt->alloc;
    size_t n = grid->dims[0] * grid->dims[1] * grid->dims[2];
    size_t es = grid->type == GEOM_ISO_SCALAR_F32 ? sizeof(float) : sizeof(double), bytes;
    if (geom__size_mul(n, es, &bytes) != GEOM_OK) {
        if (out)
            memset(out, 0, sizeof *out);
        return geom__diag_set(diag, GEOM_ERR_LIMIT, "", 0, 0, "geom_iso_extract_grid: grid too large");
    }
    void *neg = geom__alloc(al, bytes ? bytes : 1);
    if (!neg) {
        if (out)
            memset(out, 0, sizeof *out);
        return geom__diag_set(diag, GEOM_ERR_NOMEM, "", 0, 0, "geom_iso_extract_grid: out of memory");
    }
    if (grid->type == GEOM_ISO_SCALAR_F32) {
        const float *src = grid->data;
        float *d = neg;
        for (size_t i = 0; i < n; i++)
            d[i] = -src[i];
    } else {
        const double *src = grid->data;
        double *d = neg;
        for (size_t i = 0; i < n; i++)
            d[i] = -src[i];
    }
    geom_iso_grid g = *grid;
    g.data = neg;
    geom_iso_options o = *opt;
    o.iso = -opt->iso;
    geom_status st = extract_grid(&g, &o, out, diag);
    geom__free(al, neg, bytes ? bytes : 1);
    if (st == GEOM_OK)
        signed_volume(out);
    return st;
}
