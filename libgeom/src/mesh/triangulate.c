/*
 * Ear-clipping triangulation (Meisters 1975 "Polygons have ears"; ElGindy,
 * Everett & Toussaint 1993 for the reflex-vertex test) of simple polygons in
 * 3D, and in-place triangulation of a mesh's polygons.
 *
 * The polygon is projected onto the coordinate plane most orthogonal to its
 * Newell normal (dropping that coordinate, mirrored if needed so the polygon
 * is counter-clockwise): the projected coordinates are the input doubles
 * themselves, so geom_orient2d's exact signs apply to them directly. An ear
 * is a strictly convex vertex whose triangle contains no other remaining
 * vertex that is reflex or collinear (closed-triangle test); only such
 * vertices can lie inside an ear candidate of a simple polygon. Among the
 * ears, the best-shaped one (largest area / longest edge^2) is clipped
 * first, so near-slivers are avoided when possible. Ear flags are cached:
 * after a clip they are recomputed at the two neighbours and at the vertices
 * whose triangle holds a neighbour that stopped being reflex, and the chosen
 * ear is re-verified, for O(n^2) time on typical polygons; above 64
 * vertices the grid path below (triangulate_large) applies the same rule in
 * about O(n^1.4) on random polygons. A diagonal that
 * passes within 1e-10 (relative to its length) of a remaining vertex
 * is avoided while another ear exists: on rotated input whose vertices were
 * collinear before rounding it would leave slivers. Fallbacks
 * (for non-simple or degenerate input) in order: a collinear vertex (a
 * zero-area triangle, only when no proper ear exists), any convex vertex,
 * any vertex — so the output always has n-2 triangles forming a
 * combinatorial triangulation of the polygon.
 */
#include "mesh/mesh_internal.h"
#include "mesh/triangulate_internal.h"

#include <float.h>

#define INV GEOM_INVALID_INDEX

/* Newell normal of the polygon, translated to its first point and scaled by
 * the largest coordinate difference (no overflow for huge coordinates).
 * Returns 0 if a coordinate is non-finite. */
static int newell(size_t n, const double *pts, double nrm[3])
{
    const double *o = pts;
    double s = 0.0;
    for (size_t i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) {
            double x = pts[3 * i + k];
            if (!isfinite(x))
                return 0;
            double d = fabs(0.5 * x - 0.5 * o[k]); /* halved: no overflow */
            if (d > s)
                s = d;
        }
    nrm[0] = nrm[1] = nrm[2] = 0.0;
    if (!(s > 0.0) || !isfinite(s))
        return isfinite(s);
    double inv = 1.0 / s;
    for (size_t i = 0; i < n; ++i) {
        const double *a = pts + 3 * i, *b = pts + 3 * (i + 1 < n ? i + 1 : 0);
        double ax = (0.5 * a[0] - 0.5 * o[0]) * inv, ay = (0.5 * a[1] - 0.5 * o[1]) * inv,
               az = (0.5 * a[2] - 0.5 * o[2]) * inv;
        double bx = (0.5 * b[0] - 0.5 * o[0]) * inv, by = (0.5 * b[1] - 0.5 * o[1]) * inv,
               bz = (0.5 * b[2] - 0.5 * o[2]) * inv;
        nrm[0] += (ay - by) * (az + bz);
        nrm[1] += (az - bz) * (ax + bx);
        nrm[2] += (ax - bx) * (ay + by);
    }
    return 1;
}

typedef struct ec {
    size_t n;
    const double *pts;
    int u, v;          /* projected coordinates (exact: input doubles) */
    double *sxy;       /* scaled projected coordinates, for ear quality only */
    uint32_t *prv, *nxt;
    uint8_t *refl;     /* reflex or collinear (orient <= 0) */
    uint8_t *ear;      /* cached: convex and empty (re-verified before use) */
    double *qual;      /* ear quality: 2 area / longest edge^2 (scaled) */
} ec;

static double orient(const ec *e, uint32_t a, uint32_t b, uint32_t c)
{
    double pa[2] = {e->pts[3 * (size_t)a + e->u], e->pts[3 * (size_t)a + e->v]};
    double pb[2] = {e->pts[3 * (size_t)b + e->u], e->pts[3 * (size_t)b + e->v]};
    double pc[2] = {e->pts[3 * (size_t)c + e->u], e->pts[3 * (size_t)c + e->v]};
    return geom_orient2d(pa, pb, pc);
}

static void update_reflex(ec *e, uint32_t i)
{
    e->refl[i] = orient(e, e->prv[i], i, e->nxt[i]) <= 0.0;
}

