/* Quadtree/octree queries: kNN and radius (point trees), box, frustum and
 * ordered ray traversal. Every traversal prunes with the nodes' tight
 * bounds, so the answers equal a brute-force scan's. */
#include "spatial/spatial_internal.h"

#include <string.h>

static const double *ibox(const geom_octree *t, size_t i)
{
    return t->ibox + 6 * i;
}

static uint32_t child_count(const geom_octree_node *nd)
{
    return nd->first_child == GEOM_INVALID_INDEX ? 0 : (uint32_t)__builtin_popcount(nd->child_mask);
}

/* ------------------------------------------------------------------ kNN */

static void knn_rec(const geom_octree *t, uint32_t id, const double q[3], geom__kbest *b)
{
    const geom_octree_node *nd = &t->nodes[id];
    for (uint32_t k = 0; k < nd->own_count; k++) {
        size_t i = nd->item_start + k;
        geom__kbest_insert(b, geom__d2(ibox(t, i), q), t->items[i]);
    }
    uint32_t nc = child_count(nd);
    if (!nc)
        return;
    uint32_t order[8];
    double d[8];
    for (uint32_t k = 0; k < nc; k++) {
        order[k] = nd->first_child + k;
        d[k] = geom__box_d2(&t->nodes[order[k]].bounds, q);
        for (uint32_t j = k; j > 0 && d[j] < d[j - 1]; j--) {
            double x = d[j]; d[j] = d[j - 1]; d[j - 1] = x;
            uint32_t y = order[j]; order[j] = order[j - 1]; order[j - 1] = y;
        }
    }
    for (uint32_t k = 0; k < nc; k++) {
        if (b->count == b->k && d[k] > b->d2[b->k - 1])
            break;
        knn_rec(t, order[k], q, b);
    }
}

static void knn_one(const void *ctx, const double q[3], geom__kbest *b)
{
    const geom_octree *t = ctx;
    if (b->k && t->node_count)
        knn_rec(t, 0, q, b);
}

geom_status geom_octree_knn(const geom_octree *t, const double *queries, size_t nq, size_t k,
                            uint32_t *index, double *distance, int threads, geom_diag *diag)
{
    if (!t || !t->points)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                             "kNN: NULL tree or a tree of elements (kNN needs points)");
    return geom__knn_batch(geom__octree_alloc(t), t, knn_one, t->dim, t->n, queries, nq, k, index,
                           distance, threads, diag);
}

/* --------------------------------------------------------------- radius */

typedef struct qctx {
    const geom_octree *t;
    const double *queries;
    double r, r2b;
    double lo[3], hi[3];
    const double *planes;
    geom_ray ray;
} qctx;

static int radius_rec(const geom_octree *t, uint32_t id, const double q[3], double r, double r2b,
                      geom__hits *h)
{
    const geom_octree_node *nd = &t->nodes[id];
    if (geom__box_d2(&nd->bounds, q) > r2b)
        return 0;
    for (uint32_t k = 0; k < nd->own_count; k++) {
        size_t i = nd->item_start + k;
        double d2 = geom__d2(ibox(t, i), q);
        if (d2 <= r2b && sqrt(d2) <= r && geom__hits_push(h, t->items[i], d2))
            return -1;
    }
    uint32_t nc = child_count(nd);
    for (uint32_t k = 0; k < nc; k++)
        if (radius_rec(t, nd->first_child + k, q, r, r2b, h))
            return -1;
    return 0;
}

static geom_status radius_row(const void *ctx, size_t qi, geom__hits *h)
{
    const qctx *c = ctx;
    double q[3];
    geom__load_query(c->queries, qi, c->t->dim, q);
    size_t from = h->n;
    if (c->t->node_count && radius_rec(c->t, 0, q, c->r, c->r2b, h))
        return GEOM_ERR_NOMEM;
    geom__hits_sort(h, from);
    return GEOM_OK;
}

