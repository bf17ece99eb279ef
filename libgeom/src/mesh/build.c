/*
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
#include "mesh/mesh_internal.h"

#include <assert.h>
#include <stdio.h>

#define INV GEOM_INVALID_INDEX

typedef struct bscratch {
    const geom_allocator *a;
    void *p[24];
    size_t sz[24];
    int n;
} bscratch;

static void *bs_alloc(bscratch *s, size_t n, size_t es)
{
    size_t b;
    if (geom_size_mul(n ? n : 1, es, &b) != GEOM_OK)
        return NULL;
    void *p = geom_alloc(s->a, b);
    if (p) {
        s->p[s->n] = p;
        s->sz[s->n] = b;
        s->n++;
    }
    return p;
}

static void bs_free_all(bscratch *s)
{
    while (s->n > 0) {
        s->n--;
        geom_free(s->a, s->p[s->n], s->sz[s->n]);
    }
}

static void report_add(size_t *count, uint32_t *first, uint32_t idx)
{
    if (*count < GEOM_MESH_REPORT_FIRST)
        first[*count] = idx;
    (*count)++;
}

/* core's union-find (core/unionfind.c) */
static uint32_t uf_find(uint32_t *parent, uint32_t x) { return geom__uf_find(parent, x); }
static void uf_union(uint32_t *parent, uint32_t a, uint32_t b) { geom__uf_union(parent, a, b); }

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
    uint32_t ra = uf_find(k->fan, a), rb = uf_find(k->fan, b);
    if (ra == rb) {
        k->out_end[ra] = k->in_end[ra] = INV;
        return;
    }
    uint32_t in = k->in_end[ra], out = k->out_end[rb];
    uf_union(k->fan, ra, rb);
    uint32_t r = uf_find(k->fan, ra);
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
    uint32_t a0 = uf_find(k->fan, x), a1 = uf_find(k->fan, cf_next(k, y));
    uint32_t b0 = uf_find(k->fan, cf_next(k, x)), b1 = uf_find(k->fan, y);
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
        p[e][0] = cf_map(uf_find(k->fan, w[e]), a0, a1, b0, b1);
        p[e][1] = cf_map(uf_find(k->fan, cf_next(k, w[e])), a0, a1, b0, b1);
        uint32_t g = e > 0 ? eglue[w[e]] : INV;
        if (g != INV) {
            uint32_t q0 = cf_map(uf_find(k->fan, g), a0, a1, b0, b1);
            uint32_t q1 = cf_map(uf_find(k->fan, cf_next(k, g)), a0, a1, b0, b1);
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

/* Step 5's numbering, shared by both paths: one edge per glued pair or
 * unglued use, in the order of its first corner; corner c becomes halfedge
 * he_of[c] (2e for the first use, 2e + 1 for its partner). Returns the
 * halfedge count. */
static size_t number_edges(size_t C, const uint32_t *partner, uint32_t *he_of)
{
    size_t E = 0;
    for (size_t c = 0; c < C; ++c)
        he_of[c] = INV;
    for (size_t c = 0; c < C; ++c) {
        if (he_of[c] != INV)
            continue;
        he_of[c] = (uint32_t)(2 * E);
        if (partner[c] != INV)
            he_of[partner[c]] = (uint32_t)(2 * E + 1);
        E++;
    }
    return 2 * E;
}

/* The repairing build (steps 1-7 above). Arguments are checked by the
 * caller; rep is zeroed. */
static geom_status build_repair(geom_mesh *m, size_t nverts, const double *xyz, size_t nfaces,
                                const uint32_t *face_sizes, const uint32_t *indices, int skip,
                                int keep, geom_mesh_build_report *rep, geom_diag *diag)
{
    bscratch S;
    memset(&S, 0, sizeof S);
    S.a = &m->alloc;
    geom_status st = GEOM_OK;

    /* ---- 1. validate faces */
    uint32_t *stamp = bs_alloc(&S, nverts, sizeof(uint32_t));
    uint8_t *face_ok = bs_alloc(&S, nfaces, 1);
    if (!stamp || !face_ok) {
        st = GEOM_ERR_NOMEM;
        goto out;
    }
    for (size_t i = 0; i < nverts; ++i)
        stamp[i] = INV;
    size_t F = 0, C = 0, off = 0;
    for (size_t f = 0; f < nfaces; ++f) {
        size_t n = face_sizes[f];
        const char *why = NULL;
        if (n > 0 && !indices)
            why = "NULL indices";
        else if (n < 3)
            why = "fewer than 3 vertices";
        else
            for (size_t k = 0; k < n; ++k) {
                uint32_t v = indices[off + k];
                if ((size_t)v >= nverts) {
                    why = "vertex index out of range";
                    break;
                }
                if (stamp[v] == (uint32_t)f) {
                    why = "repeated vertex";
                    break;
                }
                stamp[v] = (uint32_t)f;
            }
        face_ok[f] = why == NULL;
        if (why) {
            if (!skip) {
                st = geom_diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                                   "geom_mesh_build: face %zu: %s", f, why);
                goto out;
            }
            report_add(&rep->invalid_faces, rep->first_invalid_faces, (uint32_t)f);
        } else {
            F++;
            C += n;
        }
        off += n;
    }
    if (C > (size_t)INT32_MAX - 2) {
        st = geom_diag_set(diag, GEOM_ERR_LIMIT, "", 0, 0,
                           "geom_mesh_build: more than 2^31 face corners");
        goto out;
    }

    /* ---- compact valid faces: corner vertex cv, next vertex cb, face cf */
    uint32_t *fs = bs_alloc(&S, F + 1, sizeof(uint32_t));
    uint32_t *forig = bs_alloc(&S, F, sizeof(uint32_t));
    uint32_t *cv = bs_alloc(&S, C, sizeof(uint32_t));
    uint32_t *cb = bs_alloc(&S, C, sizeof(uint32_t));
    uint32_t *cf = bs_alloc(&S, C, sizeof(uint32_t));
    uint32_t *order = bs_alloc(&S, C, sizeof(uint32_t));
    uint32_t *tmp = bs_alloc(&S, C, sizeof(uint32_t));
    uint32_t *partner = bs_alloc(&S, C, sizeof(uint32_t));
    uint8_t *flip = bs_alloc(&S, F, 1);
    uint8_t *fflag = bs_alloc(&S, F, 1);
    uint32_t *cnt = bs_alloc(&S, nverts + 1, sizeof(uint32_t));
    if (!fs || !forig || !cv || !cb || !cf || !order || !tmp || !partner || !flip || !fflag ||
        !cnt) {
        st = GEOM_ERR_NOMEM;
        goto out;
    }
    {
        size_t fo = 0, c = 0;
        off = 0;
        for (size_t f = 0; f < nfaces; ++f) {
            size_t n = face_sizes[f];
            if (face_ok[f]) {
                fs[fo] = (uint32_t)c;
                forig[fo] = (uint32_t)f;
                for (size_t k = 0; k < n; ++k) {
                    cv[c + k] = indices[off + k];
                    cb[c + k] = indices[off + (k + 1 < n ? k + 1 : 0)];
                    cf[c + k] = (uint32_t)fo;
                }
                c += n;
                fo++;
            }
            off += n;
        }
        fs[F] = (uint32_t)C;
    }
    memset(fflag, 0, F ? F : 1);

    /* ---- 2. sort corners by undirected edge (lo, hi): counting sorts */
#define LO(c) (cv[c] < cb[c] ? cv[c] : cb[c])
#define HI(c) (cv[c] < cb[c] ? cb[c] : cv[c])
    {
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
    }
    for (size_t c = 0; c < C; ++c)
        partner[c] = INV;
    for (size_t i = 0; i < C;) {
        size_t j = i + 1;
        uint32_t lo = LO(order[i]), hi = HI(order[i]);
        while (j < C && LO(order[j]) == lo && HI(order[j]) == hi)
            ++j;
        if (j - i == 2) {
            partner[order[i]] = order[i + 1];
            partner[order[i + 1]] = order[i];
        }
        i = j;
    }

    /* ---- 3. orientation by BFS across two-face edges */
    memset(flip, 0, F ? F : 1);
    if (!keep && F) {
        uint8_t *seen = bs_alloc(&S, F, 1);
        uint32_t *queue = tmp; /* tmp is free again; F <= C */
        if (!seen) {
            st = GEOM_ERR_NOMEM;
            goto out;
        }
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
                for (uint32_t c = fs[f]; c < fs[f + 1]; ++c) {
                    uint32_t p = partner[c];
                    if (p == INV)
                        continue;
                    uint32_t g = cf[p];
                    /* same input direction -> g must be flipped relative to f */
                    uint8_t same = (cv[c] == cv[p]);
                    uint8_t want = (uint8_t)(flip[f] ^ same);
                    if (!seen[g]) {
                        seen[g] = 1;
                        flip[g] = want;
                        queue[qt++] = g;
                    } else if (flip[g] != want)
                        conflict = 1;
                }
            }
            if (conflict)
                rep->nonorientable_components++;
        }
    }

    /* ---- 4. pair edge uses by oriented direction */
