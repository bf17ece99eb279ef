/*
 * geom_mesh_build's repairing path (build.c tries build_fast.c first).
 * Polygon soup -> manifold, consistently oriented half-edge mesh, with
 * repairs. Linear time apart from union-find (inverse Ackermann):
 *
 *  1. validate faces (out-of-range / repeated indices, < 3 vertices) with a
 *     per-vertex stamp;
 *  2. group the corners' undirected edges (min, max) by two stable counting
 *     sorts (by max, then by min): O(corners + vertices), no per-vertex
 *     search, so high valence costs nothing extra;
 *  3. orient: breadth-first over faces across edges used by exactly two faces
 *     (each connected set follows its first face); a conflict marks the
 *     component non-orientable;
 *  4. pair the uses of each undirected edge: two uses glue when their
 *     oriented directions are opposite. An edge used twice the same way (a
 *     non-orientable cut, or keep_orientation) glues nothing, and the face
 *     with more such edges (the later one on a tie) is reported detached.
 *     An edge used more than twice first glues nothing; with the fans of
 *     corners that the other edges make (as in step 6, on corners), it then
 *     glues each pair of its uses whose faces already meet around both of
 *     its vertices (the two ends of one fan at each end: two closed
 *     surfaces touching along the edge stay two closed surfaces, as CGAL's
 *     orient_polygon_soup makes them), then the first compatible pair of
 *     the uses left unless that would make two edges join the same two
 *     vertices. So no two output edges ever join the same two vertices
 *     (gluing compatible pairs in input order, as this once did, could: two
 *     tetrahedra on one edge with their faces interleaved became one
 *     surface with a doubled edge). The faces outside the edge's first
 *     glued pair ("kept") are reported detached: they end up on other
 *     copies of the edge's vertices (at least one of the two differs);
 *  5. one edge per pair or unpaired use; face cycles in oriented order;
 *  6. vertex fans: corners at a vertex linked through glued edges form
 *     paths or cycles (each edge use is glued at most once). Union-find over
 *     outgoing halfedges gives the fans; the fan holding the lowest halfedge
 *     keeps the input vertex index, each other fan gets a new vertex (copy of
 *     the input vertex's position, vertex_origin recording it). This splits
 *     non-manifold vertices and completes every detachment;
 *  7. boundary halfedges: each output vertex has at most one fan, hence at
 *     most one boundary gap, so next(b) = the boundary outgoing halfedge of
 *     b's target.
 * The result always satisfies every invariant geom_mesh_validate checks.
 *
 * Input errors (invalid faces without skip_invalid_faces, non-finite
 * coordinates, NULL arrays) are found before m is touched, so m keeps its
 * contents; running out of memory later leaves m empty.
 *
 * Report conventions: split_vertices counts the input vertices that
 * received more than one output vertex for any reason (so it includes the
 * endpoints of detached edges); added_vertices the copies made.
 */
#include "mesh/build_internal.h"

#define INV GEOM_INVALID_INDEX

enum { FL_DETACHED = 1, FL_NONMANIFOLD = 2 };

/*
 * Corner fans, for edges with more than two faces (step 4). Corner c is the
 * corner of face cf[c] that its ORIENTED boundary leaves: it goes from
 * src(c) to dst(c) (cv -> cb, or cb -> cv when the face is flipped). The
 * fan of c is the set of corners leaving src(c) that glued edges join into
 * one path or cycle around it (each outgoing and each incoming edge of a
 * corner is glued at most once), kept with union-find; a path has one
 * corner whose outgoing edge is unglued (out_end) and one whose incoming
 * edge is (in_end), a cycle none (INV).
 */
typedef struct cfans {
    const uint32_t *cf, *fs;
    const uint8_t *flip;
    uint32_t *partner;
    uint32_t *fan;     /* union-find parent, per corner */
    uint32_t *out_end; /* per fan root */
    uint32_t *in_end;  /* per fan root */
} cfans;

/* The corner after c in its face's oriented order (the one leaving dst(c)). */
static uint32_t cf_next(const cfans *k, uint32_t c)
{
    uint32_t f = k->cf[c], s = k->fs[f], e = k->fs[f + 1];
    if (!k->flip[f])
        return c + 1 < e ? c + 1 : s;
    return c > s ? c - 1 : e - 1;
}

