/*
 * Marching squares with the asymptotic decider (Nielson and Hamann 1991),
 * edge-keyed shared vertices refined by safeguarded root finding (Illinois
 * regula falsi with a bisection fallback), and joining into polylines.
 * Rows are processed one at a time, so memory is O(nx) plus the output.
 */
#include "implicit/implicit_internal.h"

#include <float.h>
#include <string.h>
#include <time.h>

#define NOV UINT32_MAX /* no vertex yet */

static double now_seconds(void) { return geom__seconds(); }

typedef struct ctx {
    const geom_implicit_field *f;
    double iso, z;
    int refine;
    int max_it;
    const geom_allocator *alloc;
    double *xy;
    size_t nv, cap_v;
    uint32_t *seg; /* pairs (from, to) */
    size_t nseg, cap_seg;
    size_t evals, refined;
    geom_status err;
} ctx;

static double field_at(ctx *c, double x, double y)
{
    double p[3] = {x, y, c->z};
    c->evals++;
    return c->f->value(c->f->user, p) - c->iso;
}

/* Grow *buf (elements of size `size`, capacity *cap) to hold `need`. */
static int grow(ctx *c, void **buf, size_t *cap, size_t need, size_t size)
{
    geom_status st = geom__grow(c->alloc, buf, cap, need, size);
    if (st != GEOM_OK) {
        c->err = st;
        return -1;
    }
    return 0;
}

static uint32_t add_vertex(ctx *c, double x, double y)
{
    if (c->nv >= (size_t)UINT32_MAX - 1) {
        c->err = GEOM_ERR_LIMIT;
        return NOV;
    }
    void *buf = c->xy;
    if (grow(c, &buf, &c->cap_v, c->nv + 1, 2 * sizeof(double)) != 0)
        return NOV;
    c->xy = buf;
    c->xy[2 * c->nv] = x;
    c->xy[2 * c->nv + 1] = y;
    return (uint32_t)c->nv++;
}

static void add_segment(ctx *c, uint32_t a, uint32_t b)
{
    void *buf = c->seg;
    if (grow(c, &buf, &c->cap_seg, c->nseg + 1, 2 * sizeof(uint32_t)) != 0)
        return;
    c->seg = buf;
    c->seg[2 * c->nseg] = a;
    c->seg[2 * c->nseg + 1] = b;
    c->nseg++;
}

/* The field along an edge: axis 0 varies x at y = other, axis 1 y. */
typedef struct edge_fn {
    ctx *c;
    int axis;
    double other;
} edge_fn;

static double along_edge(void *u, double t)
{
    edge_fn *e = u;
    double d = e->axis == 0 ? field_at(e->c, t, e->other) : field_at(e->c, e->other, t);
    return isnan(d) ? INFINITY : d; /* NaN is outside along the edge too */
}

/*
 * The crossing on the edge from coordinate a to b (along axis; the other
 * coordinate fixed) whose end values (f - iso) da and db are finite or
 * infinite, of opposite strict signs. Linear interpolation, then (refine)
 * the library's root finder (geom_implicit_bracket_root) on the edge's
 * coordinate. The result is strictly between a and b.
 */
static double crossing(ctx *c, int axis, double other, double a, double b, double da, double db)
{
    double x;
    if (isfinite(da) && isfinite(db)) {
        double t = da / (da - db);
        x = a + t * (b - a);
    } else {
        x = a + 0.5 * (b - a);
    }
    if (!(x > a && x < b))
        x = !(x > a) ? nextafter(a, b) : nextafter(b, a);
    if (!c->refine)
        return x;
    c->refined++;
    edge_fn e = {c, axis, other};
    /* field_at counts the evaluations itself */
    return geom_implicit_bracket_root(along_edge, &e, a, b, da, db, x, c->max_it, NULL);
}