/* r lies within NEAR_DIAG * |pq| of the segment pq (scaled coordinates). */
#define NEAR_DIAG 1e-10
static int near_segment(const ec *e, uint32_t p, uint32_t q, uint32_t r)
{
    const double *a = e->sxy + 2 * (size_t)p, *b = e->sxy + 2 * (size_t)q,
                 *c = e->sxy + 2 * (size_t)r;
    double dx = b[0] - a[0], dy = b[1] - a[1], rx = c[0] - a[0], ry = c[1] - a[1];
    double l2 = dx * dx + dy * dy, t = rx * dx + ry * dy, cr = dx * ry - dy * rx;
    return t >= 0.0 && t <= l2 && fabs(cr) <= NEAR_DIAG * l2;
}

/* No reflex/collinear remaining vertex (other than p, i, q) lies in the
 * closed triangle p i q, and (when strict) no remaining vertex lies within
 * rounding distance of the diagonal pq. */
static int empty_triangle_ex(const ec *e, uint32_t i, int strict)
{
    uint32_t p = e->prv[i], q = e->nxt[i];
    for (uint32_t r = e->nxt[q]; r != p; r = e->nxt[r]) {
        if (strict && near_segment(e, p, q, r))
            return 0;
        if (!e->refl[r])
            continue;
        if (orient(e, p, i, r) >= 0.0 && orient(e, i, q, r) >= 0.0 && orient(e, q, p, r) >= 0.0)
            return 0;
    }
    return 1;
}

static int empty_triangle(const ec *e, uint32_t i) { return empty_triangle_ex(e, i, 1); }

static double ear_quality(const ec *e, uint32_t i)
{
    const double *a = e->sxy + 2 * (size_t)e->prv[i], *b = e->sxy + 2 * (size_t)i,
                 *c = e->sxy + 2 * (size_t)e->nxt[i];
    double abx = b[0] - a[0], aby = b[1] - a[1], bcx = c[0] - b[0], bcy = c[1] - b[1];
    double cax = a[0] - c[0], cay = a[1] - c[1];
    double l = abx * abx + aby * aby, l2 = bcx * bcx + bcy * bcy, l3 = cax * cax + cay * cay;
    if (l2 > l)
        l = l2;
    if (l3 > l)
        l = l3;
    double area2 = fabs(abx * bcy - aby * bcx);
    return l > 0.0 ? area2 / l : 0.0;
}

static void update_ear(ec *e, uint32_t i)
{
    e->ear[i] = !e->refl[i] && empty_triangle(e, i);
    e->qual[i] = e->ear[i] ? ear_quality(e, i) : 0.0;
}

/* The remaining vertex (from cur) with the best cached ear quality, after
 * re-verifying it; INV if none. */
static uint32_t best_ear(ec *e, uint32_t cur, size_t left)
{
    for (;;) {
        uint32_t best = INV, i = cur;
        for (size_t s = 0; s < left; ++s, i = e->nxt[i])
            if (e->ear[i] && (best == INV || e->qual[i] > e->qual[best]))
                best = i;
        if (best == INV)
            return INV;
        if (!e->refl[best] && empty_triangle(e, best))
            return best;
        e->ear[best] = 0; /* stale */
    }
}

/* ------------------------------------------------ large polygons (grid) */

/* For n > SMALL the same ear rule runs in near-linear time on typical
 * polygons: every remaining vertex sits in a uniform grid over the scaled
 * projected coordinates (about one vertex per cell), so the emptiness test of
 * an ear candidate visits only the cells of its triangle's bounding box
 * (padded for the near-diagonal rule; sxy is a monotone function of the exact
 * coordinates, so the closed exact triangle lies in that box). Ears wait in
 * an indexed max-heap on their quality (ties: lower index); a convex vertex
 * that is not an ear records the vertex that blocked it and is re-examined
 * when that vertex is clipped or stops being reflex, or when its own
 * neighbours change. Fallbacks are those of the small path. */
typedef struct fg {
    ec *e;
    double x0, y0, inv; /* cell = floor((s - x0) * inv) */
    uint32_t nx, ny;
    size_t ncell, cap; /* cells in use, allocated */
    uint32_t *head, *gnx, *gpv, *gcell; /* grid cells: doubly linked */
    uint32_t *heap, *hpos;              /* indexed max-heap of ears */
    size_t nh;
    uint32_t *blk, *bhead, *bnx, *bpv; /* blocker of each vertex; lists */
} fg;

static uint32_t cell_of(const fg *g, double s, double o, uint32_t m)
{
    double c = (s - o) * g->inv;
    if (!(c > 0.0))
        return 0;
    return c >= (double)m ? m - 1 : (uint32_t)c;
}

