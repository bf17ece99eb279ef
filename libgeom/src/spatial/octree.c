/*
 * Quadtree/octree, linear build: every item gets the Morton code of the
 * deepest cell (of a 2^B grid over the bounding square/cube) containing its
 * box, and its level; the items are radix-sorted by (code truncated to the
 * level, level), which puts the items of every subtree in one contiguous
 * run, the node's own items first and then its children in octant order.
 * The tree is then cut top-down over the sorted run (sequential, O(n) after
 * the sort). 2:1 balancing splits, repeatedly, every leaf that has a
 * neighbouring leaf (faces, edges, corners) more than one level deeper;
 * splitting a leaf only re-partitions its contiguous run.
 */
#include "spatial/spatial_internal.h"

#include <string.h>

#define LEVEL_BITS 5

typedef struct bctx {
    geom_octree *t;
    const uint64_t *keys; /* sorted: code << 5 | level */
    int B;                /* bits per axis */
    uint32_t bucket, maxd;
    int balance;
    double origin[3], side;
    uint64_t *ncode; /* per node: cell code at its level (grown with nodes) */
    size_t ncode_cap;
    geom_status st;
} bctx;

static uint64_t key_code(uint64_t k) { return k >> LEVEL_BITS; }
static uint32_t key_level(uint64_t k) { return (uint32_t)(k & 31); }

/* Octant digit of a full code at level L+1 (the child below level L). */
static uint32_t digit(const bctx *c, uint64_t code, uint32_t L)
{
    int d = c->t->dim;
    int shift = d * (c->B - (int)L - 1);
    return (uint32_t)((code >> shift) & ((1u << d) - 1));
}

static void cell_box(const bctx *c, uint64_t code, uint32_t L, geom_aabb *box)
{
    /* De-interleave the code's top L digits into integer cell coordinates. */
    int d = c->t->dim;
    uint64_t q[3] = {0, 0, 0};
    for (uint32_t l = 0; l < L; l++) {
        uint32_t dg = digit(c, code, l);
        for (int k = 0; k < d; k++)
            q[k] = q[k] << 1 | ((dg >> k) & 1);
    }
    double h = c->side / (double)((uint64_t)1 << L);
    double lo[3], hi[3];
    for (int k = 0; k < 3; k++) {
        if (k < d) {
            lo[k] = c->origin[k] + (double)q[k] * h;
            hi[k] = c->origin[k] + (double)(q[k] + 1) * h;
        } else {
            lo[k] = hi[k] = 0;
        }
    }
    box->min = (geom_vec3){lo[0], lo[1], lo[2]};
    box->max = (geom_vec3){hi[0], hi[1], hi[2]};
}

static uint32_t new_nodes(bctx *c, uint32_t count)
{
    geom_octree *t = c->t;
    const geom_allocator *a = geom__octree_alloc(t);
    size_t need = t->node_count + count;
    geom_status st = geom__grow(a, (void **)&t->nodes, &t->node_cap, need, sizeof *t->nodes);
    if (st == GEOM_OK)
        st = geom__grow(a, (void **)&c->ncode, &c->ncode_cap, need, sizeof *c->ncode);
    if (st != GEOM_OK) {
        c->st = st;
        return UINT32_MAX;
    }
    uint32_t id = (uint32_t)t->node_count;
    t->node_count += count;
    return id;
}

static geom_aabb item_box(const geom_octree *t, size_t i)
{
    const double *b = t->ibox + 6 * i;
    geom_aabb x = {{b[0], b[1], b[2]}, {b[3], b[4], b[5]}};
    return x;
}

static void init_node(bctx *c, uint32_t id, uint64_t code, uint32_t L, size_t s, size_t n)
{
    geom_octree_node *nd = &c->t->nodes[id];
    cell_box(c, code, L, &nd->cell);
    nd->bounds = geom_aabb_empty();
    nd->first_child = GEOM_INVALID_INDEX;
    nd->child_mask = 0;
    nd->item_start = (uint32_t)s;
    nd->item_total = (uint32_t)n;
    nd->own_count = (uint32_t)n;
    nd->level = L;
    c->ncode[id] = code;
}