/* Vertex slots and flags of the two rows of the current cell row. */
typedef struct rows {
    double *d[2];        /* node values - iso, bottom and top */
    uint32_t *h[2];      /* horizontal edge vertices, bottom and top */
    uint32_t *nd[2];     /* node vertices (value == iso), bottom and top */
    unsigned char *hs[2]; /* node-to-node segment emitted on the horizontal side */
    uint32_t *v;         /* vertical edge vertices of the row */
    unsigned char *vs;   /* node-to-node segment emitted on the vertical side */
    size_t *s[2];        /* the grid row each node slot holds (SIZE_MAX: none) */
    size_t *sv;          /* the cell row each vertical slot holds */
} rows;

/* Infinities as +-DBL_MAX for the decider, as geom_iso_extract has them. */
static double finite_or_max(double d)
{
    return d > DBL_MAX ? DBL_MAX : d < -DBL_MAX ? -DBL_MAX : d;
}

/* Exact sign of d0*d2 - d1*d3 (core's orient2d of (d0, d1), (d3, d2) and
 * the origin, on values scaled by a power of two so that the products stay
 * in range): the same predicate as geom_iso_extract's face decider. */
static double det2(double d0, double d2, double d1, double d3)
{
    d0 = finite_or_max(d0);
    d1 = finite_or_max(d1);
    d2 = finite_or_max(d2);
    d3 = finite_or_max(d3);
    double m = fmax(fmax(fabs(d0), fabs(d1)), fmax(fabs(d2), fabs(d3)));
    if (!(m > 0.0))
        return 0.0;
    int e;
    frexp(m, &e);
    const double a[2] = {ldexp(d0, -e), ldexp(d1, -e)};
    const double b[2] = {ldexp(d3, -e), ldexp(d2, -e)};
    const double o[2] = {0.0, 0.0};
    return geom_orient2d(a, b, o);
}

typedef struct cross {
    uint32_t v;
    int corner; /* the grid corner (0..3) when the vertex is a node, else -1 */
} cross;

/* The vertex where edge k of cell (i, j) is crossed. */
static cross edge_vertex(ctx *c, rows *R, size_t i, int k, const double dv[4], const double *X,
                         double yb, double yt)
{
    static const int ca[4] = {0, 1, 3, 0}, cb[4] = {1, 2, 2, 3};
    int a = ca[k], b = cb[k];
    cross r = {NOV, -1};
    /* node vertex when the inside end is exactly on the isovalue (the
     * outside end is > 0, never 0) */
    int zc = dv[a] == 0.0 ? a : dv[b] == 0.0 ? b : -1;
    if (zc >= 0) {
        size_t ni = (zc == 0 || zc == 3) ? i : i + 1;
        uint32_t *slot = (zc == 0 || zc == 1) ? &R->nd[0][ni] : &R->nd[1][ni];
        if (*slot == NOV)
            *slot = add_vertex(c, X[ni], (zc == 0 || zc == 1) ? yb : yt);
        r.v = *slot;
        r.corner = zc;
        return r;
    }
    uint32_t *slot;
    switch (k) {
    case 0: slot = &R->h[0][i]; break;
    case 1: slot = &R->v[i + 1]; break;
    case 2: slot = &R->h[1][i]; break;
    default: slot = &R->v[i]; break;
    }
    if (*slot == NOV) {
        double pos;
        if (k == 0 || k == 2) {
            double y = k == 0 ? yb : yt;
            pos = crossing(c, 0, y, X[i], X[i + 1], dv[a], dv[b]);
            *slot = add_vertex(c, pos, y);
        } else {
            double x = k == 1 ? X[i + 1] : X[i];
            pos = crossing(c, 1, x, yb, yt, dv[a], dv[b]);
            *slot = add_vertex(c, x, pos);
        }
    }
    r.v = *slot;
    return r;
}

/* Emit the segment p -> q of cell i unless it is degenerate or a
 * node-to-node segment already emitted along a shared cell side. */
