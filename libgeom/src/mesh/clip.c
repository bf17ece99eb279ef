/*
 * Clipping a polygon mesh by a plane or a view frustum, with linear
 * interpolation of vertex and corner channels and optional caps.
 *
 * Per plane a*x + b*y + c*z + d >= 0 (normalised to a unit normal):
 *  - each live vertex is classified by its signed distance s; |s| at most
 *    1e-12 times the bounding-box diagonal counts as 0 and the vertex is
 *    projected onto the plane ("snapped"), so a vertex on (or within
 *    rounding of) the plane never creates a sliver;
 *  - a face with no vertex below is kept whole, except a face lying in the
 *    plane, kept only when its normal points away from the kept side (it
 *    bounds the kept part); a face with no vertex above is dropped;
 *  - other faces are clipped Sutherland-Hodgman style: an edge whose ends
 *    are strictly on opposite sides gets one new vertex at
 *    t = s_A / (s_A - s_B) from its end A (the end its first halfedge starts
 *    from, so both faces share it exactly); when a non-convex polygon leaves
 *    several pieces, the pieces' chains are re-paired along the line where
 *    the plane meets the face (crossings sorted along it and joined in
 *    consecutive pairs), so each piece is its own polygon;
 *  - VERTEX channels at a new vertex, and CORNER channels at a new corner,
 *    are a + t (b - a) of the two ends' values (the corner values of that
 *    face), so a linear function stays linear; FACE channels are copied;
 *    EDGE channels are copied to the kept parts of old edges and zero on
 *    new edges;
 *  - with caps, the cut's boundary edges that lie in the plane are chained
 *    into loops, loops are nested (holes joined to their outer loop by a
 *    bridge, after Eberly's "Triangulation by ear clipping") and
 *    triangulated by geom_polygon_triangulate (exact orientation tests;
 *    a monotone sweep above 64 vertices, ear clipping below), then
 *    improved by Lawson flips towards the constrained Delaunay triangulation
 *    (no slivers where the loop has nearly collinear vertices); cap corners
 *    get the cap's outward normal -(a,b,c)/|(a,b,c)| in a CORNER "normal"
 *    channel and in a FACE "normal" channel, zero in every other corner and
 *    face channel; vertex channels are those of the shared boundary
 *    vertices.
 * The result is built once by geom_mesh_build (orientation kept; its direct link
 * first, repaired only where the pieces need it) with its vertex, face and corner
 * channels; EDGE channels are added after the others. Face groups
 * and material libraries are copied; tags and polylines are not (their
 * indices refer to the input). When every live vertex lies strictly above
 * the plane nothing is cut and the result is a clone (tags and polylines
 * included). A frustum is six planes applied in turn (a plane whose normal
 * is zero keeps everything when its constant is >= 0, nothing otherwise).
 */
#include "mesh/mesh_internal.h"

#include <stdlib.h>

#define INV GEOM_INVALID_INDEX

enum { CK_KEEP = 0, CK_CUT = 1, CK_CAP = 2 };

typedef struct clip_ctx {
    const geom_mesh *m;
    const geom_allocator *al;
    double n[3], d;   /* unit plane */
    double *s;        /* signed distance per vertex (snapped: 0) */
    int8_t *sg;       /* sign per vertex */
    const double *pos;

    /* soup under construction: vertices are codes (v < nv: original vertex,
     * nv + e: the cut point of edge e) */
    size_t nf, fcap, fcap2;
    uint32_t *fsize, *forig;
    size_t ni, icap, icap2, icap3;
    uint32_t *code, *csrc;
    uint8_t *ckind;
} clip_ctx;

