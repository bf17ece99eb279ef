/* BVH: input validation, primitive bounds, depth-first flattening, refit and
 * accessors. The builders (binned SAH, LBVH) are in bvh_sah.c and bvh_lbvh.c. */
#include "spatial/spatial_internal.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

uint32_t geom__bvh_tmp_new(geom__bvh_build *b)
{
    size_t id;
#ifdef GEOM_SPATIAL_OPENMP
#pragma omp atomic capture
#endif
    id = b->tmp_count++;
    return (uint32_t)id;
}

typedef struct bounds_src {
    const double *pos;
    const uint32_t *tris;
    const geom_aabb *boxes;
    geom_bvh_bounds_fn fn;
    void *user;
} bounds_src;

static void ref_box(const bounds_src *s, size_t i, geom__bvh_ref *r)
{
    if (s->tris) {
        const double *a = s->pos + 3 * (size_t)s->tris[3 * i];
        const double *b = s->pos + 3 * (size_t)s->tris[3 * i + 1];
        const double *c = s->pos + 3 * (size_t)s->tris[3 * i + 2];
        for (int k = 0; k < 3; k++) {
            double lo = a[k], hi = a[k];
            if (b[k] < lo) lo = b[k];
            if (b[k] > hi) hi = b[k];
            if (c[k] < lo) lo = c[k];
            if (c[k] > hi) hi = c[k];
            r->lo[k] = lo;
            r->hi[k] = hi;
        }
    } else {
        geom_aabb bx;
        if (s->boxes)
            bx = s->boxes[i];
        else
            s->fn(s->user, i, &bx);
        r->lo[0] = bx.min.x;
        r->lo[1] = bx.min.y;
        r->lo[2] = bx.min.z;
        r->hi[0] = bx.max.x;
        r->hi[1] = bx.max.y;
        r->hi[2] = bx.max.z;
    }
    r->id = (uint32_t)i;
    r->pad = 0;
}

static void ref_box_fn(const void *src, size_t i, geom__bvh_ref *r)
{
    ref_box((const bounds_src *)src, i, r);
}

/* The temporary nodes are already in depth-first order (left = id + 1):
 * rewrite them in place as flat nodes (each flat node is no larger than a
 * temporary one and lies at or before it); returns the depth. */
static size_t preorder_in_place(geom__bvh_tmp *tmp, size_t count)
{
    _Static_assert(sizeof(geom_bvh_node) <= sizeof(geom__bvh_tmp), "flat node larger than temp node");
    geom_bvh_node *nodes = (geom_bvh_node *)(void *)tmp;
    size_t pend[256];
    int sp = 0;
    size_t depth = 1, maxd = 0;
    for (size_t i = 0; i < count; i++) {
        geom__bvh_tmp t = tmp[i];
        geom_bvh_node nd;
        nd.box = t.box;
        nd.axis = t.axis;
        nd.pad = 0;
        if (depth > maxd)
            maxd = depth;
        if (t.left == UINT32_MAX) {
            nd.index = t.start;
            nd.count = t.count;
            depth = sp > 0 ? pend[--sp] : 0;
        } else {
            nd.index = t.right;
            nd.count = 0;
            pend[sp++] = depth + 1;
            depth++;
        }
        memcpy(&nodes[i], &nd, sizeof nd);
    }
    return maxd;
}

static int ref_ok(const geom__bvh_ref *r)
{
    for (int k = 0; k < 3; k++)
        if (!isfinite(r->lo[k]) || !isfinite(r->hi[k]) || !(r->lo[k] <= r->hi[k]))
            return 0;
    return 1;
}

static void free_bvh(geom_bvh *b)
{
    const geom_allocator *a = b->has_alloc ? &b->alloc : NULL;
    geom__free(a, b->nodes, b->node_count * sizeof *b->nodes);
    geom__free(a, b->prims, b->prim_count * sizeof *b->prims);
    geom__free(a, b, sizeof *b);
}