/* Number of items at the start of [s, s+n) stored at level <= L. */
static size_t own_prefix(const bctx *c, size_t s, size_t n, uint32_t L)
{
    size_t k = 0;
    while (k < n && key_level(c->keys[s + k]) <= L)
        k++;
    return k;
}

/* Split node id (a leaf covering [s, s+n) at level L) into children; full:
 * create all 2^dim children. Returns 0, or -1 on failure (c->st set). */
static int split(bctx *c, uint32_t id, int full)
{
    geom_octree_node nd = c->t->nodes[id];
    size_t s = nd.item_start, n = nd.item_total;
    uint32_t L = nd.level;
    uint64_t code = c->ncode[id];
    size_t own = own_prefix(c, s, n, L);
    int d = c->t->dim;
    uint32_t nchild = 1u << d;
    size_t cs[8], cn[8];
    uint32_t mask = 0, cnt = 0;
    size_t i = s + own;
    for (uint32_t o = 0; o < nchild; o++) {
        cs[o] = i;
        while (i < s + n && digit(c, key_code(c->keys[i]), L) == o)
            i++;
        cn[o] = i - cs[o];
        if (cn[o] || full) {
            mask |= 1u << o;
            cnt++;
        }
    }
    uint32_t first = new_nodes(c, cnt);
    if (first == UINT32_MAX)
        return -1;
    uint32_t k = first;
    int shift = d * (c->B - (int)L - 1);
    for (uint32_t o = 0; o < nchild; o++)
        if (mask >> o & 1)
            init_node(c, k++, code | ((uint64_t)o << shift), L + 1, cs[o], cn[o]);
    geom_octree_node *p = &c->t->nodes[id];
    p->first_child = first;
    p->child_mask = mask;
    p->own_count = (uint32_t)own;
    if (L + 1 + 1 > c->t->depth)
        c->t->depth = L + 2;
    return 0;
}

static int splittable(const bctx *c, const geom_octree_node *nd)
{
    size_t s = nd->item_start, n = nd->item_total;
    if (n <= c->bucket || nd->level >= c->maxd)
        return 0;
    /* All items in one cell: splitting cannot separate them. */
    if (c->keys[s] == c->keys[s + n - 1])
        return 0;
    /* Only items that straddle: nothing goes down. */
    if (own_prefix(c, s, n, nd->level) == n)
        return 0;
    return 1;
}

/* Top-down build: a breadth-first sweep over the node array (children are
 * appended, so the loop reaches them). */
static int build_all(bctx *c)
{
    for (size_t i = 0; i < c->t->node_count; i++) {
        geom_octree_node nd = c->t->nodes[i];
        if (splittable(c, &nd) && split(c, (uint32_t)i, c->balance))
            return -1;
    }
    return 0;
}

/* Deepest node containing integer cell (q at level L), descending from the root. */
static uint32_t locate(const bctx *c, const uint64_t q[3], uint32_t L)
{
    const geom_octree *t = c->t;
    uint32_t id = 0;
    int d = t->dim;
    for (;;) {
        const geom_octree_node *nd = &t->nodes[id];
        if (nd->first_child == GEOM_INVALID_INDEX || nd->level >= L)
            return id;
        uint32_t o = 0;
        for (int k = 0; k < d; k++)
            o |= (uint32_t)((q[k] >> (L - nd->level - 1)) & 1) << k;
        if (!(nd->child_mask >> o & 1))
            return id; /* cannot happen in a balanced (full) tree */
        uint32_t below = nd->child_mask & ((1u << o) - 1);
        id = nd->first_child + (uint32_t)__builtin_popcount(below);
    }
}

static void cell_coords(const bctx *c, uint64_t code, uint32_t L, uint64_t q[3])
{
    int d = c->t->dim;
    q[0] = q[1] = q[2] = 0;
    for (uint32_t l = 0; l < L; l++) {
        uint32_t dg = digit(c, code, l);
        for (int k = 0; k < d; k++)
            q[k] = q[k] << 1 | ((dg >> k) & 1);
    }
}

