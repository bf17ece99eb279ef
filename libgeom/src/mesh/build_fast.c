/*
 * geom_mesh_build's path for input that is already an oriented manifold
 * mesh: what the library itself produces and what most files hold. Tried
 * first for every input; anything the repairing path (build_repair.c) would
 * change returns GEOM_MESH__NEEDS_REPAIR, so the result, when there is one,
 * is exactly the repairing path's: the same element numbering (edges in the
 * order of their first corner, faces and vertices as input), no flipped
 * face, no split vertex. The phases:
 *
 *  1. faces: at least 3 vertices, indices in range, no repeated vertex;
 *  2. pairing: the corners leaving each vertex (one counting sort by source
 *     vertex); a corner a -> b is paired with the corner b -> a among those
 *     leaving b, and numbered as it is met (geom__mesh_number_edges's
 *     order); a directed edge used twice, or an edge with more than two
 *     uses, needs the repair;
 *  3. halfedges: face cycles, boundary halfedges opposite unpaired corners;
 *  4. vertices: outgoing halfedges (the lowest interior one, a boundary one
 *     when there is one), boundary cycles, and one fan per vertex (else a
 *     vertex must be split: repair).
 * Triangle-only input (the common case) needs no per-face offsets and no
 * next-vertex array: corner c's face starts at c - c % 3.
 */
#include "mesh/build_internal.h"

#define INV GEOM_INVALID_INDEX

/* The highest bit of a corner's number marks a corner with a partner. */
#define PAIRED 0x80000000u

typedef struct fast_ctx {
    size_t nverts, F, C;
    const uint32_t *cv;  /* corner -> its vertex (the input indices) */
    const uint32_t *fsz; /* face sizes */
    uint32_t *fs;        /* face -> first corner (F + 1), NULL for triangles */
    uint32_t *cb;        /* corner -> next vertex, NULL for triangles */
    uint32_t *cnt;       /* nverts + 1 */
    uint32_t *outc;      /* corners by source vertex */
    uint32_t *he_of;     /* corner -> halfedge (| PAIRED) */
    int tri;
} fast_ctx;

static inline uint32_t next3(uint32_t c) { return c % 3 == 2 ? c - 2 : c + 1; }

/* The vertex corner c's edge goes to. */
static inline uint32_t corner_to(const fast_ctx *x, uint32_t c)
{
    return x->tri ? x->cv[next3(c)] : x->cb[c];
}

/* Phase 1. Returns 1 when the input needs the repair (bad face). */
static int fast_faces(fast_ctx *x)
{
    const uint32_t *cv = x->cv;
    const size_t nv = x->nverts;
    if (x->tri) {
        for (size_t c = 0; c < x->C; c += 3) {
            uint32_t a = cv[c], b = cv[c + 1], d = cv[c + 2];
            if ((size_t)a >= nv || (size_t)b >= nv || (size_t)d >= nv || a == b || b == d ||
                a == d)
                return 1;
        }
        return 0;
    }
    memset(x->cnt, 0xff, (nv + 1) * sizeof(uint32_t));
    size_t c = 0;
    for (size_t f = 0; f < x->F; ++f) {
        size_t n = x->fsz[f];
        x->fs[f] = (uint32_t)c;
        for (size_t k = 0; k < n; ++k) {
            uint32_t v = cv[c + k];
            if ((size_t)v >= nv || x->cnt[v] == (uint32_t)f)
                return 1;
            x->cnt[v] = (uint32_t)f;
            x->cb[c + k] = cv[c + (k + 1 < n ? k + 1 : 0)];
        }
        c += n;
    }
    x->fs[x->F] = (uint32_t)c;
    return 0;
}

/* Phase 2. Returns the halfedge count, or 0 when the input needs the
 * repair (an input with corners has at least 6 halfedges). */