#define ODIR(c) ((uint8_t)((cv[c] > cb[c]) ^ flip[cf[c]]))
    /* conflicts per face (two-face edges used twice the same way), to
     * detach the face with more of them rather than its neighbour */
    uint32_t *nconf = bs_alloc(&S, F, sizeof(uint32_t));
    if (!nconf) {
        st = GEOM_ERR_NOMEM;
        goto out;
    }
    memset(nconf, 0, (F ? F : 1) * sizeof(uint32_t));
    for (size_t c = 0; c < C; ++c) {
        uint32_t p = partner[c];
        if (p != INV && ODIR(c) == ODIR(p))
            nconf[cf[c]]++;
    }
    for (size_t c = 0; c < C; ++c)
        partner[c] = INV;
    int have_multi = 0;
    for (size_t i = 0; i < C;) {
        size_t j = i + 1;
        uint32_t lo = LO(order[i]), hi = HI(order[i]);
        while (j < C && LO(order[j]) == lo && HI(order[j]) == hi)
            ++j;
        size_t k = j - i;
        if (k == 2) {
            uint32_t c0 = order[i], c1 = order[i + 1];
            if (ODIR(c0) != ODIR(c1)) {
                partner[c0] = c1;
                partner[c1] = c0;
            } else {
                /* twice the same way: cut (non-orientable, or kept orientation) */
                rep->nonmanifold_edges++;
                uint32_t f0 = cf[c0], f1 = cf[c1];
                fflag[f0] |= FL_NONMANIFOLD;
                fflag[f1] |= FL_NONMANIFOLD;
                fflag[nconf[f0] > nconf[f1] ? f0 : f1] |= FL_DETACHED;
            }
        } else if (k > 2) {
            rep->nonmanifold_edges++;
            have_multi = 1;
            for (size_t r = i; r < j; ++r)
                fflag[cf[order[r]]] |= FL_NONMANIFOLD;
        }
        i = j;
    }
    if (have_multi) {
        /* Edges with more than two faces. Nothing of them is glued yet; then
         *  a. fans of corners from the two-face edges glued above;
         *  b. each pair of an edge's uses that are the two ends of one fan
         *     at each of the edge's vertices is glued (their faces already
         *     meet around both vertices: e.g. two closed surfaces touching
         *     along the edge). This only closes fans into cycles, and
         *     leaving such a pair unglued would give two edges between the
         *     same two vertices;
         *  c. on each edge, in edge order, the first compatible pair of the
         *     uses b left unglued (the first use of each direction) is glued
         *     unless that would make two edges join the same two vertices
         *     (checked exactly: see glue_ok; at most one such pair per edge,
         *     which glue_ok relies on);
         *  d. on each such edge, the faces outside its first glued pair
         *     (with no pair: outside its first use) are reported detached. */
        cfans K = {cf, fs, flip, partner, bs_alloc(&S, C, sizeof(uint32_t)),
                   bs_alloc(&S, C, sizeof(uint32_t)), bs_alloc(&S, C, sizeof(uint32_t))};
        uint32_t *eglue = bs_alloc(&S, C, sizeof(uint32_t));
        uint32_t *slot = tmp; /* free until step 6 */
        if (!K.fan || !K.out_end || !K.in_end || !eglue) {
            st = GEOM_ERR_NOMEM;
            goto out;
        }
        for (size_t c = 0; c < C; ++c) {
            K.fan[c] = K.out_end[c] = K.in_end[c] = (uint32_t)c;
            slot[c] = eglue[c] = INV;
        }
        /* a. */
        for (size_t c = 0; c < C; ++c)
            if (partner[c] != INV && partner[c] > c) {
                uint32_t p = partner[c];
                cf_join(&K, (uint32_t)c, cf_next(&K, p));
                cf_join(&K, p, cf_next(&K, (uint32_t)c));
            }
        /* b.: the fans of use x at the edge's lower and higher vertex */
#define SRC(x) (flip[cf[x]] ? cb[x] : cv[x])
#define FAN_LO(x) uf_find(K.fan, SRC(x) == LO(x) ? (x) : cf_next(&K, (x)))
#define FAN_HI(x) uf_find(K.fan, SRC(x) == LO(x) ? cf_next(&K, (x)) : (x))
        for (size_t i = 0; i < C;) {
            size_t j = i + 1;
            while (j < C && LO(order[j]) == LO(order[i]) && HI(order[j]) == HI(order[i]))
                ++j;
            if (j - i > 2) {
                /* a fan has two ends, so at most two uses share one */
                for (size_t r = i; r < j; ++r) {
                    uint32_t x = order[r], fl = FAN_LO(x), y = slot[fl];
                    if (y == INV)
                        slot[fl] = x;
                    else if (partner[y] == INV && FAN_HI(y) == FAN_HI(x) && ODIR(x) != ODIR(y))
                        cf_glue(&K, y, x); /* closes both fans: roots unchanged */
                }
                for (size_t r = i; r < j; ++r)
                    slot[FAN_LO(order[r])] = INV;
            }
            i = j;
        }
#undef SRC
#undef FAN_LO
#undef FAN_HI
        /* c. */
        for (size_t i = 0; i < C;) {
            size_t j = i + 1;
            while (j < C && LO(order[j]) == LO(order[i]) && HI(order[j]) == HI(order[i]))
                ++j;
            uint32_t a = INV, b = INV;
            for (size_t r = i; r < j && j - i > 2; ++r) {
                uint32_t x = order[r];
                if (partner[x] != INV)
                    continue;
                if (ODIR(x) == 0 && a == INV)
                    a = x;
                if (ODIR(x) == 1 && b == INV)
                    b = x;
            }
            uint32_t close[4];
            int nclose = 0;
            if (j - i > 2 && a != INV && b != INV &&
                glue_ok(&K, eglue, a, b, close, &nclose)) {
                cf_glue(&K, a, b);
                for (size_t r = i; r < j; ++r)
                    eglue[order[r]] = a;
                for (int e = 0; e < nclose; ++e)
                    cf_glue(&K, close[2 * e], close[2 * e + 1]);
            }
            i = j;
        }
        /* d. */
        for (size_t i = 0; i < C;) {
            size_t j = i + 1;
            while (j < C && LO(order[j]) == LO(order[i]) && HI(order[j]) == HI(order[i]))
                ++j;
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
#undef ODIR
#undef LO
#undef HI

    /* ---- 5. edges and face cycles */
    uint32_t *he_of = order; /* order is no longer needed */
    size_t H = number_edges(C, partner, he_of);

    geom_mesh__clear_all(m);
    if ((st = geom_mesh__resize(m, nverts, H, F)) != GEOM_OK ||
        (st = geom_mesh__ensure_origins(m)) != GEOM_OK)
        goto fail_mesh;
    for (size_t f = 0; f < F; ++f) {
        uint32_t s = fs[f], e = fs[f + 1];
        m->face_origin[f] = forig[f];
        m->face_flipped[f] = flip[f];
        if (!flip[f]) {
            for (uint32_t c = s; c < e; ++c) {
                uint32_t h = he_of[c], cn = c + 1 < e ? c + 1 : s;
                m->he_vertex[h] = cb[c];
                m->he_face[h] = (uint32_t)f;
                geom_mesh__link(m, h, he_of[cn]);
            }
            m->f_he[f] = he_of[e - 1];
        } else {
            for (uint32_t c = s; c < e; ++c) {
                uint32_t h = he_of[c], cp = c > s ? c - 1 : e - 1;
                m->he_vertex[h] = cv[c];
                m->he_face[h] = (uint32_t)f;
                geom_mesh__link(m, h, he_of[cp]);
            }
            m->f_he[f] = he_of[s];
        }
    }

    /* ---- 6. vertex fans (union-find over interior outgoing halfedges) */
    uint32_t *par = bs_alloc(&S, H, sizeof(uint32_t));
    uint8_t *vsplit = bs_alloc(&S, nverts, 1);
    if (!par || !vsplit) {
        st = GEOM_ERR_NOMEM;
        goto fail_mesh;
    }
    memset(vsplit, 0, nverts ? nverts : 1);
    for (size_t h = 0; h < H; ++h)
        par[h] = (uint32_t)h;
    for (size_t h = 0; h < H; ++h) {
        if (m->he_face[h] == INV)
            continue;
        uint32_t g = m->he_prev[h] ^ 1u; /* ccw neighbour around from(h) */
        if (m->he_face[g] != INV)
            uf_union(par, (uint32_t)h, g);
    }
    for (size_t h = 0; h < H; ++h)
        if (m->he_face[h] != INV)
            par[h] = uf_find(par, (uint32_t)h);
    /* roots are the smallest members: assign output vertices in place */
    uint32_t *new_orig = tmp; /* added vertices <= fans <= C */
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
                if (nverts + added >= (size_t)UINT32_MAX - 1) {
                    st = GEOM_ERR_LIMIT;
                    goto fail_mesh;
                }
                vsplit[v] = 2; /* several fans */
                new_orig[added] = v;
                par[h] = (uint32_t)(nverts + added);
                added++;
            }
        } else
            par[h] = par[r];
    }
    if ((st = geom_mesh__resize(m, nverts + added, H, F)) != GEOM_OK)
        goto fail_mesh;
    {
        double *pos = geom_mesh__pos(m);
        if (nverts)
            memcpy(pos, xyz, 3 * nverts * sizeof(double));
        for (size_t v = 0; v < nverts; ++v)
            m->vertex_origin[v] = (uint32_t)v;
        for (size_t i = 0; i < added; ++i) {
            uint32_t o = new_orig[i];
            m->vertex_origin[nverts + i] = o;
            memcpy(pos + 3 * (nverts + i), xyz + 3 * (size_t)o, 3 * sizeof(double));
        }
    }
    /* targets: every interior halfedge is prev of one interior halfedge,
     * every boundary halfedge is opposite of one */
    for (size_t h = 0; h < H; ++h) {
        if (m->he_face[h] == INV)
            continue;
        uint32_t x = par[h];
        m->he_vertex[m->he_prev[h]] = x;
        if (m->he_face[h ^ 1u] == INV)
            m->he_vertex[h ^ 1u] = x;
        if (m->v_he[x] == INV)
            m->v_he[x] = (uint32_t)h;
    }

    /* ---- 7. boundary cycles */
    for (size_t b = 1; b < H; b += 2) {
        if (m->he_face[b] != INV)
            continue;
        m->v_he[m->he_vertex[b ^ 1u]] = (uint32_t)b;
    }
    for (size_t b = 1; b < H; b += 2) {
        if (m->he_face[b] != INV)
            continue;
        geom_mesh__link(m, (uint32_t)b, m->v_he[m->he_vertex[b]]);
    }

    /* ---- report */
    rep->added_vertices = added;
    size_t n_nmf = 0;
    for (size_t v = 0; v < nverts; ++v) {
        if (vsplit[v] == 2)
            report_add(&rep->split_vertices, rep->first_split_vertices, (uint32_t)v);
        if (vsplit[v] == 0)
            rep->isolated_vertices++;
    }
    for (size_t f = 0; f < F; ++f) {
        if (flip[f])
            report_add(&rep->flipped_faces, rep->first_flipped_faces, forig[f]);
        if (fflag[f] & FL_DETACHED)
            report_add(&rep->detached_faces, rep->first_detached_faces, forig[f]);
        if ((fflag[f] & FL_NONMANIFOLD) && n_nmf < GEOM_MESH_REPORT_FIRST)
            rep->first_nonmanifold_faces[n_nmf++] = forig[f];
    }
    goto out;