/* The corner before c in its face's oriented order (its edge arrives at src(c)). */
static uint32_t cf_prev(const cfans *k, uint32_t c)
{
    uint32_t f = k->cf[c], s = k->fs[f], e = k->fs[f + 1];
    if (!k->flip[f])
        return c > s ? c - 1 : e - 1;
    return c + 1 < e ? c + 1 : s;
}

/* a's outgoing edge was glued to b's incoming edge (a and b leave the same
 * vertex): join their fans, or close the path into a cycle. */
static void cf_join(cfans *k, uint32_t a, uint32_t b)
{
    uint32_t ra = geom__uf_find(k->fan, a), rb = geom__uf_find(k->fan, b);
    if (ra == rb) {
        k->out_end[ra] = k->in_end[ra] = INV;
        return;
    }
    uint32_t in = k->in_end[ra], out = k->out_end[rb];
    geom__uf_union(k->fan, ra, rb);
    uint32_t r = geom__uf_find(k->fan, ra);
    k->in_end[r] = in;
    k->out_end[r] = out;
}

/* Glue the edges of corners x (src -> dst) and y (dst -> src). */
static void cf_glue(cfans *k, uint32_t x, uint32_t y)
{
    k->partner[x] = y;
    k->partner[y] = x;
    cf_join(k, x, cf_next(k, y)); /* around src(x) */
    cf_join(k, y, cf_next(k, x)); /* around dst(x) */
}

/* Class of fan root r once fans a0, a1 (around one vertex) and b0, b1
 * (around the other) are joined. */
static uint32_t cf_map(uint32_t r, uint32_t a0, uint32_t a1, uint32_t b0, uint32_t b1)
{
    if (r == a1)
        return a0;
    if (r == b1)
        return b0;
    return r;
}

/*
 * May the unglued uses x (src -> dst) and y (dst -> src) of an edge with
 * more than two faces be glued without making two edges join the same two
 * vertices? Only the vertices of the fans joined at src (x's and
 * next(y)'s) and at dst (next(x)'s and y's) change. The edges at them are
 * the new edge x-y, the other ends of the four fans (unglued uses) and the
 * fans' inner (glued) edges. Two inner edges never join the same two
 * vertices (before the glue they were in distinct fans, and an input edge
 * has at most one glued pair outside cycle fans), so it is enough to
 * compare the new edge and the other ends with each other, and each other
 * end with the glued pair of its own input edge (eglue, set in step 4c).
 * Two other ends that meet are uses of one input edge in opposite
 * directions, the two ends of one fan at each of its vertices once the
 * glue is made: the glue is allowed when they are glued too (closing those
 * fans); they are returned in close (2 per pair, *nclose pairs). Returns 1
 * when the glue is safe.
 */
static int glue_ok(const cfans *k, const uint32_t *eglue, uint32_t x, uint32_t y,
                   uint32_t close[4], int *nclose)
{
    uint32_t a0 = geom__uf_find(k->fan, x), a1 = geom__uf_find(k->fan, cf_next(k, y));
    uint32_t b0 = geom__uf_find(k->fan, cf_next(k, x)), b1 = geom__uf_find(k->fan, y);
    /* the other ends: in ends' unglued edge is the previous corner's */
    uint32_t w[5] = {x, INV, INV, INV, INV};
    int n = 1;
    *nclose = 0;
    if (a0 != a1) {
        w[n++] = k->in_end[a0] == INV ? INV : cf_prev(k, k->in_end[a0]);
        w[n++] = k->out_end[a1];
    }
    if (b0 != b1) {
        w[n++] = k->in_end[b1] == INV ? INV : cf_prev(k, k->in_end[b1]);
        w[n++] = k->out_end[b0];
    }
    /* vertex classes (unordered pairs) of the new edge (w[0] = x, whose
     * classes are those of the glued edge) and of each other end */
    uint32_t p[5][2];
    for (int e = 0; e < n; ++e) {
        if (w[e] == INV || (e > 0 && (w[e] == x || w[e] == y)))
            return 0; /* cannot happen: a path fan has both ends */
        p[e][0] = cf_map(geom__uf_find(k->fan, w[e]), a0, a1, b0, b1);
        p[e][1] = cf_map(geom__uf_find(k->fan, cf_next(k, w[e])), a0, a1, b0, b1);
        uint32_t g = e > 0 ? eglue[w[e]] : INV;
        if (g != INV) {
            uint32_t q0 = cf_map(geom__uf_find(k->fan, g), a0, a1, b0, b1);
            uint32_t q1 = cf_map(geom__uf_find(k->fan, cf_next(k, g)), a0, a1, b0, b1);
            if ((q0 == p[e][0] && q1 == p[e][1]) || (q0 == p[e][1] && q1 == p[e][0]))
                return 0;
        }
    }
    uint8_t paired[5] = {0, 0, 0, 0, 0};
    for (int e = 0; e < n; ++e)
        for (int f = e + 1; f < n; ++f) {
            if (w[e] == w[f]) {
                /* one use ending fans at both of its vertices: nothing meets */
                continue;
            }
            int same_fwd = p[e][0] == p[f][0] && p[e][1] == p[f][1];
            int same_rev = p[e][0] == p[f][1] && p[e][1] == p[f][0];
            if (!same_fwd && !same_rev)
                continue;
            /* the new edge meeting another use, a use meeting two, or two
             * uses the same way round: refuse */
            if (e == 0 || paired[e] || paired[f] || !same_rev || *nclose == 2)
                return 0;
            paired[e] = paired[f] = 1;
            close[2 * *nclose] = w[e];
            close[2 * *nclose + 1] = w[f];
            (*nclose)++;
        }
    return 1;
}