static inline double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
static inline void cross3(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/* The two ends of edge e: A = from(2e), B = to(2e); t of the cut from A. */
static void cut_param(const clip_ctx *c, uint32_t e, uint32_t *A, uint32_t *B, double *t)
{
    *A = c->m->he_vertex[2 * e + 1];
    *B = c->m->he_vertex[2 * e];
    double sa = c->s[*A], sb = c->s[*B];
    *t = sa / (sa - sb);
}

static void cut_point(const clip_ctx *c, uint32_t e, double p[3])
{
    uint32_t A, B;
    double t;
    cut_param(c, e, &A, &B, &t);
    const double *a = c->pos + 3 * (size_t)A, *b = c->pos + 3 * (size_t)B;
    for (int k = 0; k < 3; k++)
        p[k] = a[k] + t * (b[k] - a[k]);
}

static void code_point(const clip_ctx *c, const double *snapped, uint32_t code, double p[3])
{
    if (code < c->m->nv) {
        memcpy(p, snapped + 3 * (size_t)code, 3 * sizeof(double));
    } else {
        cut_point(c, code - (uint32_t)c->m->nv, p);
    }
}

static geom_status soup_face(clip_ctx *c, size_t n, const uint32_t *codes, const uint32_t *src,
                             const uint8_t *kind, uint32_t orig)
{
    if (geom__grow(c->al, (void **)&c->fsize, &c->fcap, c->nf + 1, 4) != GEOM_OK ||
        geom__grow(c->al, (void **)&c->forig, &c->fcap2, c->nf + 1, 4) != GEOM_OK ||
        geom__grow(c->al, (void **)&c->code, &c->icap, c->ni + n, 4) != GEOM_OK ||
        geom__grow(c->al, (void **)&c->csrc, &c->icap2, c->ni + n, 4) != GEOM_OK ||
        geom__grow(c->al, (void **)&c->ckind, &c->icap3, c->ni + n, 1) != GEOM_OK)
        return GEOM_ERR_NOMEM;
    memcpy(c->code + c->ni, codes, n * 4);
    memcpy(c->csrc + c->ni, src, n * 4);
    memcpy(c->ckind + c->ni, kind, n);
    c->ni += n;
    c->fsize[c->nf] = (uint32_t)n;
    c->forig[c->nf] = orig;
    c->nf++;
    return GEOM_OK;
}

/* Emit a polygon after removing consecutive repeated codes; fewer than 3
 * distinct corners: nothing. */
static geom_status emit_poly(clip_ctx *c, size_t n, uint32_t *codes, uint32_t *src, uint8_t *kind,
                             uint32_t orig)
{
    size_t k = 0;
    for (size_t i = 0; i < n; i++) {
        if (k > 0 && codes[k - 1] == codes[i])
            continue;
        codes[k] = codes[i];
        src[k] = src[i];
        kind[k] = kind[i];
        k++;
    }
    while (k > 1 && codes[k - 1] == codes[0])
        k--;
    if (k < 3)
        return GEOM_OK;
    return soup_face(c, k, codes, src, kind, orig);
}

/* One point of the Sutherland-Hodgman sequence of a face. */
typedef struct sh_pt {
    uint32_t code, src;
    uint8_t kind;
    uint8_t bridge_after; /* the boundary dips below the plane after it */
    uint8_t positive;     /* an original vertex strictly above */
} sh_pt;

typedef struct chain {
    size_t first, count; /* in the sequence (cyclic) */
    double t_in, t_out;  /* positions of the first / last point along the line */
    size_t next;         /* chain reached from this one's last point */
    int visited;
} chain;

typedef struct face_buf {
    uint32_t *he;
    sh_pt *pts;
    chain *ch;
    uint32_t *codes, *src;
    uint8_t *kind;
    size_t cap[6]; /* of he, pts, ch, codes, src, kind */
} face_buf;

/* Room for a face of k corners: its Sutherland-Hodgman sequence has at
 * most 2k points. */
static geom_status face_buf_reserve(const geom_allocator *al, face_buf *b, size_t k)
{
    size_t need = 2 * k + 4;
    if (geom__grow(al, (void **)&b->he, &b->cap[0], need, sizeof(uint32_t)) != GEOM_OK ||
        geom__grow(al, (void **)&b->pts, &b->cap[1], need, sizeof(sh_pt)) != GEOM_OK ||
        geom__grow(al, (void **)&b->ch, &b->cap[2], need, sizeof(chain)) != GEOM_OK ||
        geom__grow(al, (void **)&b->codes, &b->cap[3], need, sizeof(uint32_t)) != GEOM_OK ||
        geom__grow(al, (void **)&b->src, &b->cap[4], need, sizeof(uint32_t)) != GEOM_OK ||
        geom__grow(al, (void **)&b->kind, &b->cap[5], need, 1) != GEOM_OK)
        return GEOM_ERR_NOMEM;
    return GEOM_OK;
}

static void face_buf_free(const geom_allocator *al, face_buf *b)
{
    geom__free(al, b->he, b->cap[0] * sizeof(uint32_t));
    geom__free(al, b->pts, b->cap[1] * sizeof(sh_pt));
    geom__free(al, b->ch, b->cap[2] * sizeof(chain));
    geom__free(al, b->codes, b->cap[3] * sizeof(uint32_t));
    geom__free(al, b->src, b->cap[4] * sizeof(uint32_t));
    geom__free(al, b->kind, b->cap[5]);
}

typedef struct tkey {
    double t;
    size_t chain;
    int is_out;
} tkey;

static int cmp_tkey(const void *a, const void *b)
{
    const tkey *x = a, *y = b;
    if (x->t < y->t)
        return -1;
    if (x->t > y->t)
        return 1;
    if (x->chain != y->chain)
        return x->chain < y->chain ? -1 : 1;
    return x->is_out - y->is_out;
}

/* Newell normal (unnormalised) of a face from positions `p`. */
static void face_newell(const geom_mesh *m, const double *p, uint32_t f, double n[3])
{
    uint32_t h0 = m->f_he[f], h = h0;
    const double *a = p + 3 * (size_t)m->he_vertex[h0];
    n[0] = n[1] = n[2] = 0.0;
    double qp[3] = {0.0, 0.0, 0.0};
    size_t k = 0;
    do {
        uint32_t hn = m->he_next[h];
        const double *b = p + 3 * (size_t)m->he_vertex[hn];
        double q[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, x[3];
        cross3(qp, q, x);
        n[0] += x[0];
        n[1] += x[1];
        n[2] += x[2];
        memcpy(qp, q, sizeof q);
        h = hn;
    } while (h != h0 && ++k < m->nh);
}

static geom_status clip_face(clip_ctx *c, const double *snapped, uint32_t f, face_buf *b)
{
    const geom_mesh *m = c->m;
    uint32_t h0 = m->f_he[f], h = h0;
    size_t k = 0;
    int npos = 0, nneg = 0;
    do {
        geom_status st = face_buf_reserve(c->al, b, k + 1);
        if (st != GEOM_OK)
            return st;
        b->he[k++] = h;
        int8_t s = c->sg[m->he_vertex[h]];
        npos += s > 0;
        nneg += s < 0;
        h = m->he_next[h];
    } while (h != h0 && k < m->nh);
    geom_status st = face_buf_reserve(c->al, b, k);
    if (st != GEOM_OK)
        return st;

    if (nneg == 0) {
        if (npos == 0) {
            /* lying in the plane: keep when it faces away from the kept side */
            double nf[3];
            face_newell(m, snapped, f, nf);
            if (!(dot3(nf, c->n) < 0.0))
                return GEOM_OK;
        }
        for (size_t i = 0; i < k; i++) {
            b->codes[i] = m->he_vertex[b->he[i]];
            b->src[i] = b->he[i];
            b->kind[i] = CK_KEEP;
        }
        return emit_poly(c, k, b->codes, b->src, b->kind, f);
    }
    if (npos == 0)
        return GEOM_OK;

    /* Sutherland-Hodgman sequence with bridge marks */
    size_t np = 0;
    for (size_t i = 0; i < k; i++) {
        uint32_t hi = b->he[i], hj = b->he[(i + 1) % k];
        uint32_t vi = m->he_vertex[hi], vj = m->he_vertex[hj];
        int8_t si = c->sg[vi], sj = c->sg[vj];
        if (si >= 0) {
            sh_pt *p = &b->pts[np++];
            p->code = vi;
            p->src = hi;
            p->kind = CK_KEEP;
            p->positive = si > 0;
            p->bridge_after = sj < 0 && si == 0;
        }
        if ((si > 0 && sj < 0) || (si < 0 && sj > 0)) {
            sh_pt *p = &b->pts[np++];
            p->code = (uint32_t)m->nv + (hj >> 1);
            p->src = hj; /* halfedge from vi to vj, in this face */
            p->kind = CK_CUT;
            p->positive = 0;
            p->bridge_after = sj < 0;
        }
    }
    size_t nbridge = 0, last_bridge = 0;
    for (size_t i = 0; i < np; i++) {
        if (b->pts[i].bridge_after) {
            nbridge++;
            last_bridge = i;
        }
    }
    /* chains: from after a bridge to the next bridge (inclusive) */
    size_t nch = 0;
    if (nbridge > 0) {
        size_t start = (last_bridge + 1) % np;
        size_t i = start;
        for (size_t done = 0; done < np;) {
            size_t first = i, cnt = 0;
            int pos = 0;
            for (;;) {
                pos |= b->pts[i].positive;
                cnt++;
                done++;
                int br = b->pts[i].bridge_after;
                i = (i + 1) % np;
                if (br)
                    break;
            }
            if (pos) {
                chain *ch = &b->ch[nch++];
                ch->first = first;
                ch->count = cnt;
                ch->visited = 0;
                ch->next = INV;
            }
        }
    }
    if (nch <= 1) {
        size_t cnt = 0;
        if (nch == 1) {
            for (size_t j = 0; j < b->ch[0].count; j++) {
                const sh_pt *p = &b->pts[(b->ch[0].first + j) % np];
                b->codes[cnt] = p->code;
                b->src[cnt] = p->src;
                b->kind[cnt] = p->kind;
                cnt++;
            }
        }
        return cnt ? emit_poly(c, cnt, b->codes, b->src, b->kind, f) : GEOM_OK;
    }

    /* several pieces: pair the chain ends along the line plane x face */
    double nf[3], dir[3];
    face_newell(m, snapped, f, nf);
    cross3(c->n, nf, dir);
    int ok = geom__mesh_normalize3(dir);
    tkey *keys = NULL;
    if (ok) {
        keys = geom__alloc(c->al, 2 * nch * sizeof(tkey));
        if (!keys)
            return GEOM_ERR_NOMEM;
        for (size_t j = 0; j < nch; j++) {
            chain *ch = &b->ch[j];
            double pa[3], pb[3];
            code_point(c, snapped, b->pts[ch->first].code, pa);
            code_point(c, snapped, b->pts[(ch->first + ch->count - 1) % np].code, pb);
            ch->t_in = dot3(pa, dir);
            ch->t_out = dot3(pb, dir);
            keys[2 * j].t = ch->t_in;
            keys[2 * j].chain = j;
            keys[2 * j].is_out = 0;
            keys[2 * j + 1].t = ch->t_out;
            keys[2 * j + 1].chain = j;
            keys[2 * j + 1].is_out = 1;
        }
        qsort(keys, 2 * nch, sizeof(tkey), cmp_tkey);
        for (size_t j = 0; j + 1 < 2 * nch && ok; j += 2) {
            const tkey *x = &keys[j], *y = &keys[j + 1];
            if (x->is_out == y->is_out) {
                ok = 0;
                break;
            }
            const tkey *out = x->is_out ? x : y, *in = x->is_out ? y : x;
            b->ch[out->chain].next = in->chain;
        }
        geom__free(c->al, keys, 2 * nch * sizeof(tkey));
        for (size_t j = 0; j < nch && ok; j++) {
            if (b->ch[j].next == (size_t)INV)
                ok = 0;
        }
    }
    if (!ok) {
        /* fall back to one polygon through the chains in boundary order */
        for (size_t j = 0; j < nch; j++)
            b->ch[j].next = (j + 1) % nch;
    }
    for (size_t j0 = 0; j0 < nch; j0++) {
        if (b->ch[j0].visited)
            continue;
        size_t cnt = 0, j = j0;
        while (!b->ch[j].visited) {
            chain *ch = &b->ch[j];
            ch->visited = 1;
            for (size_t q = 0; q < ch->count; q++) {
                const sh_pt *p = &b->pts[(ch->first + q) % np];
                b->codes[cnt] = p->code;
                b->src[cnt] = p->src;
                b->kind[cnt] = p->kind;
                cnt++;
            }
            j = ch->next;
        }
        st = emit_poly(c, cnt, b->codes, b->src, b->kind, f);
        if (st != GEOM_OK)
            return st;
    }
    return GEOM_OK;
}

/* ------------------------------------------------------------------ caps */

typedef struct ear_ctx {
    const double *xy; /* 2 doubles per polygon entry */
    size_t n;
} ear_ctx;

typedef struct edge_slot {
    uint64_t key; /* (a << 32) | b for the directed edge a -> b */
    uint32_t slot; /* 3 * triangle + corner */
} edge_slot;

static int cmp_edge_slot(const void *a, const void *b)
{
    uint64_t x = ((const edge_slot *)a)->key, y = ((const edge_slot *)b)->key;
    return x < y ? -1 : (x > y ? 1 : 0);
}

/* Replace the neighbour `from` by `to` in triangle t's neighbour list. */
static void nbr_replace(uint32_t *nbr, uint32_t t, uint32_t from, uint32_t to)
{
    for (int k = 0; k < 3; k++) {
        if (nbr[3 * (size_t)t + k] == from) {
            nbr[3 * (size_t)t + k] = to;
            return;
        }
    }
}

/*
 * Lawson's edge flips towards the constrained Delaunay triangulation of the
 * ear-clipped polygon (the polygon's edges, bridges included, stay): an
 * interior edge is flipped when the opposite vertex lies strictly inside the
 * circumcircle (exact incircle predicate) and both new triangles are
 * strictly counter-clockwise. This maximises the smallest angle, which
 * removes the slivers ear clipping leaves where the boundary has nearly
 * collinear vertices (a plane cutting the diagonals of triangulated planar
 * polygons, or a plane nearly tangent to the surface). Returns GEOM_OK or
 * GEOM_ERR_NOMEM (the triangulation is then the ear-clipped one).
 */
static geom_status delaunay_flips(const geom_allocator *al, const ear_ctx *e, uint32_t *tris,
                                  size_t ntri)
{
    if (ntri < 2)
        return GEOM_OK;
    const size_t ns = 3 * ntri;
    edge_slot *es = geom__alloc(al, ns * sizeof(edge_slot));
    uint32_t *nbr = geom__alloc(al, ns * sizeof(uint32_t));
    if (!es || !nbr) {
        geom__free(al, es, ns * sizeof(edge_slot));
        geom__free(al, nbr, ns * sizeof(uint32_t));
        return GEOM_ERR_NOMEM;
    }
    for (size_t i = 0; i < ns; i++) {
        size_t t = i / 3, k = i % 3;
        es[i].key = ((uint64_t)tris[3 * t + k] << 32) | tris[3 * t + (k + 1) % 3];
        es[i].slot = (uint32_t)i;
    }
    qsort(es, ns, sizeof(edge_slot), cmp_edge_slot);
    for (size_t i = 0; i < ns; i++) {
        size_t t = i / 3, k = i % 3;
        uint64_t rev = ((uint64_t)tris[3 * t + (k + 1) % 3] << 32) | tris[3 * t + k];
        size_t lo = 0, hi = ns;
        while (lo < hi) {
            size_t mid = lo + (hi - lo) / 2;
            if (es[mid].key < rev)
                lo = mid + 1;
            else
                hi = mid;
        }
        nbr[i] = lo < ns && es[lo].key == rev ? es[lo].slot / 3 : GEOM_INVALID_INDEX;
    }
    geom__free(al, es, ns * sizeof(edge_slot));

    for (size_t pass = 0; pass < ns; pass++) {
        int changed = 0;
        for (uint32_t t = 0; t < ntri; t++) {
            for (int k = 0; k < 3; k++) {
                uint32_t u = nbr[3 * (size_t)t + k];
                if (u == GEOM_INVALID_INDEX)
                    continue;
                uint32_t *T = tris + 3 * (size_t)t, *U = tris + 3 * (size_t)u;
                uint32_t a = T[k], b = T[(k + 1) % 3], c = T[(k + 2) % 3];
                int j = -1;
                for (int q = 0; q < 3; q++) {
                    if (U[q] == b && U[(q + 1) % 3] == a)
                        j = q;
                }
                if (j < 0)
                    continue;
                uint32_t d = U[(j + 2) % 3];
                const double *pa = e->xy + 2 * (size_t)a, *pb = e->xy + 2 * (size_t)b,
                             *pc = e->xy + 2 * (size_t)c, *pd = e->xy + 2 * (size_t)d;
                if (!(geom_incircle(pa, pb, pc, pd) > 0.0))
                    continue;
                if (!(geom_orient2d(pc, pa, pd) > 0.0) || !(geom_orient2d(pd, pb, pc) > 0.0))
                    continue;
                uint32_t n_bc = nbr[3 * (size_t)t + (k + 1) % 3];
                uint32_t n_ca = nbr[3 * (size_t)t + (k + 2) % 3];
                uint32_t n_ad = nbr[3 * (size_t)u + (j + 1) % 3];
                uint32_t n_db = nbr[3 * (size_t)u + (j + 2) % 3];
                /* t' = (c, a, d), u' = (d, b, c) */
                T[0] = c;
                T[1] = a;
                T[2] = d;
                U[0] = d;
                U[1] = b;
                U[2] = c;
                nbr[3 * (size_t)t] = n_ca;
                nbr[3 * (size_t)t + 1] = n_ad;
                nbr[3 * (size_t)t + 2] = u;
                nbr[3 * (size_t)u] = n_db;
                nbr[3 * (size_t)u + 1] = n_bc;
                nbr[3 * (size_t)u + 2] = t;
                if (n_ad != GEOM_INVALID_INDEX)
                    nbr_replace(nbr, n_ad, u, t);
                if (n_bc != GEOM_INVALID_INDEX)
                    nbr_replace(nbr, n_bc, t, u);
                changed = 1;
            }
        }
        if (!changed)
            break;
    }
    geom__free(al, nbr, ns * sizeof(uint32_t));
    return GEOM_OK;
}

typedef struct loop {
    size_t first, count; /* range in the loop arrays (codes and xy) */
    double area;
} loop;

static double loop_area(const double *xy, const loop *l)
{
    double a = 0.0;
    const double *o = xy + 2 * l->first;
    for (size_t i = 1; i + 1 < l->count; i++) {
        const double *p = xy + 2 * (l->first + i);
        const double *q = xy + 2 * (l->first + i + 1);
        a += (p[0] - o[0]) * (q[1] - o[1]) - (p[1] - o[1]) * (q[0] - o[0]);
    }
    return 0.5 * a;
}

/* Even-odd point in polygon. */
static int point_in_loop(const double *xy, const loop *l, const double p[2])
{
    int in = 0;
    for (size_t i = 0, j = l->count - 1; i < l->count; j = i++) {
        const double *a = xy + 2 * (l->first + i);
        const double *b = xy + 2 * (l->first + j);
        if ((a[1] > p[1]) != (b[1] > p[1])) {
            double x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if (p[0] < x)
                in = !in;
        }
    }
    return in;
}

/* Merge hole `h` (clockwise) into polygon `poly` (counter-clockwise, a list
 * of vertex ids, *n entries, capacity enough for n + hole + 2) by a bridge
 * from the hole's rightmost vertex (Eberly 2002). */
static void bridge_hole(const double *xy, uint32_t *poly, size_t *n, const uint32_t *hole,
                        size_t hn)
{
    size_t mi = 0;
    for (size_t i = 1; i < hn; i++) {
        const double *a = xy + 2 * (size_t)hole[i], *b = xy + 2 * (size_t)hole[mi];
        if (a[0] > b[0] || (a[0] == b[0] && a[1] < b[1]))
            mi = i;
    }
    const double *M = xy + 2 * (size_t)hole[mi];
    /* nearest edge hit by the ray M + (s, 0), s >= 0, among the edges
     * going up (the ones seen from inside: right sides of the outer loop,
     * left sides of holes already bridged) */
    size_t best = INV;
    double bx = INFINITY;
    for (size_t i = 0; i < *n; i++) {
        const double *a = xy + 2 * (size_t)poly[i], *b = xy + 2 * (size_t)poly[(i + 1) % *n];
        if (!(a[1] <= M[1] && M[1] <= b[1] && a[1] < b[1]))
            continue;
        double x;
        if (M[1] == a[1])
            x = a[0];
        else if (M[1] == b[1])
            x = b[0];
        else
            x = a[0] + (M[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
        if (x >= M[0] && x < bx) {
            bx = x;
            best = i;
        }
    }
    size_t P;
    if (best == (size_t)INV) {
        /* should not happen for a hole inside the polygon: nearest vertex */
        P = 0;
        double bd = INFINITY;
        for (size_t i = 0; i < *n; i++) {
            const double *a = xy + 2 * (size_t)poly[i];
            double d = (a[0] - M[0]) * (a[0] - M[0]) + (a[1] - M[1]) * (a[1] - M[1]);
            if (d < bd) {
                bd = d;
                P = i;
            }
        }
    } else {
        size_t i0 = best, i1 = (best + 1) % *n;
        const double *a = xy + 2 * (size_t)poly[i0], *b = xy + 2 * (size_t)poly[i1];
        P = a[0] > b[0] ? i0 : i1;
        double I[2] = {bx, M[1]};
        const double *Pp = xy + 2 * (size_t)poly[P];
        if (!(Pp[0] == I[0] && Pp[1] == I[1])) {
            /* reflex vertices inside triangle (M, I, P) block the view: take
             * the one with the smallest angle to the ray */
            double o = geom_orient2d(M, I, Pp);
            double bestang = INFINITY, bestd = INFINITY;
            size_t cand = P;
            for (size_t i = 0; i < *n; i++) {
                const double *r = xy + 2 * (size_t)poly[i];
                const double *rp = xy + 2 * (size_t)poly[(i + *n - 1) % *n];
                const double *rn = xy + 2 * (size_t)poly[(i + 1) % *n];
                if (i == P || geom_orient2d(rp, r, rn) > 0.0)
                    continue; /* convex */
                double o1 = geom_orient2d(M, I, r), o2 = geom_orient2d(I, Pp, r),
                       o3 = geom_orient2d(Pp, M, r);
                int inside = o > 0.0 ? (o1 >= 0.0 && o2 >= 0.0 && o3 >= 0.0)
                                     : (o1 <= 0.0 && o2 <= 0.0 && o3 <= 0.0);
                if (!inside || (r[0] == M[0] && r[1] == M[1]))
                    continue;
                double dx = r[0] - M[0], dy = r[1] - M[1];
                double ang = fabs(atan2(dy, dx));
                double dd = dx * dx + dy * dy;
                if (ang < bestang || (ang == bestang && dd < bestd)) {
                    bestang = ang;
                    bestd = dd;
                    cand = i;
                }
            }
            P = cand;
        }
    }
    /* new polygon: poly[0..P], hole[mi..mi] (hn + 1 entries), poly[P..n-1] */
    size_t tail = *n - P; /* entries poly[P..n-1] */
    memmove(poly + P + 1 + hn + 1, poly + P, tail * sizeof(uint32_t));
    for (size_t i = 0; i <= hn; i++)
        poly[P + 1 + i] = hole[(mi + i) % hn];
    /* poly[P + 1 + hn + 1] is now the copy of poly[P] (first of the tail) */
    *n += hn + 2;
}

static int cmp_loop_maxx_desc(const void *a, const void *b)
{
    const double *x = a, *y = b; /* pairs (maxx, index) */
    if (x[0] > y[0])
        return -1;
    if (x[0] < y[0])
        return 1;
    return 0;
}


static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : (x > y ? 1 : 0);
}

static int has_u64(const uint64_t *s, size_t n, uint64_t k)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (s[mid] < k)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < n && s[lo] == k;
}

/* Orthonormal (u, w) in the plane with u x w = nc. */
static void plane_frame(const double nc[3], double u[3], double w[3])
{
    double a[3] = {0.0, 0.0, 0.0};
    int k = 0;
    if (fabs(nc[1]) < fabs(nc[k]))
        k = 1;
    if (fabs(nc[2]) < fabs(nc[k]))
        k = 2;
    a[k] = 1.0;
    cross3(a, nc, u); /* orthogonal to nc */
    geom__mesh_normalize3(u);
    cross3(nc, u, w);
    geom__mesh_normalize3(w);
}

typedef struct cap_bufs {
    uint64_t *de, *sorted;
    size_t nde, decap;
    uint32_t *cfrom, *cto, *off, *adj, *pos, *pv, *lv, *poly, *tris;
    uint8_t *used;
    loop *loops;
    double *xy, *xy2, *hkey;
    size_t *hole_of;
    double *xyz; /* the polygon in the plane z = 0, for geom_polygon_triangulate */
    size_t ncap, ncode, nloops, nlv, poly_cap;
} cap_bufs;

static void cap_free(const geom_allocator *al, cap_bufs *b)
{
    geom__free(al, b->de, b->decap * 8);
    geom__free(al, b->sorted, b->nde * 8);
    geom__free(al, b->cfrom, (b->nde + 1) * 4);
    geom__free(al, b->cto, (b->nde + 1) * 4);
    geom__free(al, b->off, (b->ncode + 2) * 4);
    geom__free(al, b->adj, (b->nde + 1) * 4);
    geom__free(al, b->pos, (b->ncode + 1) * 4);
    geom__free(al, b->pv, (b->nde + 2) * 4);
    geom__free(al, b->lv, (b->nde + 1) * 4);
    geom__free(al, b->used, b->nde + 1);
    geom__free(al, b->loops, (b->nde + 1) * sizeof(loop));
    geom__free(al, b->xy, (b->nde + 1) * 2 * sizeof(double));
    geom__free(al, b->hkey, (b->nde + 1) * 2 * sizeof(double));
    geom__free(al, b->hole_of, (b->nde + 1) * sizeof(size_t));
    geom__free(al, b->poly, b->poly_cap * 4);
    geom__free(al, b->tris, b->poly_cap * 3 * 4);
    geom__free(al, b->xy2, b->poly_cap * 2 * sizeof(double));
    geom__free(al, b->xyz, b->poly_cap * 3 * sizeof(double));
}

/* Close the cut: chain the soup's unmatched on-plane edges into loops,
 * nest them and append ear-clipped cap triangles to the soup. */
static geom_status make_caps(clip_ctx *c, const double *snapped)
{
    const geom_mesh *m = c->m;
    const geom_allocator *al = c->al;
    const size_t nv = m->nv;
    geom_status st = GEOM_OK;
    cap_bufs b;
    memset(&b, 0, sizeof b);
    b.ncode = nv + m->nh / 2;

    size_t base = 0;
    for (size_t f = 0; f < c->nf; f++) {
        size_t n = c->fsize[f];
        for (size_t i = 0; i < n; i++) {
            uint32_t a = c->code[base + i], bb = c->code[base + (i + 1) % n];
            int ona = a >= nv || c->sg[a] == 0, onb = bb >= nv || c->sg[bb] == 0;
            if (!ona || !onb)
                continue;
            st = geom__grow(al, (void **)&b.de, &b.decap, b.nde + 1, sizeof *b.de);
            if (st != GEOM_OK)
                goto done;
            b.de[b.nde++] = ((uint64_t)a << 32) | bb;
        }
        base += n;
    }
    if (b.nde == 0)
        goto done;

    b.sorted = geom__alloc(al, b.nde * 8);
    b.cfrom = geom__alloc(al, (b.nde + 1) * 4);
    b.cto = geom__alloc(al, (b.nde + 1) * 4);
    b.off = geom__alloc(al, (b.ncode + 2) * 4);
    b.adj = geom__alloc(al, (b.nde + 1) * 4);
    b.pos = geom__alloc(al, (b.ncode + 1) * 4);
    b.pv = geom__alloc(al, (b.nde + 2) * 4);
    b.lv = geom__alloc(al, (b.nde + 1) * 4);
    b.used = geom__alloc(al, b.nde + 1);
    b.loops = geom__alloc(al, (b.nde + 1) * sizeof(loop));
    b.xy = geom__alloc(al, (b.nde + 1) * 2 * sizeof(double));
    b.hkey = geom__alloc(al, (b.nde + 1) * 2 * sizeof(double));
    b.hole_of = geom__alloc(al, (b.nde + 1) * sizeof(size_t));
    if (!b.sorted || !b.cfrom || !b.cto || !b.off || !b.adj || !b.pos || !b.pv || !b.lv ||
        !b.used || !b.loops || !b.xy || !b.hkey || !b.hole_of) {
        st = GEOM_ERR_NOMEM;
        goto done;
    }
    memcpy(b.sorted, b.de, b.nde * 8);
    qsort(b.sorted, b.nde, 8, cmp_u64);
    /* cap edges: reversed unmatched edges */
    for (size_t i = 0; i < b.nde; i++) {
        uint32_t a = (uint32_t)(b.de[i] >> 32), bb = (uint32_t)b.de[i];
        if (has_u64(b.sorted, b.nde, ((uint64_t)bb << 32) | a))
            continue;
        b.cfrom[b.ncap] = bb;
        b.cto[b.ncap] = a;
        b.ncap++;
    }
    if (b.ncap == 0)
        goto done;
    memset(b.off, 0, (b.ncode + 2) * 4);
    for (size_t i = 0; i < b.ncap; i++)
        b.off[b.cfrom[i] + 1]++;
    for (size_t i = 0; i < b.ncode; i++)
        b.off[i + 1] += b.off[i];
    {
        /* fill adjacency using pos[] as a cursor */
        for (size_t i = 0; i < b.ncode; i++)
            b.pos[i] = b.off[i];
        for (size_t i = 0; i < b.ncap; i++)
            b.adj[b.pos[b.cfrom[i]]++] = (uint32_t)i;
        for (size_t i = 0; i < b.ncode; i++)
            b.pos[i] = INV;
        memset(b.used, 0, b.ncap);
    }
    /* loops: walk unused edges, cutting out a cycle whenever the walk
     * returns to a vertex on its path (pinched loops become simple ones) */
    for (size_t e0 = 0; e0 < b.ncap; e0++) {
        if (b.used[e0])
            continue;
        size_t top = 0;
        b.pv[top] = b.cfrom[e0];
        b.pos[b.cfrom[e0]] = 0;
        top = 1;
        size_t e = e0;
        for (;;) {
            b.used[e] = 1;
            uint32_t y = b.cto[e];
            if (b.pos[y] != INV) {
                size_t k = b.pos[y];
                loop *l = &b.loops[b.nloops++];
                l->first = b.nlv;
                l->count = top - k;
                for (size_t i = k; i < top; i++) {
                    b.lv[b.nlv++] = b.pv[i];
                    if (i > k)
                        b.pos[b.pv[i]] = INV;
                }
                top = k + 1;
            } else {
                b.pos[y] = (uint32_t)top;
                b.pv[top++] = y;
            }
            uint32_t cur = b.pv[top - 1];
            size_t nexte = INV;
            for (uint32_t q = b.off[cur]; q < b.off[cur + 1]; q++) {
                if (!b.used[b.adj[q]]) {
                    nexte = b.adj[q];
                    break;
                }
            }
            if (nexte == (size_t)INV)
                break;
            e = nexte;
        }
        for (size_t i = 0; i < top; i++)
            b.pos[b.pv[i]] = INV;
    }

    /* 2D coordinates seen from outside the cap (normal -n) */
    double nc[3] = {-c->n[0], -c->n[1], -c->n[2]}, u[3], w[3];
    plane_frame(nc, u, w);
    for (size_t i = 0; i < b.nlv; i++) {
        double p[3];
        code_point(c, snapped, b.lv[i], p);
        b.xy[2 * i] = dot3(p, u);
        b.xy[2 * i + 1] = dot3(p, w);
    }
    for (size_t l = 0; l < b.nloops; l++) {
        b.loops[l].area = b.loops[l].count >= 3 ? loop_area(b.xy, &b.loops[l]) : 0.0;
        b.hole_of[l] = INV;
    }
    /* each hole goes to the smallest outer loop containing it */
    for (size_t h = 0; h < b.nloops; h++) {
        if (!(b.loops[h].area < 0.0))
            continue;
        const double *p0 = b.xy + 2 * b.loops[h].first, *p1 = b.xy + 2 * (b.loops[h].first + 1);
        double mid[2] = {0.5 * (p0[0] + p1[0]), 0.5 * (p0[1] + p1[1])};
        double best = INFINITY;
        for (size_t o = 0; o < b.nloops; o++) {
            if (!(b.loops[o].area > 0.0) || !(b.loops[o].area < best))
                continue;
            if (point_in_loop(b.xy, &b.loops[o], mid)) {
                best = b.loops[o].area;
                b.hole_of[h] = o;
            }
        }
    }
    /* polygon buffers: an outer loop plus its holes and two bridge
     * vertices per hole never exceed nlv + 2 * nloops entries */
    b.poly_cap = b.nlv + 2 * b.nloops + 4;
    b.poly = geom__alloc(al, b.poly_cap * 4);
    b.tris = geom__alloc(al, b.poly_cap * 3 * 4);
    b.xy2 = geom__alloc(al, b.poly_cap * 2 * sizeof(double));
    b.xyz = geom__alloc(al, b.poly_cap * 3 * sizeof(double));
    if (!b.poly || !b.tris || !b.xy2 || !b.xyz) {
        st = GEOM_ERR_NOMEM;
        goto done;
    }
    for (size_t o = 0; o < b.nloops; o++) {
        if (!(b.loops[o].area > 0.0))
            continue;
        /* polygon of positions into lv/xy: the outer loop, then the holes
         * by decreasing rightmost x */
        size_t nh = 0;
        for (size_t h = 0; h < b.nloops; h++) {
            if (b.hole_of[h] == o) {
                double mx = -INFINITY;
                for (size_t i = 0; i < b.loops[h].count; i++)
                    mx = fmax(mx, b.xy[2 * (b.loops[h].first + i)]);
                b.hkey[2 * nh] = mx;
                b.hkey[2 * nh + 1] = (double)h;
                nh++;
            }
        }
        size_t n = b.loops[o].count;
        for (size_t i = 0; i < n; i++)
            b.poly[i] = (uint32_t)(b.loops[o].first + i);
        qsort(b.hkey, nh, 2 * sizeof(double), cmp_loop_maxx_desc);
        for (size_t q = 0; q < nh; q++) {
            const loop *hl = &b.loops[(size_t)b.hkey[2 * q + 1]];
            /* hole ids (positions in lv) */
            uint32_t *hole = b.tris; /* scratch: tris has 3 * poly_cap entries */
            for (size_t i = 0; i < hl->count; i++)
                hole[i] = (uint32_t)(hl->first + i);
            bridge_hole(b.xy, b.poly, &n, hole, hl->count);
        }
        for (size_t i = 0; i < n; i++) {
            b.xy2[2 * i] = b.xy[2 * (size_t)b.poly[i]];
            b.xy2[2 * i + 1] = b.xy[2 * (size_t)b.poly[i] + 1];
        }
        /* the library's ear clipper (geom_polygon_triangulate) on the bridged
         * polygon, then Lawson flips */
        for (size_t i = 0; i < n; i++) {
            b.xyz[3 * i] = b.xy2[2 * i];
            b.xyz[3 * i + 1] = b.xy2[2 * i + 1];
            b.xyz[3 * i + 2] = 0.0;
        }
        size_t nt = n >= 3 ? n - 2 : 0;
        if (nt && geom_polygon_triangulate(n, b.xyz, b.tris) == GEOM_ERR_NOMEM) {
            st = GEOM_ERR_NOMEM;
            goto done;
        }
        ear_ctx ec = {b.xy2, n};
        st = delaunay_flips(al, &ec, b.tris, nt);
        if (st != GEOM_OK)
            goto done;
        for (size_t t = 0; t < nt; t++) {
            uint32_t codes[3], src[3] = {INV, INV, INV};
            uint8_t kind[3] = {CK_CAP, CK_CAP, CK_CAP};
            for (int j = 0; j < 3; j++)
                codes[j] = b.lv[b.poly[b.tris[3 * t + j]]];
            if (codes[0] == codes[1] || codes[1] == codes[2] || codes[0] == codes[2])
                continue;
            st = soup_face(c, 3, codes, src, kind, INV);
            if (st != GEOM_OK)
                goto done;
        }
    }

done:
    cap_free(al, &b);
    return st;
}

/* ---------------------------------------------------------------- driver */

typedef struct src_info {
    uint32_t a, b; /* original vertices; b == INV for a kept vertex */
    double t;
} src_info;

static geom_status copy_meta(const geom_mesh *m, geom_mesh *o, const clip_ctx *c,
                             const uint32_t *fmap)
{
    geom_status st = GEOM_OK;
    for (size_t i = 0; i < geom_mesh_mtllib_count(m); i++) {
        st = geom_mesh_mtllib_add(o, geom_mesh_mtllib_get(m, i));
        if (st != GEOM_OK)
            return st;
    }
    const uint32_t *g = geom_mesh_face_cgroups(m);
    if (!g)
        return GEOM_OK;
    for (size_t i = 0; i < geom_mesh_group_count(m); i++) {
        geom_mesh_group gr;
        st = geom_mesh_group_get(m, i, &gr);
        if (st == GEOM_OK)
            st = geom_mesh_group_add(o, &gr, NULL);
        if (st != GEOM_OK)
            return st;
    }
    uint32_t *og = geom_mesh_face_groups(o);
    if (!og && o->nf > 0)
        return GEOM_ERR_NOMEM;
    for (size_t f = 0; f < o->nf; f++) {
        uint32_t sf = fmap ? fmap[f] : (uint32_t)f;
        uint32_t of = sf < c->nf ? c->forig[sf] : INV;
        og[f] = of == INV ? INV : g[of];
    }
    return GEOM_OK;
}

/* The attribute streams of the output soup (every channel but EDGE ones),
 * built before the mesh so geom_mesh_build attaches them in one go. */
typedef struct clip_streams {
    geom_mesh_build_channel *ch; /* one per VERTEX/FACE/CORNER input channel */
    size_t n;
    double **vals;  /* owned values, per stream */
    size_t *nvals;  /* doubles allocated */
    uint32_t **idx; /* owned corner indices (CORNER streams) */
    size_t nidx;    /* entries of each idx array */
} clip_streams;

static void clip_streams_free(const geom_allocator *al, clip_streams *S, size_t nin)
{
    /* the entries are initialised only when all four arrays were allocated */
    for (size_t i = 0; S->ch && S->vals && S->nvals && S->idx && i < nin; i++) {
        geom__free(al, S->vals[i], (S->nvals[i] ? S->nvals[i] : 1) * sizeof(double));
        geom__free(al, S->idx[i], (S->nidx ? S->nidx : 1) * sizeof(uint32_t));
    }
    geom__free(al, S->ch, (nin ? nin : 1) * sizeof *S->ch);
    geom__free(al, S->vals, (nin ? nin : 1) * sizeof *S->vals);
    geom__free(al, S->nvals, (nin ? nin : 1) * sizeof *S->nvals);
    geom__free(al, S->idx, (nin ? nin : 1) * sizeof *S->idx);
    memset(S, 0, sizeof *S);
}

/* Soup faces geom_mesh_build would skip (fewer than 3 or repeated
 * vertices): their corners get no values, as they get no faces. */
static geom_status soup_face_ok(const geom_allocator *al, const clip_ctx *c, const uint32_t *indices,
                                const uint32_t *soff, size_t nout, uint8_t **out)
{
    uint8_t *ok = geom__alloc(al, c->nf ? c->nf : 1);
    uint32_t *stamp = geom__alloc(al, (nout ? nout : 1) * sizeof(uint32_t));
    if (!ok || !stamp) {
        geom__free(al, ok, c->nf ? c->nf : 1);
        geom__free(al, stamp, (nout ? nout : 1) * sizeof(uint32_t));
        return GEOM_ERR_NOMEM;
    }
    for (size_t v = 0; v < nout; v++)
        stamp[v] = INV;
    for (size_t f = 0; f < c->nf; f++) {
        ok[f] = c->fsize[f] >= 3;
        for (uint32_t q = soff[f]; q < soff[f + 1] && ok[f]; q++) {
            uint32_t v = indices[q];
            if (v >= nout || stamp[v] == (uint32_t)f)
                ok[f] = 0;
            else
                stamp[v] = (uint32_t)f;
        }
    }
    geom__free(al, stamp, (nout ? nout : 1) * sizeof(uint32_t));
    *out = ok;
    return GEOM_OK;
}

static geom_status make_streams(const geom_mesh *m, const clip_ctx *c, const src_info *vsrc,
                                size_t nvout, const uint32_t *soff, const uint8_t *face_ok,
                                const uint32_t *cutrank, size_t ncut, clip_streams *S)
{
    const geom_allocator *al = c->al;
    const size_t nin = m->n_channels;
    geom_status st = GEOM_OK;
    uint32_t *cp_idx = NULL, *cp_a = NULL, *cp_b = NULL;
    double capn[3] = {-c->n[0], -c->n[1], -c->n[2]};
    S->nidx = soff[c->nf];
    S->ch = geom__alloc(al, (nin ? nin : 1) * sizeof *S->ch);
    S->vals = geom__alloc(al, (nin ? nin : 1) * sizeof *S->vals);
    S->nvals = geom__alloc(al, (nin ? nin : 1) * sizeof *S->nvals);
    S->idx = geom__alloc(al, (nin ? nin : 1) * sizeof *S->idx);
    if (!S->ch || !S->vals || !S->nvals || !S->idx)
        return GEOM_ERR_NOMEM;
    for (size_t i = 0; i < nin; i++) {
        S->vals[i] = NULL;
        S->nvals[i] = 0;
        S->idx[i] = NULL;
    }
    for (uint32_t ci = 1; ci < nin; ci++) {
        const geom__mesh_channel *ch = &m->channels[ci];
        const size_t nc = ch->ncomp;
        int is_normal = nc == 3 && strcmp(ch->name, "normal") == 0;
        geom_mesh_build_channel *out = &S->ch[S->n];
        size_t nv = ch->domain == GEOM_MESH_DOMAIN_VERTEX ? nvout
                    : ch->domain == GEOM_MESH_DOMAIN_FACE ? c->nf
                                                          : ch->pool + 2 * ncut + 1;
        if (ch->domain == GEOM_MESH_DOMAIN_EDGE)
            continue; /* after the build: edges do not exist before */
        double *d = geom__alloc(al, (nv * nc > 0 ? nv * nc : 1) * sizeof(double));
        if (!d) {
            st = GEOM_ERR_NOMEM;
            goto done;
        }
        S->vals[S->n] = d;
        S->nvals[S->n] = nv * nc;
        memset(d, 0, nv * nc * sizeof(double));
        memset(out, 0, sizeof *out);
        out->name = ch->name;
        out->domain = ch->domain;
        out->ncomp = nc;
        out->values = d;
        if (ch->domain == GEOM_MESH_DOMAIN_VERTEX) {
            for (size_t v = 0; v < nvout; v++) {
                const src_info *si = &vsrc[v];
                const double *a = ch->data + (size_t)si->a * nc;
                if (si->b == INV) {
                    memcpy(d + v * nc, a, nc * sizeof(double));
                } else {
                    const double *bb = ch->data + (size_t)si->b * nc;
                    for (size_t k = 0; k < nc; k++)
                        d[v * nc + k] = a[k] + si->t * (bb[k] - a[k]);
                }
            }
        } else if (ch->domain == GEOM_MESH_DOMAIN_FACE) {
            for (size_t f = 0; f < c->nf; f++) {
                uint32_t of = c->forig[f];
                if (of != INV)
                    memcpy(d + f * nc, ch->data + (size_t)of * nc, nc * sizeof(double));
                else if (is_normal)
                    memcpy(d + f * nc, capn, sizeof capn);
            }
        } else {
            /* CORNER: the input pool, then the values of new corners made as
             * they are met (soup faces in order, corners in order) */
            const size_t P = ch->pool;
            const uint32_t *idx = ch->corner;
            uint32_t *cix = geom__alloc(al, (S->nidx ? S->nidx : 1) * sizeof(uint32_t));
            if (!cix) {
                st = GEOM_ERR_NOMEM;
                goto done;
            }
            S->idx[S->n] = cix;
            if (P)
                memcpy(d, ch->data, P * nc * sizeof(double));
            size_t np = P;
            uint32_t cap_entry = INV;
            if (!cp_idx) {
                cp_idx = geom__alloc(al, (2 * ncut + 1) * 4);
                cp_a = geom__alloc(al, (2 * ncut + 1) * 4);
                cp_b = geom__alloc(al, (2 * ncut + 1) * 4);
                if (!cp_idx || !cp_a || !cp_b) {
                    st = GEOM_ERR_NOMEM;
                    goto done;
                }
            }
            for (size_t i = 0; i < 2 * ncut; i++)
                cp_idx[i] = INV;
            for (size_t sf = 0; sf < c->nf; sf++) {
                for (size_t q = soff[sf]; q < soff[sf + 1]; q++) {
                    uint32_t res = INV;
                    if (!face_ok[sf]) {
                        cix[q] = INV;
                        continue;
                    }
                    if (c->ckind[q] == CK_KEEP) {
                        res = idx[c->csrc[q]];
                    } else if (c->ckind[q] == CK_CUT) {
                        uint32_t g = c->csrc[q], e = g >> 1, A, B;
                        double t;
                        cut_param(c, e, &A, &B, &t);
                        uint32_t ia, ib;
                        if ((g & 1u) == 0) {
                            ib = idx[g];
                            ia = idx[m->he_prev[g]];
                        } else {
                            ia = idx[g];
                            ib = idx[m->he_prev[g]];
                        }
                        if (ia != INV && ib != INV && ia < P && ib < P) {
                            size_t slot = 2 * (size_t)cutrank[e] + (g & 1u);
                            size_t other = slot ^ 1u;
                            if (cp_idx[slot] != INV) {
                                res = cp_idx[slot];
                            } else if (cp_idx[other] != INV && cp_a[other] == ia &&
                                       cp_b[other] == ib) {
                                res = cp_idx[other];
                            } else {
                                const double *va = ch->data + (size_t)ia * nc;
                                const double *vb = ch->data + (size_t)ib * nc;
                                for (size_t kk = 0; kk < nc; kk++)
                                    d[np * nc + kk] = va[kk] + t * (vb[kk] - va[kk]);
                                res = (uint32_t)np++;
                            }
                            cp_idx[slot] = res;
                            cp_a[slot] = ia;
                            cp_b[slot] = ib;
                        }
                    } else {
                        if (cap_entry == INV) {
                            cap_entry = (uint32_t)np++;
                            for (size_t kk = 0; kk < nc; kk++)
                                d[(size_t)cap_entry * nc + kk] = is_normal ? capn[kk] : 0.0;
                        }
                        res = cap_entry;
                    }
                    cix[q] = res;
                }
            }
            out->n_values = np;
            out->indices = cix;
        }
        S->n++;
    }
done:
    geom__free(al, cp_idx, (2 * ncut + 1) * 4);
    geom__free(al, cp_a, (2 * ncut + 1) * 4);
    geom__free(al, cp_b, (2 * ncut + 1) * 4);
    return st;
}

/* EDGE channels, after the build: the kept parts of old edges keep their
 * values, new edges get zeros. */
static geom_status copy_edge_channels(const geom_mesh *m, geom_mesh *o, const src_info *vsrc,
                                      size_t nvout)
{
    const uint32_t *vorig = geom_mesh_vertex_origin(o);
    for (uint32_t ci = 1; ci < m->n_channels; ci++) {
        const geom__mesh_channel *ch = &m->channels[ci];
        if (ch->domain != GEOM_MESH_DOMAIN_EDGE)
            continue;
        uint32_t oid;
        geom_status st = geom_mesh_channel_add(o, ch->name, ch->domain, ch->ncomp, &oid);
        if (st != GEOM_OK)
            return st;
        const size_t nc = ch->ncomp;
        double *d = geom_mesh_channel_data(o, oid);
        for (size_t e = 0; e < o->nh / 2; e++) {
            if (o->e_del[e])
                continue;
            uint32_t x = o->he_vertex[2 * e], y = o->he_vertex[2 * e + 1];
            uint32_t sx = vorig ? vorig[x] : x, sy = vorig ? vorig[y] : y;
            if (sx >= nvout || sy >= nvout)
                continue;
            const src_info *a = &vsrc[sx], *bb = &vsrc[sy];
            uint32_t oe = INV;
            if (a->b == INV && bb->b == INV) {
                oe = geom_mesh_find_edge(m, a->a, bb->a);
            } else if (a->b == INV || bb->b == INV) {
                const src_info *kept = a->b == INV ? a : bb, *cut = a->b == INV ? bb : a;
                if (kept->a == cut->a || kept->a == cut->b)
                    oe = geom_mesh_find_edge(m, cut->a, cut->b);
            }
            if (oe != INV)
                memcpy(d + e * nc, ch->data + (size_t)oe * nc, nc * sizeof(double));
        }
    }
    return GEOM_OK;
}

geom_status geom_mesh_clip_plane(const geom_mesh *m, const double plane[4],
                                 const geom_clip_options *opt, geom_mesh **out)
{
    if (out)
        *out = NULL;
    if (!m || !plane || !out)
        return GEOM_ERR_INVALID_ARG;
    for (int k = 0; k < 4; k++) {
        if (!isfinite(plane[k]))
            return GEOM_ERR_INVALID_ARG;
    }
    double sc = fmax(fabs(plane[0]), fmax(fabs(plane[1]), fabs(plane[2])));
    if (!(sc > 0.0))
        return GEOM_ERR_DEGENERATE;
    clip_ctx c;
    memset(&c, 0, sizeof c);
    {
        double a = plane[0] / sc, b = plane[1] / sc, cc = plane[2] / sc;
        double l = sqrt(a * a + b * b + cc * cc);
        c.n[0] = a / l;
        c.n[1] = b / l;
        c.n[2] = cc / l;
        c.d = plane[3] / sc / l;
    }
    c.m = m;
    c.al = &m->alloc;
    c.pos = geom__mesh_pos(m);
    const geom_allocator *al = c.al;
    const size_t nv = m->nv, ne = m->nh / 2;
    int cap = opt ? opt->cap : 0;
    geom_status st = GEOM_OK;
    double *snapped = NULL, *xyz = NULL;
    uint32_t *newid = NULL, *indices = NULL, *soff = NULL, *cutrank = NULL;
    src_info *vsrc = NULL;
    face_buf fb;
    memset(&fb, 0, sizeof fb);
    geom_mesh *o = NULL;
    size_t ncodes = nv + ne, nout = 0, ncut = 0;

    /* tolerance from the bounding box diagonal */
    geom_aabb bb = geom_mesh_bbox(m);
    double diag = 0.0;
    if (!geom_aabb_is_empty(bb)) {
        double dx = bb.max.x * 0.5 - bb.min.x * 0.5, dy = bb.max.y * 0.5 - bb.min.y * 0.5,
               dz = bb.max.z * 0.5 - bb.min.z * 0.5;
        diag = 2.0 * geom_vec3_length(geom_vec3_make(dx, dy, dz));
    }
    double tol = isfinite(diag) ? 1e-12 * diag : 0.0;

    c.s = geom__alloc(al, (nv ? nv : 1) * sizeof(double));
    c.sg = geom__alloc(al, nv ? nv : 1);
    snapped = geom__alloc(al, (nv ? nv : 1) * 3 * sizeof(double));
    if (!c.s || !c.sg || !snapped) {
        st = GEOM_ERR_NOMEM;
        goto done;
    }
    size_t n_nonpos = 0;
    for (size_t v = 0; v < nv; v++) {
        const double *p = c.pos + 3 * v;
        double s = c.n[0] * p[0] + c.n[1] * p[1] + c.n[2] * p[2] + c.d;
        memcpy(snapped + 3 * v, p, 3 * sizeof(double));
        if (m->v_del[v]) {
            c.s[v] = -1.0;
            c.sg[v] = -1;
            continue;
        }
        if (!isfinite(s)) {
            c.s[v] = -1.0;
            c.sg[v] = -1; /* non-finite positions are dropped */
        } else if (fabs(s) <= tol) {
            c.s[v] = 0.0;
            c.sg[v] = 0;
            for (int k = 0; k < 3; k++)
                snapped[3 * v + k] = p[k] - s * c.n[k];
        } else {
            c.s[v] = s;
            c.sg[v] = s > 0.0 ? 1 : -1;
        }
        if (c.sg[v] <= 0)
            n_nonpos++;
    }
    if (n_nonpos == 0) {
        st = geom_mesh_clone(m, out);
        goto done;
    }

    for (size_t f = 0; f < m->nf; f++) {
        if (m->f_del[f])
            continue;
        st = clip_face(&c, snapped, (uint32_t)f, &fb);
        if (st != GEOM_OK)
            goto done;
    }
    if (cap) {
        st = make_caps(&c, snapped);
        if (st != GEOM_OK)
            goto done;
    }

    /* number the output vertices: kept original ones, then cut points */
    newid = geom__alloc(al, (ncodes ? ncodes : 1) * sizeof(uint32_t));
    cutrank = geom__alloc(al, (ne ? ne : 1) * sizeof(uint32_t));
    soff = geom__alloc(al, (c.nf + 1) * sizeof(uint32_t));
    if (!newid || !cutrank || !soff) {
        st = GEOM_ERR_NOMEM;
        goto done;
    }
    for (size_t i = 0; i < ncodes; i++)
        newid[i] = 0;
    for (size_t i = 0; i < c.ni; i++)
        newid[c.code[i]] = 1;
    for (size_t v = 0; v < nv; v++) {
        if (!m->v_del[v] && m->v_he[v] == INV && c.sg[v] >= 0)
            newid[v] = 1; /* isolated vertices on the kept side stay */
    }
    for (size_t i = 0; i < ncodes; i++) {
        if (newid[i]) {
            newid[i] = (uint32_t)nout++;
            if (i >= nv)
                cutrank[i - nv] = (uint32_t)ncut++;
        } else {
            newid[i] = INV;
            if (i >= nv)
                cutrank[i - nv] = INV;
        }
    }
    xyz = geom__alloc(al, (nout ? nout : 1) * 3 * sizeof(double));
    vsrc = geom__alloc(al, (nout ? nout : 1) * sizeof(src_info));
    indices = geom__alloc(al, (c.ni ? c.ni : 1) * sizeof(uint32_t));
    if (!xyz || !vsrc || !indices) {
        st = GEOM_ERR_NOMEM;
        goto done;
    }
    for (size_t i = 0; i < ncodes; i++) {
        uint32_t id = newid[i];
        if (id == INV)
            continue;
        code_point(&c, snapped, (uint32_t)i, xyz + 3 * (size_t)id);
        if (i < nv) {
            vsrc[id].a = (uint32_t)i;
            vsrc[id].b = INV;
            vsrc[id].t = 0.0;
        } else {
            cut_param(&c, (uint32_t)(i - nv), &vsrc[id].a, &vsrc[id].b, &vsrc[id].t);
        }
    }
    for (size_t i = 0; i < c.ni; i++)
        indices[i] = newid[c.code[i]];
    soff[0] = 0;
    for (size_t f = 0; f < c.nf; f++)
        soff[f + 1] = soff[f] + c.fsize[f];

    {
        uint8_t *face_ok = NULL;
        clip_streams S;
        memset(&S, 0, sizeof S);
        st = soup_face_ok(al, &c, indices, soff, nout, &face_ok);
        if (st == GEOM_OK)
            st = make_streams(m, &c, vsrc, nout, soff, face_ok, cutrank, ncut, &S);
        if (st == GEOM_OK && !(o = geom_mesh_create(al)))
            st = GEOM_ERR_NOMEM;
        if (st == GEOM_OK) {
            geom_mesh_build_options bo;
            memset(&bo, 0, sizeof bo);
            bo.keep_orientation = 1;
            bo.skip_invalid_faces = 1;
            bo.channels = S.ch;
            bo.n_channels = S.n;
            st = geom_mesh_build(o, nout, xyz, c.nf, c.fsize, indices, &bo, NULL, NULL);
        }
        clip_streams_free(al, &S, m->n_channels);
        geom__free(al, face_ok, c.nf ? c.nf : 1);
        if (st != GEOM_OK)
            goto done;
    }
    st = copy_edge_channels(m, o, vsrc, nout);
    if (st == GEOM_OK)
        st = copy_meta(m, o, &c, geom_mesh_face_origin(o));
    if (st != GEOM_OK)
        goto done;
    *out = o;
    o = NULL;

done:
    geom_mesh_destroy(o);
    face_buf_free(al, &fb);
    geom__free(al, c.s, (nv ? nv : 1) * sizeof(double));
    geom__free(al, c.sg, nv ? nv : 1);
    geom__free(al, snapped, (nv ? nv : 1) * 3 * sizeof(double));
    geom__free(al, c.fsize, c.fcap * 4);
    geom__free(al, c.forig, c.fcap2 * 4);
    geom__free(al, c.code, c.icap * 4);
    geom__free(al, c.csrc, c.icap2 * 4);
    geom__free(al, c.ckind, c.icap3);
    geom__free(al, newid, (ncodes ? ncodes : 1) * sizeof(uint32_t));
    geom__free(al, cutrank, (ne ? ne : 1) * sizeof(uint32_t));
    geom__free(al, soff, (c.nf + 1) * sizeof(uint32_t));
    geom__free(al, xyz, (nout ? nout : 1) * 3 * sizeof(double));
    geom__free(al, vsrc, (nout ? nout : 1) * sizeof(src_info));
    geom__free(al, indices, (c.ni ? c.ni : 1) * sizeof(uint32_t));
    return st;
}

geom_status geom_mesh_clip_frustum(const geom_mesh *m, geom_mat4 view_proj,
                                   const geom_clip_options *opt, geom_mesh **out)
{
    if (out)
        *out = NULL;
    if (!m || !out)
        return GEOM_ERR_INVALID_ARG;
    for (int k = 0; k < 16; k++) {
        if (!isfinite(view_proj.m[k]))
            return GEOM_ERR_INVALID_ARG;
    }
    /* Gribb & Hartmann: rows r_i of the matrix; inside: r3.x +- r_i.x >= 0 */
    double row[4][4];
    for (int r = 0; r < 4; r++)
        for (int col = 0; col < 4; col++)
            row[r][col] = view_proj.m[4 * col + r];
    double planes[6][4];
    for (int i = 0; i < 3; i++) {
        for (int k = 0; k < 4; k++) {
            planes[2 * i][k] = row[3][k] + row[i][k];
            planes[2 * i + 1][k] = row[3][k] - row[i][k];
        }
    }
    geom_mesh *cur = NULL;
    geom_status st = geom_mesh_clone(m, &cur);
    if (st != GEOM_OK)
        return st;
    for (int i = 0; i < 6; i++) {
        const double *pl = planes[i];
        if (pl[0] == 0.0 && pl[1] == 0.0 && pl[2] == 0.0) {
            if (pl[3] >= 0.0)
                continue; /* the whole space is inside */
            /* nothing is inside: the empty mesh */
            geom_mesh *e = geom_mesh_create(&m->alloc);
            if (!e) {
                geom_mesh_destroy(cur);
                return GEOM_ERR_NOMEM;
            }
            geom_mesh_destroy(cur);
            *out = e;
            return GEOM_OK;
        }
        geom_mesh *next = NULL;
        st = geom_mesh_clip_plane(cur, pl, opt, &next);
        geom_mesh_destroy(cur);
        if (st != GEOM_OK)
            return st;
        cur = next;
    }
    *out = cur;
    return GEOM_OK;
}