static void grid_del(fg *g, uint32_t i)
{
    uint32_t c = g->gcell[i];
    if (c == INV)
        return;
    if (g->gpv[i] != INV)
        g->gnx[g->gpv[i]] = g->gnx[i];
    else
        g->head[c] = g->gnx[i];
    if (g->gnx[i] != INV)
        g->gpv[g->gnx[i]] = g->gpv[i];
    g->gcell[i] = INV;
}

static int hbetter(const fg *g, uint32_t a, uint32_t b)
{
    double qa = g->e->qual[a], qb = g->e->qual[b];
    return qa > qb || (qa == qb && a < b);
}

static void hswap(fg *g, size_t a, size_t b)
{
    uint32_t t = g->heap[a];
    g->heap[a] = g->heap[b];
    g->heap[b] = t;
    g->hpos[g->heap[a]] = (uint32_t)a;
    g->hpos[g->heap[b]] = (uint32_t)b;
}

static void hfix(fg *g, size_t k)
{
    while (k > 0 && hbetter(g, g->heap[k], g->heap[(k - 1) / 2])) {
        hswap(g, k, (k - 1) / 2);
        k = (k - 1) / 2;
    }
    for (;;) {
        size_t l = 2 * k + 1, r = l + 1, b = k;
        if (l < g->nh && hbetter(g, g->heap[l], g->heap[b]))
            b = l;
        if (r < g->nh && hbetter(g, g->heap[r], g->heap[b]))
            b = r;
        if (b == k)
            return;
        hswap(g, k, b);
        k = b;
    }
}

static void hdel(fg *g, uint32_t i)
{
    uint32_t k = g->hpos[i];
    if (k == INV)
        return;
    g->hpos[i] = INV;
    if (--g->nh == k)
        return;
    g->heap[k] = g->heap[g->nh];
    g->hpos[g->heap[k]] = k;
    hfix(g, k);
}

static void hset(fg *g, uint32_t i)
{
    if (g->hpos[i] == INV) {
        g->heap[g->nh] = i;
        g->hpos[i] = (uint32_t)g->nh;
        g->nh++;
    }
    hfix(g, g->hpos[i]);
}

static void blk_set(fg *g, uint32_t i, uint32_t r)
{
    uint32_t o = g->blk[i];
    if (o == r)
        return;
    if (o != INV) {
        if (g->bpv[i] != INV)
            g->bnx[g->bpv[i]] = g->bnx[i];
        else
            g->bhead[o] = g->bnx[i];
        if (g->bnx[i] != INV)
            g->bpv[g->bnx[i]] = g->bpv[i];
    }
    g->blk[i] = r;
    if (r != INV) {
        g->bpv[i] = INV;
        g->bnx[i] = g->bhead[r];
        if (g->bhead[r] != INV)
            g->bpv[g->bhead[r]] = i;
        g->bhead[r] = i;
    }
}

/* The first remaining vertex that keeps i from being an ear (reflex or
 * collinear in the closed triangle, or, when strict, near the diagonal);
 * INV if none. */
static uint32_t grid_blocker(const fg *g, uint32_t i, int strict)
{
    const ec *e = g->e;
    uint32_t p = e->prv[i], q = e->nxt[i];
    const double *a = e->sxy + 2 * (size_t)p, *b = e->sxy + 2 * (size_t)i,
                 *c = e->sxy + 2 * (size_t)q;
    double lx = fmin(a[0], fmin(b[0], c[0])), hx = fmax(a[0], fmax(b[0], c[0]));
    double ly = fmin(a[1], fmin(b[1], c[1])), hy = fmax(a[1], fmax(b[1], c[1]));
    double pad = 1e-9 * fmax(hx - lx, hy - ly) + 8.0 * DBL_EPSILON;
    uint32_t cy0 = cell_of(g, ly - pad, g->y0, g->ny), cy1 = cell_of(g, hy + pad, g->y0, g->ny);
    const double *v[3] = {a, b, c};
    double ch = 1.0 / g->inv;
    for (uint32_t cy = cy0; cy <= cy1; ++cy) {
        /* x extent of the triangle within this row (padded): the extremes
         * lie on the edges clipped to the row's band */
        double yl = g->y0 + (double)cy * ch - pad, yh = g->y0 + (double)(cy + 1) * ch + pad;
        if (cy == cy0)
            yl = ly - pad;
        if (cy == cy1)
            yh = hy + pad;
        double xl = INFINITY, xh = -INFINITY;
        for (int k = 0; k < 3; ++k) {
            const double *s0 = v[k], *s1 = v[(k + 1) % 3];
            double ya = s0[1], yb = s1[1];
            if (fmax(ya, yb) < yl || fmin(ya, yb) > yh)
                continue;
            double dy = yb - ya, t0 = 0.0, t1 = 1.0;
            if (dy != 0.0) {
                double ta = (yl - ya) / dy, tb = (yh - ya) / dy;
                if (ta > tb) {
                    double t = ta;
                    ta = tb;
                    tb = t;
                }
                t0 = fmax(0.0, ta);
                t1 = fmin(1.0, tb);
            }
            double xa = s0[0] + t0 * (s1[0] - s0[0]), xb = s0[0] + t1 * (s1[0] - s0[0]);
            xl = fmin(xl, fmin(xa, xb));
            xh = fmax(xh, fmax(xa, xb));
        }
        if (!(xl <= xh))
            continue;
        xl = fmax(xl, lx);
        xh = fmin(xh, hx);
        uint32_t cx0 = cell_of(g, xl - pad, g->x0, g->nx), cx1 = cell_of(g, xh + pad, g->x0, g->nx);
        for (uint32_t cx = cx0; cx <= cx1; ++cx)
            for (uint32_t r = g->head[(size_t)cy * g->nx + cx]; r != INV; r = g->gnx[r]) {
                if (r == p || r == i || r == q)
                    continue;
                if (strict && near_segment(e, p, q, r))
                    return r;
                if (e->refl[r] && orient(e, p, i, r) >= 0.0 && orient(e, i, q, r) >= 0.0 &&
                    orient(e, q, p, r) >= 0.0)
                    return r;
            }
    }
    return INV;
}

