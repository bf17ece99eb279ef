/*
 * Polygon triangulation by monotone decomposition in O(n log n): Lee &
 * Preparata 1977 and Garey, Johnson, Preparata & Tarjan 1978, as presented
 * in de Berg, Cheong, van Kreveld & Overmars, "Computational Geometry:
 * Algorithms and Applications", 3rd ed., ch. 3 (MakeMonotone with
 * HandleStart/End/Split/Merge/RegularVertex, then
 * TriangulateMonotonePolygon).
 *
 * Steps:
 *  1. Forced degeneracies are clipped first, in O(n): a vertex equal to a
 *     neighbour, or the tip of a zero-width spike (its neighbours collinear
 *     with it on the same side), can only be in a zero-area triangle in any
 *     triangulation; it is cut off as the triangle (prev, v, next).
 *  2. The remaining polygon is made counter-clockwise exactly (the turn at
 *     its lowest vertex, by geom_orient2d), mirroring x/y if needed.
 *  3. Sweep top to bottom in the order (y descending, then x ascending, then
 *     index: a symbolic rotation, so no two vertices share a sweep position).
 *     Vertices are start/end/split/merge/regular by that order and the exact
 *     turn; the status is a treap of the edges with the interior on their
 *     right, keyed by x at the sweep line (every comparison is an exact
 *     orient2d sign), each with its helper. Split and merge vertices get the
 *     book's diagonals.
 *  4. Around each vertex, its diagonals are sorted by exact angle inside its
 *     interior wedge; the faces of the polygon + diagonals are walked
 *     (expected: diagonals + 1 faces, each y-monotone).
 *  5. Each face is triangulated by the book's linear stack algorithm. A
 *     triangle that would not be strictly positive (orient2d > 0) makes
 *     that face fall back to the ear clipper (collinear runs can force the
 *     stack algorithm's choice).
 *
 * Any inconsistency (an edge missing from the status, no edge left of a
 * split or merge vertex, the wrong face count, a straight spike the sweep
 * cannot classify) rejects the polygon with GEOM_ERR_DEGENERATE: for a
 * simple polygon none of them happens, so a rejection means a non-simple
 * input, and the caller's ear clipper takes over.
 */
#include "mesh/triangulate_internal.h"

#include "core/internal.h"

#include <string.h>

#define NIL UINT32_MAX

typedef struct sw {
    size_t m;            /* vertices after step 1 */
    double *xy;          /* 2*m local coordinates (x, y), exact input doubles */
    uint32_t *org;       /* local -> input index */
    uint32_t *rank;      /* sweep position of each local vertex (0 = top) */
    /* status treap over edges e = (e, e+1) */
    uint32_t *tl, *tr, *tp, *tpri, *helper, root;
    uint8_t *merge, *in_t;
    uint32_t *dg; /* diagonals: dg[2k], dg[2k+1] */
    size_t nd, dcap;
} sw;

static double ori(const sw *s, uint32_t a, uint32_t b, uint32_t c)
{
    return geom_orient2d(s->xy + 2 * (size_t)a, s->xy + 2 * (size_t)b, s->xy + 2 * (size_t)c);
}

/* a is before b in the sweep (strict total order on local indices). */
static int above(const double *xy, uint32_t a, uint32_t b)
{
    double ya = xy[2 * (size_t)a + 1], yb = xy[2 * (size_t)b + 1];
    if (ya != yb)
        return ya > yb;
    double xa = xy[2 * (size_t)a], xb = xy[2 * (size_t)b];
    if (xa != xb)
        return xa < xb;
    return a < b;
}

/* Sort keys: the coordinates next to the index, so the merge passes stream
 * through memory instead of fetching xy at random. */
typedef struct skey {
    double y, x;
    uint32_t i, pad;
} skey;

static int key_above(const skey *a, const skey *b)
{
    if (a->y != b->y)
        return a->y > b->y;
    if (a->x != b->x)
        return a->x < b->x;
    return a->i < b->i;
}

