/*
 * Box queries over a BVH (geom_bvh_query_boxes): a depth-first walk of the
 * flat node layout per query, pruning the subtrees whose (conservative)
 * node box misses the query, then each leaf primitive's own box against the
 * query. Closed boxes, comparisons only, so the answer is exactly the
 * brute-force one. Rows are sorted by primitive and assembled in query
 * order by the shared batch-row machinery (neighbors.c).
 */
#include "spatial/spatial_internal.h"

#include <math.h>

typedef struct qctx {
    const geom_bvh *b;
    const geom_aabb *prims;
    const geom_aabb *queries;
} qctx;

/* Closed boxes meet: no axis separates them (false when either is empty). */
static inline int boxes_meet(const geom_aabb *p, const geom_aabb *q)
{
    return p->min.x <= q->max.x && p->max.x >= q->min.x && p->min.y <= q->max.y &&
           p->max.y >= q->min.y && p->min.z <= q->max.z && p->max.z >= q->min.z;
}

static geom_status query_row(const void *ctx, size_t q, geom__hits *h)
{
    const qctx *c = ctx;
    const geom_bvh *b = c->b;
    const geom_aabb *box = &c->queries[q];
    if (b->node_count == 0 || !(box->min.x <= box->max.x && box->min.y <= box->max.y &&
                                box->min.z <= box->max.z))
        return GEOM_OK;
    /* the walk keeps at most one pending right child per level */
    uint32_t local[128];
    size_t cap = b->depth + 1, bytes = 0;
    uint32_t *stack = local;
    if (cap > sizeof local / sizeof *local) {
        if (geom__size_mul(cap, sizeof *stack, &bytes) != GEOM_OK ||
            !(stack = geom__alloc(h->a, bytes)))
            return GEOM_ERR_NOMEM;
    }
    size_t from = h->n, top = 0;
    geom_status st = GEOM_OK;
    uint32_t node = 0;
    for (;;) {
        const geom_bvh_node *nd = &b->nodes[node];
        if (boxes_meet(&nd->box, box)) {
            if (nd->count == 0) {
                if (top == cap) { /* cannot happen with the builders' depth */
                    st = GEOM_ERR_LIMIT;
                    goto done;
                }
                stack[top++] = nd->index; /* right child later, left child now */
                node++;
                continue;
            }
            for (uint32_t i = 0; i < nd->count; i++) {
                uint32_t p = b->prims[nd->index + i];
                if (boxes_meet(&c->prims[p], box) && geom__hits_push(h, p, 0.0) != 0) {
                    st = GEOM_ERR_NOMEM;
                    goto done;
                }
            }
        }
        if (top == 0)
            break;
        node = stack[--top];
    }
    geom__hits_sort(h, from);
done:
    if (stack != local)
        geom__free(h->a, stack, bytes);
    return st;
}

geom_status geom_bvh_query_boxes(const geom_bvh *b, const geom_aabb *prim_boxes,
                                 const geom_aabb *queries, size_t m, geom_neighbors *out,
                                 int threads, geom_diag *diag)
{
    if (!b || !out || (m && !queries) || (b->prim_count && !prim_boxes))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                             "BVH box query: NULL argument");
    for (size_t q = 0; q < m; q++) {
        const geom_aabb *v = &queries[q];
        if (isnan(v->min.x) || isnan(v->min.y) || isnan(v->min.z) || isnan(v->max.x) ||
            isnan(v->max.y) || isnan(v->max.z))
            return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                                 "BVH box query: query box %zu has a NaN bound", q);
    }
    qctx c = {b, prim_boxes, queries};
    return geom__batch_rows(b->has_alloc ? &b->alloc : NULL, m, query_row, &c, threads, 0, out);
}