/* The state of one repairing build: the valid faces compacted into corners
 * (corner c: vertex cv[c], next vertex cb[c], face cf[c]; face f: corners
 * fs[f] .. fs[f + 1] - 1, input face forig[f]) and the per-step arrays. */
typedef struct rctx {
    geom__mesh_bscratch S;
    size_t nverts, nfaces, F, C;
    const uint32_t *face_sizes, *indices;
    geom_mesh_build_report *rep;
    uint8_t *face_ok;
    uint32_t *fs, *forig, *cv, *cb, *cf, *order, *tmp, *partner, *cnt;
    uint8_t *flip, *fflag;
} rctx;

#define LO(c) (x->cv[c] < x->cb[c] ? x->cv[c] : x->cb[c])
#define HI(c) (x->cv[c] < x->cb[c] ? x->cb[c] : x->cv[c])
#define ODIR(c) ((uint8_t)((x->cv[c] > x->cb[c]) ^ x->flip[x->cf[c]]))

/* The end of the run of corners in order[] from i on one undirected edge. */
static size_t edge_run(const rctx *x, size_t i)
{
    size_t j = i + 1;
    uint32_t lo = LO(x->order[i]), hi = HI(x->order[i]);
    while (j < x->C && LO(x->order[j]) == lo && HI(x->order[j]) == hi)
        ++j;
    return j;
}

/* 1. validate faces: counts F and C. */
static geom_status rp_validate(rctx *x, int skip, geom_diag *diag)
{
    uint32_t *stamp = geom__mesh_bs_alloc(&x->S, x->nverts, sizeof(uint32_t));
    x->face_ok = geom__mesh_bs_alloc(&x->S, x->nfaces, 1);
    if (!stamp || !x->face_ok)
        return GEOM_ERR_NOMEM;
    memset(stamp, 0xff, (x->nverts ? x->nverts : 1) * sizeof(uint32_t));
    const uint32_t *indices = x->indices;
    size_t off = 0;
    for (size_t f = 0; f < x->nfaces; ++f) {
        size_t n = x->face_sizes[f];
        const char *why = NULL;
        if (n > 0 && !indices)
            why = "NULL indices";
        else if (n < 3)
            why = "fewer than 3 vertices";
        else
            for (size_t k = 0; k < n; ++k) {
                uint32_t v = indices[off + k];
                if ((size_t)v >= x->nverts) {
                    why = "vertex index out of range";
                    break;
                }
                if (stamp[v] == (uint32_t)f) {
                    why = "repeated vertex";
                    break;
                }
                stamp[v] = (uint32_t)f;
            }
        x->face_ok[f] = why == NULL;
        if (why) {
            if (!skip)
                return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                                     "geom_mesh_build: face %zu: %s", f, why);
            geom__mesh_report_add(&x->rep->invalid_faces, x->rep->first_invalid_faces,
                                  (uint32_t)f);
        } else {
            x->F++;
            x->C += n;
        }
        off += n;
    }
    geom__mesh_bs_free_one(&x->S, stamp);
    if (x->C > (size_t)INT32_MAX - 2)
        return geom__diag_set(diag, GEOM_ERR_LIMIT, "", 0, 0,
                             "geom_mesh_build: more than 2^31 face corners");
    return GEOM_OK;
}