fail_mesh:
    geom_mesh__clear_all(m);
out:
    bs_free_all(&S);
    return st;
}

/* ------------------------------------------------------------ trusted path */

/* Returned by build_trusted when the input needs the repairing path. */
#define NEEDS_REPAIR 1

/*
 * The build for input known to be an oriented manifold mesh: the same
 * element numbering as build_repair gives it (edges in the order of their
 * first corner, faces and vertices as input), without the orientation and
 * non-manifold passes. Edge uses are paired through per-vertex lists of
 * outgoing corners; a directed edge used twice, an edge used the same way
 * twice or a vertex whose faces form more than one fan returns NEEDS_REPAIR
 * (m is then cleared), as does an index out of range, a face with fewer
 * than 3 or repeated vertices.
 */
static int build_trusted(geom_mesh *m, size_t nverts, const double *xyz, size_t nfaces,
                         const uint32_t *face_sizes, const uint32_t *indices,
                         geom_mesh_build_report *rep, geom_status *stp)
{
    bscratch S;
    memset(&S, 0, sizeof S);
    S.a = &m->alloc;
    geom_status st = GEOM_OK;
    int repair = 0;
    size_t C = 0;
    for (size_t f = 0; f < nfaces; ++f) {
        if (face_sizes[f] < 3)
            return NEEDS_REPAIR;
        C += face_sizes[f];
    }
    if (C > (size_t)INT32_MAX - 2 || (C && !indices))
        return NEEDS_REPAIR;
    const size_t F = nfaces;
    const uint32_t *cv = indices;
    uint32_t *fs = bs_alloc(&S, F + 1, sizeof(uint32_t));
    uint32_t *cb = bs_alloc(&S, C, sizeof(uint32_t));
    uint32_t *cnt = bs_alloc(&S, nverts + 1, sizeof(uint32_t));
    uint32_t *outc = bs_alloc(&S, C, sizeof(uint32_t));
    uint32_t *partner = bs_alloc(&S, C, sizeof(uint32_t));
    if (!fs || !cb || !cnt || !outc || !partner) {
        st = GEOM_ERR_NOMEM;
        goto out;
    }
    /* faces, next vertex of each corner, range and repeat checks */
    {
        memset(cnt, 0xff, (nverts + 1) * sizeof(uint32_t));
        size_t c = 0;
        for (size_t f = 0; f < F; ++f) {
            size_t n = face_sizes[f];
            fs[f] = (uint32_t)c;
            for (size_t k = 0; k < n; ++k) {
                uint32_t v = cv[c + k];
                if ((size_t)v >= nverts) {
                    repair = 1;
                    goto out;
                }
                cb[c + k] = cv[c + (k + 1 < n ? k + 1 : 0)];
            }
            if (n == 3) {
                if (cv[c] == cv[c + 1] || cv[c + 1] == cv[c + 2] || cv[c] == cv[c + 2]) {
                    repair = 1;
                    goto out;
                }
            } else {
                for (size_t k = 0; k < n; ++k) {
                    if (cnt[cv[c + k]] == (uint32_t)f) {
                        repair = 1;
                        goto out;
                    }
                    cnt[cv[c + k]] = (uint32_t)f;
                }
            }
            c += n;
        }
        fs[F] = (uint32_t)C;
    }
    /* outgoing corners of each vertex (counting sort by source vertex) */
    memset(cnt, 0, (nverts + 1) * sizeof(uint32_t));
    for (size_t c = 0; c < C; ++c)
        cnt[cv[c] + 1]++;
    for (size_t v = 0; v < nverts; ++v)
        cnt[v + 1] += cnt[v];
    for (size_t c = 0; c < C; ++c)
        outc[cnt[cv[c]]++] = (uint32_t)c;
    /* cnt[v] is now the end of v's list, cnt[v - 1] (0 for v = 0) its start */
    for (size_t c = 0; c < C; ++c)
        partner[c] = INV;
    for (size_t c = 0; c < C; ++c) {
        if (partner[c] != INV)
            continue;
        uint32_t a = cv[c], b = cb[c];
        uint32_t s = b ? cnt[b - 1] : 0, e = cnt[b], found = INV;
        for (uint32_t i = s; i < e; ++i) {
            uint32_t d = outc[i];
            if (cb[d] == a) {
                if (found != INV || partner[d] != INV) {
                    repair = 1; /* an edge with more than two uses */
                    goto out;
                }
                found = d;
            }
        }
        if (found != INV) {
            partner[c] = found;
            partner[found] = (uint32_t)c;
        }
    }

    /* edges in the order of their first corner (as build_repair step 5) */
    uint32_t *he_of = outc;
    const size_t H = number_edges(C, partner, he_of);
    geom_mesh__clear_all(m);
    if ((st = geom_mesh__resize(m, nverts, H, F)) != GEOM_OK ||
        (st = geom_mesh__ensure_origins(m)) != GEOM_OK)
        goto fail_mesh;
    for (size_t f = 0; f < F; ++f) {
        uint32_t s = fs[f], e = fs[f + 1];
        m->face_origin[f] = (uint32_t)f;
        for (uint32_t c = s; c < e; ++c) {
            uint32_t h = he_of[c], cn = c + 1 < e ? c + 1 : s;
            m->he_vertex[h] = cb[c];
            m->he_face[h] = (uint32_t)f;
            geom_mesh__link(m, h, he_of[cn]);
            if (partner[c] == INV)
                m->he_vertex[h ^ 1u] = cv[c]; /* boundary halfedge */
        }
        m->f_he[f] = he_of[e - 1];
    }
    /* outgoing halfedges: the lowest interior one, then the boundary one;
     * cnt counts each vertex's outgoing halfedges for the fan check */
    memset(cnt, 0, (nverts + 1) * sizeof(uint32_t));
    for (size_t h = 0; h < H; ++h) {
        uint32_t x = m->he_vertex[h ^ 1u];
        cnt[x]++;
        if (m->he_face[h] != INV && m->v_he[x] == INV)
            m->v_he[x] = (uint32_t)h;
    }
    for (size_t b = 1; b < H; b += 2) {
        if (m->he_face[b] != INV)
            continue;
        uint32_t x = m->he_vertex[b ^ 1u];
        if (m->he_face[m->v_he[x]] == INV) {
            repair = 1; /* two boundary gaps at x */
            goto fail_mesh;
        }
        m->v_he[x] = (uint32_t)b;
    }
    for (size_t b = 1; b < H; b += 2)
        if (m->he_face[b] == INV)
            geom_mesh__link(m, (uint32_t)b, m->v_he[m->he_vertex[b]]);
    /* one fan per vertex: rotating from v_he visits every outgoing halfedge */
    for (size_t v = 0; v < nverts; ++v) {
        uint32_t h0 = m->v_he[v], h = h0, n = 0;
        if (h0 == INV) {
            rep->isolated_vertices++;
            continue;
        }
        do {
            h = m->he_next[h ^ 1u];
            n++;
        } while (h != h0 && n <= cnt[v]);
        if (n != cnt[v]) {
            repair = 1;
            goto fail_mesh;
        }
    }
    {
        double *pos = geom_mesh__pos(m);
        if (nverts)
            memcpy(pos, xyz, 3 * nverts * sizeof(double));
        for (size_t v = 0; v < nverts; ++v)
            m->vertex_origin[v] = (uint32_t)v;
    }
    goto out;

fail_mesh:
    geom_mesh__clear_all(m);
out:
    bs_free_all(&S);
    *stp = st;
    return repair ? NEEDS_REPAIR : 0;
}