static size_t fast_pair(fast_ctx *x)
{
    const uint32_t *cv = x->cv;
    uint32_t *cnt = x->cnt, *outc = x->outc, *he_of = x->he_of;
    const size_t C = x->C, nv = x->nverts;
    memset(cnt, 0, (nv + 1) * sizeof(uint32_t));
    for (size_t c = 0; c < C; ++c)
        cnt[cv[c] + 1]++;
    for (size_t v = 0; v < nv; ++v)
        cnt[v + 1] += cnt[v];
    for (size_t c = 0; c < C; ++c)
        outc[cnt[cv[c]]++] = (uint32_t)c;
    /* cnt[v] is now the end of v's list, cnt[v - 1] (0 for v = 0) its start */
    memset(he_of, 0xff, C * sizeof(uint32_t));
    uint32_t E = 0;
    for (size_t c = 0; c < C; ++c) {
        if (he_of[c] != INV)
            continue;
        uint32_t a = cv[c], b = corner_to(x, (uint32_t)c);
        uint32_t s = b ? cnt[b - 1] : 0, e = cnt[b], found = INV;
        for (uint32_t i = s; i < e; ++i) {
            uint32_t d = outc[i];
            if (corner_to(x, d) == a) {
                if (found != INV || he_of[d] != INV)
                    return 0; /* an edge with more than two uses */
                found = d;
            }
        }
        if (found != INV) {
            he_of[c] = (2 * E) | PAIRED;
            he_of[found] = (2 * E + 1) | PAIRED;
        } else
            he_of[c] = 2 * E;
        E++;
    }
    return 2 * (size_t)E;
}

/* Phase 3: face cycles (he_next only) and the boundary halfedges' target
 * and face. x->he_of lives in m->he_prev (H >= C entries), which is written
 * here by no one: the face cycles' he_prev is filled afterwards from their
 * he_next (fast_prev), once he_of is no longer needed. */
static void fast_halfedges(const fast_ctx *x, geom_mesh *m)
{
    const uint32_t *cv = x->cv, *he_of = x->he_of;
    uint32_t *next = m->he_next, *hv = m->he_vertex, *hf = m->he_face;
    for (size_t f = 0; f < x->F; ++f) {
        uint32_t s = x->tri ? (uint32_t)(3 * f) : x->fs[f];
        uint32_t e = x->tri ? s + 3 : x->fs[f + 1];
        m->face_origin[f] = (uint32_t)f;
        uint32_t hp = he_of[e - 1] & ~PAIRED;
        for (uint32_t c = s; c < e; ++c) {
            uint32_t hc = he_of[c], h = hc & ~PAIRED;
            hv[h] = c + 1 < e ? cv[c + 1] : cv[s];
            hf[h] = (uint32_t)f;
            next[hp] = h;
            if (!(hc & PAIRED)) {
                hv[h ^ 1u] = cv[c]; /* boundary halfedge */
                hf[h ^ 1u] = INV;
            }
            hp = h;
        }
        m->f_he[f] = hp;
    }
}

/* The face cycles' he_prev, from their he_next (the boundary cycles are
 * linked, both ways, by fast_vertices). */
static void fast_prev(geom_mesh *m)
{
    const uint32_t *next = m->he_next, *hf = m->he_face;
    uint32_t *prev = m->he_prev;
    for (size_t h = 0; h < m->nh; ++h)
        if (hf[h] != INV)
            prev[next[h]] = (uint32_t)h;
}

/* Declared in mesh_internal.h: outgoing halfedges, boundary links and
 * (with cnt) the one-fan check, for the fast path and subdivision's direct
 * output. */
int geom__mesh_link_vertices(geom_mesh *m, uint32_t *cnt, size_t *isolated)
{
    const size_t H = m->nh, nv = m->nv;
    memset(m->v_he, 0xff, nv * sizeof(uint32_t));
    if (cnt) {
        memset(cnt, 0, nv * sizeof(uint32_t));
        for (size_t h = 0; h < H; ++h) {
            uint32_t v = m->he_vertex[h ^ 1u];
            cnt[v]++;
            if (m->he_face[h] != INV && m->v_he[v] == INV)
                m->v_he[v] = (uint32_t)h;
        }
    } else {
        for (size_t h = 0; h < H; ++h) {
            uint32_t v = m->he_vertex[h ^ 1u];
            if (m->he_face[h] != INV && m->v_he[v] == INV)
                m->v_he[v] = (uint32_t)h;
        }
    }
    for (size_t b = 1; b < H; b += 2) {
        if (m->he_face[b] != INV)
            continue;
        uint32_t v = m->he_vertex[b ^ 1u];
        if (m->he_face[m->v_he[v]] == INV)
            return 1; /* two boundary gaps at v */
        m->v_he[v] = (uint32_t)b;
    }
    for (size_t b = 1; b < H; b += 2)
        if (m->he_face[b] == INV)
            geom__mesh_link(m, (uint32_t)b, m->v_he[m->he_vertex[b]]);
    if (!cnt)
        return 0;
    /* one fan per vertex: rotating from v_he visits every outgoing halfedge */
    for (size_t v = 0; v < nv; ++v) {
        uint32_t h0 = m->v_he[v], h = h0, n = 0;
        if (h0 == INV) {
            if (isolated)
                (*isolated)++;
            continue;
        }
        do {
            h = m->he_next[h ^ 1u];
            n++;
        } while (h != h0 && n <= cnt[v]);
        if (n != cnt[v])
            return 1;
    }
    return 0;
}