/* Compact the valid faces into corners. */
static geom_status rp_compact(rctx *x)
{
    const size_t F = x->F, C = x->C;
    geom__mesh_bscratch *S = &x->S;
    x->fs = geom__mesh_bs_alloc(S, F + 1, sizeof(uint32_t));
    x->forig = geom__mesh_bs_alloc(S, F, sizeof(uint32_t));
    x->cv = geom__mesh_bs_alloc(S, C, sizeof(uint32_t));
    x->cb = geom__mesh_bs_alloc(S, C, sizeof(uint32_t));
    x->cf = geom__mesh_bs_alloc(S, C, sizeof(uint32_t));
    x->order = geom__mesh_bs_alloc(S, C, sizeof(uint32_t));
    x->tmp = geom__mesh_bs_alloc(S, C, sizeof(uint32_t));
    x->partner = geom__mesh_bs_alloc(S, C, sizeof(uint32_t));
    x->flip = geom__mesh_bs_alloc(S, F, 1);
    x->fflag = geom__mesh_bs_alloc(S, F, 1);
    x->cnt = geom__mesh_bs_alloc(S, x->nverts + 1, sizeof(uint32_t));
    if (!x->fs || !x->forig || !x->cv || !x->cb || !x->cf || !x->order || !x->tmp ||
        !x->partner || !x->flip || !x->fflag || !x->cnt)
        return GEOM_ERR_NOMEM;
    size_t fo = 0, c = 0, off = 0;
    for (size_t f = 0; f < x->nfaces; ++f) {
        size_t n = x->face_sizes[f];
        if (x->face_ok[f]) {
            x->fs[fo] = (uint32_t)c;
            x->forig[fo] = (uint32_t)f;
            for (size_t k = 0; k < n; ++k) {
                x->cv[c + k] = x->indices[off + k];
                x->cb[c + k] = x->indices[off + (k + 1 < n ? k + 1 : 0)];
                x->cf[c + k] = (uint32_t)fo;
            }
            c += n;
            fo++;
        }
        off += n;
    }
    x->fs[F] = (uint32_t)C;
    memset(x->fflag, 0, F ? F : 1);
    memset(x->flip, 0, F ? F : 1);
    geom__mesh_bs_free_one(S, x->face_ok);
    x->face_ok = NULL;
    return GEOM_OK;
}

/* 2. sort corners by undirected edge (lo, hi): two stable counting sorts;
 * the uses of two-use edges are partners (for the orientation). */
static void rp_sort_edges(rctx *x)
{
    const size_t C = x->C, nverts = x->nverts;
    uint32_t *cnt = x->cnt, *tmp = x->tmp, *order = x->order;
    memset(cnt, 0, (nverts + 1) * sizeof(uint32_t));
    for (size_t c = 0; c < C; ++c)
        cnt[HI(c) + 1]++;
    for (size_t v = 0; v < nverts; ++v)
        cnt[v + 1] += cnt[v];
    for (size_t c = 0; c < C; ++c)
        tmp[cnt[HI(c)]++] = (uint32_t)c;
    memset(cnt, 0, (nverts + 1) * sizeof(uint32_t));
    for (size_t c = 0; c < C; ++c)
        cnt[LO(c) + 1]++;
    for (size_t v = 0; v < nverts; ++v)
        cnt[v + 1] += cnt[v];
    for (size_t i = 0; i < C; ++i) {
        uint32_t c = tmp[i];
        order[cnt[LO(c)]++] = c;
    }
    memset(x->partner, 0xff, C * sizeof(uint32_t));
    for (size_t i = 0; i < C;) {
        size_t j = edge_run(x, i);
        if (j - i == 2) {
            x->partner[order[i]] = order[i + 1];
            x->partner[order[i + 1]] = order[i];
        }
        i = j;
    }
}

/* 3. orientation by breadth-first search across two-face edges. */
static geom_status rp_orient(rctx *x)
{
    const size_t F = x->F;
    uint8_t *seen = geom__mesh_bs_alloc(&x->S, F, 1);
    uint32_t *queue = x->tmp; /* tmp is free again; F <= C */
    if (!seen)
        return GEOM_ERR_NOMEM;
    memset(seen, 0, F);
    for (size_t f0 = 0; f0 < F; ++f0) {
        if (seen[f0])
            continue;
        size_t qh = 0, qt = 0;
        int conflict = 0;
        seen[f0] = 1;
        queue[qt++] = (uint32_t)f0;
        while (qh < qt) {
            uint32_t f = queue[qh++];
            for (uint32_t c = x->fs[f]; c < x->fs[f + 1]; ++c) {
                uint32_t p = x->partner[c];
                if (p == INV)
                    continue;
                uint32_t g = x->cf[p];
                /* same input direction -> g must be flipped relative to f */
                uint8_t same = (x->cv[c] == x->cv[p]);
                uint8_t want = (uint8_t)(x->flip[f] ^ same);
                if (!seen[g]) {
                    seen[g] = 1;
                    x->flip[g] = want;
                    queue[qt++] = g;
                } else if (x->flip[g] != want)
                    conflict = 1;
            }
        }
        if (conflict)
            x->rep->nonorientable_components++;
    }
    geom__mesh_bs_free_one(&x->S, seen);
    return GEOM_OK;
}