static void emit_segment(ctx *c, rows *R, size_t i, cross p, cross q)
{
    if (p.v == NOV || q.v == NOV || p.v == q.v)
        return;
    if (p.corner >= 0 && q.corner >= 0) {
        int lo = p.corner < q.corner ? p.corner : q.corner;
        int hi = p.corner < q.corner ? q.corner : p.corner;
        unsigned char *flag = NULL;
        if (lo == 0 && hi == 1)
            flag = &R->hs[0][i];
        else if (lo == 1 && hi == 2)
            flag = &R->vs[i + 1];
        else if (lo == 2 && hi == 3)
            flag = &R->hs[1][i];
        else if (lo == 0 && hi == 3)
            flag = &R->vs[i];
        if (flag) {
            if (*flag)
                return;
            *flag = 1;
        }
    }
    add_segment(c, p.v, q.v);
}

/* Node i of grid row jrow into row slot r (once: the stamp says whether it
 * is there), its edge slots cleared; a NaN node is counted, the first in
 * scan order (rows of increasing y, then x) kept. */
static void node_at(ctx *c, rows *R, int r, size_t i, size_t jrow, const double *X, double y,
                    geom_implicit_contour_report *rep)
{
    if (R->s[r][i] == jrow)
        return;
    R->s[r][i] = jrow;
    double d = field_at(c, X[i], y);
    if (isnan(d)) {
        if (rep->nan_nodes++ == 0 || jrow < rep->nan_first[1] ||
            (jrow == rep->nan_first[1] && i < rep->nan_first[0])) {
            rep->nan_first[0] = i;
            rep->nan_first[1] = jrow;
            rep->nan_point[0] = X[i];
            rep->nan_point[1] = y;
        }
    }
    R->d[r][i] = d;
    R->h[r][i] = NOV;
    R->nd[r][i] = NOV;
    R->hs[r][i] = 0;
}

static void vertical_at(rows *R, size_t i, size_t j)
{
    if (R->sv[i] == j)
        return;
    R->sv[i] = j;
    R->v[i] = NOV;
    R->vs[i] = 0;
}

/* Cells i0..i1-1 of cell row j (between y = yb and yt), left to right. */
static void cell_run(ctx *c, rows *R, const double *X, size_t j, double yb, double yt, size_t i0,
                     size_t i1, geom_implicit_contour_report *rep)
{
    for (size_t i = i0; i < i1 && c->err == GEOM_OK; i++) {
        for (size_t q = i; q <= i + 1; q++) {
            node_at(c, R, 0, q, j, X, yb, rep);
            node_at(c, R, 1, q, j + 1, X, yt, rep);
            vertical_at(R, q, j);
        }
        double dv[4] = {R->d[0][i], R->d[0][i + 1], R->d[1][i + 1], R->d[1][i]};
        /* a NaN corner is outside, as +inf (as geom_iso_extract has it) */
        if (isnan(dv[0]) || isnan(dv[1]) || isnan(dv[2]) || isnan(dv[3])) {
            rep->skipped_cells++;
            for (int k = 0; k < 4; k++)
                if (isnan(dv[k]))
                    dv[k] = INFINITY;
        }
        /* the library's one inside convention (as geom_iso_extract):
         * f <= iso is inside, the level iso + epsilon */
        int in[4], code = 0;
        for (int k = 0; k < 4; k++) {
            in[k] = dv[k] <= 0.0;
            code |= in[k] << k;
        }
        if (code == 0 || code == 15)
            continue;
        /* Crossings: edge k runs from corner k to corner k+1 (CCW);
         * "out" when it leaves the inside, "in" when it enters. */
        int outs[2], ins[2], no = 0, ni = 0;
        for (int k = 0; k < 4; k++) {
            int a = in[k], b = in[(k + 1) & 3];
            if (a && !b)
                outs[no++] = k;
            else if (!a && b)
                ins[ni++] = k;
        }
        if (no == 1) {
            cross p = edge_vertex(c, R, i, outs[0], dv, X, yb, yt);
            cross q = edge_vertex(c, R, i, ins[0], dv, X, yb, yt);
            emit_segment(c, R, i, p, q);
            continue;
        }
        /* Saddle: the inside corners are joined when the bilinear
         * interpolant is inside (<= 0) at its saddle point. With D = d0
         * d2 - d1 d3 and denominator d0 + d2 - d1 - d3 (negative for
         * code 5, positive for code 10: the outside corners are > 0),
         * that is D >= 0 (code 5), D <= 0 (10); at D == 0 the level
         * iso + epsilon joins them, as the 3D face decider does. */
        rep->saddles++;
        double D = det2(dv[0], dv[2], dv[1], dv[3]);
        int joined = code == 5 ? D >= 0.0 : D <= 0.0;
        for (int m = 0; m < 2; m++) {
            int k = outs[m];
            int target = joined ? (k + 1) & 3 : (k + 3) & 3;
            cross p = edge_vertex(c, R, i, k, dv, X, yb, yt);
            cross q = edge_vertex(c, R, i, target, dv, X, yb, yt);
            emit_segment(c, R, i, p, q);
        }
    }
}