void geom_bvh_destroy(geom_bvh *b)
{
    if (b)
        free_bvh(b);
}

/* Depth-first pre-order copy of the temporary tree; returns the depth. */
static size_t flatten(const geom__bvh_tmp *tmp, uint32_t root, geom_bvh_node *nodes,
                      size_t *next, size_t depth)
{
    /* Explicit stack: (temp id, flat slot of the parent to patch, depth). */
    typedef struct item { uint32_t t; uint32_t parent; size_t depth; } item;
    item stack[256];
    int sp = 0;
    size_t maxd = 0;
    stack[sp++] = (item){root, UINT32_MAX, depth};
    while (sp > 0) {
        item it = stack[--sp];
        size_t i = (*next)++;
        if (it.parent != UINT32_MAX)
            nodes[it.parent].index = (uint32_t)i;
        const geom__bvh_tmp *t = &tmp[it.t];
        nodes[i].box = t->box;
        nodes[i].pad = 0;
        nodes[i].axis = t->axis;
        if (it.depth > maxd)
            maxd = it.depth;
        if (t->left == UINT32_MAX) {
            nodes[i].index = t->start;
            nodes[i].count = t->count;
        } else {
            nodes[i].count = 0;
            nodes[i].index = 0;
            /* Right is popped after the whole left subtree: push it first. */
            stack[sp++] = (item){t->right, (uint32_t)i, it.depth + 1};
            stack[sp++] = (item){t->left, UINT32_MAX, it.depth + 1};
        }
    }
    return maxd;
}