/* --------------------------------------------------------- attribute streams */

static geom_status check_streams(const geom_mesh_build_options *opt, size_t nverts, size_t nfaces,
                                 size_t ncorners, geom_diag *diag)
{
    size_t n = opt ? opt->n_channels : 0;
    if (n && !opt->channels)
        return geom_diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                             "geom_mesh_build: NULL channels");
    for (size_t i = 0; i < n; ++i) {
        const geom_mesh_build_channel *c = &opt->channels[i];
        const char *why = NULL;
        size_t nvals = c->domain == GEOM_MESH_DOMAIN_VERTEX ? nverts
                       : c->domain == GEOM_MESH_DOMAIN_FACE ? nfaces
                                                            : c->n_values;
        if (!c->name || !c->name[0] || strlen(c->name) >= GEOM_MESH__NAME_MAX)
            why = "empty or too long name";
        else if (c->domain != GEOM_MESH_DOMAIN_VERTEX && c->domain != GEOM_MESH_DOMAIN_FACE &&
                 c->domain != GEOM_MESH_DOMAIN_CORNER)
            why = "domain must be VERTEX, FACE or CORNER";
        else if (c->ncomp == 0)
            why = "ncomp is 0";
        else if (nvals && !c->values)
            why = "NULL values";
        else if (c->domain == GEOM_MESH_DOMAIN_VERTEX && strcmp(c->name, "position") == 0)
            why = "\"position\" is the positions argument";
        else if (c->domain == GEOM_MESH_DOMAIN_CORNER) {
            if (ncorners && !c->indices)
                why = "NULL corner indices";
            else if (c->n_values >= (size_t)UINT32_MAX)
                why = "pool too large";
            else
                for (size_t k = 0; k < ncorners && !why; ++k)
                    if (c->indices[k] != INV && (size_t)c->indices[k] >= c->n_values)
                        why = "corner index past the pool";
        }
        for (size_t j = 0; j < i && !why; ++j)
            if (opt->channels[j].domain == c->domain &&
                strcmp(opt->channels[j].name, c->name) == 0)
                why = "repeated name";
        if (why)
            return geom_diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                                 "geom_mesh_build: channel %zu: %s", i, why);
    }
    return GEOM_OK;
}

