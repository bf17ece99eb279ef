/*
 * Constrained Delaunay triangulation in the plane with the exact
 * predicates of core (geom_orient2d, geom_incircle): incremental
 * Bowyer-Watson insertion inside a super triangle (cavities never cross a
 * constrained edge, Chew 1989), segment recovery by edge flips (Sloan
 * 1993), and inside/outside classification by the parity of constrained
 * edges crossed from the super triangle. Used by the trimmed-face mesher.
 */
#include "step/cdt.h"

#include <string.h>

void geom__cdt_free(geom__cdt *c)
{
    geom__free(c->a, c->xy, c->capp * 2 * sizeof(double));
    geom__free(c->a, c->tri, c->capt * sizeof(geom__cdt_tri));
    geom__free(c->a, c->stack, c->capstack * sizeof(int32_t));
    geom__free(c->a, c->mark, c->capmark * sizeof(uint32_t));
    memset(c, 0, sizeof *c);
}

static geom_status add_point(geom__cdt *c, double x, double y, int32_t *id)
{
    geom_status st = geom__grow(c->a, (void **)&c->xy, &c->capp, c->np + 1, 2 * sizeof(double));
    if (st)
        return st;
    c->xy[2 * c->np] = x;
    c->xy[2 * c->np + 1] = y;
    *id = (int32_t)c->np++;
    return GEOM_OK;
}

static geom_status new_tri(geom__cdt *c, int32_t a, int32_t b, int32_t d, int32_t *out)
{
    geom_status st = geom__grow(c->a, (void **)&c->tri, &c->capt, c->nt + 1, sizeof(geom__cdt_tri));
    if (st)
        return st;
    st = geom__grow(c->a, (void **)&c->mark, &c->capmark, c->nt + 1, sizeof(uint32_t));
    if (st)
        return st;
    geom__cdt_tri *t = &c->tri[c->nt];
    t->v[0] = a;
    t->v[1] = b;
    t->v[2] = d;
    t->n[0] = t->n[1] = t->n[2] = -1;
    t->con[0] = t->con[1] = t->con[2] = 0;
    t->dead = 0;
    t->inside = 1;
    c->mark[c->nt] = 0;
    *out = (int32_t)c->nt++;
    return GEOM_OK;
}

geom_status geom__cdt_init(geom__cdt *c, const geom_allocator *a, const double box[4])
{
    memset(c, 0, sizeof *c);
    c->a = a;
    double cx = 0.5 * (box[0] + box[1]), cy = 0.5 * (box[2] + box[3]);
    double r = fmax(box[1] - box[0], box[3] - box[2]);
    if (!(r > 0))
        r = 1;
    r *= 16;
    int32_t i0, i1, i2, t;
    geom_status st;
    if ((st = add_point(c, cx - 2 * r, cy - r, &i0)) || (st = add_point(c, cx + 2 * r, cy - r, &i1)) ||
        (st = add_point(c, cx, cy + 2 * r, &i2)) || (st = new_tri(c, i0, i1, i2, &t)))
        return st;
    c->last = 0;
    return GEOM_OK;
}

static const double *P(const geom__cdt *c, int32_t i)
{
    return c->xy + 2 * i;
}

/* index k of vertex v in triangle t, or -1 */
static int vidx(const geom__cdt_tri *t, int32_t v)
{
    for (int k = 0; k < 3; k++)
        if (t->v[k] == v)
            return k;
    return -1;
}

/* The edge of t2 that is (a, b) in either direction: the index of its
 * opposite vertex, or -1. */
static int edge_of(const geom__cdt_tri *t2, int32_t a, int32_t b)
{
    for (int k = 0; k < 3; k++) {
        int32_t p = t2->v[(k + 1) % 3], q = t2->v[(k + 2) % 3];
        if ((p == a && q == b) || (p == b && q == a))
            return k;
    }
    return -1;
}