/* Phase 4. Returns 1 when a vertex must be split (the repair). */
static int fast_vertices(const fast_ctx *x, geom_mesh *m, geom_mesh_build_report *rep)
{
    return geom__mesh_link_vertices(m, x->cnt, &rep->isolated_vertices);
}

int geom__mesh_build_fast(geom_mesh *m, size_t nverts, const double *xyz, size_t nfaces,
                          const uint32_t *face_sizes, const uint32_t *indices,
                          geom_mesh_build_report *rep, geom_status *stp)
{
    geom__mesh_bscratch S;
    memset(&S, 0, sizeof S);
    S.a = &m->alloc;
    *stp = GEOM_OK;
    int repair = 0;
    fast_ctx x;
    memset(&x, 0, sizeof x);
    x.nverts = nverts;
    x.F = nfaces;
    x.cv = indices;
    x.fsz = face_sizes;
    x.tri = 1;
    for (size_t f = 0; f < nfaces; ++f) {
        if (face_sizes[f] < 3)
            return GEOM_MESH__NEEDS_REPAIR;
        x.tri &= face_sizes[f] == 3;
        x.C += face_sizes[f];
    }
    /* PAIRED needs the halfedge numbers below 2^31 */
    if (x.C >= (size_t)1 << 30 || (x.C && !indices))
        return GEOM_MESH__NEEDS_REPAIR;
    const size_t C = x.C;
    x.cnt = geom__mesh_bs_alloc(&S, nverts + 1, sizeof(uint32_t));
    x.outc = geom__mesh_bs_alloc(&S, C, sizeof(uint32_t));
    x.he_of = geom__mesh_bs_alloc(&S, C, sizeof(uint32_t));
    if (!x.tri) {
        x.fs = geom__mesh_bs_alloc(&S, nfaces + 1, sizeof(uint32_t));
        x.cb = geom__mesh_bs_alloc(&S, C, sizeof(uint32_t));
    }
    if (!x.cnt || !x.outc || !x.he_of || (!x.tri && (!x.fs || !x.cb))) {
        *stp = GEOM_ERR_NOMEM;
        goto out;
    }
    size_t H = 0;
    if (fast_faces(&x) || (C && (H = fast_pair(&x)) == 0)) {
        repair = 1;
        goto out;
    }
    geom__mesh_bs_free_one(&S, x.outc);
    if ((*stp = geom__mesh_build_storage(m, nverts, H, nfaces)) != GEOM_OK)
        goto fail_mesh;
    /* he_of moves into he_prev (H >= C), whose pages are the only ones of
     * the new halfedge arrays touched so far: the corner numbering and the
     * four halfedge arrays are never resident together */
    if (C)
        memcpy(m->he_prev, x.he_of, C * sizeof(uint32_t));
    geom__mesh_bs_free_one(&S, x.he_of);
    x.he_of = m->he_prev;
    fast_halfedges(&x, m);
    x.he_of = NULL;
    fast_prev(m);
    /* the corner arrays are done: freed before the vertex arrays are
     * written, which keeps them out of the peak */
    geom__mesh_bs_free_one(&S, x.cb);
    geom__mesh_bs_free_one(&S, x.fs);
    if (fast_vertices(&x, m, rep)) {
        repair = 1;
        goto fail_mesh;
    }
    if (nverts && geom__mesh_pos(m) != xyz) /* adopted: already in place */
        memcpy(geom__mesh_pos(m), xyz, 3 * nverts * sizeof(double));
    for (size_t v = 0; v < nverts; ++v)
        m->vertex_origin[v] = (uint32_t)v;
    goto out;

fail_mesh:
    geom__mesh_clear_all(m);
out:
    geom__mesh_bs_free_all(&S);
    return repair ? GEOM_MESH__NEEDS_REPAIR : 0;
}