/* Attach the streams to the built mesh (which has its origin maps).
 * fstart: the input faces' first corners (nfaces + 1 entries). */
static geom_status attach_streams(geom_mesh *m, const geom_mesh_build_options *opt,
                                  const uint32_t *fstart)
{
    size_t n = opt ? opt->n_channels : 0;
    for (size_t i = 0; i < n; ++i) {
        const geom_mesh_build_channel *c = &opt->channels[i];
        const size_t nc = c->ncomp;
        uint32_t id;
        geom_status st = geom_mesh_channel_add(m, c->name, c->domain, nc, &id);
        if (st != GEOM_OK)
            return st;
        if (c->domain == GEOM_MESH_DOMAIN_VERTEX) {
            double *d = m->channels[id].data;
            for (size_t v = 0; v < m->nv; ++v)
                memcpy(d + v * nc, c->values + (size_t)m->vertex_origin[v] * nc,
                       nc * sizeof(double));
        } else if (c->domain == GEOM_MESH_DOMAIN_FACE) {
            double *d = m->channels[id].data;
            for (size_t f = 0; f < m->nf; ++f)
                memcpy(d + f * nc, c->values + (size_t)m->face_origin[f] * nc,
                       nc * sizeof(double));
        } else {
            if ((st = geom_mesh_corner_pool_resize(m, id, c->n_values)) != GEOM_OK)
                return st;
            geom_mesh__channel *ch = &m->channels[id];
            if (c->n_values)
                memcpy(ch->data, c->values, c->n_values * nc * sizeof(double));
            uint32_t *ci = ch->corner;
            for (size_t f = 0; f < m->nf; ++f) {
                /* input corner k: k next-steps from f_he when not flipped,
                 * (n - k) % n (k prev-steps) when flipped */
                const uint32_t *src = c->indices + fstart[m->face_origin[f]];
                uint32_t h0 = m->f_he[f], h = h0;
                size_t k = 0;
                if (!m->face_flipped[f]) {
                    do {
                        ci[h] = src[k++];
                        h = m->he_next[h];
                    } while (h != h0);
                } else {
                    do {
                        ci[h] = src[k++];
                        h = m->he_prev[h];
                    } while (h != h0);
                }
            }
        }
    }
    return GEOM_OK;
}