/* ----------------------------------------------------------- polylines */

typedef struct plbuild {
    uint32_t *idx;
    size_t n, cap;
    size_t *start;
    unsigned char *closed;
    size_t np, capp, capc; /* capacities of start and closed */
} plbuild;

static int pl_push(ctx *c, plbuild *B, uint32_t v)
{
    void *buf = B->idx;
    if (grow(c, &buf, &B->cap, B->n + 1, sizeof(uint32_t)) != 0)
        return -1;
    B->idx = buf;
    B->idx[B->n++] = v;
    return 0;
}

static int pl_finish(ctx *c, plbuild *B, size_t first, int closed)
{
    void *buf = B->start;
    if (grow(c, &buf, &B->capp, B->np + 2, sizeof(size_t)) != 0)
        return -1;
    B->start = buf;
    buf = B->closed;
    if (grow(c, &buf, &B->capc, B->np + 2, 1) != 0)
        return -1;
    B->closed = buf;
    B->start[B->np] = first;
    B->closed[B->np] = (unsigned char)closed;
    B->np++;
    B->start[B->np] = B->n;
    return 0;
}

/* Resize a block to exactly newb bytes (allocating when p is NULL). */
static void *resize(ctx *c, void *p, size_t oldb, size_t newb)
{
    if (!p)
        return geom__alloc(c->alloc, newb);
    if (oldb == newb)
        return p;
    return geom__realloc(c->alloc, p, oldb, newb);
}

/* Walk from segment s following vertices with one segment in and one out. */
static int walk(ctx *c, plbuild *B, size_t s, const uint32_t *indeg, const uint32_t *outdeg,
                const size_t *off, const uint32_t *list, unsigned char *used)
{
    size_t first = B->n;
    uint32_t v0 = c->seg[2 * s];
    if (pl_push(c, B, v0) != 0)
        return -1;
    int closed = 0;
    size_t cur = s;
    for (;;) {
        used[cur] = 1;
        uint32_t w = c->seg[2 * cur + 1];
        if (w == v0) {
            closed = 1;
            break;
        }
        if (pl_push(c, B, w) != 0)
            return -1;
        if (indeg[w] != 1 || outdeg[w] != 1)
            break;
        size_t nxt = list[off[w]];
        if (used[nxt])
            break;
        cur = nxt;
    }
    return pl_finish(c, B, first, closed);
}