/* 4. pair edge uses by oriented direction; *have_multi is set when an edge
 * has more than two uses (see rp_multi). */
static geom_status rp_pair(rctx *x, int *have_multi)
{
    const size_t F = x->F, C = x->C;
    uint32_t *partner = x->partner, *order = x->order, *cf = x->cf;
    uint8_t *fflag = x->fflag;
    /* conflicts per face (two-face edges used twice the same way), to
     * detach the face with more of them rather than its neighbour */
    uint32_t *nconf = geom__mesh_bs_alloc(&x->S, F, sizeof(uint32_t));
    if (!nconf)
        return GEOM_ERR_NOMEM;
    memset(nconf, 0, (F ? F : 1) * sizeof(uint32_t));
    for (size_t c = 0; c < C; ++c) {
        uint32_t p = partner[c];
        if (p != INV && ODIR(c) == ODIR(p))
            nconf[cf[c]]++;
    }
    memset(partner, 0xff, C * sizeof(uint32_t));
    *have_multi = 0;
    for (size_t i = 0; i < C;) {
        size_t j = edge_run(x, i);
        size_t k = j - i;
        if (k == 2) {
            uint32_t c0 = order[i], c1 = order[i + 1];
            if (ODIR(c0) != ODIR(c1)) {
                partner[c0] = c1;
                partner[c1] = c0;
            } else {
                /* twice the same way: cut (non-orientable, or kept orientation) */
                x->rep->nonmanifold_edges++;
                uint32_t f0 = cf[c0], f1 = cf[c1];
                fflag[f0] |= FL_NONMANIFOLD;
                fflag[f1] |= FL_NONMANIFOLD;
                fflag[nconf[f0] > nconf[f1] ? f0 : f1] |= FL_DETACHED;
            }
        } else if (k > 2) {
            x->rep->nonmanifold_edges++;
            *have_multi = 1;
            for (size_t r = i; r < j; ++r)
                fflag[cf[order[r]]] |= FL_NONMANIFOLD;
        }
        i = j;
    }
    geom__mesh_bs_free_one(&x->S, nconf);
    return GEOM_OK;
}

/* b.: glue each pair of an edge's uses that are the two ends of one fan at
 * each of the edge's vertices. */
static void rp_multi_close(rctx *x, cfans *K)
{
    const size_t C = x->C;
    const uint32_t *order = x->order, *cv = x->cv, *cb = x->cb, *cf = x->cf;
    const uint8_t *flip = x->flip;
    uint32_t *slot = x->tmp; /* free until step 6 */
    for (size_t c = 0; c < C; ++c)
        slot[c] = INV;
#define SRC(y) (flip[cf[y]] ? cb[y] : cv[y])
#define FAN_LO(y) geom__uf_find(K->fan, SRC(y) == LO(y) ? (y) : cf_next(K, (y)))
#define FAN_HI(y) geom__uf_find(K->fan, SRC(y) == LO(y) ? cf_next(K, (y)) : (y))
    for (size_t i = 0; i < C;) {
        size_t j = edge_run(x, i);
        if (j - i > 2) {
            /* a fan has two ends, so at most two uses share one */
            for (size_t r = i; r < j; ++r) {
                uint32_t u = order[r], fl = FAN_LO(u), y = slot[fl];
                if (y == INV)
                    slot[fl] = u;
                else if (x->partner[y] == INV && FAN_HI(y) == FAN_HI(u) && ODIR(u) != ODIR(y))
                    cf_glue(K, y, u); /* closes both fans: roots unchanged */
            }
            for (size_t r = i; r < j; ++r)
                slot[FAN_LO(order[r])] = INV;
        }
        i = j;
    }
#undef SRC
#undef FAN_LO
#undef FAN_HI
}