static geom_status build_common(size_t n, const bounds_src *src, const geom_bvh_options *opt,
                                geom_bvh **out, geom_diag *diag)
{
    geom_bvh_options o;
    memset(&o, 0, sizeof o);
    if (opt)
        o = *opt;
    const geom_allocator *a = o.alloc;
    if (n >= ((size_t)1 << 31))
        return geom__diag_set(diag, GEOM_ERR_LIMIT, "", 0, 0, "BVH: %zu primitives (at most 2^31-1)", n);
    if (o.method != GEOM_BVH_SAH && o.method != GEOM_BVH_LBVH)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0, "BVH: unknown method %d", (int)o.method);
    if (o.bins > 256)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0, "BVH: %u bins (at most 256)", o.bins);
    geom_bvh *b = geom__alloc(a, sizeof *b);
    if (!b)
        return geom__diag_set(diag, GEOM_ERR_NOMEM, "", 0, 0, "BVH: out of memory");
    memset(b, 0, sizeof *b);
    if (a) {
        b->alloc = *a;
        b->has_alloc = 1;
    }
    if (n == 0) {
        *out = b;
        return GEOM_OK;
    }
    geom__bvh_build bd;
    memset(&bd, 0, sizeof bd);
    bd.n = n;
    bd.max_leaf = o.max_leaf_size ? o.max_leaf_size : 4;
    bd.bins = o.bins ? o.bins : 16;
    if (bd.bins < 2)
        bd.bins = 2;
    bd.threads = geom__spatial_threads(o.threads);
    bd.alloc = a;
    bd.box_fn = ref_box_fn;
    bd.src = src;
    /* The LBVH sorts the references themselves; the SAH build keeps its own
     * compact copy and asks box_fn again, so it needs none here. */
    int keep_refs = o.method == GEOM_BVH_LBVH;
    bd.refs = keep_refs ? geom__alloc(a, n * sizeof *bd.refs) : NULL;
    geom__advise_huge(a, bd.refs, n * sizeof *bd.refs, GEOM__BVH_HUGE_MIN);
    bd.tmp = geom__alloc(a, 2 * n * sizeof *bd.tmp);
    geom__advise_huge(a, bd.tmp, 2 * n * sizeof *bd.tmp, GEOM__BVH_HUGE_MIN);
    b->prims = geom__alloc(a, n * sizeof *b->prims);
    b->prim_count = n;
    geom_status st = GEOM_OK;
    if ((keep_refs && !bd.refs) || !bd.tmp || !b->prims) {
        st = geom__diag_set(diag, GEOM_ERR_NOMEM, "", 0, 0, "BVH: out of memory");
        goto fail;
    }
    if (keep_refs) {
        geom__bvh_ref *refs = bd.refs;
        ptrdiff_t nn = (ptrdiff_t)n;
#ifdef GEOM_SPATIAL_OPENMP
#pragma omp parallel for schedule(static) num_threads(bd.threads) if (n > 65536)
#endif
        for (ptrdiff_t i = 0; i < nn; i++)
            ref_box(src, (size_t)i, &refs[i]);
    }
    for (int k = 0; k < 3; k++) {
        bd.scene_lo[k] = INFINITY;
        bd.scene_hi[k] = -INFINITY;
    }
    for (size_t i = 0; i < n; i++) {
        geom__bvh_ref own;
        const geom__bvh_ref *ri = &own;
        if (keep_refs)
            ri = &bd.refs[i];
        else
            ref_box(src, i, &own);
        /* A triangle's min/max can hide a NaN vertex: test the vertices. */
        int bad = !ref_ok(ri);
        for (int k = 0; k < 3; k++) {
            if (ri->lo[k] < bd.scene_lo[k]) bd.scene_lo[k] = ri->lo[k];
            if (ri->hi[k] > bd.scene_hi[k]) bd.scene_hi[k] = ri->hi[k];
        }
        if (src->tris && !bad)
            for (int k = 0; k < 3; k++)
                bad |= !geom__isfinite3(src->pos + 3 * (size_t)src->tris[3 * i + k]);
        if (bad) {
            if (src->tris) {
                for (int k = 0; k < 3; k++)
                    if (!geom__isfinite3(src->pos + 3 * (size_t)src->tris[3 * i + k])) {
                        st = geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                                           "BVH: triangle %zu: vertex %u has a NaN/Inf coordinate",
                                           i, src->tris[3 * i + k]);
                        goto fail;
                    }
            }
            st = geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                               "BVH: primitive %zu has a NaN/Inf or empty box", i);
            goto fail;
        }
    }
    uint32_t root = o.method == GEOM_BVH_LBVH ? geom__bvh_build_lbvh(&bd) : geom__bvh_build_sah(&bd);
    if (root == UINT32_MAX) {
        st = geom__diag_set(diag, GEOM_ERR_NOMEM, "", 0, 0, "BVH: out of memory");
        goto fail;
    }
    if (bd.preorder && root == 0) {
        b->depth = preorder_in_place(bd.tmp, bd.tmp_count);
        geom_bvh_node *shrunk = geom__realloc(a, bd.tmp, 2 * n * sizeof *bd.tmp,
                                             bd.tmp_count * sizeof *b->nodes);
        if (!shrunk) {
            st = geom__diag_set(diag, GEOM_ERR_NOMEM, "", 0, 0, "BVH: out of memory");
            goto fail;
        }
        b->nodes = shrunk;
        bd.tmp = NULL;
        b->node_count = bd.tmp_count;
    } else {
        b->nodes = geom__alloc(a, bd.tmp_count * sizeof *b->nodes);
        if (!b->nodes) {
            st = geom__diag_set(diag, GEOM_ERR_NOMEM, "", 0, 0, "BVH: out of memory");
            goto fail;
        }
        b->node_count = bd.tmp_count;
        size_t next = 0;
        b->depth = flatten(bd.tmp, root, b->nodes, &next, 1);
    }
    for (size_t i = 0; i < n; i++)
        b->prims[i] = bd.order ? bd.order[i] : bd.refs[i].id;
    geom__free(a, bd.order, n * sizeof *bd.order);
    if (keep_refs)
        geom__free(a, bd.refs, n * sizeof *bd.refs);
    geom__free(a, bd.tmp, 2 * n * sizeof *bd.tmp);
    *out = b;
    return GEOM_OK;