geom_status geom_octree_radius(const geom_octree *t, const double *queries, size_t nq, double r,
                               geom_neighbors *out, int threads, geom_diag *diag)
{
    if (!t || !t->points || !out || (nq && !queries))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                             "radius query: NULL argument or a tree of elements");
    geom_status st0 = geom__radius_query_check(queries, nq, t->dim, r, diag);
    if (st0 != GEOM_OK)
        return st0;
    qctx c;
    memset(&c, 0, sizeof c);
    c.t = t;
    c.queries = queries;
    c.r = r;
    c.r2b = geom__r2_bound(r);
    geom_status st = geom__batch_rows(geom__octree_alloc(t), nq, radius_row, &c, threads, 1, out);
    if (st != GEOM_OK)
        return geom__diag_set(diag, st, "", 0, 0, "radius query: out of memory");
    return GEOM_OK;
}

/* ------------------------------------------------------------------ box */

static int box_meets(const double *lo, const double *hi, const double blo[3], const double bhi[3])
{
    return lo[0] <= bhi[0] && hi[0] >= blo[0] && lo[1] <= bhi[1] && hi[1] >= blo[1] &&
           lo[2] <= bhi[2] && hi[2] >= blo[2];
}

static int box_rec(const geom_octree *t, uint32_t id, const qctx *c, geom__hits *h)
{
    const geom_octree_node *nd = &t->nodes[id];
    double lo[3] = {nd->bounds.min.x, nd->bounds.min.y, nd->bounds.min.z};
    double hi[3] = {nd->bounds.max.x, nd->bounds.max.y, nd->bounds.max.z};
    if (!box_meets(lo, hi, c->lo, c->hi))
        return 0;
    for (uint32_t k = 0; k < nd->own_count; k++) {
        size_t i = nd->item_start + k;
        const double *b = ibox(t, i);
        if (box_meets(b, b + 3, c->lo, c->hi) && geom__hits_push(h, t->items[i], 0.0))
            return -1;
    }
    uint32_t nc = child_count(nd);
    for (uint32_t k = 0; k < nc; k++)
        if (box_rec(t, nd->first_child + k, c, h))
            return -1;
    return 0;
}

static geom_status box_row(const void *ctx, size_t qi, geom__hits *h)
{
    (void)qi;
    const qctx *c = ctx;
    if (c->t->node_count && box_rec(c->t, 0, c, h))
        return GEOM_ERR_NOMEM;
    geom__hits_sort(h, 0);
    return GEOM_OK;
}

geom_status geom_octree_box(const geom_octree *t, const double *lo, const double *hi,
                            geom_neighbors *out)
{
    if (!t || !lo || !hi || !out)
        return GEOM_ERR_INVALID_ARG;
    qctx c;
    memset(&c, 0, sizeof c);
    c.t = t;
    for (int k = 0; k < 3; k++) {
        c.lo[k] = k < t->dim ? lo[k] : 0.0;
        c.hi[k] = k < t->dim ? hi[k] : 0.0;
        if (isnan(c.lo[k]) || isnan(c.hi[k]))
            return GEOM_ERR_INVALID_ARG;
    }
    return geom__batch_rows(geom__octree_alloc(t), 1, box_row, &c, 1, 0, out);
}

/* -------------------------------------------------------------- frustum */

/* A box is outside when its corner farthest along a plane's normal is on
 * the negative side. */
static int box_outside(const double *lo, const double *hi, const double *planes)
{
    for (int p = 0; p < 6; p++) {
        const double *pl = planes + 4 * p;
        double x = pl[0] >= 0 ? hi[0] : lo[0];
        double y = pl[1] >= 0 ? hi[1] : lo[1];
        double z = pl[2] >= 0 ? hi[2] : lo[2];
        if (pl[0] * x + pl[1] * y + pl[2] * z + pl[3] < 0)
            return 1;
    }
    return 0;
}

static int frustum_rec(const geom_octree *t, uint32_t id, const qctx *c, geom__hits *h)
{
    const geom_octree_node *nd = &t->nodes[id];
    double lo[3] = {nd->bounds.min.x, nd->bounds.min.y, nd->bounds.min.z};
    double hi[3] = {nd->bounds.max.x, nd->bounds.max.y, nd->bounds.max.z};
    if (nd->item_total == 0 || box_outside(lo, hi, c->planes))
        return 0;
    for (uint32_t k = 0; k < nd->own_count; k++) {
        size_t i = nd->item_start + k;
        const double *b = ibox(t, i);
        if (!box_outside(b, b + 3, c->planes) && geom__hits_push(h, t->items[i], 0.0))
            return -1;
    }
    uint32_t nc = child_count(nd);
    for (uint32_t k = 0; k < nc; k++)
        if (frustum_rec(t, nd->first_child + k, c, h))
            return -1;
    return 0;
}