/* c.: on each edge, the first compatible pair of the uses left unglued. */
static void rp_multi_glue(rctx *x, cfans *K, uint32_t *eglue)
{
    const size_t C = x->C;
    const uint32_t *order = x->order;
    for (size_t i = 0; i < C;) {
        size_t j = edge_run(x, i);
        uint32_t a = INV, b = INV;
        for (size_t r = i; r < j && j - i > 2; ++r) {
            uint32_t u = order[r];
            if (x->partner[u] != INV)
                continue;
            if (ODIR(u) == 0 && a == INV)
                a = u;
            if (ODIR(u) == 1 && b == INV)
                b = u;
        }
        uint32_t close[4];
        int nclose = 0;
        if (j - i > 2 && a != INV && b != INV && glue_ok(K, eglue, a, b, close, &nclose)) {
            cf_glue(K, a, b);
            for (size_t r = i; r < j; ++r)
                eglue[order[r]] = a;
            for (int e = 0; e < nclose; ++e)
                cf_glue(K, close[2 * e], close[2 * e + 1]);
        }
        i = j;
    }
}

/* d.: the faces outside each such edge's first glued pair (with no pair:
 * outside its first use) are detached. */
static void rp_multi_detach(rctx *x)
{
    const size_t C = x->C;
    const uint32_t *order = x->order, *cf = x->cf, *partner = x->partner;
    uint8_t *fflag = x->fflag;
    for (size_t i = 0; i < C;) {
        size_t j = edge_run(x, i);
        if (j - i > 2) {
            uint32_t keep_c = order[i];
            for (size_t r = i; r < j; ++r)
                if (partner[order[r]] != INV) {
                    keep_c = order[r];
                    break;
                }
            fflag[cf[keep_c]] |= 0x80;
            if (partner[keep_c] != INV)
                fflag[cf[partner[keep_c]]] |= 0x80;
            for (size_t r = i; r < j; ++r)
                if (!(fflag[cf[order[r]]] & 0x80))
                    fflag[cf[order[r]]] |= FL_DETACHED;
            for (size_t r = i; r < j; ++r)
                fflag[cf[order[r]]] &= (uint8_t)~0x80u;
        }
        i = j;
    }
}

/*
 * Edges with more than two faces. Nothing of them is glued yet; then
 *  a. fans of corners from the two-face edges glued above;
 *  b. each pair of an edge's uses that are the two ends of one fan at each
 *     of the edge's vertices is glued (their faces already meet around both
 *     vertices: e.g. two closed surfaces touching along the edge). This
 *     only closes fans into cycles, and leaving such a pair unglued would
 *     give two edges between the same two vertices;
 *  c. on each edge, in edge order, the first compatible pair of the uses b
 *     left unglued (the first use of each direction) is glued unless that
 *     would make two edges join the same two vertices (checked exactly: see
 *     glue_ok; at most one such pair per edge, which glue_ok relies on);
 *  d. on each such edge, the faces outside its first glued pair (with no
 *     pair: outside its first use) are reported detached.
 */
static geom_status rp_multi(rctx *x)
{
    const size_t C = x->C;
    geom__mesh_bscratch *S = &x->S;
    cfans K = {x->cf,
               x->fs,
               x->flip,
               x->partner,
               geom__mesh_bs_alloc(S, C, sizeof(uint32_t)),
               geom__mesh_bs_alloc(S, C, sizeof(uint32_t)),
               geom__mesh_bs_alloc(S, C, sizeof(uint32_t))};
    uint32_t *eglue = geom__mesh_bs_alloc(S, C, sizeof(uint32_t));
    if (!K.fan || !K.out_end || !K.in_end || !eglue)
        return GEOM_ERR_NOMEM;
    for (size_t c = 0; c < C; ++c) {
        K.fan[c] = K.out_end[c] = K.in_end[c] = (uint32_t)c;
        eglue[c] = INV;
    }
    /* a. */
    for (size_t c = 0; c < C; ++c)
        if (x->partner[c] != INV && x->partner[c] > c) {
            uint32_t p = x->partner[c];
            cf_join(&K, (uint32_t)c, cf_next(&K, p));
            cf_join(&K, p, cf_next(&K, (uint32_t)c));
        }
    rp_multi_close(x, &K);
    rp_multi_glue(x, &K, eglue);
    rp_multi_detach(x);
    geom__mesh_bs_free_one(S, eglue);
    geom__mesh_bs_free_one(S, K.in_end);
    geom__mesh_bs_free_one(S, K.out_end);
    geom__mesh_bs_free_one(S, K.fan);
    return GEOM_OK;
}