static void fupdate(fg *g, uint32_t i)
{
    ec *e = g->e;
    uint32_t r = INV;
    e->ear[i] = 0;
    if (!e->refl[i]) {
        r = grid_blocker(g, i, 1);
        e->ear[i] = r == INV;
    }
    blk_set(g, i, r);
    if (e->ear[i]) {
        e->qual[i] = ear_quality(e, i);
        hset(g, i);
    } else
        hdel(g, i);
}

/* Re-examine the vertices that r blocked. */
static void unblock(fg *g, uint32_t r)
{
    uint32_t i = g->bhead[r];
    g->bhead[r] = INV;
    while (i != INV) {
        uint32_t nx = g->bnx[i];
        g->blk[i] = INV;
        fupdate(g, i);
        i = nx;
    }
}

/* (Re)build the grid over the `left` remaining vertices from `cur`: about
 * one vertex per cell over their bounding box, at most g->cap cells. */
static void grid_build(fg *g, uint32_t cur, size_t left)
{
    const ec *e = g->e;
    const double *s = e->sxy;
    double x0 = s[2 * (size_t)cur], x1 = x0, y0 = s[2 * (size_t)cur + 1], y1 = y0;
    uint32_t i = cur;
    for (size_t k = 0; k < left; ++k, i = e->nxt[i]) {
        x0 = fmin(x0, s[2 * (size_t)i]);
        x1 = fmax(x1, s[2 * (size_t)i]);
        y0 = fmin(y0, s[2 * (size_t)i + 1]);
        y1 = fmax(y1, s[2 * (size_t)i + 1]);
    }
    double w = x1 - x0, h = y1 - y0, cs = sqrt(w * h / (double)left);
    if (!(cs > 0.0))
        cs = fmax(w, h) / (double)left;
    if (!(cs > 0.0))
        cs = 1.0;
    double fx = floor(w / cs) + 1.0, fy = floor(h / cs) + 1.0;
    uint32_t nx = fx > (double)(2 * left) ? (uint32_t)(2 * left) : (uint32_t)fx;
    uint32_t ny = fy > (double)(2 * left) ? (uint32_t)(2 * left) : (uint32_t)fy;
    while ((size_t)nx * ny > g->cap) { /* thin boxes: keep the grid O(n) */
        nx = nx > 1 ? (nx + 1) / 2 : 1;
        ny = ny > 1 ? (ny + 1) / 2 : 1;
    }
    g->x0 = x0;
    g->y0 = y0;
    g->inv = 1.0 / fmax(w / nx, h / ny);
    if (!isfinite(g->inv) || !(g->inv > 0.0))
        g->inv = 1.0;
    g->nx = nx;
    g->ny = ny;
    g->ncell = (size_t)nx * ny;
    for (size_t c = 0; c < g->ncell; ++c)
        g->head[c] = INV;
    i = cur;
    for (size_t k = 0; k < left; ++k, i = e->nxt[i]) {
        uint32_t c = cell_of(g, s[2 * (size_t)i + 1], y0, ny) * nx +
                     cell_of(g, s[2 * (size_t)i], x0, nx);
        g->gcell[i] = c;
        g->gpv[i] = INV;
        g->gnx[i] = g->head[c];
        if (g->head[c] != INV)
            g->gpv[g->head[c]] = i;
        g->head[c] = i;
    }
}