/* Bottom-up merge sort of k (n keys) by the sweep order; tmp: n keys.
 * Returns the array holding the result (k or tmp). */
static skey *sweep_sort(skey *k, skey *tmp, size_t n)
{
    skey *a = k, *b = tmp;
    for (size_t w = 1; w < n; w *= 2) {
        for (size_t lo = 0; lo < n; lo += 2 * w) {
            size_t mid = lo + w < n ? lo + w : n, hi = lo + 2 * w < n ? lo + 2 * w : n;
            size_t i = lo, j = mid, o = lo;
            while (i < mid && j < hi)
                b[o++] = key_above(a + j, a + i) ? a[j++] : a[i++];
            while (i < mid)
                b[o++] = a[i++];
            while (j < hi)
                b[o++] = a[j++];
        }
        skey *t = a;
        a = b;
        b = t;
    }
    return a;
}

/* ----------------------------------------------------------- status treap */

static uint32_t hash32(uint32_t x)
{
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

static void set_child(sw *s, uint32_t p, uint32_t old, uint32_t x)
{
    if (p == NIL)
        s->root = x;
    else if (s->tl[p] == old)
        s->tl[p] = x;
    else
        s->tr[p] = x;
}

/* Rotate x above its parent. */
static void rot_up(sw *s, uint32_t x)
{
    uint32_t p = s->tp[x], g = s->tp[p];
    if (s->tl[p] == x) {
        s->tl[p] = s->tr[x];
        if (s->tr[x] != NIL)
            s->tp[s->tr[x]] = p;
        s->tr[x] = p;
    } else {
        s->tr[p] = s->tl[x];
        if (s->tl[x] != NIL)
            s->tp[s->tl[x]] = p;
        s->tl[x] = p;
    }
    s->tp[p] = x;
    s->tp[x] = g;
    set_child(s, g, p, x);
}

/* Insert edge x immediately right of edge a (a == NIL: leftmost). */
static void t_insert_after(sw *s, uint32_t a, uint32_t x)
{
    s->tl[x] = s->tr[x] = NIL;
    s->tpri[x] = hash32(x);
    s->in_t[x] = 1;
    if (s->root == NIL) {
        s->root = x;
        s->tp[x] = NIL;
        return;
    }
    uint32_t at;
    int left = 1;
    if (a == NIL)
        at = s->root;
    else if (s->tr[a] == NIL) {
        at = a;
        left = 0;
    } else
        at = s->tr[a];
    if (left)
        while (s->tl[at] != NIL)
            at = s->tl[at];
    if (left)
        s->tl[at] = x;
    else
        s->tr[at] = x;
    s->tp[x] = at;
    while (s->tp[x] != NIL && s->tpri[x] > s->tpri[s->tp[x]])
        rot_up(s, x);
}

static void t_delete(sw *s, uint32_t x)
{
    while (s->tl[x] != NIL && s->tr[x] != NIL)
        rot_up(s, s->tpri[s->tl[x]] > s->tpri[s->tr[x]] ? s->tl[x] : s->tr[x]);
    uint32_t c = s->tl[x] != NIL ? s->tl[x] : s->tr[x], p = s->tp[x];
    if (c != NIL)
        s->tp[c] = p;
    set_child(s, p, x, c);
    s->in_t[x] = 0;
}

/* Edge y takes edge x's place (same position in the order). */
static void t_replace(sw *s, uint32_t x, uint32_t y)
{
    s->tl[y] = s->tl[x];
    s->tr[y] = s->tr[x];
    s->tp[y] = s->tp[x];
    s->tpri[y] = s->tpri[x];
    if (s->tl[y] != NIL)
        s->tp[s->tl[y]] = y;
    if (s->tr[y] != NIL)
        s->tp[s->tr[y]] = y;
    set_child(s, s->tp[y], x, y);
    s->in_t[x] = 0;
    s->in_t[y] = 1;
}

/* The status edge directly left of vertex v (strictly: orient2d > 0 along
 * the edge's downward direction); NIL if none. */
static uint32_t t_left_of(const sw *s, uint32_t v)
{
    uint32_t c = s->root, best = NIL;
    size_t m = s->m;
    while (c != NIL) {
        uint32_t d = (uint32_t)(c + 1 < m ? c + 1 : 0);
        if (ori(s, c, d, v) > 0.0) {
            best = c;
            c = s->tr[c];
        } else
            c = s->tl[c];
    }
    return best;
}

static int add_diag(sw *s, uint32_t a, uint32_t b)
{
    size_t m = s->m;
    if (a == b || s->nd >= s->dcap || (a + 1) % m == b || (b + 1) % m == a)
        return 0;
    s->dg[2 * s->nd] = a;
    s->dg[2 * s->nd + 1] = b;
    s->nd++;
    return 1;
}

/* De Berg et al.'s fix-up: when the helper of edge e is a merge vertex, the
 * diagonal from v to it. 0 when the diagonal cannot be added. */
static int fix_up(sw *s, uint32_t v, uint32_t e)
{
    return !s->merge[s->helper[e]] || add_diag(s, v, s->helper[e]);
}

/* The edge directly left of v, fixed up, gets v as its helper (merge
 * vertices, and regular ones with the interior to their left). 0 on
 * inconsistency. */
static int left_helper(sw *s, uint32_t v)
{
    uint32_t ej = t_left_of(s, v);
    if (ej == NIL || !fix_up(s, v, ej))
        return 0;
    s->helper[ej] = v;
    return 1;
}

/* Steps 3: the diagonals of the monotone decomposition; 0 on inconsistency. */
static int make_monotone(sw *s, const uint32_t *order)
{
    size_t m = s->m;
    s->root = NIL;
    memset(s->in_t, 0, m);
    memset(s->merge, 0, m);
    for (size_t k = 0; k < m; ++k) {
        uint32_t v = order[k], p = (uint32_t)(v ? v - 1 : m - 1), q = (uint32_t)(v + 1 < m ? v + 1 : 0);
        int pa = s->rank[p] < s->rank[v], qa = s->rank[q] < s->rank[v];
        if (!pa && !qa) {
            double o = ori(s, p, v, q);
            if (o == 0.0)
                return 0;
            uint32_t ej = t_left_of(s, v);
            if (o < 0.0) { /* split */
                if (ej == NIL || !add_diag(s, v, s->helper[ej]))
                    return 0;
                s->helper[ej] = v;
            }
            t_insert_after(s, ej, v); /* start or split: edge v goes in */
            s->helper[v] = v;
        } else if (pa && qa) {
            double o = ori(s, p, v, q);
            if (o == 0.0 || !s->in_t[p])
                return 0;
            if (!fix_up(s, v, p))
                return 0;
            t_delete(s, p);
            if (o < 0.0) { /* merge */
                s->merge[v] = 1;
                if (!left_helper(s, v))
                    return 0;
            }
        } else if (pa) { /* regular, interior to the right: edge p ends, edge v starts */
            if (!s->in_t[p])
                return 0;
            if (!fix_up(s, v, p))
                return 0;
            t_replace(s, p, v);
            s->helper[v] = v;
        } else if (!left_helper(s, v)) { /* regular, interior to the left */
            return 0;
        }
    }
    return s->root == NIL;
}

/* ------------------------------------------------ faces and their angles */

static int sgn(double a, double b) { return (a > b) - (a < b); }

/* 0 if direction v->d is within [0, pi) counter-clockwise from v->a, else 1 */
static int half(const sw *s, uint32_t v, uint32_t a, uint32_t d)
{
    double o = ori(s, v, a, d);
    if (o != 0.0)
        return o < 0.0;
    const double *pv = s->xy + 2 * (size_t)v, *pa = s->xy + 2 * (size_t)a,
                 *pd = s->xy + 2 * (size_t)d;
    int same = sgn(pa[0], pv[0]) == sgn(pd[0], pv[0]) && sgn(pa[1], pv[1]) == sgn(pd[1], pv[1]);
    return !same;
}

/* Direction v->a comes before v->b counter-clockwise from v->ref. */
static int ccw_before(const sw *s, uint32_t v, uint32_t ref, uint32_t a, uint32_t b)
{
    int ha = half(s, v, ref, a), hb = half(s, v, ref, b);
    if (ha != hb)
        return ha < hb;
    return ori(s, v, a, b) > 0.0;
}

/* ------------------------------------------- monotone piece (step 5) */

typedef struct piece {
    uint32_t *tris; /* output, input indices */
    size_t nt;
    int bad;
} piece;

static void emit(const sw *s, piece *pc, uint32_t a, uint32_t b, uint32_t c)
{
    if (!(ori(s, a, b, c) > 0.0))
        pc->bad = 1;
    uint32_t *t = pc->tris + 3 * pc->nt++;
    t[0] = s->org[a];
    t[1] = s->org[b];
    t[2] = s->org[c];
}

/* The stack algorithm on face f (k >= 3 local vertices, counter-clockwise);
 * u, ch, st: k scratch entries each. */
static void triangulate_monotone(const sw *s, piece *pc, const uint32_t *f, size_t k, uint32_t *u,
                                 uint8_t *ch, uint32_t *st)
{
    size_t it = 0, ib = 0;
    for (size_t i = 1; i < k; ++i) {
        if (s->rank[f[i]] < s->rank[f[it]])
            it = i;
        if (s->rank[f[i]] > s->rank[f[ib]])
            ib = i;
    }
    /* merge the left chain (forward from the top) and the right chain */
    size_t li = (it + 1) % k, ri = (it + k - 1) % k, c = 1;
    u[0] = f[it];
    ch[0] = 0;
    while (li != ib || ri != ib) {
        if (ri == ib || (li != ib && s->rank[f[li]] < s->rank[f[ri]])) {
            u[c] = f[li];
            ch[c++] = 0;
            li = (li + 1) % k;
        } else {
            u[c] = f[ri];
            ch[c++] = 1;
            ri = (ri + k - 1) % k;
        }
    }
    u[c] = f[ib];
    ch[c] = 2;
    /* st holds positions in u */
    size_t S = 0;
    st[S++] = 0;
    st[S++] = 1;
    for (size_t j = 2; j + 1 < k; ++j) {
        if (ch[j] != ch[st[S - 1]]) {
            for (size_t t = S - 1; t >= 1; --t) {
                if (ch[j] == 0)
                    emit(s, pc, u[j], u[st[t]], u[st[t - 1]]);
                else
                    emit(s, pc, u[j], u[st[t - 1]], u[st[t]]);
            }
            st[0] = (uint32_t)(j - 1);
            st[1] = (uint32_t)j;
            S = 2;
        } else {
            uint32_t last = st[--S];
            while (S > 0) {
                uint32_t w = st[S - 1];
                if (ch[j] == 0) {
                    if (!(ori(s, u[w], u[last], u[j]) > 0.0))
                        break;
                    emit(s, pc, u[w], u[last], u[j]);
                } else {
                    if (!(ori(s, u[j], u[last], u[w]) > 0.0))
                        break;
                    emit(s, pc, u[j], u[last], u[w]);
                }
                last = st[--S];
            }
            st[S++] = last;
            st[S++] = (uint32_t)j;
        }
    }
    size_t b = k - 1;
    int left = ch[st[S - 1]] == 0;
    for (size_t t = S - 1; t >= 1; --t) {
        if (left)
            emit(s, pc, u[b], u[st[t - 1]], u[st[t]]);
        else
            emit(s, pc, u[b], u[st[t]], u[st[t - 1]]);
    }
}

/* The ear clipper on one face (its local coordinates, counter-clockwise). */
static geom_status earclip_face(const sw *s, piece *pc, const uint32_t *f, size_t k)
{
    size_t nd = 3 * k, nu = 3 * (k - 2);
    double *p = geom__alloc(NULL, nd * sizeof(double));
    uint32_t *t = geom__alloc(NULL, nu * sizeof(uint32_t));
    if (!p || !t) {
        geom__free(NULL, p, nd * sizeof(double));
        geom__free(NULL, t, nu * sizeof(uint32_t));
        return GEOM_ERR_NOMEM;
    }
    for (size_t i = 0; i < k; ++i) {
        p[3 * i] = s->xy[2 * (size_t)f[i]];
        p[3 * i + 1] = s->xy[2 * (size_t)f[i] + 1];
        p[3 * i + 2] = 0.0;
    }
    geom_status st = geom__polygon_earclip(k, p, t);
    if (st == GEOM_ERR_NOMEM) {
        geom__free(NULL, p, nd * sizeof(double));
        geom__free(NULL, t, nu * sizeof(uint32_t));
        return st;
    }
    for (size_t i = 0; i < k - 2; ++i) {
        uint32_t *o = pc->tris + 3 * pc->nt++;
        for (int j = 0; j < 3; ++j)
            o[j] = s->org[f[t[3 * i + (size_t)j]]];
    }
    geom__free(NULL, p, nd * sizeof(double));
    geom__free(NULL, t, nu * sizeof(uint32_t));
    return GEOM_OK;
}

/* ------------------------------------------------------------- driver */

/* Local vertex b is a forced degeneracy between a and c: equal to one of
 * them, or the tip of a zero-width spike. */
static int forced(const double *xy, uint32_t a, uint32_t b, uint32_t c)
{
    const double *pa = xy + 2 * (size_t)a, *pb = xy + 2 * (size_t)b, *pc = xy + 2 * (size_t)c;
    if (geom_orient2d(pa, pb, pc) != 0.0)
        return 0;
    int sa = sgn(pb[0], pa[0]), sc = sgn(pb[0], pc[0]);
    if (sa == 0 && sc == 0) {
        sa = sgn(pb[1], pa[1]);
        sc = sgn(pb[1], pc[1]);
    }
    /* collinear: b between a and c iff it differs from both, on opposite sides */
    return !(sa != 0 && sc != 0 && sa != sc) || (pa[0] == pb[0] && pa[1] == pb[1]) ||
           (pc[0] == pb[0] && pc[1] == pb[1]);
}

geom_status geom__polygon_triangulate_sweep_ex(size_t n, const double *pts, int u, int v,
                                               uint32_t *tris, size_t *n_piece_fallbacks)
{
    if (n_piece_fallbacks)
        *n_piece_fallbacks = 0;
    if (n < 3 || n > (size_t)UINT32_MAX / 8)
        return GEOM_ERR_DEGENERATE;
    /* u32 pool: org, rank, dg (2n) persistent; then 16n shared by phases */
    size_t nu = 20 * n + 1, nb = 8 * n, ndb = 2 * n;
    uint32_t *ub = geom__alloc(NULL, nu * sizeof(uint32_t));
    uint8_t *bb = geom__alloc(NULL, nb);
    double *xy = geom__alloc(NULL, ndb * sizeof(double));
    if (!ub || !bb || !xy) {
        geom__free(NULL, ub, nu * sizeof(uint32_t));
        geom__free(NULL, bb, nb);
        geom__free(NULL, xy, ndb * sizeof(double));
        return GEOM_ERR_NOMEM;
    }
    geom_status st = GEOM_ERR_DEGENERATE;
    sw s;
    memset(&s, 0, sizeof s);
    s.xy = xy;
    s.org = ub;
    s.rank = ub + n;
    s.dg = ub + 2 * n;
    uint32_t *pool = ub + 4 * n;
    piece pc = {tris, 0, 0};

    /* 1: forced degeneracies (on input indices; prv/nxt/work in the pool) */
    uint32_t *prv = pool, *nxt = pool + n, *work = pool + 2 * n;
    for (size_t i = 0; i < n; ++i) {
        xy[2 * i] = pts[3 * i + (size_t)u];
        xy[2 * i + 1] = pts[3 * i + (size_t)v];
        prv[i] = (uint32_t)(i ? i - 1 : n - 1);
        nxt[i] = (uint32_t)(i + 1 < n ? i + 1 : 0);
        work[i] = (uint32_t)(n - 1 - i);
    }
    uint8_t *dead = bb, *inw = bb + n;
    memset(dead, 0, n);
    memset(inw, 1, n);
    size_t nw = n, left = n;
    while (nw > 0 && left > 3) {
        uint32_t b = work[--nw];
        inw[b] = 0;
        uint32_t a = prv[b], c = nxt[b];
        if (!forced(xy, a, b, c))
            continue;
        uint32_t *t = tris + 3 * pc.nt++;
        t[0] = a;
        t[1] = b;
        t[2] = c;
        dead[b] = 1;
        nxt[a] = c;
        prv[c] = a;
        left--;
        for (int j = 0; j < 2; ++j) { /* each alive vertex at most once in work */
            uint32_t w = j ? a : c;
            if (!inw[w]) {
                inw[w] = 1;
                work[nw++] = w;
            }
        }
    }
    size_t m = 0;
    for (size_t i = 0; i < n; ++i)
        if (!dead[i]) {
            s.org[m] = (uint32_t)i;
            xy[2 * m] = xy[2 * i];
            xy[2 * m + 1] = xy[2 * i + 1];
            m++;
        }
    s.m = m;
    if (m == 3) {
        uint32_t *t = tris + 3 * pc.nt++;
        t[0] = s.org[0];
        t[1] = s.org[1];
        t[2] = s.org[2];
        st = GEOM_OK;
        goto done;
    }

    /* 2: orientation from the lowest vertex, exactly */
    {
        uint32_t lo = 0;
        for (uint32_t i = 1; i < m; ++i)
            if (above(xy, lo, i))
                lo = i;
        double o = ori(&s, (uint32_t)(lo ? lo - 1 : m - 1), lo, (uint32_t)(lo + 1 < m ? lo + 1 : 0));
        if (o == 0.0)
            goto done;
        if (o < 0.0)
            for (size_t i = 0; i < m; ++i) {
                double t = xy[2 * i];
                xy[2 * i] = xy[2 * i + 1];
                xy[2 * i + 1] = t;
            }
    }

    /* 3: sort, sweep */
    {
        /* 2m keys (48 bytes per vertex) fit in the pool (64 per vertex) */
        skey *k = (skey *)(void *)pool, *srt;
        for (size_t i = 0; i < m; ++i) {
            k[i].y = xy[2 * i + 1];
            k[i].x = xy[2 * i];
            k[i].i = (uint32_t)i;
            k[i].pad = 0;
        }
        srt = sweep_sort(k, k + m, m);
        for (size_t i = 0; i < m; ++i)
            s.rank[srt[i].i] = (uint32_t)i;
    }
    uint32_t *order = pool;
    for (size_t i = 0; i < m; ++i)
        order[s.rank[i]] = (uint32_t)i;
    s.tl = pool + n;
    s.tr = pool + 2 * n;
    s.tp = pool + 3 * n;
    s.tpri = pool + 4 * n;
    s.helper = pool + 5 * n;
    s.merge = bb;
    s.in_t = bb + n;
    s.dcap = m;
    if (!make_monotone(&s, order))
        goto done;

    /* 4: half-edges: polygon edge e = e -> e+1 (ids < m); diagonal k:
     * m + 2k = dg[2k] -> dg[2k+1], m + 2k + 1 the reverse. Around each
     * vertex (CSR start/out): its polygon edge, then its diagonals
     * counter-clockwise. */
    size_t nd = s.nd, H = m + 2 * nd;
    uint32_t *start = pool, *out = pool + (m + 1), *pos = out + H, *face = pos + H,
             *pu = face + H, *stk = pu + H;
    uint8_t *seen = bb, *chain = bb + H, *mark = bb + 2 * H; /* 2H + m <= 7n */
    memset(start, 0, (m + 1) * sizeof *start);
    for (size_t i = 0; i < m; ++i)
        start[i + 1] = 1;
    for (size_t k = 0; k < 2 * nd; ++k)
        start[s.dg[k] + 1]++;
    for (size_t i = 0; i < m; ++i)
        start[i + 1] += start[i];
    for (size_t i = 0; i < m; ++i)
        out[start[i]] = (uint32_t)i; /* fill cursor below: pos[i] counts */
    for (size_t i = 0; i < m; ++i)
        pos[i] = 1;
    for (size_t k = 0; k < 2 * nd; ++k) {
        uint32_t a = s.dg[k];
        out[start[a] + pos[a]++] = (uint32_t)(m + k);
    }
    for (size_t i = 0; i < m; ++i) {
        uint32_t ref = (uint32_t)(i + 1 < m ? i + 1 : 0), *o = out + start[i];
        size_t d = start[i + 1] - start[i];
        for (size_t a = 2; a < d; ++a) { /* insertion sort (degree <= 5) */
            uint32_t h = o[a];
            uint32_t to = s.dg[(h - m) ^ 1u];
            size_t b = a;
            while (b > 1 && ccw_before(&s, (uint32_t)i, ref, to, s.dg[(o[b - 1] - m) ^ 1u])) {
                o[b] = o[b - 1];
                b--;
            }
            o[b] = h;
        }
        pos[i] = 0;
        for (size_t a = 1; a < d; ++a)
            pos[o[a]] = (uint32_t)a;
    }
    memset(seen, 0, H);
    memset(mark, 0, m);
    size_t faces = 0;
    for (size_t h0 = 0; h0 < H; ++h0) {
        if (seen[h0])
            continue;
        size_t k = 0;
        uint32_t h = (uint32_t)h0;
        do {
            if (seen[h] || k >= H)
                goto done;
            seen[h] = 1;
            uint32_t from = h < m ? h : s.dg[h - m], to;
            face[k++] = from;
            if (h < m) {
                to = (uint32_t)(h + 1 < m ? h + 1 : 0);
                h = out[start[to + 1] - 1];
            } else {
                to = s.dg[(h - m) ^ 1u];
                uint32_t tw = (uint32_t)(m + ((h - m) ^ 1u));
                h = out[start[to] + pos[tw] - 1];
            }
        } while (h != h0);
        faces++;
        if (k < 3)
            continue;
        if (pc.nt + (k - 2) > n - 2)
            goto done; /* more triangles than a triangulation has */
        /* a face through one vertex twice: not a simple polygon's piece */
        int twice = 0;
        for (size_t i = 0; i < k; ++i) {
            twice |= mark[face[i]];
            mark[face[i]] = 1;
        }
        for (size_t i = 0; i < k; ++i)
            mark[face[i]] = 0;
        if (twice)
            goto done;
        /* 5 */
        size_t nt0 = pc.nt;
        pc.bad = 0;
        triangulate_monotone(&s, &pc, face, k, pu, chain, stk);
        if (pc.bad) {
            pc.nt = nt0;
            if (n_piece_fallbacks)
                ++*n_piece_fallbacks;
            if (earclip_face(&s, &pc, face, k) != GEOM_OK) {
                st = GEOM_ERR_NOMEM;
                goto done;
            }
        }
    }
    if (faces != nd + 1 || pc.nt != n - 2)
        goto done;
    st = GEOM_OK;
done:
    geom__free(NULL, ub, nu * sizeof(uint32_t));
    geom__free(NULL, bb, nb);
    geom__free(NULL, xy, ndb * sizeof(double));
    return st;
}

geom_status geom__polygon_triangulate_sweep(size_t n, const double *pts, int u, int v,
                                            uint32_t *tris)
{
    return geom__polygon_triangulate_sweep_ex(n, pts, u, v, tris, NULL);
}