fail:
    geom__free(a, bd.order, n * sizeof *bd.order);
    if (bd.refs)
        geom__free(a, bd.refs, n * sizeof *bd.refs);
    geom__free(a, bd.tmp, 2 * n * sizeof *bd.tmp);
    free_bvh(b);
    return st;
}

geom_status geom_bvh_build_triangles(const double *positions, size_t nv, const uint32_t *tris,
                                     size_t nt, const geom_bvh_options *opt, geom_bvh **out,
                                     geom_diag *diag)
{
    if (out)
        *out = NULL;
    if (!out || (nt && (!positions || !tris)))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0, "BVH: NULL argument");
    for (size_t i = 0; i < 3 * nt; i++)
        if (tris[i] >= nv)
            return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                                 "BVH: triangle %zu: vertex index %u out of range (%zu vertices)",
                                 i / 3, tris[i], nv);
    bounds_src s = {positions, tris, NULL, NULL, NULL};
    return build_common(nt, &s, opt, out, diag);
}

geom_status geom_bvh_build_boxes(const geom_aabb *boxes, size_t n, const geom_bvh_options *opt,
                                 geom_bvh **out, geom_diag *diag)
{
    if (out)
        *out = NULL;
    if (!out || (n && !boxes))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0, "BVH: NULL argument");
    bounds_src s = {NULL, NULL, boxes, NULL, NULL};
    return build_common(n, &s, opt, out, diag);
}

geom_status geom_bvh_build_callback(size_t n, geom_bvh_bounds_fn fn, void *user,
                                    const geom_bvh_options *opt, geom_bvh **out, geom_diag *diag)
{
    if (out)
        *out = NULL;
    if (!out || (n && !fn))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0, "BVH: NULL argument");
    bounds_src s = {NULL, NULL, NULL, fn, user};
    return build_common(n, &s, opt, out, diag);
}

geom_status geom_bvh_refit_triangles(geom_bvh *b, const double *positions, size_t nv,
                                     const uint32_t *tris, size_t nt)
{
    if (!b || nt != b->prim_count || (nt && (!positions || !tris)))
        return GEOM_ERR_INVALID_ARG;
    for (size_t i = 0; i < 3 * nt; i++)
        if (tris[i] >= nv || !geom__isfinite3(positions + 3 * (size_t)tris[i]))
            return GEOM_ERR_INVALID_ARG;
    bounds_src s = {positions, tris, NULL, NULL, NULL};
    /* Children follow their parent in the depth-first layout, so a reverse
     * sweep sees both children before the parent. */
    for (size_t j = b->node_count; j-- > 0;) {
        geom_bvh_node *nd = &b->nodes[j];
        if (nd->count) {
            geom_aabb box = geom_aabb_empty();
            for (uint32_t k = 0; k < nd->count; k++) {
                geom__bvh_ref r;
                ref_box(&s, b->prims[nd->index + k], &r);
                box = geom_aabb_union(box, (geom_aabb){{r.lo[0], r.lo[1], r.lo[2]},
                                                       {r.hi[0], r.hi[1], r.hi[2]}});
            }
            nd->box = box;
        } else {
            nd->box = geom_aabb_union(b->nodes[j + 1].box, b->nodes[nd->index].box);
        }
    }
    return GEOM_OK;
}

const geom_bvh_node *geom_bvh_nodes(const geom_bvh *b, size_t *count)
{
    if (count)
        *count = b ? b->node_count : 0;
    return b ? b->nodes : NULL;
}

const uint32_t *geom_bvh_prim_indices(const geom_bvh *b, size_t *count)
{
    if (count)
        *count = b ? b->prim_count : 0;
    return b ? b->prims : NULL;
}

size_t geom_bvh_depth(const geom_bvh *b)
{
    return b ? b->depth : 0;
}

size_t geom_bvh_bytes(const geom_bvh *b)
{
    if (!b)
        return 0;
    return sizeof *b + b->node_count * sizeof *b->nodes + b->prim_count * sizeof *b->prims;
}