static geom_status triangulate_large(ec *e, uint32_t *tris)
{
    size_t n = e->n;
    fg g;
    g.e = e;
    g.cap = 4 * n;
    size_t nc = g.cap, nu = nc + 11 * n;
    uint32_t *ub = geom__alloc(NULL, nu * sizeof(uint32_t));
    if (!ub)
        return GEOM_ERR_NOMEM;
    g.head = ub;
    g.gnx = ub + nc;
    g.gpv = g.gnx + n;
    g.gcell = g.gpv + n;
    g.heap = g.gcell + n;
    g.hpos = g.heap + n;
    g.blk = g.hpos + n;
    g.bhead = g.blk + n;
    g.bnx = g.bhead + n;
    g.bpv = g.bnx + n;
    g.nh = 0;
    for (size_t i = 0; i < n; ++i)
        g.hpos[i] = g.blk[i] = g.bhead[i] = INV;
    grid_build(&g, 0, n);
    for (size_t i = 0; i < n; ++i)
        fupdate(&g, (uint32_t)i);

    size_t left = n, nt = 0;
    uint32_t cur = 0;
    int recomputed = 0;
    while (left > 3) {
        uint32_t ear = INV, i;
        int proper = 0;
        while (g.nh > 0) { /* the best ear, re-verified */
            uint32_t b = g.heap[0];
            if (!e->refl[b] && grid_blocker(&g, b, 1) == INV) {
                ear = b;
                proper = 1;
                break;
            }
            fupdate(&g, b);
        }
        if (ear == INV && !recomputed) {
            /* all cached state recomputed once before a fallback */
            i = cur;
            for (size_t s = 0; s < left; ++s, i = e->nxt[i])
                fupdate(&g, i);
            recomputed = 1;
            continue;
        }
        /* 1b: an ear by the exact test alone */
        if (ear == INV) {
            double bq = -1.0;
            i = cur;
            for (size_t s = 0; s < left; ++s, i = e->nxt[i])
                if (!e->refl[i] && grid_blocker(&g, i, 0) == INV && ear_quality(e, i) > bq) {
                    ear = i;
                    bq = ear_quality(e, i);
                }
        }
        /* 2: a collinear vertex, 3: any convex vertex, 4: any vertex */
        if (ear == INV) {
            i = cur;
            for (size_t s = 0; s < left; ++s, i = e->nxt[i])
                if (orient(e, e->prv[i], i, e->nxt[i]) == 0.0) {
                    ear = i;
                    break;
                }
        }
        if (ear == INV) {
            i = cur;
            for (size_t s = 0; s < left; ++s, i = e->nxt[i])
                if (!e->refl[i]) {
                    ear = i;
                    break;
                }
        }
        if (ear == INV)
            ear = cur;
        if (proper)
            recomputed = 0;
        uint32_t p = e->prv[ear], q = e->nxt[ear];
        tris[3 * nt] = p;
        tris[3 * nt + 1] = ear;
        tris[3 * nt + 2] = q;
        nt++;
        e->nxt[p] = q;
        e->prv[q] = p;
        left--;
        e->ear[ear] = 0;
        hdel(&g, ear);
        blk_set(&g, ear, INV);
        grid_del(&g, ear);
        uint8_t rp = e->refl[p], rq = e->refl[q];
        update_reflex(e, p);
        update_reflex(e, q);
        unblock(&g, ear);
        if (rp && !e->refl[p])
            unblock(&g, p);
        if (rq && !e->refl[q])
            unblock(&g, q);
        if (!proper) {
            /* a fallback clip may make vertices reflex: re-examine later */
            recomputed = 0;
        }
        fupdate(&g, p);
        fupdate(&g, q);
        cur = q;
        if (left >= 64 && 4 * left < g.ncell)
            grid_build(&g, cur, left); /* keep about one vertex per cell */
    }
    tris[3 * nt] = e->prv[cur];
    tris[3 * nt + 1] = cur;
    tris[3 * nt + 2] = e->nxt[cur];
    geom__free(NULL, ub, nu * sizeof(uint32_t));
    return GEOM_OK;
}