static int balance(bctx *c)
{
    int d = c->t->dim;
    int changed = 1;
    while (changed) {
        changed = 0;
        size_t count = c->t->node_count;
        for (size_t i = 0; i < count; i++) {
            geom_octree_node nd = c->t->nodes[i];
            if (nd.first_child != GEOM_INVALID_INDEX || nd.level < 2)
                continue;
            uint64_t q[3];
            cell_coords(c, c->ncode[i], nd.level, q);
            int64_t lim = (int64_t)1 << nd.level;
            for (int dz = (d == 3 ? -1 : 0); dz <= (d == 3 ? 1 : 0); dz++)
                for (int dy = -1; dy <= 1; dy++)
                    for (int dx = -1; dx <= 1; dx++) {
                        if (!dx && !dy && !dz)
                            continue;
                        int64_t nq[3] = {(int64_t)q[0] + dx, (int64_t)q[1] + dy, (int64_t)q[2] + dz};
                        int out = 0;
                        for (int k = 0; k < d; k++)
                            out |= nq[k] < 0 || nq[k] >= lim;
                        if (out)
                            continue;
                        uint64_t uq[3] = {(uint64_t)nq[0], (uint64_t)nq[1], (uint64_t)nq[2]};
                        uint32_t j = locate(c, uq, nd.level);
                        const geom_octree_node *nb = &c->t->nodes[j];
                        if (nb->first_child == GEOM_INVALID_INDEX && nb->level + 1 < nd.level) {
                            if (split(c, j, 1))
                                return -1;
                            changed = 1;
                        }
                    }
        }
    }
    return 0;
}

/* Tight bounds bottom-up: children always have larger indices. */
static void bounds_up(geom_octree *t)
{
    for (size_t i = t->node_count; i-- > 0;) {
        geom_octree_node *nd = &t->nodes[i];
        geom_aabb b = geom_aabb_empty();
        for (uint32_t k = 0; k < nd->own_count; k++)
            b = geom_aabb_union(b, item_box(t, nd->item_start + k));
        if (nd->first_child != GEOM_INVALID_INDEX) {
            uint32_t nc = (uint32_t)__builtin_popcount(nd->child_mask);
            for (uint32_t k = 0; k < nc; k++)
                b = geom_aabb_union(b, t->nodes[nd->first_child + k].bounds);
        }
        nd->bounds = b;
    }
}

typedef struct src {
    const double *pos;
    const uint32_t *idx; /* NULL for points */
    int per;             /* vertices per element (1 for points) */
    int dim;
} src;

static void elem_box(const src *s, size_t i, double lo[3], double hi[3])
{
    for (int k = 0; k < 3; k++) {
        lo[k] = INFINITY;
        hi[k] = -INFINITY;
    }
    for (int v = 0; v < s->per; v++) {
        size_t vi = s->idx ? s->idx[(size_t)s->per * i + (size_t)v] : i;
        const double *p = s->pos + (size_t)s->dim * vi;
        for (int k = 0; k < 3; k++) {
            double x = k < s->dim ? p[k] : 0.0;
            if (!isfinite(x)) { /* min/max would skip a NaN: poison the box */
                lo[k] = NAN;
                return;
            }
            if (x < lo[k]) lo[k] = x;
            if (x > hi[k]) hi[k] = x;
        }
    }
}

void geom_octree_destroy(geom_octree *t)
{
    if (!t)
        return;
    const geom_allocator *a = geom__octree_alloc(t);
    geom__free(a, t->items, t->n * sizeof *t->items);
    geom__free(a, t->ibox, 6 * t->n * sizeof *t->ibox);
    geom__free(a, t->nodes, t->node_cap * sizeof *t->nodes);
    geom__free(a, t, sizeof *t);
}