#undef ODIR
#undef LO
#undef HI

/* 5. edges and face cycles; the mesh's storage is made here. */
static geom_status rp_emit(rctx *x, geom_mesh *m, size_t *Hp)
{
    const size_t F = x->F;
    uint32_t *he_of = x->order; /* order is no longer needed */
    size_t H = geom__mesh_number_edges(x->C, x->partner, he_of);
    geom_status st = geom__mesh_build_storage(m, x->nverts, H, F);
    if (st != GEOM_OK)
        return st;
    memset(m->v_he, 0xff, x->nverts * sizeof(uint32_t));
    for (size_t f = 0; f < F; ++f) {
        uint32_t s = x->fs[f], e = x->fs[f + 1];
        m->face_origin[f] = x->forig[f];
        m->face_flipped[f] = x->flip[f];
        for (uint32_t c = s; c < e; ++c)
            if (x->partner[c] == INV)
                m->he_face[he_of[c] ^ 1u] = INV; /* boundary halfedge */
        if (!x->flip[f]) {
            for (uint32_t c = s; c < e; ++c) {
                uint32_t h = he_of[c], cn = c + 1 < e ? c + 1 : s;
                m->he_vertex[h] = x->cb[c];
                m->he_face[h] = (uint32_t)f;
                geom__mesh_link(m, h, he_of[cn]);
            }
            m->f_he[f] = he_of[e - 1];
        } else {
            for (uint32_t c = s; c < e; ++c) {
                uint32_t h = he_of[c], cp = c > s ? c - 1 : e - 1;
                m->he_vertex[h] = x->cv[c];
                m->he_face[h] = (uint32_t)f;
                geom__mesh_link(m, h, he_of[cp]);
            }
            m->f_he[f] = he_of[s];
        }
    }
    *Hp = H;
    return GEOM_OK;
}

/* 6. vertex fans (union-find over interior outgoing halfedges): the fan
 * holding the lowest halfedge keeps the input vertex, each other fan gets a
 * copy; then the halfedges' targets and the outgoing halfedges. */
static geom_status rp_fans(rctx *x, geom_mesh *m, size_t H, const double *xyz,
                           uint8_t **vsplitp)
{
    const size_t nverts = x->nverts;
    uint32_t *par = geom__mesh_bs_alloc(&x->S, H, sizeof(uint32_t));
    uint8_t *vsplit = geom__mesh_bs_alloc(&x->S, nverts, 1);
    if (!par || !vsplit)
        return GEOM_ERR_NOMEM;
    *vsplitp = vsplit;
    memset(vsplit, 0, nverts ? nverts : 1);
    for (size_t h = 0; h < H; ++h)
        par[h] = (uint32_t)h;
    for (size_t h = 0; h < H; ++h) {
        if (m->he_face[h] == INV)
            continue;
        uint32_t g = m->he_prev[h] ^ 1u; /* ccw neighbour around from(h) */
        if (m->he_face[g] != INV)
            geom__uf_union(par, (uint32_t)h, g);
    }
    for (size_t h = 0; h < H; ++h)
        if (m->he_face[h] != INV)
            par[h] = geom__uf_find(par, (uint32_t)h);
    /* roots are the smallest members: assign output vertices in place */
    uint32_t *new_orig = x->tmp; /* added vertices <= fans <= C */
    size_t added = 0;
    for (size_t h = 0; h < H; ++h) {
        if (m->he_face[h] == INV)
            continue;
        uint32_t r = par[h];
        if (r == h) {
            uint32_t v = m->he_vertex[m->he_prev[h]]; /* input vertex h leaves */
            if (m->v_he[v] == INV && !vsplit[v]) {
                vsplit[v] = 1; /* 1: taken by its first fan */
                par[h] = v;
            } else {
                if (nverts + added >= (size_t)UINT32_MAX - 1)
                    return GEOM_ERR_LIMIT;
                vsplit[v] = 2; /* several fans */
                new_orig[added] = v;
                par[h] = (uint32_t)(nverts + added);
                added++;
            }
        } else
            par[h] = par[r];
    }
    geom_status st;
    /* xyz may be m's own positions (geom__mesh_adopt_positions): growing
     * keeps them in place in the new block */
    int adopted = xyz == geom__mesh_pos(m);
    if (added && (st = geom__mesh_resize(m, nverts + added, H, x->F)) != GEOM_OK)
        return st;
    double *pos = geom__mesh_pos(m);
    if (adopted)
        xyz = pos;
    else if (nverts)
        memcpy(pos, xyz, 3 * nverts * sizeof(double));
    for (size_t v = 0; v < nverts; ++v)
        m->vertex_origin[v] = (uint32_t)v;
    for (size_t i = 0; i < added; ++i) {
        uint32_t o = new_orig[i];
        m->vertex_origin[nverts + i] = o;
        memcpy(pos + 3 * (nverts + i), xyz + 3 * (size_t)o, 3 * sizeof(double));
    }
    /* targets: every interior halfedge is prev of one interior halfedge,
     * every boundary halfedge is opposite of one */
    for (size_t h = 0; h < H; ++h) {
        if (m->he_face[h] == INV)
            continue;
        uint32_t v = par[h];
        m->he_vertex[m->he_prev[h]] = v;
        if (m->he_face[h ^ 1u] == INV)
            m->he_vertex[h ^ 1u] = v;
        if (m->v_he[v] == INV)
            m->v_he[v] = (uint32_t)h;
    }
    x->rep->added_vertices = added;
    geom__mesh_bs_free_one(&x->S, par);
    return GEOM_OK;
}

