/* CSG by combining the children's hit lists (Roth, "Ray Casting for
 * Modeling Solids", CGIP 1982): each child's hits over the whole line,
 * sorted, give its inside intervals; walking both lists keeps the inside
 * state of each child, and a hit is reported where the combined state
 * changes. Hits at the same t are processed together, so coincident faces
 * (a difference cut flush with a face) give no zero-length slivers.
 * Early outs: a bounded child's list ends at r->tmax (it is outside at
 * -inf, so later events cannot change the state before tmax), and a child whose bounding box the line
 * misses is not queried: an empty operand decides the result (nothing, or
 * the other child's own hits in the caller's mode). */
#include "ray/ray_internal.h"

static int combine(int op, int a, int b)
{
    switch (op) {
    case GEOM_RAY_CSG_UNION: return a || b;
    case GEOM_RAY_CSG_INTERSECTION: return a && b;
    default: return a && !b;
    }
}

/* 1 when the line misses child id's bounding box (so the child has no hits). */
static int line_misses(const geom_ray_scene *s, uint32_t id, const geom_ray *line)
{
    const geom__ray_node *c = &s->nodes[id];
    return c->bounded && !geom_ray_aabb(line, c->box, NULL, NULL);
}

geom_status geom__ray_csg(const geom_ray_scene *s, const geom__ray_node *nd, const geom_ray *r, int mode,
                          geom__rhits *out)
{
    geom__rhits la, lb;
    geom_ray full = *r;
    geom_status st;
    size_t i = 0, j = 0;
    int ina, inb, state;
    full.tmin = -INFINITY;
    full.tmax = r->tmax;
    {
        int ma = line_misses(s, nd->a, &full), mb = line_misses(s, nd->b, &full);
        if (ma || mb) {
            if (nd->op == GEOM_RAY_CSG_UNION) {
                if (ma && mb) return GEOM_OK;
                return geom__ray_node_query(s, ma ? nd->b : nd->a, r, mode, out);
            }
            if (ma || nd->op == GEOM_RAY_CSG_INTERSECTION) return GEOM_OK;
            return geom__ray_node_query(s, nd->a, r, mode, out); /* a - nothing */
        }
    }
    geom__rhits_init(&la, out->alloc);
    geom__rhits_init(&lb, out->alloc);
    /* A bounded child starts outside at -inf, so its events after r->tmax
     * are not needed; an unbounded one may leave after tmax: whole line. */
    full.tmax = s->nodes[nd->a].bounded ? r->tmax : INFINITY;
    st = geom__ray_node_query(s, nd->a, &full, GEOM__RAY_ALL, &la);
    full.tmax = s->nodes[nd->b].bounded ? r->tmax : INFINITY;
    if (st == GEOM_OK) st = geom__ray_node_query(s, nd->b, &full, GEOM__RAY_ALL, &lb);
    if (st != GEOM_OK) goto done;
    geom__rhits_sort(&la, 0);
    geom__rhits_sort(&lb, 0);
    /* Inside at -inf: a list that starts by leaving started inside. */
    ina = la.n > 0 && !la.h[0].enter;
    inb = lb.n > 0 && !lb.h[0].enter;
    state = combine(nd->op, ina, inb);
    while (i < la.n || j < lb.n) {
        double t;
        const geom_ray_hit *cand = NULL;
        int cand_b = 0, ns;
        if (j >= lb.n || (i < la.n && la.h[i].t <= lb.h[j].t)) t = la.h[i].t;
        else t = lb.h[j].t;
        /* Every event at this t. */
        {
            size_t i0 = i, j0 = j;
            while (i < la.n && la.h[i].t == t) { ina = la.h[i].enter; i++; }
            while (j < lb.n && lb.h[j].t == t) { inb = lb.h[j].enter; j++; }
            ns = combine(nd->op, ina, inb);
            if (ns == state) continue;
            /* The event whose own crossing matches the combined change. */
            {
                size_t k;
                for (k = i0; k < i && !cand; k++)
                    if (la.h[k].enter == ns) cand = &la.h[k];
                for (k = j0; k < j && !cand; k++) {
                    int eff = nd->op == GEOM_RAY_CSG_DIFFERENCE ? !lb.h[k].enter : lb.h[k].enter;
                    if (eff == ns) { cand = &lb.h[k]; cand_b = 1; }
                }
                if (!cand) {
                    cand_b = !(i > i0);
                    cand = cand_b ? &lb.h[j0] : &la.h[i0];
                }
            }
        }
        state = ns;
        if (t >= r->tmin && t <= r->tmax) {
            geom_ray_hit *h = geom__rhits_push(out);
            if (!h) { st = GEOM_ERR_NOMEM; goto done; }
            *h = *cand;
            h->enter = ns;
            if (cand_b && nd->op == GEOM_RAY_CSG_DIFFERENCE) {
                h->ng = geom_vec3_neg(h->ng);
                h->ns = geom_vec3_neg(h->ns);
            }
            if (mode != GEOM__RAY_ALL) break;
        }
    }
done:
    geom__rhits_free(&la);
    geom__rhits_free(&lb);
    return st;
}