static geom_status frustum_row(const void *ctx, size_t qi, geom__hits *h)
{
    (void)qi;
    const qctx *c = ctx;
    if (c->t->node_count && frustum_rec(c->t, 0, c, h))
        return GEOM_ERR_NOMEM;
    geom__hits_sort(h, 0);
    return GEOM_OK;
}

geom_status geom_octree_frustum(const geom_octree *t, const double planes[24], geom_neighbors *out)
{
    if (!t || !planes || !out)
        return GEOM_ERR_INVALID_ARG;
    for (int i = 0; i < 24; i++)
        if (!isfinite(planes[i]))
            return GEOM_ERR_INVALID_ARG;
    qctx c;
    memset(&c, 0, sizeof c);
    c.t = t;
    c.planes = planes;
    return geom__batch_rows(geom__octree_alloc(t), 1, frustum_row, &c, 1, 0, out);
}

/* ------------------------------------------------------------------ ray */

/* The children a ray passes, front to back, by Revelles, Urena and Lastra,
 * "An efficient parametric algorithm for octree traversal" (2000): with the
 * ray mirrored to positive directions (mask a), the first child comes from
 * the entry plane (the largest entry parameter) compared with the midplane
 * parameters, and each next one from the exit plane of the current child
 * (the smallest exit parameter): crossing it sets that axis's bit, or leaves
 * the node when the bit is already set. Writes up to 4 octants (x = bit 0,
 * y = bit 1, z = bit 2); returns the count. Ties (a ray through an edge or
 * along a midplane) may skip a child: the caller visits every child the
 * conservative slab test accepts, so this only orders the traversal. */
static int revelles_order(const double lo[3], const double mid[3], const double hi[3],
                          const double o[3], const double d[3], int dim, uint32_t seq[4])
{
    double t0[3], tm[3], t1[3];
    uint32_t a = 0;
    for (int k = 0; k < 3; k++) {
        if (k >= dim) {
            t0[k] = -INFINITY, tm[k] = INFINITY, t1[k] = INFINITY;
            continue;
        }
        double ok = o[k], dk = d[k];
        if (dk < 0) {
            ok = lo[k] + hi[k] - ok; /* mirror about the cell centre */
            dk = -dk;
            a |= 1u << k;
        }
        /* In the mirrored frame the lower child along k is the one whose
         * octant bit differs from the original when mirrored. */
        double mk = (a >> k & 1) ? lo[k] + hi[k] - mid[k] : mid[k];
        if (dk > 0) {
            t0[k] = (lo[k] - ok) / dk;
            tm[k] = (mk - ok) / dk;
            t1[k] = (hi[k] - ok) / dk;
        } else {
            int in = ok >= lo[k] && ok <= hi[k];
            t0[k] = in ? -INFINITY : INFINITY;
            t1[k] = in ? INFINITY : -INFINITY;
            tm[k] = ok < mk ? INFINITY : -INFINITY;
        }
    }
    double ent = t0[0] > t0[1] ? t0[0] : t0[1];
    ent = ent > t0[2] ? ent : t0[2];
    double ex = t1[0] < t1[1] ? t1[0] : t1[1];
    ex = ex < t1[2] ? ex : t1[2];
    if (!(ent <= ex))
        return 0;
    /* First child: from the entry plane. */
    uint32_t cur = 0;
    int plane = t0[0] >= t0[1] && t0[0] >= t0[2] ? 0 : t0[1] >= t0[2] ? 1 : 2;
    for (int k = 0; k < 3; k++)
        if (k != plane && tm[k] < ent)
            cur |= 1u << k;
    int n = 0;
    for (;;) {
        seq[n++] = cur ^ a;
        if (n == 4)
            break;
        /* Exit plane of the current child. */
        int axis = -1;
        double best = INFINITY;
        for (int k = 0; k < dim; k++) {
            double te = (cur >> k & 1) ? t1[k] : tm[k];
            if (axis < 0 || te < best) {
                best = te;
                axis = k;
            }
        }
        if (axis < 0 || (cur >> axis & 1))
            break;
        cur |= 1u << axis;
    }
    return n;
}