static geom_status build(const src *s, size_t n, const geom_octree_options *opt, geom_octree **out,
                         geom_diag *diag, const char *what)
{
    geom_octree_options o;
    memset(&o, 0, sizeof o);
    if (opt)
        o = *opt;
    const geom_allocator *a = o.alloc;
    if (n >= UINT32_MAX)
        return geom__diag_set(diag, GEOM_ERR_LIMIT, "", 0, 0, "tree: %zu %ss (at most 2^32-2)", n, what);
    geom_octree *t = geom__alloc(a, sizeof *t);
    if (!t)
        return geom__diag_set(diag, GEOM_ERR_NOMEM, "", 0, 0, "tree: out of memory");
    memset(t, 0, sizeof *t);
    if (a) {
        t->alloc = *a;
        t->has_alloc = 1;
    }
    t->dim = s->dim;
    t->points = s->idx == NULL;
    t->n = n;
    bctx c;
    memset(&c, 0, sizeof c);
    c.t = t;
    c.B = s->dim == 3 ? 19 : 28;
    c.bucket = o.bucket_size ? o.bucket_size : 16;
    c.maxd = o.max_depth && o.max_depth < (uint32_t)c.B ? o.max_depth : (uint32_t)c.B;
    c.balance = o.balance != 0;
    uint64_t *keys = NULL;
    uint32_t *perm = NULL;
    double *box = NULL;
    geom_status st = GEOM_OK;
    t->items = geom__alloc(a, n * sizeof *t->items);
    t->ibox = geom__alloc(a, 6 * n * sizeof *t->ibox);
    keys = geom__alloc(a, n * sizeof *keys);
    perm = geom__alloc(a, n * sizeof *perm);
    box = geom__alloc(a, 6 * n * sizeof *box);
    if (!t->items || !t->ibox || !keys || !perm || !box) {
        st = geom__diag_set(diag, GEOM_ERR_NOMEM, "", 0, 0, "tree: out of memory");
        goto done;
    }
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < n; i++) {
        double *b = box + 6 * i;
        elem_box(s, i, b, b + 3);
        for (int k = 0; k < 3; k++) {
            if (!isfinite(b[k]) || !isfinite(b[3 + k])) {
                st = geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                                   "tree: %s %zu has a NaN/Inf coordinate", what, i);
                goto done;
            }
            if (b[k] < lo[k]) lo[k] = b[k];
            if (b[3 + k] > hi[k]) hi[k] = b[3 + k];
        }
    }
    if (n == 0) {
        *out = t;
        t = NULL;
        goto done;
    }
    double side = 0;
    for (int k = 0; k < s->dim; k++)
        if (hi[k] - lo[k] > side)
            side = hi[k] - lo[k];
    if (!(side > 0))
        side = 1;
    if (!isfinite(side)) {
        st = geom__diag_set(diag, GEOM_ERR_DOMAIN, "", 0, 0, "tree: extent overflows a double");
        goto done;
    }
    for (int k = 0; k < 3; k++)
        c.origin[k] = k < s->dim ? lo[k] : 0.0;
    c.side = side;
    {
        double scale = (double)((uint64_t)1 << c.B) / side;
        uint64_t qmax = ((uint64_t)1 << c.B) - 1;
        int B = c.B, dim = s->dim;
        uint32_t maxd = c.maxd;
        ptrdiff_t nn = (ptrdiff_t)n;
        int nth = geom__spatial_threads(o.threads);
        (void)nth;
#ifdef GEOM_SPATIAL_OPENMP
#pragma omp parallel for schedule(static) num_threads(nth) if (n > 65536)
#endif
        for (ptrdiff_t i = 0; i < nn; i++) {
            const double *b = box + 6 * i;
            uint64_t ql[3] = {0, 0, 0}, qh[3] = {0, 0, 0};
            int top = -1;
            for (int k = 0; k < dim; k++) {
                double vl = (b[k] - c.origin[k]) * scale, vh = (b[3 + k] - c.origin[k]) * scale;
                ql[k] = vl >= (double)qmax ? qmax : vl > 0 ? (uint64_t)vl : 0;
                qh[k] = vh >= (double)qmax ? qmax : vh > 0 ? (uint64_t)vh : 0;
                uint64_t x = ql[k] ^ qh[k];
                int h = x ? 63 - __builtin_clzll(x) : -1;
                if (h > top)
                    top = h;
            }
            uint32_t level = (uint32_t)(B - 1 - top);
            if (level > maxd)
                level = maxd;
            uint64_t code = dim == 3 ? geom__morton3((uint32_t)ql[0], (uint32_t)ql[1], (uint32_t)ql[2])
                                     : geom__morton_spread2(ql[0]) | geom__morton_spread2(ql[1]) << 1;
            int drop = dim * (B - (int)level);
            if (drop >= 64)
                code = 0;
            else
                code = code >> drop << drop;
            keys[i] = code << LEVEL_BITS | level;
            perm[i] = (uint32_t)i;
        }
    }
    if (geom__radix_sort64(a, keys, perm, n) != GEOM_OK) {
        st = geom__diag_set(diag, GEOM_ERR_NOMEM, "", 0, 0, "tree: out of memory");
        goto done;
    }
    for (size_t i = 0; i < n; i++) {
        t->items[i] = perm[i];
        memcpy(t->ibox + 6 * i, box + 6 * (size_t)perm[i], 6 * sizeof(double));
    }
    c.keys = keys;
    uint32_t root = new_nodes(&c, 1);
    if (root == UINT32_MAX)
        goto nomem;
    init_node(&c, root, 0, 0, 0, n);
    t->depth = 1;
    if (build_all(&c) || (c.balance && balance(&c)))
        goto nomem;
    bounds_up(t);
    *out = t;
    t = NULL;
    goto done;
