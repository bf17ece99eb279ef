/* Triangle meshes through the spatial module's BVH: conservative slab tests
 * (Ize, "Robust BVH Ray Traversal", JCGT 2013: the far distance widened by
 * 2 gamma(3), the near one narrowed alike) with ordered traversal, and the
 * watertight triangle test (triangle.c). */
#include "ray/ray_internal.h"
#include "geom/spatial.h"

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
        m->tv = geom_alloc(alloc, (np ? np : 1) * 9 * sizeof(double));
        m->tid = geom_alloc(alloc, (np ? np : 1) * sizeof(uint32_t));
        if (!m->tv || !m->tid) return GEOM_ERR_NOMEM;
        for (i = 0; i < np; i++) {
            const uint32_t *t = m->tri + 3 * (size_t)pr[i];
            int k;
            for (k = 0; k < 3; k++) memcpy(m->tv + 9 * i + 3 * k, m->pos + 3 * (size_t)t[k], 3 * sizeof(double));
            m->tid[i] = pr[i];
        }
    }
    return GEOM_OK;
}

void geom__ray_mesh_free(geom__tmesh *m, const geom_allocator *alloc)
{
    if (!m) return;
    if (m->bvh) {
        size_t np = 0;
        geom_bvh_prim_indices(m->bvh, &np);
        if (m->tv) geom_free(alloc, m->tv, (np ? np : 1) * 9 * sizeof(double));
        if (m->tid) geom_free(alloc, m->tid, (np ? np : 1) * sizeof(uint32_t));
    }
    geom_bvh_destroy(m->bvh);
    geom_free(alloc, m->pos, 3 * m->nv * sizeof(double));
    if (m->nrm) geom_free(alloc, m->nrm, 3 * m->nv * sizeof(double));
    geom_free(alloc, m->tri, 3 * m->nt * sizeof(uint32_t));
    if (m->face) geom_free(alloc, m->face, m->nt * sizeof(uint32_t));
    geom_free(alloc, m, sizeof *m);
}

size_t geom__ray_mesh_bvh_nodes(const geom__tmesh *m, size_t *bytes)
{
    size_t n = 0;
    if (!m->bvh) { if (bytes) *bytes = 0; return 0; }
    geom_bvh_nodes(m->bvh, &n);
    if (bytes) *bytes = geom_bvh_bytes(m->bvh);
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

static void fill(const geom__tmesh *m, const geom_ray *r, uint32_t ti, double t, const double *b,
                 geom_ray_hit *h)
{
    const uint32_t *tv = m->tri + 3 * (size_t)ti;
    geom__tri_fill(r, m->pos + 3 * tv[0], m->pos + 3 * tv[1], m->pos + 3 * tv[2], t, b, h);
    h->prim = m->face ? m->face[ti] : ti;
    if (m->nrm) {
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

geom_status geom__ray_mesh(const geom__tmesh *m, const geom_ray *r, int mode, geom__rhits *out)
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
            uint32_t i;
            for (i = 0; i < nd->count; i++) {
                const double *tvp = m->tv + 9 * (size_t)(nd->index + i);
                uint32_t ti;
                double t, bc[3];
                if (!geom__wbw_test(&w, tvp, tvp + 3, tvp + 6, r->tmin, tmax, &t, bc)) continue;
                ti = m->tid[nd->index + i];
                if (mode == GEOM__RAY_ALL) {
                    geom_ray_hit *h = geom__rhits_push(out);
                    if (!h) return GEOM_ERR_NOMEM;
                    fill(m, r, ti, t, bc, h);
                } else {
                    if (best == GEOM_INVALID_INDEX || t < best_t || (t == best_t && ti < best)) {
                        best = ti;
                        best_t = t;
                        memcpy(best_b, bc, sizeof bc);
                        tmax = t;
                    }
                    if (mode == GEOM__RAY_ANY) goto done;
                }
            }
        }
    }
done:
    if (mode != GEOM__RAY_ALL && best != GEOM_INVALID_INDEX) {
        geom_ray_hit *h = geom__rhits_push(out);
        if (!h) return GEOM_ERR_NOMEM;
        fill(m, r, best, best_t, best_b, h);
    }
    return GEOM_OK;
}