static geom_status join(ctx *c, geom_implicit_isolines *out)
{
    size_t nv = c->nv, ns = c->nseg;
    plbuild B;
    memset(&B, 0, sizeof B);
    uint32_t *indeg = geom__alloc(c->alloc, (nv + 1) * sizeof(uint32_t));
    uint32_t *outdeg = geom__alloc(c->alloc, (nv + 1) * sizeof(uint32_t));
    size_t *off = geom__alloc(c->alloc, (nv + 1) * sizeof(size_t));
    uint32_t *list = geom__alloc(c->alloc, (ns + 1) * sizeof(uint32_t));
    unsigned char *used = geom__alloc(c->alloc, ns + 1);
    geom_status st = GEOM_OK;
    if (!indeg || !outdeg || !off || !list || !used) {
        st = GEOM_ERR_NOMEM;
        goto done;
    }
    memset(indeg, 0, (nv + 1) * sizeof(uint32_t));
    memset(outdeg, 0, (nv + 1) * sizeof(uint32_t));
    memset(used, 0, ns + 1);
    for (size_t s = 0; s < ns; s++) {
        outdeg[c->seg[2 * s]]++;
        indeg[c->seg[2 * s + 1]]++;
    }
    off[0] = 0;
    for (size_t v = 0; v < nv; v++)
        off[v + 1] = off[v] + outdeg[v];
    {
        /* fill with a cursor per vertex (reuse `list` order by segment) */
        size_t *cursor = geom__alloc(c->alloc, (nv + 1) * sizeof(size_t));
        if (!cursor) {
            st = GEOM_ERR_NOMEM;
            goto done;
        }
        memcpy(cursor, off, (nv + 1) * sizeof(size_t));
        for (size_t s = 0; s < ns; s++)
            list[cursor[c->seg[2 * s]]++] = (uint32_t)s;
        geom__free(c->alloc, cursor, (nv + 1) * sizeof(size_t));
    }
    /* Open polylines (and loops through junctions) from every vertex that
     * is not a plain pass-through, then the remaining pure loops. */
    for (size_t v = 0; v < nv && c->err == GEOM_OK; v++) {
        if (indeg[v] == 1 && outdeg[v] == 1)
            continue;
        for (size_t k = off[v]; k < off[v + 1]; k++)
            if (!used[list[k]] && walk(c, &B, list[k], indeg, outdeg, off, list, used) != 0)
                break;
    }
    for (size_t s = 0; s < ns && c->err == GEOM_OK; s++)
        if (!used[s] && walk(c, &B, s, indeg, outdeg, off, list, used) != 0)
            break;
    st = c->err;
    /* Exactly sized results (geom_implicit_isolines_free recomputes the
     * sizes from the counts): at least one element each. */
    if (st == GEOM_OK) {
        size_t ni = B.n ? B.n : 1, np1 = B.np + 1, nc = B.np ? B.np : 1;
        uint32_t *idx = resize(c, B.idx, B.cap * sizeof(uint32_t), ni * sizeof(uint32_t));
        if (idx)
            B.idx = idx, B.cap = ni;
        size_t *start = idx ? resize(c, B.start, B.capp * sizeof(size_t), np1 * sizeof(size_t))
                            : NULL;
        if (start) {
            B.start = start;
            start[B.np] = B.n;
        }
        unsigned char *cl = start ? resize(c, B.closed, B.capc, nc) : NULL;
        if (cl) {
            B.closed = cl;
            B.capp = B.capc = 0; /* start and closed now have exact sizes */
            out->indices = B.idx;
            out->n_polylines = B.np;
            out->start = B.start;
            out->closed = B.closed;
            B.idx = NULL;
            B.start = NULL;
            B.closed = NULL;
        } else {
            st = GEOM_ERR_NOMEM;
            /* free what may have been resized with the new sizes */
            if (start) {
                geom__free(c->alloc, B.start, np1 * sizeof(size_t));
                B.start = NULL;
            }
            geom__free(c->alloc, B.idx, B.cap * sizeof(uint32_t));
            B.idx = NULL;
        }
    }
done:
    geom__free(c->alloc, indeg, (nv + 1) * sizeof(uint32_t));
    geom__free(c->alloc, outdeg, (nv + 1) * sizeof(uint32_t));
    geom__free(c->alloc, off, (nv + 1) * sizeof(size_t));
    geom__free(c->alloc, list, (ns + 1) * sizeof(uint32_t));
    geom__free(c->alloc, used, ns + 1);
    geom__free(c->alloc, B.idx, B.cap * sizeof(uint32_t));
    geom__free(c->alloc, B.start, B.capp * sizeof(size_t));
    geom__free(c->alloc, B.closed, B.capc);
    return st;
}

/* ------------------------------------------------------------------ main */

void geom_implicit_isolines_free(geom_implicit_isolines *c)
{
    if (!c)
        return;
    geom_allocator a = c->alloc;
    size_t nv = c->n_vertices ? c->n_vertices : 1;
    size_t ni = c->start && c->start[c->n_polylines] ? c->start[c->n_polylines] : 1;
    size_t nc = c->n_polylines ? c->n_polylines : 1;
    if (c->indices)
        geom__free(&a, c->indices, ni * sizeof(uint32_t));
    if (c->start)
        geom__free(&a, c->start, (c->n_polylines + 1) * sizeof(size_t));
    if (c->closed)
        geom__free(&a, c->closed, nc);
    if (c->xy)
        geom__free(&a, c->xy, 2 * nv * sizeof(double));
    memset(c, 0, sizeof *c);
}