nomem:
    st = geom__diag_set(diag, GEOM_ERR_NOMEM, "", 0, 0, "tree: out of memory");
done:
    geom__free(a, c.ncode, c.ncode_cap * sizeof *c.ncode);
    geom__free(a, keys, n * sizeof *keys);
    geom__free(a, perm, n * sizeof *perm);
    geom__free(a, box, 6 * n * sizeof *box);
    geom_octree_destroy(t);
    return st;
}

geom_status geom_octree_build_points(const double *points, size_t n, int dim,
                                     const geom_octree_options *opt, geom_octree **out, geom_diag *diag)
{
    if (out)
        *out = NULL;
    if (!out || (n && !points) || (dim != 2 && dim != 3))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                             "tree: NULL argument or dimension %d (2 or 3)", dim);
    src s = {points, NULL, 1, dim};
    return build(&s, n, opt, out, diag, "point");
}

static geom_status check_idx(const uint32_t *idx, size_t m, size_t nv, int per, const char *what,
                             geom_diag *diag)
{
    for (size_t i = 0; i < (size_t)per * m; i++)
        if (idx[i] >= nv)
            return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                                 "tree: %s %zu: vertex index %u out of range (%zu vertices)", what,
                                 i / (size_t)per, idx[i], nv);
    return GEOM_OK;
}

geom_status geom_octree_build_segments(const double *positions, size_t nv, const uint32_t *segs,
                                       size_t ns, const geom_octree_options *opt, geom_octree **out,
                                       geom_diag *diag)
{
    if (out)
        *out = NULL;
    if (!out || (ns && (!positions || !segs)))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0, "tree: NULL argument");
    geom_status st = check_idx(segs, ns, nv, 2, "segment", diag);
    if (st != GEOM_OK)
        return st;
    src s = {positions, segs, 2, 2};
    return build(&s, ns, opt, out, diag, "segment");
}

geom_status geom_octree_build_triangles(const double *positions, size_t nv, const uint32_t *tris,
                                        size_t nt, const geom_octree_options *opt, geom_octree **out,
                                        geom_diag *diag)
{
    if (out)
        *out = NULL;
    if (!out || (nt && (!positions || !tris)))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0, "tree: NULL argument");
    geom_status st = check_idx(tris, nt, nv, 3, "triangle", diag);
    if (st != GEOM_OK)
        return st;
    src s = {positions, tris, 3, 3};
    return build(&s, nt, opt, out, diag, "triangle");
}

const geom_octree_node *geom_octree_nodes(const geom_octree *t, size_t *count)
{
    if (count)
        *count = t ? t->node_count : 0;
    return t ? t->nodes : NULL;
}

const uint32_t *geom_octree_items(const geom_octree *t, size_t *count)
{
    if (count)
        *count = t ? t->n : 0;
    return t ? t->items : NULL;
}

int geom_octree_dim(const geom_octree *t)
{
    return t ? t->dim : 0;
}

size_t geom_octree_depth(const geom_octree *t)
{
    return t ? t->depth : 0;
}

size_t geom_octree_bytes(const geom_octree *t)
{
    if (!t)
        return 0;
    return sizeof *t + t->n * (sizeof *t->items + 6 * sizeof(double)) +
           t->node_count * sizeof *t->nodes;
}