/* 7. boundary cycles: each output vertex has at most one boundary gap. */
static void rp_boundary(geom_mesh *m, size_t H)
{
    for (size_t b = 1; b < H; b += 2) {
        if (m->he_face[b] != INV)
            continue;
        m->v_he[m->he_vertex[b ^ 1u]] = (uint32_t)b;
    }
    for (size_t b = 1; b < H; b += 2) {
        if (m->he_face[b] != INV)
            continue;
        geom__mesh_link(m, (uint32_t)b, m->v_he[m->he_vertex[b]]);
    }
}

static void rp_report(const rctx *x, const uint8_t *vsplit)
{
    geom_mesh_build_report *rep = x->rep;
    size_t n_nmf = 0;
    for (size_t v = 0; v < x->nverts; ++v) {
        if (vsplit[v] == 2)
            geom__mesh_report_add(&rep->split_vertices, rep->first_split_vertices, (uint32_t)v);
        if (vsplit[v] == 0)
            rep->isolated_vertices++;
    }
    for (size_t f = 0; f < x->F; ++f) {
        uint32_t o = x->forig[f];
        if (x->flip[f])
            geom__mesh_report_add(&rep->flipped_faces, rep->first_flipped_faces, o);
        if (x->fflag[f] & FL_DETACHED)
            geom__mesh_report_add(&rep->detached_faces, rep->first_detached_faces, o);
        if ((x->fflag[f] & FL_NONMANIFOLD) && n_nmf < GEOM_MESH_REPORT_FIRST)
            rep->first_nonmanifold_faces[n_nmf++] = o;
    }
}

geom_status geom__mesh_build_repair(geom_mesh *m, size_t nverts, const double *xyz,
                                    size_t nfaces, const uint32_t *face_sizes,
                                    const uint32_t *indices, int skip, int keep,
                                    geom_mesh_build_report *rep, geom_diag *diag)
{
    rctx x;
    memset(&x, 0, sizeof x);
    x.S.a = &m->alloc;
    x.nverts = nverts;
    x.nfaces = nfaces;
    x.face_sizes = face_sizes;
    x.indices = indices;
    x.rep = rep;
    int have_multi = 0, touched = 0;
    size_t H = 0;
    uint8_t *vsplit = NULL;
    geom_status st;
    if ((st = rp_validate(&x, skip, diag)) != GEOM_OK || (st = rp_compact(&x)) != GEOM_OK)
        goto out;
    rp_sort_edges(&x);
    if ((!keep && x.F && (st = rp_orient(&x)) != GEOM_OK) ||
        (st = rp_pair(&x, &have_multi)) != GEOM_OK || (have_multi && (st = rp_multi(&x)) != GEOM_OK))
        goto out;
    touched = 1;
    if ((st = rp_emit(&x, m, &H)) != GEOM_OK || (st = rp_fans(&x, m, H, xyz, &vsplit)) != GEOM_OK)
        goto out;
    rp_boundary(m, H);
    rp_report(&x, vsplit);
out:
    if (st != GEOM_OK && touched)
        geom__mesh_clear_all(m);
    geom__mesh_bs_free_all(&x.S);
    return st;
}