/* Error measure |f - iso| / |grad_xy f| over the vertices. */
static void measure(ctx *c, double hstep, geom_implicit_contour_report *rep)
{
    double sum = 0.0, mx = 0.0;
    size_t n = 0;
    for (size_t v = 0; v < c->nv; v++) {
        double p[3] = {c->xy[2 * v], c->xy[2 * v + 1], c->z};
        double g[3] = {0.0, 0.0, 0.0}, fv;
        if (c->f->gradient) {
            fv = c->f->gradient(c->f->user, p, g) - c->iso;
            c->evals++;
        } else {
            fv = field_at(c, p[0], p[1]);
            double q[3] = {p[0] + hstep, p[1], c->z}, r[3] = {p[0] - hstep, p[1], c->z};
            g[0] = (c->f->value(c->f->user, q) - c->f->value(c->f->user, r)) / (2.0 * hstep);
            q[0] = p[0];
            r[0] = p[0];
            q[1] = p[1] + hstep;
            r[1] = p[1] - hstep;
            g[1] = (c->f->value(c->f->user, q) - c->f->value(c->f->user, r)) / (2.0 * hstep);
            c->evals += 4;
        }
        double gn = hypot(g[0], g[1]);
        double e = fabs(fv) / gn;
        if (!(gn > 0.0) || !isfinite(gn) || !isfinite(e)) {
            rep->unmeasured++;
            continue;
        }
        sum += e;
        if (e > mx)
            mx = e;
        n++;
    }
    rep->error.max_error = mx;
    rep->error.mean_error = n ? sum / (double)n : 0.0;
    rep->error.method = n ? GEOM_ERROR_SAMPLED : GEOM_ERROR_NONE;
    rep->error.pieces = n;
}