geom_status geom__polygon_earclip(size_t n, const double *pts, uint32_t *tris)
{
    if (n < 3 || !pts || !tris)
        return GEOM_ERR_INVALID_ARG;
    if (n > (size_t)UINT32_MAX - 1)
        return GEOM_ERR_LIMIT;
    double nrm[3];
    int finite = newell(n, pts, nrm);
    if (!finite || (nrm[0] == 0.0 && nrm[1] == 0.0 && nrm[2] == 0.0)) {
        /* Non-finite or zero-area: still a valid (fan) triangulation. */
        for (size_t i = 0; i + 2 < n; ++i) {
            tris[3 * i] = 0;
            tris[3 * i + 1] = (uint32_t)(i + 1);
            tris[3 * i + 2] = (uint32_t)(i + 2);
        }
        return finite ? GEOM_ERR_DEGENERATE : GEOM_ERR_INVALID_ARG;
    }
    if (n == 3) {
        tris[0] = 0;
        tris[1] = 1;
        tris[2] = 2;
        return GEOM_OK;
    }
    int k = 0;
    if (fabs(nrm[1]) > fabs(nrm[k]))
        k = 1;
    if (fabs(nrm[2]) > fabs(nrm[k]))
        k = 2;
    ec e;
    e.n = n;
    e.pts = pts;
    e.u = (k + 1) % 3;
    e.v = (k + 2) % 3;
    if (nrm[k] < 0.0) {
        int t = e.u;
        e.u = e.v;
        e.v = t;
    }
    /* scratch: prv, nxt (uint32), refl, ear (bytes), qual, sxy (doubles) */
    enum { SMALL = 64 };
    uint32_t su[2 * SMALL];
    uint8_t sb[2 * SMALL];
    double sd[3 * SMALL];
    uint32_t *ub = su;
    uint8_t *bb = sb;
    double *db = sd;
    if (n > SMALL) {
        ub = geom__alloc(NULL, 2 * n * sizeof(uint32_t));
        bb = geom__alloc(NULL, 2 * n);
        db = geom__alloc(NULL, 3 * n * sizeof(double));
        if (!ub || !bb || !db) {
            geom__free(NULL, ub, 2 * n * sizeof(uint32_t));
            geom__free(NULL, bb, 2 * n);
            geom__free(NULL, db, 3 * n * sizeof(double));
            return GEOM_ERR_NOMEM;
        }
    }
    e.prv = ub;
    e.nxt = ub + n;
    e.refl = bb;
    e.ear = bb + n;
    e.qual = db;
    e.sxy = db + n;
    {
        double ou = 0.5 * pts[e.u], ov = 0.5 * pts[e.v], sc = 0.0; /* halved */
        for (size_t i = 0; i < n; ++i) {
            double du = fabs(0.5 * pts[3 * i + e.u] - ou), dv = fabs(0.5 * pts[3 * i + e.v] - ov);
            sc = du > sc ? du : sc;
            sc = dv > sc ? dv : sc;
        }
        double inv = sc > 0.0 ? 1.0 / sc : 1.0;
        for (size_t i = 0; i < n; ++i) {
            e.sxy[2 * i] = (0.5 * pts[3 * i + e.u] - ou) * inv;
            e.sxy[2 * i + 1] = (0.5 * pts[3 * i + e.v] - ov) * inv;
        }
    }
    for (size_t i = 0; i < n; ++i) {
        e.prv[i] = (uint32_t)(i ? i - 1 : n - 1);
        e.nxt[i] = (uint32_t)(i + 1 < n ? i + 1 : 0);
    }
    for (size_t i = 0; i < n; ++i)
        update_reflex(&e, (uint32_t)i);
    if (n > SMALL) {
        geom_status st = triangulate_large(&e, tris);
        geom__free(NULL, ub, 2 * n * sizeof(uint32_t));
        geom__free(NULL, bb, 2 * n);
        geom__free(NULL, db, 3 * n * sizeof(double));
        return st;
    }
    for (size_t i = 0; i < n; ++i)
        update_ear(&e, (uint32_t)i);

    size_t left = n, nt = 0;
    uint32_t cur = 0;
    while (left > 3) {
        /* 1: the best-shaped proper ear (cached flags may miss ears that
         * appeared elsewhere: recompute all once before falling back) */
        uint32_t ear = best_ear(&e, cur, left), i;
        if (ear == INV) {
            i = cur;
            for (size_t s = 0; s < left; ++s, i = e.nxt[i])
                update_ear(&e, i);
            ear = best_ear(&e, cur, left);
        }
        /* 1b: an ear by the exact test alone (its diagonal passes very close
         * to a vertex) */
        if (ear == INV) {
            double bq = -1.0;
            i = cur;
            for (size_t s = 0; s < left; ++s, i = e.nxt[i])
                if (!e.refl[i] && empty_triangle_ex(&e, i, 0) && ear_quality(&e, i) > bq) {
                    ear = i;
                    bq = ear_quality(&e, i);
                }
        }
        /* 2: a collinear vertex (zero-area triangle) */
        if (ear == INV) {
            i = cur;
            for (size_t s = 0; s < left; ++s, i = e.nxt[i])
                if (orient(&e, e.prv[i], i, e.nxt[i]) == 0.0) {
                    ear = i;
                    break;
                }
        }
        /* 3: any convex vertex, 4: any vertex */
        if (ear == INV) {
            i = cur;
            for (size_t s = 0; s < left; ++s, i = e.nxt[i])
                if (!e.refl[i]) {
                    ear = i;
                    break;
                }
        }
        if (ear == INV)
            ear = cur;
        uint32_t p = e.prv[ear], q = e.nxt[ear];
        tris[3 * nt] = p;
        tris[3 * nt + 1] = ear;
        tris[3 * nt + 2] = q;
        nt++;
        e.nxt[p] = q;
        e.prv[q] = p;
        left--;
        e.ear[ear] = 0;
        uint8_t rp = e.refl[p], rq = e.refl[q];
        update_reflex(&e, p);
        update_reflex(&e, q);
        update_ear(&e, p);
        update_ear(&e, q);
        /* a vertex that stopped being reflex no longer blocks the ears
         * whose triangles hold it */
        for (int j = 0; j < 2; ++j) {
            uint32_t w = j ? q : p;
            if (!(j ? rq : rp) || e.refl[w])
                continue;
            i = q;
            for (size_t s = 0; s < left; ++s, i = e.nxt[i]) {
                if (e.refl[i] || e.ear[i] || i == p || i == q)
                    continue;
                uint32_t a = e.prv[i], b = e.nxt[i];
                if (w != a && w != b && orient(&e, a, i, w) >= 0.0 &&
                    orient(&e, i, b, w) >= 0.0 && orient(&e, b, a, w) >= 0.0)
                    update_ear(&e, i);
            }
        }
        cur = q;
    }
    tris[3 * nt] = e.prv[cur];
    tris[3 * nt + 1] = cur;
    tris[3 * nt + 2] = e.nxt[cur];
    if (n > SMALL) {
        geom__free(NULL, ub, 2 * n * sizeof(uint32_t));
        geom__free(NULL, bb, 2 * n);
        geom__free(NULL, db, 3 * n * sizeof(double));
    }
    return GEOM_OK;
}