/* Walk to a live triangle containing q (on its boundary allowed). */
int32_t geom__cdt_locate(geom__cdt *c, const double q[2])
{
    int32_t t = c->last;
    if (t < 0 || (size_t)t >= c->nt || c->tri[t].dead) {
        t = -1;
        for (size_t k = c->nt; k-- > 0;)
            if (!c->tri[k].dead) {
                t = (int32_t)k;
                break;
            }
        if (t < 0)
            return -1;
    }
    size_t steps = 0, limit = 4 * c->nt + 16;
    while (steps++ < limit) {
        const geom__cdt_tri *T = &c->tri[t];
        int moved = 0;
        for (int k = 0; k < 3; k++) {
            const double *a = P(c, T->v[(k + 1) % 3]), *b = P(c, T->v[(k + 2) % 3]);
            if (geom_orient2d(a, b, q) < 0 && T->n[k] >= 0) {
                t = T->n[k];
                moved = 1;
                break;
            }
        }
        if (!moved)
            return t;
    }
    /* the walk cycled (it cannot on a Delaunay triangulation, but be safe) */
    for (size_t k = 0; k < c->nt; k++) {
        const geom__cdt_tri *T = &c->tri[k];
        if (T->dead)
            continue;
        if (geom_orient2d(P(c, T->v[0]), P(c, T->v[1]), q) >= 0 &&
            geom_orient2d(P(c, T->v[1]), P(c, T->v[2]), q) >= 0 &&
            geom_orient2d(P(c, T->v[2]), P(c, T->v[0]), q) >= 0)
            return (int32_t)k;
    }
    return -1;
}

geom_status geom__cdt_insert(geom__cdt *c, double x, double y, int32_t *vid)
{
    double q[2] = {x, y};
    *vid = -1;
    int32_t t0 = geom__cdt_locate(c, q);
    if (t0 < 0)
        return GEOM_ERR_DOMAIN;
    for (int k = 0; k < 3; k++) {
        const double *p = P(c, c->tri[t0].v[k]);
        if (p[0] == x && p[1] == y) {
            *vid = c->tri[t0].v[k];
            return GEOM_ERR_DEGENERATE; /* duplicate */
        }
    }
    /* cavity: triangles whose circumcircle holds q, connected to t0
     * without crossing constrained edges */
    c->stamp++;
    size_t ns = 0;
    geom_status st = geom__grow(c->a, (void **)&c->stack, &c->capstack, 1, sizeof(int32_t));
    if (st)
        return st;
    c->stack[ns++] = t0;
    c->mark[t0] = c->stamp;
    size_t head = 0;
    while (head < ns) {
        int32_t t = c->stack[head++];
        for (int k = 0; k < 3; k++) {
            int32_t u = c->tri[t].n[k];
            if (u < 0 || c->tri[t].con[k] || c->mark[u] == c->stamp)
                continue;
            const geom__cdt_tri *U = &c->tri[u];
            if (geom_incircle(P(c, U->v[0]), P(c, U->v[1]), P(c, U->v[2]), q) > 0) {
                if ((st = geom__grow(c->a, (void **)&c->stack, &c->capstack, ns + 1, sizeof(int32_t))))
                    return st;
                c->stack[ns++] = u;
                c->mark[u] = c->stamp;
            }
        }
    }
    /* the boundary edges of the cavity must all see q strictly on their
     * left, else q is on a constrained edge: refuse */
    for (size_t i = 0; i < ns; i++) {
        const geom__cdt_tri *T = &c->tri[c->stack[i]];
        for (int k = 0; k < 3; k++) {
            int32_t u = T->n[k];
            if (u >= 0 && c->mark[u] == c->stamp)
                continue;
            if (geom_orient2d(P(c, T->v[(k + 1) % 3]), P(c, T->v[(k + 2) % 3]), q) <= 0)
                return GEOM_ERR_DEGENERATE;
        }
    }
    int32_t id;
    if ((st = add_point(c, x, y, &id)))
        return st;
    size_t first_new = c->nt;
    /* new triangles (a, b, q) on each boundary edge */
    size_t nc = ns;
    for (size_t i = 0; i < nc; i++) {
        int32_t t = c->stack[i];
        for (int k = 0; k < 3; k++) {
            int32_t u = c->tri[t].n[k];
            if (u >= 0 && c->mark[u] == c->stamp)
                continue;
            int32_t a = c->tri[t].v[(k + 1) % 3], b = c->tri[t].v[(k + 2) % 3];
            uint8_t con = c->tri[t].con[k], in = c->tri[t].inside;
            int32_t nt;
            if ((st = new_tri(c, a, b, id, &nt)))
                return st;
            c->mark[nt] = 0;
            c->tri[nt].n[2] = u;
            c->tri[nt].con[2] = con;
            c->tri[nt].inside = in;
            if (u >= 0) {
                int e = edge_of(&c->tri[u], a, b);
                if (e >= 0)
                    c->tri[u].n[e] = nt;
            }
        }
    }
    for (size_t i = 0; i < nc; i++)
        c->tri[c->stack[i]].dead = 1;
    /* link the new triangles around q: (a, b, q) meets (b, x, q) along
     * (b, q) and (y, a, q) along (q, a) */
    for (size_t i = first_new; i < c->nt; i++) {
        geom__cdt_tri *T = &c->tri[i];
        for (size_t j = first_new; j < c->nt; j++) {
            if (i == j)
                continue;
            const geom__cdt_tri *U = &c->tri[j];
            if (U->v[0] == T->v[1]) /* U starts where T's base ends: edge (b, q) */
                T->n[0] = (int32_t)j;
            if (U->v[1] == T->v[0]) /* edge (q, a) */
                T->n[1] = (int32_t)j;
        }
    }
    c->last = (int32_t)(c->nt - 1);
    *vid = id;
    return GEOM_OK;
}