geom_status geom_implicit_contour(const geom_implicit_field *field, const double bounds[4],
                                  size_t nx, size_t ny,
                                  const geom_implicit_contour_options *opt,
                                  geom_implicit_isolines *out, geom_diag *diag)
{
    double t0 = now_seconds();
    if (out)
        memset(out, 0, sizeof *out);
    if (!field || !field->value || !bounds || !out)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0, "NULL field, bounds or output");
    geom_implicit_contour_options o;
    if (opt)
        o = *opt;
    else
        memset(&o, 0, sizeof o);
    for (int k = 0; k < 4; k++)
        if (!isfinite(bounds[k]))
            return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0, "non-finite bounds");
    if (!(bounds[0] < bounds[2]) || !(bounds[1] < bounds[3]))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0,
                             "empty bounds: need x0 < x1 and y0 < y1");
    if (nx == 0 || ny == 0)
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0, "the grid needs cells");
    if (!isfinite(o.iso) || !isfinite(o.z))
        return geom__diag_set(diag, GEOM_ERR_INVALID_ARG, "", 0, 0, "non-finite iso or z");
    size_t tmp;
    if (nx >= SIZE_MAX / 64 || ny >= SIZE_MAX / 64 ||
        geom__size_mul(nx + 1, ny + 1, &tmp) != GEOM_OK)
        return geom__diag_set(diag, GEOM_ERR_LIMIT, "", 0, 0, "grid too large");

    ctx c;
    memset(&c, 0, sizeof c);
    c.f = field;
    c.iso = o.iso;
    c.z = o.z;
    c.alloc = o.alloc;
    c.refine = o.refine == GEOM_IMPLICIT_REFINE_ALWAYS ||
               (o.refine == GEOM_IMPLICIT_REFINE_AUTO && field->exact);
    c.max_it = o.max_iterations > 0 ? o.max_iterations : 100;
    if (c.alloc)
        out->alloc = *c.alloc; /* join() hands its arrays to out */

    size_t n1 = nx + 1;
    double *X = geom__alloc(c.alloc, n1 * sizeof(double));
    rows R;
    memset(&R, 0, sizeof R);
    for (int r = 0; r < 2; r++) {
        R.d[r] = geom__alloc(c.alloc, n1 * sizeof(double));
        R.h[r] = geom__alloc(c.alloc, n1 * sizeof(uint32_t));
        R.nd[r] = geom__alloc(c.alloc, n1 * sizeof(uint32_t));
        R.hs[r] = geom__alloc(c.alloc, n1);
    }
    R.v = geom__alloc(c.alloc, n1 * sizeof(uint32_t));
    R.vs = geom__alloc(c.alloc, n1);
    R.s[0] = geom__alloc(c.alloc, n1 * sizeof(size_t));
    R.s[1] = geom__alloc(c.alloc, n1 * sizeof(size_t));
    R.sv = geom__alloc(c.alloc, n1 * sizeof(size_t));
    geom_status st = GEOM_OK;
    if (!X || !R.d[0] || !R.d[1] || !R.h[0] || !R.h[1] || !R.nd[0] || !R.nd[1] || !R.hs[0] ||
        !R.hs[1] || !R.v || !R.vs || !R.s[0] || !R.s[1] || !R.sv) {
        st = GEOM_ERR_NOMEM;
        goto cleanup;
    }
    for (size_t i = 0; i <= nx; i++)
        X[i] = i == nx ? bounds[2]
                       : (bounds[0] * (double)(nx - i) + bounds[2] * (double)i) / (double)nx;
    geom_implicit_contour_report *rep = &out->report;
    rep->cells = nx * ny;
    for (int r = 0; r < 2; r++)
        for (size_t i = 0; i <= nx; i++)
            R.s[r][i] = SIZE_MAX;
    for (size_t i = 0; i <= nx; i++)
        R.sv[i] = SIZE_MAX;
    /* the blocks the isoline may cross (every cell without field->bounds) */
    uint64_t *bits = NULL;
    size_t wpr = 0, B = 0, calls = 0;
    double active = 0;
    st = geom__contour_blocks(field, bounds, nx, ny, o.iso, o.z, c.alloc, &bits, &wpr, &B, &active,
                              &calls);
    if (st != GEOM_OK)
        goto cleanup;
    size_t nby = B ? (ny + B - 1) / B : 0;
    for (size_t j = 0; j < ny && c.err == GEOM_OK; j++) {
        double yb = j == 0 ? bounds[1] : geom__contour_coord(bounds[1], bounds[3], ny, j);
        double yt = geom__contour_coord(bounds[1], bounds[3], ny, j + 1);
        if (!bits) {
            cell_run(&c, &R, X, j, yb, yt, 0, nx, rep);
        } else {
            /* runs of active blocks in this block row, left to right */
            const uint64_t *row = bits + (j / B) * wpr;
            size_t nbx = (nx + B - 1) / B;
            for (size_t bx = 0; bx < nbx && c.err == GEOM_OK;) {
                uint64_t w = row[bx / 64] >> (bx % 64);
                if (w == 0) {
                    bx = (bx / 64 + 1) * 64;
                    continue;
                }
                if (!(w & 1)) {
                    bx += (size_t)__builtin_ctzll(w);
                    continue;
                }
                size_t bend = bx;
                while (bend < nbx && ((row[bend / 64] >> (bend % 64)) & 1))
                    bend++;
                size_t ie = bend * B < nx ? bend * B : nx;
                cell_run(&c, &R, X, j, yb, yt, bx * B, ie, rep);
                bx = bend;
            }
        }
        /* the top row becomes the bottom row */
        double *td = R.d[0];
        R.d[0] = R.d[1];
        R.d[1] = td;
        uint32_t *th = R.h[0];
        R.h[0] = R.h[1];
        R.h[1] = th;
        uint32_t *tn = R.nd[0];
        R.nd[0] = R.nd[1];
        R.nd[1] = tn;
        unsigned char *ts = R.hs[0];
        R.hs[0] = R.hs[1];
        R.hs[1] = ts;
        size_t *tsz = R.s[0];
        R.s[0] = R.s[1];
        R.s[1] = tsz;
    }
    geom__contour_blocks_free(c.alloc, bits, wpr, nby);
    st = c.err;
    if (st == GEOM_OK)
        st = join(&c, out);
    if (st == GEOM_OK) {
        size_t nv = c.nv ? c.nv : 1;
        double *xy = resize(&c, c.xy, c.cap_v * 2 * sizeof(double), nv * 2 * sizeof(double));
        if (!xy) {
            st = GEOM_ERR_NOMEM;
        } else {
            c.xy = xy;
            c.cap_v = nv;
        }
    }
    if (st == GEOM_OK) {
        double h = fmin((bounds[2] - bounds[0]) / (double)nx, (bounds[3] - bounds[1]) / (double)ny);
        measure(&c, 1e-6 * h, rep);
        out->xy = c.xy;
        out->n_vertices = c.nv;
        c.xy = NULL;
        rep->refined = c.refined;
        rep->error.evaluations = c.evals;
        rep->seconds = now_seconds() - t0;
        rep->error.seconds = rep->seconds;
    }