/* Above this many vertices the monotone sweep (triangulate_sweep.c) runs
 * first; at or below it the ear clipper alone (best-shaped ears first). */
#define SWEEP_MIN 64

geom_status geom_polygon_triangulate(size_t n, const double *pts, uint32_t *tris)
{
    if (n <= SWEEP_MIN || !pts || !tris)
        return geom__polygon_earclip(n, pts, tris);
    if (n > (size_t)UINT32_MAX - 1)
        return GEOM_ERR_LIMIT;
    double nrm[3];
    if (!newell(n, pts, nrm) || (nrm[0] == 0.0 && nrm[1] == 0.0 && nrm[2] == 0.0))
        return geom__polygon_earclip(n, pts, tris); /* the fan and its status */
    int k = 0;
    if (fabs(nrm[1]) > fabs(nrm[k]))
        k = 1;
    if (fabs(nrm[2]) > fabs(nrm[k]))
        k = 2;
    geom_status st = geom__polygon_triangulate_sweep(n, pts, (k + 1) % 3, (k + 2) % 3, tris);
    if (st != GEOM_ERR_DEGENERATE)
        return st;
    return geom__polygon_earclip(n, pts, tris); /* rejected: not simple */
}

/* --------------------------------------------------------------- mesh */

geom_status geom_mesh_triangulate(geom_mesh *m, size_t *n_new_faces)
{
    if (n_new_faces)
        *n_new_faces = 0;
    if (!m)
        return GEOM_ERR_INVALID_ARG;
    size_t add = 0, nmax = 0, nf0 = m->nf;
    for (size_t f = 0; f < nf0; ++f) {
        if (m->f_del[f])
            continue;
        size_t n = geom_mesh_face_valence(m, (uint32_t)f);
        if (n > 3) {
            add += n - 3;
            if (n > nmax)
                nmax = n;
            uint32_t h = m->f_he[f];
            for (size_t k = 0; k < n; ++k, h = m->he_next[h])
                if (!geom__isfinite3(geom__mesh_pos(m) + 3 * (size_t)m->he_vertex[h]))
                    return GEOM_ERR_INVALID_ARG; /* nothing changed yet */
        }
    }
    if (add == 0)
        return GEOM_OK;
    if (add > (size_t)UINT32_MAX / 2)
        return GEOM_ERR_LIMIT;
    geom_status st = geom__mesh_reserve(m, m->nv, m->nh + 2 * add, m->nf + add);
    if (st != GEOM_OK)
        return st;
    /* scratch: pts 3n doubles; tris 3(n-2), hk n, diagonals (n-3) x (lo, hi,
     * halfedge, hash slot), hash slots hc (a power of two >= 2n; linear
     * probing, emptied after each face) */
    const geom_allocator *a = &m->alloc;
    size_t hc = 16;
    while (hc < 2 * nmax)
        hc *= 2;
    size_t nd = 3 * nmax, nu = 3 * nmax + nmax + 4 * nmax + hc;
    double *pts = geom__alloc(a, nd * sizeof(double));
    uint32_t *ub = geom__alloc(a, nu * sizeof(uint32_t));
    if (!pts || !ub) {
        geom__free(a, pts, nd * sizeof(double));
        geom__free(a, ub, nu * sizeof(uint32_t));
        return GEOM_ERR_NOMEM;
    }
    uint32_t *tris = ub, *hk = ub + 3 * nmax, *dg = hk + nmax, *hs = dg + 4 * nmax;
    for (size_t i = 0; i < hc; ++i)
        hs[i] = INV;
    const double *pos = geom__mesh_pos(m);
    for (size_t f = 0; f < nf0; ++f) {
        if (m->f_del[f])
            continue;
        size_t n = geom_mesh_face_valence(m, (uint32_t)f);
        if (n <= 3)
            continue;
        uint32_t h = m->f_he[f];
        for (size_t k = 0; k < n; ++k, h = m->he_next[h]) {
            hk[k] = h;
            memcpy(pts + 3 * k, pos + 3 * (size_t)m->he_vertex[h], 3 * sizeof(double));
        }
        (void)geom_polygon_triangulate(n, pts, tris); /* degenerate: a fan is written */
        size_t ndg = 0;
        for (size_t t = 0; t < n - 2; ++t) {
            uint32_t face = t == 0 ? (uint32_t)f : (uint32_t)m->nf;
            if (t > 0) {
                geom__mesh_resize(m, m->nv, m->nh, m->nf + 1); /* reserved: cannot fail */
                if (m->face_origin)
                    m->face_origin[face] = m->face_origin[f];
                if (m->face_group)
                    m->face_group[face] = m->face_group[f];
                for (size_t c = 0; c < m->n_channels; ++c) {
                    geom__mesh_channel *ch = &m->channels[c];
                    if (ch->domain == GEOM_MESH_DOMAIN_FACE)
                        memcpy(ch->data + (size_t)face * ch->ncomp, ch->data + f * ch->ncomp,
                               ch->ncomp * sizeof(double));
                }
            }
            uint32_t th[3];
            for (int j = 0; j < 3; ++j) {
                uint32_t la = tris[3 * t + (size_t)j], lb = tris[3 * t + (size_t)((j + 1) % 3)];
                uint32_t he;
                if (lb == (la + 1) % n)
                    he = hk[lb];
                else {
                    /* diagonal la -> lb: existing (opposite direction) or new */
                    uint32_t lo = la < lb ? la : lb, hi = la < lb ? lb : la;
                    he = INV;
                    size_t slot = (size_t)((lo * 2654435761u) ^ (hi * 40503u)) & (hc - 1);
                    for (; hs[slot] != INV; slot = (slot + 1) & (hc - 1)) {
                        const uint32_t *d = dg + 4 * (size_t)hs[slot];
                        if (d[0] == lo && d[1] == hi) {
                            he = d[2] ^ 1u;
                            break;
                        }
                    }
                    if (he == INV) {
                        he = (uint32_t)m->nh;
                        geom__mesh_resize(m, m->nv, m->nh + 2, m->nf);
                        m->he_vertex[he] = m->he_vertex[hk[lb]];
                        m->he_vertex[he ^ 1u] = m->he_vertex[hk[la]];
                        dg[4 * ndg] = lo;
                        dg[4 * ndg + 1] = hi;
                        dg[4 * ndg + 2] = he;
                        dg[4 * ndg + 3] = (uint32_t)slot;
                        hs[slot] = (uint32_t)ndg;
                        ndg++;
                    }
                    /* corner of this triangle at lb: the polygon's corner at lb */
                    for (size_t c = 0; c < m->n_channels; ++c) {
                        geom__mesh_channel *ch = &m->channels[c];
                        if (ch->domain == GEOM_MESH_DOMAIN_CORNER)
                            ch->corner[he] = ch->corner[hk[lb]];
                    }
                }
                th[j] = he;
                m->he_face[he] = face;
            }
            geom__mesh_link(m, th[0], th[1]);
            geom__mesh_link(m, th[1], th[2]);
            geom__mesh_link(m, th[2], th[0]);
            m->f_he[face] = th[0];
        }
        for (size_t d = 0; d < ndg; ++d)
            hs[dg[4 * d + 3]] = INV;
    }
    geom__free(a, pts, nd * sizeof(double));
    geom__free(a, ub, nu * sizeof(uint32_t));
    if (m->face_flipped) {
        /* input corners no longer correspond to faces */
        geom__free(a, m->face_flipped, m->cap_f);
        m->face_flipped = NULL;
    }
    if (n_new_faces)
        *n_new_faces = add;
    return GEOM_OK;
}