static int crosses(const geom__cdt *c, int32_t a, int32_t b, int32_t p, int32_t q)
{
    if (p == a || p == b || q == a || q == b)
        return 0;
    double o1 = geom_orient2d(P(c, a), P(c, b), P(c, p)), o2 = geom_orient2d(P(c, a), P(c, b), P(c, q));
    double o3 = geom_orient2d(P(c, p), P(c, q), P(c, a)), o4 = geom_orient2d(P(c, p), P(c, q), P(c, b));
    return ((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0));
}

static void mark_edge(geom__cdt *c, int32_t t, int k)
{
    c->tri[t].con[k] = 1;
    int32_t u = c->tri[t].n[k];
    if (u >= 0) {
        int e = edge_of(&c->tri[u], c->tri[t].v[(k + 1) % 3], c->tri[t].v[(k + 2) % 3]);
        if (e >= 0)
            c->tri[u].con[e] = 1;
    }
}

/* Flip the edge opposite vertex k of t with its neighbour. */
static void flip(geom__cdt *c, int32_t t, int k)
{
    geom__cdt_tri *T = &c->tri[t];
    int32_t u = T->n[k];
    geom__cdt_tri *U = &c->tri[u];
    int32_t r = T->v[k], p = T->v[(k + 1) % 3], q = T->v[(k + 2) % 3];
    int e = edge_of(U, p, q);
    int32_t s = U->v[e];
    /* T = (r, p, q), U = (s, q, p); new T = (r, p, s), U = (s, q, r) */
    int32_t nT_rp = T->n[(k + 2) % 3]; /* across (r, p) */
    int32_t nT_qr = T->n[(k + 1) % 3]; /* across (q, r) */
    uint8_t cT_rp = T->con[(k + 2) % 3], cT_qr = T->con[(k + 1) % 3];
    int ie = vidx(U, s);
    int32_t nU_sq = U->n[(ie + 2) % 3]; /* across (s, q) */
    int32_t nU_ps = U->n[(ie + 1) % 3]; /* across (p, s) */
    uint8_t cU_sq = U->con[(ie + 2) % 3], cU_ps = U->con[(ie + 1) % 3];
    T->v[0] = r, T->v[1] = p, T->v[2] = s;
    U->v[0] = s, U->v[1] = q, U->v[2] = r;
    /* T: n[0] across (p, s), n[1] across (s, r) = U, n[2] across (r, p) */
    T->n[0] = nU_ps, T->con[0] = cU_ps;
    T->n[1] = u, T->con[1] = 0;
    T->n[2] = nT_rp, T->con[2] = cT_rp;
    /* U: n[0] across (q, r), n[1] across (r, s) = T, n[2] across (s, q) */
    U->n[0] = nT_qr, U->con[0] = cT_qr;
    U->n[1] = t, U->con[1] = 0;
    U->n[2] = nU_sq, U->con[2] = cU_sq;
    if (nU_ps >= 0) {
        int e2 = edge_of(&c->tri[nU_ps], p, s);
        if (e2 >= 0)
            c->tri[nU_ps].n[e2] = t;
    }
    if (nT_qr >= 0) {
        int e2 = edge_of(&c->tri[nT_qr], q, r);
        if (e2 >= 0)
            c->tri[nT_qr].n[e2] = u;
    }
}