cleanup:
    geom__free(c.alloc, X, n1 * sizeof(double));
    for (int r = 0; r < 2; r++) {
        geom__free(c.alloc, R.d[r], n1 * sizeof(double));
        geom__free(c.alloc, R.h[r], n1 * sizeof(uint32_t));
        geom__free(c.alloc, R.nd[r], n1 * sizeof(uint32_t));
        geom__free(c.alloc, R.hs[r], n1);
    }
    geom__free(c.alloc, R.v, n1 * sizeof(uint32_t));
    geom__free(c.alloc, R.vs, n1);
    for (int r = 0; r < 2; r++)
        geom__free(c.alloc, R.s[r], n1 * sizeof(size_t));
    geom__free(c.alloc, R.sv, n1 * sizeof(size_t));
    geom__free(c.alloc, c.xy, c.cap_v * 2 * sizeof(double));
    geom__free(c.alloc, c.seg, c.cap_seg * 2 * sizeof(uint32_t));
    if (st != GEOM_OK) {
        geom_implicit_isolines_free(out);
        return geom__diag_set(diag, st, "", 0, 0, "marching squares failed: %s",
                             geom_status_str(st));
    }
    return GEOM_OK;
}

geom_status geom_implicit_isolines_to_mesh(const geom_implicit_isolines *c, double z,
                                           geom_mesh *m)
{
    if (!c || !m || !isfinite(z))
        return GEOM_ERR_INVALID_ARG;
    size_t base = geom_mesh_n_vertices(m);
    if (base + c->n_vertices >= (size_t)UINT32_MAX)
        return GEOM_ERR_LIMIT;
    for (size_t v = 0; v < c->n_vertices; v++) {
        double p[3] = {c->xy[2 * v], c->xy[2 * v + 1], z};
        geom_status st = geom_mesh_add_vertex(m, p, NULL);
        if (st != GEOM_OK)
            return st;
    }
    size_t maxlen = 0;
    for (size_t k = 0; k < c->n_polylines; k++) {
        size_t len = c->start[k + 1] - c->start[k] + (c->closed[k] ? 1 : 0);
        if (len > maxlen)
            maxlen = len;
    }
    if (maxlen == 0)
        return GEOM_OK;
    uint32_t *buf = geom__alloc(NULL, maxlen * sizeof(uint32_t));
    if (!buf)
        return GEOM_ERR_NOMEM;
    geom_status st = GEOM_OK;
    for (size_t k = 0; k < c->n_polylines && st == GEOM_OK; k++) {
        size_t n = 0;
        for (size_t q = c->start[k]; q < c->start[k + 1]; q++)
            buf[n++] = (uint32_t)(base + c->indices[q]);
        if (c->closed[k] && n > 0)
            buf[n++] = buf[0];
        st = geom_mesh_polyline_add(m, n, buf);
    }
    geom__free(NULL, buf, maxlen * sizeof(uint32_t));
    return st;
}