geom_status geom_mesh_build(geom_mesh *m, size_t nverts, const double *xyz, size_t nfaces,
                            const uint32_t *face_sizes, const uint32_t *indices,
                            const geom_mesh_build_options *opt, geom_mesh_build_report *report,
                            geom_diag *diag)
{
    geom_mesh_build_report rep_local;
    geom_mesh_build_report *rep = report ? report : &rep_local;
    memset(rep, 0, sizeof *rep);
    if (!m || (nverts && !xyz) || (nfaces && !face_sizes))
        return geom_diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                             "geom_mesh_build: NULL argument");
    if (nverts >= (size_t)UINT32_MAX || nfaces >= (size_t)UINT32_MAX)
        return geom_diag_set(diag, GEOM_ERR_LIMIT, "", 0, 0,
                             "geom_mesh_build: more than 2^32-2 vertices or faces");
    for (size_t i = 0; i < nverts; ++i)
        if (!geom_isfinite3(xyz + 3 * i))
            return geom_diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                                 "geom_mesh_build: vertex %zu has a non-finite coordinate", i);
    size_t nch = opt ? opt->n_channels : 0;
    uint32_t *fstart = NULL;
    size_t ncorners = 0;
    geom_status st;
    if (nch) {
        /* input corner offsets of the faces, for the streams */
        size_t bytes;
        if (geom_size_mul(nfaces + 1, sizeof(uint32_t), &bytes) != GEOM_OK)
            return geom_diag_set(diag, GEOM_ERR_LIMIT, NULL, 0, 0, "geom_mesh_build: too large for 32-bit indices");
        fstart = geom_alloc(&m->alloc, bytes);
        if (!fstart)
            return geom_diag_set(diag, GEOM_ERR_NOMEM, "", 0, 0, "geom_mesh_build: out of memory");
        for (size_t f = 0; f < nfaces; ++f) {
            fstart[f] = (uint32_t)ncorners;
            ncorners += face_sizes[f];
            if (ncorners > (size_t)INT32_MAX) {
                geom_free(&m->alloc, fstart, bytes);
                return geom_diag_set(diag, GEOM_ERR_LIMIT, "", 0, 0,
                                     "geom_mesh_build: more than 2^31 face corners");
            }
        }
        fstart[nfaces] = (uint32_t)ncorners;
        if ((st = check_streams(opt, nverts, nfaces, ncorners, diag)) != GEOM_OK) {
            geom_free(&m->alloc, fstart, bytes);
            return st;
        }
    }
    int repair = 1;
    st = GEOM_OK;
    if (opt && opt->trusted)
        repair = build_trusted(m, nverts, xyz, nfaces, face_sizes, indices, rep, &st) == NEEDS_REPAIR;
    if (repair && st == GEOM_OK) {
        memset(rep, 0, sizeof *rep);
        st = build_repair(m, nverts, xyz, nfaces, face_sizes, indices,
                          opt && opt->skip_invalid_faces, opt && opt->keep_orientation, rep,
                          diag);
    }
    if (st == GEOM_OK && nch) {
        st = attach_streams(m, opt, fstart);
        if (st != GEOM_OK)
            geom_mesh__clear_all(m);
    }
    if (fstart)
        geom_free(&m->alloc, fstart, (nfaces + 1) * sizeof(uint32_t));
#ifndef NDEBUG
    if (st == GEOM_OK && opt && opt->trusted && !repair) {
        /* the trusted path must give what the repairing one gives: a mesh
         * that passes every check (when the check itself can run: it may
         * run out of memory) */
        size_t nd = 0;
        geom_status vs = geom_mesh_validate(m, NULL, 0, &nd);
        assert(vs != GEOM_OK || nd == 0);
        (void)vs;
        (void)nd;
    }
#endif
    return st;
}