static int ray_rec(const geom_octree *t, uint32_t id, const geom_ray *ray, geom__hits *h)
{
    const geom_octree_node *nd = &t->nodes[id];
    for (uint32_t k = 0; k < nd->own_count; k++) {
        size_t i = nd->item_start + k;
        const double *b = ibox(t, i);
        geom_aabb bx = {{b[0], b[1], b[2]}, {b[3], b[4], b[5]}};
        double t0;
        if (geom_ray_aabb(ray, bx, &t0, NULL) && geom__hits_push(h, t->items[i], t0))
            return -1;
    }
    uint32_t nc = child_count(nd);
    if (!nc)
        return 0;
    /* Children in Revelles order, then any other child the conservative slab
     * test accepts (grazing rays), each pruned by its tight bounds. */
    const geom_octree_node *c0 = &t->nodes[nd->first_child];
    uint32_t o0 = (uint32_t)__builtin_ctz(nd->child_mask);
    double lo[3] = {nd->cell.min.x, nd->cell.min.y, nd->cell.min.z};
    double hi[3] = {nd->cell.max.x, nd->cell.max.y, nd->cell.max.z};
    double clo[3] = {c0->cell.min.x, c0->cell.min.y, c0->cell.min.z};
    double chi[3] = {c0->cell.max.x, c0->cell.max.y, c0->cell.max.z};
    double mid[3], org[3] = {ray->origin.x, ray->origin.y, ray->origin.z};
    double dir[3] = {ray->dir.x, ray->dir.y, ray->dir.z};
    for (int k = 0; k < 3; k++)
        mid[k] = (o0 >> k & 1) ? clo[k] : chi[k]; /* the split plane, from a child's cell */
    uint32_t seq[4];
    int ns = revelles_order(lo, mid, hi, org, dir, t->dim, seq);
    uint32_t done = 0;
    for (int s = 0; s < ns; s++) {
        uint32_t oct = seq[s];
        if (!(nd->child_mask >> oct & 1))
            continue;
        done |= 1u << oct;
        uint32_t c = nd->first_child + (uint32_t)__builtin_popcount(nd->child_mask & ((1u << oct) - 1));
        if (t->nodes[c].item_total == 0 || !geom_ray_aabb(ray, t->nodes[c].bounds, NULL, NULL))
            continue;
        if (ray_rec(t, c, ray, h))
            return -1;
    }
    for (uint32_t oct = 0; oct < 8; oct++) {
        if (!(nd->child_mask >> oct & 1) || (done >> oct & 1))
            continue;
        uint32_t c = nd->first_child + (uint32_t)__builtin_popcount(nd->child_mask & ((1u << oct) - 1));
        if (t->nodes[c].item_total == 0 || !geom_ray_aabb(ray, t->nodes[c].bounds, NULL, NULL))
            continue;
        if (ray_rec(t, c, ray, h))
            return -1;
    }
    return 0;
}

static geom_status ray_row(const void *ctx, size_t qi, geom__hits *h)
{
    (void)qi;
    const qctx *c = ctx;
    if (c->t->node_count && geom_ray_aabb(&c->ray, c->t->nodes[0].bounds, NULL, NULL) &&
        ray_rec(c->t, 0, &c->ray, h))
        return GEOM_ERR_NOMEM;
    geom__hits_sort(h, 0); /* by entry parameter, then index */
    return GEOM_OK;
}

geom_status geom_octree_ray(const geom_octree *t, const geom_ray *ray, geom_neighbors *out)
{
    if (!t || !ray || !out)
        return GEOM_ERR_INVALID_ARG;
    qctx c;
    memset(&c, 0, sizeof c);
    c.t = t;
    c.ray = *ray;
    if (t->dim == 2) {
        c.ray.origin.z = 0;
        c.ray.dir.z = 0;
    }
    if (isnan(c.ray.origin.x) || isnan(c.ray.origin.y) || isnan(c.ray.origin.z) ||
        isnan(c.ray.dir.x) || isnan(c.ray.dir.y) || isnan(c.ray.dir.z) || isnan(c.ray.tmin) ||
        isnan(c.ray.tmax))
        return GEOM_ERR_INVALID_ARG;
    return geom__batch_rows(geom__octree_alloc(t), 1, ray_row, &c, 1, 2, out);
}