geom_status geom__cdt_constrain(geom__cdt *c, int32_t a, int32_t b, int depth)
{
    if (a == b)
        return GEOM_OK;
    if (depth > 64)
        return GEOM_ERR_LIMIT;
    for (size_t iter = 0; iter < 100000; iter++) {
        int32_t ft = -1;
        int fk = -1, found_edge = 0;
        for (size_t t = 0; t < c->nt && !found_edge; t++) {
            const geom__cdt_tri *T = &c->tri[t];
            if (T->dead)
                continue;
            int ia = vidx(T, a);
            if (ia >= 0 && vidx(T, b) >= 0) {
                mark_edge(c, (int32_t)t, 3 - ia - vidx(T, b));
                found_edge = 1;
                break;
            }
            /* a vertex exactly on the segment: split there */
            if (ia >= 0) {
                for (int k = 1; k < 3; k++) {
                    int32_t v = T->v[(ia + k) % 3];
                    if (v == b)
                        continue;
                    const double *pa = P(c, a), *pb = P(c, b), *pv = P(c, v);
                    if (geom_orient2d(pa, pb, pv) == 0 &&
                        (pv[0] - pa[0]) * (pb[0] - pa[0]) + (pv[1] - pa[1]) * (pb[1] - pa[1]) > 0 &&
                        (pv[0] - pb[0]) * (pa[0] - pb[0]) + (pv[1] - pb[1]) * (pa[1] - pb[1]) > 0) {
                        geom_status st = geom__cdt_constrain(c, a, v, depth + 1);
                        if (st)
                            return st;
                        return geom__cdt_constrain(c, v, b, depth + 1);
                    }
                }
            }
            if (ft >= 0)
                continue;
            for (int k = 0; k < 3; k++) {
                if (crosses(c, a, b, T->v[(k + 1) % 3], T->v[(k + 2) % 3]) && T->n[k] >= 0) {
                    /* flippable: the quad is strictly convex */
                    const geom__cdt_tri *U = &c->tri[T->n[k]];
                    int e = edge_of(U, T->v[(k + 1) % 3], T->v[(k + 2) % 3]);
                    if (e < 0 || T->con[k])
                        continue;
                    int32_t r = T->v[k], s = U->v[e];
                    double o1 = geom_orient2d(P(c, r), P(c, s), P(c, T->v[(k + 1) % 3]));
                    double o2 = geom_orient2d(P(c, r), P(c, s), P(c, T->v[(k + 2) % 3]));
                    if ((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) {
                        ft = (int32_t)t;
                        fk = k;
                        break;
                    }
                }
            }
        }
        if (found_edge)
            return GEOM_OK;
        if (ft < 0)
            return GEOM_ERR_DEGENERATE; /* crosses another constraint, or stuck */
        flip(c, ft, fk);
    }
    return GEOM_ERR_LIMIT;
}

void geom__cdt_classify(geom__cdt *c)
{
    for (size_t t = 0; t < c->nt; t++)
        c->tri[t].inside = 2; /* unknown */
    size_t ns = 0;
    for (size_t t = 0; t < c->nt; t++) {
        geom__cdt_tri *T = &c->tri[t];
        if (T->dead)
            continue;
        if (T->v[0] < 3 || T->v[1] < 3 || T->v[2] < 3) {
            T->inside = 0;
            if (geom__grow(c->a, (void **)&c->stack, &c->capstack, ns + 1, sizeof(int32_t)))
                return;
            c->stack[ns++] = (int32_t)t;
        }
    }
    /* breadth-first by layers: same side across free edges, flip across
     * constrained ones (the first label reached wins) */
    size_t head = 0;
    while (head < ns) {
        int32_t t = c->stack[head++];
        for (int k = 0; k < 3; k++) {
            int32_t u = c->tri[t].n[k];
            if (u < 0 || c->tri[u].dead || c->tri[u].inside != 2)
                continue;
            if (c->tri[t].con[k])
                continue;
            c->tri[u].inside = c->tri[t].inside;
            if (geom__grow(c->a, (void **)&c->stack, &c->capstack, ns + 1, sizeof(int32_t)))
                return;
            c->stack[ns++] = u;
        }
        if (head == ns) {
            /* cross constraints from everything labelled so far */
            for (size_t i = 0; i < ns; i++) {
                int32_t w = c->stack[i];
                for (int k = 0; k < 3; k++) {
                    int32_t u = c->tri[w].n[k];
                    if (u < 0 || c->tri[u].dead || c->tri[u].inside != 2 || !c->tri[w].con[k])
                        continue;
                    c->tri[u].inside = (uint8_t)!c->tri[w].inside;
                    if (geom__grow(c->a, (void **)&c->stack, &c->capstack, ns + 1, sizeof(int32_t)))
                        return;
                    c->stack[ns++] = u;
                }
            }
        }
    }
    for (size_t t = 0; t < c->nt; t++)
        if (c->tri[t].inside == 2)
            c->tri[t].inside = 0;
}
